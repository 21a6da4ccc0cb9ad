//! The editor window (eframe). For now a read-only view of the layout: the map with its
//! obstacles and arrow trees, and a summary panel. Authoring arrives with the editor issue.

use crate::doc::{Layout, Shape};
use eframe::egui::{self, Color32, Pos2, Rect, Stroke, Vec2};
use std::path::PathBuf;

/// The editor application state.
pub struct EditorApp {
    pub doc: Layout,
    pub path: Option<PathBuf>,
}

impl EditorApp {
    pub fn new(doc: Layout, path: Option<PathBuf>) -> Self {
        Self { doc, path }
    }

    fn title(&self) -> String {
        let file = self.path.as_ref().and_then(|p| p.file_name()).map_or_else(
            || "default layout".to_string(),
            |f| f.to_string_lossy().into_owned(),
        );
        format!("{file} — windloom")
    }
}

impl eframe::App for EditorApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        ui.ctx()
            .send_viewport_cmd(egui::ViewportCommand::Title(self.title()));
        egui::Panel::left("summary")
            .resizable(true)
            .default_size(220.0)
            .show(ui, |ui| summary(ui, &self.doc));
        egui::CentralPanel::default().show(ui, |ui| map_view(ui, &self.doc));
    }
}

fn summary(ui: &mut egui::Ui, doc: &Layout) {
    ui.heading(&doc.name);
    ui.label(format!(
        "World {} × {} m, grid {} × {}",
        doc.world.size[0], doc.world.size[1], doc.world.grid[0], doc.world.grid[1]
    ));
    ui.separator();
    ui.strong("Trees");
    for t in &doc.trees {
        ui.label(format!(
            "{} {} ({} points)",
            if t.enabled { "●" } else { "○" },
            t.name,
            t.root.count()
        ));
    }
    ui.strong("Obstacles");
    for o in &doc.obstacles {
        ui.label(&o.name);
    }
    ui.strong("Ambient");
    for a in &doc.ambient {
        ui.label(format!("{} ({})", a.name, a.kind.type_name()));
    }
}

/// World → screen mapping that fits the world rectangle into `rect`, keeping its aspect.
pub struct MapTransform {
    pub origin: Pos2,
    pub scale: f32,
    pub world_min: [f32; 2],
}

impl MapTransform {
    pub fn fit(doc: &Layout, rect: Rect) -> Self {
        let (min, _) = doc.bounds();
        let size = doc.world.size;
        let scale = (rect.width() / size[0]).min(rect.height() / size[1]) * 0.95;
        let used = Vec2::new(size[0] * scale, size[1] * scale);
        Self {
            origin: rect.center() - used * 0.5,
            scale,
            world_min: min,
        }
    }

    pub fn to_screen(&self, p: [f32; 2]) -> Pos2 {
        self.origin
            + Vec2::new(
                (p[0] - self.world_min[0]) * self.scale,
                (p[1] - self.world_min[1]) * self.scale,
            )
    }
}

fn map_view(ui: &mut egui::Ui, doc: &Layout) {
    let (rect, _) = ui.allocate_exact_size(ui.available_size(), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    let t = MapTransform::fit(doc, rect);
    let (min, max) = doc.bounds();
    let world = Rect::from_min_max(t.to_screen(min), t.to_screen(max));
    painter.rect_filled(world, 2.0, Color32::from_rgb(46, 62, 40));
    // A 10 m grid.
    let grid = Stroke::new(1.0, Color32::from_white_alpha(18));
    let mut x = (min[0] / 10.0).ceil() * 10.0;
    while x <= max[0] {
        painter.line_segment([t.to_screen([x, min[1]]), t.to_screen([x, max[1]])], grid);
        x += 10.0;
    }
    let mut z = (min[1] / 10.0).ceil() * 10.0;
    while z <= max[1] {
        painter.line_segment([t.to_screen([min[0], z]), t.to_screen([max[0], z])], grid);
        z += 10.0;
    }
    let rock = Color32::from_rgb(120, 110, 100);
    for o in &doc.obstacles {
        match &o.shape {
            Shape::Circle { center, radius } => {
                painter.circle_filled(t.to_screen(*center), radius * t.scale, rock);
            }
            Shape::Polygon { points } => {
                let pts = points.iter().map(|p| t.to_screen(*p)).collect();
                painter.add(egui::Shape::convex_polygon(pts, rock, Stroke::NONE));
            }
        }
    }
    let arrow_colour = Color32::from_rgb(90, 170, 255);
    for tree in &doc.trees {
        let alpha = if tree.enabled { 255 } else { 90 };
        let colour = Color32::from_rgba_unmultiplied(90, 170, 255, alpha);
        for (parent, child, _) in tree.root.arrows() {
            let a = t.to_screen(parent.pos);
            let b = t.to_screen(child.pos);
            let width = (1.0 + child.strength / 15.0).min(6.0);
            painter.arrow(a, b - a, Stroke::new(width, colour));
            painter.circle_filled(b, 4.0, arrow_colour);
        }
        let r = t.to_screen(tree.root.pos);
        painter.rect_filled(
            Rect::from_center_size(r, Vec2::splat(10.0)),
            1.0,
            Color32::from_rgb(230, 80, 60),
        );
    }
}

/// Opens the editor window on `doc`.
pub fn run(doc: Layout, path: Option<PathBuf>) -> eframe::Result {
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1280.0, 800.0])
            .with_title("windloom"),
        ..Default::default()
    };
    eframe::run_native(
        "windloom",
        options,
        Box::new(move |_cc| Ok(Box::new(EditorApp::new(doc, path)))),
    )
}
