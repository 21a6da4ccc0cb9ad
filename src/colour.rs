//! Colour scales shared by the editor and the headless renderer.

/// Speed colour (perceptual "turbo" scale) for `t` in [0, 1], as RGB bytes.
pub fn speed_rgb(t: f32) -> [u8; 3] {
    let c = colorous::TURBO.eval_continuous(f64::from(t.clamp(0.0, 1.0)) * 0.9 + 0.05);
    [c.r, c.g, c.b]
}

/// Diverging colour for a signed value in [-1, 1] (blue negative, red positive).
pub fn signed_rgb(t: f32) -> [u8; 3] {
    let c = colorous::RED_BLUE.eval_continuous(f64::from(0.5 - 0.5 * t.clamp(-1.0, 1.0)));
    [c.r, c.g, c.b]
}

/// The range a fixed speed scale may take, m/s (the editor's View → Fixed speed scale,
/// `render --speed-scale`).
pub const FIXED_SCALE_RANGE: (f32, f32) = (0.5, 200.0);

/// The speed at the top of the speed scale for a wind field: its peak speed, at least 1 m/s
/// (the map view's scale and legend, and the 3D view's wind colours).
pub fn speed_scale(velocity: &[[f32; 2]]) -> f32 {
    velocity
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1]).sqrt())
        .fold(1.0f32, f32::max)
}

/// Steps of the speed scale in the GPU look-up tables (the map view's and the 3D view's):
/// `t` picks step `round(t × 255)`.
pub const SPEED_STEPS: usize = 256;

/// The speed scale in [`SPEED_STEPS`] steps as linear RGB (alpha 1), for shaders that light
/// or blend in linear light: the 3D view's wind colours.
pub fn speed_table_linear() -> Vec<[f32; 4]> {
    (0..SPEED_STEPS)
        .map(|k| {
            let [r, g, b] = speed_rgb(k as f32 / (SPEED_STEPS - 1) as f32);
            [linear(r), linear(g), linear(b), 1.0]
        })
        .collect()
}

/// An sRGB-encoded byte as linear light in [0, 1] (the sRGB transfer function, with the
/// constants egui's `ecolor` uses, so that the 3D view's wind colours and the map's agree
/// to the bit). The platform's `powf`, as egui's: on each platform the two agree to the bit
/// (`crate::num`'s would not). No bake or map picture reads it; the GPU's grass pictures do,
/// which differ by GPU anyway.
pub fn linear(s: u8) -> f32 {
    if s <= 10 {
        f32::from(s) / 3294.6
    } else {
        ((f32::from(s) + 14.025) / 269.025).powf(2.4)
    }
}
