//! The grass renderer: blades as GPU instances in the live wind over a ground plane, shaped by
//! the CWD-Sim model (`src/grass/cwd.rs` is its CPU twin) or by Jahrmann's Bezier physics
//! (`src/grass/bezier.rs`). Per-blade data is uploaded once; per frame the CPU writes one
//! small scene uniform (camera, time, sphere) and, when it changes, the wind grid. Each frame:
//! the trail pass (while a sphere pushes or its trail lasts), the model's compute pass (CWD
//! poses or Bezier steps), the far field (the grass's look from afar, which the ground shows
//! where blades are missing), the cull pass (orientation, frustum, distance, LOD → per-level
//! visible lists and indirect draw arguments), then ground, scene and one indirect draw per
//! LOD level, each blade a strip built in the vertex shader from its index. Passes:
//! `shaders/grass_*.wgsl`, sharing `grass_common.wgsl` (and `grass_shape.wgsl` for the cull
//! pass and the blades).
//!
//! Takes `&wgpu::Device` / `&wgpu::Queue` and never egui. `camera.rs`: the glam camera and
//! the orbit that frames the world; `cull.rs`, `bezier.rs`, `trail.rs`, `far.rs`: those
//! passes' buffers and pipelines; `draw.rs`: the render pipelines; `backdrop.rs`: the map
//! image on the ground; `target.rs`: the colour + depth target and whole frames into it;
//! `headless.rs`: pictures and the benchmark for the CLI.

mod backdrop;
mod bezier;
mod camera;
mod cull;
mod draw;
pub use draw::SAMPLES;
mod far;
mod headless;
mod target;
mod trail;

use backdrop::{backdrop_texture, look_group, look_layout};
pub use bezier::{BezierPass, BezierState};
pub use camera::{Camera, FRAME_MARGIN, FRAME_PITCHES_DEG, Orbit};
pub use cull::{CullPass, CullStats, CullUniform, strip_vertices};
pub use far::{FarPass, FarUniform};
pub use headless::{
    BenchOptions, GrassBench, GrassEstimate, PictureOptions, PushPath, Written, bench,
    count_written, estimate, picture, settle,
};
pub use target::{FramePart, Target, render_into, render_offscreen};

use super::GpuError;
use super::buffer_entry as entry;
use super::{buffers_group, storage};
use crate::doc::GrassModel;
use crate::doc::Layout;
use crate::grass::cull::{CullParams, LOD_SEGMENTS};
use crate::grass::scene::SceneVertex;
use crate::grass::trail::Sphere;
use crate::grass::{Blade, cwd};
use bytemuck::{Pod, Zeroable};
use glam::Mat4;
use wgpu::util::DeviceExt;

/// The shared header of the grass passes.
pub const COMMON: &str = include_str!("../../../shaders/grass_common.wgsl");
/// The second header of the passes that read a blade's curve whatever the model.
pub const SHAPE: &str = include_str!("../../../shaders/grass_shape.wgsl");

/// Every grass pass's shader: `(name, source)`, each compiled after [`COMMON`] (and
/// [`SHAPE`] for `grass_cull` and `grass_blades`).
pub const SHADERS: [(&str, &str); 10] = [
    (
        "grass_cull",
        include_str!("../../../shaders/grass_cull.wgsl"),
    ),
    (
        "grass_trail",
        include_str!("../../../shaders/grass_trail.wgsl"),
    ),
    (
        "grass_bezier",
        include_str!("../../../shaders/grass_bezier.wgsl"),
    ),
    (
        "grass_wind",
        include_str!("../../../shaders/grass_wind.wgsl"),
    ),
    (
        "grass_scene",
        include_str!("../../../shaders/grass_scene.wgsl"),
    ),
    (
        "grass_deform",
        include_str!("../../../shaders/grass_deform.wgsl"),
    ),
    (
        "grass_blades",
        include_str!("../../../shaders/grass_blades.wgsl"),
    ),
    (
        "grass_ground",
        include_str!("../../../shaders/grass_ground.wgsl"),
    ),
    ("grass_far", include_str!("../../../shaders/grass_far.wgsl")),
    ("grass_sky", include_str!("../../../shaders/grass_sky.wgsl")),
];

/// The full WGSL of grass pass `name` (the common header, then the pass; `grass_wind` alone:
/// it writes the wind grid the header declares read-only).
pub fn shader_source(name: &str) -> Option<String> {
    SHADERS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(n, s)| match *n {
            "grass_wind" => s.to_string(),
            "grass_cull" | "grass_blades" => format!("{COMMON}\n{SHAPE}\n{s}"),
            _ => format!("{COMMON}\n{s}"),
        })
}

/// Records a dispatch of 64-wide workgroups over `blades` blades, in two dimensions when one
/// would exceed the 65,535-workgroup limit (`blade_index` in `grass_common.wgsl`).
pub(super) fn dispatch_blades(pass: &mut wgpu::ComputePass<'_>, blades: u32) {
    let groups = blades.div_ceil(64);
    if groups == 0 {
        return;
    }
    let x = groups.min(65_535);
    pass.dispatch_workgroups(x, groups.div_ceil(x), 1);
}

/// The scene; mirrors `struct Scene` in `shaders/grass_common.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Scene {
    /// World → clip space with reversed depth ([`Camera::draw_view_proj`]).
    pub view_proj: [[f32; 4]; 4],
    /// The inverse of [`Camera::view_proj`], the usual depth (the sky's view rays, from depth 0
    /// at the near plane to 1 at the far one).
    pub inv_view_proj: [[f32; 4]; 4],
    pub eye: [f32; 4],
    pub sun: [f32; 4],
    pub origin: [f32; 2],
    pub cell: [f32; 2],
    pub nx: u32,
    pub ny: u32,
    pub blades: u32,
    pub segments: u32,
    pub k1: f32,
    pub k2: f32,
    pub lambda: f32,
    pub response: f32,
    pub bend_max: f32,
    pub flutter: f32,
    pub flutter_hz: f32,
    pub saturation: f32,
    pub c1: f32,
    pub c2: f32,
    pub m_min: f32,
    pub m_max: f32,
    pub world_min: [f32; 2],
    pub world_max: [f32; 2],
    pub palettes: u32,
    pub srgb_target: u32,
    /// 1: the paper's equations as printed (pictures of its failure only).
    pub literal: u32,
    /// Opacity of the map backdrop over the ground (0: none).
    pub backdrop: f32,
    /// The pushing sphere: centre and radius (0: none).
    pub sphere: [f32; 4],
    pub trail_origin: [f32; 2],
    pub trail_cell: [f32; 2],
    pub trail_nx: u32,
    pub trail_ny: u32,
    /// 0: CWD; 1: Bezier.
    pub model: u32,
    pub trail_on: u32,
    pub dt: f32,
    pub lifetime: f32,
    /// The wind colours' opacity over the grass and ground (0: off).
    pub wind_colours: f32,
    /// The speed, m/s, at the top of the wind colours' scale.
    pub wind_scale: f32,
    /// Where the map backdrop lies: `[x0, z0, x1, z1]` in metres.
    pub backdrop_rect: [f32; 4],
    /// The terrain's heights (binding 5, `ground` in grass_common.wgsl): one per cell centre
    /// of a grid of `ground_nx × ground_ny` cells of `ground_cell` metres from
    /// `ground_origin`; the ground mesh has `ground_quads` quads (`[0, 0]`: flat, y = 0).
    pub ground_origin: [f32; 2],
    pub ground_cell: [f32; 2],
    pub ground_nx: u32,
    pub ground_ny: u32,
    pub ground_quads: [u32; 2],
    /// Metres from the eye over which the far plane fades into the horizon's colour
    /// ([`crate::grass::light::haze`]).
    pub fade: [f32; 2],
    pub _pad_fade: [f32; 2],
}

/// Quads along each side of the ground mesh over terrain, at most (one a height cell below
/// that).
pub const GROUND_QUADS_MAX: u32 = 256;

/// The ground the 3D view stands on: the terrain's heights (`sim::terrain::TerrainField`'s,
/// one a cell centre of its grid) and where they lie; a single 0 and a flat ground without
/// terrain.
struct Ground {
    heights: Vec<f32>,
    origin: [f32; 2],
    cell: [f32; 2],
    grid: [u32; 2],
    quads: [u32; 2],
}

impl Ground {
    fn of(layout: &Layout, terrain: Option<&crate::sim::terrain::TerrainField>) -> Self {
        let (min, _) = layout.bounds();
        match terrain {
            Some(t) => {
                let grid = [t.nx as u32, t.ny as u32];
                Self {
                    origin: t.origin,
                    cell: t.cell,
                    quads: grid.map(|n| n.min(GROUND_QUADS_MAX)),
                    grid,
                    heights: t.heights.clone(),
                }
            }
            None => Self {
                heights: vec![0.0],
                origin: min,
                cell: [1.0, 1.0],
                grid: [1, 1],
                quads: [0, 0],
            },
        }
    }
}

/// A blade's pose this frame; mirrors `struct Pose` in `shaders/grass_common.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Pose {
    pub push: [f32; 2],
    pub scale: f32,
    pub dim: f32,
}

/// The sun: unit-ish vector toward it (xyz) and the sky's share of the light (w).
pub const SUN: [f32; 4] = [0.42, 0.80, 0.43, 0.32];
/// Segments of a blade at full detail.
pub const SEGMENTS: u32 = LOD_SEGMENTS[0];
/// How long the sphere's trail lasts by default, seconds.
pub const TRAIL_LIFETIME: f32 = 3.0;
/// The depth buffer format the renderer draws with.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Blades, wind and pipelines for one layout's grass.
pub struct GrassRenderer {
    scene: Scene,
    /// Blades uploaded.
    total: u32,
    scene_buf: wgpu::Buffer,
    blades: wgpu::Buffer,
    wind: wgpu::Buffer,
    palettes: wgpu::Buffer,
    /// The terrain's heights (`Scene::ground_*`), and the terrain they came from.
    ground: wgpu::Buffer,
    terrain: Option<std::sync::Arc<crate::sim::terrain::TerrainField>>,
    /// Per-blade poses, written by the deform pass each frame (bound in the groups below).
    poses: wgpu::Buffer,
    layout0: wgpu::BindGroupLayout,
    group0: wgpu::BindGroup,
    /// The poses for the deform pass to write.
    group_deform: wgpu::BindGroup,
    /// Poses and Bezier states, read-only (group 1 of the cull pass and the blades).
    layout_shape: wgpu::BindGroupLayout,
    group_shape: wgpu::BindGroup,
    deform: wgpu::ComputePipeline,
    /// The ground, obstacles, arrows and blades, plain or with the wind colours.
    draw: draw::DrawPipelines,
    /// The Bezier model's states and pass, while that model is chosen.
    bezier: Option<bezier::BezierPass>,
    cull: CullPass,
    /// Whether the blades are drawn nearest first (on by default; off: in their stored order,
    /// which `bench --grass --stored-order` times against it).
    near_first: bool,
    trail: trail::TrailPass,
    /// The grass's look from afar, which the ground shows where blades are missing.
    far: FarPass,
    /// Seconds the trail still holds anything (the trail pass and its reads are skipped at 0).
    trail_left: f32,
    /// Obstacles as solids, the arrows, and the map's footprint (vertex buffer, count).
    solids: Option<(wgpu::Buffer, u32)>,
    lines: Option<(wgpu::Buffer, u32)>,
    footprint: Option<(wgpu::Buffer, u32)>,
    /// The faces → wind grid pass for a GPU-run field, its grid uniform, and its bind group
    /// for the field last bound.
    wind_pipeline: wgpu::ComputePipeline,
    wind_grid: wgpu::Buffer,
    wind_group: Option<(super::mapview::FieldBuffers, wgpu::BindGroup)>,
    /// The map backdrop's image (1 × 1 until one is set).
    backdrop: wgpu::Texture,
    /// What the ground (group 1) and the blades (group 3) read the far field and the backdrop
    /// through (`backdrop::look_layout`), made again when either changes.
    look_layout: wgpu::BindGroupLayout,
    look_group: wgpu::BindGroup,
}

/// Group 0: the scene, blades, wind and palettes, and the trail.
fn scene_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    buffers: [&wgpu::Buffer; 4],
    trail: &wgpu::Texture,
    ground: &wgpu::Buffer,
) -> wgpu::BindGroup {
    let view = trail.create_view(&Default::default());
    let mut entries = super::buffer_entries(&buffers);
    entries.push(wgpu::BindGroupEntry {
        binding: 4,
        resource: wgpu::BindingResource::TextureView(&view),
    });
    entries.push(wgpu::BindGroupEntry {
        binding: 5,
        resource: ground.as_entire_binding(),
    });
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("grass scene"),
        layout,
        entries: &entries,
    })
}

fn vertices(device: &wgpu::Device, v: &[SceneVertex]) -> Option<(wgpu::Buffer, u32)> {
    (!v.is_empty()).then(|| {
        let b = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("grass scene"),
            contents: bytemuck::cast_slice(v),
            usage: wgpu::BufferUsages::VERTEX,
        });
        (b, v.len() as u32)
    })
}

/// The most blades a device with `limits` can hold: its largest per-blade array (the Bezier
/// model's control points, 48 bytes a blade) must fit one storage-buffer binding. Lavapipe
/// binds 128 MiB: about 2.8 million blades. Never more than [`crate::grass::MAX_BLADES`].
pub fn max_blades(limits: &wgpu::Limits) -> usize {
    let cap = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    let widest = [
        std::mem::size_of::<Blade>(),
        std::mem::size_of::<Pose>(),
        std::mem::size_of::<BezierState>(),
    ]
    .into_iter()
    .max()
    .unwrap_or(1) as u64;
    usize::try_from(cap / widest)
        .unwrap_or(usize::MAX)
        .min(crate::grass::MAX_BLADES)
}

impl GrassRenderer {
    /// The grass of `layout` (its `blades`, from [`crate::grass::scatter`]) for targets of
    /// `format` with a [`DEPTH_FORMAT`] depth buffer. The wind starts calm.
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        layout: &Layout,
        blades: &[Blade],
    ) -> Self {
        use wgpu::ShaderStages as S;
        let g = &layout.grass;
        let (min, max) = layout.bounds();
        let (trail_nx, trail_ny) = crate::grass::trail::grid(min, max);
        let terrain = crate::sim::terrain::TerrainField::new(layout).map(std::sync::Arc::new);
        let ground = Ground::of(layout, terrain.as_deref());
        let scene = Scene {
            view_proj: Mat4::IDENTITY.to_cols_array_2d(),
            inv_view_proj: Mat4::IDENTITY.to_cols_array_2d(),
            eye: [0.0; 4],
            sun: SUN,
            origin: min,
            cell: [1.0, 1.0],
            nx: 1,
            ny: 1,
            blades: blades.len() as u32,
            segments: SEGMENTS,
            k1: g.k1,
            k2: g.k2,
            lambda: g.lambda,
            response: cwd::WIND_RESPONSE,
            bend_max: cwd::BEND_MAX,
            flutter: cwd::FLUTTER,
            flutter_hz: cwd::FLUTTER_HZ,
            saturation: cwd::SATURATION,
            c1: g.shadow.c1,
            c2: g.shadow.c2,
            m_min: g.shadow.m_min,
            m_max: g.shadow.m_max,
            world_min: min,
            world_max: max,
            palettes: g.palettes.len().max(1) as u32,
            srgb_target: u32::from(format.is_srgb()),
            literal: 0,
            backdrop: 0.0,
            sphere: [0.0; 4],
            trail_origin: min,
            trail_cell: [
                (max[0] - min[0]) / trail_nx as f32,
                (max[1] - min[1]) / trail_ny as f32,
            ],
            trail_nx,
            trail_ny,
            model: 0,
            trail_on: 0,
            dt: 0.0,
            lifetime: TRAIL_LIFETIME,
            wind_colours: 0.0,
            wind_scale: 1.0,
            backdrop_rect: {
                let [a, b] = layout
                    .world
                    .map
                    .as_ref()
                    .map_or([min, max], |m| m.placed((min, max)));
                [a[0], a[1], b[0], b[1]]
            },
            ground_origin: ground.origin,
            ground_cell: ground.cell,
            ground_nx: ground.grid[0],
            ground_ny: ground.grid[1],
            ground_quads: ground.quads,
            fade: [1e6, 2e6],
            _pad_fade: [0.0; 2],
        };
        let mut colours: Vec<[f32; 4]> = g
            .palettes
            .iter()
            .flat_map(|p| {
                [
                    [p.base[0], p.base[1], p.base[2], 1.0],
                    [p.tip[0], p.tip[1], p.tip[2], 1.0],
                ]
            })
            .collect();
        if colours.is_empty() {
            let (b, t) = (
                crate::grass::far::FALLBACK_BASE,
                crate::grass::far::FALLBACK_TIP,
            );
            colours = vec![[b[0], b[1], b[2], 1.0], [t[0], t[1], t[2], 1.0]];
        }
        // The wind colours' scale after the palettes (`wind_colour` in grass_common.wgsl).
        colours.extend(crate::colour::speed_table_linear());
        // Storage buffers may not be empty.
        let blade_bytes: &[u8] = if blades.is_empty() {
            &[0; std::mem::size_of::<Blade>()]
        } else {
            bytemuck::cast_slice(blades)
        };
        let n = blades.len().max(1) as u64;
        let scene_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("grass scene"),
            contents: bytemuck::bytes_of(&scene),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let blades_buf = storage(device, "grass blades", blade_bytes);
        let wind = storage(device, "grass wind", &[0; 8]);
        let palettes = storage(device, "grass palettes", bytemuck::cast_slice(&colours));
        let poses = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("grass poses"),
            size: n * std::mem::size_of::<Pose>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let all = S::VERTEX | S::FRAGMENT | S::COMPUTE;
        let ro = wgpu::BufferBindingType::Storage { read_only: true };
        let rw = wgpu::BufferBindingType::Storage { read_only: false };
        let layout0 = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass scene"),
            entries: &[
                entry(0, all, wgpu::BufferBindingType::Storage { read_only: true }),
                entry(1, all, ro),
                entry(2, all, ro),
                entry(3, all, ro),
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: all,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                entry(5, all, ro),
            ],
        });
        let layout_deform = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass poses (deform)"),
            entries: &[entry(0, S::COMPUTE, rw)],
        });
        let layout_shape = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass shape"),
            entries: &[
                entry(0, S::VERTEX | S::COMPUTE, ro),
                entry(1, S::VERTEX | S::COMPUTE, ro),
            ],
        });
        let module = |name: &str| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(name),
                source: wgpu::ShaderSource::Wgsl(shader_source(name).expect("listed").into()),
            })
        };
        let trail = trail::TrailPass::new(
            device,
            &layout0,
            &module("grass_trail"),
            (trail_nx, trail_ny),
        );
        let ground = storage(
            device,
            "grass ground",
            bytemuck::cast_slice(&ground.heights),
        );
        let group0 = scene_group(
            device,
            &layout0,
            [&scene_buf, &blades_buf, &wind, &palettes],
            &trail.texture,
            &ground,
        );
        let group_deform = buffers_group(device, "grass poses", &layout_deform, &[&poses]);
        // No Bezier states until that model is chosen: a placeholder.
        let no_states = storage(device, "no bezier states", &[0; 48]);
        let group_shape =
            buffers_group(device, "grass shape", &layout_shape, &[&poses, &no_states]);
        let cull = CullPass::new(
            device,
            (&layout0, &layout_shape),
            &module("grass_cull"),
            (blades.len() as u32, &crate::grass::order_by_x(blades)),
            CullParams::for_grass(g),
        );
        let far = FarPass::new(
            device,
            &layout0,
            &module("grass_far"),
            layout,
            blades.len() as u32,
            scene.sun,
        );
        let compute_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("grass deform"),
            bind_group_layouts: &[Some(&layout0), Some(&layout_deform)],
            immediate_size: 0,
        });
        let deform = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("grass_deform"),
            layout: Some(&compute_layout),
            module: &module("grass_deform"),
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let look_layout = look_layout(device);
        let backdrop = backdrop_texture(device, [1, 1]);
        let look_group = look_group(device, &look_layout, &far, &backdrop);
        let draw = draw::DrawPipelines::new(
            device,
            format,
            &module,
            [&layout0, &layout_shape, &cull.level_layout],
            &look_layout,
        );
        Self {
            total: scene.blades,
            scene,
            scene_buf,
            blades: blades_buf,
            wind,
            palettes,
            ground,
            terrain,
            poses,
            layout0,
            group0,
            group_deform,
            layout_shape,
            group_shape,
            deform,
            draw,
            bezier: None,
            cull,
            near_first: true,
            trail,
            far,
            trail_left: 0.0,
            solids: None,
            lines: None,
            footprint: None,
            wind_pipeline: device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("grass_wind"),
                layout: None,
                module: &module("grass_wind"),
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            }),
            wind_grid: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("grass wind grid"),
                size: 16,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            wind_group: None,
            backdrop,
            look_layout,
            look_group,
        }
    }

    /// Draws eqs. 12–14 as the paper prints them — unbounded bend, no length restored, eq. 14
    /// with the raw speed — to show the problem our reading solves (`docs/GRASS.md`).
    pub fn set_paper_literal(&mut self, literal: bool) {
        self.scene.literal = u32::from(literal);
    }

    /// The terrain the grass and the ground stand on (`None`: flat ground at y = 0).
    pub fn terrain(&self) -> Option<&std::sync::Arc<crate::sim::terrain::TerrainField>> {
        self.terrain.as_ref()
    }

    /// What the view shows besides grass: obstacles as solids and the arrows (a triangle list
    /// and a line list from [`crate::grass::scene`]).
    pub fn set_scene(
        &mut self,
        device: &wgpu::Device,
        solids: &[SceneVertex],
        lines: &[SceneVertex],
    ) {
        self.solids = vertices(device, solids);
        self.lines = vertices(device, lines);
    }

    /// [`Self::set_scene`] from `layout`: its obstacles, and its arrows unless `arrows` is
    /// false (the editor's View → Arrows in the 3D view, `render --no-arrows`).
    pub fn set_layout_scene(&mut self, device: &wgpu::Device, layout: &Layout, arrows: bool) {
        let lines = if arrows {
            crate::grass::scene::arrows(layout)
        } else {
            Vec::new()
        };
        self.set_scene(device, &crate::grass::scene::solids(layout), &lines);
    }

    /// Lays the layout's map backdrop over the ground: `rgba` (sRGB, 8 bits, `size` pixels,
    /// placed where the layout's `world.map` says, as on the map) at `opacity`; `None`
    /// removes it.
    pub fn set_backdrop(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        image: Option<(&[u8], [u32; 2], f32)>,
    ) {
        let Some((rgba, [w, h], opacity)) = image else {
            self.scene.backdrop = 0.0;
            return;
        };
        assert_eq!(
            rgba.len(),
            (w * h * 4) as usize,
            "RGBA8 pixels of the given size"
        );
        let texture = backdrop_texture(device, [w, h]);
        queue.write_texture(
            texture.as_image_copy(),
            rgba,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * w),
                rows_per_image: Some(h),
            },
            texture.size(),
        );
        self.look_group = look_group(device, &self.look_layout, &self.far, &texture);
        self.backdrop = texture;
        self.scene.backdrop = opacity;
    }

    /// The map view's footprint on the ground (a line list; empty: none).
    pub fn set_footprint(&mut self, device: &wgpu::Device, lines: &[SceneVertex]) {
        self.footprint = vertices(device, lines);
    }

    /// Blades drawn.
    pub fn blade_count(&self) -> u32 {
        self.scene.blades
    }

    /// Replaces the blades in the first `blades.len()` slots (at most the uploaded count),
    /// as a view-dependent sample ([`crate::grass::sample`]) does when the camera moves; the
    /// passes then run over those alone (a close view may have fewer blades to draw than the
    /// budget holds). The LOD levels start afresh; a Bezier state whose slot got a new blade
    /// starts at rest (the Bezier pass sees its root moved), the others carry on.
    pub fn replace_blades(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        blades: &[Blade],
    ) {
        let n = blades.len().min(self.total as usize);
        self.scene.blades = n as u32;
        if n == 0 {
            return;
        }
        queue.write_buffer(&self.blades, 0, bytemuck::cast_slice(&blades[..n]));
        self.cull
            .set_order(queue, &crate::grass::order_by_x(&blades[..n]));
        self.cull.reset_levels(encoder);
    }

    /// Sets the wind grid: cell-centred velocities `(x, z)` m/s, `nx × ny`, row-major, over
    /// cells of `cell` metres from `origin` (a CPU solver's `velocity_field`, or a GPU field
    /// read into cells).
    pub fn set_wind(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        (nx, ny): (usize, usize),
        origin: [f32; 2],
        cell: [f32; 2],
        velocity: &[[f32; 2]],
    ) {
        assert_eq!(velocity.len(), nx * ny, "a wind grid of nx × ny cells");
        self.ensure_wind(device, (nx, ny), origin, cell);
        queue.write_buffer(&self.wind, 0, bytemuck::cast_slice(velocity));
    }

    /// Sizes the wind grid for `nx × ny` cells (a new buffer and bind group if it changes).
    fn ensure_wind(
        &mut self,
        device: &wgpu::Device,
        (nx, ny): (usize, usize),
        origin: [f32; 2],
        cell: [f32; 2],
    ) {
        let bytes = (nx * ny * 8) as u64;
        if bytes != self.wind.size() {
            self.wind = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("grass wind"),
                size: bytes.max(8),
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            self.wind_group = None;
            self.group0 = scene_group(
                device,
                &self.layout0,
                [&self.scene_buf, &self.blades, &self.wind, &self.palettes],
                &self.trail.texture,
                &self.ground,
            );
        }
        if self.far.resize(device, (nx, ny)) {
            self.look_group = look_group(device, &self.look_layout, &self.far, &self.backdrop);
        }
        self.scene.nx = nx as u32;
        self.scene.ny = ny as u32;
        self.scene.origin = origin;
        self.scene.cell = cell;
    }

    /// Records the wind grid taken from a GPU-run field's faces (`grass_wind.wgsl`), so the
    /// grass follows the GPU solver with no read-back.
    pub fn wind_from_field(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        field: &super::mapview::FieldBuffers,
    ) {
        let (nx, ny) = (field.nx as usize, field.ny as usize);
        self.ensure_wind(device, (nx, ny), field.origin, field.cell);
        queue.write_buffer(
            &self.wind_grid,
            0,
            bytemuck::cast_slice(&[field.nx, field.ny, 0, 0]),
        );
        if self.wind_group.as_ref().is_none_or(|(f, _)| f != field) {
            let layout = self.wind_pipeline.get_bind_group_layout(0);
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("grass wind from field"),
                layout: &layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: self.wind_grid.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: field.u.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: field.v.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: self.wind.as_entire_binding(),
                    },
                ],
            });
            self.wind_group = Some((field.clone(), group));
        }
        let Some((_, group)) = &self.wind_group else {
            return;
        };
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("grass wind from field"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.wind_pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(field.nx.div_ceil(8), field.ny.div_ceil(8), 1);
    }

    /// The wind grid, read back (for tests; waits for the GPU).
    pub fn read_wind(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<[f32; 2]>, GpuError> {
        let bytes = super::read_buffer(device, queue, &self.wind)?;
        Ok(bytemuck::cast_slice(&bytes).to_vec())
    }

    /// Chooses the blade model: the Bezier model's states are made (every blade upright) on
    /// the first switch to it and dropped on the way back, so the CWD model costs no memory
    /// for them.
    pub fn set_model(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, model: GrassModel) {
        let bezier = model == GrassModel::BezierPhysics;
        if bezier == self.bezier.is_some() {
            return;
        }
        let states = if bezier {
            let mut pass = bezier::BezierPass::new(device, &self.layout0, self.total);
            // Every uploaded blade, whatever the budget.
            let mut all = self.scene;
            all.blades = self.total;
            queue.write_buffer(&self.scene_buf, 0, bytemuck::bytes_of(&all));
            let mut enc = device.create_command_encoder(&Default::default());
            pass.record_rest(&mut enc, &self.group0, self.total);
            self.cull.reset_levels(&mut enc);
            queue.submit([enc.finish()]);
            let states = pass.states.clone();
            self.bezier = Some(pass);
            states
        } else {
            self.bezier = None;
            storage(device, "no bezier states", &[0; 48])
        };
        self.scene.model = u32::from(bezier);
        self.group_shape = buffers_group(
            device,
            "grass shape",
            &self.layout_shape,
            &[&self.poses, &states],
        );
    }

    /// The blade model drawn.
    pub fn model(&self) -> GrassModel {
        if self.bezier.is_some() {
            GrassModel::BezierPhysics
        } else {
            GrassModel::CwdQuadratic
        }
    }

    /// The culling and LOD settings (the 3D view's toggles).
    pub fn cull_params(&self) -> CullParams {
        self.cull.params
    }

    pub fn set_cull(&mut self, params: CullParams) {
        self.cull.params = params;
    }

    /// Whether the blades are drawn nearest first, so the depth test drops the hidden ones
    /// before they are shaded (on by default), or in the order they are stored in (to measure
    /// what the order saves: the picture is the same).
    pub fn set_near_first(&mut self, on: bool) {
        self.near_first = on;
    }

    /// Whether the ground shows the grass's look from afar where the blades drawn cover less
    /// than the field would ([`crate::grass::far`]); on by default.
    pub fn set_far(&mut self, on: bool) {
        self.far.set_on(on, self.total);
    }

    /// The threshold of the view-dependent sample the blades now drawn were chosen with
    /// ([`crate::grass::sample::Sample::threshold`]; infinite or 0: every blade is drawn), so
    /// the far field fills in what the sample thins.
    pub fn set_sample_reach(&mut self, threshold: f32) {
        self.far.uniform.sample_reach = if threshold.is_finite() {
            threshold.max(0.0)
        } else {
            0.0
        };
    }

    /// The table of the field's look by view direction (in the wind at the level's edge) that the ground beyond the level
    /// takes ([`crate::grass::far::surround_table`]), after a [`Self::prepare`] (for tests;
    /// waits for the GPU).
    pub fn read_surround(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        self.far.read_surround(device, queue)
    }

    /// The far field's settings as last written (for tests).
    pub fn far_uniform(&self) -> FarUniform {
        self.far.uniform
    }

    /// The far field's texels, row-major: the grass's look from afar (rgb) and the share of
    /// blade coverage drawn there (a), after a [`Self::prepare`] (for tests; waits for the GPU).
    pub fn read_far(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        self.far.read(device, queue)
    }

    /// The sphere pushing the grass this frame (`None`: none); it leaves a trail that fades
    /// over the trail's lifetime.
    pub fn set_sphere(&mut self, sphere: Option<Sphere>) {
        self.scene.sphere = sphere.map_or([0.0; 4], |s| {
            [s.centre[0], s.centre[1], s.centre[2], s.radius.max(0.0)]
        });
    }

    /// Colours the grass and the ground by the wind's speed, as the map view's speed scale
    /// does (`colour::speed_rgb`, `scale` m/s at its top), at `opacity` over their lit colour;
    /// `None` (or opacity 0) draws them as they are. Blades take their wind cell's speed,
    /// the ground the speed bilinear between cell centres.
    pub fn set_wind_colours(&mut self, colours: Option<(f32, f32)>) {
        let (opacity, scale) = colours.unwrap_or((0.0, 1.0));
        self.scene.wind_colours = if opacity.is_finite() {
            opacity.clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.scene.wind_scale = if scale.is_finite() && scale > 0.0 {
            scale
        } else {
            1.0
        };
    }

    /// Seconds the trail takes to fade back (0: no trail, only the sphere itself).
    pub fn set_trail_lifetime(&mut self, seconds: f32) {
        self.scene.lifetime = seconds.max(0.0);
    }

    /// Records this frame's passes for `camera` at simulation `time`, `dt` seconds after the
    /// last frame (the Bezier blades and the trail advance by it), drawing into a picture of
    /// `aspect` (width / height): the trail, the model's pass and the cull pass.
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        camera: &Camera,
        aspect: f32,
        time: f32,
        dt: f32,
    ) {
        let dt = dt.clamp(0.0, 0.25);
        self.scene.view_proj = camera.draw_view_proj(aspect).to_cols_array_2d();
        self.scene.inv_view_proj = camera.view_proj(aspect).inverse().to_cols_array_2d();
        let far = camera.far_plane();
        self.scene.fade = [0.1 * far, 0.9 * far];
        self.scene.eye = [camera.eye.x, camera.eye.y, camera.eye.z, time];
        self.scene.dt = dt;
        let pushing = self.scene.sphere[3] > 0.0;
        let trail_was_on = self.trail_left > 0.0;
        if pushing {
            self.trail_left = self.scene.lifetime + dt;
        } else {
            self.trail_left = (self.trail_left - dt).max(0.0);
        }
        // One more step once the trail is spent, so it ends at zero rather than at its last
        // value.
        let step_trail = pushing || trail_was_on;
        self.scene.trail_on = u32::from(step_trail);
        queue.write_buffer(&self.scene_buf, 0, bytemuck::bytes_of(&self.scene));
        if step_trail {
            self.trail.record(encoder, &self.group0);
        }
        let blades = self.blade_count();
        if let Some(bz) = &mut self.bezier {
            bz.advance(queue, encoder, &self.group0, blades, dt);
        } else {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("grass deform"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.deform);
            pass.set_bind_group(0, &self.group0, &[]);
            pass.set_bind_group(1, &self.group_deform, &[]);
            dispatch_blades(&mut pass, blades);
        }
        self.far
            .record(queue, encoder, &self.group0, &self.cull.params);
        // The visible lists nearest first, so the depth test culls hidden fragments before
        // they are shaded.
        let walk = if self.near_first {
            crate::grass::Walk::toward((camera.target - camera.eye).to_array())
        } else {
            crate::grass::Walk::STORED
        };
        self.cull.record(
            queue,
            encoder,
            &self.group0,
            &self.group_shape,
            (blades, walk),
        );
    }

    /// Draws the obstacles, the blades (one indirect draw per LOD level, nearest first), the
    /// ground, the sky and the lines over them (the pass needs a [`DEPTH_FORMAT`] depth
    /// attachment). Near to far, so the depth test drops what is hidden before it is shaded:
    /// the ground under the blades and the sky behind everything are shaded only where they
    /// show. Drawn first, the sky and the ground were shaded under every blade.
    pub fn paint(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_bind_group(0, &self.group0, &[]);
        let coloured = self.scene.wind_colours > 0.0;
        if let Some((b, n)) = &self.solids {
            pass.set_pipeline(&self.draw.solids);
            pass.set_vertex_buffer(0, b.slice(..));
            pass.draw(0..*n, 0..1);
        }
        pass.set_bind_group(3, &self.look_group, &[]);
        if self.scene.blades > 0 {
            pass.set_bind_group(1, &self.group_shape, &[]);
            self.cull.draw(pass, self.draw.blades(coloured));
        }
        pass.set_pipeline(self.draw.ground(coloured));
        pass.set_bind_group(1, &self.look_group, &[]);
        // The level's quads, then the ring of quads beyond it (`grass_ground.wgsl`).
        let [qx, qz] = self.scene.ground_quads.map(|q| q.max(1));
        pass.draw(0..6 * (qx * qz + 2 * (qx + 2) + 2 * qz), 0..1);
        // Only where nothing was drawn (`grass_sky.wgsl` lies on the far plane).
        pass.set_pipeline(&self.draw.sky);
        pass.draw(0..3, 0..1);
        // Last, over the blades (the lines' pipeline has no depth test).
        for (b, n) in self.lines.iter().chain(&self.footprint) {
            pass.set_pipeline(&self.draw.lines);
            pass.set_vertex_buffer(0, b.slice(..));
            pass.draw(0..*n, 0..1);
        }
    }

    /// Whether the view still changes with no change to its inputs: a pushed trail still
    /// fading (the Bezier blades' settling is the caller's to time).
    pub fn trail_active(&self) -> bool {
        self.trail_left > 0.0
    }

    /// How many read-backs of the cull counters have arrived ([`CullPass::stats_reads`]).
    pub fn cull_stats_reads(&self) -> u64 {
        self.cull.stats_reads()
    }

    /// The latest cull counters the GPU has sent back, starting the next read-back (call after
    /// each frame's submission; never waits).
    pub fn poll_cull_stats(&mut self) -> Option<CullStats> {
        self.cull.poll_stats()
    }

    /// The last frame's cull counters and each LOD level's visible blades (for tests and the
    /// benchmark; waits for the GPU).
    pub fn read_cull(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<(CullStats, [Vec<u32>; 3]), GpuError> {
        self.cull.read_stats(device, queue)
    }

    /// The far LOD level's draw arguments, one triangle list over its blades (for tests,
    /// waits for the GPU).
    pub fn read_far_draw(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<[u32; 4], GpuError> {
        self.cull.read_far_draw(device, queue)
    }

    /// The Bezier blades' control points (`None` with the CWD model; for tests, waits for the
    /// GPU).
    pub fn read_bezier(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Option<Result<Vec<BezierState>, GpuError>> {
        self.bezier
            .as_ref()
            .map(|b| b.read(device, queue, self.scene.blades))
    }

    /// The trail's texels, row-major, [`crate::grass::trail::grid`] of the world (for tests;
    /// waits for the GPU).
    pub fn read_trail(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<f32>, GpuError> {
        self.trail.read(device, queue)
    }

    /// Every blade's deformed tip (xyz) and its shade (w) as the vertex shader places it,
    /// after a [`Self::prepare`] (for tests; waits for the GPU).
    pub fn read_tips(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        let mut enc = device.create_command_encoder(&Default::default());
        let tips = self.cull.record_tips(
            device,
            &mut enc,
            (&self.group0, &self.group_shape),
            self.scene.blades,
        );
        queue.submit([enc.finish()]);
        let bytes = super::read_buffer(device, queue, &tips)?;
        Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes)[..self.scene.blades as usize].to_vec())
    }
}
