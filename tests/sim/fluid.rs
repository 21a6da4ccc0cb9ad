//! The CPU solver behaves like a fluid: uniform flow, decaying energy, kept vortices, flow
//! around obstacles, sharper gusts with MacCormack.

use super::*;

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
    vortex_at([32.0, 32.0], Boundary::Periodic, vorticity)
}

/// A Gaussian vortex centred at `c` (cells) in a 64 × 64 box with `boundary`, peaking at
/// 5.15 m/s, in a layout whose wind is 8 m/s (an ambient layer that does not pull).
fn vortex_at(c: [f32; 2], boundary: Boundary, vorticity: f32) -> Solver {
    vortex_in_wind(c, boundary, vorticity, 8.0)
}

/// [`vortex_at`] in a layout whose wind (`forces::reference_speed`) is `wind` m/s.
fn vortex_in_wind(c: [f32; 2], boundary: Boundary, vorticity: f32, wind: f32) -> Solver {
    let mut l = Layout::new("vortex", [64.0, 64.0], [64, 64]);
    l.sim.boundary = boundary;
    l.sim.vorticity = vorticity;
    l.sim.ambient_coupling = 0.0;
    if wind > 0.0 {
        l.ambient.push(doc::AmbientLayer::new(
            1,
            "still",
            doc::AmbientKind::Directional {
                direction_deg: 0.0,
                main: wind,
                turbulence: 0.0,
                pulse_magnitude: 0.0,
                pulse_frequency: 0.0,
            },
        ));
    }
    assert_eq!(windloom::sim::forces::reference_speed(&l), wind);
    let mut s = Solver::new(&l);
    let (nx, ny) = (s.nx, s.ny);
    let omega = |x: f32, z: f32| {
        let (dx, dz) = (x - c[0], z - c[1]);
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

/// Confinement is bounded: it takes no face past the wind the layout sets
/// (`forces::reference_speed`), nor further past it than the face already is, however large
/// ε — a vortex peaking at 5.15 m/s in a layout of 3 m/s wind, at the largest ε the
/// validator accepts. With no wind set at all it turns nothing faster.
#[test]
fn confinement_takes_no_face_past_the_wind_the_layout_sets() {
    for wind in [3.0, 0.0] {
        let mut s = vortex_in_wind([32.0, 32.0], Boundary::Periodic, 1000.0, wind);
        let (u0, v0) = (s.u.clone(), s.v.clone());
        s.compute_curl();
        s.confine_vorticity(1.0 / 60.0);
        let mut moved = 0;
        for (new, old) in s.u.iter().zip(&u0).chain(s.v.iter().zip(&v0)) {
            let limit = old.abs().max(wind);
            assert!(
                new.abs() <= limit,
                "wind {wind}: {old} -> {new} (limit {limit})"
            );
            moved += usize::from(new != old);
        }
        assert!(
            moved > 100,
            "wind {wind}: confinement still turns the wind ({moved} faces)"
        );
    }
}

/// The vorticity factor's meaning (`solver::confinement_rate`): ε itself up to the knee (2,
/// the default; every example), then rising ever more slowly to the ceiling (5), so the
/// paper's 50 and the validator's 1,000 confine as hard as the liveliest sane setting and
/// no harder.
#[test]
fn the_vorticity_factor_saturates_at_the_ceiling() {
    use windloom::sim::solver::{CONFINEMENT_CEILING, CONFINEMENT_KNEE, confinement_rate};
    for eps in [0.0, 0.5, 1.0, 2.0] {
        assert_eq!(confinement_rate(eps), eps);
    }
    assert_eq!(CONFINEMENT_KNEE, 2.0);
    let mut last = 0.0;
    for k in 1..=10_000 {
        let eps = k as f32 * 0.1;
        let r = confinement_rate(eps);
        assert!(
            r >= last && r <= CONFINEMENT_CEILING,
            "ε {eps}: {r} after {last}"
        );
        last = r;
    }
    assert!((confinement_rate(3.0) - 2.964).abs() < 1e-3);
    assert!((confinement_rate(5.0) - 4.285).abs() < 1e-3);
    assert!(confinement_rate(50.0) > 0.999 * CONFINEMENT_CEILING);
}

/// On an open grid confinement pushes no cell along the edge: a vortex straddling the west
/// edge leaves the faces there (the u faces on the edge, the v faces of the edge column)
/// as they were, while one cell in it pushes, and on a closed grid the same v faces are
/// pushed. (An open edge's inflow keeps the edge's velocity, so a force there was fed back
/// into every later step's inflow; the 10,000-step test in `stability.rs` is what that did.)
#[test]
fn confinement_leaves_the_cells_along_an_open_edge_alone() {
    let at = [1.0, 32.0];
    let dt = 1.0 / 60.0;
    let mut open = vortex_at(at, Boundary::Open, 30.0);
    let (nx, ny) = (open.nx, open.ny);
    let (u0, v0) = (open.u.clone(), open.v.clone());
    open.compute_curl();
    assert!(
        open.curl[32 * nx].abs() > 1.0,
        "the edge cell spins: {}",
        open.curl[32 * nx]
    );
    open.confine_vorticity(dt);
    let edge_u = |u: &[f32]| (0..ny).map(|j| u[j * (nx + 1)]).collect::<Vec<_>>();
    let edge_v = |v: &[f32]| (0..=ny).map(|j| v[j * nx]).collect::<Vec<_>>();
    assert_eq!(edge_u(&open.u), edge_u(&u0), "u faces on the open edge");
    assert_eq!(edge_v(&open.v), edge_v(&v0), "v faces of the edge column");
    let moved = |a: &[f32], b: &[f32]| a.iter().zip(b).filter(|(x, y)| x != y).count();
    assert!(
        moved(&open.v, &v0) > 100,
        "the vortex one cell in is pushed"
    );

    let mut closed = vortex_at(at, Boundary::Closed, 30.0);
    let v1 = closed.v.clone();
    closed.compute_curl();
    closed.confine_vorticity(dt);
    assert!(
        moved(&edge_v(&closed.v), &edge_v(&v1)) > 10,
        "a closed grid's edge column is pushed"
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
        locked: false,
        hidden: false,
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
