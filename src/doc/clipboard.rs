//! Copy and paste: a selection becomes a layout of its own (the clipboard's text is that
//! layout's JSON, so a whole layout file copied from a text editor pastes too), and a layout
//! pastes into another as one edit with fresh ids.

use super::edit::Edit;
use super::parse::{Diagnostics, parse, to_json};
use super::types::*;

/// Something a user can pick to copy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Item {
    /// A whole tree.
    Tree(u32),
    /// A node: a root copies its tree; any other node its subtree, with the arrow into it
    /// (the copy's root stands where its parent stood).
    Node(u32),
    Obstacle(u32),
    Ambient(u32),
    Probe(u32),
}

/// The name a copied selection carries.
pub const CLIPBOARD_NAME: &str = "windloom clipboard";

/// The picked items of `layout` as a layout of their own, in the layout's order, its world
/// kept (without the files it names: the map, the terrain, the density map) so that the
/// text reads back as a valid layout. `None` when nothing picked exists.
pub fn copy(layout: &Layout, items: &[Item]) -> Option<Layout> {
    let items: std::collections::HashSet<Item> = items.iter().copied().collect();
    let picked = |item: Item| items.contains(&item);
    let mut out = Layout::new(CLIPBOARD_NAME, layout.world.size, layout.world.grid);
    out.world.origin = layout.world.origin;
    for tree in &layout.trees {
        if picked(Item::Tree(tree.id)) || picked(Item::Node(tree.root.id)) {
            out.trees.push(tree.clone());
            continue;
        }
        // Picked subtrees that are not inside another picked subtree.
        for node in tree.root.iter() {
            if !picked(Item::Node(node.id)) {
                continue;
            }
            let inside = tree
                .root
                .iter()
                .any(|a| a.id != node.id && picked(Item::Node(a.id)) && a.find(node.id).is_some());
            if inside {
                continue;
            }
            let Some((parent, _)) = tree.root.parent_of(node.id) else {
                continue;
            };
            let mut root = Node::new(0, parent.pos, parent.strength, parent.radius);
            root.children.push(node.clone());
            out.trees.push(Tree {
                name: format!("{} part", tree.name),
                root,
                ..tree.clone()
            });
        }
    }
    out.obstacles = (layout.obstacles.iter())
        .filter(|o| picked(Item::Obstacle(o.id)))
        .cloned()
        .collect();
    out.ambient = (layout.ambient.iter())
        .filter(|a| picked(Item::Ambient(a.id)))
        .cloned()
        .collect();
    out.probes = (layout.probes.iter())
        .filter(|p| picked(Item::Probe(p.id)))
        .cloned()
        .collect();
    let empty = out.trees.is_empty()
        && out.obstacles.is_empty()
        && out.ambient.is_empty()
        && out.probes.is_empty();
    (!empty).then_some(out)
}

/// The clipboard's text for a copied selection: the layout's JSON.
pub fn to_text(copied: &Layout) -> String {
    to_json(copied)
}

/// A layout read from the clipboard's text, with every problem found.
pub fn from_text(text: &str) -> Result<Layout, Diagnostics> {
    parse(text)
}

/// What a paste adds: the edit (one undo step) and the new items, to select.
#[derive(Debug, Clone, PartialEq)]
pub struct Pasted {
    pub edit: Edit,
    pub items: Vec<Item>,
}

/// The middle of what `copied` holds on the map (its points, obstacles' centres): where a
/// paste at the pointer puts it. `None` for ambient layers alone.
pub fn centre(copied: &Layout) -> Option<Vec2> {
    let bounds = copied.bounds();
    let points: Vec<Vec2> = (copied.nodes().map(|(_, n)| n.pos))
        .chain(copied.obstacles.iter().map(|o| o.shape.centre(bounds)))
        .chain(copied.probes.iter().map(|p| p.pos))
        .collect();
    let (lo, hi) = points.iter().fold(
        ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        },
    );
    (!points.is_empty()).then(|| [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0])
}

/// `copied` pasted into `layout`, moved by `offset` metres: every tree, node, obstacle and
/// layer takes a fresh id, so pasting twice, or into the layout it came from, never
/// clashes. Pasted items are unlocked and shown. `None` when `copied` holds nothing.
pub fn paste(layout: &Layout, mut copied: Layout, offset: Vec2) -> Option<Pasted> {
    let mut next = layout.next_id();
    let mut fresh = || {
        let id = next;
        next += 1;
        id
    };
    let bounds = copied.bounds();
    let mut edits = Vec::new();
    let mut items = Vec::new();
    for mut tree in copied.trees.drain(..) {
        tree.id = fresh();
        tree.locked = false;
        tree.hidden = false;
        fn renumber(n: &mut Node, fresh: &mut dyn FnMut() -> u32, offset: Vec2) {
            n.id = fresh();
            n.pos = [n.pos[0] + offset[0], n.pos[1] + offset[1]];
            for c in &mut n.children {
                renumber(c, fresh, offset);
            }
        }
        renumber(&mut tree.root, &mut fresh, offset);
        items.push(Item::Tree(tree.id));
        edits.push(Edit::AddTree {
            index: usize::MAX,
            tree,
        });
    }
    for mut obstacle in copied.obstacles.drain(..) {
        obstacle.id = fresh();
        obstacle.locked = false;
        obstacle.hidden = false;
        obstacle.shape.translate(offset, bounds);
        items.push(Item::Obstacle(obstacle.id));
        edits.push(Edit::AddObstacle {
            index: usize::MAX,
            obstacle,
        });
    }
    for mut layer in copied.ambient.drain(..) {
        layer.id = fresh();
        layer.locked = false;
        layer.hidden = false;
        items.push(Item::Ambient(layer.id));
        edits.push(Edit::AddAmbient {
            index: usize::MAX,
            layer,
        });
    }
    for mut probe in copied.probes.drain(..) {
        probe.id = fresh();
        probe.pos = [probe.pos[0] + offset[0], probe.pos[1] + offset[1]];
        items.push(Item::Probe(probe.id));
        edits.push(Edit::AddProbe {
            index: usize::MAX,
            probe,
        });
    }
    (!edits.is_empty()).then_some(Pasted {
        edit: Edit::Named("Paste", Box::new(Edit::Batch(edits))),
        items,
    })
}
