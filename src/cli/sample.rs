//! `windloom sample BAKE`: the wind a game reads from a bake, at points given on stdin, by
//! the runtime itself (`src/runtime`): what a script, a test or another engine's port of the
//! runtime's rules (the Godot add-on's `WindloomField`) can be checked against.

use super::{CliError, SampleOutside};
use std::io::{BufRead, BufWriter, Write};
use std::path::Path;
use std::process::ExitCode;
use windloom_runtime::{Bake, Options, Outside};

/// The most characters of a line echoed in an error.
const LINE_SHOWN: usize = 80;

pub fn run(
    bake: &Path,
    outside: SampleOutside,
    format: Option<String>,
) -> Result<ExitCode, CliError> {
    let options = Options {
        outside: match outside {
            SampleOutside::Clamp => Outside::Clamp,
            SampleOutside::Zero => Outside::Zero,
            SampleOutside::Wrap => Outside::Wrap,
        },
        format,
        ..Options::default()
    };
    let wind = Bake::open(bake, &options)
        .map_err(|e| CliError::failed(format!("{}: cannot open the bake", bake.display()), e))?;
    let stdin = std::io::stdin();
    let mut out = BufWriter::new(std::io::stdout().lock());
    let wrote = |e: std::io::Error| CliError::failed("stdout".into(), e);
    for (n, line) in stdin.lock().lines().enumerate() {
        let line = line.map_err(|e| CliError::failed(format!("stdin line {}", n + 1), e))?;
        if line.trim().is_empty() || line.trim_start().starts_with('#') {
            continue;
        }
        let [x, y, z, t] = point(&line).ok_or_else(|| {
            CliError::Message(format!(
                "stdin line {}: expected four numbers X Y Z T (metres, seconds), got {:?}",
                n + 1,
                crate::doc::printable(&line, LINE_SHOWN)
            ))
        })?;
        let w = wind.wind_at([x as f32, y as f32, z as f32], t);
        writeln!(out, "{:?} {:?} {:?}", w[0], w[1], w[2]).map_err(wrote)?;
    }
    out.flush().map_err(wrote)?;
    Ok(ExitCode::SUCCESS)
}

/// `X Y Z T`, separated by spaces, tabs or commas.
fn point(line: &str) -> Option<[f64; 4]> {
    let mut it = line
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<f64>().ok());
    let p = [it.next()??, it.next()??, it.next()??, it.next()??];
    it.next().is_none().then_some(p)
}
