//! `windloom probe LAYOUT --at X,Z … --seconds S --csv FILE`: the wind at points over time,
//! headless, as the editor's probes read it.

use super::{CliError, Command};
use crate::engine::probe;
use crate::{doc, io};
use std::process::ExitCode;

/// Runs a `Command::Probe`.
pub fn run(command: Command) -> Result<ExitCode, CliError> {
    let Command::Probe {
        layout,
        at,
        warmup,
        seconds,
        hz,
        csv,
        backend,
    } = command
    else {
        unreachable!("probe::run is called with a probe command");
    };
    if !(0.1..=3600.0).contains(&seconds) {
        return Err(CliError::Message(format!(
            "--seconds must be 0.1 to 3600, got {seconds}"
        )));
    }
    if !(0.0..=3600.0).contains(&warmup) {
        return Err(CliError::Message(format!(
            "--warmup must be 0 to 3600, got {warmup}"
        )));
    }
    if let Some(out) = &csv {
        io::check_target(out)
            .map_err(|e| CliError::failed(format!("cannot write {}", out.display()), e))?;
    }
    let l = io::load(&layout)?;
    // One reading a step at most: `1 / dt` in f32 is a hair under a whole rate (1 / (1/60)
    // is 59.999996), so the rate the designer reads as the step's is taken.
    let max_hz = 1.0 / l.sim.dt;
    if !(hz > 0.0 && hz <= max_hz * (1.0 + 1e-5)) {
        return Err(CliError::Message(format!(
            "--hz must be above 0 and at most {max_hz:.0} (one reading a step), got {hz}"
        )));
    }
    let (names, points): (Vec<String>, Vec<[f32; 2]>) = if at.is_empty() {
        l.probes.iter().map(|p| (p.name.clone(), p.pos)).unzip()
    } else {
        at.iter()
            .map(|p| (format!("{},{}", p[0], p[1]), *p))
            .unzip()
    };
    if points.is_empty() {
        return Err(CliError::Message(format!(
            "nothing to measure: give --at X,Z, or add probes to {}",
            layout.display()
        )));
    }
    let (lo, hi) = l.bounds();
    if let Some(p) =
        (points.iter()).find(|p| p[0] < lo[0] || p[0] > hi[0] || p[1] < lo[1] || p[1] > hi[1])
    {
        return Err(CliError::Message(format!(
            "the point {},{} lies outside the world (x {} to {}, z {} to {})",
            p[0], p[1], lo[0], hi[0], lo[1], hi[1]
        )));
    }
    let (records, note) = probe::run(&l, &points, warmup, seconds, hz, backend)?;
    if let Some(note) = note {
        eprintln!("note: {note}");
    }
    println!("probe, min m/s, mean m/s, max m/s, gust factor, mean direction deg");
    for (name, r) in names.iter().zip(&records) {
        let s = probe::stats(r).expect("a run reads every probe at least once");
        println!(
            "{}, {:.2}, {:.2}, {:.2}, {:.2}, {:.0}",
            doc::printable(name, 80),
            s.min,
            s.mean,
            s.max,
            s.gust_factor,
            s.mean_direction_deg
        );
    }
    if let Some(out) = &csv {
        io::write_atomic(out, probe::csv(&names, &records).as_bytes())
            .map_err(|e| CliError::failed(format!("cannot write {}", out.display()), e))?;
        eprintln!("wrote {}", out.display());
    }
    Ok(ExitCode::SUCCESS)
}
