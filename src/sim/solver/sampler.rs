//! The clamped bilinear sampler of the advection passes on non-periodic grids, in vectorised
//! row loops. Its four loads are unchecked so the loops compile into gathers: the one
//! `unsafe` block of the solver, kept here beside the checks that make it sound.

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
pub(super) fn sample_clamped(
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
pub(super) fn correct_clamped(
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
