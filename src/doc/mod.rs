//! The document model: layout types, parsing with diagnostics, validation, advice on valid but
//! risky settings, migration, and edit commands with undo. Plain data: no egui, no wgpu, no
//! file system.

mod advice;
mod edit;
mod parse;
mod types;
mod validate;

pub use advice::{VORTICITY_ADVISED, VORTICITY_MACCORMACK_ADVISED, advise};
pub use edit::{Edit, EditError, History, TreeProps};
pub use parse::{Diagnostic, Diagnostics, parse, schema, to_json};
pub use types::*;
pub use validate::{
    COORD_MAX, DT_MAX, DT_MIN, GRID_AXIS_MAX, GRID_AXIS_MIN, GRID_MEMORY_BUDGET, Issue, LENGTH_MIN,
    MULTIGRID_BYTES_PER_CELL, RADIUS_MAX, SOLVER_BYTES_PER_CELL, STRENGTH_MAX, WORLD_SIZE_MAX,
    WORLD_SIZE_MIN, for_each_ear, grid_memory, polygon_area, validate,
};

/// The bundled default layout (`layouts/meadow.json`), embedded in the binary.
pub const DEFAULT_LAYOUT_JSON: &str = include_str!("../../layouts/meadow.json");

/// The bundled default layout, parsed.
pub fn default_layout() -> Layout {
    parse(DEFAULT_LAYOUT_JSON).expect("the bundled default layout is valid")
}
