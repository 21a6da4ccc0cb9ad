//! Every format's encoder by its tag, and what a bake in a set of formats writes: its files'
//! names and the disk it may take at its peak.

use super::format::{Encoder, Extent};
use super::manifest::{Format, MANIFEST};
use super::{exr, fga, png, raw, vf, volume};

/// The file that writes `format`.
pub(super) fn encoder(format: Format) -> &'static dyn Encoder {
    match format {
        Format::Exr => &exr::Exr,
        Format::Png8 => &png::Flowmap { sixteen: false },
        Format::Png16 => &png::Flowmap { sixteen: true },
        Format::Fga => &fga::Fga,
        Format::Vf => &vf::Vf,
        Format::Raw => &raw::Raw,
        Format::Atlas => &png::AtlasFormat,
        Format::AtlasExr => &exr::AtlasExr,
        Format::Dds => &volume::Volume,
    }
}

/// Every file a bake of `count` frames in `formats` writes, the manifest last.
pub fn output_names(formats: &[Format], count: usize) -> Vec<String> {
    let mut names: Vec<String> = formats
        .iter()
        .flat_map(|&f| encoder(f).names(count))
        .collect();
    names.push(MANIFEST.to_string());
    names
}

/// An upper bound of the disk a bake takes at its peak: every output, the manifest, and the
/// temporary frame files (the frame stream when `raw` is not kept, and a loop's `2N` source
/// frames). `layers`: the volume's layers (`dds`).
pub fn disk_need(
    nx: usize,
    ny: usize,
    layers: usize,
    formats: &[Format],
    frames: usize,
    looped: bool,
    half: bool,
) -> u64 {
    let n = frames as u64;
    let frame_raw = (nx * ny) as u64 * 8;
    // The frame stream (kept as wind.f32 or deleted at the end), and a loop's source frames.
    let mut need = frame_raw * n + if looped { frame_raw * 2 * n } else { 0 };
    let size = Extent {
        nx,
        ny,
        layers,
        frames,
        half,
    };
    for f in formats {
        need += encoder(*f).max_bytes(&size);
    }
    // The manifest: a few hundred bytes per file.
    need + 64 * 1024 + 1024 * output_names(formats, frames).len() as u64
}
