//! One bake in memory, and the wind it gives at a point and a time.

use crate::manifest::{Manifest, Profile};

/// How positions and winds are written: the axes and units of the engine asking.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(C)]
pub enum Axes {
    /// windloom's own: x east, y up, z south, metres, m/s (right-handed, y-up). Godot and
    /// Bevy use these axes as they are.
    #[default]
    Windloom = 0,
    /// Unity: X = x, Y = up, Z = −z (north), metres, m/s (left-handed, y-up).
    Unity = 1,
    /// Unreal: X = x, Y = z, Z = up, centimetres, cm/s (left-handed, z-up).
    Unreal = 2,
}

impl Axes {
    /// A position in these axes as windloom's `[x, y, z]`, metres.
    #[inline]
    fn engine_to_world(self, p: [f32; 3]) -> [f32; 3] {
        match self {
            Axes::Windloom => p,
            Axes::Unity => [p[0], p[1], -p[2]],
            Axes::Unreal => [p[0] * 0.01, p[2] * 0.01, p[1] * 0.01],
        }
    }

    /// windloom's horizontal wind `[x, z]`, m/s, in these axes and units.
    #[inline]
    fn world_to_engine(self, w: [f32; 2]) -> [f32; 3] {
        match self {
            Axes::Windloom => [w[0], 0.0, w[1]],
            Axes::Unity => [w[0], 0.0, -w[1]],
            Axes::Unreal => [w[0] * 100.0, w[1] * 100.0, 0.0],
        }
    }
}

/// What the wind is beyond the baked rectangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(C)]
pub enum Outside {
    /// The wind at the nearest point of the rectangle's edge, as an engine's texture sampler
    /// set to *Clamp* reads the baked textures.
    #[default]
    Clamp = 0,
    /// No wind outside the rectangle.
    Zero = 1,
    /// The bake repeats in x and z (for levels simulated with `sim.boundary = "periodic"`,
    /// whose fields tile).
    Wrap = 2,
}

/// How a bake is read and answered.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Options {
    pub axes: Axes,
    pub outside: Outside,
    /// The format to read (`raw`, `exr`, `png16`, `png8`, `vf`, `dds`), or `None` for the
    /// most precise one the bake holds.
    pub format: Option<String>,
}

/// The log law of the surface layer, as the bake's profile gives it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LogLaw {
    z0: f32,
    top: f32,
    /// `ln(h_ref / z0)`: the factor is 1, exactly, at the reference height.
    at_reference: f32,
}

impl LogLaw {
    pub(crate) fn new(p: &Profile) -> Option<Self> {
        let (z0, href) = (p.roughness_length, p.reference_height);
        if !(z0 > 0.0 && href > z0 && p.top > 0.0) {
            return None;
        }
        Some(Self {
            z0,
            top: p.top,
            at_reference: ln(href / z0),
        })
    }

    /// The wind at `h` metres above the ground as a multiple of the baked wind.
    #[inline]
    pub(crate) fn factor(&self, h: f32) -> f32 {
        if h > self.z0 {
            ln(h.min(self.top) / self.z0) / self.at_reference
        } else {
            0.0
        }
    }
}

/// `ln x` for finite `x ≥ 1` (the law's `h / z0`), within a few units in the last place:
/// the exponent's share, and `2·atanh((m − 1)/(m + 1))` of the mantissa `m` in `[√½, √2)` by
/// its series to the ninth power (the next term is under 1e-9). Plain IEEE operations in a
/// fixed order, so the same bits on every platform, and a third of `libm::logf`'s
/// instructions (that one handles every float; the law needs these).
#[inline(always)]
pub(crate) fn ln(x: f32) -> f32 {
    let bits = x.to_bits();
    let mantissa = bits & 0x007f_ffff;
    // Above √2 (mantissa bits past √2's), halve m and count one more in the exponent:
    // integer selects, no branch to mispredict.
    let big = mantissa > 0x0035_04f3;
    let e = ((bits >> 23) & 0xff) as i32 - 127 + i32::from(big);
    let m = f32::from_bits(mantissa | if big { 0x3f00_0000 } else { 0x3f80_0000 });
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let series = s * (2.0 + s2 * (2.0 / 3.0 + s2 * (0.4 + s2 * (2.0 / 7.0 + s2 * (2.0 / 9.0)))));
    e as f32 * std::f32::consts::LN_2 + series
}

/// A grid of values over a world rectangle, sampled bilinearly between cell centres.
#[derive(Debug, Clone)]
pub(crate) struct Grid {
    pub nx: usize,
    pub ny: usize,
    pub min: [f32; 2],
    pub max: [f32; 2],
    /// Cells a metre along x and z.
    pub per_metre: [f32; 2],
}

impl Grid {
    pub(crate) fn new(nx: usize, ny: usize, min: [f32; 2], max: [f32; 2]) -> Self {
        Self {
            nx,
            ny,
            min,
            max,
            per_metre: [nx as f32 / (max[0] - min[0]), ny as f32 / (max[1] - min[1])],
        }
    }
}

/// Where a point falls between four cell centres: the corners' indices into a plane of
/// `nx × ny` cells (row-major), and the weights along x and z.
#[derive(Clone, Copy)]
struct Cell {
    k00: usize,
    k10: usize,
    k01: usize,
    k11: usize,
    fx: f32,
    fz: f32,
}

impl Grid {
    /// The cells around world point `(x, z)`, or `None` outside the rectangle when
    /// `outside` says so. Every index is below `nx × ny`.
    #[inline(always)]
    fn locate(&self, x: f32, z: f32, outside: Outside) -> Option<Cell> {
        let (nx, ny) = (self.nx, self.ny);
        let gx = (x - self.min[0]) * self.per_metre[0] - 0.5;
        let gz = (z - self.min[1]) * self.per_metre[1] - 0.5;
        let (i0, i1, j0, j1, fx, fz) = match outside {
            Outside::Clamp | Outside::Zero => {
                if outside == Outside::Zero
                    && !(x >= self.min[0]
                        && x <= self.max[0]
                        && z >= self.min[1]
                        && z <= self.max[1])
                {
                    return None;
                }
                // `max` first: a NaN becomes 0, the corner cell.
                let gx = gx.max(0.0).min((nx - 1) as f32);
                let gz = gz.max(0.0).min((ny - 1) as f32);
                // SAFETY: 0 ≤ gx ≤ nx − 1 and 0 ≤ gz ≤ ny − 1 (a NaN became 0 above), and
                // the grid's sides fit an i32 (the runtime refuses larger): in range, not NaN.
                let (i0, j0) = unsafe {
                    (
                        gx.to_int_unchecked::<i32>() as usize,
                        gz.to_int_unchecked::<i32>() as usize,
                    )
                };
                (
                    i0,
                    i0 + usize::from(i0 + 1 < nx),
                    j0,
                    j0 + usize::from(j0 + 1 < ny),
                    gx - i0 as f32,
                    gz - j0 as f32,
                )
            }
            Outside::Wrap => {
                let (fx0, fz0) = (gx.floor(), gz.floor());
                let wrap = |g: f32, n: usize| (g.rem_euclid(n as f32) as usize).min(n - 1);
                let (i0, j0) = (wrap(fx0, nx), wrap(fz0, ny));
                let (fx, fz) = (gx - fx0, gz - fz0);
                (
                    i0,
                    (i0 + 1) % nx,
                    j0,
                    (j0 + 1) % ny,
                    if fx.is_finite() { fx } else { 0.0 },
                    if fz.is_finite() { fz } else { 0.0 },
                )
            }
        };
        Some(Cell {
            k00: j0 * nx + i0,
            k10: j0 * nx + i1,
            k01: j1 * nx + i0,
            k11: j1 * nx + i1,
            fx,
            fz,
        })
    }
}

#[inline(always)]
fn lerp(a: [f32; 2], b: [f32; 2], t: f32) -> [f32; 2] {
    [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t]
}

/// Bilinear between the four corners `at` gives.
#[inline(always)]
fn bilinear(c: &Cell, at: impl Fn(usize) -> [f32; 2]) -> [f32; 2] {
    lerp(
        lerp(at(c.k00), at(c.k10), c.fx),
        lerp(at(c.k01), at(c.k11), c.fx),
        c.fz,
    )
}

/// The ground's heights at the cells' centres.
#[derive(Debug, Clone)]
pub(crate) struct Heights {
    pub grid: Grid,
    pub metres: Vec<f32>,
}

impl Heights {
    #[inline(always)]
    fn at_cell(&self, c: &Cell) -> f32 {
        let h = &self.metres;
        let a = h[c.k00] + (h[c.k10] - h[c.k00]) * c.fx;
        let b = h[c.k01] + (h[c.k11] - h[c.k01]) * c.fx;
        a + (b - a) * c.fz
    }

    /// The ground at `(x, z)`: beyond the rectangle the edge's, or where the bake wraps the
    /// wrapped point's.
    #[inline]
    fn at(&self, x: f32, z: f32, outside: Outside) -> f32 {
        let outside = if outside == Outside::Wrap {
            Outside::Wrap
        } else {
            Outside::Clamp
        };
        self.grid
            .locate(x, z, outside)
            .map_or(0.0, |c| self.at_cell(&c))
    }
}

/// One whole bake, read from one manifest: every frame of the wind, the profile and the
/// ground, ready to answer [`Bake::wind_at`].
#[derive(Debug, Clone)]
pub struct Bake {
    pub(crate) manifest: Manifest,
    pub(crate) grid: Grid,
    /// `frames × ny × nx` winds `[x, z]` in m/s at the profile's reference height.
    pub(crate) wind: Vec<[f32; 2]>,
    pub(crate) law: Option<LogLaw>,
    pub(crate) heights: Option<Heights>,
    /// The heights sit on the wind's own cells (every bake windloom writes): the wind's
    /// corners serve for both.
    pub(crate) heights_on_wind_grid: bool,
    pub(crate) options: Options,
    /// The files the wind was read from.
    pub(crate) source: Vec<String>,
    pub(crate) format: String,
}

/// The two frames a time falls between and the weight of the second.
#[derive(Clone, Copy)]
struct Moment {
    a: usize,
    b: usize,
    w: f32,
}

impl Bake {
    /// The number of frames.
    pub fn frames(&self) -> usize {
        self.manifest.frames.count
    }

    /// Frames a second of the baked wind.
    pub fn fps(&self) -> f32 {
        self.manifest.frames.fps
    }

    /// Whether the frames loop (`--loop`): time wraps past the last frame.
    pub fn looped(&self) -> bool {
        self.manifest.frames.looped
    }

    /// The seconds the frames span: `frames / fps` for a loop (the last frame blends back
    /// into the first), `(frames − 1) / fps` otherwise.
    pub fn duration(&self) -> f32 {
        let n = self.frames() as f32;
        if self.looped() {
            n / self.fps()
        } else {
            (n - 1.0).max(0.0) / self.fps()
        }
    }

    /// The manifest's `sequence`: one more with every bake into the same folder.
    pub fn sequence(&self) -> u64 {
        self.manifest.sequence
    }

    /// The baked cells, `[columns along x, rows along z]`.
    pub fn grid(&self) -> [usize; 2] {
        [self.grid.nx, self.grid.ny]
    }

    /// The world rectangle the wind covers, `[x, z]` minimum and maximum, metres (windloom's
    /// axes).
    pub fn bounds(&self) -> ([f32; 2], [f32; 2]) {
        (self.grid.min, self.grid.max)
    }

    /// The bake's strongest wind, m/s.
    pub fn max_speed(&self) -> f32 {
        self.manifest.max_speed
    }

    /// The format the wind was read from (`raw`, `exr`, …) and its files.
    pub fn source(&self) -> (&str, &[String]) {
        (&self.format, &self.source)
    }

    /// The options the bake answers with.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// The bytes the wind, the heights and this struct take in memory.
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.wind.capacity() * std::mem::size_of::<[f32; 2]>()
            + self.heights.as_ref().map_or(0, |h| h.metres.capacity() * 4)
    }

    /// The ground's height at world point `(x, z)` (windloom's axes, metres): the bake's
    /// terrain where it has one, else 0; beyond the rectangle the edge's, or with
    /// [`Outside::Wrap`] the wrapped point's (the ground the wind there was baked over).
    pub fn ground_at(&self, x: f32, z: f32) -> f32 {
        (self.heights.as_ref()).map_or(0.0, |h| h.at(x, z, self.options.outside))
    }

    /// The frames `t` seconds fall between. In f64: a game's clock a month on (2.6 million
    /// seconds, 156 million frames at 60 fps) still finds its place to a millionth of a frame
    /// (f32 would step 16 frames at a time there). A time that is no number reads the first
    /// frame; an infinite one the first or the last frame of a bake that does not loop.
    #[inline]
    fn moment(&self, t: f64) -> Moment {
        let n = self.frames();
        if n <= 1 {
            return Moment { a: 0, b: 0, w: 0.0 };
        }
        let last = (n - 1) as f64;
        let f = t * f64::from(self.fps());
        let f = if self.looped() {
            if f.is_finite() {
                f.rem_euclid(n as f64)
            } else {
                0.0
            }
        } else if f.is_nan() {
            0.0
        } else {
            f.clamp(0.0, last)
        };
        let a = (f as usize).min(n - 1);
        let b = if self.looped() {
            (a + 1) % n
        } else {
            (a + 1).min(n - 1)
        };
        Moment {
            a,
            b,
            w: ((f - a as f64) as f32).clamp(0.0, 1.0),
        }
    }

    #[inline]
    fn frame(&self, k: usize) -> &[[f32; 2]] {
        let cells = self.grid.nx * self.grid.ny;
        &self.wind[k * cells..(k + 1) * cells]
    }

    /// The wind at a point in windloom's axes (m/s, `[x, z]`), the corners read by `at`.
    #[inline(always)]
    fn sample(&self, p: [f32; 3], at: impl Fn(usize) -> [f32; 2]) -> [f32; 2] {
        let [x, y, z] = p;
        let Some(c) = self.grid.locate(x, z, self.options.outside) else {
            return [0.0, 0.0];
        };
        let v = bilinear(&c, at);
        let Some(law) = &self.law else {
            return v;
        };
        let ground = match &self.heights {
            None => 0.0,
            // The wind's own corners: clamped to the edge's cells, or wrapped as the wind is.
            Some(h) if self.heights_on_wind_grid => h.at_cell(&c),
            Some(h) => h.at(x, z, self.options.outside),
        };
        let k = law.factor(y - ground);
        [v[0] * k, v[1] * k]
    }

    /// The wind at `position` (in the [`Options::axes`]) at `t` seconds of the game's clock
    /// (f64, so a clock that has run for weeks reads the wind as precisely as one just
    /// started): m/s (cm/s in Unreal's axes), in the same axes.
    ///
    /// Bilinear between the baked cells' centres; the height above the ground (the bake's
    /// terrain, else `y = 0`) scales it by the profile's log law (zero at and below the
    /// roughness length, the baked wind at the reference height, the wind at the profile's
    /// top above it); linear in time between frames, frame `k` at `t = k / fps`, wrapping
    /// for a looped bake and holding the first or last frame otherwise. Beyond the baked
    /// rectangle, [`Options::outside`] says. The wind is horizontal: the vertical part is 0.
    pub fn wind_at(&self, position: [f32; 3], t: f64) -> [f32; 3] {
        let m = self.moment(t);
        let (fa, fb) = (self.frame(m.a), self.frame(m.b));
        let p = self.options.axes.engine_to_world(position);
        // Each corner blended in time, then in space: what `wind_at_many` reads from its
        // blended frame, to the bit.
        let v = self.sample(p, |k| lerp(fa[k], fb[k], m.w));
        self.options.axes.world_to_engine(v)
    }

    /// [`Self::wind_at`] for many positions at one time, into `out` (as long as `positions`;
    /// a shorter `out` gets the first positions' winds).
    pub fn wind_at_many(&self, positions: &[[f32; 3]], t: f64, out: &mut [[f32; 3]]) {
        let m = self.moment(t);
        let (fa, fb) = (self.frame(m.a), self.frame(m.b));
        let n = positions.len().min(out.len());
        if m.w == 0.0 {
            // SAFETY: `locate` gives indices below nx × ny, a frame's length.
            self.each(positions, out, |k| unsafe { *fa.get_unchecked(k) });
        } else if n * 32 >= fa.len() {
            // Many points: one frame blended once (about a nanosecond a cell) and read as
            // one, each cell as `wind_at` blends a corner, to the bit.
            let blended: Vec<[f32; 2]> =
                fa.iter().zip(fb).map(|(a, b)| lerp(*a, *b, m.w)).collect();
            // SAFETY: as above; `blended` is a frame long.
            self.each(positions, out, |k| unsafe { *blended.get_unchecked(k) });
        } else {
            // SAFETY: as above, for both frames.
            self.each(positions, out, |k| unsafe {
                lerp(*fa.get_unchecked(k), *fb.get_unchecked(k), m.w)
            });
        }
    }

    /// The wind at every position into `out`, the corners (indices below a frame's length)
    /// read by `at`.
    #[inline(always)]
    fn each(&self, positions: &[[f32; 3]], out: &mut [[f32; 3]], at: impl Fn(usize) -> [f32; 2]) {
        let axes = self.options.axes;
        for (p, o) in positions.iter().zip(out.iter_mut()) {
            *o = axes.world_to_engine(self.sample(axes.engine_to_world(*p), &at));
        }
    }
}
