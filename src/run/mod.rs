//! A run: a scene (with its plan) integrated in time to results in memory
//! and a summary (docs/reference/08-multibody.md §8); the caller writes them
//! (the report layer). The track tables (and, with
//! `method = "table"`, the contact lookup tables) are built on demand and
//! cached ([`crate::session::cache`]); the vehicle file becomes a
//! `runtime::multibody::VehicleModel`; the system is integrated with the scene's method while
//! outputs are sampled at the scene's interval. Ctrl-C (a stop flag) ends
//! the run at the next accepted step with the results so far, as does a
//! failure (derailment, a contact that cannot be solved): the error is
//! kept in [`RunOutcome::failure`] so that the results can be written first.

pub mod blow_up;
pub mod curving;
pub mod diagnostics;
pub mod nadal;
pub mod stream;
pub mod summary;
pub mod warnings;

pub use summary::{EnergySummary, RunSummary, WheelsetSummary};

use crate::session::Session;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use summary::wheelset_summaries;

use anyhow::{Context, Result, anyhow};
use runtime::integrators::{IntegrationStats, IntegratorError, OutputGrid, integrate};
use runtime::multibody::{DynamicsError, Recorder};
use runtime::results::RunResults;

use crate::config::scene::LoadedScene;

/// Why a run stopped when the user interrupted it (Ctrl-C, SIGINT): the
/// summary's `stopped` and the results file's `status`.
pub const INTERRUPTED: &str = "interrupted";

/// Progress of a run, for the CLI's bar.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunProgress {
    /// Simulated time reached and to reach (s).
    pub simulated_s: f64,
    pub total_s: f64,
    /// Wall time of the integration so far (s).
    pub wall_s: f64,
}

/// A run that ended, in memory: what the caller writes (the results file,
/// plots) or uses directly (a study). Nothing is written by the run.
#[derive(Debug)]
pub struct RunOutcome {
    /// The sampled time series with the run's attributes and scene text.
    pub results: RunResults,
    /// The figures of the run; `output` and `plots` are filled by whoever
    /// writes them.
    pub summary: RunSummary,
    /// Why the run ended early with an error (derailment, a contact that
    /// cannot be solved), if it did; the results hold the samples so far.
    pub failure: Option<RunFailure>,
}

/// The error that ended a run early.
#[derive(Debug)]
pub struct RunFailure {
    /// Simulated time of the last sample (s).
    pub at_s: f64,
    /// The diagnostic's headline (time, wheelset, wheel, zone), if any.
    pub headline: Option<String>,
    pub error: anyhow::Error,
}

impl RunOutcome {
    /// The summary, or the failure as an error that says where the
    /// samples so far were written (`written_to`, e.g. the results file).
    pub fn into_result(self, written_to: &str) -> Result<RunSummary> {
        self.into_parts(written_to).1
    }

    /// The results, and the summary or the failure ([`Self::into_result`]).
    pub fn into_parts(self, written_to: &str) -> (RunResults, Result<RunSummary>) {
        let summary = match self.failure {
            Some(f) => Err(f.error.context(format!(
                "the run failed at t = {:.4} s{}; the results so far are in {written_to}",
                f.at_s,
                f.headline.map_or(String::new(), |h| format!(" ({h})")),
            ))),
            None => Ok(self.summary),
        };
        (self.results, summary)
    }
}

/// Plans and runs a scene (module docs). `progress` is called every few
/// hundred accepted steps; `stop` ends the run cleanly when set.
pub fn run_scene(
    scene: &LoadedScene,
    progress: &mut dyn FnMut(RunProgress),
    stop: Option<Arc<AtomicBool>>,
) -> Result<RunOutcome> {
    let plan = crate::session::plan::plan(scene).context("planning the run")?;
    run_scene_with_plan(scene, plan, progress, stop, None)
}

/// Runs a scene with the decisions of [`crate::session::plan::plan`]; a run
/// whose flange guard trips is repeated with the flange searched (`auto`).
/// With a `sink` the samples go to it while the run goes on
/// ([`stream`]) and the outcome's results are the bounded view of them;
/// without, every sample stays in memory (the studies).
pub fn run_scene_with_plan(
    scene: &LoadedScene,
    mut plan: crate::session::plan::Plan,
    progress: &mut dyn FnMut(RunProgress),
    stop: Option<Arc<AtomicBool>>,
    sink: Option<&mut dyn runtime::results::ResultsSink>,
) -> Result<RunOutcome> {
    let mut stream = sink.map(stream::Stream::new);
    loop {
        let session = Session::assemble(scene, plan.clone())?;
        match run_session(&session, progress, stop.clone(), stream.as_mut())? {
            Attempt::Done(outcome) => return Ok(*outcome),
            Attempt::Revise(why) => {
                if let Some(s) = stream.as_mut() {
                    s.restart().context("restarting the results file")?;
                }
                plan.revise_flange(&why)
            }
        }
    }
}

/// One run of a plan.
enum Attempt {
    Done(Box<RunOutcome>),
    /// The flange guard tripped (where, and the time lost).
    Revise(String),
}

/// One run of an assembled session; `Revise` when its flange guard trips.
fn run_session(
    session: &Session,
    progress: &mut dyn FnMut(RunProgress),
    stop: Option<Arc<AtomicBool>>,
    mut stream: Option<&mut stream::Stream<'_>>,
) -> Result<Attempt> {
    let setup_start = Instant::now();
    let ls = &session.scene;
    let scene = &ls.scene;
    let plan = &session.plan;
    let integrator = session.method;
    let (mut system, y0) = session.system()?;
    // With a flange guard the system stops on its own flag, set by the
    // guard or by the caller's (checked at every accepted step).
    let guard = plan.flange_guard;
    let guard_flag = Arc::new(AtomicBool::new(false));
    match (stop.clone(), guard) {
        (Some(flag), None) => system.set_stop_flag(flag),
        (None, None) => {}
        (_, Some(_)) => system.set_stop_flag(guard_flag.clone()),
    }
    system.enable_energy_ledger();
    let total_s = scene.duration_s();
    let setup_time_s = session.setup_time_s + setup_start.elapsed().as_secs_f64();
    let start = Instant::now();
    let mut accepted = 0u64;
    {
        let progress_ref = &mut *progress;
        let (user_stop, guard_flag) =
            (stop.clone().filter(|_| guard.is_some()), guard_flag.clone());
        system.set_progress(Box::new(move |t| {
            accepted += 1;
            if let Some(u) = &user_stop
                && u.load(std::sync::atomic::Ordering::Relaxed)
            {
                guard_flag.store(true, std::sync::atomic::Ordering::Relaxed);
            }
            if accepted % 256 == 0 {
                progress_ref(RunProgress {
                    simulated_s: t,
                    total_s,
                    wall_s: start.elapsed().as_secs_f64(),
                });
            }
        }));
    }
    let mut recorder = Recorder::new(&system);
    // The samples of the run (or of its first chunk), reserved at once.
    let expected_samples = (total_s / scene.run.output_interval_s).ceil() + 2.0;
    if expected_samples.is_finite() && expected_samples > 0.0 {
        recorder
            .results
            .reserve((expected_samples as usize).min(stream::FLUSH_SAMPLES));
    }
    let mut tripped: Option<String> = None;
    // Remembers the state of each evaluation for the diagnostic of a failure.
    let mut watched = crate::run::diagnostics::Watched::new(&mut system);
    let outcome = integrate(
        &integrator,
        &mut watched,
        0.0,
        &y0,
        total_s,
        &OutputGrid {
            interval_s: scene.run.output_interval_s,
        },
        &mut |sys, t, y| {
            sys.note(t, y);
            recorder.record(sys, t, y)?;
            if let Some(g) = guard
                && tripped.is_none()
            {
                tripped = crate::session::plan::guard_check(&g, &recorder.results, t);
                if tripped.is_some() {
                    guard_flag.store(true, std::sync::atomic::Ordering::Relaxed);
                }
            }
            if let Some(s) = stream.as_mut() {
                s.flush(&mut recorder.results, stream::FLUSH_SAMPLES, t)?;
            }
            Ok(())
        },
    );
    let wall_time_s = start.elapsed().as_secs_f64();
    let energy = watched.energy_ledger().map(EnergySummary::from);
    // The flange search off with online contact: nothing stops a flange
    // from passing through its rail.
    let flange_off = plan.flange == crate::config::scene::FlangeMode::Off
        && plan.method == crate::config::scene::ContactMethodKind::Online;
    let diagnostic = outcome.as_ref().err().map(|e| {
        watched.diagnose(
            e,
            &crate::run::diagnostics::DiagnoseContext {
                method: &integrator,
                references: crate::run::diagnostics::wheelset_references(
                    &watched,
                    &recorder.results,
                ),
                energy: energy.clone(),
                flange_off,
            },
        )
    });
    let hertz_floor_evaluations = watched.hertz_floor_evaluations();
    if let Some(why) = tripped {
        return Ok(Attempt::Revise(format!(
            "{why}; the first attempt took {wall_time_s:.2} s of integration"
        )));
    }
    let counters = system.counters();
    let stats_solvers =
        system
            .solvers()
            .iter()
            .fold(runtime::contact::SolverStats::default(), |mut a, s| {
                a.solves += s.stats.solves;
                a.iterations += s.stats.iterations;
                a.cold_starts += s.stats.cold_starts;
                a.flange_skipped += s.stats.flange_skipped;
                a.clear_skipped += s.stats.clear_skipped;
                a.minimisations += s.stats.minimisations;
                a
            });
    let track_end_reached = system.track_end_reached();
    // The last samples to the sink, and the view of all of them in place
    // of the recorder's record.
    let mut simulated_time_s = recorder.results.time_s.last().copied().unwrap_or(0.0);
    let (mut output_samples, mut summary_stride) = (recorder.results.len(), 1);
    if let Some(s) = stream.as_mut() {
        s.flush(&mut recorder.results, 1, simulated_time_s)
            .context("writing the last samples")?;
        output_samples = s.samples();
        simulated_time_s = s.last_time_s();
        summary_stride = s.view_into(&mut recorder.results);
    }
    let wheelsets = wheelset_summaries(&recorder.results);
    let curving = curving::CurvingSummary::of(&session.track, &recorder.results);
    // What the inputs dropped (a profile cut to its longest stretch).
    let mut warnings: Vec<_> = session
        .warnings
        .iter()
        .map(|m| crate::run::warnings::RunWarning::input(m.clone()))
        .collect();
    if flange_off {
        warnings.extend(flange_warnings(
            &system,
            &recorder.results,
            plan,
            &wheelsets,
        ));
    }
    drop(system);
    for w in &wheelsets {
        warnings.extend(crate::run::warnings::airborne(
            &w.name,
            &w.nadal,
            scene.initial.speed_m_s,
        ));
    }
    // A failed run's balance is the diagnostic's (a sign of a blow-up).
    if outcome.is_ok()
        && let Some(w) = energy
            .as_ref()
            .and_then(|e| crate::run::warnings::energy_residual(e, &integrator))
    {
        warnings.push(w);
    }
    let (stats, error) = match outcome {
        Ok(s) => (Some(s), None),
        // A blow-up's own words (or a flange run through): the runtime's
        // error would call the |y| it reached a derailment.
        Err(IntegratorError::System(DynamicsError::Derailed {
            wheelset,
            t_s,
            lateral_mm,
            limit_mm,
        })) if diagnostic.as_ref().is_some_and(|d| d.is_not_a_derailment()) => (
            None,
            Some(anyhow!(
                "{} at t = {t_s:.6} s: wheelset '{wheelset}' reached |y| = {:.1} mm, beyond the {limit_mm:.1} mm of the derailment check",
                diagnostic.as_ref().map_or("", |d| d.kind.as_str()),
                lateral_mm.abs()
            )),
        ),
        Err(e) => (None, Some(anyhow!(e))),
    };
    let stopped = match &stats {
        Some(IntegrationStats { stopped: true, .. }) => {
            if stop
                .as_ref()
                .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
            {
                Some(INTERRUPTED.to_string())
            } else if track_end_reached {
                Some("end of track".to_string())
            } else {
                Some("stopped".to_string())
            }
        }
        _ => None,
    };
    let mut results = recorder.results;
    results.scene_toml = ls.text.clone();
    results.attributes = vec![
        ("title".into(), scene.title.clone().into()),
        ("scene".into(), ls.origin.clone().into()),
        ("vehicle".into(), session.vehicle_file.name.clone().into()),
        (
            "creep_law".into(),
            scene.contact.creep_law.to_string().into(),
        ),
        (
            "contact_method".into(),
            scene.contact.method.to_string().into(),
        ),
        (
            "flange_search".into(),
            scene.contact.flange.to_string().into(),
        ),
        ("integrator".into(), scene.run.integrator.to_string().into()),
        ("formulation".into(), {
            let switches = scene.formulation.describe();
            if switches.is_empty() {
                "ours".to_string()
            } else {
                switches.join("; ")
            }
            .into()
        }),
        ("speed_m_s".into(), scene.initial.speed_m_s.into()),
        ("track".into(), session.track_source.path.clone().into()),
        ("plan".into(), plan.to_text().into()),
        (
            "plan_json".into(),
            serde_json::to_string(plan)
                .context("the plan as JSON")?
                .into(),
        ),
        (
            "status".into(),
            match (&error, &stopped) {
                (Some(e), _) => match diagnostic.as_ref().and_then(|d| d.likely_cause.as_ref()) {
                    Some(c) => format!("failed: {e} (likely cause: {c})"),
                    None => format!("failed: {e}"),
                },
                // Ctrl-C: the file holds a partial run, and says so first.
                (None, Some(s)) if s == INTERRUPTED => INTERRUPTED.to_string(),
                (None, Some(s)) => format!("stopped: {s}"),
                (None, None) => crate::run::warnings::completed_status(&warnings),
            }
            .into(),
        ),
        (
            "warnings".into(),
            crate::run::warnings::warnings_attribute(&warnings).into(),
        ),
    ];
    let fallbacks = crate::run::diagnostics::FallbackCounts::count(
        stats_solvers.minimisations,
        hertz_floor_evaluations,
        stats.as_ref().map_or(0, |s| s.dense_lu_fallbacks),
        &results,
    );
    results
        .attributes
        .extend(crate::run::diagnostics::run_attributes(
            stats.as_ref(),
            counters.accepted,
            counters.evaluations,
            stats_solvers.solves,
            &fallbacks,
            diagnostic.as_ref(),
        ));
    let summary = RunSummary {
        scene: ls.origin.clone(),
        title: scene.title.clone(),
        output: String::new(),
        plots: Vec::new(),
        creep_law: scene.contact.creep_law,
        contact_method: scene.contact.method,
        formulation: scene.formulation.describe(),
        integrator: scene.run.integrator,
        speed_m_s: scene.initial.speed_m_s,
        simulated_time_s,
        wall_time_s,
        real_time_factor: if wall_time_s > 0.0 {
            simulated_time_s / wall_time_s
        } else {
            f64::INFINITY
        },
        setup_time_s,
        steps: stats.map_or(counters.accepted, |s| s.steps),
        rejected_steps: stats.map_or(0, |s| s.rejected),
        rhs_evaluations: counters.evaluations,
        jacobians: stats.map_or(0, |s| s.jacobian_evaluations),
        output_samples,
        summary_stride,
        peak_memory_mib: None,
        cpu_time_s: None,
        contact_solves: stats_solvers.solves,
        mean_newton_iterations: if stats_solvers.solves > 0 {
            stats_solvers.iterations as f64 / stats_solvers.solves as f64
        } else {
            0.0
        },
        cold_starts: stats_solvers.cold_starts,
        flange_searches_skipped: stats_solvers.flange_skipped + stats_solvers.clear_skipped,
        flange_contact_states: counters.flange_contact_states,
        wheelsets,
        curving,
        fallbacks,
        energy,
        stopped,
        warnings,
        error: error.as_ref().map(crate::error_text::chain_text),
        track: session.track_source.clone(),
        plan: plan.clone(),
    };
    let failure = error.map(|e| RunFailure {
        at_s: simulated_time_s,
        headline: diagnostic.as_ref().map(|d| d.headline()),
        error: e,
    });
    Ok(Attempt::Done(Box::new(RunOutcome {
        results,
        summary,
        failure,
    })))
}

/// The flange warnings of a run with the flange search off
/// ([`warnings::flange_passage`]). The clearances are measured only when a
/// wheelset went beyond the smallest clearance the planner knows (or when
/// it knows none).
fn flange_warnings(
    system: &runtime::multibody::VehicleSystem<'_>,
    results: &RunResults,
    plan: &crate::session::plan::Plan,
    wheelsets: &[WheelsetSummary],
) -> Vec<warnings::RunWarning> {
    let known = plan
        .flange_facts
        .map(|f| f.clearance_m)
        .filter(|c| c.is_finite());
    if known.is_some_and(|c| wheelsets.iter().all(|w| w.peak_lateral_mm * 1e-3 <= c)) {
        return Vec::new();
    }
    match warnings::clearances(system) {
        Ok(c) => warnings::flange_passage(results, &c),
        Err(why) => vec![warnings::check_failed(
            "the flange passage (flange search off)",
            &why,
        )],
    }
}
