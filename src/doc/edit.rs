//! Edit commands: every change a user can make to a layout. Applying a command returns its
//! inverse, so [`History`] can undo and redo anything. A command that fails leaves the
//! document untouched.

use super::types::*;
use super::validate::{Issue, validate};

/// The header of a tree (everything but its nodes).
#[derive(Debug, Clone, PartialEq)]
pub struct TreeProps {
    pub name: String,
    pub enabled: bool,
    pub window: TimeWindow,
    pub emission: Emission,
    pub propagation_speed: f32,
    pub locked: bool,
    pub hidden: bool,
    pub keys: Vec<Key>,
}

impl TreeProps {
    pub fn of(tree: &Tree) -> Self {
        Self {
            name: tree.name.clone(),
            enabled: tree.enabled,
            window: tree.window,
            emission: tree.emission,
            propagation_speed: tree.propagation_speed,
            locked: tree.locked,
            hidden: tree.hidden,
            keys: tree.keys.clone(),
        }
    }
}

/// One undoable change.
#[derive(Debug, Clone, PartialEq)]
pub enum Edit {
    /// Inserts a tree (with all its nodes) at `index` in the tree list.
    AddTree {
        index: usize,
        tree: Tree,
    },
    RemoveTree {
        id: u32,
    },
    SetTreeProps {
        id: u32,
        props: TreeProps,
    },
    /// Inserts `node` (with its subtree) as child number `index` of node `parent`.
    AddNode {
        parent: u32,
        index: usize,
        node: Node,
    },
    /// Removes a non-root node with its subtree.
    RemoveNode {
        id: u32,
    },
    MoveNode {
        id: u32,
        pos: Vec2,
    },
    SetNode {
        id: u32,
        strength: f32,
        radius: f32,
    },
    /// Replaces a branch's keyframes (a point other than a root).
    SetNodeKeys {
        id: u32,
        keys: Vec<Key>,
    },
    AddObstacle {
        index: usize,
        obstacle: Obstacle,
    },
    RemoveObstacle {
        id: u32,
    },
    /// Replaces the obstacle with the same id.
    SetObstacle {
        obstacle: Obstacle,
    },
    AddAmbient {
        index: usize,
        layer: AmbientLayer,
    },
    RemoveAmbient {
        id: u32,
    },
    /// Replaces the ambient layer with the same id.
    SetAmbient {
        layer: AmbientLayer,
    },
    AddProbe {
        index: usize,
        probe: Probe,
    },
    RemoveProbe {
        id: u32,
    },
    /// Replaces the probe with the same id.
    SetProbe {
        probe: Probe,
    },
    SetWorld(World),
    SetSim(SimParams),
    SetGrass(GrassParams),
    SetTimeline(Timeline),
    Rename(String),
    /// Renames the files the layout names (its backdrop, masks, heightmap, density map):
    /// every path equal to a pair's first becomes its second, all at once. Pixels stay as
    /// they are: the same images under new names (a Save As into another folder keeps each
    /// read image's file; a new image takes a free name).
    Repath(Vec<(String, String)>),
    /// Several edits as one undo step; applied in order, undone in reverse.
    Batch(Vec<Edit>),
    /// An edit named for what the user did ("Apply preset", "Paste"), for the Undo menu.
    Named(&'static str, Box<Edit>),
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EditError {
    #[error("no tree with id {0}")]
    NoTree(u32),
    #[error("no node with id {0}")]
    NoNode(u32),
    #[error("no obstacle with id {0}")]
    NoObstacle(u32),
    #[error("no ambient layer with id {0}")]
    NoLayer(u32),
    #[error("no probe with id {0}")]
    NoProbe(u32),
    #[error("node {0} is a root: remove its tree instead")]
    Root(u32),
    #[error("the edit would make the layout invalid: {}", .0.first().map(|i| i.to_string()).unwrap_or_default())]
    Invalid(Vec<Issue>),
}

fn tree_of_node(doc: &Layout, id: u32) -> Option<usize> {
    doc.trees.iter().position(|t| t.root.find(id).is_some())
}

fn node_mut(doc: &mut Layout, id: u32) -> Result<&mut Node, EditError> {
    doc.trees
        .iter_mut()
        .find_map(|t| t.root.find_mut(id))
        .ok_or(EditError::NoNode(id))
}

fn index_by_id<T>(items: &[T], id: u32, get: impl Fn(&T) -> u32) -> Option<usize> {
    items.iter().position(|x| get(x) == id)
}

impl Edit {
    /// A short name for menus ("Undo Move node").
    pub fn label(&self) -> &'static str {
        match self {
            Self::AddTree { .. } => "Add tree",
            Self::RemoveTree { .. } => "Delete tree",
            Self::SetTreeProps { .. } => "Change tree",
            Self::AddNode { .. } => "Add arrow",
            Self::RemoveNode { .. } => "Delete node",
            Self::MoveNode { .. } => "Move node",
            Self::SetNode { .. } => "Change node",
            Self::SetNodeKeys { .. } => "Change branch keys",
            Self::AddObstacle { .. } => "Add obstacle",
            Self::RemoveObstacle { .. } => "Delete obstacle",
            Self::SetObstacle { .. } => "Change obstacle",
            Self::AddAmbient { .. } => "Add ambient layer",
            Self::RemoveAmbient { .. } => "Delete ambient layer",
            Self::SetAmbient { .. } => "Change ambient layer",
            Self::AddProbe { .. } => "Add probe",
            Self::RemoveProbe { .. } => "Delete probe",
            Self::SetProbe { .. } => "Change probe",
            Self::SetWorld(_) => "Change world",
            Self::SetSim(_) => "Change simulation",
            Self::SetGrass(_) => "Change grass",
            Self::SetTimeline(_) => "Change timeline",
            Self::Rename(_) => "Rename layout",
            Self::Repath(_) => "Rename image files",
            Self::Named(label, _) => label,
            // A batch is named after what it does where that is one thing: the edits' own
            // name when they share it, "Delete selection" for a mixed deletion.
            Self::Batch(edits) => match edits.split_first() {
                Some((first, rest)) if rest.iter().all(|e| e.label() == first.label()) => {
                    first.label()
                }
                Some(_) if edits.iter().all(|e| e.label().starts_with("Delete")) => {
                    "Delete selection"
                }
                Some(_) if edits.iter().all(|e| e.label().starts_with("Add")) => "Add selection",
                _ => "Edit",
            },
        }
    }

    /// Applies the edit and returns its inverse. On error the document is unchanged, and an
    /// edit that would leave an invalid document (a negative radius, a duplicate id…) is an
    /// error too.
    pub fn apply(self, doc: &mut Layout) -> Result<Edit, EditError> {
        let before = validate(doc);
        let inverse = self.apply_unchecked(doc)?;
        let issues = validate(doc);
        if issues.iter().any(|i| !before.contains(i)) {
            inverse
                .apply_unchecked(doc)
                .expect("the inverse of an applied edit applies");
            return Err(EditError::Invalid(issues));
        }
        Ok(inverse)
    }

    fn apply_unchecked(self, doc: &mut Layout) -> Result<Edit, EditError> {
        Ok(match self {
            Self::AddTree { index, tree } => {
                let id = tree.id;
                doc.trees.insert(index.min(doc.trees.len()), tree);
                Self::RemoveTree { id }
            }
            Self::RemoveTree { id } => {
                let i = index_by_id(&doc.trees, id, |t| t.id).ok_or(EditError::NoTree(id))?;
                let tree = doc.trees.remove(i);
                Self::AddTree { index: i, tree }
            }
            Self::SetTreeProps { id, props } => {
                let tree = doc
                    .trees
                    .iter_mut()
                    .find(|t| t.id == id)
                    .ok_or(EditError::NoTree(id))?;
                let old = TreeProps::of(tree);
                tree.name = props.name;
                tree.enabled = props.enabled;
                tree.window = props.window;
                tree.emission = props.emission;
                tree.propagation_speed = props.propagation_speed;
                tree.locked = props.locked;
                tree.hidden = props.hidden;
                tree.keys = props.keys;
                Self::SetTreeProps { id, props: old }
            }
            Self::AddNode {
                parent,
                index,
                node,
            } => {
                let id = node.id;
                let p = node_mut(doc, parent)?;
                p.children.insert(index.min(p.children.len()), node);
                Self::RemoveNode { id }
            }
            Self::RemoveNode { id } => {
                let t = tree_of_node(doc, id).ok_or(EditError::NoNode(id))?;
                let root = &mut doc.trees[t].root;
                if root.id == id {
                    return Err(EditError::Root(id));
                }
                let (parent, index) = root
                    .parent_of(id)
                    .map(|(p, i)| (p.id, i))
                    .expect("a non-root node has a parent");
                let node = root
                    .find_mut(parent)
                    .expect("parent exists")
                    .children
                    .remove(index);
                Self::AddNode {
                    parent,
                    index,
                    node,
                }
            }
            Self::MoveNode { id, pos } => {
                let n = node_mut(doc, id)?;
                let old = std::mem::replace(&mut n.pos, pos);
                Self::MoveNode { id, pos: old }
            }
            Self::SetNode {
                id,
                strength,
                radius,
            } => {
                let n = node_mut(doc, id)?;
                let old = Self::SetNode {
                    id,
                    strength: n.strength,
                    radius: n.radius,
                };
                n.strength = strength;
                n.radius = radius;
                old
            }
            Self::AddObstacle { index, obstacle } => {
                let id = obstacle.id;
                doc.obstacles
                    .insert(index.min(doc.obstacles.len()), obstacle);
                Self::RemoveObstacle { id }
            }
            Self::RemoveObstacle { id } => {
                let i =
                    index_by_id(&doc.obstacles, id, |o| o.id).ok_or(EditError::NoObstacle(id))?;
                let obstacle = doc.obstacles.remove(i);
                Self::AddObstacle { index: i, obstacle }
            }
            Self::SetObstacle { obstacle } => {
                let id = obstacle.id;
                let i =
                    index_by_id(&doc.obstacles, id, |o| o.id).ok_or(EditError::NoObstacle(id))?;
                let old = std::mem::replace(&mut doc.obstacles[i], obstacle);
                Self::SetObstacle { obstacle: old }
            }
            Self::AddAmbient { index, layer } => {
                let id = layer.id;
                doc.ambient.insert(index.min(doc.ambient.len()), layer);
                Self::RemoveAmbient { id }
            }
            Self::RemoveAmbient { id } => {
                let i = index_by_id(&doc.ambient, id, |a| a.id).ok_or(EditError::NoLayer(id))?;
                let layer = doc.ambient.remove(i);
                Self::AddAmbient { index: i, layer }
            }
            Self::SetAmbient { layer } => {
                let id = layer.id;
                let i = index_by_id(&doc.ambient, id, |a| a.id).ok_or(EditError::NoLayer(id))?;
                let old = std::mem::replace(&mut doc.ambient[i], layer);
                Self::SetAmbient { layer: old }
            }
            Self::AddProbe { index, probe } => {
                let id = probe.id;
                doc.probes.insert(index.min(doc.probes.len()), probe);
                Self::RemoveProbe { id }
            }
            Self::RemoveProbe { id } => {
                let i = index_by_id(&doc.probes, id, |p| p.id).ok_or(EditError::NoProbe(id))?;
                let probe = doc.probes.remove(i);
                Self::AddProbe { index: i, probe }
            }
            Self::SetProbe { probe } => {
                let id = probe.id;
                let i = index_by_id(&doc.probes, id, |p| p.id).ok_or(EditError::NoProbe(id))?;
                let old = std::mem::replace(&mut doc.probes[i], probe);
                Self::SetProbe { probe: old }
            }
            Self::SetWorld(w) => Self::SetWorld(std::mem::replace(&mut doc.world, w)),
            Self::SetSim(s) => Self::SetSim(std::mem::replace(&mut doc.sim, s)),
            Self::SetGrass(g) => Self::SetGrass(std::mem::replace(&mut doc.grass, g)),
            Self::SetTimeline(t) => Self::SetTimeline(std::mem::replace(&mut doc.timeline, t)),
            Self::SetNodeKeys { id, keys } => {
                let n = node_mut(doc, id)?;
                let old = std::mem::replace(&mut n.keys, keys);
                Self::SetNodeKeys { id, keys: old }
            }
            Self::Rename(n) => Self::Rename(std::mem::replace(&mut doc.name, n)),
            Self::Repath(pairs) => {
                super::portable::for_each_file_mut(doc, |path, _| {
                    if let Some((_, to)) = pairs.iter().find(|(from, _)| from == path) {
                        path.clone_from(to);
                    }
                });
                Self::Repath(pairs.into_iter().map(|(a, b)| (b, a)).collect())
            }
            Self::Batch(edits) => {
                let mut inverses = Vec::with_capacity(edits.len());
                for e in edits {
                    match e.apply_unchecked(doc) {
                        Ok(inv) => inverses.push(inv),
                        Err(err) => {
                            for inv in inverses.into_iter().rev() {
                                inv.apply_unchecked(doc)
                                    .expect("the inverse of an applied edit applies");
                            }
                            return Err(err);
                        }
                    }
                }
                inverses.reverse();
                Self::Batch(inverses)
            }
            Self::Named(label, edit) => Self::Named(label, Box::new(edit.apply_unchecked(doc)?)),
        })
    }
}

struct Entry {
    /// The edit that undoes this step.
    inverse: Edit,
    /// What the step did ([`Edit::label`] of the edit that made it, the first of a gesture),
    /// for the Undo menu item: not the inverse's (undoing an added obstacle read "Undo
    /// Delete obstacle").
    label: &'static str,
    /// Continuous gestures (a slider drag) share a key and collapse into one step.
    merge_key: Option<u64>,
}

/// Undo/redo over [`Edit`]s.
#[derive(Default)]
pub struct History {
    undo: Vec<Entry>,
    redo: Vec<Edit>,
}

impl History {
    pub fn new() -> Self {
        Self::default()
    }

    /// Applies an edit as a new undo step.
    pub fn apply(&mut self, doc: &mut Layout, edit: Edit) -> Result<(), EditError> {
        let label = edit.label();
        let inverse = edit.apply(doc)?;
        self.undo.push(Entry {
            inverse,
            label,
            merge_key: None,
        });
        self.redo.clear();
        Ok(())
    }

    /// Applies an edit that continues a gesture: consecutive edits with the same `key` form one
    /// undo step (undo returns to the state before the first of them).
    pub fn apply_merged(
        &mut self,
        doc: &mut Layout,
        edit: Edit,
        key: u64,
    ) -> Result<(), EditError> {
        let label = edit.label();
        let inverse = edit.apply(doc)?;
        match self.undo.last() {
            Some(top) if top.merge_key == Some(key) => {}
            _ => self.undo.push(Entry {
                inverse,
                label,
                merge_key: Some(key),
            }),
        }
        self.redo.clear();
        Ok(())
    }

    /// Ends the current gesture: the next merged edit starts a new undo step.
    pub fn end_gesture(&mut self) {
        if let Some(top) = self.undo.last_mut() {
            top.merge_key = None;
        }
    }

    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// What the next undo would undo, for menus.
    pub fn undo_label(&self) -> Option<&'static str> {
        self.undo.last().map(|e| e.label)
    }

    pub fn redo_label(&self) -> Option<&'static str> {
        self.redo.last().map(Edit::label)
    }

    /// Undoes the last step; returns false when there is nothing to undo.
    pub fn undo(&mut self, doc: &mut Layout) -> bool {
        let Some(entry) = self.undo.pop() else {
            return false;
        };
        let redo = entry
            .inverse
            .apply_unchecked(doc)
            .expect("an inverse applies to the document it was made from");
        self.redo.push(redo);
        true
    }

    /// Redoes the last undone step; returns false when there is nothing to redo.
    pub fn redo(&mut self, doc: &mut Layout) -> bool {
        let Some(edit) = self.redo.pop() else {
            return false;
        };
        let label = edit.label();
        let inverse = edit
            .apply_unchecked(doc)
            .expect("a redo applies to the document it was undone from");
        self.undo.push(Entry {
            inverse,
            label,
            merge_key: None,
        });
        true
    }

    pub fn clear(&mut self) {
        self.undo.clear();
        self.redo.clear();
    }
}
