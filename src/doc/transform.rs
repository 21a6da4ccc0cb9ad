//! Rotating and scaling a selection (trees, points, obstacles, mixed) about a pivot, and the
//! edits on a polygon's corners: each as one edit.

use super::bounds;
use super::clipboard::Item;
use super::edit::Edit;
use super::types::*;

/// A rotation by `angle` radians (from +x toward +z, clockwise on the map) and a uniform
/// scale by `scale`, about `pivot`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    pub pivot: Vec2,
    pub angle: f32,
    pub scale: f32,
}

impl Transform {
    pub fn apply(&self, p: Vec2) -> Vec2 {
        let (s, c) = crate::num::sin_cos(self.angle);
        let d = [p[0] - self.pivot[0], p[1] - self.pivot[1]];
        [
            self.pivot[0] + self.scale * (c * d[0] - s * d[1]),
            self.pivot[1] + self.scale * (s * d[0] + c * d[1]),
        ]
    }
}

/// The items as a set: a box-selected chain of thousands of points is looked up once per
/// point, not searched (the handles ask every frame of a drag).
type Picked = std::collections::HashSet<Item>;

fn picked(items: &[Item]) -> Picked {
    items.iter().copied().collect()
}

/// The nodes the items move: a tree (or its root) all its nodes, a point itself.
fn nodes_of<'a>(layout: &'a Layout, items: &Picked) -> Vec<&'a Node> {
    let mut out: Vec<&Node> = Vec::new();
    for t in layout.trees.iter().filter(|t| t.pickable()) {
        if items.contains(&Item::Tree(t.id)) {
            out.extend(t.root.iter());
        } else {
            out.extend(t.root.iter().filter(|n| items.contains(&Item::Node(n.id))));
        }
    }
    out.sort_by_key(|n| n.id);
    out.dedup_by_key(|n| n.id);
    out
}

fn obstacles_of<'a>(layout: &'a Layout, items: &Picked) -> impl Iterator<Item = &'a Obstacle> {
    (layout.obstacles.iter()).filter(|o| o.pickable() && items.contains(&Item::Obstacle(o.id)))
}

fn probes_of<'a>(layout: &'a Layout, items: &Picked) -> impl Iterator<Item = &'a Probe> {
    (layout.probes.iter()).filter(|p| items.contains(&Item::Probe(p.id)))
}

/// The middle of the items' bounding box on the map (points, and obstacles' outlines), the
/// pivot their handles turn and scale about; `None` when none of them is on the map.
pub fn pivot(layout: &Layout, items: &[Item]) -> Option<Vec2> {
    let (lo, hi) = extent(layout, items)?;
    Some([(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0])
}

/// The items' bounding box on the map.
pub fn extent(layout: &Layout, items: &[Item]) -> Option<(Vec2, Vec2)> {
    let bounds = layout.bounds();
    let items = &picked(items);
    let mut pts: Vec<Vec2> = nodes_of(layout, items).iter().map(|n| n.pos).collect();
    pts.extend(probes_of(layout, items).map(|p| p.pos));
    for o in obstacles_of(layout, items) {
        match &o.shape {
            Shape::Circle { center, radius } => {
                pts.push([center[0] - radius, center[1] - radius]);
                pts.push([center[0] + radius, center[1] + radius]);
            }
            Shape::Polygon { points } => pts.extend(points.iter().copied()),
            Shape::Mask { rect, .. } => pts.extend(placed(rect, bounds)),
        }
    }
    let first = *pts.first()?;
    Some(pts.iter().fold((first, first), |(lo, hi), p| {
        (
            [lo[0].min(p[0]), lo[1].min(p[1])],
            [hi[0].max(p[0]), hi[1].max(p[1])],
        )
    }))
}

/// The edit that transforms the items of `layout` by `t`: points move (a tree's all), arrows'
/// and circles' radii scale, polygons' corners move; a mask (an axis-aligned image) keeps
/// its orientation, its rectangle moved and scaled about the pivot. Locked and hidden items
/// stay. `None` when nothing moves.
pub fn transform(layout: &Layout, items: &[Item], t: Transform) -> Option<Edit> {
    let items = &picked(items);
    let mut edits = Vec::new();
    let radius = |r: f32| bounds::RADIUS.clamp(r * t.scale);
    for n in nodes_of(layout, items) {
        edits.push(Edit::MoveNode {
            id: n.id,
            pos: t.apply(n.pos),
        });
        if t.scale != 1.0 {
            edits.push(Edit::SetNode {
                id: n.id,
                strength: n.strength,
                radius: radius(n.radius),
            });
        }
    }
    let bounds = layout.bounds();
    for o in obstacles_of(layout, items) {
        let mut o = o.clone();
        match &mut o.shape {
            Shape::Circle { center, radius: r } => {
                *center = t.apply(*center);
                *r = radius(*r);
            }
            Shape::Polygon { points } => {
                for p in points.iter_mut() {
                    *p = t.apply(*p);
                }
            }
            Shape::Mask { rect, .. } => {
                let [a, b] = placed(rect, bounds);
                let c = t.apply([(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]);
                let half = [(b[0] - a[0]) / 2.0 * t.scale, (b[1] - a[1]) / 2.0 * t.scale];
                *rect = Some([
                    [c[0] - half[0], c[1] - half[1]],
                    [c[0] + half[0], c[1] + half[1]],
                ]);
            }
        }
        edits.push(Edit::SetObstacle { obstacle: o });
    }
    for p in probes_of(layout, items) {
        edits.push(Edit::SetProbe {
            probe: Probe {
                pos: t.apply(p.pos),
                ..p.clone()
            },
        });
    }
    (!edits.is_empty()).then(|| {
        let label = if t.scale != 1.0 && t.angle == 0.0 {
            "Scale"
        } else if t.scale == 1.0 {
            "Rotate"
        } else {
            "Rotate and scale"
        };
        Edit::Named(label, Box::new(Edit::Batch(edits)))
    })
}

/// The edit that sets every selected point's strength and radius (`None`: keep each one's),
/// the inspector's edit of several points at once.
pub fn set_points(
    layout: &Layout,
    items: &[Item],
    strength: Option<f32>,
    radius: Option<f32>,
) -> Option<Edit> {
    let edits: Vec<Edit> = (nodes_of(layout, &picked(items)).iter())
        .map(|n| Edit::SetNode {
            id: n.id,
            strength: strength.unwrap_or(n.strength),
            radius: radius.unwrap_or(n.radius),
        })
        .collect();
    (!edits.is_empty()).then(|| Edit::Named("Change points", Box::new(Edit::Batch(edits))))
}

/// A polygon obstacle with corner `index` at `to`.
pub fn move_corner(o: &Obstacle, index: usize, to: Vec2) -> Option<Obstacle> {
    let mut o = o.clone();
    let Shape::Polygon { points } = &mut o.shape else {
        return None;
    };
    *points.get_mut(index)? = to;
    Some(o)
}

/// A polygon obstacle with a corner `at`, inserted after corner `after` (on the edge from it to
/// the next).
pub fn insert_corner(o: &Obstacle, after: usize, at: Vec2) -> Option<Obstacle> {
    let mut o = o.clone();
    let Shape::Polygon { points } = &mut o.shape else {
        return None;
    };
    if after >= points.len() || points.len() >= bounds::POLYGON_POINTS_MAX {
        return None;
    }
    points.insert(after + 1, at);
    Some(o)
}

/// A polygon obstacle without corner `index`; `None` for a triangle (a polygon keeps three).
pub fn delete_corner(o: &Obstacle, index: usize) -> Option<Obstacle> {
    let mut o = o.clone();
    let Shape::Polygon { points } = &mut o.shape else {
        return None;
    };
    if points.len() <= 3 || index >= points.len() {
        return None;
    }
    points.remove(index);
    Some(o)
}
