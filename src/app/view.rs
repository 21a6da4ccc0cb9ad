//! The map view: world ↔ screen transform (pan, zoom), drawing and hit-testing.

use crate::doc::{Layout, Node, Shape, Vec2 as W2};
use crate::engine::live::Snapshot;
use eframe::egui::{self, Color32, Pos2, Rect, Stroke, Vec2};

/// How the wind is shown on the map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum WindView {
    Speed,
    Glyphs,
    Streaks,
    Curl,
    Pressure,
    Off,
}

impl WindView {
    pub const ALL: [WindView; 6] = [
        WindView::Streaks,
        WindView::Speed,
        WindView::Glyphs,
        WindView::Curl,
        WindView::Pressure,
        WindView::Off,
    ];

    pub fn label(self) -> &'static str {
        match self {
            Self::Speed => "Speed colour map",
            Self::Glyphs => "Arrow glyphs",
            Self::Streaks => "Streaks",
            Self::Curl => "Curl",
            Self::Pressure => "Pressure",
            Self::Off => "Off",
        }
    }
}

/// The map's zoom range in pixels per metre: the largest world (100 km) fits in 100 pixels,
/// and a metre can fill a screen.
pub const ZOOM_MIN: f32 = 1e-3;
pub const ZOOM_MAX: f32 = 2000.0;

/// Pan and zoom of the map: screen = `center_screen + (world − center_world) × zoom`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Camera {
    /// World point shown at the centre of the view.
    pub center: [f32; 2],
    /// Pixels per metre.
    pub zoom: f32,
}

impl Camera {
    /// Frames the whole world in `rect` with a margin.
    pub fn frame_all(doc: &Layout, rect: Rect) -> Self {
        let (min, max) = doc.bounds();
        let size = doc.world.size;
        let zoom = (rect.width() / size[0]).min(rect.height() / size[1]) * 0.92;
        Self {
            center: [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0],
            zoom: zoom.clamp(ZOOM_MIN, ZOOM_MAX),
        }
    }

    /// The view that frames the world box `[lo, hi]` in `rect` (at least `least` metres of
    /// it a side: a lone point is seen with what is around it).
    pub fn frame_box(lo: W2, hi: W2, rect: Rect, least: f32) -> Self {
        let w = (hi[0] - lo[0]).max(least);
        let h = (hi[1] - lo[1]).max(least);
        let zoom = (rect.width() / w).min(rect.height() / h) * 0.8;
        Self {
            center: [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0],
            zoom: zoom.clamp(ZOOM_MIN, ZOOM_MAX),
        }
    }

    /// The same view in a pane resized from `before` to `after`: the zoom scales with the
    /// zoom that frames the whole world, so a framed world stays framed and a close-up stays as
    /// close relative to the pane; the centre stays.
    pub fn refit(&mut self, doc: &Layout, before: Rect, after: Rect) {
        let fit = |r: Rect| Self::frame_all(doc, r).zoom;
        self.zoom = (self.zoom * fit(after) / fit(before)).clamp(ZOOM_MIN, ZOOM_MAX);
    }

    pub fn to_screen(&self, rect: Rect, p: W2) -> Pos2 {
        rect.center()
            + Vec2::new(
                (p[0] - self.center[0]) * self.zoom,
                (p[1] - self.center[1]) * self.zoom,
            )
    }

    pub fn to_world(&self, rect: Rect, s: Pos2) -> W2 {
        let d = s - rect.center();
        [
            self.center[0] + d.x / self.zoom,
            self.center[1] + d.y / self.zoom,
        ]
    }

    /// Zooms by `factor` keeping the world point under `anchor` fixed.
    pub fn zoom_about(&mut self, rect: Rect, anchor: Pos2, factor: f32) {
        let before = self.to_world(rect, anchor);
        self.zoom = (self.zoom * factor).clamp(ZOOM_MIN, ZOOM_MAX);
        let after = self.to_world(rect, anchor);
        self.center[0] += before[0] - after[0];
        self.center[1] += before[1] - after[1];
    }

    pub fn pan_pixels(&mut self, delta: Vec2) {
        self.center[0] -= delta.x / self.zoom;
        self.center[1] -= delta.y / self.zoom;
    }
}

/// Colours of the editor's marks.
pub const ROOT_COLOUR: Color32 = Color32::from_rgb(235, 90, 60);
pub const END_COLOUR: Color32 = Color32::from_rgb(250, 250, 250);
pub const ARROW_COLOUR: Color32 = Color32::from_rgb(70, 160, 255);
pub const SELECT_COLOUR: Color32 = Color32::from_rgb(255, 200, 40);
pub const OBSTACLE_COLOUR: Color32 = Color32::from_rgb(128, 118, 106);

/// Arrow line width in points for a strength in m/s.
pub fn arrow_width(strength: f32) -> f32 {
    (1.5 + strength * 0.35).clamp(1.5, 9.0)
}

/// Colour for a speed relative to the view's maximum, from a perceptual colour map.
pub fn speed_colour(t: f32) -> Color32 {
    let [r, g, b] = crate::colour::speed_rgb(t);
    Color32::from_rgb(r, g, b)
}

/// Diverging colour for a signed value in [-1, 1].
pub fn signed_colour(t: f32) -> Color32 {
    let [r, g, b] = crate::colour::signed_rgb(t);
    Color32::from_rgb(r, g, b)
}

/// The value at the top of view `mode`'s colour scale: for the speed views `fixed` (the
/// View menu's fixed speed scale) or else the peak speed (at least 1 m/s); the peak
/// magnitude of curl or pressure.
pub fn field_scale(snap: &Snapshot, mode: WindView, fixed: Option<f32>) -> f32 {
    match mode {
        WindView::Curl => snap.curl.iter().fold(1e-6f32, |m, x| m.max(x.abs())),
        WindView::Pressure => snap.pressure.iter().fold(1e-6f32, |m, x| m.max(x.abs())),
        _ => fixed.unwrap_or_else(|| crate::colour::speed_scale(&snap.velocity)),
    }
}

/// The field as an image for the colour-map views (one pixel per cell), and the value that
/// maps to the top of the scale ([`field_scale`]).
pub fn field_image(
    snap: &Snapshot,
    mode: WindView,
    fixed: Option<f32>,
) -> Option<(egui::ColorImage, f32)> {
    if snap.nx == 0 || mode == WindView::Off {
        return None;
    }
    let scale = field_scale(snap, mode, fixed);
    let pixels: Vec<Color32> = match mode {
        WindView::Curl | WindView::Pressure => {
            let data = if mode == WindView::Curl {
                &snap.curl
            } else {
                &snap.pressure
            };
            data.iter().map(|x| signed_colour(x / scale)).collect()
        }
        _ => {
            let dim = if mode == WindView::Speed { 230 } else { 120 };
            snap.velocity
                .iter()
                .map(|v| speed_colour((v[0] * v[0] + v[1] * v[1]).sqrt() / scale))
                .map(|c| c.gamma_multiply(dim as f32 / 255.0))
                .map(|c| Color32::from_rgba_unmultiplied(c.r(), c.g(), c.b(), dim))
                .collect()
        }
    };
    Some((egui::ColorImage::new([snap.nx, snap.ny], pixels), scale))
}

/// Draws an arrow tree: arrows (width by strength), end points and the root.
pub fn draw_tree(
    painter: &egui::Painter,
    cam: &Camera,
    rect: Rect,
    root: &Node,
    enabled: bool,
    is_selected: &dyn Fn(u32) -> bool,
    hovered: Option<u32>,
) {
    let alpha = if enabled { 255 } else { 90 };
    let arrow = ARROW_COLOUR.gamma_multiply(alpha as f32 / 255.0);
    for (parent, child, _) in root.arrows() {
        let a = cam.to_screen(rect, parent.pos);
        let b = cam.to_screen(rect, child.pos);
        let w = arrow_width(child.strength);
        draw_arrow(painter, a, b, w, arrow);
    }
    for n in root.iter() {
        let p = cam.to_screen(rect, n.pos);
        let sel = is_selected(n.id);
        if sel || hovered == Some(n.id) {
            let r = n.radius * cam.zoom;
            painter.circle_stroke(
                p,
                r,
                Stroke::new(1.0, Color32::from_white_alpha(if sel { 160 } else { 90 })),
            );
        }
        let outline = if sel { SELECT_COLOUR } else { Color32::BLACK };
        if n.id == root.id {
            painter.rect(
                Rect::from_center_size(p, Vec2::splat(12.0)),
                2.0,
                ROOT_COLOUR,
                Stroke::new(if sel { 2.5 } else { 1.0 }, outline),
                egui::StrokeKind::Outside,
            );
        } else {
            painter.circle(
                p,
                5.5,
                END_COLOUR,
                Stroke::new(if sel { 2.5 } else { 1.0 }, outline),
            );
        }
    }
}

/// A filled arrow from `a` to `b`: a shaft and a head sized by the width.
pub fn draw_arrow(painter: &egui::Painter, a: Pos2, b: Pos2, width: f32, colour: Color32) {
    let d = b - a;
    let len = d.length();
    if len < 1.0 {
        return;
    }
    let dir = d / len;
    let head = (width * 2.8 + 6.0).min(len * 0.6);
    let base = b - dir * head;
    painter.line_segment([a, base], Stroke::new(width, colour));
    let n = dir.rot90() * (head * 0.55);
    painter.add(egui::Shape::convex_polygon(
        vec![b, base + n, base - n],
        colour,
        Stroke::NONE,
    ));
}

/// Draws the obstacles that are not hidden.
pub fn draw_obstacles(
    painter: &egui::Painter,
    cam: &Camera,
    rect: Rect,
    doc: &Layout,
    is_selected: &dyn Fn(u32) -> bool,
) {
    for o in doc.obstacles.iter().filter(|o| !o.hidden) {
        let sel = is_selected(o.id);
        let stroke = Stroke::new(
            if sel { 2.5 } else { 1.0 },
            if sel {
                SELECT_COLOUR
            } else {
                Color32::from_black_alpha(160)
            },
        );
        match &o.shape {
            Shape::Circle { center, radius } => {
                painter.circle(
                    cam.to_screen(rect, *center),
                    radius * cam.zoom,
                    OBSTACLE_COLOUR,
                    stroke,
                );
            }
            Shape::Polygon { points } => {
                let pts: Vec<Pos2> = points.iter().map(|p| cam.to_screen(rect, *p)).collect();
                // Triangulate as a fan for the fill (fine for the simple shapes users draw);
                // the outline shows the true shape.
                let mut mesh = egui::Mesh::default();
                for p in &pts {
                    mesh.colored_vertex(*p, OBSTACLE_COLOUR);
                }
                crate::doc::for_each_ear(points, |a, b, c| {
                    mesh.add_triangle(a as u32, b as u32, c as u32)
                });
                painter.add(mesh);
                painter.add(egui::Shape::closed_line(pts, stroke));
            }
            Shape::Mask { rect: r, .. } => {
                // The solid pixels (sampled at up to 512 a side), and the image's rectangle.
                let mut mesh = egui::Mesh::default();
                for [a, b] in o.shape.mask_runs(doc.bounds(), 512) {
                    let q = Rect::from_two_pos(cam.to_screen(rect, a), cam.to_screen(rect, b));
                    mesh.add_colored_rect(q, OBSTACLE_COLOUR);
                }
                painter.add(mesh);
                let [a, b] = crate::doc::placed(r, doc.bounds());
                painter.rect_stroke(
                    Rect::from_two_pos(cam.to_screen(rect, a), cam.to_screen(rect, b)),
                    0.0,
                    stroke,
                    egui::StrokeKind::Middle,
                );
            }
        }
    }
}

/// The node nearest to screen point `s` within `radius` points, among the trees that are
/// neither hidden nor locked.
pub fn hit_node(doc: &Layout, cam: &Camera, rect: Rect, s: Pos2, radius: f32) -> Option<u32> {
    (doc.trees.iter())
        .filter(|t| t.pickable())
        .flat_map(|t| t.root.iter())
        .map(|n| (n.id, cam.to_screen(rect, n.pos).distance(s)))
        .filter(|(_, d)| *d <= radius)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(id, _)| id)
}

/// The probe nearest to screen point `s` within `radius` points.
pub fn hit_probe(doc: &Layout, cam: &Camera, rect: Rect, s: Pos2, radius: f32) -> Option<u32> {
    (doc.probes.iter())
        .map(|p| (p.id, cam.to_screen(rect, p.pos).distance(s)))
        .filter(|(_, d)| *d <= radius)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(id, _)| id)
}

/// Draws the probes: a pin in each one's plot colour, its name beside it.
pub fn draw_probes(
    painter: &egui::Painter,
    cam: &Camera,
    rect: Rect,
    doc: &Layout,
    is_selected: &dyn Fn(u32) -> bool,
) {
    for (k, p) in doc.probes.iter().enumerate() {
        let at = cam.to_screen(rect, p.pos);
        let ring = if is_selected(p.id) {
            Stroke::new(2.5, SELECT_COLOUR)
        } else {
            Stroke::new(1.5, Color32::WHITE)
        };
        painter.circle(at, 6.0, super::probes::colour(k), ring);
        painter.circle_filled(at, 1.5, Color32::BLACK);
        painter.text(
            at + Vec2::new(9.0, -9.0),
            egui::Align2::LEFT_BOTTOM,
            &p.name,
            egui::FontId::proportional(12.0),
            Color32::WHITE,
        );
    }
}

/// The obstacle under screen point `s`, among those neither hidden nor locked.
pub fn hit_obstacle(doc: &Layout, cam: &Camera, rect: Rect, s: Pos2) -> Option<u32> {
    let w = cam.to_world(rect, s);
    doc.obstacles
        .iter()
        .rev()
        .filter(|o| o.pickable())
        .find(|o| match &o.shape {
            Shape::Circle { center, radius } => {
                (w[0] - center[0]).hypot(w[1] - center[1]) <= *radius
            }
            Shape::Polygon { points } => point_in_polygon(w, points),
            Shape::Mask { .. } => o.shape.mask_contains(w, doc.bounds()),
        })
        .map(|o| o.id)
}

pub fn point_in_polygon(p: W2, poly: &[W2]) -> bool {
    let mut inside = false;
    let n = poly.len();
    for i in 0..n {
        let a = poly[i];
        let b = poly[(i + n - 1) % n];
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0]
        {
            inside = !inside;
        }
    }
    inside
}

/// Streak particles advected through the field, each with a short fading trail.
pub struct Streaks {
    particles: Vec<Particle>,
    seed: u32,
}

struct Particle {
    trail: Vec<W2>,
    age: f32,
    life: f32,
}

const TRAIL: usize = 14;

impl Streaks {
    pub fn new() -> Self {
        Self {
            particles: Vec::new(),
            seed: 1,
        }
    }

    fn random(&mut self) -> f32 {
        self.seed ^= self.seed << 13;
        self.seed ^= self.seed >> 17;
        self.seed ^= self.seed << 5;
        (self.seed >> 8) as f32 / 16_777_216.0
    }

    fn spawn(&mut self, doc: &Layout) -> Particle {
        let (min, _) = doc.bounds();
        let p = [
            min[0] + self.random() * doc.world.size[0],
            min[1] + self.random() * doc.world.size[1],
        ];
        let life = 1.5 + self.random() * 2.5;
        Particle {
            trail: vec![p],
            age: 0.0,
            life,
        }
    }

    /// Moves the particles by `dt` seconds of simulated wind.
    pub fn advance(&mut self, doc: &Layout, snap: &Snapshot, dt: f32, count: usize) {
        while self.particles.len() < count {
            let mut p = self.spawn(doc);
            p.age = self.random() * p.life;
            self.particles.push(p);
        }
        self.particles.truncate(count);
        let (min, max) = doc.bounds();
        for k in 0..self.particles.len() {
            let dead = {
                let p = &mut self.particles[k];
                let head = *p.trail.last().unwrap_or(&[0.0, 0.0]);
                let v = snap.sample(head);
                let next = [head[0] + v[0] * dt, head[1] + v[1] * dt];
                p.trail.push(next);
                if p.trail.len() > TRAIL {
                    p.trail.remove(0);
                }
                p.age += dt;
                let out =
                    next[0] < min[0] || next[1] < min[1] || next[0] > max[0] || next[1] > max[1];
                p.age > p.life || out || (v[0] == 0.0 && v[1] == 0.0 && p.age > 0.5)
            };
            if dead {
                self.particles[k] = self.spawn(doc);
            }
        }
    }

    pub fn draw(
        &self,
        painter: &egui::Painter,
        cam: &Camera,
        rect: Rect,
        snap: &Snapshot,
        max_speed: f32,
    ) {
        for p in &self.particles {
            let (Some(&head), true) = (p.trail.last(), p.trail.len() >= 2) else {
                continue;
            };
            let fade = (1.0 - (2.0 * p.age / p.life - 1.0).abs()).clamp(0.0, 1.0);
            let v = snap.sample(head);
            let colour = speed_colour((v[0].hypot(v[1]) / max_speed.max(1e-3)).sqrt());
            let n = p.trail.len();
            for k in 1..n {
                let a = cam.to_screen(rect, p.trail[k - 1]);
                let b = cam.to_screen(rect, p.trail[k]);
                let t = k as f32 / n as f32;
                let alpha = (t * fade * 230.0) as u8;
                painter.line_segment(
                    [a, b],
                    Stroke::new(
                        1.6,
                        Color32::from_rgba_unmultiplied(colour.r(), colour.g(), colour.b(), alpha),
                    ),
                );
            }
        }
    }
}

impl Default for Streaks {
    fn default() -> Self {
        Self::new()
    }
}

/// Arrow glyphs on a regular screen-space lattice, length by speed.
pub fn draw_glyphs(
    painter: &egui::Painter,
    cam: &Camera,
    rect: Rect,
    doc: &Layout,
    snap: &Snapshot,
    max_speed: f32,
) {
    let spacing = 26.0;
    let (min, max) = doc.bounds();
    let a = cam.to_screen(rect, min).max(rect.min);
    let b = cam.to_screen(rect, max).min(rect.max);
    let mut y = a.y + spacing * 0.5;
    while y < b.y {
        let mut x = a.x + spacing * 0.5;
        while x < b.x {
            let w = cam.to_world(rect, Pos2::new(x, y));
            let v = snap.sample(w);
            let s = v[0].hypot(v[1]);
            if s > max_speed * 0.02 {
                let len = spacing * 0.9 * (s / max_speed).sqrt();
                let d = Vec2::new(v[0], v[1]) / s * len;
                let c = Pos2::new(x, y);
                draw_arrow(
                    painter,
                    c - d * 0.5,
                    c + d * 0.5,
                    1.5,
                    speed_colour(s / max_speed),
                );
            }
            x += spacing;
        }
        y += spacing;
    }
}

/// A ring with a dot at `at`: where the pointer of the other view (the map beside the 3D
/// view, or the 3D view beside the map) is on the ground.
pub fn draw_pointer_mark(painter: &egui::Painter, at: Pos2) {
    let dark = egui::Stroke::new(3.0, Color32::from_black_alpha(160));
    let light = egui::Stroke::new(1.5, Color32::WHITE);
    for stroke in [dark, light] {
        painter.circle_stroke(at, 7.0, stroke);
    }
    painter.circle_filled(at, 2.0, Color32::WHITE);
}

/// What the map's gizmo shows of an ambient layer: its name, the unit direction its wind
/// blows (world `[x, z]`, `doc::direction` of its `direction_deg`), and the spatial scale of
/// its gusts in metres where it has one (noise: its feature size; FFT: its tile; sine: its
/// wavelength; a directional layer's gusts are uniform in space).
#[derive(Debug, Clone, PartialEq)]
pub struct AmbientGizmo {
    pub name: String,
    pub direction: [f32; 2],
    pub gust_scale: Option<f32>,
}

/// The gizmos of `layout`'s enabled ambient layers not hidden, in the layers' order.
pub fn ambient_gizmos(layout: &Layout) -> Vec<AmbientGizmo> {
    use crate::doc::AmbientKind as K;
    layout
        .ambient
        .iter()
        .filter(|a| a.enabled && !a.hidden)
        .map(|a| {
            let (deg, gust_scale) = match &a.kind {
                K::Directional { direction_deg, .. } => (*direction_deg, None),
                K::Noise {
                    direction_deg,
                    scale,
                    ..
                } => (*direction_deg, Some(*scale)),
                K::Fft {
                    direction_deg,
                    tile_size,
                    ..
                } => (*direction_deg, Some(*tile_size)),
                K::Sine {
                    direction_deg,
                    wavelength,
                    ..
                } => (*direction_deg, Some(*wavelength)),
            };
            AmbientGizmo {
                name: a.name.clone(),
                direction: crate::doc::direction(deg),
                gust_scale,
            }
        })
        .collect()
}

/// The ambient layers' gizmos inside the world's top-left corner, one under the other: a
/// dial with an arrow the way the layer's wind blows, its name, and a bar as long as its
/// gusts' scale on the map (capped at 200 points, the length written beside it).
pub fn draw_ambient_gizmos(painter: &egui::Painter, cam: &Camera, rect: Rect, doc: &Layout) {
    let (min, _) = doc.bounds();
    let corner = cam.to_screen(rect, min).max(rect.min) + Vec2::new(34.0, 34.0);
    let ink = Color32::from_rgb(250, 220, 120);
    for (k, g) in ambient_gizmos(doc).iter().enumerate() {
        let c = corner + Vec2::new(0.0, 58.0 * k as f32);
        painter.circle_filled(c, 22.0, Color32::from_black_alpha(140));
        painter.circle_stroke(c, 22.0, Stroke::new(1.0, ink));
        // World +x is the map's right, +z its down.
        let d = Vec2::new(g.direction[0], g.direction[1]) * 17.0;
        painter.arrow(c - d, d * 2.0, Stroke::new(2.0, ink));
        let font = egui::FontId::proportional(12.0);
        let at = c + Vec2::new(28.0, -14.0);
        painter.text(at, egui::Align2::LEFT_TOP, &g.name, font.clone(), ink);
        if let Some(m) = g.gust_scale {
            let len = (m * cam.zoom).min(200.0);
            let y = at.y + 18.0;
            painter.line_segment(
                [Pos2::new(at.x, y), Pos2::new(at.x + len, y)],
                Stroke::new(2.0, ink),
            );
            painter.text(
                Pos2::new(at.x + len + 6.0, y),
                egui::Align2::LEFT_CENTER,
                format!("gusts {m:.0} m"),
                font,
                ink,
            );
        }
    }
}

/// The colour scale of view `mode` with its title and range (top right of `rect`): the map
/// view's, and the 3D view's while it shows the wind colours.
pub fn draw_legend(painter: &egui::Painter, rect: Rect, mode: WindView, scale: f32) {
    if mode == WindView::Off || scale <= 0.0 {
        return;
    }
    // A plate 10 points inside the top right corner: the title, the bar, its range.
    let w = 180.0;
    let plate = Rect::from_min_size(
        rect.right_top() + Vec2::new(-w - 30.0, 10.0),
        Vec2::new(w + 20.0, 56.0),
    );
    let origin = plate.min + Vec2::new(10.0, 6.0);
    let bar = Rect::from_min_size(origin + Vec2::new(0.0, 18.0), Vec2::new(w, 10.0));
    painter.rect_filled(plate, 4.0, Color32::from_black_alpha(150));
    let n = 32;
    for k in 0..n {
        let t = k as f32 / (n - 1) as f32;
        let c = match mode {
            WindView::Curl | WindView::Pressure => signed_colour(t * 2.0 - 1.0),
            _ => speed_colour(t),
        };
        let x0 = bar.left() + w * k as f32 / n as f32;
        painter.rect_filled(
            Rect::from_min_size(
                Pos2::new(x0, bar.top()),
                Vec2::new(w / n as f32 + 0.5, bar.height()),
            ),
            0.0,
            c,
        );
    }
    let (title, lo, hi) = match mode {
        WindView::Curl => (
            "curl (1/s)",
            format!("{:.2}", -scale),
            format!("{scale:.2}"),
        ),
        WindView::Pressure => ("pressure", format!("{:.2}", -scale), format!("{scale:.2}")),
        _ => ("wind speed (m/s)", "0".to_string(), format!("{scale:.1}")),
    };
    let font = egui::FontId::proportional(12.0);
    painter.text(
        origin,
        egui::Align2::LEFT_TOP,
        title,
        font.clone(),
        Color32::WHITE,
    );
    painter.text(
        bar.left_bottom() + Vec2::new(0.0, 2.0),
        egui::Align2::LEFT_TOP,
        lo,
        font.clone(),
        Color32::WHITE,
    );
    painter.text(
        bar.right_bottom() + Vec2::new(0.0, 2.0),
        egui::Align2::RIGHT_TOP,
        hi,
        font,
        Color32::WHITE,
    );
}
