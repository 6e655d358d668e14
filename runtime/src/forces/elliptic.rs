//! Complete elliptic integrals of the first and second kind, K and E.
//!
//! # Argument convention: the parameter m = k²
//!
//! Every function here takes the **parameter** `m = k²` (k the modulus), or
//! its complement `m_c = 1 − m = k′²`, never the modulus k itself; the
//! convention is in each function's name (`_m`, `_mc`). It is the convention of
//! Abramowitz & Stegun ch. 17 (A&S 17.3.1, 17.3.3) and of SciPy's
//! `scipy.special.ellipk(m)` / `ellipe(m)`:
//!
//! ```text
//! K(m) = ∫₀^{π/2} dθ / √(1 − m sin²θ),    E(m) = ∫₀^{π/2} √(1 − m sin²θ) dθ.
//! ```
//!
//! (In the Hertz problem, docs/reference/07-contact-forces.md §7.1, the "K(e), E(e)" of the eccentricity e are
//! K and E of the parameter m = e².)
//!
//! # Domain
//!
//! Finite m ≤ 1 (negative m included, down to −f64::MAX: both integrals are
//! real there). At m = 1, K has a logarithmic singularity:
//! [`ellipk_m`]`(1.0)` returns `Ok(f64::INFINITY)` and [`ellipe_m`]`(1.0)`
//! returns `Ok(1.0)` (the integrands at m = 1 are 1/cos θ, not integrable,
//! and cos θ). m > 1, NaN and ±∞ are [`EllipticError`]s.
//!
//! # Method: the arithmetic–geometric mean
//!
//! A&S §17.6 and DLMF §19.8(i) (eqs. 19.8.1–19.8.5): with
//!
//! ```text
//! a₀ = 1, b₀ = √m_c, c₀² = m;  a_{n+1} = (aₙ + bₙ)/2,  b_{n+1} = √(aₙ bₙ),
//! c_{n+1} = cₙ² / (4 a_{n+1})         (= (aₙ − bₙ)/2, DLMF 19.8.3)
//! K = π / (2 M),  M = lim aₙ;        (K − E) / K = Σ_{n≥0} 2^{n−1} cₙ² =: Σ
//! ```
//!
//! so E = K (1 − Σ) (for m > 1/2, where 1 − Σ cancels, E comes from
//! Legendre's relation instead: see `complete`). The recurrence c_{n+1} = cₙ²/(4a_{n+1}) (rather than the
//! difference (aₙ − bₙ)/2) keeps every cₙ to full *relative* precision, so Σ,
//! a sum of positive terms for 0 ≤ m < 1, and therefore K − E = K Σ are exact
//! to a few ulps even for tiny m — the Hertz eccentricity solve
//! ([`crate::forces::hertz`]) depends on that. Convergence is quadratic: 4
//! iterations at m = 0.5, 5 up to m = 0.99, 7 at m = 1 − 10⁻⁶, 8 at
//! m = 1 − 10⁻¹², 12 for the smallest m_c > 0.
//!
//! Accuracy (tests/hertz_reference.rs, against SciPy and 40-digit mpmath
//! values of the same binary m): K and E to a few ulps, relative error
//! < 4e-16 measured for m ∈ [−10³, 1 − 10⁻⁶] and for m_c = 1 − m down to
//! 1e-300 (tests here: tiny m, m → 1, m → −∞, Legendre's relation). About
//! 20 ns per call (two AGM runs for m > 1/2).

use std::f64::consts::FRAC_PI_2;

/// Why a complete elliptic integral could not be evaluated.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum EllipticError {
    /// The parameter m = k² is not a finite number ≤ 1.
    #[error(
        "elliptic parameter m = {m} is outside the domain of the real complete integrals (finite m ≤ 1)"
    )]
    ParameterOutOfDomain { m: f64 },
    /// The complementary parameter m_c = 1 − m is not a finite number ≥ 0.
    #[error(
        "complementary elliptic parameter m_c = 1 − m = {mc} is outside the domain (finite m_c ≥ 0)"
    )]
    ComplementaryOutOfDomain { mc: f64 },
}

/// K(m) and E(m) of one parameter m (module docs for the convention).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompleteElliptic {
    /// K(m), complete integral of the first kind (dimensionless); +∞ at m = 1.
    pub k_first: f64,
    /// E(m), complete integral of the second kind (dimensionless).
    pub e_second: f64,
}

/// Complete elliptic integral of the first kind K(m), parameter m = k²
/// (A&S 17.3.1; SciPy `ellipk(m)`). `K(1) = +∞`; m > 1 or non-finite m is an
/// error.
pub fn ellipk_m(m: f64) -> Result<f64, EllipticError> {
    ellipke_m(m).map(|v| v.k_first)
}

/// Complete elliptic integral of the second kind E(m), parameter m = k²
/// (A&S 17.3.3; SciPy `ellipe(m)`). `E(1) = 1`; m > 1 or non-finite m is an
/// error.
pub fn ellipe_m(m: f64) -> Result<f64, EllipticError> {
    ellipke_m(m).map(|v| v.e_second)
}

/// K(m) and E(m) together (one AGM run gives both), parameter m = k².
pub fn ellipke_m(m: f64) -> Result<CompleteElliptic, EllipticError> {
    let mc = 1.0 - m;
    if !(m <= 1.0 && m.is_finite() && mc.is_finite()) {
        return Err(EllipticError::ParameterOutOfDomain { m });
    }
    Ok(complete(m, mc))
}

/// K and E as functions of the **complementary** parameter m_c = 1 − m = k′²
/// (finite m_c ≥ 0; m_c = 0 gives K = +∞, E = 1). Use it when m_c is the
/// quantity known accurately (m near 1, e.g. a very elongated Hertz ellipse,
/// where m_c = (b/a)²): K(1 − m_c) is then exact to a few ulps, whereas
/// forming m = 1 − m_c first would lose the low digits of m_c.
pub fn ellipke_mc(mc: f64) -> Result<CompleteElliptic, EllipticError> {
    if !(mc >= 0.0 && mc.is_finite()) {
        return Err(EllipticError::ComplementaryOutOfDomain { mc });
    }
    Ok(complete(1.0 - mc, mc))
}

/// K(m) and E(m) for m ≤ 1 with m + m_c = 1 (both given, see [`agm_sums`]).
///
/// For m ≤ 1/2 one AGM run: E = K (1 − Σ). For m > 1/2 the difference
/// 1 − Σ cancels more and more (Σ → 1 as m → 1), so E is taken from
/// Legendre's relation E K′ + E′ K − K K′ = π/2 (DLMF 19.7.1) instead, with
/// K′ = K(m_c), E′ = E(m_c) from a second AGM run at the complementary
/// parameter and K′ − E′ = K′ Σ′:
///
/// ```text
/// E = (π/2 + K (K′ − E′)) / K′ = π/(2K′) + K Σ′,
/// ```
///
/// a sum of two positive terms, exact to a few ulps up to m = 1.
///
/// m < 0 is mapped into (0, 1) first by the negative-parameter (imaginary
/// modulus) transformation (A&S 17.4.17–17.4.18, DLMF §19.7(ii)):
/// K(m) = K(m′)/√(1 − m), E(m) = √(1 − m) E(m′), m′ = −m/(1 − m), so that
/// no sum cancels for large |m| either.
#[inline]
fn complete(m: f64, mc: f64) -> CompleteElliptic {
    if m < 0.0 {
        // m′ = −m/(1 − m) ∈ (0, 1), m′_c = 1/(1 − m); both without cancellation.
        let t = complete(-m / mc, 1.0 / mc);
        let root = mc.sqrt();
        return CompleteElliptic {
            k_first: t.k_first / root,
            e_second: t.e_second * root,
        };
    }
    let s = agm_sums(m, mc);
    if s.k_first.is_infinite() {
        // m = 1: E(1) = ∫₀^{π/2} cos θ dθ = 1; K(1) = +∞.
        return CompleteElliptic {
            k_first: f64::INFINITY,
            e_second: 1.0,
        };
    }
    let e_second = if m <= 0.5 {
        s.k_first * (1.0 - s.sigma)
    } else {
        let c = agm_sums(mc, m); // K′, Σ′ of the complementary parameter
        FRAC_PI_2 / c.k_first + s.k_first * c.sigma
    };
    CompleteElliptic {
        k_first: s.k_first,
        e_second,
    }
}

/// Output of one AGM run (module docs), for callers that need the sums
/// themselves ([`crate::forces::hertz`] solves its eccentricity equation with them,
/// free of the cancellation in K − E and E − m_c K).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AgmSums {
    /// K(m) = π / (2 M(1, √m_c)); +∞ when m_c = 0.
    pub k_first: f64,
    /// Σ = Σ_{n≥0} 2^{n−1} cₙ² = (K − E)/K.
    pub sigma: f64,
    /// S₁ = Σ_{n≥1} 2^{n−1} cₙ² = Σ − m/2 (positive for m ≠ 0).
    pub s1: f64,
}

/// Iteration cap of the AGM; never reached for finite m_c > 0 (12 iterations
/// suffice down to m_c = 2⁻¹⁰²², and the loop ends on its tolerance).
const AGM_MAX_ITER: usize = 64;
/// The AGM stops once |cₙ| ≤ `AGM_TOL` · aₙ. Then a_{n} − b_{n} = 2 c_{n+1}
/// ≈ cₙ²/(2aₙ) ≤ 2e-18 aₙ, so aₙ is the mean M to within rounding, and the
/// next term 2ⁿ c_{n+1}² of Σ is below 1e-36 · 2ⁿ.
const AGM_TOL: f64 = 3e-9;

/// The AGM of A&S §17.6 / DLMF 19.8 for parameter `m` and its complement
/// `mc`; the caller guarantees m + mc = 1 (to rounding), m ≤ 1, finite
/// mc ≥ 0, and passes whichever of the two it knows exactly unrounded (this
/// is why both are arguments). Allocation-free; a handful of `sqrt` and
/// divisions.
#[inline]
pub(crate) fn agm_sums(m: f64, mc: f64) -> AgmSums {
    if mc == 0.0 {
        // M(1, 0) = 0: K = +∞ (K's integrand is 1/cos θ); Σ → 1, S₁ → 1/2.
        return AgmSums {
            k_first: f64::INFINITY,
            sigma: 1.0,
            s1: 0.5,
        };
    }
    let mut a = 1.0_f64;
    let mut b = mc.sqrt();
    let mut c = m; // c₀² for the first step (c₀ itself may be imaginary for m < 0)
    let mut first = true;
    let mut s1 = 0.0_f64;
    let mut weight = 1.0_f64; // 2^{n−1} for n = 1, 2, …
    for _ in 0..AGM_MAX_ITER {
        let a_next = 0.5 * (a + b);
        let b_next = (a * b).sqrt();
        // DLMF 19.8.3: c_{n+1} = cₙ² / (4 a_{n+1}); for n = 0, cₙ² = m.
        let c_sq = if first { c } else { c * c };
        first = false;
        let c_next = c_sq / (4.0 * a_next);
        s1 += weight * c_next * c_next;
        weight *= 2.0;
        a = a_next;
        b = b_next;
        c = c_next;
        if c.abs() <= AGM_TOL * a {
            break;
        }
    }
    AgmSums {
        k_first: FRAC_PI_2 / a,
        sigma: 0.5 * m + s1,
        s1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn zero_parameter_is_half_pi_exactly() {
        let v = ellipke_m(0.0).unwrap();
        assert_eq!(v.k_first, FRAC_PI_2);
        assert_eq!(v.e_second, FRAC_PI_2);
        let v = ellipke_mc(1.0).unwrap();
        assert_eq!(v.k_first, FRAC_PI_2);
        assert_eq!(v.e_second, FRAC_PI_2);
    }

    #[test]
    fn singular_end_is_documented_value() {
        assert_eq!(ellipk_m(1.0).unwrap(), f64::INFINITY);
        assert_eq!(ellipe_m(1.0).unwrap(), 1.0);
        let v = ellipke_mc(0.0).unwrap();
        assert_eq!(v.k_first, f64::INFINITY);
        assert_eq!(v.e_second, 1.0);
    }

    #[test]
    fn out_of_domain_is_an_error() {
        for m in [1.0 + 1e-15, 2.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(
                matches!(ellipk_m(m), Err(EllipticError::ParameterOutOfDomain { .. })),
                "m = {m}"
            );
            assert!(ellipe_m(m).is_err(), "m = {m}");
        }
        // The most negative m is still in the domain: K ≈ ln(4√|m|)/√|m|,
        // E ≈ √|m| (leading terms, from the imaginary-modulus transformation
        // K(m) = K(m/(m−1))/√(1−m), E(m) = √(1−m) E(m/(m−1)), DLMF §19.7(ii),
        // and the m → 1 limits).
        let v = ellipke_m(-f64::MAX).unwrap();
        let r = f64::MAX.sqrt();
        assert!(rel(v.e_second, r) < 1e-15);
        assert!(rel(v.k_first, (4.0 * r).ln() / r) < 1e-12);
        for mc in [-1e-300, -1.0, f64::NAN, f64::INFINITY] {
            assert!(
                matches!(
                    ellipke_mc(mc),
                    Err(EllipticError::ComplementaryOutOfDomain { .. })
                ),
                "mc = {mc}"
            );
        }
    }

    /// The lemniscatic value K(1/2) = Γ(1/4)² / (4√π) (Γ(1/4) = 3.6256099082219083119…),
    /// and Legendre's relation E K′ + E′ K − K K′ = π/2 (DLMF 19.7.1) for the
    /// parameters m and 1 − m.
    #[test]
    fn special_value_and_legendre_relation() {
        let gamma_quarter = 3.625_609_908_221_908_f64;
        let k_half = gamma_quarter * gamma_quarter / (4.0 * PI.sqrt());
        assert!(rel(ellipk_m(0.5).unwrap(), k_half) < 4e-16);
        for m in [1e-12, 1e-6, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 0.999_999] {
            let v = ellipke_m(m).unwrap();
            let w = ellipke_mc(m).unwrap(); // K(1 − m), E(1 − m)
            let lhs = v.e_second * w.k_first + w.e_second * v.k_first - v.k_first * w.k_first;
            assert!(rel(lhs, FRAC_PI_2) < 3e-15, "m = {m}: {lhs}");
        }
    }

    /// Small-m hypergeometric series (A&S 17.3.11–17.3.12): K = π/2 (1 + m/4 + 9m²/64 + …),
    /// E = π/2 (1 − m/4 − 3m²/64 − …); and K − E = (π/4) m (1 + 3m/8 + …)
    /// computed as K Σ keeps full relative precision for tiny m.
    #[test]
    fn small_parameter_series() {
        // Truncation: next terms are O(m³) in K, E and O(m²) relative in K − E.
        for m in [1e-300, 1e-100, 1e-20, 1e-10, 1e-8] {
            let v = ellipke_m(m).unwrap();
            let k = FRAC_PI_2 * (1.0 + m / 4.0 + 9.0 * m * m / 64.0);
            let e = FRAC_PI_2 * (1.0 - m / 4.0 - 3.0 * m * m / 64.0);
            assert!(rel(v.k_first, k) < 2e-16, "m = {m}");
            assert!(rel(v.e_second, e) < 2e-16, "m = {m}");
            let s = agm_sums(m, 1.0 - m);
            let k_minus_e = s.k_first * s.sigma;
            let series = 0.25 * PI * m * (1.0 + 0.375 * m);
            assert!(rel(k_minus_e, series) < 1e-15, "m = {m}");
        }
    }

    /// Near m = 1 (A&S 17.3.26, 17.3.36; DLMF §19.12): K ≈ L + (m_c/4)(L − 1),
    /// E ≈ 1 + (m_c/2)(L − 1/2), L = ln(4/√m_c); next terms O(m_c² L).
    #[test]
    fn logarithmic_end() {
        for mc in [1e-300, 1e-100, 1e-30, 1e-14] {
            let v = ellipke_mc(mc).unwrap();
            let l = (4.0 / mc.sqrt()).ln();
            assert!(
                rel(v.k_first, l + 0.25 * mc * (l - 1.0)) < 1e-15,
                "mc = {mc}"
            );
            assert!(
                rel(v.e_second, 1.0 + 0.5 * mc * (l - 0.5)) < 1e-15,
                "mc = {mc}"
            );
        }
    }

    #[test]
    fn monotone_over_the_domain() {
        let mut prev = ellipke_m(-50.0).unwrap();
        let mut m: f64 = -50.0;
        while m < 1.0 {
            m += if m < 0.99 {
                0.01
            } else {
                (1.0 - m) * 0.5 + 1e-17
            };
            let m = m.min(1.0);
            let v = ellipke_m(m).unwrap();
            assert!(v.k_first > prev.k_first, "K not increasing at m = {m}");
            assert!(v.e_second < prev.e_second, "E not decreasing at m = {m}");
            prev = v;
        }
    }
}
