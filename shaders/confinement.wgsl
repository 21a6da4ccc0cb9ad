// Step 3: vorticity confinement, f = r(ε)·h·min(1, |v|/U)·w·(N_z, −N_x) with N the
// (regularised) unit gradient of |w| and U the layout's wind (`Confinement`), first
// at cell centres (`force`; zero in the cells along an open edge, whose inflow would feed it
// back), then averaged onto the free faces (`apply_u`, `apply_v`), each clamped to
// ±max_speed. The limiter: confinement takes no face past the layout's reference speed
// (`P.speed_cap`), nor further past it than it already is. CPU twin:
// `Solver::confine_vorticity`.

@group(0) @binding(1) var<storage, read> curl: array<f32>;
@group(0) @binding(2) var<storage, read_write> fx: array<f32>;
@group(0) @binding(3) var<storage, read_write> fz: array<f32>;
@group(0) @binding(4) var<storage, read_write> u: array<f32>;
@group(0) @binding(5) var<storage, read_write> v: array<f32>;
@group(0) @binding(6) var<storage, read> u_free: array<u32>;
@group(0) @binding(7) var<storage, read> v_free: array<u32>;

@compute @workgroup_size(8, 8)
fn force(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    if (i >= P.nx || j >= P.ny) {
        return;
    }
    let nx = P.nx;
    if (P.open != 0u && (i == 0u || j == 0u || i == nx - 1u || j == P.ny - 1u)) {
        fx[j * nx + i] = 0.0;
        fz[j * nx + i] = 0.0;
        return;
    }
    let ni = neighbours(i, nx);
    let nj = neighbours(j, P.ny);
    let w = curl[j * nx + i];
    let gx = 0.5 * (abs(curl[j * nx + ni.y]) - abs(curl[j * nx + ni.x]));
    let gz = 0.5 * (abs(curl[nj.y * nx + i]) - abs(curl[nj.x * nx + i]));
    // `vorticity::confinement_norm`: β·w in the norm, so the direction fades to zero across
    // a ridge of |w| instead of flipping (`CONFINEMENT_BETA`, 0.5).
    let bw = 0.5 * w;
    let len = sqrt(gx * gx + gz * gz + bw * bw) + 1e-5;
    // Scaled by the cell's speed over the reference speed, up to 1 (`Confinement::inv_speed`).
    let uc = 0.5 * (u[j * (nx + 1u) + i] + u[j * (nx + 1u) + i + 1u]);
    let vc = 0.5 * (v[j * nx + i] + v[(j + 1u) * nx + i]);
    let weight = min(length(vec2<f32>(uc, vc)) * P.inv_speed, 1.0);
    let s = P.eps * P.h * weight * w / len;
    fx[j * nx + i] = s * gz;
    fz[j * nx + i] = -s * gx;
}

@compute @workgroup_size(8, 8)
fn apply_u(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    let nx = P.nx;
    if (i > nx || j >= P.ny) {
        return;
    }
    let k = j * (nx + 1u) + i;
    if (u_free[k] == 0u) {
        return;
    }
    let wrap = P.periodic != 0u;
    let left = select(i - 1u, select(0u, nx - 1u, wrap), i == 0u);
    let right = select(i, select(nx - 1u, 0u, wrap), i == nx);
    let a = fx[j * nx + left];
    let b = fx[j * nx + right];
    let m = max(abs(u[k]), P.speed_cap);
    u[k] = clamp(clamp(u[k] + P.dt * 0.5 * (a + b), -m, m), -P.max_speed, P.max_speed);
}

@compute @workgroup_size(8, 8)
fn apply_v(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    let nx = P.nx;
    let ny = P.ny;
    if (i >= nx || j > ny) {
        return;
    }
    let k = j * nx + i;
    if (v_free[k] == 0u) {
        return;
    }
    let wrap = P.periodic != 0u;
    let below = select(j - 1u, select(0u, ny - 1u, wrap), j == 0u);
    let above = select(j, select(ny - 1u, 0u, wrap), j == ny);
    let m = max(abs(v[k]), P.speed_cap);
    let pushed = clamp(v[k] + P.dt * 0.5 * (fz[below * nx + i] + fz[above * nx + i]), -m, m);
    v[k] = clamp(pushed, -P.max_speed, P.max_speed);
}
