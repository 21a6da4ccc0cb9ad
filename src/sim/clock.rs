//! The simulation's clock, one for every solver and every caller (the editor, `probe`, the
//! GPU solver and the bake): time is the count of substeps times their length, computed in
//! f64, never summed step by step in f32 (which drifted −0.10 s after 10 minutes and −2.8 s
//! after an hour, so keyframes, windows and pulses fired late in the editor against the bake).

/// Simulated seconds, as substeps taken × their length (`dt / substeps`, as the solvers
/// step). A change of the length (an edit of `dt` or of the substeps) starts a new count
/// from the time reached.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clock {
    /// Seconds reached when the length last changed (or the clock was set).
    base: f64,
    /// Substeps of `length` since then.
    ticks: u64,
    /// One substep, seconds (the f32 the solvers step with, widened exactly).
    length: f64,
}

impl Default for Clock {
    fn default() -> Self {
        Self::at(0.0)
    }
}

impl Clock {
    /// A clock reading `seconds`.
    pub fn at(seconds: f64) -> Self {
        Self {
            base: seconds,
            ticks: 0,
            length: 0.0,
        }
    }

    /// One substep of `dt` seconds taken (the f32 the solver stepped with).
    #[inline]
    pub fn tick(&mut self, dt: f32) {
        let dt = f64::from(dt);
        if dt != self.length {
            *self = Self {
                base: self.seconds(),
                ticks: 0,
                length: dt,
            };
        }
        self.ticks += 1;
    }

    /// The time reached, seconds.
    #[inline]
    pub fn seconds(&self) -> f64 {
        self.base + self.ticks as f64 * self.length
    }

    /// The time reached as the forces take it, seconds.
    #[inline]
    pub fn time(&self) -> f32 {
        self.seconds() as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An hour of 60 Hz steps: the clock reads k / 60 s at every step k (to f64's rounding),
    /// where summing the f32 step drifted 2.8 s.
    #[test]
    fn an_hour_of_steps_keeps_time() {
        let dt = 1.0f32 / 60.0;
        let mut c = Clock::default();
        let mut summed = 0.0f32;
        for k in 1..=3600 * 60u64 {
            c.tick(dt);
            summed += dt;
            let exact = k as f64 * f64::from(dt);
            assert!((c.seconds() - exact).abs() < 1e-9, "step {k}");
        }
        assert!((c.seconds() - 3600.0).abs() < 1e-3);
        assert!(
            (f64::from(summed) - 3600.0).abs() > 1.0,
            "f32 sums drift: {summed}"
        );
    }

    /// A new step length starts counting from the time reached: no jump.
    #[test]
    fn a_new_step_length_continues_from_the_time_reached() {
        let mut c = Clock::at(2.0);
        c.tick(0.5);
        c.tick(0.5);
        assert_eq!(c.seconds(), 3.0);
        c.tick(0.25);
        assert_eq!(c.seconds(), 3.25);
    }
}
