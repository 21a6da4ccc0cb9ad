//! The map backdrop laid over the grass's ground and tinting the blades' bases, and the
//! group the ground and the blades read it and the far field through.

pub(super) fn backdrop_texture(device: &wgpu::Device, size: [u32; 2]) -> wgpu::Texture {
    super::super::texture_2d(
        device,
        "grass backdrop",
        size,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    )
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
            super::super::texture_entry(5, both),
            // The far texels' density shares (`FarPass::shares`), sampled as the texels.
            super::super::texture_entry(6, both),
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
