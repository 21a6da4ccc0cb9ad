// Shared by the grass passes (prepended to each by `gpu::grass`): the scene, mirrored by
// `gpu::grass::Scene` (#[repr(C)], bytemuck), the blades (`grass::Blade`) and the CWD
// deformation of `src/grass/cwd.rs` — the CPU twin every function here is tested against.

struct Scene {
    // World to clip space, depth reversed (near 1, far 0; drawn with `Greater`).
    view_proj: mat4x4<f32>,
    // The inverse of the usual-depth one (near 0, far 1): the sky pass's view rays.
    inv_view_proj: mat4x4<f32>,
    // Camera position; w: the simulation time in seconds (the flutter's clock).
    eye: vec4<f32>,
    // Unit vector toward the sun; w: ambient (sky) light.
    sun: vec4<f32>,
    // Wind grid: origin and cell size (metres), cells along x and z.
    origin: vec2<f32>,
    cell: vec2<f32>,
    nx: u32,
    ny: u32,
    blades: u32,
    segments: u32,
    // Eq. 11, eq. 13 and the bend's response (`cwd::WIND_RESPONSE`, `cwd::BEND_MAX`).
    k1: f32,
    k2: f32,
    lambda: f32,
    response: f32,
    bend_max: f32,
    flutter: f32,
    flutter_hz: f32,
    saturation: f32,
    // Eq. 14.
    c1: f32,
    c2: f32,
    m_min: f32,
    m_max: f32,
    // World rectangle (the ground).
    world_min: vec2<f32>,
    world_max: vec2<f32>,
    palettes: u32,
    // 1 when the target stores sRGB (the shader writes linear values then).
    srgb_target: u32,
    // 1: eqs. 12–14 as the paper prints them (no saturation, no length restored) — only for
    // the before/after pictures in docs/GRASS.md.
    literal: u32,
    // Opacity of the map backdrop over the ground (0: no backdrop).
    backdrop: f32,
    // The pushing sphere: centre (xyz) and radius (w; 0: none).
    sphere: vec4<f32>,
    // The trail grid (`grass::trail`): origin and texel size (metres), texels along x and z.
    trail_origin: vec2<f32>,
    trail_cell: vec2<f32>,
    trail_nx: u32,
    trail_ny: u32,
    // 0: the CWD model; 1: the Bezier physics blades.
    model: u32,
    // 1 when the trail holds anything (0: the grass skips reading it).
    trail_on: u32,
    // This frame's step (seconds) and the trail's lifetime.
    dt: f32,
    lifetime: f32,
    // The wind colours (`GrassRenderer::set_wind_colours`): opacity (0: off) and the speed,
    // m/s, at the top of the scale.
    wind_colours: f32,
    wind_scale: f32,
    // Where the map backdrop lies: x0, z0, x1, z1 in metres (`MapBackdrop::placed`).
    backdrop_rect: vec4<f32>,
    // The terrain's heights (`ground`): a grid of cells from `ground_origin`, and the ground
    // mesh's quads along x and z (0: flat ground at y = 0).
    ground_origin: vec2<f32>,
    ground_cell: vec2<f32>,
    ground_nx: u32,
    ground_ny: u32,
    ground_quads: vec2<u32>,
    // Distances (metres) over which the far plane fades into the horizon's colour
    // (`light::haze`'s `fade`).
    fade: vec2<f32>,
    _pad_fade: vec2<f32>,
}

// The far field (`gpu::grass::FarUniform`; `grass::far`): a grid of texels over the world
// holding the grass's look from afar, and what the ground needs to blend to it.
struct Far {
    // Texel grid: origin and texel size (metres), texels along x and z.
    origin: vec2<f32>,
    cell: vec2<f32>,
    nx: u32,
    ny: u32,
    // Bits: 1 the ground shows the far field; 2 distance culling is on.
    flags: u32,
    buckets: u32,
    max_distance: f32,
    // A blade budget's sample threshold (metres; 0: every blade drawn).
    sample_reach: f32,
    // The mean blade.
    height: f32,
    width: f32,
    stiffness: f32,
    // Blades a square metre.
    density: f32,
    // The cull's density thinning (`CullParams::thin_distance`; 0: none).
    thin_distance: f32,
    _pad1: f32,
    // The palettes' mean base and tip colours (linear, the mean tint applied).
    base: vec4<f32>,
    tip: vec4<f32>,
}

// `far::SURROUND_AZIMUTHS`, `far::SURROUND_ELEVATIONS`: the table of the ground beyond the
// level's look by view direction (`grass_far.wgsl` writes it, `grass_ground.wgsl` reads it).
const SURROUND_AZIMUTHS: u32 = 64u;
const SURROUND_ELEVATIONS: u32 = 32u;

// A Bezier blade's control points (`gpu::grass::BezierState`): root, guide, tip.
struct BezierState {
    v0: vec4<f32>,
    v1: vec4<f32>,
    v2: vec4<f32>,
}

struct Blade {
    pos: vec2<f32>,
    facing: f32,
    height: f32,
    width: f32,
    stiffness: f32,
    palette: u32,
    variation: f32,
}

// Per blade, per frame (the deform pass): the wind's push `B·v̂` in the blade's frame
// (side, forward), the length-restoring scale, and eq. 14's wind dimming.
struct Pose {
    push: vec2<f32>,
    scale: f32,
    dim: f32,
}

// Segments of the arc-length estimate (`cwd::LENGTH_SEGMENTS`).
const LENGTH_SEGMENTS: u32 = 16u;
const TAU: f32 = 6.283185307179586;

@group(0) @binding(0) var<storage, read> S: Scene;
@group(0) @binding(1) var<storage, read> blades: array<Blade>;
// The wind grid: cell-centred velocity (x, z), m/s, row-major.
@group(0) @binding(2) var<storage, read> wind: array<vec2<f32>>;
// Per palette: base then tip colour (linear RGB); after the palettes, the speed scale's 256
// steps (linear RGB, `colour::speed_table_linear`) for the wind colours.
@group(0) @binding(3) var<storage, read> palettes: array<vec4<f32>>;
// The trail's remaining life per texel (r32float, `grass::trail`).
@group(0) @binding(4) var trail: texture_2d<f32>;

// The terrain's height at each cell centre of its grid (one 0 for flat ground).
@group(0) @binding(5) var<storage, read> ground_heights: array<f32>;

// The ground's height at world `p`, bilinear between the terrain's cell centres and clamped
// at its edges (0 on flat ground): `sim::terrain::TerrainField::ground_at`.
fn ground(p: vec2<f32>) -> f32 {
    if (S.ground_quads.x == 0u) {
        return 0.0;
    }
    let g = (p - S.ground_origin) / S.ground_cell - vec2<f32>(0.5);
    let hi = vec2<f32>(f32(S.ground_nx - 1u), f32(S.ground_ny - 1u));
    let c = clamp(g, vec2<f32>(0.0), hi);
    let i0 = vec2<u32>(floor(c));
    let i1 = min(i0 + vec2<u32>(1u), vec2<u32>(S.ground_nx - 1u, S.ground_ny - 1u));
    let f = c - floor(c);
    let n = S.ground_nx;
    let a = mix(ground_heights[i0.y * n + i0.x], ground_heights[i0.y * n + i1.x], f.x);
    let b = mix(ground_heights[i1.y * n + i0.x], ground_heights[i1.y * n + i1.x], f.x);
    return mix(a, b, f.y);
}

// Blade `k` of a dispatch of 64-wide workgroups laid out in two dimensions (a dimension holds
// at most 65,535 workgroups: 4.2 M blades).
fn blade_index(wid: vec3<u32>, nwg: vec3<u32>, lid: u32) -> u32 {
    return (wid.y * nwg.x + wid.x) * 64u + lid;
}

// `Trail::life_at`: bilinear between texel centres, clamped at the edges.
fn trail_life(p: vec2<f32>) -> f32 {
    let g = (p - S.trail_origin) / S.trail_cell - vec2<f32>(0.5);
    let g0 = floor(g);
    let f = g - g0;
    let hi = vec2<i32>(i32(S.trail_nx) - 1, i32(S.trail_ny) - 1);
    let i0 = clamp(vec2<i32>(g0), vec2<i32>(0), hi);
    let i1 = clamp(vec2<i32>(g0) + vec2<i32>(1), vec2<i32>(0), hi);
    let a = textureLoad(trail, vec2<i32>(i0.x, i0.y), 0).r * (1.0 - f.x) + textureLoad(trail, vec2<i32>(i1.x, i0.y), 0).r * f.x;
    let b = textureLoad(trail, vec2<i32>(i0.x, i1.y), 0).r * (1.0 - f.x) + textureLoad(trail, vec2<i32>(i1.x, i1.y), 0).r * f.x;
    return a * (1.0 - f.y) + b * f.y;
}

// `Trail::crush_at`: the crush (x) and the direction crushed blades lie in (yz), down the
// trail's gradient or `fallback` where it is flat.
fn trail_crush(p: vec2<f32>, fallback: vec2<f32>) -> vec3<f32> {
    if (S.trail_on == 0u) {
        return vec3<f32>(0.0, fallback);
    }
    let v = clamp(trail_life(p), 0.0, 1.0);
    let c = v * v * (3.0 - 2.0 * v);
    if (c <= 0.0) {
        return vec3<f32>(0.0, fallback);
    }
    let hx = vec2<f32>(S.trail_cell.x, 0.0);
    let hy = vec2<f32>(0.0, S.trail_cell.y);
    let g = vec2<f32>(trail_life(p + hx) - trail_life(p - hx), trail_life(p + hy) - trail_life(p - hy));
    let l = length(g);
    if (l > 1e-4) {
        return vec3<f32>(c, -g / l);
    }
    return vec3<f32>(c, fallback);
}

fn bezier_point(v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>, t: f32) -> vec3<f32> {
    return v0 * ((1.0 - t) * (1.0 - t)) + v1 * (2.0 * (1.0 - t) * t) + v2 * (t * t);
}

// Eq. 1: the blade's wind cell (blades in one cell share its wind).
fn blade_wind(b: Blade) -> vec2<f32> {
    let g = (b.pos - S.origin) / S.cell;
    let i = u32(clamp(g.x, 0.0, f32(S.nx - 1u)));
    let j = u32(clamp(g.y, 0.0, f32(S.ny - 1u)));
    return wind[j * S.nx + i];
}

// The wind bilinear between cell centres, clamped at the grid's edges (the ground's wind
// colours; the blades take their cell's, `blade_wind`).
fn wind_between_cells(p: vec2<f32>) -> vec2<f32> {
    let g = (p - S.origin) / S.cell - vec2<f32>(0.5);
    let hi = vec2<f32>(f32(S.nx - 1u), f32(S.ny - 1u));
    let c = clamp(g, vec2<f32>(0.0), hi);
    let i0 = vec2<u32>(floor(c));
    let i1 = min(i0 + vec2<u32>(1u), vec2<u32>(S.nx - 1u, S.ny - 1u));
    let f = c - floor(c);
    let a = mix(wind[i0.y * S.nx + i0.x], wind[i0.y * S.nx + i1.x], f.x);
    let b = mix(wind[i1.y * S.nx + i0.x], wind[i1.y * S.nx + i1.x], f.x);
    return mix(a, b, f.y);
}

// The map view's speed colour of wind `w` (`colour::speed_rgb` at speed / scale, the same
// step of 256 as `map_common.wgsl`'s `lut_colour`), linear.
fn wind_colour(w: vec2<f32>) -> vec3<f32> {
    let t = clamp(length(w) / S.wind_scale, 0.0, 1.0);
    return palettes[2u * S.palettes + u32(t * 255.0 + 0.5)].rgb;
}

// Forward (facing) and side unit vectors, world (x, z): `cwd::frame`.
fn blade_frame(b: Blade) -> mat2x2<f32> {
    let s = sin(b.facing);
    let c = cos(b.facing);
    return mat2x2<f32>(vec2<f32>(c, s), vec2<f32>(-s, c));
}

// `cwd::FLUTTER_SPREAD`: radians of flutter phase per unit of a blade's variation.
const FLUTTER_SPREAD: f32 = 40.0;

// `cwd::push_with`: the saturated bend with a flutter of relative amplitude `flutter` (`S.flutter`
// for a blade, 0 for the far field's probes: the mean of many blades' phases), toward the
// wind, in the blade's frame.
fn blade_push(b: Blade, w: vec2<f32>, time: f32, flutter: f32) -> vec2<f32> {
    let speed = length(w);
    if (speed <= 0.0) {
        return vec2<f32>(0.0);
    }
    let f = S.response / max(b.stiffness, 1e-3);
    let fr = blade_frame(b);
    let d = w / speed;
    if (S.literal != 0u) {
        return (1.0 - S.lambda) * f * speed * vec2<f32>(dot(d, fr[1]), dot(d, fr[0]));
    }
    let bend = S.bend_max * tanh((1.0 - S.lambda) * f * speed / S.bend_max);
    let phase = b.variation * FLUTTER_SPREAD;
    let hz = S.flutter_hz * (1.0 + 0.25 * b.variation);
    let wave = 1.0 + flutter * (bend / S.bend_max) * sin(TAU * hz * time + phase);
    return bend * wave * vec2<f32>(dot(d, fr[1]), dot(d, fr[0]));
}

// `cwd::bent`: blade-frame (side, up, forward) point at `t` before the length is restored.
fn bent(b: Blade, push: vec2<f32>, t: f32) -> vec3<f32> {
    let h = b.height;
    let y = t * h;
    let p = vec3<f32>(0.0, y - S.k1 * y * y, S.k2 * y * y);
    let r = p.y / h;
    let s = h * r * r;
    return vec3<f32>(p.x + s * push.x, max(p.y - s * length(push), 0.0), p.z + s * push.y);
}

// The bend a fully crushed blade gets (`cwd::CRUSH_BEND`).
const CRUSH_BEND: f32 = 0.92;

// `cwd::crushed`: the wind's push blended with the trail's crush toward world `toward`.
fn blade_crushed(b: Blade, push: vec2<f32>, crush: vec3<f32>) -> vec2<f32> {
    let c = crush.x;
    if (c <= 0.0) {
        return push;
    }
    let fr = blade_frame(b);
    let t = vec2<f32>(dot(crush.yz, fr[1]), dot(crush.yz, fr[0]));
    return (1.0 - c) * push + c * CRUSH_BEND * t;
}

// The deform pass's work for one blade: `cwd::centreline_crushed`'s per-blade part.
fn blade_pose(b: Blade, time: f32) -> Pose {
    return blade_pose_with(b, time, S.flutter);
}

// `blade_pose` with a flutter of relative amplitude `flutter` (0: the far field's steady mean).
fn blade_pose_with(b: Blade, time: f32, flutter: f32) -> Pose {
    let w = blade_wind(b);
    let fr = blade_frame(b);
    let push = blade_crushed(b, blade_push(b, w, time, flutter), trail_crush(b.pos, fr[0]));
    return pose_of(b, push, length(w));
}

// The pose of a blade pushed by `push` in a wind of `speed` m/s: its length restored, eq. 14's
// dimming (`cwd::centreline_crushed`).
fn pose_of(b: Blade, push: vec2<f32>, speed: f32) -> Pose {
    var len = 0.0;
    var prev = vec3<f32>(0.0);
    for (var k = 1u; k <= LENGTH_SEGMENTS; k = k + 1u) {
        let q = bent(b, push, f32(k) / f32(LENGTH_SEGMENTS));
        len = len + length(q - prev);
        prev = q;
    }
    if (S.literal != 0u) {
        return Pose(push, 1.0, S.c1 * speed);
    }
    let dim = S.c1 * S.saturation * tanh(speed / S.saturation);
    return Pose(push, b.height / max(len, 1e-9), dim);
}

// World position of the blade's centreline at `t` (y up): `cwd::centreline`'s points.
fn blade_point(b: Blade, pose: Pose, t: f32) -> vec3<f32> {
    let q = bent(b, pose.push, t) * pose.scale;
    let fr = blade_frame(b);
    let xz = b.pos + q.x * fr[1] + q.z * fr[0];
    return vec3<f32>(xz.x, q.y, xz.y);
}

// Eq. 14 with the saturated wind (`cwd::Point::shade`).
fn blade_shade(height: f32, pose: Pose) -> f32 {
    return clamp(height - pose.dim + S.c2, S.m_min, S.m_max);
}

fn encode(c: vec3<f32>) -> vec3<f32> {
    // Linear → sRGB when the target does not do it.
    if (S.srgb_target != 0u) {
        return c;
    }
    return select(1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055, c * 12.92, c <= vec3<f32>(0.0031308));
}

// `far::MIN_VIEW_SINE`: the shallowest view elevation (its sine) the field's cover counts.
const MIN_VIEW_SINE: f32 = 0.05;

// The light (`grass::light`, its CPU twin, holds what each constant means).
const SKY_ZENITH: vec3<f32> = vec3<f32>(0.20, 0.38, 0.72);
const SKY_HORIZON: vec3<f32> = vec3<f32>(0.62, 0.70, 0.78);
const SUN_GLOW: f32 = 0.35;
const SUN_GLOW_POWER: f32 = 24.0;
const GROUND_MIRROR: vec3<f32> = vec3<f32>(0.05, 0.06, 0.035);
const SHEEN_F0: f32 = 0.2;
const SHEEN_F90: f32 = 0.5;
const SHEEN: f32 = 1.3;
const SHEEN_UPRIGHT: f32 = 0.15;
const SHEEN_GREY: f32 = 0.8;
const LAY_REST: f32 = 0.07;
const SHEEN_TURN: f32 = 0.07;
const SPECULAR_POWER: f32 = 20.0;
const SPECULAR: f32 = 0.5;
const TRANSLUCENCY: f32 = 0.35;
const FORWARD_SCATTER: f32 = 1.5;
const SKY_AT_ROOT: f32 = 0.45;
const HAZE_DENSITY: f32 = 1.0 / 300.0;
const HAZE_HEIGHT: f32 = 20.0;

// `light::sky`: the sky's radiance in unit direction `dir`.
fn sky_colour(dir: vec3<f32>) -> vec3<f32> {
    let l = normalize(S.sun.xyz);
    let up = max(dir.y, 0.0);
    let base = mix(SKY_HORIZON, SKY_ZENITH, sqrt(up));
    return base + vec3<f32>(SUN_GLOW * pow(max(dot(dir, l), 0.0), SUN_GLOW_POWER));
}

// `light::MIRROR_BLUR`.
const MIRROR_BLUR: f32 = 0.15;

// `light::mirrored`: the sky and the ground blurred into each other across the horizon.
fn mirrored(r: vec3<f32>) -> vec3<f32> {
    let x = clamp((r.y + MIRROR_BLUR) / (2.0 * MIRROR_BLUR), 0.0, 1.0);
    return mix(GROUND_MIRROR, sky_colour(r), x * x * (3.0 - 2.0 * x));
}

// `light::haze`: the share of the horizon's colour over a surface at `p` seen from the eye.
fn haze(p: vec3<f32>) -> f32 {
    let e = S.eye.xyz;
    let d = distance(e, p);
    let ye = e.y / HAZE_HEIGHT;
    let yp = p.y / HAZE_HEIGHT;
    var mean = exp(-0.5 * (ye + yp));
    if (abs(ye - yp) > 1e-3) {
        mean = (exp(-yp) - exp(-ye)) / (ye - yp);
    }
    let air = 1.0 - exp(-HAZE_DENSITY * d * mean);
    let x = clamp((d - S.fade.x) / max(S.fade.y - S.fade.x, 1e-3), 0.0, 1.0);
    return max(air, x * x * (3.0 - 2.0 * x));
}

// A surface's lit colour at `p`, seen through the haze.
fn hazed(c: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    return mix(c, SKY_HORIZON, haze(p));
}

// `far::lay`: how far a blade of `height` whose tip stands `tip` from its root lies over.
fn blade_lay(tip: vec3<f32>, height: f32) -> f32 {
    return min(length(tip.xz) / max(height, 1e-6), 1.0);
}

// `light::sheen_turn`: how far a blade laid over by `lay` has turned its glossy face up.
fn sheen_turn(lay: f32) -> f32 {
    let past = max((lay - LAY_REST) / (1.0 - LAY_REST), 0.0);
    return 1.0 - exp(-past / SHEEN_TURN);
}

// `light::blade`: the light on a blade of colour `albedo`, unit normal `n` toward the eye,
// unit `view` toward the eye, at height fraction `t`, of a blade laid over by `lay`.
fn blade_light(albedo: vec3<f32>, n: vec3<f32>, view: vec3<f32>, t0: f32, lay: f32) -> vec3<f32> {
    let l = normalize(S.sun.xyz);
    let a = S.sun.w;
    let t = clamp(t0, 0.0, 1.0);
    let open = SKY_AT_ROOT + (1.0 - SKY_AT_ROOT) * t;
    let d = dot(n, l);
    let toward_sun = max(dot(-view, l), 0.0);
    let ts2 = toward_sun * toward_sun;
    let through = TRANSLUCENCY * max(-d, 0.0) * (1.0 + FORWARD_SCATTER * ts2 * ts2);
    let diffuse = a * (0.6 + 0.4 * n.y) * open + (1.0 - a) * (max(d, 0.0) + through);
    // The glossy face, turned up by the lay (`light::blade`).
    let turn = sheen_turn(lay);
    var m = mix(n, vec3<f32>(0.0, 1.0, 0.0), turn);
    let ml = length(m);
    if (ml > 0.0) {
        m = m / ml;
    }
    let nv = clamp(dot(m, view), 0.0, 1.0);
    let g = 1.0 - nv;
    let fresnel = SHEEN_F0 + (SHEEN_F90 - SHEEN_F0) * (g * g * g * g * g);
    let r = 2.0 * dot(m, view) * m - view;
    var h = l + view;
    let hl = length(h);
    if (hl > 0.0) {
        h = h / hl;
    }
    let highlight = SPECULAR * (1.0 - a) * pow(max(dot(m, h), 0.0), SPECULAR_POWER) * select(0.0, 1.0, dot(m, l) > 0.0);
    let weight = SHEEN_UPRIGHT + (1.0 - SHEEN_UPRIGHT) * turn;
    let c = mirrored(r);
    let grey = mix(c, vec3<f32>(dot(c, vec3<f32>(0.2126, 0.7152, 0.0722))), SHEEN_GREY);
    let sheen = SHEEN * fresnel * open * weight * (grey + vec3<f32>(highlight));
    return albedo * diffuse + sheen;
}
