//! The editor, driven like a user would: egui_kittest on the software (lavapipe) adapter, and
//! the real window under Xvfb.
//!
//! Without a GPU adapter these tests skip with a loud message, unless `CI` is set: CI must run
//! them for real, so there a missing adapter is a failure.
#![allow(
    clippy::unwrap_used,
    reason = "a test that unwraps fails there, which is what a test is for"
)]

use eframe::egui::{self, Event, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::Path;
use std::time::{Duration, Instant};
use windloom::app::{EditorApp, Sel, Tool};
use windloom::doc::{self, Layout};
use windloom::engine::live::LiveSim;
use windloom::engine::{Backend, RunsOn};

fn in_ci() -> bool {
    std::env::var_os("CI").is_some()
}

/// Whether a wgpu adapter exists (lavapipe counts). In CI its absence fails the test.
/// The adapter the GPU tests get, if any.
fn adapter_info() -> Option<eframe::wgpu::AdapterInfo> {
    let instance =
        eframe::wgpu::Instance::new(eframe::wgpu::InstanceDescriptor::new_without_display_handle());
    pollster::block_on(instance.request_adapter(&Default::default()))
        .ok()
        .map(|a| a.get_info())
}

fn gpu_available() -> bool {
    let ok = adapter_info().is_some();
    if !ok {
        assert!(
            !in_ci(),
            "CI must run the GPU tests: no wgpu adapter found (is mesa-vulkan-drivers installed?)"
        );
        eprintln!(
            "\n!!!!! SKIPPING: no wgpu adapter (install mesa-vulkan-drivers for lavapipe) !!!!!\n"
        );
    }
    ok
}

/// Whether the adapter the GPU tests get is a software rasteriser (lavapipe).
fn software_adapter() -> bool {
    adapter_info().is_some_and(|info| windloom::gpu::is_software(&info))
}

fn example(name: &str) -> Layout {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("layouts")
        .join(name);
    windloom::io::load(&p).unwrap()
}

fn harness(doc: Layout) -> Harness<'static, EditorApp> {
    harness_on(doc, None)
}

/// The editor on `doc`, read from `path` if given, paused, after its first frames.
fn harness_on(doc: Layout, path: Option<std::path::PathBuf>) -> Harness<'static, EditorApp> {
    let mut h = Harness::builder()
        .with_size(egui::vec2(1280.0, 800.0))
        .with_max_steps(16)
        .wgpu()
        .build_eframe(move |cc| {
            let mut app = EditorApp::new(doc, path, &cc.egui_ctx);
            app.live.set_playing(false);
            app
        });
    h.run_steps(3);
    h
}

/// The editor on `doc` on a device made as the editor makes it, with the GPU attached (its map
/// passes, the 3D view), paused; `set` adjusts it before the first frame.
fn gpu_harness(
    doc: Layout,
    set: impl FnOnce(&mut EditorApp) + 'static,
) -> Harness<'static, EditorApp> {
    gpu_harness_sized(doc, egui::vec2(1280.0, 800.0), set)
}

/// [`gpu_harness`] in a window of `size` points.
fn gpu_harness_sized(
    doc: Layout,
    size: egui::Vec2,
    set: impl FnOnce(&mut EditorApp) + 'static,
) -> Harness<'static, EditorApp> {
    Harness::builder()
        .with_size(size)
        .with_max_steps(16)
        .wgpu_setup(windloom_wgpu_setup())
        .build_eframe(move |cc| {
            let mut app = EditorApp::new(doc, None, &cc.egui_ctx);
            app.live.set_playing(false);
            set(&mut app);
            app.attach_gpu(
                cc.wgpu_render_state
                    .as_ref()
                    .expect("kittest's wgpu renderer"),
            );
            app
        })
}

fn click(h: &mut Harness<'_, EditorApp>, pos: Pos2) {
    h.event(Event::PointerMoved(pos));
    h.run_steps(1);
    for pressed in [true, false] {
        h.event(Event::PointerButton {
            pos,
            button: PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        });
        h.run_steps(1);
    }
    h.run_steps(1);
}

fn drag(h: &mut Harness<'_, EditorApp>, from: Pos2, to: Pos2) {
    h.event(Event::PointerMoved(from));
    h.run_steps(1);
    h.event(Event::PointerButton {
        pos: from,
        button: PointerButton::Primary,
        pressed: true,
        modifiers: Modifiers::NONE,
    });
    h.run_steps(1);
    for k in 1..=8 {
        let p = from + (to - from) * (k as f32 / 8.0);
        h.event(Event::PointerMoved(p));
        h.run_steps(1);
    }
    h.event(Event::PointerButton {
        pos: to,
        button: PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::NONE,
    });
    h.run_steps(2);
}

/// World distance that one screen point covers, for position tolerances.
fn metres_per_point(h: &Harness<'_, EditorApp>) -> f32 {
    1.0 / h.state().map.camera.expect("the map has been drawn").zoom
}

/// The device the editor would make: kittest's software-preferring setup with windloom's
/// features and limits (`gpu::device_descriptor`), as `app::run` asks eframe for.
fn windloom_wgpu_setup() -> eframe::egui_wgpu::WgpuSetup {
    let mut setup = egui_kittest::wgpu::default_wgpu_setup();
    if let eframe::egui_wgpu::WgpuSetup::CreateNew(create) = &mut setup {
        create.device_descriptor = std::sync::Arc::new(windloom::gpu::device_descriptor);
    }
    setup
}

/// Steps the paused worker `n` times and waits until the snapshot shows them, on `backend`,
/// drawing frames meanwhile (the UI thread submits the simulation's GPU work).
fn step_and_wait(h: &mut Harness<'_, EditorApp>, n: usize, backend: RunsOn) {
    let before = h.state().live.snapshot().time;
    let dt = h.state().doc.sim.dt;
    for _ in 0..n {
        h.state().live.step_once();
    }
    let deadline = Instant::now() + Duration::from_secs(240);
    loop {
        let s = h.state().live.snapshot();
        if s.runs_on == backend && s.time >= before + n as f32 * dt - 1e-3 {
            return;
        }
        assert!(
            Instant::now() < deadline,
            "the simulation did not reach t = {} on {backend:?} (at {} on {:?}; {:?})",
            before + n as f32 * dt,
            s.time,
            s.runs_on,
            s.notice
        );
        h.step();
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Whether a program can be started (`--help`/`-version` output is not looked at).
fn program_exists(name: &str, arg: &str) -> bool {
    std::process::Command::new(name)
        .arg(arg)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok()
}

/// Polls `f` every 200 ms for up to `secs` seconds.
fn wait_for<T>(secs: u64, mut f: impl FnMut() -> Option<T>) -> Option<T> {
    let end = Instant::now() + Duration::from_secs(secs);
    while Instant::now() < end {
        if let Some(t) = f() {
            return Some(t);
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    None
}

/// Authoring with the mouse and the inspector.
mod editing;
/// An editor left open: memory and wgpu resources flat over hundreds of frames.
mod endurance;
/// Copy and paste, nudging, lock and hide.
mod everyday;
/// Export / Bake from the editor.
mod export;
/// Files: bad files, autosave and recovery, a typed path without a dialog, changes on disk,
/// concurrent saves, and a killed editor's last edit.
mod files;
/// Painted and attached images: saved, autosaved and restored.
mod images;
/// A level built from nothing: backdrop handles, new masks and density maps, the brush.
mod level;
/// Shapes edited with handles, transforms, several points at once.
mod shapes;
/// A map that holds still: panels, menus, drags at a low frame rate.
mod steady;
/// The timeline: keys, scrubbing, a looping range.
mod timeline;
/// The map and the 3D view on the GPU.
mod views;
/// The window: snapshots, Xvfb, no display, idling.
mod window;
