//! The 3D view's camera (glam): where it stands, what it sees, and the ground under a pixel.

use crate::doc::Layout;
use glam::{Mat4, Vec3};

/// A perspective camera looking from `eye` at `target` (world metres, y up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

impl Camera {
    /// The world's middle seen from its south-west (+z, −x) side, above it, near enough that
    /// the blades read as blades: the world's corners fall outside a 16:9 picture (the
    /// editor's "frame all" shows it whole).
    pub fn overview(layout: &Layout) -> Self {
        let (min, max) = layout.bounds();
        let c = Vec3::new((min[0] + max[0]) / 2.0, 0.0, (min[1] + max[1]) / 2.0);
        let r = (max[0] - min[0]).hypot(max[1] - min[1]) / 2.0;
        Self {
            eye: c + Vec3::new(-0.55 * r, 0.55 * r, 0.95 * r),
            target: c,
            fov_y: 45f32.to_radians(),
        }
    }

    /// Standing in the grass: eye 1.7 m up, a tenth of the way in from the world's south-west
    /// corner, looking across the world's middle — near, middle and far blades in one view
    /// (the grass benchmark's camera).
    pub fn walk(layout: &Layout) -> Self {
        let (min, max) = layout.bounds();
        let (w, d) = (max[0] - min[0], max[1] - min[1]);
        Self {
            eye: Vec3::new(min[0] + 0.1 * w, 1.7, max[1] - 0.1 * d),
            target: Vec3::new((min[0] + max[0]) / 2.0, 0.0, (min[1] + max[1]) / 2.0),
            fov_y: 45f32.to_radians(),
        }
    }

    /// Where the ray through `ndc` (x right, y up, each −1..1) meets the ground (y = 0), if it
    /// does in front of the camera.
    pub fn ground_point(&self, aspect: f32, ndc: [f32; 2]) -> Option<Vec3> {
        let inv = self.view_proj(aspect).inverse();
        let near = inv.project_point3(Vec3::new(ndc[0], ndc[1], 0.0));
        let far = inv.project_point3(Vec3::new(ndc[0], ndc[1], 1.0));
        let d = far - near;
        if d.y.abs() < 1e-9 {
            return None;
        }
        let t = -near.y / d.y;
        (t > 0.0).then(|| near + d * t)
    }

    /// Where the ray through `ndc` first meets the ground of heights `height(x, z)` (metres),
    /// if it does in front of the camera within its far plane: marched in 512 steps, then
    /// bisected.
    pub fn terrain_point(
        &self,
        aspect: f32,
        ndc: [f32; 2],
        height: &dyn Fn([f32; 2]) -> f32,
    ) -> Option<Vec3> {
        let inv = self.view_proj(aspect).inverse();
        let near = inv.project_point3(Vec3::new(ndc[0], ndc[1], 0.0));
        let far = inv.project_point3(Vec3::new(ndc[0], ndc[1], 1.0));
        let at = |t: f32| near + (far - near) * t;
        let above = |t: f32| {
            let p = at(t);
            p.y - height([p.x, p.z])
        };
        const STEPS: usize = 512;
        let mut prev = 0.0;
        if above(prev) <= 0.0 {
            return None;
        }
        for k in 1..=STEPS {
            let t = k as f32 / STEPS as f32;
            if above(t) <= 0.0 {
                let (mut lo, mut hi) = (prev, t);
                for _ in 0..24 {
                    let mid = 0.5 * (lo + hi);
                    if above(mid) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                return Some(at(hi));
            }
            prev = t;
        }
        None
    }

    /// World → clip space for a picture of `aspect` (width / height).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        self.projected(aspect, self.near_plane(), self.far_plane())
    }

    /// The view through a perspective that puts depth 0 at `depth_0` metres and 1 at
    /// `depth_1` (glam's `perspective_rh`, either way round).
    fn projected(&self, aspect: f32, depth_0: f32, depth_1: f32) -> Mat4 {
        Mat4::perspective_rh(self.fov_y, aspect, depth_0, depth_1)
            * Mat4::look_at_rh(self.eye, self.target, Vec3::Y)
    }

    /// [`Self::view_proj`] with its depth reversed (the near plane at depth 1, the far plane
    /// at 0), which the grass is drawn with: into a `Depth32Float` buffer cleared to 0 and
    /// tested with `Greater`. A float's precision is densest near 0, so reversed depth keeps it
    /// nearly even out to the far plane. With the usual depth, blades 100 m off were told apart
    /// only beyond about 6 mm of depth, so overlapping blades tied; which one won depended on
    /// the order the cull pass's workgroups listed them, which a real GPU changes from frame to
    /// frame: a fixed view in calm air shimmered on an NVIDIA GPU, though not on lavapipe.
    /// Only depth changes: the same points land on the same pixels.
    pub fn draw_view_proj(&self, aspect: f32) -> Mat4 {
        self.projected(aspect, self.far_plane(), self.near_plane())
    }

    /// How near the camera sees (metres): a five-hundredth of its distance to the target.
    pub fn near_plane(&self) -> f32 {
        ((self.eye - self.target).length().max(0.01) * 0.002).max(0.01)
    }

    /// How far the camera sees (metres): far enough that the ground beyond the level reaches
    /// nearly to the horizon (within a degree from a third of a kilometre up), where it fades
    /// into the sky.
    pub fn far_plane(&self) -> f32 {
        (self.eye - self.target).length().max(0.01) * 50.0
    }
}

/// How far from the picture's centre (in normalised device coordinates, 1 at the edge) a
/// framed world's corners may come.
pub const FRAME_MARGIN: f32 = 0.94;

/// The pitches (degrees above the ground) "frame all" chooses among.
pub const FRAME_PITCHES_DEG: [f32; 6] = [35.0, 40.0, 45.0, 50.0, 55.0, 60.0];

/// An orbit camera for the 3D view: around a point on the ground, by yaw, pitch and distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    pub target: glam::Vec3,
    /// Radians: yaw around +y from +x toward +z, pitch above the ground.
    pub yaw: f32,
    pub pitch: f32,
    pub distance: f32,
}

impl Orbit {
    /// Looking at the middle of the world from its south (+z), as the map view shows it (x to
    /// the right, −z up the picture: *Map + 3D* side by side read alike), from the nearest
    /// distance that shows the whole world in a view of `aspect` (width / height): its corners,
    /// on the ground and as high as the tallest blade or obstacle, inside `FRAME_MARGIN` of the
    /// picture. Of the pitches in [`FRAME_PITCHES_DEG`], the one whose picture the level fills
    /// most: seen 35° up, a level as wide as the picture is a thin band across it (the meadow
    /// filled a third of a 16:10 picture), the rest haze, and a designer framing the level
    /// wants to see the level.
    pub fn frame_all(doc: &crate::doc::Layout, aspect: f32) -> Self {
        let mut best: Option<(Self, f32)> = None;
        for deg in FRAME_PITCHES_DEG {
            let o = Self::frame_at(doc, aspect, deg.to_radians());
            let share = o.ground_share(doc, aspect);
            if best.is_none_or(|(_, s)| share > s) {
                best = Some((o, share));
            }
        }
        best.map(|(o, _)| o).expect("at least one pitch")
    }

    /// The nearest orbit at `pitch` that shows the whole world (see [`Self::frame_all`]).
    fn frame_at(doc: &crate::doc::Layout, aspect: f32, pitch: f32) -> Self {
        let (min, max) = doc.bounds();
        let r = (max[0] - min[0]).hypot(max[1] - min[1]) / 2.0;
        let mut orbit = Self {
            target: glam::Vec3::new((min[0] + max[0]) / 2.0, 0.0, (min[1] + max[1]) / 2.0),
            yaw: std::f32::consts::FRAC_PI_2,
            pitch,
            distance: r,
        };
        let top = doc.grass.height[1].max(crate::grass::scene::OBSTACLE_HEIGHT);
        let corners: Vec<glam::Vec3> = [0.0, top]
            .into_iter()
            .flat_map(|y| {
                [
                    (min[0], min[1]),
                    (max[0], min[1]),
                    (min[0], max[1]),
                    (max[0], max[1]),
                ]
                .map(|(x, z)| glam::Vec3::new(x, y, z))
            })
            .collect();
        let aspect = aspect.clamp(0.1, 10.0);
        let fits = |o: &Self| {
            let vp = o.camera().view_proj(aspect);
            corners.iter().all(|c| {
                let p = vp * c.extend(1.0);
                p.w > 0.0 && (p.x / p.w).abs() <= FRAME_MARGIN && (p.y / p.w).abs() <= FRAME_MARGIN
            })
        };
        // The corners' extent in the picture shrinks as the camera backs away along its ray.
        let (mut near, mut far) = (0.05 * r, 50.0 * r);
        for _ in 0..40 {
            orbit.distance = 0.5 * (near + far);
            if fits(&orbit) {
                far = orbit.distance;
            } else {
                near = orbit.distance;
            }
        }
        orbit.distance = far;
        orbit
    }

    /// The share of a picture of `aspect` the world's ground rectangle covers from this orbit
    /// (0–1; the world must be in front of the camera).
    pub fn ground_share(&self, doc: &crate::doc::Layout, aspect: f32) -> f32 {
        let (min, max) = doc.bounds();
        let vp = self.camera().view_proj(aspect.clamp(0.1, 10.0));
        let p: Vec<glam::Vec2> = [
            (min[0], min[1]),
            (max[0], min[1]),
            (max[0], max[1]),
            (min[0], max[1]),
        ]
        .map(|(x, z)| {
            let c = vp * glam::Vec4::new(x, 0.0, z, 1.0);
            glam::Vec2::new(c.x, c.y) / c.w
        })
        .to_vec();
        let twice: f32 = (0..4).map(|i| p[i].perp_dot(p[(i + 1) % 4])).sum();
        (twice.abs() / 2.0 / 4.0).min(1.0)
    }

    pub fn camera(&self) -> Camera {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        let eye = self.target + glam::Vec3::new(cy * cp, sp, sy * cp) * self.distance;
        Camera {
            eye,
            target: self.target,
            fov_y: 45f32.to_radians(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The grass is drawn with reversed depth: the same pixels as [`Camera::view_proj`], the
    /// near plane at depth 1 and the far one at 0, and two blades a millimetre apart 100 m
    /// and 400 m from the eye (the benchmark camera's mid and far field) get different depths
    /// in a 32-bit depth buffer. With the usual depth they tied there, and which one showed
    /// followed the cull's list order, which a real GPU changes each frame.
    #[test]
    fn reversed_depth_tells_far_blades_apart() {
        let cam = Camera {
            eye: Vec3::new(10.0, 1.7, 70.0),
            target: Vec3::new(60.0, 0.0, 40.0),
            fov_y: 45f32.to_radians(),
        };
        let aspect = 16.0 / 9.0;
        let (usual, drawn) = (cam.view_proj(aspect), cam.draw_view_proj(aspect));
        let depth = |m: &Mat4, p: Vec3| m.project_point3(p).z;
        let ahead = (cam.target - cam.eye).normalize();
        let near = cam.eye + ahead * cam.near_plane();
        let far = cam.eye + ahead * cam.far_plane();
        assert!((depth(&drawn, near) - 1.0).abs() < 1e-4 && depth(&drawn, far).abs() < 1e-4);
        for d in [5.0, 100.0, 400.0] {
            let p = cam.eye + ahead * d + Vec3::new(3.0, 0.0, 0.0);
            let (a, b) = (usual.project_point3(p), drawn.project_point3(p));
            assert!((a.x - b.x).abs() < 1e-5 && (a.y - b.y).abs() < 1e-5);
        }
        // Gaps in units of the float spacing at the depth (its "ulps").
        let ulps = |m: &Mat4, p: Vec3, q: Vec3| {
            let (a, b) = (depth(m, p), depth(m, q));
            (a - b) / (a.abs().max(b.abs()) * f32::EPSILON)
        };
        for d in [100.0, 400.0] {
            let (p, q) = (cam.eye + ahead * d, cam.eye + ahead * (d + 0.001));
            let (reversed, plain) = (ulps(&drawn, p, q), ulps(&usual, p, q).abs());
            assert!(
                reversed >= 8.0,
                "{d} m: reversed depth ties ({reversed} ulps)"
            );
            assert!(
                plain <= 2.0,
                "{d} m: the usual depth is {plain} ulps apart, so this no longer shows why"
            );
        }
    }

    /// "Frame all" shows every example whole in views from tall to wide, and no farther than
    /// it must: some corner comes near the picture's edge.
    #[test]
    fn framing_shows_the_whole_world_and_fills_the_view() {
        for name in [
            "meadow",
            "obstacles",
            "two-winds",
            "branching",
            "breeze-fft",
        ] {
            let path = format!("{}/layouts/{name}.json", env!("CARGO_MANIFEST_DIR"));
            let doc = crate::doc::parse(&std::fs::read_to_string(path).unwrap()).unwrap();
            let (min, max) = doc.bounds();
            for aspect in [0.5, 1.0, 1.6, 16.0 / 9.0, 3.0] {
                let o = Orbit::frame_all(&doc, aspect);
                let vp = o.camera().view_proj(aspect);
                let mut widest = 0.0f32;
                for y in [0.0, crate::grass::scene::OBSTACLE_HEIGHT] {
                    for (x, z) in [
                        (min[0], min[1]),
                        (max[0], min[1]),
                        (min[0], max[1]),
                        (max[0], max[1]),
                    ] {
                        let p = vp * glam::Vec4::new(x, y, z, 1.0);
                        assert!(p.w > 0.0, "{name} {aspect}: a corner behind the camera");
                        let (sx, sy) = ((p.x / p.w).abs(), (p.y / p.w).abs());
                        assert!(
                            sx <= FRAME_MARGIN + 1e-4 && sy <= FRAME_MARGIN + 1e-4,
                            "{name} at aspect {aspect}: corner ({x}, {y}, {z}) at ({sx}, {sy})"
                        );
                        widest = widest.max(sx).max(sy);
                    }
                }
                assert!(
                    widest >= FRAME_MARGIN - 0.01,
                    "{name} at {aspect}: framed loosely, {widest}"
                );
                // In a landscape picture the level is most of it, not a band across the
                // middle (the meadow filled 34 % of 16:10 seen from 35° up; 57 % now).
                let share = o.ground_share(&doc, aspect);
                if (1.5..=1.8).contains(&aspect) {
                    assert!(share >= 0.45, "{name} at {aspect}: the level fills {share}");
                }
                for deg in FRAME_PITCHES_DEG {
                    let other = Orbit::frame_at(&doc, aspect, deg.to_radians());
                    assert!(
                        other.ground_share(&doc, aspect) <= share + 1e-6,
                        "{name} at {aspect}: {deg}° fills more"
                    );
                }
            }
        }
    }
}
