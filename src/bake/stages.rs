//! A bake, step by step: [`check`] the request and stage the folder, [`simulate`] the frames
//! to disk, [`encode`] them in every format, [`write_manifest`]; then the staging folder
//! replaces the output folder.

use super::encoders::{disk_need, encoder, output_names};
use super::error::{BakeError, human_bytes};
use super::field::{check_finite, crossfade};
use super::folder::{self, Staging, sync_file, write_file};
use super::format::ExportContext;
use super::frames::{FrameReader, FrameWriter};
use super::manifest::{
    self, FileEntry, Format, FramesInfo, LayoutInfo, MANIFEST, MANIFEST_VERSION, Manifest,
    WorldInfo, layout_hash,
};
use super::notes::{ADVICE, field_notes};
use super::options::{self, BakeOptions, SettingsError};
use super::timing::FrameTiming;
use super::{exr, fga, heights, png, raw};
use crate::doc::{self, Layout};
use crate::engine::Stepper;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// Progress reports: `(done, total, what)`.
pub type Progress<'a> = &'a mut dyn FnMut(usize, usize, &str);

/// [`super::bake`], whose errors may still name files in the staging folder.
pub(super) fn bake_staged(
    layout: &Layout,
    out: &Path,
    opts: &BakeOptions,
    cancel: &AtomicBool,
    progress: Progress<'_>,
) -> Result<Manifest, BakeError> {
    let plan = check(layout, out, opts)?;
    let frames = simulate(&plan, opts, cancel, &mut *progress)?;
    let (ctx, files) = encode(&plan, opts, &frames, cancel, &mut *progress)?;
    let manifest = write_manifest(&plan, opts, &ctx, frames, files)?;
    if cancel.load(Ordering::Relaxed) {
        return Err(BakeError::Cancelled);
    }
    plan.staging.commit()?;
    Ok(manifest)
}

/// A bake checked and staged: what the steps after the check share.
struct Plan {
    /// The layout at the bake's grid.
    layout: Layout,
    /// The formats asked for, each once, in order.
    formats: Vec<Format>,
    timing: FrameTiming,
    nx: usize,
    ny: usize,
    /// Frames to write.
    count: usize,
    staging: Staging,
    /// The staging folder, where every file is written.
    dir: PathBuf,
}

/// The request checked (settings, layout, the output folder's name, the disk it needs) and
/// the staging folder made beside `out`.
fn check(layout: &Layout, out: &Path, opts: &BakeOptions) -> Result<Plan, BakeError> {
    let layout = check_layout(layout, opts)?;
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
    let count = opts.frames;
    let mut formats = opts.formats.clone();
    formats.sort();
    formats.dedup();
    if formats.contains(&Format::Atlas) || formats.contains(&Format::AtlasExr) {
        options::check_atlas(count, nx, ny)?;
    }
    let layers = layout.world.profile.layers as usize;
    let heights_need = if layout.world.terrain.is_some() {
        (nx * ny * 2) as u64 + 65536
    } else {
        0
    };
    let need = disk_need(nx, ny, layers, &formats, count, opts.looped, opts.half) + heights_need;
    if need > opts.max_bytes {
        return Err(BakeError::Disk {
            need,
            limit: format!("the {} budget", human_bytes(opts.max_bytes)),
            budget: true,
        });
    }
    let staging = Staging::new(out)?;
    if let Some(free) = crate::platform::fs::free_space(staging.path())
        && need > free
    {
        return Err(BakeError::Disk {
            need,
            limit: format!("the {} free on {}", human_bytes(free), out.display()),
            budget: false,
        });
    }
    let mut names = output_names(&formats, count);
    if layout.world.terrain.is_some() {
        names.push(heights::NAME.to_string());
    }
    staging.check_names(names.iter().map(String::as_str))?;
    let dir = staging.path().to_path_buf();
    Ok(Plan {
        layout,
        formats,
        timing,
        nx,
        ny,
        count,
        staging,
        dir,
    })
}

/// The settings checked, and the layout at the bake's grid checked as a bake needs it: valid,
/// its masks there, and every name in it one that every platform can hold.
fn check_layout(layout: &Layout, opts: &BakeOptions) -> Result<Layout, BakeError> {
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
    Ok(layout)
}

/// The frames simulated and on disk.
struct Simulated {
    /// The frame stream: `wind.f32` when `raw` is kept, else a hidden file removed after
    /// encoding.
    path: PathBuf,
    keep_raw: bool,
    /// Its length, flushed to disk.
    bytes: u64,
    max_speed: f32,
    solver_name: String,
    solver_note: Option<String>,
    /// Steps simulated, and those plus the frames to encode (for progress).
    sim_steps: usize,
    total: usize,
}

/// Simulates with the step that fits the frame rate, streaming each frame to disk; a loop's
/// `2N` frames are crossfaded into `N`.
fn simulate(
    plan: &Plan,
    opts: &BakeOptions,
    cancel: &AtomicBool,
    progress: Progress<'_>,
) -> Result<Simulated, BakeError> {
    let (timing, n, nx, ny) = (&plan.timing, plan.count, plan.nx, plan.ny);
    let mut sim_layout = plan.layout.clone();
    sim_layout.sim.dt = timing.dt;
    let simulated = if opts.looped { 2 * n } else { n };
    let sim_steps = timing.warmup_steps + (simulated - 1) * timing.steps_per_frame;
    let total = sim_steps + n;
    let keep_raw = plan.formats.contains(&Format::Raw);
    let frames_path = plan
        .dir
        .join(if keep_raw { raw::NAME } else { ".frames.f32" });
    let source_path = if opts.looped {
        plan.dir.join(".loop-source.f32")
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
    for k in 0..simulated {
        if k > 0 {
            advance(&mut solver, timing.steps_per_frame)?;
        }
        let field = solver.velocity_field().map_err(SettingsError::Gpu)?;
        check_finite(&field, k)?;
        writer.push(&field)?;
    }
    drop(solver);
    let mut max_speed = writer.max_speed;
    let mut bytes = writer.finish()?;
    if opts.looped {
        let mut source = FrameReader::open(&source_path, nx, ny)?;
        let mut looped = FrameWriter::create(&frames_path, nx, ny)?;
        for k in 0..n {
            let (late, early) = (source.read(k + n)?, source.read(k)?);
            looped.push(&crossfade(&late, &early, k, n).data)?;
        }
        max_speed = looped.max_speed;
        bytes = looped.finish()?;
        drop(source);
        remove(&source_path)?;
    }
    Ok(Simulated {
        path: frames_path,
        keep_raw,
        bytes,
        max_speed,
        solver_name,
        solver_note,
        sim_steps,
        total,
    })
}

fn remove(path: &Path) -> Result<(), BakeError> {
    std::fs::remove_file(path).map_err(|source| BakeError::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// Every format's files, one frame at a time (the atlases and `raw`, whose one file holds
/// every frame, beside the loop), each file's manifest entry with its size.
fn encode(
    plan: &Plan,
    opts: &BakeOptions,
    sim: &Simulated,
    cancel: &AtomicBool,
    progress: Progress<'_>,
) -> Result<(ExportContext, Vec<FileEntry>), BakeError> {
    let (min, max) = plan.layout.bounds();
    let ctx = ExportContext {
        nx: plan.nx,
        ny: plan.ny,
        count: plan.count,
        max_speed: sim.max_speed,
        min,
        max,
        half: opts.half,
        fps: opts.fps,
        flip_green: opts.flip_green,
        profile: plan.layout.world.profile.clone(),
    };
    let (dir, formats) = (&plan.dir, &plan.formats);
    let mut files: BTreeMap<Format, Vec<FileEntry>> = BTreeMap::new();
    let mut atlas = if formats.contains(&Format::Atlas) {
        Some(png::Atlas::create(&ctx, &dir.join(png::ATLAS_NAME))?)
    } else {
        None
    };
    let mut reader = FrameReader::open(&sim.path, plan.nx, plan.ny)?;
    for k in 0..plan.count {
        if cancel.load(Ordering::Relaxed) {
            return Err(BakeError::Cancelled);
        }
        let f = reader.read(k)?;
        for &format in formats {
            for output in encoder(format).frame(&ctx, k, &f)? {
                let mut entry = output.entry;
                entry.bytes = write_file(dir, &output.name, &output.bytes)?;
                files.entry(format).or_default().push(entry);
            }
        }
        if let Some(a) = &mut atlas {
            a.push(f)?;
        }
        progress(sim.sim_steps + k + 1, sim.total, "encoding");
    }
    if formats.contains(&Format::AtlasExr) {
        let (bytes, mut entry) = exr::atlas(&ctx, &mut reader)?;
        entry.bytes = write_file(dir, exr::ATLAS_EXR_NAME, &bytes)?;
        files.insert(Format::AtlasExr, vec![entry]);
    }
    drop(reader);
    if let Some(a) = atlas {
        let (path, mut entry) = a.finish()?;
        entry.bytes = sync_file(&path)?;
        files.insert(Format::Atlas, vec![entry]);
    }
    if sim.keep_raw {
        let mut entry = raw::entry(&ctx);
        entry.bytes = sim.bytes;
        files.insert(Format::Raw, vec![entry]);
    } else {
        remove(&sim.path)?;
    }
    Ok((ctx, files.into_values().flatten().collect()))
}

/// The terrain's heights and `manifest.json`, last: each file's CRC read back as it lies on
/// disk (what the next bake into the folder checks before it removes a file as this bake's).
fn write_manifest(
    plan: &Plan,
    opts: &BakeOptions,
    ctx: &ExportContext,
    sim: Simulated,
    mut files: Vec<FileEntry>,
) -> Result<Manifest, BakeError> {
    let (layout, dir, (nx, ny)) = (&plan.layout, &plan.dir, (plan.nx, plan.ny));
    let mut terrain = heights::write(dir, layout)?;
    for e in &mut files {
        e.crc32 = folder::crc32_of(&dir.join(&e.name))?;
    }
    if let Some(t) = &mut terrain {
        t.crc32 = folder::crc32_of(&dir.join(t.file))?;
    }
    let has_fga = plan.formats.contains(&Format::Fga);
    let manifest = Manifest {
        format: manifest::FORMAT,
        version: MANIFEST_VERSION,
        sequence: plan.staging.next_sequence(),
        layout: LayoutInfo {
            name: layout.name.clone(),
            hash: layout_hash(layout),
        },
        grid: [nx, ny],
        world: WorldInfo {
            min: ctx.min,
            max: ctx.max,
            units: "m",
            cell_size: [
                layout.world.size[0] / nx as f32,
                layout.world.size[1] / ny as f32,
            ],
        },
        world_axes: manifest::WORLD_AXES,
        frames: FramesInfo {
            count: plan.count,
            fps: opts.fps,
            looped: opts.looped,
            loop_method: opts.looped.then_some(
                "crossfade: frame k = (1 - k/N)·S[k+N] + (k/N)·S[k] over 2N simulated frames S, S[j] at warmup_seconds + j / fps",
            ),
            warmup_seconds: plan.timing.warmup_seconds(),
            sim_dt: plan.timing.dt,
            steps_per_frame: plan.timing.steps_per_frame,
            layout_dt: layout.sim.dt,
        },
        max_speed: sim.max_speed,
        solver: sim.solver_name,
        notes: sim
            .solver_note
            .into_iter()
            .chain(has_fga.then(|| fga::note(nx, ny)).flatten())
            .chain(doc::advise(layout).iter().map(|a| format!("{ADVICE}{a}")))
            .chain(field_notes(layout, sim.max_speed))
            .collect(),
        profile: Some(manifest::profile_info(&layout.world.profile)),
        engines: super::engines::engines(ctx, &files),
        files,
        terrain,
    };
    let json = serde_json::to_string_pretty(&manifest).expect("a manifest serialises") + "\n";
    write_file(dir, MANIFEST, json.as_bytes())?;
    Ok(manifest)
}
