//! The light the grass is drawn in: the sun, the sky, a view-dependent sheen on the blades, the
//! shade toward their roots and the haze of the air — the CPU twin of `grass_common.wgsl`'s
//! `sky_colour`, `haze` and `blade_light` (the blades, the far field and the sky pass all
//! light with them; `tests/sim/gpu/far.rs` compares the far field, which uses the same
//! function the blade shader does, texel for texel).
//!
//! Why a sheen: a blade is a thin waxy leaf. Upright, its faces look sideways and mirror the
//! ground and the horizon; bent away from the eye, its upper face turns toward the sky and
//! mirrors it, and near grazing it mirrors most of what falls on it (Fresnel). That is how a
//! field shows the wind from afar — bands of light where gusts lay it over — and it is what
//! the diffuse-only light lacked: a calm meadow and one in a gale were the same picture.

use glam::Vec3;

/// The sky straight up, and at the horizon (linear RGB). The horizon colour is also the
/// haze's: far ground fades into the sky where they meet.
pub const SKY_ZENITH: [f32; 3] = [0.20, 0.38, 0.72];
pub const SKY_HORIZON: [f32; 3] = [0.62, 0.70, 0.78];
/// How much the sky brightens toward the sun, and how tight that glow is.
pub const SUN_GLOW: f32 = 0.35;
pub const SUN_GLOW_POWER: f32 = 24.0;
/// What a blade mirrors below the horizon: the ground's light (linear, grey-green).
pub const GROUND_MIRROR: [f32; 3] = [0.05, 0.06, 0.035];
/// The blade's cuticle: reflectance seen face-on (Schlick's `F0`), how much of the mirrored
/// light a blade keeps (its surface is rough and not a mirror everywhere), and the sun's
/// highlight sharpness (a Blinn–Phong power) and strength.
pub const SHEEN_F0: f32 = 0.2;
/// The reflectance at grazing (Schlick's `F90`): under 1 for a rough face, whose grazing
/// reflection is shadowed and scattered by its own roughness (the rough-surface form of
/// Schlick's approximation). With a mirror's 1, a field laid over by a breeze and seen
/// along the ground turned white.
pub const SHEEN_F90: f32 = 0.5;
pub const SHEEN: f32 = 1.3;
/// The share of the sheen an upright blade keeps: a bent blade's face is stretched and
/// smoothed toward the sky, an upright one's is the rougher edge-lit surface.
pub const SHEEN_UPRIGHT: f32 = 0.15;

/// How much of the mirrored light's colour a blade's sheen loses to its waxy, scattering
/// surface (0: a mirror's colour, 1: grey): a field shines silver, not sky-blue.
pub const SHEEN_GREY: f32 = 0.8;

/// The lay a blade has at rest, under its own weight (eq. 11's droop: the meadow's blades
/// reach 3–7 % of their length): the sheen answers to the lay past it, the wind's.
pub const LAY_REST: f32 = 0.07;
/// The lay (past rest) over which a blade's glossy face turns most of the way up
/// (`1 − e^(−past/SHEEN_TURN)`): a blade starting to bend twists to meet the wind and turns
/// its face to the sky at once, then lies down slowly.
pub const SHEEN_TURN: f32 = 0.07;

/// How far a blade laid over by `lay` has turned its glossy face up, 0 at rest to 1: it
/// tilts the face toward the sky and weighs the sheen. It turns at once as a blade starts to
/// bend, so that a breeze shows from afar as a lighter, silvery field; past ~3 m/s the
/// sheen is nearly all there, and a gale lightens the field further by laying the blades'
/// lit length over the canopy. (It followed `lay` itself, and the sheen `√lay`: a blade in
/// a light breeze still mirrored the ground seen from above while eq. 14 already dimmed it,
/// and a breeze-blown field read *darker* than a calm one until ~4 m/s — a gale's level
/// looked like calm air.)
pub fn sheen_turn(lay: f32) -> f32 {
    let past = ((lay - LAY_REST) / (1.0 - LAY_REST)).max(0.0);
    1.0 - (-past / SHEEN_TURN).exp()
}

/// The light a blade's face mirrors in direction `r`, greyed by [`SHEEN_GREY`].
fn sheen_colour(r: Vec3, sun: Vec3) -> Vec3 {
    let c = mirrored(r, sun);
    c.lerp(
        Vec3::splat(c.dot(Vec3::new(0.2126, 0.7152, 0.0722))),
        SHEEN_GREY,
    )
}
pub const SPECULAR_POWER: f32 = 20.0;
pub const SPECULAR: f32 = 0.5;
/// Light through a blade: its share of the sun on the far side, and how much more of it
/// shows looking toward the sun (forward scattering).
pub const TRANSLUCENCY: f32 = 0.35;
pub const FORWARD_SCATTER: f32 = 1.5;
/// The sky a blade's root still sees among its neighbours (its tip sees all of it): the
/// occlusion toward the root, on the sky's light.
pub const SKY_AT_ROOT: f32 = 0.45;
/// The ground haze: its density at the ground (per metre of view ray: `1/e` over 300 m, a hazy summer day)
/// and the height over which it thins by `1/e`. Thick near the ground and thin above, it
/// veils the far ground of a low view — so the ground beyond the level melts into the sky
/// at the horizon — and barely touches the level seen from above.
pub const HAZE_DENSITY: f32 = 1.0 / 300.0;
pub const HAZE_HEIGHT: f32 = 20.0;
/// The sky's radiance in direction `dir` (unit, y up) with the sun toward `sun` (unit): from
/// the horizon's colour to the zenith's, brighter around the sun; below the horizon, the
/// horizon's colour (the haze hides the ground there).
pub fn sky(dir: Vec3, sun: Vec3) -> Vec3 {
    let up = dir.y.max(0.0);
    let base = Vec3::from(SKY_HORIZON).lerp(Vec3::from(SKY_ZENITH), up.sqrt());
    let glow = SUN_GLOW * dir.dot(sun).max(0.0).powf(SUN_GLOW_POWER);
    base + Vec3::splat(glow)
}

/// Half the band of reflected directions (sine of their elevation) over which a blade's
/// rough face blurs the ground below the horizon into the sky above it.
pub const MIRROR_BLUR: f32 = 0.15;

/// What a blade mirrors in direction `r`: the sky above the horizon, the ground below it,
/// blurred into each other across [`MIRROR_BLUR`] of the horizon. (A sharp horizon made the
/// sheen jump where a face's reflection crossed it: from afar, a straight seam across a
/// breeze-blown field where the view's azimuth passed that point.)
pub fn mirrored(r: Vec3, sun: Vec3) -> Vec3 {
    let x = ((r.y + MIRROR_BLUR) / (2.0 * MIRROR_BLUR)).clamp(0.0, 1.0);
    let k = x * x * (3.0 - 2.0 * x);
    Vec3::from(GROUND_MIRROR).lerp(sky(r, sun), k)
}

/// The share of the horizon's colour over a surface at `point` seen from `eye` (metres, y
/// up): the ground haze's optical depth along the ray, `σ·d·H·(e^(−y_p/H) − e^(−y_e/H))/(y_e −
/// y_p)` (density `σ·e^(−y/H)` integrated along the straight ray, [`HAZE_DENSITY`],
/// [`HAZE_HEIGHT`]), and toward the far plane (`fade`: `[start, end]` metres) all of it, so
/// the ground meets the sky without an edge.
pub fn haze(eye: Vec3, point: Vec3, fade: [f32; 2]) -> f32 {
    let d = eye.distance(point);
    let (ye, yp) = (eye.y / HAZE_HEIGHT, point.y / HAZE_HEIGHT);
    let mean = if (ye - yp).abs() > 1e-3 {
        ((-yp).exp() - (-ye).exp()) / (ye - yp)
    } else {
        (-0.5 * (ye + yp)).exp()
    };
    let air = 1.0 - (-HAZE_DENSITY * d * mean).exp();
    let x = ((d - fade[0]) / (fade[1] - fade[0]).max(1e-3)).clamp(0.0, 1.0);
    air.max(x * x * (3.0 - 2.0 * x))
}

/// The light on a blade (linear RGB) of colour `albedo` (eq. 14's shade applied), unit normal
/// `n` turned toward the eye, unit vector `view` toward the eye, at height fraction `t` (0
/// root, 1 tip), under `sun` (unit) with the sky's share `ambient`:
///
/// - the sky, `ambient·(0.6 + 0.4 n_y)`, dimmed toward the root ([`SKY_AT_ROOT`]);
/// - the sun on the lit face, and [`TRANSLUCENCY`] of it through the blade, more so looking
///   toward the sun;
/// - the sheen, not tinted by the blade: the sky (or ground) mirrored by the blade's glossy
///   face, times Schlick's Fresnel, plus the sun's highlight, dimmed toward the root like the
///   sky. The mirroring face is the blade's own, turned up toward the sky by [`sheen_turn`]
///   of how far the blade lies over, `lay` (its tip's reach along the ground over its
///   length, 0–1), and the sheen weighs from [`SHEEN_UPRIGHT`] to all of it by the same turn:
///   a blade bending in the wind twists to meet it face-on and turns a face up, whichever way
///   it leans from the eye, so a field laid over by a gust shines from every side — the
///   travelling bands of light that show wind across a whole level.
pub fn blade(albedo: Vec3, n: Vec3, view: Vec3, t: f32, lay: f32, sun: Vec3, ambient: f32) -> Vec3 {
    let t = t.clamp(0.0, 1.0);
    let open = SKY_AT_ROOT + (1.0 - SKY_AT_ROOT) * t;
    let d = n.dot(sun);
    let toward_sun = (-view).dot(sun).max(0.0);
    let through = TRANSLUCENCY * (-d).max(0.0) * (1.0 + FORWARD_SCATTER * toward_sun.powi(4));
    let diffuse = ambient * (0.6 + 0.4 * n.y) * open + (1.0 - ambient) * (d.max(0.0) + through);
    let turn = sheen_turn(lay);
    let m = n.lerp(Vec3::Y, turn).normalize_or_zero();
    let nv = m.dot(view).clamp(0.0, 1.0);
    let fresnel = SHEEN_F0 + (SHEEN_F90 - SHEEN_F0) * (1.0 - nv).powi(5);
    let r = 2.0 * m.dot(view) * m - view;
    let h = (sun + view).normalize_or_zero();
    let highlight = if m.dot(sun) > 0.0 {
        SPECULAR * (1.0 - ambient) * m.dot(h).max(0.0).powf(SPECULAR_POWER)
    } else {
        0.0
    };
    let weight = SHEEN_UPRIGHT + (1.0 - SHEEN_UPRIGHT) * turn;
    let sheen = SHEEN * fresnel * open * weight * (sheen_colour(r, sun) + Vec3::splat(highlight));
    albedo * diffuse + sheen
}

#[cfg(test)]
mod tests {
    use super::*;

    const SUN: Vec3 = Vec3::new(0.42, 0.80, 0.43);

    fn sun() -> Vec3 {
        SUN.normalize()
    }

    /// A blade laid over away from the eye mirrors the sky and is brighter than an upright
    /// one seen from the same place: the sheen that shows the wind.
    #[test]
    fn a_blade_bent_away_from_the_eye_shines() {
        let albedo = Vec3::new(0.1, 0.25, 0.05);
        // The eye 38° up, looking along +z; blades face along z.
        let view = Vec3::new(0.0, 38f32.to_radians().sin(), -38f32.to_radians().cos());
        let upright = Vec3::new(0.0, 0.0, -1.0);
        let bent = Vec3::new(0.0, 0.6f32.sin(), -0.6f32.cos());
        let a = blade(albedo, upright, view, 0.7, 0.0, sun(), 0.32);
        let b = blade(albedo, bent, view, 0.7, 0.6f32.sin(), sun(), 0.32);
        assert!(b.length() > 1.3 * a.length(), "{a} → {b}");
        // Laid over across the line of sight (its face still looking sideways), it shines too.
        let side = Vec3::new(-1.0, 0.0, 0.0);
        let c = blade(albedo, side, view, 0.7, 0.6f32.sin(), sun(), 0.32);
        let d = blade(albedo, side, view, 0.7, 0.0, sun(), 0.32);
        assert!(c.length() > 1.3 * d.length(), "{d} → {c}");
    }

    /// The face turns up only past a blade's resting droop, at once as the wind starts to
    /// lay it over and never back; and what it mirrors has no step at the horizon.
    #[test]
    fn the_sheen_turns_with_the_wind_and_has_no_edge() {
        assert_eq!(sheen_turn(0.0), 0.0);
        assert_eq!(sheen_turn(LAY_REST), 0.0);
        assert!(
            sheen_turn(LAY_REST + 0.1) > 0.45,
            "{}",
            sheen_turn(LAY_REST + 0.1)
        );
        assert!(sheen_turn(1.0) > 0.99);
        let mut last = 0.0;
        for k in 0..=100 {
            let t = sheen_turn(k as f32 / 100.0);
            assert!(t >= last && t <= 1.0, "{k}: {t}");
            last = t;
        }
        let s = sun();
        let at = |y: f32| mirrored(Vec3::new((1.0 - y * y).sqrt(), y, 0.0), s);
        for k in -40..40 {
            let (a, b) = (at(k as f32 / 200.0), at((k + 1) as f32 / 200.0));
            assert!(
                (a - b).abs().max_element() < 0.03,
                "a step at {}: {a} {b}",
                k as f32 / 200.0
            );
        }
        assert_eq!(at(-0.5), Vec3::from(GROUND_MIRROR));
        assert_eq!(at(0.5), sky(Vec3::new(0.75f32.sqrt(), 0.5, 0.0), s));
    }

    #[test]
    fn the_root_is_darker_than_the_tip_and_haze_reaches_the_horizon() {
        let albedo = Vec3::new(0.1, 0.25, 0.05);
        let view = Vec3::new(0.0, 0.6, -0.8);
        let n = Vec3::new(0.0, 0.0, -1.0);
        let at = |t| blade(albedo, n, view, t, 0.0, sun(), 0.32).y;
        assert!(at(0.0) < at(1.0));
        let fade = [5e3, 1e4];
        // From 150 m up, a level 250 m off is hardly veiled; from 2 m up, ground 2 km off is.
        let high = Vec3::new(0.0, 150.0, 0.0);
        assert!(haze(high, Vec3::new(200.0, 0.0, 0.0), fade) < 0.15);
        let low = Vec3::new(0.0, 2.0, 0.0);
        assert!(haze(low, Vec3::new(2000.0, 0.0, 0.0), fade) > 0.9);
        assert!(haze(low, Vec3::new(30.0, 0.0, 0.0), fade) < 0.1);
        assert_eq!(haze(low, Vec3::new(1e4, 0.0, 0.0), fade), 1.0);
        let up = sky(Vec3::Y, sun());
        let flat = sky(Vec3::new(1.0, 0.0, 0.0), sun());
        assert!(
            up.z / up.x > flat.z / flat.x,
            "the zenith is bluer: {up} {flat}"
        );
    }
}
