//! Baking: run a layout headless and write the wind in the formats game engines read.
//!
//! Frames sit at exactly `warmup + k / fps` seconds of simulated time (`timing`). They are
//! streamed to disk as the solver makes them (`frames`), then encoded one at a time, so memory
//! does not grow with the frame count; the disk a bake can take is checked before it starts.
//! Everything is written into a staging folder beside the output folder, which then replaces
//! the output folder as a whole, keeping the user's own files (`folder`). An error or a
//! cancellation removes the staging folder and leaves the output folder as it was.

mod engines;
mod exr;
mod fga;
mod folder;
mod format;
mod frames;
mod heights;
mod manifest;
mod options;
mod png;
mod raw;
pub mod timing;
mod vf;
mod volume;

pub use engines::Engines;
pub use format::Format;
pub use manifest::{
    Axes, Channel, Encoding, FileEntry, FramesInfo, IndexAxis, LayoutInfo, MANIFEST,
    MANIFEST_VERSION, Manifest, ProfileInfo, Quantity, Sample, SubImages, TerrainInfo, WorldAxis,
    WorldInfo, layout_hash, schema as manifest_schema,
};
pub use options::{
    BakeOptions, DEFAULT_MAX_BYTES, FRAMES_MAX, SECONDS_MAX, SettingsError, atlas_message,
    span_message,
};
pub use png::ATLAS_MAX_SIDE;
pub use timing::FrameTiming;

use crate::doc::{self, Layout};
use crate::engine::Stepper;
use format::frame_name;
use frames::{FrameReader, FrameWriter};
use std::collections::BTreeMap;
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
            .map(|v| crate::num::hypot(v[0], v[1]))
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

/// Why a bake is refused for its disk: it needs up to `need` bytes, more than `limit`;
/// `raise` says what else to change, in the caller's words (empty: nothing).
pub fn disk_message(need: u64, limit: &str, raise: &str) -> String {
    format!(
        "this bake needs up to {} of disk, more than {limit}; bake fewer frames, formats or cells{raise}",
        human_bytes(need)
    )
}

/// Bytes as a person reads them: `512 B`, `3.2 MiB`, `1.50 GiB`.
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut v = bytes as f64;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < UNITS.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{bytes} B")
    } else {
        format!("{v:.2} {}", UNITS[u])
    }
}

#[derive(Debug, thiserror::Error)]
pub enum BakeError {
    #[error("invalid bake settings: {0}")]
    Settings(#[from] SettingsError),
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
    #[error(
        "{}",
        disk_message(*need, limit, if *budget { ", or raise the disk budget" } else { "" })
    )]
    Disk {
        need: u64,
        /// What it exceeds, e.g. `the 16.00 GiB budget`.
        limit: String,
        /// Whether it exceeds the budget asked for ([`BakeOptions::max_bytes`]), rather than
        /// the free space.
        budget: bool,
    },
    #[error("cancelled; no files were written")]
    Cancelled,
    #[error(
        "the wind went non-finite in frame {frame} (cell {cell}); nothing was written — the layout or the solver settings make the simulation unstable"
    )]
    NonFinite { frame: usize, cell: usize },
}

impl BakeError {
    /// The error naming the file of the output folder rather than its namesake in the hidden
    /// staging folder, which the user never sees.
    fn outside_staging(self, out: &Path) -> Self {
        let fix = |path: PathBuf| {
            let parts: Vec<_> = path.components().collect();
            match parts
                .iter()
                .position(|c| c.as_os_str().to_string_lossy().starts_with(folder::MARK))
            {
                Some(i) => parts[i + 1..]
                    .iter()
                    .fold(out.to_path_buf(), |p, c| p.join(c)),
                None => path,
            }
        };
        match self {
            Self::Output { path, source } => Self::Output {
                path: fix(path),
                source,
            },
            Self::Write { path, source } => Self::Write {
                path: fix(path),
                source: crate::io::plain(source),
            },
            other => other,
        }
    }
}

/// How a manifest note that repeats the layout's advice (`doc::advise`) starts: the CLI
/// said those before the bake.
pub const ADVICE: &str = "advice: ";

/// How far past the layout's own wind a baked field may peak before a note says so: arrows
/// that meet and turn lift a field above its arrows by a little (the examples: up to 1.46×,
/// walled-garden's breeze through its gaps; confinement adds at most a few hundredths).
pub const PEAK_NOTED: f32 = 2.5;

/// What the baked numbers say about the layout: a field far faster than the wind the layout
/// sets (`sim::forces::reference_speed`), or a field that never moves (no enabled arrow, or
/// obstacles over the whole map).
pub fn field_notes(layout: &Layout, max_speed: f32) -> Vec<String> {
    let strongest = crate::sim::forces::reference_speed(layout);
    let mut notes = Vec::new();
    if max_speed == 0.0 {
        notes.push(
            "the baked wind is still: every cell of every frame is zero (no enabled arrow or \
             layer blows, or obstacles cover the map)"
                .to_string(),
        );
    } else if strongest > 0.0 && max_speed > PEAK_NOTED * strongest {
        notes.push(format!(
            "the baked wind peaks at {max_speed:.1} m/s, {:.1}× the strongest push in the layout \
             ({strongest:.1} m/s); look at it in the editor before shipping it",
            max_speed / strongest
        ));
    }
    notes
}

/// Refuses a frame holding a NaN or an infinity: a bake never ships one.
pub fn check_finite(field: &[[f32; 2]], frame: usize) -> Result<(), BakeError> {
    match field
        .iter()
        .position(|v| !(v[0].is_finite() && v[1].is_finite()))
    {
        Some(cell) => Err(BakeError::NonFinite { frame, cell }),
        None => Ok(()),
    }
}

/// Progress reports: `(done, total, what)`.
pub type Progress<'a> = &'a mut dyn FnMut(usize, usize, &str);

/// Frame `k` of a seamless loop of `n` frames from `2n` simulated ones `S`: it blends
/// `S[k+n]` (weight `1 − k/n`) with `S[k]` (weight `k/n`). Frame 0 is `S[n]`; the last frame is
/// almost `S[n−1]`, whose natural successor is `S[n]`, so playing the last frame then the
/// first is one ordinary simulation step.
pub fn crossfade(late: &Field, early: &Field, k: usize, n: usize) -> Field {
    let w = k as f32 / n as f32;
    Field {
        nx: late.nx,
        ny: late.ny,
        data: late
            .data
            .iter()
            .zip(&early.data)
            .map(|(p, q)| [p[0] * (1.0 - w) + q[0] * w, p[1] * (1.0 - w) + q[1] * w])
            .collect(),
    }
}

/// Unreal's importer rejects larger axes.
pub const FGA_MAX: usize = 128;

/// The file that writes `format`.
fn encoder(format: Format) -> &'static dyn format::Encoder {
    match format {
        Format::Exr => &exr::Exr,
        Format::Png8 => &png::Flowmap { sixteen: false },
        Format::Png16 => &png::Flowmap { sixteen: true },
        Format::Fga => &fga::Fga,
        Format::Vf => &vf::Vf,
        Format::Raw => &raw::Raw,
        Format::Atlas => &png::AtlasFormat,
        Format::AtlasExr => &exr::AtlasExr,
        Format::Dds => &volume::Volume,
    }
}

/// Every file a bake of `count` frames in `formats` writes, the manifest last.
pub fn output_names(formats: &[Format], count: usize) -> Vec<String> {
    let mut names: Vec<String> = formats
        .iter()
        .flat_map(|&f| encoder(f).names(count))
        .collect();
    names.push(MANIFEST.to_string());
    names
}

/// An upper bound of the disk a bake takes at its peak: every output, the manifest, and the
/// temporary frame files (the frame stream when `raw` is not kept, and a loop's `2N` source
/// frames). `layers`: the volume's layers (`dds`).
pub fn disk_need(
    nx: usize,
    ny: usize,
    layers: usize,
    formats: &[Format],
    frames: usize,
    looped: bool,
    half: bool,
) -> u64 {
    let n = frames as u64;
    let frame_raw = (nx * ny) as u64 * 8;
    // The frame stream (kept as wind.f32 or deleted at the end), and a loop's source frames.
    let mut need = frame_raw * n + if looped { frame_raw * 2 * n } else { 0 };
    let size = format::Extent {
        nx,
        ny,
        layers,
        frames,
        half,
    };
    for f in formats {
        need += encoder(*f).max_bytes(&size);
    }
    // The manifest: a few hundred bytes per file.
    need + 64 * 1024 + 1024 * output_names(formats, frames).len() as u64
}

/// What an exporter hands back: file name, bytes, and its manifest entry (minus size).
pub(crate) struct Output {
    pub name: String,
    pub bytes: Vec<u8>,
    pub entry: FileEntry,
}

/// Writes a file and flushes it to disk before the folder swap can make it visible.
pub(crate) fn write_file(dir: &Path, name: &str, bytes: &[u8]) -> Result<u64, BakeError> {
    use std::io::Write;
    let path = dir.join(name);
    let err = |source| BakeError::Write {
        path: path.clone(),
        source,
    };
    let mut f = std::fs::File::create(&path).map_err(err)?;
    f.write_all(bytes).map_err(err)?;
    f.sync_all().map_err(err)?;
    Ok(bytes.len() as u64)
}

fn sync_file(path: &Path) -> Result<u64, BakeError> {
    let err = |source| BakeError::Write {
        path: path.to_path_buf(),
        source,
    };
    let f = crate::platform::fs::flush_file(path).map_err(err)?;
    Ok(f.metadata().map_err(err)?.len())
}

/// Bakes `layout` into the folder `out`, which it replaces as a whole (keeping files the user
/// put there). Returns the manifest written.
pub fn bake(
    layout: &Layout,
    out: &Path,
    opts: &BakeOptions,
    cancel: &AtomicBool,
    progress: Progress<'_>,
) -> Result<Manifest, BakeError> {
    bake_staged(layout, out, opts, cancel, progress).map_err(|e| e.outside_staging(out))
}

/// [`bake`], whose errors may still name files in the staging folder.
fn bake_staged(
    layout: &Layout,
    out: &Path,
    opts: &BakeOptions,
    cancel: &AtomicBool,
    progress: Progress<'_>,
) -> Result<Manifest, BakeError> {
    options::check(opts)?;
    let mut layout = layout.clone();
    if let Some(g) = opts.grid {
        layout.world.grid = g;
    }
    if let Some(i) = doc::validate(&layout).first() {
        return Err(BakeError::Layout(i.to_string()));
    }
    if let Some(p) = doc::mask_problems(&layout).first() {
        return Err(BakeError::Layout(format!(
            "{p}; a bake without it would ship wrong wind"
        )));
    }
    // A bake made here must open on every machine of the team: its folder's name and the
    // files the layout names, as Windows (the strictest) allows them.
    if let Some(p) = doc::portable::layout_problems(&layout).first() {
        return Err(BakeError::Layout(format!(
            "{p} (rename it so the layout opens on every platform)"
        )));
    }
    if let Some(name) = out.file_name().map(|n| n.to_string_lossy())
        && let Some(why) = doc::portable::name_problem(&name)
    {
        return Err(BakeError::Output {
            path: out.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("not every platform can hold it: {why}"),
            ),
        });
    }
    let timing = FrameTiming::new(opts.fps, layout.sim.dt, opts.warmup);
    let (nx, ny) = (layout.world.grid[0] as usize, layout.world.grid[1] as usize);
    let n = opts.frames;
    let mut formats = opts.formats.clone();
    formats.sort();
    formats.dedup();
    if formats.contains(&Format::Atlas) || formats.contains(&Format::AtlasExr) {
        options::check_atlas(n, nx, ny)?;
    }
    let layers = layout.world.profile.layers as usize;
    let heights_need = if layout.world.terrain.is_some() {
        (nx * ny * 2) as u64 + 65536
    } else {
        0
    };
    let need = disk_need(nx, ny, layers, &formats, n, opts.looped, opts.half) + heights_need;
    if need > opts.max_bytes {
        return Err(BakeError::Disk {
            need,
            limit: format!("the {} budget", human_bytes(opts.max_bytes)),
            budget: true,
        });
    }
    let staging = folder::Staging::new(out)?;
    if let Some(free) = crate::platform::fs::free_space(staging.path())
        && need > free
    {
        return Err(BakeError::Disk {
            need,
            limit: format!("the {} free on {}", human_bytes(free), out.display()),
            budget: false,
        });
    }
    let mut names = output_names(&formats, n);
    if layout.world.terrain.is_some() {
        names.push(heights::NAME.to_string());
    }
    staging.check_names(names.iter().map(String::as_str))?;
    let dir = staging.path().to_path_buf();

    // Simulate with the step that fits the frame rate, streaming each frame to disk.
    let mut sim_layout = layout.clone();
    sim_layout.sim.dt = timing.dt;
    let simulated = if opts.looped { 2 * n } else { n };
    let sim_steps = timing.warmup_steps + (simulated - 1) * timing.steps_per_frame;
    let total = sim_steps + n;
    let keep_raw = formats.contains(&Format::Raw);
    let frames_path = dir.join(if keep_raw { raw::NAME } else { ".frames.f32" });
    let source_path = if opts.looped {
        dir.join(".loop-source.f32")
    } else {
        frames_path.clone()
    };
    let (mut solver, solver_note) =
        Stepper::new(&sim_layout, opts.backend).map_err(SettingsError::Gpu)?;
    let solver_name = solver.describe();
    let mut steps = 0;
    let mut advance = |solver: &mut Stepper, count: usize| -> Result<(), BakeError> {
        for _ in 0..count {
            if cancel.load(Ordering::Relaxed) {
                return Err(BakeError::Cancelled);
            }
            solver.step();
            steps += 1;
            // The solvers' one clock (substeps counted, in f64), as in the editor and
            // `probe`: frame k sits at warmup + k / fps to within f32's rounding of `dt`.
            if steps % 8 == 0 || steps == sim_steps {
                progress(steps, total, "simulating");
            }
        }
        Ok(())
    };
    let mut writer = FrameWriter::create(&source_path, nx, ny)?;
    advance(&mut solver, timing.warmup_steps)?;
    let first = solver.velocity_field().map_err(SettingsError::Gpu)?;
    check_finite(&first, 0)?;
    writer.push(&first)?;
    for k in 1..simulated {
        advance(&mut solver, timing.steps_per_frame)?;
        let field = solver.velocity_field().map_err(SettingsError::Gpu)?;
        check_finite(&field, k)?;
        writer.push(&field)?;
    }
    drop(solver);
    let mut max_speed = writer.max_speed;
    // The length of the final frame stream (flushed to disk by `finish`).
    let mut frames_bytes = writer.finish()?;
    if opts.looped {
        let mut source = FrameReader::open(&source_path, nx, ny)?;
        let mut looped = FrameWriter::create(&frames_path, nx, ny)?;
        for k in 0..n {
            let (late, early) = (source.read(k + n)?, source.read(k)?);
            looped.push(&crossfade(&late, &early, k, n).data)?;
        }
        max_speed = looped.max_speed;
        frames_bytes = looped.finish()?;
        drop(source);
        std::fs::remove_file(&source_path).map_err(|source| BakeError::Write {
            path: source_path.clone(),
            source,
        })?;
    }

    // Encode, one frame at a time.
    let (min, max) = layout.bounds();
    let ctx = ExportContext {
        nx,
        ny,
        count: n,
        max_speed,
        min,
        max,
        half: opts.half,
        fps: opts.fps,
        flip_green: opts.flip_green,
        profile: layout.world.profile.clone(),
    };
    let mut files: BTreeMap<Format, Vec<FileEntry>> = BTreeMap::new();
    let mut atlas = if formats.contains(&Format::Atlas) {
        Some(png::Atlas::create(&ctx, &dir.join(png::ATLAS_NAME))?)
    } else {
        None
    };
    let mut reader = FrameReader::open(&frames_path, nx, ny)?;
    for k in 0..n {
        if cancel.load(Ordering::Relaxed) {
            return Err(BakeError::Cancelled);
        }
        let f = reader.read(k)?;
        for &format in &formats {
            for output in encoder(format).frame(&ctx, k, &f)? {
                let mut entry = output.entry;
                entry.bytes = write_file(&dir, &output.name, &output.bytes)?;
                files.entry(format).or_default().push(entry);
            }
        }
        if let Some(a) = &mut atlas {
            a.push(f)?;
        }
        progress(sim_steps + k + 1, total, "encoding");
    }
    if formats.contains(&Format::AtlasExr) {
        let (bytes, mut entry) = exr::atlas(&ctx, &mut reader)?;
        entry.bytes = write_file(&dir, exr::ATLAS_EXR_NAME, &bytes)?;
        files.insert(Format::AtlasExr, vec![entry]);
    }
    drop(reader);
    if let Some(a) = atlas {
        let (path, mut entry) = a.finish()?;
        entry.bytes = sync_file(&path)?;
        files.insert(Format::Atlas, vec![entry]);
    }
    if keep_raw {
        let mut entry = raw::entry(&ctx);
        entry.bytes = frames_bytes;
        files.insert(Format::Raw, vec![entry]);
    } else {
        std::fs::remove_file(&frames_path).map_err(|source| BakeError::Write {
            path: frames_path.clone(),
            source,
        })?;
    }

    let mut terrain = heights::write(&dir, &layout)?;
    let mut files: Vec<FileEntry> = files.into_values().flatten().collect();
    // Each file's CRC, read back as it lies on disk: what the next bake into the folder
    // checks before it removes a file as this bake's.
    for e in &mut files {
        e.crc32 = folder::crc32_of(&dir.join(&e.name))?;
    }
    if let Some(t) = &mut terrain {
        t.crc32 = folder::crc32_of(&dir.join(t.file))?;
    }
    let manifest = Manifest {
        format: "windloom-bake",
        version: MANIFEST_VERSION,
        sequence: staging.next_sequence(),
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
        world_axes: manifest::WORLD_AXES,
        frames: FramesInfo {
            count: n,
            fps: opts.fps,
            looped: opts.looped,
            loop_method: opts.looped.then_some(
                "crossfade: frame k = (1 - k/N)·S[k+N] + (k/N)·S[k] over 2N simulated frames S, S[j] at warmup_seconds + j / fps",
            ),
            warmup_seconds: timing.warmup_seconds(),
            sim_dt: timing.dt,
            steps_per_frame: timing.steps_per_frame,
            layout_dt: layout.sim.dt,
        },
        max_speed,
        solver: solver_name,
        notes: solver_note
            .into_iter()
            .chain(formats.contains(&Format::Fga).then(|| fga::note(nx, ny)).flatten())
            .chain(doc::advise(&layout).iter().map(|a| format!("{ADVICE}{a}")))
            .chain(field_notes(&layout, max_speed))
            .collect(),
        profile: Some(manifest::ProfileInfo::new(&layout.world.profile)),
        engines: engines::engines(&ctx, &files),
        files,
        terrain,
    };
    let json = serde_json::to_string_pretty(&manifest).expect("a manifest serialises") + "\n";
    write_file(&dir, MANIFEST, json.as_bytes())?;
    if cancel.load(Ordering::Relaxed) {
        return Err(BakeError::Cancelled);
    }
    staging.commit()?;
    Ok(manifest)
}

/// Everything an exporter needs.
pub(crate) struct ExportContext {
    pub nx: usize,
    pub ny: usize,
    /// Frames in the bake.
    pub count: usize,
    pub max_speed: f32,
    pub min: [f32; 2],
    pub max: [f32; 2],
    pub half: bool,
    pub fps: f32,
    /// Flowmaps and the atlas store green as the world −z wind (up the image).
    pub flip_green: bool,
    /// The vertical profile the volume is baked with.
    pub profile: doc::VerticalProfile,
}

impl ExportContext {
    fn name(&self, stem: &str, k: usize, ext: &str) -> String {
        frame_name(stem, k, self.count, ext)
    }

    fn frame_index(&self, k: usize) -> Option<usize> {
        (self.count > 1).then_some(k)
    }

    /// The speed that maps to the ends of the 8/16-bit flowmap range.
    fn flow_scale(&self) -> f32 {
        self.max_speed.max(1e-6)
    }
}
