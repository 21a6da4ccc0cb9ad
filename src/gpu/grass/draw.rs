//! The grass's render pipelines, 4× multisampled: the obstacles' solids, the blades, the
//! ground, the sky and the arrows' lines, in the order they are drawn — the ground and the
//! blades also with the wind colours over them, as pipelines of their own so the plain ones
//! carry no trace of them (`GrassRenderer::set_wind_colours`).

use crate::grass::scene::SceneVertex;

const TRIANGLES: wgpu::PrimitiveTopology = wgpu::PrimitiveTopology::TriangleList;

pub(super) struct DrawPipelines {
    ground: wgpu::RenderPipeline,
    coloured_ground: wgpu::RenderPipeline,
    blades: wgpu::RenderPipeline,
    coloured_blades: wgpu::RenderPipeline,
    far_blades: wgpu::RenderPipeline,
    coloured_far_blades: wgpu::RenderPipeline,
    pub(super) solids: wgpu::RenderPipeline,
    pub(super) lines: wgpu::RenderPipeline,
    pub(super) sky: wgpu::RenderPipeline,
}

/// Samples a pixel of the grass's picture: 4× multisampling, which every WebGPU adapter
/// offers for its colour and depth formats. Blades are thinner than a pixel a few metres
/// away; one sample a pixel made them a speckle that crawled as they swayed.
pub const SAMPLES: u32 = 4;

impl DrawPipelines {
    /// Pipelines drawing into `format` with a [`super::DEPTH_FORMAT`] depth buffer. `module`
    /// compiles a listed grass shader; `[scene, shape, level]` are the scene group's (0), the
    /// poses and Bezier states' (1) and the cull pass's LOD level (2) layouts the blades bind;
    /// `look` the far field and backdrop group the ground binds as 1 and the blades as 3.
    pub(super) fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        module: &dyn Fn(&str) -> wgpu::ShaderModule,
        [scene, shape, level]: [&wgpu::BindGroupLayout; 3],
        look: &wgpu::BindGroupLayout,
    ) -> Self {
        let layout = |label: &str, groups: &[&wgpu::BindGroupLayout]| {
            let groups: Vec<_> = groups.iter().map(|g| Some(*g)).collect();
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: &groups,
                immediate_size: 0,
            })
        };
        let draw_layout = layout("grass draw", &[scene]);
        let blade_layout = layout("grass blades", &[scene, shape, level, look]);
        let ground_layout = layout("grass ground", &[scene, look]);
        let scene_vertex = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<SceneVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4],
        };
        let render = |name: &str,
                      [vs, fs]: [&str; 2],
                      topology: wgpu::PrimitiveTopology,
                      buffers: &[Option<wgpu::VertexBufferLayout<'_>>]| {
            let m = module(name);
            let overlay = fs == "fs_line";
            let sky = name == "grass_sky";
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(name),
                layout: Some(match name {
                    "grass_ground" => &ground_layout,
                    "grass_blades" => &blade_layout,
                    _ => &draw_layout,
                }),
                vertex: wgpu::VertexState {
                    module: &m,
                    entry_point: Some(vs),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    ..Default::default()
                },
                // The lines (the arrows, the map's footprint) are drawn last and over
                // everything, as an editor draws its gizmos: on the ground, the grass would
                // hide them wherever it is dense. The sky, drawn after the rest on the far
                // plane, only where the depth is still the cleared far plane's.
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: super::DEPTH_FORMAT,
                    depth_write_enabled: Some(!overlay && !sky),
                    depth_compare: Some(if overlay {
                        wgpu::CompareFunction::Always
                    } else if sky {
                        wgpu::CompareFunction::Equal
                    } else {
                        // Reversed depth: nearer is greater (`Camera::draw_view_proj`).
                        wgpu::CompareFunction::Greater
                    }),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: SAMPLES,
                    ..Default::default()
                },
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
        let strip = wgpu::PrimitiveTopology::TriangleStrip;
        Self {
            ground: render("grass_ground", ["vs_main", "fs_main"], TRIANGLES, &[]),
            coloured_ground: render(
                "grass_ground",
                ["vs_main", "fs_wind_colours"],
                TRIANGLES,
                &[],
            ),
            blades: render("grass_blades", ["vs_main", "fs_main"], strip, &[]),
            coloured_blades: render(
                "grass_blades",
                ["vs_wind_colours", "fs_wind_colours"],
                strip,
                &[],
            ),
            far_blades: render("grass_blades", ["vs_far", "fs_main"], TRIANGLES, &[]),
            coloured_far_blades: render(
                "grass_blades",
                ["vs_far_wind_colours", "fs_wind_colours"],
                TRIANGLES,
                &[],
            ),
            solids: render(
                "grass_scene",
                ["vs_main", "fs_solid"],
                TRIANGLES,
                &[Some(scene_vertex.clone())],
            ),
            lines: render(
                "grass_scene",
                ["vs_main", "fs_line"],
                wgpu::PrimitiveTopology::LineList,
                &[Some(scene_vertex)],
            ),
            sky: render("grass_sky", ["vs_main", "fs_main"], TRIANGLES, &[]),
        }
    }

    /// The ground's pipeline, with the wind colours or without.
    pub(super) fn ground(&self, wind_colours: bool) -> &wgpu::RenderPipeline {
        if wind_colours {
            &self.coloured_ground
        } else {
            &self.ground
        }
    }

    /// The blades' pipelines, with the wind colours or without: the near levels' instanced
    /// strips, and the far level's triangle list.
    pub(super) fn blades(&self, wind_colours: bool) -> [&wgpu::RenderPipeline; 2] {
        if wind_colours {
            [&self.coloured_blades, &self.coloured_far_blades]
        } else {
            [&self.blades, &self.far_blades]
        }
    }
}
