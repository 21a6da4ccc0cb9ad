//! Obstacle rasterisation: circles and polygons onto the wind grid, with tiny-skia coverage.

use crate::doc::{Layout, Shape};
use tiny_skia::{FillRule, Mask, PathBuilder, Transform};

/// A cell is solid when the obstacles cover at least this fraction of it.
pub const SOLID_COVERAGE: f32 = 0.5;

/// One byte per cell (`1` solid, `0` fluid), row-major, row `j` along world `+z`.
pub fn rasterize(layout: &Layout) -> Vec<u8> {
    let [nx, ny] = layout.world.grid;
    let mut solid = vec![0u8; nx as usize * ny as usize];
    if layout.obstacles.is_empty() {
        return solid;
    }
    let Some(mut mask) = Mask::new(nx, ny) else {
        return solid;
    };
    let (min, _) = layout.bounds();
    let sx = nx as f32 / layout.world.size[0];
    let sz = ny as f32 / layout.world.size[1];
    let transform = Transform::from_row(sx, 0.0, 0.0, sz, -min[0] * sx, -min[1] * sz);
    for o in &layout.obstacles {
        let path = match &o.shape {
            Shape::Circle { center, radius } => {
                PathBuilder::from_circle(center[0], center[1], *radius)
            }
            Shape::Polygon { points } => {
                let mut pb = PathBuilder::new();
                for (i, p) in points.iter().enumerate() {
                    if i == 0 {
                        pb.move_to(p[0], p[1]);
                    } else {
                        pb.line_to(p[0], p[1]);
                    }
                }
                pb.close();
                pb.finish()
            }
        };
        if let Some(path) = path {
            mask.fill_path(&path, FillRule::Winding, true, transform);
        }
    }
    let threshold = (SOLID_COVERAGE * 255.0) as u8;
    for (s, &m) in solid.iter_mut().zip(mask.data()) {
        *s = u8::from(m >= threshold);
    }
    solid
}
