//! Obstacles from a level's collision mask: the image's dark pixels become solid cells by the
//! same coverage rule as the drawn shapes, wherever the mask is placed, and the wind flows
//! around them on the CPU as on the GPU.

use super::*;
use windloom::doc::{MaskImage, MaskPixels};

/// A `w × h` mask: black (solid) where `solid(x, y)`, white elsewhere, written as an 8-bit
/// PNG into `dir` and read back through `io` as a layout would.
fn mask_file(
    dir: &Path,
    name: &str,
    w: u32,
    h: u32,
    solid: impl Fn(u32, u32) -> bool,
) -> MaskImage {
    let img = image::GrayImage::from_fn(w, h, |x, y| {
        image::Luma([if solid(x, y) { 0 } else { 255 }])
    });
    img.save(dir.join(name)).unwrap();
    windloom::io::load_mask(dir, name, "mask image").unwrap()
}

fn with_mask(l: &mut Layout, image: MaskImage, rect: Option<[[f32; 2]; 2]>, invert: bool) {
    l.obstacles.push(doc::Obstacle {
        id: 99,
        name: "level".into(),
        shape: Shape::Mask {
            image: "mask.png".into(),
            threshold: 0.5,
            invert,
            rect,
            pixels: MaskPixels::Loaded(std::sync::Arc::new(image)),
        },
        locked: false,
        hidden: false,
    });
}

/// A mask drawing a square makes the same solid cells as a polygon of that square; inverted,
/// the other cells; placed over half the world, the square lands where the rectangle says.
#[test]
fn a_mask_makes_the_cells_a_shape_of_its_dark_pixels_would() {
    let dir = tempfile::tempdir().unwrap();
    let mut base = Layout::new("mask", [100.0, 100.0], [50, 50]);
    base.obstacles.clear();
    // 200 px over 100 m: the square [30, 60] × [40, 70] m is pixels [60, 120) × [80, 140).
    let image = mask_file(dir.path(), "mask.png", 200, 200, |x, y| {
        (60..120).contains(&x) && (80..140).contains(&y)
    });
    let mut masked = base.clone();
    with_mask(&mut masked, image.clone(), None, false);
    let mut drawn = base.clone();
    drawn.obstacles.push(doc::Obstacle {
        id: 1,
        name: "square".into(),
        shape: Shape::Polygon {
            points: vec![[30.0, 40.0], [60.0, 40.0], [60.0, 70.0], [30.0, 70.0]],
        },
        locked: false,
        hidden: false,
    });
    let solid = windloom::sim::obstacles::rasterize(&masked);
    assert_eq!(solid, windloom::sim::obstacles::rasterize(&drawn));
    assert_eq!(solid.iter().filter(|&&s| s == 1).count(), 15 * 15);
    let mut inverted = base.clone();
    with_mask(&mut inverted, image.clone(), None, true);
    let inv = windloom::sim::obstacles::rasterize(&inverted);
    assert!(
        solid.iter().zip(&inv).all(|(a, b)| a + b == 1),
        "inverted: the other cells"
    );
    // Over [50, 100] × [0, 50] m only: the square at [65, 80] × [20, 35] m.
    let mut placed = base.clone();
    with_mask(
        &mut placed,
        image,
        Some([[50.0, 0.0], [100.0, 50.0]]),
        false,
    );
    let s = windloom::sim::obstacles::rasterize(&placed);
    let at = |x: f32, z: f32| s[(z / 2.0) as usize * 50 + (x / 2.0) as usize];
    assert_eq!(at(70.0, 25.0), 1);
    assert_eq!((at(40.0, 55.0), at(60.0, 10.0), at(90.0, 45.0)), (0, 0, 0));
    // 7.5 cells a side: the half-covered edge cells are solid (the rule is at least half),
    // the corner cell, a quarter covered, is not.
    assert_eq!(s.iter().filter(|&&c| c == 1).count(), 8 * 8 - 1);
}

/// A mask that is not loaded (a layout built from text, or a file that could not be read)
/// adds no solid cell and is named by `mask_problems`; an EXR mask reads as its luminance.
#[test]
fn an_unread_mask_is_named_and_an_exr_mask_reads_its_luminance() {
    let dir = tempfile::tempdir().unwrap();
    let text = r#"{"format": "windloom-layout", "version": 1, "name": "m",
        "world": {"size": [10, 10], "grid": [10, 10]},
        "obstacles": [{"id": 1, "name": "walls", "shape": {"kind": "mask", "image": "walls.png"}}]}"#;
    let parsed = doc::parse(text).unwrap();
    assert!(
        windloom::sim::obstacles::rasterize(&parsed)
            .iter()
            .all(|&s| s == 0)
    );
    let problems = doc::mask_problems(&parsed);
    assert_eq!(problems.len(), 1);
    assert!(problems[0].contains("obstacles[0] \"walls\"") && problems[0].contains("walls.png"));
    // Through io, a missing file is the reason, with its path.
    let file = dir.path().join("level.json");
    std::fs::write(&file, text).unwrap();
    let loaded = windloom::io::load(&file).unwrap();
    let p = doc::mask_problems(&loaded);
    assert!(
        p[0].contains("mask image") && p[0].contains("walls.png"),
        "{p:?}"
    );
    // An EXR: left half dark (0.2), right half bright (0.8).
    use exr::prelude::*;
    let pixels = SpecificChannels::rgb(|p: Vec2<usize>| {
        let l = if p.x() < 8 { 0.2f32 } else { 0.8 };
        (l, l, l)
    });
    Image::from_channels((16, 4), pixels)
        .write()
        .to_file(dir.path().join("walls.exr"))
        .unwrap();
    let m = windloom::io::load_mask(dir.path(), "walls.exr", "mask image").unwrap();
    assert_eq!((m.width, m.height), (16, 4));
    assert!(m.solid_at(0.1, 0.5, 0.5, false) && !m.solid_at(0.9, 0.5, 0.5, false));
    assert!((f32::from(m.luminance[0]) / 65535.0 - 0.2).abs() < 1e-3);
}

/// The wind goes around a mask's building: zero in its cells, and the CPU and GPU solvers
/// see the same solid cells.
#[test]
fn the_wind_flows_around_a_mask_on_the_cpu_and_the_gpu() {
    let dir = tempfile::tempdir().unwrap();
    let mut l = example("meadow.json");
    l.world.grid = [60, 40];
    // A block in the middle of the level, a fifth of it across.
    let image = mask_file(dir.path(), "mask.png", 100, 100, |x, y| {
        (40..60).contains(&x) && (40..60).contains(&y)
    });
    with_mask(&mut l, image, None, false);
    let mut s = Solver::new(&l);
    run(&mut s, 3.0);
    let solid = &s.solid;
    assert!(solid.iter().filter(|&&c| c == 1).count() >= 12 * 8);
    let field = s.velocity_field();
    for (k, v) in field.iter().enumerate() {
        if solid[k] == 1 {
            assert_eq!(*v, [0.0, 0.0], "cell {k} inside the block");
        }
    }
    // The GPU solver, from the same layout, keeps the block's cells still too.
    if let Ok(ctx) = windloom::gpu::GpuContext::headless() {
        let mut g = windloom::gpu::GpuSolver::new(&ctx, &l).unwrap();
        for _ in 0..30 {
            g.step(&ctx);
        }
        let v = g.velocity_field(&ctx).unwrap();
        for (k, v) in v.iter().enumerate() {
            if solid[k] == 1 {
                assert_eq!(*v, [0.0, 0.0], "GPU cell {k} inside the block");
            }
        }
        assert!(
            v.iter().any(|v| v[0] != 0.0),
            "the GPU's wind blows elsewhere"
        );
    }
}

/// Grass where the level has grass: a density map's black third grows none, its grey third
/// about half, its white third all; an all-white map changes no blade at all.
#[test]
fn a_density_map_thins_the_grass_where_the_level_has_none() {
    let dir = tempfile::tempdir().unwrap();
    let mut l = Layout::new("lawn", [90.0, 30.0], [45, 15]);
    l.obstacles.clear();
    l.grass.density = 8.0;
    let img = image::GrayImage::from_fn(90, 10, |x, _| {
        image::Luma([match x / 30 {
            0 => 0,
            1 => 128,
            _ => 255,
        }])
    });
    img.save(dir.path().join("grass.png")).unwrap();
    let map = |name: &str| doc::DensityMap {
        image: name.into(),
        rect: None,
        pixels: MaskPixels::Loaded(std::sync::Arc::new(
            windloom::io::load_mask(dir.path(), name, "density map").unwrap(),
        )),
    };
    let all = windloom::grass::scatter(&l);
    let mut thinned = l.clone();
    thinned.grass.density_map = Some(map("grass.png"));
    let some = windloom::grass::scatter(&thinned);
    let third = |b: &[windloom::grass::Blade], k: f32| {
        b.iter()
            .filter(|b| b.pos[0] >= 30.0 * k && b.pos[0] < 30.0 * (k + 1.0))
            .count()
    };
    let full = third(&all, 1.0) as f64;
    assert!(full > 5000.0, "{full}");
    assert_eq!(third(&some, 0.0), 0, "none on black");
    assert_eq!(third(&some, 2.0), third(&all, 2.0), "all on white");
    let grey = third(&some, 1.0) as f64 / full;
    assert!((grey - 128.0 / 255.0).abs() < 0.03, "grey keeps {grey}");
    // Each kept blade is the blade the layout without a map has there.
    assert!(some.iter().all(|b| all.contains(b)));
    let white = image::GrayImage::from_pixel(4, 4, image::Luma([255]));
    white.save(dir.path().join("white.png")).unwrap();
    let mut lawn = l.clone();
    lawn.grass.density_map = Some(map("white.png"));
    assert_eq!(windloom::grass::scatter(&lawn), all);
    // Unread, the map is a warning and the grass grows everywhere.
    let mut unread = l.clone();
    unread.grass.density_map = Some(doc::DensityMap {
        image: "gone.png".into(),
        rect: None,
        pixels: MaskPixels::NotLoaded,
    });
    assert_eq!(windloom::grass::scatter(&unread), all);
    assert!(
        doc::density_map_problem(&unread)
            .unwrap()
            .contains("gone.png")
    );
}

/// A mask's solid area as the views draw it: rectangles that cover exactly its solid samples,
/// a straight wall one rectangle (not one per row, which showed seams in the 3D view).
#[test]
fn a_mask_s_solid_area_is_few_rectangles_covering_exactly_its_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let image = mask_file(dir.path(), "mask.png", 40, 40, |x, y| {
        (10..14).contains(&x) || ((20..30).contains(&x) && (5..15).contains(&y))
    });
    let mut l = Layout::new("walls", [40.0, 40.0], [40, 40]);
    l.obstacles.clear();
    with_mask(&mut l, image, None, false);
    let runs = l.obstacles[0].shape.mask_runs(l.bounds(), 512);
    assert_eq!(runs.len(), 2, "{runs:?}");
    let area: f32 = runs
        .iter()
        .map(|[a, b]| (b[0] - a[0]) * (b[1] - a[1]))
        .sum();
    assert_eq!(area, 4.0 * 40.0 + 10.0 * 10.0);
    for x in 0..40 {
        for z in 0..40 {
            let p = [x as f32 + 0.5, z as f32 + 0.5];
            let drawn = runs
                .iter()
                .any(|[a, b]| p[0] > a[0] && p[0] < b[0] && p[1] > a[1] && p[1] < b[1]);
            assert_eq!(
                drawn,
                l.obstacles[0].shape.mask_contains(p, l.bounds()),
                "{p:?}"
            );
        }
    }
}
