//! The Presets menu: windloom's wind and grass presets and the user's own (saved in their
//! config folder), each applied as one undo step.

use super::{EditorApp, Sel};
use crate::doc::presets;
use crate::io::presets::{self as user, Kind};
use eframe::egui;

/// The Presets menu's state: where the user's presets live.
pub struct PresetsState {
    pub folder: Option<std::path::PathBuf>,
}

impl Default for PresetsState {
    fn default() -> Self {
        Self {
            folder: user::folder(),
        }
    }
}

pub fn presets_menu(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui) {
    ui.menu_button("Wind", |ui| {
        ui.weak("Replaces the ambient layers, adds its trees");
        for name in presets::WIND {
            if ui.button(name).clicked()
                && let Some(p) = presets::wind(name, &app.doc)
            {
                apply(app, ctx, Kind::Wind, name, p);
            }
        }
        yours(app, ctx, ui, Kind::Wind);
    });
    ui.menu_button("Grass", |ui| {
        ui.weak("Blades and colours; keeps the density map");
        for name in presets::GRASS {
            if ui.button(name).clicked()
                && let Some(grass) = presets::grass(name)
            {
                let mut p = presets::grass_of(&app.doc);
                p.grass = grass;
                apply(app, ctx, Kind::Grass, name, p);
            }
        }
        yours(app, ctx, ui, Kind::Grass);
    });
}

/// Applies a preset (a layout holding it) as one edit.
fn apply(
    app: &mut EditorApp,
    ctx: &egui::Context,
    kind: Kind,
    name: &str,
    preset: crate::doc::Layout,
) {
    let edit = match kind {
        Kind::Wind => presets::apply_wind(&app.doc, preset),
        Kind::Grass => presets::apply_grass(&app.doc, preset.grass),
    };
    if app.edit(ctx, edit) {
        if kind == Kind::Wind {
            app.selection.retain(|s| !matches!(s, Sel::Ambient(_)));
        }
        app.say(
            ctx,
            format!("Applied the {} preset “{name}”", kind.folder()),
        );
    }
}

/// The user's presets of `kind` (apply, delete), and saving this layout's as a new one.
fn yours(app: &mut EditorApp, ctx: &egui::Context, ui: &mut egui::Ui, kind: Kind) {
    ui.separator();
    let Some(folder) = app.presets.folder.clone() else {
        ui.weak("No config folder: your own presets cannot be kept");
        return;
    };
    let mine = user::list(&folder, kind);
    if mine.is_empty() {
        ui.weak("Your presets appear here");
    }
    for (name, path) in mine {
        ui.horizontal(|ui| {
            if ui
                .small_button("×")
                .on_hover_text("Delete this preset")
                .clicked()
            {
                match user::delete(&path) {
                    Ok(()) => app.say(ctx, format!("Deleted the preset “{name}”")),
                    Err(e) => app.say(ctx, e.to_string()),
                }
            }
            if ui
                .button(&name)
                .on_hover_text(path.display().to_string())
                .clicked()
            {
                match user::read(&path) {
                    Ok(p) => apply(app, ctx, kind, &name, p),
                    Err(e) => app.say(ctx, e.to_string()),
                }
            }
        });
    }
    let what = match kind {
        Kind::Wind => {
            "Saves the ambient layers and the selected trees (all trees when none is selected)"
        }
        Kind::Grass => "Saves the grass settings (not the density map)",
    };
    if ui.button("Save as preset…").on_hover_text(what).clicked() {
        app.dialog = Some(super::Dialog::SavePreset {
            kind,
            name: String::new(),
            refused: None,
        });
    }
}

/// The Save as preset dialog's body: the name, Save and Cancel; whether it stays open.
pub fn save_dialog(
    app: &mut EditorApp,
    ctx: &egui::Context,
    ui: &mut egui::Ui,
    kind: Kind,
    name: &mut String,
    refused: &mut Option<String>,
) -> bool {
    ui.heading(format!("Save this {} as a preset", kind.folder()));
    ui.label(match kind {
        Kind::Wind => {
            "The ambient layers and the selected trees (all trees when none is selected)."
        }
        Kind::Grass => "The grass settings (not the density map).",
    });
    let field = ui.add(egui::TextEdit::singleline(name).hint_text("preset name"));
    if !field.has_focus() && name.is_empty() {
        field.request_focus();
    }
    let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
    let mut keep = true;
    ui.horizontal(|ui| {
        if ui.button("Save").clicked() || enter {
            let Some(folder) = app.presets.folder.clone() else {
                keep = false;
                return;
            };
            let preset = match kind {
                Kind::Wind => presets::wind_of(&app.doc, &selected_trees(app)),
                Kind::Grass => presets::grass_of(&app.doc),
            };
            let name = name.trim().to_string();
            match user::save(&folder, kind, &name, &preset) {
                Ok(path) => {
                    app.say(
                        ctx,
                        format!("Saved the preset “{name}” to {}", path.display()),
                    );
                    keep = false;
                }
                Err(e) => *refused = Some(e.to_string()),
            }
        }
        if ui.button("Cancel").clicked() {
            keep = false;
        }
    });
    // Why a name was refused, in the dialog, where the eye is.
    if let Some(why) = refused {
        ui.colored_label(ui.visuals().warn_fg_color, why.as_str());
    }
    keep
}

/// The trees the selection touches.
fn selected_trees(app: &EditorApp) -> Vec<u32> {
    let mut ids: Vec<u32> = (app.selection.iter())
        .filter_map(|s| match *s {
            Sel::Tree(id) => Some(id),
            Sel::Node(n) => (app.doc.trees.iter())
                .find(|t| t.root.find(n).is_some())
                .map(|t| t.id),
            _ => None,
        })
        .collect();
    ids.sort();
    ids.dedup();
    ids
}
