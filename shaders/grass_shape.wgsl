// Shared by the grass passes that need a blade's deformed curve whatever the model (prepended
// after `grass_common.wgsl` to `grass_cull.wgsl` and `grass_blades.wgsl`): the CWD poses and
// the Bezier states, read-only, and the curve of either.

@group(1) @binding(0) var<storage, read> poses: array<Pose>;
@group(1) @binding(1) var<storage, read> states: array<BezierState>;

// Blade `k`'s deformed centreline at `t` (0 root, 1 tip), world metres.
fn curve_point(k: u32, b: Blade, t: f32) -> vec3<f32> {
    // Both models bend the blade over flat ground; the terrain lifts it where it stands.
    let lift = vec3<f32>(0.0, ground(b.pos), 0.0);
    if (S.model == 1u) {
        let s = states[k];
        return bezier_point(s.v0.xyz, s.v1.xyz, s.v2.xyz, t) + lift;
    }
    return blade_point(b, poses[k], t) + lift;
}

// Eq. 14 at height `y` of blade `k` (the Bezier blades dim by their wind as the CWD ones do).
fn curve_shade(k: u32, b: Blade, y: f32) -> f32 {
    if (S.model == 1u) {
        let dim = S.c1 * S.saturation * tanh(length(blade_wind(b)) / S.saturation);
        return clamp(y - dim + S.c2, S.m_min, S.m_max);
    }
    return blade_shade(y, poses[k]);
}

// The culling and LOD settings (`gpu::grass::CullUniform`, from `grass::cull::CullParams`).
struct Cull {
    // Bits: 1 orientation, 2 frustum, 4 distance, 8 LOD; 16 the blades walked from the last,
    // 32 walked by x (`grass::Walk`: the visible lists nearest first).
    flags: u32,
    buckets: u32,
    // Entries per LOD level in the visible list.
    capacity: u32,
    _pad0: u32,
    orientation_limit: f32,
    frustum_tolerance: f32,
    max_distance: f32,
    lod_near: f32,
    lod_far: f32,
    dither: f32,
    hysteresis: f32,
    // Past it the field thins with the square of the distance (0: not at all).
    thin_distance: f32,
}

// `cull::pcg01`.
fn pcg01(k: u32) -> f32 {
    let state = k * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return f32(((word >> 22u) ^ word) >> 8u) / 16777216.0;
}

// `cull::reach`: how far blade `k` is drawn under distance culling.
fn reach(c: Cull, k: u32) -> f32 {
    let n = max(c.buckets, 1u);
    let bucket = min(u32(pcg01(k ^ 0x9e3779b9u) * f32(n)), n - 1u);
    let r = c.max_distance * (1.0 - f32(bucket) / f32(n));
    if (c.thin_distance > 0.0) {
        // `cull::thin_draw`.
        return min(r, c.thin_distance / sqrt(max(pcg01(k ^ 0x85ebca6bu), 1e-12)));
    }
    return r;
}

// `cull::kept_share`.
fn kept_share(c: Cull, d: f32) -> f32 {
    let buckets = max(1.0 - d / c.max_distance, 0.0);
    if (c.thin_distance > 0.0 && d > c.thin_distance) {
        let q = c.thin_distance / d;
        return buckets * q * q;
    }
    return buckets;
}

// `cull::distance_width`: fade-in over the last `FADE` of the reach, and the widening.
fn distance_width(c: Cull, k: u32, d: f32) -> f32 {
    if ((c.flags & 4u) == 0u) {
        return 1.0;
    }
    let r = reach(c, k);
    let fade = clamp((r - d) / (0.2 * r), 0.0, 1.0);
    let kept = max(kept_share(c, d), 1.0 / 3.0);
    return fade * fade * (3.0 - 2.0 * fade) / kept;
}
