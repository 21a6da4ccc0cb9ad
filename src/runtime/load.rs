//! Opening a bake folder: the manifest, the files it lists, and the manifest again, so that
//! what is kept is one whole bake (a bake landing meanwhile is read again); then each file
//! decoded by the manifest's numbers alone.

use crate::file;
use crate::manifest::{self, FileEntry, IndexAxis, Manifest};
use crate::read::{self, Kind};
use crate::wind::{Bake, Grid, Heights, LogLaw, Options};
use crate::{Error, MANIFEST};
use std::path::Path;

/// How many times [`Bake::open`] reads a bake that keeps changing under it (a re-bake
/// landing meanwhile) before it gives up; a reload reads once and tries again at its next
/// poll, so a game's thread never waits out a re-bake.
pub(crate) const ATTEMPTS: usize = 8;

/// The most frames a bake may hold (at 60 fps, 27 minutes).
pub const MAX_FRAMES: usize = 100_000;
/// The most cells a bake may have along x or along z (the editor's largest grid).
pub const MAX_GRID_SIDE: usize = 16_384;
/// The most memory a bake's wind may take once read (every frame's cells, 8 bytes each):
/// the most `windloom bake` writes unless told otherwise (`--max-bytes`). Memory the machine
/// cannot give is refused too, not an abort.
pub const MAX_WIND_BYTES: u64 = 16 << 30;

/// Reads the bake in `folder` whole, reading it again (up to `attempts` times, waiting a
/// little longer each time) while a new bake lands under it.
pub(crate) fn open(
    folder: &Path,
    options: &Options,
    attempts: usize,
) -> Result<(Bake, Vec<u8>), Error> {
    let path = folder.join(MANIFEST);
    let mut last = None;
    for attempt in 0..attempts {
        if attempt > 0 {
            std::thread::sleep(std::time::Duration::from_millis(25 << attempt.min(4)));
        }
        let before = read_manifest(&path)?;
        let m = parse(&path, &before)?;
        let picked = pick(folder, &m, options)?;
        let files: Result<Vec<Vec<u8>>, Error> = (picked.entries.iter())
            .zip(&picked.paths)
            .map(|(e, (p, limit))| file::read(p, *limit, Some(e.bytes)))
            .chain(
                picked
                    .heights
                    .iter()
                    .map(|(p, limit)| file::read(p, *limit, None)),
            )
            .collect();
        // The same manifest after the files: they are all of this bake.
        let after = read_manifest(&path).ok();
        if after.as_deref() != Some(&before[..]) {
            last = Some(files.err());
            continue;
        }
        let files = files?;
        return Ok((decode(folder, m, picked, files, options)?, before));
    }
    Err(match last.flatten() {
        Some(e) => e,
        None => Error::Changing {
            path: folder.to_path_buf(),
            attempts,
        },
    })
}

/// The manifest's bytes, at most [`file::MAX_MANIFEST_BYTES`].
pub(crate) fn read_manifest(path: &Path) -> Result<Vec<u8>, Error> {
    file::read(path, file::MAX_MANIFEST_BYTES, None)
}

/// The manifest's JSON, checked to be one this runtime reads.
pub(crate) fn parse(path: &Path, bytes: &[u8]) -> Result<Manifest, Error> {
    let m: Manifest = serde_json::from_slice(bytes).map_err(|e| Error::Manifest {
        path: path.to_path_buf(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    let bad = |message: String| Error::Bake {
        path: path.to_path_buf(),
        message,
    };
    if m.format != manifest::FORMAT {
        return Err(bad(format!(
            "format: `{}`, not `{}`",
            m.format,
            manifest::FORMAT
        )));
    }
    if m.version != manifest::VERSION {
        return Err(bad(format!(
            "version: {}; this runtime reads version {} (bake again with this windloom)",
            m.version,
            manifest::VERSION
        )));
    }
    let frames_ok = (1..=MAX_FRAMES).contains(&m.frames.count);
    if !(frames_ok && m.frames.fps > 0.0 && m.frames.fps.is_finite()) {
        return Err(bad(format!(
            "frames: {} at {} fps (1 to {MAX_FRAMES} frames, a finite rate above 0)",
            m.frames.count, m.frames.fps
        )));
    }
    if !m.max_speed.is_finite() {
        return Err(bad(format!("max_speed: {}, not a number", m.max_speed)));
    }
    if let Some(p) = &m.profile {
        let numbers = [p.roughness_length, p.reference_height, p.top];
        if !numbers.iter().chain(&p.factors).all(|x| x.is_finite()) {
            return Err(bad(
                "profile: a height, the roughness or a factor is not a finite number".into(),
            ));
        }
    }
    Ok(m)
}

/// The files one format's wind is read from, and the terrain's, each with its path in the
/// folder and the most bytes it may hold.
pub(crate) struct Picked {
    format: String,
    kind: Kind,
    entries: Vec<FileEntry>,
    paths: Vec<(std::path::PathBuf, u64)>,
    heights: Option<(std::path::PathBuf, u64)>,
    /// The cells of the wind's grid, checked against the limits.
    grid: Grid,
}

/// The most bytes a file of `cells` cells of `channels` samples may take: twice the raw
/// floats (a PNG's or an EXR's headers and rows, uncompressed at worst), and 1 MiB more.
fn most_bytes(cells: usize, channels: usize) -> Option<u64> {
    (cells as u64)
        .checked_mul(channels as u64)?
        .checked_mul(8)?
        .checked_add(1 << 20)
}

/// The cells of one file: the product of its index axes' (checked), times the frames it
/// holds.
fn cells_of(e: &FileEntry, frames: usize) -> Option<usize> {
    (e.axes.index.iter()).try_fold(frames, |n, a| n.checked_mul(a.cells))
}

/// How precisely a file holds the wind: lower is better. Full-resolution floats first, a
/// 2D file before a volume (which holds it times the profile), resampled files last.
fn rank(e: &FileEntry) -> u32 {
    let sample = match e.encoding.sample.as_str() {
        "f32" => 0,
        "f16" => 2,
        "unorm16" => 4,
        "unorm8" => 6,
        _ => 100,
    };
    let volume = u32::from(
        e.axes
            .index
            .iter()
            .any(|a| axis_name(&a.world) == "y" && a.cells > 1),
    );
    let resampled = if e.resampled_from.is_some() { 20 } else { 0 };
    sample + volume + resampled
}

fn axis_name(world: &str) -> &str {
    world.trim_start_matches(['+', '-'])
}

fn pick(folder: &Path, m: &Manifest, options: &Options) -> Result<Picked, Error> {
    let path = folder.join(MANIFEST);
    // Group the readable files by format and kind (a volume's DDS, VF and EXR share a format).
    let mut groups: Vec<(String, Kind, Vec<FileEntry>)> = Vec::new();
    // Every name a plain file name in the folder, before any is looked at.
    for (k, e) in m.files.iter().enumerate() {
        file::inside(folder, &e.name, &format!("files[{k}].name"))?;
    }
    if let Some(t) = &m.terrain {
        file::inside(folder, &t.file, "terrain.file")?;
    }
    for e in &m.files {
        let Some(kind) = Kind::of(e).filter(|k| k.available()) else {
            continue;
        };
        match groups.iter_mut().find(|g| g.0 == e.format && g.1 == kind) {
            Some(g) => g.2.push(e.clone()),
            None => groups.push((e.format.clone(), kind, vec![e.clone()])),
        }
    }
    let names: Vec<String> = groups.iter().map(|g| g.0.clone()).collect();
    if let Some(want) = &options.format {
        groups.retain(|g| &g.0 == want);
        if groups.is_empty() {
            return Err(Error::Bake {
                path,
                message: format!(
                    "no `{want}` files the runtime reads; this bake has {}",
                    list(&names)
                ),
            });
        }
    }
    // Every frame must be there: one file holding them all, or one a frame.
    let count = m.frames.count;
    let mut partial = Vec::new();
    groups.retain(|g| {
        let mut frames: Vec<usize> = g.2.iter().filter_map(|e| e.frame).collect();
        frames.sort_unstable();
        let whole = (g.2.len() == 1 && g.2[0].frame.is_none())
            || (frames.len() == g.2.len() && frames.iter().copied().eq(0..count));
        if !whole {
            partial.push(format!(
                "`{}` lists {} file(s) for the {count} frames of `frames.count`",
                g.0,
                g.2.len()
            ));
        }
        whole
    });
    if groups.is_empty()
        && let Some(first) = partial.first()
    {
        return Err(Error::Bake {
            path,
            message: format!("{first}: not every frame is there (a frame is missing or twice)"),
        });
    }
    // The most precise first, the raw file first among equals (the bake's own numbers).
    groups.sort_by_key(|g| (rank(&g.2[0]), g.1 != Kind::Raw));
    // A game may ship only the files it reads: the first format whose every file is there.
    // When none is whole, the best one's first missing file is named.
    let missing = |g: &(String, Kind, Vec<FileEntry>)| {
        g.2.iter()
            .map(|e| folder.join(&e.name))
            .find(|p| !p.exists())
    };
    if !groups.is_empty() && groups.iter().all(|g| missing(g).is_some()) {
        return Err(Error::Bake {
            path: missing(&groups[0]).expect("every group misses a file"),
            message: "not there, and the manifest lists it (ship the files of at least one \
                      format with manifest.json)"
                .into(),
        });
    }
    let best = groups
        .into_iter()
        .find(|g| missing(g).is_none())
        .ok_or_else(|| Error::Bake {
            path: path.clone(),
            message: format!(
                "no file the runtime reads (raw, exr, png8, png16, vf or dds, every frame); \
                 this bake has {}",
                list(&m.files.iter().map(|f| f.format.clone()).collect::<Vec<_>>())
            ),
        })?;
    let (format, kind, mut entries) = best;
    entries.sort_by_key(|e| e.frame);
    sized(folder, m, format, kind, entries)
}

/// The picked files checked against the limits before anything is read: the wind's grid,
/// the memory its frames take, and the bytes each file may hold; the terrain's too.
fn sized(
    folder: &Path,
    m: &Manifest,
    format: String,
    kind: Kind,
    entries: Vec<FileEntry>,
) -> Result<Picked, Error> {
    let bad = |e: &FileEntry, message: String| Error::Bake {
        path: folder.join(&e.name),
        message,
    };
    let first = &entries[0];
    let grid = grid_of(&first.axes.index).filter(sane).ok_or_else(|| {
        bad(
            first,
            format!("axes: no x and z axes of 1 to {MAX_GRID_SIDE} cells over a finite range"),
        )
    })?;
    let count = m.frames.count;
    let wind_bytes = (grid.nx as u64)
        .checked_mul(grid.ny as u64)
        .and_then(|c| c.checked_mul(count as u64))
        .and_then(|c| c.checked_mul(8))
        .filter(|&b| {
            b <= MAX_WIND_BYTES && usize::try_from(b).is_ok_and(|b| b <= isize::MAX as usize)
        });
    if wind_bytes.is_none() {
        return Err(bad(
            first,
            format!(
                "{count} frames of {} × {} cells take more than the {} GiB a bake may hold",
                grid.nx,
                grid.ny,
                MAX_WIND_BYTES >> 30
            ),
        ));
    }
    let mut paths = Vec::with_capacity(entries.len());
    for e in &entries {
        // Every name is a plain one in the folder (`pick` checked them all).
        let path = folder.join(&e.name);
        let frames = if e.frame.is_some() { 1 } else { count };
        let channels = e.encoding.channels.len();
        let limit = cells_of(e, frames)
            .filter(|_| (1..=16).contains(&channels))
            .and_then(|c| most_bytes(c, channels))
            .filter(|&b| b <= 2 * MAX_WIND_BYTES)
            .ok_or_else(|| {
                bad(
                    e,
                    "axes or channels: more cells or channels than a bake holds".into(),
                )
            })?;
        if e.bytes > limit {
            return Err(bad(
                e,
                format!(
                    "bytes: {}, more than a file of its cells and channels takes ({limit})",
                    e.bytes
                ),
            ));
        }
        paths.push((path, limit));
    }
    let heights = match &m.terrain {
        None => None,
        Some(t) => {
            let path = folder.join(&t.file);
            let g = grid_of(&t.axes).filter(sane).ok_or_else(|| Error::Bake {
                path: path.clone(),
                message: format!(
                    "terrain.axes: no x and z axes of 1 to {MAX_GRID_SIDE} cells over a finite range"
                ),
            })?;
            let limit = (g.nx.checked_mul(g.ny))
                .and_then(|c| most_bytes(c, 2))
                .unwrap_or(u64::MAX);
            Some((path, limit))
        }
    };
    Ok(Picked {
        format,
        kind,
        entries,
        paths,
        heights,
        grid,
    })
}

fn list(names: &[String]) -> String {
    let mut n: Vec<&str> = names.iter().map(String::as_str).collect();
    n.sort_unstable();
    n.dedup();
    if n.is_empty() {
        "none".into()
    } else {
        n.join(", ")
    }
}

/// A grid the sampler can index: at most [`MAX_GRID_SIDE`] cells a side (an i32 holds
/// them: its float-to-index conversion relies on it), over a finite rectangle of some size.
fn sane(g: &Grid) -> bool {
    (1..=MAX_GRID_SIDE).contains(&g.nx)
        && (1..=MAX_GRID_SIDE).contains(&g.ny)
        && g.min.iter().chain(&g.max).all(|v| v.is_finite())
        && g.max[0] > g.min[0]
        && g.max[1] > g.min[1]
        && g.per_metre.iter().all(|p| p.is_finite() && *p > 0.0)
}

/// The rectangle an entry's x and z axes cover, and their cells.
fn grid_of(axes: &[IndexAxis]) -> Option<Grid> {
    let find = |name: &str| axes.iter().find(|a| axis_name(&a.world) == name);
    let (x, z) = (find("x")?, find("z")?);
    Some(Grid::new(
        x.cells,
        z.cells,
        [x.range[0], z.range[0]],
        [x.range[1], z.range[1]],
    ))
}

fn decode(
    folder: &Path,
    m: Manifest,
    picked: Picked,
    files: Vec<Vec<u8>>,
    options: &Options,
) -> Result<Bake, Error> {
    let bad = |e: &FileEntry, message: String| Error::Bake {
        path: folder.join(&e.name),
        message,
    };
    let grid = picked.grid.clone();
    let cells = grid.nx * grid.ny;
    let count = m.frames.count;
    let factors = m
        .profile
        .as_ref()
        .map(|p| p.factors.clone())
        .unwrap_or_default();
    let mut wind = Vec::new();
    wind.try_reserve_exact(count * cells).map_err(|_| {
        bad(
            &picked.entries[0],
            format!(
                "not enough memory for the wind's {} MB",
                (count * cells * 8) >> 20
            ),
        )
    })?;
    for (e, bytes) in picked.entries.iter().zip(&files) {
        let want = if e.frame.is_some() { 1 } else { count };
        let in_file = cells_of(e, want).unwrap_or(usize::MAX);
        let stored = read::stored(picked.kind, e, bytes, in_file).map_err(|msg| bad(e, msg))?;
        let frames = decode_file(e, &grid, &stored, &factors).map_err(|msg| bad(e, msg))?;
        if let Some(k) = frames
            .iter()
            .position(|w| !(w[0].is_finite() && w[1].is_finite()))
        {
            return Err(bad(
                e,
                format!(
                    "cell {} of frame {} decodes to {:?} m/s: not a finite wind",
                    k % cells,
                    e.frame.unwrap_or(k / cells),
                    frames[k]
                ),
            ));
        }
        if frames.len() != want * cells {
            return Err(bad(
                e,
                format!(
                    "{} cells where {want} frame(s) of {} × {} need {}",
                    frames.len(),
                    grid.nx,
                    grid.ny,
                    want * cells
                ),
            ));
        }
        wind.extend(frames);
    }
    let heights = match (&m.terrain, files.get(picked.entries.len())) {
        (Some(t), Some(bytes)) => {
            let path = folder.join(&t.file);
            let bad = |message: String| Error::Bake {
                path: path.clone(),
                message,
            };
            if t.sample != "unorm16" {
                return Err(bad(format!("sample `{}`; heights are unorm16", t.sample)));
            }
            if !(t.scale.is_finite() && t.offset.is_finite()) {
                return Err(bad("terrain: scale or offset not a finite number".into()));
            }
            let g = grid_of(&t.axes)
                .filter(sane)
                .ok_or_else(|| bad("terrain.axes: no x and z axes".into()))?;
            let (w, h, grey) = read::grey16(bytes, [g.nx, g.ny]).map_err(bad)?;
            // Rows down the image run +z; a `-z` axis would run them north.
            let flip = t.axes.iter().any(|a| a.world == "-z");
            let metres = (0..h)
                .flat_map(|j| {
                    let row = if flip { h - 1 - j } else { j };
                    grey[row * w..(row + 1) * w].iter().copied()
                })
                .map(|s| s * t.scale + t.offset)
                .collect::<Vec<f32>>();
            if metres.iter().any(|m| !m.is_finite()) {
                return Err(bad("a height decodes to no finite number".into()));
            }
            Some(Heights { grid: g, metres })
        }
        _ => None,
    };
    let heights_on_wind_grid = heights.as_ref().is_some_and(|h| {
        let g = &h.grid;
        (g.nx, g.ny, g.min, g.max) == (grid.nx, grid.ny, grid.min, grid.max)
    });
    Ok(Bake {
        heights_on_wind_grid,
        law: m.profile.as_ref().and_then(LogLaw::new),
        source: picked.entries.iter().map(|e| e.name.clone()).collect(),
        format: picked.format,
        manifest: m,
        grid,
        wind,
        heights,
        options: options.clone(),
    })
}

/// One file's cells as the wind `[x, z]` at the reference height, in the grid's order
/// (row `j` along +z, column `i` along +x), frame after frame.
fn decode_file(
    e: &FileEntry,
    grid: &Grid,
    stored: &read::Stored,
    factors: &[f32],
) -> Result<Vec<[f32; 2]>, String> {
    let index = &e.axes.index;
    let per_cell = stored.channels;
    if per_cell == 0 || !stored.values.len().is_multiple_of(per_cell) {
        return Err("the samples do not fill whole cells".into());
    }
    // The channels: which feed x and z, with their sign and numbers.
    let mut cx = None;
    let mut cz = None;
    for (c, ch) in e.encoding.channels.iter().enumerate() {
        if ch.quantity != "velocity" {
            continue;
        }
        let axis = ch.axis.as_deref().unwrap_or("");
        let sign = if axis.starts_with('-') { -1.0 } else { 1.0 };
        match axis_name(axis) {
            "x" => cx = Some((c, sign, ch.scale, ch.offset)),
            "z" => cz = Some((c, sign, ch.scale, ch.offset)),
            _ => {}
        }
    }
    let (Some(cx), Some(cz)) = (cx, cz) else {
        return Err("encoding: no velocity channels along x and z".into());
    };
    if ![cx.2, cx.3, cz.2, cz.3].iter().all(|v| v.is_finite()) {
        return Err("encoding: a channel's scale or offset is not a finite number".into());
    }
    // The index axes: per file axis, its cells, and where it goes (x, z, a layer).
    let mut layer_axis = None;
    for (a, axis) in index.iter().enumerate() {
        match axis_name(&axis.world) {
            "x" if axis.cells == grid.nx => {}
            "z" if axis.cells == grid.ny => {}
            "x" | "z" => {
                return Err(format!(
                    "axes: {} cells along {}, where the bake's first file has {} × {}",
                    axis.cells, axis.world, grid.nx, grid.ny
                ));
            }
            "y" if axis.cells == 1 => {}
            "y" => layer_axis = Some(a),
            other => return Err(format!("axes: an index axis along `{other}`")),
        }
    }
    // A volume holds the wind times each layer's factor: read the layer nearest the
    // reference height (factor nearest 1) and divide its factor out.
    let layer = match layer_axis {
        None => None,
        Some(a) => {
            if factors.len() != index[a].cells {
                return Err(format!(
                    "a volume of {} layers, and the manifest's profile has {} factors",
                    index[a].cells,
                    factors.len()
                ));
            }
            let k = (0..factors.len())
                .filter(|&k| factors[k] > 0.0)
                .min_by(|&a, &b| {
                    libm::fabsf(libm::logf(factors[a]))
                        .total_cmp(&libm::fabsf(libm::logf(factors[b])))
                })
                .ok_or("the profile's factors are all zero: no layer holds the wind")?;
            Some((a, k, 1.0 / factors[k]))
        }
    };
    let per_frame = cells_of(e, 1).ok_or("axes: more cells than a bake holds")?;
    let cells = stored.values.len() / per_cell;
    if per_frame == 0 || !cells.is_multiple_of(per_frame) {
        return Err(format!(
            "{cells} cells, not a whole number of the axes' {per_frame}"
        ));
    }
    let frames = cells / per_frame;
    let plane = grid.nx * grid.ny;
    let mut out = vec![[0.0f32; 2]; frames * plane];
    let value = |s: &[f32], (c, sign, scale, offset): (usize, f32, f32, f32)| {
        sign * (s[c] * scale + offset)
    };
    let mut coord = vec![0usize; index.len()];
    for (flat, s) in stored.values.chunks_exact(per_cell).enumerate() {
        let frame = flat / per_frame;
        let mut rest = flat % per_frame;
        for (a, axis) in index.iter().enumerate() {
            coord[a] = rest % axis.cells;
            rest /= axis.cells;
        }
        let (mut i, mut j, mut keep) = (0, 0, true);
        for (a, axis) in index.iter().enumerate() {
            let c = if axis.world.starts_with('-') {
                axis.cells - 1 - coord[a]
            } else {
                coord[a]
            };
            match axis_name(&axis.world) {
                "x" => i = c,
                "z" => j = c,
                _ => {
                    if let Some((la, k, _)) = layer
                        && la == a
                    {
                        keep = c == k;
                    }
                }
            }
        }
        if keep {
            let up = layer.map_or(1.0, |l| l.2);
            out[frame * plane + j * grid.nx + i] = [value(s, cx) * up, value(s, cz) * up];
        }
    }
    Ok(out)
}
