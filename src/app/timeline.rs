//! The timeline under the map: the simulation's time, the play range (looping by default;
//! both kept in the layout, `doc::Timeline`; the bake's frames at a click), the keyframes of
//! the trees, their branches and the ambient layers, and scrubbing (the field at the time
//! clicked or dragged to, re-simulated from the live wind's checkpoints, and said so while
//! it is).

use super::{EditorApp, Sel};
use crate::doc::{self, Edit, Key};
use eframe::egui::{self, Color32, Pos2, Rect, RichText, Sense, Stroke};

/// The timeline's own state (what it plays is the layout's: `doc::Timeline`).
pub struct Timeline {
    /// The track's rectangle as last drawn (tests click it).
    pub track: Rect,
}

impl Default for Timeline {
    fn default() -> Self {
        Self {
            track: Rect::NOTHING,
        }
    }
}

/// The keys the selection names, and whose: a tree's (the tree, or its root, selected), a
/// branch's (a point other than a root: the arrow ending there and those after it), an
/// ambient layer's.
pub fn selected_keys(app: &EditorApp) -> Option<(Sel, Vec<Key>)> {
    let doc = &app.doc;
    match app.selection.first().copied()? {
        Sel::Tree(id) => (doc.trees.iter())
            .find(|t| t.id == id)
            .map(|t| (Sel::Tree(id), t.keys.clone())),
        Sel::Node(n) => (doc.trees.iter()).find_map(|t| {
            if t.root.id == n {
                Some((Sel::Tree(t.id), t.keys.clone()))
            } else {
                t.root.find(n).map(|node| (Sel::Node(n), node.keys.clone()))
            }
        }),
        Sel::Ambient(id) => (doc.ambient.iter())
            .find(|a| a.id == id)
            .map(|a| (Sel::Ambient(id), a.keys.clone())),
        _ => None,
    }
}

/// The edit that gives the tree or layer `owner` the keys `keys` (sorted by time).
pub fn set_keys(app: &EditorApp, owner: Sel, mut keys: Vec<Key>) -> Option<Edit> {
    keys.sort_by(|a, b| a.time.total_cmp(&b.time));
    match owner {
        Sel::Tree(id) => {
            let t = app.doc.trees.iter().find(|t| t.id == id)?;
            let mut props = doc::TreeProps::of(t);
            props.keys = keys;
            Some(Edit::SetTreeProps { id, props })
        }
        Sel::Ambient(id) => {
            let mut l = app.doc.ambient.iter().find(|a| a.id == id)?.clone();
            l.keys = keys;
            Some(Edit::SetAmbient { layer: l })
        }
        Sel::Node(id) => Some(Edit::SetNodeKeys { id, keys }),
        _ => None,
    }
}

/// What a key of `owner` acts on, for the timeline's button and messages.
pub fn keyed_what(owner: Sel) -> &'static str {
    match owner {
        Sel::Node(_) => "branch",
        Sel::Ambient(_) => "layer",
        _ => "tree",
    }
}

impl EditorApp {
    /// Adds a key at time `t` to the selected tree or layer, holding the values its keys give
    /// there (so the wind does not change until the key is edited): one undo step.
    pub fn add_key_at(&mut self, ctx: &egui::Context, t: f32) -> bool {
        let Some((owner, mut keys)) = selected_keys(self) else {
            self.say(
                ctx,
                "Select a tree, a branch (one of its points) or an ambient layer to key it",
            );
            return false;
        };
        let t = (t * 100.0).round() / 100.0;
        if keys.iter().any(|k| (k.time - t).abs() < 1e-3) {
            self.say(ctx, format!("There is a key at {t} s already"));
            return false;
        }
        let (strength, turn) = doc::key_values(&keys, t);
        keys.push(Key {
            time: t,
            strength,
            rotation_deg: turn.to_degrees(),
            ease: doc::Ease::Smooth,
        });
        match set_keys(self, owner, keys) {
            Some(e) => self.edit(ctx, e),
            None => false,
        }
    }

    /// Playing in a looping range: back to its start at its end (or when before it); not
    /// while a seek is under way.
    pub fn keep_in_range(&mut self) {
        let [a, b] = self.doc.timeline.range;
        let (time, seeking) = self.live.time_shown();
        if self.doc.timeline.looping
            && self.live.playing
            && seeking.is_none()
            && b > a
            && (time >= b || time + 0.05 < a)
        {
            self.live.seek(a);
        }
    }
}

/// The x of time `t` on the track, and back.
fn x_of(track: Rect, span: f32, t: f32) -> f32 {
    track.left() + t / span * track.width()
}

fn t_of(track: Rect, span: f32, x: f32) -> f32 {
    ((x - track.left()) / track.width() * span).clamp(0.0, span)
}

pub fn panel(app: &mut EditorApp, ui: &mut egui::Ui) {
    let ctx = ui.ctx().clone();
    let (time, seeking) = app.live.time_shown();
    let field_time = app.live.snapshot().time;
    egui::Panel::bottom("timeline")
        .resizable(false)
        .show(ui, |ui| {
            let bake = (
                app.export.warmup,
                app.export.warmup + app.export.frames as f32 / app.export.fps.max(1e-3),
            );
            ui.horizontal(|ui| {
                ui.monospace(format!("t = {time:7.2} s"));
                if seeking.is_some() {
                    // Scrubbed back after an edit, the field is simulated again from calm:
                    // say so, and how far it has come.
                    ui.spinner();
                    ui.label(
                        RichText::new(format!("recomputing: {field_time:.1} s"))
                            .color(ui.visuals().warn_fg_color),
                    )
                    .on_hover_text(
                        "The wind at the time shown is being simulated again from the last \
                         state kept before it (an edit forgets the ones after it); a key taken \
                         now is at the time shown",
                    );
                }
                ui.separator();
                let mut tl = app.doc.timeline;
                let l = ui.label("Play range");
                let [mut a, mut b] = tl.range;
                let mut changed = ui
                    .add(
                        egui::DragValue::new(&mut a)
                            .range(0.0..=1.0e6)
                            .speed(0.1)
                            .suffix(" s"),
                    )
                    .labelled_by(l.id)
                    .changed();
                ui.label("to");
                changed |= ui
                    .add(
                        egui::DragValue::new(&mut b)
                            .range(0.1..=1.0e6)
                            .speed(0.1)
                            .suffix(" s"),
                    )
                    .labelled_by(l.id)
                    .changed();
                tl.range = [a.min(b - 0.1).max(0.0), b.max(a + 0.1)];
                changed |= ui
                    .checkbox(&mut tl.looping, "Loop")
                    .on_hover_text("Playing jumps back to the range's start at its end (saved with the layout)")
                    .changed();
                if changed {
                    app.edit_merged(&ctx, Edit::SetTimeline(tl), "timeline");
                }
                if ui
                    .button("Bake's frames")
                    .on_hover_text(
                        "The play range of the Export dialog's frames (warm-up to its last frame), \
                         looping: the bake's loop as the simulation runs it (a looped bake also \
                         cross-fades its ends)",
                    )
                    .clicked()
                {
                    let tl = doc::Timeline {
                        range: [bake.0, bake.1],
                        looping: true,
                    };
                    app.edit(&ctx, Edit::SetTimeline(tl));
                    app.live.seek(bake.0);
                }
                ui.separator();
                let owner = selected_keys(app);
                let key_tip = match &owner {
                    Some((o, _)) => format!(
                        "A key of the {} at the time shown, holding the wind's values there (K)",
                        keyed_what(*o)
                    ),
                    None => "Select a tree, a branch (one of its points) or an ambient layer to \
                             key its strength and direction"
                        .to_owned(),
                };
                let label = match &owner {
                    Some((o, _)) => format!("+ Key {}", keyed_what(*o)),
                    None => "+ Key".to_owned(),
                };
                if ui
                    .add_enabled(owner.is_some(), egui::Button::new(label))
                    .on_hover_text(&key_tip)
                    .on_disabled_hover_text(&key_tip)
                    .clicked()
                {
                    app.add_key_at(&ctx, time);
                }
                ui.weak("click the track: go to a time");
            });
            // The track.
            let keys_of_all: Vec<(bool, Vec<Key>)> = {
                let sel = selected_keys(app).map(|(s, _)| s);
                let trees = app.doc.trees.iter().flat_map(|t| {
                    let branches = (t.root.iter().skip(1))
                        .map(|n| (sel == Some(Sel::Node(n.id)), n.keys.clone()));
                    std::iter::once((sel == Some(Sel::Tree(t.id)), t.keys.clone())).chain(branches)
                });
                let layers = (app.doc.ambient.iter())
                    .map(|a| (sel == Some(Sel::Ambient(a.id)), a.keys.clone()));
                trees.chain(layers).filter(|(_, k)| !k.is_empty()).collect()
            };
            let last_key = (keys_of_all.iter())
                .flat_map(|(_, k)| k.iter().map(|k| k.time))
                .fold(0.0f32, f32::max);
            let span = [app.doc.timeline.range[1], bake.1, last_key, time]
                .into_iter()
                .fold(10.0f32, f32::max)
                * 1.05;
            let (track, response) = ui.allocate_exact_size(
                egui::vec2(ui.available_width(), 30.0),
                Sense::click_and_drag(),
            );
            app.timeline.track = track;
            let painter = ui.painter_at(track);
            painter.rect_filled(track, 2.0, Color32::from_gray(32));
            let band = |a: f32, b: f32, y: (f32, f32), c: Color32| {
                painter.rect_filled(
                    Rect::from_min_max(
                        Pos2::new(x_of(track, span, a), y.0),
                        Pos2::new(x_of(track, span, b), y.1),
                    ),
                    0.0,
                    c,
                );
            };
            let [a, b] = app.doc.timeline.range;
            band(
                a,
                b,
                (track.top(), track.bottom()),
                Color32::from_rgba_unmultiplied(80, 140, 220, 40),
            );
            band(
                bake.0,
                bake.1,
                (track.bottom() - 4.0, track.bottom()),
                Color32::from_rgb(230, 170, 60),
            );
            // Seconds ticks.
            let step = [1.0f32, 2.0, 5.0, 10.0, 30.0, 60.0, 120.0, 300.0, 600.0]
                .into_iter()
                .find(|s| span / s <= 12.0)
                .unwrap_or(1800.0);
            let mut s = 0.0;
            while s <= span {
                let x = x_of(track, span, s);
                painter.line_segment(
                    [Pos2::new(x, track.top()), Pos2::new(x, track.top() + 5.0)],
                    Stroke::new(1.0, Color32::from_gray(110)),
                );
                painter.text(
                    Pos2::new(x + 2.0, track.top() + 4.0),
                    egui::Align2::LEFT_TOP,
                    format!("{s:.0}"),
                    egui::FontId::proportional(10.0),
                    Color32::from_gray(130),
                );
                s += step;
            }
            // Keys: diamonds, the selection's bright.
            for (selected, keys) in &keys_of_all {
                let colour = if *selected {
                    super::view::SELECT_COLOUR
                } else {
                    Color32::from_gray(150)
                };
                for k in keys {
                    let c = Pos2::new(x_of(track, span, k.time), track.center().y + 3.0);
                    let r = if *selected { 5.0 } else { 3.5 };
                    painter.add(egui::Shape::convex_polygon(
                        vec![
                            c + egui::vec2(0.0, -r),
                            c + egui::vec2(r, 0.0),
                            c + egui::vec2(0.0, r),
                            c + egui::vec2(-r, 0.0),
                        ],
                        colour,
                        Stroke::new(1.0, Color32::BLACK),
                    ));
                }
            }
            // The playhead at the time shown; while it is being recomputed, a faint line where
            // the field has got to.
            if seeking.is_some() {
                let x = x_of(track, span, field_time);
                painter.line_segment(
                    [Pos2::new(x, track.top()), Pos2::new(x, track.bottom())],
                    Stroke::new(1.0, Color32::from_white_alpha(90)),
                );
            }
            let x = x_of(track, span, time);
            painter.line_segment(
                [Pos2::new(x, track.top()), Pos2::new(x, track.bottom())],
                Stroke::new(2.0, Color32::WHITE),
            );
            if (response.clicked() || response.dragged())
                && let Some(p) = response.interact_pointer_pos()
            {
                app.live.seek(t_of(track, span, p.x));
                ctx.request_repaint();
            }
        });
}
