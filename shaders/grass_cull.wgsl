// Grass, compute: which blades this frame draws and at which LOD level — orientation, frustum
// and distance culling, then the dithered, hysteretic distance LOD — with the survivors
// compacted per level into `visible`, whose counts are the instance counts of the indirect
// draws. Each workgroup counts its survivors in workgroup memory and reserves its slots with
// one global atomic per level, so 10 M blades make 160 k atomics, not 10 M. CPU twin:
// `grass::cull::classify`.

@group(2) @binding(0) var<storage, read_write> visible: array<u32>;
@group(2) @binding(1) var<storage, read> C: Cull;
// Per level: draw_indirect's (vertex_count, instance_count, first_vertex, first_instance);
// then blades culled by orientation, frustum and distance, and one word spare; then the far
// level once more as one draw of its triangles without instancing, (3 × count, 1, 0, 0):
// what is drawn (`cull::FAR_DRAW`), where the instanced arguments keep the counts.
@group(2) @binding(2) var<storage, read_write> args: array<atomic<u32>, 20>;
// Each blade's level last frame plus one (0: not drawn yet), for the hysteresis.
@group(2) @binding(3) var<storage, read_write> lods: array<u32>;
// The blades' slots by x (`grass::order_by_x`), walked when the camera looks along x.
@group(2) @binding(4) var<storage, read> order: array<u32>;
// Tips and shades (tests only: the `tips_main` entry point, with a group 2 of its own).
@group(2) @binding(5) var<storage, read_write> tips: array<vec4<f32>>;

var<workgroup> counts: array<atomic<u32>, 6>;
var<workgroup> bases: array<u32, 3>;

// `cull::level`.
fn lod_level(k: u32, d: f32, prev: u32) -> u32 {
    if ((C.flags & 8u) == 0u) {
        return 0u;
    }
    let j = 1.0 + C.dither * (pcg01(k) - 0.5);
    let plain = u32(d > C.lod_near * j) + u32(d > C.lod_far * j);
    if (prev >= 3u || plain == prev) {
        return plain;
    }
    if (plain > prev) {
        let s = 1.0 + C.hysteresis;
        return max(u32(d > C.lod_near * j * s) + u32(d > C.lod_far * j * s), prev);
    }
    let s = 1.0 - C.hysteresis;
    return min(u32(d > C.lod_near * j * s) + u32(d > C.lod_far * j * s), prev);
}

// 0–2: drawn at that level; 3: culled by orientation, 4: by the frustum, 5: by distance.
fn classify(k: u32) -> u32 {
    let b = blades[k];
    let root = curve_point(k, b, 0.0);
    let eye = S.eye.xyz;
    if ((C.flags & 1u) != 0u) {
        let d = root.xz - eye.xz;
        let l = length(d);
        let fr = blade_frame(b);
        if (l > 0.0 && abs(dot(d, fr[1]) / l) > C.orientation_limit) {
            return 3u;
        }
    }
    if ((C.flags & 2u) != 0u) {
        let pts = array<vec3<f32>, 3>(root, curve_point(k, b, 0.5), curve_point(k, b, 1.0));
        var inside = false;
        for (var n = 0u; n < 3u; n = n + 1u) {
            let c = S.view_proj * vec4<f32>(pts[n], 1.0);
            let h = c.w * (1.0 + C.frustum_tolerance);
            let slack = min(min(h - abs(c.x), h - abs(c.y)), min(h - c.z, c.z + h - c.w));
            inside = inside || (c.w > 0.0 && slack >= 0.0);
        }
        if (!inside) {
            return 4u;
        }
    }
    let d = distance(root, eye);
    if ((C.flags & 4u) != 0u && d >= reach(C, k)) {
        return 5u;
    }
    let stored = lods[k];
    let level = lod_level(k, d, select(stored - 1u, 3u, stored == 0u));
    lods[k] = level + 1u;
    return level;
}

@compute @workgroup_size(64)
fn main(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let n = blade_index(wid, nwg, lid);
    // Walked as `grass::Walk::slot` says: the lists fill in about the order the workgroups
    // run, so they hold the nearest blades first when that order meets the camera.
    var k = n;
    if (n < S.blades) {
        let m = select(n, S.blades - 1u - n, (C.flags & 16u) != 0u);
        k = select(m, order[m], (C.flags & 32u) != 0u);
    }
    if (lid < 6u) {
        atomicStore(&counts[lid], 0u);
    }
    workgroupBarrier();
    var verdict = 6u;
    if (n < S.blades) {
        verdict = classify(k);
    }
    var slot = 0u;
    if (verdict < 6u) {
        slot = atomicAdd(&counts[verdict], 1u);
    }
    workgroupBarrier();
    if (lid < 3u) {
        let n = atomicLoad(&counts[lid]);
        bases[lid] = atomicAdd(&args[lid * 4u + 1u], n);
        if (lid == 2u) {
            // The far level's blades are one triangle each (`LOD_SEGMENTS[2]` is 1).
            atomicAdd(&args[16u], 3u * n);
        }
    } else if (lid < 6u) {
        atomicAdd(&args[12u + lid - 3u], atomicLoad(&counts[lid]));
    }
    workgroupBarrier();
    if (verdict < 3u) {
        visible[verdict * C.capacity + bases[verdict] + slot] = k;
    }
}

// The deformed tip (xyz) and its shade (w): what the vertex shader draws at the top of each
// blade, for either model.
@compute @workgroup_size(64)
fn tips_main(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let k = blade_index(wid, nwg, lid);
    if (k >= S.blades) {
        return;
    }
    let b = blades[k];
    let p = curve_point(k, b, 1.0);
    tips[k] = vec4<f32>(p, curve_shade(k, b, p.y - ground(b.pos)));
}
