//! When a bake's frames are taken: at exactly `warmup + k / fps` seconds of simulated time.
//!
//! The solver's step must not exceed the layout's `sim.dt`, and a frame interval of `1 / fps`
//! is rarely a whole number of such steps (24 fps at dt = 1/60 is 2.5 steps). Rounding the step
//! count, as earlier versions did, plays the wind at the wrong speed (24 fps came out 20% slow).
//! Instead the step count per frame is rounded *up* and the step shortened to fit:
//! `steps = ceil(1 / (fps · dt_max))`, `dt = 1 / (fps · steps)`.

/// How a bake steps the solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameTiming {
    /// Solver steps between two frames.
    pub steps_per_frame: usize,
    /// The step length used, seconds (≤ the layout's `sim.dt`, up to rounding).
    pub dt: f32,
    /// Steps before the first frame: the warm-up rounded to whole frames.
    pub warmup_steps: usize,
    /// Frames per second, as asked.
    pub fps: f64,
}

/// Relative slack before a step count is rounded up: `1 / (fps · dt)` computed in floats lands
/// a hair above a whole number when the true quotient is whole (60 fps at dt = 1/60).
const SLACK: f64 = 1e-4;

impl FrameTiming {
    /// Timing for frames at `fps` with steps of at most `dt_max` seconds after `warmup`
    /// seconds (rounded to the nearest whole frame). The caller has checked that `fps`,
    /// `dt_max` and `warmup` are finite and positive (zero for the warm-up).
    pub fn new(fps: f32, dt_max: f32, warmup: f32) -> Self {
        let fps = f64::from(fps);
        let per_frame = 1.0 / (fps * f64::from(dt_max));
        let steps_per_frame = ((per_frame * (1.0 - SLACK)).ceil() as usize).max(1);
        let dt = (1.0 / (fps * steps_per_frame as f64)) as f32;
        let warmup_frames = (f64::from(warmup) * fps).round() as usize;
        Self {
            steps_per_frame,
            dt,
            warmup_steps: warmup_frames * steps_per_frame,
            fps,
        }
    }

    /// Simulated time after `steps` steps, computed from the count (not accumulated), so
    /// frame `k` sits at `warmup + k / fps` to the precision of an `f64`.
    pub fn time_after(&self, steps: usize) -> f64 {
        steps as f64 / (self.fps * self.steps_per_frame as f64)
    }

    /// The warm-up actually simulated, seconds.
    pub fn warmup_seconds(&self) -> f64 {
        self.time_after(self.warmup_steps)
    }
}
