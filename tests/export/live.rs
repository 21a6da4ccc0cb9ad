//! The live link: `bake --watch` bakes again on each save of the layout, each bake whole and
//! one higher in `sequence`; an engine polling the folder by path, as the engine scripts do,
//! never reads a partial or mixed bake.

use super::*;
use serde_json::Value;
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// One look at the folder as an engine script takes it, by path: the manifest, every file
/// it lists, the manifest again. `None` when a bake landed in between (the script then looks
/// again); else the sequence, after checking the files belong to that manifest's bake.
fn engine_look(out: &Path) -> Option<u64> {
    let read_manifest = || -> Option<Value> {
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).ok()?).ok()
    };
    let m = read_manifest()?;
    let files: Vec<(String, Vec<u8>)> = m["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            let name = f["name"].as_str().unwrap().to_string();
            let bytes = std::fs::read(out.join(&name)).unwrap_or_default();
            (name, bytes)
        })
        .collect();
    let again = read_manifest()?;
    if again["sequence"] != m["sequence"] {
        return None;
    }
    assert_eq!(again, m, "one sequence, one manifest");
    // The same manifest before and after: every file is there, whole, of this bake.
    for ((name, bytes), entry) in files.iter().zip(m["files"].as_array().unwrap()) {
        assert_eq!(
            bytes.len() as u64,
            entry["bytes"].as_u64().unwrap(),
            "{name} of sequence {}",
            m["sequence"]
        );
    }
    let raw = &files.iter().find(|(n, _)| n == "wind.f32").unwrap().1;
    let max = f32s(raw)
        .chunks_exact(2)
        .map(|v| v[0].hypot(v[1]))
        .fold(0.0f32, f32::max);
    assert_eq!(
        max,
        m["max_speed"].as_f64().unwrap() as f32,
        "wind.f32 is of this manifest's bake"
    );
    Some(m["sequence"].as_u64().unwrap())
}

/// The watching process, killed if the test fails before it stops it.
struct Watcher(std::process::Child);

impl Drop for Watcher {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn watch_rebakes_on_each_save_and_a_polling_engine_sees_whole_bakes() {
    let dir = tempfile::tempdir().unwrap();
    let (file, out) = (dir.path().join("level.json"), dir.path().join("wind"));
    let mut layout = example("two-winds.json");
    windloom::io::save(&file, &layout).unwrap();
    let mut watcher = Watcher(
        Command::new(env!("CARGO_BIN_EXE_windloom"))
            .args([
                "bake",
                file.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ])
            .args(["--format", "raw", "--format", "vf", "--format", "png8"])
            .args([
                "--grid", "40x30", "--warmup", "0.3", "--frames", "3", "--watch",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    let child = &mut watcher.0;
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let first = lines.next().unwrap().unwrap();
    assert!(first.contains("sequence 1"), "{first}");
    let watching = lines.next().unwrap().unwrap();
    assert!(watching.starts_with("watching "), "{watching}");
    let saves = 8;
    let stop = AtomicBool::new(false);
    let seen = std::thread::scope(|s| {
        let engine = s.spawn(|| {
            let mut seen: Vec<u64> = Vec::new();
            while !stop.load(Ordering::SeqCst) {
                if let Some(q) = engine_look(&out) {
                    assert!(seen.last().is_none_or(|&l| q >= l), "sequence went back");
                    seen.push(q);
                }
            }
            seen
        });
        for save in 0..saves {
            // A designer's save: the first arrow a little stronger each time.
            layout.trees[0].root.children[0].strength += 0.5;
            windloom::io::save(&file, &layout).unwrap();
            let want = save as u64 + 2;
            let line = lines.next().unwrap().unwrap();
            assert!(line.contains(&format!("sequence {want}")), "{line}");
        }
        stop.store(true, Ordering::SeqCst);
        engine.join().unwrap()
    });
    // A broken save is reported and the last bake stays.
    std::fs::write(&file, "{ not json").unwrap();
    std::thread::sleep(Duration::from_millis(800));
    assert_eq!(engine_look(&out), Some(saves as u64 + 1));
    // Ctrl-C ends the watch.
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    let deadline = Instant::now() + Duration::from_secs(30);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(Instant::now() < deadline, "the watch did not stop");
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert_eq!(status.code(), Some(0), "{err}");
    assert!(
        err.contains("the last bake stays, watching for the next save"),
        "{err}"
    );
    let distinct: BTreeSet<u64> = seen.iter().copied().collect();
    assert!(
        seen.len() > 20 && distinct.len() >= 3,
        "the engine looked {} times and saw sequences {distinct:?}",
        seen.len()
    );
}
