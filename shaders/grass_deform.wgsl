// Grass, compute: each blade's pose for this frame — its wind cell's velocity (eq. 1), the
// saturated bend with flutter (eq. 12), and the scale that restores its length (eq. 13 as we
// read it) — so the vertex shader only evaluates the curve. CPU twin: `grass::cwd::push` and
// the renormalisation in `grass::cwd::centreline`.

@group(1) @binding(0) var<storage, read_write> poses: array<Pose>;
// Tip positions (tests only: the `tips` entry point).
@group(1) @binding(1) var<storage, read_write> tips: array<vec4<f32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if (k >= S.blades) {
        return;
    }
    poses[k] = blade_pose(blades[k], S.eye.w);
}

// The deformed tip (xyz) and its shade (w), from the poses: what the vertex shader draws at
// the top of each blade.
@compute @workgroup_size(64)
fn tips_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if (k >= S.blades) {
        return;
    }
    let b = blades[k];
    let pose = poses[k];
    let p = blade_point(b, pose, 1.0);
    tips[k] = vec4<f32>(p, blade_shade(p.y, pose));
}
