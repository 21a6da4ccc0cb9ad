// Step 7: semi-Lagrangian advection of the face fields, the dissipation `keep` folded into the
// write: each free face traces back along the velocity at the face (its own component and the
// mean of the four nearest faces of the other) and samples the source bilinearly, clamped at
// the edges or wrapped on periodic grids; faces that are not free get 0.
// CPU twin: `advect_faces` in `src/sim/solver/mod.rs` (through `Solver::advect`).

@group(0) @binding(1) var<storage, read> u: array<f32>;
@group(0) @binding(2) var<storage, read> v: array<f32>;
@group(0) @binding(3) var<storage, read> src: array<f32>;
@group(0) @binding(4) var<storage, read_write> dst: array<f32>;
@group(0) @binding(5) var<storage, read> free: array<u32>;

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

@compute @workgroup_size(8, 8)
fn advect_u(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    let nx = P.nx;
    let w = nx + 1u;
    if (i > nx || j >= P.ny) {
        return;
    }
    let k = j * w + i;
    if (free[k] == 0u) {
        dst[k] = 0.0;
        return;
    }
    var il = min(select(i - 1u, 0u, i == 0u), nx - 1u);
    var ir = min(i, nx - 1u);
    if (P.periodic != 0u) {
        il = (i + nx - 1u) % nx;
        ir = i % nx;
    }
    let vz = 0.25 * (v[j * nx + il] + v[j * nx + ir] + v[(j + 1u) * nx + il] + v[(j + 1u) * nx + ir]);
    let x = f32(i) - u[k] * (P.dt / P.hx);
    let z = f32(j) + 0.5 - vz * (P.dt / P.hz);
    dst[k] = sample(w, P.ny, x, z - 0.5) * P.keep;
}

@compute @workgroup_size(8, 8)
fn advect_v(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    let nx = P.nx;
    let ny = P.ny;
    if (i >= nx || j > ny) {
        return;
    }
    let k = j * nx + i;
    if (free[k] == 0u) {
        dst[k] = 0.0;
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
    let x = f32(i) + 0.5 - ux * (P.dt / P.hx);
    let z = f32(j) - v[k] * (P.dt / P.hz);
    dst[k] = sample(nx, ny + 1u, x - 0.5, z) * P.keep;
}
