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

/// The ambient wind along a row (what the forces pass uses) is `Ambient::wind` point by point,
/// to the bit: every kind of layer, alone and stacked, for rows of faces from many to a
/// texel (runs of faces) to several texels a face apart (face by face), rows crossing the FFT
/// tile's edge and starting at negative x, both components, at several times.
#[test]
fn ambient_rows_give_the_bits_of_the_wind_point_by_point() {
    let mut stacked = example("meadow.json");
    stacked.ambient.extend(example("breeze-fft.json").ambient);
    for kind in [
        doc::AmbientKind::Noise {
            direction_deg: 200.0,
            scale: 7.0,
            speed: 1.5,
            strength: 3.0,
        },
        doc::AmbientKind::Sine {
            direction_deg: 95.0,
            amplitude: 2.0,
            wavelength: 11.0,
            frequency: 0.4,
        },
    ] {
        let mut a = stacked.ambient[0].clone();
        a.id = 100 + stacked.ambient.len() as u32;
        a.kind = kind;
        stacked.ambient.push(a);
    }
    let layouts = [example("meadow.json"), example("breeze-fft.json"), stacked];
    let mut scratch = forces::RowScratch::default();
    let mut checked = 0;
    for l in &layouts {
        let mut ambient = forces::Ambient::new(l);
        // Face spacings from 40 faces a texel (1 m texels) to 2.5 texels a face.
        for spacing in [0.025f32, 0.2, 0.3, 0.7, 1.0, 2.5] {
            for (x0, z) in [(0.0f32, 3.3), (-17.25, 40.1), (61.9, -2.0)] {
                let xs: Vec<f32> = (0..300).map(|i| x0 + i as f32 * spacing).collect();
                let mut row = vec![0.0; xs.len()];
                for t in [0.0, 1.7, 9.25] {
                    ambient.set_time(t);
                    for c in 0..2 {
                        ambient.component_row(c, z, &xs, &mut row, &mut scratch);
                        for (k, &x) in xs.iter().enumerate() {
                            let want = ambient.wind([x, z])[c];
                            assert!(
                                row[k].to_bits() == want.to_bits(),
                                "{}: spacing {spacing}, x {x}, z {z}, t {t}, component {c}: \
                                 row {} vs wind {want}",
                                l.name,
                                row[k]
                            );
                            checked += 1;
                        }
                    }
                }
            }
        }
    }
    assert_eq!(checked, 3 * 6 * 3 * 300 * 3 * 2);
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

    // A level's own proportions, as `bake --grid` writes them.
    let out = bench(&["--grid", "48x32", "--steps", "1", "--warmup", "0"]);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["grid"], serde_json::json!([48, 32]));
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

mod gpu;

/// The grass model's CPU side: placement and the CWD deformation (the GPU's twin).
mod grass;

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
