//! Export / Bake from the editor: in the background, from the File menu, into the layout's
//! own folder.

use super::*;

#[test]
fn export_dialog_bakes_in_the_background_and_cancel_leaves_nothing() {
    let ctx = egui::Context::default();
    let doc = example("meadow.json");
    let dir = tempfile::tempdir().unwrap();

    let mut dialog = windloom::app::export::ExportDialog::default();
    dialog.frames = 2;
    dialog.warmup = 0.5;
    dialog.use_layout_grid = false;
    dialog.grid = [32, 24];
    dialog.out = dir.path().join("ok").display().to_string();
    dialog.start(&doc, &ctx);
    dialog.wait();
    assert!(matches!(&dialog.result, Some(Ok(_))), "{:?}", dialog.result);
    assert!(dir.path().join("ok/manifest.json").exists());
    assert!(dir.path().join("ok/wind_0001.exr").exists());

    // A long bake, cancelled at once: no file, not even a staging folder, remains.
    dialog.out = dir.path().join("cancelled").display().to_string();
    dialog.frames = 400;
    dialog.grid = [256, 256];
    dialog.start(&doc, &ctx);
    dialog.cancel();
    dialog.wait();
    assert!(
        matches!(&dialog.result, Some(Err(e)) if e.contains("cancelled")),
        "{:?}",
        dialog.result
    );
    let left: Vec<_> = std::fs::read_dir(dir.path().join("cancelled"))
        .map(|r| r.collect())
        .unwrap_or_default();
    assert!(left.is_empty(), "{left:?}");

    // Closing the editor mid-bake cancels it and waits for the worker: when `shutdown`
    // returns, the thread is gone and nothing is left.
    dialog.out = dir.path().join("closed").display().to_string();
    dialog.start(&doc, &ctx);
    dialog.shutdown();
    assert!(!dialog.running());
    let left: Vec<_> = std::fs::read_dir(dir.path().join("closed"))
        .map(|r| r.collect())
        .unwrap_or_default();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn export_is_reachable_from_the_file_menu() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("meadow.json"));
    h.get_by_label("File").click();
    h.run_steps(2);
    h.get_by_label("Export/Bake…").click();
    h.run_steps(2);
    assert!(h.state().export.open);
    assert!(
        h.query_by_label("Bake").is_some(),
        "the dialog shows a Bake button"
    );
}

/// The export folder the dialog suggests is the layout's own (`levels/forest.json` →
/// `levels/forest-bake`), so baking two layouts of one folder never replaces one bake with
/// the other; it follows the open file until the user picks a folder, which then stays.
#[test]
fn the_suggested_export_folder_is_the_layout_s_own() {
    if !gpu_available() {
        return;
    }
    let levels = Path::new("levels");
    let mut h = harness_on(example("meadow.json"), Some(levels.join("meadow.json")));
    let open_dialog = |h: &mut Harness<'_, EditorApp>| {
        h.state_mut().export.open = false;
        h.run_steps(2);
        h.get_by_label("File").click();
        h.run_steps(2);
        h.get_by_label("Export/Bake…").click();
        h.run_steps(2);
        assert!(h.state().export.open);
        h.state().export.out.clone()
    };
    let folder = |name: &str| levels.join(name).display().to_string();
    assert_eq!(open_dialog(&mut h), folder("meadow-bake"));
    // Another file opened: the suggestion follows it.
    h.state_mut().doc.set_path(Some(levels.join("forest.json")));
    assert_eq!(open_dialog(&mut h), folder("forest-bake"));
    // A folder the user typed stays, whatever is opened next.
    h.state_mut().export.out = "/srv/game/wind".into();
    h.state_mut().doc.set_path(Some(levels.join("meadow.json")));
    assert_eq!(open_dialog(&mut h), "/srv/game/wind");
}

/// File → Live export bakes the layout at once, then again after each edit once the edits
/// pause — one bake for a burst of edits, not one per frame — each with the next sequence,
/// and says so in the status bar.
#[test]
fn live_export_bakes_again_after_each_edit() {
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("live");
    let mut h = harness(example("meadow.json"));
    {
        let e = &mut h.state_mut().export;
        e.use_layout_grid = false;
        e.grid = [24, 16];
        e.warmup = 0.2;
        e.formats = vec![(windloom::bake::Format::Raw, true)];
        e.out = out.display().to_string();
    }
    h.get_by_label("File").click();
    h.run_steps(2);
    h.get_by_label("Live export").click();
    h.run_steps(2);
    assert!(h.state().export.live);
    let sequence = |h: &mut Harness<'_, EditorApp>, want: u64| -> serde_json::Value {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
        loop {
            h.run_steps(1);
            if let Ok(text) = std::fs::read_to_string(out.join("manifest.json")) {
                let m: serde_json::Value = serde_json::from_str(&text).unwrap();
                if m["sequence"].as_u64() >= Some(want) && !h.state().export.running() {
                    return m;
                }
            }
            assert!(std::time::Instant::now() < deadline, "no bake {want}");
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
    };
    let m = sequence(&mut h, 1);
    assert_eq!(
        m["layout"]["hash"],
        windloom::bake::layout_hash(&{
            let mut l = h.state().doc.layout().clone();
            l.world.grid = [24, 16];
            l
        })
    );
    // A burst of edits (a drag's worth), then a pause: one more bake, of the last state.
    let ctx = h.ctx.clone();
    let node = h.state().doc.trees[0].root.children[0].clone();
    let set = |h: &mut Harness<'_, EditorApp>, strength: f32| {
        h.state_mut().edit(
            &ctx,
            windloom::doc::Edit::SetNode {
                id: node.id,
                strength,
                radius: node.radius,
            },
        );
    };
    for k in 0..5 {
        set(&mut h, 4.0 + k as f32);
        h.run_steps(1);
    }
    let m = sequence(&mut h, 2);
    std::thread::sleep(std::time::Duration::from_secs_f64(
        windloom::app::export::LIVE_SETTLE * 2.0,
    ));
    h.run_steps(3);
    let again: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(again["sequence"], 2, "one bake for the burst");
    let mut last = h.state().doc.layout().clone();
    assert_eq!(last.trees[0].root.children[0].strength, 8.0);
    last.world.grid = [24, 16];
    assert_eq!(m["layout"]["hash"], windloom::bake::layout_hash(&last));
    assert!(
        h.state()
            .message
            .as_ref()
            .is_some_and(|(t, _)| t.starts_with("Live export: Baked")),
        "{:?}",
        h.state().message
    );
    // Off: edits no longer bake.
    h.state_mut().export.set_live(false);
    set(&mut h, 1.0);
    h.run_steps(3);
    std::thread::sleep(std::time::Duration::from_secs_f64(
        windloom::app::export::LIVE_SETTLE * 2.0,
    ));
    h.run_steps(3);
    assert!(!h.state().export.running());
    let after: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(after["sequence"], 2);
}

/// The dialog speaks engines: Unreal, Unity or Godot picks the formats and frames its guide
/// leads with (steady, or an animated loop); changing a format makes it the user's own
/// (Custom); every format says which engine reads it.
#[test]
fn the_export_dialog_picks_formats_by_engine() {
    use windloom::app::export::Engine;
    use windloom::bake::Format;
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("meadow.json"));
    h.state_mut().export.open = true;
    h.run_steps(2);
    let on = |h: &Harness<'_, EditorApp>| -> Vec<Format> {
        (h.state().export.formats.iter())
            .filter(|(_, on)| *on)
            .map(|(f, _)| *f)
            .collect()
    };
    h.get_by_label("Unreal").click();
    h.run_steps(2);
    assert_eq!(on(&h), vec![Format::Exr, Format::Fga, Format::Dds]);
    assert_eq!(h.state().export.engine(), Some((Engine::Unreal, false)));
    h.get_by_label("Animated loop").click();
    h.run_steps(2);
    assert_eq!(on(&h), vec![Format::Atlas]);
    let e = &h.state().export;
    assert!(e.frames == 64 && e.looped && e.fps == 16.0);
    h.get_by_label("Unity").click();
    h.run_steps(2);
    assert_eq!(
        h.state().export.engine(),
        Some((Engine::Unity, true)),
        "still animated"
    );
    assert_eq!(on(&h), vec![Format::Vf]);
    h.get_by_label("Godot").click();
    h.run_steps(2);
    h.get_by_label("Steady").click();
    h.run_steps(2);
    assert_eq!(on(&h), vec![Format::Exr, Format::Dds]);
    assert_eq!(h.state().export.frames, 1);
    // A format of one's own: Custom.
    h.get_by_label("raw").click();
    h.run_steps(2);
    assert_eq!(h.state().export.engine(), None);
    for f in Format::ALL {
        let hint = f.engines_hint();
        assert!(
            ["Unreal", "Unity", "Godot", "any engine", "runtime"]
                .iter()
                .any(|e| hint.contains(e)),
            "{f:?}: {hint}"
        );
    }
}

/// Live export bakes once a gesture ends: a drag held still past the settling time, then
/// moved on and released, is one edit and one bake (it was two), and the dialog names the
/// folder the bake went to in full.
#[test]
fn live_export_bakes_once_for_a_drag_held_still() {
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("live");
    let mut h = harness(example("two-winds.json"));
    {
        let e = &mut h.state_mut().export;
        e.use_layout_grid = false;
        e.grid = [24, 16];
        e.warmup = 0.2;
        e.formats = vec![(windloom::bake::Format::Raw, true)];
        e.out = out.display().to_string();
        e.set_live(true);
    }
    let sequence = || -> Option<u64> {
        let text = std::fs::read_to_string(out.join("manifest.json")).ok()?;
        serde_json::from_str::<serde_json::Value>(&text).ok()?["sequence"].as_u64()
    };
    let settle = |h: &mut Harness<'_, EditorApp>| {
        let until =
            Instant::now() + Duration::from_secs_f64(windloom::app::export::LIVE_SETTLE * 3.0);
        while Instant::now() < until || h.state().export.running() {
            h.run_steps(1);
            std::thread::sleep(Duration::from_millis(20));
        }
    };
    settle(&mut h);
    assert_eq!(
        sequence(),
        Some(1),
        "the layout baked when Live export was turned on"
    );
    // Press on a point, move, hold still past the settling time, move on, release.
    let from = h.state().screen_pos([32.0, 40.0]);
    let mid = h.state().screen_pos([36.0, 40.0]);
    let to = h.state().screen_pos([40.0, 44.0]);
    h.event(Event::PointerMoved(from));
    h.run_steps(1);
    h.event(Event::PointerButton {
        pos: from,
        button: PointerButton::Primary,
        pressed: true,
        modifiers: Modifiers::NONE,
    });
    h.run_steps(1);
    for k in 1..=4 {
        h.event(Event::PointerMoved(from + (mid - from) * (k as f32 / 4.0)));
        h.run_steps(1);
    }
    settle(&mut h);
    assert_eq!(sequence(), Some(1), "no bake while the drag is held");
    h.event(Event::PointerMoved(to));
    h.run_steps(1);
    h.event(Event::PointerButton {
        pos: to,
        button: PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::NONE,
    });
    h.run_steps(2);
    settle(&mut h);
    settle(&mut h);
    assert_eq!(sequence(), Some(2), "one bake for the drag");
    let said = match &h.state().export.result {
        Some(Ok(msg)) => msg.clone(),
        other => panic!("{other:?}"),
    };
    assert!(said.contains(&out.display().to_string()), "{said}");
    assert_eq!(h.state().export.baked_to.as_deref(), Some(out.as_path()));
    h.state_mut().export.set_live(false);
}
