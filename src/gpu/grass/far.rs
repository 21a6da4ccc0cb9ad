//! The far field on the GPU (`shaders/grass_far.wgsl`; CPU twin [`crate::grass::far`]): an
//! `rgba16float` texture over the world, each texel the blades' look from afar (rgb) and how
//! much of the ground takes it (a), recomputed each frame (the wind, the eye and the cull
//! change) and sampled, filtered, by the ground and the blades ([`super::look`]). A
//! texture rather than a buffer: on a software rasteriser the ground's four buffer loads
//! and its own interpolation per pixel cost about 100 ms a 1080p frame, one filtered sample
//! does not.

use super::super::buffer_entry as entry;
use crate::doc::Layout;
use crate::gpu::GpuError;
use crate::grass::cull::CullParams;
use crate::grass::far::{self, Look};
use bytemuck::{Pod, Zeroable};

/// The far field's settings as the shaders read them; mirrors `struct Far` in
/// `shaders/grass_common.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct FarUniform {
    pub origin: [f32; 2],
    pub cell: [f32; 2],
    pub nx: u32,
    pub ny: u32,
    /// Bits: 1 the ground shows the far field; 2 distance culling is on.
    pub flags: u32,
    pub buckets: u32,
    pub max_distance: f32,
    /// A blade budget's sample threshold (metres; 0: every blade drawn).
    pub sample_reach: f32,
    pub height: f32,
    pub width: f32,
    pub stiffness: f32,
    /// Blades a square metre.
    pub density: f32,
    /// The cull's density thinning (`CullParams::thin_distance`; 0: none).
    pub thin_distance: f32,
    pub _pad1: f32,
    pub base: [f32; 4],
    pub tip: [f32; 4],
}

/// The far field's texels, uniform and pipeline, and the ground's view of them.
pub struct FarPass {
    pub(super) uniform: FarUniform,
    pub(super) uniform_buf: wgpu::Buffer,
    pub(super) texels: wgpu::Texture,
    pub(super) sampler: wgpu::Sampler,
    /// The field's look by view direction in the wind at the level's edge, which the ground beyond the level takes
    /// ([`far::surround_table`]; [`far::SURROUND_AZIMUTHS`] × [`far::SURROUND_ELEVATIONS`]).
    pub(super) surround: wgpu::Texture,
    /// Each texel's share of the layout's density (the density map's mean over it,
    /// [`far::density_shares`]; 8 bits, filtered by the ground): the far pass thins the
    /// field's coverage by it and the ground its lower canopy.
    pub(super) shares: wgpu::Texture,
    /// The shares to upload at the next record, after a resize.
    shares_due: bool,
    /// The layout's density map, to take the shares of.
    density_map: Option<crate::doc::DensityMap>,
    compute_layout: wgpu::BindGroupLayout,
    compute_group: wgpu::BindGroup,
    pipeline: wgpu::ComputePipeline,
    surround_pipeline: wgpu::ComputePipeline,
    /// The world rectangle the texels cover.
    world: ([f32; 2], [f32; 2]),
}

impl FarPass {
    /// The far field of `layout`'s grass (`blades` of them; none: never drawn) under `sun`,
    /// one texel to start with (see [`Self::resize`]).
    pub fn new(
        device: &wgpu::Device,
        layout0: &wgpu::BindGroupLayout,
        module: &wgpu::ShaderModule,
        layout: &Layout,
        blades: u32,
        sun: [f32; 4],
    ) -> Self {
        use wgpu::ShaderStages as S;
        let g = &layout.grass;
        let look = Look::new(g, sun);
        let mid = |r: [f32; 2]| 0.5 * (r[0] + r[1]);
        let (min, max) = layout.bounds();
        let uniform = FarUniform {
            origin: min,
            cell: [max[0] - min[0], max[1] - min[1]],
            nx: 1,
            ny: 1,
            flags: u32::from(blades > 0),
            buckets: 1,
            max_distance: 1.0,
            sample_reach: 0.0,
            height: mid(g.height),
            width: mid(g.width),
            stiffness: mid(g.stiffness),
            density: g.density,
            thin_distance: 0.0,
            _pad1: 0.0,
            base: [look.base[0], look.base[1], look.base[2], 1.0],
            tip: [look.tip[0], look.tip[1], look.tip[2], 1.0],
        };
        let uniform_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("grass far"),
            size: std::mem::size_of::<FarUniform>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let texels = texel_texture(device, (1, 1));
        let shares = share_texture(device, (1, 1));
        let surround = texel_texture(
            device,
            (
                far::SURROUND_AZIMUTHS as u32,
                far::SURROUND_ELEVATIONS as u32,
            ),
        );
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("grass far"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let compute_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass far (compute)"),
            entries: &[
                entry(
                    0,
                    S::COMPUTE,
                    wgpu::BufferBindingType::Storage { read_only: true },
                ),
                crate::gpu::storage_texture_entry(1, FORMAT),
                crate::gpu::storage_texture_entry(2, FORMAT),
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: S::COMPUTE,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("grass far"),
            bind_group_layouts: &[Some(layout0), Some(&compute_layout)],
            immediate_size: 0,
        });
        let pipeline_for = |entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("grass_far"),
                layout: Some(&pipeline_layout),
                module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let pipeline = pipeline_for("main");
        let surround_pipeline = pipeline_for("surround");
        let compute_group = group(
            device,
            &compute_layout,
            &uniform_buf,
            [&texels, &surround, &shares],
        );
        Self {
            uniform,
            compute_group,
            uniform_buf,
            texels,
            sampler,
            surround,
            shares,
            shares_due: true,
            density_map: g.density_map.clone(),
            compute_layout,
            pipeline,
            surround_pipeline,
            world: (min, max),
        }
    }

    /// Sizes the texels for a wind grid of `nx × ny` cells ([`far::grid`]); whether they
    /// changed (the groups that read them must then be made again).
    pub fn resize(&mut self, device: &wgpu::Device, (nx, ny): (usize, usize)) -> bool {
        let (fx, fy) = far::grid(nx, ny);
        if (fx as u32, fy as u32) == (self.uniform.nx, self.uniform.ny) {
            return false;
        }
        let (min, max) = self.world;
        self.uniform.nx = fx as u32;
        self.uniform.ny = fy as u32;
        self.uniform.cell = [(max[0] - min[0]) / fx as f32, (max[1] - min[1]) / fy as f32];
        self.texels = texel_texture(device, (fx as u32, fy as u32));
        self.shares = share_texture(device, (fx as u32, fy as u32));
        self.shares_due = true;
        self.compute_group = group(
            device,
            &self.compute_layout,
            &self.uniform_buf,
            [&self.texels, &self.surround, &self.shares],
        );
        true
    }

    /// Each texel's share of the layout's density, row-major ([`far::density_shares`]).
    pub fn shares(&self) -> Vec<f32> {
        let n = (self.uniform.nx as usize, self.uniform.ny as usize);
        far::density_shares(self.density_map.as_ref(), self.world, n)
    }

    /// Whether the ground shows the far field (never for a layout with no blades).
    pub fn set_on(&mut self, on: bool, blades: u32) {
        self.uniform.flags = (self.uniform.flags & !1) | u32::from(on && blades > 0);
    }

    /// Records this frame's texels for the cull settings `cull` (the scene uniform, group 0,
    /// holds the eye, the time, the wind and the trail), and the table of the look of the
    /// ground beyond the level (it changes with the light and the grass, not the eye).
    pub fn record(
        &mut self,
        queue: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        group0: &wgpu::BindGroup,
        cull: &CullParams,
    ) {
        self.uniform.flags = (self.uniform.flags & 1) | (u32::from(cull.distance) << 1);
        self.uniform.buckets = cull.buckets.max(1);
        self.uniform.max_distance = cull.max_distance.max(1e-3);
        self.uniform.thin_distance = if cull.distance {
            cull.thin_distance
        } else {
            0.0
        };
        queue.write_buffer(&self.uniform_buf, 0, bytemuck::bytes_of(&self.uniform));
        if std::mem::take(&mut self.shares_due) {
            let bytes: Vec<u8> = (self.shares().iter())
                .map(|s| (s.clamp(0.0, 1.0) * 255.0).round() as u8)
                .collect();
            queue.write_texture(
                self.shares.as_image_copy(),
                &bytes,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.uniform.nx),
                    rows_per_image: Some(self.uniform.ny),
                },
                self.shares.size(),
            );
        }
        if self.uniform.flags & 1 == 0 {
            return;
        }
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("grass far"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group0, &[]);
        pass.set_bind_group(1, &self.compute_group, &[]);
        pass.dispatch_workgroups(self.uniform.nx.div_ceil(8), self.uniform.ny.div_ceil(8), 1);
        pass.set_pipeline(&self.surround_pipeline);
        pass.dispatch_workgroups(
            (far::SURROUND_AZIMUTHS as u32).div_ceil(8),
            (far::SURROUND_ELEVATIONS as u32).div_ceil(8),
            1,
        );
    }

    /// The texels, row-major: colour (rgb) and the share of the ground it takes (a) (for
    /// tests; waits for the GPU).
    pub fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        read_halves(device, queue, &self.texels)
    }

    /// The table of the ground beyond the level's look, row-major by elevation (for tests;
    /// waits for the GPU).
    pub fn read_surround(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        read_halves(device, queue, &self.surround)
    }
}

/// A texture of [`FORMAT`], row-major, as floats.
fn read_halves(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<[f32; 4]>, GpuError> {
    let bytes = crate::gpu::read_texture(device, queue, texture, 8)?;
    let half = |k: usize| half::f16::from_le_bytes([bytes[k], bytes[k + 1]]).to_f32();
    Ok((0..bytes.len() / 8)
        .map(|t| [0, 1, 2, 3].map(|c| half(t * 8 + c * 2)))
        .collect())
}

/// The texels' format: half floats are plenty for a colour and a share, and filterable and
/// writable from a compute pass on every adapter.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The texels' density shares, 8 bits each (a share to a 255th is plenty), filtered.
fn share_texture(device: &wgpu::Device, (w, h): (u32, u32)) -> wgpu::Texture {
    super::super::texture_2d(
        device,
        "grass far shares",
        [w.max(1), h.max(1)],
        wgpu::TextureFormat::R8Unorm,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    )
}

fn texel_texture(device: &wgpu::Device, (w, h): (u32, u32)) -> wgpu::Texture {
    super::super::texture_2d(
        device,
        "grass far texels",
        [w.max(1), h.max(1)],
        FORMAT,
        wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
    )
}

/// The compute pass's bind group over the uniform, the texels, the surround's table and the
/// density shares (the ground and the blades read them through
/// [`super::backdrop::look_group`]).
fn group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    uniform: &wgpu::Buffer,
    [texels, surround, shares]: [&wgpu::Texture; 3],
) -> wgpu::BindGroup {
    let view = |t: &wgpu::Texture| t.create_view(&Default::default());
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("grass far"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&view(texels)),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&view(surround)),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(&view(shares)),
            },
        ],
    })
}
