//! Every layout, however extreme, runs 10,000 steps finite and bounded, within its memory
//! budget.

use super::*;

#[test]
fn solver_memory_stays_within_the_validation_budget() {
    // Without wind trees, and with them: their splats' gains, which the forces keep across
    // steps, get what the base arrays leave of the budget.
    let mut branching = example("branching.json");
    branching.trees[0].propagation_speed = 1000.0;
    for pressure in [doc::PressureSolve::Jacobi, doc::PressureSolve::Multigrid] {
        for grid in [[8, 8], [100, 37], [256, 256], [300, 20], [20, 300]] {
            for (name, base) in [
                ("empty", Layout::new("m", [10.0, 10.0], grid)),
                ("branching", branching.clone()),
            ] {
                let mut l = base;
                l.world.grid = grid;
                l.sim.pressure = pressure;
                let mut s = Solver::new(&l);
                // The multigrid hierarchy is made by the first solve; the arrows switch
                // on in the first steps.
                for _ in 0..3 {
                    s.step();
                }
                assert!(
                    s.memory_bytes() <= s.memory_budget(),
                    "{name} {pressure:?} {grid:?}: {} > {}",
                    s.memory_bytes(),
                    s.memory_budget()
                );
                if name == "branching" && grid[0] * grid[1] >= 100 * 37 {
                    assert!(
                        s.force_gain_floats > 0,
                        "{pressure:?} {grid:?}: no gains kept"
                    );
                }
            }
        }
    }
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
                    locked: false,
                    hidden: false,
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
    run_checked(s, 10_000, 500, bound, what)
}

/// Steps `s` `steps` times, checking every `every` steps that the field is finite and no
/// cell is faster than `bound`; returns the fastest speed seen.
fn run_checked(s: &mut Solver, steps: usize, every: usize, bound: f32, what: &str) -> f32 {
    let mut peak = 0.0f32;
    for k in 1..=steps {
        s.step();
        if k % every == 0 {
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
/// stays finite and near its arrows: checked every 500 steps, no cell ever faster than 2.5
/// times the strongest arrow (or than 25 m/s). The peaks are 7.1 (meadow), 11.2
/// (branching, arrows ≤ 10 m/s), 6.2 (breeze-fft), 14.4 (obstacles, ≤ 12.5) and 21.1 m/s
/// (two-winds, ≤ 11.25, where its jets meet). While confinement still pushed the cells
/// along open edges, thin jets grew there and branching and obstacles spiked to 55–77 m/s
/// (docs/RELIABILITY.md, "Findings").
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
        let bound = 2.5
            * l.trees
                .iter()
                .map(|t| strongest(&t.root))
                .fold(10.0, f32::max);
        let peak = run_10000_steps(&mut Solver::new(&l), bound, name);
        println!("{name}: 10,000 steps, peak {peak:.2} m/s (bound {bound:.0})");
    }
}

/// Arrows at the edges of an open map (wind blowing in from the border, out of it, along
/// it, and a strong one out across it), 100 s each on a 100 × 100 m map at 1 m cells: no
/// cell ever faster than twice the arrow. The peaks (every 300 steps) are 11.9–14.1 m/s
/// from the 10 m/s arrows and 19.7 from the 20 m/s one; while confinement still pushed the
/// cells along open edges they were 26.7–44.8 and 194 (docs/RELIABILITY.md, "Findings").
#[test]
fn arrows_at_an_open_edge_keep_the_wind_near_their_strength() {
    for (what, points, strength, radius) in [
        (
            "in from the west edge",
            [[0.5, 50.0], [30.0, 50.0], [60.0, 50.0]],
            10.0,
            5.0,
        ),
        (
            "out of the east edge",
            [[40.0, 50.0], [70.0, 50.0], [99.5, 50.0]],
            10.0,
            5.0,
        ),
        (
            "along the north edge",
            [[5.0, 1.0], [50.0, 1.0], [95.0, 1.0]],
            10.0,
            5.0,
        ),
        (
            "out across the east edge",
            [[80.0, 50.0], [90.0, 50.0], [99.9, 50.0]],
            20.0,
            10.0,
        ),
    ] {
        let mut l = Layout::new("edge", [100.0, 100.0], [100, 100]);
        l.sim.boundary = Boundary::Open;
        l.trees.push(tree(1, chain(10, &points, strength, radius)));
        assert!(doc::validate(&l).is_empty(), "{:?}", doc::validate(&l));
        let peak = run_checked(&mut Solver::new(&l), 6000, 300, 2.0 * strength, what);
        println!("{what}: peak {peak:.1} m/s from {strength} m/s");
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
                    locked: false,
                    hidden: false,
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

/// The solver's fields hold no subnormal numbers: while the wind spreads into still air its
/// fronts (and later its decaying tails) would otherwise fill 2–4 % of a 1000² grid with
/// them, and on Intel cores every vector instruction that meets one takes a microcode
/// assist (`solver::flush`). The arrow examples through their first 40 steps at 300², with
/// both advection schemes and both pressure solves (without the flush, obstacles has 70
/// subnormal u faces after its second step).
#[test]
fn the_fields_hold_no_subnormal_numbers() {
    use doc::{Advection, PressureSolve};
    for name in ["obstacles.json", "two-winds.json", "branching.json"] {
        for advection in [Advection::SemiLagrangian, Advection::MacCormack] {
            for pressure in [PressureSolve::Jacobi, PressureSolve::Multigrid] {
                let mut l = example(name);
                l.world.grid = [300, 300];
                (l.sim.advection, l.sim.pressure) = (advection, pressure);
                let mut s = Solver::new(&l);
                for step in 1..=40 {
                    s.step();
                    for (field, values) in [("u", &s.u), ("v", &s.v), ("p", &s.p)] {
                        let n = values.iter().filter(|x| x.is_subnormal()).count();
                        assert_eq!(
                            n, 0,
                            "{name}, {advection:?}, {pressure:?}: {n} subnormal {field} values after step {step}"
                        );
                    }
                }
            }
        }
    }
}
