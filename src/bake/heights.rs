//! The terrain's heights beside the wind: `heights.png`, the ground's height at each baked
//! cell's centre as a 16-bit grey PNG, decoded by the manifest's `terrain` block
//! (`height = stored × scale + offset`, metres). An engine stands its grass and particles on
//! the same ground the wind was shaped by.

use super::error::BakeError;
use super::manifest::{IndexAxis, Sample, TerrainInfo, WorldAxis};
use crate::doc::Layout;
use crate::sim::terrain::TerrainField;
use std::path::Path;

pub const NAME: &str = super::manifest::HEIGHTS;

/// Writes `heights.png` into `dir` for a layout with terrain (baked at `layout`'s grid);
/// `None` without terrain.
pub(crate) fn write(dir: &Path, layout: &Layout) -> Result<Option<TerrainInfo>, BakeError> {
    let (Some(t), Some(field)) = (&layout.world.terrain, TerrainField::new(layout)) else {
        return Ok(None);
    };
    let (nx, ny) = (field.nx, field.ny);
    let (lo, hi) = (t.heights[0], t.heights[1]);
    let step = (hi - lo) / 65535.0;
    let stored: Vec<u16> = field
        .heights
        .iter()
        .map(|&h| {
            if step > 0.0 {
                ((h - lo) / step).round().clamp(0.0, 65535.0) as u16
            } else {
                0
            }
        })
        .collect();
    // Row 0 (the top of the image) is the grid's row 0, at the world's smallest z.
    let img =
        image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_raw(nx as u32, ny as u32, stored)
            .expect("one sample a cell");
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .map_err(|e| BakeError::Write {
        path: dir.join(NAME),
        source: std::io::Error::other(e.to_string()),
    })?;
    let written = super::folder::write_file(dir, NAME, &bytes)?;
    let (min, max) = layout.bounds();
    Ok(Some(TerrainInfo {
        file: NAME,
        sample: Sample::Unorm16,
        units: "m",
        // A reader samples n / 65535 (`unorm16`).
        scale: hi - lo,
        offset: lo,
        axes: vec![
            IndexAxis {
                name: "pixel_x",
                world: WorldAxis::PlusX,
                cells: nx,
                range: [min[0], max[0]],
            },
            IndexAxis {
                name: "pixel_y",
                world: WorldAxis::PlusZ,
                cells: ny,
                range: [min[1], max[1]],
            },
        ],
        heightmap: t.heightmap.clone(),
        strength: t.strength,
        feature_length: t.feature_length_for(layout.world.size),
        bytes: written,
        crc32: 0,
    }))
}
