// Grass, render: the ground under the blades — the world rectangle at y = 0 (or the terrain, a
// mesh of `S.ground_quads` quads at its heights), a soil colour
// darkened under the grass or, where the layout has a map backdrop, the backdrop image laid
// over it at its opacity; lit by the same sun and sky as the blades. Where the renderer draws
// fewer blades than the field holds (distance culling, a blade budget), the ground takes the
// far field's look (`grass_far.wgsl`) by the share of coverage the blades no longer give.
// With the wind colours on (`fs_wind_colours`), the map view's speed colour of the wind there
// goes over it all. Beyond the level the ground runs on to the horizon as the
// field's look in the wind at the level's edge along each view (`far::surround_at`, drawn by `vs_main` after the level's quads), and everything fades into the sky through the haze.

@group(1) @binding(0) var<storage, read> F: Far;
@group(1) @binding(1) var far_image: texture_2d<f32>;
@group(1) @binding(2) var far_sampler: sampler;
@group(1) @binding(3) var backdrop_image: texture_2d<f32>;
@group(1) @binding(4) var backdrop_sampler: sampler;
@group(1) @binding(5) var surround_table: texture_2d<f32>;
// The far texels' density shares (`far::density_shares`): none on a road.
@group(1) @binding(6) var shares: texture_2d<f32>;

// `far::surround_at`: the field's look along the view `v` (toward the eye) from the
// table `grass_far.wgsl` writes — bilinear between texel centres, the azimuth wrapping
// round, the elevation clamped.
fn surround_at(v: vec3<f32>) -> vec4<f32> {
    let na = i32(SURROUND_AZIMUTHS);
    let ne = SURROUND_ELEVATIONS;
    let x = (atan2(v.z, v.x) / TAU + 0.5) * f32(na) - 0.5;
    let y = clamp(v.y, 0.0, 1.0) * f32(ne - 1u);
    let x0 = floor(x);
    let y0 = min(floor(y), f32(ne - 2u));
    let fx = x - x0;
    let fy = y - y0;
    let i0 = ((i32(x0) % na) + na) % na;
    let i1 = (i0 + 1) % na;
    let j0 = i32(y0);
    let a = mix(textureLoad(surround_table, vec2<i32>(i0, j0), 0), textureLoad(surround_table, vec2<i32>(i1, j0), 0), fx);
    let b = mix(textureLoad(surround_table, vec2<i32>(i0, j0 + 1), 0), textureLoad(surround_table, vec2<i32>(i1, j0 + 1), 0), fx);
    return mix(a, b, fy);
}

struct GroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) world: vec2<f32>,
    @location(2) height: f32,
}

const CORNERS: array<vec2<f32>, 6> = array<vec2<f32>, 6>(
    vec2<f32>(0.0, 0.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0),
    vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 1.0),
);

fn ground_vertex(w: vec2<f32>, c: vec2<f32>) -> GroundOut {
    let y = ground(w);
    return GroundOut(S.view_proj * vec4<f32>(w.x, y, w.y, 1.0), c, w, y);
}

// Quad q of a qx × qz mesh over the level (one quad over flat ground), then the quads of the
// ring beyond it (`surround_vertex`).
@vertex
fn vs_main(@builtin(vertex_index) k: u32) -> GroundOut {
    let corner = CORNERS[k % 6u];
    let qx = max(S.ground_quads.x, 1u);
    let qz = max(S.ground_quads.y, 1u);
    let q = k / 6u;
    if (q >= qx * qz) {
        return surround_vertex(k - 6u * qx * qz);
    }
    let c = (vec2<f32>(f32(q % qx), f32(q / qx)) + corner) / vec2<f32>(f32(qx), f32(qz));
    let w = mix(S.world_min, S.world_max, c);
    return ground_vertex(w, c);
}

// One of a grid line's positions along an axis of `q` quads from `lo` to `hi`, with one more
// line `reach` beyond each end: line 0 is `lo − reach`, lines 1..q+1 the mesh's, q+2 `hi + reach`.
fn ring_line(a: u32, q: u32, lo: f32, hi: f32, reach: f32) -> f32 {
    if (a == 0u) {
        return lo - reach;
    }
    if (a > q + 1u) {
        return hi + reach;
    }
    return mix(lo, hi, f32(a - 1u) / f32(q));
}

// The ground beyond the level: the ring of quads around the mesh's qx × qz, out past the far
// plane — a row of qx + 2 quads on each side along x, and one at each end of every row
// between. Its inner edge has the mesh's vertices (their heights), its outer edge those
// heights carried outward (`ground` clamps at the terrain's edge), so no crack shows.
fn surround_vertex(k: u32) -> GroundOut {
    let qx = max(S.ground_quads.x, 1u);
    let qz = max(S.ground_quads.y, 1u);
    let q = k / 6u;
    var cell = vec2<u32>(0u, 0u);
    if (q < qx + 2u) {
        cell = vec2<u32>(q, 0u);
    } else if (q < 2u * (qx + 2u)) {
        cell = vec2<u32>(q - (qx + 2u), qz + 1u);
    } else {
        let r = q - 2u * (qx + 2u);
        cell = vec2<u32>(select(0u, qx + 1u, (r & 1u) == 1u), 1u + r / 2u);
    }
    let a = cell + vec2<u32>(CORNERS[k % 6u]);
    let reach = 2.0 * S.fade.y;
    let w = vec2<f32>(
        ring_line(a.x, qx, S.world_min.x, S.world_max.x, reach),
        ring_line(a.y, qz, S.world_min.y, S.world_max.y, reach),
    );
    return ground_vertex(w, (w - S.world_min) / (S.world_max - S.world_min));
}

// The ground's lit colour, the far field blended in.
// `far::EARTH`.
const EARTH: vec3<f32> = vec3<f32>(0.095, 0.08, 0.06);

fn ground_colour(in: GroundOut) -> vec3<f32> {
    // The far field, bilinear between texel centres and clamped at the edges (the sampler's).
    let far_uv = (in.world - F.origin) / (F.cell * vec2<f32>(f32(F.nx), f32(F.ny)));
    let far = textureSample(far_image, far_sampler, far_uv);
    // How much of the layout's density grows here (`far::density_shares`): none on a road.
    let share = textureSample(shares, far_sampler, far_uv).r;
    // `far::canopy_share`: the lower canopy's share, thinned in a sparse field.
    let canopy = share * min(max(F.density, 0.0) / CANOPY_FULL_DENSITY, 1.0);
    // `far::bare_ground`: the grass's darkened colour under it, bare earth where none grows.
    let soil = mix(EARTH, palettes[0].rgb * 0.55 + vec3<f32>(0.035, 0.028, 0.015), share);
    // The image is sRGB; the texture view decodes it to linear.
    // Where the layout places the picture; soil outside it.
    let r = S.backdrop_rect;
    let buv = (in.world - r.xy) / (r.zw - r.xy);
    let map = textureSample(backdrop_image, backdrop_sampler, buv).rgb;
    let inside = all(buv >= vec2<f32>(0.0)) && all(buv <= vec2<f32>(1.0));
    let surface = mix(soil, map, select(0.0, clamp(S.backdrop, 0.0, 1.0), inside));
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
    let pos = vec3<f32>(in.world.x, in.height, in.world.y);
    if ((F.flags & 1u) != 0u) {
        // Where the map shows, it stays the ground; elsewhere the lower canopy covers it.
        let shown = select(0.0, clamp(S.backdrop, 0.0, 1.0), inside);
        if (outside_level(in.world)) {
            // The field beyond the level, as seen along this view: it hides the more
            // ground the lower the view.
            let beyond = surround_at(normalize(S.eye.xyz - pos));
            let thin = min(max(F.density, 0.0) / CANOPY_FULL_DENSITY, 1.0);
            colour = far_ground(colour, beyond.rgb, clamp(beyond.a, 0.0, 1.0), shown, thin);
        } else {
            // rgb: the blades from afar, lit; a: how much of the ground they take here.
            colour = far_ground(colour, far.rgb, clamp(far.a, 0.0, 1.0), shown, canopy);
        }
    }
    return hazed(colour, pos);
}


// `far::UNDERSTOREY`, `far::UNDERSTOREY_SHADE`, `far::MAP_THROUGH_CANOPY`,
// `far::CANOPY_FULL_DENSITY`.
const UNDERSTOREY: f32 = 0.85;
const CANOPY_FULL_DENSITY: f32 = 10.0;
const UNDERSTOREY_SHADE: f32 = 0.6;
const MAP_THROUGH_CANOPY: f32 = 0.5;

// `far::ground`: the lit ground `lit` under a field whose look from afar is `look`: the lower
// canopy (the look, shaded) over the share of it where grass grows (`share`), less where the
// map shows (`shown`), then the look itself over the share `take` the drawn blades leave to it.
fn far_ground(lit: vec3<f32>, look: vec3<f32>, take: f32, shown: f32, share: f32) -> vec3<f32> {
    let canopy = UNDERSTOREY * share * (1.0 - MAP_THROUGH_CANOPY * shown);
    let under = mix(lit, look * UNDERSTOREY_SHADE, canopy);
    return mix(under, look, take);
}

fn outside_level(p: vec2<f32>) -> bool {
    return any(p < S.world_min) || any(p > S.world_max);
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
    // Beyond the level there is no wind to show.
    let opacity = select(S.wind_colours, 0.0, outside_level(in.world));
    return vec4<f32>(encode(mix(ground_colour(in), w, opacity)), 1.0);
}
