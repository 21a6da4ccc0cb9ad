//! A view-dependent sample of the blades, for renderers that can draw only a fixed number of
//! them (the editor's 3D view on a software adapter draws 40,000 of a meadow's 600,000): a
//! budget on the blades the frame would draw.
//!
//! An even random sample spreads the budget over the whole world, so a close view shows a
//! few blades a square metre. This sample spends it only on blades the cull pass would draw —
//! roots inside the view (widened by [`VIEW_SLACK`], so a small turn of the camera keeps its
//! blades) and not seen edge-on (the cull's orientation test) — dense near the camera and
//! thinning with distance like the blades' size on screen: blade `i` is kept when `hash(i) <
//! p(dᵢ) = min(1, (T / dᵢ)²)`, where `dᵢ` is its root's distance from the eye and `T` is chosen
//! so that exactly `budget` blades are kept: they are the `budget` smallest keys
//! `dᵢ·√hash(i)`. The survivors widen by `1 / p` (at most [`MAX_WIDEN`]) so the thinned field
//! keeps its coverage, and the far field shows the rest (out of view it was bare ground
//! once, so a share of the budget went behind the camera; now the far field covers it until
//! the sample is chosen again).
//!
//! [`assign`] keeps a blade that stays in the sample in the same slot of the renderer's blade
//! buffer, so only the blades that enter or leave the sample change when the camera moves.

use super::Blade;
use glam::{Mat4, Vec3, Vec4};

/// The view widened by this fraction of clip-space `w` before a root counts as outside.
pub const VIEW_SLACK: f32 = 0.15;
/// Widest a surviving blade is drawn, as a multiple of its width.
pub const MAX_WIDEN: f32 = 2.5;

/// Blade `i`'s key: the eye distance at which it would enter the sample; `None` when the
/// frame would not draw it (its root outside the view, or the blade edge-on).
pub fn key(i: u32, blade: &Blade, eye: Vec3, view_proj: &Mat4) -> Option<f32> {
    let root = Vec3::new(blade.pos[0], 0.0, blade.pos[1]);
    let c = *view_proj * Vec4::new(root.x, root.y, root.z, 1.0);
    let h = c.w * (1.0 + VIEW_SLACK);
    let inside = c.w > 0.0 && c.x.abs() <= h && c.y.abs() <= h;
    let (dx, dz) = (root.x - eye.x, root.z - eye.z);
    let ground = dx.hypot(dz);
    let side = super::cull::side(blade);
    let edge_on = ground > 0.0
        && ((dx * side[0] + dz * side[1]) / ground).abs()
            > super::cull::CullParams::default().orientation_limit;
    if !inside || edge_on {
        return None;
    }
    let d = root.distance(eye).max(1e-3);
    Some(d * super::hash01(i, 0x5a3e, 0x7e1d).sqrt())
}

/// The blades a view keeps, nearest first by key, and the threshold `T` (the largest key kept;
/// infinite when every blade is kept).
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    pub blades: Vec<u32>,
    pub threshold: f32,
}

/// The `budget` blades of `all` the frame would draw with the smallest keys for a camera at
/// `eye` with `view_proj` (all of those, when fewer).
pub fn choose(all: &[Blade], eye: Vec3, view_proj: &Mat4, budget: usize) -> Sample {
    if all.len() <= budget {
        return Sample {
            blades: (0..all.len() as u32).collect(),
            threshold: f32::INFINITY,
        };
    }
    let mut keyed: Vec<(f32, u32)> = all
        .iter()
        .enumerate()
        .filter_map(|(i, b)| Some((key(i as u32, b, eye, view_proj)?, i as u32)))
        .collect();
    let by_key = |a: &(f32, u32), b: &(f32, u32)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
    if budget == 0 {
        return Sample {
            blades: Vec::new(),
            threshold: 0.0,
        };
    }
    if keyed.len() <= budget {
        keyed.sort_unstable_by(by_key);
        return Sample {
            blades: keyed.into_iter().map(|(_, i)| i).collect(),
            threshold: f32::INFINITY,
        };
    }
    keyed.select_nth_unstable_by(budget - 1, by_key);
    keyed.truncate(budget);
    keyed.sort_unstable_by(by_key);
    Sample {
        threshold: keyed.last().map_or(0.0, |k| k.0),
        blades: keyed.into_iter().map(|(_, i)| i).collect(),
    }
}

/// How much wider `blade` is drawn in a sample of threshold `threshold` for an eye at `eye`:
/// `1 / p` for the fraction `p` of the blades around it that the sample keeps, at most
/// [`MAX_WIDEN`].
pub fn widen(blade: &Blade, eye: Vec3, threshold: f32) -> f32 {
    let root = Vec3::new(blade.pos[0], 0.0, blade.pos[1]);
    let d = root.distance(eye).max(1e-3);
    let p = (threshold / d).powi(2).min(1.0);
    (1.0 / p.max(1e-6)).min(MAX_WIDEN)
}

/// Slots for a new sample: `chosen` (blade indices, `prev.len()` of them, or fewer) laid into
/// slots so that a blade already in `prev` keeps its slot; the others fill the freed slots in
/// `chosen`'s order. `n` is the number of blades there are. (When fewer are chosen than
/// `prev` holds, the slots left empty are dropped and the ones after them move up.)
pub fn assign(prev: &[u32], chosen: &[u32], n: usize) -> Vec<u32> {
    const NONE: u32 = u32::MAX;
    let mut wanted = vec![false; n];
    for &b in chosen {
        wanted[b as usize] = true;
    }
    let mut placed = vec![false; n];
    let mut slots: Vec<u32> = prev
        .iter()
        .map(|&b| {
            if (b as usize) < n && wanted[b as usize] && !placed[b as usize] {
                placed[b as usize] = true;
                b
            } else {
                NONE
            }
        })
        .collect();
    slots.resize(chosen.len().max(prev.len()), NONE);
    let mut incoming = chosen.iter().copied().filter(|&b| !placed[b as usize]);
    for s in &mut slots {
        if *s == NONE {
            match incoming.next() {
                Some(b) => *s = b,
                None => break,
            }
        }
    }
    slots.retain(|&s| s != NONE);
    slots
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 100 m × 100 m field of 40,000 blades on a 0.5 m lattice.
    fn field() -> Vec<Blade> {
        (0..200 * 200)
            .map(|i| Blade {
                pos: [(i % 200) as f32 * 0.5 + 0.25, (i / 200) as f32 * 0.5 + 0.25],
                facing: 0.0,
                height: 0.5,
                width: 0.05,
                stiffness: 1.0,
                palette: 0,
                variation: 0.0,
            })
            .collect()
    }

    fn camera(eye: Vec3, target: Vec3) -> Mat4 {
        Mat4::perspective_rh(45f32.to_radians(), 1.5, 0.05, 500.0)
            * Mat4::look_at_rh(eye, target, Vec3::Y)
    }

    /// The sample is dense where the camera looks from close by and thins like 1/d² away from
    /// it: every blade near the eye is kept, a far ring keeps a few per cent.
    #[test]
    fn a_close_view_keeps_the_near_field_whole_and_thins_the_far_field() {
        let all = field();
        let eye = Vec3::new(50.0, 2.0, 50.0);
        let vp = camera(eye, Vec3::new(60.0, 0.0, 50.0));
        let s = choose(&all, eye, &vp, 1_500);
        assert_eq!(s.blades.len(), 1_500);
        let mut kept = vec![false; all.len()];
        for &b in &s.blades {
            kept[b as usize] = true;
        }
        // Fraction kept in view, in rings by ground distance from the eye.
        let ring = |r0: f32, r1: f32| {
            let (mut n, mut k) = (0, 0);
            for (i, b) in all.iter().enumerate() {
                let dx = b.pos[0] - eye.x;
                let dz = b.pos[1] - eye.z;
                let r = dx.hypot(dz);
                // In front, within ±30° of the view axis (+x).
                if r >= r0 && r < r1 && dx > 0.0 && dz.abs() < dx * 0.58 {
                    n += 1;
                    k += usize::from(kept[i]);
                }
            }
            k as f32 / n as f32
        };
        // (From 4 m: nearer, the ground is below the view.)
        let near = ring(4.0, s.threshold * 0.5);
        let mid = ring(2.0 * s.threshold, 2.5 * s.threshold);
        let far = ring(4.0 * s.threshold, 5.0 * s.threshold);
        assert_eq!(near, 1.0, "threshold {}", s.threshold);
        // p(d) = (T/d)²: about 1/5 at 2–2.5 T and 1/20 at 4–5 T (3-D distance, eye 2 m up).
        assert!((0.12..0.32).contains(&mid), "mid {mid}");
        assert!((0.025..0.075).contains(&far), "far {far}");
        // An even sample would keep 3.75 % everywhere, behind the camera as much as ahead.
        let behind = s
            .blades
            .iter()
            .filter(|&&b| all[b as usize].pos[0] < eye.x - 5.0)
            .count();
        let ahead = s
            .blades
            .iter()
            .filter(|&&b| all[b as usize].pos[0] > eye.x + 5.0)
            .count();
        assert_eq!(
            behind, 0,
            "the budget goes to blades in view: {ahead} ahead"
        );
        // None edge-on (the cull would not draw them).
        let eyes_side = |b: &Blade| {
            let side = crate::grass::cull::side(b);
            let (dx, dz) = (b.pos[0] - eye.x, b.pos[1] - eye.z);
            ((dx * side[0] + dz * side[1]) / dx.hypot(dz)).abs()
        };
        assert!(s.blades.iter().all(|&b| eyes_side(&all[b as usize]) <= 0.9));
        // Survivors widen to keep coverage, near blades not at all.
        let w = |b: u32| widen(&all[b as usize], eye, s.threshold);
        let nearest = s.blades.iter().copied().min_by(|&a, &b| {
            let d = |i: u32| Vec3::new(all[i as usize].pos[0], 0.0, all[i as usize].pos[1]);
            d(a).distance(eye).total_cmp(&d(b).distance(eye))
        });
        assert_eq!(w(nearest.unwrap()), 1.0);
        assert!(s.blades.iter().all(|&b| (1.0..=MAX_WIDEN).contains(&w(b))));
        assert!(w(*s.blades.last().unwrap()) > 1.0);
    }

    /// With a budget of at least the field, the sample is every blade, unwidened.
    #[test]
    fn a_budget_above_the_field_keeps_every_blade() {
        let all = field();
        let eye = Vec3::new(50.0, 80.0, 120.0);
        let vp = camera(eye, Vec3::new(50.0, 0.0, 50.0));
        let s = choose(&all, eye, &vp, all.len());
        assert_eq!(s.blades.len(), all.len());
        assert_eq!(widen(&all[7], eye, s.threshold), 1.0);
    }

    /// A blade that stays in the sample keeps its slot; each chosen blade takes exactly one.
    #[test]
    fn blades_that_stay_keep_their_slots() {
        let all = field();
        let vp0 = camera(Vec3::new(20.0, 3.0, 20.0), Vec3::new(30.0, 0.0, 30.0));
        let vp1 = camera(Vec3::new(21.0, 3.0, 20.0), Vec3::new(31.0, 0.0, 30.0));
        let a = choose(&all, Vec3::new(20.0, 3.0, 20.0), &vp0, 3_000);
        let b = choose(&all, Vec3::new(21.0, 3.0, 20.0), &vp1, 3_000);
        let slots0 = assign(&[], &a.blades, all.len());
        assert_eq!(slots0, a.blades);
        let slots1 = assign(&slots0, &b.blades, all.len());
        assert_eq!(slots1.len(), 3_000);
        let mut sorted = slots1.clone();
        sorted.sort_unstable();
        let mut want = b.blades.clone();
        want.sort_unstable();
        assert_eq!(sorted, want, "every chosen blade in exactly one slot");
        let stayed = slots0.iter().zip(&slots1).filter(|(x, y)| x == y).count();
        let common = a.blades.iter().filter(|x| b.blades.contains(x)).count();
        assert_eq!(stayed, common, "a blade in both samples keeps its slot");
        assert!(
            common > 2_000,
            "a 1 m step keeps most of the sample: {common}"
        );
    }
}
