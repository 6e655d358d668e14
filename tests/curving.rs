//! End to end: the curving, safety and wear outputs of `sim run` on the
//! R 300 m curve of `tables/tracks/curve_r300` (the ML95-like bogie,
//! 15 m/s, 40 m from the end of the entry clothoid into the arc): the
//! results file carries ΣY and Tγ, the JSON and text summaries the
//! Prud'homme and unloading verdicts with their criteria, the angle of
//! attack, Tγ, the track's elements and the arc's quasi-static values,
//! and the plots include `curving.png`.

mod common;

use common::*;
use runtime::io::schema::read_results;

const ARGS: [&str; 8] = [
    "--set",
    "initial.s_m=95",
    "--set",
    "run.distance_m=40",
    "--set",
    "initial.speed_m_s=15",
    "--set",
    "initial.lateral_m=0",
];

/// The curve's centreline, as an absolute path (valid however `--set`
/// resolves relative ones).
fn centerline() -> String {
    let p = shipped("tracks/curve_r300/centerline.csv");
    format!("track.centerline={}", p.display())
}

#[test]
fn a_curve_run_reports_curving_safety_and_wear() {
    let dir = scratch("curving_e2e");
    let out = dir.join("curve.h5");
    let scene = shipped("scenes/bogie_straight.toml");
    let o = run(sim()
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .args(["run", "-q", "--json", scene.to_str().unwrap(), "-o"])
        .arg(&out)
        .arg("--plots")
        .arg(dir.join("plots"))
        .args(["--set", &centerline()])
        .args(ARGS));
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON summary");

    // Results: ΣY per wheelset, Tγ per wheel and zone.
    let r = read_results(&out).unwrap();
    let front = &r.wheelsets[0];
    assert_eq!(front.sum_y_n.len(), r.time_s.len());
    // The leading wheelset of a left-hand curve is pushed left (+n) by
    // its outer (right) wheel's flange: ΣY > 0 on the arc (measured
    // 7.1 kN quasi-static at 15 m/s).
    let last = *front.sum_y_n.last().unwrap();
    assert!(last > 2e3 && last < 20e3, "ΣY {last} N");
    let t = front.wheels[1].wear_number_n.last().copied().unwrap();
    assert!(t > 50.0 && t < 1000.0, "Tγ {t} N");
    assert!(
        front.wheels[1].zones[0]
            .wear_number_n
            .iter()
            .any(|v| v.is_finite())
    );

    // JSON: the verdicts with their criteria, from the static load.
    let s = &j["wheelsets"][0]["safety"];
    let p = s["static_axle_load_kn"].as_f64().unwrap();
    assert!((p - 100.0).abs() < 5.0, "P {p} kN");
    let limit = s["prudhomme"]["limit_kn"].as_f64().unwrap();
    assert!((limit - (10.0 + p / 3.0)).abs() < 1e-9);
    assert_eq!(s["prudhomme"]["verdict"], "below_limit");
    assert!(
        s["prudhomme"]["criterion"]
            .as_str()
            .unwrap()
            .contains("10 + P/3")
    );
    assert_eq!(s["unloading"][0]["verdict"], "below_limit");
    assert_eq!(s["unloading"][0]["limit"], 0.6);
    // The leading wheelset yaws nose right (outwards) in a left curve.
    let aoa = s["max_angle_of_attack_mrad"].as_f64().unwrap();
    assert!(aoa < -1.0 && aoa > -20.0, "angle of attack {aoa} mrad");
    assert!(s["wear"][1]["mean_wear_number_n"].as_f64().unwrap() > 10.0);

    // The track's elements and the arc (R 300 m from 110 to 260 m, found
    // within the 5 % band): a control-point track has no design elements.
    assert_eq!(j["curving"]["track_elements_source"], "curvature");
    let kinds: Vec<&str> = j["curving"]["track_elements"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["kind"].as_str().unwrap())
        .collect();
    assert_eq!(
        kinds,
        ["straight", "transition", "arc", "transition", "straight"]
    );
    let arc = &j["curving"]["arcs"][0];
    assert!(
        (arc["radius_m"].as_f64().unwrap() - 300.0).abs() < 6.0,
        "{arc}"
    );
    let qs = arc["wheelsets"][0]["quantities"].as_array().unwrap();
    let sum_y = qs.iter().find(|q| q["quantity"] == "sum_y").unwrap();
    let qst = sum_y["quasi_static"].as_f64().unwrap();
    assert!(qst > 2.0 && qst < 20.0, "{sum_y}");
    assert!(sum_y["windows"].as_u64().unwrap() > 100, "{sum_y}");

    // Plots: the curving page.
    let plots: Vec<&str> = j["plots"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_str().unwrap())
        .collect();
    let page = plots.iter().find(|p| p.ends_with("curving.png")).unwrap();
    assert!(std::fs::metadata(page).unwrap().len() > 50_000);

    // Text: the same figures with the criteria named.
    let o = run(sim()
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .args(["run", "-q", "--no-plots", scene.to_str().unwrap(), "-o"])
        .arg(dir.join("text.h5"))
        .args(["--set", &centerline()])
        .args(ARGS));
    let text = stdout(&o);
    for needle in [
        "ΣY max",
        "Prud'homme",
        "ΔQ/Q0",
        "angle of attack",
        "Tγ",
        "track elements (from the curvature): straight",
        "(R 300 m)",
        "quasi-static (50 %)",
    ] {
        assert!(text.contains(needle), "{needle} missing:\n{text}");
    }
}
