//! Creep force laws (paper §4.6–4.7, docs/reference/07-contact-forces.md §7.3): from the creepages of one
//! wheel–rail contact, its Hertz ellipse and normal force, the tangential
//! forces and the spin moment **on the wheel**, in the contact frame.
//!
//! # Conventions (docs/reference/01-units-frames.md §1)
//!
//! - Contact frame: `t_c` rolling direction, `l_c = n_c × t_c` lateral,
//!   `n_c` normal from rail into wheel.
//! - Creepages are wheel-minus-rail slip over the rolling speed: ξ along
//!   `t_c`, η along `l_c` (dimensionless), spin φ about `n_c` (1/m); see
//!   [`crate::forces::creepage`].
//! - Forces are on the wheel and oppose the slip: a positive ξ gives a
//!   negative Fx. Fx along `t_c`, Fy along `l_c` (N), Mz about `n_c` (N·m).
//!   Every law is odd in the creepages: (−ξ, −η, −φ) gives (−Fx, −Fy, −Mz).
//! - `a` is the semi-axis of the contact ellipse in the rolling direction,
//!   `b` the lateral one (m), as returned by [`crate::forces::hertz::HertzContact`].
//!
//! # Laws ([`CreepLaw`])
//!
//! | law | source | Fx, Fy | Mz | saturation |
//! |---|---|---|---|---|
//! | [`CreepLaw::KalkerLinear`] | Kalker, paper eq. 23 | linear | linear | none |
//! | [`CreepLaw::Heuristic`] | Shen, Hedrick & Elkins 1983, paper eq. 24–26 | cubic in the Kalker force | 0 | μN |
//! | [`CreepLaw::Polach`] | Polach 1999, 2005 | Polach | 0 | μN |
//! | [`CreepLaw::Fastsim`] | Kalker 1982 (simplified theory) | strip integration | integrated | μN (pointwise) |
//! | [`CreepLaw::Fastrip`] | Sichani, Enblom & Berg 2016 (strip theory + FASTSIM) | strip integration | integrated | μN (pointwise) |
//!
//! A zero normal force gives zero forces for every law (no contact patch).

mod fastrip;
mod fastsim;
mod heuristic;
mod kalker;
mod polach;

pub use fastrip::FastripParams;
pub use fastsim::{FastsimParams, TractionBound};
pub use heuristic::heuristic_with_coefficients;
pub use kalker::{KalkerCoefficients, kalker_coefficients};
pub use polach::{PolachParams, SlipVelocityFriction};

/// Why a creep force could not be evaluated.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum CreepError {
    /// An input quantity violates its rule.
    #[error("creep law input {quantity} = {value}: {rule}")]
    InvalidInput {
        quantity: &'static str,
        value: f64,
        rule: &'static str,
    },
    /// A parameter of a creep law violates its rule.
    #[error("{law} creep law parameter {parameter} = {value}: {rule}")]
    InvalidParameter {
        law: &'static str,
        parameter: &'static str,
        value: f64,
        rule: &'static str,
    },
}

/// Everything a creep law needs at one contact (SI units; conventions in the
/// module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CreepInput {
    /// Longitudinal creepage ξ (dimensionless), along `t_c`.
    pub xi: f64,
    /// Lateral creepage η (dimensionless), along `l_c`.
    pub eta: f64,
    /// Spin creepage φ (1/m), about `n_c`.
    pub phi_1_m: f64,
    /// Normal force N (N), ≥ 0.
    pub normal_force_n: f64,
    /// Semi-axis of the contact ellipse in the rolling direction, a (m).
    pub a_m: f64,
    /// Lateral semi-axis of the contact ellipse, b (m).
    pub b_m: f64,
    /// Coefficient of friction μ (dimensionless); for Polach with
    /// slip-velocity dependent friction, the maximum (static) value μ0.
    pub friction_coefficient: f64,
    /// Rolling speed V (m/s), ≥ 0: the slip velocity is w = V·√(ξ² + η²)
    /// (used only by laws whose friction depends on it).
    pub rolling_speed_m_s: f64,
    /// Combined shear modulus G (Pa) of wheel and rail.
    pub shear_modulus_pa: f64,
    /// Combined Poisson's ratio ν (dimensionless), 0 ≤ ν ≤ 0.5.
    pub poisson: f64,
}

impl CreepInput {
    /// Checks every field; a zero normal force needs no ellipse (a = b = 0
    /// is accepted then).
    pub fn validate(&self) -> Result<(), CreepError> {
        let bad = |quantity, value, rule| {
            Err(CreepError::InvalidInput {
                quantity,
                value,
                rule,
            })
        };
        for (name, v) in [
            ("xi", self.xi),
            ("eta", self.eta),
            ("phi (1/m)", self.phi_1_m),
        ] {
            if !v.is_finite() {
                return bad(name, v, "creepage must be finite");
            }
        }
        if !(self.normal_force_n.is_finite() && self.normal_force_n >= 0.0) {
            return bad(
                "normal force (N)",
                self.normal_force_n,
                "must be finite and >= 0",
            );
        }
        if !(self.friction_coefficient.is_finite() && self.friction_coefficient >= 0.0) {
            return bad(
                "friction coefficient",
                self.friction_coefficient,
                "must be finite and >= 0",
            );
        }
        if !(self.rolling_speed_m_s.is_finite() && self.rolling_speed_m_s >= 0.0) {
            return bad(
                "rolling speed (m/s)",
                self.rolling_speed_m_s,
                "must be finite and >= 0",
            );
        }
        if !(self.shear_modulus_pa.is_finite() && self.shear_modulus_pa > 0.0) {
            return bad(
                "shear modulus (Pa)",
                self.shear_modulus_pa,
                "must be finite and > 0",
            );
        }
        if !(0.0..=0.5).contains(&self.poisson) {
            return bad("Poisson's ratio", self.poisson, "must lie in [0, 0.5]");
        }
        if self.normal_force_n > 0.0 {
            for (name, v) in [("a (m)", self.a_m), ("b (m)", self.b_m)] {
                if !(v.is_finite() && v > 0.0) {
                    return bad(
                        name,
                        v,
                        "contact semi-axis must be finite and > 0 when N > 0",
                    );
                }
            }
        }
        Ok(())
    }
}

/// Creep forces on the wheel in the contact frame (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CreepForces {
    /// Longitudinal force Fx along `t_c` (N).
    pub fx_n: f64,
    /// Lateral force Fy along `l_c` (N).
    pub fy_n: f64,
    /// Spin moment Mz about `n_c` (N·m); 0 for laws that neglect it.
    pub mz_nm: f64,
}

impl CreepForces {
    /// No force.
    pub const ZERO: CreepForces = CreepForces {
        fx_n: 0.0,
        fy_n: 0.0,
        mz_nm: 0.0,
    };

    /// Magnitude of the tangential force √(Fx² + Fy²) (N).
    pub fn tangential_n(&self) -> f64 {
        self.fx_n.hypot(self.fy_n)
    }
}

/// A creep law with its parameters, selectable per run (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CreepLaw {
    /// No tangential forces (frictionless contact): for energy checks and
    /// for scenes that study the normal problem only.
    None,
    /// Kalker's linear theory (paper eq. 23); no saturation.
    KalkerLinear,
    /// Shen–Hedrick–Elkins heuristic saturation of the Kalker force (paper
    /// eq. 24–26); spin moment neglected.
    Heuristic,
    /// Polach's method (1999, optional 2005 extension and slip-velocity
    /// dependent friction).
    Polach(PolachParams),
    /// Kalker's simplified theory, FASTSIM (Kalker 1982), on the Hertz
    /// ellipse.
    Fastsim(FastsimParams),
    /// FaStrip (Sichani, Enblom & Berg 2016): the strip theory in the
    /// adhesion zone, FASTSIM with the Hertz traction bound in the slip zone.
    Fastrip(FastripParams),
}

impl Default for CreepLaw {
    /// Polach with its 1999 parameters (kA = kS = 1, constant friction): a
    /// saturating law with spin, the usual choice in vehicle dynamics codes.
    fn default() -> Self {
        CreepLaw::Polach(PolachParams::default())
    }
}

impl CreepLaw {
    /// The names accepted by [`CreepLaw::from_name`].
    pub const NAMES: [&'static str; 6] = [
        "kalker",
        "heuristic",
        "polach",
        "fastsim",
        "fastrip",
        "none",
    ];

    /// The law of that name (`kalker`, `heuristic`, `polach`, `fastsim`,
    /// `fastrip`, `none`) with default parameters.
    pub fn from_name(name: &str) -> Option<CreepLaw> {
        match name {
            "none" => Some(CreepLaw::None),
            "kalker" => Some(CreepLaw::KalkerLinear),
            "heuristic" => Some(CreepLaw::Heuristic),
            "polach" => Some(CreepLaw::Polach(PolachParams::default())),
            "fastsim" => Some(CreepLaw::Fastsim(FastsimParams::default())),
            "fastrip" => Some(CreepLaw::Fastrip(FastripParams::default())),
            _ => None,
        }
    }

    /// Short name (`kalker`, `heuristic`, `polach`, `fastsim`, `fastrip`,
    /// `none`).
    pub fn name(&self) -> &'static str {
        match self {
            CreepLaw::None => "none",
            CreepLaw::KalkerLinear => "kalker",
            CreepLaw::Heuristic => "heuristic",
            CreepLaw::Polach(_) => "polach",
            CreepLaw::Fastsim(_) => "fastsim",
            CreepLaw::Fastrip(_) => "fastrip",
        }
    }

    /// Checks the law's parameters.
    pub fn validate(&self) -> Result<(), CreepError> {
        match self {
            CreepLaw::None | CreepLaw::KalkerLinear | CreepLaw::Heuristic => Ok(()),
            CreepLaw::Polach(p) => p.validate(),
            CreepLaw::Fastsim(p) => p.validate(),
            CreepLaw::Fastrip(p) => p.validate(),
        }
    }

    /// Forces on the wheel for `input` (validated here; the law's parameters
    /// are checked by [`CreepLaw::validate`], which a run calls once).
    pub fn evaluate(&self, input: &CreepInput) -> Result<CreepForces, CreepError> {
        input.validate()?;
        if input.normal_force_n == 0.0 {
            return Ok(CreepForces::ZERO);
        }
        match self {
            CreepLaw::None => Ok(CreepForces::ZERO),
            CreepLaw::KalkerLinear => kalker::linear_forces(input),
            CreepLaw::Heuristic => heuristic::forces(input),
            CreepLaw::Polach(p) => polach::forces(input, p),
            CreepLaw::Fastsim(p) => fastsim::forces(input, p),
            CreepLaw::Fastrip(p) => fastrip::forces(input, p),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input() -> CreepInput {
        CreepInput {
            xi: 1e-4,
            eta: -2e-4,
            phi_1_m: 0.05,
            normal_force_n: 80e3,
            a_m: 6e-3,
            b_m: 4e-3,
            friction_coefficient: 0.3,
            rolling_speed_m_s: 30.0,
            shear_modulus_pa: 80.77e9,
            poisson: 0.3,
        }
    }

    #[test]
    fn kalker_linear_matches_eq_23() {
        let i = input();
        let c = kalker_coefficients(i.a_m / i.b_m, i.poisson).unwrap();
        let f = CreepLaw::KalkerLinear.evaluate(&i).unwrap();
        let gab = i.shear_modulus_pa * i.a_m * i.b_m;
        let sq = (i.a_m * i.b_m).sqrt();
        assert!((f.fx_n + gab * c.c11 * i.xi).abs() < 1e-9 * gab * c.c11 * i.xi.abs());
        let fy = -gab * c.c22 * i.eta - gab * sq * c.c23 * i.phi_1_m;
        assert!((f.fy_n - fy).abs() < 1e-9 * fy.abs());
        let mz = gab * sq * c.c23 * i.eta - gab * sq * sq * c.c33 * i.phi_1_m;
        assert!((f.mz_nm - mz).abs() < 1e-9 * mz.abs());
        // Forces oppose the slip.
        assert!(f.fx_n < 0.0);
    }

    #[test]
    fn zero_normal_force_gives_zero_for_every_law() {
        let mut i = input();
        i.normal_force_n = 0.0;
        i.a_m = 0.0;
        i.b_m = 0.0;
        for name in CreepLaw::NAMES {
            let law = CreepLaw::from_name(name).unwrap();
            assert_eq!(law.name(), name);
            assert_eq!(law.evaluate(&i).unwrap(), CreepForces::ZERO);
        }
        assert!(CreepLaw::from_name("coulomb").is_none());
    }

    #[test]
    fn invalid_inputs_are_named() {
        let mut i = input();
        i.xi = f64::NAN;
        let e = CreepLaw::KalkerLinear.evaluate(&i).unwrap_err();
        assert!(e.to_string().contains("xi"), "{e}");
        let mut i = input();
        i.b_m = 0.0;
        assert!(CreepLaw::KalkerLinear.evaluate(&i).is_err());
        let mut i = input();
        i.normal_force_n = -1.0;
        assert!(CreepLaw::KalkerLinear.evaluate(&i).is_err());
        let mut i = input();
        i.poisson = 0.6;
        assert!(CreepLaw::KalkerLinear.evaluate(&i).is_err());
    }
}
