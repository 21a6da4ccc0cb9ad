//! Which solver a bake steps: the CPU one, or the GPU one where it covers the layout.

use super::BakeError;
use crate::doc::Layout;
use crate::gpu::{GpuContext, GpuSolver};
use crate::sim::Solver;

/// The solver a bake asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Backend {
    /// The CPU solver (the reference).
    #[default]
    Cpu,
    /// The GPU solver; an error when there is no adapter or it does not cover the layout.
    Gpu,
    /// The GPU when a hardware adapter exists and covers the layout, else the CPU (with a
    /// note in the manifest saying why).
    Auto,
}

pub(crate) enum Stepper {
    Cpu(Box<Solver>),
    Gpu(Box<(GpuContext, GpuSolver)>),
}

fn gpu_error(e: crate::gpu::GpuError) -> BakeError {
    BakeError::Settings(format!("--backend gpu: {e}"))
}

impl Stepper {
    /// The stepper for `backend`, and a note when `auto` fell back to the CPU.
    pub(crate) fn new(
        layout: &Layout,
        backend: Backend,
    ) -> Result<(Self, Option<String>), BakeError> {
        let cpu = || Self::Cpu(Box::new(Solver::new(layout)));
        match backend {
            Backend::Cpu => Ok((cpu(), None)),
            Backend::Gpu => {
                let ctx = GpuContext::headless().map_err(gpu_error)?;
                let s = GpuSolver::new(&ctx, layout).map_err(gpu_error)?;
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
    pub(crate) fn describe(&self) -> String {
        match self {
            Self::Cpu(_) => "cpu".into(),
            Self::Gpu(g) => format!("gpu: {}", g.0.describe()),
        }
    }

    pub(crate) fn step(&mut self) {
        match self {
            Self::Cpu(s) => s.step(),
            Self::Gpu(g) => {
                let (ctx, s) = &mut **g;
                s.step(ctx);
            }
        }
    }

    pub(crate) fn set_time(&mut self, t: f32) {
        match self {
            Self::Cpu(s) => s.time = t,
            Self::Gpu(g) => g.1.time = t,
        }
    }

    pub(crate) fn velocity_field(&mut self) -> Result<Vec<[f32; 2]>, BakeError> {
        match self {
            Self::Cpu(s) => Ok(s.velocity_field()),
            Self::Gpu(g) => g.1.velocity_field(&g.0).map_err(gpu_error),
        }
    }
}
