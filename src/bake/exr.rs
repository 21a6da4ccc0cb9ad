//! OpenEXR: float R = world x velocity, G = world z velocity, B = speed (m/s). Always R, G and
//! B (TinyEXR-based importers such as Godot's reject a file without B), and always a
//! *scanline* image in increasing-Y order: TinyEXR, which Godot bundles, reads tiled images
//! with their rows reversed relative to OpenEXR, while both read scanline images the same way.
//! ZIP compression in blocks of 16 lines: lossless, and read by every EXR loader.

use super::format::{Encoder, Extent, frame_names};
use super::manifest::{self as m, Axes, Channel, Sample, WorldAxis, image_axes};
use super::{BakeError, ExportContext, Field, FileEntry, Format, Output};
use exr::prelude::{Encoding, Image, SpecificChannels, Vec2, WritableImage, f16};

/// The encoding every windloom EXR uses.
pub(crate) const ENCODING: Encoding = Encoding::SMALL_LOSSLESS;

/// A `width × height` RGB image as EXR bytes (half floats when `half`), scanline, ZIP;
/// `pixel(x, y)` gives each pixel, row 0 at the top.
pub(crate) fn rgb_bytes(
    name: &str,
    (width, height): (usize, usize),
    half: bool,
    pixel: impl Fn(usize, usize) -> (f32, f32, f32) + Sync,
) -> Result<Vec<u8>, BakeError> {
    let mut bytes = Vec::new();
    let cursor = std::io::Cursor::new(&mut bytes);
    let result = if half {
        let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
            let (r, g, b) = pixel(p.x(), p.y());
            (f16::from_f32(r), f16::from_f32(g), f16::from_f32(b))
        });
        Image::from_encoded_channels((width, height), ENCODING, channels)
            .write()
            .to_buffered(cursor)
    } else {
        let channels = SpecificChannels::rgb(|p: Vec2<usize>| pixel(p.x(), p.y()));
        Image::from_encoded_channels((width, height), ENCODING, channels)
            .write()
            .to_buffered(cursor)
    };
    result.map_err(|e| BakeError::Encode {
        name: name.to_string(),
        message: e.to_string(),
    })?;
    Ok(bytes)
}

/// Samples, ZIP's overhead on incompressible data, the line-offset table and the header of
/// one `width × height` RGB image.
pub(crate) fn rgb_max_bytes(width: usize, height: usize, half: bool) -> u64 {
    let raw = (width * height) as u64 * 3 * if half { 2 } else { 4 };
    raw + raw / 100 + height.div_ceil(16) as u64 * 16 + 4096
}

fn frame(ctx: &ExportContext, k: usize, f: &Field) -> Result<Output, BakeError> {
    let name = ctx.name("wind", k, "exr");
    let bytes = rgb_bytes(&name, (f.nx, f.ny), ctx.half, |x, y| {
        let v = f.at(x, y);
        (v[0], v[1], v[0].hypot(v[1]))
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

    fn max_bytes(&self, e: &Extent) -> u64 {
        let (nx, ny, frames, half) = (e.nx, e.ny, e.frames, e.half);
        frames as u64 * rgb_max_bytes(nx, ny, half)
    }

    fn frame(&self, ctx: &ExportContext, k: usize, f: &Field) -> Result<Vec<Output>, BakeError> {
        frame(ctx, k, f).map(|o| vec![o])
    }
}
