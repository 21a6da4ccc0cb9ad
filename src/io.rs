//! The file system edge: loading layouts with diagnostics and writing files atomically.

use crate::doc::{self, Diagnostics, Layout};
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// Every problem of the file, one per line, each prefixed with the file name.
    #[error("{}", .diagnostics.0.iter().map(|d| format!("{}:{d}", path.display())).collect::<Vec<_>>().join("\n"))]
    Invalid {
        path: PathBuf,
        diagnostics: Diagnostics,
    },
}

/// Reads and validates a layout file.
pub fn load(path: &Path) -> Result<Layout, LoadError> {
    let text = std::fs::read_to_string(path).map_err(|source| LoadError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    doc::parse(&text).map_err(|diagnostics| LoadError::Invalid {
        path: path.to_path_buf(),
        diagnostics,
    })
}

/// Saves a layout atomically (see [`write_atomic`]).
pub fn save(path: &Path, layout: &Layout) -> std::io::Result<()> {
    write_atomic(path, doc::to_json(layout).as_bytes())
}

/// Writes `bytes` to `path` so that readers see either the old file or the whole new one:
/// the data goes to a temporary file in the same folder, is flushed to disk, and is then
/// renamed over `path`. On any failure `path` is untouched and the temporary file removed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut tmp = tempfile::Builder::new()
        .prefix(".windloom-")
        .suffix(".tmp")
        .tempfile_in(dir)?;
    tmp.write_all(bytes)?;
    tmp.as_file().sync_all()?;
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}
