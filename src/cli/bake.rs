//! `windloom bake LAYOUT --out DIR`: the layout simulated headless and written in the chosen
//! formats, with a progress bar (or a line every 10 s where stderr is not a terminal), and
//! Ctrl-C, SIGTERM and SIGHUP cancelling it cleanly. With `--watch` it bakes again each time
//! the layout file changes, until a signal stops it.

use super::{CliError, Command, MESSAGE_SHOWN, warn_advice};
use crate::bake::{self, BakeError, SettingsError};
use crate::{doc, io};
use std::io::IsTerminal;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Runs a `Command::Bake`.
pub fn run(command: Command) -> Result<ExitCode, CliError> {
    let Command::Bake {
        layout,
        out,
        formats,
        warmup,
        frames,
        fps,
        looped,
        grid,
        half,
        flip_green,
        max_disk,
        backend,
        watch,
    } = command
    else {
        unreachable!("bake::run is called with a bake command");
    };
    // With --watch, the file as it is before it is read: a save from now on is a change.
    let file = watch.then(|| io::disk::Watch::read(&layout));
    let l = io::load(&layout)?;
    warn_advice(&l, &layout);
    let opts = bake::BakeOptions {
        formats: if formats.is_empty() {
            bake::Format::ALL.to_vec()
        } else {
            formats
        },
        warmup,
        frames,
        fps,
        looped,
        grid,
        half,
        flip_green,
        max_bytes: max_disk,
        backend,
    };
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    // Ctrl-C, SIGTERM (`docker stop`, `timeout`, a cancelled CI job) and SIGHUP (a closed
    // terminal) all cancel the bake, which then removes what it wrote.
    ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst)).map_err(|e| {
        CliError::failed(
            "could not install the Ctrl-C, SIGTERM and SIGHUP handler".into(),
            e,
        )
    })?;
    match bake_once(&l, &out, &opts, &cancel) {
        Ok(()) => {}
        Err(BakeError::Cancelled) => return Ok(cancelled()),
        Err(e) => return Err(in_flags(e)),
    }
    let Some(mut file) = file else {
        return Ok(ExitCode::SUCCESS);
    };
    println!("watching {} for changes; Ctrl-C stops", layout.display());
    loop {
        if cancel.load(Ordering::SeqCst) {
            println!("stopped watching");
            return Ok(ExitCode::SUCCESS);
        }
        std::thread::sleep(WATCH_POLL);
        match file.check() {
            None => {}
            Some(io::disk::Change::Deleted) => eprintln!(
                "warning: {} is gone; the last bake stays, watching for it to come back",
                layout.display()
            ),
            Some(io::disk::Change::Modified) => match io::load(&layout) {
                Err(e) => eprintln!(
                    "error: {}; the last bake stays, watching for the next save",
                    doc::printable(&e.to_string(), MESSAGE_SHOWN)
                ),
                Ok(l) => {
                    warn_advice(&l, &layout);
                    match bake_once(&l, &out, &opts, &cancel) {
                        Ok(()) => {}
                        Err(BakeError::Cancelled) => return Ok(cancelled()),
                        // Settings and the disk budget are the command line's: no save of
                        // the layout changes them.
                        Err(
                            e @ (BakeError::Settings(_) | BakeError::Disk { budget: true, .. }),
                        ) => {
                            return Err(in_flags(e));
                        }
                        Err(e) => eprintln!(
                            "error: {}; the last bake stays, watching for the next save",
                            in_flags(e)
                        ),
                    }
                }
            },
        }
    }
}

/// How often `--watch` looks at the layout file (a `stat`; it is read only when that changed).
const WATCH_POLL: Duration = Duration::from_millis(200);

fn cancelled() -> ExitCode {
    eprintln!("cancelled (a signal): no files were written");
    ExitCode::from(130)
}

/// One bake with its progress bar, and what it says when done.
fn bake_once(
    l: &doc::Layout,
    out: &std::path::Path,
    opts: &bake::BakeOptions,
    cancel: &AtomicBool,
) -> Result<(), BakeError> {
    let bar = if std::io::stderr().is_terminal() {
        indicatif::ProgressBar::new(1)
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg:>12} [{bar:40}] {pos}/{len} {eta}")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    // Where stderr is not a terminal (a CI log, a pipe) a long bake still says how far it
    // is: a line every 10 s, none for a bake that ends sooner.
    let lines = !std::io::stderr().is_terminal();
    let mut last_line = Instant::now();
    let mut progress = |done: usize, total: usize, what: &str| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(what.to_string());
        if lines && last_line.elapsed() >= Duration::from_secs(10) {
            last_line = Instant::now();
            eprintln!(
                "{what}: {:.0}% (step {done} of {total})",
                100.0 * done as f64 / total.max(1) as f64
            );
        }
    };
    let result = bake::bake(l, out, opts, cancel, &mut progress);
    bar.finish_and_clear();
    let m = result?;
    // The advice was said before the bake; the rest is news.
    for n in m.notes.iter().filter(|n| !n.starts_with(bake::ADVICE)) {
        eprintln!("note: {}", doc::printable(n, MESSAGE_SHOWN));
    }
    println!(
        "baked {} frame(s) of {}x{} into {} ({} files + {}, sequence {})",
        m.frames.count,
        m.grid[0],
        m.grid[1],
        out.display(),
        m.files.len(),
        bake::MANIFEST,
        m.sequence
    );
    Ok(())
}

/// A bake's error said with the flags that change it.
fn in_flags(e: BakeError) -> CliError {
    match e {
        BakeError::Settings(s) => {
            CliError::Message(format!("invalid bake settings: {}", settings(&s)))
        }
        BakeError::Disk {
            need,
            limit,
            budget: true,
        } => CliError::Message(bake::disk_message(need, &limit, ", or raise --max-disk")),
        e => e.into(),
    }
}

/// A settings error in the words of the command line.
fn settings(e: &SettingsError) -> String {
    use crate::bake::{FRAMES_MAX, SECONDS_MAX};
    match e {
        SettingsError::NoFormat => "no --format given".into(),
        SettingsError::Frames(n) => format!("--frames must be 1 to {FRAMES_MAX}, got {n}"),
        SettingsError::Fps(fps) => format!("--fps must be between 0 and 1000, got {fps}"),
        SettingsError::Warmup(w) => {
            format!("--warmup must be 0 to {SECONDS_MAX} seconds, got {w}")
        }
        SettingsError::LoopTooShort => "--loop needs --frames 2 or more".into(),
        SettingsError::Span {
            frames,
            fps,
            looped,
            span,
        } => bake::span_message(
            *frames,
            *fps,
            *looped,
            *span,
            "raise --fps or bake fewer --frames",
        ),
        SettingsError::Atlas {
            frames,
            nx,
            ny,
            size,
        } => bake::atlas_message(*frames, *nx, *ny, *size, "--format atlas"),
        SettingsError::Gpu(g) => format!("--backend gpu: {g}"),
    }
}
