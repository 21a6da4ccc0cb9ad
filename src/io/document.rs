//! The document the editor owns: the layout, its undo history, its file (the path, what was
//! last read or written there, the watch on it) and its recovery copy. No egui: the editor's
//! panels ask it and tell it; what they show of it is theirs. It lives at the file system's
//! edge beside the watch (`disk.rs`) and the recovery copies (`recovery.rs`) it keeps.
//!
//! The layout is read through `Deref` (`app.doc.trees`) and changed only by an [`Edit`]
//! (one undo step, or one gesture) or by replacing it whole (New, Open, Restore), so every
//! change is undoable, validated and noticed.

use super::{disk, recovery};
use crate::doc::{self, Edit, EditError, History, Layout};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Seconds between two autosaves of unsaved work.
pub const AUTOSAVE_SECONDS: f64 = 20.0;

/// The editor's document.
pub struct Document {
    layout: Layout,
    history: History,
    path: Option<PathBuf>,
    /// The layout's JSON as the file last held it (empty: no file, or one to overwrite).
    saved_json: String,
    /// The grey images (masks, the density map, the heightmap) as their files last held them
    /// ([`painted_images`]): a painted one is unsaved work, written beside the layout on save.
    saved_images: Vec<(String, Arc<doc::MaskImage>)>,
    dirty: bool,
    /// Changed since the editor last looked ([`Self::take_changed`]).
    changed: bool,
    /// The document's file as the editor last read or wrote it.
    disk: Option<disk::Watch>,
    /// A change to that file made by someone else, not yet answered (Reload / Keep mine).
    pub disk_change: Option<disk::Change>,
    last_disk_check: f64,
    /// Wakes the editor when the file's stamp changes, and the file it was last told to poll.
    poller: disk::Poller,
    polled: Option<PathBuf>,
    recovery: Option<recovery::Recovery>,
    /// Why the last autosave failed (shown in the status bar until one works).
    pub recovery_error: Option<String>,
    /// Recovery copies of editors that are gone, still to offer.
    recover_queue: Vec<recovery::Found>,
    last_autosave: f64,
}

impl std::ops::Deref for Document {
    type Target = Layout;

    fn deref(&self) -> &Layout {
        &self.layout
    }
}

impl Document {
    /// `layout`, read from `path` if any (so unchanged: not dirty), its file watched by
    /// `poller`.
    pub fn new(layout: Layout, path: Option<PathBuf>, poller: disk::Poller) -> Self {
        Self {
            saved_json: doc::to_json(&layout),
            saved_images: grey_images(&layout),
            disk: path.as_deref().map(disk::Watch::read),
            layout,
            history: History::new(),
            path,
            dirty: false,
            changed: false,
            disk_change: None,
            last_disk_check: 0.0,
            poller,
            polled: None,
            recovery: None,
            recovery_error: None,
            recover_queue: Vec::new(),
            last_autosave: 0.0,
        }
    }

    /// The layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The file the document was read from or last saved to.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// Where Save writes, without saving (a test, or the Export dialog's guess of a folder).
    pub fn set_path(&mut self, path: Option<PathBuf>) {
        self.path = path;
    }

    /// Whether the layout differs from its file (as of the last [`Self::take_changed`]).
    pub fn is_dirty(&self) -> bool {
        self.dirty
    }

    /// The undo history, to read (what Undo and Redo would do).
    pub fn history(&self) -> &History {
        &self.history
    }

    /// Applies an edit as one undo step.
    pub fn apply(&mut self, e: Edit) -> Result<(), EditError> {
        self.history.apply(&mut self.layout, e)?;
        self.changed = true;
        Ok(())
    }

    /// Applies an edit that continues the gesture `key` (a drag, a slider): one undo step
    /// in all.
    pub fn apply_merged(&mut self, e: Edit, key: u64) -> Result<(), EditError> {
        self.history.apply_merged(&mut self.layout, e, key)?;
        self.changed = true;
        Ok(())
    }

    /// Ends the gesture in progress: the next edit is a step of its own.
    pub fn end_gesture(&mut self) {
        self.history.end_gesture();
    }

    /// Undoes the last step; whether there was one.
    pub fn undo(&mut self) -> bool {
        let done = self.history.undo(&mut self.layout);
        self.changed |= done;
        done
    }

    /// Redoes the last undone step; whether there was one.
    pub fn redo(&mut self) -> bool {
        let done = self.history.redo(&mut self.layout);
        self.changed |= done;
        done
    }

    /// Replaces the whole layout (New, Open, Restore), from `path` if any; `saved`: as that
    /// file holds it (else it counts as unsaved). The history starts anew.
    pub fn replace(&mut self, layout: Layout, path: Option<PathBuf>, saved: bool) {
        self.saved_images = grey_images(&layout);
        self.saved_json = if saved {
            doc::to_json(&layout)
        } else {
            String::new()
        };
        self.layout = layout;
        self.disk = path.as_deref().map(disk::Watch::read);
        self.disk_change = None;
        self.path = path;
        self.history.clear();
        self.changed = true;
    }

    /// Whether the layout changed since the last call (an edit, an undo, a replacement),
    /// updating [`Self::is_dirty`].
    pub fn take_changed(&mut self) -> bool {
        if !std::mem::take(&mut self.changed) {
            return false;
        }
        self.dirty = doc::to_json(&self.layout) != self.saved_json
            || !painted_images(&self.layout, &self.saved_images).is_empty();
        true
    }

    /// Writes the layout to `path` atomically; it is then the document's file, saved.
    pub fn write_to(&mut self, path: &Path) -> std::io::Result<()> {
        // The painted images first, each replaced atomically beside the layout: a layout
        // never names an image older than its strokes.
        crate::io::check_portable(path, &self.layout)?;
        let base = crate::io::layout_base(Some(path));
        for (name, image) in painted_images(&self.layout, &self.saved_images) {
            let file = crate::io::layout_file(&base, &name);
            let bytes = encode_grey(&file, &image)
                .map_err(|e| std::io::Error::other(format!("{}: {e}", file.display())))?;
            crate::io::write_atomic(&file, &bytes)
                .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", file.display())))?;
        }
        self.saved_images = grey_images(&self.layout);
        let json = doc::to_json(&self.layout);
        crate::io::write_atomic(path, json.as_bytes())?;
        self.disk = Some(disk::Watch::written(path, json.as_bytes()));
        self.disk_change = None;
        self.saved_json = json;
        self.path = Some(path.to_path_buf());
        self.dirty = false;
        self.remove_recovery();
        Ok(())
    }

    /// Lets the unsaved changes go (the user said Discard): nothing asks about them again.
    pub fn discard_changes(&mut self) {
        self.dirty = false;
    }

    /// Looks whether the document's file changed on disk; a change is kept in
    /// [`Self::disk_change`] until answered.
    pub fn check_disk(&mut self) {
        if let Some(change) = self.disk.as_mut().and_then(disk::Watch::check) {
            log::info!("{} changed on disk: {change:?}", self.path_label());
            self.disk_change = Some(change);
        }
    }

    /// Watches the file on the frames there are (at most every [`disk::CHECK_SECONDS`]), and
    /// by the poller's thread, which wakes an idle editor only when the file changed.
    pub fn watch_disk(&mut self, now: f64) {
        let watched = self.disk.as_ref().map(|w| w.path().to_path_buf());
        if watched != self.polled {
            self.poller.watch(watched.as_deref());
            self.polled = watched;
        }
        if self.disk.is_some()
            && (self.poller.poked() || now - self.last_disk_check >= disk::CHECK_SECONDS)
        {
            self.last_disk_check = now;
            self.check_disk();
        }
    }

    /// Answers a change on disk by keeping the editor's layout: it counts as unsaved, and the
    /// next Save overwrites the file.
    pub fn keep_mine(&mut self) {
        self.disk_change = None;
        self.saved_json.clear();
        self.changed = true;
    }

    /// The document's file name, or "untitled".
    pub fn path_label(&self) -> String {
        self.path
            .as_ref()
            .and_then(|p| p.file_name())
            .map_or_else(|| "untitled".into(), |f| f.to_string_lossy().into_owned())
    }

    /// The folder unsaved work is autosaved into, one copy per document (`None`: no
    /// autosave).
    pub fn set_recovery_dir(&mut self, dir: Option<PathBuf>) {
        self.remove_recovery();
        self.recovery = dir.map(recovery::Recovery::new);
    }

    /// Recovery copies found from editors that are gone, offered one by one
    /// ([`Self::next_found`]).
    pub fn offer_found(&mut self, mut found: Vec<recovery::Found>) {
        found.reverse();
        self.recover_queue = found;
    }

    /// The next recovery copy to offer, if any.
    pub fn next_found(&mut self) -> Option<recovery::Found> {
        self.recover_queue.pop()
    }

    /// Where this document's recovery copy goes.
    pub fn recovery_path(&self) -> Option<PathBuf> {
        self.recovery
            .as_ref()
            .map(|r| r.path_for(self.path.as_deref()))
    }

    /// Writes the recovery copy now (atomically). Returns where it went, or why it could not
    /// be written (kept in [`Self::recovery_error`] until a write works).
    pub fn write_recovery(&mut self) -> Result<PathBuf, String> {
        let Some(r) = &mut self.recovery else {
            return Err("no recovery folder".into());
        };
        match r.write(&self.layout, self.path.as_deref()) {
            Ok(written) => {
                self.recovery_error = None;
                Ok(written)
            }
            Err(e) => {
                self.recovery_error = Some(e.clone());
                Err(e)
            }
        }
    }

    /// Removes this document's recovery copy (saved, or discarded on quitting).
    pub fn remove_recovery(&mut self) {
        if let Some(r) = &mut self.recovery {
            r.remove();
        }
    }

    /// Writes the recovery copy of unsaved work when [`AUTOSAVE_SECONDS`] have passed since
    /// the last; a failure newly met, to say.
    pub fn autosave(&mut self, now: f64) -> Option<String> {
        if !self.dirty || now - self.last_autosave < AUTOSAVE_SECONDS {
            return None;
        }
        self.last_autosave = now;
        let failing = self.recovery_error.is_some();
        match self.write_recovery() {
            Err(e) if !failing => Some(e),
            _ => None,
        }
    }

    /// When the next autosave is due, while there is unsaved work.
    pub fn next_autosave(&self) -> Option<f64> {
        self.dirty.then_some(self.last_autosave + AUTOSAVE_SECONDS)
    }
}

/// The layout's read grey images by the file each names: its mask obstacles', the terrain's
/// heightmap and the grass's density map.
fn grey_images(layout: &Layout) -> Vec<(String, Arc<doc::MaskImage>)> {
    doc::portable::files(layout)
        .into_iter()
        .filter_map(|(_, path, grey)| match grey {
            Some((doc::MaskPixels::Loaded(i), _)) => Some((path.to_owned(), i.clone())),
            _ => None,
        })
        .collect()
}

/// The images of `layout` painted since `saved` was taken: those whose pixels are not the
/// ones their file held (a new path read from disk is not painted).
pub fn painted_images(
    layout: &Layout,
    saved: &[(String, Arc<doc::MaskImage>)],
) -> Vec<(String, Arc<doc::MaskImage>)> {
    grey_images(layout)
        .into_iter()
        .filter(|(name, image)| {
            saved
                .iter()
                .find(|(n, _)| n == name)
                .is_some_and(|(_, s)| !Arc::ptr_eq(s, image))
        })
        .collect()
}

/// A grey image's bytes for `file`: an EXR (grey in R, G and B, half floats) where its name
/// ends in `.exr`, else a 16-bit grey PNG.
fn encode_grey(file: &Path, image: &doc::MaskImage) -> Result<Vec<u8>, String> {
    let (w, h) = (image.width as usize, image.height as usize);
    let exr = file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if exr {
        use exr::prelude::*;
        let l = |p: Vec2<usize>| f32::from(image.luminance[p.y() * w + p.x()]) / 65535.0;
        let img = Image::from_channels((w, h), SpecificChannels::rgb(|p| (l(p), l(p), l(p))));
        let mut out = std::io::Cursor::new(Vec::new());
        img.write()
            .to_buffered(&mut out)
            .map_err(|e| e.to_string())?;
        return Ok(out.into_inner());
    }
    let buf = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_raw(
        image.width,
        image.height,
        image.luminance.clone(),
    )
    .ok_or("the image's pixels do not fill it")?;
    let mut out = Vec::new();
    buf.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
        .map_err(|e| e.to_string())?;
    Ok(out)
}
