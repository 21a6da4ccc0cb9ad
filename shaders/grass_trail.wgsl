// Grass, compute: the pushing sphere's trail (`grass::trail::Trail::step`, its CPU twin) — each
// texel's remaining life falls by dt / lifetime, then the sphere's footprint stamps
// 1 − (d/r)² where that is higher. Reads the trail (group 0) and writes the next one; the
// renderer copies it back before the grass reads it.

@group(1) @binding(0) var next: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= S.trail_nx || id.y >= S.trail_ny) {
        return;
    }
    var fall = 1.0;
    if (S.lifetime > 0.0) {
        fall = S.dt / S.lifetime;
    }
    var v = max(textureLoad(trail, vec2<i32>(id.xy), 0).r - fall, 0.0);
    if (S.sphere.w > 0.0) {
        let p = S.trail_origin + (vec2<f32>(id.xy) + vec2<f32>(0.5)) * S.trail_cell;
        let d = p - S.sphere.xz;
        let d2 = dot(d, d);
        let r2 = S.sphere.w * S.sphere.w;
        if (d2 < r2) {
            v = max(v, 1.0 - d2 / r2);
        }
    }
    textureStore(next, vec2<i32>(id.xy), vec4<f32>(v, 0.0, 0.0, 0.0));
}
