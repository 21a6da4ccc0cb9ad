//! Raw little-endian f32: all frames in one file, frame-major, then row `j` (+z), then column
//! `i` (+x), two channels `[x, z]` in m/s. The file is the bake's frame stream itself
//! (`frames.rs`); this names it and describes it.

use super::error::BakeError;
use super::field::Field;
use super::format::{Encoder, Extent};
use super::format::{ExportContext, Output};
use super::manifest::{Axes, Channel, Encoding, IndexAxis, Sample, WorldAxis};
use super::manifest::{FileEntry, Format};

pub(crate) const NAME: &str = "wind.f32";

pub(crate) fn entry(ctx: &ExportContext) -> FileEntry {
    FileEntry {
        name: NAME.to_string(),
        format: Format::Raw,
        frame: None,
        grid: [ctx.nx, ctx.ny],
        resampled_from: None,
        encoding: Encoding {
            sample: Sample::F32,
            units: "m/s",
            channels: vec![
                Channel::velocity("x", WorldAxis::PlusX, 1.0, 0.0),
                Channel::velocity("z", WorldAxis::PlusZ, 1.0, 0.0),
            ],
            green_flipped: None,
            storage: format!(
                "little-endian f32, [frame][row j][column i][channel x, z], {} frames",
                ctx.count
            ),
        },
        axes: Axes {
            index: vec![
                IndexAxis {
                    name: "i",
                    world: WorldAxis::PlusX,
                    cells: ctx.nx,
                    range: [ctx.min[0], ctx.max[0]],
                },
                IndexAxis {
                    name: "j",
                    world: WorldAxis::PlusZ,
                    cells: ctx.ny,
                    range: [ctx.min[1], ctx.max[1]],
                },
            ],
            sub_images: None,
            engine_frame: None,
        },
        bytes: 0,
        crc32: 0,
    }
}

/// The raw format: its one file is the frame stream, counted by the bake itself.
pub(crate) struct Raw;

impl Encoder for Raw {
    fn names(&self, _count: usize) -> Vec<String> {
        vec![NAME.to_string()]
    }

    fn max_bytes(&self, _: &Extent) -> u64 {
        0
    }

    fn frame(&self, _: &ExportContext, _: usize, _: &Field) -> Result<Vec<Output>, BakeError> {
        Ok(Vec::new())
    }
}
