//! `windloom render`: a top-down picture of a layout and its simulated wind, drawn with
//! tiny-skia — backdrop, obstacles, evenly spaced streamlines coloured by speed, the arrow
//! trees, a legend and a scale bar. For thumbnails and design documents.

use crate::colour::speed_rgb;
use crate::doc::{Layout, Shape};
use crate::sim::Solver;
use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use std::path::Path;
use tiny_skia::{
    Color, FillRule, FilterQuality, LineCap, LineJoin, Paint, PathBuilder, Pixmap, PixmapPaint,
    Rect, Stroke, Transform,
};

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error("picture size must be 64x64 to 8192x8192, got {0}x{1}")]
    Size(u32, u32),
    #[error("--time must be 0 to 3600 seconds, got {0}")]
    Time(f32),
    #[error("encoding the PNG: {0}")]
    Encode(String),
    #[error("the world ({0} × {1} m) is too thin to draw in a {2}x{3} picture")]
    Degenerate(f32, f32, u32, u32),
}

/// World → picture mapping.
struct View {
    scale: f32,
    ox: f32,
    oy: f32,
    min: [f32; 2],
}

impl View {
    fn px(&self, p: [f32; 2]) -> (f32, f32) {
        (
            self.ox + (p[0] - self.min[0]) * self.scale,
            self.oy + (p[1] - self.min[1]) * self.scale,
        )
    }
}

fn rgba(c: [u8; 3], a: u8) -> Color {
    Color::from_rgba8(c[0], c[1], c[2], a)
}

fn paint(c: Color) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color(c);
    p.anti_alias = true;
    p
}

/// Pictures are 64x64 to 8192x8192 pixels.
fn check_size(w: u32, h: u32) -> Result<(), RenderError> {
    if (64..=8192).contains(&w) && (64..=8192).contains(&h) {
        Ok(())
    } else {
        Err(RenderError::Size(w, h))
    }
}

/// Simulates `layout` for `time` seconds and draws it into a `size` PNG. `base` is the folder
/// the layout's backdrop path is relative to.
/// `speed_scale`: the speed (m/s) at the top of the colours, as the editor's fixed speed
/// scale; `None`: the field's peak.
pub fn render_png(
    layout: &Layout,
    base: &Path,
    size: [u32; 2],
    time: f32,
    speed_scale: Option<f32>,
) -> Result<Vec<u8>, RenderError> {
    let [w, h] = size;
    check_size(w, h)?;
    if !(time.is_finite() && (0.0..=3600.0).contains(&time)) {
        return Err(RenderError::Time(time));
    }
    let mut solver = Solver::new(layout);
    while solver.time() + 1e-6 < time {
        solver.step();
    }
    let pix = render_scaled(layout, base, &solver, [w, h], speed_scale)?;
    pix.encode_png()
        .map_err(|e| RenderError::Encode(e.to_string()))
}

/// Draws the picture of `solver`'s current field. `w × h` must be 64x64 to 8192x8192 and
/// the layout valid (its bounds are what keep every coordinate a finite pixel).
pub fn render(
    layout: &Layout,
    base: &Path,
    solver: &Solver,
    w: u32,
    h: u32,
) -> Result<Pixmap, RenderError> {
    render_scaled(layout, base, solver, [w, h], None)
}

/// [`render`] with the speed colours from 0 to `speed_scale` m/s (`None`: to the field's
/// peak); faster wind takes the top colour.
pub fn render_scaled(
    layout: &Layout,
    base: &Path,
    solver: &Solver,
    [w, h]: [u32; 2],
    speed_scale: Option<f32>,
) -> Result<Pixmap, RenderError> {
    let degenerate = || RenderError::Degenerate(layout.world.size[0], layout.world.size[1], w, h);
    check_size(w, h)?;
    let mut pix = Pixmap::new(w, h).ok_or_else(degenerate)?;
    pix.fill(Color::from_rgba8(24, 27, 32, 255));
    let font = FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|e| RenderError::Encode(format!("the bundled font: {e}")))?;
    // Text and line scale: grows with the picture, but the title and legend bands (140 units
    // together) never take more than half the height, nor the side margins half the width.
    let ui = (h as f32 / 1000.0)
        .max(0.6)
        .min(h as f32 * 0.5 / 140.0)
        .min(w as f32 * 0.5 / 48.0);

    // Fit the world between a title band and a legend band.
    let (min, max) = layout.bounds();
    let size = layout.world.size;
    let top = 56.0 * ui;
    let bottom = 84.0 * ui;
    let margin = 24.0 * ui;
    let scale = ((w as f32 - 2.0 * margin) / size[0]).min((h as f32 - top - bottom) / size[1]);
    let view = View {
        scale,
        ox: (w as f32 - size[0] * scale) / 2.0,
        oy: top + ((h as f32 - top - bottom) - size[1] * scale) / 2.0,
        min,
    };
    let (x0, y0) = view.px(min);
    let (x1, y1) = view.px(max);
    let world = Rect::from_ltrb(x0, y0, x1, y1)
        .filter(|r| r.width() > 0.0 && r.height() > 0.0)
        .ok_or_else(degenerate)?;
    pix.fill_rect(
        world,
        &paint(Color::from_rgba8(44, 58, 40, 255)),
        Transform::identity(),
        None,
    );
    draw_backdrop(&mut pix, layout, base, &view);

    // Speed underlay: the field as a small image, stretched with bilinear filtering.
    let field = solver.velocity_field();
    let peak = field
        .iter()
        .map(|v| crate::num::hypot(v[0], v[1]))
        .fold(1e-3f32, f32::max);
    let max_speed = speed_scale
        .filter(|s| s.is_finite() && *s > 0.0)
        .unwrap_or(peak);
    if let Some(mut under) = Pixmap::new(solver.nx as u32, solver.ny as u32) {
        for (p, v) in under.pixels_mut().iter_mut().zip(&field) {
            let t = (crate::num::hypot(v[0], v[1]) / max_speed).min(1.0);
            let c = speed_rgb(t);
            let a = (40.0 + 120.0 * t.sqrt()) as u8;
            *p = tiny_skia::ColorU8::from_rgba(c[0], c[1], c[2], a).premultiply();
        }
        let t = Transform::from_row(
            world.width() / solver.nx as f32,
            0.0,
            0.0,
            world.height() / solver.ny as f32,
            x0,
            y0,
        );
        let pp = PixmapPaint {
            quality: FilterQuality::Bilinear,
            ..Default::default()
        };
        pix.draw_pixmap(0, 0, under.as_ref(), &pp, t, None);
    }
    // The ground's shape over the speed colours, under the lines.
    draw_relief(&mut pix, layout, &view);

    // A metre grid.
    let step = nice_step(80.0 * ui / scale);
    let grid_paint = paint(Color::from_rgba8(255, 255, 255, 20));
    let thin = Stroke {
        width: 1.0,
        ..Default::default()
    };
    // At most a few hundred lines at these scales; the cap guards against a step that a
    // large coordinate's rounding would swallow.
    let mut gx = (min[0] / step).ceil() * step;
    for _ in 0..1000 {
        if gx > max[0] {
            break;
        }
        line(
            &mut pix,
            view.px([gx, min[1]]),
            view.px([gx, max[1]]),
            &grid_paint,
            &thin,
        );
        gx += step;
    }
    let mut gz = (min[1] / step).ceil() * step;
    for _ in 0..1000 {
        if gz > max[1] {
            break;
        }
        line(
            &mut pix,
            view.px([min[0], gz]),
            view.px([max[0], gz]),
            &grid_paint,
            &thin,
        );
        gz += step;
    }

    draw_streamlines(&mut pix, &view, solver, (max_speed, peak), ui);
    draw_obstacles(&mut pix, &view, layout, ui);
    draw_trees(&mut pix, &view, layout, ui);

    // Frame, title, legend, scale bar.
    let frame = PathBuilder::from_rect(world);
    pix.stroke_path(
        &frame,
        &paint(Color::from_rgba8(255, 255, 255, 80)),
        &thin,
        Transform::identity(),
        None,
    );
    let white = [235, 235, 235];
    let sub = format!(
        "{:.0} × {:.0} m, grid {} × {}, t = {:.1} s",
        size[0],
        size[1],
        solver.nx,
        solver.ny,
        solver.time()
    );
    let tw = text_width(&font, 20.0 * ui, &layout.name);
    let sw = text_width(&font, 14.0 * ui, &sub);
    let gap = 24.0 * ui;
    // Title and legend line up with the world, unless it is too narrow to hold them side by
    // side (a tall world, or a wide short picture): then with the picture's margins.
    let needs = (tw + sw).max(260.0 * ui + 160.0 * ui) + gap;
    let (left, right) = if x1 - x0 >= needs {
        (x0, x1)
    } else {
        (margin, w as f32 - margin)
    };
    text(
        &mut pix,
        &font,
        20.0 * ui,
        (left, top - 16.0 * ui),
        &layout.name,
        white,
    );
    if right - left >= tw + sw + gap {
        text(
            &mut pix,
            &font,
            14.0 * ui,
            (right - sw, top - 16.0 * ui),
            &sub,
            [170, 170, 170],
        );
    }
    legend(
        &mut pix,
        &font,
        (left, y1 + 22.0 * ui),
        (260.0 * ui).min((right - left) * 0.6),
        12.0 * ui,
        max_speed,
        ui,
    );
    scale_bar(&mut pix, &font, &view, (right, y1 + 22.0 * ui), ui);
    Ok(pix)
}

fn nice_step(metres: f32) -> f32 {
    let mut decade = 0.1f32;
    loop {
        for m in [1.0, 2.0, 5.0] {
            if decade * m >= metres {
                return decade * m;
            }
        }
        decade *= 10.0;
    }
}

fn line(pix: &mut Pixmap, a: (f32, f32), b: (f32, f32), p: &Paint, s: &Stroke) {
    let mut pb = PathBuilder::new();
    pb.move_to(a.0, a.1);
    pb.line_to(b.0, b.1);
    if let Some(path) = pb.finish() {
        pix.stroke_path(&path, p, s, Transform::identity(), None);
    }
}

fn draw_backdrop(pix: &mut Pixmap, layout: &Layout, base: &Path, view: &View) {
    let Some(map) = &layout.world.map else {
        return;
    };
    // A backdrop that cannot be read is drawn without (`render` says why on the command line).
    let Ok(img) = crate::io::load_backdrop(base, map) else {
        return;
    };
    let Some(mut p) = Pixmap::new(img.width(), img.height()) else {
        return;
    };
    for (dst, src) in p.pixels_mut().iter_mut().zip(img.pixels()) {
        *dst = tiny_skia::ColorU8::from_rgba(src[0], src[1], src[2], src[3]).premultiply();
    }
    // Where the layout places it (the world rectangle unless it says otherwise).
    let [a, b] = map.placed(layout.bounds());
    let ((x0, y0), (x1, y1)) = (view.px(a), view.px(b));
    let t = Transform::from_row(
        (x1 - x0) / img.width() as f32,
        0.0,
        0.0,
        (y1 - y0) / img.height() as f32,
        x0,
        y0,
    );
    let pp = PixmapPaint {
        opacity: map.opacity,
        quality: FilterQuality::Bilinear,
        ..Default::default()
    };
    pix.draw_pixmap(0, 0, p.as_ref(), &pp, t, None);
}

/// The terrain's hill shade and contour lines (`sim::terrain::relief`) over the world.
fn draw_relief(pix: &mut Pixmap, layout: &Layout, view: &View) {
    let (min, max) = layout.bounds();
    let ((x0, y0), (x1, y1)) = (view.px(min), view.px(max));
    let (w, h) = (
        ((x1 - x0) as usize).clamp(16, 2048),
        ((y1 - y0) as usize).clamp(16, 2048),
    );
    let Some(rgba) = crate::sim::terrain::relief(layout, (w, h), true, true) else {
        return;
    };
    let Some(mut p) = Pixmap::new(w as u32, h as u32) else {
        return;
    };
    for (dst, src) in p.pixels_mut().iter_mut().zip(rgba.chunks_exact(4)) {
        *dst = tiny_skia::ColorU8::from_rgba(src[0], src[1], src[2], src[3]).premultiply();
    }
    let t = Transform::from_row((x1 - x0) / w as f32, 0.0, 0.0, (y1 - y0) / h as f32, x0, y0);
    let pp = PixmapPaint {
        quality: FilterQuality::Bilinear,
        ..Default::default()
    };
    pix.draw_pixmap(0, 0, p.as_ref(), &pp, t, None);
}

/// Evenly spaced streamlines: seeds on a jittered lattice, traced both ways with RK2 until
/// they slow down, leave the world, hit a solid or come too close to an earlier line.
/// Streamlines coloured on the scale `max_speed`; where the wind is under 3 % of the field's
/// own `peak` none starts or goes on, whatever the colour scale.
fn draw_streamlines(
    pix: &mut Pixmap,
    view: &View,
    s: &Solver,
    (max_speed, peak): (f32, f32),
    ui: f32,
) {
    let spacing = 16.0 * ui; // pixels between lines
    let (w, h) = (pix.width() as f32, pix.height() as f32);
    let cell = spacing * 0.5;
    let (gw, gh) = ((w / cell) as usize + 1, (h / cell) as usize + 1);
    let mut taken = vec![false; gw * gh];
    let occupied = |taken: &[bool], p: (f32, f32)| {
        let (i, j) = ((p.0 / cell) as usize, (p.1 / cell) as usize);
        i >= gw || j >= gh || taken[j * gw + i]
    };
    let min = view.min;
    let step_m = 0.6 * s.hx.min(s.hz);
    // Shaped once for every line (over terrain, `velocity_at` shapes the field each call).
    let wind = s.wind_sampler();
    let speed = |p: [f32; 2]| {
        let v = wind.at(p);
        (v, crate::num::hypot(v[0], v[1]))
    };
    let inside = |p: [f32; 2]| s.cell_at(p).is_some_and(|(i, j)| !s.is_solid(i, j));
    let mut seeds = Vec::new();
    let mut rng = 0x9e37_79b9u32;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 17;
        rng ^= rng << 5;
        (rng >> 8) as f32 / 16_777_216.0
    };
    let size = [s.hx * s.nx as f32, s.hz * s.ny as f32];
    let n_x = (size[0] * view.scale / spacing) as usize + 1;
    let n_z = (size[1] * view.scale / spacing) as usize + 1;
    for j in 0..n_z {
        for i in 0..n_x {
            seeds.push([
                min[0] + (i as f32 + next()) * spacing / view.scale,
                min[1] + (j as f32 + next()) * spacing / view.scale,
            ]);
        }
    }
    // Faster places first, so the strongest flow gets the continuous lines.
    seeds.sort_by(|a, b| speed(*b).1.total_cmp(&speed(*a).1));
    let cutoff = peak * 0.03;
    for seed in seeds {
        if !inside(seed) || speed(seed).1 < cutoff || occupied(&taken, view.px(seed)) {
            continue;
        }
        let mut line_pts: Vec<([f32; 2], f32)> = Vec::new();
        for dir in [-1.0f32, 1.0] {
            let mut p = seed;
            let mut pts = Vec::new();
            for _ in 0..600 {
                let (v, sp) = speed(p);
                if sp < cutoff {
                    break;
                }
                let mid = [
                    p[0] + dir * v[0] / sp * step_m * 0.5,
                    p[1] + dir * v[1] / sp * step_m * 0.5,
                ];
                let (vm, spm) = speed(mid);
                if spm < cutoff {
                    break;
                }
                let q = [
                    p[0] + dir * vm[0] / spm * step_m,
                    p[1] + dir * vm[1] / spm * step_m,
                ];
                if !inside(q) {
                    break;
                }
                let qp = view.px(q);
                if occupied(&taken, qp) && !pts.is_empty() {
                    break;
                }
                pts.push((q, spm));
                p = q;
            }
            if dir < 0.0 {
                pts.reverse();
                line_pts.extend(pts);
                line_pts.push((seed, speed(seed).1));
            } else {
                line_pts.extend(pts);
            }
        }
        if line_pts.len() < 6 {
            continue;
        }
        for (p, _) in &line_pts {
            let (x, y) = view.px(*p);
            let (i, j) = ((x / cell) as usize, (y / cell) as usize);
            if i < gw && j < gh {
                taken[j * gw + i] = true;
            }
        }
        // Draw segment by segment, coloured by speed, faded at the ends.
        let n = line_pts.len();
        for k in 1..n {
            let (a, sa) = line_pts[k - 1];
            let (b, _) = line_pts[k];
            let t = (sa / max_speed).min(1.0);
            let fade = ((k.min(n - k) as f32) / 12.0).min(1.0);
            let c = speed_rgb(t.sqrt());
            let stroke = Stroke {
                width: (1.0 + 1.6 * t) * ui,
                line_cap: LineCap::Round,
                ..Default::default()
            };
            line(
                pix,
                view.px(a),
                view.px(b),
                &paint(rgba(c, (60.0 + 190.0 * fade) as u8)),
                &stroke,
            );
        }
        // A chevron in the middle shows which way the wind blows.
        let (a, _) = line_pts[n / 2 - 1];
        let (b, sb) = line_pts[n / 2 + 1];
        chevron(
            pix,
            view.px(a),
            view.px(b),
            5.0 * ui,
            rgba(speed_rgb((sb / max_speed).min(1.0).sqrt()), 230),
            ui,
        );
    }
}

fn chevron(pix: &mut Pixmap, a: (f32, f32), b: (f32, f32), size: f32, c: Color, ui: f32) {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = crate::num::hypot(dx, dy);
    if len < 1e-3 {
        return;
    }
    let (ux, uy) = (dx / len, dy / len);
    let tip = b;
    let mut pb = PathBuilder::new();
    pb.move_to(
        tip.0 - ux * size - uy * size * 0.6,
        tip.1 - uy * size + ux * size * 0.6,
    );
    pb.line_to(tip.0, tip.1);
    pb.line_to(
        tip.0 - ux * size + uy * size * 0.6,
        tip.1 - uy * size - ux * size * 0.6,
    );
    if let Some(path) = pb.finish() {
        let s = Stroke {
            width: 1.5 * ui,
            line_cap: LineCap::Round,
            line_join: LineJoin::Round,
            ..Default::default()
        };
        pix.stroke_path(&path, &paint(c), &s, Transform::identity(), None);
    }
}

fn draw_obstacles(pix: &mut Pixmap, view: &View, layout: &Layout, ui: f32) {
    let fill = paint(Color::from_rgba8(128, 118, 106, 255));
    let edge = paint(Color::from_rgba8(30, 28, 26, 255));
    let stroke = Stroke {
        width: 1.5 * ui,
        ..Default::default()
    };
    for o in &layout.obstacles {
        let path = match &o.shape {
            Shape::Circle { center, radius } => {
                let (x, y) = view.px(*center);
                PathBuilder::from_circle(x, y, radius * view.scale)
            }
            Shape::Polygon { points } => {
                let mut pb = PathBuilder::new();
                for (k, p) in points.iter().enumerate() {
                    let (x, y) = view.px(*p);
                    if k == 0 {
                        pb.move_to(x, y);
                    } else {
                        pb.line_to(x, y);
                    }
                }
                pb.close();
                pb.finish()
            }
            Shape::Mask { .. } => {
                // Its solid pixels as rectangles, at up to 1024 a side.
                let mut pb = PathBuilder::new();
                for [a, b] in o.shape.mask_runs(layout.bounds(), 1024) {
                    let ((x0, y0), (x1, y1)) = (view.px(a), view.px(b));
                    if let Some(r) =
                        tiny_skia::Rect::from_ltrb(x0.min(x1), y0.min(y1), x0.max(x1), y0.max(y1))
                    {
                        pb.push_rect(r);
                    }
                }
                pb.finish()
            }
        };
        if let Some(path) = path {
            pix.fill_path(&path, &fill, FillRule::Winding, Transform::identity(), None);
            // A mask's rows are filled only: an outline per row would stripe it.
            if !matches!(o.shape, Shape::Mask { .. }) {
                pix.stroke_path(&path, &edge, &stroke, Transform::identity(), None);
            }
        }
    }
}

fn draw_trees(pix: &mut Pixmap, view: &View, layout: &Layout, ui: f32) {
    let blue = [70, 160, 255];
    for tree in &layout.trees {
        let alpha = if tree.enabled { 255 } else { 110 };
        for (parent, child, _) in tree.root.arrows() {
            let a = view.px(parent.pos);
            let b = view.px(child.pos);
            let width = (1.5 + child.strength * 0.35).clamp(1.5, 9.0) * ui;
            arrow(pix, a, b, width, rgba(blue, alpha), ui);
        }
        for n in tree.root.iter() {
            let (x, y) = view.px(n.pos);
            let outline = Stroke {
                width: 1.5 * ui,
                ..Default::default()
            };
            let black = paint(Color::from_rgba8(0, 0, 0, 255));
            if n.id == tree.root.id {
                let r = 7.0 * ui;
                // A point far off the picture (allowed: arrows may start outside the world)
                // may round to an empty square; it would not be seen anyway.
                let Some(rect) = Rect::from_ltrb(x - r, y - r, x + r, y + r) else {
                    continue;
                };
                pix.fill_rect(
                    rect,
                    &paint(Color::from_rgba8(235, 90, 60, alpha)),
                    Transform::identity(),
                    None,
                );
                pix.stroke_path(
                    &PathBuilder::from_rect(rect),
                    &black,
                    &outline,
                    Transform::identity(),
                    None,
                );
            } else if let Some(c) = PathBuilder::from_circle(x, y, 5.5 * ui) {
                pix.fill_path(
                    &c,
                    &paint(Color::from_rgba8(250, 250, 250, alpha)),
                    FillRule::Winding,
                    Transform::identity(),
                    None,
                );
                pix.stroke_path(&c, &black, &outline, Transform::identity(), None);
            }
        }
    }
}

fn arrow(pix: &mut Pixmap, a: (f32, f32), b: (f32, f32), width: f32, c: Color, ui: f32) {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = crate::num::hypot(dx, dy);
    if len < 1.0 {
        return;
    }
    let (ux, uy) = (dx / len, dy / len);
    let head = (width * 2.8 + 6.0 * ui).min(len * 0.6);
    let base = (b.0 - ux * head, b.1 - uy * head);
    let shaft = Stroke {
        width,
        line_cap: LineCap::Round,
        ..Default::default()
    };
    line(pix, a, base, &paint(c), &shaft);
    let (nx, ny) = (-uy * head * 0.55, ux * head * 0.55);
    let mut pb = PathBuilder::new();
    pb.move_to(b.0, b.1);
    pb.line_to(base.0 + nx, base.1 + ny);
    pb.line_to(base.0 - nx, base.1 - ny);
    pb.close();
    if let Some(p) = pb.finish() {
        pix.fill_path(
            &p,
            &paint(c),
            FillRule::Winding,
            Transform::identity(),
            None,
        );
    }
}

fn legend(
    pix: &mut Pixmap,
    font: &FontRef<'_>,
    at: (f32, f32),
    w: f32,
    h: f32,
    max_speed: f32,
    ui: f32,
) {
    let (x, y) = at;
    let n = 64;
    for k in 0..n {
        let t = k as f32 / (n - 1) as f32;
        let Some(r) = Rect::from_xywh(
            x + w * k as f32 / n as f32,
            y + 18.0 * ui,
            w / n as f32 + 0.6,
            h,
        ) else {
            continue;
        };
        pix.fill_rect(
            r,
            &paint(rgba(speed_rgb(t.sqrt()), 255)),
            Transform::identity(),
            None,
        );
    }
    let grey = [200, 200, 200];
    text(
        pix,
        font,
        13.0 * ui,
        (x, y + 12.0 * ui),
        "wind speed (m/s)",
        grey,
    );
    // Position t along the bar is speed t·max (coloured as the streamlines are).
    for t in [0.0f32, 0.5, 1.0] {
        let s = format!("{:.1}", max_speed * t);
        let tw = text_width(font, 12.0 * ui, &s);
        let px = x + w * t - tw * t;
        text(
            pix,
            font,
            12.0 * ui,
            (px, y + 18.0 * ui + h + 14.0 * ui),
            &s,
            grey,
        );
    }
}

fn scale_bar(pix: &mut Pixmap, font: &FontRef<'_>, view: &View, right_top: (f32, f32), ui: f32) {
    let metres = nice_step(140.0 * ui / view.scale);
    let len = metres * view.scale;
    let (x1, y) = (right_top.0, right_top.1 + 24.0 * ui);
    let x0 = x1 - len;
    let p = paint(Color::from_rgba8(230, 230, 230, 255));
    let s = Stroke {
        width: 2.0 * ui,
        ..Default::default()
    };
    line(pix, (x0, y), (x1, y), &p, &s);
    line(pix, (x0, y - 5.0 * ui), (x0, y + 5.0 * ui), &p, &s);
    line(pix, (x1, y - 5.0 * ui), (x1, y + 5.0 * ui), &p, &s);
    let label = format!("{metres} m");
    let tw = text_width(font, 13.0 * ui, &label);
    text(
        pix,
        font,
        13.0 * ui,
        (x0 + (len - tw) / 2.0, y - 8.0 * ui),
        &label,
        [230, 230, 230],
    );
}

fn text_width(font: &FontRef<'_>, size: f32, s: &str) -> f32 {
    let f = font.as_scaled(PxScale::from(size));
    s.chars().map(|c| f.h_advance(f.glyph_id(c))).sum()
}

/// Draws `s` with its baseline at `at`, alpha-blended into the pixmap.
fn text(pix: &mut Pixmap, font: &FontRef<'_>, size: f32, at: (f32, f32), s: &str, colour: [u8; 3]) {
    let scaled = font.as_scaled(PxScale::from(size));
    let (w, h) = (pix.width() as i32, pix.height() as i32);
    let mut x = at.0;
    let pixels = pix.pixels_mut();
    for c in s.chars() {
        let id = scaled.glyph_id(c);
        let glyph = id.with_scale_and_position(PxScale::from(size), ab_glyph::point(x, at.1));
        x += scaled.h_advance(id);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let bounds = outline.px_bounds();
        outline.draw(|gx, gy, cov| {
            let (px, py) = (
                bounds.min.x as i32 + gx as i32,
                bounds.min.y as i32 + gy as i32,
            );
            if px < 0 || py < 0 || px >= w || py >= h {
                return;
            }
            let p = &mut pixels[(py * w + px) as usize];
            let a = cov.clamp(0.0, 1.0);
            let blend = |dst: u8, src: u8| (f32::from(dst) * (1.0 - a) + f32::from(src) * a) as u8;
            let d = p.demultiply();
            *p = tiny_skia::ColorU8::from_rgba(
                blend(d.red(), colour[0]),
                blend(d.green(), colour[1]),
                blend(d.blue(), colour[2]),
                d.alpha().max((a * 255.0) as u8),
            )
            .premultiply();
        });
    }
}
