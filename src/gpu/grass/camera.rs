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

    /// World → clip space for a picture of `aspect` (width / height).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let dist = (self.eye - self.target).length().max(0.01);
        let proj = Mat4::perspective_rh(self.fov_y, aspect, (dist * 0.002).max(0.01), dist * 20.0);
        proj * Mat4::look_at_rh(self.eye, self.target, Vec3::Y)
    }
}
