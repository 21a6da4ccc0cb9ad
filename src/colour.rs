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
