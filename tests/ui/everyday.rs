//! Everyday editing: copy and paste through the system clipboard (within a layout and into
//! another), the arrow keys nudging the selection, and lock and hide in the Layers list.

use super::*;
use eframe::egui::OutputCommand;

/// The text the last frame put on the system clipboard.
fn copied_text(h: &Harness<'_, EditorApp>) -> Option<String> {
    (h.output().platform_output.commands.iter()).find_map(|c| match c {
        OutputCommand::CopyText(t) => Some(t.clone()),
        _ => None,
    })
}

#[test]
fn copy_and_paste_go_through_the_system_clipboard_with_fresh_ids() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("obstacles.json"));
    h.state_mut().selection = vec![Sel::Node(101), Sel::Obstacle(10)];
    h.run_steps(1);
    // Ctrl+C reaches the app as the integration's Copy event.
    h.event(Event::Copy);
    h.step();
    let text = copied_text(&h).expect("Copy puts the selection on the clipboard");
    let copied = doc::parse(&text).expect("the clipboard holds a layout");
    assert_eq!((copied.trees.len(), copied.obstacles.len()), (1, 1));

    // Into another layout (another editor), with the pointer off the map: in place.
    let mut other = harness(example("two-winds.json"));
    let before = doc::to_json(&other.state().doc);
    other.event(Event::Paste(text.clone()));
    other.run_steps(2);
    let d = &other.state().doc;
    assert_eq!((d.trees.len(), d.obstacles.len()), (3, 1));
    let west_gale = d.trees.last().unwrap();
    assert_eq!(west_gale.name, "West gale");
    assert_eq!(west_gale.root.pos, [6.0, 58.0], "pasted in place");
    let pasted = [
        Sel::Node(west_gale.root.id),
        Sel::Obstacle(d.obstacles[0].id),
    ];
    assert_eq!(
        other.state().selection,
        pasted,
        "the pasted items are selected"
    );
    let mut all: Vec<u32> = d.nodes().map(|(_, n)| n.id).collect();
    all.extend(d.trees.iter().map(|t| t.id));
    all.sort();
    let n = all.len();
    all.dedup();
    assert_eq!(all.len(), n, "ids are remapped: none clashes");
    other.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    other.run_steps(2);
    assert_eq!(
        doc::to_json(&other.state().doc),
        before,
        "one undo takes it out"
    );

    // Back into its own layout at the pointer: the copy's middle under it.
    let at = h.state().screen_pos([60.0, 30.0]);
    h.event(Event::PointerMoved(at));
    h.run_steps(1);
    h.event(Event::Paste(text));
    h.run_steps(2);
    let d = &h.state().doc;
    assert_eq!((d.trees.len(), d.obstacles.len()), (4, 5));
    let centre = doc::clipboard::centre(
        &doc::clipboard::copy(
            d,
            &[
                doc::clipboard::Item::Tree(d.trees[3].id),
                doc::clipboard::Item::Obstacle(d.obstacles[4].id),
            ],
        )
        .unwrap(),
    )
    .unwrap();
    let tol = 1.5 * metres_per_point(&h);
    assert!(
        (centre[0] - 60.0).abs() < tol && (centre[1] - 30.0).abs() < tol,
        "pasted around the pointer: {centre:?}"
    );

    // Text that is no layout changes nothing and says why.
    let before = doc::to_json(&h.state().doc);
    h.event(Event::Paste("not a layout".into()));
    h.run_steps(2);
    assert_eq!(doc::to_json(&h.state().doc), before);
    let said = h.state().message.clone().map(|m| m.0).unwrap_or_default();
    assert!(said.contains("no windloom layout"), "{said}");
}

#[test]
fn arrow_keys_nudge_the_selection_and_pan_the_map_without_one() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("obstacles.json"));
    let start = h.state().doc.trees[0].root.children[0].pos;
    h.state_mut().selection = vec![Sel::Node(102), Sel::Obstacle(10)];
    h.run_steps(1);
    let camera = h.state().map.camera;
    h.key_press(egui::Key::ArrowRight);
    h.run_steps(1);
    h.key_press_modifiers(Modifiers::SHIFT, egui::Key::ArrowDown);
    h.run_steps(1);
    let d = &h.state().doc;
    let end = d.trees[0].root.children[0].pos;
    assert_eq!([end[0] - start[0], end[1] - start[1]], [1.0, 10.0]);
    assert_eq!(
        d.obstacles[0].shape,
        doc::Shape::Circle {
            center: [63.0, 70.0],
            radius: 7.0
        },
        "the obstacle moves with it"
    );
    assert_eq!(
        camera,
        h.state().map.camera,
        "the map does not pan meanwhile"
    );
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(1);
    let back = h.state().doc.trees[0].root.children[0].pos;
    assert_eq!(
        back,
        [start[0] + 1.0, start[1]],
        "each nudge is its own undo step"
    );

    // Nothing selected: the arrow keys pan.
    h.state_mut().selection.clear();
    h.run_steps(1);
    let before = h.state().map.camera.unwrap().center;
    let json = doc::to_json(&h.state().doc);
    h.key_down(egui::Key::ArrowLeft);
    h.run_steps(3);
    h.key_up(egui::Key::ArrowLeft);
    h.run_steps(1);
    let after = h.state().map.camera.unwrap().center;
    assert!(
        after[0] < before[0],
        "the view pans west: {before:?} -> {after:?}"
    );
    assert_eq!(doc::to_json(&h.state().doc), json);
}

#[test]
fn locked_and_hidden_items_stay_put_on_the_map() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("obstacles.json"));
    // The Layers list: trees first (three), then obstacles; lock the first obstacle.
    let lock = h.get_all_by_label("lock").nth(3).expect("a lock per layer");
    lock.click();
    h.run_steps(2);
    assert!(h.state().doc.obstacles[0].locked);
    // A click on it on the map does not pick it; a drag does not move it.
    let rock = h.state().screen_pos([62.0, 60.0]);
    click(&mut h, rock);
    assert!(!h.state().selection.contains(&Sel::Obstacle(10)));
    drag(&mut h, rock, rock + egui::vec2(40.0, 0.0));
    assert_eq!(
        h.state().doc.obstacles[0].shape,
        example("obstacles.json").obstacles[0].shape
    );
    // Selected in the list, the inspector shows it without changing it.
    h.state_mut().selection = vec![Sel::Obstacle(10)];
    h.run_steps(2);
    h.get_by_label_contains("Locked: unlock it");

    // Hide the first tree: its root is not picked, and it still blows.
    let hide = h.get_all_by_label("hide").next().expect("a hide per layer");
    hide.click();
    h.run_steps(2);
    assert!(h.state().doc.trees[0].hidden && h.state().doc.trees[0].enabled);
    h.state_mut().selection.clear();
    let root = h.state().screen_pos([6.0, 58.0]);
    click(&mut h, root);
    assert!(h.state().selection.is_empty(), "{:?}", h.state().selection);

    // Both are edits: undone in turn.
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(1);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(1);
    let d = &h.state().doc;
    assert!(!d.trees[0].hidden && !d.obstacles[0].locked);
}
