//! The manifest's `engines` block: per engine, the exact import settings and parameters the
//! guides in `docs/engines/` quote and the engine scripts read. Names are the engines' own:
//! Unity's Inspector labels, Unreal's Python enum values, Godot 4's `.import` keys and shader
//! uniforms. `bake/engines.rs` fills it for a bake's files.

use serde::Serialize;

/// Settings per engine; an engine is absent when the bake holds no file it reads.
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct Engines {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unity: Option<Unity>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unreal: Option<Unreal>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub godot: Option<Godot>,
}

/// Unity (`docs/engines/unity.md`).
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct Unity {
    /// VFX Graph's *Vector Field Force* on the `vf` files.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vector_field: Option<UnityVectorField>,
    /// The same block on the volume's `wind_volume.vf` files (`dds`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub volume: Option<UnityVectorField>,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
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

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct UnityVfImport {
    pub output_format: &'static str,
    pub wrap_mode: &'static str,
    pub filter_mode: &'static str,
}

/// Unreal (`docs/engines/unreal.md`).
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
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

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
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

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct UnrealVectorField {
    pub files: Vec<String>,
    /// The asset's *Intensity*: 1 gives the stored cm/s.
    pub intensity: f32,
    /// The asset's bounds, cm (Unreal X, Y, Z).
    pub bounds_min_cm: [f32; 3],
    pub bounds_max_cm: [f32; 3],
}

/// A texture asset's settings, as Unreal's Python API names them.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
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

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
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

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct UnrealMaterialTexture {
    pub files: Vec<String>,
    pub texture: UnrealTexture,
    pub bounds_min_cm: [f32; 2],
    pub bounds_size_cm: [f32; 2],
}

/// Godot 4 (`docs/engines/godot.md`).
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
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

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
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

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
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

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
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

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
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
