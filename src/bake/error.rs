//! Why a bake fails ([`BakeError`]), and how a disk refusal is said.

use super::options::SettingsError;
use std::path::PathBuf;

/// Why a bake is refused for its disk: it needs up to `need` bytes, more than `limit`;
/// `raise` says what else to change, in the caller's words (empty: nothing).
pub fn disk_message(need: u64, limit: &str, raise: &str) -> String {
    format!(
        "this bake needs up to {} of disk, more than {limit}; bake fewer frames, formats or cells{raise}",
        human_bytes(need)
    )
}

/// Bytes as a person reads them: `512 B`, `3.2 MiB`, `1.50 GiB`.
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut v = bytes as f64;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < UNITS.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{bytes} B")
    } else {
        format!("{v:.2} {}", UNITS[u])
    }
}

#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    #[error("invalid bake settings: {0}")]
    Settings(#[from] SettingsError),
    #[error("the layout is invalid: {0}")]
    Layout(String),
    #[error("cannot use output folder {}: {source}", path.display())]
    Output {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("writing {}: {source}", path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("encoding {name}: {message}")]
    Encode { name: String, message: String },
    #[error(
        "{}",
        disk_message(*need, limit, if *budget { ", or raise the disk budget" } else { "" })
    )]
    Disk {
        need: u64,
        /// What it exceeds, e.g. `the 16.00 GiB budget`.
        limit: String,
        /// Whether it exceeds the budget asked for ([`BakeOptions::max_bytes`](super::BakeOptions::max_bytes)), rather than
        /// the free space.
        budget: bool,
    },
    #[error("cancelled; no files were written")]
    Cancelled,
    #[error(
        "the wind went non-finite in frame {frame} (cell {cell}); nothing was written — the layout or the solver settings make the simulation unstable"
    )]
    NonFinite { frame: usize, cell: usize },
}
