//! Step 5 as multigrid (`sim.pressure = "multigrid"`): V-cycles over a hierarchy of coarser
//! grids, each holding the same kind of system as the fine one.
//!
//! Every level solves `D x − Σ a_n x_n = b` in volume scale (a link's weight is the open face
//! length over the distance between the two cell centres, `D` the sum of a cell's links and
//! its open-edge links), which on the fine grid is the Jacobi system times `hx·hz`. Coarse
//! levels are built from the fine links, so obstacles, open edges, periodic wraps, odd sizes
//! and non-square cells need no special cases:
//!
//! - a coarse cell groups two fine cells along each coarsened axis (one at an odd end); an
//!   axis is coarsened only while its cells are at most 1.6 times as wide as the other
//!   axis's (semi-coarsening keeps the coupling roughly isotropic, where point smoothing
//!   works);
//! - a coarse link is the fine links it crosses, each times its own centre distance (its open
//!   face length), over the coarse centre distance: partly blocked faces pass their open
//!   share, and an open edge's link sees the fine `p = 0` half a fine cell beyond the edge;
//! - the residual is restricted as the sum over the children (cells outside the solve hold
//!   none), the correction prolonged linearly between coarse centres, from the coarse cells
//!   in the solve only.
//!
//! The smoother is damped Jacobi with Chebyshev weights (each pass `x + w·(jacobi − x)`,
//! the weights the reciprocal roots of the Chebyshev polynomial that is smallest over the
//! eigenvalues of `D⁻¹A` a coarser level cannot represent, largest first), one pass from
//! one array into another (so every pass reads only the previous one, runs in parallel row
//! by row, and gives the same bits on any number of threads); the coarsest level runs
//! red–black Gauss–Seidel sweeps. Its GPU twin runs the same passes.

use super::*;

mod hierarchy;
mod rows;

pub(crate) use super::bands::Relax;
pub(crate) use hierarchy::*;
use rows::*;

/// Smoothing passes on the finest level after each coarse correction, and on every coarser
/// level before and after it. Even counts: a pass goes from one array into the other, so an
/// even count ends where it started (the GPU's passes rely on it).
///
/// The finest level is not smoothed before it is restricted: a running flow starts from
/// last step's pressure, whose residual has little grid-scale noise left to alias, and a
/// pre-smoothing there was a pass over the whole grid of its own (memory-bound at 1000²:
/// about a fifth of a cycle). 6 passes after the correction, where there were 2 before and
/// 4 after, cut a developed step as much per cycle (one V-cycle at 1000², the worst example:
/// breeze-fft 120× with 2 + 4, 108× with 0 + 6) in 10% less time. A cold start pays: white
/// noise from zero, 28–40× in the first cycle instead of 75–122×.
pub(crate) const FINE_PASSES: usize = 6;
pub(crate) const COARSE_PASSES: usize = 4;
const _: () = assert!(FINE_PASSES.is_multiple_of(2) && COARSE_PASSES.is_multiple_of(2));

/// The low end of the eigenvalues of `D⁻¹A` (whose spectrum lies in (0, 2]) that the
/// smoothing damps, on the finest level and on the coarser ones: below it the coarse
/// correction takes over. With both axes halved, the modes the next level cannot hold have
/// eigenvalues above about 0.5 on square cells and lower on cells up to 1.6 times as wide
/// as deep (the x-rough, z-smooth ones). The coarser levels reach further down, which makes
/// their smoothing more of a solve: that is what breeze-fft's smooth, changing gusts need
/// (one cycle at 1000²: 109× at 0.3, 120× at 0.2, the other examples within 2%). Measured
/// in docs/SOLVER.md.
const FINE_LOW: f64 = 0.3;
const COARSE_LOW: f64 = 0.2;

/// The weights of `passes` damped Jacobi passes that minimise the largest amplification over
/// the eigenvalues `[low, 2]` of `D⁻¹A`: a pass with weight `w` multiplies an eigenvalue
/// `λ`'s error by `1 − w·λ`, so the product over the passes is a polynomial in `λ` with
/// roots `1/w`, and the Chebyshev polynomial of that degree, shifted to the interval, is the
/// smallest such polynomial there. The largest weight goes first and the smallest last: in
/// exact arithmetic the order does not matter, but a last pass with a weight near 2.5
/// multiplies the rounding of `jacobi − x` by it, and the divergence it leaves (the
/// solve's float32 floor) was twice a red–black sweep's; ending on the smallest weight
/// (about 0.5) halves that floor and lifts what one cycle cuts (meadow at 1000²: 150× →
/// 238×, its floor 2.1e-5 → 8.3e-6 /s RMS).
pub(crate) fn chebyshev_weights(passes: usize, low: f64) -> Vec<f32> {
    let (mid, half) = ((2.0 + low) / 2.0, (2.0 - low) / 2.0);
    (0..passes)
        .map(|i| {
            let angle = std::f64::consts::PI * (2 * i + 1) as f64 / (2 * passes) as f64;
            (1.0 / (mid + half * crate::num::cos64(angle))) as f32
        })
        .rev()
        .collect()
}

/// The smoothing weights of a hierarchy: the finest level's after each correction, and the
/// coarser levels' (before and after alike).
#[derive(Debug, Clone)]
pub(crate) struct Smoothing {
    pub(crate) fine: Vec<f32>,
    pub(crate) coarse: Vec<f32>,
}

impl Default for Smoothing {
    fn default() -> Self {
        Self {
            fine: chebyshev_weights(FINE_PASSES, FINE_LOW),
            coarse: chebyshev_weights(COARSE_PASSES, COARSE_LOW),
        }
    }
}

impl Smoothing {
    /// Level `l`'s weights before (`post` false) or after its coarse correction.
    pub(crate) fn weights(&self, l: usize, post: bool) -> &[f32] {
        match (l, post) {
            (0, false) => &[],
            (0, true) => &self.fine,
            _ => &self.coarse,
        }
    }
}

/// The multigrid hierarchy for one solver's grid and obstacles.
pub(crate) struct Multigrid {
    pub(crate) levels: Vec<Level>,
    pub(crate) smoothing: Smoothing,
}

impl Multigrid {
    pub(crate) fn new(
        nx: usize,
        ny: usize,
        hx: f32,
        hz: f32,
        flags: &[u8],
        boundary: Boundary,
    ) -> Self {
        let wraps = boundary == Boundary::Periodic;
        let open = boundary == Boundary::Open;
        let mut levels = vec![Level::finest(nx, ny, hx, hz, flags, wraps)];
        while let Some(c) = levels.last().and_then(|l| l.coarser(hx, hz)) {
            levels.push(c);
        }
        for l in 0..levels.len() - 1 {
            let (fine, coarse) = levels.split_at_mut(l + 1);
            let (f, c) = (&mut fine[l], &coarse[0]);
            f.from_x = c.x_axis.interpolation(&f.x_axis, open);
            f.from_z = c.z_axis.interpolation(&f.z_axis, open);
            f.ex = vec![0.0; f.nx * c.ny];
            let ew = expansion_weights(f, c);
            f.den = correction_denominators(f, &ew, &f.inv_d);
            f.pairs = regular_pairs(&f.from_x, c.nx);
        }
        Self {
            levels,
            smoothing: Smoothing::default(),
        }
    }

    /// Bytes `cycles` V-cycles must read and write (each array element once per pass), as
    /// the solver runs them: on the finest level, per cycle, the residual (p, div, flags:
    /// 9 B a cell), the expansion (8 B per expanded value) and the post-smoothing pass (p,
    /// div, flags, 1/Σw and the correction's expanded rows and denominators in, p out: 25 B);
    /// on a coarser level, per cycle, blocked passes of 24 B a cell (x, b, links, 1/D in, x
    /// out), the residual (20 B) and the expansion; the coarsest level one 24 B pass per 24
    /// half sweeps.
    pub fn solve_bytes(&self, cycles: u64) -> u64 {
        cycles * self.cycle_bytes()
    }

    /// [`Self::solve_bytes`] per cycle.
    fn cycle_bytes(&self) -> u64 {
        let n = self.levels.len();
        let cells = |l: &Level| (l.nx * l.ny) as u64;
        let ex = |l: &Level| 8 * (l.ex.len() as u64);
        let mut bytes = 0;
        for (k, l) in self.levels.iter().enumerate() {
            bytes += if k + 1 == n {
                let passes = 2 * coarsest_sweeps(l) as u64;
                24 * cells(l) * passes.div_ceil(MAX_BLOCK_LEVELS as u64)
            } else if k == 0 {
                (9 + 25) * cells(l) + ex(l)
            } else {
                (24 + 20 + 28) * cells(l) + ex(l)
            };
        }
        bytes
    }

    /// Bytes the hierarchy holds.
    pub(crate) fn bytes(&self) -> usize {
        self.levels.iter().map(Level::bytes).sum()
    }

    /// `cycles` V-cycles with every level, the finest too, on its explicit links (the plain
    /// form of the solver's cycle, whose finest level runs on the Jacobi arrays, and the CPU
    /// twin of the GPU's): unknowns `x` (the warm start in, the result out), `tmp` a second
    /// array of the same size, right-hand side `b_scale · b`.
    #[cfg(test)]
    pub(crate) fn solve(
        &mut self,
        x: &mut Vec<f32>,
        tmp: &mut Vec<f32>,
        b: &[f32],
        b_scale: f32,
        cycles: usize,
    ) {
        let b = b.iter().map(|v| b_scale * v).collect();
        put(
            &mut self.levels[0],
            std::mem::take(x),
            std::mem::take(tmp),
            b,
        );
        for _ in 0..cycles {
            self.cycle(0);
        }
        (*x, *tmp, _) = take(&mut self.levels[0]);
    }

    /// A V-cycle on level `l` from its `x`, for the right-hand side its `b` holds (a
    /// restriction leaves the coarser level's `x` at zero): smoothing (none on the finest
    /// level), restriction, the coarser level's cycle, prolongation, smoothing.
    fn cycle(&mut self, l: usize) {
        let n = self.levels.len();
        let lv = &mut self.levels[l];
        let (mut x, mut t, b) = take(lv);
        // The coarsest level is solved by red–black sweeps; the others smooth before
        // restricting (their weights are empty on the finest level).
        let coarsest = l == n - 1;
        let (passes, relax) = if coarsest {
            (2 * coarsest_sweeps(lv), Relax::RedBlack(0))
        } else {
            let w = self.smoothing.weights(l, false);
            (w.len(), Relax::Damped(w))
        };
        smooth(lv, &mut x, &mut t, &b, 1.0, passes, relax, false);
        if coarsest {
            put(lv, x, t, b);
            return;
        }
        {
            let (fine, coarse) = self.levels.split_at_mut(l + 1);
            restrict(&fine[l], &x, &b, 1.0, &mut coarse[0]);
        }
        self.cycle(l + 1);
        let (fine, coarse) = self.levels.split_at_mut(l + 1);
        let f = &mut fine[l];
        expand(f, &coarse[0]);
        let w = self.smoothing.weights(l, true);
        smooth(f, &mut x, &mut t, &b, 1.0, w.len(), Relax::Damped(w), true);
        put(f, x, t, b);
    }

    /// Drops the finest level's links, diagonal and link runs: the solver's flags and its
    /// own obstacle runs stand for them.
    fn drop_finest_links(&mut self) {
        let f = &mut self.levels[0];
        for v in [
            &mut f.ax,
            &mut f.az,
            &mut f.edge_x,
            &mut f.edge_z,
            &mut f.diag,
            &mut f.inv_d,
        ] {
            *v = Vec::new();
        }
        f.runs = Vec::new();
    }
}

fn take(l: &mut Level) -> (Vec<f32>, Vec<f32>, Vec<f32>) {
    (
        std::mem::take(&mut l.x),
        std::mem::take(&mut l.tmp),
        std::mem::take(&mut l.b),
    )
}

fn put(l: &mut Level, x: Vec<f32>, t: Vec<f32>, b: Vec<f32>) {
    (l.x, l.tmp, l.b) = (x, t, b);
}

/// Red–black sweeps on the coarsest level: enough to carry a correction across it.
pub(crate) fn coarsest_sweeps(l: &Level) -> usize {
    (2 * (l.nx + l.ny)).clamp(8, 400)
}

/// `passes` relaxation passes on `lv` from `x` into `x` (through `tmp`) as blocked passes
/// (see [`band_passes`]); with `correct`, the coarser level's correction (its [`expand`]ed
/// rows) is added to `x` as the first pass reads it.
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
pub(crate) fn smooth(
    lv: &Level,
    x: &mut Vec<f32>,
    tmp: &mut Vec<f32>,
    b: &[f32],
    b_scale: f32,
    passes: usize,
    relax: Relax,
    correct: bool,
) {
    for (done, block) in blocks(passes) {
        let r = relax.after(done);
        relax_passes(lv, x, tmp, b, b_scale, block, r, correct && done == 0);
        std::mem::swap(x, tmp);
    }
}

/// `passes` relaxation passes from `x` into `out`, one blocked pass over the grid.
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
pub(crate) fn relax_passes(
    lv: &Level,
    x: &[f32],
    out: &mut [f32],
    b: &[f32],
    b_scale: f32,
    passes: usize,
    relax: Relax,
    correct: bool,
) {
    let (nx, ny) = (lv.nx, lv.ny);
    let pass = |t: usize, j: usize, dst: &mut [f32], below: &[f32], row: &[f32], above: &[f32]| {
        let damp = relax.weight(t - 1);
        lv.relax_row(j, dst, [below, row, above], b, b_scale, damp);
        relax.finish(t - 1, j, dst, row);
    };
    for_each_band(out, nx, ny, passes, |a, b, out| {
        let input = |j: usize, dst: &mut [f32]| {
            dst.copy_from_slice(&x[j * nx..][..nx]);
            if correct {
                add_correction(lv, j, dst);
            }
        };
        // Two rows at a time as two rows (the coarse levels' relaxation has no paired kernel).
        let pair =
            |t: usize, [j0, j1]: [usize; 2], [d0, d1]: [&mut [f32]; 2], rows: [&[f32]; 4]| {
                pass(t, j0, d0, rows[0], rows[1], rows[2]);
                pass(t, j1, d1, rows[1], rows[2], rows[3]);
            };
        band_passes(
            nx,
            ny,
            lv.z_axis.wraps,
            out,
            a,
            b,
            passes,
            input,
            pass,
            pair,
        );
    });
}

/// The residual of row `j` of `lv` into `out`.
pub(crate) fn residual(lv: &Level, x: &[f32], b: &[f32], b_scale: f32, j: usize, out: &mut [f32]) {
    let nx = lv.nx;
    let (jb, jt) = neighbours(j, lv.ny, lv.z_axis.wraps);
    let row = |k: usize| &x[k * nx..][..nx];
    lv.link_sum(j, out, row(jb), row(j), row(jt));
    residual_row(
        out,
        &x[j * nx..][..nx],
        &b[j * nx..][..nx],
        b_scale,
        &lv.diag[j * nx..][..nx],
    );
}

/// The coarse right-hand side: each coarse cell sums its children's residuals (`residual_row`
/// makes row `j`'s residual in a finer-row buffer); the coarse unknowns start from zero.
fn restrict_rows(
    c: &mut Level,
    fine_nx: usize,
    fine_ny: usize,
    residual_row: impl Fn(usize, &mut [f32]) + Sync,
) {
    c.x.fill(0.0);
    let (xa, za, mx) = (&c.x_axis, &c.z_axis, c.nx);
    c.b.par_chunks_mut(mx)
        .enumerate()
        .with_min_len(rows_per_job(fine_nx))
        .for_each_init(
            || (vec![0.0f32; fine_nx], vec![0.0f32; fine_nx]),
            |(r, acc), (jc, out)| {
                let mut rows = za.children(jc, fine_ny);
                let first = rows
                    .next()
                    .expect("a coarse row covers one fine row or more");
                residual_row(first, acc);
                for j in rows {
                    residual_row(j, r);
                    for (a, r) in acc.iter_mut().zip(r.iter()) {
                        *a += r;
                    }
                }
                if xa.coarsened {
                    let pairs = fine_nx / 2;
                    for (o, pair) in out.iter_mut().zip(acc.chunks_exact(2)) {
                        *o = pair[0] + pair[1];
                    }
                    if fine_nx % 2 == 1 {
                        out[pairs] = acc[fine_nx - 1];
                    }
                } else {
                    out.copy_from_slice(acc);
                }
            },
        );
}

/// The coarse right-hand side from level `f`'s residual.
pub(crate) fn restrict(f: &Level, x: &[f32], b: &[f32], b_scale: f32, c: &mut Level) {
    restrict_rows(c, f.nx, f.ny, |j, out| residual(f, x, b, b_scale, j, out));
}

/// Interpolates the coarse correction along x to the finer level's columns, one row per
/// coarse row (the weights behind each value, [`Level::ew`], depend only on the hierarchy
/// and are made once by [`expansion_weights`]).
pub(crate) fn expand(f: &mut Level, c: &Level) {
    let (nx, mx) = (f.nx, c.nx);
    let (from_x, pairs) = (&f.from_x, f.pairs);
    f.ex.par_chunks_mut(nx)
        .enumerate()
        .with_min_len(rows_per_job(nx))
        .for_each(|(jc, e)| {
            let x = &c.x[jc * mx..][..mx];
            let inv = &c.inv_d[jc * mx..][..mx];
            let (c0, c1, tl, tr) = pairs;
            // The ends through the table.
            for i in (0..2 * c0).chain(2 * c1..nx) {
                let ix = &from_x[i];
                let (wa, wb) = interp_weights(ix, inv);
                let xb = if ix.far == Interp::EDGE {
                    0.0
                } else {
                    x[ix.far as usize]
                };
                e[i] = wa * x[ix.near as usize] + wb * xb;
            }
            if c1 > c0 {
                expand_pairs(
                    &mut e[2 * c0..2 * c1],
                    &x[c0 - 1..c1 + 1],
                    &inv[c0 - 1..c1 + 1],
                    tl,
                    tr,
                );
            }
        });
}

/// Adds the coarse correction to row `j` of level `f` (from its [`expand`]ed rows, blended
/// along z and divided by [`Level::den`]; ±0 outside the solve).
pub(crate) fn add_correction(f: &Level, j: usize, row: &mut [f32]) {
    let nx = f.nx;
    let iz = f.from_z[j];
    let en = &f.ex[iz.near as usize * nx..][..nx];
    let den = &f.den[j * nx..][..nx];
    if iz.far == Interp::EDGE {
        correct_row(row, en, en, 1.0 - iz.t, iz.t, 0.0, den);
    } else {
        let ef = &f.ex[iz.far as usize * nx..][..nx];
        correct_row(row, en, ef, 1.0 - iz.t, iz.t, 1.0, den);
    }
}

impl Solver {
    /// Step 5 by multigrid: the warm start ([`SimParams::warm_start`]), then
    /// `pressure_cycles` V-cycles. The finest level runs on the Jacobi system's own arrays:
    /// its smoothing passes are blocked passes like the Jacobi iterations (the warm start
    /// folded into the first, the prolonged correction into the first after the coarse
    /// solve), its residual is read from the flags.
    pub fn solve_pressure_multigrid(&mut self) {
        let warm = self.params.warm_start();
        let boundary = self.params.boundary;
        let mut mg = self.multigrid.take().unwrap_or_else(|| {
            let mut mg = Multigrid::new(self.nx, self.ny, self.hx, self.hz, &self.flags, boundary);
            mg.drop_finest_links();
            mg
        });
        let cycles = self.params.pressure_cycles as usize;
        if mg.levels.len() == 1 {
            // Too small to coarsen: sweeps alone, as on a coarsest level.
            let passes = 2 * coarsest_sweeps(&mg.levels[0]) * cycles;
            self.sweeps_blocked(passes, warm, Some(Relax::RedBlack(0)), None);
            self.multigrid = Some(mg);
            return;
        }
        // No pre-smoothing (see FINE_PASSES): the warm start's scale is multiplied in as the
        // first restriction and the first post-smoothing read the pressure.
        let mut scale = warm;
        for _ in 0..cycles {
            self.restrict_fine(&mut mg.levels[1], scale);
            mg.cycle(1);
            let (fine, coarse) = mg.levels.split_at_mut(1);
            expand(&mut fine[0], &coarse[0]);
            let post = Relax::Damped(&mg.smoothing.fine);
            self.sweeps_blocked(FINE_PASSES, scale, Some(post), Some(&mg.levels[0]));
            scale = 1.0;
        }
        self.multigrid = Some(mg);
    }

    /// The coarse right-hand side from the finest level's pressure times `scale`: each coarse
    /// cell sums its children's volume-scaled residuals.
    fn restrict_fine(&self, c: &mut Level, scale: f32) {
        let (nx, ny) = (self.nx, self.ny);
        let st = self.stencil();
        let vol = self.hx * self.hz;
        let wraps = self.params.boundary == Boundary::Periodic;
        let (p, div, flags) = (&self.p, &self.div, &self.flags);
        let runs = &self.row_irregular;
        restrict_rows(c, nx, ny, |j, out| {
            let (jb, jt) = neighbours(j, ny, wraps);
            let row = |k: usize| &p[k * nx..][..nx];
            fine_residual_row(
                &st,
                vol,
                scale,
                out,
                [row(jb), row(j), row(jt)],
                &div[j * nx..][..nx],
                &flags[j * nx..][..nx],
                &runs[j],
            );
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Solver;

    /// The prolongation's paired fast path gives the index table's bits, on the obstacles
    /// example (cells in and out of the solve) at even and odd sizes, every boundary, and
    /// every level; and it covers the interior of every axis coarsened in pairs.
    #[test]
    fn expansion_pairs_give_the_tables_bits() {
        let mut layout =
            crate::doc::parse(include_str!("../../../../layouts/obstacles.json")).unwrap();
        for grid in [[90, 70], [91, 37], [64, 129]] {
            layout.world.grid = grid;
            for boundary in [Boundary::Closed, Boundary::Open, Boundary::Periodic] {
                layout.sim.boundary = boundary;
                let s = Solver::new(&layout);
                let mut mg = Multigrid::new(s.nx, s.ny, s.hx, s.hz, &s.flags, boundary);
                for l in 0..mg.levels.len() - 1 {
                    let (fine, coarse) = mg.levels.split_at_mut(l + 1);
                    let (f, c) = (&mut fine[l], &mut coarse[0]);
                    // Noise in every cell, those outside the solve too (the sweeps leave ±0
                    // there), so the weights' in-solve factors count.
                    let mut seed = 7 + l as u32;
                    for x in c.x.iter_mut() {
                        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                        *x = (seed >> 8) as f32 / (1 << 24) as f32 - 0.5;
                    }
                    if f.x_axis.len() != c.x_axis.len() {
                        let (c0, c1, ..) = f.pairs;
                        assert!(
                            c1 > c0 && c1 - c0 + 3 >= c.nx,
                            "{grid:?} level {l}: {c0}..{c1} of {}",
                            c.nx
                        );
                    }
                    expand(f, c);
                    let fast = f.ex.clone();
                    f.pairs = (0, 0, 0.0, 0.0);
                    expand(f, c);
                    let first = fast
                        .iter()
                        .zip(&f.ex)
                        .position(|(a, b)| a.to_bits() != b.to_bits());
                    assert!(
                        first.is_none(),
                        "{grid:?} {boundary:?} level {l}: value {first:?} differs"
                    );
                }
            }
        }
    }
}
