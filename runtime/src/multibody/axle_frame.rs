//! A wheelset's equations of motion in its **non-spinning axle frame**
//! (docs/reference/08-multibody.md §8.1, "Wheelsets in their axle frame").
//!
//! A wheelset is a body of revolution about its axle (body y): its inertia
//! is diag(I_r, I_y, I_r) in any frame that shares the axle. So its state
//! may be kept in a frame that follows the axle's direction but does not
//! turn about it: the quaternion q of that **axle frame** (axle = its y
//! axis), and the wheelset's total angular velocity ω expressed in the axle
//! frame's axes. The frame's own angular velocity is ω minus the spin,
//! ω_f = ω − (ω·ŷ) ŷ, and with L = I ω (I constant in the frame) the
//! Newton–Euler equations in a moving frame read (Goldstein, *Classical
//! Mechanics*, 3rd ed., §4.9 "rate of change in a rotating frame", and
//! §5.7 for the symmetric top; Ginsberg, *Advanced Engineering Dynamics*,
//! 2nd ed., §8.2, "Euler's equations in a non-body-fixed frame" for axially
//! symmetric rotors):
//!
//! ```text
//! q̇ = ½ q ⊗ (0, ω_f)
//! I ω̇ = Rᵀ M − ω_f × (I ω)
//! ```
//!
//! The motion is the same as in a frame spinning with the wheel (the
//! body-axis equations of [`super::body::derivatives`]): the axle's
//! direction, the global angular velocity R ω and the kinetic energy
//! ½ ωᵀ I ω are equal; only the spin angle, which no force depends on for a
//! body of revolution, is not carried. What changes is the state's
//! behaviour in time: in body axes the roll and yaw rates and the
//! quaternion turn with the spin (43 rad/s at 20 m/s), so an integrator
//! must resolve the wheel's revolution and the Jacobian of the stiff creep
//! modes turns with it; in the axle frame they vary as slowly as the
//! wheelset's lateral motion, which lets the stiff integrator
//! ([`crate::integrators::rosenbrock`]) take steps of milliseconds.

use nalgebra::Vector3;

use super::body::{BodyError, BodyState, INERTIA_REL_TOL, RigidBody, Wrench, quaternion_rate};

/// A wheelset's inertia must be that of a body of revolution about its
/// axle: I_xx = I_zz and no products of inertia (each within
/// [`INERTIA_REL_TOL`] of the largest entry).
pub fn check_axisymmetric(body: &RigidBody) -> Result<(), BodyError> {
    let j = &body.inertia_kg_m2;
    let scale = j.amax();
    let tol = INERTIA_REL_TOL * scale;
    let products = [j[(0, 1)], j[(0, 2)], j[(1, 2)]];
    if (j[(0, 0)] - j[(2, 2)]).abs() > tol || products.iter().any(|p| p.abs() > tol) {
        return Err(BodyError::NotAxisymmetric {
            roll_kg_m2: j[(0, 0)],
            yaw_kg_m2: j[(2, 2)],
            largest_product_kg_m2: products.iter().fold(0.0_f64, |m, p| m.max(p.abs())),
        });
    }
    Ok(())
}

/// dy/dt of a wheelset whose `state` is in its axle frame (module docs),
/// into `out` (at least [`BodyState::LEN`] long).
pub fn axle_frame_derivatives(
    body: &RigidBody,
    state: &BodyState,
    wrench: &Wrench,
    gravity_m_s2: &Vector3<f64>,
    out: &mut [f64],
) {
    let out = &mut out[..BodyState::LEN];
    let w = &state.angular_velocity_rad_s;
    let w_frame = Vector3::new(w.x, 0.0, w.z);
    let q_dot = quaternion_rate(state, &w_frame);
    let accel = wrench.force_n / body.mass_kg + gravity_m_s2;
    let moment_frame = state
        .orientation
        .inverse_transform_vector(&wrench.moment_nm);
    let j = &body.inertia_kg_m2;
    let rhs = moment_frame - w_frame.cross(&(j * w));
    // Diagonal inertia (checked by `check_axisymmetric`).
    let alpha = Vector3::new(rhs.x / j[(0, 0)], rhs.y / j[(1, 1)], rhs.z / j[(2, 2)]);
    out[0..3].copy_from_slice(state.velocity_m_s.as_slice());
    out[3..7].copy_from_slice(&q_dot);
    out[7..10].copy_from_slice(accel.as_slice());
    out[10..BodyState::LEN].copy_from_slice(alpha.as_slice());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::multibody::body::derivatives;
    use nalgebra::{Matrix3, UnitQuaternion};

    fn wheelset() -> RigidBody {
        RigidBody {
            mass_kg: 1430.0,
            inertia_kg_m2: Matrix3::from_diagonal(&Vector3::new(790.0, 82.0, 790.0)),
        }
    }

    /// RK4 over `steps` of `h` s of one formulation under a constant
    /// global moment; returns the final state.
    fn integrate(
        f: fn(&RigidBody, &BodyState, &Wrench, &Vector3<f64>, &mut [f64]),
        s0: &BodyState,
        moment_nm: Vector3<f64>,
        h: f64,
        steps: usize,
    ) -> BodyState {
        let b = wheelset();
        let mut wrench = Wrench::zero();
        wrench.add_moment(&moment_nm);
        let g = Vector3::zeros();
        let mut y = [0.0; BodyState::LEN];
        s0.write_to(&mut y);
        let rhs = |y: &[f64; BodyState::LEN]| {
            let mut d = [0.0; BodyState::LEN];
            f(&b, &BodyState::read_from(y), &wrench, &g, &mut d);
            d
        };
        for _ in 0..steps {
            let k1 = rhs(&y);
            let stage =
                |k: &[f64; BodyState::LEN], c: f64| std::array::from_fn(|i| y[i] + c * h * k[i]);
            let k2 = rhs(&stage(&k1, 0.5));
            let k3 = rhs(&stage(&k2, 0.5));
            let k4 = rhs(&stage(&k3, 1.0));
            for i in 0..BodyState::LEN {
                y[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
            }
        }
        BodyState::read_from(&y)
    }

    /// A wheelset spinning at 43 rad/s (20 m/s on 0.46 m wheels) with a
    /// yaw and roll rate and a moment about every axis: the axle-frame and
    /// the body-axis equations give the same axle direction, global
    /// angular velocity and kinetic energy after 0.5 s (to 1e-9), and the
    /// axle frame does not turn about the axle.
    #[test]
    fn the_axle_frame_moves_like_the_spinning_body() {
        let q0 = UnitQuaternion::from_scaled_axis(Vector3::new(0.01, 0.0, 0.02));
        let s0 = BodyState {
            angular_velocity_rad_s: Vector3::new(0.3, -43.0, 0.5),
            ..BodyState::at_rest(Vector3::zeros(), q0)
        };
        let m = Vector3::new(120.0, -40.0, 300.0);
        let body = integrate(derivatives, &s0, m, 1e-5, 50_000);
        let axle = integrate(axle_frame_derivatives, &s0, m, 1e-5, 50_000);
        let axis = |s: &BodyState| s.rotation().column(1).into_owned();
        assert!((axis(&body) - axis(&axle)).norm() < 1e-9);
        let w_err = (body.angular_velocity_global() - axle.angular_velocity_global()).norm();
        assert!(w_err < 1e-9, "ω error {w_err:e}");
        let b = wheelset();
        assert!((body.kinetic_energy_j(&b) - axle.kinetic_energy_j(&b)).abs() < 1e-8);
        // The spinning body turned ~21 rad about its axle; the axle frame's
        // x axis stays within the wheelset's yaw and roll (< 0.5 rad).
        let x_body = body.rotation().column(0).into_owned();
        let x_axle = axle.rotation().column(0).into_owned();
        assert!(x_axle.x > 0.85, "{x_axle}");
        assert!((x_body - x_axle).norm() > 1e-2);
    }

    #[test]
    fn a_wheelset_must_be_a_body_of_revolution() {
        assert!(check_axisymmetric(&wheelset()).is_ok());
        let mut b = wheelset();
        b.inertia_kg_m2[(2, 2)] = 800.0;
        assert!(matches!(
            check_axisymmetric(&b),
            Err(BodyError::NotAxisymmetric { .. })
        ));
        let mut b = wheelset();
        b.inertia_kg_m2[(0, 1)] = 5.0;
        b.inertia_kg_m2[(1, 0)] = 5.0;
        assert!(check_axisymmetric(&b).is_err());
    }
}
