//! The formats a bake writes, as the manifest, the command line and the Export dialog name
//! them.

use serde::Serialize;

/// Output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, PartialOrd, Ord)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
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

    /// The format of this name ([`Format::name`]).
    pub fn from_name(name: &str) -> Option<Format> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

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
