//! Step 5, the pressure solve: the warm start and Jacobi iterations, cache-blocked (each band
//! of rows runs many iterations while it is in cache, on `bands.rs`'s pipeline), the row
//! kernels the multigrid smoother shares, and the plain sweep they must equal.

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
            self.p.par_iter_mut().for_each(|p| *p = flush(*p * decay));
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

    /// A cell with four fluid neighbours (`l`, `r` along x, `b`, `t` along z) and
    /// divergence `d`: what the flagged stencil gives there, by the fast path's arithmetic.
    #[inline(always)]
    pub(super) fn regular(&self, l: f32, r: f32, b: f32, t: f32, d: f32) -> f32 {
        flush((self.wx * (l + r) + self.wz * (b + t) - d) * self.inv_regular)
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
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
#[simd_kernel]
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
    let r = JacobiRow {
        below,
        row,
        above,
        d,
        f,
        inv_w,
    };
    if !r.ends(st, out, damp) {
        return;
    }
    for_spans(out.len(), irregular, |a, b, flagged| {
        r.span(st, out, a, b, flagged, damp)
    });
}

/// Two Jacobi rows at once, `j` and `j + 1` (`rows`: the previous iterate's rows `j − 1`
/// to `j + 2`; the others as [`jacobi_row`] takes them, one per output row): the same
/// values, bit for bit, as two calls of [`jacobi_row`]. Where neither row is irregular one
/// loop makes both, reading the two middle rows once for both, so a blocked pass
/// ([`band_passes`]) reads four source rows per two rows instead of six: 1–11% off the
/// bench's pressure pass at 1000², least on obstacles (12–16% with the arrays in cache).
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
#[simd_kernel]
pub(super) fn jacobi_rows2(
    st: &Stencil,
    o0: &mut [f32],
    o1: &mut [f32],
    [below, r0, r1, above]: [&[f32]; 4],
    [d0, d1]: [&[f32]; 2],
    [f0, f1]: [&[u8]; 2],
    [w0, w1]: [&[f32]; 2],
    [irr0, irr1]: [&[(usize, usize)]; 2],
    damp: Option<f32>,
) {
    let (n, nx) = (o0.len(), r0.len());
    assert!(nx == n && o1.len() == n, "rows of one width");
    let lower = JacobiRow {
        below,
        row: r0,
        above: r1,
        d: d0,
        f: f0,
        inv_w: w0,
    };
    let upper = JacobiRow {
        below: r0,
        row: r1,
        above,
        d: d1,
        f: f1,
        inv_w: w1,
    };
    // Both rows' ends (a one-cell row is its end only).
    let interior = lower.ends(st, o0, damp);
    upper.ends(st, o1, damp);
    if !interior {
        return;
    }
    if irr0.is_empty() && irr1.is_empty() {
        // Most rows: one span, without the run bookkeeping (whose live values made the
        // loop spill its pointers).
        regular_pair(
            st,
            &mut o0[1..n - 1],
            &mut o1[1..n - 1],
            [below, r0, r1, above],
            [d0, d1],
            1,
            damp,
        );
        return;
    }
    for_union_spans(n, irr0, irr1, |a, b, flagged| {
        if flagged {
            // Either row is irregular somewhere in a..b: each row by its own runs.
            for_spans_in(a, b, irr0, |a, b, fl| lower.span(st, o0, a, b, fl, damp));
            for_spans_in(a, b, irr1, |a, b, fl| upper.span(st, o1, a, b, fl, damp));
            return;
        }
        regular_pair(
            st,
            &mut o0[a..b],
            &mut o1[a..b],
            [below, r0, r1, above],
            [d0, d1],
            a,
            damp,
        );
    });
}

/// Cells `a..a + p0.len()` of two rows whose cells there all have four fluid neighbours
/// (`JacobiRow::span`'s regular loops, for both rows at once).
#[inline(always)]
fn regular_pair(
    st: &Stencil,
    p0: &mut [f32],
    p1: &mut [f32],
    [below, r0, r1, above]: [&[f32]; 4],
    [d0, d1]: [&[f32]; 2],
    a: usize,
    damp: Option<f32>,
) {
    let m = p0.len();
    let p1 = &mut p1[..m];
    let (l0, c0, rr0) = (&r0[a - 1..][..m], &r0[a..][..m], &r0[a + 1..][..m]);
    let (l1, c1, rr1) = (&r1[a - 1..][..m], &r1[a..][..m], &r1[a + 1..][..m]);
    let (bl, ab, dd0, dd1) = (
        &below[a..][..m],
        &above[a..][..m],
        &d0[a..][..m],
        &d1[a..][..m],
    );
    if let Some(w) = damp {
        for i in 0..m {
            p0[i] = damped(c0[i], w, st.regular(l0[i], rr0[i], bl[i], c1[i], dd0[i]));
            p1[i] = damped(c1[i], w, st.regular(l1[i], rr1[i], c0[i], ab[i], dd1[i]));
        }
    } else {
        for i in 0..m {
            p0[i] = st.regular(l0[i], rr0[i], bl[i], c1[i], dd0[i]);
            p1[i] = st.regular(l1[i], rr1[i], c0[i], ab[i], dd1[i]);
        }
    }
}

/// What one Jacobi row reads: the previous iterate's rows below, at and above it, and the
/// row's divergence, pressure flags and `1 / Σw`.
struct JacobiRow<'a> {
    below: &'a [f32],
    row: &'a [f32],
    above: &'a [f32],
    d: &'a [f32],
    f: &'a [u8],
    inv_w: &'a [f32],
}

impl JacobiRow<'_> {
    /// Cell `i` from its flags, its left and right neighbours given (they wrap at the
    /// row's ends).
    #[inline(always)]
    fn cell(&self, st: &Stencil, i: usize, l: f32, r: f32, damp: Option<f32>) -> f32 {
        let fl = self.f[i];
        let v = flush(
            (st.wx * (pick(fl, L, l) + pick(fl, R, r))
                + st.wz * (pick(fl, B, self.below[i]) + pick(fl, T, self.above[i]))
                - self.d[i])
                * self.inv_w[i],
        );
        match damp {
            Some(w) => damped(self.row[i], w, v),
            None => v,
        }
    }

    /// The row's two end cells, whose neighbours wrap to the other end (used only where
    /// periodic flags say so); false when the row has no interior.
    #[inline(always)]
    fn ends(&self, st: &Stencil, out: &mut [f32], damp: Option<f32>) -> bool {
        let (nx, row) = (out.len(), self.row);
        out[0] = self.cell(st, 0, row[nx - 1], row[1 % nx], damp);
        if nx == 1 {
            return false;
        }
        out[nx - 1] = self.cell(st, nx - 1, row[nx - 2], row[0], damp);
        true
    }

    /// Interior cells `a..b` into `out[a..b]`, through the flags or on the fast path.
    #[inline(always)]
    fn span(
        &self,
        st: &Stencil,
        out: &mut [f32],
        a: usize,
        b: usize,
        flagged: bool,
        damp: Option<f32>,
    ) {
        let (wx, wz) = (st.wx, st.wz);
        let (row, n) = (self.row, b - a);
        let (o, l, r) = (&mut out[a..b], &row[a - 1..][..n], &row[a + 1..][..n]);
        let (bl, ab, dd) = (&self.below[a..b], &self.above[a..b], &self.d[a..b]);
        if flagged {
            let (ff, iw) = (&self.f[a..b], &self.inv_w[a..b]);
            for i in 0..n {
                let fl = ff[i];
                o[i] = flush(
                    (wx * (pick(fl, L, l[i]) + pick(fl, R, r[i]))
                        + wz * (pick(fl, B, bl[i]) + pick(fl, T, ab[i]))
                        - dd[i])
                        * iw[i],
                );
            }
            if let Some(w) = damp {
                damp_row(o, &row[a..b], w);
            }
        } else if let Some(w) = damp {
            let c = &row[a..b];
            for i in 0..n {
                o[i] = damped(c[i], w, st.regular(l[i], r[i], bl[i], ab[i], dd[i]));
            }
        } else {
            for i in 0..n {
                o[i] = st.regular(l[i], r[i], bl[i], ab[i], dd[i]);
            }
        }
    }
}

/// Calls `span(a, b, flagged)` over the interior cells `1..n − 1` of a row in order: each run
/// of `irregular` flagged, the cells between the runs not.
#[inline(always)]
pub(super) fn for_spans(
    n: usize,
    irregular: &[(usize, usize)],
    span: impl FnMut(usize, usize, bool),
) {
    for_spans_in(1, n - 1, irregular, span);
}

/// [`for_spans`] over cells `a..b` only: the runs clipped to them.
#[inline(always)]
fn for_spans_in(
    a: usize,
    b: usize,
    irregular: &[(usize, usize)],
    mut span: impl FnMut(usize, usize, bool),
) {
    let mut next = a;
    for &(ra, rb) in irregular {
        let (ra, rb) = (ra.max(a), rb.min(b));
        if ra >= rb {
            continue;
        }
        span(next, ra, false);
        span(ra, rb, true);
        next = rb;
    }
    span(next, b, false);
}

/// [`for_spans`] over the union of two rows' runs: flagged where either row is irregular.
#[inline(always)]
fn for_union_spans(
    n: usize,
    first: &[(usize, usize)],
    second: &[(usize, usize)],
    mut span: impl FnMut(usize, usize, bool),
) {
    let (mut i, mut k, mut next) = (0, 0, 1);
    let mut open: Option<(usize, usize)> = None;
    loop {
        // The run that starts first, of either row (each row's runs are in order).
        let run = match (first.get(i), second.get(k)) {
            (Some(x), Some(y)) if x.0 <= y.0 => {
                i += 1;
                *x
            }
            (_, Some(y)) => {
                k += 1;
                *y
            }
            (Some(x), None) => {
                i += 1;
                *x
            }
            (None, None) => break,
        };
        open = match open {
            Some((a, b)) if run.0 <= b => Some((a, b.max(run.1))),
            Some((a, b)) => {
                span(next, a, false);
                span(a, b, true);
                next = b;
                Some(run)
            }
            None => Some(run),
        };
    }
    if let Some((a, b)) = open {
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
/// written to `out`: [`band_passes`] with the Jacobi rows, two at a time.
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
    let pair = |t: usize, js: [usize; 2], dst: [&mut [f32]; 2], rows: [&[f32]; 4]| {
        let row = |j: usize| j * nx..(j + 1) * nx;
        let [r0, r1] = [rows[1], rows[2]];
        let [o0, o1] = dst;
        jacobi_rows2(
            &c.st,
            o0,
            o1,
            rows,
            js.map(|j| &c.div[row(j)]),
            js.map(|j| &c.flags[row(j)]),
            js.map(|j| &c.inv_w[row(j)]),
            js.map(|j| c.irregular[j].as_slice()),
            c.relax.and_then(|r| r.weight(t - 1)),
        );
        if let Some(r) = c.relax {
            r.finish(t - 1, js[0], o0, r0);
            r.finish(t - 1, js[1], o1, r1);
        }
    };
    band_passes(nx, c.ny, c.wraps, out, a, b, levels, input, pass, pair);
}

/// Damped Jacobi: `dst ← prev + w·(dst − prev)`, `dst` holding the Jacobi values (cells
/// outside the solve hold 0 in both, and keep it).
#[inline(always)]
fn damp_row(dst: &mut [f32], prev: &[f32], w: f32) {
    for (d, &p) in dst.iter_mut().zip(prev) {
        *d = damped(p, w, *d);
    }
}

/// A damped Jacobi update: `prev + w·(jacobi − prev)`.
#[inline(always)]
pub(super) fn damped(prev: f32, w: f32, jacobi: f32) -> f32 {
    flush(prev + w * (jacobi - prev))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Spans of `for_union_spans` as (start, end, flagged), empty ones left out.
    fn union(n: usize, a: &[(usize, usize)], b: &[(usize, usize)]) -> Vec<(usize, usize, bool)> {
        let mut v = Vec::new();
        for_union_spans(n, a, b, |s, e, f| {
            if s < e {
                v.push((s, e, f));
            }
        });
        v
    }

    /// The union of two rows' runs: flagged wherever either row is, in order, covering the
    /// interior once: disjoint, overlapping, nested, touching and absent runs.
    #[test]
    fn union_spans_cover_the_interior_once() {
        assert_eq!(union(10, &[], &[]), [(1, 9, false)]);
        assert_eq!(
            union(20, &[(2, 4), (10, 12)], &[(6, 7)]),
            [
                (1, 2, false),
                (2, 4, true),
                (4, 6, false),
                (6, 7, true),
                (7, 10, false),
                (10, 12, true),
                (12, 19, false)
            ]
        );
        assert_eq!(
            union(20, &[(2, 8)], &[(3, 5), (8, 9), (17, 19)]),
            [(1, 2, false), (2, 9, true), (9, 17, false), (17, 19, true)]
        );
        assert_eq!(union(6, &[], &[(1, 5)]), [(1, 5, true)]);
    }

    /// Two rows at once give the bits of one row at a time: rows with and without irregular
    /// runs (flags as walls, obstacles and periodic edges give them), plain and damped
    /// passes, widths from one cell up.
    #[test]
    fn paired_rows_give_the_bits_of_single_rows() {
        let st = Stencil::new(0.7, 1.3);
        let mut seed = 12345u32;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed
        };
        for n in [1usize, 2, 3, 5, 17, 64, 131] {
            for case in 0..6 {
                let mut val = || (rnd() % 2001) as f32 / 1000.0 - 1.0;
                let rows: Vec<Vec<f32>> = (0..4).map(|_| (0..n).map(|_| val()).collect()).collect();
                let d: Vec<Vec<f32>> = (0..2).map(|_| (0..n).map(|_| val()).collect()).collect();
                // Case 0: both regular; 1, 2: one row irregular; others: both, at random.
                let flags: Vec<Vec<u8>> = (0..2)
                    .map(|r| {
                        (0..n)
                            .map(|_| {
                                let irregular = match case {
                                    0 => false,
                                    1 | 2 => r == case - 1 && rnd() % 4 == 0,
                                    _ => rnd() % 5 == 0,
                                };
                                if irregular {
                                    (rnd() % 256) as u8
                                } else {
                                    ALL_FLUID
                                }
                            })
                            .collect()
                    })
                    .collect();
                let inv: Vec<Vec<f32>> = flags
                    .iter()
                    .map(|f| f.iter().map(|&fl| st.inv_weight(fl)).collect())
                    .collect();
                let runs: Vec<Vec<(usize, usize)>> =
                    flags.iter().map(|f| irregular_runs(f)).collect();
                for damp in [None, Some(0.8)] {
                    let mut want = [vec![0.0; n], vec![0.0; n]];
                    for r in 0..2 {
                        jacobi_row(
                            &st,
                            &mut want[r],
                            &rows[r],
                            &rows[r + 1],
                            &rows[r + 2],
                            &d[r],
                            &flags[r],
                            &inv[r],
                            &runs[r],
                            damp,
                        );
                    }
                    let (mut o0, mut o1) = (vec![f32::NAN; n], vec![f32::NAN; n]);
                    jacobi_rows2(
                        &st,
                        &mut o0,
                        &mut o1,
                        [&rows[0], &rows[1], &rows[2], &rows[3]],
                        [&d[0], &d[1]],
                        [&flags[0], &flags[1]],
                        [&inv[0], &inv[1]],
                        [&runs[0], &runs[1]],
                        damp,
                    );
                    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    assert_eq!(
                        bits(&o0),
                        bits(&want[0]),
                        "row 0, n {n}, case {case}, {damp:?}"
                    );
                    assert_eq!(
                        bits(&o1),
                        bits(&want[1]),
                        "row 1, n {n}, case {case}, {damp:?}"
                    );
                }
            }
        }
    }
}
