//! A level built from nothing in the editor: a backdrop picture placed with its handles, a
//! mask obstacle made from it by a threshold and painted with the soft brush, a rectangle and
//! a fill, a blank density map painted, and all of it saved beside the layout and read back.

use super::*;
use windloom::doc::{MaskPixels, Shape};

/// A picture of a level, `w` × `h`: a green field with a dark building over `dark`
/// (pixel columns and rows).
fn picture(path: &Path, w: u32, h: u32, dark: [std::ops::Range<u32>; 2]) {
    let img = image::RgbaImage::from_fn(w, h, |x, y| {
        if dark[0].contains(&x) && dark[1].contains(&y) {
            image::Rgba([40, 40, 40, 255])
        } else {
            image::Rgba([90, 143, 60, 255])
        }
    });
    img.save(path).unwrap();
}

fn mask_image(l: &doc::Layout) -> std::sync::Arc<doc::MaskImage> {
    match &l.obstacles[0].shape {
        Shape::Mask {
            pixels: MaskPixels::Loaded(i),
            ..
        } => i.clone(),
        other => panic!("no loaded mask: {other:?}"),
    }
}

/// Drags with the pointer's button down from `from` to `to` in a few frames, Shift held or
/// not (the paint tool's erase).
fn drag_with(h: &mut Harness<'_, EditorApp>, from: Pos2, to: Pos2, shift: bool) {
    let m = if shift {
        Modifiers::SHIFT
    } else {
        Modifiers::NONE
    };
    h.event(Event::ModifiersChanged(m));
    drag(h, from, to);
    h.event(Event::ModifiersChanged(Modifiers::NONE));
    h.run_steps(1);
}

/// The whole of a new level, as a designer makes it: nothing on disk but a picture.
#[test]
fn a_level_is_built_from_a_picture_and_saved_with_its_images() {
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let level = dir.path().join("garden.json");
    // 300 × 200 pixels over a 150 m × 100 m world: the building at x 20–40 m, z 10–30 m.
    picture(&dir.path().join("garden.png"), 300, 200, [40..80, 20..60]);
    let mut doc = doc::Layout::untitled("Untitled");
    doc.world.size = [150.0, 100.0];
    doc.world.grid = [150, 100];
    let mut h = harness_on(doc, Some(level.clone()));
    // The backdrop, typed into the inspector.
    h.get_by_label("Map image").focus();
    h.run_steps(1);
    h.get_by_label("Map image").type_text("garden.png");
    h.key_press(egui::Key::Enter);
    h.run_steps(2);
    assert!(h.state().doc.world.map.is_some(), "the backdrop is set");

    // Edit → New mask obstacle…: from the backdrop, at the threshold that splits it.
    h.get_by_label("Edit").click();
    h.run_steps(2);
    h.get_by_label("New mask obstacle…").click();
    h.run_steps(3);
    h.get_by_label("Create").click();
    h.run_steps(3);
    let d = &h.state().doc;
    assert_eq!(d.obstacles.len(), 1, "{:?}", h.state().message);
    let bounds = d.bounds();
    let shape = &d.obstacles[0].shape;
    assert!(
        shape.mask_contains([30.0, 20.0], bounds),
        "the building is solid"
    );
    assert!(
        !shape.mask_contains([100.0, 60.0], bounds),
        "the field is open"
    );
    assert_eq!(h.state().tool, Tool::Paint, "ready to paint it");
    assert!(matches!(shape, Shape::Mask { image, .. } if image == "garden-mask.png"));

    // A soft brush at half opacity: a grey stroke, lighter at its edge.
    h.state_mut().settings.brush.hardness = 0.0;
    h.state_mut().settings.brush.opacity = 0.5;
    h.state_mut().brush_radius = 4.0;
    let before = mask_image(&h.state().doc);
    let (a, b) = (
        h.state().screen_pos([80.0, 70.0]),
        h.state().screen_pos([120.0, 70.0]),
    );
    drag(&mut h, a, b);
    let after = mask_image(&h.state().doc);
    let at = |m: &doc::MaskImage, p: [f32; 2]| {
        m.luminance[(p[1] / 0.5) as usize * m.width as usize + (p[0] / 0.5) as usize]
    };
    let middle = at(&after, [100.0, 70.0]);
    let edge = at(&after, [100.0, 73.0]);
    assert!(
        (middle as i32 - 32_768).abs() < 2_000,
        "half way to solid in the middle: {middle}"
    );
    assert!(
        edge > middle && edge < u16::MAX,
        "softer at the edge: {edge}"
    );
    assert_eq!(
        at(&after, [100.0, 80.0]),
        u16::MAX,
        "nothing past the radius"
    );
    assert_eq!(at(&before, [100.0, 70.0]), u16::MAX);

    // A rectangle, full opacity: a wall.
    h.state_mut().settings.brush.opacity = 1.0;
    h.state_mut().settings.brush.mark = windloom::app::paint::Mark::Rectangle;
    let (a, b) = (
        h.state().screen_pos([60.0, 40.0]),
        h.state().screen_pos([90.0, 44.0]),
    );
    drag(&mut h, a, b);
    let bounds = h.state().doc.bounds();
    assert!(
        h.state().doc.obstacles[0]
            .shape
            .mask_contains([75.0, 42.0], bounds)
    );
    // A fill, Shift: the building cleared, the wall kept.
    h.state_mut().settings.brush.mark = windloom::app::paint::Mark::Fill;
    let p = h.state().screen_pos([30.0, 20.0]);
    h.event(Event::ModifiersChanged(Modifiers::SHIFT));
    click(&mut h, p);
    h.event(Event::ModifiersChanged(Modifiers::NONE));
    h.run_steps(1);
    let shape = &h.state().doc.obstacles[0].shape;
    assert!(
        !shape.mask_contains([30.0, 20.0], bounds),
        "the building was filled open"
    );
    assert!(shape.mask_contains([75.0, 42.0], bounds), "and only it");
    let undo = h.state().doc.history().undo_label();
    assert_eq!(undo, Some("Change obstacle"), "each mark one step");

    // A blank density map (grass everywhere), a road of bare ground painted across it.
    h.state_mut().selection.clear();
    h.get_by_label("Edit").click();
    h.run_steps(2);
    h.get_by_label("New density map…").click();
    h.run_steps(3);
    h.get_by_label("Blank: grass everywhere, to paint roads and water out of")
        .click();
    h.run_steps(2);
    h.get_by_label("Create").click();
    h.run_steps(3);
    let density = |h: &Harness<'_, EditorApp>, p| {
        h.state()
            .doc
            .grass
            .density_map
            .as_ref()
            .expect("a density map")
            .at(p, bounds)
    };
    assert_eq!(density(&h, [10.0, 90.0]), 1.0);
    h.state_mut().settings.brush.mark = windloom::app::paint::Mark::Brush;
    h.state_mut().settings.brush.hardness = 1.0;
    let (a, b) = (
        h.state().screen_pos([5.0, 90.0]),
        h.state().screen_pos([145.0, 90.0]),
    );
    drag_with(&mut h, a, b, true);
    assert_eq!(density(&h, [10.0, 90.0]), 0.0, "a bare road");

    // Saved: the layout, its two new images beside it; read back as they were.
    let _ = h.state_mut().doc.take_changed();
    let painted = h.state().doc.layout().clone();
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::S);
    h.run_steps(2);
    assert!(!h.state().doc.is_dirty(), "{:?}", h.state().message);
    for f in ["garden.json", "garden-mask.png", "garden-grass.png"] {
        assert!(dir.path().join(f).is_file(), "{f} was written");
    }
    let back = windloom::io::load(&level).unwrap();
    assert_eq!(back, painted, "the layout reads back as it was");
    assert_eq!(*mask_image(&back), *mask_image(&painted));
    assert_eq!(
        back.grass.density_map.as_ref().unwrap().pixels.image(),
        painted.grass.density_map.as_ref().unwrap().pixels.image()
    );
}

/// The backdrop, picked in the Layers list, shows its corners: a corner dragged scales it
/// from the opposite one with its aspect kept, a drag inside moves it; each one undo step.
#[test]
fn the_backdrop_is_placed_by_its_handles_with_its_aspect_kept() {
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let level = dir.path().join("level.json");
    picture(&dir.path().join("top.png"), 60, 40, [0..10, 0..10]);
    let mut doc = doc::Layout::untitled("level");
    doc.world.size = [150.0, 100.0];
    doc.world.map = Some(doc::MapBackdrop {
        image: "top.png".into(),
        opacity: 1.0,
        rect: None,
    });
    windloom::io::save(&level, &doc).unwrap();
    let mut h = harness_on(windloom::io::load(&level).unwrap(), Some(level));
    h.get_by_label("top.png").click();
    h.run_steps(2);
    assert_eq!(h.state().selection, vec![Sel::Backdrop]);
    let tol = 1.5 * metres_per_point(&h);
    // The bottom-right corner pulled in to (120, 84) m: the pointer projected on the
    // diagonal, 0.83 of it, the top-left still at 0.
    let (a, b) = (
        h.state().screen_pos([150.0, 100.0]),
        h.state().screen_pos([120.0, 84.0]),
    );
    drag(&mut h, a, b);
    let r = h.state().doc.world.map.as_ref().unwrap().rect.unwrap();
    assert!(r[0] == [0.0, 0.0], "{r:?}");
    let s = (120.0 * 150.0 + 84.0 * 100.0) / (150.0f32 * 150.0 + 100.0 * 100.0);
    assert!(
        (r[1][0] - 150.0 * s).abs() < tol && (r[1][1] - 100.0 * s).abs() < tol,
        "{r:?}"
    );
    let aspect = (r[1][0] - r[0][0]) / (r[1][1] - r[0][1]);
    assert!((aspect - 1.5).abs() < 1e-3, "aspect kept: {aspect}");
    // Dragged from inside: moved by 10 m, 5 m.
    let (a, b) = (
        h.state().screen_pos([60.0, 40.0]),
        h.state().screen_pos([70.0, 45.0]),
    );
    drag(&mut h, a, b);
    let moved = h.state().doc.world.map.as_ref().unwrap().rect.unwrap();
    assert!(
        (moved[0][0] - 10.0).abs() < tol && (moved[0][1] - 5.0).abs() < tol,
        "{moved:?}"
    );
    assert!(((moved[1][0] - moved[0][0]) - (r[1][0] - r[0][0])).abs() < 1e-3);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(
        h.state().doc.world.map.as_ref().unwrap().rect,
        Some(r),
        "one step"
    );
}
