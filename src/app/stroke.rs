//! The Stroke tool: a path dragged on the map becomes an arrow chain along it
//! (`doc::stroke`), a new tree, or the continuation of the point it starts on; one undo step.

use super::map::{Gesture, HIT};
use super::view::{self, Camera};
use super::{EditorApp, Sel};
use crate::doc::{self, Edit, stroke};
use eframe::egui::{self, Color32, Rect, Stroke};

/// Screen points the pointer moves before the path takes another point.
const STEP: f32 = 3.0;

pub fn tool(
    app: &mut EditorApp,
    ctx: &egui::Context,
    response: &egui::Response,
    rect: Rect,
    cam: &Camera,
    painter: &egui::Painter,
) {
    let down = ctx.input(|i| i.pointer.primary_down());
    let pointer = response.interact_pointer_pos().or(response.hover_pos());
    if !matches!(app.map.gesture, Some(Gesture::Stroke { .. }))
        && response.is_pointer_button_down_on()
        && down
        && let Some(p) = ctx.input(|i| i.pointer.press_origin()).or(pointer)
    {
        let from = view::hit_node(&app.doc, cam, rect, p, HIT);
        let start = from
            .and_then(|id| app.doc.trees.iter().find_map(|t| t.root.find(id)))
            .map_or_else(|| app.snap(cam.to_world(rect, p)), |n| n.pos);
        app.map.gesture = Some(Gesture::Stroke {
            from,
            path: vec![start],
        });
    }
    let Some(Gesture::Stroke { from, path }) = &mut app.map.gesture else {
        return;
    };
    if let Some(p) = pointer.filter(|_| down) {
        let last = cam.to_screen(rect, *path.last().expect("a stroke starts with a point"));
        if last.distance(p) >= STEP {
            path.push(cam.to_world(rect, p));
        }
    }
    // The path drawn, and the chain it will make.
    let settings = app.settings.stroke;
    let kept = stroke::simplify(path, settings.tolerance());
    let line: Vec<_> = path.iter().map(|q| cam.to_screen(rect, *q)).collect();
    painter.add(egui::Shape::line(
        line,
        Stroke::new(1.5, Color32::from_white_alpha(140)),
    ));
    for w in kept.windows(2) {
        view::draw_arrow(
            painter,
            cam.to_screen(rect, w[0]),
            cam.to_screen(rect, w[1]),
            view::arrow_width(settings.strength),
            view::ARROW_COLOUR.gamma_multiply(0.7),
        );
    }
    if !down {
        let from = *from;
        app.map.gesture = None;
        finish(app, ctx, from, kept);
    }
}

/// Adds the chain along `points`: under node `from`, or as a new tree rooted at the first
/// point.
fn finish(app: &mut EditorApp, ctx: &egui::Context, from: Option<u32>, points: Vec<doc::Vec2>) {
    let settings = app.settings.stroke;
    let id = app.doc.next_id();
    // A tree's id first, then its points'.
    let Some(chain) = stroke::chain(&points, settings, id + 1) else {
        return;
    };
    let last = chain.iter().last().map_or(chain.id, |n| n.id);
    let edit = match from {
        Some(parent) => {
            // The chain's first point is the node it starts on.
            let Some(first) = chain.children.into_iter().next() else {
                return;
            };
            Edit::AddNode {
                parent,
                index: usize::MAX,
                node: first,
            }
        }
        None => Edit::AddTree {
            index: app.doc.trees.len(),
            tree: doc::Tree {
                id,
                name: format!("Stroke {}", app.doc.trees.len() + 1),
                enabled: true,
                window: doc::TimeWindow::Always,
                emission: doc::Emission::Continuous,
                propagation_speed: 20.0,
                locked: false,
                hidden: false,
                root: chain,
                keys: Vec::new(),
            },
        },
    };
    if app.edit(ctx, edit) {
        app.selection = vec![Sel::Node(last)];
    }
}
