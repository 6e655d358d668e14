//! Hertz contact ellipse, approach and normal stiffness (docs/reference/07-contact-forces.md §7.1).
//!
//! # Inputs and conventions
//!
//! - `A` (rolling direction) and `B` (lateral), the principal **relative
//!   curvatures** (1/m) of the two bodies at the contact point, docs/reference/07-contact-forces.md §7.1:
//!   A = ½(κ_w,roll + κ_r,roll), B = ½(κ_w,lat + κ_r,lat) (so a sphere of
//!   radius R on a plane has A = B = 1/(2R)). Hertz theory needs A > 0 and
//!   B > 0; A ≤ 0 or B ≤ 0 (conformal or concave contact) is reported as
//!   [`HertzError::NonHertzian`], never clamped.
//! - [`Material`]: Young's modulus (Pa) and Poisson's ratio, the **same for
//!   both bodies** (wheel and rail steel), which is what the formulas of
//!   docs/reference/07-contact-forces.md §7.1 assume (1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ = 2(1 − ν²)/E,
//!   Johnson 1985 §4.2, with equal materials).
//! - The normal force N (N) for the semi-axes and the approach.
//!
//! # Formulas (docs/reference/07-contact-forces.md §7.1; Johnson, *Contact Mechanics*, 1985, §4.2)
//!
//! ```text
//! θ = acos(|B − A| / (A + B))
//! e: max(A,B)/min(A,B) = [E(e)/(1 − e²) − K(e)] / [K(e) − E(e)]
//! m = (2E(e) / (π(1 − e²)))^(1/3),  n = m √(1 − e²),  r = 2K(e) / (π m)
//! major = m c,  minor = n c,  c = [3N(1 − ν²) / (2E(A + B))]^(1/3)
//! δ = r [(1.5(1 − ν²)/E)² (A + B) N²]^(1/3)   ⇔   N = K_H δ^1.5,
//! K_H = 2E / (3(1 − ν²) r^1.5 √(A + B))
//! ```
//!
//! K(e), E(e) are the complete elliptic integrals of parameter e² (see
//! [`crate::forces::elliptic`]; SciPy `ellipk(e**2)`). The major axis lies along the
//! direction of the **smaller** relative curvature: A < B makes the rolling
//! semi-axis `a` the major one. A = B (θ = 90°) is the circle: e = 0 and
//! m = n = r = 1 exactly. These are the classical Hertz coefficients m, n, r
//! as functions of θ (e.g. at θ = 30°: m = 2.731, n = 0.493, r = 0.726).
//!
//! # Solving for the eccentricity (no table, no allocation)
//!
//! The unknown is u = −ln(1 − e²) = 2 ln(major/minor) ∈ [0, ∞), from which
//! both 1 − e² = exp(−u) and e² = −expm1(−u) (= 1 − exp(−u) once u ≥ ln 2)
//! follow without cancellation (the circle end needs e², the elongated end
//! 1 − e²). With the AGM sums of
//! [`crate::forces::elliptic`] (Σ = (K − E)/K = e²/2 + S₁, S₁ > 0), the ratio is
//!
//! ```text
//! ρ(u) = (E − (1 − e²)K) / ((1 − e²)(K − E)) = (e²/2 − S₁) / ((1 − e²) Σ),
//! ρ − 1 = (e⁴/2 − (2 − e²) S₁) / ((1 − e²) Σ)        (used for e² < 1/2)
//! ```
//!
//! (K cancels; neither form subtracts nearly equal K and E), and Newton's
//! method is applied to g(u) = ln ρ(u) − ln(max/min) with the analytic slope
//! dln ρ/du = 1 + (1 − e²)/(2D) − (1 − Σ)/(2Σ) = 1 + (2S₁ − Σ²)/(2ΣD),
//! D = e²/2 − S₁ (from dE/dm = (E − K)/(2m), dK/dm = (E − (1 − m)K)/(2m(1 − m)),
//! DLMF 19.4.1 written for m = k²). The initial guess is accurate to
//! 1.5e-9 relative: a (6, 6) rational fit of u/s in s = ln(max/min) on
//! [0, 12] (fitted to 40-digit values, 1.43e-9 max error), and for s > 12 the
//! m_c → 0 asymptotics of K, E (A&S 17.3.26, 17.3.36) to first order in
//! m_c, solved by two Newton steps (error < 2e-11). One Newton step then lands
//! within ~1e-17 of the root; its size (≤ 1e-8 u) is the convergence test, and
//! K, E are carried to the new point by their first-order Taylor terms
//! (dK/du = K D/(2e²), dE/du = −(1 − e²)K Σ/(2e²)), whose remainder is below
//! 1e-16 relative; e² and 1 − e² are carried likewise (1 − e^(−step) =
//! step(1 − step/2) to O(step³)). So a shape costs one AGM run (5–8 square
//! roots and divisions) and six elementary functions (ln_1p, exp, expm1 or
//! none, ln_1p or ln, cbrt, sqrt): ≈ 0.16 µs on the development machine
//! (the `#[ignore]`d timing test in tests/hertz_reference.rs). A second
//! Newton step would be taken only if the first one exceeded the tolerance;
//! over 2·10⁶ ratios spanning the supported range it never did.
//!
//! Accuracy (tests/hertz_reference.rs): e, e², 1 − e², K(e), E(e), m, n, r,
//! θ, the semi-axes, δ and K_H agree with 40-digit mpmath values to 1.3e-15
//! relative for max/min ≤ 1e3 and to 6e-15 up to 1e12 (the largest errors
//! are 1 − e² and E(e) of the most elongated ellipses, where e²/2 − S₁ and
//! 1 − Σ lose about log₂K bits), and with SciPy `brentq` solutions to
//! 1.8e-10 (the SciPy reference's own error near the circle).
//!
//! Supported: max(A,B)/min(A,B) ≤ [`MAX_CURVATURE_RATIO`] (an ellipse with
//! axis ratio 3.9·10⁶, far beyond where Hertz theory applies); beyond it,
//! [`HertzError::CurvatureRatioOutOfRange`].

use std::f64::consts::{FRAC_PI_2, LN_2, PI};

use crate::forces::elliptic::agm_sums;

/// Largest supported max(A, B) / min(A, B) (dimensionless); the major/minor
/// semi-axis ratio there is 3.9e6. Larger ratios are an error, not a
/// clamp (nearly conformal contact is outside Hertz theory anyway).
pub const MAX_CURVATURE_RATIO: f64 = 1e12;

/// Why a Hertz contact could not be computed.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum HertzError {
    /// A curvature, or A + B, is NaN or infinite.
    #[error(
        "relative curvatures must be finite (and so must their sum): A = {a_curv_1_m} 1/m (rolling), B = {b_curv_1_m} 1/m (lateral)"
    )]
    NonFiniteCurvature { a_curv_1_m: f64, b_curv_1_m: f64 },
    /// A ≤ 0 or B ≤ 0: conformal or concave contact, outside Hertz theory
    /// (docs/reference/07-contact-forces.md §7.1: reported, not clamped).
    #[error(
        "non-Hertzian contact geometry: relative curvatures A = {a_curv_1_m} 1/m (rolling) and B = {b_curv_1_m} 1/m (lateral) must both be > 0 (conformal or concave contact)"
    )]
    NonHertzian { a_curv_1_m: f64, b_curv_1_m: f64 },
    /// max(A, B)/min(A, B) exceeds [`MAX_CURVATURE_RATIO`].
    #[error(
        "curvature ratio max(A,B)/min(A,B) = {ratio} exceeds the supported {max_ratio} (A = {a_curv_1_m} 1/m, B = {b_curv_1_m} 1/m): the contact is nearly conformal"
    )]
    CurvatureRatioOutOfRange {
        a_curv_1_m: f64,
        b_curv_1_m: f64,
        ratio: f64,
        max_ratio: f64,
    },
    /// Young's modulus not finite and > 0, or Poisson's ratio not in (−1, 0.5].
    #[error(
        "invalid material: Young's modulus {young_pa} Pa must be finite and > 0, Poisson's ratio {poisson} must lie in (-1, 0.5]"
    )]
    InvalidMaterial { young_pa: f64, poisson: f64 },
    /// The normal force is negative or not finite.
    #[error("normal force {normal_force_n} N must be finite and >= 0")]
    InvalidNormalForce { normal_force_n: f64 },
    /// The eccentricity iteration failed (not expected for valid input; kept
    /// so that a failure is reported, never returned as a wrong ellipse).
    #[error(
        "Hertz eccentricity solve did not converge for curvature ratio {ratio} after {iterations} Newton steps (last step {last_step} in u = -ln(1 - e^2))"
    )]
    NoConvergence {
        ratio: f64,
        iterations: usize,
        last_step: f64,
    },
}

/// Elastic constants of wheel and rail (both bodies the same, docs/reference/07-contact-forces.md §7.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub young_pa: f64,
    /// Poisson's ratio ν (dimensionless).
    pub poisson: f64,
}

impl Default for Material {
    /// Steel, docs/reference/07-contact-forces.md §7.1: E = 210 GPa, ν = 0.3.
    fn default() -> Self {
        Material {
            young_pa: 210e9,
            poisson: 0.3,
        }
    }
}

impl Material {
    /// Shear modulus G = E / (2(1 + ν)) (Pa), docs/reference/07-contact-forces.md §7.1 (isotropic
    /// elasticity).
    pub fn shear_modulus_pa(&self) -> f64 {
        self.young_pa / (2.0 * (1.0 + self.poisson))
    }

    /// Checks E finite and > 0 (Pa) and −1 < ν ≤ 0.5 (the isotropic range;
    /// 1 − ν² > 0 is what the Hertz formulas need).
    pub fn validate(&self) -> Result<(), HertzError> {
        let ok = self.young_pa.is_finite()
            && self.young_pa > 0.0
            && self.poisson > -1.0
            && self.poisson <= 0.5;
        if ok {
            Ok(())
        } else {
            Err(HertzError::InvalidMaterial {
                young_pa: self.young_pa,
                poisson: self.poisson,
            })
        }
    }

    /// (1 − ν²) / E (1/Pa); 1/E* = 2(1 − ν²)/E for two equal bodies
    /// (Johnson 1985 §4.2).
    #[inline]
    fn compliance_1_pa(&self) -> f64 {
        (1.0 - self.poisson * self.poisson) / self.young_pa
    }
}

/// Which semi-axis of the contact ellipse is the major one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MajorAxis {
    /// A < B: the semi-axis `a` along the rolling direction is the major one.
    Rolling,
    /// A > B: the lateral semi-axis `b` is the major one.
    Lateral,
    /// A = B: a circle (e = 0).
    Circular,
}

/// The shape of the Hertz ellipse for given relative curvatures A, B
/// (`docs/reference/07-contact-forces.md` §7.1): everything that does not depend on the force or the material,
/// computed once by [`HertzShape::new`] (≈ 0.16 µs, no allocation). Fields are
/// private so that a shape is always a solved one; read them by the methods.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzShape {
    a_curv_1_m: f64,
    b_curv_1_m: f64,
    major: MajorAxis,
    e_sq: f64,
    one_minus_e_sq: f64,
    k_first: f64,
    e_second: f64,
    m_coef: f64,
    n_coef: f64,
    r_coef: f64,
}

/// Coefficients (ascending powers of s) of the rational fit of u/s, u =
/// −ln(1 − e²), s = ln(max/min), on 0 ≤ s ≤ [`FIT_S_MAX`]: numerator P …
const FIT_P: [f64; 7] = [
    1.333_333_331_648_508_3,
    0.450_562_498_245_999_14,
    0.192_219_901_038_756_9,
    0.057_765_874_152_473_11,
    0.009_380_828_246_123_235,
    0.001_652_194_958_947_642,
    8.010_777_713_348_549e-5,
];
/// … and denominator Q (Q(0) = 1, Q > 1 on the interval). Least-squares fit
/// with Lawson reweighting to 40-digit solutions of the ratio equation;
/// max relative error 1.43e-9.
const FIT_Q: [f64; 7] = [
    1.0,
    0.337_921_796_866_079_26,
    0.148_795_280_969_202,
    0.044_886_259_701_705_504,
    0.007_536_258_496_632_916,
    0.001_376_978_411_836_797_4,
    7.913_025_299_779_486e-5,
];
/// Upper end of the fit's interval in s = ln(max/min) (ratio ≈ 1.6e5).
const FIT_S_MAX: f64 = 12.0;
/// Newton stops once the step in u is ≤ this fraction of u; the error after
/// such a step is O(step²) ≲ 1e-17 u (module docs).
const STEP_TOL: f64 = 1e-8;
/// Newton steps before [`HertzError::NoConvergence`] (1 is the norm).
const MAX_NEWTON: usize = 12;

/// Initial u = −ln(1 − e²) for s = ln(max/min) > 0 (module docs), relative
/// error < 1.5e-9.
#[inline]
fn initial_u(s: f64) -> f64 {
    if s <= FIT_S_MAX {
        let mut p = FIT_P[6];
        let mut q = FIT_Q[6];
        for i in (0..6).rev() {
            p = p * s + FIT_P[i];
            q = q * s + FIT_Q[i];
        }
        s * p / q
    } else {
        // m_c = 1 − e² → 0, L = ln(4/√m_c) = ln 4 + u/2 (A&S 17.3.26, 17.3.36):
        // K ≈ L + m_c(L − 1)/4, E ≈ 1 + m_c(L − 1/2)/2, so
        // ln ρ ≈ u − ln(L − 1) − m_c(L/2 + 1/4) + m_c L/(4(L − 1)) + O(m_c² L²).
        let ln4 = 2.0 * LN_2;
        let mut u = s + (0.5 * s + ln4 - 1.0).ln();
        for _ in 0..2 {
            let l = ln4 + 0.5 * u;
            let mc = (-u).exp();
            let h = u - (l - 1.0).ln() - mc * (0.5 * l + 0.25) + mc * l / (4.0 * (l - 1.0)) - s;
            u -= h / (1.0 - 0.5 / (l - 1.0));
        }
        u
    }
}

impl HertzShape {
    /// Solves the ellipse shape for relative curvatures A (rolling direction)
    /// and B (lateral), both in 1/m (module docs).
    ///
    /// Errors: non-finite input ([`HertzError::NonFiniteCurvature`]), A ≤ 0 or
    /// B ≤ 0 ([`HertzError::NonHertzian`]), max/min >
    /// [`MAX_CURVATURE_RATIO`].
    pub fn new(a_curv_1_m: f64, b_curv_1_m: f64) -> Result<HertzShape, HertzError> {
        let sum = a_curv_1_m + b_curv_1_m;
        if !(a_curv_1_m.is_finite() && b_curv_1_m.is_finite() && sum.is_finite()) {
            return Err(HertzError::NonFiniteCurvature {
                a_curv_1_m,
                b_curv_1_m,
            });
        }
        if !(a_curv_1_m > 0.0 && b_curv_1_m > 0.0) {
            return Err(HertzError::NonHertzian {
                a_curv_1_m,
                b_curv_1_m,
            });
        }
        let (major, lo, hi) = if a_curv_1_m < b_curv_1_m {
            (MajorAxis::Rolling, a_curv_1_m, b_curv_1_m)
        } else if a_curv_1_m > b_curv_1_m {
            (MajorAxis::Lateral, b_curv_1_m, a_curv_1_m)
        } else {
            // The circle: e = 0, K = E = π/2, m = n = r = 1 exactly.
            return Ok(HertzShape {
                a_curv_1_m,
                b_curv_1_m,
                major: MajorAxis::Circular,
                e_sq: 0.0,
                one_minus_e_sq: 1.0,
                k_first: FRAC_PI_2,
                e_second: FRAC_PI_2,
                m_coef: 1.0,
                n_coef: 1.0,
                r_coef: 1.0,
            });
        };
        let ratio = hi / lo;
        if ratio > MAX_CURVATURE_RATIO {
            return Err(HertzError::CurvatureRatioOutOfRange {
                a_curv_1_m,
                b_curv_1_m,
                ratio,
                max_ratio: MAX_CURVATURE_RATIO,
            });
        }
        // s = ln(hi/lo) without rounding hi/lo first: hi − lo is exact when
        // the two are within a factor 2, which is where s is small.
        let s = ((hi - lo) / lo).ln_1p();
        let Solved {
            e_sq,
            one_minus_e_sq,
            k_first,
            e_second,
        } = solve_u(s, ratio)?;
        // docs/reference/07-contact-forces.md §7.1: m = (2E/(π(1 − e²)))^(1/3), n = m√(1 − e²), r = 2K/(π m).
        let m_coef = (2.0 * e_second / (PI * one_minus_e_sq)).cbrt();
        let n_coef = m_coef * one_minus_e_sq.sqrt();
        let r_coef = 2.0 * k_first / (PI * m_coef);
        Ok(HertzShape {
            a_curv_1_m,
            b_curv_1_m,
            major,
            e_sq,
            one_minus_e_sq,
            k_first,
            e_second,
            m_coef,
            n_coef,
            r_coef,
        })
    }

    /// Relative curvature A in the rolling direction (1/m), as given.
    pub fn a_curv_1_m(&self) -> f64 {
        self.a_curv_1_m
    }
    /// Relative curvature B in the lateral direction (1/m), as given.
    pub fn b_curv_1_m(&self) -> f64 {
        self.b_curv_1_m
    }
    /// θ = acos(|B − A|/(A + B)) (rad), in (0, π/2]; π/2 for the circle
    /// (docs/reference/07-contact-forces.md §7.1). Evaluated as the identical 2·atan(√(min/max)) (with
    /// q = min/max, cos θ = (1 − q)/(1 + q), so tan²(θ/2) = q), which keeps
    /// full precision for small θ, where acos of a rounded argument near 1
    /// loses half the digits. Computed on request (no other output needs it).
    pub fn theta_rad(&self) -> f64 {
        let (a, b) = (self.a_curv_1_m, self.b_curv_1_m);
        2.0 * (a.min(b) / a.max(b)).sqrt().atan()
    }
    /// Which semi-axis is the major one (along the smaller curvature).
    pub fn major_axis(&self) -> MajorAxis {
        self.major
    }
    /// Eccentricity e = √(1 − (minor/major)²) (dimensionless), 0 for the
    /// circle.
    pub fn eccentricity(&self) -> f64 {
        self.e_sq.sqrt()
    }
    /// e² (dimensionless), the parameter of K(e), E(e); accurate to full
    /// relative precision even for a nearly circular ellipse.
    pub fn eccentricity_sq(&self) -> f64 {
        self.e_sq
    }
    /// 1 − e² = (minor/major)² (dimensionless); accurate to full relative
    /// precision even for a very elongated ellipse.
    pub fn one_minus_eccentricity_sq(&self) -> f64 {
        self.one_minus_e_sq
    }
    /// minor/major semi-axis ratio n/m = √(1 − e²) (dimensionless), in (0, 1].
    pub fn axis_ratio(&self) -> f64 {
        self.n_coef / self.m_coef
    }
    /// K(e): complete elliptic integral of the first kind, parameter e².
    pub fn elliptic_k(&self) -> f64 {
        self.k_first
    }
    /// E(e): complete elliptic integral of the second kind, parameter e².
    pub fn elliptic_e(&self) -> f64 {
        self.e_second
    }
    /// Hertz coefficient m = (2E(e)/(π(1 − e²)))^(1/3) (dimensionless, ≥ 1).
    pub fn m_coef(&self) -> f64 {
        self.m_coef
    }
    /// Hertz coefficient n = m √(1 − e²) (dimensionless, ≤ 1).
    pub fn n_coef(&self) -> f64 {
        self.n_coef
    }
    /// Hertz coefficient r = 2K(e)/(π m) (dimensionless).
    pub fn r_coef(&self) -> f64 {
        self.r_coef
    }

    /// Hertz normal stiffness K_H = 2E / (3(1 − ν²) r^1.5 √(A + B))
    /// (N/m^1.5), so that N = K_H δ^1.5 (docs/reference/07-contact-forces.md §7.1). Hot path: the material
    /// is not validated here (see [`Material::validate`], [`HertzContact`]).
    #[inline]
    pub fn stiffness_n_m15(&self, material: &Material) -> f64 {
        let sum = self.a_curv_1_m + self.b_curv_1_m;
        2.0 / (3.0 * material.compliance_1_pa() * self.r_coef * (self.r_coef * sum).sqrt())
    }

    /// Semi-axes (a along the rolling direction, b lateral) (m) for the normal
    /// force N (N): major = m c, minor = n c, c = [3N(1 − ν²)/(2E(A + B))]^(1/3)
    /// (docs/reference/07-contact-forces.md §7.1). Hot path: N ≥ 0 and the material are not checked (a
    /// negative N gives negative semi-axes; use [`HertzContact::new`] for
    /// checked input).
    #[inline]
    pub fn semi_axes_m(&self, normal_force_n: f64, material: &Material) -> (f64, f64) {
        self.semi_axes_for_scale(self.scale_m(normal_force_n, material))
    }

    /// Normal approach δ (m) of the two bodies under N (N):
    /// δ = r [(1.5(1 − ν²)/E)² (A + B) N²]^(1/3) (docs/reference/07-contact-forces.md §7.1; for the sphere
    /// it is Johnson's δ = a²/R, 1985 §4.2), computed as r (A + B) c² from
    /// the semi-axes' scale c (the same quantity: c³ (A + B) = 1.5(1 −
    /// ν²)N/E), so that [`HertzContact`] takes one cube root for both.
    /// Hot path: inputs not checked (c² makes the sign of N irrelevant
    /// here).
    #[inline]
    pub fn approach_m(&self, normal_force_n: f64, material: &Material) -> f64 {
        self.approach_for_scale(self.scale_m(normal_force_n, material))
    }

    /// The semi-axes' scale c = [3N(1 − ν²)/(2E(A + B))]^(1/3) (m).
    #[inline]
    fn scale_m(&self, normal_force_n: f64, material: &Material) -> f64 {
        let sum = self.a_curv_1_m + self.b_curv_1_m;
        (1.5 * normal_force_n * material.compliance_1_pa() / sum).cbrt()
    }

    /// (a rolling, b lateral) (m) for the scale `c_m`: major m c, minor n c.
    #[inline]
    fn semi_axes_for_scale(&self, c_m: f64) -> (f64, f64) {
        let (major_m, minor_m) = (self.m_coef * c_m, self.n_coef * c_m);
        match self.major {
            MajorAxis::Rolling | MajorAxis::Circular => (major_m, minor_m),
            MajorAxis::Lateral => (minor_m, major_m),
        }
    }

    /// δ = r (A + B) c² (m) for the scale `c_m`.
    #[inline]
    fn approach_for_scale(&self, c_m: f64) -> f64 {
        self.r_coef * (self.a_curv_1_m + self.b_curv_1_m) * c_m * c_m
    }
}

/// e² = 1 − e^(−u) and 1 − e² = e^(−u), each to full relative precision:
/// `expm1` only where 1 − e^(−u) would cancel (u < ln 2, i.e. e² < 1/2).
#[inline]
fn e_sq_pair(u: f64) -> (f64, f64) {
    if u < LN_2 {
        (-(-u).exp_m1(), (-u).exp())
    } else {
        let mc = (-u).exp();
        (1.0 - mc, mc)
    }
}

/// Solution of the eccentricity equation: e², 1 − e², K(e), E(e).
struct Solved {
    e_sq: f64,
    one_minus_e_sq: f64,
    k_first: f64,
    e_second: f64,
}

/// Newton on g(u) = ln ρ(u) − s, u = −ln(1 − e²) (module docs).
#[inline]
fn solve_u(s: f64, ratio: f64) -> Result<Solved, HertzError> {
    let mut u = initial_u(s);
    let mut last_step = f64::NAN;
    for _ in 0..MAX_NEWTON {
        let (m, mc) = e_sq_pair(u);
        let agm = agm_sums(m, mc);
        let sigma = agm.sigma;
        let s1 = agm.s1;
        let d = 0.5 * m - s1; // (E − (1 − e²)K)/K
        let (ln_rho, slope) = if m < 0.5 {
            let rho_m1 = (0.5 * m * m - (2.0 - m) * s1) / (mc * sigma);
            let slope = 1.0 + (2.0 * s1 - sigma * sigma) / (2.0 * sigma * d);
            (rho_m1.ln_1p(), slope)
        } else {
            let slope = 1.0 + mc / (2.0 * d) - (1.0 - sigma) / (2.0 * sigma);
            ((d / sigma).ln() + u, slope)
        };
        let step = -(ln_rho - s) / slope;
        if !step.is_finite() {
            break;
        }
        last_step = step;
        if step.abs() <= STEP_TOL * u {
            // First-order Taylor transport of K, E to u + step (module docs).
            let k = agm.k_first;
            let e = k * (1.0 - sigma);
            let dk_du = k * d / (2.0 * m);
            let de_du = -mc * k * sigma / (2.0 * m);
            // e² and 1 − e² at u + step: 1 − e^(−step) = step(1 − step/2) to
            // O(step³) ≤ 1e-24 u³ (no second exp).
            let de_sq = mc * step * (1.0 - 0.5 * step);
            return Ok(Solved {
                e_sq: m + de_sq,
                one_minus_e_sq: mc - de_sq,
                k_first: k + dk_du * step,
                e_second: e + de_du * step,
            });
        }
        // The root is > 0; never step to u ≤ 0 (ρ(0) = 1 < ratio).
        u = if u + step > 0.0 { u + step } else { 0.5 * u };
    }
    Err(HertzError::NoConvergence {
        ratio,
        iterations: MAX_NEWTON,
        last_step,
    })
}

/// One Hertz contact solved for a normal force: the shape and everything
/// that depends on N and the material (docs/reference/07-contact-forces.md §7.1). Plain output data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzContact {
    /// Shape of the ellipse (e, m, n, r, θ, major axis).
    pub shape: HertzShape,
    /// Normal force N (N) the contact was solved for.
    pub normal_force_n: f64,
    /// Semi-axis along the rolling direction, `a` (m).
    pub a_rolling_m: f64,
    /// Semi-axis along the lateral direction, `b` (m).
    pub b_lateral_m: f64,
    /// Normal approach δ (m).
    pub approach_m: f64,
    /// Hertz stiffness K_H (N/m^1.5), N = K_H δ^1.5.
    pub stiffness_n_m15: f64,
}

impl HertzContact {
    /// Solves the shape for A, B (1/m) and evaluates it at the normal force
    /// N (N) and `material`, with every input checked.
    pub fn new(
        a_curv_1_m: f64,
        b_curv_1_m: f64,
        normal_force_n: f64,
        material: &Material,
    ) -> Result<HertzContact, HertzError> {
        let shape = HertzShape::new(a_curv_1_m, b_curv_1_m)?;
        HertzContact::from_shape(&shape, normal_force_n, material)
    }

    /// Evaluates an already solved shape at the normal force N (N) (finite,
    /// ≥ 0) and `material` (validated).
    pub fn from_shape(
        shape: &HertzShape,
        normal_force_n: f64,
        material: &Material,
    ) -> Result<HertzContact, HertzError> {
        material.validate()?;
        if !(normal_force_n.is_finite() && normal_force_n >= 0.0) {
            return Err(HertzError::InvalidNormalForce { normal_force_n });
        }
        let c_m = shape.scale_m(normal_force_n, material);
        let (a_rolling_m, b_lateral_m) = shape.semi_axes_for_scale(c_m);
        Ok(HertzContact {
            shape: *shape,
            normal_force_n,
            a_rolling_m,
            b_lateral_m,
            approach_m: shape.approach_for_scale(c_m),
            stiffness_n_m15: shape.stiffness_n_m15(material),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::elliptic::{ellipke_m, ellipke_mc};

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    /// Sphere of radius R on a plane: A = B = 1/(2R) (docs/reference/07-contact-forces.md §7.1). Johnson
    /// 1985 §4.2: a = (3NR/(4E*))^(1/3), δ = a²/R, N = (4/3) E* √R δ^1.5,
    /// 1/E* = 2(1 − ν²)/E.
    #[test]
    fn sphere_on_plane_matches_johnson() {
        let mat = Material::default();
        let e_star = mat.young_pa / (2.0 * (1.0 - mat.poisson * mat.poisson));
        for radius_m in [0.005, 0.46, 3.0] {
            let curv = 0.5 / radius_m;
            let shape = HertzShape::new(curv, curv).unwrap();
            assert_eq!(shape.eccentricity(), 0.0);
            assert_eq!(shape.major_axis(), MajorAxis::Circular);
            assert_eq!(shape.theta_rad(), FRAC_PI_2);
            for v in [shape.m_coef(), shape.n_coef(), shape.r_coef()] {
                assert!((v - 1.0).abs() <= 1e-14, "{v}");
            }
            let k = shape.stiffness_n_m15(&mat);
            assert!(rel(k, 4.0 / 3.0 * e_star * radius_m.sqrt()) < 1e-14);
            for force_n in [1.0, 1e4, 1.2e5] {
                let (a, b) = shape.semi_axes_m(force_n, &mat);
                let a_johnson = (3.0 * force_n * radius_m / (4.0 * e_star)).cbrt();
                assert_eq!(a, b);
                assert!(rel(a, a_johnson) < 1e-14);
                let delta = shape.approach_m(force_n, &mat);
                assert!(rel(delta, a_johnson * a_johnson / radius_m) < 1e-14);
                // N = K δ^1.5 round trip.
                assert!(rel(k * delta.powf(1.5), force_n) < 1e-14);
            }
        }
    }

    /// Approach and stiffness are consistent (N = K δ^1.5) for elliptical
    /// contacts too, and the semi-axes scale as N^(1/3), δ as N^(2/3).
    #[test]
    fn force_approach_round_trip_and_scaling() {
        let mat = Material {
            young_pa: 205e9,
            poisson: 0.28,
        };
        for (a_curv, b_curv) in [(1.087, 6.25), (1.087, 0.2), (3.0, 1e3), (1.0, 1.0 + 1e-9)] {
            let shape = HertzShape::new(a_curv, b_curv).unwrap();
            let k = shape.stiffness_n_m15(&mat);
            let (a1, b1) = shape.semi_axes_m(1e3, &mat);
            let d1 = shape.approach_m(1e3, &mat);
            for force_n in [0.1, 50e3, 2e5] {
                let delta = shape.approach_m(force_n, &mat);
                assert!(rel(k * delta.powf(1.5), force_n) < 1e-13);
                let scale = (force_n / 1e3).cbrt();
                let (a, b) = shape.semi_axes_m(force_n, &mat);
                assert!(rel(a, a1 * scale) < 1e-14 && rel(b, b1 * scale) < 1e-14);
                assert!(rel(delta, d1 * scale * scale) < 1e-14);
            }
            // Semi-axes: major = m c, minor = n c along the smaller curvature.
            let (a, b) = shape.semi_axes_m(1e4, &mat);
            assert_eq!(a > b, a_curv < b_curv);
            assert!(rel(a.min(b) / a.max(b), shape.axis_ratio()) < 1e-14);
        }
    }

    /// The solution satisfies the ratio equation of docs/reference/07-contact-forces.md §7.1 when K, E are
    /// recomputed independently with `ellipke_m(e²)` (for ratios where the
    /// naive formula is well conditioned).
    #[test]
    fn solves_the_ratio_equation() {
        for ratio in [1.1, 1.5, 2.0, 3.0, 7.5, 13.93, 100.0, 1e3, 1e4, 1e6] {
            let shape = HertzShape::new(2.0, 2.0 * ratio).unwrap();
            let m = shape.eccentricity_sq();
            let mc = shape.one_minus_eccentricity_sq();
            assert!((m + mc - 1.0).abs() <= 2.0 * f64::EPSILON);
            // Evaluate K, E from the accurately known one of e², 1 − e².
            let ke = if m < 0.5 {
                ellipke_m(m).unwrap()
            } else {
                ellipke_mc(mc).unwrap()
            };
            assert!(rel(shape.elliptic_k(), ke.k_first) < 1e-14);
            assert!(rel(shape.elliptic_e(), ke.e_second) < 1e-14);
            let lhs = (ke.e_second / mc - ke.k_first) / (ke.k_first - ke.e_second);
            assert!(rel(lhs, ratio) < 1e-12, "ratio {ratio}: {lhs}");
        }
    }

    /// Nearly circular, ρ = 1 + ε: e² = (4/3)ε − (14/9)ε² + O(ε³) (series
    /// inversion of the ratio equation with the K, E series of A&S
    /// 17.3.11–17.3.12; checked against 50-digit mpmath, next coefficient
    /// +31/18), resolved to full relative precision down to ε = 2⁻⁵²;
    /// m, n, r → 1 continuously.
    #[test]
    fn nearly_circular_is_continuous() {
        for eps in [f64::EPSILON, 1e-14, 1e-11, 1e-8, 1e-5] {
            let b_curv = 1.0 + eps;
            let eps = b_curv - 1.0; // the ε actually represented (exact)
            let shape = HertzShape::new(1.0, b_curv).unwrap();
            assert_eq!(shape.major_axis(), MajorAxis::Rolling);
            let e_sq_series = 4.0 / 3.0 * eps - 14.0 / 9.0 * eps * eps;
            let err = rel(shape.eccentricity_sq(), e_sq_series);
            assert!(err < 2.0 * eps * eps + 5e-16, "eps {eps}: {err:e}");
            for v in [shape.m_coef(), shape.n_coef(), shape.r_coef()] {
                assert!((v - 1.0).abs() < 2.0 * eps + 1e-15, "eps {eps}: {v}");
            }
        }
    }

    /// Swapping A and B swaps the semi-axes and keeps everything else.
    #[test]
    fn swapping_curvatures_swaps_axes() {
        let mat = Material::default();
        for (p, q) in [(1.0, 2.0), (0.8, 50.0), (7.0, 7.000_001), (1e-3, 1e5)] {
            let s1 = HertzShape::new(p, q).unwrap();
            let s2 = HertzShape::new(q, p).unwrap();
            assert_eq!(s1.major_axis(), MajorAxis::Rolling);
            assert_eq!(s2.major_axis(), MajorAxis::Lateral);
            assert_eq!(s1.eccentricity_sq(), s2.eccentricity_sq());
            assert_eq!(s1.m_coef(), s2.m_coef());
            assert_eq!(s1.n_coef(), s2.n_coef());
            assert_eq!(s1.r_coef(), s2.r_coef());
            assert_eq!(s1.theta_rad(), s2.theta_rad());
            let (a1, b1) = s1.semi_axes_m(9e4, &mat);
            let (a2, b2) = s2.semi_axes_m(9e4, &mat);
            assert_eq!((a1, b1), (b2, a2));
            assert_eq!(s1.approach_m(9e4, &mat), s2.approach_m(9e4, &mat));
            assert_eq!(s1.stiffness_n_m15(&mat), s2.stiffness_n_m15(&mat));
        }
    }

    /// The shape depends only on B/A: scaling both curvatures by λ keeps
    /// e, m, n, r (the semi-axes scale as λ^(−1/3), docs/reference/07-contact-forces.md §7.1 c ∝ (A+B)^(−1/3)).
    #[test]
    fn shape_depends_on_the_ratio_only() {
        let mat = Material::default();
        let base = HertzShape::new(1.3, 4.1).unwrap();
        let (a0, b0) = base.semi_axes_m(1e4, &mat);
        for lambda in [1e-3, 0.5, 3.0, 1e4] {
            let s = HertzShape::new(1.3 * lambda, 4.1 * lambda).unwrap();
            assert!(rel(s.eccentricity_sq(), base.eccentricity_sq()) < 1e-14);
            assert!(rel(s.m_coef(), base.m_coef()) < 1e-14);
            assert!(rel(s.r_coef(), base.r_coef()) < 1e-14);
            let (a, b) = s.semi_axes_m(1e4, &mat);
            let scale = lambda.cbrt().recip();
            assert!(rel(a, a0 * scale) < 1e-14 && rel(b, b0 * scale) < 1e-14);
        }
    }

    /// As the ellipse elongates (ratio up, θ down): e and m increase, n, r
    /// and θ decrease, strictly — over the whole range, across every branch
    /// switch of the solver (e² = 1/2, u = ln 2, s = 12).
    #[test]
    fn monotone_in_the_curvature_ratio() {
        let mut prev = HertzShape::new(1.0, 1.0).unwrap();
        let mut ratio = 1.0_f64;
        while ratio < MAX_CURVATURE_RATIO {
            ratio = (ratio * 1.003 + 1e-9).min(MAX_CURVATURE_RATIO);
            let s = HertzShape::new(1.0, ratio).unwrap();
            assert!(
                s.eccentricity_sq() > prev.eccentricity_sq(),
                "ratio {ratio}"
            );
            assert!(s.m_coef() > prev.m_coef(), "ratio {ratio}");
            assert!(s.n_coef() < prev.n_coef(), "ratio {ratio}");
            assert!(s.r_coef() < prev.r_coef(), "ratio {ratio}");
            assert!(s.theta_rad() < prev.theta_rad(), "ratio {ratio}");
            prev = s;
        }
    }

    /// Each solver branch agrees with its neighbour at the switch: the
    /// ratios where e² = 1/2 (ρ ≈ 1.68), u = ln 2 (the same point) and
    /// s = ln ρ = 12 (fit → asymptotic initial guess). A jump would show as
    /// a relative change far above the 1e-12 the tiny ratio step explains.
    #[test]
    fn branch_switches_are_seamless() {
        let switch_ratios = [
            {
                let ke = ellipke_m(0.5).unwrap();
                (ke.e_second / 0.5 - ke.k_first) / (ke.k_first - ke.e_second)
            },
            FIT_S_MAX.exp(),
        ];
        for r in switch_ratios {
            let below = HertzShape::new(1.0, r * (1.0 - 1e-13)).unwrap();
            let above = HertzShape::new(1.0, r * (1.0 + 1e-13)).unwrap();
            for (x, y) in [
                (below.eccentricity_sq(), above.eccentricity_sq()),
                (
                    below.one_minus_eccentricity_sq(),
                    above.one_minus_eccentricity_sq(),
                ),
                (below.m_coef(), above.m_coef()),
                (below.r_coef(), above.r_coef()),
                (below.elliptic_k(), above.elliptic_k()),
                (below.elliptic_e(), above.elliptic_e()),
            ] {
                assert!(rel(x, y) < 1e-12, "at ratio {r}: {x} vs {y}");
            }
        }
    }

    #[test]
    fn theta_is_acos_of_the_curvature_difference() {
        // A = 3B: |B − A|/(A + B) = 1/2, θ = 60°.
        let s = HertzShape::new(3.0, 1.0).unwrap();
        assert!((s.theta_rad() - PI / 3.0).abs() < 1e-15);
        // The reference form (docs/reference/07-contact-forces.md §7.1) itself, where it is well conditioned.
        for (a, b) in [(1.0, 1.5), (2.0, 0.3), (0.7, 9.0)] {
            let theta = HertzShape::new(a, b).unwrap().theta_rad();
            let spec = (f64::abs(b - a) / (a + b)).acos();
            assert!((theta - spec).abs() < 1e-15, "{a}, {b}");
        }
        // Small θ: θ ≈ 2√(min/max) to O(θ³).
        let s = HertzShape::new(1.0, 1e12).unwrap();
        assert!(rel(s.theta_rad(), 2e-6) < 1e-12);
    }

    #[test]
    fn non_hertzian_geometry_is_reported() {
        for (a, b) in [
            (0.0, 1.0),
            (1.0, 0.0),
            (-0.5, 2.0),
            (2.0, -1e-12),
            (-1.0, -1.0),
            (-0.0, 1.0),
        ] {
            assert_eq!(
                HertzShape::new(a, b),
                Err(HertzError::NonHertzian {
                    a_curv_1_m: a,
                    b_curv_1_m: b
                })
            );
        }
        for (a, b) in [
            (f64::NAN, 1.0),
            (1.0, f64::INFINITY),
            (f64::NEG_INFINITY, 1.0),
            (f64::MAX, f64::MAX),
        ] {
            assert!(
                matches!(
                    HertzShape::new(a, b),
                    Err(HertzError::NonFiniteCurvature { .. })
                ),
                "{a}, {b}"
            );
        }
        let err = HertzShape::new(1e-13, 1.0).unwrap_err();
        assert!(matches!(err, HertzError::CurvatureRatioOutOfRange { ratio, .. } if ratio > 1e12));
        assert!(HertzShape::new(1.0, MAX_CURVATURE_RATIO).is_ok());
        // The message names the values and units.
        let msg = HertzShape::new(-0.5, 2.0).unwrap_err().to_string();
        assert!(msg.contains("-0.5 1/m") && msg.contains("2 1/m"), "{msg}");
    }

    #[test]
    fn checked_contact_validates_force_and_material() {
        let mat = Material::default();
        let c = HertzContact::new(1.087, 6.25, 1e5, &mat).unwrap();
        let (a, b) = c.shape.semi_axes_m(1e5, &mat);
        assert_eq!((c.a_rolling_m, c.b_lateral_m), (a, b));
        assert_eq!(c.approach_m, c.shape.approach_m(1e5, &mat));
        assert_eq!(c.stiffness_n_m15, c.shape.stiffness_n_m15(&mat));
        let zero = HertzContact::new(1.087, 6.25, 0.0, &mat).unwrap();
        assert_eq!(
            (zero.a_rolling_m, zero.b_lateral_m, zero.approach_m),
            (0.0, 0.0, 0.0)
        );
        for n in [-1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                HertzContact::new(1.0, 2.0, n, &mat),
                Err(HertzError::InvalidNormalForce { .. })
            ));
        }
        for (young_pa, poisson) in [
            (0.0, 0.3),
            (-2e11, 0.3),
            (f64::NAN, 0.3),
            (2e11, 0.6),
            (2e11, -1.0),
            (2e11, f64::NAN),
        ] {
            let bad = Material { young_pa, poisson };
            match HertzContact::new(1.0, 2.0, 1e4, &bad) {
                Err(HertzError::InvalidMaterial {
                    young_pa: y,
                    poisson: p,
                }) => {
                    assert!(y.to_bits() == young_pa.to_bits() && p.to_bits() == poisson.to_bits())
                }
                other => panic!("{young_pa}, {poisson}: {other:?}"),
            }
        }
        assert_eq!(
            HertzContact::new(-1.0, 2.0, 1e4, &mat),
            Err(HertzError::NonHertzian {
                a_curv_1_m: -1.0,
                b_curv_1_m: 2.0
            })
        );
    }

    #[test]
    fn default_material_is_steel() {
        let m = Material::default();
        assert_eq!((m.young_pa, m.poisson), (210e9, 0.3));
        assert!(rel(m.shear_modulus_pa(), 210e9 / 2.6) < 1e-15);
        assert!(m.validate().is_ok());
    }
}
