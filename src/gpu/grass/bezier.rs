//! The Bezier physics blades' compute pass (`shaders/grass_bezier.wgsl`, issue 12): per-blade
//! control points on the GPU, advanced in the fixed steps of [`crate::grass::bezier`] — its CPU
//! twin. The renderer owns one while the Bezier model is chosen
//! ([`super::GrassRenderer::set_model`]); the cull pass and the vertex shader read its states.

use crate::gpu::GpuError;
use crate::grass::bezier::{RECOVERY, STEP, WIND};

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
    pub(super) states: wgpu::Buffer,
    physics: wgpu::Buffer,
    group: wgpu::BindGroup,
    pipeline: wgpu::ComputePipeline,
    rest: wgpu::ComputePipeline,
    /// Simulated time not yet stepped (less than one [`STEP`]).
    carry: f32,
}

impl BezierPass {
    /// States for `blades` blades (set upright by [`Self::record_rest`]); `layout0`: the
    /// renderer's group 0.
    pub(super) fn new(device: &wgpu::Device, layout0: &wgpu::BindGroupLayout, blades: u32) -> Self {
        let states = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("bezier states"),
            size: u64::from(blades.max(1)) * std::mem::size_of::<BezierState>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let physics = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("bezier physics"),
            size: std::mem::size_of::<Physics>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
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
                    wgpu::BufferBindingType::Storage { read_only: true },
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
        let pipeline = |entry_point: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry_point),
                layout: Some(&layout),
                module: &module,
                entry_point: Some(entry_point),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        Self {
            states,
            physics,
            group,
            pipeline: pipeline("main"),
            rest: pipeline("rest_main"),
            carry: 0.0,
        }
    }

    /// Records every one of `blades` blades set upright, at rest.
    pub(super) fn record_rest(
        &mut self,
        enc: &mut wgpu::CommandEncoder,
        group0: &wgpu::BindGroup,
        blades: u32,
    ) {
        self.carry = 0.0;
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&self.rest);
        pass.set_bind_group(0, group0, &[]);
        pass.set_bind_group(1, &self.group, &[]);
        super::dispatch_blades(&mut pass, blades);
    }

    /// Records `dt` seconds of simulation in fixed [`STEP`]s (the remainder carried to the
    /// next call), for `blades` blades, with the scene uniform's wind, sphere and trail.
    pub(super) fn advance(
        &mut self,
        queue: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        group0: &wgpu::BindGroup,
        blades: u32,
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
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("grass bezier"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group0, &[]);
        pass.set_bind_group(1, &self.group, &[]);
        super::dispatch_blades(&mut pass, blades);
    }

    /// Every blade's control points, read back (for tests; waits for the GPU).
    pub fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        blades: u32,
    ) -> Result<Vec<BezierState>, GpuError> {
        let bytes = crate::gpu::read_buffer(device, queue, &self.states)?;
        Ok(bytemuck::cast_slice(&bytes)[..blades as usize].to_vec())
    }
}
