//! The CPU solver behaves like a fluid, and the force model like the paper's AGC trees.

use proptest::prelude::*;
use std::path::Path;
use windloom::doc::{self, Boundary, Emission, Layout, Node, Shape, TimeWindow, Tree};
use windloom::sim::{Solver, forces};

fn example(name: &str) -> Layout {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("layouts")
        .join(name);
    windloom::io::load(&p).unwrap_or_else(|e| panic!("{e}"))
}

fn tree(id: u32, root: Node) -> Tree {
    Tree {
        id,
        name: format!("tree {id}"),
        enabled: true,
        window: TimeWindow::Always,
        emission: Emission::Continuous,
        propagation_speed: 50.0,
        root,
    }
}

/// A chain root → a → b … through `points`, every arrow with the same strength and radius.
fn chain(first_id: u32, points: &[[f32; 2]], strength: f32, radius: f32) -> Node {
    let mut node: Option<Node> = None;
    for (k, p) in points.iter().enumerate().rev() {
        let mut n = Node::new(first_id + k as u32, *p, strength, radius);
        if let Some(child) = node.take() {
            n.children.push(child);
        }
        node = Some(n);
    }
    node.unwrap()
}

fn run(solver: &mut Solver, seconds: f32) {
    let steps = (seconds / solver.params.dt).round() as usize;
    for _ in 0..steps {
        solver.step();
    }
}

/// Deterministic pseudo-random values in [-1, 1].
fn noise_field(n: usize, seed: u64) -> Vec<f32> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        })
        .collect()
}

/// A solver for `l` whose faces hold white noise of amplitude `a` (u from `seeds.0`, v from
/// `seeds.1`), with the boundaries enforced.
fn noisy_solver(l: &Layout, seeds: (u64, u64), a: f32) -> Solver {
    let mut s = Solver::new(l);
    let (u, v) = s.faces_mut();
    for (f, seed) in [(u, seeds.0), (v, seeds.1)] {
        let noise = noise_field(f.len(), seed);
        for (x, n) in f.iter_mut().zip(noise) {
            *x = a * n;
        }
    }
    s.enforce_boundaries();
    s
}

fn random_solver(boundary: Boundary, n: u32) -> Solver {
    let mut l = Layout::new("random", [64.0, 64.0], [n, n]);
    l.sim.boundary = boundary;
    l.sim.pressure_decay = 0.0;
    noisy_solver(&l, (1, 2), 1.0)
}

/// The projection's divergence reduction per Jacobi iteration count, on white-noise fields.
/// Printed (run with --nocapture) and recorded in docs/SOLVER.md.
#[test]
fn projection_removes_most_divergence() {
    for boundary in [Boundary::Open, Boundary::Closed, Boundary::Periodic] {
        let mut factors = Vec::new();
        for iterations in [20u32, 50, 100, 200] {
            let mut s = random_solver(boundary, 128);
            s.params.pressure_iterations = iterations;
            let before = s.divergence_rms();
            s.solve_pressure();
            s.subtract_gradient();
            let after = s.divergence_rms();
            factors.push((iterations, before / after));
        }
        println!("{boundary:?}: divergence reduction (iterations, factor): {factors:?}");
        // Stated targets: ≥ 5× at the default 20 iterations, ≥ 15× at 200, and more
        // iterations never worse.
        assert!(factors[0].1 >= 5.0, "{boundary:?}: {factors:?}");
        assert!(factors[3].1 >= 15.0, "{boundary:?}: {factors:?}");
        assert!(
            factors.windows(2).all(|w| w[1].1 >= w[0].1),
            "{boundary:?}: {factors:?}"
        );
    }
}

/// Multigrid: the projection of a white-noise field per V-cycle count, for every boundary, on
/// grids with odd sizes (coarse cells with one child), non-square cells (semi-coarsened
/// levels) and obstacles. Printed (run with --nocapture) and recorded in docs/SOLVER.md. A
/// cold start, which the cycle is not tuned for: the finest level is not smoothed before its
/// first restriction (a running flow's warm start leaves little grid-scale noise there), so
/// the first cycle cuts white noise less than a developed step (28–40× against 108–405×).
#[test]
fn multigrid_cuts_white_noise_divergence_twentyfold_in_one_cycle_five_hundredfold_in_two() {
    for boundary in [Boundary::Open, Boundary::Closed, Boundary::Periodic] {
        for (what, grid) in [
            ("128x128", [128, 128]),
            ("125x63", [125, 63]),
            ("200x48", [200, 48]),
            ("150x100", [150, 100]),
            ("obstacles 90x70", [90, 70]),
        ] {
            let mut factors = Vec::new();
            for cycles in [1u32, 2, 3] {
                let mut l = if what.starts_with("obstacles") {
                    example("obstacles.json")
                } else {
                    Layout::new("random", [64.0, 64.0], grid)
                };
                l.world.grid = grid;
                l.sim.boundary = boundary;
                l.sim.pressure_decay = 0.0;
                l.sim.pressure = doc::PressureSolve::Multigrid;
                l.sim.pressure_cycles = cycles;
                let mut s = noisy_solver(&l, (1, 2), 1.0);
                let before = s.divergence_rms();
                s.solve_pressure();
                s.subtract_gradient();
                let after = s.divergence_rms();
                factors.push(before / after);
            }
            println!("{boundary:?} {what}: divergence cut by 1, 2, 3 V-cycles: {factors:.1?}");
            assert!(factors[0] >= 20.0, "{boundary:?} {what}: {factors:?}");
            assert!(factors[1] >= 500.0, "{boundary:?} {what}: {factors:?}");
            assert!(
                factors[2] >= 5.0 * factors[1],
                "{boundary:?} {what}: {factors:?}"
            );
        }
    }
}

/// Multigrid's float32 floor: cycled to convergence, the projection leaves white noise's
/// divergence at the rounding of the pressure it solves for, and the order of the smoothing
/// weights sets that rounding. Measured: 1.0e7× (open, 256²) and 6.9e6× (periodic, 300 ×
/// 200) ending on the smallest weight; 4.7e6× and 3.3e6× ending on the largest.
#[test]
fn multigrid_converges_to_the_float_floor() {
    for (boundary, grid) in [
        (Boundary::Open, [256, 256]),
        (Boundary::Periodic, [300, 200]),
    ] {
        let mut l = Layout::new("random", [64.0, 64.0], grid);
        l.sim.boundary = boundary;
        l.sim.pressure_decay = 0.0;
        l.sim.pressure = doc::PressureSolve::Multigrid;
        l.sim.pressure_cycles = 12;
        let mut s = noisy_solver(&l, (3, 4), 1.0);
        let before = s.divergence_rms();
        s.solve_pressure();
        s.subtract_gradient();
        let after = s.divergence_rms();
        let cut = before / after;
        println!("{boundary:?} {grid:?}: 12 V-cycles cut white noise's divergence {cut:.3e}×");
        assert!(cut >= 5.5e6, "{boundary:?} {grid:?}: only {cut:.3e}×");
    }
}

/// Every bundled example, run with multigrid at its own grid until the flow is developed:
/// one step's projection cuts the divergence at least a hundredfold with one V-cycle (issue
/// 14's bar) and a thousandfold with the default two; 20 Jacobi iterations cut it about
/// 1.1× on the same flows.
#[test]
fn multigrid_keeps_every_example_a_hundredfold_closer_to_divergence_free() {
    for name in [
        "meadow.json",
        "obstacles.json",
        "two-winds.json",
        "breeze-fft.json",
        "branching.json",
    ] {
        let cut = |pressure, cycles: Option<u32>| {
            let mut l = example(name);
            l.sim.pressure = pressure;
            if let Some(c) = cycles {
                l.sim.pressure_cycles = c;
            }
            let mut s = Solver::new(&l);
            run(&mut s, 1.0);
            s.measure_projection = true;
            s.step();
            let (before, after) = s.projection.unwrap();
            assert!(
                after.is_finite() && before > 0.0,
                "{name}: {before} {after}"
            );
            before / after
        };
        let (one, two, jacobi) = (
            cut(doc::PressureSolve::Multigrid, Some(1)),
            cut(doc::PressureSolve::Multigrid, None),
            cut(doc::PressureSolve::Jacobi, None),
        );
        println!(
            "{name}: one projection cuts the divergence {one:.0}× (one V-cycle), {two:.0}× (two), {jacobi:.2}× (20 Jacobi iterations)"
        );
        assert!(one >= 100.0, "{name}: one V-cycle cut only {one}×");
        assert!(two >= 1000.0, "{name}: two V-cycles cut only {two}×");
    }
}

#[test]
fn uniform_flow_stays_uniform_when_periodic() {
    let mut l = Layout::new("uniform", [40.0, 30.0], [40, 30]);
    l.sim.boundary = Boundary::Periodic;
    l.sim.velocity_dissipation = 0.0;
    let mut s = Solver::new(&l);
    let (u, v) = s.faces_mut();
    u.fill(3.0);
    v.fill(-1.25);
    run(&mut s, 2.0);
    for (i, x) in s.u.iter().enumerate() {
        assert!((x - 3.0).abs() < 1e-4, "u[{i}] = {x}");
    }
    for (i, x) in s.v.iter().enumerate() {
        assert!((x + 1.25).abs() < 1e-4, "v[{i}] = {x}");
    }
}

#[test]
fn kinetic_energy_decays_monotonically_without_forces() {
    for boundary in [Boundary::Closed, Boundary::Periodic, Boundary::Open] {
        let mut s = random_solver(boundary, 64);
        s.params.velocity_dissipation = 0.3;
        s.params.vorticity = 0.0;
        s.params.pressure_decay = 0.8;
        let mut e = s.kinetic_energy();
        for step in 0..120 {
            s.step();
            let next = s.kinetic_energy();
            assert!(
                next <= e,
                "{boundary:?}: energy rose at step {step}: {e} -> {next}"
            );
            e = next;
        }
        assert!(e > 0.0);
    }
}

/// A Gaussian vortex at the centre of a periodic box.
fn vortex_solver(vorticity: f32) -> Solver {
    let mut l = Layout::new("vortex", [64.0, 64.0], [64, 64]);
    l.sim.boundary = Boundary::Periodic;
    l.sim.vorticity = vorticity;
    let mut s = Solver::new(&l);
    let (nx, ny) = (s.nx, s.ny);
    let omega = |x: f32, z: f32| {
        let (dx, dz) = (x - 32.0, z - 32.0);
        // Counter-clockwise in (x, z): u = -dz·g, v = dx·g.
        let g = 2.0 * (-(dx * dx + dz * dz) / 36.0).exp();
        (-dz * g, dx * g)
    };
    let (u, v) = s.faces_mut();
    for j in 0..ny {
        for i in 0..=nx {
            u[j * (nx + 1) + i] = omega(i as f32, j as f32 + 0.5).0;
        }
    }
    for j in 0..=ny {
        for i in 0..nx {
            v[j * nx + i] = omega(i as f32 + 0.5, j as f32).1;
        }
    }
    s.enforce_boundaries();
    s
}

fn peak_curl(s: &mut Solver) -> f32 {
    s.compute_curl();
    s.curl.iter().fold(0.0f32, |m, w| m.max(w.abs()))
}

#[test]
fn vorticity_confinement_does_not_lower_peak_vorticity() {
    let mut s = vortex_solver(30.0);
    let before = peak_curl(&mut s);
    assert!(before > 1.0, "the test vortex must spin: {before}");
    s.confine_vorticity(1.0 / 60.0);
    let after = peak_curl(&mut s);
    assert!(
        after > before,
        "confinement lowered the peak: {before} -> {after}"
    );

    // Over whole steps, confinement keeps the vortex stronger than without it.
    let mut with = vortex_solver(30.0);
    let mut without = vortex_solver(0.0);
    run(&mut with, 1.0);
    run(&mut without, 1.0);
    assert!(peak_curl(&mut with) > peak_curl(&mut without) * 1.05);
}

#[test]
fn an_arrow_blows_downstream_not_upstream() {
    let mut l = Layout::new("arrow", [100.0, 60.0], [100, 60]);
    l.trees
        .push(tree(1, chain(10, &[[30.0, 30.0], [50.0, 30.0]], 10.0, 4.0)));
    let mut s = Solver::new(&l);
    run(&mut s, 4.0);
    // 15 m past the arrow's end and 15 m before its root. Continuity draws air in from behind
    // too, but spread over a half-plane, so it is much slower than the jet downstream.
    let down = s.velocity_at([65.0, 30.0]);
    let up = s.velocity_at([15.0, 30.0]);
    let speed = |v: [f32; 2]| (v[0] * v[0] + v[1] * v[1]).sqrt();
    assert!(down[0] > 1.0, "downstream wind {down:?}");
    assert!(
        down[0].abs() > 5.0 * down[1].abs(),
        "downstream is along the arrow: {down:?}"
    );
    assert!(speed(down) > 2.5 * speed(up), "down {down:?} vs up {up:?}");
    assert!(up[0] > -0.05, "no flow against the arrow upstream: {up:?}");
}

#[test]
fn two_opposing_winds_deflect_sideways_where_they_meet() {
    let l = example("two-winds.json");
    let mut s = Solver::new(&l);
    run(&mut s, 3.0);
    let (cx, cz) = (60.0, 40.0);
    let north = s.velocity_at([cx, cz - 10.0]);
    let south = s.velocity_at([cx, cz + 10.0]);
    let incoming = s.velocity_at([45.0, cz]);
    let centre = s.velocity_at([cx, cz]);
    assert!(incoming[0] > 1.0, "the west wind arrives: {incoming:?}");
    // Flow turns aside: toward −z north of the centre, toward +z south of it…
    assert!(north[1] < -0.5, "north of the meeting point {north:?}");
    assert!(south[1] > 0.5, "south of the meeting point {south:?}");
    // …and the head-on component cancels in the middle.
    assert!(
        centre[0].abs() < 0.25 * incoming[0],
        "centre {centre:?} vs {incoming:?}"
    );
}

#[test]
fn flow_goes_around_an_obstacle_and_is_zero_inside() {
    let mut l = Layout::new("rock", [100.0, 60.0], [100, 60]);
    l.trees
        .push(tree(1, chain(10, &[[10.0, 30.0], [35.0, 30.0]], 10.0, 8.0)));
    l.obstacles.push(doc::Obstacle {
        id: 2,
        name: "rock".into(),
        shape: Shape::Circle {
            center: [55.0, 30.0],
            radius: 8.0,
        },
    });
    let mut s = Solver::new(&l);
    run(&mut s, 3.0);
    let (nx, ny) = (s.nx, s.ny);
    let mut solid_cells = 0;
    for j in 0..ny {
        for i in 0..nx {
            if s.is_solid(i, j) {
                solid_cells += 1;
                assert_eq!(s.cell_velocity(i, j), [0.0, 0.0], "inside at ({i}, {j})");
                // Faces of solid cells carry no flow.
                assert_eq!(s.u[j * (nx + 1) + i], 0.0);
                assert_eq!(s.u[j * (nx + 1) + i + 1], 0.0);
            }
        }
    }
    // Area of the disc in 1 m cells, within rasterisation error.
    let area = std::f32::consts::PI * 64.0;
    assert!(
        (solid_cells as f32 - area).abs() < 0.1 * area,
        "{solid_cells} cells"
    );
    let flank_n = s.velocity_at([55.0, 19.0]);
    let flank_s = s.velocity_at([55.0, 41.0]);
    let wake = s.velocity_at([66.0, 30.0]);
    assert!(
        flank_n[0] > 1.0 && flank_s[0] > 1.0,
        "{flank_n:?} {flank_s:?}"
    );
    // Ahead of the rock the flow splits: toward −z on the north side, +z on the south.
    let ahead_n = s.velocity_at([44.0, 25.0]);
    let ahead_s = s.velocity_at([44.0, 35.0]);
    assert!(
        ahead_n[1] < 0.0 && ahead_s[1] > 0.0,
        "{ahead_n:?} {ahead_s:?}"
    );
    assert!(
        wake[0] < 0.5 * flank_n[0],
        "sheltered wake {wake:?} vs flank {flank_n:?}"
    );
}

#[test]
fn a_branching_tree_feeds_all_its_branches() {
    let l = example("branching.json");
    let mut s = Solver::new(&l);
    run(&mut s, 3.0);
    let arrows = l.trees[0].root.arrows();
    let leaves: Vec<_> = arrows
        .iter()
        .filter(|(_, c, _)| c.children.is_empty())
        .collect();
    assert!(leaves.len() >= 3);
    for (p, c, _) in leaves {
        let mid = [(p.pos[0] + c.pos[0]) / 2.0, (p.pos[1] + c.pos[1]) / 2.0];
        let d = [c.pos[0] - p.pos[0], c.pos[1] - p.pos[1]];
        let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let w = s.velocity_at(mid);
        let along = (w[0] * d[0] + w[1] * d[1]) / len;
        assert!(along > 1.0, "branch ending at {:?} gets {w:?}", c.pos);
    }
}

#[test]
fn a_pulse_reaches_the_leaves_later_than_the_root() {
    let mut l = Layout::new("pulse", [120.0, 40.0], [120, 40]);
    let mut t = tree(
        1,
        chain(
            10,
            &[[5.0, 20.0], [30.0, 20.0], [60.0, 20.0], [90.0, 20.0]],
            10.0,
            4.0,
        ),
    );
    t.propagation_speed = 30.0;
    l.trees.push(t);
    // Force model: the first arrow fires at once, the last one after (25+30)/30 s.
    let active = |time: f32| forces::agc_splats(&l, time).len();
    assert_eq!(active(0.0), 1);
    assert_eq!(active(1.0), 2);
    assert_eq!(active(2.0), 3);
    // In the fluid: first time the wind passes 1 m/s at the first and the last arrow.
    let mut s = Solver::new(&l);
    let mut first = None;
    let mut last = None;
    for step in 0..240 {
        s.step();
        let time = step as f32 * s.params.dt;
        if first.is_none() && s.velocity_at([20.0, 20.0])[0] > 1.0 {
            first = Some(time);
        }
        if last.is_none() && s.velocity_at([80.0, 20.0])[0] > 1.0 {
            last = Some(time);
        }
    }
    let (first, last) = (first.unwrap(), last.unwrap());
    assert!(last > first + 1.0, "root {first} s, leaf {last} s");
}

#[test]
fn windows_emission_and_disabled_trees() {
    let mut l = Layout::new("w", [50.0, 50.0], [32, 32]);
    let mut t = tree(1, chain(10, &[[5.0, 5.0], [20.0, 5.0]], 10.0, 3.0));
    t.window = TimeWindow::Between {
        start: 1.0,
        end: 2.0,
    };
    l.trees.push(t);
    let n = |l: &Layout, time: f32| forces::agc_splats(l, time).len();
    assert_eq!(n(&l, 0.5), 0);
    assert_eq!(n(&l, 1.5), 1);
    assert_eq!(n(&l, 2.5), 0);
    l.trees[0].window = TimeWindow::Always;
    l.trees[0].emission = Emission::Pulsed {
        period: 2.0,
        duty: 0.25,
    };
    assert_eq!(n(&l, 0.1), 1);
    assert_eq!(n(&l, 0.9), 0);
    assert_eq!(n(&l, 2.2), 1);
    l.trees[0].enabled = false;
    assert_eq!(n(&l, 0.1), 0);
}

#[test]
fn forces_never_enter_obstacles() {
    let mut l = example("obstacles.json");
    l.sim.vorticity = 0.0;
    let mut s = Solver::new(&l);
    s.apply_forces(l.sim.dt);
    let (nx, ny) = (s.nx, s.ny);
    let mut pushed = 0;
    for j in 0..ny {
        for i in 0..nx {
            let v = s.cell_velocity(i, j);
            if s.is_solid(i, j) {
                assert_eq!(v, [0.0, 0.0]);
            } else if v != [0.0, 0.0] {
                pushed += 1;
            }
        }
    }
    assert!(pushed > 100, "the arrows push somewhere");
}

/// `f` run on a pool of `threads` rayon threads (the banding, and so the work each thread
/// does, changes with the count; the results must not).
fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn same_layout_same_bytes_with_one_or_two_threads() {
    let run_with = |threads: usize, name: &str, advection: doc::Advection| {
        on_threads(threads, || {
            let (file, multigrid) = match name.split_once('/') {
                Some((file, _)) => (file, true),
                None => (name, false),
            };
            let mut l = example(file);
            l.sim.advection = advection;
            if multigrid {
                l.sim.pressure = doc::PressureSolve::Multigrid;
            }
            let mut s = Solver::new(&l);
            for _ in 0..25 {
                s.step();
            }
            s.state_bytes()
        })
    };
    for (name, adv) in [
        ("obstacles.json", doc::Advection::SemiLagrangian),
        ("breeze-fft.json", doc::Advection::MacCormack),
        ("two-winds.json/multigrid", doc::Advection::SemiLagrangian),
    ] {
        let a = run_with(1, name, adv);
        let b = run_with(2, name, adv);
        assert!(a == b, "{name}: 1 and 2 threads differ");
        assert!(a.iter().any(|&x| x != 0), "{name}: the field moved");
    }
}

/// The fast passes (rows split into interior and ends, vectorisable loops, cache-blocked
/// Jacobi bands) give exactly the bits of the straightforward per-cell reference passes, for
/// every boundary kind, both advection schemes, obstacles, ambient layers, non-square cells,
/// Jacobi counts that need several blocks, and any thread count (which changes the banding).
fn floats(bytes: &[u8]) -> impl Iterator<Item = f32> + '_ {
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
}

#[test]
fn fast_passes_match_the_reference_bit_for_bit() {
    use doc::Advection::{MacCormack, SemiLagrangian};
    let cases = [
        ("obstacles.json", Boundary::Open, SemiLagrangian, 20),
        ("obstacles.json", Boundary::Closed, MacCormack, 60),
        ("obstacles.json", Boundary::Periodic, SemiLagrangian, 7),
        ("meadow.json", Boundary::Open, MacCormack, 1),
        ("breeze-fft.json", Boundary::Periodic, MacCormack, 20),
        ("two-winds.json", Boundary::Closed, SemiLagrangian, 0),
    ];
    for (name, boundary, advection, iterations) in cases {
        let mut l = example(name);
        l.world.grid = [90, 70];
        l.sim.boundary = boundary;
        l.sim.advection = advection;
        l.sim.pressure_iterations = iterations;
        let mut reference = Solver::new(&l);
        for _ in 0..12 {
            reference.step_reference();
        }
        let want = reference.state_bytes();
        assert!(want.iter().any(|&b| b != 0), "{name}: the field moved");
        for threads in [1, 2, 3] {
            let got = on_threads(threads, || {
                let mut s = Solver::new(&l);
                for _ in 0..12 {
                    s.step();
                }
                s.state_bytes()
            });
            // The same numbers: f32 equality, so only a zero's sign may differ (the plain
            // forces loop adds nothing where the fast one adds +0.0 to a −0.0).
            let first = floats(&want).zip(floats(&got)).position(|(a, b)| a != b);
            assert!(
                first.is_none(),
                "{name} {boundary:?} {advection:?} K={iterations}, {threads} threads: \
                 first differing value {first:?} of {}",
                want.len() / 4
            );
        }
    }
}

/// Steps 2–4 fused into one banded sweep give the bits of the curl, confinement and
/// divergence passes run one after another: every boundary, the smallest and odd grids,
/// obstacles, non-square cells, and 1–3 threads (which move the band edges).
#[test]
fn the_fused_vorticity_sweep_gives_the_three_passes_bits() {
    let dt = 1.0 / 60.0;
    for boundary in [Boundary::Open, Boundary::Closed, Boundary::Periodic] {
        for grid in [[8, 8], [13, 9], [41, 70], [90, 33]] {
            let mut l = example("obstacles.json");
            l.world.grid = grid;
            l.world.size[1] *= 0.7;
            l.sim.boundary = boundary;
            l.sim.vorticity = 8.0;
            let seeded = || noisy_solver(&l, (5, 6), 6.0);
            let mut want = seeded();
            want.compute_curl();
            want.confine_vorticity(dt);
            want.compute_divergence();
            let bits = |s: &Solver| -> Vec<u32> {
                [&s.u, &s.v, &s.curl, &s.div]
                    .into_iter()
                    .flat_map(|f| f.iter().map(|x| x.to_bits()))
                    .collect()
            };
            let want_bits = bits(&want);
            assert!(
                want.curl.iter().any(|&w| w != 0.0) && want.div.iter().any(|&d| d != 0.0),
                "{boundary:?} {grid:?}: a field to compare"
            );
            for threads in [1, 2, 3] {
                let got = on_threads(threads, || {
                    let mut s = seeded();
                    assert!(s.fuses_vorticity());
                    s.vorticity_divergence(dt);
                    bits(&s)
                });
                let first = want_bits.iter().zip(&got).position(|(a, b)| a != b);
                assert!(
                    first.is_none(),
                    "{boundary:?} {grid:?}, {threads} threads: first differing value {first:?} \
                     (u, v, curl, div concatenated)"
                );
            }
        }
    }
}

#[test]
fn maccormack_keeps_a_gust_sharper_than_semi_lagrangian() {
    let peak_after = |adv: doc::Advection| {
        let mut l = Layout::new("gust", [64.0, 16.0], [128, 32]);
        l.sim.boundary = Boundary::Periodic;
        l.sim.advection = adv;
        l.sim.vorticity = 0.0;
        l.sim.velocity_dissipation = 0.0;
        let mut s = Solver::new(&l);
        let nx = s.nx;
        let (u, v) = s.faces_mut();
        // A uniform 4 m/s stream carrying a narrow band of cross wind: v varies along x only,
        // so the field is divergence-free and the band should just travel downstream.
        u.fill(4.0);
        for (k, x) in v.iter_mut().enumerate() {
            *x = if (20..24).contains(&(k % nx)) {
                3.0
            } else {
                0.0
            };
        }
        s.enforce_boundaries();
        run(&mut s, 2.0);
        s.v.iter().fold(0.0f32, |m, &x| m.max(x))
    };
    let sl = peak_after(doc::Advection::SemiLagrangian);
    let mc = peak_after(doc::Advection::MacCormack);
    assert!(
        mc > sl + 0.3,
        "MacCormack peak {mc} vs semi-Lagrangian {sl}"
    );
    assert!(mc <= 3.0 + 1e-3, "the limiter allows no overshoot: {mc}");
}

#[test]
fn solver_memory_stays_within_the_validation_budget() {
    for pressure in [doc::PressureSolve::Jacobi, doc::PressureSolve::Multigrid] {
        for grid in [[8, 8], [100, 37], [256, 256], [300, 20], [20, 300]] {
            let mut l = Layout::new("m", [10.0, 10.0], grid);
            l.sim.pressure = pressure;
            let mut s = Solver::new(&l);
            // The multigrid hierarchy is made by the first solve.
            s.step();
            assert!(
                s.memory_bytes() <= s.memory_budget(),
                "{pressure:?} {grid:?}: {} > {}",
                s.memory_bytes(),
                s.memory_budget()
            );
        }
    }
}

/// The forces' vectorisable `e^x` stays within 2 ulp of the true value over the range the
/// Gaussian weights and arrow responses use, is exactly 1 at 0, and bottoms out at e⁻⁸⁷.
#[test]
fn exp_neg_is_accurate_to_two_ulp() {
    let mut worst = 0.0f64;
    let n = 200_000;
    for k in 0..=n {
        let x = -87.0 * k as f32 / n as f32;
        let got = forces::exp_neg(x);
        let want = f64::from(x).exp();
        let ulp = f64::from(f32::EPSILON) * want; // one ulp ≈ ε · value
        worst = worst.max((f64::from(got) - want).abs() / ulp);
    }
    println!("exp_neg: worst error {worst:.2} ulp");
    assert!(worst <= 2.0, "worst error {worst} ulp");
    assert_eq!(forces::exp_neg(0.0), 1.0);
    assert_eq!(forces::exp_neg(5.0), 1.0);
    for x in [-1000.0, f32::NEG_INFINITY] {
        let e = forces::exp_neg(x);
        assert!(e > 0.0 && e < 2e-38, "exp_neg({x}) = {e}");
    }
}

/// The forces visit, in each row, only the faces inside a splat's slice
/// (`ArrowSplat::x_extent_at`): every point a splat pushes lies inside its slice, the slice
/// is no wider than the pushed points (up to a hair), and for a slanted arrow it is much
/// narrower than the bounding box near the arrow's ends.
#[test]
fn a_splat_s_row_slice_holds_every_point_it_pushes_and_no_more() {
    let mut rng = 0x2545_f491_u32;
    let mut next = move || {
        rng ^= rng << 13;
        rng ^= rng >> 17;
        rng ^= rng << 5;
        rng as f32 / u32::MAX as f32
    };
    let mut narrower = 0;
    for case in 0..300 {
        let a = [next() * 100.0 - 50.0, next() * 100.0 - 50.0];
        // Some arrows are axis-aligned or of zero length, the awkward cases of the strip.
        let b = match case % 4 {
            0 => [a[0], a[1] + next() * 30.0],
            1 => [a[0] + next() * 30.0, a[1]],
            2 if case % 8 == 2 => a,
            _ => [next() * 100.0 - 50.0, next() * 100.0 - 50.0],
        };
        let s = forces::ArrowSplat {
            a,
            b,
            dir: [1.0, 0.0],
            strength: 5.0,
            radius: 0.5 + next() * 8.0,
        };
        let (lo, hi) = s.bounds();
        for k in 0..40 {
            let z = lo[1] - 1.0 + (hi[1] - lo[1] + 2.0) * k as f32 / 39.0;
            let pushed: Vec<f32> = (0..=2000)
                .map(|i| lo[0] - 1.0 + (hi[0] - lo[0] + 2.0) * i as f32 / 2000.0)
                .filter(|&x| s.weight([x, z]) > 0.0)
                .collect();
            let extent = s.x_extent_at(z);
            let (Some(&first), Some(&last)) = (pushed.first(), pushed.last()) else {
                // No pushed sample on this line: the slice is absent or a sliver.
                if let Some((x0, x1)) = extent {
                    assert!(
                        x1 - x0 < 0.2,
                        "{s:?} z={z}: slice {x0}..{x1} pushes nothing"
                    );
                }
                continue;
            };
            let (x0, x1) = extent.unwrap_or_else(|| panic!("{s:?} z={z}: no slice"));
            let hair = 1e-3 * (1.0 + x0.abs().max(x1.abs()));
            assert!(
                x0 <= first + hair && last <= x1 + hair,
                "{s:?} z={z}: pushed {first}..{last} outside the slice {x0}..{x1}"
            );
            let step = (hi[0] - lo[0] + 2.0) / 2000.0;
            assert!(
                first - x0 <= step + hair && x1 - last <= step + hair,
                "{s:?} z={z}: slice {x0}..{x1} wider than the pushed {first}..{last}"
            );
            if x1 - x0 < 0.8 * (hi[0] - lo[0]) {
                narrower += 1;
            }
        }
    }
    // Near a slanted arrow's ends the slice is far narrower than the box's row.
    assert!(
        narrower > 1000,
        "only {narrower} rows narrower than the box"
    );
}

#[test]
fn fft_gusts_tile_and_have_unit_rms() {
    let mut f = forces::FftGusts::new(64, 32.0, 6.0, [1.0, 0.0], 7);
    f.evaluate(1.5);
    let rms = (f.field().iter().map(|v| v * v).sum::<f32>() / 4096.0).sqrt();
    assert!(rms > 0.3 && rms < 3.0, "rms {rms}");
    for p in [[0.3, 0.7], [5.5, 12.25], [31.9, 0.1]] {
        let a = f.sample(p);
        let b = f.sample([p[0] + 32.0, p[1] - 64.0]);
        assert!((a - b).abs() < 1e-4, "{p:?}: {a} vs {b}");
    }
    // It evolves in time.
    let before = f.field().to_vec();
    f.evaluate(3.0);
    assert!(
        before
            .iter()
            .zip(f.field())
            .any(|(a, b)| (a - b).abs() > 0.1)
    );
}

#[test]
fn ambient_layers_drive_the_field_toward_their_wind() {
    let mut l = example("breeze-fft.json");
    l.sim.vorticity = 0.0;
    let mut s = Solver::new(&l);
    run(&mut s, 4.0);
    let field = s.velocity_field();
    let mean = field
        .iter()
        .fold([0.0f32, 0.0], |a, v| [a[0] + v[0], a[1] + v[1]]);
    let n = field.len() as f32;
    let mean = [mean[0] / n, mean[1] / n];
    let dir = doc::direction(20.0);
    let along = mean[0] * dir[0] + mean[1] * dir[1];
    assert!(
        along > 3.0,
        "mean wind {mean:?} should approach 6 m/s at 20°"
    );
}

fn extreme_layout() -> impl Strategy<Value = Layout> {
    (
        8u32..40,
        8u32..40,
        // The depth is 0.7 × the width and must stay ≥ 1 m, the validator's least size.
        (1.0f32 / 0.7 + 0.01)..2000.0,
        0.0f32..doc::STRENGTH_MAX,
        0.01f32..5000.0,
        0.001f32..(1.0 / 30.0),
        0.0f32..1000.0,
        0.0f32..100.0,
        prop_oneof![
            Just(Boundary::Open),
            Just(Boundary::Closed),
            Just(Boundary::Periodic)
        ],
        any::<bool>(),
    )
        .prop_map(
            |(nx, ny, size, strength, radius, dt, vort, diss, boundary, mc)| {
                let mut l = Layout::new("extreme", [size, size * 0.7], [nx, ny]);
                l.sim.dt = dt;
                l.sim.vorticity = vort;
                l.sim.velocity_dissipation = diss;
                l.sim.boundary = boundary;
                if mc {
                    l.sim.advection = doc::Advection::MacCormack;
                }
                let r = radius.min(doc::RADIUS_MAX);
                l.trees.push(tree(
                    1,
                    chain(
                        10,
                        &[
                            [0.1 * size, 0.3 * size],
                            [0.5 * size, 0.2 * size],
                            [0.9 * size, 0.6 * size],
                        ],
                        strength,
                        r,
                    ),
                ));
                l.obstacles.push(doc::Obstacle {
                    id: 2,
                    name: "rock".into(),
                    shape: Shape::Circle {
                        center: [0.6 * size, 0.4 * size],
                        radius: 0.1 * size,
                    },
                });
                l
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Random extreme layouts, stepped many times, never produce NaN or infinity.
    #[test]
    fn extreme_layouts_stay_finite(l in extreme_layout()) {
        prop_assert!(doc::validate(&l).is_empty(), "{:?}", doc::validate(&l));
        let mut s = Solver::new(&l);
        for _ in 0..150 {
            s.step();
        }
        prop_assert!(s.u.iter().chain(&s.v).chain(&s.p).all(|x| x.is_finite()));
    }
}

fn strongest(node: &doc::Node) -> f32 {
    node.children
        .iter()
        .map(strongest)
        .fold(node.strength, f32::max)
}

fn max_speed(s: &Solver) -> f32 {
    s.velocity_field()
        .iter()
        .map(|v| v[0].hypot(v[1]))
        .fold(0.0, f32::max)
}

/// Steps `s` 10,000 times, checking every 500 steps that the field is finite and no cell is
/// faster than `bound`; returns the fastest speed seen.
fn run_10000_steps(s: &mut Solver, bound: f32, what: &str) -> f32 {
    let mut peak = 0.0f32;
    for k in 1..=10_000 {
        s.step();
        if k % 500 == 0 {
            assert!(
                s.u.iter().chain(&s.v).chain(&s.p).all(|x| x.is_finite()),
                "{what}: non-finite after {k} steps"
            );
            let m = max_speed(s);
            peak = peak.max(m);
            assert!(
                m <= bound,
                "{what}: {m} m/s after {k} steps (bound {bound})"
            );
        }
    }
    peak
}

/// Every example layout, run for 10,000 steps (on half its grid, so the test stays quick),
/// stays finite and bounded: checked every 500 steps, no cell ever faster than twenty times
/// the strongest arrow (or 10 m/s) — a blow-up grows past any such bound within a few steps.
/// (Not a plausibility bound: the branching and obstacles layouts' fastest cells spike to
/// 4–8× their strongest arrow and fall back — recorded in docs/RELIABILITY.md as a finding.)
#[test]
fn every_example_runs_10000_steps_finite_and_bounded() {
    for name in [
        "meadow.json",
        "branching.json",
        "breeze-fft.json",
        "obstacles.json",
        "two-winds.json",
    ] {
        let mut l = example(name);
        let g = l.world.grid;
        l.world.grid = [(g[0] / 2).max(8), (g[1] / 2).max(8)];
        let bound = 20.0
            * l.trees
                .iter()
                .map(|t| strongest(&t.root))
                .fold(10.0, f32::max);
        let peak = run_10000_steps(&mut Solver::new(&l), bound, name);
        println!("{name}: 10,000 steps, peak {peak:.2} m/s (bound {bound:.0})");
    }
}

/// The extremes the validator allows, 10,000 steps each: arrows of 500 m/s whose radius
/// covers the whole map, one-cell obstacles, every boundary, both advection schemes — finite
/// and bounded throughout.
#[test]
fn extreme_layouts_run_10000_steps_finite_and_bounded() {
    for boundary in [Boundary::Open, Boundary::Closed, Boundary::Periodic] {
        for mc in [false, true] {
            let size = 40.0;
            let mut l = Layout::new("extreme", [size, size * 0.75], [32, 24]);
            l.sim.boundary = boundary;
            if mc {
                l.sim.advection = doc::Advection::MacCormack;
            }
            l.sim.vorticity = 50.0;
            l.trees.push(tree(
                1,
                chain(
                    10,
                    &[[4.0, 15.0], [20.0, 5.0], [36.0, 25.0]],
                    doc::STRENGTH_MAX,
                    100.0,
                ),
            ));
            // One-cell obstacles (a cell is 1.25 m) scattered over the map.
            for k in 0..12u32 {
                l.obstacles.push(doc::Obstacle {
                    id: 100 + k,
                    name: format!("pebble {k}"),
                    shape: Shape::Circle {
                        center: [3.0 + 3.1 * k as f32, 4.0 + 1.7 * (k % 13) as f32],
                        radius: 0.6,
                    },
                });
            }
            assert!(doc::validate(&l).is_empty(), "{:?}", doc::validate(&l));
            let peak = run_10000_steps(
                &mut Solver::new(&l),
                3.0 * doc::STRENGTH_MAX,
                &format!("{boundary:?} MacCormack {mc}"),
            );
            println!("{boundary:?}, MacCormack {mc}: peak {peak:.1} m/s");
        }
    }
}

/// Random extreme layouts from the generator above (grids to 40², arrows to 500 m/s with
/// radii past the whole map, any step the validator allows, vorticity to 1,000, dissipation to
/// 100, every boundary, both advections), 10,000 steps each: finite throughout. Bounded by
/// three times the strongest arrow the validator allows when the vorticity factor is at most
/// 5; above that, confinement feeds the field until the solver's speed clamp holds it
/// (measured in docs/RELIABILITY.md, "Findings"), so the bound is the clamp's.
#[test]
fn random_extreme_layouts_run_10000_steps_finite_and_bounded() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    for k in 0..6 {
        let drawn = extreme_layout().new_tree(&mut runner).unwrap().current();
        // The layout as drawn, and again with its vorticity factor brought into [0, 5].
        let mut tame = drawn.clone();
        tame.sim.vorticity = drawn.sim.vorticity / 200.0;
        for (l, bound) in [
            (drawn, windloom::sim::MAX_SPEED * std::f32::consts::SQRT_2),
            (tame, 3.0 * doc::STRENGTH_MAX),
        ] {
            assert!(doc::validate(&l).is_empty(), "{:?}", doc::validate(&l));
            let what = format!(
                "random extreme {k}: {:?} grid, dt {:.4}, vorticity {:.1}, {:?}, {:?}",
                l.world.grid, l.sim.dt, l.sim.vorticity, l.sim.boundary, l.sim.advection
            );
            let peak = run_10000_steps(&mut Solver::new(&l), bound, &what);
            println!("{what}: peak {peak:.1} m/s");
        }
    }
}

/// Runs `windloom bench --backend cpu … --json` with `args`; the output of a run that worked.
fn bench(args: &[&str]) -> std::process::Output {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args(["bench", "--backend", "cpu", "--json"])
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// `windloom bench --json` prints one JSON object with the fields the performance record
/// needs, and its bound is the byte count over the bandwidth it measured.
#[test]
fn bench_prints_one_json_object_with_the_split_and_the_bound() {
    let out = bench(&[
        "--grid",
        "64",
        "--iterations",
        "4",
        "--steps",
        "3",
        "--warmup",
        "1",
        "--threads",
        "2",
    ]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(text.trim().lines().count(), 1, "one line: {text}");
    let j: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(j["grid"], serde_json::json!([64, 64]));
    assert_eq!(j["iterations"], 4);
    assert_eq!(j["steps"], 3);
    assert_eq!(j["threads"], 2);
    // The obstacles layout confines vorticity, so the CPU step fuses curl, confinement and
    // divergence into one sweep and reports it as one pass.
    let passes = [
        "forces",
        "curl_confinement_divergence",
        "pressure",
        "gradient",
        "advection",
    ];
    let mut bytes = 0;
    for p in passes {
        let ms = j["passes_ms"][p].as_f64().unwrap();
        assert!(ms >= 0.0, "{p}: {ms}");
        bytes += j["passes_bytes"][p].as_u64().unwrap();
    }
    assert_eq!(j["passes_ms"].as_object().unwrap().len(), passes.len());
    assert_eq!(j["passes_bytes"].as_object().unwrap().len(), passes.len());
    assert_eq!(j["bytes_per_step"].as_u64().unwrap(), bytes);
    // The unfused pipeline's count: three passes (curl 4F + 5C, confinement 32C + 9F,
    // divergence 4F + 5C) where the fused sweep moves 9F + 9C.
    let (c, f) = (64 * 64, 2 * 65 * 64);
    let substeps = example("obstacles.json").sim.substeps.max(1) as u64;
    let unfused = j["unfused_bytes_per_step"].as_u64().unwrap();
    assert_eq!(
        unfused - bytes,
        (8 * f + 33 * c) * substeps,
        "unfused {unfused}, fused {bytes}"
    );
    // Pressure: 8 bytes/cell warm start + 13 bytes/cell per iteration.
    assert_eq!(j["passes_bytes"]["pressure"], 64 * 64 * (8 + 13 * 4));
    let (median, min) = (
        j["median_ms"].as_f64().unwrap(),
        j["min_ms"].as_f64().unwrap(),
    );
    assert!(min > 0.0 && min <= median, "min {min}, median {median}");
    let bw = j["bandwidth_gb_s"].as_f64().unwrap();
    let bound = j["bound_ms"].as_f64().unwrap();
    assert!(bw > 0.1, "bandwidth {bw} GB/s");
    let want = bytes as f64 / (bw * 1e9) * 1e3;
    assert!(
        (bound - want).abs() <= 1e-9 * want.max(1.0),
        "bound {bound} vs {want}"
    );
    assert!((j["ratio_to_bound"].as_f64().unwrap() - median / bound).abs() < 1e-9 * median / bound);
    let unfused_bound = j["unfused_bound_ms"].as_f64().unwrap();
    let want = unfused as f64 / (bw * 1e9) * 1e3;
    assert!((unfused_bound - want).abs() <= 1e-9 * want.max(1.0));
    let ratio = j["ratio_to_unfused_bound"].as_f64().unwrap();
    assert!((ratio - median / unfused_bound).abs() < 1e-9 * ratio);
    // The projection of a developed step cuts the divergence (4 Jacobi iterations: a little).
    let (before, after) = (
        j["divergence_before"].as_f64().unwrap(),
        j["divergence_after"].as_f64().unwrap(),
    );
    assert!(before > 0.0 && after < before, "{before} -> {after}");
    let cut = j["divergence_reduction"].as_f64().unwrap();
    assert!((cut - before / after).abs() <= 1e-3 * cut, "{cut}");
}

/// `bench --layout all` runs every bundled example and prints a JSON array, one object each.
#[test]
fn bench_runs_every_example_as_a_json_array() {
    let out = bench(&[
        "--grid",
        "32",
        "--iterations",
        "2",
        "--steps",
        "1",
        "--warmup",
        "0",
        "--layout",
        "all",
    ]);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let names: Vec<&str> = j
        .as_array()
        .expect("an array")
        .iter()
        .map(|r| r["layout"].as_str().unwrap())
        .collect();
    for name in [
        "obstacles.json",
        "meadow.json",
        "two-winds.json",
        "breeze-fft.json",
        "branching.json",
    ] {
        assert!(
            names.iter().any(|n| n.ends_with(name)),
            "{name} in {names:?}"
        );
    }
    assert!(
        j.as_array()
            .unwrap()
            .iter()
            .all(|r| r["grid"] == serde_json::json!([32, 32]))
    );
}

// ---- The GPU passes against the CPU ---------------------------------------------------------

mod gpu {
    use super::example;
    use windloom::doc::{Advection, Boundary};
    use windloom::gpu::fluid::{FieldId, GpuFluid, SHADERS, shader_source};
    use windloom::gpu::mapview;
    use windloom::gpu::{GpuContext, GpuError};
    use windloom::sim::Solver;

    #[test]
    fn every_shader_parses_and_validates_with_naga() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
        let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".wgsl") && n != "common.wgsl")
            .collect();
        on_disk.sort();
        // Headers, validated inside every pass they are prepended to.
        on_disk.retain(|n| {
            n != "map_common.wgsl"
                && n != "grass_common.wgsl"
                && n != "grass_shape.wgsl"
                && n != "mg_common.wgsl"
        });
        let mut listed: Vec<String> = SHADERS
            .iter()
            .chain(mapview::SHADERS.iter())
            .chain(windloom::gpu::grass::SHADERS.iter())
            .chain(windloom::gpu::multigrid::MG_SHADERS.iter())
            .map(|(n, _)| format!("{n}.wgsl"))
            .collect();
        listed.sort();
        assert_eq!(
            on_disk, listed,
            "every shader file is compiled by the solver or the map view"
        );
        let sources = SHADERS
            .iter()
            .map(|(n, _)| (n, shader_source(n).unwrap()))
            .chain(
                mapview::SHADERS
                    .iter()
                    .map(|(n, _)| (n, mapview::shader_source(n).unwrap())),
            )
            .chain(
                windloom::gpu::grass::SHADERS
                    .iter()
                    .map(|(n, _)| (n, windloom::gpu::grass::shader_source(n).unwrap())),
            )
            .chain(
                windloom::gpu::multigrid::MG_SHADERS
                    .iter()
                    .map(|(n, _)| (n, windloom::gpu::multigrid::shader_source(n).unwrap())),
            );
        for (name, source) in sources {
            let module = naga::front::wgsl::parse_str(&source)
                .unwrap_or_else(|e| panic!("{name}.wgsl: {}", e.emit_to_string(&source)));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::empty(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}.wgsl: {}", e.emit_to_string(&source)));
        }
    }

    /// The software adapter; CI must have it (it installs lavapipe), elsewhere a missing
    /// adapter skips loudly.
    fn context() -> Option<GpuContext> {
        match GpuContext::headless() {
            Ok(c) => Some(c),
            Err(e @ GpuError::NoAdapter(_)) if std::env::var_os("CI").is_none() => {
                eprintln!("\n!!! SKIPPING a GPU test: {e}\n");
                None
            }
            Err(e) => panic!("CI requires a GPU adapter (lavapipe): {e}"),
        }
    }

    /// Deterministic pseudo-random values in `[-a, a]`.
    fn noise(n: usize, seed: u64, a: f32) -> Vec<f32> {
        let mut s = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (0..n)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((s >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0) * a
            })
            .collect()
    }

    /// The obstacles example on a small grid with non-square cells, in `boundary` mode, with
    /// a random field (zero on the faces that are not free).
    fn random_solver(boundary: Boundary, seed: u64) -> Solver {
        let mut l = example("obstacles.json");
        l.world.grid = [40, 28];
        l.sim.boundary = boundary;
        l.sim.advection = Advection::SemiLagrangian;
        let mut s = Solver::new(&l);
        let (nu, nv) = (s.u.len(), s.v.len());
        let (u, v) = s.faces_mut();
        u.copy_from_slice(&noise(nu, seed, 6.0));
        v.copy_from_slice(&noise(nv, seed + 1, 6.0));
        s.enforce_boundaries();
        let n = s.p.len();
        s.p = noise(n, seed + 2, 3.0);
        s.div = noise(n, seed + 3, 2.0);
        s.compute_curl();
        s
    }

    fn max_err(gpu: &[f32], cpu: &[f32]) -> (f32, f32) {
        assert_eq!(gpu.len(), cpu.len());
        let peak = cpu.iter().fold(0.0f32, |m, x| m.max(x.abs()));
        let err = gpu
            .iter()
            .zip(cpu)
            .fold(0.0f32, |m, (a, b)| m.max((a - b).abs()));
        (err, peak)
    }

    fn check(what: &str, gpu: &[f32], cpu: &[f32], rel: f32) {
        let (err, peak) = max_err(gpu, cpu);
        println!("{what}: max |GPU − CPU| {err:.2e}, peak {peak:.3}");
        assert!(peak > 0.0, "{what}: an all-zero field tests nothing");
        assert!(
            err <= rel * peak,
            "{what}: GPU differs from the CPU by {err} (peak {peak}, allowed {})",
            rel * peak
        );
    }

    /// Each pass on the GPU against the same pass on the CPU, from the same random state, on
    /// every boundary mode with obstacles: max error ≤ 1e-5 of the field's peak.
    #[test]
    fn each_pass_matches_the_cpu_on_every_boundary_with_obstacles() {
        let Some(ctx) = context() else { return };
        let (device, queue) = (&ctx.device, &ctx.queue);
        for (n, boundary) in [Boundary::Closed, Boundary::Open, Boundary::Periodic]
            .into_iter()
            .enumerate()
        {
            let seed = 100 * n as u64;
            let base = random_solver(boundary, seed);
            let dt = base.params.dt;
            let mut gpu = GpuFluid::new(device, &base);
            let run =
                |gpu: &mut GpuFluid, pass: &dyn Fn(&mut GpuFluid, &mut wgpu::CommandEncoder)| {
                    gpu.upload_state(queue, &base);
                    let mut enc = device.create_command_encoder(&Default::default());
                    pass(gpu, &mut enc);
                    queue.submit([enc.finish()]);
                };
            let get = |gpu: &GpuFluid, f| gpu.download(device, queue, f).unwrap();
            let tag = |pass: &str| format!("{pass} ({boundary:?})");

            // Forces: the arrows, and every kind of ambient layer.
            let mut windy = example("obstacles.json");
            windy.ambient = example("meadow.json").ambient;
            windy.ambient.extend(example("breeze-fft.json").ambient);
            let extra = [
                r#"{"type":"noise","direction_deg":30,"scale":9,"speed":3,"strength":4}"#,
                r#"{"type":"sine","direction_deg":-60,"amplitude":2.5,"wavelength":17,"frequency":0.4}"#,
            ];
            for (n, k) in extra.iter().enumerate() {
                windy.ambient.push(windloom::doc::AmbientLayer {
                    id: 90 + n as u32,
                    name: format!("extra {n}"),
                    enabled: true,
                    kind: serde_json::from_str(k).unwrap(),
                });
            }
            let kinds: std::collections::BTreeSet<&str> =
                windy.ambient.iter().map(|a| a.kind.type_name()).collect();
            assert_eq!(kinds.len(), 4, "{kinds:?}");
            let t = 1.7;
            let mut cpu = random_solver(boundary, seed);
            let mut l = windy.clone();
            l.world.grid = [40, 28];
            l.sim.boundary = boundary;
            let mut cpu_windy = Solver::new(&l);
            cpu_windy.u.clone_from(&cpu.u);
            cpu_windy.v.clone_from(&cpu.v);
            cpu_windy.time = t;
            cpu_windy.apply_forces(dt);
            cpu.u = cpu_windy.u;
            cpu.v = cpu_windy.v;
            let splats = windloom::sim::forces::agc_splats(&windy, t);
            assert!(!splats.is_empty());
            let mut ambient = windloom::sim::forces::Ambient::new(&windy);
            ambient.set_time(t);
            let (layers, gusts) = ambient.layer_params();
            let coupling = 1.0 - (-base.params.ambient_coupling * dt).exp();
            run(&mut gpu, &|g, e| {
                g.forces(device, queue, e, &splats, (&layers, &gusts, coupling), dt)
            });
            check(&tag("forces u"), &get(&gpu, FieldId::U), &cpu.u, 1e-5);
            check(&tag("forces v"), &get(&gpu, FieldId::V), &cpu.v, 1e-5);
            let moved = cpu
                .u
                .iter()
                .zip(&base.u)
                .filter(|(a, b)| (*a - *b).abs() > 1e-3)
                .count();
            assert!(
                moved > 50,
                "the arrows moved {moved} faces: a real test of the forces"
            );

            let mut cpu = random_solver(boundary, seed);
            cpu.curl.fill(0.0);
            cpu.compute_curl();
            run(&mut gpu, &|g, e| g.curl(device, e));
            check(&tag("curl"), &get(&gpu, FieldId::Curl), &cpu.curl, 1e-5);

            let mut cpu = random_solver(boundary, seed);
            cpu.confine_vorticity(dt);
            run(&mut gpu, &|g, e| g.confine(device, queue, e, dt));
            check(&tag("confinement u"), &get(&gpu, FieldId::U), &cpu.u, 1e-5);
            check(&tag("confinement v"), &get(&gpu, FieldId::V), &cpu.v, 1e-5);

            let mut cpu = random_solver(boundary, seed);
            cpu.compute_divergence();
            run(&mut gpu, &|g, e| g.divergence(device, e));
            check(&tag("divergence"), &get(&gpu, FieldId::Div), &cpu.div, 1e-5);

            let mut cpu = random_solver(boundary, seed);
            cpu.solve_pressure();
            let iterations = cpu.params.pressure_iterations as usize;
            run(&mut gpu, &|g, e| g.pressure(device, e, iterations));
            check(&tag("pressure"), &get(&gpu, FieldId::P), &cpu.p, 1e-5);

            let mut cpu = random_solver(boundary, seed);
            cpu.subtract_gradient();
            run(&mut gpu, &|g, e| g.gradient(device, e));
            check(&tag("gradient u"), &get(&gpu, FieldId::U), &cpu.u, 1e-5);
            check(&tag("gradient v"), &get(&gpu, FieldId::V), &cpu.v, 1e-5);

            let mut cpu = random_solver(boundary, seed);
            cpu.advect(dt);
            let keep = 1.0 / (1.0 + cpu.params.velocity_dissipation * dt);
            gpu.upload_state(queue, &base);
            let mut enc = device.create_command_encoder(&Default::default());
            gpu.advect(device, queue, &mut enc, dt, keep, false);
            queue.submit([enc.finish()]);
            check(&tag("advection u"), &get(&gpu, FieldId::U), &cpu.u, 1e-5);
            check(&tag("advection v"), &get(&gpu, FieldId::V), &cpu.v, 1e-5);

            let mut cpu = random_solver(boundary, seed);
            cpu.params.advection = Advection::MacCormack;
            cpu.advect(dt);
            gpu.upload_state(queue, &base);
            let mut enc = device.create_command_encoder(&Default::default());
            gpu.advect(device, queue, &mut enc, dt, keep, true);
            queue.submit([enc.finish()]);
            check(&tag("MacCormack u"), &get(&gpu, FieldId::U), &cpu.u, 1e-5);
            check(&tag("MacCormack v"), &get(&gpu, FieldId::V), &cpu.v, 1e-5);
        }
    }

    /// The passes chained over 12 substeps (no forces: that pass is still CPU-only) from a
    /// random field: the GPU's velocity stays within 1e-4 of the CPU's peak. Bits differ only
    /// in the pressure solve (fused multiply-adds), and advection carries those on.
    #[test]
    fn the_passes_chained_stay_with_the_cpu() {
        let Some(ctx) = context() else { return };
        let (device, queue) = (&ctx.device, &ctx.queue);
        for boundary in [Boundary::Closed, Boundary::Open, Boundary::Periodic] {
            let mut cpu = random_solver(boundary, 7);
            let mut gpu = GpuFluid::new(device, &cpu);
            gpu.upload_state(queue, &cpu);
            let dt = cpu.params.dt;
            let keep = 1.0 / (1.0 + cpu.params.velocity_dissipation * dt);
            let iterations = cpu.params.pressure_iterations as usize;
            for _ in 0..12 {
                cpu.compute_curl();
                cpu.confine_vorticity(dt);
                cpu.compute_divergence();
                cpu.solve_pressure();
                cpu.subtract_gradient();
                cpu.advect(dt);
                gpu.substep_without_forces(device, queue, dt, iterations, keep, false);
            }
            let u = gpu.download(device, queue, FieldId::U).unwrap();
            let v = gpu.download(device, queue, FieldId::V).unwrap();
            check(&format!("12 substeps, u ({boundary:?})"), &u, &cpu.u, 1e-4);
            check(&format!("12 substeps, v ({boundary:?})"), &v, &cpu.v, 1e-4);
        }
    }

    fn mean_speed(f: &[[f32; 2]]) -> f64 {
        f.iter().map(|v| f64::from(v[0].hypot(v[1]))).sum::<f64>() / f.len() as f64
    }

    fn energy(f: &[[f32; 2]]) -> f64 {
        f.iter()
            .map(|v| 0.5 * f64::from(v[0] * v[0] + v[1] * v[1]))
            .sum()
    }

    /// 200 whole steps of the example layouts the GPU covers, from rest, on the GPU and on the
    /// CPU: the kinetic energy and the mean speed agree within 2%. Eddies amplify a last-bit
    /// difference (the pressure solve's fused multiply-adds) into a different but equally
    /// likely flow, so the fields are compared point by point only where the flow is steady.
    #[test]
    fn whole_runs_agree_with_the_cpu() {
        let Some(ctx) = context() else { return };
        use windloom::doc::PressureSolve::{Jacobi, Multigrid};
        for (name, grid, advection, pressure) in [
            ("meadow.json", [60, 40], Advection::SemiLagrangian, Jacobi),
            (
                "breeze-fft.json",
                [48, 48],
                Advection::SemiLagrangian,
                Jacobi,
            ),
            (
                "branching.json",
                [60, 40],
                Advection::SemiLagrangian,
                Jacobi,
            ),
            (
                "two-winds.json",
                [60, 40],
                Advection::SemiLagrangian,
                Jacobi,
            ),
            (
                "obstacles.json",
                [48, 48],
                Advection::SemiLagrangian,
                Jacobi,
            ),
            ("two-winds.json", [60, 40], Advection::MacCormack, Jacobi),
            (
                "meadow.json",
                [60, 40],
                Advection::SemiLagrangian,
                Multigrid,
            ),
            (
                "breeze-fft.json",
                [48, 48],
                Advection::SemiLagrangian,
                Multigrid,
            ),
            (
                "obstacles.json",
                [48, 48],
                Advection::SemiLagrangian,
                Multigrid,
            ),
        ] {
            let mut l = example(name);
            l.world.grid = grid;
            l.sim.advection = advection;
            l.sim.pressure = pressure;
            let mut cpu = Solver::new(&l);
            let mut gpu = windloom::gpu::GpuSolver::new(&ctx, &l).unwrap();
            for _ in 0..200 {
                cpu.step();
                gpu.step(&ctx);
            }
            gpu.finish(&ctx).unwrap();
            assert!((gpu.time - cpu.time).abs() < 1e-4);
            let (a, b) = (gpu.velocity_field(&ctx).unwrap(), cpu.velocity_field());
            let peak = b.iter().fold(0.0f32, |m, v| m.max(v[0].hypot(v[1])));
            let err = a
                .iter()
                .zip(&b)
                .fold(0.0f32, |m, (p, q)| m.max((p[0] - q[0]).hypot(p[1] - q[1])));
            let (ea, eb) = (energy(&a), energy(&b));
            let (sa, sb) = (mean_speed(&a), mean_speed(&b));
            println!(
                "{name} ({advection:?}, {pressure:?}): 200 steps, max |Δv| {err:.2e} of peak {peak:.2}, energy {ea:.1} vs {eb:.1}, mean speed {sa:.3} vs {sb:.3}"
            );
            assert!(peak > 1.0, "{name}: the wind blows");
            // At these grids and lengths the flows have not yet diverged: point by point too.
            assert!(err <= 1e-3 * peak, "{name}: max |Δv| {err} of peak {peak}");
            assert!((ea / eb - 1.0).abs() < 0.02, "{name}: energy {ea} vs {eb}");
            assert!(
                (sa / sb - 1.0).abs() < 0.02,
                "{name}: mean speed {sa} vs {sb}"
            );
        }
    }

    fn bake_raw(backend: windloom::bake::Backend) -> (Vec<f32>, windloom::bake::Manifest) {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("bake");
        let opts = windloom::bake::BakeOptions {
            formats: vec![windloom::bake::Format::Raw],
            warmup: 1.0,
            frames: 3,
            fps: 10.0,
            grid: Some([60, 40]),
            backend,
            ..Default::default()
        };
        let m = windloom::bake::bake(
            &example("two-winds.json"),
            &out,
            &opts,
            &std::sync::atomic::AtomicBool::new(false),
            &mut |_, _, _| {},
        )
        .unwrap();
        let bytes = std::fs::read(out.join("wind.f32")).unwrap();
        let data = bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        (data, m)
    }

    /// `bake --backend gpu` and `--backend cpu` of the same layout give the same wind within
    /// the whole-run bound; `auto` on a software adapter bakes on the CPU and says why.
    #[test]
    fn a_gpu_bake_agrees_with_a_cpu_bake() {
        let Some(_ctx) = context() else { return };
        use windloom::bake::Backend;
        let (cpu, mc) = bake_raw(Backend::Cpu);
        let (gpu, mg) = bake_raw(Backend::Gpu);
        assert_eq!(mc.solver, "cpu");
        assert!(mg.solver.starts_with("gpu: "), "{}", mg.solver);
        let peak = cpu.iter().fold(0.0f32, |m, x| m.max(x.abs()));
        let err = gpu
            .iter()
            .zip(&cpu)
            .fold(0.0f32, |m, (a, b)| m.max((a - b).abs()));
        println!("gpu bake vs cpu bake: max error {err:.2e} of peak {peak:.2}");
        assert!(peak > 1.0 && err <= 1e-3 * peak, "{err} of {peak}");
        if _ctx.adapter.device_type == wgpu::DeviceType::Cpu {
            let (auto, ma) = bake_raw(Backend::Auto);
            assert_eq!(ma.solver, "cpu");
            assert!(
                ma.notes.iter().any(|n| n.contains("software")),
                "{:?}",
                ma.notes
            );
            assert_eq!(auto, cpu);
        }
    }

    #[test]
    fn bench_reports_the_gpu_it_ran_on() {
        let Some(_ctx) = context() else { return };
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
            .args([
                "bench",
                "--backend",
                "gpu",
                "--grid",
                "48",
                "--steps",
                "3",
                "--warmup",
                "1",
                "--json",
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(r["backend"], "gpu");
        assert_eq!(r["adapter"]["name"], _ctx.adapter.name.as_str());
        assert_eq!(r["grid"], serde_json::json!([48, 48]));
        assert!(r["median_ms"].as_f64().unwrap() > 0.0);
        assert!(r["bytes_per_step"].as_u64().unwrap() > 0);
        // lavapipe has timestamp queries: every pass of the obstacles layout is timed, and
        // the passes add up to no more than the wall time of a step.
        if r["timestamps"] == true {
            let passes = r["passes_ms"].as_object().unwrap();
            for p in [
                "forces",
                "curl",
                "confinement",
                "divergence",
                "pressure",
                "gradient",
                "advection",
            ] {
                assert!(passes[p].as_f64().unwrap() >= 0.0, "{p} timed: {passes:?}");
            }
            let sum: f64 = passes.values().map(|v| v.as_f64().unwrap()).sum();
            assert!(
                sum > 0.0 && sum <= r["median_ms"].as_f64().unwrap() * 1.5,
                "{sum} vs {}",
                r["median_ms"]
            );
        }
    }

    /// `bench --grass` prints one JSON object per run: the model and culling asked for, and
    /// counters that account for every blade; culling draws fewer blades than no culling.
    #[test]
    fn grass_bench_reports_the_model_culling_and_every_blade() {
        let Some(_ctx) = context() else { return };
        let run = |model: &str, cull: &str| {
            let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
                .args([
                    "bench", "--grass", "20000", "--model", model, "--cull", cull, "--size",
                    "320x180", "--steps", "2", "--json",
                ])
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
            assert_eq!(r["model"], model);
            assert_eq!(r["cull"], cull == "on");
            assert_eq!(r["adapter"], _ctx.adapter.name.as_str());
            let c = &r["culled"];
            let n = |v: &serde_json::Value| v.as_u64().unwrap();
            let drawn: u64 = c["drawn"].as_array().unwrap().iter().map(n).sum();
            assert_eq!(
                drawn + n(&c["orientation"]) + n(&c["frustum"]) + n(&c["distance"]),
                n(&r["blades"]),
                "{r}"
            );
            assert!(r["median_ms"].as_f64().unwrap() > 0.0);
            drawn
        };
        for model in ["cwd", "bezier"] {
            let (on, off) = (run(model, "on"), run(model, "off"));
            println!("{model}: {on} blades drawn culled, {off} not");
            assert!(on < off, "culling draws fewer blades");
        }
    }

    /// The grass passes against the CPU model (`grass::cwd`), and pictures of them.
    mod grass {
        use super::{context, example};
        use windloom::doc::Layout;
        use windloom::gpu::GpuContext;
        use windloom::gpu::grass::{Camera, GrassRenderer, SEGMENTS, render_offscreen};
        use windloom::grass::{cwd, scatter, wind_cell};

        fn layout(density: f32) -> Layout {
            let mut l = example("meadow.json");
            l.world.size = [12.0, 8.0];
            l.world.grid = [24, 16];
            l.grass.density = density;
            l
        }

        /// A wind grid of random directions and speeds up to 40 m/s.
        fn random_wind(n: usize, seed: u64) -> Vec<[f32; 2]> {
            let a = super::noise(n, seed, std::f32::consts::PI);
            let s = super::noise(n, seed + 1, 20.0);
            a.iter()
                .zip(&s)
                .map(|(a, s)| [(s + 20.0) * a.cos(), (s + 20.0) * a.sin()])
                .collect()
        }

        /// Each blade's deformed tip as the vertex shader places it matches the CPU model's,
        /// in random winds up to 40 m/s, at several times (the flutter's clock), and with a
        /// sphere's trail crushing part of the field (`cwd::centreline_crushed` fed by the CPU
        /// trail).
        #[test]
        fn gpu_blade_tips_match_the_cpu_model() {
            use windloom::grass::trail::{Sphere, Trail};
            let Some(ctx) = context() else { return };
            let l = layout(30.0);
            let blades = scatter(&l);
            assert!(blades.len() > 2000);
            let (nx, ny) = (24, 16);
            let cell = [0.5, 0.5];
            let mut r =
                GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
            let (min, max) = l.bounds();
            let mut trail = Trail::new(min, max);
            let camera = Camera::overview(&l);
            let mut worst = (0.0f32, 0.0f32);
            let mut crushed = 0;
            for (k, time) in [0.0f32, 1.7, 12.25].into_iter().enumerate() {
                let wind = random_wind(nx * ny, 40 + k as u64);
                r.set_wind(&ctx.device, &ctx.queue, (nx, ny), [0.0, 0.0], cell, &wind);
                // The last time: a sphere has crossed the field.
                let sphere = (k == 2).then_some(Sphere {
                    centre: [6.0, 0.4, 4.0],
                    radius: 1.5,
                });
                r.set_sphere(sphere);
                trail.step(sphere, 0.25, windloom::gpu::grass::TRAIL_LIFETIME);
                let mut enc = ctx.device.create_command_encoder(&Default::default());
                r.prepare(&ctx.queue, &mut enc, &camera, 1.5, time, 0.25);
                ctx.queue.submit([enc.finish()]);
                let tips = r.read_tips(&ctx.device, &ctx.queue).unwrap();
                for (b, gpu) in blades.iter().zip(&tips) {
                    let w = wind[wind_cell(b.pos, [0.0, 0.0], cell, (nx, ny))];
                    let crush = if sphere.is_some() {
                        trail.crush_at(b.pos, cwd::frame(b).0)
                    } else {
                        (0.0, [0.0, 0.0])
                    };
                    crushed += usize::from(crush.0 > 0.5);
                    let cpu =
                        cwd::centreline_crushed(b, w, &l.grass, time, SEGMENTS as usize, crush)
                            [SEGMENTS as usize];
                    let d = (0..3).fold(0.0f32, |m, c| m.max((gpu[c] - cpu.pos[c]).abs()));
                    worst.0 = worst.0.max(d / b.height);
                    worst.1 = worst.1.max((gpu[3] - cpu.shade).abs());
                }
            }
            println!(
                "grass tips: max |GPU − CPU| {:.2e} of the blade height, shade {:.2e}; {crushed} blades crushed",
                worst.0, worst.1
            );
            assert!(crushed > 100, "the sphere crushed part of the field");
            assert!(
                worst.0 <= 1e-3,
                "tips differ by {} of a blade's height",
                worst.0
            );
            assert!(worst.1 <= 1e-3, "shades differ by {}", worst.1);
        }

        /// The Bezier physics pass against its CPU twin (`grass::bezier`): random blades in
        /// random winds up to 40 m/s, 40 frames at 60 fps while a sphere rolls across the
        /// field leaving its trail (the CPU twin steps `grass::trail` alongside): control
        /// points within 1e-3 m; the blades the sphere passed lean away from its path.
        #[test]
        fn gpu_bezier_blades_match_the_cpu_model() {
            use windloom::grass::bezier::{Push, State};
            use windloom::grass::trail::{Sphere, Trail};
            let Some(ctx) = context() else { return };
            let l = layout(8.0);
            let blades = scatter(&l);
            let (nx, ny) = (24, 16);
            let cell = [0.5, 0.5];
            let wind = random_wind(nx * ny, 77);
            let mut r =
                GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
            r.set_wind(&ctx.device, &ctx.queue, (nx, ny), [0.0, 0.0], cell, &wind);
            r.set_model(
                &ctx.device,
                &ctx.queue,
                windloom::doc::GrassModel::BezierPhysics,
            );
            let (min, max) = l.bounds();
            let mut trail = Trail::new(min, max);
            let lifetime = 2.0;
            r.set_trail_lifetime(lifetime);
            let camera = Camera::overview(&l);
            let frames = 40;
            let dt = 1.0 / 60.0;
            let sphere_at = |f: usize| Sphere {
                centre: [2.0 + 0.2 * f as f32, 0.3, 4.0],
                radius: 0.6,
            };
            let mut cpu: Vec<State> = blades.iter().map(State::rest).collect();
            for f in 0..frames {
                let sphere = Some(sphere_at(f));
                r.set_sphere(sphere);
                let mut enc = ctx.device.create_command_encoder(&Default::default());
                r.prepare(&ctx.queue, &mut enc, &camera, 1.5, 0.0, dt);
                ctx.queue.submit([enc.finish()]);
                trail.step(sphere, dt, lifetime);
                for (b, s) in blades.iter().zip(&mut cpu) {
                    let w = wind[wind_cell(b.pos, [0.0, 0.0], cell, (nx, ny))];
                    let (c, dir) = trail.crush_at(b.pos, cwd::frame(b).0);
                    let push = Push {
                        sphere,
                        crush: c,
                        dir,
                    };
                    s.advance_pushed(b, w, push, dt);
                }
            }
            let gpu = r.read_bezier(&ctx.device, &ctx.queue).unwrap().unwrap();
            let mut worst = 0.0f32;
            let (mut moved, mut away, mut near) = (0, 0, 0);
            for ((b, g), s) in blades.iter().zip(&gpu).zip(&cpu) {
                for c in 0..3 {
                    worst = worst
                        .max((g.v1[c] - s.v1[c]).abs())
                        .max((g.v2[c] - s.v2[c]).abs());
                }
                let mut calm = State::rest(b);
                let w = wind[wind_cell(b.pos, [0.0, 0.0], cell, (nx, ny))];
                for _ in 0..frames {
                    calm.advance(b, w, dt);
                }
                if (0..3).any(|c| (s.v2[c] - State::rest(b).v2[c]).abs() > 0.01) {
                    moved += 1;
                }
                // Blades within the swept band, beside the path's middle line, lean out of it.
                let off = b.pos[1] - 4.0;
                if (3.5..=8.0).contains(&b.pos[0]) && (0.15..0.45).contains(&off.abs()) {
                    near += 1;
                    if (s.v2[2] - b.pos[1]) * off.signum() > (calm.v2[2] - b.pos[1]) * off.signum()
                    {
                        away += 1;
                    }
                }
            }
            println!(
                "bezier: max |GPU − CPU| {worst:.2e} m over {} blades ({moved} moved; {away} of {near} beside the path lean away from it)",
                blades.len()
            );
            assert!(moved > blades.len() / 2, "the wind moved the blades");
            assert!(
                near > 10 && away * 10 >= near * 8,
                "blades lean out of the sphere's path"
            );
            assert!(
                worst <= 1e-3,
                "the GPU's blades differ from the CPU's by {worst} m"
            );
        }

        /// The trail pass against `grass::trail::Trail`: a sphere dragged across the world,
        /// then left to fade — every texel within 1e-5 each time, and nothing left after the
        /// lifetime (whatever the frame rate).
        #[test]
        fn the_trail_matches_the_cpu_and_fades_in_its_lifetime() {
            use windloom::grass::trail::{Sphere, Trail};
            let Some(ctx) = context() else { return };
            let l = layout(1.0);
            let blades = scatter(&l);
            let mut r =
                GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
            let (min, max) = l.bounds();
            let mut cpu = Trail::new(min, max);
            let lifetime = 1.5;
            r.set_trail_lifetime(lifetime);
            let camera = Camera::overview(&l);
            let mut worst = 0.0f32;
            let mut frame = |r: &mut GrassRenderer, sphere: Option<Sphere>, dt: f32| {
                r.set_sphere(sphere);
                let mut enc = ctx.device.create_command_encoder(&Default::default());
                r.prepare(&ctx.queue, &mut enc, &camera, 1.5, 0.0, dt);
                ctx.queue.submit([enc.finish()]);
                cpu.step(sphere, dt, lifetime);
                let gpu = r.read_trail(&ctx.device, &ctx.queue).unwrap();
                assert_eq!(gpu.len(), cpu.life.len());
                for (g, c) in gpu.iter().zip(&cpu.life) {
                    worst = worst.max((g - c).abs());
                }
                gpu
            };
            for f in 0..20 {
                let s = Sphere {
                    centre: [1.0 + 0.5 * f as f32, 0.5, 2.0 + 0.2 * f as f32],
                    radius: 1.0,
                };
                frame(&mut r, Some(s), 1.0 / 30.0);
            }
            let trodden = frame(&mut r, None, 1.0 / 144.0);
            let marked = trodden.iter().filter(|&&v| v > 0.5).count();
            // Fade at 144 fps for the rest of the lifetime.
            let mut last = trodden;
            for _ in 0..(lifetime * 144.0) as usize {
                last = frame(&mut r, None, 1.0 / 144.0);
            }
            println!(
                "trail: {marked} texels trodden, max |GPU − CPU| {worst:.1e}, max left after the lifetime {}",
                last.iter().cloned().fold(0.0f32, f32::max)
            );
            assert!(marked > 100, "the sphere left a trail");
            assert!(worst <= 1e-5, "the GPU's trail differs by {worst}");
            assert!(
                last.iter().all(|&v| v == 0.0),
                "the trail is gone after its lifetime"
            );
        }

        /// The cull pass against `grass::cull::classify` for random cameras over a field of
        /// blades in the wind, for both models, frame after frame (the LOD hysteresis carries
        /// state): every blade the CPU decides with a margin is decided the same on the GPU,
        /// and the indirect draw counts equal the CPU's counts.
        #[test]
        fn culling_on_the_gpu_matches_the_cpu_for_random_cameras() {
            use windloom::grass::bezier::State;
            use windloom::grass::cull::{self, CullParams, NO_LEVEL, Verdict};
            let Some(ctx) = context() else { return };
            let mut l = layout(30.0);
            l.world.size = [40.0, 30.0];
            l.world.grid = [20, 15];
            let blades = scatter(&l);
            let (nx, ny) = (20, 15);
            let cell = [2.0, 2.0];
            let wind = random_wind(nx * ny, 5);
            let mut params = CullParams::for_height(0.5);
            // Distances that fall inside a 40 m field.
            params.lod_near = 4.0;
            params.lod_far = 12.0;
            params.max_distance = 45.0;
            let mut rng = 12345u64;
            let mut next = || {
                rng = rng
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (rng >> 40) as f32 / (1u64 << 24) as f32
            };
            for model in [
                windloom::doc::GrassModel::CwdQuadratic,
                windloom::doc::GrassModel::BezierPhysics,
            ] {
                let mut r =
                    GrassRenderer::new(&ctx.device, wgpu::TextureFormat::Rgba8Unorm, &l, &blades);
                r.set_wind(&ctx.device, &ctx.queue, (nx, ny), [0.0, 0.0], cell, &wind);
                r.set_model(&ctx.device, &ctx.queue, model);
                r.set_cull(params);
                let mut prev = vec![NO_LEVEL; blades.len()];
                let mut states: Vec<State> = blades.iter().map(State::rest).collect();
                let (mut ambiguous, mut compared) = (0usize, 0usize);
                let mut eye = glam::Vec3::new(20.0, 3.0, 35.0);
                for frame in 0..8 {
                    // A random camera, then a small move (the hysteresis's case).
                    if frame % 2 == 0 {
                        eye = glam::Vec3::new(next() * 40.0, 0.5 + next() * 12.0, next() * 30.0);
                    } else {
                        eye += glam::Vec3::new(0.3, 0.05, -0.2);
                    }
                    let target = glam::Vec3::new(next() * 40.0, 0.0, next() * 30.0);
                    let camera = Camera {
                        eye,
                        target,
                        fov_y: (30.0 + next() * 40.0f32).to_radians(),
                    };
                    let aspect = 1.2 + next();
                    let mut enc = ctx.device.create_command_encoder(&Default::default());
                    r.prepare(&ctx.queue, &mut enc, &camera, aspect, 0.5, 1.0 / 60.0);
                    ctx.queue.submit([enc.finish()]);
                    let (stats, lists) = r.read_cull(&ctx.device, &ctx.queue).unwrap();
                    let mut gpu = vec![None; blades.len()];
                    for (lvl, list) in lists.iter().enumerate() {
                        for &k in list {
                            assert!(gpu[k as usize].is_none(), "blade {k} listed twice");
                            gpu[k as usize] = Some(lvl as u32);
                        }
                    }
                    let vp = camera.view_proj(aspect);
                    let mut counts = [0u32; 6];
                    let mut frame_ambiguous = 0;
                    for (k, b) in blades.iter().enumerate() {
                        let w = wind[wind_cell(b.pos, [0.0, 0.0], cell, (nx, ny))];
                        let pts = match model {
                            windloom::doc::GrassModel::CwdQuadratic => {
                                let c = cwd::centreline(b, w, &l.grass, 0.5, 2);
                                [c[0].pos, c[1].pos, c[2].pos]
                            }
                            windloom::doc::GrassModel::BezierPhysics => {
                                states[k].advance(b, w, 1.0 / 60.0);
                                let s = &states[k];
                                [s.point(0.0), s.point(0.5), s.point(1.0)]
                            }
                        };
                        let (v, margin) = cull::classify(
                            k as u32,
                            cull::side(b),
                            pts,
                            eye.to_array(),
                            &vp,
                            prev[k],
                            &params,
                        );
                        counts[match v {
                            Verdict::Level(l) => l as usize,
                            Verdict::Orientation => 3,
                            Verdict::Frustum => 4,
                            Verdict::Distance => 5,
                        }] += 1;
                        let cpu_level = match v {
                            Verdict::Level(l) => Some(l),
                            _ => None,
                        };
                        if margin < 1e-4 {
                            frame_ambiguous += 1;
                            // Follow the GPU where f32 rounding could go either way.
                            if let Some(g) = gpu[k] {
                                prev[k] = g;
                            }
                            continue;
                        }
                        compared += 1;
                        assert_eq!(
                            gpu[k], cpu_level,
                            "{model:?} frame {frame}: blade {k} ({v:?}, margin {margin})"
                        );
                        if let Some(l) = cpu_level {
                            prev[k] = l;
                        }
                    }
                    ambiguous += frame_ambiguous;
                    let drawn = [counts[0], counts[1], counts[2]];
                    let culled = [counts[3], counts[4], counts[5]];
                    let gpu_culled = [stats.orientation, stats.frustum, stats.distance];
                    if frame_ambiguous == 0 {
                        assert_eq!(stats.drawn, drawn, "{model:?}: indirect counts");
                        assert_eq!(gpu_culled, culled, "{model:?}: cull counters");
                    } else {
                        for (g, c) in stats.drawn.iter().zip(&drawn) {
                            assert!(g.abs_diff(*c) as usize <= frame_ambiguous);
                        }
                    }
                    assert_eq!(stats.total as usize, blades.len());
                }
                println!(
                    "{model:?}: {compared} decisions equal, {ambiguous} within 1e-4 of a threshold set aside"
                );
                assert!(ambiguous * 1000 <= compared, "too many borderline blades");
            }
        }
        /// With the GPU running the field, the grass's wind grid is made on the GPU from the
        /// solver's faces: it equals the CPU's cell-centred velocity exactly.
        #[test]
        fn the_wind_grid_from_a_gpu_field_equals_the_cpu_cells() {
            let Some(ctx) = context() else { return };
            let cpu = super::random_solver(windloom::doc::Boundary::Open, 21);
            let mut fluid = example("obstacles.json");
            fluid.world.grid = [40, 28];
            let gpu = windloom::gpu::GpuSolver::from_solver(&ctx, &fluid, &cpu).unwrap();
            let l = layout(5.0);
            let mut r = GrassRenderer::new(
                &ctx.device,
                wgpu::TextureFormat::Rgba8Unorm,
                &l,
                &scatter(&l),
            );
            let mut enc = ctx.device.create_command_encoder(&Default::default());
            r.wind_from_field(&ctx.device, &ctx.queue, &mut enc, &gpu.field());
            ctx.queue.submit([enc.finish()]);
            let wind = r.read_wind(&ctx.device, &ctx.queue).unwrap();
            let want = cpu.velocity_field();
            assert!(want.iter().any(|v| v[0] != 0.0), "a field to compare");
            assert_eq!(wind, want, "the GPU's cells are the CPU's, bit for bit");
        }

        /// What the editor's 3D view shows (the target's encoded texture, which egui reads as
        /// plain RGBA8) is the frame's sRGB bytes, on an adapter that can view a texture in
        /// another format and, through a copy, on one that cannot (a GL adapter; on Vulkan the
        /// copy is forced): the same bytes both ways, and a real picture (sky above, grass
        /// below).
        #[test]
        fn the_editor_s_view_of_the_grass_is_the_frame_with_or_without_format_views() {
            use windloom::gpu::grass::Target;
            let Some(ctx) = context() else { return };
            let l = layout(4.0);
            let mut r = GrassRenderer::new(
                &ctx.device,
                wgpu::TextureFormat::Rgba8UnormSrgb,
                &l,
                &scatter(&l),
            );
            let camera = Camera {
                eye: glam::Vec3::new(2.0, 1.4, 7.5),
                target: glam::Vec3::new(6.0, 0.2, 4.0),
                fov_y: 45f32.to_radians(),
            };
            let (w, h) = (96u32, 64u32);
            let mut shown = Vec::new();
            // Both ways where the adapter has format views; on one without (GL), the copy.
            let has_views = ctx.downlevel.contains(wgpu::DownlevelFlags::VIEW_FORMATS);
            for views in [true, false].into_iter().filter(|&v| has_views || !v) {
                let mut downlevel = ctx.downlevel;
                downlevel.set(wgpu::DownlevelFlags::VIEW_FORMATS, views);
                let target = Target::new(&ctx.device, [w, h], downlevel);
                windloom::gpu::grass::render_into(
                    &ctx.device,
                    &ctx.queue,
                    &mut r,
                    &camera,
                    (0.0, 0.0),
                    &target,
                )
                .unwrap();
                let frame =
                    windloom::gpu::read_texture(&ctx.device, &ctx.queue, &target.texture, 4)
                        .unwrap();
                let encoded = windloom::gpu::read_texture(
                    &ctx.device,
                    &ctx.queue,
                    target.encoded_texture(),
                    4,
                )
                .unwrap();
                assert_eq!(
                    frame.len(),
                    (w * h * 4) as usize,
                    "format views {views}: a whole frame"
                );
                assert!(
                    frame == encoded,
                    "format views {views}: the view shows the frame's bytes"
                );
                shown.push(encoded);
            }
            assert!(ctx.fault().is_none(), "{:?}", ctx.fault());
            assert!(
                shown.iter().all(|s| *s == shown[0]),
                "both ways show the same picture"
            );
            let px = |x: u32, y: u32| &shown[0][((y * w + x) * 4) as usize..][..3];
            let (sky, ground) = (px(w / 2, 1), px(w / 2, h - 2));
            assert!(sky[2] > sky[0] && sky[2] > 150, "sky at the top: {sky:?}");
            assert!(ground != sky, "something under the sky: {ground:?}");
        }

        /// A device that has reported an error no scope caught cannot be trusted to have drawn
        /// anything: `render --view grass` then fails with the device's message instead of
        /// writing whatever the texture held.
        #[test]
        fn a_grass_picture_from_a_faulted_device_is_an_error() {
            let Some(ctx) = context() else { return };
            let l = layout(4.0);
            let options = windloom::gpu::grass::PictureOptions {
                size: [64, 48],
                time: 0.0,
                camera: None,
                paper_literal: false,
                push: None,
            };
            let dir = tempfile::tempdir().unwrap();
            assert!(windloom::gpu::grass::picture(&ctx, &l, dir.path(), &options).is_ok());
            // An invalid buffer (mapped both ways), outside any error scope.
            let _ = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("invalid on purpose"),
                size: 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::MAP_WRITE,
                mapped_at_creation: false,
            });
            let Err(err) = windloom::gpu::grass::picture(&ctx, &l, dir.path(), &options) else {
                panic!("a faulted device drew a picture");
            };
            let text = err.to_string();
            assert!(
                text.contains("drawing the grass") && text.contains("invalid on purpose"),
                "the error says what failed and why: {text}"
            );
        }

        /// A layout's map backdrop colours the ground under the grass (`render --view grass`).
        #[test]
        fn the_ground_shows_the_map_backdrop() {
            let Some(ctx) = context() else { return };
            let dir = tempfile::tempdir().unwrap();
            // Left half red, right half blue.
            let img = image::RgbaImage::from_fn(64, 64, |x, _| {
                if x < 32 {
                    image::Rgba([230, 20, 20, 255])
                } else {
                    image::Rgba([20, 20, 230, 255])
                }
            });
            img.save(dir.path().join("level.png")).unwrap();
            let mut l = layout(0.01);
            l.world.size = [10.0, 10.0];
            l.world.map = Some(windloom::doc::MapBackdrop {
                image: "level.png".into(),
                opacity: 1.0,
            });
            let camera = Camera {
                eye: glam::Vec3::new(5.0, 14.0, 9.0),
                target: glam::Vec3::new(5.0, 0.0, 5.0),
                fov_y: 45f32.to_radians(),
            };
            let (w, h) = (160u32, 120u32);
            let options = windloom::gpu::grass::PictureOptions {
                size: [w, h],
                time: 0.0,
                camera: Some(camera),
                paper_literal: false,
                push: None,
            };
            let px = windloom::gpu::grass::picture(&ctx, &l, dir.path(), &options).unwrap();
            let at = |x: u32, y: u32| &px[((y * w + x) * 4) as usize..][..3];
            let (left, right) = (at(w / 4, h / 2), at(3 * w / 4, h / 2));
            println!("ground left {left:?}, right {right:?}");
            assert!(
                left[0] > 120 && left[2] < 60,
                "the red half shows on the left: {left:?}"
            );
            assert!(
                right[2] > 120 && right[0] < 60,
                "the blue half on the right: {right:?}"
            );
            // Without the backdrop (the same picture otherwise), soil.
            l.world.map = None;
            let px = windloom::gpu::grass::picture(&ctx, &l, dir.path(), &options).unwrap();
            let soil = &px[(((h / 2) * w + w / 4) * 4) as usize..][..3];
            assert!(
                soil[0] < 120 && soil[2] < 60,
                "plain ground is soil: {soil:?}"
            );
        }

        fn picture(ctx: &GpuContext, speed: f32, model: windloom::doc::GrassModel) -> Vec<u8> {
            let l = layout(40.0);
            let blades = scatter(&l);
            let mut r = GrassRenderer::new(
                &ctx.device,
                wgpu::TextureFormat::Rgba8UnormSrgb,
                &l,
                &blades,
            );
            r.set_model(&ctx.device, &ctx.queue, model);
            let wind = vec![[speed * 0.8, speed * -0.6]; 24 * 16];
            r.set_wind(
                &ctx.device,
                &ctx.queue,
                (24, 16),
                [0.0, 0.0],
                [0.5, 0.5],
                &wind,
            );
            let camera = Camera {
                eye: glam::Vec3::new(2.0, 1.4, 7.5),
                target: glam::Vec3::new(6.0, 0.2, 4.0),
                fov_y: 45f32.to_radians(),
            };
            // Two seconds at 60 fps for the Bezier blades to answer the wind.
            if model == windloom::doc::GrassModel::BezierPhysics {
                for _ in 0..120 {
                    let mut enc = ctx.device.create_command_encoder(&Default::default());
                    r.prepare(&ctx.queue, &mut enc, &camera, 16.0 / 9.0, 0.0, 1.0 / 60.0);
                    ctx.queue.submit([enc.finish()]);
                }
            }
            render_offscreen(ctx, &mut r, &camera, (0.0, 1.0 / 60.0), [320, 180])
                .unwrap()
                .0
        }

        fn luminance(p: &[u8]) -> f64 {
            p.chunks(4)
                .map(|c| {
                    0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2])
                })
                .sum::<f64>()
                / (p.len() / 4) as f64
        }

        /// Calm, breezy and gale pictures of the CWD model, and calm and gale pictures of the
        /// Bezier blades, against committed references (mean channel difference ≤ 1.5/255,
        /// and under 1% of pixels off by more than 24/255); a gale is visibly different from
        /// calm but darkens the picture by less than 12%.
        #[test]
        fn grass_pictures_match_their_references_and_a_gale_stays_lit() {
            use windloom::doc::GrassModel::{BezierPhysics, CwdQuadratic};
            let Some(ctx) = context() else { return };
            let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots");
            let mut pictures = Vec::new();
            for (name, speed, model) in [
                ("calm", 0.0, CwdQuadratic),
                ("breezy", 4.0, CwdQuadratic),
                ("gale", 30.0, CwdQuadratic),
                ("bezier_calm", 0.0, BezierPhysics),
                ("bezier_gale", 30.0, BezierPhysics),
            ] {
                let pixels = picture(&ctx, speed, model);
                let path = dir.join(format!("grass_{name}.png"));
                if std::env::var_os("UPDATE_SNAPSHOTS").is_some() {
                    image::RgbaImage::from_raw(320, 180, pixels.clone())
                        .unwrap()
                        .save(&path)
                        .unwrap();
                }
                let reference = image::open(&path)
                    .unwrap_or_else(|e| {
                        panic!("{}: {e} (UPDATE_SNAPSHOTS=1 writes it)", path.display())
                    })
                    .to_rgba8();
                let diffs: Vec<u8> = pixels
                    .iter()
                    .zip(reference.as_raw())
                    .map(|(a, b)| a.abs_diff(*b))
                    .collect();
                let mean = diffs.iter().map(|&d| f64::from(d)).sum::<f64>() / diffs.len() as f64;
                let off = diffs
                    .chunks(4)
                    .filter(|c| c.iter().any(|&d| d > 24))
                    .count();
                println!("grass_{name}: mean difference {mean:.3}, {off} pixels off");
                assert!(
                    mean <= 1.5,
                    "grass_{name}: mean difference {mean} from the reference"
                );
                assert!(
                    off * 100 <= 320 * 180,
                    "grass_{name}: {off} pixels differ from the reference"
                );
                pictures.push(pixels);
            }
            let (calm, gale) = (luminance(&pictures[0]), luminance(&pictures[2]));
            println!(
                "mean luminance: calm {calm:.1}, breezy {:.1}, gale {gale:.1}",
                luminance(&pictures[1])
            );
            assert!(
                gale >= calm * 0.88,
                "a gale darkens the grass too much: {gale} against {calm}"
            );
            for (calm, gale) in [(0, 2), (3, 4)] {
                let changed = pictures[calm]
                    .iter()
                    .zip(&pictures[gale])
                    .filter(|(a, b)| a != b)
                    .count();
                assert!(
                    changed > pictures[calm].len() / 10,
                    "a gale must change the picture"
                );
            }
            let (calm, gale) = (luminance(&pictures[3]), luminance(&pictures[4]));
            assert!(
                gale >= calm * 0.88,
                "a gale darkens the Bezier grass too much: {gale} against {calm}"
            );
        }
    }

    /// The map view's passes (`shaders/map_*.wgsl`) against their CPU twins in `app::view`.
    mod map {
        use super::{context, random_solver};
        use windloom::app::live::Snapshot;
        use windloom::doc::Boundary;
        use windloom::gpu::mapview::{Frame, Layer, MapRenderer, Overlay, Particle};
        use windloom::gpu::{GpuContext, GpuSolver};
        use windloom::sim::Solver;

        fn snapshot(s: &Solver) -> Snapshot {
            Snapshot {
                nx: s.nx,
                ny: s.ny,
                origin: s.origin,
                size: [s.hx * s.nx as f32, s.hz * s.ny as f32],
                velocity: s.velocity_field(),
                pressure: s.p.clone(),
                ..Default::default()
            }
        }

        /// A frame that fits the world exactly into `w` pixels across at 1 pixel per point.
        fn frame(s: &Solver, w: u32, layer: Layer, overlay: Overlay) -> (Frame, [u32; 2]) {
            let size = [s.hx * s.nx as f32, s.hz * s.ny as f32];
            let zoom = w as f32 / size[0];
            let h = (size[1] * zoom).round() as u32;
            let min = s.origin;
            let max = [min[0] + size[0], min[1] + size[1]];
            let f = Frame {
                layer,
                overlay,
                alpha: 1.0,
                center: [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0],
                zoom,
                ppp: 1.0,
                viewport_px: [w as f32, h as f32],
                world_min: min,
                world_max: max,
                dt: 0.0,
                streaks: 0,
                lattice_origin: min,
                lattice_step: 1.0,
                lattice: [0, 0],
            };
            (f, [w, h])
        }

        fn setup(seed: u64) -> Option<(GpuContext, Solver, GpuSolver)> {
            let ctx = context()?;
            let cpu = random_solver(Boundary::Closed, seed);
            let layout = {
                let mut l = super::example("obstacles.json");
                l.world.grid = [40, 28];
                l
            };
            let gpu = GpuSolver::from_solver(&ctx, &layout, &cpu).unwrap();
            Some((ctx, cpu, gpu))
        }

        /// The stats pass's peaks equal the CPU's: the colour scales need no read-back.
        #[test]
        fn the_stats_pass_finds_the_cpu_peaks() {
            let Some((ctx, cpu, gpu)) = setup(11) else {
                return;
            };
            let (device, queue) = (&ctx.device, &ctx.queue);
            let mut r = MapRenderer::new(device, wgpu::TextureFormat::Rgba8Unorm);
            let (f, _) = frame(&cpu, 80, Layer::Speed, Overlay::None);
            let mut enc = device.create_command_encoder(&Default::default());
            r.prepare(device, queue, &mut enc, &gpu.field(), &f);
            queue.submit([enc.finish()]);
            let [speed, curl, pressure] = r.read_stats(device, queue).unwrap();
            let snap = snapshot(&cpu);
            let cpu_speed = snap
                .velocity
                .iter()
                .fold(0.0f32, |m, v| m.max(v[0].hypot(v[1])));
            let cpu_pressure = cpu.p.iter().fold(0.0f32, |m, p| m.max(p.abs()));
            // The curl the view shows: central differences of cell-centred velocities.
            let (nx, ny) = (cpu.nx, cpu.ny);
            let at = |i: usize, j: usize| snap.velocity[j * nx + i];
            let mut cpu_curl = 0.0f32;
            for j in 0..ny {
                for i in 0..nx {
                    let (il, ir) = (i.saturating_sub(1), (i + 1).min(nx - 1));
                    let (jb, jt) = (j.saturating_sub(1), (j + 1).min(ny - 1));
                    let dvdx = (at(ir, j)[1] - at(il, j)[1]) / ((ir - il) as f32 * cpu.hx);
                    let dudz = (at(i, jt)[0] - at(i, jb)[0]) / ((jt - jb) as f32 * cpu.hz);
                    cpu_curl = cpu_curl.max((dvdx - dudz).abs());
                }
            }
            for (what, g, c) in [
                ("speed", speed, cpu_speed),
                ("curl", curl, cpu_curl),
                ("pressure", pressure, cpu_pressure),
            ] {
                println!("peak {what}: GPU {g}, CPU {c}");
                assert!(c > 0.0);
                assert!((g - c).abs() <= 1e-5 * c, "peak {what}: GPU {g}, CPU {c}");
            }
        }

        /// One frame of streak advection on the GPU moves each particle's head by the
        /// velocity the CPU view samples there, keeps the trail, and rebirths dead particles
        /// inside the world.
        #[test]
        fn streaks_advect_as_the_cpu_view_does() {
            let Some((ctx, cpu, gpu)) = setup(12) else {
                return;
            };
            let (device, queue) = (&ctx.device, &ctx.queue);
            let snap = snapshot(&cpu);
            let (mut f, _) = frame(&cpu, 80, Layer::Speed, Overlay::Streaks);
            f.dt = 0.05;
            let size = snap.size;
            let mut particles = Vec::new();
            for k in 0..64u32 {
                let len = if k % 2 == 0 { 5 } else { 14 };
                let mut q = Particle {
                    trail: [[0.0; 2]; 16],
                    age: 1.0,
                    life: if k == 7 { 1.01 } else { 3.0 },
                    len,
                    seed: k,
                };
                for n in 0..len as usize {
                    let t = (k as f32 * 0.37 + n as f32 * 0.01).fract();
                    q.trail[n] = [
                        snap.origin[0] + size[0] * (0.2 + 0.6 * t),
                        snap.origin[1] + size[1] * (0.2 + 0.6 * (k as f32 / 64.0)),
                    ];
                }
                particles.push(q);
            }
            f.streaks = particles.len() as u32;
            let mut r = MapRenderer::new(device, wgpu::TextureFormat::Rgba8Unorm);
            r.write_particles(device, queue, &particles);
            let mut enc = device.create_command_encoder(&Default::default());
            r.prepare(device, queue, &mut enc, &gpu.field(), &f);
            queue.submit([enc.finish()]);
            let after = r.read_particles(device, queue).unwrap();
            let mut worst = 0.0f32;
            let mut reborn = 0;
            for (k, (a, b)) in particles.iter().zip(&after).enumerate() {
                let head = a.trail[a.len as usize - 1];
                let v = snap.sample(head);
                let want = [head[0] + v[0] * f.dt, head[1] + v[1] * f.dt];
                // The CPU view's rule: too old, out of the world, or stuck in calm air (inside
                // an obstacle).
                let out = want[0] < snap.origin[0]
                    || want[1] < snap.origin[1]
                    || want[0] > snap.origin[0] + size[0]
                    || want[1] > snap.origin[1] + size[1];
                let dies = a.age + f.dt > a.life || out || (v == [0.0, 0.0] && a.age + f.dt > 0.5);
                assert_eq!(dies, k == 7 || v == [0.0, 0.0], "particle {k}");
                if dies {
                    // Born again: one point, inside the world.
                    assert_eq!(b.len, 1, "particle {k}: a dead streak is reborn");
                    let p = b.trail[0];
                    assert!(p[0] >= snap.origin[0] && p[0] <= snap.origin[0] + size[0]);
                    assert!(p[1] >= snap.origin[1] && p[1] <= snap.origin[1] + size[1]);
                    reborn += 1;
                    continue;
                }
                let (got, kept) = if a.len < 14 {
                    assert_eq!(b.len, a.len + 1);
                    (
                        b.trail[a.len as usize],
                        b.trail[..a.len as usize] == a.trail[..a.len as usize],
                    )
                } else {
                    assert_eq!(b.len, 14);
                    (b.trail[13], b.trail[..13] == a.trail[1..14])
                };
                assert!(
                    kept,
                    "particle {k}: the trail keeps its older points in order"
                );
                worst = worst.max((got[0] - want[0]).abs().max((got[1] - want[1]).abs()));
                assert!((b.age - (a.age + f.dt)).abs() < 1e-6);
            }
            println!("streak heads: max |GPU − CPU| {worst:.2e} m; {reborn} reborn");
            assert!(reborn < 16, "most test particles live on");
            assert!(
                worst <= 1e-4,
                "streak heads differ from the CPU view by {worst} m"
            );
        }

        /// Renders the map view's colour map offscreen; returns RGBA pixels and the size.
        fn render(ctx: &GpuContext, gpu: &GpuSolver, f: &Frame, [w, h]: [u32; 2]) -> Vec<u8> {
            let (device, queue) = (&ctx.device, &ctx.queue);
            let format = wgpu::TextureFormat::Rgba8Unorm;
            let mut r = MapRenderer::new(device, format);
            let target = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("map test target"),
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            let view = target.create_view(&Default::default());
            let mut enc = device.create_command_encoder(&Default::default());
            r.prepare(device, queue, &mut enc, &gpu.field(), f);
            {
                let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("map test"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                r.paint(&mut pass);
            }
            queue.submit([enc.finish()]);
            windloom::gpu::read_texture(device, queue, &target, 4).unwrap()
        }

        /// Every pixel of the GPU colour map (speed, and pressure) is the colour the CPU
        /// view gives the field sampled at that pixel's centre, within the colour table's
        /// quantisation (4/255 a channel).
        #[test]
        fn the_colour_map_matches_the_cpu_view_pixel_by_pixel() {
            let Some((ctx, cpu, gpu)) = setup(13) else {
                return;
            };
            let snap = snapshot(&cpu);
            for layer in [Layer::Speed, Layer::Pressure] {
                let (f, [w, h]) = frame(&cpu, 160, layer, Overlay::None);
                let pixels = render(&ctx, &gpu, &f, [w, h]);
                let speed_scale = snap
                    .velocity
                    .iter()
                    .fold(1.0f32, |m, v| m.max(v[0].hypot(v[1])));
                let p_scale = cpu.p.iter().fold(1e-6f32, |m, p| m.max(p.abs()));
                let mut worst = 0u8;
                for y in 0..h {
                    for x in 0..w {
                        let world = [
                            f.world_min[0] + (x as f32 + 0.5) / f.zoom,
                            f.world_min[1] + (y as f32 + 0.5) / f.zoom,
                        ];
                        let want = match layer {
                            Layer::Speed => {
                                let v = snap.sample(world);
                                windloom::colour::speed_rgb(v[0].hypot(v[1]) / speed_scale)
                            }
                            _ => windloom::colour::signed_rgb(
                                pressure_at(&snap, &cpu.p, world) / p_scale,
                            ),
                        };
                        let got = &pixels[((y * w + x) * 4) as usize..][..4];
                        assert_eq!(got[3], 255, "the colour map is opaque at alpha 1");
                        for c in 0..3 {
                            worst = worst.max(got[c].abs_diff(want[c]));
                        }
                    }
                }
                println!("{layer:?}: max channel difference {worst}/255 over {w}x{h} pixels");
                assert!(
                    worst <= 4,
                    "{layer:?}: GPU pixels differ from the CPU view by {worst}/255"
                );
            }
        }

        /// Pressure bilinear between cell centres (as `Snapshot::sample` does velocity).
        fn pressure_at(snap: &Snapshot, p: &[f32], w: [f32; 2]) -> f32 {
            let (nx, ny) = (snap.nx, snap.ny);
            let x = ((w[0] - snap.origin[0]) / snap.size[0] * nx as f32 - 0.5)
                .clamp(0.0, (nx - 1) as f32);
            let z = ((w[1] - snap.origin[1]) / snap.size[1] * ny as f32 - 0.5)
                .clamp(0.0, (ny - 1) as f32);
            let (i0, j0) = (x as usize, z as usize);
            let (i1, j1) = ((i0 + 1).min(nx - 1), (j0 + 1).min(ny - 1));
            let (fx, fz) = (x - i0 as f32, z - j0 as f32);
            let at = |i: usize, j: usize| p[j * nx + i];
            let a = at(i0, j0) + (at(i1, j0) - at(i0, j0)) * fx;
            let b = at(i0, j1) + (at(i1, j1) - at(i0, j1)) * fx;
            a + (b - a) * fz
        }
    }
}

/// The grass model's CPU side: placement and the CWD deformation (the GPU's twin).
mod grass {
    use super::example;
    use windloom::doc::GrassParams;
    use windloom::grass::cwd::{self, Point};
    use windloom::grass::{Blade, in_obstacle, scatter};

    fn blade(facing: f32, height: f32, stiffness: f32) -> Blade {
        Blade {
            pos: [3.0, 4.0],
            facing,
            height,
            width: 0.03,
            stiffness,
            palette: 0,
            variation: 0.3,
        }
    }

    fn length(points: &[Point]) -> f32 {
        points
            .windows(2)
            .map(|w| {
                let (a, b) = (w[0].pos, w[1].pos);
                ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt()
            })
            .sum()
    }

    /// Blades of every shape the parameters allow, facing every way.
    fn blades() -> Vec<Blade> {
        let mut out = Vec::new();
        for f in 0..8 {
            for &h in &[0.3, 0.5, 0.7, 1.2] {
                for &s in &[0.5, 1.0, 1.5] {
                    out.push(blade(f as f32 * 0.785 + 0.1, h, s));
                }
            }
        }
        out
    }

    #[test]
    fn calm_air_gives_the_rest_shape() {
        let g = GrassParams::default();
        for b in blades() {
            let calm = cwd::centreline(&b, [0.0, 0.0], &g, 3.7, 8);
            let later = cwd::centreline(&b, [0.0, 0.0], &g, 9.1, 8);
            assert_eq!(calm, later, "no wind, no motion");
            // The rest shape: eq. 11 alone, at the blade's length, bending toward its facing.
            let (fwd, _) = cwd::frame(&b);
            let tip = calm[8].pos;
            let lean = (tip[0] - b.pos[0]) * fwd[0] + (tip[2] - b.pos[1]) * fwd[1];
            assert!(
                lean > 0.0 && lean < 0.2 * b.height,
                "rests leaning a little forward"
            );
            assert!(tip[1] > 0.95 * b.height, "and nearly upright");
            assert!((length(&calm) - b.height).abs() <= 0.02 * b.height);
        }
    }

    #[test]
    fn length_is_kept_in_any_wind_up_to_40_m_s() {
        let g = GrassParams::default();
        for b in blades() {
            for speed in [0.5, 2.0, 6.0, 12.0, 25.0, 40.0] {
                for dir in 0..6 {
                    let a = dir as f32 * 1.047;
                    let wind = [speed * a.cos(), speed * a.sin()];
                    // Finely sampled: the true curve, not the points the length was fixed on.
                    let pts = cwd::centreline(&b, wind, &g, 1.3, 64);
                    let len = length(&pts);
                    assert!(
                        (len - b.height).abs() <= 0.02 * b.height,
                        "{speed} m/s: length {len} for a {} m blade",
                        b.height
                    );
                    assert!(
                        pts.iter().all(|p| p.pos[1] >= 0.0),
                        "never below the ground"
                    );
                }
            }
        }
    }

    #[test]
    fn the_tip_moves_downwind_and_saturates_before_the_blade_is_flat() {
        let g = GrassParams::default();
        for b in blades() {
            let rest = cwd::centreline(&b, [0.0, 0.0], &g, 0.0, 8)[8].pos;
            for speed in [2.0f32, 5.0, 10.0, 20.0, 40.0] {
                let dir = [0.6f32, 0.8];
                let tip = cwd::centreline(&b, [speed * dir[0], speed * dir[1]], &g, 0.0, 8)[8].pos;
                let downwind = (tip[0] - rest[0]) * dir[0] + (tip[2] - rest[2]) * dir[1];
                assert!(downwind > 0.0, "{speed} m/s: the tip moves downwind");
                if speed >= 10.0 {
                    // (In light wind against its lean a blade first straightens up.)
                    assert!(
                        tip[1] < rest[1],
                        "{speed} m/s: a strong wind lowers the tip"
                    );
                }
                // The paper's open problem: not flat, even at 40 m/s.
                assert!(
                    tip[1] > 0.25 * b.height,
                    "{speed} m/s: tip at {} of {}",
                    tip[1],
                    b.height
                );
            }
        }
    }

    #[test]
    fn the_shadow_stays_in_range_and_a_gale_does_not_blacken_the_grass() {
        let g = GrassParams::default();
        let s = g.shadow;
        for b in blades() {
            for speed in [0.0f32, 3.0, 10.0, 40.0] {
                for p in cwd::centreline(&b, [speed, 0.0], &g, 0.5, 8) {
                    assert!(p.shade >= s.m_min && p.shade <= s.m_max);
                }
            }
            let tip = |v: f32| cwd::centreline(&b, [v, 0.0], &g, 0.5, 8)[8].shade;
            let mean = |v: f32| {
                let p = cwd::centreline(&b, [v, 0.0], &g, 0.5, 8);
                p.iter().map(|p| p.shade).sum::<f32>() / p.len() as f32
            };
            // Eq. 14 as printed sends a 40 m/s tip to m_min (black); saturated, it stays lit.
            assert!(
                tip(40.0) > s.m_min + 0.05,
                "a gale's tip keeps its light: {}",
                tip(40.0)
            );
            assert!(
                mean(40.0) < mean(0.0),
                "but the blade is shaded more than a calm one"
            );
        }
    }

    #[test]
    fn strong_wind_still_moves() {
        // Capping the wind would freeze blades at the cap: the flutter keeps them alive.
        let g = GrassParams::default();
        let b = blade(0.3, 0.6, 1.0);
        let tips: Vec<f32> = (0..20)
            .map(|k| cwd::centreline(&b, [30.0, 0.0], &g, k as f32 * 0.05, 8)[8].pos[0])
            .collect();
        let (lo, hi) = tips
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(
            hi - lo > 0.01 * b.height,
            "the tip sways in a gale: {lo}..{hi}"
        );
    }

    /// The 3D view's extras: every obstacle a closed prism (walls all round, a triangulated top
    /// covering its area), every enabled arrow on the ground with its head.
    #[test]
    fn the_3d_scene_has_every_obstacle_and_arrow() {
        use windloom::doc::Shape;
        use windloom::grass::scene::{OBSTACLE_HEIGHT, arrows, solids};
        let l = example("obstacles.json");
        let v = solids(&l);
        let ring = |s: &Shape| match s {
            Shape::Circle { .. } => 32,
            Shape::Polygon { points } => points.len(),
        };
        let want: usize = l
            .obstacles
            .iter()
            .map(|o| 6 * ring(&o.shape) + 3 * (ring(&o.shape) - 2))
            .sum();
        assert_eq!(v.len(), want, "walls and a whole top for each obstacle");
        assert!(
            v.iter()
                .all(|p| p.pos[1] == 0.0 || p.pos[1] == OBSTACLE_HEIGHT)
        );
        // The tops' triangles cover the obstacles' areas.
        let tops: f32 = v
            .chunks(3)
            .filter(|t| t.iter().all(|p| p.pos[1] == OBSTACLE_HEIGHT))
            .map(|t| {
                let (a, b, c) = (t[0].pos, t[1].pos, t[2].pos);
                ((b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0])).abs() / 2.0
            })
            .sum();
        let areas: f32 = l
            .obstacles
            .iter()
            .map(|o| match &o.shape {
                Shape::Circle { radius, .. } => {
                    16.0 * radius * radius * (std::f32::consts::TAU / 32.0).sin()
                }
                Shape::Polygon { points } => windloom::doc::polygon_area(points).abs(),
            })
            .sum();
        assert!(
            (tops - areas).abs() < 1e-3 * areas,
            "tops {tops} m² for {areas} m² of obstacles"
        );
        let edges: usize = l
            .trees
            .iter()
            .filter(|t| t.enabled)
            .map(|t| t.root.arrows().len())
            .sum();
        let roots = l.trees.iter().filter(|t| t.enabled).count();
        assert_eq!(
            arrows(&l).len(),
            4 * roots + 6 * edges,
            "a cross per root, a shaft and head per arrow"
        );
    }

    /// The Bezier physics blades (issue 12's CPU twin): length and ground kept in any wind,
    /// back to rest when the wind drops, bent downwind, the same at 30 and 144 fps.
    mod bezier {
        use super::blades;
        use windloom::grass::bezier::{Push, State};
        use windloom::grass::trail::{Sphere, Trail};

        /// A sphere set down beside a blade pushes its tip away from the sphere's centre, the
        /// length kept; its trail holds the blade down, and once the trail has faded the blade
        /// stands again.
        #[test]
        fn a_sphere_pushes_blades_away_and_they_recover_after_the_trail() {
            for b in blades() {
                for side in [-1.0f32, 1.0] {
                    let mut s = State::rest(&b);
                    let sphere = Sphere {
                        centre: [b.pos[0] + side * 0.25, 0.3, b.pos[1]],
                        radius: 0.4,
                    };
                    let mut trail = Trail::new(
                        [b.pos[0] - 3.0, b.pos[1] - 3.0],
                        [b.pos[0] + 3.0, b.pos[1] + 3.0],
                    );
                    let lifetime = 1.0;
                    for _ in 0..30 {
                        trail.step(Some(sphere), 1.0 / 60.0, lifetime);
                        let (crush, dir) = trail.crush_at(b.pos, [1.0, 0.0]);
                        s.advance_pushed(
                            &b,
                            [0.0, 0.0],
                            Push {
                                sphere: Some(sphere),
                                crush,
                                dir,
                            },
                            1.0 / 60.0,
                        );
                    }
                    let moved = s.v2[0] - b.pos[0];
                    assert!(
                        moved * side < -0.3 * b.height,
                        "the tip moves away from the sphere: {moved} (sphere on side {side})"
                    );
                    assert!((s.length(64) - b.height).abs() <= 0.02 * b.height);
                    // Sphere gone: the trail holds the blade down for a while…
                    let rest = run(&b, [0.0, 0.0], 4.0, 60.0).v2;
                    let mut path = Vec::new();
                    for _ in 0..150 {
                        trail.step(None, 1.0 / 60.0, lifetime);
                        let (crush, dir) = trail.crush_at(b.pos, [1.0, 0.0]);
                        let push = Push {
                            sphere: None,
                            crush,
                            dir,
                        };
                        s.advance_pushed(&b, [0.0, 0.0], push, 1.0 / 60.0);
                        path.push(s.v2);
                    }
                    let gap = |p: &[f32; 3]| {
                        ((p[0] - rest[0]).powi(2)
                            + (p[1] - rest[1]).powi(2)
                            + (p[2] - rest[2]).powi(2))
                        .sqrt()
                    };
                    assert!(
                        path[10][1] < rest[1] - 0.1 * b.height,
                        "held down: {} of {}",
                        path[10][1],
                        rest[1]
                    );
                    // …then it returns to where gravity alone leaves it, its tip closing on
                    // that point frame after frame: no jitter, no overshoot.
                    assert!(gap(path.last().unwrap()) < 0.02 * b.height, "back at rest");
                    let away = path
                        .windows(2)
                        .map(|w| gap(&w[1]) - gap(&w[0]))
                        .fold(0.0f32, f32::max);
                    assert!(
                        away < 1e-4,
                        "the tip moves away from rest while settling: {away} m"
                    );
                }
            }
        }

        fn run(b: &windloom::grass::Blade, wind: [f32; 2], seconds: f32, fps: f32) -> State {
            let mut s = State::rest(b);
            for _ in 0..(seconds * fps).round() as usize {
                s.advance(b, wind, 1.0 / fps);
            }
            s
        }

        #[test]
        fn length_and_ground_are_kept_in_any_wind() {
            for b in blades() {
                for speed in [0.0f32, 3.0, 10.0, 40.0] {
                    let mut s = State::rest(&b);
                    for k in 0..240 {
                        let a = k as f32 * 0.05;
                        s.advance(&b, [speed * a.cos(), speed * a.sin()], 1.0 / 60.0);
                        let l = s.length(64);
                        assert!(
                            (l - b.height).abs() <= 0.02 * b.height,
                            "{speed} m/s: length {l} of {}",
                            b.height
                        );
                        assert!(s.v2[1] >= 0.0 && s.v1[1] >= 0.0, "above the ground");
                    }
                }
            }
        }

        #[test]
        fn calm_air_brings_a_blade_back_to_rest() {
            for b in blades() {
                let calm = run(&b, [0.0, 0.0], 4.0, 60.0);
                let mut s = run(&b, [12.0, -5.0], 3.0, 60.0);
                assert!(
                    (0..3).any(|c| (s.v2[c] - calm.v2[c]).abs() > 0.01),
                    "the wind moved it"
                );
                for _ in 0..240 {
                    s.advance(&b, [0.0, 0.0], 1.0 / 60.0);
                }
                let d = (0..3).fold(0.0f32, |m, c| m.max((s.v2[c] - calm.v2[c]).abs()));
                assert!(d < 1e-3 * b.height.max(1.0), "back to rest within {d} m");
                // At rest it stands: gravity bends it, recovery holds it up.
                assert!(
                    calm.v2[1] > 0.6 * b.height,
                    "a calm blade stands: tip at {}",
                    calm.v2[1]
                );
            }
        }

        #[test]
        fn wind_bends_the_tip_downwind() {
            for b in blades() {
                let calm = run(&b, [0.0, 0.0], 3.0, 60.0);
                let dir = [0.6f32, -0.8];
                let windy = run(&b, [8.0 * dir[0], 8.0 * dir[1]], 3.0, 60.0);
                let moved =
                    (windy.v2[0] - calm.v2[0]) * dir[0] + (windy.v2[2] - calm.v2[2]) * dir[1];
                assert!(moved > 0.01 * b.height, "the tip moves downwind: {moved}");
            }
        }

        #[test]
        fn the_same_wind_gives_the_same_motion_at_30_and_144_fps() {
            for b in blades() {
                let a = run(&b, [6.0, 2.0], 2.0, 30.0);
                let c = run(&b, [6.0, 2.0], 2.0, 144.0);
                let d = (0..3).fold(0.0f32, |m, k| m.max((a.v2[k] - c.v2[k]).abs()));
                assert!(d < 1e-4, "30 and 144 fps differ by {d} m");
            }
        }
    }

    #[test]
    fn placement_is_deterministic_dense_as_asked_and_clear_of_obstacles() {
        let mut l = example("obstacles.json");
        l.grass = GrassParams {
            density: 20.0,
            ..GrassParams::default()
        };
        let a = scatter(&l);
        assert_eq!(a, scatter(&l), "the same seed gives the same blades");
        l.grass.seed += 1;
        assert_ne!(a, scatter(&l), "another seed, other blades");
        l.grass.seed -= 1;
        assert!(
            a.iter().all(|b| !in_obstacle(&l, b.pos)),
            "no blade in an obstacle"
        );
        // Density over the free area (estimated on a fine lattice) within 5%.
        let [w, d] = l.world.size;
        let n = 600;
        let free = (0..n * n)
            .filter(|k| {
                let p = [
                    l.world.origin[0] + ((k % n) as f32 + 0.5) / n as f32 * w,
                    l.world.origin[1] + ((k / n) as f32 + 0.5) / n as f32 * d,
                ];
                !in_obstacle(&l, p)
            })
            .count() as f32
            / (n * n) as f32
            * w
            * d;
        let density = a.len() as f32 / free;
        assert!(
            (density - 20.0).abs() <= 0.05 * 20.0,
            "{density} blades/m² where 20 were asked"
        );
        let g = &l.grass;
        for b in &a {
            assert!(b.height >= g.height[0] && b.height <= g.height[1]);
            assert!(b.width >= g.width[0] && b.width <= g.width[1]);
            assert!((b.palette as usize) < g.palettes.len());
        }
    }

    /// The point under the pointer, where the editor puts the pushing sphere: a ground point
    /// projected to the screen and cast back lands where it was, for many cameras.
    #[test]
    fn the_ray_under_the_pointer_finds_the_ground_point() {
        use windloom::gpu::grass::Camera;
        for k in 0..200 {
            let f = |s: u32| windloom::grass::cull::pcg01(k * 7 + s);
            let camera = Camera {
                eye: glam::Vec3::new(f(1) * 50.0, 0.5 + f(2) * 30.0, f(3) * 50.0),
                target: glam::Vec3::new(f(4) * 50.0, 0.0, f(5) * 50.0),
                fov_y: (20.0 + 60.0 * f(6)).to_radians(),
            };
            let aspect = 0.8 + f(7);
            let g = glam::Vec3::new(f(8) * 50.0, 0.0, f(9) * 50.0);
            let c = camera.view_proj(aspect) * g.extend(1.0);
            if c.w <= 0.0 || c.x.abs() > c.w || c.y.abs() > c.w {
                continue;
            }
            let hit = camera
                .ground_point(aspect, [c.x / c.w, c.y / c.w])
                .expect("a visible ground point is hit");
            assert!(
                hit.distance(g) <= 1e-3 * (1.0 + camera.eye.distance(g)),
                "{hit} for {g}"
            );
        }
    }

    /// The cull's CPU twin: LOD boundaries are a dithered band with hysteresis, and distance
    /// culling thins the field gradually with no blade popping.
    mod cull {
        use windloom::grass::cull::{CullParams, NO_LEVEL, distance_width, level, reach};

        #[test]
        fn lod_levels_do_not_flicker_at_a_boundary_and_change_over_a_band() {
            let p = CullParams::for_height(0.5);
            // A camera jittering ±1% around a blade's boundary keeps the blade's level.
            for k in 0..2000u32 {
                let mut l = level(k, p.lod_near * 0.5, NO_LEVEL, &p);
                let mut changes = 0;
                let jitter = p.lod_near * (1.0 + p.dither * ((k as f32 * 0.618).fract() - 0.5));
                for f in 0..60 {
                    let d = jitter * (1.0 + 0.01 * if f % 2 == 0 { 1.0 } else { -1.0 });
                    let n = level(k, d, l, &p);
                    changes += usize::from(n != l && f > 0);
                    l = n;
                }
                assert!(
                    changes <= 1,
                    "blade {k} flickers between levels: {changes} changes"
                );
            }
            // At one distance, blades differ: a band, not a line.
            let d = p.lod_near;
            let coarse = (0..2000u32)
                .filter(|&k| level(k, d, NO_LEVEL, &p) == 1)
                .count();
            assert!(
                (400..1600).contains(&coarse),
                "{coarse} of 2000 blades coarser at the boundary"
            );
            // Far from the boundaries every blade agrees.
            assert!((0..2000).all(|k| level(k, 0.5 * p.lod_near, NO_LEVEL, &p) == 0));
            assert!((0..2000).all(|k| level(k, 2.0 * p.lod_far, NO_LEVEL, &p) == 2));
        }

        #[test]
        fn distance_culling_thins_gradually_and_fades_blades_out() {
            let p = CullParams::for_height(0.5);
            let n = 20_000u32;
            let kept = |d: f32| (0..n).filter(|&k| d < reach(k, &p)).count() as f32 / n as f32;
            let mut last = 1.0;
            for step in 1..=10 {
                let d = p.max_distance * step as f32 / 10.0 - 1e-3;
                let f = kept(d);
                assert!(f <= last, "fewer blades farther away");
                assert!(
                    (f - (1.0 - d / p.max_distance)).abs() < 0.15,
                    "about 1 − d/max kept at {d} m: {f}"
                );
                last = f;
            }
            assert_eq!(kept(p.max_distance + 1.0), 0.0);
            // A blade's width reaches zero at its reach (it fades out, never pops), and
            // survivors widen where the field is thinned.
            for k in 0..500 {
                let r = reach(k, &p);
                assert!(distance_width(k, r * 0.9999, &p) < 0.01);
                assert!(distance_width(k, 0.0, &p) == 1.0);
            }
            let far = (0..n)
                .map(|k| (k, 0.5 * p.max_distance))
                .find(|&(k, d)| d < 0.7 * reach(k, &p))
                .unwrap();
            assert!(distance_width(far.0, far.1, &p) > 1.5);
        }
    }
}

/// The advection samplers read a face's neighbourhood as whole rows where the departure
/// point lies within a cell of the face, and point by point elsewhere (farther points, the
/// row ends, the first and last rows, a period's seam). Both must give the reference's bits:
/// a flow of slow smooth wind (most faces local) with a band of fast noise (points up to
/// three cells away), every boundary, both schemes, 1–3 threads.
#[test]
fn advection_matches_the_reference_near_and_far() {
    use doc::Advection::{MacCormack, SemiLagrangian};
    for boundary in [Boundary::Open, Boundary::Closed, Boundary::Periodic] {
        for advection in [SemiLagrangian, MacCormack] {
            let mut l = example("obstacles.json");
            l.world.grid = [67, 45];
            l.sim.boundary = boundary;
            l.sim.advection = advection;
            let seeded = || {
                let mut s = noisy_solver(&l, (11, 12), 1.0);
                let dt = s.params.dt;
                let cells = [l.world.size[0] / 67.0 / dt, l.world.size[1] / 45.0 / dt];
                let (u, v) = s.faces_mut();
                for (c, f) in [u, v].into_iter().enumerate() {
                    let w = f.len() / if c == 0 { 45 } else { 46 };
                    for (k, x) in f.iter_mut().enumerate() {
                        let (i, j) = ((k % w) as f32, (k / w) as f32);
                        let smooth = 0.8 * (0.21 * i + 0.13 * j + c as f32).sin();
                        let band = if (20.0..26.0).contains(&j) {
                            3.0 * *x
                        } else {
                            0.0
                        };
                        *x = (smooth + band) * cells[c];
                    }
                }
                s.enforce_boundaries();
                s
            };
            let dt = l.sim.dt;
            let bits = |s: &Solver| -> Vec<u32> {
                [&s.u, &s.v]
                    .into_iter()
                    .flat_map(|f| f.iter().map(|x| x.to_bits()))
                    .collect()
            };
            let mut want = seeded();
            let speeds = |s: &Solver, far: bool| {
                let cell = l.world.size[0] / 67.0 / dt;
                s.u.iter().filter(|&&u| (u.abs() >= cell) == far).count()
            };
            assert!(
                speeds(&want, true) > 50 && speeds(&want, false) > 1000,
                "{boundary:?}: faces both near and far"
            );
            want.advect_plain_reference(dt);
            let want = bits(&want);
            for threads in [1, 2, 3] {
                let got = on_threads(threads, || {
                    let mut s = seeded();
                    s.advect(dt);
                    bits(&s)
                });
                let first = want.iter().zip(&got).position(|(a, b)| a != b);
                assert!(
                    first.is_none(),
                    "{boundary:?} {advection:?}, {threads} threads: first differing value {first:?}"
                );
            }
        }
    }
}
