//! The command line: what `windloom` takes, and how each value is read. The value types are
//! the library's own (`engine::Backend`, `bake::Format`, `doc::GrassModel`…), read by the
//! [`clap::ValueEnum`] impls at the end of this file.

use crate::app::Central;
use crate::bake::Format;
use crate::doc::{Advection, GrassModel, PressureSolve};
use crate::engine::Backend;
use clap::builder::PossibleValue;
use clap::{Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

const AFTER_HELP: &str = "\
Examples:
  windloom                               open the editor on the bundled default layout
  windloom layouts/obstacles.json        open the editor on a layout
  windloom layouts/meadow.json --view 3d open the editor on the grass in 3D
  windloom my-new-level.json             start a new layout there (Save writes it)
  windloom validate layouts/*.json       check layout files, print every error
  windloom schema > layout.schema.json   the JSON Schema of the layout format
  windloom schema --manifest             the JSON Schema of a bake's manifest.json
  windloom fmt my-level.json             rewrite a layout in canonical form
  windloom bake layouts/meadow.json --out bake/ --format exr --format fga
  windloom bake layouts/obstacles.json --out bake/ --frames 48 --fps 24 --loop
  windloom render layouts/obstacles.json -o obstacles.png --size 1600x1200 --time 8
  windloom render layouts/meadow.json --view grass -o grass.png --camera \"40,1.6,52,48,0.2,40\"
  windloom bench --grass 1000000 --model cwd --json
  windloom bench --backend cpu --grid 1000 --iterations 20 --steps 30 --json
  windloom bench --runtime bake --samples 100000 --json";

/// Author wind over a top-down map of a level, simulate it, and export it for game engines.
#[derive(Parser)]
#[command(version, about, after_help = AFTER_HELP, args_conflicts_with_subcommands = true)]
pub struct Cli {
    /// Layout to open in the editor (the bundled default layout when omitted; a new layout,
    /// which Save writes there, when no such file exists yet in an existing folder).
    pub file: Option<PathBuf>,
    /// Where the editor's live wind runs, for this run (the View menu changes it later);
    /// without it, the choice last made in the View menu.
    #[arg(long, value_enum)]
    pub backend: Option<Backend>,
    /// The view the editor opens on: the map, the grass in 3D, or both side by side (the
    /// View menu changes it later); without it, the view last used.
    #[arg(long, value_enum)]
    pub view: Option<Central>,
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Subcommand)]
pub enum Command {
    /// Check layout files. Prints `FILE: ok` or every error as `FILE:LINE:COLUMN: path: message`;
    /// exits 0 only if every file is valid.
    ///
    /// Example: windloom validate layouts/meadow.json layouts/two-winds.json
    Validate {
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// Print the JSON Schema of the layout format (docs/layout.schema.json), or with
    /// --manifest that of a bake's manifest.json (docs/manifest.schema.json).
    ///
    /// Example: windloom schema --manifest > manifest.schema.json
    Schema {
        /// The schema of a bake's manifest.json instead of the layout's.
        #[arg(long)]
        manifest: bool,
    },
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
    /// VF_V), raw (f32 + manifest), atlas (all frames in one 16-bit PNG flipbook), atlas-exr
    /// (the same in half-float EXR, m/s), dds (the wind as a volume up the layout's
    /// world.profile: a DDS 3D texture, and the same volume for Unity as VF and for Godot as
    /// EXR slices). Frame k is the wind at exactly warmup +
    /// k/fps seconds. The new bake replaces the output folder as a
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
        #[arg(long = "format", value_parser = format_parser())]
        formats: Vec<Format>,
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
        /// EXR and the DDS volume as 16-bit half floats.
        #[arg(long)]
        half: bool,
        /// Flowmaps (png8, png16) and the atlas with green flipped: green grows up the image
        /// (toward north, world −z), as shaders whose v coordinate runs up the image expect;
        /// without it green grows down the image (+z, south).
        #[arg(long)]
        flip_green: bool,
        /// Most disk the bake may take (e.g. 500M, 16G, 2T); checked before it starts against
        /// an upper bound of what it writes, as is the free space.
        #[arg(long, default_value = "16G", value_parser = parse_bytes)]
        max_disk: u64,
        /// Solver to run.
        #[arg(long, value_enum, default_value_t = Backend::Cpu)]
        backend: Backend,
        /// Bake again whenever the layout file changes, until Ctrl-C: each bake replaces the
        /// folder whole, its manifest's sequence one higher (engine scripts reload on it).
        #[arg(long)]
        watch: bool,
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
        #[arg(long, value_enum, default_value_t = RenderView::Map)]
        view: RenderView,
        /// The 3D view's camera, "eye_x,eye_y,eye_z,target_x,target_y,target_z" in metres
        /// (y up); default: the whole world from the south, above it, framed as the editor's
        /// "frame all" frames it.
        #[arg(long, value_parser = parse_camera, allow_hyphen_values = true)]
        camera: Option<[f32; 6]>,
        /// With --view grass: bend the blades by eqs. 12–14 exactly as the CWD-Sim paper prints
        /// them (to see the strong-wind problem windloom's reading solves).
        #[arg(long)]
        paper_literal: bool,
        /// With --view grass: draw with this blade model instead of the layout's.
        #[arg(long, value_enum)]
        model: Option<GrassModel>,
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
    /// Measure the wind at points over time, headless: each probe's min, mean and max speed,
    /// gust factor (the highest 3-second mean over the mean) and mean direction on stdout,
    /// and with --csv every reading (speed, direction, components) as CSV.
    ///
    /// Example: windloom probe layouts/obstacles.json --at 40,60 --at 90,30 --seconds 30 --csv probes.csv
    Probe {
        /// The layout file to run.
        layout: PathBuf,
        /// A point X,Z in metres (repeatable); without it, the layout's own probes.
        #[arg(long = "at", value_parser = parse_point, allow_hyphen_values = true)]
        at: Vec<[f32; 2]>,
        /// Seconds simulated from calm before the first reading (0 to 3600).
        #[arg(long, default_value_t = 5.0)]
        warmup: f32,
        /// Seconds read after the warm-up (0.1 to 3600).
        #[arg(long, default_value_t = 30.0)]
        seconds: f32,
        /// Readings per second (at most one per step).
        #[arg(long, default_value_t = 20.0)]
        hz: f32,
        /// Write every reading to this CSV file (atomically).
        #[arg(long)]
        csv: Option<PathBuf>,
        /// Solver to run.
        #[arg(long, value_enum, default_value_t = Backend::Cpu)]
        backend: Backend,
    },
    /// Read a bake's wind as a game does (the runtime a game links, `src/runtime`): one point
    /// a line on stdin, `X Y Z T` (metres in windloom's axes: x east, y up, z south; seconds of
    /// the game's clock), and the wind there, `WX WY WZ` in m/s, a line each on stdout, each
    /// number as the shortest text that reads back to the same f32.
    ///
    /// Example: echo "40 2 30 1.5" | windloom sample bake/ --outside wrap
    Sample {
        /// The bake folder (`bake --out`).
        bake: PathBuf,
        /// The wind beyond the baked rectangle: the edge's (clamp), none (zero), or the bake
        /// repeated (wrap).
        #[arg(long, value_enum, default_value_t = SampleOutside::Clamp)]
        outside: SampleOutside,
        /// The format to read (raw, exr, png16, png8, vf, dds); default: the most precise the
        /// bake holds.
        #[arg(long)]
        format: Option<String>,
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
        #[arg(long, value_enum, default_value_t = Advection::SemiLagrangian)]
        advection: Advection,
        /// Pressure solve: Jacobi (--iterations sweeps) or multigrid (--cycles V-cycles).
        #[arg(long, value_enum, default_value_t = PressureSolve::Multigrid)]
        pressure: PressureSolve,
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
        #[arg(long, value_enum, default_value_t = GrassModel::CwdQuadratic)]
        model: GrassModel,
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
        /// With --grass: no GPU, only what the cull would draw of the N blades at the camera
        /// (blades per LOD level and triangles a frame), estimated by its CPU twin from a
        /// sample of them: the cost of a field bigger than this device holds.
        #[arg(long, requires = "grass")]
        estimate: bool,
        /// With --grass: draw the blades in the order they are stored in, not nearest first,
        /// to time what the order saves (the picture is the same).
        #[arg(long, requires = "grass")]
        stored_order: bool,
        /// Time the runtime instead (`src/runtime`, what a game links): `wind_at_many` over
        /// --samples points a call, --steps calls, one thread, on the bake in this folder.
        #[arg(long, value_name = "BAKE_DIR", conflicts_with = "grass")]
        runtime: Option<PathBuf>,
        /// With --runtime: points a call.
        #[arg(long, default_value_t = 100_000, requires = "runtime")]
        samples: usize,
    },
}

/// `sample --outside`: the runtime's `Outside`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SampleOutside {
    Clamp,
    Zero,
    Wrap,
}

/// What `render` draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum RenderView {
    /// The top-down map of the wind.
    Map,
    /// The grass in 3D, on the GPU.
    Grass,
}

/// A switch given as `on` or `off`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum OnOff {
    On,
    Off,
}

/// `NXxNY` → `[nx, ny]`.
pub fn parse_grid(s: &str) -> Result<[u32; 2], String> {
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
pub fn parse_grid_or_side(s: &str) -> Result<[u32; 2], String> {
    match s.trim().parse::<u32>() {
        Ok(n) => Ok([n, n]),
        Err(_) if s.contains(['x', 'X']) => parse_grid(s),
        Err(_) => Err(format!(
            "expected N (cells a side) or WIDTHxHEIGHT like 256x128, got {s:?}"
        )),
    }
}

/// `500M`, `16G`, `2T`, `1048576` → bytes (binary units: 1K = 1024).
pub fn parse_bytes(s: &str) -> Result<u64, String> {
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

/// `"a,b,c…"` → exactly `N` numbers (not yet checked for finiteness).
fn numbers<const N: usize>(s: &str) -> Option<[f32; N]> {
    let v: Vec<f32> = s
        .split(',')
        .map(|t| t.trim().parse::<f32>().ok())
        .collect::<Option<_>>()?;
    v.try_into().ok()
}

/// `"x,z"` → a finite point in metres.
pub fn parse_point(s: &str) -> Result<[f32; 2], String> {
    let a: [f32; 2] = numbers(s).ok_or_else(|| format!("expected X,Z in metres, got {s:?}"))?;
    if a.iter().any(|x| !x.is_finite()) {
        return Err(format!("{s:?}: X and Z must be finite numbers"));
    }
    Ok(a)
}

/// `"1,2,3,4,5,6"` → six finite numbers.
pub fn parse_camera(s: &str) -> Result<[f32; 6], String> {
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

/// `"x0,z0,x1,z1,r"` → five finite numbers, the radius positive.
pub fn parse_push(s: &str) -> Result<[f32; 5], String> {
    let a: [f32; 5] =
        numbers(s).ok_or_else(|| format!("expected x0,z0,x1,z1,radius in metres, got {s:?}"))?;
    if a.iter().any(|x| !x.is_finite()) || a[4] <= 0.0 || a[4] > 1000.0 {
        return Err(format!(
            "{s:?}: finite numbers, and a radius above 0 and at most 1000 m"
        ));
    }
    Ok(a)
}

/// A speed for the top of the speed colours, within [`crate::colour::FIXED_SCALE_RANGE`].
pub fn parse_speed_scale(s: &str) -> Result<f32, String> {
    let (lo, hi) = crate::colour::FIXED_SCALE_RANGE;
    match s.trim().parse::<f32>() {
        Ok(v) if (lo..=hi).contains(&v) => Ok(v),
        _ => Err(format!("expected a speed from {lo} to {hi} m/s, got {s:?}")),
    }
}

/// An opacity from 0 to 1.
pub fn parse_opacity(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(a) if (0.0..=1.0).contains(&a) => Ok(a),
        _ => Err(format!("expected an opacity from 0 to 1, got {s:?}")),
    }
}

// The library's enums, as the command line names them.

impl ValueEnum for Backend {
    fn value_variants<'a>() -> &'a [Self] {
        // The order `--help` lists them in.
        &[Backend::Cpu, Backend::Gpu, Backend::Auto]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        let help = match self {
            Backend::Cpu => "The CPU reference solver",
            Backend::Gpu => "The GPU solver (wgpu: Vulkan, Metal, DX12; lavapipe counts)",
            Backend::Auto => {
                "The GPU when a hardware adapter exists, else the CPU (for the editor: on a \
                 software adapter, whichever measures faster for the grid)"
            }
        };
        Some(PossibleValue::new(self.name()).help(help))
    }
}

/// `--format`: one of the bake's formats by its name ([`Format::name`]); clap lists them
/// and refuses any other as it does an enum's. (The type is the bake format's crate's, so it
/// takes a parser rather than a `ValueEnum` impl.)
fn format_parser() -> impl clap::builder::TypedValueParser<Value = Format> {
    use clap::builder::TypedValueParser as _;
    clap::builder::PossibleValuesParser::new(Format::ALL.map(Format::name))
        .map(|name| Format::from_name(&name).expect("clap gives only the names of Format::ALL"))
}

impl ValueEnum for GrassModel {
    fn value_variants<'a>() -> &'a [Self] {
        &[GrassModel::CwdQuadratic, GrassModel::BezierPhysics]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(match self {
            GrassModel::CwdQuadratic => "cwd",
            GrassModel::BezierPhysics => "bezier",
        }))
    }
}

impl ValueEnum for Advection {
    fn value_variants<'a>() -> &'a [Self] {
        &[Advection::SemiLagrangian, Advection::MacCormack]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(match self {
            Advection::SemiLagrangian => "semi-lagrangian",
            Advection::MacCormack => "mac-cormack",
        }))
    }
}

impl ValueEnum for PressureSolve {
    fn value_variants<'a>() -> &'a [Self] {
        &[PressureSolve::Jacobi, PressureSolve::Multigrid]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(match self {
            PressureSolve::Jacobi => "jacobi",
            PressureSolve::Multigrid => "multigrid",
        }))
    }
}

impl ValueEnum for Central {
    fn value_variants<'a>() -> &'a [Self] {
        &Central::ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        let (name, help) = match self {
            Central::Map => ("map", "The top-down map (authoring)"),
            Central::Grass => ("3d", "The grass in 3D in the live wind"),
            Central::Split => ("split", "Both, side by side"),
        };
        Some(PossibleValue::new(name).help(help))
    }
}
