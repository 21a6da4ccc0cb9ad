//! A baked frame ([`Field`]) and what is done to frames: area-averaged resampling, the
//! check that a frame holds only finite winds, and the crossfade that makes a loop seamless.

use super::error::BakeError;

/// A baked frame: cell-centred world velocity `[x, z]` in m/s, row-major (`i` along +x fastest,
/// row `j` along +z).
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    pub nx: usize,
    pub ny: usize,
    pub data: Vec<[f32; 2]>,
}

impl Field {
    pub fn at(&self, i: usize, j: usize) -> [f32; 2] {
        self.data[j * self.nx + i]
    }

    pub fn max_speed(&self) -> f32 {
        self.data
            .iter()
            .map(|v| crate::num::hypot(v[0], v[1]))
            .fold(0.0, f32::max)
    }

    /// Area-averaged resampling onto `nx × ny` cells: each output cell is the mean of the
    /// input cells it covers, weighted by the overlapping area.
    pub fn resample(&self, nx: usize, ny: usize) -> Field {
        if nx == self.nx && ny == self.ny {
            return self.clone();
        }
        let wx = overlap_weights(self.nx, nx);
        let wz = overlap_weights(self.ny, ny);
        let mut data = vec![[0.0f32; 2]; nx * ny];
        for (oj, zs) in wz.iter().enumerate() {
            for (oi, xs) in wx.iter().enumerate() {
                let mut acc = [0.0f64; 2];
                let mut total = 0.0f64;
                for &(j, a) in zs {
                    for &(i, b) in xs {
                        let w = a * b;
                        let v = self.at(i, j);
                        acc[0] += f64::from(v[0]) * w;
                        acc[1] += f64::from(v[1]) * w;
                        total += w;
                    }
                }
                data[oj * nx + oi] = [(acc[0] / total) as f32, (acc[1] / total) as f32];
            }
        }
        Field { nx, ny, data }
    }
}

/// For each of `m` output cells over `n` input cells: the input cells it overlaps and by how
/// much (in input-cell units).
fn overlap_weights(n: usize, m: usize) -> Vec<Vec<(usize, f64)>> {
    let scale = n as f64 / m as f64;
    (0..m)
        .map(|o| {
            let (a, b) = (o as f64 * scale, (o + 1) as f64 * scale);
            let first = a.floor() as usize;
            let last = (b.ceil() as usize).min(n);
            (first..last)
                .map(|i| {
                    let w = (b.min(i as f64 + 1.0) - a.max(i as f64)).max(0.0);
                    (i, w)
                })
                .filter(|(_, w)| *w > 0.0)
                .collect()
        })
        .collect()
}

/// Refuses a frame holding a NaN or an infinity: a bake never ships one.
pub fn check_finite(field: &[[f32; 2]], frame: usize) -> Result<(), BakeError> {
    match field
        .iter()
        .position(|v| !(v[0].is_finite() && v[1].is_finite()))
    {
        Some(cell) => Err(BakeError::NonFinite { frame, cell }),
        None => Ok(()),
    }
}

/// Frame `k` of a seamless loop of `n` frames from `2n` simulated ones `S`: it blends
/// `S[k+n]` (weight `1 − k/n`) with `S[k]` (weight `k/n`). Frame 0 is `S[n]`; the last frame is
/// almost `S[n−1]`, whose natural successor is `S[n]`, so playing the last frame then the
/// first is one ordinary simulation step.
pub fn crossfade(late: &Field, early: &Field, k: usize, n: usize) -> Field {
    let w = k as f32 / n as f32;
    Field {
        nx: late.nx,
        ny: late.ny,
        data: late
            .data
            .iter()
            .zip(&early.data)
            .map(|(p, q)| [p[0] * (1.0 - w) + q[0] * w, p[1] * (1.0 - w) + q[1] * w])
            .collect(),
    }
}
