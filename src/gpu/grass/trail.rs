//! The pushing sphere's trail on the GPU (`shaders/grass_trail.wgsl`; CPU twin
//! [`crate::grass::trail::Trail`]): an `r32float` world-space texture the grass passes read
//! (group 0), stepped each frame into a second texture and copied back.

use crate::gpu::GpuError;

pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

pub struct TrailPass {
    pub(super) texture: wgpu::Texture,
    next: wgpu::Texture,
    group: wgpu::BindGroup,
    pipeline: wgpu::ComputePipeline,
    pub nx: u32,
    pub ny: u32,
}

impl TrailPass {
    pub fn new(
        device: &wgpu::Device,
        layout0: &wgpu::BindGroupLayout,
        module: &wgpu::ShaderModule,
        (nx, ny): (u32, u32),
    ) -> Self {
        let texture = |label, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: nx,
                    height: ny,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: FORMAT,
                usage,
                view_formats: &[],
            })
        };
        let tex = texture(
            "grass trail",
            wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_DST
                | wgpu::TextureUsages::COPY_SRC,
        );
        let next = texture(
            "grass trail next",
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
        );
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass trail"),
            entries: &[crate::gpu::storage_texture_entry(0, FORMAT)],
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("grass trail"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(
                    &next.create_view(&Default::default()),
                ),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("grass trail"),
            bind_group_layouts: &[Some(layout0), Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("grass_trail"),
            layout: Some(&pipeline_layout),
            module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        Self {
            texture: tex,
            next,
            group,
            pipeline,
            nx,
            ny,
        }
    }

    /// Records one step of the trail (the scene uniform holds the sphere, dt and lifetime),
    /// and the copy that makes it the trail the grass reads.
    pub fn record(&self, enc: &mut wgpu::CommandEncoder, group0: &wgpu::BindGroup) {
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("grass trail"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, group0, &[]);
            pass.set_bind_group(1, &self.group, &[]);
            pass.dispatch_workgroups(self.nx.div_ceil(8), self.ny.div_ceil(8), 1);
        }
        enc.copy_texture_to_texture(
            self.next.as_image_copy(),
            self.texture.as_image_copy(),
            self.texture.size(),
        );
    }

    /// The trail's texels, row-major (for tests; waits for the GPU).
    pub fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Vec<f32>, GpuError> {
        let bytes = crate::gpu::read_texture(device, queue, &self.texture, 4)?;
        Ok(bytemuck::cast_slice(&bytes).to_vec())
    }
}
