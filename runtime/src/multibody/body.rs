//! 6-DOF rigid bodies: state layout, Newton–Euler equations, energies
//! (docs/reference/08-multibody.md §8).
//!
//! # Frames and state (docs/reference/01-units-frames.md §1: global Z up, gravity −Z)
//!
//! A body's state is the position r of its centre of gravity (CG) in the
//! global frame, the unit quaternion q rotating **body axes into global
//! axes** (a body vector u has global components R(q) u), the CG velocity v
//! (global) and the angular velocity ω **in body axes**. In an integrator's
//! flat state vector a body occupies [`BodyState::LEN`] = 13 numbers:
//!
//! ```text
//! [ r_x r_y r_z | q_w q_i q_j q_k | v_x v_y v_z | ω_x ω_y ω_z ]
//!   0   1   2     3   4   5   6     7   8   9     10  11  12
//! ```
//!
//! # Equations of motion (Newton–Euler)
//!
//! With F the applied force and M the applied moment about the CG, both
//! global ([`Wrench`]), J the inertia tensor about the CG in body axes, m the
//! mass and g the gravity vector:
//!
//! ```text
//! ṙ = v
//! q̇ = ½ q ⊗ (0, ω)                       (quaternion kinematics, ω in body axes)
//! m v̇ = F + m g
//! J ω̇ = Rᵀ M − ω × (J ω)                  (Euler's equations in body axes)
//! ```
//!
//! Sources: Nikravesh, *Computer-Aided Analysis of Mechanical Systems*
//! (Prentice Hall, 1988), the Euler-parameter kinematics ω′ = 2 L(p) ṗ, i.e.
//! ṗ = ½ L(p)ᵀ ω′ for ω′ in body axes (the product ½ q ⊗ (0, ω′)), and the
//! Newton–Euler equations of a spatial body, J′ ω̇′ = n′ − ω̃′ J′ ω′;
//! Shabana, *Dynamics of Multibody Systems* (3rd ed., Cambridge, 2005),
//! chs. 2–3 (rigid-body kinematics, Newton–Euler equations); Goldstein,
//! *Classical Mechanics* (3rd ed.), §5.5 (Euler's equations).
//!
//! # Quaternion normalisation (no Baumgarte stabilisation)
//!
//! No constraint-stabilisation term (Baumgarte's −α(|q|² − 1) q) is added to
//! q̇. Instead [`BodyState::read_from`] **normalises** the stored quaternion:
//! the stages of a Runge–Kutta step, y + h Σ aᵢⱼ kⱼ, are not on the unit
//! sphere (each kⱼ is tangent to the sphere at a different point, so
//! |q| = 1 + O(h²) at a stage), and an unnormalised q would not be a rotation
//! (R(q) would scale lengths by |q|²). With normalisation on read the right
//! hand side is the smooth field ½ (q/|q|) ⊗ (0, ω), whose exact solutions
//! from a unit q stay unit; a Runge–Kutta method keeps its order on it, and
//! the stored |q| drifts only by the truncation error. The caller may write
//! the normalised state back after an accepted step ([`BodyState::read_from`]
//! then [`BodyState::write_to`]) so that drift does not accumulate; the
//! physics never sees it either way, because every use of q goes through the
//! normalised value.

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// Relative tolerance of the inertia checks in [`RigidBody::validate`]
/// (symmetry, triangle inequalities), relative to the largest entry or the
/// sum of principal moments. A thin plate meets I₃ = I₁ + I₂ exactly in
/// theory and to rounding in practice, so equality must pass.
pub const INERTIA_REL_TOL: f64 = 1e-9;

/// Why a [`RigidBody`] is not physical.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum BodyError {
    /// Mass not finite or not > 0.
    #[error("mass {mass_kg} kg must be finite and > 0")]
    InvalidMass { mass_kg: f64 },
    /// An inertia entry is NaN or infinite.
    #[error("inertia entry ({row}, {col}) = {value_kg_m2} kg·m² must be finite")]
    NonFiniteInertia {
        row: usize,
        col: usize,
        value_kg_m2: f64,
    },
    /// J is not symmetric (J_rc ≠ J_cr beyond [`INERTIA_REL_TOL`]).
    #[error(
        "inertia must be symmetric: J({row},{col}) = {upper_kg_m2} kg·m² but J({col},{row}) = {lower_kg_m2} kg·m²"
    )]
    AsymmetricInertia {
        row: usize,
        col: usize,
        upper_kg_m2: f64,
        lower_kg_m2: f64,
    },
    /// A principal moment is ≤ 0 (J not positive definite).
    #[error(
        "inertia must be positive definite: principal moments {principal_kg_m2:?} kg·m² (smallest must be > 0)"
    )]
    NotPositiveDefinite { principal_kg_m2: [f64; 3] },
    /// A principal moment exceeds the sum of the other two (no mass
    /// distribution has such an inertia).
    #[error(
        "inertia violates the triangle inequality: principal moments {principal_kg_m2:?} kg·m², each must be <= the sum of the other two"
    )]
    TriangleInequality { principal_kg_m2: [f64; 3] },
    /// A wheelset's inertia is not that of a body of revolution about its
    /// axle (`axle_frame::check_axisymmetric`).
    #[error(
        "a wheelset is a body of revolution about its axle (body y): its roll inertia {roll_kg_m2} kg·m² must equal its yaw inertia {yaw_kg_m2} kg·m² and its products of inertia be 0 (largest {largest_product_kg_m2} kg·m²)"
    )]
    NotAxisymmetric {
        roll_kg_m2: f64,
        yaw_kg_m2: f64,
        largest_product_kg_m2: f64,
    },
}

/// Mass properties of a rigid body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidBody {
    /// Mass (kg).
    pub mass_kg: f64,
    /// Inertia tensor about the centre of gravity, in body axes (kg·m²).
    pub inertia_kg_m2: Matrix3<f64>,
}

impl RigidBody {
    /// Checks, in this order: mass finite and > 0; inertia entries finite;
    /// inertia symmetric; positive definite; triangle inequalities of the
    /// principal moments (Iᵢ ≤ Iⱼ + Iₖ). The last two allow
    /// [`INERTIA_REL_TOL`] of rounding.
    pub fn validate(&self) -> Result<(), BodyError> {
        if !(self.mass_kg.is_finite() && self.mass_kg > 0.0) {
            return Err(BodyError::InvalidMass {
                mass_kg: self.mass_kg,
            });
        }
        let j = &self.inertia_kg_m2;
        for row in 0..3 {
            for col in 0..3 {
                if !j[(row, col)].is_finite() {
                    return Err(BodyError::NonFiniteInertia {
                        row,
                        col,
                        value_kg_m2: j[(row, col)],
                    });
                }
            }
        }
        let scale = j.amax();
        for (row, col) in [(0, 1), (0, 2), (1, 2)] {
            if (j[(row, col)] - j[(col, row)]).abs() > INERTIA_REL_TOL * scale {
                return Err(BodyError::AsymmetricInertia {
                    row,
                    col,
                    upper_kg_m2: j[(row, col)],
                    lower_kg_m2: j[(col, row)],
                });
            }
        }
        let e = j.symmetric_eigenvalues();
        let principal_kg_m2 = [e[0], e[1], e[2]];
        if principal_kg_m2.iter().any(|&p| p <= 0.0) {
            return Err(BodyError::NotPositiveDefinite { principal_kg_m2 });
        }
        let sum: f64 = principal_kg_m2.iter().sum();
        if principal_kg_m2
            .iter()
            .any(|&p| p > sum - p + INERTIA_REL_TOL * sum)
        {
            return Err(BodyError::TriangleInequality { principal_kg_m2 });
        }
        Ok(())
    }
}

/// Kinematic state of one rigid body (see the module docs for the frames).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Centre-of-gravity position, global (m).
    pub position_m: Vector3<f64>,
    /// Rotation body → global.
    pub orientation: UnitQuaternion<f64>,
    /// Centre-of-gravity velocity, global (m/s).
    pub velocity_m_s: Vector3<f64>,
    /// Angular velocity in **body** axes (rad/s).
    pub angular_velocity_rad_s: Vector3<f64>,
}

impl BodyState {
    /// Number of `f64`s a body occupies in a flat state vector.
    pub const LEN: usize = 13;

    /// Index of the velocity within a body's slot: position (3) and
    /// orientation quaternion (4) come before, velocity (3) and angular
    /// velocity (3) from here.
    pub const VELOCITY_OFFSET: usize = 7;

    /// The indices of body `k`'s state in a flat state vector holding the
    /// states of several bodies one after another ([`Self::LEN`] each).
    pub fn slot(k: usize) -> std::ops::Range<usize> {
        Self::LEN * k..Self::LEN * (k + 1)
    }

    /// A body at rest at `position_m` with `orientation`.
    pub fn at_rest(position_m: Vector3<f64>, orientation: UnitQuaternion<f64>) -> Self {
        Self {
            position_m,
            orientation,
            velocity_m_s: Vector3::zeros(),
            angular_velocity_rad_s: Vector3::zeros(),
        }
    }

    /// Writes the state into `y[..Self::LEN]` in the layout of the module docs
    /// (quaternion as [w, i, j, k]).
    ///
    /// # Panics
    /// If `y.len() < Self::LEN` (a programming error in the caller's layout).
    pub fn write_to(&self, y: &mut [f64]) {
        let y = &mut y[..Self::LEN];
        y[0..3].copy_from_slice(self.position_m.as_slice());
        let q = self.orientation.quaternion();
        y[3..7].copy_from_slice(&[q.w, q.i, q.j, q.k]);
        y[7..10].copy_from_slice(self.velocity_m_s.as_slice());
        y[10..Self::LEN].copy_from_slice(self.angular_velocity_rad_s.as_slice());
    }

    /// Reads a state from `y[..Self::LEN]`, **normalising the quaternion**: a
    /// Runge–Kutta stage value (and, slowly, the stored state) drifts off the
    /// unit sphere, and only the normalised quaternion is a rotation (see the
    /// module docs). A zero quaternion gives NaN components.
    ///
    /// # Panics
    /// If `y.len() < Self::LEN`.
    pub fn read_from(y: &[f64]) -> BodyState {
        let y = &y[..Self::LEN];
        BodyState {
            position_m: Vector3::new(y[0], y[1], y[2]),
            orientation: UnitQuaternion::from_quaternion(Quaternion::new(y[3], y[4], y[5], y[6])),
            velocity_m_s: Vector3::new(y[7], y[8], y[9]),
            angular_velocity_rad_s: Vector3::new(y[10], y[11], y[12]),
        }
    }

    /// Rotation matrix body → global.
    pub fn rotation(&self) -> Matrix3<f64> {
        self.orientation.to_rotation_matrix().into_inner()
    }

    /// Global position (m) of a point given in body axes from the CG (m):
    /// r + R p.
    pub fn point_position(&self, body_point_m: &Vector3<f64>) -> Vector3<f64> {
        self.position_m + self.orientation * body_point_m
    }

    /// Global velocity (m/s) of a body point given in body axes from the CG
    /// (m): v + R (ω × p).
    pub fn point_velocity(&self, body_point_m: &Vector3<f64>) -> Vector3<f64> {
        self.velocity_m_s + self.orientation * self.angular_velocity_rad_s.cross(body_point_m)
    }

    /// Angular velocity in global axes (rad/s): R ω.
    pub fn angular_velocity_global(&self) -> Vector3<f64> {
        self.orientation * self.angular_velocity_rad_s
    }

    /// Kinetic energy (J): ½ m |v|² + ½ ωᵀ J ω.
    pub fn kinetic_energy_j(&self, body: &RigidBody) -> f64 {
        let w = &self.angular_velocity_rad_s;
        0.5 * body.mass_kg * self.velocity_m_s.norm_squared()
            + 0.5 * w.dot(&(body.inertia_kg_m2 * w))
    }

    /// Gravitational potential energy (J), zero at the global origin:
    /// −m g·r (= m 9.81 z for g = (0, 0, −9.81) m/s²).
    pub fn potential_energy_j(&self, body: &RigidBody, gravity_m_s2: &Vector3<f64>) -> f64 {
        -body.mass_kg * gravity_m_s2.dot(&self.position_m)
    }

    /// Angular momentum about the CG, global axes (kg·m²/s): R J ω.
    pub fn angular_momentum_global(&self, body: &RigidBody) -> Vector3<f64> {
        self.orientation * (body.inertia_kg_m2 * self.angular_velocity_rad_s)
    }

    /// Angular momentum about a fixed global point (kg·m²/s):
    /// R J ω + (r − point) × m v (for systems of several bodies).
    pub fn angular_momentum_about(&self, body: &RigidBody, point_m: &Vector3<f64>) -> Vector3<f64> {
        self.angular_momentum_global(body)
            + (self.position_m - point_m).cross(&(body.mass_kg * self.velocity_m_s))
    }
}

/// Resultant of the applied forces on one body: a force and a moment about
/// the body's CG, both in global axes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Wrench {
    /// Resultant force, global (N).
    pub force_n: Vector3<f64>,
    /// Resultant moment about the CG, global (N·m).
    pub moment_nm: Vector3<f64>,
}

impl Wrench {
    /// The zero wrench.
    pub fn zero() -> Self {
        Self::default()
    }

    /// Adds a global `force` (N) acting at the global `point` (m) of a body
    /// whose CG is at `cg` (m): the force, and the moment (point − cg) × force.
    pub fn add_force_at(&mut self, cg: &Vector3<f64>, point: &Vector3<f64>, force: &Vector3<f64>) {
        self.force_n += force;
        self.moment_nm += (point - cg).cross(force);
    }

    /// Adds a pure moment (couple), global (N·m).
    pub fn add_moment(&mut self, moment_nm: &Vector3<f64>) {
        self.moment_nm += moment_nm;
    }

    /// Adds another wrench about the same CG.
    pub fn add(&mut self, other: &Wrench) {
        self.force_n += other.force_n;
        self.moment_nm += other.moment_nm;
    }
}

/// Writes the [`BodyState::LEN`] time derivatives of `state` into
/// `out[..BodyState::LEN]` (same layout as
/// [`BodyState::write_to`]): ṙ = v, q̇ = ½ q ⊗ (0, ω), v̇ = F/m + g,
/// ω̇ = J⁻¹ (Rᵀ M − ω × J ω) (module docs; Nikravesh 1988, Shabana 2005).
///
/// `wrench` holds the applied forces **other than gravity**; gravity acts at
/// the CG as m g. The body should have passed [`RigidBody::validate`]; a
/// singular inertia gives NaN angular accelerations.
///
/// # Panics
/// If `out.len() < BodyState::LEN`.
pub fn derivatives(
    body: &RigidBody,
    state: &BodyState,
    wrench: &Wrench,
    gravity_m_s2: &Vector3<f64>,
    out: &mut [f64],
) {
    let out = &mut out[..BodyState::LEN];
    let w = &state.angular_velocity_rad_s;
    let q_dot = quaternion_rate(state, w);
    let accel = wrench.force_n / body.mass_kg + gravity_m_s2;
    let moment_body = state
        .orientation
        .inverse_transform_vector(&wrench.moment_nm);
    let j = &body.inertia_kg_m2;
    let rhs = moment_body - w.cross(&(j * w));
    let alpha = match j.try_inverse() {
        Some(j_inv) => j_inv * rhs,
        None => Vector3::repeat(f64::NAN),
    };
    out[0..3].copy_from_slice(state.velocity_m_s.as_slice());
    out[3..7].copy_from_slice(&q_dot);
    out[7..10].copy_from_slice(accel.as_slice());
    out[10..BodyState::LEN].copy_from_slice(alpha.as_slice());
}

/// q̇ = ½ q ⊗ (0, ω) of the state's orientation for an angular velocity
/// `w` in its axes (rad/s), as [q̇_w, q̇_i, q̇_j, q̇_k]: scalar −½ q_v·ω,
/// vector ½ (q_w ω + q_v × ω) (module docs).
pub fn quaternion_rate(state: &BodyState, w: &Vector3<f64>) -> [f64; 4] {
    let q = state.orientation.quaternion();
    let qv = q.imag();
    let q_dot_w = -0.5 * qv.dot(w);
    let q_dot_v = 0.5 * (q.w * w + qv.cross(w));
    [q_dot_w, q_dot_v.x, q_dot_v.y, q_dot_v.z]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn body() -> RigidBody {
        RigidBody {
            mass_kg: 2.0,
            inertia_kg_m2: Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0)),
        }
    }

    #[test]
    fn validate_names_the_rule() {
        assert_eq!(body().validate(), Ok(()));
        let mut b = body();
        b.mass_kg = 0.0;
        assert!(matches!(b.validate(), Err(BodyError::InvalidMass { .. })));
        b = body();
        b.inertia_kg_m2[(2, 2)] = f64::NAN;
        assert!(matches!(
            b.validate(),
            Err(BodyError::NonFiniteInertia { row: 2, col: 2, .. })
        ));
        b = body();
        b.inertia_kg_m2[(0, 2)] = 0.1;
        assert!(matches!(
            b.validate(),
            Err(BodyError::AsymmetricInertia { row: 0, col: 2, .. })
        ));
        b = body();
        b.inertia_kg_m2[(1, 1)] = -2.0;
        assert!(matches!(
            b.validate(),
            Err(BodyError::NotPositiveDefinite { .. })
        ));
        b = body();
        b.inertia_kg_m2[(2, 2)] = 3.1; // > 1 + 2
        assert!(matches!(
            b.validate(),
            Err(BodyError::TriangleInequality { .. })
        ));
        // A thin plate (I3 = I1 + I2 exactly) is physical.
        b = body();
        b.inertia_kg_m2[(2, 2)] = 3.0;
        assert_eq!(b.validate(), Ok(()));
        // A rotated, full (non-diagonal) symmetric inertia passes.
        let r = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.2, 0.5))
            .to_rotation_matrix()
            .into_inner();
        b.inertia_kg_m2 = r * body().inertia_kg_m2 * r.transpose();
        assert_eq!(b.validate(), Ok(()));
    }

    #[test]
    fn state_round_trip_and_normalisation() {
        let s = BodyState {
            position_m: Vector3::new(1.0, 2.0, 3.0),
            orientation: UnitQuaternion::from_scaled_axis(Vector3::new(0.1, 0.2, 0.3)),
            velocity_m_s: Vector3::new(4.0, 5.0, 6.0),
            angular_velocity_rad_s: Vector3::new(7.0, 8.0, 9.0),
        };
        let mut y = [0.0; 15];
        s.write_to(&mut y[2..]);
        assert_eq!(BodyState::read_from(&y[2..]), s);
        // Scale the stored quaternion: the read state is the same rotation.
        for v in &mut y[5..9] {
            *v *= 1.3;
        }
        let r = BodyState::read_from(&y[2..]);
        assert!((r.orientation.quaternion().norm() - 1.0).abs() < 1e-15);
        assert!(r.orientation.angle_to(&s.orientation) < 1e-15);
    }

    #[test]
    fn point_kinematics() {
        let s = BodyState {
            position_m: Vector3::new(1.0, 0.0, 0.0),
            orientation: UnitQuaternion::from_scaled_axis(
                Vector3::z() * std::f64::consts::FRAC_PI_2,
            ),
            velocity_m_s: Vector3::new(0.0, 0.0, 1.0),
            angular_velocity_rad_s: Vector3::new(0.0, 0.0, 2.0),
        };
        let p = Vector3::new(1.0, 0.0, 0.0); // body x → global y after 90° yaw
        assert!((s.point_position(&p) - Vector3::new(1.0, 1.0, 0.0)).norm() < 1e-15);
        // ω × p = (0, 2, 0) in body axes → (−2, 0, 0) global.
        assert!((s.point_velocity(&p) - Vector3::new(-2.0, 0.0, 1.0)).norm() < 1e-15);
        assert!((s.angular_velocity_global() - Vector3::new(0.0, 0.0, 2.0)).norm() < 1e-15);
    }

    /// q̇ from `derivatives` equals d/dt [q ⊗ exp(½ ω t)] at t = 0 (central
    /// difference, step 1e-5 s: truncation ~1e-11).
    #[test]
    fn quaternion_rate_matches_exponential() {
        let b = RigidBody {
            mass_kg: 1.0,
            inertia_kg_m2: Matrix3::identity(),
        };
        let q0 = UnitQuaternion::from_scaled_axis(Vector3::new(0.4, -0.7, 1.1));
        let w = Vector3::new(0.9, -1.3, 2.2);
        let s = BodyState {
            angular_velocity_rad_s: w,
            ..BodyState::at_rest(Vector3::zeros(), q0)
        };
        let mut d = [0.0; BodyState::LEN];
        derivatives(&b, &s, &Wrench::zero(), &Vector3::zeros(), &mut d);
        let h = 1e-5;
        let at = |t: f64| (q0 * UnitQuaternion::from_scaled_axis(w * t)).into_inner();
        let fd = (at(h) - at(-h)) / (2.0 * h);
        let ours = Quaternion::new(d[3], d[4], d[5], d[6]);
        let err = (ours - fd).norm();
        assert!(err < 1e-9, "q̇ error {err:e}");
    }

    /// A force off the CG gives v̇ = F/m + g and ω̇ = J⁻¹ Rᵀ ((p − r) × F) for
    /// a body at rest (exact to rounding, 1e-14).
    #[test]
    fn off_cg_force_moment() {
        let b = body();
        let q =
            UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
        let s = BodyState::at_rest(Vector3::new(1.0, 2.0, 3.0), q);
        let mut wr = Wrench::zero();
        // Force +Z at a point 0.5 m along global +X from the CG: moment −0.5·F about Y.
        let f = Vector3::new(0.0, 0.0, 10.0);
        wr.add_force_at(
            &s.position_m,
            &(s.position_m + Vector3::new(0.5, 0.0, 0.0)),
            &f,
        );
        assert!((wr.moment_nm - Vector3::new(0.0, -5.0, 0.0)).norm() < 1e-14);
        let g = Vector3::new(0.0, 0.0, -9.81);
        let mut d = [0.0; BodyState::LEN];
        derivatives(&b, &s, &wr, &g, &mut d);
        assert!((d[9] - (10.0 / 2.0 - 9.81)).abs() < 1e-14);
        // After a 90° yaw body x is global y, so the global moment −5 ŷ is
        // −5 about body x: ω̇ = (−5/1, 0, 0) rad/s².
        let alpha = Vector3::new(d[10], d[11], d[12]);
        assert!(
            (alpha - Vector3::new(-5.0, 0.0, 0.0)).norm() < 1e-14,
            "{alpha}"
        );
    }

    #[test]
    fn energies_and_momentum() {
        let b = body();
        let s = BodyState {
            position_m: Vector3::new(0.0, 0.0, 2.0),
            orientation: UnitQuaternion::identity(),
            velocity_m_s: Vector3::new(3.0, 0.0, 0.0),
            angular_velocity_rad_s: Vector3::new(1.0, 1.0, 1.0),
        };
        assert!((s.kinetic_energy_j(&b) - (9.0 + 0.5 * 6.0)).abs() < 1e-14);
        let g = Vector3::new(0.0, 0.0, -9.81);
        assert!((s.potential_energy_j(&b, &g) - 2.0 * 9.81 * 2.0).abs() < 1e-13);
        assert_eq!(s.angular_momentum_global(&b), Vector3::new(1.0, 2.0, 3.0));
        // About the origin: + r × m v = (0,0,2) × (6,0,0) = (0, 12, 0).
        assert_eq!(
            s.angular_momentum_about(&b, &Vector3::zeros()),
            Vector3::new(1.0, 14.0, 3.0)
        );
    }
}
