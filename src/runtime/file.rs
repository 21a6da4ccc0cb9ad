//! Reading a bake's files as untrusted input: only plain files inside the bake folder, never
//! more bytes than stated, and nothing that can block a game's thread (a FIFO, a device).

use crate::Error;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// The largest `manifest.json` read (a bake of a thousand frame files lists about 0.5 MB).
pub const MAX_MANIFEST_BYTES: u64 = 16 << 20;

/// A file name from a manifest as a path inside `folder`: one plain name (no folder, no
/// `..`, not absolute, no drive), or an error naming it.
pub(crate) fn inside(folder: &Path, name: &str, field: &str) -> Result<PathBuf, Error> {
    let mut parts = Path::new(name).components();
    let plain = matches!(parts.next(), Some(Component::Normal(_)))
        && parts.next().is_none()
        && !name.contains(['/', '\\', ':', '\0']);
    if !plain {
        return Err(Error::Bake {
            path: folder.join(crate::MANIFEST),
            message: format!(
                "{field}: `{name}` is not a file name in the bake's folder (a bake lists its \
                 own files by name alone)"
            ),
        });
    }
    Ok(folder.join(name))
}

/// Opens `path` for reading without waiting on it (a FIFO opens at once instead of
/// blocking until a writer comes), and only if it is a plain file.
fn open_plain(path: &Path) -> Result<std::fs::File, Error> {
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(rustix::fs::OFlags::NONBLOCK.bits() as i32);
    }
    let file = options.open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if !meta.is_file() {
        return Err(Error::Bake {
            path: path.to_path_buf(),
            message: "not a plain file (a folder, a pipe or a device); a bake holds files".into(),
        });
    }
    Ok(file)
}

/// Reads the plain file at `path` whole, refusing it unless it holds at most `limit` bytes
/// (or exactly `exact`, when given) before any of it is read; the read itself stops one byte
/// past the limit, so a file growing meanwhile cannot make it read more.
pub(crate) fn read(path: &Path, limit: u64, exact: Option<u64>) -> Result<Vec<u8>, Error> {
    let file = open_plain(path)?;
    let bad = |message: String| Error::Bake {
        path: path.to_path_buf(),
        message,
    };
    let size = file
        .metadata()
        .map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?
        .len();
    let limit = exact.map_or(limit, |e| e.min(limit));
    match exact {
        Some(e) if size != e => {
            return Err(bad(format!(
                "{size} bytes where the manifest lists {e}: not the file this bake wrote"
            )));
        }
        _ if size > limit => {
            return Err(bad(format!(
                "{size} bytes, more than the {limit} it may hold"
            )));
        }
        _ => {}
    }
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(size as usize)
        .map_err(|_| bad(format!("not enough memory to read its {size} bytes")))?;
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
    if bytes.len() as u64 > limit || exact.is_some_and(|e| bytes.len() as u64 != e) {
        return Err(bad(format!(
            "changed while it was read ({} bytes, {size} before)",
            bytes.len()
        )));
    }
    Ok(bytes)
}

/// `text` as one bounded line for an error: control characters (a newline, a terminal's
/// escape) written as `\u{..}`, and at most [`MAX_ERROR_CHARS`] characters.
pub(crate) fn one_line(text: &str) -> String {
    let mut out = String::with_capacity(text.len().min(4 * MAX_ERROR_CHARS));
    let mut n = 0;
    for c in text.chars() {
        let escaped = c.is_control().then(|| c.escape_unicode());
        let len = escaped.as_ref().map_or(1, |e| e.len());
        if n + len >= MAX_ERROR_CHARS {
            out.push('…');
            break;
        }
        n += len;
        match escaped {
            Some(e) => out.extend(e),
            None => out.push(c),
        }
    }
    out
}

/// The longest error the runtime gives, in characters.
pub const MAX_ERROR_CHARS: usize = 480;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_stay_in_the_folder() {
        let f = Path::new("bake");
        assert!(inside(f, "wind.f32", "files[0].name").is_ok());
        for name in [
            "../secret",
            "/etc/passwd",
            "a/b.png",
            "a\\b.png",
            "..",
            ".",
            "",
            "C:x",
        ] {
            let e = inside(f, name, "files[0].name").unwrap_err().to_string();
            assert!(e.contains("files[0].name"), "{name}: {e}");
        }
    }

    #[test]
    fn errors_are_one_bounded_line() {
        let s = one_line(&format!("a\nb\u{1b}[31m{}", "x".repeat(5000)));
        assert!(!s.chars().any(char::is_control), "{s}");
        assert!(
            s.chars().count() <= MAX_ERROR_CHARS,
            "{}",
            s.chars().count()
        );
        assert!(s.starts_with("a\\u{a}b\\u{1b}[31m"));
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_or_a_device_is_refused_at_once() {
        let dir = std::env::temp_dir().join(format!("windloom-fifo-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("manifest.json");
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        // Would block for ever without a writer, were it opened as a file is.
        let e = read(&fifo, MAX_MANIFEST_BYTES, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("not a plain file"), "{e}");
        let e = read(Path::new("/dev/zero"), MAX_MANIFEST_BYTES, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("not a plain file"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
