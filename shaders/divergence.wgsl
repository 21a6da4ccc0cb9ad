// Step 4: divergence per cell, (u_R − u_L)/hx + (v_T − v_B)/hz, 0 in solids.
// CPU twin: `Solver::compute_divergence`.

@group(0) @binding(1) var<storage, read> u: array<f32>;
@group(0) @binding(2) var<storage, read> v: array<f32>;
@group(0) @binding(3) var<storage, read> solid: array<u32>;
@group(0) @binding(4) var<storage, read_write> div: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    let nx = P.nx;
    if (i >= nx || j >= P.ny) {
        return;
    }
    let k = j * nx + i;
    if (solid[k] != 0u) {
        div[k] = 0.0;
        return;
    }
    let w = nx + 1u;
    div[k] = (u[j * w + i + 1u] - u[j * w + i]) / P.hx + (v[(j + 1u) * nx + i] - v[j * nx + i]) / P.hz;
}
