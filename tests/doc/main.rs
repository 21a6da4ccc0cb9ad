//! The layout document: examples, validation errors, schema, atomic saves, edits and undo, CLI.
#![allow(
    clippy::unwrap_used,
    reason = "a test that unwraps fails there, which is what a test is for"
)]

use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::process::Command;
use windloom::doc::{self, Edit, History, Layout, Node, Shape};

const EXAMPLES: &[&str] = &[
    "meadow.json",
    "two-winds.json",
    "branching.json",
    "obstacles.json",
    "breeze-fft.json",
    "walled-garden.json",
];

fn example_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("layouts")
        .join(name)
}

fn example(name: &str) -> Layout {
    windloom::io::load(&example_path(name)).unwrap_or_else(|e| panic!("{e}"))
}

fn errors(text: &str) -> Vec<String> {
    match doc::parse(text) {
        Ok(_) => panic!("expected errors for:\n{text}"),
        Err(d) => d.0.iter().map(ToString::to_string).collect(),
    }
}

fn has(errors: &[String], needle: &str) {
    assert!(
        errors.iter().any(|e| e.contains(needle)),
        "no error contains {needle:?}; got:\n{}",
        errors.join("\n")
    );
}

/// A small valid layout in canonical form, as text, to corrupt in tests.
fn small_text() -> String {
    let mut l = Layout::new("t", [50.0, 40.0], [50, 40]);
    let mut root = Node::new(1, [5.0, 20.0], 10.0, 3.0);
    let mut child = Node::new(2, [20.0, 20.0], 25.0, 4.0);
    child.children.push(Node::new(3, [35.0, 25.0], 20.0, 4.0));
    root.children.push(child);
    l.trees.push(doc::Tree {
        id: 10,
        name: "a".into(),
        enabled: true,
        window: doc::TimeWindow::Always,
        emission: doc::Emission::Continuous,
        propagation_speed: 20.0,
        root,
        locked: false,
        hidden: false,
        keys: Vec::new(),
    });
    doc::to_json(&l)
}

#[test]
fn examples_load_validate_and_are_canonical() {
    for name in EXAMPLES {
        let text = std::fs::read_to_string(example_path(name)).unwrap();
        let layout = example(name);
        assert!(doc::validate(&layout).is_empty(), "{name} has issues");
        // Saving is stable: the committed file is exactly what windloom writes…
        assert_eq!(
            doc::to_json(&layout),
            text,
            "{name} is not in canonical form"
        );
        // …and reading it back gives the same document.
        assert_eq!(
            doc::parse(&doc::to_json(&layout)).unwrap(),
            layout,
            "{name}"
        );
    }
}

#[test]
fn examples_express_what_they_are_named_for() {
    let two = example("two-winds.json");
    assert_eq!(two.trees.len(), 2);
    let dir = |t: &doc::Tree| t.root.children[0].pos[0] - t.root.pos[0];
    assert!(
        dir(&two.trees[0]) * dir(&two.trees[1]) < 0.0,
        "winds must oppose"
    );
    let branching = example("branching.json");
    let branches = branching.trees[0]
        .root
        .iter()
        .filter(|n| n.children.len() > 1)
        .count();
    assert!(branches >= 1, "branching.json must branch");
    assert!(
        branching.trees[0].root.iter().any(|n| n.children.len() == 1
            && n.id != branching.trees[0].root.id
            && !n.children[0].children.is_empty()),
        "branching.json must chain"
    );
    let obstacles = example("obstacles.json");
    assert!(obstacles.trees.len() >= 2 && obstacles.obstacles.len() >= 3);
    assert!(
        obstacles
            .obstacles
            .iter()
            .any(|o| matches!(o.shape, Shape::Polygon { .. }))
    );
    let fft = example("breeze-fft.json");
    assert!(fft.trees.is_empty());
    assert!(
        fft.ambient
            .iter()
            .all(|a| matches!(a.kind, doc::AmbientKind::Fft { .. }))
    );
}

#[test]
fn default_layout_is_the_bundled_meadow() {
    assert_eq!(doc::default_layout(), example("meadow.json"));
}

#[test]
fn syntax_error_has_line_and_column() {
    let text = "{\n  \"format\": \"windloom-layout\",\n  \"version\": 1,,\n}";
    let e = errors(text);
    assert_eq!(e.len(), 1);
    assert!(e[0].starts_with("3:16: "), "{}", e[0]);
}

/// A text that is not JSON still gets the path of the value being read where it breaks, so
/// a NaN or an infinity written by a script (which JSON cannot hold) names its field.
#[test]
fn syntax_errors_name_the_field_being_read() {
    let nan = small_text().replacen("\"radius\": 4.0", "\"radius\": NaN", 1);
    let e = errors(&nan);
    assert_eq!(e.len(), 1, "{e:?}");
    let line = nan.lines().position(|l| l.contains("NaN")).unwrap() + 1;
    assert!(e[0].starts_with(&format!("{line}:")), "{}", e[0]);
    assert!(
        e[0].contains("trees[0].root.children[0].radius: ")
            && e[0].contains("NaN and infinities are not numbers in JSON"),
        "{}",
        e[0]
    );
    let inf = small_text().replacen("\"strength\": 25.0", "\"strength\": -Infinity", 1);
    let e = errors(&inf);
    assert!(
        e[0].contains("trees[0].root.children[0].strength: "),
        "{}",
        e[0]
    );
    assert!(e[0].contains("not numbers in JSON"), "{}", e[0]);
    // Keys with escapes, nested arrays, and an object left open at the end of the file.
    for (text, path) in [
        ("{\"a\\u0062\": [1, {\"k\": tru}]}", "ab[1].k: "),
        ("{\"world\": {\"size\": [10 10]}}", "world.size[0]: "),
        ("{\"world\": {\"size\": [10, 10],\n", "world: "),
        ("{\"x\": \"}]\", \"y\": [[1], [2, ]]}", "y[1][1]: "),
    ] {
        let e = errors(text);
        assert!(e[0].contains(path), "{text}: {}", e[0]);
        assert!(!e[0].contains("NaN"), "{}", e[0]);
    }
}

#[test]
fn file_errors_name_the_file_line_and_path() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bad.json");
    let text = small_text().replace("\"radius\": 4.0", "\"radius\": -1.0");
    std::fs::write(&p, &text).unwrap();
    let msg = windloom::io::load(&p).unwrap_err().to_string();
    let first = msg.lines().next().unwrap();
    // The value -1.0 of the first child's radius.
    let line = text
        .lines()
        .position(|l| l.contains("-1.0"))
        .map(|i| i + 1)
        .unwrap();
    let want = format!("{}:{line}:", p.display());
    assert!(first.starts_with(&want), "{first}");
    assert!(
        first.ends_with("trees[0].root.children[0].radius: must be > 0, got -1"),
        "{first}"
    );
    // Both bad radii are reported, not only the first.
    assert_eq!(msg.lines().count(), 2, "{msg}");
}

#[test]
fn unknown_fields_suggest_the_nearest_name_and_all_are_reported() {
    let text = small_text()
        .replacen("\"strength\": 25.0", "\"strenght\": 25.0", 1)
        .replacen("\"name\": \"t\"", "\"name\": \"t\", \"colour\": 3", 1)
        .replacen(
            "\"propagation_speed\": 20.0",
            "\"propagation_speed\": -2.0",
            1,
        );
    let e = errors(&text);
    has(
        &e,
        "trees[0].root.children[0].strenght: unknown field `strenght`, did you mean `strength`?",
    );
    has(&e, "colour: unknown field `colour`, expected one of:");
    // A value error elsewhere in the same file is reported in the same run.
    has(&e, "trees[0].propagation_speed: must be > 0, got -2");
}

#[test]
fn unknown_fields_inside_tagged_variants_are_found() {
    let text = small_text().replacen(
        "\"kind\": \"always\"",
        "\"kind\": \"always\", \"start\": 1",
        1,
    );
    has(
        &errors(&text),
        "trees[0].window.start: unknown field `start`",
    );
}

#[test]
fn non_finite_numbers_are_rejected() {
    // JSON has no NaN literal: a syntax error with its position.
    let nan = small_text().replacen("\"strength\": 25.0", "\"strength\": NaN", 1);
    let e = errors(&nan);
    assert_eq!(e.len(), 1);
    // A number too large for f32 becomes infinite: rejected by name.
    let inf = small_text().replacen("\"strength\": 25.0", "\"strength\": 1e39", 1);
    has(
        &errors(&inf),
        "trees[0].root.children[0].strength: must be a finite number, got inf",
    );
}

#[test]
fn duplicate_node_ids_are_rejected() {
    let text = small_text().replacen("\"id\": 3", "\"id\": 2", 1);
    has(
        &errors(&text),
        "trees[0].root.children[0].children[0].id: duplicate node id 2 (already used by trees[0].root.children[0])",
    );
}

#[test]
fn versions_newer_and_unknown_are_rejected() {
    let newer = small_text().replacen("\"version\": 1", "\"version\": 7", 1);
    let e = errors(&newer);
    has(&e, "version: version 7 was made by a newer windloom");
    assert!(e[0].starts_with("3:14: "), "{}", e[0]);
    let zero = small_text().replacen("\"version\": 1", "\"version\": 0", 1);
    has(&errors(&zero), "version: version 0 does not exist");
    let other = small_text().replacen("windloom-layout", "something-else", 1);
    has(&errors(&other), "this is not a windloom layout");
}

#[test]
fn absurd_sizes_are_rejected_with_the_budget() {
    let text = small_text().replacen("\"size\": [\n      50.0", "\"size\": [\n      -5.0", 1);
    has(&errors(&text), "world.size[0]: must be > 0, got -5");
    let huge = small_text().replacen(
        "\"grid\": [\n      50,\n      40",
        "\"grid\": [\n      16000,\n      16000",
        1,
    );
    let e = errors(&huge);
    has(
        &e,
        "world.grid: 16000x16000 needs 24414 MiB of solver memory, over the budget of 2048 MiB",
    );
    let axis = small_text().replacen("\"grid\": [\n      50", "\"grid\": [\n      3", 1);
    has(
        &errors(&axis),
        "world.grid[0]: must be between 8 and 16384 cells, got 3",
    );
}

#[test]
fn pressure_solve_settings_are_checked() {
    let cycles = small_text().replacen("\"pressure_cycles\": 2", "\"pressure_cycles\": 0", 1);
    has(
        &errors(&cycles),
        "sim.pressure_cycles: must be between 1 and 20, got 0",
    );
    let unknown = small_text().replacen(
        "\"pressure\": \"multigrid\"",
        "\"pressure\": \"conjugate\"",
        1,
    );
    has(
        &errors(&unknown),
        "sim.pressure: unknown variant `conjugate`",
    );
    // 5000² fits the budget with Jacobi, not with multigrid's hierarchy (the default) on top.
    let big_mg = small_text().replacen(
        "\"grid\": [\n      50,\n      40",
        "\"grid\": [\n      5000,\n      5000",
        1,
    );
    let big = big_mg.replacen("\"pressure\": \"multigrid\"", "\"pressure\": \"jacobi\"", 1);
    assert!(
        doc::parse(&big).is_ok(),
        "5000x5000 with Jacobi fits the budget"
    );
    has(
        &errors(&big_mg),
        "world.grid: 5000x5000 needs 2384 MiB of solver memory, over the budget of 2048 MiB",
    );
}

#[test]
fn wrong_types_name_the_field() {
    let text = small_text().replacen("\"strength\": 25.0", "\"strength\": \"strong\"", 1);
    has(
        &errors(&text),
        "trees[0].root.children[0].strength: invalid type: string \"strong\"",
    );
}

#[test]
fn schema_file_is_up_to_date() {
    let want = serde_json::to_string_pretty(&doc::schema()).unwrap() + "\n";
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/layout.schema.json");
    if std::env::var_os("UPDATE_SCHEMA").is_some() {
        std::fs::write(&path, &want).unwrap();
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "docs/layout.schema.json is out of date: run `UPDATE_SCHEMA=1 cargo test --test doc schema`"
    );
}

/// `windloom NEW.json` (the editor on a file not there yet, in a folder that is) starts a new
/// layout named after the file, as File → New does, and writes nothing until Save; a file
/// that is there loads, and a missing folder or a bad file is the error `load` gives.
#[test]
fn the_editor_s_file_may_be_new_but_not_its_folder() {
    let dir = tempfile::tempdir().unwrap();
    let new = dir.path().join("my-level.json");
    let (layout, is_new) = windloom::io::load_or_new(&new).unwrap();
    assert!(is_new);
    assert_eq!(layout, Layout::untitled("my-level"));
    assert!(layout.trees.is_empty() && layout.world.grid == [200, 200]);
    assert!(!new.exists(), "nothing written before Save");
    windloom::io::save(&new, &example("branching.json")).unwrap();
    assert_eq!(
        windloom::io::load_or_new(&new).unwrap(),
        (example("branching.json"), false)
    );
    let e = windloom::io::load_or_new(&dir.path().join("no-folder/x.json")).unwrap_err();
    assert!(
        matches!(&e, windloom::io::LoadError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound),
        "{e}"
    );
    std::fs::write(&new, "{").unwrap();
    assert!(matches!(
        windloom::io::load_or_new(&new),
        Err(windloom::io::LoadError::Invalid { .. })
    ));
}

#[test]
fn atomic_save_replaces_whole_files_and_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("level.json");
    let layout = example("branching.json");
    windloom::io::save(&p, &layout).unwrap();
    assert_eq!(windloom::io::load(&p).unwrap(), layout);
    // Saving onto a directory fails: the directory and the earlier file stay as they were,
    // and no temporary file is left in the folder.
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    assert!(windloom::io::save(&sub, &layout).is_err());
    assert!(sub.is_dir());
    // A missing folder is an error too, not a partial write, and the message names the
    // folder (not the temporary file the save would have written first).
    let missing = dir.path().join("missing");
    let e = windloom::io::save(&missing.join("x.json"), &layout).unwrap_err();
    assert_eq!(e.kind(), std::io::ErrorKind::NotFound);
    let msg = e.to_string();
    assert!(
        msg.contains(&format!("{} does not exist", missing.display()))
            && !msg.contains(".windloom-"),
        "{msg}"
    );
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
    assert_eq!(windloom::io::load(&p).unwrap(), layout);
}

/// A picked file is stored relative to the layout's folder when inside it (with `/`), as it
/// is when not.
#[test]
fn picked_paths_are_stored_relative_to_the_layout() {
    use windloom::io::{layout_base, relative_to};
    let dir = tempfile::tempdir().unwrap();
    let base = layout_base(Some(&dir.path().join("level.json")));
    assert_eq!(base, dir.path());
    let inside = dir.path().join("maps").join("top.png");
    assert_eq!(relative_to(&inside, &base), "maps/top.png");
    let outside = std::path::Path::new("/elsewhere/top.png");
    assert_eq!(relative_to(outside, &base), "/elsewhere/top.png");
    // A layout never saved: paths are relative to the working folder, a file there stored
    // by its name and one elsewhere as it is (not "//elsewhere/top.png").
    assert_eq!(layout_base(None), std::path::Path::new("."));
    let here = std::env::current_dir().unwrap().join("top.png");
    assert_eq!(relative_to(&here, &layout_base(None)), "top.png");
    let tmp = std::env::temp_dir()
        .join("windloom-nowhere")
        .join("top.png");
    if !tmp.starts_with(std::env::current_dir().unwrap()) {
        assert_eq!(
            relative_to(&tmp, &layout_base(None)),
            tmp.display().to_string()
        );
    }
}

#[test]
fn failed_edit_leaves_document_untouched() {
    let mut l = example("branching.json");
    let before = doc::to_json(&l);
    let mut h = History::new();
    let bad = Edit::SetNode {
        id: l.trees[0].root.children[0].id,
        strength: 10.0,
        radius: -3.0,
    };
    assert!(h.apply(&mut l, bad).is_err());
    assert!(h.apply(&mut l, Edit::RemoveNode { id: 99999 }).is_err());
    let root = l.trees[0].root.id;
    assert!(h.apply(&mut l, Edit::RemoveNode { id: root }).is_err());
    assert_eq!(doc::to_json(&l), before);
    assert!(!h.can_undo());
}

#[test]
fn a_gesture_is_one_undo_step() {
    let mut l = example("meadow.json");
    let before = doc::to_json(&l);
    let id = l.trees[0].root.children[0].id;
    let mut h = History::new();
    for i in 0..10 {
        h.apply_merged(
            &mut l,
            Edit::SetNode {
                id,
                strength: 5.0 + i as f32,
                radius: 5.0,
            },
            42,
        )
        .unwrap();
    }
    h.end_gesture();
    assert_eq!(l.trees[0].root.children[0].strength, 14.0);
    assert!(h.undo(&mut l));
    assert_eq!(doc::to_json(&l), before);
    assert!(!h.can_undo());
    assert!(h.redo(&mut l));
    assert_eq!(l.trees[0].root.children[0].strength, 14.0);
}

/// The Edit menu names what Undo and Redo would do to the document: the step as the user
/// took it ("Undo Add obstacle", "Redo Add obstacle"), not the edit that reverses it (it
/// read "Undo Delete obstacle" after adding a rock, and "Undo Delete node" after drawing an
/// arrow).
#[test]
fn undo_and_redo_are_named_after_the_step() {
    let mut l = example("meadow.json");
    let mut h = History::new();
    assert_eq!((h.undo_label(), h.redo_label()), (None, None));
    let rock = doc::Obstacle {
        id: 77,
        name: "Rock".into(),
        shape: Shape::Circle {
            center: [10.0, 10.0],
            radius: 2.0,
        },
        locked: false,
        hidden: false,
    };
    let index = l.obstacles.len();
    let add = Edit::AddObstacle {
        index,
        obstacle: rock,
    };
    h.apply(&mut l, add).unwrap();
    assert_eq!(h.undo_label(), Some("Add obstacle"));
    let id = l.trees[0].root.children[0].id;
    for strength in [6.0, 7.0] {
        let e = Edit::SetNode {
            id,
            strength,
            radius: 5.0,
        };
        h.apply_merged(&mut l, e, 7).unwrap();
    }
    assert_eq!(h.undo_label(), Some("Change node"));
    assert!(h.undo(&mut l));
    assert_eq!(
        (h.undo_label(), h.redo_label()),
        (Some("Add obstacle"), Some("Change node"))
    );
    assert!(h.undo(&mut l));
    assert_eq!(
        (h.undo_label(), h.redo_label()),
        (None, Some("Add obstacle"))
    );
    assert!(h.redo(&mut l));
    assert_eq!(h.undo_label(), Some("Add obstacle"));
    h.apply(&mut l, Edit::RemoveNode { id }).unwrap();
    assert_eq!(h.undo_label(), Some("Delete node"));
    // A batch is named after what it does: a deletion of several kinds of thing, or the
    // shared name of its edits.
    let tree = l.trees[0].id;
    let both = Edit::Batch(vec![
        Edit::RemoveObstacle { id: 77 },
        Edit::RemoveTree { id: tree },
    ]);
    h.apply(&mut l, both).unwrap();
    assert_eq!(h.undo_label(), Some("Delete selection"));
    assert!(h.undo(&mut l));
    assert_eq!(h.redo_label(), Some("Delete selection"));
    let props = doc::TreeProps::of(&l.trees[0]);
    let same = Edit::Batch(vec![Edit::SetTreeProps { id: tree, props }]);
    h.apply(&mut l, same).unwrap();
    assert_eq!(h.undo_label(), Some("Change tree"));
}

/// A random user action, resolved against the current document when applied.
#[derive(Debug, Clone)]
enum Op {
    AddChild {
        node: usize,
        dx: f32,
        dz: f32,
    },
    RemoveNode {
        node: usize,
    },
    MoveNode {
        node: usize,
        x: f32,
        z: f32,
    },
    SetNode {
        node: usize,
        strength: f32,
        radius: f32,
    },
    AddTree {
        x: f32,
        z: f32,
    },
    RemoveTree {
        tree: usize,
    },
    ToggleTree {
        tree: usize,
    },
    AddCircle {
        x: f32,
        z: f32,
        r: f32,
    },
    RemoveObstacle {
        obstacle: usize,
    },
    SetVorticity {
        v: f32,
    },
    Batch {
        a: usize,
        b: usize,
    },
}

fn op() -> impl Strategy<Value = Op> {
    let n = 0usize..64;
    let c = -200.0f32..200.0;
    prop_oneof![
        (n.clone(), -20.0f32..20.0, -20.0f32..20.0).prop_map(|(node, dx, dz)| Op::AddChild {
            node,
            dx,
            dz
        }),
        n.clone().prop_map(|node| Op::RemoveNode { node }),
        (n.clone(), c.clone(), c.clone()).prop_map(|(node, x, z)| Op::MoveNode { node, x, z }),
        (n.clone(), -10.0f32..200.0, -2.0f32..30.0).prop_map(|(node, strength, radius)| {
            Op::SetNode {
                node,
                strength,
                radius,
            }
        }),
        (c.clone(), c.clone()).prop_map(|(x, z)| Op::AddTree { x, z }),
        n.clone().prop_map(|tree| Op::RemoveTree { tree }),
        n.clone().prop_map(|tree| Op::ToggleTree { tree }),
        (c.clone(), c, -1.0f32..10.0).prop_map(|(x, z, r)| Op::AddCircle { x, z, r }),
        n.clone()
            .prop_map(|obstacle| Op::RemoveObstacle { obstacle }),
        (-5.0f32..80.0).prop_map(|v| Op::SetVorticity { v }),
        (n.clone(), n).prop_map(|(a, b)| Op::Batch { a, b }),
    ]
}

fn to_edit(l: &Layout, op: &Op) -> Option<Edit> {
    let nodes: Vec<&Node> = l.nodes().map(|(_, n)| n).collect();
    let pick_node = |i: usize| (!nodes.is_empty()).then(|| nodes[i % nodes.len()]);
    let id = l.next_id();
    Some(match *op {
        Op::AddChild { node, dx, dz } => {
            let p = pick_node(node)?;
            Edit::AddNode {
                parent: p.id,
                index: p.children.len(),
                node: Node::new(id, [p.pos[0] + dx, p.pos[1] + dz], 20.0, 4.0),
            }
        }
        Op::RemoveNode { node } => Edit::RemoveNode {
            id: pick_node(node)?.id,
        },
        Op::MoveNode { node, x, z } => Edit::MoveNode {
            id: pick_node(node)?.id,
            pos: [x, z],
        },
        Op::SetNode {
            node,
            strength,
            radius,
        } => Edit::SetNode {
            id: pick_node(node)?.id,
            strength,
            radius,
        },
        Op::AddTree { x, z } => Edit::AddTree {
            index: l.trees.len(),
            tree: doc::Tree {
                id,
                name: format!("tree {id}"),
                enabled: true,
                window: doc::TimeWindow::Always,
                emission: doc::Emission::Continuous,
                propagation_speed: 15.0,
                root: Node::new(id + 1, [x, z], 20.0, 5.0),
                locked: false,
                hidden: false,
                keys: Vec::new(),
            },
        },
        Op::RemoveTree { tree } => Edit::RemoveTree {
            id: l.trees.get(tree % l.trees.len().max(1))?.id,
        },
        Op::ToggleTree { tree } => {
            let t = l.trees.get(tree % l.trees.len().max(1))?;
            let mut props = doc::TreeProps::of(t);
            props.enabled = !props.enabled;
            Edit::SetTreeProps { id: t.id, props }
        }
        Op::AddCircle { x, z, r } => Edit::AddObstacle {
            index: 0,
            obstacle: doc::Obstacle {
                id,
                name: "rock".into(),
                shape: Shape::Circle {
                    center: [x, z],
                    radius: r,
                },
                locked: false,
                hidden: false,
            },
        },
        Op::RemoveObstacle { obstacle } => Edit::RemoveObstacle {
            id: l.obstacles.get(obstacle % l.obstacles.len().max(1))?.id,
        },
        Op::SetVorticity { v } => {
            let mut sim = l.sim;
            sim.vorticity = v;
            Edit::SetSim(sim)
        }
        Op::Batch { a, b } => Edit::Batch(vec![
            to_edit(
                l,
                &Op::MoveNode {
                    node: a,
                    x: 1.0,
                    z: 2.0,
                },
            )?,
            to_edit(l, &Op::RemoveNode { node: b })?,
        ]),
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Any sequence of edits, undone, gives back the original bytes; redone, the final bytes.
    #[test]
    fn undo_all_restores_the_document_byte_for_byte(ops in prop::collection::vec(op(), 1..40)) {
        let mut l = example("obstacles.json");
        let original = doc::to_json(&l);
        let mut h = History::new();
        for op in &ops {
            let Some(edit) = to_edit(&l, op) else { continue };
            let before = doc::to_json(&l);
            if h.apply(&mut l, edit).is_err() {
                prop_assert_eq!(&doc::to_json(&l), &before, "a failed edit changed the document");
            }
            prop_assert!(doc::validate(&l).is_empty(), "an edit made the document invalid");
        }
        let edited = doc::to_json(&l);
        while h.undo(&mut l) {}
        prop_assert_eq!(&doc::to_json(&l), &original);
        while h.redo(&mut l) {}
        prop_assert_eq!(&doc::to_json(&l), &edited);
    }
}

fn windloom(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_windloom"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn cli_validate_reports_every_file_and_fails_on_any_error() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.json");
    std::fs::write(
        &bad,
        small_text().replacen("\"radius\": 3.0", "\"radius\": 0.0", 1),
    )
    .unwrap();
    let good = example_path("meadow.json");
    let (code, out, _) = windloom(&["validate", good.to_str().unwrap(), bad.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains(&format!("{}: ok", good.display())), "{out}");
    assert!(
        out.contains("trees[0].root.radius: must be > 0, got 0"),
        "{out}"
    );
    let all: Vec<String> = EXAMPLES
        .iter()
        .map(|e| example_path(e).to_string_lossy().into_owned())
        .collect();
    let mut args = vec!["validate"];
    args.extend(all.iter().map(String::as_str));
    let (code, out, _) = windloom(&args);
    assert_eq!(code, 0, "{out}");
    assert_eq!(
        out.lines().filter(|l| l.ends_with(": ok")).count(),
        EXAMPLES.len()
    );
    let (code, _, err) = windloom(&["validate", "/nonexistent/x.json"]);
    assert_eq!(code, 1);
    let _ = err;
}

/// Valid settings known to make bad wind are named, not refused: confinement above 2 with
/// MacCormack advection, which the bounded confinement's limiter does not hold (with
/// semi-Lagrangian advection every ε is held, and advised nothing). The bundled examples
/// draw no advice; `validate` prints it after "ok"
/// and still exits 0, and `bake` says it on stderr and bakes.
#[test]
fn settings_that_run_away_are_advised_against_not_refused() {
    for name in EXAMPLES {
        assert!(doc::advise(&example(name)).is_empty(), "{name}");
    }
    let mut l = example("obstacles.json");
    let advice = |l: &Layout, vorticity: f32, advection: doc::Advection| {
        let mut l = l.clone();
        l.sim.vorticity = vorticity;
        l.sim.advection = advection;
        assert!(doc::validate(&l).is_empty(), "still valid");
        doc::advise(&l)
    };
    use doc::Advection::{MacCormack, SemiLagrangian};
    assert!(advice(&l, doc::VORTICITY_MACCORMACK_ADVISED, MacCormack).is_empty());
    let a = advice(&l, 3.0, MacCormack);
    assert_eq!(a.len(), 1, "{a:?}");
    assert_eq!(a[0].path, "sim.vorticity");
    assert!(
        a[0].message.starts_with("3 with MacCormack") && a[0].message.contains("2 or below"),
        "{}",
        a[0]
    );
    // Semi-Lagrangian advection is held by the bounded confinement at every ε.
    for eps in [2.0, 10.0, 1000.0] {
        assert!(advice(&l, eps, SemiLagrangian).is_empty(), "ε {eps}");
    }

    l.sim.vorticity = 3.0;
    l.sim.advection = MacCormack;
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("mc.json");
    std::fs::write(&f, doc::to_json(&l)).unwrap();
    let (code, out, _) = windloom(&["validate", f.to_str().unwrap()]);
    assert_eq!(code, 0, "advice is not an error: {out}");
    assert!(
        out.starts_with(&format!(
            "{}: ok; warning: sim.vorticity: 3 with MacCormack",
            f.display()
        )),
        "{out}"
    );
    let out_dir = dir.path().join("bake");
    let (code, _, err) = windloom(&[
        "bake",
        f.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--format",
        "raw",
        "--warmup",
        "0.1",
        "--frames",
        "1",
        "--grid",
        "32x32",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("warning: ") && err.contains("sim.vorticity: 3 with MacCormack"),
        "{err}"
    );
    assert!(out_dir.join("manifest.json").exists(), "baked anyway");
}

#[test]
fn cli_schema_and_help() {
    let (code, out, _) = windloom(&["schema"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v, doc::schema());
    let (code, out, _) = windloom(&["--help"]);
    assert_eq!(code, 0);
    for cmd in [
        "validate",
        "schema",
        "Examples:",
        "windloom validate layouts/*.json",
    ] {
        assert!(out.contains(cmd), "--help lacks {cmd}:\n{out}");
    }
    let (_, out, _) = windloom(&["validate", "--help"]);
    assert!(out.contains("Example: windloom validate"), "{out}");
    // The editor's view: named in the help, a wrong one refused with the choices and no
    // window opened.
    let (_, out, _) = windloom(&["--help"]);
    assert!(out.contains("--view <VIEW>"), "{out}");
    let (code, _, err) = windloom(&["--view", "sideways", "layouts/meadow.json"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("possible values: map, 3d, split"), "{err}");
}

#[test]
fn cli_fmt_canonicalises_and_refuses_invalid_files() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("x.json");
    let compact =
        serde_json::to_string(&serde_json::from_str::<serde_json::Value>(&small_text()).unwrap())
            .unwrap();
    std::fs::write(&p, &compact).unwrap();
    let (code, _, err) = windloom(&["fmt", p.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(std::fs::read_to_string(&p).unwrap(), small_text());
    let broken = "{ \"format\": ";
    std::fs::write(&p, broken).unwrap();
    let (code, _, err) = windloom(&["fmt", p.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains(&format!("{}:1:", p.display())), "{err}");
    assert_eq!(std::fs::read_to_string(&p).unwrap(), broken);
}

#[test]
fn coordinates_and_sizes_are_bounded_to_what_the_solver_and_renderer_can_represent() {
    // The three layouts that used to pass validation and then panic or poison the solver.
    let far = small_text().replacen(" 5.0,\n", " 3e38,\n", 1);
    has(
        &errors(&far),
        "trees[0].root.pos[0]: must be between -1000000 and 1000000, got 3e38",
    );
    let tiny = small_text().replacen("\"size\": [\n      50.0", "\"size\": [\n      1e-40", 1);
    has(
        &errors(&tiny),
        "world.size[0]: must be at least 1, got 1e-40",
    );
    let thin = small_text().replacen("\"radius\": 3.0", "\"radius\": 1e-30", 1);
    has(
        &errors(&thin),
        "trees[0].root.radius: must be at least 0.001",
    );
    let fast = small_text().replacen("\"dt\": 0.016666668", "\"dt\": 1e-9", 1);
    has(&errors(&fast), "sim.dt: must be at least 0.0001");
    // The errors carry the file position.
    let e = errors(&far);
    assert!(
        e.iter().any(|e| e.starts_with(&format!(
            "{}:",
            far.lines().position(|l| l.contains("3e38")).unwrap() + 1
        ))),
        "{e:?}"
    );
}

/// A field's schema in `schema`: `def` is a definition, or `Definition.variant` for a field
/// of a tagged enum's variant.
fn field_schema<'a>(schema: &'a serde_json::Value, def: &str, prop: &str) -> &'a serde_json::Value {
    let defs = &schema["$defs"];
    let props = match def.split_once('.') {
        None => &defs[def]["properties"],
        Some((def, variant)) => {
            let arms = defs[def]["oneOf"].as_array().expect("a tagged enum");
            let arm = arms
                .iter()
                .find(|a| {
                    let p = &a["properties"];
                    p["kind"]["const"] == variant || p["type"]["const"] == variant
                })
                .unwrap_or_else(|| panic!("{def} has a variant {variant}"));
            &arm["properties"]
        }
    };
    let field = &props[prop];
    assert!(!field.is_null(), "the schema has {def}.{prop}");
    // An array's numbers carry the bound on their items.
    if field["type"] == "array" {
        &field["items"]
    } else {
        field
    }
}

/// A layout with one of everything a bound applies to: a windowed, pulsed tree, a circle,
/// a map backdrop, and a layer of each ambient kind.
fn everything() -> serde_json::Value {
    let mut l = example("meadow.json");
    l.trees[0].window = doc::TimeWindow::Between {
        start: 1.0,
        end: 10.0,
    };
    l.trees[0].emission = doc::Emission::Pulsed {
        period: 3.0,
        duty: 0.5,
    };
    l.world.map = Some(doc::MapBackdrop {
        image: "level.png".into(),
        opacity: 1.0,
        rect: None,
    });
    // Not the default profile, so that the layout holds it; a roughness below every
    // reference height the bounds allow.
    l.world.profile = doc::VerticalProfile {
        roughness_length: 0.001,
        layers: 8,
        ..Default::default()
    };
    l.obstacles = vec![
        doc::Obstacle {
            id: 1,
            name: "rock".into(),
            shape: Shape::Circle {
                center: [10.0, 10.0],
                radius: 2.0,
            },
            locked: false,
            hidden: false,
        },
        doc::Obstacle {
            id: 2,
            name: "walls".into(),
            shape: Shape::Mask {
                image: "walls.png".into(),
                threshold: 0.5,
                invert: false,
                rect: None,
                pixels: Default::default(),
            },
            locked: false,
            hidden: false,
        },
    ];
    let kinds = [
        r#"{"type": "directional", "direction_deg": 0, "main": 3, "turbulence": 1, "pulse_magnitude": 0.5, "pulse_frequency": 0.2}"#,
        r#"{"type": "noise", "direction_deg": 0, "scale": 20, "speed": 2, "strength": 3}"#,
        r#"{"type": "fft", "direction_deg": 0, "wind_speed": 5, "amplitude": 1, "resolution": 64, "tile_size": 50, "seed": 1}"#,
        r#"{"type": "sine", "direction_deg": 0, "amplitude": 1, "wavelength": 20, "frequency": 0.5}"#,
    ];
    l.ambient = kinds
        .iter()
        .enumerate()
        .map(|(i, k)| doc::AmbientLayer {
            id: i as u32 + 1,
            name: format!("layer {i}"),
            enabled: true,
            kind: serde_json::from_str(k).unwrap(),
            locked: false,
            hidden: false,
            keys: Vec::new(),
        })
        .collect();
    l.trees[0].keys = vec![doc::Key {
        time: 1.0,
        strength: 1.0,
        rotation_deg: 0.0,
        ease: doc::Ease::Linear,
    }];
    l.probes = vec![doc::Probe {
        id: 1,
        name: "probe".into(),
        pos: [10.0, 10.0],
    }];
    l.timeline = doc::Timeline {
        range: [0.0, 20.0],
        looping: false,
    };
    assert!(doc::validate(&l).is_empty(), "{:?}", doc::validate(&l));
    serde_json::to_value(&l).unwrap()
}

/// Where [`everything`] holds each bounded field: a JSON pointer.
fn pointer(def: &str, prop: &str) -> String {
    let ambient = |k: usize| format!("/ambient/{k}/kind/{prop}");
    match def {
        "World" | "MapBackdrop" if prop == "opacity" => "/world/map/opacity".into(),
        "World" => format!("/world/{prop}/1"),
        "VerticalProfile" => format!("/world/profile/{prop}"),
        "Tree" => format!("/trees/0/{prop}"),
        "TimeWindow.between" => format!("/trees/0/window/{prop}"),
        "Emission.pulsed" => format!("/trees/0/emission/{prop}"),
        "Node" if prop == "pos" => "/trees/0/root/pos/0".into(),
        "Probe" => format!("/probes/0/{prop}/0"),
        "Key" => format!("/trees/0/keys/0/{prop}"),
        "Timeline" => format!("/timeline/{prop}/1"),
        "Node" => format!("/trees/0/root/{prop}"),
        "Shape.circle" if prop == "center" => "/obstacles/0/shape/center/1".into(),
        "Shape.circle" => format!("/obstacles/0/shape/{prop}"),
        "Shape.mask" => format!("/obstacles/1/shape/{prop}"),
        "AmbientKind.directional" => ambient(0),
        "AmbientKind.noise" => ambient(1),
        "AmbientKind.fft" => ambient(2),
        "AmbientKind.sine" => ambient(3),
        "SimParams" => format!("/sim/{prop}"),
        // The upper end of a range (its lower end must stay below it).
        "GrassParams" if ["height", "width", "stiffness"].contains(&prop) => {
            format!("/grass/{prop}/1")
        }
        "GrassParams" => format!("/grass/{prop}"),
        "Shadow" if prop == "m_min" => "/grass/shadow/m_max".into(),
        "Shadow" => format!("/grass/shadow/{prop}"),
        "Palette" => format!("/grass/palettes/0/{prop}/2"),
        _ => panic!("no place for {def}.{prop}"),
    }
}

/// `/trees/0/root/pos/0` → `trees[0].root.pos[0]`, as `validate` names a field.
fn issue_path(pointer: &str) -> String {
    let mut out = String::new();
    for part in pointer.trim_start_matches('/').split('/') {
        if part.parse::<usize>().is_ok() {
            out += &format!("[{part}]");
        } else {
            if !out.is_empty() {
                out.push('.');
            }
            out += part;
        }
    }
    out
}

/// The issues `validate` reports at `path` for `layout` with the field at `ptr` set to `v`,
/// but those that relate it to another field (an end before its start).
fn issues_at(layout: &serde_json::Value, ptr: &str, v: serde_json::Value) -> Vec<String> {
    let mut l = layout.clone();
    *l.pointer_mut(ptr)
        .unwrap_or_else(|| panic!("{ptr} in the layout")) = v;
    let l: Layout = serde_json::from_value(l).unwrap();
    let path = issue_path(ptr);
    doc::validate(&l)
        .into_iter()
        .filter(|i| i.path == path && !i.message.contains("must be after"))
        .map(|i| i.to_string())
        .collect()
}

/// Every number field's bound is written once (`doc::bounds`): the schema states it, and
/// `validate` takes its ends and refuses a value past either.
#[test]
fn the_schema_and_validate_state_every_bound_of_the_one_table() {
    let schema = doc::schema();
    let layout = everything();
    let json = |v: f64| serde_json::json!(v as f32);
    for &(def, prop, b) in doc::bounds::NUMBERS {
        let field = field_schema(&schema, def, prop);
        let at = |key: &str| field[key].as_f64();
        assert_eq!(at("maximum"), Some(b.max), "{def}.{prop}: schema maximum");
        if b.above_zero && b.min <= 0.0 {
            assert_eq!(at("exclusiveMinimum"), Some(0.0), "{def}.{prop}: above 0");
        } else {
            assert_eq!(at("minimum"), Some(b.min), "{def}.{prop}: schema minimum");
        }
        let ptr = pointer(def, prop);
        for ok in [b.lo(), b.hi()] {
            let found = issues_at(&layout, &ptr, json(f64::from(ok)));
            assert!(found.is_empty(), "{def}.{prop} = {ok} is valid: {found:?}");
        }
        let step = |x: f64| x.abs().max(1.0) * 1e-3;
        let below = if b.above_zero && b.min <= 0.0 {
            0.0
        } else {
            b.min - step(b.min)
        };
        for bad in [below, b.max + step(b.max)] {
            let found = issues_at(&layout, &ptr, json(bad));
            assert!(!found.is_empty(), "{def}.{prop} = {bad} is refused");
        }
    }
    for &(def, prop, c) in doc::bounds::COUNTS {
        let field = field_schema(&schema, def, prop);
        assert_eq!(
            field["minimum"].as_u64(),
            Some(u64::from(c.min)),
            "{def}.{prop}"
        );
        assert_eq!(
            field["maximum"].as_u64(),
            Some(u64::from(c.max)),
            "{def}.{prop}"
        );
        let ptr = match def {
            "World" => "/world/grid/0".to_string(),
            "VerticalProfile" => format!("/world/profile/{prop}"),
            "AmbientKind.fft" => format!("/ambient/2/kind/{prop}"),
            _ => format!("/sim/{prop}"),
        };
        for ok in [c.min, c.max] {
            let found = issues_at(&layout, &ptr, ok.into());
            assert!(found.is_empty(), "{def}.{prop} = {ok} is valid: {found:?}");
        }
        for bad in [c.min - 1, c.max + 1] {
            let found = issues_at(&layout, &ptr, bad.into());
            assert!(!found.is_empty(), "{def}.{prop} = {bad} is refused");
        }
    }
}

#[cfg(unix)]
#[test]
fn saving_keeps_the_files_mode_and_writes_through_symlinks() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let layout = example("meadow.json");
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o7777;
    for m in [0o644, 0o640, 0o664, 0o600] {
        let p = dir.path().join(format!("level-{m:o}.json"));
        std::fs::write(&p, "{}").unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(m)).unwrap();
        windloom::io::save(&p, &layout).unwrap();
        assert_eq!(mode(&p), m, "save keeps {m:o}");
        assert_eq!(windloom::io::load(&p).unwrap(), layout);
    }
    // A symlinked layout (shared from another folder): the link stays, its target changes.
    let shared = dir.path().join("shared");
    std::fs::create_dir(&shared).unwrap();
    let target = shared.join("level.json");
    std::fs::write(&target, doc::to_json(&example("obstacles.json"))).unwrap();
    std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o644)).unwrap();
    let link = dir.path().join("link.json");
    std::os::unix::fs::symlink("shared/level.json", &link).unwrap();
    windloom::io::save(&link, &layout).unwrap();
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(windloom::io::load(&target).unwrap(), layout);
    assert_eq!(mode(&target), 0o644);
    // `windloom fmt` through the link, on a non-canonical file.
    std::fs::write(&target, doc::to_json(&layout).replace("\n", "\n  ")).unwrap();
    let (code, _, err) = windloom(&["fmt", link.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(
        std::fs::read_to_string(&target).unwrap(),
        doc::to_json(&layout)
    );
    assert_eq!(mode(&target), 0o644);
    // No temporary file is left anywhere.
    for d in [dir.path(), shared.as_path()] {
        for e in std::fs::read_dir(d).unwrap() {
            let n = e.unwrap().file_name().into_string().unwrap();
            assert!(!n.ends_with(".tmp"), "{n} left behind");
        }
    }
}

/// Fuzzing the loader (issue 13): arbitrary bytes and mutated layouts.
mod editing;
mod fuzz;
mod portable;
mod presets;

/// The editor never makes a layout that windloom cannot open again: its own edit commands
/// refuse to chain an arrow past the limit (or name a layer past its length), and the longest
/// chain they allow saves and loads back. A chain one longer, written by hand, is refused with
/// the limit named and the position of the arrow that goes past it.
#[test]
fn the_editor_s_edits_stay_within_what_loads() {
    let mut l = doc::default_layout();
    let mut history = doc::History::new();
    let mut tip = l.trees[0].root.id;
    let mut added = 0;
    let refused = loop {
        let id = l.next_id();
        let at = l.trees[0].root.find(tip).unwrap().pos;
        let node = doc::Node {
            id,
            pos: [at[0] + 0.01, at[1]],
            strength: 5.0,
            radius: 2.0,
            children: Vec::new(),
            keys: Vec::new(),
        };
        let edit = doc::Edit::AddNode {
            parent: tip,
            index: 0,
            node,
        };
        match history.apply(&mut l, edit) {
            Ok(()) => {
                added += 1;
                tip = id;
            }
            Err(e) => break e.to_string(),
        }
        assert!(added <= doc::CHAIN_MAX + 1, "no limit");
    };
    assert!(
        refused.contains("a chain of arrows holds at most 160"),
        "{refused}"
    );
    // The root's first child was already a chain of the meadow's own arrows.
    let depth = |n: &doc::Node| {
        let mut d = 0;
        let mut n = n;
        while let Some(c) = n.children.first() {
            d += 1;
            n = c;
        }
        d
    };
    assert_eq!(depth(&l.trees[0].root), doc::CHAIN_MAX);
    let text = doc::to_json(&l);
    assert_eq!(doc::parse(&text).unwrap(), l);
    // One more, written by hand: refused, at its place.
    let mut longer = l.clone();
    let mut n = &mut longer.trees[0].root;
    while !n.children.is_empty() {
        n = &mut n.children[0];
    }
    let p = n.pos;
    n.children.push(doc::Node {
        id: 999_999,
        pos: [p[0] + 0.01, p[1]],
        strength: 5.0,
        radius: 2.0,
        children: Vec::new(),
        keys: Vec::new(),
    });
    let text = doc::to_json(&longer);
    let e = doc::parse(&text).unwrap_err().to_string();
    assert!(e.contains("holds at most 160"), "{e}");
    let line: usize = e.split(':').next().unwrap().parse().unwrap();
    assert!(line > 1_000, "placed at line {line}: {e}");
    assert!(e.len() < 600, "a short message: {e}");
    // Far deeper (a chain of 2,000, as a script might write): refused before it is parsed.
    let mut deep = String::from(r#"{"format":"windloom-layout","version":1,"trees":["#);
    deep += &"{\"children\":[".repeat(2_000);
    let e = doc::parse(&deep).unwrap_err().to_string();
    assert!(e.contains("nested deeper than the 500 levels"), "{e}");
    // A name past the limit is refused by the edit, too.
    let long = "x".repeat(doc::NAME_MAX + 1);
    let e = history
        .apply(&mut l, doc::Edit::Rename(long))
        .unwrap_err()
        .to_string();
    assert!(e.contains("at most 256 characters"), "{e}");
}

/// The log law has no wind at or below the roughness length: a profile whose simulated wind
/// stands there is refused, naming the field; an old layout without a profile loads with
/// the defaults and saves without one.
#[test]
fn the_vertical_profile_is_checked_and_optional() {
    let mut l = example("meadow.json");
    assert!(l.world.profile.is_default());
    assert!(
        !doc::to_json(&l).contains("profile"),
        "a default profile is not written"
    );
    l.world.profile.roughness_length = 3.0;
    let issues = doc::validate(&l);
    assert_eq!(issues.len(), 1, "{issues:?}");
    assert_eq!(issues[0].path, "world.profile.reference_height");
    assert!(
        issues[0].message.contains("roughness length (3 m)"),
        "{}",
        issues[0]
    );
    l.world.profile.reference_height = 10.0;
    assert!(doc::validate(&l).is_empty());
    let text = doc::to_json(&l);
    assert!(text.contains("\"roughness_length\": 3.0"), "{text}");
    assert_eq!(doc::parse(&text).unwrap(), l);
}
