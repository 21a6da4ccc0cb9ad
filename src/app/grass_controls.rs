//! The 3D view's own controls (egui only; the GPU side is `gpu_view.rs`): a toggle per
//! culling test, for the LOD and for the far field, the wind colours, the pushing sphere and
//! its trail, and the counters line — blades total, culled by each test, drawn per LOD level.
//! (The arrows' toggle is in the View menu: the row has no room left.)

use crate::gpu::grass::CullStats;
use crate::grass::cull::{CullParams, LOD_SEGMENTS};
use eframe::egui;

/// What the user set in the 3D view (kept across blade rebuilds, not saved in the layout: it
/// is how the view draws, not what the level is).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GrassControls {
    /// `None` until the first renderer gives its defaults (they follow the blade height).
    pub cull: Option<CullParams>,
    /// The ground shows the grass's look from afar where fewer blades are drawn than the field
    /// holds (`crate::grass::far`).
    pub far: bool,
    /// Left-drag pushes a sphere through the grass instead of orbiting.
    pub push: bool,
    pub radius: f32,
    pub lifetime: f32,
    /// The grass and ground coloured by the wind's speed, on the map view's scale, so a still
    /// view shows where the wind blows; and how opaque those colours are.
    pub wind_colours: bool,
    pub wind_opacity: f32,
    /// The AGC arrows drawn over everything; off, the grass is seen as it will look in the
    /// game (View → Arrows in the 3D view).
    pub arrows: bool,
}

/// The wind colours' opacity slider's range (saved settings are clamped into it).
pub const WIND_OPACITY: std::ops::RangeInclusive<f32> = 0.1..=1.0;

impl Default for GrassControls {
    fn default() -> Self {
        Self {
            cull: None,
            far: true,
            push: false,
            radius: 0.6,
            lifetime: crate::gpu::grass::TRAIL_LIFETIME,
            wind_colours: false,
            wind_opacity: 0.6,
            arrows: true,
        }
    }
}

impl GrassControls {
    /// One row of toggles and sliders.
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            if let Some(c) = &mut self.cull {
                ui.label("Cull:");
                ui.checkbox(&mut c.orientation, "edge-on")
                    .on_hover_text("Blades seen edge-on (Jahrmann's orientation test)");
                ui.checkbox(&mut c.frustum, "off-screen")
                    .on_hover_text("Blades outside the view, with a margin for bent blades");
                ui.checkbox(&mut c.distance, "distance")
                    .on_hover_text("Thin the field with distance, in buckets; survivors widen");
                ui.checkbox(&mut c.lod, "LOD").on_hover_text(format!(
                    "{} / {} / {} segments a blade, near to far (dithered, with hysteresis)",
                    LOD_SEGMENTS[0], LOD_SEGMENTS[1], LOD_SEGMENTS[2]
                ));
                ui.checkbox(&mut self.far, "far field").on_hover_text(
                    "Where fewer blades are drawn than the field holds (far away, or a \
                     software adapter's sample), the ground shows the grass and its wind as \
                     seen from afar",
                );
                ui.separator();
            }
            ui.checkbox(&mut self.wind_colours, "wind colours")
                .on_hover_text(
                    "Colour the grass and ground by the wind's speed, on the map view's scale \
                 (its legend top right), so a still view shows where the wind blows",
                );
            // The values are drag fields, one widget each, so the row wraps between them in a
            // narrow pane (a slider is several widgets, and ran off the pane's edge).
            if self.wind_colours {
                ui.add(
                    egui::DragValue::new(&mut self.wind_opacity)
                        .range(WIND_OPACITY)
                        .speed(0.01)
                        .fixed_decimals(2)
                        .prefix("opacity "),
                )
                .on_hover_text("How opaque the wind colours are over the grass");
            }
            ui.separator();
            ui.toggle_value(&mut self.push, "Push")
                .on_hover_text("Left-drag pushes a sphere through the grass (Ctrl+drag orbits)");
            if self.push {
                ui.add(
                    egui::DragValue::new(&mut self.radius)
                        .range(0.1..=5.0)
                        .speed(0.02)
                        .fixed_decimals(2)
                        .prefix("radius ")
                        .suffix(" m"),
                )
                .on_hover_text("The pushing sphere's radius");
                ui.add(
                    egui::DragValue::new(&mut self.lifetime)
                        .range(0.0..=20.0)
                        .speed(0.1)
                        .fixed_decimals(1)
                        .prefix("trail ")
                        .suffix(" s"),
                )
                .on_hover_text("How long the trail the sphere leaves takes to fade");
            }
        });
    }
}

/// `v` with its thousands grouped: 2,795,520.
pub fn grouped(v: u32) -> String {
    let s = v.to_string();
    let mut out = String::new();
    for (k, c) in s.chars().enumerate() {
        if k > 0 && (s.len() - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The counters line: `blades` considered, culled by each test, drawn per LOD level.
pub fn counters(stats: &CullStats, total: u32) -> String {
    let n = grouped;
    let mut line = format!("{} blades", n(stats.total));
    if stats.total < total {
        line += &format!(" (of {})", n(total));
    }
    line += &format!(
        " · culled: edge-on {}, off-screen {}, distance {} · drawn: {} at {} seg, {} at {}, {} at {}",
        n(stats.orientation),
        n(stats.frustum),
        n(stats.distance),
        n(stats.drawn[0]),
        LOD_SEGMENTS[0],
        n(stats.drawn[1]),
        LOD_SEGMENTS[1],
        n(stats.drawn[2]),
        LOD_SEGMENTS[2],
    );
    line
}
