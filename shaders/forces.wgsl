// Step 1, the AGC arrows: each active arrow is a capsule splat that drives the wind on the
// free faces along its direction toward its strength,
// Δvel = (1 − e^(−k·g·dt)) · max(0, strength − vel·dir) · dir, g = exp(−d²/r²) within 3 r,
// overlapping arrows' pushes summed and scaled by min(1, 4 / n), n = (Σ gain)² / Σ gain²
// the number of arrows effectively overlapping (at most four arrows' rate).
// The ambient layers then pull every free face toward their wind: Δvel = (w − vel)·coupling.
// `inc_u`/`inc_v` write every face's change from the velocity before the pass; `add` then adds
// it, clamped to ±max_speed. CPU twin: `Solver::apply_forces` with `sim::forces::ArrowSplat`
// (mirrored by `struct Splat`), `sim::forces::LayerParams` (by `struct Layer`),
// `sim::forces::Ambient::wind`, `gradient_noise` and `exp_neg`.

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
@group(0) @binding(7) var<storage, read> layers: array<Layer>;
// The FFT layers' gust fields, one after the other.
@group(0) @binding(8) var<storage, read> gusts: array<f32>;

struct Layer {
    // 0 directional, 1 noise, 2 FFT gusts, 3 sine.
    kind: u32,
    fft_offset: u32,
    fft_n: u32,
    _pad: u32,
    dir: vec2<f32>,
    // dir · speed · t: how far the pattern has scrolled.
    shift: vec2<f32>,
    a: f32,
    b: f32,
    c: f32,
    _pad2: f32,
}

// (sin a, cos a): Cody–Waite reduction by π/2 in three parts and polynomials on [−π/4, π/4],
// accurate to about 1e-7 for the arguments that occur, on any GPU.
fn sincos(a: f32) -> vec2<f32> {
    let k = round(a * 0.63661975);
    let r = ((a - k * 1.5703125) - k * 4.8375129699707031e-4) - k * 7.5497899548918821e-8;
    let r2 = r * r;
    let s = r + r * r2 * (-0.16666667 + r2 * (0.0083333333 + r2 * (-0.00019841270 + r2 * 2.7557319e-6)));
    let c = 1.0 + r2 * (-0.5 + r2 * (0.041666668 + r2 * (-0.0013888889 + r2 * 2.4801587e-5)));
    let q = i32(k) & 3;
    if (q == 0) {
        return vec2<f32>(s, c);
    }
    if (q == 1) {
        return vec2<f32>(c, -s);
    }
    if (q == 2) {
        return vec2<f32>(-s, -c);
    }
    return vec2<f32>(-c, s);
}

// The CPU's integer hash (`sim::forces::hash`), bit for bit.
fn hash(x: i32, y: i32, seed: u32) -> u32 {
    var h = (bitcast<u32>(x) * 0x8da6b343u) ^ (bitcast<u32>(y) * 0xd8163841u) ^ (seed * 0xcb1ab31fu);
    h = h ^ (h >> 16u);
    h = h * 0x7feb352du;
    h = h ^ (h >> 15u);
    h = h * 0x846ca68bu;
    return h ^ (h >> 16u);
}

fn grad(ix: i32, iy: i32, seed: u32, dx: f32, dy: f32) -> f32 {
    let a = f32(hash(ix, iy, seed) >> 8u) * (6.2831855 / 16777216.0);
    let sc = sincos(a);
    return sc.y * dx + sc.x * dy;
}

fn fade(t: f32) -> f32 {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// 2D gradient noise in about [−1, 1]: `sim::forces::gradient_noise`.
fn gradient_noise(x: f32, y: f32, seed: u32) -> f32 {
    let xf = floor(x);
    let yf = floor(y);
    let fx = x - xf;
    let fy = y - yf;
    let xi = i32(xf);
    let yi = i32(yf);
    let n00 = grad(xi, yi, seed, fx, fy);
    let n10 = grad(xi + 1, yi, seed, fx - 1.0, fy);
    let n01 = grad(xi, yi + 1, seed, fx, fy - 1.0);
    let n11 = grad(xi + 1, yi + 1, seed, fx - 1.0, fy - 1.0);
    let u = fade(fx);
    let v = fade(fy);
    let nx0 = n00 + (n10 - n00) * u;
    let nx1 = n01 + (n11 - n01) * u;
    return (nx0 + (nx1 - nx0) * v) * 1.4142135;
}

// Rust's f32::rem_euclid(1.0).
fn rem1(x: f32) -> f32 {
    let r = x % 1.0;
    return select(r, r + 1.0, r < 0.0);
}

// An FFT layer's unit-rms gust at world point `p`, bilinear, wrapping every tile (`c`).
fn fft_sample(l: Layer, p: vec2<f32>) -> f32 {
    let n = l.fft_n;
    let x = rem1(p.x / l.c) * f32(n);
    let z = rem1(p.y / l.c) * f32(n);
    let i0 = u32(floor(x)) % n;
    let j0 = u32(floor(z)) % n;
    let i1 = (i0 + 1u) % n;
    let j1 = (j0 + 1u) % n;
    let fx = x - floor(x);
    let fz = z - floor(z);
    let o = l.fft_offset;
    let a = gusts[o + j0 * n + i0] + (gusts[o + j0 * n + i1] - gusts[o + j0 * n + i0]) * fx;
    let b = gusts[o + j1 * n + i0] + (gusts[o + j1 * n + i1] - gusts[o + j1 * n + i0]) * fx;
    return a + (b - a) * fz;
}

// The ambient layers' target wind at world point `p`: `sim::forces::Ambient::wind`.
fn ambient_wind(p: vec2<f32>) -> vec2<f32> {
    var w = vec2<f32>(0.0, 0.0);
    for (var n = 0u; n < P.layers; n = n + 1u) {
        let l = layers[n];
        var speed = 0.0;
        if (l.kind == 0u) {
            // Directional: frozen turbulence scrolled with the mean wind, and the gusty mean.
            let q = vec2<f32>(p.x - l.shift.x, p.y - l.shift.y);
            let s = 1.0 / 8.0;
            w.x = w.x + l.a * gradient_noise(q.x * s, q.y * s, 11u);
            w.y = w.y + l.a * gradient_noise(q.x * s, q.y * s, 23u);
            speed = l.b;
        } else if (l.kind == 1u) {
            let q = vec2<f32>(p.x - l.shift.x, p.y - l.shift.y);
            let nz = gradient_noise(q.x / l.a, q.y / l.a, 5u);
            speed = l.b * clamp(0.5 + 0.5 * nz, 0.0, 1.0);
        } else if (l.kind == 2u) {
            var f = 0.0;
            if (l.fft_n > 0u) {
                f = fft_sample(l, vec2<f32>(p.x - l.shift.x, p.y - l.shift.y));
            }
            speed = l.a + l.b * f;
        } else {
            let x = p.x * l.dir.x + p.y * l.dir.y;
            speed = l.a * sincos(6.2831855 * (x / l.b - l.c)).x;
        }
        w.x = w.x + l.dir.x * speed;
        w.y = w.y + l.dir.y * speed;
    }
    return w;
}

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

// At most this many arrows' rates push where arrows overlap (`sim::forces::OVERLAP_ARROWS`).
const OVERLAP_ARROWS: f32 = 4.0;

// The change of component `c` (0: x, 1: z) at world point `at` where the wind is `vel`.
fn increment(at: vec2<f32>, vel: vec2<f32>, c: u32) -> f32 {
    var sum = 0.0;
    var gains = 0.0;
    var squares = 0.0;
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
        let gain = 1.0 - exp_neg(-P.response * g * P.dt);
        let m = gain * deficit;
        sum = sum + sp.dir[c] * m;
        gains = gains + gain;
        squares = squares + gain * gain;
    }
    // `sim::forces::combine`: a crowd of overlapping arrows pushes at four arrows' rate
    // (`OVERLAP_ARROWS`) toward the gain-weighted mean of their pushes, never by their sum;
    // up to four arrows as they always did (the scale is 1).
    if (gains > 0.0) {
        sum = sum * min(OVERLAP_ARROWS * squares / (gains * gains), 1.0);
    }
    if (P.layers > 0u) {
        sum = sum + (ambient_wind(at)[c] - vel[c]) * P.coupling;
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
fn add(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
) {
    let k = flat_index(id, nwg);
    if (k < arrayLength(&field)) {
        field[k] = clamp(field[k] + inc[k], -P.max_speed, P.max_speed);
    }
}
