//! The timeline: keys added and edited as undoable edits, scrubbing to a time (and back,
//! from the checkpoints), and a looping play range.

use super::*;

#[test]
fn keys_are_added_at_the_time_shown_and_scrubbing_goes_to_a_time() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("two-winds.json"));
    h.get_by_label("Play range");
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
    let mut h = harness(example("two-winds.json"));
    h.state_mut().timeline.range = (0.0, 0.5);
    h.state_mut().timeline.looping = true;
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
