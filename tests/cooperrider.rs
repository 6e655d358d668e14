//! The Cooperrider car as a cross-code comparison (issue 6): DYTSI's RSGEO
//! contact table imported through `track-preproc import-contact-table`, the
//! imported-table contact in the dynamics, the car on a straight,
//! `sim compare-contact-tables`, its linear critical speed (eigenvalues
//! against the time domain), its nonlinear critical speed and the
//! bifurcation diagram.

mod common;

use common::*;
use runtime::geometry::track::straight_track;
use runtime::multibody::imported_contact::{normal_force_n, settle_imported};

const RSGEO: &str = "contact/cooperrider_RSGEO.dat";
const SCENE: &str = "scenes/cooperrider_straight.toml";
/// Static wheel load of the car (N): half of a wheelset's weight plus two
/// primary preloads (tables/vehicles/cooperrider_car.toml).
const WHEEL_LOAD_N: f64 = 66_602.297_25;

fn import(dir: &std::path::Path) -> std::path::PathBuf {
    let out = dir.join("rsgeo.h5");
    let o = run(track_preproc()
        .args(["import-contact-table", "--format", "rsgeo"])
        .arg(shipped(RSGEO))
        .arg("-o")
        .arg(&out)
        .arg("--json"));
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("json");
    assert_eq!(j["rows"], 3402);
    // The values at y = 0 quoted in the data's README.
    let near = |k: &str, v: f64, tol: f64| {
        let x = j[k].as_f64().expect(k);
        assert!((x - v).abs() <= tol, "{k} = {x}, expected {v}");
    };
    near("normal_force_at_0_n", 66_661.0, 1.0);
    near("contact_angle_at_0_rad", 0.01422, 5e-6);
    near("a_at_0_m", 5.95e-3, 5e-6);
    near("b_at_0_m", 6.65e-3, 5e-6);
    near("rolling_radius_at_0_m", 0.424883, 5e-7);
    near("wheel_lateral_at_0_m", 0.756301, 5e-7);
    near("y_min_m", -0.017, 1e-12);
    near("y_max_m", 0.01701, 1e-12);
    out
}

#[test]
fn import_writes_the_table_and_reads_it_back_unchanged() {
    let dir = scratch("cooperrider_import");
    let h5 = import(&dir);
    let back = runtime::io::schema::read_imported_contact_table(&h5).expect("read back");
    let direct = preproc::rsgeo::read_rsgeo(&shipped(RSGEO)).expect("parse");
    assert_eq!(back.rows, direct.rows);
    assert_eq!(back.y_m, direct.y_m);
    assert_eq!(back.format, "rsgeo");
    let p = runtime::io::schema::read_provenance(&h5).expect("provenance");
    assert!(p.command_line.contains("import-contact-table"));
    assert!(p.inputs[0].text.starts_with("#\n\"rh(51)\""));
    // Only rsgeo is a format, and a bad file names its line.
    let o = run(track_preproc()
        .args(["import-contact-table", "--format", "csv"])
        .arg(shipped(RSGEO))
        .arg("-o")
        .arg(dir.join("x.h5")));
    assert!(!o.status.success());
    let bad = dir.join("bad.dat");
    let text = std::fs::read_to_string(shipped(RSGEO)).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    lines[10] = "1.0 2.0";
    std::fs::write(&bad, lines.join("\n")).unwrap();
    let o = run(track_preproc()
        .args(["import-contact-table", "--format", "rsgeo"])
        .arg(&bad)
        .arg("-o")
        .arg(dir.join("bad.h5")));
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(e.contains("line 11") && e.contains("2 values"), "{e}");
    assert!(!dir.join("bad.h5").exists());
}

#[test]
fn the_contact_is_symmetric_at_zero_and_carries_n0() {
    let table = preproc::rsgeo::read_rsgeo(&shipped(RSGEO)).expect("parse");
    let track = straight_track(60.0, 0.1, 1.435, 1.507, 0.0);
    let s = settle_imported(&track, &table, 30.0, 0.0, 0.0, WHEEL_LOAD_N).expect("seated");
    let [l, r] = [
        s.contacts.candidates[0][0].expect("left"),
        s.contacts.candidates[1][0].expect("right"),
    ];
    let centre = track.centerline.at(30.0).unwrap().position;
    assert!(s.roll_rad.abs() < 1e-12, "roll {}", s.roll_rad);
    assert!((l.penetration_m - r.penetration_m).abs() < 1e-15);
    assert!(((l.wheel_point.y - centre.y) + (r.wheel_point.y - centre.y)).abs() < 1e-12);
    assert!((l.normal.y + r.normal.y).abs() < 1e-15 && l.normal.y < 0.0);
    // 0.756301 m from the centre, 0.424883 m below the axle.
    assert!(((l.wheel_point.y - centre.y) - 0.756301).abs() < 1e-6);
    assert!(((s.pose.position.z - l.wheel_point.z) - 0.424883).abs() < 1e-6);
    let row = table.row_at(0.0).unwrap();
    let n = normal_force_n(&row, l.penetration_m);
    // The static load is within 0.1 % of the table's N0: the table was made for it.
    assert!(
        (n - row.normal_force_n).abs() < 1e-3 * row.normal_force_n,
        "{n}"
    );
    assert!((n * l.normal.z - WHEEL_LOAD_N).abs() < 1e-6 * WHEEL_LOAD_N);
    // Mirrored shifts give mirrored contacts.
    let a = settle_imported(&track, &table, 30.0, 0.004, 0.0, WHEEL_LOAD_N).unwrap();
    let b = settle_imported(&track, &table, 30.0, -0.004, 0.0, WHEEL_LOAD_N).unwrap();
    assert!((a.roll_rad + b.roll_rad).abs() < 1e-12);
    for k in 0..2 {
        let (ca, cb) = (
            a.contacts.candidates[k][0].unwrap(),
            b.contacts.candidates[1 - k][0].unwrap(),
        );
        assert!((ca.contact_angle_rad - cb.contact_angle_rad).abs() < 1e-15);
        assert!((ca.normal.y + cb.normal.y).abs() < 1e-15);
    }
    // The flange side at +y is the left wheel's.
    let la = a.contacts.candidates[0][0].unwrap();
    let ra = a.contacts.candidates[1][0].unwrap();
    assert!(la.rolling_radius_m > ra.rolling_radius_m);
    assert!(la.contact_angle_rad > ra.contact_angle_rad);
}

fn run_scene(dir: &std::path::Path, name: &str, extra: &[&str]) -> (serde_json::Value, String) {
    let out = dir.join(format!("{name}.h5"));
    let mut cmd = sim();
    cmd.arg("run")
        .arg(shipped(SCENE))
        .arg("-o")
        .arg(&out)
        .args(["--json", "--no-plots", "--quiet"]);
    for e in extra {
        cmd.args(["--set", e]);
    }
    let o = run(&mut cmd);
    let j = if o.status.success() {
        serde_json::from_str(&stdout(&o)).expect("json")
    } else {
        serde_json::Value::Null
    };
    (j, stderr(&o))
}

#[test]
fn the_car_runs_two_seconds_at_40_m_s_and_starts_on_n0() {
    let dir = scratch("cooperrider_run");
    let (j, err) = run_scene(&dir, "car", &["run.duration_s=2"]);
    assert!(j["error"].is_null(), "{err}");
    assert!((j["simulated_time_s"].as_f64().unwrap() - 2.0).abs() < 1e-9);
    assert_eq!(j["wheelsets"].as_array().unwrap().len(), 4);
    let f = hdf5::File::open(dir.join("car.h5")).unwrap();
    for w in 0..4 {
        let lat: Vec<f64> = f
            .dataset(&format!("wheelset_{w}/lateral_m"))
            .unwrap()
            .read_raw()
            .unwrap();
        assert!(lat.iter().all(|v| v.is_finite()));
        assert!(
            (lat[0] - 0.003).abs() < 1e-9,
            "starts 3 mm left: {}",
            lat[0]
        );
        // 40 m/s is below this car's critical speed: the offset decays.
        let late = lat[lat.len() * 3 / 4..]
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(late < 1.5e-3, "wheelset {w}: late amplitude {late}");
        for side in ["left", "right"] {
            let n: Vec<f64> = f
                .dataset(&format!("wheelset_{w}/{side}/tread/normal_n"))
                .unwrap()
                .read_raw()
                .unwrap();
            assert!(n.iter().all(|v| v.is_finite() && *v > 30e3), "{side}");
            // Static normal force at the start ≈ N0 (66 661 N at y = 0;
            // 66 605–66 663 N at the 3 mm start): within 0.5 %.
            assert!(
                (n[0] - 66_661.0).abs() < 0.005 * 66_661.0,
                "{side}: {}",
                n[0]
            );
        }
    }
    // The same run from the imported .h5 instead of the .dat: identical.
    let h5 = import(&dir);
    let (j2, err) = run_scene(
        &dir,
        "car_h5",
        &[
            "run.duration_s=0.2",
            &format!("contact.imported_table=\"{}\"", h5.display()),
        ],
    );
    assert!(j2["error"].is_null(), "{err}");
    let (j3, _) = run_scene(&dir, "car_dat", &["run.duration_s=0.2"]);
    assert_eq!(
        j2["wheelsets"][0]["final_lateral_mm"],
        j3["wheelsets"][0]["final_lateral_mm"]
    );
}

#[test]
fn scene_rules_and_derailment_are_reported() {
    let dir = scratch("cooperrider_rules");
    let (_, err) = run_scene(&dir, "polach", &["contact.creep_law=polach"]);
    assert!(
        err.contains("not available with method = \"imported\""),
        "{err}"
    );
    let (_, err) = run_scene(&dir, "no_table", &["contact.imported_table="]);
    assert!(err.contains("needs imported_table"), "{err}");
    // Beyond the table (±17 mm) the wheelset has derailed in that model.
    let (_, err) = run_scene(&dir, "off", &["initial.lateral_m=0.0175"]);
    assert!(err.contains("derailed") && err.contains("-0.017"), "{err}");
}

#[test]
fn compare_contact_tables_writes_its_plots() {
    let dir = scratch("cooperrider_compare");
    let ours = dir.join("ours.h5");
    let o = run(track_preproc()
        .args(["contact-table", "--wheel"])
        .arg(shipped("profiles/MBench_S1002_v3.prw"))
        .arg("--rail")
        .arg(shipped("profiles/MBench_UIC60_v3.prr"))
        .args([
            "--rail-inclination",
            "0",
            "--wheel-radius",
            "0.425",
            "--wheel-load-n",
            "66661",
            "--y-range-mm",
            "3",
            "--y-step-mm",
            "0.5",
            "-o",
        ])
        .arg(&ours));
    assert!(o.status.success(), "{}", stderr(&o));
    let out = dir.join("cmp");
    let o = run(sim()
        .args(["compare-contact-tables", "--ours"])
        .arg(&ours)
        .arg("--imported")
        .arg(shipped(RSGEO))
        .arg("--out")
        .arg(&out)
        .arg("--json"));
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(j["points"], 13);
    let files = files_in(&out);
    for f in [
        "comparison.csv",
        "contact_angle.png",
        "contact_position.png",
        "delta_r.png",
        "rolling_radius.png",
        "semi_axes.png",
    ] {
        assert!(files.contains(&f.to_string()), "{files:?}");
        assert!(std::fs::metadata(out.join(f)).unwrap().len() > 1000, "{f}");
    }
    let q = &j["quantities"];
    // At y = 0 both rolling radii are within 0.1 mm of 424.9 mm.
    let r_ours = q[0]["ours_at_0"].as_f64().unwrap();
    let r_imp = q[0]["imported_at_0"].as_f64().unwrap();
    assert!(
        (r_imp - 424.883).abs() < 1e-3 && (r_ours - 424.9).abs() < 0.1,
        "{r_ours} {r_imp}"
    );
    // Semi-axes: the imported a at y = 0 and ours finite.
    assert!((q[2]["imported_at_0"].as_f64().unwrap() - 5.952).abs() < 1e-3);
    assert!(q[2]["ours_at_0"].as_f64().unwrap().is_finite());
}

/// The car's linear critical speed from the eigenvalues, checked against
/// the time domain: 0.1 mm motions decay 4 % below it and grow 4 % above
/// it (`docs/guide/critical-speed.md`, "A published model": eigenvalues 110.7 m/s at 4.71 Hz, time
/// domain 112.8 m/s — the contact-angle slope of the table falls with
/// the amplitude, see there).
#[test]
fn linear_critical_speed_agrees_with_the_time_domain() {
    let dir = scratch("cooperrider_critical");
    let o = run(sim()
        .arg("critical-speed")
        .arg(shipped(SCENE))
        .args([
            "--method", "linear", "--min", "60", "--max", "150", "--json",
        ])
        .arg("--out")
        .arg(dir.join("linear")));
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("json");
    let r = &j["results"][0];
    let v = r["speed_m_s"].as_f64().expect("a critical speed");
    let f = r["frequency_hz"].as_f64().expect("a hunting frequency");
    assert!((v - 110.7).abs() < 1.0, "linear critical speed {v} m/s");
    assert!((f - 4.71).abs() < 0.1, "hunting frequency {f} Hz");
    // Growth rates of 0.1 mm motions at 0.96 v and 1.04 v (3 s runs).
    let rate = |speed: f64| {
        let out = dir.join(format!("run_{speed:.0}.h5"));
        let o = run(sim()
            .arg("run")
            .arg(shipped(SCENE))
            .arg("-o")
            .arg(&out)
            .args(["--json", "--no-plots", "--quiet"])
            .args(["--set", &format!("initial.speed_m_s={speed}")])
            .args(["--set", "initial.lateral_m=1e-4"])
            .args(["--set", "run.duration_s=3"])
            .args(["--set", "track.straight_m=500"]));
        assert!(o.status.success(), "{}", stderr(&o));
        let f = hdf5::File::open(&out).unwrap();
        let y: Vec<f64> = f
            .dataset("wheelset_0/lateral_m")
            .unwrap()
            .read_raw()
            .unwrap();
        // Peak |y| over the second and the last second.
        let n = y.len();
        let peak = |a: usize, b: usize| y[a..b].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        peak(n / 3, 2 * n / 3) / peak(2 * n / 3, n)
    };
    let below = rate(0.96 * v);
    let above = rate(1.04 * v);
    assert!(
        below > 1.0,
        "decays below: earlier/later peak ratio {below}"
    );
    assert!(above < 1.0, "grows above: earlier/later peak ratio {above}");
}

/// The nonlinear critical speed: the hunting cycle survives far below the
/// linear critical speed (110.7 m/s), a subcritical bifurcation. Ramps at
/// 1 m/s² (the guide's 0.5 m/s² gives 59.0 m/s by `critical-speed` and
/// 59.1 m/s by `bifurcation`; 1 m/s² measured 57.96 and 57.99 m/s):
/// - `sim critical-speed --method ramp` from a cycle at 150 m/s;
/// - `sim bifurcation` on a coarse up-scan (40, 85, 130 m/s): small motions
///   decay at 40 and 85 m/s and grow into a flange-limited cycle at
///   130 m/s, and the ramp-down from 130 m/s loses the cycle near 58 m/s.
#[test]
fn nonlinear_critical_speed_and_bifurcation_diagram() {
    let dir = scratch("cooperrider_nonlinear");
    let o = run(sim()
        .arg("critical-speed")
        .arg(shipped(SCENE))
        .args([
            "--method",
            "ramp",
            "--min",
            "40",
            "--max",
            "150",
            "--ramp-deceleration",
            "1",
            "--set",
            "initial.lateral_m=1e-4",
            "--json",
        ])
        .arg("--out")
        .arg(dir.join("ramp")));
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("json");
    let v = j["results"][0]["speed_m_s"]
        .as_f64()
        .unwrap_or_else(|| panic!("no nonlinear critical speed: {}", j["results"][0]));
    assert!(
        (53.0..63.0).contains(&v),
        "nonlinear critical speed {v} m/s"
    );
    let f = j["results"][0]["frequency_hz"].as_f64().expect("frequency");
    assert!((3.0..4.5).contains(&f), "cycle frequency as it dies {f} Hz");

    let o = run(sim()
        .arg("bifurcation")
        .arg(shipped(SCENE))
        .args([
            "--min",
            "40",
            "--max",
            "130",
            "--step",
            "45",
            "--ramp-deceleration",
            "1",
            "--set",
            "initial.lateral_m=1e-4",
            "--set",
            "track.straight_m=1400",
            "--json",
        ])
        .arg("--out")
        .arg(dir.join("bifurcation")));
    assert!(o.status.success(), "{}", stderr(&o));
    let b: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("json");
    // The leading wheelset's points (the up-scan lists every wheelset).
    let amp: Vec<(f64, f64)> = b["up_scan"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["wheelset_index"] == 0)
        .map(|p| {
            (
                p["speed_m_s"].as_f64().unwrap(),
                p["amplitude_mm"].as_f64().unwrap(),
            )
        })
        .collect();
    assert_eq!(amp.len(), 3, "{amp:?}");
    assert!(amp[0].1 < 0.01 && amp[1].1 < 0.01, "decay below: {amp:?}");
    assert!(amp[2].1 > 1.0, "a hunting cycle at 130 m/s: {amp:?}");
    assert_eq!(b["up_scan_jump_m_s"].as_f64(), Some(130.0));
    let death = b["ramp_death_m_s"].as_f64().expect("the cycle dies");
    assert!((53.0..63.0).contains(&death), "ramp-down death {death} m/s");
    for f in ["bifurcation.csv", "bifurcation.png"] {
        assert!(dir.join("bifurcation").join(f).exists(), "{f} missing");
    }
}
