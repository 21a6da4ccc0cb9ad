//! The bake's `manifest.json`: what was baked, from which layout, on which solver, and how
//! each file's values and axes map to the world's wind.

use super::Format;
use crate::doc::{self, Layout};
use serde::Serialize;
use sha2::Digest;

/// One file of a bake, as the manifest describes it.
#[derive(Debug, Clone, Serialize, PartialEq)]
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
    /// How stored values map to world velocity.
    pub encoding: serde_json::Value,
    /// How the file's axes map to the world's.
    pub axes: serde_json::Value,
    pub bytes: u64,
}

/// The bake's `manifest.json`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Manifest {
    pub format: &'static str,
    pub version: u32,
    pub layout: LayoutInfo,
    pub grid: [usize; 2],
    pub world: WorldInfo,
    pub axes: serde_json::Value,
    pub frames: FramesInfo,
    /// Largest wind speed over all frames, m/s (the PNG flowmap scale).
    pub max_speed: f32,
    /// The solver that ran: `cpu`, or `gpu: ADAPTER`.
    pub solver: String,
    pub notes: Vec<String>,
    pub files: Vec<FileEntry>,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct LayoutInfo {
    pub name: String,
    /// `sha256:` of the layout's canonical JSON.
    pub hash: String,
}

#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WorldInfo {
    pub min: [f32; 2],
    pub max: [f32; 2],
    pub units: &'static str,
    pub cell_size: [f32; 2],
}

#[derive(Debug, Clone, Serialize, PartialEq)]
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

/// The content hash the manifest records: sha256 of the canonical layout JSON.
pub fn layout_hash(layout: &Layout) -> String {
    let digest = sha2::Sha256::digest(doc::to_json(layout).as_bytes());
    let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
    format!("sha256:{hex}")
}
