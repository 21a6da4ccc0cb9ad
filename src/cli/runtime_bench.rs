//! `windloom bench --runtime BAKE`: what the runtime (`src/runtime`) costs a game: the time
//! `wind_at_many` takes for `--samples` points a call, on one thread, and the memory the
//! bake takes once read.

use super::CliError;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;
use windloom_runtime::{Bake, Options};

/// What `bench --runtime --json` prints.
#[derive(Debug, serde::Serialize)]
pub struct RuntimeReport {
    pub bake: String,
    /// The format the wind was read from.
    pub format: String,
    pub grid: [usize; 2],
    pub frames: usize,
    pub samples_per_call: usize,
    pub calls: usize,
    /// Milliseconds a call: the median and the fastest.
    pub median_ms: f64,
    pub min_ms: f64,
    /// Nanoseconds a sample at the median.
    pub ns_per_sample: f64,
    /// Milliseconds per 100,000 samples at the median.
    pub ms_per_100k: f64,
    pub memory_bytes: usize,
    /// Milliseconds to open the bake (read and decode every file).
    pub open_ms: f64,
    pub cpu_simd: &'static str,
}

/// Points spread over the bake's rectangle (and a little beyond), from the ground to 1.2 ×
/// its 20 m default top, by a fixed sequence: the same points every run.
fn points(bake: &Bake, n: usize) -> Vec<[f32; 3]> {
    let (min, max) = bake.bounds();
    let mut s = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..n)
        .map(|_| {
            let x = min[0] - 2.0 + (max[0] - min[0] + 4.0) * next();
            let z = min[1] - 2.0 + (max[1] - min[1] + 4.0) * next();
            [x, bake.ground_at(x, z) + 24.0 * next(), z]
        })
        .collect()
}

pub fn run(dir: &Path, samples: usize, calls: usize, json: bool) -> Result<ExitCode, CliError> {
    if samples == 0 || calls == 0 {
        return Err(CliError::Message(
            "--samples and --steps must be at least 1 for --runtime".into(),
        ));
    }
    let start = Instant::now();
    let bake =
        Bake::open(dir, &Options::default()).map_err(|e| CliError::Message(e.to_string()))?;
    let open_ms = start.elapsed().as_secs_f64() * 1e3;
    let at = points(&bake, samples);
    let mut out = vec![[0.0f32; 3]; samples];
    // Each call at another moment between frames, as a game's clock runs.
    let mut times = Vec::with_capacity(calls);
    for k in 0..calls + 3 {
        let t = k as f64 * 0.37 / f64::from(bake.fps().max(1e-3));
        let s = Instant::now();
        bake.wind_at_many(std::hint::black_box(&at), t, &mut out);
        std::hint::black_box(&out);
        if k >= 3 {
            times.push(s.elapsed().as_secs_f64() * 1e3);
        }
    }
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    let report = RuntimeReport {
        bake: dir.display().to_string(),
        format: bake.source().0.to_string(),
        grid: bake.grid(),
        frames: bake.frames(),
        samples_per_call: samples,
        calls,
        median_ms: median,
        min_ms: times[0],
        ns_per_sample: median * 1e6 / samples as f64,
        ms_per_100k: median * 1e5 / samples as f64,
        memory_bytes: bake.memory_bytes(),
        open_ms,
        cpu_simd: crate::sim::bench::cpu_simd(),
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "runtime on {} ({}, {} x {} cells, {} frames, {:.1} MB in memory, opened in {:.0} ms)",
            report.bake,
            report.format,
            report.grid[0],
            report.grid[1],
            report.frames,
            report.memory_bytes as f64 / 1e6,
            report.open_ms
        );
        println!(
            "wind_at_many, {} samples a call, one thread: median {:.3} ms, min {:.3} ms ({:.1} ns a sample, {:.3} ms per 100,000; cpu_simd {})",
            samples,
            median,
            report.min_ms,
            report.ns_per_sample,
            report.ms_per_100k,
            report.cpu_simd
        );
    }
    Ok(ExitCode::SUCCESS)
}
