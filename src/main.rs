//! The `windloom` binary: parses arguments and hands over to the library.

use anyhow::Context;
use clap::{Parser, Subcommand};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use windloom::{bake, doc, io};

const AFTER_HELP: &str = "\
Examples:
  windloom                               open the editor on the bundled default layout
  windloom layouts/obstacles.json        open the editor on a layout
  windloom layouts/meadow.json --view 3d open the editor on the grass in 3D
  windloom my-new-level.json             start a new layout there (Save writes it)
  windloom validate layouts/*.json       check layout files, print every error
  windloom schema > layout.schema.json   the JSON Schema of the layout format
  windloom fmt my-level.json             rewrite a layout in canonical form
  windloom bake layouts/meadow.json --out bake/ --format exr --format fga
  windloom bake layouts/obstacles.json --out bake/ --frames 48 --fps 24 --loop
  windloom render layouts/obstacles.json -o obstacles.png --size 1600x1200 --time 8
  windloom render layouts/meadow.json --view grass -o grass.png --camera \"40,1.6,52,48,0.2,40\"
  windloom bench --grass 1000000 --model cwd --json
  windloom bench --backend cpu --grid 1000 --iterations 20 --steps 30 --json";

/// Author wind over a top-down map of a level, simulate it, and export it for game engines.
#[derive(Parser)]
#[command(version, about, after_help = AFTER_HELP, args_conflicts_with_subcommands = true)]
struct Cli {
    /// Layout to open in the editor (the bundled default layout when omitted; a new layout,
    /// which Save writes there, when no such file exists yet in an existing folder).
    file: Option<PathBuf>,
    /// Where the editor's live wind runs, for this run (the View menu changes it later);
    /// without it, the choice last made in the View menu.
    #[arg(long, value_enum)]
    backend: Option<Backend>,
    /// The view the editor opens on: the map, the grass in 3D, or both side by side (the
    /// View menu changes it later); without it, the view last used.
    #[arg(long, value_enum)]
    view: Option<windloom::app::Central>,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Check layout files. Prints `FILE: ok` or every error as `FILE:LINE:COLUMN: path: message`;
    /// exits 0 only if every file is valid.
    ///
    /// Example: windloom validate layouts/meadow.json layouts/two-winds.json
    Validate {
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// Print the JSON Schema of the layout format (also in docs/layout.schema.json).
    ///
    /// Example: windloom schema > layout.schema.json
    Schema,
    /// Rewrite layout files in canonical form (stable field order, pretty-printed), atomically.
    /// Invalid files are reported and left untouched.
    ///
    /// Example: windloom fmt layouts/*.json
    Fmt {
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// Simulate a layout headless and export the wind for game engines, with a manifest.json.
    ///
    /// Formats (repeat --format; default all): exr (float RGB), png8 / png16 (flowmaps, RG
    /// centred on 0.5), fga (Unreal vector field, ≤128 per axis, area-averaged), vf (Unity
    /// VF_V), raw (f32 + manifest), atlas (all frames in one 16-bit PNG flipbook). Frame k is
    /// the wind at exactly warmup + k/fps seconds. The new bake replaces the output folder as a
    /// whole when everything is written (files you put there stay); Ctrl-C or an error leaves
    /// the folder as it was.
    ///
    /// Example: windloom bake layouts/obstacles.json --out bake/ --frames 48 --fps 24 --loop
    Bake {
        /// The layout file to bake.
        layout: PathBuf,
        /// Output folder (created if missing).
        #[arg(long, short)]
        out: PathBuf,
        /// Formats to write (repeatable).
        #[arg(long = "format", value_enum)]
        formats: Vec<FormatArg>,
        /// Seconds simulated before the first frame.
        #[arg(long, default_value_t = 5.0)]
        warmup: f32,
        /// Frames to capture (1: one steady frame).
        #[arg(long, default_value_t = 1)]
        frames: usize,
        /// Frames per second of the sequence.
        #[arg(long, default_value_t = 30.0)]
        fps: f32,
        /// Make the sequence loop seamlessly (cross-fade of two simulated runs).
        #[arg(long = "loop")]
        looped: bool,
        /// Override the layout's grid, e.g. 256x256.
        #[arg(long, value_parser = parse_grid)]
        grid: Option<[u32; 2]>,
        /// EXR as 16-bit half floats.
        #[arg(long)]
        half: bool,
        /// Most disk the bake may take (e.g. 500M, 16G, 2T); checked before it starts against
        /// an upper bound of what it writes, as is the free space.
        #[arg(long, default_value = "16G", value_parser = parse_bytes)]
        max_disk: u64,
        /// Solver to run.
        #[arg(long, value_enum, default_value_t = Backend::Cpu)]
        backend: Backend,
    },
    /// Draw a top-down picture of a layout and its simulated wind (PNG, tiny-skia).
    ///
    /// Example: windloom render layouts/obstacles.json -o obstacles.png --size 1600x1200 --time 8
    Render {
        /// The layout file to draw.
        layout: PathBuf,
        /// The PNG to write.
        #[arg(short, long)]
        output: PathBuf,
        /// Picture size in pixels, WxH.
        #[arg(long, default_value = "1600x1000", value_parser = parse_grid)]
        size: [u32; 2],
        /// Simulated seconds before the picture is taken.
        #[arg(long, default_value_t = 6.0)]
        time: f32,
        /// What to draw: the top-down map of the wind, or the grass in 3D (on the GPU).
        #[arg(long, value_enum, default_value_t = ViewArg::Map)]
        view: ViewArg,
        /// The 3D view's camera, "eye_x,eye_y,eye_z,target_x,target_y,target_z" in metres
        /// (y up); default: the whole world from the south-west, above it, framed as the editor's
        /// "frame all" frames it.
        #[arg(long, value_parser = parse_camera, allow_hyphen_values = true)]
        camera: Option<[f32; 6]>,
        /// With --view grass: bend the blades by eqs. 12–14 exactly as the CWD-Sim paper prints
        /// them (to see the strong-wind problem windloom's reading solves).
        #[arg(long)]
        paper_literal: bool,
        /// With --view grass: draw with this blade model instead of the layout's.
        #[arg(long, value_enum)]
        model: Option<GrassModelArg>,
        /// With --view grass: roll a sphere through the grass first, "x0,z0,x1,z1,radius" in
        /// metres, over the last second; its trail shows in the picture.
        #[arg(long, value_parser = parse_push, allow_hyphen_values = true)]
        push: Option<[f32; 5]>,
        /// With --view grass: colour the grass and ground by the wind's speed at this opacity
        /// (0 to 1), on the map view's scale, as the editor's "wind colours" toggle does.
        #[arg(long, value_parser = parse_opacity)]
        wind_colours: Option<f32>,
        /// With --view grass: leave out the AGC arrows, which are otherwise drawn over the
        /// grass as the editor's 3D view draws them (for a picture of the grass alone).
        #[arg(long)]
        no_arrows: bool,
        /// The speed (m/s, 0.5 to 200) at the top of the speed colours, in the map and in the
        /// grass's wind colours, as the editor's View → Fixed speed scale; default: the
        /// field's peak. Pictures of different layouts or times then use the same colours.
        #[arg(long, value_parser = parse_speed_scale)]
        speed_scale: Option<f32>,
    },
    /// Benchmark the solver: median and min ms per step, the per-pass split, the bytes each
    /// pass moves and the memory bandwidth measured in the same run.
    ///
    /// Example: windloom bench --backend cpu --grid 1000 --iterations 20 --steps 30 --json
    Bench {
        /// Which solver to time.
        #[arg(long, value_enum, default_value_t = Backend::Cpu)]
        backend: Backend,
        /// Grid: N for N × N cells, or WIDTHxHEIGHT as `bake --grid` takes it (e.g. 240x160).
        #[arg(long, default_value = "512", value_parser = parse_grid_or_side)]
        grid: [u32; 2],
        /// Jacobi pressure iterations per step.
        #[arg(long, default_value_t = 20)]
        iterations: u32,
        /// Timed steps.
        #[arg(long, default_value_t = 30)]
        steps: usize,
        /// Untimed steps first, so the field is developed.
        #[arg(long, default_value_t = 5)]
        warmup: usize,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Layout to run, resized to the grid (default: the bundled obstacles example; `all`:
        /// every bundled example in turn, printed as a JSON array with --json).
        #[arg(long)]
        layout: Option<PathBuf>,
        /// Advection scheme.
        #[arg(long, value_enum, default_value_t = AdvectionArg::SemiLagrangian)]
        advection: AdvectionArg,
        /// Pressure solve: Jacobi (--iterations sweeps) or multigrid (--cycles V-cycles).
        #[arg(long, value_enum, default_value_t = PressureArg::Jacobi)]
        pressure: PressureArg,
        /// Multigrid V-cycles per step (with --pressure multigrid).
        #[arg(long, default_value_t = 2)]
        cycles: u32,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// Time the grass instead: about N blades of the layout (default: the bundled meadow)
        /// drawn at --size offscreen on the GPU.
        #[arg(long)]
        grass: Option<usize>,
        /// Grass model to time.
        #[arg(long, value_enum, default_value_t = GrassModelArg::Cwd)]
        model: GrassModelArg,
        /// Culling and LOD for --grass (off: every blade drawn at full detail).
        #[arg(long, value_enum, default_value_t = OnOff::On)]
        cull: OnOff,
        /// The camera for --grass, "eye_x,eye_y,eye_z,target_x,target_y,target_z"; default:
        /// standing in the grass 1.7 m up near the south-west corner, looking across.
        #[arg(long, value_parser = parse_camera, allow_hyphen_values = true)]
        camera: Option<[f32; 6]>,
        /// Picture size for --grass, WxH.
        #[arg(long, default_value = "1920x1080", value_parser = parse_grid)]
        size: [u32; 2],
        /// With --grass: draw the wind colours at this opacity (0 to 1), to time them.
        #[arg(long, value_parser = parse_opacity)]
        wind_colours: Option<f32>,
    },
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Backend {
    /// The CPU reference solver.
    Cpu,
    /// The GPU solver (wgpu: Vulkan, Metal, DX12; lavapipe counts).
    Gpu,
    /// The GPU when a hardware adapter exists, else the CPU (for the editor: on a software
    /// adapter, whichever measures faster for the grid).
    Auto,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum FormatArg {
    Exr,
    Png8,
    Png16,
    Fga,
    Vf,
    Raw,
    Atlas,
}

impl From<FormatArg> for bake::Format {
    fn from(f: FormatArg) -> Self {
        match f {
            FormatArg::Exr => Self::Exr,
            FormatArg::Png8 => Self::Png8,
            FormatArg::Png16 => Self::Png16,
            FormatArg::Fga => Self::Fga,
            FormatArg::Vf => Self::Vf,
            FormatArg::Raw => Self::Raw,
            FormatArg::Atlas => Self::Atlas,
        }
    }
}

/// `NXxNY` → `[nx, ny]`.
fn parse_grid(s: &str) -> Result<[u32; 2], String> {
    let (a, b) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT like 256x128, got {s:?}"))?;
    let n = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| format!("expected WIDTHxHEIGHT like 256x128, got {s:?}"))
    };
    Ok([n(a)?, n(b)?])
}

/// `N` → `[N, N]`, or `NXxNY` as [`parse_grid`].
fn parse_grid_or_side(s: &str) -> Result<[u32; 2], String> {
    match s.trim().parse::<u32>() {
        Ok(n) => Ok([n, n]),
        Err(_) if s.contains(['x', 'X']) => parse_grid(s),
        Err(_) => Err(format!(
            "expected N (cells a side) or WIDTHxHEIGHT like 256x128, got {s:?}"
        )),
    }
}

/// `500M`, `16G`, `2T`, `1048576` → bytes (binary units: 1K = 1024).
fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let err = || format!("expected a size like 500M, 16G or 2T, got {s:?}");
    let (num, unit) = match t.find(|c: char| c.is_ascii_alphabetic()) {
        Some(i) => t.split_at(i),
        None => (t, ""),
    };
    let shift = match unit
        .to_ascii_uppercase()
        .trim_end_matches("IB")
        .trim_end_matches('B')
    {
        "" => 0,
        "K" => 10,
        "M" => 20,
        "G" => 30,
        "T" => 40,
        _ => return Err(err()),
    };
    let v: f64 = num.trim().parse().map_err(|_| err())?;
    let bytes = v * (1u64 << shift) as f64;
    if !(v.is_finite() && v > 0.0 && bytes < 2f64.powi(63)) {
        return Err(err());
    }
    Ok(bytes as u64)
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum ViewArg {
    Map,
    Grass,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum GrassModelArg {
    Cwd,
    Bezier,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum OnOff {
    On,
    Off,
}

/// `"a,b,c…"` → exactly `N` numbers (not yet checked for finiteness).
fn numbers<const N: usize>(s: &str) -> Option<[f32; N]> {
    let v: Vec<f32> = s
        .split(',')
        .map(|t| t.trim().parse::<f32>().ok())
        .collect::<Option<_>>()?;
    v.try_into().ok()
}

/// `"1,2,3,4,5,6"` → six finite numbers.
fn parse_camera(s: &str) -> Result<[f32; 6], String> {
    let a: [f32; 6] = numbers(s).ok_or_else(|| {
        format!("expected eye_x,eye_y,eye_z,target_x,target_y,target_z, got {s:?}")
    })?;
    if a.iter().any(|x| !x.is_finite()) || a[..3] == a[3..] {
        return Err(format!(
            "{s:?}: the eye and the target must be distinct finite points"
        ));
    }
    Ok(a)
}

/// Why the layout's map backdrop (if it has one) cannot be shown.
fn backdrop_warning(l: &doc::Layout, file: &std::path::Path) -> Option<String> {
    let base = io::layout_base(Some(file));
    let map = l.world.map.as_ref()?;
    io::load_backdrop(&base, map).err().map(|e| e.to_string())
}

/// The camera `--camera` names (45° lens).
fn camera_from(c: [f32; 6]) -> windloom::gpu::grass::Camera {
    windloom::gpu::grass::Camera {
        eye: glam::Vec3::new(c[0], c[1], c[2]),
        target: glam::Vec3::new(c[3], c[4], c[5]),
        fov_y: 45f32.to_radians(),
    }
}

/// `"x0,z0,x1,z1,r"` → five finite numbers, the radius positive.
fn parse_push(s: &str) -> Result<[f32; 5], String> {
    let a: [f32; 5] =
        numbers(s).ok_or_else(|| format!("expected x0,z0,x1,z1,radius in metres, got {s:?}"))?;
    if a.iter().any(|x| !x.is_finite()) || a[4] <= 0.0 || a[4] > 1000.0 {
        return Err(format!(
            "{s:?}: finite numbers, and a radius above 0 and at most 1000 m"
        ));
    }
    Ok(a)
}

fn parse_speed_scale(s: &str) -> Result<f32, String> {
    let (lo, hi) = windloom::colour::FIXED_SCALE_RANGE;
    match s.trim().parse::<f32>() {
        Ok(v) if (lo..=hi).contains(&v) => Ok(v),
        _ => Err(format!("expected a speed from {lo} to {hi} m/s, got {s:?}")),
    }
}

fn parse_opacity(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(a) if (0.0..=1.0).contains(&a) => Ok(a),
        _ => Err(format!("expected an opacity from 0 to 1, got {s:?}")),
    }
}

impl GrassModelArg {
    fn model(self) -> doc::GrassModel {
        match self {
            GrassModelArg::Cwd => doc::GrassModel::CwdQuadratic,
            GrassModelArg::Bezier => doc::GrassModel::BezierPhysics,
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum AdvectionArg {
    SemiLagrangian,
    MacCormack,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum PressureArg {
    Jacobi,
    Multigrid,
}

/// The bundled examples `bench --layout all` runs, first the default bench layout.
const BENCH_LAYOUTS: [(&str, &str); 5] = [
    (
        "layouts/obstacles.json",
        include_str!("../layouts/obstacles.json"),
    ),
    (
        "layouts/meadow.json",
        include_str!("../layouts/meadow.json"),
    ),
    (
        "layouts/two-winds.json",
        include_str!("../layouts/two-winds.json"),
    ),
    (
        "layouts/breeze-fft.json",
        include_str!("../layouts/breeze-fft.json"),
    ),
    (
        "layouts/branching.json",
        include_str!("../layouts/branching.json"),
    ),
];

/// The layouts a solver bench runs: the one given, every bundled example for `all`, or the
/// obstacles example.
fn bench_layouts(layout: &Option<PathBuf>) -> anyhow::Result<Vec<(doc::Layout, String)>> {
    let bundled = |(name, text): (&str, &str)| -> anyhow::Result<(doc::Layout, String)> {
        let l = doc::parse(text).map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        Ok((l, name.to_string()))
    };
    match layout {
        Some(p) if p.as_os_str() == "all" => BENCH_LAYOUTS.into_iter().map(bundled).collect(),
        Some(p) => Ok(vec![(io::load(p)?, p.display().to_string())]),
        None => Ok(vec![bundled(BENCH_LAYOUTS[0])?]),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if cli.command.is_some() {
        quiet_device_select();
    }
    // `RUST_LOG=info` (or `wgpu=warn`, `windloom=debug`…) shows what eframe, wgpu and windloom
    // log; by default windloom's own warnings alone (wgpu reports failed probes of backends it
    // does not use as errors).
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("windloom=warn"))
        .init();
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", doc::printable(&one_line(&e), MESSAGE_SHOWN));
            ExitCode::FAILURE
        }
    }
}

/// The most characters of one message line printed: a message quotes paths and values from
/// untrusted input, so it is bounded and its control characters escaped ([`doc::printable`]).
const MESSAGE_SHOWN: usize = 2000;

/// Prints each line of `text` on stdout, bounded and escaped.
fn print_lines(text: &str) {
    for line in text.lines() {
        println!("{}", doc::printable(line, MESSAGE_SHOWN));
    }
}

/// An error and its causes on one line, `a: b: c`, leaving out a cause the message before it
/// already says: the library's errors put their I/O cause in their own message ("FILE: No
/// such file or directory"), which `{:#}` printed a second time.
fn one_line(e: &anyhow::Error) -> String {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let cause = cause.to_string();
        if !line.ends_with(&cause) {
            line = format!("{line}: {cause}");
        }
    }
    line
}

/// Mesa's Vulkan device-select layer asks the Wayland compositor which GPU drives the
/// display; where `XDG_RUNTIME_DIR` is unset (a CI job, a build server, ssh) libwayland then
/// prints "error: XDG_RUNTIME_DIR is invalid or not set in the environment." twice on a run
/// that succeeds. The headless commands drive no display, so there they turn the layer off
/// (`NODEVICE_SELECT=1`, unless the caller set it); wgpu still picks the adapter.
fn quiet_device_select() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_none()
        && std::env::var_os("NODEVICE_SELECT").is_none()
    {
        // SAFETY: called first thing in `main`, before any other thread exists.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
}

/// What to do when the editor's window cannot open: no display, or no graphics driver.
fn window_hint(e: &eframe::Error) -> &'static str {
    match e {
        eframe::Error::Winit(_) | eframe::Error::WinitEventLoop(_) => {
            " (on a machine without a display, run the editor under Xvfb: xvfb-run -a windloom; \
             `windloom bake` and `windloom render` need no display)"
        }
        eframe::Error::Wgpu(_) => {
            " (the editor draws with wgpu: Vulkan, Metal, DX12 or OpenGL; on Linux install a \
             Vulkan driver, for software rendering: apt-get install mesa-vulkan-drivers \
             libvulkan1)"
        }
        _ => "",
    }
}

fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        None => {
            let (doc, note) = match &cli.file {
                Some(path) => match io::load_or_new(path)? {
                    (doc, false) => (doc, None),
                    (doc, true) => (
                        doc,
                        // Short: the status bar is full in the 3D view.
                        Some(format!(
                            "{} is new: Save creates it",
                            path.file_name().unwrap_or_default().to_string_lossy()
                        )),
                    ),
                },
                None => (doc::default_layout(), None),
            };
            let backend = cli.backend.map(|b| match b {
                Backend::Cpu => windloom::app::live::BackendChoice::Cpu,
                Backend::Gpu => windloom::app::live::BackendChoice::Gpu,
                Backend::Auto => windloom::app::live::BackendChoice::Auto,
            });
            let launch = windloom::app::Launch {
                path: cli.file,
                backend,
                view: cli.view,
                note,
            };
            windloom::app::run(doc, launch).map_err(|e| {
                anyhow::anyhow!("could not open the editor window: {e}{}", window_hint(&e))
            })?;
            Ok(ExitCode::SUCCESS)
        }
        Some(Command::Validate { files }) => {
            let mut ok = true;
            for f in &files {
                match io::load(f) {
                    Ok(l) => {
                        let mut line = format!("{}: ok", f.display());
                        if let Some(w) = backdrop_warning(&l, f) {
                            line += &format!("; warning: {w} (the layout opens without it)");
                        }
                        for a in doc::advise(&l) {
                            line += &format!("; warning: {a}");
                        }
                        print_lines(&line);
                    }
                    Err(e) => {
                        ok = false;
                        print_lines(&e.to_string());
                    }
                }
            }
            Ok(if ok {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            })
        }
        Some(Command::Schema) => {
            println!("{}", serde_json::to_string_pretty(&doc::schema())?);
            Ok(ExitCode::SUCCESS)
        }
        Some(Command::Fmt { files }) => {
            let mut ok = true;
            for f in &files {
                match io::load(f) {
                    Ok(layout) => io::save(f, &layout)
                        .with_context(|| format!("could not write {}", f.display()))?,
                    Err(e) => {
                        ok = false;
                        for line in e.to_string().lines() {
                            eprintln!("{}", doc::printable(line, MESSAGE_SHOWN));
                        }
                    }
                }
            }
            Ok(if ok {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            })
        }
        Some(Command::Bake {
            layout,
            out,
            formats,
            warmup,
            frames,
            fps,
            looped,
            grid,
            half,
            max_disk,
            backend,
        }) => {
            let l = io::load(&layout)?;
            for a in doc::advise(&l) {
                eprintln!(
                    "warning: {}",
                    doc::printable(&format!("{}: {a}", layout.display()), MESSAGE_SHOWN)
                );
            }
            let opts = bake::BakeOptions {
                formats: if formats.is_empty() {
                    bake::Format::ALL.to_vec()
                } else {
                    formats.into_iter().map(Into::into).collect()
                },
                warmup,
                frames,
                fps,
                looped,
                grid,
                half,
                max_bytes: max_disk,
                backend: match backend {
                    Backend::Cpu => bake::Backend::Cpu,
                    Backend::Gpu => bake::Backend::Gpu,
                    Backend::Auto => bake::Backend::Auto,
                },
            };
            let cancel = Arc::new(AtomicBool::new(false));
            let flag = cancel.clone();
            // Ctrl-C, SIGTERM (`docker stop`, `timeout`, a cancelled CI job) and SIGHUP (a
            // closed terminal) all cancel the bake, which then removes what it wrote.
            ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst))
                .context("could not install the Ctrl-C, SIGTERM and SIGHUP handler")?;
            let bar = if std::io::stderr().is_terminal() {
                indicatif::ProgressBar::new(1)
            } else {
                indicatif::ProgressBar::hidden()
            };
            bar.set_style(
                indicatif::ProgressStyle::with_template("{msg:>12} [{bar:40}] {pos}/{len} {eta}")
                    .expect("a valid template")
                    .progress_chars("=> "),
            );
            // Where stderr is not a terminal (a CI log, a pipe) a long bake still says how
            // far it is: a line every 10 s, none for a bake that ends sooner.
            let lines = !std::io::stderr().is_terminal();
            let mut last_line = std::time::Instant::now();
            let mut progress = |done: usize, total: usize, what: &str| {
                bar.set_length(total as u64);
                bar.set_position(done as u64);
                bar.set_message(what.to_string());
                if lines && last_line.elapsed() >= std::time::Duration::from_secs(10) {
                    last_line = std::time::Instant::now();
                    eprintln!(
                        "{what}: {:.0}% (step {done} of {total})",
                        100.0 * done as f64 / total.max(1) as f64
                    );
                }
            };
            let result = bake::bake(&l, &out, &opts, &cancel, &mut progress);
            bar.finish_and_clear();
            match result {
                Ok(m) => {
                    // The advice was said before the bake; the rest is news.
                    for n in m.notes.iter().filter(|n| !n.starts_with(bake::ADVICE)) {
                        eprintln!("note: {}", doc::printable(n, MESSAGE_SHOWN));
                    }
                    println!(
                        "baked {} frame(s) of {}x{} into {} ({} files + {})",
                        m.frames.count,
                        m.grid[0],
                        m.grid[1],
                        out.display(),
                        m.files.len(),
                        bake::MANIFEST
                    );
                    Ok(ExitCode::SUCCESS)
                }
                Err(bake::BakeError::Cancelled) => {
                    eprintln!("cancelled (a signal): no files were written");
                    Ok(ExitCode::from(130))
                }
                Err(e) => Err(e.into()),
            }
        }
        Some(Command::Render {
            layout,
            output,
            size,
            time,
            view,
            camera,
            paper_literal,
            model,
            push,
            wind_colours,
            no_arrows,
            speed_scale,
        }) => {
            if matches!(view, ViewArg::Map) {
                // Said rather than ignored: a map picture with its arrows, say, after
                // `--no-arrows`, would look like a bug.
                let grass_only = [
                    ("--camera", camera.is_some()),
                    ("--paper-literal", paper_literal),
                    ("--model", model.is_some()),
                    ("--push", push.is_some()),
                    ("--wind-colours", wind_colours.is_some()),
                    ("--no-arrows", no_arrows),
                ];
                if let Some((flag, _)) = grass_only.iter().find(|(_, given)| *given) {
                    anyhow::bail!("{flag} is for the 3D grass picture: add --view grass");
                }
            }
            io::check_target(&output)
                .with_context(|| format!("cannot write {}", output.display()))?;
            let mut l = io::load(&layout)?;
            if let Some(m) = model {
                l.grass.model = m.model();
            }
            let base = io::layout_base(Some(&layout));
            if let Some(w) = backdrop_warning(&l, &layout) {
                eprintln!(
                    "warning: {}; drawn without it",
                    doc::printable(&w, MESSAGE_SHOWN)
                );
            }
            for a in doc::advise(&l) {
                eprintln!(
                    "warning: {}",
                    doc::printable(&format!("{}: {a}", layout.display()), MESSAGE_SHOWN)
                );
            }
            let png = match view {
                ViewArg::Map => windloom::render::render_png(&l, &base, size, time, speed_scale)?,
                ViewArg::Grass => {
                    anyhow::ensure!(
                        (16..=16384).contains(&size[0]) && (16..=16384).contains(&size[1]),
                        "--size: each side must be 16 to 16384 pixels"
                    );
                    let ctx = windloom::gpu::GpuContext::headless()?;
                    let camera = camera.map(camera_from);
                    let options = windloom::gpu::grass::PictureOptions {
                        size,
                        time,
                        camera,
                        paper_literal,
                        push: push.map(|p| windloom::gpu::grass::PushPath {
                            from: [p[0], p[1]],
                            to: [p[2], p[3]],
                            radius: p[4],
                        }),
                        wind_colours,
                        speed_scale,
                        arrows: !no_arrows,
                    };
                    let pixels = windloom::gpu::grass::picture(&ctx, &l, &base, &options)?;
                    let mut png = Vec::new();
                    image::RgbaImage::from_raw(size[0], size[1], pixels)
                        .context("picture size")?
                        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
                    png
                }
            };
            io::write_atomic(&output, &png)
                .with_context(|| format!("could not write {}", output.display()))?;
            println!("wrote {}", output.display());
            Ok(ExitCode::SUCCESS)
        }
        Some(Command::Bench {
            backend,
            grid,
            iterations,
            steps,
            warmup,
            threads,
            layout,
            advection,
            pressure,
            cycles,
            json,
            grass,
            model,
            cull,
            camera,
            size,
            wind_colours,
        }) => {
            if let Some(n) = grass {
                let model = model.model();
                let l = match &layout {
                    Some(p) => io::load(p)?,
                    None => doc::default_layout(),
                };
                anyhow::ensure!(
                    n <= windloom::grass::MAX_BLADES,
                    "--grass: at most {} blades",
                    windloom::grass::MAX_BLADES
                );
                let ctx = windloom::gpu::GpuContext::headless()?;
                let options = windloom::gpu::grass::BenchOptions {
                    blades: n,
                    size,
                    frames: steps.clamp(1, 100),
                    model,
                    cull: cull == OnOff::On,
                    camera: camera.map(camera_from),
                    wind_colours,
                };
                let r = windloom::gpu::grass::bench(&ctx, &l, &options)?;
                if json {
                    println!("{}", serde_json::to_string(&r)?);
                } else {
                    println!(
                        "{} blades ({}, culling {}) at {}x{} on {} ({}): median {:.2} ms, min {:.2} ms a frame over {} frames (compute passes alone {:.2} ms, drawing alone {:.2} ms); drawn per LOD {:?}, culled by orientation {}, frustum {}, distance {}",
                        r.blades,
                        r.model,
                        if r.cull { "on" } else { "off" },
                        r.size[0],
                        r.size[1],
                        r.adapter,
                        r.adapter_type,
                        r.median_ms,
                        r.min_ms,
                        r.frames,
                        r.compute_ms,
                        r.draw_ms,
                        r.culled.drawn,
                        r.culled.orientation,
                        r.culled.frustum,
                        r.culled.distance,
                    );
                }
                return Ok(ExitCode::SUCCESS);
            }
            let many = layout.as_ref().is_some_and(|p| p.as_os_str() == "all");
            // One device (or one thread pool) for every layout of the run.
            let ctx = match backend {
                Backend::Gpu => Some(windloom::gpu::GpuContext::headless()?),
                _ => None,
            };
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads.unwrap_or(0))
                .build()?;
            let mut reports = Vec::new();
            for (mut l, name) in bench_layouts(&layout)? {
                l.world.grid = grid;
                l.sim.pressure_iterations = iterations;
                l.sim.pressure_cycles = cycles;
                l.sim.pressure = match pressure {
                    PressureArg::Jacobi => doc::PressureSolve::Jacobi,
                    PressureArg::Multigrid => doc::PressureSolve::Multigrid,
                };
                l.sim.advection = match advection {
                    AdvectionArg::SemiLagrangian => doc::Advection::SemiLagrangian,
                    AdvectionArg::MacCormack => doc::Advection::MacCormack,
                };
                let issues = doc::validate(&l);
                if let Some(i) = issues.first() {
                    anyhow::bail!("bench settings ({name}): {i}");
                }
                let report = if let Some(ctx) = &ctx {
                    let r = windloom::gpu::bench::run(ctx, &l, &name, warmup, steps)?;
                    if !json {
                        println!(
                            "{} {}x{}, {}, GPU {} ({}): median {:.2} ms, min {:.2} ms per step (recording {:.2} ms of it), {:.1} GB/s effective",
                            r.layout,
                            r.grid[0],
                            r.grid[1],
                            r.solve,
                            r.adapter.name,
                            r.adapter.device_type,
                            r.median_ms,
                            r.min_ms,
                            r.record_ms,
                            r.effective_gb_s
                        );
                        for (pass, ms) in &r.passes_ms {
                            println!("  {pass:<12} {ms:8.3} ms (GPU timestamps)");
                        }
                    }
                    serde_json::to_value(&r)?
                } else {
                    let report =
                        pool.install(|| windloom::sim::bench::run_cpu(&l, &name, warmup, steps));
                    if !json {
                        println!(
                            "{} {}x{}, {}, {} threads, {}: median {:.2} ms, min {:.2} ms per step",
                            report.layout,
                            report.grid[0],
                            report.grid[1],
                            report.solve,
                            report.threads,
                            report.cpu_simd,
                            report.median_ms,
                            report.min_ms
                        );
                        for (pass, ms) in &report.passes_ms {
                            let mb = report.passes_bytes[pass] as f64 / 1e6;
                            println!("  {pass:<28} {ms:8.2} ms  {mb:9.1} MB");
                        }
                        println!(
                            "  bandwidth {:.1} GB/s, bound {:.2} ms, ratio {:.2}; unfused bound {:.2} ms, ratio {:.2}",
                            report.bandwidth_gb_s,
                            report.bound_ms,
                            report.ratio_to_bound,
                            report.unfused_bound_ms,
                            report.ratio_to_unfused_bound
                        );
                        println!(
                            "  projection: RMS divergence {:.3e} -> {:.3e} (cut {:.1}x)",
                            report.divergence_before,
                            report.divergence_after,
                            report.divergence_reduction
                        );
                    }
                    serde_json::to_value(&report)?
                };
                reports.push(report);
            }
            if json {
                // One object for one layout; an array for `--layout all`.
                let out = if many {
                    serde_json::Value::Array(reports)
                } else {
                    reports.remove(0)
                };
                println!("{}", serde_json::to_string(&out)?);
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}
