//! What the 3D view draws besides grass, as plain vertex lists (no wgpu): obstacles as simple
//! solids, the AGC arrow trees on the ground, and the map view's footprint. Drawn by
//! `shaders/grass_scene.wgsl`; `SceneVertex` mirrors its vertex input.

use crate::doc::{Layout, Shape};

/// One vertex: world position (metres, y up) and a linear RGBA colour.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SceneVertex {
    pub pos: [f32; 3],
    pub colour: [f32; 4],
}

/// How tall obstacles stand in the 3D view (layouts give them no height).
pub const OBSTACLE_HEIGHT: f32 = 2.5;
const STONE: [f32; 4] = [0.21, 0.18, 0.15, 1.0];
const ARROW: [f32; 4] = [0.06, 0.35, 1.0, 1.0];
const ROOT: [f32; 4] = [0.83, 0.10, 0.05, 1.0];
const PROBE: [f32; 4] = [1.0, 0.47, 0.78, 1.0];
const FOOTPRINT: [f32; 4] = [1.0, 0.78, 0.05, 1.0];

fn v(p: [f32; 3], colour: [f32; 4]) -> SceneVertex {
    SceneVertex { pos: p, colour }
}

/// Obstacles (those not hidden) as prisms `OBSTACLE_HEIGHT` tall: walls and a top, as a triangle list. Circles are
/// 32-sided.
pub fn solids(layout: &Layout) -> Vec<SceneVertex> {
    let mut out = Vec::new();
    let h = OBSTACLE_HEIGHT;
    for o in layout.obstacles.iter().filter(|o| !o.hidden) {
        let ring: Vec<[f32; 2]> = match &o.shape {
            Shape::Circle { center, radius } => (0..32)
                .map(|k| {
                    let a = k as f32 / 32.0 * std::f32::consts::TAU;
                    [center[0] + radius * a.cos(), center[1] + radius * a.sin()]
                })
                .collect(),
            Shape::Polygon { points } => points.clone(),
            Shape::Mask { .. } => {
                // A box per run of solid samples (at up to 128 a side).
                for [a, b] in o.shape.mask_runs(layout.bounds(), 128) {
                    prism(&mut out, &[a, [b[0], a[1]], b, [a[0], b[1]]], h);
                }
                continue;
            }
        };
        prism(&mut out, &ring, h);
    }
    out
}

/// A prism `h` tall over the polygon `ring`: walls and a top.
fn prism(out: &mut Vec<SceneVertex>, ring: &[[f32; 2]], h: f32) {
    {
        let n = ring.len();
        for k in 0..n {
            let (a, b) = (ring[k], ring[(k + 1) % n]);
            let (a0, b0) = ([a[0], 0.0, a[1]], [b[0], 0.0, b[1]]);
            let (a1, b1) = ([a[0], h, a[1]], [b[0], h, b[1]]);
            for p in [a0, b0, a1, b0, b1, a1] {
                out.push(v(p, STONE));
            }
        }
        let top = [STONE[0] * 1.3, STONE[1] * 1.3, STONE[2] * 1.3, 1.0];
        crate::doc::for_each_ear(ring, |a, b, c| {
            for k in [a, b, c] {
                out.push(v([ring[k][0], h, ring[k][1]], top));
            }
        });
    }
}

/// The layout's probes as posts, and the enabled AGC trees not hidden as lines on the ground (an arrow per edge, a cross at each root), as
/// a line list.
pub fn arrows(layout: &Layout) -> Vec<SceneVertex> {
    let y = 0.05;
    let mut out = Vec::new();
    // Probes: a post 2.5 m tall with a cross at its foot.
    for p in &layout.probes {
        let q = p.pos;
        out.push(v([q[0], 0.0, q[1]], PROBE));
        out.push(v([q[0], 2.5, q[1]], PROBE));
        for (dx, dz) in [(0.5, 0.0), (0.0, 0.5)] {
            out.push(v([q[0] - dx, y, q[1] - dz], PROBE));
            out.push(v([q[0] + dx, y, q[1] + dz], PROBE));
        }
    }
    for tree in layout.trees.iter().filter(|t| t.enabled && !t.hidden) {
        let r = tree.root.pos;
        for (dx, dz) in [(0.8, 0.0), (0.0, 0.8)] {
            out.push(v([r[0] - dx, y, r[1] - dz], ROOT));
            out.push(v([r[0] + dx, y, r[1] + dz], ROOT));
        }
        for (parent, child, _) in tree.root.arrows() {
            let (a, b) = (parent.pos, child.pos);
            out.push(v([a[0], y, a[1]], ARROW));
            out.push(v([b[0], y, b[1]], ARROW));
            let d = [b[0] - a[0], b[1] - a[1]];
            let len = d[0].hypot(d[1]);
            if len > 1e-3 {
                let (ux, uz) = (d[0] / len, d[1] / len);
                let head = (len * 0.25).min(2.0);
                for side in [-1.0, 1.0] {
                    let p = [
                        b[0] - ux * head - uz * head * 0.5 * side,
                        b[1] - uz * head + ux * head * 0.5 * side,
                    ];
                    out.push(v([b[0], y, b[1]], ARROW));
                    out.push(v([p[0], y, p[1]], ARROW));
                }
            }
        }
    }
    out
}

/// The map view's visible rectangle `min..max` (world x, z) on the ground, as a line list.
pub fn footprint(min: [f32; 2], max: [f32; 2]) -> Vec<SceneVertex> {
    let y = 0.1;
    let c = [
        [min[0], min[1]],
        [max[0], min[1]],
        [max[0], max[1]],
        [min[0], max[1]],
    ];
    (0..4)
        .flat_map(|k| {
            let (a, b) = (c[k], c[(k + 1) % 4]);
            [v([a[0], y, a[1]], FOOTPRINT), v([b[0], y, b[1]], FOOTPRINT)]
        })
        .collect()
}
