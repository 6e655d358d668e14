//! The flange search decision: `off` on an ideal straight when every
//! wheel starts far enough from its flange and the linearised centred run
//! is stable with margin (the hunting check), watched by a
//! [`FlangeGuard`]; `auto` otherwise (module docs of [`super`]). The
//! assessment (`assess`) comes before the contact method (the table
//! needs no flange contact to be expected), the decision (`decide`)
//! after it.

use anyhow::{Context, Result};
use runtime::multibody::linear::linearise;
use runtime::multibody::{InitialConditions, VehicleSystem};
use serde::Serialize;

use super::facts::{CheckModel, FlangeFacts, TrackFacts, flange_facts};
use super::{By, Decision, mm};
use crate::config::scene::{ContactMethodKind, FlangeMode, LoadedScene, PlanMode};

/// Safety margin of the `auto` flange rule (m; `ContactOptions::auto_margin_m`).
pub const AUTO_MARGIN_M: f64 = 0.003;

/// Extra margin of the flange guard before the `auto` threshold (m): covers
/// the lateral motion between two output samples.
pub const GUARD_MARGIN_M: f64 = 0.001;

/// Largest initial approach for `flange = off`, as a fraction of the
/// guard's threshold: a motion that decays from its start reaches the guard
/// only if it overshoots its start by a third.
pub const START_FRACTION: f64 = 0.75;

/// Least damping ratio of the linearised hunting mode for `flange = off`:
/// the envelope of a 5 % damped mode falls e-fold within about three
/// cycles; nearer the linear critical speed the subcritical hunting cycle
/// (`docs/guide/critical-speed.md`: 5–10 m/s below it) may be reached.
pub const MIN_HUNTING_DAMPING: f64 = 0.05;

/// Stop an `off` run whose wheelset approaches its flange: trips when
/// |y| + |ψ|·`reach_per_rad_m` ≥ `threshold_m` for any wheelset at an
/// output sample (y lateral displacement, ψ yaw relative to the track).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlangeGuard {
    /// Flangeway clearance − `auto` margin − [`GUARD_MARGIN_M`] (m).
    pub threshold_m: f64,
    /// √(2 R0 h_flange) (m per rad of yaw).
    pub reach_per_rad_m: f64,
}

impl FlangeGuard {
    /// Whether a wheelset at lateral displacement `lateral_m` and yaw
    /// `yaw_rad` trips the guard.
    pub fn trips(&self, lateral_m: f64, yaw_rad: f64) -> bool {
        lateral_m.abs() + yaw_rad.abs() * self.reach_per_rad_m >= self.threshold_m
    }
}

/// The flange guard at an output sample: where it trips (wheelset, time,
/// distance, lateral and yaw), or `None`.
pub fn guard_check(
    guard: &FlangeGuard,
    results: &runtime::results::RunResults,
    t_s: f64,
) -> Option<String> {
    results.wheelsets.iter().find_map(|w| {
        let (y, psi) = (*w.lateral_m.last()?, *w.yaw_rad.last()?);
        guard.trips(y, psi).then(|| {
            format!(
                "wheelset '{}' reached {} (yaw {:.2} mrad) at t = {t_s:.3} s, s = {:.1} m, guard {}",
                w.name,
                mm(y),
                psi * 1e3,
                w.distance_m.last().copied().unwrap_or(f64::NAN),
                mm(guard.threshold_m)
            )
        })
    })
}

/// Damping ratio and frequency (Hz) of the hunting mode of the centred run
/// at the scene's speed, creep law and friction, online contact, on the
/// check's ideal straight (`runtime::multibody::linear`); `None` when there
/// is no oscillatory lateral mode.
fn hunting(ls: &LoadedScene, check: &mut CheckModel) -> Result<Option<(f64, f64)>> {
    let mut scene = ls.clone();
    scene.scene.contact.method = ContactMethodKind::Online;
    // Off: the centred run has no flange contact, and the assembly then
    // skips the flangeway clearance sweep.
    scene.scene.contact.flange = FlangeMode::Off;
    let v = check.vehicle_file();
    let s_start = check.s_start_m;
    let (track, vehicle) = check.model()?;
    let mut settings = crate::session::settings::system_settings(&scene, v, track)?;
    settings.s_start_m = s_start;
    settings.deceleration_m_s2 = 0.0;
    let (mut system, y0) =
        VehicleSystem::assemble(track, vehicle, settings, InitialConditions::default())
            .context("assembling the vehicle for the stability check")?;
    let lin = linearise(&mut system, &y0).context("linearising the centred run")?;
    Ok(lin.hunting().map(|m| (m.damping_ratio, m.frequency_hz)))
}

/// Whether the run can do without the flange search, and why.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Assessment {
    /// An ideal straight with a contact that searches (not imported): the
    /// flange facts matter only there.
    pub straight: bool,
    /// The vehicle's flange facts ([`FlangeFacts::UNKNOWN`] unless
    /// `straight`).
    pub facts: FlangeFacts,
    /// No flange contact expected: the geometric check passed and the
    /// hunting mode is damped.
    pub no_flange_expected: bool,
    pub reason: String,
    geometric_ok: bool,
    /// Whether the hunting check ran.
    checked: bool,
    guard_threshold_m: f64,
}

/// Assess the flange search: the geometric check (initial approach within
/// [`START_FRACTION`] of the guard, no loads or pushes) and, when
/// `may_decide` (the planner decides the flange search or the method) and
/// it can matter, the hunting check.
pub(super) fn assess(
    ls: &LoadedScene,
    track: &TrackFacts,
    check: &mut CheckModel,
    may_decide: bool,
) -> Result<Assessment> {
    let scene = &ls.scene;
    let v = scene.initial.speed_m_s;
    let straight = track.straight() && scene.contact.method != ContactMethodKind::Imported;
    let facts = if straight {
        flange_facts(ls, check)?
    } else {
        FlangeFacts::UNKNOWN
    };
    let threshold = facts.clearance_m - AUTO_MARGIN_M;
    let guard_threshold = threshold - GUARD_MARGIN_M;
    let start_limit = START_FRACTION * guard_threshold;
    // External loads and initial pushes can drive a wheelset to its flange
    // whatever the track: the flange is then searched.
    let disturbed = scene.load != crate::config::load::LoadSection::default()
        || scene.perturbation != crate::config::load::PerturbationSection::default();
    let geometric_ok = straight && !disturbed && facts.initial_approach_m <= start_limit;
    let geometric_reason = if disturbed {
        "the scene applies a [load] or a [perturbation]".to_string()
    } else if !track.straight() {
        format!(
            "the track is not an ideal straight over the range ({})",
            track.kind_name()
        )
    } else if !straight {
        "an imported contact".to_string()
    } else if !geometric_ok {
        format!(
            "initial approach {} > {} (3/4 of the guard {}: the auto threshold {} clearance − {} = {}, less 1 mm)",
            mm(facts.initial_approach_m),
            mm(start_limit),
            mm(guard_threshold),
            mm(facts.clearance_m),
            mm(AUTO_MARGIN_M),
            mm(threshold)
        )
    } else {
        format!(
            "ideal straight, initial approach {} ≤ {} (3/4 of the guard {})",
            mm(facts.initial_approach_m),
            mm(start_limit),
            mm(guard_threshold)
        )
    };
    // The linear check costs an assembly and a linearisation: only when the
    // planner decides and it can matter. A check that cannot be made is no
    // reason to fail the run: the flange is then searched.
    let stability =
        (geometric_ok && may_decide).then(|| hunting(ls, check).map_err(|e| format!("{e:#}")));
    let checked = stability.is_some();
    let (no_flange_expected, reason) = match (geometric_ok, stability) {
        (false, _) => (false, geometric_reason.clone()),
        (true, Some(Err(e))) => (
            false,
            format!("{geometric_reason}, but the stability check failed: {e}"),
        ),
        (true, None) => (
            false,
            format!(
                "{geometric_reason}; the hunting mode's damping is checked only when the planner decides"
            ),
        ),
        (true, Some(Ok(None))) => (
            false,
            format!(
                "{geometric_reason}, but no hunting mode found at {v} m/s to check its damping"
            ),
        ),
        (true, Some(Ok(Some((zeta, f))))) if zeta >= MIN_HUNTING_DAMPING => (
            true,
            format!(
                "{geometric_reason}; hunting mode damped at {v} m/s (ζ = {zeta:.3} ≥ {MIN_HUNTING_DAMPING}, {f:.2} Hz)"
            ),
        ),
        (true, Some(Ok(Some((zeta, f))))) => (
            false,
            format!(
                "{geometric_reason}, but the hunting mode at {v} m/s has ζ = {zeta:.3} < {MIN_HUNTING_DAMPING} ({f:.2} Hz): the motion may grow to the flange"
            ),
        ),
    };
    Ok(Assessment {
        straight,
        facts,
        no_flange_expected,
        reason,
        geometric_ok,
        checked,
        guard_threshold_m: guard_threshold,
    })
}

/// Decide the flange search once the contact `method` is known: `scene`
/// is the scene's own setting, `method_chosen` and `flange_chosen` whether
/// the planner chooses those items.
pub(super) fn decide(
    a: &Assessment,
    scene: FlangeMode,
    method: ContactMethodKind,
    mode: PlanMode,
    method_chosen: bool,
    flange_chosen: bool,
) -> (Decision, FlangeMode, Option<FlangeGuard>) {
    let flange_reason = &a.reason;
    if method == ContactMethodKind::Table && method_chosen && flange_chosen {
        // Chosen only when no flange contact is expected: the assembly's
        // settling then needs no flange search (nor its clearance sweep).
        (
            Decision {
                item: "flange_search".into(),
                value: "off".into(),
                by: By::Planner,
                reason: format!(
                    "the table contact takes its flange contact from its table; off for the settling at assembly: {flange_reason}"
                ),
            },
            FlangeMode::Off,
            None,
        )
    } else if method != ContactMethodKind::Online {
        (
            Decision {
                item: "flange_search".into(),
                value: if method == ContactMethodKind::Imported {
                    "not used".into()
                } else {
                    format!("{scene} (settling only)")
                },
                by: By::Scene,
                reason: if method == ContactMethodKind::Imported {
                    "the imported contact takes its one contact per wheel from its table".into()
                } else {
                    format!(
                        "the {method} contact takes its flange contact from its table; the flange search only settles the wheelsets at assembly"
                    )
                },
            },
            scene,
            None,
        )
    } else if mode == PlanMode::Everything {
        (
            Decision {
                item: "flange_search".into(),
                value: FlangeMode::On.to_string(),
                by: By::Everything,
                reason: "searched at every solve".into(),
            },
            FlangeMode::On,
            None,
        )
    } else if flange_chosen {
        let off = a.no_flange_expected;
        let flange = if off {
            FlangeMode::Off
        } else {
            FlangeMode::Auto
        };
        let guard = off.then_some(FlangeGuard {
            threshold_m: a.guard_threshold_m,
            reach_per_rad_m: a.facts.reach_per_rad_m,
        });
        (
            Decision {
                item: "flange_search".into(),
                value: flange.to_string(),
                by: By::Planner,
                reason: if off {
                    format!(
                        "{flange_reason}; guarded: the run is repeated with auto if a wheelset reaches {}",
                        mm(a.guard_threshold_m)
                    )
                } else {
                    format!("{flange_reason} (auto: searched within 3 mm of the flange)")
                },
            },
            flange,
            guard,
        )
    } else {
        (
            Decision {
                item: "flange_search".into(),
                value: scene.to_string(),
                by: By::Scene,
                reason: format!(
                    "the planner {}: {flange_reason}",
                    if a.geometric_ok && !a.checked {
                        "might choose off"
                    } else if a.no_flange_expected {
                        "would choose off"
                    } else {
                        "would choose auto"
                    }
                ),
            },
            scene,
            None,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_guard_adds_the_yawed_flange_reach() {
        let g = FlangeGuard {
            threshold_m: 0.0028,
            reach_per_rad_m: 0.155,
        };
        assert!(!g.trips(-0.002, 0.0));
        assert!(g.trips(-0.0028, 0.0));
        assert!(g.trips(0.002, -0.006), "2 mm + 6 mrad × 0.155 m = 2.93 mm");
        assert!(!g.trips(0.002, 0.005), "2 mm + 0.78 mm");
    }

    #[test]
    fn the_flange_facts_and_the_hunting_check_share_one_vehicle_model() {
        let ls = LoadedScene::default_scene(&[]).expect("default scene");
        let v = crate::config::vehicle::VehicleFile::load(&ls.path(&ls.scene.vehicle.file))
            .expect("vehicle");
        let mut check = CheckModel::new(&ls, &v).expect("check track");
        // Whether the flangeway clearance is cached or not, the model is
        // built once: by the sweep on a miss, else by the hunting check.
        let facts = flange_facts(&ls, &mut check).expect("flange facts");
        assert!(facts.clearance_m.is_finite() && facts.reach_per_rad_m > 0.0);
        assert!(check.builds() <= 1);
        hunting(&ls, &mut check).expect("hunting check");
        hunting(&ls, &mut check).expect("hunting check again");
        assert_eq!(check.builds(), 1);
    }
}
