// Map view, render: arrow glyphs on a regular lattice (fixed spacing on screen), each
// pointing downwind with a length growing as the square root of the speed; calm points get
// none. CPU twin: `app::view::draw_glyphs`.

@group(1) @binding(0) var<storage, read> stats: array<u32, 4>;

struct GlyphOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
}

// Vertices per glyph: the shaft (two triangles) and the head (one).
const GLYPH_VERTICES: u32 = 9u;

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) k: u32) -> GlyphOut {
    var out: GlyphOut;
    out.clip = vec4<f32>(2.0, 2.0, 0.0, 1.0);
    out.colour = vec4<f32>(0.0);
    let cols = max(V.lattice_cols, 1u);
    let c = V.lattice_origin + vec2<f32>(f32(k % cols), f32(k / cols)) * V.lattice_step;
    let vel = sample_velocity(c);
    let s = length(vel);
    let scale = scale_of(vec3<u32>(stats[0], stats[1], stats[2]), 0u);
    if (s <= scale * 0.02) {
        return out;
    }
    // Sizes in points (as the CPU view's `draw_arrow` with width 1.5), then metres.
    let m_per_pt = 1.0 / V.zoom;
    let len = V.lattice_step * 0.9 * sqrt(s / scale);
    let dir = vel / s;
    let side = vec2<f32>(-dir.y, dir.x);
    let tail = c - dir * (len * 0.5);
    let tip = c + dir * (len * 0.5);
    let head = min((1.5 * 2.8 + 6.0) * m_per_pt, len * 0.6);
    let base = tip - dir * head;
    let half_w = 0.75 * m_per_pt;
    var w: vec2<f32>;
    switch vi {
        case 0u: { w = tail - side * half_w; }
        case 1u: { w = base - side * half_w; }
        case 2u: { w = tail + side * half_w; }
        case 3u: { w = base - side * half_w; }
        case 4u: { w = base + side * half_w; }
        case 5u: { w = tail + side * half_w; }
        case 6u: { w = tip; }
        case 7u: { w = base + side * (head * 0.55); }
        default: { w = base - side * (head * 0.55); }
    }
    out.clip = to_clip(w);
    out.colour = output(speed_colour(s / scale), 1.0);
    return out;
}

@fragment
fn fs_main(in: GlyphOut) -> @location(0) vec4<f32> {
    return in.colour;
}
