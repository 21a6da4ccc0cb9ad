//! The grey images a layout owns (mask obstacles' images, the density map, the heightmap),
//! however they arrived (opened, attached, pasted, made new), painted in the editor: saved,
//! autosaved and restored with the same pixels and the same wind, and never written over a
//! file the editor did not read.

use super::*;
use std::sync::Arc;
use windloom::doc::{MaskImage, MaskPixels, Shape};

/// A grey 16-bit PNG of `w` × `h` pixels, `f(x, y)` each.
fn write_grey(path: &Path, w: u32, h: u32, f: impl Fn(u32, u32) -> u16) {
    let image = MaskImage {
        width: w,
        height: h,
        luminance: (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect(),
    };
    let bytes = windloom::io::images::encode_grey(path, &image, false).unwrap();
    std::fs::write(path, bytes).unwrap();
}

/// The pixels an image field holds.
fn pixels(p: &MaskPixels) -> Arc<MaskImage> {
    match p {
        MaskPixels::Loaded(i) => i.clone(),
        other => panic!("the image is not loaded: {other:?}"),
    }
}

fn mask_pixels(l: &doc::Layout, k: usize) -> Arc<MaskImage> {
    match &l.obstacles[k].shape {
        Shape::Mask { pixels: p, .. } => pixels(p),
        other => panic!("obstacle {k} is no mask: {other:?}"),
    }
}

fn density_pixels(l: &doc::Layout) -> Arc<MaskImage> {
    pixels(&l.grass.density_map.as_ref().expect("a density map").pixels)
}

/// A layout holding one mask obstacle over `rect` naming `image`, as text to paste.
fn mask_to_paste(image: &str, rect: [[f32; 2]; 2]) -> String {
    let mut l = doc::Layout::untitled("clip");
    l.obstacles.push(doc::Obstacle {
        id: 1,
        name: "Rocks".into(),
        shape: Shape::Mask {
            image: image.into(),
            threshold: 0.5,
            invert: false,
            rect: Some(rect),
            pixels: MaskPixels::NotLoaded,
        },
        locked: false,
        hidden: false,
    });
    doc::to_json(&l)
}

/// A copy of a bundled example and the images it names in a folder of its own.
fn level_in(dir: &Path, name: &str, images: &[&str]) -> std::path::PathBuf {
    let layouts = Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts");
    for f in std::iter::once(name).chain(images.iter().copied()) {
        std::fs::copy(layouts.join(f), dir.join(f)).unwrap();
    }
    dir.join(name)
}

/// The bug a designer met: a density map attached and a mask pasted in this session, then
/// painted. Save must write both (it said "Saved" and wrote neither), and reopening shows the
/// strokes.
#[test]
fn images_attached_or_pasted_then_painted_are_saved_and_read_back() {
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let level = level_in(dir.path(), "two-winds.json", &[]);
    // The level's pictures, made elsewhere: grass everywhere, and open rock ground.
    write_grey(&dir.path().join("grass.png"), 60, 40, |_, _| u16::MAX);
    write_grey(&dir.path().join("rocks.png"), 40, 30, |_, _| u16::MAX);
    let rocks_before = std::fs::read(dir.path().join("rocks.png")).unwrap();
    let mut h = harness_on(windloom::io::load(&level).unwrap(), Some(level.clone()));

    // Attached: the density map typed into the Grass section.
    h.get_by_label("Grass").click();
    h.run_steps(2);
    h.get_by_label("Density map").focus();
    h.run_steps(1);
    h.get_by_label("Density map").type_text("grass.png");
    h.key_press(egui::Key::Enter);
    h.run_steps(2);
    let attached = density_pixels(&h.state().doc);
    assert_eq!((attached.width, attached.height), (60, 40));
    assert!(
        h.state().doc.unsaved_images().is_empty(),
        "an attached image is its file: nothing to write back"
    );
    h.key_press(egui::Key::Escape);
    h.run_steps(1);
    // Pasted: a mask obstacle naming rocks.png beside the layout.
    h.event(Event::Paste(mask_to_paste(
        "rocks.png",
        [[10.0, 10.0], [50.0, 40.0]],
    )));
    h.run_steps(2);
    assert_eq!(h.state().doc.obstacles.len(), 1, "the mask was pasted");
    assert!(
        !h.state().doc.obstacles[0]
            .shape
            .mask_contains([30.0, 25.0], h.state().doc.bounds())
    );

    // Painted: the mask solid across its middle, then bare ground on the density map.
    let id = h.state().doc.obstacles[0].id;
    h.state_mut().selection = vec![Sel::Obstacle(id)];
    h.key_press(egui::Key::B);
    h.run_steps(2);
    let (a, b) = (
        h.state().screen_pos([20.0, 25.0]),
        h.state().screen_pos([40.0, 25.0]),
    );
    drag(&mut h, a, b);
    let bounds = h.state().doc.bounds();
    assert!(
        h.state().doc.obstacles[0]
            .shape
            .mask_contains([30.0, 25.0], bounds),
        "painted"
    );
    h.state_mut().selection.clear();
    h.run_steps(1);
    // Shift-drag: bare ground.
    let (a, b) = (
        h.state().screen_pos([70.0, 60.0]),
        h.state().screen_pos([90.0, 60.0]),
    );
    h.event(Event::ModifiersChanged(Modifiers::SHIFT));
    drag(&mut h, a, b);
    h.event(Event::ModifiersChanged(Modifiers::NONE));
    h.run_steps(1);
    let _ = h.state_mut().doc.take_changed();
    let density = density_pixels(&h.state().doc);
    let mask = mask_pixels(&h.state().doc, 0);
    assert!(
        !Arc::ptr_eq(&density, &attached),
        "the density map was painted"
    );
    assert!(h.state().doc.is_dirty(), "painted images are unsaved work");
    assert_eq!(h.state().doc.unsaved_images().len(), 2);

    // Ctrl+S: both images written, the layout saved, nothing left unsaved.
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::S);
    h.run_steps(2);
    assert!(!h.state().doc.is_dirty(), "{:?}", h.state().message);
    assert!(h.state().doc.unsaved_images().is_empty());
    assert_ne!(
        std::fs::read(dir.path().join("rocks.png")).unwrap(),
        rocks_before
    );

    // Reopened: the same pixels, read from the files.
    let reopened = windloom::io::load(&level).unwrap();
    assert_eq!(*mask_pixels(&reopened, 0), *mask);
    assert_eq!(*density_pixels(&reopened), *density);
    assert!(
        reopened.obstacles[0]
            .shape
            .mask_contains([30.0, 25.0], bounds)
    );
}

/// Saved into another folder, a layout keeps naming the images it read (`../a/rocks.png`),
/// so none is lost; its painted ones are written to the files it names.
#[test]
fn save_as_into_another_folder_keeps_every_image() {
    let root = tempfile::tempdir().unwrap();
    let a = root.path().join("a");
    let b = root.path().join("b");
    std::fs::create_dir_all(&a).unwrap();
    std::fs::create_dir_all(&b).unwrap();
    let level = level_in(
        &a,
        "walled-garden.json",
        &[
            "walled-garden-mask.png",
            "walled-garden-grass.png",
            "walled-garden-heights.png",
        ],
    );
    // In b, a file of someone else's with the name of one of a's images.
    std::fs::write(b.join("walled-garden-grass.png"), b"theirs").unwrap();
    let ctx = egui::Context::default();
    let mut app = EditorApp::new(
        windloom::io::load(&level).unwrap(),
        Some(level.clone()),
        &ctx,
    );
    // Paint the density map (as a stroke lands: a new image in place of the old).
    let mut painted = (*density_pixels(&app.doc)).clone();
    painted.luminance.iter_mut().take(500).for_each(|l| *l = 0);
    let mut g = app.doc.grass.clone();
    g.density_map.as_mut().unwrap().pixels = MaskPixels::Loaded(Arc::new(painted.clone()));
    assert!(app.edit(&ctx, doc::Edit::SetGrass(g)));
    let target = b.join("copy.json");
    assert!(app.save_to(&ctx, &target), "{:?}", app.dialog.is_some());
    let saved = windloom::io::load(&target).unwrap();
    assert_eq!(
        saved.grass.density_map.as_ref().unwrap().image,
        "../a/walled-garden-grass.png"
    );
    assert_eq!(*density_pixels(&saved), painted, "the strokes went with it");
    assert_eq!(*mask_pixels(&saved, 0), *mask_pixels(app.doc.layout(), 0));
    assert!(
        saved
            .world
            .terrain
            .as_ref()
            .unwrap()
            .pixels
            .image()
            .is_some()
    );
    assert_eq!(
        std::fs::read(b.join("walled-garden-grass.png")).unwrap(),
        b"theirs"
    );
    assert!(!app.doc.is_dirty());
}

/// The editor killed with painted, unsaved strokes: Restore brings back the layout and its
/// images as they were at the last autosave, the other images from the level's folder (not
/// the recovery folder), the same wind, and Save then writes the strokes to the level.
#[test]
fn painted_work_comes_back_after_a_kill_with_the_same_wind() {
    if !gpu_available() {
        return;
    }
    let home = tempfile::tempdir().unwrap();
    let level = level_in(
        home.path(),
        "walled-garden.json",
        &[
            "walled-garden-mask.png",
            "walled-garden-grass.png",
            "walled-garden-heights.png",
        ],
    );
    let mask_file = home.path().join("walled-garden-mask.png");
    let mask_before = std::fs::read(&mask_file).unwrap();
    let recovery = home.path().join("recovery");
    let mut h = harness_on(windloom::io::load(&level).unwrap(), Some(level.clone()));
    h.state_mut().doc.set_recovery_dir(Some(recovery.clone()));
    let id = h.state().doc.obstacles[0].id;
    h.state_mut().selection = vec![Sel::Obstacle(id)];
    h.key_press(egui::Key::B);
    h.run_steps(2);
    let (a, b) = (
        h.state().screen_pos([25.0, 20.0]),
        h.state().screen_pos([35.0, 20.0]),
    );
    drag(&mut h, a, b);
    let bounds = h.state().doc.bounds();
    assert!(
        h.state().doc.obstacles[0]
            .shape
            .mask_contains([30.0, 20.0], bounds)
    );
    let _ = h.state_mut().doc.take_changed();
    let painted = h.state().doc.layout().clone();
    // The autosave, then the editor is gone without a word (no on_exit, no save).
    h.state_mut().doc.write_recovery().unwrap();
    let found = windloom::io::recovery::Recovery::found(&recovery);
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].images.len(), 1, "the painted mask is in the copy");
    std::mem::forget(h);

    // The next editor offers the copy; the designer clicks Restore.
    let other = home.path().join("other-recovery");
    let mut h = harness(doc::default_layout());
    h.state_mut().doc.set_recovery_dir(Some(other));
    h.state_mut().doc.offer_found(found);
    h.state_mut().next_recovery();
    h.run_steps(2);
    h.get_by_label("Restore").click();
    h.run_steps(3);
    let app = h.state();
    assert_eq!(
        app.doc.path(),
        Some(level.canonicalize().unwrap().as_path())
    );
    assert_eq!(
        *mask_pixels(app.doc.layout(), 0),
        *mask_pixels(&painted, 0),
        "same strokes"
    );
    assert_eq!(*density_pixels(app.doc.layout()), *density_pixels(&painted));
    assert_eq!(
        app.doc.world.terrain.as_ref().unwrap().pixels.image(),
        painted.world.terrain.as_ref().unwrap().pixels.image(),
        "the heightmap read from the level's folder"
    );
    assert!(app.doc.is_dirty(), "restored work is unsaved");
    assert_eq!(
        std::fs::read(&mask_file).unwrap(),
        mask_before,
        "the level is untouched"
    );
    // The same wind: the solver on the restored layout steps to the same bits.
    let wind = |l: &doc::Layout| {
        let mut s = windloom::sim::Solver::new(l);
        for _ in 0..20 {
            s.step();
        }
        s.state_bytes()
    };
    assert!(
        wind(app.doc.layout()) == wind(&painted),
        "the same wind after Restore"
    );
    // Ctrl+S writes the strokes to the level's mask.
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::S);
    h.run_steps(2);
    assert!(!h.state().doc.is_dirty());
    let saved = windloom::io::load(&level).unwrap();
    assert_eq!(*mask_pixels(&saved, 0), *mask_pixels(&painted, 0));
}
