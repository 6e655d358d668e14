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
use crate::config::scene::{LoadedScene, Scene};
use crate::run::run_scene;
use crate::studies::critical_speed::{CriticalSpeedSettings, growth_rate, time_domain};

/// The reference run: finest table step, online contact with the flange
/// always searched, RK4 at 0.1 ms. Measured on the bogie at 84 m/s over
/// 100 m: within 1.3e-10 m of RK4 at 0.02 ms and of DOPRI5 at rtol 1e-10
/// (`docs/guide/speed-accuracy-tradeoff.md`), so converged far below any variant's error; DOPRI5 at rtol 1e-9
/// is no more accurate and no faster.
pub const REFERENCE_OVERRIDES: [&str; 5] = [
    "track.step_m=0.01",
    "contact.flange=\"on\"",
    "contact.method=\"online\"",
    "run.integrator=\"rk4\"",
    "run.step_s=1e-4",
];

/// Largest DOPRI5 step of the dopri5 variants (s): DOPRI5 is limited by
/// stability near 1.2 ms on the bogie (`docs/guide/performance.md`), 2 ms lets it choose.
pub const DOPRI5_MAX_STEP_S: f64 = 2e-3;

/// Run length of `--quick` (m) unless the scene's length is overridden.
pub const QUICK_DISTANCE_M: f64 = 50.0;

/// Errors below this are drawn at it on the log axis of `pareto.png` (m).
pub const PLOT_ERROR_FLOOR_M: f64 = 1e-9;

/// Amplitudes below this are not motion (m): zero crossings after the
/// motion has died out are not counted.
const NOISE_M: f64 = 1e-7;

/// One run setting: the overrides it applies after the reference's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Variant {
    pub name: String,
    /// Which knob (or "combination", "reference", …).
    pub knob: String,
    /// The knob's value, as shown in the plot's legend.
    pub value: String,
    /// Overrides applied after [`REFERENCE_OVERRIDES`].
    pub overrides: Vec<String>,
    /// The variant with the same settings and the reference's table step
    /// (for the table-step rule), if this one differs from it in the table
    /// step only.
    pub fine_table_partner: Option<String>,
}

impl Variant {
    fn new(name: &str, knob: &str, value: &str, overrides: &[&str]) -> Variant {
        Variant {
            name: name.into(),
            knob: knob.into(),
            value: value.into(),
            overrides: overrides.iter().map(|s| s.to_string()).collect(),
            fine_table_partner: None,
        }
    }

    fn partner(mut self, name: &str) -> Variant {
        self.fine_table_partner = Some(name.into());
        self
    }

    /// A user's variant `NAME:KEY=VALUE;KEY=VALUE…` (`--variant`).
    pub fn parse(spec: &str) -> Result<Variant> {
        let (name, rest) = spec
            .split_once(':')
            .context("a variant is NAME:KEY=VALUE;KEY=VALUE…")?;
        let name = name.trim();
        ensure!(!name.is_empty(), "the variant has no name");
        let overrides: Vec<String> = rest
            .split(';')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect();
        for o in &overrides {
            ensure!(o.contains('='), "'{o}' is not KEY=VALUE");
        }
        Ok(Variant {
            name: name.into(),
            knob: "user".into(),
            value: name.into(),
            overrides,
            fine_table_partner: None,
        })
    }

    /// File-name form of the name.
    pub fn slug(&self) -> String {
        let s: String = self
            .name
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        let mut out = String::new();
        for c in s.chars() {
            if !(c == '_' && out.ends_with('_')) {
                out.push(c);
            }
        }
        out.trim_matches('_').to_string()
    }
}

/// Name of the reference variant.
pub const REFERENCE: &str = "reference";

/// The scene's own settings of the reference's keys, as overrides.
fn scene_settings(scene: &Scene) -> Vec<String> {
    let mut v = vec![
        format!("track.step_m={}", scene.track.step_m),
        format!("contact.flange=\"{}\"", scene.contact.flange),
        format!("contact.method=\"{}\"", scene.contact.method),
        format!("run.integrator=\"{}\"", scene.run.integrator),
        format!("run.step_s={}", scene.run.step_s),
    ];
    if scene.run.integrator == IntegratorKind::Dopri5 {
        v.push(format!("run.rtol={}", scene.run.rtol));
        v.push(format!("run.atol={}", scene.run.atol));
        v.push(format!("run.max_step_s={}", scene.run.max_step_s));
    }
    v
}

/// The variants of a study of `scene` (module docs); `quick`: the reference
/// and four (RK4 at 1 and 0.2 ms, table step 1 m, "quick look"). The table
/// step and scheme knobs are left out when the scene reads a table file
/// (they are ignored then) and the scheme when it uses an ideal straight;
/// the reasons are returned.
pub fn variants(scene: &Scene, quick: bool) -> (Vec<Variant>, Vec<String>) {
    let dp = |rtol: &str| -> Vec<String> {
        vec![
            "run.integrator=\"dopri5\"".into(),
            format!("run.rtol={rtol}"),
            format!("run.max_step_s={DOPRI5_MAX_STEP_S}"),
        ]
    };
    let quick_look = Variant::new(
        "quick look",
        "combination",
        "quick look",
        &[
            "contact.method=\"table\"",
            "contact.flange=\"auto\"",
            "track.step_m=0.5",
            "run.step_s=1e-3",
        ],
    );
    let reference = Variant::new(REFERENCE, "reference", "reference", &[]);
    let mut skipped = Vec::new();
    let tables_file = scene.track.tables.is_some();
    if tables_file {
        skipped.push(
            "table step, spline scheme: the scene reads a table file (step and scheme are fixed in it)"
                .to_string(),
        );
    } else if scene.track.straight_m.is_some() {
        skipped.push("spline scheme: the scene's track is an ideal straight (no spline)".into());
    }
    if quick {
        let mut v = vec![
            reference,
            Variant::new("rk4 1 ms", "rk4 step", "1 ms", &["run.step_s=1e-3"]),
            Variant::new("rk4 0.2 ms", "rk4 step", "0.2 ms", &["run.step_s=2e-4"]),
        ];
        if !tables_file {
            v.push(
                Variant::new("table step 1 m", "table step", "1 m", &["track.step_m=1"])
                    .partner(REFERENCE),
            );
        }
        v.push(quick_look);
        return (v, skipped);
    }
    let mut v = vec![reference];
    if !tables_file {
        for (step, name) in [("1", "1 m"), ("0.5", "0.5 m"), ("0.1", "0.1 m")] {
            v.push(
                Variant::new(
                    &format!("table step {name}"),
                    "table step",
                    name,
                    &[&format!("track.step_m={step}")],
                )
                .partner(REFERENCE),
            );
        }
    }
    v.push(Variant::new(
        "contact table",
        "contact",
        "table",
        &["contact.method=\"table\""],
    ));
    v.push(Variant::new(
        "flange off",
        "contact",
        "flange off",
        &["contact.flange=\"off\""],
    ));
    v.push(Variant::new(
        "flange auto",
        "contact",
        "flange auto",
        &["contact.flange=\"auto\""],
    ));
    for (step, name) in [
        ("1e-3", "1 ms"),
        ("5e-4", "0.5 ms"),
        ("2e-4", "0.2 ms"),
        ("5e-5", "0.05 ms"),
    ] {
        v.push(Variant::new(
            &format!("rk4 {name}"),
            "rk4 step",
            name,
            &[&format!("run.step_s={step}")],
        ));
    }
    for rtol in ["1e-4", "1e-6", "1e-8", "1e-9"] {
        let mut var = Variant::new(&format!("dopri5 rtol {rtol}"), "dopri5 rtol", rtol, &[]);
        var.overrides = dp(rtol);
        v.push(var);
    }
    for law in ["kalker", "heuristic", "polach", "fastsim"] {
        if law != scene.contact.creep_law.as_str() {
            v.push(Variant::new(
                &format!("creep {law}"),
                "model",
                law,
                &[&format!("contact.creep_law=\"{law}\"")],
            ));
        }
    }
    if scene.track.centerline.is_some() {
        for scheme in ["cubic", "akima", "pchip"] {
            if scheme != scene.track.scheme {
                v.push(Variant::new(
                    &format!("scheme {scheme}"),
                    "model",
                    scheme,
                    &[&format!("track.scheme=\"{scheme}\"")],
                ));
            }
        }
    }
    if !tables_file {
        for (step, name) in [("0.1", "0.1 m"), ("0.5", "0.5 m"), ("1", "1 m")] {
            v.push(
                Variant::new(
                    &format!("table step {name} + rk4 1 ms"),
                    "table step × rk4 1 ms",
                    name,
                    &[&format!("track.step_m={step}"), "run.step_s=1e-3"],
                )
                .partner("rk4 1 ms"),
            );
        }
    }
    v.push(quick_look);
    v.push(Variant::new(
        "design study",
        "combination",
        "design study",
        &[
            "contact.flange=\"auto\"",
            "track.step_m=0.1",
            "run.step_s=5e-4",
        ],
    ));
    let mut adaptive = Variant::new("adaptive", "combination", "adaptive", &[]);
    adaptive.overrides = [
        "contact.flange=\"auto\"".to_string(),
        "track.step_m=0.1".into(),
    ]
    .into_iter()
    .chain(dp("1e-6"))
    .collect();
    v.push(adaptive);
    let mut given = Variant::new("scene as given", "combination", "scene as given", &[]);
    given.overrides = scene_settings(scene);
    v.push(given);
    (v, skipped)
}

/// The scene shortened for `--quick`: [`QUICK_DISTANCE_M`] unless `keep`
/// (the user set the length).
pub fn quick_scene(scene: &LoadedScene, keep: bool) -> Result<LoadedScene> {
    if keep {
        return Ok(scene.clone());
    }
    let mut o = vec![Variation::Distance(QUICK_DISTANCE_M)];
    if scene.scene.run.duration_s.is_some() {
        o.push(Variation::Remove("run.duration_s".into()));
    }
    let mut quick = scene.varied(&o)?;
    quick.origin = scene.origin.clone();
    Ok(quick)
}

/// The scene of a variant: the reference's overrides, then its own.
pub fn variant_scene(scene: &LoadedScene, v: &Variant) -> Result<LoadedScene> {
    let variations = REFERENCE_OVERRIDES
        .iter()
        .copied()
        .chain(v.overrides.iter().map(String::as_str))
        .map(Variation::parse)
        .collect::<Result<Vec<_>>>()
        .with_context(|| format!("variant '{}'", v.name))?;
    let mut vs = scene
        .varied(&variations)
        .with_context(|| format!("variant '{}'", v.name))?;
    vs.origin = format!("{} [{}]", scene.origin, v.name);
    Ok(vs)
}

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

/// Linear interpolation of samples `(t, y)` at `x` (t increasing, x within).
fn interpolate(t: &[f64], y: &[f64], x: f64) -> f64 {
    let i = t.partition_point(|&v| v <= x);
    if i == 0 {
        return y[0];
    }
    if i >= t.len() {
        return y[t.len() - 1];
    }
    let (t0, t1) = (t[i - 1], t[i]);
    if t1 <= t0 {
        return y[i - 1];
    }
    y[i - 1] + (y[i] - y[i - 1]) * (x - t0) / (t1 - t0)
}

/// Hunting frequency (Hz) from the zero crossings (both ways, linearly
/// interpolated) of `y(t)` while the motion lasts (|y| above 1e-3 of its
/// peak and 0.1 µm); `None` below 3 crossings.
pub fn hunting_frequency_hz(t: &[f64], y: &[f64]) -> Option<f64> {
    let peak = y
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    let floor = (1e-3 * peak).max(NOISE_M);
    let last = y.iter().rposition(|v| v.abs() > floor)?;
    let n = (last + 1).min(y.len().saturating_sub(1));
    let crossings: Vec<f64> = (0..n)
        .filter(|&i| {
            y[i].is_finite()
                && y[i + 1].is_finite()
                && ((y[i] < 0.0 && y[i + 1] >= 0.0) || (y[i] > 0.0 && y[i + 1] <= 0.0))
        })
        .map(|i| t[i] + (t[i + 1] - t[i]) * y[i] / (y[i] - y[i + 1]))
        .collect();
    if crossings.len() < 3 {
        return None;
    }
    let span = crossings[crossings.len() - 1] - crossings[0];
    (span > 0.0).then(|| (crossings.len() - 1) as f64 / (2.0 * span))
}

fn or_zero(v: f64) -> f64 {
    if v.is_finite() { v } else { 0.0 }
}

/// What a run measures by itself after the start transient `skip_s` (the
/// peaks and the growth-rate fit; the frequency takes every crossing).
pub fn measures(r: &RunResults, skip_s: f64) -> Measures {
    let (mut y_peak, mut n_peak) = (0.0_f64, 0.0_f64);
    for ws in &r.wheelsets {
        for wheel in &ws.wheels {
            let [a, b] = &wheel.zones;
            for i in 0..a.lateral_force_n.len() {
                if r.time_s[i] < skip_s {
                    continue;
                }
                y_peak = y_peak
                    .max((or_zero(a.lateral_force_n[i]) + or_zero(b.lateral_force_n[i])).abs());
                n_peak = n_peak.max(or_zero(a.normal_n[i]) + or_zero(b.normal_n[i]));
            }
        }
    }
    let (frequency, rate) = match r.wheelsets.first() {
        Some(w) => (
            hunting_frequency_hz(&r.time_s, &w.lateral_m),
            growth_rate(r, 0, skip_s)
                .map(|f| f.rate_1_s)
                .filter(|v| v.is_finite()),
        ),
        None => (None, None),
    };
    Measures {
        hunting_frequency_hz: frequency,
        growth_rate_1_s: rate,
        peak_lateral_force_n: y_peak,
        peak_normal_force_n: n_peak,
    }
}

/// Max and RMS of wheelset `wheelset`'s lateral difference (m) between
/// `run` and `reference` (0 = the leading wheelset), over the reference's
/// samples within the run's span (the run interpolated linearly at them),
/// and that span (s).
pub fn lateral_difference(
    reference: &RunResults,
    run: &RunResults,
    wheelset: usize,
) -> Result<(f64, f64, f64)> {
    let (wr, wv) = match (
        reference.wheelsets.get(wheelset),
        run.wheelsets.get(wheelset),
    ) {
        (Some(a), Some(b)) => (a, b),
        _ => bail!("wheelset {wheelset} is not in both runs"),
    };
    ensure!(
        run.time_s.len() >= 2,
        "the run has {} samples, too few to compare",
        run.time_s.len()
    );
    let (t0, t1) = (run.time_s[0], run.time_s[run.time_s.len() - 1]);
    let (mut max, mut sum2, mut n) = (0.0_f64, 0.0, 0usize);
    let (mut first, mut last) = (f64::NAN, f64::NAN);
    for (&t, &yr) in reference.time_s.iter().zip(&wr.lateral_m) {
        if t < t0 - 1e-12 || t > t1 + 1e-12 {
            continue;
        }
        let d = interpolate(&run.time_s, &wv.lateral_m, t) - yr;
        ensure!(
            d.is_finite(),
            "the lateral displacement is not finite at t = {t} s"
        );
        max = max.max(d.abs());
        sum2 += d * d;
        n += 1;
        if first.is_nan() {
            first = t;
        }
        last = t;
    }
    ensure!(n > 0, "the run and the reference have no common time span");
    Ok((max, (sum2 / n as f64).sqrt(), last - first))
}

/// Errors of `run` against `reference` (module docs).
pub fn compare(reference: &RunResults, run: &RunResults, skip_s: f64) -> Result<Errors> {
    let (max, rms, span) = lateral_difference(reference, run, 0)?;
    let (a, b) = (measures(reference, skip_s), measures(run, skip_s));
    let diff = |x: Option<f64>, y: Option<f64>| x.zip(y).map(|(x, y)| (x - y).abs());
    Ok(Errors {
        lateral_max_m: max,
        lateral_rms_m: rms,
        compared_s: span,
        frequency_hz: diff(a.hunting_frequency_hz, b.hunting_frequency_hz),
        growth_rate_1_s: diff(a.growth_rate_1_s, b.growth_rate_1_s),
        peak_lateral_force_n: (a.peak_lateral_force_n - b.peak_lateral_force_n).abs(),
        peak_normal_force_n: (a.peak_normal_force_n - b.peak_normal_force_n).abs(),
    })
}

/// Which points `(cost, error)` are on the Pareto front (no other point is
/// at most as costly and as wrong, and better in one). Non-finite points
/// are never on it.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(c, e)| {
            c.is_finite()
                && e.is_finite()
                && !points.iter().any(|&(c2, e2)| {
                    c2.is_finite() && e2.is_finite() && c2 <= c && e2 <= e && (c2 < c || e2 < e)
                })
        })
        .collect()
}

fn median(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    Some(if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    })
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
            runtime::schema::write_results(&output, &outcome.results)
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

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x}"))
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Short number for the tables.
fn fmt(v: Option<f64>, digits: usize) -> String {
    match v {
        Some(0.0) => "0".into(),
        Some(x) if x.is_finite() && (x.abs() >= 1e4 || x.abs() < 1e-2) => {
            format!("{x:.*e}", digits.saturating_sub(1))
        }
        Some(x) if x.is_finite() => format!("{x:.*}", digits),
        Some(x) => format!("{x}"),
        None => "—".into(),
    }
}

impl TradeoffReport {
    /// `tradeoff.csv`: one row per variant, SI units.
    pub fn to_csv(&self) -> String {
        let mut s = String::from(
            "name,knob,overrides,status,error,wall_time_median_s,wall_time_min_s,wall_time_max_s,setup_time_median_s,simulated_time_s,real_time_factor,steps,rejected_steps,rhs_evaluations,table_step_m,distance_per_step_m,table_step_ratio,lateral_max_error_m,lateral_rms_error_m,hunting_frequency_hz,frequency_error_hz,growth_rate_1_s,growth_rate_error_1_s,peak_lateral_force_n,peak_lateral_force_error_n,peak_normal_force_n,peak_normal_force_error_n,critical_speed_m_s,critical_speed_error_m_s,pareto,results\n",
        );
        for r in &self.variants {
            let m = r.measures;
            let e = r.errors;
            let fields = [
                csv_field(&r.name),
                csv_field(&r.knob),
                csv_field(&r.overrides.join(";")),
                csv_field(&r.status),
                csv_field(r.error.as_deref().unwrap_or("")),
                opt(r.wall_time_median_s),
                opt(r.wall_time_min_s),
                opt(r.wall_time_max_s),
                opt(r.setup_time_median_s),
                opt(r.simulated_time_s),
                opt(r.real_time_factor),
                r.steps.map_or(String::new(), |v| v.to_string()),
                r.rejected_steps.map_or(String::new(), |v| v.to_string()),
                r.rhs_evaluations.map_or(String::new(), |v| v.to_string()),
                format!("{}", r.table_step_m),
                opt(r.distance_per_step_m),
                opt(r.table_step_ratio),
                opt(e.map(|e| e.lateral_max_m)),
                opt(e.map(|e| e.lateral_rms_m)),
                opt(m.and_then(|m| m.hunting_frequency_hz)),
                opt(e.and_then(|e| e.frequency_hz)),
                opt(m.and_then(|m| m.growth_rate_1_s)),
                opt(e.and_then(|e| e.growth_rate_1_s)),
                opt(m.map(|m| m.peak_lateral_force_n)),
                opt(e.map(|e| e.peak_lateral_force_n)),
                opt(m.map(|m| m.peak_normal_force_n)),
                opt(e.map(|e| e.peak_normal_force_n)),
                opt(r.critical_speed_m_s),
                opt(r.critical_speed_error_m_s),
                r.pareto.to_string(),
                csv_field(r.results.as_deref().unwrap_or("")),
            ];
            s += &fields.join(",");
            s.push('\n');
        }
        s
    }

    /// `tradeoff.md`: the table, the rule check, the failures.
    pub fn to_markdown(&self) -> String {
        let mut s = format!(
            "# Speed against accuracy: {}\n\n{} m/s, {}, outputs every {} s; median of {} run(s) per variant, one at a time, on a machine with {} hardware thread(s); study wall time {:.1} s.\n\nReference: `{}`. Every variant applies the reference's overrides, then its own (below). Errors against the reference: the leading wheelset's lateral displacement (max, RMS), the hunting frequency (zero crossings), the peak total lateral force |Y| and normal force N over all wheels. ★: on the Pareto front of (wall time, max lateral error).\n\n",
            self.scene,
            self.speed_m_s,
            self.distance_m
                .map_or_else(|| "the scene's duration".into(), |d| format!("{d} m")),
            self.output_interval_s,
            self.repeats,
            self.threads,
            self.total_wall_time_s,
            self.reference_overrides.join(" "),
        );
        let cs = self
            .variants
            .iter()
            .any(|r| r.critical_speed_m_s.is_some() || r.critical_speed_note.is_some());
        s += "| variant | overrides | wall time [s] median (min–max) | RTF | lateral max [µm] | lateral RMS [µm] | f [Hz] (error) | σ [1/s] (error) | peak Y [kN] (error) | peak N [kN] (error) | step / (V·Δt) |";
        if cs {
            s += " critical speed [m/s] (error) |";
        }
        s += "\n|---|---|---|---|---|---|---|---|---|---|---|";
        if cs {
            s += "---|";
        }
        s.push('\n');
        for r in &self.variants {
            let m = r.measures;
            let e = r.errors;
            let name = if r.pareto {
                format!("★ {}", r.name)
            } else {
                r.name.clone()
            };
            let overrides = if r.overrides.is_empty() {
                "—".to_string()
            } else {
                format!("`{}`", r.overrides.join(" "))
            };
            if r.status == "failed" {
                s += &format!(
                    "| {name} | {overrides} | failed: {} |{}\n",
                    r.error
                        .clone()
                        .unwrap_or_default()
                        .replace('|', "/")
                        .replace('\n', " "),
                    " |".repeat(if cs { 9 } else { 8 })
                );
                continue;
            }
            let pair = |a: Option<f64>, b: Option<f64>, scale: f64, d: usize| {
                format!(
                    "{} ({})",
                    fmt(a.map(|v| v * scale), d),
                    fmt(b.map(|v| v * scale), 2)
                )
            };
            s += &format!(
                "| {name}{} | {overrides} | {} ({}–{}) | {} | {} | {} | {} | {} | {} | {} | {} |",
                if r.status == "ok" {
                    String::new()
                } else {
                    format!(" ({})", r.status)
                },
                fmt(r.wall_time_median_s, 3),
                fmt(r.wall_time_min_s, 3),
                fmt(r.wall_time_max_s, 3),
                fmt(r.real_time_factor, 2),
                fmt(e.map(|e| e.lateral_max_m * 1e6), 3),
                fmt(e.map(|e| e.lateral_rms_m * 1e6), 3),
                pair(
                    m.and_then(|m| m.hunting_frequency_hz),
                    e.and_then(|e| e.frequency_hz),
                    1.0,
                    4
                ),
                pair(
                    m.and_then(|m| m.growth_rate_1_s),
                    e.and_then(|e| e.growth_rate_1_s),
                    1.0,
                    3
                ),
                pair(
                    m.map(|m| m.peak_lateral_force_n),
                    e.map(|e| e.peak_lateral_force_n),
                    1e-3,
                    3
                ),
                pair(
                    m.map(|m| m.peak_normal_force_n),
                    e.map(|e| e.peak_normal_force_n),
                    1e-3,
                    3
                ),
                fmt(r.table_step_ratio, 2),
            );
            if cs {
                s += &format!(
                    " {} |",
                    match (r.critical_speed_m_s, &r.critical_speed_note) {
                        (Some(_), _) =>
                            pair(r.critical_speed_m_s, r.critical_speed_error_m_s, 1.0, 2),
                        (None, Some(n)) => n.clone(),
                        _ => "—".into(),
                    }
                );
            }
            s.push('\n');
        }
        if !self.rule.is_empty() {
            s += "\n## The table-step rule (paper §2: table step ≤ V·Δt)\n\nThe table step's own error: each run against the run with the same integrator and a 0.01 m table.\n\n| variant | against | table step [m] | V·Δt [m] | ratio | max lateral difference [µm] | the partner's own error [µm] |\n|---|---|---|---|---|---|---|\n";
            for r in &self.rule {
                s += &format!(
                    "| {} | {} | {} | {} | {} | {} | {} |\n",
                    r.variant,
                    r.partner,
                    r.table_step_m,
                    fmt(Some(r.distance_per_step_m), 3),
                    fmt(Some(r.ratio), 2),
                    fmt(Some(r.lateral_max_m * 1e6), 3),
                    fmt(Some(r.partner_error_m * 1e6), 3),
                );
            }
        }
        let failed: Vec<&VariantResult> =
            self.variants.iter().filter(|r| r.status != "ok").collect();
        if !failed.is_empty() {
            s += "\n## Failed or stopped\n\n";
            for r in failed {
                s += &format!(
                    "- **{}** ({}): {}\n",
                    r.name,
                    r.status,
                    r.error.clone().unwrap_or_default()
                );
            }
        }
        for k in &self.skipped {
            s += &format!("\nNot varied: {k}.\n");
        }
        s
    }

    /// Terminal summary.
    pub fn to_text(&self) -> String {
        let mut s = format!(
            "speed against accuracy, {} ({} m/s; {} repeat(s), {:.1} s)\n  {:<30} {:>9} {:>8} {:>12} {:>12} {:>10} {:>10} {:>8}\n",
            self.scene,
            self.speed_m_s,
            self.repeats,
            self.total_wall_time_s,
            "variant",
            "wall [s]",
            "RTF",
            "lat max[µm]",
            "lat rms[µm]",
            "Δf [Hz]",
            "ΔY [kN]",
            "ratio"
        );
        for r in &self.variants {
            if r.status == "failed" {
                s += &format!(
                    "  {:<30} failed: {}\n",
                    r.name,
                    r.error.clone().unwrap_or_default()
                );
                continue;
            }
            let e = r.errors;
            s += &format!(
                "  {:<30} {:>9} {:>8} {:>12} {:>12} {:>10} {:>10} {:>8}{}\n",
                format!("{}{}", if r.pareto { "* " } else { "" }, r.name),
                fmt(r.wall_time_median_s, 3),
                fmt(r.real_time_factor, 2),
                fmt(e.map(|e| e.lateral_max_m * 1e6), 3),
                fmt(e.map(|e| e.lateral_rms_m * 1e6), 3),
                fmt(e.and_then(|e| e.frequency_hz), 3),
                fmt(e.map(|e| e.peak_lateral_force_n * 1e-3), 3),
                fmt(r.table_step_ratio, 2),
                if r.status == "ok" {
                    String::new()
                } else {
                    format!("  ({})", r.status)
                }
            );
        }
        s += "  * on the Pareto front (wall time, max lateral error)\n";
        for f in &self.files {
            s += &format!("  wrote {f}\n");
        }
        s
    }

    /// The Pareto chart: log₁₀ max lateral error (mm) against log₁₀ median
    /// wall time (s), one line per knob through its values in the legend's
    /// order, the front in black.
    pub fn pareto_chart(&self) -> preproc::plot::LineChart {
        use preproc::plot::{LineChart, Series, SeriesStyle};
        let mut chart = LineChart::new(
            format!(
                "Speed against accuracy, {} ({} m/s)",
                self.scene, self.speed_m_s
            ),
            "log₁₀ wall time [s] (median)",
            "log₁₀ max lateral error of the leading wheelset [mm]",
        );
        let point = |r: &VariantResult| -> Option<(f64, f64)> {
            let w = r.wall_time_median_s?;
            let e = r.errors?.lateral_max_m;
            (r.status == "ok" && w > 0.0)
                .then(|| (w.log10(), (e.max(PLOT_ERROR_FLOOR_M) * 1e3).log10()))
        };
        // Knob groups in a fixed order (7 colours; black is the front).
        let groups: [(&str, &[&str]); 7] = [
            ("table step", &["table step"]),
            ("rk4 step", &["rk4 step"]),
            ("dopri5 rtol", &["dopri5 rtol"]),
            ("table step with rk4 1 ms", &["table step × rk4 1 ms"]),
            ("contact", &["contact"]),
            ("creep law / scheme", &["model"]),
            ("combinations", &["combination", "user"]),
        ];
        let colours = [0usize, 1, 2, 3, 4, 5, 7];
        for ((label, knobs), c) in groups.iter().zip(colours) {
            let members: Vec<&VariantResult> = self
                .variants
                .iter()
                .filter(|r| knobs.contains(&r.knob.as_str()))
                .filter(|r| point(r).is_some())
                .collect();
            if members.is_empty() {
                continue;
            }
            let names: Vec<&str> = members.iter().map(|r| r.value.as_str()).collect();
            chart.series.push(
                Series::line(
                    format!("{label}: {}", names.join(" → ")),
                    members.iter().filter_map(|r| point(r)).collect(),
                )
                .with_style(SeriesStyle::LineAndPoints)
                .with_colour(c),
            );
        }
        if let Some(r) = self.variants.iter().find(|r| r.knob == "reference") {
            chart.series.push(
                Series::points(
                    format!(
                        "reference (error 0, drawn at {:e} mm)",
                        PLOT_ERROR_FLOOR_M * 1e3
                    ),
                    point(r).into_iter().collect(),
                )
                .with_colour(6),
            );
        }
        let mut front: Vec<(f64, f64)> = self
            .variants
            .iter()
            .filter(|r| r.pareto)
            .filter_map(point)
            .collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart
            .series
            .push(Series::line("Pareto front", front).with_colour(6));
        chart
    }

    /// Writes `tradeoff.csv`, `tradeoff.md`, `pareto.png` and, with `json`,
    /// `tradeoff.json` into `dir`.
    pub fn write(&mut self, dir: &Path, json: bool) -> Result<()> {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let csv = dir.join("tradeoff.csv");
        std::fs::write(&csv, self.to_csv())
            .with_context(|| format!("writing {}", csv.display()))?;
        let md = dir.join("tradeoff.md");
        std::fs::write(&md, self.to_markdown())
            .with_context(|| format!("writing {}", md.display()))?;
        let png = dir.join("pareto.png");
        preproc::plot::write_line_chart(&png, &self.pareto_chart(), (1800, 1100))
            .context("writing the Pareto chart")?;
        self.files = vec![
            csv.display().to_string(),
            md.display().to_string(),
            png.display().to_string(),
        ];
        if json {
            let path = dir.join("tradeoff.json");
            self.files.push(path.display().to_string());
            std::fs::write(&path, serde_json::to_string_pretty(self)?)
                .with_context(|| format!("writing {}", path.display()))?;
        }
        Ok(())
    }
}

/// Arguments of `sim tradeoff`.
#[derive(Debug, clap::Args)]
pub struct TradeoffArgs {
    /// Scene file (TOML).
    #[arg(value_name = "SCENE.toml")]
    pub scene: PathBuf,
    /// Output directory (tradeoff.csv, tradeoff.md, pareto.png, runs/).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Runs per variant; the wall time is their median [default: 3, 1 with --quick].
    #[arg(long, value_name = "N")]
    pub repeats: Option<usize>,
    /// Reduced study: the reference and four variants over 50 m (tests, CI).
    #[arg(long)]
    pub quick: bool,
    /// Set a scene entry for every variant, before the reference's overrides (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Add a variant: NAME:KEY=VALUE;KEY=VALUE… applied after the reference's overrides (repeatable).
    #[arg(long = "variant", value_name = "SPEC")]
    pub variant: Vec<String>,
    /// Also the time-domain critical speed of every variant: MIN:MAX:TOL or MIN:MAX:TOL:DISTANCE_M (m/s, m; expensive).
    #[arg(long, value_name = "SPEC")]
    pub critical_speed: Option<String>,
    /// Parallel runs of the critical-speed searches [default: the number of cores].
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Print the report as JSON (and write tradeoff.json).
    #[arg(long)]
    pub json: bool,
}

/// `sim tradeoff`.
pub fn command(args: &TradeoffArgs) -> Result<()> {
    let mut scene = LoadedScene::load(&args.scene, &args.set)?;
    if args.quick {
        let keep = args.set.iter().any(|s| {
            s.trim_start().starts_with("run.distance_m")
                || s.trim_start().starts_with("run.duration_s")
        });
        scene = quick_scene(&scene, keep)?;
    }
    let settings = TradeoffSettings {
        repeats: args.repeats.unwrap_or(if args.quick { 1 } else { 3 }),
        quick: args.quick,
        out_dir: args.out.clone(),
        extra: args
            .variant
            .iter()
            .map(|v| Variant::parse(v).with_context(|| format!("--variant {v}")))
            .collect::<Result<_>>()?,
        critical_speed: args
            .critical_speed
            .as_deref()
            .map(CriticalSpeedSpec::parse)
            .transpose()?,
        jobs: args
            .jobs
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
    };
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::Relaxed));
    }
    let quiet = args.json;
    let mut progress = |line: &str| {
        if !quiet {
            eprintln!("{line}");
        }
    };
    let mut report = run_tradeoff(&scene, &settings, &mut progress, stop)?;
    report.write(&args.out, args.json)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.to_text());
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
            "creep kalker",
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
        assert_eq!(quick.len(), 5);
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
