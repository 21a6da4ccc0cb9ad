//! The bilinear samplers of the advection passes, clamped (open and closed grids) or wrapped
//! (periodic grids), in vectorised row loops. Their four loads are unchecked so the loops
//! compile into gathers: the solver's only `unsafe` blocks, kept here beside the checks that
//! make them sound.

use super::*;

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

    /// `(a, b, c, d, fx, fz)`: the samples at `(i0, j0)`, `(i0+1, j0)`, `(i0, j0+1)`,
    /// `(i0+1, j0+1)` and the fractions.
    #[inline(always)]
    pub(super) fn corners(&self, x: f32, z: f32) -> (f32, f32, f32, f32, f32, f32) {
        let x = x.clamp(0.0, self.xmax);
        let z = z.clamp(0.0, self.zmax);
        let i0 = index(x, self.xmax).min(self.imax);
        let j0 = index(z, self.zmax).min(self.jmax);
        let (fx, fz) = (x - i0 as f32, z - j0 as f32);
        let (k, w) = ((j0 * self.w as i32 + i0) as usize, self.w);
        // SAFETY: 0 ≤ i0 ≤ w − 2 and 0 ≤ j0 ≤ h − 2 (the clamps above; NaN gives 0), so
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

/// `t` clamped to `[0, m]` (`0 ≤ m < 2³¹`; NaN gives 0) and truncated to an i32: what
/// `t as i32` and a clamp give, in vector instructions. Rust's saturating `as` compiles to a
/// scalar compare and select per lane on AVX2, and those took half the sampler's time.
#[inline(always)]
fn index(t: f32, m: f32) -> i32 {
    // `max` turns NaN into 0.
    let t = t.max(0.0).min(m);
    // SAFETY: `t` is finite and in [0, 2³¹), so its truncation fits an i32.
    unsafe { t.to_int_unchecked::<i32>() }
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
    let i1 = if i0 + 1 == n { 0 } else { i0 + 1 };
    (i0, i1, t - i0 as f32)
}

impl Wrapped<'_> {
    /// As [`Clamped::corners`], the indices wrapped: `(i1, j1)` is `(i0 + 1, j0 + 1)` modulo
    /// the period.
    #[inline(always)]
    pub(super) fn corners(&self, x: f32, z: f32) -> (f32, f32, f32, f32, f32, f32) {
        let (i0, i1, fx) = wrap(x, self.px, self.ix);
        let (j0, j1, fz) = wrap(z, self.pz, self.iz);
        let (r0, r1) = (j0 as usize * self.w, j1 as usize * self.w);
        let (i0, i1) = (i0 as usize, i1 as usize);
        // SAFETY: 0 ≤ i0, i1 < px ≤ w and 0 ≤ j0, j1 < pz ≤ h (the clamps and selects in
        // `wrap`), so every index is below w·h ≤ src.len(), as `new` asserts.
        let (a, b, c, d) = unsafe {
            let s = self.src;
            (
                *s.get_unchecked(r0 + i0),
                *s.get_unchecked(r0 + i1),
                *s.get_unchecked(r1 + i0),
                *s.get_unchecked(r1 + i1),
            )
        };
        (a, b, c, d, fx, fz)
    }
}

/// The row loops of one sampler type `$ty`: `$sample` (semi-Lagrangian: the bilinear sample
/// at each departure point, offset by `-o` into sample coordinates, times `keep`; 0 on faces
/// that are not free) and `$correct` (MacCormack: `back` holds φ̌ on entry and
/// `(φ̂ + (φ − φ̌)/2)` clamped to the range of the four samples of φ around the departure
/// point, times `keep`, on exit). Compiled for several SIMD levels, picked at run time; the
/// same bits as the reference's sampler. A macro rather than a generic so each loop is
/// written once and still compiles as plainly as a hand-written one.
macro_rules! row_samplers {
    ($ty:ident, $sample:ident, $correct:ident) => {
        #[allow(clippy::too_many_arguments)]
        #[cfg_attr(not(windloom_static_simd), multiversion(targets = "simd"))]
        #[cfg_attr(
            windloom_static_simd,
            multiversion(targets = "simd", dispatcher = "static")
        )]
        pub(super) fn $sample(
            f: &$ty,
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

        #[allow(clippy::too_many_arguments)]
        #[cfg_attr(not(windloom_static_simd), multiversion(targets = "simd"))]
        #[cfg_attr(
            windloom_static_simd,
            multiversion(targets = "simd", dispatcher = "static")
        )]
        pub(super) fn $correct(
            f: &$ty,
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
                // `x.clamp(lo, hi)` without its `lo ≤ hi` assertion, which would keep the
                // loop scalar (lo ≤ hi always holds here).
                let x = if x < lo { lo } else { x };
                let x = if x > hi { hi } else { x };
                back[i] = if free[i] != 0 { x * keep } else { 0.0 };
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
}
