//! Autosaved copies of unsaved work, one per document: `<key>.json` (the layout) beside
//! `<key>.owner` (which process wrote it, which file it belongs to, the folder its paths start
//! from, and which of its images are unsaved) and `<key>.images/` (those images, 16-bit PNGs
//! named by their pixels' hash) in the recovery folder. Two editors never share a copy — the
//! key is the document's path, or a session id for a new document — and a copy is offered back
//! only when the editor that wrote it is gone, with the path of the file it was editing, so
//! the next Save goes there. Restoring reads the layout's other images from the level's own
//! folder, as the layout names them. No egui here.

use super::images::Grey;
use crate::doc::{Layout, MaskImage};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Weak};

/// Who wrote a recovery copy (`<key>.owner`), and what else the copy needs to come back.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
struct Owner {
    pid: u32,
    path: Option<PathBuf>,
    /// The folder the layout's relative paths started from (the file's, or the working
    /// folder of a new layout).
    #[serde(default)]
    base: Option<PathBuf>,
    /// Each unsaved image: the path the layout names it by, and its file in the copy's
    /// images folder.
    #[serde(default)]
    images: Vec<(String, String)>,
}

/// A recovery copy left by an editor that is no longer running.
#[derive(Debug, Clone, PartialEq)]
pub struct Found {
    /// The autosaved layout.
    pub layout: PathBuf,
    /// The file that editor was editing (`None`: a new, never-saved document).
    pub origin: Option<PathBuf>,
    /// The folder its relative paths started from (`None`: a copy of an earlier version:
    /// the origin's folder).
    pub base: Option<PathBuf>,
    /// The unsaved images it holds: the path the layout names each by, and the copy's file.
    pub images: Vec<(String, PathBuf)>,
}

/// A recovery copy read back: the layout with every image loaded (the unsaved ones from the
/// copy, the rest from the level's folder), and which images are the copy's.
#[derive(Debug)]
pub struct Restored {
    pub layout: Layout,
    pub recovered: Vec<String>,
}

/// The folder of a copy's images, beside its layout.
fn images_dir(layout: &Path) -> PathBuf {
    layout.with_extension("images")
}

impl Found {
    /// The copy at `layout` with nothing else known of it (an earlier version's, or one to
    /// remove).
    pub fn at(layout: PathBuf) -> Self {
        Self {
            layout,
            origin: None,
            base: None,
            images: Vec::new(),
        }
    }

    /// What the "Restore unsaved work?" dialog says of this copy to an editor that has
    /// `open` open: whose copy it is, and, when that is not the open file, that Restore
    /// replaces it (an editor started on one layout can be offered another's copy).
    pub fn offer(&self, open: Option<&Path>) -> String {
        let what = match &self.origin {
            Some(p) => format!("{}", p.display()),
            None => "a new layout that was never saved".into(),
        };
        let mut text = format!(
            "windloom did not close cleanly last time. A recovery copy of {what} was found."
        );
        // The origin is kept canonical; the open file's path is as it was typed.
        let same = |o: &Path| {
            let o = o.canonicalize().unwrap_or_else(|_| o.to_path_buf());
            self.origin.as_deref() == Some(o.as_path())
        };
        if let Some(open) = open.filter(|&o| !same(o)) {
            text += &format!(" Restore opens it in place of {}.", open.display());
        }
        text + " Discard deletes the copy."
    }

    /// Deletes the copy (after it was restored or discarded).
    pub fn remove(&self) {
        let _ = std::fs::remove_file(&self.layout);
        let _ = std::fs::remove_file(self.layout.with_extension("owner"));
        let _ = std::fs::remove_dir_all(images_dir(&self.layout));
    }

    /// Reads the copy back as the editor that wrote it had it: its layout, its unsaved images
    /// from the copy, and every other image from the level's folder (the origin's, or the
    /// folder a new layout's paths started from), as the layout names them. A new layout's
    /// relative paths are made absolute when that folder is not the working folder now.
    pub fn restore(&self) -> Result<Restored, String> {
        let mut layout = super::load_unread(&self.layout).map_err(|e| e.to_string())?;
        let base = match (&self.origin, &self.base) {
            (Some(origin), _) => super::layout_base(Some(origin)),
            (None, Some(base)) => base.clone(),
            (None, None) => PathBuf::from("."),
        };
        let mut recovered = Vec::new();
        for (name, file) in &self.images {
            let dir = file.parent().unwrap_or(Path::new("."));
            let leaf = file.file_name().unwrap_or_default().to_string_lossy();
            let image = super::load_mask(dir, &leaf, "recovered image")
                .map_err(|e| format!("the recovery copy's image for {name}: {e}"))?;
            let image = Arc::new(image);
            crate::doc::portable::for_each_file_mut(&mut layout, |path, grey| {
                if path == name
                    && let Some((pixels, _)) = grey
                {
                    *pixels = crate::doc::MaskPixels::Loaded(image.clone());
                }
            });
            recovered.push(name.clone());
        }
        if self.origin.is_none() {
            let here = super::images::file_key(Path::new("."), ".");
            if super::images::file_key(&base, ".") != here {
                crate::doc::portable::for_each_file_mut(&mut layout, |path, _| {
                    if !Path::new(path.as_str()).is_absolute() && !recovered.contains(path) {
                        *path = super::images::file_key(&base, path).display().to_string();
                    }
                });
            }
        }
        super::load_masks(&mut layout, &base);
        Ok(Restored { layout, recovered })
    }
}

/// This editor's recovery copies.
#[derive(Debug, Clone)]
pub struct Recovery {
    dir: PathBuf,
    /// Names this editor's never-saved documents.
    session: String,
    /// The copy last written (removed when the document's path changes or it is saved).
    written: Option<PathBuf>,
    /// The images last written into the copy: each by its pixels (while the editor holds
    /// them) and its file, so an image unchanged since is not encoded again.
    images: Vec<(Weak<MaskImage>, PathBuf)>,
}

/// How old a temporary file of an atomic write must be before it counts as left by a killed
/// editor (a write takes milliseconds; another running editor's is never this old).
pub const STALE_TEMPORARY: std::time::Duration = std::time::Duration::from_secs(600);

/// Removes the temporary files (`.windloom-*.tmp`) that atomic writes into `dir` left when
/// their editor was killed mid-write, once older than `older_than`; returns how many went.
/// Nothing reads them (a copy is only ever a `.json`), but each crash would leave one more.
pub fn sweep_temporaries(dir: &Path, older_than: std::time::Duration) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let now = std::time::SystemTime::now();
    entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            let name = p.file_name().unwrap_or_default().to_string_lossy();
            name.starts_with(".windloom-") && name.ends_with(".tmp")
        })
        .filter(|p| {
            std::fs::symlink_metadata(p)
                .and_then(|m| m.modified())
                .is_ok_and(|t| now.duration_since(t).is_ok_and(|age| age >= older_than))
        })
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count()
}

/// A recovery image's file name: the hash of its size and pixels (SHA-256, 16 hex digits).
fn image_hash(image: &MaskImage) -> String {
    use sha2::Digest;
    let mut h = sha2::Sha256::new();
    h.update(image.width.to_le_bytes());
    h.update(image.height.to_le_bytes());
    h.update(bytemuck::cast_slice::<u16, u8>(&image.luminance));
    h.finalize()[..8]
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// A short stable hash of a path (FNV-1a), for file names.
fn fnv(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

impl Recovery {
    pub fn new(dir: PathBuf) -> Self {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        Self {
            dir,
            session: format!("untitled-{}-{nanos:x}", std::process::id()),
            written: None,
            images: Vec::new(),
        }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The copy's path for a document at `doc_path`.
    pub fn path_for(&self, doc_path: Option<&Path>) -> PathBuf {
        let key = match doc_path {
            Some(p) => {
                let p = p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
                let stem: String = p
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default()
                    .chars()
                    .map(|c| {
                        if c.is_alphanumeric() || c == '-' {
                            c
                        } else {
                            '_'
                        }
                    })
                    .take(40)
                    .collect();
                format!("{stem}-{:016x}", fnv(&p.to_string_lossy()))
            }
            None => self.session.clone(),
        };
        self.dir.join(format!("{key}.json"))
    }

    /// Writes `doc` (being edited at `doc_path`, its relative paths from `base`) and its
    /// unsaved images as this document's copy, each file atomically: the images first (named
    /// by their pixels, so a file once written never changes), then the owner that names
    /// them, then the layout; images no longer named go last. A copy for the document's
    /// previous path is removed.
    pub fn write(
        &mut self,
        doc: &Layout,
        doc_path: Option<&Path>,
        base: &Path,
        unsaved: &[Grey],
    ) -> Result<PathBuf, String> {
        let path = self.path_for(doc_path);
        std::fs::create_dir_all(&self.dir)
            .map_err(|e| format!("could not create {}: {e}", self.dir.display()))?;
        let dir = images_dir(&path);
        let mut images = Vec::new();
        let mut kept = Vec::new();
        for g in unsaved {
            let file =
                match self.images.iter().find(|(w, f)| {
                    w.upgrade().is_some_and(|i| Arc::ptr_eq(&i, &g.image)) && f.exists()
                }) {
                    Some((_, f)) => f.clone(),
                    None => {
                        let file = dir.join(format!("{}.png", image_hash(&g.image)));
                        if !file.exists() {
                            std::fs::create_dir_all(&dir)
                                .map_err(|e| format!("could not create {}: {e}", dir.display()))?;
                            let bytes = super::images::encode_grey(&file, &g.image, true)
                                .map_err(|e| format!("{}: {e}", file.display()))?;
                            crate::io::write_atomic(&file, &bytes)
                                .map_err(|e| format!("{}: {e}", file.display()))?;
                        }
                        file
                    }
                };
            kept.push((Arc::downgrade(&g.image), file.clone()));
            let leaf = file
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned();
            images.push((g.name.clone(), leaf));
        }
        // The owner (which file the copy is of) first: an editor killed between the two
        // writes then leaves the old copy with its owner, never a new copy without one
        // (restored as untitled, its way back to the level's file lost).
        let owner = Owner {
            pid: std::process::id(),
            path: doc_path.map(|p| p.canonicalize().unwrap_or_else(|_| p.to_path_buf())),
            base: Some(super::images::file_key(base, ".")),
            images,
        };
        let json = serde_json::to_vec(&owner).map_err(|e| e.to_string())?;
        let owner_path = path.with_extension("owner");
        crate::io::write_atomic(&owner_path, &json)
            .map_err(|e| format!("{}: {e}", owner_path.display()))?;
        crate::io::save(&path, doc).map_err(|e| format!("{}: {e}", path.display()))?;
        // Images the copy no longer names.
        if let Ok(entries) = std::fs::read_dir(&dir) {
            for e in entries.flatten() {
                let p = e.path();
                let named = kept.iter().any(|(_, f)| *f == p);
                let temporary = p
                    .file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with(".windloom-"));
                if !named && !temporary {
                    let _ = std::fs::remove_file(&p);
                }
            }
        }
        if kept.is_empty() {
            let _ = std::fs::remove_dir(&dir);
        }
        self.images = kept;
        if let Some(old) = self.written.replace(path.clone())
            && old != path
        {
            Found::at(old).remove();
        }
        Ok(path)
    }

    /// Removes this editor's copy (the work was saved, or discarded on purpose).
    pub fn remove(&mut self) {
        if let Some(p) = self.written.take() {
            Found::at(p).remove();
        }
        self.images.clear();
    }

    /// The copies in `dir` whose editors are gone, newest first. A copy without a readable
    /// owner is offered too (nothing says its editor is running).
    pub fn found(dir: &Path) -> Vec<Found> {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return Vec::new();
        };
        let mut found: Vec<(std::time::SystemTime, Found)> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .filter_map(|layout| {
                let owner: Option<Owner> = std::fs::read(layout.with_extension("owner"))
                    .ok()
                    .and_then(|b| serde_json::from_slice(&b).ok());
                if owner.as_ref().is_some_and(|o| {
                    // Where the system cannot tell, the owner is taken as gone: a
                    // recovery offered twice beats one never offered.
                    o.pid != std::process::id()
                        && crate::platform::process::alive(o.pid).unwrap_or(false)
                }) {
                    return None;
                }
                let modified = std::fs::metadata(&layout)
                    .and_then(|m| m.modified())
                    .unwrap_or(std::time::UNIX_EPOCH);
                let dir = images_dir(&layout);
                let (origin, base, images) = match owner {
                    Some(o) => (
                        o.path,
                        o.base,
                        (o.images.into_iter())
                            .map(|(name, file)| (name, dir.join(file)))
                            .collect(),
                    ),
                    None => (None, None, Vec::new()),
                };
                Some((
                    modified,
                    Found {
                        layout,
                        origin,
                        base,
                        images,
                    },
                ))
            })
            .collect();
        found.sort_by_key(|f| std::cmp::Reverse(f.0));
        found.into_iter().map(|(_, f)| f).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dialog names the file whose copy it offers, and says when restoring it would
    /// replace the layout the editor was started on.
    #[test]
    fn the_offer_says_whose_copy_and_what_restore_replaces() {
        let found = |origin: Option<&str>| Found {
            origin: origin.map(PathBuf::from),
            ..Found::at(PathBuf::from("/r/copy.json"))
        };
        let (level, other) = (Path::new("/levels/a.json"), Path::new("/levels/b.json"));
        let same = found(Some("/levels/a.json")).offer(Some(level));
        assert!(same.contains("copy of /levels/a.json"), "{same}");
        assert!(!same.contains("in place of"), "{same}");
        let elsewhere = found(Some("/levels/a.json")).offer(Some(other));
        assert!(
            elsewhere.contains("copy of /levels/a.json")
                && elsewhere.contains("in place of /levels/b.json"),
            "{elsewhere}"
        );
        let unsaved = found(None).offer(Some(level));
        assert!(
            unsaved.contains("never saved") && unsaved.contains("in place of /levels/a.json"),
            "{unsaved}"
        );
        // The same file by another spelling of its path is the same file.
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let real = dir.path().join("a.json");
        std::fs::write(&real, b"{}").unwrap();
        let canonical = real.canonicalize().unwrap();
        let copy = Found {
            origin: Some(canonical.clone()),
            ..Found::at(PathBuf::from("/r/copy.json"))
        };
        let spelled = copy.offer(Some(&dir.path().join("sub/../a.json")));
        assert!(!spelled.contains("in place of"), "{spelled}");
        let fresh = found(Some("/levels/a.json")).offer(None);
        assert!(!fresh.contains("in place of"), "{fresh}");
        assert!(fresh.contains("Discard deletes the copy"), "{fresh}");
    }

    /// A killed write's temporary file goes once it is old; a fresh one (another editor
    /// writing now), copies and the user's own files stay.
    #[test]
    fn stale_temporaries_are_swept_and_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let file = |name: &str, age_s: u64| {
            let p = dir.path().join(name);
            let f = std::fs::File::create(&p).unwrap();
            let t = std::time::SystemTime::now() - std::time::Duration::from_secs(age_s);
            f.set_modified(t).unwrap();
            p
        };
        let stale = file(".windloom-AbC123.tmp", 3600);
        let fresh = file(".windloom-XyZ789.tmp", 5);
        let copy = file("level-0123456789abcdef.json", 3600);
        let other = file(".other-editor.tmp", 3600);
        assert_eq!(sweep_temporaries(dir.path(), STALE_TEMPORARY), 1);
        assert!(!stale.exists());
        assert!(fresh.exists() && copy.exists() && other.exists());
        assert_eq!(
            sweep_temporaries(&dir.path().join("missing"), STALE_TEMPORARY),
            0
        );
    }
}
