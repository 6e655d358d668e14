//! Model only what a scene requires (issue 7, docs/reference/01-units-frames.md §0: "a run models only
//! what its scene requires"). Before a run, [`plan`] looks at the scene —
//! the track's geometry over the stretch the run covers, the vehicle, the
//! speed and the initial offset, the stated tolerance — and decides:
//!
//! | item | the planner's rule |
//! |---|---|
//! | flange search | `off` on an ideal straight (no curvature, cant or irregularity over the run's range) when the initial approach of every wheel, \|y₀\| + \|ψ₀\|·√(2 R0 h_flange), is at most [`START_FRACTION`] of the guard's threshold (below) **and** the linearised centred run is stable with margin at the scene's speed (hunting mode damping ratio ≥ [`MIN_HUNTING_DAMPING`]); `auto` otherwise. An `off` run is watched ([`FlangeGuard`]): should a wheelset come within [`GUARD_MARGIN_M`] of the `auto` threshold, the run is repeated with `auto`. Until then the `auto` rule would not have searched either, so the results are those of `auto`. |
//! | irregularities | the build's irregularity stage runs only when the scene gives an irregularity table (stated with its largest deviation over the run's range). |
//! | track range | only the stretch the run covers: from the rearmost point of the vehicle (wheelsets, bodies, references) at the start, minus [`RANGE_MARGIN_M`], to the foremost point at the end (distance, or duration × speed, less with a deceleration), plus the 2 m the dynamics keeps ahead and [`RANGE_MARGIN_M`]. Built in memory ([`build_track_range`]); the rows are those of the whole-track table (same grid). |
//! | table step | exact at any step on an ideal straight (linear interpolation of straight lines; `sim tradeoff` on the bogie measured zero error up to 1 m): [`MAX_STEP_M`]. Otherwise the coarsest of [`NICE_STEPS_M`] whose chord error h²κ/8 stays within [`GEOMETRY_TOLERANCE_M`] (κ the largest curvature of the rails over the range, irregularities included). The paper's rule h ≤ V·Δt (§2) is reported for comparison. |
//! | contact method | the contact lookup table where its error measured by `sim tradeoff` (`tables/planner/measured.toml`, [`measured()`]) is within the scene's `run.lateral_tolerance_m`; online otherwise (and always without a stated tolerance). |
//! | integrator | on an ideal straight over the range, `rosenbrock` (ROS34PW2, docs/reference/08-multibody.md §8.5; rtol 1e-9, largest step 10 ms) at atol [`SUSPENDED_ATOL`] = 5e-6, or [`FREE_FLANGE_ATOL`] = 2e-7 when a free wheelset (no suspension element attached) may reach its flanges (flange search `auto` or `on`); with `run.lateral_tolerance_m`, atol ≤ tolerance / the measured error per atol (2 suspended, 7 free with flange). Measured against RK4 at 0.1 ms: bogie 8.8 µm (20 m/s) and 7.2 µm (36 m/s), car 4.1 µm at 5e-6, 3–4× less CPU than RK4 at 0.5 ms; the flange-limited free wheelset 79 µm at 5e-6, 1.3 µm at 2e-7. Elsewhere RK4 at the scene's step: in sustained flange contact (curves) the stiff integrator was 1.7–2.5× slower than RK4 and 11–16 µm off ([`integrator`]). |
//! | creep law | never chosen (it is physics, not numerics); its cost relative to Polach, measured by `sim tradeoff`, is stated (`tables/planner/measured.toml`, [`measured()`]). |
//!
//! The `[plan]` section of the scene says who decides:
//!
//! - `mode = "scene"` (the default, every shipped scene): the scene runs as
//!   written; the block reports the scene's values and what the planner
//!   would choose (the cheap checks only: no linearisation).
//! - `mode = "required"`: the planner chooses every item the scene leaves
//!   out — an entry present in the scene (`contact.flange`,
//!   `contact.method`, `track.step_m`, `track.range_m`, `run.integrator`)
//!   forces that choice — and the items listed in `choose` (`flange`,
//!   `method`, `step`, `range`, `integrator`, or `all`) even when the scene
//!   sets them.
//! - `mode = "everything"`: the reference to measure against — flange
//!   always searched, online contact (an imported contact stays), the finest
//!   table step [`FINEST_STEP_M`] (the `sim tradeoff` reference's), the
//!   whole track, RK4 at [`REFERENCE_STEP_S`] = 0.1 ms.
//!
//! The decisions are one block of the output ([`Plan::to_text`]), the
//! `plan` object of `sim run --json` and the `plan` attribute of the
//! results file.
//!
//! One file per decision — [`flange`], [`irregularities`], [`range`],
//! [`step`], [`method`], [`integrator`], [`creep_law`] — each deciding from what it is
//! given ([`facts`]: the track over the range, the vehicle's flange, the
//! distance travelled) and returning its [`Decision`] and value; [`plan`]
//! calls them in order. The vehicle model of the flange checks is built at
//! most once per plan (the flangeway clearance sweep and the hunting check
//! share it). The measured constants (wall times, the contact table's
//! error) are data, not code: `tables/planner/measured.toml`, regenerated
//! by `scripts/planner_constants.sh`.

pub mod creep_law;
pub mod facts;
mod facts_cache;
pub mod flange;
pub mod integrator;
pub mod irregularities;
pub mod measured;
pub mod method;
pub mod range;
pub mod step;

use std::collections::BTreeSet;
use std::time::Instant;

use anyhow::Result;
use serde::Serialize;

use crate::config::scene::{ContactMethodKind, FlangeMode, LoadedScene, PlanItem, PlanMode};

pub use facts::{
    DYNAMICS_LOOKAHEAD_M, FlangeFacts, RANGE_MARGIN_M, STRAIGHT_CURVATURE_1_M, TrackFacts,
    required_range_m, travel_m,
};
pub use flange::{
    AUTO_MARGIN_M, FlangeGuard, GUARD_MARGIN_M, MIN_HUNTING_DAMPING, START_FRACTION, guard_check,
};
pub use integrator::{
    FREE_FLANGE_ATOL, IntegratorChoice, IntegratorPlan, REFERENCE_STEP_S, SUSPENDED_ATOL,
};
pub use measured::{
    CreepLawCost, CreepLawCosts, Measured, MeasuredTableError, Provenance, TrackKind, measured,
};
pub use range::{build_config, build_track_range, geometry_files, track_inputs_key};
pub use step::{FINEST_STEP_M, GEOMETRY_TOLERANCE_M, MAX_STEP_M, NICE_STEPS_M};

/// The items the planner may choose (`[plan] choose`).
pub const ITEMS: [&str; 5] = ["flange", "method", "step", "range", "integrator"];

/// Who set a value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum By {
    /// The scene's own entry (or its default in `mode = "scene"`).
    Scene,
    /// The planner.
    Planner,
    /// `mode = "everything"`.
    Everything,
}

impl By {
    fn name(self) -> &'static str {
        match self {
            By::Scene => "scene",
            By::Planner => "planner",
            By::Everything => "everything",
        }
    }
}

/// One line of the block.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Decision {
    /// `flange_search`, `irregularities`, `track_range`, `table_step`,
    /// `contact_method`, `integrator`, `creep_law`.
    pub item: String,
    pub value: String,
    pub by: By,
    pub reason: String,
}

/// The decisions for one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    /// Who decided (`[plan] mode`).
    pub mode: PlanMode,
    /// The block, in order.
    pub decisions: Vec<Decision>,
    /// The values to run with.
    pub flange: FlangeMode,
    pub method: ContactMethodKind,
    /// Table step (m); `None` with a table file.
    pub step_m: Option<f64>,
    /// Track range (m); `None`: the whole track.
    pub range_m: Option<[f64; 2]>,
    /// Length of an ideal straight (m), shortened to the range.
    pub straight_m: Option<f64>,
    /// The integrator (`choice: None`: the scene's).
    pub integrator: IntegratorPlan,
    /// Watch an `off` run (see [`FlangeGuard`]).
    pub flange_guard: Option<FlangeGuard>,
    /// Set when a run was repeated: why.
    pub revised: Option<String>,
    pub track: TrackFacts,
    pub flange_facts: Option<FlangeFacts>,
    /// Wall time of the planning (s).
    pub planning_time_s: f64,
}

/// Entries written in the scene (after the overrides): those force a choice.
fn explicit_entries(ls: &LoadedScene) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let Ok(table) = ls.text.parse::<toml::Table>() else {
        return out;
    };
    for (section, key) in [
        ("contact", "flange"),
        ("contact", "method"),
        ("track", "step_m"),
        ("track", "range_m"),
        ("run", "integrator"),
    ] {
        if table
            .get(section)
            .and_then(toml::Value::as_table)
            .is_some_and(|t| t.contains_key(key))
        {
            out.insert(format!("{section}.{key}"));
        }
    }
    out
}

/// A length (m) as the block shows it: millimetres, two decimals.
fn mm(x_m: f64) -> String {
    format!("{:.2} mm", x_m * 1e3)
}

/// Decide what the scene requires (module docs): the facts, then one
/// decision per item, in the order of the block.
pub fn plan(ls: &LoadedScene) -> Result<Plan> {
    let start = Instant::now();
    let scene = &ls.scene;
    let mode = scene.plan.mode;
    let explicit = explicit_entries(ls);
    let planner_chooses = |item: PlanItem, entry: &str| -> bool {
        mode == PlanMode::Required && (scene.plan.chooses(item) || !explicit.contains(entry))
    };
    let vfile = ls.vehicle_file()?;
    let wanted = required_range_m(ls, &vfile);
    let track = facts::track_facts(ls, wanted)?;
    let mut decisions = Vec::new();

    decisions.push(irregularities::decide(&track));

    let range = range::decide(
        ls,
        &vfile,
        &track,
        wanted,
        mode,
        planner_chooses(PlanItem::Range, "track.range_m"),
    );
    decisions.push(range.decision);

    let (decision, step_m) = step::decide(
        scene,
        &track,
        mode,
        planner_chooses(PlanItem::Step, "track.step_m"),
    );
    decisions.push(decision);

    // The flange search is assessed before the method (the table needs no
    // flange contact to be expected) and decided after it.
    let c = &scene.contact;
    let method_chosen = planner_chooses(PlanItem::Method, "contact.method")
        && c.method != ContactMethodKind::Imported;
    let flange_chosen = planner_chooses(PlanItem::Flange, "contact.flange");
    let mut check = facts::CheckModel::new(ls, &vfile)?;
    let assessment = flange::assess(
        ls,
        &track,
        &mut check,
        mode != PlanMode::Scene && (flange_chosen || method_chosen),
    )?;

    let (decision, method) = method::decide(
        scene,
        track.track_kind(),
        assessment.no_flange_expected,
        mode,
        method_chosen,
    )?;
    decisions.push(decision);

    let (decision, flange, flange_guard) = flange::decide(
        &assessment,
        c.flange,
        method,
        mode,
        method_chosen,
        flange_chosen,
    );
    decisions.push(decision);

    let (decision, integrator) = integrator::decide(
        scene,
        integrator::free_wheelsets(&vfile),
        flange,
        track.straight(),
        mode,
        planner_chooses(PlanItem::Integrator, "run.integrator"),
    );
    decisions.push(decision);

    decisions.push(creep_law::decide(c.creep_law)?);

    Ok(Plan {
        mode,
        decisions,
        flange,
        method,
        step_m,
        range_m: range.range_m,
        straight_m: range.straight_m,
        integrator,
        flange_guard,
        revised: None,
        track,
        flange_facts: assessment.straight.then_some(assessment.facts),
        planning_time_s: start.elapsed().as_secs_f64(),
    })
}

impl Plan {
    /// The scene to run: `ls` with the plan's choices.
    pub fn apply(&self, ls: &LoadedScene) -> LoadedScene {
        let mut out = ls.clone();
        let s = &mut out.scene;
        s.contact.flange = self.flange;
        s.contact.method = self.method;
        if let Some(h) = self.step_m {
            s.track.step_m = h;
        }
        s.track.range_m = self.range_m;
        if s.track.straight_m.is_some() {
            s.track.straight_m = self.straight_m;
        }
        if let Some(c) = &self.integrator.choice {
            c.apply(&mut s.run);
        }
        out
    }

    /// The `off` flange search did not hold: search with `auto` (`why`
    /// says where the guard tripped).
    pub fn revise_flange(&mut self, why: &str) {
        self.flange = FlangeMode::Auto;
        self.flange_guard = None;
        self.revised = Some(format!("flange search off → auto: {why}"));
        if let Some(d) = self
            .decisions
            .iter_mut()
            .find(|d| d.item == "flange_search")
        {
            d.value = "auto".into();
            d.reason = format!("revised during the run ({why}); planned off: {}", d.reason);
        }
        if let Some(d) = self.decisions.iter_mut().find(|d| d.item == "integrator") {
            integrator::revise(&mut self.integrator, d);
        }
    }

    /// The block printed before the summary.
    pub fn to_text(&self) -> String {
        let mut s = format!(
            "plan (mode {}; planned in {:.3} s):\n",
            self.mode, self.planning_time_s
        );
        for d in &self.decisions {
            s += &format!(
                "  {:<15} {:<16} [{}] {}\n",
                d.item.replace('_', " "),
                d.value,
                d.by.name(),
                d.reason
            );
        }
        if let Some(r) = &self.revised {
            s += &format!("  revised: {r}\n");
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plan_sections_are_checked() {
        let ok = LoadedScene::default_scene(&[
            "plan.mode=required".into(),
            "plan.choose=[\"flange\", \"all\"]".into(),
        ])
        .expect("a valid [plan]");
        assert!(ok.scene.plan.chooses(PlanItem::Step));
        let ok = LoadedScene::default_scene(&[
            "plan.mode=required".into(),
            "plan.choose=[\"integrator\"]".into(),
        ])
        .expect("the integrator is a choose item");
        assert!(ok.scene.plan.chooses(PlanItem::Integrator));
        assert!(!ok.scene.plan.chooses(PlanItem::Step));
        for (mode, choose, what) in [
            ("sometimes", "[]", "sometimes"),
            ("required", "[\"creep_law\"]", "creep_law"),
            ("scene", "[\"flange\"]", "choose"),
        ] {
            let e = LoadedScene::default_scene(&[
                format!("plan.mode={mode}"),
                format!("plan.choose={choose}"),
            ])
            .unwrap_err();
            assert!(format!("{e:#}").contains(what), "{e:#}");
        }
    }
}
