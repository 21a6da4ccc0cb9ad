// Grass, render: the ground under the blades — the world rectangle at y = 0, a soil colour
// darkened under the grass, with the same sun and sky light as the blades.

@vertex
fn vs_main(@builtin(vertex_index) k: u32) -> @builtin(position) vec4<f32> {
    let c = array<vec2<f32>, 6>(
        vec2<f32>(0.0, 0.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0),
        vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 1.0),
    )[k];
    let w = mix(S.world_min, S.world_max, c);
    return S.view_proj * vec4<f32>(w.x, 0.0, w.y, 1.0);
}

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    let soil = palettes[0].rgb * 0.55 + vec3<f32>(0.035, 0.028, 0.015);
    let l = normalize(S.sun.xyz);
    let light = S.sun.w + (1.0 - S.sun.w) * max(l.y, 0.0);
    return vec4<f32>(encode(soil * light), 1.0);
}
