//! The culling and LOD pass (`shaders/grass_cull.wgsl`; CPU twin [`crate::grass::cull`]):
//! which blades this frame draws, compacted per LOD level into a visible list whose counts are
//! written straight into `draw_indirect` arguments, so the CPU never learns how many blades
//! survive unless it asks ([`CullPass::read_stats`], or the non-blocking
//! [`CullPass::poll_stats`] the editor's counters use).

use crate::gpu::{GpuError, buffer_entry as entry};
use crate::grass::Walk;
use crate::grass::cull::{CullParams, LOD_SEGMENTS};
use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};
use wgpu::util::DeviceExt;

/// The settings as the shaders read them; mirrors `struct Cull` in `shaders/grass_shape.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CullUniform {
    pub flags: u32,
    pub buckets: u32,
    pub capacity: u32,
    pub _pad0: u32,
    pub orientation_limit: f32,
    pub frustum_tolerance: f32,
    pub max_distance: f32,
    pub lod_near: f32,
    pub lod_far: f32,
    pub dither: f32,
    pub hysteresis: f32,
    pub thin_distance: f32,
}

impl CullUniform {
    /// `walk`: the order the blades are walked in, which each level's list keeps about
    /// ([`crate::grass::Walk`]).
    pub fn new(p: &CullParams, capacity: u32, walk: Walk) -> Self {
        Self {
            flags: u32::from(p.orientation)
                | u32::from(p.frustum) << 1
                | u32::from(p.distance) << 2
                | u32::from(p.lod) << 3
                | u32::from(walk.reverse) << 4
                | u32::from(walk.by_x) << 5,
            buckets: p.buckets.max(1),
            capacity,
            _pad0: 0,
            orientation_limit: p.orientation_limit,
            frustum_tolerance: p.frustum_tolerance,
            max_distance: p.max_distance.max(1e-3),
            lod_near: p.lod_near,
            lod_far: p.lod_far,
            dither: p.dither,
            hysteresis: p.hysteresis,
            thin_distance: p.thin_distance,
        }
    }
}

/// One LOD level's draw; mirrors `struct Level` in `shaders/grass_blades.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct LevelUniform {
    segments: u32,
    level: u32,
    _pad: [u32; 2],
}

/// What one frame's cull pass did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct CullStats {
    /// Blades considered.
    pub total: u32,
    pub orientation: u32,
    pub frustum: u32,
    pub distance: u32,
    /// Blades drawn at each LOD level (near to far).
    pub drawn: [u32; 3],
}

impl CullStats {
    fn from_words(w: &[u32], total: u32) -> Self {
        Self {
            total,
            orientation: w[12],
            frustum: w[13],
            distance: w[14],
            drawn: [w[1], w[5], w[9]],
        }
    }

    /// Blades drawn at all.
    pub fn drawn_total(&self) -> u32 {
        self.drawn.iter().sum()
    }
}

/// Vertices of a blade of `segments` rows (a strip up both edges, then the tip).
pub fn strip_vertices(segments: u32) -> u32 {
    2 * segments + 1
}

/// The far LOD level: one segment, one triangle a blade, drawn without instancing.
const FAR_LEVEL: usize = 2;
const _: () = assert!(
    LOD_SEGMENTS[FAR_LEVEL] == 1,
    "grass_cull.wgsl counts 3 vertices a far blade"
);

/// Byte offset in the arguments buffer of the far level's non-instanced draw: after the three
/// levels' instanced arguments and the culled counters (`args` in `grass_cull.wgsl`).
const FAR_DRAW: u64 = 64;

/// Words in the arguments buffer.
const ARGS_WORDS: usize = 20;

const IDLE: u8 = 0;
const COPIED: u8 = 1;
const MAPPING: u8 = 2;
const MAPPED: u8 = 3;

/// The pass's buffers and pipelines.
pub struct CullPass {
    pub params: CullParams,
    capacity: u32,
    uniform: wgpu::Buffer,
    /// Three levels' visible lists, `capacity` entries each.
    visible: wgpu::Buffer,
    /// Draw arguments per level, then the counters (`args` in the shader).
    args: wgpu::Buffer,
    pub(super) lods: wgpu::Buffer,
    /// The blades' slots by x ([`crate::grass::order_by_x`]), for walks along x.
    order: wgpu::Buffer,
    group: wgpu::BindGroup,
    tips_layout: wgpu::BindGroupLayout,
    pub(super) level_groups: [wgpu::BindGroup; 3],
    pub(super) level_layout: wgpu::BindGroupLayout,
    main: wgpu::ComputePipeline,
    pub(super) tips_pipeline: wgpu::ComputePipeline,
    readback: wgpu::Buffer,
    readback_state: Arc<AtomicU8>,
    last: Option<CullStats>,
    /// How many read-backs have arrived.
    reads: u64,
    last_total: u32,
}

impl CullPass {
    /// For `blades` blades, the first `by_x.len()` of them walked along x in that order
    /// ([`crate::grass::order_by_x`]); `layout0`/`layout_shape`: the renderer's groups 0 and
    /// 1; `module`: `grass_cull` compiled.
    pub fn new(
        device: &wgpu::Device,
        (layout0, layout_shape): (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
        module: &wgpu::ShaderModule,
        (blades, by_x): (u32, &[u32]),
        params: CullParams,
    ) -> Self {
        use wgpu::ShaderStages as S;
        let rw = wgpu::BufferBindingType::Storage { read_only: false };
        let ro = wgpu::BufferBindingType::Storage { read_only: true };
        // Each level's list starts on a 256-byte boundary so it can be bound on its own.
        let capacity = blades.max(1).div_ceil(64) * 64;
        let buffer = |label, size: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        let uniform = buffer(
            "grass cull",
            std::mem::size_of::<CullUniform>() as u64,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        );
        let slice = u64::from(capacity) * 4;
        let visible = buffer("grass visible", 3 * slice, storage);
        let args = buffer(
            "grass draw args",
            ARGS_WORDS as u64 * 4,
            storage | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
        );
        let lods = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("grass lods"),
            size: u64::from(capacity) * 4,
            usage: storage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        // Storage buffers may not be empty.
        let order = crate::gpu::storage(
            device,
            "grass order by x",
            bytemuck::cast_slice(if by_x.is_empty() { &[0u32] } else { by_x }),
        );
        let readback = buffer(
            "grass cull stats",
            64,
            wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        );
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass cull"),
            entries: &[
                entry(0, S::COMPUTE, rw),
                entry(1, S::COMPUTE, ro),
                entry(2, S::COMPUTE, rw),
                entry(3, S::COMPUTE, rw),
                entry(4, S::COMPUTE, ro),
            ],
        });
        // The tips (tests only) have a group of their own, made when they are read.
        let tips_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass tips"),
            entries: &[entry(5, S::COMPUTE, rw)],
        });
        let level_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass level"),
            entries: &[
                entry(0, S::VERTEX, ro),
                entry(1, S::VERTEX, ro),
                entry(2, S::VERTEX, ro),
            ],
        });
        fn whole(b: &wgpu::Buffer) -> wgpu::BindingResource<'_> {
            b.as_entire_binding()
        }
        let group = crate::gpu::buffers_group(
            device,
            "grass cull",
            &layout,
            &[&visible, &uniform, &args, &lods, &order],
        );
        let level_groups = [0u32, 1, 2].map(|l| {
            let level = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("grass level"),
                contents: bytemuck::bytes_of(&LevelUniform {
                    segments: LOD_SEGMENTS[l as usize],
                    level: l,
                    _pad: [0; 2],
                }),
                usage: wgpu::BufferUsages::STORAGE,
            });
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("grass level"),
                layout: &level_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &visible,
                            offset: u64::from(l) * slice,
                            size: wgpu::BufferSize::new(slice),
                        }),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: whole(&uniform),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: whole(&level),
                    },
                ],
            })
        });
        let pipeline = |entry_point: &str, group2: &wgpu::BindGroupLayout| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(entry_point),
                bind_group_layouts: &[Some(layout0), Some(layout_shape), Some(group2)],
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry_point),
                layout: Some(&layout),
                module,
                entry_point: Some(entry_point),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        Self {
            params,
            capacity,
            uniform,
            visible,
            args,
            lods,
            order,
            group,
            level_groups,
            level_layout,
            main: pipeline("main", &layout),
            tips_pipeline: pipeline("tips_main", &tips_layout),
            tips_layout,
            readback,
            readback_state: Arc::new(AtomicU8::new(IDLE)),
            last: None,
            reads: 0,
            last_total: 0,
        }
    }

    /// Forgets every blade's last LOD level (after the blades or the model change).
    pub fn reset_levels(&self, enc: &mut wgpu::CommandEncoder) {
        // Stored as level + 1: zero is "none".
        enc.clear_buffer(&self.lods, 0, None);
    }

    /// Replaces the order by x of the first `by_x.len()` blades (after they change; at most
    /// as many as it was made for).
    pub fn set_order(&self, queue: &wgpu::Queue, by_x: &[u32]) {
        let n = by_x.len().min(self.order.size() as usize / 4);
        if n > 0 {
            queue.write_buffer(&self.order, 0, bytemuck::cast_slice(&by_x[..n]));
        }
    }

    /// Records the pass over `blades` blades (groups 0 and 1 bound by the caller's values),
    /// walking them as `walk` says (nearest first: the depth test then spares the hidden
    /// blades' shading, where far-to-near shades every one).
    pub fn record(
        &mut self,
        queue: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        group0: &wgpu::BindGroup,
        shape: &wgpu::BindGroup,
        (blades, walk): (u32, Walk),
    ) {
        let mut words = [0u32; ARGS_WORDS];
        for (l, s) in LOD_SEGMENTS.iter().enumerate() {
            words[l * 4] = strip_vertices(*s);
        }
        // The far draw: its vertex count grows with the blades; one instance.
        words[FAR_DRAW as usize / 4 + 1] = 1;
        queue.write_buffer(&self.args, 0, bytemuck::cast_slice(&words));
        queue.write_buffer(
            &self.uniform,
            0,
            bytemuck::bytes_of(&CullUniform::new(&self.params, self.capacity, walk)),
        );
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("grass cull"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.main);
            pass.set_bind_group(0, group0, &[]);
            pass.set_bind_group(1, shape, &[]);
            pass.set_bind_group(2, &self.group, &[]);
            super::dispatch_blades(&mut pass, blades);
        }
        self.last_total = blades;
        if self.readback_state.load(Ordering::Acquire) == IDLE {
            enc.copy_buffer_to_buffer(&self.args, 0, &self.readback, 0, 64);
            self.readback_state.store(COPIED, Ordering::Release);
        }
    }

    /// Records the tips pass (tests) over `blades` blades into a new buffer of 16 bytes a
    /// blade, returned.
    pub(super) fn record_tips(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        (group0, shape): (&wgpu::BindGroup, &wgpu::BindGroup),
        blades: u32,
    ) -> wgpu::Buffer {
        let tips = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("grass tips"),
            size: u64::from(blades.max(1)) * 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("grass tips"),
            layout: &self.tips_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 5,
                resource: tips.as_entire_binding(),
            }],
        });
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&self.tips_pipeline);
        pass.set_bind_group(0, group0, &[]);
        pass.set_bind_group(1, shape, &[]);
        pass.set_bind_group(2, &group, &[]);
        super::dispatch_blades(&mut pass, blades);
        drop(pass);
        tips
    }

    /// Draws the blades of every level from the visible lists (group 2 is the level's): the
    /// near levels as instanced strips with `strip`, the far level's one-triangle blades as
    /// one triangle list with `far` (the draw arguments after the counters).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, [strip, far]: [&wgpu::RenderPipeline; 2]) {
        for (l, g) in self.level_groups.iter().enumerate() {
            pass.set_bind_group(2, g, &[]);
            if l == FAR_LEVEL {
                pass.set_pipeline(far);
                pass.draw_indirect(&self.args, FAR_DRAW);
            } else {
                pass.set_pipeline(strip);
                pass.draw_indirect(&self.args, l as u64 * 16);
            }
        }
    }

    /// After the frame's submission: starts reading the counters back without waiting, and
    /// returns the latest that arrived (the editor's counters, a frame or two behind).
    pub fn poll_stats(&mut self) -> Option<CullStats> {
        match self.readback_state.load(Ordering::Acquire) {
            COPIED => {
                self.readback_state.store(MAPPING, Ordering::Release);
                let state = self.readback_state.clone();
                self.readback
                    .slice(..)
                    .map_async(wgpu::MapMode::Read, move |r| {
                        state.store(if r.is_ok() { MAPPED } else { IDLE }, Ordering::Release);
                    });
            }
            MAPPED => {
                if let Ok(data) = self.readback.slice(..).get_mapped_range() {
                    let words: &[u32] = bytemuck::cast_slice(&data);
                    self.last = Some(CullStats::from_words(words, self.last_total));
                    self.reads += 1;
                }
                self.readback.unmap();
                self.readback_state.store(IDLE, Ordering::Release);
            }
            _ => {}
        }
        self.last
    }

    /// How many read-backs of the counters have arrived: two more than now, and counters of
    /// a frame recorded from now on have arrived.
    pub fn stats_reads(&self) -> u64 {
        self.reads
    }

    /// The far level's draw arguments `(vertex_count, instance_count, first_vertex,
    /// first_instance)`, as the last cull pass left them (tests; waits for the GPU).
    pub fn read_far_draw(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<[u32; 4], GpuError> {
        let words = crate::gpu::read_buffer(device, queue, &self.args)?;
        let words: &[u32] = bytemuck::cast_slice(&words);
        let at = FAR_DRAW as usize / 4;
        Ok([words[at], words[at + 1], words[at + 2], words[at + 3]])
    }

    /// The last frame's counters and each level's visible blade indices (waits for the GPU).
    pub fn read_stats(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<(CullStats, [Vec<u32>; 3]), GpuError> {
        let words = crate::gpu::read_buffer(device, queue, &self.args)?;
        let words: &[u32] = bytemuck::cast_slice(&words);
        let stats = CullStats::from_words(words, self.last_total);
        let all = crate::gpu::read_buffer(device, queue, &self.visible)?;
        let all: &[u32] = bytemuck::cast_slice(&all);
        let cap = self.capacity as usize;
        let lists = [0, 1, 2].map(|l| all[l * cap..][..stats.drawn[l] as usize].to_vec());
        Ok((stats, lists))
    }
}
