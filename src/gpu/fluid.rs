//! The fluid passes on the GPU: each a compute shader in `shaders/`, each the twin of a CPU
//! solver pass (`src/sim/solver/`), on the CPU's staggered MAC layout in storage buffers.
//!
//! The passes: forces (AGC splats and ambient layers), curl, vorticity confinement,
//! divergence, the Jacobi pressure solve with its warm start, gradient subtraction,
//! semi-Lagrangian and limited MacCormack advection with dissipation, and the periodic face
//! sync — with every boundary mode and obstacle masks. See `docs/SOLVER.md`.

use super::multigrid::{Fine, GpuMultigrid};
use crate::doc::{Boundary, PressureSolve};
use crate::sim::Solver;
use crate::sim::forces::{ArrowSplat, LayerParams};
use crate::sim::solver::{Confinement, MAX_SPEED};
use crate::sim::terrain::TerrainField;
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

/// Step parameters; mirrors `struct Params` in `shaders/common.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Params {
    pub nx: u32,
    pub ny: u32,
    pub periodic: u32,
    pub splats: u32,
    pub hx: f32,
    pub hz: f32,
    pub dt: f32,
    pub keep: f32,
    pub eps: f32,
    pub h: f32,
    pub wx: f32,
    pub wz: f32,
    pub decay: f32,
    pub max_speed: f32,
    pub response: f32,
    /// 1 for open boundaries (the confinement leaves the edge cells alone).
    pub open: u32,
    pub origin: [f32; 2],
    pub coupling: f32,
    pub layers: u32,
    /// Confinement takes no face past this speed (m/s), and scales a cell's push by its
    /// speed times `inv_speed` up to 1: `Confinement::speed_cap`, `Confinement::inv_speed`.
    pub speed_cap: f32,
    pub inv_speed: f32,
}

/// The shared header every pass is compiled with.
pub const COMMON: &str = include_str!("../../shaders/common.wgsl");

/// Every pass's shader file: `(name, source)`, each compiled after [`COMMON`].
pub const SHADERS: [(&str, &str); 9] = [
    ("forces", include_str!("../../shaders/forces.wgsl")),
    ("curl", include_str!("../../shaders/curl.wgsl")),
    (
        "confinement",
        include_str!("../../shaders/confinement.wgsl"),
    ),
    ("divergence", include_str!("../../shaders/divergence.wgsl")),
    ("jacobi", include_str!("../../shaders/jacobi.wgsl")),
    ("gradient", include_str!("../../shaders/gradient.wgsl")),
    ("advect", include_str!("../../shaders/advect.wgsl")),
    ("periodic", include_str!("../../shaders/periodic.wgsl")),
    ("terrain", include_str!("../../shaders/terrain.wgsl")),
];

/// The full WGSL of pass `name` (the common header, then the pass).
pub fn shader_source(name: &str) -> Option<String> {
    SHADERS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| format!("{COMMON}\n{s}"))
}

struct Kernel {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

/// The GPU's copy of the solver state and the passes that step it.
pub struct GpuFluid {
    pub nx: usize,
    pub ny: usize,
    periodic: bool,
    params: Params,
    params_buf: wgpu::Buffer,
    u: wgpu::Buffer,
    v: wgpu::Buffer,
    u_tmp: wgpu::Buffer,
    v_tmp: wgpu::Buffer,
    u_hat: wgpu::Buffer,
    v_hat: wgpu::Buffer,
    p: wgpu::Buffer,
    p_tmp: wgpu::Buffer,
    div: wgpu::Buffer,
    curl: wgpu::Buffer,
    fx: wgpu::Buffer,
    fz: wgpu::Buffer,
    solid: wgpu::Buffer,
    u_free: wgpu::Buffer,
    v_free: wgpu::Buffer,
    flags: wgpu::Buffer,
    inv_w: wgpu::Buffer,
    /// The active AGC splats, the ambient layers and their FFT gust fields (each grown as
    /// needed; at least one element).
    splats: wgpu::Buffer,
    layers: wgpu::Buffer,
    gusts: wgpu::Buffer,
    kernels: std::collections::HashMap<&'static str, Kernel>,
    bind_groups: std::sync::Mutex<BindGroups>,
    /// The pressure solve [`Self::pressure`] records, and the multigrid V-cycles.
    pub pressure_solve: PressureSolve,
    pub pressure_cycles: usize,
    /// Jacobi sweeps two a dispatch (`pair` in jacobi.wgsl) rather than one (`main`): the
    /// same values. On by default; a software adapter turns it off (see
    /// [`crate::gpu::GpuSolver::new`]).
    pub paired_sweeps: bool,
    /// What the multigrid hierarchy is built from (on first use): the pressure flags, cell
    /// size and boundary of the CPU solver this was made from.
    mg_source: (Vec<u8>, [f32; 2], Boundary),
    multigrid: std::sync::OnceLock<GpuMultigrid>,
    profiler: std::sync::Mutex<Option<Profiler>>,
    /// The terrain's coefficients per cell and the shaped faces it writes (`None`: flat
    /// ground, and the wind is `u`, `v`).
    terrain: Option<TerrainBuffers>,
}

/// The terrain pass's buffers: `sim::terrain::Cell` per face (`TerrainField::faces`), and the
/// shaped u and v faces.
struct TerrainBuffers {
    cells: wgpu::Buffer,
    u: wgpu::Buffer,
    v: wgpu::Buffer,
}

/// Per-pass GPU times from timestamp queries around each dispatch.
struct Profiler {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    read: wgpu::Buffer,
    /// The pass of each recorded dispatch, in order (two queries each).
    passes: Vec<&'static str>,
}

/// Dispatches a profiler records between two reads of [`GpuFluid::pass_times`].
const PROFILED_DISPATCHES: u32 = 1024;

/// The solver pass a kernel belongs to, as the CPU solver's timings name them.
fn pass_of(kernel: &str) -> &'static str {
    match kernel {
        "inc_u" | "inc_v" | "add" => "forces",
        "curl" => "curl",
        "force" | "apply_u" | "apply_v" => "confinement",
        "divergence" => "divergence",
        "decay" | "main" | "pair" | "mg_smooth" | "mg_coarsest" | "mg_restrict" | "mg_prolong" => {
            "pressure"
        }
        "u_faces" | "v_faces" => "gradient",
        "sync_u" | "sync_v" => "periodic",
        "shape_u" | "shape_v" => "terrain",
        _ => "advection",
    }
}

/// Bind groups by kernel and the buffers bound at each binding.
type BindGroups = std::collections::HashMap<(String, Vec<(u32, wgpu::Buffer)>), wgpu::BindGroup>;

/// Which field to move between the CPU solver and the GPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldId {
    U,
    V,
    P,
    Div,
    Curl,
}

use super::storage;

fn floats(device: &wgpu::Device, label: &str, data: &[f32]) -> wgpu::Buffer {
    storage(device, label, bytemuck::cast_slice(data))
}

fn mask(device: &wgpu::Device, label: &str, data: &[u8]) -> wgpu::Buffer {
    let words: Vec<u32> = data.iter().map(|&b| u32::from(b)).collect();
    storage(device, label, bytemuck::cast_slice(&words))
}

fn grow_buffer(device: &wgpu::Device, label: &str, bytes: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16).next_power_of_two() as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Writes `data` into `buf`, first replacing it with a larger one if it is too small (then
/// returns true: bind groups holding the old one must go).
fn upload_growing(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buf: &mut wgpu::Buffer,
    label: &str,
    data: &[u8],
) -> bool {
    let grow = data.len() as u64 > buf.size();
    if grow {
        *buf = grow_buffer(device, label, data.len());
    }
    if !data.is_empty() {
        queue.write_buffer(buf, 0, data);
    }
    grow
}

/// Workgroups of `size` to cover `n` invocations.
fn groups(n: usize, size: u32) -> u32 {
    (n as u32).div_ceil(size)
}

/// The most workgroups a dispatch may have along one dimension (WebGPU's
/// `maxComputeWorkgroupsPerDimension` default, which every adapter meets).
const GROUPS_PER_DIMENSION: u32 = 65_535;

/// Workgroups of 64 covering `n` elements of a one-dimensional pass, as rows of at most
/// [`GROUPS_PER_DIMENSION`]: a 2048² grid's faces need 65,568. The shaders find their element
/// with `flat_index` (`shaders/common.wgsl`); the last row's spare invocations fall outside
/// the array and do nothing.
pub(crate) fn flat_groups(n: usize) -> (u32, u32) {
    let g = groups(n, 64);
    if g == 0 {
        return (0, 0);
    }
    let x = g.min(GROUPS_PER_DIMENSION);
    (x, g.div_ceil(x))
}

impl GpuFluid {
    /// Uploads `solver`'s grid, masks and state. The solver fixes the layout: its grid, cell
    /// size, boundary mode and obstacles.
    pub fn new(device: &wgpu::Device, solver: &Solver) -> Self {
        let (nx, ny) = (solver.nx, solver.ny);
        let sp = &solver.params;
        let periodic = sp.boundary == crate::doc::Boundary::Periodic;
        let conf = solver.confinement();
        let params = Params {
            nx: nx as u32,
            ny: ny as u32,
            periodic: u32::from(periodic),
            splats: 0,
            hx: solver.hx,
            hz: solver.hz,
            dt: sp.dt,
            keep: 1.0,
            eps: conf.rate,
            h: solver.hx.min(solver.hz),
            wx: 1.0 / (solver.hx * solver.hx),
            wz: 1.0 / (solver.hz * solver.hz),
            decay: sp.warm_start(),
            max_speed: MAX_SPEED,
            response: sp.arrow_response,
            open: u32::from(sp.boundary == crate::doc::Boundary::Open),
            origin: solver.origin,
            coupling: 0.0,
            layers: 0,
            speed_cap: conf.speed_cap,
            inv_speed: conf.inv_speed,
        };
        let params_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fluid params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let mut kernels = std::collections::HashMap::new();
        for (name, _) in SHADERS {
            let source = shader_source(name).expect("listed");
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(name),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            for entry in entry_points(name) {
                let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry.0),
                    layout: None,
                    module: &module,
                    entry_point: Some(entry.1),
                    compilation_options: Default::default(),
                    cache: None,
                });
                let layout = pipeline.get_bind_group_layout(0);
                kernels.insert(entry.0, Kernel { pipeline, layout });
            }
        }
        Self {
            nx,
            ny,
            periodic,
            params,
            params_buf,
            u: floats(device, "u", &solver.u),
            v: floats(device, "v", &solver.v),
            u_tmp: floats(device, "u_tmp", &solver.u),
            v_tmp: floats(device, "v_tmp", &solver.v),
            u_hat: floats(device, "u_hat", &solver.u),
            v_hat: floats(device, "v_hat", &solver.v),
            p: floats(device, "p", &solver.p),
            p_tmp: floats(device, "p_tmp", &solver.p),
            div: floats(device, "div", &solver.div),
            curl: floats(device, "curl", &solver.curl),
            fx: floats(device, "fx", &solver.p),
            fz: floats(device, "fz", &solver.p),
            solid: mask(device, "solid", &solver.solid),
            u_free: mask(device, "u_free", &solver.u_free),
            v_free: mask(device, "v_free", &solver.v_free),
            flags: mask(device, "flags", &solver.flags),
            inv_w: floats(device, "inv_w", &solver.inv_w),
            splats: grow_buffer(device, "splats", 16 * std::mem::size_of::<ArrowSplat>()),
            layers: grow_buffer(device, "layers", 4 * std::mem::size_of::<LayerParams>()),
            gusts: grow_buffer(device, "gusts", 4),
            kernels,
            bind_groups: Default::default(),
            profiler: Default::default(),
            pressure_solve: sp.pressure,
            pressure_cycles: sp.pressure_cycles as usize,
            paired_sweeps: true,
            mg_source: (solver.flags.clone(), [solver.hx, solver.hz], sp.boundary),
            multigrid: Default::default(),
            terrain: solver.terrain.as_ref().map(|t| TerrainBuffers {
                cells: storage(
                    device,
                    "terrain faces",
                    bytemuck::cast_slice(&t.face_cells()),
                ),
                u: floats(device, "wind u", &solver.u),
                v: floats(device, "wind v", &solver.v),
            }),
        }
    }

    /// Replaces the terrain's coefficients (an edit of the terrain); `None`: flat ground.
    pub fn set_terrain(&mut self, device: &wgpu::Device, terrain: Option<&TerrainField>) {
        self.terrain = terrain.map(|t| TerrainBuffers {
            cells: storage(
                device,
                "terrain faces",
                bytemuck::cast_slice(&t.face_cells()),
            ),
            u: floats(device, "wind u", &vec![0.0; (self.nx + 1) * self.ny]),
            v: floats(device, "wind v", &vec![0.0; self.nx * (self.ny + 1)]),
        });
    }

    /// The buffers the wind leaves the solver in, `(u, v)` faces: the terrain-shaped copies
    /// ([`Self::shape_terrain`]), or the solver's own over flat ground.
    pub fn wind_buffers(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        match &self.terrain {
            Some(t) => (&t.u, &t.v),
            None => (&self.u, &self.v),
        }
    }

    /// Records the terrain pass (`shaders/terrain.wgsl`): the wind faces from the solver's.
    /// Nothing over flat ground. Twin of `sim::terrain::TerrainField::shape_faces`.
    pub fn shape_terrain(&self, device: &wgpu::Device, enc: &mut wgpu::CommandEncoder) {
        let Some(t) = &self.terrain else {
            return;
        };
        let (nx, ny) = (self.nx, self.ny);
        let b = [
            (1, &self.u),
            (2, &self.v),
            (3, &t.cells),
            (4, &t.u),
            (6, &self.u_free),
        ];
        self.dispatch(device, enc, "shape_u", &b, (nx + 1, ny));
        let b = [
            (1, &self.u),
            (2, &self.v),
            (3, &t.cells),
            (5, &t.v),
            (7, &self.v_free),
        ];
        self.dispatch(device, enc, "shape_v", &b, (nx, ny + 1));
    }

    /// The GPU buffer holding field `f` (the editor's map view draws from u, v and p).
    pub fn buffer(&self, f: FieldId) -> &wgpu::Buffer {
        match f {
            FieldId::U => &self.u,
            FieldId::V => &self.v,
            FieldId::P => &self.p,
            FieldId::Div => &self.div,
            FieldId::Curl => &self.curl,
        }
    }

    /// Copies a field of `solver` to the GPU.
    pub fn upload(&self, queue: &wgpu::Queue, solver: &Solver, f: FieldId) {
        let data = match f {
            FieldId::U => &solver.u,
            FieldId::V => &solver.v,
            FieldId::P => &solver.p,
            FieldId::Div => &solver.div,
            FieldId::Curl => &solver.curl,
        };
        queue.write_buffer(self.buffer(f), 0, bytemuck::cast_slice(data));
    }

    /// Copies every state field of `solver` (u, v, p, div, curl) to the GPU.
    pub fn upload_state(&self, queue: &wgpu::Queue, solver: &Solver) {
        for f in [
            FieldId::U,
            FieldId::V,
            FieldId::P,
            FieldId::Div,
            FieldId::Curl,
        ] {
            self.upload(queue, solver, f);
        }
    }

    /// Reads a field back (waits for the GPU).
    pub fn download(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        f: FieldId,
    ) -> Result<Vec<f32>, super::GpuError> {
        self.download_via(
            device,
            &|cb| {
                queue.submit([cb]);
            },
            f,
        )
    }

    /// [`Self::download`], its copy submitted by `submit`.
    pub fn download_via(
        &self,
        device: &wgpu::Device,
        submit: &dyn Fn(wgpu::CommandBuffer),
        f: FieldId,
    ) -> Result<Vec<f32>, super::GpuError> {
        let bytes = super::read_buffer_via(device, submit, self.buffer(f))?;
        Ok(bytemuck::cast_slice::<u8, f32>(&bytes).to_vec())
    }

    /// Sets the share of last step's pressure the next solve starts from
    /// ([`crate::doc::SimParams::warm_start`]), which changes with the pressure solve.
    pub fn set_warm_start(&mut self, queue: &wgpu::Queue, warm: f32) {
        if self.params.decay.to_bits() != warm.to_bits() {
            self.set_params(queue, |p| p.decay = warm);
        }
    }

    /// `min(hx, hz)`, metres: the cell size confinement scales by.
    pub fn cell_size(&self) -> f32 {
        self.params.h
    }

    /// Sets what a layout edit may change between steps: the confinement (its rate,
    /// `confinement_rate` of ε, and its reference speed) and the arrows' response (1/s).
    pub fn set_rates(&mut self, queue: &wgpu::Queue, conf: Confinement, response: f32) {
        let p = &self.params;
        if (p.eps, p.speed_cap, p.inv_speed, p.response)
            != (conf.rate, conf.speed_cap, conf.inv_speed, response)
        {
            self.set_params(queue, |p| {
                p.eps = conf.rate;
                p.speed_cap = conf.speed_cap;
                p.inv_speed = conf.inv_speed;
                p.response = response;
            });
        }
    }

    fn set_params(&mut self, queue: &wgpu::Queue, change: impl FnOnce(&mut Params)) {
        change(&mut self.params);
        queue.write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&self.params));
    }

    /// Records one dispatch of `kernel` over `(x, y)` invocations (`y == 1`: a 1D dispatch)
    /// with `buffers` at their bindings (binding 0 is the parameters). The layouts are the
    /// shaders' own, so each entry point gets exactly the bindings it uses.
    fn dispatch(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        kernel: &str,
        buffers: &[(u32, &wgpu::Buffer)],
        (x, y): (usize, usize),
    ) {
        let k = &self.kernels[kernel];
        // Bind groups are made once per (kernel, buffers) and kept: the buffers live as long
        // as the grid, so after the first step no dispatch creates anything.
        let key = (
            kernel.to_string(),
            buffers
                .iter()
                .map(|&(n, b)| (n, b.clone()))
                .collect::<Vec<_>>(),
        );
        let mut cache = self.bind_groups.lock().unwrap_or_else(|e| e.into_inner());
        let group = cache.entry(key).or_insert_with(|| {
            let mut entries = vec![wgpu::BindGroupEntry {
                binding: 0,
                resource: self.params_buf.as_entire_binding(),
            }];
            for &(binding, b) in buffers {
                entries.push(wgpu::BindGroupEntry {
                    binding,
                    resource: b.as_entire_binding(),
                });
            }
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(kernel),
                layout: &k.layout,
                entries: &entries,
            })
        });
        self.with_timestamps(kernel, &mut |timestamp_writes| {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(kernel),
                timestamp_writes,
            });
            pass.set_pipeline(&k.pipeline);
            pass.set_bind_group(0, &*group, &[]);
            if y == 1 {
                let (gx, gy) = flat_groups(x);
                pass.dispatch_workgroups(gx, gy, 1);
            } else if kernel == "pair" {
                // 16 × 16 tiles (`TILE` in jacobi.wgsl).
                pass.dispatch_workgroups(groups(x, 16), groups(y, 16), 1);
            } else {
                pass.dispatch_workgroups(groups(x, 8), groups(y, 8), 1);
            }
        });
    }

    /// Stops timing the dispatches (each timed dispatch costs the GPU a timestamp pair and
    /// the CPU a read-back).
    pub fn disable_profiling(&self) {
        *self.profiler.lock().unwrap_or_else(|e| e.into_inner()) = None;
    }

    /// Starts timing every dispatch with timestamp queries; false when the device cannot.
    pub fn enable_profiling(&self, device: &wgpu::Device) -> bool {
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return false;
        }
        let bytes = u64::from(2 * PROFILED_DISPATCHES) * 8;
        let buffer = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        let profiler = Profiler {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * PROFILED_DISPATCHES,
            }),
            resolve: buffer(
                "timestamps",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            read: buffer(
                "timestamps read-back",
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            passes: Vec::new(),
        };
        *self.profiler.lock().unwrap_or_else(|e| e.into_inner()) = Some(profiler);
        true
    }

    /// GPU milliseconds per pass over the dispatches since the last call (waits for the GPU);
    /// empty when profiling is off.
    pub fn pass_times(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        submit: &dyn Fn(wgpu::CommandBuffer),
    ) -> Result<std::collections::BTreeMap<&'static str, f64>, super::GpuError> {
        let mut guard = self.profiler.lock().unwrap_or_else(|e| e.into_inner());
        let mut times = std::collections::BTreeMap::new();
        let Some(p) = guard.as_mut() else {
            return Ok(times);
        };
        let n = p.passes.len() as u32;
        if n == 0 {
            return Ok(times);
        }
        let runtime = |message: String| super::GpuError::Runtime {
            what: "reading timestamps".into(),
            message,
        };
        let mut enc = device.create_command_encoder(&Default::default());
        enc.resolve_query_set(&p.set, 0..2 * n, &p.resolve, 0);
        enc.copy_buffer_to_buffer(&p.resolve, 0, &p.read, 0, u64::from(2 * n) * 8);
        submit(enc.finish());
        let (tx, rx) = std::sync::mpsc::channel();
        p.read.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| runtime(e.to_string()))?;
        rx.recv()
            .map_err(|e| runtime(e.to_string()))?
            .map_err(|e| runtime(e.to_string()))?;
        let period_ms = f64::from(queue.get_timestamp_period()) * 1e-6;
        {
            let view = p
                .read
                .slice(..)
                .get_mapped_range()
                .map_err(|e| runtime(e.to_string()))?;
            let stamps: &[u64] = bytemuck::cast_slice(&view);
            for (k, pass) in p.passes.iter().enumerate() {
                let ticks = stamps[2 * k + 1].saturating_sub(stamps[2 * k]);
                *times.entry(*pass).or_insert(0.0) += ticks as f64 * period_ms;
            }
        }
        p.read.unmap();
        p.passes.clear();
        Ok(times)
    }

    fn sync_periodic(&self, device: &wgpu::Device, enc: &mut wgpu::CommandEncoder) {
        if self.periodic {
            self.dispatch(device, enc, "sync_u", &[(1, &self.u)], (self.ny, 1));
            self.dispatch(device, enc, "sync_v", &[(2, &self.v)], (self.nx, 1));
        }
    }

    /// Records the forces over `dt`: the active AGC `splats` (from
    /// [`crate::sim::forces::agc_splats`] at the step's time) and the ambient `layers` with
    /// their FFT `gusts` (from [`crate::sim::forces::Ambient::layer_params`]) pulling with
    /// `coupling` (`1 − e^(−ambient_coupling·dt)`). Twin of [`Solver::apply_forces`].
    #[allow(
        clippy::too_many_arguments,
        reason = "one argument per buffer or setting the pass's shader binds"
    )]
    pub fn forces(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        splats: &[ArrowSplat],
        (layers, gusts, coupling): (&[LayerParams], &[f32], f32),
        dt: f32,
    ) {
        let coupling = if layers.is_empty() { 0.0 } else { coupling };
        if splats.is_empty() && coupling == 0.0 {
            return;
        }
        let grew = [
            upload_growing(
                device,
                queue,
                &mut self.splats,
                "splats",
                bytemuck::cast_slice(splats),
            ),
            upload_growing(
                device,
                queue,
                &mut self.layers,
                "layers",
                bytemuck::cast_slice(layers),
            ),
            upload_growing(
                device,
                queue,
                &mut self.gusts,
                "gusts",
                bytemuck::cast_slice(gusts),
            ),
        ];
        if grew.contains(&true) {
            self.bind_groups
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .clear();
        }
        self.set_params(queue, |p| {
            p.dt = dt;
            p.splats = splats.len() as u32;
            p.layers = if coupling > 0.0 {
                layers.len() as u32
            } else {
                0
            };
            p.coupling = coupling;
        });
        let (nx, ny) = (self.nx, self.ny);
        let on_u = [
            (1, &self.u),
            (2, &self.v),
            (3, &self.splats),
            (4, &self.u_tmp),
            (5, &self.u_free),
            (7, &self.layers),
            (8, &self.gusts),
        ];
        self.dispatch(device, enc, "inc_u", &on_u, (nx + 1, ny));
        let on_v = [
            (1, &self.u),
            (2, &self.v),
            (3, &self.splats),
            (4, &self.v_tmp),
            (5, &self.v_free),
            (7, &self.layers),
            (8, &self.gusts),
        ];
        self.dispatch(device, enc, "inc_v", &on_v, (nx, ny + 1));
        self.dispatch(
            device,
            enc,
            "add",
            &[(4, &self.u_tmp), (6, &self.u)],
            ((nx + 1) * ny, 1),
        );
        self.dispatch(
            device,
            enc,
            "add",
            &[(4, &self.v_tmp), (6, &self.v)],
            (nx * (ny + 1), 1),
        );
        self.sync_periodic(device, enc);
    }

    /// Records the curl pass. Twin of [`Solver::compute_curl`].
    pub fn curl(&self, device: &wgpu::Device, enc: &mut wgpu::CommandEncoder) {
        let b = [
            (1, &self.u),
            (2, &self.v),
            (3, &self.solid),
            (4, &self.curl),
        ];
        self.dispatch(device, enc, "curl", &b, (self.nx, self.ny));
    }

    /// Records vorticity confinement over `dt` (reads the curl). Twin of
    /// [`Solver::confine_vorticity`].
    pub fn confine(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        dt: f32,
    ) {
        if self.params.eps <= 0.0 {
            return;
        }
        self.set_params(queue, |p| p.dt = dt);
        let (nx, ny) = (self.nx, self.ny);
        let force = [
            (1, &self.curl),
            (2, &self.fx),
            (3, &self.fz),
            (4, &self.u),
            (5, &self.v),
        ];
        self.dispatch(device, enc, "force", &force, (nx, ny));
        let on_u = [(2, &self.fx), (4, &self.u), (6, &self.u_free)];
        self.dispatch(device, enc, "apply_u", &on_u, (nx + 1, ny));
        let on_v = [(3, &self.fz), (5, &self.v), (7, &self.v_free)];
        self.dispatch(device, enc, "apply_v", &on_v, (nx, ny + 1));
        self.sync_periodic(device, enc);
    }

    /// Records the divergence pass. Twin of [`Solver::compute_divergence`].
    pub fn divergence(&self, device: &wgpu::Device, enc: &mut wgpu::CommandEncoder) {
        let b = [(1, &self.u), (2, &self.v), (3, &self.solid), (4, &self.div)];
        self.dispatch(device, enc, "divergence", &b, (self.nx, self.ny));
    }

    /// Records the pressure solve: the warm start's decay, then `iterations` Jacobi sweeps or
    /// (`pressure_solve` multigrid) `pressure_cycles` V-cycles. Twin of
    /// [`Solver::solve_pressure`].
    pub fn pressure(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        iterations: usize,
    ) {
        let (nx, ny) = (self.nx, self.ny);
        self.dispatch(device, enc, "decay", &[(6, &self.p)], (nx * ny, 1));
        if self.pressure_solve == PressureSolve::Multigrid {
            let stamp =
                |kernel: &str, f: &mut dyn FnMut(Option<wgpu::ComputePassTimestampWrites<'_>>)| {
                    self.with_timestamps(kernel, f)
                };
            let fine = Fine {
                stamp: &stamp,
                ..self.fine()
            };
            self.multigrid(device)
                .record_cycles(device, enc, fine, self.pressure_cycles);
            return;
        }
        // Two sweeps a dispatch (`pair`), and one (`main`) for an odd count; or one each.
        let per = if self.paired_sweeps { 2 } else { 1 };
        let dispatches = iterations.div_ceil(per);
        for d in 0..dispatches {
            let (from, to) = if d % 2 == 0 {
                (&self.p, &self.p_tmp)
            } else {
                (&self.p_tmp, &self.p)
            };
            let b = [
                (1, from),
                (2, to),
                (3, &self.div),
                (4, &self.flags),
                (5, &self.inv_w),
            ];
            let kernel = if per == 2 && 2 * d + 1 < iterations {
                "pair"
            } else {
                "main"
            };
            self.dispatch(device, enc, kernel, &b, (nx, ny));
        }
        if dispatches % 2 == 1 {
            enc.copy_buffer_to_buffer(&self.p_tmp, 0, &self.p, 0, self.p.size());
        }
    }

    /// The multigrid hierarchy, built and uploaded on first use.
    fn multigrid(&self, device: &wgpu::Device) -> &GpuMultigrid {
        self.multigrid.get_or_init(|| {
            let (flags, [hx, hz], boundary) = &self.mg_source;
            GpuMultigrid::new(device, (self.nx, self.ny), (*hx, *hz), flags, *boundary)
        })
    }

    /// The finest level's arrays of the multigrid solve: pressure, its scratch, divergence.
    fn fine(&self) -> Fine<'_> {
        Fine {
            p: &self.p,
            p_tmp: &self.p_tmp,
            div: &self.div,
            stamp: &super::multigrid::no_stamp,
        }
    }

    /// Calls `f` with the timestamp writes for a pass of `kernel` when profiling.
    fn with_timestamps(
        &self,
        kernel: &str,
        f: &mut dyn FnMut(Option<wgpu::ComputePassTimestampWrites<'_>>),
    ) {
        let mut profiler = self.profiler.lock().unwrap_or_else(|e| e.into_inner());
        let timestamp_writes = profiler.as_mut().and_then(|p| {
            let n = p.passes.len() as u32;
            (n < PROFILED_DISPATCHES).then(|| {
                p.passes.push(pass_of(kernel));
                wgpu::ComputePassTimestampWrites {
                    query_set: &p.set,
                    beginning_of_pass_write_index: Some(2 * n),
                    end_of_pass_write_index: Some(2 * n + 1),
                }
            })
        });
        f(timestamp_writes);
    }

    /// Records the gradient subtraction. Twin of [`Solver::subtract_gradient`].
    pub fn gradient(&self, device: &wgpu::Device, enc: &mut wgpu::CommandEncoder) {
        let (nx, ny) = (self.nx, self.ny);
        let bu = [(1, &self.p), (2, &self.u), (4, &self.u_free)];
        self.dispatch(device, enc, "u_faces", &bu, (nx + 1, ny));
        let bv = [(1, &self.p), (3, &self.v), (5, &self.v_free)];
        self.dispatch(device, enc, "v_faces", &bv, (nx, ny + 1));
        self.sync_periodic(device, enc);
    }

    /// Records advection over `dt` with dissipation `keep`: semi-Lagrangian, or limited
    /// MacCormack with `maccormack`. Twin of [`Solver::advect`].
    pub fn advect(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        dt: f32,
        keep: f32,
        maccormack: bool,
    ) {
        self.set_params(queue, |p| {
            p.dt = dt;
            p.keep = keep;
        });
        let (nx, ny) = (self.nx, self.ny);
        if maccormack {
            for (f, tmp, hat, free, c, size) in [
                (
                    &self.u,
                    &self.u_tmp,
                    &self.u_hat,
                    &self.u_free,
                    "u",
                    (nx + 1, ny),
                ),
                (
                    &self.v,
                    &self.v_tmp,
                    &self.v_hat,
                    &self.v_free,
                    "v",
                    (nx, ny + 1),
                ),
            ] {
                let vel = [(1, &self.u), (2, &self.v)];
                let fwd = [vel[0], vel[1], (3, f), (4, tmp), (5, free)];
                self.dispatch(device, enc, &format!("trace_{c}"), &fwd, size);
                let back = [vel[0], vel[1], (3, tmp), (4, hat), (5, free)];
                self.dispatch(device, enc, &format!("retrace_{c}"), &back, size);
                let fix = [vel[0], vel[1], (3, tmp), (5, free), (6, hat)];
                self.dispatch(device, enc, &format!("maccormack_{c}"), &fix, size);
            }
            enc.copy_buffer_to_buffer(&self.u_hat, 0, &self.u, 0, self.u.size());
            enc.copy_buffer_to_buffer(&self.v_hat, 0, &self.v, 0, self.v.size());
            self.sync_periodic(device, enc);
            return;
        }
        let bu = [
            (1, &self.u),
            (2, &self.v),
            (3, &self.u),
            (4, &self.u_tmp),
            (5, &self.u_free),
        ];
        self.dispatch(device, enc, "advect_u", &bu, (nx + 1, ny));
        let bv = [
            (1, &self.u),
            (2, &self.v),
            (3, &self.v),
            (4, &self.v_tmp),
            (5, &self.v_free),
        ];
        self.dispatch(device, enc, "advect_v", &bv, (nx, ny + 1));
        enc.copy_buffer_to_buffer(&self.u_tmp, 0, &self.u, 0, self.u.size());
        enc.copy_buffer_to_buffer(&self.v_tmp, 0, &self.v, 0, self.v.size());
        self.sync_periodic(device, enc);
    }
}

impl GpuFluid {
    /// Records one substep of everything but the forces, in the CPU solver's order: curl,
    /// vorticity confinement, divergence, pressure, gradient subtraction, advection.
    #[allow(
        clippy::too_many_arguments,
        reason = "one argument per buffer or setting the pass's shader binds"
    )]
    pub fn record_substep(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        enc: &mut wgpu::CommandEncoder,
        dt: f32,
        iterations: usize,
        keep: f32,
        maccormack: bool,
    ) {
        self.curl(device, enc);
        self.confine(device, queue, enc, dt);
        self.divergence(device, enc);
        self.pressure(device, enc, iterations);
        self.gradient(device, enc);
        self.advect(device, queue, enc, dt, keep, maccormack);
    }

    /// [`Self::record_substep`] in a command encoder of its own, submitted.
    pub fn substep_without_forces(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        dt: f32,
        iterations: usize,
        keep: f32,
        maccormack: bool,
    ) {
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("fluid substep"),
        });
        self.record_substep(device, queue, &mut enc, dt, iterations, keep, maccormack);
        queue.submit([enc.finish()]);
    }
}

/// The entry points of each pass's shader: `(kernel name, entry point)`.
fn entry_points(shader: &str) -> &'static [(&'static str, &'static str)] {
    match shader {
        "forces" => &[("inc_u", "inc_u"), ("inc_v", "inc_v"), ("add", "add")],
        "curl" => &[("curl", "main")],
        "confinement" => &[
            ("force", "force"),
            ("apply_u", "apply_u"),
            ("apply_v", "apply_v"),
        ],
        "divergence" => &[("divergence", "main")],
        "jacobi" => &[("decay", "decay"), ("main", "main"), ("pair", "pair")],
        "gradient" => &[("u_faces", "u_faces"), ("v_faces", "v_faces")],
        "advect" => &[
            ("advect_u", "advect_u"),
            ("advect_v", "advect_v"),
            ("trace_u", "trace_u"),
            ("trace_v", "trace_v"),
            ("retrace_u", "retrace_u"),
            ("retrace_v", "retrace_v"),
            ("maccormack_u", "maccormack_u"),
            ("maccormack_v", "maccormack_v"),
        ],
        "periodic" => &[("sync_u", "sync_u"), ("sync_v", "sync_v")],
        "terrain" => &[("shape_u", "shape_u"), ("shape_v", "shape_v")],
        _ => &[],
    }
}
