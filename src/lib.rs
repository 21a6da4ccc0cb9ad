//! windloom: author wind over a top-down map of a level, simulate it, export it for engines.
//!
//! Each module imports only from the floors below it (`docs/ARCHITECTURE.md`): `doc` at the
//! bottom, then `sim`, `grass` and `io`, `gpu`, `engine`, `bake`, the editor (`app`) and the
//! command line (`cli`) at the top.

pub mod app;
pub mod bake;
pub mod cli;
pub mod colour;
pub mod doc;
pub mod engine;
pub mod gpu;
pub mod grass;
pub mod io;
pub mod num;
pub mod platform;
pub mod render;
pub mod sim;
