//! The solver benchmark behind `windloom bench`: times steps and passes, counts the bytes each
//! pass must move, and measures the machine's memory bandwidth in the same run, so the result
//! can be compared with the bandwidth bound. Speed is measured here, never asserted in tests.

use super::Solver;
use super::solver::Multigrid;
use crate::doc::{Advection, Layout, PressureSolve};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::time::Instant;

#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    pub backend: &'static str,
    pub layout: String,
    pub grid: [usize; 2],
    pub iterations: u32,
    /// The pressure solve: `jacobi` or `multigrid`, with its V-cycles per projection.
    pub pressure: PressureSolve,
    pub cycles: u32,
    /// The same in words, e.g. "20 Jacobi iterations" or "2 multigrid V-cycles".
    pub solve: String,
    pub steps: usize,
    pub threads: usize,
    /// The widest SIMD extension the CPU reports; the vectorised kernels are compiled for
    /// several levels and pick theirs at run time.
    pub cpu_simd: &'static str,
    pub advection: Advection,
    pub median_ms: f64,
    pub min_ms: f64,
    /// Median milliseconds per pass.
    pub passes_ms: BTreeMap<&'static str, f64>,
    /// Bytes each pass reads plus writes per step (each array element once).
    pub passes_bytes: BTreeMap<&'static str, u64>,
    pub bytes_per_step: u64,
    /// Parallel copy bandwidth measured in this run, (read + write bytes) / s.
    pub bandwidth_gb_s: f64,
    /// `bytes_per_step / bandwidth`: the fastest a step could be if every pass streamed.
    pub bound_ms: f64,
    /// `median_ms / bound_ms`.
    pub ratio_to_bound: f64,
    /// The same step's bytes and bound if every pass ran separately (the unfused pipeline
    /// the GPU still runs: steps 2–4 as three passes, MacCormack as three sweeps): the
    /// reference the fused passes are measured against; and `median_ms` over that bound.
    pub unfused_bytes_per_step: u64,
    /// Of `passes_bytes.forces`, the splat gains the CPU step keeps and reads back each step
    /// (`solver/gains.rs`); the unfused count has none (its forces compute them).
    pub gain_bytes_per_step: u64,
    pub unfused_bound_ms: f64,
    pub ratio_to_unfused_bound: f64,
    /// RMS divergence over fluid cells before the pressure solve and after the gradient
    /// subtraction, in one more (untimed) step after the timed ones, and their ratio: how
    /// much the projection cut the divergence in a step of the developed flow.
    pub divergence_before: f32,
    pub divergence_after: f32,
    pub divergence_reduction: f32,
}

/// The pressure solve in words.
pub fn solve_words(p: &crate::doc::SimParams) -> String {
    match p.pressure {
        PressureSolve::Jacobi => format!("{} Jacobi iterations", p.pressure_iterations),
        PressureSolve::Multigrid => format!("{} multigrid V-cycles", p.pressure_cycles),
    }
}

/// Bytes of kept splat gains the last forces pass read back (`solver/gains.rs`).
fn gain_bytes(s: &Solver) -> u64 {
    4 * s.force_gain_floats as u64
}

/// Bytes each pass must read and write for one step (see docs/PERFORMANCE.md): with `fused`,
/// as the CPU step runs them (steps 2–4 in one sweep when it confines vorticity, MacCormack's
/// backward step and correction in one, the splat gains read back from memory), else as
/// separate passes (the GPU's).
pub fn pass_bytes(s: &Solver, force_faces: usize, fused: bool) -> Vec<(&'static str, u64)> {
    let c = (s.nx * s.ny) as u64;
    let f = ((s.nx + 1) * s.ny + s.nx * (s.ny + 1)) as u64;
    let k = u64::from(s.params.pressure_iterations);
    let advection = match s.params.advection {
        Advection::SemiLagrangian => 9 * f,
        // Fused: the forward sweep 9F, then the backward step and the correction in one
        // sweep: read u, v (velocities and φ), φ̂, masks, write φ' (13F). Unfused, the
        // backward sweep also writes φ̌ and the correction reads u, v and φ̌ again (39F).
        Advection::MacCormack if fused => 22 * f,
        Advection::MacCormack => 39 * f,
    };
    let confinement = if s.params.vorticity > 0.0 {
        12 * c + 20 * c + 9 * f
    } else {
        0
    };
    // Fused: the faces and their free masks read once, the solid mask once, the new faces,
    // the curl and the divergence written once.
    let steps_2_4 = if fused && s.fuses_vorticity() {
        vec![("curl_confinement_divergence", 9 * f + 9 * c)]
    } else {
        vec![
            ("curl", 4 * f + 5 * c),
            ("confinement", confinement),
            ("divergence", 4 * f + 5 * c),
        ]
    };
    // The faces the forces reach (velocities, the other component's four, free mask,
    // increment written and added); the CPU step also reads back the splat gains it keeps
    // (the separate passes, the GPU's, compute them).
    let gains = if fused { gain_bytes(s) } else { 0 };
    let mut passes = vec![("forces", 25 * force_faces as u64 + gains)];
    passes.extend(steps_2_4);
    passes.extend([
        ("pressure", pressure_bytes(s, k)),
        ("gradient", 4 * c + 9 * f),
        ("advection", advection),
    ]);
    passes
}

/// Bytes of one projection's pressure solve: Jacobi's warm start and `k` iterations, or the
/// multigrid V-cycles (see [`Multigrid::solve_bytes`]).
fn pressure_bytes(s: &Solver, k: u64) -> u64 {
    let c = (s.nx * s.ny) as u64;
    match s.params.pressure {
        PressureSolve::Jacobi => 8 * c + 13 * c * k,
        PressureSolve::Multigrid => {
            let cycles = u64::from(s.params.pressure_cycles);
            match &s.multigrid {
                Some(mg) => mg.solve_bytes(cycles),
                None => Multigrid::new(s.nx, s.ny, s.hx, s.hz, &s.flags, s.params.boundary)
                    .solve_bytes(cycles),
            }
        }
    }
}

/// Best-of-five parallel copy bandwidth over 2 × 256 MiB, in GB/s (read + write bytes).
pub fn measure_bandwidth() -> f64 {
    let n = 64 << 20;
    let src = vec![1.0f32; n];
    let mut dst = vec![0.0f32; n];
    let chunk = n / (rayon::current_num_threads() * 8).max(1);
    let mut best = f64::MAX;
    for _ in 0..5 {
        let t = Instant::now();
        dst.par_chunks_mut(chunk)
            .zip(src.par_chunks(chunk))
            .for_each(|(d, s)| d.copy_from_slice(s));
        best = best.min(t.elapsed().as_secs_f64());
    }
    std::hint::black_box(&dst);
    (2 * n * 4) as f64 / best / 1e9
}

/// The widest SIMD extension the solver's kernels use: the one `multiversion` picked for its
/// clones on this CPU (at run time), or, in a `windloom_static_simd` build, the one the
/// build targets. Asked of a function compiled the way the kernels are, so it follows
/// `multiversion`'s own rules: its AVX-512 clone needs Ice Lake's extensions too (VBMI2,
/// VNNI, BITALG, GFNI, VAES…), and an AVX-512 CPU without them (Skylake-X), or a build for
/// `x86-64-v4` alone, runs the AVX2 clones.
pub fn cpu_simd() -> &'static str {
    // A `&'static str` either way: the static build's names carry a suffix.
    macro_rules! name {
        ($s:literal) => {
            if cfg!(windloom_static_simd) {
                concat!($s, " (static)")
            } else {
                $s
            }
        };
    }
    #[cfg_attr(
        not(windloom_static_simd),
        multiversion::multiversion(targets = "simd")
    )]
    #[cfg_attr(
        windloom_static_simd,
        multiversion::multiversion(targets = "simd", dispatcher = "static")
    )]
    fn selected() -> &'static str {
        // The first arm the clone's target matches (its features, detected or built in).
        multiversion::target::match_target! {
            "x86_64+avx512f" => name!("avx512"),
            "x86_64+avx2" => name!("avx2"),
            "x86_64+sse4.1" => name!("sse4.1"),
            "x86_64" => name!("sse2"),
            "aarch64" => name!("neon"),
            _ => "none",
        }
    }
    selected()
}

/// Bytes the terrain pass moves: each face reads both components (each element counted
/// once), its coefficients, and writes its shaped value.
fn terrain_bytes(s: &Solver) -> u64 {
    let faces = (s.u.len() + s.v.len()) as u64;
    faces * (4 * 3 + std::mem::size_of::<super::terrain::Cell>() as u64)
}

pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Runs `steps` timed steps (after `warmup` untimed ones) of `layout` on the CPU solver.
pub fn run_cpu(layout: &Layout, name: &str, warmup: usize, steps: usize) -> BenchReport {
    let bandwidth = measure_bandwidth();
    let mut s = Solver::new(layout);
    for _ in 0..warmup {
        s.step();
    }
    let mut totals = Vec::with_capacity(steps);
    let mut per_pass: BTreeMap<&'static str, Vec<f64>> = BTreeMap::new();
    let mut bytes: BTreeMap<&'static str, u64> = BTreeMap::new();
    let mut unfused_bytes = 0;
    let mut gain_bytes_total = 0;
    // The shaped faces' buffers, kept as a reader keeps its own (a first touch of fresh pages
    // each read would time the allocator, not the pass).
    let (mut su, mut sv) = (vec![0.0; s.u.len()], vec![0.0; s.v.len()]);
    for _ in 0..steps.max(1) {
        s.timings = Default::default();
        let t = Instant::now();
        s.step();
        let mut ms = t.elapsed().as_secs_f64() * 1e3;
        if s.terrain.is_some() {
            // The terrain shapes the wind as it leaves the solver: on the GPU every step, on
            // the CPU every frame read; timed here as one more pass of the step.
            let t = Instant::now();
            if let Some(terrain) = &s.terrain {
                terrain.shape_faces_into((&s.u, &s.v), s.free_faces(), (&mut su, &mut sv));
            }
            std::hint::black_box((&su, &sv));
            let terrain = t.elapsed().as_secs_f64() * 1e3;
            per_pass.entry("terrain").or_default().push(terrain);
            *bytes.entry("terrain").or_default() += terrain_bytes(&s);
            ms += terrain;
        }
        totals.push(ms);
        let passes = pass_bytes(&s, s.force_faces, true);
        for (name, secs) in s.timings.as_pairs() {
            if passes.iter().any(|(p, _)| *p == name) {
                per_pass.entry(name).or_default().push(secs * 1e3);
            }
        }
        for (name, b) in passes {
            *bytes.entry(name).or_default() += b * u64::from(s.params.substeps);
        }
        gain_bytes_total += gain_bytes(&s) * u64::from(s.params.substeps);
        unfused_bytes += pass_bytes(&s, s.force_faces, false)
            .iter()
            .map(|(_, b)| b)
            .sum::<u64>()
            * u64::from(s.params.substeps);
    }
    s.measure_projection = true;
    s.step();
    let (divergence_before, divergence_after) = s.projection.unwrap_or((0.0, 0.0));
    let n = steps.max(1) as u64;
    bytes.values_mut().for_each(|b| *b /= n);
    let bytes_per_step: u64 = bytes.values().sum();
    let unfused_bytes_per_step = unfused_bytes / n;
    let unfused_bound_ms = unfused_bytes_per_step as f64 / (bandwidth * 1e9) * 1e3;
    let median_ms = median(&mut totals.clone());
    let min_ms = totals.iter().copied().fold(f64::MAX, f64::min);
    let bound_ms = bytes_per_step as f64 / (bandwidth * 1e9) * 1e3;
    BenchReport {
        backend: "cpu",
        layout: name.to_string(),
        grid: [s.nx, s.ny],
        iterations: s.params.pressure_iterations,
        pressure: s.params.pressure,
        cycles: s.params.pressure_cycles,
        solve: solve_words(&s.params),
        steps: steps.max(1),
        threads: rayon::current_num_threads(),
        cpu_simd: cpu_simd(),
        advection: s.params.advection,
        median_ms,
        min_ms,
        passes_ms: per_pass
            .into_iter()
            .map(|(k, mut v)| (k, median(&mut v)))
            .collect(),
        passes_bytes: bytes,
        bytes_per_step,
        bandwidth_gb_s: bandwidth,
        bound_ms,
        ratio_to_bound: median_ms / bound_ms,
        unfused_bytes_per_step,
        gain_bytes_per_step: gain_bytes_total / n,
        unfused_bound_ms,
        ratio_to_unfused_bound: median_ms / unfused_bound_ms,
        divergence_before,
        divergence_after,
        divergence_reduction: divergence_before / divergence_after.max(f32::MIN_POSITIVE),
    }
}
