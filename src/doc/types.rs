//! The layout document: what a designer saves. Plain data (serde + schemars), no I/O.
//!
//! Coordinates (see `docs/ARCHITECTURE.md` and `docs/EXPORT.md`, "Axes and units"): the
//! world is a `width × depth` rectangle on the ground plane, world `x` east and `z` south,
//! `y` up. A 2D position or vector `[a, b]` in this document is always world `(x, z)` in metres
//! (or m/s). Angles (`direction_deg`) are measured from `+x` toward `+z`, so on a top-down map
//! drawn with `+z` pointing down the screen they turn clockwise.

// The schema states the bounds `validate` enforces, read from `bounds.rs`; `tests/doc`
// checks every one.
use super::bounds::*;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The `format` tag every layout file carries.
pub const FORMAT: &str = "windloom-layout";
/// The layout format version this build writes.
pub const VERSION: u32 = 1;

/// A 2D point or vector in world metres: `[x, z]`.
pub type Vec2 = [f32; 2];

/// A complete wind layout. A layout file is UTF-8 JSON of at most 16 MiB (a leading byte
/// order mark is allowed), nested at most 500 levels deep (each object, array and
/// field counts one), with no key twice in one object;
/// it holds at most 10,000 points (roots and arrow ends) over all its trees, and a chain of
/// arrows at most 160 long.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Layout {
    /// Always `"windloom-layout"`.
    pub format: String,
    /// Format version; this build reads 1 and writes 1.
    pub version: u32,
    /// Human-readable name of the layout, at most 256 characters.
    #[schemars(length(max = NAME_MAX))]
    pub name: String,
    pub world: World,
    /// AGC arrow trees (paper §3.5), at most 1,000.
    #[serde(default)]
    #[schemars(length(max = TREES_MAX))]
    pub trees: Vec<Tree>,
    /// Solid obstacles the wind flows around, at most 10,000.
    #[serde(default)]
    #[schemars(length(max = OBSTACLES_MAX))]
    pub obstacles: Vec<Obstacle>,
    /// Ambient wind layers added everywhere, at most 64.
    #[serde(default)]
    #[schemars(length(max = AMBIENT_MAX))]
    pub ambient: Vec<AmbientLayer>,
    /// Points where the editor plots the wind over time (and `windloom probe` measures it),
    /// at most 64.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[schemars(length(max = PROBES_MAX))]
    pub probes: Vec<Probe>,
    #[serde(default)]
    pub sim: SimParams,
    #[serde(default)]
    pub grass: GrassParams,
    /// The editor's timeline: the play range and whether playing loops over it (absent:
    /// 0 to 30 s, looping).
    #[serde(default, skip_serializing_if = "Timeline::is_default")]
    pub timeline: Timeline,
}

/// The editor's timeline, kept with the layout: what the designer plays.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Timeline {
    /// The play range `[start, end]`, simulated seconds (0 to 1e7, `start < end`).
    #[schemars(inner(range(min = WINDOW_TIME.min, max = WINDOW_TIME.max)))]
    pub range: Vec2,
    /// Playing jumps back to the range's start at its end.
    #[serde(rename = "loop", default = "yes")]
    pub looping: bool,
}

impl Default for Timeline {
    fn default() -> Self {
        Self {
            range: [0.0, 30.0],
            looping: true,
        }
    }
}

impl Timeline {
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }
}

/// A named point where the wind is measured over time: a player's spot, a banner.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Probe {
    /// Stable id, unique among the layout's probes.
    pub id: u32,
    /// At most 256 characters.
    #[schemars(length(max = NAME_MAX))]
    pub name: String,
    /// World position `[x, z]` in metres, each within ±1e6.
    #[schemars(inner(range(min = COORD.min, max = COORD.max)))]
    pub pos: Vec2,
}

/// The world rectangle, the wind grid laid over it, and the map backdrop.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct World {
    /// World size in metres: `[width (x), depth (z)]`, each 1 to 100000.
    #[schemars(inner(range(min = WORLD_SIZE.min, max = WORLD_SIZE.max)))]
    pub size: Vec2,
    /// World position of the rectangle's minimum corner `[x0, z0]` in metres, each within
    /// ±1e6.
    #[serde(default)]
    #[schemars(inner(range(min = COORD.min, max = COORD.max)))]
    pub origin: Vec2,
    /// Wind grid resolution `[nx, ny]`: columns along `+x`, rows along `+z`, each 8 to 16384
    /// cells, and at most 2 GiB of solver memory (56 bytes a cell) in all.
    #[schemars(inner(range(min = GRID_AXIS.min, max = GRID_AXIS.max)))]
    pub grid: [u32; 2],
    /// Optional top-down picture of the level drawn under the wind.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub map: Option<MapBackdrop>,
    /// How the wind changes with height above the ground, for the baked volume (`bake
    /// --format dds`). Absent: the defaults (grass, the field at 2 m, 16 layers to 20 m).
    #[serde(default, skip_serializing_if = "VerticalProfile::is_default")]
    pub profile: VerticalProfile,
    /// The level's ground: a heightmap that shapes the wind (`docs/SOLVER.md`, "Terrain"),
    /// carries the grass and the obstacles in the 3D view, and is shaded on the map. Absent:
    /// flat ground, and the wind is the 2D solve's, bit for bit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub terrain: Option<Terrain>,
}

/// The level's heightmap and how the wind feels it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Terrain {
    /// A grey image (16-bit PNG for smooth slopes, 8-bit PNG or EXR), relative to the layout
    /// file: black is the lowest height, white the highest.
    #[schemars(length(min = 1))]
    pub heightmap: String,
    /// The heights black and white stand for, `[min, max]` in metres (each within ±10000).
    #[schemars(inner(range(min = TERRAIN_HEIGHT.min, max = TERRAIN_HEIGHT.max)))]
    pub heights: Vec2,
    /// Where the heightmap lies, `[[x0, z0], [x1, z1]]` in metres, as a mask's or the
    /// backdrop's; absent: the world rectangle. Beyond it the ground continues at the
    /// image's edge heights.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(inner(inner(inner(range(min = COORD.min, max = COORD.max)))))]
    pub rect: Option<[Vec2; 2]>,
    /// How strongly the terrain shapes the wind, 0 (not at all) to 2; 1 is the model as
    /// documented.
    #[serde(default = "default_terrain_strength")]
    #[schemars(range(min = TERRAIN_STRENGTH.min, max = TERRAIN_STRENGTH.max))]
    pub strength: f32,
    /// The size of the hills and valleys the wind answers to, metres (the distance over
    /// which slope and curvature are measured; above 0, at most 100000). Absent: a twentieth of the
    /// world's shorter side.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(max = FEATURE_LENGTH.max), extend("exclusiveMinimum" = 0))]
    pub feature_length: Option<f32>,
    #[serde(skip)]
    #[schemars(skip)]
    pub pixels: MaskPixels,
}

fn default_terrain_strength() -> f32 {
    1.0
}

impl Terrain {
    /// The ground's height in metres at world point `p` (`bounds`: the world's), bilinear
    /// between the heightmap's pixel centres, the edge pixels continuing beyond the image;
    /// the lowest height where the image is not loaded.
    pub fn height_at(&self, p: Vec2, bounds: (Vec2, Vec2)) -> f32 {
        let Some(m) = self.pixels.image() else {
            return self.heights[0];
        };
        let r = placed(&self.rect, bounds);
        let u = (p[0] - r[0][0]) / (r[1][0] - r[0][0]);
        let v = (p[1] - r[0][1]) / (r[1][1] - r[0][1]);
        self.heights[0] + (self.heights[1] - self.heights[0]) * m.bilinear_at(u, v)
    }

    /// The feature length in metres for a world of `size`.
    pub fn feature_length_for(&self, size: Vec2) -> f32 {
        self.feature_length.unwrap_or(size[0].min(size[1]) / 20.0)
    }
}

/// The wind's vertical profile: the log law of the surface layer,
/// `u(h) = u_ref · ln(h / z0) / ln(h_ref / z0)` for `h > z0`, zero at and below `z0`, where
/// `u_ref` is the simulated (2D) wind, taken to be the wind at `reference_height`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VerticalProfile {
    /// The roughness length `z0` in metres, above zero and at most 10: about 0.0002 over
    /// water, 0.01–0.05 over grass, 0.1–0.5 over crops and bushes, 1–2 over forest and town.
    #[serde(default = "default_roughness")]
    #[schemars(range(max = ROUGHNESS.max), extend("exclusiveMinimum" = 0))]
    pub roughness_length: f32,
    /// The height the simulated wind stands for, metres (0.1 to 1000, above the roughness
    /// length).
    #[serde(default = "default_reference_height")]
    #[schemars(range(min = PROFILE_HEIGHT.min, max = PROFILE_HEIGHT.max))]
    pub reference_height: f32,
    /// The top of the baked volume, metres above the ground (0.1 to 1000).
    #[serde(default = "default_top")]
    #[schemars(range(min = PROFILE_HEIGHT.min, max = PROFILE_HEIGHT.max))]
    pub top: f32,
    /// Layers from the ground to `top`, 1 to 256; layer `k` holds the wind at the height
    /// `(k + 0.5) · top / layers`.
    #[serde(default = "default_layers")]
    #[schemars(range(min = PROFILE_LAYERS.min, max = PROFILE_LAYERS.max))]
    pub layers: u32,
}

fn default_roughness() -> f32 {
    0.03
}

fn default_reference_height() -> f32 {
    2.0
}

fn default_top() -> f32 {
    20.0
}

fn default_layers() -> u32 {
    16
}

impl Default for VerticalProfile {
    fn default() -> Self {
        Self {
            roughness_length: default_roughness(),
            reference_height: default_reference_height(),
            top: default_top(),
            layers: default_layers(),
        }
    }
}

impl VerticalProfile {
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// The height of layer `k`'s centre, metres.
    pub fn layer_height(&self, k: u32) -> f32 {
        (k as f32 + 0.5) * self.top / self.layers as f32
    }

    /// The wind at height `h` as a multiple of the simulated wind: the log law, 0 at and
    /// below the roughness length, 1 at the reference height.
    pub fn factor(&self, h: f32) -> f32 {
        let z0 = f64::from(self.roughness_length);
        let h = f64::from(h);
        if h <= z0 {
            return 0.0;
        }
        (crate::num::ln64(h / z0) / crate::num::ln64(f64::from(self.reference_height) / z0)) as f32
    }
}

/// A backdrop image stretched over the world rectangle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MapBackdrop {
    /// Image path, relative to the layout file.
    pub image: String,
    /// 0 (invisible) to 1 (opaque).
    #[serde(default = "one")]
    #[schemars(range(min = OPACITY.min, max = OPACITY.max))]
    pub opacity: f32,
    /// Where the image lies, `[[x0, z0], [x1, z1]]` in metres (`x0 < x1`, `z0 < z1`; the
    /// image's top-left at `[x0, z0]`), so a level's picture lines up with its world; absent:
    /// stretched over the world rectangle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(inner(inner(inner(range(min = COORD.min, max = COORD.max)))))]
    pub rect: Option<[Vec2; 2]>,
}

impl MapBackdrop {
    /// The world rectangle the image covers (`bounds`: the world's).
    pub fn placed(&self, bounds: (Vec2, Vec2)) -> [Vec2; 2] {
        placed(&self.rect, bounds)
    }
}

fn one() -> f32 {
    1.0
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn yes() -> bool {
    true
}

/// A keyframe: at `time` seconds, a factor `strength` on the speeds and a turn of
/// `rotation_deg` degrees (clockwise on the map, from +x toward +z); between two keys the
/// values ease from one to the next as the earlier key says, and hold before the first and
/// after the last.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Key {
    /// Seconds of simulation time, 0 to 1e7.
    #[schemars(range(min = WINDOW_TIME.min, max = WINDOW_TIME.max))]
    pub time: f32,
    /// 0 to 10: 1 is the authored strength, 0 calm.
    #[serde(default = "one")]
    #[schemars(range(min = KEY_STRENGTH.min, max = KEY_STRENGTH.max))]
    pub strength: f32,
    /// Degrees, ±3600: the tree turns about its root, the layer's direction turns.
    #[serde(default)]
    #[schemars(range(min = KEY_ROTATION.min, max = KEY_ROTATION.max))]
    pub rotation_deg: f32,
    /// How the values go from this key to the next.
    #[serde(default)]
    pub ease: Ease,
}

/// How a keyframe's values go to the next key's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Ease {
    /// At a steady rate.
    #[default]
    Linear,
    /// Slow at both ends (smoothstep).
    Smooth,
}

/// The strength factor and the rotation (radians) `keys` give at time `t`: `(1, 0)` without
/// keys.
pub fn key_values(keys: &[Key], t: f32) -> (f32, f32) {
    let (Some(first), Some(last)) = (keys.first(), keys.last()) else {
        return (1.0, 0.0);
    };
    let at = |k: &Key| (k.strength, k.rotation_deg.to_radians());
    if t <= first.time {
        return at(first);
    }
    if t >= last.time {
        return at(last);
    }
    let i = keys.partition_point(|k| k.time <= t);
    let (a, b) = (&keys[i - 1], &keys[i]);
    let mut f = (t - a.time) / (b.time - a.time).max(f32::MIN_POSITIVE);
    if a.ease == Ease::Smooth {
        f = f * f * (3.0 - 2.0 * f);
    }
    let (sa, ra) = at(a);
    let (sb, rb) = at(b);
    (sa + (sb - sa) * f, ra + (rb - ra) * f)
}

/// An AGC arrow tree: a root point whose children are arrow end points, recursively.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Tree {
    /// Stable id, unique among the layout's trees.
    pub id: u32,
    /// At most 256 characters.
    #[schemars(length(max = NAME_MAX))]
    pub name: String,
    #[serde(default = "yes")]
    pub enabled: bool,
    /// When the tree blows.
    #[serde(default)]
    pub window: TimeWindow,
    /// Continuous or pulsed.
    #[serde(default)]
    pub emission: Emission,
    /// How fast (m/s, along the arrows) a pulse travels from the root to the leaves.
    #[serde(default = "default_propagation_speed")]
    #[schemars(range(min = PROPAGATION_SPEED.min, max = PROPAGATION_SPEED.max))]
    pub propagation_speed: f32,
    /// Keyframes of the tree's strength and direction over time (a factor on every arrow's
    /// strength, and a turn of the whole tree about its root), at most 1,000, in time order;
    /// none: steady.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[schemars(length(max = KEYS_MAX))]
    pub keys: Vec<Key>,
    /// Locked: drawn on the map but not picked, moved or nudged there, and not changed in the
    /// inspector (the Layers list still selects it, and unlocks it).
    #[serde(default, skip_serializing_if = "is_false")]
    pub locked: bool,
    /// Hidden: not drawn on the map or in the 3D view, and not picked there; it still acts on
    /// the wind (switch a tree or layer off with `enabled`).
    #[serde(default, skip_serializing_if = "is_false")]
    pub hidden: bool,
    /// The root point. Each child is the end point of an arrow from its parent.
    pub root: Node,
}

fn default_propagation_speed() -> f32 {
    20.0
}

/// A point of an arrow tree. For every node but the root, the arrow parent → node applies a
/// force in its direction with this node's strength and radius. Nesting makes cycles
/// impossible to express.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Node {
    /// Stable id, unique among all nodes of the layout.
    pub id: u32,
    /// World position `[x, z]` in metres, each within ±1e6; at least 1 mm from its parent.
    #[schemars(inner(range(min = COORD.min, max = COORD.max)))]
    pub pos: Vec2,
    /// Wind speed (m/s) the arrow ending here drives toward along its centre line, 0 to 500.
    #[schemars(range(min = STRENGTH.min, max = STRENGTH.max))]
    pub strength: f32,
    /// Gaussian radius (metres) of the arrow ending here, 0.001 to 100000.
    #[schemars(range(min = RADIUS.min, max = RADIUS.max))]
    pub radius: f32,
    /// End points of arrows starting here: several branch, a child's children chain. A chain
    /// holds at most 160 arrows from its root, and a layout at most 10,000 points in all.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub children: Vec<Node>,
    /// The branch's keyframes (a point other than the root): the arrow ending here and every
    /// arrow after it, their strength scaled and turned about the arrow's start point, on top
    /// of the tree's keys and the keys of the branches it grows from; at most 1,000, in time
    /// order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[schemars(length(max = KEYS_MAX))]
    pub keys: Vec<Key>,
}

/// The time a tree is active.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TimeWindow {
    #[default]
    Always,
    /// Active from `start` to `end` seconds of simulation time.
    Between {
        #[schemars(range(min = WINDOW_TIME.min, max = WINDOW_TIME.max))]
        start: f32,
        #[schemars(range(min = WINDOW_TIME.min, max = WINDOW_TIME.max))]
        end: f32,
    },
}

/// How a tree emits force.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Emission {
    #[default]
    Continuous,
    /// On for `duty × period` seconds out of every `period`.
    Pulsed {
        #[schemars(range(min = PERIOD.min, max = PERIOD.max))]
        period: f32,
        #[schemars(range(max = DUTY.max), extend("exclusiveMinimum" = 0))]
        duty: f32,
    },
}

/// A named solid obstacle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Obstacle {
    /// Stable id, unique among the layout's obstacles.
    pub id: u32,
    /// At most 256 characters.
    #[schemars(length(max = NAME_MAX))]
    pub name: String,
    pub shape: Shape,
    /// Locked: drawn on the map but not picked, moved or nudged there, and not changed in the
    /// inspector (the Layers list still selects it, and unlocks it).
    #[serde(default, skip_serializing_if = "is_false")]
    pub locked: bool,
    /// Hidden: not drawn on the map or in the 3D view, and not picked there; it still acts on
    /// the wind (switch a tree or layer off with `enabled`).
    #[serde(default, skip_serializing_if = "is_false")]
    pub hidden: bool,
}

/// An obstacle's outline in world metres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    Circle {
        /// Centre `[x, z]` in metres, each within ±1e6.
        #[schemars(inner(range(min = COORD.min, max = COORD.max)))]
        center: Vec2,
        /// Metres, 0.001 to 100000.
        #[schemars(range(min = RADIUS.min, max = RADIUS.max))]
        radius: f32,
    },
    /// A simple polygon, 3 to 10,000 points, implicitly closed.
    Polygon {
        /// Corners `[x, z]` in metres, each coordinate within ±1e6.
        #[schemars(length(min = 3, max = POLYGON_POINTS_MAX), inner(inner(range(min = COORD.min, max = COORD.max))))]
        points: Vec<Vec2>,
    },
    /// A level's collision mask: solid where the image's luminance is below `threshold`
    /// (above it when `invert`), stretched over `rect` (the world rectangle when absent).
    Mask {
        /// Image path, relative to the layout file: PNG (8 or 16 bits) or EXR, at most 16384
        /// pixels a side.
        #[schemars(length(min = 1))]
        image: String,
        /// Luminance 0 to 1 at which a pixel turns solid.
        #[serde(default = "half")]
        #[schemars(range(min = MASK_THRESHOLD.min, max = MASK_THRESHOLD.max))]
        threshold: f32,
        /// Solid where the luminance is above the threshold instead.
        #[serde(default)]
        invert: bool,
        /// Where the image lies, `[[x0, z0], [x1, z1]]` in metres (`x0 < x1`, `z0 < z1`; the
        /// image's top-left at `[x0, z0]`); absent: the world rectangle.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        #[schemars(inner(inner(inner(range(min = COORD.min, max = COORD.max)))))]
        rect: Option<[Vec2; 2]>,
        /// The image's pixels, read beside the layout file by `io` (never written into it).
        #[serde(skip)]
        #[schemars(skip)]
        pixels: MaskPixels,
    },
}

fn half() -> f32 {
    0.5
}

impl Shape {
    /// The middle of the outline: a circle's centre, a polygon's mean corner, a mask's
    /// rectangle's middle (`bounds`: the world's, where the mask has no rectangle).
    pub fn centre(&self, bounds: (Vec2, Vec2)) -> Vec2 {
        match self {
            Self::Circle { center, .. } => *center,
            Self::Polygon { points } => {
                let n = points.len().max(1) as f32;
                let s = (points.iter()).fold([0.0, 0.0], |a, p| [a[0] + p[0], a[1] + p[1]]);
                [s[0] / n, s[1] / n]
            }
            Self::Mask { rect, .. } => {
                let [a, b] = placed(rect, bounds);
                [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]
            }
        }
    }
}

/// A decoded mask image: luminance per pixel, row-major from the top-left, 0 to 65535.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MaskImage {
    pub width: u32,
    pub height: u32,
    pub luminance: Vec<u16>,
}

impl MaskImage {
    /// Whether the pixel under `(u, v)` (0 to 1 across and down the image) is solid.
    pub fn solid_at(&self, u: f32, v: f32, threshold: f32, invert: bool) -> bool {
        (self.luminance_at(u, v) < threshold) != invert
    }

    /// The luminance, 0 to 1, of the pixel under `(u, v)` (0 to 1 across and down).
    pub fn luminance_at(&self, u: f32, v: f32) -> f32 {
        let x = ((u * self.width as f32) as i64).clamp(0, i64::from(self.width) - 1) as usize;
        let y = ((v * self.height as f32) as i64).clamp(0, i64::from(self.height) - 1) as usize;
        f32::from(self.luminance[y * self.width as usize + x]) / 65535.0
    }

    /// The luminance, 0 to 1, at `(u, v)` (0 to 1 across and down), bilinear between pixel
    /// centres, the edge pixels continuing beyond the image: for heights, which must not
    /// step from pixel to pixel.
    pub fn bilinear_at(&self, u: f32, v: f32) -> f32 {
        let (w, h) = (self.width as usize, self.height as usize);
        let x = (u * w as f32 - 0.5).clamp(0.0, (w - 1) as f32);
        let y = (v * h as f32 - 0.5).clamp(0.0, (h - 1) as f32);
        let (x0, y0) = (x as usize, y as usize);
        let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let at = |x: usize, y: usize| f32::from(self.luminance[y * w + x]) / 65535.0;
        let top = at(x0, y0) + (at(x1, y0) - at(x0, y0)) * fx;
        let bottom = at(x0, y1) + (at(x1, y1) - at(x0, y1)) * fx;
        top + (bottom - top) * fy
    }
}

/// Where an image the layout places lies: its own rectangle, or the world's (`bounds`).
pub fn placed(rect: &Option<[Vec2; 2]>, bounds: (Vec2, Vec2)) -> [Vec2; 2] {
    rect.unwrap_or([bounds.0, bounds.1])
}

/// World point `p` as `(u, v)` across and down an image placed over `rect`, or `None`
/// outside it.
pub fn image_uv(rect: [Vec2; 2], p: Vec2) -> Option<[f32; 2]> {
    let u = (p[0] - rect[0][0]) / (rect[1][0] - rect[0][0]);
    let v = (p[1] - rect[0][1]) / (rect[1][1] - rect[0][1]);
    ((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v)).then_some([u, v])
}

/// A mask obstacle's pixels: a cache of the file its `image` names, so two masks naming one
/// file are equal whatever is loaded.
#[derive(Debug, Clone, Default)]
pub enum MaskPixels {
    /// Not read yet (a layout parsed from text).
    #[default]
    NotLoaded,
    Loaded(std::sync::Arc<MaskImage>),
    /// Read and refused: why, in one line naming the file.
    Failed(std::sync::Arc<str>),
}

impl PartialEq for MaskPixels {
    /// Pixels not read yet equal any: a layout parsed from text equals the same layout read
    /// with its images. Two read images compare by content (the same shared pixels at once),
    /// so a painted image is a change.
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Self::Loaded(a), Self::Loaded(b)) => std::sync::Arc::ptr_eq(a, b) || a == b,
            _ => true,
        }
    }
}

impl MaskPixels {
    pub fn image(&self) -> Option<&MaskImage> {
        match self {
            Self::Loaded(i) => Some(i),
            _ => None,
        }
    }
}

impl Shape {
    /// Whether world point `p` lies on a mask obstacle's solid pixels (`false` for other
    /// shapes and for a mask whose image is not loaded). `bounds`: the layout's.
    pub fn mask_contains(&self, p: Vec2, bounds: (Vec2, Vec2)) -> bool {
        let Some((image, r, threshold, invert)) = self.loaded_mask(bounds) else {
            return false;
        };
        image_uv(r, p).is_some_and(|[u, v]| image.solid_at(u, v, threshold, invert))
    }

    /// A mask obstacle's loaded image, where it lies, its threshold and inversion (`None`
    /// for other shapes and for a mask whose image is not loaded).
    fn loaded_mask(&self, bounds: (Vec2, Vec2)) -> Option<(&MaskImage, [Vec2; 2], f32, bool)> {
        let Self::Mask {
            threshold,
            invert,
            rect,
            pixels,
            ..
        } = self
        else {
            return None;
        };
        Some((pixels.image()?, placed(rect, bounds), *threshold, *invert))
    }

    /// A mask's solid area as world rectangles `[min, max]`: the runs of solid samples along
    /// each row of a grid of at most `max` samples a side over the mask's rectangle, a run
    /// that spans the same columns as one on the row above merged into it (for drawing; the
    /// solvers sample every cell).
    pub fn mask_runs(&self, bounds: (Vec2, Vec2), max: u32) -> Vec<[Vec2; 2]> {
        let Some((image, r, threshold, invert)) = self.loaded_mask(bounds) else {
            return Vec::new();
        };
        let (cols, rows) = (image.width.min(max), image.height.min(max));
        let (dx, dz) = (
            (r[1][0] - r[0][0]) / cols as f32,
            (r[1][1] - r[0][1]) / rows as f32,
        );
        let mut runs: Vec<[Vec2; 2]> = Vec::new();
        // Runs open on the row above, by their columns: a run that spans the same columns
        // on the next row grows down instead of starting a new rectangle (a wall is one box,
        // not one per row).
        let mut open: std::collections::HashMap<(u32, u32), usize> = Default::default();
        for row in 0..rows {
            let mut next = std::collections::HashMap::new();
            let v = (row as f32 + 0.5) / rows as f32;
            let mut start = None;
            for col in 0..=cols {
                let solid = col < cols
                    && image.solid_at((col as f32 + 0.5) / cols as f32, v, threshold, invert);
                match (solid, start) {
                    (true, None) => start = Some(col),
                    (false, Some(c0)) => {
                        let bottom = r[0][1] + (row + 1) as f32 * dz;
                        let k = match open.get(&(c0, col)) {
                            Some(&k) => {
                                runs[k][1][1] = bottom;
                                k
                            }
                            None => {
                                runs.push([
                                    [r[0][0] + c0 as f32 * dx, r[0][1] + row as f32 * dz],
                                    [r[0][0] + col as f32 * dx, bottom],
                                ]);
                                runs.len() - 1
                            }
                        };
                        next.insert((c0, col), k);
                        start = None;
                    }
                    _ => {}
                }
            }
            open = next;
        }
        runs
    }

    /// The shape moved by `d` metres (a mask's rectangle, placed over the world when it had
    /// none).
    pub fn translate(&mut self, d: Vec2, bounds: (Vec2, Vec2)) {
        match self {
            Self::Circle { center, .. } => {
                center[0] += d[0];
                center[1] += d[1];
            }
            Self::Polygon { points } => {
                for p in points {
                    p[0] += d[0];
                    p[1] += d[1];
                }
            }
            Self::Mask { rect, .. } => {
                let [a, b] = placed(rect, bounds);
                *rect = Some([[a[0] + d[0], a[1] + d[1]], [b[0] + d[0], b[1] + d[1]]]);
            }
        }
    }
}

/// A named ambient layer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AmbientLayer {
    /// Stable id, unique among the layout's ambient layers.
    pub id: u32,
    /// At most 256 characters.
    #[schemars(length(max = NAME_MAX))]
    pub name: String,
    #[serde(default = "yes")]
    pub enabled: bool,
    pub kind: AmbientKind,
    /// Keyframes of the layer's strength and direction over time (a factor on its speeds,
    /// and a turn of its direction), at most 1,000, in time order; none: steady.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[schemars(length(max = KEYS_MAX))]
    pub keys: Vec<Key>,
    /// Locked: drawn on the map but not picked, moved or nudged there, and not changed in the
    /// inspector (the Layers list still selects it, and unlocks it).
    #[serde(default, skip_serializing_if = "is_false")]
    pub locked: bool,
    /// Hidden: not drawn on the map or in the 3D view, and not picked there; it still acts on
    /// the wind (switch a tree or layer off with `enabled`).
    #[serde(default, skip_serializing_if = "is_false")]
    pub hidden: bool,
}

/// Ambient wind sources; each defines a target wind field `w(x, t)` in m/s.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum AmbientKind {
    /// Constant wind with gusts (Unity WindZone): `main × (1 + pulse)` plus turbulence.
    Directional {
        direction_deg: f32,
        /// Steady speed, m/s.
        #[schemars(range(min = AMBIENT_SPEED.min, max = AMBIENT_SPEED.max))]
        main: f32,
        /// Amplitude (m/s) of spatially varying noise added to the wind.
        #[schemars(range(min = AMBIENT_SPEED.min, max = AMBIENT_SPEED.max))]
        turbulence: f32,
        /// Relative size of periodic gusts (0 = none, 1 = doubles the wind at the peak).
        #[schemars(range(min = PULSE_MAGNITUDE.min, max = PULSE_MAGNITUDE.max))]
        pulse_magnitude: f32,
        /// Gusts per second.
        #[schemars(range(min = PULSE_FREQUENCY.min, max = PULSE_FREQUENCY.max))]
        pulse_frequency: f32,
    },
    /// Gradient noise scrolled along the wind direction (Ghost of Tsushima, Godot demo).
    Noise {
        direction_deg: f32,
        /// Feature size in metres.
        #[schemars(range(min = FEATURE_LENGTH.min, max = FEATURE_LENGTH.max))]
        scale: f32,
        /// Scroll speed in m/s.
        #[schemars(range(min = SCROLL_SPEED.min, max = SCROLL_SPEED.max))]
        speed: f32,
        /// Peak wind in m/s.
        #[schemars(range(min = AMBIENT_SPEED.min, max = AMBIENT_SPEED.max))]
        strength: f32,
    },
    /// Tessendorf/Phillips-spectrum gust field, inverse-FFT'd, tiling every `tile_size` metres.
    Fft {
        direction_deg: f32,
        /// Wind speed V in m/s (sets the spectrum's peak, L = V²/g) and the mean wind.
        #[schemars(range(min = FFT_WIND_SPEED.min, max = FFT_WIND_SPEED.max))]
        wind_speed: f32,
        /// Gust amplitude in m/s (standard deviation of the gust field).
        #[schemars(range(min = AMBIENT_SPEED.min, max = AMBIENT_SPEED.max))]
        amplitude: f32,
        /// FFT size per axis (power of two, 8–512).
        #[schemars(range(min = FFT_RESOLUTION.min, max = FFT_RESOLUTION.max))]
        resolution: u32,
        /// Metres covered by one FFT tile.
        #[schemars(range(min = FEATURE_LENGTH.min, max = FEATURE_LENGTH.max))]
        tile_size: f32,
        seed: u64,
    },
    /// Trigonometric baseline: `amplitude × sin(2π (x·d / wavelength − frequency t))`.
    Sine {
        direction_deg: f32,
        #[schemars(range(min = AMBIENT_SPEED.min, max = AMBIENT_SPEED.max))]
        amplitude: f32,
        #[schemars(range(min = FEATURE_LENGTH.min, max = FEATURE_LENGTH.max))]
        wavelength: f32,
        #[schemars(range(min = SINE_FREQUENCY.min, max = SINE_FREQUENCY.max))]
        frequency: f32,
    },
}

impl AmbientLayer {
    /// An enabled layer, shown, unlocked, without keyframes.
    pub fn new(id: u32, name: &str, kind: AmbientKind) -> Self {
        Self {
            id,
            name: name.into(),
            enabled: true,
            kind,
            keys: Vec::new(),
            locked: false,
            hidden: false,
        }
    }
}

impl AmbientKind {
    pub fn type_name(&self) -> &'static str {
        match self {
            Self::Directional { .. } => "directional",
            Self::Noise { .. } => "noise",
            Self::Fft { .. } => "fft",
            Self::Sine { .. } => "sine",
        }
    }
}

/// Fluid solver parameters (defaults: the WebGL reference solver, wind-model.md §2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default)]
#[serde(deny_unknown_fields)]
pub struct SimParams {
    /// Seconds per step, 0.0001 to 1/30. Bakes may step a little shorter so that frames
    /// fall exactly on the frame rate.
    #[schemars(range(min = DT.min, max = DT.max))]
    pub dt: f32,
    /// Solver substeps per step (each of `dt / substeps`).
    #[schemars(range(min = SUBSTEPS.min, max = SUBSTEPS.max))]
    pub substeps: u32,
    /// How the projection solves for pressure: Jacobi iterations or multigrid V-cycles.
    pub pressure: PressureSolve,
    /// Jacobi iterations per projection (`pressure = "jacobi"`).
    #[schemars(range(min = PRESSURE_ITERATIONS.min, max = PRESSURE_ITERATIONS.max))]
    pub pressure_iterations: u32,
    /// V-cycles per projection (`pressure = "multigrid"`).
    #[schemars(range(min = PRESSURE_CYCLES.min, max = PRESSURE_CYCLES.max))]
    pub pressure_cycles: u32,
    /// Jacobi's warm start: the previous pressure is multiplied by this (0 = cold start).
    /// Multigrid ignores it and starts from [`MULTIGRID_WARM_START`] of the previous pressure.
    #[schemars(range(min = PRESSURE_DECAY.min, max = PRESSURE_DECAY.max))]
    pub pressure_decay: f32,
    /// Vorticity confinement strength ε: the force `r(ε)·h·min(1, |v|/U)·w·N` (h the cell
    /// size in metres, U the layout's strongest arrow or ambient wind) with the rate r(ε) = ε
    /// up to 2, then rising ever more slowly toward 5, so the paper's factor 50 (texel units)
    /// confines at the ceiling. Confinement never pushes the wind past U (docs/SOLVER.md).
    #[schemars(range(min = VORTICITY.min, max = VORTICITY.max))]
    pub vorticity: f32,
    /// Velocity dissipation rate (1/s): `vel /= 1 + dissipation × dt`.
    #[schemars(range(min = VELOCITY_DISSIPATION.min, max = VELOCITY_DISSIPATION.max))]
    pub velocity_dissipation: f32,
    /// Rate (1/s) at which the field relaxes toward the ambient layers' wind.
    #[schemars(range(min = AMBIENT_COUPLING.min, max = AMBIENT_COUPLING.max))]
    pub ambient_coupling: f32,
    /// Rate (1/s) at which an arrow brings the wind on its centre line up to its strength.
    #[schemars(range(min = ARROW_RESPONSE.min, max = ARROW_RESPONSE.max))]
    pub arrow_response: f32,
    pub boundary: Boundary,
    pub advection: Advection,
}

impl Default for SimParams {
    fn default() -> Self {
        Self {
            dt: 1.0 / 60.0,
            substeps: 1,
            pressure: PressureSolve::Multigrid,
            pressure_iterations: 20,
            pressure_cycles: 2,
            pressure_decay: 0.8,
            vorticity: 2.0,
            velocity_dissipation: 0.2,
            ambient_coupling: 1.0,
            arrow_response: 4.0,
            boundary: Boundary::Open,
            advection: Advection::SemiLagrangian,
        }
    }
}

/// The share of last step's pressure a multigrid solve starts from, whatever
/// `pressure_decay` says. A solve that converges gives the same pressure from any start, so
/// a decay only throws away work the cycle must redo (0.8 left a developed step's divergence
/// 2–4 times higher after one cycle); the 1% still taken off keeps the pressure's free
/// constants (closed or periodic worlds, fluid walled in by obstacles) from drifting.
pub const MULTIGRID_WARM_START: f32 = 0.99;

impl SimParams {
    /// The factor on last step's pressure that this step's solve starts from.
    pub fn warm_start(&self) -> f32 {
        match self.pressure {
            PressureSolve::Jacobi => self.pressure_decay,
            PressureSolve::Multigrid => MULTIGRID_WARM_START,
        }
    }
}

/// The pressure solve of each projection.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PressureSolve {
    /// `pressure_iterations` Jacobi sweeps: cheap, but they remove only the divergence that
    /// varies over a few cells, so large grids keep much of the rest.
    #[default]
    Jacobi,
    /// `pressure_cycles` multigrid V-cycles: every scale of the divergence at once.
    Multigrid,
}

/// What happens at the edge of the world.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Boundary {
    /// Walls: no flow through the edge.
    Closed,
    /// Outflow: zero-gradient velocity, zero pressure outside.
    #[default]
    Open,
    /// The field wraps; baked fields tile seamlessly.
    Periodic,
}

/// Advection scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Advection {
    /// First-order semi-Lagrangian (paper eqs. 9–10).
    #[default]
    SemiLagrangian,
    /// Limited MacCormack: second order, keeps gusts sharp.
    MacCormack,
}

/// Grass preview parameters (paper eqs. 11–14 and the Bezier model of Jahrmann & Wimmer).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default)]
#[serde(deny_unknown_fields)]
pub struct GrassParams {
    /// Blades per square metre.
    #[schemars(range(max = GRASS_DENSITY.max), extend("exclusiveMinimum" = 0))]
    pub density: f32,
    /// Blade height range `[min, max]` in metres.
    #[schemars(extend("items" = {"type": "number", "format": "float", "exclusiveMinimum": 0, "maximum": BLADE_HEIGHT.max}))]
    pub height: Vec2,
    /// Blade width range `[min, max]` in metres.
    #[schemars(extend("items" = {"type": "number", "format": "float", "exclusiveMinimum": 0, "maximum": BLADE_WIDTH.max}))]
    pub width: Vec2,
    /// Stiffness range `[min, max]` (Bezier model recovery).
    #[schemars(extend("items" = {"type": "number", "format": "float", "exclusiveMinimum": 0, "maximum": STIFFNESS.max}))]
    pub stiffness: Vec2,
    /// Gravity bend, eq. 11.
    #[schemars(range(min = BEND.min, max = BEND.max))]
    pub k1: f32,
    /// Forward bend, eq. 11.
    #[schemars(range(min = BEND.min, max = BEND.max))]
    pub k2: f32,
    /// Stiffness blend λ of eq. 13 (1 stiff, 0 fully driven).
    #[schemars(range(min = LAMBDA.min, max = LAMBDA.max))]
    pub lambda: f32,
    pub shadow: Shadow,
    /// Base-to-tip colour gradients; each blade picks one.
    pub palettes: Vec<Palette>,
    pub seed: u64,
    pub model: GrassModel,
    /// Where the level has grass: a grey image (PNG 8/16-bit or EXR, relative to the layout
    /// file) over the world (or its `rect`), its luminance 0–1 multiplying `density` (black:
    /// no grass, on roads and water).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub density_map: Option<DensityMap>,
}

/// A grass density map: its image, and the image's pixels once `io` has read them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DensityMap {
    #[schemars(length(min = 1))]
    pub image: String,
    /// Where the image lies, `[[x0, z0], [x1, z1]]` in metres, as a mask's or the backdrop's;
    /// absent: the world rectangle. Outside it the grass grows at the full density.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(inner(inner(inner(range(min = COORD.min, max = COORD.max)))))]
    pub rect: Option<[Vec2; 2]>,
    #[serde(skip)]
    #[schemars(skip)]
    pub pixels: MaskPixels,
}

impl DensityMap {
    /// The density's share at world point `p` (`bounds`: the world's), 0 to 1; 1 where the
    /// image is not loaded or does not reach (the grass grows as if there were no map).
    pub fn at(&self, p: Vec2, bounds: (Vec2, Vec2)) -> f32 {
        let Some(m) = self.pixels.image() else {
            return 1.0;
        };
        image_uv(placed(&self.rect, bounds), p).map_or(1.0, |[u, v]| m.luminance_at(u, v))
    }
}

impl Default for GrassParams {
    fn default() -> Self {
        Self {
            density: 60.0,
            height: [0.3, 0.7],
            width: [0.02, 0.05],
            stiffness: [0.5, 1.5],
            k1: 0.05,
            k2: 0.1,
            lambda: 0.2,
            shadow: Shadow::default(),
            palettes: vec![
                Palette {
                    name: "meadow".into(),
                    base: [0.10, 0.22, 0.05],
                    tip: [0.45, 0.65, 0.20],
                },
                Palette {
                    name: "dry".into(),
                    base: [0.25, 0.25, 0.08],
                    tip: [0.75, 0.70, 0.35],
                },
            ],
            seed: 1,
            model: GrassModel::CwdQuadratic,
            density_map: None,
        }
    }
}

/// Height-based self-shadow, eq. 14: `base × clamp(y − |F|·c1 + c2, m_min, m_max)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default)]
#[serde(deny_unknown_fields)]
pub struct Shadow {
    #[schemars(range(min = SHADOW_CLAMP.min, max = SHADOW_CLAMP.max))]
    pub m_min: f32,
    #[schemars(range(min = SHADOW_CLAMP.min, max = SHADOW_CLAMP.max))]
    pub m_max: f32,
    #[schemars(range(min = SHADOW_TERM.min, max = SHADOW_TERM.max))]
    pub c1: f32,
    #[schemars(range(min = SHADOW_TERM.min, max = SHADOW_TERM.max))]
    pub c2: f32,
}

impl Default for Shadow {
    fn default() -> Self {
        Self {
            m_min: 0.35,
            m_max: 1.0,
            c1: 0.05,
            c2: 0.55,
        }
    }
}

/// A blade colour gradient, linear RGB 0–1.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Palette {
    pub name: String,
    #[schemars(inner(range(min = COLOUR.min, max = COLOUR.max)))]
    pub base: [f32; 3],
    #[schemars(inner(range(min = COLOUR.min, max = COLOUR.max)))]
    pub tip: [f32; 3],
}

/// Blade deformation model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum GrassModel {
    /// The paper's grouped quadratic deformation (eqs. 11–14).
    #[default]
    CwdQuadratic,
    /// Jahrmann & Wimmer Bezier blades with a physics compute pass.
    BezierPhysics,
}

impl Layout {
    /// What File → New starts: an empty 100 m × 100 m world on a 200 × 200 grid.
    pub fn untitled(name: &str) -> Self {
        Self::new(name, [100.0, 100.0], [200, 200])
    }

    /// A new, empty layout over a `width × depth` world.
    pub fn new(name: &str, size: Vec2, grid: [u32; 2]) -> Self {
        Self {
            format: FORMAT.into(),
            version: VERSION,
            name: name.into(),
            world: World {
                size,
                origin: [0.0, 0.0],
                grid,
                map: None,
                profile: VerticalProfile::default(),
                terrain: None,
            },
            trees: Vec::new(),
            obstacles: Vec::new(),
            ambient: Vec::new(),
            probes: Vec::new(),
            sim: SimParams::default(),
            grass: GrassParams::default(),
            timeline: Timeline::default(),
        }
    }

    /// All nodes of all trees, depth first, with their tree index.
    pub fn nodes(&self) -> impl Iterator<Item = (usize, &Node)> {
        self.trees
            .iter()
            .enumerate()
            .flat_map(|(t, tree)| tree.root.iter().map(move |n| (t, n)))
    }

    /// The largest id in use by any node, tree, obstacle, layer or probe, plus one.
    pub fn next_id(&self) -> u32 {
        let nodes = self.nodes().map(|(_, n)| n.id);
        let trees = self.trees.iter().map(|t| t.id);
        let obstacles = self.obstacles.iter().map(|o| o.id);
        let layers = self.ambient.iter().map(|a| a.id);
        let probes = self.probes.iter().map(|p| p.id);
        nodes
            .chain(trees)
            .chain(obstacles)
            .chain(layers)
            .chain(probes)
            .max()
            .map_or(1, |m| m + 1)
    }

    /// World rectangle `(min, max)` in metres.
    pub fn bounds(&self) -> (Vec2, Vec2) {
        let o = self.world.origin;
        let s = self.world.size;
        (o, [o[0] + s[0], o[1] + s[1]])
    }
}

impl Tree {
    /// Whether the map picks and moves it: neither hidden nor locked.
    pub fn pickable(&self) -> bool {
        !self.hidden && !self.locked
    }
}

impl Obstacle {
    /// Whether the map picks and moves it: neither hidden nor locked.
    pub fn pickable(&self) -> bool {
        !self.hidden && !self.locked
    }
}

impl Node {
    pub fn new(id: u32, pos: Vec2, strength: f32, radius: f32) -> Self {
        Self {
            id,
            pos,
            strength,
            radius,
            children: Vec::new(),
            keys: Vec::new(),
        }
    }

    /// This node and all its descendants, depth first (parents before children).
    pub fn iter(&self) -> NodeIter<'_> {
        NodeIter { stack: vec![self] }
    }

    /// Finds a node of this subtree by id.
    pub fn find(&self, id: u32) -> Option<&Node> {
        self.iter().find(|n| n.id == id)
    }

    /// Finds a node of this subtree by id, mutably.
    pub fn find_mut(&mut self, id: u32) -> Option<&mut Node> {
        if self.id == id {
            return Some(self);
        }
        self.children.iter_mut().find_map(|c| c.find_mut(id))
    }

    /// The parent of node `id` within this subtree and the child's index in it.
    pub fn parent_of(&self, id: u32) -> Option<(&Node, usize)> {
        for (i, c) in self.children.iter().enumerate() {
            if c.id == id {
                return Some((self, i));
            }
            if let Some(found) = c.parent_of(id) {
                return Some(found);
            }
        }
        None
    }

    /// Every arrow of this subtree as `(parent, child, path length from this node to the
    /// parent in metres)`, parents before children.
    pub fn arrows(&self) -> Vec<(&Node, &Node, f32)> {
        let mut out = Vec::new();
        let mut stack = vec![(self, 0.0f32)];
        while let Some((n, s)) = stack.pop() {
            for c in n.children.iter().rev() {
                out.push((n, c, s));
                let len = ((c.pos[0] - n.pos[0]).powi(2) + (c.pos[1] - n.pos[1]).powi(2)).sqrt();
                stack.push((c, s + len));
            }
        }
        out
    }

    pub fn count(&self) -> usize {
        self.iter().count()
    }
}

/// An arrow of a tree as its keys place it at a time: its ends, the factor on its strength,
/// its end node, and the distance along the tree from the root to its start.
#[derive(Debug, Clone, Copy)]
pub struct KeyedArrow<'a> {
    pub a: Vec2,
    pub b: Vec2,
    pub factor: f32,
    pub child: &'a Node,
    pub path_len: f32,
}

/// A turn about a point: its centre and the sine and cosine of its angle.
type Turn = (Vec2, f32, f32);

/// `p` turned by `turns`, the innermost (last) first, each as `centre + R·(p − centre)`.
fn turned(p: Vec2, turns: &[Turn]) -> Vec2 {
    turns.iter().rev().fold(p, |p, &(c, sin, cos)| {
        let d = [p[0] - c[0], p[1] - c[1]];
        [
            c[0] + cos * d[0] - sin * d[1],
            c[1] + sin * d[0] + cos * d[1],
        ]
    })
}

impl Tree {
    /// Every arrow as the keys place it at time `t`: the tree's keys scale every arrow and
    /// turn the tree about its root; a branch's keys (a point's) scale the arrow ending there
    /// and every arrow after it, and turn them about that arrow's start, within what the keys
    /// before them did. Without keys: the arrows as drawn, factor 1.
    pub fn keyed_arrows(&self, t: f32) -> Vec<KeyedArrow<'_>> {
        let (factor, turn) = key_values(&self.keys, t);
        let turn_about = |centre: Vec2, angle: f32| -> Option<Turn> {
            (angle != 0.0).then(|| {
                let (sin, cos) = crate::num::sin_cos(angle);
                (centre, sin, cos)
            })
        };
        let tree_turns: Vec<Turn> = turn_about(self.root.pos, turn).into_iter().collect();
        let mut out = Vec::new();
        let mut stack = vec![(&self.root, 0.0f32, factor, tree_turns)];
        while let Some((n, s, f, turns)) = stack.pop() {
            for c in n.children.iter().rev() {
                let (cf, ct) = if c.keys.is_empty() {
                    (f, turns.clone())
                } else {
                    let (kf, kt) = key_values(&c.keys, t);
                    let mut ct = turns.clone();
                    ct.extend(turn_about(n.pos, kt));
                    (f * kf, ct)
                };
                out.push(KeyedArrow {
                    a: turned(n.pos, &ct),
                    b: turned(c.pos, &ct),
                    factor: cf,
                    child: c,
                    path_len: s,
                });
                let len = ((c.pos[0] - n.pos[0]).powi(2) + (c.pos[1] - n.pos[1]).powi(2)).sqrt();
                stack.push((c, s + len, cf, ct));
            }
        }
        out
    }

    /// Whether any key (the tree's or a branch's) moves or scales its arrows.
    pub fn is_keyed(&self) -> bool {
        !self.keys.is_empty() || self.root.iter().any(|n| !n.keys.is_empty())
    }
}

/// Depth-first iterator over a node and its descendants.
pub struct NodeIter<'a> {
    stack: Vec<&'a Node>,
}

impl<'a> Iterator for NodeIter<'a> {
    type Item = &'a Node;
    fn next(&mut self) -> Option<&'a Node> {
        let n = self.stack.pop()?;
        self.stack.extend(n.children.iter().rev());
        Some(n)
    }
}

/// Unit vector for an angle measured from `+x` toward `+z`.
pub fn direction(deg: f32) -> Vec2 {
    let r = deg.to_radians();
    [crate::num::cos(r), crate::num::sin(r)]
}
