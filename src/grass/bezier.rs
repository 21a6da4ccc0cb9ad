//! Jahrmann & Wimmer's physics blades (seeds 001 and 003; issue 12), on the CPU: the twin the
//! GPU compute pass will be tested against. A blade is a quadratic Bezier curve `v0, v1, v2`
//! (root, guide, tip) of height `h`; each step moves the tip by the forces on it, then validates
//! the state:
//!
//! - gravity `g = gE + gF`, the environmental `gE = (0, −9.81, 0)` and the front gravity
//!   `gF = ¼·|gE|·f` along the blade's facing `f`;
//! - recovery toward the rest tip `iv2 = v0 + h·up`: `r = (iv2 − v2)·stiffness·RECOVERY`
//!   (`RECOVERY` scales the layout's stiffness range to metres: at stiffness 1 gravity alone
//!   bends the tip by about 0.12 m);
//! - wind from the field at the root, `w = WIND·V·θ`, weighted by `θ = fd·fr`: the direction
//!   alignment `fd = 1 − |V̂·(v2 − v0)̂|` (a blade seen edge-on by the wind catches less) and the
//!   height ratio `fr = ((v2 − v0)·up)/h` (a flattened blade catches less);
//! - `v2 += (g + r + w)·Δt`, then validation: `v2` kept above the ground, `v1` placed above the
//!   root from how far the tip leans, and the curve scaled about the root to the blade's length
//!   (measured by [`LENGTH_CHORDS`] chords).
//!
//! Frame-rate independence: [`State::advance`] integrates in fixed steps of [`STEP`] seconds
//! and carries the remainder, so 30 and 144 frames a second make the same steps.

use super::Blade;
use super::trail::Sphere;

/// The fixed integration step, seconds.
pub const STEP: f32 = 1.0 / 240.0;
/// Metres of recovery force per metre of displacement, per unit of stiffness.
pub const RECOVERY: f32 = 80.0;
/// Wind force per m/s of wind.
pub const WIND: f32 = 3.2;
const GRAVITY: f32 = 9.81;
/// Chords the length correction measures the curve with.
pub const LENGTH_CHORDS: usize = 8;

type V3 = [f32; 3];

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn mul(a: V3, k: f32) -> V3 {
    [a[0] * k, a[1] * k, a[2] * k]
}
fn dot(a: V3, b: V3) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn len(a: V3) -> f32 {
    dot(a, a).sqrt()
}

const UP: V3 = [0.0, 1.0, 0.0];

/// What pushes a blade besides the wind: the sphere it collides with (Jahrmann's collision
/// against the tip and the curve's middle) and the trail's crush at its root with the direction
/// crushed blades lie in (`trail::Trail::crush_at`), which moves the rest tip toward the
/// ground so the recovery force brings the blade back as the trail fades.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Push {
    pub sphere: Option<Sphere>,
    pub crush: f32,
    pub dir: [f32; 2],
}

/// Where a fully crushed blade's tip rests, as fractions of its height: along the crush
/// direction, and up.
pub const CRUSHED: [f32; 2] = [0.95, 0.3];

/// A blade's simulated state: root, guide and tip (world metres, y up), and the time not yet
/// integrated (less than one [`STEP`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    pub v0: V3,
    pub v1: V3,
    pub v2: V3,
    pub carry: f32,
}

impl State {
    /// Upright: guide and tip at the blade's height above the root.
    pub fn rest(blade: &Blade) -> Self {
        let v0 = [blade.pos[0], 0.0, blade.pos[1]];
        let top = add(v0, mul(UP, blade.height));
        Self {
            v0,
            v1: top,
            v2: top,
            carry: 0.0,
        }
    }

    /// Advances by `dt` seconds of wind `wind` (world x, z; m/s) at the root.
    pub fn advance(&mut self, blade: &Blade, wind: [f32; 2], dt: f32) {
        self.advance_pushed(blade, wind, Push::default(), dt);
    }

    /// [`Self::advance`] with a sphere and a trail pushing the blade.
    pub fn advance_pushed(&mut self, blade: &Blade, wind: [f32; 2], push: Push, dt: f32) {
        // As the GPU pass counts them, so both make the same steps.
        self.carry += dt;
        let steps = (self.carry / STEP).floor();
        self.carry -= steps * STEP;
        for _ in 0..steps as u32 {
            self.step_pushed(blade, wind, push, STEP);
        }
    }

    /// One integration step of `dt` seconds and the state validation.
    pub fn step(&mut self, blade: &Blade, wind: [f32; 2], dt: f32) {
        self.step_pushed(blade, wind, Push::default(), dt);
    }

    /// [`Self::step`] with a sphere and a trail pushing the blade.
    pub fn step_pushed(&mut self, blade: &Blade, wind: [f32; 2], push: Push, dt: f32) {
        let h = blade.height;
        let (s, c) = blade.facing.sin_cos();
        let front = [c, 0.0, s];
        let ge = [0.0, -GRAVITY, 0.0];
        let g = add(ge, mul(front, 0.25 * GRAVITY));
        let upright = add(self.v0, mul(UP, h));
        let crushed = add(
            self.v0,
            [
                push.dir[0] * CRUSHED[0] * h,
                CRUSHED[1] * h,
                push.dir[1] * CRUSHED[0] * h,
            ],
        );
        let iv2 = add(mul(upright, 1.0 - push.crush), mul(crushed, push.crush));
        let r = mul(sub(iv2, self.v2), blade.stiffness * RECOVERY);
        let v = [wind[0], 0.0, wind[1]];
        let speed = len(v);
        let lean = sub(self.v2, self.v0);
        let w = if speed > 0.0 && len(lean) > 0.0 {
            let fd = 1.0 - (dot(mul(v, 1.0 / speed), mul(lean, 1.0 / len(lean)))).abs();
            let fr = dot(lean, UP) / h;
            mul(v, WIND * fd * fr)
        } else {
            [0.0; 3]
        };
        self.v2 = add(self.v2, mul(add(add(g, r), w), dt));
        if let Some(s) = push.sphere {
            self.collide(s);
        }
        self.validate(h);
    }

    /// Jahrmann's collision: the tip and the curve's middle pushed out of the sphere, the
    /// middle's push applied to the tip four times over (the middle moves a quarter as far).
    fn collide(&mut self, s: Sphere) {
        let out = |p: V3| {
            let d = sub(p, s.centre);
            let l = len(d);
            if l < s.radius && l > 1e-6 {
                mul(d, (s.radius - l) / l)
            } else {
                [0.0; 3]
            }
        };
        let mid = add(
            add(mul(self.v0, 0.25), mul(self.v1, 0.5)),
            mul(self.v2, 0.25),
        );
        let d = add(out(self.v2), mul(out(mid), 4.0));
        self.v2 = add(self.v2, d);
    }

    /// Jahrmann's state validation: tip above the ground, guide from the tip's lean, length
    /// restored.
    fn validate(&mut self, h: f32) {
        let up_part = dot(UP, sub(self.v2, self.v0));
        self.v2 = sub(self.v2, mul(UP, up_part.min(0.0)));
        let d = sub(self.v2, self.v0);
        let lproj = len(sub(d, mul(UP, dot(d, UP))));
        self.v1 = add(
            self.v0,
            mul(UP, h * (1.0 - lproj / h).max(0.05 * (lproj / h).max(1.0))),
        );
        // Measured by chords: Jahrmann's estimate (2·|v2 − v0| + |v1 − v0| + |v2 − v1|)/3 is up
        // to 4 % off for a strongly bent blade; scaling every point about the root scales the
        // curve's length exactly.
        let l = self.length(LENGTH_CHORDS);
        if l > 0.0 {
            let k = h / l;
            let v1 = add(self.v0, mul(sub(self.v1, self.v0), k));
            self.v2 = add(v1, mul(sub(self.v2, self.v1), k));
            self.v1 = v1;
        }
    }

    /// The point of the curve at `t` (0 root, 1 tip).
    pub fn point(&self, t: f32) -> V3 {
        let a = (1.0 - t) * (1.0 - t);
        let b = 2.0 * (1.0 - t) * t;
        let c = t * t;
        add(add(mul(self.v0, a), mul(self.v1, b)), mul(self.v2, c))
    }

    /// The curve's length, from `n` chords.
    pub fn length(&self, n: usize) -> f32 {
        (1..=n)
            .map(|k| {
                len(sub(
                    self.point(k as f32 / n as f32),
                    self.point((k - 1) as f32 / n as f32),
                ))
            })
            .sum()
    }
}
