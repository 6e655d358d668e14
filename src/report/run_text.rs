//! The text form of a run's summary (what `sim run` prints).

use crate::run::RunSummary;

impl RunSummary {
    /// Human-readable summary.
    pub fn to_text(&self) -> String {
        let mut s = format!(
            "{}\n  {} → {}\n  creep law {}, contact {}, integrator {}, {} m/s\n  simulated {:.3} s in {:.3} s wall (real-time factor {:.2}; setup {:.2} s)\n  {} steps ({} rejected), {} evaluations{}, {} contact solves ({:.2} Newton iterations each, {} cold starts)\n",
            self.title,
            self.scene,
            self.output,
            self.creep_law,
            self.contact_method,
            self.integrator,
            self.speed_m_s,
            self.simulated_time_s,
            self.wall_time_s,
            self.real_time_factor,
            self.setup_time_s,
            self.steps,
            self.rejected_steps,
            self.rhs_evaluations,
            if self.jacobians > 0 {
                format!(" ({} Jacobians)", self.jacobians)
            } else {
                String::new()
            },
            self.contact_solves,
            self.mean_newton_iterations,
            self.cold_starts
        );
        if !self.formulation.is_empty() {
            s += &format!(
                "  formulation (published switches): {}\n",
                self.formulation.join(", ")
            );
        }
        s += &format!(
            "  {} samples in the results{}\n",
            self.output_samples,
            self.peak_memory_mib
                .map_or(String::new(), |m| format!("; peak memory {m:.0} MiB")),
        );
        if let Some(c) = self.cpu_time_s {
            s += &format!("  process CPU time {c:.3} s (setup, run, results file and plots)\n");
        }
        if self.summary_stride > 1 {
            s += &format!(
                "  the figures below and the plots are from every {}-th of the {} samples (memory bound; the results file holds them all)\n",
                self.summary_stride, self.output_samples
            );
        }
        for w in &self.wheelsets {
            s += &format!(
                "  wheelset {}: peak lateral {:.2} mm (final {:+.2} mm); travelled left {:.3} m, right {:.3} m; flange contact {:.2} s / {:.2} s ({} events)\n",
                w.name,
                w.peak_lateral_mm,
                w.final_lateral_mm,
                w.travelled_left_m,
                w.travelled_right_m,
                w.flange_contact_left_s,
                w.flange_contact_right_s,
                w.flange_contact_events
            );
        }
        if let Some(e) = &self.energy {
            s += &format!(
                "  energy: {:.1} J → {:.1} J; axle torque work {:.1} J, reference work {:.1} J, element turning {:.3} J, contact normal work {:.1} J, creep dissipation {:.1} J, contact damping {:.1} J, dampers {:.1} J; residual {:.3} J\n",
                e.initial_j,
                e.final_j,
                e.axle_torque_work_j,
                e.reference_work_j,
                e.element_turning_work_j,
                e.contact_normal_work_j,
                e.creep_dissipation_j,
                e.contact_damping_dissipation_j,
                e.damper_dissipation_j,
                e.residual_j
            );
        }
        for w in &self.wheelsets {
            s += &crate::run::nadal::nadal_text(&w.name, &w.nadal);
        }
        for w in &self.wheelsets {
            s += &crate::run::curving::text::safety_text(&w.name, &w.safety);
        }
        s += &crate::run::curving::text::curving_text(&self.curving);
        s += &self.fallbacks.to_text();
        if let Some(st) = &self.stopped {
            s += &format!("  stopped early: {st}\n");
        }
        if let Some(r) = &self.plan.revised {
            s += &format!("  plan revised: {r}\n");
        }
        for p in &self.plots {
            s += &format!("  plot {p}\n");
        }
        s += &format!(
            "  track {} ({})\n",
            self.track.path,
            if self.track.built {
                format!("built in {:.2} s", self.track.build_time_s)
            } else {
                "cached".into()
            }
        );
        for w in &self.warnings {
            s += &format!("  WARNING ({}): {}\n", w.short(), w.message);
        }
        s
    }
}
