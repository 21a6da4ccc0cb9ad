// Step 7: advection of the face fields, the dissipation `keep` folded into the write: each
// free face traces back along the velocity at the face (its own component and the mean of the
// four nearest faces of the other) and samples the source bilinearly, clamped at the edges or
// wrapped on periodic grids; faces that are not free get 0. `advect_u`/`advect_v` are the
// semi-Lagrangian step (and, with −dt, MacCormack's backward step); `maccormack_u`/`_v` the
// limited correction φ' = clamp(φ̂ + (φ − φ̌)/2, forward stencil's min, max) · keep.
// CPU twins: `advect_faces` and `maccormack` in `src/sim/solver/mod.rs` (`Solver::advect`).

@group(0) @binding(1) var<storage, read> u: array<f32>;
@group(0) @binding(2) var<storage, read> v: array<f32>;
@group(0) @binding(3) var<storage, read> src: array<f32>;
@group(0) @binding(4) var<storage, read_write> dst: array<f32>;
@group(0) @binding(5) var<storage, read> free: array<u32>;
// MacCormack: φ̌ on entry, the corrected field on exit.
@group(0) @binding(6) var<storage, read_write> back: array<f32>;

// Sample indices and weight along one axis of `n` samples: clamped to [0, n − 1], or wrapped
// every `period` samples.
fn axis(x: f32, n: u32, period: u32) -> vec3<f32> {
    if (P.periodic != 0u) {
        let p = f32(period);
        let xw = x - p * floor(x / p);
        let i0 = min(u32(floor(xw)), period - 1u);
        return vec3<f32>(f32(i0), f32((i0 + 1u) % period), xw - f32(i0));
    }
    let xc = clamp(x, 0.0, f32(n - 1u));
    let i0 = min(u32(xc), n - 2u);
    return vec3<f32>(f32(i0), f32(min(i0 + 1u, n - 1u)), xc - f32(i0));
}

// Bilinear sample of `f` (1: the advected source `src`; 2: the velocity u; 3: v) with
// `w × h` samples at fractional sample coordinates: (value, min, max of the four samples).
fn fetch(which: u32, k: u32) -> f32 {
    if (which == 2u) {
        return u[k];
    }
    if (which == 3u) {
        return v[k];
    }
    return src[k];
}

fn sample_range(which: u32, w: u32, h: u32, x: f32, z: f32) -> vec3<f32> {
    let ax = axis(x, w, P.nx);
    let az = axis(z, h, P.ny);
    let i0 = u32(ax.x);
    let i1 = u32(ax.y);
    let j0 = u32(az.x);
    let j1 = u32(az.y);
    let a = fetch(which, j0 * w + i0);
    let b = fetch(which, j0 * w + i1);
    let c = fetch(which, j1 * w + i0);
    let d = fetch(which, j1 * w + i1);
    let top = a + (b - a) * ax.z;
    let bottom = c + (d - c) * ax.z;
    return vec3<f32>(top + (bottom - top) * az.z, min(min(a, b), min(c, d)), max(max(a, b), max(c, d)));
}

// Bilinear sample of `src` with `w × h` samples at fractional sample coordinates.
fn sample(w: u32, h: u32, x: f32, z: f32) -> f32 {
    let ax = axis(x, w, P.nx);
    let az = axis(z, h, P.ny);
    let i0 = u32(ax.x);
    let i1 = u32(ax.y);
    let j0 = u32(az.x);
    let j1 = u32(az.y);
    let a = src[j0 * w + i0];
    let b = src[j0 * w + i1];
    let c = src[j1 * w + i0];
    let d = src[j1 * w + i1];
    let top = a + (b - a) * ax.z;
    let bottom = c + (d - c) * ax.z;
    return top + (bottom - top) * az.z;
}

// Departure point (grid units) of u face (i, j) over `dt`.
fn depart_u(i: u32, j: u32, dt: f32) -> vec2<f32> {
    let nx = P.nx;
    let k = j * (nx + 1u) + i;
    var il = min(select(i - 1u, 0u, i == 0u), nx - 1u);
    var ir = min(i, nx - 1u);
    if (P.periodic != 0u) {
        il = (i + nx - 1u) % nx;
        ir = i % nx;
    }
    let vz = 0.25 * (v[j * nx + il] + v[j * nx + ir] + v[(j + 1u) * nx + il] + v[(j + 1u) * nx + ir]);
    return vec2<f32>(f32(i) - u[k] * (dt / P.hx), f32(j) + 0.5 - vz * (dt / P.hz));
}

// Departure point (grid units) of v face (i, j) over `dt`.
fn depart_v(i: u32, j: u32, dt: f32) -> vec2<f32> {
    let nx = P.nx;
    let ny = P.ny;
    var jb = min(select(j - 1u, 0u, j == 0u), ny - 1u);
    var jt = min(j, ny - 1u);
    if (P.periodic != 0u) {
        jb = (j + ny - 1u) % ny;
        jt = j % ny;
    }
    let w = nx + 1u;
    let ux = 0.25 * (u[jb * w + i] + u[jb * w + i + 1u] + u[jt * w + i] + u[jt * w + i + 1u]);
    return vec2<f32>(f32(i) + 0.5 - ux * (dt / P.hx), f32(j) - v[j * nx + i] * (dt / P.hz));
}

@compute @workgroup_size(8, 8)
fn maccormack_u(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    let w = P.nx + 1u;
    if (i > P.nx || j >= P.ny) {
        return;
    }
    let k = j * w + i;
    if (free[k] == 0u) {
        back[k] = 0.0;
        return;
    }
    let d = depart_u(i, j, P.dt);
    let r = sample_range(2u, w, P.ny, d.x, d.y - 0.5);
    back[k] = clamp(src[k] + 0.5 * (u[k] - back[k]), r.y, r.z) * P.keep;
}

@compute @workgroup_size(8, 8)
fn maccormack_v(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    let nx = P.nx;
    if (i >= nx || j > P.ny) {
        return;
    }
    let k = j * nx + i;
    if (free[k] == 0u) {
        back[k] = 0.0;
        return;
    }
    let d = depart_v(i, j, P.dt);
    let r = sample_range(3u, nx, P.ny + 1u, d.x - 0.5, d.y);
    back[k] = clamp(src[k] + 0.5 * (v[k] - back[k]), r.y, r.z) * P.keep;
}

// Semi-Lagrangian step of the u faces from `src` into `dst` over `dt`, times `keep`.
fn advect_u_with(id: vec3<u32>, dt: f32, keep: f32) {
    let i = id.x;
    let j = id.y;
    let w = P.nx + 1u;
    if (i > P.nx || j >= P.ny) {
        return;
    }
    let k = j * w + i;
    if (free[k] == 0u) {
        dst[k] = 0.0;
        return;
    }
    let d = depart_u(i, j, dt);
    dst[k] = sample(w, P.ny, d.x, d.y - 0.5) * keep;
}

// Semi-Lagrangian step of the v faces from `src` into `dst` over `dt`, times `keep`.
fn advect_v_with(id: vec3<u32>, dt: f32, keep: f32) {
    let i = id.x;
    let j = id.y;
    let nx = P.nx;
    if (i >= nx || j > P.ny) {
        return;
    }
    let k = j * nx + i;
    if (free[k] == 0u) {
        dst[k] = 0.0;
        return;
    }
    let d = depart_v(i, j, dt);
    dst[k] = sample(nx, P.ny + 1u, d.x - 0.5, d.y) * keep;
}

// The semi-Lagrangian scheme: one step, with dissipation.
@compute @workgroup_size(8, 8)
fn advect_u(@builtin(global_invocation_id) id: vec3<u32>) {
    advect_u_with(id, P.dt, P.keep);
}

@compute @workgroup_size(8, 8)
fn advect_v(@builtin(global_invocation_id) id: vec3<u32>) {
    advect_v_with(id, P.dt, P.keep);
}

// MacCormack's forward step φ̂ (no dissipation yet) ...
@compute @workgroup_size(8, 8)
fn trace_u(@builtin(global_invocation_id) id: vec3<u32>) {
    advect_u_with(id, P.dt, 1.0);
}

@compute @workgroup_size(8, 8)
fn trace_v(@builtin(global_invocation_id) id: vec3<u32>) {
    advect_v_with(id, P.dt, 1.0);
}

// ... and its backward step φ̌ from φ̂, along the same velocity.
@compute @workgroup_size(8, 8)
fn retrace_u(@builtin(global_invocation_id) id: vec3<u32>) {
    advect_u_with(id, -P.dt, 1.0);
}

@compute @workgroup_size(8, 8)
fn retrace_v(@builtin(global_invocation_id) id: vec3<u32>) {
    advect_v_with(id, -P.dt, 1.0);
}
