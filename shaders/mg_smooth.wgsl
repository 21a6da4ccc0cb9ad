// Multigrid relaxation: one pass on one level, from `x` into `x_out`, of the Jacobi value
// v = (Σ a x_n + b_scale·b) / D. With `colour` 0 or 1, a red–black Gauss–Seidel half sweep:
// cells with (i + j) % 2 == colour get v, the others keep their value; with `colour` 2, a
// damped Jacobi pass: every cell gets x + weight·(v − x). CPU twin: `multigrid::relax_passes`
// (one pass, `Relax::RedBlack` or `Relax::Damped`).

@group(0) @binding(2) var<storage, read_write> x_out: array<f32>;
@group(0) @binding(3) var<storage, read> b: array<f32>;
@group(0) @binding(6) var<storage, read> inv_d: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    if (i >= M.nx || j >= M.ny) {
        return;
    }
    let k = j * M.nx + i;
    if (M.colour < 2u && (i + j + M.colour) % 2u != 0u) {
        x_out[k] = x[k];
        return;
    }
    let v = (link_sum(i, j) + M.b_scale * b[k]) * inv_d[k];
    if (M.colour == 2u) {
        x_out[k] = x[k] + M.weight * (v - x[k]);
    } else {
        x_out[k] = v;
    }
}
