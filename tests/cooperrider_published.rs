//! The Cooperrider car with DYTSI's published data
//! (`tables/vehicles/cooperrider_published.toml`, issue 15): its values are
//! DYTSI's (CooperriderOrthogonalModel::setupModel and the model block of
//! its example inputs, quoted in the file's comments and in
//! docs/guide/cooperrider-cross-code.md), the preloads carry the weights,
//! and its scene runs. A typo in a value, a point or a preload fails here.

mod common;

use common::*;
use railsim::config::statics::PreloadMode;
use railsim::config::vehicle::{ElementEntry, GRAVITY_M_S2, VehicleFile};

const VEHICLE: &str = "vehicles/cooperrider_published.toml";
const SCENE: &str = "scenes/cooperrider_published.toml";

// DYTSI's numbers (CooperriderOrthogonalModel::setupModel; XML model block).
const CAR_KG: f64 = 44_388.0;
/// DYTSI's car body as implemented: its pitch equation divides by Ix.
const CAR_INERTIA: [f64; 3] = [2.80e5, 2.80e5, 5.0e5];
const FRAME_KG: f64 = 2_918.9;
const FRAME_INERTIA: [f64; 3] = [6_780.0; 3];
const WHEELSET_KG: f64 = 1_022.0;
const WHEELSET_INERTIA: [f64; 3] = [678.0, 80.0, 678.0];
const R0_M: f64 = 0.425;
const H1_M: f64 = 0.0762;
const H2_M: f64 = 1.5584;
const U1_M: f64 = 7.5;
const U2_M: f64 = 1.074;
const K1: f64 = 1_823_000.0;
const K2: f64 = 3_646_000.0;
const K3: f64 = 3_646_000.0;
const K4: f64 = 182_300.0;
const K5: f64 = 333_300.0;
const K6: f64 = 903_350.0;
const D1: f64 = 20_000.0;
const D2: f64 = 29_200.0;
const D6: f64 = 166_669.0;

fn vehicle() -> VehicleFile {
    let path = shipped(VEHICLE);
    VehicleFile::load(&path).unwrap_or_else(|e| panic!("{}: {e:#}", path.display()))
}

fn element<'a>(v: &'a VehicleFile, name: &str) -> &'a ElementEntry {
    v.elements
        .iter()
        .find(|e| e.name == name)
        .unwrap_or_else(|| panic!("no element '{name}'"))
}

fn close3(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol)
}

#[test]
fn the_published_file_has_dytsi_masses_inertias_and_positions() {
    let v = vehicle();
    assert_eq!(v.wheelsets.len(), 4);
    assert_eq!(v.bodies.len(), 3);
    // 4 wheelsets × 2 sides × 3 primary + 2 frames × 2 sides × 3 secondary + drive.
    assert_eq!(v.elements.len(), 24 + 12 + 1);
    let xs: Vec<f64> = v.wheelsets.iter().map(|w| w.x_m).collect();
    let want = [U1_M + U2_M, U1_M - U2_M, -U1_M + U2_M, -U1_M - U2_M];
    for (x, w) in xs.iter().zip(want) {
        assert!((x - w).abs() < 1e-12, "{xs:?}");
    }
    for w in &v.wheelsets {
        assert_eq!(w.mass_kg, WHEELSET_KG);
        assert_eq!(w.inertia_kg_m2, WHEELSET_INERTIA);
        assert_eq!(w.nominal_radius_m, R0_M);
    }
    for b in &v.bodies {
        let (mass, inertia, z) = match b.name.as_str() {
            "car body" => (CAR_KG, CAR_INERTIA, R0_M + H1_M + H2_M),
            "front frame" | "rear frame" => (FRAME_KG, FRAME_INERTIA, R0_M + H1_M),
            other => panic!("unexpected body {other}"),
        };
        assert_eq!(b.mass_kg, mass, "{}", b.name);
        assert_eq!(b.inertia_kg_m2, inertia, "{}", b.name);
        assert!((b.cg_m[2] - z).abs() < 1e-12, "{}: {:?}", b.name, b.cg_m);
    }
}

#[test]
fn the_published_elements_have_dytsi_stiffness_damping_and_points() {
    let v = vehicle();
    // Primary lateral: frame at ±(a + l1), wheelset at ±a, axle height.
    let e = element(&v, "primary lateral front bogie front left");
    assert_eq!(e.stiffness_n_m, [0.0, K1, 0.0]);
    assert!(close3(e.point_a_m.unwrap(), [8.574, 1.05, 0.425], 1e-12));
    assert!(close3(e.point_b_m.unwrap(), [8.574, 0.75, 0.425], 1e-12));
    // Primary vertical: frame at its CG + v1 (1.15 m), axle height below.
    let e = element(&v, "primary vertical rear bogie front right");
    assert_eq!(e.stiffness_n_m, [0.0, 0.0, K3]);
    assert!(close3(e.point_a_m.unwrap(), [-6.426, -0.62, 1.15], 1e-12));
    assert!(close3(e.point_b_m.unwrap(), [-6.426, -0.62, 0.425], 1e-12));
    // Primary longitudinal: frame at x1 = 0.349 from its CG towards the axle.
    let e = element(&v, "primary longitudinal rear bogie rear left");
    assert_eq!(e.stiffness_n_m, [K2, 0.0, 0.0]);
    assert!(close3(e.point_a_m.unwrap(), [-7.849, 0.62, 0.425], 1e-12));
    assert!(close3(e.point_b_m.unwrap(), [-8.574, 0.62, 0.425], 1e-12));
    // Every primary damper is DYTSI's D3 = D4 = D5 = 0.
    for e in v.elements.iter().filter(|e| e.name.starts_with("primary")) {
        assert_eq!(e.damping_n_s_m, [0.0; 3], "{}", e.name);
    }
    // Secondary.
    let e = element(&v, "secondary lateral front frame right");
    assert_eq!(e.stiffness_n_m, [0.0, K4, 0.0]);
    assert_eq!(e.damping_n_s_m, [0.0, D2, 0.0]);
    assert!(close3(e.point_a_m.unwrap(), [7.5, -1.65, 1.1596], 1e-12));
    assert!(close3(e.point_b_m.unwrap(), [7.5, -1.35, 1.1596], 1e-12));
    let e = element(&v, "secondary vertical rear frame left");
    assert_eq!(e.stiffness_n_m, [0.0, 0.0, K5]);
    assert_eq!(e.damping_n_s_m, [0.0, 0.0, D1]);
    assert!(close3(e.point_a_m.unwrap(), [-7.5, 0.68, 1.75], 1e-12));
    assert!(close3(e.point_b_m.unwrap(), [-7.5, 0.68, 1.45], 1e-12));
    let e = element(&v, "secondary yaw rear frame right");
    assert_eq!(e.stiffness_n_m, [K6, 0.0, 0.0]);
    assert_eq!(e.damping_n_s_m, [D6, 0.0, 0.0]);
    assert!(close3(e.point_a_m.unwrap(), [-8.259, -1.5, 0.5012], 1e-12));
    assert!(close3(e.point_b_m.unwrap(), [-7.5, -1.5, 0.5012], 1e-12));
}

/// The hand-written preloads are DYTSI's static loads
/// (GeneralModel::setupStaticLoads: the car body's weight on the four
/// secondary vertical springs, car body and frames on the eight primary
/// ones) and they balance every body: the solve without them gives them
/// back, and the wheels carry the car's weight.
#[test]
fn the_published_preloads_carry_the_weight() {
    let v = vehicle();
    let secondary_n = CAR_KG * GRAVITY_M_S2 / 4.0;
    let primary_n = (CAR_KG + 2.0 * FRAME_KG) * GRAVITY_M_S2 / 8.0;
    for e in &v.elements {
        let want = if e.name.starts_with("secondary vertical") {
            -secondary_n
        } else if e.name.starts_with("primary vertical") {
            -primary_n
        } else {
            0.0
        };
        assert!(
            (e.preload_n[2] - want).abs() < 1e-6 && e.preload_n[0] == 0.0 && e.preload_n[1] == 0.0,
            "{}: {:?}, expected z {want}",
            e.name,
            e.preload_n
        );
    }
    // Solved preloads (no preload_n in the file) equal the written ones.
    let text = std::fs::read_to_string(shipped(VEHICLE)).unwrap();
    let stripped: String = text
        .lines()
        .filter(|l| !l.trim_start().starts_with("preload_n"))
        .collect::<Vec<_>>()
        .join("\n");
    let mut solved = VehicleFile::parse(&stripped).unwrap();
    solved.resolve().unwrap_or_else(|e| panic!("{e:#}"));
    let s = solved.statics.as_ref().unwrap();
    assert_eq!(s.mode, PreloadMode::Solve);
    for ((e, a), b) in v
        .elements
        .iter()
        .zip(v.element_preloads_n())
        .zip(&s.preloads_n)
    {
        for k in 0..3 {
            assert!(
                (a[k] - b[k]).abs() < 1e-9 * secondary_n,
                "{}: written {a:?}, solved {b:?}",
                e.name
            );
        }
    }
    for (body, f, m) in &s.residual {
        let worst = f.iter().chain(m).fold(0.0_f64, |a, x| a.max(x.abs()));
        assert!(worst < 1e-6, "{body}: {f:?} {m:?}");
    }
    // Each body is in equilibrium with the written preloads, and each wheel
    // carries an eighth of the car: (1022 g + 2 × primary) / 2.
    for b in &v.bodies {
        let f = v.static_force_on(&b.name, b.mass_kg);
        assert!(f.iter().all(|x| x.abs() < 1e-6), "{}: {f:?}", b.name);
    }
    let total_kg = CAR_KG + 2.0 * FRAME_KG + 4.0 * WHEELSET_KG;
    for w in &v.wheelsets {
        let q = v.static_wheel_load_n(w);
        assert!((q - 66_602.297_25).abs() < 1e-6, "{}: {q}", w.name);
        assert!((q - total_kg * GRAVITY_M_S2 / 8.0).abs() < 1e-6, "{q}");
    }
}

#[test]
fn the_published_scene_runs_the_published_vehicle() {
    let scene = std::fs::read_to_string(shipped(SCENE)).unwrap();
    assert!(scene.contains("file = \"../vehicles/cooperrider_published.toml\""));
    let dir = scratch("cooperrider_published_run");
    let o = run(sim()
        .arg("run")
        .arg(shipped(SCENE))
        .arg("-o")
        .arg(dir.join("run.h5"))
        .args(["--no-plots", "--quiet", "--json"])
        .args(["--set", "run.duration_s=0.5"]));
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("json");
    assert_eq!(j["contact_method"], "imported");
    assert_eq!(j["speed_m_s"], 40.0);
    let ws = j["wheelsets"].as_array().expect("wheelsets");
    assert_eq!(ws.len(), 4);
    // Started 0.1 mm to the left, far below the hunting speed: the
    // wheelsets stay within that offset.
    for w in ws {
        let peak = w["peak_lateral_mm"].as_f64().unwrap();
        assert!(peak <= 0.1 + 1e-9, "{}: {peak} mm", w["name"]);
    }
}
