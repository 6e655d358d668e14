//! Quick experiment: the ML95-like wheelset on a straight track.
//! `cargo run --release -p runtime --example wheelset_run -- SPEED DT LAW`

use std::path::Path;
use std::time::Instant;

use nalgebra::Matrix3;
use runtime::body::RigidBody;
use runtime::contact::{ContactOptions, FlangeSearch, WheelsetContactModel};
use runtime::contact_force::ContactForceSettings;
use runtime::creep::CreepLaw;
use runtime::dynamics::{
    InitialConditions, Recorder, SystemSettings, VehicleModel, VehicleSystem, WheelsetSpec,
};
use runtime::integrator::{Method, OutputGrid, Rk4, integrate};
use runtime::profile::{RailPlacement, RailProfileOptions, WheelProfileOptions};
use runtime::profile_import::{ImportOptions, load_rail, load_wheel};
use runtime::track::straight_track;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let speed: f64 = args.get(1).map_or(10.0, |s| s.parse().unwrap());
    let dt: f64 = args.get(2).map_or(1e-4, |s| s.parse().unwrap());
    let law = args.get(3).map_or("polach", |s| s.as_str());
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tables/profiles");
    let wheel = load_wheel(
        &dir.join("ml95_like/ml95_like_wheel.csv"),
        &ImportOptions::default(),
        WheelProfileOptions {
            nominal_radius_m: 0.43,
            ..Default::default()
        },
    )
    .unwrap();
    let rail = load_rail(
        &dir.join("MBench_UIC60_v3.prr"),
        &ImportOptions::default(),
        RailProfileOptions::default(),
    )
    .unwrap();
    let placement = RailPlacement {
        gauge_m: 1.435,
        rail_spacing_m: 1.507,
        inclination_rad: (1.0f64 / 40.0).atan(),
    };
    let track = straight_track(
        300.0,
        0.1,
        placement.gauge_m,
        placement.rail_spacing_m,
        placement.inclination_rad,
    );
    let contact =
        WheelsetContactModel::new(wheel.clone(), wheel, 1.360, &rail, &rail, placement).unwrap();
    let mass = 1430.0;
    let vehicle = VehicleModel {
        name: "ML95-like wheelset".into(),
        wheelsets: vec![WheelsetSpec {
            name: "ws".into(),
            body: RigidBody {
                mass_kg: mass,
                inertia_kg_m2: Matrix3::from_diagonal(&nalgebra::Vector3::new(790.0, 82.0, 790.0)),
            },
            contact,
            x_m: 0.0,
            y_m: 0.0,
            nominal_radius_m: 0.43,
            static_wheel_load_n: 0.5 * mass * 9.81,
        }],
        bodies: vec![],
        references: vec![],
        elements: vec![],
    };
    let settings = SystemSettings {
        forces: ContactForceSettings {
            creep_law: CreepLaw::from_name(law).unwrap(),
            ..Default::default()
        },
        contact: ContactOptions {
            flange: FlangeSearch::Auto,
            ..Default::default()
        },
        speed_m_s: speed,
        s_start_m: 5.0,
        ..Default::default()
    };
    let (mut system, y0) = VehicleSystem::assemble(
        &track,
        &vehicle,
        settings,
        InitialConditions {
            lateral_m: -0.002,
            yaw_rad: 0.0,
        },
    )
    .unwrap();
    for sv in system.solvers() {
        eprintln!("options {:?}", sv.options);
    }
    let mut rec = Recorder::new(&system);
    let t_end: f64 = args.get(4).map_or(280.0 / speed, |s| s.parse().unwrap());
    let start = Instant::now();
    let stats = integrate(
        &Method::Rk4(Rk4 { step_s: dt }),
        &mut system,
        0.0,
        &y0,
        t_end,
        &OutputGrid { interval_s: 0.01 },
        &mut |sys, t, y| rec.record(sys, t, y),
    );
    let wall = start.elapsed().as_secs_f64();
    match &stats {
        Ok(s) => eprintln!(
            "steps {} rhs {} t_end {:.3} wall {wall:.3} s",
            s.steps, s.rhs_evaluations, s.t_end_reached
        ),
        Err(e) => eprintln!("error: {e} after {wall:.3} s"),
    }
    for sv in system.solvers() {
        eprintln!("solver stats {:?}", sv.stats);
    }
    eprintln!("counters {:?}", system.counters());
    let r = &rec.results;
    let ws = &r.wheelsets[0];
    for i in (0..r.len()).step_by(20) {
        println!(
            "{:8.3} {:8.3} {:+8.3} {:+8.3} N {:7.0} {:7.0} Y {:+7.0} {:+7.0} fl {} {}",
            r.time_s[i],
            ws.distance_m[i],
            ws.lateral_m[i] * 1e3,
            ws.yaw_rad[i] * 1e3,
            ws.wheels[0].zones[0].normal_n[i],
            ws.wheels[1].zones[0].normal_n[i],
            ws.wheels[0].zones[0].lateral_force_n[i],
            ws.wheels[1].zones[0].lateral_force_n[i],
            ws.wheels[0].flange_contact[i],
            ws.wheels[1].flange_contact[i],
        );
    }
}
