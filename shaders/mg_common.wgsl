// Shared by the multigrid passes (prepended to each by `gpu::multigrid`): one level's
// parameters, mirrored by `gpu::multigrid::MgParams` (#[repr(C)], bytemuck), and its link sum.
// A level solves D x − Σ a x_n = b in volume scale; `ax` holds the links across its vertical
// faces ((nx + 1) × ny, face i of row j between cells i − 1 and i, the end faces the wrapped
// link or 0), `az` across its horizontal faces (nx × (ny + 1)). CPU: `sim::solver::multigrid`.

struct Mg {
    // This level's size, and the next coarser level's.
    nx: u32,
    ny: u32,
    cnx: u32,
    cny: u32,
    // 1 when the level wraps (periodic boundaries).
    wraps: u32,
    // The smoother: a red–black half sweep updating the cells with (i + j) % 2 == colour
    // (0, 1), or a damped Jacobi pass with `weight` (2).
    colour: u32,
    // 1 when the coarser level groups two cells along x / z.
    coarse_x: u32,
    coarse_z: u32,
    // The right-hand side is b_scale · b (−hx·hz on the finest level, whose b is the divergence).
    b_scale: f32,
    weight: f32,
    // On the coarsest level: the red–black sweeps that solve it (`mg_coarsest`).
    sweeps: u32,
    _pad: f32,
}

@group(0) @binding(0) var<storage, read> M: Mg;
@group(0) @binding(1) var<storage, read> x: array<f32>;
@group(0) @binding(4) var<storage, read> ax: array<f32>;
@group(0) @binding(5) var<storage, read> az: array<f32>;

// Σ a x_n over cell (i, j)'s four links, in the CPU's order (`multigrid::link_sum_row`).
fn link_sum(i: u32, j: u32) -> f32 {
    let nx = M.nx;
    let ny = M.ny;
    var l = 0.0;
    var r = 0.0;
    if (i > 0u) { l = x[j * nx + i - 1u]; } else if (M.wraps != 0u) { l = x[j * nx + nx - 1u]; }
    if (i + 1u < nx) { r = x[j * nx + i + 1u]; } else if (M.wraps != 0u) { r = x[j * nx]; }
    var jb = select(j - 1u, 0u, j == 0u);
    var jt = min(j + 1u, ny - 1u);
    if (M.wraps != 0u) {
        jb = (j + ny - 1u) % ny;
        jt = (j + 1u) % ny;
    }
    let w = nx + 1u;
    return ax[j * w + i] * l + ax[j * w + i + 1u] * r + az[j * nx + i] * x[jb * nx + i]
        + az[(j + 1u) * nx + i] * x[jt * nx + i];
}
