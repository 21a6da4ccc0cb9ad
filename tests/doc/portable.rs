//! Layouts carried between Windows, macOS and Linux: a layout written on Windows (`\` in its
//! image paths, CRLF line ends) opens here with its images; what Windows cannot hold (a
//! reserved name such as `CON`, a `:` in a name) is refused at save and at bake with one line
//! naming it, and nothing is written.

use super::example_path;
use std::path::Path;
use windloom::doc::{self, MaskPixels};

/// walled-garden.json as a Windows user keeps it: its images in a `maps` folder named with
/// `\`, every line ended by CRLF. Returns the layout's path.
fn windows_copy(dir: &Path) -> std::path::PathBuf {
    let layouts = example_path("walled-garden.json")
        .parent()
        .unwrap()
        .to_path_buf();
    std::fs::create_dir(dir.join("maps")).unwrap();
    let mut text = std::fs::read_to_string(layouts.join("walled-garden.json")).unwrap();
    for image in [
        "walled-garden-grass.png",
        "walled-garden-heights.png",
        "walled-garden-mask.png",
    ] {
        std::fs::copy(layouts.join(image), dir.join("maps").join(image)).unwrap();
        // "maps\\NAME" in JSON is the path maps\NAME.
        text = text.replace(&format!("\"{image}\""), &format!("\"maps\\\\{image}\""));
    }
    let path = dir.join("walled-garden.json");
    std::fs::write(&path, text.replace('\n', "\r\n")).unwrap();
    path
}

fn loaded(p: &MaskPixels) -> bool {
    matches!(p, MaskPixels::Loaded(_))
}

#[test]
fn a_layout_written_on_windows_opens_with_its_images() {
    let dir = tempfile::tempdir().unwrap();
    let path = windows_copy(dir.path());
    let layout = windloom::io::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let original = windloom::io::load(&example_path("walled-garden.json")).unwrap();
    assert!(
        loaded(&layout.world.terrain.as_ref().unwrap().pixels),
        "the heightmap"
    );
    assert!(
        loaded(&layout.grass.density_map.as_ref().unwrap().pixels),
        "the density map"
    );
    let masks: Vec<bool> = layout
        .obstacles
        .iter()
        .filter_map(|o| match &o.shape {
            doc::Shape::Mask { pixels, .. } => Some(loaded(pixels)),
            _ => None,
        })
        .collect();
    assert!(
        !masks.is_empty() && masks.iter().all(|m| *m),
        "every mask image"
    );
    // CRLF and `\` change nothing else: the same layout but for its paths.
    assert_eq!(layout.trees, original.trees);
    assert_eq!(layout.world.grid, original.world.grid);
    // Saved again, it names its images with `/`, which every platform reads.
    let saved = dir.path().join("saved.json");
    windloom::io::save(&saved, &layout).unwrap();
    let text = std::fs::read_to_string(&saved).unwrap();
    assert!(
        !text.contains("maps\\\\"),
        "no backslash paths written back"
    );
    assert!(windloom::io::load(&saved).is_ok());
}

#[test]
fn a_crlf_layout_s_errors_keep_their_lines() {
    // The tree's name made a number, on the line it is on; the file's lines ended by CRLF.
    let text = super::small_text();
    let line = 1 + text
        .lines()
        .position(|l| l.contains("\"name\": \"a\""))
        .unwrap();
    let broken = text
        .replace("\"name\": \"a\"", "\"name\": 5")
        .replace('\n', "\r\n");
    assert!(
        doc::parse(&text.replace('\n', "\r\n")).is_ok(),
        "CRLF alone parses"
    );
    let errs: Vec<String> = match doc::parse(&broken) {
        Ok(_) => panic!("a number for a name parsed"),
        Err(d) => d.0.iter().map(ToString::to_string).collect(),
    };
    assert!(
        errs.iter().any(|e| e.starts_with(&format!("{line}:"))),
        "line {line}: {errs:?}"
    );
}

#[test]
fn names_windows_cannot_hold_are_refused_at_save_with_nothing_written() {
    let dir = tempfile::tempdir().unwrap();
    let layout = windloom::io::load(&example_path("meadow.json")).unwrap();
    for name in ["CON.json", "aux", "level?.json", "level.json."] {
        let path = dir.path().join(name);
        let e = windloom::io::save(&path, &layout)
            .expect_err(name)
            .to_string();
        assert!(
            e.contains("file name") && e.contains("Windows"),
            "{name}: {e}"
        );
        assert!(!path.exists(), "{name} written");
    }
    // A layout naming an image Windows cannot hold: the field and the part.
    let mut layout = windloom::io::load(&example_path("walled-garden.json")).unwrap();
    layout.world.terrain.as_mut().unwrap().heightmap = "maps/nul.png".into();
    let path = dir.path().join("garden.json");
    let e = windloom::io::save(&path, &layout).unwrap_err().to_string();
    assert!(
        e.contains("world.terrain.heightmap") && e.contains("\"nul.png\""),
        "{e}"
    );
    assert!(!path.exists());
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "nothing left behind"
    );
}

#[test]
fn names_windows_cannot_hold_are_refused_at_bake() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("COM1");
    let run = |layout: &str, out: &Path| {
        std::process::Command::new(env!("CARGO_BIN_EXE_windloom"))
            .args(["bake", layout, "--out"])
            .arg(out)
            .args(["--grid", "24x16", "--warmup", "0", "--format", "raw"])
            .output()
            .unwrap()
    };
    let meadow = example_path("meadow.json");
    let o = run(meadow.to_str().unwrap(), &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("COM1") && err.contains("reserves"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    assert!(!out.exists());
    // A layout naming a reserved image name (it exists here; Windows could not hold it).
    let garden = windows_copy(dir.path());
    std::fs::rename(
        dir.path().join("maps/walled-garden-mask.png"),
        dir.path().join("maps/prn.png"),
    )
    .unwrap();
    let text = std::fs::read_to_string(&garden)
        .unwrap()
        .replace("maps\\\\walled-garden-mask.png", "maps\\\\prn.png");
    std::fs::write(&garden, text).unwrap();
    let out = dir.path().join("bake");
    let o = run(garden.to_str().unwrap(), &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("\"prn.png\"") && err.contains("obstacles["),
        "{err}"
    );
    assert!(!out.exists());
}
