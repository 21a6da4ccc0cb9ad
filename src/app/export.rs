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
}

/// Seconds a live export waits after an edit, so that a drag bakes once at its end rather
/// than at each frame of it.
pub const LIVE_SETTLE: f64 = 0.4;

struct Job {
    cancel: Arc<AtomicBool>,
    progress: Arc<Mutex<(usize, usize, String)>>,
    done: Arc<Mutex<Option<Result<String, String>>>>,
    /// The worker thread, joined when it has finished (or on close).
    handle: Option<std::thread::JoinHandle<()>>,
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
        }
    }
}

impl ExportDialog {
    pub fn running(&self) -> bool {
        self.job.is_some()
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
        let (layout, opts, out) = (
            layout.clone(),
            self.options(),
            PathBuf::from(self.out.trim()),
        );
        let (c, p, d, ctx) = (cancel.clone(), progress.clone(), done.clone(), ctx.clone());
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
            self.result = Some(r);
            if let Some(h) = self.job.take().and_then(|mut j| j.handle.take()) {
                let _ = h.join();
            }
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
        let now = ctx.input(|i| i.time);
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
                    ui.label("Formats");
                    ui.horizontal_wrapped(|ui| {
                        for (f, on) in &mut self.formats {
                            ui.checkbox(on, f.name());
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
