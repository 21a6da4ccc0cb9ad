//! Every solver pass in its straightforward form: one face or cell at a time, written as the
//! formula reads, with the boundary cases inline. The passes in `mod.rs` are restructured for
//! speed (rows split into interior and ends, vectorisable loops, cache-blocked Jacobi) and
//! must give the same bits: `tests/sim.rs` steps both on layouts with every boundary kind and
//! compares the fields byte for byte. This is also the form the GPU passes mirror.

use super::*;

impl Solver {
    /// One step through the reference passes: same order, same arithmetic as [`Self::step`].
    pub fn step_reference(&mut self) {
        let n = self.params.substeps.max(1);
        let dt = self.params.dt / n as f32;
        for _ in 0..n {
            self.apply_forces_reference(dt);
            self.compute_curl_reference();
            self.confine_vorticity_reference(dt);
            self.compute_divergence_reference();
            let decay = self.params.pressure_decay;
            self.p.iter_mut().for_each(|p| *p *= decay);
            for _ in 0..self.params.pressure_iterations {
                self.jacobi_iteration();
            }
            self.subtract_gradient_reference();
            self.advect_reference(dt);
            self.time += dt;
        }
    }

    /// Step 1 with the face-by-face increments below.
    fn apply_forces_reference(&mut self, dt: f32) {
        self.apply_forces_with(dt, increments_reference);
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
                let (jb, jt) = neighbours(j, ny, periodic);
                for (i, w) in row.iter_mut().enumerate() {
                    if solid[j * nx + i] != 0 {
                        *w = 0.0;
                        continue;
                    }
                    let (il, ir) = neighbours(i, nx, periodic);
                    let dvdx = (vc(ir, j) - vc(il, j))
                        / (hx * (ir as f32 - il as f32).abs().clamp(1.0, 2.0));
                    let dudz = (uc(i, jt) - uc(i, jb))
                        / (hz * (jt as f32 - jb as f32).abs().clamp(1.0, 2.0));
                    *w = dvdx - dudz;
                }
            });
    }

    /// Step 3: vorticity confinement, `f = ε h w (N_z, −N_x)` with `N` the unit gradient of
    /// `|w|`, pushing along the rotation so small eddies survive advection.
    fn confine_vorticity_reference(&mut self, dt: f32) {
        let eps = self.params.vorticity;
        if eps <= 0.0 {
            return;
        }
        let (nx, ny) = (self.nx, self.ny);
        let periodic = self.params.boundary == Boundary::Periodic;
        let h = self.hx.min(self.hz);
        let curl = &self.curl;
        // Cell-centred force: x into p_tmp, z into div (both free until the divergence pass).
        self.p_tmp
            .par_chunks_mut(nx)
            .zip(self.div.par_chunks_mut(nx))
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, (fx_row, fz_row))| {
                let (jb, jt) = neighbours(j, ny, periodic);
                for i in 0..nx {
                    let (il, ir) = neighbours(i, nx, periodic);
                    let w = curl[j * nx + i];
                    let gx = 0.5 * (curl[j * nx + ir].abs() - curl[j * nx + il].abs());
                    let gz = 0.5 * (curl[jt * nx + i].abs() - curl[jb * nx + i].abs());
                    let len = (gx * gx + gz * gz).sqrt() + 1e-5;
                    let s = eps * h * w / len;
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
                    *u = clamp_speed(*u + dt * 0.5 * (a + b));
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
                    *v = clamp_speed(*v + dt * 0.5 * (fz[jb * nx + i] + fz[jt * nx + i]));
                }
            });
        self.sync_periodic();
    }

    /// Step 4: divergence per cell, `(u_R − u_L)/hx + (v_T − v_B)/hz` (0 in solids).
    fn compute_divergence_reference(&mut self) {
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
                    *u -= (px(i, j) - px(i - 1, j)) / hx;
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
                    *v -= (pz(i, j) - pz(i, j - 1)) / hz;
                }
            });
        self.sync_periodic();
    }

    /// Step 7 with the face-by-face kernels below.
    fn advect_reference(&mut self, dt: f32) {
        self.advect_with(dt, advect_faces_reference, maccormack_reference);
    }
}

/// Semi-Lagrangian advection of one face field (`is_v`: the v faces) by the velocity `(u, v)`.
#[allow(clippy::too_many_arguments)]
fn advect_faces_reference(
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
        .for_each(|(j, row)| {
            for (i, out) in row.iter_mut().enumerate() {
                *out = if free[j * w + i] == 0 {
                    0.0
                } else {
                    let (x, z) = departure(g, u, v, i, j, is_v, dt);
                    let s = if is_v {
                        bilerp(g, src, g.nx, g.ny + 1, x - 0.5, z)
                    } else {
                        bilerp(g, src, g.nx + 1, g.ny, x, z - 0.5)
                    };
                    s * keep
                };
            }
        });
}

/// MacCormack correction: `back` holds φ̌ on entry and the limited result on exit.
#[allow(clippy::too_many_arguments)]
fn maccormack_reference(
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
    back.par_chunks_mut(w)
        .enumerate()
        .with_min_len(rows_per_job(w))
        .for_each(|(j, row)| {
            for (i, out) in row.iter_mut().enumerate() {
                let k = j * w + i;
                if free[k] == 0 {
                    *out = 0.0;
                    continue;
                }
                let (x, z) = departure(g, u, v, i, j, is_v, dt);
                let (_, lo, hi) = if is_v {
                    sample_v(g, orig, x, z)
                } else {
                    sample_u(g, orig, x, z)
                };
                *out = (fwd[k] + 0.5 * (orig[k] - *out)).clamp(lo, hi) * keep;
            }
        });
}

/// The velocity change of the faces each row's forces reach, face by face, into `inc` (u faces,
/// or v faces with `is_v`); returns those ranges, row by row.
fn increments_reference(
    f: &Forcing,
    u: &[f32],
    v: &[f32],
    inc: &mut [f32],
    free: &[u8],
    is_v: bool,
) -> Vec<std::ops::Range<usize>> {
    let g = &f.g;
    let w = if is_v { g.nx } else { g.nx + 1 };
    inc.par_chunks_mut(w)
        .enumerate()
        .with_min_len(rows_per_job(w))
        .map(|(j, row)| {
            let reach = f.row_reach(j, w, is_v);
            row[reach.clone()].fill(0.0);
            let (ox, z_world) = (if is_v { 0.5 } else { 0.0 }, f.row_z(j, is_v));
            let c = usize::from(is_v);
            let x_of = |i: usize| f.origin[0] + (i as f32 + ox) * g.hx;
            for (s, &b) in f.splats.iter().zip(&f.bounds) {
                if z_world < b.0[1] || z_world > b.1[1] {
                    continue;
                }
                for i in f.columns(b, w, is_v).into_iter().flatten() {
                    if free[j * w + i] == 0 {
                        continue;
                    }
                    let weight = s.weight([x_of(i), z_world]);
                    if weight == 0.0 {
                        continue;
                    }
                    let vel = face_velocity(g, u, v, i, j, is_v);
                    row[i] += s.impulse_weighted(weight, vel, f.response, f.dt)[c];
                }
            }
            if f.coupling > 0.0 {
                for (i, out) in row.iter_mut().enumerate() {
                    if free[j * w + i] == 0 {
                        continue;
                    }
                    let vel = face_velocity(g, u, v, i, j, is_v);
                    *out += (f.ambient.wind([x_of(i), z_world])[c] - vel[c]) * f.coupling;
                }
            }
            reach
        })
        .collect()
}

/// Bilinear sample of a `w × h` face field at fractional sample coordinates: the generic
/// sampler for periodic grids, a clamp-only fast path otherwise (same arithmetic, same bits).
#[inline(always)]
fn bilerp(g: &Geometry, f: &[f32], w: usize, h: usize, x: f32, z: f32) -> f32 {
    if g.periodic {
        return bilinear(g, f, w, h, x, z).0;
    }
    let x = x.clamp(0.0, (w - 1) as f32);
    let z = z.clamp(0.0, (h - 1) as f32);
    let i0 = (x as usize).min(w - 2);
    let j0 = (z as usize).min(h - 2);
    let fx = x - i0 as f32;
    let fz = z - j0 as f32;
    let k = j0 * w + i0;
    let (a, b, c, d) = (f[k], f[k + 1], f[k + w], f[k + w + 1]);
    let top = a + (b - a) * fx;
    let bottom = c + (d - c) * fx;
    top + (bottom - top) * fz
}
