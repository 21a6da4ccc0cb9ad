//! The GPU side: device setup and the fluid passes, on wgpu (the same wgpu 30 that eframe and
//! egui-wgpu are built on, so one device can serve the UI and the wind). Everything here takes
//! `&wgpu::Device` and `&wgpu::Queue` and knows nothing of egui. Structs shared with WGSL are
//! `#[repr(C)]` + bytemuck and name the shader they mirror.

pub mod bench;
mod context;
pub mod fluid;
mod solver;

pub use context::{GpuContext, GpuError};
pub use solver::GpuSolver;
