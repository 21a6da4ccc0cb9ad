//! The editor (eframe/egui): AGC arrow-tree authoring over a top-down map, with the wind live.
//!
//! The app owns a [`Document`] (the layout, its undo history, its file and recovery copy);
//! every change goes through an [`Edit`]. The simulation runs on a worker thread
//! ([`LiveSim`]) and never blocks the UI.

pub use crate::io::{AUTOSAVE_SECONDS, Document};
mod clipboard;
pub mod context_menu;
pub mod export;
mod files;
mod gpu_view;
mod handles;
pub mod input;
pub use crate::gpu::grass::Orbit;
pub use gpu_view::SOFTWARE_BLADE_BUDGET;
pub use map::scale_bar_metres as map_scale_bar_metres;
mod grass_controls;
mod inspector;
mod map;
pub mod new_image;
pub mod paint;
mod panels;
pub mod presets;
mod probes;
mod stroke;
pub mod timeline;
pub mod view;

use crate::doc::{self, Edit, Layout};
use crate::engine::Backend;
use crate::engine::live::LiveSim;
use crate::io::{disk, recovery};
use eframe::egui::{self, Pos2, Rect};
use std::path::{Path, PathBuf};
use view::WindView;

/// What the pointer does on the map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Tool {
    /// Click to select, drag to move, drag on empty map to box-select.
    Select,
    /// Click to place the root of a new tree.
    AddRoot,
    /// Drag from any node to place a child end point.
    AddArrow,
    /// Drag from the centre outwards to place a circular obstacle.
    Circle,
    /// Click points; click the first point (or press Enter) to close.
    Polygon,
    /// Paint a mask obstacle's pixels or the grass density map.
    Paint,
    /// Click to drop a probe that plots the wind where it stands.
    Probe,
    /// Drag a free path: an arrow chain along it.
    Stroke,
}

impl Tool {
    pub const ALL: [Tool; 8] = [
        Tool::Select,
        Tool::AddRoot,
        Tool::AddArrow,
        Tool::Stroke,
        Tool::Circle,
        Tool::Polygon,
        Tool::Paint,
        Tool::Probe,
    ];

    pub fn label(self) -> &'static str {
        match self {
            Self::Select => "Select",
            Self::AddRoot => "Add root",
            Self::AddArrow => "Add arrow",
            Self::Circle => "Circle",
            Self::Polygon => "Polygon",
            Self::Paint => "Paint",
            Self::Stroke => "Stroke",
            Self::Probe => "Probe",
        }
    }

    pub fn key(self) -> egui::Key {
        match self {
            Self::Select => egui::Key::S,
            Self::AddRoot => egui::Key::R,
            Self::AddArrow => egui::Key::A,
            Self::Circle => egui::Key::C,
            Self::Polygon => egui::Key::P,
            Self::Paint => egui::Key::B,
            Self::Stroke => egui::Key::W,
            Self::Probe => egui::Key::M,
        }
    }

    pub fn hint(self) -> &'static str {
        match self {
            Self::Select => {
                "Click to select (Shift adds), drag to move, drag on empty map to box-select"
            }
            Self::AddRoot => "Click on the map to place the root of a new wind tree",
            Self::AddArrow => {
                "Drag from any point to place an arrow end point; several from one point branch"
            }
            Self::Circle => "Drag from the centre outwards to place a round obstacle",
            Self::Polygon => {
                "Click corners; click the first corner or press Enter to close, Esc to cancel"
            }
            Self::Probe => {
                "Click to drop a probe: the wind where it stands is plotted under the map (also \
                 on the ground in the 3D view)"
            }
            Self::Stroke => {
                "Drag a path: an arrow chain along it (from a point: it continues that tree); \
                 strength and radius in the toolbar"
            }
            Self::Paint => {
                "Drag to paint the selected mask obstacle solid (or, with none selected, grass \
                 on the density map); Shift-drag erases; [ and ] change the brush"
            }
        }
    }
}

/// Something selectable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Sel {
    Node(u32),
    Tree(u32),
    Obstacle(u32),
    Ambient(u32),
    Probe(u32),
    /// The map's backdrop picture (picked in the Layers list): moved and scaled on the map.
    Backdrop,
}

/// Command buffers from the simulation thread, each with the acknowledgement it waits for.
/// What the central area shows (View menu, toolbar; `windloom FILE --view map|3d|split`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Central {
    /// The top-down map (authoring).
    #[default]
    Map,
    /// The grass in 3D in the live wind.
    Grass,
    /// Both, side by side.
    Split,
}

impl Central {
    pub const ALL: [Central; 3] = [Central::Map, Central::Grass, Central::Split];

    pub fn label(self) -> &'static str {
        match self {
            Central::Map => "Map",
            Central::Grass => "3D grass",
            Central::Split => "Map + 3D",
        }
    }
}

/// Settings that persist between runs.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Settings {
    pub recent: Vec<PathBuf>,
    pub wind_view: WindView,
    pub snap: bool,
    pub snap_step: f32,
    pub streak_count: usize,
    pub show_grid: bool,
    /// The terrain on the map: its hill shade, and contour lines (View menu).
    pub hill_shade: bool,
    pub contours: bool,
    /// Where the live wind runs (View menu).
    pub backend: Backend,
    /// Map, 3D grass, or both (View menu, toolbar).
    pub central: Central,
    /// The 3D view's wind colours (its row of toggles): on or off, and their opacity.
    pub wind_colours: bool,
    pub wind_opacity: f32,
    /// The 3D view's arrows (View → Arrows in the 3D view).
    pub grass_arrows: bool,
    /// The speed at the top of the speed colours (map and 3D), m/s; `None`: the field's peak
    /// (View menu).
    pub speed_scale: Option<f32>,
    /// The Stroke tool's arrows.
    pub stroke: doc::stroke::StrokeSettings,
    /// The probes' panel open (plots and statistics) or folded to one line of readings.
    pub probes_open: bool,
    /// The paint tool's mark, hardness and opacity.
    pub brush: paint::Brush,
    /// The map's wind colours' opacity, 0.1 to 1 (`None`: automatic, [`map_wind_opacity`]):
    /// how much of the backdrop shows through them.
    pub map_wind_opacity: Option<f32>,
}

/// The map's wind colours' opacity when the designer has not set one: all of it over a
/// plain world, [`MAP_WIND_OVER_BACKDROP`] of it where a backdrop would be hidden.
pub fn map_wind_opacity(set: Option<f32>, backdrop: bool) -> f32 {
    set.unwrap_or(if backdrop {
        MAP_WIND_OVER_BACKDROP
    } else {
        1.0
    })
}

/// The automatic opacity of the map's wind colours over a backdrop: the level's picture reads
/// through the speed colours (at their full 90 % it was hidden).
pub const MAP_WIND_OVER_BACKDROP: f32 = 0.55;
/// The opacities the designer may set.
pub const MAP_WIND_OPACITY: std::ops::RangeInclusive<f32> = 0.1..=1.0;

/// What a colour scale was found for: the snapshot, the view, the fixed speed scale.
type ScaleKey = (u64, WindView, Option<f32>);

impl Default for Settings {
    fn default() -> Self {
        Self {
            recent: Vec::new(),
            wind_view: WindView::Streaks,
            snap: false,
            snap_step: 1.0,
            streak_count: 1500,
            show_grid: true,
            hill_shade: true,
            contours: false,
            backend: Backend::Auto,
            central: Central::Map,
            wind_colours: false,
            wind_opacity: grass_controls::GrassControls::default().wind_opacity,
            grass_arrows: true,
            speed_scale: None,
            stroke: Default::default(),
            probes_open: true,
            brush: Default::default(),
            map_wind_opacity: None,
        }
    }
}

const SETTINGS_KEY: &str = "windloom-settings";
/// The fixed speed scale's range, m/s.
pub const SPEED_SCALE: (f32, f32) = crate::colour::FIXED_SCALE_RANGE;
/// The name of a new layout (File → New), which its first save replaces by the file's.
pub const UNTITLED: &str = "Untitled";
/// Longest press that still counts as a click, in frame time (egui's default is 0.8 s).
const CLICK_SECONDS: f64 = 10.0;
/// Seconds a status message shows.
pub const MESSAGE_SECONDS: f64 = 6.0;
/// Seconds between two frames beyond which the editor counts as having rested.
const IDLE_GAP: f64 = 1.0;

/// A modal question or message.
pub enum Dialog {
    Error {
        title: String,
        text: String,
    },
    /// Unsaved changes would be lost by `then`.
    Discard {
        then: Pending,
    },
    ConfirmDelete {
        count: usize,
        sel: Vec<Sel>,
    },
    Recover {
        found: recovery::Found,
        /// What the dialog says of it ([`recovery::Found::offer`]), written when it opens.
        text: String,
    },
    /// A path typed in the editor: where the system's file dialog cannot open (no desktop
    /// portal), or by choice (File → Open path… / Save to path…).
    Path {
        save: bool,
        text: String,
        note: Option<String>,
    },
    Shortcuts,
    /// A new mask obstacle or density map, blank or from a picture.
    NewImage(Box<new_image::NewImage>),
    /// Save as preset: its kind, the name typed so far, why the last one was refused.
    SavePreset {
        kind: crate::io::presets::Kind,
        name: String,
        refused: Option<String>,
    },
}

/// An action waiting for the user to confirm discarding changes.
#[derive(Clone)]
pub enum Pending {
    New,
    Open(Option<PathBuf>),
    /// Open a path typed in the editor.
    OpenTyped,
    Quit,
}

/// The editor application state.
pub struct EditorApp {
    /// The layout, its history, its file and its recovery copy.
    pub doc: Document,
    pub selection: Vec<Sel>,
    pub tool: Tool,
    /// The paint brush's radius, metres, and the stroke in progress.
    pub brush_radius: f32,
    pub paint: Option<paint::PaintStroke>,
    /// The map view's own state: its camera, rectangle, gesture, textures, readouts.
    pub map: map::MapState,
    /// The status bar's rectangle in the last frame (tests mask it: it shows timings).
    pub status_rect: Rect,
    /// The toolbar's width in one row, as last drawn: it shares the menu bar's row while
    /// that has room, and takes a wrapped row of its own below it when not.
    toolbar_width: f32,
    pub settings: Settings,
    /// eframe's GPU device as the editor uses it (declared before `live` so that its queue
    /// of the simulation thread's GPU work is dropped first: a worker waiting on it then
    /// gives up instead of blocking the join).
    pub gpu: gpu_view::GpuBridge,
    pub live: LiveSim,
    pub dialog: Option<Dialog>,
    /// A short message shown in the status bar (why an edit was refused, what was saved)
    /// and when it was first shown (+∞ until the next frame shows it: [`Self::tell`]).
    pub message: Option<(String, f64)>,
    frame_ms: f32,
    /// When the last frame began (editor seconds), and whether this one came after a rest
    /// (the status bar then says "idle" rather than a frame rate of frames long gone).
    last_frame_at: f64,
    pub idle: bool,
    /// CPU milliseconds the last frames spent building the UI (smoothed).
    ui_ms: f32,
    /// For waking the UI from other threads.
    repaint: egui::Context,
    /// The 3D grass view.
    pub grass_view: gpu_view::GrassView,
    /// The window title last sent to the window.
    sent_title: Option<String>,
    allow_close: bool,
    pub export: export::ExportDialog,
    /// Help → User guide.
    pub guide: panels::Guide,
    /// What this editor last copied.
    copied: clipboard::Copied,
    /// The Presets menu: the user's presets folder.
    pub presets: presets::PresetsState,
    /// The inspector's typed rotation (degrees) and scale (percent).
    pub transform_input: (f32, f32),
    /// What the probes read of the live wind.
    pub probe_log: probes::ProbeLog,
    /// The timeline under the map: play range, loop, scrubbing.
    pub timeline: timeline::Timeline,
    /// The pointer's events, paced so a slow frame loses no gesture ([`input`]).
    pacer: input::InputPacer,
}

impl EditorApp {
    /// An editor on `doc` (read from `path`, if any), with the simulation running.
    pub fn new(doc: Layout, path: Option<PathBuf>, ctx: &egui::Context) -> Self {
        // egui times a press by the frames it arrives in: a quick click whose release comes
        // in the frame after a slow one (a 3D view's first frame on a software adapter, a
        // big grid rebuilt) counted as a long press past 0.8 s and was lost. A still press is
        // a click however long (drags start by moving, and nothing here is press-and-hold).
        ctx.options_mut(|o| o.input_options.max_click_duration = CLICK_SECONDS);
        let repaint_ctx = ctx.clone();
        let live = LiveSim::start(&doc, move || repaint_ctx.request_repaint());
        let poller = {
            let ctx = ctx.clone();
            disk::Poller::start(move || ctx.request_repaint())
        };
        Self {
            doc: Document::new(doc, path, poller),
            selection: Vec::new(),
            tool: Tool::Select,
            brush_radius: 2.0,
            paint: None,
            map: map::MapState::default(),
            status_rect: Rect::NOTHING,
            toolbar_width: 0.0,
            settings: Settings::default(),
            gpu: gpu_view::GpuBridge::default(),
            live,
            dialog: None,
            message: None,
            frame_ms: 0.0,
            last_frame_at: 0.0,
            idle: false,
            ui_ms: 0.0,
            repaint: ctx.clone(),
            grass_view: Default::default(),
            sent_title: None,
            allow_close: false,
            export: export::ExportDialog::default(),
            guide: Default::default(),
            copied: Default::default(),
            presets: Default::default(),
            transform_input: (90.0, 200.0),
            probe_log: Default::default(),
            timeline: Default::default(),
            pacer: Default::default(),
        }
    }

    /// Paces a frame's events as the window's hook does ([`input::InputPacer`]): those egui
    /// should see now stay in `events`; whether some are held for the next frame. For a
    /// harness that feeds events itself (eframe calls [`eframe::App::raw_input_hook`]).
    pub fn pace(&mut self, events: &mut Vec<egui::Event>) -> bool {
        self.pacer.pace(events)
    }

    /// Adds a new wind tree rooted at `pos` (one undo step), its root selected; whether it
    /// was added.
    pub fn add_root(&mut self, ctx: &egui::Context, pos: doc::Vec2) -> bool {
        let id = self.doc.next_id();
        let tree = doc::Tree {
            id,
            name: format!("Wind {}", self.doc.trees.len() + 1),
            enabled: true,
            window: doc::TimeWindow::Always,
            emission: doc::Emission::Continuous,
            propagation_speed: 20.0,
            root: doc::Node::new(id + 1, pos, 8.0, 5.0),
            locked: false,
            hidden: false,
            keys: Vec::new(),
        };
        let index = self.doc.trees.len();
        let added = self.edit(ctx, Edit::AddTree { index, tree });
        if added {
            self.selection = vec![Sel::Node(id + 1)];
        }
        added
    }

    /// Opens the dialog that makes a new mask obstacle or density map.
    pub fn new_image(&mut self, kind: new_image::Kind) {
        self.dialog = Some(Dialog::NewImage(Box::new(new_image::NewImage::new(
            self, kind,
        ))));
    }

    /// Takes the settings of an earlier run, the 3D view's wind colours and arrows with them.
    pub fn apply_settings(&mut self, s: Settings) {
        let c = &mut self.grass_view.controls;
        c.wind_colours = s.wind_colours;
        c.arrows = s.grass_arrows;
        let range = grass_controls::WIND_OPACITY;
        c.wind_opacity = if s.wind_opacity.is_finite() {
            s.wind_opacity.clamp(*range.start(), *range.end())
        } else {
            Settings::default().wind_opacity
        };
        self.settings = s;
        self.settings.brush = self.settings.brush.sane();
        self.settings.map_wind_opacity = self
            .settings
            .map_wind_opacity
            .filter(|v| v.is_finite())
            .map(|v| v.clamp(*MAP_WIND_OPACITY.start(), *MAP_WIND_OPACITY.end()));
        let step = self.settings.snap_step;
        self.settings.snap_step = if step.is_finite() {
            step.clamp(*panels::SNAP_STEP.start(), *panels::SNAP_STEP.end())
        } else {
            Settings::default().snap_step
        };
        self.settings.speed_scale = self
            .settings
            .speed_scale
            .filter(|v| v.is_finite())
            .map(|v| v.clamp(SPEED_SCALE.0, SPEED_SCALE.1));
    }

    /// The settings as the next run should find them.
    pub fn settings_to_save(&self) -> Settings {
        let c = &self.grass_view.controls;
        Settings {
            wind_colours: c.wind_colours,
            wind_opacity: c.wind_opacity,
            grass_arrows: c.arrows,
            ..self.settings.clone()
        }
    }

    /// The editor as eframe creates it: settings and window state restored, the adapter
    /// named, and an offer to restore unsaved work if the last session did not end cleanly.
    pub fn from_creation_context(
        cc: &eframe::CreationContext<'_>,
        doc: Layout,
        launch: Launch,
    ) -> Self {
        let mut app = Self::new(doc, launch.path.clone(), &cc.egui_ctx);
        if let Some(storage) = cc.storage
            && let Some(s) = eframe::get_value::<Settings>(storage, SETTINGS_KEY)
        {
            app.apply_settings(s);
        }
        app.launch(&launch);
        if let Some(rs) = &cc.wgpu_render_state {
            app.attach_gpu(rs);
        }
        if let Some(dir) = eframe::storage_dir("windloom") {
            recovery::sweep_temporaries(&dir.join("recovery"), recovery::STALE_TEMPORARY);
            let mut found = recovery::Recovery::found(&dir.join("recovery"));
            // The single shared copy of earlier versions.
            let legacy = dir.join("recovery.json");
            if legacy.exists() {
                found.push(recovery::Found::at(legacy));
            }
            app.doc.offer_found(found);
            app.next_recovery();
            app.doc.set_recovery_dir(Some(dir.join("recovery")));
        }
        app
    }

    /// What the command line asked for, over the settings of the last run: where the wind
    /// runs, the view, the first status message; a layout file that exists goes into Open
    /// Recent as one opened from the menu does.
    pub fn launch(&mut self, launch: &Launch) {
        if let Some(b) = launch.backend {
            self.settings.backend = b;
        }
        if let Some(v) = launch.view {
            self.settings.central = v;
        }
        if let Some(note) = &launch.note {
            self.tell(note.clone());
        }
        if let Some(p) = launch.path.as_deref().filter(|p| p.is_file()) {
            self.remember_recent(p);
        }
    }

    /// Gives the live wind eframe's device: the map renderer is installed on it and the
    /// field runs there when the backend choice says so (View menu).
    pub fn attach_gpu(&mut self, rs: &egui_wgpu::RenderState) {
        let info = rs.adapter.get_info();
        self.gpu.adapter = format!("{} ({:?})", info.name, info.backend);
        log::info!(
            "editor device: {} ({:?}, {:?}, driver {} {})",
            info.name,
            info.device_type,
            info.backend,
            info.driver,
            info.driver_info
        );
        match crate::gpu::GpuContext::from_parts(&rs.adapter, rs.device.clone(), rs.queue.clone()) {
            Ok(ctx) => {
                // wgpu reconfigures the window's surface (on a resize) only while no other
                // thread submits to its queue, and panics otherwise: the simulation thread's
                // GPU work is therefore submitted here, on the UI thread, which it wakes and
                // waits for.
                let (tx, rx) = std::sync::mpsc::channel();
                let wake = self.repaint.clone();
                let ctx = ctx.with_submitter(std::sync::Arc::new(move |cb| {
                    let (ack, done) = std::sync::mpsc::sync_channel(1);
                    if tx.send((cb, ack)).is_ok() {
                        wake.request_repaint();
                        let _ = done.recv_timeout(std::time::Duration::from_secs(10));
                    }
                }));
                self.gpu.submissions = Some(rx);
                gpu_view::install(rs);
                self.gpu.map_on_gpu = true;
                self.gpu.render_state = Some(rs.clone());
                self.live.set_gpu(ctx, self.settings.backend);
            }
            Err(e) => {
                self.tell(format!("the wind stays on the CPU: {e}"));
            }
        }
    }

    /// The wgpu resources the editor's device holds now (`None` without a GPU device).
    pub fn gpu_resources(&self) -> Option<crate::gpu::LiveResources> {
        crate::gpu::LiveResources::of(&self.gpu.render_state.as_ref()?.instance)
    }

    /// The 3D grass view, or why there is none.
    fn grass(&mut self, ui: &mut egui::Ui) {
        match self.gpu.render_state.clone() {
            Some(rs) => {
                let snap = self.live.snapshot();
                // The map's visible part, when the map is beside the 3D view.
                let footprint = (self.settings.central == Central::Split)
                    .then(|| {
                        self.map.camera.map(|c| {
                            let a = c.to_world(self.map.rect, self.map.rect.min);
                            let b = c.to_world(self.map.rect, self.map.rect.max);
                            let (lo, hi) = self.doc.bounds();
                            (
                                [a[0].max(lo[0]), a[1].max(lo[1])],
                                [b[0].min(hi[0]), b[1].min(hi[1])],
                            )
                        })
                    })
                    .flatten();
                let base = crate::io::layout_base(self.doc.path());
                self.grass_view.speed_scale = self.settings.speed_scale;
                // Beside the map (drawn first this frame), its pointer: marked in 3D too.
                let beside = footprint.map(|footprint| gpu_view::MapBeside {
                    footprint,
                    pointer: self.map.cursor_world,
                });
                self.grass_view
                    .show(ui, &rs, &self.doc, &snap, beside, &base);
                // The status bar reads the ground under the pointer in 3D as on the map (beside
                // the map, whichever view the pointer is over).
                // The Probe tool drops one on the ground clicked in 3D.
                if self.tool == Tool::Probe
                    && let Some(at) = self.grass_view.clicked_ground.take()
                {
                    let ctx = ui.ctx().clone();
                    self.add_probe(&ctx, at);
                }
                let hover = self.grass_view.hover_ground;
                if hover.is_some() || self.settings.central == Central::Grass {
                    self.map.cursor_world = hover;
                }
            }
            None => {
                ui.centered_and_justified(|ui| {
                    ui.label("The 3D grass view needs a GPU device (wgpu), and none is in use.");
                });
            }
        }
    }

    /// Submits the GPU work the simulation thread has handed over, in order.
    fn submit_gpu_work(&self) {
        if let (Some(rx), Some(rs)) = (&self.gpu.submissions, &self.gpu.render_state) {
            while let Ok((cb, ack)) = rx.try_recv() {
                rs.queue.submit([cb]);
                let _ = ack.send(());
            }
        }
    }

    /// Where the live wind should run; the running field is handed over.
    pub fn set_backend(&mut self, choice: Backend) {
        self.settings.backend = choice;
        self.live.set_backend(choice);
    }

    /// Screen position of a world point in the map view (as of the last frame).
    pub fn screen_pos(&self, world: doc::Vec2) -> Pos2 {
        self.map.camera.map_or(self.map.rect.center(), |c| {
            c.to_screen(self.map.rect, world)
        })
    }

    /// The window's title: the file's name, or the layout's when it has no file yet (the
    /// bundled default, a new layout).
    pub fn title(&self) -> String {
        let what = match self.doc.path() {
            Some(_) => self.doc.path_label(),
            None if self.doc.name.trim().is_empty() => "untitled".into(),
            None => self.doc.name.clone(),
        };
        format!(
            "{}{what} — windloom",
            if self.doc.is_dirty() { "● " } else { "" }
        )
    }

    fn say(&mut self, ctx: &egui::Context, text: impl Into<String>) {
        self.message = Some((text.into(), ctx.input(|i| i.time)));
    }

    /// Shows `text` in the status bar from the next frame on, for as long as every status
    /// message shows: for what is found before the window shows (a slow first frame would
    /// otherwise use up its time).
    pub fn tell(&mut self, text: impl Into<String>) {
        self.message = Some((text.into(), f64::INFINITY));
    }

    /// Applies an edit as one undo step.
    pub fn edit(&mut self, ctx: &egui::Context, e: Edit) -> bool {
        let r = self.doc.apply(e);
        self.edited(ctx, r)
    }

    /// Applies an edit that continues a gesture (a drag, a slider): one undo step in all.
    pub fn edit_merged(&mut self, ctx: &egui::Context, e: Edit, key: impl std::hash::Hash) -> bool {
        let r = self.doc.apply_merged(e, gesture_key(key));
        self.edited(ctx, r)
    }

    /// Notes an applied edit, or tells the user why it was refused.
    fn edited(&mut self, ctx: &egui::Context, r: Result<(), doc::EditError>) -> bool {
        match r {
            Ok(()) => true,
            Err(err) => {
                self.say(ctx, err.to_string());
                false
            }
        }
    }

    pub fn undo(&mut self) {
        if self.doc.undo() {
            self.prune_selection();
        }
    }

    pub fn redo(&mut self) {
        if self.doc.redo() {
            self.prune_selection();
        }
    }

    fn prune_selection(&mut self) {
        let doc = &self.doc;
        self.selection.retain(|s| match *s {
            Sel::Node(id) => doc.nodes().any(|(_, n)| n.id == id),
            Sel::Tree(id) => doc.trees.iter().any(|t| t.id == id),
            Sel::Obstacle(id) => doc.obstacles.iter().any(|o| o.id == id),
            Sel::Ambient(id) => doc.ambient.iter().any(|a| a.id == id),
            Sel::Probe(id) => doc.probes.iter().any(|p| p.id == id),
            Sel::Backdrop => doc.world.map.is_some(),
        });
    }

    /// Deletes the selection (nodes with their subtrees, whole trees for roots, obstacles,
    /// ambient layers) as one undo step; asks first when it would remove many points.
    pub fn delete_selection(&mut self, ctx: &egui::Context, confirmed: bool) {
        let sel = self.selection.clone();
        let mut count = 0;
        let mut edits = Vec::new();
        let roots: Vec<u32> = self.doc.trees.iter().map(|t| t.root.id).collect();
        for s in &sel {
            match *s {
                Sel::Node(id) => {
                    // Skip nodes inside a subtree that is deleted anyway.
                    if sel.iter().any(|o| match *o {
                        Sel::Node(a) if a != id => self
                            .doc
                            .trees
                            .iter()
                            .filter_map(|t| t.root.find(a))
                            .any(|n| n.find(id).is_some()),
                        Sel::Tree(t) => self
                            .doc
                            .trees
                            .iter()
                            .any(|tr| tr.id == t && tr.root.find(id).is_some()),
                        _ => false,
                    }) {
                        continue;
                    }
                    if roots.contains(&id) {
                        if let Some(t) = self.doc.trees.iter().find(|t| t.root.id == id) {
                            count += t.root.count();
                            edits.push(Edit::RemoveTree { id: t.id });
                        }
                    } else if let Some(n) = self.doc.trees.iter().find_map(|t| t.root.find(id)) {
                        count += n.count();
                        edits.push(Edit::RemoveNode { id });
                    }
                }
                Sel::Tree(id) => {
                    if let Some(t) = self.doc.trees.iter().find(|t| t.id == id)
                        && !sel.contains(&Sel::Node(t.root.id))
                    {
                        count += t.root.count();
                        edits.push(Edit::RemoveTree { id });
                    }
                }
                Sel::Obstacle(id) => edits.push(Edit::RemoveObstacle { id }),
                Sel::Ambient(id) => edits.push(Edit::RemoveAmbient { id }),
                Sel::Probe(id) => edits.push(Edit::RemoveProbe { id }),
                Sel::Backdrop => {
                    let mut w = self.doc.world.clone();
                    if w.map.take().is_some() {
                        edits.push(Edit::SetWorld(w));
                    }
                }
            }
        }
        if edits.is_empty() {
            return;
        }
        if count > 8 && !confirmed {
            self.dialog = Some(Dialog::ConfirmDelete { count, sel });
            return;
        }
        if self.edit(ctx, Edit::Batch(edits)) {
            self.selection.clear();
        }
    }

    /// Duplicates the selected subtrees (beside their originals), trees and obstacles.
    pub fn duplicate_selection(&mut self, ctx: &egui::Context) {
        let offset = 3.0;
        let mut next = self.doc.next_id();
        let mut fresh = |n: &doc::Node| -> doc::Node {
            fn copy(n: &doc::Node, next: &mut u32, d: f32) -> doc::Node {
                let id = *next;
                *next += 1;
                doc::Node {
                    id,
                    pos: [n.pos[0] + d, n.pos[1] + d],
                    strength: n.strength,
                    radius: n.radius,
                    children: n.children.iter().map(|c| copy(c, next, d)).collect(),
                    keys: n.keys.clone(),
                }
            }
            copy(n, &mut next, offset)
        };
        let mut edits = Vec::new();
        let mut new_sel = Vec::new();
        for s in self.selection.clone() {
            match s {
                Sel::Node(id) => {
                    if let Some(t) = self.doc.trees.iter().find(|t| t.root.id == id) {
                        let root = fresh(&t.root);
                        new_sel.push(Sel::Node(root.id));
                        let mut tree = t.clone();
                        tree.root = root;
                        tree.name = format!("{} copy", t.name);
                        edits.push((Some(tree), None, None));
                    } else if let Some((parent, _)) =
                        self.doc.trees.iter().find_map(|t| t.root.parent_of(id))
                    {
                        let node = parent.children.iter().find(|c| c.id == id).map(&mut fresh);
                        if let Some(node) = node {
                            new_sel.push(Sel::Node(node.id));
                            edits.push((None, Some((parent.id, node)), None));
                        }
                    }
                }
                Sel::Obstacle(id) => {
                    if let Some(o) = self.doc.obstacles.iter().find(|o| o.id == id) {
                        let mut o = o.clone();
                        // Named apart from the original in the Layers list, as a tree's
                        // copy is.
                        o.name = format!("{} copy", o.name);
                        o.shape.translate([offset, offset], self.doc.bounds());
                        edits.push((None, None, Some(o)));
                    }
                }
                _ => {}
            }
        }
        let mut batch = Vec::new();
        for (tree, node, obstacle) in edits {
            if let Some(mut t) = tree {
                t.id = next;
                next += 1;
                batch.push(Edit::AddTree {
                    index: self.doc.trees.len() + batch.len(),
                    tree: t,
                });
            }
            if let Some((parent, node)) = node {
                batch.push(Edit::AddNode {
                    parent,
                    index: usize::MAX,
                    node,
                });
            }
            if let Some(mut o) = obstacle {
                o.id = next;
                next += 1;
                new_sel.push(Sel::Obstacle(o.id));
                batch.push(Edit::AddObstacle {
                    index: usize::MAX,
                    obstacle: o,
                });
            }
        }
        if !batch.is_empty() && self.edit(ctx, Edit::Batch(batch)) {
            self.selection = new_sel;
        }
    }

    fn snap(&self, p: doc::Vec2) -> doc::Vec2 {
        if !self.settings.snap {
            return p;
        }
        let s = self.settings.snap_step.max(0.01);
        [(p[0] / s).round() * s, (p[1] / s).round() * s]
    }

    fn shortcuts(&mut self, ctx: &egui::Context) {
        use egui::{Key, KeyboardShortcut as KS, Modifiers as M};
        // A dialog open (a question, a path being typed): its keys are its own, never a tool
        // switch or an edit behind it.
        if self.dialog.is_some() {
            return;
        }
        let typing = ctx.egui_wants_keyboard_input();
        let pressed = |s: KS| ctx.input_mut(|i| i.consume_shortcut(&s));
        if pressed(KS::new(M::COMMAND | M::SHIFT, Key::Z)) || pressed(KS::new(M::COMMAND, Key::Y)) {
            self.redo();
        }
        if pressed(KS::new(M::COMMAND, Key::Z)) {
            self.undo();
        }
        if pressed(KS::new(M::COMMAND | M::SHIFT, Key::S)) {
            self.save_as(ctx);
        }
        if pressed(KS::new(M::COMMAND, Key::S)) {
            self.save(ctx);
        }
        if pressed(KS::new(M::COMMAND, Key::O)) {
            self.request(ctx, Pending::Open(None));
        }
        if pressed(KS::new(M::COMMAND, Key::N)) {
            self.request(ctx, Pending::New);
        }
        if pressed(KS::new(M::COMMAND, Key::D)) {
            self.duplicate_selection(ctx);
        }
        if typing {
            return;
        }
        if pressed(KS::new(M::NONE, Key::Delete)) || pressed(KS::new(M::NONE, Key::Backspace)) {
            self.delete_selection(ctx, false);
        }
        if pressed(KS::new(M::NONE, Key::K)) {
            // The time shown: the one scrubbed to, even while it is being recomputed.
            let (t, _) = self.live.time_shown();
            self.add_key_at(ctx, t);
        }
        if pressed(KS::new(M::NONE, Key::F)) {
            // The selection, or the whole world with nothing selected.
            self.focus_selection();
        }
        if pressed(KS::new(M::COMMAND, Key::A)) {
            self.select_all();
        }
        if pressed(KS::new(M::NONE, Key::Space)) {
            let p = !self.live.playing;
            self.live.set_playing(p);
        }
        if pressed(KS::new(M::NONE, Key::Escape)) {
            if self.map.polygon.is_empty() {
                self.selection.clear();
            } else {
                self.map.polygon.clear();
            }
        }
        for t in Tool::ALL {
            if pressed(KS::new(M::NONE, t.key())) {
                self.tool = t;
                self.map.polygon.clear();
            }
        }
        if self.tool == Tool::Paint {
            // The brush's size, by steps of a quarter.
            let r = &mut self.brush_radius;
            if pressed(KS::new(M::NONE, Key::OpenBracket)) {
                *r = (*r / 1.25).clamp(*paint::RADIUS.start(), *paint::RADIUS.end());
            }
            if pressed(KS::new(M::NONE, Key::CloseBracket)) {
                *r = (*r * 1.25).clamp(*paint::RADIUS.start(), *paint::RADIUS.end());
            }
        }
        self.clipboard_events(ctx);
        // The arrow keys nudge the selection (by the snap step, ten with Shift) and pan the
        // map when nothing selected can move.
        let step = self.settings.snap_step.max(0.01)
            * if ctx.input(|i| i.modifiers.shift) {
                10.0
            } else {
                1.0
            };
        let keys = [
            (Key::ArrowLeft, [-1.0, 0.0]),
            (Key::ArrowRight, [1.0, 0.0]),
            (Key::ArrowUp, [0.0, -1.0]),
            (Key::ArrowDown, [0.0, 1.0]),
        ];
        let mut nudged = false;
        if !self.selection.is_empty() {
            for (key, d) in keys {
                let times = ctx.input(|i| {
                    (i.events.iter())
                        .filter(|e| matches!(e, egui::Event::Key { key: k, pressed: true, .. } if *k == key))
                        .count()
                });
                for _ in 0..times {
                    nudged |= map::nudge_selection(self, ctx, [d[0] * step, d[1] * step]);
                }
            }
        }
        if nudged || !self.selection.is_empty() && self.can_nudge() {
            return;
        }
        let pan = 40.0;
        for (key, d) in keys {
            if ctx.input(|i| i.key_down(key)) {
                if let Some(c) = &mut self.map.camera {
                    let d = egui::vec2(-d[0], -d[1]) * pan;
                    c.pan_pixels(d * ctx.input(|i| i.stable_dt).min(0.1) * 10.0);
                }
                ctx.request_repaint();
            }
        }
    }

    /// Whether `sel` belongs to a locked tree, obstacle or ambient layer (the inspector then
    /// shows it without changing it).
    pub fn locked(&self, sel: Option<Sel>) -> bool {
        let doc = &self.doc;
        match sel {
            Some(Sel::Node(id)) => {
                (doc.trees.iter()).any(|t| t.locked && t.root.find(id).is_some())
            }
            Some(Sel::Tree(id)) => doc.trees.iter().any(|t| t.id == id && t.locked),
            Some(Sel::Obstacle(id)) => doc.obstacles.iter().any(|o| o.id == id && o.locked),
            Some(Sel::Ambient(id)) => doc.ambient.iter().any(|a| a.id == id && a.locked),
            Some(Sel::Probe(_) | Sel::Backdrop) => false,
            None => false,
        }
    }

    /// Whether anything selected moves with the arrow keys (not locked, not hidden, not an
    /// ambient layer).
    fn can_nudge(&self) -> bool {
        self.selection.iter().any(|s| match *s {
            Sel::Node(id) => {
                (self.doc.trees.iter()).any(|t| t.pickable() && t.root.find(id).is_some())
            }
            Sel::Tree(id) => self.doc.trees.iter().any(|t| t.id == id && t.pickable()),
            Sel::Obstacle(id) => self
                .doc
                .obstacles
                .iter()
                .any(|o| o.id == id && o.pickable()),
            Sel::Ambient(_) => false,
            Sel::Probe(_) => true,
            Sel::Backdrop => self.doc.world.map.is_some(),
        })
    }
}

impl eframe::App for EditorApp {
    fn raw_input_hook(&mut self, ctx: &egui::Context, raw_input: &mut egui::RawInput) {
        self.pacer.pace_raw(ctx, raw_input);
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();

        let started = std::time::Instant::now();
        // A press while a menu or popup is open closes it and does nothing else: it never
        // reaches the map or the 3D view (until its release).
        if ctx.input(|i| i.pointer.any_pressed()) && egui::Popup::is_any_open(&ctx) {
            self.map.swallowed = true;
        }
        self.grass_view.swallowed = self.map.swallowed;
        self.submit_gpu_work();
        let now = ctx.input(|i| i.time);
        if let Some((_, at)) = &mut self.message
            && at.is_infinite()
        {
            *at = now;
        }
        let dt = ctx.input(|i| i.stable_dt);
        self.frame_ms = self.frame_ms * 0.9 + dt * 1000.0 * 0.1;
        // A frame's second pass (egui runs one when something changed size, such as the
        // status bar's text) comes at the same time as its first: it keeps the first pass's
        // verdict rather than read as a frame that came at once, which woke a resting editor.
        if ctx.current_pass_index() == 0 {
            self.idle = now - self.last_frame_at > IDLE_GAP;
            self.last_frame_at = now;
        }

        // Closing the window with unsaved changes asks first.
        if ctx.input(|i| i.viewport().close_requested()) && !self.allow_close && self.doc.is_dirty()
        {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.dialog = Some(Dialog::Discard {
                then: Pending::Quit,
            });
        }

        // A gesture (drag, slider) ends when the pointer is released and no field is focused.
        if !ctx.input(|i| i.pointer.any_down()) && ctx.memory(|m| m.focused().is_none()) {
            self.doc.end_gesture();
        }

        self.shortcuts(&ctx);
        panels::menu_bar(self, ui);
        panels::disk_banner(self, ui);
        panels::status_bar(self, ui);
        panels::layers_panel(self, ui);
        inspector::inspector_panel(self, ui);
        {
            let snap = self.live.snapshot();
            self.probe_log.record(&self.doc, &snap);
            self.keep_in_range();
        }
        probes::panel(self, ui);
        timeline::panel(self, ui);
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE.fill(egui::Color32::from_gray(24)))
            .show(ui, |ui| match self.settings.central {
                Central::Map => map::map_view(self, ui),
                Central::Grass => self.grass(ui),
                Central::Split => {
                    let half = (ui.available_width() / 2.0).floor();
                    let h = ui.available_height();
                    // Each pane lays out top-down (the grass controls above the 3D view):
                    // a child of the row would inherit its left-to-right layout.
                    let down = egui::Layout::top_down(egui::Align::Min);
                    // The panes touch; inside each the spacing is the usual one (the 3D
                    // view's row of toggles ran its ticks into the labels before them).
                    let spacing = ui.spacing().item_spacing.x;
                    ui.horizontal_top(|ui| {
                        ui.spacing_mut().item_spacing.x = 0.0;
                        ui.allocate_ui_with_layout(egui::vec2(half, h), down, |ui| {
                            ui.spacing_mut().item_spacing.x = spacing;
                            map::map_view(self, ui);
                        });
                        ui.allocate_ui_with_layout(ui.available_size(), down, |ui| {
                            ui.spacing_mut().item_spacing.x = spacing;
                            self.grass(ui);
                        });
                    });
                }
            });
        panels::dialogs(self, &ctx);
        panels::guide_window(&mut self.guide, &ctx);
        self.export.ui(&ctx, &self.doc);
        if let Some(news) = self.export.take_live_news() {
            self.say(&ctx, news);
        }

        if self.doc.take_changed() {
            self.live.set_layout(&self.doc);
            self.export.edited(now);
        }
        // Every viewport command requests another frame: send the title only when it changes,
        // or an idle editor would redraw forever.
        let title = self.title();
        if self.sent_title.as_deref() != Some(title.as_str()) {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.sent_title = Some(title);
        }
        // Unsaved work is autosaved every AUTOSAVE_SECONDS while the editor works, and at
        // once when it comes to rest (the frame a second after the last activity), so a
        // resting editor needs no frame to autosave: it draws nothing at all (a frame every
        // 20 s to autosave took 1-2 % of a core on a software adapter).
        self.autosave(&ctx, now, self.idle);
        // A resting editor takes a status message down when its time is up.
        let wake = |at: f64| {
            let wait = (at - now).max(0.0);
            ctx.request_repaint_after(std::time::Duration::from_secs_f64(wait));
        };
        if let Some((_, at)) = &self.message
            && now - at < MESSAGE_SECONDS
        {
            wake(at + MESSAGE_SECONDS);
        }
        // The file on disk: looked at on the frames there are (at most once a second), and
        // by the poller's thread, which wakes an idle editor only when the file changed.
        self.doc.watch_disk(now);
        if self.live.playing {
            ctx.request_repaint();
        }
        if !self.idle {
            // Should this be the last frame for a while, one more once the editor has rested,
            // so the status bar says so (frames that come sooner make this one moot).
            ctx.request_repaint_after(std::time::Duration::from_secs_f64(IDLE_GAP * 1.1));
        }
        self.submit_gpu_work();
        if ctx.input(|i| i.pointer.any_released() || !i.pointer.any_down()) {
            self.map.swallowed = false;
        }
        let ui_ms = started.elapsed().as_secs_f32() * 1e3;
        self.ui_ms = if self.ui_ms == 0.0 {
            ui_ms
        } else {
            self.ui_ms * 0.9 + ui_ms * 0.1
        };
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, SETTINGS_KEY, &self.settings_to_save());
    }

    fn on_exit(&mut self) {
        self.export.shutdown();
        if !self.doc.is_dirty() {
            self.doc.remove_recovery();
        }
    }
}

/// Whether a file dialog that returned nothing did so too fast for a person to have
/// cancelled it: it could not open at all (no desktop portal, no display server support).
fn native_dialog_failed(started: std::time::Instant) -> bool {
    started.elapsed() < std::time::Duration::from_millis(150)
}

/// A stable number for a gesture key (slider, drag) so its edits merge into one undo step.
pub fn gesture_key(key: impl std::hash::Hash) -> u64 {
    use std::hash::Hasher;
    let mut h = std::hash::DefaultHasher::new();
    key.hash(&mut h);
    h.finish()
}

/// How the command line starts the editor.
#[derive(Debug, Clone, Default)]
pub struct Launch {
    /// The layout's file (read from it, or to be saved there when it does not exist yet).
    pub path: Option<PathBuf>,
    /// Where the live wind runs, for this run (`--backend`).
    pub backend: Option<Backend>,
    /// The view to open on (`--view`).
    pub view: Option<Central>,
    /// Shown in the status bar at first.
    pub note: Option<String>,
}

/// Opens the editor window on `doc` as `launch` says. The wgpu device is created with the
/// features and limits the simulation passes need, so one device can serve the UI and the
/// wind.
pub fn run(doc: Layout, launch: Launch) -> eframe::Result {
    let mut options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1400.0, 860.0])
            .with_min_inner_size([800.0, 500.0])
            .with_title("windloom"),
        persist_window: true,
        ..Default::default()
    };
    if let egui_wgpu::WgpuSetup::CreateNew(create) = &mut options.wgpu_options.wgpu_setup {
        create.device_descriptor = std::sync::Arc::new(crate::gpu::device_descriptor);
    }
    eframe::run_native(
        "windloom",
        options,
        Box::new(move |cc| Ok(Box::new(EditorApp::from_creation_context(cc, doc, launch)))),
    )
}

use eframe::egui_wgpu;
