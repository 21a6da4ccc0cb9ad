// Grass, render: the blades of one LOD level, drawn indirectly — instance `i` is blade
// `visible[i]` of this level's list (compacted by `grass_cull.wgsl`). Each blade is a triangle
// strip made here from its index: `segments` rows up the deformed curve of either model
// (`grass_shape.wgsl`'s `curve_point`) ending at the tip, the width pinched toward the tip with
// per-blade variation and narrowed as distance culling fades the blade out (widened where
// the field is thinned); a base-to-tip palette gradient with per-blade hue and brightness
// variation, eq. 14's self-shadow, and the sun, sky and sheen of `blade_light` through the
// haze. No per-blade mesh exists on the CPU.
// CPU twins of the shape: `grass::cwd::centreline`, `grass::bezier::State::point`,
// `grass::cull::distance_width`.

struct Level {
    segments: u32,
    level: u32,
    _pad: vec2<u32>,
}

@group(2) @binding(0) var<storage, read> visible: array<u32>;
@group(2) @binding(1) var<storage, read> C: Cull;
@group(2) @binding(2) var<storage, read> L: Level;
// The far field and the map backdrop (`gpu::grass::backdrop::look_layout`), read at the root.
@group(3) @binding(0) var<storage, read> F: Far;
@group(3) @binding(1) var far_image: texture_2d<f32>;
@group(3) @binding(2) var far_sampler: sampler;
@group(3) @binding(3) var backdrop_image: texture_2d<f32>;
@group(3) @binding(4) var backdrop_sampler: sampler;

// How much of the map's colour a blade's base takes where the backdrop shows (at full
// opacity), fading to none at the tip.
const MAP_TINT: f32 = 0.5;

// `far::prefilter`: the share of the far field's look a blade `d` metres away takes instead of
// its own colour — none while it is tall on screen, all once it is a few pixels tall.
fn prefilter(d: f32) -> f32 {
    if ((F.flags & 1u) == 0u) {
        return 0.0;
    }
    return smoothstep(0.7 * C.lod_far, 3.0 * C.lod_far, d);
}

struct BladeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) world: vec3<f32>,
    // The blade's width direction (the rounding of its normal across it).
    @location(3) side: vec3<f32>,
    // x: −1 at the left edge, 1 at the right; y: the height fraction (0 root, 1 tip); z: how
    // far the blade lies over (`blade_lay`).
    @location(4) at: vec3<f32>,
    // The far field's look at the root (rgb) and the share of it the blade takes (a).
    @location(5) look: vec4<f32>,
}

// Vertices a blade of `segments` rows takes (`2·segments + 1`: left and right up each row, the
// tip last).
fn blade_vertex(vi: u32, i: u32) -> BladeOut {
    let k = visible[i];
    let b = blades[k];
    let n = f32(L.segments);
    let t = min(f32(vi / 2u) / n, 1.0);
    let across = select(-1.0, 1.0, (vi & 1u) == 1u);
    let p = curve_point(k, b, t);
    // Along the blade, and across it (the blade's side, in the ground plane).
    let ahead = curve_point(k, b, min(t + 0.5 / n, 1.0)) - curve_point(k, b, max(t - 0.5 / n, 0.0));
    let fr = blade_frame(b);
    let side = vec3<f32>(fr[1].x, 0.0, fr[1].y);
    // Tip pinch: full width low down, narrowing to a point, shape varying per blade.
    let pinch = 1.0 - pow(t, 1.4 + 0.6 * b.variation);
    let lift = ground(b.pos);
    let root = vec3<f32>(b.pos.x, lift, b.pos.y);
    let half = 0.5 * b.width * pinch * distance_width(C, k, distance(root, S.eye.xyz));
    let pos = p + side * (across * half);
    var out: BladeOut;
    out.clip = S.view_proj * vec4<f32>(pos, 1.0);
    out.normal = normalize(cross(side, ahead + vec3<f32>(0.0, 1e-6, 0.0)));
    let base = palettes[2u * b.palette].rgb;
    let tip = palettes[2u * b.palette + 1u].rgb;
    // Per-blade brightness and a slight hue shift toward yellow or blue-green.
    let v = b.variation;
    let tint = vec3<f32>(1.0 + 0.08 * v, 1.0 + 0.04 * v, 1.0 - 0.10 * v) * (1.0 + 0.12 * v);
    var albedo = mix(base, tip, t) * tint;
    // The map image under the blade tints its base, as the ground under it.
    let r = S.backdrop_rect;
    let buv = (b.pos - r.xy) / (r.zw - r.xy);
    if (S.backdrop > 0.0 && all(buv >= vec2<f32>(0.0)) && all(buv <= vec2<f32>(1.0))) {
        let map = textureSampleLevel(backdrop_image, backdrop_sampler, buv, 0.0).rgb;
        albedo = mix(albedo, map, MAP_TINT * clamp(S.backdrop, 0.0, 1.0) * (1.0 - t));
    }
    out.colour = albedo * curve_shade(k, b, p.y - lift);
    let far_uv = (b.pos - F.origin) / (F.cell * vec2<f32>(f32(F.nx), f32(F.ny)));
    let look = textureSampleLevel(far_image, far_sampler, far_uv, 0.0).rgb;
    out.look = vec4<f32>(look, prefilter(distance(root, S.eye.xyz)));
    out.world = pos;
    out.side = side;
    out.at = vec3<f32>(across, t, blade_lay(curve_point(k, b, 1.0) - root, b.height));
    return out;
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) i: u32) -> BladeOut {
    return blade_vertex(vi, i);
}

// With the wind colours on (`GrassRenderer::set_wind_colours`), a pipeline of its own: even
// a branch on them here and in the fragment cost lavapipe 6–10% a frame with them off.
struct ColouredOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) world: vec3<f32>,
    @location(3) side: vec3<f32>,
    @location(4) at: vec3<f32>,
    @location(5) look: vec4<f32>,
    // The speed colour of the blade's wind (its cell's).
    @location(6) wind: vec3<f32>,
}

fn coloured_vertex(vi: u32, i: u32) -> ColouredOut {
    let o = blade_vertex(vi, i);
    let w = wind_colour(blade_wind(blades[visible[i]]));
    return ColouredOut(o.clip, o.colour, o.normal, o.world, o.side, o.at, o.look, w);
}

@vertex
fn vs_wind_colours(@builtin(vertex_index) vi: u32, @builtin(instance_index) i: u32) -> ColouredOut {
    return coloured_vertex(vi, i);
}

// The far level, whose blades are one triangle each, drawn as one triangle list without
// instancing: vertex `vi` is corner `vi % 3` of the level's blade `vi / 3`. The same triangles
// in the same order as three-vertex instances, but GPUs shade tiny instances poorly (NVIDIA:
// a warp's vertices come from one instance), and most drawn blades are far ones.
@vertex
fn vs_far(@builtin(vertex_index) vi: u32) -> BladeOut {
    return blade_vertex(vi % 3u, vi / 3u);
}

@vertex
fn vs_far_wind_colours(@builtin(vertex_index) vi: u32) -> ColouredOut {
    return coloured_vertex(vi % 3u, vi / 3u);
}

// How far a blade's normal turns toward its edges: a blade is a shallow trough, not a flat
// card, so its light and sheen change across it.
const ROUNDING: f32 = 0.35;

// The lit blade (`grass::light::blade`) on the side facing the camera, its normal rounded
// across the width; far off, the far field's look in its place (a blade a few pixels tall
// shows the field's mean, not its own shade: no speckle); seen through the haze.
fn lit_blade(colour: vec3<f32>, normal: vec3<f32>, world: vec3<f32>, side: vec3<f32>, at: vec3<f32>, look: vec4<f32>, front: bool) -> vec3<f32> {
    var n = normalize(normal);
    if (!front) {
        n = -n;
    }
    n = normalize(n + (ROUNDING * at.x) * side);
    let to_eye = S.eye.xyz - world;
    let d = length(to_eye);
    let view = to_eye / max(d, 1e-6);
    let own = blade_light(colour, n, view, at.y, at.z);
    return hazed(mix(own, look.rgb, look.a), world);
}

@fragment
fn fs_main(in: BladeOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    return vec4<f32>(encode(lit_blade(in.colour, in.normal, in.world, in.side, in.at, in.look, front)), 1.0);
}

// The lit blade with the wind colours over it at their opacity.
@fragment
fn fs_wind_colours(in: ColouredOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let lit = lit_blade(in.colour, in.normal, in.world, in.side, in.at, in.look, front);
    return vec4<f32>(encode(mix(lit, in.wind, S.wind_colours)), 1.0);
}
