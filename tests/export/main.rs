//! Bakes read back by readers written from the format specifications
//! (the engines' own, as `docs/EXPORT.md` and `docs/engines/` quote them), not by the writers' code, and compared with the
//! raw field.
#![allow(
    clippy::unwrap_used,
    reason = "a test that unwraps fails there, which is what a test is for"
)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use windloom::bake::{self, BakeOptions, Format};
use windloom::doc::Layout;

fn example(name: &str) -> Layout {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("layouts")
        .join(name);
    windloom::io::load(&p).unwrap()
}

/// Bakes, and checks the manifest written against its schema.
fn run(layout: &Layout, out: &Path, opts: &BakeOptions) -> bake::Manifest {
    let m = bake::bake(
        layout,
        out,
        opts,
        &AtomicBool::new(false),
        &mut |_, _, _| {},
    )
    .unwrap();
    manifest(out);
    m
}

fn small(frames: usize) -> BakeOptions {
    BakeOptions {
        warmup: 1.5,
        frames,
        fps: 10.0,
        grid: Some([48, 32]),
        ..Default::default()
    }
}

fn f32s(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// Trilinear filtering of a `w × h × d` grid of 3-vectors at texture coordinate `t` (texel
/// centres at `(i + 0.5) / size`), clamped at the edges, as GPUs sample a 3D texture.
fn trilinear(
    size: [usize; 3],
    texel: impl Fn(usize, usize, usize) -> [f64; 3],
    t: [f64; 3],
) -> [f64; 3] {
    let p = [0, 1, 2].map(|a| t[a] * size[a] as f64 - 0.5);
    let f = p.map(|x| x - x.floor());
    let b = p.map(|x| x.floor() as i64);
    let mut out = [0.0; 3];
    for corner in 0..8 {
        let o = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
        let weight: f64 = (0..3)
            .map(|a| if o[a] == 1 { f[a] } else { 1.0 - f[a] })
            .product();
        let c = [0, 1, 2].map(|a| (b[a] + o[a] as i64).clamp(0, size[a] as i64 - 1) as usize);
        for (o, t) in out.iter_mut().zip(texel(c[0], c[1], c[2])) {
            *o += weight * t;
        }
    }
    out
}

/// Bilinear filtering of a `w × h` grid of values at texture coordinate `t` (texel centres
/// at `(i + 0.5) / size`), clamped at the edges, as GPUs sample a 2D texture.
fn bilinear(size: [usize; 2], texel: impl Fn(usize, usize) -> f64, t: [f64; 2]) -> f64 {
    let (w, h) = (size[0] as f64, size[1] as f64);
    let at = |x: i64, y: i64| {
        texel(
            x.clamp(0, size[0] as i64 - 1) as usize,
            y.clamp(0, size[1] as i64 - 1) as usize,
        )
    };
    let (x, y) = (t[0] * w - 0.5, t[1] * h - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (x0, y0) = (x0 as i64, y0 as i64);
    let row = |y| at(x0, y) * (1.0 - fx) + at(x0 + 1, y) * fx;
    row(y0) * (1.0 - fy) + row(y0 + 1) * fy
}

/// The raw bake: `[frame][j][i][x, z]`.
struct Raw {
    nx: usize,
    ny: usize,
    data: Vec<f32>,
}

impl Raw {
    fn read(dir: &Path, m: &serde_json::Value) -> Raw {
        let grid = &m["grid"];
        let (nx, ny) = (
            grid[0].as_u64().unwrap() as usize,
            grid[1].as_u64().unwrap() as usize,
        );
        let data = f32s(&std::fs::read(dir.join("wind.f32")).unwrap());
        let frames = m["frames"]["count"].as_u64().unwrap() as usize;
        assert_eq!(data.len(), frames * nx * ny * 2, "raw length");
        Raw { nx, ny, data }
    }

    fn at(&self, frame: usize, i: usize, j: usize) -> [f32; 2] {
        let k = ((frame * self.ny + j) * self.nx + i) * 2;
        [self.data[k], self.data[k + 1]]
    }
}

/// The bake's `manifest.json`, checked against its schema.
fn manifest(dir: &Path) -> serde_json::Value {
    let m =
        serde_json::from_str(&std::fs::read_to_string(dir.join("manifest.json")).unwrap()).unwrap();
    manifest::check_schema(&m);
    m
}

fn file_of<'a>(m: &'a serde_json::Value, format: &str) -> Vec<&'a serde_json::Value> {
    m["files"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["format"] == format)
        .collect()
}

#[test]
fn manifest_lists_exactly_the_files_written() {
    let dir = tempfile::tempdir().unwrap();
    let layout = example("obstacles.json");
    run(&layout, dir.path(), &small(3));
    let m = manifest(dir.path());
    assert_eq!(m["format"], "windloom-bake");
    assert_eq!(m["version"], 2);
    assert_eq!(m["sequence"], 1, "the first bake into a folder");
    assert_eq!(m["layout"]["name"], "Obstacles");
    assert_eq!(
        m["layout"]["hash"],
        bake::layout_hash(&{
            let mut l = layout.clone();
            l.world.grid = [48, 32];
            l
        })
    );
    assert_eq!(m["grid"], serde_json::json!([48, 32]));
    assert_eq!(m["world"]["units"], "m");
    assert_eq!(m["world"]["max"], serde_json::json!([120.0, 120.0]));
    assert_eq!(m["frames"]["count"], 3);
    assert_eq!(m["frames"]["fps"], 10.0);
    assert_eq!(m["frames"]["loop"], false);
    for f in m["files"].as_array().unwrap() {
        assert!(f["axes"].is_object() && f["encoding"].is_object(), "{f}");
    }
    let listed: BTreeSet<String> = m["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["name"].as_str().unwrap().to_string())
        .chain(["manifest.json".to_string()])
        .collect();
    let on_disk: BTreeSet<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert_eq!(listed, on_disk, "no staging leftovers, nothing unlisted");
    for f in m["files"].as_array().unwrap() {
        let len = std::fs::metadata(dir.path().join(f["name"].as_str().unwrap()))
            .unwrap()
            .len();
        assert_eq!(f["bytes"].as_u64().unwrap(), len);
    }
}

#[test]
fn fga_reads_back_per_the_unreal_format() {
    let dir = tempfile::tempdir().unwrap();
    run(&example("obstacles.json"), dir.path(), &small(1));
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let text = std::fs::read_to_string(dir.path().join("wind.fga")).unwrap();
    // Comma-separated numbers with any whitespace between them.
    let nums: Vec<f64> = text
        .split([',', '\n', ' ', '\r', '\t'])
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap())
        .collect();
    let (sx, sy, sz) = (nums[0] as usize, nums[1] as usize, nums[2] as usize);
    assert_eq!((sx, sy, sz), (48, 32, 1));
    // Bounds in centimetres: x and z of the world, a slab in Unreal Z.
    assert_eq!(&nums[3..9], &[0.0, 0.0, 0.0, 12000.0, 12000.0, 200.0]);
    let vecs = &nums[9..];
    assert_eq!(
        vecs.len(),
        sx * sy * sz * 3,
        "exactly SizeX*SizeY*SizeZ vectors"
    );
    // X fastest, then Y: index x + SizeX * y; vectors in cm/s, Unreal Y = world z.
    for (i, j) in [(0, 0), (47, 0), (5, 17), (47, 31), (20, 9)] {
        let k = (i + sx * j) * 3;
        let want = raw.at(0, i, j);
        assert!(
            (vecs[k] - f64::from(want[0]) * 100.0).abs() < 1e-2,
            "x at {i},{j}"
        );
        assert!(
            (vecs[k + 1] - f64::from(want[1]) * 100.0).abs() < 1e-2,
            "y at {i},{j}"
        );
        assert_eq!(vecs[k + 2], 0.0);
    }
    // Size, minimum and maximum on three lines, then one vector per line.
    assert_eq!(text.lines().count(), 3 + sx * sy);
}

/// Reads an FGA as Unreal's importer does (`VectorFieldFactory.cpp`'s `ParseFGA`): each value
/// runs to the next comma (or the end of the file) and is read by `atoi`/`atof`, which skip
/// leading whitespace and stop at the first character that is not part of a number; three
/// sizes, six bounds, then `SizeX·SizeY·SizeZ·3` values. It fails when the file ends before
/// them, and warns "File contains additional information" when anything is left after them.
/// Returns the sizes, the bounds, the values and whether it warned.
fn fga_as_unreal_reads_it(text: &str) -> ([i64; 3], [f64; 6], Vec<f64>, bool) {
    /// The value up to the next comma (or the end), and what follows that comma.
    fn next(rest: &str) -> (&str, &str) {
        match rest.find(',') {
            Some(i) => (&rest[..i], &rest[i + 1..]),
            None => (rest, ""),
        }
    }
    // atof: leading whitespace, then the longest prefix that is a number.
    let atof = |t: &str| {
        let t = t.trim_start();
        (1..=t.len())
            .rev()
            .find_map(|n| t.get(..n).and_then(|p| p.parse::<f64>().ok()))
            .unwrap_or(0.0)
    };
    let mut rest = text;
    let read = |rest: &mut &str| {
        let (token, after) = next(rest);
        *rest = after;
        atof(token)
    };
    let size = [0; 3].map(|_| read(&mut rest) as i64);
    let bounds = [0; 6].map(|_| read(&mut rest));
    let count = (size[0] * size[1] * size[2] * 3) as usize;
    let mut values = Vec::with_capacity(count);
    // Values while the file lasts, as many as the sizes say.
    while values.len() < count {
        values.push(read(&mut rest));
        if rest.is_empty() {
            break;
        }
    }
    assert_eq!(values.len(), count, "Unreal: Expected {count} values");
    (size, bounds, values, !rest.is_empty())
}

/// Unreal imports every FGA a bake writes without a warning ("File contains additional
/// information", which every file drew while each line, the last too, ended with a comma),
/// with the sizes, bounds and vectors the manifest describes.
#[test]
fn fga_imports_into_unreal_without_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::Fga, Format::Raw],
        ..small(2)
    };
    run(&example("two-winds.json"), dir.path(), &opts);
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    for (k, entry) in file_of(&m, "fga").into_iter().enumerate() {
        let name = entry["name"].as_str().unwrap();
        let text = std::fs::read_to_string(dir.path().join(name)).unwrap();
        let (size, bounds, values, warned) = fga_as_unreal_reads_it(&text);
        assert!(!warned, "{name}: Unreal warns of additional information");
        assert_eq!(size, [48, 32, 1], "{name}");
        assert_eq!(
            bounds.to_vec(),
            ["bounds_min_cm", "bounds_max_cm"]
                .iter()
                .flat_map(|b| {
                    m["engines"]["unreal"]["vector_field_static"][b]
                        .as_array()
                        .unwrap()
                        .clone()
                })
                .map(|v| v.as_f64().unwrap())
                .collect::<Vec<_>>()
        );
        for (i, j) in [(0, 0), (47, 0), (3, 5), (47, 31)] {
            let at = (i + 48 * j) * 3;
            let want = raw.at(k, i, j);
            assert!(
                (values[at] - f64::from(want[0]) * 100.0).abs() < 1e-2,
                "{name} x {i},{j}"
            );
            assert!(
                (values[at + 1] - f64::from(want[1]) * 100.0).abs() < 1e-2,
                "{name} y {i},{j}"
            );
            assert_eq!(values[at + 2], 0.0);
        }
    }
    // The emulation tells the two apart: the old ending drew the warning.
    let old = "2,1,1,\n0,0,0,\n100,100,200,\n1,2,0,\n3,4,0,\n";
    assert!(
        fga_as_unreal_reads_it(old).3,
        "a trailing comma and newline warn"
    );
}

/// Reads an FGA the way line-based readers do (Blender's FGA add-on and others): line 1 the
/// sizes, line 2 the minimum corner, line 3 the maximum corner, then one vector per line.
fn fga_by_lines(text: &str) -> ([usize; 3], [f64; 3], [f64; 3], Vec<[f64; 3]>) {
    let mut lines = text.lines();
    let mut row = |what: &str| -> Vec<f64> {
        lines
            .next()
            .unwrap_or_else(|| panic!("no {what} line"))
            .split(',')
            .filter(|t| !t.trim().is_empty())
            .map(|t| t.trim().parse().unwrap())
            .collect()
    };
    let size = row("size");
    let min = row("min");
    let max = row("max");
    assert_eq!(
        (size.len(), min.len(), max.len()),
        (3, 3, 3),
        "three values a line"
    );
    let vectors: Vec<[f64; 3]> = lines
        .map(|l| {
            let v: Vec<f64> = l
                .split(',')
                .filter(|t| !t.trim().is_empty())
                .map(|t| t.trim().parse().unwrap())
                .collect();
            assert_eq!(v.len(), 3, "one vector per line: {l:?}");
            [v[0], v[1], v[2]]
        })
        .collect();
    (
        [size[0] as usize, size[1] as usize, size[2] as usize],
        [min[0], min[1], min[2]],
        [max[0], max[1], max[2]],
        vectors,
    )
}

#[test]
fn fga_reads_the_same_line_by_line() {
    let dir = tempfile::tempdir().unwrap();
    let layout = example("two-winds.json");
    run(&layout, dir.path(), &small(1));
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let text = std::fs::read_to_string(dir.path().join("wind.fga")).unwrap();
    let (size, min, max, vectors) = fga_by_lines(&text);
    assert_eq!(size, [48, 32, 1]);
    let (lo, hi) = layout.bounds();
    assert_eq!(
        min,
        [f64::from(lo[0]) * 100.0, f64::from(lo[1]) * 100.0, 0.0]
    );
    assert_eq!(
        max,
        [f64::from(hi[0]) * 100.0, f64::from(hi[1]) * 100.0, 200.0]
    );
    assert_eq!(vectors.len(), 48 * 32);
    for (i, j) in [(0, 0), (3, 5), (47, 31), (20, 9)] {
        let v = vectors[i + 48 * j];
        let want = raw.at(0, i, j);
        assert!(
            (v[0] - f64::from(want[0]) * 100.0).abs() < 1e-2,
            "x at {i},{j}"
        );
        assert!(
            (v[1] - f64::from(want[1]) * 100.0).abs() < 1e-2,
            "y at {i},{j}"
        );
    }
}

#[test]
fn fga_is_area_averaged_down_to_128() {
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::Fga, Format::Raw],
        grid: Some([256, 192]),
        warmup: 1.0,
        ..Default::default()
    };
    let m = run(&example("obstacles.json"), dir.path(), &opts);
    assert!(
        m.notes
            .iter()
            .any(|n| n.contains("resampled 256x192 to 128x96")),
        "{:?}",
        m.notes
    );
    let fga = m.files.iter().find(|f| f.format == Format::Fga).unwrap();
    assert_eq!(fga.grid, [128, 96]);
    assert_eq!(fga.resampled_from, Some([256, 192]));
    let mj = manifest(dir.path());
    let raw = Raw::read(dir.path(), &mj);
    let text = std::fs::read_to_string(dir.path().join("wind.fga")).unwrap();
    let nums: Vec<f64> = text
        .split([',', '\n'])
        .filter(|t| !t.trim().is_empty())
        .map(|t| t.trim().parse().unwrap())
        .collect();
    // Each FGA cell is the mean of a 2×2 block of the raw grid.
    for (i, j) in [(0, 0), (63, 40), (127, 95), (10, 70)] {
        let k = 9 + (i + 128 * j) * 3;
        let mut mean = [0.0f64; 2];
        for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let v = raw.at(0, 2 * i + di, 2 * j + dj);
            mean[0] += f64::from(v[0]) * 25.0;
            mean[1] += f64::from(v[1]) * 25.0;
        }
        assert!(
            (nums[k] - mean[0]).abs() < 1e-2 && (nums[k + 1] - mean[1]).abs() < 1e-2,
            "cell {i},{j}"
        );
    }
}

#[test]
fn vf_reads_back_per_the_unity_format() {
    let dir = tempfile::tempdir().unwrap();
    run(&example("two-winds.json"), dir.path(), &small(1));
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let bytes = std::fs::read(dir.path().join("wind.vf")).unwrap();
    assert_eq!(&bytes[0..4], b"VF_V");
    let size: Vec<usize> = bytes[4..10]
        .chunks_exact(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]) as usize)
        .collect();
    assert_eq!(size, vec![48, 1, 32]);
    assert_eq!(bytes.len(), 10 + 4 * 3 * 48 * 32, "exact length");
    let v = f32s(&bytes[10..]);
    // Unity Z points north: Z index k holds grid row ny-1-k; vectors (x, 0, -z) m/s divided
    // by the box's size on each axis (the world's 100 m width and depth here).
    let scale: Vec<f32> = file_of(&m, "vf")[0]["encoding"]["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["scale"].as_f64().unwrap() as f32)
        .collect();
    let (lo, hi) = example("two-winds.json").bounds();
    assert_eq!(scale, [hi[0] - lo[0], 1.0, hi[1] - lo[1]]);
    for (i, j) in [(0, 0), (47, 31), (24, 16), (3, 29)] {
        let k = 31 - j;
        let idx = (i + 48 * k) * 3;
        let want = raw.at(0, i, j);
        assert_eq!(
            [v[idx], v[idx + 1], v[idx + 2]],
            [want[0] / scale[0], 0.0, -want[1] / scale[2]],
            "cell {i},{j}"
        );
    }
}

/// VFX Graph's *Vector Field Force*, as `VectorFieldForce.cs` writes it: the particle's
/// position into the box's space (`InvFieldTransform`), `+ 0.5`, a trilinear sample of the
/// imported `Texture3D` (wrap Clamp, as the guide sets it), `* 2 - 1` only with Data Encoding
/// Unsigned Normalized (the guide says Signed), then `mul(FieldTransform, float4(value, 0))`
/// (each axis times the box size) and `* Intensity`. Followed as `docs/engines/unity.md` and
/// the manifest say, the force target is the baked wind in m/s in Unity's axes at every
/// cell; with the block's defaults (Unsigned Normalized) it is not.
#[test]
fn unity_s_vector_field_force_gives_the_wind_in_m_s() {
    let dir = tempfile::tempdir().unwrap();
    // A world that is not square (the box scales its axes differently).
    let mut layout = example("meadow.json");
    layout.world.grid = [60, 40];
    run(&layout, dir.path(), &small(1));
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let entry = file_of(&m, "vf")[0];
    let unity = &m["engines"]["unity"]["vector_field"];
    assert_eq!(unity["files"][0], entry["name"]);
    assert_eq!(unity["data_encoding"], "Signed");
    assert_eq!(unity["import"]["wrap_mode"], "Clamp");
    let vec3 = |v: &serde_json::Value| -> [f64; 3] {
        let a = v.as_array().unwrap();
        [0, 1, 2].map(|k| a[k].as_f64().unwrap())
    };
    let (centre, size) = (vec3(&unity["box_center"]), vec3(&unity["box_size"]));
    let intensity = unity["intensity"].as_f64().unwrap();
    let bytes = std::fs::read(dir.path().join("wind.vf")).unwrap();
    let dims: Vec<usize> = bytes[4..10]
        .chunks_exact(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]) as usize)
        .collect();
    let v = f32s(&bytes[10..]);
    let (w, h, d) = (dims[0], dims[1], dims[2]);
    // Trilinear filtering of the imported Texture3D, clamped at its edges (wrap Clamp).
    let texel = |x: usize, y: usize, z: usize| -> [f64; 3] {
        let i = (x + w * (y + h * z)) * 3;
        [0, 1, 2].map(|c| f64::from(v[i + c]))
    };
    let force = |position: [f64; 3], unsigned: bool| -> [f64; 3] {
        // An axis-aligned box: InvFieldTransform is (p - centre) / size.
        let coord = [0, 1, 2].map(|a| (position[a] - centre[a]) / size[a] + 0.5);
        let mut value = trilinear([w, h, d], texel, coord);
        if unsigned {
            value = value.map(|x| x * 2.0 - 1.0);
        }
        [0, 1, 2].map(|a| value[a] * size[a] * intensity)
    };
    let (lo, hi) = layout.bounds();
    let (nx, ny) = (raw.nx, raw.ny);
    let mut worst_default = 0.0f64;
    for j in 0..ny {
        for i in 0..nx {
            // The cell's centre in Unity's axes (z north), on the field's mid-height.
            let x = f64::from(lo[0]) + (i as f64 + 0.5) * f64::from(hi[0] - lo[0]) / nx as f64;
            let z = f64::from(lo[1]) + (j as f64 + 0.5) * f64::from(hi[1] - lo[1]) / ny as f64;
            let p = [x, 0.0, -z];
            let want = raw.at(0, i, j);
            let want = [f64::from(want[0]), 0.0, -f64::from(want[1])];
            let got = force(p, false);
            for (a, (got, want)) in got.iter().zip(want).enumerate() {
                assert!(
                    (got - want).abs() <= 1e-4 * (1.0 + want.abs()),
                    "cell {i},{j} axis {a}: {got} m/s, the bake says {want}"
                );
            }
            let default = force(p, true);
            worst_default = worst_default.max((default[0] - want[0]).abs());
        }
    }
    // The block's default encoding would not give the wind: the guide must say Signed.
    assert!(worst_default > 1.0, "{worst_default}");
}

#[test]
fn exr_reads_back_with_the_exr_crate() {
    use exr::prelude::*;
    for half in [false, true] {
        let dir = tempfile::tempdir().unwrap();
        let opts = BakeOptions {
            formats: vec![Format::Exr, Format::Raw],
            half,
            ..small(1)
        };
        run(&example("meadow.json"), dir.path(), &opts);
        let m = manifest(dir.path());
        let raw = Raw::read(dir.path(), &m);
        let image = read_all_flat_layers_from_file(dir.path().join("wind.exr")).unwrap();
        let layer = &image.layer_data[0];
        assert_eq!(layer.size, Vec2(48, 32));
        let names: Vec<String> = layer
            .channel_data
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        assert_eq!(names, ["B", "G", "R"], "R, G and B are all present");
        let channel = |name: &str| {
            let c = layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name.to_string() == name)
                .unwrap();
            c.sample_data.values_as_f32().collect::<Vec<f32>>()
        };
        let (r, g, b) = (channel("R"), channel("G"), channel("B"));
        for (i, j) in [(0, 0), (47, 31), (24, 16), (10, 20)] {
            let want = raw.at(0, i, j);
            let k = j * 48 + i;
            let tol = if half {
                2e-3 * want[0].abs().max(want[1].abs()).max(1.0)
            } else {
                0.0
            };
            assert!(
                (r[k] - want[0]).abs() <= tol,
                "R at {i},{j}: {} vs {}",
                r[k],
                want[0]
            );
            assert!((g[k] - want[1]).abs() <= tol, "G at {i},{j}");
            assert!(
                (b[k] - want[0].hypot(want[1])).abs() <= tol.max(1e-6),
                "B at {i},{j}"
            );
        }
    }
}

#[test]
fn png_flowmaps_decode_within_quantisation() {
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::Png8, Format::Png16, Format::Raw],
        ..small(1)
    };
    let manifest_struct = run(&example("branching.json"), dir.path(), &opts);
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let scale = m["max_speed"].as_f64().unwrap() as f32;
    assert!((scale - manifest_struct.max_speed).abs() < 1e-6 && scale > 1.0);
    for (name, max, bits) in [("flow8.png", 255.0f32, 8), ("flow16.png", 65535.0, 16)] {
        let entry = file_of(&m, if bits == 8 { "png8" } else { "png16" })[0];
        let red = &entry["encoding"]["channels"][0];
        assert_eq!(red["scale"].as_f64().unwrap() as f32, 2.0 * scale);
        assert_eq!(red["offset"].as_f64().unwrap() as f32, -scale);
        let img = image::open(dir.path().join(name)).unwrap();
        assert_eq!((img.width(), img.height()), (48, 32));
        let img = img.to_rgb16();
        let step = 2.0 * scale / max; // one quantisation step in m/s
        for (i, j) in [(0, 0), (47, 31), (24, 16), (10, 5)] {
            let p = img.get_pixel(i as u32, j as u32);
            // to_rgb16 widens 8-bit values by 257; divide back to the file's own levels.
            let to_unit = |c: u16| {
                if bits == 8 {
                    f32::from(c) / 257.0 / 255.0
                } else {
                    f32::from(c) / 65535.0
                }
            };
            let decode = |c: u16| (to_unit(c) * 2.0 - 1.0) * scale;
            let want = raw.at(0, i, j);
            assert!(
                (decode(p[0]) - want[0]).abs() <= step,
                "{name} R at {i},{j}"
            );
            assert!(
                (decode(p[1]) - want[1]).abs() <= step,
                "{name} G at {i},{j}"
            );
            assert_eq!(p[2], 0, "{name} B unused");
        }
    }
}

/// `--flip-green` (the Export dialog's *Flowmap green: flipped*): the flowmaps and the atlas
/// store green as the world −z wind, so green grows up the image; red and the rest are as
/// without it, and the manifest says which. Through the CLI, as a user asks for it.
#[test]
fn flipped_green_grows_up_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/two-winds.json");
    let bake = |out: &Path, flip: bool| {
        let mut args = vec![
            "bake".to_string(),
            layout.display().to_string(),
            "--out".into(),
            out.display().to_string(),
            "--grid".into(),
            "48x32".into(),
            "--warmup".into(),
            "1".into(),
            "--frames".into(),
            "2".into(),
        ];
        for f in ["png8", "png16", "atlas", "raw"] {
            args.extend(["--format".to_string(), f.to_string()]);
        }
        if flip {
            args.push("--flip-green".into());
        }
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
            .args(&args)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    let (plain, flipped) = (dir.path().join("plain"), dir.path().join("flipped"));
    bake(&plain, false);
    bake(&flipped, true);
    let m = manifest(&flipped);
    let raw = Raw::read(&flipped, &m);
    let scale = m["max_speed"].as_f64().unwrap() as f32;
    for (format, file, max) in [
        ("png8", "flow8_0001.png", 255.0f32),
        ("png16", "flow16_0001.png", 65535.0),
        ("atlas", "atlas.png", 65535.0),
    ] {
        let entry = file_of(&m, format)[0];
        assert_eq!(entry["encoding"]["green_flipped"], true, "{format}");
        assert_eq!(entry["encoding"]["channels"][1]["axis"], "-z");
        let plain_entry = file_of(&manifest(&plain), format)[0].clone();
        assert_eq!(plain_entry["encoding"]["green_flipped"], false);
        let img = image::open(flipped.join(file)).unwrap().to_rgb16();
        let unflipped = image::open(plain.join(file)).unwrap().to_rgb16();
        let step = 2.0 * scale / max;
        let unit = |c: u16| f32::from(c) / 65535.0;
        // Frame 1: its own file, or the atlas's second sub-image.
        let x0 = if format == "atlas" { 48 } else { 0 };
        for (i, j) in [(0, 0), (47, 31), (24, 16), (10, 5)] {
            let p = img.get_pixel(x0 + i as u32, j as u32);
            let q = unflipped.get_pixel(x0 + i as u32, j as u32);
            let want = raw.at(1, i, j);
            let decode = |c: u16| (unit(c) * 2.0 - 1.0) * scale;
            assert_eq!(p[0], q[0], "{format}: red as without the flip");
            assert!(
                (decode(p[0]) - want[0]).abs() <= step,
                "{format} R at {i},{j}"
            );
            assert!(
                (decode(p[1]) + want[1]).abs() <= step,
                "{format} G at {i},{j}: {} is the wind toward north, the bake's z is {}",
                decode(p[1]),
                want[1]
            );
        }
    }
}

#[test]
fn atlas_holds_every_frame_where_the_manifest_says() {
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::Atlas, Format::Raw],
        ..small(5)
    };
    run(&example("obstacles.json"), dir.path(), &opts);
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let entry = file_of(&m, "atlas")[0];
    let sub = &entry["axes"]["sub_images"];
    let (cols, rows) = (
        sub["columns"].as_u64().unwrap() as u32,
        sub["rows"].as_u64().unwrap() as u32,
    );
    assert_eq!((cols, rows, sub["count"].as_u64().unwrap()), (3, 2, 5));
    let img = image::open(dir.path().join("atlas.png"))
        .unwrap()
        .to_rgb16();
    assert_eq!((img.width(), img.height()), (cols * 48, rows * 32));
    let scale = m["max_speed"].as_f64().unwrap() as f32;
    for frame in 0..5 {
        let (ox, oy) = ((frame as u32 % cols) * 48, (frame as u32 / cols) * 32);
        for (i, j) in [(0, 0), (47, 31), (20, 10)] {
            let p = img.get_pixel(ox + i as u32, oy + j as u32);
            let decode = |c: u16| (f32::from(c) / 65535.0 * 2.0 - 1.0) * scale;
            let want = raw.at(frame, i, j);
            assert!(
                (decode(p[0]) - want[0]).abs() <= 2.0 * scale / 65535.0,
                "frame {frame} at {i},{j}"
            );
            assert!((decode(p[1]) - want[1]).abs() <= 2.0 * scale / 65535.0);
        }
    }
    // The unused sixth cell is zero velocity.
    let p = img.get_pixel(2 * 48 + 5, 32 + 5);
    assert!((i32::from(p[0]) - 32768).abs() <= 1 && (i32::from(p[1]) - 32768).abs() <= 1);
}

/// An atlas bake and its raw frames, as the engine tests read it.
struct AtlasBake {
    _dir: tempfile::TempDir,
    raw: Raw,
    /// Sub-images: columns, rows.
    grid: [f64; 2],
    /// The flowmap's `encoding.scale`, m/s.
    scale: f64,
    fps: f64,
    img: image::ImageBuffer<image::Rgb<u16>, Vec<u16>>,
}

/// Bakes `frames` frames of the example `name` as an atlas (and raw, to compare with).
fn bake_atlas(name: &str, frames: usize) -> AtlasBake {
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::Atlas, Format::Raw],
        ..small(frames)
    };
    run(&example(name), dir.path(), &opts);
    let m = manifest(dir.path());
    let entry = file_of(&m, "atlas")[0];
    let sub = &entry["axes"]["sub_images"];
    AtlasBake {
        raw: Raw::read(dir.path(), &m),
        grid: [
            sub["columns"].as_u64().unwrap() as f64,
            sub["rows"].as_u64().unwrap() as f64,
        ],
        scale: {
            // What the Unreal scratch pad and the Godot shader are given.
            let unreal = &m["engines"]["unreal"]["niagara_atlas"]["scale"];
            assert_eq!(
                unreal,
                &m["engines"]["godot"]["shader_parameters"]["atlas_scale"]
            );
            unreal.as_f64().unwrap()
        },
        fps: sub["fps"].as_f64().unwrap(),
        img: image::open(dir.path().join("atlas.png"))
            .unwrap()
            .to_rgb16(),
        _dir: dir,
    }
}

impl AtlasBake {
    /// Frame `frame`'s texture coordinate for the level's `uv`, half a texel inside its
    /// sub-image (as both engine paths compute it).
    fn frame_uv(&self, frame: usize, uv: [f64; 2]) -> [f64; 2] {
        let size = [f64::from(self.img.width()), f64::from(self.img.height())];
        let columns = self.grid[0] as usize;
        let cell = [(frame % columns) as f64, (frame / columns) as f64];
        [0, 1].map(|a| {
            let half = 0.5 * self.grid[a] / size[a];
            (cell[a] + uv[a].clamp(half, 1.0 - half)) / self.grid[a]
        })
    }

    /// Linear filtering of channel `c` at texture coordinate `t` (texel centres at
    /// (i + 0.5) / size), clamped at the texture's edge, each 16-bit texel read as the
    /// engine imports it (`unit`).
    fn sample(&self, t: [f64; 2], c: usize, unit: impl Fn(u16) -> f64) -> f64 {
        let size = [self.img.width() as usize, self.img.height() as usize];
        bilinear(
            size,
            |x, y| unit(self.img.get_pixel(x as u32, y as u32)[c]),
            t,
        )
    }
}

/// Cell `k` of `n` along an axis as the level's uv: 0 and 1 for the first and last cell (the
/// level's edge), the cell's centre between.
fn edge_uv(k: usize, n: usize) -> f64 {
    if k == 0 {
        0.0
    } else if k == n - 1 {
        1.0
    } else {
        (k as f64 + 0.5) / n as f64
    }
}

/// The Godot grass shader's wind (`docs/engines/godot/addons/windloom/windloom_wind.gdshaderinc`) reads the animated atlas
/// as Godot samples it — linear filtering, clamped at the texture's edge, 8 bits a channel
/// (Godot's PNG loader keeps 8 of the 16) — and gets each frame's wind at every cell, the
/// level's edges included: its uv stops half a texel inside the frame's sub-image. With the
/// 0.001 margin it had, a sample at the edge took 40 % of the next frame.
#[test]
fn godot_reads_each_atlas_frame_to_the_level_s_edge() {
    let shader = include_str!("../../docs/engines/godot/addons/windloom/windloom_wind.gdshaderinc");
    // The emulation below is this line's arithmetic.
    assert!(
        shader.contains(
            "vec2 half_texel = 0.5 * vec2(atlas_grid) / vec2(textureSize(wind_atlas, 0));"
        ) && shader.contains("clamp(uv, half_texel, vec2(1.0) - half_texel)"),
        "the shader clamps as emulated here"
    );
    let atlas = bake_atlas("two-winds.json", 5);
    // Godot's 8-bit texel, as a unit value.
    let unit = |v: u16| f64::from((v >> 8) as u8) / 255.0;
    let (nx, ny) = (atlas.raw.nx, atlas.raw.ny);
    // 8-bit rounding of a 16-bit value, decoded: at most one 8-bit step.
    let step = 2.0 * atlas.scale / 255.0;
    for frame in 0..5 {
        // The level's edge and corners, where the world uv is 0 or 1.
        for (i, j) in [
            (0, 0),
            (nx - 1, 0),
            (0, ny - 1),
            (nx - 1, ny - 1),
            (0, ny / 2),
            (nx / 2, 0),
        ] {
            let auv = atlas.frame_uv(frame, [edge_uv(i, nx), edge_uv(j, ny)]);
            for (c, &want) in atlas.raw.at(frame, i, j).iter().enumerate() {
                let got = (atlas.sample(auv, c, unit) * 2.0 - 1.0) * atlas.scale;
                assert!(
                    (got - f64::from(want)).abs() <= step,
                    "frame {frame} cell {i},{j} channel {c}: {got} against {want}"
                );
            }
        }
    }
}

/// The Unreal guide's animated path (`docs/engines/unreal.md`): the atlas imported as HDR
/// (each 16-bit channel a half float), sampled bilinearly at the guide's UV (half a texel
/// inside the frame's sub-image), decoded `(rg * 2 - 1) * scale * 100` into cm/s with
/// Unreal X = world x and Y = world z. At every frame's edges and corners it is the bake's
/// wind within a half float's rounding.
#[test]
fn unreal_reads_each_atlas_frame_to_the_level_s_edge() {
    let guide = include_str!("../../docs/engines/unreal.md");
    assert!(
        guide.contains("float2 halfTexel = 0.5 * Grid / AtlasSize;")
            && guide.contains("OutUV = (cell + clamp(uv, halfTexel, 1.0 - halfTexel)) / Grid;")
            && guide.contains("(Sample.rg * 2 - 1) * Scale * 100"),
        "the guide's HLSL is what this test follows"
    );
    let atlas = bake_atlas("two-winds.json", 7);
    // HDR import: the unit value as a half float.
    let unit = |v: u16| f64::from(half::f16::from_f32(f32::from(v) / 65535.0).to_f32());
    let (lo, hi) = example("two-winds.json").bounds();
    let min_cm = [f64::from(lo[0]) * 100.0, f64::from(lo[1]) * 100.0];
    let size_cm = [
        f64::from(hi[0] - lo[0]) * 100.0,
        f64::from(hi[1] - lo[1]) * 100.0,
    ];
    let (nx, ny) = (atlas.raw.nx, atlas.raw.ny);
    // A half float near 1 holds 11 bits: the decoded wind to 2 · scale · 2^-11, plus the
    // 16-bit step.
    let tolerance = 2.0 * atlas.scale * (2f64.powi(-11) + 1.0 / 65535.0);
    for frame in 0..7 {
        let time = (frame as f64 + 0.5) / atlas.fps;
        let frame_at = (time * atlas.fps).floor() as usize % 7;
        assert_eq!(frame_at, frame);
        for (i, j) in [
            (0, 0),
            (nx - 1, 0),
            (0, ny - 1),
            (nx - 1, ny - 1),
            (nx - 1, ny / 2),
        ] {
            // The particle at the level's edge or corner, in cm (Unreal X, Y = world x, z).
            let position = [
                min_cm[0] + edge_uv(i, nx) * size_cm[0],
                min_cm[1] + edge_uv(j, ny) * size_cm[1],
            ];
            let uv = [0, 1].map(|a| (position[a] - min_cm[a]) / size_cm[a]);
            let out_uv = atlas.frame_uv(frame_at, uv);
            for (c, &want) in atlas.raw.at(frame, i, j).iter().enumerate() {
                let cm_s = (atlas.sample(out_uv, c, unit) * 2.0 - 1.0) * atlas.scale * 100.0;
                assert!(
                    (cm_s / 100.0 - f64::from(want)).abs() <= tolerance,
                    "frame {frame} cell {i},{j} axis {c}: {} m/s, the bake says {want}",
                    cm_s / 100.0
                );
            }
        }
    }
}

fn rms_diff(raw: &Raw, a: usize, b: usize) -> f32 {
    let mut s = 0.0f64;
    for j in 0..raw.ny {
        for i in 0..raw.nx {
            let (p, q) = (raw.at(a, i, j), raw.at(b, i, j));
            s += f64::from((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2));
        }
    }
    (s / (raw.nx * raw.ny) as f64).sqrt() as f32
}

#[test]
fn a_looped_bake_has_no_seam() {
    // The pulsed north-east gust makes the field change all the time.
    let layout = example("obstacles.json");
    let n = 12;
    let opts = |looped| BakeOptions {
        formats: vec![Format::Raw],
        looped,
        ..small(n)
    };
    let plain = tempfile::tempdir().unwrap();
    run(&layout, plain.path(), &opts(false));
    let raw_plain = Raw::read(plain.path(), &manifest(plain.path()));
    let looped = tempfile::tempdir().unwrap();
    run(&layout, looped.path(), &opts(true));
    let m = manifest(looped.path());
    assert_eq!(m["frames"]["loop"], true);
    assert!(
        m["frames"]["loop_method"]
            .as_str()
            .unwrap()
            .contains("crossfade")
    );
    let raw = Raw::read(looped.path(), &m);
    let steps: Vec<f32> = (0..n - 1).map(|k| rms_diff(&raw, k, k + 1)).collect();
    let typical = steps.iter().copied().fold(0.0, f32::max);
    let seam = rms_diff(&raw, n - 1, 0);
    let plain_seam = rms_diff(&raw_plain, n - 1, 0);
    println!("loop seam {seam}, largest step {typical}, seam without --loop {plain_seam}");
    assert!(seam <= 1.5 * typical, "seam {seam} vs steps {steps:?}");
    assert!(
        plain_seam > 2.0 * seam,
        "without --loop the jump is larger: {plain_seam} vs {seam}"
    );
}

#[test]
fn every_example_bakes_in_every_format_and_the_same_bake_gives_the_same_bytes() {
    for name in [
        "meadow.json",
        "two-winds.json",
        "branching.json",
        "obstacles.json",
        "breeze-fft.json",
        "walled-garden.json",
    ] {
        let layout = example(name);
        let a = tempfile::tempdir().unwrap();
        let b = tempfile::tempdir().unwrap();
        let opts = BakeOptions {
            warmup: 0.5,
            frames: 2,
            grid: Some([40, 40]),
            ..Default::default()
        };
        let m = run(&layout, a.path(), &opts);
        run(&layout, b.path(), &opts);
        let formats: BTreeSet<Format> = m.files.iter().map(|f| f.format).collect();
        assert_eq!(formats.len(), Format::ALL.len(), "{name}");
        for f in m
            .files
            .iter()
            .map(|f| f.name.clone())
            .chain(["manifest.json".into()])
        {
            let x = std::fs::read(a.path().join(&f)).unwrap();
            let y = std::fs::read(b.path().join(&f)).unwrap();
            assert!(x == y, "{name}: {f} differs between two identical bakes");
        }
    }
}

fn entries(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir).map_or_else(|_| Vec::new(), |r| r.map(|e| e.unwrap().path()).collect())
}

#[test]
fn cancelled_or_failed_bakes_leave_no_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let cancel = AtomicBool::new(false);
    let mut calls = 0;
    let result = bake::bake(
        &example("meadow.json"),
        &out,
        &small(4),
        &cancel,
        &mut |_, _, _| {
            calls += 1;
            if calls == 3 {
                cancel.store(true, std::sync::atomic::Ordering::SeqCst);
            }
        },
    );
    assert!(
        matches!(result, Err(bake::BakeError::Cancelled)),
        "{result:?}"
    );
    assert!(entries(&out).is_empty(), "{:?}", entries(&out));

    // An output "folder" that is a file is a clear error.
    let file = dir.path().join("not-a-folder");
    std::fs::write(&file, "x").unwrap();
    let err = bake::bake(
        &example("meadow.json"),
        &file,
        &small(1),
        &AtomicBool::new(false),
        &mut |_, _, _| {},
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("cannot use output folder") && err.contains("not-a-folder"),
        "{err}"
    );

    // Bad settings are refused before anything is written.
    let bad = BakeOptions {
        looped: true,
        ..small(1)
    };
    let err = bake::bake(
        &example("meadow.json"),
        &out,
        &bad,
        &AtomicBool::new(false),
        &mut |_, _, _| {},
    )
    .unwrap_err();
    // The library names the setting as the Export dialog does; the CLI says it with its
    // flags (`cli_says_bake_settings_with_its_flags`).
    assert!(
        matches!(
            err,
            bake::BakeError::Settings(bake::SettingsError::LoopTooShort)
        ),
        "{err}"
    );
    assert!(
        err.to_string().contains("a loop needs 2 frames or more"),
        "{err}"
    );
    assert!(entries(&out).is_empty());
}

/// The settings a bake refuses, said on the command line with the flags that change them
/// (the library's errors are typed and name no flag: the Export dialog shows the same ones).
#[test]
fn cli_says_bake_settings_with_its_flags() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bake");
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/meadow.json");
    let cases: [(&[&str], &str); 6] = [
        (&["--frames", "0"], "--frames must be 1 to 100000, got 0"),
        (&["--fps", "0"], "--fps must be between 0 and 1000, got 0"),
        (
            &["--warmup=-1"],
            "--warmup must be 0 to 36000 seconds, got -1",
        ),
        (&["--loop"], "--loop needs --frames 2 or more"),
        (
            &["--frames", "90000", "--fps", "1"],
            "raise --fps or bake fewer --frames",
        ),
        (
            &["--frames", "5000", "--format", "atlas", "--grid", "512x512"],
            "or leave out --format atlas",
        ),
    ];
    for (flags, said) in cases {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
            .args([
                "bake",
                layout.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ])
            .args(flags)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{flags:?}: {err}");
        assert!(
            err.starts_with("error: invalid bake settings: "),
            "{flags:?}: {err}"
        );
        assert!(err.contains(said), "{flags:?}: {err}");
        assert!(!out.exists(), "{flags:?} wrote nothing");
    }
    // A budget too small is said with the flag that raises it.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args([
            "bake",
            layout.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .args(["--max-disk", "1K"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("or raise --max-disk"), "{err}");
}

#[test]
fn cli_bake_and_render() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bake");
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/meadow.json");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args([
            "bake",
            layout.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--format",
            "vf",
            "--format",
            "raw",
            "--grid",
            "32x16",
            "--warmup",
            "0.5",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut names: Vec<String> = entries(&out)
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["manifest.json", "wind.f32", "wind.vf"]);
    // An unwritable output is a clear, non-zero error.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args([
            "bake",
            layout.to_str().unwrap(),
            "--out",
            layout.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("cannot use output folder"));

    let png = dir.path().join("meadow.png");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args([
            "render",
            layout.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--size",
            "640x400",
            "--time",
            "2",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!((img.width(), img.height()), (640, 400));
    // The picture is not blank: it holds many colours (streamlines, legend, arrows).
    let colours: BTreeSet<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    assert!(colours.len() > 500, "{} colours", colours.len());
}

/// A headless grass picture from a job with no desktop session (no `XDG_RUNTIME_DIR`)
/// succeeds with nothing on stderr (Mesa's device-select layer used to print two
/// "error: XDG_RUNTIME_DIR is invalid" lines); an empty `WGPU_BACKEND` means every backend,
/// as unset does; one naming no backend is a one-line error that names the variable.
#[test]
fn a_headless_grass_picture_is_quiet_and_wgpu_backend_is_read_as_meant() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("grass.png");
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/meadow.json");
    let render = |backend: Option<&str>| {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"));
        c.args([
            "render",
            layout.to_str().unwrap(),
            "--view",
            "grass",
            "-o",
            png.to_str().unwrap(),
            "--size",
            "96x64",
        ])
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("NODEVICE_SELECT")
        .env_remove("RUST_LOG");
        match backend {
            Some(b) => c.env("WGPU_BACKEND", b),
            None => c.env_remove("WGPU_BACKEND"),
        };
        let o = c.output().unwrap();
        (
            o.status.success(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (ok, stderr) = render(None);
    if !ok && stderr.contains("no GPU adapter") && std::env::var_os("CI").is_none() {
        eprintln!("\n!!! SKIPPING a GPU test: {stderr}\n");
        return;
    }
    assert!(ok, "render --view grass failed: {stderr}");
    assert_eq!(
        stderr, "",
        "a successful headless render prints nothing on stderr"
    );
    let (ok, stderr) = render(Some(""));
    assert!(
        ok && stderr.is_empty(),
        "an empty WGPU_BACKEND is unset: {stderr}"
    );
    let (ok, stderr) = render(Some("vulcan"));
    assert!(!ok, "a backend wgpu does not know is an error");
    assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
    assert!(
        stderr.contains("WGPU_BACKEND=\"vulcan\"") && stderr.contains("vulkan, gl"),
        "the error names the variable and what it may hold: {stderr}"
    );
}

#[test]
fn render_draws_the_arrows_and_wind_where_they_are() {
    let layout = example("two-winds.json");
    let mut solver = windloom::sim::Solver::new(&layout);
    for _ in 0..240 {
        solver.step();
    }
    let pix = windloom::render::render(&layout, Path::new("."), &solver, 800, 600).unwrap();
    // Find a pixel of the arrow colour (70, 160, 255) along the west tree's first arrow.
    let arrow_pixels = pix
        .pixels()
        .iter()
        .filter(|p| {
            let c = p.demultiply();
            (i32::from(c.red()) - 70).abs() < 8
                && (i32::from(c.green()) - 160).abs() < 8
                && (i32::from(c.blue()) - 255).abs() < 8
        })
        .count();
    assert!(arrow_pixels > 500, "arrows drawn: {arrow_pixels} pixels");
}

/// `render --speed-scale`: a fixed top for the speed colours. At the field's own peak it is
/// the default picture, pixel for pixel; at four times the peak the fastest wind is drawn
/// with the colours of a quarter of the scale, so the picture changes; out of range is
/// refused by name.
#[test]
fn render_takes_a_fixed_speed_scale() {
    let layout = example("two-winds.json");
    let mut solver = windloom::sim::Solver::new(&layout);
    for _ in 0..120 {
        solver.step();
    }
    let peak = solver
        .velocity_field()
        .iter()
        .map(|v| v[0].hypot(v[1]))
        .fold(1e-3f32, f32::max);
    let draw = |scale| {
        windloom::render::render_scaled(&layout, Path::new("."), &solver, [400, 300], scale)
            .unwrap()
            .data()
            .to_vec()
    };
    let plain = draw(None);
    assert!(
        plain == draw(Some(peak)),
        "the peak as a fixed scale is the default"
    );
    let wide = draw(Some(4.0 * peak));
    let changed = plain
        .chunks(4)
        .zip(wide.chunks(4))
        .filter(|(a, b)| a.iter().zip(*b).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    assert!(
        changed > 2_000,
        "a wider scale recolours the wind: {changed} pixels"
    );

    let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args([
            "render",
            "layouts/two-winds.json",
            "-o",
            "/dev/null",
            "--speed-scale",
            "0.1",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("--speed-scale") && err.contains("0.5 to 200"),
        "{err}"
    );
}

#[test]
fn ctrl_c_during_a_cli_bake_leaves_no_files() {
    // Ctrl-C, and what `docker stop`, `timeout` and a cancelled CI job send (SIGTERM), and a
    // closed terminal (SIGHUP): each cancels the bake, which cleans up.
    for signal in ["INT", "TERM", "HUP"] {
        signal_cancels_a_bake(signal);
    }
}

fn signal_cancels_a_bake(signal: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bake");
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/obstacles.json");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args([
            "bake",
            layout.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--frames",
            "500",
            "--format",
            "raw",
            "--grid",
            "256x256",
            "--backend",
            "auto",
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the bake has started (its staging folder beside `bake` exists), then press
    // Ctrl-C.
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while staging_folders(dir.path()).is_empty() {
        assert!(
            std::time::Instant::now() < deadline,
            "the bake never started"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let status = std::process::Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(130),
        "SIG{signal}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("no files were written"));
    assert!(!out.exists(), "{:?}", entries(&out));
    assert!(
        staging_folders(dir.path()).is_empty(),
        "{:?}",
        entries(dir.path())
    );
}

fn staging_folders(dir: &Path) -> Vec<PathBuf> {
    entries(dir)
        .into_iter()
        .filter(|p| p.to_string_lossy().contains(".windloom-bake-"))
        .collect()
}

/// The engine-side scripts, run against bakes.
mod engines;
/// `bake --watch` and an engine polling its folder (Unix: it stops the watch with SIGINT).
#[cfg(unix)]
mod live;
/// The manifest's schema, and every file decoded by the manifest alone.
mod manifest;
/// `windloom probe` and the probes' statistics.
mod probes;
/// The runtime: a bake read back as a game reads it, from Rust and from C.
mod runtime;
/// Terrain: the shaped wind and the heights in a bake.
mod terrain;
/// What a studio must be able to trust: frame timing, other EXR readers, one bake per
/// folder, limits and modes, and no half-written output after a kill.
mod trust;
/// The volume: DDS, the log law, Unity's and Godot's volume paths.
mod volume;

/// Hostile files, folders, signals and file systems, each ending in a result or a one-line
/// refusal within seconds.
mod hostile;
/// A bake as a hostile game asset, read by the runtime; its edges and its clock.
mod lying_bakes;

/// The half-float EXR atlas, read as Godot reads an EXR (floats, not 8 bits) and sampled as
/// `windloom_grass.gdshader` does with `atlas_is_float` (the manifest's choice when the bake
/// has it): each frame's wind at the level's edges within half-float rounding, ten times
/// closer than the 16-bit PNG atlas gets in Godot.
#[test]
fn godot_reads_the_float_atlas_at_full_precision() {
    use exr::prelude::*;
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::AtlasExr, Format::Atlas, Format::Raw],
        ..small(5)
    };
    run(&example("two-winds.json"), dir.path(), &opts);
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let p = &m["engines"]["godot"]["shader_parameters"];
    assert_eq!(p["wind_atlas"], "atlas.exr", "Godot gets the float atlas");
    assert_eq!(p["atlas_is_float"], true);
    let grid = [
        p["atlas_grid"][0].as_f64().unwrap(),
        p["atlas_grid"][1].as_f64().unwrap(),
    ];
    let image = read_all_flat_layers_from_file(dir.path().join("atlas.exr")).unwrap();
    let layer = &image.layer_data[0];
    let (w, h) = (layer.size.width(), layer.size.height());
    let channel = |name: &str| -> Vec<f32> {
        let c = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
            .unwrap();
        c.sample_data.values_as_f32().collect()
    };
    let rg = [channel("R"), channel("G")];
    let sample = |t: [f64; 2], c: usize| bilinear([w, h], |x, y| f64::from(rg[c][y * w + x]), t);
    let (nx, ny) = (raw.nx, raw.ny);
    let mut worst = 0.0f64;
    for frame in 0..5 {
        for (i, j) in [
            (0, 0),
            (nx - 1, 0),
            (0, ny - 1),
            (nx - 1, ny - 1),
            (nx / 2, ny / 2),
        ] {
            let uv = [edge_uv(i, nx), edge_uv(j, ny)];
            let columns = grid[0] as usize;
            let cell = [(frame % columns) as f64, (frame / columns) as f64];
            let size = [w as f64, h as f64];
            let auv: [f64; 2] = [0, 1].map(|a| {
                let half = 0.5 * grid[a] / size[a];
                (cell[a] + uv[a].clamp(half, 1.0 - half)) / grid[a]
            });
            for (c, &want) in raw.at(frame, i, j).iter().enumerate() {
                let got = sample(auv, c);
                let err = (got - f64::from(want)).abs();
                worst = worst.max(err);
                assert!(
                    err <= 1e-3 * f64::from(want).abs() + 1e-4,
                    "frame {frame} cell {i},{j} channel {c}: {got} against {want}"
                );
            }
        }
    }
    let png_step = 2.0 * m["max_speed"].as_f64().unwrap() / 255.0;
    assert!(
        worst * 10.0 < png_step,
        "{worst} m/s against the PNG's {png_step}"
    );
}

/// A backdrop placed by `world.map.rect` lines up with the world where it says: rendered over
/// the east half only, the picture's colour is there and not in the west half; the 3D view's
/// ground lays it the same way (`backdrop_rect` in the grass scene).
#[test]
fn a_placed_backdrop_lands_where_its_rectangle_says() {
    let dir = tempfile::tempdir().unwrap();
    image::RgbaImage::from_pixel(8, 8, image::Rgba([250, 20, 200, 255]))
        .save(dir.path().join("level.png"))
        .unwrap();
    let mut layout = example("meadow.json");
    layout.trees.clear();
    layout.ambient.clear();
    let (lo, hi) = layout.bounds();
    let mid = (lo[0] + hi[0]) / 2.0;
    layout.world.map = Some(windloom::doc::MapBackdrop {
        image: "level.png".into(),
        opacity: 1.0,
        rect: Some([[mid, lo[1]], [hi[0], hi[1]]]),
    });
    assert!(windloom::doc::validate(&layout).is_empty());
    let solver = windloom::sim::Solver::new(&layout);
    let pix = windloom::render::render(&layout, dir.path(), &solver, 800, 600).unwrap();
    let magenta = |x: u32, y: u32| {
        let c = pix.pixel(x, y).unwrap().demultiply();
        c.red() > 200 && c.green() < 60 && c.blue() > 160
    };
    // The world spans most of the picture; sample a row through its middle.
    let row = 300;
    let (west, east): (Vec<u32>, Vec<u32>) = (100..700).partition(|&x| x < 400);
    let east_hits = east.iter().filter(|&&x| magenta(x, row)).count();
    let west_hits = west.iter().filter(|&&x| magenta(x, row)).count();
    assert!(
        east_hits > 200 && west_hits == 0,
        "east {east_hits}, west {west_hits}"
    );
    // Corners out of order are refused by name.
    let mut bad = layout.clone();
    bad.world.map.as_mut().unwrap().rect = Some([[hi[0], lo[1]], [mid, hi[1]]]);
    let issues = windloom::doc::validate(&bad);
    assert!(
        issues.iter().any(|i| i.path == "world.map.rect"),
        "{issues:?}"
    );
}
