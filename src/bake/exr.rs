//! OpenEXR: float R = world x velocity, G = world z velocity, B = speed (m/s). Always R, G and
//! B (TinyEXR-based importers such as Godot's reject a file without B), and always a
//! *scanline* image in increasing-Y order: TinyEXR, which Godot bundles, reads tiled images
//! with their rows reversed relative to OpenEXR, while both read scanline images the same way.
//! ZIP compression in blocks of 16 lines: lossless, and read by every EXR loader.

use super::error::BakeError;
use super::field::Field;
use super::format::{Encoder, Extent, frame_names};
use super::format::{ExportContext, Output, atlas_axes, image_axes};
use super::manifest::{self as m, Axes, Channel, Sample, WorldAxis};
use super::manifest::{FileEntry, Format};
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

/// A windloom EXR's channels: R, G the wind along x and z, B the speed, in m/s.
fn wind_encoding(sample: Sample, storage: String) -> m::Encoding {
    m::Encoding {
        sample,
        units: "m/s",
        channels: vec![
            Channel::velocity("R", WorldAxis::PlusX, 1.0, 0.0),
            Channel::velocity("G", WorldAxis::PlusZ, 1.0, 0.0),
            Channel::speed("B"),
        ],
        green_flipped: None,
        storage,
    }
}

fn frame(ctx: &ExportContext, k: usize, f: &Field) -> Result<Output, BakeError> {
    let name = ctx.name("wind", k, "exr");
    let bytes = rgb_bytes(&name, (f.nx, f.ny), ctx.half, |x, y| {
        let v = f.at(x, y);
        (v[0], v[1], crate::num::hypot(v[0], v[1]))
    })?;
    Ok(Output {
        entry: FileEntry {
            name: name.clone(),
            format: Format::Exr,
            frame: ctx.frame_index(k),
            grid: [f.nx, f.ny],
            resampled_from: None,
            encoding: wind_encoding(
                if ctx.half { Sample::F16 } else { Sample::F32 },
                "OpenEXR scanline, increasing Y, ZIP (16 lines per block), channels B, G, R".into(),
            ),
            axes: Axes {
                index: image_axes(ctx, f.nx, f.ny),
                sub_images: None,
                engine_frame: None,
            },
            bytes: 0,
            crc32: 0,
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

pub(crate) const ATLAS_EXR_NAME: &str = "atlas.exr";

/// All frames in one half-float EXR, laid out as the PNG atlas (`png::atlas_grid`): R, G the
/// wind along x and z, B the speed, in m/s — what Godot reads at full precision where its
/// PNG loader keeps 8 bits of the 16-bit atlas. Written after the frames are made, from the
/// frame stream, one band of sub-images in memory at a time.
pub(crate) fn atlas(
    ctx: &ExportContext,
    frames: &mut super::frames::FrameReader,
) -> Result<(Vec<u8>, FileEntry), BakeError> {
    let (columns, rows) = super::manifest::atlas_grid(ctx.count);
    let (nx, ny) = (ctx.nx, ctx.ny);
    // The band of sub-images holding the rows being written: (band, its frames).
    let band: std::sync::Mutex<(usize, Vec<Field>)> =
        std::sync::Mutex::new((usize::MAX, Vec::new()));
    let frames = std::sync::Mutex::new(frames);
    let failed = std::sync::Mutex::new(None);
    let bytes = rgb_bytes(ATLAS_EXR_NAME, (columns * nx, rows * ny), true, |x, y| {
        let (r, column) = (y / ny, x / nx);
        let k = r * columns + column;
        if k >= ctx.count {
            return (0.0, 0.0, 0.0);
        }
        let mut band = band.lock().unwrap_or_else(|e| e.into_inner());
        if band.0 != r {
            let mut reader = frames.lock().unwrap_or_else(|e| e.into_inner());
            let first = r * columns;
            let last = (first + columns).min(ctx.count);
            let mut loaded = Vec::with_capacity(last - first);
            for k in first..last {
                match reader.read(k) {
                    Ok(f) => loaded.push(f),
                    Err(e) => {
                        *failed.lock().unwrap_or_else(|e| e.into_inner()) = Some(e);
                        return (0.0, 0.0, 0.0);
                    }
                }
            }
            *band = (r, loaded);
        }
        let Some(f) = band.1.get(column) else {
            return (0.0, 0.0, 0.0);
        };
        let v = f.at(x % nx, y % ny);
        (v[0], v[1], crate::num::hypot(v[0], v[1]))
    })?;
    if let Some(e) = failed.into_inner().unwrap_or_else(|e| e.into_inner()) {
        return Err(e);
    }
    let entry = FileEntry {
        name: ATLAS_EXR_NAME.to_string(),
        format: Format::AtlasExr,
        frame: None,
        grid: [nx, ny],
        resampled_from: None,
        encoding: wind_encoding(
            Sample::F16,
            format!(
                "OpenEXR scanline, increasing Y, ZIP, half floats: {columns} × {rows} sub-images of {nx} × {ny} pixels; unused sub-images hold zero wind"
            ),
        ),
        axes: atlas_axes(ctx),
        bytes: 0,
        crc32: 0,
    };
    Ok((bytes, entry))
}

/// The EXR atlas: one file, written from the frame stream after the frames are made.
pub(crate) struct AtlasExr;

impl Encoder for AtlasExr {
    fn names(&self, _count: usize) -> Vec<String> {
        vec![ATLAS_EXR_NAME.to_string()]
    }

    fn max_bytes(&self, e: &Extent) -> u64 {
        let (c, r) = super::manifest::atlas_grid(e.frames);
        rgb_max_bytes(c * e.nx, r * e.ny, true)
    }

    fn frame(&self, _: &ExportContext, _: usize, _: &Field) -> Result<Vec<Output>, BakeError> {
        Ok(Vec::new())
    }
}
