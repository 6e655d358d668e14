//! Polach's creep force method (docs/reference/07-contact-forces.md §7.3): the 1999 method with spin, its
//! 2005 extension for large creepages (reduction factors kA, kS) and the
//! optional slip-velocity dependent friction coefficient.
//!
//! # Sources
//!
//! - **Polach 1999**: O. Polach, "A fast wheel–rail forces calculation computer
//!   code", *Vehicle System Dynamics* 33 (Suppl.), 1999, pp. 728–739.
//! - **Polach 2005**: O. Polach, "Creep forces in simulations of traction vehicles
//!   running on adhesion limit", *Wear* 258 (2005), pp. 992–1000.
//!
//! We had no copy of either paper at hand while writing this module, so the
//! formulae below are labelled (P1)…(P10) here rather than with the papers'
//! own equation numbers (which we could not verify); each says which paper it
//! comes from. Where docs/reference/07-contact-forces.md §7.3 states a formula explicitly it is followed.
//! ε_M uses the *signed* s_yC — hence the |ε_M| in (P8) — as in the
//! published method (a third-party translation of Polach's FORTRAN listing
//! agrees).
//!
//! # Formulae
//!
//! Polach's notation: Q = normal force N; creepages s_x = ξ, s_y = η; spin
//! ψ = φ (1/m); f = μ.
//!
//! Without spin (Polach 1999), with the 2005 factors kA, kS (Polach 2005;
//! kA = kS = 1 is the 1999 form):
//!
//! ```text
//! (P1) s = √(ξ² + η²)
//! (P2) F = 2Qμ/π · [ kA ε / (1 + (kA ε)²) + atan(kS ε) ],   kS ≤ kA ≤ 1
//! (P3) ε = (2/3) · C π a² b / (Q μ) · s_C,   C = (3/8) · (G/a) · c_jj
//!          = π G a b c_jj s_C / (4 Q μ)                       (docs/reference/07-contact-forces.md §7.3)
//! (P4) c_jj = √( (c11 ξ/s)² + (c22 η/s)² )
//! (P5) Fx = F ξ/s_C,   Fy = F η/s_C          (Polach's sign, see below)
//! ```
//!
//! C (N/m³) is Polach's contact shear stiffness per unit area; substituting
//! C = 3G c_jj/(8a) into (2/3) C π a² b s/(Qμ) gives exactly the reference's
//! (`docs/reference/07-contact-forces.md` §7.3)
//! π G a b c_jj s/(4Qμ): both forms are the same number.
//!
//! Spin (Polach 1999; K_S is the reference's name for the shape factor
//! 1 + 6.3(1 − e^(−a/b))):
//!
//! ```text
//! (P6) s_yC = η + φ a   if |η + φ a| > |η|,   else s_yC = η
//!      s_C  = √(ξ² + s_yC²)
//! (P7) F_yS = −(9/16) a Q μ K_M K_S φ / s_C,   K_S = 1 + 6.3 (1 − e^(−a/b))
//! (P8) K_M = |ε_M| (δ³/3 − δ²/2 + 1/6) − (1/3) √((1 − δ²)³)
//! (P9) δ = (ε_M² − 1)/(ε_M² + 1),
//!      ε_M = (8/3) · G b √(ab) / (Q μ) · c23 s_yC / K_S
//! ```
//!
//! and Polach's total lateral force is F η/s_C + F_yS. The spin moment is
//! neglected by the method: Mz = 0 (docs/reference/07-contact-forces.md §7.3, "zero where the law neglects
//! it").
//!
//! Slip-velocity dependent friction (Polach 2005):
//!
//! ```text
//! (P10) μ(w) = μ0 [ (1 − A) e^(−B w) + A ],   w = V s  (slip velocity, m/s)
//! ```
//!
//! with μ0 = [`CreepInput::friction_coefficient`] and V =
//! [`CreepInput::rolling_speed_m_s`]; μ(w) is used everywhere μ appears
//! above. As V → 0 (or s → 0), w → 0 and μ → μ0.
//!
//! # K_M in closed form
//!
//! With x = |ε_M|, 1 − δ = 2/(1 + x²), 1 + δ = 2x²/(1 + x²), and
//! δ³/3 − δ²/2 + 1/6 = (δ − 1)²(2δ + 1)/6, (P8) simplifies exactly to
//!
//! ```text
//! K_M = −(2/3) |ε_M| / (1 + ε_M²)²
//! ```
//!
//! which is what [`forces`] evaluates: the published form cancels
//! catastrophically for large ε_M (both terms → 0 like 1/ε_M³ while each is
//! computed with an absolute error ~ ε_M · 10⁻¹⁶), the closed form does not.
//! A unit test checks the two agree. So K_M ≤ 0, K_M ≈ −(2/3)|ε_M| for small
//! ε_M, K_M → 0 for large ε_M (pure large spin gives no net lateral force),
//! and |K_M| ≤ (2/3)(1/√3)/(4/3)² ≈ 0.2165 (at ε_M² = 1/3).
//!
//! # Signs (docs/reference/01-units-frames.md §1)
//!
//! Polach writes the forces along the creepages (P5), (P7): in his
//! convention the force has the sign of the creepage. Here creepages are
//! wheel-minus-rail and the forces are those **on the wheel**, opposing the
//! slip, as in [`super::kalker`]: every force of (P5), (P7) is negated.
//! Implemented:
//!
//! ```text
//! Fx = −F ξ/s_C
//! Fy = −F η/s_C + (9/16) a Q μ K_M K_S φ/s_C        (K_M ≤ 0)
//! Mz = 0
//! ```
//!
//! The law is odd: (−ξ, −η, −φ) → (−Fx, −Fy, 0) exactly (s, s_C, c_jj, |s_yC|
//! and F are even; ξ, η, φ, s_yC flip).
//!
//! # Small-creepage limit (kA = kS = 1)
//!
//! For ε → 0, F = 2Qμ/π (2ε − (4/3)ε³ + …) = G a b c_jj s_C (1 − (2/3)ε²…),
//! so Fx → −G a b c_jj ξ and Fy → −G a b c_jj η: for pure ξ (c_jj = c11) and
//! pure η (c_jj = c22) this is Kalker's linear law (paper eq. 23) with its
//! signs. For ε_M → 0, K_M → −(2/3)|ε_M| and the spin force →
//! −(9/16)(2/3)(8/3) G (ab)^1.5 c23 φ |s_yC|/s_C = −G (ab)^1.5 c23 φ |s_yC|/s_C,
//! which is Kalker's −G (ab)^1.5 c23 φ whenever ξ = 0 (then |s_yC| = s_C),
//! in particular for pure spin and for any (η, φ) pair. With the 2005
//! factors the initial slope is scaled by (kA + kS)/2 (dF/dε at 0 is
//! kA + kS instead of 2), by design (docs/reference/07-contact-forces.md §7.3); the spin force is not
//! scaled (Polach 2005 changes only (P2)).
//!
//! Two deviations from Kalker's linear law in that limit are inherent in the
//! published method and kept: with ξ and η both non-zero the force is along
//! the creepage with the combined coefficient c_jj (P4) instead of c11 ξ,
//! c22 η separately; with ξ and φ both non-zero the spin force is reduced by
//! |s_yC|/s_C.
//!
//! # Saturation
//!
//! For kS ≤ kA, kA ε/(1 + (kA ε)²) < atan(1/(kA ε)) ≤ π/2 − atan(kS ε), so
//! F < μQ (P2); with kS > kA, F could reach up to (1 + 1/π) μQ, which is why
//! [`PolachParams::validate`] demands kS ≤ kA as Polach does. The spin force
//! is added to Fy (P7): when η and φ act in the same direction (s_yC
//! modified), |(Fx, Fy)| ≤ μQ √(ξ² + (|η| + 0.89 |φa|)²)/s_C < μQ, because
//! (9/16) |K_M| K_S ≤ (9/16)(0.2165)(7.3) ≈ 0.89; when they oppose, no bound
//! follows from the formulae, although μQ was never exceeded with Kalker's
//! coefficients in our sweeps (random sampling over a/b = 0.1…10 and
//! creepages 10⁻⁵…1, and the grid of `tests/creep_laws.rs`). So that the
//! law's contract |F| ≤ μN holds by construction, the resultant of (Fx, Fy)
//! is **limited to μ(w) N** (scaled along its own direction) whenever it
//! would exceed it; this guard is our addition, not Polach's, and it leaves
//! the law odd and continuous.
//!
//! # Edge cases
//!
//! - μ(w) = 0 (μ0 = 0): zero force.
//! - ξ = η = φ = 0: s_C = 0, zero force (s_C = 0 only there: φ ≠ 0 with
//!   ξ = η = 0 gives s_yC = φa ≠ 0).
//! - Pure spin (s = 0, s_C > 0): c_jj (P4) is undefined but multiplies
//!   nothing (Fx = Fy = 0 from (P5) since ξ = η = 0); c22 is used. The spin
//!   force is finite: |φ|/s_C ≤ 2/a always.
//! - Overflowing ε or ε_M (tiny Q μ): the rational terms are evaluated in
//!   forms that tend to 0, never ∞/∞.

use std::f64::consts::PI;

use super::kalker::kalker_coefficients;
use super::{CreepError, CreepForces, CreepInput};

/// Law name used in [`CreepError::InvalidParameter`].
const LAW: &str = "Polach";

/// Parameters of Polach's method (module docs). The default is the 1999
/// form: kA = kS = 1, constant friction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolachParams {
    /// kA, reduction factor of the initial slope in the area of adhesion
    /// Polach 2005 (dimensionless, 0 < kA ≤ 1; 1 in the 1999 form).
    pub k_a: f64,
    /// kS, reduction factor of the initial slope in the area of slip Polach 2005
    /// (dimensionless, 0 < kS ≤ kA; 1 in the 1999 form).
    pub k_s: f64,
    /// Slip-velocity dependent friction μ(w) Polach 2005; `None`: constant μ = μ0.
    pub slip_friction: Option<SlipVelocityFriction>,
}

/// Slip-velocity dependent friction coefficient Polach 2005 (module docs, (P10)):
/// μ(w) = μ0 [(1 − A) e^(−B w) + A], w = slip velocity (m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipVelocityFriction {
    /// A = μ∞/μ0, ratio of the friction coefficient at infinite slip
    /// velocity to the maximum one (dimensionless, 0 ≤ A ≤ 1).
    pub a_ratio: f64,
    /// B, coefficient of the exponential decrease of friction with slip
    /// velocity (s/m, ≥ 0).
    pub b_s_m: f64,
}

impl SlipVelocityFriction {
    /// μ(w) = μ0 [(1 − A) e^(−B w) + A] for the maximum friction
    /// coefficient `mu0` and the slip velocity `slip_velocity_m_s` ≥ 0 (P10).
    pub fn friction(&self, mu0: f64, slip_velocity_m_s: f64) -> f64 {
        if self.b_s_m == 0.0 {
            // No decrease; also avoids 0 · ∞ for an infinite slip velocity.
            return mu0;
        }
        let decay = (-self.b_s_m * slip_velocity_m_s).exp();
        mu0 * ((1.0 - self.a_ratio) * decay + self.a_ratio)
    }

    /// Checks A ∈ [0, 1] and B ≥ 0, both finite.
    pub fn validate(&self) -> Result<(), CreepError> {
        if !(self.a_ratio.is_finite() && (0.0..=1.0).contains(&self.a_ratio)) {
            return Err(invalid(
                "A (mu_inf/mu0)",
                self.a_ratio,
                "must be finite with 0 <= A <= 1 (Polach 2005)",
            ));
        }
        if !(self.b_s_m.is_finite() && self.b_s_m >= 0.0) {
            return Err(invalid(
                "B (s/m)",
                self.b_s_m,
                "must be finite and >= 0 (Polach 2005)",
            ));
        }
        Ok(())
    }
}

impl Default for PolachParams {
    /// The 1999 form: kA = kS = 1, constant friction.
    fn default() -> Self {
        Self::polach_1999()
    }
}

impl PolachParams {
    /// Names accepted by [`PolachParams::preset`].
    pub const PRESET_NAMES: [&'static str; 3] = ["1999", "dry-2005", "wet-2005"];

    /// μ0 of the dry preset, Polach 2005 Table 1 (advisory: the law takes μ0 from
    /// [`CreepInput::friction_coefficient`]; a run that selects the preset
    /// should set that to this value unless it has its own).
    pub const DRY_2005_MU0: f64 = 0.55;

    /// μ0 of the wet preset, Polach 2005 Table 1 (advisory, as
    /// [`PolachParams::DRY_2005_MU0`]).
    pub const WET_2005_MU0: f64 = 0.30;

    /// The 1999 method Polach 1999: kA = kS = 1, constant friction (the default).
    pub const fn polach_1999() -> Self {
        PolachParams {
            k_a: 1.0,
            k_s: 1.0,
            slip_friction: None,
        }
    }

    /// Dry rail, Polach 2005 Table 1 (locomotive measurements): kA = 1.00,
    /// kS = 0.40, A = 0.40, B = 0.60 s/m; μ0 = 0.55 is advisory
    /// ([`PolachParams::DRY_2005_MU0`]).
    pub const fn dry_2005() -> Self {
        PolachParams {
            k_a: 1.0,
            k_s: 0.4,
            slip_friction: Some(SlipVelocityFriction {
                a_ratio: 0.4,
                b_s_m: 0.6,
            }),
        }
    }

    /// Wet rail, Polach 2005 Table 1: kA = 0.30, kS = 0.10, A = 0.40,
    /// B = 0.20 s/m; μ0 = 0.30 is advisory
    /// ([`PolachParams::WET_2005_MU0`]).
    pub const fn wet_2005() -> Self {
        PolachParams {
            k_a: 0.3,
            k_s: 0.1,
            slip_friction: Some(SlipVelocityFriction {
                a_ratio: 0.4,
                b_s_m: 0.2,
            }),
        }
    }

    /// The preset of that name ([`PolachParams::PRESET_NAMES`]) and its
    /// advisory μ0, if the source gives one (`None` for the 1999 form, whose
    /// friction is whatever the run uses).
    pub fn preset(name: &str) -> Option<(PolachParams, Option<f64>)> {
        match name {
            "1999" => Some((Self::polach_1999(), None)),
            "dry-2005" => Some((Self::dry_2005(), Some(Self::DRY_2005_MU0))),
            "wet-2005" => Some((Self::wet_2005(), Some(Self::WET_2005_MU0))),
            _ => None,
        }
    }

    /// Factor (kA + kS)/2 by which the 2005 form scales the initial slope of
    /// the creep curve relative to Kalker's linear law (module docs).
    pub fn initial_slope_factor(&self) -> f64 {
        0.5 * (self.k_a + self.k_s)
    }

    /// Checks 0 < kS ≤ kA ≤ 1 (finite), as Polach 2005 requires — kS ≤ kA is also
    /// what keeps F ≤ μQ (module docs) — and the friction parameters.
    pub fn validate(&self) -> Result<(), CreepError> {
        if !(self.k_a.is_finite() && self.k_a > 0.0 && self.k_a <= 1.0) {
            return Err(invalid(
                "kA",
                self.k_a,
                "must be finite with 0 < kA <= 1 (Polach 2005: kS <= kA <= 1)",
            ));
        }
        if !(self.k_s.is_finite() && self.k_s > 0.0) {
            return Err(invalid("kS", self.k_s, "must be finite and > 0"));
        }
        if self.k_s > self.k_a {
            return Err(invalid(
                "kS",
                self.k_s,
                "must not exceed kA (Polach 2005: kS <= kA <= 1; else |F| may exceed muN)",
            ));
        }
        if let Some(f) = &self.slip_friction {
            f.validate()?;
        }
        Ok(())
    }
}

fn invalid(parameter: &'static str, value: f64, rule: &'static str) -> CreepError {
    CreepError::InvalidParameter {
        law: LAW,
        parameter,
        value,
        rule,
    }
}

/// Polach's forces on the wheel (module docs); `input` validated, N > 0.
/// The parameters are checked again here (a few comparisons), so that
/// unvalidated ones give an error rather than NaN or |F| > μN.
pub(crate) fn forces(input: &CreepInput, p: &PolachParams) -> Result<CreepForces, CreepError> {
    p.validate()?;
    let q = input.normal_force_n;
    let (xi, eta, phi) = (input.xi, input.eta, input.phi_1_m);
    let (a, b) = (input.a_m, input.b_m);
    let g = input.shear_modulus_pa;

    // (P1), (P10): friction at the slip velocity w = V s.
    let s = xi.hypot(eta);
    let mu0 = input.friction_coefficient;
    let mu = match &p.slip_friction {
        None => mu0,
        Some(f) => f.friction(mu0, input.rolling_speed_m_s * s),
    };
    if mu <= 0.0 {
        return Ok(CreepForces::ZERO);
    }

    // (P6): spin-modified lateral creepage and total creepage.
    let phi_a = phi * a;
    let s_yc = if (eta + phi_a).abs() > eta.abs() {
        eta + phi_a
    } else {
        eta
    };
    let s_c = xi.hypot(s_yc);
    if s_c == 0.0 {
        // ξ = η = φ = 0 (module docs).
        return Ok(CreepForces::ZERO);
    }

    let c = kalker_coefficients(a / b, input.poisson)?;
    // (P4); for pure spin c_jj multiplies ξ = η = 0 (module docs).
    let c_jj = if s > 0.0 {
        (c.c11 * xi / s).hypot(c.c22 * eta / s)
    } else {
        c.c22
    };

    // (P2), (P3), (P5) with the wheel's sign.
    let qmu = q * mu;
    let eps = PI * g * a * b * c_jj * s_c / (4.0 * qmu);
    let f = 2.0 * qmu / PI * saturation_shape(eps, p.k_a, p.k_s);
    let mut fx = -f * xi / s_c;
    let mut fy = -f * eta / s_c;

    // (P7)–(P9): lateral force from spin, wheel's sign.
    if phi != 0.0 {
        let k_s_shape = 1.0 + 6.3 * (1.0 - (-a / b).exp());
        let eps_m = 8.0 / 3.0 * g * b * (a * b).sqrt() / qmu * c.c23 * s_yc.abs() / k_s_shape;
        let k_m = spin_factor(eps_m);
        fy += 9.0 / 16.0 * a * qmu * k_m * k_s_shape * phi / s_c;
    }

    // Resultant limited to μN (module docs, "Saturation").
    let limit = qmu;
    let t = fx.hypot(fy);
    if t > limit {
        let k = limit / t;
        fx *= k;
        fy *= k;
    }
    Ok(CreepForces {
        fx_n: fx,
        fy_n: fy,
        mz_nm: 0.0,
    })
}

/// F/(2Qμ/π) of (P2): kA ε/(1 + (kA ε)²) + atan(kS ε), for ε ≥ 0 (also
/// ε = ∞: the first term is written 1/(x + 1/x) above x = 1 so that it tends
/// to 0 rather than ∞/∞).
fn saturation_shape(eps: f64, k_a: f64, k_s: f64) -> f64 {
    let x = k_a * eps;
    let adhesion = if x <= 1.0 {
        x / (1.0 + x * x)
    } else {
        1.0 / (x + 1.0 / x)
    };
    adhesion + (k_s * eps).atan()
}

/// K_M of (P8) in its exact closed form −(2/3)|ε_M|/(1 + ε_M²)² (module
/// docs); written 1/(x (x + 1/x)²) above x = 1, so ε_M = ∞ gives 0.
fn spin_factor(eps_m: f64) -> f64 {
    let x = eps_m.abs();
    if x <= 1.0 {
        let d = 1.0 + x * x;
        -2.0 / 3.0 * x / (d * d)
    } else {
        let t = x + 1.0 / x;
        -2.0 / 3.0 / (x * t * t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (P8)–(P9) exactly as published.
    fn spin_factor_published(eps_m: f64) -> f64 {
        let e2 = eps_m * eps_m;
        let d = (e2 - 1.0) / (e2 + 1.0);
        eps_m.abs() * (d.powi(3) / 3.0 - d * d / 2.0 + 1.0 / 6.0)
            - (1.0 / 3.0) * (1.0 - d * d).powi(3).sqrt()
    }

    #[test]
    fn spin_factor_matches_the_published_form() {
        // Where the published form is well conditioned (ε_M ≤ 10), the two
        // agree to rounding; above, the published form loses digits.
        let mut e = 1e-6;
        while e <= 10.0 {
            let closed = spin_factor(e);
            let published = spin_factor_published(e);
            assert!(
                (closed - published).abs() <= 1e-13,
                "eps_M = {e}: {closed} vs {published}"
            );
            assert_eq!(spin_factor(-e), closed, "even in eps_M");
            e *= 1.1;
        }
        // Known values: 0, the maximum |K_M| at ε_M² = 1/3, ε_M = 1.
        assert_eq!(spin_factor(0.0), 0.0);
        let x = (1.0_f64 / 3.0).sqrt();
        assert!((spin_factor(x) + 2.0 / 3.0 * x * 9.0 / 16.0).abs() < 1e-15);
        assert!((spin_factor(1.0) + 1.0 / 6.0).abs() < 1e-15);
        // Bounded by the value at the maximum everywhere, and → 0 at ∞.
        let mut e = 1e-3;
        while e < 1e200 {
            let k = spin_factor(e);
            assert!(k <= 0.0 && k >= spin_factor(x) - 1e-15 && k.is_finite());
            e *= 1.3;
        }
        assert_eq!(spin_factor(f64::INFINITY), 0.0);
        // Large ε_M: ≈ −(2/3)/ε_M³ (where the published form is noise).
        let k = spin_factor(1e6);
        assert!((k * 1e18 + 2.0 / 3.0).abs() < 1e-11, "{k}");
    }

    #[test]
    fn saturation_shape_limits_and_bound() {
        // Small ε: 2ε for kA = kS = 1 (slope kA + kS in general).
        let e = 1e-8;
        assert!((saturation_shape(e, 1.0, 1.0) / e - 2.0).abs() < 1e-12);
        assert!((saturation_shape(e, 1.0, 0.4) / e - 1.4).abs() < 1e-12);
        // Large ε: π/2; ∞ handled.
        assert_eq!(saturation_shape(f64::INFINITY, 1.0, 0.4), PI / 2.0);
        assert!((saturation_shape(1e12, 1.0, 1.0) - PI / 2.0).abs() < 1e-11);
        // kS ≤ kA: never above π/2 (F ≤ μQ) but for rounding; continuous at
        // kA ε = 1.
        for (ka, ks) in [(1.0, 1.0), (1.0, 0.4), (0.3, 0.1), (0.5, 0.5)] {
            let mut e = 1e-4;
            while e < 1e8 {
                // Strictly below in exact arithmetic; rounding may reach it.
                let v = saturation_shape(e, ka, ks);
                assert!(v <= PI / 2.0 * (1.0 + 1e-15), "{ka} {ks} {e}");
                e *= 1.05;
            }
            let at = 1.0 / ka;
            let below = saturation_shape(at * (1.0 - 1e-12), ka, ks);
            let above = saturation_shape(at * (1.0 + 1e-12), ka, ks);
            assert!((below - above).abs() < 1e-10);
        }
        // kS > kA can exceed π/2: why validate() forbids it.
        assert!(saturation_shape(10.0, 0.1, 1.0) > PI / 2.0);
        // kA = kS = 1 is monotone: derivative 2/(1 + ε²)² > 0.
        let mut last = 0.0;
        for k in 1..=10_000 {
            let v = saturation_shape(k as f64 * 1e-3, 1.0, 1.0);
            assert!(v > last);
            last = v;
        }
    }

    #[test]
    fn friction_function() {
        let f = SlipVelocityFriction {
            a_ratio: 0.4,
            b_s_m: 0.6,
        };
        assert_eq!(f.friction(0.55, 0.0), 0.55);
        let w = 2.0;
        let want = 0.55 * (0.6 * (-1.2_f64).exp() + 0.4);
        assert!((f.friction(0.55, w) - want).abs() < 1e-15);
        assert!((f.friction(0.55, 1e6) - 0.4 * 0.55).abs() < 1e-15);
        assert!((f.friction(0.55, f64::INFINITY) - 0.4 * 0.55).abs() < 1e-15);
        // Falling with w.
        let mut last = f64::INFINITY;
        for k in 0..100 {
            let mu = f.friction(0.55, k as f64 * 0.1);
            assert!(mu < last && mu >= 0.22);
            last = mu;
        }
        // B = 0: constant, even at infinite slip velocity.
        let flat = SlipVelocityFriction {
            a_ratio: 0.4,
            b_s_m: 0.0,
        };
        assert_eq!(flat.friction(0.3, f64::INFINITY), 0.3);
    }

    #[test]
    fn presets_have_the_published_values_and_validate() {
        let d = PolachParams::dry_2005();
        assert_eq!((d.k_a, d.k_s), (1.0, 0.4));
        let f = d.slip_friction.unwrap();
        assert_eq!((f.a_ratio, f.b_s_m), (0.4, 0.6));
        let w = PolachParams::wet_2005();
        assert_eq!((w.k_a, w.k_s), (0.3, 0.1));
        let f = w.slip_friction.unwrap();
        assert_eq!((f.a_ratio, f.b_s_m), (0.4, 0.2));
        assert_eq!(PolachParams::DRY_2005_MU0, 0.55);
        assert_eq!(PolachParams::WET_2005_MU0, 0.30);
        assert_eq!(PolachParams::default(), PolachParams::polach_1999());
        assert_eq!(PolachParams::default().initial_slope_factor(), 1.0);
        assert!((d.initial_slope_factor() - 0.7).abs() < 1e-15);
        for name in PolachParams::PRESET_NAMES {
            let (p, mu0) = PolachParams::preset(name).unwrap();
            p.validate().unwrap();
            assert_eq!(mu0.is_some(), name != "1999");
        }
        assert_eq!(
            PolachParams::preset("dry-2005"),
            Some((d, Some(PolachParams::DRY_2005_MU0)))
        );
        assert!(PolachParams::preset("icy").is_none());
    }

    #[test]
    fn invalid_parameters_name_their_rule() {
        let base = PolachParams::default();
        let cases: [(PolachParams, &str); 8] = [
            (PolachParams { k_a: 0.0, ..base }, "kA"),
            (PolachParams { k_a: 1.2, ..base }, "kA"),
            (
                PolachParams {
                    k_a: f64::NAN,
                    ..base
                },
                "kA",
            ),
            (PolachParams { k_s: 0.0, ..base }, "kS"),
            (
                PolachParams {
                    k_a: 0.3,
                    k_s: 0.4,
                    ..base
                },
                "kS",
            ),
            (
                PolachParams {
                    k_s: f64::INFINITY,
                    ..base
                },
                "kS",
            ),
            (
                PolachParams {
                    slip_friction: Some(SlipVelocityFriction {
                        a_ratio: 1.5,
                        b_s_m: 0.6,
                    }),
                    ..base
                },
                "A",
            ),
            (
                PolachParams {
                    slip_friction: Some(SlipVelocityFriction {
                        a_ratio: 0.4,
                        b_s_m: -0.1,
                    }),
                    ..base
                },
                "B",
            ),
        ];
        for (p, name) in cases {
            let e = p.validate().unwrap_err();
            match e {
                CreepError::InvalidParameter { law, parameter, .. } => {
                    assert_eq!(law, "Polach");
                    assert!(parameter.starts_with(name), "{parameter} vs {name}");
                }
                other => panic!("unexpected {other:?}"),
            }
            assert!(e.to_string().contains(name), "{e}");
        }
        // Boundary values are accepted.
        PolachParams {
            k_a: 1.0,
            k_s: 1.0,
            slip_friction: Some(SlipVelocityFriction {
                a_ratio: 0.0,
                b_s_m: 0.0,
            }),
        }
        .validate()
        .unwrap();
        PolachParams {
            k_a: 0.5,
            k_s: 0.5,
            slip_friction: Some(SlipVelocityFriction {
                a_ratio: 1.0,
                b_s_m: 3.0,
            }),
        }
        .validate()
        .unwrap();
    }

    fn input(xi: f64, eta: f64, phi: f64) -> CreepInput {
        CreepInput {
            xi,
            eta,
            phi_1_m: phi,
            normal_force_n: 80e3,
            a_m: 6e-3,
            b_m: 4e-3,
            friction_coefficient: 0.3,
            rolling_speed_m_s: 30.0,
            shear_modulus_pa: 80.8e9,
            poisson: 0.28,
        }
    }

    #[test]
    fn edge_cases_are_finite() {
        let p = PolachParams::default();
        // No creepage: zero, no NaN.
        assert_eq!(
            forces(&input(0.0, 0.0, 0.0), &p).unwrap(),
            CreepForces::ZERO
        );
        // Pure spin: lateral force only, opposing φ (Kalker's sign).
        let f = forces(&input(0.0, 0.0, 0.3), &p).unwrap();
        assert_eq!(f.fx_n, 0.0);
        assert!(f.fy_n < 0.0 && f.fy_n.is_finite());
        assert_eq!(f.mz_nm, 0.0);
        // μ = 0: zero.
        let mut i = input(0.01, 0.02, 1.0);
        i.friction_coefficient = 0.0;
        assert_eq!(forces(&i, &p).unwrap(), CreepForces::ZERO);
        // Vanishing N μ (ε, ε_M → ∞): finite, bounded by μN.
        let mut i = input(0.01, -0.02, 1.0);
        i.normal_force_n = 1e-300;
        let f = forces(&i, &PolachParams::dry_2005()).unwrap();
        assert!(f.fx_n.is_finite() && f.fy_n.is_finite());
        assert!(f.tangential_n() <= 0.3 * 1e-300 * (1.0 + 1e-12));
        // Huge creepages: F = μN, spin force gone, so |(Fx, Fy)| = μN s/s_C.
        let (xi, phi) = (1e200, 1e200);
        let f = forces(&input(xi, 0.0, phi), &p).unwrap();
        assert!(f.fx_n.is_finite() && f.fy_n.is_finite());
        assert_eq!(f.fy_n, 0.0);
        let s_over_sc = xi / xi.hypot(phi * 6e-3);
        assert!((f.tangential_n() / (0.3 * 80e3) - s_over_sc).abs() < 1e-12);
    }
}
