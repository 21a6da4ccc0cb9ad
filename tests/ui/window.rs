//! The window itself: a snapshot of the whole editor, the real window under Xvfb, what the
//! editor says when it cannot open one, and an idle editor that stops drawing.

use super::*;

#[test]
fn editor_window_snapshot() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("obstacles.json"));
    h.state_mut().settings.wind_view = windloom::app::view::WindView::Glyphs;
    // Two simulated seconds, stepped on the paused worker, so the picture is deterministic.
    let dt = h.state().doc.sim.dt;
    for _ in 0..120 {
        h.state().live.step_once();
    }
    let deadline = Instant::now() + Duration::from_secs(120);
    while h.state().live.snapshot().time < 120.0 * dt - 1e-3 {
        assert!(Instant::now() < deadline, "the simulation thread stalled");
        std::thread::sleep(Duration::from_millis(50));
    }
    h.run_steps(3);
    // The status bar shows timings and frame rate, which differ from run to run.
    let status = h.state().status_rect;
    h.mask(status);
    h.snapshot("editor_obstacles");
}

#[test]
fn the_window_opens_under_xvfb() {
    let have_xvfb = program_exists("xvfb-run", "--help");
    if !have_xvfb {
        assert!(!in_ci(), "CI must run the window test: xvfb-run not found");
        eprintln!("\n!!!!! SKIPPING: xvfb-run not installed (apt-get install xvfb) !!!!!\n");
        return;
    }
    let runtime = tempfile::tempdir().unwrap();
    let mut child = std::process::Command::new("xvfb-run")
        .args([
            "-a",
            "-s",
            "-screen 0 1280x800x24",
            env!("CARGO_BIN_EXE_windloom"),
        ])
        .env("XDG_RUNTIME_DIR", runtime.path())
        .env("HOME", runtime.path())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_secs(8));
    let status = child.try_wait().unwrap();
    if status.is_none() {
        // Still running: the window is up. Stop it (xvfb-run then stops its Xvfb) — only
        // this test's editor, xvfb-run's child: other tests run editors of their own.
        let _ = std::process::Command::new("pkill")
            .args([
                "-P",
                &child.id().to_string(),
                "-f",
                env!("CARGO_BIN_EXE_windloom"),
            ])
            .status();
    }
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        status.is_none(),
        "the editor exited early: {status:?}\n{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// The editor that cannot open its window says what to do and exits non-zero: with no
/// display (run it under Xvfb), and with a display but no graphics backend wgpu can use
/// (install a Vulkan driver; `WGPU_BACKEND=dx12` stands in for a machine without one).
#[test]
fn an_editor_that_cannot_open_its_window_says_what_to_do() {
    let runtime = tempfile::tempdir().unwrap();
    let editor = || {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_windloom"));
        c.env("XDG_RUNTIME_DIR", runtime.path())
            .env("HOME", runtime.path())
            .env_remove("WAYLAND_DISPLAY");
        c
    };
    let out = editor().env_remove("DISPLAY").output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "no display: {stderr}");
    assert!(
        stderr.contains("could not open the editor window") && stderr.contains("xvfb-run -a"),
        "no display: {stderr}"
    );
    let have_xvfb = program_exists("xvfb-run", "--help");
    if !have_xvfb {
        assert!(!in_ci(), "CI must run the window test: xvfb-run not found");
        eprintln!("\n!!!!! SKIPPING the no-backend half: xvfb-run not installed !!!!!\n");
        return;
    }
    let out = std::process::Command::new("xvfb-run")
        .args([
            "-a",
            "-s",
            "-screen 0 640x480x24",
            env!("CARGO_BIN_EXE_windloom"),
        ])
        .env("XDG_RUNTIME_DIR", runtime.path())
        .env("HOME", runtime.path())
        .env("WGPU_BACKEND", "dx12")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "no backend: {stderr}");
    assert!(
        stderr.contains("could not open the editor window")
            && stderr.contains("apt-get install mesa-vulkan-drivers")
            && stderr.contains("WGPU_BACKEND=vulkan"),
        "no backend: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// Paused, with no input, the editor stops drawing: nothing requests another frame (the
/// window title was sent every frame, and each viewport command asks for a repaint, so an
/// idle editor used to redraw forever at 180% CPU).
#[test]
fn an_idle_paused_editor_stops_drawing() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("meadow.json"));
    // Let the simulation thread publish its first field, then the editor must settle.
    std::thread::sleep(Duration::from_millis(300));
    let frames = h.try_run().expect("an idle editor keeps asking for frames");
    assert!(frames <= 8, "{frames} frames to settle");
    // And it stays idle.
    std::thread::sleep(Duration::from_millis(300));
    let more = h.try_run().expect("an idle editor keeps asking for frames");
    assert!(more <= 2, "{more} frames drawn while idle");
}

/// The status bar's frame rate is of frames being drawn: after a rest it says "idle", not the
/// rate of frames long gone, and the editor draws one frame to say so.
#[test]
fn the_status_bar_says_idle_after_a_rest() {
    if !gpu_available() {
        return;
    }
    let mut h = harness(example("meadow.json"));
    h.run_steps(3);
    assert!(h.query_by_label_contains(" fps").is_some());
    let now = h.ctx.input(|i| i.time);
    h.input_mut().time = Some(now + 2.0);
    h.step();
    assert!(
        h.query_by_label_contains("· idle").is_some(),
        "the frame after a rest says idle"
    );
}
