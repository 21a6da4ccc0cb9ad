//! The `windloom` binary: parses arguments and hands over to the library.

use anyhow::Context;
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use windloom::{doc, io};

const AFTER_HELP: &str = "\
Examples:
  windloom                               open the editor on the bundled default layout
  windloom layouts/obstacles.json        open the editor on a layout
  windloom validate layouts/*.json       check layout files, print every error
  windloom schema > layout.schema.json   the JSON Schema of the layout format
  windloom fmt my-level.json             rewrite a layout in canonical form
  windloom bench --backend cpu --grid 1000 --iterations 20 --steps 30 --json";

/// Author wind over a top-down map of a level, simulate it, and export it for game engines.
#[derive(Parser)]
#[command(version, about, after_help = AFTER_HELP, args_conflicts_with_subcommands = true)]
struct Cli {
    /// Layout to open in the editor (the bundled default layout when omitted).
    file: Option<PathBuf>,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Check layout files. Prints `FILE: ok` or every error as `FILE:LINE:COLUMN: path: message`;
    /// exits 0 only if every file is valid.
    ///
    /// Example: windloom validate layouts/meadow.json layouts/two-winds.json
    Validate {
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// Print the JSON Schema of the layout format (also in docs/layout.schema.json).
    ///
    /// Example: windloom schema > layout.schema.json
    Schema,
    /// Rewrite layout files in canonical form (stable field order, pretty-printed), atomically.
    /// Invalid files are reported and left untouched.
    ///
    /// Example: windloom fmt layouts/*.json
    Fmt {
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// Benchmark the solver: median and min ms per step, the per-pass split, the bytes each
    /// pass moves and the memory bandwidth measured in the same run.
    ///
    /// Example: windloom bench --backend cpu --grid 1000 --iterations 20 --steps 30 --json
    Bench {
        /// Which solver to time.
        #[arg(long, value_enum, default_value_t = Backend::Cpu)]
        backend: Backend,
        /// Grid cells per axis (N × N).
        #[arg(long, default_value_t = 512)]
        grid: u32,
        /// Jacobi pressure iterations per step.
        #[arg(long, default_value_t = 20)]
        iterations: u32,
        /// Timed steps.
        #[arg(long, default_value_t = 30)]
        steps: usize,
        /// Untimed steps first, so the field is developed.
        #[arg(long, default_value_t = 5)]
        warmup: usize,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Layout to run (default: the bundled obstacles example, resized to the grid).
        #[arg(long)]
        layout: Option<PathBuf>,
        /// Advection scheme.
        #[arg(long, value_enum, default_value_t = AdvectionArg::SemiLagrangian)]
        advection: AdvectionArg,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
    },
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Backend {
    Cpu,
    Gpu,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum AdvectionArg {
    SemiLagrangian,
    MacCormack,
}

const BENCH_LAYOUT: &str = include_str!("../layouts/obstacles.json");

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        None => {
            let doc = match &cli.file {
                Some(path) => io::load(path)?,
                None => doc::default_layout(),
            };
            windloom::app::run(doc, cli.file)
                .map_err(|e| anyhow::anyhow!("could not open the editor window: {e}"))?;
            Ok(ExitCode::SUCCESS)
        }
        Some(Command::Validate { files }) => {
            let mut ok = true;
            for f in &files {
                match io::load(f) {
                    Ok(_) => println!("{}: ok", f.display()),
                    Err(e) => {
                        ok = false;
                        println!("{e}");
                    }
                }
            }
            Ok(if ok {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            })
        }
        Some(Command::Schema) => {
            println!("{}", serde_json::to_string_pretty(&doc::schema())?);
            Ok(ExitCode::SUCCESS)
        }
        Some(Command::Fmt { files }) => {
            let mut ok = true;
            for f in &files {
                match io::load(f) {
                    Ok(layout) => io::save(f, &layout)
                        .with_context(|| format!("could not write {}", f.display()))?,
                    Err(e) => {
                        ok = false;
                        eprintln!("{e}");
                    }
                }
            }
            Ok(if ok {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            })
        }
        Some(Command::Bench {
            backend,
            grid,
            iterations,
            steps,
            warmup,
            threads,
            layout,
            advection,
            json,
        }) => {
            if backend == Backend::Gpu {
                anyhow::bail!("the GPU solver is not built yet: use --backend cpu");
            }
            let (mut l, name) = match &layout {
                Some(p) => (io::load(p)?, p.display().to_string()),
                None => (
                    doc::parse(BENCH_LAYOUT).map_err(|e| anyhow::anyhow!("{e}"))?,
                    "layouts/obstacles.json".to_string(),
                ),
            };
            l.world.grid = [grid, grid];
            l.sim.pressure_iterations = iterations;
            l.sim.advection = match advection {
                AdvectionArg::SemiLagrangian => doc::Advection::SemiLagrangian,
                AdvectionArg::MacCormack => doc::Advection::MacCormack,
            };
            let issues = doc::validate(&l);
            if let Some(i) = issues.first() {
                anyhow::bail!("bench settings: {i}");
            }
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads.unwrap_or(0))
                .build()?;
            let report = pool.install(|| windloom::sim::bench::run_cpu(&l, &name, warmup, steps));
            if json {
                println!("{}", serde_json::to_string(&report)?);
            } else {
                println!(
                    "{} {}x{}, {} Jacobi iterations, {} threads: median {:.2} ms, min {:.2} ms per step",
                    report.layout,
                    report.grid[0],
                    report.grid[1],
                    report.iterations,
                    report.threads,
                    report.median_ms,
                    report.min_ms
                );
                for (pass, ms) in &report.passes_ms {
                    let mb = report.passes_bytes[pass] as f64 / 1e6;
                    println!("  {pass:<12} {ms:8.2} ms  {mb:9.1} MB");
                }
                println!(
                    "  bandwidth {:.1} GB/s, bound {:.2} ms, ratio {:.2}",
                    report.bandwidth_gb_s, report.bound_ms, report.ratio_to_bound
                );
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}
