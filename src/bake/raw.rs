//! Raw little-endian f32: all frames in one file, frame-major, then row `j` (+z), then column
//! `i` (+x), two channels `[x, z]` in m/s. The file is the bake's frame stream itself
//! (`frames.rs`); this names it and describes it.

use super::format::Encoder;
use super::{BakeError, ExportContext, Field, FileEntry, Format, Output};

pub(crate) const NAME: &str = "wind.f32";

pub(crate) fn entry(ctx: &ExportContext) -> FileEntry {
    FileEntry {
        name: NAME.to_string(),
        format: Format::Raw,
        frame: None,
        grid: [ctx.nx, ctx.ny],
        resampled_from: None,
        encoding: serde_json::json!({
            "type": "f32", "endian": "little", "channels": ["x", "z"], "units": "m/s",
            "layout": "[frame][row j][column i][channel]", "frames": ctx.count,
            "scale": 1.0, "offset": 0.0,
        }),
        axes: serde_json::json!({"i": "+x (east)", "j": "+z (south)"}),
        bytes: 0,
    }
}

/// The raw format: its one file is the frame stream, counted by the bake itself.
pub(crate) struct Raw;

impl Encoder for Raw {
    fn names(&self, _count: usize) -> Vec<String> {
        vec![NAME.to_string()]
    }

    fn max_bytes(&self, _nx: usize, _ny: usize, _frames: usize, _half: bool) -> u64 {
        0
    }

    fn frame(&self, _: &ExportContext, _: usize, _: &Field) -> Result<Option<Output>, BakeError> {
        Ok(None)
    }
}
