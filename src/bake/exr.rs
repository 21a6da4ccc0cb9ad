//! OpenEXR: float R = world x velocity, G = world z velocity, B = speed (m/s). Always R, G and
//! B (TinyEXR-based importers such as Godot's reject a file without B), and always a
//! *scanline* image in increasing-Y order: TinyEXR, which Godot bundles, reads tiled images
//! with their rows reversed relative to OpenEXR, while both read scanline images the same way.
//! ZIP compression in blocks of 16 lines: lossless, and read by every EXR loader.

use super::format::{Encoder, frame_names};
use super::manifest::{self as m, Axes, Channel, Sample, WorldAxis, image_axes};
use super::{BakeError, ExportContext, Field, FileEntry, Format, Output};
use exr::prelude::{Encoding, Image, SpecificChannels, Vec2, WritableImage, f16};

/// The encoding every windloom EXR uses.
pub(crate) const ENCODING: Encoding = Encoding::SMALL_LOSSLESS;

fn frame(ctx: &ExportContext, k: usize, f: &Field) -> Result<Output, BakeError> {
    let name = ctx.name("wind", k, "exr");
    let pixel = |p: Vec2<usize>| {
        let v = f.at(p.x(), p.y());
        (v[0], v[1], v[0].hypot(v[1]))
    };
    let mut bytes = Vec::new();
    let cursor = std::io::Cursor::new(&mut bytes);
    let result = if ctx.half {
        let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
            let (r, g, b) = pixel(p);
            (f16::from_f32(r), f16::from_f32(g), f16::from_f32(b))
        });
        Image::from_encoded_channels((f.nx, f.ny), ENCODING, channels)
            .write()
            .to_buffered(cursor)
    } else {
        let channels = SpecificChannels::rgb(pixel);
        Image::from_encoded_channels((f.nx, f.ny), ENCODING, channels)
            .write()
            .to_buffered(cursor)
    };
    result.map_err(|e| BakeError::Encode {
        name: name.clone(),
        message: e.to_string(),
    })?;
    Ok(Output {
        entry: FileEntry {
            name: name.clone(),
            format: Format::Exr,
            frame: ctx.frame_index(k),
            grid: [f.nx, f.ny],
            resampled_from: None,
            encoding: m::Encoding {
                sample: if ctx.half { Sample::F16 } else { Sample::F32 },
                units: "m/s",
                channels: vec![
                    Channel::velocity("R", WorldAxis::PlusX, 1.0, 0.0),
                    Channel::velocity("G", WorldAxis::PlusZ, 1.0, 0.0),
                    Channel::speed("B"),
                ],
                green_flipped: None,
                storage:
                    "OpenEXR scanline, increasing Y, ZIP (16 lines per block), channels B, G, R"
                        .to_string(),
            },
            axes: Axes {
                index: image_axes(ctx, f.nx, f.ny),
                sub_images: None,
                engine_frame: None,
            },
            bytes: 0,
        },
        name,
        bytes,
    })
}

/// The EXR format.
pub(crate) struct Exr;

impl Encoder for Exr {
    fn names(&self, count: usize) -> Vec<String> {
        frame_names("wind", count, "exr")
    }

    /// The samples, what ZIP adds to incompressible data, the line-offset table and the header.
    fn max_bytes(&self, nx: usize, ny: usize, frames: usize, half: bool) -> u64 {
        let raw = (nx * ny) as u64 * 3 * if half { 2 } else { 4 };
        let blocks = ny.div_ceil(16) as u64;
        frames as u64 * (raw + raw / 100 + blocks * 16 + 4096)
    }

    fn frame(&self, ctx: &ExportContext, k: usize, f: &Field) -> Result<Option<Output>, BakeError> {
        frame(ctx, k, f).map(Some)
    }
}
