//! What a bake is asked for ([`BakeOptions`]) and why a request is refused
//! ([`SettingsError`]). The errors name settings as the Export dialog labels them; the CLI
//! says them with its flags instead (`cli::bake`).

use super::manifest::{self, ATLAS_MAX_SIDE, Format};
use crate::engine::Backend;
use crate::gpu::GpuError;

/// What to bake.
#[derive(Debug, Clone, PartialEq)]
pub struct BakeOptions {
    pub formats: Vec<Format>,
    /// Seconds simulated before the first captured frame (rounded to whole frames).
    pub warmup: f32,
    /// Frames to capture (1: one steady frame).
    pub frames: usize,
    /// Frames per second of the captured sequence.
    pub fps: f32,
    /// Make the sequence loop seamlessly.
    pub looped: bool,
    /// Override the layout's grid.
    pub grid: Option<[u32; 2]>,
    /// Write EXR as 16-bit half floats instead of 32-bit.
    pub half: bool,
    /// Store the flowmaps' and the atlas's green as the world −z wind, so green grows up the
    /// image (toward north), as shaders whose v coordinate runs up the image expect.
    pub flip_green: bool,
    /// Most disk the bake may take, in bytes, counted before it starts (an upper bound of
    /// what every output and the temporary frame files need).
    pub max_bytes: u64,
    /// Which solver runs the bake.
    pub backend: Backend,
}

/// The default disk budget of a bake: 16 GiB.
pub const DEFAULT_MAX_BYTES: u64 = 16 << 30;

/// Longest sequence a bake takes (about an hour at 30 fps); the disk budget usually binds first.
pub const FRAMES_MAX: usize = 100_000;

/// The most simulated seconds a bake runs before its first frame (`--warmup`), and between
/// its first frame and its last (`--frames` ÷ `--fps`): ten hours each.
pub const SECONDS_MAX: f32 = 36_000.0;

impl Default for BakeOptions {
    fn default() -> Self {
        Self {
            formats: Format::ALL.to_vec(),
            warmup: 5.0,
            frames: 1,
            fps: 30.0,
            looped: false,
            grid: None,
            half: false,
            flip_green: false,
            max_bytes: DEFAULT_MAX_BYTES,
            backend: Backend::Cpu,
        }
    }
}

/// A bake request refused before anything runs (or a GPU asked for that cannot run it),
/// typed so that each caller can name the setting in its own words: the Export dialog by
/// its labels (this type's messages), the CLI by its flags.
#[derive(Debug, thiserror::Error)]
pub enum SettingsError {
    #[error("no format chosen")]
    NoFormat,
    #[error("frames must be 1 to {FRAMES_MAX}, got {0}")]
    Frames(usize),
    #[error("frames per second must be between 0 and 1000, got {0}")]
    Fps(f32),
    #[error("the warm-up must be 0 to {SECONDS_MAX} seconds, got {0}")]
    Warmup(f32),
    #[error("a loop needs 2 frames or more")]
    LoopTooShort,
    #[error(
        "{}",
        span_message(*frames, *fps, *looped, *span, "raise the frame rate or bake fewer frames")
    )]
    Span {
        frames: usize,
        fps: f32,
        looped: bool,
        span: f64,
    },
    #[error("{}", atlas_message(*frames, *nx, *ny, *size, "the atlas"))]
    Atlas {
        frames: usize,
        nx: usize,
        ny: usize,
        size: [usize; 2],
    },
    /// The GPU solver asked for could not start or failed.
    #[error("the GPU solver: {0}")]
    Gpu(#[from] GpuError),
}

/// Why `frames` at `fps` are refused: their span in simulated seconds; `fix` says what to
/// change, in the caller's words (the dialog's, or the CLI's flags).
pub fn span_message(frames: usize, fps: f32, looped: bool, span: f64, fix: &str) -> String {
    let doubled = if looped {
        " (a loop simulates twice its frames)"
    } else {
        ""
    };
    format!(
        "{frames} frames at {fps} fps span {span:.0} simulated seconds{doubled}, more than the {SECONDS_MAX} a bake may; {fix}"
    )
}

/// Why an atlas is refused: its size in pixels; `format` names the atlas in the caller's
/// words.
pub fn atlas_message(
    frames: usize,
    nx: usize,
    ny: usize,
    size: [usize; 2],
    format: &str,
) -> String {
    format!(
        "the atlas of {frames} frames of {nx}x{ny} would be {}x{} pixels, over the {ATLAS_MAX_SIDE} a GPU texture allows; bake fewer frames or cells, or leave out {format}",
        size[0], size[1]
    )
}

/// Refuses settings no bake can honour, before anything runs.
pub(super) fn check(opts: &BakeOptions) -> Result<(), SettingsError> {
    if opts.formats.is_empty() {
        return Err(SettingsError::NoFormat);
    }
    if !(1..=FRAMES_MAX).contains(&opts.frames) {
        return Err(SettingsError::Frames(opts.frames));
    }
    if !(opts.fps.is_finite() && opts.fps > 0.0 && opts.fps <= 1000.0) {
        return Err(SettingsError::Fps(opts.fps));
    }
    if !(opts.warmup.is_finite() && opts.warmup >= 0.0 && opts.warmup <= SECONDS_MAX) {
        return Err(SettingsError::Warmup(opts.warmup));
    }
    if opts.looped && opts.frames < 2 {
        return Err(SettingsError::LoopTooShort);
    }
    // The frames' span in simulated seconds (a loop simulates twice its frames).
    let simulated = if opts.looped { 2 } else { 1 } * opts.frames;
    let span = (simulated.saturating_sub(1)) as f64 / f64::from(opts.fps);
    if span > f64::from(SECONDS_MAX) {
        return Err(SettingsError::Span {
            frames: opts.frames,
            fps: opts.fps,
            looped: opts.looped,
            span,
        });
    }
    Ok(())
}

/// Refuses an atlas of `frames` frames of `nx × ny` larger than a GPU texture.
pub(super) fn check_atlas(frames: usize, nx: usize, ny: usize) -> Result<(), SettingsError> {
    let (c, r) = manifest::atlas_grid(frames);
    if c * nx > ATLAS_MAX_SIDE || r * ny > ATLAS_MAX_SIDE {
        return Err(SettingsError::Atlas {
            frames,
            nx,
            ny,
            size: [c * nx, r * ny],
        });
    }
    Ok(())
}
