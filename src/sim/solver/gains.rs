//! The forces pass's per-face splat gains, kept across steps: an arrow's push at a face is
//! `dir · gain · deficit`, where the gain `1 − e^(−k·g·dt)` (two exponentials and a
//! segment distance) depends only on where the face is, and the deficit on the wind there.
//! An arrow's geometry, the response `k` and `dt` change only on an edit, so each splat's
//! gains are computed once and read back every step after: the forces pass then does a few
//! operations per face and is limited by memory rather than by vector width. Same bits as
//! computing them each step (the same function on the same numbers).

use super::forcing::{Forcing, SplatSpan};
use super::*;

/// What a splat's gains depend on besides the grid (which a solver keeps for life): its
/// segment and radius, the response and the substep, as bits.
type Key = [u32; 7];

fn key(s: &ArrowSplat, k: f32, dt: f32) -> Key {
    [s.a[0], s.a[1], s.b[0], s.b[1], s.radius, k, dt].map(f32::to_bits)
}

/// One splat's gains over the faces its push reaches: for u faces and v faces, per row, the
/// run of faces [`Forcing::splat_span`] computes in one vectorised loop.
pub(crate) struct SplatGains {
    key: Key,
    /// The substep that last used it (older ones go first when the budget is full).
    used: u64,
    /// Per component (u, v), per row of faces: `(first face, faces, offset into gains)`.
    rows: [Vec<(usize, usize, usize)>; 2],
    gains: [Vec<f32>; 2],
}

impl SplatGains {
    /// The gains of row `j`'s run of u faces (v faces with `is_v`): its first face and the
    /// values.
    pub(super) fn row(&self, is_v: bool, j: usize) -> (usize, &[f32]) {
        let c = usize::from(is_v);
        let (first, n, off) = self.rows[c][j];
        (first, &self.gains[c][off..off + n])
    }

    /// Floats held (u and v faces).
    pub(super) fn floats(&self) -> usize {
        self.gains[0].len() + self.gains[1].len()
    }
}

/// The gains kept for the splats of recent substeps, within a budget of floats.
#[derive(Default)]
pub(crate) struct GainCache {
    entries: Vec<SplatGains>,
    /// Substeps run so far (the clock for [`SplatGains::used`]).
    clock: u64,
}

impl GainCache {
    /// Makes sure every splat of `f` that fits in `budget` floats (with the others kept)
    /// has its gains, computing the new ones in parallel over rows, and returns, per splat,
    /// the index of its entry. A splat that does not fit is computed each step instead, as
    /// before there was a cache: the same bits without the memory.
    pub(super) fn refresh(&mut self, f: &Forcing, budget: usize) -> Vec<Option<usize>> {
        self.clock += 1;
        let keys: Vec<Key> = f.splats.iter().map(|s| key(s, f.response, f.dt)).collect();
        for e in &mut self.entries {
            if keys.contains(&e.key) {
                e.used = self.clock;
            }
        }
        for (i, s) in f.splats.iter().enumerate() {
            if self.entries.iter().any(|e| e.key == keys[i]) {
                continue;
            }
            let rows = [false, true].map(|is_v| runs(f, s, f.bounds[i], is_v));
            let need: usize = rows.iter().flatten().map(|r| r.1).sum();
            // Room: drop the least recently used entries that this substep does not use.
            let mut held: usize = self.entries.iter().map(SplatGains::floats).sum();
            while held + need > budget {
                let Some(old) = self
                    .entries
                    .iter()
                    .enumerate()
                    .filter(|(_, e)| e.used != self.clock)
                    .min_by_key(|(_, e)| e.used)
                    .map(|(k, _)| k)
                else {
                    break;
                };
                held -= self.entries.swap_remove(old).floats();
            }
            if held + need > budget {
                continue;
            }
            let gains = [0, 1].map(|c| fill(f, s, c == 1, &rows[c]));
            self.entries.push(SplatGains {
                key: keys[i],
                used: self.clock,
                rows,
                gains,
            });
        }
        keys.iter()
            .map(|k| self.entries.iter().position(|e| &e.key == k))
            .collect()
    }

    pub(super) fn get(&self, k: usize) -> &SplatGains {
        &self.entries[k]
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        self.entries.iter().map(SplatGains::floats).sum::<usize>() * 4
    }
}

/// Per row of u faces (v faces with `is_v`), the run `(first, faces, offset)` of splat `s`
/// (bounds `b`) that [`Forcing::splat_span`] pushes in its vectorised loop, offsets packed.
fn runs(
    f: &Forcing,
    s: &ArrowSplat,
    b: ([f32; 2], [f32; 2]),
    is_v: bool,
) -> Vec<(usize, usize, usize)> {
    let (w, rows) = f.g.faces(is_v);
    let mut off = 0;
    (0..rows)
        .map(|j| {
            let z = f.row_z(j, is_v);
            let run = f
                .splat_row(s, b, z, w, is_v)
                .and_then(|span| f.interior_run(&span, is_v));
            let (first, n) = run.map_or((0, 0), |(a, b)| (a, b - a + 1));
            off += n;
            (first, n, off - n)
        })
        .collect()
}

/// The gains of every run in `rows`, computed in parallel over rows.
fn fill(f: &Forcing, s: &ArrowSplat, is_v: bool, rows: &[(usize, usize, usize)]) -> Vec<f32> {
    let total = rows.last().map_or(0, |r| r.2 + r.1);
    let mut gains = vec![0.0; total];
    let mut rest = gains.as_mut_slice();
    let mut jobs = Vec::with_capacity(rows.len());
    for (j, &(first, n, _)) in rows.iter().enumerate() {
        let (run, tail) = rest.split_at_mut(n);
        rest = tail;
        if n > 0 {
            jobs.push((j, first, run));
        }
    }
    jobs.into_par_iter().for_each(|(j, first, run)| {
        splat_gains(&f.span_of(s, j, is_v, first), run);
    });
    gains
}

/// The gains of a run of faces: `out[q]` for face `first + q` of the run's row, by the very
/// arithmetic [`super::forcing::splat_faces`] used to do inline (the face's x, then
/// [`ArrowSplat::gain`]).
#[simd_kernel]
pub(super) fn splat_gains(p: &SplatSpan, out: &mut [f32]) {
    let splat = *p.s;
    let first = p.first as i32;
    for (q, o) in out.iter_mut().enumerate() {
        *o = splat.gain([p.x(first + q as i32), p.z], p.k, p.dt);
    }
}
