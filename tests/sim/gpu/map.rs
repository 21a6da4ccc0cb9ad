use super::{context, random_solver};
use windloom::doc::Boundary;
use windloom::engine::live::Snapshot;
use windloom::gpu::mapview::{Frame, Layer, MapRenderer, Overlay, Particle};
use windloom::gpu::{GpuContext, GpuSolver};
use windloom::sim::Solver;

fn snapshot(s: &Solver) -> Snapshot {
    Snapshot {
        nx: s.nx,
        ny: s.ny,
        origin: s.origin,
        size: [s.hx * s.nx as f32, s.hz * s.ny as f32],
        velocity: s.velocity_field(),
        pressure: s.p.clone(),
        ..Default::default()
    }
}

/// A frame that fits the world exactly into `w` pixels across at 1 pixel per point.
fn frame(s: &Solver, w: u32, layer: Layer, overlay: Overlay) -> (Frame, [u32; 2]) {
    let size = [s.hx * s.nx as f32, s.hz * s.ny as f32];
    let zoom = w as f32 / size[0];
    let h = (size[1] * zoom).round() as u32;
    let min = s.origin;
    let max = [min[0] + size[0], min[1] + size[1]];
    let f = Frame {
        layer,
        overlay,
        alpha: 1.0,
        center: [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0],
        zoom,
        ppp: 1.0,
        viewport_px: [w as f32, h as f32],
        world_min: min,
        world_max: max,
        dt: 0.0,
        streaks: 0,
        lattice_origin: min,
        lattice_step: 1.0,
        lattice: [0, 0],
        speed_scale: None,
    };
    (f, [w, h])
}

fn setup(seed: u64) -> Option<(GpuContext, Solver, GpuSolver)> {
    let ctx = context()?;
    let cpu = random_solver(Boundary::Closed, seed);
    let layout = {
        let mut l = super::example("obstacles.json");
        l.world.grid = [40, 28];
        l
    };
    let gpu = GpuSolver::from_solver(&ctx, &layout, &cpu).unwrap();
    Some((ctx, cpu, gpu))
}

/// The stats pass's peaks equal the CPU's: the colour scales need no read-back.
#[test]
fn the_stats_pass_finds_the_cpu_peaks() {
    let Some((ctx, cpu, gpu)) = setup(11) else {
        return;
    };
    let (device, queue) = (&ctx.device, &ctx.queue);
    let mut r = MapRenderer::new(device, wgpu::TextureFormat::Rgba8Unorm);
    let (f, _) = frame(&cpu, 80, Layer::Speed, Overlay::None);
    let mut enc = device.create_command_encoder(&Default::default());
    r.prepare(device, queue, &mut enc, &gpu.field(), &f);
    queue.submit([enc.finish()]);
    let [speed, curl, pressure] = r.read_stats(device, queue).unwrap();
    let snap = snapshot(&cpu);
    let cpu_speed = snap
        .velocity
        .iter()
        .fold(0.0f32, |m, v| m.max(v[0].hypot(v[1])));
    let cpu_pressure = cpu.p.iter().fold(0.0f32, |m, p| m.max(p.abs()));
    // The curl the view shows: central differences of cell-centred velocities.
    let (nx, ny) = (cpu.nx, cpu.ny);
    let at = |i: usize, j: usize| snap.velocity[j * nx + i];
    let mut cpu_curl = 0.0f32;
    for j in 0..ny {
        for i in 0..nx {
            let (il, ir) = (i.saturating_sub(1), (i + 1).min(nx - 1));
            let (jb, jt) = (j.saturating_sub(1), (j + 1).min(ny - 1));
            let dvdx = (at(ir, j)[1] - at(il, j)[1]) / ((ir - il) as f32 * cpu.hx);
            let dudz = (at(i, jt)[0] - at(i, jb)[0]) / ((jt - jb) as f32 * cpu.hz);
            cpu_curl = cpu_curl.max((dvdx - dudz).abs());
        }
    }
    for (what, g, c) in [
        ("speed", speed, cpu_speed),
        ("curl", curl, cpu_curl),
        ("pressure", pressure, cpu_pressure),
    ] {
        println!("peak {what}: GPU {g}, CPU {c}");
        assert!(c > 0.0);
        assert!((g - c).abs() <= 1e-5 * c, "peak {what}: GPU {g}, CPU {c}");
    }
}

/// One frame of streak advection on the GPU moves each particle's head by the
/// velocity the CPU view samples there, keeps the trail, and rebirths dead particles
/// inside the world.
#[test]
fn streaks_advect_as_the_cpu_view_does() {
    let Some((ctx, cpu, gpu)) = setup(12) else {
        return;
    };
    let (device, queue) = (&ctx.device, &ctx.queue);
    let snap = snapshot(&cpu);
    let (mut f, _) = frame(&cpu, 80, Layer::Speed, Overlay::Streaks);
    f.dt = 0.05;
    let size = snap.size;
    let mut particles = Vec::new();
    for k in 0..64u32 {
        let len = if k % 2 == 0 { 5 } else { 14 };
        let mut q = Particle {
            trail: [[0.0; 2]; 16],
            age: 1.0,
            life: if k == 7 { 1.01 } else { 3.0 },
            len,
            seed: k,
        };
        for n in 0..len as usize {
            let t = (k as f32 * 0.37 + n as f32 * 0.01).fract();
            q.trail[n] = [
                snap.origin[0] + size[0] * (0.2 + 0.6 * t),
                snap.origin[1] + size[1] * (0.2 + 0.6 * (k as f32 / 64.0)),
            ];
        }
        particles.push(q);
    }
    f.streaks = particles.len() as u32;
    let mut r = MapRenderer::new(device, wgpu::TextureFormat::Rgba8Unorm);
    r.write_particles(device, queue, &particles);
    let mut enc = device.create_command_encoder(&Default::default());
    r.prepare(device, queue, &mut enc, &gpu.field(), &f);
    queue.submit([enc.finish()]);
    let after = r.read_particles(device, queue).unwrap();
    let mut worst = 0.0f32;
    let mut reborn = 0;
    for (k, (a, b)) in particles.iter().zip(&after).enumerate() {
        let head = a.trail[a.len as usize - 1];
        let v = snap.sample(head);
        let want = [head[0] + v[0] * f.dt, head[1] + v[1] * f.dt];
        // The CPU view's rule: too old, out of the world, or stuck in calm air (inside
        // an obstacle).
        let out = want[0] < snap.origin[0]
            || want[1] < snap.origin[1]
            || want[0] > snap.origin[0] + size[0]
            || want[1] > snap.origin[1] + size[1];
        let dies = a.age + f.dt > a.life || out || (v == [0.0, 0.0] && a.age + f.dt > 0.5);
        assert_eq!(dies, k == 7 || v == [0.0, 0.0], "particle {k}");
        if dies {
            // Born again: one point, inside the world.
            assert_eq!(b.len, 1, "particle {k}: a dead streak is reborn");
            let p = b.trail[0];
            assert!(p[0] >= snap.origin[0] && p[0] <= snap.origin[0] + size[0]);
            assert!(p[1] >= snap.origin[1] && p[1] <= snap.origin[1] + size[1]);
            reborn += 1;
            continue;
        }
        let (got, kept) = if a.len < 14 {
            assert_eq!(b.len, a.len + 1);
            (
                b.trail[a.len as usize],
                b.trail[..a.len as usize] == a.trail[..a.len as usize],
            )
        } else {
            assert_eq!(b.len, 14);
            (b.trail[13], b.trail[..13] == a.trail[1..14])
        };
        assert!(
            kept,
            "particle {k}: the trail keeps its older points in order"
        );
        worst = worst.max((got[0] - want[0]).abs().max((got[1] - want[1]).abs()));
        assert!((b.age - (a.age + f.dt)).abs() < 1e-6);
    }
    println!("streak heads: max |GPU − CPU| {worst:.2e} m; {reborn} reborn");
    assert!(reborn < 16, "most test particles live on");
    assert!(
        worst <= 1e-4,
        "streak heads differ from the CPU view by {worst} m"
    );
}

/// Renders the map view's colour map offscreen; returns RGBA pixels and the size.
fn render(ctx: &GpuContext, gpu: &GpuSolver, f: &Frame, [w, h]: [u32; 2]) -> Vec<u8> {
    let (device, queue) = (&ctx.device, &ctx.queue);
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let mut r = MapRenderer::new(device, format);
    let target = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("map test target"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = target.create_view(&Default::default());
    let mut enc = device.create_command_encoder(&Default::default());
    r.prepare(device, queue, &mut enc, &gpu.field(), f);
    {
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("map test"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        r.paint(&mut pass);
    }
    queue.submit([enc.finish()]);
    windloom::gpu::read_texture(device, queue, &target, 4).unwrap()
}

/// Every pixel of the GPU colour map (speed on the field's peak and on a fixed scale, and
/// pressure) is the colour the CPU view gives the field sampled at that pixel's centre,
/// within the colour table's quantisation (4/255 a channel).
#[test]
fn the_colour_map_matches_the_cpu_view_pixel_by_pixel() {
    let Some((ctx, cpu, gpu)) = setup(13) else {
        return;
    };
    let snap = snapshot(&cpu);
    let peak = snap
        .velocity
        .iter()
        .fold(1.0f32, |m, v| m.max(v[0].hypot(v[1])));
    // Speed on the field's peak, then on a fixed scale of twice it (the View menu's).
    for (layer, fixed) in [
        (Layer::Speed, None),
        (Layer::Speed, Some(2.0 * peak)),
        (Layer::Pressure, None),
    ] {
        let (mut f, [w, h]) = frame(&cpu, 160, layer, Overlay::None);
        f.speed_scale = fixed;
        let pixels = render(&ctx, &gpu, &f, [w, h]);
        let speed_scale = fixed.unwrap_or(peak);
        let p_scale = cpu.p.iter().fold(1e-6f32, |m, p| m.max(p.abs()));
        let mut worst = 0u8;
        for y in 0..h {
            for x in 0..w {
                let world = [
                    f.world_min[0] + (x as f32 + 0.5) / f.zoom,
                    f.world_min[1] + (y as f32 + 0.5) / f.zoom,
                ];
                let want = match layer {
                    Layer::Speed => {
                        let v = snap.sample(world);
                        windloom::colour::speed_rgb(v[0].hypot(v[1]) / speed_scale)
                    }
                    _ => windloom::colour::signed_rgb(pressure_at(&snap, &cpu.p, world) / p_scale),
                };
                let got = &pixels[((y * w + x) * 4) as usize..][..4];
                assert_eq!(got[3], 255, "the colour map is opaque at alpha 1");
                for c in 0..3 {
                    worst = worst.max(got[c].abs_diff(want[c]));
                }
            }
        }
        println!("{layer:?} ({fixed:?}): max channel difference {worst}/255 over {w}x{h} pixels");
        assert!(
            worst <= 4,
            "{layer:?}: GPU pixels differ from the CPU view by {worst}/255"
        );
    }
}

/// Pressure bilinear between cell centres (as `Snapshot::sample` does velocity).
fn pressure_at(snap: &Snapshot, p: &[f32], w: [f32; 2]) -> f32 {
    let (nx, ny) = (snap.nx, snap.ny);
    let x = ((w[0] - snap.origin[0]) / snap.size[0] * nx as f32 - 0.5).clamp(0.0, (nx - 1) as f32);
    let z = ((w[1] - snap.origin[1]) / snap.size[1] * ny as f32 - 0.5).clamp(0.0, (ny - 1) as f32);
    let (i0, j0) = (x as usize, z as usize);
    let (i1, j1) = ((i0 + 1).min(nx - 1), (j0 + 1).min(ny - 1));
    let (fx, fz) = (x - i0 as f32, z - j0 as f32);
    let at = |i: usize, j: usize| p[j * nx + i];
    let a = at(i0, j0) + (at(i1, j0) - at(i0, j0)) * fx;
    let b = at(i0, j1) + (at(i1, j1) - at(i0, j1)) * fx;
    a + (b - a) * fz
}
