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
