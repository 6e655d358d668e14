//! Online contact on tabulated tracks with curvature, cant, transitions and
//! irregularities (issue 3: "a wheelset in any 3-D pose on any tabulated
//! track"): the wheelset placed on the track follows it, both wheels find
//! their contacts, and the warm-started search keeps converging within 3
//! Newton iterations while the wheelset rolls along.

use std::path::{Path, PathBuf};

use preproc::contact_table::ContactTableConfig;
use preproc::{BuildConfig, BuildRequest, NoProgress, build_tables};
use runtime::contact::quasi_static::{Support, settle};
use runtime::contact::{ContactOptions, ContactSolver, FlangeSearch, WheelsetPose};
use runtime::geometry::track::{Side, TrackTables};

fn shipped(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tables")
        .join(rel)
}

fn track(dir: &str, irregular: bool) -> TrackTables {
    let req = BuildRequest {
        geometry: preproc::GeometryFiles::centerline(shipped(&format!(
            "tracks/{dir}/centerline.csv"
        ))),
        irregularities: irregular.then(|| shipped(&format!("tracks/{dir}/irregularities.csv"))),
        output: PathBuf::from("unused.h5"),
        config: BuildConfig {
            inclination: "1:40".parse().unwrap(),
            ..Default::default()
        },
        contact: None,
        command_line: String::new(),
    };
    build_tables(&req, &NoProgress).unwrap().0
}

fn ml95_config(track: &TrackTables) -> ContactTableConfig {
    ContactTableConfig {
        wheel_profile: shipped("profiles/ml95_like/ml95_like_wheel.csv"),
        rail_profile: shipped("profiles/MBench_UIC60_v3.prr"),
        wheel_radius_m: 0.43,
        gauge_m: track.meta.gauge_m,
        rail_spacing_m: track.meta.rail_spacing_m,
        rail_inclination_rad: track.meta.rail_inclination_rad,
        // The file is drawn canted 1:40: with the track's 1:40, 1:20 on purpose.
        rail_profile_cant_rad: Some((1.0_f64 / 40.0).atan()),
        ..Default::default()
    }
}

/// Roll the centred wheelset along `track` from `s0` to `s1` (2 cm steps),
/// at the height and roll of a rigid settling at `s0`, time stepping as a
/// run does (patches followed by warm start); returns the worst warm
/// iteration count and whether every step found contact on both wheels.
fn roll_along(track: &TrackTables, s0: f64, s1: f64) -> (u32, bool) {
    let model = ml95_config(track).model().unwrap().0;
    let mut solver = ContactSolver::new(ContactOptions {
        flange: FlangeSearch::Off,
        reuse_clear_pieces: true,
        ..Default::default()
    });
    let st = settle(&model, track, s0, 0.0, 0.0, Support::Rigid, &mut solver).unwrap();
    let (mut worst, mut both) = (0, true);
    let n = ((s1 - s0) / 0.02) as usize;
    for k in 1..=n {
        let s = s0 + 0.02 * k as f64;
        let pose = WheelsetPose::on_track(track, s, 0.0, st.height_m, 0.0, st.roll_rad).unwrap();
        let contacts = solver.solve(&model, track, &pose).unwrap();
        for side in Side::BOTH {
            let c = contacts.side(side).next();
            both &= c.is_some_and(|c| c.penetration_m.abs() < 5e-4);
            if let Some(c) = c {
                assert!(!c.cold_start, "cold start at s = {s}");
                worst = worst.max(c.iterations);
            }
        }
    }
    (worst, both)
}

/// On the R 300 m curve with 100 mm cant and its clothoids, the centred
/// wheelset rests on both rails with no roll relative to the canted track,
/// and rolls through the transition and the arc with warm starts only.
#[test]
fn wheelset_on_the_canted_curve_with_transitions() {
    let t = track("curve_r300", false);
    let model = ml95_config(&t).model().unwrap().0;
    let mut solver = ContactSolver::new(ContactOptions {
        flange: FlangeSearch::On,
        ..Default::default()
    });
    for s in [25.0, 80.0, 185.0, 290.0] {
        let st = settle(&model, &t, s, 0.0, 0.0, Support::Rigid, &mut solver).unwrap();
        // Roll relative to the track frame (which carries the cant): tiny.
        assert!(st.roll_rad.abs() < 2e-4, "roll {} at s = {s}", st.roll_rad);
        assert!(
            (st.height_m - 0.43).abs() < 2e-3,
            "height {} at s = {s}",
            st.height_m
        );
        let dr = st.rolling_radius_difference_m().unwrap();
        assert!(dr.abs() < 2e-4, "Δr {dr} at s = {s}");
    }
    // Through the entry clothoid into the arc.
    let (worst, both) = roll_along(&t, 40.0, 130.0);
    assert!(both, "a wheel lost its contact");
    assert!(worst <= 3, "warm Newton took {worst} iterations");
}

/// On the straight with irregularities (a few mm), the centred wheelset
/// rolling along keeps both contacts with warm starts within 3 iterations.
#[test]
fn wheelset_on_the_irregular_track() {
    let t = track("irregular_300m", true);
    let (worst, _) = roll_along(&t, 20.0, 60.0);
    assert!(worst <= 3, "warm Newton took {worst} iterations");
}
