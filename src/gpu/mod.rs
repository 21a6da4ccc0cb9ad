//! The GPU side: device setup and the fluid passes, on wgpu (the same wgpu 30 that eframe and
//! egui-wgpu are built on, so one device can serve the UI and the wind). Everything here takes
//! `&wgpu::Device` and `&wgpu::Queue` and knows nothing of egui. Structs shared with WGSL are
//! `#[repr(C)]` + bytemuck and name the shader they mirror.

pub mod bench;
mod context;
pub mod fluid;
pub mod grass;
pub mod mapview;
pub mod multigrid;
mod solver;

pub use context::{GpuContext, GpuError, Submitter, device_descriptor, is_software};
pub use solver::GpuSolver;

/// The default adapter (lavapipe in CI) with the passes' device descriptor, `limits` changed
/// by the caller, or `None` (loudly) where there is none; CI must have one. For the library's
/// own GPU tests.
#[cfg(test)]
pub(crate) fn test_context(limits: impl FnOnce(&mut wgpu::Limits)) -> Option<GpuContext> {
    let instance = context::headless_instance().expect("WGPU_BACKEND names a backend");
    let adapter =
        match pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
        {
            Ok(a) => a,
            Err(e) if std::env::var_os("CI").is_none() => {
                eprintln!("SKIPPED: no GPU adapter ({e}); CI requires one");
                return None;
            }
            Err(e) => panic!("CI requires a GPU adapter (lavapipe): {e}"),
        };
    let mut desc = device_descriptor(&adapter);
    limits(&mut desc.required_limits);
    let (device, queue) = pollster::block_on(adapter.request_device(&desc)).unwrap();
    Some(GpuContext::from_parts(&adapter, device, queue).unwrap())
}

/// How many of each kind of wgpu resource the program holds, from wgpu's own report: what a
/// view that runs for hours must keep constant (a resource made per frame and kept shows
/// here as a count that climbs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LiveResources {
    pub buffers: usize,
    pub textures: usize,
    pub texture_views: usize,
    pub samplers: usize,
    pub bind_groups: usize,
    pub bind_group_layouts: usize,
    pub pipelines: usize,
    pub shader_modules: usize,
    pub query_sets: usize,
    pub command_encoders: usize,
    pub command_buffers: usize,
}

impl LiveResources {
    /// The resources `instance` holds for its user (`None` where wgpu has no report: a
    /// WebGPU instance).
    pub fn of(instance: &wgpu::Instance) -> Option<Self> {
        let report = instance.generate_report()?;
        let hub = report.hub_report();
        Some(Self {
            buffers: hub.buffers.num_kept_from_user,
            textures: hub.textures.num_kept_from_user,
            texture_views: hub.texture_views.num_kept_from_user,
            samplers: hub.samplers.num_kept_from_user,
            bind_groups: hub.bind_groups.num_kept_from_user,
            bind_group_layouts: hub.bind_group_layouts.num_kept_from_user,
            pipelines: hub.render_pipelines.num_kept_from_user
                + hub.compute_pipelines.num_kept_from_user,
            shader_modules: hub.shader_modules.num_kept_from_user,
            query_sets: hub.query_sets.num_kept_from_user,
            command_encoders: hub.command_encoders.num_kept_from_user,
            command_buffers: hub.command_buffers.num_kept_from_user,
        })
    }

    /// Whether `later` holds no more than `slack` more of any kind than `self`.
    pub fn at_most_plus(&self, later: &Self, slack: usize) -> bool {
        let kinds = |r: &Self| {
            [
                r.buffers,
                r.textures,
                r.texture_views,
                r.samplers,
                r.bind_groups,
                r.bind_group_layouts,
                r.pipelines,
                r.shader_modules,
                r.query_sets,
                r.command_encoders,
                r.command_buffers,
            ]
        };
        kinds(later)
            .iter()
            .zip(kinds(self))
            .all(|(&l, e)| l <= e + slack)
    }
}

/// A 2D texture of one mip level and one sample, `w × h` texels of `format`.
pub(crate) fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    [w, h]: [u32; 2],
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// A bind-group-layout entry for a filterable 2D float texture at `binding`, seen by the
/// `visibility` stages.
pub(crate) fn texture_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// Bind-group-layout entries for a filterable 2D float texture at `binding` and a filtering
/// sampler at `binding + 1`, seen by the `visibility` stages (the grass ground's and blades' images).
pub(crate) fn sampled_texture_entries(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> [wgpu::BindGroupLayoutEntry; 2] {
    [
        texture_entry(binding, visibility),
        wgpu::BindGroupLayoutEntry {
            binding: binding + 1,
            visibility,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            count: None,
        },
    ]
}

/// A bind-group-layout entry for a write-only 2D storage texture of `format` at `binding`, for
/// a compute pass.
pub(crate) fn storage_texture_entry(
    binding: u32,
    format: wgpu::TextureFormat,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        count: None,
    }
}

/// A bind-group-layout entry for a buffer at `binding` (the passes' explicit layouts).
pub(crate) fn buffer_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    ty: wgpu::BufferBindingType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A storage buffer holding `bytes` (readable back and rewritable).
pub(crate) fn storage(device: &wgpu::Device, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytes,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
    })
}

/// Whole-buffer entries at bindings 0, 1, 2… in order.
pub fn buffer_entries<'a>(buffers: &[&'a wgpu::Buffer]) -> Vec<wgpu::BindGroupEntry<'a>> {
    buffers
        .iter()
        .enumerate()
        .map(|(k, b)| wgpu::BindGroupEntry {
            binding: k as u32,
            resource: b.as_entire_binding(),
        })
        .collect()
}

/// A bind group of whole buffers at bindings 0, 1, 2… in order.
pub fn buffers_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    let entries = buffer_entries(buffers);
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// A 2D texture's texels, rows packed tightly (`texel` bytes each; waits for the GPU).
pub fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    texel: u32,
) -> Result<Vec<u8>, GpuError> {
    let (w, h) = (texture.width(), texture.height());
    let row = (w * texel).div_ceil(256) * 256;
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("texture read-back"),
        size: u64::from(row * h),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&Default::default());
    enc.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &out,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(h),
            },
        },
        texture.size(),
    );
    queue.submit([enc.finish()]);
    let bytes = read_buffer(device, queue, &out)?;
    Ok((0..h as usize)
        .flat_map(|y| bytes[y * row as usize..][..(w * texel) as usize].to_vec())
        .collect())
}

/// Copies `src` (a buffer with `COPY_SRC`) back to the CPU; waits for the GPU.
pub fn read_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    src: &wgpu::Buffer,
) -> Result<Vec<u8>, GpuError> {
    read_buffer_via(
        device,
        &|cb| {
            queue.submit([cb]);
        },
        src,
    )
}

/// [`read_buffer`], its copy submitted by `submit`.
pub fn read_buffer_via(
    device: &wgpu::Device,
    submit: &dyn Fn(wgpu::CommandBuffer),
    src: &wgpu::Buffer,
) -> Result<Vec<u8>, GpuError> {
    let size = src.size();
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read-back"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&Default::default());
    enc.copy_buffer_to_buffer(src, 0, &staging, 0, size);
    submit(enc.finish());
    let (tx, rx) = std::sync::mpsc::channel();
    staging.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    let runtime = |message: String| GpuError::Runtime {
        what: "reading a buffer back".into(),
        message,
    };
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| runtime(e.to_string()))?;
    rx.recv()
        .map_err(|e| runtime(e.to_string()))?
        .map_err(|e| runtime(e.to_string()))?;
    let data = staging
        .slice(..)
        .get_mapped_range()
        .map_err(|e| runtime(e.to_string()))?
        .to_vec();
    staging.unmap();
    Ok(data)
}
