//! The inspector: the selection's properties (a point, a tree, an obstacle, an ambient layer)
//! or, with nothing selected, the layout's world, simulation and grass. Every change is an
//! `Edit`; a drag or a typed value is one undo step.

use super::{EditorApp, Sel};
use crate::doc::bounds::{self, Bound};
use crate::doc::{self, AmbientKind, Edit, Emission, Shape, TimeWindow, TreeProps};
use eframe::egui::{self, RichText};

/// The widths the inspector may take, points (it is as wide as the user drags it).
pub const INSPECTOR_WIDTH: std::ops::RangeInclusive<f32> = 240.0..=460.0;

/// One grid row: a label and the widget it names (for screen readers and tests too).
fn row(ui: &mut egui::Ui, label: &str, add: impl FnOnce(&mut egui::Ui) -> egui::Response) -> bool {
    let l = ui.label(label);
    let r = add(ui).labelled_by(l.id);
    ui.end_row();
    r.changed()
}

/// A `[min, max]` range as two labelled fields, "LABEL min" and "LABEL max", each held to
/// `bound` (as `validate` checks each end).
fn min_max(
    ui: &mut egui::Ui,
    label: &str,
    v: &mut [f32; 2],
    bound: Bound,
    speed: f64,
    suffix: &str,
) -> bool {
    let lo = num(ui, &format!("{label} min"), &mut v[0], bound, speed, suffix);
    lo | num(ui, &format!("{label} max"), &mut v[1], bound, speed, suffix)
}

/// What a direction field offers: any finite angle is valid (`validate`), and one turn
/// either way reaches every direction.
const ONE_TURN: Bound = Bound::new(-360.0, 360.0);

/// A labelled number field in a grid, held to the field's bound (`doc::bounds`, which
/// `validate` and the schema read too).
fn num(
    ui: &mut egui::Ui,
    label: &str,
    v: &mut f32,
    bound: Bound,
    speed: f64,
    suffix: &str,
) -> bool {
    row(ui, label, |ui| ui.add(number(v, bound, speed, suffix)))
}

/// The drag field [`num`] and [`num_tip`] show.
fn number<'a>(v: &'a mut f32, bound: Bound, speed: f64, suffix: &str) -> egui::DragValue<'a> {
    egui::DragValue::new(v)
        .range(bound.range())
        .speed(speed)
        .suffix(suffix)
}

/// [`num`] with `tip` shown on hover: what the setting does, and the paper's symbol for it.
fn num_tip(
    ui: &mut egui::Ui,
    (label, tip): (&str, &str),
    v: &mut f32,
    bound: Bound,
    speed: f64,
    suffix: &str,
) -> bool {
    row(ui, label, |ui| {
        ui.add(number(v, bound, speed, suffix)).on_hover_text(tip)
    })
}

/// The direction of an ambient layer's wind, as the layout stores it.
const DIRECTION_TIP: &str = "The way the wind blows, in degrees from +x (east, the map's right) \
     toward +z (south, down the map): 0 blows east, 90 south, 180 west, 270 north";

/// A setting chosen from a few named values, shown by name (not by its Rust spelling) with
/// what each does on hover.
trait Choice: Copy + PartialEq + 'static {
    const ALL: &'static [Self];
    fn label(self) -> &'static str;
    fn hint(self) -> &'static str;
}

impl Choice for doc::PressureSolve {
    const ALL: &'static [Self] = &[Self::Jacobi, Self::Multigrid];
    fn label(self) -> &'static str {
        match self {
            Self::Jacobi => "Jacobi",
            Self::Multigrid => "Multigrid",
        }
    }
    fn hint(self) -> &'static str {
        match self {
            Self::Jacobi => {
                "Cheap sweeps that remove small-scale divergence; big grids keep some of the \
                 large-scale rest"
            }
            Self::Multigrid => "V-cycles that remove divergence at every scale",
        }
    }
}

impl Choice for doc::Boundary {
    const ALL: &'static [Self] = &[Self::Open, Self::Closed, Self::Periodic];
    fn label(self) -> &'static str {
        match self {
            Self::Open => "Open",
            Self::Closed => "Closed (walls)",
            Self::Periodic => "Periodic (tiles)",
        }
    }
    fn hint(self) -> &'static str {
        match self {
            Self::Open => "Wind leaves the world freely at its edges",
            Self::Closed => "The edges are walls: no wind crosses them",
            Self::Periodic => {
                "Wind leaving one edge enters the opposite one: bakes tile seamlessly"
            }
        }
    }
}

impl Choice for doc::Advection {
    const ALL: &'static [Self] = &[Self::SemiLagrangian, Self::MacCormack];
    fn label(self) -> &'static str {
        match self {
            Self::SemiLagrangian => "Semi-Lagrangian",
            Self::MacCormack => "MacCormack",
        }
    }
    fn hint(self) -> &'static str {
        match self {
            Self::SemiLagrangian => {
                "First order, the paper's scheme: smooth and stable, blurs gusts"
            }
            Self::MacCormack => {
                "Limited second order: keeps gusts sharp; a step costs about twice as much"
            }
        }
    }
}

impl Choice for doc::GrassModel {
    const ALL: &'static [Self] = &[Self::CwdQuadratic, Self::BezierPhysics];
    fn label(self) -> &'static str {
        match self {
            Self::CwdQuadratic => "CWD quadratic",
            Self::BezierPhysics => "Bezier physics",
        }
    }
    fn hint(self) -> &'static str {
        match self {
            Self::CwdQuadratic => "The paper's grouped quadratic bend with height self-shadow",
            Self::BezierPhysics => {
                "Bezier blades stepped by physics (gravity, stiffness, wind): they sway and settle"
            }
        }
    }
}

/// A labelled drop-down of a [`Choice`] in a grid row; true when the user picked another value.
fn choice<T: Choice>(ui: &mut egui::Ui, label: &str, value: &mut T) -> bool {
    let l = ui.label(label);
    let mut changed = false;
    egui::ComboBox::from_id_salt(label)
        .selected_text(value.label())
        .show_ui(ui, |ui| {
            for &c in T::ALL {
                changed |= ui
                    .selectable_value(value, c, c.label())
                    .on_hover_text(c.hint())
                    .changed();
            }
        })
        .response
        .labelled_by(l.id)
        .on_hover_text(value.hint());
    ui.end_row();
    changed
}

pub fn inspector_panel(app: &mut EditorApp, ui: &mut egui::Ui) {
    let ctx = ui.ctx().clone();
    egui::Panel::right("inspector")
        .resizable(true)
        .default_size(290.0)
        // Whatever it shows, never wider than this (a width remembered from an earlier run
        // too): a long warning wraps inside it.
        .size_range(INSPECTOR_WIDTH)
        .show(ui, |ui| {
            // Fill the panel's width whatever is selected: a panel that shrank to its content
            // would move the map under the pointer each time the selection changes. And never
            // grow with it: what is wider than the panel scrolls (a vertical-only area would
            // widen the panel to its widest row).
            egui::ScrollArea::both()
                .auto_shrink([false, false])
                .show(ui, |ui| {
                    ui.heading("Inspector");
                    ui.add_space(4.0);
                    let locked = app.locked(app.selection.first().copied());
                    if locked {
                        ui.weak("Locked: unlock it in the Layers list to change it.");
                    }
                    ui.add_enabled_ui(!locked, |ui| match app.selection.first().copied() {
                        Some(Sel::Node(id)) if app.selection.len() == 1 => {
                            node_inspector(app, &ctx, ui, id)
                        }
                        Some(Sel::Tree(id)) => {
                            if let Some(root) =
                                app.doc.trees.iter().find(|t| t.id == id).map(|t| t.root.id)
                            {
                                node_inspector(app, &ctx, ui, root);
                            }
                            ui.separator();
                            transform_section(app, &ctx, ui);
                        }
                        Some(Sel::Obstacle(id)) if app.selection.len() == 1 => {
                            obstacle_inspector(app, &ctx, ui, id);
                            ui.separator();
                            transform_section(app, &ctx, ui);
                        }
                        Some(Sel::Ambient(id)) => ambient_inspector(app, &ctx, ui, id),
                        Some(Sel::Backdrop) if app.selection.len() == 1 => {
                            backdrop_inspector(app, &ctx, ui)
                        }
                        Some(Sel::Probe(id)) if app.selection.len() == 1 => {
                            probe_inspector(app, &ctx, ui, id)
                        }
                        Some(_) => {
                            ui.label(format!("{} items selected", app.selection.len()));
                            ui.weak("Delete (Del) or duplicate (Ctrl+D) them, or drag to move.");
                            ui.separator();
                            points_section(app, &ctx, ui);
                            transform_section(app, &ctx, ui);
                        }
                        None => layout_inspector(app, &ctx, ui),
                    });
                });
        });
}

/// The selected points' strength and radius, edited all at once: a field shows the first
/// point's value (and says when the others differ); a change sets every point to it.
fn points_section(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    use crate::doc::transform;
    let items = super::handles::items(&app.selection);
    let picked: std::collections::HashSet<doc::Item> = items.iter().copied().collect();
    let points: Vec<(f32, f32)> = (app.doc.trees.iter())
        .flat_map(|t| t.root.iter())
        .filter(|n| picked.contains(&doc::Item::Node(n.id)))
        .map(|n| (n.strength, n.radius))
        .collect();
    let Some(&(mut strength, mut radius)) = points.first() else {
        return;
    };
    ui.label(RichText::new(format!("{} points", points.len())).strong());
    let mixed = |f: fn(&(f32, f32)) -> f32| points.iter().any(|p| f(p) != f(&points[0]));
    let (mut s_changed, mut r_changed) = (false, false);
    egui::Grid::new("points").num_columns(2).show(ui, |ui| {
        s_changed = num(ui, "Strength", &mut strength, bounds::STRENGTH, 0.1, " m/s");
        if mixed(|p| p.0) {
            ui.label("");
            ui.weak("(they differ: a change sets them all)");
            ui.end_row();
        }
        r_changed = num(ui, "Radius", &mut radius, bounds::RADIUS, 0.05, " m");
        if mixed(|p| p.1) {
            ui.label("");
            ui.weak("(they differ: a change sets them all)");
            ui.end_row();
        }
    });
    let edit = transform::set_points(
        &app.doc,
        &items,
        s_changed.then_some(strength),
        r_changed.then_some(radius),
    );
    if (s_changed || r_changed)
        && let Some(e) = edit
    {
        app.edit_merged(ctx, e, "points");
    }
    ui.separator();
}

/// Rotate and scale the selection by typed values, about the middle of its box (the map's
/// handles do it by dragging).
fn transform_section(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    use crate::doc::transform;
    let items = super::handles::items(&app.selection);
    let Some(pivot) = transform::pivot(&app.doc, &items) else {
        return;
    };
    ui.label(RichText::new("Transform").strong());
    let (mut angle, mut percent) = app.transform_input;
    let mut apply = None;
    egui::Grid::new("transform").num_columns(3).show(ui, |ui| {
        ui.label("Angle");
        ui.add(
            egui::DragValue::new(&mut angle)
                .range(-360.0..=360.0)
                .suffix("°"),
        );
        if ui
            .button("Rotate")
            .on_hover_text("Clockwise on the map, about the middle of the selection")
            .clicked()
        {
            apply = Some(transform::Transform {
                pivot,
                angle: angle.to_radians(),
                scale: 1.0,
            });
        }
        ui.end_row();
        ui.label("Factor");
        ui.add(
            egui::DragValue::new(&mut percent)
                .range(1.0..=5000.0)
                .suffix(" %"),
        );
        if ui
            .button("Scale")
            .on_hover_text("Positions and radii, about the middle of the selection")
            .clicked()
        {
            apply = Some(transform::Transform {
                pivot,
                angle: 0.0,
                scale: percent / 100.0,
            });
        }
        ui.end_row();
    });
    app.transform_input = (angle, percent);
    if let Some(t) = apply
        && let Some(e) = transform::transform(&app.doc, &items, t)
    {
        app.edit(ctx, e);
    }
    ui.weak("Or drag the handles on the map: the round one turns (Shift: by 15°), the square one scales.");
}

fn probe_inspector(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui, id: u32) {
    let Some(mut p) = app.doc.probes.iter().find(|p| p.id == id).cloned() else {
        return;
    };
    ui.label(RichText::new("Probe").strong());
    let mut changed = false;
    egui::Grid::new("probe").num_columns(2).show(ui, |ui| {
        changed |= row(ui, "Name", |ui| ui.text_edit_singleline(&mut p.name));
        changed |= num(ui, "x", &mut p.pos[0], bounds::COORD, 0.1, " m");
        changed |= num(ui, "z", &mut p.pos[1], bounds::COORD, 0.1, " m");
    });
    ui.weak("Its readings are plotted under the map; drag it to move it.");
    if changed {
        app.edit_merged(ctx, Edit::SetProbe { probe: p }, ("probe", id));
    }
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
        // The sliders show a working range and take any typed value; the bound holds it.
        strength = bounds::STRENGTH.clamp(strength);
        radius = bounds::RADIUS.clamp(radius);
        changed |= num(ui, "x", &mut pos[0], bounds::COORD, 0.1, " m");
        changed |= num(ui, "z", &mut pos[1], bounds::COORD, 0.1, " m");
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
    if !is_root {
        // The branch from here on ramps and turns on its own, within the tree's keys.
        ui.separator();
        keys_section(app, ctx, ui, Sel::Node(id));
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
            changed |= num(ui, "  start", start, bounds::WINDOW_TIME, 0.1, " s");
            let after_start = Bound {
                min: f64::from(*start) + 0.01,
                ..bounds::WINDOW_TIME
            };
            changed |= num(ui, "  end", end, after_start, 0.1, " s");
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
            changed |= num(ui, "  period", period, bounds::PERIOD, 0.05, " s");
            changed |= row(ui, "  duty", |ui| {
                ui.add(egui::Slider::new(duty, bounds::DUTY.range()))
            });
        }
        changed |= num(
            ui,
            "Pulse speed",
            &mut p.propagation_speed,
            bounds::PROPAGATION_SPEED,
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
    ui.separator();
    keys_section(app, ctx, ui, Sel::Tree(tree.id));
}

fn obstacle_inspector(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui, id: u32) {
    let Some(mut o) = app.doc.obstacles.iter().find(|o| o.id == id).cloned() else {
        return;
    };
    ui.label(RichText::new("Obstacle").strong());
    let mut changed = false;
    let mut new_image = false;
    let mut dialog_failed = false;
    let base = app.doc.base();
    egui::Grid::new("obstacle").num_columns(2).show(ui, |ui| {
        changed |= row(ui, "Name", |ui| ui.text_edit_singleline(&mut o.name));
        match &mut o.shape {
            Shape::Circle { center, radius } => {
                changed |= num(ui, "Centre x", &mut center[0], bounds::COORD, 0.1, " m");
                changed |= num(ui, "Centre z", &mut center[1], bounds::COORD, 0.1, " m");
                changed |= num(ui, "Radius", radius, bounds::RADIUS, 0.05, " m");
            }
            Shape::Mask {
                image,
                threshold,
                invert,
                pixels,
                ..
            } => {
                if let Some(path) = file_row(
                    ui,
                    "Mask image",
                    image,
                    "a grey image",
                    "PNG or EXR, relative to the layout's folder",
                    GREY_FILES,
                    &base,
                    false,
                    &mut dialog_failed,
                )
                .filter(|p| !p.is_empty())
                {
                    *image = path;
                    *pixels = doc::MaskPixels::NotLoaded;
                    new_image = true;
                }
                changed |= row(ui, "Threshold", |ui| {
                    ui.add(egui::Slider::new(threshold, bounds::MASK_THRESHOLD.range()))
                        .on_hover_text(
                            "Solid where the image is darker than this (lighter, inverted)",
                        )
                });
                changed |= row(ui, "Inverted", |ui| ui.checkbox(invert, ""));
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
    if let Shape::Mask { image, pixels, .. } = &mut o.shape {
        // A new image path is read at once (relative to the layout's folder).
        if new_image {
            *pixels = app.doc.read_grey(image, "mask image");
        }
        match pixels {
            doc::MaskPixels::Loaded(m) => {
                ui.weak(format!("{} × {} pixels", m.width, m.height));
            }
            doc::MaskPixels::Failed(why) => not_read(ui, why),
            doc::MaskPixels::NotLoaded => {}
        }
    }
    if new_image {
        app.edit(ctx, Edit::SetObstacle { obstacle: o });
    } else if changed {
        app.edit_merged(ctx, Edit::SetObstacle { obstacle: o }, ("obstacle", id));
    }
    if dialog_failed {
        app.say(ctx, DIALOG_FAILED);
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
                changed |= num_tip(
                    ui,
                    ("Direction", DIRECTION_TIP),
                    direction_deg,
                    ONE_TURN,
                    1.0,
                    "°",
                );
                changed |= num(ui, "Main", main, bounds::AMBIENT_SPEED, 0.05, " m/s");
                changed |= num(
                    ui,
                    "Turbulence",
                    turbulence,
                    bounds::AMBIENT_SPEED,
                    0.05,
                    " m/s",
                );
                changed |= num(
                    ui,
                    "Gust size",
                    pulse_magnitude,
                    bounds::PULSE_MAGNITUDE,
                    0.01,
                    "",
                );
                changed |= num(
                    ui,
                    "Gusts per s",
                    pulse_frequency,
                    bounds::PULSE_FREQUENCY,
                    0.01,
                    " Hz",
                );
            }
            AmbientKind::Noise {
                direction_deg,
                scale,
                speed,
                strength,
            } => {
                changed |= num_tip(
                    ui,
                    ("Direction", DIRECTION_TIP),
                    direction_deg,
                    ONE_TURN,
                    1.0,
                    "°",
                );
                changed |= num(ui, "Scale", scale, bounds::FEATURE_LENGTH, 0.1, " m");
                changed |= num(
                    ui,
                    "Scroll speed",
                    speed,
                    bounds::SCROLL_SPEED,
                    0.05,
                    " m/s",
                );
                changed |= num(
                    ui,
                    "Strength",
                    strength,
                    bounds::AMBIENT_SPEED,
                    0.05,
                    " m/s",
                );
            }
            AmbientKind::Fft {
                direction_deg,
                wind_speed,
                amplitude,
                resolution,
                tile_size,
                seed,
            } => {
                changed |= num_tip(
                    ui,
                    ("Direction", DIRECTION_TIP),
                    direction_deg,
                    ONE_TURN,
                    1.0,
                    "°",
                );
                changed |= num(
                    ui,
                    "Wind speed",
                    wind_speed,
                    bounds::FFT_WIND_SPEED,
                    0.05,
                    " m/s",
                );
                changed |= num(
                    ui,
                    "Amplitude",
                    amplitude,
                    bounds::AMBIENT_SPEED,
                    0.05,
                    " m/s",
                );
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
                changed |= num(
                    ui,
                    "Tile size",
                    tile_size,
                    bounds::FEATURE_LENGTH,
                    0.5,
                    " m",
                );
                changed |= row(ui, "Seed", |ui| ui.add(egui::DragValue::new(seed)));
            }
            AmbientKind::Sine {
                direction_deg,
                amplitude,
                wavelength,
                frequency,
            } => {
                changed |= num_tip(
                    ui,
                    ("Direction", DIRECTION_TIP),
                    direction_deg,
                    ONE_TURN,
                    1.0,
                    "°",
                );
                changed |= num(
                    ui,
                    "Amplitude",
                    amplitude,
                    bounds::AMBIENT_SPEED,
                    0.05,
                    " m/s",
                );
                changed |= num(
                    ui,
                    "Wavelength",
                    wavelength,
                    bounds::FEATURE_LENGTH,
                    0.1,
                    " m",
                );
                changed |= num(
                    ui,
                    "Frequency",
                    frequency,
                    bounds::SINE_FREQUENCY,
                    0.01,
                    " Hz",
                );
            }
        }
    });
    if changed {
        app.edit_merged(ctx, Edit::SetAmbient { layer: l }, ("ambient", id));
    }
    ui.separator();
    keys_section(app, ctx, ui, Sel::Ambient(id));
}

/// The keyframes of a tree, a branch or an ambient layer: one row each (time, strength
/// factor, turn, ease, ×), and a key at the time shown; each change one undo step (a drag
/// one in all).
fn keys_section(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui, owner: Sel) {
    let keys = match owner {
        Sel::Node(id) => app
            .doc
            .trees
            .iter()
            .find_map(|t| t.root.find(id))
            .map(|n| n.keys.clone()),
        Sel::Tree(id) => app
            .doc
            .trees
            .iter()
            .find(|t| t.id == id)
            .map(|t| t.keys.clone()),
        Sel::Ambient(id) => app
            .doc
            .ambient
            .iter()
            .find(|a| a.id == id)
            .map(|a| a.keys.clone()),
        _ => None,
    };
    let Some(mut keys) = keys else {
        return;
    };
    let (title, tip) = match owner {
        Sel::Node(_) => (
            "Branch keyframes",
            "This branch's own strength (a factor on the speeds of the arrow ending here and \
             every arrow after it) and turn (about the arrow's start) over time, within the \
             tree's keys; the timeline under the map shows them",
        ),
        _ => (
            "Keyframes",
            "Strength (a factor on the speeds) and a turn over time; the timeline under the map \
             shows them",
        ),
    };
    ui.label(RichText::new(title).strong()).on_hover_text(tip);
    let mut changed = false;
    let mut remove = None;
    if keys.is_empty() {
        ui.weak("None: steady. Add one at the time shown (K), then change it.");
    } else {
        egui::Grid::new(("keys", owner))
            .num_columns(5)
            .show(ui, |ui| {
                for h in ["time", "strength", "turn", "ease", ""] {
                    ui.weak(h);
                }
                ui.end_row();
                for (k, key) in keys.iter_mut().enumerate() {
                    // Each held to its bound in `doc::bounds`, as `validate` holds it.
                    let fields = [
                        number(&mut key.time, bounds::WINDOW_TIME, 0.05, " s"),
                        number(&mut key.strength, bounds::KEY_STRENGTH, 0.01, "").prefix("×"),
                        number(&mut key.rotation_deg, bounds::KEY_ROTATION, 1.0, "°"),
                    ];
                    for field in fields {
                        changed |= ui.add(field).changed();
                    }
                    let smooth = key.ease == doc::Ease::Smooth;
                    if ui
                        .selectable_label(smooth, if smooth { "smooth" } else { "linear" })
                        .on_hover_text("How the values go on to the next key: click to switch")
                        .clicked()
                    {
                        key.ease = if smooth {
                            doc::Ease::Linear
                        } else {
                            doc::Ease::Smooth
                        };
                        changed = true;
                    }
                    if ui
                        .small_button("×")
                        .on_hover_text("Delete this key")
                        .clicked()
                    {
                        remove = Some(k);
                    }
                    ui.end_row();
                }
            });
    }
    if let Some(k) = remove {
        keys.remove(k);
        changed = true;
    }
    if changed && let Some(e) = super::timeline::set_keys(app, owner, keys) {
        app.edit_merged(ctx, e, ("keys", owner));
    }
    let (t, _) = app.live.time_shown();
    if ui
        .button(format!("+ Key at {t:.2} s"))
        .on_hover_text("K")
        .clicked()
    {
        app.add_key_at(ctx, t);
    }
}

/// A file the layout names, as a grid row: its path (relative to the layout's folder; typed,
/// committed on Enter or when the field loses focus, never a read per keystroke),
/// **Choose…** (the system's file dialog, `filter` its name and extensions) and **×**
/// (none). Returns the new path ("" for none) when one was committed; sets `dialog_failed`
/// when the system's file dialog could not open.
#[allow(
    clippy::too_many_arguments,
    reason = "one row's label, text, tip and dialog"
)]
fn file_row(
    ui: &mut egui::Ui,
    label: &str,
    current: &str,
    hint: &str,
    tip: &str,
    filter: (&str, &[&str]),
    base: &std::path::Path,
    clearable: bool,
    dialog_failed: &mut bool,
) -> Option<String> {
    let l = ui.label(label);
    let mut committed = None;
    ui.horizontal(|ui| {
        // The text being typed lives in egui's memory until committed.
        let id = egui::Id::unique(("inspector file row", label));
        let mut text = ui
            .data(|d| d.get_temp::<(String, String)>(id))
            .filter(|(from, _)| from == current)
            .map_or_else(|| current.to_owned(), |(_, t)| t);
        let r = ui
            .add(
                egui::TextEdit::singleline(&mut text)
                    .hint_text(hint)
                    .desired_width(100.0),
            )
            .labelled_by(l.id)
            .on_hover_text(tip);
        if r.lost_focus() && text.trim() != current {
            committed = Some(text.trim().to_owned());
        }
        ui.data_mut(|d| d.insert_temp(id, (current.to_owned(), text)));
        if ui
            .small_button("…")
            .on_hover_text(format!("Choose the {}", label.to_lowercase()))
            .clicked()
        {
            let mut dialog = rfd::FileDialog::new().add_filter(filter.0, filter.1);
            if base.is_dir() {
                dialog = dialog.set_directory(base);
            }
            let started = std::time::Instant::now();
            match dialog.pick_file() {
                Some(p) => committed = Some(crate::io::images::stored_name(&p, base)),
                None if super::native_dialog_failed(started) => *dialog_failed = true,
                None => {}
            }
        }
        if clearable && !current.is_empty() && ui.small_button("×").on_hover_text("None").clicked()
        {
            committed = Some(String::new());
        }
    });
    ui.end_row();
    committed
}

/// A file that could not be read, said in the panel's width: its name (the whole message,
/// with the full path, on hover), wrapped, so the panel never widens.
fn not_read(ui: &mut egui::Ui, why: &str) {
    let short: Vec<String> = why
        .split(' ')
        .map(|w| {
            let bare = w.trim_end_matches([':', ',', ';']);
            if bare.len() > 24 && bare.contains(['/', '\\']) {
                let leaf = bare.rsplit(['/', '\\']).next().unwrap_or(bare);
                format!("{leaf}{}", &w[bare.len()..])
            } else {
                w.to_owned()
            }
        })
        .collect();
    let text =
        RichText::new(format!("Not read: {}", short.join(" "))).color(ui.visuals().warn_fg_color);
    ui.add(egui::Label::new(text).wrap()).on_hover_text(why);
}

/// The image types a grey image may be.
const GREY_FILES: (&str, &[&str]) = ("PNG or EXR image", &["png", "exr", "PNG", "EXR"]);

/// The backdrop, selected: its picture, opacity and corners, and where to place it.
fn backdrop_inspector(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    let Some(mut m) = app.doc.world.map.clone() else {
        return;
    };
    ui.label(RichText::new("Backdrop").strong());
    let bounds = app.doc.bounds();
    let mut changed = false;
    egui::Grid::new("backdrop").num_columns(2).show(ui, |ui| {
        changed |= row(ui, "Map opacity", |ui| {
            ui.add(egui::Slider::new(&mut m.opacity, bounds::OPACITY.range()))
        });
        let [mut a, mut b] = m.placed(bounds);
        let mut xs = [a[0], b[0]];
        let mut zs = [a[1], b[1]];
        let moved = min_max(ui, "Map placed x", &mut xs, bounds::COORD, 0.1, " m")
            | min_max(ui, "Map placed z", &mut zs, bounds::COORD, 0.1, " m");
        if moved && xs[0] < xs[1] && zs[0] < zs[1] {
            (a, b) = ([xs[0], zs[0]], [xs[1], zs[1]]);
            m.rect = Some([a, b]);
            changed = true;
        }
    });
    ui.weak(format!(
        "{}: drag it on the map to move it, a corner to scale it (its aspect kept; Shift frees \
         it).",
        m.image
    ));
    ui.horizontal(|ui| {
        if ui
            .button("Fit to the world")
            .on_hover_text("Stretch it over the world rectangle")
            .clicked()
        {
            m.rect = None;
            changed = true;
        }
        let picture = app.map.backdrop_size();
        if ui
            .add_enabled(picture.is_some(), egui::Button::new("Its own aspect"))
            .on_hover_text("Keep its width and make its depth match the picture's proportions")
            .clicked()
            && let Some([pw, ph]) = picture
        {
            let [a, b] = m.placed(bounds);
            let depth = (b[0] - a[0]) * ph / pw.max(1.0);
            m.rect = Some([a, [b[0], a[1] + depth]]);
            changed = true;
        }
    });
    if changed {
        let mut w = app.doc.world.clone();
        w.map = Some(m);
        app.edit_merged(ctx, Edit::SetWorld(w), "backdrop");
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
    world_section(app, ctx, ui);
    sim_section(app, ctx, ui);
    grass_section(app, ctx, ui);
    ui.add_space(6.0);
    ui.weak("Select a point, tree, obstacle or layer to edit it.");
}

/// The world: its size, grid and map backdrop.
fn world_section(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    ui.add_space(6.0);
    ui.label(RichText::new("World").strong());
    let mut w = app.doc.world.clone();
    let mut changed = false;
    let mut image_changed = false;
    let mut dialog_failed = false;
    egui::Grid::new("world").num_columns(2).show(ui, |ui| {
        changed |= num(ui, "Width", &mut w.size[0], bounds::WORLD_SIZE, 0.5, " m");
        changed |= num(ui, "Depth", &mut w.size[1], bounds::WORLD_SIZE, 0.5, " m");
        let l = ui.label("Grid");
        ui.horizontal(|ui| {
            changed |= ui
                .add(egui::DragValue::new(&mut w.grid[0]).range(bounds::GRID_AXIS.range()))
                .labelled_by(l.id)
                .changed();
            ui.label("×");
            changed |= ui
                .add(egui::DragValue::new(&mut w.grid[1]).range(bounds::GRID_AXIS.range()))
                .labelled_by(l.id)
                .changed();
        });
        ui.end_row();
        let base = app.doc.base();
        let current = w.map.as_ref().map_or(String::new(), |m| m.image.clone());
        if let Some(image) = file_row(
            ui,
            "Map image",
            &current,
            "none",
            "A top-down picture of the level (PNG or JPEG), relative to the layout's folder",
            (
                "PNG or JPEG image",
                &["png", "jpg", "jpeg", "PNG", "JPG", "JPEG"],
            ),
            &base,
            true,
            &mut dialog_failed,
        ) {
            let opacity = w.map.as_ref().map_or(1.0, |m| m.opacity);
            let rect = w.map.as_ref().and_then(|m| m.rect);
            w.map = (!image.is_empty()).then_some(doc::MapBackdrop {
                image,
                opacity,
                rect,
            });
            image_changed = true;
        }
    });
    // Where the picture lies, in a grid of its own: its long names would push the picture's
    // buttons out of the panel.
    egui::Grid::new("world map").num_columns(2).show(ui, |ui| {
        let world_bounds = app.doc.bounds();
        if let Some(map) = &mut w.map {
            changed |= row(ui, "Map opacity", |ui| {
                ui.add(egui::Slider::new(&mut map.opacity, bounds::OPACITY.range()))
            });
            // Where the picture lies: its top-left and bottom-right corners in the world.
            let [mut a, mut b] = map.placed(world_bounds);
            let mut xs = [a[0], b[0]];
            let mut zs = [a[1], b[1]];
            let moved = min_max(ui, "Map placed x", &mut xs, bounds::COORD, 0.1, " m")
                | min_max(ui, "Map placed z", &mut zs, bounds::COORD, 0.1, " m");
            // Only a rectangle with its corners in order (as `validate` asks).
            if moved && xs[0] < xs[1] && zs[0] < zs[1] {
                (a, b) = ([xs[0], zs[0]], [xs[1], zs[1]]);
                map.rect = (a != world_bounds.0 || b != world_bounds.1).then_some([a, b]);
                changed = true;
            }
        }
    });
    // The level's ground: its heightmap and how the wind feels it.
    egui::CollapsingHeader::new("Terrain")
        .id_salt("terrain")
        .default_open(w.terrain.is_some())
        .show(ui, |ui| {
            egui::Grid::new("terrain").num_columns(2).show(ui, |ui| {
                let current = w
                    .terrain
                    .as_ref()
                    .map_or(String::new(), |t| t.heightmap.clone());
                if let Some(path) = file_row(
                    ui,
                    "Heightmap",
                    &current,
                    "none: flat",
                    "A grey image over the world (16-bit PNG for smooth slopes, or EXR), relative \
                     to the layout's folder: black the lowest height, white the highest",
                    GREY_FILES,
                    &app.doc.base(),
                    true,
                    &mut dialog_failed,
                ) {
                    image_changed = true;
                    let old = w.terrain.take();
                    w.terrain = (!path.is_empty()).then(|| {
                        let pixels = app.doc.read_grey(&path, "heightmap");
                        match old {
                            Some(t) => doc::Terrain {
                                heightmap: path.clone(),
                                pixels,
                                ..t
                            },
                            None => doc::Terrain {
                                heightmap: path.clone(),
                                heights: [0.0, 10.0],
                                rect: None,
                                strength: 1.0,
                                feature_length: None,
                                pixels,
                            },
                        }
                    });
                }
                if let Some(t) = &mut w.terrain {
                    let mut h = t.heights;
                    if min_max(ui, "Heights", &mut h, bounds::TERRAIN_HEIGHT, 0.1, " m")
                        && h[0] <= h[1]
                    {
                        t.heights = h;
                        changed = true;
                    }
                    changed |= row(ui, "Strength", |ui| {
                        ui.add(egui::Slider::new(
                            &mut t.strength,
                            bounds::TERRAIN_STRENGTH.range(),
                        ))
                        .on_hover_text(
                            "How strongly the ground shapes the wind: 0 not at all, 1 as \
                             documented (docs/SOLVER.md, Terrain)",
                        )
                    });
                    let mut l = t.feature_length_for(w.size);
                    if num(ui, "Hill size", &mut l, bounds::FEATURE_LENGTH, 0.1, " m") {
                        t.feature_length = Some(l);
                        changed = true;
                    }
                }
            });
            if let Some(doc::MaskPixels::Failed(why)) = w.terrain.as_ref().map(|t| &t.pixels) {
                not_read(ui, why);
            }
            if w.terrain.is_some() {
                ui.weak(
                    "Crests speed the wind up, lee slopes and hollows slow it, valleys turn it \
                     along them.",
                );
            }
        });
    // The vertical profile of the baked volume (Export: dds).
    egui::CollapsingHeader::new("Wind above the ground")
        .id_salt("profile")
        .show(ui, |ui| {
            let p = &mut w.profile;
            egui::Grid::new("profile").num_columns(2).show(ui, |ui| {
                changed |= num(
                    ui,
                    "Roughness length",
                    &mut p.roughness_length,
                    bounds::ROUGHNESS,
                    0.001,
                    " m",
                );
                changed |= num(
                    ui,
                    "Simulated at",
                    &mut p.reference_height,
                    bounds::PROFILE_HEIGHT,
                    0.05,
                    " m",
                );
                changed |= num(
                    ui,
                    "Volume top",
                    &mut p.top,
                    bounds::PROFILE_HEIGHT,
                    0.1,
                    " m",
                );
                changed |= row(ui, "Layers", |ui| {
                    ui.add(
                        egui::DragValue::new(&mut p.layers).range(bounds::PROFILE_LAYERS.range()),
                    )
                });
            });
            ui.weak(format!(
                "Log law: the wind at 1 m is {:.0} %, at the top {:.0} % of the simulated wind.",
                100.0 * p.factor(1.0),
                100.0 * p.factor(p.top)
            ));
        });
    if image_changed {
        // A new picture is its own undo step, not part of a drag of the sizes.
        app.edit(ctx, Edit::SetWorld(w));
    } else if changed {
        app.edit_merged(ctx, Edit::SetWorld(w), "world");
    }
    if dialog_failed {
        app.say(ctx, DIALOG_FAILED);
    }
}

/// The simulation's settings, and the advice on those that make bad wind.
fn sim_section(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    ui.add_space(6.0);
    ui.label(RichText::new("Simulation").strong());
    let mut s = app.doc.sim;
    let mut changed = false;
    egui::Grid::new("sim").num_columns(2).show(ui, |ui| {
        changed |= choice(ui, "Pressure solve", &mut s.pressure);
        changed |= match s.pressure {
            doc::PressureSolve::Jacobi => row(ui, "Pressure iterations", |ui| {
                ui.add(
                    egui::Slider::new(&mut s.pressure_iterations, 1..=200)
                        .clamping(egui::SliderClamping::Never),
                )
            }),
            doc::PressureSolve::Multigrid => row(ui, "V-cycles", |ui| {
                ui.add(
                    egui::Slider::new(&mut s.pressure_cycles, 1..=20)
                        .clamping(egui::SliderClamping::Never),
                )
                .on_hover_text(
                    "Each V-cycle removes most of the divergence left: one cuts a \
                         running flow's about 100–500×, two reach float precision on most \
                         layouts. More cost time and change nothing you can see.",
                )
            }),
        };
        changed |= row(ui, "Vorticity", |ui| {
            ui.add(
                egui::Slider::new(&mut s.vorticity, 0.0..=10.0)
                    .clamping(egui::SliderClamping::Never),
            )
            .on_hover_text(
                "How hard confinement keeps the eddies that wind makes in wakes and along \
                 its jets: 0 none, 2 the default. Past 2 each step adds less, toward a \
                 ceiling at about 10 (the paper's 50 confines as 10 does). It never makes \
                 the wind faster than your strongest arrow or ambient layer.",
            )
        });
        changed |= row(ui, "Dissipation", |ui| {
            ui.add(
                egui::Slider::new(&mut s.velocity_dissipation, 0.0..=5.0)
                    .clamping(egui::SliderClamping::Never),
            )
        });
        changed |= row(ui, "Arrow response", |ui| {
            ui.add(
                egui::Slider::new(&mut s.arrow_response, 0.1..=30.0)
                    .suffix(" /s")
                    .clamping(egui::SliderClamping::Never),
            )
        });
        if !app.doc.ambient.is_empty() {
            changed |= row(ui, "Ambient pull", |ui| {
                ui.add(
                    egui::Slider::new(&mut s.ambient_coupling, 0.0..=20.0)
                        .suffix(" /s")
                        .clamping(egui::SliderClamping::Never),
                )
                .on_hover_text(
                    "How fast the wind relaxes toward the ambient layers' wind: everywhere, \
                         the arrows' jets included, so it holds them below their strength (a \
                         10 m/s arrow in a 4 m/s breeze settles near 8.8 m/s at 1 /s against \
                         an arrow response of 4 /s). Lower it, or raise Arrow response, to \
                         keep the jets at their strength.",
                )
            });
        }
        changed |= choice(ui, "Boundary", &mut s.boundary);
        changed |= choice(ui, "Advection", &mut s.advection);
    });
    if changed {
        // The sliders show a working range and take any typed value; the bounds hold them.
        s.vorticity = bounds::VORTICITY.clamp(s.vorticity);
        s.velocity_dissipation = bounds::VELOCITY_DISSIPATION.clamp(s.velocity_dissipation);
        s.arrow_response = bounds::ARROW_RESPONSE.clamp(s.arrow_response);
        s.ambient_coupling = bounds::AMBIENT_COUPLING.clamp(s.ambient_coupling);
        s.pressure_iterations = bounds::PRESSURE_ITERATIONS.clamp(s.pressure_iterations);
        s.pressure_cycles = bounds::PRESSURE_CYCLES.clamp(s.pressure_cycles);
        app.edit_merged(ctx, Edit::SetSim(s), "sim");
    }
    for a in doc::advise(&app.doc) {
        // "sim.vorticity" → "Vorticity 2 with MacCormack advection can …"
        let field = a.path.rsplit('.').next().unwrap_or(&a.path);
        let mut chars = field.chars();
        let field: String = chars.next().map_or_else(String::new, |c| {
            c.to_uppercase()
                .chain(chars.map(|c| if c == '_' { ' ' } else { c }))
                .collect()
        });
        ui.label(RichText::new(format!("{field} {}", a.message)).color(ui.visuals().warn_fg_color))
            .on_hover_text(format!("{}: see docs/RELIABILITY.md, \"Findings\"", a.path));
    }
}

/// The grass's settings, folded away until opened.
fn grass_section(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    ui.add_space(6.0);
    egui::CollapsingHeader::new(RichText::new("Grass").strong()).show(ui, |ui| {
        let mut g = app.doc.grass.clone();
        let mut changed = false;
        let mut image_changed = false;
        let mut dialog_failed = false;
        // The density map in a grid of its own: the settings' long names would push its
        // buttons out of the panel.
        egui::Grid::new("grass map").num_columns(2).show(ui, |ui| {
            changed |= num(
                ui,
                "Density",
                &mut g.density,
                bounds::GRASS_DENSITY,
                1.0,
                " /m²",
            );
            // Where the level has grass: a grey image over the world (read when committed).
            let current = g
                .density_map
                .as_ref()
                .map_or(String::new(), |m| m.image.clone());
            if let Some(path) = file_row(
                ui,
                "Density map",
                &current,
                "none",
                "A grey image over the world (PNG or EXR, relative to the layout's folder): \
                 white grows the full density, black none",
                GREY_FILES,
                &app.doc.base(),
                true,
                &mut dialog_failed,
            ) {
                image_changed = true;
                g.density_map = (!path.is_empty()).then(|| doc::DensityMap {
                    pixels: app.doc.read_grey(&path, "density map"),
                    image: path,
                    rect: g.density_map.as_ref().and_then(|m| m.rect),
                });
            }
        });
        if let Some(doc::MaskPixels::Failed(why)) = g.density_map.as_ref().map(|m| &m.pixels) {
            not_read(ui, why);
        }
        if ui
            .button("New density map…")
            .on_hover_text(
                "Where the grass grows, made here to paint: blank (grass everywhere), or from a \
                 picture of the level by a threshold",
            )
            .clicked()
        {
            app.new_image(super::new_image::Kind::Density);
        }
        egui::Grid::new("grass").num_columns(2).show(ui, |ui| {
            changed |= num_tip(ui, GRAVITY_BEND, &mut g.k1, bounds::BEND, 0.005, "");
            changed |= num_tip(ui, FORWARD_LEAN, &mut g.k2, bounds::BEND, 0.005, "");
            changed |= num_tip(ui, STIFFNESS, &mut g.lambda, bounds::LAMBDA, 0.01, "");
            changed |= min_max(
                ui,
                "Height",
                &mut g.height,
                bounds::BLADE_HEIGHT,
                0.01,
                " m",
            );
            changed |= min_max(ui, "Width", &mut g.width, bounds::BLADE_WIDTH, 0.001, " m");
            changed |= min_max(
                ui,
                "Blade stiffness",
                &mut g.stiffness,
                bounds::STIFFNESS,
                0.01,
                "",
            );
            changed |= num_tip(
                ui,
                SHADOW_FROM_WIND,
                &mut g.shadow.c1,
                bounds::SHADOW_TERM,
                0.005,
                "",
            );
            changed |= num_tip(
                ui,
                SHADOW_LIFT,
                &mut g.shadow.c2,
                bounds::SHADOW_TERM,
                0.01,
                "",
            );
            changed |= num(
                ui,
                "Shadow min",
                &mut g.shadow.m_min,
                bounds::SHADOW_CLAMP,
                0.01,
                "",
            );
            changed |= num(
                ui,
                "Shadow max",
                &mut g.shadow.m_max,
                bounds::SHADOW_CLAMP,
                0.01,
                "",
            );
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
            changed |= choice(ui, "Model", &mut g.model);
        });
        if image_changed {
            // A new image is its own undo step.
            app.edit(ctx, Edit::SetGrass(g));
        } else if changed {
            app.edit_merged(ctx, Edit::SetGrass(g), "grass");
        }
        if dialog_failed {
            app.say(ctx, DIALOG_FAILED);
        }
    });
}

/// What the status bar says when the system's file dialog could not open.
const DIALOG_FAILED: &str = "The system's file dialog could not open (is a desktop portal \
                             running?): type the image's path in its field";

/// The grass settings' names, for what they do, with the CWD-Sim paper's symbol on hover.
const GRAVITY_BEND: (&str, &str) = (
    "Gravity bend",
    "How far a blade's own weight bends it over at rest (k1 in the paper's eq. 11)",
);
const FORWARD_LEAN: (&str, &str) = (
    "Forward lean",
    "How far a blade leans the way it faces at rest (k2 in eq. 11)",
);
const STIFFNESS: (&str, &str) = (
    "Stiffness",
    "The share of the wind's push every blade resists: 0 bends fully, 1 not at all (lambda in eq. 13)",
);
const SHADOW_FROM_WIND: (&str, &str) = (
    "Shadow from wind",
    "How much a bent blade darkens in the wind (c1 in eq. 14)",
);
const SHADOW_LIFT: (&str, &str) = (
    "Shadow lift",
    "Brightness added at every height of the blade (c2 in eq. 14)",
);
