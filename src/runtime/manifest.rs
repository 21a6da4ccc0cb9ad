//! The parts of a bake's `manifest.json` the runtime reads: the format's own crate's reader
//! types (`src/bake_format/read.rs`), beside the types windloom writes it with.

pub(crate) use windloom_bake_format::read::*;
pub(crate) use windloom_bake_format::{FORMAT, MANIFEST_VERSION as VERSION};
