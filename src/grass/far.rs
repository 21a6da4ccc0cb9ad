//! The grass seen from afar: what the ground shows where the renderer draws fewer blades than
//! the field holds — beyond the distance cull, and where a blade budget thins the field
//! ([`super::sample`]). The CPU twin of `shaders/grass_far.wgsl` and of the far field in
//! `shaders/grass_ground.wgsl`.
//!
//! Without it, a view of the whole world showed plain soil: at that distance every blade is
//! under the cull's 2-pixel rule, so a designer who framed the level saw neither the grass's
//! colours nor anything of the wind. With it the ground carries the field's look, evaluated
//! per texel of a grid over the world (the wind grid, at most [`MAX_TEXELS`] a side) from the
//! same model the blades use:
//!
//! - [`texel`]: [`PROBES`] mean blades (the layout's mean height, width and stiffness, the
//!   palettes' mean colours, facings spread evenly) stand at the texel's centre in its wind
//!   cell's velocity, bent by the CWD model without flutter (the mean of many blades'
//!   flutter at their own phases) and the trail's crush. Each is cut
//!   into [`POINTS`] segments, coloured and shaded as the blade shader colours and shades them
//!   (base-to-tip gradient, eq. 14's self-shadow, [`super::light::blade`]'s sun, sky and
//!   sheen on the side facing the eye), and weighted by the area it shows the eye. The same areas give how much of the
//!   ground the field hides along the line of sight (Beer–Lambert over the layout's density):
//!   from above, more ground shows between upright blades than between bent ones.
//! - [`cover`]: the share of the field's blade coverage the renderer still draws at a
//!   distance — the distance cull's buckets with their fade and widening, times the sample's
//!   kept share with its widening. The ground takes the blades' colour over the share
//!   `hidden · (1 − cover)` of it, so near blades stand on plain ground and the far field
//!   takes over where they thin out, with no line between.

use super::Blade;
use super::cull::{CullParams, FADE, MAX_WIDEN};
use super::cwd;
use crate::doc::GrassParams;
use glam::{Vec3, Vec4};

/// Mean blades evaluated per texel, their facings spread evenly around the circle.
pub const PROBES: usize = 4;
/// Segments each probe blade is cut into.
pub const POINTS: usize = 4;
/// Most texels of the far field along a side (the wind grid when it is smaller).
pub const MAX_TEXELS: usize = 256;
/// The blade shader's per-blade tint `(1 + 0.08v, 1 + 0.04v, 1 − 0.10v)·(1 + 0.12v)` averaged
/// over the variation `v`, uniform in `[-1, 1]` (`E[v] = 0`, `E[v²] = ⅓`).
pub const MEAN_TINT: [f32; 3] = [
    1.0 + 0.12 * 0.08 / 3.0,
    1.0 + 0.12 * 0.04 / 3.0,
    1.0 - 0.12 * 0.10 / 3.0,
];

/// Texels of the far field over a wind grid of `nx × ny` cells: the same grid, or one scaled
/// down to at most [`MAX_TEXELS`] along its longer side.
pub fn grid(nx: usize, ny: usize) -> (usize, usize) {
    let longest = nx.max(ny).max(1);
    if longest <= MAX_TEXELS {
        return (nx.max(1), ny.max(1));
    }
    let scale = MAX_TEXELS as f32 / longest as f32;
    let fit = |n: usize| ((n as f32 * scale).round() as usize).clamp(1, MAX_TEXELS);
    (fit(nx), fit(ny))
}

/// What the far field draws with besides the wind: the mean palette (linear RGB, the mean
/// tint applied), the sun (unit vector toward it) and the sky's share of the light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Look {
    pub base: [f32; 3],
    pub tip: [f32; 3],
    pub sun: [f32; 3],
    pub ambient: f32,
}

impl Look {
    /// The mean of `g`'s palettes (the blades pick one each, evenly), under `sun` (`xyz` toward
    /// it, `w` the sky's share, as the renderer's scene holds it).
    pub fn new(g: &GrassParams, sun: [f32; 4]) -> Self {
        let mean = |pick: fn(&crate::doc::Palette) -> [f32; 3], fallback: [f32; 3]| {
            let sum: Vec3 = g.palettes.iter().map(|p| Vec3::from(pick(p))).sum();
            let mean = if g.palettes.is_empty() {
                Vec3::from(fallback)
            } else {
                sum / g.palettes.len() as f32
            };
            (mean * Vec3::from(MEAN_TINT)).to_array()
        };
        Self {
            base: mean(|p| p.base, FALLBACK_BASE),
            tip: mean(|p| p.tip, FALLBACK_TIP),
            sun: Vec3::new(sun[0], sun[1], sun[2])
                .normalize_or_zero()
                .to_array(),
            ambient: sun[3],
        }
    }
}

/// The palette the renderer uses when a layout has none: base and tip (linear RGB).
pub const FALLBACK_BASE: [f32; 3] = [0.1, 0.22, 0.05];
pub const FALLBACK_TIP: [f32; 3] = [0.45, 0.65, 0.2];

/// Probe blade `m` of a texel centred at `pos`: the layout's mean blade, facing
/// `τ·(m + ½)/PROBES`, with no colour variation.
pub fn probe(g: &GrassParams, pos: [f32; 2], m: usize) -> Blade {
    let mid = |r: [f32; 2]| 0.5 * (r[0] + r[1]);
    Blade {
        pos,
        facing: std::f32::consts::TAU * (m as f32 + 0.5) / PROBES as f32,
        height: mid(g.height),
        width: mid(g.width),
        stiffness: mid(g.stiffness),
        palette: 0,
        variation: 0.0,
    }
}

/// How far a blade of `height` whose tip stands `tip` from its root lies over: the tip's
/// reach along the ground over the blade's length, 0 upright to 1 flat (`blade_lay` in
/// `grass_common.wgsl`).
pub fn lay(tip: Vec3, height: f32) -> f32 {
    (tip.x.hypot(tip.z) / height.max(1e-6)).min(1.0)
}

/// The share of the ground between the drawn blades that the lower canopy covers, and how
/// dark it is against the field's look (its own blades shade it). A layout's blade density
/// is what the renderer can afford, not a real meadow's thousands of stems a square metre:
/// drawn over bare soil, a field seen from afar was two-thirds soil, and neither its grass
/// nor its wind showed.
pub const UNDERSTOREY: f32 = 0.85;
pub const UNDERSTOREY_SHADE: f32 = 0.6;
/// The share of the lower canopy a map backdrop lets through where grass grows on it: the
/// level's picture still reads under its grass, and the grass's wind shows over it. (All of
/// it let through, a level laid over its picture showed the picture from afar, and no wind.)
pub const MAP_THROUGH_CANOPY: f32 = 0.5;

/// The ground's colour under the far field (`far_ground` in `grass_ground.wgsl`): the lit
/// ground `lit` (soil, or the map where it shows by `shown`), the lower canopy — the field's
/// look `look`, shaded — over the share of it where grass grows (`share`, [`canopy_share`]:
/// none on a road), less [`MAP_THROUGH_CANOPY`] of it where the map shows, then `look` itself
/// over the share `take` the drawn blades leave to it (the texel's `hidden · (1 − cover)`).
pub fn ground(lit: Vec3, look: Vec3, take: f32, shown: f32, share: f32) -> Vec3 {
    let canopy = UNDERSTOREY * share * (1.0 - MAP_THROUGH_CANOPY * shown);
    let under = lit.lerp(look * UNDERSTOREY_SHADE, canopy);
    under.lerp(look, take)
}

/// Blades a square metre from which the lower canopy covers its full share: a sparser field
/// has no canopy to speak of between its blades (a layout of a blade in 100 m² laid a green
/// film over its map backdrop).
pub const CANOPY_FULL_DENSITY: f32 = 10.0;

/// The lower canopy's share of the ground under `share` of a layout's `density` (blades a
/// square metre): `share`, thinned below [`CANOPY_FULL_DENSITY`].
pub fn canopy_share(share: f32, density: f32) -> f32 {
    share * (density.max(0.0) / CANOPY_FULL_DENSITY).min(1.0)
}

/// Bare earth, linear RGB: the ground where the density map grows no grass (a road, a
/// pond's bed). The ground under grass is the grass's own darkened colour, which over a road
/// read as lush grass.
pub const EARTH: [f32; 3] = [0.095, 0.08, 0.06];

/// The ground's own colour under a share `share` of the layout's density: `soil` (the
/// grass's darkened colour) under grass, [`EARTH`] where none grows (`soil` itself wherever
/// the grass grows in full, as without a density map).
pub fn bare_ground(soil: Vec3, share: f32) -> Vec3 {
    Vec3::from(EARTH).lerp(soil, share.clamp(0.0, 1.0))
}

/// Samples a side of a far texel takes of the density map.
pub const SHARE_SAMPLES: usize = 4;

/// The share of the layout's density that grows over the world box `texel` (the density
/// map's mean over it, [`SHARE_SAMPLES`]² samples; 1 without a map; `bounds`: the world's):
/// none over a road or a pond, which from afar then shows its ground, not grass.
pub fn density_share(
    map: Option<&crate::doc::DensityMap>,
    bounds: ([f32; 2], [f32; 2]),
    texel: [[f32; 2]; 2],
) -> f32 {
    let Some(map) = map else {
        return 1.0;
    };
    let n = SHARE_SAMPLES;
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..n {
            let f = |k: usize, a: f32, b: f32| a + (b - a) * (k as f32 + 0.5) / n as f32;
            let p = [
                f(i, texel[0][0], texel[1][0]),
                f(j, texel[0][1], texel[1][1]),
            ];
            sum += map.at(p, bounds);
        }
    }
    sum / (n * n) as f32
}

/// [`density_share`] of every texel of a far field of `fx × fy` texels over the world
/// `bounds`, row-major.
pub fn density_shares(
    map: Option<&crate::doc::DensityMap>,
    bounds: ([f32; 2], [f32; 2]),
    (fx, fy): (usize, usize),
) -> Vec<f32> {
    let (min, max) = bounds;
    let cell = [(max[0] - min[0]) / fx as f32, (max[1] - min[1]) / fy as f32];
    (0..fy)
        .flat_map(|j| (0..fx).map(move |i| (i, j)))
        .map(|(i, j)| {
            let a = [min[0] + i as f32 * cell[0], min[1] + j as f32 * cell[1]];
            density_share(map, bounds, [a, [a[0] + cell[0], a[1] + cell[1]]])
        })
        .collect()
}

/// A texel's `hidden` where only `share` of the layout's density grows: the optical depth
/// scaled by the share (`1 − e^(−ρ·s·D) = 1 − (1 − hidden)^s`).
pub fn thinned(hidden: f32, share: f32) -> f32 {
    1.0 - (1.0 - hidden).max(0.0).powf(share.max(0.0))
}

/// The share of the far field's look a drawn blade `distance` metres away takes instead of
/// its own colour (`prefilter` in `grass_blades.wgsl`): none within 0.7× the cull's far LOD
/// boundary (a blade ~37 px tall at 1080 lines), all past 3× it (~9 px), smoothstep between.
/// A blade a few pixels tall cannot show its own colour, shade and sheen, only add noise to
/// the field's mean: drawn in its own colours, the mid distance was a salt-and-pepper
/// speckle that crawled as the blades swayed. This is a level of detail for the shading, as
/// the segments are for the shape.
pub fn prefilter(distance: f32, cull: &CullParams) -> f32 {
    let (a, b) = (0.7 * cull.lod_far, 3.0 * cull.lod_far);
    let x = ((distance - a) / (b - a).max(1e-6)).clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Shallowest view elevation (its sine) the ground coverage is computed for: nearer the
/// horizon the field counts as fully covered.
pub const MIN_VIEW_SINE: f32 = 0.05;

/// What the field looks like from afar at one texel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Texel {
    /// The blades' mean colour as the eye sees them (linear RGB, lit).
    pub colour: [f32; 3],
    /// How much of the ground the blades hide along the eye's line of sight (0–1); the rest
    /// is the ground between them.
    pub hidden: f32,
}

/// The far field at a texel centred at `pos` whose wind cell blows `wind` (m/s), seen from
/// `eye`, with the trail's crush `(c, direction)` there (`(0, _)`: none). The probes bend
/// without flutter ([`cwd::push_with`]): a texel stands for many blades, each fluttering at
/// its own phase, whose mean is the steady bend.
///
/// Each probe segment counts by the area it shows the eye: `w·pinch(t)·length·|n·v|` for the
/// blade's width `w`, the shader's tip pinch `1 − t^1.4`, and its unit normal `n` against the
/// unit vector `v` toward the eye. The same areas, projected down the line of sight onto the
/// ground (`÷ v_y`) and summed over `density` blades a square metre, are the optical depth
/// `τ` of the field; the ground shows through a share `e^−τ` of it (Beer–Lambert).
pub fn texel(
    g: &GrassParams,
    look: &Look,
    wind: [f32; 2],
    pos: [f32; 2],
    eye: [f32; 3],
    crush: (f32, [f32; 2]),
) -> Texel {
    let (base, tip) = (Vec3::from(look.base), Vec3::from(look.tip));
    let eye = Vec3::from(eye);
    let (mut sum, mut plain, mut weights, mut depth) = (Vec3::ZERO, Vec3::ZERO, 0.0f32, 0.0f32);
    for m in 0..PROBES {
        let b = probe(g, pos, m);
        let line = cwd::centreline_with(&b, wind, g, None, POINTS, crush);
        let (_, side) = cwd::frame(&b);
        let side = Vec3::new(side[0], 0.0, side[1]);
        let laid = lay(
            Vec3::from(line[POINTS].pos) - Vec3::from(line[0].pos),
            b.height,
        );
        for (s, pair) in line.windows(2).enumerate() {
            let (p0, p1) = (Vec3::from(pair[0].pos), Vec3::from(pair[1].pos));
            let t = (s as f32 + 0.5) / POINTS as f32;
            let ahead = p1 - p0;
            let n = side.cross(ahead).normalize_or_zero();
            let view = (eye - 0.5 * (p0 + p1)).normalize_or_zero();
            let facing = n.dot(view);
            let n = if facing < 0.0 { -n } else { n };
            let shade = 0.5 * (pair[0].shade + pair[1].shade);
            let colour = super::light::blade(
                base.lerp(tip, t) * shade,
                n,
                view,
                t,
                laid,
                Vec3::from(look.sun),
                look.ambient,
            );
            let w = (1.0 - t.powf(1.4)) * ahead.length() * facing.abs();
            sum += colour * w;
            plain += colour;
            weights += w;
            depth += w * b.width / view.y.max(MIN_VIEW_SINE);
        }
    }
    let colour = if weights > 1e-12 {
        sum / weights
    } else {
        plain / (PROBES * POINTS) as f32
    };
    Texel {
        colour: colour.to_array(),
        hidden: 1.0 - (-g.density.max(0.0) * depth / PROBES as f32).exp(),
    }
}

/// Draws of the density thinning's hash [`super::cull::thin_draw`] (evenly spread) that
/// [`cover`] averages over.
pub const THIN_DRAWS: u32 = 16;

/// The share (0–1) of the field's blade coverage the renderer draws at `distance` metres
/// from the eye: the distance cull's buckets and density thinning (each blade kept to its
/// reach, fading over the last [`FADE`] of it — averaged over the buckets and over
/// [`THIN_DRAWS`] draws of the thinning's hash — the survivors widened by `1 / kept`,
/// [`super::cull::kept_share`], at most [`MAX_WIDEN`]) and a blade budget's
/// sample (blades kept with `p = min(1, (reach / d)²)` and widened by `1 / p`, at most
/// [`super::sample::MAX_WIDEN`]; `sample_reach` is the sample's threshold, 0 when every blade
/// is drawn).
pub fn cover(distance: f32, cull: &CullParams, sample_reach: f32) -> f32 {
    let d = distance.max(0.0);
    let culled = if cull.distance {
        let n = cull.buckets.max(1);
        let max = cull.max_distance.max(1e-3);
        let thin = cull.thin_distance;
        let draws = if thin > 0.0 { THIN_DRAWS } else { 1 };
        let mut kept = 0.0;
        for b in 0..n {
            let bucket = max * (1.0 - b as f32 / n as f32);
            for j in 0..draws {
                let r = if thin > 0.0 {
                    bucket.min(thin / ((j as f32 + 0.5) / draws as f32).sqrt())
                } else {
                    bucket
                };
                let f = ((r - d) / (FADE * r)).clamp(0.0, 1.0);
                kept += f * f * (3.0 - 2.0 * f);
            }
        }
        let share = super::cull::kept_share(
            d,
            &CullParams {
                max_distance: max,
                ..*cull
            },
        );
        kept / (n * draws) as f32 / share.max(1.0 / MAX_WIDEN)
    } else {
        1.0
    };
    let sampled = if sample_reach > 0.0 && d > 0.0 {
        let q = sample_reach / d;
        let p = (q * q).min(1.0);
        (p * super::sample::MAX_WIDEN).min(1.0)
    } else {
        1.0
    };
    (culled * sampled).clamp(0.0, 1.0)
}

/// Azimuths of the table of the ground beyond the level ([`surround_table`]).
pub const SURROUND_AZIMUTHS: usize = 64;
/// View elevations (their sines, 0 to 1) of the table of the ground beyond the level.
pub const SURROUND_ELEVATIONS: usize = 32;
/// How far (metres) along its view direction the eye of a [`surround`] stands: far enough
/// that the blades' own height does not tilt the view.
pub const SURROUND_EYE: f32 = 1.0e4;

/// The view direction (unit, from the ground toward the eye) at the centre of the table's
/// texel `(i, j)`: azimuth `2π·((i + ½)/SURROUND_AZIMUTHS − ½)` from +x toward +z, elevation
/// sine `j/(SURROUND_ELEVATIONS − 1)`.
pub fn surround_direction(i: usize, j: usize) -> Vec3 {
    let a = std::f32::consts::TAU * ((i as f32 + 0.5) / SURROUND_AZIMUTHS as f32 - 0.5);
    let s = j as f32 / (SURROUND_ELEVATIONS - 1) as f32;
    let c = (1.0 - s * s).max(0.0).sqrt();
    Vec3::new(c * a.cos(), s, c * a.sin())
}

/// Cells on the border of an `nx × ny` grid, each once ([`border_cell`]).
pub fn border_cells(nx: usize, ny: usize) -> usize {
    if nx == 0 || ny == 0 {
        return 0;
    }
    let side = if nx > 1 { 2 } else { 1 };
    nx + if ny > 1 { nx } else { 0 } + ny.saturating_sub(2) * side
}

/// The `k`th border cell `(i, j)` of an `nx × ny` grid: the first row, the last, then the
/// rows between, their first cell and their last (`border_cell` in `grass_far.wgsl`).
pub fn border_cell(k: usize, nx: usize, ny: usize) -> (usize, usize) {
    if k < nx {
        return (k, 0);
    }
    let k = k - nx;
    if ny > 1 && k < nx {
        return (k, ny - 1);
    }
    let k = if ny > 1 { k - nx } else { k };
    let side = if nx > 1 { 2 } else { 1 };
    (if k % side == 0 { 0 } else { nx - 1 }, 1 + k / side)
}

/// The wind the world beyond the level blows with (`edge_wind` in `grass_far.wgsl`): the
/// weather at the level's edge carried on past it — the mean wind of the wind grid's border
/// cells (`nx × ny`, row-major), leaving out those blowing over twice the border's mean
/// speed. An ambient breeze over the level blows over the meadow round it too, but an
/// arrow's jet leaving the level is that level's, not the world's: the meadow's 4× gale
/// crosses its west and east edges at up to 19 m/s, and with it the plain mean was 3.1 m/s
/// where the weather along the edge is 1.4.
pub fn edge_wind(wind: &[[f32; 2]], (nx, ny): (usize, usize)) -> [f32; 2] {
    let n = border_cells(nx, ny);
    if n == 0 || wind.len() < nx * ny {
        return [0.0, 0.0];
    }
    let at = |k: usize| {
        let (i, j) = border_cell(k, nx, ny);
        wind[j * nx + i]
    };
    let speed = |w: [f32; 2]| w[0].hypot(w[1]);
    let mean_speed = (0..n).map(|k| speed(at(k))).sum::<f32>() / n as f32;
    let (mut sum, mut count) = ([0.0f32; 2], 0u32);
    for w in (0..n).map(at) {
        if speed(w) <= 2.0 * mean_speed {
            sum = [sum[0] + w[0], sum[1] + w[1]];
            count += 1;
        }
    }
    if count == 0 {
        return [0.0, 0.0];
    }
    [sum[0] / count as f32, sum[1] / count as f32]
}

/// The ground beyond the level seen along `view` (unit, toward the eye) in the wind `wind`
/// ([`edge_wind`]): the field's look there (a [`texel`] in that wind, the eye
/// [`SURROUND_EYE`] off along `view`) — rgb, and in a the share of the ground it hides. The
/// level sits in a meadow of its own grass, in the same weather, rather than on a plate in
/// the sky; and as the level's own look changes with the view across a picture, so does its
/// surround's, so the two meet with no step at its edge. (In still air round a level in a
/// breeze, the breeze-lit level stood out from the meadow as a pale plate.)
pub fn surround(g: &GrassParams, look: &Look, view: Vec3, wind: [f32; 2]) -> [f32; 4] {
    let eye = view.normalize_or_zero() * SURROUND_EYE;
    let t = texel(g, look, wind, [0.0, 0.0], eye.to_array(), (0.0, [0.0, 0.0]));
    [t.colour[0], t.colour[1], t.colour[2], t.hidden]
}

/// [`surround`] at every texel centre of the table ([`surround_direction`]), row-major by
/// elevation, in the wind `wind`: what the far pass writes for the ground shader to look up.
pub fn surround_table(g: &GrassParams, look: &Look, wind: [f32; 2]) -> Vec<[f32; 4]> {
    (0..SURROUND_ELEVATIONS)
        .flat_map(|j| (0..SURROUND_AZIMUTHS).map(move |i| (i, j)))
        .map(|(i, j)| surround(g, look, surround_direction(i, j), wind))
        .collect()
}

/// The ground shader's look-up of `table` ([`surround_table`]) along `view`: bilinear between
/// texel centres, the azimuth wrapping round, the elevation clamped to the table.
pub fn surround_at(table: &[[f32; 4]], view: Vec3) -> [f32; 4] {
    let (na, ne) = (SURROUND_AZIMUTHS as i64, SURROUND_ELEVATIONS as i64);
    let x = (view.z.atan2(view.x) / std::f32::consts::TAU + 0.5) * na as f32 - 0.5;
    let y = view.y.clamp(0.0, 1.0) * (ne - 1) as f32;
    let (x0, y0) = (x.floor(), y.floor().min((ne - 2) as f32));
    let (fx, fy) = (x - x0, y - y0);
    let i0 = (x0 as i64).rem_euclid(na);
    let i1 = (i0 + 1) % na;
    let j0 = y0 as i64;
    let load = |i: i64, j: i64| Vec4::from(table[(j * na + i) as usize]);
    let row = |j: i64| load(i0, j).lerp(load(i1, j), fx);
    row(j0).lerp(row(j0 + 1), fy).to_array()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The border is walked once, every cell of it, whatever the grid's shape; the weather
    /// beyond the level is the border's breeze, not an arrow's jet crossing it.
    #[test]
    fn the_world_beyond_takes_the_breeze_at_the_edge_not_the_jets() {
        for (nx, ny) in [(1, 1), (5, 1), (1, 4), (2, 2), (7, 5), (240, 160)] {
            let mut seen = std::collections::HashSet::new();
            for k in 0..border_cells(nx, ny) {
                let (i, j) = border_cell(k, nx, ny);
                assert!(i < nx && j < ny, "{nx}x{ny}: {k} -> ({i}, {j})");
                assert!(i == 0 || j == 0 || i == nx - 1 || j == ny - 1);
                assert!(seen.insert((i, j)), "{nx}x{ny}: ({i}, {j}) twice");
            }
            let inner = nx.saturating_sub(2) * ny.saturating_sub(2);
            assert_eq!(seen.len(), nx * ny - inner, "{nx}x{ny}");
        }
        // A 1.5 m/s breeze from the west, a 20 m/s jet through rows 70-89 of 160.
        let (nx, ny) = (240, 160);
        let wind: Vec<[f32; 2]> = (0..nx * ny)
            .map(|k| {
                if (70..90).contains(&(k / nx)) {
                    [20.0, 0.5]
                } else {
                    [1.5, 0.1]
                }
            })
            .collect();
        let w = edge_wind(&wind, (nx, ny));
        assert!(
            (w[0] - 1.5).abs() < 1e-4 && (w[1] - 0.1).abs() < 1e-4,
            "{w:?}"
        );
        // A uniform wind, however strong, is the weather.
        let gale = vec![[0.0, -12.0]; nx * ny];
        assert_eq!(edge_wind(&gale, (nx, ny)), [0.0, -12.0]);
        assert_eq!(edge_wind(&[], (0, 0)), [0.0, 0.0]);
    }

    /// From afar (the meadow's "frame all" eye, 60° up) the field is lighter in any breeze
    /// than in still air, whichever way it blows, and lighter in a gale than in a breeze: the
    /// sheen of blades turning their faces up outweighs eq. 14's dimming from the first
    /// breath. (With the sheen following `√lay`, 1.5–3 m/s read darker than still air and
    /// a breeze-blown level looked calm.)
    #[test]
    fn a_field_brightens_with_the_wind_from_afar() {
        let g = GrassParams {
            height: [0.3, 0.7],
            width: [0.02, 0.05],
            stiffness: [0.5, 1.5],
            ..GrassParams::default()
        };
        let look = Look::new(&g, [0.42, 0.80, 0.43, 0.32]);
        let eye = [60.0, 102.6, 99.2];
        let lum = |wind: [f32; 2]| {
            let c = texel(&g, &look, wind, [60.0, 40.0], eye, (0.0, [0.0, 0.0])).colour;
            0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
        };
        let still = lum([0.0, 0.0]);
        for deg in [0.0f32, 90.0, 180.0, 270.0] {
            let (s, c) = deg.to_radians().sin_cos();
            let at = |speed: f32| lum([speed * c, speed * s]);
            for speed in [1.5, 3.0, 5.0] {
                // Measured: 4–41 % lighter at 1.5 m/s (blowing toward the eye least: it
                // sees the blades' undersides), 21–81 % at 3 m/s.
                let floor = if speed < 2.0 { 1.03 } else { 1.15 };
                assert!(
                    at(speed) > floor * still,
                    "{deg}° {speed} m/s: {} against {still}",
                    at(speed)
                );
            }
            assert!(
                at(12.0) > at(1.5),
                "{deg}°: a gale {} against a breeze {}",
                at(12.0),
                at(1.5)
            );
        }
    }

    /// The ground shader's look-up returns the table at its texel centres, blends between
    /// them, and wraps round the azimuth with no seam behind the eye.
    #[test]
    fn the_surround_table_is_looked_up_as_the_shader_does() {
        let g = GrassParams::default();
        let look = Look::new(&g, [0.4, 0.8, 0.3, 0.3]);
        let table = surround_table(&g, &look, [0.0, 0.0]);
        for (i, j) in [(0, 0), (5, 7), (63, 31), (32, 16)] {
            let got = surround_at(&table, surround_direction(i, j));
            let want = table[j * SURROUND_AZIMUTHS + i];
            for k in 0..4 {
                assert!(
                    (got[k] - want[k]).abs() < 1e-4,
                    "({i}, {j}): {got:?} {want:?}"
                );
            }
        }
        // Half-way between two texel centres in azimuth: their mean.
        let (a, b) = (surround_direction(9, 10), surround_direction(10, 10));
        let mid = surround_at(&table, (a + b).normalize());
        let want =
            0.5 * (table[10 * SURROUND_AZIMUTHS + 9][0] + table[10 * SURROUND_AZIMUTHS + 10][0]);
        assert!((mid[0] - want).abs() < 1e-3, "{} {want}", mid[0]);
        // Either side of the azimuth's wrap (views toward −x): nearly the same.
        let s = 0.4f32;
        let c = (1.0 - s * s).sqrt();
        let side = |a: f32| surround_at(&table, Vec3::new(c * a.cos(), s, c * a.sin()));
        let (l, r) = (
            side(std::f32::consts::PI - 1e-3),
            side(-std::f32::consts::PI + 1e-3),
        );
        for k in 0..4 {
            assert!(
                (l[k] - r[k]).abs() < 1e-3,
                "a seam behind the eye: {l:?} {r:?}"
            );
        }
    }

    /// A texel's share is the density map's mean over it; a bare one hides nothing, the
    /// lower canopy leaves bare earth bare and lets half of a map through, and a sparse field
    /// has little canopy.
    #[test]
    fn the_density_map_thins_the_field_and_its_canopy() {
        let map = crate::doc::DensityMap {
            image: "m.png".into(),
            rect: None,
            pixels: crate::doc::MaskPixels::Loaded(std::sync::Arc::new(crate::doc::MaskImage {
                width: 2,
                height: 1,
                luminance: vec![0, u16::MAX],
            })),
        };
        let bounds = ([0.0, 0.0], [10.0, 10.0]);
        let shares = density_shares(Some(&map), bounds, (4, 1));
        assert_eq!(shares, vec![0.0, 0.0, 1.0, 1.0]);
        assert_eq!(density_shares(None, bounds, (2, 1)), vec![1.0, 1.0]);
        // Straddling the two halves: half.
        assert_eq!(
            density_share(Some(&map), bounds, [[4.0, 0.0], [6.0, 10.0]]),
            0.5
        );
        assert_eq!(thinned(0.8, 0.0), 0.0);
        assert!((thinned(0.8, 1.0) - 0.8).abs() < 1e-6);
        assert!(
            (thinned(0.75, 0.5) - 0.5).abs() < 1e-6,
            "half the depth: 1 - sqrt(0.25)"
        );
        let (lit, look) = (Vec3::splat(0.5), Vec3::new(0.1, 0.4, 0.1));
        assert_eq!(
            ground(lit, look, 0.0, 0.0, 0.0),
            lit,
            "bare: the ground itself"
        );
        let over_map = ground(lit, look, 0.0, 1.0, 1.0);
        let over_soil = ground(lit, look, 0.0, 0.0, 1.0);
        let canopy = |c: Vec3| (c.x - lit.x) / (look.x * UNDERSTOREY_SHADE - lit.x);
        assert!((canopy(over_soil) - UNDERSTOREY).abs() < 1e-5);
        assert!((canopy(over_map) - UNDERSTOREY * MAP_THROUGH_CANOPY).abs() < 1e-5);
        assert_eq!(canopy_share(1.0, 60.0), 1.0);
        assert!((canopy_share(1.0, 2.0) - 0.2).abs() < 1e-6);
        assert_eq!(bare_ground(Vec3::ONE, 0.0), Vec3::from(EARTH));
        assert_eq!(bare_ground(Vec3::ONE, 1.0), Vec3::ONE);
    }
}
