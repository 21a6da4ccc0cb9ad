// Map view, render: each streak particle's trail as a ribbon of quads 1.6 points wide, fading
// toward its tail and in and out over its life, coloured by the speed at its head.
// CPU twin: `app::view::Streaks::draw`.

@group(1) @binding(0) var<storage, read> stats: array<u32, 4>;
@group(1) @binding(1) var<storage, read> particles: array<Particle>;

struct StreakOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
}

// Vertices per particle: (TRAIL − 1) segments of two triangles.
const SEGMENT_VERTICES: u32 = 6u;

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) k: u32) -> StreakOut {
    let q = particles[k];
    let s = vi / SEGMENT_VERTICES;
    var out: StreakOut;
    out.clip = vec4<f32>(2.0, 2.0, 0.0, 1.0);
    out.colour = vec4<f32>(0.0);
    if (s + 1u >= q.len || q.life <= 0.0) {
        return out; // a degenerate triangle, off screen
    }
    let a = to_clip(q.trail[s]);
    let b = to_clip(q.trail[s + 1u]);
    // Ribbon half-width in clip units, perpendicular to the segment on screen.
    let half_px = 0.8 * V.ppp;
    let d_px = (b.xy - a.xy) * 0.5 * V.viewport_px;
    let len = length(d_px);
    if (len < 1e-4) {
        return out;
    }
    let n_px = vec2<f32>(-d_px.y, d_px.x) / len * half_px;
    let n = n_px / (0.5 * V.viewport_px);
    let corner = array<vec2<f32>, 6>(
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(0.0, 1.0),
        vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0),
    )[vi % SEGMENT_VERTICES];
    let base = mix(a.xy, b.xy, corner.x);
    out.clip = vec4<f32>(base + n * corner.y, 0.0, 1.0);
    let fade = clamp(1.0 - abs(2.0 * q.age / q.life - 1.0), 0.0, 1.0);
    let t = f32(s + 1u) / f32(q.len);
    let alpha = t * fade * (230.0 / 255.0);
    let scale = scale_of(vec3<u32>(stats[0], stats[1], stats[2]), 0u);
    let head = length(sample_velocity(q.trail[q.len - 1u]));
    out.colour = output(speed_colour(sqrt(head / scale)), alpha);
    return out;
}

@fragment
fn fs_main(in: StreakOut) -> @location(0) vec4<f32> {
    return in.colour;
}
