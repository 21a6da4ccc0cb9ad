//! The `windloom` binary: parses arguments, sets up logging, and hands over to the library's
//! commands (`windloom::cli`); an error is printed on one line and exits non-zero.

use clap::Parser;
use std::process::ExitCode;
use windloom::{cli, doc};

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    if cli.command.is_some() {
        quiet_device_select();
    }
    // `RUST_LOG=info` (or `wgpu=warn`, `windloom=debug`…) shows what eframe, wgpu and windloom
    // log; by default windloom's own warnings alone (wgpu reports failed probes of backends it
    // does not use as errors).
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("windloom=warn"))
        .init();
    match cli::run(cli) {
        Ok(code) => code,
        Err(e) => {
            let line = one_line(&anyhow::Error::from(e));
            eprintln!("error: {}", doc::printable(&line, cli::MESSAGE_SHOWN));
            ExitCode::FAILURE
        }
    }
}

/// An error and its causes on one line, `a: b: c`, leaving out a cause the message before it
/// already says: the library's errors put their I/O cause in their own message ("FILE: No
/// such file or directory"), which `{:#}` printed a second time.
fn one_line(e: &anyhow::Error) -> String {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let cause = cause.to_string();
        if !line.ends_with(&cause) {
            line = format!("{line}: {cause}");
        }
    }
    line
}

/// Mesa's Vulkan device-select layer asks the Wayland compositor which GPU drives the
/// display; where `XDG_RUNTIME_DIR` is unset (a CI job, a build server, ssh) libwayland then
/// prints "error: XDG_RUNTIME_DIR is invalid or not set in the environment." twice on a run
/// that succeeds. The headless commands drive no display, so there they turn the layer off
/// (`NODEVICE_SELECT=1`, unless the caller set it); wgpu still picks the adapter.
fn quiet_device_select() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_none()
        && std::env::var_os("NODEVICE_SELECT").is_none()
    {
        // SAFETY: called first thing in `main`, before any other thread exists.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
}
