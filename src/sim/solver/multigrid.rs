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
//!   axis is coarsened only while its cells are not much wider than the other axis's (semi-
//!   coarsening keeps the coupling roughly isotropic, where point smoothing works);
//! - a coarse link is the fine links it crosses, each times its own centre distance (its open
//!   face length), over the coarse centre distance: partly blocked faces pass their open
//!   share, and an open edge's link sees the fine `p = 0` half a fine cell beyond the edge;
//! - the residual is restricted as the sum over the children (cells outside the solve hold
//!   none), the correction prolonged linearly between coarse centres, from the coarse cells
//!   in the solve only.
//!
//! The smoother is red–black Gauss–Seidel, one colour per pass from one array into another
//! (so every pass reads only the previous one, runs in parallel row by row, and gives the
//! same bits on any number of threads); its GPU twin runs the same passes.

use super::*;

/// Red–black sweeps before and after each coarse correction.
pub(crate) const PRE_SWEEPS: usize = 2;
pub(crate) const POST_SWEEPS: usize = 2;
/// Coarsening stops at this many cells (or when no axis can be halved); that level is solved
/// by sweeps alone.
const COARSEST_CELLS: usize = 64;

/// One axis of a level: its cells' extents in fine cells, how it was made from the finer
/// level's axis, and whether it wraps.
#[derive(Clone, Debug)]
pub(crate) struct Axis {
    /// `(lo, hi)` of every cell, in fine cells from the grid's start.
    pub(crate) cells: Vec<(f32, f32)>,
    /// True when each of these cells groups two of the finer level's (one at an odd end).
    pub(crate) coarsened: bool,
    /// Fine cells along the axis (the wrap length).
    pub(crate) fine: f32,
    pub(crate) wraps: bool,
}

impl Axis {
    fn fine(n: usize, wraps: bool) -> Self {
        Self {
            cells: (0..n).map(|i| (i as f32, i as f32 + 1.0)).collect(),
            coarsened: false,
            fine: n as f32,
            wraps,
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.cells.len()
    }

    fn centre(&self, i: usize) -> f32 {
        let (lo, hi) = self.cells[i];
        0.5 * (lo + hi)
    }

    /// Centre distance across face `k` (between cells `k − 1` and `k`; the end faces are the
    /// wrapped link).
    fn gap(&self, k: usize) -> f32 {
        let n = self.len();
        if k == 0 || k == n {
            self.centre(0) + self.fine - self.centre(n - 1)
        } else {
            self.centre(k) - self.centre(k - 1)
        }
    }

    /// Centre distance from the first (`end` false) or last cell to the fine `p = 0` half a
    /// fine cell beyond the edge.
    fn edge_gap(&self, end: bool) -> f32 {
        if end {
            self.fine + 0.5 - self.centre(self.len() - 1)
        } else {
            self.centre(0) + 0.5
        }
    }

    /// Halves the axis: cell `I` groups cells `2I` and `2I + 1`.
    fn coarser(&self) -> Self {
        let n = self.len();
        Self {
            cells: (0..n.div_ceil(2))
                .map(|c| (self.cells[2 * c].0, self.cells[(2 * c + 1).min(n - 1)].1))
                .collect(),
            coarsened: true,
            fine: self.fine,
            wraps: self.wraps,
        }
    }

    /// The same cells, one per finer cell.
    fn kept(&self) -> Self {
        Self {
            coarsened: false,
            ..self.clone()
        }
    }

    /// The finer cells of coarse cell `c` on this axis.
    pub(crate) fn children(&self, c: usize, fine_len: usize) -> Range<usize> {
        if self.coarsened {
            2 * c..(2 * c + 2).min(fine_len)
        } else {
            c..c + 1
        }
    }

    /// The finer face that coarse face `k` lies on.
    fn fine_face(&self, k: usize, fine_len: usize) -> usize {
        if self.coarsened {
            (2 * k).min(fine_len)
        } else {
            k
        }
    }

    /// Linear prolongation from this (coarse) axis to `finer`: for each finer cell, the coarse
    /// cell it lies in, the nearest other coarse cell on its side (or, past the last centre
    /// at an open edge, the fine `p = 0` beyond the edge: [`Interp::EDGE`]), and its weight.
    pub(crate) fn interpolation(&self, finer: &Axis, open: bool) -> Vec<Interp> {
        let n = self.len();
        (0..finer.len())
            .map(|f| {
                let c = if self.coarsened { f / 2 } else { f };
                let (x, xc) = (finer.centre(f), self.centre(c));
                let edge = |xe: f32| open.then_some((Interp::EDGE, xe));
                let toward = if x < xc - 1e-3 {
                    if c > 0 {
                        Some((c as u32 - 1, self.centre(c - 1)))
                    } else if self.wraps {
                        Some((n as u32 - 1, self.centre(n - 1) - self.fine))
                    } else {
                        edge(-0.5)
                    }
                } else if x > xc + 1e-3 {
                    if c + 1 < n {
                        Some((c as u32 + 1, self.centre(c + 1)))
                    } else if self.wraps {
                        Some((0, self.centre(0) + self.fine))
                    } else {
                        edge(self.fine + 0.5)
                    }
                } else {
                    None
                };
                let (far, t) = toward.map_or((c as u32, 0.0), |(o, xo)| (o, (x - xc) / (xo - xc)));
                Interp {
                    near: c as u32,
                    far,
                    t,
                }
            })
            .collect()
    }
}

/// A finer cell's linear interpolation along one axis: `(1 − t)·near + t·far`; mirrors
/// `struct Interp` in `shaders/mg_prolong.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Interp {
    pub(crate) near: u32,
    pub(crate) far: u32,
    pub(crate) t: f32,
}

impl Interp {
    /// `far` of a finer cell between the last coarse centre and an open edge: the correction
    /// falls linearly to 0 at the fine grid's `p = 0` half a fine cell beyond the edge.
    pub(crate) const EDGE: u32 = u32::MAX;
}

/// One grid of the hierarchy: its links and, below the finest, its unknowns.
pub(crate) struct Level {
    pub(crate) nx: usize,
    pub(crate) ny: usize,
    pub(crate) x_axis: Axis,
    pub(crate) z_axis: Axis,
    /// Links across the vertical faces, `(nx + 1) × ny`: face `i` of row `j` joins cells
    /// `i − 1` and `i`; the end faces hold the wrapped link when periodic, else 0.
    pub(crate) ax: Vec<f32>,
    /// Links across the horizontal faces, `nx × (ny + 1)`.
    pub(crate) az: Vec<f32>,
    /// Open-edge links of the first and last cell of each row (`2 × ny`: left, right) and of
    /// each column (`2 × nx`: bottom, top).
    edge_x: Vec<f32>,
    edge_z: Vec<f32>,
    /// `D` per cell (0 outside the solve) and `1 / D` (0 there too).
    pub(crate) diag: Vec<f32>,
    pub(crate) inv_d: Vec<f32>,
    /// The unknowns, a second array for the red–black passes, and the right-hand side
    /// (empty on the finest level, whose are the solver's pressure, `p_tmp` and divergence).
    pub(crate) x: Vec<f32>,
    pub(crate) tmp: Vec<f32>,
    pub(crate) b: Vec<f32>,
    /// Prolongation from the next coarser level (empty on the coarsest).
    pub(crate) from_x: Vec<Interp>,
    pub(crate) from_z: Vec<Interp>,
    /// The coarser level's correction interpolated along x to this level's columns, one row
    /// per coarse row (`nx × coarse ny`), and the weights of the coarse cells in the solve
    /// that made each value: rows are then blended along z as they are read.
    pub(crate) ex: Vec<f32>,
    pub(crate) ew: Vec<f32>,
    /// The coarse columns `c0..c1` whose two finer cells interpolate toward their left and
    /// right neighbours with the same weights `(t_left, t_right)` (the interior of an axis
    /// coarsened in pairs): [`expand`] runs them without the index table.
    pairs: (usize, usize, f32, f32),
    /// The links most interior faces have across x and z (a cell with these four links
    /// and no edge link is "regular"), and per row the runs `(start, end)` of interior cells
    /// (1..nx − 1) that are not, merged across short gaps: the row kernels run everything
    /// else on a fast path that reads no links (the same products, so the same bits).
    regular: (f32, f32),
    runs: Vec<Vec<(usize, usize)>>,
}

impl Level {
    /// The finest level: the Jacobi system's links times `hx·hz`.
    fn finest(nx: usize, ny: usize, hx: f32, hz: f32, flags: &[u8], wraps: bool) -> Self {
        let (lx, lz) = (hz / hx, hx / hz);
        let has = |i: usize, j: usize, bit: u8| flags[j * nx + i] & bit != 0;
        let mut ax = vec![0.0; (nx + 1) * ny];
        for j in 0..ny {
            for i in 0..nx {
                if has(i, j, L) {
                    ax[j * (nx + 1) + i] = lx;
                }
            }
            ax[j * (nx + 1) + nx] = ax[j * (nx + 1)];
        }
        let mut az = vec![0.0; nx * (ny + 1)];
        for j in 0..ny {
            for i in 0..nx {
                if has(i, j, B) {
                    az[j * nx + i] = lz;
                }
            }
        }
        az.copy_within(0..nx, ny * nx);
        let open = |i, j, bit: u8, w: f32| if has(i, j, bit << EDGE) { w } else { 0.0 };
        let edge_x = (0..ny)
            .flat_map(|j| [open(0, j, L, lx), open(nx - 1, j, R, lx)])
            .collect();
        let edge_z = (0..nx)
            .flat_map(|i| [open(i, 0, B, lz), open(i, ny - 1, T, lz)])
            .collect();
        Self::with_links(
            Axis::fine(nx, wraps),
            Axis::fine(ny, wraps),
            ax,
            az,
            edge_x,
            edge_z,
        )
    }

    fn with_links(
        x_axis: Axis,
        z_axis: Axis,
        ax: Vec<f32>,
        az: Vec<f32>,
        edge_x: Vec<f32>,
        edge_z: Vec<f32>,
    ) -> Self {
        let (nx, ny) = (x_axis.len(), z_axis.len());
        let mut diag = vec![0.0; nx * ny];
        for j in 0..ny {
            for i in 0..nx {
                let mut d = ax[j * (nx + 1) + i]
                    + ax[j * (nx + 1) + i + 1]
                    + az[j * nx + i]
                    + az[(j + 1) * nx + i];
                if i == 0 {
                    d += edge_x[2 * j];
                }
                if i == nx - 1 {
                    d += edge_x[2 * j + 1];
                }
                if j == 0 {
                    d += edge_z[2 * i];
                }
                if j == ny - 1 {
                    d += edge_z[2 * i + 1];
                }
                diag[j * nx + i] = d;
            }
        }
        let inv_d = diag
            .iter()
            .map(|&d| if d > 0.0 { 1.0 / d } else { 0.0 })
            .collect();
        let regular = (most_common(&ax), most_common(&az));
        let runs = (0..ny)
            .map(|j| {
                let is_regular = |i: usize| {
                    let bits = |v: f32| v.to_bits();
                    let (lx, lz) = (bits(regular.0), bits(regular.1));
                    bits(ax[j * (nx + 1) + i]) == lx
                        && bits(ax[j * (nx + 1) + i + 1]) == lx
                        && bits(az[j * nx + i]) == lz
                        && bits(az[(j + 1) * nx + i]) == lz
                };
                runs_where_not(nx, is_regular)
            })
            .collect();
        Self {
            nx,
            ny,
            x_axis,
            z_axis,
            ax,
            az,
            edge_x,
            edge_z,
            diag,
            inv_d,
            x: Vec::new(),
            tmp: Vec::new(),
            b: Vec::new(),
            from_x: Vec::new(),
            from_z: Vec::new(),
            ex: Vec::new(),
            ew: Vec::new(),
            pairs: (0, 0, 0.0, 0.0),
            regular,
            runs,
        }
    }

    /// Cell size along x and z in metres (from the widest cell), for the coarsening choice.
    fn spacing(&self, hx: f32, hz: f32) -> (f32, f32) {
        let w = |a: &Axis| a.cells.iter().map(|c| c.1 - c.0).fold(0.0, f32::max);
        (hx * w(&self.x_axis), hz * w(&self.z_axis))
    }

    /// The next coarser level, or `None` when this one is coarse enough.
    fn coarser(&self, hx: f32, hz: f32) -> Option<Level> {
        let (nx, ny) = (self.nx, self.ny);
        if nx * ny <= COARSEST_CELLS {
            return None;
        }
        let (sx, sz) = self.spacing(hx, hz);
        let can = |n: usize| n > 2;
        // An axis is coarsened while its cells are not much wider than the other axis's.
        let strong_x = sx <= std::f32::consts::SQRT_2 * sz || !can(ny);
        let strong_z = sz <= std::f32::consts::SQRT_2 * sx || !can(nx);
        let (cx, cz) = (can(nx) && strong_x, can(ny) && strong_z);
        if !cx && !cz {
            return None;
        }
        let xa = if cx {
            self.x_axis.coarser()
        } else {
            self.x_axis.kept()
        };
        let za = if cz {
            self.z_axis.coarser()
        } else {
            self.z_axis.kept()
        };
        let (mx, my) = (xa.len(), za.len());
        // A coarse link: the fine links it crosses times their centre distance (the open face
        // length), over the coarse centre distance.
        let mut ax = vec![0.0; (mx + 1) * my];
        for jc in 0..my {
            for k in 0..=mx {
                let kf = xa.fine_face(k, nx);
                let open: f32 = za
                    .children(jc, ny)
                    .map(|j| self.ax[j * (nx + 1) + kf] * self.x_axis.gap(kf))
                    .sum();
                ax[jc * (mx + 1) + k] = open / xa.gap(k);
            }
        }
        let mut az = vec![0.0; mx * (my + 1)];
        for k in 0..=my {
            let kf = za.fine_face(k, ny);
            for ic in 0..mx {
                let open: f32 = xa
                    .children(ic, nx)
                    .map(|i| self.az[kf * nx + i] * self.z_axis.gap(kf))
                    .sum();
                az[k * mx + ic] = open / za.gap(k);
            }
        }
        let mut edge_x = vec![0.0; 2 * my];
        for jc in 0..my {
            for (s, end) in [(0, false), (1, true)] {
                let open: f32 = za
                    .children(jc, ny)
                    .map(|j| self.edge_x[2 * j + s] * self.x_axis.edge_gap(end))
                    .sum();
                edge_x[2 * jc + s] = open / xa.edge_gap(end);
            }
        }
        let mut edge_z = vec![0.0; 2 * mx];
        for ic in 0..mx {
            for (s, end) in [(0, false), (1, true)] {
                let open: f32 = xa
                    .children(ic, nx)
                    .map(|i| self.edge_z[2 * i + s] * self.z_axis.edge_gap(end))
                    .sum();
                edge_z[2 * ic + s] = open / za.edge_gap(end);
            }
        }
        let mut level = Level::with_links(xa, za, ax, az, edge_x, edge_z);
        level.x = vec![0.0; mx * my];
        level.tmp = vec![0.0; mx * my];
        level.b = vec![0.0; mx * my];
        Some(level)
    }

    /// Bytes this level holds.
    fn bytes(&self) -> usize {
        let f32s = self.ax.len()
            + self.az.len()
            + self.edge_x.len()
            + self.edge_z.len()
            + self.diag.len()
            + self.inv_d.len()
            + self.x.len()
            + self.tmp.len()
            + self.b.len()
            + self.ex.len()
            + self.ew.len();
        let axes = self.x_axis.len() + self.z_axis.len();
        f32s * 4 + axes * 8 + (self.from_x.len() + self.from_z.len()) * 12
    }

    /// `out = Σ a x_n` for row `j`, from its rows `below`, `row`, `above` (wrapped; at a
    /// closed end the row itself, whose link there is 0).
    fn link_sum(&self, j: usize, out: &mut [f32], below: &[f32], row: &[f32], above: &[f32]) {
        let nx = self.nx;
        link_sum_row(
            out,
            [below, row, above],
            &self.ax[j * (nx + 1)..][..nx + 1],
            &self.az[j * nx..][..nx],
            &self.az[(j + 1) * nx..][..nx],
            self.x_axis.wraps,
            self.regular,
            &self.runs[j],
        );
    }
}

/// The multigrid hierarchy for one solver's grid and obstacles.
pub(crate) struct Multigrid {
    pub(crate) levels: Vec<Level>,
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
        while let Some(c) = levels.last().unwrap().coarser(hx, hz) {
            levels.push(c);
        }
        for l in 0..levels.len() - 1 {
            let (fine, coarse) = levels.split_at_mut(l + 1);
            let (f, c) = (&mut fine[l], &coarse[0]);
            f.from_x = c.x_axis.interpolation(&f.x_axis, open);
            f.from_z = c.z_axis.interpolation(&f.z_axis, open);
            f.ex = vec![0.0; f.nx * c.ny];
            f.ew = expansion_weights(f, c);
            f.pairs = regular_pairs(&f.from_x, c.nx);
        }
        Self { levels }
    }

    /// Bytes `cycles` V-cycles must read and write (each array element once per pass), as
    /// the solver runs them: on the finest level one blocked pre-smoothing pass before the
    /// first cycle (p, div, flags, 1/Σw in, p out: 17 B a cell), and per cycle the residual
    /// (p, div, flags: 9 B), the expansion (8 B per expanded value) and the post-smoothing
    /// pass reading the expanded rows too (21 B); on a coarser level, per cycle, blocked
    /// passes of 24 B a cell (x, b, links, 1/D in, x out), the residual (20 B) and the
    /// expansion; the coarsest level one 24 B pass per 24 half sweeps.
    pub fn solve_bytes(&self, cycles: u64) -> u64 {
        17 * (self.levels[0].nx * self.levels[0].ny) as u64 + cycles * self.cycle_bytes()
    }

    /// [`Self::solve_bytes`] per cycle, less the finest level's pre-smoothing.
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
                (9 + 21) * cells(l) + ex(l)
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
        for k in 0..cycles {
            self.cycle(0, k == 0);
        }
        (*x, *tmp, _) = take(&mut self.levels[0]);
    }

    /// A V-cycle on level `l` from its `x`, for the right-hand side its `b` holds (a
    /// restriction leaves the coarser level's `x` at zero), pre-smoothing first when `pre`
    /// (the finest level's later cycles start from the previous cycle's post-smoothing).
    fn cycle(&mut self, l: usize, pre: bool) {
        let n = self.levels.len();
        let lv = &mut self.levels[l];
        let (mut x, mut t, b) = take(lv);
        if l == n - 1 {
            sweeps(lv, &mut x, &mut t, &b, 1.0, coarsest_sweeps(lv), 0, false);
            put(lv, x, t, b);
            return;
        }
        if pre {
            sweeps(lv, &mut x, &mut t, &b, 1.0, PRE_SWEEPS, 0, false);
        }
        {
            let (fine, coarse) = self.levels.split_at_mut(l + 1);
            restrict(&fine[l], &x, &b, 1.0, &mut coarse[0]);
        }
        self.cycle(l + 1, true);
        let (fine, coarse) = self.levels.split_at_mut(l + 1);
        let f = &mut fine[l];
        expand(f, &coarse[0]);
        sweeps(f, &mut x, &mut t, &b, 1.0, POST_SWEEPS, 1, true);
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

/// Sweeps on the coarsest level: enough to carry a correction across it.
pub(crate) fn coarsest_sweeps(l: &Level) -> usize {
    (2 * (l.nx + l.ny)).clamp(8, 400)
}

/// `n` red–black sweeps on `lv` from `x` into `x` (through `tmp`), colour `first` first, as
/// blocked passes (see [`band_passes`]); with `correct`, the coarser level's correction (its
/// [`expand`]ed rows) is added to `x` as the first pass reads it.
#[allow(clippy::too_many_arguments)]
pub(crate) fn sweeps(
    lv: &Level,
    x: &mut Vec<f32>,
    tmp: &mut Vec<f32>,
    b: &[f32],
    b_scale: f32,
    n: usize,
    first: usize,
    correct: bool,
) {
    for (done, passes) in blocks(2 * n) {
        let colour = (first + done) % 2;
        half_sweeps(lv, x, tmp, b, b_scale, passes, colour, correct && done == 0);
        std::mem::swap(x, tmp);
    }
}

/// `passes` red–black half sweeps from `x` into `out`, one blocked pass over the grid.
#[allow(clippy::too_many_arguments)]
pub(crate) fn half_sweeps(
    lv: &Level,
    x: &[f32],
    out: &mut [f32],
    b: &[f32],
    b_scale: f32,
    passes: usize,
    first: usize,
    correct: bool,
) {
    let (nx, ny) = (lv.nx, lv.ny);
    let pass = |t: usize, j: usize, dst: &mut [f32], below: &[f32], row: &[f32], above: &[f32]| {
        lv.link_sum(j, dst, below, row, above);
        relax_row(dst, &b[j * nx..][..nx], b_scale, &lv.inv_d[j * nx..][..nx]);
        keep_other_colour(dst, row, j + first + t - 1);
    };
    for_each_band(out, nx, ny, passes, |a, b, out| {
        let input = |j: usize, dst: &mut [f32]| {
            dst.copy_from_slice(&x[j * nx..][..nx]);
            if correct {
                add_correction(lv, j, dst, &lv.inv_d);
            }
        };
        band_passes(nx, ny, lv.z_axis.wraps, out, a, b, passes, input, pass);
    });
}

/// `out = Σ a x_n` over a row's four links (the row's ends wrap when `wraps`; otherwise
/// their end links are 0). Interior cells outside `irregular` have the `regular` links
/// `(x, z)` and skip the link arrays (the same products in the same order).
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(windloom_static_simd), multiversion(targets = "simd"))]
#[cfg_attr(
    windloom_static_simd,
    multiversion(targets = "simd", dispatcher = "static")
)]
pub(crate) fn link_sum_row(
    out: &mut [f32],
    [below, row, above]: [&[f32]; 3],
    ax: &[f32],
    az_b: &[f32],
    az_t: &[f32],
    wraps: bool,
    (lx, lz): (f32, f32),
    irregular: &[(usize, usize)],
) {
    let n = out.len();
    let (first, last) = if wraps {
        (row[n - 1], row[0])
    } else {
        (0.0, 0.0)
    };
    let left = |i: usize| if i == 0 { first } else { row[i - 1] };
    let right = |i: usize| if i + 1 == n { last } else { row[i + 1] };
    for i in [0, n - 1] {
        out[i] = ax[i] * left(i) + ax[i + 1] * right(i) + az_b[i] * below[i] + az_t[i] * above[i];
    }
    if n < 3 {
        return;
    }
    // Interior cells a..b, through the links or on the fast path.
    let span = |out: &mut [f32], a: usize, b: usize, linked: bool| {
        let m = b - a;
        let (o, l, r) = (&mut out[a..b], &row[a - 1..][..m], &row[a + 1..][..m]);
        let (bl, ab) = (&below[a..b], &above[a..b]);
        if linked {
            let (al, ar) = (&ax[a..b], &ax[a + 1..][..m]);
            let (lb, lt) = (&az_b[a..b], &az_t[a..b]);
            for i in 0..m {
                o[i] = al[i] * l[i] + ar[i] * r[i] + lb[i] * bl[i] + lt[i] * ab[i];
            }
        } else {
            for i in 0..m {
                o[i] = lx * l[i] + lx * r[i] + lz * bl[i] + lz * ab[i];
            }
        }
    };
    for_spans(n, irregular, |a, b, flagged| span(out, a, b, flagged));
}

/// The value most entries of `v` hold (bit for bit; ties go to the smallest bits), judged
/// from about 4,096 evenly spaced entries: the value only decides where the row kernels take
/// their fast path, never a result, and sorting a million links cost the first multigrid
/// step tens of milliseconds at 1000².
fn most_common(v: &[f32]) -> f32 {
    let stride = (v.len() / 4096).max(1);
    let mut bits: Vec<u32> = v.iter().step_by(stride).map(|x| x.to_bits()).collect();
    bits.sort_unstable();
    let best = bits
        .chunk_by(|a, b| a == b)
        .max_by(|a, b| a.len().cmp(&b.len()).then(b[0].cmp(&a[0])))
        .map_or(0, |run| run[0]);
    f32::from_bits(best)
}

/// `s ← (s + b_scale·b) / D` (0 outside the solve), in place over a row of link sums.
#[cfg_attr(not(windloom_static_simd), multiversion(targets = "simd"))]
#[cfg_attr(
    windloom_static_simd,
    multiversion(targets = "simd", dispatcher = "static")
)]
fn relax_row(s: &mut [f32], b: &[f32], b_scale: f32, inv_d: &[f32]) {
    for ((s, &b), &w) in s.iter_mut().zip(b).zip(inv_d) {
        *s = (*s + b_scale * b) * w;
    }
}

/// `s ← b_scale·b + s − D x` (0 outside the solve), in place over a row of link sums.
#[cfg_attr(not(windloom_static_simd), multiversion(targets = "simd"))]
#[cfg_attr(
    windloom_static_simd,
    multiversion(targets = "simd", dispatcher = "static")
)]
fn residual_row(s: &mut [f32], x: &[f32], b: &[f32], b_scale: f32, diag: &[f32]) {
    for (((s, &x), &b), &d) in s.iter_mut().zip(x).zip(b).zip(diag) {
        *s = if d > 0.0 {
            b_scale * b + *s - d * x
        } else {
            0.0
        };
    }
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
                residual_row(rows.next().unwrap(), acc);
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

/// [`expand`] over the coarse cells `1..x.len() − 1` of a row, each giving its two finer
/// cells (into `e`, two per cell): the left one from the cell and its left neighbour (weight
/// `tl` on the neighbour), the right one from the cell and its right neighbour (`tr`), each
/// coarse cell weighted by whether it is in the solve — the table's arithmetic, without the
/// table's indices and branches, so it vectorises.
#[cfg_attr(not(windloom_static_simd), multiversion(targets = "simd"))]
#[cfg_attr(
    windloom_static_simd,
    multiversion(targets = "simd", dispatcher = "static")
)]
fn expand_pairs(e: &mut [f32], x: &[f32], inv: &[f32], tl: f32, tr: f32) {
    let n = e.len() / 2;
    let (x, inv) = (&x[..n + 2], &inv[..n + 2]);
    let inside = |c: usize| f32::from(u8::from(inv[c] > 0.0));
    for k in 0..n {
        let m = [inside(k), inside(k + 1), inside(k + 2)];
        e[2 * k] = (1.0 - tl) * m[1] * x[k + 1] + tl * m[0] * x[k];
        e[2 * k + 1] = (1.0 - tr) * m[1] * x[k + 1] + tr * m[2] * x[k + 2];
    }
}

/// The coarse columns `(c0, c1)` whose finer cells `2c` and `2c + 1` interpolate from `c`
/// toward `c − 1` and `c + 1` with one weight each `(t_left, t_right)`, as [`expand_pairs`]
/// assumes; `c1 == c0` when the axis was not coarsened in pairs.
fn regular_pairs(from_x: &[Interp], mx: usize) -> (usize, usize, f32, f32) {
    let n = from_x.len();
    if n < 6 || mx < 3 || n / 2 > mx {
        return (0, 0, 0.0, 0.0);
    }
    let (tl, tr) = (from_x[2].t, from_x[3].t);
    let regular = |c: usize| {
        let (l, r) = (from_x[2 * c], from_x[2 * c + 1]);
        let pair = |ix: Interp, far: usize, t: f32| {
            ix.near as usize == c && ix.far as usize == far && ix.t.to_bits() == t.to_bits()
        };
        pair(l, c - 1, tl) && pair(r, c + 1, tr)
    };
    // The longest run of regular columns within 1..mx − 1 (and within the finer axis).
    let last = (mx - 1).min(n / 2);
    let (mut best, mut start) = ((0, 0), 1);
    for c in 1..=last {
        if c == last || !regular(c) {
            if c - start > best.1 - best.0 {
                best = (start, c);
            }
            start = c + 1;
        }
    }
    (best.0, best.1, tl, tr)
}

/// The weights of an interpolated value's two coarse cells: their linear weights times 1 for
/// a cell in the solve, 0 for one outside (an open edge beyond the last centre counts as a
/// cell in the solve holding 0).
#[inline(always)]
fn interp_weights(ix: &Interp, inv: &[f32]) -> (f32, f32) {
    let inside = |c: u32| f32::from(u8::from(inv[c as usize] > 0.0));
    let mb = if ix.far == Interp::EDGE {
        1.0
    } else {
        inside(ix.far)
    };
    ((1.0 - ix.t) * inside(ix.near), ix.t * mb)
}

/// For each coarse row, the weight of the coarse cells in the solve behind each value
/// [`expand`] makes: what its interpolation is divided by where rows are blended.
fn expansion_weights(f: &Level, c: &Level) -> Vec<f32> {
    let mx = c.nx;
    (0..c.ny)
        .flat_map(|jc| {
            let inv = &c.inv_d[jc * mx..][..mx];
            f.from_x.iter().map(move |ix| {
                let (wa, wb) = interp_weights(ix, inv);
                wa + wb
            })
        })
        .collect()
}

/// Adds the coarse correction to row `j` of level `f` (from its [`expand`]ed rows, blended
/// along z), in the cells in the solve (`inv`: the level's `1 / D`, 0 outside).
pub(crate) fn add_correction(f: &Level, j: usize, row: &mut [f32], inv: &[f32]) {
    let nx = f.nx;
    let iz = f.from_z[j];
    let near = iz.near as usize * nx;
    let (en, wn) = (&f.ex[near..][..nx], &f.ew[near..][..nx]);
    let inv = &inv[j * nx..][..nx];
    if iz.far == Interp::EDGE {
        correct_row(row, en, wn, en, wn, 1.0 - iz.t, iz.t, true, inv);
    } else {
        let far = iz.far as usize * nx;
        let (ef, wf) = (&f.ex[far..][..nx], &f.ew[far..][..nx]);
        correct_row(row, en, wn, ef, wf, 1.0 - iz.t, iz.t, false, inv);
    }
}

/// `row += (tn·en + tf·ef) / (tn·wn + tf·wf)` in the cells in the solve; an `edge` far row
/// holds 0 with weight 1.
#[allow(clippy::too_many_arguments)]
#[cfg_attr(not(windloom_static_simd), multiversion(targets = "simd"))]
#[cfg_attr(
    windloom_static_simd,
    multiversion(targets = "simd", dispatcher = "static")
)]
fn correct_row(
    row: &mut [f32],
    en: &[f32],
    wn: &[f32],
    ef: &[f32],
    wf: &[f32],
    tn: f32,
    tf: f32,
    edge: bool,
    inv: &[f32],
) {
    let (ke, kw) = if edge { (0.0, 1.0) } else { (1.0, 0.0) };
    // Every value is written, the kept ones plus −0 (which leaves any value's bits as they
    // are): a conditional store vectorises to a masked store (`vmaskmovps`), slow on AMD's
    // cores.
    for i in 0..row.len() {
        let num = tn * en[i] + tf * (ke * ef[i]);
        let den = tn * wn[i] + tf * (ke * wf[i] + kw);
        let add = if inv[i] > 0.0 && den > 0.0 {
            num / den
        } else {
            -0.0
        };
        row[i] += add;
    }
}

/// One row of the finest level's residual in volume scale, from the Jacobi system's flags:
/// `hx·hz·(Σ w p_n − div − Σw·p)` (0 outside the solve). Interior cells outside the row's
/// `irregular` runs have four fluid neighbours and skip the flags (the same bits, as in
/// [`super::pressure::jacobi_row`]).
#[cfg_attr(not(windloom_static_simd), multiversion(targets = "simd"))]
#[cfg_attr(
    windloom_static_simd,
    multiversion(targets = "simd", dispatcher = "static")
)]
fn fine_residual_row(
    st: &Stencil,
    vol: f32,
    out: &mut [f32],
    [below, row, above]: [&[f32]; 3],
    d: &[f32],
    f: &[u8],
    irregular: &[(usize, usize)],
) {
    let n = row.len();
    let (wx, wz) = (st.wx, st.wz);
    let cell = |fl: u8, l: f32, r: f32, b: f32, a: f32, p: f32, d: f32| {
        let ws = st.weight_sum(fl);
        let s = wx * (pick(fl, L, l) + pick(fl, R, r)) + wz * (pick(fl, B, b) + pick(fl, T, a));
        if fl != 0 { vol * (s - d - ws * p) } else { 0.0 }
    };
    for i in [0, n - 1] {
        let (l, r) = (row[(i + n - 1) % n], row[(i + 1) % n]);
        out[i] = cell(f[i], l, r, below[i], above[i], row[i], d[i]);
    }
    if n < 3 {
        return;
    }
    let ws_regular = st.weight_sum(ALL_FLUID);
    // Interior cells a..b, through the flags or on the fast path.
    let span = |out: &mut [f32], a: usize, b: usize, flagged: bool| {
        let m = b - a;
        let (o, l, c, r) = (
            &mut out[a..b],
            &row[a - 1..][..m],
            &row[a..b],
            &row[a + 1..][..m],
        );
        let (bl, ab, dd) = (&below[a..b], &above[a..b], &d[a..b]);
        if flagged {
            let ff = &f[a..b];
            for i in 0..m {
                o[i] = cell(ff[i], l[i], r[i], bl[i], ab[i], c[i], dd[i]);
            }
        } else {
            for i in 0..m {
                let s = wx * (l[i] + r[i]) + wz * (bl[i] + ab[i]);
                o[i] = vol * (s - dd[i] - ws_regular * c[i]);
            }
        }
    };
    for_spans(n, irregular, |a, b, flagged| span(out, a, b, flagged));
}

impl Solver {
    /// Step 5 by multigrid: the warm start, then `pressure_cycles` V-cycles. The finest level
    /// runs on the Jacobi system's own arrays: its red–black sweeps are blocked passes like
    /// the Jacobi iterations (the warm start folded into the first, the prolonged correction
    /// into the first after the coarse solve), its residual is read from the flags.
    pub fn solve_pressure_multigrid(&mut self) {
        let decay = self.params.pressure_decay;
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
            self.sweeps_blocked(passes, decay, Some(0), None);
            self.multigrid = Some(mg);
            return;
        }
        // Pre-smoothing before the first cycle only: a later cycle starts from the previous
        // one's post-smoothing, and more sweeps there do not lift what the cycle cuts.
        self.sweeps_blocked(2 * PRE_SWEEPS, decay, Some(0), None);
        for _ in 0..cycles {
            self.restrict_fine(&mut mg.levels[1]);
            mg.cycle(1, true);
            let (fine, coarse) = mg.levels.split_at_mut(1);
            expand(&mut fine[0], &coarse[0]);
            self.sweeps_blocked(2 * POST_SWEEPS, 1.0, Some(1), Some(&mg.levels[0]));
        }
        self.multigrid = Some(mg);
    }

    /// The coarse right-hand side from the finest level: each coarse cell sums its children's
    /// volume-scaled residuals.
    fn restrict_fine(&self, c: &mut Level) {
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
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/obstacles.json");
        let mut layout = crate::io::load(&path).unwrap();
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
