//! The live simulation: a worker thread that owns the CPU solver, takes layout edits and
//! transport commands, and publishes field snapshots. The UI never waits for it.

use crate::doc::Layout;
use crate::sim::Solver;
use std::sync::mpsc::{self, Receiver, Sender, TryRecvError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// One published state of the field, cell-centred.
#[derive(Clone, Default)]
pub struct Snapshot {
    pub nx: usize,
    pub ny: usize,
    /// World rectangle the grid covers.
    pub origin: [f32; 2],
    pub size: [f32; 2],
    pub velocity: Vec<[f32; 2]>,
    pub curl: Vec<f32>,
    pub pressure: Vec<f32>,
    pub time: f32,
    /// Mean wall-clock milliseconds per simulation step, recently.
    pub ms_per_step: f32,
    /// Increases with every published snapshot.
    pub serial: u64,
}

impl Snapshot {
    /// Velocity at a world point (nearest cell), if inside the grid.
    pub fn velocity_at(&self, p: [f32; 2]) -> Option<[f32; 2]> {
        if self.nx == 0 {
            return None;
        }
        let x = ((p[0] - self.origin[0]) / self.size[0] * self.nx as f32).floor();
        let z = ((p[1] - self.origin[1]) / self.size[1] * self.ny as f32).floor();
        if x < 0.0 || z < 0.0 || x >= self.nx as f32 || z >= self.ny as f32 {
            return None;
        }
        Some(self.velocity[z as usize * self.nx + x as usize])
    }

    /// Velocity at a world point, bilinear between cell centres (zero outside).
    pub fn sample(&self, p: [f32; 2]) -> [f32; 2] {
        if self.nx == 0 {
            return [0.0, 0.0];
        }
        let x = (p[0] - self.origin[0]) / self.size[0] * self.nx as f32 - 0.5;
        let z = (p[1] - self.origin[1]) / self.size[1] * self.ny as f32 - 0.5;
        let x = x.clamp(0.0, (self.nx - 1) as f32);
        let z = z.clamp(0.0, (self.ny - 1) as f32);
        let (i0, j0) = (x as usize, z as usize);
        let (i1, j1) = ((i0 + 1).min(self.nx - 1), (j0 + 1).min(self.ny - 1));
        let (fx, fz) = (x - i0 as f32, z - j0 as f32);
        let at = |i: usize, j: usize| self.velocity[j * self.nx + i];
        let lerp =
            |a: [f32; 2], b: [f32; 2], t: f32| [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t];
        lerp(
            lerp(at(i0, j0), at(i1, j0), fx),
            lerp(at(i0, j1), at(i1, j1), fx),
            fz,
        )
    }
}

enum Command {
    Layout(Box<Layout>),
    Play(bool),
    Step,
    Reset,
    Speed(f32),
    Quit,
}

/// Handle to the simulation thread.
pub struct LiveSim {
    tx: Sender<Command>,
    latest: Arc<Mutex<Arc<Snapshot>>>,
    thread: Option<JoinHandle<()>>,
    pub playing: bool,
    pub speed: f32,
}

impl LiveSim {
    /// Starts the worker on `layout`, playing. `repaint` is called after each published
    /// snapshot (the UI passes a closure that requests a repaint).
    pub fn start(layout: &Layout, repaint: impl Fn() + Send + 'static) -> Self {
        let (tx, rx) = mpsc::channel();
        let latest = Arc::new(Mutex::new(Arc::new(Snapshot::default())));
        let shared = latest.clone();
        let layout = layout.clone();
        let thread = std::thread::Builder::new()
            .name("windloom-sim".into())
            .spawn(move || worker(layout, rx, shared, repaint))
            .expect("the simulation thread starts");
        Self {
            tx,
            latest,
            thread: Some(thread),
            playing: true,
            speed: 1.0,
        }
    }

    /// Sends the edited layout; it takes effect at the worker's next step.
    pub fn set_layout(&self, layout: &Layout) {
        let _ = self.tx.send(Command::Layout(Box::new(layout.clone())));
    }

    pub fn set_playing(&mut self, playing: bool) {
        self.playing = playing;
        let _ = self.tx.send(Command::Play(playing));
    }

    pub fn step_once(&self) {
        let _ = self.tx.send(Command::Step);
    }

    pub fn reset(&self) {
        let _ = self.tx.send(Command::Reset);
    }

    /// Simulated seconds per real second.
    pub fn set_speed(&mut self, speed: f32) {
        self.speed = speed;
        let _ = self.tx.send(Command::Speed(speed));
    }

    /// The most recent snapshot, shared: the simulation thread publishes a new one rather
    /// than changing this, so taking it each frame copies a pointer, not the fields.
    pub fn snapshot(&self) -> Arc<Snapshot> {
        match self.latest.lock() {
            Ok(s) => Arc::clone(&s),
            Err(p) => Arc::clone(&p.into_inner()),
        }
    }

    /// Runs `f` on the latest snapshot without copying it.
    pub fn with_snapshot<R>(&self, f: impl FnOnce(&Snapshot) -> R) -> R {
        f(&self.snapshot())
    }
}

impl Drop for LiveSim {
    fn drop(&mut self) {
        let _ = self.tx.send(Command::Quit);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// Whether a layout change needs a new solver (grid, world, obstacles or boundary changed).
fn needs_rebuild(old: &Layout, new: &Layout) -> bool {
    old.world.size != new.world.size
        || old.world.origin != new.world.origin
        || old.world.grid != new.world.grid
        || old.obstacles != new.obstacles
        || old.sim.boundary != new.sim.boundary
}

fn publish(solver: &mut Solver, shared: &Mutex<Arc<Snapshot>>, ms: f32, serial: &mut u64) {
    *serial += 1;
    let snap = Snapshot {
        nx: solver.nx,
        ny: solver.ny,
        origin: solver.origin,
        size: [solver.hx * solver.nx as f32, solver.hz * solver.ny as f32],
        velocity: solver.velocity_field(),
        curl: {
            solver.compute_curl();
            solver.curl.clone()
        },
        pressure: solver.p.clone(),
        time: solver.time,
        ms_per_step: ms,
        serial: *serial,
    };
    let snap = Arc::new(snap);
    match shared.lock() {
        Ok(mut s) => *s = snap,
        Err(p) => *p.into_inner() = snap,
    }
}

fn worker(
    mut layout: Layout,
    rx: Receiver<Command>,
    shared: Arc<Mutex<Arc<Snapshot>>>,
    repaint: impl Fn(),
) {
    let mut solver = Solver::new(&layout);
    let mut playing = true;
    let mut speed = 1.0f32;
    let mut serial = 0u64;
    let mut ms = 0.0f32;
    let mut owed = 0.0f64; // simulated seconds we are behind real time
    let mut last = Instant::now();
    publish(&mut solver, &shared, ms, &mut serial);
    repaint();
    loop {
        let mut single_steps = 0usize;
        // Only the newest of several queued layouts matters (a dragged grid size sends one per
        // frame); rebuilding the solver for each would waste seconds at large grids.
        let mut newest: Option<Box<Layout>> = None;
        loop {
            let cmd = if playing {
                match rx.try_recv() {
                    Ok(c) => c,
                    Err(TryRecvError::Empty) => break,
                    Err(TryRecvError::Disconnected) => return,
                }
            } else {
                // Paused: sleep until told something.
                match rx.recv_timeout(Duration::from_millis(100)) {
                    Ok(c) => c,
                    Err(mpsc::RecvTimeoutError::Timeout) => break,
                    Err(mpsc::RecvTimeoutError::Disconnected) => return,
                }
            };
            match cmd {
                Command::Layout(l) => newest = Some(l),
                Command::Play(p) => {
                    playing = p;
                    last = Instant::now();
                    owed = 0.0;
                }
                Command::Step => single_steps += 1,
                Command::Reset => {
                    if let Some(l) = newest.take() {
                        layout = *l;
                    }
                    solver = Solver::new(&layout);
                    owed = 0.0;
                    publish(&mut solver, &shared, ms, &mut serial);
                    repaint();
                }
                Command::Speed(s) => speed = s,
                Command::Quit => return,
            }
        }
        if let Some(l) = newest.take() {
            if needs_rebuild(&layout, &l) {
                let time = solver.time;
                solver = Solver::new(&l);
                solver.time = time;
            } else {
                solver.set_layout(&l);
            }
            layout = *l;
        }
        if single_steps > 0 {
            let t = Instant::now();
            for _ in 0..single_steps {
                solver.step();
            }
            ms = t.elapsed().as_secs_f32() * 1e3 / single_steps as f32;
            publish(&mut solver, &shared, ms, &mut serial);
            repaint();
            continue;
        }
        if !playing {
            continue;
        }
        let now = Instant::now();
        owed += (now - last).as_secs_f64() * f64::from(speed);
        last = now;
        let dt = f64::from(layout.sim.dt);
        // Never fall more than a few steps behind: a slow machine runs in slow motion rather
        // than piling up work.
        owed = owed.min(dt * 4.0);
        if owed < dt {
            std::thread::sleep(
                Duration::from_secs_f64((dt - owed) / f64::from(speed.max(0.01)))
                    .min(Duration::from_millis(20)),
            );
            continue;
        }
        while owed >= dt {
            let t = Instant::now();
            solver.step();
            let step_ms = t.elapsed().as_secs_f32() * 1e3;
            ms = if ms == 0.0 {
                step_ms
            } else {
                ms * 0.9 + step_ms * 0.1
            };
            owed -= dt;
        }
        publish(&mut solver, &shared, ms, &mut serial);
        repaint();
    }
}
