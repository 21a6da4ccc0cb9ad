//! Unity VFX Graph vector fields (`VF_V`): little-endian, sizes as three u16, then f32 x, y, z
//! per cell, X fastest, then Y, then Z. Unity is Y-up and left-handed: X = east, Y = up,
//! Z = north, so a world row `j` (counted southward) becomes Z index `ny − 1 − j` and the
//! world z velocity is negated.

use super::format::{Encoder, frame_names};
use super::{BakeError, ExportContext, Field, FileEntry, Format, Output};

/// Bytes of one file for an `nx × ny` grid.
fn size(nx: usize, ny: usize) -> u64 {
    10 + 12 * (nx * ny) as u64
}

fn frame(ctx: &ExportContext, k: usize, f: &Field) -> Output {
    let (nx, ny) = (f.nx, f.ny);
    let mut bytes = Vec::with_capacity(size(nx, ny) as usize);
    bytes.extend_from_slice(b"VF_V");
    for size in [nx, 1, ny] {
        bytes.extend_from_slice(&(size as u16).to_le_bytes());
    }
    for kz in 0..ny {
        let j = ny - 1 - kz;
        for i in 0..nx {
            let v = f.at(i, j);
            for c in [v[0], 0.0, -v[1]] {
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
            encoding: serde_json::json!({"units": "m/s", "scale": 1.0, "offset": 0.0, "size": [nx, 1, ny]}),
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
