//! Steps 2–4: the curl, vorticity confinement and the divergence. Each is a pass of its own
//! (the GPU's twins, and what the per-pass tests compare), and [`Solver::vorticity_divergence`]
//! runs all three as one sweep down bands of rows, each row computed by the same row kernels,
//! so the fused sweep gives the passes' bits while reading the faces once instead of three
//! times and never writing the cell-centred forces out.

use super::*;

impl Solver {
    /// Steps 2–4 as the step runs them: one fused sweep (see the module notes), or, without
    /// vorticity confinement, the curl and divergence passes.
    pub fn vorticity_divergence(&mut self, dt: f32) {
        let eps = self.params.vorticity;
        if eps <= 0.0 {
            self.compute_curl();
            self.compute_divergence();
            return;
        }
        let (nx, ny) = (self.nx, self.ny);
        let ctx = Fused {
            nx,
            ny,
            hx: self.hx,
            hz: self.hz,
            conf: self.confinement(),
            dt,
            boundary: self.params.boundary,
            u: &self.u,
            v: &self.v,
            solid: &self.solid,
            u_free: &self.u_free,
            v_free: &self.v_free,
        };
        // Two bands per thread; each recomputes up to three rows of curl and two of forces
        // beyond its ends, so bands stay well over that.
        let rows = ny
            .div_ceil(2 * rayon::current_num_threads())
            .max(16)
            .min(ny);
        let (v_rows, v_last) = self.v_tmp.split_at_mut(ny * nx);
        self.curl
            .par_chunks_mut(rows * nx)
            .zip(self.div.par_chunks_mut(rows * nx))
            .zip(self.u_tmp.par_chunks_mut(rows * (nx + 1)))
            .zip(v_rows.par_chunks_mut(rows * nx))
            .enumerate()
            .for_each(|(k, (((curl, div), u), v))| {
                let a = k * rows;
                ctx.band(a, a + curl.len() / nx, Out { curl, div, u, v });
            });
        // The last row of v faces: a copy of the first when periodic (below); otherwise its
        // force is the last cell row's, made again from the finished curl.
        if ctx.boundary != Boundary::Periodic {
            let (mut fx, mut fz) = (vec![0.0; nx], vec![0.0; nx]);
            let j = ny - 1;
            let (jb, jt) = neighbours(j, ny, false);
            let c = |r: usize| &self.curl[r * nx..][..nx];
            let rows = (c(j), c(jb), c(jt));
            let faces = ctx.faces(j);
            cell_forces(&mut fx, &mut fz, rows, faces, ctx.conf, ctx.boundary, j, ny);
            v_last.copy_from_slice(&self.v[ny * nx..]);
            add_v_row(
                v_last,
                &self.v_free[ny * nx..],
                &fz,
                &fz,
                dt,
                ctx.conf.speed_cap,
            );
        }
        std::mem::swap(&mut self.u, &mut self.u_tmp);
        std::mem::swap(&mut self.v, &mut self.v_tmp);
        self.sync_periodic();
    }

    /// Step 2: vorticity at cell centres, `∂v/∂x − ∂u/∂z`, central differences (one-sided at
    /// non-periodic edges).
    pub fn compute_curl(&mut self) {
        let (nx, ny) = (self.nx, self.ny);
        let (hx, hz) = (self.hx, self.hz);
        let periodic = self.params.boundary == Boundary::Periodic;
        let (u, v, solid) = (&self.u, &self.v, &self.solid);
        self.curl
            .par_chunks_mut(nx)
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, row)| curl_row(row, j, nx, ny, hx, hz, periodic, u, v, solid));
    }

    /// Step 3: vorticity confinement, `f = r(ε)·h·min(1, |v|/U)·w·(N_z, −N_x)` with `N` the
    /// (regularised) unit gradient of `|w|`, pushing along the rotation so small eddies
    /// survive advection, and taking no face past `U` ([`Confinement`]); none in the cells
    /// along an open edge (docs/SOLVER.md, step 3).
    pub fn confine_vorticity(&mut self, dt: f32) {
        let eps = self.params.vorticity;
        if eps <= 0.0 {
            return;
        }
        let (nx, ny) = (self.nx, self.ny);
        let boundary = self.params.boundary;
        let periodic = boundary == Boundary::Periodic;
        let conf = self.confinement();
        let cap = conf.speed_cap;
        let curl = &self.curl;
        let (u, v) = (&self.u, &self.v);
        // Cell-centred force: x into p_tmp, z into div (both free until the divergence pass).
        self.p_tmp
            .par_chunks_mut(nx)
            .zip(self.div.par_chunks_mut(nx))
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, (fx, fz))| {
                let (jb, jt) = neighbours(j, ny, periodic);
                let c = |r: usize| &curl[r * nx..][..nx];
                let faces = row_faces(u, v, nx, j);
                cell_forces(fx, fz, (c(j), c(jb), c(jt)), faces, conf, boundary, j, ny);
            });
        let (fx, fz) = (&self.p_tmp, &self.div);
        let (u_free, v_free) = (&self.u_free, &self.v_free);
        self.u
            .par_chunks_mut(nx + 1)
            .enumerate()
            .with_min_len(rows_per_job(nx + 1))
            .for_each(|(j, row)| {
                let free = &u_free[j * (nx + 1)..][..nx + 1];
                add_u_row(row, free, &fx[j * nx..][..nx], periodic, dt, cap);
            });
        self.v
            .par_chunks_mut(nx)
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, row)| {
                let (jb, jt) = face_cells(j, ny, periodic);
                let free = &v_free[j * nx..][..nx];
                add_v_row(
                    row,
                    free,
                    &fz[jb * nx..][..nx],
                    &fz[jt * nx..][..nx],
                    dt,
                    cap,
                );
            });
        self.sync_periodic();
    }

    /// Step 4: divergence per cell, `(u_R − u_L)/hx + (v_T − v_B)/hz` (0 in solids).
    pub fn compute_divergence(&mut self) {
        let (nx, hx, hz) = (self.nx, self.hx, self.hz);
        let (u, v, solid) = (&self.u, &self.v, &self.solid);
        self.div
            .par_chunks_mut(nx)
            .enumerate()
            .with_min_len(rows_per_job(nx))
            .for_each(|(j, row)| {
                divergence_row(
                    row,
                    &u[j * (nx + 1)..][..nx + 1],
                    &v[j * nx..][..nx],
                    &v[(j + 1) * nx..][..nx],
                    &solid[j * nx..][..nx],
                    hx,
                    hz,
                );
            });
    }
}

/// The faces around cell row `j` of a grid `nx` cells wide: its `nx + 1` u faces, and the
/// rows of v faces below and above it (what a cell's speed is read from).
fn row_faces<'a>(
    u: &'a [f32],
    v: &'a [f32],
    nx: usize,
    j: usize,
) -> (&'a [f32], &'a [f32], &'a [f32]) {
    (
        &u[j * (nx + 1)..][..nx + 1],
        &v[j * nx..][..nx],
        &v[(j + 1) * nx..][..nx],
    )
}

/// The cells below and above v face row `j` (the end rows wrap when periodic, else see the
/// one cell beside them).
fn face_cells(j: usize, ny: usize, periodic: bool) -> (usize, usize) {
    let jb = match j {
        0 if periodic => ny - 1,
        0 => 0,
        _ => j - 1,
    };
    let jt = match j {
        _ if j < ny => j,
        _ if periodic => 0,
        _ => ny - 1,
    };
    (jb, jt)
}

/// Row `j` of the curl from the faces `u`, `v` (whole arrays).
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
fn curl_row(
    row: &mut [f32],
    j: usize,
    nx: usize,
    ny: usize,
    hx: f32,
    hz: f32,
    periodic: bool,
    u: &[f32],
    v: &[f32],
    solid: &[u8],
) {
    let w = nx + 1;
    let (jb, jt) = neighbours(j, ny, periodic);
    let dz = hz * (jt as f32 - jb as f32).abs().clamp(1.0, 2.0);
    let (ub, ut) = (&u[jb * w..][..w], &u[jt * w..][..w]);
    let (v0, v1) = (&v[j * nx..][..nx], &v[(j + 1) * nx..][..nx]);
    let sd = &solid[j * nx..][..nx];
    for i in row_ends(nx) {
        let (il, ir) = neighbours(i, nx, periodic);
        let vc = |i: usize| 0.5 * (v0[i] + v1[i]);
        let dx = hx * (ir as f32 - il as f32).abs().clamp(1.0, 2.0);
        let dvdx = (vc(ir) - vc(il)) / dx;
        let dudz = (0.5 * (ut[i] + ut[i + 1]) - 0.5 * (ub[i] + ub[i + 1])) / dz;
        row[i] = if sd[i] != 0 { 0.0 } else { dvdx - dudz };
    }
    if nx > 2 {
        curl_interior(row, sd, ub, ut, v0, v1, hx * 2.0, dz);
    }
}

/// The curl of a row's interior cells (`|ir − il| = 2` there, so `dx = 2 hx`).
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
#[simd_kernel]
fn curl_interior(
    row: &mut [f32],
    sd: &[u8],
    ub: &[f32],
    ut: &[f32],
    v0: &[f32],
    v1: &[f32],
    dx: f32,
    dz: f32,
) {
    let n = row.len() - 2;
    let (o, sd) = (&mut row[1..=n], &sd[1..=n]);
    let (v0l, v0r, v1l, v1r) = (&v0[..n], &v0[2..], &v1[..n], &v1[2..]);
    let (ub0, ub1, ut0, ut1) = (&ub[1..=n], &ub[2..=n + 1], &ut[1..=n], &ut[2..=n + 1]);
    for k in 0..n {
        let dvdx = (0.5 * (v0r[k] + v1r[k]) - 0.5 * (v0l[k] + v1l[k])) / dx;
        let dudz = (0.5 * (ut0[k] + ut1[k]) - 0.5 * (ub0[k] + ub1[k])) / dz;
        o[k] = if sd[k] != 0 { 0.0 } else { dvdx - dudz };
    }
}

/// How much of the curl `w` a cell's gradient of `|w|` must reach (per cell) before the
/// confinement's direction is taken as a unit vector: `N = ∇|w| / √(|∇|w||² + (β·w)²)`.
///
/// The textbook `N̂ = ∇|w| / |∇|w||` flips sign across every ridge of `|w|` — the flank of an
/// arrow's jet, the core of an eddy — where its gradient vanishes, so the force there jumped
/// by `2·ε·h·|w|` on a last bit: the GPU and the CPU fields parted by up to a quarter of the
/// peak speed on two-winds after 120 steps from that alone (5e-6 of it without confinement).
/// With `β·w` in the norm the direction fades to zero at a ridge instead of flipping, the
/// smallest eddies (a gradient of about half the curl a cell) keep 71 % of their push, and
/// broad features, whose gradient is a small part of their curl a cell, get less: the force
/// is continuous and acts at the grid's scale, as confinement is meant to. β = 0.5 brings
/// every example's GPU field within 1e-4 of the CPU's peak speed after 120 steps (0.25 left
/// 1.3e-3 on branching).
pub const CONFINEMENT_BETA: f32 = 0.5;

/// The norm [`CONFINEMENT_BETA`] describes (with `1e-5` for a cell of no curl at all).
#[inline(always)]
pub(super) fn confinement_norm(gx: f32, gz: f32, w: f32) -> f32 {
    let bw = CONFINEMENT_BETA * w;
    (gx * gx + gz * gz + bw * bw).sqrt() + 1e-5
}

/// The confinement force of one cell from its curl `w` and its neighbours' `l, r, b, t`.
#[inline(always)]
fn force(conf: Confinement, speed: f32, w: f32, l: f32, r: f32, b: f32, t: f32) -> (f32, f32) {
    let gx = 0.5 * (r.abs() - l.abs());
    let gz = 0.5 * (t.abs() - b.abs());
    let len = confinement_norm(gx, gz, w);
    let s = conf.eps_h * (speed * conf.inv_speed).min(1.0) * w / len;
    (s * gz, -s * gx)
}

/// The cell-centred confinement force `(fx, fz)` of cell row `j` of `ny`, from the curl
/// rows `(c, cb, ct)`: the row's own, and those below and above it ([`force_row`]).
///
/// Along an open edge (its first and last rows, and every row's first and last cell) the
/// force is zero. The air that enters through an open edge keeps the edge's velocity
/// (zero-gradient advection), so a force there is fed back into each later step's inflow
/// instead of being carried away, and the curl's one-sided differences there push along the
/// edge: at ε = 2, thin jets grew at the inflow edges and ran into the map, to 10× the
/// arrows' strength on `branching.json` (docs/RELIABILITY.md). Closed and periodic edges are
/// pushed as before.
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
fn cell_forces(
    fx: &mut [f32],
    fz: &mut [f32],
    (c, cb, ct): (&[f32], &[f32], &[f32]),
    faces: (&[f32], &[f32], &[f32]),
    conf: Confinement,
    boundary: Boundary,
    j: usize,
    ny: usize,
) {
    let open = boundary == Boundary::Open;
    if open && (j == 0 || j + 1 == ny) {
        fx.fill(0.0);
        fz.fill(0.0);
    } else {
        force_row(fx, fz, c, cb, ct, faces, conf, boundary);
    }
}

/// The cell-centred confinement force of a row, `(fx, fz)`, from its curl `c` and the curl
/// rows below and above it; zero in its end cells on an open grid (see [`cell_forces`]).
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
#[simd_kernel]
fn force_row(
    fx: &mut [f32],
    fz: &mut [f32],
    c: &[f32],
    cb: &[f32],
    ct: &[f32],
    (ur, vb, vt): (&[f32], &[f32], &[f32]),
    conf: Confinement,
    boundary: Boundary,
) {
    let nx = c.len();
    let periodic = boundary == Boundary::Periodic;
    // As the GPU's `length`: √(x² + z²) of the face means.
    let speed = |a: f32, b: f32, c: f32, d: f32| {
        let (x, z) = (0.5 * (a + b), 0.5 * (c + d));
        (x * x + z * z).sqrt()
    };
    for i in row_ends(nx) {
        let (il, ir) = neighbours(i, nx, periodic);
        (fx[i], fz[i]) = if boundary == Boundary::Open {
            (0.0, 0.0)
        } else {
            let sp = speed(ur[i], ur[i + 1], vb[i], vt[i]);
            force(conf, sp, c[i], c[il], c[ir], cb[i], ct[i])
        };
    }
    let Some(n) = nx.checked_sub(2) else { return };
    let (fxi, fzi) = (&mut fx[1..=n], &mut fz[1..=n]);
    let (cl, cc, cr) = (&c[..n], &c[1..=n], &c[2..]);
    let (cb, ct) = (&cb[1..=n], &ct[1..=n]);
    let (ul, urr, vb, vt) = (&ur[1..=n], &ur[2..=n + 1], &vb[1..=n], &vt[1..=n]);
    for k in 0..n {
        let sp = speed(ul[k], urr[k], vb[k], vt[k]);
        (fxi[k], fzi[k]) = force(conf, sp, cc[k], cl[k], cr[k], cb[k], ct[k]);
    }
}

/// A face's velocity `x` with the mean of the two confinement forces `a`, `b` beside it
/// added over `dt`, limited and flushed: what [`add_u_row`] and [`add_v_row`] store. The
/// limiter: confinement takes no face past `cap`, the layout's reference speed, nor further
/// past it than it already is ([`Confinement::speed_cap`]).
#[inline(always)]
fn confined(x: f32, a: f32, b: f32, dt: f32, cap: f32) -> f32 {
    let m = x.abs().max(cap);
    flush(clamp_speed((x + dt * 0.5 * (a + b)).clamp(-m, m)))
}

/// Adds the force `f` (cell-centred x, one row) to a row of u faces where they are free: each
/// face gets the mean of the cells beside it (the end faces: the wrapped cell when periodic,
/// else the one cell beside them).
#[simd_kernel]
fn add_u_row(row: &mut [f32], free: &[u8], f: &[f32], periodic: bool, dt: f32, cap: f32) {
    let nx = f.len();
    let add = |x: f32, a: f32, b: f32| confined(x, a, b, dt, cap);
    let (first, last) = if periodic { (nx - 1, 0) } else { (0, nx - 1) };
    if free[0] != 0 {
        row[0] = add(row[0], f[first], f[0]);
    }
    if free[nx] != 0 {
        row[nx] = add(row[nx], f[nx - 1], f[last]);
    }
    let (r, fr) = (&mut row[1..nx], &free[1..nx]);
    let (a, b) = (&f[..nx - 1], &f[1..]);
    // Computed everywhere, kept where free: branch-free, so it vectorises.
    for k in 0..nx - 1 {
        let x = r[k];
        r[k] = bit_select(fr[k] != 0, add(x, a[k], b[k]), x);
    }
}

/// Adds the mean of the z forces of the cells below (`a`) and above (`b`) to a row of v faces
/// where they are free.
#[simd_kernel]
fn add_v_row(row: &mut [f32], free: &[u8], a: &[f32], b: &[f32], dt: f32, cap: f32) {
    let add = |x: f32, a: f32, b: f32| confined(x, a, b, dt, cap);
    let n = row.len();
    let (free, a, b) = (&free[..n], &a[..n], &b[..n]);
    // Computed everywhere, kept where free: branch-free, so it vectorises.
    for i in 0..n {
        let x = row[i];
        row[i] = bit_select(free[i] != 0, add(x, a[i], b[i]), x);
    }
}

/// One row of the divergence: `(u_R − u_L)/hx + (v_T − v_B)/hz` from its u faces `ur`
/// (`nx + 1`) and the v face rows below and above it (0 in solids).
#[simd_kernel]
pub(super) fn divergence_row(
    row: &mut [f32],
    ur: &[f32],
    vb: &[f32],
    vt: &[f32],
    s: &[u8],
    hx: f32,
    hz: f32,
) {
    let n = row.len();
    let (ul, urr, vb, vt, s) = (&ur[..n], &ur[1..=n], &vb[..n], &vt[..n], &s[..n]);
    for i in 0..n {
        row[i] = bit_select(s[i] != 0, 0.0, (urr[i] - ul[i]) / hx + (vt[i] - vb[i]) / hz);
    }
}

/// What every band of the fused sweep reads.
struct Fused<'a> {
    nx: usize,
    ny: usize,
    hx: f32,
    hz: f32,
    conf: Confinement,
    dt: f32,
    boundary: Boundary,
    u: &'a [f32],
    v: &'a [f32],
    solid: &'a [u8],
    u_free: &'a [u8],
    v_free: &'a [u8],
}

/// A band's rows of the fused sweep's outputs (`v`: its faces' rows, the band's first face
/// row to the one below its last cell row's top face).
struct Out<'a> {
    curl: &'a mut [f32],
    div: &'a mut [f32],
    u: &'a mut [f32],
    v: &'a mut [f32],
}

impl Fused<'_> {
    /// The faces around cell row `j` as the step found them: its u faces, and the v faces
    /// below and above it (what a cell's speed is read from).
    fn faces(&self, j: usize) -> (&[f32], &[f32], &[f32]) {
        row_faces(self.u, self.v, self.nx, j)
    }

    /// Cell rows `a..b` of the fused sweep: going down the band, each row's curl, then the
    /// forces of the row before it (whose curl neighbours are now known), its u faces and the
    /// v face below it, then the divergence of the row before that (whose faces are now all
    /// updated). Rows are virtual (they run past the grid's ends when periodic and wrap to
    /// real rows); curl and forces live in three-row rings, and rows beyond the band are
    /// computed but not written.
    fn band(&self, a: usize, b: usize, out: Out) {
        let (nx, ny, per) = (self.nx, self.ny, self.boundary == Boundary::Periodic);
        let (a, b, n) = (a as isize, b as isize, ny as isize);
        let real = |s: isize| s.rem_euclid(n) as usize;
        // The rows either side of virtual row `s` (clamped at non-periodic ends).
        let side = |s: isize| {
            if per {
                (s - 1, s + 1)
            } else {
                ((s - 1).max(0), (s + 1).min(n - 1))
            }
        };
        // Face f lies between cells f − 1 and f: faces a..=b need forces a − 1 ..= b.
        let (fa, fb) = if per {
            (a - 1, b)
        } else {
            ((a - 1).max(0), b.min(n - 1))
        };
        let (ca, cb) = (side(fa).0, side(fb).1);
        let slot = |s: isize| s.rem_euclid(3) as usize * nx;
        let mut curl = vec![0.0f32; 3 * nx];
        let (mut fx, mut fz) = (vec![0.0f32; 3 * nx], vec![0.0f32; 3 * nx]);
        // Face b's new values (the band's top face belongs to the next band).
        let mut top = vec![0.0f32; nx];
        let Out {
            curl: curl_out,
            div,
            u: u_out,
            v: v_out,
        } = out;
        let w = nx + 1;
        let mut next_div = a;
        for s in ca..=cb + 1 {
            if s <= cb {
                let r = real(s);
                let dst = &mut curl[slot(s)..][..nx];
                curl_row(
                    dst, r, nx, ny, self.hx, self.hz, per, self.u, self.v, self.solid,
                );
                if (a..b).contains(&s) {
                    curl_out[(s - a) as usize * nx..][..nx].copy_from_slice(dst);
                }
            }
            let t = s - 1;
            if t < fa || t > fb {
                continue;
            }
            let (tb, tt) = side(t);
            let c = |s: isize| &curl[slot(s)..][..nx];
            cell_forces(
                &mut fx[slot(t)..][..nx],
                &mut fz[slot(t)..][..nx],
                (c(t), c(tb), c(tt)),
                self.faces(real(t)),
                self.conf,
                self.boundary,
                real(t),
                ny,
            );
            if (a..b).contains(&t) {
                let r = real(t);
                let row = &mut u_out[(t - a) as usize * w..][..w];
                row.copy_from_slice(&self.u[r * w..][..w]);
                add_u_row(
                    row,
                    &self.u_free[r * w..][..w],
                    &fx[slot(t)..][..nx],
                    per,
                    self.dt,
                    self.conf.speed_cap,
                );
            }
            // The faces whose forces are now all known: face t, and past a closed or open
            // top the grid's last face (its one cell is t).
            let last = if !per && t == n - 1 { n } else { t };
            for f in t..=last {
                if f < a || f > b {
                    continue;
                }
                let (below, above) = if per {
                    (f - 1, f)
                } else {
                    ((f - 1).max(0), f.min(n - 1))
                };
                let r = if per { real(f) } else { f as usize };
                let dst = if f < b {
                    &mut v_out[(f - a) as usize * nx..][..nx]
                } else {
                    &mut top[..]
                };
                dst.copy_from_slice(&self.v[r * nx..][..nx]);
                add_v_row(
                    dst,
                    &self.v_free[r * nx..][..nx],
                    &fz[slot(below)..][..nx],
                    &fz[slot(above)..][..nx],
                    self.dt,
                    self.conf.speed_cap,
                );
            }
            // Divergence of the rows whose top face is done.
            while next_div < b && next_div < last {
                let k = (next_div - a) as usize;
                let vt = if next_div + 1 < b {
                    &v_out[(k + 1) * nx..][..nx]
                } else {
                    &top[..]
                };
                divergence_row(
                    &mut div[k * nx..][..nx],
                    &u_out[k * w..][..w],
                    &v_out[k * nx..][..nx],
                    vt,
                    &self.solid[real(next_div) * nx..][..nx],
                    self.hx,
                    self.hz,
                );
                next_div += 1;
            }
        }
        debug_assert_eq!(next_div, b, "every row's divergence was made");
    }
}

/// Up to this vorticity factor ε the confinement pushes at rate ε (1/s, times the cell size
/// and the curl): every layout made before the ceiling keeps its look ([`confinement_rate`]).
pub const CONFINEMENT_KNEE: f32 = 2.0;

/// The most the confinement's rate reaches, however large ε: above it confinement feeds
/// grid-scale eddies faster than advection and dissipation take them away, and the field
/// fills with noise at the arrows' speed (docs/SOLVER.md, step 3).
pub const CONFINEMENT_CEILING: f32 = 5.0;

/// The rate the vorticity factor `eps` confines at: `eps` up to [`CONFINEMENT_KNEE`], then
/// rising ever more slowly toward [`CONFINEMENT_CEILING`] (a `tanh` knee, smooth in ε):
/// 3 → 2.96, 5 → 4.28, 10 → 4.97, and the paper's 50 (in texel units) the ceiling.
pub fn confinement_rate(eps: f32) -> f32 {
    let span = CONFINEMENT_CEILING - CONFINEMENT_KNEE;
    if eps <= CONFINEMENT_KNEE {
        eps.max(0.0)
    } else {
        CONFINEMENT_KNEE + span * crate::num::tanh((eps - CONFINEMENT_KNEE) / span)
    }
}

/// What a step's confinement force needs ([`Solver::confinement`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Confinement {
    /// [`confinement_rate`] of ε (1/s).
    pub rate: f32,
    /// The rate times the cell size `min(hx, hz)`.
    pub eps_h: f32,
    /// No face is pushed past this speed (m/s), nor further past it if it is already: the
    /// layout's reference speed ([`crate::sim::forces::reference_speed`]).
    pub speed_cap: f32,
    /// `1 / speed_cap` (a large number when no wind is set): a cell's push is scaled by its
    /// speed over the reference speed, up to 1.
    pub inv_speed: f32,
}

impl Confinement {
    /// The confinement of vorticity factor `eps` on cells of `h` metres under a layout whose
    /// reference speed is `speed` (m/s).
    pub fn new(eps: f32, h: f32, speed: f32) -> Self {
        let rate = confinement_rate(eps);
        Self {
            rate,
            eps_h: rate * h,
            speed_cap: speed,
            inv_speed: 1.0 / speed.max(1e-6),
        }
    }
}

impl Solver {
    /// The confinement of this solver's layout and parameters (see [`Confinement`]).
    pub fn confinement(&self) -> Confinement {
        Confinement::new(
            self.params.vorticity,
            self.hx.min(self.hz),
            self.reference_speed,
        )
    }
}
