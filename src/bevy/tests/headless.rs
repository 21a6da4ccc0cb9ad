//! A headless Bevy app (no window, no renderer) with the plugin: every entity's sampled wind
//! is the raw bake's at its cell and the game's clock from the frame it is spawned, where it
//! stands after a move (its own or its parent's) that frame, and a re-bake into the folder
//! is picked up off the game's thread and answered with; a missing bake is no panic.
//!
//! It bakes with the windloom binary: `WINDLOOM_BIN`, else the newest `windloom` under the
//! workspace's `target/` (CI sets `WINDLOOM_BIN`).
#![allow(
    clippy::unwrap_used,
    reason = "a test that unwraps fails there, which is what a test is for"
)]

use bevy::app::App;
use bevy::ecs::message::Messages;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;
use windloom_bevy::{Wind, WindReloaded, WindSample, WindloomPlugin};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn windloom() -> PathBuf {
    if let Some(p) = std::env::var_os("WINDLOOM_BIN") {
        return PathBuf::from(p);
    }
    ["ci", "release", "debug"]
        .iter()
        .map(|p| root().join("target").join(p).join("windloom"))
        .filter(|p| p.exists())
        .max_by_key(|p| p.metadata().and_then(|m| m.modified()).ok())
        .expect("no windloom binary: build it (cargo build --bin windloom) or set WINDLOOM_BIN")
}

fn bake(layout: &str, out: &Path) {
    let status = Command::new(windloom())
        .arg("bake")
        .arg(root().join("layouts").join(layout))
        .arg("--out")
        .arg(out)
        .args(["--format", "raw", "--frames", "4", "--fps", "10"])
        .args(["--warmup", "1.5", "--grid", "48x32"])
        .status()
        .unwrap();
    assert!(status.success(), "windloom bake {layout}");
}

/// The raw frames, and what the manifest says of them.
struct Raw {
    nx: usize,
    ny: usize,
    min: [f32; 2],
    cell: [f32; 2],
    fps: f32,
    height: f32,
    frames: Vec<f32>,
}

impl Raw {
    fn read(dir: &Path) -> Raw {
        let text = std::fs::read_to_string(dir.join("manifest.json")).unwrap();
        let m: serde_json::Value = serde_json::from_str(&text).unwrap();
        let f = |v: &serde_json::Value| v.as_f64().unwrap() as f32;
        let (nx, ny) = (
            m["grid"][0].as_u64().unwrap() as usize,
            m["grid"][1].as_u64().unwrap() as usize,
        );
        let bytes = std::fs::read(dir.join("wind.f32")).unwrap();
        let frames: Vec<f32> = bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        assert_eq!(frames.len(), 4 * nx * ny * 2);
        Raw {
            nx,
            ny,
            min: [f(&m["world"]["min"][0]), f(&m["world"]["min"][1])],
            cell: [
                f(&m["world"]["cell_size"][0]),
                f(&m["world"]["cell_size"][1]),
            ],
            fps: f(&m["frames"]["fps"]),
            height: f(&m["profile"]["reference_height"]),
            frames,
        }
    }

    /// The wind at cell (i, j) at `t` seconds: frames blended linearly, the last held.
    fn at(&self, i: usize, j: usize, t: f32) -> Vec3 {
        let f = (t * self.fps).clamp(0.0, 3.0);
        let k = (f as usize).min(2);
        let w = f - k as f32;
        let v = |k: usize, c: usize| self.frames[((k * self.ny + j) * self.nx + i) * 2 + c];
        let mix = |c: usize| v(k, c) + (v(k + 1, c) - v(k, c)) * w;
        Vec3::new(mix(0), 0.0, mix(1))
    }

    fn centre(&self, i: usize, j: usize) -> Vec3 {
        Vec3::new(
            self.min[0] + (i as f32 + 0.5) * self.cell[0],
            self.height,
            self.min[1] + (j as f32 + 0.5) * self.cell[1],
        )
    }
}

fn check(app: &mut App, raw: &Raw, cells: &[(Entity, usize, usize)]) -> usize {
    let t = app.world().resource::<Time>().elapsed_secs();
    let mut checked = 0;
    for &(e, i, j) in cells {
        let got = app.world().get::<WindSample>(e).unwrap().wind;
        let want = raw.at(i, j, t);
        assert!(
            (got - want).abs().max_element() <= 1e-4 * (1.0 + want.abs().max_element()),
            "cell ({i}, {j}) at {t} s: sampled {got}, raw {want}"
        );
        checked += 1;
    }
    checked
}

#[test]
fn entities_sample_the_baked_wind_and_a_re_bake_reloads() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bake");
    bake("two-winds.json", &out);
    let raw = Raw::read(&out);

    let mut app = App::new();
    app.add_plugins((MinimalPlugins, bevy::transform::TransformPlugin))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_millis(
            35,
        )))
        .add_plugins(WindloomPlugin {
            poll_every: Some(Duration::from_millis(70)),
            ..WindloomPlugin::new(&out)
        });
    let cells: Vec<(Entity, usize, usize)> = (0..raw.ny)
        .step_by(3)
        .flat_map(|j| (0..raw.nx).step_by(5).map(move |i| (i, j)))
        .map(|(i, j)| {
            let e = app
                .world_mut()
                .spawn((
                    Transform::from_translation(raw.centre(i, j)),
                    WindSample::default(),
                ))
                .id();
            (e, i, j)
        })
        .collect();
    // From the first frame on (before transforms propagate), every sample is the bake's
    // wind at the entity and the clock, between frames and past the last.
    let mut checked = 0;
    for _ in 0..12 {
        app.update();
        checked += check(&mut app, &raw, &cells);
    }
    assert!(checked > 1000);
    assert_eq!(app.world().resource::<Wind>().bake().unwrap().sequence(), 1);

    // A re-bake of another level into the folder: picked up, announced, answered with.
    bake("branching.json", &out);
    let new = Raw::read(&out);
    // Read on the plugin's own thread, every 70 ms of real time: frames go on meanwhile.
    let mut reloaded = None;
    for _ in 0..250 {
        std::thread::sleep(Duration::from_millis(20));
        app.update();
        let messages = app.world().resource::<Messages<WindReloaded>>();
        if let Some(m) = messages.iter_current_update_messages().last() {
            reloaded = Some(*m);
            break;
        }
    }
    assert_eq!(reloaded, Some(WindReloaded { sequence: 2 }));
    // The new level covers another rectangle: the entities move to its cells.
    for &(e, i, j) in &cells {
        app.world_mut().get_mut::<Transform>(e).unwrap().translation = new.centre(i, j);
    }
    app.update();
    app.update();
    assert!(check(&mut app, &new, &cells) > 100);
    assert!(app.world().resource::<Wind>().last_error().is_none());
}

fn app_on(folder: &Path, poll_every: Option<Duration>) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, bevy::transform::TransformPlugin))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_millis(
            35,
        )))
        .add_plugins(WindloomPlugin {
            poll_every,
            ..WindloomPlugin::new(folder)
        });
    app
}

/// Where an entity stands the frame it moves: a system ordered before the sample moves a
/// plain entity and the parent of another, and both read the wind where they now stand
/// (it read last frame's place, or the origin on an entity's first frame).
#[test]
fn the_wind_is_where_the_entity_stands_this_frame() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bake");
    bake("two-winds.json", &out);
    let raw = Raw::read(&out);
    let mut app = app_on(&out, None);
    /// Walks from its start cell, 3 cells along x and 1 along z a frame.
    #[derive(Component)]
    struct Walker((usize, usize));
    #[derive(Resource)]
    struct Step(usize);
    let (a, b) = ((5usize, 7usize), (30usize, 20usize));
    let at = |c: (usize, usize), k: usize| ((c.0 + 3 * k) % raw.nx, (c.1 + k) % raw.ny);
    let walk = {
        let raw_centre = {
            let r = Raw::read(&out);
            move |c: (usize, usize)| r.centre(c.0, c.1)
        };
        move |mut step: ResMut<Step>, mut q: Query<(&mut Transform, &Walker)>| {
            step.0 += 1;
            for (mut t, w) in &mut q {
                let c = ((w.0.0 + 3 * step.0) % 48, (w.0.1 + step.0) % 32);
                t.translation = raw_centre(c);
            }
        }
    };
    app.insert_resource(Step(0))
        .add_systems(Update, walk.before(windloom_bevy::WindSystems::Sample));
    // A plain walker, and a parent walker carrying a child with no offset of its own but
    // height (its parent stands at the reference height already; the child adds 0).
    let plain = app
        .world_mut()
        .spawn((Transform::default(), WindSample::default(), Walker(a)))
        .id();
    let parent = app
        .world_mut()
        .spawn((Transform::default(), Walker(b)))
        .id();
    let child = app
        .world_mut()
        .spawn((Transform::default(), WindSample::default(), ChildOf(parent)))
        .id();
    for k in 1..=6 {
        app.update();
        let t = app.world().resource::<Time>().elapsed_secs();
        for (e, start) in [(plain, a), (child, b)] {
            let (i, j) = at(start, k);
            let got = app.world().get::<WindSample>(e).unwrap().wind;
            let want = raw.at(i, j, t);
            assert!(
                (got - want).abs().max_element() <= 1e-4 * (1.0 + want.abs().max_element()),
                "frame {k}, cell ({i}, {j}): sampled {got}, the wind there {want}"
            );
        }
    }
}

/// A missing bake is no panic: the game runs with no wind, says why, and picks the bake
/// up once it lands.
#[test]
fn a_missing_bake_runs_without_wind_until_one_lands() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bake");
    let mut app = app_on(&out, Some(Duration::from_millis(50)));
    let e = app
        .world_mut()
        .spawn((Transform::from_xyz(10.0, 2.0, 10.0), WindSample::default()))
        .id();
    app.update();
    let wind = app.world().resource::<Wind>();
    assert!(wind.bake().is_none());
    assert!(
        wind.last_error()
            .is_some_and(|e| e.contains("manifest.json")),
        "{:?}",
        wind.last_error()
    );
    assert_eq!(app.world().get::<WindSample>(e).unwrap().wind, Vec3::ZERO);
    bake("two-winds.json", &out);
    let mut landed = false;
    for _ in 0..250 {
        std::thread::sleep(Duration::from_millis(20));
        app.update();
        if app.world().resource::<Wind>().bake().is_some() {
            landed = true;
            break;
        }
    }
    assert!(landed, "the bake that landed was never read");
    app.update();
    assert_ne!(app.world().get::<WindSample>(e).unwrap().wind, Vec3::ZERO);
    assert!(app.world().resource::<Wind>().last_error().is_none());
}
