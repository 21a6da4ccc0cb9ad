// Multigrid restriction: each coarse cell's right-hand side is the sum of its children's
// residuals b_scale·b + Σ a x_n − D x (0 outside the solve), summed as the CPU does: down
// the children's rows first, then across. CPU twin: `multigrid::restrict`.

@group(0) @binding(3) var<storage, read> b: array<f32>;
@group(0) @binding(6) var<storage, read> diag: array<f32>;
@group(0) @binding(7) var<storage, read_write> coarse_b: array<f32>;

fn residual(i: u32, j: u32) -> f32 {
    let k = j * M.nx + i;
    let d = diag[k];
    if (d > 0.0) {
        return M.b_scale * b[k] + link_sum(i, j) - d * x[k];
    }
    return 0.0;
}

// Both children rows of column i summed (one row when z is not coarsened or at an odd end).
fn column(i: u32, j0: u32, two: bool) -> f32 {
    var s = residual(i, j0);
    if (two) {
        s = s + residual(i, j0 + 1u);
    }
    return s;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let ic = id.x;
    let jc = id.y;
    if (ic >= M.cnx || jc >= M.cny) {
        return;
    }
    let i0 = select(ic, 2u * ic, M.coarse_x != 0u);
    let j0 = select(jc, 2u * jc, M.coarse_z != 0u);
    let two_i = M.coarse_x != 0u && i0 + 1u < M.nx;
    let two_j = M.coarse_z != 0u && j0 + 1u < M.ny;
    var s = column(i0, j0, two_j);
    if (two_i) {
        s = s + column(i0 + 1u, j0, two_j);
    }
    coarse_b[jc * M.cnx + ic] = s;
}
