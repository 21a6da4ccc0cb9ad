//! The document the editor owns: the layout, its undo history, its file (the path, what was
//! last read or written there, the watch on it) and its recovery copy. No egui: the editor's
//! panels ask it and tell it; what they show of it is theirs. It lives at the file system's
//! edge beside the watch (`disk.rs`) and the recovery copies (`recovery.rs`) it keeps.
//!
//! The layout is read through `Deref` (`app.doc.trees`) and changed only by an [`Edit`]
//! (one undo step, or one gesture) or by replacing it whole (New, Open, Restore), so every
//! change is undoable, validated and noticed.

use super::images::{self, ImageFiles};
use super::{disk, recovery};
use crate::doc::{self, Edit, EditError, History, Layout};
use std::path::{Path, PathBuf};

/// Seconds between two autosaves of unsaved work.
pub const AUTOSAVE_SECONDS: f64 = 20.0;

/// The editor's document.
pub struct Document {
    layout: Layout,
    history: History,
    path: Option<PathBuf>,
    /// The layout's JSON as the file last held it (empty: no file, or one to overwrite).
    saved_json: String,
    /// The grey images (masks, the density map, the heightmap) against their files: one not
    /// as its file holds it (painted, newly made, pasted, recovered) is unsaved work, written
    /// on save and into every recovery copy.
    images: ImageFiles,
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
    /// Changed since the last recovery copy was written (a copy already holding the work is
    /// not written again).
    unsaved_since_copy: bool,
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
        let mut images = ImageFiles::default();
        images.note_layout(&layout, &crate::io::layout_base(path.as_deref()));
        Self {
            saved_json: doc::to_json(&layout),
            images,
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
            unsaved_since_copy: false,
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

    /// The folder the layout's relative paths start from: its file's, or the working folder
    /// for a layout not saved yet.
    pub fn base(&self) -> PathBuf {
        crate::io::layout_base(self.path.as_deref())
    }

    /// Reads the grey image `name` (relative to [`Self::base`]; `what` it is, for messages)
    /// for the layout to hold: the pixels, as its file holds them, or why not. Every image
    /// the editor attaches is read here, so that only painted or new pixels count as unsaved.
    pub fn read_grey(&mut self, name: &str, what: &'static str) -> doc::MaskPixels {
        let base = self.base();
        let pixels = crate::io::grey_pixels(&base, name, what);
        if let doc::MaskPixels::Loaded(image) = &pixels {
            self.images
                .note(images::file_key(&base, name), image.clone());
        }
        pixels
    }

    /// Reads the grey images of `layout` (one to paste in) that are not loaded yet, beside
    /// this document's file; images already loaded (painted in this editor) stay unsaved
    /// work.
    pub fn read_images(&mut self, layout: &mut Layout) {
        let base = self.base();
        let had = images::greys(layout, &base);
        crate::io::load_masks(layout, &base);
        for g in images::greys(layout, &base) {
            if !had
                .iter()
                .any(|h| std::sync::Arc::ptr_eq(&h.image, &g.image))
            {
                self.images.note(g.file, g.image);
            }
        }
    }

    /// The grey images that are unsaved work: their files do not hold these pixels.
    pub fn unsaved_images(&self) -> Vec<images::Grey> {
        self.images.unsaved(&self.layout, &self.base())
    }

    /// The edit a save to `path` needs first (`None`: none): the images keep naming their
    /// files from `path`'s folder, and a new image takes a free name where a file this editor
    /// never read is in the way ([`ImageFiles::plan_save`]).
    pub fn save_plan(&self, path: &Path) -> Option<Edit> {
        let to = crate::io::layout_base(Some(path));
        let pairs = self.images.plan_save(&self.layout, &self.base(), &to);
        (!pairs.is_empty()).then_some(Edit::Repath(pairs))
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
        self.images.clear();
        self.images
            .note_layout(&layout, &crate::io::layout_base(path.as_deref()));
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
        self.unsaved_since_copy = true;
        self.dirty =
            doc::to_json(&self.layout) != self.saved_json || !self.unsaved_images().is_empty();
        true
    }

    /// The images `names` of a restored copy are the copy's, not their files': unsaved work
    /// (their files stay the document's to write).
    pub fn mark_recovered(&mut self, names: &[String]) {
        let base = self.base();
        self.images.unsave(&self.layout, &base, names);
        self.changed = true;
    }

    /// Writes the layout to `path` atomically, its unsaved images first (each replaced
    /// atomically where the layout names it from `path`'s folder: a layout never names an
    /// image older than its strokes); it is then the document's file, saved. Nothing is
    /// written when a name is not portable, when two items name one file with different
    /// pixels, or when an image would replace a file this editor never read.
    pub fn write_to(&mut self, path: &Path) -> std::io::Result<()> {
        crate::io::check_portable(path, &self.layout)?;
        let base = crate::io::layout_base(Some(path));
        let mut images = std::mem::take(&mut self.images);
        let written = images.write(&self.layout, &base);
        self.images = images;
        written?;
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
        let base = crate::io::layout_base(self.path.as_deref());
        let unsaved = self.images.unsaved(&self.layout, &base);
        match r.write(&self.layout, self.path.as_deref(), &base, &unsaved) {
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

    /// Writes the recovery copy of unsaved work changed since the last copy, when
    /// [`AUTOSAVE_SECONDS`] have passed since that one, or at once when the editor comes to
    /// `rest` (so a resting editor needs no frame to autosave); a failure newly met, to say.
    pub fn autosave(&mut self, now: f64, rest: bool) -> Option<String> {
        let due = now - self.last_autosave >= AUTOSAVE_SECONDS || rest;
        if !self.dirty || !self.unsaved_since_copy || !due {
            return None;
        }
        self.last_autosave = now;
        let failing = self.recovery_error.is_some();
        match self.write_recovery() {
            Ok(_) => {
                self.unsaved_since_copy = false;
                None
            }
            // Tried again in AUTOSAVE_SECONDS (or at the next rest).
            Err(e) if !failing => Some(e),
            Err(_) => None,
        }
    }
}
