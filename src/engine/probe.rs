//! Probes: the wind at fixed points over time, its statistics (min, mean, max, gust
//! factor) and its CSV, for the editor's plots and `windloom probe`. The editor records the
//! live field's snapshots; [`run`] steps a layout headless, on the backend asked for.

use super::live::Snapshot;
use super::{Backend, Stepper};
use crate::doc::Layout;
use crate::gpu::GpuError;

/// One reading: the simulation time (s) and the wind there (m/s, `[x, z]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reading {
    pub time: f32,
    pub wind: [f32; 2],
}

impl Reading {
    pub fn speed(&self) -> f32 {
        crate::num::hypot(self.wind[0], self.wind[1])
    }

    /// The way the wind blows, in degrees from +x (east) toward +z (south), 0 to 360: the
    /// ambient layers' convention.
    pub fn direction_deg(&self) -> f32 {
        crate::num::atan2(self.wind[1], self.wind[0])
            .to_degrees()
            .rem_euclid(360.0)
    }
}

/// The seconds a gust is averaged over (the WMO's definition of a gust: the highest 3-second
/// mean speed).
pub const GUST_SECONDS: f32 = 3.0;

/// What a designer reads off a probe's record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stats {
    pub min: f32,
    pub mean: f32,
    pub max: f32,
    /// The highest [`GUST_SECONDS`] mean speed over the mean speed (1 for a steady wind;
    /// `NaN` when the mean is zero); over a record shorter than that, the highest reading.
    pub gust_factor: f32,
    /// The mean wind's direction (of the mean vector), degrees as [`Reading::direction_deg`].
    pub mean_direction_deg: f32,
}

/// The statistics of `readings` (in time order); `None` for none.
pub fn stats(readings: &[Reading]) -> Option<Stats> {
    let n = readings.len();
    if n == 0 {
        return None;
    }
    let speeds: Vec<f32> = readings.iter().map(Reading::speed).collect();
    let mean = speeds.iter().sum::<f32>() / n as f32;
    let min = speeds.iter().copied().fold(f32::INFINITY, f32::min);
    let max = speeds.iter().copied().fold(0.0, f32::max);
    // The highest mean over any window of GUST_SECONDS (two pointers over the readings).
    let mut gust = 0.0f32;
    let mut sum = 0.0;
    let mut start = 0;
    let span = readings[n - 1].time - readings[0].time;
    for (k, r) in readings.iter().enumerate() {
        sum += speeds[k];
        while r.time - readings[start].time > GUST_SECONDS {
            sum -= speeds[start];
            start += 1;
        }
        if span < GUST_SECONDS || r.time - readings[0].time >= GUST_SECONDS {
            gust = gust.max(sum / (k - start + 1) as f32);
        }
    }
    let gust = if span < GUST_SECONDS { max } else { gust };
    let mu = readings
        .iter()
        .fold([0.0, 0.0], |a, r| [a[0] + r.wind[0], a[1] + r.wind[1]]);
    let mean_vector = Reading {
        time: 0.0,
        wind: [mu[0] / n as f32, mu[1] / n as f32],
    };
    Some(Stats {
        min,
        mean,
        max,
        gust_factor: if mean > 0.0 { gust / mean } else { f32::NAN },
        mean_direction_deg: mean_vector.direction_deg(),
    })
}

/// The wind at `p` in a cell-centred field over the layout's grid (bilinear, as the map
/// reads it).
fn sample(layout: &Layout, field: Vec<[f32; 2]>, points: &[[f32; 2]]) -> Vec<[f32; 2]> {
    let snap = Snapshot {
        nx: layout.world.grid[0] as usize,
        ny: layout.world.grid[1] as usize,
        origin: layout.world.origin,
        size: layout.world.size,
        velocity: field,
        ..Default::default()
    };
    points.iter().map(|p| snap.sample(*p)).collect()
}

/// Runs `layout` from calm, `warmup` seconds unread, then `seconds` more reading the wind at
/// `points` `hz` times a second (every so many steps, the first at the end of the warm-up,
/// as a bake's first frame): one record per point, and a note where `auto` fell back to the
/// CPU. Each reading's time is the solver's clock, the one the editor and the bake keep.
pub fn run(
    layout: &Layout,
    points: &[[f32; 2]],
    warmup: f32,
    seconds: f32,
    hz: f32,
    backend: Backend,
) -> Result<(Vec<Vec<Reading>>, Option<String>), GpuError> {
    let (mut stepper, note) = Stepper::new(layout, backend)?;
    let dt = layout.sim.dt;
    let first = (warmup / dt).round() as usize;
    let steps = (seconds / dt).round().max(1.0) as usize;
    let every = (1.0 / (hz * dt)).round().max(1.0) as usize;
    for _ in 0..first {
        stepper.step();
    }
    let mut out = vec![Vec::new(); points.len()];
    for k in 0..steps {
        if k % every == 0 {
            let field = stepper.velocity_field()?;
            let time = stepper.seconds() as f32;
            for (record, wind) in out.iter_mut().zip(sample(layout, field, points)) {
                record.push(Reading { time, wind });
            }
        }
        if k + 1 < steps {
            stepper.step();
        }
    }
    Ok((out, note))
}

/// The records as CSV: `time_s`, then for each probe its speed (m/s), direction (degrees) and
/// wind components (m/s), one row per reading time (the records share their times).
pub fn csv(names: &[String], records: &[Vec<Reading>]) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["time_s".to_string()];
    for n in names {
        header.extend([
            format!("{n} speed_mps"),
            format!("{n} direction_deg"),
            format!("{n} x_mps"),
            format!("{n} z_mps"),
        ]);
    }
    w.write_record(&header).expect("CSV into memory");
    let rows = records.iter().map(Vec::len).min().unwrap_or(0);
    for k in 0..rows {
        let mut row = vec![format!("{:.4}", records[0][k].time)];
        for r in records {
            let r = r[k];
            row.extend([
                format!("{:.4}", r.speed()),
                format!("{:.2}", r.direction_deg()),
                format!("{:.4}", r.wind[0]),
                format!("{:.4}", r.wind[1]),
            ]);
        }
        w.write_record(&row).expect("CSV into memory");
    }
    String::from_utf8(w.into_inner().expect("CSV into memory")).expect("CSV of UTF-8 text")
}
