//! End to end: `sim run` on the paper's cases (§5) with the shipped scenes.
//!
//! - the unsuspended ML95-like wheelset: hunting wavelength against
//!   Klingel's L = 2π√(b0 R0/λ) = 15.96 m (b0 0.75 m, R0 0.43 m, λ 0.05)
//!   within 3 % at 2 and 10 m/s, constant amplitude at 2 m/s, growth to a
//!   flange-limited cycle at 20 m/s (paper Fig. 15);
//! - the ML95-like bogie: decay at 30 m/s, growth at 90 m/s, and the
//!   Heuristic law less stable than Kalker and Polach near the critical
//!   speed (paper Fig. 18, Table 1: in kind; our ML95-like data are not the
//!   paper's, so the critical speed differs in number — docs/guide/critical-speed.md);
//! - table contact agrees with online contact;
//! - the results file layout, the `--json` summary, the default scene, the
//!   table cache, Ctrl-C.

mod common;

use std::path::Path;

use common::*;
use runtime::{io::schema::read_results, results::RunResults};

const KLINGEL_M: f64 = 15.957_311_601_523_154;

fn scene(name: &str) -> String {
    shipped(&format!("scenes/{name}"))
        .to_str()
        .expect("utf-8 path")
        .to_string()
}

/// `sim run` with a private table cache; returns the JSON summary.
fn run_sim(dir: &Path, args: &[&str]) -> serde_json::Value {
    let o = run(sim()
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .args(["run", "--json", "--no-plots"])
        .args(args));
    assert!(o.status.success(), "sim run {args:?}: {}", stderr(&o));
    serde_json::from_str(&stdout(&o)).expect("JSON summary")
}

/// Upward zero crossings of the lateral displacement against distance (m).
fn zero_crossings(r: &RunResults, wheelset: usize) -> Vec<f64> {
    let w = &r.wheelsets[wheelset];
    let (x, y) = (&w.distance_m, &w.lateral_m);
    (0..y.len() - 1)
        .filter(|&i| y[i] < 0.0 && y[i + 1] >= 0.0)
        .map(|i| x[i] + (x[i + 1] - x[i]) * (-y[i]) / (y[i + 1] - y[i]))
        .collect()
}

fn wavelength_m(r: &RunResults) -> f64 {
    let z = zero_crossings(r, 0);
    assert!(z.len() >= 3, "too few cycles: {z:?}");
    (z[z.len() - 1] - z[0]) / (z.len() - 1) as f64
}

/// Largest |lateral| (m) of a wheelset over the samples whose distance lies
/// in `[from, to)` (m).
fn amplitude_m(r: &RunResults, wheelset: usize, from: f64, to: f64) -> f64 {
    let w = &r.wheelsets[wheelset];
    w.distance_m
        .iter()
        .zip(&w.lateral_m)
        .filter(|(d, _)| **d >= from && **d < to)
        .fold(0.0_f64, |m, (_, y)| m.max(y.abs()))
}

#[test]
fn wheelset_hunts_with_the_klingel_wavelength_at_10_m_s() {
    let dir = scratch("run_wheelset_10");
    let out = dir.join("ws10.h5");
    let summary = run_sim(
        &dir,
        &[
            &scene("wheelset_straight.toml"),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "run.distance_m=80",
        ],
    );
    let r = read_results(&out).expect("results file");
    // Every sample carries the wheelset's track position s: the scene's
    // start (initial.s_m = 5 m) plus the distance travelled.
    let w = &r.wheelsets[0];
    assert_eq!(w.track_s_m.len(), r.time_s.len());
    for (s, d) in w.track_s_m.iter().zip(&w.distance_m) {
        assert!((s - d - 5.0).abs() < 1e-9, "track s {s} vs distance {d}");
    }
    let l = wavelength_m(&r);
    // Measured 15.83 m (−0.8 %): the wheelset's roll and the gravitational
    // stiffness shorten the kinematic wavelength slightly.
    assert!(
        (l / KLINGEL_M - 1.0).abs() < 0.03,
        "wavelength {l:.3} m vs Klingel {KLINGEL_M:.3} m"
    );
    // The unsuspended wheelset is unstable: the amplitude grows.
    let early = amplitude_m(&r, 0, 5.0, 25.0);
    let late = amplitude_m(&r, 0, 60.0, 80.0);
    assert!(late > early * 1.1, "amplitude {early} → {late}");
    // Summary fields of the issue.
    for key in [
        "simulated_time_s",
        "wall_time_s",
        "real_time_factor",
        "steps",
        "contact_solves",
        "mean_newton_iterations",
        "flange_contact_states",
    ] {
        assert!(summary[key].is_number(), "{key} missing: {summary}");
    }
    assert!((summary["simulated_time_s"].as_f64().unwrap() - 8.0).abs() < 1e-9);
    let ws = &summary["wheelsets"][0];
    for key in [
        "peak_lateral_mm",
        "travelled_left_m",
        "travelled_right_m",
        "flange_contact_left_s",
    ] {
        assert!(ws[key].is_number(), "{key} missing: {ws}");
    }
    // Both wheels travel the 80 m (to the hunting path's extra length).
    for key in ["travelled_left_m", "travelled_right_m"] {
        let d = ws[key].as_f64().unwrap();
        assert!((d - 80.0).abs() < 0.05, "{key} = {d}");
    }
    assert_eq!(r.attribute_text("creep_law"), Some("polach"));
    assert!(r.scene_toml.contains("overrides: run.distance_m=80"));
}

/// `sim run` with `creep_law = "fastrip"` (FaStrip): the run records the
/// law, and the unsuspended wheelset hunts with Klingel's wavelength within
/// 3 % as with Polach (the kinematic wavelength does not depend on the creep
/// law).
#[test]
fn wheelset_hunts_with_fastrip() {
    let dir = scratch("run_wheelset_fastrip");
    let out = dir.join("ws_fastrip.h5");
    run_sim(
        &dir,
        &[
            &scene("wheelset_straight.toml"),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "run.distance_m=50",
            "--set",
            "contact.creep_law=fastrip",
        ],
    );
    let r = read_results(&out).expect("results file");
    assert_eq!(r.attribute_text("creep_law"), Some("fastrip"));
    let l = wavelength_m(&r);
    assert!(
        (l / KLINGEL_M - 1.0).abs() < 0.03,
        "wavelength {l:.3} m vs Klingel {KLINGEL_M:.3} m"
    );
}

/// At 2 m/s the creep forces damp the motion just enough that the amplitude
/// stays constant (paper §5: "the critical speed of the unsuspended
/// wheelset is close to 2 m/s").
#[test]
fn wheelset_at_2_m_s_keeps_its_amplitude_and_wavelength() {
    let dir = scratch("run_wheelset_2");
    let out = dir.join("ws2.h5");
    run_sim(
        &dir,
        &[
            &scene("wheelset_straight.toml"),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "initial.speed_m_s=2",
            "--set",
            "run.distance_m=50",
        ],
    );
    let r = read_results(&out).unwrap();
    let l = wavelength_m(&r);
    assert!(
        (l / KLINGEL_M - 1.0).abs() < 0.03,
        "wavelength {l:.3} m vs Klingel {KLINGEL_M:.3} m"
    );
    // Measured: 2.000 → 2.017 mm over three wavelengths.
    let early = amplitude_m(&r, 0, 1.0, 17.0);
    let late = amplitude_m(&r, 0, 33.0, 50.0);
    assert!(
        (late / early - 1.0).abs() < 0.05,
        "amplitude {early} → {late}"
    );
}

/// At 20 m/s the motion grows until the flanges limit it: the peak lateral
/// displacement reaches the flangeway clearance (6.8 mm for the ML95-like
/// wheel on UIC60 1:20) and the flanges touch.
#[test]
fn wheelset_at_20_m_s_reaches_a_flange_limited_cycle() {
    let dir = scratch("run_wheelset_20");
    let out = dir.join("ws20.h5");
    let summary = run_sim(
        &dir,
        &[
            &scene("wheelset_straight.toml"),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "initial.speed_m_s=20",
            "--set",
            "run.distance_m=200",
        ],
    );
    let peak = summary["wheelsets"][0]["peak_lateral_mm"].as_f64().unwrap();
    assert!((6.0..8.0).contains(&peak), "peak {peak} mm");
    let flange = summary["wheelsets"][0]["flange_contact_events"]
        .as_u64()
        .unwrap();
    assert!(flange >= 2, "flange contacts {flange}");
    let r = read_results(&out).unwrap();
    let f = &r.wheelsets[0].wheels[0].zones[1];
    assert!(
        f.normal_n.iter().any(|n| n.is_finite() && *n > 100.0),
        "left flange never loaded"
    );
}

/// The bogie: stable at 30 m/s, hunting at 90 m/s (our ML95-like bogie's
/// critical speed lies near 80 m/s; the paper's ML95 has 39 m/s).
#[test]
fn bogie_decays_below_and_grows_above_the_critical_speed() {
    let dir = scratch("run_bogie");
    for (speed, grows) in [("30", false), ("90", true)] {
        let out = dir.join(format!("bogie{speed}.h5"));
        run_sim(
            &dir,
            &[
                &scene("bogie_straight.toml"),
                "-o",
                out.to_str().unwrap(),
                "--set",
                &format!("initial.speed_m_s={speed}"),
                "--set",
                "run.step_s=2e-4",
            ],
        );
        let r = read_results(&out).unwrap();
        for ws in 0..2 {
            let late = amplitude_m(&r, ws, 200.0, 280.0);
            if grows {
                assert!(late > 4e-3, "{speed} m/s, wheelset {ws}: {late}");
            } else {
                assert!(late < 1e-4, "{speed} m/s, wheelset {ws}: {late}");
            }
        }
    }
}

/// Paper Fig. 18 and Table 1, in kind: near the critical speed the
/// Heuristic law is the least stable (paper: 35 m/s against 39 for Kalker
/// and Polach). At 80 m/s our bogie's motion after 280 m is largest with
/// the Heuristic law.
#[test]
fn heuristic_law_is_less_stable_than_kalker_and_polach() {
    let dir = scratch("run_bogie_laws");
    let mut late = Vec::new();
    for law in ["kalker", "heuristic", "polach"] {
        let out = dir.join(format!("{law}.h5"));
        run_sim(
            &dir,
            &[
                &scene("bogie_straight.toml"),
                "-o",
                out.to_str().unwrap(),
                "--set",
                "initial.speed_m_s=80",
                "--set",
                "run.step_s=2e-4",
                "--set",
                &format!("contact.creep_law={law}"),
            ],
        );
        let r = read_results(&out).unwrap();
        late.push(amplitude_m(&r, 0, 200.0, 280.0));
    }
    let (kalker, heuristic, polach) = (late[0], late[1], late[2]);
    assert!(
        heuristic > 2.0 * kalker && heuristic > 2.0 * polach,
        "late amplitudes: Kalker {kalker}, Heuristic {heuristic}, Polach {polach}"
    );
}

/// Contact from the lookup table gives the same motion as online contact on
/// the tread (the bogie at 20 m/s, within 0.05 mm), and the table is built
/// once and then read from the cache.
#[test]
fn table_contact_matches_online_contact() {
    let dir = scratch("run_table");
    let mut runs = Vec::new();
    for method in ["online", "table", "table"] {
        let out = dir.join(format!("{method}{}.h5", runs.len()));
        let s = run_sim(
            &dir,
            &[
                &scene("bogie_straight.toml"),
                "-o",
                out.to_str().unwrap(),
                "--set",
                "initial.speed_m_s=20",
                "--set",
                "run.distance_m=60",
                "--set",
                &format!("contact.method={method}"),
            ],
        );
        runs.push((s, read_results(&out).unwrap()));
    }
    let (a, b) = (&runs[0].1, &runs[1].1);
    let diff = a.wheelsets[0]
        .lateral_m
        .iter()
        .zip(&b.wheelsets[0].lateral_m)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(diff < 5e-5, "online vs table lateral: {diff} m");
    // The table method does not run Newton.
    assert!(runs[1].0["contact_solves"].as_u64().unwrap() < 1000);
    // First run built the track tables, the later ones found them cached.
    assert_eq!(runs[0].0["track"]["built"], true);
    assert_eq!(runs[2].0["track"]["built"], false);
}

/// `sim run` without a scene runs the paper's single-wheelset case; the
/// results file has the documented layout and the plots are written.
#[test]
fn default_scene_writes_results_and_plots() {
    let dir = scratch("run_default");
    let out = dir.join("default.h5");
    let o = run(sim()
        .current_dir(&dir)
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .args([
            "run",
            "-o",
            out.to_str().unwrap(),
            "--set",
            "run.distance_m=20",
            "--quiet",
        ]));
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("real-time factor"), "{text}");
    let plots = dir.join("default_plots");
    assert_eq!(
        files_in(&plots),
        vec![
            "contact_forces.png",
            "creepages.png",
            "curving.png",
            "lateral_displacement.png"
        ]
    );
    let h = run(std::process::Command::new("h5dump").args(["-H", out.to_str().unwrap()]));
    let layout = stdout(&h);
    for name in [
        "time_s",
        "wheelset_0",
        "lateral_m",
        "yaw_rad",
        "roll_rad",
        "distance_m",
        "speed_m_s",
        "travelled_m",
        "flange_contact",
        "normal_n",
        "fx_n",
        "fy_n",
        "xi",
        "eta",
        "phi_1_m",
        "y_wheel_m",
        "scene",
    ] {
        assert!(layout.contains(name), "{name} missing from the layout");
    }
}

/// Ctrl-C stops the run at the next step and the results so far are
/// written, marked as interrupted; `sim run` then exits with 130, so that
/// `sim run … && next-step` does not go on with a partial run.
#[test]
fn ctrl_c_stops_cleanly_and_writes_the_results() {
    let dir = scratch("run_ctrl_c");
    let out = dir.join("interrupted.h5");
    // The track built into the cache first, so that the interrupted run
    // is integrating (not building its track) when the signal comes.
    let warm = run(sim()
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .args([
            "run",
            &scene("wheelset_straight.toml"),
            "--no-plots",
            "--quiet",
        ])
        .arg("-o")
        .arg(dir.join("warm.h5"))
        .args(["--set", "run.distance_m=0.05"]));
    assert!(warm.status.success(), "{}", stderr(&warm));
    let child = sim()
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .args([
            "run",
            &scene("wheelset_straight.toml"),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "initial.speed_m_s=2",
            "--no-plots",
            "--json",
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("sim starts");
    // The results file is created (under its temporary name) just before
    // the run starts; a second later it is integrating.
    let started = std::time::Instant::now();
    while !files_in(&dir)
        .iter()
        .any(|f| f.starts_with(".interrupted.h5.tmp-"))
        && started.elapsed().as_secs() < 120
    {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::thread::sleep(std::time::Duration::from_millis(1000));
    let k = run(std::process::Command::new("kill").args(["-INT", &child.id().to_string()]));
    assert!(k.status.success(), "kill -INT failed");
    let o = child.wait_with_output().expect("sim ends");
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("interrupted (Ctrl-C)") && stderr(&o).contains("interrupted.h5"),
        "{}",
        stderr(&o)
    );
    let summary: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    assert_eq!(summary["stopped"], "interrupted", "{summary}");
    let t = summary["simulated_time_s"].as_f64().unwrap();
    assert!(t > 0.0 && t < 140.0, "{t}");
    let r = read_results(&out).unwrap();
    assert!(r.len() > 10);
    assert_eq!(r.attribute_text("status"), Some("interrupted"));
}
