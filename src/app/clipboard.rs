//! Copy, cut and paste through the system clipboard: the selection goes out as layout JSON
//! (`doc::clipboard`), so it pastes into this layout, another editor's, or a text editor;
//! what comes in is read as a layout, given fresh ids and added as one undo step.

use super::{EditorApp, Sel};
use crate::doc::{self, clipboard};
use eframe::egui;

/// How far (metres, along x and z) each repeated paste in place lands from the one before,
/// so copies do not hide their original.
const PASTE_STEP: f32 = 3.0;

/// What this editor last put on the clipboard: its text, the layout with its images read
/// (a pasted mask takes those pixels when the text comes back), and how often it was pasted
/// in place since.
#[derive(Default)]
pub struct Copied {
    text: String,
    layout: Option<doc::Layout>,
    pastes: u32,
}

fn selection_of(items: &[clipboard::Item], layout: &doc::Layout) -> Vec<Sel> {
    (items.iter())
        .map(|i| match *i {
            // A pasted tree is selected by its root, so it moves at once.
            clipboard::Item::Tree(id) => layout
                .trees
                .iter()
                .find(|t| t.id == id)
                .map_or(Sel::Tree(id), |t| Sel::Node(t.root.id)),
            clipboard::Item::Node(id) => Sel::Node(id),
            clipboard::Item::Obstacle(id) => Sel::Obstacle(id),
            clipboard::Item::Ambient(id) => Sel::Ambient(id),
            clipboard::Item::Probe(id) => Sel::Probe(id),
        })
        .collect()
}

impl EditorApp {
    /// Puts the selection on the system clipboard as layout JSON; `false` when nothing is
    /// selected.
    pub fn copy_selection(&mut self, ctx: &egui::Context) -> bool {
        let Some(copied) = clipboard::copy(&self.doc, &super::handles::items(&self.selection))
        else {
            return false;
        };
        let text = clipboard::to_text(&copied);
        let n = copied.trees.len()
            + copied.obstacles.len()
            + copied.ambient.len()
            + copied.probes.len();
        ctx.copy_text(text.clone());
        self.copied = Copied {
            text,
            layout: Some(copied),
            pastes: 0,
        };
        self.say(
            ctx,
            format!("Copied {n} item{}", if n == 1 { "" } else { "s" }),
        );
        true
    }

    /// Copies the selection, then deletes it.
    pub fn cut_selection(&mut self, ctx: &egui::Context) {
        if self.copy_selection(ctx) {
            self.delete_selection(ctx, true);
        }
    }

    /// Pastes a layout's text (the system clipboard's): at the pointer when it is over the
    /// map, in place otherwise (a step aside for each repeat of this editor's own copy). The
    /// pasted items are selected; text that is no layout is refused with its first problem.
    pub fn paste_text(&mut self, ctx: &egui::Context, text: &str) {
        let ours = text == self.copied.text;
        let mut copied = match (ours, &self.copied.layout) {
            (true, Some(l)) => l.clone(),
            _ => match clipboard::from_text(text) {
                Ok(l) => l,
                Err(e) => {
                    let first = e.0.first().map(|d| d.to_string()).unwrap_or_default();
                    self.say(
                        ctx,
                        format!("the clipboard holds no windloom layout: {first}"),
                    );
                    return;
                }
            },
        };
        // Masks from elsewhere: their images read beside this layout.
        self.doc.read_images(&mut copied);
        let at_pointer = self.map.paste_at.take().or_else(|| {
            self.map.cursor_world.filter(|_| {
                self.map
                    .rect
                    .contains(ctx.pointer_latest_pos().unwrap_or_default())
            })
        });
        let offset = match (at_pointer, clipboard::centre(&copied)) {
            (Some(p), Some(c)) => [p[0] - c[0], p[1] - c[1]],
            _ if ours => {
                self.copied.pastes += 1;
                let d = PASTE_STEP * self.copied.pastes as f32;
                [d, d]
            }
            _ => [0.0, 0.0],
        };
        let Some(pasted) = clipboard::paste(&self.doc, copied, offset) else {
            self.say(ctx, "the clipboard's layout holds nothing to paste");
            return;
        };
        let n = pasted.items.len();
        if self.edit(ctx, pasted.edit) {
            self.selection = selection_of(&pasted.items, &self.doc);
            self.say(
                ctx,
                format!("Pasted {n} item{}", if n == 1 { "" } else { "s" }),
            );
        }
    }

    /// Copy, cut and paste as the window's integration delivers them (it turns Ctrl+C, X
    /// and V into these events, a paste with the clipboard's text), when no text field has
    /// the keyboard.
    pub(super) fn clipboard_events(&mut self, ctx: &egui::Context) {
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let events: Vec<egui::Event> = ctx.input(|i| i.events.clone());
        for e in events {
            match e {
                egui::Event::Copy => {
                    self.copy_selection(ctx);
                }
                egui::Event::Cut => self.cut_selection(ctx),
                egui::Event::Paste(text) => self.paste_text(ctx, &text),
                _ => {}
            }
        }
    }
}
