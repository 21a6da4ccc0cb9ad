//! The grass without a window: `windloom render --view grass` and `windloom bench --grass`.

use super::{
    Camera, CullStats, FramePart, GrassRenderer, SAMPLES, Target, max_blades, render_into,
    render_offscreen,
};
use crate::doc::{GrassModel, Layout};
use crate::gpu::GpuError;
use crate::grass::cull::CullParams;

/// Frames a second the headless renders step the Bezier blades at.
const FPS: f32 = 60.0;

/// Lets the Bezier blades (with the CWD model: nothing to settle) answer the wind for
/// `seconds` before a picture at `time`, at 60 frames a second.
pub fn settle(
    ctx: &crate::gpu::GpuContext,
    grass: &mut GrassRenderer,
    camera: &Camera,
    time: f32,
    seconds: f32,
) {
    if grass.model() != GrassModel::BezierPhysics {
        return;
    }
    let frames = (seconds * FPS).round() as usize;
    for k in 0..frames {
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        let t = time - seconds + k as f32 / FPS;
        grass.prepare(&ctx.queue, &mut enc, camera, 16.0 / 9.0, t, 1.0 / FPS);
        ctx.queue.submit([enc.finish()]);
    }
}

/// Gives `grass` the layout's wind after `time` simulated seconds (the CPU solver); returns
/// the top of its speed scale ([`crate::colour::speed_scale`]).
fn wind_at(
    ctx: &crate::gpu::GpuContext,
    grass: &mut GrassRenderer,
    layout: &Layout,
    time: f32,
) -> f32 {
    let mut solver = crate::sim::Solver::new(layout);
    let steps = (time / layout.sim.dt).round().max(0.0) as usize;
    for _ in 0..steps {
        solver.step();
    }
    let velocity = solver.velocity_field();
    grass.set_wind(
        &ctx.device,
        &ctx.queue,
        (solver.nx, solver.ny),
        solver.origin,
        [solver.hx, solver.hz],
        &velocity,
    );
    crate::colour::speed_scale(&velocity)
}

/// How `windloom render --view grass` draws: the picture's size, the wind's time, the camera
/// (when `None`, the whole world framed as the editor's "frame all" frames it:
/// [`super::Orbit::frame_all`]), the paper's literal equations, and a sphere rolled
/// through the grass before the picture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PictureOptions {
    pub size: [u32; 2],
    pub time: f32,
    pub camera: Option<Camera>,
    pub paper_literal: bool,
    pub push: Option<PushPath>,
    /// The wind colours' opacity (`None`: off), as the editor's 3D view draws them.
    pub wind_colours: Option<f32>,
    /// The speed (m/s) at the top of the wind colours (`None`: the field's peak), as the
    /// editor's fixed speed scale.
    pub speed_scale: Option<f32>,
    /// Draw the AGC arrows over the grass, as the editor's 3D view does (`render
    /// --no-arrows`: a picture of the grass alone).
    pub arrows: bool,
}

impl Default for PictureOptions {
    /// `render --view grass`'s defaults: 1600 × 1000 after 6 s, the whole level framed, the
    /// layout's own grass, no wind colours, the arrows drawn.
    fn default() -> Self {
        Self {
            size: [1600, 1000],
            time: 6.0,
            camera: None,
            paper_literal: false,
            push: None,
            wind_colours: None,
            speed_scale: None,
            arrows: true,
        }
    }
}

/// A sphere of `radius` rolled from `from` to `to` (world `(x, z)`) over the second before the
/// picture; its trail shows in it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PushPath {
    pub from: [f32; 2],
    pub to: [f32; 2],
    pub radius: f32,
}

/// How many blades `layout` lays out, and how many the device holds ([`max_blades`]).
fn blade_room(ctx: &crate::gpu::GpuContext, layout: &Layout) -> (usize, usize) {
    let (nx, nz, _) = crate::grass::strata(layout);
    (nx * nz, max_blades(&ctx.device.limits()))
}

/// `layout`'s blades, thinned evenly to what the device can hold ([`max_blades`]), with a
/// warning when they are.
pub(crate) fn scatter_for(
    ctx: &crate::gpu::GpuContext,
    layout: &Layout,
) -> Vec<crate::grass::Blade> {
    let most = max_blades(&ctx.device.limits());
    let (blades, of_layout) = crate::grass::scatter_fitted(layout, most);
    if let Some(wanted) = of_layout {
        log::warn!(
            "the layout's ~{wanted} blades are more than {} can hold: drawing {}, thinned evenly",
            ctx.describe(),
            blades.len()
        );
    }
    blades
}

/// A picture of `layout`'s grass in its wind after `time` seconds: RGBA8 sRGB pixels, `size`
/// wide and high, the ground under the grass showing `backdrop` (the layout's map image,
/// decoded by the caller: `io::layout_backdrop`) at the map's opacity.
/// `windloom render --view grass`.
pub fn picture(
    ctx: &crate::gpu::GpuContext,
    layout: &Layout,
    backdrop: Option<&image::RgbaImage>,
    o: &PictureOptions,
) -> Result<Vec<u8>, GpuError> {
    let (size, time) = (o.size, o.time);
    let blades = scatter_for(ctx, layout);
    let mut grass = GrassRenderer::new(
        &ctx.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        layout,
        &blades,
    );
    grass.set_paper_literal(o.paper_literal);
    grass.set_model(&ctx.device, &ctx.queue, layout.grass.model);
    if let Some(img) = backdrop {
        let size = [img.width(), img.height()];
        let opacity = layout.world.map.as_ref().map_or(1.0, |m| m.opacity);
        grass.set_backdrop(&ctx.device, &ctx.queue, Some((img.as_raw(), size, opacity)));
    }
    grass.set_layout_scene(&ctx.device, layout, o.arrows);
    let peak = wind_at(ctx, &mut grass, layout, time);
    let scale = o.speed_scale.unwrap_or(peak);
    grass.set_wind_colours(o.wind_colours.map(|opacity| (opacity, scale)));
    let aspect = o.size[0].max(1) as f32 / o.size[1].max(1) as f32;
    let camera = o
        .camera
        .unwrap_or_else(|| super::Orbit::frame_all(layout, aspect).camera());
    settle(ctx, &mut grass, &camera, time, 3.0);
    if let Some(p) = o.push {
        let frames = FPS as usize;
        for k in 0..=frames {
            let f = k as f32 / frames as f32;
            let at = |a: f32, b: f32| a + (b - a) * f;
            grass.set_sphere((k < frames).then_some(crate::grass::trail::Sphere {
                centre: [
                    at(p.from[0], p.to[0]),
                    0.5 * p.radius,
                    at(p.from[1], p.to[1]),
                ],
                radius: p.radius,
            }));
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            grass.prepare(&ctx.queue, &mut enc, &camera, 16.0 / 9.0, time, 1.0 / FPS);
            ctx.queue.submit([enc.finish()]);
        }
    }
    let (pixels, _) = render_offscreen(ctx, &mut grass, &camera, (time, 1.0 / FPS), size)?;
    Ok(pixels)
}

/// `windloom bench --grass N --model cwd|bezier --cull on|off`: frame times drawing about
/// `blades` blades of `layout` (its density raised or lowered to give that many) at `size`, in
/// its wind after 2 s, seen by `camera` ([`Camera::walk`] when `None`: standing in the grass);
/// every compute pass included (for the Bezier model, one frame's physics at 60 fps).
#[derive(Debug, Clone, serde::Serialize)]
pub struct GrassBench {
    pub adapter: String,
    pub adapter_type: String,
    pub model: String,
    pub cull: bool,
    /// The wind colours' opacity (`None`: off).
    pub wind_colours: Option<f32>,
    /// The blades drawn nearest first, or in their stored order (`--stored-order`).
    pub near_first: bool,
    pub blades: u32,
    pub size: [u32; 2],
    pub frames: usize,
    pub median_ms: f64,
    pub min_ms: f64,
    /// Median milliseconds of the compute passes alone (wind, model, far field, cull) and of
    /// the render pass alone, each submitted and waited for: where a frame's time goes.
    pub compute_ms: f64,
    pub draw_ms: f64,
    /// The last frame's counters: culled by each test, drawn per LOD level.
    pub culled: CullStats,
    /// Segments per blade at each LOD level.
    pub lod_segments: [u32; 3],
    /// Triangles the last frame drew ([`crate::grass::cull::triangles`] of `culled.drawn`).
    pub triangles: u64,
    /// The samples one frame's render pass wrote: the pixels' side of a frame, as the
    /// triangles are the geometry's (`None` on a GL adapter, whose occlusion queries only say
    /// whether any sample passed).
    pub written: Option<Written>,
}

/// The samples a render pass wrote: those that passed the depth test (an occlusion query), on
/// any adapter. A GPU shades a fragment where one of its samples passes, so the layers
/// written are the layers shaded, and the picture's own layer is one of them.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Written {
    pub samples: u64,
    /// `samples` over the picture's samples (pixels × [`SAMPLES`]): how many times a
    /// sample is written, 1 with no overdraw at all.
    pub layers: f64,
}

/// Counts the samples one render pass into `target` writes over the blades the last compute
/// passes kept; `None` on a GL adapter (wgpu asks GL whether any sample passed, not how many).
pub fn count_written(
    ctx: &crate::gpu::GpuContext,
    grass: &GrassRenderer,
    target: &Target,
) -> Result<Option<Written>, GpuError> {
    if ctx.adapter.backend == wgpu::Backend::Gl {
        return Ok(None);
    }
    let device = &ctx.device;
    let set = device.create_query_set(&wgpu::QuerySetDescriptor {
        label: Some("grass samples written"),
        ty: wgpu::QueryType::Occlusion,
        count: 1,
    });
    let resolved = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("grass samples written"),
        size: 8,
        usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&Default::default());
    grass.record_draw_counted(&mut enc, target, Some(&set));
    enc.resolve_query_set(&set, 0..1, &resolved, 0);
    ctx.queue.submit([enc.finish()]);
    let bytes = crate::gpu::read_buffer(device, &ctx.queue, &resolved)?;
    let samples: u64 = bytemuck::pod_read_unaligned(&bytes[..8]);
    let all = f64::from(target.size[0]) * f64::from(target.size[1]) * f64::from(SAMPLES);
    Ok(Some(Written {
        samples,
        layers: samples as f64 / all.max(1.0),
    }))
}

/// What `bench --grass N --estimate` reports: what the cull would draw of `blades` blades at
/// a camera, from its CPU twin ([`crate::grass::cull::estimate_drawn`]) on `sample` of them.
#[derive(Debug, Clone, serde::Serialize)]
pub struct GrassEstimate {
    pub blades: usize,
    pub size: [u32; 2],
    pub sample: u32,
    /// Blades drawn at each LOD level.
    pub drawn: [u64; 3],
    pub triangles: u64,
    pub lod_segments: [u32; 3],
}

/// Blades the estimate classifies (enough for the counts to within about 1 %).
pub const ESTIMATE_SAMPLE: u32 = 400_000;

/// What the cull would draw of `blades` blades of `layout` (at the density that gives that
/// many) seen by `camera` ([`Camera::walk`] when `None`) in a picture of `size`.
pub fn estimate(
    layout: &Layout,
    blades: usize,
    camera: Option<Camera>,
    size: [u32; 2],
) -> GrassEstimate {
    let mut layout = layout.clone();
    let area = layout.world.size[0] * layout.world.size[1];
    layout.grass.density = (blades as f32 / area).max(1e-3);
    let camera = camera.unwrap_or_else(|| Camera::walk(&layout));
    let aspect = size[0].max(1) as f32 / size[1].max(1) as f32;
    let params = CullParams::for_grass(&layout.grass);
    let drawn = crate::grass::cull::estimate_drawn(
        &layout,
        blades as u64,
        camera.eye.to_array(),
        &camera.view_proj(aspect),
        &params,
        ESTIMATE_SAMPLE,
    )
    .map(|d| d.round() as u64);
    GrassEstimate {
        blades,
        size,
        sample: ESTIMATE_SAMPLE,
        drawn,
        triangles: crate::grass::cull::triangles(drawn),
        lod_segments: crate::grass::cull::LOD_SEGMENTS,
    }
}

/// What `bench --grass` times: about `blades` blades, pictures of `size`, `frames` timed
/// frames, the model, culling on or off, the camera ([`Camera::walk`] when `None`) and the
/// wind colours.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BenchOptions {
    pub blades: usize,
    pub size: [u32; 2],
    pub frames: usize,
    pub model: GrassModel,
    pub cull: bool,
    pub camera: Option<Camera>,
    /// The wind colours' opacity (`None`: off).
    pub wind_colours: Option<f32>,
    /// The blades drawn nearest first (the renderer's way), or in their stored order.
    pub near_first: bool,
}

pub fn bench(
    ctx: &crate::gpu::GpuContext,
    layout: &Layout,
    o: &BenchOptions,
) -> Result<GrassBench, GpuError> {
    let BenchOptions {
        blades,
        size,
        frames,
        model,
        cull,
        camera,
        wind_colours,
        near_first,
    } = *o;
    let mut layout = layout.clone();
    let area = layout.world.size[0] * layout.world.size[1];
    layout.grass.density = (blades as f32 / area).max(1e-3);
    let (wanted, most) = blade_room(ctx, &layout);
    if wanted > most {
        return Err(GpuError::Unsupported {
            adapter: ctx.describe(),
            what: format!(
                "hold {wanted} blades: its storage buffers bind {} MiB, room for {most} blades",
                ctx.device.limits().max_storage_buffer_binding_size >> 20
            ),
        });
    }
    let placed = crate::grass::scatter(&layout);
    let mut grass = GrassRenderer::new(
        &ctx.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        &layout,
        &placed,
    );
    grass.set_model(&ctx.device, &ctx.queue, model);
    if !cull {
        grass.set_cull(CullParams::OFF);
    }
    grass.set_near_first(near_first);
    let scale = wind_at(ctx, &mut grass, &layout, 2.0);
    grass.set_wind_colours(wind_colours.map(|opacity| (opacity, scale)));
    let camera = camera.unwrap_or_else(|| Camera::walk(&layout));
    let target = Target::new(&ctx.device, size, ctx.downlevel);
    // One untimed frame (pipelines, first use of the buffers), then the timed ones.
    let whole = FramePart::Whole;
    render_into(
        &ctx.device,
        &ctx.queue,
        &mut grass,
        &camera,
        (2.0, 1.0 / FPS),
        &target,
        whole,
    )?;
    // Whole frames, then (where the time goes) the compute passes alone and the render pass
    // alone over the blades the last compute passes kept, each submitted and waited for:
    // sorted milliseconds.
    let mut timed = |part| -> Result<Vec<f64>, GpuError> {
        let mut t = Vec::with_capacity(frames.max(1));
        for k in 0..frames.max(1) {
            t.push(render_into(
                &ctx.device,
                &ctx.queue,
                &mut grass,
                &camera,
                (2.0 + k as f32 / FPS, 1.0 / FPS),
                &target,
                part,
            )?);
        }
        t.sort_by(f64::total_cmp);
        Ok(t)
    };
    let times = timed(FramePart::Whole)?;
    let median = |t: &[f64]| t[t.len() / 2];
    let compute_ms = median(&timed(FramePart::Compute)?);
    let draw_ms = median(&timed(FramePart::Draw)?);
    let (culled, _) = grass.read_cull(&ctx.device, &ctx.queue)?;
    let written = count_written(ctx, &grass, &target)?;
    // Frames timed on a faulted device drew nothing worth timing.
    ctx.check("drawing the grass")?;
    Ok(GrassBench {
        adapter: ctx.adapter.name.clone(),
        adapter_type: format!("{:?}", ctx.adapter.device_type),
        model: match model {
            GrassModel::CwdQuadratic => "cwd",
            GrassModel::BezierPhysics => "bezier",
        }
        .into(),
        cull,
        wind_colours,
        near_first,
        blades: grass.blade_count(),
        size,
        frames: times.len(),
        median_ms: times[times.len() / 2],
        min_ms: times[0],
        compute_ms,
        draw_ms,
        triangles: crate::grass::cull::triangles(culled.drawn.map(u64::from)),
        culled,
        lod_segments: crate::grass::cull::LOD_SEGMENTS,
        written,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meadow() -> Layout {
        let text = include_str!("../../../layouts/meadow.json");
        crate::doc::parse(text).unwrap()
    }

    /// A device that binds 8 MiB per storage buffer holds 174,762 blades; the meadow has
    /// about 600,000. Its picture thins them evenly instead of failing validation, and a bench
    /// that asks for more than the device holds is refused with the limit named.
    #[test]
    fn grass_beyond_the_device_s_buffers_is_thinned_or_refused() {
        let Some(ctx) = crate::gpu::test_context(|l| l.max_storage_buffer_binding_size = 8 << 20)
        else {
            return;
        };
        let layout = meadow();
        let most = max_blades(&ctx.device.limits());
        assert_eq!(most, (8 << 20) / 48);
        let (nx, nz, _) = crate::grass::strata(&layout);
        assert!(nx * nz > 3 * most, "the meadow must be over the limit");

        let blades = scatter_for(&ctx, &layout);
        assert!(blades.len() <= most && blades.len() > most * 9 / 10);
        // Evenly: each quarter of the world keeps about a quarter of them.
        let (min, max) = layout.bounds();
        let mid = [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0];
        for q in 0..4 {
            let n = blades
                .iter()
                .filter(|b| (b.pos[0] < mid[0]) == (q & 1 == 0) && (b.pos[1] < mid[1]) == (q < 2))
                .count();
            let share = n as f32 / blades.len() as f32;
            assert!((share - 0.25).abs() < 0.03, "quarter {q}: {share}");
        }

        let o = PictureOptions {
            size: [96, 64],
            time: 0.5,
            ..Default::default()
        };
        let pixels = picture(&ctx, &layout, None, &o).expect("a thinned picture");
        assert_eq!(pixels.len(), 96 * 64 * 4);
        assert!(ctx.fault().is_none(), "{:?}", ctx.fault());

        let asked = BenchOptions {
            blades: 2 * most,
            size: [64, 64],
            frames: 1,
            model: GrassModel::CwdQuadratic,
            cull: true,
            camera: None,
            wind_colours: None,
            near_first: true,
        };
        let e = bench(&ctx, &layout, &asked).unwrap_err().to_string();
        assert!(
            e.contains(&format!("room for {most} blades")) && e.contains("8 MiB"),
            "{e}"
        );
    }
}
