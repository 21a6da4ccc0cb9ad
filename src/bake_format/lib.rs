//! The format of a windloom bake, shared by its writer (windloom's `bake/`) and its readers
//! (the runtime a game links; the Godot add-on follows the same): the manifest's types as
//! written (each deriving its JSON Schema with the `schema` feature:
//! `docs/manifest.schema.json`, `windloom schema --manifest`), the format tags, the file
//! names, the version, the atlas grid, and the part a reader reads ([`read`]). One crate, so
//! the writer and the reader of one format cannot drift apart: its tests write a manifest
//! with the writer's types and read it with the reader's.
//!
//! `manifest.json`: what was baked, from which layout, on which solver, how each
//! file's stored values and axes map to the world's wind, and the settings each engine
//! imports it with. Every type here derives its JSON Schema (`docs/manifest.schema.json`,
//! `windloom schema --manifest`).
//!
//! One decode rule holds for every file: a channel's value, in m/s along the channel's world
//! axis, is `stored × scale + offset`, where `stored` is what a reader samples (a float as
//! written; an integer channel as a GPU samples it, divided by 255 or 65535; the number in a
//! text file).

pub mod engines;
mod formats;
pub mod read;

pub use engines::Engines;
pub use formats::Format;

use serde::Serialize;

/// The manifest's `format`.
pub const FORMAT: &str = "windloom-bake";

/// The vertical profile's law (`profile.law`): the baked wind stands for the wind at the
/// reference height `h_ref` above the ground, and `u(h)` carries it up and down.
pub const LAW: &str = "log: u(h) = u_ref · ln(h / z0) / ln(h_ref / z0) for h > z0, else 0";

/// The terrain's heights file, where a layout has terrain.
pub const HEIGHTS: &str = "heights.png";

/// The manifest's `version`: 2 made `encoding` and `axes` data (v1 held prose) and added
/// `world_axes`, `engines` and `sequence`.
pub const MANIFEST_VERSION: u32 = 2;

/// A world axis with its sign: a channel holds the wind along it; a file's index grows along it.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum WorldAxis {
    #[serde(rename = "+x")]
    PlusX,
    #[serde(rename = "-x")]
    MinusX,
    #[serde(rename = "+y")]
    PlusY,
    #[serde(rename = "-y")]
    MinusY,
    #[serde(rename = "+z")]
    PlusZ,
    #[serde(rename = "-z")]
    MinusZ,
}

/// What a reader samples from a file.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Sample {
    /// 8-bit unsigned integers, read as `n / 255` (as a GPU samples a UNORM texture).
    Unorm8,
    /// 16-bit unsigned integers, read as `n / 65535`.
    Unorm16,
    /// IEEE half floats.
    F16,
    /// IEEE single floats.
    F32,
    /// Decimal numbers in text.
    Text,
}

/// What a channel holds.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// The wind along the channel's `axis`.
    Velocity,
    /// The wind's horizontal speed.
    Speed,
    /// Nothing: always zero after decoding.
    Unused,
}

/// One channel of a file: `value (m/s) = stored × scale + offset`.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct Channel {
    /// The channel's name in the file: `R`, `G`, `B`, `A`; `X`, `Y`, `Z`; `x`, `z`.
    pub name: &'static str,
    pub quantity: Quantity,
    /// For a velocity channel: the world axis, with its sign, whose wind it holds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub axis: Option<WorldAxis>,
    pub scale: f32,
    pub offset: f32,
}

impl Channel {
    pub fn velocity(name: &'static str, axis: WorldAxis, scale: f32, offset: f32) -> Self {
        Self {
            name,
            quantity: Quantity::Velocity,
            axis: Some(axis),
            scale,
            offset,
        }
    }

    pub fn speed(name: &'static str) -> Self {
        Self {
            name,
            quantity: Quantity::Speed,
            axis: None,
            scale: 1.0,
            offset: 0.0,
        }
    }

    pub fn unused(name: &'static str) -> Self {
        Self {
            name,
            quantity: Quantity::Unused,
            axis: None,
            scale: 0.0,
            offset: 0.0,
        }
    }
}

/// How a file's stored values become wind.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct Encoding {
    pub sample: Sample,
    /// The decoded values' unit: always `m/s`.
    pub units: &'static str,
    /// Every channel a reader finds, in the file's order.
    pub channels: Vec<Channel>,
    /// For flowmaps and the atlas: green holds the −z wind (`--flip-green`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub green_flipped: Option<bool>,
    /// How the file is laid out, for a reader writing its own parser.
    pub storage: String,
}

/// One index axis of a file.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct IndexAxis {
    /// The axis's name in the file: `pixel_x`, `pixel_y` (down the image), `X`, `Y`, `Z`,
    /// `i`, `j`, `layer`.
    pub name: &'static str,
    /// The world axis the index grows along; index 0 sits at the world's minimum along it
    /// when the sign is `+`, at its maximum when `-`.
    pub world: WorldAxis,
    /// Cells along it.
    pub cells: usize,
    /// The world extent the cells cover along the unsigned axis, metres.
    pub range: [f32; 2],
}

/// An atlas's grid of frames.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct SubImages {
    pub columns: usize,
    pub rows: usize,
    pub count: usize,
    pub fps: f32,
    /// Frame `k` sits at column `k % columns`, row `k / columns`, row 0 at the top; unused
    /// sub-images hold zero wind.
    pub order: &'static str,
}

/// How a file's axes map to the world's.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct Axes {
    /// The file's index axes, fastest first (within one sub-image, for an atlas).
    pub index: Vec<IndexAxis>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sub_images: Option<SubImages>,
    /// The engine frame the file is written in, where it is an engine's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub engine_frame: Option<&'static str>,
}

/// One file of a bake, as the manifest describes it.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct FileEntry {
    pub name: String,
    pub format: Format,
    /// Which frame (absent for files holding all frames).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frame: Option<usize>,
    /// Cells per axis in this file (after any resampling).
    pub grid: [usize; 2],
    /// The baked grid this file was area-averaged down from, if it was.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resampled_from: Option<[usize; 2]>,
    pub encoding: Encoding,
    pub axes: Axes,
    pub bytes: u64,
    /// The CRC-32 of the file's bytes (ISO-HDLC, as zlib and PNG compute it): how a later
    /// bake into this folder tells the file this bake wrote from one put there since.
    pub crc32: u32,
}

/// The world's frame, as data.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct WorldAxes {
    /// `east`.
    pub x: &'static str,
    /// `up`.
    pub y: &'static str,
    /// `south`.
    pub z: &'static str,
    pub right_handed: bool,
    pub units: &'static str,
}

pub const WORLD_AXES: WorldAxes = WorldAxes {
    x: "east",
    y: "up",
    z: "south",
    right_handed: true,
    units: "m",
};

/// The bake's `manifest.json`.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct Manifest {
    /// Always `windloom-bake`.
    pub format: &'static str,
    pub version: u32,
    /// Counts the bakes into this folder: one more than the bake this one replaced (1 in a
    /// new folder). A reader polling the folder (`bake --watch`, the editor's Live export)
    /// reloads when it changes.
    pub sequence: u64,
    pub layout: LayoutInfo,
    pub grid: [usize; 2],
    pub world: WorldInfo,
    pub world_axes: WorldAxes,
    pub frames: FramesInfo,
    /// Largest wind speed over all frames, m/s (the PNG flowmap scale).
    pub max_speed: f32,
    /// The solver that ran: `cpu`, or `gpu: ADAPTER`.
    pub solver: String,
    pub notes: Vec<String>,
    pub files: Vec<FileEntry>,
    /// The vertical profile: the height the baked wind stands for, the law that carries it
    /// up and down (what the runtime answers with), and the layers of the volume files
    /// (`dds`). Every bake since 2026-12 has it; earlier ones only with `dds`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profile: Option<ProfileInfo>,
    /// The settings each engine's guide and script import these files with.
    pub engines: Engines,
    /// The ground the wind was shaped by (`heights.png`), where the layout has terrain.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub terrain: Option<TerrainInfo>,
}

/// The terrain's heights file: `height (m) = stored × scale + offset` at each baked cell's
/// centre, `stored` sampled as `sample` says (for `unorm16`, `n / 65535`).
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct TerrainInfo {
    /// Always `heights.png`: a 16-bit grey PNG.
    pub file: &'static str,
    pub sample: Sample,
    /// Always `m`.
    pub units: &'static str,
    pub scale: f32,
    pub offset: f32,
    /// The image's axes: `pixel_x` along `+x`, `pixel_y` (down the image) along `+z`, one
    /// pixel a baked cell.
    pub axes: Vec<IndexAxis>,
    /// The layout's heightmap the heights were sampled from.
    pub heightmap: String,
    /// How strongly the terrain shaped the wind (the layout's `world.terrain.strength`).
    pub strength: f32,
    /// The feature length, metres, slope and curvature were measured over.
    pub feature_length: f32,
    pub bytes: u64,
    /// The CRC-32 of the file's bytes, as each file entry's `crc32`.
    pub crc32: u32,
}

/// The vertical profile: the baked wind stands for the wind at `reference_height` above the
/// ground; a volume's layer `k` holds it times `factors[k]`.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct ProfileInfo {
    /// `log: u(h) = u_ref · ln(h / z0) / ln(h_ref / z0) for h > z0, else 0`.
    pub law: &'static str,
    /// `z0`, metres.
    pub roughness_length: f32,
    /// `h_ref`: the height the simulated wind stands for, metres.
    pub reference_height: f32,
    /// The volume's top, metres above the ground.
    pub top: f32,
    pub layers: u32,
    /// The height of each layer's centre, metres.
    pub heights: Vec<f32>,
    /// Each layer's wind as a multiple of the simulated wind.
    pub factors: Vec<f32>,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct LayoutInfo {
    pub name: String,
    /// `sha256:` of the layout's canonical JSON.
    pub hash: String,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct WorldInfo {
    pub min: [f32; 2],
    pub max: [f32; 2],
    pub units: &'static str,
    pub cell_size: [f32; 2],
}

#[derive(Debug, Clone, Serialize, PartialEq)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(deny_unknown_fields))]
pub struct FramesInfo {
    pub count: usize,
    pub fps: f32,
    #[serde(rename = "loop")]
    pub looped: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub loop_method: Option<&'static str>,
    /// Simulated seconds before frame 0 (the asked warm-up rounded to whole frames). Frame
    /// `k` is the wind at `warmup_seconds + k / fps` (for loops, see `loop_method`).
    pub warmup_seconds: f64,
    /// The solver step used: `1 / (fps · steps_per_frame)`, at most the layout's `sim.dt`.
    pub sim_dt: f32,
    pub steps_per_frame: usize,
    /// The layout's own `sim.dt`, the longest step the bake may take.
    pub layout_dt: f32,
}

pub const MANIFEST: &str = "manifest.json";

#[cfg(feature = "schema")]
/// The JSON Schema of `manifest.json` (`docs/manifest.schema.json`).
pub fn schema() -> serde_json::Value {
    serde_json::to_value(schemars::schema_for!(Manifest)).expect("a schema is always JSON")
}

/// Largest atlas side in pixels: what GPUs accept as a texture side.
pub const ATLAS_MAX_SIDE: usize = 16384;

/// The atlas's grid of sub-images for `n` frames: `(columns, rows)`.
pub fn atlas_grid(n: usize) -> (usize, usize) {
    let columns = (n as f64).sqrt().ceil() as usize;
    (columns, n.div_ceil(columns))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axis(name: &'static str, world: WorldAxis, cells: usize, range: [f32; 2]) -> IndexAxis {
        IndexAxis {
            name,
            world,
            cells,
            range,
        }
    }

    /// A manifest as windloom writes one: a raw file of two frames, a 16-bit flowmap a
    /// frame with its green flipped, the profile and the terrain.
    fn written() -> Manifest {
        let image = vec![
            axis("pixel_x", WorldAxis::PlusX, 4, [-2.0, 6.0]),
            axis("pixel_y", WorldAxis::PlusZ, 3, [1.0, 7.0]),
        ];
        let flow = |k: usize| FileEntry {
            name: format!("flow16_{k:04}.png"),
            format: Format::Png16,
            frame: Some(k),
            grid: [4, 3],
            resampled_from: None,
            encoding: Encoding {
                sample: Sample::Unorm16,
                units: "m/s",
                channels: vec![
                    Channel::velocity("R", WorldAxis::PlusX, 14.0, -7.0),
                    Channel::velocity("G", WorldAxis::MinusZ, 14.0, -7.0),
                    Channel::unused("B"),
                ],
                green_flipped: Some(true),
                storage: "PNG".into(),
            },
            axes: Axes {
                index: image.clone(),
                sub_images: None,
                engine_frame: None,
            },
            bytes: 300 + k as u64,
            crc32: 7,
        };
        Manifest {
            format: FORMAT,
            version: MANIFEST_VERSION,
            sequence: 5,
            layout: LayoutInfo {
                name: "a".into(),
                hash: "sha256:0".into(),
            },
            grid: [4, 3],
            world: WorldInfo {
                min: [-2.0, 1.0],
                max: [6.0, 7.0],
                units: "m",
                cell_size: [2.0, 2.0],
            },
            world_axes: WORLD_AXES,
            frames: FramesInfo {
                count: 2,
                fps: 12.5,
                looped: true,
                loop_method: None,
                warmup_seconds: 1.0,
                sim_dt: 0.01,
                steps_per_frame: 8,
                layout_dt: 0.02,
            },
            max_speed: 7.0,
            solver: "cpu".into(),
            notes: vec![],
            files: vec![
                FileEntry {
                    name: "wind.f32".into(),
                    format: Format::Raw,
                    frame: None,
                    grid: [4, 3],
                    resampled_from: None,
                    encoding: Encoding {
                        sample: Sample::F32,
                        units: "m/s",
                        channels: vec![
                            Channel::velocity("x", WorldAxis::PlusX, 1.0, 0.0),
                            Channel::velocity("z", WorldAxis::PlusZ, 1.0, 0.0),
                        ],
                        green_flipped: None,
                        storage: "f32".into(),
                    },
                    axes: Axes {
                        index: vec![
                            axis("i", WorldAxis::PlusX, 4, [-2.0, 6.0]),
                            axis("j", WorldAxis::PlusZ, 3, [1.0, 7.0]),
                        ],
                        sub_images: None,
                        engine_frame: None,
                    },
                    bytes: 192,
                    crc32: 9,
                },
                flow(0),
                flow(1),
            ],
            profile: Some(ProfileInfo {
                law: LAW,
                roughness_length: 0.03,
                reference_height: 2.0,
                top: 20.0,
                layers: 2,
                heights: vec![5.0, 15.0],
                factors: vec![1.2, 1.5],
            }),
            engines: Engines::default(),
            terrain: Some(TerrainInfo {
                file: HEIGHTS,
                sample: Sample::Unorm16,
                units: "m",
                scale: 10.0,
                offset: -1.0,
                axes: image,
                heightmap: "h.png".into(),
                strength: 1.0,
                feature_length: 8.0,
                bytes: 99,
                crc32: 3,
            }),
        }
    }

    /// What the writer's types write, the reader's types read, field for field: the
    /// writer and the reader of the format cannot drift apart unseen.
    #[test]
    fn what_the_writer_writes_the_reader_reads() {
        let w = written();
        let text = serde_json::to_string_pretty(&w).expect("a manifest serialises");
        let r: read::Manifest = serde_json::from_str(&text).expect("the reader reads it");
        assert_eq!(
            (r.format.as_str(), r.version, r.sequence),
            (FORMAT, MANIFEST_VERSION, 5)
        );
        assert_eq!(
            (r.frames.count, r.frames.fps, r.frames.looped, r.max_speed),
            (2, 12.5, true, 7.0)
        );
        assert_eq!(r.files.len(), w.files.len());
        for (r, w) in r.files.iter().zip(&w.files) {
            assert_eq!(
                (&r.name, r.format.as_str(), r.frame, r.bytes),
                (&w.name, w.format.name(), w.frame, w.bytes)
            );
            assert_eq!(r.encoding.channels.len(), w.encoding.channels.len());
            for (rc, wc) in r.encoding.channels.iter().zip(&w.encoding.channels) {
                let axis = wc.axis.map(|a| serde_json::to_value(a).expect("an axis"));
                assert_eq!(
                    (rc.name.as_str(), rc.scale, rc.offset),
                    (wc.name, wc.scale, wc.offset)
                );
                assert_eq!(rc.axis.as_deref(), axis.as_ref().and_then(|a| a.as_str()));
            }
            for (ra, wa) in r.axes.index.iter().zip(&w.axes.index) {
                let world = serde_json::to_value(wa.world).expect("an axis");
                assert_eq!(
                    (Some(ra.world.as_str()), ra.cells, ra.range),
                    (world.as_str(), wa.cells, wa.range)
                );
            }
        }
        let (rp, wp) = (r.profile.expect("a profile"), w.profile.expect("a profile"));
        assert_eq!(
            (
                rp.roughness_length,
                rp.reference_height,
                rp.top,
                &rp.factors
            ),
            (
                wp.roughness_length,
                wp.reference_height,
                wp.top,
                &wp.factors
            )
        );
        let (rt, wt) = (r.terrain.expect("terrain"), w.terrain.expect("terrain"));
        assert_eq!(
            (
                rt.file.as_str(),
                rt.sample.as_str(),
                rt.scale,
                rt.offset,
                rt.axes.len()
            ),
            (HEIGHTS, "unorm16", wt.scale, wt.offset, 2)
        );
    }
}
