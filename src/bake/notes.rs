//! What a bake's manifest notes say about the layout and the wind it baked.

use crate::doc::Layout;

/// How a manifest note that repeats the layout's advice (`doc::advise`) starts: the CLI
/// said those before the bake.
pub const ADVICE: &str = "advice: ";

/// How far past the layout's own wind a baked field may peak before a note says so: arrows
/// that meet and turn lift a field above its arrows by a little (the examples: up to 1.46×,
/// walled-garden's breeze through its gaps; confinement adds at most a few hundredths).
pub const PEAK_NOTED: f32 = 2.5;

/// What the baked numbers say about the layout: a field far faster than the wind the layout
/// sets (`sim::forces::reference_speed`), or a field that never moves (no enabled arrow, or
/// obstacles over the whole map).
pub fn field_notes(layout: &Layout, max_speed: f32) -> Vec<String> {
    let strongest = crate::sim::forces::reference_speed(layout);
    let mut notes = Vec::new();
    if max_speed == 0.0 {
        notes.push(
            "the baked wind is still: every cell of every frame is zero (no enabled arrow or \
             layer blows, or obstacles cover the map)"
                .to_string(),
        );
    } else if strongest > 0.0 && max_speed > PEAK_NOTED * strongest {
        notes.push(format!(
            "the baked wind peaks at {max_speed:.1} m/s, {:.1}× the strongest push in the layout \
             ({strongest:.1} m/s); look at it in the editor before shipping it",
            max_speed / strongest
        ));
    }
    notes
}
