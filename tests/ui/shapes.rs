//! Shapes edited on the map with the Select tool's handles: a polygon's corners dragged,
//! inserted and deleted, a circle's radius, a selection turned and scaled by its handles and
//! by typed values, and several points' strength set at once.

use super::*;
use windloom::doc::Shape;

fn corners(h: &Harness<'_, EditorApp>, id: u32) -> Vec<[f32; 2]> {
    match &h
        .state()
        .doc
        .obstacles
        .iter()
        .find(|o| o.id == id)
        .unwrap()
        .shape
    {
        Shape::Polygon { points } => points.clone(),
        s => panic!("not a polygon: {s:?}"),
    }
}

fn right_click(h: &mut Harness<'_, EditorApp>, pos: Pos2) {
    h.event(Event::PointerMoved(pos));
    h.run_steps(1);
    for pressed in [true, false] {
        h.event(Event::PointerButton {
            pos,
            button: PointerButton::Secondary,
            pressed,
            modifiers: Modifiers::NONE,
        });
        h.run_steps(1);
    }
    h.run_steps(1);
}

#[test]
fn polygon_corners_are_dragged_inserted_and_deleted_on_the_map() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("obstacles.json"));
    let tol = 1.5 * metres_per_point(&h);
    // The barn: [78, 36] [96, 36] [96, 50] [78, 50].
    h.state_mut().selection = vec![Sel::Obstacle(12)];
    h.run_steps(2);
    let from = h.state().screen_pos([78.0, 36.0]);
    let to = h.state().screen_pos([70.0, 30.0]);
    drag(&mut h, from, to);
    let c = corners(&h, 12);
    assert_eq!(c.len(), 4);
    assert!(
        (c[0][0] - 70.0).abs() < tol && (c[0][1] - 30.0).abs() < tol,
        "{c:?}"
    );
    assert_eq!(
        h.state().selection,
        vec![Sel::Obstacle(12)],
        "still selected"
    );

    // The east edge's midpoint dragged out: a fifth corner there.
    let mid = h.state().screen_pos([96.0, 43.0]);
    let out = h.state().screen_pos([104.0, 43.0]);
    drag(&mut h, mid, out);
    let c = corners(&h, 12);
    assert_eq!(c.len(), 5, "{c:?}");
    assert!(
        (c[2][0] - 104.0).abs() < tol && (c[2][1] - 43.0).abs() < tol,
        "{c:?}"
    );
    // One undo step takes the inserted corner back whole.
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(corners(&h, 12).len(), 4);

    // A right-click on a corner deletes it, down to a triangle and no further.
    for _ in 0..2 {
        let at = h.state().screen_pos(corners(&h, 12)[1]);
        right_click(&mut h, at);
    }
    assert_eq!(corners(&h, 12).len(), 3);
    let said = h.state().message.clone().map(|m| m.0).unwrap_or_default();
    assert!(said.contains("three corners"), "{said}");

    // The rock's radius handle, on its east edge: 7 m dragged to 12 m.
    h.state_mut().selection = vec![Sel::Obstacle(10)];
    h.run_steps(2);
    let edge = h.state().screen_pos([69.0, 60.0]);
    let wider = h.state().screen_pos([74.0, 60.0]);
    drag(&mut h, edge, wider);
    let Shape::Circle { radius, center } = h.state().doc.obstacles[0].shape.clone() else {
        panic!()
    };
    assert!((radius - 12.0).abs() < tol, "radius {radius}");
    assert_eq!(center, [62.0, 60.0], "the centre stays");
}

#[test]
fn a_selection_turns_and_scales_by_its_handles_and_by_typed_values() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("obstacles.json"));
    let tol = 2.0 * metres_per_point(&h);
    // The west gale's tree and the big rock.
    let items = [doc::Item::Tree(1), doc::Item::Obstacle(10)];
    h.state_mut().selection = vec![Sel::Tree(1), Sel::Obstacle(10)];
    h.run_steps(2);
    let (lo, hi) = doc::transform::extent(&h.state().doc, &items).unwrap();
    let pivot = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    let before = h.state().doc.layout().clone();

    // The scale handle (the box's bottom-right, 10 points out) dragged twice as far out.
    let corner = h.state().screen_pos(hi) + egui::vec2(10.0, 10.0);
    let centre = h.state().screen_pos(pivot);
    drag(&mut h, corner, centre + (corner - centre) * 2.0);
    let Shape::Circle { radius, .. } = h.state().doc.obstacles[0].shape else {
        panic!()
    };
    assert!((radius - 14.0).abs() < 0.1, "the rock doubles: {radius}");
    let root = h.state().doc.trees[0].root.pos;
    let was = before.trees[0].root.pos;
    let want = [
        pivot[0] + 2.0 * (was[0] - pivot[0]),
        pivot[1] + 2.0 * (was[1] - pivot[1]),
    ];
    assert!((root[0] - want[0]).abs() < 2.0 * tol && (root[1] - want[1]).abs() < 2.0 * tol);
    assert_eq!(
        h.state().doc.trees[1],
        before.trees[1],
        "what is not selected stays"
    );
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(doc::to_json(&h.state().doc), doc::to_json(&before));

    // The rotate handle, above the box, dragged a quarter turn round with Shift (15° steps).
    let (lo, hi) = doc::transform::extent(&h.state().doc, &items).unwrap();
    let top = egui::pos2(
        (h.state().screen_pos(lo).x + h.state().screen_pos(hi).x) / 2.0,
        h.state().screen_pos(lo).y - 10.0 - 26.0,
    );
    let r = top.distance(centre);
    h.event(Event::PointerMoved(top));
    h.event(Event::ModifiersChanged(Modifiers::SHIFT));
    h.run_steps(1);
    h.event(Event::PointerButton {
        pos: top,
        button: PointerButton::Primary,
        pressed: true,
        modifiers: Modifiers::SHIFT,
    });
    h.run_steps(1);
    for k in 1..=8 {
        let a = -std::f32::consts::FRAC_PI_2 + k as f32 / 8.0 * std::f32::consts::FRAC_PI_2 * 1.02;
        let p = centre + egui::vec2(a.cos(), a.sin()) * r;
        h.event(Event::PointerMoved(p));
        h.run_steps(1);
    }
    h.event(Event::PointerButton {
        pos: centre + egui::vec2(r, 0.0),
        button: PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::SHIFT,
    });
    h.event(Event::ModifiersChanged(Modifiers::NONE));
    h.run_steps(2);
    let root = h.state().doc.trees[0].root.pos;
    let d = [was[0] - pivot[0], was[1] - pivot[1]];
    let want = [pivot[0] - d[1], pivot[1] + d[0]];
    assert!(
        (root[0] - want[0]).abs() < 1e-2 && (root[1] - want[1]).abs() < 1e-2,
        "a quarter turn, snapped: {root:?} vs {want:?}"
    );
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);

    // Typed: the inspector's Rotate (90° by default) does the same in one step.
    h.get_by_label("Rotate").click();
    h.run_steps(2);
    let root = h.state().doc.trees[0].root.pos;
    assert!((root[0] - want[0]).abs() < 1e-3 && (root[1] - want[1]).abs() < 1e-3);
    assert_eq!(h.state().doc.history().undo_label(), Some("Rotate"));
}

#[test]
fn several_points_take_one_strength() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("obstacles.json"));
    h.state_mut().selection = vec![Sel::Node(102), Sel::Node(105), Sel::Node(108)];
    h.run_steps(2);
    assert_eq!(h.get_all_by_label_contains("they differ").count(), 2);
    // The Strength field of the points: typed into.
    let row = h.get_by_label("Strength").rect().center().y;
    let field = h
        .get_all_by_role(egui::accesskit::Role::SpinButton)
        .find(|f| (f.rect().center().y - row).abs() < 4.0)
        .expect("the points' strength field")
        .rect()
        .center();
    click(&mut h, field);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::A);
    h.event(Event::Text("13".into()));
    h.key_press(egui::Key::Enter);
    h.run_steps(3);
    let d = &h.state().doc;
    let s: Vec<f32> = [102, 105, 108]
        .iter()
        .map(|id| d.nodes().find(|(_, n)| n.id == *id).unwrap().1.strength)
        .collect();
    assert_eq!(s, [13.0, 13.0, 13.0]);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(
        doc::to_json(&h.state().doc),
        doc::to_json(&example("obstacles.json"))
    );
}
