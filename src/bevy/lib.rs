//! A windloom bake in a Bevy game.
//!
//! [`WindloomPlugin`] opens a bake folder (`windloom bake LEVEL --out FOLDER`) into the
//! [`Wind`] resource, which answers the wind at any point at any time and follows the
//! folder as it is baked again (`windloom bake --watch`, the editor's Live export): a new
//! bake answers once read whole (on a thread of its own: the game's frames never wait on
//! the disk), a broken one leaves the last good bake answering and is logged once. Give an
//! entity a [`WindSample`] and, each frame, its `wind` is the wind where the entity stands
//! that frame (its `Transform` and its parents', as they are when [`WindSystems::Sample`]
//! runs in `Update`: on the frame it is spawned, and after a system that moves it
//! `.before(WindSystems::Sample)`) at the game's clock ([`Time`], in f64 seconds), in m/s.
//!
//! A bake missing or broken at start does not stop the game: the wind is zero, the error is
//! logged (`tracing`, which Bevy's `LogPlugin` shows) and [`Wind::last_error`] says it, and
//! the folder is looked at again until a good bake lands.
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
use bevy::ecs::hierarchy::ChildOf;
use bevy::ecs::prelude::*;
use bevy::math::Vec3;
use bevy::time::Time;
use bevy::transform::components::{GlobalTransform, Transform};
use std::path::PathBuf;
use std::sync::mpsc::{Receiver, TryRecvError};
use std::sync::{Arc, Mutex};
use std::time::Duration;
pub use windloom_runtime::{Axes, Bake, LiveBake, Options, Outside};

/// Opens a bake folder into [`Wind`] and samples it for every [`WindSample`].
pub struct WindloomPlugin {
    pub folder: PathBuf,
    /// How the bake is read (Bevy's axes are windloom's: leave `axes` as it is).
    pub options: Options,
    /// How often the folder is looked at for a new bake (real time, on the reading
    /// thread); `None`: only when [`Wind::reload`] is called.
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

/// What the reading thread hands over: a new bake, or why the newest could not be read.
type News = Result<Arc<Bake>, String>;

/// Where the folder is followed: on a thread of its own (polling), or here (on demand).
enum Follow {
    /// The reading thread's news; the thread stops once this is dropped.
    Thread {
        news: Mutex<Receiver<News>>,
        _alive: Arc<()>,
    },
    /// Read when [`Wind::reload`] asks, on the caller's thread: the bake followed, or the
    /// folder and options to open it with once a bake lands.
    Here(Mutex<Option<LiveBake>>, PathBuf, Options),
}

/// The wind of the bake: [`Wind::at`] anywhere, any time.
#[derive(Resource)]
pub struct Wind {
    bake: Option<Arc<Bake>>,
    last_error: Option<String>,
    follow: Follow,
}

impl Wind {
    /// The wind at `position` at `seconds` of the game's clock, m/s; zero while no bake
    /// could be read.
    pub fn at(&self, position: Vec3, seconds: f64) -> Vec3 {
        self.bake.as_ref().map_or(Vec3::ZERO, |b| {
            Vec3::from(b.wind_at(position.to_array(), seconds))
        })
    }

    /// The bake answering now (its frames, bounds, sequence, memory), if one could be read.
    pub fn bake(&self) -> Option<&Bake> {
        self.bake.as_deref()
    }

    /// Why the newest bake in the folder is not the one answering, if it is not.
    pub fn last_error(&self) -> Option<&str> {
        self.last_error.as_deref()
    }

    /// Looks for a new bake now: `true` when one answers from now on. With polling on, this
    /// takes what the reading thread has read (it never reads on this thread); with it off,
    /// it reads the folder here.
    pub fn reload(&mut self) -> bool {
        let mut fresh = false;
        for news in self.news() {
            fresh |= self.take(news);
        }
        fresh
    }

    /// What happened in the folder since last asked.
    fn news(&mut self) -> Vec<News> {
        match &mut self.follow {
            Follow::Thread { news, .. } => {
                let Ok(rx) = news.get_mut() else {
                    return Vec::new();
                };
                let mut out = Vec::new();
                loop {
                    match rx.try_recv() {
                        Ok(n) => out.push(n),
                        Err(TryRecvError::Empty | TryRecvError::Disconnected) => break out,
                    }
                }
            }
            Follow::Here(live, folder, options) => {
                let Ok(live) = live.get_mut() else {
                    return Vec::new();
                };
                look(live, folder, options).into_iter().collect()
            }
        }
    }

    /// Takes one piece of news: `true` for a new bake. A failure is logged once.
    fn take(&mut self, news: News) -> bool {
        match news {
            Ok(bake) => {
                self.bake = Some(bake);
                self.last_error = None;
                true
            }
            Err(e) => {
                if self.last_error.as_deref() != Some(&e) {
                    tracing::warn!("windloom: {e} (the last good bake goes on answering)");
                    self.last_error = Some(e);
                }
                false
            }
        }
    }
}

/// One look at the folder: the bake opened if none was, else a poll. `None`: no news.
fn look(live: &mut Option<LiveBake>, folder: &PathBuf, options: &Options) -> Option<News> {
    match live {
        None => match LiveBake::open(folder, options.clone()) {
            Ok(l) => {
                let b = l.shared();
                *live = Some(l);
                Some(Ok(b))
            }
            Err(e) => Some(Err(e.to_string())),
        },
        Some(l) => match l.poll() {
            Ok(true) => Some(Ok(l.shared())),
            Ok(false) => None,
            Err(e) => Some(Err(e.to_string())),
        },
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
    /// m/s where the entity stands this frame, at the game's clock.
    pub wind: Vec3,
}

/// The plugin's systems, to order a game's own after them.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum WindSystems {
    /// Takes a new bake the reading thread has read (`PreUpdate`).
    Reload,
    /// Writes every [`WindSample`] (`Update`): order systems that move entities before it
    /// and those that read the wind after it.
    Sample,
}

impl Plugin for WindloomPlugin {
    fn build(&self, app: &mut App) {
        // The bake at start, read here so the first frame has its wind; a missing or
        // broken one is logged and looked for again, never a panic.
        let mut live = None;
        let first = look(&mut live, &self.folder, &self.options);
        let follow = match self.poll_every {
            Some(every) => {
                let (tx, rx) = std::sync::mpsc::channel();
                let alive = Arc::new(());
                let weak = Arc::downgrade(&alive);
                let (folder, options) = (self.folder.clone(), self.options.clone());
                let spawned = std::thread::Builder::new()
                    .name("windloom bake reader".into())
                    .spawn(move || {
                        let mut live = live;
                        // Stops once the game drops the wind (or quits).
                        while weak.upgrade().is_some() {
                            std::thread::sleep(every);
                            if let Some(news) = look(&mut live, &folder, &options)
                                && tx.send(news).is_err()
                            {
                                return;
                            }
                        }
                    });
                if let Err(e) = spawned {
                    tracing::warn!("windloom: no thread to follow re-bakes ({e})");
                }
                Follow::Thread {
                    news: Mutex::new(rx),
                    _alive: alive,
                }
            }
            None => Follow::Here(Mutex::new(live), self.folder.clone(), self.options.clone()),
        };
        let mut wind = Wind {
            bake: None,
            last_error: None,
            follow,
        };
        if let Some(news) = first {
            wind.take(news);
        }
        app.insert_resource(wind)
            .add_message::<WindReloaded>()
            .add_systems(PreUpdate, reload.in_set(WindSystems::Reload))
            .add_systems(Update, sample.in_set(WindSystems::Sample));
    }
}

fn reload(mut wind: ResMut<Wind>, mut sent: MessageWriter<WindReloaded>) {
    if !matches!(wind.follow, Follow::Thread { .. }) {
        return;
    }
    if wind.reload()
        && let Some(b) = wind.bake()
    {
        sent.write(WindReloaded {
            sequence: b.sequence(),
        });
    }
}

/// The most parents followed up from an entity (a deeper hierarchy is cut there).
const MAX_DEPTH: usize = 256;

/// Where `e` stands now: its `Transform` composed with its parents' (what transform
/// propagation will make its `GlobalTransform` at the end of the frame), or its
/// `GlobalTransform` where it has no `Transform`.
fn standing(
    e: Entity,
    global: Option<&GlobalTransform>,
    transforms: &Query<(&Transform, Option<&ChildOf>)>,
) -> Option<Vec3> {
    let Ok((t, mut parent)) = transforms.get(e) else {
        return global.map(GlobalTransform::translation);
    };
    let mut m = t.compute_affine();
    for _ in 0..MAX_DEPTH {
        let Some(p) = parent else { break };
        let Ok((pt, pp)) = transforms.get(p.parent()) else {
            break;
        };
        m = pt.compute_affine() * m;
        parent = pp;
    }
    Some(Vec3::from(m.translation))
}

fn sample(
    wind: Res<Wind>,
    time: Res<Time>,
    mut q: Query<(Entity, Option<&GlobalTransform>, &mut WindSample)>,
    transforms: Query<(&Transform, Option<&ChildOf>)>,
) {
    let t = time.elapsed_secs_f64();
    let Some(bake) = wind.bake() else {
        for (_, _, mut s) in &mut q {
            s.wind = Vec3::ZERO;
        }
        return;
    };
    for (e, global, mut s) in &mut q {
        if let Some(at) = standing(e, global, &transforms) {
            s.wind = Vec3::from(bake.wind_at(at.to_array(), t));
        }
    }
}
