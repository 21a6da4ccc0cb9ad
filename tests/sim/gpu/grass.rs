use super::{context, example};
use windloom::doc::Layout;
use windloom::gpu::GpuContext;
use windloom::gpu::grass::{Camera, GrassRenderer, SEGMENTS, render_offscreen};
use windloom::grass::{cwd, scatter, wind_cell};

/// The layout's map backdrop from `base`, decoded as `render` decodes it (none when it has
/// none or it cannot be read).
fn backdrop(l: &Layout, base: &std::path::Path) -> Option<image::RgbaImage> {
    windloom::io::layout_backdrop(l, base).and_then(Result::ok)
}

fn layout(density: f32) -> Layout {
    let mut l = example("meadow.json");
    l.world.size = [12.0, 8.0];
    l.world.grid = [24, 16];
    l.grass.density = density;
    l
}

/// A wind grid of random directions and speeds up to 40 m/s.
fn random_wind(n: usize, seed: u64) -> Vec<[f32; 2]> {
    let a = super::noise(n, seed, std::f32::consts::PI);
    let s = super::noise(n, seed + 1, 20.0);
    a.iter()
        .zip(&s)
        .map(|(a, s)| [(s + 20.0) * a.cos(), (s + 20.0) * a.sin()])
        .collect()
}

/// Each blade's deformed tip as the vertex shader places it matches the CPU model's,
/// in random winds up to 40 m/s, at several times (the flutter's clock), and with a
/// sphere's trail crushing part of the field (`cwd::centreline_crushed` fed by the CPU
/// trail).
#[test]
fn gpu_blade_tips_match_the_cpu_model() {
    use windloom::grass::trail::{Sphere, Trail};
    let Some(ctx) = context() else { return };
    let l = layout(30.0);
    let blades = scatter(&l);
    assert!(blades.len() > 2000);
    let (nx, ny) = (24, 16);
    let cell = [0.5, 0.5];
    let mut r = GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
    let (min, max) = l.bounds();
    let mut trail = Trail::new(min, max);
    let camera = Camera::overview(&l);
    let mut worst = (0.0f32, 0.0f32);
    let mut crushed = 0;
    for (k, time) in [0.0f32, 1.7, 12.25].into_iter().enumerate() {
        let wind = random_wind(nx * ny, 40 + k as u64);
        r.set_wind(&ctx.device, &ctx.queue, (nx, ny), [0.0, 0.0], cell, &wind);
        // The last time: a sphere has crossed the field.
        let sphere = (k == 2).then_some(Sphere {
            centre: [6.0, 0.4, 4.0],
            radius: 1.5,
        });
        r.set_sphere(sphere);
        trail.step(sphere, 0.25, windloom::gpu::grass::TRAIL_LIFETIME);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        r.prepare(&ctx.queue, &mut enc, &camera, 1.5, time, 0.25);
        ctx.queue.submit([enc.finish()]);
        let tips = r.read_tips(&ctx.device, &ctx.queue).unwrap();
        for (b, gpu) in blades.iter().zip(&tips) {
            let w = wind[wind_cell(b.pos, [0.0, 0.0], cell, (nx, ny))];
            let crush = if sphere.is_some() {
                trail.crush_at(b.pos, cwd::frame(b).0)
            } else {
                (0.0, [0.0, 0.0])
            };
            crushed += usize::from(crush.0 > 0.5);
            let cpu = cwd::centreline_crushed(b, w, &l.grass, time, SEGMENTS as usize, crush)
                [SEGMENTS as usize];
            let d = (0..3).fold(0.0f32, |m, c| m.max((gpu[c] - cpu.pos[c]).abs()));
            worst.0 = worst.0.max(d / b.height);
            worst.1 = worst.1.max((gpu[3] - cpu.shade).abs());
        }
    }
    println!(
        "grass tips: max |GPU − CPU| {:.2e} of the blade height, shade {:.2e}; {crushed} blades crushed",
        worst.0, worst.1
    );
    assert!(crushed > 100, "the sphere crushed part of the field");
    assert!(
        worst.0 <= 1e-3,
        "tips differ by {} of a blade's height",
        worst.0
    );
    assert!(worst.1 <= 1e-3, "shades differ by {}", worst.1);
}

/// The Bezier physics pass against its CPU twin (`grass::bezier`): random blades in
/// random winds up to 40 m/s, 40 frames at 60 fps while a sphere rolls across the
/// field leaving its trail (the CPU twin steps `grass::trail` alongside): control
/// points within 1e-3 m; the blades the sphere passed lean away from its path.
#[test]
fn gpu_bezier_blades_match_the_cpu_model() {
    use windloom::grass::bezier::{Push, State};
    use windloom::grass::trail::{Sphere, Trail};
    let Some(ctx) = context() else { return };
    let l = layout(8.0);
    let blades = scatter(&l);
    let (nx, ny) = (24, 16);
    let cell = [0.5, 0.5];
    let wind = random_wind(nx * ny, 77);
    let mut r = GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
    r.set_wind(&ctx.device, &ctx.queue, (nx, ny), [0.0, 0.0], cell, &wind);
    r.set_model(
        &ctx.device,
        &ctx.queue,
        windloom::doc::GrassModel::BezierPhysics,
    );
    let (min, max) = l.bounds();
    let mut trail = Trail::new(min, max);
    let lifetime = 2.0;
    r.set_trail_lifetime(lifetime);
    let camera = Camera::overview(&l);
    let frames = 40;
    let dt = 1.0 / 60.0;
    let sphere_at = |f: usize| Sphere {
        centre: [2.0 + 0.2 * f as f32, 0.3, 4.0],
        radius: 0.6,
    };
    let mut cpu: Vec<State> = blades.iter().map(State::rest).collect();
    for f in 0..frames {
        let sphere = Some(sphere_at(f));
        r.set_sphere(sphere);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        r.prepare(&ctx.queue, &mut enc, &camera, 1.5, 0.0, dt);
        ctx.queue.submit([enc.finish()]);
        trail.step(sphere, dt, lifetime);
        for (b, s) in blades.iter().zip(&mut cpu) {
            let w = wind[wind_cell(b.pos, [0.0, 0.0], cell, (nx, ny))];
            let (c, dir) = trail.crush_at(b.pos, cwd::frame(b).0);
            let push = Push {
                sphere,
                crush: c,
                dir,
            };
            s.advance_pushed(b, w, push, dt);
        }
    }
    let gpu = r.read_bezier(&ctx.device, &ctx.queue).unwrap().unwrap();
    let mut worst = 0.0f32;
    let (mut moved, mut away, mut near) = (0, 0, 0);
    for ((b, g), s) in blades.iter().zip(&gpu).zip(&cpu) {
        for c in 0..3 {
            worst = worst
                .max((g.v1[c] - s.v1[c]).abs())
                .max((g.v2[c] - s.v2[c]).abs());
        }
        let mut calm = State::rest(b);
        let w = wind[wind_cell(b.pos, [0.0, 0.0], cell, (nx, ny))];
        for _ in 0..frames {
            calm.advance(b, w, dt);
        }
        if (0..3).any(|c| (s.v2[c] - State::rest(b).v2[c]).abs() > 0.01) {
            moved += 1;
        }
        // Blades within the swept band, beside the path's middle line, lean out of it.
        let off = b.pos[1] - 4.0;
        if (3.5..=8.0).contains(&b.pos[0]) && (0.15..0.45).contains(&off.abs()) {
            near += 1;
            if (s.v2[2] - b.pos[1]) * off.signum() > (calm.v2[2] - b.pos[1]) * off.signum() {
                away += 1;
            }
        }
    }
    println!(
        "bezier: max |GPU − CPU| {worst:.2e} m over {} blades ({moved} moved; {away} of {near} beside the path lean away from it)",
        blades.len()
    );
    assert!(moved > blades.len() / 2, "the wind moved the blades");
    assert!(
        near > 10 && away * 10 >= near * 8,
        "blades lean out of the sphere's path"
    );
    assert!(
        worst <= 1e-3,
        "the GPU's blades differ from the CPU's by {worst} m"
    );
}

/// The trail pass against `grass::trail::Trail`: a sphere dragged across the world,
/// then left to fade — every texel within 1e-5 each time, and nothing left after the
/// lifetime (whatever the frame rate).
#[test]
fn the_trail_matches_the_cpu_and_fades_in_its_lifetime() {
    use windloom::grass::trail::{Sphere, Trail};
    let Some(ctx) = context() else { return };
    let l = layout(1.0);
    let blades = scatter(&l);
    let mut r = GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
    let (min, max) = l.bounds();
    let mut cpu = Trail::new(min, max);
    let lifetime = 1.5;
    r.set_trail_lifetime(lifetime);
    let camera = Camera::overview(&l);
    let mut worst = 0.0f32;
    let mut frame = |r: &mut GrassRenderer, sphere: Option<Sphere>, dt: f32| {
        r.set_sphere(sphere);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        r.prepare(&ctx.queue, &mut enc, &camera, 1.5, 0.0, dt);
        ctx.queue.submit([enc.finish()]);
        cpu.step(sphere, dt, lifetime);
        let gpu = r.read_trail(&ctx.device, &ctx.queue).unwrap();
        assert_eq!(gpu.len(), cpu.life.len());
        for (g, c) in gpu.iter().zip(&cpu.life) {
            worst = worst.max((g - c).abs());
        }
        gpu
    };
    for f in 0..20 {
        let s = Sphere {
            centre: [1.0 + 0.5 * f as f32, 0.5, 2.0 + 0.2 * f as f32],
            radius: 1.0,
        };
        frame(&mut r, Some(s), 1.0 / 30.0);
    }
    let trodden = frame(&mut r, None, 1.0 / 144.0);
    let marked = trodden.iter().filter(|&&v| v > 0.5).count();
    // Fade at 144 fps for the rest of the lifetime.
    let mut last = trodden;
    for _ in 0..(lifetime * 144.0) as usize {
        last = frame(&mut r, None, 1.0 / 144.0);
    }
    println!(
        "trail: {marked} texels trodden, max |GPU − CPU| {worst:.1e}, max left after the lifetime {}",
        last.iter().cloned().fold(0.0f32, f32::max)
    );
    assert!(marked > 100, "the sphere left a trail");
    assert!(worst <= 1e-5, "the GPU's trail differs by {worst}");
    assert!(
        last.iter().all(|&v| v == 0.0),
        "the trail is gone after its lifetime"
    );
}

/// The cull pass against `grass::cull::classify` for random cameras over a field of
/// blades in the wind, for both models, frame after frame (the LOD hysteresis carries
/// state): every blade the CPU decides with a margin is decided the same on the GPU,
/// and the indirect draw counts equal the CPU's counts.
#[test]
fn culling_on_the_gpu_matches_the_cpu_for_random_cameras() {
    use windloom::grass::bezier::State;
    use windloom::grass::cull::{self, CullParams, NO_LEVEL, Verdict};
    let Some(ctx) = context() else { return };
    let mut l = layout(30.0);
    l.world.size = [40.0, 30.0];
    l.world.grid = [20, 15];
    let blades = scatter(&l);
    let (nx, ny) = (20, 15);
    let cell = [2.0, 2.0];
    let wind = random_wind(nx * ny, 5);
    let mut params = CullParams::for_height(0.5);
    // Distances that fall inside a 40 m field.
    params.lod_near = 4.0;
    params.lod_far = 12.0;
    params.max_distance = 45.0;
    // And the density thinning past 10 m (the field is 20/m², so it thins within view).
    params.thin_distance = 10.0;
    let mut rng = 12345u64;
    let mut next = || {
        rng = rng
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (rng >> 40) as f32 / (1u64 << 24) as f32
    };
    for model in [
        windloom::doc::GrassModel::CwdQuadratic,
        windloom::doc::GrassModel::BezierPhysics,
    ] {
        let mut r = GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
        r.set_wind(&ctx.device, &ctx.queue, (nx, ny), [0.0, 0.0], cell, &wind);
        r.set_model(&ctx.device, &ctx.queue, model);
        r.set_cull(params);
        let mut prev = vec![NO_LEVEL; blades.len()];
        let mut states: Vec<State> = blades.iter().map(State::rest).collect();
        let (mut ambiguous, mut compared) = (0usize, 0usize);
        let mut eye = glam::Vec3::new(20.0, 3.0, 35.0);
        for frame in 0..8 {
            // A random camera, then a small move (the hysteresis's case).
            if frame % 2 == 0 {
                eye = glam::Vec3::new(next() * 40.0, 0.5 + next() * 12.0, next() * 30.0);
            } else {
                eye += glam::Vec3::new(0.3, 0.05, -0.2);
            }
            let target = glam::Vec3::new(next() * 40.0, 0.0, next() * 30.0);
            let camera = Camera {
                eye,
                target,
                fov_y: (30.0 + next() * 40.0f32).to_radians(),
            };
            let aspect = 1.2 + next();
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            r.prepare(&ctx.queue, &mut enc, &camera, aspect, 0.5, 1.0 / 60.0);
            ctx.queue.submit([enc.finish()]);
            let (stats, lists) = r.read_cull(&ctx.device, &ctx.queue).unwrap();
            // The far level is drawn as one triangle list: one triangle for each blade kept.
            assert_eq!(
                r.read_far_draw(&ctx.device, &ctx.queue).unwrap(),
                [3 * stats.drawn[2], 1, 0, 0],
                "the far draw covers the far level's blades"
            );
            let mut gpu = vec![None; blades.len()];
            for (lvl, list) in lists.iter().enumerate() {
                for &k in list {
                    assert!(gpu[k as usize].is_none(), "blade {k} listed twice");
                    gpu[k as usize] = Some(lvl as u32);
                }
            }
            let vp = camera.view_proj(aspect);
            let mut counts = [0u32; 6];
            let mut frame_ambiguous = 0;
            for (k, b) in blades.iter().enumerate() {
                let w = wind[wind_cell(b.pos, [0.0, 0.0], cell, (nx, ny))];
                let pts = match model {
                    windloom::doc::GrassModel::CwdQuadratic => {
                        let c = cwd::centreline(b, w, &l.grass, 0.5, 2);
                        [c[0].pos, c[1].pos, c[2].pos]
                    }
                    windloom::doc::GrassModel::BezierPhysics => {
                        states[k].advance(b, w, 1.0 / 60.0);
                        let s = &states[k];
                        [s.point(0.0), s.point(0.5), s.point(1.0)]
                    }
                };
                let (v, margin) = cull::classify(
                    k as u32,
                    cull::side(b),
                    pts,
                    eye.to_array(),
                    &vp,
                    prev[k],
                    &params,
                );
                counts[match v {
                    Verdict::Level(l) => l as usize,
                    Verdict::Orientation => 3,
                    Verdict::Frustum => 4,
                    Verdict::Distance => 5,
                }] += 1;
                let cpu_level = match v {
                    Verdict::Level(l) => Some(l),
                    _ => None,
                };
                if margin < 1e-4 {
                    frame_ambiguous += 1;
                    // Follow the GPU where f32 rounding could go either way.
                    if let Some(g) = gpu[k] {
                        prev[k] = g;
                    }
                    continue;
                }
                compared += 1;
                assert_eq!(
                    gpu[k], cpu_level,
                    "{model:?} frame {frame}: blade {k} ({v:?}, margin {margin})"
                );
                if let Some(l) = cpu_level {
                    prev[k] = l;
                }
            }
            ambiguous += frame_ambiguous;
            let drawn = [counts[0], counts[1], counts[2]];
            let culled = [counts[3], counts[4], counts[5]];
            let gpu_culled = [stats.orientation, stats.frustum, stats.distance];
            if frame_ambiguous == 0 {
                assert_eq!(stats.drawn, drawn, "{model:?}: indirect counts");
                assert_eq!(gpu_culled, culled, "{model:?}: cull counters");
            } else {
                for (g, c) in stats.drawn.iter().zip(&drawn) {
                    assert!(g.abs_diff(*c) as usize <= frame_ambiguous);
                }
            }
            assert_eq!(stats.total as usize, blades.len());
        }
        println!(
            "{model:?}: {compared} decisions equal, {ambiguous} within 1e-4 of a threshold set aside"
        );
        assert!(ambiguous * 1000 <= compared, "too many borderline blades");
    }
}
/// With the GPU running the field, the grass's wind grid is made on the GPU from the
/// solver's faces: it equals the CPU's cell-centred velocity exactly.
#[test]
fn the_wind_grid_from_a_gpu_field_equals_the_cpu_cells() {
    let Some(ctx) = context() else { return };
    let cpu = super::random_solver(windloom::doc::Boundary::Open, 21);
    let mut fluid = example("obstacles.json");
    fluid.world.grid = [40, 28];
    let gpu = windloom::gpu::GpuSolver::from_solver(&ctx, &fluid, &cpu).unwrap();
    let l = layout(5.0);
    let mut r = GrassRenderer::new(
        &ctx.device,
        wgpu::TextureFormat::Rgba8Unorm,
        &l,
        &scatter(&l),
    );
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    r.wind_from_field(&ctx.device, &ctx.queue, &mut enc, &gpu.field());
    ctx.queue.submit([enc.finish()]);
    let wind = r.read_wind(&ctx.device, &ctx.queue).unwrap();
    let want = cpu.velocity_field();
    assert!(want.iter().any(|v| v[0] != 0.0), "a field to compare");
    assert_eq!(wind, want, "the GPU's cells are the CPU's, bit for bit");
}

/// What the editor's 3D view shows (the target's encoded texture, which egui reads as
/// plain RGBA8) is the frame's sRGB bytes, on an adapter that can view a texture in
/// another format and, through a copy, on one that cannot (a GL adapter; on Vulkan the
/// copy is forced): the same bytes both ways, and a real picture (sky above, grass
/// below).
#[test]
fn the_editor_s_view_of_the_grass_is_the_frame_with_or_without_format_views() {
    use windloom::gpu::grass::Target;
    let Some(ctx) = context() else { return };
    let l = layout(4.0);
    let mut r = GrassRenderer::new(
        &ctx.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        &l,
        &scatter(&l),
    );
    let camera = Camera {
        eye: glam::Vec3::new(2.0, 1.4, 7.5),
        target: glam::Vec3::new(6.0, 0.2, 4.0),
        fov_y: 45f32.to_radians(),
    };
    let (w, h) = (96u32, 64u32);
    let mut shown = Vec::new();
    // Both ways where the adapter has format views; on one without (GL), the copy.
    let has_views = ctx.downlevel.contains(wgpu::DownlevelFlags::VIEW_FORMATS);
    for views in [true, false].into_iter().filter(|&v| has_views || !v) {
        let mut downlevel = ctx.downlevel;
        downlevel.set(wgpu::DownlevelFlags::VIEW_FORMATS, views);
        let target = Target::new(&ctx.device, [w, h], downlevel);
        windloom::gpu::grass::render_into(
            &ctx.device,
            &ctx.queue,
            &mut r,
            &camera,
            (0.0, 0.0),
            &target,
            windloom::gpu::grass::FramePart::Whole,
        )
        .unwrap();
        let frame =
            windloom::gpu::read_texture(&ctx.device, &ctx.queue, &target.texture, 4).unwrap();
        let encoded =
            windloom::gpu::read_texture(&ctx.device, &ctx.queue, target.encoded_texture(), 4)
                .unwrap();
        assert_eq!(
            frame.len(),
            (w * h * 4) as usize,
            "format views {views}: a whole frame"
        );
        assert!(
            frame == encoded,
            "format views {views}: the view shows the frame's bytes"
        );
        shown.push(encoded);
    }
    assert!(ctx.fault().is_none(), "{:?}", ctx.fault());
    assert!(
        shown.iter().all(|s| *s == shown[0]),
        "both ways show the same picture"
    );
    let px = |x: u32, y: u32| &shown[0][((y * w + x) * 4) as usize..][..3];
    let (sky, ground) = (px(w / 2, 1), px(w / 2, h - 2));
    assert!(sky[2] > sky[0] && sky[2] > 150, "sky at the top: {sky:?}");
    assert!(ground != sky, "something under the sky: {ground:?}");
}

/// A device that has reported an error no scope caught cannot be trusted to have drawn
/// anything: `render --view grass` then fails with the device's message instead of
/// writing whatever the texture held.
#[test]
fn a_grass_picture_from_a_faulted_device_is_an_error() {
    let Some(ctx) = context() else { return };
    let l = layout(4.0);
    let options = windloom::gpu::grass::PictureOptions {
        size: [64, 48],
        time: 0.0,
        ..Default::default()
    };
    let dir = tempfile::tempdir().unwrap();
    assert!(
        windloom::gpu::grass::picture(&ctx, &l, backdrop(&l, dir.path()).as_ref(), &options)
            .is_ok()
    );
    // An invalid buffer (mapped both ways), outside any error scope.
    let _ = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("invalid on purpose"),
        size: 16,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::MAP_WRITE,
        mapped_at_creation: false,
    });
    let Err(err) =
        windloom::gpu::grass::picture(&ctx, &l, backdrop(&l, dir.path()).as_ref(), &options)
    else {
        panic!("a faulted device drew a picture");
    };
    let text = err.to_string();
    assert!(
        text.contains("drawing the grass") && text.contains("invalid on purpose"),
        "the error says what failed and why: {text}"
    );
}

/// A layout's map backdrop colours the ground under the grass (`render --view grass`).
#[test]
fn the_ground_shows_the_map_backdrop() {
    let Some(ctx) = context() else { return };
    let dir = tempfile::tempdir().unwrap();
    // Left half red, right half blue.
    let img = image::RgbaImage::from_fn(64, 64, |x, _| {
        if x < 32 {
            image::Rgba([230, 20, 20, 255])
        } else {
            image::Rgba([20, 20, 230, 255])
        }
    });
    img.save(dir.path().join("level.png")).unwrap();
    let mut l = layout(0.01);
    l.world.size = [10.0, 10.0];
    l.world.map = Some(windloom::doc::MapBackdrop {
        image: "level.png".into(),
        opacity: 1.0,
        rect: None,
    });
    let camera = Camera {
        eye: glam::Vec3::new(5.0, 14.0, 9.0),
        target: glam::Vec3::new(5.0, 0.0, 5.0),
        fov_y: 45f32.to_radians(),
    };
    let (w, h) = (160u32, 120u32);
    let options = windloom::gpu::grass::PictureOptions {
        size: [w, h],
        time: 0.0,
        camera: Some(camera),
        ..Default::default()
    };
    let px = windloom::gpu::grass::picture(&ctx, &l, backdrop(&l, dir.path()).as_ref(), &options)
        .unwrap();
    let at = |x: u32, y: u32| &px[((y * w + x) * 4) as usize..][..3];
    let (left, right) = (at(w / 4, h / 2), at(3 * w / 4, h / 2));
    println!("ground left {left:?}, right {right:?}");
    assert!(
        left[0] > 120 && left[2] < 60,
        "the red half shows on the left: {left:?}"
    );
    assert!(
        right[2] > 120 && right[0] < 60,
        "the blue half on the right: {right:?}"
    );
    // Placed over the east half only (`world.map.rect`): the red half of the picture now
    // lands right of the middle, and the west is the field's own ground.
    l.world.map.as_mut().unwrap().rect = Some([[5.0, 0.0], [10.0, 10.0]]);
    let px = windloom::gpu::grass::picture(&ctx, &l, backdrop(&l, dir.path()).as_ref(), &options)
        .unwrap();
    let at = |x: u32, y: u32| px[((y * w + x) * 4) as usize..][..3].to_vec();
    let (west, east_red, east_blue) = (
        at(w / 4, h / 2),
        at(w / 2 + w / 12, h / 2),
        at(w / 2 + w / 4 + w / 32, h / 2),
    );
    // The field's own ground (its lower canopy over the soil): greenish, neither map colour.
    let plain = |p: &[u8]| p[0] < 120 && p[2] < 90 && p[1] >= p[0] && p[1] >= p[2];
    assert!(plain(&west), "the field's ground in the west: {west:?}");
    assert!(
        east_red[0] > 120 && east_red[2] < 60,
        "red east of the middle: {east_red:?}"
    );
    assert!(
        east_blue[2] > 120 && east_blue[0] < 60,
        "blue at the east edge: {east_blue:?}"
    );
    l.world.map.as_mut().unwrap().rect = None;
    // Without the backdrop (the same picture otherwise), the field's own ground.
    l.world.map = None;
    let px = windloom::gpu::grass::picture(&ctx, &l, backdrop(&l, dir.path()).as_ref(), &options)
        .unwrap();
    let soil = &px[(((h / 2) * w + w / 4) * 4) as usize..][..3];
    assert!(plain(soil), "plain ground is the field's: {soil:?}");
}

/// A renderer of `l`'s blades (on [`layout`]'s 24 × 16 wind grid) for sRGB pictures, in a
/// wind `wind` (m/s) the same everywhere.
fn steady_renderer(ctx: &GpuContext, l: &Layout, wind: [f32; 2]) -> (GrassRenderer, usize) {
    let blades = scatter(l);
    let mut r = GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8UnormSrgb, l, &blades);
    let cells = vec![wind; 24 * 16];
    r.set_wind(
        &ctx.device,
        &ctx.queue,
        (24, 16),
        [0.0, 0.0],
        [0.5, 0.5],
        &cells,
    );
    (r, blades.len())
}

fn picture(ctx: &GpuContext, speed: f32, model: windloom::doc::GrassModel) -> Vec<u8> {
    let (mut r, _) = steady_renderer(ctx, &layout(40.0), [speed * 0.8, speed * -0.6]);
    r.set_model(&ctx.device, &ctx.queue, model);
    let camera = Camera {
        eye: glam::Vec3::new(2.0, 1.4, 7.5),
        target: glam::Vec3::new(6.0, 0.2, 4.0),
        fov_y: 45f32.to_radians(),
    };
    // Two seconds for the Bezier blades to answer the wind.
    windloom::gpu::grass::settle(ctx, &mut r, &camera, 0.0, 2.0);
    render_offscreen(ctx, &mut r, &camera, (0.0, 1.0 / 60.0), [320, 180])
        .unwrap()
        .0
}

fn luminance(p: &[u8]) -> f64 {
    p.chunks(4)
        .map(|c| 0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2]))
        .sum::<f64>()
        / (p.len() / 4) as f64
}

/// Calm, breezy and gale pictures of the CWD model, and calm and gale pictures of the
/// Bezier blades, against committed references (mean channel difference ≤ 1.5/255,
/// and under 1% of pixels off by more than 24/255); a gale is visibly different from
/// calm but darkens the picture by less than 12%.
#[test]
fn grass_pictures_match_their_references_and_a_gale_stays_lit() {
    use windloom::doc::GrassModel::{BezierPhysics, CwdQuadratic};
    let Some(ctx) = context() else { return };
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots");
    let mut pictures = Vec::new();
    for (name, speed, model) in [
        ("calm", 0.0, CwdQuadratic),
        ("breezy", 4.0, CwdQuadratic),
        ("gale", 30.0, CwdQuadratic),
        ("bezier_calm", 0.0, BezierPhysics),
        ("bezier_gale", 30.0, BezierPhysics),
    ] {
        let pixels = picture(&ctx, speed, model);
        let path = dir.join(format!("grass_{name}.png"));
        if std::env::var_os("UPDATE_SNAPSHOTS").is_some() {
            image::RgbaImage::from_raw(320, 180, pixels.clone())
                .unwrap()
                .save(&path)
                .unwrap();
        }
        let reference = image::open(&path)
            .unwrap_or_else(|e| panic!("{}: {e} (UPDATE_SNAPSHOTS=1 writes it)", path.display()))
            .to_rgba8();
        let diffs: Vec<u8> = pixels
            .iter()
            .zip(reference.as_raw())
            .map(|(a, b)| a.abs_diff(*b))
            .collect();
        let mean = diffs.iter().map(|&d| f64::from(d)).sum::<f64>() / diffs.len() as f64;
        let off = diffs
            .chunks(4)
            .filter(|c| c.iter().any(|&d| d > 24))
            .count();
        println!("grass_{name}: mean difference {mean:.3}, {off} pixels off");
        assert!(
            mean <= 1.5,
            "grass_{name}: mean difference {mean} from the reference"
        );
        assert!(
            off * 100 <= 320 * 180,
            "grass_{name}: {off} pixels differ from the reference"
        );
        pictures.push(pixels);
    }
    let (calm, gale) = (luminance(&pictures[0]), luminance(&pictures[2]));
    println!(
        "mean luminance: calm {calm:.1}, breezy {:.1}, gale {gale:.1}",
        luminance(&pictures[1])
    );
    assert!(
        gale >= calm * 0.88,
        "a gale darkens the grass too much: {gale} against {calm}"
    );
    for (calm, gale) in [(0, 2), (3, 4)] {
        let changed = pictures[calm]
            .iter()
            .zip(&pictures[gale])
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            changed > pictures[calm].len() / 10,
            "a gale must change the picture"
        );
    }
    let (calm, gale) = (luminance(&pictures[3]), luminance(&pictures[4]));
    assert!(
        gale >= calm * 0.88,
        "a gale darkens the Bezier grass too much: {gale} against {calm}"
    );
}

/// `render --view grass` with no `--camera` shows the whole level, as the editor's "frame
/// all" does (it used to crop the world's corners): for every example, no pixel on the
/// picture's border is the level, and the level fills over a fifth of the picture. The level
/// is told from the world around it (the calm field to the horizon, the sky) by the wind
/// colours, which only the level takes.
#[test]
fn the_default_grass_picture_shows_the_whole_level() {
    let Some(ctx) = context() else { return };
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts");
    let (w, h) = (160u32, 100u32);
    let plain = windloom::gpu::grass::PictureOptions {
        size: [w, h],
        time: 0.5,
        arrows: false,
        ..Default::default()
    };
    let coloured = windloom::gpu::grass::PictureOptions {
        wind_colours: Some(1.0),
        ..plain
    };
    for name in ["meadow.json", "obstacles.json", "branching.json"] {
        let mut l = example(name);
        // Fewer blades: the framing, not the grass, is under test.
        l.grass.density = l.grass.density.min(4.0);
        let shot =
            |o| windloom::gpu::grass::picture(&ctx, &l, backdrop(&l, &dir).as_ref(), o).unwrap();
        let (a, b) = (shot(&plain), shot(&coloured));
        let level = |x: u32, y: u32| {
            let k = ((y * w + x) * 4) as usize;
            (0..3).any(|c| a[k + c].abs_diff(b[k + c]) > 3)
        };
        let border = (0..w)
            .flat_map(|x| [(x, 0), (x, h - 1)])
            .chain((0..h).flat_map(|y| [(0, y), (w - 1, y)]));
        for (x, y) in border {
            assert!(
                !level(x, y),
                "{name}: the level reaches the edge at ({x}, {y})"
            );
        }
        let ground = (0..w * h).filter(|k| level(k % w, k / w)).count();
        println!("{name}: the level covers {ground} of {} pixels", w * h);
        assert!(
            ground * 5 > (w * h) as usize,
            "{name}: the level is too small"
        );
    }
}

/// `render --view grass --wind-colours A --speed-scale S`: the wind colours' top at a fixed
/// speed. The field's own scale given as the fixed one is the default picture, byte for
/// byte; four times it darkens the fast wind's colours, so the picture changes.
#[test]
fn the_grass_picture_takes_a_fixed_speed_scale() {
    let Some(ctx) = context() else { return };
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts");
    let mut l = example("two-winds.json");
    l.grass.density = l.grass.density.min(4.0);
    let time = 2.0;
    // The scale the picture finds itself: the CPU solver's field at `time`.
    let mut solver = windloom::sim::Solver::new(&l);
    for _ in 0..(time / l.sim.dt).round() as usize {
        solver.step();
    }
    let own = windloom::colour::speed_scale(&solver.velocity_field());
    let picture = |speed_scale| {
        let o = windloom::gpu::grass::PictureOptions {
            size: [160, 100],
            time,
            wind_colours: Some(1.0),
            speed_scale,
            ..Default::default()
        };
        windloom::gpu::grass::picture(&ctx, &l, backdrop(&l, &dir).as_ref(), &o).unwrap()
    };
    let plain = picture(None);
    assert!(
        plain == picture(Some(own)),
        "the field's own scale, fixed, is the default"
    );
    let wide = picture(Some(4.0 * own));
    let changed = plain
        .chunks(4)
        .zip(wide.chunks(4))
        .filter(|(a, b)| a.iter().zip(*b).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    println!(
        "{changed} of {} pixels recoloured on a {:.1} m/s scale",
        160 * 100,
        4.0 * own
    );
    assert!(
        changed > 1_000,
        "a wider scale recolours the wind: {changed} pixels"
    );
}

/// The AGC arrows show whole over dense grass, as editors draw their gizmos: an arrow
/// across a 400-blades-per-m² meadow, seen from a walker's height, covers at least 90% of
/// the pixels it covers over bare ground (drawn on the ground with a depth test, as it
/// once was, the blades hid most of it).
#[test]
fn the_arrows_show_over_dense_grass() {
    let Some(ctx) = context() else { return };
    let mut l = layout(400.0);
    l.trees.truncate(1);
    let tree = &mut l.trees[0];
    tree.enabled = true;
    tree.root.pos = [3.0, 5.5];
    tree.root.children.truncate(1);
    tree.root.children[0].pos = [9.5, 3.0];
    tree.root.children[0].children.clear();
    let lines = windloom::grass::scene::arrows(&l);
    assert!(
        lines.len() >= 6,
        "a root's cross and an arrow with its head"
    );
    let camera = Camera {
        eye: glam::Vec3::new(6.0, 1.6, 9.5),
        target: glam::Vec3::new(6.0, 0.0, 4.0),
        fov_y: 50f32.to_radians(),
    };
    // The pixels the arrows change: the picture with them against the same one without.
    let arrow_pixels = |density: f32| {
        let mut l = l.clone();
        l.grass.density = density;
        let (mut r, blades) = steady_renderer(&ctx, &l, [3.0, 0.0]);
        let mut shot = |lines: &[windloom::grass::scene::SceneVertex]| {
            r.set_scene(&ctx.device, &[], lines);
            render_offscreen(&ctx, &mut r, &camera, (1.0, 1.0 / 60.0), [320, 200])
                .unwrap()
                .0
        };
        let (with, without) = (shot(&lines), shot(&[]));
        let changed = with
            .chunks(4)
            .zip(without.chunks(4))
            .filter(|(a, b)| a.iter().zip(*b).any(|(x, y)| x.abs_diff(*y) > 24))
            .count();
        (changed, blades)
    };
    let (bare, few) = arrow_pixels(0.01);
    let (over_grass, many) = arrow_pixels(400.0);
    println!("arrow pixels: {bare} over bare ground ({few} blades), {over_grass} over {many}");
    assert!(many > 30_000, "dense grass: {many} blades");
    assert!(bare > 300, "the arrow is in the picture: {bare} pixels");
    assert!(
        over_grass * 10 >= bare * 9,
        "the grass hides the arrows: {over_grass} of {bare} pixels show"
    );
}

/// `render --view grass --no-arrows`: the grass alone. The meadow framed whole has its
/// arrow tree's blue over the grass with the arrows, and no pixel of that blue without
/// them; nothing else changes.
#[test]
fn a_grass_picture_can_leave_out_the_arrows() {
    let Some(ctx) = context() else { return };
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts");
    let mut l = example("meadow.json");
    l.grass.density = l.grass.density.min(4.0);
    let (w, h) = (320u32, 200u32);
    let shot = |arrows: bool| {
        let options = windloom::gpu::grass::PictureOptions {
            size: [w, h],
            time: 1.0,
            arrows,
            ..Default::default()
        };
        windloom::gpu::grass::picture(&ctx, &l, backdrop(&l, &dir).as_ref(), &options).unwrap()
    };
    // The arrows' saturated blue; the sky is a pale blue, the grass and soil are not blue.
    let blue = |p: &[u8]| p.chunks(4).filter(|c| c[2] > 200 && c[0] < 120).count();
    let (with, without) = (shot(true), shot(false));
    println!(
        "arrow-blue pixels: {} with the arrows, {} without",
        blue(&with),
        blue(&without)
    );
    assert!(blue(&with) > 100, "the arrows show: {}", blue(&with));
    assert_eq!(blue(&without), 0, "no arrows");
    let changed = with
        .chunks(4)
        .zip(without.chunks(4))
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        changed <= 3 * blue(&with),
        "only the arrows' pixels change: {changed}"
    );
}

/// Over terrain every blade stands on the ground the CPU twin computes
/// (`TerrainField::ground_at`): its tip is the flat-ground blade's, lifted by the ground's
/// height at its root, its shade unchanged.
#[test]
fn blades_stand_on_the_terrain() {
    let Some(ctx) = context() else { return };
    let dir = tempfile::tempdir().unwrap();
    let mut l = layout(20.0);
    // A 3 m mound in the middle of the 12 × 8 m field.
    let img = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_fn(48, 32, |x, y| {
        let (dx, dz) = (x as f32 / 48.0 - 0.5, y as f32 / 32.0 - 0.5);
        image::Luma([((-(dx * dx + dz * dz) * 12.0).exp() * 65535.0) as u16])
    });
    img.save(dir.path().join("mound.png")).unwrap();
    l.world.terrain = Some(windloom::doc::Terrain {
        heightmap: "mound.png".into(),
        heights: [0.0, 3.0],
        rect: None,
        strength: 1.0,
        feature_length: None,
        pixels: windloom::io::grey_pixels(dir.path(), "mound.png", "heightmap"),
    });
    let ground = windloom::sim::terrain::TerrainField::new(&l).unwrap();
    let blades = scatter(&l);
    let mut r = GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
    let wind = vec![[3.0, 1.0]; 24 * 16];
    r.set_wind(
        &ctx.device,
        &ctx.queue,
        (24, 16),
        [0.0, 0.0],
        [0.5, 0.5],
        &wind,
    );
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    r.prepare(&ctx.queue, &mut enc, &Camera::overview(&l), 1.5, 2.0, 0.25);
    ctx.queue.submit([enc.finish()]);
    let tips = r.read_tips(&ctx.device, &ctx.queue).unwrap();
    let (mut worst, mut lifted) = (0.0f32, 0);
    for (b, gpu) in blades.iter().zip(&tips) {
        let cpu = cwd::centreline_crushed(
            b,
            [3.0, 1.0],
            &l.grass,
            2.0,
            SEGMENTS as usize,
            (0.0, [0.0, 0.0]),
        )[SEGMENTS as usize];
        let lift = ground.ground_at(b.pos);
        lifted += usize::from(lift > 1.0);
        let want = [cpu.pos[0], cpu.pos[1] + lift, cpu.pos[2]];
        let d = (0..3).fold(0.0f32, |m, c| m.max((gpu[c] - want[c]).abs()));
        worst = worst.max(d).max((gpu[3] - cpu.shade).abs());
    }
    assert!(
        lifted > blades.len() / 10,
        "the mound lifts many blades: {lifted}"
    );
    assert!(worst <= 2e-3, "tips differ from the ground's by {worst} m");
}

/// Drawn nearest first (the stored rows or by x, `grass::Walk`), a dense field writes fewer
/// samples than in its stored order (the depth test drops the hidden blades before they are
/// shaded) and never more, under 1.5 times a sample from each side of the level (counted
/// where the adapter counts them: not GL); and the picture is the same either way.
#[test]
fn blades_drawn_nearest_first_write_fewer_samples_for_the_same_picture() {
    use windloom::gpu::grass::{Target, count_written};
    let Some(ctx) = context() else { return };
    let l = layout(2500.0);
    let (mut r, blades) = steady_renderer(&ctx, &l, [1.2, -0.9]);
    let size = [480, 270];
    let target = Target::new(&ctx.device, size, ctx.downlevel);
    // From each side, 1.6 m up, looking across the middle; and from high above the south.
    let sides = [
        ("north, looking −z", [6.0, 1.6, 7.6], [6.0, 0.0, 0.0]),
        ("south, looking +z", [6.0, 1.6, 0.4], [6.0, 0.0, 8.0]),
        ("west, looking +x", [0.4, 1.6, 4.0], [12.0, 0.0, 4.0]),
        ("east, looking −x", [11.6, 1.6, 4.0], [0.0, 0.0, 4.0]),
        (
            "south-west, looking −z and +x",
            [1.0, 1.6, 7.0],
            [8.0, 0.0, 2.0],
        ),
        ("above, looking down −z", [6.0, 9.0, 10.0], [6.0, 0.0, 4.0]),
    ];
    for (side, eye, target_at) in sides {
        let camera = Camera {
            eye: glam::Vec3::from(eye),
            target: glam::Vec3::from(target_at),
            fov_y: 45f32.to_radians(),
        };
        let mut shoot = |near_first: bool| {
            r.set_near_first(near_first);
            let (pixels, _) =
                render_offscreen(&ctx, &mut r, &camera, (0.0, 1.0 / 60.0), size).unwrap();
            (pixels, count_written(&ctx, &r, &target).unwrap())
        };
        let (near, stored) = (shoot(true), shoot(false));
        if let (Some(n), Some(s)) = (near.1, stored.1) {
            let (a, b) = (n.samples, s.samples);
            println!(
                "{side}: {blades} blades, samples written {a} nearest first ({:.2} a sample), \
                 {b} in the stored order ({:.2})",
                n.layers, s.layers
            );
            assert!(
                a <= b + b / 1000,
                "{side}: nearest first wrote more: {a} > {b}"
            );
            // Wherever the stored rows do not run toward the camera (all but looking +z),
            // nearest first saves samples; and from every side each sample is written about
            // once (the stored order wrote up to 15 times along the rows and against them).
            if !side.contains("+z") {
                assert!(a * 10 < b * 9, "{side}: {a} is not 10 % under {b}");
            }
            assert!(
                n.layers < 1.5,
                "{side}: each sample written {:.2} times",
                n.layers
            );
        } else {
            assert_eq!(
                ctx.adapter.backend,
                wgpu::Backend::Gl,
                "only GL cannot count"
            );
            println!("{side}: samples written not counted on GL; the pictures compared");
        }
        // The same picture: only blades crossing at one depth could swap.
        let diff: Vec<u8> = near
            .0
            .iter()
            .zip(&stored.0)
            .map(|(p, q)| p.abs_diff(*q))
            .collect();
        let mean = diff.iter().map(|&d| f64::from(d)).sum::<f64>() / diff.len() as f64;
        let off = diff.iter().filter(|&&d| d > 24).count();
        println!("{side}: the pictures differ by {mean:.3} on average, {off} channels by over 24");
        assert!(
            mean < 0.2 && off * 1000 < diff.len(),
            "{side}: {mean}, {off}"
        );
    }
}
