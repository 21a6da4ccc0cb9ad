//! Noticing when the open layout file changes on disk behind the editor's back: a second
//! editor saving it, a script rewriting it, version control checking out another revision.

use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// Seconds between two looks at the file (a `stat`; the file is read only when that changed).
pub const CHECK_SECONDS: f64 = 1.0;

/// What happened to the file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Change {
    /// Someone else wrote different content.
    Modified,
    /// The file is gone (deleted or moved).
    Deleted,
}

/// The editor's idea of its file: what it last read or wrote there.
#[derive(Debug, Clone)]
pub struct Watch {
    path: PathBuf,
    /// Modification time and length when last looked at (`None`: no file).
    stamp: Option<(Option<SystemTime>, u64)>,
    /// Hash of the content the editor knows (`None`: no file).
    content: Option<u64>,
}

fn hash(bytes: &[u8]) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    bytes.hash(&mut h);
    h.finish()
}

fn stamp(path: &Path) -> Option<(Option<SystemTime>, u64)> {
    let m = std::fs::metadata(path).ok()?;
    Some((m.modified().ok(), m.len()))
}

impl Watch {
    /// Watches `path` as it is now (the editor just read it, or is about to).
    pub fn read(path: &Path) -> Self {
        Self {
            path: path.to_path_buf(),
            stamp: stamp(path),
            content: std::fs::read(path).ok().map(|b| hash(&b)),
        }
    }

    /// Watches `path` after the editor wrote `bytes` there.
    pub fn written(path: &Path, bytes: &[u8]) -> Self {
        Self {
            path: path.to_path_buf(),
            stamp: stamp(path),
            content: Some(hash(bytes)),
        }
    }

    /// Looks at the file: a change not seen before, if any. A rewrite with the same content
    /// (a `touch`, a save of identical text) is not a change. Each change is reported once.
    pub fn check(&mut self) -> Option<Change> {
        let now = stamp(&self.path);
        if now == self.stamp {
            return None;
        }
        self.stamp = now;
        let content = std::fs::read(&self.path).ok().map(|b| hash(&b));
        if content == self.content {
            return None;
        }
        self.content = content;
        Some(match content {
            Some(_) => Change::Modified,
            None => Change::Deleted,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rewrite_is_a_change_a_touch_is_not_and_each_is_told_once() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("level.json");
        std::fs::write(&f, b"one").unwrap();
        let mut w = Watch::read(&f);
        assert_eq!(w.check(), None);
        // The same bytes again (a new modification time): not a change.
        std::thread::sleep(std::time::Duration::from_millis(20));
        std::fs::write(&f, b"one").unwrap();
        assert_eq!(w.check(), None);
        std::fs::write(&f, b"two!").unwrap();
        assert_eq!(w.check(), Some(Change::Modified));
        assert_eq!(w.check(), None, "told once");
        std::fs::remove_file(&f).unwrap();
        assert_eq!(w.check(), Some(Change::Deleted));
        assert_eq!(w.check(), None);
        let mut mine = Watch::written(&f, b"mine");
        std::fs::write(&f, b"mine").unwrap();
        assert_eq!(mine.check(), None, "what the editor wrote is no change");
    }
}
