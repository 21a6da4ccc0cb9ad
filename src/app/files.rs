//! The document's file as the editor's windows handle it: open, save (never over another
//! program's change unasked), the typed-path fallback, discard prompts, autosave messages,
//! recovery offers, and answers to a change on disk. Methods of [`EditorApp`]; what they ask
//! of the document itself (writing it, watching it, its recovery copy) is [`Document`]'s.

use super::*;

impl EditorApp {
    /// Replaces the whole document (New, Open, Restore).
    pub(super) fn replace_document(&mut self, doc: Layout, path: Option<PathBuf>, saved: bool) {
        self.doc.replace(doc, path, saved);
        self.selection.clear();
        self.map.camera = None;
        self.map.backdrop = None;
        self.map.polygon.clear();
        self.map.gesture = None;
        self.live.reset();
    }

    /// Loads a layout file; on error shows every problem and keeps the current document.
    pub fn open_path(&mut self, path: &Path) {
        match crate::io::load(path) {
            Ok(doc) => {
                let mut masks = crate::doc::mask_problems(&doc);
                masks.extend(crate::doc::density_map_problem(&doc));
                self.replace_document(doc, Some(path.to_path_buf()), true);
                self.remember_recent(path);
                if let Some(m) = masks.first() {
                    // The wind runs without the mask's obstacles; the inspector says why too.
                    self.tell(format!("Warning: {m}; the layout runs without it"));
                }
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
        if self.doc.path() == Some(path) {
            self.doc.check_disk();
            if self.doc.disk_change == Some(disk::Change::Modified) {
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
            && self.doc.path() != Some(path)
            && let Some(stem) = path.file_stem().map(|s| s.to_string_lossy().into_owned())
        {
            self.edit(ctx, Edit::Rename(stem));
        }
        // The images keep naming their files from the new folder, and a new image takes a
        // free name where a file this editor never read is in the way (one undo step).
        if let Some(plan) = self.doc.save_plan(path) {
            self.edit(ctx, plan);
        }
        match self.doc.write_to(path) {
            Ok(()) => {
                self.remember_recent(path);
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
        match self.doc.path().map(Path::to_path_buf) {
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
        if let Some(dir) = self.doc.path().and_then(Path::parent) {
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
        match self.doc.path().and_then(Path::parent) {
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
        let text = match (self.doc.path(), save) {
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
        if self.doc.is_dirty() {
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
                self.doc.remove_recovery();
                self.allow_close = true;
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
    }

    /// Answers a change on disk by loading the file as it is now (the editor's unsaved
    /// changes go; a file that no longer parses is shown as an error and nothing changes).
    pub fn reload_from_disk(&mut self) {
        self.doc.disk_change = None;
        if let Some(p) = self.doc.path().map(Path::to_path_buf) {
            self.open_path(&p);
        }
    }

    /// Shows the next recovery copy left by an editor that is gone, if any.
    pub fn next_recovery(&mut self) {
        if self.dialog.is_none()
            && let Some(found) = self.doc.next_found()
        {
            let text = found.offer(self.doc.path());
            self.dialog = Some(Dialog::Recover { found, text });
        }
    }

    /// Autosaves unsaved work when it is due (or now, `resting`: the editor is coming to
    /// rest), and says a failure newly met.
    pub(super) fn autosave(&mut self, ctx: &egui::Context, now: f64, resting: bool) {
        if let Some(e) = self.doc.autosave(now, resting) {
            self.say(ctx, format!("Autosave failed: {e}"));
        }
    }

    /// Restores a recovery copy: its layout, unsaved, with the path of the file it was
    /// editing (so Save goes back there), its unsaved images from the copy and every other
    /// image from the level's folder, as the layout names them.
    pub fn restore(&mut self, found: &recovery::Found) -> Result<(), String> {
        let restored = found.restore()?;
        self.replace_document(restored.layout, found.origin.clone(), false);
        self.doc.mark_recovered(&restored.recovered);
        // Our own copy first, then the old one goes (unless it is the same file).
        let ours = self.doc.write_recovery().ok();
        if ours.as_deref() != Some(found.layout.as_path()) {
            found.remove();
        }
        Ok(())
    }
}
