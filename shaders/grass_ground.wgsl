// Grass, render: the ground under the blades — the world rectangle at y = 0, a soil colour
// darkened under the grass or, where the layout has a map backdrop, the backdrop image laid
// over it at its opacity; lit by the same sun and sky as the blades.

@group(2) @binding(0) var backdrop_image: texture_2d<f32>;
@group(2) @binding(1) var backdrop_sampler: sampler;

struct GroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) k: u32) -> GroundOut {
    let c = array<vec2<f32>, 6>(
        vec2<f32>(0.0, 0.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0),
        vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 1.0),
    )[k];
    let w = mix(S.world_min, S.world_max, c);
    return GroundOut(S.view_proj * vec4<f32>(w.x, 0.0, w.y, 1.0), c);
}

@fragment
fn fs_main(in: GroundOut) -> @location(0) vec4<f32> {
    let soil = palettes[0].rgb * 0.55 + vec3<f32>(0.035, 0.028, 0.015);
    // The image is sRGB; the texture view decodes it to linear.
    let map = textureSample(backdrop_image, backdrop_sampler, in.uv).rgb;
    let ground = mix(soil, map, clamp(S.backdrop, 0.0, 1.0));
    let l = normalize(S.sun.xyz);
    let light = S.sun.w + (1.0 - S.sun.w) * max(l.y, 0.0);
    return vec4<f32>(encode(ground * light), 1.0);
}
