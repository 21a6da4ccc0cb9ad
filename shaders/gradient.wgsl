// Step 6: subtract the pressure gradient from every free face (others are zeroed). Outside
// the grid the pressure wraps (periodic) or is 0 (open edges; closed edges are not free).
// CPU twin: `Solver::subtract_gradient`.

@group(0) @binding(1) var<storage, read> p: array<f32>;
@group(0) @binding(2) var<storage, read_write> u: array<f32>;
@group(0) @binding(3) var<storage, read_write> v: array<f32>;
@group(0) @binding(4) var<storage, read> u_free: array<u32>;
@group(0) @binding(5) var<storage, read> v_free: array<u32>;

// Pressure of cell column `i` (may be −1 or nx) in row `j`.
fn px(i: i32, j: u32) -> f32 {
    let nx = i32(P.nx);
    let wrap = P.periodic != 0u;
    if (i < 0) {
        return select(0.0, p[j * P.nx + P.nx - 1u], wrap);
    }
    if (i >= nx) {
        return select(0.0, p[j * P.nx], wrap);
    }
    return p[j * P.nx + u32(i)];
}

// Pressure of cell row `j` (may be −1 or ny) in column `i`.
fn pz(i: u32, j: i32) -> f32 {
    let ny = i32(P.ny);
    let wrap = P.periodic != 0u;
    if (j < 0) {
        return select(0.0, p[(P.ny - 1u) * P.nx + i], wrap);
    }
    if (j >= ny) {
        return select(0.0, p[i], wrap);
    }
    return p[u32(j) * P.nx + i];
}

@compute @workgroup_size(8, 8)
fn u_faces(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    if (i > P.nx || j >= P.ny) {
        return;
    }
    let k = j * (P.nx + 1u) + i;
    if (u_free[k] == 0u) {
        u[k] = 0.0;
        return;
    }
    u[k] = u[k] - (px(i32(i), j) - px(i32(i) - 1, j)) / P.hx;
}

@compute @workgroup_size(8, 8)
fn v_faces(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    if (i >= P.nx || j > P.ny) {
        return;
    }
    let k = j * P.nx + i;
    if (v_free[k] == 0u) {
        v[k] = 0.0;
        return;
    }
    v[k] = v[k] - (pz(i, i32(j)) - pz(i, i32(j) - 1)) / P.hz;
}
