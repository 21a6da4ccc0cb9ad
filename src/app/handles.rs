//! The Select tool's handles on the selection: a polygon's corners (drag to move; right- or
//! Alt-click to delete) and its edges' midpoints (drag to insert a corner), a circle's
//! radius, and the selection's box with a rotate and a scale handle. Each drag is one undo
//! step, computed from the selection as it was when the drag began.

use super::map::Gesture;
use super::view::{self, Camera};
use super::{EditorApp, Sel};
use crate::doc::{self, Edit, Item, Shape, transform};
use eframe::egui::{self, Color32, Pos2, Rect, Stroke};

/// What a handle does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Handle {
    Corner {
        obstacle: u32,
        index: usize,
    },
    Midpoint {
        obstacle: u32,
        after: usize,
    },
    Radius {
        obstacle: u32,
    },
    Rotate,
    Scale,
    /// A corner of the selected backdrop (0 top-left, then clockwise): drag to scale it from
    /// the opposite corner, its aspect kept (Shift frees it).
    BackdropCorner(usize),
}

/// Screen points within which a handle is hit.
const HIT: f32 = 7.0;
/// How far above the selection's box its rotate handle stands, screen points.
const ROTATE_OFFSET: f32 = 26.0;
/// How far the selection's box stands outside it, screen points (its scale handle clear of
/// a corner's).
const BOX_MARGIN: f32 = 10.0;

/// The selection as items of the document.
pub fn items(selection: &[Sel]) -> Vec<Item> {
    (selection.iter())
        .filter_map(|s| match *s {
            Sel::Node(id) => Some(Item::Node(id)),
            Sel::Tree(id) => Some(Item::Tree(id)),
            Sel::Obstacle(id) => Some(Item::Obstacle(id)),
            Sel::Ambient(id) => Some(Item::Ambient(id)),
            Sel::Probe(id) => Some(Item::Probe(id)),
            Sel::Backdrop => None,
        })
        .collect()
}

/// The one selected obstacle that its handles edit, if the selection is one obstacle.
fn single_obstacle(app: &EditorApp) -> Option<&doc::Obstacle> {
    match app.selection.as_slice() {
        [Sel::Obstacle(id)] => (app.doc.obstacles.iter()).find(|o| o.id == *id && o.pickable()),
        _ => None,
    }
}

/// The selection's box on screen, when it has one worth turning: not a lone point or circle.
fn selection_box(app: &EditorApp, cam: &Camera, rect: Rect) -> Option<Rect> {
    let lone = match app.selection.as_slice() {
        [Sel::Node(_)] => true,
        [Sel::Obstacle(_)] => {
            single_obstacle(app).is_none_or(|o| matches!(o.shape, Shape::Circle { .. }))
        }
        _ => app.selection.is_empty(),
    };
    if lone {
        return None;
    }
    let (lo, hi) = transform::extent(&app.doc, &items(&app.selection))?;
    let r = Rect::from_two_pos(cam.to_screen(rect, lo), cam.to_screen(rect, hi));
    (r.width() > 2.0 || r.height() > 2.0).then(|| r.expand(BOX_MARGIN))
}

/// The selected backdrop's corners in the world (top-left, then clockwise), if the selection
/// is the backdrop.
fn backdrop_corners(app: &EditorApp) -> Option<[doc::Vec2; 4]> {
    let ([Sel::Backdrop], Some(m)) = (app.selection.as_slice(), &app.doc.world.map) else {
        return None;
    };
    let [a, b] = m.placed(app.doc.bounds());
    Some([a, [b[0], a[1]], b, [a[0], b[1]]])
}

/// Whether world point `w` lies on the selected backdrop (a drag there moves it).
pub fn on_backdrop(app: &EditorApp, w: doc::Vec2) -> bool {
    backdrop_corners(app)
        .is_some_and(|[a, _, b, _]| (a[0]..=b[0]).contains(&w[0]) && (a[1]..=b[1]).contains(&w[1]))
}

/// Every handle of the selection, with where it is on screen.
pub fn handles(app: &EditorApp, cam: &Camera, rect: Rect) -> Vec<(Handle, Pos2)> {
    let mut out = Vec::new();
    if let Some(corners) = backdrop_corners(app) {
        for (k, c) in corners.iter().enumerate() {
            out.push((Handle::BackdropCorner(k), cam.to_screen(rect, *c)));
        }
    }
    if let Some(o) = single_obstacle(app) {
        match &o.shape {
            Shape::Polygon { points } => {
                let n = points.len();
                for (i, p) in points.iter().enumerate() {
                    let q = points[(i + 1) % n];
                    let mid = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
                    out.push((
                        Handle::Midpoint {
                            obstacle: o.id,
                            after: i,
                        },
                        cam.to_screen(rect, mid),
                    ));
                }
                // Corners after midpoints: they win where both are under the pointer.
                for (i, p) in points.iter().enumerate() {
                    out.push((
                        Handle::Corner {
                            obstacle: o.id,
                            index: i,
                        },
                        cam.to_screen(rect, *p),
                    ));
                }
            }
            Shape::Circle { center, radius } => out.push((
                Handle::Radius { obstacle: o.id },
                cam.to_screen(rect, [center[0] + radius, center[1]]),
            )),
            Shape::Mask { .. } => {}
        }
    }
    if let Some(b) = selection_box(app, cam, rect) {
        out.push((Handle::Scale, b.right_bottom()));
        out.push((
            Handle::Rotate,
            b.center_top() - egui::vec2(0.0, ROTATE_OFFSET),
        ));
    }
    out
}

/// The handle under screen point `p` (the last drawn wins).
pub fn hit(handles: &[(Handle, Pos2)], p: Pos2) -> Option<Handle> {
    (handles.iter().rev())
        .find(|(_, at)| at.distance(p) <= HIT)
        .map(|(h, _)| *h)
}

pub fn draw(app: &EditorApp, painter: &egui::Painter, cam: &Camera, rect: Rect) {
    let ink = view::SELECT_COLOUR;
    if let Some(corners) = backdrop_corners(app) {
        let mut line: Vec<Pos2> = corners.iter().map(|c| cam.to_screen(rect, *c)).collect();
        line.push(line[0]);
        painter.add(egui::Shape::line(line, Stroke::new(1.5, ink)));
    }
    if let Some(b) = selection_box(app, cam, rect) {
        let dashes = egui::Shape::dashed_line(
            &[
                b.left_top(),
                b.right_top(),
                b.right_bottom(),
                b.left_bottom(),
                b.left_top(),
            ],
            Stroke::new(1.0, ink.gamma_multiply(0.7)),
            5.0,
            4.0,
        );
        painter.extend(dashes);
        let top = b.center_top();
        painter.line_segment(
            [top, top - egui::vec2(0.0, ROTATE_OFFSET)],
            Stroke::new(1.0, ink.gamma_multiply(0.7)),
        );
    }
    for (h, at) in handles(app, cam, rect) {
        match h {
            Handle::Corner { .. } | Handle::Scale | Handle::BackdropCorner(_) => {
                painter.rect(
                    Rect::from_center_size(at, egui::vec2(8.0, 8.0)),
                    1.0,
                    Color32::WHITE,
                    Stroke::new(1.0, Color32::BLACK),
                    egui::StrokeKind::Outside,
                );
            }
            Handle::Midpoint { .. } => {
                painter.circle(
                    at,
                    3.0,
                    Color32::from_white_alpha(120),
                    Stroke::new(1.0, Color32::BLACK),
                );
            }
            Handle::Radius { .. } | Handle::Rotate => {
                painter.circle(at, 5.0, ink, Stroke::new(1.0, Color32::BLACK));
            }
        }
    }
}

/// Starts dragging handle `h` from world point `w`.
pub fn start(app: &mut EditorApp, ctx: &egui::Context, h: Handle, w: doc::Vec2, key: u64) {
    let gesture = match h {
        Handle::Corner { obstacle, index } => Gesture::Corner {
            obstacle,
            index,
            key,
        },
        Handle::Midpoint { obstacle, after } => {
            let Some(o) = app.doc.obstacles.iter().find(|o| o.id == obstacle) else {
                return;
            };
            let Some(o) = transform::insert_corner(o, after, w) else {
                return;
            };
            app.edit_merged(ctx, Edit::SetObstacle { obstacle: o }, key);
            Gesture::Corner {
                obstacle,
                index: after + 1,
                key,
            }
        }
        Handle::Radius { obstacle } => Gesture::Radius { obstacle, key },
        Handle::BackdropCorner(k) => {
            let Some(corners) = backdrop_corners(app) else {
                return;
            };
            let (anchor, corner) = (corners[(k + 2) % 4], corners[k]);
            Gesture::Backdrop {
                anchor,
                diagonal: [corner[0] - anchor[0], corner[1] - anchor[1]],
                key,
            }
        }
        Handle::Rotate | Handle::Scale => {
            let items = items(&app.selection);
            let Some(pivot) = transform::pivot(&app.doc, &items) else {
                return;
            };
            Gesture::Transform {
                rotate: h == Handle::Rotate,
                pivot,
                from: w,
                original: Box::new(app.doc.layout().clone()),
                items,
                key,
            }
        }
    };
    app.map.gesture = Some(gesture);
}

/// Continues a handle's drag with the pointer at world point `w` (`fine`: Shift held, which
/// turns by 15° steps, and frees a backdrop's aspect).
pub fn drag(app: &mut EditorApp, ctx: &egui::Context, w: doc::Vec2, fine: bool) {
    let w_at = w;
    let Some(g) = app.map.gesture.clone() else {
        return;
    };
    match g {
        Gesture::Corner {
            obstacle,
            index,
            key,
        } => {
            let to = app.snap(w);
            if let Some(o) = (app.doc.obstacles.iter())
                .find(|o| o.id == obstacle)
                .and_then(|o| transform::move_corner(o, index, to))
            {
                app.edit_merged(ctx, Edit::SetObstacle { obstacle: o }, key);
            }
        }
        Gesture::Radius { obstacle, key } => {
            let Some(mut o) = app.doc.obstacles.iter().find(|o| o.id == obstacle).cloned() else {
                return;
            };
            if let Shape::Circle { center, radius } = &mut o.shape {
                *radius = doc::bounds::RADIUS.clamp((w[0] - center[0]).hypot(w[1] - center[1]));
            }
            app.edit_merged(ctx, Edit::SetObstacle { obstacle: o }, key);
        }
        Gesture::Backdrop {
            anchor,
            diagonal,
            key,
        } => {
            let mut w = app.doc.world.clone();
            let Some(m) = &mut w.map else {
                return;
            };
            let to = [w_at[0] - anchor[0], w_at[1] - anchor[1]];
            let far = if fine {
                // Free: the corner under the pointer, on the side it started on.
                let side = |t: f32, d: f32| d.signum() * (t * d.signum()).max(0.1);
                [
                    anchor[0] + side(to[0], diagonal[0]),
                    anchor[1] + side(to[1], diagonal[1]),
                ]
            } else {
                // The aspect kept: the pointer projected on the diagonal.
                let d2 = diagonal[0] * diagonal[0] + diagonal[1] * diagonal[1];
                let s = ((to[0] * diagonal[0] + to[1] * diagonal[1]) / d2.max(1e-9)).max(0.01);
                [anchor[0] + s * diagonal[0], anchor[1] + s * diagonal[1]]
            };
            m.rect = Some([
                [anchor[0].min(far[0]), anchor[1].min(far[1])],
                [anchor[0].max(far[0]), anchor[1].max(far[1])],
            ]);
            app.edit_merged(
                ctx,
                Edit::Named("Scale backdrop", Box::new(Edit::SetWorld(w))),
                key,
            );
        }
        Gesture::Transform {
            rotate,
            pivot,
            from,
            original,
            items,
            key,
        } => {
            let a = [from[0] - pivot[0], from[1] - pivot[1]];
            let b = [w[0] - pivot[0], w[1] - pivot[1]];
            let t = if rotate {
                let mut angle = b[1].atan2(b[0]) - a[1].atan2(a[0]);
                if fine {
                    let step = 15f32.to_radians();
                    angle = (angle / step).round() * step;
                }
                transform::Transform {
                    pivot,
                    angle,
                    scale: 1.0,
                }
            } else {
                let scale = (b[0].hypot(b[1]) / a[0].hypot(a[1]).max(1e-3)).clamp(0.02, 50.0);
                transform::Transform {
                    pivot,
                    angle: 0.0,
                    scale,
                }
            };
            if let Some(e) = transform::transform(&original, &items, t) {
                app.edit_merged(ctx, e, key);
            }
        }
        _ => {}
    }
}

/// Deletes corner `index` of polygon `obstacle` (a triangle keeps its three).
pub fn delete_corner(app: &mut EditorApp, ctx: &egui::Context, obstacle: u32, index: usize) {
    let Some(o) = app.doc.obstacles.iter().find(|o| o.id == obstacle) else {
        return;
    };
    match transform::delete_corner(o, index) {
        Some(o) => {
            app.edit(ctx, Edit::SetObstacle { obstacle: o });
        }
        None => app.say(ctx, "A polygon keeps at least three corners"),
    }
}
