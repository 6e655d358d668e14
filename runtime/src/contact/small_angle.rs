//! The sine and cosine of the wheel's angle s_w (the contact equations'
//! third unknown, [`super::geometry`]): near the contact the point lies
//! within a few hundredths of a radian of the axle's vertical (lead or lag
//! of a yawed wheelset), where their Taylor series, summed as polynomials,
//! give them to the last bit or so without the library call (whose cost
//! and register spills showed in the warm solve's profile,
//! docs/reference/06-contact-detection.md §6.2). Beyond
//! [`SERIES_LIMIT_RAD`] the library's `sin_cos` is used.
//!
//! Series (Abramowitz & Stegun, Handbook of Mathematical Functions,
//! 4.3.65 and 4.3.66):
//!
//!   sin x = x − x³/3! + x⁵/5! − … ,   cos x = 1 − x²/2! + x⁴/4! − … ;
//!
//! up to x¹¹ and x¹², the first term left out is below 3·10⁻²² of the
//! value for |x| ≤ 1/8 (x¹³/13! and x¹⁴/14!), far below the double's
//! half-ulp (1.1·10⁻¹⁶), so the result is the rounding of the sums:
//! within one ulp of the correctly rounded value (tested against the
//! library below).

/// Largest |s_w| (rad) summed by the series: 1/8 rad (7.2°).
pub(crate) const SERIES_LIMIT_RAD: f64 = 0.125;

/// 1/n! for the odd (sine) and even (cosine) terms from n = 3 and n = 2,
/// with their signs.
const SIN_TERMS: [f64; 5] = [
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5_040.0,
    1.0 / 362_880.0,
    -1.0 / 39_916_800.0,
];
const COS_TERMS: [f64; 6] = [
    -1.0 / 2.0,
    1.0 / 24.0,
    -1.0 / 720.0,
    1.0 / 40_320.0,
    -1.0 / 3_628_800.0,
    1.0 / 479_001_600.0,
];

/// (sin x, cos x) of an angle `x_rad` (rad): the series for
/// |x| ≤ [`SERIES_LIMIT_RAD`], the library's `sin_cos` beyond (and for
/// NaN).
#[inline(always)]
pub(crate) fn sin_cos(x_rad: f64) -> (f64, f64) {
    // NaN fails the test too (the library's NaNs).
    if x_rad.abs() > SERIES_LIMIT_RAD || x_rad.is_nan() {
        return x_rad.sin_cos();
    }
    let x2 = x_rad * x_rad;
    // Horner in x²: sin x = x + x·x²·P(x²), cos x = 1 + x²·Q(x²).
    let p = SIN_TERMS[0]
        + x2 * (SIN_TERMS[1] + x2 * (SIN_TERMS[2] + x2 * (SIN_TERMS[3] + x2 * SIN_TERMS[4])));
    let q = COS_TERMS[0]
        + x2 * (COS_TERMS[1]
            + x2 * (COS_TERMS[2] + x2 * (COS_TERMS[3] + x2 * (COS_TERMS[4] + x2 * COS_TERMS[5]))));
    (x_rad + x_rad * (x2 * p), 1.0 + x2 * q)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place of `b`.
    fn ulps(a: f64, b: f64) -> f64 {
        let ulp = f64::from_bits(b.abs().to_bits() + 1) - b.abs();
        (a - b).abs() / ulp
    }

    /// Within one ulp of the library over the series' range, densely and
    /// at its ends, and the library's bits beyond it.
    #[test]
    fn the_series_agrees_with_the_library_to_one_ulp() {
        let n = 200_001;
        let mut worst: (f64, f64) = (0.0, 0.0);
        for k in 0..n {
            let x = SERIES_LIMIT_RAD * (2.0 * k as f64 / (n - 1) as f64 - 1.0);
            let (s, c) = sin_cos(x);
            let (s_lib, c_lib) = x.sin_cos();
            if s_lib != 0.0 {
                worst.0 = worst.0.max(ulps(s, s_lib));
            } else {
                assert_eq!(s, 0.0);
            }
            worst.1 = worst.1.max(ulps(c, c_lib));
        }
        assert!(
            worst.0 <= 1.0 && worst.1 <= 1.0,
            "worst (sin, cos) {worst:?} ulp"
        );
        for x in [1e-300, -3e-9, f64::MIN_POSITIVE] {
            let (s, c) = sin_cos(x);
            assert_eq!((s, c), (x, 1.0), "{x:e}");
        }
        for x in [0.12500001, -0.2, 1.0, 3.0, -100.0] {
            assert_eq!(sin_cos(x), x.sin_cos(), "{x}");
        }
        let (s, c) = sin_cos(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
    }
}
