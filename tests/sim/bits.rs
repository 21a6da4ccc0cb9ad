//! The fast passes give the reference's numbers bit for bit, whatever the thread count.

use super::*;

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
        // The reference twin solves the pressure by Jacobi; multigrid has its own tests
        // (`tests/sim/pressure.rs`).
        l.sim.pressure = doc::PressureSolve::Jacobi;
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

/// The splat gains the forces pass keeps across steps give the bits of the reference, which
/// computes every push afresh: with room for every splat, for none (`max_gain_bytes =
/// Some(0)`: computed each step) and for some only (the rest computed each step, the least
/// recently used dropped), while pulses switch the arrows on and off and an edit moves a
/// point (new gains for the arrows it ends and starts).
#[test]
fn kept_splat_gains_give_the_bits_of_computing_them() {
    let mut l = example("branching.json");
    l.world.grid = [90, 70];
    l.sim.pressure = doc::PressureSolve::Jacobi;
    l.trees[0].propagation_speed = 400.0;
    l.trees[0].emission = doc::Emission::Pulsed {
        period: 0.2,
        duty: 0.5,
    };
    let mut moved = l.clone();
    moved.trees[0].root.children[0].pos[1] += 7.0;
    let run = |s: &mut Solver, step: fn(&mut Solver)| {
        for k in 0..40 {
            if k == 25 {
                s.set_layout(&moved);
            }
            step(s);
        }
        s.state_bytes()
    };
    let want = run(&mut Solver::new(&l), Solver::step_reference);
    assert!(want.iter().any(|&b| b != 0), "the field moved");
    for budget in [None, Some(0), Some(12_000)] {
        let got = on_threads(2, || {
            let mut s = Solver::new(&l);
            s.max_gain_bytes = budget;
            run(&mut s, Solver::step)
        });
        let first = floats(&want).zip(floats(&got)).position(|(a, b)| a != b);
        assert!(
            first.is_none(),
            "gains kept in {budget:?} bytes: first differing value {first:?}"
        );
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

/// The ambient wind along a row (what the forces pass uses) is `Ambient::wind` point by point,
/// to the bit: every kind of layer, alone and stacked, for rows of faces from many to a
/// texel (runs of faces) to several texels or noise cells a face apart (face by face), rows
/// crossing the FFT tile's edge and starting at negative x, both components, at several
/// times; one scratch throughout, as a thread keeps it row after row (its cached lattice
/// gradients included); each row face by face and from the FFT tables a pass makes, which
/// are not used once the time or the row has changed.
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
    let (mut checked, mut tabled) = (0, 0);
    for l in &layouts {
        let mut ambient = forces::Ambient::new(l);
        // Face spacings from 40 faces a texel (1 m texels) to 2.5 texels a face, and 20 m
        // (noise lattices finer than the faces: their gradients are not cached).
        for spacing in [0.025f32, 0.2, 0.3, 0.7, 1.0, 2.5, 20.0] {
            for (x0, z) in [(0.0f32, 3.3), (-17.25, 40.1), (61.9, -2.0)] {
                let xs: Vec<f32> = (0..300).map(|i| x0 + i as f32 * spacing).collect();
                let mut row = vec![0.0; xs.len()];
                let mut stale = forces::FftTables::NONE;
                for t in [0.0, 1.7, 9.25] {
                    ambient.set_time(t);
                    // Face by face, from FFT tables made for 400 rows 5 cm apart around this
                    // one (as a pass at 1000² over 50 m makes them), and from the tables of
                    // the time before, which must not be used.
                    let zs: Vec<f32> = (0..400).map(|i| z + (i - 200) as f32 * 0.05).collect();
                    let tables = ambient.fft_tables(&xs, zs.iter().copied());
                    tabled += tables.count();
                    for tables in [&forces::FftTables::NONE, &tables, &stale] {
                        for c in 0..2 {
                            ambient.component_row(c, z, &xs, tables, &mut row, &mut scratch);
                            for (k, &x) in xs.iter().enumerate() {
                                let want = ambient.wind([x, z])[c];
                                assert!(
                                    row[k].to_bits() == want.to_bits(),
                                    "{}: spacing {spacing}, x {x}, z {z}, t {t}, component {c}, \
                                     {} tables: row {} vs wind {want}",
                                    l.name,
                                    tables.count(),
                                    row[k]
                                );
                                checked += 1;
                            }
                        }
                    }
                    // Rows the tables were not made for (shorter; as long, but moved along x)
                    // sample the field themselves.
                    let moved: Vec<f32> = xs.iter().map(|x| x + 0.3 * spacing).collect();
                    for other in [&xs[..150], &moved[..]] {
                        let n = other.len();
                        ambient.component_row(0, z, other, &tables, &mut row[..n], &mut scratch);
                        for (k, &x) in other.iter().enumerate() {
                            assert_eq!(row[k].to_bits(), ambient.wind([x, z])[0].to_bits());
                        }
                    }
                    stale = tables;
                }
            }
        }
    }
    assert_eq!(checked, 3 * 7 * 3 * 300 * 3 * 2 * 3);
    // breeze-fft's layer, and the stacked layouts' one, at every spacing, place and time.
    assert_eq!(tabled, 2 * 7 * 3 * 3, "FFT layers get tables");
}

/// The advection samplers read a face's neighbourhood as whole rows where the departure
/// point lies within a cell of the face, and point by point elsewhere (farther points, the
/// row ends, the first and last rows, a period's seam). Both must give the reference's bits:
/// a flow of slow smooth wind (most faces local) with a band of fast noise (points up to
/// three cells away) and a rim of flow across each edge (points off the field or across a
/// period's seam: into it at 1.6 cells a step at the low edges, out of it at 0.6 at the
/// high ones), every boundary, both schemes, 1–3 threads; and the same on grids of a few
/// cells, where the row loop's window and rim leave few faces or none to it.
#[test]
fn advection_matches_the_reference_near_and_far() {
    use doc::Advection::{MacCormack, SemiLagrangian};
    for [nx, nz] in [[67, 45], [3, 2], [4, 4], [5, 3], [7, 6]] {
        for boundary in [Boundary::Open, Boundary::Closed, Boundary::Periodic] {
            for advection in [SemiLagrangian, MacCormack] {
                let mut l = example("obstacles.json");
                l.world.grid = [nx, nz];
                l.sim.boundary = boundary;
                l.sim.advection = advection;
                let seeded = || {
                    let mut s = noisy_solver(&l, (11, 12), 1.0);
                    let dt = s.params.dt;
                    let cells = [
                        l.world.size[0] / nx as f32 / dt,
                        l.world.size[1] / nz as f32 / dt,
                    ];
                    let (u, v) = s.faces_mut();
                    for (c, f) in [u, v].into_iter().enumerate() {
                        let h = nz as usize + c;
                        let w = f.len() / h;
                        // Along the face's own axis, from the low and the high edge.
                        let rim = |t: f32, n: usize| {
                            if t < 2.0 {
                                1.6
                            } else if t > n as f32 - 3.0 {
                                -0.6
                            } else {
                                0.0
                            }
                        };
                        for (k, x) in f.iter_mut().enumerate() {
                            let (i, j) = ((k % w) as f32, (k / w) as f32);
                            let smooth = 0.8 * (0.21 * i + 0.13 * j + c as f32).sin();
                            let band = if (20.0..26.0).contains(&j) {
                                3.0 * *x
                            } else {
                                0.0
                            };
                            let rim = if c == 0 { rim(i, w) } else { rim(j, h) };
                            *x = (smooth + band + rim) * cells[c];
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
                    let cell = l.world.size[0] / nx as f32 / dt;
                    s.u.iter().filter(|&&u| (u.abs() >= cell) == far).count()
                };
                assert!(
                    nx < 67 || speeds(&want, true) > 50 && speeds(&want, false) > 1000,
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
                        "{nx}x{nz} {boundary:?} {advection:?}, {threads} threads: \
                     first differing value {first:?}"
                    );
                }
            }
        }
    }
}
