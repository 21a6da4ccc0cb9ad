//! The document model: layout types, parsing with diagnostics, validation, advice on valid but
//! risky settings, migration, and edit commands with undo. Plain data: no egui, no wgpu, no
//! file system.

mod advice;
pub mod bounds;
pub mod clipboard;
mod edit;
mod parse;
pub mod portable;
pub mod presets;
pub mod raster;
pub mod stroke;
pub mod transform;
mod types;
mod validate;

pub use advice::{VORTICITY_MACCORMACK_ADVISED, advise};
pub use bounds::{
    AMBIENT_MAX, Bound, CHAIN_MAX, COORD_MAX, Count, DT_MAX, DT_MIN, GRID_AXIS_MAX, GRID_AXIS_MIN,
    GRID_MEMORY_BUDGET, LAYOUT_MAX_BYTES, LENGTH_MIN, MULTIGRID_BYTES_PER_CELL, NAME_MAX,
    NESTING_MAX, NODES_MAX, OBSTACLES_MAX, POLYGON_POINTS_MAX, RADIUS_MAX, SOLVER_BYTES_PER_CELL,
    STRENGTH_MAX, TREES_MAX, WORLD_SIZE_MAX, WORLD_SIZE_MIN,
};
pub use clipboard::Item;
pub use edit::{Edit, EditError, History, TreeProps};
pub use parse::{Diagnostic, Diagnostics, parse, parse_bytes, schema, to_json};
pub use types::*;
pub use validate::{
    Issue, density_map_problem, for_each_ear, grid_memory, mask_problems, polygon_area, validate,
};

/// The bundled default layout (`layouts/meadow.json`), embedded in the binary.
pub const DEFAULT_LAYOUT_JSON: &str = include_str!("../../layouts/meadow.json");

/// The bundled default layout, parsed.
pub fn default_layout() -> Layout {
    parse(DEFAULT_LAYOUT_JSON).expect("the bundled default layout is valid")
}

/// `s` as a message may show it: control characters (a terminal's escape sequences, a
/// carriage return, a line break) written as escapes (`\u{1b}`), and at most `max`
/// characters of it, the rest counted. Every message that quotes a file's text, a name or a
/// path goes through this, so a hostile file cannot flood or drive the terminal.
pub fn printable(s: &str, max: usize) -> String {
    let mut out = String::new();
    let mut chars = s.chars();
    for (shown, c) in chars.by_ref().enumerate() {
        if shown == max {
            let rest = 1 + chars.count();
            out.push_str(&format!("… ({rest} more characters)"));
            break;
        }
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// A value (a key, a name) quoted in a message: [`printable`], at most 80 characters.
pub fn quote(s: &str) -> String {
    printable(s, 80)
}
