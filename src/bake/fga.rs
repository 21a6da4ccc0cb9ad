//! Unreal FGA vector fields: `SizeX,SizeY,SizeZ,` then the bounds, then one `x,y,z,` vector per
//! line, X fastest. At most 128 cells per axis: larger grids are area-averaged down.

use super::{ExportContext, FGA_MAX, FileEntry, Format, Output};
use std::fmt::Write;

/// Slab thickness of the 2D field as a volume, in Unreal units (cm).
pub const FGA_HEIGHT_CM: f32 = 200.0;

pub(crate) fn write(ctx: &ExportContext<'_>) -> (Vec<Output>, Option<String>) {
    let (nx, ny) = (ctx.frames[0].nx, ctx.frames[0].ny);
    let s = (FGA_MAX as f64 / nx.max(ny) as f64).min(1.0);
    let (fx, fy) = (
        ((nx as f64 * s).round() as usize).clamp(1, FGA_MAX),
        ((ny as f64 * s).round() as usize).clamp(1, FGA_MAX),
    );
    let resampled = (fx, fy) != (nx, ny);
    let note = resampled.then(|| {
        format!("fga: resampled {nx}x{ny} to {fx}x{fy} by area averaging (Unreal accepts at most {FGA_MAX} per axis)")
    });
    let cm = 100.0;
    let mut out = Vec::new();
    for (k, frame) in ctx.frames.iter().enumerate() {
        let f = frame.resample(fx, fy);
        let mut text = String::with_capacity(fx * fy * 24 + 128);
        let _ = writeln!(text, "{fx},{fy},1,");
        let _ = writeln!(
            text,
            "{},{},{},{},{},{},",
            ctx.min[0] * cm,
            ctx.min[1] * cm,
            0.0,
            ctx.max[0] * cm,
            ctx.max[1] * cm,
            FGA_HEIGHT_CM
        );
        for v in &f.data {
            let _ = writeln!(text, "{},{},0,", v[0] * cm, v[1] * cm);
        }
        let name = ctx.name("wind", k, "fga");
        out.push(Output {
            entry: FileEntry {
                name: name.clone(),
                format: Format::Fga,
                frame: ctx.frame_index(k),
                grid: [fx, fy],
                resampled_from: resampled.then_some([nx, ny]),
                encoding: serde_json::json!({"units": "cm/s", "scale": 100.0, "offset": 0.0,
                    "values": "x,y,z per cell, X fastest, then Y, then Z (SizeZ = 1)"}),
                axes: serde_json::json!({
                    "unreal": "Z-up, left-handed, centimetres",
                    "X": "world +x (east)", "Y": "world +z (south)", "Z": "world +y (up)",
                    "bounds_cm": [ctx.min[0] * cm, ctx.min[1] * cm, 0.0, ctx.max[0] * cm, ctx.max[1] * cm, FGA_HEIGHT_CM],
                }),
                bytes: 0,
            },
            name,
            bytes: text.into_bytes(),
        });
    }
    (out, note)
}
