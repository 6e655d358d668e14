//! What a run reports: per-wheelset figures, the energy bookkeeping and the
//! run's counters ([`RunSummary`]), and its text form.

use crate::config::scene::{ContactMethodKind, CreepLawName, IntegratorKind};
use crate::session::track::TrackSource;

use runtime::multibody::EnergyLedger;
use runtime::results::RunResults;
use serde::Serialize;

/// Per-wheelset figures of a run.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelsetSummary {
    pub name: String,
    /// Largest |lateral displacement| from the centreline (mm).
    pub peak_lateral_mm: f64,
    /// Lateral displacement at the end (mm).
    pub final_lateral_mm: f64,
    /// Distance travelled by the left and right wheels along their rails (m).
    pub travelled_left_m: f64,
    pub travelled_right_m: f64,
    /// Time with flange contact (s), left and right (from the samples).
    pub flange_contact_left_s: f64,
    pub flange_contact_right_s: f64,
    /// Number of separate flange contacts (onsets in the samples).
    pub flange_contact_events: u64,
    /// Nadal's criterion per wheel, left then right, with the fraction of
    /// samples each wheel was airborne ([`crate::run::nadal`]).
    pub nadal: Vec<crate::run::nadal::WheelNadal>,
    /// ΣY against Prud'homme, ΔQ/Q0, angle of attack and Tγ
    /// ([`crate::run::curving::safety`]).
    pub safety: crate::run::curving::WheelsetSafety,
}

/// The energy bookkeeping of a run (J;
/// `runtime::multibody::EnergyLedger`): E − E0 = axle torque work +
/// reference work + element turning work + contact normal work − creep,
/// contact damping and damper dissipation, up to `residual_j`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct EnergySummary {
    /// Mechanical energy (kinetic, gravity, springs, Hertz) at the start and
    /// the end (J).
    pub initial_j: f64,
    pub final_j: f64,
    pub axle_torque_work_j: f64,
    pub reference_work_j: f64,
    pub creep_dissipation_j: f64,
    pub contact_damping_dissipation_j: f64,
    pub damper_dissipation_j: f64,
    /// Work of the spring–dampers beyond their potential: their directions
    /// turn with their first body (J).
    pub element_turning_work_j: f64,
    /// Work of the contacts' elastic normal forces beyond their elastic
    /// energy 0.4 K δ^2.5 (J): not zero where the normal force is not the
    /// gradient of that energy (docs/reference/08-multibody.md §8.6).
    pub contact_normal_work_j: f64,
    /// What the balance leaves unexplained (J).
    pub residual_j: f64,
}

impl From<&EnergyLedger> for EnergySummary {
    fn from(l: &EnergyLedger) -> Self {
        EnergySummary {
            initial_j: l.initial_energy_j,
            final_j: l.energy_j,
            axle_torque_work_j: l.axle_torque_work_j,
            reference_work_j: l.reference_work_j,
            creep_dissipation_j: l.creep_dissipation_j,
            contact_damping_dissipation_j: l.contact_damping_dissipation_j,
            damper_dissipation_j: l.damper_dissipation_j,
            element_turning_work_j: l.element_turning_work_j,
            contact_normal_work_j: l.contact_normal_work_j,
            residual_j: l.residual_j(),
        }
    }
}

/// The `--json` summary of a run.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RunSummary {
    pub scene: String,
    pub title: String,
    pub output: String,
    pub plots: Vec<String>,
    pub creep_law: CreepLawName,
    pub contact_method: ContactMethodKind,
    /// The `[formulation]` switches that are not ours (`key = value`;
    /// empty: ours).
    pub formulation: Vec<String>,
    pub integrator: IntegratorKind,
    pub speed_m_s: f64,
    /// Simulated time (s), the wall time of the integration (s) and their
    /// ratio (> 1: faster than real time).
    pub simulated_time_s: f64,
    pub wall_time_s: f64,
    pub real_time_factor: f64,
    /// Wall time before the integration: tables, vehicle, settling (s).
    pub setup_time_s: f64,
    pub steps: u64,
    pub rejected_steps: u64,
    pub rhs_evaluations: u64,
    /// Finite-difference Jacobians of the stiff integrator (`rosenbrock`;
    /// 0 for the explicit methods), part of `rhs_evaluations`.
    pub jacobians: u64,
    /// Samples in the results (the file holds them all).
    pub output_samples: usize,
    /// The summary's figures and the plots come from every
    /// `summary_stride`-th sample (1: all; more for a run longer than
    /// `crate::run::stream::VIEW_MAX_SAMPLES` samples, whose memory is
    /// bounded that way).
    pub summary_stride: usize,
    /// Peak resident memory of the process when the outputs were written
    /// (MiB; Linux `VmHWM`), `None` where the system does not say.
    pub peak_memory_mib: Option<f64>,
    /// CPU time of the process, user plus system, when the outputs were
    /// written (s; `getrusage`, every thread): setup, run, results file
    /// and plots. `None` where the system does not say.
    pub cpu_time_s: Option<f64>,
    pub contact_solves: u64,
    pub mean_newton_iterations: f64,
    pub cold_starts: u64,
    /// Flange pieces not searched (auto rule or off) and clear pieces not
    /// searched again.
    pub flange_searches_skipped: u64,
    /// Accepted states with a flange in contact, summed over the wheels.
    pub flange_contact_states: u64,
    pub wheelsets: Vec<WheelsetSummary>,
    /// The track's elements and the quasi-static values over its arcs
    /// ([`crate::run::curving`]).
    pub curving: crate::run::curving::CurvingSummary,
    /// Fallbacks the run went through ([`crate::run::diagnostics`]).
    pub fallbacks: crate::run::diagnostics::FallbackCounts,
    /// Energy bookkeeping between the first and the last accepted state.
    pub energy: Option<EnergySummary>,
    /// Why the run ended before its end time: "interrupted" (Ctrl-C),
    /// "end of track"; `None` when it completed.
    pub stopped: Option<String>,
    /// What the inputs dropped ([`crate::session::Session::warnings`]) and
    /// what the results show to be doubtful ([`crate::run::warnings`]);
    /// also in the results' `status` and `warnings` attributes.
    pub warnings: Vec<crate::run::warnings::RunWarning>,
    /// The error that ended the run, if any (the results so far are written).
    pub error: Option<String>,
    pub track: TrackSource,
    /// What the planner decided ([`crate::session::plan`]).
    pub plan: crate::session::plan::Plan,
}

pub(crate) fn wheelset_summaries(r: &RunResults) -> Vec<WheelsetSummary> {
    let dt = |i: usize| -> f64 {
        if i + 1 < r.time_s.len() {
            r.time_s[i + 1] - r.time_s[i]
        } else {
            0.0
        }
    };
    r.wheelsets
        .iter()
        .map(|w| {
            let peak =
                w.lateral_m.iter().fold(
                    0.0_f64,
                    |m, v| if v.is_finite() { m.max(v.abs()) } else { m },
                );
            let time_in = |flags: &[u8]| -> f64 {
                // 0.0 + …: an empty f64 sum is −0.0.
                0.0 + flags
                    .iter()
                    .enumerate()
                    .filter(|(_, f)| **f == 1)
                    .map(|(i, _)| dt(i))
                    .sum::<f64>()
            };
            let events = w
                .wheels
                .iter()
                .map(|wh| {
                    wh.flange_contact
                        .windows(2)
                        .filter(|p| p[0] == 0 && p[1] == 1)
                        .count() as u64
                        + u64::from(wh.flange_contact.first() == Some(&1))
                })
                .sum();
            WheelsetSummary {
                name: w.name.clone(),
                peak_lateral_mm: peak * 1e3,
                final_lateral_mm: w.lateral_m.last().copied().unwrap_or(f64::NAN) * 1e3,
                travelled_left_m: w.wheels[0].travelled_m.last().copied().unwrap_or(0.0),
                travelled_right_m: w.wheels[1].travelled_m.last().copied().unwrap_or(0.0),
                flange_contact_left_s: time_in(&w.wheels[0].flange_contact),
                flange_contact_right_s: time_in(&w.wheels[1].flange_contact),
                flange_contact_events: events,
                nadal: crate::run::nadal::nadal_summary(w, &r.time_s),
                safety: crate::run::curving::safety::wheelset_safety(w),
            }
        })
        .collect()
}
