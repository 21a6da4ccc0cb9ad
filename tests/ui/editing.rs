//! Authoring with the mouse and the inspector: a tree drawn, edited and undone, the
//! inspector's warnings and choices, the map under the pointer, the map image, and the
//! toolbar's layout in a narrow window.

use super::*;

#[test]
fn authoring_a_tree_with_the_mouse_then_inspector_and_undo() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(Layout::new("blank", [100.0, 80.0], [50, 40]));
    let tol = 1.5 * metres_per_point(&h);

    // Root tool: click on the map → a tree whose root is where we clicked.
    h.get_by_label("Add root").click();
    h.run_steps(2);
    assert_eq!(h.state().tool, Tool::AddRoot);
    let at = h.state().screen_pos([30.0, 40.0]);
    click(&mut h, at);
    let doc = &h.state().doc;
    assert_eq!(doc.trees.len(), 1, "a click with the root tool adds a tree");
    let root = doc.trees[0].root.clone();
    assert!(
        (root.pos[0] - 30.0).abs() < tol && (root.pos[1] - 40.0).abs() < tol,
        "root at {:?}",
        root.pos
    );

    // Drag out of the root (the tool switched to Add arrow) → a child, the arrow pointing east.
    assert_eq!(h.state().tool, Tool::AddArrow);
    let from = h.state().screen_pos(root.pos);
    let to = h.state().screen_pos([60.0, 40.0]);
    drag(&mut h, from, to);
    let root = h.state().doc.trees[0].root.clone();
    assert_eq!(
        root.children.len(),
        1,
        "dragging from the root adds an end point"
    );
    let child = &root.children[0];
    assert!(
        (child.pos[0] - 60.0).abs() < tol && (child.pos[1] - 40.0).abs() < tol,
        "child at {:?}",
        child.pos
    );
    assert!(child.pos[0] - root.pos[0] > 25.0, "the arrow points east");
    assert_eq!(h.state().selection, vec![Sel::Node(child.id)]);

    // A second drag from the same root branches.
    let to2 = h.state().screen_pos([55.0, 20.0]);
    drag(&mut h, from, to2);
    assert_eq!(
        h.state().doc.trees[0].root.children.len(),
        2,
        "a second arrow branches"
    );
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().doc.trees[0].root.children.len(), 1);
    h.state_mut().selection = vec![Sel::Node(child.id)];
    h.run_steps(2);

    // Inspector: the strength slider changes the node.
    let before = child.strength;
    let inspector_left = h.state().map.rect.right();
    let slider = h
        .get_all_by_role(egui::accesskit::Role::Slider)
        .find(|s| s.rect().left() > inspector_left)
        .expect("the inspector shows the strength slider");
    let r = slider.rect();
    let target = Pos2::new(r.left() + r.width() * 0.9, r.center().y);
    click(&mut h, target);
    let after = h.state().doc.trees[0].root.children[0].strength;
    assert!(after > before + 10.0, "strength {before} -> {after}");

    // Undo restores it, then the arrow, then the tree; redo brings the arrow back.
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().doc.trees[0].root.children[0].strength, before);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert!(h.state().doc.trees[0].root.children.is_empty());
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert!(h.state().doc.trees.is_empty());
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, egui::Key::Z);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Y);
    h.run_steps(2);
    assert_eq!(h.state().doc.trees[0].root.children.len(), 1);
    assert!(
        h.state().doc.is_dirty(),
        "an edited document is marked dirty"
    );
}

/// The inspector says when the simulation settings are known to run away (MacCormack with
/// vorticity above 2), in words naming the field, and says nothing for the examples.
#[test]
fn the_inspector_warns_of_settings_that_run_away() {
    if !gpu_available() {
        return;
    }
    let warning = "Vorticity 3 with MacCormack advection can drive the wind";
    let mut h = harness(example("obstacles.json"));
    assert!(h.query_by_label_contains(warning).is_none());
    let mut sim = h.state().doc.sim;
    sim.advection = doc::Advection::MacCormack;
    sim.vorticity = 3.0;
    h.state_mut().doc.apply(doc::Edit::SetSim(sim)).unwrap();
    h.run_steps(2);
    assert!(
        h.query_by_label_contains(warning).is_some(),
        "the inspector shows the advice"
    );
    // So does the export dialog, before a bake ships such wind.
    let bake_warning = "Warning: sim.vorticity: 3 with MacCormack advection";
    assert!(h.query_by_label_contains(bake_warning).is_none());
    h.state_mut().export.open = true;
    h.run_steps(2);
    assert!(
        h.query_by_label_contains(bake_warning).is_some(),
        "the export dialog shows the advice"
    );
    sim.vorticity = 0.5;
    h.state_mut().doc.apply(doc::Edit::SetSim(sim)).unwrap();
    h.run_steps(2);
    assert!(
        h.query_by_label_contains("MacCormack advection can drive")
            .is_none()
    );
}

/// The ambient layers' pull on the wind is a slider beside the arrows' response, shown only
/// where there are ambient layers to pull (a layout without them has nothing it would do).
#[test]
fn the_ambient_pull_is_in_the_inspector_where_there_are_ambient_layers() {
    if !gpu_available() {
        return;
    }
    let shown = |name: &str| {
        let h = harness(example(name));
        assert!(h.query_all_by_label("Arrow response").count() > 0);
        h.query_all_by_label("Ambient pull").count() > 0
    };
    assert!(!shown("branching.json"), "no ambient layer");
    assert!(shown("breeze-fft.json"), "an FFT layer");
}

/// Ctrl+D copies the selection beside it, 3 m off, with new ids and names that tell the
/// copy from the original in the Layers list ("Boulder copy", as a tree's copy was already
/// named); one undo step takes the copies away.
#[test]
fn a_duplicate_is_named_apart_from_its_original() {
    let ctx = egui::Context::default();
    let mut app = EditorApp::new(example("obstacles.json"), None, &ctx);
    let before = doc::to_json(&app.doc);
    let rock = app.doc.obstacles[1].clone();
    let tree = app.doc.trees[0].clone();
    app.selection = vec![Sel::Obstacle(rock.id), Sel::Node(tree.root.id)];
    app.duplicate_selection(&ctx);
    let copy = app.doc.obstacles.last().unwrap().clone();
    assert_eq!(copy.name, format!("{} copy", rock.name));
    assert_ne!(copy.id, rock.id);
    match (&rock.shape, &copy.shape) {
        (doc::Shape::Circle { center: a, .. }, doc::Shape::Circle { center: b, .. }) => {
            assert_eq!([b[0] - a[0], b[1] - a[1]], [3.0, 3.0]);
        }
        (a, b) => panic!("{a:?} copied as {b:?}"),
    }
    let tree_copy = app.doc.trees.last().unwrap();
    assert_eq!(tree_copy.name, format!("{} copy", tree.name));
    assert_ne!(tree_copy.root.id, tree.root.id);
    assert!(doc::validate(&app.doc).is_empty(), "ids stay unique");
    app.undo();
    assert_eq!(doc::to_json(app.doc.layout()), before, "one undo step");
}

/// The simulation's and the grass's choices read as words a designer knows (not the Rust
/// spelling: "SemiLagrangian", "CwdQuadratic"), and picking one by clicking is one undo step.
#[test]
fn the_inspector_s_choices_read_as_words_and_switch_by_clicking() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("meadow.json"));
    h.run_steps(2);
    let shown = |h: &Harness<'_, EditorApp>, label: &str| h.get_by_label(label).value();
    for (label, value) in [
        ("Pressure solve", "Multigrid"),
        ("Boundary", "Open"),
        ("Advection", "Semi-Lagrangian"),
    ] {
        assert_eq!(shown(&h, label).as_deref(), Some(value), "{label}");
    }
    h.get_by_label("Advection").click();
    h.run_steps(2);
    h.get_by_label("MacCormack").click();
    h.run_steps(2);
    assert_eq!(h.state().doc.sim.advection, doc::Advection::MacCormack);
    assert_eq!(shown(&h, "Advection").as_deref(), Some("MacCormack"));

    h.get_by_label("Boundary").click();
    h.run_steps(2);
    h.get_by_label("Periodic (tiles)").click();
    h.run_steps(2);
    assert_eq!(h.state().doc.sim.boundary, doc::Boundary::Periodic);

    // The grass model, in its collapsed section.
    h.get_by_label("Grass").click();
    h.run_steps(2);
    assert_eq!(shown(&h, "Model").as_deref(), Some("CWD quadratic"));
    // Scrolled into view as a user would (the section ends below the window).
    for _ in 0..20 {
        if h.get_by_label("Model").rect().bottom() < 760.0 {
            break;
        }
        h.get_by_label("Model").scroll_down();
        h.run_steps(2);
    }
    h.get_by_label("Model").click();
    h.run_steps(2);
    h.get_by_label("Bezier physics").click();
    h.run_steps(2);
    assert_eq!(h.state().doc.grass.model, doc::GrassModel::BezierPhysics);

    // Each pick is its own undo step, undone in turn.
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().doc.grass.model, doc::GrassModel::CwdQuadratic);
    assert_eq!(h.state().doc.sim.boundary, doc::Boundary::Periodic);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().doc.sim.boundary, doc::Boundary::Open);
    assert_eq!(h.state().doc.sim.advection, doc::Advection::MacCormack);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().doc.sim.advection, doc::Advection::SemiLagrangian);
}

/// The map does not move under the pointer when the selection changes: the side panels keep
/// their widths whatever the inspector shows (a node, an obstacle, nothing), so a click that
/// adds a root and the drag that follows from it land on the same world point.
#[test]
fn the_map_stays_put_when_the_selection_changes() {
    if !gpu_available() {
        return;
    }
    let doc = example("obstacles.json");
    let node = doc.trees[0].root.children[0].id;
    let obstacle = doc.obstacles[0].id;
    let mut h = harness(doc);
    let still = h.state().map.rect;
    for sel in [
        vec![Sel::Node(node)],
        vec![Sel::Obstacle(obstacle)],
        vec![Sel::Tree(h.state().doc.trees[1].id)],
        vec![],
    ] {
        h.state_mut().selection = sel.clone();
        h.run_steps(3);
        assert_eq!(
            h.state().map.rect,
            still,
            "the map moved with {sel:?} selected"
        );
    }
}

/// The level's picture is set from the inspector (typed, committed on Enter), as one undo
/// step, and cleared the same way; the map then loads it from beside the layout.
#[test]
fn the_map_image_is_set_in_the_inspector() {
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let level = dir.path().join("level.json");
    windloom::io::save(&level, &example("obstacles.json")).unwrap();
    image::RgbaImage::from_pixel(64, 64, image::Rgba([90, 140, 60, 255]))
        .save(dir.path().join("top-down.png"))
        .unwrap();
    let mut h = harness_on(windloom::io::load(&level).unwrap(), Some(level.clone()));
    let type_in = |h: &mut Harness<'_, EditorApp>, text: &str| {
        h.get_by_label("Map image").focus();
        h.run_steps(1);
        h.key_press_modifiers(Modifiers::COMMAND, egui::Key::A);
        h.run_steps(1);
        if text.is_empty() {
            h.key_press(egui::Key::Backspace);
        } else {
            h.get_by_label("Map image").type_text(text);
        }
        h.run_steps(1);
        h.key_press(egui::Key::Enter);
        h.run_steps(2);
    };
    type_in(&mut h, "top-down.png");
    let map = h.state().doc.world.map.clone().expect("a map image");
    assert_eq!((map.image.as_str(), map.opacity), ("top-down.png", 1.0));
    assert!(h.state().doc.is_dirty());
    // It loads from the layout's folder: no "could not read" message, as a missing one gets.
    assert!(h.query_by_label_contains("shown without it").is_none());
    type_in(&mut h, "missing.png");
    assert!(h.query_by_label_contains("shown without it").is_some());
    h.state_mut().undo();
    h.run_steps(2);
    h.state_mut().undo();
    h.run_steps(2);
    assert_eq!(h.state().doc.world.map, None, "one undo step");
    h.state_mut().redo();
    h.run_steps(2);
    assert!(h.state().doc.world.map.is_some());
    type_in(&mut h, "");
    assert_eq!(h.state().doc.world.map, None, "an empty field clears it");
}

/// In a narrow window the toolbar wraps onto a row of its own under the menus instead of
/// running off the right edge (where the view buttons were lost); in a wide one it shares the
/// menus' row.
#[test]
fn a_narrow_window_wraps_the_toolbar_instead_of_hiding_it() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("obstacles.json"));
    let row = |h: &Harness<'_, EditorApp>, label: &str| h.get_by_label(label).rect();
    let file = row(&h, "File");
    for label in ["Select", "Map + 3D"] {
        assert!(
            (row(&h, label).center().y - file.center().y).abs() < 2.0,
            "{label} beside the menus in a wide window"
        );
    }
    h.set_size(egui::vec2(900.0, 700.0));
    h.run_steps(4);
    for label in ["Select", "Reset", "Wind:", "3D grass", "Map + 3D"] {
        let r = row(&h, label);
        assert!(
            r.right() <= 900.0 && r.top() > file.bottom() - 1.0,
            "{label} at {r:?}: on screen, under the menus"
        );
    }
    assert!(h.state().map.rect.top() > row(&h, "Map + 3D").bottom());
    h.set_size(egui::vec2(1280.0, 800.0));
    h.run_steps(4);
    assert!((row(&h, "Map + 3D").center().y - file.center().y).abs() < 2.0);
}

#[test]
fn dragging_a_node_moves_it_in_one_undo_step() {
    if !gpu_available() {
        return;
    }
    let doc = example("meadow.json");
    let node = doc.trees[0].root.children[0].clone();
    let mut h = harness(doc);
    let tol = 1.5 * metres_per_point(&h);
    let from = h.state().screen_pos(node.pos);
    let to = h
        .state()
        .screen_pos([node.pos[0] + 10.0, node.pos[1] + 5.0]);
    drag(&mut h, from, to);
    let moved = h.state().doc.trees[0].root.children[0].pos;
    assert!(
        (moved[0] - node.pos[0] - 10.0).abs() < tol && (moved[1] - node.pos[1] - 5.0).abs() < tol,
        "{moved:?}"
    );
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(
        h.state().doc.trees[0].root.children[0].pos,
        node.pos,
        "one undo undoes the whole drag"
    );
}

/// The pointer moving onto `pos`, pressed and released there, all within one frame (a quick
/// click while frames are slow).
fn click_in_one_frame(h: &mut Harness<'_, EditorApp>, pos: Pos2) {
    let button = |pressed| Event::PointerButton {
        pos,
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    };
    h.input_mut()
        .events
        .extend([Event::PointerMoved(pos), button(true), button(false)]);
    h.step();
    h.run_steps(2);
}

/// A quick click across one slow frame: pressed in one frame, released in the next, which
/// began `secs` later (egui times a press by the frames it arrives in).
fn click_across_a_slow_frame(h: &mut Harness<'_, EditorApp>, pos: Pos2, secs: f64) {
    let button = |pressed| Event::PointerButton {
        pos,
        button: PointerButton::Primary,
        pressed,
        modifiers: Modifiers::NONE,
    };
    let now = h.ctx.input(|i| i.time);
    h.input_mut().time = Some(now + 0.02);
    h.input_mut()
        .events
        .extend([Event::PointerMoved(pos), button(true)]);
    h.step();
    h.input_mut().time = Some(now + 0.02 + secs);
    h.input_mut().events.push(button(false));
    h.step();
    h.run_steps(2);
}

/// A press and a release that arrive in one slow frame, or either side of one, still act: a
/// toolbar button, a menu item, a click on the map with the root tool.
#[test]
fn a_click_within_one_frame_is_not_lost() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(Layout::new("blank", [100.0, 80.0], [50, 40]));
    // The toolbar.
    let at = h.get_by_label("3D grass").rect().center();
    click_in_one_frame(&mut h, at);
    assert_eq!(h.state().settings.central, windloom::app::Central::Grass);
    let at = h.get_by_label("Map").rect().center();
    click_in_one_frame(&mut h, at);
    assert_eq!(h.state().settings.central, windloom::app::Central::Map);
    // A menu item: the View menu opened, then its item clicked within a frame.
    let at = h.get_by_label("View").rect().center();
    click_in_one_frame(&mut h, at);
    let item = h
        .get_all_by_label("Map + 3D")
        .map(|n| n.rect())
        .find(|r| r.top() > 30.0)
        .expect("the View menu's item");
    click_in_one_frame(&mut h, item.center());
    assert_eq!(h.state().settings.central, windloom::app::Central::Split);
    h.state_mut().settings.central = windloom::app::Central::Map;
    h.run_steps(2);
    // The map, with the root tool.
    let at = h.get_by_label("Add root").rect().center();
    click_in_one_frame(&mut h, at);
    assert_eq!(h.state().tool, Tool::AddRoot);
    let at = h.state().screen_pos([30.0, 40.0]);
    click_in_one_frame(&mut h, at);
    assert_eq!(h.state().doc.trees.len(), 1, "the map click added a tree");

    // Released in the frame after a 1.5 s frame (the 3D view's first frame on a software
    // adapter, a big grid's rebuild): still a click.
    let at = h.get_by_label("3D grass").rect().center();
    click_across_a_slow_frame(&mut h, at, 1.5);
    assert_eq!(h.state().settings.central, windloom::app::Central::Grass);
    let at = h.get_by_label("Map").rect().center();
    click_across_a_slow_frame(&mut h, at, 1.5);
    assert_eq!(h.state().settings.central, windloom::app::Central::Map);
    h.state_mut().tool = Tool::AddRoot;
    let at = h.state().screen_pos([60.0, 40.0]);
    click_across_a_slow_frame(&mut h, at, 1.5);
    assert_eq!(h.state().doc.trees.len(), 2, "the map click added a tree");
}

/// A long tree or layer name is cut with "…" in the Layers panel, which keeps its width (the
/// map does not shift), and Help → User guide opens the guide beside the work.
#[test]
fn long_names_keep_the_panels_and_the_guide_opens() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("meadow.json"));
    h.run_steps(2);
    let map_left = h.state().map.rect.left();
    let ctx = h.ctx.clone();
    let id = h.state().doc.trees[0].id;
    let mut props = windloom::doc::TreeProps::of(&h.state().doc.trees[0]);
    props.name = "The valley wind along the northern river, past the old mill, the bridge \
                  and the orchards"
        .into();
    assert!(
        h.state_mut()
            .edit(&ctx, windloom::doc::Edit::SetTreeProps { id, props })
    );
    h.run_steps(3);
    assert_eq!(
        h.state().map.rect.left(),
        map_left,
        "the Layers panel widened"
    );
    assert!(h.query_by_label_contains("The valley wind").is_some());

    h.get_by_label("Help").click();
    h.run_steps(2);
    h.get_by_label("User guide").click();
    h.run_steps(3);
    assert!(h.state().guide.open);
    assert!(
        h.query_by_label_contains("The editor: a user guide")
            .is_some()
    );
}

/// The wind's vertical profile sits under World, collapsed: opened, its fields show the
/// layout's profile, a typed roughness length is one undo step, and the line under it says
/// what the law makes of the wind near the ground.
#[test]
fn the_vertical_profile_is_edited_in_the_world_section() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("meadow.json"));
    h.run_steps(2);
    assert!(h.query_by_label("Roughness length").is_none(), "collapsed");
    h.get_by_label("Wind above the ground").click();
    h.run_steps(2);
    assert_eq!(
        h.get_by_label("Roughness length").value().as_deref(),
        Some("0.030 m")
    );
    assert!(h.query_by_label_contains("at 1 m is 83 %").is_some());
    h.get_by_label("Roughness length").click();
    h.run_steps(1);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::A);
    h.run_steps(1);
    h.get_by_label("Roughness length").type_text("0.5");
    h.key_press(egui::Key::Enter);
    h.run_steps(2);
    assert_eq!(h.state().doc.world.profile.roughness_length, 0.5);
    // ln(1 / 0.5) / ln(2 / 0.5) = 0.5.
    assert!(h.query_by_label_contains("at 1 m is 50 %").is_some());
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().doc.world.profile.roughness_length, 0.03);
}

/// A layout with terrain opens with its Terrain section showing; the hill size is typed and
/// undone like any edit, and clearing the heightmap (committed with Enter) makes the ground
/// flat.
#[test]
fn the_terrain_is_edited_in_the_world_section() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("walled-garden.json"));
    h.run_steps(2);
    assert_eq!(
        h.get_by_label("Hill size").value().as_deref(),
        Some("8.0 m")
    );
    h.get_by_label("Hill size").click();
    h.run_steps(1);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::A);
    h.run_steps(1);
    h.get_by_label("Hill size").type_text("12");
    h.key_press(egui::Key::Enter);
    h.run_steps(2);
    let t = h.state().doc.world.terrain.clone().unwrap();
    assert_eq!(t.feature_length, Some(12.0));
    assert!(t.pixels.image().is_some(), "the heightmap was read");
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(
        h.state().doc.world.terrain.as_ref().unwrap().feature_length,
        Some(8.0)
    );
    // The heightmap's path emptied: flat ground, the section's other rows gone.
    h.get_by_label("Heightmap").click();
    h.run_steps(1);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::A);
    h.run_steps(1);
    h.key_press(egui::Key::Backspace);
    h.run_steps(2);
    assert!(
        h.state().doc.world.terrain.is_some(),
        "a path is committed on Enter, not read at each key"
    );
    h.key_press(egui::Key::Enter);
    h.run_steps(2);
    assert!(h.state().doc.world.terrain.is_none());
    assert!(h.query_by_label("Hill size").is_none());
}

/// The paint tool: a stroke over the selected mask makes its pixels solid in one undo step; a
/// stroke with no mask selected grows grass on the density map; both are unsaved work, and
/// saving writes the painted images beside the layout, which read back as painted.
#[test]
fn painting_a_mask_and_the_density_map_saves_them_beside_the_layout() {
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let layouts = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("layouts");
    for f in [
        "walled-garden.json",
        "walled-garden-mask.png",
        "walled-garden-grass.png",
        "walled-garden-heights.png",
    ] {
        std::fs::copy(layouts.join(f), dir.path().join(f)).unwrap();
    }
    let path = dir.path().join("walled-garden.json");
    let json_before = std::fs::read_to_string(&path).unwrap();
    let mut h = harness_on(windloom::io::load(&path).unwrap(), Some(path.clone()));
    let mask_id = h.state().doc.obstacles[0].id;
    let bounds = h.state().doc.bounds();
    let solid_at = |h: &Harness<'_, EditorApp>, p: [f32; 2]| {
        h.state().doc.obstacles[0].shape.mask_contains(p, bounds)
    };
    assert!(!solid_at(&h, [30.0, 20.0]), "open ground before");

    h.state_mut().selection = vec![Sel::Obstacle(mask_id)];
    h.key_press(egui::Key::B);
    h.run_steps(2);
    assert_eq!(h.state().tool, Tool::Paint);
    let (a, b) = (
        h.state().screen_pos([25.0, 20.0]),
        h.state().screen_pos([35.0, 20.0]),
    );
    drag(&mut h, a, b);
    assert!(solid_at(&h, [30.0, 20.0]), "painted solid");
    assert!(!solid_at(&h, [30.0, 30.0]), "only under the brush");
    assert_eq!(
        h.state().doc.history().undo_label(),
        Some("Change obstacle"),
        "one step for the stroke"
    );
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert!(!solid_at(&h, [30.0, 20.0]), "undone");
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, egui::Key::Z);
    h.run_steps(2);
    assert!(solid_at(&h, [30.0, 20.0]), "redone");

    // No mask selected: the density map, over the pond (no grass) at (20, 20).
    h.state_mut().selection.clear();
    let density = |h: &Harness<'_, EditorApp>| {
        h.state()
            .doc
            .grass
            .density_map
            .as_ref()
            .unwrap()
            .at([20.0, 20.0], bounds)
    };
    assert!(density(&h) < 0.1, "the pond grows no grass");
    let (a, b) = (
        h.state().screen_pos([18.0, 20.0]),
        h.state().screen_pos([22.0, 20.0]),
    );
    drag(&mut h, a, b);
    assert!(density(&h) > 0.99, "grass painted over the pond");
    assert!(h.state_mut().doc.take_changed() || h.state().doc.is_dirty());
    assert!(h.state().doc.is_dirty(), "painted images are unsaved work");

    h.state_mut().doc.write_to(&path).unwrap();
    assert!(!h.state().doc.is_dirty());
    let mask = windloom::io::load_mask(dir.path(), "walled-garden-mask.png", "mask").unwrap();
    assert!(
        mask.solid_at(30.0 / 120.0, 20.0 / 80.0, 0.5, false),
        "saved solid"
    );
    let grass = windloom::io::load_mask(dir.path(), "walled-garden-grass.png", "grass").unwrap();
    assert!(
        grass.luminance_at(20.0 / 120.0, 20.0 / 80.0) > 0.99,
        "saved grass"
    );
    assert_eq!(
        windloom::doc::parse(&std::fs::read_to_string(&path).unwrap()).unwrap(),
        windloom::doc::parse(&json_before).unwrap(),
        "the layout names the same images"
    );
}

/// The grass settings read as what they do, the paper's symbol on hover; a typed gravity bend
/// is the layout's k1, one undo step.
#[test]
fn grass_settings_are_named_for_what_they_do() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("meadow.json"));
    h.run_steps(2);
    h.get_by_label("Grass").click();
    h.run_steps(2);
    for label in [
        "Gravity bend",
        "Forward lean",
        "Stiffness",
        "Shadow from wind",
        "Shadow lift",
    ] {
        assert!(h.query_by_label(label).is_some(), "{label}");
    }
    for old in ["k1 (gravity)", "λ (stiffness)", "Shadow c1 (wind)"] {
        assert!(h.query_by_label(old).is_none(), "{old}");
    }
    h.get_by_label("Gravity bend").hover();
    // Past egui's tooltip delay.
    h.run_steps(60);
    assert!(
        h.query_by_label_contains("k1 in the paper's eq. 11")
            .is_some(),
        "the symbol on hover"
    );
    let k1 = h.state().doc.grass.k1;
    h.get_by_label("Gravity bend").click();
    h.run_steps(1);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::A);
    h.run_steps(1);
    h.get_by_label("Gravity bend").type_text("0.125");
    h.key_press(egui::Key::Enter);
    h.run_steps(2);
    assert_eq!(h.state().doc.grass.k1, 0.125);
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().doc.grass.k1, k1);
}

/// Each enabled ambient layer has a gizmo on the map: the way its wind blows by the stated
/// convention (0° east, +x; 90° south, +z) and the scale of its gusts where it has one.
#[test]
fn ambient_gizmos_point_the_way_the_wind_blows() {
    use windloom::app::view::ambient_gizmos;
    let mut l = example("breeze-fft.json");
    let g = ambient_gizmos(&l);
    assert_eq!(g.len(), 1);
    let windloom::doc::AmbientKind::Fft {
        direction_deg,
        tile_size,
        ..
    } = l.ambient[0].kind.clone()
    else {
        panic!("the example's layer is an FFT field");
    };
    assert_eq!(g[0].gust_scale, Some(tile_size));
    let d = windloom::doc::direction(direction_deg);
    assert!((g[0].direction[0] - d[0]).abs() < 1e-6 && (g[0].direction[1] - d[1]).abs() < 1e-6);
    if let windloom::doc::AmbientKind::Fft { direction_deg, .. } = &mut l.ambient[0].kind {
        *direction_deg = 90.0;
    }
    let south = ambient_gizmos(&l)[0].direction;
    assert!(
        south[0].abs() < 1e-6 && (south[1] - 1.0).abs() < 1e-6,
        "{south:?}"
    );
    l.ambient[0].enabled = false;
    assert!(ambient_gizmos(&l).is_empty(), "a disabled layer has none");
}
