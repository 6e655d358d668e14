//! End to end: `sim tradeoff --quick` on the shipped bogie scene at 84 m/s
//! (it hunts slowly there, so the frequency is measurable over 50 m): the
//! three files and the JSON, the reference's own errors are zero, every
//! variant's errors are finite and non-negative, a coarse RK4 step is less
//! accurate than a fine one, a variant that fails is reported as failed.
//! No wall-clock checks here (`scripts/tradeoff_regression.sh` has them).

mod common;

use common::*;
use serde_json::Value;

fn bogie_scene() -> String {
    shipped("scenes/bogie_straight.toml")
        .to_str()
        .expect("utf-8 path")
        .to_string()
}

fn variant<'a>(report: &'a Value, name: &str) -> &'a Value {
    report["variants"]
        .as_array()
        .expect("variants")
        .iter()
        .find(|v| v["name"] == name)
        .unwrap_or_else(|| panic!("no variant '{name}' in {report:#}"))
}

fn num(v: &Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} is not a number in {v:#}"))
}

#[test]
fn quick_study_on_the_bogie() {
    let dir = scratch("tradeoff_quick");
    let out = dir.join("study");
    let o = run(sim()
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .args(["tradeoff", &bogie_scene(), "--quick", "--json", "--out"])
        .arg(&out)
        .args([
            "--set",
            "initial.speed_m_s=84",
            "--variant",
            "unstable:run.step_s=0.01",
        ]));
    assert!(o.status.success(), "sim tradeoff: {}", stderr(&o));
    let report: Value = serde_json::from_str(&stdout(&o)).expect("JSON report");

    // The files.
    for f in ["tradeoff.csv", "tradeoff.md", "pareto.png", "tradeoff.json"] {
        let p = out.join(f);
        assert!(
            p.metadata().map(|m| m.len() > 100).unwrap_or(false),
            "{} missing or empty",
            p.display()
        );
    }
    let png = std::fs::read(out.join("pareto.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let md = std::fs::read_to_string(out.join("tradeoff.md")).unwrap();
    assert!(
        md.contains("| variant |") && md.contains("table-step rule"),
        "{md}"
    );
    let csv = std::fs::read_to_string(out.join("tradeoff.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    for col in [
        "name",
        "overrides",
        "wall_time_median_s",
        "wall_time_min_s",
        "wall_time_max_s",
        "real_time_factor",
        "lateral_max_error_m",
        "lateral_rms_error_m",
        "frequency_error_hz",
        "peak_lateral_force_error_n",
        "peak_normal_force_error_n",
        "table_step_ratio",
    ] {
        assert!(header.contains(&col), "{col} not in {header:?}");
    }
    let variants = report["variants"].as_array().unwrap();
    assert_eq!(csv.lines().count(), 1 + variants.len(), "{csv}");
    assert_eq!(
        variants.len(),
        7,
        "reference, five variants, the failing one"
    );

    // The reference against itself.
    let reference = variant(&report, "reference");
    assert_eq!(reference["status"], "ok");
    for key in [
        "lateral_max_m",
        "lateral_rms_m",
        "frequency_hz",
        "peak_lateral_force_n",
        "peak_normal_force_n",
    ] {
        assert_eq!(num(&reference["errors"], key), 0.0, "reference {key}");
    }
    // 0.01 m table / (84 m/s × 0.1 ms).
    assert!((num(reference, "table_step_ratio") - 0.01 / (84.0 * 1e-4)).abs() < 1e-9);
    let f_ref = num(&reference["measures"], "hunting_frequency_hz");
    assert!((2.0..5.0).contains(&f_ref), "hunting frequency {f_ref} Hz");

    // Every variant that ran: finite, non-negative errors, a wall time and
    // a real-time factor.
    for v in variants.iter().filter(|v| v["status"] == "ok") {
        let e = &v["errors"];
        for key in [
            "lateral_max_m",
            "lateral_rms_m",
            "frequency_hz",
            "peak_lateral_force_n",
            "peak_normal_force_n",
        ] {
            let x = num(e, key);
            assert!(x.is_finite() && x >= 0.0, "{}: {key} = {x}", v["name"]);
        }
        assert!(num(e, "lateral_rms_m") <= num(e, "lateral_max_m"));
        assert!(num(v, "wall_time_median_s") > 0.0);
        assert!(num(v, "wall_time_min_s") <= num(v, "wall_time_median_s"));
        assert!(num(v, "real_time_factor") > 0.0);
    }

    // A coarse step is less accurate than a fine one (RK4: 4th order, so
    // 1 ms against 0.2 ms is ~600× apart; ask for 10×), and neither is
    // exact.
    let coarse = num(&variant(&report, "rk4 1 ms")["errors"], "lateral_max_m");
    let fine = num(&variant(&report, "rk4 0.2 ms")["errors"], "lateral_max_m");
    assert!(
        fine > 0.0 && coarse > 10.0 * fine,
        "coarse {coarse}, fine {fine}"
    );
    // The stiff integrator at its defaults runs and stays within the 10 µm
    // its tolerance is set for (docs/reference/08-multibody.md §8.5).
    let ros = variant(&report, "rosenbrock atol 5e-6");
    assert_eq!(ros["status"], "ok");
    let ros_err = num(&ros["errors"], "lateral_max_m");
    assert!(ros_err > 0.0 && ros_err < 10e-6, "rosenbrock {ros_err} m");
    // The quick look (table contact, 0.5 m table, RK4 1 ms) is the least
    // accurate and the fastest.
    let quick = variant(&report, "quick look");
    assert!(num(&quick["errors"], "lateral_max_m") > coarse);

    // The failing variant is reported, with its error.
    let failed = variant(&report, "unstable");
    assert_eq!(failed["status"], "failed");
    let msg = failed["error"].as_str().unwrap();
    assert!(msg.contains("derailed") || msg.contains("failed"), "{msg}");
    assert!(failed["errors"].is_null());
    assert!(md.contains("unstable") && md.contains("failed"), "{md}");
}

#[test]
fn bad_arguments_name_the_rule() {
    let dir = scratch("tradeoff_bad");
    for (args, what) in [
        (vec!["--critical-speed", "70:100"], "MIN:MAX:TOL"),
        (vec!["--variant", "no-overrides"], "NAME:KEY=VALUE"),
        (vec!["--variant", "x:step"], "KEY=VALUE"),
        (vec!["--set", "run.integrator=euler"], "integrator"),
        (vec!["--repeats", "0"], "repeats"),
    ] {
        let o = run(sim()
            .env("RAILSIM_CACHE_DIR", dir.join("cache"))
            .args(["tradeoff", &bogie_scene(), "--quick", "--out"])
            .arg(dir.join("out"))
            .args(&args));
        assert!(!o.status.success(), "{args:?} succeeded");
        assert!(stderr(&o).contains(what), "{args:?}: {}", stderr(&o));
    }
}
