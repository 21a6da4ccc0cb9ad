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

/// The largest map backdrop windloom reads: pixels along a side, pixels in all, bytes on disk.
pub const BACKDROP_MAX_SIDE: u32 = 16_384;
pub const BACKDROP_MAX_PIXELS: u64 = 64 << 20;
pub const BACKDROP_MAX_BYTES: u64 = 256 << 20;

/// Why a layout's map backdrop could not be shown. Never a reason to refuse the layout: the
/// editor, `render` and `validate` report it as a warning and go on without the image.
#[derive(Debug, thiserror::Error)]
pub enum BackdropError {
    #[error("map image {}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("map image {}: {size} bytes, more than the {} MiB windloom reads", path.display(), BACKDROP_MAX_BYTES >> 20)]
    TooManyBytes { path: PathBuf, size: u64 },
    #[error("map image {}: {w}×{h} pixels, more than windloom reads ({BACKDROP_MAX_SIDE} a side, {} Mpixels)", path.display(), BACKDROP_MAX_PIXELS >> 20)]
    TooLarge { path: PathBuf, w: u32, h: u32 },
    #[error("map image {}: {message}", path.display())]
    Decode { path: PathBuf, message: String },
}

/// The folder a layout's relative paths (its map image) start from: the layout file's
/// folder ([`parent_dir`]), or the working folder (`.`) for a layout not yet saved.
pub fn layout_base(layout_path: Option<&Path>) -> PathBuf {
    layout_path.map_or(Path::new("."), parent_dir).to_path_buf()
}

/// `path` as the layout stores it: relative to `base` when inside it (with `/` separators, so
/// the layout moves between systems with its folder), else as it is.
pub fn relative_to(path: &Path, base: &Path) -> String {
    let abs = |p: &Path| {
        std::path::absolute(p)
            .map(|a| a.canonicalize().unwrap_or(a))
            .unwrap_or_else(|_| p.to_path_buf())
    };
    match abs(path).strip_prefix(abs(base)) {
        Ok(rel) => rel
            .components()
            .map(|c| c.as_os_str().to_string_lossy())
            .collect::<Vec<_>>()
            .join("/"),
        Err(_) => path.display().to_string(),
    }
}

/// The map backdrop's image (`map.image`, relative to the layout's folder `base`), as RGBA8:
/// its size checked on disk and in its header before any pixel is decoded.
pub fn load_backdrop(
    base: &Path,
    map: &doc::MapBackdrop,
) -> Result<image::RgbaImage, BackdropError> {
    let path = base.join(&map.image);
    let io = |source| BackdropError::Io {
        path: path.clone(),
        source,
    };
    let size = std::fs::metadata(&path).map_err(io)?.len();
    if size > BACKDROP_MAX_BYTES {
        return Err(BackdropError::TooManyBytes { path, size });
    }
    let decode = |e: image::ImageError| BackdropError::Decode {
        path: path.clone(),
        message: e.to_string(),
    };
    let reader = image::ImageReader::open(&path)
        .map_err(io)?
        .with_guessed_format()
        .map_err(io)?;
    let (w, h) = reader.into_dimensions().map_err(decode)?;
    if w > BACKDROP_MAX_SIDE
        || h > BACKDROP_MAX_SIDE
        || u64::from(w) * u64::from(h) > BACKDROP_MAX_PIXELS
    {
        return Err(BackdropError::TooLarge { path, w, h });
    }
    let mut reader = image::ImageReader::open(&path)
        .map_err(io)?
        .with_guessed_format()
        .map_err(io)?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(BACKDROP_MAX_SIDE);
    limits.max_image_height = Some(BACKDROP_MAX_SIDE);
    limits.max_alloc = Some(BACKDROP_MAX_PIXELS * 8);
    reader.limits(limits);
    Ok(reader.decode().map_err(decode)?.to_rgba8())
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

/// What the editor opens for `path`: the layout there (`false`), or, where no file is there
/// yet but its folder is, a new layout as File → New makes it, named after the file
/// (`true`), which Save then writes to `path`. Any other failure is the error [`load`] gives.
pub fn load_or_new(path: &Path) -> Result<(Layout, bool), LoadError> {
    match load(path) {
        Err(LoadError::Io { source, .. })
            if source.kind() == std::io::ErrorKind::NotFound && parent_dir(path).is_dir() =>
        {
            let name = path
                .file_stem()
                .map_or("Untitled".into(), |s| s.to_string_lossy());
            Ok((Layout::untitled(&name), true))
        }
        other => other.map(|l| (l, false)),
    }
}

/// Saves a layout atomically (see [`write_atomic`]).
pub fn save(path: &Path, layout: &Layout) -> std::io::Result<()> {
    write_atomic(path, doc::to_json(layout).as_bytes())
}

/// Symbolic links followed before a path is given up on (Linux's own limit).
const MAX_LINKS: usize = 40;

/// The file a write to `path` must replace: `path` itself, or, when `path` is a symbolic link
/// (to a file that may not exist yet), the file it finally points to. Replacing the link with
/// a plain file would cut it from the file it shared.
pub fn resolve_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let target = std::fs::read_link(&p)?;
                p = match p.parent() {
                    Some(dir) => dir.join(target),
                    None => target,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(std::io::Error::other(format!(
        "{}: more than {MAX_LINKS} levels of symbolic links",
        path.display()
    )))
}

/// The folder a file lives in (`.` for a bare file name).
pub fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Flushes a folder's entries to disk, so a rename inside it survives a power cut.
pub fn sync_dir(dir: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    std::fs::File::open(dir)?.sync_all()?;
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}

/// Writes `bytes` to `path` so that readers see either the old file or the whole new one:
/// the data goes to a temporary file in the same folder, is flushed to disk, and is then
/// renamed over `path`, and the folder is flushed so the new name is durable. On any failure
/// `path` is untouched and the temporary file removed.
///
/// The new file keeps the old one's permissions (and, where allowed, its owner and group); a
/// new file gets the user's usual mode (0666 less the umask). A symbolic link is written
/// through: its target is replaced and the link stays.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let path = resolve_links(path)?;
    let dir = parent_dir(&path);
    let old = std::fs::metadata(&path).ok().filter(|m| m.is_file());
    let mut builder = tempfile::Builder::new();
    builder.prefix(".windloom-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // open(2) takes the umask off this, as it does for any new file.
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    // tempfile names its own temporary file in the error; the user wants the folder.
    let mut tmp = builder
        .tempfile_in(dir)
        .map_err(|e| folder_error(dir, e.kind()))?;
    if let Some(old) = &old {
        keep_owner_and_mode(tmp.as_file(), old)?;
    }
    tmp.write_all(bytes)?;
    tmp.as_file().sync_all()?;
    tmp.persist(&path).map_err(|e| e.error)?;
    sync_dir(dir)
}

/// Why a file cannot be created in `dir`, naming the folder.
fn folder_error(dir: &Path, kind: std::io::ErrorKind) -> std::io::Error {
    use std::io::ErrorKind as K;
    let why = match kind {
        K::NotFound => "does not exist".to_string(),
        K::PermissionDenied => "is not writable (permission denied)".to_string(),
        K::NotADirectory => "is not a folder".to_string(),
        other => format!("cannot hold a new file ({other})"),
    };
    std::io::Error::new(kind, format!("the folder {} {why}", dir.display()))
}

/// Gives `file` the permissions of `old`, and its owner and group where this user may.
fn keep_owner_and_mode(file: &std::fs::File, old: &std::fs::Metadata) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let mine = file.metadata()?;
        if (mine.uid(), mine.gid()) != (old.uid(), old.gid()) {
            // Only root may give a file away; a member of the group may still keep the group.
            let _ = std::os::unix::fs::fchown(file, Some(old.uid()), Some(old.gid()))
                .or_else(|_| std::os::unix::fs::fchown(file, None, Some(old.gid())));
        }
    }
    file.set_permissions(old.permissions())
}
