//! Whole solver steps on the GPU: the passes of [`super::fluid`] in the CPU solver's order,
//! one command encoder a substep (one a step at the usual `substeps = 1`), no read-back.
//!
//! Covers every layout: the CPU uploads per substep only the active AGC splats, the ambient
//! layers' time-dependent parameters and, for FFT layers, the gust field it evaluates.

use super::fluid::{FieldId, GpuFluid};
use super::{GpuContext, GpuError};
use crate::doc::{Advection, Layout, SimParams};
use crate::sim::Solver;
use crate::sim::forces::{Ambient, agc_splats, reference_speed};
use crate::sim::solver::Confinement;

/// The GPU twin of [`Solver`] for the layouts it covers.
pub struct GpuSolver {
    fluid: GpuFluid,
    layout: Layout,
    /// The ambient layers, prepared on the CPU (FFT spectra) and evaluated per substep into
    /// the small parameter and gust buffers the GPU reads.
    ambient: Ambient,
    /// The layout's [`reference_speed`], found once a layout (as the CPU solver caches it).
    reference_speed: f32,
    pub params: SimParams,
    pub nx: usize,
    pub ny: usize,
    /// Simulated time, counted in substeps as the CPU solver counts it.
    pub clock: crate::sim::Clock,
}

impl GpuSolver {
    /// Simulated seconds, as the forces take them.
    pub fn time(&self) -> f32 {
        self.clock.time()
    }

    /// Sets the simulated time (a seek, a bake's frame).
    pub fn set_time(&mut self, seconds: f64) {
        self.clock = crate::sim::Clock::at(seconds);
    }

    /// A GPU solver for `layout` at rest (the layout must be valid).
    pub fn new(ctx: &GpuContext, layout: &Layout) -> Result<Self, GpuError> {
        // Checked before the CPU solver that seeds it is made (a refused grid can be large).
        let [nx, ny] = layout.world.grid;
        fits(ctx, nx as usize, ny as usize)?;
        Self::build(ctx, layout, &Solver::new(layout))
    }

    /// A GPU solver that takes over `cpu`'s running field (velocity, pressure, time).
    /// `layout` must be the one `cpu` was made from.
    pub fn from_solver(ctx: &GpuContext, layout: &Layout, cpu: &Solver) -> Result<Self, GpuError> {
        fits(ctx, cpu.nx, cpu.ny)?;
        Self::build(ctx, layout, cpu)
    }

    /// [`Self::from_solver`] once the grid is known to fit.
    fn build(ctx: &GpuContext, layout: &Layout, cpu: &Solver) -> Result<Self, GpuError> {
        ctx.check("the device")?;
        // `GpuFluid::new` creates its buffers holding `cpu`'s state; an allocation the device
        // refuses is an error here, not a panic.
        let oom = ctx.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let invalid = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut fluid = GpuFluid::new(&ctx.device, cpu);
        // Two Jacobi sweeps a dispatch halve the pressure solve's time on an H200 (0.33 →
        // 0.17 ms at 1000²), but lavapipe's workgroup barriers double it there: one sweep a
        // dispatch on a software adapter.
        fluid.paired_sweeps = !super::is_software(&ctx.adapter);
        let invalid = pollster::block_on(invalid.pop());
        if let Some(e) = invalid.or(pollster::block_on(oom.pop())) {
            return Err(GpuError::Runtime {
                what: format!("creating the {}x{} grid", cpu.nx, cpu.ny),
                message: e.to_string(),
            });
        }
        let solver = Self {
            fluid,
            layout: layout.clone(),
            ambient: Ambient::new(layout),
            reference_speed: reference_speed(layout),
            params: layout.sim,
            nx: cpu.nx,
            ny: cpu.ny,
            clock: cpu.clock,
        };
        solver.reshape(ctx);
        Ok(solver)
    }

    /// Replaces the layout the forces come from (an edit), keeping the running field; a
    /// change of terrain uploads `terrain`, the layout's over this grid (the CPU solver's,
    /// made once for both), through `ctx`.
    pub fn set_layout_on(
        &mut self,
        ctx: &GpuContext,
        layout: &Layout,
        terrain: Option<&crate::sim::terrain::TerrainField>,
    ) {
        if layout.world.terrain != self.layout.world.terrain {
            self.fluid.set_terrain(&ctx.device, terrain);
            self.reshape(ctx);
        }
        self.set_layout(layout);
    }

    /// Writes the wind faces from the field as it is (after a new terrain, or a field handed
    /// over), rather than waiting for the next step.
    fn reshape(&self, ctx: &GpuContext) {
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("terrain"),
            });
        self.fluid.shape_terrain(&ctx.device, &mut enc);
        ctx.submit(enc.finish());
    }

    /// Replaces the layout the forces come from (an edit), keeping the running field; as
    /// [`Solver::set_layout`], grid, world, obstacle and boundary changes need a new solver.
    pub fn set_layout(&mut self, layout: &Layout) {
        self.layout = layout.clone();
        self.ambient = Ambient::new(layout);
        self.reference_speed = reference_speed(layout);
        self.params = layout.sim;
    }

    /// The buffers the field lives in, for drawing it where it is (the editor's map view).
    pub fn field(&self) -> super::mapview::FieldBuffers {
        let l = &self.layout.world;
        let (u, v) = self.fluid.wind_buffers();
        super::mapview::FieldBuffers {
            u: u.clone(),
            v: v.clone(),
            p: self.fluid.buffer(FieldId::P).clone(),
            nx: self.nx as u32,
            ny: self.ny as u32,
            origin: l.origin,
            cell: [l.size[0] / self.nx as f32, l.size[1] / self.ny as f32],
        }
    }

    /// Copies the running field (velocity, pressure, time) into `cpu`, a solver made from the
    /// same layout: the hand-over back to the CPU, and the editor's throttled read-back.
    pub fn read_into(&self, ctx: &GpuContext, cpu: &mut Solver) -> Result<(), GpuError> {
        let (u, v) = self.faces(ctx)?;
        let p = self
            .fluid
            .download_via(&ctx.device, &|cb| ctx.submit(cb), FieldId::P)?;
        if u.len() != cpu.u.len() || v.len() != cpu.v.len() || p.len() != cpu.p.len() {
            return Err(GpuError::Runtime {
                what: "handing the field to the CPU".into(),
                message: format!(
                    "the CPU solver's grid is {}x{}, the GPU's {}x{}",
                    cpu.nx, cpu.ny, self.nx, self.ny
                ),
            });
        }
        cpu.u = u;
        cpu.v = v;
        cpu.p = p;
        cpu.clock = self.clock;
        Ok(())
    }

    /// Records and submits one step (its substeps), without waiting for the GPU.
    pub fn step(&mut self, ctx: &GpuContext) {
        let (device, queue) = (&ctx.device, &ctx.queue);
        let n = self.params.substeps.max(1);
        let dt = self.params.dt / n as f32;
        let keep = 1.0 / (1.0 + self.params.velocity_dissipation * dt);
        let iterations = self.params.pressure_iterations as usize;
        self.fluid.pressure_solve = self.params.pressure;
        self.fluid.pressure_cycles = self.params.pressure_cycles as usize;
        self.fluid.set_warm_start(queue, self.params.warm_start());
        let maccormack = self.params.advection == Advection::MacCormack;
        // As the CPU reads them each step: an edit of ε, the arrows or their response takes
        // effect now (they were fixed when the GPU solver was made).
        let h = self.fluid.cell_size();
        let conf = Confinement::new(self.params.vorticity, h, self.reference_speed);
        self.fluid
            .set_rates(queue, conf, self.params.arrow_response);
        for _ in 0..n {
            let splats = agc_splats(&self.layout, self.clock.time());
            self.ambient.set_time(self.clock.time());
            let (layers, gusts) = self.ambient.layer_params();
            // As the CPU computes it, so both pull with the same factor.
            let coupling = 1.0 - (-self.params.ambient_coupling * dt).exp();
            let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("fluid step"),
            });
            self.fluid.forces(
                device,
                queue,
                &mut enc,
                &splats,
                (&layers, &gusts, coupling),
                dt,
            );
            self.fluid
                .record_substep(device, queue, &mut enc, dt, iterations, keep, maccormack);
            self.fluid.shape_terrain(device, &mut enc);
            // One encoder a substep, no read-back: the parameters all passes read are written
            // once before it runs.
            ctx.submit(enc.finish());
            self.clock.tick(dt);
        }
    }

    /// Starts per-pass GPU timing; false when the adapter has no timestamp queries.
    pub fn enable_profiling(&self, ctx: &GpuContext) -> bool {
        self.fluid.enable_profiling(&ctx.device)
    }

    /// Stops per-pass GPU timing.
    pub fn disable_profiling(&self) {
        self.fluid.disable_profiling();
    }

    /// GPU milliseconds per pass since the last call (empty without profiling).
    pub fn pass_times(
        &self,
        ctx: &GpuContext,
    ) -> Result<std::collections::BTreeMap<&'static str, f64>, GpuError> {
        self.fluid
            .pass_times(&ctx.device, &ctx.queue, &|cb| ctx.submit(cb))
    }

    /// Waits until the GPU has finished every submitted step; an error when the device was
    /// lost or reported a fault meanwhile (the field is then not to be trusted).
    pub fn finish(&self, ctx: &GpuContext) -> Result<(), GpuError> {
        ctx.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Runtime {
                what: "a solver step".into(),
                message: e.to_string(),
            })?;
        ctx.check("the device")
    }

    /// The face velocities `(u, v)` read back from the GPU.
    pub fn faces(&self, ctx: &GpuContext) -> Result<(Vec<f32>, Vec<f32>), GpuError> {
        Ok((
            self.fluid
                .download_via(&ctx.device, &|cb| ctx.submit(cb), FieldId::U)?,
            self.fluid
                .download_via(&ctx.device, &|cb| ctx.submit(cb), FieldId::V)?,
        ))
    }

    /// The wind's faces `(u, v)` as they leave the solver, read back: terrain-shaped, as
    /// [`Solver::wind_faces`].
    pub fn wind_faces(&self, ctx: &GpuContext) -> Result<(Vec<f32>, Vec<f32>), GpuError> {
        let (u, v) = self.fluid.wind_buffers();
        let read = |b| {
            super::read_buffer_via(&ctx.device, &|cb| ctx.submit(cb), b)
                .map(|bytes| bytemuck::cast_slice::<u8, f32>(&bytes).to_vec())
        };
        Ok((read(u)?, read(v)?))
    }

    /// The wind, cell-centred `[x, z]` (m/s), row-major, as [`Solver::velocity_field`].
    pub fn velocity_field(&self, ctx: &GpuContext) -> Result<Vec<[f32; 2]>, GpuError> {
        let (u, v) = self.wind_faces(ctx)?;
        Ok(crate::sim::solver::cell_centred(self.nx, self.ny, &u, &v))
    }
}

/// Whether an `nx × ny` grid's largest field fits what the device can bind and allocate: a
/// clear refusal before any buffer is made, rather than a validation error at the first step.
fn fits(ctx: &GpuContext, nx: usize, ny: usize) -> Result<(), GpuError> {
    let limits = ctx.device.limits();
    let largest = ((nx + 1) * ny).max(nx * (ny + 1)) as u64 * 4;
    let cap = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    if largest > cap {
        return Err(GpuError::Unsupported {
            adapter: ctx.describe(),
            what: format!(
                "hold a {nx}x{ny} grid: a velocity field takes {} MiB, over its {} MiB storage-buffer limit",
                largest.div_ceil(1 << 20),
                cap >> 20
            ),
        });
    }
    Ok(())
}
