// Step 5: the pressure solve. `decay` scales the previous pressure (the warm start); `main` is
// one Jacobi sweep p ← (wx (p_L + p_R) + wz (p_B + p_T) − div) / Σw over the neighbours that take
// part (flags: L 1, R 2, B 4, T 8; solids and closed walls drop out, open edges hold p = 0
// outside), with `inv_w` the cell's 1 / Σw (0 outside the solve).
// CPU twin: `Solver::jacobi_iteration` (and the blocked `Solver::solve_pressure`).

@group(0) @binding(1) var<storage, read> p_in: array<f32>;
@group(0) @binding(2) var<storage, read_write> p_out: array<f32>;
@group(0) @binding(3) var<storage, read> div: array<f32>;
@group(0) @binding(4) var<storage, read> flags: array<u32>;
@group(0) @binding(5) var<storage, read> inv_w: array<f32>;
@group(0) @binding(6) var<storage, read_write> p: array<f32>;

fn pick(fl: u32, bit: u32, x: f32) -> f32 {
    return select(0.0, x, (fl & bit) != 0u);
}

@compute @workgroup_size(64)
fn decay(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
) {
    let k = flat_index(id, nwg);
    if (k < P.nx * P.ny) {
        p[k] = p[k] * P.decay;
    }
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    let nx = P.nx;
    let ny = P.ny;
    if (i >= nx || j >= ny) {
        return;
    }
    // Rows beyond the grid have zero weight unless periodic; a row's ends wrap (used only
    // where the periodic flags say so).
    var jb = select(j - 1u, 0u, j == 0u);
    var jt = min(j + 1u, ny - 1u);
    if (P.periodic != 0u) {
        jb = (j + ny - 1u) % ny;
        jt = (j + 1u) % ny;
    }
    let il = select(i - 1u, nx - 1u, i == 0u);
    let ir = select(i + 1u, 0u, i == nx - 1u);
    let k = j * nx + i;
    let fl = flags[k];
    p_out[k] = (P.wx * (pick(fl, 1u, p_in[j * nx + il]) + pick(fl, 2u, p_in[j * nx + ir]))
        + P.wz * (pick(fl, 4u, p_in[jb * nx + i]) + pick(fl, 8u, p_in[jt * nx + i]))
        - div[k]) * inv_w[k];
}
