//! Right-click menus, on the map and in the Layers list: what a designer does to the item
//! under the pointer (duplicate, delete, select its tree, lock, hide, focus, copy) or, on
//! empty map, to the layout (select all, paste here, frame all, a root here). Each entry is
//! the editor's own command, so it is one undo step and names its key where it has one.

use super::{EditorApp, Sel, Tool};
use crate::doc::{self, Edit, TreeProps};
use eframe::egui;

/// What a right-click landed on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// An item (a point, tree, obstacle, layer, probe, the backdrop).
    Item(Sel),
    /// Empty map, at this world point.
    Map(doc::Vec2),
}

impl EditorApp {
    /// Whether `s` is hidden and locked (`None`: it has no such flags).
    fn flags(&self, s: Sel) -> Option<(bool, bool)> {
        let d = &self.doc;
        match s {
            Sel::Tree(id) => d
                .trees
                .iter()
                .find(|t| t.id == id)
                .map(|t| (t.hidden, t.locked)),
            Sel::Node(id) => (d.trees.iter())
                .find(|t| t.root.find(id).is_some())
                .map(|t| (t.hidden, t.locked)),
            Sel::Obstacle(id) => (d.obstacles.iter())
                .find(|o| o.id == id)
                .map(|o| (o.hidden, o.locked)),
            Sel::Ambient(id) => (d.ambient.iter())
                .find(|a| a.id == id)
                .map(|a| (a.hidden, a.locked)),
            Sel::Probe(_) | Sel::Backdrop => None,
        }
    }

    /// The edit that gives `s` (a point: its tree) these hidden and locked flags.
    pub fn flags_edit(&self, s: Sel, hidden: bool, locked: bool) -> Option<Edit> {
        let d = &self.doc;
        match s {
            Sel::Tree(_) | Sel::Node(_) => {
                let t = d.trees.iter().find(|t| match s {
                    Sel::Tree(id) => t.id == id,
                    Sel::Node(id) => t.root.find(id).is_some(),
                    _ => false,
                })?;
                let mut p = TreeProps::of(t);
                p.hidden = hidden;
                p.locked = locked;
                Some(Edit::SetTreeProps { id: t.id, props: p })
            }
            Sel::Obstacle(id) => {
                let mut o = d.obstacles.iter().find(|o| o.id == id)?.clone();
                o.hidden = hidden;
                o.locked = locked;
                Some(Edit::SetObstacle { obstacle: o })
            }
            Sel::Ambient(id) => {
                let mut a = d.ambient.iter().find(|a| a.id == id)?.clone();
                a.hidden = hidden;
                a.locked = locked;
                Some(Edit::SetAmbient { layer: a })
            }
            Sel::Probe(_) | Sel::Backdrop => None,
        }
    }

    /// Frames the selection on the map (a point or a probe: the 30 m about it), or the whole
    /// world when nothing is selected (F).
    pub fn focus_selection(&mut self) {
        let rect = self.map.rect;
        let items = super::handles::items(&self.selection);
        let extent = if self.selection == [Sel::Backdrop] {
            let b = self.doc.bounds();
            self.doc.world.map.as_ref().map(|m| {
                let [a, c] = m.placed(b);
                (a, c)
            })
        } else {
            doc::transform::extent(&self.doc, &items)
        };
        self.map.camera = Some(match extent {
            Some((lo, hi)) => super::view::Camera::frame_box(lo, hi, rect, 30.0),
            None => super::view::Camera::frame_all(&self.doc, rect),
        });
    }

    /// Selects everything the map picks: every point of a tree not locked or hidden, every
    /// such obstacle, every probe (Ctrl+A).
    pub fn select_all(&mut self) {
        let d = &self.doc;
        let nodes = (d.trees.iter())
            .filter(|t| t.pickable())
            .flat_map(|t| t.root.iter())
            .map(|n| Sel::Node(n.id));
        let obstacles = (d.obstacles.iter())
            .filter(|o| o.pickable())
            .map(|o| Sel::Obstacle(o.id));
        let probes = d.probes.iter().map(|p| Sel::Probe(p.id));
        self.selection = nodes.chain(obstacles).chain(probes).collect();
    }
}

/// What a menu entry does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    Duplicate,
    Copy,
    Delete,
    SelectTree(u32),
    /// Hidden, locked.
    Flags(bool, bool),
    Focus,
    SelectAll,
    PasteAt(doc::Vec2),
    RootAt(doc::Vec2),
    ProbeAt(doc::Vec2),
    FrameAll,
}

/// The menu's entries for `target` (`ui` is the menu), read from the editor as it is; the
/// entry chosen, to [`apply`].
pub fn entries(app: &EditorApp, ui: &mut egui::Ui, target: Target) -> Option<Action> {
    let ctx = ui.ctx().clone();
    let shortcut =
        |key| ctx.format_shortcut(&egui::KeyboardShortcut::new(egui::Modifiers::COMMAND, key));
    let mut chosen = None;
    let mut entry = |ui: &mut egui::Ui, b: egui::Button<'_>, a: Action| {
        if ui.add(b).clicked() {
            chosen = Some(a);
            ui.close();
        }
    };
    match target {
        Target::Item(s) => {
            // On the rest of the selection too, when it was part of it.
            let several = app.selection.contains(&s) && app.selection.len() > 1;
            let what = if several { "them" } else { "it" };
            if !matches!(s, Sel::Backdrop | Sel::Ambient(_)) {
                let b = egui::Button::new(format!("Duplicate {what}"))
                    .shortcut_text(shortcut(egui::Key::D));
                entry(ui, b, Action::Duplicate);
            }
            if !matches!(s, Sel::Backdrop) {
                let b =
                    egui::Button::new(format!("Copy {what}")).shortcut_text(shortcut(egui::Key::C));
                entry(ui, b, Action::Copy);
            }
            let b = egui::Button::new(format!("Delete {what}")).shortcut_text("Del");
            entry(ui, b, Action::Delete);
            ui.separator();
            if let Sel::Node(id) = s
                && let Some(t) = app.doc.trees.iter().find(|t| t.root.find(id).is_some())
            {
                let b = egui::Button::new(format!("Select its tree, {}", t.name));
                entry(ui, b, Action::SelectTree(t.id));
            }
            if let Some((hidden, locked)) = app.flags(s) {
                let whose = if matches!(s, Sel::Node(_)) {
                    " its tree"
                } else {
                    " it"
                };
                let lock = if locked { "Unlock" } else { "Lock" };
                let b = egui::Button::new(format!("{lock}{whose}"));
                entry(ui, b, Action::Flags(hidden, !locked));
                let hide = if hidden { "Show" } else { "Hide" };
                let b = egui::Button::new(format!("{hide}{whose}"));
                entry(ui, b, Action::Flags(!hidden, locked));
            }
            if !matches!(s, Sel::Ambient(_)) {
                let b = egui::Button::new(format!("Focus on {what}")).shortcut_text("F");
                entry(ui, b, Action::Focus);
            }
        }
        Target::Map(at) => {
            let b = egui::Button::new("Select all").shortcut_text(shortcut(egui::Key::A));
            entry(ui, b, Action::SelectAll);
            let b = egui::Button::new("Paste here").shortcut_text(shortcut(egui::Key::V));
            entry(ui, b, Action::PasteAt(at));
            entry(
                ui,
                egui::Button::new("Add a wind tree's root here"),
                Action::RootAt(at),
            );
            entry(
                ui,
                egui::Button::new("Drop a probe here"),
                Action::ProbeAt(at),
            );
            ui.separator();
            entry(
                ui,
                egui::Button::new("Frame all").shortcut_text("F"),
                Action::FrameAll,
            );
        }
    }
    chosen
}

/// Does what the entry chosen for `target` says, as the editor's own command.
pub fn apply(app: &mut EditorApp, ctx: &egui::Context, target: Target, action: Action) {
    if let Target::Item(s) = target
        && !app.selection.contains(&s)
    {
        app.selection = vec![s];
    }
    match action {
        Action::Duplicate => app.duplicate_selection(ctx),
        Action::Copy => {
            app.copy_selection(ctx);
        }
        Action::Delete => app.delete_selection(ctx, false),
        Action::SelectTree(id) => app.selection = vec![Sel::Tree(id)],
        Action::Flags(hidden, locked) => {
            if let Target::Item(s) = target
                && let Some(e) = app.flags_edit(s, hidden, locked)
            {
                app.edit(ctx, e);
            }
        }
        Action::Focus => app.focus_selection(),
        Action::SelectAll => app.select_all(),
        Action::PasteAt(at) => {
            app.map.paste_at = Some(at);
            ctx.send_viewport_cmd(egui::ViewportCommand::RequestPaste);
        }
        Action::RootAt(at) => {
            if app.add_root(ctx, at) {
                app.tool = Tool::AddArrow;
            }
        }
        Action::ProbeAt(at) => app.add_probe(ctx, at),
        Action::FrameAll => {
            app.selection.clear();
            app.focus_selection();
        }
    }
}
