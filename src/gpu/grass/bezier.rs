//! The Bezier physics blades' compute pass (`shaders/grass_bezier.wgsl`, issue 12): per-blade
//! control points on the GPU, advanced in the fixed steps of [`crate::grass::bezier`] — its CPU
//! twin. Not yet drawn, culled or level-of-detailed: this is the simulation alone.

use super::GrassRenderer;
use crate::gpu::GpuError;
use crate::grass::Blade;
use crate::grass::bezier::{RECOVERY, STEP, State, WIND};
use wgpu::util::DeviceExt;

/// A blade's control points; mirrors `struct BezierState` in `shaders/grass_bezier.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BezierState {
    pub v0: [f32; 4],
    pub v1: [f32; 4],
    pub v2: [f32; 4],
}

/// The pass's parameters; mirrors `struct Physics` in `shaders/grass_bezier.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct Physics {
    steps: u32,
    dt: f32,
    recovery: f32,
    wind_k: f32,
}

/// Every blade's Bezier state on the GPU, and the pass that steps it.
pub struct BezierPass {
    states: wgpu::Buffer,
    physics: wgpu::Buffer,
    group: wgpu::BindGroup,
    pipeline: wgpu::ComputePipeline,
    blades: u32,
    /// Simulated time not yet stepped (less than one [`STEP`]).
    carry: f32,
}

impl BezierPass {
    /// The blades at rest (upright), for `grass`'s blades.
    pub fn new(device: &wgpu::Device, grass: &GrassRenderer, blades: &[Blade]) -> Self {
        let v4 = |v: [f32; 3]| [v[0], v[1], v[2], 0.0];
        let init: Vec<BezierState> = blades
            .iter()
            .map(|b| {
                let s = State::rest(b);
                BezierState {
                    v0: v4(s.v0),
                    v1: v4(s.v1),
                    v2: v4(s.v2),
                }
            })
            .collect();
        let bytes: &[u8] = if init.is_empty() {
            &[0; 48]
        } else {
            bytemuck::cast_slice(&init)
        };
        let states = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("bezier states"),
            contents: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let physics = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("bezier physics"),
            size: std::mem::size_of::<Physics>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (layout0, _) = grass.scene_group();
        let layout1 = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("bezier"),
            entries: &[
                crate::gpu::buffer_entry(
                    0,
                    wgpu::ShaderStages::COMPUTE,
                    wgpu::BufferBindingType::Storage { read_only: false },
                ),
                crate::gpu::buffer_entry(
                    1,
                    wgpu::ShaderStages::COMPUTE,
                    wgpu::BufferBindingType::Uniform,
                ),
            ],
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("bezier"),
            layout: &layout1,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: states.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: physics.as_entire_binding(),
                },
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("bezier"),
            bind_group_layouts: &[Some(layout0), Some(&layout1)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("grass_bezier"),
            source: wgpu::ShaderSource::Wgsl(
                super::shader_source("grass_bezier").expect("listed").into(),
            ),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("grass_bezier"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        Self {
            states,
            physics,
            group,
            pipeline,
            blades: blades.len() as u32,
            carry: 0.0,
        }
    }

    /// Records `dt` seconds of simulation in fixed [`STEP`]s (the remainder carried to the
    /// next call), in the wind `grass` holds; the scene uniform must be current (a
    /// [`GrassRenderer::prepare`] this frame).
    pub fn advance(
        &mut self,
        queue: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        grass: &GrassRenderer,
        dt: f32,
    ) {
        self.carry += dt;
        let steps = (self.carry / STEP).floor();
        self.carry -= steps * STEP;
        let physics = Physics {
            steps: steps as u32,
            dt: STEP,
            recovery: RECOVERY,
            wind_k: WIND,
        };
        queue.write_buffer(&self.physics, 0, bytemuck::bytes_of(&physics));
        let (_, group0) = grass.scene_group();
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("grass bezier"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group0, &[]);
        pass.set_bind_group(1, &self.group, &[]);
        pass.dispatch_workgroups(self.blades.div_ceil(64), 1, 1);
    }

    /// Every blade's control points, read back (for tests; waits for the GPU).
    pub fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<BezierState>, GpuError> {
        let bytes = crate::gpu::read_buffer(device, queue, &self.states)?;
        Ok(bytemuck::cast_slice(&bytes)[..self.blades as usize].to_vec())
    }
}
