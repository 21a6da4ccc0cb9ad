//! The Export dialog: the same bake as `windloom bake`, on a background thread, with progress
//! and cancel. A cancelled or failed bake leaves no files (the bake writes into a staging
//! folder and moves files into place only on success). *Live export* (File menu, or the
//! dialog) bakes again with the dialog's settings after each edit, as `bake --watch` does on
//! each save: one bake at a time, the latest layout once the edits pause.

use crate::bake::{self, BakeOptions, Format};
use crate::doc::Layout;
use eframe::egui;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

/// Settings of the dialog (kept between openings).
pub struct ExportDialog {
    pub open: bool,
    pub formats: Vec<(Format, bool)>,
    pub frames: usize,
    pub fps: f32,
    pub warmup: f32,
    pub looped: bool,
    /// Flowmaps and the atlas with green growing up the image (`bake --flip-green`).
    pub flip_green: bool,
    pub grid: [u32; 2],
    pub use_layout_grid: bool,
    pub out: String,
    /// The folder [`Self::suggest_out`] last filled in: while `out` still holds it, the
    /// user has not chosen one, and it follows the open file.
    suggested: String,
    job: Option<Job>,
    pub result: Option<Result<String, String>>,
    /// Bake again after each edit.
    pub live: bool,
    /// When the layout last changed unbaked (live export), editor seconds.
    dirty_at: Option<f64>,
    /// A finished live bake's one-line result, for the status bar.
    live_news: Option<String>,
    /// Where the last bake went, once it is there (Open folder).
    pub baked_to: Option<PathBuf>,
}

/// Seconds a live export waits after an edit, so that a drag bakes once at its end rather
/// than at each frame of it.
pub const LIVE_SETTLE: f64 = 0.4;

/// The engines the dialog bakes for, each with the formats and frames its guide
/// (docs/engines/) leads with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Engine {
    Unreal,
    Unity,
    Godot,
}

/// What an engine gets: its formats, frames, frames a second and whether they loop.
pub struct Preset {
    pub formats: &'static [Format],
    pub frames: usize,
    pub fps: f32,
    pub looped: bool,
}

impl Engine {
    pub const ALL: [Engine; 3] = [Engine::Unreal, Engine::Unity, Engine::Godot];

    pub fn name(self) -> &'static str {
        match self {
            Engine::Unreal => "Unreal",
            Engine::Unity => "Unity",
            Engine::Godot => "Godot",
        }
    }

    /// The bake for this engine, steady (one field) or `animated` (a loop).
    pub fn preset(self, animated: bool) -> Preset {
        use Format::*;
        let steady = |formats| Preset {
            formats,
            frames: 1,
            fps: 30.0,
            looped: false,
        };
        let animated_at = |formats, frames, fps| Preset {
            formats,
            frames,
            fps,
            looped: true,
        };
        match (self, animated) {
            (Engine::Unreal, false) => steady(&[Fga, Exr, Dds]),
            (Engine::Unreal, true) => animated_at(&[Atlas], 64, 16.0),
            (Engine::Unity, false) => steady(&[Vf, Exr, Dds]),
            (Engine::Unity, true) => animated_at(&[Vf], 48, 24.0),
            (Engine::Godot, false) => steady(&[Exr, Dds]),
            (Engine::Godot, true) => animated_at(&[AtlasExr, Atlas], 48, 24.0),
        }
    }

    /// What the engine does with its bake, and where its guide is.
    pub fn what(self, animated: bool) -> &'static str {
        match (self, animated) {
            (Engine::Unreal, false) => {
                "A Niagara vector field (FGA), a material texture (EXR) and the wind volume \
                 (DDS); docs/engines/unreal.md, imported by windloom_import.py"
            }
            (Engine::Unreal, true) => {
                "A looping flipbook atlas sampled in Niagara's particle update; \
                 docs/engines/unreal.md"
            }
            (Engine::Unity, false) => {
                "A VFX Graph vector field (VF), a texture (EXR) and the wind volume; \
                 docs/engines/unity.md"
            }
            (Engine::Unity, true) => {
                "A vector field a frame, stepped through at the bake's rate, looping; \
                 docs/engines/unity.md"
            }
            (Engine::Godot, false) => {
                "A texture (EXR) for the add-on's grass and particle shaders and the wind \
                 volume; docs/engines/godot.md"
            }
            (Engine::Godot, true) => {
                "A looping flipbook atlas (EXR, and PNG for the web) for the add-on's shaders; \
                 docs/engines/godot.md"
            }
        }
    }
}

struct Job {
    cancel: Arc<AtomicBool>,
    progress: Arc<Mutex<(usize, usize, String)>>,
    done: Arc<Mutex<Option<Result<String, String>>>>,
    /// The worker thread, joined when it has finished (or on close).
    handle: Option<std::thread::JoinHandle<()>>,
    /// Where it bakes into.
    out: PathBuf,
}

impl Default for ExportDialog {
    fn default() -> Self {
        Self {
            open: false,
            formats: Format::ALL
                .iter()
                .map(|f| (*f, matches!(f, Format::Exr | Format::Png16 | Format::Raw)))
                .collect(),
            frames: 1,
            fps: 30.0,
            warmup: 5.0,
            looped: false,
            flip_green: false,
            grid: [128, 128],
            use_layout_grid: true,
            out: "bake".into(),
            suggested: "bake".into(),
            job: None,
            result: None,
            live: false,
            dirty_at: None,
            live_news: None,
            baked_to: None,
        }
    }
}

impl ExportDialog {
    pub fn running(&self) -> bool {
        self.job.is_some()
    }

    /// Takes `engine`'s bake, steady or animated.
    pub fn apply(&mut self, engine: Engine, animated: bool) {
        let p = engine.preset(animated);
        for (f, on) in &mut self.formats {
            *on = p.formats.contains(f);
        }
        self.frames = p.frames;
        self.fps = p.fps;
        self.looped = p.looped;
        self.flip_green = false;
    }

    /// The engine and kind of bake the settings are, if they are one of the presets (else
    /// the user's own: Custom).
    pub fn engine(&self) -> Option<(Engine, bool)> {
        Engine::ALL
            .iter()
            .flat_map(|e| [(*e, false), (*e, true)])
            .find(|&(e, animated)| {
                let p = e.preset(animated);
                self.formats
                    .iter()
                    .all(|(f, on)| *on == p.formats.contains(f))
                    && self.frames == p.frames
                    && (p.frames == 1 || self.fps == p.fps && self.looped == p.looped)
                    && !self.flip_green
            })
    }

    fn options(&self) -> BakeOptions {
        BakeOptions {
            formats: self
                .formats
                .iter()
                .filter(|(_, on)| *on)
                .map(|(f, _)| *f)
                .collect(),
            warmup: self.warmup,
            frames: self.frames,
            fps: self.fps,
            looped: self.looped,
            grid: (!self.use_layout_grid).then_some(self.grid),
            half: false,
            flip_green: self.flip_green,
            max_bytes: bake::DEFAULT_MAX_BYTES,
            backend: crate::engine::Backend::Cpu,
        }
    }

    /// Fills in the output folder for the layout at `path` (none: not saved yet) unless the
    /// user has typed or chosen one: `<its folder>/<its name>-bake`, so two layouts of one
    /// folder never bake into (and replace) the same folder; `bake` for an unsaved layout.
    pub fn suggest_out(&mut self, path: Option<&std::path::Path>) {
        if self.out.trim() != self.suggested {
            return;
        }
        let suggestion = match path {
            Some(p) => {
                let stem = p
                    .file_stem()
                    .map_or("layout".into(), |s| s.to_string_lossy());
                let dir = p.parent().unwrap_or(std::path::Path::new(""));
                dir.join(format!("{stem}-bake")).display().to_string()
            }
            None => "bake".into(),
        };
        self.out.clone_from(&suggestion);
        self.suggested = suggestion;
    }

    /// Starts baking `layout` in the background.
    pub fn start(&mut self, layout: &Layout, ctx: &egui::Context) {
        let cancel = Arc::new(AtomicBool::new(false));
        let progress = Arc::new(Mutex::new((0, 1, "starting".to_string())));
        let done = Arc::new(Mutex::new(None));
        let out = PathBuf::from(self.out.trim());
        // Said in full: "bake" alone does not say where on the disk it went.
        let out = std::path::absolute(&out).unwrap_or(out);
        let (layout, opts) = (layout.clone(), self.options());
        let (c, p, d, ctx) = (cancel.clone(), progress.clone(), done.clone(), ctx.clone());
        let into = out.clone();
        let worker = std::thread::Builder::new()
            .name("windloom-export".into())
            .spawn(move || {
                let mut report = |a: usize, b: usize, what: &str| {
                    if let Ok(mut g) = p.lock() {
                        *g = (a, b, what.to_string());
                    }
                    ctx.request_repaint();
                };
                // A panic in the bake is reported as its result, never a dialog that says
                // "running" forever.
                let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    bake::bake(&layout, &out, &opts, &c, &mut report)
                }));
                let r = match r {
                    Ok(r) => r
                        .map(|m| {
                            // The manifest's notes (advice that applied, a field far past
                            // its arrows, a still field) under the summary.
                            let mut msg = format!(
                                "Baked {} frame(s), {} files, into {} (sequence {})",
                                m.frames.count,
                                m.files.len() + 1,
                                out.display(),
                                m.sequence
                            );
                            for n in &m.notes {
                                msg += &format!("\nNote: {n}");
                            }
                            msg
                        })
                        .map_err(|e| e.to_string()),
                    Err(panic) => Err(format!(
                        "the export stopped unexpectedly ({}); nothing was written to {}",
                        panic_message(&panic),
                        out.display()
                    )),
                };
                if let Ok(mut g) = d.lock() {
                    *g = Some(r);
                }
                ctx.request_repaint();
            });
        self.result = None;
        match worker {
            Ok(handle) => {
                self.job = Some(Job {
                    cancel,
                    progress,
                    done,
                    handle: Some(handle),
                    out: into,
                })
            }
            Err(e) => self.result = Some(Err(format!("could not start the export: {e}"))),
        }
    }

    pub fn cancel(&self) {
        if let Some(j) = &self.job {
            j.cancel.store(true, Ordering::SeqCst);
        }
    }

    /// Collects a finished job's result (and its thread).
    fn poll(&mut self) {
        let finished = self
            .job
            .as_ref()
            .and_then(|j| j.done.lock().ok().and_then(|mut d| d.take()));
        if let Some(r) = finished {
            if self.live {
                self.live_news = Some(match &r {
                    Ok(msg) => format!("Live export: {}", msg.lines().next().unwrap_or_default()),
                    Err(e) => format!("Live export failed: {e}"),
                });
            }
            if let Some(mut job) = self.job.take() {
                if r.is_ok() {
                    self.baked_to = Some(job.out.clone());
                }
                if let Some(h) = job.handle.take() {
                    let _ = h.join();
                }
            }
            self.result = Some(r);
        }
    }

    /// On closing the editor: cancels a running export and waits for its thread (a cancelled
    /// bake leaves nothing behind).
    pub fn shutdown(&mut self) {
        if let Some(mut j) = self.job.take() {
            j.cancel.store(true, Ordering::SeqCst);
            if let Some(h) = j.handle.take() {
                let _ = h.join();
            }
        }
    }

    /// The layout changed: a live export bakes it once the edits pause.
    pub fn edited(&mut self, now: f64) {
        if self.live {
            self.dirty_at = Some(now);
        }
    }

    /// Turns live export on (baking the layout at once) or off (a running bake finishes).
    pub fn set_live(&mut self, on: bool) {
        self.live = on;
        self.dirty_at = on.then_some(f64::NEG_INFINITY);
    }

    /// A finished live bake's result, once.
    pub fn take_live_news(&mut self) -> Option<String> {
        self.live_news.take()
    }

    /// Starts a live bake when one is due and none runs; wakes the editor when one will be.
    fn live_tick(&mut self, ctx: &egui::Context, layout: &Layout) {
        let Some(at) = self.dirty_at.filter(|_| self.live) else {
            return;
        };
        if self.running() {
            // The edit bakes when this bake is done (its end repaints).
            return;
        }
        // A gesture under way (a drag held still, a number being typed) is one edit, baked
        // once when it ends: not each time the pointer rests mid-drag.
        let gesture = ctx.input(|i| i.pointer.any_down()) || ctx.memory(|m| m.focused().is_some());
        let now = ctx.input(|i| i.time);
        if gesture {
            self.dirty_at = Some(now.max(at));
            ctx.request_repaint_after(std::time::Duration::from_secs_f64(LIVE_SETTLE));
            return;
        }
        if now - at >= LIVE_SETTLE {
            self.dirty_at = None;
            self.start(layout, ctx);
        } else {
            ctx.request_repaint_after(std::time::Duration::from_secs_f64(LIVE_SETTLE - (now - at)));
        }
    }

    pub fn ui(&mut self, ctx: &egui::Context, layout: &Layout) {
        self.poll();
        self.live_tick(ctx, layout);
        if !self.open {
            return;
        }
        let mut open = self.open;
        egui::Window::new("Export / Bake")
            .open(&mut open)
            .resizable(false)
            .show(ctx, |ui| {
                let busy = self.running();
                ui.add_enabled_ui(!busy, |ui| {
                    // The engine first: each picks its formats and frames (docs/engines/).
                    let current = self.engine();
                    let animated = current.map_or(self.frames > 1, |(_, a)| a);
                    ui.horizontal(|ui| {
                        ui.label("For");
                        for e in Engine::ALL {
                            let on = current.is_some_and(|(c, _)| c == e);
                            if ui
                                .selectable_label(on, e.name())
                                .on_hover_text(e.what(animated))
                                .clicked()
                            {
                                self.apply(e, animated);
                            }
                        }
                        ui.selectable_label(current.is_none(), "Custom")
                            .on_hover_text("The formats and frames below, as you set them");
                    });
                    if let Some((e, _)) = current {
                        ui.horizontal(|ui| {
                            for (anim, label) in [(false, "Steady"), (true, "Animated loop")] {
                                if ui.radio(animated == anim, label).clicked() {
                                    self.apply(e, anim);
                                }
                            }
                        });
                        ui.weak(e.what(animated));
                    }
                    ui.label("Formats");
                    ui.horizontal_wrapped(|ui| {
                        for (f, on) in &mut self.formats {
                            ui.checkbox(on, f.name()).on_hover_text(f.engines_hint());
                        }
                    });
                    egui::Grid::new("export").num_columns(2).show(ui, |ui| {
                        let l = ui.label("Frames");
                        ui.add(egui::DragValue::new(&mut self.frames).range(1..=10_000))
                            .labelled_by(l.id);
                        ui.end_row();
                        let l = ui.label("Frames per second");
                        ui.add(egui::DragValue::new(&mut self.fps).range(1.0..=240.0))
                            .labelled_by(l.id);
                        ui.end_row();
                        let l = ui.label("Warm-up");
                        ui.add(
                            egui::DragValue::new(&mut self.warmup)
                                .range(0.0..=600.0)
                                .suffix(" s"),
                        )
                        .labelled_by(l.id);
                        ui.end_row();
                        let l = ui.label("Loop");
                        ui.checkbox(&mut self.looped, "seamless (cross-fade)")
                            .labelled_by(l.id);
                        ui.end_row();
                        let l = ui.label("Flowmap green");
                        ui.checkbox(&mut self.flip_green, "flipped (grows up the image)")
                            .labelled_by(l.id)
                            .on_hover_text(
                                "PNG flowmaps and the atlas store green as the wind toward \
                                 north (up the image), as shaders whose v runs up the image \
                                 expect; off, green grows down the image (south)",
                            );
                        ui.end_row();
                        let l = ui.label("Grid");
                        ui.horizontal(|ui| {
                            ui.checkbox(
                                &mut self.use_layout_grid,
                                format!(
                                    "layout's ({}×{})",
                                    layout.world.grid[0], layout.world.grid[1]
                                ),
                            )
                            .labelled_by(l.id);
                            if !self.use_layout_grid {
                                ui.add(egui::DragValue::new(&mut self.grid[0]).range(8..=4096))
                                    .labelled_by(l.id);
                                ui.label("×");
                                ui.add(egui::DragValue::new(&mut self.grid[1]).range(8..=4096))
                                    .labelled_by(l.id);
                            }
                        });
                        ui.end_row();
                        let l = ui.label("Output folder");
                        ui.horizontal(|ui| {
                            ui.text_edit_singleline(&mut self.out).labelled_by(l.id);
                            if ui.button("Choose…").clicked()
                                && let Some(dir) = rfd::FileDialog::new().pick_folder()
                            {
                                self.out = dir.display().to_string();
                            }
                        });
                        ui.end_row();
                    });
                });
                ui.separator();
                // What the bake will ship: settings known to make bad wind are said here too.
                for a in crate::doc::advise(layout) {
                    ui.colored_label(ui.visuals().warn_fg_color, format!("Warning: {a}"));
                }
                if let Some(j) = &self.job {
                    let (a, b, what) = j.progress.lock().map(|g| g.clone()).unwrap_or_default();
                    ui.add(
                        egui::ProgressBar::new(a as f32 / b.max(1) as f32)
                            .text(format!("{what} {a}/{b}")),
                    );
                    if ui.button("Cancel").clicked() {
                        self.cancel();
                    }
                } else if ui.button("Bake").clicked() {
                    self.start(layout, ctx);
                }
                let mut live = self.live;
                if ui
                    .checkbox(&mut live, "Live export: bake again after each edit")
                    .changed()
                {
                    self.set_live(live);
                }
                match &self.result {
                    Some(Ok(msg)) => {
                        ui.colored_label(egui::Color32::LIGHT_GREEN, msg);
                        if let Some(dir) = &self.baked_to
                            && ui
                                .button("Open folder")
                                .on_hover_text(dir.display().to_string())
                                .clicked()
                            && let Err(e) = crate::platform::process::show_folder(dir)
                        {
                            self.result = Some(Err(e));
                        }
                    }
                    Some(Err(msg)) => {
                        ui.colored_label(egui::Color32::from_rgb(255, 120, 100), msg);
                    }
                    None => {}
                }
            });
        self.open = open;
    }

    /// Blocks until the running job finishes (tests).
    pub fn wait(&mut self) {
        while self.running() {
            self.poll();
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
    }
}

/// The text of a caught panic.
fn panic_message(panic: &Box<dyn std::any::Any + Send>) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".into())
}
