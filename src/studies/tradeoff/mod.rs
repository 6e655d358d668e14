//! `sim tradeoff`: what the knobs a user can turn buy in speed and cost in
//! accuracy. The same scene is run with each knob turned on its own — table
//! step, contact method, flange search, integrator step or tolerance, creep
//! law, spline scheme — and in a few combinations, against a **reference
//! run** ([`REFERENCE_OVERRIDES`]: table step 0.01 m, online contact with
//! the flange always searched, RK4 at 0.1 ms). Every variant is the scene
//! with the reference's overrides and then its own (so the one-knob
//! variants differ from the reference in that knob only); the variant
//! "scene as given" restores the scene's own settings.
//!
//! Per variant ([`VariantResult`]):
//!
//! - wall time: the `wall_time_s` of [`run_scene`] (the integration, not the
//!   set-up: tables, vehicle, settling), median, min and max of `repeats`
//!   runs; the real-time factor is the simulated time over the median;
//! - errors against the reference ([`compare`]): max and RMS of the leading
//!   wheelset's lateral displacement, interpolated linearly onto the
//!   reference's time grid (every variant samples at the scene's
//!   `output_interval_s`, so the grids coincide); the hunting frequency
//!   from the zero crossings of that displacement ([`hunting_frequency_hz`]);
//!   the growth rate of its peaks ([`crate::studies::critical_speed::growth_rate`]);
//!   the peaks over all wheels of the total lateral contact force |Y| and of
//!   the total normal force (tread + flange). The growth rate and the peaks
//!   skip the first 20 % of the run: the start is the same assembled state
//!   in every variant, and its transient would hide the differences;
//! - the paper's table-step rule (§2: the table step should not exceed the
//!   distance covered in one integrator step): the ratio
//!   `track.step_m / (V · Δt)`, Δt the RK4 step or DOPRI5's mean accepted
//!   step. The variants "table step × rk4 1 ms" and [`RuleRow`] measure the
//!   table step's own error at two integrator steps (against the run with
//!   the same integrator and the finest table);
//! - optionally the time-domain critical speed
//!   ([`crate::studies::critical_speed::time_domain`]) of the variant's settings and
//!   its error against the reference's (expensive: one bracketing search
//!   per variant).
//!
//! A variant that fails (an unstable step, a contact that cannot be solved)
//! is reported with its error. The Pareto front is taken over (median wall
//! time, max lateral error). Outputs: `tradeoff.csv`, `tradeoff.md`,
//! `pareto.png` (and `tradeoff.json` on request), the results files in
//! `runs/`.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, Result, bail, ensure};
use runtime::results::RunResults;
use serde::Serialize;

use crate::config::Variation;
use crate::config::scene::IntegratorKind;
use crate::config::scene::LoadedScene;
use crate::run::run_scene;
use crate::studies::critical_speed::{CriticalSpeedSettings, time_domain};

mod measures;
mod variants;

pub use measures::*;
pub use variants::*;

/// Optional time-domain critical speed of every variant.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CriticalSpeedSpec {
    pub min_m_s: f64,
    pub max_m_s: f64,
    pub tol_m_s: f64,
    /// Run length of each speed (m).
    pub distance_m: f64,
    /// Start transient skipped by the growth-rate fit (s).
    pub skip_s: f64,
}

impl CriticalSpeedSpec {
    /// `MIN:MAX:TOL[:DISTANCE_M]` (m/s, m), e.g. `70:100:0.5:250`.
    pub fn parse(s: &str) -> Result<CriticalSpeedSpec> {
        let parts: Vec<f64> = s
            .split(':')
            .map(|p| {
                p.trim()
                    .parse::<f64>()
                    .with_context(|| format!("'{p}' is not a number"))
            })
            .collect::<Result<_>>()
            .with_context(|| format!("--critical-speed {s}: MIN:MAX:TOL[:DISTANCE_M]"))?;
        ensure!(
            (3..=4).contains(&parts.len()),
            "--critical-speed {s}: give MIN:MAX:TOL[:DISTANCE_M] (m/s, m/s, m/s, m)"
        );
        let spec = CriticalSpeedSpec {
            min_m_s: parts[0],
            max_m_s: parts[1],
            tol_m_s: parts[2],
            distance_m: parts.get(3).copied().unwrap_or(250.0),
            skip_s: 1.0,
        };
        ensure!(
            spec.distance_m.is_finite() && spec.distance_m > 0.0,
            "--critical-speed: distance {} m must be > 0",
            spec.distance_m
        );
        Ok(spec)
    }
}

/// Study settings.
#[derive(Debug, Clone, PartialEq)]
pub struct TradeoffSettings {
    /// Runs per variant (wall time: median).
    pub repeats: usize,
    pub quick: bool,
    pub out_dir: PathBuf,
    /// Variants added to the study (`--variant`).
    pub extra: Vec<Variant>,
    pub critical_speed: Option<CriticalSpeedSpec>,
    /// Parallel runs of the critical-speed searches (the variants themselves
    /// run one at a time, so that their wall times do not compete).
    pub jobs: usize,
}

/// Errors of a variant against the reference.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Errors {
    /// Leading wheelset's lateral displacement: max and RMS difference (m).
    pub lateral_max_m: f64,
    pub lateral_rms_m: f64,
    /// Span compared (s): the reference's samples within the variant's run.
    pub compared_s: f64,
    /// |f − f_ref| of the hunting frequency (Hz); `None` when either has too
    /// few zero crossings.
    pub frequency_hz: Option<f64>,
    /// |σ − σ_ref| of the growth rate (1/s); `None` when either has no fit.
    pub growth_rate_1_s: Option<f64>,
    /// |peak − peak_ref| of the peak total lateral force |Y| and of the peak
    /// total normal force (N).
    pub peak_lateral_force_n: f64,
    pub peak_normal_force_n: f64,
}

/// What a run measures by itself.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Measures {
    pub hunting_frequency_hz: Option<f64>,
    pub growth_rate_1_s: Option<f64>,
    /// Peaks over every wheel and the samples after the start transient (N).
    pub peak_lateral_force_n: f64,
    pub peak_normal_force_n: f64,
}

/// One row of the study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VariantResult {
    pub name: String,
    pub knob: String,
    pub value: String,
    pub overrides: Vec<String>,
    /// `ok`, `failed`, or `stopped: …` (e.g. end of track).
    pub status: String,
    pub error: Option<String>,
    pub wall_time_median_s: Option<f64>,
    pub wall_time_min_s: Option<f64>,
    pub wall_time_max_s: Option<f64>,
    pub setup_time_median_s: Option<f64>,
    pub simulated_time_s: Option<f64>,
    pub real_time_factor: Option<f64>,
    pub steps: Option<u64>,
    pub rejected_steps: Option<u64>,
    pub rhs_evaluations: Option<u64>,
    /// The table-step rule: table step, distance per integrator step (mean
    /// for DOPRI5) and their ratio (> 1 breaks the paper's rule).
    pub table_step_m: f64,
    pub distance_per_step_m: Option<f64>,
    pub table_step_ratio: Option<f64>,
    pub measures: Option<Measures>,
    pub errors: Option<Errors>,
    pub critical_speed_m_s: Option<f64>,
    pub critical_speed_error_m_s: Option<f64>,
    pub critical_speed_note: Option<String>,
    /// On the Pareto front of (median wall time, max lateral error).
    pub pareto: bool,
    /// Results file of the last repeat.
    pub results: Option<String>,
}

/// The table step's own error at one integrator step: the variant against
/// the run with the same integrator and the reference's table step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RuleRow {
    pub variant: String,
    pub partner: String,
    pub table_step_m: f64,
    pub distance_per_step_m: f64,
    pub ratio: f64,
    /// Max |Δy| of the leading wheelset against the partner (m).
    pub lateral_max_m: f64,
    /// The partner's own max lateral error against the reference (m).
    pub partner_error_m: f64,
}

/// Everything `sim tradeoff` reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TradeoffReport {
    pub scene: String,
    pub speed_m_s: f64,
    pub distance_m: Option<f64>,
    pub output_interval_s: f64,
    pub reference_overrides: Vec<String>,
    pub repeats: usize,
    pub quick: bool,
    /// Hardware threads of the machine (the runs are sequential).
    pub threads: usize,
    pub variants: Vec<VariantResult>,
    pub rule: Vec<RuleRow>,
    pub skipped: Vec<String>,
    pub total_wall_time_s: f64,
    pub files: Vec<String>,
}

/// Runs the study (module docs); `progress` gets one line per run.
pub fn run_tradeoff(
    scene: &LoadedScene,
    settings: &TradeoffSettings,
    progress: &mut dyn FnMut(&str),
    stop: Arc<AtomicBool>,
) -> Result<TradeoffReport> {
    ensure!(settings.repeats >= 1, "--repeats must be >= 1");
    let start = std::time::Instant::now();
    let (mut list, skipped) = variants(&scene.scene, settings.quick);
    for e in &settings.extra {
        ensure!(
            !list.iter().any(|v| v.name == e.name),
            "variant '{}' exists already",
            e.name
        );
        list.push(e.clone());
    }
    let runs_dir = settings.out_dir.join("runs");
    std::fs::create_dir_all(&runs_dir)
        .with_context(|| format!("creating {}", runs_dir.display()))?;
    let skip_s = 0.2 * scene.scene.duration_s();
    let mut rows: Vec<VariantResult> = Vec::new();
    let mut loaded: Vec<Option<RunResults>> = Vec::new();
    for v in &list {
        if stop.load(Ordering::Relaxed) {
            bail!("interrupted");
        }
        let (row, results) = run_variant(scene, v, settings, &runs_dir, progress, &stop)?;
        if v.name == REFERENCE && results.is_none() {
            bail!(
                "the reference run failed, nothing to compare with: {}",
                row.error.clone().unwrap_or_default()
            );
        }
        rows.push(row);
        loaded.push(results);
    }
    let reference = loaded[0]
        .clone()
        .context("the reference run has no results")?;
    for (row, r) in rows.iter_mut().zip(&loaded) {
        if let Some(r) = r {
            row.measures = Some(measures(r, skip_s));
            match compare(&reference, r, skip_s) {
                Ok(e) => row.errors = Some(e),
                Err(e) => {
                    row.status = "failed".into();
                    row.error = Some(format!(
                        "comparison with the reference: {}",
                        crate::error_text::chain_text(&e)
                    ));
                }
            }
        }
    }
    // The table-step rule: each variant with a fine-table partner.
    let mut rule = Vec::new();
    for (i, v) in list.iter().enumerate() {
        let Some(p) = &v.fine_table_partner else {
            continue;
        };
        let Some(j) = list.iter().position(|w| &w.name == p) else {
            continue;
        };
        if let (Some(a), Some(b), Some(d), Some(ratio)) = (
            &loaded[i],
            &loaded[j],
            rows[i].distance_per_step_m,
            rows[i].table_step_ratio,
        ) && let Ok((max, _, _)) = lateral_difference(b, a, 0)
        {
            rule.push(RuleRow {
                variant: v.name.clone(),
                partner: p.clone(),
                table_step_m: rows[i].table_step_m,
                distance_per_step_m: d,
                ratio,
                lateral_max_m: max,
                partner_error_m: rows[j].errors.map_or(f64::NAN, |e| e.lateral_max_m),
            });
        }
    }
    // Pareto front over (median wall time, max lateral error).
    let points: Vec<(f64, f64)> = rows
        .iter()
        .map(
            |r| match (r.wall_time_median_s, r.errors, r.status.as_str()) {
                (Some(w), Some(e), "ok") => (w, e.lateral_max_m),
                _ => (f64::NAN, f64::NAN),
            },
        )
        .collect();
    for (row, on) in rows.iter_mut().zip(pareto_front(&points)) {
        row.pareto = on;
    }
    if let Some(cs) = &settings.critical_speed {
        critical_speeds(scene, &list, &mut rows, cs, settings, progress, &stop)?;
    }
    Ok(TradeoffReport {
        scene: scene.origin.clone(),
        speed_m_s: scene.scene.initial.speed_m_s,
        distance_m: scene.scene.run.distance_m,
        output_interval_s: scene.scene.run.output_interval_s,
        reference_overrides: REFERENCE_OVERRIDES.iter().map(|s| s.to_string()).collect(),
        repeats: settings.repeats,
        quick: settings.quick,
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        variants: rows,
        rule,
        skipped,
        total_wall_time_s: start.elapsed().as_secs_f64(),
        files: Vec::new(),
    })
}

/// Runs one variant `repeats` times; the results of the last run.
fn run_variant(
    scene: &LoadedScene,
    v: &Variant,
    settings: &TradeoffSettings,
    runs_dir: &Path,
    progress: &mut dyn FnMut(&str),
    stop: &Arc<AtomicBool>,
) -> Result<(VariantResult, Option<RunResults>)> {
    let mut row = VariantResult {
        name: v.name.clone(),
        knob: v.knob.clone(),
        value: v.value.clone(),
        overrides: v.overrides.clone(),
        status: "ok".into(),
        error: None,
        wall_time_median_s: None,
        wall_time_min_s: None,
        wall_time_max_s: None,
        setup_time_median_s: None,
        simulated_time_s: None,
        real_time_factor: None,
        steps: None,
        rejected_steps: None,
        rhs_evaluations: None,
        table_step_m: scene.scene.track.step_m,
        distance_per_step_m: None,
        table_step_ratio: None,
        measures: None,
        errors: None,
        critical_speed_m_s: None,
        critical_speed_error_m_s: None,
        critical_speed_note: None,
        pareto: false,
        results: None,
    };
    let vs = match variant_scene(scene, v) {
        Ok(s) => s,
        Err(e) => {
            row.status = "failed".into();
            row.error = Some(crate::error_text::chain_text(&e));
            progress(&format!(
                "{}: failed: {}",
                v.name,
                crate::error_text::chain_text(&e)
            ));
            return Ok((row, None));
        }
    };
    row.table_step_m = vs.scene.track.step_m;
    let output = runs_dir.join(format!("{}.h5", v.slug()));
    let (mut walls, mut setups) = (Vec::new(), Vec::new());
    let mut last = None;
    for k in 0..settings.repeats {
        let ran = run_scene(&vs, &mut |_| {}, Some(stop.clone())).and_then(|outcome| {
            runtime::io::schema::write_results(&output, &outcome.results)
                .with_context(|| format!("writing {}", output.display()))?;
            let (results, summary) = outcome.into_parts(&output.display().to_string());
            summary.map(|s| (s, results))
        });
        match ran {
            Ok((s, results)) => {
                progress(&format!(
                    "{} ({}/{}): {:.3} s wall",
                    v.name,
                    k + 1,
                    settings.repeats,
                    s.wall_time_s
                ));
                walls.push(s.wall_time_s);
                setups.push(s.setup_time_s);
                last = Some((s, results));
            }
            Err(e) => {
                if stop.load(Ordering::Relaxed) {
                    bail!("interrupted");
                }
                row.status = "failed".into();
                row.error = Some(crate::error_text::chain_text(&e));
                progress(&format!(
                    "{}: failed: {}",
                    v.name,
                    crate::error_text::chain_text(&e)
                ));
                return Ok((row, None));
            }
        }
    }
    let (s, results) = last.context("no run")?;
    if let Some(st) = &s.stopped {
        if st == "interrupted" {
            bail!("interrupted");
        }
        row.status = format!("stopped: {st}");
    }
    let wall = median(&walls);
    row.wall_time_median_s = wall;
    row.wall_time_min_s = walls.iter().copied().reduce(f64::min);
    row.wall_time_max_s = walls.iter().copied().reduce(f64::max);
    row.setup_time_median_s = median(&setups);
    row.simulated_time_s = Some(s.simulated_time_s);
    row.real_time_factor = wall.filter(|w| *w > 0.0).map(|w| s.simulated_time_s / w);
    row.steps = Some(s.steps);
    row.rejected_steps = Some(s.rejected_steps);
    row.rhs_evaluations = Some(s.rhs_evaluations);
    let dt = match vs.scene.run.integrator {
        IntegratorKind::Rk4 => Some(vs.scene.run.step_s),
        _ => (s.steps > 0).then(|| s.simulated_time_s / s.steps as f64),
    };
    row.distance_per_step_m = dt.map(|dt| vs.scene.initial.speed_m_s * dt);
    row.table_step_ratio = row
        .distance_per_step_m
        .filter(|d| *d > 0.0)
        .map(|d| row.table_step_m / d);
    row.results = Some(output.display().to_string());
    Ok((row, Some(results)))
}

/// The time-domain critical speed of every variant that ran (module docs).
fn critical_speeds(
    scene: &LoadedScene,
    list: &[Variant],
    rows: &mut [VariantResult],
    cs: &CriticalSpeedSpec,
    settings: &TradeoffSettings,
    progress: &mut dyn FnMut(&str),
    stop: &Arc<AtomicBool>,
) -> Result<()> {
    let mut reference_speed = None;
    for (v, row) in list.iter().zip(rows.iter_mut()) {
        if row.status == "failed" {
            continue;
        }
        if stop.load(Ordering::Relaxed) {
            bail!("interrupted");
        }
        let mut vs = variant_scene(scene, v)?;
        let mut o = vec![Variation::Distance(cs.distance_m)];
        if vs.scene.run.duration_s.is_some() {
            o.push(Variation::Remove("run.duration_s".into()));
        }
        let origin = vs.origin.clone();
        vs = vs.varied(&o)?;
        vs.origin = origin;
        let law = vs.scene.contact.creep_law;
        let cs_settings = CriticalSpeedSettings {
            laws: vec![law],
            min_m_s: cs.min_m_s,
            max_m_s: cs.max_m_s,
            tol_m_s: cs.tol_m_s,
            jobs: settings.jobs.max(1),
            methods: vec![crate::studies::critical_speed::CriticalSpeedMethod::Time],
            out_dir: settings.out_dir.join("critical_speed").join(v.slug()),
            skip_s: cs.skip_s,
            ramp_deceleration_m_s2: 0.5,
            criterion: crate::studies::cycle_death::HuntingCriterion::All,
        };
        cs_settings.validate()?;
        let t0 = std::time::Instant::now();
        let r = time_domain(&vs, law, &cs_settings, stop.clone())
            .with_context(|| format!("critical speed of '{}'", v.name))?;
        progress(&format!(
            "{}: critical speed {} ({:.1} s)",
            v.name,
            r.speed_m_s
                .map_or_else(|| "—".to_string(), |s| format!("{s:.2} m/s")),
            t0.elapsed().as_secs_f64()
        ));
        row.critical_speed_m_s = r.speed_m_s;
        row.critical_speed_note = r.note;
        if v.name == REFERENCE {
            reference_speed = r.speed_m_s;
        }
        row.critical_speed_error_m_s = reference_speed.zip(r.speed_m_s).map(|(a, b)| (a - b).abs());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use runtime::results::WheelsetSample;

    fn sine(freq: f64, amp: f64, rate: f64) -> RunResults {
        let mut r = RunResults::with_wheelsets(["ws"]);
        for i in 0..1000 {
            let t = i as f64 * 0.005;
            let y = amp * (rate * t).exp() * (std::f64::consts::TAU * freq * t + 0.3).sin();
            let mut s = WheelsetSample {
                lateral_m: y,
                ..Default::default()
            };
            s.wheels[0].zones[0].in_contact = true;
            s.wheels[0].zones[0].lateral_force_n = 1e6 * y;
            s.wheels[0].zones[0].normal_n = 5e4 + 1e6 * y;
            r.push(t, &[s]).unwrap();
        }
        r
    }

    #[test]
    fn frequency_from_zero_crossings() {
        let r = sine(3.3, 0.002, -0.2);
        let f = hunting_frequency_hz(&r.time_s, &r.wheelsets[0].lateral_m).unwrap();
        assert!((f - 3.3).abs() < 1e-3, "{f}");
        // A motion that dies out: the crossings in the noise do not count.
        let t: Vec<f64> = (0..400).map(|i| i as f64 * 0.01).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|t| {
                if *t < 1.0 {
                    1e-3 * (std::f64::consts::TAU * 2.0 * t).cos()
                } else {
                    1e-12 * (40.0 * t).sin()
                }
            })
            .collect();
        let f = hunting_frequency_hz(&t, &y).unwrap();
        assert!((f - 2.0).abs() < 0.05, "{f}");
        assert_eq!(hunting_frequency_hz(&t[..30], &y[..30]), None);
    }

    #[test]
    fn errors_of_a_run_against_itself_are_zero_and_grow_with_the_difference() {
        let a = sine(3.0, 0.002, -0.1);
        let e = compare(&a, &a, 1.0).unwrap();
        assert_eq!(e.lateral_max_m, 0.0);
        assert_eq!(e.lateral_rms_m, 0.0);
        assert_eq!(e.frequency_hz, Some(0.0));
        assert_eq!(e.peak_lateral_force_n, 0.0);
        let b = sine(3.05, 0.002, -0.1);
        let c = sine(3.2, 0.002, -0.1);
        let (eb, ec) = (compare(&a, &b, 1.0).unwrap(), compare(&a, &c, 1.0).unwrap());
        assert!(eb.lateral_max_m > 0.0 && ec.lateral_max_m > eb.lateral_max_m);
        assert!(eb.lateral_rms_m <= eb.lateral_max_m);
        assert!((ec.frequency_hz.unwrap() - 0.2).abs() < 2e-3, "{ec:?}");
        let m = measures(&a, 0.0);
        assert!((m.peak_normal_force_n - 5e4 - 1.99e3).abs() < 10.0, "{m:?}");
        // After the skip: the decayed peaks only.
        let m = measures(&a, 1.0);
        let late = 2e3 * (-0.1_f64).exp();
        assert!(
            m.peak_lateral_force_n <= late && m.peak_lateral_force_n > late - 30.0,
            "{m:?}"
        );
        assert!((m.growth_rate_1_s.unwrap() + 0.1).abs() < 5e-3, "{m:?}");
    }

    #[test]
    fn pareto_front_keeps_the_undominated() {
        let pts = [
            (1.0, 0.0),
            (0.5, 1e-6),
            (0.6, 2e-6),
            (0.2, 1e-3),
            (0.2, 2e-3),
            (f64::NAN, f64::NAN),
        ];
        assert_eq!(
            pareto_front(&pts),
            vec![true, true, false, true, false, false]
        );
    }

    #[test]
    fn variants_of_the_bogie_scene() {
        let s = LoadedScene::load(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("tables/scenes/bogie_straight.toml"),
            &[],
        )
        .unwrap();
        let (full, skipped) = variants(&s.scene, false);
        assert!(skipped.is_empty(), "{skipped:?}");
        assert_eq!(full[0].name, REFERENCE);
        let names: Vec<&str> = full.iter().map(|v| v.name.as_str()).collect();
        for n in [
            "table step 1 m",
            "contact table",
            "flange off",
            "rk4 1 ms",
            "dopri5 rtol 1e-6",
            "rosenbrock atol 5e-6",
            "rosenbrock atol 2e-7",
            "creep kalker",
            "creep fastrip",
            "scheme pchip",
            "quick look",
            "design study",
            "scene as given",
        ] {
            assert!(names.contains(&n), "{n} missing from {names:?}");
        }
        assert!(!names.contains(&"creep polach"), "the scene's own law");
        let mut unique = names.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), names.len(), "{names:?}");
        // Every variant's scene is valid.
        for v in &full {
            let vs = variant_scene(&s, v).unwrap();
            assert!(vs.scene.duration_s() > 0.0);
        }
        // The scene's own settings are restored by "scene as given".
        let given = full.iter().find(|v| v.name == "scene as given").unwrap();
        let vs = variant_scene(&s, given).unwrap();
        assert_eq!(vs.scene.track.step_m, s.scene.track.step_m);
        assert_eq!(vs.scene.run.step_s, s.scene.run.step_s);
        assert_eq!(vs.scene.contact.flange, s.scene.contact.flange);
        let (quick, _) = variants(&s.scene, true);
        assert_eq!(quick.len(), 6);
        assert!(quick.iter().any(|v| v.name == "rosenbrock atol 5e-6"));
        let q = quick_scene(&s, false).unwrap();
        assert_eq!(q.scene.run.distance_m, Some(QUICK_DISTANCE_M));
    }

    #[test]
    fn user_variants_and_critical_speed_specs_parse() {
        let v = Variant::parse("coarse rk4: run.step_s=2e-3; track.step_m=1").unwrap();
        assert_eq!(v.name, "coarse rk4");
        assert_eq!(v.overrides, ["run.step_s=2e-3", "track.step_m=1"]);
        assert_eq!(v.slug(), "coarse_rk4");
        assert!(Variant::parse("no overrides here").is_err());
        assert!(Variant::parse("x: step").is_err());
        let c = CriticalSpeedSpec::parse("70:100:0.5").unwrap();
        assert_eq!(
            (c.min_m_s, c.max_m_s, c.tol_m_s, c.distance_m),
            (70.0, 100.0, 0.5, 250.0)
        );
        assert_eq!(
            CriticalSpeedSpec::parse("70:100:0.5:300")
                .unwrap()
                .distance_m,
            300.0
        );
        assert!(CriticalSpeedSpec::parse("70:100").is_err());
        assert!(CriticalSpeedSpec::parse("70:x:1").is_err());
    }
}
