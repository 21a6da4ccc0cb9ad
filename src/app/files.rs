//! The document's file: open, save (atomically, never over another program's change unasked),
//! the typed-path fallback, discard prompts, autosave and recovery copies, and noticing the
//! file change on disk. Methods of [`EditorApp`]; the file-system pieces without egui are
//! `recovery.rs` and `disk.rs`.

use super::*;

impl EditorApp {
    /// Replaces the whole document (New, Open, Restore).
    pub(super) fn replace_document(&mut self, doc: Layout, path: Option<PathBuf>, saved: bool) {
        self.saved_json = if saved {
            doc::to_json(&doc)
        } else {
            String::new()
        };
        self.doc = doc;
        self.disk = path.as_deref().map(disk::Watch::read);
        self.disk_change = None;
        self.path = path;
        self.history.clear();
        self.selection.clear();
        self.camera = None;
        self.backdrop = None;
        self.polygon.clear();
        self.gesture = None;
        self.doc_changed = true;
        self.live.reset();
    }

    /// Loads a layout file; on error shows every problem and keeps the current document.
    pub fn open_path(&mut self, path: &Path) {
        match crate::io::load(path) {
            Ok(doc) => {
                self.replace_document(doc, Some(path.to_path_buf()), true);
                self.remember_recent(path);
            }
            Err(e) => {
                self.dialog = Some(Dialog::Error {
                    title: format!("Could not open {}", path.display()),
                    text: e.to_string(),
                });
            }
        }
    }

    pub(super) fn remember_recent(&mut self, path: &Path) {
        let p = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        self.settings.recent.retain(|r| r != &p);
        self.settings.recent.insert(0, p);
        self.settings.recent.truncate(10);
    }

    /// Saves to `path` atomically; returns whether it worked (errors go to a dialog). Refuses
    /// to overwrite the document's own file when someone else changed it since the editor read
    /// it, until the user answers the question the editor then shows (Reload or Keep mine).
    pub fn save_to(&mut self, ctx: &egui::Context, path: &Path) -> bool {
        if self.path.as_deref() == Some(path) {
            self.check_disk();
            if self.disk_change == Some(disk::Change::Modified) {
                self.say(
                    ctx,
                    format!(
                        "Not saved: {} changed on disk — Reload it, or Keep mine to overwrite it",
                        path.display()
                    ),
                );
                return false;
            }
        }
        // A layout never named takes its file's name on its first save elsewhere (one undo
        // step): "Untitled" in a file called valley.json helps nobody.
        let unnamed = self.doc.name.trim().is_empty() || self.doc.name == UNTITLED;
        if unnamed
            && self.path.as_deref() != Some(path)
            && let Some(stem) = path.file_stem().map(|s| s.to_string_lossy().into_owned())
        {
            self.edit(ctx, Edit::Rename(stem));
        }
        let json = doc::to_json(&self.doc);
        match crate::io::write_atomic(path, json.as_bytes()) {
            Ok(()) => {
                self.disk = Some(disk::Watch::written(path, json.as_bytes()));
                self.disk_change = None;
                self.saved_json = json;
                self.path = Some(path.to_path_buf());
                self.dirty = false;
                self.remember_recent(path);
                self.remove_recovery();
                self.say(ctx, format!("Saved {}", path.display()));
                true
            }
            Err(e) => {
                self.dialog = Some(Dialog::Error {
                    title: "Could not save".into(),
                    text: format!("{}: {e}", path.display()),
                });
                false
            }
        }
    }

    pub fn save(&mut self, ctx: &egui::Context) -> bool {
        match self.path.clone() {
            Some(p) => self.save_to(ctx, &p),
            None => self.save_as(ctx),
        }
    }

    pub fn save_as(&mut self, ctx: &egui::Context) -> bool {
        let mut dialog = rfd::FileDialog::new()
            .add_filter("windloom layout", &["json"])
            .set_file_name(format!(
                "{}.json",
                self.doc.name.to_lowercase().replace(' ', "-")
            ));
        if let Some(dir) = self.path.as_ref().and_then(|p| p.parent()) {
            dialog = dialog.set_directory(dir);
        }
        let started = std::time::Instant::now();
        match dialog.save_file() {
            Some(p) => self.save_to(ctx, &p),
            None => {
                if native_dialog_failed(started) {
                    self.path_prompt(true, true);
                }
                false
            }
        }
    }

    /// The folder file prompts start in: the layout's own, else the working directory.
    fn prompt_folder(&self) -> PathBuf {
        let cwd = || std::env::current_dir().unwrap_or_default();
        match self.path.as_deref().and_then(Path::parent) {
            Some(d) if d.as_os_str().is_empty() => cwd(),
            Some(d) if d.is_relative() => cwd().join(d),
            Some(d) => d.to_path_buf(),
            None => cwd(),
        }
    }

    /// Asks for a path in the editor (`failed`: because the system dialog could not open),
    /// starting in the layout's folder: its file to save over, or the folder to open from.
    pub fn path_prompt(&mut self, save: bool, failed: bool) {
        let dir = self.prompt_folder();
        let text = match (&self.path, save) {
            (Some(p), _) => dir.join(p.file_name().unwrap_or_default()),
            (None, true) => dir.join(format!(
                "{}.json",
                self.doc.name.to_lowercase().replace(' ', "-")
            )),
            (None, false) => dir.join(""),
        }
        .display()
        .to_string();
        self.dialog = Some(Dialog::Path {
            save,
            text,
            note: failed.then(|| {
                "The system's file dialog could not open (is a desktop portal running?). \
                 Type the path instead."
                    .into()
            }),
        });
    }

    /// Saves to a path typed in the editor, making its folder if it does not exist yet;
    /// on failure, why (the prompt stays open with the typed path).
    pub fn save_typed(&mut self, ctx: &egui::Context, path: &Path) -> Result<(), String> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
            && !dir.exists()
        {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("could not make the folder {}: {e}", dir.display()))?;
        }
        self.take_error(|app| {
            app.save_to(ctx, path);
        })
    }

    /// Opens a path typed in the editor; on failure, why (the prompt stays open).
    pub fn open_typed(&mut self, path: &Path) -> Result<(), String> {
        self.take_error(|app| app.open_path(path))
    }

    /// Runs `f`, turning the error dialog it leaves (if any) into the error's text.
    fn take_error(&mut self, f: impl FnOnce(&mut Self)) -> Result<(), String> {
        f(self);
        match self.dialog.take() {
            Some(Dialog::Error { title, text }) => Err(format!("{title}: {text}")),
            other => {
                self.dialog = other;
                Ok(())
            }
        }
    }

    /// Runs `p` now, or asks first when it would discard unsaved changes.
    pub(super) fn request(&mut self, ctx: &egui::Context, p: Pending) {
        if self.dirty {
            self.dialog = Some(Dialog::Discard { then: p });
        } else {
            self.run_pending(ctx, p);
        }
    }

    pub fn run_pending(&mut self, ctx: &egui::Context, p: Pending) {
        match p {
            Pending::New => {
                let doc = Layout::untitled(UNTITLED);
                self.replace_document(doc, None, true);
            }
            Pending::Open(Some(path)) => self.open_path(&path),
            Pending::Open(None) => {
                let started = std::time::Instant::now();
                match rfd::FileDialog::new()
                    .add_filter("windloom layout", &["json"])
                    .pick_file()
                {
                    Some(path) => self.open_path(&path),
                    None if native_dialog_failed(started) => self.path_prompt(false, true),
                    None => {}
                }
            }
            Pending::OpenTyped => self.path_prompt(false, false),
            Pending::Quit => {
                self.remove_recovery();
                self.allow_close = true;
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
    }

    /// Looks whether the document's file changed on disk (the editor does every
    /// [`disk::CHECK_SECONDS`]); a change is kept in [`Self::disk_change`] until answered.
    pub fn check_disk(&mut self) {
        if let Some(change) = self.disk.as_mut().and_then(disk::Watch::check) {
            log::info!("{} changed on disk: {change:?}", self.path_label());
            self.disk_change = Some(change);
        }
    }

    /// Answers a change on disk by loading the file as it is now (the editor's unsaved
    /// changes go; a file that no longer parses is shown as an error and nothing changes).
    pub fn reload_from_disk(&mut self) {
        self.disk_change = None;
        if let Some(p) = self.path.clone() {
            self.open_path(&p);
        }
    }

    /// Answers a change on disk by keeping the editor's document: it counts as unsaved, and
    /// the next Save overwrites the file.
    pub fn keep_mine(&mut self) {
        self.disk_change = None;
        self.saved_json.clear();
        self.doc_changed = true;
    }

    /// The document's file name, or "untitled".
    pub(crate) fn path_label(&self) -> String {
        self.path
            .as_ref()
            .and_then(|p| p.file_name())
            .map_or_else(|| "untitled".into(), |f| f.to_string_lossy().into_owned())
    }

    pub(super) fn remove_recovery(&mut self) {
        if let Some(r) = &mut self.recovery {
            r.remove();
        }
    }

    /// Shows the next recovery copy left by an editor that is gone, if any.
    pub(crate) fn next_recovery(&mut self) {
        if self.dialog.is_none()
            && let Some(found) = self.recover_queue.pop()
        {
            let text = found.offer(self.path.as_deref());
            self.dialog = Some(Dialog::Recover { found, text });
        }
    }

    pub(super) fn autosave(&mut self, ctx: &egui::Context, now: f64) {
        if !self.dirty || now - self.last_autosave < AUTOSAVE_SECONDS {
            return;
        }
        self.last_autosave = now;
        let failing = self.recovery_error.is_some();
        if let Err(e) = self.write_recovery()
            && !failing
        {
            self.say(ctx, format!("Autosave failed: {e}"));
        }
    }

    /// The folder unsaved work is autosaved into, one copy per document (the eframe storage
    /// folder's `recovery/` when run normally; `None`: no autosave).
    pub fn set_recovery_dir(&mut self, dir: Option<PathBuf>) {
        self.remove_recovery();
        self.recovery = dir.map(recovery::Recovery::new);
    }

    /// Where this document's recovery copy goes.
    pub fn recovery_path(&self) -> Option<PathBuf> {
        self.recovery
            .as_ref()
            .map(|r| r.path_for(self.path.as_deref()))
    }

    /// Writes the document's recovery copy now (atomically); autosave calls this. Returns
    /// where it went, or why it could not be written.
    pub fn write_recovery(&mut self) -> Result<PathBuf, String> {
        let Some(r) = &mut self.recovery else {
            return Err("no recovery folder".into());
        };
        match r.write(&self.doc, self.path.as_deref()) {
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

    /// Restores a recovery copy: its layout, unsaved, with the path of the file it was
    /// editing (so Save goes back there).
    pub fn restore(&mut self, found: &recovery::Found) -> Result<(), String> {
        let doc = crate::io::load(&found.layout).map_err(|e| e.to_string())?;
        self.replace_document(doc, found.origin.clone(), false);
        // Our own copy first, then the old one goes (unless it is the same file).
        let ours = self.write_recovery().ok();
        if ours.as_deref() != Some(found.layout.as_path()) {
            found.remove();
        }
        Ok(())
    }
}
