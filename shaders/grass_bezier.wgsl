// Grass, compute: Jahrmann & Wimmer's physics blades (issue 12) — each blade's Bezier control
// points advanced by `steps` fixed steps: gravity (environmental and front), recovery toward
// the rest tip (moved toward the ground where the trail crushes the grass), wind from the
// blade's wind cell (eq. 1) weighted by direction alignment and height ratio, the pushing
// sphere's collision with the tip and the curve's middle, then state validation (tip above
// the ground, guide from the tip's lean, the length restored from an 8-chord measure). CPU
// twin: `grass::bezier::State::step_pushed`.

struct Physics {
    steps: u32,
    dt: f32,
    recovery: f32,
    wind_k: f32,
}

@group(1) @binding(0) var<storage, read_write> states: array<BezierState>;
@group(1) @binding(1) var<storage, read> PH: Physics;

const GRAVITY: f32 = 9.81;
const LENGTH_CHORDS: u32 = 8u;
// `bezier::CRUSHED`: a fully crushed blade's rest tip, as fractions of its height.
const CRUSHED: vec2<f32> = vec2<f32>(0.95, 0.3);

fn curve_length(v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>) -> f32 {
    var l = 0.0;
    for (var k = 1u; k <= LENGTH_CHORDS; k = k + 1u) {
        let a = bezier_point(v0, v1, v2, f32(k) / f32(LENGTH_CHORDS));
        let b = bezier_point(v0, v1, v2, f32(k - 1u) / f32(LENGTH_CHORDS));
        l = l + length(a - b);
    }
    return l;
}

// `State::collide`: how far the sphere pushes point `p` out of itself.
fn sphere_out(p: vec3<f32>) -> vec3<f32> {
    let d = p - S.sphere.xyz;
    let l = length(d);
    if (l < S.sphere.w && l > 1e-6) {
        return d * ((S.sphere.w - l) / l);
    }
    return vec3<f32>(0.0);
}

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
    let b = blades[k];
    let up = vec3<f32>(0.0, 1.0, 0.0);
    let h = b.height;
    let front = vec3<f32>(cos(b.facing), 0.0, sin(b.facing));
    let g = vec3<f32>(0.0, -GRAVITY, 0.0) + front * (0.25 * GRAVITY);
    let w2 = blade_wind(b);
    let wind = vec3<f32>(w2.x, 0.0, w2.y);
    let speed = length(wind);
    var v0 = states[k].v0.xyz;
    var v1 = states[k].v1.xyz;
    var v2 = states[k].v2.xyz;
    // A slot given another blade (`GrassRenderer::replace_blades`) starts it at rest.
    if (v0.x != b.pos.x || v0.z != b.pos.y) {
        v0 = vec3<f32>(b.pos.x, 0.0, b.pos.y);
        v1 = v0 + up * h;
        v2 = v1;
        states[k].v0 = vec4<f32>(v0, 0.0);
    }
    let crush = trail_crush(b.pos, front.xz);
    let crushed = v0 + vec3<f32>(crush.y * CRUSHED.x * h, CRUSHED.y * h, crush.z * CRUSHED.x * h);
    let iv2 = (v0 + up * h) * (1.0 - crush.x) + crushed * crush.x;
    for (var n = 0u; n < PH.steps; n = n + 1u) {
        let r = (iv2 - v2) * (b.stiffness * PH.recovery);
        let lean = v2 - v0;
        var w = vec3<f32>(0.0);
        if (speed > 0.0 && length(lean) > 0.0) {
            let fd = 1.0 - abs(dot(wind / speed, lean / length(lean)));
            let fr = dot(lean, up) / h;
            w = wind * (PH.wind_k * fd * fr);
        }
        v2 = v2 + (g + r + w) * PH.dt;
        if (S.sphere.w > 0.0) {
            let mid = v0 * 0.25 + v1 * 0.5 + v2 * 0.25;
            v2 = v2 + sphere_out(v2) + sphere_out(mid) * 4.0;
        }
        // Validation.
        v2 = v2 - up * min(dot(up, v2 - v0), 0.0);
        let d = v2 - v0;
        let lproj = length(d - up * dot(d, up));
        v1 = v0 + up * (h * max(1.0 - lproj / h, 0.05 * max(lproj / h, 1.0)));
        let l = curve_length(v0, v1, v2);
        if (l > 0.0) {
            let s = h / l;
            let v1c = v0 + (v1 - v0) * s;
            v2 = v1c + (v2 - v1) * s;
            v1 = v1c;
        }
    }
    states[k].v1 = vec4<f32>(v1, 0.0);
    states[k].v2 = vec4<f32>(v2, 0.0);
}

// Every blade upright at rest (`State::rest`): the states made on the GPU, so a switch of
// model needs no copy of the blades on the CPU.
@compute @workgroup_size(64)
fn rest_main(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let k = blade_index(wid, nwg, lid);
    if (k >= S.blades) {
        return;
    }
    let b = blades[k];
    let v0 = vec3<f32>(b.pos.x, 0.0, b.pos.y);
    let top = v0 + vec3<f32>(0.0, b.height, 0.0);
    states[k] = BezierState(vec4<f32>(v0, 0.0), vec4<f32>(top, 0.0), vec4<f32>(top, 0.0));
}
