// Periodic boundaries: the last column of u faces and the last row of v faces are the first
// ones. Run after every pass that writes faces on periodic grids.
// CPU twin: `Solver::sync_periodic`.

@group(0) @binding(1) var<storage, read_write> u: array<f32>;
@group(0) @binding(2) var<storage, read_write> v: array<f32>;

@compute @workgroup_size(64)
fn sync_u(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
) {
    let j = flat_index(id, nwg);
    if (j < P.ny) {
        let w = P.nx + 1u;
        u[j * w + P.nx] = u[j * w];
    }
}

@compute @workgroup_size(64)
fn sync_v(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
) {
    let i = flat_index(id, nwg);
    if (i < P.nx) {
        v[P.ny * P.nx + i] = v[i];
    }
}
