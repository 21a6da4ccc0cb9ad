//! windloom: author wind over a top-down map of a level, simulate it, export it for engines.
//!
//! Dependency direction (see `docs/ARCHITECTURE.md`): `doc` ← `sim` ← {`io`, `app`, CLI}.

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
