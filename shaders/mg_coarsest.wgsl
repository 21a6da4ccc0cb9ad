// Multigrid's coarsest level solved in one dispatch: `M.sweeps` red–black sweeps (colour 0
// first) by one workgroup in workgroup memory, from `x` into `x_out`. Each half sweep is
// `mg_smooth`'s, value for value: the cells of its colour get (Σ a x_n + b_scale·b) / D from
// the previous half sweep's values, the others keep theirs (two copies in workgroup memory,
// so a wrapped odd-sized level, where a cell can neighbour its own colour, reads the old
// values as the separate passes do). A coarsest level is a few dozen cells; as separate
// passes its solve was 2·sweeps dispatches a V-cycle (64 at 1000²), each too small to fill a
// GPU. Used when the level has at most `COARSEST_CAP` cells (`gpu::multigrid`). CPU twin:
// `multigrid::smooth` with `Relax::RedBlack(0)` on the coarsest level.

@group(0) @binding(2) var<storage, read_write> x_out: array<f32>;
@group(0) @binding(3) var<storage, read> b: array<f32>;
@group(0) @binding(6) var<storage, read> inv_d: array<f32>;

// `gpu::multigrid::COARSEST_CAP`: two copies of the level fill WebGPU's 16 KiB default.
const CAP: u32 = 2048u;
var<workgroup> s: array<f32, 4096>;

// `link_sum` (mg_common.wgsl) over the copy at `o`, in the same order.
fn link_sum_at(o: u32, i: u32, j: u32) -> f32 {
    let nx = M.nx;
    let ny = M.ny;
    var l = 0.0;
    var r = 0.0;
    if (i > 0u) { l = s[o + j * nx + i - 1u]; } else if (M.wraps != 0u) { l = s[o + j * nx + nx - 1u]; }
    if (i + 1u < nx) { r = s[o + j * nx + i + 1u]; } else if (M.wraps != 0u) { r = s[o + j * nx]; }
    var jb = select(j - 1u, 0u, j == 0u);
    var jt = min(j + 1u, ny - 1u);
    if (M.wraps != 0u) {
        jb = (j + ny - 1u) % ny;
        jt = (j + 1u) % ny;
    }
    let w = nx + 1u;
    return ax[j * w + i] * l + ax[j * w + i + 1u] * r + az[j * nx + i] * s[o + jb * nx + i]
        + az[(j + 1u) * nx + i] * s[o + jt * nx + i];
}

@compute @workgroup_size(64)
fn main(@builtin(local_invocation_index) lid: u32) {
    let n = M.nx * M.ny;
    for (var k = lid; k < n; k = k + 64u) {
        s[k] = x[k];
    }
    workgroupBarrier();
    for (var h = 0u; h < 2u * M.sweeps; h = h + 1u) {
        let colour = h % 2u;
        let src = colour * CAP;
        let dst = (1u - colour) * CAP;
        for (var k = lid; k < n; k = k + 64u) {
            let i = k % M.nx;
            let j = k / M.nx;
            if ((i + j + colour) % 2u != 0u) {
                s[dst + k] = s[src + k];
            } else {
                s[dst + k] = (link_sum_at(src, i, j) + M.b_scale * b[k]) * inv_d[k];
            }
        }
        workgroupBarrier();
    }
    for (var k = lid; k < n; k = k + 64u) {
        x_out[k] = s[k];
    }
}
