//! The paint tool: over a mask obstacle's pixels (paint makes them solid, Shift erases) or,
//! with no mask selected, over the grass density map (paint grows grass, Shift clears it).
//! Three marks: a soft **brush** (its radius, hardness and opacity), a **rectangle** dragged
//! corner to corner, and a **fill** of the region clicked (a mask's solid or open pixels
//! joined to the one clicked; the density map's of about the same density). A stroke lays
//! its marks on a coverage of the image as it was (`doc::raster`) and lands as one edit when
//! the button comes up: one undo step a stroke, the wind and grass rebuilt once, and a
//! stroke's dabs never build up past its opacity. Saving writes the painted image beside the
//! layout (`io::Document::write_to`).

use super::{EditorApp, Sel};
use crate::doc::{self, Edit, MaskImage, MaskPixels, Shape, raster};
use eframe::egui::{self, Color32, Rect, Stroke};
use std::sync::Arc;

/// What a stroke paints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// The mask obstacle with this id.
    Mask(u32),
    /// The grass's density map.
    Density,
}

/// The paint tool's mark.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Mark {
    /// A soft round brush dragged over the image.
    #[default]
    Brush,
    /// A rectangle dragged from one corner to the other.
    Rectangle,
    /// The region joined to the pixel clicked.
    Fill,
}

impl Mark {
    pub const ALL: [Mark; 3] = [Mark::Brush, Mark::Rectangle, Mark::Fill];

    pub fn label(self) -> &'static str {
        match self {
            Mark::Brush => "Brush",
            Mark::Rectangle => "Rect",
            Mark::Fill => "Fill",
        }
    }

    pub fn hint(self) -> &'static str {
        match self {
            Mark::Brush => "A soft round brush: drag over the image",
            Mark::Rectangle => "Drag a rectangle from one corner to the other",
            Mark::Fill => {
                "Click to fill the region joined to the pixel clicked (a mask's solid or open \
                 pixels, the density map's of about the same density)"
            }
        }
    }
}

/// The paint tool's settings (kept between runs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Brush {
    pub mark: Mark,
    /// The share of the radius painted at full strength, 0 (soft all the way) to 1 (a hard
    /// edge).
    pub hardness: f32,
    /// How far a stroke moves the pixels toward the paint, 0 to 1.
    pub opacity: f32,
}

impl Default for Brush {
    fn default() -> Self {
        Self {
            mark: Mark::Brush,
            hardness: 0.7,
            opacity: 1.0,
        }
    }
}

impl Brush {
    /// Within range, whatever an earlier run's settings file holds.
    pub fn sane(self) -> Self {
        let unit = |v: f32, d: f32| if v.is_finite() { v.clamp(0.0, 1.0) } else { d };
        let d = Self::default();
        Self {
            mark: self.mark,
            hardness: unit(self.hardness, d.hardness),
            opacity: unit(self.opacity, d.opacity),
        }
    }
}

/// A stroke in progress: the image as it was, each pixel's coverage so far, where it lies,
/// the value it paints, the mark and its opacity, and what to draw on the map until it
/// lands.
pub struct PaintStroke {
    target: Target,
    original: Arc<MaskImage>,
    cover: Vec<f32>,
    rect: [doc::Vec2; 2],
    value: u16,
    brush: Brush,
    /// Where the stroke started (a rectangle's first corner) and the pointer's last point.
    start: doc::Vec2,
    last: doc::Vec2,
    dabs: Vec<doc::Vec2>,
}

/// The brush's radius range, metres.
pub const RADIUS: std::ops::RangeInclusive<f32> = 0.1..=100.0;

/// What the brush would paint now: the selected mask obstacle, else the density map.
pub fn target(app: &EditorApp) -> Option<Target> {
    if let [Sel::Obstacle(id)] = app.selection.as_slice()
        && app
            .doc
            .obstacles
            .iter()
            .any(|o| o.id == *id && matches!(o.shape, Shape::Mask { .. }))
    {
        return Some(Target::Mask(*id));
    }
    app.doc.grass.density_map.as_ref().map(|_| Target::Density)
}

/// The image a stroke paints, where it lies, and for a mask its threshold and inversion.
type Painted<'a> = (&'a MaskPixels, [doc::Vec2; 2], Option<(f32, bool)>);

/// The image `t` paints ([`Painted`]).
fn image_of(layout: &doc::Layout, t: Target) -> Option<Painted<'_>> {
    let bounds = layout.bounds();
    match t {
        Target::Mask(id) => {
            layout
                .obstacles
                .iter()
                .find(|o| o.id == id)
                .and_then(|o| match &o.shape {
                    Shape::Mask {
                        pixels,
                        rect,
                        threshold,
                        invert,
                        ..
                    } => Some((
                        pixels,
                        doc::placed(rect, bounds),
                        Some((*threshold, *invert)),
                    )),
                    _ => None,
                })
        }
        Target::Density => layout
            .grass
            .density_map
            .as_ref()
            .map(|m| (&m.pixels, doc::placed(&m.rect, bounds), None)),
    }
}

/// The edit that puts `image` in place of `t`'s pixels, and the new file name it takes when
/// another item names the same file (which keeps its pixels: two items never hold different
/// pixels under one name).
fn edit_for(app: &EditorApp, t: Target, image: MaskImage) -> Option<(Edit, Option<String>)> {
    let layout: &doc::Layout = &app.doc;
    let pixels = MaskPixels::Loaded(std::sync::Arc::new(image));
    let name =
        match t {
            Target::Mask(id) => layout
                .obstacles
                .iter()
                .find(|o| o.id == id)
                .and_then(|o| match &o.shape {
                    Shape::Mask { image, .. } => Some(image.clone()),
                    _ => None,
                }),
            Target::Density => layout.grass.density_map.as_ref().map(|m| m.image.clone()),
        }?;
    let files = doc::portable::files(layout);
    let shared = files.iter().filter(|(_, n, _)| *n == name).count() > 1;
    let renamed = shared.then(|| {
        let base = app.doc.base();
        crate::io::images::free_name(&name, |n| {
            !files.iter().any(|(_, m, _)| *m == n)
                && !crate::io::images::file_key(&base, n).exists()
        })
    });
    let edit = match t {
        Target::Mask(id) => {
            let mut o = layout.obstacles.iter().find(|o| o.id == id)?.clone();
            if let Shape::Mask {
                pixels: p, image, ..
            } = &mut o.shape
            {
                *p = pixels;
                if let Some(n) = &renamed {
                    image.clone_from(n);
                }
            }
            Edit::SetObstacle { obstacle: o }
        }
        Target::Density => {
            let mut g = layout.grass.clone();
            let m = g.density_map.as_mut()?;
            m.pixels = pixels;
            if let Some(n) = &renamed {
                m.image.clone_from(n);
            }
            Edit::SetGrass(g)
        }
    };
    Some((edit, renamed))
}

/// One frame of the paint tool on the map.
pub fn tool(
    app: &mut EditorApp,
    ctx: &egui::Context,
    response: &egui::Response,
    rect: Rect,
    cam: &super::view::Camera,
    painter: &egui::Painter,
) {
    let radius = app.brush_radius;
    let down = ctx.input(|i| i.pointer.primary_down());
    let erase = ctx.input(|i| i.modifiers.shift);
    let pointer = response.interact_pointer_pos().or(response.hover_pos());
    let world = pointer.map(|p| cam.to_world(rect, p));
    if app.paint.is_none()
        && response.is_pointer_button_down_on()
        && down
        && let Some(p) = ctx
            .input(|i| i.pointer.press_origin())
            .map(|p| cam.to_world(rect, p))
            .or(world)
    {
        start(app, ctx, p, erase);
    }
    if let Some(s) = &mut app.paint {
        if let Some(p) = world.filter(|_| down) {
            let size = (s.original.width, s.original.height);
            match s.brush.mark {
                Mark::Brush => {
                    // Dabs a third of the radius apart, so a fast drag leaves no gaps.
                    let d = (p[0] - s.last[0]).hypot(p[1] - s.last[1]);
                    let n = (d / (radius / 3.0)).ceil().max(1.0) as usize;
                    for k in 1..=n {
                        let t = k as f32 / n as f32;
                        let q = [
                            s.last[0] + (p[0] - s.last[0]) * t,
                            s.last[1] + (p[1] - s.last[1]) * t,
                        ];
                        raster::dab(size, s.rect, q, radius, s.brush.hardness, &mut s.cover);
                        s.dabs.push(q);
                    }
                }
                Mark::Rectangle | Mark::Fill => {}
            }
            s.last = p;
        }
        if !down {
            finish(app, ctx);
        }
    }
    // The stroke so far, and the brush under the pointer.
    let px = |r: f32| r * cam.zoom;
    if let Some(s) = &app.paint {
        let alpha = (40.0 + 80.0 * s.brush.opacity) as u8;
        let fill = if s.value < u16::MAX / 2 {
            Color32::from_rgba_unmultiplied(20, 20, 20, alpha)
        } else {
            Color32::from_rgba_unmultiplied(240, 240, 240, alpha)
        };
        match s.brush.mark {
            Mark::Brush => {
                for d in &s.dabs {
                    painter.circle_filled(cam.to_screen(rect, *d), px(radius), fill);
                }
            }
            Mark::Rectangle => {
                let r =
                    Rect::from_two_pos(cam.to_screen(rect, s.start), cam.to_screen(rect, s.last));
                painter.rect(
                    r,
                    0.0,
                    fill,
                    Stroke::new(1.0, Color32::from_white_alpha(200)),
                    egui::StrokeKind::Inside,
                );
            }
            Mark::Fill => {}
        }
    }
    if let Some(p) = response.hover_pos() {
        let ring = Stroke::new(1.5, Color32::from_white_alpha(200));
        match app.settings.brush.mark {
            Mark::Brush => {
                painter.circle_stroke(p, px(radius), ring);
                // The hard core, where the brush paints at full strength.
                let core = app.settings.brush.hardness;
                if core > 0.02 && core < 0.98 {
                    painter.circle_stroke(
                        p,
                        px(radius * core),
                        Stroke::new(1.0, Color32::from_white_alpha(90)),
                    );
                }
            }
            Mark::Rectangle | Mark::Fill => {
                painter.line_segment([p - egui::vec2(8.0, 0.0), p + egui::vec2(8.0, 0.0)], ring);
                painter.line_segment([p - egui::vec2(0.0, 8.0), p + egui::vec2(0.0, 8.0)], ring);
            }
        }
    }
}

fn start(app: &mut EditorApp, ctx: &egui::Context, p: doc::Vec2, erase: bool) {
    let Some(t) = target(app) else {
        app.say(
            ctx,
            "Nothing to paint: select a mask obstacle, or give the grass a density map",
        );
        return;
    };
    let Some((pixels, rect, mask)) = image_of(&app.doc, t) else {
        return;
    };
    let MaskPixels::Loaded(original) = pixels else {
        app.say(ctx, "The image is not loaded, so it cannot be painted");
        return;
    };
    let original = original.clone();
    // A mask's solid value is dark (light when inverted); the density map's grass is white.
    let solid = if mask.is_some_and(|(_, invert)| invert) {
        u16::MAX
    } else {
        0
    };
    let value = match (mask, erase) {
        (Some(_), false) => solid,
        (Some(_), true) => u16::MAX - solid,
        (None, false) => u16::MAX,
        (None, true) => 0,
    };
    let brush = app.settings.brush;
    let size = (original.width, original.height);
    let mut cover = vec![0.0; original.luminance.len()];
    match brush.mark {
        Mark::Brush => {
            raster::dab(size, rect, p, app.brush_radius, brush.hardness, &mut cover);
        }
        Mark::Rectangle => {}
        Mark::Fill => {
            // A mask's pixels as solid or open, as the clicked one is; the density map's
            // within a tenth of its density.
            let same: Box<dyn Fn(u16) -> bool> = match (mask, doc::image_uv(rect, p)) {
                (_, None) => Box::new(|_| false),
                (Some((threshold, invert)), Some([u, v])) => {
                    let solid_at = original.solid_at(u, v, threshold, invert);
                    Box::new(move |l: u16| {
                        (((f32::from(l) / 65535.0) < threshold) != invert) == solid_at
                    })
                }
                (None, Some([u, v])) => {
                    let l0 = original.luminance_at(u, v);
                    Box::new(move |l: u16| (f32::from(l) / 65535.0 - l0).abs() <= 0.1)
                }
            };
            raster::fill(&original, rect, p, same, &mut cover);
        }
    }
    app.paint = Some(PaintStroke {
        target: t,
        original,
        cover,
        rect,
        value,
        brush,
        start: p,
        last: p,
        dabs: vec![p],
    });
}

fn finish(app: &mut EditorApp, ctx: &egui::Context) {
    let Some(mut s) = app.paint.take() else {
        return;
    };
    if s.brush.mark == Mark::Rectangle {
        let size = (s.original.width, s.original.height);
        raster::rectangle(size, s.rect, s.start, s.last, &mut s.cover);
    }
    let image = raster::blend(&s.original, &s.cover, s.value, s.brush.opacity);
    if image == *s.original {
        return;
    }
    if let Some((e, renamed)) = edit_for(app, s.target, image)
        && app.edit(ctx, e)
        && let Some(n) = renamed
    {
        app.say(
            ctx,
            format!("Painted as {n}: another item names the original, which keeps its pixels"),
        );
    }
}

/// The density map's bare ground on the map while the brush paints it: dark where it grows
/// less grass (sampled at up to 128 a side).
pub fn draw_density(
    app: &EditorApp,
    painter: &egui::Painter,
    cam: &super::view::Camera,
    rect: Rect,
) {
    let Some(m) = &app.doc.grass.density_map else {
        return;
    };
    let Some(img) = m.pixels.image() else {
        return;
    };
    let [a, b] = doc::placed(&m.rect, app.doc.bounds());
    let (nx, ny) = (img.width.min(128), img.height.min(128));
    let mut mesh = egui::Mesh::default();
    for j in 0..ny {
        for i in 0..nx {
            let l = img.luminance_at((i as f32 + 0.5) / nx as f32, (j as f32 + 0.5) / ny as f32);
            if l >= 0.99 {
                continue;
            }
            let p = |fi: f32, fj: f32| {
                [
                    a[0] + (b[0] - a[0]) * fi / nx as f32,
                    a[1] + (b[1] - a[1]) * fj / ny as f32,
                ]
            };
            let q = Rect::from_two_pos(
                cam.to_screen(rect, p(i as f32, j as f32)),
                cam.to_screen(rect, p(i as f32 + 1.0, j as f32 + 1.0)),
            );
            let alpha = ((1.0 - l) * 150.0) as u8;
            mesh.add_colored_rect(q, Color32::from_rgba_unmultiplied(60, 35, 10, alpha));
        }
    }
    painter.add(mesh);
}
