//! The band pipeline both pressure solves run on: a blocked pass runs many relaxation passes
//! over one band of rows while it is in cache ([`band_passes`]), the bands in parallel
//! ([`for_each_band`]), in blocks of at most [`MAX_BLOCK_LEVELS`] passes ([`blocks`]). The
//! Jacobi solve (`pressure.rs`) and the multigrid smoother (`multigrid/`) supply the row
//! kernels; a multigrid pass says how it turns Jacobi values into its own ([`Relax`]).

use super::*;

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

/// Red–black: keeps `prev` in the cells of the colour not updated by this pass, those with
/// `(i + k) % 2 == 1` (`k` = row + colour). Eight cells at a time through a bit mask the
/// compiler cannot see through: with a visible pattern it stores only the kept cells, one
/// by one or by a masked store, both far slower than a blend and a plain store.
#[simd_kernel]
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

/// `levels` passes for output rows `a..b`, written to `out`, in one sweep down the band:
/// `input(j, row)` fills row `j` of pass 0, and `pass(t, j, dst, below, row, above)` makes
/// row `j` of pass `t` from pass `t − 1`'s rows; `pair(t, [j, j + 1], dsts, rows)` makes two
/// rows at once from pass `t − 1`'s rows `j − 1 ..= j + 2` (the same values as two `pass`es:
/// it reads the two middle rows once for both). The sweep goes two rows at a time: pass `t`
/// trails pass `t − 1` by two rows, and each keeps only its last six rows (a ring), so the
/// band's working set stays in cache while every pass runs. To produce rows `a..b` after
/// `levels` passes, pass `t` must cover `levels − t` extra rows on each side (the
/// trapezoid); those ghost rows are recomputed by the neighbouring bands, with the same
/// arithmetic, so the result does not depend on the banding. Rows wrap when `wraps`;
/// otherwise the first and last rows have no neighbour beyond the grid (its weight is zero)
/// and get the row itself.
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
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
    pair: impl Fn(usize, [usize; 2], [&mut [f32]; 2], [&[f32]; 4]),
) {
    const RING: usize = 6;
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
    let slot = |r: isize| r.rem_euclid(RING as isize) as usize * nx;
    // Rings for passes 0..levels (0 is the input); the last writes to `out`. At the step
    // that reads rows r, r + 1, pass t makes rows s = r − 2t and s + 1 from pass t − 1's
    // rows s − 1 ..= s + 2, made two steps and this step before: with s + 3, five rows
    // live in each ring of six.
    let mut ring = vec![0.0f32; levels * RING * nx];
    let mut r = lo(0);
    while r < hi(0) + 2 * k {
        for q in [r, r + 1] {
            if q < hi(0) {
                input(wrap(q), &mut ring[slot(q)..][..nx]);
            }
        }
        for t in 1..=k {
            let s = r - 2 * t;
            let made = |q: isize| q >= lo(t) && q < hi(t);
            if !made(s) && !made(s + 1) {
                continue;
            }
            // A row's neighbours in pass t − 1, the row itself beyond its range.
            let below = |q: isize| if q > lo(t - 1) { q - 1 } else { q };
            let above = |q: isize| if q + 1 < hi(t - 1) { q + 1 } else { q };
            let (prev, cur) = ring.split_at_mut(t as usize * RING * nx);
            let prev = &prev[(t as usize - 1) * RING * nx..];
            let row = |q: isize| &prev[slot(q)..][..nx];
            // Rows s and s + 1 of pass t: in `out` for the last pass, else in its ring
            // (adjacent slots, or the ring's last and first).
            let (d0, d1): (&mut [f32], &mut [f32]) = if t == k {
                // Pass k makes rows a..b exactly (at least one of the two).
                let at = |q: isize| (q - a) as usize * nx;
                match (made(s), made(s + 1)) {
                    (true, true) => {
                        let (x, y) = out.split_at_mut(at(s + 1));
                        (&mut x[at(s)..], &mut y[..nx])
                    }
                    (true, false) => (&mut out[at(s)..][..nx], &mut []),
                    _ => (&mut [], &mut out[at(s + 1)..][..nx]),
                }
            } else {
                let (i0, i1) = (slot(s), slot(s + 1));
                let cur = &mut cur[..RING * nx];
                if i0 < i1 {
                    let (x, y) = cur.split_at_mut(i1);
                    (&mut x[i0..], &mut y[..nx])
                } else {
                    let (x, y) = cur.split_at_mut(i0);
                    (&mut y[..nx], &mut x[i1..][..nx])
                }
            };
            if made(s) && made(s + 1) {
                let rows = [row(below(s)), row(s), row(s + 1), row(above(s + 1))];
                pair(t as usize, [wrap(s), wrap(s + 1)], [d0, d1], rows);
                continue;
            }
            for (q, dst) in [(s, d0), (s + 1, d1)] {
                if made(q) {
                    pass(
                        t as usize,
                        wrap(q),
                        dst,
                        row(below(q)),
                        row(q),
                        row(above(q)),
                    );
                }
            }
        }
        r += 2;
    }
}
