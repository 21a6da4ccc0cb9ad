//! The runtime (`src/runtime`): a bake as a game reads it. Every format it reads gives the
//! raw bake's wind at every cell within the format's rounding; the profile, the terrain,
//! time, loops, the world's edge and the engines' axes as documented; re-bakes followed
//! whole, never mixed, the last good bake kept; the C interface from a C program; and the
//! editor's own sample of the same solver run.

use super::*;
use windloom_runtime::{Axes, Bake, LiveBake, Options, Outside};

fn opts(format: &str) -> Options {
    Options {
        format: Some(format.into()),
        ..Options::default()
    }
}

/// The cell centres of `m`'s grid, world metres.
fn centre(m: &bake::Manifest, i: usize, j: usize) -> (f32, f32) {
    let c = m.world.cell_size;
    (
        m.world.min[0] + (i as f32 + 0.5) * c[0],
        m.world.min[1] + (j as f32 + 0.5) * c[1],
    )
}

/// What a position rounds to in f32 costs at a cell centre: the wind's change over a
/// millionth of a cell, well under any sample type's rounding but f32's.
const POSITION_ROUNDING: f32 = 1e-4;

/// Winds the same within [`POSITION_ROUNDING`].
fn same(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= POSITION_ROUNDING)
}

fn reference_height(dir: &Path) -> f32 {
    manifest(dir)["profile"]["reference_height"]
        .as_f64()
        .unwrap() as f32
}

/// Every format the runtime reads gives the raw wind at every cell of every frame, within
/// the rounding of the format's samples.
#[test]
fn every_format_reads_back_to_the_raw_wind() {
    for (layout, half) in [("branching.json", false), ("two-winds.json", true)] {
        let dir = tempfile::tempdir().unwrap();
        let m = run(
            &example(layout),
            dir.path(),
            &BakeOptions {
                half,
                formats: vec![
                    Format::Raw,
                    Format::Exr,
                    Format::Png16,
                    Format::Png8,
                    Format::Vf,
                    Format::Dds,
                    Format::Fga,
                ],
                ..small(3)
            },
        );
        let raw = Raw::read(dir.path(), &manifest(dir.path()));
        let y = reference_height(dir.path());
        // With no format asked for, the bake's own numbers.
        let best = Bake::open(dir.path(), &Options::default()).unwrap();
        assert_eq!(best.source().0, "raw");
        let peak = m.max_speed;
        for (format, tol) in [
            ("raw", 0.0),
            ("exr", if half { 2e-3 * peak } else { 1e-6 * peak }),
            ("vf", 2e-6 * peak),
            ("dds", if half { 2e-3 * peak } else { 2e-6 * peak }),
            ("png16", 2.0 * peak / 65535.0 * 0.51),
            ("png8", 2.0 * peak / 255.0 * 0.51),
        ] {
            let b = Bake::open(dir.path(), &opts(format)).unwrap();
            assert_eq!(b.source().0, format);
            assert_eq!(b.frames(), 3);
            for k in 0..3 {
                let t = k as f32 / m.frames.fps;
                for j in 0..raw.ny {
                    for i in 0..raw.nx {
                        let (x, z) = centre(&m, i, j);
                        let w = b.wind_at([x, y, z], f64::from(t));
                        let v = raw.at(k, i, j);
                        assert!(
                            (w[0] - v[0]).abs() <= tol + POSITION_ROUNDING
                                && (w[2] - v[1]).abs() <= tol + POSITION_ROUNDING
                                && w[1] == 0.0,
                            "{layout} {format} frame {k} cell ({i}, {j}): {w:?}, raw {v:?} (± {tol})"
                        );
                    }
                }
            }
        }
        // A game ships only the files it reads: the volume as Unity's VF or Godot's EXR
        // slices, or the 8-bit flowmaps, each read alone, and nothing but the manifest is
        // refused naming the file it lacks.
        for (what, keep, tol) in [
            ("VF volume", "wind_volume", ".vf", 2e-6 * peak),
            (
                "EXR slices",
                "wind_volume",
                ".exr",
                if half { 2e-3 * peak } else { 2e-6 * peak },
            ),
            ("8-bit flowmaps", "flow8", ".png", 2.0 * peak / 255.0 * 0.51),
        ]
        .map(|(w, stem, ext, tol)| (w, (stem, ext), tol))
        {
            let shipped = tempfile::tempdir().unwrap();
            std::fs::copy(
                dir.path().join("manifest.json"),
                shipped.path().join("manifest.json"),
            )
            .unwrap();
            let names: Vec<&String> = m
                .files
                .iter()
                .map(|f| &f.name)
                .filter(|n| n.starts_with(keep.0) && n.ends_with(keep.1))
                .collect();
            assert!(!names.is_empty(), "{what}");
            for n in &names {
                std::fs::copy(dir.path().join(n), shipped.path().join(n)).unwrap();
            }
            let b = Bake::open(shipped.path(), &Options::default()).unwrap();
            assert_eq!(b.source().1.len(), names.len(), "{what}: {:?}", b.source());
            for k in 0..3 {
                for j in 0..raw.ny {
                    for i in 0..raw.nx {
                        let (x, z) = centre(&m, i, j);
                        let w = b.wind_at([x, y, z], f64::from(k as f32 / m.frames.fps));
                        let v = raw.at(k, i, j);
                        assert!(
                            (w[0] - v[0]).abs() <= tol + POSITION_ROUNDING
                                && (w[2] - v[1]).abs() <= tol + POSITION_ROUNDING,
                            "{layout}, {what} alone, frame {k} cell ({i}, {j}): {w:?}, raw {v:?}"
                        );
                    }
                }
            }
        }
        let bare = tempfile::tempdir().unwrap();
        std::fs::copy(
            dir.path().join("manifest.json"),
            bare.path().join("manifest.json"),
        )
        .unwrap();
        let e = Bake::open(bare.path(), &Options::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("wind.f32: not there"), "{e}");
        // FGA (area-averaged cm/s text) is not read: asked for, it says what the bake has.
        let e = Bake::open(dir.path(), &opts("fga"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no `fga` files the runtime reads") && e.contains("raw"),
            "{e}"
        );
    }
}

/// Between frames the wind is blended linearly; a loop wraps, a plain bake holds its first
/// and last frames; up the profile the log law; beyond the edge as `Outside` says; and the
/// engines' axes and units.
#[test]
fn time_height_edges_and_axes_are_as_documented() {
    let dir = tempfile::tempdir().unwrap();
    let looped = BakeOptions {
        looped: true,
        formats: vec![Format::Raw],
        ..small(4)
    };
    let m = run(&example("two-winds.json"), dir.path(), &looped);
    let raw = Raw::read(dir.path(), &manifest(dir.path()));
    let b = Bake::open(dir.path(), &Options::default()).unwrap();
    let profile = m.profile.clone().expect("every bake states its profile");
    let y = profile.reference_height;
    let fps = f64::from(m.frames.fps);
    let (i, j) = (raw.nx / 3, raw.ny / 2);
    let (x, z) = centre(&m, i, j);
    let close = |a: [f32; 3], b: [f32; 2], what: &str| {
        assert!(
            (a[0] - b[0]).abs() <= POSITION_ROUNDING * (1.0 + b[0].abs())
                && (a[2] - b[1]).abs() <= POSITION_ROUNDING * (1.0 + b[1].abs()),
            "{what}: {a:?}, want {b:?}"
        );
    };
    let mix =
        |a: [f32; 2], c: [f32; 2], w: f32| [a[0] + (c[0] - a[0]) * w, a[1] + (c[1] - a[1]) * w];
    close(
        b.wind_at([x, y, z], 1.25 / fps),
        mix(raw.at(1, i, j), raw.at(2, i, j), 0.25),
        "a quarter past frame 1",
    );
    // A loop of 4 frames: after the last comes the first, and time wraps both ways.
    close(
        b.wind_at([x, y, z], 3.5 / fps),
        mix(raw.at(3, i, j), raw.at(0, i, j), 0.5),
        "between the last frame and the first",
    );
    close(
        b.wind_at([x, y, z], 4.0 / fps),
        raw.at(0, i, j),
        "one loop on",
    );
    close(
        b.wind_at([x, y, z], -1.0 / fps),
        raw.at(3, i, j),
        "one frame before 0",
    );
    assert!((f64::from(b.duration()) - 4.0 / fps).abs() < 1e-6);
    // The log law up the profile: zero at the roughness length, the top's wind above it.
    let law = |h: f32| {
        let z0 = f64::from(profile.roughness_length);
        ((f64::from(h) / z0).ln() / (f64::from(y) / z0).ln()) as f32
    };
    let v = raw.at(0, i, j);
    // A sweep from just above z0 to the top: every mantissa and a dozen exponents of the
    // law's logarithm.
    let z0 = profile.roughness_length;
    let sweep = (0..400).map(|k| z0 * 1.01 * (profile.top / (z0 * 1.01)).powf(k as f32 / 399.0));
    for h in [0.5 * y, 2.0 * y, 7.3].into_iter().chain(sweep) {
        let f = law(h);
        close(
            b.wind_at([x, h, z], 0.0),
            [v[0] * f, v[1] * f],
            &format!("{h} m up"),
        );
    }
    let f = law(profile.top);
    close(
        b.wind_at([x, 3.0 * profile.top, z], 0.0),
        [v[0] * f, v[1] * f],
        "above the top",
    );
    close(
        b.wind_at([x, profile.roughness_length, z], 0.0),
        [0.0, 0.0],
        "at z0",
    );
    close(b.wind_at([x, -1.0, z], 0.0), [0.0, 0.0], "underground");
    // Beyond the rectangle: the nearest edge's wind, or none.
    let west = m.world.min[0] - 50.0;
    close(
        b.wind_at([west, y, z], 0.0),
        raw.at(0, 0, j),
        "west of the world",
    );
    let zero = Bake::open(
        dir.path(),
        &Options {
            outside: Outside::Zero,
            ..Options::default()
        },
    )
    .unwrap();
    close(
        zero.wind_at([west, y, z], 0.0),
        [0.0, 0.0],
        "west, outside = zero",
    );
    close(zero.wind_at([x, y, z], 0.0), v, "inside, outside = zero");
    let wrap = Bake::open(
        dir.path(),
        &Options {
            outside: Outside::Wrap,
            ..Options::default()
        },
    )
    .unwrap();
    let width = m.world.max[0] - m.world.min[0];
    close(
        wrap.wind_at([x + 2.0 * width, y, z], 0.0),
        v,
        "two widths east, wrapped",
    );
    // Unity (z north) and Unreal (cm, z up).
    let unity = Bake::open(
        dir.path(),
        &Options {
            axes: Axes::Unity,
            ..Options::default()
        },
    )
    .unwrap();
    close(unity.wind_at([x, y, -z], 0.0), [v[0], -v[1]], "Unity");
    let unreal = Bake::open(
        dir.path(),
        &Options {
            axes: Axes::Unreal,
            ..Options::default()
        },
    )
    .unwrap();
    let w = unreal.wind_at([x * 100.0, z * 100.0, y * 100.0], 0.0);
    close([w[0], 0.0, w[1]], [v[0] * 100.0, v[1] * 100.0], "Unreal");
    assert_eq!(w[2], 0.0);
    // A bake that does not loop holds its ends.
    let plain = tempfile::tempdir().unwrap();
    run(
        &example("two-winds.json"),
        plain.path(),
        &BakeOptions {
            formats: vec![Format::Raw],
            ..small(3)
        },
    );
    let raw = Raw::read(plain.path(), &manifest(plain.path()));
    let b = Bake::open(plain.path(), &Options::default()).unwrap();
    close(
        b.wind_at([x, y, z], 10.0),
        raw.at(2, i, j),
        "after the last frame",
    );
    close(
        b.wind_at([x, y, z], -3.0),
        raw.at(0, i, j),
        "before the first",
    );
    close(b.wind_at([x, y, z], f64::NAN), raw.at(0, i, j), "at NaN");
    // Many points at once: the same answers.
    let points: Vec<[f32; 3]> = (0..500)
        .map(|k| {
            [
                k as f32 * 0.37 - 20.0,
                (k % 13) as f32,
                k as f32 * 0.21 - 10.0,
            ]
        })
        .collect();
    let mut out = vec![[0.0; 3]; points.len()];
    b.wind_at_many(&points, 0.13, &mut out);
    for (p, o) in points.iter().zip(&out) {
        assert_eq!(*o, b.wind_at(*p, 0.13));
    }
}

/// Over terrain the wind stands on the ground the bake shaped it with (`heights.png`).
#[test]
fn the_wind_stands_on_the_baked_terrain() {
    let dir = tempfile::tempdir().unwrap();
    let m = run(
        &example("walled-garden.json"),
        dir.path(),
        &BakeOptions {
            formats: vec![Format::Raw],
            ..small(1)
        },
    );
    let t = m.terrain.as_ref().expect("walled-garden has terrain");
    let raw = Raw::read(dir.path(), &manifest(dir.path()));
    let img = image::open(dir.path().join("heights.png"))
        .unwrap()
        .to_luma16();
    let b = Bake::open(dir.path(), &Options::default()).unwrap();
    let y = reference_height(dir.path());
    let mut rise = 0.0f32;
    for j in 0..raw.ny {
        for i in 0..raw.nx {
            let (x, z) = centre(&m, i, j);
            let ground =
                f32::from(img.get_pixel(i as u32, j as u32)[0]) / 65535.0 * t.scale + t.offset;
            rise = rise.max(ground - t.offset);
            assert!((b.ground_at(x, z) - ground).abs() <= 1e-4 * (1.0 + ground.abs()));
            let w = b.wind_at([x, ground + y, z], 0.0);
            let v = raw.at(0, i, j);
            assert!(
                (w[0] - v[0]).abs() <= 1e-4 * (1.0 + v[0].abs())
                    && (w[2] - v[1]).abs() <= 1e-4 * (1.0 + v[1].abs()),
                "cell ({i}, {j}) on ground {ground}: {w:?}, raw {v:?}"
            );
        }
    }
    assert!(
        rise > 1.0,
        "the terrain rises {rise} m: a flat test proves nothing"
    );
}

/// The same numbers everywhere: one bake read through the runtime, through its C interface,
/// and as the editor's own solver makes it. The bake's first frame, simulated again here as
/// the bake does, is the raw bake to the bit; the editor's map readout (`Snapshot::sample`)
/// of it gives what the runtime answers, at the cells and between them; and a C program
/// linked to the runtime's library reads the raw bake at every cell (Linux).
#[test]
fn one_bake_reads_the_same_in_rust_in_c_and_in_the_editor() {
    let dir = tempfile::tempdir().unwrap();
    let layout = example("branching.json");
    let opts = BakeOptions {
        formats: vec![Format::Raw],
        ..small(1)
    };
    let m = run(&layout, dir.path(), &opts);
    // The bake's run: its step, its warm-up, its clock.
    let mut sim = layout.clone();
    sim.world.grid = [m.grid[0] as u32, m.grid[1] as u32];
    sim.sim.dt = m.frames.sim_dt;
    let per_second = f64::from(m.frames.fps) * m.frames.steps_per_frame as f64;
    let steps = (m.frames.warmup_seconds * per_second).round() as usize;
    let (mut stepper, _) =
        windloom::engine::Stepper::new(&sim, windloom::engine::Backend::Cpu).unwrap();
    for _ in 0..steps {
        stepper.step();
    }
    let field = stepper.velocity_field().unwrap();
    let raw = Raw::read(dir.path(), &manifest(dir.path()));
    let same = (0..raw.ny)
        .flat_map(|j| (0..raw.nx).map(move |i| (i, j)))
        .all(|(i, j)| field[j * raw.nx + i] == raw.at(0, i, j));
    assert!(same, "the run here is not the bake's run");
    let snapshot = windloom::engine::live::Snapshot {
        nx: raw.nx,
        ny: raw.ny,
        origin: m.world.min,
        size: [
            m.world.max[0] - m.world.min[0],
            m.world.max[1] - m.world.min[1],
        ],
        velocity: field,
        ..Default::default()
    };
    let b = Bake::open(dir.path(), &Options::default()).unwrap();
    let y = reference_height(dir.path());
    for k in 0..2000 {
        let (u, v) = (
            (k as f32 * 0.618_034).fract(),
            (k as f32 * 0.414_213_6).fract(),
        );
        let x = m.world.min[0] + u * snapshot.size[0];
        let z = m.world.min[1] + v * snapshot.size[1];
        let want = snapshot.sample([x, z]);
        let got = b.wind_at([x, y, z], 0.0);
        assert!(
            (got[0] - want[0]).abs() <= 1e-5 * (1.0 + want[0].abs())
                && (got[2] - want[1]).abs() <= 1e-5 * (1.0 + want[1].abs()),
            "at ({x}, {z}): runtime {got:?}, editor {want:?}"
        );
    }
    #[cfg(target_os = "linux")]
    c_check(dir.path(), 1);
}

/// `windloom sample` answers what the runtime answers, to the bit, at points inside and
/// beyond the rectangle, in each edge mode, at times between frames and a month on (what
/// tests/godot/run.py checks the Godot add-on's GDScript against); a line that is no point is
/// refused naming its line, and nothing is answered past it.
#[test]
fn sample_answers_as_the_runtime_does() {
    let dir = tempfile::tempdir().unwrap();
    let opts = BakeOptions {
        formats: vec![Format::Raw],
        looped: true,
        ..small(3)
    };
    run(&example("two-winds.json"), dir.path(), &opts);
    let points: Vec<[f64; 4]> = (0..300)
        .map(|k| {
            let f = |a: f64| (k as f64 * a).fract();
            [
                -30.0 + 180.0 * f(0.618_034),
                -1.0 + 26.0 * f(0.414_213_6),
                -20.0 + 120.0 * f(0.732_050_8),
                -2.0 + 6.0 * f(0.236_068) + if k == 7 { 2.6e6 } else { 0.0 },
            ]
        })
        .collect();
    let text: String = points
        .iter()
        .map(|p| format!("{} {}, {}\t{}\n", p[0], p[1], p[2], p[3]))
        .collect::<String>()
        + "# a comment, then a blank line\n\n";
    for (name, outside) in [
        ("clamp", Outside::Clamp),
        ("zero", Outside::Zero),
        ("wrap", Outside::Wrap),
    ] {
        let out = sample_cli(dir.path(), &["--outside", name], &text);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let b = Bake::open(
            dir.path(),
            &Options {
                outside,
                ..Options::default()
            },
        )
        .unwrap();
        let lines: Vec<String> = String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .map(String::from)
            .collect();
        assert_eq!(lines.len(), points.len(), "{name}: one answer a point");
        for (p, line) in points.iter().zip(&lines) {
            let w = b.wind_at([p[0] as f32, p[1] as f32, p[2] as f32], p[3]);
            let got: Vec<f32> = line.split(' ').map(|v| v.parse().unwrap()).collect();
            assert_eq!(got, w.to_vec(), "{name}: at {p:?}");
        }
    }
    let out = sample_cli(dir.path(), &[], "1 2 3 4\n1 2 x 4\n5 6 7 8\n");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("stdin line 2") && err.lines().count() == 1,
        "{err}"
    );
    assert_eq!(String::from_utf8_lossy(&out.stdout).lines().count(), 1);
}

fn sample_cli(bake: &Path, args: &[&str], input: &str) -> std::process::Output {
    use std::io::Write;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
        .arg("sample")
        .arg(bake)
        .args(args)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    child.wait_with_output().unwrap()
}

/// The runtime follows re-bakes by `sequence`: a new bake answers once read whole; a broken
/// one is reported and the last good bake answers on; and while bakes land as fast as the
/// CPU makes them, every bake it reads is one bake's wind, never a mixture.
#[test]
fn re_bakes_are_followed_whole_and_a_broken_one_keeps_the_last_good() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bake");
    let one = BakeOptions {
        formats: vec![Format::Raw, Format::Exr],
        ..small(1)
    };
    let a_layout = example("two-winds.json");
    let mut b_layout = example("branching.json");
    b_layout.world.grid = a_layout.world.grid;
    run(&a_layout, &out, &one);
    let a = Raw::read(&out, &manifest(&out)).data;
    let mut live = LiveBake::open(&out, Options::default()).unwrap();
    assert_eq!(live.bake().sequence(), 1);
    assert!(!live.poll().unwrap(), "nothing new");
    run(&b_layout, &out, &one);
    let b = Raw::read(&out, &manifest(&out)).data;
    let apart = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max);
    assert!(apart > 0.1, "the two bakes differ by {apart} m/s only");
    assert!(live.poll().unwrap(), "the re-bake is seen");
    assert_eq!(live.bake().sequence(), 2);
    let y = reference_height(&out);
    let [nx, ny] = live.bake().grid();
    let first = |bake: &Bake| -> Vec<f32> {
        let (min, max) = bake.bounds();
        (0..ny)
            .flat_map(|j| (0..nx).map(move |i| (i, j)))
            .flat_map(|(i, j)| {
                let x = min[0] + (i as f32 + 0.5) * (max[0] - min[0]) / nx as f32;
                let z = min[1] + (j as f32 + 0.5) * (max[1] - min[1]) / ny as f32;
                let w = bake.wind_at([x, y, z], 0.0);
                [w[0], w[2]]
            })
            .collect()
    };
    assert!(same(&first(live.bake()), &b));

    // A broken bake: the manifest moves on, the file the runtime reads is cut short.
    let path = out.join("manifest.json");
    let good = std::fs::read_to_string(&path).unwrap();
    let raw = std::fs::read(out.join("wind.f32")).unwrap();
    std::fs::write(out.join("wind.f32"), &raw[..raw.len() / 2]).unwrap();
    std::fs::write(&path, good.replace("\"sequence\": 2", "\"sequence\": 3")).unwrap();
    let e = live.poll().unwrap_err().to_string();
    assert!(e.contains("wind.f32") && e.contains("bytes"), "{e}");
    assert_eq!(live.bake().sequence(), 2, "the last good bake answers");
    assert!(same(&first(live.bake()), &b));
    assert!(live.last_error().is_some_and(|l| l.contains("wind.f32")));
    assert!(
        !live.poll().unwrap(),
        "the same broken bake is not read again"
    );
    // A manifest that does not parse: one line naming it and the position.
    std::fs::write(&path, "{\"format\": \"windloom-bake\", ").unwrap();
    let e = live.poll().unwrap_err().to_string();
    assert!(e.contains("manifest.json: line 1, column"), "{e}");
    assert_eq!(live.bake().sequence(), 2);
    // The folder made whole again (a bake refuses to replace a folder whose manifest is
    // not a bake's): the bake that answers, nothing new.
    std::fs::write(&path, &good).unwrap();
    std::fs::write(out.join("wind.f32"), &raw).unwrap();
    assert!(!live.poll().unwrap());

    // Bakes landing one after another while it reads: each read is one bake.
    run(&a_layout, &out, &one);
    assert!(live.poll().unwrap() && live.last_error().is_none());
    let stop = std::sync::Arc::new(AtomicBool::new(false));
    let baker = {
        let (out, stop) = (out.clone(), stop.clone());
        let (a_layout, b_layout, one) = (a_layout.clone(), b_layout.clone(), one.clone());
        std::thread::spawn(move || {
            let mut n = 0;
            while !stop.load(std::sync::atomic::Ordering::Relaxed) && n < 40 {
                let l = if n % 2 == 0 { &b_layout } else { &a_layout };
                bake::bake(l, &out, &one, &AtomicBool::new(false), &mut |_, _, _| {}).unwrap();
                n += 1;
            }
            n
        })
    };
    let (mut seen, mut reads) = (std::collections::BTreeSet::new(), 0);
    let started = std::time::Instant::now();
    while seen.len() < 6 && started.elapsed().as_secs() < 60 {
        if let Ok(true) = live.poll() {
            let w = first(live.bake());
            assert!(
                same(&w, &a) || same(&w, &b),
                "sequence {}: a mixture of two bakes",
                live.bake().sequence()
            );
            seen.insert(live.bake().sequence());
            reads += 1;
        }
    }
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    let bakes = baker.join().unwrap();
    assert!(reads >= 3, "{reads} re-bakes read while {bakes} landed");
}

/// A C program, linked to the runtime's library as an engine links it, reads the wind at
/// every cell of every frame and checks it against the raw bake it reads itself.
#[cfg(target_os = "linux")]
#[test]
fn the_c_interface_reads_the_raw_bake_at_every_cell() {
    let dir = tempfile::tempdir().unwrap();
    let bake_dir = dir.path().join("bake");
    run(
        &example("obstacles.json"),
        &bake_dir,
        &BakeOptions {
            formats: vec![Format::Raw, Format::Png8],
            ..small(3)
        },
    );
    c_check(&bake_dir, 3);
}

/// Builds `tests/runtime/check.c` against the runtime's library and runs it on the bake in
/// `bake_dir` (`frames` frames): it must check every cell of every frame and pass.
#[cfg(target_os = "linux")]
fn c_check(bake_dir: &Path, frames: u64) {
    // The library cargo built beside this test (the runtime's cdylib, as a dependency).
    let deps = std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .to_path_buf();
    assert!(
        deps.join("libwindloom_runtime.so").exists(),
        "no libwindloom_runtime.so in {}",
        deps.display()
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let work = tempfile::tempdir().unwrap();
    let exe = work.path().join("check");
    let cc = std::process::Command::new("cc")
        .arg(root.join("tests/runtime/check.c"))
        .arg("-std=c99")
        .args(["-Wall", "-Wextra", "-Werror", "-O1"])
        .arg("-I")
        .arg(root.join("src/runtime"))
        .arg("-L")
        .arg(&deps)
        .arg(format!("-Wl,-rpath,{}", deps.display()))
        .args(["-lwindloom_runtime", "-lm", "-o"])
        .arg(&exe)
        .output()
        .expect("a C compiler (cc)");
    assert!(
        cc.status.success(),
        "cc: {}",
        String::from_utf8_lossy(&cc.stderr)
    );
    let y = reference_height(bake_dir).to_string();
    let out = std::process::Command::new(&exe)
        .arg(bake_dir)
        .arg(&y)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let m = manifest(bake_dir);
    let cells = m["grid"][0].as_u64().unwrap() * m["grid"][1].as_u64().unwrap() * frames;
    assert!(
        text.starts_with(&format!("checked {cells} cells of {frames} frames")),
        "{text}"
    );
}
