//! Grass: where the blades stand and how they bend — plain data and arithmetic, no wgpu, no
//! egui. The GPU renderer (`crate::gpu::grass`, when built) mirrors these functions; they are
//! its CPU twins.
//!
//! - [`scatter`]: blades placed deterministically for `grass.seed` (stratified jitter at
//!   `grass.density` per m², thinned by the density map where there is one), none inside an
//!   obstacle, each with its own facing, height,
//!   width, stiffness, palette and colour variation.
//! - [`cwd`]: the CWD-Sim quadratic deformation (paper eqs. 11–14) as
//!   `../shared/reference/wind-model.md` reads it, with the paper's open problem solved
//!   (strong wind neither flattens nor blackens a blade).
//! - [`bezier`]: Jahrmann & Wimmer's physics blades; [`cull`]: which blades a frame draws and
//!   at what detail; [`trail`]: the path a pushing sphere leaves; [`sample`]: which blades a
//!   renderer with a blade budget keeps for a view; [`far`]: what the ground shows where the
//!   renderer draws fewer blades than the field holds; [`light`]: the sun, sky, sheen and haze
//!   they are drawn in.

pub mod bezier;
pub mod cull;
pub mod cwd;
pub mod far;
pub mod light;
pub mod sample;
pub mod scene;
pub mod trail;

use crate::doc::{Layout, Shape};

/// One blade's constant data; mirrors `struct Blade` in `shaders/grass_common.wgsl` (when the
/// renderer lands) — 32 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Blade {
    /// Root position, world `(x, z)` metres.
    pub pos: [f32; 2],
    /// Facing: the angle (radians, from `+x` toward `+z`) the blade bends toward at rest.
    pub facing: f32,
    pub height: f32,
    pub width: f32,
    pub stiffness: f32,
    /// Palette index, and a per-blade colour variation in `[-1, 1]`.
    pub palette: u32,
    pub variation: f32,
}

/// The most blades a layout may have (32 Mi: 1 GiB of blade data; 20 M blades at 60 fps is
/// the renderer's goal on a hardware GPU).
pub const MAX_BLADES: usize = 32 << 20;

/// A deterministic hash of three integers to `[0, 1)` (PCG-style mixing).
pub fn hash01(a: u32, b: u32, seed: u64) -> f32 {
    let mut h = (seed as u32) ^ ((seed >> 32) as u32).wrapping_mul(0x9e37_79b9);
    for x in [a, b] {
        h ^= x.wrapping_mul(0x85eb_ca6b);
        h = h.rotate_left(13).wrapping_mul(0xc2b2_ae35);
        h ^= h >> 16;
    }
    h = h.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    h = ((h >> ((h >> 28) + 4)) ^ h).wrapping_mul(277_803_737);
    h ^= h >> 22;
    (h >> 8) as f32 / 16_777_216.0
}

/// Whether world point `p` lies inside any obstacle of `layout`.
pub fn in_obstacle(layout: &Layout, p: [f32; 2]) -> bool {
    layout.obstacles.iter().any(|o| match &o.shape {
        Shape::Circle { center, radius } => (p[0] - center[0]).hypot(p[1] - center[1]) <= *radius,
        Shape::Mask { .. } => o.shape.mask_contains(p, layout.bounds()),
        Shape::Polygon { points } => {
            let mut inside = false;
            let n = points.len();
            for i in 0..n {
                let (a, b) = (points[i], points[(i + n - 1) % n]);
                if (a[1] > p[1]) != (b[1] > p[1])
                    && p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0]
                {
                    inside = !inside;
                }
            }
            inside
        }
    })
}

/// How many strata (one blade each) [`scatter`] lays over the world: `(columns, rows)` of
/// squares `1/√density` metres across, thinned evenly if that exceeds [`MAX_BLADES`].
pub fn strata(layout: &Layout) -> (usize, usize, f32) {
    strata_within(layout, MAX_BLADES)
}

/// [`strata`], thinned evenly to at most `cap` blades (and [`MAX_BLADES`]).
pub fn strata_within(layout: &Layout, cap: usize) -> (usize, usize, f32) {
    let cap = cap.clamp(1, MAX_BLADES);
    let g = &layout.grass;
    let [w, d] = layout.world.size;
    let mut step = 1.0 / g.density.max(1e-6).sqrt();
    let count = |s: f32| {
        (
            (w / s).round().max(1.0) as usize,
            (d / s).round().max(1.0) as usize,
        )
    };
    let (mut nx, mut nz) = count(step);
    // Rounding can leave a thinned grid a little over the cap: thin again until it fits.
    while nx.saturating_mul(nz) > cap {
        step *= ((nx * nz) as f32 / cap as f32).sqrt() * 1.0001;
        (nx, nz) = count(step);
    }
    (nx, nz, step)
}

/// Whether [`scatter`]'s order runs away from a camera looking along `forward` (x, y, z), so
/// that walking the blades from the last draws the nearest first. Blades are laid row by
/// row, x within a row and the rows by increasing z: a ray through the field crosses the rows,
/// so along it the nearer blades come later in that order when the camera looks toward −z
/// (earlier toward +z); looking along a row, x decides.
pub fn stored_far_to_near(forward: [f32; 3]) -> bool {
    let [x, _, z] = forward;
    if z.abs() > 1e-3 * x.abs() {
        z < 0.0
    } else {
        x < 0.0
    }
}

/// The blades of `layout`: one per stratum at a random point inside it, unless that point is
/// inside an obstacle. Deterministic for `grass.seed`; the same seed gives the same blades in
/// the same order on every machine.
pub fn scatter(layout: &Layout) -> Vec<Blade> {
    scatter_within(layout, MAX_BLADES)
}

/// [`scatter_within`]`(layout, cap)`, and, when that thinned them, about how many blades the
/// layout itself lays out: its strata times the share of the thinned strata whose blade
/// fell outside the obstacles (counting them exactly would mean scattering them all, up to
/// [`MAX_BLADES`], which is what a device that cannot hold them cannot afford either).
pub fn scatter_fitted(layout: &Layout, cap: usize) -> (Vec<Blade>, Option<usize>) {
    let (nx, nz, _) = strata(layout);
    let (tx, tz, _) = strata_within(layout, cap);
    let blades = scatter_within(layout, cap);
    let of_layout = (tx * tz < nx * nz)
        .then(|| (blades.len() as f64 / (tx * tz) as f64 * (nx * nz) as f64).round() as usize);
    (blades, of_layout)
}

/// [`scatter`] over [`strata_within`]`(layout, cap)`: at most `cap` blades, thinned evenly
/// (what a GPU that cannot hold them all draws).
pub fn scatter_within(layout: &Layout, cap: usize) -> Vec<Blade> {
    let g = &layout.grass;
    let (nx, nz, _) = strata_within(layout, cap);
    let [w, d] = layout.world.size;
    let (sx, sz) = (w / nx as f32, d / nz as f32);
    let o = layout.world.origin;
    let palettes = g.palettes.len().max(1) as u32;
    let lerp = |r: [f32; 2], t: f32| r[0] + (r[1] - r[0]) * t;
    let mut blades = Vec::with_capacity(nx * nz);
    let bounds = layout.bounds();
    for j in 0..nz {
        for i in 0..nx {
            let (a, b) = (i as u32, j as u32);
            let r = |k: u64| {
                hash01(
                    a,
                    b,
                    g.seed.wrapping_mul(0x2545_f491_4f6c_dd1d).wrapping_add(k),
                )
            };
            let pos = [o[0] + (i as f32 + r(0)) * sx, o[1] + (j as f32 + r(1)) * sz];
            if in_obstacle(layout, pos) {
                continue;
            }
            // Where the level has grass: kept with the density map's share there (a draw of
            // its own, so a layout without a map keeps every blade as it was).
            if let Some(map) = &g.density_map
                && r(8) >= map.at(pos, bounds)
            {
                continue;
            }
            blades.push(Blade {
                pos,
                facing: r(2) * std::f32::consts::TAU,
                height: lerp(g.height, r(3)),
                width: lerp(g.width, r(4)),
                stiffness: lerp(g.stiffness, r(5)),
                palette: ((r(6) * palettes as f32) as u32).min(palettes - 1),
                variation: r(7) * 2.0 - 1.0,
            });
        }
    }
    blades
}

/// Eq. 1: the index of the wind cell (row-major, `nx × ny` cells of `cell` metres from
/// `origin`) a blade at `pos` takes its wind from; blades in one cell share it.
pub fn wind_cell(
    pos: [f32; 2],
    origin: [f32; 2],
    cell: [f32; 2],
    (nx, ny): (usize, usize),
) -> usize {
    let i = ((pos[0] - origin[0]) / cell[0]).clamp(0.0, (nx - 1) as f32) as usize;
    let j = ((pos[1] - origin[1]) / cell[1]).clamp(0.0, (ny - 1) as f32) as usize;
    j * nx + i
}
