//! The row kernels of the cycle: link sums, relaxation, residuals, the prolongation's
//! interior and the correction, each compiled for the SIMD levels `multiversion` targets.

use super::*;

/// The link sum of a row's end cell `i` (0 or n − 1), whose neighbour beyond the end is
/// the row's other end when it `wraps` and 0 (with a 0 link) otherwise.
#[inline(always)]
fn end_link_sum(
    i: usize,
    [below, row, above]: [&[f32]; 3],
    (ax, az_b, az_t): (&[f32], &[f32], &[f32]),
    wraps: bool,
) -> f32 {
    let n = row.len();
    let (first, last) = if wraps {
        (row[n - 1], row[0])
    } else {
        (0.0, 0.0)
    };
    let left = if i == 0 { first } else { row[i - 1] };
    let right = if i + 1 == n { last } else { row[i + 1] };
    ax[i] * left + ax[i + 1] * right + az_b[i] * below[i] + az_t[i] * above[i]
}

/// `out = Σ a x_n` over a row's four links (the row's ends wrap when `wraps`; otherwise
/// their end links are 0). Interior cells outside `irregular` have the `regular` links
/// `(x, z)` and skip the link arrays (the same products in the same order).
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
#[simd_kernel]
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
    for i in [0, n - 1] {
        out[i] = end_link_sum(i, [below, row, above], (ax, az_b, az_t), wraps);
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

/// One relaxation pass's row in one loop: the Jacobi value `v = (Σ a x_n + b_scale·b) / D`
/// (the link sum in [`link_sum_row`]'s order; 0 outside the solve, where `1/D` is 0), and
/// with `damp = Some(w)` the damped value `x + w·(v − x)` (`damp_row`'s arithmetic).
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
#[simd_kernel]
pub(crate) fn relax_link_row(
    out: &mut [f32],
    [below, row, above]: [&[f32]; 3],
    (ax, az_b, az_t): (&[f32], &[f32], &[f32]),
    wraps: bool,
    regular: (f32, f32),
    irregular: &[(usize, usize)],
    (b, b_scale, inv_d): (&[f32], f32, &[f32]),
    damp: Option<f32>,
) {
    let n = out.len();
    for i in [0, n - 1] {
        let s = end_link_sum(i, [below, row, above], (ax, az_b, az_t), wraps);
        let v = (s + b_scale * b[i]) * inv_d[i];
        out[i] = match damp {
            Some(w) => damped(row[i], w, v),
            None => v,
        };
    }
    if n < 3 {
        return;
    }
    let links = (ax, az_b, az_t);
    let rhs = (b, b_scale, inv_d);
    for_spans(n, irregular, |a, e, linked| {
        let rows = [below, row, above];
        match (linked, damp) {
            (true, Some(w)) => relax_span::<true, true>(out, rows, links, regular, rhs, w, a, e),
            (true, None) => relax_span::<true, false>(out, rows, links, regular, rhs, 0.0, a, e),
            (false, Some(w)) => relax_span::<false, true>(out, rows, links, regular, rhs, w, a, e),
            (false, None) => relax_span::<false, false>(out, rows, links, regular, rhs, 0.0, a, e),
        }
    });
}

/// [`relax_link_row`] over the interior cells `a..e`: through the links (`LINKED`) or with
/// the regular ones, damped (`DAMP`, weight `w`) or not.
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
#[inline(always)]
fn relax_span<const LINKED: bool, const DAMP: bool>(
    out: &mut [f32],
    [below, row, above]: [&[f32]; 3],
    (ax, az_b, az_t): (&[f32], &[f32], &[f32]),
    (lx, lz): (f32, f32),
    (b, b_scale, inv_d): (&[f32], f32, &[f32]),
    w: f32,
    a: usize,
    e: usize,
) {
    let m = e - a;
    let (o, l, r) = (&mut out[a..e], &row[a - 1..][..m], &row[a + 1..][..m]);
    let (c, bl, ab) = (&row[a..e], &below[a..e], &above[a..e]);
    let (al, ar) = (&ax[a..e], &ax[a + 1..][..m]);
    let (lb, lt) = (&az_b[a..e], &az_t[a..e]);
    let (bb, inv) = (&b[a..e], &inv_d[a..e]);
    for i in 0..m {
        let s = if LINKED {
            al[i] * l[i] + ar[i] * r[i] + lb[i] * bl[i] + lt[i] * ab[i]
        } else {
            lx * l[i] + lx * r[i] + lz * bl[i] + lz * ab[i]
        };
        let v = (s + b_scale * bb[i]) * inv[i];
        o[i] = if DAMP { damped(c[i], w, v) } else { v };
    }
}

/// `s ← b_scale·b + s − D x` (0 outside the solve), in place over a row of link sums.
#[simd_kernel]
pub(super) fn residual_row(s: &mut [f32], x: &[f32], b: &[f32], b_scale: f32, diag: &[f32]) {
    for (((s, &x), &b), &d) in s.iter_mut().zip(x).zip(b).zip(diag) {
        *s = if d > 0.0 {
            b_scale * b + *s - d * x
        } else {
            0.0
        };
    }
}

/// [`expand`] over the coarse cells `1..x.len() − 1` of a row, each giving its two finer
/// cells (into `e`, two per cell): the left one from the cell and its left neighbour (weight
/// `tl` on the neighbour), the right one from the cell and its right neighbour (`tr`), each
/// coarse cell weighted by whether it is in the solve — the table's arithmetic, without the
/// table's indices and branches, so it vectorises.
#[simd_kernel]
pub(super) fn expand_pairs(e: &mut [f32], x: &[f32], inv: &[f32], tl: f32, tr: f32) {
    let n = e.len() / 2;
    let (x, inv) = (&x[..n + 2], &inv[..n + 2]);
    let inside = |c: usize| f32::from(u8::from(inv[c] > 0.0));
    for k in 0..n {
        let m = [inside(k), inside(k + 1), inside(k + 2)];
        e[2 * k] = (1.0 - tl) * m[1] * x[k + 1] + tl * m[0] * x[k];
        e[2 * k + 1] = (1.0 - tr) * m[1] * x[k + 1] + tr * m[2] * x[k + 2];
    }
}

/// `row += (tn·en + tf·(ke·ef)) / den` (`ke` 0 where the far row is an open edge's 0; `den`
/// +∞ where the correction is ±0). Every value is written: a conditional store vectorises
/// to a masked store (`vmaskmovps`), slow on AMD's cores.
#[simd_kernel]
pub(super) fn correct_row(
    row: &mut [f32],
    en: &[f32],
    ef: &[f32],
    tn: f32,
    tf: f32,
    ke: f32,
    den: &[f32],
) {
    for i in 0..row.len() {
        row[i] += (tn * en[i] + tf * (ke * ef[i])) / den[i];
    }
}

/// One row of the finest level's residual in volume scale, from the Jacobi system's flags:
/// `hx·hz·(Σ w p_n − div − Σw·p)` (0 outside the solve), for the pressure `scale · p` (the
/// warm start, multiplied in as it is read: `× 1` is exact). Interior cells outside the row's
/// `irregular` runs have four fluid neighbours and skip the flags (the same bits, as in
/// [`super::pressure::jacobi_row`]).
#[allow(
    clippy::too_many_arguments,
    reason = "a row kernel: each field row its own slice, which the SIMD clones vectorise"
)]
#[simd_kernel]
pub(super) fn fine_residual_row(
    st: &Stencil,
    vol: f32,
    scale: f32,
    out: &mut [f32],
    [below, row, above]: [&[f32]; 3],
    d: &[f32],
    f: &[u8],
    irregular: &[(usize, usize)],
) {
    let n = row.len();
    let (wx, wz) = (st.wx, st.wz);
    let cell = |fl: u8, l: f32, r: f32, b: f32, a: f32, p: f32, d: f32| {
        let (l, r, b, a, p) = (scale * l, scale * r, scale * b, scale * a, scale * p);
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
                let s = wx * (scale * l[i] + scale * r[i]) + wz * (scale * bl[i] + scale * ab[i]);
                o[i] = vol * (s - dd[i] - ws_regular * (scale * c[i]));
            }
        }
    };
    for_spans(n, irregular, |a, b, flagged| span(out, a, b, flagged));
}
