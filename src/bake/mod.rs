//! Baking: run a layout headless and write the wind in the formats game engines read.
//!
//! Every file is first written into a staging folder inside the output folder and renamed
//! into place only when the whole bake succeeded, the manifest last; an error or a
//! cancellation removes the staging folder, so no partial file is ever left behind.

mod exr;
mod fga;
mod png;
mod raw;
mod vf;

use crate::doc::{self, Layout};
use crate::sim::Solver;
use serde::Serialize;
use sha2::Digest;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// A baked frame: cell-centred world velocity `[x, z]` in m/s, row-major (`i` along +x fastest,
/// row `j` along +z).
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    pub nx: usize,
    pub ny: usize,
    pub data: Vec<[f32; 2]>,
}

impl Field {
    pub fn at(&self, i: usize, j: usize) -> [f32; 2] {
        self.data[j * self.nx + i]
    }

    pub fn max_speed(&self) -> f32 {
        self.data
            .iter()
            .map(|v| v[0].hypot(v[1]))
            .fold(0.0, f32::max)
    }

    /// Area-averaged resampling onto `nx × ny` cells: each output cell is the mean of the
    /// input cells it covers, weighted by the overlapping area.
    pub fn resample(&self, nx: usize, ny: usize) -> Field {
        if nx == self.nx && ny == self.ny {
            return self.clone();
        }
        let wx = overlap_weights(self.nx, nx);
        let wz = overlap_weights(self.ny, ny);
        let mut data = vec![[0.0f32; 2]; nx * ny];
        for (oj, zs) in wz.iter().enumerate() {
            for (oi, xs) in wx.iter().enumerate() {
                let mut acc = [0.0f64; 2];
                let mut total = 0.0f64;
                for &(j, a) in zs {
                    for &(i, b) in xs {
                        let w = a * b;
                        let v = self.at(i, j);
                        acc[0] += f64::from(v[0]) * w;
                        acc[1] += f64::from(v[1]) * w;
                        total += w;
                    }
                }
                data[oj * nx + oi] = [(acc[0] / total) as f32, (acc[1] / total) as f32];
            }
        }
        Field { nx, ny, data }
    }
}

/// For each of `m` output cells over `n` input cells: the input cells it overlaps and by how
/// much (in input-cell units).
fn overlap_weights(n: usize, m: usize) -> Vec<Vec<(usize, f64)>> {
    let scale = n as f64 / m as f64;
    (0..m)
        .map(|o| {
            let (a, b) = (o as f64 * scale, (o + 1) as f64 * scale);
            let first = a.floor() as usize;
            let last = (b.ceil() as usize).min(n);
            (first..last)
                .map(|i| {
                    let w = (b.min(i as f64 + 1.0) - a.max(i as f64)).max(0.0);
                    (i, w)
                })
                .filter(|(_, w)| *w > 0.0)
                .collect()
        })
        .collect()
}

/// Output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, PartialOrd, Ord)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// OpenEXR, float RGB: R = world x, G = world z, B = speed (m/s).
    Exr,
    /// 8-bit PNG flowmap, RG centred on 0.5.
    Png8,
    /// 16-bit PNG flowmap, RG centred on 0.5.
    Png16,
    /// Unreal vector field (FGA), at most 128 cells per axis.
    Fga,
    /// Unity VFX Graph vector field (VF_V).
    Vf,
    /// Little-endian f32 pairs, all frames in one file.
    Raw,
    /// All frames in one 16-bit PNG flipbook.
    Atlas,
}

impl Format {
    pub const ALL: [Format; 7] = [
        Format::Exr,
        Format::Png8,
        Format::Png16,
        Format::Fga,
        Format::Vf,
        Format::Raw,
        Format::Atlas,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::Exr => "exr",
            Self::Png8 => "png8",
            Self::Png16 => "png16",
            Self::Fga => "fga",
            Self::Vf => "vf",
            Self::Raw => "raw",
            Self::Atlas => "atlas",
        }
    }
}

/// What to bake.
#[derive(Debug, Clone, PartialEq)]
pub struct BakeOptions {
    pub formats: Vec<Format>,
    /// Seconds simulated before the first captured frame.
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
}

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
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    #[error("invalid bake settings: {0}")]
    Settings(String),
    #[error("the layout is invalid: {0}")]
    Layout(String),
    #[error("cannot use output folder {}: {source}", path.display())]
    Output {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("writing {}: {source}", path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("encoding {name}: {message}")]
    Encode { name: String, message: String },
    #[error("cancelled; no files were written")]
    Cancelled,
}

/// Progress reports: `(done, total, what)`.
pub type Progress<'a> = &'a mut dyn FnMut(usize, usize, &str);

/// One file of a bake, as the manifest describes it.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FileEntry {
    pub name: String,
    pub format: Format,
    /// Which frame (absent for files holding all frames).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frame: Option<usize>,
    /// Cells per axis in this file (after any resampling).
    pub grid: [usize; 2],
    /// The baked grid this file was area-averaged down from, if it was.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resampled_from: Option<[usize; 2]>,
    /// How stored values map to world velocity.
    pub encoding: serde_json::Value,
    /// How the file's axes map to the world's.
    pub axes: serde_json::Value,
    pub bytes: u64,
}

/// The bake's `manifest.json`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Manifest {
    pub format: &'static str,
    pub version: u32,
    pub layout: LayoutInfo,
    pub grid: [usize; 2],
    pub world: WorldInfo,
    pub axes: serde_json::Value,
    pub frames: FramesInfo,
    /// Largest wind speed over all frames, m/s (the PNG flowmap scale).
    pub max_speed: f32,
    pub notes: Vec<String>,
    pub files: Vec<FileEntry>,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct LayoutInfo {
    pub name: String,
    /// `sha256:` of the layout's canonical JSON.
    pub hash: String,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WorldInfo {
    pub min: [f32; 2],
    pub max: [f32; 2],
    pub units: &'static str,
    pub cell_size: [f32; 2],
}

#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FramesInfo {
    pub count: usize,
    pub fps: f32,
    #[serde(rename = "loop")]
    pub looped: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub loop_method: Option<&'static str>,
    pub warmup_seconds: f32,
    pub sim_dt: f32,
    pub steps_per_frame: usize,
}

pub const MANIFEST: &str = "manifest.json";
/// Unreal's importer rejects larger axes.
pub const FGA_MAX: usize = 128;

/// The content hash the manifest records: sha256 of the canonical layout JSON.
pub fn layout_hash(layout: &Layout) -> String {
    let digest = sha2::Sha256::digest(doc::to_json(layout).as_bytes());
    let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
    format!("sha256:{hex}")
}

/// Simulates `layout` and returns the frames to export (looped if asked).
pub fn capture(
    layout: &Layout,
    opts: &BakeOptions,
    cancel: &AtomicBool,
    progress: Progress<'_>,
) -> Result<(Vec<Field>, FramesInfo), BakeError> {
    if opts.frames == 0 {
        return Err(BakeError::Settings("--frames must be at least 1".into()));
    }
    if !(opts.fps.is_finite() && opts.fps > 0.0 && opts.fps <= 1000.0) {
        return Err(BakeError::Settings(format!(
            "--fps must be between 0 and 1000, got {}",
            opts.fps
        )));
    }
    if !(opts.warmup.is_finite() && opts.warmup >= 0.0 && opts.warmup <= 36_000.0) {
        return Err(BakeError::Settings(format!(
            "--warmup must be 0 to 36000 seconds, got {}",
            opts.warmup
        )));
    }
    if opts.looped && opts.frames < 2 {
        return Err(BakeError::Settings(
            "--loop needs --frames 2 or more".into(),
        ));
    }
    let dt = layout.sim.dt;
    let steps_per_frame = ((1.0 / (opts.fps * dt)).round() as usize).max(1);
    let warmup_steps = (opts.warmup / dt).round() as usize;
    // A loop cross-fades two runs of the sequence, so it simulates twice as many frames.
    let simulated = if opts.looped {
        opts.frames * 2
    } else {
        opts.frames
    };
    let total = warmup_steps + (simulated - 1) * steps_per_frame;
    let mut solver = Solver::new(layout);
    let mut done = 0;
    let mut step = |solver: &mut Solver, n: usize, done: &mut usize| -> Result<(), BakeError> {
        for _ in 0..n {
            if cancel.load(Ordering::Relaxed) {
                return Err(BakeError::Cancelled);
            }
            solver.step();
            *done += 1;
            if *done % 8 == 0 || *done == total {
                progress(*done, total, "simulating");
            }
        }
        Ok(())
    };
    step(&mut solver, warmup_steps, &mut done)?;
    let mut frames = Vec::with_capacity(simulated);
    for k in 0..simulated {
        if k > 0 {
            step(&mut solver, steps_per_frame, &mut done)?;
        }
        frames.push(Field {
            nx: solver.nx,
            ny: solver.ny,
            data: solver.velocity_field(),
        });
    }
    let frames = if opts.looped {
        crossfade_loop(&frames, opts.frames)
    } else {
        frames
    };
    Ok((
        frames,
        FramesInfo {
            count: opts.frames,
            fps: opts.fps,
            looped: opts.looped,
            loop_method: opts.looped.then_some(
                "crossfade: frame k = (1 - k/N)·S[k+N] + (k/N)·S[k] over 2N simulated frames S",
            ),
            warmup_seconds: warmup_steps as f32 * dt,
            sim_dt: dt,
            steps_per_frame,
        },
    ))
}

/// A seamless loop of `n` frames from `2n` simulated ones: frame `k` blends `S[k+n]` (weight
/// `1 − k/n`) with `S[k]` (weight `k/n`). Frame 0 is `S[n]`; the last frame is almost
/// `S[n−1]`, whose natural successor is `S[n]`, so playing the last frame then the first is
/// one ordinary simulation step.
pub fn crossfade_loop(s: &[Field], n: usize) -> Vec<Field> {
    (0..n)
        .map(|k| {
            let w = k as f32 / n as f32;
            let (a, b) = (&s[k + n], &s[k]);
            Field {
                nx: a.nx,
                ny: a.ny,
                data: a
                    .data
                    .iter()
                    .zip(&b.data)
                    .map(|(p, q)| [p[0] * (1.0 - w) + q[0] * w, p[1] * (1.0 - w) + q[1] * w])
                    .collect(),
            }
        })
        .collect()
}

/// The file name of frame `k` of `count` with extension `ext`.
fn frame_name(stem: &str, k: usize, count: usize, ext: &str) -> String {
    if count == 1 {
        format!("{stem}.{ext}")
    } else {
        format!("{stem}_{k:04}.{ext}")
    }
}

/// What an exporter hands back: file name, bytes, and its manifest entry (minus size).
pub(crate) struct Output {
    pub name: String,
    pub bytes: Vec<u8>,
    pub entry: FileEntry,
}

/// Bakes `layout` into `out`. Returns the manifest written.
pub fn bake(
    layout: &Layout,
    out: &Path,
    opts: &BakeOptions,
    cancel: &AtomicBool,
    progress: Progress<'_>,
) -> Result<Manifest, BakeError> {
    if opts.formats.is_empty() {
        return Err(BakeError::Settings("no --format given".into()));
    }
    let mut layout = layout.clone();
    if let Some(g) = opts.grid {
        layout.world.grid = g;
    }
    let issues = doc::validate(&layout);
    if let Some(i) = issues.first() {
        return Err(BakeError::Layout(i.to_string()));
    }
    std::fs::create_dir_all(out).map_err(|source| BakeError::Output {
        path: out.to_path_buf(),
        source,
    })?;
    // Staging inside the output folder, so the final renames stay on one file system.
    let staging = tempfile::Builder::new()
        .prefix(".windloom-bake-")
        .tempdir_in(out)
        .map_err(|source| BakeError::Output {
            path: out.to_path_buf(),
            source,
        })?;

    let (frames, frames_info) = capture(&layout, opts, cancel, progress)?;
    let (nx, ny) = (frames[0].nx, frames[0].ny);
    let max_speed = frames.iter().map(Field::max_speed).fold(0.0, f32::max);
    let (min, max) = layout.bounds();
    let mut notes = Vec::new();
    let mut outputs: Vec<Output> = Vec::new();
    let mut formats = opts.formats.clone();
    formats.sort();
    formats.dedup();
    let ctx = ExportContext {
        frames: &frames,
        max_speed,
        min,
        max,
        half: opts.half,
        fps: opts.fps,
    };
    for (k, f) in formats.iter().enumerate() {
        if cancel.load(Ordering::Relaxed) {
            return Err(BakeError::Cancelled);
        }
        progress(k, formats.len(), f.name());
        let files = match f {
            Format::Exr => exr::write(&ctx)?,
            Format::Png8 => png::flowmaps(&ctx, false)?,
            Format::Png16 => png::flowmaps(&ctx, true)?,
            Format::Atlas => png::atlas(&ctx)?,
            Format::Fga => {
                let (files, note) = fga::write(&ctx);
                notes.extend(note);
                files
            }
            Format::Vf => vf::write(&ctx),
            Format::Raw => raw::write(&ctx),
        };
        outputs.extend(files);
    }

    let mut manifest = Manifest {
        format: "windloom-bake",
        version: 1,
        layout: LayoutInfo {
            name: layout.name.clone(),
            hash: layout_hash(&layout),
        },
        grid: [nx, ny],
        world: WorldInfo {
            min,
            max,
            units: "m",
            cell_size: [
                layout.world.size[0] / nx as f32,
                layout.world.size[1] / ny as f32,
            ],
        },
        axes: serde_json::json!({
            "system": "world: x east, y up, z south (right-handed, y-up), metres",
            "grid_i": "+x (east), column 0 at world x = min[0]",
            "grid_j": "+z (south), row 0 at world z = min[1]",
            "velocity": "[x, z] in m/s at cell centres",
        }),
        frames: frames_info,
        max_speed,
        notes,
        files: Vec::new(),
    };
    // Write everything into staging, then move it into place, the manifest last.
    for o in &outputs {
        let path = staging.path().join(&o.name);
        std::fs::write(&path, &o.bytes).map_err(|source| BakeError::Write { path, source })?;
        let mut e = o.entry.clone();
        e.bytes = o.bytes.len() as u64;
        manifest.files.push(e);
    }
    let json = serde_json::to_string_pretty(&manifest).expect("a manifest serialises") + "\n";
    let mpath = staging.path().join(MANIFEST);
    std::fs::write(&mpath, json).map_err(|source| BakeError::Write {
        path: mpath,
        source,
    })?;
    if cancel.load(Ordering::Relaxed) {
        return Err(BakeError::Cancelled);
    }
    for name in outputs.iter().map(|o| o.name.as_str()).chain([MANIFEST]) {
        let to = out.join(name);
        std::fs::rename(staging.path().join(name), &to)
            .map_err(|source| BakeError::Write { path: to, source })?;
    }
    Ok(manifest)
}

/// Everything an exporter needs.
pub(crate) struct ExportContext<'a> {
    pub frames: &'a [Field],
    pub max_speed: f32,
    pub min: [f32; 2],
    pub max: [f32; 2],
    pub half: bool,
    pub fps: f32,
}

impl ExportContext<'_> {
    fn name(&self, stem: &str, k: usize, ext: &str) -> String {
        frame_name(stem, k, self.frames.len(), ext)
    }

    fn frame_index(&self, k: usize) -> Option<usize> {
        (self.frames.len() > 1).then_some(k)
    }

    /// The speed that maps to the ends of the 8/16-bit flowmap range.
    fn flow_scale(&self) -> f32 {
        self.max_speed.max(1e-6)
    }
}
