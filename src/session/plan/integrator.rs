//! The integrator decision (module docs of [`super`]): the stiff-aware
//! Rosenbrock-W method (docs/reference/08-multibody.md §8.5) with an
//! absolute tolerance from the vehicle, the flange decision and the
//! scene's tolerance; RK4 at [`REFERENCE_STEP_S`] for `mode = "everything"`.
//!
//! The rule and its measured justification (lateral error = the largest
//! difference of any wheelset's lateral displacement from RK4 at 0.1 ms;
//! `docs/guide/speed-accuracy-tradeoff.md`, "The integrator"):
//!
//! - Rosenbrock at atol [`SUSPENDED_ATOL`] = 5e-6 (rtol 1e-9, largest step
//!   10 ms: the integrator's defaults): the ML95-like bogie 8.8 µm at 20 m/s
//!   and 7.2 µm at 36 m/s, the Cooperrider car 4.1 µm at 40 m/s, 3–4× less
//!   CPU than RK4 at 0.5 ms (docs/reference/08-multibody.md §8.5).
//! - atol [`FREE_FLANGE_ATOL`] = 2e-7 when a wheelset without any suspension
//!   element (a free wheelset) may reach its flanges (flange search `auto`
//!   or `on`): the flange-limited free ML95-like wheelset at 20 m/s (55
//!   flange impacts) is 79 µm off at 5e-6, 14 µm at 1e-6 and 1.3 µm at
//!   2e-7. A suspended wheelset is held off its flange by its suspension:
//!   the bogie's figures above include its flange contacts at 36 m/s.
//! - Only on an ideal straight over the run's range. Elsewhere RK4 at the
//!   scene's step: in sustained flange contact the reused Jacobian does
//!   not hold the flange's stiffness, steps shrink below 0.5 ms and the
//!   Jacobian is renewed every dozen steps — the bogie scenes on R 250 m
//!   and R 600 m took 98 539 and 130 348 steps (7 635 and 7 124 rejected),
//!   1.7× and 2.5× RK4's wall time, and were 11 and 16 µm off RK4 at
//!   0.5 ms ([`CURVED_TRACK_REASON`]).
//! - With `run.lateral_tolerance_m` the atol is at most the tolerance over
//!   the measured error per unit atol ([`SUSPENDED_ERROR_PER_ATOL`] = 2,
//!   from 8.8 µm at 5e-6; [`FREE_FLANGE_ERROR_PER_ATOL`] = 7, from 1.3 µm at
//!   2e-7). The error was measured to fall faster than linearly with the
//!   atol (79 → 14 → 1.3 µm for 5e-6 → 1e-6 → 2e-7), so the linear scaling
//!   below the measured point is conservative.

use serde::Serialize;

use super::{By, Decision};
use crate::config::scene::{
    FlangeMode, IntegratorKind, PlanMode, ROSENBROCK_DEFAULT_TOLERANCES, Scene,
};
use crate::config::vehicle::VehicleFile;

/// Rosenbrock's absolute tolerance for a vehicle whose wheelsets are all
/// suspended, or that cannot reach its flanges (module docs: 8.8 µm on
/// the bogie at 20 m/s).
pub const SUSPENDED_ATOL: f64 = 5e-6;

/// Rosenbrock's absolute tolerance when a free wheelset may reach its
/// flanges (module docs: 1.3 µm on the flange-limited wheelset at 20 m/s).
pub const FREE_FLANGE_ATOL: f64 = 2e-7;

/// Measured lateral error per unit of atol (m/m) of the suspended case:
/// 8.8 µm at 5e-6, rounded up.
pub const SUSPENDED_ERROR_PER_ATOL: f64 = 2.0;

/// Measured lateral error per unit of atol (m/m) of the free wheelset in
/// flange contact: 1.3 µm at 2e-7, rounded up.
pub const FREE_FLANGE_ERROR_PER_ATOL: f64 = 7.0;

/// The step of the reference run (s): RK4 at 0.1 ms, the reference of the
/// measurements above and of `sim tradeoff`.
pub const REFERENCE_STEP_S: f64 = 1e-4;

/// The integrator a plan runs with.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct IntegratorChoice {
    pub kind: IntegratorKind,
    /// RK4's step (s); `None` for an adaptive method.
    pub step_s: Option<f64>,
    /// Rosenbrock's relative and absolute tolerances and largest step (s).
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    pub max_step_s: Option<f64>,
}

impl IntegratorChoice {
    fn rk4(step_s: f64) -> Self {
        Self {
            kind: IntegratorKind::Rk4,
            step_s: Some(step_s),
            rtol: None,
            atol: None,
            max_step_s: None,
        }
    }

    fn rosenbrock(atol: f64) -> Self {
        let (rtol, _, max_step_s) = ROSENBROCK_DEFAULT_TOLERANCES;
        Self {
            kind: IntegratorKind::Rosenbrock,
            step_s: None,
            rtol: Some(rtol),
            atol: Some(atol),
            max_step_s: Some(max_step_s),
        }
    }

    /// As the block shows it.
    pub fn text(&self) -> String {
        match (self.kind, self.step_s, self.atol) {
            (IntegratorKind::Rk4, Some(h), _) => format!("rk4 {:.3} ms", h * 1e3),
            (k, _, Some(a)) => format!("{k} atol {a:.1e}"),
            (k, _, _) => k.to_string(),
        }
    }

    /// Writes the choice into the scene's `[run]`.
    pub fn apply(&self, run: &mut crate::config::scene::RunSection) {
        run.integrator = self.kind;
        if let Some(h) = self.step_s {
            run.step_s = h;
        }
        if self.kind != IntegratorKind::Rk4 {
            run.rtol = self.rtol;
            run.atol = self.atol;
            run.max_step_s = self.max_step_s;
        }
    }
}

/// The integrator part of a plan: the choice (`None`: the scene's, as
/// written) and what a revision needs.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct IntegratorPlan {
    pub choice: Option<IntegratorChoice>,
    /// The vehicle's wheelsets without a suspension element.
    pub free_wheelsets: Vec<String>,
    /// The scene's `run.lateral_tolerance_m` (m).
    pub lateral_tolerance_m: Option<f64>,
    /// Whether the track is an ideal straight over the run's range (the
    /// stiff integrator is chosen only there, module docs).
    pub straight: bool,
    /// The scene's RK4 step (s), kept on other tracks.
    pub scene_step_s: f64,
}

/// The wheelsets of `v` no element is attached to (neither end).
pub fn free_wheelsets(v: &VehicleFile) -> Vec<String> {
    v.wheelsets
        .iter()
        .filter(|w| {
            !v.elements
                .iter()
                .any(|e| e.body_a == w.name || e.body_b == w.name)
        })
        .map(|w| w.name.clone())
        .collect()
}

/// What the planner would choose (module docs), and why.
pub fn planned(
    free: &[String],
    flange: FlangeMode,
    lateral_tolerance_m: Option<f64>,
) -> (IntegratorChoice, String) {
    let flange_searched = flange != FlangeMode::Off;
    let (base, per_atol, why) = match free.first() {
        Some(name) if flange_searched => (
            FREE_FLANGE_ATOL,
            FREE_FLANGE_ERROR_PER_ATOL,
            format!(
                "free wheelset '{name}' (no suspension element) may run into its flanges (flange search {flange}): measured 1.3 µm at 2e-7 on the flange-limited wheelset at 20 m/s (79 µm at 5e-6)"
            ),
        ),
        _ => (
            SUSPENDED_ATOL,
            SUSPENDED_ERROR_PER_ATOL,
            format!(
                "{}: measured at most 8.8 / 7.3 µm on the bogie at 20 / 36 m/s, 5.2 µm on the car at 40 m/s",
                if free.is_empty() {
                    "every wheelset suspended"
                } else {
                    "no flange contact expected (flange search off)"
                }
            ),
        ),
    };
    match lateral_tolerance_m {
        Some(tol) if tol / per_atol < base => (
            IntegratorChoice::rosenbrock(tol / per_atol),
            format!(
                "{why}; tolerance {:.2} µm / {per_atol} µm per µm of atol",
                tol * 1e6
            ),
        ),
        _ => (IntegratorChoice::rosenbrock(base), why),
    }
}

/// The scene's integrator as the block shows it.
fn scene_text(scene: &Scene) -> String {
    let r = &scene.run;
    match r.integrator {
        IntegratorKind::Rk4 => IntegratorChoice::rk4(r.step_s).text(),
        k => format!("{k} atol {:.1e}", r.tolerances().1),
    }
}

/// What the planner would choose on a track that is (`straight`) or is
/// not an ideal straight over the range (module docs): off the straight,
/// RK4 at the scene's step `scene_step_s`.
pub fn planned_on(
    straight: bool,
    scene_step_s: f64,
    free: &[String],
    flange: FlangeMode,
    lateral_tolerance_m: Option<f64>,
) -> (IntegratorChoice, String) {
    if straight {
        planned(free, flange, lateral_tolerance_m)
    } else {
        (
            IntegratorChoice::rk4(scene_step_s),
            CURVED_TRACK_REASON.to_string(),
        )
    }
}

/// Why the stiff integrator is not chosen off an ideal straight.
pub const CURVED_TRACK_REASON: &str = "the track is not an ideal straight over the range: in sustained flange contact (curves) the stiff integrator is slower than RK4 and less accurate (measured: the bogie scenes on R 250 m and R 600 m took 1.7× and 2.5× RK4's wall time, 11 and 16 µm off), so RK4 at the scene's step";

/// Decide the integrator: `flange` the plan's flange search, `chosen`
/// whether the planner chooses it (`mode = "required"` without
/// `run.integrator`, or `integrator` in `[plan] choose`).
pub fn decide(
    scene: &Scene,
    free: Vec<String>,
    flange: FlangeMode,
    straight: bool,
    mode: PlanMode,
    chosen: bool,
) -> (Decision, IntegratorPlan) {
    let tol = scene.run.lateral_tolerance_m;
    let scene_step_s = scene.run.step_s;
    let (planned, why) = planned_on(straight, scene_step_s, &free, flange, tol);
    let (value, by, reason, choice) = match mode {
        PlanMode::Everything => {
            let c = IntegratorChoice::rk4(REFERENCE_STEP_S);
            (
                c.text(),
                By::Everything,
                "the fine reference of the measurements (RK4 at 0.1 ms)".to_string(),
                Some(c),
            )
        }
        PlanMode::Required if chosen => (planned.text(), By::Planner, why, Some(planned)),
        _ => (
            scene_text(scene),
            By::Scene,
            format!("the planner would choose {}: {why}", planned.text()),
            None,
        ),
    };
    (
        Decision {
            item: "integrator".into(),
            value,
            by,
            reason,
        },
        IntegratorPlan {
            choice,
            free_wheelsets: free,
            lateral_tolerance_m: tol,
            straight,
            scene_step_s,
        },
    )
}

/// After the flange search was revised to `auto`: the planner's choice
/// again (a free wheelset now tightens the atol); the scene's and the
/// reference's stay.
pub fn revise(p: &mut IntegratorPlan, d: &mut Decision) {
    if d.by != By::Planner {
        return;
    }
    let (c, why) = planned_on(
        p.straight,
        p.scene_step_s,
        &p.free_wheelsets,
        FlangeMode::Auto,
        p.lateral_tolerance_m,
    );
    if p.choice != Some(c) {
        p.choice = Some(c);
        d.value = c.text();
        d.reason = format!("revised with the flange search: {why}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::scene::LoadedScene;

    fn vehicle(name: &str) -> VehicleFile {
        VehicleFile::load(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("tables/vehicles")
                .join(name),
        )
        .expect("shipped vehicle")
    }

    #[test]
    fn a_free_wheelset_with_the_flange_searched_gets_the_tight_atol() {
        let free = free_wheelsets(&vehicle("ml95_like_wheelset.toml"));
        assert_eq!(free, vec!["wheelset".to_string()]);
        let (c, why) = planned(&free, FlangeMode::Auto, None);
        assert_eq!(c.kind, IntegratorKind::Rosenbrock);
        assert_eq!(c.atol, Some(FREE_FLANGE_ATOL));
        assert!(why.contains("free wheelset 'wheelset'"), "{why}");
        // Flange off: the free wheelset is never near its flange.
        let (c, _) = planned(&free, FlangeMode::Off, None);
        assert_eq!(c.atol, Some(SUSPENDED_ATOL));
    }

    #[test]
    fn a_bogie_gets_the_default_atol_and_a_tolerance_tightens_it() {
        let free = free_wheelsets(&vehicle("ml95_like_bogie.toml"));
        assert!(free.is_empty(), "{free:?}");
        let (c, _) = planned(&free, FlangeMode::Auto, None);
        assert_eq!(c.kind, IntegratorKind::Rosenbrock);
        assert_eq!(c.atol, Some(SUSPENDED_ATOL));
        assert_eq!(c.rtol, Some(ROSENBROCK_DEFAULT_TOLERANCES.0));
        // 10 µm admits 5e-6; 2 µm asks for 1e-6.
        let (c, _) = planned(&free, FlangeMode::Auto, Some(1e-5));
        assert_eq!(c.atol, Some(SUSPENDED_ATOL));
        let (c, why) = planned(&free, FlangeMode::Auto, Some(2e-6));
        assert!((c.atol.unwrap() - 1e-6).abs() < 1e-18, "{c:?}");
        assert!(why.contains("tolerance 2.00 µm"), "{why}");
    }

    #[test]
    fn off_the_straight_rk4_at_the_scenes_step_stays() {
        let free = free_wheelsets(&vehicle("ml95_like_bogie.toml"));
        let (c, why) = planned_on(false, 5e-4, &free, FlangeMode::Auto, None);
        assert_eq!(c, IntegratorChoice::rk4(5e-4));
        assert!(why.contains("not an ideal straight"), "{why}");
        let (c, _) = planned_on(true, 5e-4, &free, FlangeMode::Auto, None);
        assert_eq!(c.kind, IntegratorKind::Rosenbrock);
    }

    #[test]
    fn modes_scene_required_and_everything() {
        let ls = LoadedScene::default_scene(&[]).expect("scene");
        let s = &ls.scene;
        let free = vec!["wheelset".to_string()];
        // Scene: the scene's RK4 stays; the block says what the planner
        // would choose.
        let (d, p) = decide(
            s,
            free.clone(),
            FlangeMode::Auto,
            true,
            PlanMode::Scene,
            false,
        );
        assert_eq!(p.choice, None);
        assert_eq!(d.by, By::Scene);
        assert_eq!(d.value, "rk4 0.100 ms");
        assert!(
            d.reason.contains("would choose rosenbrock atol 2.0e-7"),
            "{}",
            d.reason
        );
        // Required, set in the scene and not chosen: the scene's.
        let (_, p) = decide(
            s,
            free.clone(),
            FlangeMode::Auto,
            true,
            PlanMode::Required,
            false,
        );
        assert_eq!(p.choice, None);
        let (d, p) = decide(
            s,
            free.clone(),
            FlangeMode::Auto,
            true,
            PlanMode::Required,
            true,
        );
        assert_eq!(d.by, By::Planner);
        assert_eq!(p.choice.unwrap().atol, Some(FREE_FLANGE_ATOL));
        let mut run = s.run.clone();
        p.choice.unwrap().apply(&mut run);
        assert_eq!(run.integrator, IntegratorKind::Rosenbrock);
        assert_eq!(run.tolerances().1, FREE_FLANGE_ATOL);
        // Everything: RK4 at 0.1 ms.
        let (d, p) = decide(s, free, FlangeMode::On, true, PlanMode::Everything, false);
        assert_eq!(d.by, By::Everything);
        assert_eq!(p.choice, Some(IntegratorChoice::rk4(REFERENCE_STEP_S)));
    }

    #[test]
    fn a_revised_flange_search_tightens_the_planners_atol_only() {
        let ls = LoadedScene::default_scene(&[]).expect("scene");
        let free = vec!["wheelset".to_string()];
        let (mut d, mut p) = decide(
            &ls.scene,
            free.clone(),
            FlangeMode::Off,
            true,
            PlanMode::Required,
            true,
        );
        assert_eq!(p.choice.unwrap().atol, Some(SUSPENDED_ATOL));
        revise(&mut p, &mut d);
        assert_eq!(p.choice.unwrap().atol, Some(FREE_FLANGE_ATOL));
        assert!(d.reason.starts_with("revised"), "{}", d.reason);
        let (mut d, mut p) = decide(
            &ls.scene,
            free,
            FlangeMode::Off,
            true,
            PlanMode::Scene,
            false,
        );
        revise(&mut p, &mut d);
        assert_eq!(p.choice, None);
    }
}
