//! A map that holds still: panels keep their width whatever they show, a panel coming or
//! going beside the map moves nothing on it, a click that closes a menu never reaches the
//! map, and drags and clicks land where they were released at a low frame rate (a whole
//! gesture handed over in one frame, as a window at a few frames a second does).

use super::*;

/// Feeds `frames` to the editor as a slow window would (each inner list arrives in one
/// frame), through the editor's own pacing of events (`EditorApp::pace`, which the window
/// runs before each frame), and draws frames until nothing is held back.
fn slow_frames(h: &mut Harness<'_, EditorApp>, frames: Vec<Vec<Event>>) {
    for frame in frames {
        let mut events = frame;
        loop {
            let held = h.state_mut().pace(&mut events);
            // Into one frame's input (`Harness::event` would give each event a frame).
            h.input_mut().events.append(&mut events);
            h.step();
            if !held {
                break;
            }
        }
    }
    h.run_steps(2);
}

fn button(pos: Pos2, pressed: bool) -> Event {
    Event::PointerButton {
        pos,
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    }
}

/// A point's position in the layout.
fn node_pos(h: &Harness<'_, EditorApp>, id: u32) -> [f32; 2] {
    h.state()
        .doc
        .trees
        .iter()
        .find_map(|t| t.root.find(id))
        .expect("the point")
        .pos
}

/// Moves at a few frames a second: a quick drag in one frame, a slow one over three, a
/// circle's radius by its handle, an arrow dragged out and a click in one frame each land
/// where the pointer was released (before, the quick drag was lost and the others landed
/// short by what moved in their first and last frames).
#[test]
fn drags_and_clicks_at_a_low_frame_rate_land_where_released() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("obstacles.json"));
    let tol = 0.75 * metres_per_point(&h);
    let close = |a: [f32; 2], b: [f32; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) < tol;

    // A quick drag: press, movement and release in one frame.
    let (from, to) = (node_pos(&h, 101), [20.0, 50.0]);
    let (a, b) = (h.state().screen_pos(from), h.state().screen_pos(to));
    slow_frames(
        &mut h,
        vec![vec![
            Event::PointerMoved(a),
            button(a, true),
            Event::PointerMoved(a + (b - a) * 0.5),
            Event::PointerMoved(b),
            button(b, false),
        ]],
    );
    assert!(
        close(node_pos(&h, 101), to),
        "quick drag: {:?}",
        node_pos(&h, 101)
    );
    assert_eq!(h.state().doc.history().undo_label(), Some("Move node"));

    // A slow drag over three frames, movement in each.
    let (from, to) = (to, [30.0, 40.0]);
    let (a, b) = (h.state().screen_pos(from), h.state().screen_pos(to));
    let at = |t: f32| a + (b - a) * t;
    slow_frames(
        &mut h,
        vec![
            vec![
                Event::PointerMoved(a),
                button(a, true),
                Event::PointerMoved(at(0.3)),
            ],
            vec![Event::PointerMoved(at(0.6))],
            vec![
                Event::PointerMoved(at(0.9)),
                Event::PointerMoved(b),
                button(b, false),
            ],
        ],
    );
    assert!(
        close(node_pos(&h, 101), to),
        "slow drag: {:?}",
        node_pos(&h, 101)
    );

    // A circle's radius handle (on its east edge), dragged out quickly.
    h.state_mut().selection = vec![Sel::Obstacle(10)];
    h.run_steps(2);
    let edge = h.state().screen_pos([69.0, 60.0]);
    let out = h.state().screen_pos([74.0, 60.0]);
    slow_frames(
        &mut h,
        vec![vec![
            Event::PointerMoved(edge),
            button(edge, true),
            Event::PointerMoved(out),
            button(out, false),
        ]],
    );
    let radius = match h.state().doc.obstacles[0].shape {
        doc::Shape::Circle { radius, .. } => radius,
        _ => unreachable!(),
    };
    assert!((radius - 12.0).abs() < tol, "radius {radius}");

    // An arrow dragged out of a point in one frame ends where the button came up.
    h.key_press(egui::Key::A);
    h.run_steps(2);
    let tip = node_pos(&h, 101);
    let (a, b) = (
        h.state().screen_pos(tip),
        h.state().screen_pos([30.0, 20.0]),
    );
    let before = h.state().doc.trees[0].root.count();
    slow_frames(
        &mut h,
        vec![vec![
            Event::PointerMoved(a),
            button(a, true),
            Event::PointerMoved(b),
            button(b, false),
        ]],
    );
    assert_eq!(
        h.state().doc.trees[0].root.count(),
        before + 1,
        "an arrow was added"
    );
    let [Sel::Node(new)] = h.state().selection[..] else {
        panic!("the new point is selected: {:?}", h.state().selection);
    };
    assert!(
        close(node_pos(&h, new), [30.0, 20.0]),
        "{:?}",
        node_pos(&h, new)
    );

    // A click in one frame selects.
    h.key_press(egui::Key::S);
    h.run_steps(2);
    let p = h.state().screen_pos(node_pos(&h, 104));
    slow_frames(
        &mut h,
        vec![vec![
            Event::PointerMoved(p),
            button(p, true),
            button(p, false),
        ]],
    );
    assert_eq!(h.state().selection, vec![Sel::Node(104)]);
}

/// A click outside an open menu closes it and does nothing else: with Add root, the click
/// that closes the View menu adds no tree; the next click does.
#[test]
fn a_click_that_closes_a_menu_never_reaches_the_map() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("two-winds.json"));
    h.key_press(egui::Key::R);
    h.run_steps(2);
    h.get_by_label("View").click();
    h.run_steps(2);
    assert!(egui::Popup::is_any_open(&h.ctx), "the View menu is open");
    let p = h.state().screen_pos([20.0, 70.0]);
    click(&mut h, p);
    h.run_steps(2);
    assert!(!egui::Popup::is_any_open(&h.ctx), "the click closed it");
    assert_eq!(h.state().doc.trees.len(), 2, "and added no tree");
    click(&mut h, p);
    h.run_steps(2);
    assert_eq!(h.state().doc.trees.len(), 3, "the next click adds one");
}

/// The first probe opens its panel under the map: nothing on the map moves or rescales
/// (before, the map was refitted into the smaller pane between two clicks); the panel folds
/// to one line of readings and unfolds, and the map holds still each time. A file the
/// inspector cannot read is said inside the inspector's width, which does not change.
#[test]
fn panels_that_come_and_go_move_nothing_on_the_map() {
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let level = dir.path().join("level.json");
    windloom::io::save(&level, &example("two-winds.json")).unwrap();
    let mut h = harness_on(windloom::io::load(&level).unwrap(), Some(level));
    h.run_steps(2);
    let root = h.state().doc.trees[0].root.pos;
    let seen = |h: &Harness<'_, EditorApp>| h.state().screen_pos(root);
    let (at, rect, zoom) = (
        seen(&h),
        h.state().map.rect,
        h.state().map.camera.unwrap().zoom,
    );
    let still = |h: &Harness<'_, EditorApp>, what: &str| {
        assert!(
            seen(h).distance(at) < 0.5,
            "{what}: {:?} moved to {:?}",
            at,
            seen(h)
        );
        assert_eq!(h.state().map.camera.unwrap().zoom, zoom, "{what}: rescaled");
    };

    h.key_press(egui::Key::M);
    h.run_steps(2);
    let p = h.state().screen_pos([60.0, 20.0]);
    click(&mut h, p);
    h.run_steps(3);
    assert_eq!(h.state().doc.probes.len(), 1);
    assert!(
        h.state().map.rect.height() < rect.height(),
        "the probes' panel is open"
    );
    still(&h, "the first probe");
    h.get_by_label("Probes").click();
    h.run_steps(3);
    assert!(!h.state().settings.probes_open, "folded");
    still(&h, "folded");
    h.get_by_label("Probes").click();
    h.run_steps(3);
    assert!(h.state().settings.probes_open, "open again");
    still(&h, "unfolded");

    // A long path that cannot be read: the warning wraps; the inspector keeps its width.
    h.key_press(egui::Key::Escape);
    h.run_steps(2);
    let right = h.state().map.rect.right();
    h.get_by_label("Grass").click();
    h.run_steps(2);
    h.get_by_label("Density map").focus();
    h.run_steps(1);
    let long = format!("{}/grass.png", "a-folder-that-is-not-there".repeat(6));
    h.get_by_label("Density map").type_text(&long);
    h.key_press(egui::Key::Enter);
    h.run_steps(3);
    assert!(
        h.query_by_label_contains("Not read: density map grass.png")
            .is_some(),
        "the warning names the file"
    );
    assert_eq!(
        h.state().map.rect.right(),
        right,
        "the inspector kept its width"
    );
    still(&h, "a long warning");
}
