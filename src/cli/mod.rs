//! The commands of the `windloom` binary, as a library: [`Cli`] is what it takes, [`run`]
//! does it. One file per command; `main.rs` keeps logging, the one-line error and the exit
//! code. Everything here calls the same library code the editor calls: only the window is
//! the editor's own.

mod args;
mod bake;
mod bench;
mod editor;
mod fmt;
mod probe;
mod render;
mod runtime_bench;
mod sample;
mod validate;

pub use args::{Cli, Command, OnOff, RenderView, SampleOutside};

use crate::doc;
use std::process::ExitCode;

/// The error of a command. Its message (and its causes, in [`std::error::Error::source`])
/// is what the user reads, on one line.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A message that says it all: a flag's value refused (naming the flag), the editor's
    /// window that cannot open.
    #[error("{0}")]
    Message(String),
    /// A step that failed, with its cause.
    #[error("{what}")]
    Failed {
        what: String,
        #[source]
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    #[error(transparent)]
    Load(#[from] crate::io::LoadError),
    #[error(transparent)]
    Bake(#[from] crate::bake::BakeError),
    #[error(transparent)]
    Gpu(#[from] crate::gpu::GpuError),
    #[error(transparent)]
    Render(#[from] crate::render::RenderError),
    #[error(transparent)]
    Json(#[from] serde_json::Error),
}

impl CliError {
    /// `what` failed because of `source`.
    fn failed(what: String, source: impl std::error::Error + Send + Sync + 'static) -> Self {
        Self::Failed {
            what,
            source: Box::new(source),
        }
    }
}

/// Runs the command `cli` names, or opens the editor when it names none.
pub fn run(cli: Cli) -> Result<ExitCode, CliError> {
    match cli.command {
        None => editor::run(cli.file, cli.backend, cli.view),
        Some(Command::Validate { files }) => validate::run(&files),
        Some(Command::Schema { manifest }) => {
            let schema = if manifest {
                crate::bake::manifest_schema()
            } else {
                doc::schema()
            };
            println!("{}", serde_json::to_string_pretty(&schema)?);
            Ok(ExitCode::SUCCESS)
        }
        Some(Command::Fmt { files }) => fmt::run(&files),
        Some(command @ Command::Bake { .. }) => bake::run(command),
        Some(command @ Command::Render { .. }) => render::run(command),
        Some(command @ Command::Bench { .. }) => bench::run(command),
        Some(command @ Command::Probe { .. }) => probe::run(command),
        Some(Command::Sample {
            bake,
            outside,
            format,
        }) => sample::run(&bake, outside, format),
    }
}

/// The most characters of one message line printed: a message quotes paths and values from
/// untrusted input, so it is bounded and its control characters escaped ([`doc::printable`]).
pub const MESSAGE_SHOWN: usize = 2000;

/// Prints each line of `text` on stdout, bounded and escaped.
fn print_lines(text: &str) {
    for line in text.lines() {
        println!("{}", doc::printable(line, MESSAGE_SHOWN));
    }
}

/// Prints a warning about `layout` on stderr, bounded and escaped.
fn warn(text: &str) {
    eprintln!("warning: {}", doc::printable(text, MESSAGE_SHOWN));
}

/// Why the layout's map backdrop (if it has one) cannot be shown.
fn backdrop_warning(l: &doc::Layout, file: &std::path::Path) -> Option<String> {
    let base = crate::io::layout_base(Some(file));
    crate::io::layout_backdrop(l, &base)?
        .err()
        .map(|e| e.to_string())
}

/// Each of the layout's advice (`doc::advise`) as a warning naming the file.
fn warn_advice(l: &doc::Layout, file: &std::path::Path) {
    for a in doc::advise(l) {
        warn(&format!("{}: {a}", file.display()));
    }
    for m in doc::mask_problems(l) {
        warn(&format!("{}: {m}", file.display()));
    }
    if let Some(d) = doc::density_map_problem(l) {
        warn(&format!(
            "{}: {d} (the grass grows everywhere)",
            file.display()
        ));
    }
}

/// The camera `--camera` names (45° lens).
fn camera_from(c: [f32; 6]) -> crate::gpu::grass::Camera {
    crate::gpu::grass::Camera {
        eye: glam::Vec3::new(c[0], c[1], c[2]),
        target: glam::Vec3::new(c[3], c[4], c[5]),
        fov_y: 45f32.to_radians(),
    }
}

/// `SUCCESS` when `ok`, else `FAILURE`.
fn exit(ok: bool) -> ExitCode {
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
