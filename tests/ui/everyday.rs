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

/// Presses at `points[0]`, moves through every point, releases at the last.
fn drag_path(h: &mut Harness<'_, EditorApp>, points: &[Pos2]) {
    h.event(Event::PointerMoved(points[0]));
    h.run_steps(1);
    h.event(Event::PointerButton {
        pos: points[0],
        button: PointerButton::Primary,
        pressed: true,
        modifiers: Modifiers::NONE,
    });
    h.run_steps(1);
    for p in &points[1..] {
        h.event(Event::PointerMoved(*p));
        h.run_steps(1);
    }
    h.event(Event::PointerButton {
        pos: *points.last().unwrap(),
        button: PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::NONE,
    });
    h.run_steps(2);
}

#[test]
fn a_stroke_draws_an_arrow_chain_along_the_path() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(Layout::new("blank", [100.0, 80.0], [50, 40]));
    h.key_press(egui::Key::W);
    h.run_steps(1);
    assert_eq!(h.state().tool, Tool::Stroke);
    // Down a street and round its corner: (10, 10) east to (60, 10), then south to (60, 60),
    // drawn a metre at a time.
    let mut world: Vec<[f32; 2]> = (0..=50).map(|k| [10.0 + k as f32, 10.0]).collect();
    world.extend((1..=50).map(|k| [60.0, 10.0 + k as f32]));
    let screen: Vec<Pos2> = world.iter().map(|w| h.state().screen_pos(*w)).collect();
    drag_path(&mut h, &screen);
    let d = &h.state().doc;
    assert_eq!(d.trees.len(), 1, "a stroke on empty map makes a tree");
    let tree = &d.trees[0];
    let points: Vec<[f32; 2]> = tree.root.iter().map(|n| n.pos).collect();
    assert_eq!(points.len(), 3, "two arrows, round the corner: {points:?}");
    let tol = 2.0 * metres_per_point(&h);
    for (p, want) in points
        .iter()
        .zip([[10.0, 10.0], [60.0, 10.0], [60.0, 60.0]])
    {
        assert!(
            (p[0] - want[0]).abs() < tol && (p[1] - want[1]).abs() < tol,
            "{points:?}"
        );
    }
    let s = h.state().settings.stroke;
    let end = tree.root.children[0].children[0].clone();
    assert_eq!((end.strength, end.radius), (s.strength, s.radius));
    assert_eq!(h.state().selection, vec![Sel::Node(end.id)]);

    // A stroke from the chain's end continues it, west.
    let from = h.state().screen_pos(end.pos);
    let to: Vec<Pos2> = (0..=30)
        .map(|k| h.state().screen_pos([60.0 - k as f32, 60.0]))
        .collect();
    drag_path(&mut h, &[vec![from], to].concat());
    let tree = &h.state().doc.trees[0];
    assert_eq!(h.state().doc.trees.len(), 1);
    assert_eq!(tree.root.count(), 4, "one more arrow under the end point");
    // Each stroke is one undo step.
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(1);
    assert_eq!(h.state().doc.trees[0].root.count(), 3);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(1);
    assert!(h.state().doc.trees.is_empty());
}

/// The names of the editor's ambient layers, in order.
fn ambient_names(h: &Harness<'_, EditorApp>) -> Vec<String> {
    (h.state().doc.ambient.iter())
        .map(|a| a.name.clone())
        .collect()
}

/// Opens the Presets menu's `sub` menu.
fn presets_submenu(h: &mut Harness<'_, EditorApp>, sub: &str) {
    h.get_by_label("Presets").click();
    h.run_steps(2);
    // The menu's item, not the inspector's section of the same name (further down).
    let item = h
        .get_all_by_label(sub)
        .min_by(|a, b| a.rect().top().total_cmp(&b.rect().top()))
        .unwrap();
    item.hover();
    h.run_steps(2);
}

#[test]
fn presets_apply_in_one_undo_step_and_the_user_s_own_are_kept() {
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().to_path_buf();
    let mut h = harness(example("obstacles.json"));
    h.state_mut().presets.folder = Some(folder.clone());
    h.run_steps(1);
    let before = doc::to_json(&h.state().doc);

    presets_submenu(&mut h, "Wind");
    h.get_by_label("Storm").click();
    h.run_steps(2);
    assert_eq!(ambient_names(&h), ["Storm", "Storm gusts"]);
    assert_eq!(
        h.state().doc.history().undo_label(),
        Some("Apply wind preset")
    );

    presets_submenu(&mut h, "Grass");
    h.get_by_label("Wheat").click();
    h.run_steps(2);
    let wheat = doc::presets::grass("Wheat").unwrap();
    assert_eq!(h.state().doc.grass.height, wheat.height);

    // Save this wind as the user's own, then take both presets back.
    presets_submenu(&mut h, "Wind");
    h.get_by_label("Save as preset…").click();
    h.run_steps(2);
    // A name that is a path is refused in the dialog, which stays.
    h.event(Event::Text("../storm".into()));
    h.run_steps(1);
    h.get_by_label("Save").click();
    h.run_steps(2);
    h.get_by_label_contains("letters, digits");
    h.get_by_label("Cancel").click();
    h.run_steps(2);
    presets_submenu(&mut h, "Wind");
    h.get_by_label("Save as preset…").click();
    h.run_steps(2);
    h.event(Event::Text("Big storm".into()));
    h.run_steps(1);
    h.key_press(egui::Key::Enter);
    h.run_steps(2);
    let saved = folder.join("wind").join("Big storm.json");
    assert!(saved.is_file(), "{:?}", h.state().message);
    assert!(h.state().dialog.is_none(), "the dialog closes once saved");
    for _ in 0..2 {
        h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
        h.run_steps(1);
    }
    assert_eq!(
        doc::to_json(&h.state().doc),
        before,
        "two undos, two presets"
    );

    // Another layout (another session) finds it in the menu and applies it.
    let mut other = harness(example("meadow.json"));
    other.state_mut().presets.folder = Some(folder);
    other.run_steps(1);
    presets_submenu(&mut other, "Wind");
    other.get_by_label("Big storm").click();
    other.run_steps(2);
    assert_eq!(ambient_names(&other), ["Storm", "Storm gusts"]);
}

#[test]
fn probes_dropped_on_the_map_and_in_3d_plot_the_wind_and_export_it() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("obstacles.json"));
    h.key_press(egui::Key::M);
    h.run_steps(1);
    assert_eq!(h.state().tool, Tool::Probe);
    let tol = 1.5 * metres_per_point(&h);
    let at = h.state().screen_pos([40.0, 60.0]);
    click(&mut h, at);
    let p = h.state().doc.probes.clone();
    assert_eq!(p.len(), 1, "a click drops a probe");
    assert!((p[0].pos[0] - 40.0).abs() < tol && (p[0].pos[1] - 60.0).abs() < tol);
    assert_eq!(h.state().selection, vec![Sel::Probe(p[0].id)]);
    assert_eq!(h.state().doc.history().undo_label(), Some("Add probe"));

    // The wind steps on: the probe reads it, and the panel under the map says so.
    for _ in 0..6 {
        step_and_wait(&mut h, 10, RunsOn::Cpu);
        h.run_steps(1);
    }
    let readings = h.state().probe_log.records[&p[0].id].clone();
    assert!(readings.len() >= 2, "{} readings", readings.len());
    let last = readings.last().unwrap();
    assert!(
        last.speed() > 1.0,
        "the west gale blows at the probe: {last:?}"
    );
    h.get_by_label("gust factor");
    h.get_by_label("Export CSV…");

    // Export: a CSV a reader takes back, one row per reading.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p.csv");
    let ctx = h.ctx.clone();
    assert!(h.state_mut().export_probes_csv(&ctx, &out));
    let rows = csv::Reader::from_path(&out).unwrap().records().count();
    assert_eq!(rows, readings.len());

    // Dragged with the Select tool, it moves in one step.
    h.key_press(egui::Key::S);
    h.run_steps(1);
    // (The probes' panel took room from the map: where the probe is now.)
    let at = h.state().screen_pos(p[0].pos);
    let to = h.state().screen_pos([50.0, 70.0]);
    drag(&mut h, at, to);
    let moved = h.state().doc.probes[0].pos;
    assert!(
        (moved[0] - 50.0).abs() < tol && (moved[1] - 70.0).abs() < tol,
        "{moved:?}"
    );
    // Delete removes it, and the panel with it.
    h.key_press(egui::Key::Delete);
    h.run_steps(2);
    assert!(h.state().doc.probes.is_empty());
    assert!(h.query_by_label("Export CSV…").is_none());
}

#[test]
fn a_probe_drops_on_the_ground_clicked_in_the_3d_view() {
    if !gpu_available() {
        return;
    }
    let mut h = gpu_harness(example("meadow.json"), |app| {
        app.settings.central = windloom::app::Central::Grass;
        app.tool = Tool::Probe;
    });
    h.run_steps(6);
    let r = h.state().grass_view.rect.expect("the 3D view is drawn");
    let at = r.center() + egui::vec2(0.0, r.height() * 0.2);
    h.event(Event::PointerMoved(at));
    h.run_steps(2);
    let ground = h
        .state()
        .grass_view
        .hover_ground
        .expect("the pointer is over the ground");
    click(&mut h, at);
    let probes = &h.state().doc.probes;
    assert_eq!(probes.len(), 1, "a click on the ground drops a probe");
    let d = (probes[0].pos[0] - ground[0]).hypot(probes[0].pos[1] - ground[1]);
    assert!(d < 0.5, "{:?} vs {ground:?}", probes[0].pos);
}

/// A right-click with the pointer's secondary button at `pos`, in its own frames.
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
    h.run_steps(2);
}

/// Right-click menus do what a designer does to the item under the pointer, each one undo
/// step: on the map a point (duplicated, its tree selected, locked), an obstacle (hidden),
/// empty map (select all, a root placed there); in the Layers list a tree (focus on it).
#[test]
fn right_click_menus_act_on_the_item_under_the_pointer() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("obstacles.json"));
    // West gale's middle point, 102 at (30, 60).
    let p = h.state().screen_pos([30.0, 60.0]);
    right_click(&mut h, p);
    assert_eq!(
        h.state().selection,
        vec![Sel::Node(102)],
        "selected at once"
    );
    let nodes = h.state().doc.trees[0].root.count();
    h.get_by_label_contains("Duplicate it").click();
    h.run_steps(2);
    assert_eq!(
        h.state().doc.trees[0].root.count(),
        nodes + 2,
        "the point and its child"
    );
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().doc.trees[0].root.count(), nodes);
    right_click(&mut h, p);
    h.get_by_label("Select its tree, West gale").click();
    h.run_steps(2);
    assert_eq!(h.state().selection, vec![Sel::Tree(1)]);
    right_click(&mut h, p);
    h.get_by_label("Lock its tree").click();
    h.run_steps(2);
    assert!(h.state().doc.trees[0].locked);
    // The big rock (circle at 62, 60): hidden.
    let rock = h.state().screen_pos([62.0, 66.0]);
    right_click(&mut h, rock);
    assert_eq!(h.state().selection, vec![Sel::Obstacle(10)]);
    h.get_by_label("Hide it").click();
    h.run_steps(2);
    assert!(h.state().doc.obstacles[0].hidden);
    assert_eq!(
        h.state().doc.history().undo_label(),
        Some("Change obstacle")
    );
    // Empty map: select all, then a root placed where it was clicked.
    let empty = h.state().screen_pos([100.0, 100.0]);
    right_click(&mut h, empty);
    h.get_by_label_contains("Select all").click();
    h.run_steps(2);
    let all = h.state().selection.len();
    let pickable = (h.state().doc.trees.iter())
        .filter(|t| t.pickable())
        .map(|t| t.root.count())
        .sum::<usize>()
        + h.state()
            .doc
            .obstacles
            .iter()
            .filter(|o| o.pickable())
            .count();
    assert_eq!(
        all, pickable,
        "everything the map picks (not the locked, not the hidden)"
    );
    right_click(&mut h, empty);
    h.get_by_label("Add a wind tree's root here").click();
    h.run_steps(2);
    let new_root = h.state().doc.trees.last().unwrap().root.pos;
    let tol = 1.5 * metres_per_point(&h);
    assert!(
        (new_root[0] - 100.0).abs() < tol && (new_root[1] - 100.0).abs() < tol,
        "{new_root:?}"
    );
    // The Layers list: Focus on a tree frames it.
    let before = h.state().map.camera.unwrap();
    let row = h.get_by_label("South draught (3)").rect().center();
    right_click(&mut h, row);
    h.get_by_label_contains("Focus on it").click();
    h.run_steps(2);
    let after = h.state().map.camera.unwrap();
    assert!(
        after.zoom > before.zoom,
        "closer: {} > {}",
        after.zoom,
        before.zoom
    );
    let t = &h.state().doc.trees[1];
    let (lo, hi) =
        windloom::doc::transform::extent(&h.state().doc, &[windloom::doc::Item::Tree(t.id)])
            .unwrap();
    let mid = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    assert!((after.center[0] - mid[0]).abs() < 1e-3 && (after.center[1] - mid[1]).abs() < 1e-3);
}

/// Ctrl+A selects everything the map picks; the snap step is the designer's (Edit menu), and
/// a dragged point lands on it; the map's scale bar is a round length of 60 to 150 points.
#[test]
fn select_all_a_snap_step_of_one_s_own_and_a_scale_bar() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("two-winds.json"));
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::A);
    h.run_steps(2);
    assert_eq!(h.state().selection.len(), 6, "all six points");
    h.key_press(egui::Key::Escape);
    h.run_steps(1);
    h.get_by_label("Edit").click();
    h.run_steps(2);
    h.get_by_label("Snap to").click();
    h.run_steps(1);
    assert!(h.state().settings.snap);
    h.state_mut().settings.snap_step = 5.0;
    h.key_press(egui::Key::Escape);
    h.run_steps(2);
    let (a, b) = (
        h.state().screen_pos([32.0, 40.0]),
        h.state().screen_pos([43.3, 47.9]),
    );
    drag(&mut h, a, b);
    let p = h.state().doc.trees[0].root.find(102).unwrap().pos;
    assert_eq!(p, [45.0, 50.0], "on the 5 m step");
    for zoom in [0.01f32, 0.37, 1.0, 6.4, 55.0, 900.0] {
        let m = windloom::app::map_scale_bar_metres(zoom);
        let px = m * zoom;
        assert!((60.0..=150.0).contains(&px), "{zoom}: {m} m is {px} points");
        let lead = m / 10f32.powf(m.log10().floor());
        assert!(
            [1.0, 2.0, 5.0].iter().any(|l| (lead - l).abs() < 1e-3),
            "{m} is 1, 2 or 5 times a power of ten"
        );
    }
}
