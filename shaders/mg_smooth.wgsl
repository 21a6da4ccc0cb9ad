// Multigrid smoother: one red–black Gauss–Seidel half sweep on one level, from `x` into
// `x_out`: cells with (i + j) % 2 == colour get (Σ a x_n + b_scale·b) / D, the others keep
// their value. CPU twin: `multigrid::half_sweeps` (one pass).

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
    if ((i + j + M.colour) % 2u != 0u) {
        x_out[k] = x[k];
        return;
    }
    x_out[k] = (link_sum(i, j) + M.b_scale * b[k]) * inv_d[k];
}
