//! The grass without a window: `windloom render --view grass` and `windloom bench --grass`.

use super::{Camera, GrassRenderer, render_offscreen};
use crate::doc::Layout;
use crate::gpu::GpuError;

/// Gives `grass` the layout's wind after `time` simulated seconds (the CPU solver).
fn wind_at(ctx: &crate::gpu::GpuContext, grass: &mut GrassRenderer, layout: &Layout, time: f32) {
    let mut solver = crate::sim::Solver::new(layout);
    let steps = (time / layout.sim.dt).round().max(0.0) as usize;
    for _ in 0..steps {
        solver.step();
    }
    grass.set_wind(
        &ctx.device,
        &ctx.queue,
        (solver.nx, solver.ny),
        solver.origin,
        [solver.hx, solver.hz],
        &solver.velocity_field(),
    );
}

/// A picture of `layout`'s grass in its wind after `time` seconds, seen by `camera` (the
/// [`Camera::overview`] when `None`): RGBA8 sRGB pixels, `size` wide and high. `windloom
/// render --view grass`.
pub fn picture(
    ctx: &crate::gpu::GpuContext,
    layout: &Layout,
    base: &std::path::Path,
    size: [u32; 2],
    time: f32,
    camera: Option<Camera>,
    paper_literal: bool,
) -> Result<Vec<u8>, GpuError> {
    let blades = crate::grass::scatter(layout);
    let mut grass = GrassRenderer::new(
        &ctx.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        layout,
        &blades,
    );
    grass.set_paper_literal(paper_literal);
    if let Some(map) = &layout.world.map {
        let path = base.join(&map.image);
        let img = image::open(&path)
            .map_err(|e| GpuError::Runtime {
                what: format!("reading the map backdrop {}", path.display()),
                message: e.to_string(),
            })?
            .to_rgba8();
        let size = [img.width(), img.height()];
        grass.set_backdrop(
            &ctx.device,
            &ctx.queue,
            Some((img.as_raw(), size, map.opacity)),
        );
    }
    grass.set_scene(
        &ctx.device,
        &crate::grass::scene::solids(layout),
        &crate::grass::scene::arrows(layout),
    );
    wind_at(ctx, &mut grass, layout, time);
    let camera = camera.unwrap_or_else(|| Camera::overview(layout));
    let (pixels, _) = render_offscreen(&ctx.device, &ctx.queue, &mut grass, &camera, time, size)?;
    Ok(pixels)
}

/// `windloom bench --grass N`: frame times drawing about `blades` blades of `layout` (its
/// density raised or lowered to give that many) at `size`, in its wind after 2 s.
#[derive(Debug, Clone, serde::Serialize)]
pub struct GrassBench {
    pub adapter: String,
    pub adapter_type: String,
    pub model: String,
    pub blades: u32,
    pub size: [u32; 2],
    pub frames: usize,
    pub median_ms: f64,
    pub min_ms: f64,
}

pub fn bench(
    ctx: &crate::gpu::GpuContext,
    layout: &Layout,
    blades: usize,
    size: [u32; 2],
    frames: usize,
) -> Result<GrassBench, GpuError> {
    let mut layout = layout.clone();
    let area = layout.world.size[0] * layout.world.size[1];
    layout.grass.density = (blades as f32 / area).max(1e-3);
    let placed = crate::grass::scatter(&layout);
    let mut grass = GrassRenderer::new(
        &ctx.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        &layout,
        &placed,
    );
    wind_at(ctx, &mut grass, &layout, 2.0);
    let camera = Camera::overview(&layout);
    // One untimed frame (pipelines, first use of the buffers), then the timed ones.
    render_offscreen(&ctx.device, &ctx.queue, &mut grass, &camera, 2.0, size)?;
    let mut times = Vec::with_capacity(frames);
    for k in 0..frames.max(1) {
        let (_, ms) = render_offscreen(
            &ctx.device,
            &ctx.queue,
            &mut grass,
            &camera,
            2.0 + k as f32 / 60.0,
            size,
        )?;
        times.push(ms);
    }
    times.sort_by(f64::total_cmp);
    Ok(GrassBench {
        adapter: ctx.adapter.name.clone(),
        adapter_type: format!("{:?}", ctx.adapter.device_type),
        model: "cwd".into(),
        blades: grass.blade_count(),
        size,
        frames: times.len(),
        median_ms: times[times.len() / 2],
        min_ms: times[0],
    })
}
