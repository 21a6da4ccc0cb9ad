//! Settings that are valid but known to make bad wind: the layout loads, bakes and runs, and
//! the CLI and the editor say what to expect. Each advice names its field and the measured
//! behaviour behind it (docs/RELIABILITY.md, "Findings").

use super::types::*;
use super::validate::Issue;

/// Above this vorticity factor MacCormack advection lets confinement push the wind past the
/// layout's own wind (`forces::reference_speed`). MacCormack no longer damps the small eddies
/// confinement feeds, so the bounded confinement's limiter (docs/SOLVER.md, step 3) holds the
/// semi-Lagrangian field but not this one. The fastest cell over 120 s of
/// `layouts/obstacles.json` with MacCormack, over its 12.5 m/s arrows: 1.42× at ε 0, 1.48× at
/// 2, 1.74× at 3 and 2.67× at 50 (two-winds 1.40, 1.42, 1.47, 2.73; branching 1.10, 1.10,
/// 1.12, 2.63).
pub const VORTICITY_MACCORMACK_ADVISED: f32 = 2.0;

/// The advice for a valid layout (empty when there is none), each with the JSON path of its
/// field. Run it only on layouts [`super::validate`] accepts.
pub fn advise(layout: &Layout) -> Vec<Issue> {
    let mut out = Vec::new();
    let s = &layout.sim;
    if s.advection == Advection::MacCormack && s.vorticity > VORTICITY_MACCORMACK_ADVISED {
        out.push(Issue {
            path: "sim.vorticity".into(),
            message: format!(
                "{} with MacCormack advection can drive the wind past the layout's own \
                 (obstacles.json: 1.7× its arrows at 3 and 2.7× at 50); keep it at \
                 {VORTICITY_MACCORMACK_ADVISED} or below, or use semi-Lagrangian advection",
                s.vorticity
            ),
        });
    }
    out
}
