// Grass, render: what the 3D view shows besides grass — obstacles as solids (triangles, lit by
// their face normal), the AGC arrows and the map view's footprint on the ground (lines).
// Vertices come from `grass::scene` (`SceneVertex`: position, linear colour).

struct SceneOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
    @location(1) world: vec3<f32>,
}

@vertex
fn vs_main(@location(0) at: vec3<f32>, @location(1) colour: vec4<f32>) -> SceneOut {
    // Obstacles, arrows and the footprint stand on the terrain, each vertex on the ground
    // under it.
    let pos = at + vec3<f32>(0.0, ground(at.xz), 0.0);
    return SceneOut(S.view_proj * vec4<f32>(pos, 1.0), colour, pos);
}

// Solids: flat shading from the face normal (screen-space derivatives of the position), seen
// through the haze.
@fragment
fn fs_solid(in: SceneOut) -> @location(0) vec4<f32> {
    let n = normalize(cross(dpdx(in.world), dpdy(in.world)));
    let l = normalize(S.sun.xyz);
    let light = S.sun.w + (1.0 - S.sun.w) * abs(dot(n, l));
    return vec4<f32>(encode(hazed(in.colour.rgb * light, in.world)), 1.0);
}

// Lines: their own colour, unlit.
@fragment
fn fs_line(in: SceneOut) -> @location(0) vec4<f32> {
    return vec4<f32>(encode(in.colour.rgb), 1.0);
}
