//! The manifest's `engines` block: per engine, the exact import settings and parameters the
//! guides in `docs/engines/` quote and the engine scripts read, for the files this bake holds.
//! Names are the engines' own: Unity's Inspector labels, Unreal's Python enum values, Godot
//! 4's `.import` keys and shader uniforms.

use super::manifest::FileEntry;
use super::{ExportContext, Format};
use schemars::JsonSchema;
use serde::Serialize;

/// Settings per engine; an engine is absent when the bake holds no file it reads.
#[derive(Debug, Clone, Default, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct Engines {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unity: Option<Unity>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unreal: Option<Unreal>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub godot: Option<Godot>,
}

/// Unity (`docs/engines/unity.md`).
#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct Unity {
    /// VFX Graph's *Vector Field Force* on the `vf` files.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vector_field: Option<UnityVectorField>,
    /// The same block on the volume's `wind_volume.vf` files (`dds`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub volume: Option<UnityVectorField>,
}

#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct UnityVectorField {
    pub files: Vec<String>,
    /// The VF importer's Inspector.
    pub import: UnityVfImport,
    pub block: &'static str,
    /// *Data Encoding*: `Signed`.
    pub data_encoding: &'static str,
    pub intensity: f32,
    pub closed_field: bool,
    pub conserve_magnitude: bool,
    /// *Field Transform* position, Unity metres.
    pub box_center: [f32; 3],
    /// *Field Transform* scale, Unity metres: the size each stored value is multiplied by.
    pub box_size: [f32; 3],
}

#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct UnityVfImport {
    pub output_format: &'static str,
    pub wrap_mode: &'static str,
    pub filter_mode: &'static str,
}

/// Unreal (`docs/engines/unreal.md`).
#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct Unreal {
    /// The `fga` files as *Vector Field Static* assets for Niagara.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vector_field_static: Option<UnrealVectorField>,
    /// The atlas sampled in a Niagara scratch pad (the animated path).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub niagara_atlas: Option<UnrealAtlas>,
    /// The `exr` files in a grass material's World Position Offset.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub material_texture: Option<UnrealMaterialTexture>,
    /// The volume's `wind_volume.dds` files as Volume Textures, sampled in Niagara.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub volume_texture: Option<UnrealVolume>,
}

#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct UnrealVolume {
    pub files: Vec<String>,
    /// `TextureCompressionSettings`: `TC_HDR_F32` for 32-bit floats, `TC_HDR` for `--half`.
    pub compression_settings: &'static str,
    pub srgb: bool,
    pub mip_gen_settings: &'static str,
    /// `TextureAddress`, all three axes.
    pub address_mode: &'static str,
    pub filter: &'static str,
    /// The volume's minimum corner and size in Unreal cm (X east, Y south, Z up): a sample
    /// at `uvw = (position − min) / size`.
    pub bounds_min_cm: [f32; 3],
    pub bounds_size_cm: [f32; 3],
    /// Unreal's wind in cm/s from a sample: `float3(R, B, G) × 100` (the file holds world
    /// x, y, z; Unreal's Y is world z, its Z world y).
    pub swizzle: &'static str,
}

#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct UnrealVectorField {
    pub files: Vec<String>,
    /// The asset's *Intensity*: 1 gives the stored cm/s.
    pub intensity: f32,
    /// The asset's bounds, cm (Unreal X, Y, Z).
    pub bounds_min_cm: [f32; 3],
    pub bounds_max_cm: [f32; 3],
}

/// A texture asset's settings, as Unreal's Python API names them.
#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct UnrealTexture {
    /// `TextureCompressionSettings`.
    pub compression_settings: &'static str,
    pub srgb: bool,
    /// `TextureMipGenSettings`.
    pub mip_gen_settings: &'static str,
    /// `TextureAddress`, both axes.
    pub address_x: &'static str,
    pub address_y: &'static str,
    /// `TextureFilter`.
    pub filter: &'static str,
}

const UNREAL_HDR: UnrealTexture = UnrealTexture {
    compression_settings: "TC_HDR",
    srgb: false,
    mip_gen_settings: "TMGS_NO_MIPMAPS",
    address_x: "TA_CLAMP",
    address_y: "TA_CLAMP",
    filter: "TF_BILINEAR",
};

#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct UnrealAtlas {
    pub file: String,
    pub texture: UnrealTexture,
    /// The scratch pad's inputs (Unreal X, Y = world x, z; cm).
    pub bounds_min_cm: [f32; 2],
    pub bounds_size_cm: [f32; 2],
    pub grid: [usize; 2],
    pub frames: usize,
    pub fps: f32,
    /// Flowmap scale, m/s: `wind (cm/s) = (sample.rg · 2 − 1) · scale · 100`.
    pub scale: f32,
    pub atlas_size: [usize; 2],
}

#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct UnrealMaterialTexture {
    pub files: Vec<String>,
    pub texture: UnrealTexture,
    pub bounds_min_cm: [f32; 2],
    pub bounds_size_cm: [f32; 2],
}

/// Godot 4 (`docs/engines/godot.md`).
#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct Godot {
    /// The textures to import with `import` (EXR, flowmaps, atlas).
    pub textures: Vec<String>,
    /// The `[params]` of each texture's `.import` file (ResourceImporterTexture).
    pub import: GodotImport,
    /// `windloom_grass.gdshader`'s uniforms.
    pub shader_parameters: GodotShader,
    /// The volume's EXR slices as `Texture3D`s, for `windloom_particles.gdshader`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub volume: Option<GodotVolume>,
}

#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct GodotVolume {
    pub files: Vec<String>,
    /// The `.import` file's `[remap]` importer: `3d_texture`.
    pub importer: &'static str,
    /// The resource type: `CompressedTexture3D`.
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// The `.import` file's `[params]`.
    pub import: GodotVolumeImport,
    /// `windloom_particles.gdshader`'s uniforms: the volume's minimum corner and size, metres.
    pub volume_min: [f32; 3],
    pub volume_size: [f32; 3],
}

#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct GodotVolumeImport {
    /// 3: VRAM Uncompressed (keeps the floats).
    #[serde(rename = "compress/mode")]
    pub compress_mode: u8,
    #[serde(rename = "mipmaps/generate")]
    pub mipmaps: bool,
    #[serde(rename = "slices/horizontal")]
    pub horizontal: u32,
    /// The layers.
    #[serde(rename = "slices/vertical")]
    pub vertical: u32,
}

#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct GodotImport {
    /// 0: Lossless.
    #[serde(rename = "compress/mode")]
    pub compress_mode: u8,
    /// 2: Disabled.
    #[serde(rename = "compress/normal_map")]
    pub normal_map: u8,
    #[serde(rename = "mipmaps/generate")]
    pub mipmaps: bool,
    #[serde(rename = "process/fix_alpha_border")]
    pub fix_alpha_border: bool,
    /// 0: Disabled (the default, 1, VRAM-compresses the texture once a 3D material uses it).
    #[serde(rename = "detect_3d/compress_to")]
    pub detect_3d: u8,
}

#[derive(Debug, Clone, Serialize, JsonSchema, PartialEq)]
#[schemars(deny_unknown_fields)]
pub struct GodotShader {
    pub bounds_min: [f32; 2],
    pub bounds_max: [f32; 2],
    /// The steady field (the first EXR), when the bake has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wind_tex: Option<String>,
    pub use_atlas: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wind_atlas: Option<String>,
    /// The atlas holds m/s as floats (`atlas.exr`), not a flowmap.
    pub atlas_is_float: bool,
    pub atlas_grid: [usize; 2],
    pub atlas_frames: usize,
    pub atlas_fps: f32,
    pub atlas_scale: f32,
}

const CM: f32 = 100.0;

/// The engines block for a bake's files.
pub(crate) fn engines(ctx: &ExportContext, files: &[FileEntry]) -> Engines {
    let names = |format: Format| -> Vec<String> {
        files
            .iter()
            .filter(|f| f.format == format)
            .map(|f| f.name.clone())
            .collect()
    };
    let (min, max) = (ctx.min, ctx.max);
    let min_cm = [min[0] * CM, min[1] * CM];
    let size_cm = [(max[0] - min[0]) * CM, (max[1] - min[1]) * CM];
    let atlas = files.iter().find(|f| f.format == Format::Atlas);
    // Godot reads the EXR atlas at full precision, the PNG one at 8 bits: the EXR first.
    let godot_atlas = files
        .iter()
        .find(|f| f.format == Format::AtlasExr)
        .or(atlas);

    // The volume's files by extension.
    let volume = |ext: &str| -> Vec<String> {
        names(Format::Dds)
            .into_iter()
            .filter(|n| n.ends_with(ext))
            .collect()
    };
    // The box of a field `box_size` high standing on the ground (the volume), or of a 1 m
    // slab centred on it (the 2D field).
    let vector_field = |files: Vec<String>, box_size: [f32; 3], centre_y: f32| {
        (!files.is_empty()).then(|| UnityVectorField {
            files,
            import: UnityVfImport {
                output_format: "Float",
                wrap_mode: "Clamp",
                filter_mode: "Bilinear",
            },
            block: "Vector Field Force",
            data_encoding: "Signed",
            intensity: 1.0,
            closed_field: true,
            conserve_magnitude: false,
            box_center: [(min[0] + max[0]) / 2.0, centre_y, -(min[1] + max[1]) / 2.0],
            box_size,
        })
    };
    let unity = Unity {
        vector_field: vector_field(names(Format::Vf), super::vf::box_size(ctx), 0.0),
        volume: vector_field(
            volume(".vf"),
            super::volume::unity_box(ctx),
            ctx.profile.top / 2.0,
        ),
    };
    let unity = (unity.vector_field.is_some() || unity.volume.is_some()).then_some(unity);

    let fga = names(Format::Fga);
    let exr = names(Format::Exr);
    let vector_field_static = (!fga.is_empty()).then(|| UnrealVectorField {
        files: fga,
        intensity: 1.0,
        bounds_min_cm: [min_cm[0], min_cm[1], 0.0],
        bounds_max_cm: [max[0] * CM, max[1] * CM, super::fga::FGA_HEIGHT_CM],
    });
    let niagara_atlas = atlas.map(|a| {
        let sub = a.axes.sub_images.as_ref().expect("an atlas has sub-images");
        UnrealAtlas {
            file: a.name.clone(),
            texture: UNREAL_HDR,
            bounds_min_cm: min_cm,
            bounds_size_cm: size_cm,
            grid: [sub.columns, sub.rows],
            frames: sub.count,
            fps: sub.fps,
            scale: ctx.flow_scale(),
            atlas_size: [sub.columns * a.grid[0], sub.rows * a.grid[1]],
        }
    });
    let material_texture = (!exr.is_empty()).then(|| UnrealMaterialTexture {
        files: exr.clone(),
        texture: UNREAL_HDR,
        bounds_min_cm: min_cm,
        bounds_size_cm: size_cm,
    });
    let dds = volume(".dds");
    let top = ctx.profile.top;
    let volume_texture = (!dds.is_empty()).then(|| UnrealVolume {
        files: dds,
        compression_settings: if ctx.half { "TC_HDR" } else { "TC_HDR_F32" },
        srgb: false,
        mip_gen_settings: "TMGS_NO_MIPMAPS",
        address_mode: "TA_CLAMP",
        filter: "TF_BILINEAR",
        bounds_min_cm: [min_cm[0], min_cm[1], 0.0],
        bounds_size_cm: [size_cm[0], size_cm[1], top * CM],
        swizzle: "wind_cm_s = float3(R, B, G) * 100",
    });
    let unreal = (vector_field_static.is_some()
        || niagara_atlas.is_some()
        || material_texture.is_some()
        || volume_texture.is_some())
    .then_some(Unreal {
        vector_field_static,
        niagara_atlas,
        material_texture,
        volume_texture,
    });

    let textures: Vec<String> = files
        .iter()
        .filter(|f| {
            matches!(
                f.format,
                Format::Exr | Format::Png8 | Format::Png16 | Format::Atlas | Format::AtlasExr
            )
        })
        .map(|f| f.name.clone())
        .collect();
    let slices = volume(".exr");
    let godot_volume = (!slices.is_empty()).then(|| GodotVolume {
        files: slices,
        importer: "3d_texture",
        kind: "CompressedTexture3D",
        import: GodotVolumeImport {
            compress_mode: 3,
            mipmaps: false,
            horizontal: 1,
            vertical: ctx.profile.layers,
        },
        volume_min: [min[0], 0.0, min[1]],
        volume_size: [max[0] - min[0], top, max[1] - min[1]],
    });
    let godot = (!textures.is_empty() || godot_volume.is_some()).then(|| {
        let sub = godot_atlas.and_then(|a| a.axes.sub_images.as_ref());
        let float = godot_atlas.is_some_and(|a| a.format == Format::AtlasExr);
        Godot {
            textures,
            import: GodotImport {
                compress_mode: 0,
                normal_map: 2,
                mipmaps: false,
                fix_alpha_border: false,
                detect_3d: 0,
            },
            shader_parameters: GodotShader {
                bounds_min: min,
                bounds_max: max,
                wind_tex: exr.first().cloned(),
                use_atlas: godot_atlas.is_some(),
                wind_atlas: godot_atlas.map(|a| a.name.clone()),
                atlas_is_float: float,
                atlas_grid: sub.map_or([1, 1], |s| [s.columns, s.rows]),
                atlas_frames: sub.map_or(1, |s| s.count),
                atlas_fps: sub.map_or(ctx.fps, |s| s.fps),
                atlas_scale: if float { 1.0 } else { ctx.flow_scale() },
            },
            volume: godot_volume,
        }
    });
    Engines {
        unity,
        unreal,
        godot,
    }
}
