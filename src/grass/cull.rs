//! Which blades a frame draws, and with how many segments: Jahrmann & Wimmer's culling tests
//! (seed 001) and a distance LOD, on the CPU — the twin `shaders/grass_cull.wgsl` is tested
//! against. Per blade, from its root, middle and tip (the deformed curve at t = 0, ½, 1):
//!
//! - **orientation**: a blade seen edge-on — the ground-plane direction from the camera to its
//!   root nearly along the blade's width — is culled (`|dir·side| > orientation_limit`);
//! - **frustum**: culled when none of the three points lies inside the view frustum widened by
//!   `frustum_tolerance` (a fraction of `w` in clip space), which keeps bent and wide blades at
//!   the edge;
//! - **distance**, in buckets: each blade falls in one of `buckets` buckets (a hash of its index,
//!   so no pattern shows); bucket `b` is kept up to `max_distance·(1 − b/buckets)`, so the field
//!   thins with distance instead of ending at a line; past `thin_distance` the field also
//!   thins with the square of the distance (a second hash, [`thin_draw`]), so however dense
//!   the field the drawn blades stay a few pixels apart. A blade fades (narrows) over the last
//!   [`FADE`] of its range and the survivors widen to keep the far field's coverage
//!   ([`distance_width`]), so no blade pops;
//! - **LOD**: level 0, 1 or 2 ([`LOD_SEGMENTS`] segments) by distance, with the boundaries
//!   dithered per blade by `dither` (a band, not a line) and with `hysteresis`: a blade drawn at
//!   one level changes only when it is past the boundary by that fraction, so blades at a
//!   boundary do not flicker as the camera moves.

use super::Blade;

/// Segments per blade at each LOD level (near to far).
pub const LOD_SEGMENTS: [u32; 3] = [5, 3, 1];
/// The fraction of a blade's distance range over which it fades out.
pub const FADE: f32 = 0.2;
/// No previous level (a blade not yet drawn).
pub const NO_LEVEL: u32 = 3;
/// Widest a surviving far blade is drawn, as a multiple of its width.
pub const MAX_WIDEN: f32 = 3.0;

/// The culling and LOD settings (the 3D view's toggles; `windloom bench --cull`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CullParams {
    pub orientation: bool,
    pub frustum: bool,
    pub distance: bool,
    pub lod: bool,
    /// Cull when `|dir·side|` exceeds this (Jahrmann: 0.9).
    pub orientation_limit: f32,
    /// Frustum widening, a fraction of clip-space `w`.
    pub frustum_tolerance: f32,
    /// Metres beyond which no blade is drawn; blades thin toward it.
    pub max_distance: f32,
    pub buckets: u32,
    /// Metres beyond which the field thins with the square of the distance, so the drawn
    /// blades stay about [`THIN_SPACING_PX`] apart on screen however dense the field
    /// ([`CullParams::for_grass`]; 0: no such thinning).
    pub thin_distance: f32,
    /// LOD boundaries (metres): level 0 → 1, 1 → 2.
    pub lod_near: f32,
    pub lod_far: f32,
    /// Width of the dithered band, a fraction of each boundary.
    pub dither: f32,
    /// A level changes only this fraction past the boundary.
    pub hysteresis: f32,
}

impl CullParams {
    /// Every test off: every blade drawn at full detail.
    pub const OFF: Self = Self {
        orientation: false,
        frustum: false,
        distance: false,
        lod: false,
        ..Self::DEFAULT
    };
    const DEFAULT: Self = Self {
        orientation: true,
        frustum: true,
        distance: true,
        lod: true,
        orientation_limit: 0.9,
        frustum_tolerance: 0.1,
        max_distance: 300.0,
        buckets: 8,
        thin_distance: 0.0,
        lod_near: 8.0,
        lod_far: 25.0,
        dither: 0.3,
        hysteresis: 0.05,
    };

    /// Every test on, with distances for blades of `height` metres (the mean of the layout's
    /// range) seen at 1080 lines through a 45° lens: full detail while a blade is over ~80 px
    /// tall, 3 segments down to ~26 px, and none once it would be under 2 px.
    pub fn for_height(height: f32) -> Self {
        let at = |px: f32| height * FOCAL_1080 / px;
        Self {
            lod_near: at(80.0),
            lod_far: at(26.0),
            max_distance: at(2.0),
            ..Self::DEFAULT
        }
    }
}

/// How far apart (pixels at 1080 lines through a 45° lens) the field's drawn blades are kept,
/// at least: nearer than this, more blades add triangles but not picture — they overlap
/// within a pixel, and the far field ([`super::far`]) shows their look.
pub const THIN_SPACING_PX: f32 = 2.5;

impl CullParams {
    /// [`CullParams::for_height`] for the layout's mean blade height, thinning the field past
    /// the distance at which blades `1/√density` metres apart come [`THIN_SPACING_PX`] apart
    /// on screen: 20 M blades over the meadow draw as few triangles as 2.5 M did.
    pub fn for_grass(g: &crate::doc::GrassParams) -> Self {
        let spacing = 1.0 / g.density.max(1e-6).sqrt();
        Self {
            thin_distance: spacing * FOCAL_1080 / THIN_SPACING_PX,
            ..Self::for_height(0.5 * (g.height[0] + g.height[1]))
        }
    }
}

/// Pixels per metre at 1 m for 1080 lines through a 45° lens: `540 / tan 22.5°`.
pub const FOCAL_1080: f32 = 1303.6753;

impl Default for CullParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// What the cull pass decides for a blade.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    Orientation,
    Frustum,
    Distance,
    /// Drawn, at this LOD level.
    Level(u32),
}

/// A PCG hash of `k` to `[0, 1)` (`pcg01` in `grass_cull.wgsl`).
pub fn pcg01(k: u32) -> f32 {
    let state = k.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (((word >> 22) ^ word) >> 8) as f32 / 16_777_216.0
}

/// Blade `k`'s distance bucket.
pub fn bucket(k: u32, buckets: u32) -> u32 {
    ((pcg01(k ^ 0x9e37_79b9) * buckets as f32) as u32).min(buckets.max(1) - 1)
}

/// Blade `k`'s draw for the density thinning, uniform in `[0, 1)`: it is drawn while the share
/// of the field kept there, `(thin_distance / d)²`, is above it.
pub fn thin_draw(k: u32) -> f32 {
    pcg01(k ^ 0x85eb_ca6b)
}

/// How far blade `k` is drawn (metres) under distance culling: its bucket's reach, and under
/// the density thinning `thin_distance / √draw`.
pub fn reach(k: u32, p: &CullParams) -> f32 {
    let b = p.buckets.max(1);
    let bucket = p.max_distance * (1.0 - bucket(k, b) as f32 / b as f32);
    if p.thin_distance > 0.0 {
        bucket.min(p.thin_distance / thin_draw(k).max(1e-12).sqrt())
    } else {
        bucket
    }
}

/// The share of the field distance culling means to keep at `distance`: the buckets'
/// `1 − d/max`, times the density thinning's `min(1, (thin/d)²)`.
pub fn kept_share(distance: f32, p: &CullParams) -> f32 {
    let buckets = (1.0 - distance / p.max_distance).max(0.0);
    if p.thin_distance > 0.0 && distance > p.thin_distance {
        buckets * (p.thin_distance / distance).powi(2)
    } else {
        buckets
    }
}

/// The width multiplier of blade `k` at `distance` under distance culling: 0 → 1 as it fades
/// in over the last [`FADE`] of its reach, times the widening that keeps the thinned field's
/// coverage (`1 / kept fraction`, at most [`MAX_WIDEN`]).
pub fn distance_width(k: u32, distance: f32, p: &CullParams) -> f32 {
    if !p.distance {
        return 1.0;
    }
    let r = reach(k, p);
    let fade = ((r - distance) / (FADE * r)).clamp(0.0, 1.0);
    let kept = kept_share(distance, p).max(1.0 / MAX_WIDEN);
    fade * fade * (3.0 - 2.0 * fade) / kept
}

/// The LOD level of blade `k` at `distance`, given the level it was drawn at last frame
/// (`prev`, or [`NO_LEVEL`]).
pub fn level(k: u32, distance: f32, prev: u32, p: &CullParams) -> u32 {
    if !p.lod {
        return 0;
    }
    let j = 1.0 + p.dither * (pcg01(k) - 0.5);
    let at = |shift: f32| {
        u32::from(distance > p.lod_near * j * shift) + u32::from(distance > p.lod_far * j * shift)
    };
    let plain = at(1.0);
    if prev >= NO_LEVEL || plain == prev {
        plain
    } else if plain > prev {
        at(1.0 + p.hysteresis).max(prev)
    } else {
        at(1.0 - p.hysteresis).min(prev)
    }
}

/// The pass's decision for blade `k` (`side`: its width direction on the ground, `(x, z)`),
/// whose deformed curve passes `root`, `mid` and `tip`, seen from `eye` through `view_proj`
/// (column-major, as the shaders get it). Also returns how near the decision came to going the
/// other way (the smallest margin to any threshold it tested), so tests can set aside blades
/// that f32 rounding could tip.
pub fn classify(
    k: u32,
    side: [f32; 2],
    [root, mid, tip]: [[f32; 3]; 3],
    eye: [f32; 3],
    view_proj: &glam::Mat4,
    prev: u32,
    p: &CullParams,
) -> (Verdict, f32) {
    let mut margin = f32::INFINITY;
    if p.orientation {
        let d = [root[0] - eye[0], root[2] - eye[2]];
        let l = d[0].hypot(d[1]);
        if l > 0.0 {
            let c = ((d[0] * side[0] + d[1] * side[1]) / l).abs();
            margin = margin.min((c - p.orientation_limit).abs());
            if c > p.orientation_limit {
                return (Verdict::Orientation, margin);
            }
        }
    }
    if p.frustum {
        let mut inside = false;
        let mut m = f32::INFINITY;
        for q in [root, mid, tip] {
            let c = *view_proj * glam::Vec4::new(q[0], q[1], q[2], 1.0);
            let h = c.w * (1.0 + p.frustum_tolerance);
            let slack = (h - c.x.abs())
                .min(h - c.y.abs())
                .min(h - c.z)
                .min(c.z + h - c.w);
            if c.w > 0.0 {
                m = m.min((slack / c.w).abs());
                inside |= slack >= 0.0;
            }
        }
        margin = margin.min(m);
        if !inside {
            return (Verdict::Frustum, margin);
        }
    }
    let d = glam::Vec3::from(root).distance(glam::Vec3::from(eye));
    if p.distance {
        let r = reach(k, p);
        margin = margin.min((d - r).abs() / r.max(1e-6));
        if d >= r {
            return (Verdict::Distance, margin);
        }
    }
    if p.lod {
        let j = 1.0 + p.dither * (pcg01(k) - 0.5);
        for b in [p.lod_near, p.lod_far] {
            for s in [1.0, 1.0 - p.hysteresis, 1.0 + p.hysteresis] {
                margin = margin.min((d - b * j * s).abs() / (b * j * s).max(1e-6));
            }
        }
    }
    (Verdict::Level(level(k, d, prev, p)), margin)
}

/// The ground-plane width direction of `blade` (`cwd::frame`'s side).
pub fn side(blade: &Blade) -> [f32; 2] {
    let (s, c) = blade.facing.sin_cos();
    [-s, c]
}

/// Triangles a frame draws for `drawn` blades at each LOD level: a strip of `2·s + 1`
/// vertices is `2·s − 1` triangles (9, 5 and 1).
pub fn triangles(drawn: [u64; 3]) -> u64 {
    drawn
        .iter()
        .zip(LOD_SEGMENTS)
        .map(|(&n, s)| n * u64::from(2 * s - 1))
        .sum()
}

/// What the cull pass would draw at each LOD level of `n` blades spread evenly over
/// `layout`'s world, seen from `eye` through `view_proj`, estimated from `sample` of them
/// (blade `k` of the `n` for `k` evenly spread over `0..n`, so each keeps its own hashes)
/// placed at random in calm air and scaled up: a count for a field too big to place on this
/// device (`bench --grass` with more blades than its storage buffers hold), tested against
/// the GPU's counters where both fit. Obstacles are ignored (they only lower it).
pub fn estimate_drawn(
    layout: &crate::doc::Layout,
    n: u64,
    eye: [f32; 3],
    view_proj: &glam::Mat4,
    p: &CullParams,
    sample: u32,
) -> [f64; 3] {
    let g = &layout.grass;
    let (min, max) = layout.bounds();
    let mut drawn = [0u64; 3];
    let sample = sample.max(1);
    for s in 0..sample {
        let k = ((u64::from(s) * n) / u64::from(sample)) as u32;
        let r = |salt: u32| super::hash01(s, salt, 0x5eed_cafe);
        let mix = |range: [f32; 2], salt| range[0] + (range[1] - range[0]) * r(salt);
        let blade = Blade {
            pos: [
                min[0] + (max[0] - min[0]) * r(1),
                min[1] + (max[1] - min[1]) * r(2),
            ],
            facing: std::f32::consts::TAU * r(3),
            height: mix(g.height, 4),
            width: mix(g.width, 5),
            stiffness: mix(g.stiffness, 6),
            palette: 0,
            variation: 0.0,
        };
        let c = super::cwd::centreline(&blade, [0.0, 0.0], g, 0.0, 2);
        let pts = [c[0].pos, c[1].pos, c[2].pos];
        if let (Verdict::Level(l), _) = classify(k, side(&blade), pts, eye, view_proj, NO_LEVEL, p)
        {
            drawn[l as usize] += 1;
        }
    }
    let scale = n as f64 / f64::from(sample);
    drawn.map(|d| d as f64 * scale)
}
