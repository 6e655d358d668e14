//! Wheel–rail contact forces at one contact (paper §4.1 steps c–e, §4.4–4.7;
//! docs/reference/07-contact-forces.md §7): from a solved contact [`Candidate`] and the motion of the
//! wheelset to the force and moment on the wheel.
//!
//! Pipeline (each step its own module):
//!
//! 1. creepages and penetration rate from the velocities at the contact
//!    point ([`crate::forces::creepage`]);
//! 2. the Hertz ellipse shape from the principal relative curvatures
//!    A = ½(κ_w,roll + κ_r,roll), B = ½(κ_w,lat + κ_r,lat) (docs/reference/07-contact-forces.md §7.1,
//!    [`crate::forces::hertz`]) — non-Hertzian geometry (A ≤ 0 or B ≤ 0, or a
//!    curvature ratio beyond the Hertz solver's range) is an error naming
//!    the contact, never silently clamped; with
//!    [`NonHertzianPolicy::Floor`] the run goes on with the documented,
//!    flagged fallback instead ([`NonHertzianPolicy`]);
//! 3. the normal force N = K δ^1.5 [1 + 3(1 − e²)/4 · δ̇/δ̇⁽⁻⁾] with the
//!    hysteresis memory of the contact slot ([`crate::forces::normal`]), or a given
//!    N (quasi-static problems);
//! 4. the semi-axes a, b at that N, then the creep law ([`crate::forces::creep`]).
//!
//! The force on the wheel is N n_c + Fx t_c + Fy l_c (N, global), applied
//! at the wheel's contact point, plus the spin moment Mz n_c (N·m); the rail
//! receives the opposite. The track is fixed in the global frame (rail
//! velocities zero), as in every scene of docs/reference/08-multibody.md §8.

use nalgebra::Vector3;

use crate::contact::Candidate;
use crate::forces::creep::{CreepError, CreepForces, CreepInput, CreepLaw};
use crate::forces::creepage::{
    ContactFrame, CreepageError, CreepageInput, CreepageOptions, Creepages,
    material_point_velocity_m_s,
};
use crate::forces::hertz::{HertzContact, HertzError, HertzShape, Material};
use crate::forces::normal::{ContactMemory, NormalForce, NormalForceError, NormalForceModel};
use crate::geometry::profile::Zone;
use crate::geometry::track::Side;

/// Why a contact force could not be evaluated. Every variant names the
/// contact (wheel side and profile zone).
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum ContactForceError {
    #[error("{side} wheel, {zone}: {source}", zone = zone.name())]
    Hertz {
        side: Side,
        zone: Zone,
        #[source]
        source: HertzError,
    },
    #[error("{side} wheel, {zone}: {source}", zone = zone.name())]
    Normal {
        side: Side,
        zone: Zone,
        #[source]
        source: NormalForceError,
    },
    #[error("{side} wheel, {zone}: {source}", zone = zone.name())]
    Creepage {
        side: Side,
        zone: Zone,
        #[source]
        source: CreepageError,
    },
    #[error("{side} wheel, {zone}: {source}", zone = zone.name())]
    Creep {
        side: Side,
        zone: Zone,
        #[source]
        source: CreepError,
    },
    /// A setting violates its rule (checked by
    /// [`ContactForceSettings::validate`]).
    #[error("contact force setting {setting} = {value}: {rule}")]
    InvalidSetting {
        setting: &'static str,
        value: f64,
        rule: &'static str,
    },
}

/// Everything that turns contact geometry and motion into forces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactForceSettings {
    /// Elastic constants of wheel and rail (docs/reference/07-contact-forces.md §7.1; default steel).
    pub material: Material,
    /// Coefficient of friction μ (dimensionless; default 0.3, dry rail —
    /// the usual value of vehicle-dynamics studies).
    pub friction_coefficient: f64,
    /// Creep law (default Polach 1999).
    pub creep_law: CreepLaw,
    /// Normal force with hysteresis damping.
    pub normal: NormalForceModel,
    /// Creepage regularisation at low speed.
    pub creepage: CreepageOptions,
    /// What a non-Hertzian contact does (default: stop with the error).
    pub non_hertzian: NonHertzianPolicy,
}

/// What to do where the contact geometry is outside Hertz theory
/// (`docs/reference/07-contact-forces.md` §7.1): A ≤ 0 or B ≤ 0 (a conformal or concave contact: a worn wheel's
/// hollow tread on a rail head of about the same radius, a throat around
/// the rail's gauge corner), or max(A, B)/min(A, B) beyond
/// [`crate::forces::hertz::MAX_CURVATURE_RATIO`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NonHertzianPolicy {
    /// Report the error ([`ContactForceError::Hertz`] naming the wheel and
    /// zone, with A and B): a run stops there and writes its results.
    #[default]
    Stop,
    /// Floor both relative curvatures at [`NON_HERTZIAN_FLOOR_1_M`] and go
    /// on with the ellipse, stiffness and creep coefficients of the floored
    /// geometry; the contact is flagged ([`ContactForce::hertz_fallback`])
    /// so that runs can count and report it. The floor is the one the
    /// quasi-static settling of [`crate::contact::quasi_static`] already
    /// uses for such contacts (0.05 1/m, the relative curvature 1/(2R) of a
    /// 10 m sphere on a plane). With A ≈ 1.16 1/m (a 0.43 m wheel) the
    /// ellipse is 7.6 times wider than long (2.5 cm wide, 3.3 mm long
    /// under 10 kN of steel): the order of a conformal band's width. It
    /// keeps a run going through brief conformal episodes; it is not a
    /// non-Hertzian contact theory.
    Floor,
}

/// Relative curvature floor of [`NonHertzianPolicy::Floor`] (1/m).
pub const NON_HERTZIAN_FLOOR_1_M: f64 = 0.05;

impl std::str::FromStr for NonHertzianPolicy {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "stop" => Ok(Self::Stop),
            "floor" => Ok(Self::Floor),
            other => Err(format!(
                "non-Hertzian policy '{other}' is not stop or floor"
            )),
        }
    }
}

impl Default for ContactForceSettings {
    fn default() -> Self {
        ContactForceSettings {
            material: Material::default(),
            friction_coefficient: 0.3,
            creep_law: CreepLaw::default(),
            normal: NormalForceModel::default(),
            creepage: CreepageOptions::default(),
            non_hertzian: NonHertzianPolicy::Stop,
        }
    }
}

impl ContactForceSettings {
    /// Checks every setting, naming the violated rule.
    pub fn validate(&self) -> Result<(), ContactForceError> {
        let setting = |setting, value, rule| ContactForceError::InvalidSetting {
            setting,
            value,
            rule,
        };
        if let Err(e) = self.material.validate() {
            let HertzError::InvalidMaterial { young_pa, poisson } = e else {
                return Err(setting("material", f64::NAN, "invalid"));
            };
            return Err(if young_pa.is_finite() && young_pa > 0.0 {
                setting("Poisson's ratio", poisson, "must lie in [0, 0.5]")
            } else {
                setting("Young's modulus (Pa)", young_pa, "must be finite and > 0")
            });
        }
        if !(0.0..=0.5).contains(&self.material.poisson) {
            return Err(setting(
                "Poisson's ratio",
                self.material.poisson,
                "creep laws need 0 <= nu <= 0.5 (Kalker's table)",
            ));
        }
        if !(self.friction_coefficient.is_finite() && self.friction_coefficient >= 0.0) {
            return Err(setting(
                "friction coefficient",
                self.friction_coefficient,
                "must be finite and >= 0",
            ));
        }
        self.creep_law
            .validate()
            .map_err(|e| setting("creep law", f64::NAN, creep_rule(&e)))?;
        if let Err(e) = self.normal.validate() {
            return Err(setting(
                "normal force model",
                f64::NAN,
                match e {
                    NormalForceError::InvalidRestitution { .. } => {
                        "restitution coefficient must lie in (0, 1]"
                    }
                    _ => "minimum impact velocity must be finite and > 0 m/s",
                },
            ));
        }
        if self.creepage.validate().is_err() {
            return Err(setting(
                "minimum rolling speed (m/s)",
                self.creepage.min_rolling_speed_m_s,
                "must be finite and > 0",
            ));
        }
        Ok(())
    }
}

fn creep_rule(e: &CreepError) -> &'static str {
    match e {
        CreepError::InvalidInput { rule, .. } | CreepError::InvalidParameter { rule, .. } => rule,
    }
}

/// Motion of the wheelset body (global frame, SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelsetMotion {
    /// Position of the wheelset centre (m).
    pub centre_m: Vector3<f64>,
    /// Velocity of the wheelset centre (m/s).
    pub velocity_m_s: Vector3<f64>,
    /// Angular velocity of the wheelset, spin included (rad/s).
    pub angular_velocity_rad_s: Vector3<f64>,
    /// Forward speed: centre velocity along the track tangent (m/s), the
    /// rolling speed of the creepages ([`crate::forces::creepage`]).
    pub forward_speed_m_s: f64,
}

impl WheelsetMotion {
    /// A wheelset at `centre_m` moving at `speed_m_s` along `forward`
    /// (unit), rolling without slip on wheels of radius `radius_m` about the
    /// axle `axle` (unit, pointing left): ω = (V/r₀) η, which makes the
    /// bottom point of a wheel of radius r₀ still (docs/reference/01-units-frames.md §1 frames).
    pub fn rolling(
        centre_m: Vector3<f64>,
        forward: Vector3<f64>,
        axle: Vector3<f64>,
        speed_m_s: f64,
        radius_m: f64,
    ) -> Self {
        WheelsetMotion {
            centre_m,
            velocity_m_s: forward * speed_m_s,
            angular_velocity_rad_s: axle * (speed_m_s / radius_m),
            forward_speed_m_s: speed_m_s,
        }
    }
}

/// Principal relative curvatures (A rolling, B lateral) of a contact (1/m),
/// docs/reference/07-contact-forces.md §7.1: A = ½(κ_w,roll + κ_r,roll), B = ½(κ_w,lat + κ_r,lat).
pub fn relative_curvatures_1_m(c: &Candidate) -> (f64, f64) {
    let k = &c.curvatures;
    (
        0.5 * (k.wheel_rolling_1_m + k.rail_rolling_1_m),
        0.5 * (k.wheel_lateral_1_m + k.rail_lateral_1_m),
    )
}

/// The Hertz ellipse shape of a contact (docs/reference/07-contact-forces.md §7.1); non-Hertzian geometry
/// is an error naming the contact.
pub fn hertz_shape(c: &Candidate) -> Result<HertzShape, ContactForceError> {
    let (a, b) = relative_curvatures_1_m(c);
    HertzShape::new(a, b).map_err(|source| ContactForceError::Hertz {
        side: c.side,
        zone: c.zone,
        source,
    })
}

/// Creepages of a contact for the wheelset's motion (rail fixed).
pub fn contact_creepages(
    settings: &ContactForceSettings,
    c: &Candidate,
    motion: &WheelsetMotion,
) -> Result<Creepages, ContactForceError> {
    let input = CreepageInput {
        wheel_point_velocity_m_s: material_point_velocity_m_s(
            &motion.velocity_m_s,
            &motion.angular_velocity_rad_s,
            &motion.centre_m,
            &c.wheel_point,
        ),
        rail_point_velocity_m_s: Vector3::zeros(),
        wheel_angular_velocity_rad_s: motion.angular_velocity_rad_s,
        rail_angular_velocity_rad_s: Vector3::zeros(),
        frame: ContactFrame {
            tangent: c.tangent,
            lateral: c.lateral,
            normal: c.normal,
        },
        forward_speed_m_s: motion.forward_speed_m_s,
    };
    settings
        .creepage
        .creepages(&input)
        .map_err(|source| ContactForceError::Creepage {
            side: c.side,
            zone: c.zone,
            source,
        })
}

/// The tangential problem of a contact at a known normal force: the
/// ellipse at N, and the creep forces for the creepages.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentialContact {
    /// Hertz ellipse at the normal force (semi-axes a rolling, b lateral).
    pub hertz: HertzContact,
    pub creepages: Creepages,
    /// Fx, Fy, Mz on the wheel, contact frame (N, N·m).
    pub creep: CreepForces,
}

/// Ellipse and creep forces of contact `c` carrying `normal_force_n` (N)
/// with creepages `creepages`.
pub fn tangential_forces(
    settings: &ContactForceSettings,
    c: &Candidate,
    shape: &HertzShape,
    normal_force_n: f64,
    creepages: &Creepages,
) -> Result<TangentialContact, ContactForceError> {
    let hertz =
        HertzContact::from_shape(shape, normal_force_n, &settings.material).map_err(|source| {
            ContactForceError::Hertz {
                side: c.side,
                zone: c.zone,
                source,
            }
        })?;
    let input = CreepInput {
        xi: creepages.xi,
        eta: creepages.eta,
        phi_1_m: creepages.phi_1_m,
        normal_force_n,
        a_m: hertz.a_rolling_m,
        b_m: hertz.b_lateral_m,
        friction_coefficient: settings.friction_coefficient,
        rolling_speed_m_s: creepages.effective_speed_m_s,
        shear_modulus_pa: settings.material.shear_modulus_pa(),
        poisson: settings.material.poisson,
    };
    let creep = settings
        .creep_law
        .evaluate(&input)
        .map_err(|source| ContactForceError::Creep {
            side: c.side,
            zone: c.zone,
            source,
        })?;
    Ok(TangentialContact {
        hertz,
        creepages: *creepages,
        creep,
    })
}

/// The complete force of one contact at one state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactForce {
    /// Normal force with its elastic and damping parts, and the hysteresis
    /// memory to commit when the state is accepted.
    pub normal: NormalForce,
    pub tangential: TangentialContact,
    /// Total force on the wheel, N n_c + Fx t_c + Fy l_c (N, global).
    pub force_on_wheel_n: Vector3<f64>,
    /// Spin moment on the wheel, Mz n_c (N·m, global), about the contact
    /// point.
    pub moment_on_wheel_nm: Vector3<f64>,
    /// Where the force acts: the wheel's contact point (m, global).
    pub point_m: Vector3<f64>,
    /// The geometry was non-Hertzian and the ellipse comes from the floored
    /// curvatures ([`NonHertzianPolicy::Floor`]).
    pub hertz_fallback: bool,
}

/// The Hertz shape of a contact under `policy`: the exact one, or with
/// [`NonHertzianPolicy::Floor`] the floored one where the geometry is not
/// Hertzian (the flag says which).
pub fn hertz_shape_with_policy(
    c: &Candidate,
    policy: NonHertzianPolicy,
) -> Result<(HertzShape, bool), ContactForceError> {
    match hertz_shape(c) {
        Ok(shape) => Ok((shape, false)),
        Err(ContactForceError::Hertz {
            source: HertzError::NonHertzian { .. } | HertzError::CurvatureRatioOutOfRange { .. },
            ..
        }) if policy == NonHertzianPolicy::Floor => {
            let (a, b) = relative_curvatures_1_m(c);
            let shape =
                HertzShape::new(a.max(NON_HERTZIAN_FLOOR_1_M), b.max(NON_HERTZIAN_FLOOR_1_M))
                    .map_err(|source| ContactForceError::Hertz {
                        side: c.side,
                        zone: c.zone,
                        source,
                    })?;
            Ok((shape, true))
        }
        Err(e) => Err(e),
    }
}

/// Step c–e of the paper's algorithm for one contact: creepages, normal
/// force (hysteresis, `memory` of this contact slot), ellipse, creep forces.
/// `Ok(None)` when the bodies do not touch (δ < 0).
pub fn evaluate_contact(
    settings: &ContactForceSettings,
    c: &Candidate,
    memory: &ContactMemory,
    motion: &WheelsetMotion,
) -> Result<Option<ContactForce>, ContactForceError> {
    if !c.in_contact() {
        return Ok(None);
    }
    let (shape, hertz_fallback) = hertz_shape_with_policy(c, settings.non_hertzian)?;
    let creepages = contact_creepages(settings, c, motion)?;
    let normal = settings
        .normal
        .evaluate(
            memory,
            shape.stiffness_n_m15(&settings.material),
            c.penetration_m,
            creepages.slip.penetration_rate_m_s,
        )
        .map_err(|source| ContactForceError::Normal {
            side: c.side,
            zone: c.zone,
            source,
        })?;
    let tangential = tangential_forces(settings, c, &shape, normal.force_n, &creepages)?;
    let f = &tangential.creep;
    Ok(Some(ContactForce {
        normal,
        tangential,
        force_on_wheel_n: c.normal * normal.force_n + c.tangent * f.fx_n + c.lateral * f.fy_n,
        moment_on_wheel_nm: c.normal * f.mz_nm,
        point_m: c.wheel_point,
        hertz_fallback,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{Curvatures, SolveMethod, SurfaceParams};

    /// A tread contact with the given lateral curvatures (1/m) of wheel
    /// and rail on a 0.43 m wheel.
    fn candidate(wheel_lateral_1_m: f64, rail_lateral_1_m: f64) -> Candidate {
        Candidate {
            side: Side::Right,
            zone: Zone::Tread,
            segment: 0,
            params: SurfaceParams {
                s_rail_m: 0.0,
                u_rail_m: 0.0,
                s_wheel_rad: 0.0,
                u_wheel_m: 0.0,
            },
            iterations: 1,
            cold_start: false,
            method: SolveMethod::Newton,
            penetration_m: 1e-5,
            wheel_point: Vector3::zeros(),
            rail_point: Vector3::zeros(),
            normal: Vector3::z(),
            tangent: Vector3::x(),
            lateral: Vector3::y(),
            contact_angle_rad: 0.0,
            rolling_radius_m: 0.43,
            curvatures: Curvatures {
                wheel_rolling_1_m: 1.0 / 0.43,
                wheel_lateral_1_m,
                rail_rolling_1_m: 0.0,
                rail_lateral_1_m,
            },
            wheel_profile_point_m: (0.0, 0.0),
            rail_profile_point_m: (0.0, 0.0),
        }
    }

    #[test]
    fn non_hertzian_contact_stops_or_falls_back_flagged() {
        // A hollow tread of radius 290 mm on a 300 mm rail head: B < 0.
        let c = candidate(-1.0 / 0.29, 1.0 / 0.3);
        let e = hertz_shape_with_policy(&c, NonHertzianPolicy::Stop).unwrap_err();
        assert!(
            matches!(
                e,
                ContactForceError::Hertz {
                    side: Side::Right,
                    zone: Zone::Tread,
                    source: HertzError::NonHertzian { .. }
                }
            ),
            "{e}"
        );
        let (shape, flagged) = hertz_shape_with_policy(&c, NonHertzianPolicy::Floor).unwrap();
        assert!(flagged);
        assert_eq!(shape.b_curv_1_m(), NON_HERTZIAN_FLOOR_1_M);
        assert_eq!(shape.a_curv_1_m(), 0.5 / 0.43);
        // The floored ellipse under 10 kN of steel: 7.6 times wider than long.
        let (a, b) = shape.semi_axes_m(1e4, &crate::forces::hertz::Material::default());
        assert!((b / a - 7.600).abs() < 0.005, "b/a = {}", b / a);
        assert!((b - 0.01264).abs() < 1e-4, "b = {b}");
        // Hertzian geometry is never touched, whatever the policy.
        let ok = candidate(0.0, 1.0 / 0.3);
        for p in [NonHertzianPolicy::Stop, NonHertzianPolicy::Floor] {
            let (shape, flagged) = hertz_shape_with_policy(&ok, p).unwrap();
            assert!(!flagged);
            assert_eq!(shape.b_curv_1_m(), 0.5 / 0.3);
        }
        assert_eq!("Floor".parse(), Ok(NonHertzianPolicy::Floor));
        assert!("clamp".parse::<NonHertzianPolicy>().is_err());
    }
}
