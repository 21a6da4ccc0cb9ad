//! Keyframes: a tree's strength and direction, an ambient layer's, followed by the CPU
//! solver as keyed; the GPU follows them too (tests/sim/gpu.rs) and a bake with them.

use super::*;
use windloom::doc::{AmbientKind, AmbientLayer, Ease, Key, key_values};

fn key(time: f32, strength: f32, rotation_deg: f32, ease: Ease) -> Key {
    Key {
        time,
        strength,
        rotation_deg,
        ease,
    }
}

#[test]
fn keys_ease_between_values_and_hold_outside() {
    let keys = [
        key(2.0, 0.0, 0.0, Ease::Linear),
        key(4.0, 1.0, 90.0, Ease::Smooth),
        key(8.0, 0.5, 90.0, Ease::Linear),
    ];
    assert_eq!(key_values(&[], 5.0), (1.0, 0.0), "no keys: as authored");
    assert_eq!(key_values(&keys, 0.0).0, 0.0, "held before the first");
    assert_eq!(key_values(&keys, 99.0).0, 0.5, "held after the last");
    let (s, r) = key_values(&keys, 3.0);
    assert!((s - 0.5).abs() < 1e-6 && (r - 45f32.to_radians()).abs() < 1e-6);
    // Smooth: a quarter of the way in time is less than a quarter of the way in value.
    let (s, _) = key_values(&keys, 5.0);
    let linear = 1.0 - 0.5 * 0.25;
    assert!(s > linear && s < 1.0, "{s}");
    assert!(
        (key_values(&keys, 6.0).0 - 0.75).abs() < 1e-6,
        "smoothstep's middle is linear's"
    );
}

fn keyed_tree(keys: Vec<Key>) -> Layout {
    let mut l = Layout::new("keys", [100.0, 100.0], [64, 64]);
    let mut t = tree(1, chain(10, &[[20.0, 50.0], [80.0, 50.0]], 8.0, 8.0));
    t.keys = keys;
    l.trees.push(t);
    l
}

#[test]
fn a_tree_follows_its_keyed_strength_and_turns_about_its_root() {
    // Calm until 3 s, full from 4 s.
    let l = keyed_tree(vec![
        key(3.0, 0.0, 0.0, Ease::Linear),
        key(4.0, 1.0, 0.0, Ease::Linear),
    ]);
    let mut s = Solver::new(&l);
    run(&mut s, 3.0);
    let calm = s.velocity_at([50.0, 50.0]);
    assert!(calm[0].hypot(calm[1]) < 0.05, "keyed to 0: {calm:?}");
    run(&mut s, 4.0);
    let blowing = s.velocity_at([50.0, 50.0]);
    assert!(blowing[0] > 5.0, "keyed back to full: {blowing:?}");

    // Turned a quarter about its root (20, 50): the arrow now points south, along +z.
    let l = keyed_tree(vec![key(0.0, 1.0, 90.0, Ease::Linear)]);
    let mut s = Solver::new(&l);
    run(&mut s, 5.0);
    let w = s.velocity_at([20.0, 75.0]);
    assert!(w[1] > 4.0 && w[1] > 4.0 * w[0].abs(), "south: {w:?}");
    let off = s.velocity_at([50.0, 50.0]);
    assert!(
        off[0].hypot(off[1]) < 1.0,
        "nothing left where it pointed: {off:?}"
    );
}

#[test]
fn an_ambient_layer_follows_its_keyed_strength_and_direction() {
    let mut l = Layout::new("keys", [100.0, 100.0], [48, 48]);
    l.sim.boundary = Boundary::Periodic;
    l.ambient.push(AmbientLayer {
        id: 1,
        name: "breeze".into(),
        enabled: true,
        kind: AmbientKind::Directional {
            direction_deg: 0.0,
            main: 4.0,
            turbulence: 0.0,
            pulse_magnitude: 0.0,
            pulse_frequency: 0.0,
        },
        keys: vec![
            key(0.0, 1.0, 0.0, Ease::Linear),
            key(5.0, 1.0, 0.0, Ease::Linear),
            key(6.0, 0.5, 180.0, Ease::Linear),
        ],
        locked: false,
        hidden: false,
    });
    let mut s = Solver::new(&l);
    run(&mut s, 5.0);
    let east = s.velocity_at([50.0, 50.0]);
    assert!(east[0] > 3.0, "east at first: {east:?}");
    run(&mut s, 10.0);
    let west = s.velocity_at([50.0, 50.0]);
    assert!(
        west[0] < -1.5 && west[0] > -2.5,
        "half as strong, the other way: {west:?}"
    );
}

#[test]
fn keys_are_saved_checked_and_absent_from_files_without_them() {
    // A layout written before keys reads as having none, and writes the same bytes.
    let l = example("two-winds.json");
    assert!(l.trees.iter().all(|t| t.keys.is_empty()));
    let text = doc::to_json(&l);
    assert!(!text.contains("\"keys\""));
    let mut keyed = l.clone();
    keyed.trees[0].keys = vec![
        key(1.0, 0.5, 10.0, Ease::Smooth),
        key(2.0, 1.0, 0.0, Ease::Linear),
    ];
    let back = doc::parse(&doc::to_json(&keyed)).unwrap();
    assert_eq!(back, keyed);
    // Out of order, out of bounds: said with the path.
    keyed.trees[0].keys[1].time = 0.5;
    keyed.trees[0].keys[0].strength = 11.0;
    let issues: Vec<String> = doc::validate(&keyed)
        .iter()
        .map(|i| i.to_string())
        .collect();
    assert!(
        issues
            .iter()
            .any(|i| i.contains("trees[0].keys[1].time") && i.contains("time order")),
        "{issues:?}"
    );
    assert!(
        issues
            .iter()
            .any(|i| i.contains("trees[0].keys[0].strength")),
        "{issues:?}"
    );
}

/// A branch keyed on its own (a point other than the root): off, it drops out of the wind
/// while the rest of its tree blows; turned, the arrow ending at it and those after it turn
/// about that arrow's start, within the tree's own turn; a root takes no branch keys.
#[test]
fn a_branch_ramps_up_alone_and_turns_about_its_start() {
    use windloom::sim::forces;
    // Root (20, 50) → (50, 50) → (80, 50): the second arrow (its end id 12) keyed off until
    // 3 s, full from 4 s.
    let two_arrows = || {
        let mut l = Layout::new("branch", [100.0, 100.0], [64, 64]);
        l.trees.push(tree(
            1,
            chain(10, &[[20.0, 50.0], [50.0, 50.0], [80.0, 50.0]], 8.0, 8.0),
        ));
        l
    };
    let mut l = two_arrows();
    l.trees[0].root.find_mut(12).unwrap().keys = vec![
        key(3.0, 0.0, 0.0, Ease::Linear),
        key(4.0, 1.0, 0.0, Ease::Linear),
    ];
    let strengths = |t: f32| -> Vec<f32> {
        forces::agc_splats(&l, t)
            .iter()
            .map(|s| s.strength)
            .collect()
    };
    assert_eq!(strengths(2.0), vec![8.0], "only the first arrow blows");
    assert_eq!(strengths(5.0), vec![8.0, 8.0]);
    let mut s = Solver::new(&l);
    run(&mut s, 3.0);
    let first = s.velocity_at([35.0, 50.0]);
    let second = s.velocity_at([72.0, 50.0]);
    assert!(first[0] > 4.0, "the tree blows: {first:?}");
    assert!(
        second[0] < 0.6 * first[0],
        "the branch does not: {second:?} {first:?}"
    );
    run(&mut s, 3.0);
    let second = s.velocity_at([72.0, 50.0]);
    assert!(second[0] > 4.0, "ramped up on its own: {second:?}");

    // Turned a quarter about its start (50, 50): it blows south from there.
    let mut l = two_arrows();
    l.trees[0].root.find_mut(12).unwrap().keys = vec![key(0.0, 1.0, 90.0, Ease::Linear)];
    let arrows = forces::agc_splats(&l, 1.0);
    assert_eq!(arrows[0].b, [50.0, 50.0], "the first arrow stays");
    let b = arrows[1].b;
    assert!(
        (b[0] - 50.0).abs() < 1e-4 && (b[1] - 80.0).abs() < 1e-4,
        "{b:?}"
    );
    let mut s = Solver::new(&l);
    run(&mut s, 5.0);
    let w = s.velocity_at([50.0, 68.0]);
    assert!(
        w[1] > 3.0 && w[1] > 2.0 * w[0].abs(),
        "south from the branch: {w:?}"
    );
    // Within the tree's own turn: both a quarter, the branch ends a half turn from east.
    l.trees[0].keys = vec![key(0.0, 1.0, 90.0, Ease::Linear)];
    let arrows = forces::agc_splats(&l, 1.0);
    let (a, b) = (arrows[1].a, arrows[1].b);
    assert!(
        (a[0] - 20.0).abs() < 1e-4 && (a[1] - 80.0).abs() < 1e-4,
        "{a:?}"
    );
    assert!(
        (b[0] + 10.0).abs() < 1e-4 && (b[1] - 80.0).abs() < 1e-4,
        "{b:?}"
    );

    // Saved, read back, and refused on a root.
    let back = doc::parse(&doc::to_json(&l)).unwrap();
    assert_eq!(back, l);
    l.trees[0].root.keys = vec![key(0.0, 1.0, 0.0, Ease::Linear)];
    let issues: Vec<String> = doc::validate(&l).iter().map(|i| i.to_string()).collect();
    assert!(
        issues
            .iter()
            .any(|i| i.contains("trees[0].root.keys") && i.contains("key the tree")),
        "{issues:?}"
    );
}
