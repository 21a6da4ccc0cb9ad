//! The simulation: the force model (AGC arrow trees, ambient layers), obstacle rasterisation
//! and the CPU stable-fluid solver. Knows nothing of wgpu or egui.

pub mod bench;
pub mod clock;
pub mod forces;
pub mod obstacles;
pub mod solver;
pub mod terrain;

pub use clock::Clock;
pub use solver::{MAX_SPEED, PassTimes, Solver, WindSampler};
