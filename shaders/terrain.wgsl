// The terrain's hand on the wind as it leaves the solver: each face's velocity shaped by the
// slope and curvature of the ground (docs/SOLVER.md, "Terrain"), written to the shaped copies
// the map and the grass read. Never part of the solve.
// CPU twin: `sim::terrain::TerrainField::shape_faces` and `sim::terrain::shape`.

// Mirrors `sim::terrain::Cell`.
struct Cell {
    slope: vec2<f32>,
    base: f32,
    ws: f32,
    across: vec2<f32>,
    kappa: f32,
    pad: f32,
}

@group(0) @binding(1) var<storage, read> u: array<f32>;
@group(0) @binding(2) var<storage, read> v: array<f32>;
// Each face's coefficients (`TerrainField::faces`): the u faces, then the v faces.
@group(0) @binding(3) var<storage, read> faces: array<Cell>;
@group(0) @binding(4) var<storage, read_write> u_out: array<f32>;
@group(0) @binding(5) var<storage, read_write> v_out: array<f32>;
// A face that is not free (a wall, a solid's side) stays still.
@group(0) @binding(6) var<storage, read> u_free: array<u32>;
@group(0) @binding(7) var<storage, read> v_free: array<u32>;

// `sim::terrain::shape`, branch-free as it is.
fn shape(w: vec2<f32>, c: Cell) -> vec2<f32> {
    let speed = sqrt(w.x * w.x + w.y * w.y);
    let inv = select(0.0, 1.0 / speed, speed > 0.0);
    let along = clamp((c.slope.x * w.x + c.slope.y * w.y) * inv, -1.0, 1.0);
    let k = max(c.base + c.ws * along, 0.0);
    let d = c.kappa * (w.x * c.across.x + w.y * c.across.y);
    let t = vec2<f32>(w.x - d * c.across.x, w.y - d * c.across.y);
    let len = sqrt(t.x * t.x + t.y * t.y);
    let f = select(0.0, k * speed / len, len > 0.0);
    return vec2<f32>(t.x * f, t.y * f);
}

fn vf(i: i32, j: u32) -> f32 {
    return v[j * P.nx + u32(clamp(i, 0, i32(P.nx) - 1))];
}

fn uf(i: u32, j: i32) -> f32 {
    return u[u32(clamp(j, 0, i32(P.ny) - 1)) * (P.nx + 1u) + i];
}

@compute @workgroup_size(8, 8)
fn shape_u(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    if (i > P.nx || j >= P.ny) {
        return;
    }
    let k = j * (P.nx + 1u) + i;
    let il = i32(i) - 1;
    let ir = i32(i);
    let vbar = 0.25 * (vf(il, j) + vf(ir, j) + vf(il, j + 1u) + vf(ir, j + 1u));
    u_out[k] = select(0.0, shape(vec2<f32>(u[k], vbar), faces[k]).x, u_free[k] != 0u);
}

@compute @workgroup_size(8, 8)
fn shape_v(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    if (i >= P.nx || j > P.ny) {
        return;
    }
    let k = j * P.nx + i;
    let jb = i32(j) - 1;
    let jt = i32(j);
    let ubar = 0.25 * (uf(i, jb) + uf(i + 1u, jb) + uf(i, jt) + uf(i + 1u, jt));
    v_out[k] = select(0.0, shape(vec2<f32>(ubar, v[k]), faces[(P.nx + 1u) * P.ny + k]).y, v_free[k] != 0u);
}
