//! Settings that are valid but known to make bad wind: the layout loads, bakes and runs, and
//! the CLI and the editor say what to expect. Each advice names its field and the measured
//! behaviour behind it (docs/RELIABILITY.md, "Findings").

use super::types::*;
use super::validate::Issue;

/// Above this vorticity factor MacCormack advection lets confinement run away: on
/// `layouts/obstacles.json` (arrows of 12–15 m/s) the peak is 16.4 m/s after 60 s at 0.5,
/// 51 m/s at 1 and 77 m/s after 25 s at 2.
pub const VORTICITY_MACCORMACK_ADVISED: f32 = 0.5;

/// Above this vorticity factor confinement drives the wind several times past the arrows'
/// strengths even with semi-Lagrangian advection: `layouts/two-winds.json` (arrows ≤ 12.5
/// m/s) peaks at 33–55 m/s at 5 and at hundreds of m/s from about 10.
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
                "{} with MacCormack advection can drive the wind far past the arrows' \
                 strengths (obstacles.json: 51 m/s at 1, from arrows of at most 15 m/s); keep it at \
                 {VORTICITY_MACCORMACK_ADVISED} or below, or use semi-Lagrangian advection",
                s.vorticity
            ),
        });
    } else if s.vorticity > VORTICITY_ADVISED {
        out.push(Issue {
            path: "sim.vorticity".into(),
            message: format!(
                "{} drives the wind several times past the arrows' strengths \
                 (two-winds.json: 33–55 m/s from 12.5 m/s arrows at 5, hundreds of m/s from \
                 about 10); keep it at {VORTICITY_ADVISED} or below",
                s.vorticity
            ),
        });
    }
    out
}
