// Map view, render: the colour map over the world rectangle — speed, curl or pressure, each
// pixel from the field bilinear between cell centres, normalised by the stats pass's peaks.
// CPU twin: `app::view::field_image` (one texel per cell, drawn with linear filtering).

@group(1) @binding(0) var<storage, read> stats: array<u32, 4>;

struct FieldOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec2<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) k: u32) -> FieldOut {
    // Two triangles over the world rectangle.
    let corner = array<vec2<f32>, 6>(
        vec2<f32>(0.0, 0.0), vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0),
        vec2<f32>(1.0, 0.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0),
    );
    let w = mix(V.world_min, V.world_max, corner[k]);
    return FieldOut(to_clip(w), w);
}

@fragment
fn fs_main(in: FieldOut) -> @location(0) vec4<f32> {
    let scale = scale_of(vec3<u32>(stats[0], stats[1], stats[2]), V.layer);
    if (V.layer == 1u) {
        return output(signed_colour(sample_curl(in.world) / scale), 1.0);
    }
    if (V.layer == 2u) {
        return output(signed_colour(sample_pressure(in.world) / scale), 1.0);
    }
    let s = length(sample_velocity(in.world));
    // The CPU view dims the colour by its opacity and then blends it with that opacity again.
    return output(speed_colour(s / scale) * V.alpha, V.alpha);
}
