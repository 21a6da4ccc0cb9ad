//! The map view: drawing the world, the wind and the layout, and turning pointer gestures
//! into edit commands.

use super::view::{self, Camera, WindView};
use super::{EditorApp, Sel, Tool};
use crate::doc::{self, Edit, Node, Shape};
use eframe::egui::{self, Color32, Pos2, Rect, Sense, Stroke, Vec2};

/// A pointer gesture in progress on the map.
#[derive(Debug, Clone)]
pub enum Gesture {
    /// Moving the selected nodes/obstacles; `last` is the previous pointer world position.
    Move { last: doc::Vec2, key: u64 },
    /// Dragging a new arrow out of `parent`.
    Arrow { parent: u32 },
    /// Box selection from `start` (screen).
    Box { start: Pos2, additive: bool },
    /// A new circle from its centre.
    Circle { center: doc::Vec2 },
    /// A polygon's corner dragged (an inserted one too).
    Corner {
        obstacle: u32,
        index: usize,
        key: u64,
    },
    /// A circle's radius handle dragged.
    Radius { obstacle: u32, key: u64 },
    /// The selection turned (`rotate`) or scaled about `pivot` by its handle, dragged from
    /// `from`, computed from the layout as it was.
    Transform {
        rotate: bool,
        pivot: doc::Vec2,
        from: doc::Vec2,
        original: Box<doc::Layout>,
        items: Vec<doc::Item>,
        key: u64,
    },
    /// The selected backdrop scaled by a corner: the opposite corner stays at `anchor`; the
    /// dragged one moves along the `diagonal` it had (its aspect kept) or, Shift held, to
    /// the pointer.
    Backdrop {
        anchor: doc::Vec2,
        diagonal: doc::Vec2,
        key: u64,
    },
    /// A stroke being drawn: the path so far (world), and the point it continues, if any.
    Stroke {
        from: Option<u32>,
        path: Vec<doc::Vec2>,
    },
}

/// The map view's state: what it shows and where, the gesture in progress, its textures,
/// and what it last read under the pointer.
pub struct MapState {
    pub camera: Option<Camera>,
    /// The map's screen rectangle in the last frame.
    pub rect: Rect,
    pub(super) gesture: Option<Gesture>,
    /// The corners of a polygon being drawn.
    pub(super) polygon: Vec<doc::Vec2>,
    pub(super) streaks: view::Streaks,
    /// The wind drawn on the CPU, and the view, snapshot and scale it was drawn for.
    pub(super) field_texture: Option<(super::ScaleKey, egui::TextureHandle, f32)>,
    /// The backdrop's file and its texture (`None`: it could not be read).
    pub(super) backdrop: Option<(std::path::PathBuf, Option<egui::TextureHandle>)>,
    /// The terrain's relief ([`crate::sim::terrain::relief`]) for the terrain and the
    /// contours switch it was drawn for.
    pub(super) relief: Option<(Option<crate::doc::Terrain>, [bool; 2], egui::TextureHandle)>,
    /// The world point under the pointer.
    pub cursor_world: Option<doc::Vec2>,
    /// The top of the map's colour scale as its legend last read (0: no legend).
    pub legend_scale: f32,
    /// The window's size and the central view when the pane last changed size: only their
    /// change scales the map; a panel coming or going beside it moves no point on screen.
    pub(super) window: Vec2,
    pub(super) central: super::Central,
    /// Frames drawn since the camera was made: while the window's panels settle (their first
    /// frames), the pane's changes refit the view as a window's resize does.
    pub(super) camera_age: u32,
    /// A press that closed a menu or a popup: it and its drag do nothing on the map (a click
    /// outside an open menu only closes it, as everywhere on the desktop).
    pub swallowed: bool,
    /// What the open right-click menu is about.
    pub(super) context: Option<super::context_menu::Target>,
    /// Where the next paste lands (the right-click menu's Paste here).
    pub paste_at: Option<doc::Vec2>,
}

impl MapState {
    /// The backdrop picture's size in pixels, once read.
    pub fn backdrop_size(&self) -> Option<[f32; 2]> {
        match &self.backdrop {
            Some((_, Some(t))) => Some(t.size_vec2().into()),
            _ => None,
        }
    }
}

impl Default for MapState {
    fn default() -> Self {
        Self {
            camera: None,
            rect: Rect::NOTHING,
            gesture: None,
            polygon: Vec::new(),
            streaks: view::Streaks::new(),
            field_texture: None,
            backdrop: None,
            relief: None,
            cursor_world: None,
            legend_scale: 0.0,
            window: Vec2::ZERO,
            central: super::Central::Map,
            camera_age: 0,
            context: None,
            paste_at: None,
            swallowed: false,
        }
    }
}

/// The frames a new view takes to settle: the panels around the map find their sizes.
const SETTLING_FRAMES: u32 = 4;

/// Hit radius for points, in screen points.
pub(super) const HIT: f32 = 10.0;

pub fn map_view(app: &mut EditorApp, ui: &mut egui::Ui) {
    let sense = if app.map.swallowed {
        Sense::hover()
    } else {
        Sense::click_and_drag()
    };
    let (rect, response) = ui.allocate_exact_size(ui.available_size(), sense);
    let before = std::mem::replace(&mut app.map.rect, rect);
    let window = ui.ctx().content_rect().size();
    let settling = app.map.camera_age < SETTLING_FRAMES;
    app.map.camera_age = app.map.camera_age.saturating_add(1);
    let resized = std::mem::replace(&mut app.map.window, window) != window
        || std::mem::replace(&mut app.map.central, app.settings.central) != app.settings.central
        || settling;
    if let Some(cam) = &mut app.map.camera
        && before != rect
        && before.width() > 0.0
        && before.height() > 0.0
    {
        if resized && before.size() != rect.size() {
            // The window resized, or the 3D view put beside the map: the pane keeps showing
            // what it showed.
            cam.refit(&app.doc, before, rect);
        } else {
            // A panel came or went beside the map (the probes, a wrapped toolbar): every
            // world point stays where it was on screen, at the same scale.
            let d = rect.center() - before.center();
            cam.center[0] += d.x / cam.zoom;
            cam.center[1] += d.y / cam.zoom;
        }
    }
    if app.map.camera.is_none() {
        app.map.camera_age = 0;
    }
    let cam = *app
        .map
        .camera
        .get_or_insert_with(|| Camera::frame_all(&app.doc, rect));
    let ctx = ui.ctx().clone();
    let painter = ui.painter_at(rect);

    navigate(&mut app.map, ui, &response, rect);
    let cam = app.map.camera.unwrap_or(cam);
    let hover = response.hover_pos();
    app.map.cursor_world = hover.map(|p| cam.to_world(rect, p));

    // Background: the world rectangle, the backdrop, the wind, the grid.
    let (min, max) = app.doc.bounds();
    let world = Rect::from_min_max(cam.to_screen(rect, min), cam.to_screen(rect, max));
    painter.rect_filled(world, 0.0, Color32::from_rgb(38, 52, 34));
    draw_backdrop(app, &ctx, &painter, &cam, rect);
    let snap = app.live.snapshot();
    let max_speed = draw_wind(app, &ctx, &painter, &cam, rect, world, &snap);
    // Over the wind's colours, so the ground reads through them; a little hides the streaks.
    draw_relief(app, &ctx, &painter, &cam, rect);
    app.map.legend_scale = max_speed;
    if app.settings.show_grid {
        draw_grid(&painter, &cam, rect, min, max);
    }
    painter.rect_stroke(
        world,
        0.0,
        Stroke::new(1.0, Color32::from_white_alpha(60)),
        egui::StrokeKind::Outside,
    );

    // The layout.
    let selection = app.selection.clone();
    let is_sel = |id: u32| {
        selection
            .iter()
            .any(|s| matches!(*s, Sel::Node(n) | Sel::Obstacle(n) if n == id))
    };
    view::draw_obstacles(&painter, &cam, rect, &app.doc, &is_sel);
    let hovered_node = hover.and_then(|p| view::hit_node(&app.doc, &cam, rect, p, HIT));
    for tree in app.doc.trees.iter().filter(|t| !t.hidden) {
        let tree_sel = selection.contains(&Sel::Tree(tree.id));
        view::draw_tree(
            &painter,
            &cam,
            rect,
            &tree.root,
            tree.enabled,
            &|id| tree_sel || is_sel(id),
            hovered_node,
        );
    }

    // A keyed tree (or branch) as its keys turn it now: its arrows, thin, where the wind is.
    for tree in app.doc.trees.iter().filter(|t| !t.hidden && t.is_keyed()) {
        let by_id: std::collections::HashMap<u32, doc::Vec2> =
            tree.root.iter().map(|n| (n.id, n.pos)).collect();
        for arrow in tree.keyed_arrows(snap.time) {
            let drawn = by_id.get(&arrow.child.id).copied();
            // Only arrows the keys moved; a still one is drawn as it is.
            if drawn.is_some_and(|p| (p[0] - arrow.b[0]).hypot(p[1] - arrow.b[1]) < 1e-3) {
                continue;
            }
            view::draw_arrow(
                &painter,
                cam.to_screen(rect, arrow.a),
                cam.to_screen(rect, arrow.b),
                2.0,
                Color32::from_rgba_unmultiplied(160, 220, 255, 150),
            );
        }
    }
    view::draw_probes(&painter, &cam, rect, &app.doc, &|id| {
        selection.contains(&Sel::Probe(id))
    });
    view::draw_ambient_gizmos(&painter, &cam, rect, &app.doc);
    // A selected polygon's corner right-clicked is deleted (the Select tool), not a menu:
    // looked at before the tool deletes it.
    let on_corner = response.secondary_clicked()
        && app.tool == Tool::Select
        && response.interact_pointer_pos().is_some_and(|p| {
            matches!(
                super::handles::hit(&super::handles::handles(app, &cam, rect), p),
                Some(super::handles::Handle::Corner { .. })
            )
        });
    interact(app, &ctx, &response, rect, &cam, &painter);
    if app.tool == Tool::Select {
        super::handles::draw(app, &painter, &cam, rect);
    }
    context_menu(app, &ctx, &response, rect, &cam, on_corner);
    draw_scale_bar(&painter, &cam, rect);
    view::draw_legend(&painter, rect, app.settings.wind_view, max_speed);
    // Beside the 3D view: where its pointer is on the ground (last frame's).
    if app.settings.central == super::Central::Split
        && let Some(p) = app.grass_view.hover_ground
    {
        view::draw_pointer_mark(&painter, cam.to_screen(rect, p));
    }

    // Hint for the current tool, wrapped to the map's width (narrow beside the 3D view).
    let hint = match app.tool {
        Tool::Paint => {
            let on = match super::paint::target(app) {
                Some(super::paint::Target::Mask(_)) => "the selected mask solid",
                Some(super::paint::Target::Density) => "grass on the density map",
                None => "a selected mask obstacle, or the density map (Edit menu, New…)",
            };
            format!(
                "{} — paints {on}; Shift erases; [ and ] size the brush",
                app.settings.brush.mark.hint()
            )
        }
        t => t.hint().to_owned(),
    };
    let hint = painter.layout(
        hint,
        egui::FontId::proportional(13.0),
        Color32::from_white_alpha(170),
        (rect.width() - 20.0).max(40.0),
    );
    let at = rect.left_bottom() + Vec2::new(10.0, -10.0 - hint.size().y);
    painter.galley(at, hint, Color32::from_white_alpha(170));
}

/// Where the drag that starts this frame was pressed: the press itself, not where the
/// pointer was a frame ago (at a few frames a second that was metres short).
pub(super) fn drag_origin(ctx: &egui::Context, response: &egui::Response) -> Option<Pos2> {
    ctx.input(|i| i.pointer.press_origin()).or_else(|| {
        response
            .interact_pointer_pos()
            .map(|p| p - response.drag_delta())
    })
}

/// The right-click menu: on the item under the pointer, or on the map (a right-drag pans; a
/// polygon's corner right-clicked goes, as the Select tool says).
fn context_menu(
    app: &mut EditorApp,
    ctx: &egui::Context,
    response: &egui::Response,
    rect: Rect,
    cam: &Camera,
    on_corner: bool,
) {
    use super::context_menu::{Target, apply, entries};
    if response.secondary_clicked()
        && app.map.gesture.is_none()
        && let Some(p) = response.interact_pointer_pos()
    {
        app.map.context = (!on_corner).then(|| {
            let hit = view::hit_probe(&app.doc, cam, rect, p, HIT)
                .map(Sel::Probe)
                .or_else(|| view::hit_node(&app.doc, cam, rect, p, HIT).map(Sel::Node))
                .or_else(|| view::hit_obstacle(&app.doc, cam, rect, p).map(Sel::Obstacle));
            match hit {
                Some(s) => Target::Item(s),
                None if super::handles::on_backdrop(app, cam.to_world(rect, p)) => {
                    Target::Item(Sel::Backdrop)
                }
                None => Target::Map(app.snap(cam.to_world(rect, p))),
            }
        });
    }
    let Some(target) = app.map.context else {
        return;
    };
    // What was right-clicked is selected at once, as everywhere on the desktop (with the
    // rest of the selection when it was part of it).
    if response.secondary_clicked()
        && let Target::Item(s) = target
        && !app.selection.contains(&s)
    {
        app.selection = vec![s];
    }
    let mut chosen = None;
    let shown = response.context_menu(|ui| chosen = entries(app, ui, target));
    if let Some(action) = chosen {
        apply(app, ctx, target, action);
    }
    if shown.is_none() {
        app.map.context = None;
    }
}

/// A scale bar in the map's bottom-right corner: a round length (1, 2 or 5 times a power of
/// ten metres) between 60 and 150 points long, and what it is.
fn draw_scale_bar(painter: &egui::Painter, cam: &Camera, rect: Rect) {
    let metres = scale_bar_metres(cam.zoom);
    let len = metres * cam.zoom;
    let right = rect.right_bottom() + Vec2::new(-16.0, -14.0);
    let left = right - Vec2::new(len, 0.0);
    let ink = Stroke::new(2.0, Color32::from_white_alpha(200));
    let shadow = Stroke::new(4.0, Color32::from_black_alpha(120));
    for s in [shadow, ink] {
        painter.line_segment([left, right], s);
        for x in [left, right] {
            painter.line_segment([x - Vec2::new(0.0, 5.0), x], s);
        }
    }
    let label = if metres >= 1000.0 {
        format!("{:.0} km", metres / 1000.0)
    } else if metres >= 1.0 {
        format!("{metres:.0} m")
    } else {
        format!("{:.0} cm", metres * 100.0)
    };
    painter.text(
        Pos2::new((left.x + right.x) / 2.0, left.y - 6.0),
        egui::Align2::CENTER_BOTTOM,
        label,
        egui::FontId::proportional(12.0),
        Color32::from_white_alpha(220),
    );
}

/// The scale bar's length in metres at `zoom` points a metre: the round length (1, 2 or 5
/// times a power of ten) nearest 100 points, at least 60.
pub fn scale_bar_metres(zoom: f32) -> f32 {
    for power in -2..=7 {
        for m in [1.0, 2.0, 5.0] {
            let metres = m * 10f32.powi(power);
            if metres * zoom >= 60.0 {
                return metres;
            }
        }
    }
    1.0e8
}

fn navigate(map: &mut MapState, ui: &egui::Ui, response: &egui::Response, rect: Rect) {
    let Some(cam) = map.camera.as_mut() else {
        return;
    };
    // Pan with the middle or right button.
    if response.dragged_by(egui::PointerButton::Middle)
        || response.dragged_by(egui::PointerButton::Secondary)
    {
        cam.pan_pixels(response.drag_delta());
    }
    // Zoom about the cursor with the wheel.
    if let Some(p) = response.hover_pos() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y + i.zoom_delta().ln() * 200.0);
        if scroll != 0.0 {
            cam.zoom_about(rect, p, (scroll / 300.0).exp());
        }
    }
}

fn draw_backdrop(
    app: &mut EditorApp,
    ctx: &egui::Context,
    painter: &egui::Painter,
    cam: &Camera,
    rect: Rect,
) {
    let Some(map) = app.doc.world.map.clone() else {
        app.map.backdrop = None;
        return;
    };
    let base = crate::io::layout_base(app.doc.path());
    let file = crate::io::layout_file(&base, &map.image);
    let stale = app.map.backdrop.as_ref().is_none_or(|(p, _)| p != &file);
    if stale {
        let texture = match crate::io::load_backdrop(&base, &map) {
            Ok(img) => {
                let size = [img.width() as usize, img.height() as usize];
                let ci = egui::ColorImage::from_rgba_unmultiplied(size, img.as_raw());
                Some(ctx.load_texture("backdrop", ci, egui::TextureOptions::LINEAR))
            }
            Err(e) => {
                log::warn!("{e}");
                app.say(ctx, format!("{e} (shown without it)"));
                None
            }
        };
        app.map.backdrop = Some((file, texture));
    }
    if let Some((_, Some(t))) = &app.map.backdrop {
        // Where the layout places it (the world rectangle unless it says otherwise).
        let [a, b] = map.placed(app.doc.bounds());
        painter.image(
            t.id(),
            Rect::from_two_pos(cam.to_screen(rect, a), cam.to_screen(rect, b)),
            Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)),
            Color32::from_white_alpha((map.opacity * 255.0) as u8),
        );
    }
}

/// The terrain's hill shade and contour lines over the world rectangle, under the wind.
fn draw_relief(
    app: &mut EditorApp,
    ctx: &egui::Context,
    painter: &egui::Painter,
    cam: &Camera,
    rect: Rect,
) {
    let terrain = app.doc.world.terrain.clone();
    let on = app.settings.hill_shade || app.settings.contours;
    if terrain.is_none() || !on {
        app.map.relief = None;
        return;
    }
    let flags = [app.settings.hill_shade, app.settings.contours];
    let stale = app.map.relief.as_ref().is_none_or(|(t, f, _)| {
        *t != terrain
            || *f != flags
            // A heightmap read since (equal layouts compare their pixels as equal).
            || t.as_ref().map(|t| t.pixels.image().is_some())
                != terrain.as_ref().map(|t| t.pixels.image().is_some())
    });
    if stale {
        // 1024 px along the world's longer side: thin contour lines over a zoomed map.
        let size = app.doc.world.size;
        let k = 1024.0 / size[0].max(size[1]);
        let (w, h) = (
            ((size[0] * k) as usize).clamp(16, 1024),
            ((size[1] * k) as usize).clamp(16, 1024),
        );
        let Some(rgba) = crate::sim::terrain::relief(&app.doc, (w, h), flags[0], flags[1]) else {
            return;
        };
        let img = egui::ColorImage::from_rgba_unmultiplied([w, h], &rgba);
        let tex = ctx.load_texture("terrain relief", img, egui::TextureOptions::LINEAR);
        app.map.relief = Some((terrain, flags, tex));
    }
    if let Some((_, _, tex)) = &app.map.relief {
        let (min, max) = app.doc.bounds();
        painter.image(
            tex.id(),
            Rect::from_two_pos(cam.to_screen(rect, min), cam.to_screen(rect, max)),
            Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)),
            Color32::WHITE,
        );
    }
}

/// Draws the chosen wind visualisation; returns the speed at the top of the colour scale.
fn draw_wind(
    app: &mut EditorApp,
    ctx: &egui::Context,
    painter: &egui::Painter,
    cam: &Camera,
    rect: Rect,
    world: Rect,
    snap: &crate::engine::live::Snapshot,
) -> f32 {
    let mode = app.settings.wind_view;
    if mode == WindView::Off || snap.nx == 0 {
        return 0.0;
    }
    if app.gpu.map_on_gpu {
        // On the GPU the field is drawn where it lives; a CPU-run one is copied there first
        // (three arrays a snapshot, against tessellating thousands of streak segments).
        let field = match (&snap.field, &app.gpu.render_state) {
            (Some(f), _) => Some(f.clone()),
            (None, Some(rs)) => app.gpu.uploaded.field(rs, snap),
            (None, None) => None,
        };
        if let Some(field) = field {
            return draw_wind_gpu(app, ctx, painter, cam, rect, snap, field);
        }
    }
    let fixed = app.settings.speed_scale;
    let key = (snap.serial, mode, fixed);
    let stale = app
        .map
        .field_texture
        .as_ref()
        .is_none_or(|(k, _, _)| *k != key);
    if stale && let Some((img, scale)) = view::field_image(snap, mode, fixed) {
        match &mut app.map.field_texture {
            Some((k, tex, s)) => {
                tex.set(img, egui::TextureOptions::LINEAR);
                *k = key;
                *s = scale;
            }
            None => {
                let tex = ctx.load_texture("wind", img, egui::TextureOptions::LINEAR);
                app.map.field_texture = Some((key, tex, scale));
            }
        }
    }
    let Some((_, tex, scale)) = &app.map.field_texture else {
        return 0.0;
    };
    let scale = *scale;
    // The designer's opacity over the view's own (the backdrop shows through the rest).
    let opacity =
        super::map_wind_opacity(app.settings.map_wind_opacity, app.doc.world.map.is_some());
    painter.image(
        tex.id(),
        world,
        Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)),
        Color32::from_white_alpha((opacity * 255.0).round() as u8),
    );
    match mode {
        WindView::Streaks => {
            if app.live.playing {
                let dt = ctx.input(|i| i.stable_dt).min(0.1) * app.live.speed;
                app.map
                    .streaks
                    .advance(&app.doc, snap, dt, app.settings.streak_count);
            }
            app.map.streaks.draw(painter, cam, rect, snap, scale);
        }
        WindView::Glyphs => view::draw_glyphs(painter, cam, rect, &app.doc, snap, scale),
        _ => {}
    }
    scale
}

/// The wind drawn on the GPU from the live solver's buffers (see `gpu_view`); the legend's
/// scale comes from the last read-back.
fn draw_wind_gpu(
    app: &mut EditorApp,
    ctx: &egui::Context,
    painter: &egui::Painter,
    cam: &Camera,
    rect: Rect,
    snap: &crate::engine::live::Snapshot,
    field: crate::gpu::mapview::FieldBuffers,
) -> f32 {
    use crate::gpu::mapview::{Frame, Layer, Overlay};
    let mode = app.settings.wind_view;
    let key = (snap.serial, mode, app.settings.speed_scale);
    let scale = match app.gpu.scale {
        Some((k, scale)) if k == key => scale,
        _ => {
            let scale = view::field_scale(snap, mode, app.settings.speed_scale);
            app.gpu.scale = Some((key, scale));
            scale
        }
    };
    let (min, max) = app.doc.bounds();
    // The glyph lattice: every 26 points on screen over the visible part of the world, as the
    // CPU view places it.
    let spacing = 26.0;
    let a = cam.to_screen(rect, min).max(rect.min);
    let b = cam.to_screen(rect, max).min(rect.max);
    let count = |from: f32, to: f32| ((to - from - spacing * 0.5) / spacing).ceil().max(0.0) as u32;
    let first = a + Vec2::splat(spacing * 0.5);
    let ppp = ctx.pixels_per_point();
    let frame = Frame {
        layer: match mode {
            WindView::Curl => Layer::Curl,
            WindView::Pressure => Layer::Pressure,
            _ => Layer::Speed,
        },
        overlay: match mode {
            WindView::Streaks => Overlay::Streaks,
            WindView::Glyphs => Overlay::Glyphs,
            _ => Overlay::None,
        },
        alpha: super::map_wind_opacity(app.settings.map_wind_opacity, app.doc.world.map.is_some())
            * if mode == WindView::Speed {
                230.0 / 255.0
            } else {
                120.0 / 255.0
            },
        center: cam.center,
        zoom: cam.zoom,
        ppp,
        viewport_px: [rect.width() * ppp, rect.height() * ppp],
        world_min: min,
        world_max: max,
        dt: if app.live.playing {
            ctx.input(|i| i.stable_dt).min(0.1) * app.live.speed
        } else {
            0.0
        },
        streaks: app.settings.streak_count as u32,
        lattice_origin: cam.to_world(rect, first),
        lattice_step: spacing / cam.zoom,
        lattice: [count(a.x, b.x), count(a.y, b.y)],
        speed_scale: app.settings.speed_scale,
    };
    painter.add(super::gpu_view::map_wind(rect, field, frame));
    scale
}

fn draw_grid(painter: &egui::Painter, cam: &Camera, rect: Rect, min: doc::Vec2, max: doc::Vec2) {
    // The smallest 1-2-5 spacing that keeps lines at least 40 px apart.
    let mut decade = 0.1f32;
    let step = 'found: loop {
        for m in [1.0, 2.0, 5.0] {
            if decade * m * cam.zoom >= 40.0 {
                break 'found decade * m;
            }
        }
        decade *= 10.0;
    };
    let stroke = Stroke::new(1.0, Color32::from_white_alpha(16));
    let mut x = (min[0] / step).ceil() * step;
    while x <= max[0] {
        painter.line_segment(
            [
                cam.to_screen(rect, [x, min[1]]),
                cam.to_screen(rect, [x, max[1]]),
            ],
            stroke,
        );
        x += step;
    }
    let mut z = (min[1] / step).ceil() * step;
    while z <= max[1] {
        painter.line_segment(
            [
                cam.to_screen(rect, [min[0], z]),
                cam.to_screen(rect, [max[0], z]),
            ],
            stroke,
        );
        z += step;
    }
}

/// Pointer handling for the current tool.
fn interact(
    app: &mut EditorApp,
    ctx: &egui::Context,
    response: &egui::Response,
    rect: Rect,
    cam: &Camera,
    painter: &egui::Painter,
) {
    let pointer = response.interact_pointer_pos().or(response.hover_pos());
    let shift = ctx.input(|i| i.modifiers.shift);

    match app.tool {
        Tool::Select => select_tool(app, ctx, response, rect, cam, painter, shift),
        Tool::Stroke => super::stroke::tool(app, ctx, response, rect, cam, painter),
        Tool::Probe => {
            if response.clicked_by(egui::PointerButton::Primary)
                && let Some(p) = pointer
            {
                let at = app.snap(cam.to_world(rect, p));
                app.add_probe(ctx, at);
            }
        }
        Tool::Paint => {
            if super::paint::target(app) == Some(super::paint::Target::Density) {
                super::paint::draw_density(app, painter, cam, rect);
            }
            super::paint::tool(app, ctx, response, rect, cam, painter);
        }
        Tool::AddRoot => {
            if response.clicked_by(egui::PointerButton::Primary)
                && let Some(p) = pointer
            {
                let pos = app.snap(cam.to_world(rect, p));
                if app.add_root(ctx, pos) {
                    // Next: drag arrows out of it.
                    app.tool = Tool::AddArrow;
                }
            }
        }
        Tool::AddArrow => {
            if response.drag_started_by(egui::PointerButton::Primary) {
                let start = drag_origin(ctx, response);
                let parent = start
                    .and_then(|p| view::hit_node(&app.doc, cam, rect, p, HIT))
                    .or_else(|| match app.selection.as_slice() {
                        [Sel::Node(id)] if start.is_none() => Some(*id),
                        _ => None,
                    });
                if let Some(parent) = parent {
                    app.map.gesture = Some(Gesture::Arrow { parent });
                }
            }
            if let Some(super::map::Gesture::Arrow { parent }) = app.map.gesture.clone() {
                let from = app
                    .doc
                    .trees
                    .iter()
                    .find_map(|t| t.root.find(parent))
                    .map(|n| (n.pos, n.strength, n.radius));
                if let (Some((from, strength, radius)), Some(p)) = (from, pointer) {
                    let to = app.snap(cam.to_world(rect, p));
                    let a = cam.to_screen(rect, from);
                    let b = cam.to_screen(rect, to);
                    view::draw_arrow(
                        painter,
                        a,
                        b,
                        view::arrow_width(strength),
                        view::ARROW_COLOUR.gamma_multiply(0.7),
                    );
                    if response.drag_stopped() {
                        app.map.gesture = None;
                        if a.distance(b) > 6.0 {
                            let id = app.doc.next_id();
                            let node = Node::new(id, to, strength.max(1.0), radius);
                            if app.edit(
                                ctx,
                                Edit::AddNode {
                                    parent,
                                    index: usize::MAX,
                                    node,
                                },
                            ) {
                                app.selection = vec![Sel::Node(id)];
                            }
                        }
                    }
                } else if response.drag_stopped() {
                    app.map.gesture = None;
                }
            }
        }
        Tool::Circle => {
            if response.drag_started_by(egui::PointerButton::Primary)
                && let Some(start) = drag_origin(ctx, response)
            {
                app.map.gesture = Some(Gesture::Circle {
                    center: app.snap(cam.to_world(rect, start)),
                });
            }
            if let (Some(Gesture::Circle { center }), Some(p)) = (app.map.gesture.clone(), pointer)
            {
                let w = cam.to_world(rect, p);
                let r = (w[0] - center[0]).hypot(w[1] - center[1]);
                painter.circle(
                    cam.to_screen(rect, center),
                    r * cam.zoom,
                    view::OBSTACLE_COLOUR.gamma_multiply(0.6),
                    Stroke::new(1.0, Color32::WHITE),
                );
                if response.drag_stopped() {
                    app.map.gesture = None;
                    if r * cam.zoom > 3.0 {
                        let id = app.doc.next_id();
                        let obstacle = doc::Obstacle {
                            id,
                            name: format!("Rock {}", app.doc.obstacles.len() + 1),
                            shape: Shape::Circle { center, radius: r },
                            locked: false,
                            hidden: false,
                        };
                        if app.edit(
                            ctx,
                            Edit::AddObstacle {
                                index: usize::MAX,
                                obstacle,
                            },
                        ) {
                            app.selection = vec![Sel::Obstacle(id)];
                        }
                    }
                }
            }
        }
        Tool::Polygon => {
            if let Some(p) = pointer {
                let w = app.snap(cam.to_world(rect, p));
                // Preview.
                let pts: Vec<Pos2> = app
                    .map
                    .polygon
                    .iter()
                    .map(|q| cam.to_screen(rect, *q))
                    .collect();
                if !pts.is_empty() {
                    let mut line = pts.clone();
                    line.push(cam.to_screen(rect, w));
                    painter.add(egui::Shape::line(line, Stroke::new(1.5, Color32::WHITE)));
                    painter.circle_stroke(pts[0], HIT * 0.8, Stroke::new(1.0, Color32::WHITE));
                }
                if response.clicked_by(egui::PointerButton::Primary) {
                    let closes = app.map.polygon.len() >= 3
                        && cam.to_screen(rect, app.map.polygon[0]).distance(p) <= HIT;
                    if closes {
                        close_polygon(app, ctx);
                    } else {
                        app.map.polygon.push(w);
                    }
                }
            }
            if ctx.input(|i| i.key_pressed(egui::Key::Enter)) && app.map.polygon.len() >= 3 {
                close_polygon(app, ctx);
            }
        }
    }
}

fn close_polygon(app: &mut EditorApp, ctx: &egui::Context) {
    let points = std::mem::take(&mut app.map.polygon);
    let id = app.doc.next_id();
    let obstacle = doc::Obstacle {
        id,
        name: format!("Wall {}", app.doc.obstacles.len() + 1),
        shape: Shape::Polygon { points },
        locked: false,
        hidden: false,
    };
    if app.edit(
        ctx,
        Edit::AddObstacle {
            index: usize::MAX,
            obstacle,
        },
    ) {
        app.selection = vec![Sel::Obstacle(id)];
    }
}

fn select_tool(
    app: &mut EditorApp,
    ctx: &egui::Context,
    response: &egui::Response,
    rect: Rect,
    cam: &Camera,
    painter: &egui::Painter,
    shift: bool,
) {
    let hit_at = |app: &EditorApp, p: Pos2| -> Option<Sel> {
        view::hit_probe(&app.doc, cam, rect, p, HIT)
            .map(Sel::Probe)
            .or_else(|| view::hit_node(&app.doc, cam, rect, p, HIT).map(Sel::Node))
            .or_else(|| view::hit_obstacle(&app.doc, cam, rect, p).map(Sel::Obstacle))
    };
    let handles = super::handles::handles(app, cam, rect);
    let alt = ctx.input(|i| i.modifiers.alt);
    // A corner right-clicked or Alt-clicked goes.
    let delete_click =
        response.secondary_clicked() || (alt && response.clicked_by(egui::PointerButton::Primary));
    if delete_click
        && let Some(p) = response.interact_pointer_pos()
        && let Some(super::handles::Handle::Corner { obstacle, index }) =
            super::handles::hit(&handles, p)
    {
        super::handles::delete_corner(app, ctx, obstacle, index);
        return;
    }
    if response.clicked_by(egui::PointerButton::Primary)
        && let Some(p) = response.interact_pointer_pos()
        && super::handles::hit(&handles, p).is_none()
    {
        match hit_at(app, p) {
            Some(s) if shift => {
                if let Some(k) = app.selection.iter().position(|x| *x == s) {
                    app.selection.remove(k);
                } else {
                    app.selection.push(s);
                }
            }
            Some(s) => app.selection = vec![s],
            None if !shift => app.selection.clear(),
            None => {}
        }
    }
    if response.drag_started_by(egui::PointerButton::Primary)
        && let Some(start) = drag_origin(ctx, response)
    {
        let key = super::gesture_key(("drag", ctx.input(|i| i.time).to_bits()));
        if let Some(h) = super::handles::hit(&handles, start) {
            super::handles::start(app, ctx, h, cam.to_world(rect, start), key);
        } else {
            let backdrop = super::handles::on_backdrop(app, cam.to_world(rect, start));
            match hit_at(app, start) {
                None if backdrop => {
                    // The selected backdrop, dragged where it lies: moved.
                    app.map.gesture = Some(Gesture::Move {
                        last: cam.to_world(rect, start),
                        key,
                    });
                }
                Some(s) => {
                    if !app.selection.contains(&s) {
                        if shift {
                            app.selection.push(s);
                        } else {
                            app.selection = vec![s];
                        }
                    }
                    app.map.gesture = Some(Gesture::Move {
                        last: cam.to_world(rect, start),
                        key,
                    });
                }
                None => {
                    app.map.gesture = Some(Gesture::Box {
                        start,
                        additive: shift,
                    })
                }
            }
        }
    }
    if matches!(
        app.map.gesture,
        Some(
            Gesture::Corner { .. }
                | Gesture::Radius { .. }
                | Gesture::Transform { .. }
                | Gesture::Backdrop { .. }
        )
    ) {
        // While the button is down: the release's frame has ended the gesture's undo step.
        if let Some(p) = response.interact_pointer_pos()
            && ctx.input(|i| i.pointer.primary_down())
        {
            super::handles::drag(app, ctx, cam.to_world(rect, p), shift);
        }
        if response.drag_stopped() {
            app.map.gesture = None;
            app.doc.end_gesture();
        }
    }
    match app.map.gesture.clone() {
        Some(Gesture::Move { last, key }) => {
            if let Some(p) = response.interact_pointer_pos() {
                let w = cam.to_world(rect, p);
                let d = [w[0] - last[0], w[1] - last[1]];
                if d != [0.0, 0.0] {
                    move_selection(app, ctx, d, key);
                    app.map.gesture = Some(Gesture::Move { last: w, key });
                }
            }
            if response.drag_stopped() {
                app.map.gesture = None;
                if app.settings.snap {
                    snap_selection(app, ctx, key);
                }
                app.doc.end_gesture();
            }
        }
        Some(Gesture::Box { start, additive }) => {
            if let Some(p) = response.interact_pointer_pos() {
                let r = Rect::from_two_pos(start, p);
                painter.rect(
                    r,
                    0.0,
                    Color32::from_rgba_unmultiplied(255, 200, 40, 25),
                    Stroke::new(1.0, view::SELECT_COLOUR),
                    egui::StrokeKind::Inside,
                );
                if response.drag_stopped() {
                    app.map.gesture = None;
                    if !additive {
                        app.selection.clear();
                    }
                    let picked: Vec<Sel> = (app.doc.trees.iter())
                        .filter(|t| t.pickable())
                        .flat_map(|t| t.root.iter())
                        .filter(|n| r.contains(cam.to_screen(rect, n.pos)))
                        .map(|n| Sel::Node(n.id))
                        .chain(
                            (app.doc.probes.iter())
                                .filter(|p| r.contains(cam.to_screen(rect, p.pos)))
                                .map(|p| Sel::Probe(p.id)),
                        )
                        .chain(
                            app.doc
                                .obstacles
                                .iter()
                                .filter(|o| o.pickable())
                                .filter(|o| {
                                    r.contains(
                                        cam.to_screen(rect, o.shape.centre(app.doc.bounds())),
                                    )
                                })
                                .map(|o| Sel::Obstacle(o.id)),
                        )
                        .collect();
                    for s in picked {
                        if !app.selection.contains(&s) {
                            app.selection.push(s);
                        }
                    }
                }
            }
        }
        _ => {}
    }
}

fn moved_obstacle(
    o: &doc::Obstacle,
    d: doc::Vec2,
    bounds: (doc::Vec2, doc::Vec2),
) -> doc::Obstacle {
    let mut o = o.clone();
    o.shape.translate(d, bounds);
    o
}

/// The edits that move every selected node (a selected tree: all its nodes) and obstacle by
/// `d` metres; locked and hidden items stay.
fn moves(app: &EditorApp, d: doc::Vec2) -> Vec<Edit> {
    let mut nodes: Vec<&Node> = Vec::new();
    let mut edits = Vec::new();
    for s in &app.selection {
        match *s {
            Sel::Node(id) => nodes.extend(
                (app.doc.trees.iter())
                    .filter(|t| t.pickable())
                    .find_map(|t| t.root.find(id)),
            ),
            Sel::Tree(id) => nodes.extend(
                (app.doc.trees.iter())
                    .filter(|t| t.id == id && t.pickable())
                    .flat_map(|t| t.root.iter()),
            ),
            Sel::Obstacle(id) => {
                if let Some(o) = app
                    .doc
                    .obstacles
                    .iter()
                    .find(|o| o.id == id && o.pickable())
                {
                    edits.push(Edit::SetObstacle {
                        obstacle: moved_obstacle(o, d, app.doc.bounds()),
                    });
                }
            }
            Sel::Ambient(_) => {}
            Sel::Backdrop => {
                let mut w = app.doc.world.clone();
                if let Some(m) = &mut w.map {
                    let [a, b] = m.placed(app.doc.bounds());
                    m.rect = Some([[a[0] + d[0], a[1] + d[1]], [b[0] + d[0], b[1] + d[1]]]);
                    edits.push(Edit::Named("Move backdrop", Box::new(Edit::SetWorld(w))));
                }
            }
            Sel::Probe(id) => {
                if let Some(p) = app.doc.probes.iter().find(|p| p.id == id) {
                    edits.push(Edit::SetProbe {
                        probe: doc::Probe {
                            pos: [p.pos[0] + d[0], p.pos[1] + d[1]],
                            ..p.clone()
                        },
                    });
                }
            }
        }
    }
    nodes.sort_by_key(|n| n.id);
    nodes.dedup_by_key(|n| n.id);
    let moved = nodes.iter().map(|n| Edit::MoveNode {
        id: n.id,
        pos: [n.pos[0] + d[0], n.pos[1] + d[1]],
    });
    moved.chain(edits).collect()
}

/// Moves every selected node and obstacle by `d` metres as part of gesture `key`.
fn move_selection(app: &mut EditorApp, ctx: &egui::Context, d: doc::Vec2, key: u64) {
    let edits = moves(app, d);
    if !edits.is_empty() {
        app.edit_merged(ctx, Edit::Batch(edits), key);
    }
}

/// Moves the selection by `d` metres as one undo step (the arrow keys); `false` when nothing
/// selected can move.
pub fn nudge_selection(app: &mut EditorApp, ctx: &egui::Context, d: doc::Vec2) -> bool {
    let edits = moves(app, d);
    !edits.is_empty() && app.edit(ctx, Edit::Batch(edits))
}

fn snap_selection(app: &mut EditorApp, ctx: &egui::Context, key: u64) {
    let mut edits = Vec::new();
    for s in &app.selection {
        if let Sel::Node(id) = *s
            && let Some(n) = app.doc.trees.iter().find_map(|t| t.root.find(id))
        {
            edits.push(Edit::MoveNode {
                id,
                pos: app.snap(n.pos),
            });
        }
    }
    if !edits.is_empty() {
        app.edit_merged(ctx, Edit::Batch(edits), key);
    }
}
