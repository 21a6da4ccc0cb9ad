// Step 2: vorticity at cell centres, ∂v/∂x − ∂u/∂z, central differences (one-sided at
// non-periodic edges), 0 in solids. CPU twin: `Solver::compute_curl`.

@group(0) @binding(1) var<storage, read> u: array<f32>;
@group(0) @binding(2) var<storage, read> v: array<f32>;
@group(0) @binding(3) var<storage, read> solid: array<u32>;
@group(0) @binding(4) var<storage, read_write> curl: array<f32>;

fn uc(i: u32, j: u32) -> f32 {
    let w = P.nx + 1u;
    return 0.5 * (u[j * w + i] + u[j * w + i + 1u]);
}

fn vc(i: u32, j: u32) -> f32 {
    return 0.5 * (v[j * P.nx + i] + v[(j + 1u) * P.nx + i]);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    if (i >= P.nx || j >= P.ny) {
        return;
    }
    let k = j * P.nx + i;
    if (solid[k] != 0u) {
        curl[k] = 0.0;
        return;
    }
    let ni = neighbours(i, P.nx);
    let nj = neighbours(j, P.ny);
    let dvdx = (vc(ni.y, j) - vc(ni.x, j)) / (P.hx * clamp(abs(f32(ni.y) - f32(ni.x)), 1.0, 2.0));
    let dudz = (uc(i, nj.y) - uc(i, nj.x)) / (P.hz * clamp(abs(f32(nj.y) - f32(nj.x)), 1.0, 2.0));
    curl[k] = dvdx - dudz;
}
