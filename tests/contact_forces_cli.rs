//! End to end: `sim contact` with a rolling, yawed wheelset (creepages,
//! ellipse and creep forces per contact, the stable JSON keys) and
//! `sim creep-curves` (PNG and CSV written; the curves saturate at μN).

mod common;

use common::*;

fn contact_args(y_mm: &str, yaw_mrad: &str, creep: &str) -> Vec<String> {
    [
        "contact",
        "--wheel",
        shipped("profiles/MBench_S1002_v3.prw").to_str().unwrap(),
        "--rail",
        shipped("profiles/MBench_UIC60_v3.prr").to_str().unwrap(),
        "--rail-inclination",
        "0",
        "--y-mm",
        y_mm,
        "--yaw-mrad",
        yaw_mrad,
        "--wheel-load-n",
        "50000",
        "--speed-m-s",
        "30",
        "--creep",
        creep,
        "--mu",
        "0.3",
        "--json",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

fn f(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {v}"))
}

/// A wheelset yawed 2 mrad nose-left slips to the right over both rails,
/// so η ≈ −ψ on both treads and the lateral creep force on both wheels
/// points left (+l_c, which is ≈ +Y on a tread contact); every saturating
/// law stays within μN; Kalker linear is G a b c22 |η|-sized.
#[test]
fn sim_contact_reports_creepages_and_creep_forces() {
    for creep in ["kalker", "heuristic", "polach", "fastsim", "fastrip"] {
        let o = run(sim().args(contact_args("0", "2", creep)));
        assert!(o.status.success(), "{creep}: {}", stderr(&o));
        let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
        assert_eq!(v["forces"]["creep_law"], creep);
        assert_eq!(f(&v["forces"], "speed_m_s"), 30.0);
        let mu = f(&v["forces"], "friction_coefficient");
        for w in v["wheels"].as_array().unwrap() {
            let contacts = w["contacts"].as_array().unwrap();
            assert!(!contacts.is_empty());
            for c in contacts {
                for key in [
                    "normal_n",
                    "fx_n",
                    "fy_n",
                    "mz_nm",
                    "xi",
                    "eta",
                    "phi_per_m",
                    "a_m",
                    "b_m",
                ] {
                    assert!(c[key].is_f64(), "{creep}: {key} missing in {c}");
                }
                assert!(c["force_error"].is_null());
                let eta = f(c, "eta");
                assert!((eta + 2e-3).abs() < 2e-5, "{creep}: η = {eta}");
                let fy = f(c, "fy_n");
                assert!(fy > 0.0, "{creep}: Fy = {fy}");
                let (a, b) = (f(c, "a_m"), f(c, "b_m"));
                assert!(a > 2e-3 && a < 10e-3 && b > 2e-3 && b < 10e-3, "{a} {b}");
                let n = f(c, "normal_n");
                let ft = f(c, "fx_n").hypot(fy);
                if creep == "kalker" {
                    // Unsaturated: 2 mrad of lateral creepage on a ~6×5 mm
                    // ellipse is well beyond μN (≈ 1.3 μN).
                    assert!(ft > mu * n, "{ft} vs μN {}", mu * n);
                } else {
                    assert!(ft <= mu * n * (1.0 + 1e-9), "{creep}: {ft} > μN {}", mu * n);
                    assert!(ft > 0.5 * mu * n, "{creep}: {ft}");
                }
            }
        }
    }
}

/// The text form carries the same quantities.
#[test]
fn sim_contact_text_lists_forces() {
    let mut args = contact_args("3", "0", "polach");
    args.pop(); // no --json
    let o = run(sim().args(&args));
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("creep law polach"), "{text}");
    assert_eq!(
        text.matches("creep forces on the wheel").count(),
        2,
        "{text}"
    );
    assert!(text.contains("ellipse a "), "{text}");
}

#[test]
fn sim_contact_rejects_bad_force_settings() {
    let mut args = contact_args("0", "0", "kalker");
    let i = args.iter().position(|a| a == "--mu").unwrap();
    args[i] = "--mu=-0.2".into();
    args.remove(i + 1);
    let o = run(sim().args(&args));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("friction"), "{}", stderr(&o));
    let o = run(sim().args(contact_args("0", "0", "coulomb")));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("coulomb"), "{}", stderr(&o));
}

/// `sim creep-curves`: both files, five blocks; the saturating laws
/// (heuristic, Polach, FASTSIM, FaStrip) never exceed 1 (F/μN), reach ≥ 0.98
/// at the end of the ξ and η sweeps, and all five laws share Kalker's
/// initial slope (first step, 2 %).
#[test]
fn sim_creep_curves_writes_png_and_csv() {
    let dir = scratch("creep_curves");
    let o = run(sim().args([
        "creep-curves",
        "--out",
        dir.to_str().unwrap(),
        "--points",
        "101",
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(files_in(&dir), vec!["creep_curves.csv", "creep_curves.png"]);
    let png = std::fs::read(dir.join("creep_curves.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let csv = std::fs::read_to_string(dir.join("creep_curves.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("sweep"))
        .map(|l| l.split(',').collect())
        .collect();
    let block = |name: &str| -> Vec<Vec<f64>> {
        rows.iter()
            .filter(|r| r[0] == name)
            .map(|r| r[1..].iter().map(|v| v.parse::<f64>().unwrap()).collect())
            .collect()
    };
    for name in [
        "xi",
        "eta",
        "phi_lateral_force",
        "phi_spin_moment",
        "xi_polach_presets",
    ] {
        assert_eq!(block(name).len(), 101, "{name}");
    }
    for name in ["xi", "eta"] {
        let b = block(name);
        for r in &b {
            for law in 2..=5 {
                assert!(r[law] <= 1.0 + 1e-9, "{name}: {r:?}");
            }
        }
        let last = &b[100];
        for law in 2..=5 {
            assert!(last[law] >= 0.98, "{name} end: {last:?}");
        }
        let first = &b[1];
        for law in 2..=5 {
            assert!(
                (first[law] / first[1] - 1.0).abs() < 0.02,
                "{name} slope: {first:?}"
            );
        }
    }
}
