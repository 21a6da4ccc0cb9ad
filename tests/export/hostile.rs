//! The CLI against hostile inputs and output targets, as containers, CI machines and shared
//! folders present them: every case ends within seconds in a result or a one-line refusal
//! that names the path, with a non-zero exit, nothing half-written and nothing of the user's
//! replaced. Cases that need root (device nodes, mounts) skip loudly without it.

use super::{example, run, small};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longest any case may take: a refusal is immediate; the slowest result is a small bake in
/// a debug build.
const LIMIT: Duration = Duration::from_secs(60);

struct Ran {
    code: Option<i32>,
    out: String,
    err: String,
}

impl Ran {
    /// A refusal: a non-zero exit and one line (on stdout for `validate`, on stderr for the
    /// rest) that names `what`.
    fn refused(&self, what: &str) -> &Self {
        assert!(
            self.code.is_some_and(|c| c != 0),
            "expected a refusal naming {what}, got exit {:?}\n{}\n{}",
            self.code,
            self.out,
            self.err
        );
        let text = if self.err.trim().is_empty() {
            &self.out
        } else {
            &self.err
        };
        let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(lines.len(), 1, "one line, got: {text}");
        assert!(lines[0].contains(what), "{what} not named in: {}", lines[0]);
        // In words: never the OS's error number, never the hidden staging folder.
        assert!(
            !lines[0].contains("(os error") && !lines[0].contains(".windloom-bake"),
            "{}",
            lines[0]
        );
        self
    }

    fn says(&self, needle: &str) -> &Self {
        assert!(
            self.out.contains(needle) || self.err.contains(needle),
            "{needle:?} not in\n{}\n{}",
            self.out,
            self.err
        );
        self
    }

    fn ok(&self) -> &Self {
        assert_eq!(self.code, Some(0), "{}\n{}", self.out, self.err);
        self
    }
}

/// Runs the CLI, killing it (and failing) past [`LIMIT`].
fn cli(args: &[&str]) -> Ran {
    let mut child = Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            panic!("windloom {args:?} did not end within {LIMIT:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let o = child.wait_with_output().unwrap();
    Ran {
        code: o.status.code(),
        out: String::from_utf8_lossy(&o.stdout).into_owned(),
        err: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn meadow_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts/meadow.json")
}

#[cfg(target_os = "linux")]
fn is_root() -> bool {
    rustix::process::geteuid().is_root()
}

/// A FIFO at `p`, by the system's own `mkfifo` (Linux and macOS alike).
#[cfg(unix)]
fn mkfifo(p: &Path) {
    let made = Command::new("mkfifo").arg(p).status().unwrap();
    assert!(made.success(), "mkfifo {}", p.display());
}

/// A mounted tmpfs of `size`, unmounted on drop; `None` (said loudly) where this user may
/// not mount (Linux).
#[cfg(target_os = "linux")]
struct Mount(PathBuf);

#[cfg(target_os = "linux")]
impl Mount {
    fn tmpfs(at: &Path, size: &str) -> Option<Mount> {
        std::fs::create_dir_all(at).unwrap();
        let ok = is_root()
            && Command::new("mount")
                .args(["-t", "tmpfs", "-o", &format!("size={size}"), "none", s(at)])
                .status()
                .is_ok_and(|st| st.success());
        if !ok {
            eprintln!("SKIPPED: cannot mount a tmpfs here (not root, or no CAP_SYS_ADMIN)");
            return None;
        }
        Some(Mount(at.to_path_buf()))
    }
}

#[cfg(target_os = "linux")]
impl Drop for Mount {
    fn drop(&mut self) {
        let _ = Command::new("umount").args(["-l", s(&self.0)]).status();
    }
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// No command replaces or writes into what is not a regular file: a FIFO, a socket, a device
/// node (as root), a folder. Each is refused at once with one line naming the path, and is
/// still what it was.
#[cfg(unix)]
#[test]
fn outputs_that_are_not_regular_files_are_refused() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let meadow = meadow_path();
    let fifo = dir.path().join("fifo.png");
    mkfifo(&fifo);
    let socket = dir.path().join("socket.png");
    let _listener = std::os::unix::net::UnixListener::bind(&socket).unwrap();
    let folder = dir.path().join("folder.png");
    std::fs::create_dir(&folder).unwrap();
    #[cfg_attr(
        not(target_os = "linux"),
        expect(unused_mut, reason = "only Linux adds a device node")
    )]
    let mut targets = vec![fifo.clone(), socket.clone(), folder.clone()];
    #[cfg(target_os = "linux")]
    if is_root() {
        // A private /dev/null: the test never touches the machine's own.
        let null = dir.path().join("null");
        rustix::fs::mknodat(
            rustix::fs::CWD,
            &null,
            rustix::fs::FileType::CharacterDevice,
            rustix::fs::Mode::from_raw_mode(0o666),
            rustix::fs::makedev(1, 3),
        )
        .unwrap();
        targets.push(null);
    } else {
        eprintln!("SKIPPED: the device-node output (needs root to make one)");
    }
    for t in &targets {
        let kind = std::fs::symlink_metadata(t).unwrap().file_type();
        cli(&["render", s(&meadow), "-o", s(t), "--size", "64x64"]).refused(s(t));
        // A link to it is followed and refused the same way.
        let link = dir.path().join("link.png");
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink(t, &link).unwrap();
        cli(&["render", s(&meadow), "-o", s(&link), "--size", "64x64"]).refused("link.png");
        assert_eq!(std::fs::symlink_metadata(t).unwrap().file_type(), kind);
    }
    assert!(
        std::fs::symlink_metadata(&fifo)
            .unwrap()
            .file_type()
            .is_fifo()
    );
    assert!(
        std::fs::symlink_metadata(&socket)
            .unwrap()
            .file_type()
            .is_socket()
    );
    // A bake writes a folder: a FIFO or a file where it goes is refused.
    cli(&[
        "bake",
        s(&meadow),
        "--out",
        s(&fifo),
        "--format",
        "vf",
        "--frames",
        "1",
    ])
    .refused(s(&fifo))
    .says("FIFO");
    // Nothing else appeared beside them (no temporary file, no staging folder).
    let left: Vec<String> = names(dir.path())
        .into_iter()
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

/// Inputs that never end, or are not what they claim, are refused within seconds without
/// being read whole: a FIFO (as the layout and as the map image), a character device, a
/// folder, a symbolic-link loop, a file past the size limit (sparse, so it costs no disk),
/// a file cut short, and every encoding that is not UTF-8.
#[cfg(unix)]
#[test]
fn inputs_that_never_end_or_are_not_text_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let meadow = std::fs::read_to_string(meadow_path()).unwrap();
    let fifo = d.join("fifo.json");
    mkfifo(&fifo);
    let folder = d.join("folder.json");
    std::fs::create_dir(&folder).unwrap();
    let loop_a = d.join("loop-a.json");
    std::os::unix::fs::symlink(d.join("loop-b.json"), &loop_a).unwrap();
    std::os::unix::fs::symlink(&loop_a, d.join("loop-b.json")).unwrap();
    let huge = d.join("huge.json");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len(windloom::doc::LAYOUT_MAX_BYTES + 1)
        .unwrap();
    let cut = d.join("cut.json");
    std::fs::write(&cut, &meadow[..meadow.len() / 2]).unwrap();
    let cases: Vec<(PathBuf, &str)> = vec![
        (fifo.clone(), "FIFO"),
        (PathBuf::from("/dev/zero"), "character device"),
        (folder, "folder"),
        (loop_a, "symbolic links"),
        (huge, "more than the 16 MiB"),
        (cut, "EOF"),
    ];
    cli(&["validate", s(&d.join("missing.json"))])
        .refused("missing.json")
        .says("does not exist");
    for (path, why) in &cases {
        for cmd in [
            vec!["validate", s(path)],
            vec!["fmt", s(path)],
            vec!["render", s(path), "-o", "/nonexistent-folder/x.png"],
        ] {
            let started = Instant::now();
            let r = cli(&cmd);
            r.refused(s(path)).says(why);
            assert!(started.elapsed() < Duration::from_secs(20), "{cmd:?}");
        }
    }
    // Encodings: said by name, or where the first bad byte is.
    let encodings: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "utf16le.json",
            utf16(&meadow, true, true),
            "1:1: this file is UTF-16 (little-endian)",
        ),
        (
            "utf16be.json",
            utf16(&meadow, false, false),
            "1:1: this file is UTF-16 (big-endian)",
        ),
        (
            "utf32.json",
            [0xFF, 0xFE, 0, 0]
                .into_iter()
                .chain(meadow.chars().flat_map(|c| (c as u32).to_le_bytes()))
                .collect(),
            "1:1: this file is UTF-32 (little-endian)",
        ),
        (
            "latin1.json",
            meadow
                .replacen("Meadow", "Mead\u{e9}w", 1)
                .replace('\u{e9}', "\u{1}")
                .into_bytes()
                .into_iter()
                .map(|b| if b == 1 { 0xE9 } else { b })
                .collect(),
            "byte 0xE9 is not UTF-8",
        ),
    ];
    for (name, bytes, said) in &encodings {
        let p = d.join(name);
        std::fs::write(&p, bytes).unwrap();
        cli(&["validate", s(&p)]).refused(name).says(said);
    }
    // The Latin-1 byte is placed: the line and column of the name's é.
    let line = meadow
        .lines()
        .position(|l| l.contains("\"Meadow\""))
        .unwrap()
        + 1;
    cli(&["validate", s(&d.join("latin1.json"))]).says(&format!("latin1.json:{line}:"));
    // A UTF-8 byte order mark is allowed (JSON's RFC lets a reader ignore it).
    let bom = d.join("bom.json");
    std::fs::write(&bom, [&[0xEF, 0xBB, 0xBF][..], meadow.as_bytes()].concat()).unwrap();
    cli(&["validate", s(&bom)]).ok();

    // A FIFO as the map image: a warning, and the layout works without it.
    let mut l = example("meadow.json");
    l.world.map = Some(windloom::doc::MapBackdrop {
        image: "fifo.json".into(),
        opacity: 1.0,
        rect: None,
    });
    let with_map = d.join("with-map.json");
    windloom::io::save(&with_map, &l).unwrap();
    cli(&["validate", s(&with_map)])
        .ok()
        .says("map image")
        .says("FIFO");
    let png = d.join("map.png");
    cli(&["render", s(&with_map), "-o", s(&png), "--size", "64x64"])
        .ok()
        .says("FIFO");
    assert!(png.is_file());
}

#[cfg(unix)]
fn utf16(text: &str, le: bool, bom: bool) -> Vec<u8> {
    let units = (bom.then_some(0xFEFF))
        .into_iter()
        .chain(text.encode_utf16());
    units
        .flat_map(|u| if le { u.to_le_bytes() } else { u.to_be_bytes() })
        .collect()
}

/// Messages never echo input unbounded or raw: a 10 MB unknown key gives a short line, and
/// terminal escape sequences in keys and paths are printed escaped.
#[test]
fn messages_quote_input_bounded_and_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(meadow_path()).unwrap()).unwrap();
    v["k".repeat(10_000_000)] = 1.into();
    let big = dir.path().join("big-key.json");
    std::fs::write(&big, v.to_string()).unwrap();
    let r = cli(&["validate", s(&big)]);
    r.refused("big-key.json").says("more characters");
    assert!(r.out.len() < 4_000, "{} bytes of message", r.out.len());

    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(meadow_path()).unwrap()).unwrap();
    v["\u{1b}[2Jgone"] = 1.into();
    let esc = dir.path().join("esc\u{1b}]0;pwned\u{7}.json");
    std::fs::write(&esc, v.to_string()).unwrap();
    let r = cli(&["validate", s(&esc)]);
    assert!(
        !r.out.contains('\u{1b}') && !r.out.contains('\u{7}'),
        "{r:?}",
        r = r.out
    );
    r.says("\\u{1b}[2Jgone");
    let r = cli(&["bake", s(&esc), "--out", "/proc/nowhere", "--frames", "1"]);
    assert!(!r.err.contains('\u{1b}'), "{}", r.err);
}

/// A key written twice is refused, naming both places, and `fmt` then changes nothing.
#[test]
fn duplicate_keys_are_refused_and_fmt_loses_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(meadow_path()).unwrap().replacen(
        "\"name\": \"Meadow\"",
        "\"name\": \"Meadow\", \"name\": \"Other\"",
        1,
    );
    let p = dir.path().join("dup.json");
    std::fs::write(&p, &text).unwrap();
    let line = text.lines().position(|l| l.contains("\"Other\"")).unwrap() + 1;
    cli(&["validate", s(&p)]).refused("dup.json").says(&format!(
        "dup.json:{line}:21: name: duplicate key `name` (first at {line}:3)"
    ));
    cli(&["fmt", s(&p)]).refused("dup.json");
    assert_eq!(std::fs::read_to_string(&p).unwrap(), text);
}

/// `fmt` leaves a read-only file alone, and rewrites a file with other hard links in place,
/// so the other names see the new text.
#[cfg(unix)]
#[test]
fn fmt_respects_read_only_files_and_hard_links() {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let dir = tempfile::tempdir().unwrap();
    // A valid layout in a non-canonical form (fmt has work to do).
    let text = std::fs::read_to_string(meadow_path())
        .unwrap()
        .replace("\n  ", "\n    ");
    let ro = dir.path().join("ro.json");
    std::fs::write(&ro, &text).unwrap();
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o444)).unwrap();
    cli(&["fmt", s(&ro)]).refused("ro.json").says("read-only");
    assert_eq!(std::fs::read_to_string(&ro).unwrap(), text);

    let a = dir.path().join("a.json");
    let b = dir.path().join("b.json");
    std::fs::write(&a, &text).unwrap();
    std::fs::hard_link(&a, &b).unwrap();
    let ino = std::fs::metadata(&a).unwrap().ino();
    cli(&["fmt", s(&a)]).ok();
    let canonical = std::fs::read_to_string(meadow_path()).unwrap();
    assert_eq!(std::fs::read_to_string(&a).unwrap(), canonical);
    assert_eq!(std::fs::read_to_string(&b).unwrap(), canonical);
    assert_eq!(std::fs::metadata(&a).unwrap().ino(), ino);
    assert_eq!(std::fs::metadata(&b).unwrap().nlink(), 2);
    assert_eq!(names(dir.path()), ["a.json", "b.json", "ro.json"]);
}

/// A simulated span without bound is refused at once; one inside the bound bakes.
#[test]
fn time_without_bound_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("wind");
    let meadow = meadow_path();
    for (frames, fps) in [("2", "1e-9"), ("100000", "1"), ("2", "0.00001")] {
        let started = Instant::now();
        cli(&[
            "bake",
            s(&meadow),
            "--out",
            s(&out),
            "--frames",
            frames,
            "--fps",
            fps,
        ])
        .refused("simulated seconds");
        assert!(started.elapsed() < Duration::from_secs(20));
    }
    assert!(!out.exists());
}

/// A bake into the root of a mounted file system (a Docker volume, a bind mount) works,
/// keeps the user's files, replaces the earlier bake, and leaves nothing of its own behind;
/// a bind mount of a folder on the same file system too. A full disk and a read-only file
/// system are one-line refusals that leave the earlier bake whole.
#[cfg(target_os = "linux")]
#[test]
fn bakes_into_a_mount_root_work() {
    let dir = tempfile::tempdir().unwrap();
    let Some(m) = Mount::tmpfs(&dir.path().join("volume"), "64m") else {
        return;
    };
    let meadow = meadow_path();
    let bake = |out: &Path, frames: &str, format: &str| {
        cli(&[
            "bake",
            s(&meadow),
            "--out",
            s(out),
            "--frames",
            frames,
            "--format",
            format,
            "--grid",
            "48x32",
            "--warmup",
            "0.5",
        ])
    };
    bake(&m.0, "3", "png8").ok();
    std::fs::write(m.0.join("notes.txt"), "mine").unwrap();
    bake(&m.0, "2", "vf").ok();
    assert_eq!(
        names(&m.0),
        ["manifest.json", "notes.txt", "wind_0000.vf", "wind_0001.vf"]
    );
    assert_eq!(
        std::fs::read_to_string(m.0.join("notes.txt")).unwrap(),
        "mine"
    );
    assert!(names(dir.path()).iter().all(|n| !n.starts_with('.')));

    // A bind mount of a folder of the same file system: the same device number, and still
    // a mount point that cannot be renamed.
    let src = dir.path().join("src");
    let bind = dir.path().join("bind");
    std::fs::create_dir_all(&src).unwrap();
    std::fs::create_dir_all(&bind).unwrap();
    if Command::new("mount")
        .args(["--bind", s(&src), s(&bind)])
        .status()
        .is_ok_and(|st| st.success())
    {
        let _unmount = Mount(bind.clone());
        bake(&bind, "1", "vf").ok();
        assert_eq!(names(&src), ["manifest.json", "wind.vf"]);
    } else {
        eprintln!("SKIPPED: the bind mount (mount --bind failed)");
    }

    // A full disk: a small volume that cannot hold the bake. Refused before or while
    // writing; nothing is left on it.
    let small = Mount::tmpfs(&dir.path().join("small"), "64k").unwrap();
    let r = bake(&small.0, "2", "exr");
    r.refused(s(&small.0));
    assert!(names(&small.0).is_empty(), "{:?}", names(&small.0));

    // Read-only: the earlier bake stays whole.
    let before = names(&m.0);
    assert!(
        Command::new("mount")
            .args(["-o", "remount,ro", s(&m.0)])
            .status()
            .unwrap()
            .success()
    );
    bake(&m.0, "1", "vf").refused(s(&m.0)).says("read-only");
    assert_eq!(names(&m.0), before);
}

/// An output name as long as the file system allows (255 bytes) bakes: the staging folder's
/// name does not grow with it.
#[test]
fn a_long_output_name_bakes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("w".repeat(250));
    run(&example("meadow.json"), &out, &small(1));
    assert!(out.join("manifest.json").is_file());
    run(&example("meadow.json"), &out, &small(2));
    assert_eq!(names(dir.path()), ["w".repeat(250)]);
}

/// What the bake's numbers show goes into the manifest's notes, so a bake of nonsense does
/// not pass as a good one: the paper's vorticity factor of 50 with MacCormack advection, a
/// field far past the layout's wind, and obstacles over the whole map (a still field). A
/// fan of overlapping arrows used to add up far past each arrow (to thousands of m/s) and be
/// noted here; they now drive toward the strongest of them at no more than four arrows' rate
/// (`sim::forces::combine`), so the fan's bake stays under 1.5× its arrows' 5 m/s and says
/// nothing of it.
#[test]
fn nonsense_bakes_say_so_in_the_manifest() {
    let dir = tempfile::tempdir().unwrap();
    let opts = windloom::bake::BakeOptions {
        formats: vec![windloom::bake::Format::Raw],
        warmup: 2.0,
        frames: 1,
        fps: 10.0,
        grid: Some([48, 48]),
        ..Default::default()
    };
    // A fan: 256 arrows of 5 m/s all round one root, all overlapping.
    let mut fan = example("meadow.json");
    fan.ambient.clear();
    let root = &mut fan.trees[0].root;
    root.children.clear();
    let c = root.pos;
    for k in 0..256u32 {
        let a = k as f32 * std::f32::consts::TAU / 256.0;
        root.children.push(windloom::doc::Node {
            id: 10_000 + k,
            pos: [c[0] + 20.0 * a.cos(), c[1] + 20.0 * a.sin()],
            strength: 5.0,
            radius: 15.0,
            children: Vec::new(),
            keys: Vec::new(),
        });
    }
    let m = run(&fan, &dir.path().join("fan"), &opts);
    assert!(m.max_speed < 7.5, "{}", m.max_speed);
    assert!(
        !m.notes.iter().any(|n| n.contains("strongest push")),
        "{:?}",
        m.notes
    );

    // The paper's vorticity factor: bounded now, so it bakes sane wind and says nothing;
    // with MacCormack advection, which the confinement's limiter does not hold, the advice
    // goes into the notes.
    let mut paper = example("two-winds.json");
    paper.sim.vorticity = 50.0;
    let wind = windloom::sim::forces::reference_speed(&paper);
    let m = run(&paper, &dir.path().join("paper"), &opts);
    assert!(m.max_speed <= 1.5 * wind, "{} m/s from {wind}", m.max_speed);
    assert!(m.notes.is_empty(), "{:?}", m.notes);
    paper.sim.advection = windloom::doc::Advection::MacCormack;
    let m = run(&paper, &dir.path().join("paper-mc"), &opts);
    assert!(
        m.notes
            .iter()
            .any(|n| n.starts_with("advice: sim.vorticity")),
        "{:?}",
        m.notes
    );
    // A field far past the layout's wind is noted, one a little past it is not.
    let note = |speed: f32| windloom::bake::field_notes(&paper, speed);
    assert!(note(1.4 * wind).is_empty());
    let far = note(3.0 * wind);
    assert!(
        far.len() == 1 && far[0].contains("3.0× the strongest push"),
        "{far:?}"
    );

    let mut covered = example("meadow.json");
    covered.ambient.clear();
    let [w, d] = covered.world.size;
    let o = covered.world.origin;
    covered.obstacles = vec![windloom::doc::Obstacle {
        id: 1,
        name: "Everything".into(),
        shape: windloom::doc::Shape::Polygon {
            points: vec![
                [o[0] - 1.0, o[1] - 1.0],
                [o[0] + w + 1.0, o[1] - 1.0],
                [o[0] + w + 1.0, o[1] + d + 1.0],
                [o[0] - 1.0, o[1] + d + 1.0],
            ],
        },
        locked: false,
        hidden: false,
    }];
    let m = run(&covered, &dir.path().join("covered"), &opts);
    assert_eq!(m.max_speed, 0.0);
    assert!(m.notes.iter().any(|n| n.contains("still")), "{:?}", m.notes);
    // The CLI says the notes too.
    let p = dir.path().join("covered.json");
    windloom::io::save(&p, &covered).unwrap();
    cli(&[
        "bake",
        s(&p),
        "--out",
        s(&dir.path().join("covered-cli")),
        "--frames",
        "1",
        "--format",
        "vf",
        "--grid",
        "32x32",
    ])
    .ok()
    .says("note: the baked wind is still");
}

/// A forged `manifest.json` in a folder of the user's, listing the user's own files (same
/// names, even the sizes): the next `bake --out` into it removes none of them, because a
/// bake removes only files whose content is what the earlier bake recorded (size and CRC-32),
/// not what a manifest says. A user's file where the bake writes one of the same name is
/// refused, not replaced; and the bake's own files of an earlier bake still go.
#[test]
fn a_forged_manifest_gets_none_of_the_user_s_files_removed() {
    let dir = tempfile::tempdir().unwrap();
    let meadow = meadow_path();
    // A small bake of the meadow into `out`, in `format`.
    let bake_into = |out: &Path, format: &str| {
        cli(&[
            "bake",
            s(&meadow),
            "--out",
            s(out),
            "--format",
            format,
            "--frames",
            "1",
            "--warmup",
            "0.2",
            "--grid",
            "24x16",
        ])
    };
    let notes = b"my notes, not a bake".to_vec();
    let photo = vec![7u8; 4096];
    let entry = |name: &str, bytes: usize, crc: Option<u32>| {
        let mut e = serde_json::json!({ "name": name, "format": "png8", "bytes": bytes });
        if let Some(c) = crc {
            e["crc32"] = c.into();
        }
        e
    };
    // Without CRCs (as the first bakes wrote) and with wrong ones.
    let mut out = PathBuf::new();
    for (k, crc) in [None, Some(12345)].into_iter().enumerate() {
        out = dir.path().join(format!("mine-{k}"));
        std::fs::create_dir(&out).unwrap();
        std::fs::write(out.join("notes.txt"), &notes).unwrap();
        std::fs::write(out.join("photo.png"), &photo).unwrap();
        let forged = serde_json::json!({
            "format": "windloom-bake",
            "version": 2,
            "files": [entry("notes.txt", notes.len(), crc), entry("photo.png", photo.len(), crc)],
        });
        std::fs::write(out.join("manifest.json"), forged.to_string()).unwrap();
        bake_into(&out, "vf").ok();
        assert_eq!(std::fs::read(out.join("notes.txt")).unwrap(), notes);
        assert_eq!(std::fs::read(out.join("photo.png")).unwrap(), photo);
    }
    // The bake's own files of that bake go when the next bake writes other formats.
    let vf: Vec<String> = names(&out)
        .into_iter()
        .filter(|n| n.ends_with(".vf"))
        .collect();
    assert!(!vf.is_empty());
    bake_into(&out, "raw").ok();
    let now = names(&out);
    assert!(vf.iter().all(|n| !now.contains(n)), "{now:?}");
    assert!(now.contains(&"notes.txt".to_string()) && now.contains(&"photo.png".to_string()));
    // A user's file named as the bake's output, listed by a forged manifest: refused.
    std::fs::write(out.join("wind.f32"), b"mine too").unwrap();
    let mut forged: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("manifest.json")).unwrap()).unwrap();
    forged["files"][0]["bytes"] = 8.into();
    std::fs::write(out.join("manifest.json"), forged.to_string()).unwrap();
    bake_into(&out, "raw").refused("wind.f32");
    assert_eq!(std::fs::read(out.join("wind.f32")).unwrap(), b"mine too");
}

/// A FIFO where the earlier bake's `manifest.json` should be: `bake --out` refuses at once
/// (it waited on the FIFO for ever, deaf to SIGTERM, Ctrl-C and SIGHUP).
#[cfg(unix)]
#[test]
fn a_fifo_for_the_earlier_manifest_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bake");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("wind.f32"), b"x").unwrap();
    mkfifo(&out.join("manifest.json"));
    cli(&[
        "bake",
        s(&meadow_path()),
        "--out",
        s(&out),
        "--format",
        "raw",
        "--frames",
        "1",
    ])
    .refused("manifest.json")
    .says("FIFO");
}
