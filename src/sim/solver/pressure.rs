//! Step 5, the pressure solve: the warm start and Jacobi iterations, cache-blocked (each band
//! of rows runs many iterations while it is in cache), and the plain sweep they must equal.

use super::multigrid::{Level, add_correction};
use super::*;

impl Solver {
    /// Step 5, the pressure solve `∇²p = div` the layout asks for (`sim.pressure`).
    pub fn solve_pressure(&mut self) {
        match self.params.pressure {
            PressureSolve::Jacobi => self.solve_pressure_jacobi(),
            PressureSolve::Multigrid => self.solve_pressure_multigrid(),
        }
    }

    /// Step 5 by Jacobi: warm start and Jacobi iterations, blocked for cache: each band
    /// of rows runs many iterations while its rows are in cache (see `jacobi_band`). The
    /// result is bit-for-bit that of [`Self::jacobi_iteration`] repeated.
    pub fn solve_pressure_jacobi(&mut self) {
        let decay = self.params.pressure_decay;
        let k = self.params.pressure_iterations as usize;
        if k == 0 {
            self.p.par_iter_mut().for_each(|p| *p *= decay);
            return;
        }
        // The warm start's decay is applied as the first block reads p (×1 is exact).
        self.sweeps_blocked(k, decay, None, None);
    }

    /// `passes` blocked passes from `p × scale` (plus a prolonged coarse correction when
    /// given) into `p`, in [`blocks`]: Jacobi iterations, or multigrid relaxation (`relax`:
    /// red–black half sweeps, or damped Jacobi passes with one weight each). The scale and
    /// the correction go with the first block; each block continues the previous block's
    /// colours or weights.
    pub(super) fn sweeps_blocked(
        &mut self,
        passes: usize,
        scale: f32,
        relax: Option<Relax>,
        correction: Option<&Level>,
    ) {
        for (done, levels) in blocks(passes) {
            let first = done == 0;
            self.sweep_blocked(
                levels,
                if first { scale } else { 1.0 },
                relax.map(|r| r.after(done)),
                correction.filter(|_| first),
            );
        }
    }

    /// One blocked pass of `levels ≤ MAX_BLOCK_LEVELS` passes (see [`JacobiCtx`]).
    fn sweep_blocked(
        &mut self,
        levels: usize,
        scale: f32,
        relax: Option<Relax>,
        correction: Option<&Level>,
    ) {
        let (nx, ny) = (self.nx, self.ny);
        let ctx = JacobiCtx {
            nx,
            ny,
            st: self.stencil(),
            src: &self.p,
            div: &self.div,
            flags: &self.flags,
            inv_w: &self.inv_w,
            irregular: &self.row_irregular,
            wraps: self.params.boundary == Boundary::Periodic,
            scale,
            relax,
            correction,
        };
        for_each_band(&mut self.p_tmp, nx, ny, levels, |a, b, out| {
            jacobi_band(&ctx, out, a, b, levels);
        });
        std::mem::swap(&mut self.p, &mut self.p_tmp);
    }

    pub(super) fn stencil(&self) -> Stencil {
        Stencil::new(self.hx, self.hz)
    }

    /// One plain Jacobi sweep over the whole grid: `p ← (Σ w_n p_n − div) / Σ w_n` over the
    /// neighbours that take part (solids and closed walls: Neumann, dropped; open edges:
    /// p = 0 outside). The reference for the blocked solve.
    pub fn jacobi_iteration(&mut self) {
        let (nx, ny) = (self.nx, self.ny);
        let st = self.stencil();
        let (p, div, flags, runs) = (&self.p, &self.div, &self.flags, &self.row_irregular);
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
                    &runs[j],
                    None,
                );
            });
        std::mem::swap(&mut self.p, &mut self.p_tmp);
    }
}

/// At most this many Jacobi iterations run per blocked pass over the grid: more would make the
/// ghost rows each band recomputes (≈ levels² rows) outweigh the cache savings.
pub(super) const MAX_BLOCK_LEVELS: usize = 24;

/// Splits `total` passes into blocks of at most [`MAX_BLOCK_LEVELS`], as even as possible:
/// `(passes before the block, passes in it)`.
pub(super) fn blocks(total: usize) -> impl Iterator<Item = (usize, usize)> {
    let groups = total.div_ceil(MAX_BLOCK_LEVELS);
    let mut done = 0;
    (0..groups).map(move |g| {
        let n = (total - done).div_ceil(groups - g);
        done += n;
        (done - n, n)
    })
}

/// Runs `band(a, b, rows)` in parallel over the bands of rows `a..b` of a blocked pass of
/// `levels` passes over an `nx × ny` grid written to `out`: two bands per thread for
/// balance, but each well over the 2 × levels ghost rows a band recomputes at its ends.
pub(super) fn for_each_band(
    out: &mut [f32],
    nx: usize,
    ny: usize,
    levels: usize,
    band: impl Fn(usize, usize, &mut [f32]) + Sync,
) {
    let rows = ny
        .div_ceil(2 * rayon::current_num_threads())
        .max(4 * levels)
        .min(ny);
    out.par_chunks_mut(rows * nx)
        .enumerate()
        .for_each(|(k, out)| {
            let a = k * rows;
            band(a, a + out.len() / nx, out);
        });
}

/// `x` where pressure flags `fl` have `bit`, else 0.
#[inline(always)]
pub(super) fn pick(fl: u8, bit: u8, x: f32) -> f32 {
    if fl & bit != 0 { x } else { 0.0 }
}

/// Weights of the pressure stencil: `1/hx²`, `1/hz²`, and the inverse of their sum for a cell
/// with four fluid neighbours.
#[derive(Clone, Copy)]
pub(super) struct Stencil {
    pub(super) wx: f32,
    pub(super) wz: f32,
    pub(super) inv_regular: f32,
}

impl Stencil {
    pub(super) fn new(hx: f32, hz: f32) -> Self {
        let (wx, wz) = (1.0 / (hx * hx), 1.0 / (hz * hz));
        Self {
            wx,
            wz,
            inv_regular: 1.0 / (2.0 * wx + 2.0 * wz),
        }
    }

    /// `1 / Σw` for a cell with pressure flags `fl` (fluid and open-edge neighbours count;
    /// 0 when none does). For four fluid neighbours this is exactly `inv_regular`.
    pub(super) fn inv_weight(&self, fl: u8) -> f32 {
        let ws = self.weight_sum(fl);
        if ws > 0.0 { 1.0 / ws } else { 0.0 }
    }

    /// `Σw` for a cell with pressure flags `fl`: the weights of its fluid and open-edge
    /// neighbours.
    #[inline(always)]
    pub(super) fn weight_sum(&self, fl: u8) -> f32 {
        let n =
            |b: u8| f32::from(u8::from(fl & b != 0)) + f32::from(u8::from(fl & (b << EDGE) != 0));
        self.wx * (n(L) + n(R)) + self.wz * (n(B) + n(T))
    }
}

/// One Jacobi row from the previous iterate's rows `below`, `row`, `above` (rows wrap at the
/// grid's ends): `p = (wx (p_L + p_R) + wz (p_B + p_T) − div) / Σw`, where a neighbour that
/// does not take part (solid, wall, open edge at p = 0) contributes 0 and `inv_w` holds the
/// cell's `1 / Σw` (0 for cells outside the solve). Branch-free, so it vectorises; interior
/// cells outside the row's `irregular` runs all have four fluid neighbours and skip the
/// flags (the same arithmetic, the same bits: `pick` keeps every neighbour and `1 / Σw` is
/// exactly `inv_regular` there). With `damp = Some(w)`, a damped Jacobi pass instead: each
/// cell becomes `row + w·(jacobi − row)` ([`damp_row`]'s arithmetic, in the same loop).
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(windloom_static_simd), multiversion(targets = "simd"))]
#[cfg_attr(
    windloom_static_simd,
    multiversion(targets = "simd", dispatcher = "static")
)]
pub(super) fn jacobi_row(
    st: &Stencil,
    out: &mut [f32],
    below: &[f32],
    row: &[f32],
    above: &[f32],
    d: &[f32],
    f: &[u8],
    inv_w: &[f32],
    irregular: &[(usize, usize)],
    damp: Option<f32>,
) {
    let nx = out.len();
    let Stencil {
        wx,
        wz,
        inv_regular,
    } = *st;
    let cell = |i: usize, l: f32, r: f32| {
        let fl = f[i];
        let v = (wx * (pick(fl, L, l) + pick(fl, R, r))
            + wz * (pick(fl, B, below[i]) + pick(fl, T, above[i]))
            - d[i])
            * inv_w[i];
        match damp {
            Some(w) => row[i] + w * (v - row[i]),
            None => v,
        }
    };
    // The row's ends wrap to the other end (used only where periodic flags say so).
    out[0] = cell(0, row[nx - 1], row[1 % nx]);
    if nx == 1 {
        return;
    }
    out[nx - 1] = cell(nx - 1, row[nx - 2], row[0]);
    // Interior cells a..b, on the fast path or through the flags.
    let span = |out: &mut [f32], a: usize, b: usize, flagged: bool| {
        let n = b - a;
        let (o, l, r) = (&mut out[a..b], &row[a - 1..][..n], &row[a + 1..][..n]);
        let (bl, ab, dd) = (&below[a..b], &above[a..b], &d[a..b]);
        if flagged {
            let (ff, iw) = (&f[a..b], &inv_w[a..b]);
            for i in 0..n {
                let fl = ff[i];
                o[i] = (wx * (pick(fl, L, l[i]) + pick(fl, R, r[i]))
                    + wz * (pick(fl, B, bl[i]) + pick(fl, T, ab[i]))
                    - dd[i])
                    * iw[i];
            }
            if let Some(w) = damp {
                damp_row(o, &row[a..b], w);
            }
        } else if let Some(w) = damp {
            let c = &row[a..b];
            for i in 0..n {
                let v = (wx * (l[i] + r[i]) + wz * (bl[i] + ab[i]) - dd[i]) * inv_regular;
                o[i] = c[i] + w * (v - c[i]);
            }
        } else {
            for i in 0..n {
                o[i] = (wx * (l[i] + r[i]) + wz * (bl[i] + ab[i]) - dd[i]) * inv_regular;
            }
        }
    };
    for_spans(nx, irregular, |a, b, flagged| span(out, a, b, flagged));
}

/// Calls `span(a, b, flagged)` over the interior cells `1..n − 1` of a row in order: each run
/// of `irregular` flagged, the cells between the runs not.
#[inline(always)]
pub(super) fn for_spans(
    n: usize,
    irregular: &[(usize, usize)],
    mut span: impl FnMut(usize, usize, bool),
) {
    let mut next = 1;
    for &(a, b) in irregular {
        span(next, a, false);
        span(a, b, true);
        next = b;
    }
    span(next, n - 1, false);
}

/// What every band of a blocked Jacobi pass reads.
pub(super) struct JacobiCtx<'a> {
    pub(super) nx: usize,
    pub(super) ny: usize,
    pub(super) st: Stencil,
    pub(super) src: &'a [f32],
    pub(super) div: &'a [f32],
    pub(super) flags: &'a [u8],
    pub(super) inv_w: &'a [f32],
    pub(super) irregular: &'a [Vec<(usize, usize)>],
    /// Periodic: rows wrap around, so ghost rows continue past the grid's ends.
    pub(super) wraps: bool,
    pub(super) scale: f32,
    /// Multigrid relaxation instead of plain Jacobi: pass `t` (from 1) of the block is
    /// pass `t − 1` of the relaxation ([`Relax::weight`], [`Relax::finish`]).
    pub(super) relax: Option<Relax<'a>>,
    /// Multigrid: the finest level, whose expanded coarse correction is added to the input
    /// rows as they are read (the prolongation fused into the first smoothing pass).
    pub(super) correction: Option<&'a Level>,
}

/// `levels` Jacobi iterations (or multigrid relaxation passes) for output rows `a..b`,
/// written to `out`: [`band_passes`] with the Jacobi row.
pub(super) fn jacobi_band(c: &JacobiCtx, out: &mut [f32], a: usize, b: usize, levels: usize) {
    let nx = c.nx;
    let input = |j: usize, dst: &mut [f32]| {
        let src = &c.src[j * nx..][..nx];
        for (d, s) in dst.iter_mut().zip(src) {
            *d = s * c.scale;
        }
        if let Some(f) = c.correction {
            add_correction(f, j, dst);
        }
    };
    let pass = |t: usize, j: usize, dst: &mut [f32], below: &[f32], row: &[f32], above: &[f32]| {
        jacobi_row(
            &c.st,
            dst,
            below,
            row,
            above,
            &c.div[j * nx..][..nx],
            &c.flags[j * nx..][..nx],
            &c.inv_w[j * nx..][..nx],
            &c.irregular[j],
            c.relax.and_then(|r| r.weight(t - 1)),
        );
        if let Some(r) = c.relax {
            r.finish(t - 1, j, dst, row);
        }
    };
    band_passes(nx, c.ny, c.wraps, out, a, b, levels, input, pass);
}

/// Red–black: keeps `prev` in the cells of the colour not updated by this pass, those with
/// `(i + k) % 2 == 1` (`k` = row + colour). Eight cells at a time through a bit mask the
/// compiler cannot see through: with a visible pattern it stores only the kept cells, one
/// by one or by a masked store, both far slower than a blend and a plain store.
#[cfg_attr(not(windloom_static_simd), multiversion(targets = "simd"))]
#[cfg_attr(
    windloom_static_simd,
    multiversion(targets = "simd", dispatcher = "static")
)]
pub(super) fn keep_other_colour(dst: &mut [f32], prev: &[f32], k: usize) {
    let off = 1 - k % 2;
    let kept = |i: usize| if i % 2 == off { u32::MAX } else { 0 };
    let keep: [u32; 8] = std::hint::black_box(std::array::from_fn(kept));
    let n = dst.len();
    let mut d8 = dst.chunks_exact_mut(8);
    for (d, p) in (&mut d8).zip(prev.chunks_exact(8)) {
        for i in 0..8 {
            d[i] = f32::from_bits((d[i].to_bits() & !keep[i]) | (p[i].to_bits() & keep[i]));
        }
    }
    for i in n / 8 * 8..n {
        if i % 2 == off {
            dst[i] = prev[i];
        }
    }
}

/// How a multigrid relaxation pass turns a row's Jacobi values into the pass's result.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Relax<'a> {
    /// Red–black Gauss–Seidel half sweeps, colour `c` first: pass `t` keeps the Jacobi value
    /// in the cells with `(i + j) % 2 == (c + t) % 2` and the old value in the others.
    RedBlack(usize),
    /// Damped Jacobi, pass `t` with weight `w[t]`: `x + w[t]·(jacobi − x)` in every cell.
    Damped(&'a [f32]),
}

impl<'a> Relax<'a> {
    /// The same relaxation `done` passes on (the next block of a blocked run).
    pub(crate) fn after(self, done: usize) -> Self {
        match self {
            Relax::RedBlack(c) => Relax::RedBlack((c + done) % 2),
            Relax::Damped(w) => Relax::Damped(&w[done..]),
        }
    }

    /// Pass `t`'s damping weight (none for a red–black half sweep), which the row kernels
    /// apply as they compute the Jacobi values.
    pub(crate) fn weight(self, t: usize) -> Option<f32> {
        match self {
            Relax::RedBlack(_) => None,
            Relax::Damped(w) => Some(w[t]),
        }
    }

    /// What pass `t` does to row `j` after the row kernel: a red–black half sweep keeps the
    /// other colour's values from `prev` (`dst` holds the row's Jacobi values); a damped pass
    /// is complete.
    pub(crate) fn finish(self, t: usize, j: usize, dst: &mut [f32], prev: &[f32]) {
        if let Relax::RedBlack(c) = self {
            keep_other_colour(dst, prev, j + c + t);
        }
    }
}

/// Damped Jacobi: `dst ← prev + w·(dst − prev)`, `dst` holding the Jacobi values (cells
/// outside the solve hold 0 in both, and keep it).
#[inline(always)]
fn damp_row(dst: &mut [f32], prev: &[f32], w: f32) {
    for (d, &p) in dst.iter_mut().zip(prev) {
        *d = p + w * (*d - p);
    }
}

/// `levels` passes for output rows `a..b`, written to `out`, in one sweep down the band:
/// `input(j, row)` fills row `j` of pass 0, and `pass(t, j, dst, below, row, above)` makes
/// row `j` of pass `t` from pass `t − 1`'s rows. Pass `t` trails pass `t − 1` by one row,
/// and each keeps only its last three rows (a ring), so the band's working set stays in
/// cache while every pass runs. To produce rows `a..b` after `levels` passes, pass `t` must
/// cover `levels − t` extra rows on each side (the trapezoid); those ghost rows are
/// recomputed by the neighbouring bands, with the same arithmetic, so the result does not
/// depend on the banding. Rows wrap when `wraps`; otherwise the first and last rows have no
/// neighbour beyond the grid (its weight is zero) and get the row itself.
#[allow(clippy::too_many_arguments)]
pub(super) fn band_passes(
    nx: usize,
    ny: usize,
    wraps: bool,
    out: &mut [f32],
    a: usize,
    b: usize,
    levels: usize,
    mut input: impl FnMut(usize, &mut [f32]),
    pass: impl Fn(usize, usize, &mut [f32], &[f32], &[f32], &[f32]),
) {
    let k = levels as isize;
    let (a, b) = (a as isize, b as isize);
    let lo = |t: isize| {
        let r = a - (k - t);
        if wraps { r } else { r.max(0) }
    };
    let hi = |t: isize| {
        let r = b + (k - t);
        if wraps { r } else { r.min(ny as isize) }
    };
    let wrap = |r: isize| r.rem_euclid(ny as isize) as usize;
    let slot = |r: isize| r.rem_euclid(3) as usize * nx;
    // Rings for passes 0..levels (0 is the input); the last writes to `out`.
    let mut ring = vec![0.0f32; levels * 3 * nx];
    for r in lo(0)..hi(0) + k {
        if r < hi(0) {
            input(wrap(r), &mut ring[slot(r)..][..nx]);
        }
        for t in 1..=k {
            let s = r - t;
            if s < lo(t) || s >= hi(t) {
                continue;
            }
            let sb = if s > lo(t - 1) { s - 1 } else { s };
            let sa = if s + 1 < hi(t - 1) { s + 1 } else { s };
            let (prev, cur) = ring.split_at_mut(t as usize * 3 * nx);
            let prev = &prev[(t as usize - 1) * 3 * nx..];
            let dst = if t == k {
                &mut out[(s - a) as usize * nx..][..nx]
            } else {
                &mut cur[slot(s)..][..nx]
            };
            pass(
                t as usize,
                wrap(s),
                dst,
                &prev[slot(sb)..][..nx],
                &prev[slot(s)..][..nx],
                &prev[slot(sa)..][..nx],
            );
        }
    }
}
