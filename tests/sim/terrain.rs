//! The level's ground shapes the wind (`docs/SOLVER.md`, "Terrain"): faster over crests,
//! slower in the lee, turned along valleys; over flat ground the wind is the 2D solve's, bit
//! for bit; and the GPU's terrain pass is the CPU's.

use super::*;
use windloom::doc::{AmbientKind, AmbientLayer, MaskImage, MaskPixels, Terrain};

/// A `w × h` 16-bit heightmap of `f(x, z)` (0 to 1, over the image's width and height),
/// written as a PNG into `dir` and read back through `io` as a layout would.
pub fn heightmap(dir: &Path, w: u32, h: u32, f: impl Fn(f32, f32) -> f32) -> MaskImage {
    let img = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_fn(w, h, |x, y| {
        let v = f((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
        image::Luma([(v.clamp(0.0, 1.0) * 65535.0).round() as u16])
    });
    img.save(dir.join("heights.png")).unwrap();
    windloom::io::load_mask(dir, "heights.png", "heightmap").unwrap()
}

/// A 400 × 200 m field of steady wind (`deg`, 5 m/s) on an open grid of 4 m cells.
fn breezy(deg: f32) -> Layout {
    let mut l = Layout::new("terrain", [400.0, 200.0], [100, 50]);
    l.obstacles.clear();
    l.trees.clear();
    l.sim.boundary = Boundary::Open;
    l.ambient = vec![AmbientLayer {
        id: 1,
        name: "breeze".into(),
        enabled: true,
        kind: AmbientKind::Directional {
            direction_deg: deg,
            main: 5.0,
            turbulence: 0.0,
            pulse_magnitude: 0.0,
            pulse_frequency: 0.0,
        },
        locked: false,
        hidden: false,
        keys: Vec::new(),
    }];
    l
}

fn with_terrain(l: &mut Layout, image: MaskImage, top: f32) {
    l.world.terrain = Some(Terrain {
        heightmap: "heights.png".into(),
        heights: [0.0, top],
        rect: None,
        strength: 1.0,
        feature_length: Some(20.0),
        pixels: MaskPixels::Loaded(std::sync::Arc::new(image)),
    });
}

fn speed(v: [f32; 2]) -> f32 {
    (v[0] * v[0] + v[1] * v[1]).sqrt()
}

/// A ridge 20 m high (σ = 40 m) across a 5 m/s wind: the crest at least 1.2× the wind
/// upstream, the steepest part of the lee at most 0.8×, while the solve itself stays flat.
#[test]
fn a_ridge_speeds_the_wind_over_its_crest_and_shelters_its_lee() {
    let dir = tempfile::tempdir().unwrap();
    let mut l = breezy(0.0);
    // Its crest along the centres of cell column 50, at x = 202 m.
    let ridge = |x: f32, _z: f32| (-((x * 400.0 - 202.0) / 40.0).powi(2)).exp();
    with_terrain(&mut l, heightmap(dir.path(), 800, 100, ridge), 20.0);
    let mut s = Solver::new(&l);
    run(&mut s, 12.0);
    let field = s.velocity_field();
    let at = |x: f32| field[25 * 100 + (x / 4.0) as usize];
    let (up, crest, lee) = (at(60.0), at(202.0), at(202.0 + 40.0 / 2f32.sqrt()));
    let (up, crest, lee) = (speed(up), speed(crest), speed(lee));
    eprintln!(
        "ridge: upstream {up:.2} m/s, crest {crest:.2} ({:.2}×), lee {lee:.2} ({:.2}×)",
        crest / up,
        lee / up
    );
    assert!(up > 4.0, "the breeze blows upstream: {up}");
    assert!(crest >= 1.2 * up, "crest {crest} vs upstream {up}");
    assert!(lee <= 0.8 * up, "lee {lee} vs upstream {up}");
    // The solve underneath is flat: the solver's own wind at the crest is the upstream's.
    let own = speed(s.cell_velocity(50, 25));
    assert!((own - up).abs() < 0.05 * up, "own {own} vs {up}");
    // At strength 0 the terrain is felt not at all.
    let mut calm = l.clone();
    calm.world.terrain.as_mut().unwrap().strength = 0.0;
    let mut c = Solver::new(&calm);
    run(&mut c, 12.0);
    let f0 = c.velocity_field();
    assert!((speed(f0[25 * 100 + 50]) - own).abs() < 1e-3);
}

/// A valley along z under a wind 45° across it: on the valley floor the wind turns to
/// within 20° of the valley's axis.
#[test]
fn a_valley_turns_the_wind_along_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut l = breezy(45.0);
    let valley = |x: f32, _z: f32| 1.0 - (-((x * 400.0 - 200.0) / 40.0).powi(2)).exp();
    with_terrain(&mut l, heightmap(dir.path(), 800, 100, valley), 20.0);
    let mut s = Solver::new(&l);
    run(&mut s, 12.0);
    let field = s.velocity_field();
    let angle = |v: [f32; 2]| v[0].abs().atan2(v[1].abs()).to_degrees();
    let (far, floor) = (field[25 * 100 + 12], field[25 * 100 + 50]);
    eprintln!(
        "valley: {:.1}° from its axis far away, {:.1}° on its floor",
        angle(far),
        angle(floor)
    );
    assert!((angle(far) - 45.0).abs() < 5.0, "far: {far:?}");
    assert!(angle(floor) < 20.0, "floor: {floor:?}");
    assert!(
        floor[1] > 0.0,
        "still blowing the wind's way along the valley"
    );
}

/// Flat terrain (one height everywhere) leaves today's wind exactly: the same bits as the
/// layout without terrain, arrows, obstacles and all.
#[test]
fn flat_terrain_is_the_wind_without_terrain_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let plain = example("meadow.json");
    let mut flat = plain.clone();
    with_terrain(&mut flat, heightmap(dir.path(), 64, 64, |_, _| 0.4), 30.0);
    let (mut a, mut b) = (Solver::new(&plain), Solver::new(&flat));
    run(&mut a, 2.0);
    run(&mut b, 2.0);
    let bits = |f: Vec<[f32; 2]>| f.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(a.velocity_field()), bits(b.velocity_field()));
    let (au, av) = a.wind_faces();
    let (bu, bv) = b.wind_faces();
    assert!(au == bu && av == bv);
    assert!(b.terrain.is_some());
}

/// A heightmap that cannot be read is named by the problems `validate` warns of and `bake`
/// refuses, with its field.
#[test]
fn an_unread_heightmap_is_named() {
    let text = r#"{"format": "windloom-layout", "version": 1, "name": "t",
        "world": {"size": [10, 10], "grid": [10, 10],
                  "terrain": {"heightmap": "hills.png", "heights": [0, 5]}}}"#;
    let l = doc::parse(text).unwrap();
    let p = doc::mask_problems(&l);
    assert!(
        p.len() == 1 && p[0].contains("world.terrain") && p[0].contains("hills.png"),
        "{p:?}"
    );
    let bad = text.replace("[0, 5]", "[5, 0]");
    let e = doc::parse(&bad).unwrap_err().to_string();
    assert!(e.contains("world.terrain.heights"), "{e}");
}

/// The GPU's terrain pass shapes a random field as the CPU does, to float rounding.
#[test]
fn the_gpu_terrain_pass_matches_the_cpu() {
    let Ok(ctx) = windloom::gpu::GpuContext::headless() else {
        eprintln!("SKIPPED: no GPU adapter for the terrain pass");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut l = breezy(30.0);
    l.world.grid = [61, 37];
    let hills = |x: f32, z: f32| {
        0.5 + 0.25 * (x * 9.0).sin() * (z * 7.0).cos() + 0.2 * (-((x - 0.6) * 8.0).powi(2)).exp()
    };
    with_terrain(&mut l, heightmap(dir.path(), 300, 200, hills), 25.0);
    // A rock, and closed walls: faces that must stay still whatever the terrain does.
    l.sim.boundary = Boundary::Closed;
    l.obstacles.push(doc::Obstacle {
        id: 7,
        name: "rock".into(),
        shape: Shape::Circle {
            center: [150.0, 100.0],
            radius: 30.0,
        },
        locked: false,
        hidden: false,
    });
    let mut cpu = Solver::new(&l);
    let (u, v) = cpu.faces_mut();
    u.copy_from_slice(
        &noise_field(u.len(), 3)
            .iter()
            .map(|x| 6.0 * x)
            .collect::<Vec<_>>(),
    );
    v.copy_from_slice(
        &noise_field(v.len(), 4)
            .iter()
            .map(|x| 6.0 * x)
            .collect::<Vec<_>>(),
    );
    let g = windloom::gpu::GpuSolver::from_solver(&ctx, &l, &cpu).unwrap();
    let (gu, gv) = g.wind_faces(&ctx).unwrap();
    let (cu, cv) = cpu.wind_faces();
    let worst = gu
        .iter()
        .zip(cu.iter())
        .chain(gv.iter().zip(cv.iter()))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    assert!(worst <= 1e-5 * 12.0, "largest difference {worst} m/s");
    let shaped = cu.iter().zip(&cpu.u).filter(|(a, b)| a != b).count();
    assert!(
        shaped > cu.len() / 2,
        "the hills shape most faces: {shaped}"
    );
    // Walls and the rock's sides stay still on both, and so do the rock's cells.
    let (uf, vf) = cpu.free_faces();
    for (k, f) in uf.iter().enumerate() {
        if *f == 0 {
            assert_eq!((cu[k], gu[k]), (0.0, 0.0), "u face {k}");
        }
    }
    for (k, f) in vf.iter().enumerate() {
        if *f == 0 {
            assert_eq!((cv[k], gv[k]), (0.0, 0.0), "v face {k}");
        }
    }
    let field = cpu.velocity_field();
    let rock = (0..field.len()).filter(|&k| cpu.solid[k] == 1);
    assert!(rock.clone().count() > 20);
    for k in rock {
        assert_eq!(field[k], [0.0, 0.0], "rock cell {k}");
    }
}
