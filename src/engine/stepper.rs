//! The solver a bake steps: the CPU one, or the GPU one where it covers the layout.

use super::Backend;
use crate::doc::Layout;
use crate::gpu::{GpuContext, GpuError, GpuSolver};
use crate::sim::Solver;

/// A solver a caller steps itself (a bake): the CPU one, or the GPU one on a headless device.
pub enum Stepper {
    Cpu(Box<Solver>),
    Gpu(Box<(GpuContext, GpuSolver)>),
}

impl Stepper {
    /// The stepper for `backend`, and a note when `auto` fell back to the CPU.
    pub fn new(layout: &Layout, backend: Backend) -> Result<(Self, Option<String>), GpuError> {
        let cpu = || Self::Cpu(Box::new(Solver::new(layout)));
        match backend {
            Backend::Cpu => Ok((cpu(), None)),
            Backend::Gpu => {
                let ctx = GpuContext::headless()?;
                let s = GpuSolver::new(&ctx, layout)?;
                Ok((Self::Gpu(Box::new((ctx, s))), None))
            }
            Backend::Auto => {
                let why = match GpuContext::headless() {
                    Ok(ctx) if ctx.adapter.device_type == wgpu::DeviceType::Cpu => format!(
                        "the only GPU adapter, {}, is a software rasteriser",
                        ctx.describe()
                    ),
                    Ok(ctx) => match GpuSolver::new(&ctx, layout) {
                        Ok(s) => return Ok((Self::Gpu(Box::new((ctx, s))), None)),
                        Err(e) => e.to_string(),
                    },
                    Err(e) => e.to_string(),
                };
                Ok((cpu(), Some(format!("solver: baked on the CPU ({why})"))))
            }
        }
    }

    /// `"cpu"` or `"gpu: ADAPTER"`, for the manifest.
    pub fn describe(&self) -> String {
        match self {
            Self::Cpu(_) => "cpu".into(),
            Self::Gpu(g) => format!("gpu: {}", g.0.describe()),
        }
    }

    pub fn step(&mut self) {
        match self {
            Self::Cpu(s) => s.step(),
            Self::Gpu(g) => {
                let (ctx, s) = &mut **g;
                s.step(ctx);
            }
        }
    }

    pub fn set_time(&mut self, seconds: f64) {
        match self {
            Self::Cpu(s) => s.set_time(seconds),
            Self::Gpu(g) => g.1.set_time(seconds),
        }
    }

    /// Simulated seconds (the solvers' one clock: substeps counted, in f64).
    pub fn seconds(&self) -> f64 {
        match self {
            Self::Cpu(s) => s.clock.seconds(),
            Self::Gpu(g) => g.1.clock.seconds(),
        }
    }

    pub fn velocity_field(&mut self) -> Result<Vec<[f32; 2]>, GpuError> {
        match self {
            Self::Cpu(s) => Ok(s.velocity_field()),
            Self::Gpu(g) => g.1.velocity_field(&g.0),
        }
    }
}
