//! Reading a file's stored samples, as its manifest entry describes them: the numbers a GPU
//! or an engine's importer would sample, before `value = stored × scale + offset`. Each
//! reader returns them cell after cell in the file's index order (its axes fastest first),
//! the channels of a cell together, in the manifest's channel order.

use crate::manifest::FileEntry;

/// The stored samples of one file: `channels` numbers a cell.
pub(crate) struct Stored {
    pub channels: usize,
    pub values: Vec<f32>,
}

/// The file kinds the runtime reads, by the file's name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    Raw,
    Exr,
    Png,
    Dds,
    Vf,
}

impl Kind {
    /// The kind of a file from its name; `None` for what the runtime does not read (FGA's
    /// area-averaged text, the atlases' flipbooks, which hold the same wind as the files
    /// beside them).
    pub fn of(entry: &FileEntry) -> Option<Kind> {
        if entry.axes.sub_images.is_some() {
            return None;
        }
        let ext = entry.name.rsplit_once('.').map(|(_, e)| e)?;
        Some(match ext.to_ascii_lowercase().as_str() {
            "f32" => Kind::Raw,
            "exr" => Kind::Exr,
            "png" => Kind::Png,
            "dds" => Kind::Dds,
            "vf" => Kind::Vf,
            _ => return None,
        })
    }

    /// Whether this build can decode it (EXR and PNG are cargo features).
    pub fn available(self) -> bool {
        match self {
            Kind::Exr => cfg!(feature = "exr"),
            Kind::Png => cfg!(feature = "png"),
            Kind::Raw | Kind::Dds | Kind::Vf => true,
        }
    }
}

/// The stored samples of `bytes`, a file of kind `kind` described by `entry`, holding
/// `cells` cells: an image whose header claims more is refused before it is decoded.
pub(crate) fn stored(
    kind: Kind,
    entry: &FileEntry,
    bytes: &[u8],
    cells: usize,
) -> Result<Stored, String> {
    let channels = entry.encoding.channels.len();
    let values = match kind {
        Kind::Raw => f32s(bytes, "the file")?,
        Kind::Vf => {
            if bytes.len() < 10 || &bytes[..4] != b"VF_V" {
                return Err("not a Unity vector field (no VF_V header)".into());
            }
            f32s(&bytes[10..], "the vectors after the header")?
        }
        Kind::Dds => dds(entry, bytes)?,
        Kind::Png => return png_samples(bytes, channels, cells),
        Kind::Exr => exr_samples(entry, bytes, cells)?,
    };
    Ok(Stored { channels, values })
}

fn f32s(bytes: &[u8], what: &str) -> Result<Vec<f32>, String> {
    if !bytes.len().is_multiple_of(4) {
        return Err(format!(
            "{what} is {} bytes, not a whole number of 4-byte floats",
            bytes.len()
        ));
    }
    Ok(bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect())
}

/// A DX10 DDS volume: a 148-byte header (magic, DDS_HEADER, DDS_HEADER_DXT10), then
/// RGBA32F (DXGI format 2) or RGBA16F (10) samples, width fastest.
fn dds(entry: &FileEntry, bytes: &[u8]) -> Result<Vec<f32>, String> {
    const DATA: usize = 148;
    if bytes.len() < DATA || &bytes[..4] != b"DDS " || &bytes[84..88] != b"DX10" {
        return Err("not a DX10 DDS file".into());
    }
    let dxgi = u32::from_le_bytes([bytes[128], bytes[129], bytes[130], bytes[131]]);
    let data = &bytes[DATA..];
    match (dxgi, entry.encoding.sample.as_str()) {
        (2, "f32") => f32s(data, "the texels"),
        (10, "f16") => {
            if !data.len().is_multiple_of(2) {
                return Err("the half-float texels end in half a sample".into());
            }
            Ok(data
                .chunks_exact(2)
                .map(|c| half::f16::from_le_bytes([c[0], c[1]]).to_f32())
                .collect())
        }
        (d, s) => Err(format!(
            "DXGI format {d} does not hold the manifest's `{s}` samples"
        )),
    }
}

/// A PNG's one image as stored (16-bit samples kept, big-endian; nothing expanded), if its
/// header says it is `pixels` pixels (checked before anything is decoded).
#[cfg(feature = "png")]
fn decode_png(bytes: &[u8], pixels: usize) -> Result<(png::OutputInfo, Vec<u8>), String> {
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::IDENTITY);
    let mut reader = decoder.read_info().map_err(|e| format!("PNG: {e}"))?;
    let (w, h) = (reader.info().width, reader.info().height);
    if u64::from(w) * u64::from(h) != pixels as u64 {
        return Err(format!(
            "PNG: the header says {w} × {h} pixels, the manifest's axes {pixels} cells"
        ));
    }
    let size = reader
        .output_buffer_size()
        .ok_or("PNG: the image is too large")?;
    let mut buf = vec![0; size];
    let info = reader
        .next_frame(&mut buf)
        .map_err(|e| format!("PNG: {e}"))?;
    buf.truncate(info.buffer_size());
    Ok((info, buf))
}

#[cfg(feature = "png")]
fn png_samples(bytes: &[u8], channels: usize, cells: usize) -> Result<Stored, String> {
    let (info, buf) = decode_png(bytes, cells)?;
    let per_pixel = info.color_type.samples();
    if per_pixel < channels {
        return Err(format!(
            "PNG: {per_pixel} channels a pixel, the manifest lists {channels}"
        ));
    }
    let samples: Vec<f32> = match info.bit_depth {
        png::BitDepth::Eight => buf.iter().map(|&n| f32::from(n) / 255.0).collect(),
        png::BitDepth::Sixteen => buf
            .chunks_exact(2)
            .map(|c| f32::from(u16::from_be_bytes([c[0], c[1]])) / 65535.0)
            .collect(),
        d => return Err(format!("PNG: {d:?}-bit samples; windloom writes 8 or 16")),
    };
    let values = if per_pixel == channels {
        samples
    } else {
        samples
            .chunks_exact(per_pixel)
            .flat_map(|p| p[..channels].iter().copied())
            .collect()
    };
    Ok(Stored { channels, values })
}

#[cfg(not(feature = "png"))]
fn png_samples(_: &[u8], _: usize, _: usize) -> Result<Stored, String> {
    Err("this build reads no PNG (the `png` feature is off)".into())
}

/// The channels the manifest names, each read as 32-bit floats (half floats widen exactly).
#[cfg(feature = "exr")]
fn exr_samples(entry: &FileEntry, bytes: &[u8], cells: usize) -> Result<Vec<f32>, String> {
    use exr::prelude::*;
    // The header first: no layer larger than the manifest's cells, no more than 16
    // channels, before any pixel is decoded.
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
        .map_err(|e| format!("EXR: {e}"))?;
    for h in meta.headers.iter() {
        let (w, ht) = (h.layer_size.width(), h.layer_size.height());
        if (w as u64) * (ht as u64) > cells as u64 || h.channels.list.len() > 16 {
            return Err(format!(
                "EXR: a layer of {w} × {ht} pixels and {} channels, where the manifest's axes \
                 have {cells} cells",
                h.channels.list.len()
            ));
        }
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .non_parallel()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| format!("EXR: {e}"))?;
    let list = &image.layer_data.channel_data.list;
    let columns: Vec<Vec<f32>> = entry
        .encoding
        .channels
        .iter()
        .map(|c| {
            list.iter()
                .find(|l| l.name.to_string() == c.name)
                .map(|l| l.sample_data.values_as_f32().collect())
                .ok_or_else(|| format!("EXR: no channel {}", c.name))
        })
        .collect::<std::result::Result<_, String>>()?;
    let n = columns.first().map_or(0, Vec::len);
    Ok((0..n)
        .flat_map(|k| columns.iter().map(move |c| c[k]))
        .collect())
}

#[cfg(not(feature = "exr"))]
fn exr_samples(_: &FileEntry, _: &[u8], _: usize) -> Result<Vec<f32>, String> {
    Err("this build reads no EXR (the `exr` feature is off)".into())
}

/// The grey samples of the terrain's 16-bit PNG, `n / 65535`, row after row, if it is
/// `size` pixels (checked before it is decoded).
#[cfg(feature = "png")]
pub(crate) fn grey16(bytes: &[u8], size: [usize; 2]) -> Result<(usize, usize, Vec<f32>), String> {
    let (info, buf) = decode_png(bytes, size[0].saturating_mul(size[1]))?;
    if [info.width as usize, info.height as usize] != size {
        return Err(format!(
            "{} × {} pixels, where the manifest's axes have {} × {}",
            info.width, info.height, size[0], size[1]
        ));
    }
    if info.color_type != png::ColorType::Grayscale || info.bit_depth != png::BitDepth::Sixteen {
        return Err(format!(
            "PNG: {:?} {:?}-bit; the heights are 16-bit grey",
            info.color_type, info.bit_depth
        ));
    }
    let values = buf
        .chunks_exact(2)
        .map(|c| f32::from(u16::from_be_bytes([c[0], c[1]])) / 65535.0)
        .collect();
    Ok((info.width as usize, info.height as usize, values))
}

#[cfg(not(feature = "png"))]
pub(crate) fn grey16(_: &[u8], _: [usize; 2]) -> Result<(usize, usize, Vec<f32>), String> {
    Err(
        "this build reads no PNG (the `png` feature is off), and the terrain's heights are one"
            .into(),
    )
}
