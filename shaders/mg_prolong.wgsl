// Multigrid prolongation: adds the coarse correction to this level's cells in the solve,
// interpolated linearly between the coarse cells in the solve (along x within each coarse row,
// then between the two rows), an open edge beyond the last coarse centre counting as a cell in
// the solve that holds 0. CPU twin: `multigrid::expand` then `multigrid::add_correction`.

// Mirrored by `sim::solver::multigrid::Interp`: (1 − t)·near + t·far; far = EDGE for the edge.
struct Interp {
    near: u32,
    far: u32,
    t: f32,
}

const EDGE: u32 = 0xffffffffu;

@group(0) @binding(2) var<storage, read_write> x_fine: array<f32>;
@group(0) @binding(3) var<storage, read> coarse_x: array<f32>;
@group(0) @binding(6) var<storage, read> coarse_inv_d: array<f32>;
@group(0) @binding(7) var<storage, read> fine_inv_d: array<f32>;
@group(0) @binding(8) var<storage, read> from_x: array<Interp>;
@group(0) @binding(9) var<storage, read> from_z: array<Interp>;

// The correction along x in coarse row jc at fine column i, and the weight behind it.
fn expand(jc: u32, i: u32) -> vec2<f32> {
    let ix = from_x[i];
    let row = jc * M.cnx;
    let ma = select(0.0, 1.0, coarse_inv_d[row + ix.near] > 0.0);
    let wa = 1.0 - ix.t;
    var xb = 0.0;
    var mb = 1.0;
    if (ix.far != EDGE) {
        xb = coarse_x[row + ix.far];
        mb = select(0.0, 1.0, coarse_inv_d[row + ix.far] > 0.0);
    }
    return vec2<f32>(wa * ma * coarse_x[row + ix.near] + ix.t * mb * xb, wa * ma + ix.t * mb);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    if (i >= M.nx || j >= M.ny) {
        return;
    }
    let iz = from_z[j];
    let n = expand(iz.near, i);
    var f = n;
    var ke = 1.0;
    var kw = 0.0;
    if (iz.far == EDGE) {
        ke = 0.0;
        kw = 1.0;
    } else {
        f = expand(iz.far, i);
    }
    let tn = 1.0 - iz.t;
    let tf = iz.t;
    let num = tn * n.x + tf * (ke * f.x);
    let den = tn * n.y + tf * (ke * f.y + kw);
    let k = j * M.nx + i;
    if (fine_inv_d[k] > 0.0 && den > 0.0) {
        x_fine[k] = x_fine[k] + num / den;
    }
}
