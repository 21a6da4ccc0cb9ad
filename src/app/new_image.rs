//! A mask obstacle or a density map made in the editor, for a level built from nothing: blank
//! at the world's size (open ground; grass everywhere), or thresholded from a picture of the
//! level (its backdrop by default, lined up where the backdrop lies), previewed before it is
//! made. The new image is unsaved work until Save writes it beside the layout.

use super::{EditorApp, Sel, Tool};
use crate::doc::{self, Edit, MaskPixels, Shape, raster};
use eframe::egui;
use std::sync::Arc;

/// What is made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A new mask obstacle.
    Mask,
    /// The grass's density map (in place of any it has).
    Density,
}

/// The New mask / New density map dialog's state.
pub struct NewImage {
    pub kind: Kind,
    /// From a picture (else blank).
    pub from_picture: bool,
    /// The picture's path, relative to the layout's folder.
    pub picture: String,
    /// Lit (open ground, grass) where the picture's luminance is at least this.
    pub threshold: f32,
    pub invert: bool,
    /// A blank image's pixels a metre.
    pub per_metre: f32,
    /// The new image's file name, relative to the layout's folder.
    pub name: String,
    /// The picture as last read: its path, and its pixels or why not.
    picture_read: Option<(String, Result<Arc<image::RgbaImage>, String>)>,
    /// The preview, and what it was drawn for.
    preview: Option<(PreviewKey, egui::TextureHandle)>,
}

type PreviewKey = (String, u32, bool);

impl NewImage {
    /// The dialog for `kind` over `app`'s layout: from the backdrop when there is one, else
    /// blank; a free file name named after the layout.
    pub fn new(app: &EditorApp, kind: Kind) -> Self {
        let stem = app
            .doc
            .path()
            .and_then(|p| p.file_stem())
            .map_or("level".to_owned(), |s| s.to_string_lossy().into_owned());
        let wanted = match kind {
            Kind::Mask => format!("{stem}-mask.png"),
            Kind::Density => format!("{stem}-grass.png"),
        };
        let base = app.doc.base();
        let named: Vec<String> = doc::portable::files(&app.doc)
            .iter()
            .map(|(_, n, _)| (*n).to_owned())
            .collect();
        let free = |n: &str| {
            !named.iter().any(|m| m == n) && !crate::io::images::file_key(&base, n).exists()
        };
        let name = if free(&wanted) {
            wanted
        } else {
            crate::io::images::free_name(&wanted, free)
        };
        let backdrop = app.doc.world.map.as_ref().map(|m| m.image.clone());
        Self {
            kind,
            from_picture: backdrop.is_some(),
            picture: backdrop.unwrap_or_default(),
            threshold: 0.5,
            invert: false,
            per_metre: 4.0,
            name,
            picture_read: None,
            preview: None,
        }
    }

    /// The picture, read once per path.
    fn picture(&mut self, base: &std::path::Path) -> Result<Arc<image::RgbaImage>, String> {
        let stale = self
            .picture_read
            .as_ref()
            .is_none_or(|(p, _)| *p != self.picture);
        if stale {
            let read = crate::io::load_picture(base, &self.picture, "picture")
                .map(Arc::new)
                .map_err(|e| e.to_string());
            // A new picture starts at the threshold that best splits it.
            if let Ok(p) = &read {
                self.threshold = raster::auto_threshold(p.as_raw());
            }
            self.picture_read = Some((self.picture.clone(), read));
        }
        self.picture_read.as_ref().expect("read above").1.clone()
    }

    /// The image this dialog makes now, and where it lies (`None`: over the world).
    pub fn image(
        &mut self,
        layout: &doc::Layout,
        base: &std::path::Path,
    ) -> Result<(doc::MaskImage, Option<[doc::Vec2; 2]>), String> {
        if !self.from_picture {
            let (w, h) = raster::size_for(layout.world.size, self.per_metre);
            return Ok((raster::blank(w, h, u16::MAX), None));
        }
        if self.picture.trim().is_empty() {
            return Err("choose a picture".into());
        }
        let p = self.picture(base)?;
        let image = raster::threshold(
            p.as_raw(),
            p.width(),
            p.height(),
            self.threshold,
            self.invert,
            (u16::MAX, 0),
        );
        // The backdrop's picture lies where the backdrop does.
        let rect = layout
            .world
            .map
            .as_ref()
            .filter(|m| m.image == self.picture)
            .and_then(|m| m.rect);
        Ok((image, rect))
    }

    /// Why the file name cannot be used, if it cannot.
    fn name_problem(&self, app: &EditorApp) -> Option<String> {
        let name = self.name.trim();
        if name.is_empty() {
            return Some("name the new image's file".into());
        }
        let lower = name.to_ascii_lowercase();
        if !lower.ends_with(".png") && !lower.ends_with(".exr") {
            return Some("the file name ends in .png or .exr".into());
        }
        if let Some(why) = doc::portable::path_problem(name) {
            return Some(why);
        }
        if doc::portable::files(&app.doc)
            .iter()
            .any(|(_, n, _)| *n == name)
        {
            return Some(format!("the layout names {name} already"));
        }
        if crate::io::images::file_key(&app.doc.base(), name).exists() {
            return Some(format!(
                "{name} exists beside the layout: choose another name"
            ));
        }
        None
    }
}

/// The dialog's contents; whether it stays open.
pub fn dialog(
    app: &mut EditorApp,
    ctx: &egui::Context,
    ui: &mut egui::Ui,
    d: &mut NewImage,
) -> bool {
    let what = match d.kind {
        Kind::Mask => "New mask obstacle",
        Kind::Density => "New density map",
    };
    ui.heading(what);
    let (blank_text, lit, dark) = match d.kind {
        Kind::Mask => (
            "Blank: open ground everywhere, to paint walls on",
            "open",
            "solid",
        ),
        Kind::Density => (
            "Blank: grass everywhere, to paint roads and water out of",
            "grass",
            "no grass",
        ),
    };
    ui.radio_value(&mut d.from_picture, false, blank_text);
    ui.radio_value(
        &mut d.from_picture,
        true,
        "From a picture of the level, by a threshold",
    );
    let base = app.doc.base();
    egui::Grid::new("new image").num_columns(2).show(ui, |ui| {
        if d.from_picture {
            let l = ui.label("Picture");
            ui.horizontal(|ui| {
                ui.add(egui::TextEdit::singleline(&mut d.picture).desired_width(220.0))
                    .labelled_by(l.id)
                    .on_hover_text("PNG, JPEG or EXR, relative to the layout's folder (the backdrop's by default)");
                if ui.small_button("…").on_hover_text("Choose the picture").clicked()
                    && let Some(p) = rfd::FileDialog::new()
                        .add_filter("PNG, JPEG or EXR", &["png", "jpg", "jpeg", "exr", "PNG", "JPG", "JPEG", "EXR"])
                        .set_directory(&base)
                        .pick_file()
                {
                    d.picture = crate::io::images::stored_name(&p, &base);
                }
            });
            ui.end_row();
            let l = ui.label("Threshold");
            ui.horizontal(|ui| {
                ui.add(egui::Slider::new(&mut d.threshold, 0.0..=1.0))
                    .labelled_by(l.id)
                    .on_hover_text(format!(
                        "{lit} where the picture is at least this light, {dark} where darker"
                    ));
                if ui
                    .small_button("Auto")
                    .on_hover_text("The threshold that best splits the picture into dark and light")
                    .clicked()
                    && let Some((_, Ok(p))) = &d.picture_read
                {
                    d.threshold = raster::auto_threshold(p.as_raw());
                }
            });
            ui.end_row();
            let l = ui.label("Inverted");
            ui.checkbox(&mut d.invert, format!("{lit} where darker"))
                .labelled_by(l.id);
            ui.end_row();
        } else {
            let l = ui.label("Pixels a metre");
            ui.add(egui::DragValue::new(&mut d.per_metre).range(0.1..=32.0).speed(0.1))
                .labelled_by(l.id)
                .on_hover_text("How fine it can be painted; the image covers the whole world");
            ui.end_row();
        }
        let l = ui.label("File name");
        ui.add(egui::TextEdit::singleline(&mut d.name).desired_width(220.0))
            .labelled_by(l.id)
            .on_hover_text("Written beside the layout on Save (PNG, or EXR)");
        ui.end_row();
    });
    let made = d.image(&app.doc, &base);
    match &made {
        Ok((image, _)) => {
            ui.weak(format!(
                "{} × {} pixels; the light part is {lit}, the dark {dark}",
                image.width, image.height
            ));
            preview(ui, d, image);
        }
        Err(e) => {
            ui.colored_label(ui.visuals().warn_fg_color, e);
        }
    }
    let problem = d.name_problem(app);
    if let Some(p) = &problem {
        ui.colored_label(ui.visuals().warn_fg_color, p);
    }
    let mut keep = true;
    ui.horizontal(|ui| {
        let can = made.is_ok() && problem.is_none();
        if ui.add_enabled(can, egui::Button::new("Create")).clicked()
            && let Ok((image, rect)) = made
        {
            create(app, ctx, d, image, rect);
            keep = false;
        }
        if ui.button("Cancel").clicked() {
            keep = false;
        }
    });
    keep
}

/// A small picture of what will be made: dark where the image is dark (solid, no grass).
fn preview(ui: &mut egui::Ui, d: &mut NewImage, image: &doc::MaskImage) {
    let key = (
        if d.from_picture {
            d.picture.clone()
        } else {
            String::new()
        },
        (d.threshold * 1000.0) as u32
            + if d.from_picture {
                0
            } else {
                (d.per_metre * 10.0) as u32
            },
        d.invert,
    );
    let stale = d.preview.as_ref().is_none_or(|(k, _)| *k != key);
    let kind = d.kind;
    if stale {
        let f = (256.0 / image.width.max(image.height) as f32).min(1.0);
        let (w, h) = (
            ((image.width as f32 * f).round() as usize).max(1),
            ((image.height as f32 * f).round() as usize).max(1),
        );
        let scale = (
            image.width as f32 / w as f32,
            image.height as f32 / h as f32,
        );
        let pixels: Vec<egui::Color32> = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| {
                let sx = ((x as f32 + 0.5) * scale.0) as usize;
                let sy = ((y as f32 + 0.5) * scale.1) as usize;
                let l = image.luminance[sy * image.width as usize + sx];
                match (l >= u16::MAX / 2, kind) {
                    (true, Kind::Mask) => egui::Color32::from_gray(200),
                    (false, Kind::Mask) => super::view::OBSTACLE_COLOUR,
                    (true, Kind::Density) => egui::Color32::from_rgb(96, 150, 80),
                    (false, Kind::Density) => egui::Color32::from_rgb(110, 80, 50),
                }
            })
            .collect();
        let img = egui::ColorImage::new([w, h], pixels);
        let tex = ui
            .ctx()
            .load_texture("new image preview", img, egui::TextureOptions::NEAREST);
        d.preview = Some((key, tex));
    }
    if let Some((_, tex)) = &d.preview {
        let size = tex.size_vec2();
        let fit = (240.0 / size.x).min(160.0 / size.y);
        ui.image((tex.id(), size * fit));
    }
}

/// Adds what the dialog made, as one undo step, and picks up the paint tool on it.
fn create(
    app: &mut EditorApp,
    ctx: &egui::Context,
    d: &NewImage,
    image: doc::MaskImage,
    rect: Option<[doc::Vec2; 2]>,
) {
    let pixels = MaskPixels::Loaded(Arc::new(image));
    let name = d.name.trim().to_owned();
    match d.kind {
        Kind::Mask => {
            let id = app.doc.next_id();
            let obstacle = doc::Obstacle {
                id,
                name: format!("Mask {}", app.doc.obstacles.len() + 1),
                shape: Shape::Mask {
                    image: name.clone(),
                    threshold: 0.5,
                    invert: false,
                    rect,
                    pixels,
                },
                locked: false,
                hidden: false,
            };
            let edit = Edit::Named(
                "New mask",
                Box::new(Edit::AddObstacle {
                    index: usize::MAX,
                    obstacle,
                }),
            );
            if app.edit(ctx, edit) {
                app.selection = vec![Sel::Obstacle(id)];
                app.tool = Tool::Paint;
                app.say(
                    ctx,
                    format!("New mask {name}: paint it solid (B), Shift erases; Save writes it"),
                );
            }
        }
        Kind::Density => {
            let mut g = app.doc.grass.clone();
            g.density_map = Some(doc::DensityMap {
                image: name.clone(),
                rect,
                pixels,
            });
            if app.edit(
                ctx,
                Edit::Named("New density map", Box::new(Edit::SetGrass(g))),
            ) {
                app.selection.clear();
                app.tool = Tool::Paint;
                app.say(
                    ctx,
                    format!(
                        "New density map {name}: paint grass (B), Shift clears it; Save writes it"
                    ),
                );
            }
        }
    }
}
