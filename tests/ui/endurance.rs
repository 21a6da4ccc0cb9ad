//! An editor left open all day: every view keeps its memory and its wgpu resources flat over
//! hundreds of frames (run in a process of its own, so no other test's allocations count).

use super::*;
use windloom::app::Central;

/// The process's resident memory, in bytes (Linux).
fn resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let kb: u64 = status
        .lines()
        .find(|l| l.starts_with("VmRSS:"))?
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()?;
    Some(kb * 1024)
}

/// Frames drawn before the first reading (pipelines made, caches filled, the wind developed)
/// and between the two readings.
const WARM_FRAMES: usize = 40;
/// 80 frames show both faults this test has caught: the 3D view on Mesa 22.3's lavapipe grew
/// about 1.5 MB a frame (120 MB over them, five times the limit), and a wgpu resource made
/// each frame and kept adds 80 to the count, against the 2 tolerated. (It measured 160
/// frames, which took three minutes of CI on lavapipe and caught nothing more.)
const MEASURED_FRAMES: usize = 80;
/// Growth in resident memory tolerated over the measured frames: allocator slack and egui's
/// caches; a steady leak of 0.3 MB a frame passes it.
const GROWTH_LIMIT: u64 = 24 << 20;

/// Each view through the real code path (egui_kittest drives the editor on its wgpu device,
/// each frame rendered as the window would): after a warm-up, `MEASURED_FRAMES` frames leave
/// the wgpu resources as they were and the resident memory within `GROWTH_LIMIT`. This test
/// runs the map views; the 3D ones are [`every_3d_view_keeps_its_memory_flat`].
#[test]
fn every_view_keeps_its_memory_flat() {
    views_keep_their_memory_flat("map");
}

/// [`every_view_keeps_its_memory_flat`] for the CWD grass in 3D, running and paused (the
/// views are split over three tests, so that the two cores run them side by side).
#[test]
fn every_3d_view_keeps_its_memory_flat() {
    views_keep_their_memory_flat("3D");
}

/// [`every_view_keeps_its_memory_flat`] for the Bezier grass on GPU wind and the map beside
/// the 3D view.
#[test]
fn the_bezier_and_split_views_keep_their_memory_flat() {
    views_keep_their_memory_flat("bezier+split");
}

/// Runs [`views_in_this_process`] in a process of its own for the views of group `which`
/// ("map", "3D" or "bezier+split").
fn views_keep_their_memory_flat(which: &str) {
    if !gpu_available() || resident_bytes().is_none() {
        return;
    }
    let out = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "endurance::views_in_this_process",
            "--include-ignored",
            "--nocapture",
            "--test-threads=1",
        ])
        .env("WINDLOOM_ENDURANCE_CHILD", which)
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.status.success() && text.contains("1 passed"),
        "the views grew:\n{text}"
    );
    eprintln!("{text}");
}

/// The measuring half of [`every_view_keeps_its_memory_flat`], in the process it starts.
#[test]
#[ignore = "run by every_view_keeps_its_memory_flat in a process of its own"]
fn views_in_this_process() {
    assert!(
        std::env::var_os("WINDLOOM_ENDURANCE_CHILD").is_some(),
        "run through every_view_keeps_its_memory_flat"
    );
    let cases: [(&str, Central, Backend, bool, doc::GrassModel); 6] = [
        (
            "map, running, CPU wind",
            Central::Map,
            Backend::Cpu,
            true,
            doc::GrassModel::CwdQuadratic,
        ),
        (
            "map, running, GPU wind",
            Central::Map,
            Backend::Gpu,
            true,
            doc::GrassModel::CwdQuadratic,
        ),
        (
            "3D grass, running",
            Central::Grass,
            Backend::Cpu,
            true,
            doc::GrassModel::CwdQuadratic,
        ),
        (
            "3D grass, paused",
            Central::Grass,
            Backend::Cpu,
            false,
            doc::GrassModel::CwdQuadratic,
        ),
        (
            "3D Bezier grass, running, GPU wind",
            Central::Grass,
            Backend::Gpu,
            true,
            doc::GrassModel::BezierPhysics,
        ),
        (
            "map + 3D, running",
            Central::Split,
            Backend::Cpu,
            true,
            doc::GrassModel::CwdQuadratic,
        ),
    ];
    let which = std::env::var("WINDLOOM_ENDURANCE_CHILD").unwrap();
    let mut failures = Vec::new();
    let mut ran = 0;
    for (name, central, backend, playing, model) in cases {
        let group = match (central, model) {
            (Central::Map, _) => "map",
            (Central::Grass, doc::GrassModel::CwdQuadratic) => "3D",
            _ => "bezier+split",
        };
        if group != which {
            continue;
        }
        ran += 1;
        let mut doc = example("meadow.json");
        doc.grass.model = model;
        if name.contains("probe") {
            // The probes' panel: its plots and readings at rest too.
            doc.probes.push(doc::Probe {
                id: 999,
                name: "Probe".into(),
                pos: [60.0, 40.0],
            });
        }
        // The editor's smallest window: the same code path, fewer pixels to rasterise.
        let mut h = gpu_harness_sized(doc, egui::vec2(800.0, 500.0), move |app| {
            app.settings.backend = backend;
            app.settings.central = central;
        });
        h.state_mut().live.set_playing(playing);
        let frame = |h: &mut Harness<'_, EditorApp>| {
            h.step();
            // Rendered as the window is: the map's paint callbacks run here.
            h.render().expect("the frame renders");
        };
        for _ in 0..WARM_FRAMES {
            frame(&mut h);
        }
        // The wind moves to the GPU on the simulation's thread, which builds the solver's
        // pipelines first. On an H200 the warm-up frames were drawn before it had, and the
        // solver's buffers appeared between the two readings: wait for it, then warm again.
        if backend == Backend::Gpu {
            step_and_wait(&mut h, 0, RunsOn::Gpu);
            for _ in 0..WARM_FRAMES {
                frame(&mut h);
            }
        }
        let before = (resident_bytes().unwrap(), h.state().gpu_resources());
        let started = Instant::now();
        for _ in 0..MEASURED_FRAMES {
            frame(&mut h);
        }
        let after = (resident_bytes().unwrap(), h.state().gpu_resources());
        let grew = after.0.saturating_sub(before.0);
        let ms = started.elapsed().as_secs_f64() * 1e3 / MEASURED_FRAMES as f64;
        println!(
            "{name}: resident {:.1} → {:.1} MB over {MEASURED_FRAMES} frames ({ms:.0} ms a frame); \
             wgpu {:?}",
            before.0 as f64 / 1e6,
            after.0 as f64 / 1e6,
            after.1
        );
        let (Some(b), Some(a)) = (before.1, after.1) else {
            panic!("{name}: wgpu gives no resource report");
        };
        // A read-back in flight may hold a buffer at one reading and not the other; a
        // resource made every frame and kept adds hundreds.
        if !b.at_most_plus(&a, 2) {
            failures.push(format!(
                "{name}: wgpu resources changed\n  from {:?}\n  to   {:?}",
                b, a
            ));
        }
        if grew > GROWTH_LIMIT {
            failures.push(format!(
                "{name}: resident memory grew {:.1} MB over {MEASURED_FRAMES} frames \
                 ({:.0} kB a frame)",
                grew as f64 / 1e6,
                grew as f64 / 1e3 / MEASURED_FRAMES as f64
            ));
        }
    }
    assert!(ran >= 2, "fewer than two views in {which:?}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Paused and untouched, no view asks for frames (a paused view on a laptop is a battery
/// drain): after what is moving has settled — the CWD blades at once, the Bezier blades'
/// physics within seconds — the editor asks for no immediate frame, and none sooner than a
/// second away.
#[test]
fn every_view_rests_when_paused() {
    if !gpu_available() {
        return;
    }
    let cases = [
        ("map", Central::Map, doc::GrassModel::CwdQuadratic),
        (
            "map with a probe",
            Central::Map,
            doc::GrassModel::CwdQuadratic,
        ),
        ("3D grass", Central::Grass, doc::GrassModel::CwdQuadratic),
        ("map + 3D", Central::Split, doc::GrassModel::CwdQuadratic),
        (
            "3D Bezier grass",
            Central::Grass,
            doc::GrassModel::BezierPhysics,
        ),
    ];
    for (name, central, model) in cases {
        let mut doc = example("meadow.json");
        doc.grass.model = model;
        if name.contains("probe") {
            // The probes' panel: its plots and readings at rest too.
            doc.probes.push(doc::Probe {
                id: 999,
                name: "Probe".into(),
                pos: [60.0, 40.0],
            });
        }
        // On the CPU: the automatic choice measures both backends first, and its result is
        // new data that wakes the view (as it should).
        let mut h = gpu_harness_sized(doc, egui::vec2(800.0, 500.0), move |app| {
            app.settings.central = central;
            app.settings.backend = Backend::Cpu;
        });
        // The first field arrives, the blades are built, the counters come back from the
        // GPU (real time), the Bezier blades settle (editor time: 1/60 s a frame).
        let delay = |h: &Harness<'_, EditorApp>| {
            h.output()
                .viewport_output
                .get(&egui::ViewportId::ROOT)
                .expect("the root viewport")
                .repaint_delay
        };
        let started = Instant::now();
        // The paused worker's last field (new data wakes the view, as it should).
        let mut serial = None;
        loop {
            let s = h.state().live.snapshot();
            if s.nx > 0 && serial == Some(s.serial) {
                break;
            }
            serial = Some(s.serial);
            assert!(
                started.elapsed() < Duration::from_secs(60),
                "{name}: no field"
            );
            std::thread::sleep(Duration::from_millis(300));
        }
        let mut frames = 0;
        loop {
            let drawn = h.try_run().unwrap_or(16);
            frames += drawn;
            if drawn <= 2 && delay(&h) >= Duration::from_secs(1) {
                break;
            }
            assert!(
                started.elapsed() < Duration::from_secs(60) && frames < 1000,
                "{name}: still drawing after {frames} frames; next asked for in {:?}",
                delay(&h)
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        let settled = frames;
        // And it stays at rest.
        std::thread::sleep(Duration::from_millis(300));
        let more = h.try_run().expect("rests");
        assert!(
            more <= 2 && delay(&h) >= Duration::from_secs(1),
            "{name}: {more} frames drawn at rest (after {settled} to settle), next asked for in \
             {:?} by {:?}",
            delay(&h),
            h.ctx.repaint_causes()
        );
        if model == doc::GrassModel::CwdQuadratic {
            assert!(settled <= 24, "{name}: {settled} frames to settle");
        }
    }
}
