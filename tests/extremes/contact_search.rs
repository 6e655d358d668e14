//! The contact search at the extremes of the benchmark set-up (issue 13,
//! items 3–4; docs/reference/06-contact-detection.md §6.3, §6.7), end to
//! end through `sim contact`: S1002 on UIC60 (rail file already canted,
//! `--rail-inclination 0`), the default 10 kN per wheel, FASTSIM at 2 m/s.
//!
//! - the pose of the issue, 7.5 mm and 18 mrad, used to fail with "no
//!   contact candidate on the left wheel … the wheel is off its rail": its
//!   flange contact lies 13 mm ahead of the axle; it and its mirror now
//!   settle, with the mirrored contact;
//! - at 4.9 mm the left wheel touches twice (tread and flange root), and
//!   each patch has its own ellipse, creepages and creep forces.

use serde_json::Value;

use crate::common::*;

/// `sim contact` on the benchmark set-up at `y_mm`, `yaw_mrad`, as JSON.
fn contact(y_mm: &str, yaw_mrad: &str) -> Value {
    let o = run(sim().args([
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
        "--speed-m-s",
        "2",
        "--creep",
        "fastsim",
        "--json",
    ]));
    assert!(
        o.status.success(),
        "y = {y_mm} mm, yaw = {yaw_mrad} mrad: {}",
        stderr(&o)
    );
    serde_json::from_str(&stdout(&o)).expect("JSON")
}

/// The contacts of wheel `k` (0 left, 1 right).
fn contacts(v: &Value, k: usize) -> Vec<Value> {
    v["wheels"][k]["contacts"].as_array().unwrap().clone()
}

fn num(c: &Value, key: &str) -> f64 {
    c[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing: {c}"))
}

#[test]
fn sim_contact_finds_the_leading_flange_contact_of_the_issue() {
    let a = contact("7.5", "18");
    let b = contact("-7.5", "-18");
    let (fa, fb) = (&contacts(&a, 0)[0], &contacts(&b, 1)[0]);
    assert_eq!(fa["zone"], "flange", "{a}");
    assert_eq!(fb["zone"], "flange", "{b}");
    // Lead ≈ r ψ tan γ = 0.48 m × 0.018 × tan 57° ≈ 13 mm.
    let lead = num(fa, "lead_m");
    assert!((0.012..0.015).contains(&lead), "lead {lead}");
    for key in ["lead_m", "normal_n", "penetration_m", "y_wheel_mm"] {
        assert!(
            (num(fa, key) - num(fb, key)).abs() <= 1e-6 * num(fa, key).abs().max(1e-9),
            "{key}: {} vs {}",
            num(fa, key),
            num(fb, key)
        );
    }
    // The other wheel on its tread, carrying its 10 kN.
    let ta = &contacts(&a, 1)[0];
    assert_eq!(ta["zone"], "tread");
    assert!((num(ta, "normal_n") - 1e4).abs() < 200.0, "{ta}");
}

#[test]
fn sim_contact_reports_both_patches_at_the_flange_root() {
    let v = contact("4.9", "0");
    let left = contacts(&v, 0);
    assert_eq!(left.len(), 2, "{v}");
    let (p, q) = (&left[0], &left[1]);
    assert!((num(p, "y_wheel_mm") - num(q, "y_wheel_mm")).abs() > 8.0);
    for c in [p, q] {
        assert!(
            num(c, "penetration_m") > 0.0 && num(c, "normal_n") > 100.0,
            "{c}"
        );
        assert!(c["force_error"].is_null(), "{c}");
    }
    for key in [
        "a_m",
        "b_m",
        "xi",
        "fx_n",
        "contact_angle_rad",
        "rolling_radius_m",
    ] {
        assert!(
            (num(p, key) - num(q, key)).abs() > 1e-3 * num(p, key).abs().max(1e-6),
            "{key} the same on both patches: {p} {q}"
        );
    }
    assert_eq!(contacts(&v, 1).len(), 1, "{v}");
}
