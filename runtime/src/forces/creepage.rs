//! Creepages of one wheel–rail contact in its contact frame (docs/reference/07-contact-forces.md §7.3,
//! paper §4.5–4.7; Kalker's definitions).
//!
//! # Definitions
//!
//! ```text
//! ξ = (v_w − v_r)·t_c / V      longitudinal creepage (dimensionless)
//! η = (v_w − v_r)·l_c / V      lateral creepage (dimensionless)
//! φ = (ω_w − ω_r)·n_c / V      spin creepage (1/m)
//! ```
//!
//! (docs/reference/07-contact-forces.md §7.3; Kalker, *Three-dimensional elastic bodies in rolling
//! contact*, 1990: the rigid slip of the wheel over the rail divided by
//! the rolling speed.) v_w, v_r: velocities (m/s, global) of the wheel and
//! rail **material points** at the contact ([`material_point_velocity_m_s`]);
//! ω_w, ω_r: angular velocities (rad/s, global) of the wheel and rail bodies
//! (ω_r = 0 for a track fixed in the global frame); the contact frame
//! (docs/reference/01-units-frames.md §1): n_c unit normal from the rail into the wheel, t_c the rolling
//! direction (the rail tangent projected ⟂ n_c), l_c = n_c × t_c. Creepages
//! are wheel minus rail, so a creep law's forces on the wheel oppose them
//! ([`crate::forces::creep`]).
//!
//! The numerators are returned too, as [`SlipVelocities`] (m/s and rad/s):
//! laws written in slip velocity (Polach's μ(w), w = |slip|) use them, and
//! the normal component gives the penetration rate δ̇ = (v_r − v_w)·n_c of the
//! normal force ([`crate::forces::normal`]).
//!
//! # The rolling speed V: what the simulator passes
//!
//! [`CreepageInput::forward_speed_m_s`] is **the wheelset's forward speed**:
//! the velocity of the wheelset centre projected on the track tangent t(s)
//! at the wheelset (m/s, signed: negative when running backwards). This is
//! the common railway choice (the vehicle speed V of Kalker's creepages as
//! used by Shen, Hedrick & Elkins 1983, Polach 1999 and the paper's
//! eq. 23–26; Wickens, *Fundamentals of Rail Vehicle Dynamics*, 2003);
//! it is the same for every contact of a wheelset, so left and right, tread
//! and flange creepages share one scale. The alternatives (½|v_w + v_r|·t_c,
//! the wheel's peripheral speed) differ from it by the creepages themselves,
//! a second-order change.
//!
//! # V → 0: regularisation
//!
//! The division is by V_eff = max(|V|, v_min), v_min =
//! [`CreepageOptions::min_rolling_speed_m_s`] (default 0.1 m/s):
//!
//! - |V| ≥ v_min: exactly the definitions above (with |V|, see below).
//! - |V| < v_min (starting, stopping, standstill): the creepages become
//!   slip velocities over v_min, so a creep law turns into a viscous-like
//!   damper on the slip velocity (Kalker linear: F_x = −G a b c11 s_x/v_min,
//!   N·s/m), which saturates at μN for the Heuristic and Polach laws. That is
//!   the usual regularised-Coulomb treatment of friction at low speed: it
//!   keeps the equations well-posed at V = 0 (no NaN, no infinity, forces
//!   bounded by the slip velocity) instead of dividing by zero.
//! - V_eff is continuous in V (a kink at |V| = v_min), and
//!   V_eff · (ξ, η, φ) = slip velocities exactly, always: pass
//!   [`Creepages::effective_speed_m_s`] as the creep law's rolling speed
//!   (`crate::forces::creep::CreepInput::rolling_speed_m_s`) so its slip speed
//!   w = V·√(ξ² + η²) is the true one.
//!
//! **Why 0.1 m/s**: the paper is silent. It is 200–400× below the speeds of
//! the scenes (20–40 m/s), so running creepages are exact (the `max` form
//! changes nothing above v_min, unlike √(V² + v_min²)); it is below walking
//! pace, so only starting and stopping see the regularisation. Smaller is
//! not better: the standstill damping G a b c11/v_min grows as 1/v_min
//! (≈ 1e8 N·s/m at 0.1 m/s for a 50 kN wheel load, time constant m/c ≈ 10 µs
//! on a 1000 kg wheelset) and an explicit integrator must resolve it; raise
//! v_min for standstill runs if the step size suffers.
//!
//! # Running backwards (V < 0)
//!
//! We divide by |V| (V_eff > 0), so ξ and η keep the sign of the slip and
//! every creep law, being odd in the creepages, gives forces that oppose the
//! slip in either direction (dissipative). Kalker's spin–lateral coupling
//! (c23 in eq. 23, and the spin terms of Polach's law) was derived for
//! rolling along +t_c: for rolling along −t_c the exact treatment expresses
//! the creepages in the turned frame (−t_c, −l_c, n_c), i.e. uses
//! (−ξ, −η, φ) and maps the forces back, which flips the sign of the c23
//! coupling. This module does not do it (the frame is geometric, docs/reference/01-units-frames.md §1);
//! the scenes only run forwards. [`Creepages::running_backwards`] flags
//! the case.
//!
//! # Signs on a wheelset (docs/reference/01-units-frames.md §1: global Z up, track n to the left)
//!
//! For a wheelset running along +X at speed V, spin Ω about its axle (+Y
//! when rolling forwards, Ω = V/r0), lateral velocity ẏ (+ left), yaw ψ
//! (+ nose left) and yaw rate ψ̇, wheel contact at rolling radius r and
//! contact angle γ (positive towards the track centre on both sides, as
//! `contact::Candidate::contact_angle_rad`), the definitions give, to first
//! order (tested):
//!
//! | | left wheel (y = +b) | right wheel (y = −b) |
//! |---|---|---|
//! | n_c | (0, −sin γ, cos γ) | (0, +sin γ, cos γ) |
//! | ξ | (r0 − r_L)/r0 − b ψ̇/V | (r0 − r_R)/r0 + b ψ̇/V |
//! | η | ẏ/V − ψ | ẏ/V − ψ |
//! | φ | −sin γ_L / r0 + ψ̇ cos γ_L / V | +sin γ_R / r0 + ψ̇ cos γ_R / V |
//!
//! (Wickens 2003; Garg & Dukkipati, *Dynamics of Railway Vehicle
//! Systems*, 1984, in their own axes.) So at a flange contact the spin
//! is negative on the left wheel and positive on the right one; a wheel
//! rolling on a larger radius than r0 has negative ξ (it is braked
//! relative to the rail).
//!
//! # Bad input
//!
//! Non-finite vectors or speed, a frame that is not orthonormal and
//! right-handed within [`FRAME_TOLERANCE`], or invalid options return a
//! [`CreepageError`] naming the quantity; nothing panics.

use nalgebra::Vector3;

/// Tolerance of [`ContactFrame::validate`] (dimensionless): unit lengths,
/// t_c·n_c and |l_c − n_c × t_c| within 1e-6 (the contact search's frame is
/// orthonormal to round-off; 1e-6 still rejects a wrong or left-handed
/// frame).
pub const FRAME_TOLERANCE: f64 = 1e-6;

/// Why creepages could not be computed.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum CreepageError {
    /// A vector input has a NaN or infinite component.
    #[error("creepage input {quantity} = ({x}, {y}, {z}) must be finite")]
    NonFiniteVector {
        quantity: &'static str,
        x: f64,
        y: f64,
        z: f64,
    },
    /// The forward speed is NaN or infinite.
    #[error("wheelset forward speed {forward_speed_m_s} m/s must be finite")]
    NonFiniteSpeed { forward_speed_m_s: f64 },
    /// The contact frame is not orthonormal and right-handed.
    #[error(
        "contact frame is not orthonormal and right-handed (l_c = n_c × t_c): {defect} = {value} exceeds {tolerance}"
    )]
    InvalidFrame {
        defect: &'static str,
        value: f64,
        tolerance: f64,
    },
    /// A contact frame cannot be built: zero or non-finite normal, or a rail
    /// tangent (nearly) parallel to the normal.
    #[error(
        "cannot build a contact frame from normal |n| = {normal_norm} and rail tangent |t| = {tangent_norm} whose part perpendicular to the normal is {perpendicular_norm}"
    )]
    DegenerateFrame {
        normal_norm: f64,
        tangent_norm: f64,
        perpendicular_norm: f64,
    },
    /// The minimum rolling speed is not finite and > 0.
    #[error("minimum rolling speed {min_rolling_speed_m_s} m/s must be finite and > 0")]
    InvalidMinRollingSpeed { min_rolling_speed_m_s: f64 },
}

/// Contact frame at a contact point (docs/reference/01-units-frames.md §1), unit vectors in global
/// coordinates: the same vectors as `contact::Candidate::{tangent, lateral,
/// normal}`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactFrame {
    /// t_c: rolling direction, the rail tangent projected ⟂ n_c.
    pub tangent: Vector3<f64>,
    /// l_c = n_c × t_c (lateral; to the left of the rolling direction).
    pub lateral: Vector3<f64>,
    /// n_c: surface normal from the rail into the wheel.
    pub normal: Vector3<f64>,
}

impl ContactFrame {
    /// Builds the frame of docs/reference/01-units-frames.md §1 from the contact normal n (rail into
    /// wheel) and the rail tangent (direction of increasing s); neither needs
    /// to be unit: n_c = n/|n|, t_c = (t − (t·n_c) n_c)/|…|, l_c = n_c × t_c.
    pub fn from_normal_and_rail_tangent(
        normal: &Vector3<f64>,
        rail_tangent: &Vector3<f64>,
    ) -> Result<Self, CreepageError> {
        let normal_norm = normal.norm();
        let tangent_norm = rail_tangent.norm();
        let degenerate = |perpendicular_norm| CreepageError::DegenerateFrame {
            normal_norm,
            tangent_norm,
            perpendicular_norm,
        };
        if !(normal_norm.is_finite() && normal_norm > 0.0 && tangent_norm.is_finite()) {
            return Err(degenerate(f64::NAN));
        }
        let n = normal / normal_norm;
        let t_perp = rail_tangent - n * rail_tangent.dot(&n);
        let perp = t_perp.norm();
        // Reject a tangent within ~1e-6 rad of the normal (and a zero one).
        if !(perp > 1e-6 * tangent_norm && perp > 0.0) {
            return Err(degenerate(perp));
        }
        let t = t_perp / perp;
        Ok(ContactFrame {
            tangent: t,
            lateral: n.cross(&t),
            normal: n,
        })
    }

    /// Checks finiteness, unit t_c and n_c, t_c ⟂ n_c and l_c = n_c × t_c
    /// within [`FRAME_TOLERANCE`].
    pub fn validate(&self) -> Result<(), CreepageError> {
        for (quantity, v) in [
            ("frame tangent t_c", &self.tangent),
            ("frame lateral l_c", &self.lateral),
            ("frame normal n_c", &self.normal),
        ] {
            check_finite(quantity, v)?;
        }
        let checks = [
            ("| |t_c| - 1 |", (self.tangent.norm() - 1.0).abs()),
            ("| |n_c| - 1 |", (self.normal.norm() - 1.0).abs()),
            ("|t_c · n_c|", self.tangent.dot(&self.normal).abs()),
            (
                "|l_c - n_c × t_c|",
                (self.lateral - self.normal.cross(&self.tangent)).norm(),
            ),
        ];
        for (defect, value) in checks {
            if value.is_nan() || value > FRAME_TOLERANCE {
                return Err(CreepageError::InvalidFrame {
                    defect,
                    value,
                    tolerance: FRAME_TOLERANCE,
                });
            }
        }
        Ok(())
    }
}

/// Kinematic inputs of one contact (SI units, global frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CreepageInput {
    /// Velocity (m/s) of the wheel material point at the contact
    /// ([`material_point_velocity_m_s`] of the wheelset).
    pub wheel_point_velocity_m_s: Vector3<f64>,
    /// Velocity (m/s) of the rail material point at the contact (zero for a
    /// fixed track).
    pub rail_point_velocity_m_s: Vector3<f64>,
    /// Angular velocity of the wheel (wheelset) body (rad/s): spin about the
    /// axle plus yaw, roll and pitch rates.
    pub wheel_angular_velocity_rad_s: Vector3<f64>,
    /// Angular velocity of the rail (rad/s); zero for a fixed track.
    pub rail_angular_velocity_rad_s: Vector3<f64>,
    /// Contact frame (docs/reference/01-units-frames.md §1).
    pub frame: ContactFrame,
    /// The wheelset's forward speed V (m/s): the velocity of the wheelset
    /// centre projected on the track tangent t(s); negative when running
    /// backwards (module docs).
    pub forward_speed_m_s: f64,
}

/// Configuration of the creepage computation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CreepageOptions {
    /// v_min (m/s): creepages divide by max(|V|, v_min) (module docs,
    /// "V → 0"). Finite, > 0.
    pub min_rolling_speed_m_s: f64,
}

impl Default for CreepageOptions {
    /// v_min = 0.1 m/s (justified in the module docs).
    fn default() -> Self {
        CreepageOptions {
            min_rolling_speed_m_s: 0.1,
        }
    }
}

/// Slip of the wheel over the rail at the contact, wheel minus rail, in the
/// contact frame: the creepages' numerators.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipVelocities {
    /// (v_w − v_r)·t_c (m/s).
    pub longitudinal_m_s: f64,
    /// (v_w − v_r)·l_c (m/s).
    pub lateral_m_s: f64,
    /// (ω_w − ω_r)·n_c (rad/s).
    pub spin_rad_s: f64,
    /// Penetration rate δ̇ = (v_r − v_w)·n_c (m/s), > 0 approaching: the input
    /// of [`crate::forces::normal::NormalForceModel::evaluate`].
    pub penetration_rate_m_s: f64,
}

impl SlipVelocities {
    /// Tangential slip speed w = √(s_x² + s_y²) (m/s), as in Polach's μ(w).
    pub fn magnitude_m_s(&self) -> f64 {
        self.longitudinal_m_s.hypot(self.lateral_m_s)
    }
}

/// Creepages of one contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Creepages {
    /// Longitudinal creepage ξ (dimensionless), along t_c.
    pub xi: f64,
    /// Lateral creepage η (dimensionless), along l_c.
    pub eta: f64,
    /// Spin creepage φ (1/m), about n_c.
    pub phi_1_m: f64,
    /// The slip velocities (numerators).
    pub slip: SlipVelocities,
    /// V_eff = max(|V|, v_min) (m/s), the divisor; V_eff·ξ = slip exactly.
    /// Pass it as the creep law's rolling speed.
    pub effective_speed_m_s: f64,
    /// True when |V| < v_min (the creepages are slip velocities over v_min).
    pub regularised: bool,
    /// True when V < 0 (see the module docs on the spin coupling).
    pub running_backwards: bool,
}

impl CreepageOptions {
    /// Checks v_min finite and > 0.
    pub fn validate(&self) -> Result<(), CreepageError> {
        let v = self.min_rolling_speed_m_s;
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(CreepageError::InvalidMinRollingSpeed {
                min_rolling_speed_m_s: v,
            })
        }
    }

    /// Creepages and slip velocities of one contact (module docs): ξ, η =
    /// (v_w − v_r)·(t_c, l_c)/V_eff, φ = (ω_w − ω_r)·n_c/V_eff, V_eff =
    /// max(|V|, v_min) (docs/reference/07-contact-forces.md §7.3). Validates every input.
    pub fn creepages(&self, input: &CreepageInput) -> Result<Creepages, CreepageError> {
        self.validate()?;
        check_finite(
            "wheel point velocity (m/s)",
            &input.wheel_point_velocity_m_s,
        )?;
        check_finite("rail point velocity (m/s)", &input.rail_point_velocity_m_s)?;
        check_finite(
            "wheel angular velocity (rad/s)",
            &input.wheel_angular_velocity_rad_s,
        )?;
        check_finite(
            "rail angular velocity (rad/s)",
            &input.rail_angular_velocity_rad_s,
        )?;
        let speed = input.forward_speed_m_s;
        if !speed.is_finite() {
            return Err(CreepageError::NonFiniteSpeed {
                forward_speed_m_s: speed,
            });
        }
        input.frame.validate()?;
        let f = &input.frame;
        // Slip of the wheel over the rail (docs/reference/07-contact-forces.md §7.3 numerators).
        let dv = input.wheel_point_velocity_m_s - input.rail_point_velocity_m_s;
        let dw = input.wheel_angular_velocity_rad_s - input.rail_angular_velocity_rad_s;
        let slip = SlipVelocities {
            longitudinal_m_s: dv.dot(&f.tangent),
            lateral_m_s: dv.dot(&f.lateral),
            spin_rad_s: dw.dot(&f.normal),
            // δ̇ = −(v_w − v_r)·n_c (paper §4.4, see crate::forces::normal).
            penetration_rate_m_s: -dv.dot(&f.normal),
        };
        // V_eff = max(|V|, v_min) (module docs, "V → 0").
        let v_min = self.min_rolling_speed_m_s;
        let regularised = speed.abs() < v_min;
        let v_eff = if regularised { v_min } else { speed.abs() };
        Ok(Creepages {
            xi: slip.longitudinal_m_s / v_eff,
            eta: slip.lateral_m_s / v_eff,
            phi_1_m: slip.spin_rad_s / v_eff,
            slip,
            effective_speed_m_s: v_eff,
            regularised,
            running_backwards: speed < 0.0,
        })
    }
}

/// Velocity (m/s) of the material point at `point_m` (m, global) of a rigid
/// body whose reference point `centre_m` (m, global) moves at
/// `centre_velocity_m_s` (m/s) and which turns at `angular_velocity_rad_s`
/// (rad/s, global): v = v_c + ω × (r_p − r_c) (rigid-body kinematics, Euler's
/// velocity formula; e.g. Shabana, *Dynamics of Multibody Systems*). For
/// a wheelset, `centre_m` is the axle centre, ω includes the spin about the
/// axle, and `point_m` the wheel's contact point. Hot path: not validated
/// (the creepage computation checks its result).
pub fn material_point_velocity_m_s(
    centre_velocity_m_s: &Vector3<f64>,
    angular_velocity_rad_s: &Vector3<f64>,
    centre_m: &Vector3<f64>,
    point_m: &Vector3<f64>,
) -> Vector3<f64> {
    centre_velocity_m_s + angular_velocity_rad_s.cross(&(point_m - centre_m))
}

fn check_finite(quantity: &'static str, v: &Vector3<f64>) -> Result<(), CreepageError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(CreepageError::NonFiniteVector {
            quantity,
            x: v.x,
            y: v.y,
            z: v.z,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const R0_M: f64 = 0.46;
    const B_M: f64 = 0.75;
    const LEFT: f64 = 1.0;
    const RIGHT: f64 = -1.0;

    /// A wheelset running along +X (the track tangent) on a fixed track.
    #[derive(Clone, Copy)]
    struct Wheelset {
        speed_m_s: f64,
        lateral_velocity_m_s: f64,
        yaw_rad: f64,
        yaw_rate_rad_s: f64,
        spin_rad_s: f64,
    }

    impl Wheelset {
        fn rolling(speed_m_s: f64) -> Self {
            Wheelset {
                speed_m_s,
                lateral_velocity_m_s: 0.0,
                yaw_rad: 0.0,
                yaw_rate_rad_s: 0.0,
                spin_rad_s: speed_m_s / R0_M,
            }
        }

        /// Creepage input of the wheel on `side` (+1 left, −1 right), contact
        /// at rolling radius `r_m` below the axle, contact angle `gamma_rad`
        /// (positive towards the track centre).
        fn input(&self, side: f64, r_m: f64, gamma_rad: f64) -> CreepageInput {
            let centre = Vector3::new(3.0, 0.01, R0_M);
            let axle = Vector3::new(-self.yaw_rad.sin(), self.yaw_rad.cos(), 0.0);
            let point = centre + axle * (side * B_M) - Vector3::z() * r_m;
            let omega = axle * self.spin_rad_s + Vector3::z() * self.yaw_rate_rad_s;
            let v_c = Vector3::new(self.speed_m_s, self.lateral_velocity_m_s, 0.0);
            let normal = Vector3::new(0.0, -side * gamma_rad.sin(), gamma_rad.cos());
            CreepageInput {
                wheel_point_velocity_m_s: material_point_velocity_m_s(
                    &v_c, &omega, &centre, &point,
                ),
                rail_point_velocity_m_s: Vector3::zeros(),
                wheel_angular_velocity_rad_s: omega,
                rail_angular_velocity_rad_s: Vector3::zeros(),
                frame: ContactFrame::from_normal_and_rail_tangent(&normal, &Vector3::x()).unwrap(),
                forward_speed_m_s: self.speed_m_s,
            }
        }
    }

    fn creep(input: &CreepageInput) -> Creepages {
        CreepageOptions::default().creepages(input).unwrap()
    }

    #[test]
    fn frame_from_normal_and_tangent_follows_spec() {
        let f = ContactFrame::from_normal_and_rail_tangent(
            &Vector3::new(0.0, 0.0, 2.0),
            &Vector3::new(3.0, 0.0, 0.1),
        )
        .unwrap();
        assert!((f.tangent - Vector3::x()).norm() < 1e-15);
        assert!((f.normal - Vector3::z()).norm() < 1e-15);
        // l_c = n_c × t_c points left (+Y) for a wheel on top of the rail.
        assert!((f.lateral - Vector3::y()).norm() < 1e-15);
        f.validate().unwrap();
        for (n, t) in [
            (Vector3::zeros(), Vector3::x()),
            (Vector3::z(), Vector3::z() * 5.0),
            (Vector3::z(), Vector3::zeros()),
            (Vector3::new(f64::NAN, 0.0, 1.0), Vector3::x()),
        ] {
            assert!(matches!(
                ContactFrame::from_normal_and_rail_tangent(&n, &t),
                Err(CreepageError::DegenerateFrame { .. })
            ));
        }
        // Left-handed, non-unit or non-orthogonal frames are rejected.
        let bad = [
            ContactFrame {
                lateral: -f.lateral,
                ..f
            },
            ContactFrame {
                normal: f.normal * 1.01,
                ..f
            },
            ContactFrame {
                tangent: (f.tangent + f.normal * 0.01).normalize(),
                ..f
            },
        ];
        for b in bad {
            let err = b.validate().unwrap_err();
            assert!(matches!(err, CreepageError::InvalidFrame { .. }), "{err}");
        }
    }

    /// Rolling without slip: ξ = η = φ = 0 on both wheels (γ = 0), and with
    /// a contact angle only the spin −sin γ/r0 (left), +sin γ/r0 (right).
    #[test]
    fn pure_rolling_has_zero_creepage_and_spin_signs() {
        for speed in [0.5, 20.0, 83.0] {
            let ws = Wheelset::rolling(speed);
            for side in [LEFT, RIGHT] {
                let c = creep(&ws.input(side, R0_M, 0.0));
                assert!(c.xi.abs() < 1e-14 && c.eta.abs() < 1e-14 && c.phi_1_m.abs() < 1e-14);
                assert_eq!(c.effective_speed_m_s, speed);
                assert!(!c.regularised && !c.running_backwards);
                assert!(c.slip.penetration_rate_m_s.abs() < 1e-12);
                for gamma in [0.05, 0.3, 1.2] {
                    let c = creep(&ws.input(side, R0_M, gamma));
                    assert!(c.xi.abs() < 1e-14 && c.eta.abs() < 1e-14);
                    let expect = -side * f64::sin(gamma) / R0_M;
                    assert!((c.phi_1_m - expect).abs() < 1e-13, "{side} {gamma}");
                }
            }
        }
        // The flange spin is negative on the left wheel, positive on the right.
        let ws = Wheelset::rolling(30.0);
        assert!(creep(&ws.input(LEFT, R0_M, 1.2)).phi_1_m < -1.5);
        assert!(creep(&ws.input(RIGHT, R0_M, 1.2)).phi_1_m > 1.5);
    }

    /// A rolling radius r ≠ r0 at the spin Ω = V/r0: ξ = (r0 − r)/r0 exactly.
    #[test]
    fn rolling_radius_difference_gives_longitudinal_creepage() {
        let ws = Wheelset::rolling(30.0);
        for dr in [-3e-3, 1e-4, 2e-3] {
            let left = creep(&ws.input(LEFT, R0_M + dr, 0.0));
            let right = creep(&ws.input(RIGHT, R0_M - dr, 0.0));
            assert!((left.xi - (-dr / R0_M)).abs() < 1e-14);
            assert!((right.xi - dr / R0_M).abs() < 1e-14);
            assert!(left.eta.abs() < 1e-14 && right.eta.abs() < 1e-14);
        }
    }

    /// Lateral velocity ẏ and yaw ψ: η = ẏ/V − sin ψ exactly (textbook
    /// η = ẏ/V − ψ to first order) on both wheels; yaw rate ψ̇: ξ = ∓b ψ̇/V
    /// (left −, right +) and φ = ψ̇/V at γ = 0.
    #[test]
    fn lateral_velocity_yaw_and_yaw_rate() {
        let speed = 25.0;
        for (ydot, psi) in [(0.1, 0.0), (0.0, 2e-3), (-0.05, -1e-3), (0.2, 5e-3)] {
            let ws = Wheelset {
                lateral_velocity_m_s: ydot,
                yaw_rad: psi,
                ..Wheelset::rolling(speed)
            };
            for side in [LEFT, RIGHT] {
                let c = creep(&ws.input(side, R0_M, 0.0));
                let exact: f64 = ydot / speed - psi.sin();
                assert!((c.eta - exact).abs() < 1e-14, "{ydot} {psi}");
                assert!((c.eta - (ydot / speed - psi)).abs() <= psi.abs().powi(3));
                // ξ = 1 − cos ψ: second order.
                assert!((c.xi - (1.0 - psi.cos())).abs() < 1e-14);
            }
        }
        let psidot = 0.04;
        let ws = Wheelset {
            yaw_rate_rad_s: psidot,
            ..Wheelset::rolling(speed)
        };
        let left = creep(&ws.input(LEFT, R0_M, 0.0));
        let right = creep(&ws.input(RIGHT, R0_M, 0.0));
        assert!((left.xi + B_M * psidot / speed).abs() < 1e-14);
        assert!((right.xi - B_M * psidot / speed).abs() < 1e-14);
        for c in [left, right] {
            assert!((c.phi_1_m - psidot / speed).abs() < 1e-14);
        }
    }

    /// All of the above at once against the linearised textbook formulas
    /// (module docs' table), to second order in the small quantities.
    #[test]
    fn combined_matches_linearised_textbook_formulas() {
        let speed = 30.0;
        let (ydot, psi, psidot, lambda_y) = (0.03, 1.5e-3, 0.02, 4e-4);
        let ws = Wheelset {
            lateral_velocity_m_s: ydot,
            yaw_rad: psi,
            yaw_rate_rad_s: psidot,
            ..Wheelset::rolling(speed)
        };
        let gamma = 0.04;
        for side in [LEFT, RIGHT] {
            let r = R0_M + side * lambda_y;
            let c = creep(&ws.input(side, r, gamma));
            let xi = (R0_M - r) / R0_M - side * B_M * psidot / speed;
            let eta = ydot / speed - psi;
            let phi = -side * gamma.sin() / R0_M + psidot * gamma.cos() / speed;
            let second_order = 1e-5;
            assert!((c.xi - xi).abs() < second_order, "{} {xi}", c.xi);
            assert!((c.eta - eta).abs() < second_order, "{} {eta}", c.eta);
            assert!(
                (c.phi_1_m - phi).abs() < 1e-3 * phi.abs(),
                "{} {phi}",
                c.phi_1_m
            );
        }
    }

    /// V → 0 and V = 0: finite; below v_min the creepages are slip over
    /// v_min; continuous at v_min; V < 0 divides by |V|.
    #[test]
    fn low_zero_and_negative_speed() {
        let opts = CreepageOptions::default();
        let v_min = opts.min_rolling_speed_m_s;
        // A wheel at (near) standstill, sliding forwards at 0.01 m/s, sideways
        // at −0.02 m/s and spinning at 0.5 rad/s about the normal.
        let make = |speed: f64| CreepageInput {
            wheel_point_velocity_m_s: Vector3::new(0.01, -0.02, 0.0),
            rail_point_velocity_m_s: Vector3::zeros(),
            wheel_angular_velocity_rad_s: Vector3::new(0.0, 3.0, 0.5),
            rail_angular_velocity_rad_s: Vector3::zeros(),
            frame: ContactFrame::from_normal_and_rail_tangent(&Vector3::z(), &Vector3::x())
                .unwrap(),
            forward_speed_m_s: speed,
        };
        for speed in [
            0.0,
            -0.0,
            5e-324,
            1e-300,
            1e-9,
            0.05,
            -0.05,
            v_min * (1.0 - 1e-15),
        ] {
            let c = opts.creepages(&make(speed)).unwrap();
            assert!(c.regularised);
            assert_eq!(c.effective_speed_m_s, v_min);
            assert!((c.xi - 0.01 / v_min).abs() < 1e-15);
            assert!((c.eta + 0.02 / v_min).abs() < 1e-15);
            assert!((c.phi_1_m - 0.5 / v_min).abs() < 1e-14);
            assert!((c.slip.magnitude_m_s() - 0.01f64.hypot(0.02)).abs() < 1e-17);
        }
        // Continuity across v_min.
        let below = opts.creepages(&make(v_min * (1.0 - 1e-12))).unwrap();
        let above = opts.creepages(&make(v_min * (1.0 + 1e-12))).unwrap();
        assert!(!above.regularised);
        assert!((below.xi - above.xi).abs() < 1e-10 * below.xi.abs());
        // V_eff × creepage = slip, always.
        for speed in [0.0, 0.07, 2.0, -2.0, 40.0] {
            let c = opts.creepages(&make(speed)).unwrap();
            assert!((c.xi * c.effective_speed_m_s - c.slip.longitudinal_m_s).abs() < 1e-17);
            assert!((c.eta * c.effective_speed_m_s - c.slip.lateral_m_s).abs() < 1e-17);
        }
        // Running backwards: same magnitude of divisor, creepages keep the
        // sign of the slip.
        let fwd = opts.creepages(&make(20.0)).unwrap();
        let back = opts.creepages(&make(-20.0)).unwrap();
        assert!(back.running_backwards && !fwd.running_backwards);
        assert_eq!(
            (fwd.xi, fwd.eta, fwd.phi_1_m),
            (back.xi, back.eta, back.phi_1_m)
        );
        assert!(back.xi > 0.0);
        // A larger v_min gives proportionally smaller standstill creepages.
        let soft = CreepageOptions {
            min_rolling_speed_m_s: 1.0,
        };
        assert!((soft.creepages(&make(0.0)).unwrap().xi - 0.01).abs() < 1e-17);
    }

    #[test]
    fn bad_input_is_reported() {
        let good = Wheelset::rolling(20.0).input(LEFT, R0_M, 0.1);
        let opts = CreepageOptions::default();
        opts.creepages(&good).unwrap();
        let mut i = good;
        i.wheel_point_velocity_m_s.y = f64::NAN;
        let err = opts.creepages(&i).unwrap_err();
        assert!(
            matches!(err, CreepageError::NonFiniteVector { quantity, .. } if quantity.contains("wheel point"))
        );
        let mut i = good;
        i.rail_angular_velocity_rad_s.z = f64::INFINITY;
        assert!(matches!(
            opts.creepages(&i),
            Err(CreepageError::NonFiniteVector { .. })
        ));
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let i = CreepageInput {
                forward_speed_m_s: v,
                ..good
            };
            assert!(matches!(
                opts.creepages(&i),
                Err(CreepageError::NonFiniteSpeed { .. })
            ));
        }
        let i = CreepageInput {
            frame: ContactFrame {
                lateral: -good.frame.lateral,
                ..good.frame
            },
            ..good
        };
        assert!(matches!(
            opts.creepages(&i),
            Err(CreepageError::InvalidFrame { .. })
        ));
        for v in [0.0, -0.1, f64::NAN, f64::INFINITY] {
            let o = CreepageOptions {
                min_rolling_speed_m_s: v,
            };
            assert!(matches!(
                o.creepages(&good),
                Err(CreepageError::InvalidMinRollingSpeed { .. })
            ));
        }
    }

    /// The penetration rate returned here is the normal module's δ̇, and the
    /// rail's own motion is subtracted.
    #[test]
    fn penetration_rate_and_moving_rail() {
        let mut i = Wheelset::rolling(20.0).input(RIGHT, R0_M, 0.2);
        i.wheel_point_velocity_m_s += i.frame.normal * -0.03;
        let c = creep(&i);
        assert!((c.slip.penetration_rate_m_s - 0.03).abs() < 1e-14);
        let expect = crate::forces::normal::penetration_rate_m_s(
            &i.wheel_point_velocity_m_s,
            &i.rail_point_velocity_m_s,
            &i.frame.normal,
        );
        assert_eq!(c.slip.penetration_rate_m_s, expect);
        // Moving the rail (and turning it) like the wheel removes all slip.
        i.rail_point_velocity_m_s = i.wheel_point_velocity_m_s;
        i.rail_angular_velocity_rad_s = i.wheel_angular_velocity_rad_s;
        let c = creep(&i);
        assert_eq!((c.xi, c.eta, c.phi_1_m), (0.0, 0.0, 0.0));
    }

    #[test]
    fn material_point_velocity_of_a_rolling_wheel() {
        // Rolling at 10 m/s, radius 0.5 m: the bottom point is at rest, the
        // top moves at 20 m/s, the front point moves forwards-down.
        let v_c = Vector3::new(10.0, 0.0, 0.0);
        let w = Vector3::new(0.0, 20.0, 0.0);
        let c = Vector3::new(1.0, 2.0, 0.5);
        let at = |d: Vector3<f64>| material_point_velocity_m_s(&v_c, &w, &c, &(c + d));
        assert!(at(Vector3::new(0.0, 0.0, -0.5)).norm() < 1e-15);
        assert!((at(Vector3::new(0.0, 0.0, 0.5)) - Vector3::new(20.0, 0.0, 0.0)).norm() < 1e-14);
        assert!((at(Vector3::new(0.5, 0.0, 0.0)) - Vector3::new(10.0, 0.0, -10.0)).norm() < 1e-14);
    }
}
