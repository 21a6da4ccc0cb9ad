//! The paint tool: a brush over a mask obstacle's pixels (paint makes them solid, Shift
//! erases) or, with no mask selected, over the grass density map (paint grows grass, Shift
//! clears it). A stroke paints a copy of the image and lands as one edit when the button comes
//! up: one undo step a stroke, and the wind and grass rebuilt once. Saving writes the painted
//! image beside the layout (`io::Document::write_to`).

use super::{EditorApp, Sel};
use crate::doc::{self, Edit, MaskImage, MaskPixels, Shape};
use eframe::egui::{self, Color32, Rect, Stroke};

/// What a stroke paints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// The mask obstacle with this id.
    Mask(u32),
    /// The grass's density map.
    Density,
}

/// A stroke in progress: the painted copy, where it lies, the value it paints, and the dabs
/// so far (drawn on the map until the stroke lands).
pub struct PaintStroke {
    target: Target,
    image: MaskImage,
    rect: [doc::Vec2; 2],
    value: u16,
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

/// The image `t` paints, where it lies, and whether a mask is inverted.
fn image_of(layout: &doc::Layout, t: Target) -> Option<(&MaskPixels, [doc::Vec2; 2], bool)> {
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
                        invert,
                        ..
                    } => Some((pixels, doc::placed(rect, bounds), *invert)),
                    _ => None,
                })
        }
        Target::Density => layout
            .grass
            .density_map
            .as_ref()
            .map(|m| (&m.pixels, doc::placed(&m.rect, bounds), false)),
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
        && let Some(p) = world
    {
        start(app, ctx, p, erase);
    }
    if let Some(s) = &mut app.paint {
        if let Some(p) = world.filter(|_| down) {
            // Dabs a third of the radius apart, so a fast drag leaves no gaps.
            let d = ((p[0] - s.last[0]).powi(2) + (p[1] - s.last[1]).powi(2)).sqrt();
            let n = (d / (radius / 3.0)).ceil().max(1.0) as usize;
            for k in 1..=n {
                let t = k as f32 / n as f32;
                let q = [
                    s.last[0] + (p[0] - s.last[0]) * t,
                    s.last[1] + (p[1] - s.last[1]) * t,
                ];
                s.image.paint_disc(s.rect, q, radius, s.value);
                s.dabs.push(q);
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
        let fill = if s.value == 0 {
            Color32::from_rgba_unmultiplied(20, 20, 20, 110)
        } else {
            Color32::from_rgba_unmultiplied(240, 240, 240, 90)
        };
        for d in &s.dabs {
            painter.circle_filled(cam.to_screen(rect, *d), px(radius), fill);
        }
    }
    if let Some(p) = response.hover_pos() {
        painter.circle_stroke(
            p,
            px(radius),
            Stroke::new(1.5, Color32::from_white_alpha(200)),
        );
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
    let Some((pixels, rect, invert)) = image_of(&app.doc, t) else {
        return;
    };
    let Some(image) = pixels.image() else {
        app.say(ctx, "The image is not loaded, so it cannot be painted");
        return;
    };
    // A mask's solid value is dark (light when inverted); the density map's grass is white.
    let solid = if invert { u16::MAX } else { 0 };
    let value = match (t, erase) {
        (Target::Mask(_), false) => solid,
        (Target::Mask(_), true) => u16::MAX - solid,
        (Target::Density, false) => u16::MAX,
        (Target::Density, true) => 0,
    };
    let mut image = image.clone();
    image.paint_disc(rect, p, app.brush_radius, value);
    app.paint = Some(PaintStroke {
        target: t,
        image,
        rect,
        value,
        last: p,
        dabs: vec![p],
    });
}

fn finish(app: &mut EditorApp, ctx: &egui::Context) {
    let Some(s) = app.paint.take() else {
        return;
    };
    let unchanged = image_of(&app.doc, s.target)
        .and_then(|(p, _, _)| p.image())
        .is_some_and(|i| *i == s.image);
    if unchanged {
        return;
    }
    if let Some((e, renamed)) = edit_for(app, s.target, s.image)
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
