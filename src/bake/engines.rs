//! The manifest's `engines` block, filled: per engine, the exact import settings and parameters the
//! guides in `docs/engines/` quote and the engine scripts read, for the files this bake holds.
//! Names are the engines' own: Unity's Inspector labels, Unreal's Python enum values, Godot
//! 4's `.import` keys and shader uniforms.

use super::format::ExportContext;
use super::manifest::engines::*;
use super::manifest::{FileEntry, Format};

/// The texture settings of Unreal's float wind textures.
const UNREAL_HDR: UnrealTexture = UnrealTexture {
    compression_settings: "TC_HDR",
    srgb: false,
    mip_gen_settings: "TMGS_NO_MIPMAPS",
    address_x: "TA_CLAMP",
    address_y: "TA_CLAMP",
    filter: "TF_BILINEAR",
};

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
