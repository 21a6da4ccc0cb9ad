//! `windloom bench --backend gpu`: wall time per GPU step (each step submitted and waited
//! for), GPU time per pass from timestamp queries where the adapter has them, the adapter that
//! ran it and the bytes a step must move, so the figure can be set against a GPU's memory
//! bandwidth. Speed is measured here, never asserted in tests.

use super::{GpuContext, GpuError, GpuSolver};
use crate::doc::Layout;
use crate::sim::Solver;
use crate::sim::bench::{median, pass_bytes};
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Instant;

#[derive(Debug, Clone, Serialize)]
pub struct AdapterReport {
    pub name: String,
    pub device_type: String,
    pub backend: String,
    pub driver: String,
    pub driver_info: String,
}

#[derive(Debug, Clone, Serialize)]
pub struct GpuBenchReport {
    pub backend: &'static str,
    pub adapter: AdapterReport,
    pub layout: String,
    pub grid: [usize; 2],
    pub iterations: u32,
    /// The pressure solve: `jacobi` or `multigrid`, with its V-cycles per projection.
    pub pressure: crate::doc::PressureSolve,
    pub cycles: u32,
    /// The same in words, e.g. "20 Jacobi iterations" or "2 multigrid V-cycles".
    pub solve: String,
    pub steps: usize,
    /// Milliseconds per step, recording to completion, median and best, timed without
    /// timestamp queries.
    pub median_ms: f64,
    pub min_ms: f64,
    /// Median milliseconds the CPU takes to record and submit a step (part of `median_ms`):
    /// what the step costs beyond the GPU's own work.
    pub record_ms: f64,
    /// Median milliseconds a step of the profiled steps below, timestamps and their
    /// read-back included (`None` without timestamps).
    pub profiled_median_ms: Option<f64>,
    /// Median GPU milliseconds per pass from timestamp queries, over as many steps again
    /// after the timed ones (empty where the adapter has none: see `timestamps`).
    pub passes_ms: BTreeMap<&'static str, f64>,
    pub timestamps: bool,
    /// Bytes the passes must read and write per step (each array element once; the CPU
    /// solver's count), for the bandwidth arithmetic in docs/PERFORMANCE.md.
    pub bytes_per_step: u64,
    /// `bytes_per_step / median` in GB/s: the memory bandwidth the step achieves.
    pub effective_gb_s: f64,
}

/// Runs `steps` timed steps (after `warmup` untimed ones) of `layout` on the GPU.
pub fn run(
    ctx: &GpuContext,
    layout: &Layout,
    name: &str,
    warmup: usize,
    steps: usize,
) -> Result<GpuBenchReport, GpuError> {
    let mut s = GpuSolver::new(ctx, layout)?;
    for _ in 0..warmup {
        s.step(ctx);
    }
    s.finish(ctx)?;
    let mut totals = Vec::with_capacity(steps.max(1));
    let mut recording = Vec::with_capacity(steps.max(1));
    for _ in 0..steps.max(1) {
        let t = Instant::now();
        s.step(ctx);
        recording.push(t.elapsed().as_secs_f64() * 1e3);
        s.finish(ctx)?;
        totals.push(t.elapsed().as_secs_f64() * 1e3);
    }
    // The per-pass split separately: timestamps around every dispatch change what they time.
    let timestamps = s.enable_profiling(ctx);
    let mut per_pass: BTreeMap<&'static str, Vec<f64>> = BTreeMap::new();
    let mut profiled = Vec::new();
    if timestamps {
        for _ in 0..steps.max(1) {
            let t = Instant::now();
            s.step(ctx);
            s.finish(ctx)?;
            profiled.push(t.elapsed().as_secs_f64() * 1e3);
            for (pass, ms) in s.pass_times(ctx)? {
                per_pass.entry(pass).or_default().push(ms);
            }
        }
        s.disable_profiling();
    }
    // The byte count of a step whose forces reach every face (an upper bound for arrows).
    let cpu = Solver::new(layout);
    let faces = (cpu.nx + 1) * cpu.ny + cpu.nx * (cpu.ny + 1);
    let bytes_per_step: u64 = pass_bytes(&cpu, faces, false)
        .iter()
        .map(|(_, b)| b)
        .sum::<u64>()
        * u64::from(layout.sim.substeps.max(1));
    let median_ms = median(&mut totals.clone());
    let info = &ctx.adapter;
    Ok(GpuBenchReport {
        backend: "gpu",
        adapter: AdapterReport {
            name: info.name.clone(),
            device_type: format!("{:?}", info.device_type),
            backend: format!("{:?}", info.backend),
            driver: info.driver.clone(),
            driver_info: info.driver_info.clone(),
        },
        layout: name.to_string(),
        grid: [s.nx, s.ny],
        iterations: layout.sim.pressure_iterations,
        pressure: layout.sim.pressure,
        cycles: layout.sim.pressure_cycles,
        solve: crate::sim::bench::solve_words(&layout.sim),
        steps: steps.max(1),
        median_ms,
        min_ms: totals.iter().copied().fold(f64::MAX, f64::min),
        record_ms: median(&mut recording),
        profiled_median_ms: (!profiled.is_empty()).then(|| median(&mut profiled)),
        passes_ms: per_pass
            .into_iter()
            .map(|(k, mut v)| (k, median(&mut v)))
            .collect(),
        timestamps,
        bytes_per_step,
        effective_gb_s: bytes_per_step as f64 / (median_ms * 1e-3) / 1e9,
    })
}
