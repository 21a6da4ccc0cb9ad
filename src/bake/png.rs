//! PNG flowmaps (8 and 16 bit) and the flipbook atlas: R = 0.5 + 0.5·vx/max_speed,
//! G = 0.5 + 0.5·vz/max_speed, B = 0; decode with `rg * 2 − 1` times `max_speed`.

use super::error::BakeError;
use super::field::Field;
use super::format::{Encoder, Extent, frame_names};
use super::format::{ExportContext, Output, atlas_axes, image_axes};
use super::manifest::{Axes, Channel, Encoding, Sample, WorldAxis, atlas_grid};
use super::manifest::{FileEntry, Format};
use image::{ImageBuffer, ImageEncoder, Rgb};
use std::io::Write;
use std::path::{Path, PathBuf};

fn encode(v: f32, scale: f32, levels: f32) -> f32 {
    ((0.5 + 0.5 * v / scale).clamp(0.0, 1.0) * levels).round()
}

fn flow_encoding(ctx: &ExportContext, bits: u32) -> Encoding {
    // stored (0..1) · 2S − S.
    let s = ctx.flow_scale();
    let green = if ctx.flip_green {
        WorldAxis::MinusZ
    } else {
        WorldAxis::PlusZ
    };
    Encoding {
        sample: if bits == 8 {
            Sample::Unorm8
        } else {
            Sample::Unorm16
        },
        units: "m/s",
        channels: vec![
            Channel::velocity("R", WorldAxis::PlusX, 2.0 * s, -s),
            Channel::velocity("G", green, 2.0 * s, -s),
            Channel::unused("B"),
        ],
        green_flipped: Some(ctx.flip_green),
        storage: format!("PNG, RGB, {bits} bits a channel"),
    }
}

/// The green channel's velocity: the world z wind, negated when flipped.
fn green(v: [f32; 2], flip: bool) -> f32 {
    if flip { -v[1] } else { v[1] }
}

fn encode_error(name: &str, e: impl std::fmt::Display) -> BakeError {
    BakeError::Encode {
        name: name.into(),
        message: e.to_string(),
    }
}

fn png_bytes(
    name: &str,
    w: u32,
    h: u32,
    data: &[u8],
    color: image::ExtendedColorType,
) -> Result<Vec<u8>, BakeError> {
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(data, w, h, color)
        .map_err(|e| encode_error(name, e))?;
    Ok(bytes)
}

/// One row of 16-bit RGB samples, each written with `bytes` (PNG's big-endian order for the
/// streamed atlas, native order for the image encoder).
fn row16(
    f: &Field,
    j: usize,
    scale: f32,
    flip: bool,
    out: &mut Vec<u8>,
    bytes: fn(u16) -> [u8; 2],
) {
    for i in 0..f.nx {
        let v = f.at(i, j);
        for c in [
            encode(v[0], scale, 65535.0) as u16,
            encode(green(v, flip), scale, 65535.0) as u16,
            0,
        ] {
            out.extend_from_slice(&bytes(c));
        }
    }
}

/// Most bytes a PNG of `w × h` pixels of `bytes_per_pixel` takes: the filtered rows, what
/// deflate adds to incompressible data (5 bytes per 16 KiB block), and the chunks around it.
fn max_size(w: usize, h: usize, bytes_per_pixel: usize) -> u64 {
    let raw = ((w * bytes_per_pixel + 1) * h) as u64;
    raw + raw / 1024 + 4096
}

fn flowmap(ctx: &ExportContext, k: usize, f: &Field, sixteen: bool) -> Result<Output, BakeError> {
    let scale = ctx.flow_scale();
    let (stem, format, bits) = if sixteen {
        ("flow16", Format::Png16, 16)
    } else {
        ("flow8", Format::Png8, 8)
    };
    let name = ctx.name(stem, k, "png");
    let bytes = if sixteen {
        // The encoder takes 16-bit samples in native order.
        let mut native = Vec::with_capacity(f.nx * f.ny * 6);
        for j in 0..f.ny {
            row16(f, j, scale, ctx.flip_green, &mut native, u16::to_ne_bytes);
        }
        png_bytes(
            &name,
            f.nx as u32,
            f.ny as u32,
            &native,
            image::ExtendedColorType::Rgb16,
        )?
    } else {
        let img: ImageBuffer<Rgb<u8>, Vec<u8>> =
            ImageBuffer::from_fn(f.nx as u32, f.ny as u32, |x, y| {
                let v = f.at(x as usize, y as usize);
                Rgb([
                    encode(v[0], scale, 255.0) as u8,
                    encode(green(v, ctx.flip_green), scale, 255.0) as u8,
                    0,
                ])
            });
        png_bytes(
            &name,
            img.width(),
            img.height(),
            img.as_raw(),
            image::ExtendedColorType::Rgb8,
        )?
    };
    Ok(Output {
        entry: FileEntry {
            name: name.clone(),
            format,
            frame: ctx.frame_index(k),
            grid: [f.nx, f.ny],
            resampled_from: None,
            encoding: flow_encoding(ctx, bits),
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

pub(crate) const ATLAS_NAME: &str = "atlas.png";

/// All frames in one 16-bit image, written as the frames arrive: `columns × rows`
/// sub-images, frame `k` at column `k % columns`, row `k / columns`; unused cells hold zero
/// velocity. Only one band of sub-images is held in memory.
pub(crate) struct Atlas {
    path: PathBuf,
    writer: ::png::StreamWriter<'static, std::fs::File>,
    columns: usize,
    rows: usize,
    band: Vec<Field>,
    entry: FileEntry,
    scale: f32,
    flip_green: bool,
}

impl Atlas {
    pub(crate) fn create(ctx: &ExportContext, path: &Path) -> Result<Self, BakeError> {
        let (columns, rows) = atlas_grid(ctx.count);
        let (w, h) = (columns * ctx.nx, rows * ctx.ny);
        let io = |e: std::io::Error| BakeError::Write {
            path: path.to_path_buf(),
            source: e,
        };
        let file = std::fs::File::create(path).map_err(io)?;
        let mut enc = ::png::Encoder::new(file, w as u32, h as u32);
        enc.set_color(::png::ColorType::Rgb);
        enc.set_depth(::png::BitDepth::Sixteen);
        let writer = enc
            .write_header()
            .and_then(|w| w.into_stream_writer_with_size(1 << 20))
            .map_err(|e| encode_error(ATLAS_NAME, e))?;
        let mut encoding = flow_encoding(ctx, 16);
        encoding.storage = format!(
            "PNG, RGB, 16 bits a channel: {columns} × {rows} sub-images of {} × {} pixels; unused sub-images hold zero wind (32768, 32768)",
            ctx.nx, ctx.ny
        );
        let entry = FileEntry {
            name: ATLAS_NAME.to_string(),
            format: Format::Atlas,
            frame: None,
            grid: [ctx.nx, ctx.ny],
            resampled_from: None,
            encoding,
            axes: atlas_axes(ctx),
            bytes: 0,
            crc32: 0,
        };
        Ok(Self {
            path: path.to_path_buf(),
            writer,
            columns,
            rows,
            band: Vec::with_capacity(columns),
            entry,
            scale: ctx.flow_scale(),
            flip_green: ctx.flip_green,
        })
    }

    /// Adds the next frame.
    pub(crate) fn push(&mut self, f: Field) -> Result<(), BakeError> {
        self.band.push(f);
        if self.band.len() == self.columns {
            self.flush_band()?;
        }
        Ok(())
    }

    fn flush_band(&mut self) -> Result<(), BakeError> {
        let Some(first) = self.band.first() else {
            return Ok(());
        };
        let (nx, ny) = (first.nx, first.ny);
        let blank = Field {
            nx,
            ny,
            data: vec![[0.0; 2]; nx * ny],
        };
        let mut row = Vec::with_capacity(self.columns * nx * 6);
        for j in 0..ny {
            row.clear();
            for c in 0..self.columns {
                let f = self.band.get(c).unwrap_or(&blank);
                row16(
                    f,
                    j,
                    self.scale,
                    self.flip_green,
                    &mut row,
                    u16::to_be_bytes,
                );
            }
            self.writer
                .write_all(&row)
                .map_err(|e| encode_error(ATLAS_NAME, e))?;
        }
        self.band.clear();
        self.rows -= 1;
        Ok(())
    }

    /// Writes the last band and closes the file (the caller flushes it to disk).
    pub(crate) fn finish(mut self) -> Result<(PathBuf, FileEntry), BakeError> {
        self.flush_band()?;
        debug_assert_eq!(self.rows, 0);
        self.writer
            .finish()
            .map_err(|e| encode_error(ATLAS_NAME, e))?;
        Ok((self.path, self.entry))
    }
}

/// The PNG flowmaps, 8 or 16 bits a channel.
pub(crate) struct Flowmap {
    pub sixteen: bool,
}

impl Encoder for Flowmap {
    fn names(&self, count: usize) -> Vec<String> {
        frame_names(if self.sixteen { "flow16" } else { "flow8" }, count, "png")
    }

    fn max_bytes(&self, e: &Extent) -> u64 {
        let (nx, ny, frames) = (e.nx, e.ny, e.frames);
        frames as u64 * max_size(nx, ny, if self.sixteen { 6 } else { 3 })
    }

    fn frame(&self, ctx: &ExportContext, k: usize, f: &Field) -> Result<Vec<Output>, BakeError> {
        flowmap(ctx, k, f, self.sixteen).map(|o| vec![o])
    }
}

/// The atlas: one file, written by [`Atlas`] as the frames arrive.
pub(crate) struct AtlasFormat;

impl Encoder for AtlasFormat {
    fn names(&self, _count: usize) -> Vec<String> {
        vec![ATLAS_NAME.to_string()]
    }

    fn max_bytes(&self, e: &Extent) -> u64 {
        let (nx, ny, frames) = (e.nx, e.ny, e.frames);
        let (c, r) = atlas_grid(frames);
        max_size(c * nx, r * ny, 6)
    }

    fn frame(&self, _: &ExportContext, _: usize, _: &Field) -> Result<Vec<Output>, BakeError> {
        Ok(Vec::new())
    }
}
