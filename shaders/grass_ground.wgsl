// Grass, render: the ground under the blades — the world rectangle at y = 0 (or the terrain, a
// mesh of `S.ground_quads` quads at its heights), a soil colour
// darkened under the grass or, where the layout has a map backdrop, the backdrop image laid
// over it at its opacity; lit by the same sun and sky as the blades. Where the renderer draws
// fewer blades than the field holds (distance culling, a blade budget), the ground takes the
// far field's look (`grass_far.wgsl`) by the share of coverage the blades no longer give.
// With the wind colours on (`fs_wind_colours`), the map view's speed colour of the wind there
// goes over it all.

@group(1) @binding(0) var<storage, read> F: Far;
@group(1) @binding(1) var far_image: texture_2d<f32>;
@group(1) @binding(2) var far_sampler: sampler;
@group(2) @binding(0) var backdrop_image: texture_2d<f32>;
@group(2) @binding(1) var backdrop_sampler: sampler;

struct GroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) world: vec2<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) k: u32) -> GroundOut {
    let corner = array<vec2<f32>, 6>(
        vec2<f32>(0.0, 0.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0),
        vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 1.0),
    )[k % 6u];
    // Quad q of a qx × qz mesh (one quad over flat ground).
    let qx = max(S.ground_quads.x, 1u);
    let qz = max(S.ground_quads.y, 1u);
    let q = k / 6u;
    let c = (vec2<f32>(f32(q % qx), f32(q / qx)) + corner) / vec2<f32>(f32(qx), f32(qz));
    let w = mix(S.world_min, S.world_max, c);
    return GroundOut(S.view_proj * vec4<f32>(w.x, ground(w), w.y, 1.0), c, w);
}

// The ground's lit colour, the far field blended in.
fn ground_colour(in: GroundOut) -> vec3<f32> {
    let soil = palettes[0].rgb * 0.55 + vec3<f32>(0.035, 0.028, 0.015);
    // The image is sRGB; the texture view decodes it to linear.
    // Where the layout places the picture; soil outside it.
    let r = S.backdrop_rect;
    let buv = (in.world - r.xy) / (r.zw - r.xy);
    let map = textureSample(backdrop_image, backdrop_sampler, buv).rgb;
    let inside = all(buv >= vec2<f32>(0.0)) && all(buv <= vec2<f32>(1.0));
    let surface = mix(soil, map, select(0.0, clamp(S.backdrop, 0.0, 1.0), inside));
    // The far field, bilinear between texel centres and clamped at the edges (the sampler's).
    let far_uv = (in.world - F.origin) / (F.cell * vec2<f32>(f32(F.nx), f32(F.ny)));
    let far = textureSample(far_image, far_sampler, far_uv);
    let l = normalize(S.sun.xyz);
    // The terrain's normal from its heights a cell apart (straight up over flat ground).
    var n = vec3<f32>(0.0, 1.0, 0.0);
    if (S.ground_quads.x != 0u) {
        let e = S.ground_cell;
        let dx = (ground(in.world + vec2<f32>(e.x, 0.0)) - ground(in.world - vec2<f32>(e.x, 0.0))) / (2.0 * e.x);
        let dz = (ground(in.world + vec2<f32>(0.0, e.y)) - ground(in.world - vec2<f32>(0.0, e.y))) / (2.0 * e.y);
        n = normalize(vec3<f32>(-dx, 1.0, -dz));
    }
    let light = S.sun.w + (1.0 - S.sun.w) * max(dot(n, l), 0.0);
    var colour = surface * light;
    if ((F.flags & 1u) != 0u) {
        // rgb: the blades from afar, lit; a: how much of the ground they take here.
        colour = mix(colour, far.rgb, clamp(far.a, 0.0, 1.0));
    }
    return colour;
}

@fragment
fn fs_main(in: GroundOut) -> @location(0) vec4<f32> {
    return vec4<f32>(encode(ground_colour(in)), 1.0);
}

// With the wind colours on, a pipeline of its own (`GrassRenderer::set_wind_colours`): the
// speed colour of the wind here, bilinear between cell centres, over the lit ground at their
// opacity.
@fragment
fn fs_wind_colours(in: GroundOut) -> @location(0) vec4<f32> {
    let w = wind_colour(wind_between_cells(in.world));
    return vec4<f32>(encode(mix(ground_colour(in), w, S.wind_colours)), 1.0);
}
