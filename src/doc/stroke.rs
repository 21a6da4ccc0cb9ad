//! A free stroke turned into an arrow chain: the path drawn is simplified (Ramer–Douglas–
//! Peucker) to the few points that keep it within a tolerance, and each stretch between them
//! becomes an arrow.

use super::bounds::CHAIN_MAX;
use super::types::{Node, Vec2};

/// The stroke tool's settings: each arrow's strength (m/s) and radius (m).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StrokeSettings {
    pub strength: f32,
    pub radius: f32,
}

impl Default for StrokeSettings {
    fn default() -> Self {
        Self {
            strength: 8.0,
            radius: 5.0,
        }
    }
}

impl StrokeSettings {
    /// How far (metres) the chain may stray from the path drawn: a quarter of the arrows'
    /// radius, well inside the reach of their force.
    pub fn tolerance(&self) -> f32 {
        self.radius * 0.25
    }
}

/// The points of `path` the chain keeps: within `tolerance` metres of the path, its first and
/// last points always, no two closer than 1 cm, at most [`CHAIN_MAX`] arrows (the tolerance
/// widens until it fits).
pub fn simplify(path: &[Vec2], tolerance: f32) -> Vec<Vec2> {
    let mut pts: Vec<Vec2> = Vec::with_capacity(path.len());
    for p in path.iter().filter(|p| p[0].is_finite() && p[1].is_finite()) {
        if pts.last().is_none_or(|q: &Vec2| dist(*q, *p) >= 0.01) {
            pts.push(*p);
        }
    }
    if pts.len() < 2 {
        return pts;
    }
    let as_mint: Vec<mint::Point2<f64>> = (pts.iter())
        .map(|p| mint::Point2 {
            x: p[0] as f64,
            y: p[1] as f64,
        })
        .collect();
    let mut eps = tolerance.max(1e-3) as f64;
    loop {
        let keep = ramer_douglas_peucker::rdp(&as_mint, eps);
        if keep.len() <= CHAIN_MAX + 1 {
            return keep.into_iter().map(|i| pts[i]).collect();
        }
        eps *= 1.5;
    }
}

fn dist(a: Vec2, b: Vec2) -> f32 {
    crate::num::hypot(a[0] - b[0], a[1] - b[1])
}

/// The chain along `points` (from [`simplify`]): the first point's node holds the next, and
/// so on, every arrow with the settings' strength and radius, ids from `first_id` up. `None`
/// for fewer than two points.
pub fn chain(points: &[Vec2], settings: StrokeSettings, first_id: u32) -> Option<Node> {
    if points.len() < 2 {
        return None;
    }
    let mut node: Option<Node> = None;
    for (k, p) in points.iter().enumerate().rev() {
        let mut n = Node::new(first_id + k as u32, *p, settings.strength, settings.radius);
        n.children.extend(node.take());
        node = Some(n);
    }
    node
}
