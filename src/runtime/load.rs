//! Opening a bake folder: the manifest, the files it lists, and the manifest again, so that
//! what is kept is one whole bake (a bake landing meanwhile is read again); then each file
//! decoded by the manifest's numbers alone.

use crate::manifest::{self, FileEntry, IndexAxis, Manifest};
use crate::read::{self, Kind};
use crate::wind::{Bake, Grid, Heights, LogLaw, Options};
use crate::{Error, MANIFEST};
use std::path::Path;

/// How many times a bake that keeps changing under the reader is read again.
const ATTEMPTS: usize = 8;

/// Reads the bake in `folder` whole.
pub(crate) fn open(folder: &Path, options: &Options) -> Result<(Bake, Vec<u8>), Error> {
    let path = folder.join(MANIFEST);
    let mut last = None;
    for attempt in 0..ATTEMPTS {
        if attempt > 0 {
            std::thread::sleep(std::time::Duration::from_millis(25 << attempt.min(4)));
        }
        let before = read_file(&path)?;
        let m = parse(&path, &before)?;
        let picked = pick(folder, &m, options)?;
        let files: Result<Vec<Vec<u8>>, Error> = picked
            .entries
            .iter()
            .map(|e| read_entry(folder, e))
            .chain(picked.heights.iter().map(|h| read_file(&folder.join(h))))
            .collect();
        // The same manifest after the files: they are all of this bake.
        let after = std::fs::read(&path).ok();
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
            attempts: ATTEMPTS,
        },
    })
}

pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>, Error> {
    std::fs::read(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })
}

fn read_entry(folder: &Path, e: &FileEntry) -> Result<Vec<u8>, Error> {
    let path = folder.join(&e.name);
    let bytes = read_file(&path)?;
    if bytes.len() as u64 != e.bytes {
        return Err(Error::Bake {
            path,
            message: format!(
                "{} bytes where the manifest lists {}: not the file this bake wrote",
                bytes.len(),
                e.bytes
            ),
        });
    }
    Ok(bytes)
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
    if m.frames.count == 0 || !(m.frames.fps > 0.0 && m.frames.fps.is_finite()) {
        return Err(bad(format!(
            "frames: {} at {} fps",
            m.frames.count, m.frames.fps
        )));
    }
    Ok(m)
}

/// The files one format's wind is read from, and the terrain's.
pub(crate) struct Picked {
    format: String,
    kind: Kind,
    entries: Vec<FileEntry>,
    heights: Option<String>,
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
    groups.retain(|g| {
        let mut frames: Vec<usize> = g.2.iter().filter_map(|e| e.frame).collect();
        frames.sort_unstable();
        (g.2.len() == 1 && g.2[0].frame.is_none()) || frames == (0..count).collect::<Vec<_>>()
    });
    // The most precise first, the raw file first among equals (the bake's own numbers).
    groups.sort_by_key(|g| (rank(&g.2[0]), g.1 != Kind::Raw));
    // A game may ship only the files it reads: the first format whose every file is there.
    // When none is whole, the best one's first missing file is named.
    let missing = |g: &(String, Kind, Vec<FileEntry>)| {
        g.2.iter()
            .map(|e| folder.join(&e.name))
            .find(|p| !p.is_file())
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
    Ok(Picked {
        format,
        kind,
        entries,
        heights: m.terrain.as_ref().map(|t| t.file.clone()),
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

/// A grid the sampler can index: sides an i32 holds (its float-to-index conversion relies on
/// it), over a rectangle of some size.
fn sane(g: &Grid) -> bool {
    (1..=1 << 24).contains(&g.nx)
        && (1..=1 << 24).contains(&g.ny)
        && g.max[0] > g.min[0]
        && g.max[1] > g.min[1]
        && g.per_metre.iter().all(|p| p.is_finite())
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
    let first = &picked.entries[0];
    let bad = |e: &FileEntry, message: String| Error::Bake {
        path: folder.join(&e.name),
        message,
    };
    let grid = grid_of(&first.axes.index)
        .filter(sane)
        .ok_or_else(|| bad(first, "axes: no x and z axes with cells and a range".into()))?;
    let cells = grid.nx * grid.ny;
    let count = m.frames.count;
    let factors = m
        .profile
        .as_ref()
        .map(|p| p.factors.clone())
        .unwrap_or_default();
    let mut wind = Vec::with_capacity(count * cells);
    for (e, bytes) in picked.entries.iter().zip(&files) {
        let stored = read::stored(picked.kind, e, bytes).map_err(|msg| bad(e, msg))?;
        let frames = decode_file(e, &grid, &stored, &factors).map_err(|msg| bad(e, msg))?;
        let want = if e.frame.is_some() { 1 } else { count };
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
            let (w, h, grey) = read::grey16(bytes).map_err(bad)?;
            let g = grid_of(&t.axes)
                .filter(|g| g.nx == w && g.ny == h && sane(g))
                .ok_or_else(|| bad(format!("{w} × {h} pixels, not as the manifest's axes")))?;
            if t.sample != "unorm16" {
                return Err(bad(format!("sample `{}`; heights are unorm16", t.sample)));
            }
            // Rows down the image run +z; a `-z` axis would run them north.
            let flip = t.axes.iter().any(|a| a.world == "-z");
            let metres = (0..h)
                .flat_map(|j| {
                    let row = if flip { h - 1 - j } else { j };
                    grey[row * w..(row + 1) * w].iter().copied()
                })
                .map(|s| s * t.scale + t.offset)
                .collect();
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
    let per_frame: usize = index.iter().map(|a| a.cells).product();
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
