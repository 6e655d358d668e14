//! The shipped vehicles of `runtime::fixtures::vehicles` (used by the
//! right-hand-side benches, benches/rhs.rs): every value checked against its
//! vehicle file in tables/vehicles/, and each model assembled on its
//! straight track in static balance with a finite right-hand side.

use runtime::fixtures::vehicles::ShippedVehicle;
use runtime::integrators::OdeSystem;
use runtime::multibody::body::BodyState;
use runtime::multibody::{End, InitialConditions, VehicleModel, VehicleSystem};
use toml::{Table, Value};

fn numbers(v: Option<&Value>, what: &str) -> Vec<f64> {
    match v {
        None => vec![0.0; 3],
        Some(Value::Array(a)) => a
            .iter()
            .map(|x| {
                x.as_float()
                    .or_else(|| x.as_integer().map(|i| i as f64))
                    .unwrap_or_else(|| panic!("{what}: not a number"))
            })
            .collect(),
        Some(other) => panic!("{what}: not an array: {other}"),
    }
}

fn number(t: &Table, key: &str) -> f64 {
    let v = &t[key];
    v.as_float()
        .or_else(|| v.as_integer().map(|i| i as f64))
        .unwrap_or_else(|| panic!("{key}: not a number"))
}

fn list<'a>(file: &'a Table, key: &str) -> Vec<&'a Table> {
    file.get(key)
        .and_then(Value::as_array)
        .map(|a| a.iter().map(|v| v.as_table().expect("a table")).collect())
        .unwrap_or_default()
}

fn diagonal(m: &nalgebra::Matrix3<f64>) -> Vec<f64> {
    vec![m[(0, 0)], m[(1, 1)], m[(2, 2)]]
}

fn check_against_file(which: ShippedVehicle, v: &VehicleModel) {
    let text = std::fs::read_to_string(which.file()).expect("the vehicle file");
    let file: Table = toml::from_str(&text).expect("TOML");
    assert_eq!(v.name, file["name"].as_str().unwrap());
    let wheelsets = list(&file, "wheelsets");
    assert_eq!(v.wheelsets.len(), wheelsets.len());
    for (w, f) in v.wheelsets.iter().zip(&wheelsets) {
        assert_eq!(w.name, f["name"].as_str().unwrap());
        assert_eq!(w.x_m, number(f, "x_m"), "{}", w.name);
        assert_eq!(w.body.mass_kg, number(f, "mass_kg"), "{}", w.name);
        assert_eq!(
            diagonal(&w.body.inertia_kg_m2),
            numbers(f.get("inertia_kg_m2"), &w.name)
        );
        assert_eq!(w.nominal_radius_m, number(f, "nominal_radius_m"));
        assert_eq!(w.y_m, 0.0);
    }
    let bodies = list(&file, "bodies");
    assert_eq!(v.bodies.len(), bodies.len());
    for (b, f) in v.bodies.iter().zip(&bodies) {
        assert_eq!(b.name, f["name"].as_str().unwrap());
        assert_eq!(b.body.mass_kg, number(f, "mass_kg"), "{}", b.name);
        assert_eq!(
            diagonal(&b.body.inertia_kg_m2),
            numbers(f.get("inertia_kg_m2"), &b.name)
        );
        assert_eq!(b.cg_m.as_slice(), numbers(f.get("cg_m"), &b.name));
    }
    let references = list(&file, "references");
    assert_eq!(v.references.len(), references.len());
    for (r, f) in v.references.iter().zip(&references) {
        assert_eq!(r.name, f["name"].as_str().unwrap());
        assert_eq!(r.origin_m.as_slice(), numbers(f.get("origin_m"), &r.name));
    }
    let end = |name: &str| -> End {
        let by_name = |t: &[&Table]| t.iter().position(|x| x["name"].as_str() == Some(name));
        by_name(&wheelsets)
            .map(End::Wheelset)
            .or_else(|| by_name(&bodies).map(End::Body))
            .or_else(|| by_name(&references).map(End::Reference))
            .unwrap_or_else(|| panic!("no body '{name}'"))
    };
    let elements = list(&file, "elements");
    assert_eq!(v.elements.len(), elements.len());
    for (e, f) in v.elements.iter().zip(&elements) {
        let n = &e.name;
        assert_eq!(n, f["name"].as_str().unwrap());
        assert_eq!(e.a, end(f["body_a"].as_str().unwrap()), "{n}");
        assert_eq!(e.b, end(f["body_b"].as_str().unwrap()), "{n}");
        let (pa, pb) = match f.get("point_m") {
            Some(p) => (Some(p), Some(p)),
            None => (f.get("point_a_m"), f.get("point_b_m")),
        };
        assert_eq!(e.point_a_m.as_slice(), numbers(pa, n), "{n}");
        assert_eq!(e.point_b_m.as_slice(), numbers(pb, n), "{n}");
        assert_eq!(e.stiffness_n_m.to_vec(), numbers(f.get("stiffness_n_m"), n));
        assert_eq!(e.damping_n_s_m.to_vec(), numbers(f.get("damping_n_s_m"), n));
        assert_eq!(
            e.preload_n.as_slice(),
            numbers(f.get("preload_n"), n),
            "{n}"
        );
        assert_eq!(e.internal_len(), 0, "{n}: linear in the file");
    }
}

#[test]
fn fixtures_match_the_shipped_vehicle_files() {
    for which in ShippedVehicle::ALL {
        let (vehicle, _) = which.build().expect("the shipped profiles");
        check_against_file(which, &vehicle);
    }
}

/// Centred at its assembly position, each vehicle is in static balance: the
/// preloads are the files' static balance (their header comments) and the
/// wheelsets are settled under their static wheel load Q. What remains is
/// on the wheelsets: the settle balances the normal forces alone, and the
/// creep forces of the rolling wheels (spin creepage on the coned treads)
/// add a vertical component — measured 0.19 % of the axle load 2Q on the
/// ML95-like wheelset and bogie (0.019 and 0.137 m/s²), 0.05 % on the car.
/// Bounds: |m a_z| ≤ 0.5 % of 2Q on a wheelset, |a_z| ≤ 1e-6 m/s² on a
/// suspended body (exact preloads; round-off only). A wrong preload or
/// wheel load (one axle box's 42.8 kN on a 1430 kg wheelset) gives tens of
/// metres per second².
#[test]
fn fixtures_are_in_static_balance_with_a_finite_rhs() {
    for which in ShippedVehicle::ALL {
        let (vehicle, track) = which.build().expect("the shipped profiles");
        let (mut system, y0) = VehicleSystem::assemble(
            &track,
            &vehicle,
            which.settings(20.0),
            InitialConditions::default(),
        )
        .expect("assembles");
        let mut dydt = vec![0.0; y0.len()];
        system.rhs(0.0, &y0, &mut dydt).expect("evaluates");
        assert!(dydt.iter().all(|d| d.is_finite()), "{}", which.name());
        let n_bodies = vehicle.wheelsets.len() + vehicle.bodies.len();
        for k in 0..n_bodies {
            // Slot layout: position, quaternion, velocity (7..10), ω.
            let a_z = dydt[BodyState::slot(k)][9];
            let ok = match vehicle.wheelsets.get(k) {
                Some(w) => (w.body.mass_kg * a_z).abs() <= 0.005 * 2.0 * w.static_wheel_load_n,
                None => a_z.abs() <= 1e-6,
            };
            assert!(
                ok,
                "{}: body {k} vertical acceleration {a_z} m/s²",
                which.name()
            );
        }
    }
}
