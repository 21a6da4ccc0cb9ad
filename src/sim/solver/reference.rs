//! Every solver pass in its plain form: one face or cell at a time, written as the formula
//! reads, the boundary cases inline, sharing no kernel, sampler or driver with the fast passes
//! in the other files (only the force *model* — `agc_splats`, `ArrowSplat`, `Ambient::wind` —
//! which defines what both must compute). The fast passes are restructured for speed (rows
//! split into interior and ends, vectorisable loops, cache-blocked Jacobi) and must give the
//! same numbers: `tests/sim/bits.rs` steps both on layouts with every boundary kind and both
//! advection schemes and compares the fields. The GPU passes mirror these formulas too.

use super::*;

/// Neighbour indices `(lower, upper)` of `i` on an axis of `n`: wrapped or clamped.
fn lower_upper(i: usize, n: usize, periodic: bool) -> (usize, usize) {
    if periodic {
        ((i + n - 1) % n, (i + 1) % n)
    } else {
        (i.saturating_sub(1), (i + 1).min(n - 1))
    }
}

impl Solver {
    /// One step through the reference passes, in the order of [`Self::step`].
    pub fn step_reference(&mut self) {
        let n = self.params.substeps.max(1);
        let dt = self.params.dt / n as f32;
        for _ in 0..n {
            self.forces_reference(dt);
            self.compute_curl_reference();
            self.confine_vorticity_reference(dt);
            self.divergence_reference();
            let decay = self.params.pressure_decay;
            // Stored as it is only when no iteration follows (each one flushes what it
            // writes, as the fast solve does).
            let last = self.params.pressure_iterations == 0;
            self.p
                .iter_mut()
                .for_each(|p| *p = if last { flush(*p * decay) } else { *p * decay });
            for _ in 0..self.params.pressure_iterations {
                self.jacobi_reference();
            }
            self.subtract_gradient_reference();
            self.advect_plain_reference(dt);
            self.clock.tick(dt);
        }
    }

    /// Periodic grids: the last column of u faces and the last row of v faces are the first.
    fn wrap_faces_reference(&mut self) {
        if self.params.boundary != Boundary::Periodic {
            return;
        }
        let (nx, ny) = (self.nx, self.ny);
        for j in 0..ny {
            self.u[j * (nx + 1) + nx] = self.u[j * (nx + 1)];
        }
        for i in 0..nx {
            self.v[ny * nx + i] = self.v[i];
        }
    }

    /// x velocity at the centre of v face `(i, j)`: the mean of the four u faces around it.
    fn u_at_v_face(&self, i: usize, j: usize) -> f32 {
        let (nx, ny) = (self.nx, self.ny);
        let (jb, jt) = if self.params.boundary == Boundary::Periodic {
            ((j + ny - 1) % ny, j % ny)
        } else {
            (j.saturating_sub(1).min(ny - 1), j.min(ny - 1))
        };
        let u = &self.u;
        let w = nx + 1;
        0.25 * (u[jb * w + i] + u[jb * w + i + 1] + u[jt * w + i] + u[jt * w + i + 1])
    }

    /// z velocity at the centre of u face `(i, j)`: the mean of the four v faces around it.
    fn v_at_u_face(&self, i: usize, j: usize) -> f32 {
        let nx = self.nx;
        let (il, ir) = if self.params.boundary == Boundary::Periodic {
            ((i + nx - 1) % nx, i % nx)
        } else {
            (i.saturating_sub(1).min(nx - 1), i.min(nx - 1))
        };
        let v = &self.v;
        0.25 * (v[j * nx + il] + v[j * nx + ir] + v[(j + 1) * nx + il] + v[(j + 1) * nx + ir])
    }

    /// Step 1: every free face gets the AGC arrows' impulses (in splat order) and the ambient
    /// layers' pull `(w − vel)·(1 − e^(−coupling·dt))`, all from the velocity before the step.
    fn forces_reference(&mut self, dt: f32) {
        let splats = agc_splats(&self.layout, self.time());
        self.ambient.set_time(self.time());
        let coupling = if self.ambient.is_empty() {
            0.0
        } else {
            1.0 - crate::num::exp(-self.params.ambient_coupling * dt)
        };
        if splats.is_empty() && coupling == 0.0 {
            return;
        }
        let (nx, ny, hx, hz) = (self.nx, self.ny, self.hx, self.hz);
        let [ox, oz] = self.origin;
        let k_resp = self.params.arrow_response;
        let change = |s: &Solver, p: [f32; 2], vel: [f32; 2], c: usize| -> f32 {
            let (mut inc, mut gains, mut squares) = (0.0, 0.0, 0.0f32);
            for sp in &splats {
                let g = sp.weight(p);
                if g != 0.0 {
                    inc += sp.impulse_weighted(g, vel, k_resp, dt)[c];
                    let gain = crate::sim::forces::gain_of_weight(g, k_resp, dt);
                    gains += gain;
                    squares += gain * gain;
                }
            }
            if !splats.is_empty() {
                inc = crate::sim::forces::combine(inc, gains, squares);
            }
            if coupling > 0.0 {
                inc += (s.ambient.wind(p)[c] - vel[c]) * coupling;
            }
            inc
        };
        let mut du = vec![0.0f32; self.u.len()];
        for j in 0..ny {
            for i in 0..=nx {
                let k = j * (nx + 1) + i;
                if self.u_free[k] != 0 {
                    let p = [ox + i as f32 * hx, oz + (j as f32 + 0.5) * hz];
                    du[k] = change(self, p, [self.u[k], self.v_at_u_face(i, j)], 0);
                }
            }
        }
        let mut dv = vec![0.0f32; self.v.len()];
        for j in 0..=ny {
            for i in 0..nx {
                let k = j * nx + i;
                if self.v_free[k] != 0 {
                    let p = [ox + (i as f32 + 0.5) * hx, oz + j as f32 * hz];
                    dv[k] = change(self, p, [self.u_at_v_face(i, j), self.v[k]], 1);
                }
            }
        }
        for (x, d) in self.u.iter_mut().zip(&du).chain(self.v.iter_mut().zip(&dv)) {
            if *d != 0.0 {
                *x = flush((*x + d).clamp(-MAX_SPEED, MAX_SPEED));
            }
        }
        self.wrap_faces_reference();
    }

    /// Step 2: vorticity at cell centres, `∂v/∂x − ∂u/∂z`, central differences.
    fn compute_curl_reference(&mut self) {
        let (nx, ny, hx, hz) = (self.nx, self.ny, self.hx, self.hz);
        let periodic = self.params.boundary == Boundary::Periodic;
        let (u, v) = (&self.u, &self.v);
        let uc = |i: usize, j: usize| 0.5 * (u[j * (nx + 1) + i] + u[j * (nx + 1) + i + 1]);
        let vc = |i: usize, j: usize| 0.5 * (v[j * nx + i] + v[(j + 1) * nx + i]);
        let solid = &self.solid;
        self.curl
            .par_chunks_mut(nx)
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, row)| {
                let (jb, jt) = lower_upper(j, ny, periodic);
                for (i, w) in row.iter_mut().enumerate() {
                    if solid[j * nx + i] != 0 {
                        *w = 0.0;
                        continue;
                    }
                    let (il, ir) = lower_upper(i, nx, periodic);
                    let dvdx = (vc(ir, j) - vc(il, j))
                        / (hx * (ir as f32 - il as f32).abs().clamp(1.0, 2.0));
                    let dudz = (uc(i, jt) - uc(i, jb))
                        / (hz * (jt as f32 - jb as f32).abs().clamp(1.0, 2.0));
                    *w = dvdx - dudz;
                }
            });
    }

    /// Step 3: vorticity confinement, `f = r(ε)·h·min(1, |v|/U)·w·(N_z, −N_x)` with `N` the
    /// (regularised) unit gradient of `|w|`, pushing along the rotation so small eddies
    /// survive advection, taking no face past `U` (`Confinement`). The cells along
    /// an open edge get no force: the air entering there keeps the edge's velocity, so a
    /// force there would be fed back into every later step's inflow (docs/SOLVER.md).
    fn confine_vorticity_reference(&mut self, dt: f32) {
        let eps = self.params.vorticity;
        if eps <= 0.0 {
            return;
        }
        let (nx, ny) = (self.nx, self.ny);
        let periodic = self.params.boundary == Boundary::Periodic;
        let open = self.params.boundary == Boundary::Open;
        let conf = self.confinement();
        let cap = conf.speed_cap;
        let curl = &self.curl;
        // Cell-centred force: x into p_tmp, z into div (both free until the divergence pass).
        self.p_tmp
            .par_chunks_mut(nx)
            .zip(self.div.par_chunks_mut(nx))
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, (fx_row, fz_row))| {
                let (jb, jt) = lower_upper(j, ny, periodic);
                for i in 0..nx {
                    if open && (i == 0 || j == 0 || i == nx - 1 || j == ny - 1) {
                        fx_row[i] = 0.0;
                        fz_row[i] = 0.0;
                        continue;
                    }
                    let (il, ir) = lower_upper(i, nx, periodic);
                    let w = curl[j * nx + i];
                    let gx = 0.5 * (curl[j * nx + ir].abs() - curl[j * nx + il].abs());
                    let gz = 0.5 * (curl[jt * nx + i].abs() - curl[jb * nx + i].abs());
                    let len = super::vorticity::confinement_norm(gx, gz, w);
                    let uc = 0.5 * (self.u[j * (nx + 1) + i] + self.u[j * (nx + 1) + i + 1]);
                    let vc = 0.5 * (self.v[j * nx + i] + self.v[(j + 1) * nx + i]);
                    let weight = ((uc * uc + vc * vc).sqrt() * conf.inv_speed).min(1.0);
                    let s = conf.eps_h * weight * w / len;
                    fx_row[i] = s * gz;
                    fz_row[i] = -s * gx;
                }
            });
        let fx = &self.p_tmp;
        let fz = &self.div;
        self.u
            .par_chunks_mut(nx + 1)
            .enumerate()
            .with_min_len(rows_per_job(nx + 1))
            .for_each(|(j, row)| {
                for (i, u) in row.iter_mut().enumerate() {
                    if self.u_free[j * (nx + 1) + i] == 0 {
                        continue;
                    }
                    let a = fx[j * nx
                        + if i == 0 {
                            if periodic { nx - 1 } else { 0 }
                        } else {
                            i - 1
                        }];
                    let b = fx[j * nx
                        + if i == nx {
                            if periodic { 0 } else { nx - 1 }
                        } else {
                            i
                        }];
                    let m = u.abs().max(cap);
                    *u = flush(
                        (*u + dt * 0.5 * (a + b))
                            .clamp(-m, m)
                            .clamp(-MAX_SPEED, MAX_SPEED),
                    );
                }
            });
        self.v
            .par_chunks_mut(nx)
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, row)| {
                for (i, v) in row.iter_mut().enumerate() {
                    if self.v_free[j * nx + i] == 0 {
                        continue;
                    }
                    let jb = if j == 0 {
                        if periodic { ny - 1 } else { 0 }
                    } else {
                        j - 1
                    };
                    let jt = if j == ny {
                        if periodic { 0 } else { ny - 1 }
                    } else {
                        j
                    };
                    let m = v.abs().max(cap);
                    *v = flush(
                        (*v + dt * 0.5 * (fz[jb * nx + i] + fz[jt * nx + i]))
                            .clamp(-m, m)
                            .clamp(-MAX_SPEED, MAX_SPEED),
                    );
                }
            });
        self.wrap_faces_reference();
    }

    /// Step 4: divergence per cell, `(u_R − u_L)/hx + (v_T − v_B)/hz` (0 in solids).
    fn divergence_reference(&mut self) {
        let (nx, ny, hx, hz) = (self.nx, self.ny, self.hx, self.hz);
        for j in 0..ny {
            for i in 0..nx {
                let k = j * nx + i;
                self.div[k] = if self.solid[k] != 0 {
                    0.0
                } else {
                    (self.u[j * (nx + 1) + i + 1] - self.u[j * (nx + 1) + i]) / hx
                        + (self.v[(j + 1) * nx + i] - self.v[j * nx + i]) / hz
                };
            }
        }
    }

    /// Step 5, one Jacobi sweep: `p ← (wx (p_L + p_R) + wz (p_B + p_T) − div) / Σw` over the
    /// neighbours that take part, each decided here from the solid mask and the boundary mode:
    /// a fluid cell inside the grid takes part; a solid one does not (Neumann); past the edge a
    /// closed wall does not, an open edge does with p = 0, a periodic grid wraps. Solid cells
    /// and cells with no neighbour taking part get 0.
    fn jacobi_reference(&mut self) {
        let (nx, ny) = (self.nx, self.ny);
        let (wx, wz) = (1.0 / (self.hx * self.hx), 1.0 / (self.hz * self.hz));
        let boundary = self.params.boundary;
        let (p, solid) = (&self.p, &self.solid);
        // (takes part, pressure) of the neighbour at (i + di, j + dj).
        let neighbour = |i: usize, j: usize, di: isize, dj: isize| -> (f32, f32) {
            let (a, b) = (i as isize + di, j as isize + dj);
            let inside = a >= 0 && b >= 0 && (a as usize) < nx && (b as usize) < ny;
            let (a, b) = if inside {
                (a as usize, b as usize)
            } else {
                match boundary {
                    Boundary::Closed => return (0.0, 0.0),
                    Boundary::Open => return (1.0, 0.0),
                    Boundary::Periodic => (
                        a.rem_euclid(nx as isize) as usize,
                        b.rem_euclid(ny as isize) as usize,
                    ),
                }
            };
            if solid[b * nx + a] != 0 {
                (0.0, 0.0)
            } else {
                (1.0, p[b * nx + a])
            }
        };
        let mut out = vec![0.0f32; nx * ny];
        for j in 0..ny {
            for i in 0..nx {
                let k = j * nx + i;
                if solid[k] != 0 {
                    continue;
                }
                let (nl, pl) = neighbour(i, j, -1, 0);
                let (nr, pr) = neighbour(i, j, 1, 0);
                let (nb, pb) = neighbour(i, j, 0, -1);
                let (nt, pt) = neighbour(i, j, 0, 1);
                let ws = wx * (nl + nr) + wz * (nb + nt);
                let inv = if ws > 0.0 { 1.0 / ws } else { 0.0 };
                out[k] = flush((wx * (pl + pr) + wz * (pb + pt) - self.div[k]) * inv);
            }
        }
        self.p = out;
    }

    /// Step 6: subtract the pressure gradient from every free face.
    fn subtract_gradient_reference(&mut self) {
        let (nx, ny, hx, hz) = (self.nx, self.ny, self.hx, self.hz);
        let periodic = self.params.boundary == Boundary::Periodic;
        let p = &self.p;
        let u_free = &self.u_free;
        let v_free = &self.v_free;
        // Outside the domain: periodic wraps, open edges hold p = 0 (closed edges are not free).
        let px = |i: isize, j: usize| -> f32 {
            if i < 0 {
                if periodic { p[j * nx + nx - 1] } else { 0.0 }
            } else if i as usize >= nx {
                if periodic { p[j * nx] } else { 0.0 }
            } else {
                p[j * nx + i as usize]
            }
        };
        self.u
            .par_chunks_mut(nx + 1)
            .enumerate()
            .with_min_len(rows_per_job(nx + 1))
            .for_each(|(j, row)| {
                for (i, u) in row.iter_mut().enumerate() {
                    if u_free[j * (nx + 1) + i] == 0 {
                        *u = 0.0;
                        continue;
                    }
                    let i = i as isize;
                    *u = flush(*u - (px(i, j) - px(i - 1, j)) / hx);
                }
            });
        let pz = |i: usize, j: isize| -> f32 {
            if j < 0 {
                if periodic { p[(ny - 1) * nx + i] } else { 0.0 }
            } else if j as usize >= ny {
                if periodic { p[i] } else { 0.0 }
            } else {
                p[j as usize * nx + i]
            }
        };
        self.v
            .par_chunks_mut(nx)
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, row)| {
                for (i, v) in row.iter_mut().enumerate() {
                    if v_free[j * nx + i] == 0 {
                        *v = 0.0;
                        continue;
                    }
                    let j = j as isize;
                    *v = flush(*v - (pz(i, j) - pz(i, j - 1)) / hz);
                }
            });
        self.wrap_faces_reference();
    }

    /// Departure point (grid units) of face `(i, j)` (a v face with `is_v`) over `dt`, along
    /// the velocity at the face.
    fn departure_reference(&self, i: usize, j: usize, is_v: bool, dt: f32) -> (f32, f32) {
        let (x, z, vel) = if is_v {
            let vel = [self.u_at_v_face(i, j), self.v[j * self.nx + i]];
            (i as f32 + 0.5, j as f32, vel)
        } else {
            let vel = [self.u[j * (self.nx + 1) + i], self.v_at_u_face(i, j)];
            (i as f32, j as f32 + 0.5, vel)
        };
        (x - vel[0] * (dt / self.hx), z - vel[1] * (dt / self.hz))
    }

    /// Bilinear sample of a face field (`is_v`: a v field) at grid point `(x, z)`: the value
    /// and the min/max of the four samples used. Clamped at the edges, or wrapped every
    /// `nx × ny` on periodic grids.
    fn sample_reference(&self, f: &[f32], is_v: bool, x: f32, z: f32) -> (f32, f32, f32) {
        let (nx, ny) = (self.nx, self.ny);
        // Sample coordinates: u[i, j] sits at (i, j + ½), v[i, j] at (i + ½, j).
        let (w, h, sx, sz) = if is_v {
            (nx, ny + 1, x - 0.5, z)
        } else {
            (nx + 1, ny, x, z - 0.5)
        };
        let periodic = self.params.boundary == Boundary::Periodic;
        let along = |t: f32, n: usize, period: usize| -> (usize, usize, f32) {
            if periodic {
                let p = period as f32;
                let t = t - p * (t / p).floor();
                let i0 = (t.floor() as usize).min(period - 1);
                (i0, (i0 + 1) % period, t - i0 as f32)
            } else {
                let t = t.clamp(0.0, (n - 1) as f32);
                let i0 = (t.floor() as usize).min(n - 2);
                (i0, (i0 + 1).min(n - 1), t - i0 as f32)
            }
        };
        let (i0, i1, fx) = along(sx, w, nx);
        let (j0, j1, fz) = along(sz, h, ny);
        let (a, b, c, d) = (
            f[j0 * w + i0],
            f[j0 * w + i1],
            f[j1 * w + i0],
            f[j1 * w + i1],
        );
        let top = a + (b - a) * fx;
        let bottom = c + (d - c) * fx;
        (
            top + (bottom - top) * fz,
            a.min(b).min(c).min(d),
            a.max(b).max(c).max(d),
        )
    }

    /// One semi-Lagrangian step of a face field `src` (`is_v`: v faces) over `dt`, times
    /// `keep`; faces that are not free get 0. `last`: the step's result, flushed (MacCormack's
    /// intermediate traces are not).
    fn trace_reference(&self, src: &[f32], is_v: bool, dt: f32, keep: f32, last: bool) -> Vec<f32> {
        let (nx, ny) = (self.nx, self.ny);
        let (w, h, free) = if is_v {
            (nx, ny + 1, &self.v_free)
        } else {
            (nx + 1, ny, &self.u_free)
        };
        let mut out = vec![0.0f32; w * h];
        for j in 0..h {
            for i in 0..w {
                let k = j * w + i;
                if free[k] != 0 {
                    let (x, z) = self.departure_reference(i, j, is_v, dt);
                    let x = self.sample_reference(src, is_v, x, z).0 * keep;
                    out[k] = if last { flush(x) } else { x };
                }
            }
        }
        out
    }

    /// Step 7: advection with dissipation `1 / (1 + dissipation × dt)` folded into the write.
    /// Semi-Lagrangian: φ' = A(φ). Limited MacCormack: φ̂ = A(φ), φ̌ = A⁻¹(φ̂), and
    /// φ' = clamp(φ̂ + (φ − φ̌)/2) to the range of the samples φ̂ was taken from.
    pub fn advect_plain_reference(&mut self, dt: f32) {
        let keep = 1.0 / (1.0 + self.params.velocity_dissipation * dt);
        let (u, v) = match self.params.advection {
            Advection::SemiLagrangian => (
                self.trace_reference(&self.u, false, dt, keep, true),
                self.trace_reference(&self.v, true, dt, keep, true),
            ),
            Advection::MacCormack => {
                let corrected = |s: &Solver, f: &[f32], is_v: bool| -> Vec<f32> {
                    let fwd = s.trace_reference(f, is_v, dt, 1.0, false);
                    let back = s.trace_reference(&fwd, is_v, -dt, 1.0, false);
                    let (w, free) = if is_v {
                        (s.nx, &s.v_free)
                    } else {
                        (s.nx + 1, &s.u_free)
                    };
                    (0..f.len())
                        .map(|k| {
                            if free[k] == 0 {
                                return 0.0;
                            }
                            let (x, z) = s.departure_reference(k % w, k / w, is_v, dt);
                            let (_, lo, hi) = s.sample_reference(f, is_v, x, z);
                            flush((fwd[k] + 0.5 * (f[k] - back[k])).clamp(lo, hi) * keep)
                        })
                        .collect()
                };
                (
                    corrected(self, &self.u, false),
                    corrected(self, &self.v, true),
                )
            }
        };
        self.u = u;
        self.v = v;
        self.wrap_faces_reference();
    }
}
