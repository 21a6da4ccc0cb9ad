// Step 5: the pressure solve. `decay` scales the previous pressure (the warm start); `main` is
// one Jacobi sweep p ← (wx (p_L + p_R) + wz (p_B + p_T) − div) / Σw over the neighbours that take
// part (flags: L 1, R 2, B 4, T 8; solids and closed walls drop out, open edges hold p = 0
// outside), with `inv_w` the cell's 1 / Σw (0 outside the solve).
// CPU twin: `Solver::jacobi_iteration` (and the blocked `Solver::solve_pressure`).

@group(0) @binding(1) var<storage, read> p_in: array<f32>;
@group(0) @binding(2) var<storage, read_write> p_out: array<f32>;
@group(0) @binding(3) var<storage, read> div: array<f32>;
@group(0) @binding(4) var<storage, read> flags: array<u32>;
@group(0) @binding(5) var<storage, read> inv_w: array<f32>;
@group(0) @binding(6) var<storage, read_write> p: array<f32>;

fn pick(fl: u32, bit: u32, x: f32) -> f32 {
    return select(0.0, x, (fl & bit) != 0u);
}

@compute @workgroup_size(64)
fn decay(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(num_workgroups) nwg: vec3<u32>,
) {
    let k = flat_index(id, nwg);
    if (k < P.nx * P.ny) {
        p[k] = p[k] * P.decay;
    }
}

// One sweep's value at cell (i, j) from its neighbours' previous values `l`, `r` (along x),
// `b`, `t` (along z); those the flags drop are never read into the sum.
fn sweep_at(i: u32, j: u32, l: f32, r: f32, b: f32, t: f32) -> f32 {
    let k = j * P.nx + i;
    let fl = flags[k];
    return (P.wx * (pick(fl, 1u, l) + pick(fl, 2u, r)) + P.wz * (pick(fl, 4u, b) + pick(fl, 8u, t))
        - div[k]) * inv_w[k];
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let j = id.y;
    let nx = P.nx;
    let ny = P.ny;
    if (i >= nx || j >= ny) {
        return;
    }
    // Rows beyond the grid have zero weight unless periodic; a row's ends wrap (used only
    // where the periodic flags say so).
    var jb = select(j - 1u, 0u, j == 0u);
    var jt = min(j + 1u, ny - 1u);
    if (P.periodic != 0u) {
        jb = (j + ny - 1u) % ny;
        jt = (j + 1u) % ny;
    }
    let il = select(i - 1u, nx - 1u, i == 0u);
    let ir = select(i + 1u, 0u, i == nx - 1u);
    p_out[j * nx + i] = sweep_at(
        i,
        j,
        p_in[j * nx + il],
        p_in[j * nx + ir],
        p_in[jb * nx + i],
        p_in[jt * nx + i],
    );
}

// Two sweeps in one dispatch (`pair`): each 16 × 16 workgroup loads its tile of the previous
// iterate with a margin of two cells (20 × 20), makes the first sweep over the tile and a
// margin of one (18 × 18) in workgroup memory, then the second over the tile. The values are
// `main`'s twice, bit for bit: each cell's arithmetic is `sweep_at`'s, on the same
// neighbours (wrapped when periodic; off the grid otherwise, where the flags drop them).
// Half the dispatches and half the reads of the previous iterate for 1.27× the arithmetic.
const TILE: u32 = 16u;
var<workgroup> tile_p: array<f32, 400>;
var<workgroup> tile_m: array<f32, 324>;

// The cell a tile position `c` (from −2 to n + 17) on an axis of `n` cells stands for:
// wrapped when periodic, else clamped (a clamped margin cell is only ever read where the
// flags drop it). The wrap takes an unsigned remainder of `c + n`, never negative: GLSL
// leaves `%` of a negative number undefined, and on the GL backend llvmpipe got it wrong.
fn cell_of(c: i32, n: u32) -> u32 {
    if (P.periodic != 0u) {
        return u32(c + i32(n)) % n;
    }
    return u32(clamp(c, 0, i32(n) - 1));
}

@compute @workgroup_size(16, 16)
fn pair(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let nx = P.nx;
    let ny = P.ny;
    let i0 = i32(wid.x * TILE) - 2;
    let j0 = i32(wid.y * TILE) - 2;
    for (var s = lid; s < 400u; s = s + 256u) {
        let ci = cell_of(i0 + i32(s % 20u), nx);
        let cj = cell_of(j0 + i32(s / 20u), ny);
        tile_p[s] = p_in[cj * nx + ci];
    }
    workgroupBarrier();
    for (var s = lid; s < 324u; s = s + 256u) {
        let ti = s % 18u;
        let tj = s / 18u;
        let gi = i0 + 1 + i32(ti);
        let gj = j0 + 1 + i32(tj);
        var v = 0.0;
        if (P.periodic != 0u || (gi >= 0 && gi < i32(nx) && gj >= 0 && gj < i32(ny))) {
            let c = (tj + 1u) * 20u + ti + 1u;
            v = sweep_at(
                cell_of(gi, nx),
                cell_of(gj, ny),
                tile_p[c - 1u],
                tile_p[c + 1u],
                tile_p[c - 20u],
                tile_p[c + 20u],
            );
        }
        tile_m[s] = v;
    }
    workgroupBarrier();
    let ti = lid % TILE;
    let tj = lid / TILE;
    let i = wid.x * TILE + ti;
    let j = wid.y * TILE + tj;
    if (i < nx && j < ny) {
        let c = (tj + 1u) * 18u + ti + 1u;
        p_out[j * nx + i] = sweep_at(i, j, tile_m[c - 1u], tile_m[c + 1u], tile_m[c - 18u], tile_m[c + 18u]);
    }
}
