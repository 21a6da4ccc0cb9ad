//! How the level's ground shapes the wind: a correction of the 2D solve's field by the
//! terrain's slope and curvature, after MicroMet (Liston & Elder 2006), with the valley
//! channelling taken from the heights' Hessian. `docs/SOLVER.md` ("Terrain") gives the model
//! and why it was chosen; this file is the CPU reference, `shaders/terrain.wgsl` its GPU twin.
//!
//! The solver runs the 2D wind as over flat ground; what leaves it (the map, the grass, the
//! bakes) is the shaped field. Each face's velocity `U` becomes
//! `W · |U| · dir(U − κ (U·n) n)`, with the speed factor
//! `W = max(0, base + ws · clamp(g·Û, −1, 1))`, where per cell `base = 1 + strength·γc·Ωc`
//! (curvature: crests faster, hollows slower), `g` the slope over [`SLOPE_REF`] (windward
//! faster, lee slower) and `κ (U·n) n` the share of the wind across a valley's axis that the
//! valley turns along it.

use crate::doc::Layout;
use bytemuck::{Pod, Zeroable};
use windloom_simd_kernel::simd_kernel;

/// Weight of the slope term (MicroMet's `γs`).
pub const GAMMA_SLOPE: f32 = 0.5;
/// Weight of the curvature term (MicroMet's `γc`).
pub const GAMMA_CURVATURE: f32 = 0.5;
/// The slope along the wind (rise over run) at which the slope term is full: 15°.
pub const SLOPE_REF: f32 = 0.268;
/// The curvature (MicroMet's, a height difference over a distance) at which the curvature
/// term is full.
pub const CURVATURE_REF: f32 = 0.05;
/// The valley curvature (across the valley, times the feature length) at which the
/// channelling is full.
pub const CHANNEL_REF: f32 = 0.2;
/// The most of the wind across a valley its channelling removes (strength 1).
pub const CHANNEL_MAX: f32 = 0.8;
/// The most at any strength: the wind across a valley never reverses.
pub const CHANNEL_LIMIT: f32 = 0.95;

/// One cell's terrain coefficients; mirrors `struct Cell` in `shaders/terrain.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Cell {
    /// The ground's gradient over [`SLOPE_REF`] (x, z).
    pub slope: [f32; 2],
    /// `1 + strength · γc · Ωc`: the speed factor of the curvature.
    pub base: f32,
    /// `strength · γs · 0.5`: the slope term's weight.
    pub ws: f32,
    /// The unit direction across the valley (the Hessian's steepest-up direction).
    pub across: [f32; 2],
    /// The share of the wind across the valley that turns along it, 0 to [`CHANNEL_LIMIT`].
    pub kappa: f32,
    pub _pad: f32,
}

impl Cell {
    /// Flat ground: the wind passes unchanged.
    pub const FLAT: Cell = Cell {
        slope: [0.0, 0.0],
        base: 1.0,
        ws: 0.0,
        across: [1.0, 0.0],
        kappa: 0.0,
        _pad: 0.0,
    };

    /// The mean of two cells' coefficients: a face's, from the cells either side.
    pub fn mean(a: &Cell, b: &Cell) -> Cell {
        let m = |x: f32, y: f32| 0.5 * (x + y);
        // The axis is a line, not an arrow: align b's with a's before averaging.
        let flip = if a.across[0] * b.across[0] + a.across[1] * b.across[1] < 0.0 {
            -1.0
        } else {
            1.0
        };
        let (ax, az) = (
            m(a.across[0], flip * b.across[0]),
            m(a.across[1], flip * b.across[1]),
        );
        let len = (ax * ax + az * az).sqrt();
        let across = if len > 1e-6 {
            [ax / len, az / len]
        } else {
            a.across
        };
        Cell {
            slope: [m(a.slope[0], b.slope[0]), m(a.slope[1], b.slope[1])],
            base: m(a.base, b.base),
            ws: m(a.ws, b.ws),
            across,
            kappa: m(a.kappa, b.kappa),
            _pad: 0.0,
        }
    }
}

/// The terrain's hand on velocity `u` (m/s) where the coefficients are `c`. Branch-free, so
/// the rows vectorise: over flat ground (`Cell::FLAT`) it returns `u`'s bits exactly.
#[inline(always)]
pub fn shape(u: [f32; 2], c: &Cell) -> [f32; 2] {
    shape_parts(
        u,
        [c.slope[0], c.slope[1], c.base, c.ws],
        [c.across[0], c.across[1], c.kappa],
    )
}

/// [`shape`] with the coefficients as numbers: `[slope x, slope z, base, ws]` and
/// `[across x, across z, kappa]`.
#[inline(always)]
fn shape_parts(u: [f32; 2], [sx, sz, base, ws]: [f32; 4], [ax, az, kappa]: [f32; 3]) -> [f32; 2] {
    let speed = (u[0] * u[0] + u[1] * u[1]).sqrt();
    let inv = if speed > 0.0 { 1.0 / speed } else { 0.0 };
    let along = ((sx * u[0] + sz * u[1]) * inv).clamp(-1.0, 1.0);
    let w = (base + ws * along).max(0.0);
    let d = kappa * (u[0] * ax + u[1] * az);
    let t = [u[0] - d * ax, u[1] - d * az];
    let len = (t[0] * t[0] + t[1] * t[1]).sqrt();
    let k = if len > 0.0 { w * speed / len } else { 0.0 };
    [t[0] * k, t[1] * k]
}

/// Each face's coefficients as a struct of arrays (a [`Cell`]'s fields, one array each), so
/// the CPU's rows read them as vectors; the GPU gets them as [`Cell`]s
/// ([`TerrainField::face_cells`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FaceCoefficients {
    sx: Vec<f32>,
    sz: Vec<f32>,
    base: Vec<f32>,
    ws: Vec<f32>,
    ax: Vec<f32>,
    az: Vec<f32>,
    kappa: Vec<f32>,
}

/// A run of [`FaceCoefficients`].
#[derive(Clone, Copy)]
struct Coef<'a> {
    sx: &'a [f32],
    sz: &'a [f32],
    base: &'a [f32],
    ws: &'a [f32],
    ax: &'a [f32],
    az: &'a [f32],
    kappa: &'a [f32],
}

impl<'a> Coef<'a> {
    /// Entries `k0 .. k0 + n`, each slice exactly that long (so a row's loop is checked once).
    #[inline(always)]
    fn sub(&self, k0: usize, n: usize) -> Coef<'a> {
        Coef {
            sx: &self.sx[k0..][..n],
            sz: &self.sz[k0..][..n],
            base: &self.base[k0..][..n],
            ws: &self.ws[k0..][..n],
            ax: &self.ax[k0..][..n],
            az: &self.az[k0..][..n],
            kappa: &self.kappa[k0..][..n],
        }
    }

    #[inline(always)]
    fn at(&self, i: usize) -> ([f32; 4], [f32; 3]) {
        (
            [self.sx[i], self.sz[i], self.base[i], self.ws[i]],
            [self.ax[i], self.az[i], self.kappa[i]],
        )
    }
}

impl FaceCoefficients {
    fn push(&mut self, c: Cell) {
        self.sx.push(c.slope[0]);
        self.sz.push(c.slope[1]);
        self.base.push(c.base);
        self.ws.push(c.ws);
        self.ax.push(c.across[0]);
        self.az.push(c.across[1]);
        self.kappa.push(c.kappa);
    }

    fn len(&self) -> usize {
        self.sx.len()
    }

    fn get(&self, k: usize) -> Cell {
        Cell {
            slope: [self.sx[k], self.sz[k]],
            base: self.base[k],
            ws: self.ws[k],
            across: [self.ax[k], self.az[k]],
            kappa: self.kappa[k],
            _pad: 0.0,
        }
    }

    /// Faces `k0 .. k0 + n`.
    fn run(&self, k0: usize, n: usize) -> Coef<'_> {
        Coef {
            sx: &self.sx,
            sz: &self.sz,
            base: &self.base,
            ws: &self.ws,
            ax: &self.ax,
            az: &self.az,
            kappa: &self.kappa,
        }
        .sub(k0, n)
    }
}

/// One row of shaped u faces: `out[i]` from `u[i]`, the v faces of the rows below (`b`) and
/// above (`t`) and the coefficients `c` (`nx + 1` faces, `nx` v faces a row).
#[simd_kernel]
fn shape_u_row(u: &[f32], free: &[u8], b: &[f32], t: &[f32], c: Coef<'_>, out: &mut [f32]) {
    let nx = b.len();
    let (u, free, out, c) = (
        &u[..nx + 1],
        &free[..nx + 1],
        &mut out[..nx + 1],
        c.sub(0, nx + 1),
    );
    let vbar = |l: usize, r: usize| 0.25 * (b[l] + b[r] + t[l] + t[r]);
    // A face that is not free (a wall, a solid's side) stays still, whatever blows beside it.
    let keep = |i: usize, x: f32| if free[i] != 0 { x } else { 0.0 };
    let (p, q) = c.at(0);
    out[0] = keep(0, shape_parts([u[0], vbar(0, 0)], p, q)[0]);
    for i in 1..nx {
        let (p, q) = c.at(i);
        out[i] = keep(i, shape_parts([u[i], vbar(i - 1, i)], p, q)[0]);
    }
    let (p, q) = c.at(nx);
    out[nx] = keep(nx, shape_parts([u[nx], vbar(nx - 1, nx - 1)], p, q)[0]);
}

/// One row of shaped v faces: `out[i]` from `v[i]`, the u faces of the rows below (`b`) and
/// above (`t`, `nx + 1` each) and the coefficients `c`.
#[simd_kernel]
fn shape_v_row(v: &[f32], free: &[u8], b: &[f32], t: &[f32], c: Coef<'_>, out: &mut [f32]) {
    let nx = v.len();
    let (free, b, t, out, c) = (
        &free[..nx],
        &b[..nx + 1],
        &t[..nx + 1],
        &mut out[..nx],
        c.sub(0, nx),
    );
    for i in 0..nx {
        let ubar = 0.25 * (b[i] + b[i + 1] + t[i] + t[i + 1]);
        let (p, q) = c.at(i);
        let x = shape_parts([ubar, v[i]], p, q)[1];
        out[i] = if free[i] != 0 { x } else { 0.0 };
    }
}

/// The terrain of a layout laid over its grid: the ground's height at every cell centre and
/// each cell's coefficients. `None` for a layout without terrain (the wind is the 2D solve's).
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainField {
    pub nx: usize,
    pub ny: usize,
    /// The grid's minimum corner and cell size, metres.
    pub origin: [f32; 2],
    pub cell: [f32; 2],
    /// Metres above the datum, at each cell centre, row-major.
    pub heights: Vec<f32>,
    /// Each face's coefficients, the mean of the cells either side ([`Cell::mean`], the
    /// grid's edges clamped): the u faces (`(nx + 1) × ny`), then the v faces
    /// (`nx × (ny + 1)`).
    faces: FaceCoefficients,
}

impl TerrainField {
    /// The terrain of `layout` over its grid, or `None` when it has none. Slope and curvature
    /// are measured over the terrain's feature length from the heightmap itself (bilinear),
    /// so they do not change with the grid.
    pub fn new(layout: &Layout) -> Option<Self> {
        let t = layout.world.terrain.as_ref()?;
        let w = &layout.world;
        let [nx, ny] = [w.grid[0] as usize, w.grid[1] as usize];
        let (hx, hz) = (w.size[0] / nx as f32, w.size[1] / ny as f32);
        let bounds = layout.bounds();
        let l = t.feature_length_for(w.size);
        let d = l * std::f32::consts::FRAC_1_SQRT_2;
        let at = |x: f32, z: f32| t.height_at([x, z], bounds);
        let strength = t.strength;
        let mut heights = Vec::with_capacity(nx * ny);
        let mut cells = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            let z = w.origin[1] + (j as f32 + 0.5) * hz;
            for i in 0..nx {
                let x = w.origin[0] + (i as f32 + 0.5) * hx;
                let h = at(x, z);
                let (e, wst) = (at(x + l, z), at(x - l, z));
                let (n, s) = (at(x, z + l), at(x, z - l));
                let (ne, sw) = (at(x + d, z + d), at(x - d, z - d));
                let (nw, se) = (at(x - d, z + d), at(x + d, z - d));
                heights.push(h);
                cells.push(coefficients(
                    h,
                    [e, wst, n, s],
                    [ne, sw, nw, se],
                    l,
                    strength,
                ));
            }
        }
        let cell = |i: isize, j: isize| {
            let i = i.clamp(0, nx as isize - 1) as usize;
            let j = j.clamp(0, ny as isize - 1) as usize;
            &cells[j * nx + i]
        };
        let mut faces = FaceCoefficients::default();
        for j in 0..ny as isize {
            for i in 0..=nx as isize {
                faces.push(Cell::mean(cell(i - 1, j), cell(i, j)));
            }
        }
        for j in 0..=ny as isize {
            for i in 0..nx as isize {
                faces.push(Cell::mean(cell(i, j - 1), cell(i, j)));
            }
        }
        Some(Self {
            nx,
            ny,
            origin: w.origin,
            cell: [hx, hz],
            heights,
            faces,
        })
    }

    /// Each face's coefficients as the GPU's terrain pass reads them: the u faces, then the
    /// v faces.
    pub fn face_cells(&self) -> Vec<Cell> {
        (0..self.faces.len()).map(|k| self.faces.get(k)).collect()
    }

    /// The ground's height at world `p`, bilinear between the cell centres and clamped at the
    /// grid's edges: what the 3D view stands the grass, the ground and the obstacles on (the
    /// CPU twin of `ground` in `shaders/grass_common.wgsl`).
    pub fn ground_at(&self, p: [f32; 2]) -> f32 {
        let gx = ((p[0] - self.origin[0]) / self.cell[0] - 0.5).clamp(0.0, (self.nx - 1) as f32);
        let gz = ((p[1] - self.origin[1]) / self.cell[1] - 0.5).clamp(0.0, (self.ny - 1) as f32);
        let (i0, j0) = (gx as usize, gz as usize);
        let (i1, j1) = ((i0 + 1).min(self.nx - 1), (j0 + 1).min(self.ny - 1));
        let (fx, fz) = (gx - i0 as f32, gz - j0 as f32);
        let h = |i: usize, j: usize| self.heights[j * self.nx + i];
        let a = h(i0, j0) + (h(i1, j0) - h(i0, j0)) * fx;
        let b = h(i0, j1) + (h(i1, j1) - h(i0, j1)) * fx;
        a + (b - a) * fz
    }

    /// The shaped faces of the solver's faces `u` (`(nx + 1) × ny`) and `v` (`nx × (ny + 1)`):
    /// each face's velocity (its own component and the mean of the four nearest faces of the
    /// other, the grid's edges clamped) shaped with its coefficients ([`Self::face_cells`]); a face
    /// whose `free` flag is 0 (a wall, a solid's side: `u_free`, `v_free`) stays 0.
    pub fn shape_faces(
        &self,
        (u, v): (&[f32], &[f32]),
        (u_free, v_free): (&[u8], &[u8]),
    ) -> (Vec<f32>, Vec<f32>) {
        let (mut su, mut sv) = (vec![0.0; u.len()], vec![0.0; v.len()]);
        self.shape_faces_into((u, v), (u_free, v_free), (&mut su, &mut sv));
        (su, sv)
    }

    /// [`Self::shape_faces`] into `su` and `sv` (as long as `u` and `v`).
    pub fn shape_faces_into(
        &self,
        (u, v): (&[f32], &[f32]),
        (u_free, v_free): (&[u8], &[u8]),
        (su, sv): (&mut [f32], &mut [f32]),
    ) {
        use rayon::prelude::*;
        let (nx, ny) = (self.nx, self.ny);
        let (cu, cv) = (self.faces.run(0, u.len()), self.faces.run(u.len(), v.len()));
        su.par_chunks_mut(nx + 1).enumerate().for_each(|(j, out)| {
            let k0 = j * (nx + 1);
            // The v faces below and above row j.
            let (b, t) = (&v[j * nx..][..nx], &v[(j + 1) * nx..][..nx]);
            let c = cu.sub(k0, nx + 1);
            shape_u_row(&u[k0..][..nx + 1], &u_free[k0..][..nx + 1], b, t, c, out);
        });
        sv.par_chunks_mut(nx).enumerate().for_each(|(j, out)| {
            let k0 = j * nx;
            // The u faces of the rows below and above face row j (the edge rows clamped).
            let row = |r: usize| &u[r * (nx + 1)..][..nx + 1];
            let (b, t) = (row(j.saturating_sub(1)), row(j.min(ny - 1)));
            let c = cv.sub(k0, nx);
            shape_v_row(&v[k0..][..nx], &v_free[k0..][..nx], b, t, c, out);
        });
    }
}

/// The map's picture of the terrain over the world rectangle, `w × h` pixels, row 0 at the
/// world's smallest z, straight-alpha RGBA: with `shade` a hill shade (lit from the
/// north-west, the map's top left, 45° up: slopes facing it lighter, slopes away darker, flat
/// ground clear) and with `contours` lines every [`contour_interval`] metres. `None` for a
/// layout without terrain.
pub fn relief(
    layout: &Layout,
    (w, h): (usize, usize),
    shade: bool,
    contours: bool,
) -> Option<Vec<u8>> {
    let t = layout.world.terrain.as_ref()?;
    let (min, max) = layout.bounds();
    let (dx, dz) = ((max[0] - min[0]) / w as f32, (max[1] - min[1]) / h as f32);
    let heights: Vec<f32> = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| {
            let p = [
                min[0] + (i as f32 + 0.5) * dx,
                min[1] + (j as f32 + 0.5) * dz,
            ];
            t.height_at(p, (min, max))
        })
        .collect();
    let at = |i: usize, j: usize| heights[j.min(h - 1) * w + i.min(w - 1)];
    let interval = contour_interval(t.heights[1] - t.heights[0]);
    // Toward the sun: north-west (−x, −z on the map, its top left), 45° up.
    let sun = [-0.5f32, 0.5_f32.sqrt(), -0.5];
    let mut out = vec![0u8; w * h * 4];
    for j in 0..h {
        for i in 0..w {
            let gx = (at(i + 1, j) - at(i.saturating_sub(1), j)) / (2.0 * dx);
            let gz = (at(i, j + 1) - at(i, j.saturating_sub(1))) / (2.0 * dz);
            let n = [-gx, 1.0, -gz];
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let lit = (n[0] * sun[0] + n[1] * sun[1] + n[2] * sun[2]) / len;
            let d = lit - sun[1];
            let px = &mut out[(j * w + i) * 4..][..4];
            if shade {
                let a = (d.abs() * 1.6).min(0.6);
                let v = if d > 0.0 { 255 } else { 0 };
                px.copy_from_slice(&[v, v, v, (a * 255.0) as u8]);
            }
            if contours && interval > 0.0 {
                let band = |x: f32| (x / interval).floor();
                let here = band(at(i, j));
                if band(at(i + 1, j)) != here || band(at(i, j + 1)) != here {
                    px.copy_from_slice(&[40, 25, 10, 190]);
                }
            }
        }
    }
    Some(out)
}

/// The contour interval for heights spanning `range` metres: 1, 2 or 5 times a power of ten,
/// about ten lines over the range.
pub fn contour_interval(range: f32) -> f32 {
    if range <= 0.0 || !range.is_finite() {
        return 0.0;
    }
    let raw = range / 10.0;
    let p = crate::num::powf(10.0, crate::num::log10(raw).floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&x| x >= raw)
        .unwrap_or(10.0 * p)
}

/// A cell's coefficients from the height `h` there and the heights a feature length `l` away:
/// `[east, west, north, south]` along the axes and `[ne, sw, nw, se]` along the diagonals.
fn coefficients(h: f32, axes: [f32; 4], diag: [f32; 4], l: f32, strength: f32) -> Cell {
    let [e, w, n, s] = axes;
    let [ne, sw, nw, se] = diag;
    if axes.iter().chain(&diag).all(|&x| x == h) {
        // Flat here: exactly today's wind.
        return Cell {
            ws: 0.0,
            ..Cell::FLAT
        };
    }
    let g = [(e - w) / (2.0 * l), (n - s) / (2.0 * l)];
    // MicroMet's curvature: the height over the mean of each opposite pair, over twice the
    // distance, averaged over the four directions. Positive on crests.
    let pair = |a: f32, b: f32| (h - 0.5 * (a + b)) / (2.0 * l);
    let curvature = 0.25 * (pair(e, w) + pair(n, s) + pair(ne, sw) + pair(nw, se));
    let omega_c = 0.5 * (curvature / CURVATURE_REF).clamp(-1.0, 1.0);
    // The Hessian: its largest eigenvalue's direction is across a valley, and a valley is
    // where it is positive and the other is not (a bowl has no axis to follow).
    let hxx = (e - 2.0 * h + w) / (l * l);
    let hzz = (n - 2.0 * h + s) / (l * l);
    let hxz = (ne - nw - se + sw) / (2.0 * l * l);
    let mean = 0.5 * (hxx + hzz);
    let r = (0.25 * (hxx - hzz) * (hxx - hzz) + hxz * hxz).sqrt();
    let (l1, l2) = (mean + r, mean - r);
    let theta = 0.5 * crate::num::atan2(2.0 * hxz, hxx - hzz);
    let valley = ((l1 - l2.max(0.0)).max(0.0) * l / CHANNEL_REF).min(1.0);
    Cell {
        slope: [g[0] / SLOPE_REF, g[1] / SLOPE_REF],
        base: 1.0 + strength * GAMMA_CURVATURE * omega_c,
        ws: strength * GAMMA_SLOPE * 0.5,
        across: [crate::num::cos(theta), crate::num::sin(theta)],
        kappa: (strength * CHANNEL_MAX * valley).min(CHANNEL_LIMIT),
        _pad: 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contours_fall_on_round_numbers() {
        assert_eq!(contour_interval(20.0), 2.0);
        assert_eq!(contour_interval(100.0), 10.0);
        assert_eq!(contour_interval(35.0), 5.0);
        assert_eq!(contour_interval(0.0), 0.0);
    }

    #[test]
    fn flat_cells_pass_the_wind_bit_for_bit() {
        let c = coefficients(3.0, [3.0; 4], [3.0; 4], 10.0, 1.0);
        for u in [[1.3f32, -0.7], [1e-7, 3.0], [-12.5, 0.0]] {
            let s = shape(u, &c);
            assert_eq!(s.map(f32::to_bits), u.map(f32::to_bits));
        }
    }

    #[test]
    fn a_valley_removes_the_wind_across_it_and_keeps_the_speed() {
        // A valley along z: heights rise with |x|.
        let c = coefficients(0.0, [4.0, 4.0, 0.0, 0.0], [2.0, 2.0, 2.0, 2.0], 10.0, 1.0);
        assert!(c.kappa > 0.5, "{c:?}");
        assert!(c.across[0].abs() > 0.99, "{c:?}");
        let s = shape([1.0, 1.0], &c);
        let angle = crate::num::atan2(s[0].abs(), s[1].abs()).to_degrees();
        assert!(angle < 15.0, "{angle}° from the valley's axis");
        let speed = (s[0] * s[0] + s[1] * s[1]).sqrt();
        assert!((speed / 2f32.sqrt() - c.base).abs() < 1e-5);
    }
}
