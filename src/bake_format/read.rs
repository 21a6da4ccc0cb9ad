//! The parts of a bake's `manifest.json` a reader needs, as the runtime reads them
//! (`docs/EXPORT.md`, "`manifest.json`"; its schema is `docs/manifest.schema.json`). Unknown
//! fields are ignored, so a newer bake with more to say still opens.

use serde::Deserialize;

#[derive(Debug, Clone, Deserialize)]
pub struct Manifest {
    pub format: String,
    pub version: u32,
    #[serde(default)]
    pub sequence: u64,
    pub frames: Frames,
    pub max_speed: f32,
    pub files: Vec<FileEntry>,
    #[serde(default)]
    pub profile: Option<Profile>,
    #[serde(default)]
    pub terrain: Option<Terrain>,
}

#[derive(Debug, Clone, Deserialize)]
pub struct Frames {
    pub count: usize,
    pub fps: f32,
    #[serde(rename = "loop")]
    pub looped: bool,
}

#[derive(Debug, Clone, Deserialize)]
pub struct FileEntry {
    pub name: String,
    pub format: String,
    #[serde(default)]
    pub frame: Option<usize>,
    #[serde(default)]
    pub resampled_from: Option<[usize; 2]>,
    pub encoding: Encoding,
    pub axes: Axes,
    pub bytes: u64,
}

#[derive(Debug, Clone, Deserialize)]
pub struct Encoding {
    pub sample: String,
    pub channels: Vec<Channel>,
}

/// `value (m/s) = stored × scale + offset`, along `axis`.
#[derive(Debug, Clone, Deserialize)]
pub struct Channel {
    pub name: String,
    pub quantity: String,
    #[serde(default)]
    pub axis: Option<String>,
    pub scale: f32,
    pub offset: f32,
}

#[derive(Debug, Clone, Deserialize)]
pub struct Axes {
    pub index: Vec<IndexAxis>,
    #[serde(default)]
    pub sub_images: Option<serde_json::Value>,
}

/// One index axis of a file, fastest first: the world axis it grows along (index 0 at the
/// world's minimum for `+`, its maximum for `-`), its cells and the world range they cover.
#[derive(Debug, Clone, Deserialize)]
pub struct IndexAxis {
    pub world: String,
    pub cells: usize,
    pub range: [f32; 2],
}

#[derive(Debug, Clone, Deserialize)]
pub struct Profile {
    pub roughness_length: f32,
    pub reference_height: f32,
    pub top: f32,
    #[serde(default)]
    pub factors: Vec<f32>,
}

/// `heights.png`: `height (m) = stored × scale + offset` at each cell's centre.
#[derive(Debug, Clone, Deserialize)]
pub struct Terrain {
    pub file: String,
    pub sample: String,
    pub scale: f32,
    pub offset: f32,
    pub axes: Vec<IndexAxis>,
}
