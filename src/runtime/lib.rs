//! windloom's runtime: a bake played back in a game. It opens a bake folder by its
//! `manifest.json`, reads the wind from the most precise files the bake holds (raw, EXR,
//! VF, the DDS volume, PNG flowmaps), decoding each by the manifest's own numbers
//! (`value = stored × scale + offset`, index axes as data), and answers
//! [`Bake::wind_at`]`(position, t)` in m/s, in the axes of the engine asking ([`Axes`]).
//! [`LiveBake`] follows the folder as it is baked again.
//!
//! No editor, GPU or UI code: serde for the manifest, `png`, `exr` (both cargo features)
//! and `half` for the files, `libm` so the answers are the same bits on every platform.
//! The C interface ([`c_api`], `windloom.h`) gives every engine the same calls.
//!
//! ```no_run
//! use windloom_runtime::{Bake, Options};
//! let wind = Bake::open("bake", &Options::default())?;
//! let w = wind.wind_at([12.0, 1.5, 30.0], 2.25); // m/s: [east, up, south]
//! # Ok::<(), windloom_runtime::Error>(())
//! ```
//!
//! windloom's `docs/RUNTIME.md` says what it reads, its axes, units and costs.

pub mod c_api;
mod file;
mod live;
mod load;
mod manifest;
mod read;
mod wind;

pub use file::{MAX_ERROR_CHARS, MAX_MANIFEST_BYTES};
pub use live::LiveBake;
pub use load::{MAX_FRAMES, MAX_GRID_SIDE, MAX_WIND_BYTES};
pub use wind::{Axes, Bake, Options, Outside};

use std::path::{Path, PathBuf};

/// The file every bake folder holds, listing the rest.
pub use windloom_bake_format::MANIFEST;

/// Why a bake could not be read: each names the file, in one line of at most
/// [`MAX_ERROR_CHARS`] characters (what came from the bake's files, control characters
/// included, is escaped).
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("{}", file::one_line(&format!("{}: {source}", path.display())))]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}", file::one_line(&format!("{}: line {line}, column {column}: {message}", path.display())))]
    Manifest {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
    /// A file that does not hold what its manifest says, or a bake this runtime cannot read.
    #[error("{}", file::one_line(&format!("{}: {message}", path.display())))]
    Bake { path: PathBuf, message: String },
    #[error("{}", file::one_line(&format!("{}: a new bake landed each of the {attempts} times it was read; try again when the baking stops", path.display())))]
    Changing { path: PathBuf, attempts: usize },
}

impl Bake {
    /// Reads the bake in `folder` whole (its manifest, the files it lists, its manifest
    /// again: a bake landing meanwhile is read again, so what is kept is one bake).
    pub fn open(folder: impl AsRef<Path>, options: &Options) -> Result<Bake, Error> {
        load::open(folder.as_ref(), options, load::ATTEMPTS).map(|(bake, _)| bake)
    }
}
