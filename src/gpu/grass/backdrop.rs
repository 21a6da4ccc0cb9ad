//! The map backdrop laid over the grass's ground and tinting the blades' bases, and the
//! group the ground and the blades read it and the far field through.

pub(super) fn backdrop_texture(device: &wgpu::Device, [w, h]: [u32; 2]) -> wgpu::Texture {
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

/// The layout of the group the ground (group 1) and the blades (group 3) read the far field
/// and the map backdrop through: the far field's uniform (0), its texels (1) and sampler
/// (2), the backdrop image (3) and its sampler (4), seen by both stages (the blades sample
/// them at their roots, in the vertex stage), and the table of the ground beyond the level's
/// look (5, loaded texel by texel).
pub(super) fn look_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    use wgpu::ShaderStages as S;
    let both = S::VERTEX | S::FRAGMENT;
    let [far_texels, far_sampler] = super::super::sampled_texture_entries(1, both);
    let [image, image_sampler] = super::super::sampled_texture_entries(3, both);
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("grass look"),
        entries: &[
            super::super::buffer_entry(
                0,
                both,
                wgpu::BufferBindingType::Storage { read_only: true },
            ),
            far_texels,
            far_sampler,
            image,
            image_sampler,
            wgpu::BindGroupLayoutEntry {
                binding: 5,
                visibility: both,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            // The far texels' density shares (`FarPass::shares`), sampled as the texels.
            wgpu::BindGroupLayoutEntry {
                binding: 6,
                visibility: both,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
        ],
    })
}

/// The group of [`look_layout`] over the far field's uniform and texels and the backdrop.
pub(super) fn look_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    far: &super::FarPass,
    backdrop: &wgpu::Texture,
) -> wgpu::BindGroup {
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("grass backdrop"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("grass look"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: far.uniform_buf.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(
                    &far.texels.create_view(&Default::default()),
                ),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(&far.sampler),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::TextureView(
                    &backdrop.create_view(&Default::default()),
                ),
            },
            wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::Sampler(&sampler),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(
                    &far.surround.create_view(&Default::default()),
                ),
            },
            wgpu::BindGroupEntry {
                binding: 6,
                resource: wgpu::BindingResource::TextureView(
                    &far.shares.create_view(&Default::default()),
                ),
            },
        ],
    })
}
