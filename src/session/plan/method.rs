//! The contact method decision: the contact lookup table where its error
//! measured by `sim tradeoff` (`tables/planner/measured.toml`) is within
//! the scene's `run.lateral_tolerance_m`; online otherwise (module docs of
//! [`super`]).

use anyhow::Result;

use super::measured::{TrackKind, measured};
use super::{By, Decision};
use crate::config::scene::{ContactMethodKind, PlanMode, Scene};

/// What the planner would choose on a `kind` track, and why.
fn planned(
    scene: &Scene,
    kind: TrackKind,
    no_flange_expected: bool,
) -> Result<(ContactMethodKind, String)> {
    let m = measured()?.table_error(kind);
    let name = kind.as_str();
    Ok(match (scene.run.lateral_tolerance_m, m) {
        (None, _) => (
            ContactMethodKind::Online,
            "no run.lateral_tolerance_m: the exact (online) contact".to_string(),
        ),
        (Some(tol), None) => (
            ContactMethodKind::Online,
            format!(
                "the contact table's error is not measured on a {name} track; tolerance {tol:.1e} m"
            ),
        ),
        (Some(tol), Some(m)) if !m.max_lateral_error_m.is_finite() => (
            ContactMethodKind::Online,
            format!(
                "the contact table is unusable on a {name} track: {}; tolerance {tol:.1e} m",
                m.source
            ),
        ),
        (Some(tol), Some(m)) => {
            // The error grows with the offset: scaled by |y₀| / the
            // measurement's offset when the scene's is larger.
            let scale = (scene.initial.lateral_m.abs() / m.initial_offset_m).max(1.0);
            let est = m.max_lateral_error_m * scale;
            if kind == TrackKind::Straight && !no_flange_expected {
                (
                    ContactMethodKind::Online,
                    "flange contact cannot be ruled out, and the table's zero-yaw rows do not model a yawed flange's lead (measured without flange contact)".to_string(),
                )
            } else if est <= tol {
                (
                    ContactMethodKind::Table,
                    format!(
                        "measured error {:.2} µm{} ≤ tolerance {:.2} µm ({}); the table is built once per wheel/rail pair and cached",
                        est * 1e6,
                        if scale > 1.0 {
                            format!(" (scaled ×{scale:.1} for the offset)")
                        } else {
                            String::new()
                        },
                        tol * 1e6,
                        m.source
                    ),
                )
            } else {
                (
                    ContactMethodKind::Online,
                    format!(
                        "measured table error {:.2} µm > tolerance {:.2} µm ({})",
                        est * 1e6,
                        tol * 1e6,
                        m.source
                    ),
                )
            }
        }
    })
}

/// Decide the contact method on a `kind` track: `no_flange_expected` from
/// the flange assessment, `chosen` whether the planner chooses it.
pub(super) fn decide(
    scene: &Scene,
    kind: TrackKind,
    no_flange_expected: bool,
    mode: PlanMode,
    chosen: bool,
) -> Result<(Decision, ContactMethodKind)> {
    let c = &scene.contact;
    let (planned_method, method_reason) = planned(scene, kind, no_flange_expected)?;
    let decision = |method: ContactMethodKind, by: By, reason: String| {
        (
            Decision {
                item: "contact_method".into(),
                value: method.to_string(),
                by,
                reason,
            },
            method,
        )
    };
    Ok(if c.method == ContactMethodKind::Imported {
        decision(
            c.method,
            By::Scene,
            "an imported contact table (the scene's model of the contact)".into(),
        )
    } else if mode == PlanMode::Everything {
        decision(
            ContactMethodKind::Online,
            By::Everything,
            "Newton at every evaluation".into(),
        )
    } else if chosen {
        decision(planned_method, By::Planner, method_reason)
    } else {
        decision(
            c.method,
            By::Scene,
            if mode == PlanMode::Scene {
                "the planner decides with [plan] mode = \"required\" and run.lateral_tolerance_m"
                    .into()
            } else {
                format!("the planner would choose {planned_method}: {method_reason}")
            },
        )
    })
}
