//! Obstacle rasterisation: circles and polygons onto the wind grid with tiny-skia coverage, and
//! mask images by the share of each cell their solid pixels cover (4 × 4 samples a cell).

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
    // Coverage of each cell by the mask images, 0 to 1.
    let mut images = vec![0.0f32; solid.len()];
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
            Shape::Mask {
                threshold,
                invert,
                rect,
                pixels,
                ..
            } => {
                if let Some(image) = pixels.image() {
                    let r = crate::doc::placed(rect, layout.bounds());
                    cover(layout, image, r, *threshold, *invert, &mut images);
                }
                None
            }
        };
        if let Some(path) = path {
            mask.fill_path(&path, FillRule::Winding, true, transform);
        }
    }
    // Shapes alone as ever (at least 127 of 255); with a mask's share added where it has one.
    let threshold = (SOLID_COVERAGE * 255.0) as u8;
    for ((s, &m), &c) in solid.iter_mut().zip(mask.data()).zip(&images) {
        *s = u8::from(m >= threshold || (c > 0.0 && f32::from(m) / 255.0 + c >= SOLID_COVERAGE));
    }
    solid
}

/// Samples per cell along each axis for a mask image.
const MASK_SAMPLES: usize = 4;

/// Adds each cell's share covered by the mask's solid pixels to `coverage`.
fn cover(
    layout: &Layout,
    image: &crate::doc::MaskImage,
    rect: [[f32; 2]; 2],
    threshold: f32,
    invert: bool,
    coverage: &mut [f32],
) {
    let [nx, ny] = layout.world.grid.map(|n| n as usize);
    let (min, _) = layout.bounds();
    let cell = [
        layout.world.size[0] / nx as f32,
        layout.world.size[1] / ny as f32,
    ];
    let share = 1.0 / (MASK_SAMPLES * MASK_SAMPLES) as f32;
    for j in 0..ny {
        for i in 0..nx {
            let mut hits = 0;
            for sj in 0..MASK_SAMPLES {
                for si in 0..MASK_SAMPLES {
                    let x = min[0] + (i as f32 + (si as f32 + 0.5) / MASK_SAMPLES as f32) * cell[0];
                    let z = min[1] + (j as f32 + (sj as f32 + 0.5) / MASK_SAMPLES as f32) * cell[1];
                    if crate::doc::image_uv(rect, [x, z])
                        .is_some_and(|[u, v]| image.solid_at(u, v, threshold, invert))
                    {
                        hits += 1;
                    }
                }
            }
            coverage[j * nx + i] += hits as f32 * share;
        }
    }
}
