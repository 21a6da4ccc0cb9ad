//! Menus, toolbar, layers, inspector, status bar and dialogs.

use super::view::WindView;
use super::{Dialog, EditorApp, Pending, Sel, Tool};
use crate::doc::{self, AmbientKind, Edit, Emission, Shape, TimeWindow, TreeProps};
use eframe::egui::{self, RichText};

pub fn menu_bar(app: &mut EditorApp, ui: &mut egui::Ui) {
    let ctx = ui.ctx().clone();
    egui::Panel::top("menu").show(ui, |ui| {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                if ui.button("New").clicked() {
                    app.request(&ctx, Pending::New);
                }
                if ui.button("Open…").clicked() {
                    app.request(&ctx, Pending::Open(None));
                }
                ui.menu_button("Open Recent", |ui| {
                    if app.settings.recent.is_empty() {
                        ui.weak("No recent files");
                    }
                    for p in app.settings.recent.clone() {
                        if ui.button(p.display().to_string()).clicked() {
                            app.request(&ctx, Pending::Open(Some(p)));
                        }
                    }
                });
                ui.separator();
                if ui.button("Save").clicked() {
                    app.save(&ctx);
                }
                if ui.button("Save As…").clicked() {
                    app.save_as(&ctx);
                }
                ui.separator();
                if ui.button("Export/Bake…").clicked() {
                    app.export.open = true;
                    if let Some(dir) = app.path.as_ref().and_then(|p| p.parent()) {
                        if app.export.out == "bake" {
                            app.export.out = dir.join("bake").display().to_string();
                        }
                    }
                }
                ui.separator();
                if ui.button("Quit").clicked() {
                    app.request(&ctx, Pending::Quit);
                }
            });
            ui.menu_button("Edit", |ui| {
                let undo = app
                    .history
                    .undo_label()
                    .map_or("Undo".to_string(), |l| format!("Undo {l}"));
                if ui
                    .add_enabled(app.history.can_undo(), egui::Button::new(undo))
                    .clicked()
                {
                    app.undo();
                }
                let redo = app
                    .history
                    .redo_label()
                    .map_or("Redo".to_string(), |l| format!("Redo {l}"));
                if ui
                    .add_enabled(app.history.can_redo(), egui::Button::new(redo))
                    .clicked()
                {
                    app.redo();
                }
                ui.separator();
                let any = !app.selection.is_empty();
                if ui.add_enabled(any, egui::Button::new("Delete")).clicked() {
                    app.delete_selection(&ctx, false);
                }
                if ui
                    .add_enabled(any, egui::Button::new("Duplicate"))
                    .clicked()
                {
                    app.duplicate_selection(&ctx);
                }
                ui.separator();
                ui.checkbox(&mut app.settings.snap, "Snap to grid");
            });
            ui.menu_button("View", |ui| {
                for c in crate::app::Central::ALL {
                    ui.radio_value(&mut app.settings.central, c, c.label());
                }
                ui.separator();
                for v in WindView::ALL {
                    ui.radio_value(&mut app.settings.wind_view, v, v.label());
                }
                ui.separator();
                ui.label("Wind runs on");
                let mut choice = app.settings.backend;
                for b in crate::app::live::BackendChoice::ALL {
                    ui.radio_value(&mut choice, b, b.label());
                }
                if choice != app.settings.backend {
                    app.set_backend(choice);
                }
                ui.separator();
                ui.checkbox(&mut app.settings.show_grid, "Grid lines");
                if ui.button("Frame all (F)").clicked() {
                    app.camera = None;
                }
            });
            ui.menu_button("Help", |ui| {
                if ui.button("Keyboard shortcuts").clicked() {
                    app.dialog = Some(Dialog::Shortcuts);
                }
            });
            ui.separator();
            toolbar(app, ui);
        });
    });
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
    if ui
        .add(
            egui::Slider::new(&mut speed, 0.1..=4.0)
                .logarithmic(true)
                .text("speed"),
        )
        .changed()
    {
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
            match app.cursor_world {
                Some(p) => {
                    ui.label(format!("x {:.1} m  z {:.1} m", p[0], p[1]));
                    let v = app.live.with_snapshot(|s| s.velocity_at(p));
                    match v {
                        Some(v) => ui.label(format!("wind {:.2} m/s", v[0].hypot(v[1]))),
                        None => ui.label("outside the grid"),
                    };
                }
                None => {
                    ui.weak("cursor off the map");
                }
            }
            ui.separator();
            let snap = app.live.snapshot();
            ui.label(format!("t = {:.2} s", snap.time));
            let timing = ui.label(format!(
                "{} {:.1} ms/step · {:.0} fps",
                snap.backend.label(),
                snap.ms_per_step,
                1000.0 / app.frame_ms.max(0.1)
            ));
            timing.on_hover_ui(|ui| frame_times(app, &snap, ui));
            if let Some(n) = &snap.notice {
                ui.colored_label(egui::Color32::from_rgb(255, 200, 80), n);
            }
            if app.settings.central != crate::app::Central::Map && app.grass_view.blades > 0 {
                ui.separator();
                let ms = app.grass_view.frame_ms.lock().map(|m| *m).unwrap_or(0.0);
                let g = &app.grass_view;
                if g.blades < g.total_blades {
                    ui.label(format!(
                        "{} of {} blades · grass {ms:.1} ms",
                        g.blades, g.total_blades
                    ))
                    .on_hover_text("A software adapter draws an even sample of the blades");
                } else {
                    ui.label(format!("{} blades · grass {ms:.1} ms", g.blades));
                }
            }
            ui.separator();
            ui.label(&app.adapter);
            if let Some((msg, at)) = &app.message {
                if ctx.input(|i| i.time) - at < 6.0 {
                    ui.separator();
                    ui.colored_label(egui::Color32::from_rgb(255, 200, 80), msg);
                }
            }
        });
    });
    app.status_rect = r.response.rect;
}

/// The status bar's timing tooltip: where a frame's time goes.
fn frame_times(app: &EditorApp, snap: &crate::app::live::Snapshot, ui: &mut egui::Ui) {
    egui::Grid::new("frame times")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("frame interval");
            ui.label(format!("{:.1} ms", app.frame_ms));
            ui.end_row();
            ui.label("UI (CPU, this editor's work)");
            ui.label(format!("{:.2} ms", app.ui_ms));
            ui.end_row();
            ui.label(format!("sim step ({}, wall)", snap.backend.label()));
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
            ui.label(match (snap.field.is_some(), app.gpu_view) {
                (true, true) => "on the GPU, from the solver's buffers",
                (false, true) => "on the GPU, from each snapshot uploaded",
                _ => "by egui, from CPU snapshots",
            });
            ui.end_row();
        });
}

pub fn layers_panel(app: &mut EditorApp, ui: &mut egui::Ui) {
    let ctx = ui.ctx().clone();
    egui::Panel::left("layers")
        .resizable(true)
        .default_size(230.0)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                ui.heading("Layers");
                ui.add_space(4.0);
                egui::CollapsingHeader::new(RichText::new("Wind trees").strong())
                    .default_open(true)
                    .show(ui, |ui| trees_list(app, &ctx, ui));
                egui::CollapsingHeader::new(RichText::new("Obstacles").strong())
                    .default_open(true)
                    .show(ui, |ui| {
                        let mut select = None;
                        let mut delete = None;
                        for o in &app.doc.obstacles {
                            ui.horizontal(|ui| {
                                let sel = app.selection.contains(&Sel::Obstacle(o.id));
                                if ui.selectable_label(sel, &o.name).clicked() {
                                    select = Some(o.id);
                                }
                                if ui.small_button("×").on_hover_text("Delete").clicked() {
                                    delete = Some(o.id);
                                }
                            });
                        }
                        if app.doc.obstacles.is_empty() {
                            ui.weak("Use the Circle or Polygon tool");
                        }
                        if let Some(id) = select {
                            app.selection = vec![Sel::Obstacle(id)];
                        }
                        if let Some(id) = delete {
                            app.edit(&ctx, Edit::RemoveObstacle { id });
                        }
                    });
                egui::CollapsingHeader::new(RichText::new("Ambient").strong())
                    .default_open(true)
                    .show(ui, |ui| ambient_list(app, &ctx, ui));
            });
        });
}

fn trees_list(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    let mut action: Option<Edit> = None;
    let mut select = None;
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
            let sel = app.selection.contains(&Sel::Tree(t.id));
            if ui
                .selectable_label(sel, format!("{} ({})", t.name, t.root.count()))
                .clicked()
            {
                select = Some(t.id);
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
            if ui.small_button("×").on_hover_text("Delete tree").clicked() {
                action = Some(Edit::RemoveTree { id: t.id });
            }
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
}

fn ambient_list(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    let mut action = None;
    let mut select = None;
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
            let sel = app.selection.contains(&Sel::Ambient(a.id));
            if ui
                .selectable_label(sel, format!("{} ({})", a.name, a.kind.type_name()))
                .clicked()
            {
                select = Some(a.id);
            }
            if ui.small_button("×").on_hover_text("Delete").clicked() {
                action = Some(Edit::RemoveAmbient { id: a.id });
            }
        });
    }
    ui.menu_button("+ Add layer", |ui| {
        let id = app.doc.next_id();
        let make = |name: &str, kind| doc::AmbientLayer {
            id,
            name: name.into(),
            enabled: true,
            kind,
        };
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
}

/// One grid row: a label and the widget it names (for screen readers and tests too).
fn row(ui: &mut egui::Ui, label: &str, add: impl FnOnce(&mut egui::Ui) -> egui::Response) -> bool {
    let l = ui.label(label);
    let r = add(ui).labelled_by(l.id);
    ui.end_row();
    r.changed()
}

/// A labelled number field in a grid.
fn num(
    ui: &mut egui::Ui,
    label: &str,
    v: &mut f32,
    range: std::ops::RangeInclusive<f32>,
    speed: f64,
    suffix: &str,
) -> bool {
    row(ui, label, |ui| {
        ui.add(
            egui::DragValue::new(v)
                .range(range)
                .speed(speed)
                .suffix(suffix),
        )
    })
}

pub fn inspector_panel(app: &mut EditorApp, ui: &mut egui::Ui) {
    let ctx = ui.ctx().clone();
    egui::Panel::right("inspector")
        .resizable(true)
        .default_size(290.0)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                ui.heading("Inspector");
                ui.add_space(4.0);
                match app.selection.first().copied() {
                    Some(Sel::Node(id)) if app.selection.len() == 1 => {
                        node_inspector(app, &ctx, ui, id)
                    }
                    Some(Sel::Tree(id)) => {
                        if let Some(root) =
                            app.doc.trees.iter().find(|t| t.id == id).map(|t| t.root.id)
                        {
                            node_inspector(app, &ctx, ui, root);
                        }
                    }
                    Some(Sel::Obstacle(id)) if app.selection.len() == 1 => {
                        obstacle_inspector(app, &ctx, ui, id)
                    }
                    Some(Sel::Ambient(id)) => ambient_inspector(app, &ctx, ui, id),
                    Some(_) => {
                        ui.label(format!("{} items selected", app.selection.len()));
                        ui.weak("Delete (Del) or duplicate (Ctrl+D) them, or drag to move.");
                    }
                    None => layout_inspector(app, &ctx, ui),
                }
            });
        });
}

fn node_inspector(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui, id: u32) {
    let Some(tree) = app
        .doc
        .trees
        .iter()
        .find(|t| t.root.find(id).is_some())
        .cloned()
    else {
        return;
    };
    let node = tree.root.find(id).cloned().expect("found above");
    let is_root = tree.root.id == id;
    ui.label(
        RichText::new(if is_root {
            "Root point"
        } else {
            "Arrow end point"
        })
        .strong(),
    );
    let (mut strength, mut radius) = (node.strength, node.radius);
    let mut pos = node.pos;
    let mut changed = false;
    egui::Grid::new("node").num_columns(2).show(ui, |ui| {
        changed |= row(ui, "Strength", |ui| {
            ui.add(
                egui::Slider::new(&mut strength, 0.0..=40.0)
                    .suffix(" m/s")
                    .clamping(egui::SliderClamping::Never),
            )
        });
        changed |= row(ui, "Radius", |ui| {
            ui.add(
                egui::Slider::new(&mut radius, 0.5..=40.0)
                    .suffix(" m")
                    .clamping(egui::SliderClamping::Never),
            )
        });
        changed |= num(ui, "x", &mut pos[0], -1e5..=1e5, 0.1, " m");
        changed |= num(ui, "z", &mut pos[1], -1e5..=1e5, 0.1, " m");
    });
    if is_root {
        ui.weak("The root's strength and radius are used for new arrows dragged out of it.");
    }
    if changed {
        let mut edits = vec![Edit::SetNode {
            id,
            strength,
            radius,
        }];
        if pos != node.pos {
            edits.push(Edit::MoveNode { id, pos });
        }
        app.edit_merged(ctx, Edit::Batch(edits), ("node", id));
    }
    ui.separator();
    tree_inspector(app, ctx, ui, &tree);
}

fn tree_inspector(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui, tree: &doc::Tree) {
    ui.label(RichText::new(format!("Tree “{}”", tree.name)).strong());
    let mut p = TreeProps::of(tree);
    let mut changed = false;
    egui::Grid::new("tree").num_columns(2).show(ui, |ui| {
        changed |= row(ui, "Name", |ui| ui.text_edit_singleline(&mut p.name));
        changed |= row(ui, "Enabled", |ui| ui.checkbox(&mut p.enabled, ""));
        ui.label("Active");
        let mut windowed = matches!(p.window, TimeWindow::Between { .. });
        if ui.checkbox(&mut windowed, "only between").changed() {
            p.window = if windowed {
                TimeWindow::Between {
                    start: 0.0,
                    end: 10.0,
                }
            } else {
                TimeWindow::Always
            };
            changed = true;
        }
        ui.end_row();
        if let TimeWindow::Between { start, end } = &mut p.window {
            changed |= num(ui, "  start", start, 0.0..=1e6, 0.1, " s");
            let lo = *start + 0.01;
            changed |= num(ui, "  end", end, lo..=1e6, 0.1, " s");
        }
        ui.label("Emission");
        let mut pulsed = matches!(p.emission, Emission::Pulsed { .. });
        if ui.checkbox(&mut pulsed, "pulsed").changed() {
            p.emission = if pulsed {
                Emission::Pulsed {
                    period: 3.0,
                    duty: 0.5,
                }
            } else {
                Emission::Continuous
            };
            changed = true;
        }
        ui.end_row();
        if let Emission::Pulsed { period, duty } = &mut p.emission {
            changed |= num(ui, "  period", period, 0.05..=1e5, 0.05, " s");
            changed |= row(ui, "  duty", |ui| {
                ui.add(egui::Slider::new(duty, 0.01..=1.0))
            });
        }
        changed |= num(
            ui,
            "Pulse speed",
            &mut p.propagation_speed,
            0.1..=1e5,
            0.5,
            " m/s",
        );
    });
    if changed {
        app.edit_merged(
            ctx,
            Edit::SetTreeProps {
                id: tree.id,
                props: p,
            },
            ("tree", tree.id),
        );
    }
}

fn obstacle_inspector(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui, id: u32) {
    let Some(mut o) = app.doc.obstacles.iter().find(|o| o.id == id).cloned() else {
        return;
    };
    ui.label(RichText::new("Obstacle").strong());
    let mut changed = false;
    egui::Grid::new("obstacle").num_columns(2).show(ui, |ui| {
        changed |= row(ui, "Name", |ui| ui.text_edit_singleline(&mut o.name));
        match &mut o.shape {
            Shape::Circle { center, radius } => {
                changed |= num(ui, "Centre x", &mut center[0], -1e5..=1e5, 0.1, " m");
                changed |= num(ui, "Centre z", &mut center[1], -1e5..=1e5, 0.1, " m");
                changed |= num(ui, "Radius", radius, 0.05..=1e5, 0.05, " m");
            }
            Shape::Polygon { points } => {
                for (k, p) in points.iter_mut().enumerate() {
                    let l = ui.label(format!("Corner {}", k + 1));
                    ui.horizontal(|ui| {
                        changed |= ui
                            .add(egui::DragValue::new(&mut p[0]).speed(0.1).prefix("x "))
                            .labelled_by(l.id)
                            .changed();
                        changed |= ui
                            .add(egui::DragValue::new(&mut p[1]).speed(0.1).prefix("z "))
                            .labelled_by(l.id)
                            .changed();
                    });
                    ui.end_row();
                }
            }
        }
    });
    if changed {
        app.edit_merged(ctx, Edit::SetObstacle { obstacle: o }, ("obstacle", id));
    }
}

fn ambient_inspector(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui, id: u32) {
    let Some(mut l) = app.doc.ambient.iter().find(|a| a.id == id).cloned() else {
        return;
    };
    ui.label(RichText::new(format!("Ambient layer ({})", l.kind.type_name())).strong());
    let mut changed = false;
    egui::Grid::new("ambient").num_columns(2).show(ui, |ui| {
        changed |= row(ui, "Name", |ui| ui.text_edit_singleline(&mut l.name));
        changed |= row(ui, "Enabled", |ui| ui.checkbox(&mut l.enabled, ""));
        match &mut l.kind {
            AmbientKind::Directional {
                direction_deg,
                main,
                turbulence,
                pulse_magnitude,
                pulse_frequency,
            } => {
                changed |= num(ui, "Direction", direction_deg, -360.0..=360.0, 1.0, "°");
                changed |= num(ui, "Main", main, 0.0..=500.0, 0.05, " m/s");
                changed |= num(ui, "Turbulence", turbulence, 0.0..=500.0, 0.05, " m/s");
                changed |= num(ui, "Gust size", pulse_magnitude, 0.0..=10.0, 0.01, "");
                changed |= num(ui, "Gusts per s", pulse_frequency, 0.0..=100.0, 0.01, " Hz");
            }
            AmbientKind::Noise {
                direction_deg,
                scale,
                speed,
                strength,
            } => {
                changed |= num(ui, "Direction", direction_deg, -360.0..=360.0, 1.0, "°");
                changed |= num(ui, "Scale", scale, 0.1..=1e5, 0.1, " m");
                changed |= num(ui, "Scroll speed", speed, 0.0..=1000.0, 0.05, " m/s");
                changed |= num(ui, "Strength", strength, 0.0..=500.0, 0.05, " m/s");
            }
            AmbientKind::Fft {
                direction_deg,
                wind_speed,
                amplitude,
                resolution,
                tile_size,
                seed,
            } => {
                changed |= num(ui, "Direction", direction_deg, -360.0..=360.0, 1.0, "°");
                changed |= num(ui, "Wind speed", wind_speed, 0.1..=500.0, 0.05, " m/s");
                changed |= num(ui, "Amplitude", amplitude, 0.0..=500.0, 0.05, " m/s");
                let l = ui.label("Resolution");
                egui::ComboBox::from_id_salt("fft res")
                    .selected_text(resolution.to_string())
                    .show_ui(ui, |ui| {
                        for r in [16u32, 32, 64, 128, 256] {
                            changed |= ui.selectable_value(resolution, r, r.to_string()).changed();
                        }
                    })
                    .response
                    .labelled_by(l.id);
                ui.end_row();
                changed |= num(ui, "Tile size", tile_size, 1.0..=1e5, 0.5, " m");
                changed |= row(ui, "Seed", |ui| ui.add(egui::DragValue::new(seed)));
            }
            AmbientKind::Sine {
                direction_deg,
                amplitude,
                wavelength,
                frequency,
            } => {
                changed |= num(ui, "Direction", direction_deg, -360.0..=360.0, 1.0, "°");
                changed |= num(ui, "Amplitude", amplitude, 0.0..=500.0, 0.05, " m/s");
                changed |= num(ui, "Wavelength", wavelength, 0.1..=1e5, 0.1, " m");
                changed |= num(ui, "Frequency", frequency, -100.0..=100.0, 0.01, " Hz");
            }
        }
    });
    if changed {
        app.edit_merged(ctx, Edit::SetAmbient { layer: l }, ("ambient", id));
    }
}

fn layout_inspector(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    let l = ui.label(RichText::new("Layout name").strong());
    let mut name = app.doc.name.clone();
    if ui
        .text_edit_singleline(&mut name)
        .labelled_by(l.id)
        .changed()
    {
        app.edit_merged(ctx, Edit::Rename(name), "rename");
    }
    ui.add_space(6.0);
    ui.label(RichText::new("World").strong());
    let mut w = app.doc.world.clone();
    let mut changed = false;
    egui::Grid::new("world").num_columns(2).show(ui, |ui| {
        changed |= num(
            ui,
            "Width",
            &mut w.size[0],
            1.0..=doc::GRID_AXIS_MAX as f32 * 100.0,
            0.5,
            " m",
        );
        changed |= num(
            ui,
            "Depth",
            &mut w.size[1],
            1.0..=doc::GRID_AXIS_MAX as f32 * 100.0,
            0.5,
            " m",
        );
        let l = ui.label("Grid");
        ui.horizontal(|ui| {
            changed |= ui
                .add(egui::DragValue::new(&mut w.grid[0]).range(doc::GRID_AXIS_MIN..=2048))
                .labelled_by(l.id)
                .changed();
            ui.label("×");
            changed |= ui
                .add(egui::DragValue::new(&mut w.grid[1]).range(doc::GRID_AXIS_MIN..=2048))
                .labelled_by(l.id)
                .changed();
        });
        ui.end_row();
        if let Some(map) = &mut w.map {
            changed |= row(ui, "Map opacity", |ui| {
                ui.add(egui::Slider::new(&mut map.opacity, 0.0..=1.0))
            });
        }
    });
    if changed {
        app.edit_merged(ctx, Edit::SetWorld(w), "world");
    }
    ui.add_space(6.0);
    ui.label(RichText::new("Simulation").strong());
    let mut s = app.doc.sim;
    let mut changed = false;
    egui::Grid::new("sim").num_columns(2).show(ui, |ui| {
        changed |= row(ui, "Pressure iterations", |ui| {
            ui.add(egui::Slider::new(&mut s.pressure_iterations, 1..=200))
        });
        changed |= row(ui, "Vorticity", |ui| {
            ui.add(egui::Slider::new(&mut s.vorticity, 0.0..=20.0))
        });
        changed |= row(ui, "Dissipation", |ui| {
            ui.add(egui::Slider::new(&mut s.velocity_dissipation, 0.0..=5.0))
        });
        changed |= row(ui, "Arrow response", |ui| {
            ui.add(egui::Slider::new(&mut s.arrow_response, 0.1..=30.0).suffix(" /s"))
        });
        let l = ui.label("Boundary");
        egui::ComboBox::from_id_salt("boundary")
            .selected_text(format!("{:?}", s.boundary))
            .show_ui(ui, |ui| {
                for b in [
                    doc::Boundary::Open,
                    doc::Boundary::Closed,
                    doc::Boundary::Periodic,
                ] {
                    changed |= ui
                        .selectable_value(&mut s.boundary, b, format!("{b:?}"))
                        .changed();
                }
            })
            .response
            .labelled_by(l.id);
        ui.end_row();
        let l = ui.label("Advection");
        egui::ComboBox::from_id_salt("advection")
            .selected_text(format!("{:?}", s.advection))
            .show_ui(ui, |ui| {
                for a in [doc::Advection::SemiLagrangian, doc::Advection::MacCormack] {
                    changed |= ui
                        .selectable_value(&mut s.advection, a, format!("{a:?}"))
                        .changed();
                }
            })
            .response
            .labelled_by(l.id);
        ui.end_row();
    });
    if changed {
        app.edit_merged(ctx, Edit::SetSim(s), "sim");
    }
    ui.add_space(6.0);
    egui::CollapsingHeader::new(RichText::new("Grass").strong()).show(ui, |ui| {
        let mut g = app.doc.grass.clone();
        let mut changed = false;
        egui::Grid::new("grass").num_columns(2).show(ui, |ui| {
            changed |= num(ui, "Density", &mut g.density, 0.1..=100_000.0, 1.0, " /m²");
            changed |= num(ui, "k1 (gravity)", &mut g.k1, 0.0..=10.0, 0.005, "");
            changed |= num(ui, "k2 (forward)", &mut g.k2, 0.0..=10.0, 0.005, "");
            changed |= num(ui, "λ (stiffness)", &mut g.lambda, 0.0..=1.0, 0.01, "");
            changed |= num(ui, "Height min", &mut g.height[0], 0.01..=100.0, 0.01, " m");
            changed |= num(ui, "Height max", &mut g.height[1], 0.01..=100.0, 0.01, " m");
            changed |= num(ui, "Width min", &mut g.width[0], 0.001..=10.0, 0.001, " m");
            changed |= num(ui, "Width max", &mut g.width[1], 0.001..=10.0, 0.001, " m");
            changed |= num(
                ui,
                "Stiffness min",
                &mut g.stiffness[0],
                0.01..=1000.0,
                0.01,
                "",
            );
            changed |= num(
                ui,
                "Stiffness max",
                &mut g.stiffness[1],
                0.01..=1000.0,
                0.01,
                "",
            );
            changed |= num(
                ui,
                "Shadow c1 (wind)",
                &mut g.shadow.c1,
                0.0..=10.0,
                0.005,
                "",
            );
            changed |= num(
                ui,
                "Shadow c2 (lift)",
                &mut g.shadow.c2,
                0.0..=10.0,
                0.01,
                "",
            );
            changed |= num(ui, "Shadow min", &mut g.shadow.m_min, 0.0..=10.0, 0.01, "");
            changed |= num(ui, "Shadow max", &mut g.shadow.m_max, 0.0..=10.0, 0.01, "");
            changed |= row(ui, "Seed", |ui| ui.add(egui::DragValue::new(&mut g.seed)));
            for p in &mut g.palettes {
                changed |= row(ui, &format!("Palette {}", p.name), |ui| {
                    ui.horizontal(|ui| {
                        let a = ui.color_edit_button_rgb(&mut p.base).on_hover_text("base");
                        let b = ui.color_edit_button_rgb(&mut p.tip).on_hover_text("tip");
                        a.union(b)
                    })
                    .inner
                });
            }
            let l = ui.label("Model");
            egui::ComboBox::from_id_salt("grass model")
                .selected_text(format!("{:?}", g.model))
                .show_ui(ui, |ui| {
                    for m in [
                        doc::GrassModel::CwdQuadratic,
                        doc::GrassModel::BezierPhysics,
                    ] {
                        changed |= ui
                            .selectable_value(&mut g.model, m, format!("{m:?}"))
                            .changed();
                    }
                })
                .response
                .labelled_by(l.id);
            ui.end_row();
        });
        if changed {
            app.edit_merged(ctx, Edit::SetGrass(g), "grass");
        }
    });
    ui.add_space(6.0);
    ui.weak("Select a point, tree, obstacle or layer to edit it.");
}

pub fn dialogs(app: &mut EditorApp, ctx: &egui::Context) {
    let Some(dialog) = app.dialog.take() else {
        return;
    };
    let mut keep = true;
    let modal = egui::Modal::new(egui::Id::unique("windloom dialog")).show(ctx, |ui| {
        ui.set_max_width(560.0);
        match &dialog {
            Dialog::Error { title, text } => {
                ui.heading(title);
                egui::ScrollArea::vertical().max_height(300.0).show(ui, |ui| {
                    ui.add(egui::Label::new(RichText::new(text).monospace()).wrap());
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
                        app.dirty = false;
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
            Dialog::Recover { path } => {
                ui.heading("Restore unsaved work?");
                ui.label("windloom did not close cleanly last time. A recovery copy of the layout you were editing was found.");
                ui.horizontal(|ui| {
                    if ui.button("Restore").clicked() {
                        keep = false;
                        match crate::io::load(path) {
                            Ok(doc) => app.replace_document(doc, None, false),
                            Err(e) => {
                                app.dialog = Some(Dialog::Error { title: "Could not restore".into(), text: e.to_string() });
                            }
                        }
                    }
                    if ui.button("Discard").clicked() {
                        keep = false;
                        let _ = std::fs::remove_file(path);
                    }
                });
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
    if modal.should_close() && matches!(dialog, Dialog::Shortcuts | Dialog::Error { .. }) {
        keep = false;
    }
    if keep && app.dialog.is_none() {
        app.dialog = Some(dialog);
    }
}

pub const SHORTCUTS: &[(&str, &str)] = &[
    (
        "S / R / A / C / P",
        "Select, Add root, Add arrow, Circle, Polygon tools",
    ),
    ("Ctrl+Z", "Undo"),
    ("Ctrl+Shift+Z, Ctrl+Y", "Redo"),
    (
        "Delete, Backspace",
        "Delete the selection (a point takes its subtree)",
    ),
    ("Ctrl+D", "Duplicate the selection"),
    (
        "Shift+click, drag on empty map",
        "Add to the selection, box-select",
    ),
    ("Middle/right drag, arrow keys", "Pan"),
    ("Mouse wheel", "Zoom about the cursor"),
    ("F", "Frame the whole world"),
    ("Space", "Play / pause the wind"),
    (
        "Enter / Esc",
        "Close / cancel a polygon; Esc clears the selection",
    ),
    (
        "Ctrl+N / Ctrl+O / Ctrl+S / Ctrl+Shift+S",
        "New, Open, Save, Save As",
    ),
];
