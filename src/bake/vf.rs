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
//! m/s. The manifest's `encoding.scale` is that size per axis (`value = stored × scale`).

use super::format::{Encoder, frame_names};
use super::{BakeError, ExportContext, Field, FileEntry, Format, Output};

/// Bytes of one file for an `nx × ny` grid.
fn size(nx: usize, ny: usize) -> u64 {
    10 + 12 * (nx * ny) as u64
}

fn frame(ctx: &ExportContext, k: usize, f: &Field) -> Output {
    let (nx, ny) = (f.nx, f.ny);
    // The box's size in Unity's X, Y, Z (metres): the world's width, a 1 m slab, its depth.
    let box_size = [ctx.max[0] - ctx.min[0], 1.0, ctx.max[1] - ctx.min[1]];
    let mut bytes = Vec::with_capacity(size(nx, ny) as usize);
    bytes.extend_from_slice(b"VF_V");
    for size in [nx, 1, ny] {
        bytes.extend_from_slice(&(size as u16).to_le_bytes());
    }
    for kz in 0..ny {
        let j = ny - 1 - kz;
        for i in 0..nx {
            let v = f.at(i, j);
            for c in [v[0] / box_size[0], 0.0, -v[1] / box_size[2]] {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    let name = ctx.name("wind", k, "vf");
    Output {
        entry: FileEntry {
            name: name.clone(),
            format: Format::Vf,
            frame: ctx.frame_index(k),
            grid: [nx, ny],
            resampled_from: None,
            encoding: serde_json::json!({
                "units": "m/s", "scale": box_size, "offset": 0.0, "size": [nx, 1, ny],
                "decode": "velocity = stored × scale per axis (X, Y, Z): the box size VFX Graph multiplies a sample by",
                "unity_vfx_graph": {
                    "block": "Vector Field Force", "data_encoding": "Signed", "intensity": 1.0,
                    "closed_field": true, "conserve_magnitude": false,
                    "box_center": [(ctx.min[0] + ctx.max[0]) / 2.0, 0.0, -(ctx.min[1] + ctx.max[1]) / 2.0],
                    "box_size": box_size,
                    "import": {"output_format": "Float", "wrap_mode": "Clamp", "filter_mode": "Bilinear"},
                },
            }),
            axes: serde_json::json!({
                "unity": "Y-up, left-handed, metres",
                "X": "world +x (east)", "Y": "world +y (up)", "Z": "world -z (north)",
                "index": "x + X*(y + Y*z) with z = ny - 1 - grid row",
            }),
            bytes: 0,
        },
        name,
        bytes,
    }
}

/// The VF format.
pub(crate) struct Vf;

impl Encoder for Vf {
    fn names(&self, count: usize) -> Vec<String> {
        frame_names("wind", count, "vf")
    }

    fn max_bytes(&self, nx: usize, ny: usize, frames: usize, _half: bool) -> u64 {
        frames as u64 * size(nx, ny)
    }

    fn frame(&self, ctx: &ExportContext, k: usize, f: &Field) -> Result<Option<Output>, BakeError> {
        Ok(Some(frame(ctx, k, f)))
    }
}
