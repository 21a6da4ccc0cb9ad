//! The timeline: keys added and edited as undoable edits (a tree's, a branch's), scrubbing to
//! a time (and back, from the checkpoints; said while recomputing, a key then taken at the
//! time shown), and a play range that loops by default and is saved with the layout.

use super::*;

#[test]
fn keys_are_added_at_the_time_shown_and_scrubbing_goes_to_a_time() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("two-winds.json"));
    assert_eq!(
        h.query_all_by_label("Play range").count(),
        2,
        "start and end"
    );
    // Half a second on, the West wind keyed where the time is.
    for _ in 0..3 {
        step_and_wait(&mut h, 10, RunsOn::Cpu);
    }
    let t = h.state().live.snapshot().time;
    h.state_mut().selection = vec![Sel::Tree(1)];
    h.run_steps(1);
    h.key_press(egui::Key::K);
    h.run_steps(2);
    let keys = h.state().doc.trees[0].keys.clone();
    assert_eq!(keys.len(), 1, "K keys the selected tree");
    assert!((keys[0].time - t).abs() < 0.011 && keys[0].strength == 1.0);
    assert_eq!(h.state().doc.history().undo_label(), Some("Change tree"));
    h.get_by_label("Keyframes");

    // Scrub: a click on the track goes to that time; the field is there.
    let track = h.state().timeline.track;
    assert!(track.width() > 100.0, "{track:?}");
    let target = track.left() + track.width() * 0.2;
    click(&mut h, egui::pos2(target, track.center().y));
    let deadline = Instant::now() + Duration::from_secs(60);
    let went = loop {
        h.run_steps(1);
        let s = h.state().live.snapshot().time;
        if s > 1.0 || Instant::now() > deadline {
            break s;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(went > 1.0, "the field went to the time clicked: {went}");
    // And back: the same click further left.
    click(&mut h, egui::pos2(track.left() + 2.0, track.center().y));
    let deadline = Instant::now() + Duration::from_secs(60);
    let back = loop {
        h.run_steps(1);
        let s = h.state().live.snapshot().time;
        if s < went - 0.5 || Instant::now() > deadline {
            break s;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(back < 0.5, "scrubbed back to the start: {back}");
}

#[test]
fn a_looping_play_range_keeps_the_wind_in_it() {
    if !gpu_available() {
        return;
    }
    let mut l = example("two-winds.json");
    l.timeline.range = [0.0, 0.5];
    assert!(l.timeline.looping, "a play range loops by default");
    let mut h = harness(l);
    h.state_mut().live.set_playing(true);
    let mut latest = 0.0f32;
    let mut wrapped = false;
    let until = Instant::now() + Duration::from_secs(5);
    while Instant::now() < until {
        h.run_steps(1);
        let t = h.state().live.snapshot().time;
        wrapped |= t < latest - 0.2;
        latest = t;
        std::thread::sleep(Duration::from_millis(10));
    }
    h.state_mut().live.set_playing(false);
    assert!(wrapped, "the time went back to the range's start");
    assert!(latest < 0.8, "and stays about the range: {latest}");
}

/// Loop is on for a new layout and for one saved before the timeline was; switched off it is
/// one undo step, saved with the layout and read back.
#[test]
fn the_play_range_loops_by_default_and_is_saved_with_the_layout() {
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let level = dir.path().join("level.json");
    let two = example("two-winds.json");
    assert!(two.timeline.looping && two.timeline.range == [0.0, 30.0]);
    assert!(
        !doc::to_json(&two).contains("timeline"),
        "the default is not written: files from before read and write the same"
    );
    windloom::io::save(&level, &two).unwrap();
    let mut h = harness_on(windloom::io::load(&level).unwrap(), Some(level.clone()));
    h.get_by_label("Loop").click();
    h.run_steps(2);
    assert!(!h.state().doc.timeline.looping);
    assert_eq!(
        h.state().doc.history().undo_label(),
        Some("Change timeline")
    );
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::S);
    h.run_steps(2);
    let back = windloom::io::load(&level).unwrap();
    assert!(!back.timeline.looping, "saved with the layout");
    let text = std::fs::read_to_string(&level).unwrap();
    assert!(text.contains("\"loop\": false"), "{text}");
}

/// After an edit the field's past is simulated again: scrubbed back, the timeline says it is
/// recomputing (with how far it has got) until the field is there, and K meanwhile keys the
/// time shown, the one scrubbed to, not the stale field's.
#[test]
fn a_key_taken_while_recomputing_keys_the_time_shown() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("two-winds.json"));
    step_and_wait(&mut h, 5, RunsOn::Cpu);
    // An edit: the checkpoints go.
    h.state_mut().selection = vec![Sel::Tree(1)];
    h.run_steps(1);
    let id = h.state().doc.trees[1].root.children[0].id;
    let ctx = h.ctx.clone();
    assert!(h.state_mut().edit(
        &ctx,
        doc::Edit::MoveNode {
            id,
            pos: [90.0, 42.0]
        }
    ));
    h.run_steps(2);
    let track = h.state().timeline.track;
    click(
        &mut h,
        egui::pos2(track.left() + track.width() * 0.2, track.center().y),
    );
    let (shown, seeking) = h.state().live.time_shown();
    assert!(shown > 4.0, "scrubbed to {shown}");
    assert_eq!(seeking, Some(shown), "and recomputing to it");
    h.key_press(egui::Key::K);
    h.run_steps(1);
    let keys = &h.state().doc.trees[0].keys;
    assert_eq!(keys.len(), 1);
    assert!(
        (keys[0].time - shown).abs() < 0.011,
        "keyed {} at {shown}",
        keys[0].time
    );
    // The timeline says so while it recomputes, and stops once the field is there.
    let mut said = false;
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        h.run_steps(1);
        said |= h.query_by_label_contains("recomputing").is_some();
        if h.state().live.time_shown().1.is_none() || Instant::now() > deadline {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(said, "the timeline said it was recomputing");
    let t = h.state().live.snapshot().time;
    assert!(
        (t - shown).abs() < 0.05,
        "the field got there: {t} for {shown}"
    );
    h.run_steps(2);
    assert!(h.query_by_label_contains("recomputing").is_none());
}

/// K with a point (not a root) selected keys its branch: the arrow ending there and those
/// after it, as one undo step, shown in the inspector's Branch keyframes and on the track.
#[test]
fn a_point_selected_keys_its_branch() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("two-winds.json"));
    h.state_mut().selection = vec![Sel::Node(103)];
    h.run_steps(2);
    assert!(h.query_by_label("+ Key branch").is_some());
    h.key_press(egui::Key::K);
    h.run_steps(2);
    let d = &h.state().doc;
    assert_eq!(d.trees[0].root.find(103).unwrap().keys.len(), 1);
    assert!(d.trees[0].keys.is_empty(), "not the tree's");
    assert_eq!(d.history().undo_label(), Some("Change branch keys"));
    assert!(h.query_by_label("Branch keyframes").is_some());
    // The root selected: the tree.
    h.state_mut().selection = vec![Sel::Node(101)];
    h.run_steps(2);
    assert!(h.query_by_label("+ Key tree").is_some());
}
