//! Menus, toolbar, layers, status bar and dialogs (the inspector is `inspector.rs`).

use super::context_menu::{self, Target};
use super::view::WindView;
use super::{Dialog, EditorApp, Pending, Sel, Tool};
use crate::doc::{self, AmbientKind, Edit, TreeProps};
use eframe::egui::{self, RichText};

pub fn menu_bar(app: &mut EditorApp, ui: &mut egui::Ui) {
    let mut in_row = false;
    let ctx = ui.ctx().clone();
    egui::Panel::top("menu").show(ui, |ui| {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| file_menu(app, &ctx, ui));
            ui.menu_button("Edit", |ui| edit_menu(app, &ctx, ui));
            ui.menu_button("View", |ui| view_menu(app, ui));
            ui.menu_button("Presets", |ui| super::presets::presets_menu(app, &ctx, ui));
            ui.menu_button("Help", |ui| help_menu(app, ui));
            ui.separator();
            if ui.available_width() >= app.toolbar_width {
                app.toolbar_width = ui.scope(|ui| toolbar(app, ui)).response.rect.width();
                in_row = true;
            }
        });
    });
    // A narrow window: the toolbar wraps in a panel of its own rather than running off the
    // right edge (the view buttons went first).
    if !in_row {
        egui::Panel::top("toolbar").show(ui, |ui| {
            // Styled as in the menu bar.
            ui.visuals_mut().button_frame = false;
            ui.horizontal_wrapped(|ui| toolbar(app, ui));
        });
    }
}

/// File: new, open (dialog, typed path, recent), save (dialog, typed path), export, quit.
fn file_menu(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    if ui.button("New").clicked() {
        app.request(ctx, Pending::New);
    }
    if ui.button("Open…").clicked() {
        app.request(ctx, Pending::Open(None));
    }
    if ui
        .button("Open path…")
        .on_hover_text("Type the path of a layout (no system file dialog)")
        .clicked()
    {
        app.request(ctx, Pending::OpenTyped);
    }
    ui.menu_button("Open Recent", |ui| {
        if app.settings.recent.is_empty() {
            ui.weak("No recent files");
        }
        for p in app.settings.recent.clone() {
            if ui.button(p.display().to_string()).clicked() {
                app.request(ctx, Pending::Open(Some(p)));
            }
        }
    });
    ui.separator();
    if ui.button("Save").clicked() {
        app.save(ctx);
    }
    if ui.button("Save As…").clicked() {
        app.save_as(ctx);
    }
    if ui
        .button("Save to path…")
        .on_hover_text("Type where to save (no system file dialog)")
        .clicked()
    {
        app.path_prompt(true, false);
    }
    ui.separator();
    if ui.button("Export/Bake…").clicked() {
        app.export.open = true;
        app.export.suggest_out(app.doc.path());
    }
    let mut live = app.export.live;
    if ui
        .checkbox(&mut live, "Live export")
        .on_hover_text(
            "Bake again into the Export dialog's folder, with its settings, after each edit; \
             engine scripts reload when the manifest's sequence changes",
        )
        .changed()
    {
        app.export.suggest_out(app.doc.path());
        app.export.set_live(live);
    }
    ui.separator();
    if ui.button("Quit").clicked() {
        app.request(ctx, Pending::Quit);
    }
}

/// Edit: undo and redo (named), delete, duplicate, snap.
fn edit_menu(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    let undo = app
        .doc
        .history()
        .undo_label()
        .map_or("Undo".to_string(), |l| format!("Undo {l}"));
    if ui
        .add_enabled(app.doc.history().can_undo(), egui::Button::new(undo))
        .clicked()
    {
        app.undo();
    }
    let redo = app
        .doc
        .history()
        .redo_label()
        .map_or("Redo".to_string(), |l| format!("Redo {l}"));
    if ui
        .add_enabled(app.doc.history().can_redo(), egui::Button::new(redo))
        .clicked()
    {
        app.redo();
    }
    ui.separator();
    let any = !app.selection.is_empty();
    if ui.add_enabled(any, egui::Button::new("Delete")).clicked() {
        app.delete_selection(ctx, false);
    }
    if ui
        .add_enabled(any, egui::Button::new("Duplicate"))
        .clicked()
    {
        app.duplicate_selection(ctx);
    }
    ui.separator();
    let shortcut = |ui: &egui::Ui, key| {
        ui.ctx()
            .format_shortcut(&egui::KeyboardShortcut::new(egui::Modifiers::COMMAND, key))
    };
    let cut = egui::Button::new("Cut").shortcut_text(shortcut(ui, egui::Key::X));
    if ui.add_enabled(any, cut).clicked() {
        app.cut_selection(ctx);
    }
    let copy = egui::Button::new("Copy").shortcut_text(shortcut(ui, egui::Key::C));
    if ui.add_enabled(any, copy).clicked() {
        app.copy_selection(ctx);
    }
    let paste = egui::Button::new("Paste").shortcut_text(shortcut(ui, egui::Key::V));
    if ui
        .add(paste)
        .on_hover_text("Pastes trees, obstacles and ambient layers copied from any layout")
        .clicked()
    {
        // The window's integration answers with a paste event carrying the clipboard's text.
        ctx.send_viewport_cmd(egui::ViewportCommand::RequestPaste);
    }
    ui.separator();
    if ui
        .button("New mask obstacle…")
        .on_hover_text("A grey image over the world to paint walls on: blank, or from a picture")
        .clicked()
    {
        app.new_image(super::new_image::Kind::Mask);
        ui.close();
    }
    if ui
        .button("New density map…")
        .on_hover_text(
            "Where the grass grows, to paint: blank (grass everywhere), or from a picture",
        )
        .clicked()
    {
        app.new_image(super::new_image::Kind::Density);
        ui.close();
    }
    ui.separator();
    let select_all = egui::Button::new("Select all").shortcut_text(shortcut(ui, egui::Key::A));
    if ui.add(select_all).clicked() {
        app.select_all();
        ui.close();
    }
    ui.horizontal(|ui| {
        ui.checkbox(&mut app.settings.snap, "Snap to")
            .on_hover_text("Points placed and moved land on this step; the arrow keys nudge by it");
        ui.add(
            egui::DragValue::new(&mut app.settings.snap_step)
                .range(SNAP_STEP)
                .speed(0.05)
                .suffix(" m"),
        )
        .on_hover_text("The snap step, metres (the arrow keys' nudge too)");
    });
}

/// The snap steps a designer may set, metres.
pub const SNAP_STEP: std::ops::RangeInclusive<f32> = 0.01..=1000.0;

/// View: the central view, arrows in 3D, the wind view and its scale, the backend, the grid.
fn view_menu(app: &mut EditorApp, ui: &mut egui::Ui) {
    for c in crate::app::Central::ALL {
        ui.radio_value(&mut app.settings.central, c, c.label());
    }
    ui.checkbox(&mut app.grass_view.controls.arrows, "Arrows in the 3D view")
        .on_hover_text(
            "The wind trees' arrows drawn over the grass (off: the grass as the \
             game will show it)",
        );
    ui.separator();
    for v in WindView::ALL {
        ui.radio_value(&mut app.settings.wind_view, v, v.label());
    }
    speed_scale_menu(app, ui);
    // How much of the backdrop shows through the wind's colours.
    let backdrop = app.doc.world.map.is_some();
    let mut auto = app.settings.map_wind_opacity.is_none();
    let mut o = super::map_wind_opacity(app.settings.map_wind_opacity, backdrop);
    ui.horizontal(|ui| {
        let l = ui.label("Colour opacity");
        let changed = ui
            .add(egui::Slider::new(&mut o, super::MAP_WIND_OPACITY).fixed_decimals(2))
            .labelled_by(l.id)
            .on_hover_text("How much the map's wind colours hide what is under them: the backdrop shows through the rest")
            .changed();
        if changed {
            auto = false;
        }
        if ui
            .checkbox(&mut auto, "auto")
            .on_hover_text(format!(
                "Opaque over a plain world, {:.0} % over a backdrop",
                super::MAP_WIND_OVER_BACKDROP * 100.0
            ))
            .changed()
            && auto
        {
            o = super::map_wind_opacity(None, backdrop);
        }
    });
    app.settings.map_wind_opacity = (!auto).then_some(o);
    ui.separator();
    ui.label("Wind runs on");
    let mut choice = app.settings.backend;
    for b in crate::engine::Backend::ALL {
        ui.radio_value(&mut choice, b, b.label());
    }
    if choice != app.settings.backend {
        app.set_backend(choice);
    }
    ui.separator();
    ui.checkbox(&mut app.settings.show_grid, "Grid lines");
    ui.checkbox(&mut app.settings.hill_shade, "Terrain hill shade")
        .on_hover_text("Shade the level's terrain on the map, lit from the north-west");
    ui.checkbox(&mut app.settings.contours, "Terrain contour lines")
        .on_hover_text(
            "Lines of equal height on the map, every 1, 2 or 5 metres times a power of ten",
        );
    if ui.button("Frame all (F)").clicked() {
        app.map.camera = None;
    }
}

/// Help: the user guide and the shortcuts.
fn help_menu(app: &mut EditorApp, ui: &mut egui::Ui) {
    if ui
        .button("User guide")
        .on_hover_text("docs/EDITOR.md: tools, views, files, shortcuts")
        .clicked()
    {
        app.guide.open = true;
    }
    if ui.button("Keyboard shortcuts").clicked() {
        app.dialog = Some(Dialog::Shortcuts);
    }
}

fn toolbar(app: &mut EditorApp, ui: &mut egui::Ui) {
    for t in Tool::ALL {
        let r = ui
            .selectable_label(app.tool == t, t.label())
            .on_hover_text(format!("{} ({:?})", t.hint(), t.key()));
        if r.clicked() {
            app.tool = t;
        }
    }
    if app.tool == Tool::Paint {
        use super::paint::Mark;
        let b = &mut app.settings.brush;
        for m in Mark::ALL {
            if ui
                .selectable_label(b.mark == m, m.label())
                .on_hover_text(m.hint())
                .clicked()
            {
                b.mark = m;
            }
        }
        if b.mark == Mark::Brush {
            ui.add(
                egui::DragValue::new(&mut app.brush_radius)
                    .range(super::paint::RADIUS)
                    .speed(0.05)
                    .suffix(" m"),
            )
            .on_hover_text("The brush's radius ([ and ])");
            let mut hard = b.hardness * 100.0;
            if ui
                .add(
                    egui::DragValue::new(&mut hard)
                        .range(0.0..=100.0)
                        .speed(1.0)
                        .prefix("hard ")
                        .suffix("%"),
                )
                .on_hover_text(
                    "Hardness: the share of the radius painted at full strength (100%: a hard \
                     edge; 0%: soft all the way)",
                )
                .changed()
            {
                b.hardness = hard / 100.0;
            }
        }
        let mut opacity = b.opacity * 100.0;
        if ui
            .add(
                egui::DragValue::new(&mut opacity)
                    .range(1.0..=100.0)
                    .speed(1.0)
                    .prefix("opacity ")
                    .suffix("%"),
            )
            .on_hover_text(
                "How far a stroke moves the pixels toward the paint (a stroke never builds up \
                 past it, however often it passes)",
            )
            .changed()
        {
            b.opacity = opacity / 100.0;
        }
    }
    if app.tool == Tool::Stroke {
        let s = &mut app.settings.stroke;
        ui.add(
            egui::DragValue::new(&mut s.strength)
                .range(0.0..=crate::doc::bounds::STRENGTH.max)
                .speed(0.1)
                .suffix(" m/s"),
        )
        .on_hover_text("The stroke's arrows' strength");
        ui.add(
            egui::DragValue::new(&mut s.radius)
                .range(0.5..=200.0)
                .speed(0.05)
                .suffix(" m"),
        )
        .on_hover_text("The stroke's arrows' radius; the path is kept to within a quarter of it");
    }
    ui.separator();
    let playing = app.live.playing;
    if ui
        .button(if playing { "Pause" } else { "Play" })
        .on_hover_text("Space")
        .clicked()
    {
        app.live.set_playing(!playing);
    }
    if ui
        .add_enabled(!playing, egui::Button::new("Step"))
        .clicked()
    {
        app.live.step_once();
    }
    if ui
        .button("Reset")
        .on_hover_text("Restart the wind from calm")
        .clicked()
    {
        app.live.reset();
    }
    let mut speed = app.live.speed;
    // Narrow: the toolbar shares the menus' row in a 1280-point window.
    let width = std::mem::replace(&mut ui.spacing_mut().slider_width, 60.0);
    let slider = ui
        .add(
            egui::Slider::new(&mut speed, 0.1..=4.0)
                .logarithmic(true)
                .suffix("×"),
        )
        .on_hover_text("Simulation speed: simulated seconds per second");
    ui.spacing_mut().slider_width = width;
    if slider.changed() {
        app.live.set_speed(speed);
    }
    ui.separator();
    let l = ui.label("Wind:");
    egui::ComboBox::from_id_salt("wind view")
        .selected_text(app.settings.wind_view.label())
        .show_ui(ui, |ui| {
            for v in WindView::ALL {
                ui.selectable_value(&mut app.settings.wind_view, v, v.label());
            }
        })
        .response
        .labelled_by(l.id);
    ui.separator();
    for c in crate::app::Central::ALL {
        if ui
            .selectable_label(app.settings.central == c, c.label())
            .on_hover_text("What the central area shows")
            .clicked()
        {
            app.settings.central = c;
        }
    }
}

pub fn status_bar(app: &mut EditorApp, ui: &mut egui::Ui) {
    let ctx = ui.ctx().clone();
    let r = egui::Panel::bottom("status").show(ui, |ui| {
        ui.horizontal(|ui| {
            match app.map.cursor_world {
                Some(p) => {
                    ui.label(format!("x {:.1} m  z {:.1} m", p[0], p[1]));
                    let v = app.live.with_snapshot(|s| s.velocity_at(p));
                    match v {
                        Some(v) => ui.label(format!("wind {:.2} m/s", v[0].hypot(v[1]))),
                        None => ui.label("outside the grid"),
                    };
                }
                None => {
                    ui.weak(if app.settings.central == super::Central::Grass {
                        "cursor off the ground"
                    } else {
                        "cursor off the map"
                    });
                }
            }
            ui.separator();
            let snap = app.live.snapshot();
            ui.label(format!("t = {:.2} s", snap.time));
            let rate = if app.idle {
                "idle".to_string()
            } else {
                format!("{:.0} fps", 1000.0 / app.frame_ms.max(0.1))
            };
            let timing = ui.label(format!(
                "{} {:.1} ms/step · {rate}",
                snap.runs_on.label(),
                snap.ms_per_step,
            ));
            timing.on_hover_ui(|ui| frame_times(app, &snap, ui));
            if let Some(n) = &snap.notice {
                ui.colored_label(egui::Color32::from_rgb(255, 200, 80), n);
            }
            if let Some(e) = &app.doc.recovery_error {
                ui.colored_label(egui::Color32::from_rgb(255, 110, 90), "autosave failed")
                    .on_hover_text(format!(
                        "Unsaved work is not being autosaved: {e}\nSave the layout (Ctrl+S) to keep it."
                    ));
            }
            if app.settings.central != crate::app::Central::Map && app.grass_view.blades > 0 {
                ui.separator();
                let ms = app.grass_view.frame_ms.lock().map(|m| *m).unwrap_or(0.0);
                let g = &app.grass_view;
                let n = super::grass_controls::grouped;
                let drawn = if g.blades < g.total_blades {
                    format!("{} of {}", n(g.blades), n(g.total_blades))
                } else {
                    n(g.blades)
                };
                let (text, hover) = match g.layout_blades {
                    Some(all) => (
                        format!(
                            "{drawn} blades (the GPU holds {} of the layout's ~{})",
                            n(g.total_blades),
                            n(all)
                        ),
                        Some(
                            "The layout has more blades than this GPU's storage buffers hold: \
                             they are drawn evenly thinned to fit",
                        ),
                    ),
                    None => (
                        format!("{drawn} blades"),
                        (g.blades < g.total_blades)
                            .then_some("A software adapter draws an even sample of the blades"),
                    ),
                };
                let label = ui.label(format!("{text} · grass {ms:.1} ms"));
                if let Some(hover) = hover {
                    label.on_hover_text(hover);
                }
            }
            ui.separator();
            ui.label(&app.gpu.adapter);
            if let Some((msg, at)) = &app.message
                && ctx.input(|i| i.time) - at < super::MESSAGE_SECONDS {
                    ui.separator();
                    // Cut with "…" where the bar runs out (the whole text on hover).
                    ui.add(
                        egui::Label::new(
                            egui::RichText::new(msg).color(egui::Color32::from_rgb(255, 200, 80)),
                        )
                        .truncate(),
                    );
                }
        });
    });
    app.status_rect = r.response.rect;
}

/// The status bar's timing tooltip: where a frame's time goes.
fn frame_times(app: &EditorApp, snap: &crate::engine::live::Snapshot, ui: &mut egui::Ui) {
    egui::Grid::new("frame times")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("frame interval");
            ui.label(format!("{:.1} ms", app.frame_ms));
            ui.end_row();
            ui.label("UI (CPU, this editor's work)");
            ui.label(format!("{:.2} ms", app.ui_ms));
            ui.end_row();
            ui.label(format!("sim step ({}, wall)", snap.runs_on.label()));
            ui.label(format!("{:.2} ms", snap.ms_per_step));
            ui.end_row();
            ui.label("sim step (GPU timestamps)");
            ui.label(match snap.gpu_ms_per_step {
                Some(ms) => format!("{ms:.2} ms"),
                None => "—".into(),
            });
            ui.end_row();
            if let Some([cpu, gpu]) = snap.measured {
                ui.label(format!("measured at {}×{}", snap.nx, snap.ny));
                ui.label(format!("CPU {cpu:.2} ms, GPU {gpu:.2} ms a step"));
                ui.end_row();
            }
            ui.label("wind drawn");
            ui.label(match (snap.field.is_some(), app.gpu.map_on_gpu) {
                (true, true) => "on the GPU, from the solver's buffers",
                (false, true) => "on the GPU, from each snapshot uploaded",
                _ => "by egui, from CPU snapshots",
            });
            ui.end_row();
            // The memory the timeline holds to scrub back with, and its cap.
            let (n, bytes) = snap.history;
            ui.label("timeline history");
            ui.label(format!(
                "{n} states of the wind, {:.0} of {} MB (an edit forgets them)",
                bytes as f64 / 1e6,
                crate::engine::live::CHECKPOINT_BUDGET >> 20
            ));
            ui.end_row();
        });
}

/// The widths the Layers list may take, points.
pub const LAYERS_WIDTH: std::ops::RangeInclusive<f32> = 180.0..=420.0;

pub fn layers_panel(app: &mut EditorApp, ui: &mut egui::Ui) {
    let ctx = ui.ctx().clone();
    egui::Panel::left("layers")
        .resizable(true)
        .default_size(262.0)
        .size_range(LAYERS_WIDTH)
        .show(ui, |ui| {
            // The panel keeps its width as layers come and go (see the inspector's).
            egui::ScrollArea::both()
                .auto_shrink([false, false])
                .show(ui, |ui| {
                    ui.heading("Layers");
                    ui.add_space(4.0);
                    // A right-click menu's choice, done once the list is drawn.
                    let mut menu = None;
                    if let Some(image) = app.doc.world.map.as_ref().map(|m| m.image.clone()) {
                        egui::CollapsingHeader::new(RichText::new("Backdrop").strong())
                            .default_open(true)
                            .show(ui, |ui| {
                                let sel = app.selection.contains(&Sel::Backdrop);
                                let name = std::path::Path::new(&image)
                                    .file_name()
                                    .map_or(image.clone(), |n| n.to_string_lossy().into_owned());
                                let r = layer_name(ui, sel, name)
                                    .on_hover_text("Select it to move and scale it on the map");
                                let target = Target::Item(Sel::Backdrop);
                                r.context_menu(|ui| {
                                    menu =
                                        context_menu::entries(app, ui, target).map(|a| (target, a))
                                });
                                if r.clicked() {
                                    app.selection = vec![Sel::Backdrop];
                                    app.tool = Tool::Select;
                                }
                            });
                    }
                    egui::CollapsingHeader::new(RichText::new("Wind trees").strong())
                        .default_open(true)
                        .show(ui, |ui| trees_list(app, &ctx, ui));
                    egui::CollapsingHeader::new(RichText::new("Obstacles").strong())
                        .default_open(true)
                        .show(ui, |ui| {
                            let mut select = None;
                            let mut delete = None;
                            let mut flags = None;
                            for o in &app.doc.obstacles {
                                ui.horizontal(|ui| {
                                    // The buttons right-aligned, the name cut to what is left.
                                    ui.with_layout(right_to_left(), |ui| {
                                        if ui.small_button("×").on_hover_text("Delete").clicked() {
                                            delete = Some(o.id);
                                        }
                                        if let Some((hidden, locked)) =
                                            hide_and_lock(ui, o.hidden, o.locked)
                                        {
                                            let mut o = o.clone();
                                            o.hidden = hidden;
                                            o.locked = locked;
                                            flags = Some(Edit::SetObstacle { obstacle: o });
                                        }
                                        let sel = app.selection.contains(&Sel::Obstacle(o.id));
                                        let r = layer_name(ui, sel, o.name.clone());
                                        let target = Target::Item(Sel::Obstacle(o.id));
                                        r.context_menu(|ui| {
                                            menu = context_menu::entries(app, ui, target)
                                                .map(|a| (target, a))
                                        });
                                        if r.clicked() {
                                            select = Some(o.id);
                                        }
                                    });
                                });
                            }
                            if app.doc.obstacles.is_empty() {
                                ui.weak("Use the Circle or Polygon tool, or a mask:");
                            }
                            ui.menu_button("+ Add obstacle", |ui| {
                                if ui.button("Circle (C): drag on the map").clicked() {
                                    app.tool = Tool::Circle;
                                    ui.close();
                                }
                                if ui.button("Polygon (P): click its corners").clicked() {
                                    app.tool = Tool::Polygon;
                                    ui.close();
                                }
                                if ui
                                    .button("New mask…")
                                    .on_hover_text(
                                        "A grey image over the world to paint walls on: blank, or \
                                         from a picture of the level by a threshold",
                                    )
                                    .clicked()
                                {
                                    app.new_image(super::new_image::Kind::Mask);
                                    ui.close();
                                }
                            });
                            if let Some(id) = select {
                                app.selection = vec![Sel::Obstacle(id)];
                            }
                            if let Some(id) = delete {
                                app.edit(&ctx, Edit::RemoveObstacle { id });
                            }
                            if let Some(e) = flags {
                                app.edit(&ctx, e);
                            }
                        });
                    egui::CollapsingHeader::new(RichText::new("Ambient").strong())
                        .default_open(true)
                        .show(ui, |ui| ambient_list(app, &ctx, ui));
                    if let Some((target, action)) = menu {
                        context_menu::apply(app, &ctx, target, action);
                    }
                });
        });
}

/// A layer's hide and lock toggles (right to left: lock, then hide): an eye, crossed out and
/// faded when the layer is hidden, and a padlock, shut and lit when it is locked; the new
/// values when one was clicked.
fn hide_and_lock(ui: &mut egui::Ui, hidden: bool, locked: bool) -> Option<(bool, bool)> {
    let lock_tip = if locked {
        "Locked: the map does not pick or move it and the inspector does not change it. \
         Click to unlock"
    } else {
        "Lock: the map no longer picks or moves it, the inspector no longer changes it"
    };
    let hide_tip = if hidden {
        "Hidden: not drawn on the map or in 3D (it still acts on the wind). Click to show"
    } else {
        "Hide on the map and in 3D (it still acts on the wind)"
    };
    if icon_toggle(ui, "lock", locked, lock_tip, draw_lock) {
        return Some((hidden, !locked));
    }
    if icon_toggle(ui, "hide", hidden, hide_tip, draw_eye) {
        return Some((!hidden, locked));
    }
    None
}

/// A small toggle drawn by `draw` (painter, its square, on, ink), named `name` for screen
/// readers and tests; whether it was clicked.
fn icon_toggle(
    ui: &mut egui::Ui,
    name: &str,
    on: bool,
    tip: &str,
    draw: fn(&egui::Painter, egui::Rect, bool, egui::Color32),
) -> bool {
    let size = egui::vec2(16.0, ui.spacing().interact_size.y);
    let (rect, r) = ui.allocate_exact_size(size, egui::Sense::click());
    r.widget_info(|| egui::WidgetInfo::selected(egui::Role::CheckBox, ui.is_enabled(), on, name));
    let visuals = ui.style().interact(&r);
    let ink = if r.hovered() {
        visuals.fg_stroke.color
    } else if on {
        ui.visuals().selection.stroke.color
    } else {
        ui.visuals().weak_text_color()
    };
    let square = egui::Rect::from_center_size(rect.center(), egui::vec2(12.0, 12.0));
    draw(ui.painter(), square, on, ink);
    r.on_hover_text(tip).clicked()
}

/// An eye; crossed out when `hidden`.
fn draw_eye(p: &egui::Painter, r: egui::Rect, hidden: bool, ink: egui::Color32) {
    let c = r.center();
    let (w, h) = (r.width() / 2.0, r.height() * 0.3);
    let lid = |sign: f32| -> Vec<egui::Pos2> {
        (0..=12)
            .map(|k| {
                let t = k as f32 / 12.0 * 2.0 - 1.0;
                c + egui::vec2(t * w, sign * h * (1.0 - t * t))
            })
            .collect()
    };
    let stroke = egui::Stroke::new(1.2, ink);
    p.add(egui::Shape::line(lid(-1.0), stroke));
    p.add(egui::Shape::line(lid(1.0), stroke));
    p.circle_filled(c, h * 0.6, ink);
    if hidden {
        p.line_segment([r.left_bottom(), r.right_top()], stroke);
    }
}

/// A padlock: shut when `locked`, its shackle open otherwise.
fn draw_lock(p: &egui::Painter, r: egui::Rect, locked: bool, ink: egui::Color32) {
    let body = egui::Rect::from_min_max(
        egui::pos2(r.left() + 1.0, r.center().y),
        egui::pos2(r.right() - 1.0, r.bottom()),
    );
    p.rect_filled(body, 1.0, ink);
    let (cx, top) = (r.center().x, r.top() + 1.0);
    let rad = body.width() * 0.32;
    let lift = if locked { 0.0 } else { 2.5 };
    let shackle: Vec<egui::Pos2> = (0..=12)
        .map(|k| {
            let a = std::f32::consts::PI * (k as f32 / 12.0);
            egui::pos2(cx - rad * a.cos(), top + rad - rad * a.sin() - lift)
        })
        .collect();
    let stroke = egui::Stroke::new(1.4, ink);
    let (left, right) = (shackle[0], shackle[12]);
    p.add(egui::Shape::line(shackle, stroke));
    p.line_segment([left, egui::pos2(left.x, body.top())], stroke);
    if locked {
        p.line_segment([right, egui::pos2(right.x, body.top())], stroke);
    }
}

/// A layer row's buttons, laid out from the right edge leftwards.
fn right_to_left() -> egui::Layout {
    egui::Layout::right_to_left(egui::Align::Center)
}

/// A layer's name as a selectable button that fills the row's room and is cut with "…"
/// where it runs out (the whole name on hover): a long name never widens the panel.
fn layer_name(ui: &mut egui::Ui, selected: bool, name: String) -> egui::Response {
    // Left-aligned (the grow atom takes the room to its right), with a narrow padding so a
    // usual name is shown whole next to its buttons.
    ui.spacing_mut().button_padding.x = 2.0;
    let r = ui.add_sized(
        [ui.available_width(), ui.spacing().interact_size.y],
        egui::Button::selectable(selected, (name.clone(), egui::Atom::grow()))
            .truncate()
            .frame_when_inactive(false),
    );
    let font = egui::TextStyle::Button.resolve(ui.style());
    let colour = ui.visuals().text_color();
    let wide = ui
        .ctx()
        .fonts_mut(|f| f.layout_no_wrap(name.clone(), font, colour).size().x);
    if wide + 2.0 * ui.spacing().button_padding.x > r.rect.width() {
        r.on_hover_text(name)
    } else {
        r
    }
}

fn trees_list(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    let mut action: Option<Edit> = None;
    let mut select = None;
    let mut menu = None;
    for t in &app.doc.trees {
        ui.horizontal(|ui| {
            let mut enabled = t.enabled;
            if ui
                .checkbox(&mut enabled, "")
                .on_hover_text("Enabled")
                .changed()
            {
                let mut p = TreeProps::of(t);
                p.enabled = enabled;
                action = Some(Edit::SetTreeProps { id: t.id, props: p });
            }
            // The buttons right-aligned, the name cut to what is left.
            ui.with_layout(right_to_left(), |ui| {
                if ui.small_button("×").on_hover_text("Delete tree").clicked() {
                    action = Some(Edit::RemoveTree { id: t.id });
                }
                if let Some((hidden, locked)) = hide_and_lock(ui, t.hidden, t.locked) {
                    let mut p = TreeProps::of(t);
                    p.hidden = hidden;
                    p.locked = locked;
                    action = Some(Edit::SetTreeProps { id: t.id, props: p });
                }
                if ui
                    .small_button("S")
                    .on_hover_text("Solo: enable only this tree")
                    .clicked()
                {
                    let edits = app
                        .doc
                        .trees
                        .iter()
                        .map(|o| {
                            let mut p = TreeProps::of(o);
                            p.enabled = o.id == t.id;
                            Edit::SetTreeProps { id: o.id, props: p }
                        })
                        .collect();
                    action = Some(Edit::Batch(edits));
                }
                let sel = app.selection.contains(&Sel::Tree(t.id));
                let name = format!("{} ({})", t.name, t.root.count());
                let r = layer_name(ui, sel, name);
                let target = Target::Item(Sel::Tree(t.id));
                r.context_menu(|ui| {
                    menu = context_menu::entries(app, ui, target).map(|a| (target, a))
                });
                if r.clicked() {
                    select = Some(t.id);
                }
            });
        });
    }
    if app.doc.trees.is_empty() {
        ui.weak("Use Add root, then Add arrow");
    }
    if let Some(id) = select {
        app.selection = vec![Sel::Tree(id)];
    }
    if let Some(e) = action {
        app.edit(ctx, e);
    }
    if let Some((target, a)) = menu {
        context_menu::apply(app, ctx, target, a);
    }
}

fn ambient_list(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    let mut action = None;
    let mut select = None;
    let mut menu = None;
    for a in &app.doc.ambient {
        ui.horizontal(|ui| {
            let mut enabled = a.enabled;
            if ui
                .checkbox(&mut enabled, "")
                .on_hover_text("Enabled")
                .changed()
            {
                let mut l = a.clone();
                l.enabled = enabled;
                action = Some(Edit::SetAmbient { layer: l });
            }
            ui.with_layout(right_to_left(), |ui| {
                if ui.small_button("×").on_hover_text("Delete").clicked() {
                    action = Some(Edit::RemoveAmbient { id: a.id });
                }
                if let Some((hidden, locked)) = hide_and_lock(ui, a.hidden, a.locked) {
                    let mut l = a.clone();
                    l.hidden = hidden;
                    l.locked = locked;
                    action = Some(Edit::SetAmbient { layer: l });
                }
                let sel = app.selection.contains(&Sel::Ambient(a.id));
                let name = format!("{} ({})", a.name, a.kind.type_name());
                let r = layer_name(ui, sel, name);
                let target = Target::Item(Sel::Ambient(a.id));
                r.context_menu(|ui| {
                    menu = context_menu::entries(app, ui, target).map(|t| (target, t))
                });
                if r.clicked() {
                    select = Some(a.id);
                }
            });
        });
    }
    ui.menu_button("+ Add layer", |ui| {
        let id = app.doc.next_id();
        let make = |name: &str, kind| doc::AmbientLayer::new(id, name, kind);
        let layer = if ui.button("Directional with gusts").clicked() {
            Some(make(
                "Breeze",
                AmbientKind::Directional {
                    direction_deg: 0.0,
                    main: 2.0,
                    turbulence: 0.5,
                    pulse_magnitude: 0.3,
                    pulse_frequency: 0.2,
                },
            ))
        } else if ui.button("Scrolling noise").clicked() {
            Some(make(
                "Noise",
                AmbientKind::Noise {
                    direction_deg: 0.0,
                    scale: 15.0,
                    speed: 3.0,
                    strength: 3.0,
                },
            ))
        } else if ui.button("FFT gusts").clicked() {
            Some(make(
                "FFT gusts",
                AmbientKind::Fft {
                    direction_deg: 0.0,
                    wind_speed: 4.0,
                    amplitude: 1.5,
                    resolution: 64,
                    tile_size: 64.0,
                    seed: 1,
                },
            ))
        } else if ui.button("Sine").clicked() {
            Some(make(
                "Sine",
                AmbientKind::Sine {
                    direction_deg: 0.0,
                    amplitude: 2.0,
                    wavelength: 20.0,
                    frequency: 0.3,
                },
            ))
        } else {
            None
        };
        if let Some(layer) = layer {
            select = Some(layer.id);
            action = Some(Edit::AddAmbient {
                index: usize::MAX,
                layer,
            });
            ui.close();
        }
    });
    if let Some(id) = select {
        app.selection = vec![Sel::Ambient(id)];
    }
    if let Some(e) = action {
        app.edit(ctx, e);
    }
    if let Some((target, a)) = menu {
        context_menu::apply(app, ctx, target, a);
    }
}

pub fn dialogs(app: &mut EditorApp, ctx: &egui::Context) {
    let Some(dialog) = app.dialog.take() else {
        return;
    };
    let mut keep = true;
    let mut dialog = dialog;
    let modal = egui::Modal::new(egui::Id::unique("windloom dialog")).show(ctx, |ui| {
        ui.set_max_width(560.0);
        match &mut dialog {
            Dialog::Error { title, text } => {
                ui.heading(title);
                egui::ScrollArea::vertical()
                    .max_height(300.0)
                    .show(ui, |ui| {
                        ui.add(egui::Label::new(RichText::new(text.as_str()).monospace()).wrap());
                    });
                ui.label("The current document was kept.");
                if ui.button("OK").clicked() {
                    keep = false;
                }
            }
            Dialog::Discard { then } => {
                ui.heading("Unsaved changes");
                ui.label("Your changes to this layout are not saved.");
                ui.horizontal(|ui| {
                    if ui.button("Save").clicked() && app.save(ctx) {
                        keep = false;
                        app.run_pending(ctx, then.clone());
                    }
                    if ui.button("Discard changes").clicked() {
                        keep = false;
                        app.doc.discard_changes();
                        app.run_pending(ctx, then.clone());
                    }
                    if ui.button("Cancel").clicked() {
                        keep = false;
                    }
                });
            }
            Dialog::ConfirmDelete { count, sel } => {
                ui.heading("Delete?");
                ui.label(format!("This deletes {count} points."));
                ui.horizontal(|ui| {
                    if ui.button("Delete").clicked() {
                        keep = false;
                        app.selection = sel.clone();
                        app.delete_selection(ctx, true);
                    }
                    if ui.button("Cancel").clicked() {
                        keep = false;
                    }
                });
            }
            Dialog::Recover { found, text } => {
                ui.heading("Restore unsaved work?");
                ui.label(text.as_str());
                ui.horizontal(|ui| {
                    if ui.button("Restore").clicked() {
                        keep = false;
                        if let Err(e) = app.restore(found) {
                            app.dialog = Some(Dialog::Error {
                                title: "Could not restore".into(),
                                text: e,
                            });
                        }
                    }
                    if ui.button("Discard").clicked() {
                        keep = false;
                        found.remove();
                    }
                });
            }
            Dialog::Path { save, text, note } => {
                keep = path_dialog(app, ui, *save, text, note.as_ref());
            }
            Dialog::SavePreset {
                kind,
                name,
                refused,
            } => {
                keep = super::presets::save_dialog(app, ctx, ui, *kind, name, refused);
            }
            Dialog::NewImage(d) => {
                keep = super::new_image::dialog(app, ctx, ui, d);
            }
            Dialog::Shortcuts => {
                ui.heading("Keyboard shortcuts");
                egui::Grid::new("keys").striped(true).show(ui, |ui| {
                    for (k, what) in SHORTCUTS {
                        ui.monospace(*k);
                        ui.label(*what);
                        ui.end_row();
                    }
                });
                if ui.button("Close").clicked() {
                    keep = false;
                }
            }
        }
    });
    if modal.should_close()
        && matches!(
            dialog,
            Dialog::Shortcuts | Dialog::Error { .. } | Dialog::Path { .. } | Dialog::NewImage(_)
        )
    {
        keep = false;
    }
    if keep && app.dialog.is_none() {
        app.dialog = Some(dialog);
    }
    // More recovery copies (several editors died): the next one.
    app.next_recovery();
}

/// The typed-path prompt (File → Open path… / Save to path…, or where the system's dialog
/// could not open): whether it stays open.
fn path_dialog(
    app: &mut EditorApp,
    ui: &mut egui::Ui,
    save: bool,
    text: &str,
    note: Option<&String>,
) -> bool {
    let mut keep = true;
    ui.heading(if save {
        "Save the layout as"
    } else {
        "Open a layout"
    });
    if let Some(n) = note {
        egui::ScrollArea::vertical()
            .max_height(160.0)
            .show(ui, |ui| {
                ui.colored_label(egui::Color32::from_rgb(255, 200, 80), n);
            });
    }
    let mut typed = text.to_string();
    let label = ui.label("Path of the layout file");
    let field = ui
        .add(
            egui::TextEdit::singleline(&mut typed)
                .desired_width(520.0)
                .hint_text("/path/to/level.json"),
        )
        .labelled_by(label.id);
    let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
    ui.horizontal(|ui| {
        let go = ui
            .add_enabled(
                !typed.trim().is_empty(),
                egui::Button::new(if save { "Save" } else { "Open" }),
            )
            .clicked();
        if (go || enter) && !typed.trim().is_empty() {
            keep = false;
            let path = std::path::PathBuf::from(typed.trim());
            let done = if save {
                app.save_typed(ui.ctx(), &path)
            } else {
                app.open_typed(&path)
            };
            // Failed: the prompt again, with what was typed and why.
            if let Err(why) = done {
                app.dialog = Some(Dialog::Path {
                    save,
                    text: typed.clone(),
                    note: Some(why),
                });
            }
        }
        if ui.button("Cancel").clicked() {
            keep = false;
        }
    });
    if keep && typed != text {
        app.dialog = Some(Dialog::Path {
            save,
            text: typed,
            note: note.cloned(),
        });
        keep = false;
    }
    keep
}

pub const SHORTCUTS: &[(&str, &str)] = &[
    (
        "S / R / A / W / C / P / B / M",
        "Select, Add root, Add arrow, Stroke, Circle, Polygon, Paint, Probe tools",
    ),
    ("[ / ]", "With Paint: a smaller / larger brush"),
    ("Ctrl+Z", "Undo"),
    ("Ctrl+Shift+Z, Ctrl+Y", "Redo"),
    (
        "Delete, Backspace",
        "Delete the selection (a point takes its subtree)",
    ),
    ("Ctrl+D", "Duplicate the selection"),
    ("Ctrl+A", "Select everything the map picks"),
    (
        "Right-click",
        "The item's menu (duplicate, delete, its tree, lock, hide, focus), or the map's",
    ),
    (
        "Ctrl+C / Ctrl+X / Ctrl+V",
        "Copy, cut, paste (as layout JSON; at the pointer on the map)",
    ),
    (
        "Arrow keys (Shift: x10)",
        "Nudge the selection by the snap step; pan without one",
    ),
    (
        "Shift+click, drag on empty map",
        "Add to the selection, box-select",
    ),
    (
        "Right-click / Alt+click a corner",
        "Delete a selected polygon's corner",
    ),
    ("Middle/right drag", "Pan"),
    ("Mouse wheel", "Zoom about the cursor"),
    ("F", "Frame the selection, or the whole world without one"),
    ("Space", "Play / pause the wind"),
    (
        "K",
        "Key the selected tree, branch (a point) or ambient layer at the time shown",
    ),
    (
        "Enter / Esc",
        "Close / cancel a polygon; Esc clears the selection",
    ),
    (
        "Ctrl+N / Ctrl+O / Ctrl+S / Ctrl+Shift+S",
        "New, Open, Save, Save As",
    ),
    // egui's own quit shortcut: it asks to close the window, which asks first when there
    // are unsaved changes.
    ("Ctrl+Q", "Quit (asks first when there are unsaved changes)"),
    (
        "3D view: drag, arrow keys",
        "Orbit (Ctrl+drag while Push is on)",
    ),
    ("3D view: right drag", "Pan"),
    ("3D view: wheel, + / -", "Zoom"),
    ("3D view: Home, double-click", "Frame the whole world"),
];

/// The question asked when the document's file changed on disk behind the editor's back: a
/// strip under the menu bar, until answered (it does not block editing).
pub fn disk_banner(app: &mut EditorApp, ui: &mut egui::Ui) {
    let Some(change) = app.doc.disk_change.clone() else {
        return;
    };
    let name = app.doc.path_label();
    egui::Panel::top("disk change")
        .frame(egui::Frame::side_top_panel(ui.style()).fill(egui::Color32::from_rgb(70, 56, 20)))
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                let text = match change {
                    crate::io::disk::Change::Modified => {
                        format!("{name} was changed on disk by another program.")
                    }
                    crate::io::disk::Change::Deleted => {
                        format!("{name} was deleted or moved on disk.")
                    }
                };
                ui.label(RichText::new(text).color(egui::Color32::from_rgb(255, 220, 140)));
                if change == crate::io::disk::Change::Modified {
                    let reload = ui.button("Reload").on_hover_text(if app.doc.is_dirty() {
                        "Load the file as it is now; your unsaved changes are discarded"
                    } else {
                        "Load the file as it is now"
                    });
                    if reload.clicked() {
                        app.reload_from_disk();
                    }
                }
                let keep = ui.button("Keep mine").on_hover_text(
                    "Keep the document as it is in the editor; the next Save writes it to the file",
                );
                if keep.clicked() {
                    app.doc.keep_mine();
                }
            });
        });
}

/// The View menu's speed scale: the speed colours (map and 3D) up to the field's peak, which
/// moves as the wind changes, or up to a fixed speed that stays put while you edit.
fn speed_scale_menu(app: &mut EditorApp, ui: &mut egui::Ui) {
    let (lo, hi) = super::SPEED_SCALE;
    let mut fixed = app.settings.speed_scale.is_some();
    ui.checkbox(&mut fixed, "Fixed speed scale").on_hover_text(
        "Speed colours from 0 to a speed you set, the same from one edit to the next; \
         off: to the field's peak speed",
    );
    app.settings.speed_scale = if fixed {
        // Turned on: start at the peak now, rounded up to a whole m/s.
        let peak = || {
            let snap = app.live.snapshot();
            super::view::field_scale(&snap, WindView::Speed, None).ceil()
        };
        let mut v = app.settings.speed_scale.unwrap_or_else(peak).clamp(lo, hi);
        ui.add(
            egui::DragValue::new(&mut v)
                .range(lo..=hi)
                .speed(0.1)
                .suffix(" m/s"),
        );
        Some(v)
    } else {
        None
    };
}

/// Help → User guide: `docs/EDITOR.md`, built into the editor, in a window of its own that
/// stays open beside the work.
#[derive(Default)]
pub struct Guide {
    pub open: bool,
    cache: egui_commonmark::CommonMarkCache,
}

/// The guide's text as the window shows it: its pictures left out (they are screenshots of
/// this very window), the rest as written.
fn guide_text() -> &'static str {
    static TEXT: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    TEXT.get_or_init(|| {
        include_str!("../../docs/EDITOR.md")
            .lines()
            .filter(|l| !l.trim_start().starts_with("!["))
            .collect::<Vec<_>>()
            .join("\n")
            // Glyphs egui's own font lacks: menu paths read "File › New".
            .replace('→', "›")
            .replace('●', "•")
    })
}

pub fn guide_window(guide: &mut Guide, ctx: &egui::Context) {
    let Guide { open, cache } = guide;
    egui::Window::new("User guide")
        .open(open)
        .default_size([620.0, 640.0])
        .vscroll(true)
        .show(ctx, |ui| {
            egui_commonmark::CommonMarkViewer::new().show(ui, cache, guide_text());
        });
}
