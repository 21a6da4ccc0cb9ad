// Grass, compute: the wind grid the blades read, taken straight from a GPU-run field — each
// cell's velocity the mean of its faces on the solver's staggered MAC layout — so the 3D view
// follows the GPU solver every frame with no read-back. Compiled on its own (it writes the grid
// the other grass passes only read). CPU twin: `sim::Solver::velocity_field`.

struct Grid {
    nx: u32,
    ny: u32,
    _pad: vec2<u32>,
}

@group(0) @binding(0) var<storage, read> G: Grid;
@group(0) @binding(1) var<storage, read> u: array<f32>;
@group(0) @binding(2) var<storage, read> v: array<f32>;
@group(0) @binding(3) var<storage, read_write> cells: array<vec2<f32>>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= G.nx || id.y >= G.ny) {
        return;
    }
    let i = id.x;
    let j = id.y;
    let w = G.nx + 1u;
    cells[j * G.nx + i] = vec2<f32>(
        0.5 * (u[j * w + i] + u[j * w + i + 1u]),
        0.5 * (v[j * G.nx + i] + v[(j + 1u) * G.nx + i]),
    );
}
