//! The bilinear samplers of the advection passes, clamped (open and closed grids) or wrapped
//! (periodic grids), in vectorised row loops ([`sample_row`]). Their four loads and their
//! float-to-index conversion are unchecked so the loops vectorise: the solver's only
//! `unsafe` blocks, kept here beside the checks that make them sound.

use super::*;
use crate::sim::forces::{clamp_to, index};

/// The four samples around a departure point of a `w × h` field on a non-periodic grid and
/// the bilinear weights: the point (sample coordinates `x`, `z`) is clamped to the field, as
/// [`bilinear`] does. `w, h ≥ 2` and `src.len() ≥ w·h` must hold ([`Clamped::new`] checks).
pub(super) struct Clamped<'a> {
    pub(super) src: &'a [f32],
    pub(super) w: usize,
    pub(super) xmax: f32,
    pub(super) zmax: f32,
    pub(super) imax: i32,
    pub(super) jmax: i32,
}

impl<'a> Clamped<'a> {
    pub(super) fn new(src: &'a [f32], w: usize, h: usize) -> Self {
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

    /// `(i0, j0, fx, fz)`: the point clamped to the field, its lower-left sample and the
    /// fractions. `0 ≤ i0 ≤ w − 2`, `0 ≤ j0 ≤ h − 2` (a NaN coordinate is 0).
    #[inline(always)]
    pub(super) fn cell(&self, x: f32, z: f32) -> (i32, i32, f32, f32) {
        // One clamp that also sends NaN to 0, which `index` then need not repeat: a `clamp`
        // (NaN kept) and `index`'s own made four min/max a face.
        let (x, z) = (clamp_to(x, self.xmax), clamp_to(z, self.zmax));
        // SAFETY: x, z are finite and in [0, 2³¹) (`new`: the field has fewer than 2³¹
        // samples), so their truncations fit an i32.
        let (i0, j0) = unsafe { (x.to_int_unchecked::<i32>(), z.to_int_unchecked::<i32>()) };
        let (i0, j0) = (i0.min(self.imax), j0.min(self.jmax));
        (i0, j0, x - i0 as f32, z - j0 as f32)
    }

    /// `(a, b, c, d, fx, fz)`: the samples at `(i0, j0)`, `(i0+1, j0)`, `(i0, j0+1)`,
    /// `(i0+1, j0+1)` and the fractions.
    #[inline(always)]
    pub(super) fn corners(&self, x: f32, z: f32) -> (f32, f32, f32, f32, f32, f32) {
        let (i0, j0, fx, fz) = self.cell(x, z);
        let (k, w) = ((j0 * self.w as i32 + i0) as usize, self.w);
        // SAFETY: 0 ≤ i0 ≤ w − 2 and 0 ≤ j0 ≤ h − 2 (`cell`), so
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

/// The four samples around a departure point of a face field on a periodic grid, which
/// repeats every `px × pz` samples (`px ≤ w`, `pz ≤ h`: the last face column or row of a
/// periodic grid repeats the first), as [`bilinear`] wraps them. [`Wrapped::new`] checks.
pub(super) struct Wrapped<'a> {
    pub(super) src: &'a [f32],
    pub(super) w: usize,
    pub(super) px: f32,
    pub(super) pz: f32,
    pub(super) ix: i32,
    pub(super) iz: i32,
}

impl<'a> Wrapped<'a> {
    pub(super) fn new(src: &'a [f32], w: usize, h: usize, px: usize, pz: usize) -> Self {
        assert!(
            px >= 1 && pz >= 1 && px <= w && pz <= h && src.len() >= w * h,
            "a {px}x{pz} period in a {w}x{h} field"
        );
        assert!(w * h <= i32::MAX as usize);
        Self {
            src,
            w,
            px: px as f32,
            pz: pz as f32,
            ix: px as i32,
            iz: pz as i32,
        }
    }
}

/// Sample index and fraction along a periodic axis of period `p` (`n` as an integer): the
/// coordinate wrapped, its sample clamped into the period (NaN gives 0) and the next one,
/// with selects instead of an integer modulo so the loops vectorise. [`axis`] uses it too.
#[inline(always)]
pub(super) fn wrap(t: f32, p: f32, n: i32) -> (i32, i32, f32) {
    let t = wrap_coordinate(t, p);
    // `t` lies in [0, p] but for rounding far from the period, or is NaN (index 0); the
    // clamp is what `as usize` and `min` did.
    let i0 = index(t, p).clamp(0, n - 1);
    // `i0 + 1`, or 0 past the period's end.
    let i1 = (i0 + 1) * ((i0 + 1 != n) as i32);
    (i0, i1, t - i0 as f32)
}

impl Wrapped<'_> {
    /// As [`Clamped::corners`], the indices wrapped: `(i1, j1)` is `(i0 + 1, j0 + 1)` modulo
    /// the period.
    #[inline(always)]
    pub(super) fn corners(&self, x: f32, z: f32) -> (f32, f32, f32, f32, f32, f32) {
        let (i0, i1, fx) = wrap(x, self.px, self.ix);
        let (j0, j1, fz) = wrap(z, self.pz, self.iz);
        // In i32, as the clamped sampler: w·h ≤ i32::MAX (`new`), and 32-bit lanes
        // vectorise twice as wide as 64-bit ones.
        let w = self.w as i32;
        let (r0, r1) = (j0 * w, j1 * w);
        // SAFETY: 0 ≤ i0, i1 < px ≤ w and 0 ≤ j0, j1 < pz ≤ h (the clamps and selects in
        // `wrap`), so every index is in [0, w·h) and w·h ≤ src.len(), as `new` asserts.
        let (a, b, c, d) = unsafe {
            let s = self.src;
            (
                *s.get_unchecked((r0 + i0) as usize),
                *s.get_unchecked((r0 + i1) as usize),
                *s.get_unchecked((r1 + i0) as usize),
                *s.get_unchecked((r1 + i1) as usize),
            )
        };
        (a, b, c, d, fx, fz)
    }
}

/// What the samplers' row driver needs of a field: the four samples around any point, and
/// the row stride.
pub(super) trait Field {
    /// Faces at each end of a row's interior, and rows at the field's bottom, that the row
    /// loop leaves to the point-by-point path besides the row's ends and the edge rows: those
    /// whose near cells (see [`sample_row`]) [`Self::corners`] would not take as they lie.
    const RIM: usize;
    /// `(a, b, c, d, fx, fz)`: the samples at `(i0, j0)`, `(i1, j0)`, `(i0, j1)`, `(i1, j1)`
    /// and the fractions.
    fn corners(&self, x: f32, z: f32) -> (f32, f32, f32, f32, f32, f32);
    /// `(src, w, rows)`: the samples, their row stride and their rows.
    fn window(&self) -> (&[f32], usize, i32);
}

impl Field for Clamped<'_> {
    /// A near cell lies inside the field, where [`Clamped::cell`]'s clamps change nothing.
    const RIM: usize = 0;
    #[inline(always)]
    fn corners(&self, x: f32, z: f32) -> (f32, f32, f32, f32, f32, f32) {
        Clamped::corners(self, x, z)
    }
    #[inline(always)]
    fn window(&self) -> (&[f32], usize, i32) {
        (self.src, self.w, self.jmax + 2)
    }
}

impl Field for Wrapped<'_> {
    /// The loop leaves out the first and last interior faces and the second row, so every
    /// near cell lies in `[1, p − 1)` along each axis, where the wrap changes nothing
    /// (`t − p·⌊t/p⌋` is `t` for `0 ≤ t < p − 1`) and the next sample is not across the
    /// seam (the last u face, whose next column is the period's first, is left out).
    const RIM: usize = 1;
    #[inline(always)]
    fn corners(&self, x: f32, z: f32) -> (f32, f32, f32, f32, f32, f32) {
        Wrapped::corners(self, x, z)
    }
    #[inline(always)]
    fn window(&self) -> (&[f32], usize, i32) {
        (self.src, self.w, self.iz)
    }
}

/// The value of every face `k` of row `j` of a field sampled at departure points
/// `(xs[k], zs[k])`, in the field's sample coordinates (the face `(k, j)` at `(k, j)`;
/// [`super::advection::departures_row`]): `out[k] = value(k, out[k], a, b, c, d, fx, fz)`,
/// with the four samples around the point and its fractions (`reads_old`: `value` uses
/// `out[k]`).
///
/// A face's departure point is within one cell of the face itself almost everywhere (all
/// but 0.9–1.4% of the faces on the examples with strong arrows at 1000², all of them at
/// the editor's grids): its cell is `(k − 1 or k, j − 1 or j)`. Then the four samples are
/// among the 3 × 3 around the face, which the row's interior reads as nine plain vector
/// loads and picks from per face, where fetching them point by point costs four scalar
/// loads per face (AVX2 compilers emit no gathers). The row's two end faces, the faces
/// whose point lies farther (or across a period's seam), found in a second vector pass over
/// the rows that have any, the field's first and last rows and its rim ([`Field::RIM`]: a
/// periodic field's faces next to the ends and its second row) are sampled point by point.
/// Both give the same values. `interior` is `value` for the faces the row loops sample (all
/// but the two ends): the same function, or one without the free mask where the caller
/// knows those faces are all free.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
pub(super) fn sample_row<F: Field>(
    f: &F,
    j: usize,
    xs: &[f32],
    zs: &[f32],
    out: &mut [f32],
    reads_old: bool,
    value: impl Fn(usize, f32, f32, f32, f32, f32, f32, f32) -> f32,
    interior: impl Fn(usize, f32, f32, f32, f32, f32, f32, f32) -> f32,
) {
    let n = out.len();
    let (xs, zs) = (&xs[..n], &zs[..n]);
    let (src, w, rows) = f.window();
    let by_point = |k: usize, out: &mut [f32]| {
        let (a, b, c, d, fx, fz) = f.corners(xs[k], zs[k]);
        out[k] = value(k, out[k], a, b, c, d, fx, fz);
    };
    // Rows j − 1 ..= j + 1 inside the window, and a row of the field's own width.
    if n < 3 + 2 * F::RIM || n != w || j < 1 + F::RIM || j + 1 >= rows as usize {
        // `by_point`'s body written out, so this loop's vectorisation does not hang on the
        // closure being inlined (its calls below are not).
        for k in 0..n {
            let (a, b, c, d, fx, fz) = f.corners(xs[k], zs[k]);
            out[k] = value(k, out[k], a, b, c, d, fx, fz);
        }
        return;
    }
    let m = n - 2;
    let row = |r: usize| &src[r * w..][..n];
    let (below, here, above) = (row(j - 1), row(j), row(j + 1));
    // Each row's samples at columns k − 1, k, k + 1 for the interior faces k = 1 ..= m.
    fn three(r: &[f32], m: usize) -> (&[f32], &[f32], &[f32]) {
        (&r[..m], &r[1..][..m], &r[2..][..m])
    }
    let ((bl, bc, br), (hl, hc, hr)) = (three(below, m), three(here, m));
    let (al, ac, ar) = three(above, m);
    let (xi, zi) = (&xs[1..][..m], &zs[1..][..m]);
    // Where the departure point of face `k = q + 1` lies from the face: [`Spread`].
    let j_below = (j - 1) as f32;
    let spread = |q: i32, x: f32, z: f32| Spread::of(x, z, q as f32, j_below);
    // The interior faces the loops below sample: all but the field's rim (`q` is face
    // `q + 1`).
    let qs = F::RIM..m - F::RIM;
    // Every spread of the row or-ed: outside 1.0's bits where any face is far.
    let mut spreads = 0u32;
    {
        let inner = &mut out[1..][..m];
        // The face index as an i32 counter of its own: from `q as i32`, LLVM kept the
        // MacCormack clones' AVX2 counter as two vectors of i64 and narrowed them every
        // iteration (62 instructions a vector of faces; 50 with this). A float ramp read
        // from memory instead made the AVX-512 clones' advection 1.04–1.24× as slow at
        // 1000² (docs/PERFORMANCE.md).
        for (qi, q) in (F::RIM as i32..).zip(qs.clone()) {
            let Spread { s, dx, dz, fx, fz } = spread(qi, xi[q], zi[q]);
            spreads |= s;
            // Compared as bits, not as floats: with `dz == 0.0` LLVM gave the AVX-512
            // clone's open-row loop three masked loads of the row above, which wait for
            // the mask where a plain load need not, and that loop ran 8–14% slower at
            // 1000² on one thread (see docs/PERFORMANCE.md). Near, the two are the same.
            let (left, down) = (dx.to_bits() == 0, dz.to_bits() == 0);
            // The point's lower and upper rows, then its column and the next.
            let (t0, t1, t2) = (
                bit_select(down, bl[q], hl[q]),
                bit_select(down, bc[q], hc[q]),
                bit_select(down, br[q], hr[q]),
            );
            let (u0, u1, u2) = (
                bit_select(down, hl[q], al[q]),
                bit_select(down, hc[q], ac[q]),
                bit_select(down, hr[q], ar[q]),
            );
            let (a, b) = (bit_select(left, t0, t1), bit_select(left, t1, t2));
            let (c, d) = (bit_select(left, u0, u1), bit_select(left, u1, u2));
            // A far face keeps its value for the point-by-point pass below where `value`
            // reads it (MacCormack's correction).
            let v = interior(q + 1, inner[q], a, b, c, d, fx, fz);
            inner[q] = if reads_old {
                bit_select(Spread::near(s), v, inner[q])
            } else {
                v
            };
        }
    }
    by_point(0, out);
    by_point(n - 1, out);
    for k in (1..1 + F::RIM).chain(m + 1 - F::RIM..m + 1) {
        by_point(k, out);
    }
    if !Spread::near(spreads) {
        // The far faces (0.9–1.4% of the faces where arrows are strong, in runs along the
        // jets) sampled point by point in a second vector pass over the row, which beat
        // finding them in blocks and sampling each one in scalar code.
        let inner = &mut out[1..][..m];
        for (qi, q) in (F::RIM as i32..).zip(qs) {
            let (x, z) = (xi[q], zi[q]);
            let far = !Spread::near(spread(qi, x, z).s);
            let (a, b, c, d, fx, fz) = f.corners(x, z);
            let v = interior(q + 1, inner[q], a, b, c, d, fx, fz);
            inner[q] = bit_select(far, v, inner[q]);
        }
    }
}

/// Where a departure point `(x, z)` (sample coordinates) lies from the cell `(k − 1, j − 1)`
/// to the lower left of its face `(k, j)`, for [`sample_row`]'s interior loops.
///
/// The cell's offset `(dx, dz)` is found from the point's floors, in floats. Where the
/// cell is near, one of `(k − 1 or k, j − 1 or j)`, each offset is +0.0 or 1.0 and the
/// point lies inside the field (or inside the period, past its rim), so these are the
/// numbers `corners` finds after its clamps, truncation or wrap. An integer-valued float
/// whose bits lie within 1.0's is +0.0 or 1.0, so the spread `s`, the offsets' bits or-ed,
/// lies within 1.0's just when the cell is near; a NaN, infinite, −0.0 or other offset
/// sets a bit outside (a far face, sampled point by point). Three operations an axis where
/// a clamp, a truncation and a conversion back took six, and no constants for AVX2's
/// sixteen registers to hold.
struct Spread {
    s: u32,
    dx: f32,
    dz: f32,
    fx: f32,
    fz: f32,
}

impl Spread {
    /// The offsets of `(x, z)` from `(k − 1, j − 1)` = `(q, j_below)` and its fractions.
    #[inline(always)]
    fn of(x: f32, z: f32, q: f32, j_below: f32) -> Self {
        let (fl_x, fl_z) = (x.floor(), z.floor());
        let (dx, dz) = (fl_x - q, fl_z - j_below);
        Spread {
            s: dx.to_bits() | dz.to_bits(),
            dx,
            dz,
            fx: x - fl_x,
            fz: z - fl_z,
        }
    }

    /// Whether a spread (or several or-ed) says near: its bits within 1.0's.
    #[inline(always)]
    fn near(s: u32) -> bool {
        s & !ONE == 0
    }
}

/// 1.0's bits: see [`Spread`].
const ONE: u32 = 0x3f80_0000;

/// Whether every face of a row but its two ends is free (no obstacle, no wall: every row of
/// a layout without obstacles), so [`sample_row`]'s interior loops can leave out the mask.
/// A byte minimum as a fold, which vectorises (`all` stops at each byte).
#[inline(always)]
fn interior_free(free: &[u8]) -> bool {
    let n = free.len();
    n < 3 || free[1..n - 1].iter().fold(u8::MAX, |a, &b| a.min(b)) != 0
}

/// The bilinear blend of four samples, as the reference writes it.
#[inline(always)]
fn bilerp(a: f32, b: f32, c: f32, d: f32, fx: f32, fz: f32) -> f32 {
    let top = a + (b - a) * fx;
    let bottom = c + (d - c) * fx;
    top + (bottom - top) * fz
}

/// MacCormack's corrected value `φ̂ + (φ − φ̌)/2`, clamped to the range of the four samples.
#[inline(always)]
fn limited(a: f32, b: f32, c: f32, d: f32, fwd: f32, orig: f32, back: f32) -> f32 {
    let lo = a.min(b).min(c).min(d);
    let hi = a.max(b).max(c).max(d);
    let x = fwd + 0.5 * (orig - back);
    // `x.clamp(lo, hi)` without its `lo ≤ hi` assertion, which would keep the loop scalar
    // (lo ≤ hi always holds here).
    let x = if x < lo { lo } else { x };
    if x > hi { hi } else { x }
}

/// The row loops of one sampler type `$ty`, through [`sample_row`]: `$sample`
/// (semi-Lagrangian: the bilinear sample at each departure point of row `j` of u faces, or
/// of v faces with `V`, given in the field's sample coordinates, times `keep`; 0 on
/// faces that are not free; [`flush`]ed with `FLUSH`, the step's result) and `$correct`
/// (MacCormack: `back` holds φ̌ on entry and `(φ̂ + (φ − φ̌)/2)` clamped to the range of the
/// four samples of φ around the departure point, times `keep`, on exit). Compiled for several
/// SIMD levels, picked at run time; the same bits as the reference's sampler. A macro rather
/// than a generic so each loop is written once and still compiles as plainly as a
/// hand-written one.
macro_rules! row_samplers {
    ($ty:ident, $sample:ident, $correct:ident) => {
        #[allow(
            clippy::too_many_arguments,
            reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
        )]
        #[simd_kernel]
        pub(super) fn $sample<const V: bool, const FLUSH: bool>(
            f: &$ty,
            j: usize,
            xs: &[f32],
            zs: &[f32],
            free: &[u8],
            keep: f32,
            out: &mut [f32],
        ) {
            let free = &free[..out.len()];
            // A final value is flushed; MacCormack's intermediate φ̂ and φ̌ need not be.
            let fin = |x: f32| if FLUSH { flush(x) } else { x };
            let value = |k: usize, _, a, b, c, d, fx, fz| {
                bit_select(free[k] != 0, fin(bilerp(a, b, c, d, fx, fz) * keep), 0.0)
            };
            let open = interior_free(free);
            if open {
                let open = |_, _, a, b, c, d, fx, fz| fin(bilerp(a, b, c, d, fx, fz) * keep);
                sample_row(f, j, xs, zs, out, false, value, open);
            } else {
                sample_row(f, j, xs, zs, out, false, value, value);
            }
        }

        #[allow(
            clippy::too_many_arguments,
            reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
        )]
        #[simd_kernel]
        pub(super) fn $correct<const V: bool>(
            f: &$ty,
            j: usize,
            xs: &[f32],
            zs: &[f32],
            free: &[u8],
            fwd: &[f32],
            orig: &[f32],
            keep: f32,
            back: &mut [f32],
        ) {
            let n = back.len();
            let (free, fwd, orig) = (&free[..n], &fwd[..n], &orig[..n]);
            let value = |k: usize, back, a, b, c, d, _, _| {
                let x = limited(a, b, c, d, fwd[k], orig[k], back);
                bit_select(free[k] != 0, flush(x * keep), 0.0)
            };
            let open = interior_free(free);
            if open {
                let open = |k: usize, back, a, b, c, d, _, _| {
                    flush(limited(a, b, c, d, fwd[k], orig[k], back) * keep)
                };
                sample_row(f, j, xs, zs, back, true, value, open);
            } else {
                sample_row(f, j, xs, zs, back, true, value, value);
            }
        }
    };
}

row_samplers!(Clamped, sample_clamped, correct_clamped);
row_samplers!(Wrapped, sample_wrapped, correct_wrapped);

#[cfg(test)]
mod tests {
    use super::*;

    /// The vectorisable index is the saturating `as` it replaced, for every float the
    /// samplers can meet: NaN, infinities, values far outside the field or period, and the
    /// edges (its `unsafe` conversion is only sound if it clamps first).
    #[test]
    fn the_sampler_index_is_the_saturating_conversion() {
        let mut ts = vec![
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            f32::MIN,
            -1e30,
            1e30,
            -0.0,
            0.0,
            -0.5,
            2147483648.0,
            -2147483904.0,
        ];
        for m in [1.0f32, 89.0, 90.0, 1000.0] {
            for d in [-1.0, -1e-4, 0.0, 1e-4, 0.5, 1.0, 7.3] {
                ts.push(m + d);
                ts.push(d);
            }
        }
        for &m in &[1.0f32, 89.0, 90.0, 1000.0] {
            let n = m as i32;
            for &t in &ts {
                let clamped = t.clamp(0.0, m);
                assert_eq!(
                    index(clamped, m).min(n - 1),
                    (clamped as i32).min(n - 1),
                    "clamped {t} in [0, {m}]"
                );
                let w = wrap_coordinate(t, m);
                let (i0, i1, f) = wrap(t, m, n);
                assert_eq!(i0, (w as i32).clamp(0, n - 1), "wrapped {t} by {m}");
                assert_eq!(i1, (i0 + 1) % n);
                assert_eq!(f.to_bits(), (w - i0 as f32).to_bits(), "{t} by {m}");
            }
        }
    }

    /// The row loops' cell test is sound: wherever [`Spread`] says a face's point is near,
    /// `corners` takes the cell the loop reads (`(k − 1 + dx, j − 1 + dz)`, among the
    /// 3 × 3 around the face) and the same fractions, bit for bit, on the clamped field and,
    /// past its rim, on the periodic one. Points on and beside cell edges, off the field,
    /// far away, ±0, infinite and NaN; both offsets seen near, and far points seen.
    #[test]
    fn a_near_spread_is_the_cell_corners_takes() {
        let (w, h) = (9usize, 7usize);
        // Distinct samples, so the four `corners` returns name their cell.
        let src: Vec<f32> = (0..w * h).map(|i| i as f32).collect();
        let mut ts = vec![
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -0.0,
            1e30,
            -1e30,
        ];
        for t in -2..=(w as i32 + 2) {
            let t = t as f32;
            for d in [-0.5, -1e-6, 0.0, 1e-6, 0.25, 0.5, 0.999_999] {
                ts.push(t + d);
            }
            // The floats either side of the integer.
            ts.push(f32::from_bits(t.to_bits().wrapping_sub(1)));
            ts.push(f32::from_bits(t.to_bits() + 1));
        }
        let clamped = Clamped::new(&src, w, h);
        let wrapped = Wrapped::new(&src, w, h, w - 1, h - 1);
        // A field's `corners` as an array, its rim and its rows.
        type Sampler<'a> = (&'a dyn Fn(f32, f32) -> [f32; 6], usize, usize);
        let fields: [Sampler; 2] = [
            (&|x, z| clamped.corners(x, z).into(), Clamped::RIM, h),
            (&|x, z| wrapped.corners(x, z).into(), Wrapped::RIM, h - 1),
        ];
        for (corners, rim, rows) in fields {
            let (mut near, mut far, mut offsets) = (0, 0, [false; 4]);
            // The faces the row loop samples: rows `1 + rim ..= rows − 2`, faces
            // `1 + rim ..= w − 2 − rim`.
            for j in 1 + rim..rows - 1 {
                for k in 1 + rim..w - 1 - rim {
                    for &x in &ts {
                        for &z in &ts {
                            let sp = Spread::of(x, z, (k - 1) as f32, (j - 1) as f32);
                            if !Spread::near(sp.s) {
                                far += 1;
                                continue;
                            }
                            near += 1;
                            let (dx, dz) = (sp.dx.to_bits(), sp.dz.to_bits());
                            assert!(dx == 0 || dx == ONE, "dx {} at {x}, {z}", sp.dx);
                            assert!(dz == 0 || dz == ONE, "dz {} at {x}, {z}", sp.dz);
                            let (i0, j0) =
                                (k - 1 + (dx == ONE) as usize, j - 1 + (dz == ONE) as usize);
                            offsets[(dx == ONE) as usize * 2 + (dz == ONE) as usize] = true;
                            let want = [
                                src[j0 * w + i0],
                                src[j0 * w + i0 + 1],
                                src[(j0 + 1) * w + i0],
                                src[(j0 + 1) * w + i0 + 1],
                                sp.fx,
                                sp.fz,
                            ];
                            let got = corners(x, z);
                            assert_eq!(
                                got.map(f32::to_bits),
                                want.map(f32::to_bits),
                                "face ({k}, {j}), point ({x}, {z}), rim {rim}"
                            );
                        }
                    }
                }
            }
            assert!(
                near > 1000 && far > 1000,
                "rim {rim}: {near} near, {far} far"
            );
            assert_eq!(offsets, [true; 4], "rim {rim}: every near offset seen");
        }
    }
}
