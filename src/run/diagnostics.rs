//! Diagnostics of `sim run` where the model leaves its validity, and the
//! derailment quotient of every wheel.
//!
//! - **Failures** (a contact whose equations do not converge, non-Hertzian
//!   or nearly conformal geometry, a derailment, a non-finite state, a
//!   wheelset off the track tables): the run stops, the results so far are
//!   written (`crate::run`), and the error names the time, the wheelset,
//!   the wheel and zone where there is one, and the **state** of the
//!   wheelset at the failing evaluation — lateral displacement, yaw, roll,
//!   height, forward and lateral speed, track distance. The state is taken
//!   from the last state the integrator (or the output sampler) handed to
//!   the system ([`Watched`]), which is the one that failed.
//! - **Fallbacks** the run continues through, counted per evaluation and
//!   per recorded sample and flagged per zone in the results (`fallback`,
//!   bit flags): contact points from the minimisation fallback of the
//!   contact search where Newton's Jacobian is singular (nearly conformal
//!   contact; `runtime::contact::ContactOptions`, always on), and, with
//!   `[contact] non_hertzian = "floor"`, ellipses from floored curvatures
//!   where the geometry is not Hertzian
//!   (`runtime::multibody::contact_force::NonHertzianPolicy`; the default `stop` ends
//!   the run with the diagnostic instead).
//! - **Numerical blow-ups** are told from derailments
//!   ([`crate::run::blow_up`]): a failure whose state or energy balance
//!   shows the integration running away is reported as such, with its
//!   likely cause, not as the derailment its |y| may look like.
//! - **Nadal's criterion** per wheel: [`crate::run::nadal`]; the
//!   **warnings** of a run that completed: [`crate::run::warnings`].
//!
//! The integrator's step and rejection counts and the fallback counts are
//! also written as root attributes of the results file
//! ([`run_attributes`]).

use std::ops::{Deref, DerefMut};

use runtime::contact::ContactError;
use runtime::forces::hertz::HertzError;
use runtime::integrators::JacobianBlocks;
use runtime::integrators::{Control, IntegrationStats, IntegratorError, OdeSystem};
use runtime::multibody::body::BodyState;
use runtime::multibody::contact_force::ContactForceError;
use runtime::multibody::track_motion::{project_s, track_relative, track_rotation};
use runtime::multibody::{DynamicsError, VehicleSystem};
use runtime::results::AttrValue;
use serde::Serialize;

/// A [`VehicleSystem`] that remembers the last state it was evaluated at
/// (the integrator's stages through [`OdeSystem::rhs`], the output samples
/// through [`Watched::note`]), so that a failure can report it.
pub struct Watched<'s, 'a> {
    system: &'s mut VehicleSystem<'a>,
    last_t_s: f64,
    last_y: Vec<f64>,
    /// Contacts whose ellipse came from the non-Hertzian floor, summed over
    /// the right-hand-side evaluations.
    hertz_floor_evaluations: u64,
}

impl<'s, 'a> Watched<'s, 'a> {
    pub fn new(system: &'s mut VehicleSystem<'a>) -> Self {
        Self {
            system,
            last_t_s: f64::NAN,
            last_y: Vec::new(),
            hertz_floor_evaluations: 0,
        }
    }

    /// Contacts evaluated with the non-Hertzian floor (every evaluation of
    /// the right-hand side, integrator stages included).
    pub fn hertz_floor_evaluations(&self) -> u64 {
        self.hertz_floor_evaluations
    }

    /// Remember (t, y) as the state about to be evaluated.
    pub fn note(&mut self, t_s: f64, y: &[f64]) {
        self.last_t_s = t_s;
        self.last_y.clear();
        self.last_y.extend_from_slice(y);
    }

    /// The last state evaluated (time s, state), if any.
    pub fn last_state(&self) -> Option<(f64, &[f64])> {
        (!self.last_y.is_empty()).then_some((self.last_t_s, self.last_y.as_slice()))
    }

    /// The diagnostic of a failed integration at the last state.
    pub fn diagnose(
        &self,
        error: &IntegratorError<DynamicsError>,
        context: &DiagnoseContext<'_>,
    ) -> RunDiagnostic {
        diagnose(error, self.system, self.last_state(), context)
    }
}

impl<'a> Deref for Watched<'_, 'a> {
    type Target = VehicleSystem<'a>;
    fn deref(&self) -> &Self::Target {
        self.system
    }
}

impl DerefMut for Watched<'_, '_> {
    fn deref_mut(&mut self) -> &mut Self::Target {
        self.system
    }
}

impl Watched<'_, '_> {
    /// Counts the contacts of the last evaluation that used the Hertz
    /// floor; a wheelset whose contacts were reused (a Jacobian column)
    /// was not evaluated.
    fn count_hertz_floor(&mut self) {
        let reused = self.system.contacts_reused();
        self.hertz_floor_evaluations += self
            .system
            .snapshots()
            .iter()
            .enumerate()
            .filter(|(i, _)| !reused.get(*i).copied().unwrap_or(false))
            .flat_map(|(_, s)| s.forces.iter().flatten().flatten())
            .filter(|f| f.hertz_fallback)
            .count() as u64;
    }
}

impl OdeSystem for Watched<'_, '_> {
    type Error = DynamicsError;

    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) -> Result<(), DynamicsError> {
        self.note(t, y);
        self.system.rhs(t, y, dydt)?;
        self.count_hertz_floor();
        Ok(())
    }

    fn rhs_column(
        &mut self,
        t: f64,
        y: &[f64],
        changed: &[usize],
        dydt: &mut [f64],
    ) -> Result<(), DynamicsError> {
        self.note(t, y);
        self.system.rhs_column(t, y, changed, dydt)?;
        self.count_hertz_floor();
        Ok(())
    }

    fn accept(&mut self, t: f64, y: &[f64]) -> Result<Control, DynamicsError> {
        self.system.accept(t, y)
    }

    fn jacobian_blocks(&self, n: usize) -> JacobianBlocks {
        self.system.jacobian_blocks(n)
    }

    fn structure_changed(&mut self) -> bool {
        self.system.structure_changed()
    }
}

/// Where a wheelset is relative to the track at one state (docs/reference/01-units-frames.md §1 signs).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelsetState {
    pub name: String,
    /// Track distance of the centre (m).
    pub s_m: f64,
    /// Lateral displacement from the centreline (mm), + left.
    pub lateral_mm: f64,
    /// Yaw relative to the track (mrad), + nose left.
    pub yaw_mrad: f64,
    /// Roll relative to the track (mrad), + raising the left wheel.
    pub roll_mrad: f64,
    /// Height of the centre above the rail-top plane (mm).
    pub height_mm: f64,
    /// Velocity of the centre along the track (m/s) and across it (m/s, + left).
    pub forward_speed_m_s: f64,
    pub lateral_speed_m_s: f64,
}

impl WheelsetState {
    /// "y = +7.12 mm, yaw = +3.20 mrad, …".
    pub fn to_text(&self) -> String {
        format!(
            "y = {:+.3} mm, yaw = {:+.3} mrad, roll = {:+.3} mrad, height = {:.3} mm, forward speed = {:.3} m/s, lateral speed = {:+.4} m/s, s = {:.3} m",
            self.lateral_mm,
            self.yaw_mrad,
            self.roll_mrad,
            self.height_mm,
            self.forward_speed_m_s,
            self.lateral_speed_m_s,
            self.s_m
        )
    }
}

/// The state of wheelset `i` in the system state `y` (13 variables per
/// body, wheelsets first), or `None` when it cannot be placed on the track
/// (off the tables, non-finite).
pub fn wheelset_state(system: &VehicleSystem<'_>, i: usize, y: &[f64]) -> Option<WheelsetState> {
    let w = system.vehicle().wheelsets.get(i)?;
    let slot = y.get(BodyState::slot(i))?;
    if slot.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let st = BodyState::read_from(slot);
    let c = &system.track().centerline;
    let guess = system
        .snapshots()
        .get(i)
        .map(|s| s.relative.s_m)
        .filter(|s| *s != 0.0)
        .unwrap_or(system.settings().s_start_m + w.x_m);
    let s = project_s(c, &st.position_m, guess).ok()?;
    let axle = st.rotation().column(1).into_owned();
    let r = track_relative(c, s, &st.position_m, &axle, &st.velocity_m_s).ok()?;
    let n = track_rotation(c, s).ok()?.column(1).into_owned();
    Some(WheelsetState {
        name: w.name.clone(),
        s_m: r.s_m,
        lateral_mm: r.lateral_m * 1e3,
        yaw_mrad: r.yaw_rad * 1e3,
        roll_mrad: r.roll_rad * 1e3,
        height_mm: r.vertical_m * 1e3,
        forward_speed_m_s: r.forward_speed_m_s,
        lateral_speed_m_s: st.velocity_m_s.dot(&n),
    })
}

/// Why and where a run failed, with the state there.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RunDiagnostic {
    /// What went wrong, in a few words ("non-Hertzian contact", …).
    pub kind: String,
    /// Time of the failing evaluation (s).
    pub t_s: f64,
    pub wheelset: Option<String>,
    /// "left" / "right".
    pub wheel: Option<String>,
    /// "tread" / "flange".
    pub zone: Option<String>,
    /// The named wheelset's state, or every wheelset's when none is named.
    pub states: Vec<WheelsetState>,
    /// Signs of a numerical blow-up in the failing state
    /// ([`crate::run::blow_up`]); empty when there are none.
    pub blow_up_signs: Vec<String>,
    /// The likely cause and what to do, where the kind tells it (a
    /// blow-up, a flange passed through, a step size collapse).
    pub likely_cause: Option<String>,
    /// |y| passed the derailment limit with the flange search off and no
    /// sign of a blow-up: the wheelset ran through its flange.
    pub ran_through_flange: bool,
    /// The error itself.
    pub detail: String,
}

impl RunDiagnostic {
    /// One line: kind, time, wheelset/wheel/zone, state.
    pub fn headline(&self) -> String {
        let mut s = format!("{} at t = {:.6} s", self.kind, self.t_s);
        if let Some(w) = &self.wheelset {
            s += &format!(", wheelset '{w}'");
        }
        if let Some(w) = &self.wheel {
            s += &format!(", {w} wheel");
        }
        if let Some(z) = &self.zone {
            s += &format!(", {z}");
        }
        for st in &self.states {
            s += &format!("; state of '{}': {}", st.name, st.to_text());
        }
        if self.states.is_empty() {
            s += "; state unavailable (not finite or off the track tables)";
        }
        if !self.blow_up_signs.is_empty() {
            s += &format!(
                "; signs of a numerical blow-up: {}",
                self.blow_up_signs.join("; ")
            );
        }
        if let Some(c) = &self.likely_cause {
            s += &format!("; likely cause: {c}");
        }
        s
    }

    /// Whether the failure is a numerical blow-up (signs were found).
    pub fn is_blow_up(&self) -> bool {
        !self.blow_up_signs.is_empty()
    }

    /// Whether a failure of the derailment check is no derailment: a
    /// blow-up, or a flange run through its rail with the search off.
    pub fn is_not_a_derailment(&self) -> bool {
        self.is_blow_up() || self.ran_through_flange
    }
}

/// What [`diagnose`] needs besides the system: the method (for the
/// advice), what each wheelset's state is compared with, the energy
/// balance at the last accepted state, and whether the flange search was
/// off (online contact).
#[derive(Debug, Clone)]
pub struct DiagnoseContext<'m> {
    pub method: &'m runtime::integrators::Method,
    pub references: Vec<crate::run::blow_up::WheelsetReference>,
    pub energy: Option<crate::run::summary::EnergySummary>,
    pub flange_off: bool,
}

/// The [`crate::run::blow_up::WheelsetReference`] of every wheelset of
/// `system`, with the last sample of `results` (if any).
pub fn wheelset_references(
    system: &VehicleSystem<'_>,
    results: &runtime::results::RunResults,
) -> Vec<crate::run::blow_up::WheelsetReference> {
    use runtime::geometry::track::Side;
    let t_last = results.time_s.last().copied();
    system
        .vehicle()
        .wheelsets
        .iter()
        .enumerate()
        .map(|(i, w)| {
            let wheels = Side::BOTH.map(|side| w.contact.wheel(side));
            crate::run::blow_up::WheelsetReference {
                name: w.name.clone(),
                rolling_height_m: wheels[0]
                    .nominal_radius_m()
                    .max(wheels[1].nominal_radius_m()),
                flange_depth_m: wheels[0].flange_depth_m().max(wheels[1].flange_depth_m()),
                last_sample: t_last.zip(
                    results
                        .wheelsets
                        .get(i)
                        .and_then(|s| s.speed_m_s.last().copied()),
                ),
            }
        })
        .collect()
}

/// What a dynamics error names: kind, time (s), wheelset, and (wheel,
/// zone).
type Classified = (
    String,
    Option<f64>,
    Option<String>,
    Option<(String, String)>,
);

/// Kind, time, wheelset, wheel and zone named by a dynamics error.
fn classify(e: &DynamicsError) -> Classified {
    let place = |side: &runtime::geometry::track::Side, zone: &runtime::geometry::profile::Zone| {
        Some((side.name().to_string(), zone.name().to_string()))
    };
    match e {
        DynamicsError::Contact {
            wheelset,
            t_s,
            source,
        } => {
            let (kind, at) = match source {
                ContactError::NotConverged { side, zone, .. } => (
                    "contact equations did not converge (Newton, every start)",
                    place(side, zone),
                ),
                ContactError::TooManyPatches { .. } => {
                    ("more contact patches on a wheel than slots", None)
                }
                ContactError::Track(_) => ("contact point off the track tables", None),
                ContactError::Setup(_) => ("contact search set-up", None),
            };
            (kind.into(), Some(*t_s), Some(wheelset.clone()), at)
        }
        DynamicsError::Force {
            wheelset,
            t_s,
            source,
        } => {
            let (kind, at) = match source {
                ContactForceError::Hertz { side, zone, source } => (
                    match source {
                        HertzError::NonHertzian { .. } => {
                            "non-Hertzian contact (A <= 0 or B <= 0: conformal or concave)"
                        }
                        HertzError::CurvatureRatioOutOfRange { .. } => {
                            "nearly conformal contact beyond the Hertz range"
                        }
                        HertzError::NonFiniteCurvature { .. } => "non-finite contact curvature",
                        _ => "Hertz contact",
                    },
                    place(side, zone),
                ),
                ContactForceError::Normal { side, zone, .. } => {
                    ("normal contact force", place(side, zone))
                }
                ContactForceError::Creepage { side, zone, .. } => ("creepages", place(side, zone)),
                ContactForceError::Creep { side, zone, .. } => ("creep forces", place(side, zone)),
                ContactForceError::InvalidSetting { .. } => ("contact force setting", None),
            };
            (kind.into(), Some(*t_s), Some(wheelset.clone()), at)
        }
        DynamicsError::Derailed { wheelset, t_s, .. } => (
            "derailed (lateral displacement beyond the limit)".into(),
            Some(*t_s),
            Some(wheelset.clone()),
            None,
        ),
        DynamicsError::Track { t_s, .. } => ("off the track tables".into(), Some(*t_s), None, None),
        DynamicsError::Assembly { wheelset, .. } => {
            ("assembly".into(), None, Some(wheelset.clone()), None)
        }
        other => (format!("{other}"), None, None, None),
    }
}

/// The diagnostic of a failed integration, `last` the last state the system
/// was evaluated at (time s, state); a numerical blow-up is told from a
/// derailment ([`crate::run::blow_up`]).
pub fn diagnose(
    error: &IntegratorError<DynamicsError>,
    system: &VehicleSystem<'_>,
    last: Option<(f64, &[f64])>,
    context: &DiagnoseContext<'_>,
) -> RunDiagnostic {
    let (kind, t, wheelset, at) = match error {
        IntegratorError::System(e) => classify(e),
        IntegratorError::NonFinite { t, component } => (
            format!("non-finite state or derivative (component {component})"),
            Some(*t),
            None,
            None,
        ),
        IntegratorError::StepSizeTooSmall { t, .. } => {
            ("step size below the minimum".into(), Some(*t), None, None)
        }
        IntegratorError::TooManySteps { t, .. } => {
            ("step limit reached".into(), Some(*t), None, None)
        }
        IntegratorError::InvalidSettings { .. } => ("integrator setting".into(), None, None, None),
    };
    let t_s = t.or(last.map(|(t, _)| t)).unwrap_or(f64::NAN);
    let names: Vec<&str> = system
        .vehicle()
        .wheelsets
        .iter()
        .map(|w| w.name.as_str())
        .collect();
    let which: Vec<usize> = match &wheelset {
        Some(name) => names.iter().position(|n| n == name).into_iter().collect(),
        None => (0..names.len()).collect(),
    };
    // Every wheelset's state, for the signs of a blow-up.
    let all: Vec<(usize, Option<WheelsetState>)> = match last {
        Some((_, y)) => (0..names.len())
            .map(|i| (i, wheelset_state(system, i, y)))
            .collect(),
        None => Vec::new(),
    };
    let states: Vec<WheelsetState> = all
        .iter()
        .filter(|(i, _)| which.contains(i))
        .filter_map(|(_, s)| s.clone())
        .collect();
    let finite: Vec<WheelsetState> = all.iter().filter_map(|(_, s)| s.clone()).collect();
    // A state off the tables is no sign by itself; one that is not finite is.
    let missing: Vec<String> = all
        .iter()
        .filter(|(i, s)| {
            s.is_none()
                && last.is_some_and(|(_, y)| {
                    y.get(BodyState::slot(*i))
                        .is_some_and(|v| v.iter().any(|x| !x.is_finite()))
                })
        })
        .map(|(i, _)| names[*i].to_string())
        .collect();
    let mut signs = crate::run::blow_up::blow_up_signs(
        t_s,
        &finite,
        &missing,
        &context.references,
        context.energy.as_ref(),
    );
    let non_finite = matches!(error, IntegratorError::NonFinite { .. })
        || matches!(
            error,
            IntegratorError::System(DynamicsError::Force {
                source: ContactForceError::Hertz {
                    source: HertzError::NonFiniteCurvature { .. },
                    ..
                },
                ..
            })
        );
    if non_finite && signs.is_empty() {
        signs.push(kind.clone());
    }
    let derailed = matches!(
        error,
        IntegratorError::System(DynamicsError::Derailed { .. })
    );
    let advice = crate::run::warnings::step_advice(context.method);
    let (kind, likely_cause) = if !signs.is_empty() {
        (
            if derailed {
                "numerical blow-up, not a derailment (|y| passed the derailment limit, but not by a flange climb)".to_string()
            } else {
                format!("numerical blow-up (then: {kind})")
            },
            Some(format!(
                "a step too large for the stiffest mode (contact stiffness, creep damping at low speed) or a stiffness in the wrong unit: {advice}; check the units of [contact] young_pa and of the vehicle file's stiffnesses and masses"
            )),
        )
    } else if derailed && context.flange_off {
        (
            "ran through its flange with the flange search off, not a derailment (|y| passed the derailment limit without flange contact)".to_string(),
            Some("the flange search is off: set contact.flange = \"auto\" (or \"on\")".to_string()),
        )
    } else if matches!(error, IntegratorError::StepSizeTooSmall { .. }) {
        (
            kind,
            Some("a stiffness or damping far beyond a steel contact's (check the units of [contact] young_pa and of the vehicle file's stiffnesses), or a discontinuity the step cannot pass".to_string()),
        )
    } else {
        (kind, None)
    };
    let (wheel, zone) = match at {
        Some((w, z)) => (Some(w), Some(z)),
        None => (None, None),
    };
    let ran_through_flange = derailed && context.flange_off && signs.is_empty();
    RunDiagnostic {
        kind,
        t_s,
        wheelset,
        wheel,
        zone,
        states,
        blow_up_signs: signs,
        likely_cause,
        ran_through_flange,
        detail: format!("{error}"),
    }
}

/// Fallbacks the run went through (module docs).
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Default)]
pub struct FallbackCounts {
    /// Contact solves answered by the minimisation fallback (every
    /// evaluation, integrator stages included).
    pub minimisation_solves: u64,
    /// Contacts evaluated with the non-Hertzian curvature floor (every
    /// evaluation of the right-hand side).
    pub hertz_floor_evaluations: u64,
    /// Recorded samples with at least one zone from each fallback.
    pub samples_with_minimisation: u64,
    pub samples_with_hertz_floor: u64,
    /// Factorisations of the stiff integrator's W made by the dense LU
    /// because a block pivot failed the threshold test
    /// (`runtime::integrators::body_blocks`).
    pub dense_lu_factorisations: u64,
}

impl FallbackCounts {
    /// From the solvers' statistics, the evaluations counted by [`Watched`]
    /// and the results' per-zone flags.
    pub fn count(
        minimisation_solves: u64,
        hertz_floor_evaluations: u64,
        dense_lu_factorisations: u64,
        results: &runtime::results::RunResults,
    ) -> Self {
        use runtime::results::{FALLBACK_HERTZ_FLOOR, FALLBACK_MINIMISATION};
        let samples = |bit: u8| {
            (0..results.len())
                .filter(|&i| {
                    results.wheelsets.iter().any(|w| {
                        w.wheels.iter().any(|wh| {
                            wh.zones
                                .iter()
                                .any(|z| z.fallback.get(i).is_some_and(|f| f & bit != 0))
                        })
                    })
                })
                .count() as u64
        };
        Self {
            minimisation_solves,
            hertz_floor_evaluations,
            samples_with_minimisation: samples(FALLBACK_MINIMISATION),
            samples_with_hertz_floor: samples(FALLBACK_HERTZ_FLOOR),
            dense_lu_factorisations,
        }
    }

    /// Any fallback at all.
    pub fn any(&self) -> bool {
        self.minimisation_solves + self.hertz_floor_evaluations + self.dense_lu_factorisations > 0
    }

    /// One line for the text summary (empty without fallbacks).
    pub fn to_text(&self) -> String {
        if !self.any() {
            return String::new();
        }
        format!(
            "  fallbacks: {} contact solves from the minimisation fallback (nearly conformal; {} samples), {} contact evaluations with the non-Hertzian curvature floor ({} samples), {} factorisations of W by the dense LU (a block pivot below the threshold)\n",
            self.minimisation_solves,
            self.samples_with_minimisation,
            self.hertz_floor_evaluations,
            self.samples_with_hertz_floor,
            self.dense_lu_factorisations
        )
    }
}

/// Root attributes of the results file with the integrator's and the
/// contact search's counts (`stats` is `None` when the run failed: the
/// accepted steps are then `accepted`), the fallbacks and the diagnostic.
pub fn run_attributes(
    stats: Option<&IntegrationStats>,
    accepted: u64,
    rhs_evaluations: u64,
    contact_solves: u64,
    fallbacks: &FallbackCounts,
    diagnostic: Option<&RunDiagnostic>,
) -> Vec<(String, AttrValue)> {
    let mut a: Vec<(String, AttrValue)> = vec![
        (
            "steps".to_string(),
            stats.map_or(accepted, |s| s.steps).into(),
        ),
        (
            "rejected_steps".to_string(),
            stats.map_or("unknown (the run failed)".into(), |s| s.rejected.into()),
        ),
        ("rhs_evaluations".to_string(), rhs_evaluations.into()),
        ("contact_solves".to_string(), contact_solves.into()),
        (
            "minimisation_fallbacks".to_string(),
            fallbacks.minimisation_solves.into(),
        ),
        (
            "non_hertzian_fallbacks".to_string(),
            fallbacks.hertz_floor_evaluations.into(),
        ),
        (
            "dense_lu_fallbacks".to_string(),
            fallbacks.dense_lu_factorisations.into(),
        ),
    ];
    if let Some(s) = stats {
        a.push(("min_step_s".into(), s.min_step_s.into()));
        a.push(("max_step_s".into(), s.max_step_s.into()));
    }
    if let Some(d) = diagnostic {
        a.push(("diagnostic".into(), d.headline().into()));
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headline_names_time_wheel_zone_and_state() {
        let d = RunDiagnostic {
            kind: "non-Hertzian contact".into(),
            t_s: 0.7283,
            wheelset: Some("front".into()),
            wheel: Some("left".into()),
            zone: Some("tread".into()),
            states: vec![WheelsetState {
                name: "front".into(),
                s_m: 12.3,
                lateral_mm: 0.031,
                yaw_mrad: -3.6,
                roll_mrad: 0.008,
                height_mm: 429.6,
                forward_speed_m_s: 10.0,
                lateral_speed_m_s: -0.04,
            }],
            blow_up_signs: Vec::new(),
            likely_cause: None,
            ran_through_flange: false,
            detail: "…".into(),
        };
        let h = d.headline();
        for needle in [
            "non-Hertzian contact at t = 0.728300 s",
            "wheelset 'front'",
            "left wheel",
            "tread",
            "y = +0.031 mm",
            "yaw = -3.600 mrad",
        ] {
            assert!(h.contains(needle), "{needle} not in {h}");
        }
    }

    #[test]
    fn errors_are_classified_with_their_place() {
        use runtime::contact::SurfaceParams;
        use runtime::geometry::profile::Zone;
        use runtime::geometry::track::Side;
        let e = DynamicsError::Contact {
            wheelset: "rear".into(),
            t_s: 1.5,
            source: ContactError::NotConverged {
                side: Side::Right,
                zone: Zone::Flange,
                iterations: 25,
                residual: 1e-3,
                params: SurfaceParams {
                    s_rail_m: 0.0,
                    u_rail_m: 0.0,
                    s_wheel_rad: 0.0,
                    u_wheel_m: 0.0,
                },
                s_track_m: 10.0,
                position_m: [0.0; 3],
            },
        };
        let (kind, t, ws, at) = classify(&e);
        assert!(kind.contains("did not converge"), "{kind}");
        assert_eq!(t, Some(1.5));
        assert_eq!(ws.as_deref(), Some("rear"));
        assert_eq!(at, Some(("right".into(), "flange".into())));
        let e = DynamicsError::Force {
            wheelset: "front".into(),
            t_s: 0.2,
            source: ContactForceError::Hertz {
                side: Side::Left,
                zone: Zone::Tread,
                source: HertzError::NonHertzian {
                    a_curv_1_m: 1.16,
                    b_curv_1_m: -0.01,
                },
            },
        };
        let (kind, _, _, at) = classify(&e);
        assert!(kind.starts_with("non-Hertzian"), "{kind}");
        assert_eq!(at, Some(("left".into(), "tread".into())));
    }
}
