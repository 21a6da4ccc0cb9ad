// Map view, compute: the field's peaks (speed, |curl|, |pressure|) the colour scales are
// normalised by, gathered on the GPU so drawing needs no read-back. Non-negative f32 values
// order as their bit patterns, so an atomic max over the bits is the max of the values.
// CPU twin: the maxima in `app::view::field_image`.

@group(1) @binding(0) var<storage, read_write> stats: array<atomic<u32>, 4>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= V.nx || id.y >= V.ny) {
        return;
    }
    let speed = length(cell_velocity(id.x, id.y));
    let curl = abs(cell_curl(id.x, id.y));
    let pressure = abs(p[id.y * V.nx + id.x]);
    // NaN never wins: its bits compare above every number, so leave it out.
    if (speed == speed) {
        atomicMax(&stats[0], bitcast<u32>(speed));
    }
    if (curl == curl) {
        atomicMax(&stats[1], bitcast<u32>(curl));
    }
    if (pressure == pressure) {
        atomicMax(&stats[2], bitcast<u32>(pressure));
    }
}
