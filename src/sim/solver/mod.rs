//! The CPU stable-fluid solver: the reference the GPU must match and the engine of bakes.
//!
//! A staggered (MAC) grid: `u` lives on the vertical faces (`(nx+1) × ny`, face `(i, j)` at
//! grid point `(i, j + ½)`), `v` on the horizontal faces (`nx × (ny+1)`, at `(i + ½, j)`),
//! pressure, divergence and curl at cell centres. Divergence, the pressure Laplacian and the
//! gradient are then compatible, so after projection the divergence equals the Jacobi residual
//! exactly (wind-model.md §2, item 6). Velocities are m/s; cell sizes `hx × hz` metres.
//!
//! Every pass computes each output cell from inputs only, so the result is bit-for-bit the
//! same whatever the number of rayon threads.

use super::forces::{Ambient, ArrowSplat, agc_splats};
use super::obstacles;
use super::terrain::TerrainField;
use crate::doc::{Advection, Boundary, Layout, PressureSolve, SimParams, grid_memory};
use rayon::prelude::*;
use std::ops::{Range, RangeInclusive};
use std::time::Instant;
use windloom_simd_kernel::simd_kernel;

mod advection;
mod bands;
mod forcing;
mod gains;
pub(crate) mod multigrid;
mod pressure;
mod reference;
mod sampler;
mod vorticity;

use advection::*;
use bands::*;
use gains::{GainCache, SplatGains};
pub(crate) use multigrid::Multigrid;
use pressure::*;
use sampler::*;
pub use vorticity::{
    CONFINEMENT_BETA, CONFINEMENT_CEILING, CONFINEMENT_KNEE, Confinement, confinement_rate,
};

/// No velocity component ever exceeds this (m/s): extreme authored forces saturate instead of
/// overflowing, so the field can never hold infinities or NaN.
pub const MAX_SPEED: f32 = 1.0e4;

const L: u8 = 1;
const R: u8 = 2;
const B: u8 = 4;
const T: u8 = 8;
/// Shift from "neighbour is fluid" bits to "neighbour is an open edge (p = 0)" bits.
const EDGE: u8 = 4;
const ALL_FLUID: u8 = L | R | B | T;

/// Time spent in each pass (seconds, accumulated since the last reset).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PassTimes {
    pub forces: f64,
    pub curl: f64,
    pub confinement: f64,
    pub divergence: f64,
    /// Steps 2–4 fused into one sweep (the step's path when vorticity confinement is on;
    /// curl, confinement and divergence then stay 0).
    pub curl_confinement_divergence: f64,
    pub pressure: f64,
    pub gradient: f64,
    pub advection: f64,
}

impl PassTimes {
    pub fn total(&self) -> f64 {
        self.forces
            + self.curl
            + self.confinement
            + self.divergence
            + self.curl_confinement_divergence
            + self.pressure
            + self.gradient
            + self.advection
    }

    pub fn as_pairs(&self) -> [(&'static str, f64); 8] {
        [
            ("forces", self.forces),
            ("curl", self.curl),
            ("confinement", self.confinement),
            ("divergence", self.divergence),
            (
                "curl_confinement_divergence",
                self.curl_confinement_divergence,
            ),
            ("pressure", self.pressure),
            ("gradient", self.gradient),
            ("advection", self.advection),
        ]
    }
}

/// The 2D wind solver for one layout.
pub struct Solver {
    pub nx: usize,
    pub ny: usize,
    /// Cell size in metres along x and z.
    pub hx: f32,
    pub hz: f32,
    pub origin: [f32; 2],
    pub params: SimParams,
    /// Simulated time ([`Solver::time`]): counted in substeps, as every solver counts it.
    pub clock: crate::sim::Clock,
    /// x velocity on vertical faces, `(nx + 1) × ny`.
    pub u: Vec<f32>,
    /// z velocity on horizontal faces, `nx × (ny + 1)`.
    pub v: Vec<f32>,
    /// Pressure (scaled by dt/ρ), divergence and curl at cell centres.
    pub p: Vec<f32>,
    pub div: Vec<f32>,
    pub curl: Vec<f32>,
    /// 1 where a cell is solid.
    pub solid: Vec<u8>,
    u_tmp: Vec<f32>,
    v_tmp: Vec<f32>,
    u_hat: Vec<f32>,
    v_hat: Vec<f32>,
    p_tmp: Vec<f32>,
    /// 1 where a face's velocity is free to change (not touching a solid or a wall).
    pub(crate) u_free: Vec<u8>,
    pub(crate) v_free: Vec<u8>,
    /// Per cell: which neighbours take part in the pressure solve (see `L`…`EDGE`).
    pub(crate) flags: Vec<u8>,
    /// Per cell: `1 / Σ w` of the neighbours in its pressure stencil (0 outside the solve).
    pub(crate) inv_w: Vec<f32>,
    /// Per row, the runs `(start, end)` of interior cells (1..nx − 1) that do not have four
    /// fluid neighbours (solids, cells beside them), merged across short gaps: the Jacobi
    /// row runs everything else on its fast path.
    pub(super) row_irregular: Vec<Vec<(usize, usize)>>,
    layout: Layout,
    ambient: Ambient,
    /// The layout's [`super::forces::reference_speed`]: what confinement may spin the wind up to.
    reference_speed: f32,
    pub timings: PassTimes,
    /// Faces the last forces pass visited (rows a splat or ambient layer reaches).
    pub force_faces: usize,
    /// Kept splat gains the last forces pass read (floats; see `max_gain_bytes`).
    pub force_gain_floats: usize,
    /// The splats' per-face gains, kept across steps (see `gains.rs`).
    gain_cache: GainCache,
    /// At most this many bytes of splat gains are kept across steps (`None`: what the
    /// validation's memory budget leaves, about a float per face; `Some(0)`: every step
    /// computes them). The results are the same bits either way.
    pub max_gain_bytes: Option<usize>,
    /// When set, each substep measures what its projection did: the RMS divergence over
    /// fluid cells before the pressure solve and after the gradient subtraction, kept in
    /// [`Self::projection`] (one extra divergence pass; the bench turns it on for one step).
    pub measure_projection: bool,
    /// `(before, after)` of the last measured substep.
    pub projection: Option<(f32, f32)>,
    /// The multigrid hierarchy, made by the first multigrid solve (it depends only on the
    /// grid, the obstacles and the boundary, which a solver keeps for life).
    pub(crate) multigrid: Option<Multigrid>,
    /// The level's ground over this grid (`None`: flat): what shapes the field as it leaves
    /// the solver ([`Self::wind_faces`]), never the solve itself.
    pub terrain: Option<std::sync::Arc<TerrainField>>,
}

impl Solver {
    /// A solver for `layout` at rest. The layout must be valid (see `doc::validate`).
    pub fn new(layout: &Layout) -> Self {
        let nx = layout.world.grid[0] as usize;
        let ny = layout.world.grid[1] as usize;
        let params = layout.sim;
        let solid = obstacles::rasterize(layout);
        let cell = |i: usize, j: usize| solid[j * nx + i] != 0;

        let mut u_free = vec![0u8; (nx + 1) * ny];
        for j in 0..ny {
            for i in 0..=nx {
                let free = if i > 0 && i < nx {
                    !cell(i - 1, j) && !cell(i, j)
                } else {
                    match params.boundary {
                        Boundary::Closed => false,
                        Boundary::Open => !cell(if i == 0 { 0 } else { nx - 1 }, j),
                        Boundary::Periodic => !cell(0, j) && !cell(nx - 1, j),
                    }
                };
                u_free[j * (nx + 1) + i] = u8::from(free);
            }
        }
        let mut v_free = vec![0u8; nx * (ny + 1)];
        for j in 0..=ny {
            for i in 0..nx {
                let free = if j > 0 && j < ny {
                    !cell(i, j - 1) && !cell(i, j)
                } else {
                    match params.boundary {
                        Boundary::Closed => false,
                        Boundary::Open => !cell(i, if j == 0 { 0 } else { ny - 1 }),
                        Boundary::Periodic => !cell(i, 0) && !cell(i, ny - 1),
                    }
                };
                v_free[j * nx + i] = u8::from(free);
            }
        }

        let mut flags = vec![0u8; nx * ny];
        for j in 0..ny {
            for i in 0..nx {
                if cell(i, j) {
                    continue;
                }
                let mut f = 0u8;
                let neighbours = [
                    (L, i.checked_sub(1).map(|a| (a, j)), (nx - 1, j)),
                    (R, (i + 1 < nx).then_some((i + 1, j)), (0, j)),
                    (B, j.checked_sub(1).map(|b| (i, b)), (i, ny - 1)),
                    (T, (j + 1 < ny).then_some((i, j + 1)), (i, 0)),
                ];
                for (bit, inside, wrapped) in neighbours {
                    match inside {
                        Some((a, b)) => {
                            if !cell(a, b) {
                                f |= bit;
                            }
                        }
                        None => match params.boundary {
                            Boundary::Closed => {}
                            Boundary::Open => f |= bit << EDGE,
                            Boundary::Periodic => {
                                if !cell(wrapped.0, wrapped.1) {
                                    f |= bit;
                                }
                            }
                        },
                    }
                }
                flags[j * nx + i] = f;
            }
        }
        let (hx, hz) = (
            layout.world.size[0] / nx as f32,
            layout.world.size[1] / ny as f32,
        );
        let stencil = Stencil::new(hx, hz);
        let inv_w = flags.iter().map(|&fl| stencil.inv_weight(fl)).collect();
        let row_irregular = (0..ny)
            .map(|j| irregular_runs(&flags[j * nx..][..nx]))
            .collect();

        let cells = nx * ny;
        let (min, _) = layout.bounds();
        Self {
            nx,
            ny,
            hx,
            hz,
            origin: min,
            params,
            clock: crate::sim::Clock::default(),
            u: vec![0.0; (nx + 1) * ny],
            v: vec![0.0; nx * (ny + 1)],
            p: vec![0.0; cells],
            div: vec![0.0; cells],
            curl: vec![0.0; cells],
            solid,
            u_tmp: vec![0.0; (nx + 1) * ny],
            v_tmp: vec![0.0; nx * (ny + 1)],
            u_hat: vec![0.0; (nx + 1) * ny],
            v_hat: vec![0.0; nx * (ny + 1)],
            p_tmp: vec![0.0; cells],
            u_free,
            v_free,
            flags,
            inv_w,
            row_irregular,
            layout: layout.clone(),
            ambient: Ambient::new(layout),
            reference_speed: super::forces::reference_speed(layout),
            timings: PassTimes::default(),
            measure_projection: false,
            projection: None,
            force_faces: 0,
            force_gain_floats: 0,
            gain_cache: GainCache::default(),
            max_gain_bytes: None,
            multigrid: None,
            terrain: TerrainField::new(layout).map(std::sync::Arc::new),
        }
    }

    /// Bytes of grid memory this solver holds (checked against the validation budget).
    pub fn memory_bytes(&self) -> u64 {
        let mg = self.multigrid.as_ref().map_or(0, Multigrid::bytes);
        self.base_memory_bytes() + (mg + self.gain_cache.bytes()) as u64
    }

    /// [`Self::memory_bytes`] but for the multigrid hierarchy and the kept splat gains.
    fn base_memory_bytes(&self) -> u64 {
        let f32s = self.u.len()
            + self.v.len()
            + self.p.len()
            + self.div.len()
            + self.curl.len()
            + self.u_tmp.len()
            + self.v_tmp.len()
            + self.u_hat.len()
            + self.v_hat.len()
            + self.p_tmp.len();
        let f32s = f32s + self.inv_w.len();
        let bytes = self.solid.len() + self.u_free.len() + self.v_free.len() + self.flags.len();
        (f32s * 4 + bytes) as u64
    }

    /// The validation budget less the multigrid hierarchy's share: what the base arrays
    /// and the kept splat gains may use together.
    fn memory_budget_jacobi(&self) -> u64 {
        grid_memory([self.nx as u32, self.ny as u32], PressureSolve::Jacobi)
    }

    /// Upper bound used by validation for the same grid and pressure solve.
    pub fn memory_budget(&self) -> u64 {
        grid_memory([self.nx as u32, self.ny as u32], self.params.pressure)
    }

    /// Replaces the layout the forces come from (an edit), keeping the running field. Grid,
    /// obstacles and boundary changes need a new solver.
    pub fn set_layout(&mut self, layout: &Layout) {
        if layout.world.terrain != self.layout.world.terrain {
            self.terrain = TerrainField::new(layout).map(std::sync::Arc::new);
        }
        self.layout = layout.clone();
        self.ambient = Ambient::new(layout);
        self.reference_speed = super::forces::reference_speed(layout);
        self.params = layout.sim;
    }

    /// Advances the simulation by `params.dt` (in `params.substeps` substeps).
    /// Simulated seconds, as the forces take them (the clock's f64, rounded once).
    #[inline]
    pub fn time(&self) -> f32 {
        self.clock.time()
    }

    /// Sets the simulated time (a seek, a checkpoint restored, a bake's frame).
    pub fn set_time(&mut self, seconds: f64) {
        self.clock = crate::sim::Clock::at(seconds);
    }

    pub fn step(&mut self) {
        let n = self.params.substeps.max(1);
        let dt = self.params.dt / n as f32;
        for _ in 0..n {
            self.substep(dt);
        }
    }

    fn substep(&mut self, dt: f32) {
        let t0 = Instant::now();
        self.apply_forces(dt);
        let t1 = Instant::now();
        let fused = self.fuses_vorticity();
        let (t2, t3) = if fused {
            self.vorticity_divergence(dt);
            (t1, t1)
        } else {
            self.compute_curl();
            let t2 = Instant::now();
            self.confine_vorticity(dt);
            let t3 = Instant::now();
            self.compute_divergence();
            (t2, t3)
        };
        let t4 = Instant::now();
        let before = self.measure_projection.then(|| self.fluid_rms(&self.div));
        self.solve_pressure();
        let t5 = Instant::now();
        self.subtract_gradient();
        let t6 = Instant::now();
        if let Some(before) = before {
            self.projection = Some((before, self.divergence_rms()));
        }
        self.advect(dt);
        let t7 = Instant::now();
        self.clock.tick(dt);
        let tm = &mut self.timings;
        let secs = |a: Instant, b: Instant| (b - a).as_secs_f64();
        tm.forces += secs(t0, t1);
        if fused {
            tm.curl_confinement_divergence += secs(t1, t4);
        } else {
            tm.curl += secs(t1, t2);
            tm.confinement += secs(t2, t3);
            tm.divergence += secs(t3, t4);
        }
        tm.pressure += secs(t4, t5);
        tm.gradient += secs(t5, t6);
        tm.advection += secs(t6, t7);
    }

    /// True when the step runs steps 2–4 as one fused sweep ([`Self::vorticity_divergence`]):
    /// whenever vorticity confinement is on (without it there is nothing to fuse but the
    /// curl, which only the views read).
    pub fn fuses_vorticity(&self) -> bool {
        self.params.vorticity > 0.0
    }

    /// Step 6: subtract the pressure gradient from every free face (others are zeroed).
    pub fn subtract_gradient(&mut self) {
        let (nx, ny, hx, hz) = (self.nx, self.ny, self.hx, self.hz);
        let periodic = self.params.boundary == Boundary::Periodic;
        let p = &self.p;
        let (u_free, v_free) = (&self.u_free, &self.v_free);
        self.u
            .par_chunks_mut(nx + 1)
            .enumerate()
            .with_min_len(rows_per_job(nx + 1))
            .for_each(|(j, row)| {
                let free = &u_free[j * (nx + 1)..][..nx + 1];
                let pr = &p[j * nx..][..nx];
                // Outside the domain: periodic wraps, open edges hold p = 0 (closed edges are
                // not free).
                let (outside_l, outside_r) = if periodic {
                    (pr[nx - 1], pr[0])
                } else {
                    (0.0, 0.0)
                };
                let grad = |x: f32, pr: f32, pl: f32| flush(x - (pr - pl) / hx);
                row[0] = if free[0] != 0 {
                    grad(row[0], pr[0], outside_l)
                } else {
                    0.0
                };
                row[nx] = if free[nx] != 0 {
                    grad(row[nx], outside_r, pr[nx - 1])
                } else {
                    0.0
                };
                subtract_row(&mut row[1..nx], &free[1..nx], &pr[1..], &pr[..nx - 1], hx);
            });
        let zero = vec![0.0f32; nx];
        self.v
            .par_chunks_mut(nx)
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, row)| {
                let prow = |j: usize| &p[j * nx..][..nx];
                let below = match j {
                    0 if periodic => prow(ny - 1),
                    0 => &zero,
                    _ => prow(j - 1),
                };
                let above = match j {
                    _ if j < ny => prow(j),
                    _ if periodic => prow(0),
                    _ => &zero,
                };
                subtract_row(row, &v_free[j * nx..][..nx], above, below, hz);
            });
        self.sync_periodic();
    }

    fn geometry(&self) -> Geometry {
        Geometry {
            nx: self.nx,
            ny: self.ny,
            hx: self.hx,
            hz: self.hz,
            periodic: self.params.boundary == Boundary::Periodic,
        }
    }

    /// With periodic boundaries the last face column/row is the first one.
    fn sync_periodic(&mut self) {
        if self.params.boundary != Boundary::Periodic {
            return;
        }
        let (nx, ny) = (self.nx, self.ny);
        for j in 0..ny {
            self.u[j * (nx + 1) + nx] = self.u[j * (nx + 1)];
        }
        let (first, rest) = self.v.split_at_mut(nx);
        rest[(ny - 1) * nx..ny * nx].copy_from_slice(first);
    }

    /// The solver's own velocity (m/s) at the centre of cell `(i, j)`, the average of its
    /// faces, before any terrain shapes it.
    pub fn cell_velocity(&self, i: usize, j: usize) -> [f32; 2] {
        let nx = self.nx;
        [
            0.5 * (self.u[j * (nx + 1) + i] + self.u[j * (nx + 1) + i + 1]),
            0.5 * (self.v[j * nx + i] + self.v[(j + 1) * nx + i]),
        ]
    }

    /// The wind's faces as they leave the solver: the solver's own over flat ground, shaped
    /// by the terrain ([`TerrainField::shape_faces`], walls and solids kept still) where the
    /// layout has one.
    /// The faces' free flags `(u, v)`: 1 where a face may move (not a wall, not a solid's
    /// side).
    pub fn free_faces(&self) -> (&[u8], &[u8]) {
        (&self.u_free, &self.v_free)
    }

    pub fn wind_faces(&self) -> (std::borrow::Cow<'_, [f32]>, std::borrow::Cow<'_, [f32]>) {
        use std::borrow::Cow;
        match &self.terrain {
            None => (Cow::Borrowed(&self.u[..]), Cow::Borrowed(&self.v[..])),
            Some(t) => {
                let (u, v) = t.shape_faces((&self.u, &self.v), (&self.u_free, &self.v_free));
                (Cow::Owned(u), Cow::Owned(v))
            }
        }
    }

    /// The wind, cell-centred, `nx × ny` pairs `[x, z]` in m/s, row-major: the mean of each
    /// cell's [`Self::wind_faces`] (the terrain-shaped field; [`Self::cell_velocity`] is the
    /// solver's own).
    pub fn velocity_field(&self) -> Vec<[f32; 2]> {
        let (u, v) = self.wind_faces();
        cell_centred(self.nx, self.ny, &u, &v)
    }

    /// The wind at a world point (bilinear between faces), terrain-shaped. Over terrain this
    /// shapes the whole field for the one point: to read many points, take a
    /// [`Self::wind_sampler`] once.
    pub fn velocity_at(&self, p: [f32; 2]) -> [f32; 2] {
        self.wind_sampler().at(p)
    }

    /// The terrain-shaped wind ([`Self::wind_faces`]) shaped once, to read at many points.
    pub fn wind_sampler(&self) -> WindSampler<'_> {
        let (u, v) = self.wind_faces();
        WindSampler {
            g: self.geometry(),
            origin: self.origin,
            u,
            v,
        }
    }

    /// The cell containing world point `p`, if inside the grid.
    pub fn cell_at(&self, p: [f32; 2]) -> Option<(usize, usize)> {
        let x = ((p[0] - self.origin[0]) / self.hx).floor();
        let z = ((p[1] - self.origin[1]) / self.hz).floor();
        (x >= 0.0 && z >= 0.0 && (x as usize) < self.nx && (z as usize) < self.ny)
            .then_some((x as usize, z as usize))
    }

    /// Recomputes the divergence of the current field and returns its RMS over fluid cells.
    pub fn divergence_rms(&mut self) -> f32 {
        self.compute_divergence();
        self.fluid_rms(&self.div)
    }

    /// RMS of a cell field over the fluid cells.
    fn fluid_rms(&self, field: &[f32]) -> f32 {
        let (sum, n) = field
            .iter()
            .zip(&self.solid)
            .filter(|&(_, &s)| s == 0)
            .fold((0.0f64, 0usize), |(s, n), (d, _)| {
                (s + f64::from(d * d), n + 1)
            });
        (sum / n.max(1) as f64).sqrt() as f32
    }

    /// Kinetic energy per unit density, `½ Σ |u|²` over faces (times cell area).
    pub fn kinetic_energy(&self) -> f64 {
        let a = f64::from(self.hx * self.hz);
        let su: f64 = self.u.iter().map(|x| f64::from(x * x)).sum();
        let sv: f64 = self.v.iter().map(|x| f64::from(x * x)).sum();
        0.5 * a * (su + sv)
    }

    /// Mutable access to the raw face velocities, for tests and tools that seed a field.
    pub fn faces_mut(&mut self) -> (&mut [f32], &mut [f32]) {
        (&mut self.u, &mut self.v)
    }

    /// Zeroes non-free faces and syncs periodic copies after outside changes to the faces.
    pub fn enforce_boundaries(&mut self) {
        for (u, f) in self.u.iter_mut().zip(&self.u_free) {
            if *f == 0 {
                *u = 0.0;
            }
        }
        for (v, f) in self.v.iter_mut().zip(&self.v_free) {
            if *f == 0 {
                *v = 0.0;
            }
        }
        self.sync_periodic();
    }

    /// Solid (1) or fluid (0) per cell.
    pub fn is_solid(&self, i: usize, j: usize) -> bool {
        self.solid[j * self.nx + i] != 0
    }

    /// The bytes of the velocity faces, for determinism checks.
    pub fn state_bytes(&self) -> Vec<u8> {
        self.u
            .iter()
            .chain(&self.v)
            .chain(&self.p)
            .flat_map(|x| x.to_le_bytes())
            .collect()
    }
}

/// The cell-centred velocity of faces `u` (`(nx + 1) × ny`) and `v` (`nx × (ny + 1)`): each
/// cell's mean, `nx × ny` pairs, row-major.
pub fn cell_centred(nx: usize, ny: usize, u: &[f32], v: &[f32]) -> Vec<[f32; 2]> {
    (0..ny)
        .flat_map(|j| (0..nx).map(move |i| (i, j)))
        .map(|(i, j)| {
            [
                0.5 * (u[j * (nx + 1) + i] + u[j * (nx + 1) + i + 1]),
                0.5 * (v[j * nx + i] + v[(j + 1) * nx + i]),
            ]
        })
        .collect()
}

/// Runs shorter than this apart are merged, so the Jacobi row never switches paths for a few
/// cells (its fast loop wants whole vectors).
const RUN_GAP: usize = 16;

/// The runs `(start, end)` of interior cells of a row of pressure flags (cells 1..n − 1)
/// whose flags are not [`ALL_FLUID`], merged across gaps shorter than [`RUN_GAP`].
fn irregular_runs(flags: &[u8]) -> Vec<(usize, usize)> {
    runs_where_not(flags.len(), |i| flags[i] == ALL_FLUID)
}

/// The runs `(start, end)` of interior cells `i` of a row of `n` (1..n − 1) where
/// `regular(i)` is false, merged across gaps shorter than [`RUN_GAP`].
fn runs_where_not(n: usize, regular: impl Fn(usize) -> bool) -> Vec<(usize, usize)> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for i in 1..n.saturating_sub(1) {
        if regular(i) {
            continue;
        }
        match runs.last_mut() {
            Some(last) if i - last.1 < RUN_GAP => last.1 = i + 1,
            _ => runs.push((i, i + 1)),
        }
    }
    runs
}

/// `a` where `c` holds, else `b`, as bit masks: both are computed for every lane. With a
/// plain `if`, LLVM loads only what the taken side reads: from a selected address (on AVX2 a
/// scalar load per lane) or with masked loads (`vmaskmovps`, slow on AVX2 hosts; AVX-512
/// masks are cheap, which made such loops 1.2–1.4× slower on AVX2 than on AVX-512).
#[inline(always)]
fn bit_select(c: bool, a: f32, b: f32) -> f32 {
    let m = (c as u32).wrapping_neg();
    f32::from_bits((a.to_bits() & m) | (b.to_bits() & !m))
}

/// The smallest magnitude the passes store: 2⁻⁶⁰ ≈ 8.7 × 10⁻¹⁹, in m/s for the faces and in
/// the pressure's units, so far below any wind that flushing it changes nothing a user
/// sees. See [`flush`].
pub(crate) const TINY: f32 = f32::from_bits(0x2180_0000);

/// `x`, or 0 where `|x| < TINY` (NaN kept). Every pass that writes the faces or the
/// pressure (forces, confinement, the Jacobi sweeps and the multigrid's fine-grid
/// relaxation, gradient, advection's result) flushes what it writes, as the reference passes
/// do, so the fields hold no subnormal numbers: without it the wind's spreading fronts fill
/// 2–6 % of a 1000² grid's values with them in its first steps, and on Intel cores every
/// vector instruction that meets one takes a microcode assist (an Intel Xeon's pressure pass
/// took 2–4× as long on the arrow layouts as it does now; docs/PERFORMANCE.md). Differences of stored values cannot be
/// subnormal then (their spacing at 2⁻⁶⁰ is 2⁻⁸³), so the curl and the divergence need no
/// flush, and 2⁻⁶⁰ rather than anything smaller keeps the squares of such values, which the
/// confinement takes, normal too (but where two values cancel almost exactly).
#[inline(always)]
pub(crate) fn flush(x: f32) -> f32 {
    bit_select(x.abs() < TINY, 0.0, x)
}

/// `row ← row − (hi − lo) / h` on the free faces of a row (0 on the others): the gradient
/// subtraction's interior, branch-free over equal-length slices so it vectorises.
#[simd_kernel]
fn subtract_row(row: &mut [f32], free: &[u8], hi: &[f32], lo: &[f32], h: f32) {
    let n = row.len();
    let (free, hi, lo) = (&free[..n], &hi[..n], &lo[..n]);
    for i in 0..n {
        row[i] = bit_select(free[i] != 0, flush(row[i] - (hi[i] - lo[i]) / h), 0.0);
    }
}

/// Rows per rayon job for a row of `width` cells: enough work (~8k cells) that scheduling
/// overhead stays small, while still splitting a grid over all threads.
fn rows_per_job(width: usize) -> usize {
    (8_192 / width.max(1)).max(1)
}

/// The first and last index of a row of `n` (one index when `n` is 1): the cells whose
/// neighbours wrap or clamp, handled apart from the interior loops.
fn row_ends(n: usize) -> impl Iterator<Item = usize> {
    [0, n - 1].into_iter().take(if n > 1 { 2 } else { 1 })
}

/// Neighbour indices `(lower, upper)` of `i` on an axis of `n` cells: wrapped or clamped.
#[inline]
fn neighbours(i: usize, n: usize, periodic: bool) -> (usize, usize) {
    if periodic {
        ((i + n - 1) % n, (i + 1) % n)
    } else {
        (i.saturating_sub(1), (i + 1).min(n - 1))
    }
}

#[inline]
fn clamp_speed(x: f32) -> f32 {
    x.clamp(-MAX_SPEED, MAX_SPEED)
}

/// The wind of one moment, shaped once ([`Solver::wind_sampler`]).
pub struct WindSampler<'a> {
    g: Geometry,
    origin: [f32; 2],
    u: std::borrow::Cow<'a, [f32]>,
    v: std::borrow::Cow<'a, [f32]>,
}

impl WindSampler<'_> {
    /// The wind at a world point, m/s, bilinear between faces: [`Solver::velocity_at`].
    pub fn at(&self, p: [f32; 2]) -> [f32; 2] {
        let x = (p[0] - self.origin[0]) / self.g.hx;
        let z = (p[1] - self.origin[1]) / self.g.hz;
        [
            sample_u(&self.g, &self.u, x, z).0,
            sample_v(&self.g, &self.v, x, z).0,
        ]
    }
}
