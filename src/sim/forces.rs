//! The force model: a function of (layout, time) giving the AGC arrow splats and the ambient
//! target wind. Shared by the CPU solver and (later) the GPU path, which uploads the splats.

use crate::doc::{self, AmbientKind, Emission, Layout, TimeWindow, Tree};
use bytemuck::Zeroable;
use rustfft::{FftPlanner, num_complex::Complex32};

mod row;
pub use row::{FftTables, RowScratch};

/// One active arrow at one instant: a capsule from `a` to `b` (world metres) that drives the
/// wind along `dir` (unit) toward `strength` m/s, with Gaussian weight `g = exp(-d² / radius²)`,
/// `d` the distance to the segment. The force is always along the arrow and fades as the wind
/// along it reaches `strength`: per step, `Δvel = (1 − e^(−k·g·dt)) · max(0, strength − vel·dir) · dir`
/// with `k` the layout's `arrow_response`; overlapping arrows' pushes are [`combine`]d. The
/// GPU forces pass uploads these: mirrored by
/// `struct Splat` in `shaders/forces.wgsl`.
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct ArrowSplat {
    pub a: [f32; 2],
    pub b: [f32; 2],
    pub dir: [f32; 2],
    pub strength: f32,
    pub radius: f32,
}

/// Where arrows overlap, their pushes on a face combined: the sum of each arrow's push
/// `gainᵢ·deficitᵢ·dirᵢ` (`pushes`) scaled by `min(1, 4 / n)` ([`OVERLAP_ARROWS`]), where
/// `n = (Σ gainᵢ)² / Σ gainᵢ²` (`gains`, `squares`) is how many arrows effectively overlap
/// there (`k` for `k` equal gains, about 1 where one arrow dominates). So:
/// - up to four arrows (a chain's joint, two winds meeting, a root with three branches)
///   push as they always did: the scale is 1 (to the last bit's rounding where `n` is
///   nearly 4);
/// - a crowd of them (copies, a fan) pushes at four arrows' rate toward the gain-weighted
///   mean of their pushes: 256 copies of an arrow push as four;
/// - each arrow's deficit stops at its own strength, so the wind approaches the strongest
///   of them, never their sum.
///
/// Two rules came before. Each push added in full: 256 overlapping 5 m/s arrows reached
/// 490 m/s. Then the pushes divided by `Σ gainᵢ` where that passed 1: the targets were
/// averaged, but a crowd's rate still summed, up to the whole deficit in one step (fifteen
/// arrows' rate at the defaults), and the projection squeezed its through-flow into what
/// it did not cover: 256 copies of a 5 m/s arrow drove 42 m/s along the walls of a closed
/// map, and a fan of 256 round one root 9.4 m/s along open edges.
///
/// Branch-free, so a row of faces vectorises: where no arrow reaches (`gains` 0, and so
/// `pushes` 0) the ratio is `0 / 0`, NaN, and `f32::min` returns its other argument, 1.
#[inline(always)]
pub fn combine(pushes: f32, gains: f32, squares: f32) -> f32 {
    pushes * (OVERLAP_ARROWS * squares / (gains * gains)).min(1.0)
}

/// How many arrows' rates overlapping arrows push at, at most ([`combine`]): four, so that
/// chains' joints, winds meeting and a branch point of three push as they always did. Fewer
/// weakens the forcing where arrows meet, and that forcing also damps the eddies there: at
/// two, branching's branch point let confinement raise its field's grid-scale part to 2.4×
/// the unconfined field's, from 1.6× (docs/SOLVER.md, step 1).
pub const OVERLAP_ARROWS: f32 = 4.0;

/// An arrow's gain `1 − e^(−k·g·dt)` where its Gaussian weight is `g` (response `k`, step
/// `dt`): the share of its deficit it makes up in a step.
#[inline(always)]
pub fn gain_of_weight(g: f32, k: f32, dt: f32) -> f32 {
    1.0 - exp_neg(-k * g * dt)
}

/// Beyond this many radii a splat's Gaussian (< e⁻⁹ ≈ 1.2e-4) is dropped.
pub const SPLAT_CUTOFF_RADII: f32 = 3.0;

impl ArrowSplat {
    /// Gaussian weight of the arrow at world point `p` (0 beyond the cutoff).
    #[inline(always)]
    pub fn weight(&self, p: [f32; 2]) -> f32 {
        let d2 = segment_dist2(p, self.a, self.b);
        let r2 = self.radius * self.radius;
        // Reciprocals of per-splat constants: hoisted out of loops over faces, where a
        // division per face would dominate.
        let inv_r2 = 1.0 / r2;
        if d2 > r2 * SPLAT_CUTOFF_RADII * SPLAT_CUTOFF_RADII {
            0.0
        } else {
            exp_neg(-d2 * inv_r2)
        }
    }

    /// Velocity change (m/s) over `dt` at world point `p` where the wind is `vel`, with
    /// response rate `k` (1/s).
    #[inline]
    pub fn impulse(&self, p: [f32; 2], vel: [f32; 2], k: f32, dt: f32) -> [f32; 2] {
        self.impulse_weighted(self.weight(p), vel, k, dt)
    }

    /// [`Self::impulse`] for a point whose weight `g` is already known.
    #[inline(always)]
    pub fn impulse_weighted(&self, g: f32, vel: [f32; 2], k: f32, dt: f32) -> [f32; 2] {
        if g == 0.0 {
            return [0.0, 0.0];
        }
        let deficit = (self.strength - (vel[0] * self.dir[0] + vel[1] * self.dir[1])).max(0.0);
        let m = gain_of_weight(g, k, dt) * deficit;
        [self.dir[0] * m, self.dir[1] * m]
    }

    /// The magnitude `m` of [`Self::impulse`] (the impulse is `dir · m`) without branches or
    /// arrays indexed at run time, for loops over faces that must vectorise on every SIMD
    /// level: the same numbers (a point beyond the cutoff gets `m = 0`, which adds nothing).
    #[inline(always)]
    pub fn impulse_magnitude(&self, p: [f32; 2], vx: f32, vz: f32, k: f32, dt: f32) -> f32 {
        self.gain(p, k, dt) * self.deficit(vx, vz)
    }

    /// The part of [`Self::impulse_magnitude`] that depends only on where `p` is (and on `k`
    /// and `dt`): `1 − e^(−k·g·dt)`, 0 beyond the cutoff. Branch-free, so loops over faces
    /// vectorise; the CPU solver keeps it per face while a splat stays the same.
    #[inline(always)]
    pub fn gain(&self, p: [f32; 2], k: f32, dt: f32) -> f32 {
        let d2 = segment_dist2(p, self.a, self.b);
        let r2 = self.radius * self.radius;
        let inv_r2 = 1.0 / r2;
        let beyond = d2 > r2 * SPLAT_CUTOFF_RADII * SPLAT_CUTOFF_RADII;
        let g = exp_neg(-d2 * inv_r2);
        let g = if beyond { 0.0 } else { g };
        // g = 0 gives 1 − e⁰ = 0 exactly: the zero impulse `impulse_weighted` returns early.
        gain_of_weight(g, k, dt)
    }

    /// How far the wind `(vx, vz)` falls short of `strength` along the arrow (0 when it is
    /// at or past it): the other factor of [`Self::impulse_magnitude`].
    #[inline(always)]
    pub fn deficit(&self, vx: f32, vz: f32) -> f32 {
        (self.strength - (vx * self.dir[0] + vz * self.dir[1])).max(0.0)
    }

    /// The world x-interval `(min, max)` where the line at world `z` crosses the region the
    /// splat touches (the capsule of points within the cutoff of its segment: the strip
    /// beside the segment and the discs at its ends); `None` when it misses the line. Exact
    /// up to rounding: callers widen it before choosing faces. For a slanted or short arrow
    /// it is much narrower than its bounding box's rows near the ends.
    pub fn x_extent_at(&self, z: f32) -> Option<(f32, f32)> {
        let r = self.radius * SPLAT_CUTOFF_RADII;
        let mut lo = f32::INFINITY;
        let mut hi = f32::NEG_INFINITY;
        // The discs at the ends.
        for c in [self.a, self.b] {
            let dz = z - c[1];
            let h2 = r * r - dz * dz;
            if h2 >= 0.0 {
                let h = h2.sqrt();
                lo = lo.min(c[0] - h);
                hi = hi.max(c[0] + h);
            }
        }
        // The strip: |cross(ab, p − a)| ≤ r·|ab| and 0 ≤ dot(ab, p − a) ≤ |ab|², each a
        // linear condition on x along the line.
        let ab = [self.b[0] - self.a[0], self.b[1] - self.a[1]];
        let len2 = ab[0] * ab[0] + ab[1] * ab[1];
        if len2 > 0.0 {
            let dz = z - self.a[1];
            let mut range = (f32::NEG_INFINITY, f32::INFINITY);
            // lower ≤ k·(x − a.x) + m ≤ upper
            let mut clip = |k: f32, m: f32, lower: f32, upper: f32| {
                if k == 0.0 {
                    if m < lower || m > upper {
                        range = (f32::INFINITY, f32::NEG_INFINITY);
                    }
                } else {
                    let (p, q) = ((lower - m) / k, (upper - m) / k);
                    range.0 = range.0.max(p.min(q) + self.a[0]);
                    range.1 = range.1.min(p.max(q) + self.a[0]);
                }
            };
            let rl = r * len2.sqrt();
            clip(-ab[1], ab[0] * dz, -rl, rl);
            clip(ab[0], ab[1] * dz, 0.0, len2);
            if range.0 <= range.1 {
                lo = lo.min(range.0);
                hi = hi.max(range.1);
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// World-space bounding box `(min, max)` of the region the splat touches.
    pub fn bounds(&self) -> ([f32; 2], [f32; 2]) {
        let r = self.radius * SPLAT_CUTOFF_RADII;
        (
            [self.a[0].min(self.b[0]) - r, self.a[1].min(self.b[1]) - r],
            [self.a[0].max(self.b[0]) + r, self.a[1].max(self.b[1]) + r],
        )
    }
}

/// `e^x` for `x ≤ 0`, within 2 ulp of the true value (0.65 ulp measured, tested), with `x`
/// clamped to `[−87, 0]` (so never 0, never above 1). Plain arithmetic with no library call,
/// so loops over faces that evaluate it vectorise: the forces pass takes two per face and
/// arrow. Cody–Waite range reduction `x = n ln 2 + g` with `|g| ≤ ½ ln 2`, a polynomial for
/// `e^g`, and `2ⁿ` built in the exponent bits.
#[inline(always)]
pub fn exp_neg(x: f32) -> f32 {
    const LOG2_E: f32 = std::f32::consts::LOG2_E;
    // ln 2 split so that `n · LN2_HI` is exact for the n that occur.
    const LN2_HI: f32 = 0.693_359_4;
    const LN2_LO: f32 = -2.121_944_4e-4;
    // Adding and subtracting 1.5 · 2²³ rounds to the nearest integer (no SSE4.1 needed).
    const ROUND: f32 = 12_582_912.0;
    let x = x.clamp(-87.0, 0.0);
    let t = x * LOG2_E + ROUND;
    let n = t - ROUND;
    let g = (x - n * LN2_HI) - n * LN2_LO;
    let p = 1.987_569_1e-4_f32;
    let p = p * g + 1.398_199_9e-3;
    let p = p * g + 8.333_452e-3;
    let p = p * g + 4.166_579_6e-2;
    let p = p * g + 1.666_666_5e-1;
    let p = p * g + 0.5;
    let e = p * g * g + g + 1.0;
    // n ∈ [−126, 0], so 2ⁿ is a normal number, and t = 1.5 · 2²³ + n holds n in its low
    // mantissa bits: t's bits are 0x4B40_0000 + n. Integer arithmetic on them gives 2ⁿ's
    // exponent field without a float-to-int conversion (which would not vectorise).
    let scale = f32::from_bits(t.to_bits().wrapping_sub(0x4B40_0000 - 127) << 23);
    e * scale
}

#[inline(always)]
fn segment_dist2(p: [f32; 2], a: [f32; 2], b: [f32; 2]) -> f32 {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let ap = [p[0] - a[0], p[1] - a[1]];
    let len2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = if len2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1]) * (1.0 / len2)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let d = [ap[0] - ab[0] * t, ap[1] - ab[1] * t];
    d[0] * d[0] + d[1] * d[1]
}

/// Whether a tree blows at time `t` (window only; pulses are per arrow).
fn in_window(tree: &Tree, t: f32) -> Option<f32> {
    if !tree.enabled {
        return None;
    }
    match tree.window {
        TimeWindow::Always => Some(0.0),
        TimeWindow::Between { start, end } => (t >= start && t < end).then_some(start),
    }
}

/// Whether an arrow whose pulse arrives `delay` seconds after the tree starts is on at `t`.
///
/// The wind front leaves the root when the tree's window opens and travels along the arrows
/// at the tree's propagation speed, so an arrow deeper in the tree switches on later. With
/// pulsed emission every pulse travels the same way: an arrow is on while the pulse that left
/// the root `delay` seconds ago was on.
fn arrow_active(emission: Emission, since_start: f32, delay: f32) -> bool {
    let local = since_start - delay;
    if local < 0.0 {
        return false;
    }
    match emission {
        Emission::Continuous => true,
        Emission::Pulsed { period, duty } => (local % period) < duty * period,
    }
}

/// The arrows of all trees that push at time `t`, each tree as its keyframes have it then:
/// its arrows' strengths scaled and turned about its root by the tree's keys, and a keyed
/// branch's arrows scaled and turned about the branch's start within that
/// ([`doc::Tree::keyed_arrows`]).
pub fn agc_splats(layout: &Layout, t: f32) -> Vec<ArrowSplat> {
    let mut out = Vec::new();
    for tree in &layout.trees {
        let Some(start) = in_window(tree, t) else {
            continue;
        };
        for arrow in tree.keyed_arrows(t) {
            let delay = arrow.path_len / tree.propagation_speed;
            if !arrow_active(tree.emission, t - start, delay) {
                continue;
            }
            let (a, b) = (arrow.a, arrow.b);
            let d = [b[0] - a[0], b[1] - a[1]];
            let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
            let strength = arrow.child.strength * arrow.factor;
            if len <= 0.0 || strength <= 0.0 {
                continue;
            }
            out.push(ArrowSplat {
                a,
                b,
                dir: [d[0] / len, d[1] / len],
                strength,
                radius: arrow.child.radius,
            });
        }
    }
    out
}

/// Integer hash (a PCG-style permutation), so the noise is the same on every platform and can
/// be reproduced bit for bit in WGSL.
#[inline]
fn hash(x: i32, y: i32, seed: u32) -> u32 {
    let mut h = (x as u32).wrapping_mul(0x8da6_b343)
        ^ (y as u32).wrapping_mul(0xd816_3841)
        ^ seed.wrapping_mul(0xcb1a_b31f);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^ (h >> 16)
}

/// 2D gradient noise in about [-1, 1], smooth (quintic fade), period-free.
pub fn gradient_noise(x: f32, y: f32, seed: u32) -> f32 {
    let xi = x.floor();
    let yi = y.floor();
    let fx = x - xi;
    let fy = y - yi;
    let (xi, yi) = (xi as i32, yi as i32);
    let n00 = gradient(hash_angle(xi, yi, seed), fx, fy);
    let n10 = gradient(hash_angle(xi + 1, yi, seed), fx - 1.0, fy);
    let n01 = gradient(hash_angle(xi, yi + 1, seed), fx, fy - 1.0);
    let n11 = gradient(hash_angle(xi + 1, yi + 1, seed), fx - 1.0, fy - 1.0);
    let u = fade(fx);
    let v = fade(fy);
    let nx0 = n00 + (n10 - n00) * u;
    let nx1 = n01 + (n11 - n01) * u;
    (nx0 + (nx1 - nx0) * v) * std::f32::consts::SQRT_2
}

/// The unit gradient `(cos a, sin a)` of lattice point `(ix, iy)`, its angle from the hash.
#[inline]
fn hash_angle(ix: i32, iy: i32, seed: u32) -> [f32; 2] {
    let a = (hash(ix, iy, seed) >> 8) as f32 * (std::f32::consts::TAU / 16_777_216.0);
    [crate::num::cos(a), crate::num::sin(a)]
}

/// A lattice gradient's ramp at offset `(dx, dy)` from its point.
#[inline(always)]
fn gradient(g: [f32; 2], dx: f32, dy: f32) -> f32 {
    g[0] * dx + g[1] * dy
}

/// The quintic fade `6t⁵ − 15t⁴ + 10t³`.
#[inline(always)]
fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// `t` wrapped into `[0, 1]`: `t − ⌊t⌋`, the same value as `t.rem_euclid(1.0)` (both are
/// exact for `t ≥ 0`, and round `1 + frac` the same way below 0) without its library call,
/// which kept loops over faces scalar.
#[inline(always)]
fn unit_wrap(t: f32) -> f32 {
    t - t.floor()
}

/// `t` clamped to `[0, m]` (`m ≥ 0`), NaN and −0 giving +0: two compares and selects that
/// are one `max` and one `min` instruction each, the bound as the `min`'s memory operand
/// (`f32::max`/`min` made the compiler load the bound into a register first, in loops short
/// of AVX2's sixteen).
#[inline(always)]
pub(crate) fn clamp_to(t: f32, m: f32) -> f32 {
    let t = if t > 0.0 { t } else { 0.0 };
    if t < m { t } else { m }
}

/// `t` clamped to `[0, m]` (`0 ≤ m < 2³¹`; NaN gives 0) and truncated to an i32: what
/// `t as i32` and a clamp give, in vector instructions. Rust's saturating `as` compiles to a
/// scalar compare and select per lane on AVX2, and those took half the sampler's time.
#[inline(always)]
pub(crate) fn index(t: f32, m: f32) -> i32 {
    let t = clamp_to(t, m);
    // SAFETY: `t` is finite and in [0, 2³¹), so its truncation fits an i32.
    unsafe { t.to_int_unchecked::<i32>() }
}

/// An FFT gust field (Tessendorf/Phillips spectrum), tiling with period `tile` metres.
pub struct FftGusts {
    n: usize,
    tile: f32,
    h0: Vec<Complex32>,
    omega: Vec<f32>,
    norm: f32,
    field: Vec<f32>,
    field_time: f32,
}

const GRAVITY: f32 = 9.81;

impl FftGusts {
    pub fn new(n: usize, tile: f32, wind_speed: f32, dir: [f32; 2], seed: u64) -> Self {
        let l = wind_speed * wind_speed / GRAVITY;
        let mut rng = SplitMix(seed);
        let mut h0 = vec![Complex32::new(0.0, 0.0); n * n];
        let mut omega = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n {
                let kx = wave_number(i, n, tile);
                let kz = wave_number(j, n, tile);
                let k = (kx * kx + kz * kz).sqrt();
                if k < 1e-6 {
                    continue;
                }
                let kl = k * l.max(1e-3);
                let align = (kx * dir[0] + kz * dir[1]) / k;
                // P(k) ∝ exp(-1/(kL)²)/k⁴ · |k̂·ŵ|², damping waves far below the tile size.
                let small = tile / n as f32 * 0.5;
                let p = crate::num::exp(-1.0 / (kl * kl)) / k.powi(4)
                    * align
                    * align
                    * crate::num::exp(-(k * small).powi(2));
                let (g1, g2) = rng.gaussian_pair();
                let s = (p * 0.5).sqrt();
                h0[j * n + i] = Complex32::new(g1 * s, g2 * s);
                omega[j * n + i] = (GRAVITY * k).sqrt();
            }
        }
        let mut f = Self {
            n,
            tile,
            h0,
            omega,
            norm: 1.0,
            field: vec![0.0; n * n],
            field_time: f32::NAN,
        };
        f.evaluate(0.0);
        let rms = (f.field.iter().map(|v| v * v).sum::<f32>() / (n * n) as f32).sqrt();
        f.norm = if rms > 0.0 { 1.0 / rms } else { 0.0 };
        f.field.iter_mut().for_each(|v| *v *= f.norm);
        f
    }

    /// Recomputes the field at time `t` (cached: a second call at the same `t` is free).
    pub fn evaluate(&mut self, t: f32) {
        if self.field_time == t {
            return;
        }
        let n = self.n;
        let mut h = vec![Complex32::new(0.0, 0.0); n * n];
        for j in 0..n {
            for i in 0..n {
                let m = ((n - j) % n) * n + (n - i) % n;
                let w = self.omega[j * n + i] * t;
                let e = Complex32::new(crate::num::cos(w), crate::num::sin(w));
                h[j * n + i] = self.h0[j * n + i] * e + self.h0[m].conj() * e.conj();
            }
        }
        let fft = FftPlanner::new().plan_fft_inverse(n);
        for row in h.chunks_exact_mut(n) {
            fft.process(row);
        }
        let mut col = vec![Complex32::new(0.0, 0.0); n];
        for i in 0..n {
            for j in 0..n {
                col[j] = h[j * n + i];
            }
            fft.process(&mut col);
            for j in 0..n {
                h[j * n + i] = col[j];
            }
        }
        for (f, c) in self.field.iter_mut().zip(&h) {
            *f = c.re * self.norm;
        }
        self.field_time = t;
    }

    /// The (unit-rms) gust value at world point `p`, bilinear, wrapping every `tile` metres.
    pub fn sample(&self, p: [f32; 2]) -> f32 {
        let n = self.n as f32;
        let x = unit_wrap(p[0] / self.tile) * n;
        let z = unit_wrap(p[1] / self.tile) * n;
        let (i0, j0) = (x.floor() as usize % self.n, z.floor() as usize % self.n);
        let (i1, j1) = ((i0 + 1) % self.n, (j0 + 1) % self.n);
        let (fx, fz) = (x - x.floor(), z - z.floor());
        let at = |i: usize, j: usize| self.field[j * self.n + i];
        let a = row::lerp(at(i0, j0), at(i1, j0), fx);
        let b = row::lerp(at(i0, j1), at(i1, j1), fx);
        row::lerp(a, b, fz)
    }

    pub fn field(&self) -> &[f32] {
        &self.field
    }
}

fn wave_number(i: usize, n: usize, tile: f32) -> f32 {
    let m = if i <= n / 2 {
        i as f32
    } else {
        i as f32 - n as f32
    };
    std::f32::consts::TAU * m / tile
}

/// A tiny deterministic generator for the FFT spectrum's random phases.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn unit(&mut self) -> f32 {
        ((self.next() >> 40) as f32 + 0.5) / 16_777_216.0
    }

    fn gaussian_pair(&mut self) -> (f32, f32) {
        let r = (-2.0 * crate::num::ln(self.unit())).sqrt();
        let a = std::f32::consts::TAU * self.unit();
        (r * crate::num::cos(a), r * crate::num::sin(a))
    }
}

/// One ambient layer at one instant, as the GPU forces pass reads it: everything that depends
/// only on time is computed here, with the CPU's own arithmetic, so the shader evaluates
/// exactly [`Ambient::wind`]'s per-point part. Mirrored by `struct Layer` in
/// `shaders/forces.wgsl`.
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct LayerParams {
    /// 0 directional, 1 noise, 2 FFT gusts, 3 sine.
    pub kind: u32,
    /// FFT: where its field starts in the uploaded gust fields, and its size per axis.
    pub fft_offset: u32,
    pub fft_n: u32,
    pub _pad: u32,
    /// The layer's unit direction.
    pub dir: [f32; 2],
    /// How far the pattern has scrolled: `dir · speed · t` (directional: the mean wind; noise:
    /// its speed; FFT: its wind speed).
    pub shift: [f32; 2],
    /// Directional: turbulence, speed (`main × pulse`). Noise: scale, strength. FFT: wind
    /// speed, amplitude, tile. Sine: amplitude, wavelength, `frequency × t`.
    pub a: f32,
    pub b: f32,
    pub c: f32,
    pub _pad2: f32,
}

/// [`LayerParams::kind`] of each ambient layer type.
pub const LAYER_DIRECTIONAL: u32 = 0;
pub const LAYER_NOISE: u32 = 1;
pub const LAYER_FFT: u32 = 2;
pub const LAYER_SINE: u32 = 3;

/// Ambient layers prepared for one instant: evaluates the target wind at any point.
pub struct Ambient {
    layers: Vec<(AmbientKind, Option<FftGusts>)>,
    /// Each layer's keyframes (strength factor, turn of its direction).
    keys: Vec<Vec<doc::Key>>,
    /// Each layer's time-dependent values at the current time ([`Self::set_time`]): what
    /// [`Self::wind`] evaluates per point, and what the GPU forces pass is given.
    params: Vec<LayerParams>,
}

impl Ambient {
    /// Prepares the enabled layers of `layout` (FFT spectra are built here, once).
    pub fn new(layout: &Layout) -> Self {
        let keys = (layout.ambient.iter())
            .filter(|a| a.enabled)
            .map(|a| a.keys.clone())
            .collect();
        let layers = layout
            .ambient
            .iter()
            .filter(|a| a.enabled)
            .map(|a| {
                let fft = match &a.kind {
                    AmbientKind::Fft {
                        direction_deg,
                        wind_speed,
                        resolution,
                        tile_size,
                        seed,
                        ..
                    } => Some(FftGusts::new(
                        *resolution as usize,
                        *tile_size,
                        *wind_speed,
                        doc::direction(*direction_deg),
                        *seed,
                    )),
                    _ => None,
                };
                (a.kind.clone(), fft)
            })
            .collect();
        let mut ambient = Self {
            layers,
            keys,
            params: Vec::new(),
        };
        ambient.set_time(0.0);
        ambient
    }

    pub fn is_empty(&self) -> bool {
        self.layers.is_empty()
    }

    /// Moves the layers to time `t`: evaluates the FFT fields and each layer's pulse, scroll
    /// offset and phase, once for every point.
    pub fn set_time(&mut self, t: f32) {
        for (_, fft) in &mut self.layers {
            if let Some(f) = fft {
                f.evaluate(t);
            }
        }
        let mut offset = 0u32;
        self.params = (self.layers.iter().zip(&self.keys))
            .map(|((kind, fft), keys)| {
                let blank = LayerParams::zeroed();
                // Keyframes: a factor on the layer's speeds, a turn of the way it blows (its
                // frozen pattern still scrolls the authored way, so a turn does not sweep it).
                let (f, turn) = doc::key_values(keys, t);
                let turned = |d: [f32; 2]| -> [f32; 2] {
                    let (s, c) = crate::num::sin_cos(turn);
                    [c * d[0] - s * d[1], s * d[0] + c * d[1]]
                };
                match kind {
                    AmbientKind::Directional {
                        direction_deg,
                        main,
                        turbulence,
                        pulse_magnitude,
                        pulse_frequency,
                    } => {
                        let d = doc::direction(*direction_deg);
                        let pulse = 1.0
                            + pulse_magnitude
                                * (0.5
                                    + 0.5
                                        * crate::num::sin(
                                            std::f32::consts::TAU * pulse_frequency * t,
                                        ));
                        // Frozen turbulence scrolled with the mean wind (Taylor's hypothesis).
                        LayerParams {
                            kind: LAYER_DIRECTIONAL,
                            dir: turned(d),
                            shift: [d[0] * main * t, d[1] * main * t],
                            a: turbulence * f,
                            b: main * pulse * f,
                            ..blank
                        }
                    }
                    AmbientKind::Noise {
                        direction_deg,
                        scale,
                        speed,
                        strength,
                    } => {
                        let d = doc::direction(*direction_deg);
                        LayerParams {
                            kind: LAYER_NOISE,
                            dir: turned(d),
                            shift: [d[0] * speed * t, d[1] * speed * t],
                            a: *scale,
                            b: strength * f,
                            ..blank
                        }
                    }
                    AmbientKind::Fft {
                        direction_deg,
                        wind_speed,
                        amplitude,
                        ..
                    } => {
                        let d = doc::direction(*direction_deg);
                        let (fft_offset, fft_n, tile) = match fft {
                            Some(f) => {
                                let at = offset;
                                offset += (f.n * f.n) as u32;
                                (at, f.n as u32, f.tile)
                            }
                            None => (0, 0, 1.0),
                        };
                        LayerParams {
                            kind: LAYER_FFT,
                            fft_offset,
                            fft_n,
                            dir: turned(d),
                            shift: [d[0] * wind_speed * t, d[1] * wind_speed * t],
                            a: wind_speed * f,
                            b: amplitude * f,
                            c: tile,
                            ..blank
                        }
                    }
                    AmbientKind::Sine {
                        direction_deg,
                        amplitude,
                        wavelength,
                        frequency,
                    } => LayerParams {
                        kind: LAYER_SINE,
                        dir: turned(doc::direction(*direction_deg)),
                        a: amplitude * f,
                        b: *wavelength,
                        c: frequency * t,
                        ..blank
                    },
                }
            })
            .collect();
    }

    /// The layers at the current time for the GPU, and their FFT gust fields one after the
    /// other (what [`LayerParams::fft_offset`] indexes).
    pub fn layer_params(&self) -> (Vec<LayerParams>, Vec<f32>) {
        let gusts = self
            .layers
            .iter()
            .filter_map(|(_, fft)| fft.as_ref())
            .flat_map(|f| f.field().iter().copied())
            .collect();
        (self.params.clone(), gusts)
    }

    /// Target ambient wind (m/s) at world point `p`: each layer's per-point part, from the
    /// values [`Self::set_time`] prepared (the GPU evaluates the same in `shaders/forces.wgsl`).
    pub fn wind(&self, p: [f32; 2]) -> [f32; 2] {
        let mut w = [0.0f32, 0.0];
        for (l, (_, fft)) in self.params.iter().zip(&self.layers) {
            let q = [p[0] - l.shift[0], p[1] - l.shift[1]];
            let speed = match l.kind {
                LAYER_DIRECTIONAL => {
                    let s = 1.0 / 8.0;
                    w[0] += l.a * gradient_noise(q[0] * s, q[1] * s, 11);
                    w[1] += l.a * gradient_noise(q[0] * s, q[1] * s, 23);
                    l.b
                }
                LAYER_NOISE => {
                    let n = gradient_noise(q[0] / l.a, q[1] / l.a, 5);
                    l.b * (0.5 + 0.5 * n).clamp(0.0, 1.0)
                }
                LAYER_FFT => l.a + l.b * fft.as_ref().map_or(0.0, |f| f.sample(q)),
                _ => {
                    let x = p[0] * l.dir[0] + p[1] * l.dir[1];
                    l.a * crate::num::sin(std::f32::consts::TAU * (x / l.b - l.c))
                }
            };
            w[0] += l.dir[0] * speed;
            w[1] += l.dir[1] * speed;
        }
        w
    }
}

/// The wind the designer set, in m/s: the fastest of the layout's enabled arrows (their
/// strongest node times the tree's largest key factor) and ambient layers (their mean speed,
/// pulses and turbulence included, an FFT layer's gusts at three times their amplitude,
/// times their largest key factor). What vorticity confinement may spin the wind up to
/// (docs/SOLVER.md, step 3), what a bake's notes compare its peak with
/// (`bake::field_notes`), and what the stability tests bound the field by.
pub fn reference_speed(layout: &Layout) -> f32 {
    fn factor(keys: &[doc::Key]) -> f32 {
        keys.iter().map(|k| k.strength).fold(1.0f32, f32::max)
    }
    // Each arrow drives at its end node's strength (every node but the root), times the
    // largest factor of its branch's keys and of the branches it grows from.
    fn strongest(n: &doc::Node, above: f32, factor: &dyn Fn(&[doc::Key]) -> f32) -> f32 {
        n.children
            .iter()
            .map(|c| {
                let f = above * factor(&c.keys);
                (c.strength * f).max(strongest(c, f, factor))
            })
            .fold(0.0f32, f32::max)
    }
    let arrows = (layout.trees.iter())
        .filter(|t| t.enabled)
        .map(|t| strongest(&t.root, factor(&t.keys), &factor));
    let ambient = (layout.ambient.iter()).filter(|a| a.enabled).map(|a| {
        let speed = match &a.kind {
            AmbientKind::Directional {
                main,
                turbulence,
                pulse_magnitude,
                ..
            } => main * (1.0 + pulse_magnitude) + turbulence,
            AmbientKind::Noise { strength, .. } => *strength,
            AmbientKind::Fft {
                wind_speed,
                amplitude,
                ..
            } => wind_speed + 3.0 * amplitude,
            AmbientKind::Sine { amplitude, .. } => *amplitude,
        };
        speed * factor(&a.keys)
    });
    arrows.chain(ambient).fold(0.0, f32::max)
}
