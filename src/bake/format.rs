//! The formats a bake writes. [`Format`] is what a user picks; each format's own file answers
//! for it through [`Encoder`]: the names of its files, an upper bound of their size, and the
//! encoding of a frame. `bake` finds each format's file (`encoder`), loops over the chosen
//! formats and asks them.

use super::{BakeError, ExportContext, Field, Output};
use serde::Serialize;

/// Output formats.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, schemars::JsonSchema, PartialOrd, Ord,
)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// OpenEXR, float RGB: R = world x, G = world z, B = speed (m/s).
    Exr,
    /// 8-bit PNG flowmap, RG centred on 0.5.
    Png8,
    /// 16-bit PNG flowmap, RG centred on 0.5.
    Png16,
    /// Unreal vector field (FGA), at most 128 cells per axis.
    Fga,
    /// Unity VFX Graph vector field (VF_V).
    Vf,
    /// Little-endian f32 pairs, all frames in one file.
    Raw,
    /// All frames in one 16-bit PNG flipbook.
    Atlas,
    /// All frames in one half-float EXR flipbook, laid out as `Atlas`, in m/s.
    #[serde(rename = "atlas-exr")]
    AtlasExr,
    /// The wind as a volume up the layout's vertical profile: a DDS 3D texture, with the
    /// same volume as a Unity vector field and as Godot's EXR slices.
    Dds,
}

impl Format {
    pub const ALL: [Format; 9] = [
        Format::Exr,
        Format::Png8,
        Format::Png16,
        Format::Fga,
        Format::Vf,
        Format::Raw,
        Format::Atlas,
        Format::AtlasExr,
        Format::Dds,
    ];

    /// The name on the command line (`--format`), in the manifest and in the Export dialog.
    pub fn name(self) -> &'static str {
        match self {
            Self::Exr => "exr",
            Self::Png8 => "png8",
            Self::Png16 => "png16",
            Self::Fga => "fga",
            Self::Vf => "vf",
            Self::Raw => "raw",
            Self::Atlas => "atlas",
            Self::AtlasExr => "atlas-exr",
            Self::Dds => "dds",
        }
    }
}

impl Format {
    /// What the format is and which engine reads it, for the Export dialog's tooltips
    /// (docs/engines/ has each engine's import).
    pub fn engines_hint(self) -> &'static str {
        match self {
            Self::Exr => {
                "OpenEXR flowmap, float (x, z wind and speed in m/s): Godot's and Unreal's \
                 textures, Unity's too; exact"
            }
            Self::Png8 => "8-bit PNG flowmap: any engine's texture, the smallest (mobile)",
            Self::Png16 => {
                "16-bit PNG flowmap: Unity's and Godot's textures, and Godot on the web (8 bits \
                 there)"
            }
            Self::Fga => "Unreal vector field (FGA) for Niagara and Cascade, at most 128 a side",
            Self::Vf => "Unity VFX Graph vector field (VF_V) for Vector Field Force",
            Self::Raw => {
                "Raw floats with the manifest: windloom's runtime (C, Bevy), your own engine \
                 code, and Godot on the web; exact"
            }
            Self::Atlas => {
                "Every frame in one 16-bit PNG flipbook: animated wind in Unreal's Niagara and \
                 Godot's shaders"
            }
            Self::AtlasExr => "Every frame in one half-float EXR flipbook: animated wind in Godot",
            Self::Dds => {
                "The wind as a volume up the vertical profile: a DDS 3D texture (Unreal, any \
                 engine), with a Unity vector field and Godot EXR slices of it"
            }
        }
    }
}

/// How big a bake is: `frames` frames of `nx × ny` cells, `layers` layers in a volume, and
/// `half`: 16-bit floats where the format has them.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Extent {
    pub nx: usize,
    pub ny: usize,
    pub layers: usize,
    pub frames: usize,
    pub half: bool,
}

/// What a format's file answers for it.
pub(crate) trait Encoder: Sync {
    /// The files it writes in a bake of `count` frames.
    fn names(&self, count: usize) -> Vec<String>;

    /// An upper bound of the bytes it writes for a bake of `size`.
    fn max_bytes(&self, size: &Extent) -> u64;

    /// The files of frame `k`, for a format with files per frame; none for one whose single
    /// file holds every frame (written beside the frame loop: `raw`, `atlas`).
    fn frame(&self, ctx: &ExportContext, k: usize, f: &Field) -> Result<Vec<Output>, BakeError>;
}

/// The file name of frame `k` of `count` with extension `ext`: `STEM.EXT` for one frame,
/// `STEM_0000.EXT`… for a sequence.
pub(crate) fn frame_name(stem: &str, k: usize, count: usize, ext: &str) -> String {
    if count == 1 {
        format!("{stem}.{ext}")
    } else {
        format!("{stem}_{k:04}.{ext}")
    }
}

/// The names of a format with one file per frame.
pub(crate) fn frame_names(stem: &str, count: usize, ext: &str) -> Vec<String> {
    (0..count)
        .map(|k| frame_name(stem, k, count, ext))
        .collect()
}
