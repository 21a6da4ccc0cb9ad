//! A bake as a hostile game asset: manifests and files that lie about their sizes, names,
//! numbers and kinds, each refused by the runtime at open, at once, in one bounded line that
//! names the file, never a panic, an abort, a hang, a read outside the folder or a wind that
//! is not a number; the C interface returns −1 rather than crash; and the runtime's edges
//! and clock as a game has them.

use super::*;
use serde_json::{Value, json};
use std::time::{Duration, Instant};
use windloom_runtime::{Bake, LiveBake, MAX_ERROR_CHARS, Options, Outside};

/// A small raw + PNG bake of two-winds (3 frames, 48 × 32), and its manifest.
fn good_bake(dir: &Path) -> Value {
    run(
        &example("two-winds.json"),
        dir,
        &BakeOptions {
            formats: vec![Format::Raw, Format::Png16],
            ..small(3)
        },
    );
    manifest(dir)
}

fn write_manifest(dir: &Path, m: &Value) {
    std::fs::write(
        dir.join("manifest.json"),
        serde_json::to_vec_pretty(m).unwrap(),
    )
    .unwrap();
}

/// The files entry of `format` (the first one).
fn entry<'a>(m: &'a mut Value, format: &str) -> &'a mut Value {
    m["files"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|f| f["format"] == format)
        .unwrap()
}

/// Opens `dir` as a game would, expecting a refusal: one line, bounded, quick, containing
/// every one of `says`.
fn refused(dir: &Path, options: &Options, says: &[&str]) -> String {
    let start = Instant::now();
    let e = Bake::open(dir, options).expect_err("a lying bake opened");
    let line = e.to_string();
    assert!(
        start.elapsed() < Duration::from_secs(5),
        "took {:?}",
        start.elapsed()
    );
    assert!(
        !line.chars().any(char::is_control) && line.chars().count() <= MAX_ERROR_CHARS,
        "not one bounded line: {line:?}"
    );
    for s in says {
        assert!(line.contains(s), "{line:?} does not say {s:?}");
    }
    line
}

fn raw_only() -> Options {
    Options {
        format: Some("raw".into()),
        ..Options::default()
    }
}

/// Sizes that would wrap, abort on allocation or ask for gigabytes are refused from the
/// manifest's numbers, before anything is allocated or read.
#[test]
fn sizes_that_wrap_or_ask_for_too_much_are_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let good = good_bake(dir.path());
    /// What the case is, the lie told, and what the refusal must say.
    type Case = (&'static str, fn(&mut Value), &'static [&'static str]);
    let cases: [Case; 5] = [
        (
            "frames × cells wraps (2^59 + 3 frames)",
            |m| m["frames"]["count"] = json!((1u64 << 59) + 3),
            &["frames: 576460752303423491"],
        ),
        (
            "a trillion frames",
            |m| m["frames"]["count"] = json!(1_000_000_000_000u64),
            &["frames"],
        ),
        (
            "2^24 cells an axis",
            |m| entry(m, "raw")["axes"]["index"][0]["cells"] = json!(1u64 << 24),
            &["wind.f32", "axes"],
        ),
        (
            "frames that need more than the memory a bake may take",
            |m| {
                m["frames"]["count"] = json!(90_000);
                entry(m, "raw")["axes"]["index"][0]["cells"] = json!(16_000);
            },
            &["GiB a bake may hold"],
        ),
        (
            "a file listed as 3 GiB",
            |m| entry(m, "raw")["bytes"] = json!(3u64 << 30),
            &["wind.f32", "bytes: 3221225472"],
        ),
    ];
    for (what, lie, says) in cases {
        let mut m = good.clone();
        lie(&mut m);
        write_manifest(dir.path(), &m);
        eprintln!("{what}");
        refused(dir.path(), &raw_only(), says);
    }
}

/// A file larger than the manifest says is refused by its size on disk, unread (a sparse
/// 3 GiB `wind.f32` costs nothing to make and would cost 3 GB to read).
#[test]
fn a_file_larger_than_listed_is_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    good_bake(dir.path());
    let f = std::fs::OpenOptions::new()
        .write(true)
        .open(dir.path().join("wind.f32"))
        .unwrap();
    f.set_len(3 << 30).unwrap();
    refused(
        dir.path(),
        &raw_only(),
        &["wind.f32", "3221225472 bytes where the manifest lists"],
    );
}

/// A PNG whose header claims 65535 × 65535 pixels (a 9 kB file asking for 25.8 GB) is
/// refused by its header, before any pixel is decoded.
#[test]
fn a_png_whose_header_lies_is_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = good_bake(dir.path());
    let name = entry(&mut m, "png16")["name"].as_str().unwrap().to_string();
    let path = dir.path().join(&name);
    let mut png = std::fs::read(&path).unwrap();
    // IHDR: the signature (8), the chunk's length (4) and type (4), then width and height.
    png[16..20].copy_from_slice(&65535u32.to_be_bytes());
    png[20..24].copy_from_slice(&65535u32.to_be_bytes());
    let crc = crc32(&png[12..29]);
    png[29..33].copy_from_slice(&crc.to_be_bytes());
    std::fs::write(&path, &png).unwrap();
    let png16 = Options {
        format: Some("png16".into()),
        ..Options::default()
    };
    refused(
        dir.path(),
        &png16,
        &[&name, "the header says 65535 × 65535 pixels"],
    );
}

/// CRC-32 (ISO 3309, as PNG's chunks carry it), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 == 1 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// File names that leave the folder are refused by name: nothing outside the bake is read.
#[test]
fn names_that_leave_the_folder_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let bake_dir = dir.path().join("bake");
    let good = good_bake(&bake_dir);
    // A file outside, of exactly the size listed: were it read, the bake would open.
    let raw_bytes = std::fs::read(bake_dir.join("wind.f32")).unwrap();
    std::fs::write(dir.path().join("secret.f32"), &raw_bytes).unwrap();
    std::fs::remove_file(bake_dir.join("wind.f32")).unwrap();
    for name in [
        "../secret.f32".to_string(),
        dir.path().join("secret.f32").display().to_string(),
        "sub/../../secret.f32".into(),
    ] {
        let mut m = good.clone();
        entry(&mut m, "raw")["name"] = json!(name);
        write_manifest(&bake_dir, &m);
        refused(
            &bake_dir,
            &raw_only(),
            &["is not a file name in the bake's folder"],
        );
    }
    // The terrain's file too.
    let mut m = good.clone();
    m["terrain"] = json!({
        "file": "../secret.f32", "sample": "unorm16", "scale": 1.0, "offset": 0.0,
        "axes": m["files"][0]["axes"]["index"].clone(),
    });
    write_manifest(&bake_dir, &m);
    refused(&bake_dir, &Options::default(), &["terrain.file"]);
}

/// A FIFO or a device where a file should be is refused at once (it blocked `open` and
/// `reload` for ever, or read `/dev/zero` until memory ran out).
#[cfg(unix)]
#[test]
fn fifos_and_devices_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    good_bake(dir.path());
    let wind = dir.path().join("wind.f32");
    std::fs::remove_file(&wind).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &wind).unwrap();
    refused(dir.path(), &raw_only(), &["wind.f32", "not a plain file"]);

    let manifest = dir.path().join("manifest.json");
    std::fs::remove_file(&manifest).unwrap();
    let made = std::process::Command::new("mkfifo")
        .arg(&manifest)
        .status()
        .unwrap();
    assert!(made.success());
    refused(
        dir.path(),
        &raw_only(),
        &["manifest.json", "not a plain file"],
    );
    std::fs::remove_file(&manifest).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &manifest).unwrap();
    refused(
        dir.path(),
        &raw_only(),
        &["manifest.json", "not a plain file"],
    );
}

/// Numbers that are not numbers never reach the game: a channel's scale of 1e39 (beyond
/// f32), one that makes the wind infinite, a NaN or an infinity in the file, a strongest wind
/// of 1e39.
#[test]
fn winds_that_are_not_finite_are_refused_at_open() {
    let dir = tempfile::tempdir().unwrap();
    let good = good_bake(dir.path());
    let raw_path = dir.path().join("wind.f32");
    let raw_bytes = std::fs::read(&raw_path).unwrap();
    // Beyond f32: refused as the manifest is read.
    for scale in [json!(1e39), json!(-1e39)] {
        let mut m = good.clone();
        entry(&mut m, "raw")["encoding"]["channels"][0]["scale"] = scale;
        write_manifest(dir.path(), &m);
        refused(dir.path(), &raw_only(), &["manifest.json", "out of range"]);
    }
    // A float, times the wind, that is not: refused as the file is decoded.
    let mut m = good.clone();
    entry(&mut m, "raw")["encoding"]["channels"][0]["scale"] = json!(3e38);
    write_manifest(dir.path(), &m);
    refused(dir.path(), &raw_only(), &["wind.f32", "not a finite wind"]);
    write_manifest(dir.path(), &good);
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let mut bytes = raw_bytes.clone();
        bytes[4 * 1001..4 * 1002].copy_from_slice(&bad.to_le_bytes());
        std::fs::write(&raw_path, &bytes).unwrap();
        refused(dir.path(), &raw_only(), &["wind.f32", "not a finite wind"]);
    }
    std::fs::write(&raw_path, &raw_bytes).unwrap();
    let mut m = good.clone();
    m["max_speed"] = json!(1e39);
    write_manifest(dir.path(), &m);
    refused(dir.path(), &raw_only(), &["manifest.json"]);
    // And the good bake still opens, answering finite winds.
    write_manifest(dir.path(), &good);
    let b = Bake::open(dir.path(), &raw_only()).unwrap();
    assert!(
        b.wind_at([10.0, 2.0, 10.0], 0.1)
            .iter()
            .all(|v| v.is_finite())
    );
}

/// Errors quote what came from the bake escaped and bounded, a missing frame is named as
/// one, and the last error clears once a good bake is read again.
#[test]
fn errors_are_one_line_and_say_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let good = good_bake(dir.path());
    // A newline and a terminal escape in a file name, and a name of a megabyte.
    for name in [
        "wind\n\u{1b}[2J.f32".to_string(),
        "w".repeat(1 << 20) + ".f32",
    ] {
        let mut m = good.clone();
        entry(&mut m, "raw")["name"] = json!(name);
        write_manifest(dir.path(), &m);
        let line = refused(dir.path(), &raw_only(), &[]);
        assert!(line.len() < 4 * MAX_ERROR_CHARS, "{} bytes", line.len());
    }
    // Frames that do not match `frames.count`: said so, not "no such format".
    let mut m = good.clone();
    m["frames"]["count"] = json!(4);
    write_manifest(dir.path(), &m);
    refused(
        dir.path(),
        &Options {
            format: Some("png16".into()),
            ..Options::default()
        },
        &["png16", "frames.count", "not every frame is there"],
    );
}

/// The C interface: no call crashes the game whatever it is given, `wind_at_many` with a
/// count no array can hold returns −1, and `windloom_last_error` forgets an old failure
/// after a good reload.
#[test]
fn the_c_interface_fails_with_minus_one_and_forgets_old_failures() {
    use std::ffi::{CStr, CString};
    use windloom_runtime::c_api::*;
    let dir = tempfile::tempdir().unwrap();
    let good = good_bake(dir.path());
    let folder = CString::new(dir.path().to_str().unwrap()).unwrap();
    let last = || {
        // SAFETY: windloom_last_error returns a NUL-terminated string valid until the next
        // call on this thread.
        unsafe { CStr::from_ptr(windloom_last_error()) }
            .to_string_lossy()
            .into_owned()
    };
    // SAFETY: a NUL-terminated folder; the handle is used on this thread only and closed
    // once; every pointer passed is valid for what the call reads or writes.
    unsafe {
        let w = windloom_open(folder.as_ptr(), 0, 0);
        assert!(!w.is_null(), "{}", last());
        let p = [1.0f32, 2.0, 3.0];
        let mut out = [0.0f32; 3];
        assert_eq!(
            windloom_wind_at_many(w, p.as_ptr(), usize::MAX / 3 + 1, 0.0, out.as_mut_ptr()),
            -1
        );
        assert!(last().contains("count"), "{}", last());
        // A broken re-bake: −1 and why; the good bake goes on answering.
        let mut broken = good.clone();
        broken["sequence"] = json!(99);
        entry(&mut broken, "raw")["bytes"] = json!(7);
        entry(&mut broken, "png16")["bytes"] = json!(7);
        write_manifest(dir.path(), &broken);
        assert_eq!(windloom_reload(w), -1);
        assert!(!last().is_empty());
        assert_eq!(
            windloom_wind_at(w, 10.0, 2.0, 10.0, 0.0, out.as_mut_ptr()),
            0
        );
        // The good bake back: the old failure is no longer reported.
        let mut fixed = good.clone();
        fixed["sequence"] = json!(100);
        write_manifest(dir.path(), &fixed);
        assert_eq!(windloom_reload(w), 1, "{}", last());
        assert_eq!(last(), "");
        windloom_close(w);
    }
}

/// Time as a game has it: a clock a month on reads the wind as one a minute on does (f64
/// time; f32 stepped 16 frames at a time there), and an infinite time holds the last frame of
/// a bake that does not loop.
#[test]
fn a_month_old_clock_reads_the_same_wind() {
    let dir = tempfile::tempdir().unwrap();
    run(
        &example("two-winds.json"),
        dir.path(),
        &BakeOptions {
            formats: vec![Format::Raw],
            looped: true,
            ..small(8)
        },
    );
    let b = Bake::open(dir.path(), &raw_only()).unwrap();
    let period = b.frames() as f64 / f64::from(b.fps());
    let month = 30.0 * 86_400.0;
    let cycles = (month / period).round();
    let p = [30.0, 2.0, 20.0];
    for k in 0..60 {
        let t = k as f64 / 60.0;
        let (a, m) = (b.wind_at(p, t), b.wind_at(p, cycles * period + t));
        for c in 0..3 {
            assert!(
                (a[c] - m[c]).abs() <= 1e-4 * (1.0 + a[c].abs()),
                "{t} s: {a:?}, a month on {m:?}"
            );
        }
    }
    let dir = tempfile::tempdir().unwrap();
    run(
        &example("two-winds.json"),
        dir.path(),
        &BakeOptions {
            formats: vec![Format::Raw],
            ..small(3)
        },
    );
    let b = Bake::open(dir.path(), &raw_only()).unwrap();
    assert_eq!(
        b.wind_at(p, f64::INFINITY),
        b.wind_at(p, 1e9),
        "+inf holds the last frame"
    );
    assert_eq!(b.wind_at(p, f64::NEG_INFINITY), b.wind_at(p, 0.0));
}

/// Beyond each edge, over terrain and flat, each `Outside` mode against its reference read
/// inside the rectangle: Clamp the edge's wind over the edge's ground, Zero nothing, Wrap the
/// wind and the ground of the wrapped point (it took the clamped ground: up to 2 m/s off).
#[test]
fn every_edge_mode_beyond_every_edge_over_terrain_and_flat() {
    for layout in ["walled-garden.json", "two-winds.json"] {
        let dir = tempfile::tempdir().unwrap();
        let m = run(
            &example(layout),
            dir.path(),
            &BakeOptions {
                formats: vec![Format::Raw],
                ..small(1)
            },
        );
        let open = |outside| {
            Bake::open(
                dir.path(),
                &Options {
                    outside,
                    ..raw_only()
                },
            )
            .unwrap()
        };
        let (min, max) = (m.world.min, m.world.max);
        let size = [max[0] - min[0], max[1] - min[1]];
        let (clamp, zero, wrap) = (
            open(Outside::Clamp),
            open(Outside::Zero),
            open(Outside::Wrap),
        );
        let mut wrap_differs = 0.0f32;
        // Points a third of the way along each edge and at the corners, a fifth of the
        // rectangle beyond it.
        for (fx, fz) in [
            (-0.2, 0.33),
            (1.2, 0.33),
            (0.33, -0.2),
            (0.33, 1.2),
            (-0.2, -0.2),
            (1.2, 1.2),
        ] {
            let (x, z) = (min[0] + fx * size[0], min[1] + fz * size[1]);
            let inside = |v: f32, lo: f32, hi: f32| v.clamp(lo, hi);
            let (cx, cz) = (inside(x, min[0], max[0]), inside(z, min[1], max[1]));
            let wrapped = |v: f32, lo: f32, s: f32| lo + (v - lo).rem_euclid(s);
            let (wx, wz) = (wrapped(x, min[0], size[0]), wrapped(z, min[1], size[1]));
            // Two metres above the ground that the reference stands on.
            let (cy, wy) = (clamp.ground_at(cx, cz) + 2.0, wrap.ground_at(wx, wz) + 2.0);
            let near = |a: [f32; 3], b: [f32; 3], what: &str| {
                assert!(
                    (0..3).all(|c| (a[c] - b[c]).abs() <= 2e-3 * (1.0 + b[c].abs())),
                    "{layout} ({fx}, {fz}) {what}: {a:?}, reference {b:?}"
                );
            };
            near(
                clamp.wind_at([x, cy, z], 0.0),
                clamp.wind_at([cx, cy, cz], 0.0),
                "clamp",
            );
            assert_eq!(zero.wind_at([x, cy, z], 0.0), [0.0; 3], "{layout} zero");
            let (g, gw) = (wrap.ground_at(x, z), wrap.ground_at(wx, wz));
            assert!(
                (g - gw).abs() <= 1e-3 * (1.0 + gw.abs()),
                "{layout} ground {g} vs {gw}"
            );
            let w = wrap.wind_at([x, wy, z], 0.0);
            near(w, wrap.wind_at([wx, wy, wz], 0.0), "wrap");
            wrap_differs = wrap_differs.max((w[0] - clamp.wind_at([x, wy, z], 0.0)[0]).abs());
        }
        assert!(wrap_differs > 0.0, "{layout}: wrap and clamp never differ");
    }
}

/// A re-bake storm never stalls a reload: a reload reads the folder once, and when another
/// bake lands while it reads, it answers "nothing new yet" and reads the newest next time.
#[test]
fn a_reload_reads_once_and_never_waits_out_a_re_bake() {
    let dir = tempfile::tempdir().unwrap();
    let good = good_bake(dir.path());
    let mut live = LiveBake::open(dir.path(), raw_only()).unwrap();
    // A manifest that names files not there yet (a bake half landed): one quick failure.
    let mut m = good.clone();
    m["sequence"] = json!(7);
    entry(&mut m, "raw")["name"] = json!("wind-next.f32");
    write_manifest(dir.path(), &m);
    let start = Instant::now();
    assert!(live.poll().is_err());
    assert!(
        start.elapsed() < Duration::from_millis(500),
        "{:?}",
        start.elapsed()
    );
    assert!(live.last_error().is_some());
    assert_eq!(live.bake().sequence(), good["sequence"].as_u64().unwrap());
    write_manifest(dir.path(), &good);
}

/// Every leaf of a JSON tree, by its path of keys and indices.
fn leaves(v: &Value, at: &mut Vec<Value>, out: &mut Vec<Vec<Value>>) {
    match v {
        Value::Object(o) => o.iter().for_each(|(k, c)| {
            at.push(json!(k));
            leaves(c, at, out);
            at.pop();
        }),
        Value::Array(a) => a.iter().enumerate().for_each(|(k, c)| {
            at.push(json!(k));
            leaves(c, at, out);
            at.pop();
        }),
        _ => out.push(at.clone()),
    }
}

fn leaf_mut<'a>(v: &'a mut Value, path: &[Value]) -> &'a mut Value {
    path.iter().fold(v, |v, k| match k {
        Value::String(s) => &mut v[s.as_str()],
        k => &mut v[k.as_u64().unwrap() as usize],
    })
}

/// What a hostile manifest puts in a field.
fn hostile_value(k: usize) -> Value {
    let pool = [
        json!(0),
        json!(-1),
        json!(1),
        json!(3),
        json!(u32::MAX),
        json!(u64::MAX),
        json!((1u64 << 59) + 3),
        json!(1e30),
        json!(-1e30),
        json!(3e38),
        json!(1e-40),
        json!(""),
        json!("../manifest.json"),
        json!("/dev/zero"),
        json!("-y"),
        json!("x"),
        json!("f16"),
        json!(null),
        json!([]),
        json!({}),
        json!(true),
    ];
    pool[k % pool.len()].clone()
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]
    /// Fuzzing the manifest and the files it lists: 300 bakes, each with up to four fields
    /// of the manifest set to hostile values and up to four bytes of a file changed, opened
    /// as raw, PNG and by the runtime's own choice. Each opens or is refused in one bounded
    /// line; none panics, and one that opens answers finite winds.
    #[test]
    fn fuzzed_bakes_open_or_are_refused_in_one_line(
        edits in proptest::collection::vec((0usize..10_000, 0usize..1000), 0..4),
        flips in proptest::collection::vec((0usize..1_000_000, 0u8..=255, 0usize..8), 0..4),
    ) {
        use std::sync::OnceLock;
        static GOOD: OnceLock<(tempfile::TempDir, Value)> = OnceLock::new();
        let (good_dir, good) = GOOD.get_or_init(|| {
            let d = tempfile::tempdir().unwrap();
            let m = good_bake(d.path());
            (d, m)
        });
        let dir = tempfile::tempdir().unwrap();
        for e in std::fs::read_dir(good_dir.path()).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), dir.path().join(e.file_name())).unwrap();
        }
        let mut m = good.clone();
        let mut paths = Vec::new();
        leaves(&m, &mut Vec::new(), &mut paths);
        for (p, v) in &edits {
            *leaf_mut(&mut m, &paths[p % paths.len()]) = hostile_value(*v);
        }
        write_manifest(dir.path(), &m);
        let mut names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| !p.ends_with("manifest.json"))
            .collect();
        names.sort();
        for (at, byte, file) in &flips {
            let path = &names[file % names.len()];
            let mut bytes = std::fs::read(path).unwrap();
            let k = at % bytes.len();
            bytes[k] = *byte;
            std::fs::write(path, &bytes).unwrap();
        }
        for format in [Some("raw"), Some("png16"), None] {
            let options = Options {
                format: format.map(String::from),
                ..Options::default()
            };
            match std::panic::catch_unwind(|| Bake::open(dir.path(), &options)) {
                Err(_) => panic!("opening panicked: {m}"),
                Ok(Ok(b)) => {
                    let w = b.wind_at([10.0, 2.0, 10.0], 0.37);
                    proptest::prop_assert!(w.iter().all(|v| v.is_finite()), "{w:?}");
                }
                Ok(Err(e)) => {
                    let line = e.to_string();
                    proptest::prop_assert!(
                        !line.chars().any(char::is_control)
                            && line.chars().count() <= MAX_ERROR_CHARS,
                        "{line:?}"
                    );
                }
            }
        }
    }
}
