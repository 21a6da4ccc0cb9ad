//! `windloom validate FILE…`: every file's errors, or `FILE: ok` with its warnings.

use super::{CliError, backdrop_warning, exit, print_lines};
use crate::{doc, io};
use std::path::PathBuf;
use std::process::ExitCode;

/// Checks each file; fails when any is invalid.
pub fn run(files: &[PathBuf]) -> Result<ExitCode, CliError> {
    let mut ok = true;
    for f in files {
        match io::load(f) {
            Ok(l) => {
                let mut line = format!("{}: ok", f.display());
                if let Some(w) = backdrop_warning(&l, f) {
                    line += &format!("; warning: {w} (the layout opens without it)");
                }
                for m in doc::mask_problems(&l) {
                    line += &format!("; warning: {m} (the wind runs without it; bake refuses)");
                }
                if let Some(d) = doc::density_map_problem(&l) {
                    line += &format!("; warning: {d} (the grass grows everywhere)");
                }
                for a in doc::advise(&l) {
                    line += &format!("; warning: {a}");
                }
                print_lines(&line);
            }
            Err(e) => {
                ok = false;
                print_lines(&e.to_string());
            }
        }
    }
    Ok(exit(ok))
}
