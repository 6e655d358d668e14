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

pub mod diagnostics;
pub mod summary;

pub use summary::{EnergySummary, RunSummary, WheelsetSummary};

use crate::session::Session;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use summary::wheelset_summaries;

use anyhow::{Context, Result, anyhow};
use runtime::integrators::{IntegrationStats, OutputGrid, integrate};
use runtime::multibody::Recorder;
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
    run_scene_with_plan(scene, plan, progress, stop)
}

/// Runs a scene with the decisions of [`crate::session::plan::plan`]; a run
/// whose flange guard trips is repeated with the flange searched (`auto`).
pub fn run_scene_with_plan(
    scene: &LoadedScene,
    mut plan: crate::session::plan::Plan,
    progress: &mut dyn FnMut(RunProgress),
    stop: Option<Arc<AtomicBool>>,
) -> Result<RunOutcome> {
    loop {
        let session = Session::assemble(scene, plan.clone())?;
        match run_session(&session, progress, stop.clone())? {
            Attempt::Done(outcome) => return Ok(*outcome),
            Attempt::Revise(why) => plan.revise_flange(&why),
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
            Ok(())
        },
    );
    let wall_time_s = start.elapsed().as_secs_f64();
    let diagnostic = outcome.as_ref().err().map(|e| watched.diagnose(e));
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
    let energy = system.energy_ledger().map(EnergySummary::from);
    drop(system);
    let (stats, error) = match outcome {
        Ok(s) => (Some(s), None),
        Err(e) => (None, Some(anyhow!(e))),
    };
    let simulated_time_s = recorder.results.time_s.last().copied().unwrap_or(0.0);
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
        ("title".into(), scene.title.clone()),
        ("scene".into(), ls.origin.clone()),
        ("vehicle".into(), session.vehicle_file.name.clone()),
        ("creep_law".into(), scene.contact.creep_law.to_string()),
        ("contact_method".into(), scene.contact.method.to_string()),
        ("flange_search".into(), scene.contact.flange.to_string()),
        ("integrator".into(), scene.run.integrator.to_string()),
        ("speed_m_s".into(), format!("{}", scene.initial.speed_m_s)),
        ("track".into(), session.track_source.path.clone()),
        ("plan".into(), plan.to_text()),
        (
            "plan_json".into(),
            serde_json::to_string(plan).context("the plan as JSON")?,
        ),
        (
            "status".into(),
            match (&error, &stopped) {
                (Some(e), _) => format!("failed: {e}"),
                // Ctrl-C: the file holds a partial run, and says so first.
                (None, Some(s)) if s == INTERRUPTED => INTERRUPTED.to_string(),
                (None, Some(s)) => format!("stopped: {s}"),
                (None, None) => "completed".into(),
            },
        ),
    ];
    let fallbacks = crate::run::diagnostics::FallbackCounts::count(
        stats_solvers.minimisations,
        hertz_floor_evaluations,
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
        output_samples: results.len(),
        contact_solves: stats_solvers.solves,
        mean_newton_iterations: if stats_solvers.solves > 0 {
            stats_solvers.iterations as f64 / stats_solvers.solves as f64
        } else {
            0.0
        },
        cold_starts: stats_solvers.cold_starts,
        flange_searches_skipped: stats_solvers.flange_skipped + stats_solvers.clear_skipped,
        flange_contact_states: counters.flange_contact_states,
        wheelsets: wheelset_summaries(&results),
        fallbacks,
        energy,
        stopped,
        error: error.as_ref().map(crate::error_text::chain_text),
        track: session.track_source.clone(),
        plan: plan.clone(),
        warnings: session.warnings.clone(),
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
