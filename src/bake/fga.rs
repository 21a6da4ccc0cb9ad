//! Unreal FGA vector fields. Line 1: `SizeX,SizeY,SizeZ,`; line 2: the minimum corner
//! `MinX,MinY,MinZ,`; line 3: the maximum corner `MaxX,MaxY,MaxZ,`; then one `x,y,z,` vector
//! per line, X fastest, the last without its comma (the file then ends where Unreal's
//! importer stops reading, and it imports without a warning). Unreal's own parser splits on commas and does not mind the lines, but
//! line-based readers (Blender's FGA add-on and others) take line 2 as the minimum and line 3
//! as the maximum, as Houdini, VectorayGen and Blender write them. At most 128 cells per axis:
//! larger grids are area-averaged down.

use super::error::BakeError;
use super::field::Field;
use super::format::{Encoder, Extent, frame_names};
use super::format::{ExportContext, Output};
use super::manifest::{Axes, Channel, Encoding, IndexAxis, Sample, WorldAxis};
use super::manifest::{FileEntry, Format};

/// Unreal's importer rejects larger axes.
pub const FGA_MAX: usize = 128;
use std::fmt::Write;

/// Slab thickness of the 2D field as a volume, in Unreal units (cm).
pub(crate) const FGA_HEIGHT_CM: f32 = 200.0;
const CM: f32 = 100.0;

/// The FGA grid for an `nx × ny` bake: the same, or scaled down to at most 128 per axis.
pub(crate) fn dims(nx: usize, ny: usize) -> (usize, usize) {
    let s = (FGA_MAX as f64 / nx.max(ny) as f64).min(1.0);
    (
        ((nx as f64 * s).round() as usize).clamp(1, FGA_MAX),
        ((ny as f64 * s).round() as usize).clamp(1, FGA_MAX),
    )
}

/// The manifest note when the grid had to be resampled.
pub(crate) fn note(nx: usize, ny: usize) -> Option<String> {
    let (fx, fy) = dims(nx, ny);
    ((fx, fy) != (nx, ny)).then(|| {
        format!("fga: resampled {nx}x{ny} to {fx}x{fy} by area averaging (Unreal accepts at most {FGA_MAX} per axis)")
    })
}

/// Most bytes one vector line takes: three floats written without exponent (at most 48
/// characters each, for the smallest subnormal) and their commas, plus the newline.
const MAX_LINE: u64 = 3 * 49 + 1;

fn frame(ctx: &ExportContext, k: usize, frame: &Field) -> Output {
    let (nx, ny) = (frame.nx, frame.ny);
    let (fx, fy) = dims(nx, ny);
    let resampled = (fx, fy) != (nx, ny);
    let f = frame.resample(fx, fy);
    let min = [ctx.min[0] * CM, ctx.min[1] * CM, 0.0];
    let max = [ctx.max[0] * CM, ctx.max[1] * CM, FGA_HEIGHT_CM];
    let mut text = String::with_capacity(fx * fy * 24 + 128);
    let _ = writeln!(text, "{fx},{fy},1,");
    let _ = writeln!(text, "{},{},{},", min[0], min[1], min[2]);
    let _ = writeln!(text, "{},{},{},", max[0], max[1], max[2]);
    // Every line ends with a comma but the last: Unreal's importer reads the values between
    // commas and warns "File contains additional information" when anything (a newline)
    // follows the last comma it needs.
    for (k, v) in f.data.iter().enumerate() {
        let end = if k + 1 == f.data.len() { "" } else { "," };
        let _ = writeln!(text, "{},{},0{end}", v[0] * CM, v[1] * CM);
    }
    let name = ctx.name("wind", k, "fga");
    Output {
        entry: FileEntry {
            name: name.clone(),
            format: Format::Fga,
            frame: ctx.frame_index(k),
            grid: [fx, fy],
            resampled_from: resampled.then_some([nx, ny]),
            encoding: Encoding {
                sample: Sample::Text,
                units: "m/s",
                channels: vec![
                    Channel::velocity("X", WorldAxis::PlusX, 1.0 / CM, 0.0),
                    Channel::velocity("Y", WorldAxis::PlusZ, 1.0 / CM, 0.0),
                    Channel::velocity("Z", WorldAxis::PlusY, 1.0 / CM, 0.0),
                ],
                green_flipped: None,
                storage: "FGA text, cm and cm/s: line 1 SizeX,SizeY,SizeZ; line 2 MinX,MinY,MinZ; line 3 MaxX,MaxY,MaxZ; then one X,Y,Z per line, X fastest, then Y, then Z (SizeZ = 1)"
                    .to_string(),
            },
            axes: Axes {
                index: vec![
                    IndexAxis {
                        name: "X",
                        world: WorldAxis::PlusX,
                        cells: fx,
                        range: [ctx.min[0], ctx.max[0]],
                    },
                    IndexAxis {
                        name: "Y",
                        world: WorldAxis::PlusZ,
                        cells: fy,
                        range: [ctx.min[1], ctx.max[1]],
                    },
                    IndexAxis {
                        name: "Z",
                        world: WorldAxis::PlusY,
                        cells: 1,
                        range: [0.0, FGA_HEIGHT_CM / CM],
                    },
                ],
                sub_images: None,
                engine_frame: Some("Unreal: X east, Y south, Z up (left-handed, centimetres)"),
            },
            bytes: 0,
            crc32: 0,
        },
        name,
        bytes: text.into_bytes(),
    }
}

/// The FGA format.
pub(crate) struct Fga;

impl Encoder for Fga {
    fn names(&self, count: usize) -> Vec<String> {
        frame_names("wind", count, "fga")
    }

    /// One line a cell at most, and the three header lines.
    fn max_bytes(&self, e: &Extent) -> u64 {
        let (nx, ny, frames) = (e.nx, e.ny, e.frames);
        let (fx, fy) = dims(nx, ny);
        frames as u64 * ((fx * fy) as u64 * MAX_LINE + 512)
    }

    fn frame(&self, ctx: &ExportContext, k: usize, f: &Field) -> Result<Vec<Output>, BakeError> {
        Ok(vec![frame(ctx, k, f)])
    }
}
