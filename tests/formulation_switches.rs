//! The `[formulation]` switches (issue 15; docs/guide/cooperrider-cross-code.md):
//! each one changes what it says and is named in the run's outputs.

mod common;

use common::*;

const SCENE: &str = "scenes/cooperrider_straight.toml";

/// Runs the Cooperrider scene for `duration` s with `sets`, returns the
/// results.
fn run_car(name: &str, duration: f64, sets: &[&str]) -> (runtime::results::RunResults, String) {
    let dir = scratch(name);
    let out = dir.join("run.h5");
    let mut cmd = sim();
    cmd.arg("run")
        .arg(shipped(SCENE))
        .args(["--set", &format!("run.duration_s={duration}")])
        .args(["--set", "run.output_interval_s=0.01"]);
    for s in sets {
        cmd.args(["--set", s]);
    }
    let o = run(cmd.arg("-o").arg(&out));
    assert!(o.status.success(), "{}", stderr(&o));
    (
        runtime::io::schema::read_results(&out).expect("results"),
        stdout(&o),
    )
}

/// The largest departure (m/s) of any wheelset's forward speed from the
/// references' V0 − a t.
fn speed_error(r: &runtime::results::RunResults, v0: f64, a: f64) -> f64 {
    r.wheelsets
        .iter()
        .flat_map(|w| {
            r.time_s
                .iter()
                .zip(&w.speed_m_s)
                .map(move |(t, v)| (v - (v0 - a * t)).abs())
        })
        .fold(0.0, f64::max)
}

#[test]
fn imposed_longitudinal_motion_holds_every_wheelset_at_the_references_speed_through_a_ramp() {
    let ramp = ["initial.deceleration_m_s2=2", "initial.speed_m_s=40"];
    let (free, _) = run_car("formulation_free", 1.0, &ramp);
    let mut imposed_sets = ramp.to_vec();
    imposed_sets.push("formulation.longitudinal_motion=imposed");
    let (imposed, text) = run_car("formulation_imposed", 1.0, &imposed_sets);
    let (e_free, e_imposed) = (
        speed_error(&free, 40.0, 2.0),
        speed_error(&imposed, 40.0, 2.0),
    );
    // Imposed: the tangential acceleration is dV/dt exactly (RK4 integrates
    // a constant exactly); free: the wheelsets lag on their longitudinal
    // primary springs as the car decelerates.
    assert!(e_imposed < 1e-6, "imposed: {e_imposed} m/s");
    assert!(e_free > 100.0 * e_imposed.max(1e-9), "free: {e_free} m/s");
    assert!(
        text.contains("formulation (published switches): longitudinal_motion = imposed"),
        "{text}"
    );
}

#[test]
fn the_published_preset_names_every_switch_in_the_results_and_a_switch_set_alone_overrides_it() {
    let (r, _) = run_car(
        "formulation_published",
        0.2,
        &[
            "formulation.preset=published",
            "formulation.gyroscopic=exact",
        ],
    );
    let attr = r
        .attributes
        .iter()
        .find(|(k, _)| k == "formulation")
        .map(|(_, v)| format!("{v:?}"))
        .expect("a formulation attribute");
    for s in [
        "table_interpolation = cubic_spline",
        "contact_normal = rolled",
        "longitudinal_motion = imposed",
        "element_axes = track",
        "roll_moment = axle_arm_only",
    ] {
        assert!(attr.contains(s), "{s} missing from {attr}");
    }
    assert!(!attr.contains("gyroscopic"), "{attr}");
}

#[test]
fn a_switch_of_the_imported_table_needs_an_imported_table() {
    let o = run(sim()
        .arg("run")
        .arg(shipped("scenes/wheelset_straight.toml"))
        .args([
            "--set",
            "formulation.contact_normal=rolled",
            "--set",
            "run.duration_s=0.1",
        ]));
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("contact_normal") && e.contains("method = \"imported\""),
        "{e}"
    );
}
