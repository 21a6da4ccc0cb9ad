//! Unity VFX Graph vector fields (`VF_V`): little-endian, sizes as three u16, then f32 x, y, z
//! per cell, X fastest, then Y, then Z. Unity is Y-up and left-handed: X = east, Y = up,
//! Z = north, so a world row `j` (counted southward) becomes Z index `ny − 1 − j` and the
//! world z velocity is negated.
//!
//! Each vector is the wind in m/s divided by the field's box size on its axis (the world's
//! width and depth, 1 m in Y): VFX Graph's *Vector Field Force* turns a sample into a force
//! target by the box's transform (`mul(FieldTransform, float4(value, 0))`, in
//! `VectorFieldForce.cs`), which multiplies each axis by the box's size. With the box set to
//! the world rectangle, *Data Encoding* Signed and *Intensity* 1, the target is the wind in
//! m/s. The manifest's channel `scale` is that size per axis (`value = stored × scale`).

use super::error::BakeError;
use super::field::Field;
use super::format::{Encoder, Extent, frame_names};
use super::format::{ExportContext, Output};
use super::manifest::{Axes, Channel, Encoding, IndexAxis, Sample, WorldAxis};
use super::manifest::{FileEntry, Format};

/// Bytes of one file for an `nx × ny` grid.
fn size(nx: usize, ny: usize) -> u64 {
    10 + 12 * (nx * ny) as u64
}

/// The field box's size in Unity's X, Y, Z (metres): the world's width, a 1 m slab, its
/// depth; VFX Graph multiplies each stored value by it.
pub(crate) fn box_size(ctx: &ExportContext) -> [f32; 3] {
    [ctx.max[0] - ctx.min[0], 1.0, ctx.max[1] - ctx.min[1]]
}

/// A VF file of `f` carried up `factors` (one Y layer per factor, the field times it), in
/// a box of `box_size` whose Y covers `y_range` metres: `STEM.vf` or `STEM_NNNN.vf`, its
/// manifest entry under `format`. The 2D field is one layer of factor 1 in a 1 m slab; the
/// volume (`volume.rs`) is its layers up the profile.
#[allow(
    clippy::too_many_arguments,
    reason = "each says one thing about the file"
)]
pub(crate) fn field(
    ctx: &ExportContext,
    k: usize,
    f: &Field,
    stem: &str,
    format: Format,
    factors: &[f32],
    box_size: [f32; 3],
    y_range: [f32; 2],
) -> Output {
    let (nx, ny, nl) = (f.nx, f.ny, factors.len());
    let mut bytes = Vec::with_capacity(size(nx, ny * nl) as usize);
    bytes.extend_from_slice(b"VF_V");
    for n in [nx, nl, ny] {
        bytes.extend_from_slice(&(n as u16).to_le_bytes());
    }
    for kz in 0..ny {
        let j = ny - 1 - kz;
        for s in factors {
            for i in 0..nx {
                let v = f.at(i, j);
                for c in [v[0] * s / box_size[0], 0.0, -(v[1] * s) / box_size[2]] {
                    bytes.extend_from_slice(&c.to_le_bytes());
                }
            }
        }
    }
    let name = ctx.name(stem, k, "vf");
    Output {
        entry: FileEntry {
            name: name.clone(),
            format,
            frame: ctx.frame_index(k),
            grid: [nx, ny],
            resampled_from: None,
            encoding: Encoding {
                sample: Sample::F32,
                units: "m/s",
                channels: vec![
                    Channel::velocity("X", WorldAxis::PlusX, box_size[0], 0.0),
                    Channel::velocity("Y", WorldAxis::PlusY, box_size[1], 0.0),
                    Channel::velocity("Z", WorldAxis::MinusZ, box_size[2], 0.0),
                ],
                green_flipped: None,
                storage: "VF_V: \"VF_V\", u16 sizes X, Y, Z, then f32 X, Y, Z per cell, X fastest, then Y, then Z (little-endian)"
                    .to_string(),
            },
            axes: Axes {
                index: vec![
                    IndexAxis {
                        name: "X",
                        world: WorldAxis::PlusX,
                        cells: nx,
                        range: [ctx.min[0], ctx.max[0]],
                    },
                    IndexAxis {
                        name: "Y",
                        world: WorldAxis::PlusY,
                        cells: nl,
                        range: y_range,
                    },
                    IndexAxis {
                        name: "Z",
                        world: WorldAxis::MinusZ,
                        cells: ny,
                        range: [ctx.min[1], ctx.max[1]],
                    },
                ],
                sub_images: None,
                engine_frame: Some("Unity: X east, Y up, Z north (left-handed, metres)"),
            },
            bytes: 0,
            crc32: 0,
        },
        name,
        bytes,
    }
}

fn frame(ctx: &ExportContext, k: usize, f: &Field) -> Output {
    let b = box_size(ctx);
    field(
        ctx,
        k,
        f,
        "wind",
        Format::Vf,
        &[1.0],
        b,
        [-b[1] / 2.0, b[1] / 2.0],
    )
}

/// Bytes of one volume file of `layers` layers (the volume's `max_bytes`).
pub(crate) fn volume_size(nx: usize, ny: usize, layers: usize) -> u64 {
    size(nx, ny * layers)
}

/// The VF format.
pub(crate) struct Vf;

impl Encoder for Vf {
    fn names(&self, count: usize) -> Vec<String> {
        frame_names("wind", count, "vf")
    }

    fn max_bytes(&self, e: &Extent) -> u64 {
        let (nx, ny, frames) = (e.nx, e.ny, e.frames);
        frames as u64 * size(nx, ny)
    }

    fn frame(&self, ctx: &ExportContext, k: usize, f: &Field) -> Result<Vec<Output>, BakeError> {
        Ok(vec![frame(ctx, k, f)])
    }
}
