//! The trail a pushing sphere leaves in the grass (seed 004's footpath texture, issue 12), on
//! the CPU — the twin of `shaders/grass_trail.wgsl`. A world-space grid over the layout's
//! rectangle holds each texel's remaining life in `[0, 1]`: every frame it falls by
//! `dt / lifetime`, then the sphere's footprint stamps `1 − (d/r)²` where that is higher. The
//! grass reads it at a blade's root as a crush `c = smoothstep(life)` (so blades recover with
//! an ease-out, no jitter) and a direction down its gradient (away from the path's middle):
//! the CWD model bends crushed blades that way, the Bezier model moves its rest tip there and
//! lets the recovery force bring it back as the trail fades.

/// The sphere the user pushes over the ground: centre (world x, y, z) and radius, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    pub centre: [f32; 3],
    pub radius: f32,
}

/// Texels along the trail grid's longer side at most, and the size it aims for (metres).
pub const MAX_TEXELS: u32 = 512;
pub const TEXEL: f32 = 0.08;

/// The trail grid over a world rectangle.
#[derive(Debug, Clone, PartialEq)]
pub struct Trail {
    pub origin: [f32; 2],
    pub cell: [f32; 2],
    pub nx: u32,
    pub ny: u32,
    /// Remaining life per texel, row-major.
    pub life: Vec<f32>,
}

/// The trail grid's size for a world `min..max`: [`TEXEL`]-metre texels, at most
/// [`MAX_TEXELS`] along a side.
pub fn grid(min: [f32; 2], max: [f32; 2]) -> (u32, u32) {
    let w = (max[0] - min[0]).max(1e-3);
    let h = (max[1] - min[1]).max(1e-3);
    let scale = (w.max(h) / TEXEL).min(MAX_TEXELS as f32) / w.max(h);
    (
        ((w * scale).ceil() as u32).clamp(2, MAX_TEXELS),
        ((h * scale).ceil() as u32).clamp(2, MAX_TEXELS),
    )
}

fn smooth(v: f32) -> f32 {
    let v = v.clamp(0.0, 1.0);
    v * v * (3.0 - 2.0 * v)
}

impl Trail {
    /// A fresh (untrodden) trail over `min..max`.
    pub fn new(min: [f32; 2], max: [f32; 2]) -> Self {
        let (nx, ny) = grid(min, max);
        Self {
            origin: min,
            cell: [(max[0] - min[0]) / nx as f32, (max[1] - min[1]) / ny as f32],
            nx,
            ny,
            life: vec![0.0; (nx * ny) as usize],
        }
    }

    /// One frame: `dt` seconds of fading (gone after `lifetime` seconds), then `sphere`'s
    /// footprint.
    pub fn step(&mut self, sphere: Option<Sphere>, dt: f32, lifetime: f32) {
        let fall = if lifetime > 0.0 { dt / lifetime } else { 1.0 };
        for j in 0..self.ny {
            for i in 0..self.nx {
                let k = (j * self.nx + i) as usize;
                let mut v = (self.life[k] - fall).max(0.0);
                if let Some(s) = sphere {
                    v = v.max(stamp(s, self.centre(i, j)));
                }
                self.life[k] = v;
            }
        }
    }

    /// The centre of texel `(i, j)`, world `(x, z)`.
    pub fn centre(&self, i: u32, j: u32) -> [f32; 2] {
        [
            self.origin[0] + (i as f32 + 0.5) * self.cell[0],
            self.origin[1] + (j as f32 + 0.5) * self.cell[1],
        ]
    }

    /// The life at `p` (world `(x, z)`), bilinear between texel centres, clamped at the edges.
    pub fn life_at(&self, p: [f32; 2]) -> f32 {
        let gx = (p[0] - self.origin[0]) / self.cell[0] - 0.5;
        let gy = (p[1] - self.origin[1]) / self.cell[1] - 0.5;
        let (x0, y0) = (gx.floor(), gy.floor());
        let (fx, fy) = (gx - x0, gy - y0);
        let at = |i: f32, j: f32| {
            let i = (i as i64).clamp(0, self.nx as i64 - 1) as u32;
            let j = (j as i64).clamp(0, self.ny as i64 - 1) as u32;
            self.life[(j * self.nx + i) as usize]
        };
        let a = at(x0, y0) * (1.0 - fx) + at(x0 + 1.0, y0) * fx;
        let b = at(x0, y0 + 1.0) * (1.0 - fx) + at(x0 + 1.0, y0 + 1.0) * fx;
        a * (1.0 - fy) + b * fy
    }

    /// The crush at `p` and the direction (unit, world `(x, z)`) crushed blades lie in: down
    /// the trail's gradient, or `fallback` where it is flat.
    pub fn crush_at(&self, p: [f32; 2], fallback: [f32; 2]) -> (f32, [f32; 2]) {
        let c = smooth(self.life_at(p));
        if c <= 0.0 {
            return (0.0, fallback);
        }
        let (hx, hy) = (self.cell[0], self.cell[1]);
        let gx = self.life_at([p[0] + hx, p[1]]) - self.life_at([p[0] - hx, p[1]]);
        let gy = self.life_at([p[0], p[1] + hy]) - self.life_at([p[0], p[1] - hy]);
        let l = gx.hypot(gy);
        if l > 1e-4 {
            (c, [-gx / l, -gy / l])
        } else {
            (c, fallback)
        }
    }
}

/// The sphere's footprint at ground point `p`: `1 − (d/r)²` inside the circle where it
/// touches the grass, 0 outside.
pub fn stamp(s: Sphere, p: [f32; 2]) -> f32 {
    let d2 = (p[0] - s.centre[0]).powi(2) + (p[1] - s.centre[2]).powi(2);
    let r2 = s.radius * s.radius;
    if d2 < r2 { 1.0 - d2 / r2 } else { 0.0 }
}
