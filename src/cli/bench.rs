//! `windloom bench`: the solver's time per step (CPU or GPU) on one layout or every bundled
//! example, or the grass's time per frame with `--grass N`; a table, or JSON with `--json`.

use super::{CliError, Command, OnOff, camera_from};
use crate::engine::Backend;
use crate::{doc, io};
use std::path::Path;
use std::process::ExitCode;

/// The bundled examples `bench --layout all` runs, first the default bench layout.
const BENCH_LAYOUTS: [(&str, &str); 5] = [
    (
        "layouts/obstacles.json",
        include_str!("../../layouts/obstacles.json"),
    ),
    (
        "layouts/meadow.json",
        include_str!("../../layouts/meadow.json"),
    ),
    (
        "layouts/two-winds.json",
        include_str!("../../layouts/two-winds.json"),
    ),
    (
        "layouts/breeze-fft.json",
        include_str!("../../layouts/breeze-fft.json"),
    ),
    (
        "layouts/branching.json",
        include_str!("../../layouts/branching.json"),
    ),
];

/// Whether `--layout` asks for every bundled example.
fn is_all(layout: Option<&Path>) -> bool {
    layout.is_some_and(|p| p.as_os_str() == "all")
}

/// The layouts a solver bench runs: the one given, every bundled example for `all`, or the
/// obstacles example.
fn bench_layouts(layout: Option<&Path>) -> Result<Vec<(doc::Layout, String)>, CliError> {
    let bundled = |(name, text): (&str, &str)| -> Result<(doc::Layout, String), CliError> {
        let l = doc::parse(text).map_err(|e| CliError::Message(format!("{name}: {e}")))?;
        Ok((l, name.to_string()))
    };
    match layout {
        Some(_) if is_all(layout) => BENCH_LAYOUTS.into_iter().map(bundled).collect(),
        Some(p) => Ok(vec![(io::load(p)?, p.display().to_string())]),
        None => Ok(vec![bundled(BENCH_LAYOUTS[0])?]),
    }
}

/// Runs a `Command::Bench`.
pub fn run(command: Command) -> Result<ExitCode, CliError> {
    let Command::Bench {
        backend,
        grid,
        iterations,
        steps,
        warmup,
        threads,
        layout,
        advection,
        pressure,
        cycles,
        json,
        grass,
        model,
        cull,
        camera,
        size,
        wind_colours,
        estimate,
        stored_order,
        runtime,
        samples,
    } = command
    else {
        unreachable!("bench::run is called with a bench command");
    };
    if let Some(dir) = runtime {
        return super::runtime_bench::run(&dir, samples, steps, json);
    }
    if let Some(blades) = grass {
        let l = match &layout {
            Some(p) => io::load(p)?,
            None => doc::default_layout(),
        };
        if blades > crate::grass::MAX_BLADES {
            return Err(CliError::Message(format!(
                "--grass: at most {} blades",
                crate::grass::MAX_BLADES
            )));
        }
        if estimate {
            return grass_estimate(&l, blades, camera.map(camera_from), size, json);
        }
        let options = crate::gpu::grass::BenchOptions {
            blades,
            size,
            frames: steps.clamp(1, 100),
            model,
            cull: cull == OnOff::On,
            camera: camera.map(camera_from),
            wind_colours,
            near_first: !stored_order,
        };
        return grass_bench(&l, &options, json);
    }
    let solver = SolverBench {
        backend,
        grid,
        iterations,
        cycles,
        pressure,
        advection,
        warmup,
        steps,
        threads,
        json,
    };
    solver.run(layout.as_deref())
}

/// Times the grass and prints the report.
fn grass_bench(
    l: &doc::Layout,
    options: &crate::gpu::grass::BenchOptions,
    json: bool,
) -> Result<ExitCode, CliError> {
    let ctx = crate::gpu::GpuContext::headless()?;
    let r = crate::gpu::grass::bench(&ctx, l, options)?;
    if json {
        println!("{}", serde_json::to_string(&r)?);
    } else {
        println!(
            "{} blades ({}, culling {}) at {}x{} on {} ({}): median {:.2} ms, min {:.2} ms a frame over {} frames (compute passes alone {:.2} ms, drawing alone {:.2} ms); drawn per LOD {:?} ({} triangles), culled by orientation {}, frustum {}, distance {}",
            r.blades,
            r.model,
            if r.cull { "on" } else { "off" },
            r.size[0],
            r.size[1],
            r.adapter,
            r.adapter_type,
            r.median_ms,
            r.min_ms,
            r.frames,
            r.compute_ms,
            r.draw_ms,
            r.culled.drawn,
            r.triangles,
            r.culled.orientation,
            r.culled.frustum,
            r.culled.distance,
        );
        let order = if r.near_first {
            "nearest first"
        } else {
            "in their stored order"
        };
        match r.written {
            Some(w) => println!(
                "the render pass wrote {} samples, each sample {:.2} times (blades {order})",
                w.samples, w.layers
            ),
            None => println!(
                "blades drawn {order}; the samples written are not counted on a GL adapter"
            ),
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// What the cull would draw of `blades` blades of `l` at `camera` (the bench's when `None`)
/// in a picture of `size`: its CPU twin on a sample of them, printed.
fn grass_estimate(
    l: &doc::Layout,
    blades: usize,
    camera: Option<crate::gpu::grass::Camera>,
    size: [u32; 2],
    json: bool,
) -> Result<ExitCode, CliError> {
    let r = crate::gpu::grass::estimate(l, blades, camera, size);
    if json {
        println!("{}", serde_json::to_string(&r)?);
    } else {
        println!(
            "{} blades at {}x{}: the cull would draw about {:?} per LOD level, {} triangles a frame (estimated from {} of them on the CPU)",
            r.blades, r.size[0], r.size[1], r.drawn, r.triangles, r.sample
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The solver bench's settings.
struct SolverBench {
    backend: Backend,
    grid: [u32; 2],
    iterations: u32,
    cycles: u32,
    pressure: doc::PressureSolve,
    advection: doc::Advection,
    warmup: usize,
    steps: usize,
    threads: Option<usize>,
    json: bool,
}

impl SolverBench {
    /// Times each layout and prints its report: one JSON object for one layout, an array
    /// for `--layout all`.
    fn run(&self, layout: Option<&Path>) -> Result<ExitCode, CliError> {
        // One device (or one thread pool) for every layout of the run.
        let ctx = match self.backend {
            Backend::Gpu => Some(crate::gpu::GpuContext::headless()?),
            _ => None,
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads.unwrap_or(0))
            .build()
            .map_err(|e| CliError::failed("could not start the worker threads".into(), e))?;
        let mut reports = Vec::new();
        for (mut l, name) in bench_layouts(layout)? {
            l.world.grid = self.grid;
            l.sim.pressure_iterations = self.iterations;
            l.sim.pressure_cycles = self.cycles;
            l.sim.pressure = self.pressure;
            l.sim.advection = self.advection;
            if let Some(i) = doc::validate(&l).first() {
                return Err(CliError::Message(format!("bench settings ({name}): {i}")));
            }
            let report = match &ctx {
                Some(ctx) => self.gpu(ctx, &l, &name)?,
                None => self.cpu(&pool, &l, &name)?,
            };
            reports.push(report);
        }
        if self.json {
            let out = if is_all(layout) {
                serde_json::Value::Array(reports)
            } else {
                reports.remove(0)
            };
            println!("{}", serde_json::to_string(&out)?);
        }
        Ok(ExitCode::SUCCESS)
    }

    fn gpu(
        &self,
        ctx: &crate::gpu::GpuContext,
        l: &doc::Layout,
        name: &str,
    ) -> Result<serde_json::Value, CliError> {
        let r = crate::gpu::bench::run(ctx, l, name, self.warmup, self.steps)?;
        if !self.json {
            println!(
                "{} {}x{}, {}, GPU {} ({}): median {:.2} ms, min {:.2} ms per step (recording {:.2} ms of it), {:.1} GB/s effective",
                r.layout,
                r.grid[0],
                r.grid[1],
                r.solve,
                r.adapter.name,
                r.adapter.device_type,
                r.median_ms,
                r.min_ms,
                r.record_ms,
                r.effective_gb_s
            );
            for (pass, ms) in &r.passes_ms {
                println!("  {pass:<12} {ms:8.3} ms (GPU timestamps)");
            }
        }
        Ok(serde_json::to_value(&r)?)
    }

    fn cpu(
        &self,
        pool: &rayon::ThreadPool,
        l: &doc::Layout,
        name: &str,
    ) -> Result<serde_json::Value, CliError> {
        let report = pool.install(|| crate::sim::bench::run_cpu(l, name, self.warmup, self.steps));
        if !self.json {
            println!(
                "{} {}x{}, {}, {} threads, {}: median {:.2} ms, min {:.2} ms per step",
                report.layout,
                report.grid[0],
                report.grid[1],
                report.solve,
                report.threads,
                report.cpu_simd,
                report.median_ms,
                report.min_ms
            );
            for (pass, ms) in &report.passes_ms {
                let mb = report.passes_bytes[pass] as f64 / 1e6;
                println!("  {pass:<28} {ms:8.2} ms  {mb:9.1} MB");
            }
            println!(
                "  bandwidth {:.1} GB/s, bound {:.2} ms, ratio {:.2}; unfused bound {:.2} ms, ratio {:.2}",
                report.bandwidth_gb_s,
                report.bound_ms,
                report.ratio_to_bound,
                report.unfused_bound_ms,
                report.ratio_to_unfused_bound
            );
            println!(
                "  projection: RMS divergence {:.3e} -> {:.3e} (cut {:.1}x)",
                report.divergence_before, report.divergence_after, report.divergence_reduction
            );
        }
        Ok(serde_json::to_value(&report)?)
    }
}
