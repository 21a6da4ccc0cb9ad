//! Grass: where the blades stand and how they bend — plain data and arithmetic, no wgpu, no
//! egui. The GPU renderer (`crate::gpu::grass`, when built) mirrors these functions; they are
//! its CPU twins.
//!
//! - [`scatter`]: blades placed deterministically for `grass.seed` (stratified jitter at
//!   `grass.density` per m², thinned by the density map where there is one), none inside an
//!   obstacle, each with its own facing, height,
//!   width, stiffness, palette and colour variation.
//! - [`cwd`]: the CWD-Sim quadratic deformation (paper eqs. 11–14) as
//!   `docs/GRASS.md` reads it, with the paper's open problem solved
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

/// One blade's constant data; mirrors `struct Blade` in `shaders/grass_common.wgsl` — 32
/// bytes.
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

/// The order the cull pass walks the blades in for a camera looking along `forward` (x, y,
/// z), chosen so that its lists come out about nearest first and the depth test drops hidden
/// blades before they are shaded.
///
/// [`scatter`] lays the blades row by row, x within a row and the rows by increasing z. A
/// camera looking mostly along z crosses the rows, so that order is near to far looking toward
/// +z and far to near toward −z (walked from the last). Looking mostly along x, a ray runs
/// along the rows and crosses them too: there the blades are walked by x
/// ([`order_by_x`]), from the last toward −x.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Walk {
    /// By x ([`order_by_x`]) rather than in the stored order.
    pub by_x: bool,
    /// From the last.
    pub reverse: bool,
}

impl Walk {
    /// The stored order, first to last.
    pub const STORED: Walk = Walk {
        by_x: false,
        reverse: false,
    };

    /// The walk that meets a camera looking along `forward` nearest first.
    pub fn toward(forward: [f32; 3]) -> Self {
        let [x, _, z] = forward;
        let by_x = x.abs() > z.abs();
        Self {
            by_x,
            reverse: if by_x { x < 0.0 } else { z < 0.0 },
        }
    }

    /// The slot of the `m`-th blade walked of `n`; `by_x`: [`order_by_x`] of those `n`
    /// (`grass_cull.wgsl` walks them so).
    pub fn slot(self, m: usize, n: usize, by_x: &[u32]) -> usize {
        let m = if self.reverse { n - 1 - m } else { m };
        if self.by_x { by_x[m] as usize } else { m }
    }
}

/// The blades' slots ordered by their roots' x in columns about one blade apart (as many as
/// a square grid of the blades over their bounds would have), those of one column in their
/// stored order: the walk for a camera looking along x ([`Walk`]). A counting sort, linear in
/// the blades; with columns that wide each writes along its own run, so 20 M blades take a
/// fraction of a second.
pub fn order_by_x(blades: &[Blade]) -> Vec<u32> {
    let n = blades.len();
    // The bounds from every 16th blade (and the last): reading them all again would cost
    // as much as the sort; a blade past them falls in the edge column.
    let (lo, hi) = blades.iter().step_by(16).chain(blades.last()).fold(
        ([f32::MAX; 2], [f32::MIN; 2]),
        |(lo, hi), b| {
            (
                [lo[0].min(b.pos[0]), lo[1].min(b.pos[1])],
                [hi[0].max(b.pos[0]), hi[1].max(b.pos[1])],
            )
        },
    );
    let (w, d) = ((hi[0] - lo[0]).max(0.0), (hi[1] - lo[1]).max(0.0));
    let columns = if w > 0.0 {
        let aspect = if d > 0.0 { w / d } else { n as f32 };
        ((n as f32 * aspect).sqrt().round() as usize).clamp(1, n.min(1 << 20))
    } else {
        1
    };
    let scale = if w > 0.0 { columns as f32 / w } else { 0.0 };
    let mut start = vec![0u32; columns + 1];
    // Each blade's column, kept so the blades are read twice rather than three times.
    let mut order: Vec<u32> = blades
        .iter()
        .map(|b| {
            let c = (((b.pos[0] - lo[0]) * scale) as usize).min(columns - 1);
            start[c + 1] += 1;
            c as u32
        })
        .collect();
    for c in 0..columns {
        start[c + 1] += start[c];
    }
    let of_column = std::mem::replace(&mut order, vec![0; n]);
    for (k, c) in of_column.into_iter().enumerate() {
        let at = &mut start[c as usize];
        order[*at as usize] = k as u32;
        *at += 1;
    }
    order
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
