//! `sim critical-speed`: the speed at which the hunting of the leading
//! wheelset stops decaying (the paper's definition, §5: "the lowest speed
//! at which oscillations have zero decay"), per creep law, three ways:
//!
//! - **time** (linear critical speed, time domain): the scene is run at
//!   many speeds in parallel; from each lateral history the growth rate σ
//!   (1/s) is fitted to the successive peak amplitudes after the start
//!   transient and before any flange contact (ln A = c + σ t, least
//!   squares); the first speed where σ crosses zero is bracketed and the
//!   bracket narrowed (N-section with as many speeds as jobs) to `tol`,
//!   then interpolated linearly in σ;
//! - **ramp** (nonlinear critical speed): from a flange-limited hunting
//!   cycle at the top speed the references decelerate slowly on a long
//!   ideal straight; per wheelset, its cycle dies where its amplitude last
//!   falls below a quarter of its saturated value; the critical speed is
//!   where every wheelset's cycle has died (`--criterion all`, default) or
//!   the leading one's (`leading`) ([`super::cycle_death`]);
//! - **linear** (eigenvalues): the right-hand side is linearised around the
//!   centred run ([`runtime::multibody::linear`]) and the speed at which the
//!   hunting mode's real part crosses zero is bracketed the same way.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use runtime::multibody::linear::{Mode, linearise};
use runtime::multibody::{InitialConditions, SystemSettings, VehicleSystem};
use runtime::results::RunResults;
use serde::Serialize;

use crate::config::Variation;
use crate::config::scene::CreepLawName;
use crate::config::scene::LoadedScene;
use crate::run::run_scene;
use crate::studies::cycle_death::{CycleDeaths, HuntingCriterion, ramp_deaths};

/// A growth-rate fit of the lateral motion of one wheelset.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RateFit {
    /// Growth rate σ of the peak amplitudes (1/s): > 0 growing.
    pub rate_1_s: f64,
    /// Frequency of the oscillation (Hz), from the spacing of the peaks.
    pub frequency_hz: f64,
    /// Peaks used.
    pub peaks: usize,
    /// Amplitude of the first and last peaks used (m).
    pub first_amplitude_m: f64,
    pub last_amplitude_m: f64,
}

/// Amplitudes below this are integration noise, not motion (m).
const NOISE_M: f64 = 1e-8;

/// Extrema (time, |y|) of a sampled signal, refined by the parabola through
/// the sample and its neighbours.
pub(crate) fn extrema(t: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for i in 1..y.len().saturating_sub(1) {
        let (a, b, c) = (y[i - 1], y[i], y[i + 1]);
        if !(a.is_finite() && b.is_finite() && c.is_finite()) {
            continue;
        }
        let is_max = b > a && b >= c;
        let is_min = b < a && b <= c;
        if !(is_max || is_min) {
            continue;
        }
        // Parabola through the three (equally spaced) samples.
        let den = a - 2.0 * b + c;
        let (dt, peak) = if den != 0.0 {
            let u = 0.5 * (a - c) / den;
            (u, b - 0.25 * (a - c) * u)
        } else {
            (0.0, b)
        };
        let h = t[i + 1] - t[i];
        out.push((t[i] + dt * h, peak.abs()));
    }
    out
}

/// The growth rate of wheelset `ws`'s lateral motion (module docs): peaks
/// after `skip_s` and before the first flange contact of that wheelset,
/// above the noise. `None` when fewer than 3 peaks qualify; then
/// [`RateFit::rate_1_s`] is reported as −∞ if the motion died out and +∞ if
/// it reached the flanges within the transient.
pub fn growth_rate(r: &RunResults, ws: usize, skip_s: f64) -> Option<RateFit> {
    let w = r.wheelsets.get(ws)?;
    let flange_at = (0..r.len())
        .find(|&i| w.wheels[0].flange_contact[i] == 1 || w.wheels[1].flange_contact[i] == 1)
        .map(|i| r.time_s[i])
        .unwrap_or(f64::INFINITY);
    let peaks: Vec<(f64, f64)> = extrema(&r.time_s, &w.lateral_m)
        .into_iter()
        .filter(|(t, a)| *t >= skip_s && *t < flange_at && *a > NOISE_M)
        .collect();
    if peaks.len() < 3 {
        // Decide which way it went from the whole history after the skip.
        let late: Vec<f64> = r
            .time_s
            .iter()
            .zip(&w.lateral_m)
            .filter(|(t, _)| **t >= skip_s)
            .map(|(_, y)| y.abs())
            .collect();
        let max_late = late.iter().copied().fold(0.0, f64::max);
        let rate = if flange_at.is_finite() {
            f64::INFINITY
        } else if max_late <= NOISE_M * 10.0 || late.last().is_some_and(|v| *v < 1e-3 * max_late) {
            f64::NEG_INFINITY
        } else {
            return None;
        };
        return Some(RateFit {
            rate_1_s: rate,
            frequency_hz: f64::NAN,
            peaks: peaks.len(),
            first_amplitude_m: peaks.first().map_or(f64::NAN, |p| p.1),
            last_amplitude_m: peaks.last().map_or(f64::NAN, |p| p.1),
        });
    }
    // Least squares of ln A on t.
    let n = peaks.len() as f64;
    let (st, sl) = peaks
        .iter()
        .fold((0.0, 0.0), |(a, b), (t, amp)| (a + t, b + amp.ln()));
    let (mt, ml) = (st / n, sl / n);
    let (num, den) = peaks.iter().fold((0.0, 0.0), |(a, b), (t, amp)| {
        (a + (t - mt) * (amp.ln() - ml), b + (t - mt) * (t - mt))
    });
    let spacing = (peaks[peaks.len() - 1].0 - peaks[0].0) / (peaks.len() - 1) as f64;
    Some(RateFit {
        rate_1_s: num / den,
        frequency_hz: 0.5 / spacing,
        peaks: peaks.len(),
        first_amplitude_m: peaks[0].1,
        last_amplitude_m: peaks[peaks.len() - 1].1,
    })
}

/// One evaluated speed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpeedSample {
    pub speed_m_s: f64,
    /// Growth rate (1/s): fitted (time), or the hunting eigenvalue's real
    /// part (linear).
    pub rate_1_s: f64,
    pub frequency_hz: f64,
    /// Damping ratio of the hunting mode, ζ = −σ/√(σ² + ω²) with ω = 2πf
    /// (the eigenvalue σ ± iω = −ζω₀ ± iω₀√(1 − ζ²); > 0: decaying, < 0:
    /// growing; NaN where σ or f is unknown).
    pub damping_ratio: f64,
    /// Results file of the run (time method).
    pub results: Option<String>,
}

impl SpeedSample {
    /// A sample with its damping ratio computed from `rate_1_s` and
    /// `frequency_hz`.
    pub fn new(speed_m_s: f64, rate_1_s: f64, frequency_hz: f64, results: Option<String>) -> Self {
        Self {
            speed_m_s,
            rate_1_s,
            frequency_hz,
            damping_ratio: damping_ratio(rate_1_s, frequency_hz),
            results,
        }
    }
}

/// Damping ratio ζ = −σ/√(σ² + ω²), ω = 2πf, of a mode with growth rate σ
/// (1/s) and damped frequency f (Hz).
pub fn damping_ratio(rate_1_s: f64, frequency_hz: f64) -> f64 {
    let omega = std::f64::consts::TAU * frequency_hz;
    -rate_1_s / rate_1_s.hypot(omega)
}

pub use crate::config::choices::CriticalSpeedMethod;

/// The critical speed of one law by one method.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CriticalSpeed {
    pub creep_law: CreepLawName,
    pub method: CriticalSpeedMethod,
    /// `None` when the rate does not cross zero in the range.
    pub speed_m_s: Option<f64>,
    pub speed_km_h: Option<f64>,
    /// Final bracket (m/s).
    pub bracket_m_s: Option<(f64, f64)>,
    /// Hunting frequency at the critical speed (Hz); the damping ratio of
    /// the hunting mode at every speed evaluated is in `samples`.
    pub frequency_hz: Option<f64>,
    /// Every speed evaluated, sorted.
    pub samples: Vec<SpeedSample>,
    /// What happened when no crossing was found.
    pub note: Option<String>,
    /// Ramp: every wheelset's cycle death, the criterion and the wheelset
    /// that hunts last.
    pub cycle_deaths: Option<CycleDeaths>,
}

impl CriticalSpeed {
    /// The result of a bracketing search: the zero crossing of the rate
    /// interpolated in the final bracket `br` (m/s), if there is one.
    fn bracketed(
        creep_law: CreepLawName,
        method: CriticalSpeedMethod,
        samples: Vec<SpeedSample>,
        br: Option<(f64, f64)>,
        note: Option<String>,
    ) -> CriticalSpeed {
        let (speed, freq) = match br {
            Some(b) => {
                let (v, f) = interpolate(&samples, b);
                (Some(v), Some(f))
            }
            None => (None, None),
        };
        CriticalSpeed {
            creep_law,
            method,
            speed_m_s: speed,
            speed_km_h: speed.map(|v| v * 3.6),
            bracket_m_s: br,
            frequency_hz: freq,
            samples,
            note,
            cycle_deaths: None,
        }
    }
}

/// Search settings (checked by [`CriticalSpeedSettings::validate`]).
#[derive(Debug, Clone, PartialEq)]
pub struct CriticalSpeedSettings {
    pub laws: Vec<CreepLawName>,
    pub min_m_s: f64,
    pub max_m_s: f64,
    pub tol_m_s: f64,
    pub jobs: usize,
    pub methods: Vec<CriticalSpeedMethod>,
    pub out_dir: PathBuf,
    /// Start transient skipped by the rate fit (s).
    pub skip_s: f64,
    /// Deceleration of the ramp (m/s²).
    pub ramp_deceleration_m_s2: f64,
    /// Whose cycles must have died (ramp).
    pub criterion: HuntingCriterion,
}

impl CriticalSpeedSettings {
    pub fn validate(&self) -> Result<()> {
        if !(self.min_m_s > 0.0 && self.max_m_s > self.min_m_s && self.max_m_s.is_finite()) {
            bail!(
                "speed range {} … {} m/s: need 0 < min < max",
                self.min_m_s,
                self.max_m_s
            );
        }
        if !(self.tol_m_s > 0.0 && self.tol_m_s.is_finite()) {
            bail!("tolerance {} m/s must be > 0", self.tol_m_s);
        }
        if self.jobs == 0 {
            bail!("jobs must be >= 1");
        }
        for (i, m) in self.methods.iter().enumerate() {
            if self.methods[..i].contains(m) {
                bail!("method '{m}' is given twice");
            }
        }
        for (i, law) in self.laws.iter().enumerate() {
            if self.laws[..i].contains(law) {
                bail!("creep law '{law}' is given twice");
            }
        }
        if !(self.ramp_deceleration_m_s2 > 0.0 && self.ramp_deceleration_m_s2.is_finite()) {
            bail!(
                "ramp deceleration {} m/s² must be > 0",
                self.ramp_deceleration_m_s2
            );
        }
        Ok(())
    }
}

/// The samples of a search, its final bracket (m/s) and a note when no
/// crossing was found.
type Bracketed = (Vec<SpeedSample>, Option<(f64, f64)>, Option<String>);

/// Narrows the first sign change (− → +) of `rate(v)` on [min, max] to
/// `tol`, evaluating `jobs` speeds at a time (in parallel). Returns the
/// samples and the bracket.
fn bracket(
    settings: &CriticalSpeedSettings,
    rate: &(dyn Fn(f64) -> Result<SpeedSample> + Sync),
    stop: &AtomicBool,
) -> Result<Bracketed> {
    let jobs = settings.jobs.max(1);
    let n0 = jobs.max(6);
    let grid: Vec<f64> = (0..n0)
        .map(|i| {
            settings.min_m_s + (settings.max_m_s - settings.min_m_s) * i as f64 / (n0 - 1) as f64
        })
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .context("thread pool")?;
    let eval = |speeds: &[f64]| -> Result<Vec<SpeedSample>> {
        pool.install(|| speeds.par_iter().map(|&v| rate(v)).collect())
    };
    let mut samples = eval(&grid)?;
    let crossing = |s: &[SpeedSample]| -> Option<(f64, f64)> {
        let mut sorted: Vec<&SpeedSample> = s.iter().collect();
        sorted.sort_by(|a, b| a.speed_m_s.total_cmp(&b.speed_m_s));
        sorted
            .windows(2)
            .find(|w| w[0].rate_1_s < 0.0 && w[1].rate_1_s >= 0.0)
            .map(|w| (w[0].speed_m_s, w[1].speed_m_s))
    };
    let Some(mut br) = crossing(&samples) else {
        let note = if samples.iter().all(|s| s.rate_1_s < 0.0) {
            format!(
                "stable over the whole range: critical speed above {} m/s",
                settings.max_m_s
            )
        } else if samples.iter().all(|s| s.rate_1_s >= 0.0) {
            format!(
                "unstable over the whole range: critical speed below {} m/s",
                settings.min_m_s
            )
        } else {
            "no stable-to-unstable crossing found".to_string()
        };
        return Ok((samples, None, Some(note)));
    };
    while br.1 - br.0 > settings.tol_m_s && !stop.load(std::sync::atomic::Ordering::Relaxed) {
        let k = jobs.max(2);
        let inner: Vec<f64> = (1..=k)
            .map(|i| br.0 + (br.1 - br.0) * i as f64 / (k + 1) as f64)
            .collect();
        let new = eval(&inner)?;
        samples.extend(new);
        let within: Vec<SpeedSample> = samples
            .iter()
            .filter(|s| s.speed_m_s >= br.0 - 1e-12 && s.speed_m_s <= br.1 + 1e-12)
            .cloned()
            .collect();
        match crossing(&within) {
            Some(b) => br = b,
            None => break,
        }
    }
    samples.sort_by(|a, b| a.speed_m_s.total_cmp(&b.speed_m_s));
    Ok((samples, Some(br), None))
}

fn interpolate(samples: &[SpeedSample], br: (f64, f64)) -> (f64, f64) {
    let a = samples.iter().find(|s| s.speed_m_s == br.0);
    let b = samples.iter().find(|s| s.speed_m_s == br.1);
    match (a, b) {
        (Some(a), Some(b)) if a.rate_1_s.is_finite() && b.rate_1_s.is_finite() => {
            let f = -a.rate_1_s / (b.rate_1_s - a.rate_1_s);
            (
                a.speed_m_s + f * (b.speed_m_s - a.speed_m_s),
                a.frequency_hz + f * (b.frequency_hz - a.frequency_hz),
            )
        }
        (Some(a), Some(b)) => (
            0.5 * (a.speed_m_s + b.speed_m_s),
            if a.frequency_hz.is_finite() {
                a.frequency_hz
            } else {
                b.frequency_hz
            },
        ),
        _ => (0.5 * (br.0 + br.1), f64::NAN),
    }
}

/// The whole study: every law by every method, in law order (the ramps,
/// one long run per law, side by side on `settings.jobs` threads; the time
/// and linear methods spread their speeds over the threads themselves).
/// `progress` is told what starts.
pub fn study(
    scene: &LoadedScene,
    settings: &CriticalSpeedSettings,
    stop: Arc<AtomicBool>,
    progress: &mut dyn FnMut(&str),
) -> Result<CriticalSpeedReport> {
    settings.validate()?;
    let laws = &settings.laws;
    let mut report = CriticalSpeedReport {
        scene: scene.origin.clone(),
        results: Vec::new(),
        files: Vec::new(),
    };
    let ramps: Vec<Result<CriticalSpeed>> = if settings.methods.contains(&CriticalSpeedMethod::Ramp)
    {
        progress(&format!(
            "{}: ramp …",
            laws.iter()
                .map(|l| l.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ));
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(settings.jobs.max(1))
            .build()
            .context("starting the worker threads")?;
        pool.install(|| {
            laws.par_iter()
                .map(|law| ramp(scene, *law, settings, stop.clone()))
                .collect()
        })
    } else {
        Vec::new()
    };
    // In law order, one per law (validate() refuses a law given twice).
    let mut ramps = ramps.into_iter();
    for law in laws {
        for method in &settings.methods {
            if *method != CriticalSpeedMethod::Ramp {
                progress(&format!("{law}, {method} …"));
            }
            let r = match method {
                CriticalSpeedMethod::Time => time_domain(scene, *law, settings, stop.clone()),
                CriticalSpeedMethod::Ramp => ramps.next().context("one ramp per law")?,
                CriticalSpeedMethod::Linear => linear_domain(scene, *law, settings, stop.clone()),
            }
            .with_context(|| format!("{law}, {method}"))?;
            report.results.push(r);
        }
    }
    Ok(report)
}

/// Time-domain critical speed of one law (module docs).
pub fn time_domain(
    scene: &LoadedScene,
    law: CreepLawName,
    settings: &CriticalSpeedSettings,
    stop: Arc<AtomicBool>,
) -> Result<CriticalSpeed> {
    let dir = settings.out_dir.join("runs");
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let rate = |v: f64| -> Result<SpeedSample> {
        let s = scene.varied(&[Variation::Speed(v), Variation::CreepLaw(law)])?;
        let output = dir.join(format!("{law}_{v:.4}.h5"));
        // A failed run (e.g. derailment of a violently unstable run) counts
        // as growing: its results so far are used (and written, for the user).
        let outcome = run_scene(&s, &mut |_| {}, Some(stop.clone()))
            .with_context(|| format!("run at {v} m/s"))?;
        runtime::io::schema::write_results(&output, &outcome.results)
            .with_context(|| format!("writing the run at {v} m/s to {}", output.display()))?;
        let fit = growth_rate(&outcome.results, 0, settings.skip_s);
        Ok(SpeedSample::new(
            v,
            fit.map_or(f64::NAN, |f| f.rate_1_s),
            fit.map_or(f64::NAN, |f| f.frequency_hz),
            Some(output.display().to_string()),
        ))
    };
    let (samples, br, note) = bracket(settings, &rate, &stop)?;
    Ok(CriticalSpeed::bracketed(
        law,
        CriticalSpeedMethod::Time,
        samples,
        br,
        note,
    ))
}

/// The hunting mode of the scene's vehicle at speed `v` with `law`.
pub fn hunting_mode(scene: &LoadedScene, law: CreepLawName, v: f64) -> Result<Option<Mode>> {
    let s = scene.varied(&[Variation::Speed(v), Variation::CreepLaw(law)])?;
    let (track, _) = crate::session::track::load_track(&s)?;
    let vfile = s.vehicle_file()?;
    // With `track.keep_longest_stretch` the profiles' warnings are those
    // every run of the scene reports in its summary.
    let (vehicle, _) = crate::session::vehicle::vehicle_model(
        &vfile,
        &track,
        &s.path(&s.scene.track.rail_profile),
        s.scene.track.keep_longest_stretch,
    )?;
    let mut settings: SystemSettings =
        crate::session::settings::system_settings(&s, &vfile, &track)?;
    // The linearisation is about a steady run at v: no speed ramp, no axle
    // torque (either would make the centred run non-stationary).
    settings.speed_m_s = v;
    settings.deceleration_m_s2 = 0.0;
    settings.acceleration_m_s2 = 0.0;
    settings.final_speed_m_s = None;
    settings.axle_torque_nm = 0.0;
    settings.axle_brake_torque_nm = 0.0;
    let (mut system, y0) =
        VehicleSystem::assemble(&track, &vehicle, settings, InitialConditions::default())?;
    let lin = linearise(&mut system, &y0)?;
    Ok(lin.hunting())
}

/// Linear (eigenvalue) critical speed of one law.
pub fn linear_domain(
    scene: &LoadedScene,
    law: CreepLawName,
    settings: &CriticalSpeedSettings,
    stop: Arc<AtomicBool>,
) -> Result<CriticalSpeed> {
    let rate = |v: f64| -> Result<SpeedSample> {
        let m = hunting_mode(scene, law, v)?;
        Ok(SpeedSample::new(
            v,
            m.map_or(f64::NAN, |m| m.eigenvalue.re),
            m.map_or(f64::NAN, |m| m.frequency_hz),
            None,
        ))
    };
    let (samples, br, note) = bracket(settings, &rate, &stop)?;
    Ok(CriticalSpeed::bracketed(
        law,
        CriticalSpeedMethod::Linear,
        samples,
        br,
        note,
    ))
}

/// Nonlinear critical speed by a speed ramp (module docs).
pub fn ramp(
    scene: &LoadedScene,
    law: CreepLawName,
    settings: &CriticalSpeedSettings,
    stop: Arc<AtomicBool>,
) -> Result<CriticalSpeed> {
    let (v0, v1, a) = (
        settings.max_m_s,
        settings.min_m_s,
        settings.ramp_deceleration_m_s2,
    );
    // Distance covered from v0 down to v1, plus the run-up at v0.
    let distance = (v0 * v0 - v1 * v1) / (2.0 * a);
    let length = distance + 50.0 + scene.scene.initial.s_m + 20.0;
    let mut extra = vec![Variation::Speed(v0), Variation::CreepLaw(law)];
    extra.extend(Variation::ramp_on_straight(
        &scene.scene,
        a,
        distance,
        length,
    ));
    let s = scene.varied(&extra)?;
    let dir = settings.out_dir.join("runs");
    std::fs::create_dir_all(&dir)?;
    let output = dir.join(format!("{law}_ramp.h5"));
    let ran = run_scene(&s, &mut |_| {}, Some(stop)).and_then(|outcome| {
        runtime::io::schema::write_results(&output, &outcome.results)
            .with_context(|| format!("writing the ramp run {}", output.display()))?;
        let (results, summary) = outcome.into_parts(&output.display().to_string());
        summary.map(|_| results)
    });
    let r = match ran {
        Ok(r) => r,
        Err(e) => {
            // A derailed ramp (e.g. Kalker's unsaturated forces climbing the
            // flange) has no limit cycle to follow down.
            return Ok(CriticalSpeed {
                creep_law: law,
                method: CriticalSpeedMethod::Ramp,
                speed_m_s: None,
                speed_km_h: None,
                bracket_m_s: None,
                frequency_hz: None,
                samples: vec![],
                note: Some(format!(
                    "the ramp run failed: {}",
                    crate::error_text::chain_text(&e)
                )),
                cycle_deaths: None,
            });
        }
    };
    let (deaths, peaks) = ramp_deaths(&r, v0, v1, a, settings.criterion);
    // The hunting frequency near the death of the wheelset that decides.
    let freq = deaths
        .last_hunting_index
        .zip(deaths.speed_m_s)
        .and_then(|(i, _)| {
            let w = &deaths.wheelsets[i];
            let t = w.death_time_s?;
            let threshold = crate::studies::cycle_death::DEATH_FRACTION * w.saturated_mm * 1e-3;
            let near: Vec<_> = peaks[i]
                .iter()
                .filter(|q| (q.t_s - t).abs() < 2.0 && q.amplitude_m > 0.5 * threshold)
                .collect();
            (near.len() >= 3)
                .then(|| 0.5 * (near.len() - 1) as f64 / (near[near.len() - 1].t_s - near[0].t_s))
        });
    let (speed, note) = (deaths.speed_m_s, deaths.note.clone());
    Ok(CriticalSpeed {
        creep_law: law,
        method: CriticalSpeedMethod::Ramp,
        speed_m_s: speed,
        speed_km_h: speed.map(|v| v * 3.6),
        bracket_m_s: None,
        frequency_hz: freq,
        samples: vec![SpeedSample::new(
            v0,
            f64::NAN,
            f64::NAN,
            Some(output.display().to_string()),
        )],
        note,
        cycle_deaths: Some(deaths),
    })
}

/// Everything `sim critical-speed` reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CriticalSpeedReport {
    pub scene: String,
    pub results: Vec<CriticalSpeed>,
    pub files: Vec<String>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use runtime::results::{WheelsetSample, WheelsetSeries};

    fn synthetic(rate: f64, freq: f64, flange_after_s: f64) -> RunResults {
        let mut r = RunResults::with_wheelsets(["ws"]);
        let _ = WheelsetSeries::new("x");
        for i in 0..4000 {
            let t = i as f64 * 0.005;
            let y = 0.002 * (rate * t).exp() * (2.0 * std::f64::consts::PI * freq * t).sin();
            let mut s = WheelsetSample {
                lateral_m: y,
                ..Default::default()
            };
            if t > flange_after_s {
                s.wheels[0].zones[1].in_contact = true;
            }
            r.push(t, &[s]).unwrap();
        }
        r
    }

    #[test]
    fn damping_ratio_of_known_modes() {
        // λ = −ζω₀ ± iω₀√(1 − ζ²) with ζ = 0.1, ω₀ = 2π·3 rad/s.
        let (zeta, w0) = (0.1, std::f64::consts::TAU * 3.0);
        let (sigma, f) = (
            -zeta * w0,
            w0 * (1.0f64 - zeta * zeta).sqrt() / std::f64::consts::TAU,
        );
        assert!((damping_ratio(sigma, f) - zeta).abs() < 1e-12);
        assert!(
            (damping_ratio(-sigma, f) + zeta).abs() < 1e-12,
            "growing: ζ < 0"
        );
        assert_eq!(damping_ratio(0.0, 2.0), 0.0);
        assert!(damping_ratio(f64::NAN, 2.0).is_nan());
        let s = SpeedSample::new(80.0, sigma, f, None);
        assert!((s.damping_ratio - zeta).abs() < 1e-12);
    }

    #[test]
    fn rate_and_frequency_of_a_damped_sine() {
        for rate in [-0.8, -0.1, 0.0, 0.3] {
            let r = synthetic(rate, 2.5, f64::INFINITY);
            let f = growth_rate(&r, 0, 1.0).unwrap();
            assert!((f.rate_1_s - rate).abs() < 2e-3, "{rate}: {f:?}");
            assert!((f.frequency_hz - 2.5).abs() < 1e-3, "{f:?}");
        }
    }

    #[test]
    fn peaks_after_a_flange_contact_are_ignored() {
        // Growing until 6 s, then (pretend) flange contact: the fit uses the
        // peaks before it only.
        let r = synthetic(0.4, 2.0, 6.0);
        let f = growth_rate(&r, 0, 1.0).unwrap();
        assert!((f.rate_1_s - 0.4).abs() < 2e-3, "{f:?}");
        // Flange within the transient: +∞.
        let r = synthetic(0.4, 2.0, 0.5);
        assert_eq!(growth_rate(&r, 0, 1.0).unwrap().rate_1_s, f64::INFINITY);
    }

    #[test]
    fn settings_name_the_violated_rule() {
        let good = CriticalSpeedSettings {
            laws: vec![CreepLawName::Kalker, CreepLawName::Polach],
            min_m_s: 10.0,
            max_m_s: 100.0,
            tol_m_s: 0.1,
            jobs: 2,
            methods: vec![CriticalSpeedMethod::Time, CriticalSpeedMethod::Ramp],
            out_dir: PathBuf::new(),
            skip_s: 0.0,
            ramp_deceleration_m_s2: 0.5,
            criterion: HuntingCriterion::All,
        };
        assert!(good.validate().is_ok());
        let err = |edit: fn(&mut CriticalSpeedSettings)| {
            let mut s = good.clone();
            edit(&mut s);
            s.validate().unwrap_err().to_string()
        };
        assert!(
            err(|s| s.methods.push(CriticalSpeedMethod::Ramp))
                .contains("method 'ramp' is given twice")
        );
        assert!(
            err(|s| s.laws.push(CreepLawName::Kalker))
                .contains("creep law 'kalker' is given twice")
        );
        let e = "eigen".parse::<CriticalSpeedMethod>().unwrap_err();
        assert!(
            e.contains("'eigen' is not one of time, ramp, linear"),
            "{e}"
        );
        assert!(err(|s| s.max_m_s = 5.0).contains("need 0 < min < max"));
        assert!(err(|s| s.jobs = 0).contains("jobs"));
    }

    #[test]
    fn bracketing_finds_the_first_crossing() {
        let settings = CriticalSpeedSettings {
            laws: vec![],
            min_m_s: 10.0,
            max_m_s: 100.0,
            tol_m_s: 0.05,
            jobs: 2,
            methods: vec![CriticalSpeedMethod::Time],
            out_dir: PathBuf::new(),
            skip_s: 0.0,
            ramp_deceleration_m_s2: 1.0,
            criterion: HuntingCriterion::All,
        };
        let rate = |v: f64| -> Result<SpeedSample> {
            Ok(SpeedSample::new(v, (v - 63.7) * 0.1, 2.0, None))
        };
        let (samples, br, _) = bracket(&settings, &rate, &AtomicBool::new(false)).unwrap();
        let br = br.unwrap();
        assert!(
            br.1 - br.0 <= 0.05 && br.0 <= 63.7 && br.1 >= 63.7,
            "{br:?}"
        );
        let (v, _) = interpolate(&samples, br);
        assert!((v - 63.7).abs() < 1e-9, "{v}");
    }
}
