//! The views on the GPU: the map drawn from the GPU solver, switching backends, the map
//! and the 3D view side by side, a fixed speed scale, the 3D view's wind colours, and the
//! 3D grass answering edits.

use super::*;

/// The map view with the wind on the GPU, drawn from the solver's buffers through the
/// `egui_wgpu` callback: its own snapshot beside the CPU-drawn `editor_obstacles`.
#[test]
fn editor_window_snapshot_drawn_on_the_gpu() {
    if !gpu_available() {
        return;
    }
    let mut h = gpu_harness(example("obstacles.json"), |app| {
        app.settings.backend = Backend::Gpu;
    });
    h.state_mut().settings.wind_view = windloom::app::view::WindView::Glyphs;
    step_and_wait(&mut h, 120, RunsOn::Gpu);
    let snap = h.state().live.snapshot();
    assert!(snap.field.is_some(), "the map draws from the GPU's buffers");
    h.run_steps(3);
    let status = h.state().status_rect;
    h.mask(status);
    h.snapshot("editor_obstacles_gpu");

    // The same field run on the CPU is drawn by the same GPU passes from an uploaded copy:
    // after a hand-over (bit for bit) the map looks the same.
    let on_gpu = h.render().expect("renders");
    h.state_mut().set_backend(Backend::Cpu);
    let deadline = Instant::now() + Duration::from_secs(60);
    while h.state().live.snapshot().runs_on != RunsOn::Cpu {
        assert!(Instant::now() < deadline, "no hand-over to the CPU");
        h.step();
        std::thread::sleep(Duration::from_millis(20));
    }
    h.run_steps(3);
    let on_cpu = h.render().expect("renders");
    let map = h.state().map.rect;
    let ppp = h.ctx.pixels_per_point();
    let mut differ = 0;
    let mut total = 0;
    for y in (map.top() * ppp) as u32..(map.bottom() * ppp) as u32 {
        for x in (map.left() * ppp) as u32..(map.right() * ppp) as u32 {
            total += 1;
            let (a, b) = (on_gpu.get_pixel(x, y), on_cpu.get_pixel(x, y));
            if a.0.iter().zip(b.0).any(|(p, q)| p.abs_diff(q) > 2) {
                differ += 1;
            }
        }
    }
    assert!(
        differ * 1000 <= total,
        "{differ} of {total} map pixels differ between the GPU-run and CPU-run field"
    );
}

/// Switching backends hands the running field over: the field the GPU starts from is the
/// CPU's, bit for bit, and back; and the GPU then carries on as the CPU would.
#[test]
fn switching_backends_keeps_the_running_field() {
    let Ok(ctx) = windloom::gpu::GpuContext::headless() else {
        assert!(!in_ci(), "CI must run the GPU tests: no wgpu adapter found");
        eprintln!("\n!!!!! SKIPPING: no wgpu adapter !!!!!\n");
        return;
    };
    let layout = example("meadow.json");
    let mut live = LiveSim::start(&layout, || {});
    live.set_playing(false);
    live.set_gpu(ctx, Backend::Cpu);
    let wait = |live: &LiveSim, serial: u64, backend: RunsOn| {
        let deadline = Instant::now() + Duration::from_secs(120);
        loop {
            let s = live.snapshot();
            if s.serial > serial && s.runs_on == backend {
                return s;
            }
            assert!(
                Instant::now() < deadline,
                "no snapshot on {backend:?}: {:?}",
                s.notice
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    };
    let steps = |live: &LiveSim, n: usize, backend: RunsOn| {
        let mut s = live.snapshot();
        for _ in 0..n {
            live.step_once();
            s = wait(live, s.serial, backend);
        }
        s
    };
    // A running field on the CPU.
    let cpu = steps(&live, 30, RunsOn::Cpu);
    assert!(cpu.time > 0.4 && cpu.velocity.iter().any(|v| v[0] != 0.0));
    // Onto the GPU: the same field, the same clock.
    live.set_backend(Backend::Gpu);
    let on_gpu = wait(&live, cpu.serial, RunsOn::Gpu);
    assert_eq!(on_gpu.time, cpu.time, "the clock carries over");
    assert!(
        on_gpu.velocity == cpu.velocity && on_gpu.pressure == cpu.pressure,
        "the GPU starts from the CPU's field, bit for bit"
    );
    // Ten steps on the GPU stay with ten on a CPU solver from the same field.
    let gpu_later = steps(&live, 10, RunsOn::Gpu);
    let mut reference = windloom::sim::Solver::new(&layout);
    {
        // Replay the CPU's 30 steps, then 10 more.
        for _ in 0..40 {
            reference.step();
        }
    }
    let peak = reference
        .velocity_field()
        .iter()
        .fold(0.0f32, |m, v| m.max(v[0].hypot(v[1])));
    let err = gpu_later
        .velocity
        .iter()
        .zip(reference.velocity_field())
        .fold(0.0f32, |m, (a, b)| {
            m.max((a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
        });
    assert!(
        err <= 1e-3 * peak,
        "after the hand-over the GPU drifts from the CPU: {err} (peak {peak})"
    );
    // And back to the CPU: the field the GPU had.
    live.set_backend(Backend::Cpu);
    let back = wait(&live, gpu_later.serial, RunsOn::Cpu);
    assert_eq!(back.time, gpu_later.time);
    assert!(
        back.velocity == gpu_later.velocity,
        "the CPU takes the GPU's field back, bit for bit"
    );
}

/// "Map + 3D": the map and the 3D view each get half the centre (the grass controls above
/// the 3D view, not beside it), the map reframed to show the whole world in its half, and
/// framed again on the full width when the map is alone.
#[test]
fn map_and_3d_side_by_side_each_get_their_half() {
    if !gpu_available() {
        return;
    }
    let mut h = gpu_harness(example("meadow.json"), |_| {});
    h.run_steps(3);
    let (lo, hi) = h.state().doc.bounds();
    // The world's rectangle on screen, and the map pane.
    let world = |h: &Harness<'_, EditorApp>| {
        egui::Rect::from_min_max(h.state().screen_pos(lo), h.state().screen_pos(hi))
    };
    let full = h.state().map.rect;
    let framed = world(&h);
    assert!(full.contains_rect(framed), "{framed:?} in {full:?}");

    h.state_mut().settings.central = windloom::app::Central::Split;
    h.run_steps(3);
    let map = h.state().map.rect;
    let view = h.state().grass_view.rect.expect("the 3D view is drawn");
    assert!(
        (map.width() - full.width() / 2.0).abs() <= 1.0,
        "the map takes half: {map:?} of {full:?}"
    );
    assert!(
        view.left() >= map.right() - 0.5 && view.right() <= full.right() + 0.5,
        "the 3D view beside the map: {view:?}, map {map:?}"
    );
    assert!(
        view.width() >= map.width() - 1.0 && view.height() >= 0.85 * map.height(),
        "the 3D view fills its half under its controls: {view:?}, map {map:?}"
    );
    let half = world(&h);
    assert!(
        map.contains_rect(half),
        "the whole world in the map's half: {half:?} in {map:?}"
    );
    assert!(
        half.width() >= 0.85 * map.width(),
        "framed, not shrunk: {half:?} in {map:?}"
    );
    // The 3D view frames the whole world for its pane's shape, and again when the window
    // is resized; once the user has moved the camera, a resize leaves it where it is.
    let framed_3d = |h: &Harness<'_, EditorApp>| {
        let view = h.state().grass_view.rect.unwrap();
        let aspect = view.width() / view.height();
        let want = windloom::app::Orbit::frame_all(&h.state().doc, aspect);
        (h.state().grass_view.orbit == Some(want), aspect)
    };
    assert!(framed_3d(&h).0);
    h.set_size(egui::vec2(1000.0, 800.0));
    h.run_steps(3);
    let (ok, aspect) = framed_3d(&h);
    assert!(ok, "the 3D view framed for its resized pane ({aspect})");
    let mut moved = h.state().grass_view.orbit.unwrap();
    moved.yaw += 0.5;
    h.state_mut().grass_view.orbit = Some(moved);
    h.set_size(egui::vec2(1280.0, 800.0));
    h.run_steps(3);
    assert_eq!(h.state().grass_view.orbit, Some(moved));

    // Side by side, each view marks where the other's pointer is on the ground: the map's
    // pointer at the world's centre is marked in 3D where the camera projects that point.
    let centre = {
        let (lo, hi) = h.state().doc.bounds();
        [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0]
    };
    let on_map = h.state().map.camera.unwrap().to_screen(map, centre);
    h.event(Event::PointerMoved(on_map));
    h.run_steps(2);
    let view = h.state().grass_view.rect.unwrap();
    let vp = h
        .state()
        .grass_view
        .orbit
        .unwrap()
        .camera()
        .view_proj(view.width() / view.height());
    let q = vp.project_point3(glam::Vec3::new(centre[0], 0.0, centre[1]));
    let want = egui::pos2(
        view.left() + (q.x + 1.0) / 2.0 * view.width(),
        view.top() + (1.0 - q.y) / 2.0 * view.height(),
    );
    let mark = h
        .state()
        .grass_view
        .mark
        .expect("the map's pointer marked in 3D");
    assert!((mark - want).length() < 1.0, "{mark:?}, want {want:?}");
    // And the 3D view's pointer is read on the map's side (the status bar's reading).
    h.event(Event::PointerMoved(view.center()));
    h.run_steps(2);
    assert!(h.state().grass_view.mark.is_none(), "no map pointer then");
    assert!(h.state().grass_view.hover_ground.is_some());

    h.state_mut().settings.central = windloom::app::Central::Map;
    h.run_steps(3);
    let again = world(&h);
    assert!(
        (again.width() - framed.width()).abs() <= 1.0
            && (again.center() - framed.center()).length() <= 1.0,
        "framed as before: {again:?} against {framed:?}"
    );
}

/// A fixed speed scale (View menu) holds the speed colours still: with it off the map's
/// legend reads the field's peak and the fastest cell is the top of the scale; set to twice
/// the peak, the legend reads that and the fastest cell is the scale's middle colour. A
/// hand-edited scale out of range is brought back into the menu's on load.
#[test]
fn a_fixed_speed_scale_holds_the_speed_colours_still() {
    use windloom::app::view::{WindView, field_image, field_scale, speed_colour};
    let mut h = harness(example("meadow.json"));
    h.state_mut().settings.wind_view = WindView::Speed;
    step_and_wait(&mut h, 30, RunsOn::Cpu);
    h.run_steps(2);
    let snap = h.state().live.snapshot();
    let peak = field_scale(&snap, WindView::Speed, None);
    assert!(peak > 1.0, "the meadow's wind after 30 steps: {peak}");
    assert_eq!(
        h.state().map.legend_scale,
        peak,
        "the legend reads the peak"
    );

    h.state_mut().settings.speed_scale = Some(2.0 * peak);
    h.run_steps(2);
    assert_eq!(
        h.state().map.legend_scale,
        2.0 * peak,
        "the legend reads the fixed scale"
    );

    // The fastest cell's colour (the Speed view's: 230/255 over the map).
    let fastest = (0..snap.velocity.len())
        .max_by(|&a, &b| {
            let s = |k: usize| snap.velocity[k][0].hypot(snap.velocity[k][1]);
            s(a).total_cmp(&s(b))
        })
        .unwrap();
    let shown = |t: f32| {
        let c = speed_colour(t).gamma_multiply(230.0 / 255.0);
        egui::Color32::from_rgba_unmultiplied(c.r(), c.g(), c.b(), 230)
    };
    let (auto, _) = field_image(&snap, WindView::Speed, None).unwrap();
    assert_eq!(auto.pixels[fastest], shown(1.0));
    let (fixed, scale) = field_image(&snap, WindView::Speed, Some(2.0 * peak)).unwrap();
    assert_eq!(scale, 2.0 * peak);
    assert_eq!(fixed.pixels[fastest], shown(0.5));

    let edited = serde_json::from_str(r#"{"speed_scale": 1e9}"#).unwrap();
    h.state_mut().apply_settings(edited);
    assert_eq!(h.state().settings.speed_scale, Some(200.0));
}

/// The 3D view's wind colours and arrows outlast the editor: the settings it saves carry
/// them (toggles and opacity), a new editor given those settings shows them so again,
/// settings from before they existed load with the colours off and the arrows on, and a
/// hand-edited opacity out of range is brought back into the slider's.
#[test]
fn the_3d_view_s_wind_colours_and_arrows_are_kept_between_runs() {
    use windloom::app::Settings;
    let h = {
        let mut h = harness(example("meadow.json"));
        h.state_mut().grass_view.controls.wind_colours = true;
        h.state_mut().grass_view.controls.wind_opacity = 0.8;
        h.state_mut().grass_view.controls.arrows = false;
        h.run();
        h
    };
    let json = serde_json::to_string(&h.state().settings_to_save()).unwrap();
    let mut next = harness(example("meadow.json"));
    assert!(
        !next.state().grass_view.controls.wind_colours,
        "off at first"
    );
    assert!(
        next.state().grass_view.controls.arrows,
        "arrows on at first"
    );
    next.state_mut()
        .apply_settings(serde_json::from_str::<Settings>(&json).unwrap());
    let c = next.state().grass_view.controls;
    assert!(
        c.wind_colours && c.wind_opacity == 0.8 && !c.arrows,
        "{json}"
    );

    let older: Settings = serde_json::from_str(r#"{"snap": true}"#).unwrap();
    next.state_mut().apply_settings(older);
    let c = next.state().grass_view.controls;
    assert!(!c.wind_colours && c.wind_opacity == 0.6 && c.arrows);
    assert!(
        next.state().settings.snap,
        "the rest of the settings are taken"
    );

    let edited: Settings =
        serde_json::from_str(r#"{"wind_colours": true, "wind_opacity": 7.0}"#).unwrap();
    next.state_mut().apply_settings(edited);
    assert_eq!(next.state().grass_view.controls.wind_opacity, 1.0);
}

/// The 3D grass view: drawn on eframe's device in the live wind, its blades rebuilt when a
/// grass edit changes them (and back on undo), with its own snapshots (plain, and with the
/// wind colours and their legend).
#[test]
fn the_3d_grass_view_answers_grass_edits() {
    if !gpu_available() {
        return;
    }
    // The wind on the CPU on every adapter, so the snapshot shows the same field: the
    // automatic choice runs it on a hardware GPU (lavapipe measures and takes the CPU).
    let mut h = gpu_harness(example("meadow.json"), |app| {
        app.settings.central = windloom::app::Central::Grass;
        app.settings.backend = Backend::Cpu;
    });
    step_and_wait(&mut h, 60, RunsOn::Cpu);
    h.run_steps(3);
    let all = windloom::grass::scatter(&h.state().doc).len() as u32;
    let g = &h.state().grass_view;
    assert_eq!(
        g.total_blades, all,
        "the view holds every blade of the layout"
    );
    assert!(g.blades > 0 && g.blades <= all);
    // The cull pass's counters reach the view: every blade is counted once, culled by one
    // test or drawn at one level.
    let stats = h
        .state()
        .grass_view
        .stats
        .expect("cull counters after a few frames");
    let g = &h.state().grass_view;
    assert_eq!(stats.total, g.blades);
    assert_eq!(
        stats.drawn_total() + stats.orientation + stats.frustum + stats.distance,
        stats.total
    );
    // A software adapter's sample spends nothing on edge-on blades (the cull would drop them).
    assert!(
        stats.drawn_total() > 0
            && (stats.orientation > 0 || h.state().grass_view.samples_the_view()),
        "{stats:?}"
    );
    // The snapshots are of the view a software rasteriser (CI's lavapipe) draws: a sample of
    // the blades, dense near the camera. A hardware GPU draws every blade, a different
    // picture by design, so there the pictures are not compared.
    let sampled = h.state().grass_view.blades < all;
    assert_eq!(
        sampled,
        software_adapter(),
        "a software adapter draws a sample of the meadow's blades, a hardware one all"
    );
    if !sampled {
        eprintln!(
            "\n!!!!! NOT COMPARED: the editor_grass snapshots are a software adapter's \
             blade sample; this adapter draws all {all} blades !!!!!\n"
        );
    }
    let status = h.state().status_rect;
    h.mask(status);
    if let Some(r) = h.state().grass_view.counters_rect {
        h.mask(r);
    }
    if sampled {
        h.snapshot("editor_grass");
    }

    // The wind colours: the grass and ground on the map view's speed scale, with its legend;
    // their slider fits the row, so the view keeps its size.
    let view = h.state().grass_view.rect;
    h.state_mut().grass_view.controls.wind_colours = true;
    h.run_steps(3);
    assert_eq!(h.state().grass_view.rect, view, "the 3D view kept its size");
    // Timings and counters vary from run to run (the masks hold for one snapshot).
    h.mask(h.state().status_rect);
    if let Some(r) = h.state().grass_view.counters_rect {
        h.mask(r);
    }
    if sampled {
        h.snapshot("editor_grass_wind_colours");
    }
    h.state_mut().grass_view.controls.wind_colours = false;

    // The status bar reads the ground under the pointer: the view's centre is the orbit's
    // target; off the view there is no reading.
    let view = h.state().grass_view.rect.unwrap();
    h.event(Event::PointerMoved(view.center()));
    h.run_steps(2);
    let target = h.state().grass_view.orbit.unwrap().target;
    let at = h
        .state()
        .map
        .cursor_world
        .expect("a ground point under the pointer");
    assert!(
        (at[0] - target.x).abs() < 0.5 && (at[1] - target.z).abs() < 0.5,
        "{at:?} under the centre, the camera looks at {target:?}"
    );
    h.event(Event::PointerMoved(Pos2::new(5.0, 400.0)));
    h.run_steps(2);
    assert_eq!(h.state().map.cursor_world, None, "off the 3D view");

    // Every test off: every blade drawn at full detail.
    let mut c = h.state().grass_view.controls.cull.expect("defaults");
    c.orientation = false;
    c.frustum = false;
    c.distance = false;
    c.lod = false;
    h.state_mut().grass_view.controls.cull = Some(c);
    // The counters come back without waiting, a few frames late (more while other tests load
    // the software rasteriser): up to 40 frames for them to show every blade drawn.
    for _ in 0..40 {
        h.run_steps(1);
        let s = h.state().grass_view.stats.unwrap();
        if s.drawn == [s.total, 0, 0] {
            break;
        }
    }
    let stats = h.state().grass_view.stats.unwrap();
    assert_eq!(stats.drawn, [stats.total, 0, 0], "no culling: all drawn");

    // The Bezier model, chosen as the inspector does, takes over live on the same blades.
    let mut grass = h.state().doc.grass.clone();
    grass.model = windloom::doc::GrassModel::BezierPhysics;
    let ctx = h.ctx.clone();
    assert!(
        h.state_mut()
            .edit(&ctx, windloom::doc::Edit::SetGrass(grass))
    );
    h.run_steps(3);
    assert_eq!(
        h.state().grass_view.model(),
        Some(windloom::doc::GrassModel::BezierPhysics)
    );
    assert_eq!(h.state().grass_view.total_blades, all, "no new blades");
    h.state_mut().undo();
    h.run_steps(2);
    assert_eq!(
        h.state().grass_view.model(),
        Some(windloom::doc::GrassModel::CwdQuadratic)
    );

    // Halving the density (an undoable edit, as the inspector makes it) rebuilds the blades.
    let mut grass = h.state().doc.grass.clone();
    grass.density /= 2.0;
    let ctx = h.ctx.clone();
    assert!(
        h.state_mut()
            .edit(&ctx, windloom::doc::Edit::SetGrass(grass))
    );
    h.run_steps(2);
    let half = h.state().grass_view.total_blades;
    assert!(
        (half as f32 - all as f32 / 2.0).abs() < all as f32 * 0.05,
        "{half} blades after halving {all}"
    );
    h.state_mut().undo();
    h.run_steps(2);
    assert_eq!(
        h.state().grass_view.total_blades,
        all,
        "undo brings the blades back"
    );

    // A close view on a software adapter: the blade sample follows the camera once it
    // rests, and is a budget on the blades drawn, so most of it is drawn — far more in view
    // than an even sample of the meadow would put there (the share of the field the view
    // shows: half a per cent).
    if h.state().grass_view.samples_the_view() {
        let close = windloom::app::Orbit {
            distance: 6.0,
            pitch: 0.8,
            ..h.state().grass_view.orbit.expect("the view's camera")
        };
        h.state_mut().grass_view.orbit = Some(close);
        // The culling tests on again (turned off above).
        let mut c = h.state().grass_view.controls.cull.unwrap();
        (c.orientation, c.frustum, c.distance, c.lod) = (true, true, true, true);
        h.state_mut().grass_view.controls.cull = Some(c);
        h.run_steps(40);
        let s = h.state().grass_view.stats.unwrap();
        let in_view = (s.total - s.frustum) as f32 / s.total as f32;
        let rect = h.state().grass_view.rect.unwrap();
        let vp = close.camera().view_proj(rect.width() / rect.height());
        let blades = windloom::grass::scatter(&h.state().doc);
        let even = blades
            .iter()
            .filter(|b| {
                let c = vp * glam::Vec4::new(b.pos[0], 0.0, b.pos[1], 1.0);
                c.w > 0.0 && c.x.abs() <= c.w && c.y.abs() <= c.w
            })
            .count() as f32
            / blades.len() as f32;
        let budget = windloom::app::SOFTWARE_BLADE_BUDGET as usize;
        assert!(
            in_view > 5.0 * even,
            "{in_view} of the sample in view, an even sample {even}: {s:?}"
        );
        // The budget goes to the blades the frame draws: here the view holds fewer than it,
        // so it is every one of them (the close-up at the field's full density), and most
        // of them are drawn.
        let eye = close.camera().eye;
        let drawable = blades
            .iter()
            .enumerate()
            .filter(|(i, b)| windloom::grass::sample::key(*i as u32, b, eye, &vp).is_some())
            .count();
        assert_eq!(s.total as usize, drawable.min(budget), "{s:?}");
        assert!(
            s.drawn_total() as f32 > 0.8 * s.total as f32,
            "most of the budget is drawn: {s:?}"
        );
    }
}

/// At the editor's default window size the 3D view's row of toggles and values fits its
/// pane, alone or beside the map, with Push and the wind colours on: nothing runs under the
/// inspector, and each tick sits apart from the label before it.
#[test]
fn the_3d_view_s_controls_fit_their_pane() {
    if !gpu_available() {
        return;
    }
    for central in [windloom::app::Central::Grass, windloom::app::Central::Split] {
        let mut h = gpu_harness_sized(example("meadow.json"), egui::vec2(1400.0, 860.0), |app| {
            app.live.set_playing(false);
        });
        h.state_mut().settings.central = central;
        h.state_mut().grass_view.controls.push = true;
        h.state_mut().grass_view.controls.wind_colours = true;
        h.run_steps(4);
        let pane = h.state().grass_view.rect.expect("the 3D view is drawn");
        let labels = [
            "edge-on",
            "off-screen",
            "distance",
            "LOD",
            "far field",
            "wind colours",
            "Push",
        ];
        let mut rects: Vec<(String, egui::Rect)> = labels
            .iter()
            .map(|l| (l.to_string(), h.get_by_label(l).rect()))
            .collect();
        for value in ["opacity", "radius", "trail"] {
            let r = h.get_by_label_contains(value).rect();
            rects.push((value.to_string(), r));
        }
        for (name, r) in &rects {
            assert!(
                r.left() >= pane.left() - 0.5 && r.right() <= pane.right() + 0.5,
                "{central:?}: {name} at {r:?} outside the pane {pane:?}"
            );
        }
        // In reading order, row by row: a gap between each control and the next.
        rects.sort_by(|a, b| {
            (a.1.center().y.round() as i32, a.1.left() as i32)
                .cmp(&(b.1.center().y.round() as i32, b.1.left() as i32))
        });
        for w in rects.windows(2) {
            let ((a, ra), (b, rb)) = (&w[0], &w[1]);
            if (ra.center().y - rb.center().y).abs() < 4.0 {
                assert!(
                    rb.left() - ra.right() >= 2.0,
                    "{central:?}: {b} ({rb:?}) against {a} ({ra:?})"
                );
            }
        }
    }
}

/// The 3D view's wind colours decode the speed scale's sRGB bytes exactly as egui does, so
/// they agree with the map's to the bit (`colour.rs` keeps egui out of the ground floor).
#[test]
fn wind_colours_decode_srgb_as_egui_does() {
    for s in 0..=255u8 {
        let ours = windloom::colour::linear(s);
        let egui = egui::ecolor::linear_f32_from_gamma_u8(s);
        assert_eq!(ours.to_bits(), egui.to_bits(), "byte {s}");
    }
}

/// The map's speed colours let the level's picture show through: over a red backdrop the map
/// reads red under the colours at their automatic opacity (the picture hidden at full), and
/// the View menu's opacity is the designer's, kept with the settings.
#[test]
fn the_speed_colours_let_the_backdrop_show_through() {
    use windloom::app::view::WindView;
    if !gpu_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    image::RgbaImage::from_pixel(8, 8, image::Rgba([220, 20, 20, 255]))
        .save(dir.path().join("red.png"))
        .unwrap();
    let level = dir.path().join("level.json");
    let mut l = example("two-winds.json");
    l.world.map = Some(doc::MapBackdrop {
        image: "red.png".into(),
        opacity: 1.0,
        rect: None,
    });
    windloom::io::save(&level, &l).unwrap();
    let mut h = harness_on(windloom::io::load(&level).unwrap(), Some(level));
    h.state_mut().settings.wind_view = WindView::Speed;
    step_and_wait(&mut h, 30, RunsOn::Cpu);
    h.run_steps(3);
    let redness = |h: &mut Harness<'_, EditorApp>| {
        let img = h.render().expect("renders");
        let ppp = h.ctx.pixels_per_point();
        let p = h.state().screen_pos([30.0, 20.0]);
        let px = img.get_pixel((p.x * ppp) as u32, (p.y * ppp) as u32);
        i32::from(px.0[0]) - i32::from(px.0[1].max(px.0[2]))
    };
    let auto = redness(&mut h);
    h.state_mut().settings.map_wind_opacity = Some(1.0);
    h.run_steps(2);
    let full = redness(&mut h);
    println!("red over green-blue: automatic {auto}, opaque {full}");
    assert!(
        auto > full + 40,
        "the backdrop shows through: {auto} against {full}"
    );
    assert!(
        windloom::app::map_wind_opacity(None, true) < 1.0
            && windloom::app::map_wind_opacity(None, false) == 1.0
    );
    // Kept between runs, and held to its range.
    let saved = h.state().settings_to_save();
    assert_eq!(saved.map_wind_opacity, Some(1.0));
    let edited = serde_json::from_str(r#"{"map_wind_opacity": 7.0}"#).unwrap();
    h.state_mut().apply_settings(edited);
    assert_eq!(h.state().settings.map_wind_opacity, Some(1.0));
}
