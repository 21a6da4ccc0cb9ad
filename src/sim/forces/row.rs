//! The ambient target wind along a whole row of faces at once: the same numbers as
//! [`Ambient::wind`] point by point, bit for bit, for one component only, with everything that
//! is constant along the row (the noise lattice row, its fade, the FFT row) worked out once
//! and the per-face arithmetic in loops that vectorise.

use super::{
    Ambient, FftGusts, LAYER_DIRECTIONAL, LAYER_FFT, LAYER_NOISE, fade, gradient, hash_angle,
    index, unit_wrap,
};
use windloom_simd_kernel::simd_kernel;

/// Reusable buffers for [`Ambient::component_row`] (one per thread; they only grow).
#[derive(Default)]
pub struct RowScratch {
    arg: Vec<f32>,
    noise: Vec<f32>,
    lattice: LatticeCache,
}

/// The gradients of the last few lattice rows a thread's noise rows used. A lattice cell is
/// many face rows tall (8 m for a directional layer's turbulence, against cells of a metre
/// or less), so consecutive face rows read the same two lattice rows; each gradient is a
/// sine and a cosine, which made the noise's largest cost on coarse grids.
#[derive(Default)]
struct LatticeCache {
    slots: Vec<LatticeRows>,
    /// The slot the next miss replaces (round robin).
    next: usize,
}

/// Gradients of lattice points `ix0..ix0 + n` of rows `iy` then `iy + 1`, for `seed`: they
/// depend on nothing else, so any layer asking for the same points may reuse them.
struct LatticeRows {
    key: (u32, i32, i32, usize),
    grads: Vec<[f32; 2]>,
}

/// At most this many lattice rows pairs are kept (two layers × two components fit).
const LATTICE_SLOTS: usize = 4;

impl LatticeCache {
    /// The gradients of lattice points `ix0..ix0 + n` in rows `iy` and `iy + 1` (bottom row
    /// first), made on a miss.
    fn rows(&mut self, seed: u32, iy: i32, ix0: i32, n: usize) -> &[[f32; 2]] {
        let key = (seed, iy, ix0, n);
        let k = match self.slots.iter().position(|s| s.key == key) {
            Some(k) => k,
            None => {
                let mut grads = Vec::with_capacity(2 * n);
                for dy in 0..2 {
                    grads.extend((0..n as i32).map(|dx| hash_angle(ix0 + dx, iy + dy, seed)));
                }
                let slot = LatticeRows { key, grads };
                if self.slots.len() < LATTICE_SLOTS {
                    self.slots.push(slot);
                    self.slots.len() - 1
                } else {
                    let k = self.next;
                    self.next = (k + 1) % LATTICE_SLOTS;
                    self.slots[k] = slot;
                    k
                }
            }
        };
        &self.slots[k].grads
    }
}

impl Ambient {
    /// `out[k]` = component `c` (0: x, 1: z) of [`Ambient::wind`]`([xs[k], z])`, for a row
    /// whose world x positions `xs` increase; the same bits as calling `wind` per point.
    ///
    /// `tables` holds what [`Self::fft_tables`] made for these `xs` at this time (or
    /// [`FftTables::NONE`]): an FFT layer with a table blends two of its rows.
    pub fn component_row(
        &self,
        c: usize,
        z: f32,
        xs: &[f32],
        tables: &FftTables,
        out: &mut [f32],
        scratch: &mut RowScratch,
    ) {
        let n = xs.len();
        let out = &mut out[..n];
        out.fill(0.0);
        scratch.arg.resize(n, 0.0);
        scratch.noise.resize(n, 0.0);
        let (arg, noise) = (&mut scratch.arg[..n], &mut scratch.noise[..n]);
        let lattice = &mut scratch.lattice;
        for (layer, (l, (_, fft))) in self.params.iter().zip(&self.layers).enumerate() {
            let dc = l.dir[c];
            match l.kind {
                LAYER_DIRECTIONAL => {
                    let s = 1.0 / 8.0;
                    let seed = if c == 0 { 11 } else { 23 };
                    scaled(xs, l.shift[0], s, arg);
                    noise_row(arg, (z - l.shift[1]) * s, seed, noise, lattice);
                    directional(out, noise, l.a, dc * l.b);
                }
                LAYER_NOISE => {
                    divided(xs, l.shift[0], l.a, arg);
                    noise_row(arg, (z - l.shift[1]) / l.a, 5, noise, lattice);
                    noise_speed(out, noise, l.b, dc);
                }
                LAYER_FFT => match fft {
                    Some(f) => {
                        let qz = z - l.shift[1];
                        match tables.rows(layer, f, l.shift, xs, qz) {
                            Some((a, b, fz)) => {
                                let c = FftConstants {
                                    xf: 0.0,
                                    fz,
                                    mean: l.a,
                                    amplitude: l.b,
                                    dc,
                                };
                                fft_table_row([a, b], &c, out);
                            }
                            None => fft_row(f, xs, l.shift[0], qz, l.a, l.b, dc, out, arg),
                        }
                    }
                    None => {
                        // No field: the speed is the mean alone.
                        let d = dc * (l.a + l.b * 0.0);
                        out.iter_mut().for_each(|o| *o += d);
                    }
                },
                _ => {
                    for (o, &x) in out.iter_mut().zip(xs) {
                        let along = x * l.dir[0] + z * l.dir[1];
                        let speed =
                            l.a * crate::num::sin(std::f32::consts::TAU * (along / l.b - l.c));
                        *o += dc * speed;
                    }
                }
            }
        }
    }
}

/// `arg[k] = (xs[k] − shift) · s`, as `wind` computes a directional layer's noise argument.
#[simd_kernel]
fn scaled(xs: &[f32], shift: f32, s: f32, arg: &mut [f32]) {
    for (a, &x) in arg.iter_mut().zip(xs) {
        *a = (x - shift) * s;
    }
}

/// `arg[k] = (xs[k] − shift) / scale`, as `wind` computes a noise layer's argument.
#[simd_kernel]
fn divided(xs: &[f32], shift: f32, scale: f32, arg: &mut [f32]) {
    for (a, &x) in arg.iter_mut().zip(xs) {
        *a = (x - shift) / scale;
    }
}

#[simd_kernel]
fn directional(out: &mut [f32], noise: &[f32], turbulence: f32, mean: f32) {
    for (o, &nz) in out.iter_mut().zip(noise) {
        *o = *o + turbulence * nz + mean;
    }
}

#[simd_kernel]
fn noise_speed(out: &mut [f32], noise: &[f32], strength: f32, dc: f32) {
    for (o, &nz) in out.iter_mut().zip(noise) {
        *o += dc * (strength * (0.5 + 0.5 * nz).clamp(0.0, 1.0));
    }
}

/// The four lattice gradients `(cos, sin)` of one lattice cell: `[x0y0, x1y0, x0y1, x1y1]`.
type Corners = [[f32; 2]; 4];

/// Calls `each(range, floor)` for the runs of samples of `xs` that share a floor, in order.
/// `step` is about the spacing of neighbouring samples: each run's end is guessed from it and
/// corrected by looking at the floors beside the guess, so finding a run costs a few floors,
/// not one a sample. Runs must not hold a sample whose floor differs from the run's between
/// two that share it (true of increasing `xs`, and of wrapped ones whose run is shorter than
/// the period).
fn runs(xs: &[f32], step: f32, mut each: impl FnMut(std::ops::Range<usize>, f32)) {
    let n = xs.len();
    let mut k = 0;
    while k < n {
        let xi = xs[k].floor();
        let guess = if step > 0.0 && step.is_finite() {
            ((xi + 1.0 - xs[k]) / step).ceil()
        } else {
            1.0
        };
        let mut end = if guess.is_finite() && guess >= 1.0 {
            (k + guess as usize).min(n)
        } else {
            k + 1
        };
        while end > k + 1 && xs[end - 1].floor() != xi {
            end -= 1;
        }
        while end < n && xs[end].floor() == xi {
            end += 1;
        }
        each(k..end, xi);
        k = end;
    }
}

/// The spacing of neighbouring samples of a row, about.
fn spacing(xs: &[f32]) -> f32 {
    match xs.len() {
        0 | 1 => 0.0,
        n => (xs[n - 1] - xs[0]) / (n - 1) as f32,
    }
}

/// `out[k] = gradient_noise(xs[k], y, seed)` for increasing `xs`: the lattice row and the
/// fade across it once, each lattice point's gradient once, and per sample only the blend.
/// Compiled for several SIMD levels as a whole, so the blend of each short run inlines
/// rather than paying a dispatch per run (runs are a few faces long on coarse grids).
#[simd_kernel]
fn noise_row(xs: &[f32], y: f32, seed: u32, out: &mut [f32], lattice: &mut LatticeCache) {
    let yi = y.floor();
    let fy = y - yi;
    let iy = yi as i32;
    let fv = fade(fy);
    // The lattice points the row spans (`xs` increase), their gradients from the cache.
    let (first, last) = match xs {
        [] => return,
        [a, .., b] => (a.floor(), b.floor()),
        [a] => (a.floor(), a.floor()),
    };
    let n = last - first + 2.0;
    // A lattice no finer than the faces is cached (a row of at most one gradient a face);
    // a noise finer than the grid makes its gradients run by run instead.
    let cached = (n.is_finite() && n <= (xs.len() + 1) as f32).then(|| {
        (
            first as i32,
            lattice.rows(seed, iy, first as i32, n as usize),
        )
    });
    let mut last_right: Option<(i32, [f32; 2], [f32; 2])> = None;
    runs(xs, spacing(xs), |r, xi| {
        let ix = xi as i32;
        let g = match cached {
            Some((ix0, grads)) => {
                let (k, w) = ((ix - ix0) as usize, grads.len() / 2);
                [grads[k], grads[k + 1], grads[w + k], grads[w + k + 1]]
            }
            None => {
                let left = match last_right {
                    Some((c, bottom, top)) if c == ix => (bottom, top),
                    _ => (hash_angle(ix, iy, seed), hash_angle(ix, iy + 1, seed)),
                };
                let right = (
                    hash_angle(ix + 1, iy, seed),
                    hash_angle(ix + 1, iy + 1, seed),
                );
                last_right = Some((ix + 1, right.0, right.1));
                [left.0, right.0, left.1, right.1]
            }
        };
        blend(&xs[r.clone()], xi, fy, fv, &g, &mut out[r]);
    });
}

/// The blend of [`gradient_noise`](super::gradient_noise) for samples in one lattice cell.
#[inline(always)]
fn blend(xs: &[f32], xi: f32, fy: f32, fv: f32, g: &Corners, out: &mut [f32]) {
    for (o, &x) in out.iter_mut().zip(xs) {
        let fx = x - xi;
        let n00 = gradient(g[0], fx, fy);
        let n10 = gradient(g[1], fx - 1.0, fy);
        let n01 = gradient(g[2], fx, fy - 1.0);
        let n11 = gradient(g[3], fx - 1.0, fy - 1.0);
        let u = fade(fx);
        let nx0 = n00 + (n10 - n00) * u;
        let nx1 = n01 + (n11 - n01) * u;
        *o = (nx0 + (nx1 - nx0) * fv) * std::f32::consts::SQRT_2;
    }
}

/// An FFT layer's part along a row: `dc · (mean + amplitude · sample(x − shift, qz))`, as
/// [`FftGusts::sample`] computes it: the row of texels once, the samples wrapped in one
/// vectorised loop, then per run of samples inside one texel only the blend.
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
#[simd_kernel]
fn fft_row(
    f: &FftGusts,
    xs: &[f32],
    shift: f32,
    qz: f32,
    mean: f32,
    amplitude: f32,
    dc: f32,
    out: &mut [f32],
    wrapped: &mut [f32],
) {
    let nf = f.n as f32;
    let (j0, j1, fz) = texel_rows(f, qz);
    let (r0, r1) = (&f.field[j0 * f.n..][..f.n], &f.field[j1 * f.n..][..f.n]);
    let wrapped = &mut wrapped[..xs.len()];
    texel_coordinates(xs, shift, f.tile, nf, wrapped);
    let step = spacing(xs) / f.tile * nf;
    let c = FftConstants {
        // Each run's (or face's) own texel column, filled in below.
        xf: 0.0,
        fz,
        mean,
        amplitude,
        dc,
    };
    if step > FFT_FACES_PER_RUN.recip() {
        // Short runs: finding each would cost more than its blend, so every face takes its
        // own texel (the same texel and arithmetic as a run's), the loads as vector lanes.
        return fft_faces(wrapped, [r0, r1], &c, out);
    }
    runs(wrapped, step, |r, xf| {
        let i0 = xf as usize % f.n;
        let i1 = (i0 + 1) % f.n;
        let corners = [r0[i0], r0[i1], r1[i0], r1[i1]];
        let c = FftConstants { xf, ..c };
        fft_blend(&wrapped[r.clone()], &corners, &c, &mut out[r]);
    });
}

/// The two texel rows `(j0, j1)` an FFT layer's samples at `qz` (the row's z less the
/// layer's shift) blend, and the weight `fz` of the second, as [`FftGusts::sample`] finds them.
#[inline(always)]
fn texel_rows(f: &FftGusts, qz: f32) -> (usize, usize, f32) {
    let z = unit_wrap(qz / f.tile) * f.n as f32;
    let j0 = z.floor() as usize % f.n;
    (j0, (j0 + 1) % f.n, z - z.floor())
}

/// [`fft_row`] from a table: `a` and `b` are the layer's field blended along x at this row's
/// faces in texel rows `j0` and `j1` (see [`FftTables`]), so only the blend in z is left,
/// with the same operations as [`fft_blend`].
#[simd_kernel]
fn fft_table_row(rows: [&[f32]; 2], c: &FftConstants, out: &mut [f32]) {
    let n = out.len().min(rows[0].len()).min(rows[1].len());
    let (a, b, out) = (&rows[0][..n], &rows[1][..n], &mut out[..n]);
    for k in 0..n {
        out[k] += c.part(a[k], b[k]);
    }
}

/// An FFT layer's field blended along x at a pass's faces: for each texel row `j` the rows
/// of faces sample, the value `field[j][i0] + (field[j][i1] − field[j][i0]) · fx` at each face,
/// which is the `a` (or `b`) of [`FftGusts::sample`] before its blend in z.
///
/// The faces of a pass have the same x in every row, so a face row needs only two table
/// rows and the blend between them, where sampling the field costs a texel lookup and two
/// blends along x per face. Made per pass and time by [`Ambient::fft_tables`], for layers
/// whose pass samples more face rows than texel rows (each table row then serves several).
/// A transient of at most one row of faces per texel row (a layer has at most 512 a side):
/// 8 MiB for a 4,096-face row, next to the solver's 56 bytes a cell.
pub struct FftTables {
    /// Per ambient layer: its table, if it has one.
    layers: Vec<Option<FftTable>>,
}

struct FftTable {
    /// What it was made for: the field's time, the layer's shift, and the row's faces (their
    /// number, first and last x). A table asked for anything else is not used (the row
    /// samples the field itself).
    made_for: (f32, [f32; 2], (usize, f32, f32)),
    /// Faces a row.
    w: usize,
    /// Texel row → its row in `rows` (`usize::MAX`: no face row samples it).
    slot: Vec<usize>,
    rows: Vec<f32>,
}

impl FftTables {
    /// No tables: every FFT layer samples its field face by face.
    pub const NONE: FftTables = FftTables { layers: Vec::new() };

    /// How many layers have a table.
    pub fn count(&self) -> usize {
        self.layers.iter().flatten().count()
    }

    /// The table rows of `layer` (field `f`, shifted by `shift`) a face row at `xs` and `qz`
    /// blends, and the blend's weight; none if the table was made for another time or row,
    /// or holds no row for `qz`.
    fn rows(
        &self,
        layer: usize,
        f: &FftGusts,
        shift: [f32; 2],
        xs: &[f32],
        qz: f32,
    ) -> Option<(&[f32], &[f32], f32)> {
        let t = self.layers.get(layer)?.as_ref()?;
        let (time, made_shift, faces) = t.made_for;
        let same = |a: f32, b: f32| a.to_bits() == b.to_bits();
        if !same(time, f.field_time) || made_shift != shift || faces != row_key(xs)? {
            return None;
        }
        let (j0, j1, fz) = texel_rows(f, qz);
        let row = |j: usize| {
            let k = *t.slot.get(j)?;
            t.rows.get(k.checked_mul(t.w)?..)?.get(..t.w)
        };
        Some((row(j0)?, row(j1)?, fz))
    }
}

impl Ambient {
    /// The tables ([`FftTables`]) of this time's FFT layers for rows of faces at `xs` (the
    /// same in every row), to be sampled at the rows `zs`; a layer gets one when `zs` hold
    /// more rows than the texel rows they sample. Used until the next [`Self::set_time`]
    /// changes the layer; after it, or for another row of faces, the rows sample the field
    /// face by face again.
    pub fn fft_tables(
        &self,
        xs: &[f32],
        zs: impl ExactSizeIterator<Item = f32> + Clone,
    ) -> FftTables {
        use rayon::prelude::*;
        let layers = self
            .params
            .iter()
            .zip(&self.layers)
            .map(|(l, (_, fft))| {
                let f = fft.as_ref().filter(|_| l.kind == LAYER_FFT)?;
                let mut slot = vec![usize::MAX; f.n];
                let mut used = Vec::new();
                for z in zs.clone() {
                    let (j0, j1, _) = texel_rows(f, z - l.shift[1]);
                    for j in [j0, j1] {
                        if slot[j] == usize::MAX {
                            slot[j] = used.len();
                            used.push(j);
                        }
                    }
                }
                if used.len() >= zs.len() || xs.is_empty() {
                    return None;
                }
                let w = xs.len();
                let mut wrapped = vec![0.0; w];
                texel_coordinates(xs, l.shift[0], f.tile, f.n as f32, &mut wrapped);
                let mut rows = vec![0.0; used.len() * w];
                rows.par_chunks_mut(w).zip(&used).for_each(|(out, &j)| {
                    fft_along_x(&wrapped, &f.field[j * f.n..][..f.n], out);
                });
                Some(FftTable {
                    made_for: (f.field_time, l.shift, row_key(xs)?),
                    w,
                    slot,
                    rows,
                })
            })
            .collect();
        FftTables { layers }
    }
}

/// What tells rows of faces apart for [`FftTables`]: their number and first and last x
/// (a pass's rows are evenly spaced); none for an empty row.
fn row_key(xs: &[f32]) -> Option<(usize, f32, f32)> {
    Some((xs.len(), *xs.first()?, *xs.last()?))
}

/// `out[k] = row[i0] + (row[i1] − row[i0]) · fx` for texel coordinates `xw` (the texel and
/// weight of [`fft_faces`]): one texel row of the field blended along x at each face.
#[simd_kernel]
fn fft_along_x(xw: &[f32], row: &[f32], out: &mut [f32]) {
    let texels = row.len();
    assert!((1..i32::MAX as usize).contains(&texels));
    let m = texels as i32;
    let n = out.len().min(xw.len());
    let (xw, out) = (&xw[..n], &mut out[..n]);
    for k in 0..n {
        let x = xw[k];
        let (xf, i0, i1) = texel_columns(x, m);
        // SAFETY: `texel_columns` gives columns in 0..m, the row's length.
        let (t0, t1) = unsafe {
            (
                *row.get_unchecked(i0 as usize),
                *row.get_unchecked(i1 as usize),
            )
        };
        out[k] = lerp(t0, t1, x - xf);
    }
}

/// The floor of texel coordinate `x` (in `[0, m]`) and the two texel columns a sample there
/// blends, `⌊x⌋` and the next, both wrapped into `0..m` (`m` itself is column 0, as `%`
/// makes it for a run). In i32 lanes: with 64-bit indices AVX2's cost model kept the loops
/// that call it scalar.
#[inline(always)]
fn texel_columns(x: f32, m: i32) -> (f32, i32, i32) {
    let xf = x.floor();
    let i = index(xf, m as f32);
    let i0 = if i >= m { i - m } else { i };
    let i1 = if i0 + 1 >= m { 0 } else { i0 + 1 };
    (xf, i0, i1)
}

/// Below this many faces per texel, [`fft_row`] samples face by face rather than by runs
/// (docs/PERFORMANCE.md: on AVX2 the forces 1.3–2.5× faster at 2–8 faces a texel; on a Zen 5
/// host both clones 5–8 % faster face by face at 13 faces a texel and 15 % slower at 15.6,
/// where the AVX-512 clone's gathers cost more than finding the runs).
const FFT_FACES_PER_RUN: f32 = 14.0;

/// [`fft_blend`] for every face on its own: face `k`'s texel is `⌊xw[k]⌋` (`n` wraps to 0,
/// as `%` does for a run; `c.xf` is not read), its corners gathered from the two texel rows
/// `rows` (`n` each).
#[inline(always)]
fn fft_faces(xw: &[f32], rows: [&[f32]; 2], c: &FftConstants, out: &mut [f32]) {
    let texels = rows[0].len();
    assert!(rows[1].len() == texels && (1..i32::MAX as usize).contains(&texels));
    let (r0, r1, m) = (rows[0], rows[1], texels as i32);
    let n = out.len().min(xw.len());
    let (xw, out) = (&xw[..n], &mut out[..n]);
    for k in 0..n {
        let x = xw[k];
        let (xf, i0, i1) = texel_columns(x, m);
        // SAFETY: `texel_columns` gives columns in 0..m, the rows' length.
        let t = unsafe {
            [
                *r0.get_unchecked(i0 as usize),
                *r0.get_unchecked(i1 as usize),
                *r1.get_unchecked(i0 as usize),
                *r1.get_unchecked(i1 as usize),
            ]
        };
        let fx = x - xf;
        out[k] += c.part(lerp(t[0], t[1], fx), lerp(t[2], t[3], fx));
    }
}

/// `out[k] = unit_wrap((xs[k] − shift) / tile) · n`: each sample's texel coordinate.
#[simd_kernel]
fn texel_coordinates(xs: &[f32], shift: f32, tile: f32, n: f32, out: &mut [f32]) {
    for (o, &x) in out.iter_mut().zip(xs) {
        *o = unit_wrap((x - shift) / tile) * n;
    }
}

/// What [`fft_blend`] needs besides the samples: the run's texel column, the row's fraction,
/// and the layer's mean, amplitude and direction component.
#[derive(Clone, Copy)]
struct FftConstants {
    xf: f32,
    fz: f32,
    mean: f32,
    amplitude: f32,
    dc: f32,
}

impl FftConstants {
    /// The layer's part from the field blended along x in the row's two texel rows, `a`
    /// (lower) and `b`: `dc · (mean + amplitude · lerp(a, b, fz))`, as [`FftGusts::sample`]
    /// and [`Ambient::wind`] compute it.
    #[inline(always)]
    fn part(&self, a: f32, b: f32) -> f32 {
        self.dc * (self.mean + self.amplitude * lerp(a, b, self.fz))
    }
}

/// `a + (b − a) · t`, the blend along each axis of an FFT layer's sample, the reference's
/// ([`FftGusts::sample`]) and every row kernel's.
#[inline(always)]
pub(super) fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// The bilinear blend of one texel's four values `[x0z0, x1z0, x0z1, x1z1]` for the samples
/// in it, added to `out` as the layer's part.
#[inline(always)]
fn fft_blend(xw: &[f32], t: &[f32; 4], c: &FftConstants, out: &mut [f32]) {
    for (o, &x) in out.iter_mut().zip(xw) {
        let fx = x - c.xf;
        *o += c.part(lerp(t[0], t[1], fx), lerp(t[2], t[3], fx));
    }
}
