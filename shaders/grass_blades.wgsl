// Grass, render: every blade an instance, its geometry made here from its index — `segments`
// quads up the deformed centreline (`grass_common.wgsl`'s `blade_point`), the width pinched
// toward the tip with per-blade variation; a base-to-tip palette gradient with per-blade
// hue and brightness variation, eq. 14's self-shadow, and sun and sky light. No per-blade mesh
// exists on the CPU. CPU twin of the shape: `grass::cwd::centreline`.

@group(1) @binding(0) var<storage, read> poses: array<Pose>;

struct BladeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) world: vec3<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) k: u32) -> BladeOut {
    let b = blades[k];
    let pose = poses[k];
    let seg = vi / 6u;
    let corner = array<vec2<f32>, 6>(
        vec2<f32>(0.0, -1.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, -1.0),
        vec2<f32>(1.0, -1.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 1.0),
    )[vi % 6u];
    let n = f32(S.segments);
    let t = (f32(seg) + corner.x) / n;
    let p = blade_point(b, pose, t);
    // Along the blade, and across it (the blade's side, in the ground plane).
    let ahead = blade_point(b, pose, min(t + 0.5 / n, 1.0)) - blade_point(b, pose, max(t - 0.5 / n, 0.0));
    let fr = blade_frame(b);
    let side = vec3<f32>(fr[1].x, 0.0, fr[1].y);
    // Tip pinch: full width low down, narrowing to a point, shape varying per blade.
    let pinch = 1.0 - pow(t, 1.4 + 0.6 * b.variation);
    let half = 0.5 * b.width * pinch;
    let pos = p + side * (corner.y * half);
    var out: BladeOut;
    out.clip = S.view_proj * vec4<f32>(pos, 1.0);
    out.world = pos;
    out.normal = normalize(cross(side, ahead + vec3<f32>(0.0, 1e-6, 0.0)));
    let base = palettes[2u * b.palette].rgb;
    let tip = palettes[2u * b.palette + 1u].rgb;
    // Per-blade brightness and a slight hue shift toward yellow or blue-green.
    let v = b.variation;
    let tint = vec3<f32>(1.0 + 0.08 * v, 1.0 + 0.04 * v, 1.0 - 0.10 * v) * (1.0 + 0.12 * v);
    out.colour = mix(base, tip, t) * tint * blade_shade(p.y, pose);
    return out;
}

@fragment
fn fs_main(in: BladeOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Two-sided: light the side facing the camera; grass lets some light through.
    var n = normalize(in.normal);
    if (!front) {
        n = -n;
    }
    let l = normalize(S.sun.xyz);
    let diffuse = max(dot(n, l), 0.0);
    let through = 0.35 * max(dot(-n, l), 0.0);
    let sky = S.sun.w * (0.6 + 0.4 * n.y);
    let light = sky + (1.0 - S.sun.w) * (diffuse + through);
    return vec4<f32>(encode(in.colour * light), 1.0);
}
