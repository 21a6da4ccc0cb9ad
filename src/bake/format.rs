//! The formats a bake writes. [`Format`] is what a user picks; each format's own file answers
//! for it through [`Encoder`]: the names of its files, an upper bound of their size, and the
//! encoding of a frame. `bake` finds each format's file (`encoder`), loops over the chosen
//! formats and asks them.

use super::error::BakeError;
use super::field::Field;
use super::manifest::{self, Axes, FileEntry, IndexAxis, SubImages, WorldAxis};
use crate::doc;

/// How big a bake is: `frames` frames of `nx × ny` cells, `layers` layers in a volume, and
/// `half`: 16-bit floats where the format has them.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Extent {
    pub nx: usize,
    pub ny: usize,
    pub layers: usize,
    pub frames: usize,
    pub half: bool,
}

/// What a format's file answers for it.
pub(crate) trait Encoder: Sync {
    /// The files it writes in a bake of `count` frames.
    fn names(&self, count: usize) -> Vec<String>;

    /// An upper bound of the bytes it writes for a bake of `size`.
    fn max_bytes(&self, size: &Extent) -> u64;

    /// The files of frame `k`, for a format with files per frame; none for one whose single
    /// file holds every frame (written beside the frame loop: `raw`, `atlas`).
    fn frame(&self, ctx: &ExportContext, k: usize, f: &Field) -> Result<Vec<Output>, BakeError>;
}

/// The file name of frame `k` of `count` with extension `ext`: `STEM.EXT` for one frame,
/// `STEM_0000.EXT`… for a sequence.
pub(crate) fn frame_name(stem: &str, k: usize, count: usize, ext: &str) -> String {
    if count == 1 {
        format!("{stem}.{ext}")
    } else {
        format!("{stem}_{k:04}.{ext}")
    }
}

/// The names of a format with one file per frame.
pub(crate) fn frame_names(stem: &str, count: usize, ext: &str) -> Vec<String> {
    (0..count)
        .map(|k| frame_name(stem, k, count, ext))
        .collect()
}

/// What an exporter hands back: file name, bytes, and its manifest entry (minus size).
pub(crate) struct Output {
    pub name: String,
    pub bytes: Vec<u8>,
    pub entry: FileEntry,
}

/// Everything an exporter needs.
pub(crate) struct ExportContext {
    pub nx: usize,
    pub ny: usize,
    /// Frames in the bake.
    pub count: usize,
    pub max_speed: f32,
    pub min: [f32; 2],
    pub max: [f32; 2],
    pub half: bool,
    pub fps: f32,
    /// Flowmaps and the atlas store green as the world −z wind (up the image).
    pub flip_green: bool,
    /// The vertical profile the volume is baked with.
    pub profile: doc::VerticalProfile,
}

impl ExportContext {
    pub(super) fn name(&self, stem: &str, k: usize, ext: &str) -> String {
        frame_name(stem, k, self.count, ext)
    }

    pub(super) fn frame_index(&self, k: usize) -> Option<usize> {
        (self.count > 1).then_some(k)
    }

    /// The speed that maps to the ends of the 8/16-bit flowmap range.
    pub(super) fn flow_scale(&self) -> f32 {
        self.max_speed.max(1e-6)
    }
}

/// The image axes of a flowmap, EXR or atlas frame: columns along +x, rows down the image
/// along +z (or the flipped image's).
pub(crate) fn image_axes(ctx: &ExportContext, nx: usize, ny: usize) -> Vec<IndexAxis> {
    vec![
        IndexAxis {
            name: "pixel_x",
            world: WorldAxis::PlusX,
            cells: nx,
            range: [ctx.min[0], ctx.max[0]],
        },
        IndexAxis {
            name: "pixel_y",
            world: WorldAxis::PlusZ,
            cells: ny,
            range: [ctx.min[1], ctx.max[1]],
        },
    ]
}

/// The axes of an atlas of the bake's frames (`png::atlas_grid`): a frame's image axes, and
/// where each frame's sub-image sits.
pub(crate) fn atlas_axes(ctx: &ExportContext) -> Axes {
    let (columns, rows) = manifest::atlas_grid(ctx.count);
    Axes {
        index: image_axes(ctx, ctx.nx, ctx.ny),
        sub_images: Some(SubImages {
            columns,
            rows,
            count: ctx.count,
            fps: ctx.fps,
            order: "frame k at column k % columns, row k / columns (row 0 at the top)",
        }),
        engine_frame: None,
    }
}
