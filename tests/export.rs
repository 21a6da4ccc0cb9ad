//! Bakes read back by readers written from the format specifications
//! (`../shared/reference/export-formats.md`), not by the writers' code, and compared with the
//! raw field.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use windloom::bake::{self, BakeOptions, Format};
use windloom::doc::Layout;

fn example(name: &str) -> Layout {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("layouts")
        .join(name);
    windloom::io::load(&p).unwrap()
}

fn run(layout: &Layout, out: &Path, opts: &BakeOptions) -> bake::Manifest {
    bake::bake(
        layout,
        out,
        opts,
        &AtomicBool::new(false),
        &mut |_, _, _| {},
    )
    .unwrap()
}

fn small(frames: usize) -> BakeOptions {
    BakeOptions {
        warmup: 1.5,
        frames,
        fps: 10.0,
        grid: Some([48, 32]),
        ..Default::default()
    }
}

fn f32s(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// The raw bake: `[frame][j][i][x, z]`.
struct Raw {
    nx: usize,
    ny: usize,
    data: Vec<f32>,
}

impl Raw {
    fn read(dir: &Path, m: &serde_json::Value) -> Raw {
        let grid = &m["grid"];
        let (nx, ny) = (
            grid[0].as_u64().unwrap() as usize,
            grid[1].as_u64().unwrap() as usize,
        );
        let data = f32s(&std::fs::read(dir.join("wind.f32")).unwrap());
        let frames = m["frames"]["count"].as_u64().unwrap() as usize;
        assert_eq!(data.len(), frames * nx * ny * 2, "raw length");
        Raw { nx, ny, data }
    }

    fn at(&self, frame: usize, i: usize, j: usize) -> [f32; 2] {
        let k = ((frame * self.ny + j) * self.nx + i) * 2;
        [self.data[k], self.data[k + 1]]
    }
}

fn manifest(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("manifest.json")).unwrap()).unwrap()
}

fn file_of<'a>(m: &'a serde_json::Value, format: &str) -> Vec<&'a serde_json::Value> {
    m["files"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["format"] == format)
        .collect()
}

#[test]
fn manifest_lists_exactly_the_files_written() {
    let dir = tempfile::tempdir().unwrap();
    let layout = example("obstacles.json");
    run(&layout, dir.path(), &small(3));
    let m = manifest(dir.path());
    assert_eq!(m["format"], "windloom-bake");
    assert_eq!(m["version"], 1);
    assert_eq!(m["layout"]["name"], "Obstacles");
    assert_eq!(
        m["layout"]["hash"],
        bake::layout_hash(&{
            let mut l = layout.clone();
            l.world.grid = [48, 32];
            l
        })
    );
    assert_eq!(m["grid"], serde_json::json!([48, 32]));
    assert_eq!(m["world"]["units"], "m");
    assert_eq!(m["world"]["max"], serde_json::json!([120.0, 120.0]));
    assert_eq!(m["frames"]["count"], 3);
    assert_eq!(m["frames"]["fps"], 10.0);
    assert_eq!(m["frames"]["loop"], false);
    for f in m["files"].as_array().unwrap() {
        assert!(f["axes"].is_object() && f["encoding"].is_object(), "{f}");
    }
    let listed: BTreeSet<String> = m["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["name"].as_str().unwrap().to_string())
        .chain(["manifest.json".to_string()])
        .collect();
    let on_disk: BTreeSet<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert_eq!(listed, on_disk, "no staging leftovers, nothing unlisted");
    for f in m["files"].as_array().unwrap() {
        let len = std::fs::metadata(dir.path().join(f["name"].as_str().unwrap()))
            .unwrap()
            .len();
        assert_eq!(f["bytes"].as_u64().unwrap(), len);
    }
}

#[test]
fn fga_reads_back_per_the_unreal_format() {
    let dir = tempfile::tempdir().unwrap();
    run(&example("obstacles.json"), dir.path(), &small(1));
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let text = std::fs::read_to_string(dir.path().join("wind.fga")).unwrap();
    // Comma-separated numbers with any whitespace between them.
    let nums: Vec<f64> = text
        .split([',', '\n', ' ', '\r', '\t'])
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap())
        .collect();
    let (sx, sy, sz) = (nums[0] as usize, nums[1] as usize, nums[2] as usize);
    assert_eq!((sx, sy, sz), (48, 32, 1));
    // Bounds in centimetres: x and z of the world, a slab in Unreal Z.
    assert_eq!(&nums[3..9], &[0.0, 0.0, 0.0, 12000.0, 12000.0, 200.0]);
    let vecs = &nums[9..];
    assert_eq!(
        vecs.len(),
        sx * sy * sz * 3,
        "exactly SizeX*SizeY*SizeZ vectors"
    );
    // X fastest, then Y: index x + SizeX * y; vectors in cm/s, Unreal Y = world z.
    for (i, j) in [(0, 0), (47, 0), (5, 17), (47, 31), (20, 9)] {
        let k = (i + sx * j) * 3;
        let want = raw.at(0, i, j);
        assert!(
            (vecs[k] - f64::from(want[0]) * 100.0).abs() < 1e-2,
            "x at {i},{j}"
        );
        assert!(
            (vecs[k + 1] - f64::from(want[1]) * 100.0).abs() < 1e-2,
            "y at {i},{j}"
        );
        assert_eq!(vecs[k + 2], 0.0);
    }
    // Size, minimum and maximum on three lines, then one vector per line.
    assert_eq!(text.lines().count(), 3 + sx * sy);
}

/// Reads an FGA the way line-based readers do (Blender's FGA add-on and others): line 1 the
/// sizes, line 2 the minimum corner, line 3 the maximum corner, then one vector per line.
fn fga_by_lines(text: &str) -> ([usize; 3], [f64; 3], [f64; 3], Vec<[f64; 3]>) {
    let mut lines = text.lines();
    let mut row = |what: &str| -> Vec<f64> {
        lines
            .next()
            .unwrap_or_else(|| panic!("no {what} line"))
            .split(',')
            .filter(|t| !t.trim().is_empty())
            .map(|t| t.trim().parse().unwrap())
            .collect()
    };
    let size = row("size");
    let min = row("min");
    let max = row("max");
    assert_eq!(
        (size.len(), min.len(), max.len()),
        (3, 3, 3),
        "three values a line"
    );
    let vectors: Vec<[f64; 3]> = lines
        .map(|l| {
            let v: Vec<f64> = l
                .split(',')
                .filter(|t| !t.trim().is_empty())
                .map(|t| t.trim().parse().unwrap())
                .collect();
            assert_eq!(v.len(), 3, "one vector per line: {l:?}");
            [v[0], v[1], v[2]]
        })
        .collect();
    (
        [size[0] as usize, size[1] as usize, size[2] as usize],
        [min[0], min[1], min[2]],
        [max[0], max[1], max[2]],
        vectors,
    )
}

#[test]
fn fga_reads_the_same_line_by_line() {
    let dir = tempfile::tempdir().unwrap();
    let layout = example("two-winds.json");
    run(&layout, dir.path(), &small(1));
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let text = std::fs::read_to_string(dir.path().join("wind.fga")).unwrap();
    let (size, min, max, vectors) = fga_by_lines(&text);
    assert_eq!(size, [48, 32, 1]);
    let (lo, hi) = layout.bounds();
    assert_eq!(
        min,
        [f64::from(lo[0]) * 100.0, f64::from(lo[1]) * 100.0, 0.0]
    );
    assert_eq!(
        max,
        [f64::from(hi[0]) * 100.0, f64::from(hi[1]) * 100.0, 200.0]
    );
    assert_eq!(vectors.len(), 48 * 32);
    for (i, j) in [(0, 0), (3, 5), (47, 31), (20, 9)] {
        let v = vectors[i + 48 * j];
        let want = raw.at(0, i, j);
        assert!(
            (v[0] - f64::from(want[0]) * 100.0).abs() < 1e-2,
            "x at {i},{j}"
        );
        assert!(
            (v[1] - f64::from(want[1]) * 100.0).abs() < 1e-2,
            "y at {i},{j}"
        );
    }
}

#[test]
fn fga_is_area_averaged_down_to_128() {
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::Fga, Format::Raw],
        grid: Some([256, 192]),
        warmup: 1.0,
        ..Default::default()
    };
    let m = run(&example("obstacles.json"), dir.path(), &opts);
    assert!(
        m.notes
            .iter()
            .any(|n| n.contains("resampled 256x192 to 128x96")),
        "{:?}",
        m.notes
    );
    let fga = m.files.iter().find(|f| f.format == Format::Fga).unwrap();
    assert_eq!(fga.grid, [128, 96]);
    assert_eq!(fga.resampled_from, Some([256, 192]));
    let mj = manifest(dir.path());
    let raw = Raw::read(dir.path(), &mj);
    let text = std::fs::read_to_string(dir.path().join("wind.fga")).unwrap();
    let nums: Vec<f64> = text
        .split([',', '\n'])
        .filter(|t| !t.trim().is_empty())
        .map(|t| t.trim().parse().unwrap())
        .collect();
    // Each FGA cell is the mean of a 2×2 block of the raw grid.
    for (i, j) in [(0, 0), (63, 40), (127, 95), (10, 70)] {
        let k = 9 + (i + 128 * j) * 3;
        let mut mean = [0.0f64; 2];
        for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let v = raw.at(0, 2 * i + di, 2 * j + dj);
            mean[0] += f64::from(v[0]) * 25.0;
            mean[1] += f64::from(v[1]) * 25.0;
        }
        assert!(
            (nums[k] - mean[0]).abs() < 1e-2 && (nums[k + 1] - mean[1]).abs() < 1e-2,
            "cell {i},{j}"
        );
    }
}

#[test]
fn vf_reads_back_per_the_unity_format() {
    let dir = tempfile::tempdir().unwrap();
    run(&example("two-winds.json"), dir.path(), &small(1));
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let bytes = std::fs::read(dir.path().join("wind.vf")).unwrap();
    assert_eq!(&bytes[0..4], b"VF_V");
    let size: Vec<usize> = bytes[4..10]
        .chunks_exact(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]) as usize)
        .collect();
    assert_eq!(size, vec![48, 1, 32]);
    assert_eq!(bytes.len(), 10 + 4 * 3 * 48 * 32, "exact length");
    let v = f32s(&bytes[10..]);
    // Unity Z points north: Z index k holds grid row ny-1-k; vectors (x, 0, -z).
    for (i, j) in [(0, 0), (47, 31), (24, 16), (3, 29)] {
        let k = 31 - j;
        let idx = (i + 48 * k) * 3;
        let want = raw.at(0, i, j);
        assert_eq!(
            [v[idx], v[idx + 1], v[idx + 2]],
            [want[0], 0.0, -want[1]],
            "cell {i},{j}"
        );
    }
}

#[test]
fn exr_reads_back_with_the_exr_crate() {
    use exr::prelude::*;
    for half in [false, true] {
        let dir = tempfile::tempdir().unwrap();
        let opts = BakeOptions {
            formats: vec![Format::Exr, Format::Raw],
            half,
            ..small(1)
        };
        run(&example("meadow.json"), dir.path(), &opts);
        let m = manifest(dir.path());
        let raw = Raw::read(dir.path(), &m);
        let image = read_all_flat_layers_from_file(dir.path().join("wind.exr")).unwrap();
        let layer = &image.layer_data[0];
        assert_eq!(layer.size, Vec2(48, 32));
        let names: Vec<String> = layer
            .channel_data
            .list
            .iter()
            .map(|c| c.name.to_string())
            .collect();
        assert_eq!(names, ["B", "G", "R"], "R, G and B are all present");
        let channel = |name: &str| {
            let c = layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name.to_string() == name)
                .unwrap();
            c.sample_data.values_as_f32().collect::<Vec<f32>>()
        };
        let (r, g, b) = (channel("R"), channel("G"), channel("B"));
        for (i, j) in [(0, 0), (47, 31), (24, 16), (10, 20)] {
            let want = raw.at(0, i, j);
            let k = j * 48 + i;
            let tol = if half {
                2e-3 * want[0].abs().max(want[1].abs()).max(1.0)
            } else {
                0.0
            };
            assert!(
                (r[k] - want[0]).abs() <= tol,
                "R at {i},{j}: {} vs {}",
                r[k],
                want[0]
            );
            assert!((g[k] - want[1]).abs() <= tol, "G at {i},{j}");
            assert!(
                (b[k] - want[0].hypot(want[1])).abs() <= tol.max(1e-6),
                "B at {i},{j}"
            );
        }
    }
}

#[test]
fn png_flowmaps_decode_within_quantisation() {
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::Png8, Format::Png16, Format::Raw],
        ..small(1)
    };
    let manifest_struct = run(&example("branching.json"), dir.path(), &opts);
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let scale = m["max_speed"].as_f64().unwrap() as f32;
    assert!((scale - manifest_struct.max_speed).abs() < 1e-6 && scale > 1.0);
    for (name, max, bits) in [("flow8.png", 255.0f32, 8), ("flow16.png", 65535.0, 16)] {
        let entry = file_of(&m, if bits == 8 { "png8" } else { "png16" })[0];
        assert_eq!(entry["encoding"]["scale"].as_f64().unwrap() as f32, scale);
        let img = image::open(dir.path().join(name)).unwrap();
        assert_eq!((img.width(), img.height()), (48, 32));
        let img = img.to_rgb16();
        let step = 2.0 * scale / max; // one quantisation step in m/s
        for (i, j) in [(0, 0), (47, 31), (24, 16), (10, 5)] {
            let p = img.get_pixel(i as u32, j as u32);
            // to_rgb16 widens 8-bit values by 257; divide back to the file's own levels.
            let to_unit = |c: u16| {
                if bits == 8 {
                    f32::from(c) / 257.0 / 255.0
                } else {
                    f32::from(c) / 65535.0
                }
            };
            let decode = |c: u16| (to_unit(c) * 2.0 - 1.0) * scale;
            let want = raw.at(0, i, j);
            assert!(
                (decode(p[0]) - want[0]).abs() <= step,
                "{name} R at {i},{j}"
            );
            assert!(
                (decode(p[1]) - want[1]).abs() <= step,
                "{name} G at {i},{j}"
            );
            assert_eq!(p[2], 0, "{name} B unused");
        }
    }
}

#[test]
fn atlas_holds_every_frame_where_the_manifest_says() {
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::Atlas, Format::Raw],
        ..small(5)
    };
    run(&example("obstacles.json"), dir.path(), &opts);
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let entry = file_of(&m, "atlas")[0];
    let sub = &entry["axes"]["sub_images"];
    let (cols, rows) = (
        sub["columns"].as_u64().unwrap() as u32,
        sub["rows"].as_u64().unwrap() as u32,
    );
    assert_eq!((cols, rows, sub["count"].as_u64().unwrap()), (3, 2, 5));
    let img = image::open(dir.path().join("atlas.png"))
        .unwrap()
        .to_rgb16();
    assert_eq!((img.width(), img.height()), (cols * 48, rows * 32));
    let scale = m["max_speed"].as_f64().unwrap() as f32;
    for frame in 0..5 {
        let (ox, oy) = ((frame as u32 % cols) * 48, (frame as u32 / cols) * 32);
        for (i, j) in [(0, 0), (47, 31), (20, 10)] {
            let p = img.get_pixel(ox + i as u32, oy + j as u32);
            let decode = |c: u16| (f32::from(c) / 65535.0 * 2.0 - 1.0) * scale;
            let want = raw.at(frame, i, j);
            assert!(
                (decode(p[0]) - want[0]).abs() <= 2.0 * scale / 65535.0,
                "frame {frame} at {i},{j}"
            );
            assert!((decode(p[1]) - want[1]).abs() <= 2.0 * scale / 65535.0);
        }
    }
    // The unused sixth cell is zero velocity.
    let p = img.get_pixel(2 * 48 + 5, 32 + 5);
    assert!((i32::from(p[0]) - 32768).abs() <= 1 && (i32::from(p[1]) - 32768).abs() <= 1);
}

fn rms_diff(raw: &Raw, a: usize, b: usize) -> f32 {
    let mut s = 0.0f64;
    for j in 0..raw.ny {
        for i in 0..raw.nx {
            let (p, q) = (raw.at(a, i, j), raw.at(b, i, j));
            s += f64::from((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2));
        }
    }
    (s / (raw.nx * raw.ny) as f64).sqrt() as f32
}

#[test]
fn a_looped_bake_has_no_seam() {
    // The pulsed north-east gust makes the field change all the time.
    let layout = example("obstacles.json");
    let n = 12;
    let opts = |looped| BakeOptions {
        formats: vec![Format::Raw],
        looped,
        ..small(n)
    };
    let plain = tempfile::tempdir().unwrap();
    run(&layout, plain.path(), &opts(false));
    let raw_plain = Raw::read(plain.path(), &manifest(plain.path()));
    let looped = tempfile::tempdir().unwrap();
    run(&layout, looped.path(), &opts(true));
    let m = manifest(looped.path());
    assert_eq!(m["frames"]["loop"], true);
    assert!(
        m["frames"]["loop_method"]
            .as_str()
            .unwrap()
            .contains("crossfade")
    );
    let raw = Raw::read(looped.path(), &m);
    let steps: Vec<f32> = (0..n - 1).map(|k| rms_diff(&raw, k, k + 1)).collect();
    let typical = steps.iter().copied().fold(0.0, f32::max);
    let seam = rms_diff(&raw, n - 1, 0);
    let plain_seam = rms_diff(&raw_plain, n - 1, 0);
    println!("loop seam {seam}, largest step {typical}, seam without --loop {plain_seam}");
    assert!(seam <= 1.5 * typical, "seam {seam} vs steps {steps:?}");
    assert!(
        plain_seam > 2.0 * seam,
        "without --loop the jump is larger: {plain_seam} vs {seam}"
    );
}

#[test]
fn every_example_bakes_in_every_format_and_the_same_bake_gives_the_same_bytes() {
    for name in [
        "meadow.json",
        "two-winds.json",
        "branching.json",
        "obstacles.json",
        "breeze-fft.json",
    ] {
        let layout = example(name);
        let a = tempfile::tempdir().unwrap();
        let b = tempfile::tempdir().unwrap();
        let opts = BakeOptions {
            warmup: 0.5,
            frames: 2,
            grid: Some([40, 40]),
            ..Default::default()
        };
        let m = run(&layout, a.path(), &opts);
        run(&layout, b.path(), &opts);
        let formats: BTreeSet<Format> = m.files.iter().map(|f| f.format).collect();
        assert_eq!(formats.len(), Format::ALL.len(), "{name}");
        for f in m
            .files
            .iter()
            .map(|f| f.name.clone())
            .chain(["manifest.json".into()])
        {
            let x = std::fs::read(a.path().join(&f)).unwrap();
            let y = std::fs::read(b.path().join(&f)).unwrap();
            assert!(x == y, "{name}: {f} differs between two identical bakes");
        }
    }
}

fn entries(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir).map_or_else(|_| Vec::new(), |r| r.map(|e| e.unwrap().path()).collect())
}

#[test]
fn cancelled_or_failed_bakes_leave_no_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let cancel = AtomicBool::new(false);
    let mut calls = 0;
    let result = bake::bake(
        &example("meadow.json"),
        &out,
        &small(4),
        &cancel,
        &mut |_, _, _| {
            calls += 1;
            if calls == 3 {
                cancel.store(true, std::sync::atomic::Ordering::SeqCst);
            }
        },
    );
    assert!(
        matches!(result, Err(bake::BakeError::Cancelled)),
        "{result:?}"
    );
    assert!(entries(&out).is_empty(), "{:?}", entries(&out));

    // An output "folder" that is a file is a clear error.
    let file = dir.path().join("not-a-folder");
    std::fs::write(&file, "x").unwrap();
    let err = bake::bake(
        &example("meadow.json"),
        &file,
        &small(1),
        &AtomicBool::new(false),
        &mut |_, _, _| {},
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("cannot use output folder") && err.contains("not-a-folder"),
        "{err}"
    );

    // Bad settings are refused before anything is written.
    let bad = BakeOptions {
        looped: true,
        ..small(1)
    };
    let err = bake::bake(
        &example("meadow.json"),
        &out,
        &bad,
        &AtomicBool::new(false),
        &mut |_, _, _| {},
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("--loop needs --frames 2"), "{err}");
    assert!(entries(&out).is_empty());
}

#[test]
fn cli_bake_and_render() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bake");
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/meadow.json");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args([
            "bake",
            layout.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--format",
            "vf",
            "--format",
            "raw",
            "--grid",
            "32x16",
            "--warmup",
            "0.5",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut names: Vec<String> = entries(&out)
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["manifest.json", "wind.f32", "wind.vf"]);
    // An unwritable output is a clear, non-zero error.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args([
            "bake",
            layout.to_str().unwrap(),
            "--out",
            layout.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("cannot use output folder"));

    let png = dir.path().join("meadow.png");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args([
            "render",
            layout.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--size",
            "640x400",
            "--time",
            "2",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!((img.width(), img.height()), (640, 400));
    // The picture is not blank: it holds many colours (streamlines, legend, arrows).
    let colours: BTreeSet<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    assert!(colours.len() > 500, "{} colours", colours.len());
}

#[test]
fn render_draws_the_arrows_and_wind_where_they_are() {
    let layout = example("two-winds.json");
    let mut solver = windloom::sim::Solver::new(&layout);
    for _ in 0..240 {
        solver.step();
    }
    let pix = windloom::render::render(&layout, Path::new("."), &solver, 800, 600).unwrap();
    // Find a pixel of the arrow colour (70, 160, 255) along the west tree's first arrow.
    let arrow_pixels = pix
        .pixels()
        .iter()
        .filter(|p| {
            let c = p.demultiply();
            (i32::from(c.red()) - 70).abs() < 8
                && (i32::from(c.green()) - 160).abs() < 8
                && (i32::from(c.blue()) - 255).abs() < 8
        })
        .count();
    assert!(arrow_pixels > 500, "arrows drawn: {arrow_pixels} pixels");
}

#[test]
fn ctrl_c_during_a_cli_bake_leaves_no_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bake");
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/obstacles.json");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args([
            "bake",
            layout.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--frames",
            "500",
            "--format",
            "raw",
            "--grid",
            "256x256",
            "--backend",
            "auto",
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the bake has started (its staging folder beside `bake` exists), then press
    // Ctrl-C.
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while staging_folders(dir.path()).is_empty() {
        assert!(
            std::time::Instant::now() < deadline,
            "the bake never started"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let status = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("no files were written"));
    assert!(!out.exists(), "{:?}", entries(&out));
    assert!(
        staging_folders(dir.path()).is_empty(),
        "{:?}",
        entries(dir.path())
    );
}

fn staging_folders(dir: &Path) -> Vec<PathBuf> {
    entries(dir)
        .into_iter()
        .filter(|p| p.to_string_lossy().contains(".windloom-bake-"))
        .collect()
}

// ---- Trust: frame timing ----------------------------------------------------------------------

#[test]
fn frames_sit_at_exactly_k_over_fps_for_every_rate() {
    use windloom::bake::FrameTiming;
    let rates: Vec<f32> = (1..=120)
        .map(|r| r as f32)
        .chain([23.976, 29.97, 59.94])
        .collect();
    for dt_max in [1.0 / 60.0, 1.0 / 30.0, 0.01, 1.0 / 144.0, 0.0001] {
        for &fps in &rates {
            let t = FrameTiming::new(fps, dt_max, 2.0);
            let interval = t.steps_per_frame as f64 * f64::from(t.dt);
            let want = 1.0 / f64::from(fps);
            assert!(
                ((interval - want) / want).abs() < 1e-6,
                "{fps} fps, dt_max {dt_max}: {} steps of {} = {interval} s, not {want}",
                t.steps_per_frame,
                t.dt
            );
            // The step never exceeds the layout's, and no fewer steps would do.
            assert!(
                t.dt <= dt_max * (1.0 + 1e-4),
                "{fps} fps: dt {} > {dt_max}",
                t.dt
            );
            if t.steps_per_frame > 1 {
                let fewer = 1.0 / (f64::from(fps) * (t.steps_per_frame - 1) as f64);
                assert!(
                    fewer > f64::from(dt_max),
                    "{fps} fps: more steps than needed"
                );
            }
            // The clock: frame k at warmup + k / fps, and the warm-up a whole number of frames.
            for k in [0usize, 1, 7, 1000] {
                let at = t.time_after(t.warmup_steps + k * t.steps_per_frame);
                let want = t.warmup_seconds() + k as f64 / f64::from(fps);
                assert!(
                    (at - want).abs() < 1e-9 * want.max(1.0),
                    "{fps} fps frame {k}"
                );
            }
            let frames = t.warmup_seconds() * f64::from(fps);
            assert!((frames - frames.round()).abs() < 1e-6);
            assert!((t.warmup_seconds() - 2.0).abs() <= 0.5 / f64::from(fps) + 1e-9);
        }
    }
}

#[test]
fn a_24_fps_bake_records_and_captures_frames_at_k_over_24() {
    let layout = example("obstacles.json");
    for fps in [24.0f32, 25.0, 30.0, 48.0, 50.0, 60.0, 90.0] {
        let dir = tempfile::tempdir().unwrap();
        let opts = BakeOptions {
            formats: vec![Format::Raw],
            warmup: 0.25,
            frames: 3,
            fps,
            grid: Some([24, 24]),
            ..Default::default()
        };
        run(&layout, dir.path(), &opts);
        let m = manifest(dir.path());
        let f = &m["frames"];
        let (dt, spf) = (
            f["sim_dt"].as_f64().unwrap(),
            f["steps_per_frame"].as_u64().unwrap(),
        );
        assert!(
            (dt * spf as f64 * f64::from(fps) - 1.0).abs() < 1e-6,
            "{fps} fps: frames {} s apart, manifest {f}",
            dt * spf as f64
        );
        assert_eq!(f["fps"].as_f64().unwrap(), f64::from(fps));
        assert_eq!(f["layout_dt"].as_f64().unwrap() as f32, layout.sim.dt);
        assert!(dt <= f64::from(layout.sim.dt) * (1.0 + 1e-4));
        // The frames are the solver's field after exactly those steps of exactly that dt.
        let raw = Raw::read(dir.path(), &m);
        let mut l = layout.clone();
        l.world.grid = [24, 24];
        l.sim.dt = dt as f32;
        let warmup = (f["warmup_seconds"].as_f64().unwrap() / dt).round() as usize;
        let mut solver = windloom::sim::Solver::new(&l);
        let mut steps = 0;
        for k in 0..3 {
            let until = warmup + k * spf as usize;
            while steps < until {
                solver.step();
                steps += 1;
                solver.time = (steps as f64 / (f64::from(fps) * spf as f64)) as f32;
            }
            let field = solver.velocity_field();
            for (i, j) in [(3, 5), (12, 12), (20, 2)] {
                assert_eq!(raw.at(k, i, j), field[j * 24 + i], "{fps} fps frame {k}");
            }
        }
    }
}

// ---- Trust: EXR read by other readers ---------------------------------------------------------

/// Builds `tests/exr_readers/dump.cpp` against TinyEXR (the loader Godot bundles) or OpenEXR.
/// CI installs both (`.ci/run`); elsewhere a missing library skips loudly.
fn exr_reader(which: &str) -> Option<PathBuf> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/exr_readers/dump.cpp");
    let bin = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("exr_dump_{which}"));
    let mut cmd = std::process::Command::new("g++");
    cmd.args(["-O1", "-std=c++17", "-o"]).arg(&bin).arg(&src);
    match which {
        "tinyexr" => cmd.args(["-DWITH_TINYEXR", "-lz"]),
        _ => {
            let flags = std::process::Command::new("pkg-config")
                .args(["--cflags", "--libs", "OpenEXR"])
                .output()
                .ok()
                .filter(|o| o.status.success())
                .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
                .unwrap_or_default();
            cmd.arg("-DWITH_OPENEXR").args(flags.split_whitespace())
        }
    };
    let built = cmd.output().map(|o| (o.status.success(), o.stderr));
    match built {
        Ok((true, _)) => Some(bin),
        other => {
            let why = match other {
                Ok((_, err)) => String::from_utf8_lossy(&err).into_owned(),
                Err(e) => e.to_string(),
            };
            assert!(
                std::env::var_os("CI").is_none(),
                "CI must check EXRs with {which}, but it did not build: {why}"
            );
            eprintln!(
                "\n!!! SKIPPING the {which} EXR check: it did not build ({why}).\n!!! apt-get install libtinyexr-dev libopenexr-dev g++ pkg-config (as .ci/run does)\n"
            );
            None
        }
    }
}

/// An EXR as `bin` reads it: `(width, height, [r, g, b] per pixel, row 0 first)`.
fn read_exr_with(bin: &Path, file: &Path) -> (usize, usize, Vec<[f32; 3]>) {
    let o = std::process::Command::new(bin).arg(file).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    let mut lines = text.lines();
    let wh: Vec<usize> = lines
        .next()
        .unwrap()
        .split(' ')
        .map(|t| t.parse().unwrap())
        .collect();
    let px = lines
        .map(|l| {
            let v: Vec<f32> = l.split(' ').map(|t| t.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    (wh[0], wh[1], px)
}

/// The header attributes of an EXR file, by name, read per the OpenEXR file layout.
fn exr_header(bytes: &[u8]) -> BTreeMap<String, (String, Vec<u8>)> {
    assert_eq!(&bytes[..4], &[0x76, 0x2f, 0x31, 0x01], "EXR magic");
    let flags = u32::from_le_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]);
    assert_eq!(
        flags & 0x200,
        0,
        "the version field's single-tile bit is clear"
    );
    let mut at = 8;
    let cstr = |at: &mut usize| {
        let end = bytes[*at..].iter().position(|&b| b == 0).unwrap() + *at;
        let s = String::from_utf8(bytes[*at..end].to_vec()).unwrap();
        *at = end + 1;
        s
    };
    let mut attrs = BTreeMap::new();
    loop {
        let name = cstr(&mut at);
        if name.is_empty() {
            return attrs;
        }
        let kind = cstr(&mut at);
        let len = u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        attrs.insert(name, (kind, bytes[at + 4..at + 4 + len].to_vec()));
        at += 4 + len;
    }
}

#[test]
fn exr_is_scanline_and_every_reader_sees_the_same_rows() {
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::Exr, Format::Raw],
        grid: Some([40, 64]),
        ..small(1)
    };
    run(&example("two-winds.json"), dir.path(), &opts);
    let m = manifest(dir.path());
    let raw = Raw::read(dir.path(), &m);
    let file = dir.path().join("wind.exr");
    let header = exr_header(&std::fs::read(&file).unwrap());
    assert!(
        !header.contains_key("tiles"),
        "a scanline image has no tiles attribute"
    );
    assert_eq!(header["lineOrder"].1, [0], "increasing Y");
    let mut readers = 0;
    for which in ["tinyexr", "openexr"] {
        let Some(bin) = exr_reader(which) else {
            continue;
        };
        readers += 1;
        let (w, h, px) = read_exr_with(&bin, &file);
        assert_eq!((w, h), (40, 64), "{which}");
        for j in 0..h {
            for i in 0..w {
                let want = raw.at(0, i, j);
                let got = px[j * w + i];
                assert_eq!(
                    [got[0], got[1]],
                    want,
                    "{which} reads pixel ({i},{j}) as the raw field's"
                );
                assert_eq!(got[2], want[0].hypot(want[1]), "{which} B at ({i},{j})");
            }
        }
    }
    println!("EXR checked with {readers} independent readers");
}

// ---- Trust: a bake folder holds one bake ------------------------------------------------------

fn names(dir: &Path) -> BTreeSet<String> {
    entries(dir)
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn a_bake_replaces_its_folder_as_a_whole_and_keeps_the_users_files() {
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("wind");
    let layout = example("meadow.json");
    let big = BakeOptions {
        formats: vec![Format::Exr, Format::Png8, Format::Raw],
        ..small(3)
    };
    run(&layout, &out, &big);
    // What the user and their engine add: notes, Unity .meta files, a Godot import folder.
    std::fs::write(out.join("README.txt"), "wind for level 3").unwrap();
    std::fs::write(out.join("wind_0001.exr.meta"), "guid: 1234").unwrap();
    std::fs::create_dir(out.join(".godot")).unwrap();
    std::fs::write(out.join(".godot/wind.import"), "[remap]").unwrap();
    // A different bake: one frame, one format.
    let one = BakeOptions {
        formats: vec![Format::Vf],
        ..small(1)
    };
    let m = run(&layout, &out, &one);
    let want: BTreeSet<String> = [
        "manifest.json",
        "wind.vf",
        "README.txt",
        "wind_0001.exr.meta",
        ".godot",
    ]
    .into_iter()
    .map(String::from)
    .collect();
    assert_eq!(names(&out), want, "nothing of the first bake is left");
    assert_eq!(m.files.len(), 1);
    assert_eq!(
        std::fs::read_to_string(out.join("README.txt")).unwrap(),
        "wind for level 3"
    );
    assert_eq!(
        std::fs::read_to_string(out.join(".godot/wind.import")).unwrap(),
        "[remap]"
    );
    assert!(
        staging_folders(root.path()).is_empty(),
        "{:?}",
        entries(root.path())
    );

    // A file of the user's that this bake would overwrite is refused, and nothing changes.
    std::fs::write(out.join("wind.f32"), "mine").unwrap();
    let err = bake::bake(
        &layout,
        &out,
        &BakeOptions {
            formats: vec![Format::Raw],
            ..small(1)
        },
        &AtomicBool::new(false),
        &mut |_, _, _| {},
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("wind.f32") && err.contains("not written by an earlier bake"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("wind.f32")).unwrap(),
        "mine"
    );
    assert!(out.join("wind.vf").exists());

    // A folder that holds files but no bake is not taken over.
    let docs = root.path().join("docs");
    std::fs::create_dir(&docs).unwrap();
    std::fs::write(docs.join("thesis.tex"), "x").unwrap();
    let err = bake::bake(
        &layout,
        &docs,
        &one,
        &AtomicBool::new(false),
        &mut |_, _, _| {},
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("no manifest.json"), "{err}");
    assert_eq!(names(&docs), BTreeSet::from(["thesis.tex".to_string()]));

    // Staging folders of a bake that was killed are cleared by the next bake.
    let dead = (1_000_000u32..)
        .find(|p| !Path::new(&format!("/proc/{p}")).exists())
        .unwrap();
    let stale = root.path().join(format!(".wind.windloom-bake-{dead}-1"));
    std::fs::create_dir(&stale).unwrap();
    std::fs::write(stale.join("wind.vf"), "half").unwrap();
    run(&layout, &out, &one);
    assert!(!stale.exists(), "a dead bake's staging folder is removed");
}

/// While bakes of different shapes replace a folder again and again, a reader that opens the
/// folder and reads what is inside always finds one whole bake: every file the manifest lists,
/// and no file of windloom's that it does not.
#[cfg(target_os = "linux")]
#[test]
fn a_reader_never_sees_two_bakes_at_once() {
    use std::sync::atomic::Ordering;
    let root = tempfile::tempdir().unwrap();
    let out = root.path().join("wind");
    let layout = example("meadow.json");
    let shapes = [
        BakeOptions {
            formats: vec![Format::Vf, Format::Png8],
            ..small(4)
        },
        BakeOptions {
            formats: vec![Format::Fga, Format::Vf],
            ..small(1)
        },
    ];
    run(&layout, &out, &shapes[0]);
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let canonical = out.canonicalize().unwrap();
    let stop = AtomicBool::new(false);
    let checks = std::thread::scope(|s| {
        let reader = s.spawn(|| {
            let mut checks = 0;
            while !stop.load(Ordering::SeqCst) {
                // Open the folder once and read through that handle, as a snapshot would.
                let Ok(handle) = std::fs::File::open(&out) else {
                    continue;
                };
                use std::os::fd::AsRawFd;
                let here = PathBuf::from(format!("/proc/self/fd/{}", handle.as_raw_fd()));
                let Ok(text) = std::fs::read_to_string(here.join("manifest.json")) else {
                    continue;
                };
                let m: serde_json::Value = serde_json::from_str(&text).expect("a whole manifest");
                let listed: BTreeSet<String> = m["files"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|f| f["name"].as_str().unwrap().to_string())
                    .chain(["manifest.json".into(), "notes.txt".into()])
                    .collect();
                let seen = names(&here);
                // Count the look only if the folder was still `out` after it: a folder that
                // was swapped out meanwhile is the old bake being deleted, which a reader
                // holding it open may see (docs/EXPORT.md).
                if std::fs::read_link(&here).ok().as_deref() != Some(canonical.as_path()) {
                    continue;
                }
                assert_eq!(seen, listed, "one bake, whole, with the user's file");
                checks += 1;
            }
            checks
        });
        for round in 0..12 {
            run(&layout, &out, &shapes[round % 2]);
        }
        stop.store(true, Ordering::SeqCst);
        reader.join().unwrap()
    });
    assert!(checks > 10, "the reader looked {checks} times");
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
}

// ---- Trust: limits, modes, no panics -----------------------------------------------------------

fn windloom_cli(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn oversized_bakes_are_refused_up_front_with_the_figure() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bake");
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/meadow.json");
    let l = layout.to_str().unwrap();
    let o = out.to_str().unwrap();
    let t = std::time::Instant::now();
    let r = windloom_cli(&[
        "bake",
        l,
        "--out",
        o,
        "--frames",
        "90000",
        "--format",
        "exr",
        "--format",
        "raw",
        "--max-disk",
        "1G",
    ]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success());
    assert!(
        err.contains("needs up to") && err.contains("GiB") && err.contains("1.00 GiB budget"),
        "{err}"
    );
    assert!(t.elapsed().as_secs() < 30, "refused before simulating");
    let r = windloom_cli(&["bake", l, "--out", o, "--frames", "1000000"]);
    assert!(String::from_utf8_lossy(&r.stderr).contains("--frames must be 1 to 100000"));
    let r = windloom_cli(&[
        "bake", l, "--out", o, "--frames", "20000", "--format", "atlas",
    ]);
    assert!(
        String::from_utf8_lossy(&r.stderr).contains("GPU texture allows"),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let r = windloom_cli(&["bake", l, "--out", o, "--max-disk", "lots"]);
    assert!(String::from_utf8_lossy(&r.stderr).contains("expected a size like"));
    assert!(!out.exists() && staging_folders(dir.path()).is_empty());
    // The estimate is an upper bound of what a bake writes.
    let opts = BakeOptions {
        frames: 3,
        looped: true,
        ..small(3)
    };
    let m = run(&example("obstacles.json"), &out, &opts);
    let written: u64 = m.files.iter().map(|f| f.bytes).sum();
    let need = bake::disk_need(48, 32, &Format::ALL, 3, true, false);
    assert!(
        written < need,
        "estimate {need} below the {written} bytes written"
    );
}

#[cfg(unix)]
#[test]
fn bake_and_render_outputs_get_the_users_usual_mode() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/meadow.json");
    let script = format!(
        "umask 022 && {bin} bake {l} --out {d}/bake --format vf --format raw --grid 16x16 --warmup 0 \
         && {bin} render {l} -o {d}/pic.png --size 200x150 --time 0",
        bin = env!("CARGO_BIN_EXE_windloom"),
        l = layout.display(),
        d = dir.path().display()
    );
    let o = std::process::Command::new("sh")
        .args(["-c", &script])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&dir.path().join("bake")), 0o755);
    for f in ["manifest.json", "wind.vf", "wind.f32"] {
        assert_eq!(mode(&dir.path().join("bake").join(f)), 0o644, "{f}");
    }
    assert_eq!(mode(&dir.path().join("pic.png")), 0o644);
}

#[test]
fn render_survives_odd_sizes_and_far_points() {
    let dir = tempfile::tempdir().unwrap();
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/meadow.json");
    for size in ["800x70", "64x64", "8192x64", "64x8192"] {
        let png = dir.path().join(format!("{size}.png"));
        let r = windloom_cli(&[
            "render",
            layout.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--size",
            size,
            "--time",
            "0.1",
        ]);
        assert!(
            r.status.success(),
            "{size}: {}",
            String::from_utf8_lossy(&r.stderr)
        );
        let img = image::open(&png).unwrap();
        let (w, h) = size.split_once('x').unwrap();
        assert_eq!(
            (img.width(), img.height()),
            (w.parse().unwrap(), h.parse().unwrap())
        );
    }
    // The farthest and thinnest layouts validation allows draw without a panic.
    let mut l = example("meadow.json");
    l.world.size = [100_000.0, 1.0];
    l.world.grid = [16, 8];
    l.trees[0].root.pos = [1.0e6, -1.0e6];
    l.trees[0].root.children[0].pos = [-1.0e6, 1.0e6];
    assert!(windloom::doc::validate(&l).is_empty());
    let solver = windloom::sim::Solver::new(&l);
    for (w, h) in [(64, 64), (1600, 1000), (64, 8192)] {
        let pix = windloom::render::render(&l, Path::new("."), &solver, w, h).unwrap();
        assert_eq!((pix.width(), pix.height()), (w, h));
    }
}

mod render_never_panics {
    use proptest::prelude::*;
    use std::path::Path;
    use windloom::doc::{self, Layout, Node};

    fn coord() -> impl Strategy<Value = f32> {
        prop_oneof![
            -1.0e6f32..1.0e6,
            -200.0f32..200.0,
            Just(1.0e6),
            Just(-1.0e6)
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]
        /// Anything validation lets through draws at any allowed picture size.
        #[test]
        fn on_any_valid_layout_and_size(
            size in (1.0f32..1.0e5, 1.0f32..1.0e5),
            origin in (coord(), coord()),
            grid in (8u32..40, 8u32..40),
            nodes in proptest::collection::vec((coord(), coord(), 0.0f32..500.0, 0.001f32..1.0e5), 2..5),
            picture in (64u32..700, 64u32..700),
        ) {
            let mut l = Layout::new("p", [size.0, size.1], [grid.0, grid.1]);
            l.world.origin = [origin.0, origin.1];
            let mut root = Node::new(1, [nodes[0].0, nodes[0].1], nodes[0].2, nodes[0].3);
            for (k, n) in nodes.iter().enumerate().skip(1) {
                root.children.push(Node::new(k as u32 + 1, [n.0, n.1], n.2, n.3));
            }
            l.trees.push(doc::Tree {
                id: 1,
                name: "t".into(),
                enabled: true,
                window: doc::TimeWindow::Always,
                emission: doc::Emission::Continuous,
                propagation_speed: 20.0,
                root,
            });
            prop_assume!(doc::validate(&l).is_empty());
            let mut solver = windloom::sim::Solver::new(&l);
            solver.step();
            let pix = windloom::render::render(&l, Path::new("."), &solver, picture.0, picture.1);
            // A world too thin for the picture is an error, never a panic.
            if let Ok(p) = pix {
                prop_assert_eq!((p.width(), p.height()), picture);
            }
        }
    }
}

/// A frame holding a NaN or an infinity is refused: a bake never ships one, and the error
/// names the frame and the cell.
#[test]
fn a_non_finite_frame_is_refused() {
    use windloom::bake::check_finite;
    let mut field = vec![[1.0f32, -2.0]; 64];
    assert!(check_finite(&field, 3).is_ok());
    field[17][1] = f32::NAN;
    let e = check_finite(&field, 3).unwrap_err().to_string();
    assert!(e.contains("frame 3") && e.contains("cell 17"), "{e}");
    field[17][1] = 0.0;
    field[5][0] = f32::INFINITY;
    assert!(
        check_finite(&field, 0)
            .unwrap_err()
            .to_string()
            .contains("cell 5")
    );
}

/// A PNG whose header claims `w × h` pixels (and holds almost nothing).
fn png_header(w: u32, h: u32) -> Vec<u8> {
    fn chunk(out: &mut Vec<u8>, kind: &[u8], data: &[u8]) {
        out.extend((data.len() as u32).to_be_bytes());
        let start = out.len();
        out.extend(kind);
        out.extend(data);
        // CRC-32 (IEEE) of type and data.
        let mut crc = 0xffff_ffffu32;
        for &b in &out[start..] {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 != 0 {
                    (crc >> 1) ^ 0xedb8_8320
                } else {
                    crc >> 1
                };
            }
        }
        out.extend((!crc).to_be_bytes());
    }
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend(w.to_be_bytes());
    ihdr.extend(h.to_be_bytes());
    ihdr.extend([8, 6, 0, 0, 0]);
    chunk(&mut out, b"IHDR", &ihdr);
    // An empty zlib stream: readers learn the size once they reach the first IDAT.
    chunk(&mut out, b"IDAT", &[0x78, 0x9c, 0x03, 0, 0, 0, 0, 1]);
    chunk(&mut out, b"IEND", &[]);
    out
}

/// A map backdrop that is missing, corrupt or absurdly large is a warning — from `validate`,
/// `render` and the loader — never a refusal of the layout or an attempt to decode it: the
/// 100,000² header is turned down from its header alone.
#[test]
fn a_bad_backdrop_is_a_warning_not_a_failure() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("corrupt.png"),
        b"\x89PNG\r\n\x1a\nnot a png",
    )
    .unwrap();
    std::fs::write(dir.path().join("huge.png"), png_header(100_000, 100_000)).unwrap();
    for (image, says) in [
        ("missing.png", "missing.png"),
        ("corrupt.png", "corrupt.png"),
        ("huge.png", "100000×100000 pixels"),
    ] {
        let mut l = example("meadow.json");
        l.world.grid = [40, 30];
        l.world.map = Some(windloom::doc::MapBackdrop {
            image: image.into(),
            opacity: 0.8,
        });
        let file = dir.path().join(format!("{image}.json"));
        windloom::io::save(&file, &l).unwrap();
        let started = std::time::Instant::now();
        let e = windloom::io::load_backdrop(dir.path(), l.world.map.as_ref().unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains(says), "{e}");
        assert!(
            started.elapsed().as_secs_f32() < 1.0,
            "refused without decoding"
        );
        let run = |args: &[&str]| {
            std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
                .args(args)
                .output()
                .unwrap()
        };
        let f = file.to_str().unwrap();
        let o = run(&["validate", f]);
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(o.status.success(), "{image}: validate fails: {out}");
        assert!(out.contains("warning") && out.contains(says), "{out}");
        let png = dir.path().join(format!("{image}-map.png"));
        let o = run(&[
            "render",
            f,
            "-o",
            png.to_str().unwrap(),
            "--size",
            "160x120",
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{image}: render fails: {err}");
        assert!(err.contains("warning") && err.contains(says), "{err}");
        assert!(image::open(&png).is_ok(), "a picture without the backdrop");
    }
}

/// Every file under `dir` (recursively, by relative path) with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let rel = p.strip_prefix(root).unwrap().to_string_lossy().into_owned();
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// SIGKILL at spread-out moments during `bake` into a folder holding an earlier bake, 24
/// times (from at once to three times its undisturbed duration): afterwards the folder is always exactly the earlier bake or exactly the new one —
/// never a mixture, never half a file — and the next bake clears what the killed ones left
/// beside it.
#[test]
fn sigkill_during_a_bake_leaves_the_old_bake_or_the_new_one() {
    let dir = tempfile::tempdir().unwrap();
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/obstacles.json");
    let bake = |out: &Path, frames: &str| {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"));
        c.args([
            "bake",
            layout.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .args(["--frames", frames, "--format", "raw", "--format", "exr"])
        .args(["--grid", "96x72"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null());
        c
    };
    let out = dir.path().join("wind");
    assert!(bake(&out, "6").status().unwrap().success());
    let old = snapshot(&out);
    let reference = dir.path().join("reference");
    let started = std::time::Instant::now();
    assert!(bake(&reference, "24").status().unwrap().success());
    let takes = started.elapsed();
    let new = snapshot(&reference);
    assert_ne!(old, new);
    let (mut olds, mut news) = (0, 0);
    let runs = 24;
    for k in 0..runs {
        if snapshot(&out) != old {
            std::fs::remove_dir_all(&out).unwrap();
            assert!(bake(&out, "6").status().unwrap().success());
        }
        let mut child = bake(&out, "24").spawn().unwrap();
        // Spread over three times the bake's time alone: other tests share the machine.
        std::thread::sleep(takes.mul_f64(3.0 * k as f64 / runs as f64));
        child.kill().unwrap(); // SIGKILL
        child.wait().unwrap();
        let now = snapshot(&out);
        if now == old {
            olds += 1;
        } else if now == new {
            news += 1;
        } else {
            panic!(
                "run {k}: the folder is neither bake ({} files: {:?})",
                now.len(),
                now.keys().take(5).collect::<Vec<_>>()
            );
        }
    }
    println!("{runs} kills over {takes:?}: {olds} left the old bake, {news} the new one");
    assert!(
        olds > 0 && news > 0,
        "the kills landed both before and after the switch"
    );
    // A bake after the kills removes their staging folders.
    assert!(bake(&out, "6").status().unwrap().success());
    assert_eq!(snapshot(&out), old);
    assert!(
        staging_folders(dir.path()).is_empty(),
        "{:?}",
        staging_folders(dir.path())
    );
}

/// SIGKILL at spread-out moments during `windloom fmt` (an atomic rewrite in place): the file
/// is always the old text or the new, whole.
#[test]
fn sigkill_during_a_save_leaves_the_old_file_or_the_new_one() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("level.json");
    let mut l = example("branching.json");
    l.world.grid = [64, 64];
    // Not canonical: the same layout, indented by hand.
    let old = serde_json::to_string(&serde_json::to_value(&l).unwrap()).unwrap();
    let fmt = || {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"));
        c.args(["fmt", file.to_str().unwrap()])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null());
        c
    };
    std::fs::write(&file, &old).unwrap();
    let started = std::time::Instant::now();
    assert!(fmt().status().unwrap().success());
    let takes = started.elapsed();
    let new = std::fs::read_to_string(&file).unwrap();
    assert_ne!(old, new);
    let (mut olds, mut news) = (0, 0);
    for k in 0..30 {
        std::fs::write(&file, &old).unwrap();
        let mut child = fmt().spawn().unwrap();
        std::thread::sleep(takes.mul_f64(1.4 * k as f64 / 30.0));
        child.kill().unwrap();
        child.wait().unwrap();
        let now = std::fs::read_to_string(&file).unwrap();
        if now == old {
            olds += 1;
        } else {
            assert_eq!(now, new, "run {k}: a mixture");
            news += 1;
        }
    }
    println!("30 kills over {takes:?}: {olds} old, {news} new");
    let left: Vec<_> = entries(dir.path())
        .into_iter()
        .filter(|p| p.file_name().is_some_and(|n| n != "level.json"))
        .collect();
    println!("left beside it by the kills: {left:?}");
}
