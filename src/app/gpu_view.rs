//! The editor's one bridge to the GPU (`egui_wgpu::CallbackTrait`): the map view's wind,
//! drawn by [`crate::gpu::mapview::MapRenderer`] straight from the live solver's buffers on
//! the device eframe draws the UI with. Everything GPU-side lives in `crate::gpu`; this file
//! only hands it egui's encoder and render pass.

use crate::engine::live::Snapshot;
use crate::gpu::grass::Orbit;
use crate::gpu::mapview::{FieldBuffers, Frame, MapRenderer};
use eframe::egui;
use eframe::egui_wgpu::{self, CallbackResources, CallbackTrait, ScreenDescriptor};
use eframe::wgpu;

/// Makes the map renderer for eframe's device and target format.
pub fn install(rs: &egui_wgpu::RenderState) {
    let renderer = MapRenderer::new(&rs.device, rs.target_format);
    rs.renderer.write().callback_resources.insert(renderer);
}

/// GPU work the simulation thread hands the UI thread to submit, each with a channel to
/// say it was.
pub(super) type GpuSubmissions =
    std::sync::mpsc::Receiver<(wgpu::CommandBuffer, std::sync::mpsc::SyncSender<()>)>;

/// The editor's bridge to eframe's GPU device: its render state, the live wind's GPU work
/// to submit, a CPU-run field's copy there, and the adapter's name.
pub struct GpuBridge {
    pub(super) submissions: Option<GpuSubmissions>,
    /// Whether the map can draw a GPU field (the map renderer is installed on eframe's
    /// device).
    pub map_on_gpu: bool,
    /// eframe's render state, when the map draws on the GPU.
    pub render_state: Option<egui_wgpu::RenderState>,
    /// A CPU-run field's copy on the GPU, for drawing it there.
    pub(super) uploaded: Uploaded,
    /// The colour scale of the GPU-drawn view, from the last read-back: (serial, view, scale).
    pub(super) scale: Option<(super::ScaleKey, f32)>,
    /// The adapter, as the status bar names it.
    pub adapter: String,
}

impl Default for GpuBridge {
    fn default() -> Self {
        Self {
            submissions: None,
            map_on_gpu: false,
            render_state: None,
            uploaded: Uploaded::default(),
            scale: None,
            adapter: "no GPU adapter".into(),
        }
    }
}

/// Copies of a CPU-run field on the GPU, so the map view draws it with the same passes as a
/// GPU-run one (no per-segment tessellation on the CPU); rewritten when a new snapshot arrives.
#[derive(Default)]
pub struct Uploaded {
    field: Option<(u64, FieldBuffers)>,
}

impl Uploaded {
    /// The buffers holding `snap`'s field, uploaded if it is newer than the last.
    pub fn field(&mut self, rs: &egui_wgpu::RenderState, snap: &Snapshot) -> Option<FieldBuffers> {
        let (nx, ny) = (snap.nx as u32, snap.ny as u32);
        if nx == 0
            || snap.u.len() != (snap.nx + 1) * snap.ny
            || snap.v.len() != snap.nx * (snap.ny + 1)
        {
            return None;
        }
        let data = (&snap.u[..], &snap.v[..], &snap.pressure[..]);
        let cell = [snap.size[0] / snap.nx as f32, snap.size[1] / snap.ny as f32];
        match &mut self.field {
            Some((serial, f)) if f.nx == nx && f.ny == ny => {
                if *serial != snap.serial {
                    f.write(&rs.queue, data);
                    *serial = snap.serial;
                }
                f.origin = snap.origin;
                f.cell = cell;
            }
            _ => {
                let f = FieldBuffers::upload(&rs.device, (nx, ny), snap.origin, cell, data);
                self.field = Some((snap.serial, f));
            }
        }
        self.field.as_ref().map(|(_, f)| f.clone())
    }
}

/// The wind over the map view's `rect` this frame.
pub fn map_wind(rect: egui::Rect, field: FieldBuffers, frame: Frame) -> egui::Shape {
    egui::Shape::Callback(egui_wgpu::Callback::new_paint_callback(
        rect,
        MapCallback { field, frame },
    ))
}

struct MapCallback {
    field: FieldBuffers,
    frame: Frame,
}

impl CallbackTrait for MapCallback {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        _screen: &ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
        resources: &mut CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if let Some(r) = resources.get_mut::<MapRenderer>() {
            r.prepare(device, queue, encoder, &self.field, &self.frame);
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &CallbackResources,
    ) {
        if let Some(r) = resources.get::<MapRenderer>() {
            r.paint(pass);
        }
    }
}

/// Blades the 3D view draws on a software adapter: a view-dependent sample
/// ([`crate::grass::sample`]), dense near the camera, chosen again once the camera rests.
pub const SOFTWARE_BLADE_BUDGET: u32 = 40_000;

/// Seconds the camera must rest before the software adapter's sample follows it.
const RESAMPLE_AFTER: f64 = 0.2;

/// Seconds the Bezier blades are drawn after the last change to what the view shows (the
/// wind, the camera, the settings): their physics settles over a few seconds; the CWD
/// blades' pose follows the wind at once.
const BEZIER_SETTLE: f64 = 4.0;

/// What the 3D view shows, as far as it can change between frames: while it stays the same
/// and nothing animates, the view asks for no frames.
#[derive(Debug, Clone, PartialEq)]
struct Shown {
    wind: u64,
    eye: glam::Vec3,
    target: glam::Vec3,
    size: [u32; 2],
    controls: super::grass_controls::GrassControls,
    model: crate::doc::GrassModel,
    speed_scale: Option<f32>,
    beside: Option<MapBeside>,
    sphere: bool,
}

/// The software adapter's sample: every blade of the layout, the one in each uploaded slot,
/// the camera it was chosen for, and when the camera last moved.
struct ViewSample {
    all: Vec<crate::grass::Blade>,
    slots: Vec<u32>,
    for_camera: (glam::Vec3, glam::Vec3, f32),
    seen: (glam::Vec3, glam::Vec3, f32),
    moved_at: f64,
    /// The threshold of the last sample chosen (the far field fills in what it thins).
    threshold: f32,
}

impl ViewSample {
    /// The blades for `camera` (seen with `aspect`), laid into the previous slots; each
    /// widened by what the sample thins around it.
    fn choose(
        &mut self,
        camera: &crate::gpu::grass::Camera,
        aspect: f32,
    ) -> Vec<crate::grass::Blade> {
        use crate::grass::sample;
        let vp = camera.view_proj(aspect);
        let s = sample::choose(&self.all, camera.eye, &vp, SOFTWARE_BLADE_BUDGET as usize);
        self.slots = sample::assign(&self.slots, &s.blades, self.all.len());
        self.for_camera = (camera.eye, camera.target, aspect);
        self.threshold = s.threshold;
        self.slots
            .iter()
            .map(|&i| {
                let mut b = self.all[i as usize];
                b.width *= sample::widen(&b, camera.eye, s.threshold);
                b
            })
            .collect()
    }
}

/// Text over the 3D picture on a pale plate, readable over sky and grass alike, wrapped to
/// `width`; returns the plate's rectangle.
fn on_plate(
    painter: &egui::Painter,
    pos: egui::Pos2,
    align: egui::Align2,
    text: String,
    colour: egui::Color32,
    width: f32,
) -> egui::Rect {
    let font = egui::FontId::proportional(13.0);
    let galley = painter.layout(text, font, colour, width.max(40.0));
    let at = align.anchor_size(pos, galley.size());
    let plate = at.expand2(egui::vec2(5.0, 2.0));
    painter.rect_filled(plate, 3.0, egui::Color32::from_white_alpha(150));
    painter.galley(at.min, galley, colour);
    plate
}

/// Where world point `p` appears in the view drawn in `rect` (in front of the camera).
fn on_screen(camera: &crate::gpu::grass::Camera, rect: egui::Rect, p: glam::Vec3) -> egui::Pos2 {
    let aspect = rect.width() / rect.height().max(1.0);
    let q = camera.view_proj(aspect).project_point3(p);
    egui::pos2(
        rect.left() + (q.x + 1.0) / 2.0 * rect.width(),
        rect.top() + (1.0 - q.y) / 2.0 * rect.height(),
    )
}

/// A horizontal unit vector across the camera's view (for the sphere's screen radius).
fn orbit_side(camera: &crate::gpu::grass::Camera) -> (f32, f32) {
    let d = camera.target - camera.eye;
    let l = d.x.hypot(d.z).max(1e-6);
    (-d.z / l, d.x / l)
}

/// The map beside the 3D view: the world rectangle it shows (min, max), outlined on the
/// ground, and the ground point under its pointer, marked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapBeside {
    pub footprint: ([f32; 2], [f32; 2]),
    pub pointer: Option<[f32; 2]>,
}

/// The editor's 3D view of the grass in the live wind: drawn by
/// [`crate::gpu::grass::GrassRenderer`] on eframe's device into a texture of the view's size,
/// shown as an egui image. The blades are rebuilt when the grass, world or obstacles change;
/// the wind grid is rewritten when a new snapshot arrives.
pub struct GrassView {
    grass: Option<crate::gpu::grass::GrassRenderer>,
    /// The terrain the view stands on, for finding the ground under the pointer.
    terrain: Option<std::sync::Arc<crate::sim::terrain::TerrainField>>,
    built_for: Option<(
        crate::doc::GrassParams,
        crate::doc::World,
        Vec<crate::doc::Obstacle>,
    )>,
    target: Option<(crate::gpu::grass::Target, egui::TextureId)>,
    #[expect(
        clippy::type_complexity,
        reason = "what the scene was built for, compared whole"
    )]
    scene_for: Option<(
        Vec<crate::doc::Tree>,
        Vec<crate::doc::Obstacle>,
        Vec<crate::doc::Probe>,
        bool,
    )>,
    footprint_for: Option<([f32; 2], [f32; 2])>,
    wind_serial: u64,
    /// The wind colours' scale, and the snapshot and fixed scale it was found for.
    wind_scale: Option<(u64, Option<f32>, f32)>,
    /// The View menu's fixed speed scale (`None`: the field's peak), as the map uses it.
    pub speed_scale: Option<f32>,
    pub orbit: Option<Orbit>,
    /// The last 'frame all': the aspect it was for, and the orbit it gave (while the orbit is
    /// still that, the user has not moved the camera since).
    framed_for: Option<(f32, Orbit)>,
    /// Blades drawn (of all the layout has), and the last frame's GPU milliseconds
    /// (submission to completion).
    pub blades: u32,
    pub total_blades: u32,
    /// About how many blades the layout lays out, when the device cannot hold them all and
    /// `total_blades` are those thinned evenly to fit ([`crate::grass::scatter_fitted`]).
    pub layout_blades: Option<u32>,
    pub frame_ms: std::sync::Arc<std::sync::Mutex<f32>>,
    pub controls: super::grass_controls::GrassControls,
    sample: Option<ViewSample>,
    /// The last cull counters the GPU sent back, and where the view shows them.
    pub stats: Option<crate::gpu::grass::CullStats>,
    pub counters_rect: Option<egui::Rect>,
    /// Where the 3D view was drawn last frame.
    pub rect: Option<egui::Rect>,
    /// The ground point (world x, z) under the pointer, while it is over the view.
    pub hover_ground: Option<[f32; 2]>,
    /// The ground point of the last click (a plain left click, not a drag), until taken.
    pub clicked_ground: Option<[f32; 2]>,
    /// A press that closed a menu: it and its drag do nothing here.
    pub swallowed: bool,
    /// Where the map's pointer was marked on the view last frame (beside the map).
    pub mark: Option<egui::Pos2>,
    /// What the last frame showed, and when that last changed (editor seconds).
    shown: Option<Shown>,
    changed_at: f64,
    /// The read-back of the counters that shows the last change.
    stats_due: u64,
}

impl Default for GrassView {
    fn default() -> Self {
        Self {
            grass: None,
            built_for: None,
            terrain: None,
            target: None,
            scene_for: None,
            footprint_for: None,
            wind_serial: u64::MAX,
            wind_scale: None,
            speed_scale: None,
            orbit: None,
            framed_for: None,
            blades: 0,
            total_blades: 0,
            layout_blades: None,
            frame_ms: Default::default(),
            controls: Default::default(),
            sample: None,
            stats: None,
            counters_rect: None,
            rect: None,
            hover_ground: None,
            clicked_ground: None,
            swallowed: false,
            mark: None,
            shown: None,
            changed_at: 0.0,
            stats_due: 0,
        }
    }
}

impl GrassView {
    /// Whether the view draws a sample of the blades that follows the camera (on a software
    /// adapter, when the layout has more than [`SOFTWARE_BLADE_BUDGET`]).
    pub fn samples_the_view(&self) -> bool {
        self.sample.is_some()
    }

    /// The blade model the view draws (`None` before its first frame).
    pub fn model(&self) -> Option<crate::doc::GrassModel> {
        self.grass.as_ref().map(|g| g.model())
    }

    /// Draws the view into the rest of `ui`, with the map beside it when `beside` is given.
    /// In sections: the camera the user moves, the pointer's sphere, the blades (rebuilt
    /// when the grass, world or obstacles change), the renderer's settings and wind, the
    /// texture drawn into, the frame, when to draw the next, and what is drawn over it.
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        rs: &egui_wgpu::RenderState,
        doc: &crate::doc::Layout,
        snap: &Snapshot,
        beside: Option<MapBeside>,
        base: &std::path::Path,
    ) {
        self.controls.ui(ui);
        let sense = if self.swallowed {
            egui::Sense::hover()
        } else {
            egui::Sense::click_and_drag()
        };
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), sense);
        self.rect = Some(rect);
        let aspect = rect.width() / rect.height().max(1.0);
        let camera = self.navigate(ui, &response, rect, doc);
        let ground_at = |p: egui::Pos2| {
            let ndc = [
                (p.x - rect.left()) / rect.width() * 2.0 - 1.0,
                1.0 - (p.y - rect.top()) / rect.height() * 2.0,
            ];
            match &self.terrain {
                Some(t) => camera.terrain_point(aspect, ndc, &|p| t.ground_at(p)),
                None => camera.ground_point(aspect, ndc),
            }
        };
        // The status bar's readout: the ground under the pointer.
        self.hover_ground = response.hover_pos().and_then(ground_at).map(|g| [g.x, g.z]);
        if response.clicked_by(egui::PointerButton::Primary) {
            self.clicked_ground = (response.interact_pointer_pos())
                .and_then(ground_at)
                .map(|g| [g.x, g.z]);
        }
        // The sphere: under the pointer, on the ground, while the left button is down.
        let pushing = self.controls.push && !ui.input(|i| i.modifiers.ctrl);
        let sphere = if pushing && response.is_pointer_button_down_on() {
            response.interact_pointer_pos().and_then(|p| {
                ground_at(p).map(|g| {
                    let r = self.controls.radius;
                    crate::grass::trail::Sphere {
                        centre: [g.x, 0.5 * r, g.z],
                        radius: r,
                    }
                })
            })
        } else {
            None
        };
        self.build(rs, doc, &camera, aspect, base);
        let Some(scale) = self.set_up(rs, doc, snap, sphere, beside.map(|b| b.footprint)) else {
            return;
        };
        let Some(size) = self.size_target(ui, rs, rect) else {
            return;
        };
        self.draw(ui, rs, snap, &camera, aspect);
        self.schedule(ui, doc, snap, &camera, size, beside, sphere.is_some());
        self.overlays(
            ui,
            rect,
            &camera,
            scale,
            beside.and_then(|b| b.pointer),
            sphere,
        );
    }

    /// Orbit with the left button (Ctrl+left while pushing), pan with the right or middle,
    /// zoom with the wheel, arrows and +/- while the pointer is over the view; double-click
    /// (or Home) frames the world again. A framed view stays framed as the pane changes
    /// shape (a window resize, the first frames of *Map + 3D*) until the user moves it.
    fn navigate(
        &mut self,
        ui: &egui::Ui,
        response: &egui::Response,
        rect: egui::Rect,
        doc: &crate::doc::Layout,
    ) -> crate::gpu::grass::Camera {
        let aspect = rect.width() / rect.height().max(1.0);
        let untouched = |(a, framed): (f32, Orbit)| {
            self.orbit == Some(framed) && (a - aspect).abs() > 1e-3 * aspect
        };
        if self.orbit.is_none() || self.framed_for.is_some_and(untouched) {
            let framed = Orbit::frame_all(doc, aspect);
            self.orbit = Some(framed);
            self.framed_for = Some((aspect, framed));
        }
        let orbit = self.orbit.as_mut().expect("set above");
        let pushing = self.controls.push && !ui.input(|i| i.modifiers.ctrl);
        if response.dragged_by(egui::PointerButton::Primary) && !pushing {
            let d = response.drag_delta();
            orbit.yaw += d.x * 0.008;
            orbit.pitch = (orbit.pitch + d.y * 0.006).clamp(0.03, 1.5);
        }
        if response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
        {
            let d = response.drag_delta() * orbit.distance / rect.height().max(1.0);
            let (sy, cy) = orbit.yaw.sin_cos();
            let right = glam::Vec3::new(-sy, 0.0, cy);
            let toward = glam::Vec3::new(cy, 0.0, sy);
            orbit.target += right * -d.x + toward * -d.y;
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y + i.zoom_delta().ln() * 200.0);
            orbit.distance = (orbit.distance * (-scroll / 300.0).exp()).clamp(0.5, 1e5);
        }
        // Keys while the pointer is over the view: arrows orbit, +/- zoom.
        if response.hovered() {
            let (yaw, pitch, zoom) = ui.input(|i| {
                let k = |key| f32::from(u8::from(i.key_down(key)));
                (
                    k(egui::Key::ArrowRight) - k(egui::Key::ArrowLeft),
                    k(egui::Key::ArrowUp) - k(egui::Key::ArrowDown),
                    k(egui::Key::Plus) + k(egui::Key::Equals) - k(egui::Key::Minus),
                )
            });
            if yaw != 0.0 || pitch != 0.0 || zoom != 0.0 {
                let dt = ui.input(|i| i.stable_dt).min(0.1);
                orbit.yaw += yaw * dt * 1.2;
                orbit.pitch = (orbit.pitch + pitch * dt * 0.8).clamp(0.03, 1.5);
                orbit.distance = (orbit.distance * (-zoom * dt * 1.5).exp()).clamp(0.5, 1e5);
                ui.ctx().request_repaint();
            }
        }
        if response.double_clicked()
            || (response.hovered() && ui.input(|i| i.key_pressed(egui::Key::Home)))
        {
            *orbit = Orbit::frame_all(doc, aspect);
            self.framed_for = Some((aspect, *orbit));
        }
        orbit.camera()
    }

    /// The blades, rebuilt when the grass, world or obstacles change (the model switches
    /// live, without new blades): all of them, unless the device cannot hold them (then
    /// evenly thinned), or on a software adapter a sample dense near the camera.
    fn build(
        &mut self,
        rs: &egui_wgpu::RenderState,
        doc: &crate::doc::Layout,
        camera: &crate::gpu::grass::Camera,
        aspect: f32,
        base: &std::path::Path,
    ) {
        use crate::gpu::grass::{GrassRenderer, Target};
        let mut grass_key = doc.grass.clone();
        grass_key.model = Default::default();
        let key = (grass_key, doc.world.clone(), doc.obstacles.clone());
        if self.built_for.as_ref() == Some(&key) {
            return;
        }
        let most = crate::gpu::grass::max_blades(&rs.device.limits());
        let (mut blades, of_layout) = crate::grass::scatter_fitted(doc, most);
        self.total_blades = blades.len() as u32;
        self.layout_blades = of_layout.map(|n| n as u32);
        // A software rasteriser draws about 2.6 µs a blade (docs/PERFORMANCE.md): keep the
        // view interactive there by drawing a sample, dense near the camera.
        let software = crate::gpu::is_software(&rs.adapter.get_info());
        self.sample = None;
        if software && blades.len() > SOFTWARE_BLADE_BUDGET as usize {
            let mut sample = ViewSample {
                all: blades,
                slots: Vec::new(),
                for_camera: Default::default(),
                seen: (camera.eye, camera.target, aspect),
                moved_at: 0.0,
                threshold: f32::INFINITY,
            };
            blades = sample.choose(camera, aspect);
            self.sample = Some(sample);
        }
        let mut grass = GrassRenderer::new(&rs.device, Target::FORMAT, doc, &blades);
        self.terrain = grass.terrain().cloned();
        if let Some(sample) = &self.sample {
            grass.set_sample_reach(sample.threshold);
        }
        // Defaults that follow the blade height, once; the user's toggles after that.
        let cull = *self.controls.cull.get_or_insert(grass.cull_params());
        grass.set_cull(cull);
        self.stats = None;
        if let Some(map) = &doc.world.map {
            // The backdrop, as the map shows it (unreadable: plain soil; the map view says
            // why).
            match crate::io::load_backdrop(base, map) {
                Ok(img) => {
                    let size = [img.width(), img.height()];
                    grass.set_backdrop(
                        &rs.device,
                        &rs.queue,
                        Some((img.as_raw(), size, map.opacity)),
                    );
                }
                Err(e) => log::warn!("{e}; the grass's ground is drawn without it"),
            }
        }
        self.scene_for = None;
        self.blades = grass.blade_count();
        self.grass = Some(grass);
        self.built_for = Some(key);
        self.wind_serial = u64::MAX;
    }

    /// The renderer's settings for this frame: the model, culling, far field, wind colours,
    /// the sphere and its trail, the scene of obstacles and arrows, the map's footprint and a
    /// CPU-run field's new wind. The wind colours' scale, or `None` before any blades.
    fn set_up(
        &mut self,
        rs: &egui_wgpu::RenderState,
        doc: &crate::doc::Layout,
        snap: &Snapshot,
        sphere: Option<crate::grass::trail::Sphere>,
        footprint: Option<([f32; 2], [f32; 2])>,
    ) -> Option<f32> {
        let grass = self.grass.as_mut()?;
        grass.set_model(&rs.device, &rs.queue, doc.grass.model);
        if let Some(c) = self.controls.cull {
            grass.set_cull(c);
        }
        grass.set_far(self.controls.far);
        // The wind colours on the map view's scale (its peak speed, at least 1 m/s).
        let scale = match self.wind_scale {
            Some((serial, fixed, scale)) if serial == snap.serial && fixed == self.speed_scale => {
                scale
            }
            _ => {
                let speed = super::view::WindView::Speed;
                let scale = super::view::field_scale(snap, speed, self.speed_scale);
                self.wind_scale = Some((snap.serial, self.speed_scale, scale));
                scale
            }
        };
        let colours = self.controls.wind_colours;
        grass.set_wind_colours(colours.then_some((self.controls.wind_opacity, scale)));
        grass.set_sphere(sphere);
        grass.set_trail_lifetime(self.controls.lifetime);
        // Obstacles and arrows: rebuilt when the trees or obstacles change, or the arrows are
        // switched on or off.
        let arrows = self.controls.arrows;
        let scene_key = (
            doc.trees.clone(),
            doc.obstacles.clone(),
            doc.probes.clone(),
            arrows,
        );
        if self.scene_for.as_ref() != Some(&scene_key) {
            grass.set_layout_scene(&rs.device, doc, arrows);
            self.scene_for = Some(scene_key);
        }
        if self.footprint_for != footprint {
            let lines =
                footprint.map_or_else(Vec::new, |(a, b)| crate::grass::scene::footprint(a, b));
            grass.set_footprint(&rs.device, &lines);
            self.footprint_for = footprint;
        }
        if snap.field.is_none()
            && snap.serial != self.wind_serial
            && snap.nx > 0
            && snap.velocity.len() == snap.nx * snap.ny
        {
            let cell = [snap.size[0] / snap.nx as f32, snap.size[1] / snap.ny as f32];
            grass.set_wind(
                &rs.device,
                &rs.queue,
                (snap.nx, snap.ny),
                snap.origin,
                cell,
                &snap.velocity,
            );
            self.wind_serial = snap.serial;
        }
        Some(scale)
    }

    /// The texture the view draws into, at the pane's size in pixels (made anew, and
    /// registered with egui, when the size changes). The size, or `None` without one.
    fn size_target(
        &mut self,
        ui: &egui::Ui,
        rs: &egui_wgpu::RenderState,
        rect: egui::Rect,
    ) -> Option<[u32; 2]> {
        use crate::gpu::grass::Target;
        let ppp = ui.ctx().pixels_per_point();
        let size = [
            (rect.width() * ppp).round().max(1.0) as u32,
            (rect.height() * ppp).round().max(1.0) as u32,
        ];
        if self.target.as_ref().is_none_or(|(t, _)| t.size != size) {
            let t = Target::new(
                &rs.device,
                size,
                rs.adapter.get_downlevel_capabilities().flags,
            );
            let mut renderer = rs.renderer.write();
            let id = match self.target.take() {
                Some((_, id)) => {
                    renderer.update_egui_texture_from_wgpu_texture(
                        &rs.device,
                        &t.encoded_view,
                        wgpu::FilterMode::Linear,
                        id,
                    );
                    id
                }
                None => renderer.register_native_texture(
                    &rs.device,
                    &t.encoded_view,
                    wgpu::FilterMode::Linear,
                ),
            };
            self.target = Some((t, id));
        }
        self.target.as_ref().map(|_| size)
    }

    /// Records and submits the frame: a GPU-run field read where it lives, the software
    /// sample following a resting camera, the grass drawn into the target; its GPU time
    /// lands in [`Self::frame_ms`] when the work is done.
    fn draw(
        &mut self,
        ui: &egui::Ui,
        rs: &egui_wgpu::RenderState,
        snap: &Snapshot,
        camera: &crate::gpu::grass::Camera,
        aspect: f32,
    ) {
        let (Some(grass), Some((target, _))) = (&mut self.grass, &self.target) else {
            return;
        };
        let mut enc = rs
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("grass view"),
            });
        if let Some(field) = &snap.field {
            // The GPU runs the field: the grass reads it there, every frame.
            grass.wind_from_field(&rs.device, &rs.queue, &mut enc, field);
            self.wind_serial = u64::MAX;
        }
        // The software adapter's sample follows the camera once it rests.
        if let Some(sample) = &mut self.sample {
            let now = ui.input(|i| i.time);
            let seen = (camera.eye, camera.target, aspect);
            if seen != sample.seen {
                sample.seen = seen;
                sample.moved_at = now;
            }
            if seen != sample.for_camera && now - sample.moved_at >= RESAMPLE_AFTER {
                let blades = sample.choose(camera, aspect);
                grass.replace_blades(&rs.queue, &mut enc, &blades);
                grass.set_sample_reach(sample.threshold);
            }
        }
        let dt = ui.input(|i| i.stable_dt);
        grass.record(&rs.queue, &mut enc, target, camera, snap.time, dt);
        let started = std::time::Instant::now();
        rs.queue.submit([enc.finish()]);
        self.stats = grass.poll_cull_stats().or(self.stats);
        let slot = self.frame_ms.clone();
        rs.queue.on_submitted_work_done(move || {
            if let Ok(mut ms) = slot.lock() {
                *ms = started.elapsed().as_secs_f32() * 1e3;
            }
        });
    }

    /// Frames only while the picture can change: Bezier blades settling after a change, a
    /// trail fading, the counters on their way back, the software sample due to follow a
    /// resting camera. A paused, untouched view draws nothing (new wind, input and edits
    /// wake it).
    #[expect(
        clippy::too_many_arguments,
        reason = "what the frame showed, each its own argument, compared with the last"
    )]
    fn schedule(
        &mut self,
        ui: &egui::Ui,
        doc: &crate::doc::Layout,
        snap: &Snapshot,
        camera: &crate::gpu::grass::Camera,
        size: [u32; 2],
        beside: Option<MapBeside>,
        sphere: bool,
    ) {
        let Some(grass) = &self.grass else { return };
        let now = ui.input(|i| i.time);
        let shown = Shown {
            wind: snap.serial,
            eye: camera.eye,
            target: camera.target,
            size,
            controls: self.controls,
            model: doc.grass.model,
            speed_scale: self.speed_scale,
            beside,
            sphere,
        };
        if self.shown.as_ref() != Some(&shown) {
            self.shown = Some(shown);
            self.changed_at = now;
            self.stats_due = grass.cull_stats_reads() + 2;
        }
        let settling = doc.grass.model == crate::doc::GrassModel::BezierPhysics
            && now - self.changed_at < BEZIER_SETTLE;
        if settling || sphere || grass.trail_active() {
            ui.ctx().request_repaint();
        } else if grass.cull_stats_reads() < self.stats_due {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(30));
        }
        if let Some(sample) = &self.sample {
            let (eye, target, aspect) = sample.seen;
            if (eye, target, aspect) != sample.for_camera {
                let wait = (sample.moved_at + RESAMPLE_AFTER - now).max(0.0);
                ui.ctx()
                    .request_repaint_after(std::time::Duration::from_secs_f64(wait));
            }
        }
    }

    /// The picture, and over it: the hint, the legend (with wind colours), the cull
    /// counters, the map's pointer on the ground and the sphere.
    fn overlays(
        &mut self,
        ui: &egui::Ui,
        rect: egui::Rect,
        camera: &crate::gpu::grass::Camera,
        scale: f32,
        mark: Option<[f32; 2]>,
        sphere: Option<crate::grass::trail::Sphere>,
    ) {
        let Some((_, id)) = &self.target else { return };
        ui.painter().image(
            *id,
            rect,
            egui::Rect::from_min_max(egui::Pos2::ZERO, egui::pos2(1.0, 1.0)),
            egui::Color32::WHITE,
        );
        let hint = if self.controls.push {
            "Drag to push the grass (Ctrl+drag or arrow keys orbit), right-drag to pan, wheel to zoom"
        } else {
            "Drag or arrow keys to orbit, right-drag to pan, wheel or +/- to zoom, double-click to frame all"
        };
        let hint = on_plate(
            ui.painter(),
            rect.left_top() + egui::vec2(10.0, 10.0),
            egui::Align2::LEFT_TOP,
            hint.to_owned(),
            egui::Color32::from_black_alpha(170),
            rect.width() - 20.0,
        );
        if self.controls.wind_colours {
            // The map view's legend, under the hint.
            let below = egui::Rect::from_min_max(egui::pos2(rect.left(), hint.bottom()), rect.max);
            super::view::draw_legend(ui.painter(), below, super::view::WindView::Speed, scale);
        }
        if let Some(stats) = &self.stats {
            self.counters_rect = Some(on_plate(
                ui.painter(),
                rect.left_bottom() + egui::vec2(10.0, -8.0),
                egui::Align2::LEFT_BOTTOM,
                super::grass_controls::counters(stats, self.total_blades),
                egui::Color32::from_black_alpha(190),
                rect.width() - 20.0,
            ));
        }
        // The map's pointer, on the ground (in front of the camera only).
        self.mark = mark.and_then(|[x, z]| {
            let p = glam::Vec3::new(x, 0.0, z);
            let behind = (p - camera.eye).dot(camera.target - camera.eye) <= 0.0;
            let at = on_screen(camera, rect, p);
            (!behind && rect.contains(at)).then_some(at)
        });
        if let Some(at) = self.mark {
            super::view::draw_pointer_mark(ui.painter(), at);
        }
        // The sphere, drawn over the picture where it is.
        if let Some(s) = sphere {
            let c = glam::Vec3::from(s.centre);
            let to_screen = |p: glam::Vec3| on_screen(camera, rect, p);
            let (sy, cy) = orbit_side(camera);
            let centre = to_screen(c);
            let edge = to_screen(c + glam::Vec3::new(sy, 0.0, cy) * s.radius);
            let r = centre.distance(edge);
            ui.painter().circle(
                centre,
                r,
                egui::Color32::from_rgba_unmultiplied(235, 225, 210, 45),
                egui::Stroke::new(1.5, egui::Color32::from_rgb(90, 70, 50)),
            );
        }
    }
}
