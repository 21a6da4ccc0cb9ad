use super::{context, example};
use glam::Vec3;
use windloom::doc::Layout;
use windloom::gpu::GpuContext;
use windloom::gpu::grass::{Camera, GrassRenderer, SUN, render_offscreen};
use windloom::grass::cull::CullParams;
use windloom::grass::far::{self, Look};
use windloom::grass::light;
use windloom::grass::{scatter, wind_cell};

/// The meadow example on a `w × d` m world with 0.5 m cells, at `density` blades a m².
pub(super) fn meadow(w: f32, d: f32, density: f32) -> Layout {
    let mut l = example("meadow.json");
    l.world.size = [w, d];
    l.world.grid = [(w * 2.0) as u32, (d * 2.0) as u32];
    l.grass.density = density;
    l
}

/// The far pass against its CPU twin (`grass::far::texel`, `grass::far::cover`): every texel
/// of a 48 × 32 grid in random winds up to 12 m/s at two times, seen from a corner, with the
/// distance cull's fade crossing the field and then a blade budget's sample on top: colours
/// within 2e-3 (linear, lit), the share of ground the far field takes within 1e-3 (the
/// texels are half floats: 2⁻¹¹ relative).
#[test]
fn the_far_field_matches_its_cpu_twin() {
    let Some(ctx) = context() else { return };
    let l = meadow(24.0, 16.0, 4.0);
    let blades = scatter(&l);
    let (nx, ny) = (48, 32);
    let cell = [0.5, 0.5];
    let mut r = GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
    let camera = Camera {
        eye: Vec3::new(-4.0, 5.0, -3.0),
        target: Vec3::new(12.0, 0.0, 8.0),
        fov_y: 45f32.to_radians(),
    };
    let cull = CullParams {
        max_distance: 26.0,
        thin_distance: 12.0,
        ..CullParams::for_height(0.5)
    };
    r.set_cull(cull);
    let look = Look::new(&l.grass, SUN);
    let (mut worst_colour, mut worst_cover) = (0.0f32, 0.0f32);
    let (mut lowest, mut highest) = (f32::MAX, f32::MIN);
    let mut hidden = (f32::MAX, f32::MIN);
    let mut luminances = Vec::new();
    for (k, (time, reach)) in [(0.0f32, 0.0f32), (3.7, 9.0)].into_iter().enumerate() {
        let a = super::noise(nx * ny, 70 + k as u64, std::f32::consts::PI);
        let s = super::noise(nx * ny, 80 + k as u64, 6.0);
        let wind: Vec<[f32; 2]> = a
            .iter()
            .zip(&s)
            .map(|(a, s)| [(s + 6.0) * a.cos(), (s + 6.0) * a.sin()])
            .collect();
        r.set_wind(&ctx.device, &ctx.queue, (nx, ny), [0.0, 0.0], cell, &wind);
        r.set_sample_reach(reach);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        r.prepare(&ctx.queue, &mut enc, &camera, 1.5, time, 1.0 / 60.0);
        ctx.queue.submit([enc.finish()]);
        let texels = r.read_far(&ctx.device, &ctx.queue).unwrap();
        let u = r.far_uniform();
        assert_eq!(
            (u.nx, u.ny),
            (nx as u32, ny as u32),
            "one texel a wind cell"
        );
        for (i, gpu) in texels.iter().enumerate() {
            let (tx, ty) = (i % nx, i / nx);
            let pos = [
                u.origin[0] + (tx as f32 + 0.5) * u.cell[0],
                u.origin[1] + (ty as f32 + 0.5) * u.cell[1],
            ];
            let w = wind[wind_cell(pos, [0.0, 0.0], cell, (nx, ny))];
            let cpu = far::texel(
                &l.grass,
                &look,
                w,
                pos,
                camera.eye.to_array(),
                (0.0, [0.0, 0.0]),
            );
            for (g, c) in gpu.iter().zip(cpu.colour) {
                worst_colour = worst_colour.max((g - c).abs());
            }
            let d = Vec3::new(pos[0], 0.0, pos[1]).distance(camera.eye);
            let cover = far::cover(d, &cull, reach);
            worst_cover = worst_cover.max((gpu[3] - cpu.hidden * (1.0 - cover)).abs());
            lowest = lowest.min(cover);
            highest = highest.max(cover);
            hidden = (hidden.0.min(cpu.hidden), hidden.1.max(cpu.hidden));
            let c = cpu.colour;
            luminances.push(0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]);
        }
    }
    let (dark, light) = luminances
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    println!(
        "far field: max |GPU − CPU| colour {worst_colour:.2e}, coverage {worst_cover:.2e}; \
         coverage {lowest:.3}–{highest:.3}, ground hidden {:.3}–{:.3}, luminance {dark:.3}–{light:.3}",
        hidden.0, hidden.1
    );
    assert!(
        lowest < 0.05 && highest > 0.95,
        "the test's texels span the fade"
    );
    assert!(light - dark > 0.02, "the wind changes the far field's look");
    assert!(worst_colour <= 2e-3, "colours differ by {worst_colour}");
    assert!(worst_cover <= 1e-3, "coverage differs by {worst_cover}");
}

/// Where the density map grows less grass, the far field hides less ground, as its CPU twin
/// says (`far::density_shares`, `far::thinned`): over a map bare on its left third, half
/// grown in the middle and full on the right, every texel's share of the ground within 2e-3
/// of the twin's (its share is stored to a 255th), none at all over the bare third.
#[test]
fn the_far_field_thins_where_the_density_map_does() {
    let Some(ctx) = context() else { return };
    let mut l = meadow(24.0, 16.0, 30.0);
    let (iw, ih) = (48u32, 32u32);
    let luminance = (0..ih)
        .flat_map(|_| {
            (0..iw).map(|x| match x * 3 / iw {
                0 => 0,
                1 => 32_768,
                _ => u16::MAX,
            })
        })
        .collect();
    l.grass.density_map = Some(windloom::doc::DensityMap {
        image: "unused.png".into(),
        rect: None,
        pixels: windloom::doc::MaskPixels::Loaded(std::sync::Arc::new(windloom::doc::MaskImage {
            width: iw,
            height: ih,
            luminance,
        })),
    });
    let blades = scatter(&l);
    let (nx, ny) = (48, 32);
    let cell = [0.5, 0.5];
    let mut r = GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
    let camera = Camera {
        eye: Vec3::new(12.0, 30.0, 30.0),
        target: Vec3::new(12.0, 0.0, 8.0),
        fov_y: 45f32.to_radians(),
    };
    // Every blade culled (the eye is 30 m up): the far field takes all the ground it hides.
    r.set_cull(CullParams {
        max_distance: 1.0,
        thin_distance: 0.0,
        ..CullParams::for_height(0.5)
    });
    let wind = vec![[3.0, 1.0]; nx * ny];
    r.set_wind(&ctx.device, &ctx.queue, (nx, ny), [0.0, 0.0], cell, &wind);
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    r.prepare(&ctx.queue, &mut enc, &camera, 1.5, 1.0, 1.0 / 60.0);
    ctx.queue.submit([enc.finish()]);
    let texels = r.read_far(&ctx.device, &ctx.queue).unwrap();
    let u = r.far_uniform();
    let look = Look::new(&l.grass, SUN);
    let shares = far::density_shares(l.grass.density_map.as_ref(), l.bounds(), (nx, ny));
    let mut worst = 0.0f32;
    for (i, gpu) in texels.iter().enumerate() {
        let (tx, ty) = (i % nx, i / nx);
        let pos = [
            u.origin[0] + (tx as f32 + 0.5) * u.cell[0],
            u.origin[1] + (ty as f32 + 0.5) * u.cell[1],
        ];
        let t = far::texel(
            &l.grass,
            &look,
            [3.0, 1.0],
            pos,
            camera.eye.to_array(),
            (0.0, [0.0, 0.0]),
        );
        let d = Vec3::new(pos[0], 0.0, pos[1]).distance(camera.eye);
        let cover = far::cover(d, &r.cull_params(), 0.0);
        let want = far::thinned(t.hidden, shares[i]) * (1.0 - cover);
        worst = worst.max((gpu[3] - want).abs());
        if tx < nx / 3 - 1 {
            assert_eq!(gpu[3], 0.0, "texel {tx},{ty} over bare ground hides it");
        }
        if tx > 2 * nx / 3 + 1 {
            assert!(
                gpu[3] > 0.05,
                "texel {tx},{ty} under full grass: {}",
                gpu[3]
            );
        }
    }
    println!("far field over a density map: max |GPU − CPU| share {worst:.2e}");
    assert!(worst <= 2e-3, "shares differ by {worst}");
}

/// The table of the field's look by view direction, in the wind at the level's edge, which the
/// ground beyond the level takes, against its CPU twin (`grass::far::surround_table`): every texel's colour within
/// 2e-3 and its share of the ground within 1e-3 (half floats). The look changes with the
/// view — toward the sun and away from it, from above and along the ground — which is why
/// one colour for the whole surround showed the level as a plate on it.
#[test]
fn the_ground_beyond_the_level_matches_its_cpu_twin() {
    let Some(ctx) = context() else { return };
    let l = meadow(24.0, 16.0, 4.0);
    let blades = scatter(&l);
    let mut r = GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
    let camera = Camera {
        eye: Vec3::new(-4.0, 5.0, -3.0),
        target: Vec3::new(12.0, 0.0, 8.0),
        fov_y: 45f32.to_radians(),
    };
    // A breeze along the border with a jet through the middle: the meadow beyond the level
    // takes the border's mean wind.
    let (nx, ny) = (48, 32);
    let wind: Vec<[f32; 2]> = (0..nx * ny)
        .map(|k| {
            let (i, j) = (k % nx, k / nx);
            let jet = if (14..18).contains(&j) { 20.0 } else { 0.0 };
            [2.0 + jet + 0.05 * i as f32, -1.0 + 0.04 * j as f32]
        })
        .collect();
    r.set_wind(
        &ctx.device,
        &ctx.queue,
        (nx, ny),
        [0.0, 0.0],
        [0.5, 0.5],
        &wind,
    );
    let edge = far::edge_wind(&wind, (nx, ny));
    assert!(
        edge[0] > 3.0 && edge[0] < 6.0,
        "the breeze and a little jet: {edge:?}"
    );
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    r.prepare(&ctx.queue, &mut enc, &camera, 1.5, 2.0, 1.0 / 60.0);
    ctx.queue.submit([enc.finish()]);
    let gpu = r.read_surround(&ctx.device, &ctx.queue).unwrap();
    let cpu = far::surround_table(&l.grass, &Look::new(&l.grass, SUN), edge);
    let still = far::surround_table(&l.grass, &Look::new(&l.grass, SUN), [0.0, 0.0]);
    let lit = |t: &[[f32; 4]]| t.iter().map(|c| c[1]).sum::<f32>() / t.len() as f32;
    assert!(
        lit(&cpu) > 1.05 * lit(&still),
        "the breeze lightens the meadow beyond the level: {} against {} in still air",
        lit(&cpu),
        lit(&still)
    );
    assert_eq!(gpu.len(), far::SURROUND_AZIMUTHS * far::SURROUND_ELEVATIONS);
    assert_eq!(gpu.len(), cpu.len());
    let (mut worst_colour, mut worst_hidden) = (0.0f32, 0.0f32);
    for (g, c) in gpu.iter().zip(&cpu) {
        for k in 0..3 {
            worst_colour = worst_colour.max((g[k] - c[k]).abs());
        }
        worst_hidden = worst_hidden.max((g[3] - c[3]).abs());
    }
    let lum = |c: &[f32; 4]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    let (dark, light) = cpu
        .iter()
        .map(lum)
        .fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(v), b.max(v)));
    let (low, high) = cpu
        .iter()
        .map(|c| c[3])
        .fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(v), b.max(v)));
    println!(
        "surround: max |GPU − CPU| colour {worst_colour:.2e}, hidden {worst_hidden:.2e}; \
         luminance {dark:.3}–{light:.3}, ground hidden {low:.3}–{high:.3}"
    );
    assert!(worst_colour <= 2e-3, "colours differ by {worst_colour}");
    assert!(
        worst_hidden <= 1e-3,
        "hidden shares differ by {worst_hidden}"
    );
    assert!(
        light > 1.2 * dark,
        "the calm field looks the same from every side"
    );
    assert!(
        high > low + 0.2,
        "the field hides as much ground from above as along it"
    );
}

/// A picture of `l`'s grass (far field on or off) from `camera`, 320 × 200.
fn picture(
    ctx: &GpuContext,
    l: &Layout,
    wind: &[[f32; 2]],
    camera: &Camera,
    cull: CullParams,
    far_on: bool,
) -> Vec<u8> {
    let blades = scatter(l);
    let mut r = GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8UnormSrgb, l, &blades);
    r.set_model(&ctx.device, &ctx.queue, l.grass.model);
    let [nx, ny] = l.world.grid;
    r.set_wind(
        &ctx.device,
        &ctx.queue,
        (nx as usize, ny as usize),
        l.world.origin,
        [0.5, 0.5],
        wind,
    );
    r.set_cull(cull);
    r.set_far(far_on);
    // Two seconds for the Bezier blades to answer the wind.
    windloom::gpu::grass::settle(ctx, &mut r, camera, 2.0, 2.0);
    render_offscreen(ctx, &mut r, camera, (2.0, 1.0 / 60.0), [320, 200])
        .unwrap()
        .0
}

/// The pixel `(x, y)` of world point `(wx, wz)` on the ground.
/// The pixel of a `size` picture seen through `camera` that shows the world point at
/// `(wx, wz)` at height `wy`.
pub(super) fn pixel_of_at(
    camera: &Camera,
    size: [u32; 2],
    (wx, wy, wz): (f32, f32, f32),
) -> (usize, usize) {
    let (w, h) = (size[0] as f32, size[1] as f32);
    let c = camera.view_proj(w / h) * glam::Vec4::new(wx, wy, wz, 1.0);
    let (x, y) = (c.x / c.w, c.y / c.w);
    (
        ((x * 0.5 + 0.5) * w) as usize,
        ((0.5 - y * 0.5) * h) as usize,
    )
}

pub(super) fn pixel_of(camera: &Camera, (wx, wz): (f32, f32)) -> (usize, usize) {
    let c = camera.view_proj(320.0 / 200.0) * glam::Vec4::new(wx, 0.0, wz, 1.0);
    let (x, y) = (c.x / c.w, c.y / c.w);
    (
        ((x * 0.5 + 0.5) * 320.0) as usize,
        ((0.5 - y * 0.5) * 200.0) as usize,
    )
}

/// The mean sRGB colour (0–255) of the `r`-pixel square around `(x, y)`.
fn mean_around(px: &[u8], (x, y): (usize, usize), r: usize) -> [f64; 3] {
    let mut s = [0.0; 3];
    let mut n = 0.0;
    for j in y - r..=y + r {
        for i in x - r..=x + r {
            for c in 0..3 {
                s[c] += f64::from(px[(j * 320 + i) * 4 + c]);
            }
            n += 1.0;
        }
    }
    s.map(|v| v / n)
}

/// Linear → sRGB, 0–255 (the target's encoding).
pub(super) fn srgb(c: f32) -> f64 {
    let c = c.clamp(0.0, 1.0);
    let e = if c <= 0.0031308 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    f64::from(e) * 255.0
}

/// The editor's "frame all" on a big level puts every blade past the distance cull: the
/// ground showed bare soil, the same in a gale as in calm. With the far field the ground
/// shows the blades' look where they are missing: in a band of 9 m/s wind across a calm
/// 120 × 80 m meadow seen from 420 m, each pixel is the plain ground blended to the CPU
/// twin's colour by the share it predicts (`far::texel`, `far::cover`), within 2/255 a
/// channel; with the far field off both are the plain ground.
#[test]
fn a_far_view_of_the_meadow_is_the_grass_its_cpu_twin_predicts() {
    let Some(ctx) = context() else { return };
    let l = meadow(120.0, 80.0, 60.0);
    let [nx, ny] = l.world.grid;
    let band = |z: f32| (z - 40.0).abs() < 12.0;
    let wind: Vec<[f32; 2]> = (0..nx * ny)
        .map(|k| {
            let z = (k / nx) as f32 * 0.5;
            if band(z) { [9.0, 0.0] } else { [0.0, 0.0] }
        })
        .collect();
    // 420 m away through a narrow lens: the whole level, every blade past the cull.
    let camera = Camera {
        eye: Vec3::new(60.0, 260.0, 40.0 - 330.0),
        target: Vec3::new(60.0, 0.0, 40.0),
        fov_y: 18f32.to_radians(),
    };
    let cull = CullParams::for_height(0.5);
    assert!(camera.eye.distance(Vec3::new(60.0, 0.0, 80.0)) > cull.max_distance);
    let on = picture(&ctx, &l, &wind, &camera, cull, true);
    let off = picture(&ctx, &l, &wind, &camera, cull, false);
    // The ground shader's plain ground: soil under the grass, lit by the sun and the sky.
    let p0 = l.grass.palettes[0].base;
    let sun = Vec3::new(SUN[0], SUN[1], SUN[2]).normalize();
    let light = SUN[3] + (1.0 - SUN[3]) * sun.y.max(0.0);
    let soil = Vec3::new(
        p0[0] * 0.55 + 0.035,
        p0[1] * 0.55 + 0.028,
        p0[2] * 0.55 + 0.015,
    ) * light;
    let look = Look::new(&l.grass, SUN);
    // Texel centres in the band and in the calm.
    for at in [
        (60.25, 40.25),
        (60.25, 70.25),
        (30.25, 45.25),
        (90.25, 12.25),
    ] {
        let xy = pixel_of(&camera, at);
        let w = if band(at.1) { [9.0, 0.0] } else { [0.0, 0.0] };
        let t = far::texel(
            &l.grass,
            &look,
            w,
            [at.0, at.1],
            camera.eye.to_array(),
            (0.0, [0.0, 0.0]),
        );
        let d = Vec3::new(at.0, 0.0, at.1).distance(camera.eye);
        let share = t.hidden * (1.0 - far::cover(d, &cull, 0.0));
        // The lower canopy under it all, the far field over its share, seen through the haze.
        let fade = [0.1 * camera.far_plane(), 0.9 * camera.far_plane()];
        let point = Vec3::new(at.0, 0.0, at.1);
        let seen = light::haze(camera.eye, point, fade);
        let hazed = |c: Vec3| c.lerp(Vec3::from(light::SKY_HORIZON), seen);
        let want = hazed(far::ground(soil, Vec3::from(t.colour), share, 0.0, 1.0))
            .to_array()
            .map(srgb);
        let soil_seen = hazed(soil);
        let got = mean_around(&on, xy, 0);
        let plain = mean_around(&off, xy, 0);
        println!(
            "{at:?} ({}): got {got:.1?}, twin {want:.1?} (ground hidden {:.3}), far field off {plain:.1?}",
            if band(at.1) { "wind" } else { "calm" },
            t.hidden
        );
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() <= 2.0,
                "at {at:?} the ground is {got:?}, its twin {want:?}"
            );
            assert!(
                (plain[c] - srgb(soil_seen[c])).abs() <= 1.0,
                "with the far field off, plain ground: {plain:?}"
            );
        }
        assert!(share > 0.1, "the far field takes part of the ground here");
    }
}

/// Where the blades stop, the far field takes over: the same view drawn with every blade
/// (no culling, so the ground is plain soil between them) and with none (everything past
/// the cull, so the ground is all far field) has the same mean colour within 8/255 a
/// channel, calm and in a 9 m/s wind, for the CWD blades and for the Bezier blades (whose
/// far field is the CWD model's: their steady bend is close).
#[test]
fn the_far_field_looks_like_the_blades_it_stands_for() {
    use windloom::doc::GrassModel::{BezierPhysics as Bezier, CwdQuadratic as Cwd};
    let Some(ctx) = context() else { return };
    let l = meadow(24.0, 16.0, 60.0);
    let camera = Camera {
        eye: Vec3::new(12.0, 9.0, -6.0),
        target: Vec3::new(12.0, 0.0, 8.0),
        fov_y: 30f32.to_radians(),
    };
    let none = CullParams {
        distance: true,
        max_distance: 1e-3,
        ..CullParams::OFF
    };
    let region = |px: &[u8]| mean_around(px, (160, 110), 60);
    let mut l = l;
    for (speed, model) in [(0.0f32, Cwd), (9.0, Cwd), (0.0, Bezier), (9.0, Bezier)] {
        l.grass.model = model;
        let wind = vec![[speed, 0.0]; 48 * 32];
        let blades = region(&picture(&ctx, &l, &wind, &camera, CullParams::OFF, true));
        let far_only = region(&picture(&ctx, &l, &wind, &camera, none, true));
        let soil = region(&picture(&ctx, &l, &wind, &camera, none, false));
        println!(
            "{model:?} {speed} m/s: blades {blades:.1?}, far field {far_only:.1?}, soil {soil:.1?}"
        );
        let gap = |a: [f64; 3], b: [f64; 3]| (0..3).fold(0.0f64, |m, c| m.max((a[c] - b[c]).abs()));
        assert!(
            gap(blades, far_only) <= 8.0,
            "the far field's colour {far_only:?} is not the blades' {blades:?}"
        );
        let _ = soil;
    }
}
