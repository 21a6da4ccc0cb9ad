//! Step 1, the forces: AGC arrow splats and the pull toward the ambient wind, written only
//! to the faces each row's splats reach, in vectorised runs.

use super::gains::splat_gains;
use super::*;
use crate::sim::forces::{FftTables, RowScratch, SPLAT_CUTOFF_RADII};

impl Solver {
    /// Step 1: AGC arrow splats and the pull toward the ambient wind. Both read the velocity
    /// before the pass, so the u and v faces see the same state.
    pub fn apply_forces(&mut self, dt: f32) {
        self.apply_forces_with(dt, |f, u, v, inc, free, is_v| {
            f.increments(u, v, inc, free, is_v)
        });
    }

    /// Step 1 with the given kernel for one component's increments (fast or reference).
    fn apply_forces_with(&mut self, dt: f32, increments: Increments) {
        let splats = agc_splats(&self.layout, self.time());
        self.ambient.set_time(self.time());
        let coupling = if self.ambient.is_empty() {
            0.0
        } else {
            1.0 - crate::num::exp(-self.params.ambient_coupling * dt)
        };
        let mut f = Forcing {
            g: self.geometry(),
            origin: self.origin,
            splats: &splats,
            bounds: splats.iter().map(ArrowSplat::bounds).collect(),
            ambient: &self.ambient,
            coupling,
            response: self.params.arrow_response,
            dt,
            gains: Vec::new(),
        };
        if splats.is_empty() && coupling == 0.0 {
            self.force_faces = 0;
            self.force_gain_floats = 0;
            return;
        }
        // The gains get what the validation's memory budget leaves (about a float per face).
        let room = self
            .memory_budget_jacobi()
            .saturating_sub(self.base_memory_bytes());
        let room = self.max_gain_bytes.map_or(room, |m| room.min(m as u64));
        let kept = self.gain_cache.refresh(&f, room as usize / 4);
        f.gains = kept
            .iter()
            .map(|k| k.map(|k| self.gain_cache.get(k)))
            .collect();
        self.force_gain_floats = f.gains.iter().flatten().map(|g| g.floats()).sum();
        let rows_u = increments(&f, &self.u, &self.v, &mut self.u_tmp, &self.u_free, false);
        let rows_v = increments(&f, &self.u, &self.v, &mut self.v_tmp, &self.v_free, true);
        self.force_faces = add_rows(&mut self.u, &self.u_tmp, &rows_u, self.nx + 1)
            + add_rows(&mut self.v, &self.v_tmp, &rows_v, self.nx);
        self.sync_periodic();
    }
}

/// The velocity changes of one component's faces: `(forcing, u, v, increments, free, is_v)`
/// → the range of faces written in each row ([`Forcing::increments`] and its reference twin).
pub(super) type Increments =
    fn(&Forcing, &[f32], &[f32], &mut [f32], &[u8], bool) -> Vec<Range<usize>>;

/// Everything the forces pass needs for one substep.
pub(super) struct Forcing<'a> {
    pub(super) g: Geometry,
    pub(super) origin: [f32; 2],
    pub(super) splats: &'a [ArrowSplat],
    pub(super) bounds: Vec<([f32; 2], [f32; 2])>,
    pub(super) ambient: &'a Ambient,
    pub(super) coupling: f32,
    pub(super) response: f32,
    pub(super) dt: f32,
    /// Per splat, its gains kept across steps ([`GainCache`]); `None`: computed per row.
    pub(super) gains: Vec<Option<&'a SplatGains>>,
}

impl Forcing<'_> {
    /// Faces `first..=last` of a row of `w` faces (v faces with `is_v`) inside splat bounds
    /// `(lo, hi)` along x; `None` when the bounds miss the grid.
    pub(super) fn columns(
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

    /// The faces of a row at world `z` (of `w` faces, v faces with `is_v`) that splat `s`
    /// (bounds `b`) can push: none when the row misses its bounding box, else its
    /// [`ArrowSplat::x_extent_at`] widened by a face and a rounding margin, within the box's
    /// columns. Every face left out lies beyond the cutoff, where the push is exactly zero,
    /// so skipping it changes no bit. What the forces pass visits and what the kept gains
    /// cover.
    pub(super) fn splat_row(
        &self,
        s: &ArrowSplat,
        b: ([f32; 2], [f32; 2]),
        z: f32,
        w: usize,
        is_v: bool,
    ) -> Option<RangeInclusive<usize>> {
        if z < b.0[1] || z > b.1[1] {
            return None;
        }
        let boxed = self.columns(b, w, is_v)?;
        let (x0, x1) = s.x_extent_at(z)?;
        let pad = self.g.hx + 1e-3 * (s.radius * SPLAT_CUTOFF_RADII + x1.abs() + x0.abs());
        let cols = self.columns(([x0 - pad, b.0[1]], [x1 + pad, b.1[1]]), w, is_v)?;
        let first = *cols.start().max(boxed.start());
        let last = *cols.end().min(boxed.end());
        (first <= last).then_some(first..=last)
    }

    /// The faces of row `j` that the forces write: the hull of the active splats' columns, or
    /// the whole row when ambient layers pull on it. Empty when nothing reaches the row.
    pub(super) fn row_reach(&self, j: usize, w: usize, is_v: bool) -> Range<usize> {
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
    pub(super) fn row_z(&self, j: usize, is_v: bool) -> f32 {
        let oz = if is_v { 0.0 } else { 0.5 };
        self.origin[1] + (j as f32 + oz) * self.g.hz
    }

    /// Writes the velocity change of the faces each row's forces reach (see
    /// [`Self::row_reach`]) into `inc` (u faces, or v faces with `is_v`); returns those
    /// ranges, row by row.
    pub(super) fn increments(
        &self,
        u: &[f32],
        v: &[f32],
        inc: &mut [f32],
        free: &[u8],
        is_v: bool,
    ) -> Vec<Range<usize>> {
        let g = &self.g;
        let (w, _) = g.faces(is_v);
        let c = usize::from(is_v);
        let ox = if is_v { 0.5 } else { 0.0 };
        // World x of the faces of a row: the same for every row, so made once per pass.
        let xs: Vec<f32> = if self.coupling > 0.0 {
            (0..w as i32)
                .map(|i| self.origin[0] + (i as f32 + ox) * g.hx)
                .collect()
        } else {
            Vec::new()
        };
        let tables = if self.coupling > 0.0 {
            let (_, h) = g.faces(is_v);
            let zs = (0..h).map(|j| self.row_z(j, is_v));
            self.ambient.fft_tables(&xs, zs)
        } else {
            FftTables::NONE
        };
        inc.par_chunks_mut(w)
            .enumerate()
            .with_min_len(rows_per_job(w))
            .map_init(
                || {
                    let sums = (Vec::new(), Vec::new());
                    (RowScratch::default(), Vec::new(), Vec::new(), sums)
                },
                |(scratch, target, gain_scratch, (gains, squares)), (j, row)| {
                    let reach = self.row_reach(j, w, is_v);
                    if reach.is_empty() {
                        return reach;
                    }
                    row[reach.clone()].fill(0.0);
                    // Each face's gains summed over the splats, and their squares
                    // (`sim::forces::combine`).
                    gains.resize(w, 0.0);
                    gains[reach.clone()].fill(0.0);
                    squares.resize(w, 0.0);
                    squares[reach.clone()].fill(0.0);
                    let z_world = self.row_z(j, is_v);
                    let free = &free[j * w..][..w];
                    // Each splat only visits the faces inside its x-extent; per face the
                    // splats still add up in the same order.
                    for (k, (s, &b)) in self.splats.iter().zip(&self.bounds).enumerate() {
                        if let Some(span) = self.splat_row(s, b, z_world, w, is_v) {
                            let kept = self.gains.get(k).copied().flatten();
                            let out = (&mut row[..], &mut gains[..], &mut squares[..]);
                            self.splat_span(s, kept, u, v, j, is_v, span, free, out, gain_scratch);
                        }
                    }
                    if !self.splats.is_empty() {
                        let r = reach.clone();
                        combine_row(&mut row[r.clone()], &gains[r.clone()], &squares[r]);
                    }
                    if self.coupling > 0.0 {
                        // The ambient target along the whole row at once, then the pull.
                        target.resize(w, 0.0);
                        self.ambient
                            .component_row(c, z_world, &xs, &tables, target, scratch);
                        let own = if is_v {
                            &v[j * w..][..w]
                        } else {
                            &u[j * w..][..w]
                        };
                        pull(row, target, own, free, self.coupling);
                    }
                    reach
                },
            )
            .collect()
    }

    /// The faces of a row (u faces, or v faces with `is_v`) whose velocity stencil needs no
    /// wrap or clamp: all v faces, u faces 1..nx − 1.
    fn interior(&self, is_v: bool) -> (usize, usize) {
        let nx = self.g.nx;
        if is_v { (0, nx - 1) } else { (1, nx - 1) }
    }

    /// The part `(a, b)` of a splat's faces `span` (u faces, or v faces with `is_v`) inside
    /// [`Self::interior`].
    pub(super) fn interior_run(
        &self,
        span: &RangeInclusive<usize>,
        is_v: bool,
    ) -> Option<(usize, usize)> {
        let (lo, hi) = self.interior(is_v);
        let (a, b) = (*span.start().max(&lo), *span.end().min(&hi));
        (a <= b).then_some((a, b))
    }

    /// Splat `s` over the run of row `j` (u faces, or v faces with `is_v`) that starts at
    /// face `first`.
    pub(super) fn span_of<'s>(
        &self,
        s: &'s ArrowSplat,
        j: usize,
        is_v: bool,
        first: usize,
    ) -> SplatSpan<'s> {
        SplatSpan {
            s,
            k: self.response,
            dt: self.dt,
            first,
            x0: self.origin[0],
            ox: if is_v { 0.5 } else { 0.0 },
            hx: self.g.hx,
            z: self.row_z(j, is_v),
        }
    }

    /// Adds one splat's push to the free faces `span` of row `j`, and its gains to the row's
    /// sums of gains and of squared gains (`out`: the row's increments, its gains' sums and
    /// their squares' sums): the faces whose velocity stencil wraps or clamps one at a time,
    /// the rest in one branch-free loop (face velocities and impulses vectorise) with the
    /// gains `kept` for the splat, or, when it has none kept, computed into `scratch` first.
    #[allow(
        clippy::too_many_arguments,
        reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
    )]
    pub(super) fn splat_span(
        &self,
        s: &ArrowSplat,
        kept: Option<&SplatGains>,
        u: &[f32],
        v: &[f32],
        j: usize,
        is_v: bool,
        span: std::ops::RangeInclusive<usize>,
        free: &[u8],
        (row, sums, squares): (&mut [f32], &mut [f32], &mut [f32]),
        scratch: &mut Vec<f32>,
    ) {
        let g = &self.g;
        let nx = g.nx;
        let c = usize::from(is_v);
        // Where the row's faces are: the same x and z as the run's gains.
        let at = self.span_of(s, j, is_v, 0);
        #[inline(always)]
        #[allow(
            clippy::too_many_arguments,
            reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
        )]
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
        let push = |i: usize, vel: [f32; 2]| impulse(s, at.x(i as i32), at.z, vel, at.k, at.dt, c);
        let (lo, hi) = self.interior(is_v);
        for i in span.clone().filter(|i| !(lo..=hi).contains(i)) {
            if free[i] != 0 {
                row[i] += push(i, face_velocity(g, u, v, i, j, is_v));
            }
            let g = s.gain([at.x(i as i32), at.z], at.k, at.dt);
            sums[i] += g;
            squares[i] += g * g;
        }
        let Some((a, b)) = self.interior_run(&span, is_v) else {
            return;
        };
        let n = b - a + 1;
        let (out, fr) = (&mut row[a..=b], &free[a..=b]);
        let gain = match kept {
            Some(kept) => {
                let (first, gain) = kept.row(is_v, j);
                assert_eq!((first, gain.len()), (a, n), "the kept run is this run");
                gain
            }
            None => {
                scratch.resize(n, 0.0);
                splat_gains(&self.span_of(s, j, is_v, a), scratch);
                &scratch[..]
            }
        };
        if is_v {
            let w = nx + 1;
            let (jb, jt) = u_rows_beside(g, j);
            let own = &v[j * nx + a..][..n];
            let (ub0, ub1) = (&u[jb * w + a..][..n], &u[jb * w + a + 1..][..n]);
            let (ut0, ut1) = (&u[jt * w + a..][..n], &u[jt * w + a + 1..][..n]);
            splat_faces(s, true, gain, own, [ub0, ub1, ut0, ut1], fr, out);
        } else {
            let own = &u[j * (nx + 1) + a..][..n];
            let (vb0, vb1) = (&v[j * nx + a - 1..][..n], &v[j * nx + a..][..n]);
            let (vt0, vt1) = (&v[(j + 1) * nx + a - 1..][..n], &v[(j + 1) * nx + a..][..n]);
            splat_faces(s, false, gain, own, [vb0, vb1, vt0, vt1], fr, out);
        }
        for ((sum, sq), &g) in sums[a..=b].iter_mut().zip(&mut squares[a..=b]).zip(gain) {
            *sum += g;
            *sq += g * g;
        }
    }
}

/// The arrows' summed pushes of a row's faces, scaled down where more than four overlap
/// ([`crate::sim::forces::combine`]: by their sums of gains and of squared gains).
fn combine_row(row: &mut [f32], gains: &[f32], squares: &[f32]) {
    for ((x, &g), &sq) in row.iter_mut().zip(gains).zip(squares) {
        *x = crate::sim::forces::combine(*x, g, sq);
    }
}

/// One splat over a run of faces of one row: where the faces are, for their gains
/// ([`super::gains::splat_gains`]).
pub(super) struct SplatSpan<'a> {
    pub(super) s: &'a ArrowSplat,
    pub(super) k: f32,
    pub(super) dt: f32,
    /// Index of the run's first face in its row.
    pub(super) first: usize,
    /// World x of face `i` is `x0 + (i + ox) · hx`; the row's world z is `z`.
    pub(super) x0: f32,
    pub(super) ox: f32,
    pub(super) hx: f32,
    pub(super) z: f32,
}

impl SplatSpan<'_> {
    /// World x of face `i` of the row (an `i32`, so the gains' loop vectorises).
    #[inline(always)]
    pub(super) fn x(&self, i: i32) -> f32 {
        self.x0 + (i as f32 + self.ox) * self.hx
    }
}

/// Adds splat `splat`'s push `dir · gain · deficit` to the free faces of a run whose
/// velocity stencil needs no wrap or clamp: `gain` holds the faces' gains
/// ([`ArrowSplat::gain`]), `own` is the faces' own component, `other` the four faces of the
/// other component averaged onto each (v faces with `is_v`). Compiled for several SIMD
/// levels, picked at run time: the face velocities and impulses vectorise.
#[simd_kernel]
pub(super) fn splat_faces(
    splat: &ArrowSplat,
    is_v: bool,
    gain: &[f32],
    own: &[f32],
    other: [&[f32]; 4],
    free: &[u8],
    out: &mut [f32],
) {
    let n = out.len();
    let (gain, own, free) = (&gain[..n], &own[..n], &free[..n]);
    // Plain slices and a copy of the splat: with the slices behind a non-inlined
    // `array::map` and the splat behind a second reference, AVX2's cost model kept the loop
    // scalar (only AVX-512 vectorised it).
    let [o0, o1, o2, o3] = other;
    let (o0, o1, o2, o3) = (&o0[..n], &o1[..n], &o2[..n], &o3[..n]);
    let splat = *splat;
    // The pushed component's direction, chosen once rather than a `[x, z][c]` per face.
    let dc = if is_v { splat.dir[1] } else { splat.dir[0] };
    for q in 0..n {
        let avg = 0.25 * (o0[q] + o1[q] + o2[q] + o3[q]);
        let (vx, vz) = if is_v { (avg, own[q]) } else { (own[q], avg) };
        // `impulse_magnitude`'s product, the gain read rather than computed.
        let d = dc * (gain[q] * splat.deficit(vx, vz));
        out[q] = bit_select(free[q] != 0, out[q] + d, out[q]);
    }
}

/// The ambient pull `(target − own) · coupling` added to the free faces of a row (`own`: the
/// faces' own velocity component before the pass).
#[simd_kernel]
fn pull(out: &mut [f32], target: &[f32], own: &[f32], free: &[u8], coupling: f32) {
    let n = out.len();
    let (target, own, free) = (&target[..n], &own[..n], &free[..n]);
    for q in 0..n {
        let d = (target[q] - own[q]) * coupling;
        out[q] = bit_select(free[q] != 0, out[q] + d, out[q]);
    }
}

/// `field += inc` over each row's range in `reach`; returns the number of faces touched.
pub(super) fn add_rows(field: &mut [f32], inc: &[f32], reach: &[Range<usize>], w: usize) -> usize {
    field
        .par_chunks_mut(w)
        .zip(inc.par_chunks(w))
        .zip(reach.par_iter())
        .with_min_len(rows_per_job(w))
        .map(|((f, d), r)| {
            for (x, dx) in f[r.clone()].iter_mut().zip(&d[r.clone()]) {
                *x = flush(clamp_speed(*x + dx));
            }
            r.len()
        })
        .sum()
}
