//! The bake's `manifest.json`: its types, tags and names are the format's own crate
//! (`src/bake_format/`, shared with the runtime that reads them); what is filled from the
//! layout is here: the profile block, its layers' factors, and the layout's content hash.

pub use windloom_bake_format::*;

use crate::doc::{self, Layout};
use sha2::Digest;

/// The manifest's `profile` block for the layout's vertical profile.
pub fn profile_info(p: &doc::VerticalProfile) -> ProfileInfo {
    ProfileInfo {
        law: LAW,
        roughness_length: p.roughness_length,
        reference_height: p.reference_height,
        top: p.top,
        layers: p.layers,
        heights: (0..p.layers).map(|k| p.layer_height(k)).collect(),
        factors: factors(p),
    }
}

/// The wind at each layer as a multiple of the simulated wind.
pub(crate) fn factors(p: &doc::VerticalProfile) -> Vec<f32> {
    (0..p.layers).map(|k| p.factor(p.layer_height(k))).collect()
}

/// The content hash the manifest records: sha256 of the canonical layout JSON.
pub fn layout_hash(layout: &Layout) -> String {
    let digest = sha2::Sha256::digest(doc::to_json(layout).as_bytes());
    let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
    format!("sha256:{hex}")
}
