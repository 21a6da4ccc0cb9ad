//! The CWD-Sim quadratic blade deformation (paper eqs. 11–14), as
//! `docs/GRASS.md` reads it; the CPU twin of the grass vertex shader.
//!
//! In the blade's frame (`y` up, `z` along its facing, `x` to its side), a point at height `y`
//! of the straight blade goes through:
//!
//! 1. gravity bend (eq. 11): `P' = (0, y − k1·y², k2·y²)`;
//! 2. wind translation (eq. 12): `T = F·P'y²·(Vx, −|V|, Vz)`, with `V` the blade's wind cell's
//!    velocity (eq. 1 groups blades by cell) in the blade's frame. The paper writes `−Vy` for
//!    the last component because its texture's `y` runs against world `z`; ours runs along it,
//!    so the tip moves downwind. We write it `T = h·B·t²·(v̂x, −1, v̂z)` with `t = P'y/h` and
//!    `v̂ = V/|V|`: the same quadratic in height, normalised by the blade's height `h` so that
//!    blades of every height bend alike (the paper's F per metre becomes a bend `B` per blade),
//!    and `B = B_max·tanh((1 − λ)·F·|V| / B_max)` with `F = WIND_RESPONSE / stiffness` — eq. 13's
//!    `(1 − λ)` folded in (λ → 1 stiff, λ → 0 fully driven);
//! 3. eq. 13 read as `P'' = M(P' + T)`, then the whole curve scaled about the root so that its
//!    length is the blade's height: a bent blade does not stretch;
//! 4. self-shadow (eq. 14): `shade = clamp(P''y − c1·|V|ₛ + c2, m_min, m_max)`.
//!
//! **The paper's open problem** — in strong wind its blades lie flat and turn black, and capping
//! the wind makes them rigid — is solved by: a bend `B` that grows linearly in light wind and
//! levels off smoothly at [`BEND_MAX`] (the tip stays above a quarter of the blade's height);
//! the length renormalisation (full length, no flattening by squashing); eq. 14 fed the
//! saturated speed `|V|ₛ = S·tanh(|V|/S)` ([`SATURATION`]), so a gale dims the grass by a bounded
//! amount (`c1·S`) rather than to `m_min`; and a per-blade flutter on top of the saturated bend,
//! growing with it, each blade at its own phase ([`FLUTTER_SPREAD`]), so strong wind stays
//! alive instead of freezing blades at the cap. (Gusts that roll across the field are the
//! wind's own: the solver's eddies, pulses and turbulence, carried downwind.)

use super::Blade;
use crate::doc::GrassParams;

/// `F` of eq. 12 for a blade of stiffness 1: bend per m/s (tip displacement over height).
pub const WIND_RESPONSE: f32 = 0.09;
/// The bend `B` the wind's push levels off at.
pub const BEND_MAX: f32 = 0.55;
/// `S`: wind speed (m/s) around which the self-shadow's wind term (eq. 14) saturates.
pub const SATURATION: f32 = 3.0;
/// Flutter: relative amplitude at full saturation, and its base frequency (Hz).
pub const FLUTTER: f32 = 0.15;
pub const FLUTTER_HZ: f32 = 1.6;
/// Radians of flutter phase per unit of a blade's variation (`[-1, 1]`): about six turns
/// across its range, so neighbouring blades flutter independently. (The phase was a plane
/// wave over the ground, `0.9x + 1.3z`: stripes 4 m apart running north-west whatever the
/// wind, read from afar as bands across every gale.)
pub const FLUTTER_SPREAD: f32 = 40.0;
/// Segments of the arc-length estimate behind the length renormalisation (the shader's too).
pub const LENGTH_SEGMENTS: usize = 16;

/// `S·tanh(|V|/S)`: the wind speed the blade responds to.
pub fn saturate(speed: f32) -> f32 {
    SATURATION * (speed / SATURATION).tanh()
}

/// The blade's frame: forward (its facing) and side, as world `(x, z)` unit vectors.
pub fn frame(blade: &Blade) -> ([f32; 2], [f32; 2]) {
    let (s, c) = blade.facing.sin_cos();
    ([c, s], [-s, c])
}

/// The wind's push on a blade at `time`, in its own frame: the bend `B` (eq. 12, saturated,
/// with its flutter) and the unit direction `(side, forward)` it pushes toward.
pub fn push(blade: &Blade, g: &GrassParams, wind: [f32; 2], time: f32) -> (f32, [f32; 2]) {
    push_with(blade, g, wind, Some(time))
}

/// [`push`] at `time`, or with no flutter (`None`): the mean over its phases, what a patch
/// of many blades shows from afar (the far field's probes).
pub fn push_with(
    blade: &Blade,
    g: &GrassParams,
    wind: [f32; 2],
    time: Option<f32>,
) -> (f32, [f32; 2]) {
    let speed = wind[0].hypot(wind[1]);
    if speed <= 0.0 {
        return (0.0, [0.0, 0.0]);
    }
    let f = WIND_RESPONSE / blade.stiffness.max(1e-3);
    let bend = BEND_MAX * ((1.0 - g.lambda) * f * speed / BEND_MAX).tanh();
    let flutter = time.map_or(1.0, |time| {
        let phase = blade.variation * FLUTTER_SPREAD;
        let hz = FLUTTER_HZ * (1.0 + 0.25 * blade.variation);
        1.0 + FLUTTER * (bend / BEND_MAX) * (std::f32::consts::TAU * hz * time + phase).sin()
    });
    let (fwd, side) = frame(blade);
    let w = [wind[0] / speed, wind[1] / speed];
    (
        bend * flutter,
        [
            w[0] * side[0] + w[1] * side[1],
            w[0] * fwd[0] + w[1] * fwd[1],
        ],
    )
}

/// The bend a fully crushed blade gets (the sphere's trail): it lies nearly flat.
pub const CRUSH_BEND: f32 = 0.92;

/// The wind's push blended with the trail's crush `c` toward world direction `toward`: at
/// `c = 1` the blade lies toward `toward` with a bend of [`CRUSH_BEND`], whatever the wind.
pub fn crushed(
    blade: &Blade,
    (bend, dir): (f32, [f32; 2]),
    c: f32,
    toward: [f32; 2],
) -> (f32, [f32; 2]) {
    if c <= 0.0 {
        return (bend, dir);
    }
    let (fwd, side) = frame(blade);
    let t = [
        toward[0] * side[0] + toward[1] * side[1],
        toward[0] * fwd[0] + toward[1] * fwd[1],
    ];
    let p = [
        (1.0 - c) * bend * dir[0] + c * CRUSH_BEND * t[0],
        (1.0 - c) * bend * dir[1] + c * CRUSH_BEND * t[1],
    ];
    let l = p[0].hypot(p[1]);
    if l > 0.0 {
        (l, [p[0] / l, p[1] / l])
    } else {
        (0.0, [0.0, 0.0])
    }
}

/// The blade-frame point `(x, y, z)` at `t` (0 root, 1 tip) before the length is restored.
fn bent(blade: &Blade, g: &GrassParams, (bend, dir): (f32, [f32; 2]), t: f32) -> [f32; 3] {
    let h = blade.height;
    let y = t * h;
    let p = [0.0, y - g.k1 * y * y, g.k2 * y * y];
    let r = p[1] / h;
    let s = h * bend * r * r;
    [p[0] + s * dir[0], (p[1] - s).max(0.0), p[2] + s * dir[1]]
}

/// Length of the bent centreline, from [`LENGTH_SEGMENTS`] chords.
fn bent_length(blade: &Blade, g: &GrassParams, push: (f32, [f32; 2])) -> f32 {
    let mut len = 0.0;
    let mut prev = [0.0; 3];
    for k in 1..=LENGTH_SEGMENTS {
        let q = bent(blade, g, push, k as f32 / LENGTH_SEGMENTS as f32);
        len +=
            ((q[0] - prev[0]).powi(2) + (q[1] - prev[1]).powi(2) + (q[2] - prev[2]).powi(2)).sqrt();
        prev = q;
    }
    len
}

/// A point of the deformed blade: world position (x, y up, z) and its shade (eq. 14).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    pub pos: [f32; 3],
    pub shade: f32,
}

/// The deformed centreline of `blade` in world `wind` (its cell's velocity, m/s) at `time`,
/// at `segments + 1` evenly spaced heights from root to tip.
pub fn centreline(
    blade: &Blade,
    wind: [f32; 2],
    g: &GrassParams,
    time: f32,
    segments: usize,
) -> Vec<Point> {
    centreline_crushed(blade, wind, g, time, segments, (0.0, [0.0, 0.0]))
}

/// [`centreline`] with the trail's crush `(c, direction)` at the blade's root ([`crushed`]).
pub fn centreline_crushed(
    blade: &Blade,
    wind: [f32; 2],
    g: &GrassParams,
    time: f32,
    segments: usize,
    crush: (f32, [f32; 2]),
) -> Vec<Point> {
    centreline_with(blade, wind, g, Some(time), segments, crush)
}

/// [`centreline_crushed`] at `time`, or with no flutter (`None`, [`push_with`]).
pub fn centreline_with(
    blade: &Blade,
    wind: [f32; 2],
    g: &GrassParams,
    time: Option<f32>,
    segments: usize,
    (c, toward): (f32, [f32; 2]),
) -> Vec<Point> {
    let v = crushed(blade, push_with(blade, g, wind, time), c, toward);
    let scale = blade.height / bent_length(blade, g, v).max(1e-9);
    let (fwd, side) = frame(blade);
    let dim = g.shadow.c1 * saturate(wind[0].hypot(wind[1]));
    (0..=segments)
        .map(|k| {
            let q = bent(blade, g, v, k as f32 / segments as f32);
            let q = [q[0] * scale, q[1] * scale, q[2] * scale];
            Point {
                pos: [
                    blade.pos[0] + q[0] * side[0] + q[2] * fwd[0],
                    q[1],
                    blade.pos[1] + q[0] * side[1] + q[2] * fwd[1],
                ],
                shade: (q[1] - dim + g.shadow.c2).clamp(g.shadow.m_min, g.shadow.m_max),
            }
        })
        .collect()
}
