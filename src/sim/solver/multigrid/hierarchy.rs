//! The hierarchy: each level's axes, links, diagonal and fast-path runs, made from the finer
//! level's (see the module's notes), and the prolongation tables between levels.

use super::*;

/// Both axes are halved while a level's cells are at most this many times as wide as deep
/// (or deep as wide); past it only the narrower axis is. Semi-coarsening keeps the coupling
/// near-isotropic, where point smoothing works, but costs a level of half the cells instead
/// of a quarter: at 1.5 (meadow's 120 × 80 m at N × N) it made a cycle 40% dearer. With the
/// Chebyshev smoother reaching down to 0.3 on the coarse levels, 1.6 keeps what a cycle cuts
/// on those layouts (docs/SOLVER.md).
const MAX_ASPECT: f32 = 1.6;

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
    pub(super) fn coarser(&self) -> Self {
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
    pub(super) edge_x: Vec<f32>,
    pub(super) edge_z: Vec<f32>,
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
    /// per coarse row (`nx × coarse ny`), blended along z as rows are read and divided by
    /// `den`.
    pub(crate) ex: Vec<f32>,
    /// Per cell, the weight of the coarse cells in the solve behind its correction (the two
    /// coarse rows' expansion weights, blended along z as the values are): the correction
    /// is `(t_n·e_n + t_f·e_f) / den`. `+∞` outside the solve and where no coarse cell in
    /// the solve reaches the cell, so that the correction adds ±0 there. It depends on the
    /// hierarchy only, so it is made once ([`correction_denominators`]).
    pub(crate) den: Vec<f32>,
    /// The coarse columns `c0..c1` whose two finer cells interpolate toward their left and
    /// right neighbours with the same weights `(t_left, t_right)` (the interior of an axis
    /// coarsened in pairs): [`expand`] runs them without the index table.
    pub(super) pairs: (usize, usize, f32, f32),
    /// The links most interior faces have across x and z (a cell with these four links
    /// and no edge link is "regular"), and per row the runs `(start, end)` of interior cells
    /// (1..nx − 1) that are not, merged across short gaps: the row kernels run everything
    /// else on a fast path that reads no links (the same products, so the same bits).
    pub(super) regular: (f32, f32),
    pub(super) runs: Vec<Vec<(usize, usize)>>,
}

impl Level {
    /// The finest level: the Jacobi system's links times `hx·hz`.
    pub(super) fn finest(
        nx: usize,
        ny: usize,
        hx: f32,
        hz: f32,
        flags: &[u8],
        wraps: bool,
    ) -> Self {
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
            den: Vec::new(),
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
    pub(super) fn coarser(&self, hx: f32, hz: f32) -> Option<Level> {
        let (nx, ny) = (self.nx, self.ny);
        if nx * ny <= COARSEST_CELLS {
            return None;
        }
        let (sx, sz) = self.spacing(hx, hz);
        let can = |n: usize| n > 2;
        // An axis is coarsened while its cells are not much wider than the other axis's.
        let strong_x = sx <= MAX_ASPECT * sz || !can(ny);
        let strong_z = sz <= MAX_ASPECT * sx || !can(nx);
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
    pub(super) fn bytes(&self) -> usize {
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
            + self.den.len();
        let axes = self.x_axis.len() + self.z_axis.len();
        f32s * 4 + axes * 8 + (self.from_x.len() + self.from_z.len()) * 12
    }

    /// `out = Σ a x_n` for row `j`, from its rows `below`, `row`, `above` (wrapped; at a
    /// closed end the row itself, whose link there is 0).
    pub(super) fn link_sum(
        &self,
        j: usize,
        out: &mut [f32],
        below: &[f32],
        row: &[f32],
        above: &[f32],
    ) {
        let (ax, az_b, az_t) = self.links(j);
        link_sum_row(
            out,
            [below, row, above],
            ax,
            az_b,
            az_t,
            self.x_axis.wraps,
            self.regular,
            &self.runs[j],
        );
    }

    /// Row `j`'s links: across its vertical faces (`nx + 1`), and across its lower and upper
    /// horizontal faces.
    fn links(&self, j: usize) -> (&[f32], &[f32], &[f32]) {
        let nx = self.nx;
        (
            &self.ax[j * (nx + 1)..][..nx + 1],
            &self.az[j * nx..][..nx],
            &self.az[(j + 1) * nx..][..nx],
        )
    }

    /// Row `j` of a relaxation pass: [`relax_link_row`] with the level's links.
    #[allow(
        clippy::too_many_arguments,
        reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
    )]
    pub(super) fn relax_row(
        &self,
        j: usize,
        out: &mut [f32],
        rows: [&[f32]; 3],
        b: &[f32],
        b_scale: f32,
        damp: Option<f32>,
    ) {
        let nx = self.nx;
        relax_link_row(
            out,
            rows,
            self.links(j),
            self.x_axis.wraps,
            self.regular,
            &self.runs[j],
            (&b[j * nx..][..nx], b_scale, &self.inv_d[j * nx..][..nx]),
            damp,
        );
    }
}

/// The value most entries of `v` hold (bit for bit; ties go to the smallest bits), judged
/// from about 4,096 evenly spaced entries: the value only decides where the row kernels take
/// their fast path, never a result, and sorting a million links cost the first multigrid
/// step tens of milliseconds at 1000².
pub(super) fn most_common(v: &[f32]) -> f32 {
    let stride = (v.len() / 4096).max(1);
    let mut bits: Vec<u32> = v.iter().step_by(stride).map(|x| x.to_bits()).collect();
    bits.sort_unstable();
    let best = bits
        .chunk_by(|a, b| a == b)
        .max_by(|a, b| a.len().cmp(&b.len()).then(b[0].cmp(&a[0])))
        .map_or(0, |run| run[0]);
    f32::from_bits(best)
}

/// The coarse columns `(c0, c1)` whose finer cells `2c` and `2c + 1` interpolate from `c`
/// toward `c − 1` and `c + 1` with one weight each `(t_left, t_right)`, as [`expand_pairs`]
/// assumes; `c1 == c0` when the axis was not coarsened in pairs.
pub(super) fn regular_pairs(from_x: &[Interp], mx: usize) -> (usize, usize, f32, f32) {
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
pub(super) fn interp_weights(ix: &Interp, inv: &[f32]) -> (f32, f32) {
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
pub(super) fn expansion_weights(f: &Level, c: &Level) -> Vec<f32> {
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

/// [`Level::den`] for level `f` from its expansion weights `ew` (as [`expansion_weights`]
/// makes them) and `in_solve` (the level's `1 / D`, 0 outside): per cell `t_n·w_n +
/// t_f·w_f` over the two coarse rows it blends along z, in the arithmetic the correction
/// used to do in its loop (an open edge's far row holds 0 with weight 1), so the quotient
/// keeps its bits.
pub(super) fn correction_denominators(f: &Level, ew: &[f32], in_solve: &[f32]) -> Vec<f32> {
    let nx = f.nx;
    let mut den = vec![0.0f32; nx * f.ny];
    for (j, row) in den.chunks_mut(nx).enumerate() {
        let iz = f.from_z[j];
        let (tn, tf) = (1.0 - iz.t, iz.t);
        let wn = &ew[iz.near as usize * nx..][..nx];
        let edge = iz.far == Interp::EDGE;
        let wf = if edge {
            wn
        } else {
            &ew[iz.far as usize * nx..][..nx]
        };
        let (ke, kw) = if edge { (0.0, 1.0) } else { (1.0, 0.0) };
        let inv = &in_solve[j * nx..][..nx];
        for i in 0..nx {
            let d = tn * wn[i] + tf * (ke * wf[i] + kw);
            row[i] = if inv[i] > 0.0 && d > 0.0 {
                d
            } else {
                f32::INFINITY
            };
        }
    }
    den
}
