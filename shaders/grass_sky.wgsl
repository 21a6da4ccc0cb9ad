// Grass, render: the sky behind everything — one triangle over the whole picture on the far
// plane (0: the depth is reversed), drawn after the rest and only where nothing else was;
// each pixel the sky's colour along its view ray (`grass::light::sky`: the horizon's haze up
// to the zenith's blue, brighter toward the sun). Below the horizon it is the
// horizon's colour, which is also the haze's, so the ground fades into it.

struct SkyOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) k: u32) -> SkyOut {
    let xy = vec2<f32>(f32((k << 1u) & 2u), f32(k & 2u)) * 2.0 - vec2<f32>(1.0);
    return SkyOut(vec4<f32>(xy, 0.0, 1.0), xy);
}

@fragment
fn fs_main(in: SkyOut) -> @location(0) vec4<f32> {
    let near = S.inv_view_proj * vec4<f32>(in.ndc, 0.0, 1.0);
    let far = S.inv_view_proj * vec4<f32>(in.ndc, 1.0, 1.0);
    let dir = normalize(far.xyz / far.w - near.xyz / near.w);
    return vec4<f32>(encode(sky_colour(dir)), 1.0);
}
