//! `windloom fmt FILE…`: each valid layout rewritten in canonical form, atomically; invalid
//! files reported and left untouched.

use super::{CliError, MESSAGE_SHOWN, exit};
use crate::{doc, io};
use std::path::PathBuf;
use std::process::ExitCode;

/// Rewrites each valid file; fails when any is invalid, and stops at a file it cannot write.
pub fn run(files: &[PathBuf]) -> Result<ExitCode, CliError> {
    let mut ok = true;
    for f in files {
        match io::load(f) {
            Ok(layout) => io::save(f, &layout)
                .map_err(|e| CliError::failed(format!("could not write {}", f.display()), e))?,
            Err(e) => {
                ok = false;
                for line in e.to_string().lines() {
                    eprintln!("{}", doc::printable(line, MESSAGE_SHOWN));
                }
            }
        }
    }
    Ok(exit(ok))
}
