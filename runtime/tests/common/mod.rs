//! Helpers shared by the runtime's integration tests: the shipped profiles
//! and the S1002 / UIC60 wheelset of the Manchester contact benchmark.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use runtime::contact::{ContactOptions, ContactSolver, FlangeSearch, WheelsetContactModel};
use runtime::profile::{RailPlacement, RailProfileOptions, WheelProfileOptions};
use runtime::profile_import::{ImportOptions, load_rail, load_wheel};
use runtime::track::{TrackTables, straight_track};

/// A profile shipped under `tables/profiles/`.
pub fn shipped(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tables/profiles")
        .join(rel)
}

/// S1002 wheels on UIC60 rails (the rail file is already canted 1:40),
/// gauge 1435 mm, flange backs 1360 mm apart, rails 1507 mm apart.
pub fn s1002_model() -> WheelsetContactModel {
    let wheel = load_wheel(
        &shipped("MBench_S1002_v3.prw"),
        &ImportOptions::default(),
        WheelProfileOptions::default(),
    )
    .unwrap();
    let rail = load_rail(
        &shipped("MBench_UIC60_v3.prr"),
        &ImportOptions::default(),
        RailProfileOptions::default(),
    )
    .unwrap();
    WheelsetContactModel::new(
        wheel.clone(),
        wheel,
        1.360,
        &rail,
        &rail,
        RailPlacement {
            gauge_m: 1.435,
            rail_spacing_m: 1.507,
            inclination_rad: 0.0,
        },
    )
    .unwrap()
}

/// A 20 m straight track matching the model's rail placement.
pub fn track_for(model: &WheelsetContactModel) -> TrackTables {
    let p = model.placement();
    straight_track(20.0, 0.1, p.gauge_m, p.rail_spacing_m, p.inclination_rad)
}

/// A solver that always searches the flange.
pub fn solver() -> ContactSolver {
    ContactSolver::new(ContactOptions {
        flange: FlangeSearch::On,
        ..Default::default()
    })
}
