//! Warnings of a run: what its results show to be doubtful although the
//! run went on (docs/guide/extremes-and-diagnostics.md, "Warnings").
//! Each is printed in the summary (text and `--json` `warnings`), listed
//! in the results file's `status` ("completed with warnings: …") and
//! written whole in its `warnings` attribute.
//!
//! - **Flange passed through** ([`flange_passage`]): with the flange
//!   search off (online contact), a wheelset whose |y| went beyond the
//!   flangeway clearance on that side had its flange inside the rail with
//!   no flange force computed — the clearance is where the unyawed flange
//!   touches (`runtime::contact::quasi_static::flange_clearance_m`); a yaw
//!   brings the flange to its rail earlier still, so |y| beyond it is
//!   certain passage.
//! - **Airborne wheels** ([`airborne`]): a wheel without load (Q ≤ 0 or
//!   no contact) in more than [`AIRBORNE_WARN_FRACTION`] of the samples.
//! - **No Nadal verdict**: a flanged wheel whose 2 m windows are all
//!   invalid ([`crate::run::nadal`]).
//! - **Energy residual** ([`energy_residual`]): |residual| above
//!   [`ENERGY_RESIDUAL_WARN_FRACTION`] of the largest term of the balance.

use runtime::integrators::Method;
use runtime::results::{RunResults, WHEEL_GROUPS};
use serde::Serialize;

use crate::run::nadal::{NadalVerdict, WheelNadal};
use crate::run::summary::EnergySummary;

/// A wheel without load in more than this fraction of the samples is
/// reported: 5 % of a run off the rail is no longer an incident (a drop
/// or an impact bounces for a few samples) but a regime the contact
/// model, made for rolling, describes only roughly.
pub const AIRBORNE_WARN_FRACTION: f64 = 0.05;

/// |residual| of the energy balance above this fraction of its largest
/// term is reported. Converged runs close the balance to 0.1 % or better
/// (docs/guide/extremes-and-diagnostics.md, "Extremes: motion": 0.07 %
/// of 400 J, 0.05 % of 2.07 kJ, 0.1 % at 100 m/s); ten times that is no
/// quadrature error but a step too large for the stiffest mode (RK4 at
/// 1.2 ms on the bogie at 20 m/s: 76 %).
pub const ENERGY_RESIDUAL_WARN_FRACTION: f64 = 0.01;

/// Residuals below this (J) are never reported: the ledger sums the
/// round-off of energies up to 10⁸ J (about 10⁻⁸ J per state) over up to
/// 10⁶ steps.
pub const ENERGY_RESIDUAL_FLOOR_J: f64 = 1e-2;

/// One warning of a run.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RunWarning {
    /// `input` (points dropped from a profile), `flange_passed_through`,
    /// `airborne`, `no_nadal_verdict`, `energy_residual`, `check_failed`.
    pub kind: String,
    /// What was seen, with its figures and what to do.
    pub message: String,
}

impl RunWarning {
    fn new(kind: &str, message: String) -> Self {
        Self {
            kind: kind.into(),
            message,
        }
    }

    /// A warning of the inputs ([`crate::session::Session::warnings`]:
    /// what was dropped from a profile cut to its longest usable stretch).
    pub fn input(message: String) -> Self {
        Self::new("input", message)
    }

    /// A few words for the results' `status`.
    pub fn short(&self) -> &str {
        match self.kind.as_str() {
            "flange_passed_through" => "flange passed through its rail",
            "airborne" => "wheels airborne",
            "no_nadal_verdict" => "no Nadal verdict",
            "energy_residual" => "energy residual",
            "input" => "input points dropped",
            _ => "a check could not be made",
        }
    }
}

/// The results' `status` of a completed run with `warnings`.
pub fn completed_status(warnings: &[RunWarning]) -> String {
    if warnings.is_empty() {
        return "completed".into();
    }
    let mut kinds: Vec<&str> = warnings.iter().map(RunWarning::short).collect();
    kinds.dedup();
    format!(
        "completed with warnings: {} (see the warnings attribute)",
        kinds.join(", ")
    )
}

/// The results' `warnings` attribute: one message a line, or "none".
pub fn warnings_attribute(warnings: &[RunWarning]) -> String {
    if warnings.is_empty() {
        return "none".into();
    }
    warnings
        .iter()
        .map(|w| w.message.as_str())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The largest term of an energy balance and its name: E − E0 and each
/// work and dissipation (J, absolute).
pub fn largest_energy_term(e: &EnergySummary) -> (f64, &'static str) {
    // The change of energy last: a tie names the work or dissipation.
    [
        (e.axle_torque_work_j.abs(), "the axle torque work"),
        (e.reference_work_j.abs(), "the reference work"),
        (e.element_turning_work_j.abs(), "the element turning work"),
        (e.contact_normal_work_j.abs(), "the contact normal work"),
        (e.creep_dissipation_j.abs(), "the creep dissipation"),
        (
            e.contact_damping_dissipation_j.abs(),
            "the contact damping dissipation",
        ),
        (e.damper_dissipation_j.abs(), "the damper dissipation"),
        ((e.final_j - e.initial_j).abs(), "the change of energy"),
    ]
    .into_iter()
    .filter(|(v, _)| v.is_finite())
    .fold(
        (0.0, "the change of energy"),
        |a, b| if b.0 > a.0 { b } else { a },
    )
}

/// The residual's fraction of the balance's largest term when it exceeds
/// [`ENERGY_RESIDUAL_WARN_FRACTION`] and [`ENERGY_RESIDUAL_FLOOR_J`] (a
/// non-finite residual always does); `None` otherwise.
pub fn energy_residual_excess(e: &EnergySummary) -> Option<f64> {
    let r = e.residual_j;
    if !r.is_finite() {
        return Some(f64::INFINITY);
    }
    let (largest, _) = largest_energy_term(e);
    (r.abs() > ENERGY_RESIDUAL_FLOOR_J && r.abs() > ENERGY_RESIDUAL_WARN_FRACTION * largest)
        .then(|| r.abs() / largest)
}

/// What to do about a step too large for `method`.
pub fn step_advice(method: &Method) -> String {
    match method {
        Method::Rk4(r) => format!(
            "reduce run.step_s (now {:e} s) or use run.integrator = \"dopri5\", which adapts its step",
            r.step_s
        ),
        Method::Dopri5(d) => format!(
            "tighten run.rtol (now {:e}) or lower run.max_step_s (now {:e} s)",
            d.rtol, d.max_step_s
        ),
        Method::Rosenbrock(d) => format!(
            "tighten run.rtol (now {:e}) and run.atol (now {:e}) or lower run.max_step_s (now {:e} s)",
            d.rtol, d.atol, d.max_step_s
        ),
    }
}

/// The energy warning (module docs).
pub fn energy_residual(e: &EnergySummary, method: &Method) -> Option<RunWarning> {
    let fraction = energy_residual_excess(e)?;
    let (largest, name) = largest_energy_term(e);
    Some(RunWarning::new(
        "energy_residual",
        format!(
            "the energy balance leaves {:.3} J unexplained, {:.1} % of its largest term ({name}, {largest:.3} J), above the {} % a converged run stays within, and the results are not to be trusted: either the step is too large for the stiffest mode (contact, creep at low speed) — {} — or a force of the model does work the balance does not see (a residual that does not shrink with the step; the imported contact table's normal work is booked as the contact normal work, docs/reference/08-multibody.md §8.6); halve the step: if the residual stays, it is the model's",
            e.residual_j,
            100.0 * fraction,
            100.0 * ENERGY_RESIDUAL_WARN_FRACTION,
            step_advice(method)
        ),
    ))
}

/// The airborne and no-verdict warnings of one wheelset's Nadal figures.
pub fn airborne(wheelset: &str, nadal: &[WheelNadal], speed_m_s: f64) -> Vec<RunWarning> {
    let mut out = Vec::new();
    let up: Vec<String> = nadal
        .iter()
        .filter(|w| w.airborne_fraction > AIRBORNE_WARN_FRACTION)
        .map(|w| format!("{} {:.1} %", w.wheel, 100.0 * w.airborne_fraction))
        .collect();
    if !up.is_empty() {
        out.push(RunWarning::new(
            "airborne",
            format!(
                "wheelset '{wheelset}': wheels without load (airborne) in more than {} % of the samples — {} — at {speed_m_s} m/s: the wheels leave their rails (bouncing, or a flange run through its rail); Y/Q is judged over the loaded samples only (docs/guide/extremes-and-diagnostics.md)",
                100.0 * AIRBORNE_WARN_FRACTION,
                up.join(", ")
            ),
        ));
    }
    for w in nadal
        .iter()
        .filter(|w| w.verdict == NadalVerdict::NoValidWindow)
    {
        out.push(RunWarning::new(
            "no_nadal_verdict",
            format!(
                "wheelset '{wheelset}', {} wheel: none of its {} 2 m windows is valid (each needs at least {} loaded samples, more than half of its samples; {:.1} % of the samples are airborne): no derailment verdict; the largest single sample is {}",
                w.wheel,
                w.windows,
                crate::run::nadal::MIN_LOADED_SAMPLES,
                100.0 * w.airborne_fraction,
                w.max_y_over_q
                    .map_or("—".to_string(), |v| format!("Y/Q = {v:.3}"))
            ),
        ));
    }
    out
}

/// The flangeway clearance of one wheelset towards each side (m, left
/// then right; `None` where the flange does not touch or there is none).
pub type Clearances = [Option<f64>; 2];

/// The flangeway clearances of every wheelset of `system` (wheelsets with
/// the same contact model share one sweep of
/// `runtime::contact::quasi_static::flange_clearance_m`).
pub fn clearances(
    system: &runtime::multibody::VehicleSystem<'_>,
) -> Result<Vec<Clearances>, String> {
    use runtime::contact::quasi_static::flange_clearance_m;
    use runtime::geometry::track::Side;
    let mut done: Vec<(&runtime::contact::WheelsetContactModel, Clearances)> = Vec::new();
    let mut out = Vec::new();
    for w in &system.vehicle().wheelsets {
        if let Some((_, c)) = done.iter().find(|(m, _)| *m == &w.contact) {
            out.push(*c);
            continue;
        }
        let mut c: Clearances = [None, None];
        for (k, side) in Side::BOTH.into_iter().enumerate() {
            c[k] = flange_clearance_m(&w.contact, side)
                .map_err(|e| format!("the flangeway clearance of wheelset '{}': {e}", w.name))?;
        }
        done.push((&w.contact, c));
        out.push(c);
    }
    Ok(out)
}

/// The flange warning of a run with the flange search off: each wheelset
/// whose displacement towards a side went beyond that side's clearance.
pub fn flange_passage(results: &RunResults, clearances: &[Clearances]) -> Vec<RunWarning> {
    let mut out = Vec::new();
    for (w, c) in results.wheelsets.iter().zip(clearances) {
        // y > 0 brings the left flange to its rail, y < 0 the right one.
        for (side, (clearance, sign)) in WHEEL_GROUPS.iter().zip(c.iter().zip([1.0, -1.0])) {
            let Some(clearance) = clearance else { continue };
            let beyond: Vec<usize> = w
                .lateral_m
                .iter()
                .enumerate()
                .filter(|(_, y)| sign * **y > *clearance)
                .map(|(i, _)| i)
                .collect();
            let Some(&first) = beyond.first() else {
                continue;
            };
            let peak = beyond
                .iter()
                .map(|&i| sign * w.lateral_m[i])
                .fold(0.0_f64, f64::max);
            out.push(RunWarning::new(
                "flange_passed_through",
                format!(
                    "wheelset '{}': with the flange search off, |y| reached {:.2} mm towards the {side} rail, beyond its flangeway clearance {:.2} mm, from t = {:.3} s in {} of {} samples: the {side} flange passed through its rail with no flange force computed, and the motion after that is not physical; set contact.flange = \"auto\" (or \"on\")",
                    w.name,
                    peak * 1e3,
                    clearance * 1e3,
                    results.time_s.get(first).copied().unwrap_or(f64::NAN),
                    beyond.len(),
                    results.len()
                ),
            ));
        }
    }
    out
}

/// A check that could not be made (named, with why).
pub fn check_failed(what: &str, why: &str) -> RunWarning {
    RunWarning::new(
        "check_failed",
        format!("{what} could not be checked: {why}"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use runtime::integrators::{Dopri5, Rk4};
    use runtime::results::WheelsetSeries;

    fn energy(residual_j: f64, creep_j: f64) -> EnergySummary {
        EnergySummary {
            initial_j: 1.5e6,
            final_j: 1.5e6 - 0.5 * creep_j,
            axle_torque_work_j: 0.0,
            reference_work_j: 0.0,
            creep_dissipation_j: creep_j,
            contact_damping_dissipation_j: 0.0,
            damper_dissipation_j: 0.0,
            element_turning_work_j: 0.0,
            contact_normal_work_j: 0.0,
            residual_j,
        }
    }

    #[test]
    fn the_energy_residual_is_judged_against_the_largest_term() {
        let rk4 = Method::Rk4(Rk4 { step_s: 1.2e-3 });
        // 62 J against 82 J of creep dissipation: reported, with advice.
        let w = energy_residual(&energy(62.4, 82.3), &rk4).expect("a warning");
        assert!(w.message.contains("75.8 %"), "{}", w.message);
        assert!(w.message.contains("creep dissipation"), "{}", w.message);
        assert!(w.message.contains("reduce run.step_s (now 1.2e-3 s)"));
        // 0.1 % of it: not (a converged run), nor a tiny residual of a
        // tiny balance, nor 1 % of the 1.5 MJ total energy that the
        // reference would hide it in.
        assert_eq!(energy_residual(&energy(0.08, 82.3), &rk4), None);
        assert_eq!(energy_residual(&energy(5e-3, 1e-4), &rk4), None);
        assert!(energy_residual(&energy(414.0, 1200.0), &rk4).is_some());
        assert!(energy_residual(&energy(f64::NAN, 1.0), &rk4).is_some());
        let d = Method::Dopri5(Dopri5::default());
        let w = energy_residual(&energy(-2527.0, 1e4), &d).expect("a warning");
        assert!(w.message.contains("tighten run.rtol"), "{}", w.message);
    }

    #[test]
    fn a_displacement_beyond_the_clearance_is_a_passage() {
        let mut r = RunResults {
            time_s: vec![0.0, 0.1, 0.2, 0.3],
            ..Default::default()
        };
        r.wheelsets.push(WheelsetSeries {
            name: "wheelset".into(),
            lateral_m: vec![0.015, 0.0187, 0.010, -0.005],
            ..Default::default()
        });
        let w = flange_passage(&r, &[[Some(0.0068), Some(0.0068)]]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].message.contains("18.70 mm towards the left rail"));
        assert!(w[0].message.contains("clearance 6.80 mm"));
        assert!(w[0].message.contains("3 of 4 samples"));
        // Within the clearance on both sides: nothing.
        assert!(flange_passage(&r, &[[Some(0.02), Some(0.0068)]]).is_empty());
        // The status names it; without warnings it is "completed".
        assert!(completed_status(&w).starts_with("completed with warnings: flange passed"));
        assert_eq!(completed_status(&[]), "completed");
        assert_eq!(warnings_attribute(&[]), "none");
    }
}
