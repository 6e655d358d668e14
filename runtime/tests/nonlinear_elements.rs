//! Nonlinear suspension elements in the dynamics (docs/reference/08-multibody.md §8.2):
//! a wheelset held sideways to a track-following reference by a linear
//! spring, a bump stop, a bilinear damper and a series spring–damper
//! (whose stroke is an internal state after the bodies'). Without creep
//! and with restitution 1 the only losses are the dampers': the energy
//! ledger's balance E − E0 = W − D must close, with D > 0 growing as the
//! sway decays.

use nalgebra::{Matrix3, Vector3};
use runtime::contact::{ContactOptions, FlangeSearch};
use runtime::fixtures::wheelsets;
use runtime::forces::creep::CreepLaw;
use runtime::forces::normal::NormalForceModel;
use runtime::integrators::{Method, OutputGrid, Rk4, integrate};
use runtime::multibody::body::{BodyState, RigidBody};
use runtime::multibody::contact_force::ContactForceSettings;
use runtime::multibody::element::{AxisLaws, DamperLaw, SeriesLaw, SpringLaw};
use runtime::multibody::{
    ElementSpec, End, InitialConditions, ReferenceSpec, SystemSettings, VehicleModel,
    VehicleSystem, WheelsetSpec,
};

fn vehicle(laws: AxisLaws) -> VehicleModel {
    let contact = wheelsets::ml95_uic60_1in20().unwrap();
    let mass = 1430.0;
    let centre = Vector3::new(0.0, 0.0, 0.43);
    VehicleModel {
        name: "held wheelset".into(),
        wheelsets: vec![WheelsetSpec {
            name: "wheelset".into(),
            body: RigidBody {
                mass_kg: mass,
                inertia_kg_m2: Matrix3::from_diagonal(&Vector3::new(790.0, 82.0, 790.0)),
            },
            contact,
            x_m: 0.0,
            y_m: 0.0,
            nominal_radius_m: 0.43,
            static_wheel_load_n: 0.5 * mass * 9.81,
        }],
        bodies: vec![],
        references: vec![ReferenceSpec {
            name: "frame".into(),
            origin_m: centre,
        }],
        elements: vec![ElementSpec {
            name: "lateral".into(),
            a: End::Reference(0),
            b: End::Wheelset(0),
            point_a_m: centre,
            point_b_m: centre,
            stiffness_n_m: [0.0, 2e5, 0.0],
            damping_n_s_m: [0.0; 3],
            preload_n: Vector3::zeros(),
            laws: [AxisLaws::default(), laws, AxisLaws::default()],
        }],
    }
}

/// Runs 0.6 s from 4 mm off centre; returns the ledger's (initial energy,
/// damper dissipation, residual) (J) and the internal states at the end.
fn run(laws: AxisLaws) -> (f64, f64, f64, Vec<f64>) {
    let v = vehicle(laws);
    let track = wheelsets::straight_track_for(&v.wheelsets[0].contact, 100.0);
    let settings = SystemSettings {
        forces: ContactForceSettings {
            creep_law: CreepLaw::None,
            normal: NormalForceModel {
                restitution: 1.0,
                ..Default::default()
            },
            ..Default::default()
        },
        contact: ContactOptions {
            flange: FlangeSearch::Auto,
            ..Default::default()
        },
        speed_m_s: 10.0,
        s_start_m: 5.0,
        ..Default::default()
    };
    let (mut system, y0) = VehicleSystem::assemble(
        &track,
        &v,
        settings,
        InitialConditions {
            lateral_m: -0.004,
            yaw_rad: 0.0,
        },
    )
    .unwrap();
    assert_eq!(y0.len(), BodyState::LEN + v.internal_state_len());
    system.enable_energy_ledger();
    integrate(
        &Method::Rk4(Rk4 { step_s: 1e-4 }),
        &mut system,
        0.0,
        &y0,
        0.6,
        &OutputGrid { interval_s: 0.01 },
        &mut |_, t, y| {
            assert!(y.iter().all(|v| v.is_finite()), "NaN at {t}");
            Ok(())
        },
    )
    .unwrap();
    let l = *system.energy_ledger().unwrap();
    (
        l.initial_energy_j,
        l.damper_dissipation_j,
        l.residual_j(),
        system.internal_states().to_vec(),
    )
}

/// Series spring–damper (τ = c/k = 10 ms), bump stop (2 mm clearance) and
/// bilinear damper together: one internal state, the balance closes to
/// 1e-3 of the dissipated energy (RK4 at 0.1 ms, trapezoidal powers).
#[test]
fn nonlinear_elements_keep_the_energy_balance() {
    let laws = AxisLaws {
        spring: Some(SpringLaw::BumpStop {
            clearance_m: 0.002,
            stiffness_n_m: 1e6,
        }),
        damper: Some(DamperLaw::Bilinear {
            damping_n_s_m: 2e4,
            blow_off_m_s: 0.01,
            damping_beyond_n_s_m: 2e3,
        }),
        series: Some(SeriesLaw {
            stiffness_n_m: 5e5,
            damping_n_s_m: 5e3,
        }),
    };
    let (e0, dissipated, residual, q) = run(laws);
    eprintln!("E0 = {e0:.3} J, dampers {dissipated:.6} J, residual {residual:.3e} J, q = {q:?}");
    assert_eq!(q.len(), 1);
    assert!(dissipated > 1.0, "{dissipated}");
    assert!(
        residual.abs() < 1e-3 * dissipated,
        "{residual} of {dissipated}"
    );
    // The stroke moved (the series damper crept).
    assert!(q[0].abs() > 1e-5, "{q:?}");
}

/// The series element alone: it dissipates, and the balance closes.
#[test]
fn series_element_alone_dissipates() {
    let laws = AxisLaws {
        series: Some(SeriesLaw {
            stiffness_n_m: 5e5,
            damping_n_s_m: 5e3,
        }),
        ..Default::default()
    };
    let (_, dissipated, residual, q) = run(laws);
    eprintln!("dampers {dissipated:.6} J, residual {residual:.3e} J, q = {q:?}");
    assert!(dissipated > 1.0, "{dissipated}");
    assert!(
        residual.abs() < 1e-3 * dissipated,
        "{residual} of {dissipated}"
    );
}

/// The linearisation does not include internal states: a vehicle with a
/// series element is refused with the rule, not linearised wrongly.
#[test]
fn linearisation_refuses_internal_states() {
    let v = vehicle(AxisLaws {
        series: Some(SeriesLaw {
            stiffness_n_m: 5e5,
            damping_n_s_m: 5e3,
        }),
        ..Default::default()
    });
    let track = wheelsets::straight_track_for(&v.wheelsets[0].contact, 100.0);
    let settings = SystemSettings {
        speed_m_s: 10.0,
        s_start_m: 5.0,
        ..Default::default()
    };
    let (mut system, y0) =
        VehicleSystem::assemble(&track, &v, settings, InitialConditions::default()).unwrap();
    let Err(e) = runtime::multibody::linear::linearise(&mut system, &y0) else {
        panic!("a vehicle with internal states was linearised");
    };
    assert!(e.to_string().contains("internal states"), "{e}");
}
