//! Baking: run a layout headless and write the wind in the formats game engines read.
//!
//! Frames sit at exactly `warmup + k / fps` seconds of simulated time (`timing`). They are
//! streamed to disk as the solver makes them (`frames`), then encoded one at a time, so memory
//! does not grow with the frame count; the disk a bake can take is checked before it starts.
//! Everything is written into a staging folder beside the output folder, which then replaces
//! the output folder as a whole, keeping the user's own files (`folder`). An error or a
//! cancellation removes the staging folder and leaves the output folder as it was.
//!
//! The floors, each importing only those below it: `manifest/` (the format's data: the
//! manifest's types, the format tags, the engines' settings, the profile's factors, the atlas
//! grid); `error`, `field`, `timing`, `options`, `notes`; `folder` (the staging folder and its
//! files) and `frames` (the frame stream); `format` (what an encoder is given and answers)
//! and the encoders (`exr`, `png`, `fga`, `vf`, `raw`, `volume`, `heights`, `engines`);
//! `encoders` (each format's encoder, the names and the disk of a set of formats); `stages`
//! (a bake, step by step); this file.

mod encoders;
mod engines;
mod error;
mod exr;
mod fga;
mod field;
mod folder;
mod format;
mod frames;
mod heights;
mod manifest;
mod notes;
mod options;
mod png;
mod raw;
mod stages;
pub mod timing;
mod vf;
mod volume;

pub use encoders::{disk_need, output_names};
pub use error::{BakeError, disk_message, human_bytes};
pub use fga::FGA_MAX;
pub use field::{Field, check_finite, crossfade};
pub use manifest::{
    ATLAS_MAX_SIDE, Axes, Channel, Encoding, Engines, FileEntry, Format, FramesInfo, IndexAxis,
    LayoutInfo, MANIFEST, MANIFEST_VERSION, Manifest, ProfileInfo, Quantity, Sample, SubImages,
    TerrainInfo, WorldAxis, WorldInfo, layout_hash, schema as manifest_schema,
};
pub use notes::{ADVICE, PEAK_NOTED, field_notes};
pub use options::{
    BakeOptions, DEFAULT_MAX_BYTES, FRAMES_MAX, SECONDS_MAX, SettingsError, atlas_message,
    span_message,
};
pub use stages::Progress;
pub use timing::FrameTiming;

use crate::doc::Layout;
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// Bakes `layout` into the folder `out`, which it replaces as a whole (keeping files the user
/// put there). Returns the manifest written.
pub fn bake(
    layout: &Layout,
    out: &Path,
    opts: &BakeOptions,
    cancel: &AtomicBool,
    progress: Progress<'_>,
) -> Result<Manifest, BakeError> {
    stages::bake_staged(layout, out, opts, cancel, progress)
        .map_err(|e| folder::outside_staging(e, out))
}
