// Grass, compute: each CWD blade's pose for this frame — its wind cell's velocity (eq. 1), the
// saturated bend with flutter (eq. 12) blended with the trail's crush, and the scale that
// restores its length (eq. 13 as we read it) — so the cull pass and the vertex shader only
// evaluate the curve. CPU twin: `grass::cwd::push`, `cwd::crushed` and the renormalisation in
// `grass::cwd::centreline_crushed`.

@group(1) @binding(0) var<storage, read_write> poses: array<Pose>;

@compute @workgroup_size(64)
fn main(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let k = blade_index(wid, nwg, lid);
    if (k >= S.blades) {
        return;
    }
    poses[k] = blade_pose(blades[k], S.eye.w);
}
