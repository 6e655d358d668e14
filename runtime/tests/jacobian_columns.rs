//! A Jacobian column of the vehicle (`OdeSystem::rhs_column`) reuses the
//! contacts of the wheelsets it does not perturb, taken from the accepted
//! state: on every shipped vehicle, off centre (3 mm, 2 mrad), each column's
//! derivative must match a full evaluation at the same state to the contact
//! solver's convergence, and exactly the unperturbed wheelsets are reused.

use runtime::fixtures::vehicles::ShippedVehicle;
use runtime::integrators::OdeSystem;
use runtime::multibody::body::BodyState;
use runtime::multibody::{InitialConditions, VehicleModel, VehicleSystem};

/// Largest |f_column − f_full| allowed, relative to 1 + |f_full| in the
/// state's units per second: the unperturbed wheelsets' contacts differ
/// only by the contact Newton's convergence (a warm start from another
/// state), far below the finite-difference increment's effect (1e-7
/// relative).
const TOLERANCE: f64 = 1e-7;

#[test]
fn columns_reuse_the_other_wheelsets_contacts_and_match_a_full_evaluation() {
    for_each_vehicle_off_centre(|which, vehicle, system, y0, _f0| {
        let n = y0.len();
        let n_ws = vehicle.wheelsets.len();
        let (mut f_col, mut f_full) = (vec![0.0; n], vec![0.0; n]);
        for j in 0..n {
            let mut y = y0.to_vec();
            y[j] += 1e-7 * y[j].abs().max(1.0);
            system
                .rhs_column(0.0, &y, &[j], &mut f_col)
                .expect("evaluates");
            let owner = (0..n_ws).find(|&i| BodyState::slot(i).contains(&j));
            let reused: Vec<bool> = (0..n_ws).map(|i| Some(i) != owner).collect();
            assert_eq!(
                system.contacts_reused(),
                reused.as_slice(),
                "{}: column {j}",
                which.name()
            );
            system.rhs(0.0, &y, &mut f_full).expect("evaluates");
            assert!(system.contacts_reused().iter().all(|r| !r));
            for (k, (c, f)) in f_col.iter().zip(&f_full).enumerate() {
                let d = (c - f).abs() / (1.0 + f.abs());
                assert!(
                    d <= TOLERANCE,
                    "{}: column {j}, row {k}: {c} against {f}",
                    which.name()
                );
            }
        }
        // Away from the accepted state (the first and the last wheelset
        // moved), nothing is reused.
        let mut y = y0.to_vec();
        y[0] += 1e-3;
        y[BodyState::slot(n_ws - 1).start + 1] += 1e-6;
        system
            .rhs_column(0.0, &y, &[0], &mut f_col)
            .expect("evaluates");
        assert!(
            system.contacts_reused().iter().all(|r| !r),
            "{}: two components changed, yet contacts were reused",
            which.name()
        );
    });
}

/// The colours the vehicle declares (`OdeSystem::jacobian_blocks`): bodies
/// whose columns are perturbed together must act on disjoint rows. On every
/// shipped vehicle, off centre: a body's single column leaves every row
/// outside its declared rows exactly unchanged (the declared sparsity is
/// the true one), and the colour's joint evaluation gives each member's
/// rows bit for bit as its single column does. The car (two bogies) has
/// colours; a bogie or a wheelset has none (no two bodies can share one).
#[test]
fn coloured_columns_match_single_columns_on_their_rows() {
    let mut coloured_vehicles = Vec::new();
    for_each_vehicle_off_centre(|which, _vehicle, system, y0, f0| {
        let n = y0.len();
        let layout = system.jacobian_blocks(n);
        layout.check(n).expect("a valid layout");
        if !layout.colors.is_empty() {
            coloured_vehicles.push(which.name());
        }
        let step = |v: f64| 1e-7 * v.abs().max(1.0);
        let (mut f_joint, mut f_single) = (vec![0.0; n], vec![0.0; n]);
        for color in &layout.colors {
            for j in 0..color.width() {
                let mut y = y0.to_vec();
                let mut changed = Vec::new();
                for m in color.members.iter().filter(|m| j < m.columns.len()) {
                    let i = m.columns.start + j;
                    y[i] += step(y[i]);
                    changed.push(i);
                }
                system
                    .rhs_column(0.0, &y, &changed, &mut f_joint)
                    .expect("evaluates");
                for m in color.members.iter().filter(|m| j < m.columns.len()) {
                    let i = m.columns.start + j;
                    let mut y1 = y0.to_vec();
                    y1[i] += step(y1[i]);
                    system
                        .rhs_column(0.0, &y1, &[i], &mut f_single)
                        .expect("evaluates");
                    for row in 0..n {
                        let declared = m.rows.iter().any(|r| r.contains(&row));
                        if declared {
                            assert_eq!(
                                f_joint[row].to_bits(),
                                f_single[row].to_bits(),
                                "{}: column {i}, row {row}",
                                which.name()
                            );
                        } else {
                            assert_eq!(
                                f_single[row].to_bits(),
                                f0[row].to_bits(),
                                "{}: column {i} changes row {row}, outside its declared rows",
                                which.name()
                            );
                        }
                    }
                }
            }
        }
    });
    assert_eq!(coloured_vehicles, ["car"]);
}

/// Every shipped vehicle assembled off centre (3 mm, 2 mrad), evaluated
/// and accepted at its initial state y0 (derivative f0):
/// `check(which, vehicle, system, y0, f0)`.
fn for_each_vehicle_off_centre(
    mut check: impl FnMut(ShippedVehicle, &VehicleModel, &mut VehicleSystem<'_>, &[f64], &[f64]),
) {
    for which in ShippedVehicle::ALL {
        let (vehicle, track) = which.build().expect("the shipped profiles");
        let (mut system, y0) = VehicleSystem::assemble(
            &track,
            &vehicle,
            which.settings(20.0),
            InitialConditions {
                lateral_m: 0.003,
                yaw_rad: 0.002,
            },
        )
        .expect("assembles");
        let mut f0 = vec![0.0; y0.len()];
        system.rhs(0.0, &y0, &mut f0).expect("evaluates");
        system.accept(0.0, &y0).expect("accepts");
        check(which, &vehicle, &mut system, &y0, &f0);
    }
}
