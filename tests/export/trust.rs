//! Bakes a studio can trust: frames at exactly k / fps, EXRs other readers agree on, a bake
//! folder that holds one whole bake, refused and odd inputs that fail cleanly, and a kill
//! that leaves the old output or the new one.

use super::*;

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
                // The speed as the bake computes it (`windloom::num`: the same bits on
                // every platform).
                let speed = windloom::num::hypot(want[0], want[1]);
                assert_eq!(got[2], speed, "{which} B at ({i},{j})");
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

/// A layout that is not there: `bake`, `render` and the editor each exit non-zero with one
/// line naming the file and saying why once (it used to print the OS's reason twice).
#[test]
fn a_missing_layout_is_one_line_that_names_it() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no-such-level.json");
    // In words, without the OS's error number.
    let why = "it does not exist";
    let m = missing.to_str().unwrap();
    let out = dir.path().join("out");
    let png = dir.path().join("x.png");
    for args in [
        vec!["bake", m, "--out", out.to_str().unwrap()],
        vec!["render", m, "-o", png.to_str().unwrap()],
        vec!["validate", m],
    ] {
        let r = windloom_cli(&args);
        // `validate` reports on stdout, the others on stderr.
        let err = String::from_utf8_lossy(&r.stderr) + String::from_utf8_lossy(&r.stdout);
        assert!(!r.status.success(), "{args:?} succeeded");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(m), "{args:?} names the file: {err}");
        assert_eq!(err.matches(why).count(), 1, "{args:?} says why once: {err}");
    }
    assert!(!out.exists() && !png.exists(), "nothing written");
}

/// `render`'s options for the 3D grass picture are refused on the map view, naming the
/// option and what to add, rather than ignored (a map after `--no-arrows` still had them).
#[test]
fn grass_options_on_the_map_view_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let layout = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/meadow.json");
    let png = dir.path().join("map.png");
    let (l, p) = (layout.to_str().unwrap(), png.to_str().unwrap());
    for extra in [
        vec!["--no-arrows"],
        vec!["--paper-literal"],
        vec!["--model", "bezier"],
        vec!["--wind-colours", "0.5"],
        vec!["--camera", "1,2,3,4,0,6"],
        vec!["--push", "1,1,5,5,0.5"],
    ] {
        let mut args = vec!["render", l, "-o", p, "--size", "96x64"];
        args.extend(&extra);
        let r = windloom_cli(&args);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success(), "{extra:?} was taken");
        assert!(
            err.contains(extra[0]) && err.contains("--view grass"),
            "{extra:?}: {err}"
        );
        assert!(!png.exists(), "{extra:?} wrote a picture");
    }
    // The speed scale is for both views.
    let r = windloom_cli(&[
        "render",
        l,
        "-o",
        p,
        "--size",
        "96x64",
        "--speed-scale",
        "9",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
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
    let layers = example("obstacles.json").world.profile.layers as usize;
    let need = bake::disk_need(48, 32, layers, &Format::ALL, 3, true, false);
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
                locked: false,
                hidden: false,
                keys: Vec::new(),
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
            rect: None,
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

/// Every file under `dir` (recursively, by relative path) with its bytes; a manifest's
/// `sequence` (which counts the bakes into a folder) left out, so that the same bake into two
/// folders, or twice into one, compares equal.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let rel = p.strip_prefix(root).unwrap().to_string_lossy().into_owned();
                let mut bytes = std::fs::read(&p).unwrap();
                if rel == "manifest.json" {
                    let mut m: serde_json::Value = serde_json::from_slice(&bytes)
                        .unwrap_or_else(|e| panic!("half a manifest: {e}"));
                    m.as_object_mut().unwrap().remove("sequence");
                    bytes = m.to_string().into_bytes();
                }
                out.insert(rel, bytes);
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

/// A mask obstacle whose image cannot be read: `validate` says so as a warning (the layout
/// opens, the wind runs without it); `bake` refuses in one line naming the obstacle and the
/// file, non-zero, writing nothing — a bake without the obstacles would ship wrong wind. With
/// the image there, the bake's wind is zero in the mask's cells.
#[test]
fn a_bake_refuses_a_mask_it_cannot_read_and_honours_one_it_can() {
    let dir = tempfile::tempdir().unwrap();
    let layouts = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts");
    let file = dir.path().join("garden.json");
    std::fs::copy(layouts.join("walled-garden.json"), &file).unwrap();
    // Its heightmap beside it: only the mask is missing.
    std::fs::copy(
        layouts.join("walled-garden-heights.png"),
        dir.path().join("walled-garden-heights.png"),
    )
    .unwrap();
    let out = dir.path().join("wind");
    let bin = env!("CARGO_BIN_EXE_windloom");
    let v = std::process::Command::new(bin)
        .args(["validate", file.to_str().unwrap()])
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&v.stdout);
    assert!(v.status.success(), "{said}");
    assert!(
        said.contains("ok; warning: obstacles[0]") && said.contains("walled-garden-mask.png"),
        "{said}"
    );
    let b = std::process::Command::new(bin)
        .args([
            "bake",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .args(["--format", "raw", "--grid", "48x32", "--warmup", "0.5"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&b.stderr);
    assert_eq!(b.status.code(), Some(1), "{err}");
    let line = err.lines().find(|l| l.starts_with("error:")).unwrap();
    assert!(
        line.contains("obstacles[0] \"Garden walls (mask)\"")
            && line.contains("walled-garden-mask.png")
            && line.contains("wrong wind"),
        "{line}"
    );
    assert!(!out.exists(), "nothing written");
    // With the image beside it, the bake runs and the walls are still.
    std::fs::copy(
        layouts.join("walled-garden-mask.png"),
        dir.path().join("walled-garden-mask.png"),
    )
    .unwrap();
    let mut layout = windloom::io::load(&file).unwrap();
    assert!(windloom::doc::mask_problems(&layout).is_empty());
    layout.world.grid = [48, 32];
    let solid = windloom::sim::obstacles::rasterize(&layout);
    assert!(solid.iter().filter(|&&s| s == 1).count() > 48);
    let m = run(
        &layout,
        &out,
        &BakeOptions {
            formats: vec![Format::Raw],
            grid: None,
            ..small(1)
        },
    );
    let raw = Raw::read(&out, &manifest(&out));
    assert!(m.max_speed > 1.0);
    for j in 0..32 {
        for i in 0..48 {
            if solid[j * 48 + i] == 1 {
                assert_eq!(raw.at(0, i, j), [0.0, 0.0], "wall cell {i},{j}");
            }
        }
    }
}
