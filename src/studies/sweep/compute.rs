//! One variant's computation: a run and figures of its summary, or a
//! critical speed. A failing variant gives a failed row with its error; an
//! interrupted one gives no row (a re-run computes it again).

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, Result};

use super::table::{Row, Status, value_text};
use super::{Study, Variant};
use crate::config::sweep::{Compute, Keep};
use crate::error_text::chain_text;
use crate::studies::critical_speed::{CriticalSpeedSettings, study as critical_speed_study};

/// A reference run, computed by the first variant that needs it (its
/// error as text, shared by every variant).
type ReferenceRun = Arc<std::sync::OnceLock<Result<Arc<runtime::results::RunResults>, String>>>;

/// The reference runs of a tradeoff study, by scene text: each computed
/// once per shard.
#[derive(Default)]
pub struct References {
    runs: std::sync::Mutex<std::collections::HashMap<String, ReferenceRun>>,
}

impl References {
    /// The results of `scene` run once (the first caller runs it; the
    /// others wait for it).
    fn get(
        &self,
        scene: &crate::config::scene::LoadedScene,
        stop: &Arc<AtomicBool>,
    ) -> Result<Arc<runtime::results::RunResults>> {
        let cell = {
            let mut m = self
                .runs
                .lock()
                .map_err(|_| anyhow::anyhow!("a worker thread panicked"))?;
            m.entry(scene.text.clone()).or_default().clone()
        };
        let r = cell.get_or_init(|| {
            crate::run::run_scene(scene, &mut |_| {}, Some(stop.clone()))
                .and_then(|o| {
                    let (results, summary) = o.into_parts("the reference run");
                    summary.map(|_| Arc::new(results))
                })
                .map_err(|e| chain_text(&e))
        });
        r.clone()
            .map_err(|e| anyhow::anyhow!("the reference run: {e}"))
    }
}

/// What a computation left: a row, or nothing when it was interrupted.
pub enum Outcome {
    Row(Row),
    Interrupted,
}

/// The value at a dotted path of a JSON summary (`wheelsets.0.peak_lateral_mm`):
/// numbers as they are, booleans as 0/1, anything else (absent, null,
/// text) none. In a list, a part is an index or the `quantity`, `name`,
/// `side` or `wheel` of an element (`curving.arcs.0.wheelsets.0.quantities.sum_y.quasi_static`).
pub fn figure(summary: &serde_json::Value, path: &str) -> Option<f64> {
    let mut v = summary;
    for part in path.split('.') {
        v = match v {
            serde_json::Value::Object(m) => m.get(part)?,
            serde_json::Value::Array(a) => match part.parse::<usize>() {
                Ok(i) => a.get(i)?,
                Err(_) => a.iter().find(|e| {
                    ["quantity", "name", "side", "wheel"]
                        .iter()
                        .any(|k| e.get(k).and_then(serde_json::Value::as_str) == Some(part))
                })?,
            },
            _ => return None,
        };
    }
    match v {
        serde_json::Value::Number(n) => n.as_f64(),
        serde_json::Value::Bool(b) => Some(f64::from(u8::from(*b))),
        _ => None,
    }
}

/// Computes variant `v` of `study`; its kept results go under `dir` (the
/// study folder).
pub fn compute(
    study: &Study,
    v: &Variant,
    dir: &Path,
    stop: &Arc<AtomicBool>,
    references: &References,
) -> Outcome {
    let mut row = Row {
        variant: v.index,
        params: v.params.iter().map(|(_, x)| value_text(x)).collect(),
        status: Status::Ok,
        figures: vec![None; study.layout().figures.len()],
        message: String::new(),
        results: String::new(),
    };
    let result = match &study.file.sweep.compute {
        Compute::Run { figures } => run(study, v, figures, dir, stop, &mut row),
        Compute::CriticalSpeed {
            method,
            min_m_s,
            max_m_s,
            tol_m_s,
        } => critical_speed(
            study,
            v,
            *method,
            (*min_m_s, *max_m_s, *tol_m_s),
            dir,
            stop,
            &mut row,
        ),
        Compute::Tradeoff { reference, skip_s } => {
            tradeoff(study, v, reference, *skip_s, references, stop, &mut row)
        }
    };
    if stop.load(Ordering::Relaxed) {
        return Outcome::Interrupted;
    }
    if let Err(e) = result {
        row.status = Status::Failed;
        row.figures.iter_mut().for_each(|f| *f = None);
        row.message = chain_text(&e);
    }
    Outcome::Row(row)
}

fn kept_name(v: &Variant) -> String {
    format!("runs/variant_{:06}", v.index)
}

fn run(
    study: &Study,
    v: &Variant,
    figures: &[String],
    dir: &Path,
    stop: &Arc<AtomicBool>,
    row: &mut Row,
) -> Result<()> {
    let scene = study.scene_of(v)?;
    let outcome = crate::run::run_scene(&scene, &mut |_| {}, Some(stop.clone()))?;
    if study.file.sweep.keep == Keep::Full {
        let name = format!("{}.h5", kept_name(v));
        let path = dir.join(&name);
        runtime::io::schema::write_results(&path, &outcome.results)
            .with_context(|| format!("writing {}", path.display()))?;
        row.results = name;
    }
    let summary = outcome.into_result("the variant's results")?;
    let json = serde_json::to_value(&summary)?;
    for (slot, path) in row.figures.iter_mut().zip(figures) {
        *slot = figure(&json, path);
    }
    Ok(())
}

fn critical_speed(
    study: &Study,
    v: &Variant,
    method: crate::config::choices::CriticalSpeedMethod,
    (min_m_s, max_m_s, tol_m_s): (f64, f64, f64),
    dir: &Path,
    stop: &Arc<AtomicBool>,
    row: &mut Row,
) -> Result<()> {
    let scene = study.scene_of(v)?;
    let scratch;
    let out_dir = if study.file.sweep.keep == Keep::Full {
        row.results = kept_name(v);
        dir.join(&row.results)
    } else {
        scratch = tempfile::tempdir().context("a scratch folder for the critical speed's runs")?;
        scratch.path().to_path_buf()
    };
    let settings = CriticalSpeedSettings {
        laws: vec![crate::config::sweep::variant_creep_law(&scene)],
        min_m_s,
        max_m_s,
        tol_m_s,
        // The study's threads already run variants side by side.
        jobs: 1,
        methods: vec![method],
        out_dir,
        skip_s: 1.0,
        ramp_deceleration_m_s2: 0.5,
        criterion: crate::studies::cycle_death::HuntingCriterion::All,
    };
    let report = critical_speed_study(&scene, &settings, stop.clone(), &mut |_| {})?;
    let r = report
        .results
        .first()
        .context("the critical-speed study gave no result")?;
    row.figures = vec![
        r.speed_m_s,
        r.frequency_hz,
        r.bracket_m_s.map(|b| b.0),
        r.bracket_m_s.map(|b| b.1),
    ];
    row.message = r.note.clone().unwrap_or_default();
    Ok(())
}

fn tradeoff(
    study: &Study,
    v: &Variant,
    reference: &std::collections::BTreeMap<String, toml::Value>,
    skip_s: f64,
    references: &References,
    stop: &Arc<AtomicBool>,
    row: &mut Row,
) -> Result<()> {
    let scene = study.scene_of(v)?;
    let fine: Vec<crate::config::Variation> = reference
        .iter()
        .map(|(k, x)| crate::config::Variation::Set(k.clone(), x.clone()))
        .collect();
    let reference_scene = scene.varied(&fine).context("the reference's overrides")?;
    let reference_results = references.get(&reference_scene, stop)?;
    let outcome = crate::run::run_scene(&scene, &mut |_| {}, Some(stop.clone()))?;
    let (results, summary) = outcome.into_parts("the variant's results");
    let summary = summary?;
    let e = crate::studies::tradeoff::compare(&reference_results, &results, skip_s)?;
    row.figures = vec![
        Some(e.lateral_max_m * 1e6),
        Some(e.lateral_rms_m * 1e6),
        e.frequency_hz,
        Some(summary.wall_time_s),
        Some(summary.real_time_factor),
        Some(summary.steps as f64),
        Some(summary.rhs_evaluations as f64),
    ];
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_follow_dotted_paths() {
        let s = serde_json::json!({
            "steps": 12, "stopped": null, "ok": true,
            "wheelsets": [{"peak_lateral_mm": 2.5, "safety": {"prudhomme": {"max_sum_y_kn": 31.0}},
                "quantities": [{"quantity": "lateral", "quasi_static": 1.0}, {"quantity": "sum_y", "quasi_static": -6.8}]}]
        });
        assert_eq!(
            figure(&s, "wheelsets.0.quantities.sum_y.quasi_static"),
            Some(-6.8)
        );
        assert_eq!(
            figure(&s, "wheelsets.0.quantities.1.quasi_static"),
            Some(-6.8)
        );
        assert_eq!(
            figure(&s, "wheelsets.0.quantities.y_left.quasi_static"),
            None
        );
        assert_eq!(figure(&s, "steps"), Some(12.0));
        assert_eq!(figure(&s, "ok"), Some(1.0));
        assert_eq!(figure(&s, "wheelsets.0.peak_lateral_mm"), Some(2.5));
        assert_eq!(
            figure(&s, "wheelsets.0.safety.prudhomme.max_sum_y_kn"),
            Some(31.0)
        );
        assert_eq!(figure(&s, "wheelsets.1.peak_lateral_mm"), None);
        assert_eq!(figure(&s, "stopped"), None);
        assert_eq!(figure(&s, "nothing"), None);
    }
}
