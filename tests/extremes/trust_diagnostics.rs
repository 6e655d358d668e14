//! Trust in what `sim run` says of a run (issue 12): a flange passed
//! through its rail with the flange search off, wheels in the air, a
//! broken energy balance and a numerical blow-up are each named — in the
//! summary (text and JSON) and the results file's `status` and `warnings`
//! attributes — and a unit slip in the contact material is refused before
//! the run (docs/guide/extremes-and-diagnostics.md, "Warnings" and "Blow-up
//! or derailment"). Every run is a second or less of simulated time.

use std::path::{Path, PathBuf};

use runtime::io::schema::read_results;
use runtime::results::RunResults;
use serde_json::Value;

use super::common::*;

/// One `sim run` of a shipped scene with `--json`.
struct Run {
    /// `--json` summary when the run completed.
    summary: Option<Value>,
    stderr: String,
    h5: PathBuf,
}

impl Run {
    fn summary(&self) -> &Value {
        self.summary
            .as_ref()
            .unwrap_or_else(|| panic!("the run failed:\n{}", self.stderr))
    }

    fn results(&self) -> RunResults {
        read_results(&self.h5).unwrap_or_else(|e| panic!("{e}"))
    }

    /// The kinds of the summary's warnings.
    fn warning_kinds(&self) -> Vec<String> {
        self.summary()["warnings"]
            .as_array()
            .expect("warnings")
            .iter()
            .map(|w| w["kind"].as_str().expect("kind").to_string())
            .collect()
    }
}

/// `sim run tables/scenes/SCENE --json` with `overrides` (an ideal
/// straight when `straight_m` is given).
fn sim_run(dir: &Path, name: &str, scene: &str, overrides: &[&str]) -> Run {
    let h5 = dir.join(format!("{name}.h5"));
    let mut cmd = sim();
    cmd.env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .arg("run")
        .arg(shipped(&format!("scenes/{scene}")))
        .arg("-o")
        .arg(&h5)
        .args(["--no-plots", "--json", "--quiet"]);
    for o in overrides {
        cmd.args(["--set", o]);
    }
    let o = run(&mut cmd);
    Run {
        summary: o
            .status
            .success()
            .then(|| serde_json::from_str(&stdout(&o)).expect("JSON summary")),
        stderr: stderr(&o),
        h5,
    }
}

/// The wheelset on an ideal 60 m straight for `duration` seconds.
const WHEELSET_60M: [&str; 3] = [
    "track.centerline=",
    "track.straight_m=60",
    "run.distance_m=",
];

fn text_summary(dir: &Path, scene: &str, overrides: &[&str]) -> String {
    let mut cmd = sim();
    cmd.env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .arg("run")
        .arg(shipped(&format!("scenes/{scene}")))
        .arg("-o")
        .arg(dir.join("text.h5"))
        .args(["--no-plots", "--quiet"]);
    for o in overrides {
        cmd.args(["--set", o]);
    }
    let o = run(&mut cmd);
    assert!(o.status.success(), "{}", stderr(&o));
    stdout(&o)
}

#[test]
fn trust_a_flange_passed_through_with_the_search_off_is_a_warning() {
    let dir = scratch("trust_diag_flange_off");
    // 15 mm from the centre with the flange search off: the flangeway
    // clearance is 6.8 mm, and nothing stops the wheelset there.
    let mut o: Vec<&str> = WHEELSET_60M.to_vec();
    o.extend([
        "run.duration_s=1",
        "contact.flange=off",
        "initial.lateral_m=0.015",
    ]);
    let r = sim_run(&dir, "off", "wheelset_straight.toml", &o);
    let ws = &r.summary()["wheelsets"][0];
    assert_eq!(ws["flange_contact_left_s"].as_f64(), Some(0.0));
    assert!(ws["peak_lateral_mm"].as_f64().unwrap() > 15.0);
    assert!(
        r.warning_kinds()
            .contains(&"flange_passed_through".to_string()),
        "{:?}",
        r.summary()["warnings"]
    );
    let res = r.results();
    let status = res.attribute_text("status").expect("status");
    assert!(
        status.starts_with("completed with warnings: flange passed through its rail"),
        "{status}"
    );
    let warnings = res.attribute_text("warnings").expect("warnings attribute");
    assert!(
        warnings.contains("beyond its flangeway clearance 6.8")
            && warnings.contains("contact.flange = \"auto\""),
        "{warnings}"
    );
    let text = text_summary(&dir, "wheelset_straight.toml", &o);
    assert!(
        text.contains("WARNING (flange passed through its rail): wheelset 'wheelset'"),
        "{text}"
    );
    // Within the clearance, the same setting warns of nothing.
    let mut o: Vec<&str> = WHEELSET_60M.to_vec();
    o.extend(["run.duration_s=0.3", "contact.flange=off"]);
    let r = sim_run(&dir, "off_centred", "wheelset_straight.toml", &o);
    assert!(
        r.warning_kinds().is_empty(),
        "{:?}",
        r.summary()["warnings"]
    );
    assert_eq!(r.results().attribute_text("status"), Some("completed"));
    assert_eq!(r.results().attribute_text("warnings"), Some("none"));
    // Pushed through to the derailment check, it is named for what it is.
    let mut o: Vec<&str> = WHEELSET_60M.to_vec();
    o.extend([
        "run.duration_s=1",
        "contact.flange=off",
        "load.lateral_force_n=20000",
    ]);
    let r = sim_run(&dir, "off_pushed", "wheelset_straight.toml", &o);
    assert!(r.summary.is_none());
    assert!(
        r.stderr
            .contains("ran through its flange with the flange search off, not a derailment"),
        "{}",
        r.stderr
    );
}

/// Y/Q over the 2 m windows as the summary judged it before: the mean of
/// every finite sample of the window, however few.
fn old_max_2m_mean(yq: &[f64], d: &[f64]) -> f64 {
    let mut best = f64::NEG_INFINITY;
    for i in 0..d.len() {
        if d[i] - d[0] < 2.0 {
            continue;
        }
        let window: Vec<f64> = (0..=i)
            .filter(|&j| d[j] > d[i] - 2.0 && yq[j].is_finite())
            .map(|j| yq[j])
            .collect();
        if !window.is_empty() {
            best = best.max(window.iter().sum::<f64>() / window.len() as f64);
        }
    }
    best
}

/// The largest mean over the windows the criterion accepts (EN 14363's 2 m
/// sliding mean over the loaded samples; at least 3 loaded, more than
/// half of the window's samples), recomputed from the results file.
fn valid_max_2m_mean(yq: &[f64], q: &[f64], d: &[f64]) -> Option<f64> {
    let mut best: Option<f64> = None;
    for i in 0..d.len() {
        if d[i] - d[0] < 2.0 {
            continue;
        }
        let inside: Vec<usize> = (0..=i).filter(|&j| d[j] > d[i] - 2.0).collect();
        let loaded: Vec<f64> = inside
            .iter()
            .filter(|&&j| q[j] > 0.0 && yq[j].is_finite())
            .map(|&j| yq[j])
            .collect();
        if loaded.len() >= 3 && 2 * loaded.len() > inside.len() {
            let m = loaded.iter().sum::<f64>() / loaded.len() as f64;
            best = Some(best.map_or(m, |b: f64| b.max(m)));
        }
    }
    best
}

#[test]
fn trust_airborne_wheels_are_reported_and_cannot_make_a_verdict() {
    let dir = scratch("trust_diag_airborne");
    // The unsuspended wheelset at 100 m/s bounces: each wheel is in the
    // air in about two samples of three.
    let o = [
        "initial.speed_m_s=100",
        "track.centerline=",
        "track.straight_m=100",
        "run.distance_m=80",
    ];
    let r = sim_run(&dir, "v100", "wheelset_straight.toml", &o);
    let res = r.results();
    let ws = &res.wheelsets[0];
    let mut old_flag = false;
    for (k, nadal) in r.summary()["wheelsets"][0]["nadal"]
        .as_array()
        .expect("nadal")
        .iter()
        .enumerate()
    {
        let wheel = &ws.wheels[k];
        let airborne = nadal["airborne_fraction"].as_f64().expect("fraction");
        let counted = wheel
            .q_n
            .iter()
            .filter(|q| q.is_nan() || **q <= 0.0)
            .count();
        assert!(
            (airborne - counted as f64 / res.len() as f64).abs() < 1e-12,
            "{airborne} against {counted} of {}",
            res.len()
        );
        assert!(airborne > 0.3, "wheel {k}: airborne {airborne}");
        let limit = nadal["nadal_limit"].as_f64().expect("limit");
        let valid = valid_max_2m_mean(&wheel.y_over_q, &wheel.q_n, &ws.distance_m);
        let reported = nadal["max_y_over_q_2m"].as_f64();
        assert_eq!(reported.is_some(), valid.is_some());
        if let (Some(a), Some(b)) = (reported, valid) {
            assert!((a - b).abs() < 1e-9, "wheel {k}: {a} against {b}");
        }
        assert_eq!(
            nadal["derailment_risk"].as_bool(),
            Some(valid.is_some_and(|m| m > limit)),
            "wheel {k}: {nadal}"
        );
        assert!(nadal["valid_windows"].as_u64() < nadal["windows"].as_u64());
        // Before, a window of one loaded sample was a "2 m mean".
        old_flag |= old_max_2m_mean(&wheel.y_over_q, &ws.distance_m) > limit;
        eprintln!(
            "wheel {k}: airborne {:.1} %, valid windows {} of {}, 2 m mean {reported:?} (all finite samples: {:.3}), verdict {}",
            100.0 * airborne,
            nadal["valid_windows"],
            nadal["windows"],
            old_max_2m_mean(&wheel.y_over_q, &ws.distance_m),
            nadal["verdict"]
        );
    }
    assert!(
        old_flag,
        "the run no longer shows the spike the old mean flagged"
    );
    assert!(r.warning_kinds().contains(&"airborne".to_string()));
    assert!(
        res.attribute_text("status")
            .is_some_and(|s| s.contains("wheels airborne")),
        "{:?}",
        res.attribute_text("status")
    );
    let text = text_summary(&dir, "wheelset_straight.toml", &o);
    assert!(
        text.contains("% of samples") && text.contains("windows valid"),
        "{text}"
    );
    assert!(text.contains("WARNING (wheels airborne)"), "{text}");
}

#[test]
fn trust_a_step_too_large_shows_in_the_energy_balance() {
    let dir = scratch("trust_diag_energy");
    // The bogie at 20 m/s: RK4 is stable to about 1.1 ms; at 1.2 ms it
    // runs, but creep dissipation and residual grow fourfold.
    let base = ["initial.speed_m_s=20", "run.distance_m=30"];
    let mut o = base.to_vec();
    o.push("run.step_s=1.2e-3");
    let coarse = sim_run(&dir, "rk4_1_2ms", "bogie_straight.toml", &o);
    let e = &coarse.summary()["energy"];
    eprintln!("RK4 1.2 ms: {e}");
    assert!(
        coarse
            .warning_kinds()
            .contains(&"energy_residual".to_string()),
        "{:?}",
        coarse.summary()["warnings"]
    );
    let w = coarse.results();
    let w = w.attribute_text("warnings").expect("warnings");
    assert!(w.contains("reduce run.step_s (now 1.2e-3 s)"), "{w}");
    let mut o = base.to_vec();
    o.push("run.step_s=5e-4");
    let fine = sim_run(&dir, "rk4_0_5ms", "bogie_straight.toml", &o);
    eprintln!("RK4 0.5 ms: {}", fine.summary()["energy"]);
    assert!(
        !fine
            .warning_kinds()
            .contains(&"energy_residual".to_string()),
        "{:?}",
        fine.summary()["warnings"]
    );
    assert_eq!(fine.results().attribute_text("status"), Some("completed"));
}

#[test]
fn trust_a_numerical_blow_up_is_not_called_a_derailment() {
    let dir = scratch("trust_diag_blow_up");
    // RK4 at 10 ms on the unsuspended wheelset runs away within 0.2 s:
    // |y| passes 50 mm with the wheelset rolled half a radian and 40 cm up.
    let mut o: Vec<&str> = WHEELSET_60M.to_vec();
    o.extend(["run.duration_s=0.5", "run.step_s=1e-2"]);
    let r = sim_run(&dir, "rk4_10ms", "wheelset_straight.toml", &o);
    assert!(r.summary.is_none(), "the run must fail");
    for needle in [
        "numerical blow-up, not a derailment",
        "signs of a numerical blow-up",
        "rolled",
        "likely cause: a step too large",
        "reduce run.step_s (now 1e-2 s)",
        "the results so far are in",
    ] {
        assert!(r.stderr.contains(needle), "{needle} missing:\n{}", r.stderr);
    }
    assert!(!r.stderr.contains(" derailed at"), "{}", r.stderr);
    let res = r.results();
    let status = res.attribute_text("status").expect("status");
    assert!(
        status.starts_with("failed: numerical blow-up, not a derailment")
            && status.contains("likely cause"),
        "{status}"
    );
    assert!(
        res.attribute_text("diagnostic")
            .is_some_and(|d| d.contains("signs of a numerical blow-up")),
        "{:?}",
        res.attribute_text("diagnostic")
    );
}

#[test]
fn trust_unit_slips_in_the_contact_are_refused_before_the_run() {
    let dir = scratch("trust_diag_units");
    for (set, expected) in [
        // MPa given as Pa: before, a failed settling "126 mm deep in the flange".
        (
            "contact.young_pa=210000",
            "[contact] young_pa = 2.1e5 is outside",
        ),
        // Before, a blow-up reported as a derailment.
        (
            "contact.young_pa=1e30",
            "[contact] young_pa = 1e30 is outside",
        ),
        ("contact.poisson=30", "[contact] poisson = 30 is outside"),
        ("contact.friction=30", "[contact] friction = 30 is outside"),
        // Before the run too (the bound of [run]).
        (
            "run.step_s=1e-300",
            "[run] step_s = 1e-300 s is below 1e-7 s",
        ),
    ] {
        let out = dir.join("run.h5");
        let o = run(sim()
            .env("RAILSIM_CACHE_DIR", dir.join("cache"))
            .arg("run")
            .arg(shipped("scenes/wheelset_straight.toml"))
            .args(["--no-plots", "-o"])
            .arg(&out)
            .args(["--set", set]));
        assert!(!o.status.success(), "{set}");
        let err = stderr(&o);
        assert!(
            err.contains(expected) && err.contains("check the unit"),
            "{set}: {err}"
        );
        assert!(!out.exists(), "{set}: a results file was written");
    }
}
