//! Settings that are valid but known to make bad wind: the layout loads, bakes and runs, and
//! the CLI and the editor say what to expect. Each advice names its field and the measured
//! behaviour behind it (docs/RELIABILITY.md, "Findings").

use super::types::*;
use super::validate::Issue;

/// Above this vorticity factor MacCormack advection lets confinement push the wind past the
/// arrows' strengths. The fastest cell over 60 s of the arrow examples at their own grids,
/// against the same run without confinement: 1.0–1.06× at 1, 1.2–1.45× at 2 and 1.8–3.8× at
/// 3 (`layouts/branching.json`, arrows ≤ 10 m/s: 10.7, 15.4 and 40.5 m/s).
pub const VORTICITY_MACCORMACK_ADVISED: f32 = 1.0;

/// Above this vorticity factor confinement drives the wind several times past the arrows'
/// strengths even with semi-Lagrangian advection: `layouts/two-winds.json` (arrows ≤ 11.25
/// m/s) peaks over 60 s at 17–20 m/s at 2, 19–28 at 5, 27–125 at 10 and hundreds of m/s
/// from about 20 (grids of 32² and 128²).
pub const VORTICITY_ADVISED: f32 = 5.0;

/// The advice for a valid layout (empty when there is none), each with the JSON path of its
/// field. Run it only on layouts [`super::validate`] accepts.
pub fn advise(layout: &Layout) -> Vec<Issue> {
    let mut out = Vec::new();
    let s = &layout.sim;
    if s.advection == Advection::MacCormack && s.vorticity > VORTICITY_MACCORMACK_ADVISED {
        out.push(Issue {
            path: "sim.vorticity".into(),
            message: format!(
                "{} with MacCormack advection can drive the wind past the arrows' strengths \
                 (branching.json: 15 m/s at 2 and 40 m/s at 3, from arrows of at most 10 m/s); \
                 keep it at {VORTICITY_MACCORMACK_ADVISED} or below, or use semi-Lagrangian \
                 advection",
                s.vorticity
            ),
        });
    } else if s.vorticity > VORTICITY_ADVISED {
        out.push(Issue {
            path: "sim.vorticity".into(),
            message: format!(
                "{} drives the wind several times past the arrows' strengths \
                 (two-winds.json: 27–125 m/s from 11.25 m/s arrows at 10, hundreds of m/s from \
                 about 20); keep it at {VORTICITY_ADVISED} or below",
                s.vorticity
            ),
        });
    }
    out
}
