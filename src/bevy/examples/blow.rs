//! Leaves blown around a level by its baked wind, headless: 400 leaves start in a grid over
//! the bake, 1 m up; each frame they drift toward the wind at their position (the plugin's
//! `WindSample`), and every simulated second a map of where they are is printed, with the
//! bake's rectangle as its frame. A re-bake into the folder (`windloom bake --watch`, the
//! editor's Live export) blows them differently from the next poll on.
//!
//! ```sh
//! windloom bake layouts/two-winds.json --out bake --frames 48 --loop
//! cargo run -p windloom-bevy --example blow -- bake 10
//! ```
//! (the folder, and the seconds to run: default `bake` and 10).

use bevy::app::{AppExit, ScheduleRunnerPlugin};
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use std::time::Duration;
use windloom_bevy::{Wind, WindReloaded, WindSample, WindSystems, WindloomPlugin};

/// A leaf's velocity, m/s.
#[derive(Component, Default)]
struct Leaf(Vec3);

#[derive(Resource)]
struct Run {
    seconds: f32,
    /// The last whole second printed.
    printed: Option<u32>,
}

const COLUMNS: usize = 72;
const ROWS: usize = 24;

fn main() {
    let mut args = std::env::args().skip(1);
    let folder = args.next().unwrap_or_else(|| "bake".into());
    let seconds = args
        .next()
        .map_or(10.0, |s| s.parse().expect("seconds: a number"));
    App::new()
        .add_plugins(
            MinimalPlugins.set(ScheduleRunnerPlugin::run_loop(Duration::from_secs_f64(0.0))),
        )
        .add_plugins(bevy::transform::TransformPlugin)
        // 60 frames a simulated second, as fast as the CPU runs them.
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
            1.0 / 60.0,
        )))
        .insert_resource(Run {
            seconds,
            printed: None,
        })
        .add_plugins(WindloomPlugin::new(folder))
        .add_systems(Startup, scatter)
        .add_systems(Update, (blow.after(WindSystems::Sample), show, announce))
        .run();
}

fn scatter(mut commands: Commands, wind: Res<Wind>) {
    // No bake (missing or broken: the plugin logged why), no leaves.
    let Some(bake) = wind.bake() else {
        return;
    };
    let (min, max) = bake.bounds();
    for a in 0..20 {
        for b in 0..20 {
            let x = min[0] + (a as f32 + 0.5) / 20.0 * (max[0] - min[0]);
            let z = min[1] + (b as f32 + 0.5) / 20.0 * (max[1] - min[1]);
            let y = bake.ground_at(x, z) + 1.0;
            commands.spawn((
                Transform::from_xyz(x, y, z),
                WindSample::default(),
                Leaf::default(),
            ));
        }
    }
}

/// A leaf takes the wind's velocity over about half a second (drag), and rides it.
fn blow(
    time: Res<Time>,
    wind: Res<Wind>,
    mut leaves: Query<(&mut Transform, &mut Leaf, &WindSample)>,
) {
    let dt = time.delta_secs();
    let Some(bake) = wind.bake() else {
        return;
    };
    let (min, max) = bake.bounds();
    for (mut at, mut leaf, sample) in &mut leaves {
        let v = leaf.0;
        leaf.0 = v + (sample.wind - v) * (dt / 0.5).min(1.0);
        at.translation += leaf.0 * dt;
        // Leaves blown off the level come back in on the other side.
        at.translation.x = min[0] + (at.translation.x - min[0]).rem_euclid(max[0] - min[0]);
        at.translation.z = min[1] + (at.translation.z - min[1]).rem_euclid(max[1] - min[1]);
        at.translation.y = bake.ground_at(at.translation.x, at.translation.z) + 1.0;
    }
}

fn show(
    time: Res<Time>,
    wind: Res<Wind>,
    mut run: ResMut<Run>,
    leaves: Query<(&Transform, &Leaf)>,
    mut exit: MessageWriter<AppExit>,
) {
    let second = time.elapsed_secs().floor() as u32;
    if run.printed.is_some_and(|p| second <= p) {
        return;
    }
    run.printed = Some(second);
    let Some(bake) = wind.bake() else {
        println!(
            "t = {second} s: no wind: {}",
            wind.last_error().unwrap_or("no bake")
        );
        if time.elapsed_secs() >= run.seconds {
            exit.write(AppExit::error());
        }
        return;
    };
    let (min, max) = bake.bounds();
    let mut map = vec![[b' '; COLUMNS]; ROWS];
    let mut speed = 0.0f32;
    for (at, leaf) in &leaves {
        let c = ((at.translation.x - min[0]) / (max[0] - min[0]) * COLUMNS as f32) as usize;
        let r = ((at.translation.z - min[1]) / (max[1] - min[1]) * ROWS as f32) as usize;
        let cell = &mut map[r.min(ROWS - 1)][c.min(COLUMNS - 1)];
        *cell = match *cell {
            b' ' => b'.',
            b'.' => b':',
            _ => b'#',
        };
        speed = speed.max(leaf.0.length());
    }
    println!(
        "t = {second} s: 400 leaves, fastest {speed:.1} m/s (bake {}, x east, z south down the page)",
        bake.sequence()
    );
    println!("+{}+", "-".repeat(COLUMNS));
    for row in &map {
        println!("|{}|", String::from_utf8_lossy(row));
    }
    println!("+{}+", "-".repeat(COLUMNS));
    if time.elapsed_secs() >= run.seconds {
        exit.write(AppExit::Success);
    }
}

fn announce(mut reloaded: MessageReader<WindReloaded>) {
    for r in reloaded.read() {
        println!("re-baked: bake {} blows from now on", r.sequence);
    }
}
