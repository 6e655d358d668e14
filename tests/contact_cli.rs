//! End to end: `sim contact` (the stable JSON interface) and
//! `track-preproc contact-table` / `build --wheel --rail` (the contact
//! lookup table in the table file, read back by the run-time reader).

mod common;

use common::*;
use runtime::io::schema;

fn s1002_args(y_mm: &str, yaw_mrad: &str) -> Vec<String> {
    [
        "contact",
        "--wheel",
        shipped("profiles/MBench_S1002_v3.prw").to_str().unwrap(),
        "--rail",
        shipped("profiles/MBench_UIC60_v3.prr").to_str().unwrap(),
        "--gauge",
        "1.435",
        "--back-to-back",
        "1.360",
        "--wheel-radius",
        "0.46",
        "--rail-inclination",
        "0",
        "--y-mm",
        y_mm,
        "--yaw-mrad",
        yaw_mrad,
        "--wheel-load-n",
        "10000",
        "--json",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

#[test]
fn sim_contact_json_interface() {
    let o = run(sim().args(s1002_args("3", "0")));
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    for key in ["z_m", "roll_rad", "y_m", "yaw_rad"] {
        assert!(v["wheelset"][key].is_f64(), "wheelset.{key} missing");
    }
    assert!((v["wheelset"]["y_m"].as_f64().unwrap() - 0.003).abs() < 1e-12);
    let wheels = v["wheels"].as_array().unwrap();
    assert_eq!(wheels.len(), 2);
    assert_eq!(wheels[0]["side"], "left");
    assert_eq!(wheels[1]["side"], "right");
    let mut total_vertical = 0.0;
    for w in wheels {
        let contacts = w["contacts"].as_array().unwrap();
        assert!(!contacts.is_empty(), "{w}");
        for c in contacts {
            for key in [
                "y_rail_mm",
                "y_wheel_mm",
                "contact_angle_rad",
                "penetration_m",
                "rolling_radius_m",
                "s_wheel_rad",
                "s_rail_m",
                "normal_n",
            ] {
                assert!(c[key].is_f64(), "contact.{key} missing in {c}");
            }
            assert!(c["zone"] == "tread" || c["zone"] == "flange");
            let n = c["normal_n"].as_f64().unwrap();
            total_vertical += n * c["contact_angle_rad"].as_f64().unwrap().cos();
        }
    }
    // Each wheel carries 10 kN vertically (the settling target).
    assert!((total_vertical - 20_000.0).abs() < 50.0, "{total_vertical}");
}

#[test]
fn sim_contact_flange_and_text_form() {
    // 8 mm to the left with 10 mrad of yaw: the left flange carries load,
    // ahead of or behind the axle (lead/lag).
    let o = run(sim().args(s1002_args("8", "10")));
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let left = v["wheels"][0]["contacts"].as_array().unwrap();
    let flange = left
        .iter()
        .find(|c| c["zone"] == "flange")
        .expect("flange contact");
    assert!(flange["contact_angle_rad"].as_f64().unwrap() > 0.8);
    assert!(flange["s_wheel_rad"].as_f64().unwrap().abs() > 1e-3);
    // The text form without --json.
    let mut args = s1002_args("8", "10");
    args.pop();
    let o = run(sim().args(args));
    assert!(o.status.success());
    let text = stdout(&o);
    assert!(
        text.contains("left wheel") && text.contains("flange"),
        "{text}"
    );
}

#[test]
fn sim_contact_bad_profile_is_reported() {
    let dir = scratch("contact_bad_profile");
    let bad = dir.join("wheel.csv");
    std::fs::write(&bad, "y_mm,z_mm\n0,0\n1,nan\n").unwrap();
    let mut args = s1002_args("0", "0");
    args[2] = bad.display().to_string();
    let o = run(sim().args(args));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("wheel.csv"), "{}", stderr(&o));
}

#[test]
fn contact_table_file_round_trip() {
    let dir = scratch("contact_table_cli");
    let out = dir.join("ct.h5");
    let o = run(track_preproc().args([
        "contact-table",
        "--wheel",
        shipped("profiles/MBench_S1002_v3.prw").to_str().unwrap(),
        "--rail",
        shipped("profiles/MBench_UIC60_v3.prr").to_str().unwrap(),
        "--rail-inclination",
        "0",
        "--wheel-load-n",
        "10000",
        "--y-range-mm",
        "10",
        "--y-step-mm",
        "0.5",
        "--json",
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let ct = &v["contact_table"];
    assert_eq!(ct["rows"], 41);
    let left = ct["flange_contact_left_mm"].as_f64().unwrap();
    assert!((5.0..=7.5).contains(&left), "flange contact at {left} mm");
    assert_eq!(ct["conicity"]["tan_gamma_e"].as_array().unwrap().len(), 6);

    let table = schema::read_contact_table(&out)
        .unwrap()
        .expect("a contact table");
    assert_eq!(table.y_m.len(), 41);
    assert_eq!(table.meta.support, "elastic");
    // Symmetry of the table: Δr(−y) = −Δr(y).
    let n = table.y_m.len();
    for i in 0..n {
        let (a, b) = (table.rows[i].delta_r_m, table.rows[n - 1 - i].delta_r_m);
        assert!((a + b).abs() < 1e-9, "Δr not odd at y = {}", table.y_m[i]);
    }
    // Interpolation at run time.
    let (h, _, dr) = table.wheelset_at(0.00125).unwrap();
    assert!(h > 0.45 && h < 0.47 && dr > 0.0);
    assert!(table.wheelset_at(0.02).is_err());
}

#[test]
fn build_with_profiles_writes_track_and_contact_table() {
    let dir = scratch("build_with_profiles");
    let out = dir.join("ml95.h5");
    let o = run(track_preproc().args([
        "build",
        "--centerline",
        shipped("tracks/straight_300m/centerline.csv")
            .to_str()
            .unwrap(),
        "--wheel",
        shipped("profiles/ml95_like/ml95_like_wheel.csv")
            .to_str()
            .unwrap(),
        "--rail",
        shipped("profiles/MBench_UIC60_v3.prr").to_str().unwrap(),
        "--rail-inclination",
        "1:40",
        "--rail-profile-cant",
        "1:40",
        "--wheel-radius",
        "0.43",
        "--y-step-mm",
        "0.5",
        "--json",
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let con = v["contact_table"]["conicity"]["tan_gamma_e"]
        .as_array()
        .unwrap();
    // The 1:20 cone: λ = 0.05 plus the roll effect on a 300 mm crown (≈ 5 %).
    for t in con {
        let t = t.as_f64().unwrap();
        assert!((t - 0.0525).abs() < 0.003, "tan γe = {t}");
    }
    let flange = v["contact_table"]["flange_contact_left_mm"]
        .as_f64()
        .unwrap();
    assert!(
        (6.0..=8.0).contains(&flange),
        "flange at {flange} mm (paper: about 7)"
    );
    assert!(schema::read_track(&out).is_ok());
    assert!(schema::read_contact_table(&out).unwrap().is_some());
    let prov = schema::read_provenance(&out).unwrap();
    let roles: Vec<&str> = prov.inputs.iter().map(|i| i.role.as_str()).collect();
    assert!(roles.contains(&"wheel_profile") && roles.contains(&"rail_profile"));
}

#[test]
fn contact_table_needs_both_profiles() {
    let dir = scratch("contact_table_one_profile");
    let o = run(track_preproc().args([
        "build",
        "--centerline",
        shipped("tracks/straight_300m/centerline.csv")
            .to_str()
            .unwrap(),
        "--wheel",
        shipped("profiles/MBench_S1002_v3.prw").to_str().unwrap(),
        "-o",
        dir.join("x.h5").to_str().unwrap(),
    ]));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--wheel and --rail"), "{}", stderr(&o));
}
