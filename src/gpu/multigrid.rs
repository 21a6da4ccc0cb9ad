//! The multigrid pressure solve on the GPU (`sim.pressure = "multigrid"`): the CPU builds the
//! hierarchy (`Multigrid::new`, the same levels, links, interpolation tables and smoothing
//! weights as the CPU solver's) and uploads it once; a V-cycle is then relaxation passes
//! (damped Jacobi, red–black on the coarsest level), restrictions and prolongations, each a
//! compute pass (`shaders/mg_*.wgsl`) whose CPU twin is the function of
//! `sim::solver::multigrid` it names. Every level keeps its explicit links, the finest too.

use crate::doc::Boundary;
use crate::sim::solver::multigrid::{Multigrid, coarsest_sweeps};
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

/// One level's parameters; mirrors `struct Mg` in `shaders/mg_common.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct MgParams {
    pub nx: u32,
    pub ny: u32,
    pub cnx: u32,
    pub cny: u32,
    pub wraps: u32,
    pub colour: u32,
    pub coarse_x: u32,
    pub coarse_z: u32,
    pub b_scale: f32,
    /// Damped Jacobi's weight (`colour` [`DAMPED`]).
    pub weight: f32,
    /// On the coarsest level: the red–black sweeps that solve it (`mg_coarsest`).
    pub sweeps: u32,
    pub _pad: f32,
}

/// `MgParams::colour` for a damped Jacobi pass (every cell, weighted) instead of a red–black
/// half sweep.
pub const DAMPED: u32 = 2;

/// The multigrid header every multigrid pass is compiled with.
pub const MG_COMMON: &str = include_str!("../../shaders/mg_common.wgsl");

/// The multigrid passes: `(name, source)`, each compiled after [`MG_COMMON`].
pub const MG_SHADERS: [(&str, &str); 4] = [
    ("mg_smooth", include_str!("../../shaders/mg_smooth.wgsl")),
    (
        "mg_coarsest",
        include_str!("../../shaders/mg_coarsest.wgsl"),
    ),
    (
        "mg_restrict",
        include_str!("../../shaders/mg_restrict.wgsl"),
    ),
    ("mg_prolong", include_str!("../../shaders/mg_prolong.wgsl")),
];

/// The full WGSL of multigrid pass `name`.
pub fn shader_source(name: &str) -> Option<String> {
    MG_SHADERS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| format!("{MG_COMMON}\n{s}"))
}

/// The most cells a coarsest level may have to be solved in one dispatch (`CAP` in
/// `shaders/mg_coarsest.wgsl`: two copies fill WebGPU's default 16 KiB of workgroup memory).
/// Coarsening stops at 64 cells or so; larger coarsest levels (no axis left to halve) take
/// the separate half sweeps.
pub const COARSEST_CAP: usize = 2048;

/// One level's buffers on the GPU (the finest level's unknowns, scratch and right-hand side
/// are the solver's pressure, its scratch and the divergence, passed in).
struct GpuLevel {
    nx: usize,
    ny: usize,
    ax: wgpu::Buffer,
    az: wgpu::Buffer,
    diag: wgpu::Buffer,
    inv_d: wgpu::Buffer,
    x: wgpu::Buffer,
    tmp: wgpu::Buffer,
    b: wgpu::Buffer,
    from_x: wgpu::Buffer,
    from_z: wgpu::Buffer,
    /// Parameters: red–black colour 0 (restriction and prolongation use it too) and colour 1,
    /// then one per damped pass: the level's pre-smoothing weights, then its post-smoothing
    /// weights.
    params: Vec<wgpu::Buffer>,
    /// How many damped passes before and after the coarse correction.
    pre: usize,
    post: usize,
}

struct Pass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

/// Bind groups by (pass, level, parameters, direction).
type Groups = std::collections::HashMap<(&'static str, usize, usize, u8), wgpu::BindGroup>;

/// The hierarchy on the GPU and the passes that run a V-cycle on it.
pub struct GpuMultigrid {
    levels: Vec<GpuLevel>,
    coarsest_sweeps: usize,
    smooth: Pass,
    coarsest: Pass,
    restrict: Pass,
    prolong: Pass,
    /// Bind groups, made on first use and kept (the buffers live as long as the grid).
    groups: std::sync::Mutex<Groups>,
}

fn storage(device: &wgpu::Device, label: &str, data: &[u8]) -> wgpu::Buffer {
    // wgpu refuses empty bindings: a level without a table gets one zero element.
    let data = if data.is_empty() {
        &[0u8; 12][..]
    } else {
        data
    };
    super::storage(device, label, data)
}

impl GpuMultigrid {
    /// Builds the hierarchy for a grid of `nx × ny` cells of `hx × hz` metres with the CPU
    /// solver's pressure `flags`, and uploads it.
    pub fn new(
        device: &wgpu::Device,
        (nx, ny): (usize, usize),
        (hx, hz): (f32, f32),
        flags: &[u8],
        boundary: Boundary,
    ) -> Self {
        Self::upload(
            device,
            &Multigrid::new(nx, ny, hx, hz, flags, boundary),
            hx * hz,
        )
    }

    /// Uploads a hierarchy built on the CPU (`vol`: the finest cell's area, `−vol` scaling the
    /// divergence into the finest right-hand side).
    pub(crate) fn upload(device: &wgpu::Device, mg: &Multigrid, vol: f32) -> Self {
        let n = mg.levels.len();
        let levels = (0..n)
            .map(|l| {
                let lv = &mg.levels[l];
                let coarse = mg.levels.get(l + 1);
                let f = |label: &str, v: &[f32]| storage(device, label, bytemuck::cast_slice(v));
                // The finest level's unknowns, scratch and right-hand side are the solver's.
                let cells = vec![0.0f32; if l == 0 { 0 } else { lv.nx * lv.ny }];
                let (pre, post) = (
                    mg.smoothing.weights(l, false),
                    mg.smoothing.weights(l, true),
                );
                let passes = [(0u32, 1.0f32), (1, 1.0)]
                    .into_iter()
                    .chain(pre.iter().chain(post).map(|&w| (DAMPED, w)));
                let params = passes.map(|(colour, weight)| {
                    let p = MgParams {
                        nx: lv.nx as u32,
                        ny: lv.ny as u32,
                        cnx: coarse.map_or(0, |c| c.nx as u32),
                        cny: coarse.map_or(0, |c| c.ny as u32),
                        wraps: u32::from(lv.x_axis.wraps),
                        colour,
                        coarse_x: u32::from(coarse.is_some_and(|c| c.x_axis.coarsened)),
                        coarse_z: u32::from(coarse.is_some_and(|c| c.z_axis.coarsened)),
                        b_scale: if l == 0 { -vol } else { 1.0 },
                        weight,
                        sweeps: if l + 1 == n {
                            coarsest_sweeps(lv) as u32
                        } else {
                            0
                        },
                        _pad: 0.0,
                    };
                    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("multigrid level"),
                        contents: bytemuck::bytes_of(&p),
                        usage: wgpu::BufferUsages::STORAGE,
                    })
                });
                let params = params.collect();
                GpuLevel {
                    nx: lv.nx,
                    ny: lv.ny,
                    ax: f("mg ax", &lv.ax),
                    az: f("mg az", &lv.az),
                    diag: f("mg diag", &lv.diag),
                    inv_d: f("mg inv_d", &lv.inv_d),
                    x: f("mg x", &cells),
                    tmp: f("mg tmp", &cells),
                    b: f("mg b", &cells),
                    from_x: storage(device, "mg from_x", bytemuck::cast_slice(&lv.from_x)),
                    from_z: storage(device, "mg from_z", bytemuck::cast_slice(&lv.from_z)),
                    params,
                    pre: pre.len(),
                    post: post.len(),
                }
            })
            .collect();
        let pass = |name: &str| {
            let source = shader_source(name).expect("listed");
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(name),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: None,
                module: &module,
                entry_point: Some("main"),
                compilation_options: Default::default(),
                cache: None,
            });
            let layout = pipeline.get_bind_group_layout(0);
            Pass { pipeline, layout }
        };
        Self {
            levels,
            coarsest_sweeps: coarsest_sweeps(mg.levels.last().expect("one level at least")),
            smooth: pass("mg_smooth"),
            coarsest: pass("mg_coarsest"),
            restrict: pass("mg_restrict"),
            prolong: pass("mg_prolong"),
            groups: Default::default(),
        }
    }

    #[allow(
        clippy::too_many_arguments,
        reason = "one argument per buffer or setting the pass's shader binds"
    )]
    fn run(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        fine: Fine,
        (pass, name): (&Pass, &'static str),
        key: (usize, usize, u8),
        buffers: &[(u32, &wgpu::Buffer)],
        workgroups: [u32; 2],
    ) {
        let mut groups = self.groups.lock().unwrap_or_else(|e| e.into_inner());
        let group = groups
            .entry((name, key.0, key.1, key.2))
            .or_insert_with(|| {
                let entries: Vec<_> = buffers
                    .iter()
                    .map(|&(binding, b)| wgpu::BindGroupEntry {
                        binding,
                        resource: b.as_entire_binding(),
                    })
                    .collect();
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(name),
                    layout: &pass.layout,
                    entries: &entries,
                })
            });
        (fine.stamp)(name, &mut |timestamp_writes| {
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(name),
                timestamp_writes,
            });
            cp.set_pipeline(&pass.pipeline);
            cp.set_bind_group(0, &*group, &[]);
            cp.dispatch_workgroups(workgroups[0], workgroups[1], 1);
        });
    }

    /// 8 × 8 workgroups over `x × y` cells, as the level passes take them.
    fn tiles(x: usize, y: usize) -> [u32; 2] {
        [(x as u32).div_ceil(8), (y as u32).div_ceil(8)]
    }

    /// The level's `(x, tmp, b)`: the solver's own on the finest level.
    fn arrays<'a>(
        &'a self,
        l: usize,
        fine: Fine<'a>,
    ) -> (&'a wgpu::Buffer, &'a wgpu::Buffer, &'a wgpu::Buffer) {
        if l == 0 {
            (fine.p, fine.p_tmp, fine.div)
        } else {
            let lv = &self.levels[l];
            (&lv.x, &lv.tmp, &lv.b)
        }
    }

    /// Records `sweeps` red–black sweeps on level `l`, colour `first` first (an even number
    /// of half sweeps, so the result is back in the level's `x`). Twin of
    /// `multigrid::smooth` with `Relax::RedBlack(first)`.
    pub fn record_sweeps(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        fine: Fine,
        l: usize,
        sweeps: usize,
        first: usize,
    ) {
        for h in 0..2 * sweeps {
            self.record_pass(device, enc, fine, l, (first + h) % 2, h % 2 == 1);
        }
    }

    /// Records the coarsest level's solve: its red–black sweeps, colour 0 first, in one
    /// dispatch (`mg_coarsest`) when it has at most [`COARSEST_CAP`] cells, else as separate
    /// half sweeps; the same values either way, back in the level's `x`.
    pub fn record_coarsest(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        fine: Fine,
    ) {
        let l = self.levels.len() - 1;
        let lv = &self.levels[l];
        let cells = lv.nx * lv.ny;
        if cells > COARSEST_CAP {
            self.record_sweeps(device, enc, fine, l, self.coarsest_sweeps, 0);
            return;
        }
        let (x, tmp, _) = self.arrays(l, fine);
        let buffers = self.relax_buffers(l, fine, 0, false);
        // One workgroup: the level fits its memory.
        let pass = (&self.coarsest, "mg_coarsest");
        self.run(device, enc, fine, pass, (l, 0, 0), &buffers, [1, 1]);
        enc.copy_buffer_to_buffer(tmp, 0, x, 0, (cells * 4) as u64);
    }

    /// The bindings of a relaxation pass on level `l` (`mg_smooth`, `mg_coarsest`) with
    /// parameters `params`, from `x` into `tmp` (`back`: from `tmp` into `x`).
    fn relax_buffers<'a>(
        &'a self,
        l: usize,
        fine: Fine<'a>,
        params: usize,
        back: bool,
    ) -> [(u32, &'a wgpu::Buffer); 7] {
        let lv = &self.levels[l];
        let (x, tmp, b) = self.arrays(l, fine);
        let (from, to) = if back { (tmp, x) } else { (x, tmp) };
        [
            (0, &lv.params[params]),
            (1, from),
            (2, to),
            (3, b),
            (4, &lv.ax),
            (5, &lv.az),
            (6, &lv.inv_d),
        ]
    }

    /// Records level `l`'s damped smoothing passes before (`post` false) or after its coarse
    /// correction (an even number, so the result is back in the level's `x`). Twin of
    /// `multigrid::smooth` with `Relax::Damped` and the level's weights.
    pub fn record_smoothing(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        fine: Fine,
        l: usize,
        post: bool,
    ) {
        let lv = &self.levels[l];
        let (first, n) = if post {
            (2 + lv.pre, lv.post)
        } else {
            (2, lv.pre)
        };
        for h in 0..n {
            self.record_pass(device, enc, fine, l, first + h, h % 2 == 1);
        }
    }

    /// Records one relaxation pass on level `l` with parameters `params` (0, 1: a red–black
    /// half sweep of that colour; from 2: a damped pass, see `GpuLevel::params`), from `x`
    /// into `tmp` (`back`: from `tmp` into `x`).
    pub fn record_pass(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        fine: Fine,
        l: usize,
        params: usize,
        back: bool,
    ) {
        let lv = &self.levels[l];
        let buffers = self.relax_buffers(l, fine, params, back);
        let key = (l, params, u8::from(back));
        self.run(
            device,
            enc,
            fine,
            (&self.smooth, "mg_smooth"),
            key,
            &buffers,
            Self::tiles(lv.nx, lv.ny),
        );
    }

    /// Records the restriction of level `l`'s residual into level `l + 1`'s right-hand side.
    /// Twin of `multigrid::restrict`.
    pub fn record_restrict(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        fine: Fine,
        l: usize,
    ) {
        let lv = &self.levels[l];
        let (x, _, b) = self.arrays(l, fine);
        let c = &self.levels[l + 1];
        let buffers = [
            (0, &lv.params[0]),
            (1, x),
            (3, b),
            (4, &lv.ax),
            (5, &lv.az),
            (6, &lv.diag),
            (7, &c.b),
        ];
        self.run(
            device,
            enc,
            fine,
            (&self.restrict, "mg_restrict"),
            (l, 0, 0),
            &buffers,
            Self::tiles(c.nx, c.ny),
        );
    }

    /// Records the prolongation of level `l + 1`'s correction into level `l`'s unknowns.
    /// Twin of `multigrid::expand` then `multigrid::add_correction` on every row.
    pub fn record_prolong(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        fine: Fine,
        l: usize,
    ) {
        let lv = &self.levels[l];
        let (x, _, _) = self.arrays(l, fine);
        let c = &self.levels[l + 1];
        let buffers = [
            (0, &lv.params[0]),
            (2, x),
            (3, &c.x),
            (6, &c.inv_d),
            (7, &lv.inv_d),
            (8, &lv.from_x),
            (9, &lv.from_z),
        ];
        self.run(
            device,
            enc,
            fine,
            (&self.prolong, "mg_prolong"),
            (l, 0, 0),
            &buffers,
            Self::tiles(lv.nx, lv.ny),
        );
    }

    /// Records `cycles` V-cycles on the finest level (the warm start already in `fine.p`).
    /// Twin of `Multigrid::solve`.
    pub fn record_cycles(
        &self,
        device: &wgpu::Device,
        enc: &mut wgpu::CommandEncoder,
        fine: Fine,
        cycles: usize,
    ) {
        let n = self.levels.len();
        for _ in 0..cycles {
            if n == 1 {
                self.record_coarsest(device, enc, fine);
                continue;
            }
            for l in 0..n - 1 {
                // None on the finest level (its weights before are empty).
                self.record_smoothing(device, enc, fine, l, false);
                self.record_restrict(device, enc, fine, l);
                enc.clear_buffer(&self.levels[l + 1].x, 0, None);
            }
            self.record_coarsest(device, enc, fine);
            for l in (0..n - 1).rev() {
                self.record_prolong(device, enc, fine, l);
                self.record_smoothing(device, enc, fine, l, true);
            }
        }
    }

    /// Reads level `l`'s unknowns and right-hand side back (tests; waits for the GPU).
    pub fn read_level(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        l: usize,
    ) -> Result<(Vec<f32>, Vec<f32>), super::GpuError> {
        let lv = &self.levels[l];
        let read = |b: &wgpu::Buffer| -> Result<Vec<f32>, super::GpuError> {
            let bytes = super::read_buffer_via(
                device,
                &|cb| {
                    queue.submit([cb]);
                },
                b,
            )?;
            Ok(bytemuck::cast_slice::<u8, f32>(&bytes).to_vec())
        };
        Ok((read(&lv.x)?, read(&lv.b)?))
    }

    /// Writes level `l`'s unknowns and right-hand side (tests).
    pub fn write_level(&self, queue: &wgpu::Queue, l: usize, x: &[f32], b: &[f32]) {
        let lv = &self.levels[l];
        queue.write_buffer(&lv.x, 0, bytemuck::cast_slice(x));
        queue.write_buffer(&lv.b, 0, bytemuck::cast_slice(b));
    }
}

/// Hands a pass its timestamp writes (the fluid passes' profiler, when it runs): called with
/// the pass's name and a function that begins the pass with them.
pub type Stamp<'a> = &'a dyn Fn(&str, &mut dyn FnMut(Option<wgpu::ComputePassTimestampWrites<'_>>));

/// No timestamps.
pub fn no_stamp(_: &str, f: &mut dyn FnMut(Option<wgpu::ComputePassTimestampWrites<'_>>)) {
    f(None);
}

/// The finest level's unknowns, scratch and right-hand side: the solver's pressure, its
/// scratch buffer and the divergence.
#[derive(Clone, Copy)]
pub struct Fine<'a> {
    pub p: &'a wgpu::Buffer,
    pub p_tmp: &'a wgpu::Buffer,
    pub div: &'a wgpu::Buffer,
    pub stamp: Stamp<'a>,
}

#[cfg(test)]
mod tests {
    //! Each multigrid pass on the GPU (lavapipe in CI, which must have it) against its CPU
    //! twin, from the same random state, on the obstacles example with non-square cells and
    //! every boundary mode; then whole V-cycles.
    use super::*;
    use crate::gpu::read_buffer;
    use crate::sim::Solver;
    use crate::sim::solver::multigrid::{
        Relax, add_correction, expand, relax_passes, restrict, smooth,
    };

    fn noise(n: usize, seed: u64, a: f32) -> Vec<f32> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((s >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0) * a
            })
            .collect()
    }

    /// Max |GPU − CPU| within `rel` of the CPU field's peak.
    fn check(what: &str, gpu: &[f32], cpu: &[f32], rel: f32) {
        assert_eq!(gpu.len(), cpu.len(), "{what}");
        let peak = cpu.iter().fold(0.0f32, |m, x| m.max(x.abs()));
        let err = gpu
            .iter()
            .zip(cpu)
            .fold(0.0f32, |m, (a, b)| m.max((a - b).abs()));
        println!("{what}: max |GPU − CPU| {err:.2e}, peak {peak:.3}");
        assert!(peak > 0.0, "{what}: an all-zero field tests nothing");
        assert!(
            err <= rel * peak,
            "{what}: {err} over {} (peak {peak})",
            rel * peak
        );
    }

    #[test]
    fn each_multigrid_pass_and_whole_cycles_match_the_cpu() {
        let Some(ctx) = crate::gpu::test_context(|_| {}) else {
            return;
        };
        let (device, queue) = (&ctx.device, &ctx.queue);
        let mut layout = crate::doc::parse(include_str!("../../layouts/obstacles.json")).unwrap();
        // Odd sizes on purpose (coarse cells with one child) and non-square cells.
        layout.world.grid = [41, 27];
        for (k, boundary) in [Boundary::Closed, Boundary::Open, Boundary::Periodic]
            .into_iter()
            .enumerate()
        {
            layout.sim.boundary = boundary;
            let s = Solver::new(&layout);
            let (nx, ny, vol) = (s.nx, s.ny, s.hx * s.hz);
            let mut mg = Multigrid::new(nx, ny, s.hx, s.hz, &s.flags, boundary);
            assert!(mg.levels.len() >= 3, "{:?}", mg.levels.len());
            let gpu = GpuMultigrid::upload(device, &mg, vol);
            let seed = 10 * k as u64;
            let (p0, div) = (noise(nx * ny, seed, 2.0), noise(nx * ny, seed + 1, 3.0));
            let buf = |v: &[f32]| crate::gpu::storage(device, "test", bytemuck::cast_slice(v));
            let (p, p_tmp, d) = (buf(&p0), buf(&p0), buf(&div));
            let fine = Fine {
                p: &p,
                p_tmp: &p_tmp,
                div: &d,
                stamp: &no_stamp,
            };
            let read = |b: &wgpu::Buffer| -> Vec<f32> {
                bytemuck::cast_slice(&read_buffer(device, queue, b).unwrap()).to_vec()
            };
            let record = |f: &dyn Fn(&mut wgpu::CommandEncoder)| {
                queue.write_buffer(&p, 0, bytemuck::cast_slice(&p0));
                let mut enc = device.create_command_encoder(&Default::default());
                f(&mut enc);
                queue.submit([enc.finish()]);
            };
            let tag = |what: &str| format!("{what} ({boundary:?})");

            // One red–black half sweep of each colour and the first damped pass after the
            // correction on the finest level (its parameters follow those before it).
            let w = mg.smoothing.weights(0, true)[0];
            let first_post = 2 + mg.smoothing.weights(0, false).len();
            for (params, relax) in [
                (0, Relax::RedBlack(0)),
                (1, Relax::RedBlack(1)),
                (first_post, Relax::Damped(&[w])),
            ] {
                let mut cpu = vec![0.0; nx * ny];
                relax_passes(&mg.levels[0], &p0, &mut cpu, &div, -vol, 1, relax, false);
                record(&|e| gpu.record_pass(device, e, fine, 0, params, false));
                check(
                    &tag(&format!("smooth {relax:?}")),
                    &read(&p_tmp),
                    &cpu,
                    1e-5,
                );
            }
            // A coarse level's smoothing after its correction, and two red–black sweeps (its
            // own unknowns and right-hand side).
            let lv = &mg.levels[1];
            let (x1, b1) = (
                noise(lv.nx * lv.ny, seed + 2, 1.0),
                noise(lv.nx * lv.ny, seed + 3, 1.0),
            );
            let w = mg.smoothing.weights(1, true);
            let (mut cx, mut ct) = (x1.clone(), x1.clone());
            smooth(
                lv,
                &mut cx,
                &mut ct,
                &b1,
                1.0,
                w.len(),
                Relax::Damped(w),
                false,
            );
            gpu.write_level(queue, 1, &x1, &b1);
            record(&|e| gpu.record_smoothing(device, e, fine, 1, true));
            check(
                &tag("damped smoothing level 1"),
                &gpu.read_level(device, queue, 1).unwrap().0,
                &cx,
                1e-5,
            );
            let (mut cx, mut ct) = (x1.clone(), x1.clone());
            smooth(lv, &mut cx, &mut ct, &b1, 1.0, 4, Relax::RedBlack(1), false);
            gpu.write_level(queue, 1, &x1, &b1);
            record(&|e| gpu.record_sweeps(device, e, fine, 1, 2, 1));
            check(
                &tag("red–black sweeps level 1"),
                &gpu.read_level(device, queue, 1).unwrap().0,
                &cx,
                1e-5,
            );

            // Restriction of the finest residual.
            let (f, c) = mg.levels.split_at_mut(1);
            restrict(&f[0], &p0, &div, -vol, &mut c[0]);
            record(&|e| gpu.record_restrict(device, e, fine, 0));
            check(
                &tag("restrict"),
                &gpu.read_level(device, queue, 1).unwrap().1,
                &mg.levels[1].b,
                1e-5,
            );

            // Prolongation of a coarse correction.
            mg.levels[1].x.clone_from(&x1);
            let (f, c) = mg.levels.split_at_mut(1);
            expand(&mut f[0], &c[0]);
            let mut cpu = p0.clone();
            for (j, row) in cpu.chunks_mut(nx).enumerate() {
                add_correction(&f[0], j, row);
            }
            gpu.write_level(queue, 1, &x1, &b1);
            record(&|e| gpu.record_prolong(device, e, fine, 0));
            check(&tag("prolong"), &read(&p), &cpu, 1e-5);

            // Two whole V-cycles.
            let (mut x, mut t) = (p0.clone(), p0.clone());
            mg.solve(&mut x, &mut t, &div, -vol, 2);
            record(&|e| gpu.record_cycles(device, e, fine, 2));
            check(&tag("two V-cycles"), &read(&p), &x, 1e-4);
        }
    }
}
