//! Every rigid body's state in the results file (issue 14 §2): the
//! Cooperrider car (4 wheelsets, 2 frames, a car body) and the ML95-like
//! bogie (2 wheelsets, a frame; its car body a track-following reference)
//! on a straight, short runs. Frames and signs:
//! runtime/src/results/bodies.rs, docs/reference/04-table-files.md §4.4.

mod common;

use common::*;
use runtime::results::{BodyKind, CarBody, RunResults};

fn run_scene(dir: &std::path::Path, scene: &str, extra: &[&str]) -> RunResults {
    let out = dir.join("run.h5");
    let mut cmd = sim();
    cmd.arg("run")
        .arg(shipped(scene))
        .arg("-o")
        .arg(&out)
        .args(["--no-plots", "--quiet"]);
    for e in extra {
        cmd.args(["--set", e]);
    }
    let o = run(&mut cmd);
    assert!(o.status.success(), "{}", stderr(&o));
    runtime::io::schema::read_results(&out).expect("results")
}

#[test]
fn the_cooperrider_car_records_every_body_and_its_car_body() {
    let dir = scratch("body_states_cooperrider");
    let r = run_scene(
        &dir,
        "scenes/cooperrider_straight.toml",
        &["run.duration_s=0.3", "run.output_interval_s=0.001"],
    );
    let names: Vec<&str> = r.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "front bogie front",
            "front bogie rear",
            "rear bogie front",
            "rear bogie rear",
            "front frame",
            "rear frame",
            "car body"
        ]
    );
    assert_eq!(
        r.car_body,
        Some(CarBody {
            name: "car body".into(),
            rule: CarBody::BY_NAME.into()
        })
    );
    // A wheelset's body series agree with its wheelset columns (the same
    // section, yaw and roll: the angle sequence is chosen so).
    for (k, ws) in r.wheelsets.iter().enumerate() {
        let b = &r.bodies[k];
        assert_eq!(b.kind, BodyKind::Wheelset);
        for i in 0..r.len() {
            assert_eq!(b.track_s_m[i], ws.track_s_m[i]);
            assert!((b.lateral_m[i] - ws.lateral_m[i]).abs() < 1e-12);
            assert!((b.yaw_rad[i] - ws.yaw_rad[i]).abs() < 1e-12);
            assert!((b.roll_rad[i] - ws.roll_rad[i]).abs() < 1e-12);
            // Rolling at 40 m/s on r ≈ 0.425 m: the pitch rate is the spin.
            assert!((b.pitch_rate_rad_s[i] - 40.0 / 0.425).abs() < 0.5);
        }
    }
    let car = &r.bodies[6];
    assert_eq!(car.kind, BodyKind::Free);
    assert_eq!(car.assembly_height_m, 2.0596);
    // The car body rides at its assembly height and place (within 1 mm).
    for i in 0..r.len() {
        assert!(
            (car.vertical_m[i] - 2.0596).abs() < 1e-3,
            "{}",
            car.vertical_m[i]
        );
        assert!(car.longitudinal_m[i].abs() < 1e-3);
        assert!((car.longitudinal_velocity_m_s[i] - 40.0).abs() < 0.01);
    }
    // The ride accelerations come from the equations of motion: on a
    // straight they match the central difference of the velocities, plus
    // gravity's share along the rolled lateral axis (g sin roll), to the
    // difference's own error (1 ms samples).
    let g = 9.81;
    for b in &r.bodies[4..] {
        let (mut worst_lat, mut worst_vert, mut peak) = (0.0_f64, 0.0_f64, 0.0_f64);
        for i in 50..r.len() - 1 {
            let dt = r.time_s[i + 1] - r.time_s[i - 1];
            let a_n = (b.lateral_velocity_m_s[i + 1] - b.lateral_velocity_m_s[i - 1]) / dt;
            let a_b = (b.vertical_velocity_m_s[i + 1] - b.vertical_velocity_m_s[i - 1]) / dt;
            worst_lat = worst_lat
                .max((b.lateral_acceleration_m_s2[i] - (a_n + g * b.roll_rad[i].sin())).abs());
            worst_vert = worst_vert.max((b.vertical_acceleration_m_s2[i] - a_b).abs());
            peak = peak.max(b.lateral_acceleration_m_s2[i].abs());
        }
        eprintln!(
            "{}: peak lateral {peak:.4} m/s², worst lateral {worst_lat:.2e}, vertical {worst_vert:.2e} m/s²",
            b.name
        );
        assert!(peak > 1e-3, "{}: no motion to compare", b.name);
        assert!(worst_lat < 0.05 * peak + 2e-3, "{}: {worst_lat}", b.name);
        assert!(worst_vert < 0.05 * peak + 2e-3, "{}: {worst_vert}", b.name);
    }
}

#[test]
fn the_bogie_has_no_car_body_among_its_bodies() {
    let dir = scratch("body_states_bogie");
    let r = run_scene(&dir, "scenes/bogie_straight.toml", &["run.distance_m=5"]);
    let names: Vec<&str> = r.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["front", "rear", "frame"]);
    // Its car body ("car") is a track-following reference, not a body.
    assert_eq!(r.car_body, None);
    let frame = &r.bodies[2];
    assert_eq!(frame.kind, BodyKind::Free);
    assert!(frame.lateral_m.iter().all(|v| v.is_finite()));
    assert!(
        frame
            .vertical_acceleration_m_s2
            .iter()
            .all(|v| v.is_finite())
    );
}
