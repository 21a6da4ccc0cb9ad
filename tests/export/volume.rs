//! The volume (`--format dds`): the DDS as DirectX's rules read it, the log law it follows,
//! and each engine's path — Unity's Vector Field Force on `wind_volume.vf`, Godot's
//! `Texture3D` built from the EXR slices and sampled by `windloom_particles.gdshader` —
//! played as the engines do, giving the baked wind times the profile at every cell and layer.

use super::*;
use serde_json::Value;
use windloom::doc::VerticalProfile;

/// A meadow bake with a volume, `layers` layers to 12 m over rough ground.
fn volume_bake(
    formats: Vec<Format>,
    half: bool,
) -> (tempfile::TempDir, Value, Raw, VerticalProfile) {
    let dir = tempfile::tempdir().unwrap();
    let mut layout = example("meadow.json");
    layout.world.grid = [30, 20];
    layout.world.profile = VerticalProfile {
        roughness_length: 0.5,
        reference_height: 3.0,
        top: 12.0,
        layers: 6,
    };
    let profile = layout.world.profile.clone();
    run(
        &layout,
        dir.path(),
        &BakeOptions {
            formats,
            half,
            grid: Some([30, 20]),
            ..small(1)
        },
    );
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    (dir, m, raw, profile)
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

/// The layer factors the log law gives, computed here from its formula.
fn log_law(p: &VerticalProfile) -> Vec<f64> {
    (0..p.layers)
        .map(|k| {
            let h = (f64::from(k) + 0.5) * f64::from(p.top) / f64::from(p.layers);
            let z0 = f64::from(p.roughness_length);
            if h <= z0 {
                0.0
            } else {
                (h / z0).ln() / (f64::from(p.reference_height) / z0).ln()
            }
        })
        .collect()
}

#[test]
fn the_volume_follows_the_log_law_from_zero_at_the_ground() {
    let (_dir, m, _raw, p) = volume_bake(vec![Format::Dds, Format::Raw], false);
    let want = log_law(&p);
    let profile = &m["profile"];
    assert_eq!(profile["layers"], 6);
    let factors: Vec<f64> = profile["factors"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_f64().unwrap())
        .collect();
    for (k, (got, want)) in factors.iter().zip(&want).enumerate() {
        assert!((got - want).abs() < 1e-5, "layer {k}: {got} against {want}");
    }
    // Layer 0 at 1 m is above z0 = 0.5 m: slower than the simulated wind; the wind grows
    // with height, past the simulated wind above the reference height (3 m).
    assert!(factors[0] > 0.0 && factors[0] < 0.5, "{factors:?}");
    assert!(factors.windows(2).all(|w| w[1] > w[0]), "{factors:?}");
    // Layer 1's centre is the reference height: the simulated wind itself.
    assert!(
        (factors[1] - 1.0).abs() < 1e-6 && factors[2] > 1.0,
        "{factors:?}"
    );
    // Below the roughness length the wind is zero.
    let still = VerticalProfile {
        roughness_length: 2.0,
        ..p.clone()
    };
    assert_eq!(still.factor(1.0), 0.0);
    assert_eq!(still.factor(2.0), 0.0);
    assert!((still.factor(3.0) - 1.0).abs() < 1e-6);
}

/// The DDS read as DirectX's documented layout says (`DDS_HEADER`, `DDS_PIXELFORMAT` with
/// the `DX10` FourCC, `DDS_HEADER_DXT10`), in both float widths.
#[test]
fn dds_is_a_dx10_volume_texture() {
    for half in [false, true] {
        let (dir, m, raw, p) = volume_bake(vec![Format::Dds, Format::Raw], half);
        let b = std::fs::read(dir.path().join("wind_volume.dds")).unwrap();
        assert_eq!(&b[0..4], b"DDS ");
        assert_eq!(u32_at(&b, 4), 124, "dwSize");
        let flags = u32_at(&b, 8);
        for (flag, what) in [
            (0x1, "CAPS"),
            (0x2, "HEIGHT"),
            (0x4, "WIDTH"),
            (0x1000, "PIXELFORMAT"),
            (0x80_0000, "DEPTH"),
        ] {
            assert!(flags & flag != 0, "DDSD_{what}");
        }
        let (height, width, depth) = (u32_at(&b, 12), u32_at(&b, 16), u32_at(&b, 24));
        assert_eq!((width, height, depth), (30, 20, 6));
        let texel = if half { 8 } else { 16 };
        assert_eq!(u32_at(&b, 20), 30 * texel, "pitch");
        assert_eq!(u32_at(&b, 28), 1, "one mip level");
        // DDS_PIXELFORMAT at 76: size 32, DDPF_FOURCC, "DX10".
        assert_eq!((u32_at(&b, 76), u32_at(&b, 80)), (32, 0x4));
        assert_eq!(&b[84..88], b"DX10");
        // caps at 108: DDSCAPS_TEXTURE | COMPLEX; caps2: DDSCAPS2_VOLUME.
        assert_eq!(u32_at(&b, 108) & 0x1000, 0x1000);
        assert_eq!(u32_at(&b, 112), 0x20_0000);
        // DDS_HEADER_DXT10 at 128: format, TEXTURE3D (4), misc, array size 1.
        assert_eq!(u32_at(&b, 128), if half { 10 } else { 2 }, "DXGI format");
        assert_eq!(u32_at(&b, 132), 4, "D3D10_RESOURCE_DIMENSION_TEXTURE3D");
        assert_eq!(u32_at(&b, 140), 1, "array size");
        // A second reader: the `ddsfile` crate finds the same volume and the same texels.
        let other = ddsfile::Dds::read(&b[..]).unwrap();
        assert_eq!(
            (other.get_width(), other.get_height(), other.get_depth()),
            (30, 20, 6)
        );
        assert_eq!(
            other.get_dxgi_format(),
            Some(if half {
                ddsfile::DxgiFormat::R16G16B16A16_Float
            } else {
                ddsfile::DxgiFormat::R32G32B32A32_Float
            })
        );
        assert_eq!(
            other.header10.as_ref().unwrap().resource_dimension,
            ddsfile::D3D10ResourceDimension::Texture3D
        );
        assert_eq!(other.get_num_mipmap_levels(), 1);
        let data = &b[148..];
        assert_eq!(other.get_data(0).unwrap(), data);
        assert_eq!(
            data.len() as u32,
            width * height * depth * texel,
            "no more, no less"
        );
        let factors = log_law(&p);
        let channel = |i: usize, j: usize, k: usize, c: usize| -> f64 {
            let at = ((k * 20 + j) * 30 + i) * texel as usize;
            if half {
                let o = at + 2 * c;
                f64::from(half::f16::from_le_bytes([data[o], data[o + 1]]).to_f32())
            } else {
                let o = at + 4 * c;
                f64::from(f32::from_le_bytes(data[o..o + 4].try_into().unwrap()))
            }
        };
        for (i, j) in [(0, 0), (29, 19), (15, 10), (3, 17)] {
            for (k, f) in factors.iter().enumerate() {
                let v = raw.at(0, i, j);
                let want = [f64::from(v[0]) * f, 0.0, f64::from(v[1]) * f];
                let tol = if half { 2e-3 } else { 1e-5 };
                for (c, want) in want.iter().enumerate() {
                    let got = channel(i, j, k, c);
                    assert!(
                        (got - want).abs() <= tol * (1.0 + want.abs()),
                        "half {half} cell {i},{j} layer {k} channel {c}: {got} against {want}"
                    );
                }
                let speed = want[0].hypot(want[2]);
                assert!((channel(i, j, k, 3) - speed).abs() <= 2e-3 * (1.0 + speed));
            }
        }
        assert_eq!(
            m["engines"]["unreal"]["volume_texture"]["compression_settings"],
            if half { "TC_HDR" } else { "TC_HDR_F32" }
        );
    }
}

/// Cell `(i, j)`'s centre on layer `k` in world metres `[x, y, z]`.
fn centre(
    m: &Value,
    i: usize,
    j: usize,
    k: usize,
    grid: [usize; 2],
    p: &VerticalProfile,
) -> [f64; 3] {
    let (lo, hi) = (&m["world"]["min"], &m["world"]["max"]);
    let axis = |a: usize, c: usize, n: usize| {
        let (l, h) = (lo[a].as_f64().unwrap(), hi[a].as_f64().unwrap());
        l + (c as f64 + 0.5) * (h - l) / n as f64
    };
    [
        axis(0, i, grid[0]),
        f64::from(p.layer_height(k as u32)),
        axis(1, j, grid[1]),
    ]
}

/// Unity: `wind_volume.vf` imported and placed as `engines.unity.volume` says, Vector Field
/// Force (Signed) gives the wind times the profile, in Unity's axes, at every cell and layer.
#[test]
fn unity_s_vector_field_force_gives_the_volume_s_wind() {
    let (dir, m, raw, p) = volume_bake(vec![Format::Dds, Format::Raw], false);
    let unity = &m["engines"]["unity"]["volume"];
    assert_eq!(unity["data_encoding"], "Signed");
    let vec3 = |v: &Value| [0, 1, 2].map(|k| v[k].as_f64().unwrap());
    let (box_centre, box_size) = (vec3(&unity["box_center"]), vec3(&unity["box_size"]));
    let b = std::fs::read(dir.path().join(unity["files"][0].as_str().unwrap())).unwrap();
    assert_eq!(&b[..4], b"VF_V");
    let dims: Vec<usize> = b[4..10]
        .chunks_exact(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]) as usize)
        .collect();
    assert_eq!(dims, [30, 6, 20]);
    let v = f32s(&b[10..]);
    let texel = |x: usize, y: usize, z: usize| {
        let at = (x + 30 * (y + 6 * z)) * 3;
        [0, 1, 2].map(|c| f64::from(v[at + c]))
    };
    let factors = log_law(&p);
    for j in 0..20 {
        for i in 0..30 {
            for (k, f) in factors.iter().enumerate() {
                let w = centre(&m, i, j, k, [30, 20], &p);
                let unity_pos = [w[0], w[1], -w[2]];
                let coord = [0, 1, 2].map(|a| (unity_pos[a] - box_centre[a]) / box_size[a] + 0.5);
                let s = trilinear([30, 6, 20], texel, coord);
                let got = [0, 1, 2].map(|a| s[a] * box_size[a]);
                let r = raw.at(0, i, j);
                let want = [f64::from(r[0]) * f, 0.0, -f64::from(r[1]) * f];
                for a in 0..3 {
                    assert!(
                        (got[a] - want[a]).abs() <= 1e-4 * (1.0 + want[a].abs()),
                        "cell {i},{j} layer {k} axis {a}: {} against {}",
                        got[a],
                        want[a]
                    );
                }
            }
        }
    }
}

/// Godot: the slices EXR split as the `3d_texture` importer splits it (`slices/vertical` =
/// layers, slice `k` at rows `k · height`), sampled as `windloom_volume.gdshaderinc` does,
/// gives the wind times the profile at every cell and layer.
#[test]
fn godot_s_texture3d_gives_the_volume_s_wind() {
    use exr::prelude::*;
    let shader =
        include_str!("../../docs/engines/godot/addons/windloom/windloom_volume.gdshaderinc");
    assert!(
        shader.contains("vec3 uvw = ((p - volume_min) / volume_size).xzy;")
            && shader.contains("texture(wind_volume, uvw).rgb"),
        "the shader samples as emulated here"
    );
    let (dir, m, raw, p) = volume_bake(vec![Format::Dds, Format::Raw], false);
    let g = &m["engines"]["godot"]["volume"];
    assert_eq!(g["importer"], "3d_texture");
    assert_eq!(g["import"]["slices/horizontal"], 1);
    assert_eq!(g["import"]["slices/vertical"], 6);
    let vec3 = |v: &Value| [0, 1, 2].map(|k| v[k].as_f64().unwrap());
    let (vmin, vsize) = (vec3(&g["volume_min"]), vec3(&g["volume_size"]));
    let image =
        read_all_flat_layers_from_file(dir.path().join(g["files"][0].as_str().unwrap())).unwrap();
    let layer = &image.layer_data[0];
    assert_eq!(layer.size, Vec2(30, 20 * 6));
    let channel = |name: &str| -> Vec<f32> {
        let c = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
            .unwrap();
        c.sample_data.values_as_f32().collect()
    };
    let rgb = [channel("R"), channel("G"), channel("B")];
    // The importer's slices: width 30, height 120 / 6 = 20, slice k from row 20 k.
    let slice_h = 120 / 6;
    let texel = |x: usize, y: usize, z: usize| {
        [0, 1, 2].map(|c| f64::from(rgb[c][(z * slice_h + y) * 30 + x]))
    };
    let factors = log_law(&p);
    for j in 0..20 {
        for i in 0..30 {
            for (k, f) in factors.iter().enumerate() {
                let w = centre(&m, i, j, k, [30, 20], &p);
                let uvw = [0, 1, 2].map(|a| (w[a] - vmin[a]) / vsize[a]);
                // uvw.xzy: the texture's width, height, depth are world x, z, y.
                let got = trilinear([30, 20, 6], texel, [uvw[0], uvw[2], uvw[1]]);
                let r = raw.at(0, i, j);
                let want = [f64::from(r[0]) * f, 0.0, f64::from(r[1]) * f];
                for a in 0..3 {
                    assert!(
                        (got[a] - want[a]).abs() <= 1e-5 * (1.0 + want[a].abs()),
                        "cell {i},{j} layer {k} axis {a}: {} against {}",
                        got[a],
                        want[a]
                    );
                }
            }
        }
    }
}

/// Unreal: `wind_volume.dds` as a Volume Texture, sampled at `uvw = (position − min) / size`
/// from `engines.unreal.volume_texture` (cm, Unreal's axes) with trilinear filtering, and
/// swizzled as the guide says (`float3(R, B, G) × 100`), gives the wind in cm/s in Unreal's
/// axes times the profile at every cell and layer.
#[test]
fn unreal_s_volume_texture_gives_the_volume_s_wind() {
    let (dir, m, raw, p) = volume_bake(vec![Format::Dds, Format::Raw], false);
    let v = &m["engines"]["unreal"]["volume_texture"];
    assert_eq!(v["swizzle"], "wind_cm_s = float3(R, B, G) * 100");
    let vec3 = |x: &Value| [0, 1, 2].map(|k| x[k].as_f64().unwrap());
    let (min_cm, size_cm) = (vec3(&v["bounds_min_cm"]), vec3(&v["bounds_size_cm"]));
    let b = std::fs::read(dir.path().join(v["files"][0].as_str().unwrap())).unwrap();
    let data = f32s(&b[148..]);
    // Texel (x, y, z) of the texture: width, height, depth; RGBA.
    let texel = |x: usize, y: usize, z: usize| {
        let at = ((z * 20 + y) * 30 + x) * 4;
        [0, 1, 2].map(|c| f64::from(data[at + c]))
    };
    let factors = log_law(&p);
    for j in 0..20 {
        for i in 0..30 {
            for (k, f) in factors.iter().enumerate() {
                let w = centre(&m, i, j, k, [30, 20], &p);
                // Unreal: X = world x, Y = world z, Z = up, in cm.
                let unreal_cm = [w[0] * 100.0, w[2] * 100.0, w[1] * 100.0];
                let uvw = [0, 1, 2].map(|a| (unreal_cm[a] - min_cm[a]) / size_cm[a]);
                let s = trilinear([30, 20, 6], texel, uvw);
                let got = [s[0] * 100.0, s[2] * 100.0, s[1] * 100.0];
                let r = raw.at(0, i, j);
                let want = [
                    f64::from(r[0]) * f * 100.0,
                    f64::from(r[1]) * f * 100.0,
                    0.0,
                ];
                for a in 0..3 {
                    assert!(
                        (got[a] - want[a]).abs() <= 1e-3 * (1.0 + want[a].abs()),
                        "cell {i},{j} layer {k} axis {a}: {} cm/s against {}",
                        got[a],
                        want[a]
                    );
                }
            }
        }
    }
}
