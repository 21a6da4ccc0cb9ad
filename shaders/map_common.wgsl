// Shared by the editor's map-view passes (prepended to each by `gpu::mapview`): the view,
// mirrored by `gpu::mapview::View` (#[repr(C)], bytemuck), the wind field read where the
// solver keeps it (its u, v and p storage buffers, on the CPU solver's staggered MAC layout),
// and the colour scales of `src/colour.rs` as a lookup table.
//
// World (x, z) maps to the map viewport as the editor's `Camera` does: the camera centre at the
// viewport centre, `zoom` points per metre, +z down the screen.

struct View {
    // World point at the viewport centre, metres.
    center: vec2<f32>,
    // Viewport size in physical pixels.
    viewport_px: vec2<f32>,
    // Grid origin (minimum corner) and cell size, metres.
    origin: vec2<f32>,
    cell: vec2<f32>,
    // The world rectangle (the grid's), metres.
    world_min: vec2<f32>,
    world_max: vec2<f32>,
    // Centre of the first glyph, metres.
    lattice_origin: vec2<f32>,
    // Points per metre (the camera's zoom) and physical pixels per point.
    zoom: f32,
    ppp: f32,
    // Metres between glyphs.
    lattice_step: f32,
    // Opacity of the colour map (the views over which streaks or glyphs are drawn are dimmer).
    alpha: f32,
    // Simulated seconds to advance the streaks by this frame (0 while paused).
    dt: f32,
    nx: u32,
    ny: u32,
    // 0 speed, 1 curl, 2 pressure: the value the colour map shows.
    layer: u32,
    frame: u32,
    lattice_cols: u32,
    particles: u32,
    // 1 when the render target stores sRGB (the shader then writes linear values).
    srgb_target: u32,
    // The speed colours' top, m/s (the View menu's fixed speed scale; 0: the stats pass's
    // peak).
    speed_scale: f32,
    _pad: f32,
}

// A streak particle: its trail (oldest first, `len` points), age and lifetime in seconds.
struct Particle {
    trail: array<vec2<f32>, 16>,
    age: f32,
    life: f32,
    len: u32,
    seed: u32,
}

// Points a streak's trail keeps (the CPU view's `TRAIL`).
const TRAIL: u32 = 14u;

@group(0) @binding(0) var<storage, read> V: View;
@group(0) @binding(1) var<storage, read> u: array<f32>;
@group(0) @binding(2) var<storage, read> v: array<f32>;
@group(0) @binding(3) var<storage, read> p: array<f32>;
// 256 speed colours then 256 signed colours, RGBA8 packed.
@group(0) @binding(4) var<storage, read> lut: array<u32>;

// Velocity at the centre of cell (i, j): the mean of its faces.
fn cell_velocity(i: u32, j: u32) -> vec2<f32> {
    let w = V.nx + 1u;
    return vec2<f32>(
        0.5 * (u[j * w + i] + u[j * w + i + 1u]),
        0.5 * (v[j * V.nx + i] + v[(j + 1u) * V.nx + i]),
    );
}

// Vorticity ∂v/∂x − ∂u/∂z at the centre of cell (i, j), central differences between cell
// centres (one-sided at the edges).
fn cell_curl(i: u32, j: u32) -> f32 {
    let il = select(i - 1u, 0u, i == 0u);
    let ir = min(i + 1u, V.nx - 1u);
    let jb = select(j - 1u, 0u, j == 0u);
    let jt = min(j + 1u, V.ny - 1u);
    let dvdx = (cell_velocity(ir, j).y - cell_velocity(il, j).y) / (f32(max(ir - il, 1u)) * V.cell.x);
    let dudz = (cell_velocity(i, jt).x - cell_velocity(i, jb).x) / (f32(max(jt - jb, 1u)) * V.cell.y);
    return dvdx - dudz;
}

// Continuous cell coordinates of world point `w` (cell centres at integers), clamped to the
// grid, and the lower corner cell.
fn cell_coords(w: vec2<f32>) -> vec2<f32> {
    let g = (w - V.origin) / V.cell - vec2<f32>(0.5);
    return clamp(g, vec2<f32>(0.0), vec2<f32>(f32(V.nx - 1u), f32(V.ny - 1u)));
}

// Velocity at world point `w`, bilinear between cell centres (as `Snapshot::sample`).
fn sample_velocity(w: vec2<f32>) -> vec2<f32> {
    let g = cell_coords(w);
    let i0 = u32(g.x);
    let j0 = u32(g.y);
    let i1 = min(i0 + 1u, V.nx - 1u);
    let j1 = min(j0 + 1u, V.ny - 1u);
    let f = g - vec2<f32>(f32(i0), f32(j0));
    let a = mix(cell_velocity(i0, j0), cell_velocity(i1, j0), f.x);
    let b = mix(cell_velocity(i0, j1), cell_velocity(i1, j1), f.x);
    return mix(a, b, f.y);
}

// Pressure and curl at world point `w`, bilinear between cell centres.
fn sample_pressure(w: vec2<f32>) -> f32 {
    let g = cell_coords(w);
    let i0 = u32(g.x);
    let j0 = u32(g.y);
    let i1 = min(i0 + 1u, V.nx - 1u);
    let j1 = min(j0 + 1u, V.ny - 1u);
    let f = g - vec2<f32>(f32(i0), f32(j0));
    let a = mix(p[j0 * V.nx + i0], p[j0 * V.nx + i1], f.x);
    let b = mix(p[j1 * V.nx + i0], p[j1 * V.nx + i1], f.x);
    return mix(a, b, f.y);
}

fn sample_curl(w: vec2<f32>) -> f32 {
    let g = cell_coords(w);
    let i0 = u32(g.x);
    let j0 = u32(g.y);
    let i1 = min(i0 + 1u, V.nx - 1u);
    let j1 = min(j0 + 1u, V.ny - 1u);
    let f = g - vec2<f32>(f32(i0), f32(j0));
    let a = mix(cell_curl(i0, j0), cell_curl(i1, j0), f.x);
    let b = mix(cell_curl(i0, j1), cell_curl(i1, j1), f.x);
    return mix(a, b, f.y);
}

// World point → clip space of the map viewport.
fn to_clip(w: vec2<f32>) -> vec4<f32> {
    let px = (w - V.center) * V.zoom * V.ppp;
    let ndc = vec2<f32>(px.x, -px.y) / (0.5 * V.viewport_px);
    return vec4<f32>(ndc, 0.0, 1.0);
}

// Colour `k` (0..255) of table `table` (0 speed, 1 signed), as written by the editor's
// painter (gamma-encoded 0..1).
fn lut_colour(table: u32, t: f32) -> vec3<f32> {
    let k = u32(clamp(t, 0.0, 1.0) * 255.0 + 0.5);
    return unpack4x8unorm(lut[table * 256u + k]).rgb;
}

fn speed_colour(t: f32) -> vec3<f32> {
    return lut_colour(0u, t);
}

// Diverging colour for `t` in [-1, 1].
fn signed_colour(t: f32) -> vec3<f32> {
    return lut_colour(1u, 0.5 + 0.5 * t);
}

// The premultiplied colour the pass writes, encoded for the target.
fn output(rgb: vec3<f32>, alpha: f32) -> vec4<f32> {
    var c = rgb;
    if (V.srgb_target != 0u) {
        c = select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
    }
    return vec4<f32>(c * alpha, alpha);
}

// The top of a layer's colour scale: for speed the fixed scale where one is set, else from
// the stats the stats pass gathers (as f32 bit patterns: peak speed, |curl|, |pressure|).
fn scale_of(stats: vec3<u32>, layer: u32) -> f32 {
    if (layer == 0u) {
        if (V.speed_scale > 0.0) {
            return V.speed_scale;
        }
        return max(bitcast<f32>(stats.x), 1.0);
    }
    if (layer == 1u) {
        return max(bitcast<f32>(stats.y), 1e-6);
    }
    return max(bitcast<f32>(stats.z), 1e-6);
}

// A pseudo-random number in [0, 1) from a seed (PCG hash).
fn hash01(seed: u32) -> f32 {
    var s = seed * 747796405u + 2891336453u;
    s = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    s = (s >> 22u) ^ s;
    return f32(s >> 8u) / 16777216.0;
}
