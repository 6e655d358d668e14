//! The cubic parabola y = c·x³ as a transition from a straight
//! (docs/reference/03-track-preproc.md §3h; EN 13803:2017 §6.6 lists it
//! beside the clothoid; Lindahl 2001, §2.2): its position is closed form in
//! its abscissa x along the tangent of the straight, its curvature is
//! k(x) = 6cx / (1 + 9c²x⁴)^{3/2} — not linear in the arc length s — and
//! s(x) = ∫₀ˣ √(1 + 9c²v⁴) dv (Gauss–Legendre, 4 panels of 8 points:
//! the integrand is analytic within |v| < X·a^{-1/2}, a ≤ 1/√5, so the
//! rule is exact to round-off). Here c and the abscissa X of its end are
//! chosen so that the element is exactly `length_m` long and ends with
//! exactly the curvature 1/R of the arc it leads into, so the curvature is
//! continuous at both ends.

use runtime::quadrature::gauss_legendre_8;

/// Largest end slope a = y'(X) = 3cX² of a cubic parabola: its curvature
/// peaks where 9c²x⁴ = 1/5 and falls beyond, so a transition must end
/// before (the classic limit of the cubic parabola, Lindahl 2001 §2.2).
pub const MAX_END_SLOPE: f64 = 0.447_213_595_499_958;

/// A cubic parabola from a straight to the curvature `kappa_end_1_m` (> 0;
/// the sign of the turn is the element's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubicParabola {
    /// c of y = c·x³ (1/m²).
    pub c_1_m2: f64,
    /// Abscissa of the end (m).
    pub x_end_m: f64,
    /// Arc length (m).
    pub length_m: f64,
}

/// Local values at one arc length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParabolaPoint {
    pub x_m: f64,
    pub y_m: f64,
    /// Angle of the tangent to the x axis, atan(3cx²) (rad).
    pub angle_rad: f64,
    /// Curvature (1/m), ≥ 0.
    pub kappa_1_m: f64,
    /// dκ/ds (1/m²).
    pub dkappa_ds_1_m2: f64,
}

/// ∫₀¹ √(1 + a²u⁴) du.
fn unit_length(a: f64) -> f64 {
    (0..4)
        .map(|k| {
            let lo = f64::from(k) / 4.0;
            gauss_legendre_8(lo, lo + 0.25, |u| (1.0 + a * a * u.powi(4)).sqrt())
        })
        .sum()
}

/// κ_end·L of the parabola with end slope a: 2a·F(a)/(1 + a²)^{3/2}.
fn kappa_length(a: f64) -> f64 {
    2.0 * a * unit_length(a) / (1.0 + a * a).powf(1.5)
}

impl CubicParabola {
    /// The parabola of arc length `length_m` ending at curvature
    /// `kappa_end_1_m` > 0; `None` if no cubic parabola reaches that
    /// curvature in that length (κL beyond the value at
    /// [`MAX_END_SLOPE`], about 0.78).
    pub fn new(length_m: f64, kappa_end_1_m: f64) -> Option<Self> {
        let target = kappa_end_1_m * length_m;
        if !(target > 0.0 && target <= kappa_length(MAX_END_SLOPE)) {
            return None;
        }
        // κL(a) rises monotonically on [0, MAX_END_SLOPE]: bisection.
        let (mut lo, mut hi) = (0.0, MAX_END_SLOPE);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if kappa_length(mid) < target {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo < 1e-17 {
                break;
            }
        }
        let a = 0.5 * (lo + hi);
        let x_end_m = length_m / unit_length(a);
        Some(Self {
            c_1_m2: a / (3.0 * x_end_m * x_end_m),
            x_end_m,
            length_m,
        })
    }

    /// Arc length from the start to abscissa x (m).
    pub fn arc_length(&self, x_m: f64) -> f64 {
        let c = self.c_1_m2;
        (0..4)
            .map(|k| {
                let (lo, hi) = (x_m * f64::from(k) / 4.0, x_m * f64::from(k + 1) / 4.0);
                gauss_legendre_8(lo, hi, |v| (1.0 + 9.0 * c * c * v.powi(4)).sqrt())
            })
            .sum()
    }

    /// The point at arc length `s_m` from the start (Newton on s(x)).
    pub fn at(&self, s_m: f64) -> ParabolaPoint {
        let c = self.c_1_m2;
        let mut x = s_m.clamp(0.0, self.length_m) * self.x_end_m / self.length_m;
        for _ in 0..50 {
            let step = (self.arc_length(x) - s_m) / (1.0 + 9.0 * c * c * x.powi(4)).sqrt();
            x -= step;
            if step.abs() < 1e-13 * self.length_m.max(1.0) {
                break;
            }
        }
        let q = 9.0 * c * c * x.powi(4);
        ParabolaPoint {
            x_m: x,
            y_m: c * x.powi(3),
            angle_rad: (3.0 * c * x * x).atan(),
            kappa_1_m: 6.0 * c * x / (1.0 + q).powf(1.5),
            dkappa_ds_1_m2: 6.0 * c * (1.0 - 5.0 * q) / (1.0 + q).powi(3),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The parabola of the transition (80 m into R 600 m) is 80 m
    /// long and ends at exactly 1/600 1/m; dκ/ds agrees with a central
    /// difference; too sharp a transition is refused.
    #[test]
    fn ends_at_the_arc_curvature_and_length() {
        let p = CubicParabola::new(80.0, 1.0 / 600.0).unwrap();
        assert!((p.arc_length(p.x_end_m) - 80.0).abs() < 1e-12);
        let end = p.at(80.0);
        assert!((end.kappa_1_m * 600.0 - 1.0).abs() < 1e-12, "{end:?}");
        assert!((end.x_m - p.x_end_m).abs() < 1e-9);
        let h = 1e-3;
        let d = (p.at(40.0 + h).kappa_1_m - p.at(40.0 - h).kappa_1_m) / (2.0 * h);
        assert!((d / p.at(40.0).dkappa_ds_1_m2 - 1.0).abs() < 1e-6);
        assert!(CubicParabola::new(80.0, 1.0 / 50.0).is_none());
        assert!(CubicParabola::new(80.0, 0.0).is_none());
    }
}
