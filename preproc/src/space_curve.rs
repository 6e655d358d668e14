//! A space curve through control points (paper §2a–b, docs/reference/03-track-preproc.md §3a–b): x(τ),
//! y(τ), z(τ) fitted with one of the spline schemes over the chord-length
//! parameter τ, arc length s(τ) by 8-point Gauss–Legendre quadrature per
//! piece, and the inverse τ(s) by Newton's method — so the curve can be
//! sampled at any arc length.

use nalgebra::Vector3;
use runtime::geometry::spline::{PiecewiseCubic, Scheme, SplineError};
use runtime::quadrature::gauss_legendre_8;

/// Why a curve could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CurveError {
    #[error("point {index} repeats point {prev} (zero chord)", prev = index - 1)]
    RepeatedPoint { index: usize },
    #[error(
        "the fitted curve doubles back between points {index} and {next} (its tangent turns against the chord); remove or move the points there",
        next = index + 1
    )]
    DoublesBack { index: usize },
    #[error(transparent)]
    Spline(#[from] SplineError),
}

/// Position and derivatives with respect to τ at one point of a curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePoint {
    /// Chord-length parameter.
    pub tau: f64,
    /// Position r (m).
    pub r: Vector3<f64>,
    /// dr/dτ, d²r/dτ², d³r/dτ³.
    pub d1: Vector3<f64>,
    pub d2: Vector3<f64>,
    pub d3: Vector3<f64>,
}

impl CurvePoint {
    /// Unit tangent dr/ds.
    pub fn tangent(&self) -> Vector3<f64> {
        self.d1.normalize()
    }

    /// Frenet curvature κ = |r' × r''| / |r'|³ (1/m), independent of the
    /// parameterisation.
    pub fn curvature(&self) -> f64 {
        self.d1.cross(&self.d2).norm() / self.d1.norm().powi(3)
    }

    /// Signed curvature of the horizontal projection,
    /// (x'y'' − y'x'') / (x'² + y'²)^{3/2} (1/m): positive turning left.
    pub fn horizontal_curvature(&self) -> f64 {
        let (x1, y1, x2, y2) = (self.d1.x, self.d1.y, self.d2.x, self.d2.y);
        (x1 * y2 - y1 * x2) / (x1 * x1 + y1 * y1).powf(1.5)
    }

    /// Frenet torsion (r' × r'')·r''' / |r' × r''|² (1/m); 0 where the
    /// curvature is below 1e-9 1/m (straight: torsion undefined).
    pub fn torsion(&self) -> f64 {
        let c = self.d1.cross(&self.d2);
        if self.curvature() < 1e-9 {
            0.0
        } else {
            c.dot(&self.d3) / c.norm_squared()
        }
    }
}

/// The point of a curve where it bends most ([`SpaceCurve::sharpest_bend`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bend {
    /// Piece (between control points `piece` and `piece + 1`, 0-based).
    pub piece: usize,
    /// Arc length there (m).
    pub s_m: f64,
    /// Frenet curvature there (1/m); 0 on a straight curve.
    pub curvature_1_m: f64,
}

/// A fitted space curve, parameterisable by arc length.
#[derive(Debug, Clone)]
pub struct SpaceCurve {
    coords: [PiecewiseCubic; 3],
    tau: Vec<f64>,
    /// Arc length at each knot (m); `cum[0] = 0`.
    cum: Vec<f64>,
}

impl SpaceCurve {
    /// Fit a curve through `points` (≥ 2, consecutive points distinct).
    pub fn fit(scheme: Scheme, points: &[[f64; 3]]) -> Result<Self, CurveError> {
        let mut tau = Vec::with_capacity(points.len());
        tau.push(0.0);
        for k in 1..points.len() {
            let (a, b) = (points[k - 1], points[k]);
            let chord =
                ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt();
            if chord <= 0.0 {
                return Err(CurveError::RepeatedPoint { index: k });
            }
            tau.push(tau[k - 1] + chord);
        }
        let coord = |c: usize| -> Vec<f64> { points.iter().map(|p| p[c]).collect() };
        let coords = [
            PiecewiseCubic::fit(scheme, &tau, &coord(0))?,
            PiecewiseCubic::fit(scheme, &tau, &coord(1))?,
            PiecewiseCubic::fit(scheme, &tau, &coord(2))?,
        ];
        let mut curve = Self {
            coords,
            tau,
            cum: Vec::new(),
        };
        curve.check_forward(points)?;
        let mut cum = Vec::with_capacity(points.len());
        cum.push(0.0);
        for i in 0..points.len() - 1 {
            let (a, b) = (curve.tau[i], curve.tau[i + 1]);
            let len = gauss_legendre_8(a, b, |t| curve.speed_in_piece(i, t));
            cum.push(cum[i] + len);
        }
        curve.cum = cum;
        Ok(curve)
    }

    /// The tangent must point along the chord everywhere in each piece;
    /// otherwise the spline loops or doubles back (docs/reference/02-inputs.md §2).
    fn check_forward(&self, points: &[[f64; 3]]) -> Result<(), CurveError> {
        for i in 0..points.len() - 1 {
            let (a, b) = (points[i], points[i + 1]);
            let chord = Vector3::new(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
            let (t0, t1) = (self.tau[i], self.tau[i + 1]);
            for k in 0..=16 {
                let t = t0 + (t1 - t0) * k as f64 / 16.0;
                if self.point_in_piece(i, t).d1.dot(&chord) <= 0.0 {
                    return Err(CurveError::DoublesBack { index: i });
                }
            }
        }
        Ok(())
    }

    /// Total arc length (m).
    pub fn length(&self) -> f64 {
        self.cum[self.cum.len() - 1]
    }

    /// Arc length at each control point (m).
    pub fn knot_arc_lengths(&self) -> &[f64] {
        &self.cum
    }

    /// Number of control points.
    pub fn len(&self) -> usize {
        self.tau.len()
    }

    /// Always false: a curve has at least two points.
    pub fn is_empty(&self) -> bool {
        self.tau.is_empty()
    }

    /// Where the curve bends most: the largest Frenet curvature over 17
    /// points of every piece (its ends and 15 between, as the check of
    /// [`SpaceCurve::fit`] samples it). A cubic piece's curvature varies
    /// smoothly, so this finds the peak of each piece to within a small
    /// fraction of its value.
    pub fn sharpest_bend(&self) -> Bend {
        let mut best = Bend {
            piece: 0,
            s_m: 0.0,
            curvature_1_m: 0.0,
        };
        for i in 0..self.tau.len() - 1 {
            let (t0, t1) = (self.tau[i], self.tau[i + 1]);
            for k in 0..=16 {
                let t = t0 + (t1 - t0) * k as f64 / 16.0;
                let kappa = self.point_in_piece(i, t).curvature();
                if kappa > best.curvature_1_m {
                    best = Bend {
                        piece: i,
                        s_m: self.cum[i] + gauss_legendre_8(t0, t, |u| self.speed_in_piece(i, u)),
                        curvature_1_m: kappa,
                    };
                }
            }
        }
        best
    }

    #[inline]
    fn point_in_piece(&self, i: usize, tau: f64) -> CurvePoint {
        let [x, y, z] = [
            self.coords[0].derivatives_in_piece(i, tau),
            self.coords[1].derivatives_in_piece(i, tau),
            self.coords[2].derivatives_in_piece(i, tau),
        ];
        CurvePoint {
            tau,
            r: Vector3::new(x.value, y.value, z.value),
            d1: Vector3::new(x.d1, y.d1, z.d1),
            d2: Vector3::new(x.d2, y.d2, z.d2),
            d3: Vector3::new(x.d3, y.d3, z.d3),
        }
    }

    #[inline]
    fn speed_in_piece(&self, i: usize, tau: f64) -> f64 {
        let c = |k: usize| {
            let cf = &self.coords[k].coefficients()[i];
            let t = tau - self.tau[i];
            (3.0 * cf[3] * t + 2.0 * cf[2]) * t + cf[1]
        };
        let (a, b, d) = (c(0), c(1), c(2));
        (a * a + b * b + d * d).sqrt()
    }

    /// Piece containing arc length `s` (clamped to the curve).
    fn piece_at(&self, s: f64) -> usize {
        let last = self.tau.len() - 2;
        self.cum[1..=last].partition_point(|&c| c <= s).min(last)
    }

    /// Solve s_b + ∫_{τ_b}^{τ} |r'| dτ = s for τ in piece `i` by Newton.
    ///
    /// Newton converges quadratically: after a correction Δτ the remaining
    /// error is about |r''|·Δτ²/(2|r'|). Once |Δτ| < 1e-8 m that is below
    /// 1e-16 m·|r''| — far under the tolerance for any curve a track can
    /// have (|r''| ≈ curvature ≪ 1/m) — so the last correction is accepted
    /// without another quadrature (this halves the cost of a dense table).
    fn solve_in_piece(&self, i: usize, tau_b: f64, s_b: f64, s: f64) -> f64 {
        let tol = 1e-12 + 4.0 * f64::EPSILON * s.abs();
        let mut t = tau_b + (s - s_b) / self.speed_in_piece(i, tau_b);
        for _ in 0..50 {
            let f = s_b + gauss_legendre_8(tau_b, t, |u| self.speed_in_piece(i, u)) - s;
            if f.abs() <= tol {
                break;
            }
            let dt = f / self.speed_in_piece(i, t);
            t -= dt;
            if dt.abs() < 1e-8 {
                break;
            }
        }
        t
    }

    /// The curve at arc length `s` (m); beyond the ends the end pieces are
    /// extended.
    pub fn at_arc_length(&self, s: f64) -> CurvePoint {
        let i = self.piece_at(s);
        let tau = self.solve_in_piece(i, self.tau[i], self.cum[i], s);
        self.point_in_piece(i, tau)
    }

    /// The curve at each of the increasing arc lengths `s` (m). Marches
    /// piece by piece, integrating from the previous sample, so each sample
    /// costs about two Newton steps.
    pub fn at_arc_lengths(&self, s: &[f64]) -> Vec<CurvePoint> {
        let mut out = Vec::with_capacity(s.len());
        let Some(&first) = s.first() else {
            return out;
        };
        let last_piece = self.tau.len() - 2;
        let mut i = self.piece_at(first);
        let (mut tau_b, mut s_b) = (self.tau[i], self.cum[i]);
        for &sk in s {
            if i < last_piece && sk >= self.cum[i + 1] {
                while i < last_piece && sk >= self.cum[i + 1] {
                    i += 1;
                }
                tau_b = self.tau[i];
                s_b = self.cum[i];
            }
            let tau = self.solve_in_piece(i, tau_b, s_b, sk);
            // Restart from the knot when a sample went backwards.
            if sk >= s_b {
                tau_b = tau;
                s_b = sk;
            }
            out.push(self.point_in_piece(i, tau));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn circle(r: f64, n: usize, dtheta: f64) -> Vec<[f64; 3]> {
        (0..n)
            .map(|k| {
                let th = k as f64 * dtheta;
                [r * th.sin(), r * (1.0 - th.cos()), 0.0]
            })
            .collect()
    }

    #[test]
    fn straight_line_has_exact_length_and_unit_speed() {
        let pts: Vec<[f64; 3]> = (0..11).map(|k| [k as f64, 0.0, 0.5 * k as f64]).collect();
        let c = SpaceCurve::fit(Scheme::Cubic, &pts).unwrap();
        let l = 10.0 * 1.25_f64.sqrt();
        assert!((c.length() - l).abs() < 1e-12);
        let p = c.at_arc_length(3.3);
        assert!((p.r - Vector3::new(3.3, 0.0, 1.65) / 1.25_f64.sqrt()).norm() < 1e-12);
        assert!(p.curvature() < 1e-12);
    }

    #[test]
    fn circle_length_and_curvature() {
        let r = 300.0;
        let pts = circle(r, 101, 1.0 / r);
        for scheme in [Scheme::Cubic, Scheme::CubicNatural, Scheme::Akima] {
            let c = SpaceCurve::fit(scheme, &pts).unwrap();
            assert!(
                (c.length() - 100.0).abs() < 1e-6,
                "{scheme}: {}",
                c.length()
            );
            let p = c.at_arc_length(50.0);
            assert!((p.curvature() * r - 1.0).abs() < 1e-4, "{scheme}");
        }
    }

    #[test]
    fn sharpest_bend_of_a_circle_and_a_line() {
        let c = SpaceCurve::fit(Scheme::Cubic, &circle(50.0, 40, 0.05)).unwrap();
        let b = c.sharpest_bend();
        // Within the not-a-knot end pieces' small overshoot (0.2 %).
        assert!((b.curvature_1_m * 50.0 - 1.0).abs() < 5e-3, "{b:?}");
        assert!(b.s_m >= 0.0 && b.s_m <= c.length());
        let pts: Vec<[f64; 3]> = (0..5).map(|k| [k as f64, 0.0, 0.0]).collect();
        let b = SpaceCurve::fit(Scheme::Cubic, &pts)
            .unwrap()
            .sharpest_bend();
        assert_eq!(b.curvature_1_m, 0.0);
    }

    #[test]
    fn marching_equals_single_queries() {
        let pts = circle(50.0, 40, 0.05);
        let c = SpaceCurve::fit(Scheme::Pchip, &pts).unwrap();
        let s: Vec<f64> = (0..700)
            .map(|k| k as f64 * 0.13)
            .filter(|&s| s <= c.length())
            .collect();
        let marched = c.at_arc_lengths(&s);
        for (sk, m) in s.iter().zip(&marched) {
            let single = c.at_arc_length(*sk);
            assert!((m.r - single.r).norm() < 1e-10, "s = {sk}");
        }
    }

    #[test]
    fn doubling_back_is_detected() {
        let pts = [
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [10.5, 0.2, 0.0],
            [10.0, 0.4, 0.0],
            [0.0, 0.4, 0.0],
        ];
        assert!(matches!(
            SpaceCurve::fit(Scheme::Cubic, &pts),
            Err(CurveError::DoublesBack { .. })
        ));
    }
}
