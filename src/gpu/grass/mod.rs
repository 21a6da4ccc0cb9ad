//! The grass renderer: blades as GPU instances shaped by the CWD-Sim model (`src/grass/cwd.rs`
//! is its CPU twin) in the live wind, over a ground plane. Per-blade data is uploaded once; per
//! frame the CPU writes one small scene uniform (camera, time) and, when it changes, the wind
//! grid. A compute pass poses every blade (its wind cell, bend, length-restoring scale) and the
//! vertex shader builds each blade from its index. Passes: `shaders/grass_*.wgsl`, sharing
//! `grass_common.wgsl`.
//!
//! Takes `&wgpu::Device` / `&wgpu::Queue` and never egui. Uses glam for the camera.
//! `target.rs`: the colour + depth target and whole frames into it; `headless.rs`: pictures
//! and the benchmark for the CLI.

mod bezier;
mod headless;
mod target;

pub use bezier::BezierPass;
pub use headless::{GrassBench, bench, picture};
pub use target::{Target, render_offscreen};

use super::GpuError;
use super::buffer_entry as entry;
use crate::doc::Layout;
use crate::grass::scene::SceneVertex;
use crate::grass::{Blade, cwd};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

/// The shared header of the grass passes.
pub const COMMON: &str = include_str!("../../../shaders/grass_common.wgsl");

/// Every grass pass's shader: `(name, source)`, each compiled after [`COMMON`].
pub const SHADERS: [(&str, &str); 6] = [
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
];

/// The full WGSL of grass pass `name` (the common header, then the pass; `grass_wind` alone:
/// it writes the wind grid the header declares read-only).
pub fn shader_source(name: &str) -> Option<String> {
    SHADERS.iter().find(|(n, _)| *n == name).map(|(n, s)| {
        if *n == "grass_wind" {
            s.to_string()
        } else {
            format!("{COMMON}\n{s}")
        }
    })
}

/// The scene; mirrors `struct Scene` in `shaders/grass_common.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Scene {
    pub view_proj: [[f32; 4]; 4],
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
}

/// A blade's pose this frame; mirrors `struct Pose` in `shaders/grass_common.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Pose {
    pub push: [f32; 2],
    pub scale: f32,
    pub dim: f32,
}

/// Quads per blade.
pub const SEGMENTS: u32 = 5;
/// The depth buffer format the renderer draws with.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// A perspective camera looking from `eye` at `target` (world metres, y up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

impl Camera {
    /// A view of the whole world from its south-west (+z, −x) side, above it.
    pub fn overview(layout: &Layout) -> Self {
        let (min, max) = layout.bounds();
        let c = Vec3::new((min[0] + max[0]) / 2.0, 0.0, (min[1] + max[1]) / 2.0);
        let r = (max[0] - min[0]).hypot(max[1] - min[1]) / 2.0;
        Self {
            eye: c + Vec3::new(-0.55 * r, 0.55 * r, 0.95 * r),
            target: c,
            fov_y: 45f32.to_radians(),
        }
    }

    /// World → clip space for a picture of `aspect` (width / height).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let dist = (self.eye - self.target).length().max(0.01);
        let proj = Mat4::perspective_rh(self.fov_y, aspect, (dist * 0.002).max(0.01), dist * 20.0);
        proj * Mat4::look_at_rh(self.eye, self.target, Vec3::Y)
    }
}

fn storage(device: &wgpu::Device, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytes,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
    })
}

/// Blades, wind and pipelines for one layout's grass.
pub struct GrassRenderer {
    scene: Scene,
    /// Blades uploaded (the scene's count may be fewer: [`Self::set_budget`]).
    total: u32,
    scene_buf: wgpu::Buffer,
    blades: wgpu::Buffer,
    wind: wgpu::Buffer,
    palettes: wgpu::Buffer,
    /// Per-blade poses, written by the deform pass each frame (bound in the groups below).
    _poses: wgpu::Buffer,
    tips: wgpu::Buffer,
    layout0: wgpu::BindGroupLayout,
    group0: wgpu::BindGroup,
    group1_compute: wgpu::BindGroup,
    group1_draw: wgpu::BindGroup,
    deform: wgpu::ComputePipeline,
    tips_pipeline: wgpu::ComputePipeline,
    blade_pipeline: wgpu::RenderPipeline,
    ground_pipeline: wgpu::RenderPipeline,
    solid_pipeline: wgpu::RenderPipeline,
    line_pipeline: wgpu::RenderPipeline,
    /// Obstacles as solids, the arrows, and the map's footprint (vertex buffer, count).
    solids: Option<(wgpu::Buffer, u32)>,
    lines: Option<(wgpu::Buffer, u32)>,
    footprint: Option<(wgpu::Buffer, u32)>,
    /// The faces → wind grid pass for a GPU-run field, its grid uniform, and its bind group
    /// for the field last bound.
    wind_pipeline: wgpu::ComputePipeline,
    wind_grid: wgpu::Buffer,
    wind_group: Option<(super::mapview::FieldBuffers, wgpu::BindGroup)>,
    /// The map backdrop laid over the ground (a blank 1×1 until one is set).
    backdrop_layout: wgpu::BindGroupLayout,
    backdrop_group: wgpu::BindGroup,
}

fn backdrop_texture(device: &wgpu::Device, [w, h]: [u32; 2]) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("grass backdrop"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

fn backdrop_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    texture: &wgpu::Texture,
) -> wgpu::BindGroup {
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("grass backdrop"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("grass backdrop"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(
                    &texture.create_view(&Default::default()),
                ),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Sampler(&sampler),
            },
        ],
    })
}

const TRIANGLES: wgpu::PrimitiveTopology = wgpu::PrimitiveTopology::TriangleList;

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
        let scene = Scene {
            view_proj: Mat4::IDENTITY.to_cols_array_2d(),
            eye: [0.0; 4],
            sun: [0.42, 0.80, 0.43, 0.32],
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
            colours = vec![[0.1, 0.22, 0.05, 1.0], [0.45, 0.65, 0.2, 1.0]];
        }
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
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
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
        let tips = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("grass tips"),
            size: n * 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let all = S::VERTEX | S::FRAGMENT | S::COMPUTE;
        let ro = wgpu::BufferBindingType::Storage { read_only: true };
        let rw = wgpu::BufferBindingType::Storage { read_only: false };
        let layout0 = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass scene"),
            entries: &[
                entry(0, all, wgpu::BufferBindingType::Uniform),
                entry(1, all, ro),
                entry(2, all, ro),
                entry(3, all, ro),
            ],
        });
        let layout_compute = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass poses (compute)"),
            entries: &[entry(0, S::COMPUTE, rw), entry(1, S::COMPUTE, rw)],
        });
        let layout_draw = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass poses (draw)"),
            entries: &[entry(0, S::VERTEX, ro)],
        });
        let group = |layout: &wgpu::BindGroupLayout, buffers: &[&wgpu::Buffer]| {
            let entries: Vec<_> = buffers
                .iter()
                .enumerate()
                .map(|(k, b)| wgpu::BindGroupEntry {
                    binding: k as u32,
                    resource: b.as_entire_binding(),
                })
                .collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("grass"),
                layout,
                entries: &entries,
            })
        };
        let group0 = group(&layout0, &[&scene_buf, &blades_buf, &wind, &palettes]);
        let group1_compute = group(&layout_compute, &[&poses, &tips]);
        let group1_draw = group(&layout_draw, &[&poses]);
        let module = |name: &str| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(name),
                source: wgpu::ShaderSource::Wgsl(shader_source(name).expect("listed").into()),
            })
        };
        let compute_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("grass compute"),
            bind_group_layouts: &[Some(&layout0), Some(&layout_compute)],
            immediate_size: 0,
        });
        let deform_module = module("grass_deform");
        let compute = |entry_point: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry_point),
                layout: Some(&compute_layout),
                module: &deform_module,
                entry_point: Some(entry_point),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let draw_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("grass draw"),
            bind_group_layouts: &[Some(&layout0), Some(&layout_draw)],
            immediate_size: 0,
        });
        let scene_vertex = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<SceneVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4],
        };
        let backdrop_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass backdrop"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: S::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: S::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let ground_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("grass ground"),
            bind_group_layouts: &[Some(&layout0), Some(&layout_draw), Some(&backdrop_layout)],
            immediate_size: 0,
        });
        let render = |name: &str,
                      fs: &str,
                      topology: wgpu::PrimitiveTopology,
                      buffers: &[Option<wgpu::VertexBufferLayout<'_>>]| {
            let m = module(name);
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(name),
                layout: Some(if name == "grass_ground" {
                    &ground_layout
                } else {
                    &draw_layout
                }),
                vertex: wgpu::VertexState {
                    module: &m,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &m,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        Self {
            total: scene.blades,
            scene,
            scene_buf,
            blades: blades_buf,
            wind,
            palettes,
            _poses: poses,
            tips,
            layout0,
            group0,
            group1_compute,
            group1_draw,
            deform: compute("main"),
            tips_pipeline: compute("tips_main"),
            blade_pipeline: render("grass_blades", "fs_main", TRIANGLES, &[]),
            ground_pipeline: render("grass_ground", "fs_main", TRIANGLES, &[]),
            solid_pipeline: render(
                "grass_scene",
                "fs_solid",
                TRIANGLES,
                &[Some(scene_vertex.clone())],
            ),
            line_pipeline: render(
                "grass_scene",
                "fs_line",
                wgpu::PrimitiveTopology::LineList,
                &[Some(scene_vertex)],
            ),
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
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            wind_group: None,
            backdrop_group: backdrop_group(
                device,
                &backdrop_layout,
                &backdrop_texture(device, [1, 1]),
            ),
            backdrop_layout,
        }
    }

    /// Draws eqs. 12–14 as the paper prints them — unbounded bend, no length restored, eq. 14
    /// with the raw speed — to show the problem our reading solves (`docs/GRASS.md`).
    pub fn set_paper_literal(&mut self, literal: bool) {
        self.scene.literal = u32::from(literal);
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

    /// Lays the layout's map backdrop over the ground: `rgba` (sRGB, 8 bits, `size` pixels,
    /// stretched over the world as on the map) at `opacity`; `None` removes it.
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
        self.backdrop_group = backdrop_group(device, &self.backdrop_layout, &texture);
        self.scene.backdrop = opacity;
    }

    /// The map view's footprint on the ground (a line list; empty: none).
    pub fn set_footprint(&mut self, device: &wgpu::Device, lines: &[SceneVertex]) {
        self.footprint = vertices(device, lines);
    }

    /// The scene, blades, wind and palettes bind group and its layout (group 0 of every pass).
    pub(super) fn scene_group(&self) -> (&wgpu::BindGroupLayout, &wgpu::BindGroup) {
        (&self.layout0, &self.group0)
    }

    /// Blades drawn.
    pub fn blade_count(&self) -> u32 {
        self.scene.blades
    }

    /// Poses and draws only the first `budget` blades (`None`: all of them). Shuffle the
    /// blades first ([`crate::grass::shuffle`]) so that those are an even sample of the field.
    pub fn set_budget(&mut self, budget: Option<u32>) {
        self.scene.blades = budget.map_or(self.total, |b| b.min(self.total));
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
            let entries = [
                self.scene_buf.as_entire_binding(),
                self.blades.as_entire_binding(),
                self.wind.as_entire_binding(),
                self.palettes.as_entire_binding(),
            ];
            let entries: Vec<_> = entries
                .into_iter()
                .enumerate()
                .map(|(k, resource)| wgpu::BindGroupEntry {
                    binding: k as u32,
                    resource,
                })
                .collect();
            self.group0 = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("grass"),
                layout: &self.layout0,
                entries: &entries,
            });
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

    /// Records this frame's pose pass for `camera` at simulation `time`, drawing into a
    /// picture of `aspect` (width / height).
    pub fn prepare(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        camera: &Camera,
        aspect: f32,
        time: f32,
    ) {
        self.scene.view_proj = camera.view_proj(aspect).to_cols_array_2d();
        self.scene.eye = [camera.eye.x, camera.eye.y, camera.eye.z, time];
        queue.write_buffer(&self.scene_buf, 0, bytemuck::bytes_of(&self.scene));
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("grass deform"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.deform);
        pass.set_bind_group(0, &self.group0, &[]);
        pass.set_bind_group(1, &self.group1_compute, &[]);
        pass.dispatch_workgroups(self.blade_count().div_ceil(64), 1, 1);
    }

    /// Draws the ground and the blades (the pass needs a [`DEPTH_FORMAT`] depth attachment).
    pub fn paint(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_bind_group(0, &self.group0, &[]);
        pass.set_bind_group(1, &self.group1_draw, &[]);
        pass.set_pipeline(&self.ground_pipeline);
        pass.set_bind_group(2, &self.backdrop_group, &[]);
        pass.draw(0..6, 0..1);
        if let Some((b, n)) = &self.solids {
            pass.set_pipeline(&self.solid_pipeline);
            pass.set_vertex_buffer(0, b.slice(..));
            pass.draw(0..*n, 0..1);
        }
        for (b, n) in self.lines.iter().chain(&self.footprint) {
            pass.set_pipeline(&self.line_pipeline);
            pass.set_vertex_buffer(0, b.slice(..));
            pass.draw(0..*n, 0..1);
        }
        if self.scene.blades > 0 {
            pass.set_pipeline(&self.blade_pipeline);
            pass.draw(0..SEGMENTS * 6, 0..self.blade_count());
        }
    }

    /// Every blade's deformed tip (xyz) and its shade (w) as the vertex shader places it,
    /// after a [`Self::prepare`] (for tests; waits for the GPU).
    pub fn read_tips(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        let mut enc = device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.tips_pipeline);
            pass.set_bind_group(0, &self.group0, &[]);
            pass.set_bind_group(1, &self.group1_compute, &[]);
            pass.dispatch_workgroups(self.scene.blades.div_ceil(64), 1, 1);
        }
        queue.submit([enc.finish()]);
        let bytes = super::read_buffer(device, queue, &self.tips)?;
        Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes)[..self.scene.blades as usize].to_vec())
    }
}
