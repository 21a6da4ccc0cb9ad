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
use crate::doc::{Advection, Boundary, Layout, SOLVER_BYTES_PER_CELL, SimParams};
use multiversion::multiversion;
use rayon::prelude::*;
use std::ops::{Range, RangeInclusive};
use std::time::Instant;

mod reference;

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
            + self.pressure
            + self.gradient
            + self.advection
    }

    pub fn as_pairs(&self) -> [(&'static str, f64); 7] {
        [
            ("forces", self.forces),
            ("curl", self.curl),
            ("confinement", self.confinement),
            ("divergence", self.divergence),
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
    /// Simulation time in seconds.
    pub time: f32,
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
    /// Rows whose interior cells all have four fluid neighbours (the Jacobi fast path).
    row_regular: Vec<bool>,
    layout: Layout,
    ambient: Ambient,
    pub timings: PassTimes,
    /// Faces the last forces pass visited (rows a splat or ambient layer reaches).
    pub force_faces: usize,
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
        let row_regular = (0..ny)
            .map(|j| (1..nx.saturating_sub(1)).all(|i| flags[j * nx + i] == ALL_FLUID))
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
            time: 0.0,
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
            row_regular,
            layout: layout.clone(),
            ambient: Ambient::new(layout),
            timings: PassTimes::default(),
            force_faces: 0,
        }
    }

    /// Bytes of grid memory this solver holds (checked against the validation budget).
    pub fn memory_bytes(&self) -> u64 {
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

    /// Upper bound used by validation for the same grid.
    pub fn memory_budget(&self) -> u64 {
        (self.nx * self.ny) as u64 * SOLVER_BYTES_PER_CELL
    }

    /// Replaces the layout the forces come from (an edit), keeping the running field. Grid,
    /// obstacles and boundary changes need a new solver.
    pub fn set_layout(&mut self, layout: &Layout) {
        self.layout = layout.clone();
        self.ambient = Ambient::new(layout);
        self.params = layout.sim;
    }

    /// Advances the simulation by `params.dt` (in `params.substeps` substeps).
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
        self.compute_curl();
        let t2 = Instant::now();
        self.confine_vorticity(dt);
        let t3 = Instant::now();
        self.compute_divergence();
        let t4 = Instant::now();
        self.solve_pressure();
        let t5 = Instant::now();
        self.subtract_gradient();
        let t6 = Instant::now();
        self.advect(dt);
        let t7 = Instant::now();
        self.time += dt;
        let tm = &mut self.timings;
        tm.forces += (t1 - t0).as_secs_f64();
        tm.curl += (t2 - t1).as_secs_f64();
        tm.confinement += (t3 - t2).as_secs_f64();
        tm.divergence += (t4 - t3).as_secs_f64();
        tm.pressure += (t5 - t4).as_secs_f64();
        tm.gradient += (t6 - t5).as_secs_f64();
        tm.advection += (t7 - t6).as_secs_f64();
    }

    /// Step 1: AGC arrow splats and the pull toward the ambient wind. Both read the velocity
    /// before the pass, so the u and v faces see the same state.
    pub fn apply_forces(&mut self, dt: f32) {
        self.apply_forces_with(dt, |f, u, v, inc, free, is_v| {
            f.increments(u, v, inc, free, is_v)
        });
    }

    /// Step 1 with the given kernel for one component's increments (fast or reference).
    fn apply_forces_with(&mut self, dt: f32, increments: Increments) {
        let splats = agc_splats(&self.layout, self.time);
        self.ambient.set_time(self.time);
        let coupling = if self.ambient.is_empty() {
            0.0
        } else {
            1.0 - (-self.params.ambient_coupling * dt).exp()
        };
        let f = Forcing {
            g: self.geometry(),
            origin: self.origin,
            splats: &splats,
            bounds: splats.iter().map(ArrowSplat::bounds).collect(),
            ambient: &self.ambient,
            coupling,
            response: self.params.arrow_response,
            dt,
        };
        if splats.is_empty() && coupling == 0.0 {
            self.force_faces = 0;
            return;
        }
        let rows_u = increments(&f, &self.u, &self.v, &mut self.u_tmp, &self.u_free, false);
        let rows_v = increments(&f, &self.u, &self.v, &mut self.v_tmp, &self.v_free, true);
        self.force_faces = add_rows(&mut self.u, &self.u_tmp, &rows_u, self.nx + 1)
            + add_rows(&mut self.v, &self.v_tmp, &rows_v, self.nx);
        self.sync_periodic();
    }

    /// Step 2: vorticity at cell centres, `∂v/∂x − ∂u/∂z`, central differences (one-sided at
    /// non-periodic edges).
    pub fn compute_curl(&mut self) {
        let (nx, ny, hx, hz) = (self.nx, self.ny, self.hx, self.hz);
        let periodic = self.params.boundary == Boundary::Periodic;
        let (u, v, solid) = (&self.u, &self.v, &self.solid);
        let w = nx + 1;
        self.curl
            .par_chunks_mut(nx)
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, row)| {
                let (jb, jt) = neighbours(j, ny, periodic);
                let dz = hz * (jt as f32 - jb as f32).abs().clamp(1.0, 2.0);
                let (ub, ut) = (&u[jb * w..][..w], &u[jt * w..][..w]);
                let (v0, v1) = (&v[j * nx..][..nx], &v[(j + 1) * nx..][..nx]);
                let sd = &solid[j * nx..][..nx];
                for i in row_ends(nx) {
                    let (il, ir) = neighbours(i, nx, periodic);
                    let vc = |i: usize| 0.5 * (v0[i] + v1[i]);
                    let dx = hx * (ir as f32 - il as f32).abs().clamp(1.0, 2.0);
                    let dvdx = (vc(ir) - vc(il)) / dx;
                    let dudz = (0.5 * (ut[i] + ut[i + 1]) - 0.5 * (ub[i] + ub[i + 1])) / dz;
                    row[i] = if sd[i] != 0 { 0.0 } else { dvdx - dudz };
                }
                let Some(n) = nx.checked_sub(2) else { return };
                let dx = hx * 2.0; // |ir − il| = 2 inside the row
                let (o, sd) = (&mut row[1..=n], &sd[1..=n]);
                let (v0l, v0r, v1l, v1r) = (&v0[..n], &v0[2..], &v1[..n], &v1[2..]);
                let (ub0, ub1, ut0, ut1) = (&ub[1..=n], &ub[2..=n + 1], &ut[1..=n], &ut[2..=n + 1]);
                for k in 0..n {
                    let dvdx = (0.5 * (v0r[k] + v1r[k]) - 0.5 * (v0l[k] + v1l[k])) / dx;
                    let dudz = (0.5 * (ut0[k] + ut1[k]) - 0.5 * (ub0[k] + ub1[k])) / dz;
                    o[k] = if sd[k] != 0 { 0.0 } else { dvdx - dudz };
                }
            });
    }

    /// Step 3: vorticity confinement, `f = ε h w (N_z, −N_x)` with `N` the unit gradient of
    /// `|w|`, pushing along the rotation so small eddies survive advection.
    pub fn confine_vorticity(&mut self, dt: f32) {
        let eps = self.params.vorticity;
        if eps <= 0.0 {
            return;
        }
        let (nx, ny) = (self.nx, self.ny);
        let periodic = self.params.boundary == Boundary::Periodic;
        let h = self.hx.min(self.hz);
        let curl = &self.curl;
        #[inline(always)]
        fn force(eps_h: (f32, f32), w: f32, l: f32, r: f32, b: f32, t: f32) -> (f32, f32) {
            let gx = 0.5 * (r.abs() - l.abs());
            let gz = 0.5 * (t.abs() - b.abs());
            let len = (gx * gx + gz * gz).sqrt() + 1e-5;
            let s = eps_h.0 * eps_h.1 * w / len;
            (s * gz, -s * gx)
        }
        // Cell-centred force: x into p_tmp, z into div (both free until the divergence pass).
        self.p_tmp
            .par_chunks_mut(nx)
            .zip(self.div.par_chunks_mut(nx))
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, (fx, fz))| {
                let (jb, jt) = neighbours(j, ny, periodic);
                let c = &curl[j * nx..][..nx];
                let (cb, ct) = (&curl[jb * nx..][..nx], &curl[jt * nx..][..nx]);
                for i in row_ends(nx) {
                    let (il, ir) = neighbours(i, nx, periodic);
                    (fx[i], fz[i]) = force((eps, h), c[i], c[il], c[ir], cb[i], ct[i]);
                }
                let Some(n) = nx.checked_sub(2) else { return };
                let (fxi, fzi) = (&mut fx[1..=n], &mut fz[1..=n]);
                let (cl, cc, cr) = (&c[..n], &c[1..=n], &c[2..]);
                let (cb, ct) = (&cb[1..=n], &ct[1..=n]);
                for k in 0..n {
                    (fxi[k], fzi[k]) = force((eps, h), cc[k], cl[k], cr[k], cb[k], ct[k]);
                }
            });
        let (fx, fz) = (&self.p_tmp, &self.div);
        let (u_free, v_free) = (&self.u_free, &self.v_free);
        let add = |x: f32, a: f32, b: f32| clamp_speed(x + dt * 0.5 * (a + b));
        self.u
            .par_chunks_mut(nx + 1)
            .enumerate()
            .with_min_len(rows_per_job(nx + 1))
            .for_each(|(j, row)| {
                let free = &u_free[j * (nx + 1)..][..nx + 1];
                let f = &fx[j * nx..][..nx];
                // End faces: the wrapped cell when periodic, else the one cell beside them.
                let (first, last) = if periodic { (nx - 1, 0) } else { (0, nx - 1) };
                if free[0] != 0 {
                    row[0] = add(row[0], f[first], f[0]);
                }
                if free[nx] != 0 {
                    row[nx] = add(row[nx], f[nx - 1], f[last]);
                }
                let (r, fr) = (&mut row[1..nx], &free[1..nx]);
                let (a, b) = (&f[..nx - 1], &f[1..]);
                for k in 0..nx - 1 {
                    r[k] = if fr[k] != 0 {
                        add(r[k], a[k], b[k])
                    } else {
                        r[k]
                    };
                }
            });
        self.v
            .par_chunks_mut(nx)
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, row)| {
                let jb = match j {
                    0 if periodic => ny - 1,
                    0 => 0,
                    _ => j - 1,
                };
                let jt = if j == ny {
                    if periodic { 0 } else { ny - 1 }
                } else {
                    j
                };
                let free = &v_free[j * nx..][..nx];
                let (a, b) = (&fz[jb * nx..][..nx], &fz[jt * nx..][..nx]);
                for i in 0..nx {
                    row[i] = if free[i] != 0 {
                        add(row[i], a[i], b[i])
                    } else {
                        row[i]
                    };
                }
            });
        self.sync_periodic();
    }

    /// Step 4: divergence per cell, `(u_R − u_L)/hx + (v_T − v_B)/hz` (0 in solids).
    pub fn compute_divergence(&mut self) {
        let (nx, hx, hz) = (self.nx, self.hx, self.hz);
        let (u, v, solid) = (&self.u, &self.v, &self.solid);
        self.div
            .par_chunks_mut(nx)
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, row)| {
                divergence_row(row, j, nx, hx, hz, u, v, solid);
            });
    }

    /// Steps 5: warm start and Jacobi iterations for `∇²p = div`, blocked for cache: each band
    /// of rows runs many iterations while its rows are in cache (see [`jacobi_band`]). The
    /// result is bit-for-bit that of [`Self::jacobi_iteration`] repeated.
    pub fn solve_pressure(&mut self) {
        let decay = self.params.pressure_decay;
        let k = self.params.pressure_iterations as usize;
        if k == 0 {
            self.p.par_iter_mut().for_each(|p| *p *= decay);
            return;
        }
        let groups = k.div_ceil(MAX_BLOCK_LEVELS);
        let mut done = 0;
        for g in 0..groups {
            let levels = (k - done).div_ceil(groups - g);
            // The warm start's decay is applied as the first block reads p (×1 is exact).
            let scale = if g == 0 { decay } else { 1.0 };
            self.jacobi_blocked(levels, scale);
            done += levels;
        }
    }

    /// `levels` Jacobi iterations from `p × scale` into `p` (through `p_tmp`).
    fn jacobi_blocked(&mut self, levels: usize, scale: f32) {
        let (nx, ny) = (self.nx, self.ny);
        let threads = rayon::current_num_threads();
        // Two bands per thread for balance, but each well over the 2 × levels ghost rows a
        // band recomputes at its ends.
        let band = ny.div_ceil(2 * threads).max(4 * levels).min(ny);
        let ctx = JacobiCtx {
            nx,
            ny,
            st: self.stencil(),
            src: &self.p,
            div: &self.div,
            flags: &self.flags,
            inv_w: &self.inv_w,
            regular: &self.row_regular,
            wraps: self.params.boundary == Boundary::Periodic,
            scale,
        };
        self.p_tmp
            .par_chunks_mut(band * nx)
            .enumerate()
            .for_each(|(b, out)| {
                let a = b * band;
                jacobi_band(&ctx, out, a, a + out.len() / nx, levels);
            });
        std::mem::swap(&mut self.p, &mut self.p_tmp);
    }

    fn stencil(&self) -> Stencil {
        Stencil::new(self.hx, self.hz)
    }

    /// One plain Jacobi sweep over the whole grid: `p ← (Σ w_n p_n − div) / Σ w_n` over the
    /// neighbours that take part (solids and closed walls: Neumann, dropped; open edges:
    /// p = 0 outside). The reference for the blocked solve.
    pub fn jacobi_iteration(&mut self) {
        let (nx, ny) = (self.nx, self.ny);
        let st = self.stencil();
        let (p, div, flags, regular) = (&self.p, &self.div, &self.flags, &self.row_regular);
        let inv_w = &self.inv_w;
        let wraps = self.params.boundary == Boundary::Periodic;
        self.p_tmp
            .par_chunks_mut(nx)
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, out)| {
                // Rows beyond the grid have zero weight unless periodic: pass the row itself,
                // as the blocked solve does.
                let (jb, jt) = if wraps {
                    ((j + ny - 1) % ny, (j + 1) % ny)
                } else {
                    (j.saturating_sub(1), (j + 1).min(ny - 1))
                };
                jacobi_row(
                    &st,
                    out,
                    &p[jb * nx..(jb + 1) * nx],
                    &p[j * nx..(j + 1) * nx],
                    &p[jt * nx..(jt + 1) * nx],
                    &div[j * nx..(j + 1) * nx],
                    &flags[j * nx..(j + 1) * nx],
                    &inv_w[j * nx..(j + 1) * nx],
                    regular[j],
                );
            });
        std::mem::swap(&mut self.p, &mut self.p_tmp);
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
                let grad = |x: f32, pr: f32, pl: f32| x - (pr - pl) / hx;
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
                let (r, fr) = (&mut row[1..nx], &free[1..nx]);
                let (pl, pc) = (&pr[..nx - 1], &pr[1..]);
                for k in 0..nx - 1 {
                    r[k] = if fr[k] != 0 {
                        grad(r[k], pc[k], pl[k])
                    } else {
                        0.0
                    };
                }
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
                let free = &v_free[j * nx..][..nx];
                for i in 0..nx {
                    row[i] = if free[i] != 0 {
                        row[i] - (above[i] - below[i]) / hz
                    } else {
                        0.0
                    };
                }
            });
        self.sync_periodic();
    }

    /// Step 7: advection (semi-Lagrangian or limited MacCormack) with dissipation
    /// `vel / (1 + dissipation × dt)` folded into the same write.
    pub fn advect(&mut self, dt: f32) {
        self.advect_with(dt, advect_faces, maccormack);
    }

    /// Advection with the given kernels for one face field (the fast or the reference ones).
    fn advect_with(&mut self, dt: f32, advect_faces: FaceKernel, maccormack: FaceKernel) {
        let g = self.geometry();
        let keep = 1.0 / (1.0 + self.params.velocity_dissipation * dt);
        match self.params.advection {
            Advection::SemiLagrangian => {
                let (u, v) = (&self.u, &self.v);
                advect_faces(&g, u, v, u, &mut self.u_tmp, dt, keep, &self.u_free, false);
                advect_faces(&g, u, v, v, &mut self.v_tmp, dt, keep, &self.v_free, true);
                std::mem::swap(&mut self.u, &mut self.u_tmp);
                std::mem::swap(&mut self.v, &mut self.v_tmp);
            }
            Advection::MacCormack => {
                // Forward: φ̂ = A(φ); backward: φ̌ = A⁻¹(φ̂); φ' = φ̂ + (φ − φ̌)/2, clamped to
                // the forward stencil's range so the correction cannot create new extrema.
                let (u, v) = (&self.u, &self.v);
                advect_faces(&g, u, v, u, &mut self.u_tmp, dt, 1.0, &self.u_free, false);
                advect_faces(&g, u, v, v, &mut self.v_tmp, dt, 1.0, &self.v_free, true);
                advect_faces(
                    &g,
                    u,
                    v,
                    &self.u_tmp,
                    &mut self.u_hat,
                    -dt,
                    1.0,
                    &self.u_free,
                    false,
                );
                advect_faces(
                    &g,
                    u,
                    v,
                    &self.v_tmp,
                    &mut self.v_hat,
                    -dt,
                    1.0,
                    &self.v_free,
                    true,
                );
                maccormack(
                    &g,
                    u,
                    v,
                    &self.u_tmp,
                    &mut self.u_hat,
                    dt,
                    keep,
                    &self.u_free,
                    false,
                );
                maccormack(
                    &g,
                    u,
                    v,
                    &self.v_tmp,
                    &mut self.v_hat,
                    dt,
                    keep,
                    &self.v_free,
                    true,
                );
                std::mem::swap(&mut self.u, &mut self.u_hat);
                std::mem::swap(&mut self.v, &mut self.v_hat);
            }
        }
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

    /// Velocity (m/s) at the centre of cell `(i, j)`: the average of its faces.
    pub fn cell_velocity(&self, i: usize, j: usize) -> [f32; 2] {
        let nx = self.nx;
        [
            0.5 * (self.u[j * (nx + 1) + i] + self.u[j * (nx + 1) + i + 1]),
            0.5 * (self.v[j * nx + i] + self.v[(j + 1) * nx + i]),
        ]
    }

    /// Cell-centred velocity field, `nx × ny` pairs `[x, z]` in m/s, row-major.
    pub fn velocity_field(&self) -> Vec<[f32; 2]> {
        (0..self.ny)
            .flat_map(|j| (0..self.nx).map(move |i| (i, j)))
            .map(|(i, j)| self.cell_velocity(i, j))
            .collect()
    }

    /// Velocity at a world point (bilinear between cell centres).
    pub fn velocity_at(&self, p: [f32; 2]) -> [f32; 2] {
        let g = self.geometry();
        let x = (p[0] - self.origin[0]) / self.hx;
        let z = (p[1] - self.origin[1]) / self.hz;
        [sample_u(&g, &self.u, x, z).0, sample_v(&g, &self.v, x, z).0]
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
        let (sum, n) = self
            .div
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

#[allow(clippy::too_many_arguments)]
fn divergence_row(
    row: &mut [f32],
    j: usize,
    nx: usize,
    hx: f32,
    hz: f32,
    u: &[f32],
    v: &[f32],
    solid: &[u8],
) {
    let ur = &u[j * (nx + 1)..(j + 1) * (nx + 1)];
    let vb = &v[j * nx..(j + 1) * nx];
    let vt = &v[(j + 1) * nx..(j + 2) * nx];
    let s = &solid[j * nx..(j + 1) * nx];
    for i in 0..nx {
        row[i] = if s[i] != 0 {
            0.0
        } else {
            (ur[i + 1] - ur[i]) / hx + (vt[i] - vb[i]) / hz
        };
    }
}

/// At most this many Jacobi iterations run per blocked pass over the grid: more would make the
/// ghost rows each band recomputes (≈ levels² rows) outweigh the cache savings.
const MAX_BLOCK_LEVELS: usize = 24;

/// Weights of the pressure stencil: `1/hx²`, `1/hz²`, and the inverse of their sum for a cell
/// with four fluid neighbours.
#[derive(Clone, Copy)]
struct Stencil {
    wx: f32,
    wz: f32,
    inv_regular: f32,
}

impl Stencil {
    fn new(hx: f32, hz: f32) -> Self {
        let (wx, wz) = (1.0 / (hx * hx), 1.0 / (hz * hz));
        Self {
            wx,
            wz,
            inv_regular: 1.0 / (2.0 * wx + 2.0 * wz),
        }
    }

    /// `1 / Σw` for a cell with pressure flags `fl` (fluid and open-edge neighbours count;
    /// 0 when none does). For four fluid neighbours this is exactly `inv_regular`.
    fn inv_weight(&self, fl: u8) -> f32 {
        let n =
            |b: u8| f32::from(u8::from(fl & b != 0)) + f32::from(u8::from(fl & (b << EDGE) != 0));
        let ws = self.wx * (n(L) + n(R)) + self.wz * (n(B) + n(T));
        if ws > 0.0 { 1.0 / ws } else { 0.0 }
    }
}

/// One Jacobi row from the previous iterate's rows `below`, `row`, `above` (rows wrap at the
/// grid's ends): `p = (wx (p_L + p_R) + wz (p_B + p_T) − div) / Σw`, where a neighbour that
/// does not take part (solid, wall, open edge at p = 0) contributes 0 and `inv_w` holds the
/// cell's `1 / Σw` (0 for cells outside the solve). Branch-free, so it vectorises; rows whose
/// cells all have four fluid neighbours skip the flags (the same arithmetic, the same bits).
#[allow(clippy::too_many_arguments)]
#[multiversion(targets = "simd")]
fn jacobi_row(
    st: &Stencil,
    out: &mut [f32],
    below: &[f32],
    row: &[f32],
    above: &[f32],
    d: &[f32],
    f: &[u8],
    inv_w: &[f32],
    regular: bool,
) {
    let nx = out.len();
    let Stencil {
        wx,
        wz,
        inv_regular,
    } = *st;
    #[inline(always)]
    fn pick(fl: u8, bit: u8, x: f32) -> f32 {
        if fl & bit != 0 { x } else { 0.0 }
    }
    let cell = |i: usize, l: f32, r: f32| {
        let fl = f[i];
        (wx * (pick(fl, L, l) + pick(fl, R, r))
            + wz * (pick(fl, B, below[i]) + pick(fl, T, above[i]))
            - d[i])
            * inv_w[i]
    };
    // The row's ends wrap to the other end (used only where periodic flags say so).
    out[0] = cell(0, row[nx - 1], row[1 % nx]);
    if nx == 1 {
        return;
    }
    out[nx - 1] = cell(nx - 1, row[nx - 2], row[0]);
    let n = nx - 2;
    let (o, l, r) = (&mut out[1..=n], &row[..n], &row[2..n + 2]);
    let (b, a, dd) = (&below[1..=n], &above[1..=n], &d[1..=n]);
    if regular {
        for i in 0..n {
            o[i] = (wx * (l[i] + r[i]) + wz * (b[i] + a[i]) - dd[i]) * inv_regular;
        }
    } else {
        let (ff, iw) = (&f[1..=n], &inv_w[1..=n]);
        for i in 0..n {
            let fl = ff[i];
            o[i] = (wx * (pick(fl, L, l[i]) + pick(fl, R, r[i]))
                + wz * (pick(fl, B, b[i]) + pick(fl, T, a[i]))
                - dd[i])
                * iw[i];
        }
    }
}

/// What every band of a blocked Jacobi pass reads.
struct JacobiCtx<'a> {
    nx: usize,
    ny: usize,
    st: Stencil,
    src: &'a [f32],
    div: &'a [f32],
    flags: &'a [u8],
    inv_w: &'a [f32],
    regular: &'a [bool],
    /// Periodic: rows wrap around, so ghost rows continue past the grid's ends.
    wraps: bool,
    scale: f32,
}

/// `levels` Jacobi iterations for output rows `a..b`, written to `out`, in one sweep down the
/// band: iteration `t` trails iteration `t − 1` by one row, and each keeps only its last three
/// rows (a ring), so the band's working set stays in cache while every iteration runs. To
/// produce rows `a..b` after `levels` iterations, iteration `t` must cover `levels − t` extra
/// rows on each side (the trapezoid); those ghost rows are recomputed by the neighbouring
/// bands, with the same arithmetic, so the result does not depend on the banding.
fn jacobi_band(c: &JacobiCtx, out: &mut [f32], a: usize, b: usize, levels: usize) {
    let (nx, ny) = (c.nx, c.ny);
    let k = levels as isize;
    let (a, b) = (a as isize, b as isize);
    let lo = |t: isize| {
        let r = a - (k - t);
        if c.wraps { r } else { r.max(0) }
    };
    let hi = |t: isize| {
        let r = b + (k - t);
        if c.wraps { r } else { r.min(ny as isize) }
    };
    let wrap = |r: isize| r.rem_euclid(ny as isize) as usize;
    let slot = |r: isize| r.rem_euclid(3) as usize * nx;
    // Rings for iterations 0..levels (0 is the scaled input); the last writes to `out`.
    let mut ring = vec![0.0f32; levels * 3 * nx];
    for r in lo(0)..hi(0) + k {
        if r < hi(0) {
            let src = &c.src[wrap(r) * nx..][..nx];
            let dst = &mut ring[slot(r)..][..nx];
            for (d, s) in dst.iter_mut().zip(src) {
                *d = s * c.scale;
            }
        }
        for t in 1..=k {
            let s = r - t;
            if s < lo(t) || s >= hi(t) {
                continue;
            }
            // Without wrapping, the first and last rows have no neighbour beyond the grid
            // (its weight is zero): any finite row will do, so pass the row itself.
            let sb = if s > lo(t - 1) { s - 1 } else { s };
            let sa = if s + 1 < hi(t - 1) { s + 1 } else { s };
            let (prev, cur) = ring.split_at_mut(t as usize * 3 * nx);
            let prev = &prev[(t as usize - 1) * 3 * nx..];
            let j = wrap(s);
            let dst = if t == k {
                &mut out[(s - a) as usize * nx..][..nx]
            } else {
                &mut cur[slot(s)..][..nx]
            };
            jacobi_row(
                &c.st,
                dst,
                &prev[slot(sb)..][..nx],
                &prev[slot(s)..][..nx],
                &prev[slot(sa)..][..nx],
                &c.div[j * nx..][..nx],
                &c.flags[j * nx..][..nx],
                &c.inv_w[j * nx..][..nx],
                c.regular[j],
            );
        }
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

/// The velocity changes of one component's faces: `(forcing, u, v, increments, free, is_v)`
/// → the range of faces written in each row ([`Forcing::increments`] and its reference twin).
type Increments = fn(&Forcing, &[f32], &[f32], &mut [f32], &[u8], bool) -> Vec<Range<usize>>;

/// Everything the forces pass needs for one substep.
struct Forcing<'a> {
    g: Geometry,
    origin: [f32; 2],
    splats: &'a [ArrowSplat],
    bounds: Vec<([f32; 2], [f32; 2])>,
    ambient: &'a Ambient,
    coupling: f32,
    response: f32,
    dt: f32,
}

impl Forcing<'_> {
    /// Faces `first..=last` of a row of `w` faces (v faces with `is_v`) inside splat bounds
    /// `(lo, hi)` along x; `None` when the bounds miss the grid.
    fn columns(
        &self,
        (lo, hi): ([f32; 2], [f32; 2]),
        w: usize,
        is_v: bool,
    ) -> Option<RangeInclusive<usize>> {
        let ox = if is_v { 0.5 } else { 0.0 };
        let first = (((lo[0] - self.origin[0]) / self.g.hx - ox).floor().max(0.0)) as usize;
        let last =
            (((hi[0] - self.origin[0]) / self.g.hx - ox).ceil().max(0.0) as usize).min(w - 1);
        (first <= last).then_some(first..=last)
    }

    /// The faces of row `j` that the forces write: the hull of the active splats' columns, or
    /// the whole row when ambient layers pull on it. Empty when nothing reaches the row.
    fn row_reach(&self, j: usize, w: usize, is_v: bool) -> Range<usize> {
        if self.coupling > 0.0 {
            return 0..w;
        }
        let z = self.row_z(j, is_v);
        self.bounds
            .iter()
            .filter(|(lo, hi)| z >= lo[1] && z <= hi[1])
            .filter_map(|&b| self.columns(b, w, is_v))
            .map(|c| *c.start()..*c.end() + 1)
            .reduce(|a, b| a.start.min(b.start)..a.end.max(b.end))
            .unwrap_or(0..0)
    }

    /// World z of row `j` of faces: face (i, j) sits at grid point (i, j + ½) for u, (i + ½, j)
    /// for v.
    fn row_z(&self, j: usize, is_v: bool) -> f32 {
        let oz = if is_v { 0.0 } else { 0.5 };
        self.origin[1] + (j as f32 + oz) * self.g.hz
    }

    /// Writes the velocity change of the faces each row's forces reach (see
    /// [`Self::row_reach`]) into `inc` (u faces, or v faces with `is_v`); returns those
    /// ranges, row by row.
    fn increments(
        &self,
        u: &[f32],
        v: &[f32],
        inc: &mut [f32],
        free: &[u8],
        is_v: bool,
    ) -> Vec<Range<usize>> {
        let g = &self.g;
        let w = if is_v { g.nx } else { g.nx + 1 };
        inc.par_chunks_mut(w)
            .enumerate()
            .with_min_len(rows_per_job(w))
            .map(|(j, row)| {
                let reach = self.row_reach(j, w, is_v);
                if reach.is_empty() {
                    return reach;
                }
                row[reach.clone()].fill(0.0);
                let z_world = self.row_z(j, is_v);
                let free = &free[j * w..][..w];
                // Each splat only visits the faces inside its x-extent; per face the splats
                // still add up in the same order.
                for (s, &b) in self.splats.iter().zip(&self.bounds) {
                    if z_world < b.0[1] || z_world > b.1[1] {
                        continue;
                    }
                    if let Some(span) = self.columns(b, w, is_v) {
                        self.splat_span(s, u, v, j, is_v, span, free, row);
                    }
                }
                if self.coupling > 0.0 {
                    let x_of = |i: usize| {
                        self.origin[0] + (i as f32 + if is_v { 0.5 } else { 0.0 }) * g.hx
                    };
                    let c = usize::from(is_v);
                    for (i, out) in row.iter_mut().enumerate() {
                        if free[i] == 0 {
                            continue;
                        }
                        let vel = face_velocity(g, u, v, i, j, is_v);
                        *out += (self.ambient.wind([x_of(i), z_world])[c] - vel[c]) * self.coupling;
                    }
                }
                reach
            })
            .collect()
    }

    /// Adds one splat's push to the free faces `span` of row `j`: the faces whose velocity
    /// stencil wraps or clamps one at a time, the rest in one branch-free loop (weights,
    /// face velocities and impulses all vectorise).
    #[allow(clippy::too_many_arguments)]
    fn splat_span(
        &self,
        s: &ArrowSplat,
        u: &[f32],
        v: &[f32],
        j: usize,
        is_v: bool,
        span: std::ops::RangeInclusive<usize>,
        free: &[u8],
        row: &mut [f32],
    ) {
        let g = &self.g;
        let nx = g.nx;
        let c = usize::from(is_v);
        let (ox, oz) = if is_v { (0.5, 0.0) } else { (0.0, 0.5) };
        let z_world = self.origin[1] + (j as f32 + oz) * g.hz;
        let (origin_x, hx, k, dt) = (self.origin[0], g.hx, self.response, self.dt);
        #[inline(always)]
        #[allow(clippy::too_many_arguments)]
        fn impulse(
            s: &ArrowSplat,
            x: f32,
            z: f32,
            vel: [f32; 2],
            k: f32,
            dt: f32,
            c: usize,
        ) -> f32 {
            s.impulse_weighted(s.weight([x, z]), vel, k, dt)[c]
        }
        let x_of = |i: usize| origin_x + (i as f32 + ox) * hx;
        let push = |i: usize, vel: [f32; 2]| impulse(s, x_of(i), z_world, vel, k, dt, c);
        // Faces whose stencil needs no wrap or clamp: all v faces, u faces 1..nx-1.
        let (lo, hi) = if is_v { (0, nx - 1) } else { (1, nx - 1) };
        for i in span.clone().filter(|i| !(lo..=hi).contains(i)) {
            if free[i] != 0 {
                row[i] += push(i, face_velocity(g, u, v, i, j, is_v));
            }
        }
        let (a, b) = (*span.start().max(&lo), *span.end().min(&hi));
        if a > b {
            return;
        }
        let n = b - a + 1;
        let (out, fr) = (&mut row[a..=b], &free[a..=b]);
        let span = SplatSpan {
            s,
            k,
            dt,
            first: a,
            x0: origin_x,
            ox,
            hx,
            z: z_world,
        };
        if is_v {
            let w = nx + 1;
            let (jb, jt) = u_rows_beside(g, j);
            let own = &v[j * nx + a..][..n];
            let (ub0, ub1) = (&u[jb * w + a..][..n], &u[jb * w + a + 1..][..n]);
            let (ut0, ut1) = (&u[jt * w + a..][..n], &u[jt * w + a + 1..][..n]);
            splat_faces(&span, true, own, [ub0, ub1, ut0, ut1], fr, out);
        } else {
            let own = &u[j * (nx + 1) + a..][..n];
            let (vb0, vb1) = (&v[j * nx + a - 1..][..n], &v[j * nx + a..][..n]);
            let (vt0, vt1) = (&v[(j + 1) * nx + a - 1..][..n], &v[(j + 1) * nx + a..][..n]);
            splat_faces(&span, false, own, [vb0, vb1, vt0, vt1], fr, out);
        }
    }
}

/// One splat over a run of faces of one row: what [`splat_faces`] needs besides the slices.
struct SplatSpan<'a> {
    s: &'a ArrowSplat,
    k: f32,
    dt: f32,
    /// Index of the run's first face in its row.
    first: usize,
    /// World x of face `i` is `x0 + (i + ox) · hx`; the row's world z is `z`.
    x0: f32,
    ox: f32,
    hx: f32,
    z: f32,
}

/// Adds the splat's push to the free faces of a run whose velocity stencil needs no wrap or
/// clamp: `own` is the faces' own component, `other` the four faces of the other component
/// averaged onto each (v faces with `is_v`). Compiled for several SIMD levels, picked at run
/// time: the weights, face velocities and impulses vectorise.
#[multiversion(targets = "simd")]
fn splat_faces(
    p: &SplatSpan,
    is_v: bool,
    own: &[f32],
    other: [&[f32]; 4],
    free: &[u8],
    out: &mut [f32],
) {
    let n = out.len();
    let (own, free) = (&own[..n], &free[..n]);
    let [o0, o1, o2, o3] = other.map(|o| &o[..n]);
    let c = usize::from(is_v);
    for q in 0..n {
        let avg = 0.25 * (o0[q] + o1[q] + o2[q] + o3[q]);
        let vel = if is_v { [avg, own[q]] } else { [own[q], avg] };
        let x = p.x0 + ((p.first + q) as f32 + p.ox) * p.hx;
        let d = p.s.impulse_weighted(p.s.weight([x, p.z]), vel, p.k, p.dt)[c];
        out[q] = if free[q] != 0 { out[q] + d } else { out[q] };
    }
}

/// `field += inc` over each row's range in `reach`; returns the number of faces touched.
fn add_rows(field: &mut [f32], inc: &[f32], reach: &[Range<usize>], w: usize) -> usize {
    field
        .par_chunks_mut(w)
        .zip(inc.par_chunks(w))
        .zip(reach.par_iter())
        .with_min_len(rows_per_job(w))
        .map(|((f, d), r)| {
            for (x, dx) in f[r.clone()].iter_mut().zip(&d[r.clone()]) {
                *x = clamp_speed(*x + dx);
            }
            r.len()
        })
        .sum()
}

/// A pass over one face field: `(geometry, u, v, source, destination, dt, keep, free,
/// is_v)`, as [`advect_faces`] and [`maccormack`] (and their reference twins) take it.
type FaceKernel = fn(&Geometry, &[f32], &[f32], &[f32], &mut [f32], f32, f32, &[u8], bool);

#[derive(Clone, Copy)]
struct Geometry {
    nx: usize,
    ny: usize,
    hx: f32,
    hz: f32,
    periodic: bool,
}

/// Bilinear sample of a face field with `w × h` samples, at fractional sample coordinates;
/// periodic grids wrap every `nx × ny` samples (the last face row/column repeats the first).
/// Returns the value and the min/max of the four samples used (for the MacCormack limiter).
#[inline]
fn bilinear(g: &Geometry, f: &[f32], w: usize, h: usize, x: f32, z: f32) -> (f32, f32, f32) {
    let (i0, i1, fx) = axis(x, w, g.nx, g.periodic);
    let (j0, j1, fz) = axis(z, h, g.ny, g.periodic);
    let a = f[j0 * w + i0];
    let b = f[j0 * w + i1];
    let c = f[j1 * w + i0];
    let d = f[j1 * w + i1];
    let top = a + (b - a) * fx;
    let bottom = c + (d - c) * fx;
    (
        top + (bottom - top) * fz,
        a.min(b).min(c).min(d),
        a.max(b).max(c).max(d),
    )
}

/// Sample indices and weight along one axis. Clamped: `[0, n-1]`; periodic: modulo `period`.
#[inline]
fn axis(x: f32, n: usize, period: usize, periodic: bool) -> (usize, usize, f32) {
    if periodic {
        let p = period as f32;
        let x = x.rem_euclid(p);
        let i0 = (x.floor() as usize).min(period - 1);
        let f = x - i0 as f32;
        (i0, (i0 + 1) % period, f)
    } else {
        let x = x.clamp(0.0, (n - 1) as f32);
        let i0 = (x.floor() as usize).min(n.saturating_sub(2));
        let f = x - i0 as f32;
        (i0, (i0 + 1).min(n - 1), f)
    }
}

/// `u` at grid point `(x, z)` (cell units; `u[i, j]` sits at `(i, j + ½)`).
#[inline]
fn sample_u(g: &Geometry, u: &[f32], x: f32, z: f32) -> (f32, f32, f32) {
    bilinear(g, u, g.nx + 1, g.ny, x, z - 0.5)
}

/// `v` at grid point `(x, z)` (`v[i, j]` sits at `(i + ½, j)`).
#[inline]
fn sample_v(g: &Geometry, v: &[f32], x: f32, z: f32) -> (f32, f32, f32) {
    bilinear(g, v, g.nx, g.ny + 1, x - 0.5, z)
}

/// The rows of u faces below and above the v faces of row `j` (wrapped, or clamped into the
/// grid at its bottom and top edges).
#[inline(always)]
fn u_rows_beside(g: &Geometry, j: usize) -> (usize, usize) {
    let ny = g.ny;
    if g.periodic {
        ((j + ny - 1) % ny, j % ny)
    } else {
        (j.saturating_sub(1).min(ny - 1), j.min(ny - 1))
    }
}

/// Velocity `[x, z]` at face `(i, j)` (a v face with `is_v`): the face's own component and the
/// mean of the four nearest faces of the other component (exactly the bilinear sample there).
#[inline(always)]
fn face_velocity(g: &Geometry, u: &[f32], v: &[f32], i: usize, j: usize, is_v: bool) -> [f32; 2] {
    let nx = g.nx;
    if is_v {
        // u faces at columns i, i+1 and rows j-1, j (wrapped or clamped into the grid).
        let (jb, jt) = u_rows_beside(g, j);
        let w = nx + 1;
        let ux = 0.25 * (u[jb * w + i] + u[jb * w + i + 1] + u[jt * w + i] + u[jt * w + i + 1]);
        [ux, v[j * nx + i]]
    } else {
        let (il, ir) = if g.periodic {
            ((i + nx - 1) % nx, i % nx)
        } else {
            (i.saturating_sub(1).min(nx - 1), i.min(nx - 1))
        };
        let vz =
            0.25 * (v[j * nx + il] + v[j * nx + ir] + v[(j + 1) * nx + il] + v[(j + 1) * nx + ir]);
        [u[j * (nx + 1) + i], vz]
    }
}

/// Backtraced departure point (grid units) of face `(i, j)`.
#[inline(always)]
fn departure(
    g: &Geometry,
    u: &[f32],
    v: &[f32],
    i: usize,
    j: usize,
    is_v: bool,
    dt: f32,
) -> (f32, f32) {
    let (x, z) = if is_v {
        (i as f32 + 0.5, j as f32)
    } else {
        (i as f32, j as f32 + 0.5)
    };
    let vel = face_velocity(g, u, v, i, j, is_v);
    (x - vel[0] * (dt / g.hx), z - vel[1] * (dt / g.hz))
}

/// Departure points (grid units) of the faces of row `j` (`is_v`: a row of v faces) into
/// `xs`, `zs`: exactly [`departure`] face by face, but with the row's neighbour rows chosen
/// once and the interior faces in one vectorisable loop.
#[allow(clippy::too_many_arguments)]
#[multiversion(targets = "simd")]
fn departures_row(
    g: &Geometry,
    u: &[f32],
    v: &[f32],
    j: usize,
    is_v: bool,
    dt: f32,
    xs: &mut [f32],
    zs: &mut [f32],
) {
    let nx = g.nx;
    let (cx, cz) = (dt / g.hx, dt / g.hz);
    if is_v {
        // u faces at columns i, i+1 of the rows below and above the v row (wrapped or clamped).
        let (jb, jt) = u_rows_beside(g, j);
        let w = nx + 1;
        let (ub, ut) = (&u[jb * w..][..w], &u[jt * w..][..w]);
        let vr = &v[j * nx..][..nx];
        let (xs, zs) = (&mut xs[..nx], &mut zs[..nx]);
        let z = j as f32;
        for i in 0..nx {
            let ux = 0.25 * (ub[i] + ub[i + 1] + ut[i] + ut[i + 1]);
            xs[i] = (i as f32 + 0.5) - ux * cx;
            zs[i] = z - vr[i] * cz;
        }
    } else {
        let w = nx + 1;
        let ur = &u[j * w..][..w];
        let (vb, vt) = (&v[j * nx..][..nx], &v[(j + 1) * nx..][..nx]);
        let z = j as f32 + 0.5;
        // The end faces (columns 0 and nx) take their v neighbours wrapped or clamped.
        for i in [0, nx] {
            let (x, zz) = departure(g, u, v, i, j, false, dt);
            xs[i] = x;
            zs[i] = zz;
        }
        let (xs, zs) = (&mut xs[1..nx], &mut zs[1..nx]);
        let (ui, vbl, vbr, vtl, vtr) =
            (&ur[1..nx], &vb[..nx - 1], &vb[1..], &vt[..nx - 1], &vt[1..]);
        for k in 0..nx - 1 {
            let vz = 0.25 * (vbl[k] + vbr[k] + vtl[k] + vtr[k]);
            xs[k] = (k + 1) as f32 - ui[k] * cx;
            zs[k] = z - vz * cz;
        }
    }
}

/// Samples `src` (`is_v`: the v faces) at the departure points `xs`, `zs` of a row of faces
/// on a periodic grid (wrapping, through [`bilinear`]); faces that are not free get 0.
/// `shape(value, min, max, k)` shapes each free face's output, `k` being its index in `src`.
/// Non-periodic grids use the vectorised [`sample_clamped`] and [`correct_clamped`].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn sample_row(
    g: &Geometry,
    src: &[f32],
    j: usize,
    is_v: bool,
    xs: &[f32],
    zs: &[f32],
    free: &[u8],
    out: &mut [f32],
    shape: impl Fn(f32, f32, f32, usize) -> f32,
) {
    debug_assert!(g.periodic);
    let (w, h) = if is_v {
        (g.nx, g.ny + 1)
    } else {
        (g.nx + 1, g.ny)
    };
    // Sample coordinates of the field: v sits half a cell right, u half a cell up.
    let (ox, oz) = if is_v { (0.5, 0.0) } else { (0.0, 0.5) };
    let row0 = j * w;
    let free = &free[row0..][..w];
    for i in 0..w {
        out[i] = if free[i] == 0 {
            0.0
        } else {
            let (s, lo, hi) = bilinear(g, src, w, h, xs[i] - ox, zs[i] - oz);
            shape(s, lo, hi, row0 + i)
        };
    }
}

/// The four samples around a departure point of a `w × h` field on a non-periodic grid and
/// the bilinear weights: the point (sample coordinates `x`, `z`) is clamped to the field, as
/// [`bilinear`] does. `w, h ≥ 2` and `src.len() ≥ w·h` must hold ([`Clamped::new`] checks).
struct Clamped<'a> {
    src: &'a [f32],
    w: usize,
    xmax: f32,
    zmax: f32,
    imax: i32,
    jmax: i32,
}

impl<'a> Clamped<'a> {
    fn new(src: &'a [f32], w: usize, h: usize) -> Self {
        assert!(w >= 2 && h >= 2 && src.len() >= w * h && w * h <= i32::MAX as usize);
        let (xmax, zmax) = ((w - 1) as f32, (h - 1) as f32);
        let (imax, jmax) = (w as i32 - 2, h as i32 - 2);
        Self {
            src,
            w,
            xmax,
            zmax,
            imax,
            jmax,
        }
    }

    /// `(a, b, c, d, fx, fz)`: the samples at `(i0, j0)`, `(i0+1, j0)`, `(i0, j0+1)`,
    /// `(i0+1, j0+1)` and the fractions.
    #[inline(always)]
    fn corners(&self, x: f32, z: f32) -> (f32, f32, f32, f32, f32, f32) {
        let x = x.clamp(0.0, self.xmax);
        let z = z.clamp(0.0, self.zmax);
        // In range after the clamp, so the i32 conversion is exact and cheap.
        let i0 = (x as i32).min(self.imax);
        let j0 = (z as i32).min(self.jmax);
        let (fx, fz) = (x - i0 as f32, z - j0 as f32);
        let (k, w) = ((j0 * self.w as i32 + i0) as usize, self.w);
        // SAFETY: 0 ≤ i0 ≤ w − 2 and 0 ≤ j0 ≤ h − 2 (the clamps above; NaN converts to 0), so
        // k + w + 1 ≤ (h − 2)·w + w − 2 + w + 1 = h·w − 1 < src.len(), as `new` asserts.
        // Unchecked loads let the loops over faces vectorise into gathers.
        let (a, b, c, d) = unsafe {
            let s = self.src;
            (
                *s.get_unchecked(k),
                *s.get_unchecked(k + 1),
                *s.get_unchecked(k + w),
                *s.get_unchecked(k + w + 1),
            )
        };
        (a, b, c, d, fx, fz)
    }
}

/// [`sample_row`] for semi-Lagrangian advection on a non-periodic grid: the bilinear sample of
/// the field at each departure point (offset by `-o` into sample coordinates), times `keep`;
/// 0 on faces that are not free. Same arithmetic, same bits; compiled for several SIMD levels.
#[allow(clippy::too_many_arguments)]
#[multiversion(targets = "simd")]
fn sample_clamped(
    f: &Clamped,
    [ox, oz]: [f32; 2],
    xs: &[f32],
    zs: &[f32],
    free: &[u8],
    keep: f32,
    out: &mut [f32],
) {
    let n = out.len();
    let (xs, zs, free) = (&xs[..n], &zs[..n], &free[..n]);
    for i in 0..n {
        let (a, b, c, d, fx, fz) = f.corners(xs[i] - ox, zs[i] - oz);
        let top = a + (b - a) * fx;
        let bottom = c + (d - c) * fx;
        let s = top + (bottom - top) * fz;
        out[i] = if free[i] != 0 { s * keep } else { 0.0 };
    }
}

/// The MacCormack correction of a row on a non-periodic grid: `back` holds φ̌ on entry and
/// `(φ̂ + (φ − φ̌)/2)` clamped to the range of the four samples of φ around the departure
/// point, times `keep`, on exit (0 on faces that are not free). As [`maccormack`] computes it
/// through [`sample_row`], vectorised.
#[allow(clippy::too_many_arguments)]
#[multiversion(targets = "simd")]
fn correct_clamped(
    f: &Clamped,
    [ox, oz]: [f32; 2],
    xs: &[f32],
    zs: &[f32],
    free: &[u8],
    fwd: &[f32],
    orig: &[f32],
    keep: f32,
    back: &mut [f32],
) {
    let n = back.len();
    let (xs, zs, free, fwd, orig) = (&xs[..n], &zs[..n], &free[..n], &fwd[..n], &orig[..n]);
    for i in 0..n {
        let (a, b, c, d, _, _) = f.corners(xs[i] - ox, zs[i] - oz);
        let lo = a.min(b).min(c).min(d);
        let hi = a.max(b).max(c).max(d);
        let x = fwd[i] + 0.5 * (orig[i] - back[i]);
        // `x.clamp(lo, hi)` without its `lo ≤ hi` assertion, which would keep the loop
        // scalar (lo ≤ hi always holds here).
        let x = if x < lo { lo } else { x };
        let x = if x > hi { hi } else { x };
        back[i] = if free[i] != 0 { x * keep } else { 0.0 };
    }
}

/// Semi-Lagrangian advection of one face field (`is_v`: the v faces) by the velocity `(u, v)`.
#[allow(clippy::too_many_arguments)]
fn advect_faces(
    g: &Geometry,
    u: &[f32],
    v: &[f32],
    src: &[f32],
    dst: &mut [f32],
    dt: f32,
    keep: f32,
    free: &[u8],
    is_v: bool,
) {
    let w = if is_v { g.nx } else { g.nx + 1 };
    dst.par_chunks_mut(w)
        .enumerate()
        .with_min_len(rows_per_job(w))
        .for_each_init(
            || (vec![0.0; w], vec![0.0; w]),
            |(xs, zs), (j, row)| {
                departures_row(g, u, v, j, is_v, dt, xs, zs);
                if g.periodic {
                    sample_row(g, src, j, is_v, xs, zs, free, row, |s, _, _, _| s * keep);
                } else {
                    let (w, h) = if is_v {
                        (g.nx, g.ny + 1)
                    } else {
                        (g.nx + 1, g.ny)
                    };
                    let (ox, oz) = if is_v { (0.5, 0.0) } else { (0.0, 0.5) };
                    let free = &free[j * w..][..w];
                    sample_clamped(&Clamped::new(src, w, h), [ox, oz], xs, zs, free, keep, row);
                }
            },
        );
}

/// MacCormack correction: `back` holds φ̌ on entry and the limited result on exit.
#[allow(clippy::too_many_arguments)]
fn maccormack(
    g: &Geometry,
    u: &[f32],
    v: &[f32],
    fwd: &[f32],
    back: &mut [f32],
    dt: f32,
    keep: f32,
    free: &[u8],
    is_v: bool,
) {
    let w = if is_v { g.nx } else { g.nx + 1 };
    let orig = if is_v { v } else { u };
    let h = if is_v { g.ny + 1 } else { g.ny };
    let (ox, oz) = if is_v { (0.5, 0.0) } else { (0.0, 0.5) };
    back.par_chunks_mut(w)
        .enumerate()
        .with_min_len(rows_per_job(w))
        .for_each_init(
            || (vec![0.0; w], vec![0.0; w], vec![0.0; w]),
            |(xs, zs, checked), (j, row)| {
                departures_row(g, u, v, j, is_v, dt, xs, zs);
                let k = j * w;
                if !g.periodic {
                    let (free, fwd_row, orig_row) =
                        (&free[k..][..w], &fwd[k..][..w], &orig[k..][..w]);
                    let f = Clamped::new(orig, w, h);
                    correct_clamped(&f, [ox, oz], xs, zs, free, fwd_row, orig_row, keep, row);
                    return;
                }
                checked.copy_from_slice(row);
                let shape = |_, lo: f32, hi: f32, k: usize| {
                    (fwd[k] + 0.5 * (orig[k] - checked[k - j * w])).clamp(lo, hi) * keep
                };
                sample_row(g, orig, j, is_v, xs, zs, free, row, shape);
            },
        );
}
