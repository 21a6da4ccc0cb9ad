//! Presets: every built-in one applies to every example as one undo step and leaves a valid
//! layout; the user's own are saved in a folder, listed, read back and never overwritten.

use super::*;
use doc::presets;
use windloom::io::presets::{self as user, Kind};

const EXAMPLES: [&str; 6] = [
    "meadow.json",
    "branching.json",
    "two-winds.json",
    "obstacles.json",
    "breeze-fft.json",
    "walled-garden.json",
];

#[test]
fn every_preset_applies_to_every_example_in_one_undo_step() {
    for file in EXAMPLES {
        let original = example(file);
        let before = doc::to_json(&original);
        for name in presets::WIND {
            let mut l = original.clone();
            let preset = presets::wind(name, &l).unwrap();
            let mut h = History::new();
            let edit = presets::apply_wind(&l, preset.clone());
            h.apply(&mut l, edit)
                .unwrap_or_else(|e| panic!("{name} on {file}: {e}"));
            assert!(doc::validate(&l).is_empty(), "{name} on {file}");
            assert_eq!(h.undo_label(), Some("Apply wind preset"));
            // Its layers replace the layout's; its trees join the layout's.
            let names: Vec<&str> = l.ambient.iter().map(|a| a.name.as_str()).collect();
            let want: Vec<&str> = preset.ambient.iter().map(|a| a.name.as_str()).collect();
            assert_eq!(names, want, "{name} on {file}");
            assert_eq!(l.trees.len(), original.trees.len() + preset.trees.len());
            assert!(h.undo(&mut l));
            assert_eq!(doc::to_json(&l), before, "{name} on {file} undone");
        }
        for name in presets::GRASS {
            let mut l = original.clone();
            let grass = presets::grass(name).unwrap();
            let edit = presets::apply_grass(&l, grass.clone());
            edit.apply(&mut l).unwrap();
            assert_eq!(l.grass.height, grass.height, "{name} on {file}");
            assert_eq!(
                l.grass.density_map, original.grass.density_map,
                "the level's map stays"
            );
            assert_eq!(l.grass.seed, original.grass.seed);
        }
    }
    assert!(presets::wind("Hurricane", &example("meadow.json")).is_none());
    assert!(presets::grass("Moss").is_none());
}

#[test]
fn grass_presets_differ_as_their_names_say() {
    let g = |n| presets::grass(n).unwrap();
    let (lawn, meadow, wheat, tall) = (g("Lawn"), g("Meadow"), g("Wheat"), g("Tall grass"));
    assert!(lawn.height[1] < meadow.height[0], "a lawn is short");
    assert!(wheat.height[0] > meadow.height[1] && tall.height[1] > wheat.height[1]);
    assert!(lawn.density > meadow.density, "a lawn is dense");
    // Wheat is golden: its tips redder than green.
    assert!(wheat.palettes.iter().all(|p| p.tip[0] > p.tip[1] * 0.95));
    assert!(
        tall.stiffness[1] < lawn.stiffness[0],
        "tall grass sways more"
    );
}

#[test]
fn a_wind_preset_fits_the_world_it_is_applied_to() {
    // The valley runs along the long axis, through the middle, over most of the world.
    let mut wide = Layout::new("wide", [400.0, 100.0], [128, 32]);
    wide.world.origin = [-50.0, 20.0];
    let valley = presets::wind("Valley wind", &wide).unwrap();
    let pts: Vec<[f32; 2]> = valley.trees[0].root.iter().map(|n| n.pos).collect();
    assert!(pts.iter().all(|p| p[1] == 70.0), "{pts:?}");
    assert!(pts.first().unwrap()[0] < 0.0 && pts.last().unwrap()[0] > 250.0);
    // A user's preset from a 100 m world lands stretched on a 400 m one.
    let small = example("two-winds.json");
    let saved = presets::wind_of(&small, &[2]);
    assert_eq!(saved.trees.len(), 1);
    let mut big = Layout::new(
        "big",
        [small.world.size[0] * 4.0, small.world.size[1] * 4.0],
        [64, 64],
    );
    let edit = presets::apply_wind(&big, saved);
    edit.apply(&mut big).unwrap();
    let root = big.trees[0].root.pos;
    let was = small.trees[1].root.pos;
    assert_eq!(root, [was[0] * 4.0, was[1] * 4.0]);
    assert_eq!(big.trees[0].root.radius, small.trees[1].root.radius * 4.0);
}

#[test]
fn a_user_s_presets_are_saved_listed_and_never_overwritten() {
    let dir = tempfile::tempdir().unwrap();
    let l = example("breeze-fft.json");
    assert!(user::list(dir.path(), Kind::Wind).is_empty());
    let path = user::save(
        dir.path(),
        Kind::Wind,
        "Evening gusts",
        &presets::wind_of(&l, &[]),
    )
    .unwrap();
    assert!(path.starts_with(dir.path().join("wind")));
    user::save(dir.path(), Kind::Grass, "my lawn", &presets::grass_of(&l)).unwrap();
    let listed = user::list(dir.path(), Kind::Wind);
    assert_eq!(listed.len(), 1);
    assert_eq!(listed[0].0, "Evening gusts");
    let back = user::read(&listed[0].1).unwrap();
    assert_eq!(back.ambient, l.ambient);
    // A name in use (whatever its case) is refused, and the file kept.
    let before = std::fs::read(&path).unwrap();
    let e = user::save(
        dir.path(),
        Kind::Wind,
        "evening GUSTS",
        &presets::wind_of(&example("meadow.json"), &[]),
    );
    assert!(e.unwrap_err().to_string().contains("exists already"));
    assert_eq!(std::fs::read(&path).unwrap(), before);
    // Names that are paths or empty are refused, naming the rule.
    for bad in ["", "  ", "../up", "a/b", ".hidden", "x".repeat(65).as_str()] {
        let e = user::save(dir.path(), Kind::Wind, bad, &l).unwrap_err();
        assert!(e.to_string().contains("letters, digits"), "{bad:?}: {e}");
    }
    assert_eq!(user::list(dir.path(), Kind::Wind).len(), 1);
    // A broken preset file is refused with its line and column when read.
    std::fs::write(dir.path().join("wind").join("Broken.json"), "{ nope").unwrap();
    let broken = user::list(dir.path(), Kind::Wind)
        .into_iter()
        .find(|(n, _)| n == "Broken")
        .unwrap();
    let e = user::read(&broken.1).unwrap_err().to_string();
    assert!(e.contains("Broken.json:1:"), "{e}");
    user::delete(&broken.1).unwrap();
    assert_eq!(user::list(dir.path(), Kind::Wind).len(), 1);
}
