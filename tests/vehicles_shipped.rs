//! The shipped vehicle files (`tables/vehicles/`): they load, validate, and
//! carry the numbers `tables/vehicles/README.md` documents.

use std::f64::consts::PI;
use std::path::PathBuf;

use railsim::config::vehicle::{GRAVITY_M_S2, VehicleFile};

fn vehicle(name: &str) -> VehicleFile {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tables/vehicles")
        .join(name);
    VehicleFile::load(&path).unwrap_or_else(|e| panic!("{}: {e:#}", path.display()))
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

// The numbers of tables/vehicles/README.md.
const WHEELSET_KG: f64 = 1430.0;
const WHEELSET_INERTIA: [f64; 3] = [790.0, 82.0, 790.0];
const FRAME_KG: f64 = 3600.0;
const CAR_SHARE_KG: f64 = 13_840.0;
const BOGIE_KG: f64 = 6460.0;
const LOADED_CAR_KG: f64 = 40_600.0;
const WHEELBASE_M: f64 = 2.1;
const AIR_SPRING_PRELOAD_N: f64 = 67_885.2;
const PRIMARY_PRELOAD_N: f64 = 42_771.6;
const WHEEL_LOAD_N: f64 = 49_785.75;
const BARE_WHEEL_LOAD_N: f64 = 7014.15;

#[test]
fn the_wheelset_file_is_the_bare_wheelset() {
    let v = vehicle("ml95_like_wheelset.toml");
    v.validate().unwrap();
    assert_eq!(v.name, "ML95-like wheelset");
    assert_eq!(v.wheelsets.len(), 1);
    assert!(v.bodies.is_empty() && v.references.is_empty() && v.elements.is_empty());
    let w = &v.wheelsets[0];
    assert_eq!(w.x_m, 0.0);
    assert_eq!(w.mass_kg, WHEELSET_KG);
    assert_eq!(w.inertia_kg_m2, WHEELSET_INERTIA);
    assert_eq!(w.back_to_back_m, 1.360);
    assert_eq!(w.nominal_radius_m, 0.43);
    // Taping lines at ±(1.360/2 + 0.070) m: the paper's b0 = 0.75 m.
    assert!(close(w.back_to_back_m / 2.0 + 0.070, 0.75, 1e-12));
    let load = v.static_wheel_load_n(w);
    assert!(close(load, 0.5 * w.mass_kg * GRAVITY_M_S2, 1e-9), "{load}");
    assert!(close(load, BARE_WHEEL_LOAD_N, 1e-6), "{load}");
    assert!(
        v.profile_path(w).is_file(),
        "{}",
        v.profile_path(w).display()
    );
}

#[test]
fn the_bogie_file_carries_half_a_loaded_car_on_two_wheelsets() {
    let v = vehicle("ml95_like_bogie.toml");
    v.validate().unwrap();
    assert_eq!(v.name, "ML95-like bogie");
    assert_eq!(v.wheelsets.len(), 2);
    assert_eq!(v.bodies.len(), 1);
    assert_eq!(v.references.len(), 1);
    assert_eq!(v.references[0].name, "car");
    assert_eq!(v.elements.len(), 6);

    // The wheelsets are the shipped single wheelset, at ±wheelbase/2.
    let single = vehicle("ml95_like_wheelset.toml").wheelsets[0].clone();
    let xs: Vec<f64> = v.wheelsets.iter().map(|w| w.x_m).collect();
    assert_eq!(xs, [WHEELBASE_M / 2.0, -WHEELBASE_M / 2.0]);
    for w in &v.wheelsets {
        assert_eq!(w.mass_kg, single.mass_kg);
        assert_eq!(w.inertia_kg_m2, single.inertia_kg_m2);
        assert_eq!(w.wheel_profile, single.wheel_profile);
        assert_eq!(w.back_to_back_m, single.back_to_back_m);
        assert_eq!(w.nominal_radius_m, single.nominal_radius_m);
        assert!(
            v.profile_path(w).is_file(),
            "{}",
            v.profile_path(w).display()
        );
    }

    // Mass bookkeeping.
    let frame = &v.bodies[0];
    assert_eq!(frame.name, "frame");
    assert_eq!(frame.mass_kg, FRAME_KG);
    let bogie_kg = frame.mass_kg + v.wheelsets.iter().map(|w| w.mass_kg).sum::<f64>();
    assert_eq!(bogie_kg, BOGIE_KG);
    assert_eq!(CAR_SHARE_KG, 0.5 * (LOADED_CAR_KG - 2.0 * BOGIE_KG));

    // Preloads: the air springs carry the car share, the axle boxes the
    // car share and the frame.
    let secondary: Vec<_> = v.elements.iter().filter(|e| e.body_a == "car").collect();
    let primary: Vec<_> = v.elements.iter().filter(|e| e.body_a == "frame").collect();
    assert_eq!((secondary.len(), primary.len()), (2, 4));
    for e in &secondary {
        assert_eq!(e.body_b, "frame");
        assert_eq!(e.preload_n, [0.0, 0.0, -AIR_SPRING_PRELOAD_N]);
    }
    for e in &primary {
        assert_eq!(e.preload_n, [0.0, 0.0, -PRIMARY_PRELOAD_N]);
    }
    let carried_kg = -secondary.iter().map(|e| e.preload_n[2]).sum::<f64>() / GRAVITY_M_S2;
    assert!(close(carried_kg, CAR_SHARE_KG, 1e-6), "{carried_kg}");
    assert!(close(
        4.0 * PRIMARY_PRELOAD_N,
        (FRAME_KG + CAR_SHARE_KG) * GRAVITY_M_S2,
        1e-6
    ));

    // Static wheel loads: equal, in 45–55 kN, and the four of them carry
    // the bogie and the car share.
    let loads: Vec<f64> = v
        .wheelsets
        .iter()
        .map(|w| v.static_wheel_load_n(w))
        .collect();
    assert_eq!(loads[0], loads[1]);
    for &q in &loads {
        assert!((45e3..=55e3).contains(&q), "{q}");
        assert!(close(q, WHEEL_LOAD_N, 1e-6), "{q}");
    }
    let total_kg = 2.0 * (loads[0] + loads[1]) / GRAVITY_M_S2;
    assert!(close(total_kg, BOGIE_KG + CAR_SHARE_KG, 1e-6), "{total_kg}");
}

/// The hand estimates of tables/vehicles/README.md, from the file's stiffnesses.
#[test]
fn the_documented_natural_frequencies_follow_from_the_file() {
    let v = vehicle("ml95_like_bogie.toml");
    let hz = |k: f64, m: f64| (k / m).sqrt() / (2.0 * PI);
    let sum = |body_a: &str, axis: usize| {
        v.elements
            .iter()
            .filter(|e| e.body_a == body_a)
            .map(|e| e.stiffness_n_m[axis])
            .sum::<f64>()
    };
    let (kp_z, ks_z, ks_y) = (sum("frame", 2), sum("car", 2), sum("car", 1));
    assert_eq!((kp_z, ks_z, ks_y), (4.8e6, 0.8e6, 0.4e6));
    let frame = &v.bodies[0];
    // Frame bounce on the primary alone, and with the air springs (the car
    // share being fixed to the track in this model).
    assert!(close(hz(kp_z, frame.mass_kg), 5.81, 0.005));
    #[allow(clippy::approx_constant)] // 6.28 Hz, the tables/vehicles/README.md figure, not τ
    let with_air_springs = 6.28;
    assert!(close(
        hz(kp_z + ks_z, frame.mass_kg),
        with_air_springs,
        0.005
    ));
    // Frame pitch on the primary: 4 k_z (wheelbase/2)^2.
    let pitch = 4.0 * 1.2e6 * (WHEELBASE_M / 2.0).powi(2);
    assert!(close(hz(pitch, frame.inertia_kg_m2[1]), 8.44, 0.005));
    // Car share on the air springs (primary rigid), and in series with it.
    assert!(close(hz(ks_z, CAR_SHARE_KG), 1.21, 0.005));
    let series = ks_z * kp_z / (ks_z + kp_z);
    assert!(close(hz(series, CAR_SHARE_KG), 1.12, 0.005));
    assert!(close(hz(ks_y, CAR_SHARE_KG), 0.86, 0.005));
    // Static deflection of a primary spring (mm).
    assert!(close(PRIMARY_PRELOAD_N / 1.2e6 * 1e3, 35.6, 0.05));
    // Wheelset yaw stiffness 2 k_x b^2 with the axle boxes at ±1.0 m.
    let front_left = &v.elements[0];
    assert_eq!(front_left.points().unwrap().0, [1.05, 1.0, 0.43]);
    assert_eq!(2.0 * front_left.stiffness_n_m[0] * 1.0_f64.powi(2), 20.0e6);
}
