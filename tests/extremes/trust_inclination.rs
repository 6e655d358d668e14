//! Trust (issue 12): the rail inclination. One default in every command;
//! a rail profile file that already carries a cant is detected (or
//! declared) and double canting is refused in every command; table files
//! record their inclination and rail profile, and a scene stating another
//! one is refused naming both (docs/reference/05-surfaces.md §5.7,
//! docs/reference/04-table-files.md §4.1).

use std::path::{Path, PathBuf};

use clap::CommandFactory;
use runtime::geometry::profile::rail_cant::{
    CantSource, detect_cant_rad, internal_outline, sha256_hex,
};

use super::common::*;

/// The shipped UIC60 rail, drawn canted 1:40.
fn mbench() -> PathBuf {
    shipped("profiles/MBench_UIC60_v3.prr")
}

/// atan(1/n) (rad).
fn slope(n: f64) -> f64 {
    (1.0 / n).atan()
}

/// The shipped UIC60 rail turned by `turn_rad` (positive: head towards the
/// track centre, the inclination's sense) about its origin, written as a
/// CSV profile (y towards the field side, z up, mm) into `dir`.
fn turned_mbench(dir: &Path, name: &str, turn_rad: f64) -> PathBuf {
    let f = runtime::io::profile_import::read_profile(&mbench(), &Default::default())
        .expect("shipped rail");
    let (s, c) = (-turn_rad).sin_cos();
    let mut csv = String::from("y_mm,z_mm\n");
    for (u, z) in internal_outline(&f.points_m, f.z_down) {
        let (u, z) = (u * c - z * s, u * s + z * c);
        csv += &format!("{:.9},{:.9}\n", -u * 1e3, z * 1e3);
    }
    let path = dir.join(name);
    std::fs::write(&path, csv).expect("write a profile");
    path
}

/// The carried cant detected in a profile file (rad).
fn detected(path: &Path) -> f64 {
    let f = runtime::io::profile_import::read_profile(path, &Default::default()).expect("profile");
    detect_cant_rad(&internal_outline(&f.points_m, f.z_down)).expect("detected")
}

#[test]
fn the_carried_cant_is_detected_canted_upright_and_at_1_in_20() {
    let dir = scratch("trust_inclination_detect");
    let found = detected(&mbench());
    assert!((found - slope(40.0)).abs() < 1e-5, "MBench: {found} rad");
    let upright = turned_mbench(&dir, "upright.csv", -found);
    let steep = turned_mbench(&dir, "steep.csv", slope(20.0) - found);
    assert!(detected(&upright).abs() < 1e-5, "upright");
    assert!((detected(&steep) - slope(20.0)).abs() < 1e-5, "1:20");
}

/// `sim contact` of the S1002 wheel at 2 mm (JSON): the left wheel's tread
/// rolling radius and contact angle.
fn s1002_contact(rail: &Path, extra: &[&str]) -> (f64, f64) {
    let o = run(sim()
        .args(["contact", "--wheel"])
        .arg(shipped("profiles/MBench_S1002_v3.prw"))
        .arg("--rail")
        .arg(rail)
        .args(["--y-mm", "2", "--json"])
        .args(extra));
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    let c = &v["wheels"][0]["contacts"][0];
    (
        c["rolling_radius_m"].as_f64().expect("r"),
        c["contact_angle_rad"].as_f64().expect("angle"),
    )
}

#[test]
fn an_upright_rail_with_the_default_is_the_canted_file_with_0() {
    let dir = scratch("trust_inclination_same_rail");
    let upright = turned_mbench(&dir, "upright.csv", -detected(&mbench()));
    let (r0, a0) = s1002_contact(&mbench(), &["--rail-inclination", "0"]);
    let (r1, a1) = s1002_contact(&upright, &[]);
    assert!((r0 - r1).abs() < 1e-7, "rolling radius {r0} against {r1} m");
    assert!(
        (a0 - a1).abs() < 1e-5,
        "contact angle {a0} against {a1} rad"
    );
}

/// The double-canting refusal: the command fails naming the file, the
/// carried cant, the inclination and what to give instead.
fn assert_double_canting(o: &std::process::Output, file: &str, instead: &[&str]) {
    assert!(!o.status.success(), "accepted: {}", stdout(o));
    let e = stderr(o);
    for part in [
        "double canting",
        file,
        "already carries a cant of 1:40",
        "1:20 in all",
    ]
    .iter()
    .chain(instead)
    {
        assert!(e.contains(part), "{part}: {e}");
    }
}

#[test]
fn double_canting_is_refused_in_every_command() {
    let dir = scratch("trust_inclination_double");
    let cli = ["--rail-inclination 0", "--rail-profile-cant 1:40"];
    // sim contact with its defaults.
    let o = run(sim()
        .args(["contact", "--wheel"])
        .arg(shipped("profiles/MBench_S1002_v3.prw"))
        .arg("--rail")
        .arg(mbench()));
    assert_double_canting(&o, "MBench_UIC60_v3.prr", &cli);
    // track-preproc contact-table and build, with their defaults.
    let o = run(track_preproc()
        .args(["contact-table", "--wheel"])
        .arg(shipped("profiles/MBench_S1002_v3.prw"))
        .arg("--rail")
        .arg(mbench())
        .arg("-o")
        .arg(dir.join("ct.h5")));
    assert_double_canting(&o, "MBench_UIC60_v3.prr", &cli);
    for extra in [&["--wheel", "profiles/MBench_S1002_v3.prw"][..], &[]] {
        let mut c = track_preproc();
        c.args(["build", "--centerline"])
            .arg(shipped("tracks/straight_300m/centerline.csv"))
            .arg("--rail")
            .arg(mbench())
            .arg("-o")
            .arg(dir.join("t.h5"));
        if let [flag, rel] = extra {
            c.arg(flag).arg(shipped(rel));
        }
        assert_double_canting(&run(&mut c), "MBench_UIC60_v3.prr", &cli);
    }
    // A file canted 1:20 is refused too, naming its cant.
    let steep = turned_mbench(&dir, "steep.csv", slope(20.0) - detected(&mbench()));
    let o = run(sim()
        .args(["contact", "--wheel"])
        .arg(shipped("profiles/MBench_S1002_v3.prw"))
        .arg("--rail")
        .arg(&steep));
    assert!(
        !o.status.success() && stderr(&o).contains("a cant of 1:20"),
        "{}",
        stderr(&o)
    );
    // sim run with the shipped scene less its declaration.
    let o = run(sim()
        .arg("run")
        .arg(shipped("scenes/wheelset_straight.toml"))
        .args(["--set", "track.rail_profile_cant=", "--plan-only"]));
    assert_double_canting(
        &o,
        "MBench_UIC60_v3.prr",
        &[
            "[track] rail_inclination = \"0\"",
            "[track] rail_profile_cant = \"1:40\"",
        ],
    );
    // Nothing was written.
    assert!(!dir.join("ct.h5").exists() && !dir.join("t.h5").exists());
}

#[test]
fn a_declared_cant_adds_the_inclination_on_purpose() {
    let dir = scratch("trust_inclination_declared");
    let o = run(track_preproc()
        .args(["contact-table", "--wheel"])
        .arg(shipped("profiles/MBench_S1002_v3.prw"))
        .arg("--rail")
        .arg(mbench())
        .args(["--rail-profile-cant", "1:40", "--wheel-load-n", "10000"])
        .args(["--y-range-mm", "5", "--y-step-mm", "0.5", "-o"])
        .arg(dir.join("ct.h5")));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains(
            "rail cant         1:40 in the file (declared) + inclination 1:40 = 1:20 in the track"
        ),
        "{}",
        stdout(&o)
    );
    // A declaration without a rail profile is refused, not dropped.
    let o = run(track_preproc()
        .args(["build", "--centerline"])
        .arg(shipped("tracks/straight_300m/centerline.csv"))
        .args(["--rail-profile-cant", "1:40", "-o"])
        .arg(dir.join("t.h5")));
    assert!(
        !o.status.success() && stderr(&o).contains("give --rail too"),
        "{}",
        stderr(&o)
    );
    // A declaration the head contradicts is a warning, not silence.
    let o = run(track_preproc()
        .args(["contact-table", "--wheel"])
        .arg(shipped("profiles/MBench_S1002_v3.prw"))
        .arg("--rail")
        .arg(mbench())
        .args(["--rail-profile-cant", "0", "--wheel-load-n", "10000"])
        .args(["--y-range-mm", "5", "--y-step-mm", "0.5", "-o"])
        .arg(dir.join("ct0.h5")));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("declared to carry a cant of 0, but its head looks canted 1:40"),
        "{}",
        stderr(&o)
    );
}

/// The SHA-256 of the shipped rail (tables/profiles/README.md).
const MBENCH_SHA256: &str = "5a431b69bd7ae8418b641412da6fdf1d852f4d9865080875cf3f0f3e874e3588";

#[test]
fn table_files_record_their_inclination_and_rail_profile() {
    let dir = scratch("trust_inclination_record");
    let bytes = std::fs::read(mbench()).expect("shipped rail");
    assert_eq!(sha256_hex(&bytes), MBENCH_SHA256);
    let track = dir.join("t0.h5");
    let o = run(track_preproc()
        .args(["build", "--centerline"])
        .arg(shipped("tracks/straight_300m/centerline.csv"))
        .arg("--rail")
        .arg(mbench())
        .args(["--rail-inclination", "0", "-o"])
        .arg(&track));
    assert!(o.status.success(), "{}", stderr(&o));
    let meta = runtime::io::schema::read_track_meta(&track).expect("meta");
    assert_eq!(meta.rail_inclination_rad, 0.0);
    let r = meta.rail_profile.expect("the rail profile recorded");
    assert!(r.file.ends_with("MBench_UIC60_v3.prr"), "{}", r.file);
    assert_eq!(r.sha256, MBENCH_SHA256);
    assert_eq!(r.carried_cant_source, CantSource::Detected);
    assert!((r.carried_cant_rad - slope(40.0)).abs() < 1e-5);
    // The contact table file records them too.
    let ct = dir.join("ct.h5");
    let o = run(track_preproc()
        .args(["contact-table", "--wheel"])
        .arg(shipped("profiles/MBench_S1002_v3.prw"))
        .arg("--rail")
        .arg(mbench())
        .args(["--rail-inclination", "0", "--wheel-load-n", "10000"])
        .args(["--y-range-mm", "5", "--y-step-mm", "0.5", "-o"])
        .arg(&ct));
    assert!(o.status.success(), "{}", stderr(&o));
    let t = runtime::io::schema::read_contact_table(&ct)
        .expect("read")
        .expect("a contact table");
    assert_eq!(t.meta.rail_inclination_rad, 0.0);
    let r = t.meta.rail_record.expect("the rail profile recorded");
    assert_eq!(r.sha256, MBENCH_SHA256);
    assert_eq!(r.carried_cant_source, CantSource::Detected);
}

/// A scene on the table file `tables` with `track` lines added.
fn table_scene(dir: &Path, name: &str, tables: &Path, rail: &Path, track: &str) -> PathBuf {
    let text = format!(
        r#"[track]
tables = "{tables}"
rail_profile = "{rail}"
{track}
[vehicle]
file = "{vehicle}"
[initial]
speed_m_s = 10.0
[run]
distance_m = 1.0
step_s = 1e-4
"#,
        tables = tables.display(),
        rail = rail.display(),
        vehicle = shipped("vehicles/ml95_like_wheelset.toml").display(),
    );
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write a scene");
    path
}

/// `sim run SCENE --plan-only`.
fn plan_only(scene: &Path) -> std::process::Output {
    run(sim().arg("run").arg(scene).arg("--plan-only"))
}

#[test]
fn a_scene_stating_another_inclination_or_rail_than_its_table_is_refused() {
    let dir = scratch("trust_inclination_scene");
    let track = dir.join("t0.h5");
    let o = run(track_preproc()
        .args(["build", "--centerline"])
        .arg(shipped("tracks/straight_300m/centerline.csv"))
        .arg("--rail")
        .arg(mbench())
        .args(["--rail-inclination", "0", "-o"])
        .arg(&track));
    assert!(o.status.success(), "{}", stderr(&o));
    // The table's inclination, not stated: accepted.
    let o = plan_only(&table_scene(&dir, "same.toml", &track, &mbench(), ""));
    assert!(o.status.success(), "{}", stderr(&o));
    // Stated and the same: accepted.
    let s = table_scene(
        &dir,
        "zero.toml",
        &track,
        &mbench(),
        "rail_inclination = \"0\"",
    );
    assert!(plan_only(&s).status.success());
    // Another inclination: refused naming both.
    let s = table_scene(
        &dir,
        "other.toml",
        &track,
        &mbench(),
        "rail_inclination = \"1:40\"",
    );
    let o = plan_only(&s);
    let e = stderr(&o);
    assert!(!o.status.success(), "accepted");
    for part in [
        "[track] rail_inclination = \"1:40\"",
        "t0.h5",
        "rail inclination 0",
    ] {
        assert!(e.contains(part), "{part}: {e}");
    }
    // Another rail profile (the same rail drawn upright): refused naming both.
    let upright = turned_mbench(&dir, "upright.csv", -detected(&mbench()));
    let o = plan_only(&table_scene(&dir, "rail.toml", &track, &upright, ""));
    let e = stderr(&o);
    assert!(!o.status.success(), "accepted");
    for part in [
        "upright.csv",
        "MBench_UIC60_v3.prr",
        "t0.h5",
        &MBENCH_SHA256[..12],
    ] {
        assert!(e.contains(part), "{part}: {e}");
    }
    // A table file that records no rail profile: a warning names it.
    let bare = dir.join("bare.h5");
    let o = run(track_preproc()
        .args(["build", "--centerline"])
        .arg(shipped("tracks/straight_300m/centerline.csv"))
        .args(["--rail-inclination", "0", "-o"])
        .arg(&bare));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = plan_only(&table_scene(&dir, "bare.toml", &bare, &mbench(), ""));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("bare.h5 does not record the rail profile"),
        "{}",
        stderr(&o)
    );
    // A table built at the default 1:40 without a rail: the canted rail on
    // it is double canting, refused, naming the table file.
    let bare40 = dir.join("bare40.h5");
    let o = run(track_preproc()
        .args(["build", "--centerline"])
        .arg(shipped("tracks/straight_300m/centerline.csv"))
        .arg("-o")
        .arg(&bare40));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = plan_only(&table_scene(&dir, "double.toml", &bare40, &mbench(), ""));
    assert_double_canting(
        &o,
        "MBench_UIC60_v3.prr",
        &[
            "bare40.h5 was built with the rail inclination 1:40",
            "a table file built with --rail-inclination 0",
            "[track] rail_profile_cant = \"1:40\"",
        ],
    );
    // The upright rail at the default 1:40: accepted.
    let t40 = dir.join("t40.h5");
    let o = run(track_preproc()
        .args(["build", "--centerline"])
        .arg(shipped("tracks/straight_300m/centerline.csv"))
        .arg("--rail")
        .arg(&upright)
        .arg("-o")
        .arg(&t40));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = plan_only(&table_scene(&dir, "t40.toml", &t40, &upright, ""));
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn one_default_rail_inclination_in_every_command_and_scene() {
    let default = preproc::config::DEFAULT_RAIL_INCLINATION;
    assert_eq!(default, "1:40");
    let of = |cmd: &clap::Command, sub: &str| -> String {
        let sub = cmd
            .find_subcommand(sub)
            .unwrap_or_else(|| panic!("no subcommand {sub}"));
        let arg = sub
            .get_arguments()
            .find(|a| a.get_long() == Some("rail-inclination"))
            .unwrap_or_else(|| panic!("{sub:?} has no --rail-inclination"));
        let d = arg.get_default_values();
        assert_eq!(d.len(), 1);
        d[0].to_string_lossy().into_owned()
    };
    let sim = railsim::cli::Cli::command();
    let preproc = preproc::cli::Cli::command();
    assert_eq!(of(&sim, "contact"), default, "sim contact");
    assert_eq!(of(&preproc, "build"), default, "track-preproc build");
    assert_eq!(
        of(&preproc, "contact-table"),
        default,
        "track-preproc contact-table"
    );
    // A scene that does not state it builds its track at the default.
    let scene: railsim::config::scene::Scene = toml::from_str(
        "[track]\nstraight_m = 50.0\nrail_profile = \"r.prr\"\n[vehicle]\nfile = \"v.toml\"\n[initial]\nspeed_m_s = 1.0\n[run]\nduration_s = 1.0\n",
    )
    .expect("scene");
    assert_eq!(scene.track.rail_inclination, None);
    assert_eq!(
        scene.track.inclination().expect("default").angle_rad,
        default.parse::<preproc::Inclination>().unwrap().angle_rad
    );
}
