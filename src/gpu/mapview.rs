//! The editor's map view of the wind, drawn on the GPU straight from the solver's buffers: a
//! colour map (speed, curl or pressure), arrow glyphs, and streak particles advected on the
//! GPU. Nothing is read back to draw a frame: the colour scales come from a stats pass that
//! runs before drawing. Each pass is a WGSL file in `shaders/` (`map_*.wgsl`, sharing
//! `map_common.wgsl`) with a CPU twin in `app::view`.
//!
//! Takes `&wgpu::Device` / `&wgpu::Queue` and never egui: the editor's one bridge file
//! (`app::gpu_view`) calls [`MapRenderer::prepare`] and [`MapRenderer::paint`] from an
//! `egui_wgpu::CallbackTrait`.

use super::buffer_entry as entry;
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

/// The shared header of the map-view passes.
pub const COMMON: &str = include_str!("../../shaders/map_common.wgsl");

/// Every map-view pass's shader: `(name, source)`, each compiled after [`COMMON`].
pub const SHADERS: [(&str, &str); 5] = [
    ("map_stats", include_str!("../../shaders/map_stats.wgsl")),
    ("map_field", include_str!("../../shaders/map_field.wgsl")),
    (
        "map_streaks_advect",
        include_str!("../../shaders/map_streaks_advect.wgsl"),
    ),
    (
        "map_streaks",
        include_str!("../../shaders/map_streaks.wgsl"),
    ),
    ("map_glyphs", include_str!("../../shaders/map_glyphs.wgsl")),
];

/// The full WGSL of map pass `name` (the common header, then the pass).
pub fn shader_source(name: &str) -> Option<String> {
    SHADERS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| format!("{COMMON}\n{s}"))
}

/// The view; mirrors `struct View` in `shaders/map_common.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct View {
    pub center: [f32; 2],
    pub viewport_px: [f32; 2],
    pub origin: [f32; 2],
    pub cell: [f32; 2],
    pub world_min: [f32; 2],
    pub world_max: [f32; 2],
    pub lattice_origin: [f32; 2],
    pub zoom: f32,
    pub ppp: f32,
    pub lattice_step: f32,
    pub alpha: f32,
    pub dt: f32,
    pub nx: u32,
    pub ny: u32,
    pub layer: u32,
    pub frame: u32,
    pub lattice_cols: u32,
    pub particles: u32,
    pub srgb_target: u32,
    /// The speed colours' top, m/s (0: the stats pass's peak).
    pub speed_scale: f32,
    pub _pad: f32,
}

/// A streak particle; mirrors `struct Particle` in `shaders/map_common.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Particle {
    pub trail: [[f32; 2]; 16],
    pub age: f32,
    pub life: f32,
    pub len: u32,
    pub seed: u32,
}

/// Points a streak keeps (`TRAIL` in `shaders/map_common.wgsl`).
pub const TRAIL: u32 = 14;

/// Where the field lives on the GPU: the solver's face velocities and pressure, on its grid.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldBuffers {
    pub u: wgpu::Buffer,
    pub v: wgpu::Buffer,
    pub p: wgpu::Buffer,
    pub nx: u32,
    pub ny: u32,
    /// Grid origin and cell size, metres.
    pub origin: [f32; 2],
    pub cell: [f32; 2],
}

impl FieldBuffers {
    /// Buffers holding a field computed elsewhere (the CPU solver's faces and pressure), so
    /// the map view draws a CPU-run field with the same passes as a GPU-run one.
    pub fn upload(
        device: &wgpu::Device,
        (nx, ny): (u32, u32),
        origin: [f32; 2],
        cell: [f32; 2],
        (u, v, p): (&[f32], &[f32], &[f32]),
    ) -> Self {
        let buffer = |label: &str, data: &[f32]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::cast_slice(data),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            })
        };
        Self {
            u: buffer("map u", u),
            v: buffer("map v", v),
            p: buffer("map p", p),
            nx,
            ny,
            origin,
            cell,
        }
    }

    /// Writes a new state of the same grid into buffers made by [`Self::upload`].
    pub fn write(&self, queue: &wgpu::Queue, (u, v, p): (&[f32], &[f32], &[f32])) {
        queue.write_buffer(&self.u, 0, bytemuck::cast_slice(u));
        queue.write_buffer(&self.v, 0, bytemuck::cast_slice(v));
        queue.write_buffer(&self.p, 0, bytemuck::cast_slice(p));
    }
}

/// Which value the colour map shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layer {
    Speed,
    Curl,
    Pressure,
}

/// What to draw over the colour map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Overlay {
    None,
    Glyphs,
    Streaks,
}

/// One frame's request: what to draw, where, and how far to move the streaks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub layer: Layer,
    pub overlay: Overlay,
    /// Colour-map opacity (0..1).
    pub alpha: f32,
    /// World point at the viewport centre, and points per metre.
    pub center: [f32; 2],
    pub zoom: f32,
    /// Physical pixels per point, and the viewport in physical pixels.
    pub ppp: f32,
    pub viewport_px: [f32; 2],
    /// The world rectangle.
    pub world_min: [f32; 2],
    pub world_max: [f32; 2],
    /// Simulated seconds to advance the streaks by (0 while paused).
    pub dt: f32,
    pub streaks: u32,
    /// Glyph lattice: first glyph's centre (metres), spacing (metres), glyphs per row and rows.
    pub lattice_origin: [f32; 2],
    pub lattice_step: f32,
    pub lattice: [u32; 2],
    /// The speed colours' top, m/s, where it is fixed (the View menu's fixed speed scale);
    /// `None`: the field's peak, from the stats pass.
    pub speed_scale: Option<f32>,
}

/// Bytes per streak particle on the GPU.
const PARTICLE_BYTES: u64 = std::mem::size_of::<Particle>() as u64;

/// The map view's pipelines and per-view state (streak particles, stats), made once per
/// device and target format.
pub struct MapRenderer {
    view_buf: wgpu::Buffer,
    lut: wgpu::Buffer,
    stats: wgpu::Buffer,
    particles: wgpu::Buffer,
    particle_count: u32,
    field_layout: wgpu::BindGroupLayout,
    read_layout: wgpu::BindGroupLayout,
    write_layout: wgpu::BindGroupLayout,
    stats_pipeline: wgpu::ComputePipeline,
    advect_pipeline: wgpu::ComputePipeline,
    field_pipeline: wgpu::RenderPipeline,
    streak_pipeline: wgpu::RenderPipeline,
    glyph_pipeline: wgpu::RenderPipeline,
    /// The bind groups of the field last drawn, rebuilt when its buffers change.
    bound: Option<Bound>,
    frame: Frame,
    frames: u32,
    srgb: bool,
}

struct Bound {
    field: FieldBuffers,
    field_group: wgpu::BindGroup,
    read_group: wgpu::BindGroup,
    write_group: wgpu::BindGroup,
}

fn colour_table() -> Vec<u32> {
    let pack = |[r, g, b]: [u8; 3]| u32::from_le_bytes([r, g, b, 255]);
    let steps = crate::colour::SPEED_STEPS;
    (0..steps)
        .map(|k| pack(crate::colour::speed_rgb(k as f32 / (steps - 1) as f32)))
        .chain((0..256).map(|k| pack(crate::colour::signed_rgb(k as f32 / 127.5 - 1.0))))
        .collect()
}

impl MapRenderer {
    /// Pipelines for drawing into targets of `format` (the editor's swap chain format).
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        use wgpu::ShaderStages as S;
        let all = S::VERTEX | S::FRAGMENT | S::COMPUTE;
        let ro = wgpu::BufferBindingType::Storage { read_only: true };
        let rw = wgpu::BufferBindingType::Storage { read_only: false };
        let field_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("map field"),
            entries: &[
                entry(0, all, wgpu::BufferBindingType::Storage { read_only: true }),
                entry(1, all, ro),
                entry(2, all, ro),
                entry(3, all, ro),
                entry(4, all, ro),
            ],
        });
        let read_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("map state (draw)"),
            entries: &[
                entry(0, S::VERTEX | S::FRAGMENT, ro),
                entry(1, S::VERTEX, ro),
            ],
        });
        let write_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("map state (compute)"),
            entries: &[entry(0, S::COMPUTE, rw), entry(1, S::COMPUTE, rw)],
        });
        let module = |name: &str| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(name),
                source: wgpu::ShaderSource::Wgsl(shader_source(name).expect("listed").into()),
            })
        };
        let compute = |name: &str| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(name),
                bind_group_layouts: &[Some(&field_layout), Some(&write_layout)],
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: Some(&layout),
                module: &module(name),
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let draw_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("map draw"),
            bind_group_layouts: &[Some(&field_layout), Some(&read_layout)],
            immediate_size: 0,
        });
        let render = |name: &str| {
            let m = module(name);
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(name),
                layout: Some(&draw_layout),
                vertex: wgpu::VertexState {
                    module: &m,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &m,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    // Premultiplied alpha, as egui draws.
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let storage = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        Self {
            view_buf: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("map view"),
                size: std::mem::size_of::<View>() as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            lut: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("map colours"),
                contents: bytemuck::cast_slice(&colour_table()),
                usage: wgpu::BufferUsages::STORAGE,
            }),
            stats: storage("map stats", 16),
            particles: storage("streaks", PARTICLE_BYTES),
            particle_count: 0,
            stats_pipeline: compute("map_stats"),
            advect_pipeline: compute("map_streaks_advect"),
            field_pipeline: render("map_field"),
            streak_pipeline: render("map_streaks"),
            glyph_pipeline: render("map_glyphs"),
            field_layout,
            read_layout,
            write_layout,
            bound: None,
            frame: Frame {
                layer: Layer::Speed,
                overlay: Overlay::None,
                alpha: 1.0,
                center: [0.0; 2],
                zoom: 1.0,
                ppp: 1.0,
                viewport_px: [1.0; 2],
                world_min: [0.0; 2],
                world_max: [1.0; 2],
                dt: 0.0,
                streaks: 0,
                lattice_origin: [0.0; 2],
                lattice_step: 1.0,
                lattice: [0, 0],
                speed_scale: None,
            },
            frames: 0,
            srgb: format.is_srgb(),
        }
    }

    fn bind(&mut self, device: &wgpu::Device, field: &FieldBuffers) {
        if self.bound.as_ref().is_some_and(|b| &b.field == field) {
            return;
        }
        let group = |layout: &wgpu::BindGroupLayout, buffers: &[&wgpu::Buffer]| {
            super::buffers_group(device, "map view", layout, buffers)
        };
        self.bound = Some(Bound {
            field_group: group(
                &self.field_layout,
                &[&self.view_buf, &field.u, &field.v, &field.p, &self.lut],
            ),
            read_group: group(&self.read_layout, &[&self.stats, &self.particles]),
            write_group: group(&self.write_layout, &[&self.stats, &self.particles]),
            field: field.clone(),
        });
    }

    /// Records this frame's compute work into `encoder` (the field's peaks; the streaks'
    /// advection when they are shown) and remembers what [`Self::paint`] draws.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        field: &FieldBuffers,
        frame: &Frame,
    ) {
        let streaks = if frame.overlay == Overlay::Streaks {
            frame.streaks
        } else {
            0
        };
        if streaks > 0 && streaks != self.particle_count {
            // A new, zeroed buffer: every particle is born again at a random age.
            self.particles = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("streaks"),
                size: u64::from(streaks) * PARTICLE_BYTES,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            self.particle_count = streaks;
            self.bound = None;
        }
        self.bind(device, field);
        self.frames = self.frames.wrapping_add(1);
        self.frame = *frame;
        let view = View {
            center: frame.center,
            viewport_px: frame.viewport_px,
            origin: field.origin,
            cell: field.cell,
            world_min: frame.world_min,
            world_max: frame.world_max,
            lattice_origin: frame.lattice_origin,
            zoom: frame.zoom,
            ppp: frame.ppp,
            lattice_step: frame.lattice_step,
            alpha: frame.alpha,
            dt: frame.dt,
            nx: field.nx,
            ny: field.ny,
            layer: match frame.layer {
                Layer::Speed => 0,
                Layer::Curl => 1,
                Layer::Pressure => 2,
            },
            frame: self.frames,
            lattice_cols: frame.lattice[0],
            particles: streaks,
            srgb_target: u32::from(self.srgb),
            speed_scale: frame.speed_scale.unwrap_or(0.0),
            _pad: 0.0,
        };
        queue.write_buffer(&self.view_buf, 0, bytemuck::bytes_of(&view));
        let Some(b) = &self.bound else { return };
        encoder.clear_buffer(&self.stats, 0, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("map stats"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, &b.field_group, &[]);
        pass.set_bind_group(1, &b.write_group, &[]);
        pass.set_pipeline(&self.stats_pipeline);
        pass.dispatch_workgroups(field.nx.div_ceil(8), field.ny.div_ceil(8), 1);
        if streaks > 0 {
            pass.set_pipeline(&self.advect_pipeline);
            pass.dispatch_workgroups(streaks.div_ceil(64), 1, 1);
        }
    }

    /// Draws what the last [`Self::prepare`] set up. The pass's viewport must be the map
    /// view's rectangle (egui-wgpu sets it to the callback's).
    pub fn paint(&self, pass: &mut wgpu::RenderPass<'_>) {
        let Some(b) = &self.bound else { return };
        pass.set_bind_group(0, &b.field_group, &[]);
        pass.set_bind_group(1, &b.read_group, &[]);
        pass.set_pipeline(&self.field_pipeline);
        pass.draw(0..6, 0..1);
        match self.frame.overlay {
            Overlay::Streaks if self.particle_count > 0 => {
                pass.set_pipeline(&self.streak_pipeline);
                pass.draw(0..(TRAIL - 1) * 6, 0..self.particle_count);
            }
            Overlay::Glyphs => {
                let [cols, rows] = self.frame.lattice;
                pass.set_pipeline(&self.glyph_pipeline);
                pass.draw(0..9, 0..cols * rows);
            }
            _ => {}
        }
    }

    /// The streak particles, read back (for tests; waits for the GPU).
    pub fn read_particles(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<Particle>, super::GpuError> {
        let bytes = super::read_buffer(device, queue, &self.particles)?;
        Ok(bytemuck::cast_slice(&bytes)[..self.particle_count as usize].to_vec())
    }

    /// The peaks the colour scales use: speed, |curl|, |pressure| (for tests; waits).
    pub fn read_stats(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<[f32; 3], super::GpuError> {
        let bytes = super::read_buffer(device, queue, &self.stats)?;
        let w: &[f32] = bytemuck::cast_slice(&bytes);
        Ok([w[0], w[1], w[2]])
    }

    /// Writes `particles` (for tests: a known starting state for the advection pass).
    pub fn write_particles(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        particles: &[Particle],
    ) {
        self.particles = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("streaks"),
            contents: bytemuck::cast_slice(particles),
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
        });
        let _ = queue;
        self.particle_count = particles.len() as u32;
        self.bound = None;
    }
}
