//! A windloom bake in a Bevy game.
//!
//! [`WindloomPlugin`] opens a bake folder (`windloom bake LEVEL --out FOLDER`) into the
//! [`Wind`] resource, which answers the wind at any point at any time and follows the
//! folder as it is baked again (`windloom bake --watch`, the editor's Live export): a new
//! bake answers once read whole, a broken one leaves the last good bake answering. Give an
//! entity a [`WindSample`] and, each frame, its `wind` is the wind at its
//! [`GlobalTransform`]'s translation at the game's clock ([`Time`]), in m/s.
//!
//! Axes: Bevy's are windloom's (right-handed, y up, metres), so a bake's `x` is Bevy's X,
//! its `z` (south in the editor) Bevy's Z, and the ground is `y = 0` unless the bake has
//! terrain. The plugin needs Bevy's app, ECS, time and transforms only (`MinimalPlugins`
//! and `TransformPlugin` run it headless).
//!
//! ```no_run
//! use bevy::prelude::*;
//! use windloom_bevy::{WindSample, WindloomPlugin};
//! fn push(time: Res<Time>, mut leaves: Query<(&mut Transform, &WindSample)>) {
//!     for (mut t, s) in &mut leaves {
//!         t.translation += s.wind * 0.2 * time.delta_secs();
//!     }
//! }
//! App::new()
//!     .add_plugins((MinimalPlugins, bevy::transform::TransformPlugin))
//!     .add_plugins(WindloomPlugin::new("bake"))
//!     .add_systems(Update, push.after(windloom_bevy::WindSystems::Sample))
//!     .run();
//! ```

use bevy::app::{App, Plugin, PreUpdate, Update};
use bevy::ecs::prelude::*;
use bevy::math::Vec3;
use bevy::time::{Real, Time, Timer, TimerMode};
use bevy::transform::components::GlobalTransform;
use std::path::PathBuf;
use std::time::Duration;
pub use windloom_runtime::{Axes, Bake, LiveBake, Options, Outside};

/// Opens a bake folder into [`Wind`] and samples it for every [`WindSample`].
pub struct WindloomPlugin {
    pub folder: PathBuf,
    /// How the bake is read (Bevy's axes are windloom's: leave `axes` as it is).
    pub options: Options,
    /// How often the folder is looked at for a new bake (real time); `None`: never.
    pub poll_every: Option<Duration>,
}

impl WindloomPlugin {
    /// The bake in `folder`, looked at for a new bake twice a second.
    pub fn new(folder: impl Into<PathBuf>) -> Self {
        Self {
            folder: folder.into(),
            options: Options::default(),
            poll_every: Some(Duration::from_millis(500)),
        }
    }
}

/// The wind of the bake: [`Wind::at`] anywhere, any time.
#[derive(Resource)]
pub struct Wind {
    live: LiveBake,
    poll: Option<Timer>,
}

impl Wind {
    /// The wind at `position` at `seconds` of the game's clock, m/s.
    pub fn at(&self, position: Vec3, seconds: f32) -> Vec3 {
        Vec3::from(self.live.bake().wind_at(position.to_array(), seconds))
    }

    /// The bake answering now (its frames, bounds, sequence, memory).
    pub fn bake(&self) -> &Bake {
        self.live.bake()
    }

    /// Why the newest bake in the folder is not the one answering, if it is not.
    pub fn last_error(&self) -> Option<&str> {
        self.live.last_error()
    }

    /// Looks for a new bake now: `true` when one answers from now on.
    pub fn reload(&mut self) -> bool {
        self.live.poll().unwrap_or(false)
    }
}

/// Sent when a new bake answers (`sequence` is its manifest's).
#[derive(Message, Debug, Clone, Copy, PartialEq, Eq)]
pub struct WindReloaded {
    pub sequence: u64,
}

/// The wind at an entity, written every frame by [`WindSystems::Sample`].
#[derive(Component, Debug, Clone, Copy, Default, PartialEq)]
pub struct WindSample {
    /// m/s at the entity's translation, at the game's clock.
    pub wind: Vec3,
}

/// The plugin's systems, to order a game's own after them.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum WindSystems {
    /// Looks for a new bake (`PreUpdate`).
    Reload,
    /// Writes every [`WindSample`] (`Update`).
    Sample,
}

impl Plugin for WindloomPlugin {
    fn build(&self, app: &mut App) {
        // A game without its wind is a broken build: say which folder and why.
        let live = LiveBake::open(&self.folder, self.options.clone())
            .unwrap_or_else(|e| panic!("windloom: {e}"));
        app.insert_resource(Wind {
            live,
            poll: self.poll_every.map(|d| Timer::new(d, TimerMode::Repeating)),
        })
        .add_message::<WindReloaded>()
        .add_systems(PreUpdate, reload.in_set(WindSystems::Reload))
        .add_systems(Update, sample.in_set(WindSystems::Sample));
    }
}

fn reload(mut wind: ResMut<Wind>, time: Res<Time<Real>>, mut sent: MessageWriter<WindReloaded>) {
    let wind = &mut *wind;
    let Some(timer) = &mut wind.poll else {
        return;
    };
    if !timer.tick(time.delta()).just_finished() {
        return;
    }
    if let Ok(true) = wind.live.poll() {
        sent.write(WindReloaded {
            sequence: wind.live.bake().sequence(),
        });
    }
}

fn sample(wind: Res<Wind>, time: Res<Time>, mut q: Query<(&GlobalTransform, &mut WindSample)>) {
    let bake = wind.live.bake();
    let t = time.elapsed_secs();
    for (at, mut s) in &mut q {
        s.wind = Vec3::from(bake.wind_at(at.translation().to_array(), t));
    }
}
