//! A bake of a level with terrain carries the terrain-shaped wind and the ground itself,
//! `heights.png`, decoded by the manifest's `terrain` block alone, and bakes again over
//! itself; a bake whose heightmap cannot be read is refused.

use super::*;
use windloom::doc::{AmbientKind, AmbientLayer, MaskPixels, Terrain};

/// A 200 × 100 m level with a 5 m/s breeze along +x over a ridge 16 m high at x = 102 m,
/// its heightmap written into `dir`.
fn ridge_level(dir: &Path) -> Layout {
    let mut l = Layout::new("ridge", [200.0, 100.0], [50, 25]);
    l.obstacles.clear();
    l.trees.clear();
    l.sim.boundary = windloom::doc::Boundary::Open;
    l.ambient = vec![AmbientLayer {
        id: 1,
        name: "breeze".into(),
        enabled: true,
        kind: AmbientKind::Directional {
            direction_deg: 0.0,
            main: 5.0,
            turbulence: 0.0,
            pulse_magnitude: 0.0,
            pulse_frequency: 0.0,
        },
        locked: false,
        hidden: false,
        keys: Vec::new(),
    }];
    let img = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_fn(400, 50, |x, _| {
        let m = (x as f32 + 0.5) / 2.0;
        image::Luma([((-((m - 102.0) / 20.0).powi(2)).exp() * 65535.0).round() as u16])
    });
    img.save(dir.join("ridge.png")).unwrap();
    l.world.terrain = Some(Terrain {
        heightmap: "ridge.png".into(),
        heights: [-4.0, 12.0],
        rect: None,
        strength: 1.0,
        feature_length: Some(10.0),
        pixels: MaskPixels::Loaded(std::sync::Arc::new(
            windloom::io::load_mask(dir, "ridge.png", "heightmap").unwrap(),
        )),
    });
    l
}

#[test]
fn a_bake_carries_the_terrain_shaped_wind_and_its_heights() {
    let src = tempfile::tempdir().unwrap();
    let l = ridge_level(src.path());
    let out = tempfile::tempdir().unwrap();
    let dir = out.path().join("bake");
    let opts = BakeOptions {
        formats: vec![Format::Raw],
        warmup: 8.0,
        frames: 1,
        grid: None,
        ..small(1)
    };
    run(&l, &dir, &opts);
    let m = manifest(&dir);
    let t = &m["terrain"];
    assert_eq!(t["file"], "heights.png");
    assert_eq!(t["units"], "m");
    assert_eq!(t["sample"], "unorm16");
    // Decoded by the manifest alone: row j, column i is cell (i, j)'s centre.
    let img = image::open(dir.join("heights.png")).unwrap().into_luma16();
    assert_eq!((img.width(), img.height()), (50, 25));
    let (scale, offset) = (t["scale"].as_f64().unwrap(), t["offset"].as_f64().unwrap());
    let height = |i: u32, j: u32| f64::from(img.get_pixel(i, j)[0]) / 65535.0 * scale + offset;
    assert!(
        (height(25, 12) - 12.0).abs() < 0.3,
        "crest {}",
        height(25, 12)
    );
    assert!((height(0, 3) + 4.0).abs() < 0.01, "foot {}", height(0, 3));
    assert_eq!(t["axes"][1]["world"], "+z");
    // The wind in the bake is the shaped one: faster on the crest than upstream.
    let raw = Raw::read(&dir, &m);
    let speed = |v: [f32; 2]| (v[0] * v[0] + v[1] * v[1]).sqrt();
    let (up, crest) = (speed(raw.at(0, 5, 12)), speed(raw.at(0, 25, 12)));
    assert!(crest > 1.15 * up, "crest {crest} m/s, upstream {up} m/s");
    assert!(
        m["files"]
            .as_array()
            .unwrap()
            .iter()
            .all(|f| f["name"] != "heights.png"),
        "heights are the terrain block's, not a wind file"
    );
    // A re-bake into the folder replaces the heights with the rest, the user's file kept
    // (the first bake's heights.png is the bake's, not the user's).
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    run(&l, &dir, &opts);
    assert_eq!(manifest(&dir)["sequence"], 2);
    assert!(dir.join("heights.png").is_file());
    assert_eq!(
        std::fs::read_to_string(dir.join("notes.txt")).unwrap(),
        "mine"
    );
}

#[test]
fn a_bake_refuses_a_heightmap_it_cannot_read() {
    let src = tempfile::tempdir().unwrap();
    let mut l = ridge_level(src.path());
    l.world.terrain.as_mut().unwrap().pixels =
        windloom::io::grey_pixels(src.path(), "gone.png", "heightmap");
    let out = tempfile::tempdir().unwrap();
    let dir = out.path().join("bake");
    let e = bake::bake(
        &l,
        &dir,
        &small(1),
        &AtomicBool::new(false),
        &mut |_, _, _| {},
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("world.terrain") && e.contains("gone.png"), "{e}");
    assert!(!dir.exists(), "nothing written");
}
