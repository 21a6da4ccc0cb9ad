//! The wind as a volume (`--format dds`): the baked 2D field carried up through the layout's
//! vertical profile (`world.profile`, the log law: zero at the roughness length, the
//! simulated wind at the reference height), `layers` layers from the ground to `top`, layer
//! `k` at height `(k + 0.5) · top / layers`. Written three ways, one per engine path:
//!
//! - `wind_volume.dds`: a DirectX 10 DDS 3D texture (`DXGI_FORMAT_R32G32B32A32_FLOAT`, or
//!   `R16G16B16A16_FLOAT` with `--half`), width along +x, height along +z (row 0 at the world's
//!   minimum z), depth up the layers; R, G, B the wind along world x, y (0), z, A the speed.
//!   Unreal imports it as a Volume Texture.
//! - `wind_volume.vf`: the same volume as a Unity `VF_V` field of `(nx, layers, ny)`, in Unity's
//!   axes and divided by the field box's size, as `vf.rs` writes the 2D one, for VFX Graph.
//! - `wind_volume.exr`: the layers as slices stacked down one EXR image (slice `k`, a top-down
//!   image as `wind.exr`, at rows `k · ny …`), RGB the wind along x, y, z: what Godot 4's
//!   *Texture3D* importer builds a `Texture3D` from.

use super::error::BakeError;
use super::exr::{rgb_bytes, rgb_max_bytes};
use super::field::Field;
use super::format::{Encoder, Extent, frame_names};
use super::format::{ExportContext, Output};
use super::manifest::{Axes, Channel, Encoding, IndexAxis, Sample, WorldAxis};
use super::manifest::{FileEntry, Format, factors};

/// The DDS header's size: magic, `DDS_HEADER`, `DDS_HEADER_DXT10`.
pub(crate) const DDS_HEADER_BYTES: usize = 4 + 124 + 20;
pub(crate) const DXGI_R32G32B32A32_FLOAT: u32 = 2;
pub(crate) const DXGI_R16G16B16A16_FLOAT: u32 = 10;

/// The volume's cell `(i, j, layer)`: `[x, y, z]` wind, m/s.
fn at(f: &Field, factors: &[f32], i: usize, j: usize, layer: usize) -> [f32; 3] {
    let v = f.at(i, j);
    let s = factors[layer];
    [v[0] * s, 0.0, v[1] * s]
}

fn dds(ctx: &ExportContext, k: usize, f: &Field, factors: &[f32]) -> Output {
    let (nx, ny, nl) = (f.nx, f.ny, factors.len());
    let texel = if ctx.half { 8 } else { 16 };
    let mut b = Vec::with_capacity(DDS_HEADER_BYTES + nx * ny * nl * texel);
    let u32s = |b: &mut Vec<u8>, values: &[u32]| {
        for v in values {
            b.extend_from_slice(&v.to_le_bytes());
        }
    };
    b.extend_from_slice(b"DDS ");
    // DDS_HEADER: size, flags (CAPS | HEIGHT | WIDTH | PITCH | PIXELFORMAT | MIPMAPCOUNT |
    // DEPTH), height, width, pitch, depth, mip levels, 11 reserved.
    u32s(
        &mut b,
        &[
            124,
            0x1 | 0x2 | 0x4 | 0x8 | 0x1000 | 0x2_0000 | 0x80_0000,
            ny as u32,
            nx as u32,
            (nx * texel) as u32,
            nl as u32,
            1,
        ],
    );
    u32s(&mut b, &[0; 11]);
    // DDS_PIXELFORMAT: size, FOURCC, "DX10", no masks.
    u32s(&mut b, &[32, 0x4]);
    b.extend_from_slice(b"DX10");
    u32s(&mut b, &[0; 5]);
    // caps (COMPLEX | TEXTURE), caps2 (VOLUME), caps3, caps4, reserved.
    u32s(&mut b, &[0x8 | 0x1000, 0x20_0000, 0, 0, 0]);
    // DDS_HEADER_DXT10: format, TEXTURE3D, misc, array size 1, misc2.
    let format = if ctx.half {
        DXGI_R16G16B16A16_FLOAT
    } else {
        DXGI_R32G32B32A32_FLOAT
    };
    u32s(&mut b, &[format, 4, 0, 1, 0]);
    debug_assert_eq!(b.len(), DDS_HEADER_BYTES);
    for layer in 0..nl {
        for j in 0..ny {
            for i in 0..nx {
                let w = at(f, factors, i, j, layer);
                for c in [w[0], w[1], w[2], crate::num::hypot(w[0], w[2])] {
                    if ctx.half {
                        b.extend_from_slice(&half::f16::from_f32(c).to_le_bytes());
                    } else {
                        b.extend_from_slice(&c.to_le_bytes());
                    }
                }
            }
        }
    }
    let name = ctx.name("wind_volume", k, "dds");
    let storage = format!(
        "DDS with a DX10 header: 3D texture, DXGI format {format} ({}), one mip level; texels row by row, rows slice by slice",
        if ctx.half {
            "R16G16B16A16_FLOAT"
        } else {
            "R32G32B32A32_FLOAT"
        }
    );
    Output {
        entry: entry(
            ctx,
            k,
            &name,
            (nx, ny),
            true,
            storage,
            ["width", "height", "depth"],
        ),
        name,
        bytes: b,
    }
}

/// The manifest entry of a volume file holding the wind along world x, y, z as R, G, B (and
/// the speed as A, `speed`), floats as the bake's width, its index axes `axes`: the grid's
/// two, then up the layers.
fn entry(
    ctx: &ExportContext,
    k: usize,
    name: &str,
    (nx, ny): (usize, usize),
    speed: bool,
    storage: String,
    axes: [&'static str; 3],
) -> FileEntry {
    let mut channels = vec![
        Channel::velocity("R", WorldAxis::PlusX, 1.0, 0.0),
        Channel::velocity("G", WorldAxis::PlusY, 1.0, 0.0),
        Channel::velocity("B", WorldAxis::PlusZ, 1.0, 0.0),
    ];
    if speed {
        channels.push(Channel::speed("A"));
    }
    FileEntry {
        name: name.to_string(),
        format: Format::Dds,
        frame: ctx.frame_index(k),
        grid: [nx, ny],
        resampled_from: None,
        encoding: Encoding {
            sample: if ctx.half { Sample::F16 } else { Sample::F32 },
            units: "m/s",
            channels,
            green_flipped: None,
            storage,
        },
        axes: volume_axes(ctx, nx, ny, axes),
        bytes: 0,
        crc32: 0,
    }
}

/// Index axes of a volume whose first two axes run as the grid's and whose third goes up.
fn volume_axes(ctx: &ExportContext, nx: usize, ny: usize, names: [&'static str; 3]) -> Axes {
    Axes {
        index: vec![
            IndexAxis {
                name: names[0],
                world: WorldAxis::PlusX,
                cells: nx,
                range: [ctx.min[0], ctx.max[0]],
            },
            IndexAxis {
                name: names[1],
                world: WorldAxis::PlusZ,
                cells: ny,
                range: [ctx.min[1], ctx.max[1]],
            },
            IndexAxis {
                name: names[2],
                world: WorldAxis::PlusY,
                cells: ctx.profile.layers as usize,
                range: [0.0, ctx.profile.top],
            },
        ],
        sub_images: None,
        engine_frame: None,
    }
}

/// The Unity box of the volume: the world's width, the volume's height, its depth.
pub(crate) fn unity_box(ctx: &ExportContext) -> [f32; 3] {
    [
        ctx.max[0] - ctx.min[0],
        ctx.profile.top,
        ctx.max[1] - ctx.min[1],
    ]
}

fn vf(ctx: &ExportContext, k: usize, f: &Field, factors: &[f32]) -> Output {
    let top = ctx.profile.top;
    super::vf::field(
        ctx,
        k,
        f,
        "wind_volume",
        Format::Dds,
        factors,
        unity_box(ctx),
        [0.0, top],
    )
}

fn slices(ctx: &ExportContext, k: usize, f: &Field, factors: &[f32]) -> Result<Output, BakeError> {
    let (nx, ny, nl) = (f.nx, f.ny, factors.len());
    let name = ctx.name("wind_volume", k, "exr");
    let bytes = rgb_bytes(&name, (nx, ny * nl), ctx.half, |x, y| {
        let w = at(f, factors, x, y % ny, y / ny);
        (w[0], w[1], w[2])
    })?;
    let storage = format!(
        "OpenEXR scanline, increasing Y, ZIP: {nl} slices of {nx} × {ny} pixels stacked down the image, slice k (layer k) at rows k · {ny}"
    );
    Ok(Output {
        entry: entry(
            ctx,
            k,
            &name,
            (nx, ny),
            false,
            storage,
            ["pixel_x", "pixel_y", "slice"],
        ),
        name,
        bytes,
    })
}

/// The volume format: three files a frame.
pub(crate) struct Volume;

impl Encoder for Volume {
    fn names(&self, count: usize) -> Vec<String> {
        ["dds", "vf", "exr"]
            .iter()
            .flat_map(|ext| frame_names("wind_volume", count, ext))
            .collect()
    }

    fn max_bytes(&self, e: &Extent) -> u64 {
        let cells = (e.nx * e.ny * e.layers) as u64;
        let dds = DDS_HEADER_BYTES as u64 + cells * if e.half { 8 } else { 16 };
        let vf = super::vf::volume_size(e.nx, e.ny, e.layers);
        let exr = rgb_max_bytes(e.nx, e.ny * e.layers, e.half);
        e.frames as u64 * (dds + vf + exr)
    }

    fn frame(&self, ctx: &ExportContext, k: usize, f: &Field) -> Result<Vec<Output>, BakeError> {
        let factors = factors(&ctx.profile);
        Ok(vec![
            dds(ctx, k, f, &factors),
            vf(ctx, k, f, &factors),
            slices(ctx, k, f, &factors)?,
        ])
    }
}
