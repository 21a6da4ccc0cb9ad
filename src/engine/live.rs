//! The live simulation: a worker thread that owns the solver — the CPU one, or the GPU one on
//! the editor's own device — takes layout edits and transport commands, and publishes field
//! snapshots. The UI never waits for it.
//!
//! On the GPU the field stays on the GPU: the map view draws it from the solver's buffers
//! ([`Snapshot::field`]), and the snapshot's arrays (the cursor readout, the legend) come from
//! a read-back at most [`READBACK_SECONDS`] apart. Switching backends hands the running field
//! over.

use super::{Backend, RunsOn};
use crate::doc::Layout;
use crate::gpu::mapview::FieldBuffers;
use crate::gpu::{GpuContext, GpuSolver};
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
    /// The wind's face velocities (`(nx + 1) × ny` and `nx × (ny + 1)`, terrain-shaped as
    /// `velocity`), so a CPU-run field can be drawn by the same GPU passes as a GPU-run one.
    pub u: Vec<f32>,
    pub v: Vec<f32>,
    pub curl: Vec<f32>,
    pub pressure: Vec<f32>,
    pub time: f32,
    /// Mean wall-clock milliseconds per simulation step, recently.
    pub ms_per_step: f32,
    /// Increases with every published snapshot.
    pub serial: u64,
    /// Where the field is running.
    pub runs_on: RunsOn,
    /// On the GPU: the buffers the field lives in, to draw it from.
    pub field: Option<FieldBuffers>,
    /// GPU milliseconds per step from timestamp queries (GPU backend, where the adapter has
    /// them).
    pub gpu_ms_per_step: Option<f32>,
    /// The last measurement behind an automatic choice: CPU and GPU ms per step.
    pub measured: Option<[f32; 2]>,
    /// Why the GPU is not in use when it was asked for (no device, an error), if so.
    pub notice: Option<String>,
    /// The time a seek is recomputing the field to, while it does (the field shown is on
    /// its way there).
    pub seeking: Option<f32>,
    /// The last seek ([`LiveSim::seek`]) the worker has finished, by its number.
    pub seeked: u64,
    /// What the timeline keeps of the wind's past to scrub back to: its checkpoints, and the
    /// bytes they take (at most [`CHECKPOINT_BUDGET`]).
    pub history: (usize, usize),
}

/// Wall-clock time a seek steps before it looks for newer commands and shows how far it is.
const SEEK_SLICE: Duration = Duration::from_millis(60);

/// Longest time between two read-backs of a GPU field (the cursor readout, the legend).
pub const READBACK_SECONDS: f64 = 0.25;

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
    Gpu(Box<GpuContext>, Backend),
    Backend(Backend),
    Play(bool),
    Step,
    Reset,
    /// Go to a time; the seek's number, to tell when it is done.
    Seek(f32, u64),
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
    /// The last seek asked for: its time and number.
    seek: Option<(f32, u64)>,
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
            seek: None,
        }
    }

    /// Hands the worker a GPU device (the editor's) and says where the field should run.
    pub fn set_gpu(&self, ctx: GpuContext, choice: Backend) {
        let _ = self.tx.send(Command::Gpu(Box::new(ctx), choice));
    }

    /// Where the field should run; a change hands the running field over.
    pub fn set_backend(&self, choice: Backend) {
        let _ = self.tx.send(Command::Backend(choice));
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

    /// Puts the field at simulation time `t` (the timeline's scrub): from the nearest
    /// checkpoint at or before it, stepped on to `t` in slices, each published (the field
    /// is seen on its way), a newer seek taking over from an older one at once.
    pub fn seek(&mut self, t: f32) {
        let n = self.seek.map_or(1, |(_, n)| n + 1);
        self.seek = Some((t, n));
        let _ = self.tx.send(Command::Seek(t, n));
    }

    /// The time the editor shows, and the time being recomputed to while a seek is under
    /// way: the time asked for from the moment it was asked (a key taken then is at that
    /// time, not the field's stale one), the field's own once the seek is done.
    pub fn time_shown(&self) -> (f32, Option<f32>) {
        let snap = self.snapshot();
        match self.seek {
            Some((t, n)) if snap.seeked < n => (t, Some(t)),
            _ => (snap.time, None),
        }
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

/// Whether two layouts have the same grid over the same world, so one's field fits the other.
fn same_grid(old: &Layout, new: &Layout) -> bool {
    old.world.size == new.world.size
        && old.world.origin == new.world.origin
        && old.world.grid == new.world.grid
}

/// Whether a layout change needs a new solver (grid, world, obstacles or boundary changed).
fn needs_rebuild(old: &Layout, new: &Layout) -> bool {
    !same_grid(old, new) || old.obstacles != new.obstacles || old.sim.boundary != new.sim.boundary
}

/// The solver in use: the CPU's always exists (on the GPU it holds the last read-back, and
/// takes the field back when the user switches), the GPU's while the field runs there.
/// A saved state of the field: what a seek back starts from.
struct Checkpoint {
    time: f32,
    /// The solver's clock there, restored with the field.
    clock: crate::sim::Clock,
    u: Vec<f32>,
    v: Vec<f32>,
    p: Vec<f32>,
}

/// The memory the checkpoints may take, bytes; past it every other one is dropped (they
/// stand twice as far apart).
pub const CHECKPOINT_BUDGET: usize = 256 << 20;
/// Simulated seconds between two checkpoints, at first.
pub const CHECKPOINT_SECONDS: f32 = 1.0;

struct Engine {
    cpu: Solver,
    /// States of the running field, in time order, since the layout last changed (a seek
    /// back re-simulates from the nearest; none before the calm start).
    checkpoints: Vec<Checkpoint>,
    /// Seconds between checkpoints now (doubles each time the budget is reached).
    checkpoint_every: f32,
    gpu: Option<GpuSolver>,
    ctx: Option<GpuContext>,
    choice: Backend,
    measured: Option<[f32; 2]>,
    notice: Option<String>,
    serial: u64,
    /// Mean wall-clock ms per step, recently.
    ms: f32,
    gpu_ms: Option<f32>,
    steps_since_readback: usize,
    last_readback: Instant,
    /// The field went non-finite: zeroed and no longer stepped until a Reset (or a rebuild).
    halted: bool,
    /// A seek under way: its time, its number, and whether the field goes back to the GPU
    /// when it is there.
    seeking: Option<(f32, u64, bool)>,
    /// The last seek finished, by its number.
    seeked: u64,
}

impl Engine {
    fn new(layout: &Layout) -> Self {
        Self {
            cpu: Solver::new(layout),
            checkpoints: Vec::new(),
            checkpoint_every: CHECKPOINT_SECONDS,
            gpu: None,
            ctx: None,
            choice: Backend::Auto,
            measured: None,
            notice: None,
            serial: 0,
            ms: 0.0,
            gpu_ms: None,
            steps_since_readback: 0,
            last_readback: Instant::now(),
            halted: false,
            seeking: None,
            seeked: 0,
        }
    }

    /// Steps once on whichever backend runs; on the GPU waits for it, so the worker neither
    /// queues unbounded work nor misreports the step time.
    fn step(&mut self) {
        if self.halted {
            return;
        }
        let t = Instant::now();
        match (&mut self.gpu, &self.ctx) {
            (Some(g), Some(ctx)) => {
                g.step(ctx);
                if let Err(e) = g.finish(ctx) {
                    self.fall_back(format!("GPU step failed: {e}"));
                }
            }
            _ => self.cpu.step(),
        }
        let step_ms = t.elapsed().as_secs_f32() * 1e3;
        self.ms = if self.ms == 0.0 {
            step_ms
        } else {
            self.ms * 0.9 + step_ms * 0.1
        };
        self.steps_since_readback += 1;
    }

    /// A field with a NaN or an infinity (never seen from a valid layout, but the editor must
    /// survive one): zeroed, stepping halted, and the status bar says so until a Reset.
    fn contain_blow_up(&mut self) {
        let solver = &mut self.cpu;
        if solver
            .u
            .iter()
            .chain(&solver.v)
            .chain(&solver.p)
            .all(|x| x.is_finite())
        {
            return;
        }
        let why = format!(
            "the wind blew up at t = {:.2} s (non-finite values); stopped — press Reset",
            solver.time()
        );
        log::error!("{why}");
        for x in solver
            .u
            .iter_mut()
            .chain(&mut solver.v)
            .chain(&mut solver.p)
        {
            *x = 0.0;
        }
        self.halted = true;
        self.notice = Some(why);
    }

    /// Moves the field to the CPU after a GPU failure, saying why.
    fn fall_back(&mut self, why: String) {
        log::warn!("wind moved to the CPU: {why}");
        if let (Some(g), Some(ctx)) = (self.gpu.take(), &self.ctx) {
            // Best effort: keep what the GPU had if it can still be read.
            let _ = g.read_into(ctx, &mut self.cpu);
        }
        self.notice = Some(why);
    }

    /// Runs the field where `choice` says, on `newest` when an edit was waiting (it becomes
    /// `layout`).
    fn switch_to(&mut self, choice: Backend, layout: &mut Layout, newest: Option<Box<Layout>>) {
        self.choice = choice;
        if let Some(l) = newest {
            self.new_solver(&l, true);
            *layout = *l;
        }
        self.choose(layout);
    }

    /// Decides where the field runs for `layout` and moves it there.
    fn choose(&mut self, layout: &Layout) {
        let want = match (self.choice, &self.ctx) {
            (Backend::Cpu, _) => RunsOn::Cpu,
            (_, Some(ctx)) if ctx.fault().is_some() => {
                let why = ctx.fault().unwrap_or_default();
                self.notice = Some(format!("GPU unusable ({why}): running on the CPU"));
                RunsOn::Cpu
            }
            (_, None) => {
                if self.choice == Backend::Gpu {
                    self.notice = Some("no GPU device: running on the CPU".into());
                }
                RunsOn::Cpu
            }
            (Backend::Gpu, Some(_)) => RunsOn::Gpu,
            (Backend::Auto, Some(ctx)) => {
                if ctx.is_software() {
                    match measure(layout, ctx) {
                        Ok(m) => {
                            self.measured = Some(m);
                            if m[1] < m[0] {
                                RunsOn::Gpu
                            } else {
                                RunsOn::Cpu
                            }
                        }
                        Err(e) => {
                            self.notice = Some(format!("GPU unusable, running on the CPU: {e}"));
                            RunsOn::Cpu
                        }
                    }
                } else {
                    RunsOn::Gpu
                }
            }
        };
        log::info!(
            "wind runs on the {} ({:?} asked{})",
            want.label(),
            self.choice,
            self.measured.map_or(String::new(), |m| format!(
                "; measured CPU {:.2} ms, GPU {:.2} ms a step",
                m[0], m[1]
            ))
        );
        self.move_to(want, layout);
    }

    /// Saves the CPU copy of the field (on the GPU: the last read-back) when it is a
    /// checkpoint's interval past the last one.
    fn checkpoint(&mut self) {
        let t = self.cpu.time();
        let due = self
            .checkpoints
            .last()
            .is_none_or(|c| t >= c.time + self.checkpoint_every - 1e-4);
        if !due || self.halted || t <= 0.0 {
            return;
        }
        let clock = self.cpu.clock;
        let (u, v) = self.cpu.faces_mut();
        let c = Checkpoint {
            time: t,
            clock,
            u: u.to_vec(),
            v: v.to_vec(),
            p: self.cpu.p.clone(),
        };
        let bytes = 4 * (c.u.len() + c.v.len() + c.p.len());
        self.checkpoints.push(c);
        if bytes * self.checkpoints.len() > CHECKPOINT_BUDGET {
            let mut k = 0;
            self.checkpoints.retain(|_| {
                k += 1;
                k % 2 == 0
            });
            self.checkpoint_every *= 2.0;
        }
    }

    /// Forgets the checkpoints (the layout changed: its past is another wind).
    fn forget_checkpoints(&mut self) {
        self.checkpoints.clear();
        self.checkpoint_every = CHECKPOINT_SECONDS;
    }

    /// The field at time `t`: restored from the latest checkpoint at or before it (or calm
    /// at 0), then stepped on the CPU to `t`, and handed back to the GPU if it ran there.
    #[cfg(test)]
    fn seek(&mut self, layout: &Layout, t: f32) {
        self.seek_start(layout, t, 0);
        while !self.seek_advance(layout, Duration::MAX) {}
    }

    /// Starts seek `n` to time `t`: the field on the CPU, restored from the latest checkpoint
    /// at or before `t` (or calm at 0) unless stepping on from where it is now is quicker;
    /// [`Self::seek_advance`] steps it there.
    fn seek_start(&mut self, layout: &Layout, t: f32, n: u64) {
        let on_gpu = self.gpu.is_some() || self.seeking.is_some_and(|(_, _, g)| g);
        self.move_to(RunsOn::Cpu, layout);
        let t = t.max(0.0);
        let from = self.checkpoints.iter().rposition(|c| c.time <= t + 1e-4);
        // Stepping on from where the field is now is quickest when it is before `t` and
        // after every checkpoint that is.
        let ahead = from.is_none_or(|k| self.checkpoints[k].time <= self.cpu.time())
            && self.cpu.time() <= t + 1e-4
            && !self.halted;
        if !ahead {
            match from {
                Some(k) => {
                    let c = &self.checkpoints[k];
                    let (clock, p) = (c.clock, c.p.clone());
                    let (u, v) = (c.u.clone(), c.v.clone());
                    let (nu, nv) = self.cpu.faces_mut();
                    nu.copy_from_slice(&u);
                    nv.copy_from_slice(&v);
                    self.cpu.p.copy_from_slice(&p);
                    self.cpu.clock = clock;
                }
                None => {
                    self.cpu = Solver::new(layout);
                }
            }
            self.halted = false;
        }
        self.seeking = Some((t, n, on_gpu));
    }

    /// Steps the seek under way on for at most `budget` of wall-clock time; whether it has
    /// arrived (the field then back on the GPU if it ran there).
    fn seek_advance(&mut self, layout: &Layout, budget: Duration) -> bool {
        let Some((t, n, on_gpu)) = self.seeking else {
            return true;
        };
        let started = Instant::now();
        let dt = self.cpu.params.dt;
        while self.cpu.time() + dt * 0.5 <= t {
            self.cpu.step();
            self.checkpoint();
            if started.elapsed() >= budget {
                return false;
            }
        }
        self.seeking = None;
        self.seeked = n;
        if on_gpu {
            self.move_to(RunsOn::Gpu, layout);
        }
        true
    }

    /// Hands the running field to `want`'s solver.
    fn move_to(&mut self, want: RunsOn, layout: &Layout) {
        match (want, self.gpu.is_some(), &self.ctx) {
            (RunsOn::Gpu, false, Some(ctx)) => {
                match GpuSolver::from_solver(ctx, layout, &self.cpu) {
                    Ok(g) => {
                        g.enable_profiling(ctx);
                        self.gpu = Some(g);
                        self.notice = None;
                        self.ms = 0.0;
                    }
                    Err(e) => self.notice = Some(format!("GPU unusable, running on the CPU: {e}")),
                }
            }
            (RunsOn::Cpu, true, _) => {
                if let (Some(g), Some(ctx)) = (self.gpu.take(), &self.ctx)
                    && let Err(e) = g.read_into(ctx, &mut self.cpu)
                {
                    self.notice = Some(format!("could not read the field back: {e}"));
                }
                self.ms = 0.0;
                self.gpu_ms = None;
            }
            _ => {}
        }
    }

    /// A new solver for a changed grid, world, obstacles or boundary (at the same time), or at
    /// rest after a reset; the automatic choice is measured again for the new grid.
    #[cfg(test)]
    fn rebuild(&mut self, layout: &Layout, keep_time: bool) {
        self.rebuild_showing(layout, keep_time, |_| {});
    }

    /// [`Self::rebuild`], calling `show` with the new field on the CPU before the backend is
    /// chosen again: measuring the automatic choice on a software adapter takes a second or
    /// more (the GPU passes are compiled), and the view should not show the old field, its
    /// time frozen, meanwhile.
    fn rebuild_showing(&mut self, layout: &Layout, keep_time: bool, show: impl FnOnce(&mut Self)) {
        let on_gpu = self.new_solver(layout, keep_time);
        let remeasure =
            self.choice == Backend::Auto && self.ctx.as_ref().is_some_and(|c| c.is_software());
        if remeasure {
            // Made for the old grid; the tooltip must not show it as the new one's.
            self.measured = None;
        }
        show(self);
        if remeasure {
            self.choose(layout);
        } else if on_gpu {
            self.move_to(RunsOn::Gpu, layout);
        }
    }

    /// Replaces the solver (on the CPU, the GPU's dropped); returns whether the field ran on
    /// the GPU.
    fn new_solver(&mut self, layout: &Layout, keep_time: bool) -> bool {
        self.forget_checkpoints();
        if self.halted {
            self.halted = false;
            self.notice = None;
        }
        let clock = self.cpu.clock;
        let on_gpu = self.gpu.take().is_some();
        self.cpu = Solver::new(layout);
        if keep_time {
            self.cpu.clock = clock;
        }
        on_gpu
    }

    /// A new solver for changed obstacles or boundary on the same grid ([`same_grid`]), the
    /// running wind carried over into it (zero in the new solids and wherever the new
    /// boundary says; the next projection fits the rest), so that placing or moving a rock
    /// does not calm the whole level. Where the field runs is kept, without measuring again:
    /// the grid's cost has not changed.
    fn carry_over(&mut self, layout: &Layout) {
        let on_gpu = self.gpu.is_some();
        // The field as it is now: on the GPU, read back first. A field that blew up is not
        // carried (it was zeroed); the new solver runs, as after a rebuild.
        self.move_to(RunsOn::Cpu, layout);
        let field = (!self.halted).then(|| {
            let (u, v) = self.cpu.faces_mut();
            (u.to_vec(), v.to_vec())
        });
        self.new_solver(layout, true);
        if let Some((u, v)) = field {
            let (nu, nv) = self.cpu.faces_mut();
            nu.copy_from_slice(&u);
            nv.copy_from_slice(&v);
            self.cpu.enforce_boundaries();
        }
        if on_gpu {
            self.move_to(RunsOn::Gpu, layout);
        }
    }

    fn set_layout(&mut self, layout: &Layout) {
        self.forget_checkpoints();
        self.cpu.set_layout(layout);
        if let (Some(g), Some(ctx)) = (&mut self.gpu, &self.ctx) {
            g.set_layout_on(ctx, layout, self.cpu.terrain.as_deref());
        }
    }

    /// Publishes a snapshot. On the GPU the arrays come from a read-back, made only when
    /// `force`d or when the last is older than [`READBACK_SECONDS`]; returns whether it
    /// published.
    fn publish(&mut self, shared: &Mutex<Arc<Snapshot>>, force: bool) -> bool {
        let mut field = None;
        if let (Some(g), Some(ctx)) = (&self.gpu, &self.ctx) {
            if !force && self.last_readback.elapsed().as_secs_f64() < READBACK_SECONDS {
                return false;
            }
            if let Ok(times) = g.pass_times(ctx)
                && !times.is_empty()
                && self.steps_since_readback > 0
            {
                let total: f64 = times.values().sum();
                self.gpu_ms = Some((total / self.steps_since_readback as f64) as f32);
            }
            if let Err(e) = g.read_into(ctx, &mut self.cpu) {
                self.fall_back(format!("GPU read-back failed: {e}"));
            } else {
                field = Some(g.field());
            }
        }
        self.last_readback = Instant::now();
        self.steps_since_readback = 0;
        self.serial += 1;
        self.contain_blow_up();
        self.checkpoint();
        if self.halted {
            // The zeroed copy is what the view draws, not the GPU's buffers.
            field = None;
        }
        let solver = &mut self.cpu;
        let (u, v) = solver.wind_faces();
        let (u, v) = (u.into_owned(), v.into_owned());
        let snap = Snapshot {
            nx: solver.nx,
            ny: solver.ny,
            origin: solver.origin,
            size: [solver.hx * solver.nx as f32, solver.hz * solver.ny as f32],
            velocity: crate::sim::solver::cell_centred(solver.nx, solver.ny, &u, &v),
            u,
            v,
            curl: {
                solver.compute_curl();
                solver.curl.clone()
            },
            pressure: solver.p.clone(),
            time: solver.time(),
            ms_per_step: self.ms,
            serial: self.serial,
            runs_on: if field.is_some() {
                RunsOn::Gpu
            } else {
                RunsOn::Cpu
            },
            field,
            gpu_ms_per_step: self.gpu_ms.filter(|_| self.gpu.is_some()),
            measured: self.measured,
            notice: self.notice.clone(),
            seeking: self.seeking.map(|(t, _, _)| t),
            seeked: self.seeked,
            history: (
                self.checkpoints.len(),
                (self.checkpoints.iter())
                    .map(|c| 4 * (c.u.len() + c.v.len() + c.p.len()))
                    .sum(),
            ),
        };
        let snap = Arc::new(snap);
        match shared.lock() {
            Ok(mut s) => *s = snap,
            Err(p) => *p.into_inner() = snap,
        }
        true
    }
}

/// Milliseconds per step of `layout`'s grid on the CPU and on the GPU of `ctx`, each the best
/// of a few steps after a warm-up, on solvers of their own (the running field is untouched).
pub fn measure(layout: &Layout, ctx: &GpuContext) -> Result<[f32; 2], crate::gpu::GpuError> {
    const STEPS: usize = 3;
    let mut cpu = Solver::new(layout);
    let mut best = [f32::INFINITY; 2];
    for k in 0..=STEPS {
        let t = Instant::now();
        cpu.step();
        if k > 0 {
            best[0] = best[0].min(t.elapsed().as_secs_f32() * 1e3);
        }
    }
    let mut gpu = GpuSolver::new(ctx, layout)?;
    for k in 0..=STEPS {
        let t = Instant::now();
        gpu.step(ctx);
        gpu.finish(ctx)?;
        if k > 0 {
            best[1] = best[1].min(t.elapsed().as_secs_f32() * 1e3);
        }
    }
    Ok(best)
}

fn worker(
    mut layout: Layout,
    rx: Receiver<Command>,
    shared: Arc<Mutex<Arc<Snapshot>>>,
    repaint: impl Fn(),
) {
    let mut engine = Engine::new(&layout);
    let mut playing = true;
    let mut speed = 1.0f32;
    let mut owed = 0.0f64; // simulated seconds we are behind real time
    let mut last = Instant::now();
    engine.publish(&shared, true);
    repaint();
    // A rebuilt field, shown before the backend is measured again.
    let show = |e: &mut Engine| {
        e.publish(&shared, true);
        repaint();
    };
    loop {
        let mut single_steps = 0usize;
        let mut seek: Option<(f32, u64)> = None;
        // Only the newest of several queued layouts matters (a dragged grid size sends one per
        // frame); rebuilding the solver for each would waste seconds at large grids.
        let mut newest: Option<Box<Layout>> = None;
        let mut changed = false;
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
                Command::Gpu(ctx, choice) => {
                    engine.ctx = Some(*ctx);
                    engine.switch_to(choice, &mut layout, newest.take());
                    changed = true;
                }
                Command::Backend(choice) => {
                    engine.switch_to(choice, &mut layout, newest.take());
                    changed = true;
                }
                Command::Play(p) => {
                    playing = p;
                    last = Instant::now();
                    owed = 0.0;
                }
                Command::Step => single_steps += 1,
                Command::Seek(t, n) => seek = Some((t, n)),
                Command::Reset => {
                    if let Some(l) = newest.take() {
                        layout = *l;
                    }
                    engine.rebuild_showing(&layout, false, show);
                    owed = 0.0;
                    changed = true;
                }
                Command::Speed(s) => speed = s,
                Command::Quit => return,
            }
        }
        if let Some(l) = newest.take() {
            if !needs_rebuild(&layout, &l) {
                engine.set_layout(&l);
            } else if same_grid(&layout, &l) {
                engine.carry_over(&l);
            } else {
                engine.rebuild_showing(&l, true, show);
            }
            layout = *l;
            changed = true;
        }
        // A seek under way restarts on an edited layout (its past is another wind); a new
        // one takes over.
        if let Some((t, n)) = seek.or_else(|| {
            let (t, n, _) = engine.seeking?;
            changed.then_some((t, n))
        }) {
            engine.seek_start(&layout, t, n);
        }
        if engine.seeking.is_some() {
            // A slice at a time, each shown, so the field is seen on its way and a newer
            // seek (the scrub dragged on) is taken up at once.
            engine.seek_advance(&layout, SEEK_SLICE);
            owed = 0.0;
            last = Instant::now();
            engine.publish(&shared, true);
            repaint();
            continue;
        }
        if single_steps > 0 {
            for _ in 0..single_steps {
                engine.step();
            }
            engine.publish(&shared, true);
            repaint();
            continue;
        }
        if !playing {
            if changed {
                engine.publish(&shared, true);
                repaint();
            }
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
            engine.step();
            owed -= dt;
        }
        // On the GPU the map draws from the live buffers: every step is worth a frame even
        // when no snapshot is published.
        engine.publish(&shared, changed);
        repaint();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::test_context;

    /// Scrubbing back to a time gives the field a straight run gives there, bit for bit: a
    /// checkpoint holds all the state a step reads; and it needs only the steps from the
    /// checkpoint before it.
    #[test]
    fn a_seek_back_gives_the_straight_run_s_field() {
        let mut layout = crate::doc::default_layout();
        layout.world.grid = [48, 32];
        let dt = layout.sim.dt;
        let mut straight = Solver::new(&layout);
        let target = (2.5 / dt).round() as usize;
        for _ in 0..target {
            straight.step();
        }
        let want = straight.velocity_field();
        let mut e = Engine::new(&layout);
        for _ in 0..(4.0 / dt).round() as usize {
            e.step();
            e.checkpoint();
        }
        assert!(
            e.checkpoints.len() >= 3,
            "{} checkpoints",
            e.checkpoints.len()
        );
        e.seek(&layout, target as f32 * dt);
        assert!((e.cpu.time() - straight.time()).abs() < 1e-4);
        assert_eq!(
            e.cpu.velocity_field(),
            want,
            "the same bits as the straight run"
        );
        // Forward from there, and back to the calm start.
        e.seek(&layout, 3.0);
        assert!((e.cpu.time() - 3.0).abs() < dt);
        e.seek(&layout, 0.0);
        assert_eq!(e.cpu.time(), 0.0);
        assert!(e.cpu.velocity_field().iter().all(|w| *w == [0.0, 0.0]));
        // An edit forgets them: the past of another layout is another wind.
        e.set_layout(&layout);
        assert!(e.checkpoints.is_empty());
    }

    /// A field that went non-finite is contained: zeroed, stepping stops, the snapshot says
    /// so; a Reset (a rebuild) brings the wind back.
    #[test]
    fn a_blow_up_is_contained_and_reset_recovers() {
        let layout = crate::doc::default_layout();
        let mut e = Engine::new(&layout);
        for _ in 0..5 {
            e.step();
        }
        e.cpu.u[3] = f32::NAN;
        e.cpu.v[7] = f32::INFINITY;
        let shared = Mutex::new(Arc::new(Snapshot::default()));
        e.publish(&shared, true);
        let snap = shared.lock().unwrap().clone();
        assert!(
            snap.notice
                .as_deref()
                .is_some_and(|n| n.contains("blew up")),
            "{:?}",
            snap.notice
        );
        assert!(snap.velocity.iter().flatten().all(|x| *x == 0.0));
        let t = e.cpu.time();
        e.step();
        assert_eq!(e.cpu.time(), t, "halted: no more steps");
        e.rebuild(&layout, false);
        for _ in 0..5 {
            e.step();
        }
        e.publish(&shared, true);
        let snap = shared.lock().unwrap().clone();
        assert!(snap.notice.is_none());
        assert!(
            snap.velocity.iter().flatten().any(|x| *x != 0.0),
            "the wind runs again"
        );
    }

    /// A rock placed (or moved) in a running wind keeps the wind: the field carries over into
    /// the new solver, zero in the rock, at the same time, on the CPU and on the GPU alike (a
    /// new grid still starts at rest: `a_rebuild_shows_the_new_field_before_measuring_again`).
    #[test]
    fn an_obstacle_edit_keeps_the_running_wind() {
        let rock = |l: &Layout| {
            let mut l = l.clone();
            l.obstacles.push(crate::doc::Obstacle {
                id: 9_999,
                name: "Rock".into(),
                shape: crate::doc::Shape::Circle {
                    center: [l.world.size[0] * 0.5, l.world.size[1] * 0.5],
                    radius: l.world.size[0] * 0.08,
                },
                locked: false,
                hidden: false,
            });
            l
        };
        let check = |e: &mut Engine, layout: &Layout, on_gpu: bool| {
            for _ in 0..30 {
                e.step();
            }
            e.move_to(RunsOn::Cpu, layout);
            let before = e.cpu.kinetic_energy();
            let t = e.cpu.time();
            if on_gpu {
                e.move_to(RunsOn::Gpu, layout);
            }
            let with_rock = rock(layout);
            assert!(needs_rebuild(layout, &with_rock) && same_grid(layout, &with_rock));
            e.carry_over(&with_rock);
            assert_eq!(e.gpu.is_some(), on_gpu, "where the wind runs is kept");
            e.move_to(RunsOn::Cpu, &with_rock);
            let after = e.cpu.kinetic_energy();
            assert_eq!(e.cpu.time(), t, "the time is kept");
            assert!(
                after > 0.5 * before && before > 0.0,
                "the wind is kept: energy {before} before, {after} after"
            );
            let centre = e
                .cpu
                .cell_at([with_rock.world.size[0] * 0.5, with_rock.world.size[1] * 0.5]);
            let (i, j) = centre.expect("the rock's centre is on the grid");
            assert!(e.cpu.is_solid(i, j));
            assert_eq!(e.cpu.cell_velocity(i, j), [0.0, 0.0], "no wind in the rock");
        };
        let layout = small_layout(64);
        let mut cpu = Engine::new(&layout);
        check(&mut cpu, &layout, false);
        let Some(ctx) = test_context(|_| {}) else {
            return;
        };
        let mut gpu = gpu_engine(&ctx, &layout);
        assert!(gpu.gpu.is_some(), "{:?}", gpu.notice);
        check(&mut gpu, &layout, true);
    }

    /// An engine asked to run `layout` on `ctx`'s GPU (it may end up on the CPU: the tests
    /// look at where and why).
    fn gpu_engine(ctx: &GpuContext, layout: &Layout) -> Engine {
        let mut e = Engine::new(layout);
        e.ctx = Some(ctx.clone());
        e.choice = Backend::Gpu;
        e.choose(layout);
        e
    }

    fn small_layout(n: u32) -> Layout {
        let mut l = crate::doc::default_layout();
        l.world.grid = [n, n];
        l.world.map = None;
        l
    }

    /// A device lost mid-run (destroyed here, as a driver reset would): the step that sees
    /// it moves the wind to the CPU with a message, the wind keeps running there, and a
    /// rebuild does not go back to the dead device.
    #[test]
    fn a_lost_device_moves_the_wind_to_the_cpu() {
        let Some(ctx) = test_context(|_| {}) else {
            return;
        };
        let layout = small_layout(48);
        let mut e = gpu_engine(&ctx, &layout);
        assert!(e.gpu.is_some(), "on the GPU first: {:?}", e.notice);
        for _ in 0..5 {
            e.step();
        }
        ctx.device.destroy();
        e.step();
        assert!(e.gpu.is_none(), "the wind left the lost device");
        let notice = e.notice.clone().unwrap_or_default();
        assert!(notice.contains("GPU"), "{notice}");
        let t = e.cpu.time();
        for _ in 0..5 {
            e.step();
        }
        assert!(e.cpu.time() > t, "the wind runs on the CPU");
        // Asking for the GPU again (a rebuild, the View menu) does not go back to it.
        e.rebuild(&layout, false);
        e.choose(&layout);
        assert!(e.gpu.is_none(), "not back onto a lost device");
        let notice = e.notice.clone().unwrap_or_default();
        assert!(notice.contains("GPU unusable"), "{notice}");
    }

    /// A reset or a new grid is shown at once: the view gets the new field (at rest, on the
    /// CPU, with no measurement claimed for it) before the automatic choice is measured again
    /// on a software adapter, which compiles the GPU passes (about a second on lavapipe, during
    /// which the old field used to stand frozen on screen); the measurement then made is the
    /// new grid's. On a hardware adapter nothing is measured and the field goes back to the GPU.
    #[test]
    fn a_rebuild_shows_the_new_field_before_measuring_again() {
        let Some(ctx) = test_context(|_| {}) else {
            return;
        };
        let software = ctx.is_software();
        let layout = small_layout(48);
        let mut e = Engine::new(&layout);
        e.ctx = Some(ctx.clone());
        e.choose(&layout);
        assert_eq!(e.measured.is_some(), software);
        for _ in 0..5 {
            e.step();
        }
        let smaller = small_layout(40);
        let mut shown = None;
        e.rebuild_showing(&smaller, false, |e| {
            let shared = Mutex::new(Arc::new(Snapshot::default()));
            e.publish(&shared, true);
            shown = Some(shared.lock().unwrap().clone());
        });
        let shown = shown.expect("the new field was shown");
        assert_eq!((shown.nx, shown.ny, shown.time), (40, 40, 0.0));
        assert!(
            shown.velocity.iter().flatten().all(|x| *x == 0.0),
            "at rest"
        );
        assert_eq!(
            shown.measured, None,
            "no measurement claimed for the new grid yet"
        );
        assert_eq!(e.measured.is_some(), software, "measured again afterwards");
        assert!(e.notice.is_none(), "{:?}", e.notice);
    }

    /// A grid whose velocity field is larger than the device can bind (a small GPU, here a
    /// device asked for a 1 MiB storage-buffer limit) runs on the CPU with a message saying
    /// why, instead of a validation error (a panic) at the first step.
    #[test]
    fn a_grid_over_the_buffer_limit_runs_on_the_cpu() {
        let Some(ctx) = test_context(|l| l.max_storage_buffer_binding_size = 1 << 20) else {
            return;
        };
        let layout = small_layout(520);
        let mut e = gpu_engine(&ctx, &layout);
        assert!(e.gpu.is_none());
        let notice = e.notice.clone().unwrap_or_default();
        assert!(
            notice.contains("520x520") && notice.contains("storage-buffer limit"),
            "{notice}"
        );
        e.step();
        assert!(e.cpu.time() > 0.0, "the wind runs on the CPU");
        assert!(ctx.fault().is_none(), "refused before any GPU error");
        // A grid that fits the same device runs there.
        let fits = small_layout(256);
        e.rebuild(&fits, false);
        e.choose(&fits);
        assert!(e.gpu.is_some(), "{:?}", e.notice);
    }

    /// A device that cannot make the passes at all (WebGPU's minimum limits: four storage
    /// buffers a shader stage) refuses them inside an error scope: an error naming the
    /// pipeline, the wind on the CPU, and no fault left on the device.
    #[test]
    fn a_device_that_cannot_make_the_passes_runs_the_wind_on_the_cpu() {
        let Some(ctx) = test_context(|l| *l = wgpu::Limits::downlevel_defaults()) else {
            return;
        };
        let layout = small_layout(64);
        let mut e = gpu_engine(&ctx, &layout);
        assert!(e.gpu.is_none());
        let notice = e.notice.clone().unwrap_or_default();
        assert!(
            notice.contains("GPU unusable") && notice.contains("storage"),
            "{notice}"
        );
        assert!(ctx.fault().is_none(), "caught by the error scope");
        e.step();
        assert!(e.cpu.time() > 0.0, "the wind runs on the CPU");
    }
}
