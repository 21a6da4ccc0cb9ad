//! Step 7, advection: departure points, the bilinear samplers (clamped or periodic) and the
//! semi-Lagrangian and limited MacCormack drivers.

use super::*;
use crate::sim::forces::clamp_to;

impl Solver {
    /// Step 7: advection (semi-Lagrangian or limited MacCormack) with dissipation
    /// `vel / (1 + dissipation × dt)` folded into the same write.
    pub fn advect(&mut self, dt: f32) {
        let g = self.geometry();
        let keep = 1.0 / (1.0 + self.params.velocity_dissipation * dt);
        let (u, v) = (&self.u, &self.v);
        match self.params.advection {
            Advection::SemiLagrangian => {
                advect_faces::<true>(&g, u, v, u, &mut self.u_tmp, dt, keep, &self.u_free, false);
                advect_faces::<true>(&g, u, v, v, &mut self.v_tmp, dt, keep, &self.v_free, true);
                std::mem::swap(&mut self.u, &mut self.u_tmp);
                std::mem::swap(&mut self.v, &mut self.v_tmp);
            }
            Advection::MacCormack => {
                // Forward: φ̂ = A(φ); backward: φ̌ = A⁻¹(φ̂); φ' = φ̂ + (φ − φ̌)/2, clamped to
                // the forward stencil's range so the correction cannot create new extrema.
                // The backward step and the correction share one sweep (see [`maccormack`]).
                advect_faces::<false>(&g, u, v, u, &mut self.u_tmp, dt, 1.0, &self.u_free, false);
                advect_faces::<false>(&g, u, v, v, &mut self.v_tmp, dt, 1.0, &self.v_free, true);
                let (u_fwd, v_fwd) = (&self.u_tmp, &self.v_tmp);
                maccormack(
                    &g,
                    u,
                    v,
                    u_fwd,
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
                    v_fwd,
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
}

#[derive(Clone, Copy)]
pub(super) struct Geometry {
    pub(super) nx: usize,
    pub(super) ny: usize,
    pub(super) hx: f32,
    pub(super) hz: f32,
    pub(super) periodic: bool,
}

impl Geometry {
    /// `(w, h)`: the samples of a face field, u faces or v faces with `is_v`.
    pub(super) fn faces(&self, is_v: bool) -> (usize, usize) {
        if is_v {
            (self.nx, self.ny + 1)
        } else {
            (self.nx + 1, self.ny)
        }
    }
}

/// Bilinear sample of a face field with `w × h` samples, at fractional sample coordinates;
/// periodic grids wrap every `nx × ny` samples (the last face row/column repeats the first).
/// Returns the value and the min/max of the four samples used (for the MacCormack limiter).
#[inline]
pub(super) fn bilinear(
    g: &Geometry,
    f: &[f32],
    w: usize,
    h: usize,
    x: f32,
    z: f32,
) -> (f32, f32, f32) {
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

/// A coordinate wrapped into one period `[0, p]`: `t − p·⌊t/p⌋`, as the GPU computes it
/// (`p` itself only by rounding, where the sampler's index clamp takes it back into the grid).
#[inline(always)]
pub(super) fn wrap_coordinate(t: f32, p: f32) -> f32 {
    t - p * (t / p).floor()
}

/// Sample indices and weight along one axis. Clamped: `[0, n-1]`; periodic: modulo `period`.
#[inline]
pub(super) fn axis(x: f32, n: usize, period: usize, periodic: bool) -> (usize, usize, f32) {
    if periodic {
        // The same wrap as the vectorised periodic sampler.
        let (i0, i1, f) = wrap(x, period as f32, period as i32);
        (i0 as usize, i1 as usize, f)
    } else {
        // NaN becomes 0, as in the vectorised clamped sampler.
        let x = clamp_to(x, (n - 1) as f32);
        let i0 = (x.floor() as usize).min(n.saturating_sub(2));
        let f = x - i0 as f32;
        (i0, (i0 + 1).min(n - 1), f)
    }
}

/// `u` at grid point `(x, z)` (cell units; `u[i, j]` sits at `(i, j + ½)`).
#[inline]
pub(super) fn sample_u(g: &Geometry, u: &[f32], x: f32, z: f32) -> (f32, f32, f32) {
    bilinear(g, u, g.nx + 1, g.ny, x, z - 0.5)
}

/// `v` at grid point `(x, z)` (`v[i, j]` sits at `(i + ½, j)`).
#[inline]
pub(super) fn sample_v(g: &Geometry, v: &[f32], x: f32, z: f32) -> (f32, f32, f32) {
    bilinear(g, v, g.nx, g.ny + 1, x - 0.5, z)
}

/// The rows of u faces below and above the v faces of row `j` (wrapped, or clamped into the
/// grid at its bottom and top edges).
#[inline(always)]
pub(super) fn u_rows_beside(g: &Geometry, j: usize) -> (usize, usize) {
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
pub(super) fn face_velocity(
    g: &Geometry,
    u: &[f32],
    v: &[f32],
    i: usize,
    j: usize,
    is_v: bool,
) -> [f32; 2] {
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
pub(super) fn departure(
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

/// Departure points of the faces of row `j` (`is_v`: a row of v faces) into `xs`, `zs`, in
/// the field's sample coordinates: exactly [`departure`] face by face less the offset
/// [`sample_u`] or [`sample_v`] takes off (½ cell along z for u faces, along x for v faces),
/// so the same numbers those sample at, but with the row's neighbour rows chosen once and
/// the interior faces in one vectorisable loop. The offset taken off here, in a loop that
/// waits on memory, rather than in the samplers' arithmetic-bound loops.
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
#[simd_kernel]
pub(super) fn departures_row(
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
            // The index as i32: AVX2 has no vector conversion from 64-bit integers.
            xs[i] = (((i as i32) as f32 + 0.5) - ux * cx) - 0.5;
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
            zs[i] = zz - 0.5;
        }
        let (xs, zs) = (&mut xs[1..nx], &mut zs[1..nx]);
        let (ui, vbl, vbr, vtl, vtr) =
            (&ur[1..nx], &vb[..nx - 1], &vb[1..], &vt[..nx - 1], &vt[1..]);
        for k in 0..nx - 1 {
            let vz = 0.25 * (vbl[k] + vbr[k] + vtl[k] + vtr[k]);
            xs[k] = (k as i32 + 1) as f32 - ui[k] * cx;
            zs[k] = (z - vz * cz) - 0.5;
        }
    }
}

/// Semi-Lagrangian advection of one face field (`is_v`: the v faces) by the velocity `(u, v)`.
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
pub(super) fn advect_faces<const FLUSH: bool>(
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
    let (w, _) = g.faces(is_v);
    dst.par_chunks_mut(w)
        .enumerate()
        .with_min_len(rows_per_job(w))
        .for_each_init(
            || (vec![0.0; w], vec![0.0; w]),
            |(xs, zs), (j, row)| {
                departures_row(g, u, v, j, is_v, dt, xs, zs);
                let free = &free[j * w..][..w];
                if is_v {
                    sample_row_of::<true, FLUSH>(g, src, j, xs, zs, free, keep, row);
                } else {
                    sample_row_of::<false, FLUSH>(g, src, j, xs, zs, free, keep, row);
                }
            },
        );
}

/// Row `j` of `src` (v faces with `V`) sampled at the departure points `xs`, `zs`, times
/// `keep`, through the clamped or the periodic sampler.
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
fn sample_row_of<const V: bool, const FLUSH: bool>(
    g: &Geometry,
    src: &[f32],
    j: usize,
    xs: &[f32],
    zs: &[f32],
    free: &[u8],
    keep: f32,
    row: &mut [f32],
) {
    let (w, h) = g.faces(V);
    if g.periodic {
        let f = Wrapped::new(src, w, h, g.nx, g.ny);
        sample_wrapped::<V, FLUSH>(&f, j, xs, zs, free, keep, row);
    } else {
        sample_clamped::<V, FLUSH>(&Clamped::new(src, w, h), j, xs, zs, free, keep, row);
    }
}

/// MacCormack's backward step and correction of one face field in one sweep, row by row:
/// the points the row's faces reach in `dt`, where φ̌ = A⁻¹(φ̂) samples the forward result
/// `fwd` (into `dst`'s row, still in cache for the next loop), and their departure points,
/// around which the limiter reads the four samples of φ; then `dst = (φ̂ + (φ − φ̌)/2)`
/// clamped to that range, times `keep`. The same two row kernels the separate sweeps ran,
/// so the same bits, without φ̌ making a round trip through memory.
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
pub(super) fn maccormack(
    g: &Geometry,
    u: &[f32],
    v: &[f32],
    fwd: &[f32],
    dst: &mut [f32],
    dt: f32,
    keep: f32,
    free: &[u8],
    is_v: bool,
) {
    let (w, _) = g.faces(is_v);
    dst.par_chunks_mut(w)
        .enumerate()
        .with_min_len(rows_per_job(w))
        .for_each_init(
            || (vec![0.0; w], vec![0.0; w]),
            |(xs, zs), (j, row)| {
                if is_v {
                    maccormack_row::<true>(g, u, v, fwd, j, dt, keep, free, xs, zs, row);
                } else {
                    maccormack_row::<false>(g, u, v, fwd, j, dt, keep, free, xs, zs, row);
                }
            },
        );
}

/// Row `j` of [`maccormack`] (v faces with `V`): the points the faces reach in `dt`, where
/// φ̌ = A⁻¹(φ̂) samples the forward result `fwd` into `row`, then the departure points and
/// the correction around them. `xs`, `zs`: room for a row's points.
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
fn maccormack_row<const V: bool>(
    g: &Geometry,
    u: &[f32],
    v: &[f32],
    fwd: &[f32],
    j: usize,
    dt: f32,
    keep: f32,
    free: &[u8],
    xs: &mut [f32],
    zs: &mut [f32],
    row: &mut [f32],
) {
    let (w, h) = g.faces(V);
    let orig = if V { v } else { u };
    let k = j * w;
    let (free, fwd_row, orig_row) = (&free[k..][..w], &fwd[k..][..w], &orig[k..][..w]);
    departures_row(g, u, v, j, V, -dt, xs, zs);
    sample_row_of::<V, false>(g, fwd, j, xs, zs, free, 1.0, row);
    departures_row(g, u, v, j, V, dt, xs, zs);
    if g.periodic {
        let f = Wrapped::new(orig, w, h, g.nx, g.ny);
        correct_wrapped::<V>(&f, j, xs, zs, free, fwd_row, orig_row, keep, row);
    } else {
        let f = Clamped::new(orig, w, h);
        correct_clamped::<V>(&f, j, xs, zs, free, fwd_row, orig_row, keep, row);
    }
}
