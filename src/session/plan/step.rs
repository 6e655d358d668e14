//! The table step decision: exact at any step on an ideal straight,
//! otherwise the coarsest nice step whose chord error h²κ/8 stays within
//! the geometry tolerance (module docs of [`super`]).

use super::facts::TrackFacts;
use super::{By, Decision};
use crate::config::scene::{IntegratorKind, PlanMode, Scene};

/// Largest table step the planner uses (m): the largest step `sim tradeoff`
/// measured on the straight (zero error against 0.01 m).
pub const MAX_STEP_M: f64 = 1.0;

/// The finest table step (m): the `sim tradeoff` reference's
/// (the reference run of `sim tradeoff`).
pub const FINEST_STEP_M: f64 = 0.01;

/// The steps the planner picks from (m), coarsest first (each divides 1 m).
pub const NICE_STEPS_M: [f64; 10] = [1.0, 0.5, 0.25, 0.2, 0.1, 0.05, 0.04, 0.025, 0.02, 0.01];

/// Largest chord error of the rail tables' linear interpolation the planner
/// accepts without a stated tolerance (m): h²κ/8 ≤ this (the sagitta of a
/// chord h on a curve of curvature κ; `docs/guide/build-a-track.md`, "Linear interpolation of the
/// tables"). With `run.lateral_tolerance_m` the bound is half the tolerance.
/// The bound is what `sim tradeoff` measures (bogie, 30 m/s, against a
/// 0.01 m table; largest error of the lateral displacement): on
/// `curve_r300` (κ = 3.43e-3 1/m) 3.0 / 106 / 415 µm at 0.1 / 0.5 / 1 m
/// against bounds of 4.3 / 107 / 429 µm; on `irregular_300m`
/// (κ = 1.90e-3 1/m) 0.5 / 15 / 54 µm against 2.4 / 59 / 238 µm.
pub const GEOMETRY_TOLERANCE_M: f64 = 1e-6;

/// The largest of [`NICE_STEPS_M`] within `h_m` (the finest if none).
fn nice_step_m(h_m: f64) -> f64 {
    NICE_STEPS_M
        .iter()
        .copied()
        .find(|&s| s <= h_m)
        .unwrap_or(FINEST_STEP_M)
}

/// Decide the table step (m; `None` with a table file): `chosen` whether
/// the planner chooses it.
pub(super) fn decide(
    scene: &Scene,
    facts: &TrackFacts,
    mode: PlanMode,
    chosen: bool,
) -> (Decision, Option<f64>) {
    let t = &scene.track;
    let v = scene.initial.speed_m_s;
    let dt = match scene.run.integrator {
        IntegratorKind::Rk4 => Some(scene.run.step_s),
        _ => None,
    };
    let paper = match dt {
        Some(dt) => format!("paper §2's rule h ≤ V·Δt = {:.4} m", v * dt),
        None => "paper §2's rule h ≤ V·Δt (Δt adaptive)".into(),
    };
    let (planned_step, step_reason) = if facts.straight() {
        (
            MAX_STEP_M,
            format!(
                "ideal straight over the range: linear interpolation is exact at any step (sim tradeoff: zero error up to 1 m); {paper} not needed"
            ),
        )
    } else {
        let k = facts.max_curvature_1_m;
        let (eps, eps_why) = match scene.run.lateral_tolerance_m {
            Some(tol) => (0.5 * tol, "half the tolerance"),
            None => (GEOMETRY_TOLERANCE_M, "no tolerance stated"),
        };
        let h = (8.0 * eps / k).sqrt();
        let step = nice_step_m(h).min(MAX_STEP_M);
        (
            step,
            format!(
                "largest curvature {k:.3e} 1/m (R {:.0} m): chord error h²κ/8 = {:.2} µm ≤ {:.2} µm ({eps_why}; sim tradeoff measured the lateral error below this bound); {paper}",
                1.0 / k,
                step * step * k / 8.0 * 1e6,
                eps * 1e6
            ),
        )
    };
    if let Some(fs) = facts.file_step_m {
        (
            Decision {
                item: "table_step".into(),
                value: format!("{fs} m"),
                by: By::Scene,
                reason: "a table file is used as it is".into(),
            },
            None,
        )
    } else if mode == PlanMode::Everything {
        (
            Decision {
                item: "table_step".into(),
                value: format!("{FINEST_STEP_M} m"),
                by: By::Everything,
                reason: "the finest step (sim tradeoff's reference)".into(),
            },
            Some(FINEST_STEP_M),
        )
    } else if chosen {
        (
            Decision {
                item: "table_step".into(),
                value: format!("{planned_step} m"),
                by: By::Planner,
                reason: step_reason,
            },
            Some(planned_step),
        )
    } else {
        (
            Decision {
                item: "table_step".into(),
                value: format!("{} m", t.step_m),
                by: By::Scene,
                reason: format!("the planner would choose {planned_step} m: {step_reason}"),
            },
            Some(t.step_m),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_round_down_to_the_nice_ones() {
        assert_eq!(nice_step_m(2.0), 1.0);
        assert_eq!(nice_step_m(0.107), 0.1);
        assert_eq!(nice_step_m(0.0483), 0.04);
        assert_eq!(nice_step_m(0.001), FINEST_STEP_M);
        // Every nice step divides 1 m (the rows of a range lie on the
        // whole-track grid of any of them).
        for h in NICE_STEPS_M {
            let n = 1.0 / h;
            assert!((n - n.round()).abs() < 1e-9, "{h}");
        }
    }
}
