// Shared by every fluid pass (prepended to each pass's source by `gpu::fluid`): the grid and
// step parameters, mirrored by `gpu::fluid::Params` (#[repr(C)], bytemuck), and the index
// helpers of the CPU solver (`src/sim/solver/mod.rs`). The staggered MAC layout is the CPU's:
// u faces (nx + 1) × ny, v faces nx × (ny + 1), cells nx × ny, all row-major, row j along +z.

struct Params {
    nx: u32,
    ny: u32,
    // 1 for periodic boundaries.
    periodic: u32,
    // Active AGC splats in the forces pass.
    splats: u32,
    // Cell size in metres along x and z.
    hx: f32,
    hz: f32,
    // Step (seconds), negative for a backward trace.
    dt: f32,
    // Dissipation factor folded into advection: 1 / (1 + dissipation × dt).
    keep: f32,
    // Vorticity confinement's rate (`confinement_rate` of ε, 1/s) and min(hx, hz).
    eps: f32,
    h: f32,
    // Pressure stencil weights 1/hx², 1/hz².
    wx: f32,
    wz: f32,
    // Warm-start factor of the pressure.
    decay: f32,
    // Velocity clamp, m/s (`solver::MAX_SPEED`).
    max_speed: f32,
    // Rate (1/s) at which an arrow brings the wind up to its strength.
    response: f32,
    // 1 for open boundaries: the confinement leaves the cells along the edges alone.
    open: u32,
    // World position of the grid's minimum corner, metres.
    origin: vec2<f32>,
    // Ambient layers: the pull toward their wind per substep, 1 − e^(−coupling·dt), and how
    // many layers are active.
    coupling: f32,
    layers: u32,
    // Confinement takes no face past this speed (m/s), the layout's reference speed, and
    // scales a cell's push by its speed times `inv_speed` (1 / speed_cap), up to 1.
    speed_cap: f32,
    inv_speed: f32,
}

@group(0) @binding(0) var<storage, read> P: Params;

// Neighbour indices (lower, upper) of `i` on an axis of `n` cells: wrapped or clamped.
fn neighbours(i: u32, n: u32) -> vec2<u32> {
    if (P.periodic != 0u) {
        return vec2<u32>((i + n - 1u) % n, (i + 1u) % n);
    }
    return vec2<u32>(select(i - 1u, 0u, i == 0u), min(i + 1u, n - 1u));
}

// The element a 64-wide invocation of a one-dimensional pass stands for. Such passes are
// dispatched as rows of at most 65,535 workgroups (`fluid::flat_groups`), so that arrays of
// more than 65,535 × 64 elements (a 2048² grid's faces) are covered too.
fn flat_index(id: vec3<u32>, nwg: vec3<u32>) -> u32 {
    return id.y * nwg.x * 64u + id.x;
}
