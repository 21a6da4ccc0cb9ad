//! Raw little-endian f32: all frames in one file, frame-major, then row `j` (+z), then column
//! `i` (+x), two channels `[x, z]` in m/s.

use super::{ExportContext, FileEntry, Format, Output};

pub(crate) fn write(ctx: &ExportContext<'_>) -> Vec<Output> {
    let (nx, ny) = (ctx.frames[0].nx, ctx.frames[0].ny);
    let bytes: Vec<u8> = ctx
        .frames
        .iter()
        .flat_map(|f| f.data.iter())
        .flat_map(|v| [v[0], v[1]])
        .flat_map(f32::to_le_bytes)
        .collect();
    let name = "wind.f32".to_string();
    vec![Output {
        entry: FileEntry {
            name: name.clone(),
            format: Format::Raw,
            frame: None,
            grid: [nx, ny],
            resampled_from: None,
            encoding: serde_json::json!({
                "type": "f32", "endian": "little", "channels": ["x", "z"], "units": "m/s",
                "layout": "[frame][row j][column i][channel]", "frames": ctx.frames.len(),
                "scale": 1.0, "offset": 0.0,
            }),
            axes: serde_json::json!({"i": "+x (east)", "j": "+z (south)"}),
            bytes: 0,
        },
        name,
        bytes,
    }]
}
