//! Editing as the document sees it: a selection copied as a layout of its own, pasted with
//! fresh ids as one undo step, within a layout and into another; lock and hide saved; a
//! stroke simplified into an arrow chain; a selection turned and scaled; polygon corners.

use super::*;
use doc::clipboard::{self, Item};

fn ids(l: &Layout) -> Vec<u32> {
    let mut v: Vec<u32> = (l.nodes().map(|(_, n)| n.id))
        .chain(l.trees.iter().map(|t| t.id))
        .chain(l.obstacles.iter().map(|o| o.id))
        .chain(l.ambient.iter().map(|a| a.id))
        .collect();
    v.sort();
    v
}

#[test]
fn a_copied_selection_reads_back_as_a_layout() {
    let l = example("obstacles.json");
    // A whole tree by its root, a polygon and a circle.
    let copied = clipboard::copy(
        &l,
        &[Item::Node(101), Item::Obstacle(12), Item::Obstacle(10)],
    )
    .unwrap();
    assert_eq!(copied.trees.len(), 1);
    assert_eq!(copied.trees[0].root, l.trees[0].root);
    // In the layout's order, not the picking order.
    let kept: Vec<u32> = copied.obstacles.iter().map(|o| o.id).collect();
    assert_eq!(kept, vec![10, 12]);
    let text = clipboard::to_text(&copied);
    assert_eq!(clipboard::from_text(&text).unwrap(), copied);
    // Nothing picked that exists: nothing to copy.
    assert!(clipboard::copy(&l, &[Item::Obstacle(999)]).is_none());
}

#[test]
fn a_copied_arrow_keeps_the_arrow_into_it() {
    let l = example("branching.json");
    let tree = &l.trees[0];
    let child = &tree.root.children[0];
    let copied = clipboard::copy(&l, &[Item::Node(child.id)]).unwrap();
    assert_eq!(copied.trees.len(), 1);
    let part = &copied.trees[0];
    assert_eq!(
        part.root.pos, tree.root.pos,
        "the copy's root is its parent's point"
    );
    assert_eq!(part.root.children, vec![child.clone()]);
    // A node inside a picked subtree is not copied twice.
    if let Some(grandchild) = child.children.first() {
        let both = clipboard::copy(&l, &[Item::Node(child.id), Item::Node(grandchild.id)]);
        assert_eq!(both.unwrap().trees.len(), 1);
    }
}

#[test]
fn pasting_twice_into_the_same_layout_gives_fresh_ids_in_one_undo_step_each() {
    let mut l = example("obstacles.json");
    let before = doc::to_json(&l);
    let copied = clipboard::copy(&l, &[Item::Tree(1), Item::Obstacle(13)]).unwrap();
    let mut h = History::new();
    for k in 1..=2 {
        let pasted = clipboard::paste(&l, copied.clone(), [3.0 * k as f32, 0.0]).unwrap();
        assert_eq!(pasted.items.len(), 2);
        h.apply(&mut l, pasted.edit).unwrap();
        let all = ids(&l);
        let mut unique = all.clone();
        unique.dedup();
        assert_eq!(all, unique, "every id stays unique after paste {k}");
        assert!(doc::validate(&l).is_empty());
    }
    assert_eq!(l.trees.len(), 5);
    assert_eq!(l.obstacles.len(), 6);
    // The copies are moved by the offset, and nothing else changed.
    let last = l.trees.last().unwrap();
    assert_eq!(last.root.pos[0], l.trees[0].root.pos[0] + 6.0);
    assert_eq!(last.root.pos[1], l.trees[0].root.pos[1]);
    assert!(h.undo(&mut l) && h.undo(&mut l));
    assert_eq!(doc::to_json(&l), before, "two undos take both pastes away");
}

#[test]
fn a_selection_pastes_into_another_layout_and_a_layout_file_pastes_whole() {
    let from = example("two-winds.json");
    let mut into = example("obstacles.json");
    let copied = clipboard::copy(&from, &[Item::Tree(2)]).unwrap();
    let text = clipboard::to_text(&copied);
    let pasted = clipboard::paste(&into, clipboard::from_text(&text).unwrap(), [0.0, 0.0]);
    let pasted = pasted.unwrap();
    pasted.edit.apply(&mut into).unwrap();
    let east = into.trees.last().unwrap();
    assert_eq!(east.name, "East wind");
    assert_eq!(east.root.pos, from.trees[1].root.pos);
    assert!(doc::validate(&into).is_empty());

    // A layout file's text (copied from a text editor) pastes all it holds.
    let file = std::fs::read_to_string(example_path("two-winds.json")).unwrap();
    let whole = clipboard::from_text(&file).unwrap();
    let n = into.trees.len();
    clipboard::paste(&into, whole, [0.0, 0.0])
        .unwrap()
        .edit
        .apply(&mut into)
        .unwrap();
    assert_eq!(into.trees.len(), n + 2);

    // Text that is no layout is refused with where it went wrong.
    let e = clipboard::from_text("hello").unwrap_err();
    assert!(e.to_string().starts_with("1:1:"), "{e}");
}

#[test]
fn pasted_items_come_unlocked_and_shown() {
    let mut l = example("two-winds.json");
    l.trees[0].locked = true;
    l.trees[0].hidden = true;
    let copied = clipboard::copy(&l, &[Item::Tree(1)]).unwrap();
    let pasted = clipboard::paste(&l, copied, [1.0, 1.0]).unwrap();
    pasted.edit.apply(&mut l).unwrap();
    let t = l.trees.last().unwrap();
    assert!(!t.locked && !t.hidden);
}

#[test]
fn lock_and_hide_are_saved_and_absent_when_off() {
    let mut l = example("obstacles.json");
    let plain = doc::to_json(&l);
    assert!(!plain.contains("\"locked\"") && !plain.contains("\"hidden\""));
    l.trees[1].locked = true;
    l.obstacles[0].hidden = true;
    let text = doc::to_json(&l);
    assert!(text.contains("\"locked\": true") && text.contains("\"hidden\": true"));
    let back = doc::parse(&text).unwrap();
    assert!(back.trees[1].locked && !back.trees[1].hidden);
    assert!(back.obstacles[0].hidden && !back.obstacles[0].locked);
}

/// The distance from `p` to the segment `a`–`b`.
fn to_segment(p: [f32; 2], a: [f32; 2], b: [f32; 2]) -> f32 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    let t = (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / l2).clamp(0.0, 1.0);
    (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
}

#[test]
fn a_stroke_becomes_a_chain_of_few_arrows_that_follows_it() {
    use doc::stroke::{StrokeSettings, chain, simplify};
    let settings = StrokeSettings {
        strength: 6.0,
        radius: 8.0,
    };
    // A wobbly straight line: one arrow.
    let line: Vec<[f32; 2]> = (0..200)
        .map(|k| [k as f32 * 0.5, (k as f32 * 0.7).sin() * 0.3])
        .collect();
    assert_eq!(simplify(&line, settings.tolerance()).len(), 2);
    // A valley's bend, a quarter circle of 60 m drawn with 400 points: a few arrows, none
    // straying from the path by more than the tolerance.
    let arc: Vec<[f32; 2]> = (0..=400)
        .map(|k| {
            let a = k as f32 / 400.0 * std::f32::consts::FRAC_PI_2;
            [60.0 * a.cos(), 60.0 * a.sin()]
        })
        .collect();
    let kept = simplify(&arc, settings.tolerance());
    assert!((4..=12).contains(&kept.len()), "{} points", kept.len());
    assert_eq!((kept[0], *kept.last().unwrap()), (arc[0], arc[400]));
    for p in &arc {
        let off = (kept.windows(2))
            .map(|w| to_segment(*p, w[0], w[1]))
            .fold(f32::INFINITY, f32::min);
        assert!(off <= settings.tolerance() + 1e-3, "{p:?} is {off} m off");
    }
    // The chain: root at the start, each arrow with the settings, ids in a row.
    let root = chain(&kept, settings, 50).unwrap();
    let mut l = Layout::new("stroke", [200.0, 200.0], [64, 64]);
    let mut depth = 0;
    let mut n = &root;
    while let Some(c) = n.children.first() {
        assert_eq!((c.strength, c.radius), (6.0, 8.0));
        assert_eq!(n.children.len(), 1, "a chain, no branches");
        depth += 1;
        n = c;
    }
    assert_eq!(depth, kept.len() - 1);
    l.trees.push(doc::Tree {
        id: 49,
        name: "Stroke".into(),
        enabled: true,
        window: doc::TimeWindow::Always,
        emission: doc::Emission::Continuous,
        propagation_speed: 20.0,
        locked: false,
        hidden: false,
        root,
        keys: Vec::new(),
    });
    assert!(doc::validate(&l).is_empty(), "{:?}", doc::validate(&l));
    // A scribble of thousands of turns is held to the longest chain a layout takes.
    let scribble: Vec<[f32; 2]> = (0..5000)
        .map(|k| [k as f32 * 0.1, if k % 2 == 0 { 0.0 } else { 20.0 }])
        .collect();
    let kept = simplify(&scribble, 0.01);
    assert!(kept.len() - 1 <= doc::bounds::CHAIN_MAX, "{}", kept.len());
    assert!(chain(&kept[..1], settings, 1).is_none());
}

#[test]
fn a_selection_turns_and_scales_about_its_middle_in_one_step() {
    use doc::transform::{self, Transform};
    let mut l = example("obstacles.json");
    let before = l.clone();
    let items = [Item::Tree(1), Item::Obstacle(10), Item::Obstacle(12)];
    let pivot = transform::pivot(&l, &items).unwrap();
    let quarter = Transform {
        pivot,
        angle: std::f32::consts::FRAC_PI_2,
        scale: 1.0,
    };
    let mut h = History::new();
    let e = transform::transform(&l, &items, quarter).unwrap();
    h.apply(&mut l, e).unwrap();
    assert_eq!(h.undo_label(), Some("Rotate"));
    // A quarter turn clockwise on the map: east becomes south.
    let root = l.trees[0].root.pos;
    let was = before.trees[0].root.pos;
    let d = [was[0] - pivot[0], was[1] - pivot[1]];
    assert!(
        (root[0] - (pivot[0] - d[1])).abs() < 1e-3 && (root[1] - (pivot[1] + d[0])).abs() < 1e-3
    );
    // The rest of the layout stays.
    assert_eq!(l.trees[1], before.trees[1]);
    assert_eq!(l.obstacles[1], before.obstacles[1]);
    assert!(h.undo(&mut l));
    assert_eq!(doc::to_json(&l), doc::to_json(&before));

    // Twice as big: positions from the pivot and every radius double.
    let double = Transform {
        pivot,
        angle: 0.0,
        scale: 2.0,
    };
    let e = transform::transform(&l, &items, double).unwrap();
    h.apply(&mut l, e).unwrap();
    assert_eq!(
        l.trees[0].root.children[0].radius,
        before.trees[0].root.children[0].radius * 2.0
    );
    let Shape::Circle { radius, .. } = l.obstacles[0].shape else {
        panic!()
    };
    assert_eq!(radius, 14.0);
    let (lo, hi) = transform::extent(&l, &items).unwrap();
    let (lo0, hi0) = transform::extent(&before, &items).unwrap();
    assert!(((hi[0] - lo[0]) - 2.0 * (hi0[0] - lo0[0])).abs() < 1e-3);
    assert!(doc::validate(&l).is_empty());
    // A locked obstacle stays put.
    let mut locked = before.clone();
    locked.obstacles[0].locked = true;
    let e = transform::transform(&locked, &[Item::Obstacle(10)], double);
    assert!(e.is_none());
}

#[test]
fn a_polygon_s_corners_move_insert_and_delete_down_to_three() {
    use doc::transform::{delete_corner, insert_corner, move_corner};
    let l = example("obstacles.json");
    let barn = &l.obstacles[2];
    let moved = move_corner(barn, 0, [70.0, 30.0]).unwrap();
    let Shape::Polygon { points } = &moved.shape else {
        panic!()
    };
    assert_eq!(points[0], [70.0, 30.0]);
    let five = insert_corner(barn, 0, [87.0, 30.0]).unwrap();
    let Shape::Polygon { points } = &five.shape else {
        panic!()
    };
    assert_eq!(points.len(), 5);
    assert_eq!(
        points[1],
        [87.0, 30.0],
        "after the corner its edge starts at"
    );
    let three = delete_corner(&delete_corner(&five, 1).unwrap(), 0).unwrap();
    let Shape::Polygon { points } = &three.shape else {
        panic!()
    };
    assert_eq!(points.len(), 3);
    assert!(
        delete_corner(&three, 0).is_none(),
        "a triangle keeps its corners"
    );
    assert!(
        move_corner(&l.obstacles[0], 0, [0.0, 0.0]).is_none(),
        "a circle has none"
    );
}
