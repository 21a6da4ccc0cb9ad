// Grass, compute: the far field — per texel of a grid over the world, the blades' look from
// afar (rgb, linear and lit) and how much of the ground the ground pass covers with it (a):
// the share of the ground the field hides along the line of sight, times the share of the
// field's blades the renderer does not draw at the texel's distance from the eye. So a view
// of the whole world, where every blade is culled, shows its grass and its wind, and near
// blades stand on plain ground. CPU twin: `grass::far::texel` and `grass::far::cover`.
// `surround`: the table of the field's look by view direction, in the wind at the level's
// edge, that the ground beyond the level takes (CPU twin: `grass::far::surround_table`).

@group(1) @binding(0) var<storage, read> F: Far;
@group(1) @binding(1) var far: texture_storage_2d<rgba16float, write>;
@group(1) @binding(2) var surround_table: texture_storage_2d<rgba16float, write>;
// Each texel's share of the layout's density (`far::density_shares`).
@group(1) @binding(3) var shares: texture_2d<f32>;

// `far::SURROUND_EYE`.
const SURROUND_EYE: f32 = 1.0e4;

// `far::PROBES`, `far::POINTS`.
const PROBES: u32 = 4u;
const POINTS: u32 = 4u;

fn unit_or_zero(v: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    if (l > 0.0) {
        return v / l;
    }
    return v;
}


// `far::texel`: the mean probe blades at `pos`, bent in their wind cell without flutter (the
// mean of many blades at their own phases; in the wind `w`, uncrushed, when `still`), each
// segment's colour weighted by the area it shows the eye at `eye` (rgb), and the share of
// the ground they hide (a).
fn far_texel(pos: vec2<f32>, eye: vec3<f32>, still: bool, w: vec2<f32>) -> vec4<f32> {
    var sum = vec3<f32>(0.0);
    var plain = vec3<f32>(0.0);
    var weights = 0.0;
    var depth = 0.0;
    for (var m = 0u; m < PROBES; m = m + 1u) {
        let facing = TAU * (f32(m) + 0.5) / f32(PROBES);
        let b = Blade(pos, facing, F.height, F.width, F.stiffness, 0u, 0.0);
        var pose: Pose;
        if (still) {
            pose = pose_of(b, blade_push(b, w, S.eye.w, 0.0), length(w));
        } else {
            pose = blade_pose_with(b, S.eye.w, 0.0);
        }
        let fr = blade_frame(b);
        let side = vec3<f32>(fr[1].x, 0.0, fr[1].y);
        var p0 = blade_point(b, pose, 0.0);
        let laid = blade_lay(blade_point(b, pose, 1.0) - p0, b.height);
        for (var s = 0u; s < POINTS; s = s + 1u) {
            let p1 = blade_point(b, pose, f32(s + 1u) / f32(POINTS));
            let t = (f32(s) + 0.5) / f32(POINTS);
            let ahead = p1 - p0;
            var n = unit_or_zero(cross(side, ahead));
            let view = unit_or_zero(eye - 0.5 * (p0 + p1));
            let toward = dot(n, view);
            if (toward < 0.0) {
                n = -n;
            }
            let shade = 0.5 * (blade_shade(p0.y, pose) + blade_shade(p1.y, pose));
            let colour = blade_light(mix(F.base.rgb, F.tip.rgb, t) * shade, n, view, t, laid);
            let w = (1.0 - pow(t, 1.4)) * length(ahead) * abs(toward);
            sum = sum + colour * w;
            plain = plain + colour;
            weights = weights + w;
            depth = depth + w * F.width / max(view.y, MIN_VIEW_SINE);
            p0 = p1;
        }
    }
    var colour = plain / f32(PROBES * POINTS);
    if (weights > 1e-12) {
        colour = sum / weights;
    }
    return vec4<f32>(colour, 1.0 - exp(-max(F.density, 0.0) * depth / f32(PROBES)));
}

// `far::THIN_DRAWS`.
const THIN_DRAWS: u32 = 16u;

// `far::cover`: the share of the field's coverage drawn as blades at distance `d`.
fn far_cover(d0: f32) -> f32 {
    let d = max(d0, 0.0);
    var culled = 1.0;
    if ((F.flags & 2u) != 0u) {
        let n = max(F.buckets, 1u);
        let top = max(F.max_distance, 1e-3);
        let thin = F.thin_distance;
        var draws = 1u;
        if (thin > 0.0) {
            draws = THIN_DRAWS;
        }
        var kept = 0.0;
        for (var b = 0u; b < n; b = b + 1u) {
            let bucket = top * (1.0 - f32(b) / f32(n));
            for (var j = 0u; j < draws; j = j + 1u) {
                var r = bucket;
                if (thin > 0.0) {
                    r = min(bucket, thin / sqrt((f32(j) + 0.5) / f32(draws)));
                }
                let x = clamp((r - d) / (0.2 * r), 0.0, 1.0);
                kept = kept + x * x * (3.0 - 2.0 * x);
            }
        }
        // `cull::kept_share`.
        var share = max(1.0 - d / top, 0.0);
        if (thin > 0.0 && d > thin) {
            share = share * (thin / d) * (thin / d);
        }
        culled = kept / f32(n * draws) / max(share, 1.0 / 3.0);
    }
    var sampled = 1.0;
    if (F.sample_reach > 0.0 && d > 0.0) {
        let q = F.sample_reach / d;
        sampled = min(min(q * q, 1.0) * 2.5, 1.0);
    }
    return clamp(culled * sampled, 0.0, 1.0);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= F.nx || id.y >= F.ny) {
        return;
    }
    let pos = F.origin + (vec2<f32>(id.xy) + vec2<f32>(0.5)) * F.cell;
    let d = distance(vec3<f32>(pos.x, ground(pos), pos.y), S.eye.xyz);
    // The pass runs only while the ground shows the far field (`flags & 1`).
    let look = far_texel(pos, S.eye.xyz, false, vec2<f32>(0.0));
    // `far::thinned`: where only a share of the density grows (a road, a pond: none), the
    // field hides that much less of the ground.
    let share = textureLoad(shares, vec2<i32>(id.xy), 0).r;
    let hidden = 1.0 - pow(max(1.0 - look.a, 0.0), share);
    textureStore(far, vec2<i32>(id.xy), vec4<f32>(look.rgb, hidden * (1.0 - far_cover(d))));
}

// `far::surround_direction`: the view direction at the centre of the table's texel `id`.
fn surround_direction(id: vec2<u32>) -> vec3<f32> {
    let a = TAU * ((f32(id.x) + 0.5) / f32(SURROUND_AZIMUTHS) - 0.5);
    let s = f32(id.y) / f32(SURROUND_ELEVATIONS - 1u);
    let c = sqrt(max(1.0 - s * s, 0.0));
    return vec3<f32>(c * cos(a), s, c * sin(a));
}

// `far::border_cells`: cells on the border of the wind grid, each once.
fn border_cells(nx: u32, ny: u32) -> u32 {
    if (nx == 0u || ny == 0u) {
        return 0u;
    }
    let side = select(1u, 2u, nx > 1u);
    return nx + select(0u, nx, ny > 1u) + select(0u, (ny - 2u) * side, ny > 2u);
}

// `far::border_cell`: the index in the wind grid of its `k`th border cell.
fn border_cell(k0: u32, nx: u32, ny: u32) -> u32 {
    if (k0 < nx) {
        return k0;
    }
    var k = k0 - nx;
    if (ny > 1u) {
        if (k < nx) {
            return (ny - 1u) * nx + k;
        }
        k = k - nx;
    }
    let side = select(1u, 2u, nx > 1u);
    let i = select(nx - 1u, 0u, k % side == 0u);
    return (1u + k / side) * nx + i;
}

// `far::edge_wind`: the mean wind of the border cells, those over twice the border's mean
// speed left out (an arrow's jet leaving the level is not the world's weather).
fn edge_wind() -> vec2<f32> {
    let n = border_cells(S.nx, S.ny);
    if (n == 0u) {
        return vec2<f32>(0.0);
    }
    var speed = 0.0;
    for (var k = 0u; k < n; k = k + 1u) {
        speed = speed + length(wind[border_cell(k, S.nx, S.ny)]);
    }
    let limit = 2.0 * speed / f32(n);
    var sum = vec2<f32>(0.0);
    var count = 0.0;
    for (var k = 0u; k < n; k = k + 1u) {
        let w = wind[border_cell(k, S.nx, S.ny)];
        if (length(w) <= limit) {
            sum = sum + w;
            count = count + 1.0;
        }
    }
    if (count == 0.0) {
        return vec2<f32>(0.0);
    }
    return sum / count;
}

// The edge wind, walked once a workgroup rather than once an entry.
var<workgroup> surround_wind: vec2<f32>;

// `far::surround_table`: the field's look in the wind at the level's edge, seen along each
// of the table's directions.
@compute @workgroup_size(8, 8)
fn surround(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    if (lid == 0u) {
        surround_wind = edge_wind();
    }
    workgroupBarrier();
    if (id.x >= SURROUND_AZIMUTHS || id.y >= SURROUND_ELEVATIONS) {
        return;
    }
    let eye = surround_direction(id.xy) * SURROUND_EYE;
    let look = far_texel(vec2<f32>(0.0), eye, true, surround_wind);
    textureStore(surround_table, vec2<i32>(id.xy), look);
}
