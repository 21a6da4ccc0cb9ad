// Step 1, the AGC arrows: each active arrow is a capsule splat that drives the wind on the
// free faces along its direction toward its strength,
// Δvel = (1 − e^(−k·g·dt)) · max(0, strength − vel·dir) · dir, g = exp(−d²/r²) within 3 r.
// `inc_u`/`inc_v` write every face's change from the velocity before the pass; `add_u`/`add_v`
// then add it, clamped to ±max_speed. CPU twin: `Solver::apply_forces` with
// `sim::forces::ArrowSplat` (mirrored by `struct Splat`) and `sim::forces::exp_neg`.
// The ambient layers' pull is not on the GPU yet.

struct Splat {
    a: vec2<f32>,
    b: vec2<f32>,
    dir: vec2<f32>,
    strength: f32,
    radius: f32,
}

@group(0) @binding(1) var<storage, read> u: array<f32>;
@group(0) @binding(2) var<storage, read> v: array<f32>;
@group(0) @binding(3) var<storage, read> splats: array<Splat>;
@group(0) @binding(4) var<storage, read_write> inc: array<f32>;
@group(0) @binding(5) var<storage, read> free: array<u32>;
@group(0) @binding(6) var<storage, read_write> field: array<f32>;

// e^x for x ≤ 0: the CPU's range-reduced polynomial (`sim::forces::exp_neg`). The CPU rounds
// n = x·log2(e) by adding and subtracting 1.5·2²³; shader compilers may fold that pair away
// (lavapipe does), so here `round` (to nearest even, as the CPU's trick) gives the same n.
fn exp_neg(x_in: f32) -> f32 {
    let x = clamp(x_in, -87.0, 0.0);
    let n = round(x * 1.442695041);
    let g = (x - n * 0.6933594) - n * -2.1219444e-4;
    var p = 1.9875691e-4;
    p = p * g + 1.3981999e-3;
    p = p * g + 8.333452e-3;
    p = p * g + 4.1665796e-2;
    p = p * g + 1.6666665e-1;
    p = p * g + 0.5;
    let e = p * g * g + g + 1.0;
    // n ∈ [−126, 0]: 2ⁿ is a normal number with exponent field n + 127.
    let scale = bitcast<f32>(u32(i32(n) + 127) << 23u);
    return e * scale;
}

fn segment_dist2(p: vec2<f32>, a: vec2<f32>, b: vec2<f32>) -> f32 {
    let ab = b - a;
    let ap = p - a;
    let len2 = ab.x * ab.x + ab.y * ab.y;
    var t = 0.0;
    if (len2 > 0.0) {
        t = clamp((ap.x * ab.x + ap.y * ab.y) * (1.0 / len2), 0.0, 1.0);
    }
    let d = vec2<f32>(ap.x - ab.x * t, ap.y - ab.y * t);
    return d.x * d.x + d.y * d.y;
}

// The change of component `c` (0: x, 1: z) at world point `at` where the wind is `vel`.
fn increment(at: vec2<f32>, vel: vec2<f32>, c: u32) -> f32 {
    var sum = 0.0;
    for (var s = 0u; s < P.splats; s = s + 1u) {
        let sp = splats[s];
        let d2 = segment_dist2(at, sp.a, sp.b);
        let r2 = sp.radius * sp.radius;
        if (d2 > r2 * 3.0 * 3.0) {
            continue;
        }
        let g = exp_neg(-d2 * (1.0 / r2));
        if (g == 0.0) {
            continue;
        }
        let deficit = max(sp.strength - (vel.x * sp.dir.x + vel.y * sp.dir.y), 0.0);
        let m = (1.0 - exp_neg(-P.response * g * P.dt)) * deficit;
        sum = sum + sp.dir[c] * m;
    }
    return sum;
}

@compute @workgroup_size(8, 8)
fn inc_u(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    let nx = P.nx;
    if (i > nx || j >= P.ny) {
        return;
    }
    let k = j * (nx + 1u) + i;
    if (free[k] == 0u) {
        inc[k] = 0.0;
        return;
    }
    var il = min(select(i - 1u, 0u, i == 0u), nx - 1u);
    var ir = min(i, nx - 1u);
    if (P.periodic != 0u) {
        il = (i + nx - 1u) % nx;
        ir = i % nx;
    }
    let vz = 0.25 * (v[j * nx + il] + v[j * nx + ir] + v[(j + 1u) * nx + il] + v[(j + 1u) * nx + ir]);
    let at = vec2<f32>(P.origin.x + f32(i) * P.hx, P.origin.y + (f32(j) + 0.5) * P.hz);
    inc[k] = increment(at, vec2<f32>(u[k], vz), 0u);
}

@compute @workgroup_size(8, 8)
fn inc_v(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    let nx = P.nx;
    let ny = P.ny;
    if (i >= nx || j > ny) {
        return;
    }
    let k = j * nx + i;
    if (free[k] == 0u) {
        inc[k] = 0.0;
        return;
    }
    var jb = min(select(j - 1u, 0u, j == 0u), ny - 1u);
    var jt = min(j, ny - 1u);
    if (P.periodic != 0u) {
        jb = (j + ny - 1u) % ny;
        jt = j % ny;
    }
    let w = nx + 1u;
    let ux = 0.25 * (u[jb * w + i] + u[jb * w + i + 1u] + u[jt * w + i] + u[jt * w + i + 1u]);
    let at = vec2<f32>(P.origin.x + (f32(i) + 0.5) * P.hx, P.origin.y + f32(j) * P.hz);
    inc[k] = increment(at, vec2<f32>(ux, v[k]), 1u);
}

@compute @workgroup_size(64)
fn add(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x < arrayLength(&field)) {
        field[id.x] = clamp(field[id.x] + inc[id.x], -P.max_speed, P.max_speed);
    }
}
