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
    stamp: Stamp,
    /// Hash of the content the editor knows (`None`: no file).
    content: Option<u64>,
}

fn hash(bytes: &[u8]) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    bytes.hash(&mut h);
    h.finish()
}

/// A file's modification time and length (`None`: no file).
type Stamp = Option<(Option<SystemTime>, u64)>;

fn stamp(path: &Path) -> Stamp {
    let m = std::fs::metadata(path).ok()?;
    Some((m.modified().ok(), m.len()))
}

/// The hash of the file's bytes, read as a layout is (a FIFO or a device put in its place
/// is never waited on or read without end): `None` where it cannot be.
fn read(path: &Path) -> Option<u64> {
    crate::io::read_regular(path, crate::doc::LAYOUT_MAX_BYTES, "a layout")
        .ok()
        .map(|b| hash(&b))
}

impl Watch {
    /// Watches `path` as it is now (the editor just read it, or is about to).
    pub fn read(path: &Path) -> Self {
        Self {
            path: path.to_path_buf(),
            stamp: stamp(path),
            content: read(path),
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

    /// The file watched.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Looks at the file: a change not seen before, if any. A rewrite with the same content
    /// (a `touch`, a save of identical text) is not a change. Each change is reported once.
    pub fn check(&mut self) -> Option<Change> {
        let now = stamp(&self.path);
        if now == self.stamp {
            return None;
        }
        self.stamp = now;
        let content = read(&self.path);
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

/// Looks at the watched file's stamp every [`CHECK_SECONDS`] on a thread of its own and calls
/// `wake` when it changes, so an idle editor draws no frames to notice a change on disk (the
/// editor then [`Watch::check`]s it).
pub struct Poller {
    path: std::sync::Arc<std::sync::Mutex<Option<PathBuf>>>,
    poked: std::sync::Arc<std::sync::atomic::AtomicBool>,
    stop: Option<std::sync::mpsc::Sender<()>>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Poller {
    /// Starts polling nothing; [`Poller::watch`] names the file.
    pub fn start(wake: impl Fn() + Send + 'static) -> Self {
        use std::sync::atomic::Ordering;
        let path = std::sync::Arc::new(std::sync::Mutex::new(None::<PathBuf>));
        let poked = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let (stop, stopped) = std::sync::mpsc::channel::<()>();
        let thread = {
            let (path, poked) = (path.clone(), poked.clone());
            std::thread::Builder::new()
                .name("windloom disk watch".into())
                .spawn(move || {
                    let mut seen: Option<(PathBuf, Stamp)> = None;
                    let every = std::time::Duration::from_secs_f64(CHECK_SECONDS);
                    while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) =
                        stopped.recv_timeout(every)
                    {
                        let Some(p) = path.lock().ok().and_then(|p| p.clone()) else {
                            seen = None;
                            continue;
                        };
                        let now = stamp(&p);
                        match &seen {
                            Some((q, s)) if *q == p && *s != now => {
                                poked.store(true, Ordering::Release);
                                wake();
                            }
                            _ => {}
                        }
                        seen = Some((p, now));
                    }
                })
                .ok()
        };
        Self {
            path,
            poked,
            stop: Some(stop),
            thread,
        }
    }

    /// Polls `path` from now on (`None`: nothing).
    pub fn watch(&self, path: Option<&Path>) {
        if let Ok(mut p) = self.path.lock() {
            *p = path.map(Path::to_path_buf);
        }
    }

    /// Whether the file's stamp changed since the last call.
    pub fn poked(&self) -> bool {
        self.poked.swap(false, std::sync::atomic::Ordering::AcqRel)
    }
}

impl Drop for Poller {
    fn drop(&mut self) {
        drop(self.stop.take());
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
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

    #[test]
    fn the_poller_wakes_the_editor_when_the_file_changes_and_not_before() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("level.json");
        std::fs::write(&f, b"one").unwrap();
        let (tx, rx) = std::sync::mpsc::channel();
        let poller = Poller::start(move || {
            let _ = tx.send(());
        });
        poller.watch(Some(&f));
        let wait = std::time::Duration::from_secs_f64(CHECK_SECONDS * 2.5);
        assert!(rx.recv_timeout(wait).is_err(), "no change, no wake");
        assert!(!poller.poked());
        std::fs::write(&f, b"two, longer").unwrap();
        assert!(rx.recv_timeout(wait * 2).is_ok(), "woken by the change");
        assert!(poller.poked());
        assert!(!poller.poked(), "told once");
    }
}
