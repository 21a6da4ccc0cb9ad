use super::context;
use super::far::{meadow, pixel_of, srgb};
use glam::Vec3;
use windloom::colour::{speed_rgb, speed_table_linear};
use windloom::doc::Layout;
use windloom::gpu::GpuContext;
use windloom::gpu::grass::{Camera, GrassRenderer, render_offscreen, settle};
use windloom::grass::cull::CullParams;
use windloom::grass::scatter;

/// Three bands of wind across the 24 × 16 m meadow (0.5 m cells): calm for x < 8 m, 3 m/s to
/// 16 m, 6 m/s beyond; blowing along +z so no blade hides another band.
fn banded(l: &Layout) -> Vec<[f32; 2]> {
    let [nx, ny] = l.world.grid;
    (0..nx * ny)
        .map(|k| {
            let x = (k % nx) as f32 * 0.5 + 0.25;
            [
                0.0,
                if x < 8.0 {
                    0.0
                } else if x < 16.0 {
                    3.0
                } else {
                    6.0
                },
            ]
        })
        .collect()
}

/// The meadow in `wind` from above, every blade drawn, with the wind colours at
/// `colours: (opacity, scale)` (`None`: never set).
fn picture(
    ctx: &GpuContext,
    l: &Layout,
    wind: &[[f32; 2]],
    camera: &Camera,
    colours: Option<(f32, f32)>,
) -> Vec<u8> {
    let mut r = GrassRenderer::new(
        &ctx.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        l,
        &scatter(l),
    );
    r.set_model(&ctx.device, &ctx.queue, l.grass.model);
    let [nx, ny] = l.world.grid;
    let cells = (nx as usize, ny as usize);
    r.set_wind(
        &ctx.device,
        &ctx.queue,
        cells,
        l.world.origin,
        [0.5, 0.5],
        wind,
    );
    r.set_cull(CullParams::OFF);
    if colours.is_some() {
        r.set_wind_colours(colours);
    }
    settle(ctx, &mut r, camera, 2.0, 2.0);
    render_offscreen(ctx, &mut r, camera, (2.0, 1.0 / 60.0), [320, 200])
        .unwrap()
        .0
}

/// The pixels of the 7 × 7 square around `(x, y)` (sRGB bytes, RGB).
fn square(px: &[u8], (x, y): (usize, usize)) -> Vec<[u8; 3]> {
    let mut out = Vec::new();
    for j in y - 3..=y + 3 {
        for i in x - 3..=x + 3 {
            let k = (j * 320 + i) * 4;
            out.push([px[k], px[k + 1], px[k + 2]]);
        }
    }
    out
}

fn linear(c: u8) -> f32 {
    eframe::egui::ecolor::linear_f32_from_gamma_u8(c)
}

/// The 3D view's "wind colours" show where the wind blows in a still picture, in the map
/// view's colours: in three bands of 0, 3 and 6 m/s on a 6 m/s scale, every pixel of blade
/// and ground at a band's centre is the map's speed colour (`colour::speed_rgb` at 0, ½, 1)
/// within 2/255 at full opacity, for both blade models; at half opacity each is the plain
/// picture's pixel half-way (in linear light) to that colour, within 1/255 on average over
/// the square and 16 at worst (a blade's edge pixel is the mean of its four samples: the mix
/// of means is not exactly the mean of mixes, and with each blade fluttering at its own
/// phase a band of 6 m/s is all edges); at opacity 0 the picture is the plain one, byte for
/// byte.
#[test]
fn the_wind_colours_are_the_map_view_s_speed_scale() {
    use windloom::doc::GrassModel::{BezierPhysics as Bezier, CwdQuadratic as Cwd};
    let Some(ctx) = context() else { return };
    let mut l = meadow(24.0, 16.0, 60.0);
    l.trees.clear();
    l.obstacles.clear();
    let wind = banded(&l);
    let camera = Camera {
        eye: Vec3::new(12.0, 26.0, 7.0),
        target: Vec3::new(12.0, 0.0, 8.0),
        fov_y: 40f32.to_radians(),
    };
    let table = speed_table_linear();
    let bands = [(4.0f32, 0.0f32), (12.0, 0.5), (20.0, 1.0)];
    for model in [Cwd, Bezier] {
        l.grass.model = model;
        let plain = picture(&ctx, &l, &wind, &camera, None);
        let full = picture(&ctx, &l, &wind, &camera, Some((1.0, 6.0)));
        let half = picture(&ctx, &l, &wind, &camera, Some((0.5, 6.0)));
        let zero = picture(&ctx, &l, &wind, &camera, Some((0.0, 6.0)));
        assert!(zero == plain, "{model:?}: opacity 0 changed the picture");
        for (x, t) in bands {
            let at = pixel_of(&camera, (x, 8.0));
            let want = speed_rgb(t);
            let step = table[(t * 255.0 + 0.5) as usize];
            let (full, half, plain) = (square(&full, at), square(&half, at), square(&plain, at));
            println!(
                "{model:?} band at x = {x} m (t = {t}): full {:?}, map {want:?}",
                full[24]
            );
            let mut errors = Vec::new();
            for ((f, h), p) in full.iter().zip(&half).zip(&plain) {
                for c in 0..3 {
                    let gap = (i32::from(f[c]) - i32::from(want[c])).abs();
                    assert!(
                        gap <= 2,
                        "{model:?} at x = {x} m: {f:?}, the map shows {want:?}"
                    );
                    let mixed = srgb(0.5 * (linear(p[c]) + step[c]));
                    errors.push((f64::from(h[c]) - mixed).abs());
                }
            }
            let mean = errors.iter().sum::<f64>() / errors.len() as f64;
            let worst = errors.iter().copied().fold(0.0, f64::max);
            println!(
                "{model:?} at x = {x} m, half opacity: off the mix by {mean:.2} on average, {worst:.1} at worst"
            );
            assert!(
                mean <= 1.0 && worst <= 16.0,
                "{model:?} at x = {x} m, half opacity: off the mix by {mean} on average, {worst} at worst"
            );
        }
        // The picture is not one colour: the bands are told apart.
        let calm = square(&full, pixel_of(&camera, (4.0, 8.0)))[24];
        let gale = square(&full, pixel_of(&camera, (20.0, 8.0)))[24];
        assert_ne!(calm, gale);
    }
}
