//! PNG flowmaps (8 and 16 bit) and the flipbook atlas: R = 0.5 + 0.5·vx/max_speed,
//! G = 0.5 + 0.5·vz/max_speed, B = 0; decode with `rg * 2 − 1` times `max_speed`.

use super::{BakeError, ExportContext, Field, FileEntry, Format, Output};
use image::{ImageBuffer, ImageEncoder, Rgb};

fn encode(v: f32, scale: f32, levels: f32) -> f32 {
    ((0.5 + 0.5 * v / scale).clamp(0.0, 1.0) * levels).round()
}

fn flow_encoding(ctx: &ExportContext<'_>, bits: u32) -> serde_json::Value {
    serde_json::json!({
        "bits": bits,
        "R": "world x velocity", "G": "world z velocity", "B": "unused (0)",
        "decode": "velocity = (channel / max_value * 2 - 1) * scale",
        "max_value": if bits == 8 { 255 } else { 65535 },
        "scale": ctx.flow_scale(), "offset": -1.0,
        "units": "m/s",
    })
}

fn flow_axes() -> serde_json::Value {
    serde_json::json!({
        "pixel_x": "+x (east), column 0 at world min x",
        "pixel_y": "+z (south), row 0 (top of the image) at world min z",
        "v_flip": "none: green grows toward +z, which is down the image; flip G (1 - g) for shaders that expect green to point up the image",
    })
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
        .map_err(|e| BakeError::Encode {
            name: name.into(),
            message: e.to_string(),
        })?;
    Ok(bytes)
}

fn rgb16(f: &Field, scale: f32) -> ImageBuffer<Rgb<u16>, Vec<u16>> {
    ImageBuffer::from_fn(f.nx as u32, f.ny as u32, |x, y| {
        let v = f.at(x as usize, y as usize);
        Rgb([
            encode(v[0], scale, 65535.0) as u16,
            encode(v[1], scale, 65535.0) as u16,
            0,
        ])
    })
}

fn rgb16_bytes(name: &str, img: &ImageBuffer<Rgb<u16>, Vec<u16>>) -> Result<Vec<u8>, BakeError> {
    // PNG stores 16-bit samples big-endian; the encoder takes native-order u16 as bytes.
    let raw: Vec<u8> = img.as_raw().iter().flat_map(|v| v.to_ne_bytes()).collect();
    png_bytes(
        name,
        img.width(),
        img.height(),
        &raw,
        image::ExtendedColorType::Rgb16,
    )
}

pub(crate) fn flowmaps(ctx: &ExportContext<'_>, sixteen: bool) -> Result<Vec<Output>, BakeError> {
    let scale = ctx.flow_scale();
    let (stem, format, bits) = if sixteen {
        ("flow16", Format::Png16, 16)
    } else {
        ("flow8", Format::Png8, 8)
    };
    let mut out = Vec::new();
    for (k, f) in ctx.frames.iter().enumerate() {
        let name = ctx.name(stem, k, "png");
        let bytes = if sixteen {
            rgb16_bytes(&name, &rgb16(f, scale))?
        } else {
            let img: ImageBuffer<Rgb<u8>, Vec<u8>> =
                ImageBuffer::from_fn(f.nx as u32, f.ny as u32, |x, y| {
                    let v = f.at(x as usize, y as usize);
                    Rgb([
                        encode(v[0], scale, 255.0) as u8,
                        encode(v[1], scale, 255.0) as u8,
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
        out.push(Output {
            entry: FileEntry {
                name: name.clone(),
                format,
                frame: ctx.frame_index(k),
                grid: [f.nx, f.ny],
                resampled_from: None,
                encoding: flow_encoding(ctx, bits),
                axes: flow_axes(),
                bytes: 0,
            },
            name,
            bytes,
        });
    }
    Ok(out)
}

/// All frames in one 16-bit image: `columns × rows` sub-images, frame `k` at column
/// `k % columns`, row `k / columns`; unused cells hold zero velocity.
pub(crate) fn atlas(ctx: &ExportContext<'_>) -> Result<Vec<Output>, BakeError> {
    let n = ctx.frames.len();
    let columns = (n as f64).sqrt().ceil() as usize;
    let rows = n.div_ceil(columns);
    let (nx, ny) = (ctx.frames[0].nx, ctx.frames[0].ny);
    let scale = ctx.flow_scale();
    let mid = encode(0.0, scale, 65535.0) as u16;
    let mut img: ImageBuffer<Rgb<u16>, Vec<u16>> = ImageBuffer::from_pixel(
        (columns * nx) as u32,
        (rows * ny) as u32,
        Rgb([mid, mid, 0]),
    );
    for (k, f) in ctx.frames.iter().enumerate() {
        let sub = rgb16(f, scale);
        let (ox, oy) = ((k % columns) * nx, (k / columns) * ny);
        for (x, y, p) in sub.enumerate_pixels() {
            img.put_pixel(ox as u32 + x, oy as u32 + y, *p);
        }
    }
    let name = "atlas.png".to_string();
    let bytes = rgb16_bytes(&name, &img)?;
    let mut encoding = flow_encoding(ctx, 16);
    encoding["empty_cells"] = serde_json::json!("zero velocity (0.5, 0.5)");
    Ok(vec![Output {
        entry: FileEntry {
            name: name.clone(),
            format: Format::Atlas,
            frame: None,
            grid: [nx, ny],
            resampled_from: None,
            encoding,
            axes: serde_json::json!({
                "sub_images": {"columns": columns, "rows": rows, "count": n,
                    "order": "frame k at column k % columns, row k / columns (row 0 at the top)",
                    "fps": ctx.fps},
                "within_a_sub_image": flow_axes(),
            }),
            bytes: 0,
        },
        name,
        bytes,
    }])
}
