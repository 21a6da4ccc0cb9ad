//! Every limit of a layout, in one place: what `validate` enforces, what the JSON Schema
//! states (`types.rs` reads these in its `schemars` attributes) and what the editor's
//! inspector lets a field take. A field's bound is written here once; `tests/doc` checks the
//! schema and `validate` against this table ([`NUMBERS`]).
//!
//! Bounds are `f64` so that the schema prints them as written (`0.001`, not the `f32`'s
//! `0.0010000000474974513`); `validate` compares an `f32` field with the `f32` nearest to
//! each end, which is the value the `f32` constants below hold.

use std::ops::RangeInclusive;

/// The values a number field accepts: finite, from `min` to `max`, and above zero when
/// `above_zero` (then `min` may be 0 itself and is still refused).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    pub min: f64,
    pub max: f64,
    pub above_zero: bool,
}

impl Bound {
    /// From `min` to `max`, both included.
    pub const fn new(min: f64, max: f64) -> Self {
        Self {
            min,
            max,
            above_zero: false,
        }
    }

    /// Above zero, at least `min` and at most `max`.
    pub const fn positive(min: f64, max: f64) -> Self {
        Self {
            min,
            max,
            above_zero: true,
        }
    }

    /// The smallest `f32` accepted.
    pub fn lo(self) -> f32 {
        if self.above_zero && self.min <= 0.0 {
            f32::MIN_POSITIVE
        } else {
            self.min as f32
        }
    }

    /// The largest `f32` accepted.
    pub fn hi(self) -> f32 {
        self.max as f32
    }

    /// What an editor field may take (egui's `DragValue::range`).
    pub fn range(self) -> RangeInclusive<f32> {
        self.lo()..=self.hi()
    }

    /// `v` held to the bound (a typed value past what an editor field shows).
    pub fn clamp(self, v: f32) -> f32 {
        v.clamp(self.lo(), self.hi())
    }

    /// Whether `v` is accepted (as `validate` decides it).
    pub fn contains(self, v: f32) -> bool {
        v.is_finite() && (!self.above_zero || v > 0.0) && v >= self.min as f32 && v <= self.hi()
    }
}

/// The values a whole-number field accepts, `min` to `max`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Count {
    pub min: u32,
    pub max: u32,
}

impl Count {
    pub const fn new(min: u32, max: u32) -> Self {
        Self { min, max }
    }

    pub fn contains(self, v: u32) -> bool {
        (self.min..=self.max).contains(&v)
    }

    pub fn range(self) -> RangeInclusive<u32> {
        self.min..=self.max
    }

    /// `v` held to the bound.
    pub fn clamp(self, v: u32) -> u32 {
        v.clamp(self.min, self.max)
    }
}

// The world.

/// A world side in metres. The smallest keeps cells above 0.06 mm with at most
/// [`GRID_AXIS_MAX`] cells a side, so the solver's `1/h²` and the renderer's scale stay finite.
pub const WORLD_SIZE: Bound = Bound::positive(1.0, 100_000.0);
/// Any position (origin, node, obstacle point), each coordinate, in metres from the world
/// origin `[0, 0]`: far beyond any level, and small enough that every position, scaled to
/// pixels or cells, stays a finite and precise `f32`.
pub const COORD: Bound = Bound::new(-1.0e6, 1.0e6);
/// Cells along each grid axis.
pub const GRID_AXIS: Count = Count::new(8, 16384);
/// The map backdrop's opacity.
pub const OPACITY: Bound = Bound::new(0.0, 1.0);
/// A mask obstacle's luminance threshold.
pub const MASK_THRESHOLD: Bound = Bound::new(0.0, 1.0);
/// A surface's roughness length, metres: from still water to a city centre.
pub const ROUGHNESS: Bound = Bound::positive(0.0, 10.0);
/// A height in the vertical profile, metres.
pub const PROFILE_HEIGHT: Bound = Bound::new(0.1, 1000.0);
/// A terrain height, metres: the Dead Sea shore to above Everest, with room.
pub const TERRAIN_HEIGHT: Bound = Bound::new(-10000.0, 10000.0);
/// How strongly the terrain shapes the wind.
pub const TERRAIN_STRENGTH: Bound = Bound::new(0.0, 2.0);
/// Layers of the baked volume.
pub const PROFILE_LAYERS: Count = Count::new(1, 256);

// Trees and arrows.

/// An arrow's strength: the wind speed (m/s) it drives toward.
pub const STRENGTH: Bound = Bound::new(0.0, 500.0);
/// An arrow's or a circle's radius, in metres. The smallest radius, noise scale, wavelength,
/// tile or arrow length: below it the Gaussian `1/r²` and friends overflow `f32`.
pub const RADIUS: Bound = Bound::positive(1.0e-3, 100_000.0);
/// How fast a pulse runs along a tree's arrows, m/s.
pub const PROPAGATION_SPEED: Bound = Bound::positive(1.0e-3, 1.0e6);
/// A time window's start and end, in simulated seconds.
pub const WINDOW_TIME: Bound = Bound::new(0.0, 1.0e7);
/// A keyframe's strength: a factor on the tree's arrows' (or the layer's) speeds.
pub const KEY_STRENGTH: Bound = Bound::new(0.0, 10.0);
/// A keyframe's rotation, degrees (ten turns either way).
pub const KEY_ROTATION: Bound = Bound::new(-3600.0, 3600.0);
/// Most keyframes of one tree or layer.
pub const KEYS_MAX: usize = 1_000;
/// A pulsed tree's period, in seconds.
pub const PERIOD: Bound = Bound::positive(1.0e-3, 1.0e6);
/// A pulsed tree's duty: the share of the period it blows.
pub const DUTY: Bound = Bound::positive(0.0, 1.0);

// Ambient layers.

/// An ambient wind speed or amplitude, m/s (a directional layer's main wind and turbulence,
/// a noise layer's strength, an FFT or sine layer's amplitude).
pub const AMBIENT_SPEED: Bound = Bound::new(0.0, 500.0);
/// A directional layer's gusts, relative to its main wind.
pub const PULSE_MAGNITUDE: Bound = Bound::new(0.0, 10.0);
/// A directional layer's gusts per second.
pub const PULSE_FREQUENCY: Bound = Bound::new(0.0, 100.0);
/// A feature length in metres: the terrain's hills, a noise layer's scale, an FFT tile, a sine's wavelength.
pub const FEATURE_LENGTH: Bound = Bound::positive(1.0e-3, 100_000.0);
/// A noise layer's scroll speed, m/s.
pub const SCROLL_SPEED: Bound = Bound::new(0.0, 1000.0);
/// An FFT layer's wind speed, m/s (sets the spectrum's peak).
pub const FFT_WIND_SPEED: Bound = Bound::positive(0.01, 500.0);
/// An FFT layer's size per axis (a power of two).
pub const FFT_RESOLUTION: Count = Count::new(8, 512);
/// A sine layer's frequency, 1/s (negative: travelling the other way).
pub const SINE_FREQUENCY: Bound = Bound::new(-100.0, 100.0);

// The solver.

/// The solver's step in seconds. The largest (1/30 s, written as the `f32` nearest to it
/// prints, so that a layout holding that `f32` meets the schema too) keeps the solver
/// stable; the smallest keeps a bake's step count (seconds / dt) finite.
pub const DT: Bound = Bound::positive(1.0e-4, 0.033333335);
pub const SUBSTEPS: Count = Count::new(1, 16);
pub const PRESSURE_ITERATIONS: Count = Count::new(1, 1000);
pub const PRESSURE_CYCLES: Count = Count::new(1, 20);
pub const PRESSURE_DECAY: Bound = Bound::new(0.0, 1.0);
pub const VORTICITY: Bound = Bound::new(0.0, 1000.0);
pub const VELOCITY_DISSIPATION: Bound = Bound::new(0.0, 100.0);
pub const AMBIENT_COUPLING: Bound = Bound::new(0.0, 100.0);
pub const ARROW_RESPONSE: Bound = Bound::new(0.0, 1000.0);

// The grass.

/// Blades per square metre.
pub const GRASS_DENSITY: Bound = Bound::positive(0.0, 100_000.0);
/// A blade's height range, metres, each end.
pub const BLADE_HEIGHT: Bound = Bound::positive(0.0, 100.0);
/// A blade's width range, metres, each end.
pub const BLADE_WIDTH: Bound = Bound::positive(0.0, 10.0);
/// A blade's stiffness range, each end.
pub const STIFFNESS: Bound = Bound::positive(0.0, 1000.0);
/// The bends k1 and k2 of eq. 11.
pub const BEND: Bound = Bound::new(0.0, 10.0);
/// The stiffness blend λ of eq. 13.
pub const LAMBDA: Bound = Bound::new(0.0, 1.0);
/// The self-shadow's clamp m_min and m_max (eq. 14).
pub const SHADOW_CLAMP: Bound = Bound::new(0.0, 10.0);
/// The self-shadow's c1 and c2 (eq. 14).
pub const SHADOW_TERM: Bound = Bound::new(-100.0, 100.0);
/// A palette colour channel, linear 0–1.
pub const COLOUR: Bound = Bound::new(0.0, 1.0);

/// Every number field's bound, by where the schema states it: `(definition, property, bound)`
/// (a variant's field: `Definition.variant`; an array's items: the property's own bound).
pub const NUMBERS: &[(&str, &str, Bound)] = &[
    ("World", "size", WORLD_SIZE),
    ("World", "origin", COORD),
    ("MapBackdrop", "opacity", OPACITY),
    ("VerticalProfile", "roughness_length", ROUGHNESS),
    ("VerticalProfile", "reference_height", PROFILE_HEIGHT),
    ("VerticalProfile", "top", PROFILE_HEIGHT),
    ("Tree", "propagation_speed", PROPAGATION_SPEED),
    ("Key", "time", WINDOW_TIME),
    ("Timeline", "range", WINDOW_TIME),
    ("Key", "strength", KEY_STRENGTH),
    ("Key", "rotation_deg", KEY_ROTATION),
    ("TimeWindow.between", "start", WINDOW_TIME),
    ("TimeWindow.between", "end", WINDOW_TIME),
    ("Emission.pulsed", "period", PERIOD),
    ("Emission.pulsed", "duty", DUTY),
    ("Node", "pos", COORD),
    ("Probe", "pos", COORD),
    ("Node", "strength", STRENGTH),
    ("Node", "radius", RADIUS),
    ("Shape.circle", "center", COORD),
    ("Shape.circle", "radius", RADIUS),
    ("Shape.mask", "threshold", MASK_THRESHOLD),
    ("AmbientKind.directional", "main", AMBIENT_SPEED),
    ("AmbientKind.directional", "turbulence", AMBIENT_SPEED),
    (
        "AmbientKind.directional",
        "pulse_magnitude",
        PULSE_MAGNITUDE,
    ),
    (
        "AmbientKind.directional",
        "pulse_frequency",
        PULSE_FREQUENCY,
    ),
    ("AmbientKind.noise", "scale", FEATURE_LENGTH),
    ("AmbientKind.noise", "speed", SCROLL_SPEED),
    ("AmbientKind.noise", "strength", AMBIENT_SPEED),
    ("AmbientKind.fft", "wind_speed", FFT_WIND_SPEED),
    ("AmbientKind.fft", "amplitude", AMBIENT_SPEED),
    ("AmbientKind.fft", "tile_size", FEATURE_LENGTH),
    ("AmbientKind.sine", "amplitude", AMBIENT_SPEED),
    ("AmbientKind.sine", "wavelength", FEATURE_LENGTH),
    ("AmbientKind.sine", "frequency", SINE_FREQUENCY),
    ("SimParams", "dt", DT),
    ("SimParams", "pressure_decay", PRESSURE_DECAY),
    ("SimParams", "vorticity", VORTICITY),
    ("SimParams", "velocity_dissipation", VELOCITY_DISSIPATION),
    ("SimParams", "ambient_coupling", AMBIENT_COUPLING),
    ("SimParams", "arrow_response", ARROW_RESPONSE),
    ("GrassParams", "density", GRASS_DENSITY),
    ("GrassParams", "height", BLADE_HEIGHT),
    ("GrassParams", "width", BLADE_WIDTH),
    ("GrassParams", "stiffness", STIFFNESS),
    ("GrassParams", "k1", BEND),
    ("GrassParams", "k2", BEND),
    ("GrassParams", "lambda", LAMBDA),
    ("Shadow", "m_min", SHADOW_CLAMP),
    ("Shadow", "m_max", SHADOW_CLAMP),
    ("Shadow", "c1", SHADOW_TERM),
    ("Shadow", "c2", SHADOW_TERM),
    ("Palette", "base", COLOUR),
    ("Palette", "tip", COLOUR),
];

/// Every whole-number field's bound, as [`NUMBERS`].
pub const COUNTS: &[(&str, &str, Count)] = &[
    ("World", "grid", GRID_AXIS),
    ("VerticalProfile", "layers", PROFILE_LAYERS),
    ("AmbientKind.fft", "resolution", FFT_RESOLUTION),
    ("SimParams", "substeps", SUBSTEPS),
    ("SimParams", "pressure_iterations", PRESSURE_ITERATIONS),
    ("SimParams", "pressure_cycles", PRESSURE_CYCLES),
];

// The same ends as `f32`, for the code that computes with them.

pub const COORD_MAX: f32 = COORD.max as f32;
pub const WORLD_SIZE_MIN: f32 = WORLD_SIZE.min as f32;
pub const WORLD_SIZE_MAX: f32 = WORLD_SIZE.max as f32;
pub const GRID_AXIS_MIN: u32 = GRID_AXIS.min;
pub const GRID_AXIS_MAX: u32 = GRID_AXIS.max;
/// Smallest radius, noise scale, wavelength, tile or arrow length in metres.
pub const LENGTH_MIN: f32 = RADIUS.min as f32;
pub const DT_MIN: f32 = DT.min as f32;
pub const DT_MAX: f32 = DT.max as f32;
pub const STRENGTH_MAX: f32 = STRENGTH.max as f32;
pub const RADIUS_MAX: f32 = RADIUS.max as f32;

// Sizes and counts.

/// The solver's working memory per grid cell in bytes (velocity faces, temporaries, pressure,
/// divergence, curl, solid mask). The CPU solver checks its own allocation against this.
pub const SOLVER_BYTES_PER_CELL: u64 = 56;
/// What the multigrid hierarchy adds per grid cell (`sim.pressure = "multigrid"`): the fine
/// level's links and diagonal (16) and the coarser levels' links and unknowns (at most 28 over
/// all of them, when every level halves one axis only).
pub const MULTIGRID_BYTES_PER_CELL: u64 = 44;
/// Bytes a cell of terrain adds: its height, its two faces' coefficients
/// (`sim::terrain::Cell`, 32 bytes each) and the shaped copy of its two faces.
pub const TERRAIN_BYTES_PER_CELL: u64 = 4 + 64 + 8;
/// Largest solver memory a layout may ask for: 2 GiB.
pub const GRID_MEMORY_BUDGET: u64 = 2 << 30;
/// Largest layout file windloom reads, in bytes. A layout at every count limit below stays
/// well under it; a file past it is refused before it is parsed (a 58 MB layout took 1.8 GB
/// and 10 s to read).
pub const LAYOUT_MAX_BYTES: u64 = 16 << 20;
/// Longest chain of arrows in a tree: arrows from its root to its farthest end point.
pub const CHAIN_MAX: usize = 160;
/// Most points (roots and arrow end points) in a layout, over all its trees.
pub const NODES_MAX: usize = 10_000;
/// Most wind trees, obstacles and ambient layers in a layout.
pub const TREES_MAX: usize = 1_000;
pub const OBSTACLES_MAX: usize = 10_000;
pub const AMBIENT_MAX: usize = 64;
/// Most probes in a layout.
pub const PROBES_MAX: usize = 64;
/// Most points of one polygon obstacle.
pub const POLYGON_POINTS_MAX: usize = 10_000;
/// Longest name (of the layout, a tree, an obstacle or a layer), in characters.
pub const NAME_MAX: usize = 256;
/// How deep a layout's JSON may nest, counting each open object, array and field (a chain of
/// [`CHAIN_MAX`] arrows takes three levels an arrow, 490 in all): within the 512 that the
/// parser that locates fields and finds duplicate keys reads.
pub const NESTING_MAX: usize = 500;
const _: () = assert!(3 * CHAIN_MAX + 10 <= NESTING_MAX && NESTING_MAX <= 512);
