//! One element of the plan (horizontal alignment) — straight, circular
//! arc or transition — evaluated at a plan distance σ from its start
//! (docs/reference/03-track-preproc.md §3h). Curvature κ (signed, > 0
//! turning left, docs/reference/01-units-frames.md) and heading θ are closed
//! form: κ = κ₀ + Δκ·f(u), θ = θ₀ + κ₀σ + Δκ·L·F(u) with u = σ/L and the
//! shape f of [`Ramp`]; the plan position is ∫(cos θ, sin θ) dσ by 8-point
//! Gauss–Legendre quadrature on panels of at most [`PANEL_M`], except the
//! cubic parabola, whose position is closed form in its abscissa
//! ([`CubicParabola`]).

use runtime::quadrature::gauss_legendre_8;

use super::cubic_parabola::CubicParabola;
use super::shape::Ramp;

/// Longest quadrature panel (m). On a panel of h = 5 m the heading turns by
/// at most h/R = 0.5 rad at the smallest radius accepted (10 m) and by
/// 0.02 rad at R = 250 m; the 8-point rule integrates cos θ, sin θ there to
/// round-off (its error term is ∝ (hκ)¹⁶/16!): the positions agree with
/// the closed form of an arc to 1e-9 m over kilometres (tests).
pub const PANEL_M: f64 = 5.0;

/// How the curvature runs along an element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlanShape {
    /// κ = 0.
    Straight,
    /// κ = 1/R.
    Arc,
    /// κ = κ₀ + Δκ·f(σ/L).
    Transition(Ramp),
    /// A cubic parabola from (`entry`) or to a straight.
    CubicParabola {
        parabola: CubicParabola,
        entry: bool,
    },
}

/// The plan at one σ of an element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanPoint {
    /// Plan position (m).
    pub x_m: f64,
    pub y_m: f64,
    /// Heading θ, angle of the tangent to +X (rad).
    pub heading_rad: f64,
    /// Signed plan curvature κ = dθ/dσ (1/m).
    pub kappa_1_m: f64,
    /// dκ/dσ (1/m²).
    pub dkappa_1_m2: f64,
}

/// An element placed in the plan: start position and heading fixed.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanElement {
    pub shape: PlanShape,
    pub length_m: f64,
    pub kappa_start_1_m: f64,
    pub kappa_end_1_m: f64,
    pub heading_start_rad: f64,
    /// Plan position at the start of each quadrature panel (σ, x, y) (m).
    panels: Vec<[f64; 3]>,
}

impl PlanElement {
    /// Place an element starting at (x, y) with heading `heading_start_rad`.
    pub fn new(
        shape: PlanShape,
        length_m: f64,
        kappa_start_1_m: f64,
        kappa_end_1_m: f64,
        start: [f64; 2],
        heading_start_rad: f64,
    ) -> Self {
        let mut e = Self {
            shape,
            length_m,
            kappa_start_1_m,
            kappa_end_1_m,
            heading_start_rad,
            panels: vec![[0.0, start[0], start[1]]],
        };
        if !matches!(shape, PlanShape::CubicParabola { .. }) {
            let n = (length_m / PANEL_M).ceil().max(1.0) as usize;
            for k in 1..=n {
                let [s0, x0, y0] = e.panels[k - 1];
                let s1 = length_m * k as f64 / n as f64;
                let (dx, dy) = e.integrate(s0, s1);
                e.panels.push([s1, x0 + dx, y0 + dy]);
            }
        }
        e
    }

    /// ∫ (cos θ, sin θ) dσ over [a, b].
    fn integrate(&self, a: f64, b: f64) -> (f64, f64) {
        (
            gauss_legendre_8(a, b, |s| self.heading(s).cos()),
            gauss_legendre_8(a, b, |s| self.heading(s).sin()),
        )
    }

    /// Sign of the turn of a cubic parabola.
    fn turn_sign(&self) -> f64 {
        let k = if self.kappa_end_1_m != 0.0 {
            self.kappa_end_1_m
        } else {
            self.kappa_start_1_m
        };
        k.signum()
    }

    /// Heading θ(σ) (rad), closed form.
    pub fn heading(&self, sigma_m: f64) -> f64 {
        let (k0, dk, l) = (
            self.kappa_start_1_m,
            self.kappa_end_1_m - self.kappa_start_1_m,
            self.length_m,
        );
        let th0 = self.heading_start_rad;
        match self.shape {
            PlanShape::Straight | PlanShape::Arc => th0 + k0 * sigma_m,
            PlanShape::Transition(r) => th0 + k0 * sigma_m + dk * l * r.integral(sigma_m / l),
            PlanShape::CubicParabola { parabola, entry } => {
                let sg = self.turn_sign();
                if entry {
                    th0 + sg * parabola.at(sigma_m).angle_rad
                } else {
                    let total = parabola.at(l).angle_rad;
                    th0 + sg * (total - parabola.at(l - sigma_m).angle_rad)
                }
            }
        }
    }

    /// Heading at the end (rad).
    pub fn heading_end(&self) -> f64 {
        self.heading(self.length_m)
    }

    /// The plan at σ ∈ [0, L] (clamped).
    pub fn at(&self, sigma_m: f64) -> PlanPoint {
        let s = sigma_m.clamp(0.0, self.length_m);
        let (k0, dk, l) = (
            self.kappa_start_1_m,
            self.kappa_end_1_m - self.kappa_start_1_m,
            self.length_m,
        );
        let heading_rad = self.heading(s);
        match self.shape {
            PlanShape::CubicParabola { parabola, entry } => {
                let sg = self.turn_sign();
                let th0 = self.heading_start_rad;
                let (c0, s0) = (th0.cos(), th0.sin());
                let [_, x0, y0] = self.panels[0];
                let (x_m, y_m, kappa_1_m, dkappa_1_m2) = if entry {
                    let p = parabola.at(s);
                    let (u, v) = (p.x_m, sg * p.y_m);
                    (
                        x0 + c0 * u - s0 * v,
                        y0 + s0 * u + c0 * v,
                        sg * p.kappa_1_m,
                        sg * p.dkappa_ds_1_m2,
                    )
                } else {
                    // Traversed backwards from its end, an exit parabola is an
                    // entry turning the other way.
                    let end = parabola.at(l);
                    let th1 = self.heading_end();
                    let (c1, s1) = (th1.cos(), th1.sin());
                    let (u1, v1) = (end.x_m, -sg * end.y_m);
                    let (xe, ye) = (x0 + c1 * u1 - s1 * v1, y0 + s1 * u1 + c1 * v1);
                    let p = parabola.at(l - s);
                    let (u, v) = (p.x_m, -sg * p.y_m);
                    (
                        xe - (c1 * u - s1 * v),
                        ye - (s1 * u + c1 * v),
                        sg * p.kappa_1_m,
                        -sg * p.dkappa_ds_1_m2,
                    )
                };
                PlanPoint {
                    x_m,
                    y_m,
                    heading_rad,
                    kappa_1_m,
                    dkappa_1_m2,
                }
            }
            shape => {
                let (kappa_1_m, dkappa_1_m2) = match shape {
                    PlanShape::Transition(r) => (k0 + dk * r.f(s / l), dk * r.df(s / l) / l),
                    _ => (k0, 0.0),
                };
                // The panel holding σ, and the quadrature from its start.
                let k = self
                    .panels
                    .partition_point(|p| p[0] <= s)
                    .saturating_sub(1)
                    .min(self.panels.len() - 1);
                let [sk, xk, yk] = self.panels[k];
                let (dx, dy) = if s > sk {
                    self.integrate(sk, s)
                } else {
                    (0.0, 0.0)
                };
                PlanPoint {
                    x_m: xk + dx,
                    y_m: yk + dy,
                    heading_rad,
                    kappa_1_m,
                    dkappa_1_m2,
                }
            }
        }
    }

    /// The plan position at the end (m).
    pub fn end(&self) -> [f64; 2] {
        let p = self.at(self.length_m);
        [p.x_m, p.y_m]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An arc of R = 600 m over 1000 m: the quadrature's positions agree
    /// with the closed form R(sin θ, 1 − cos θ) to 1e-9 m everywhere.
    #[test]
    fn arc_positions_match_the_closed_form() {
        let r = 600.0;
        let e = PlanElement::new(PlanShape::Arc, 1000.0, 1.0 / r, 1.0 / r, [0.0, 0.0], 0.0);
        for k in 0..=997 {
            let s = f64::from(k) * 1.003;
            let p = e.at(s);
            let th = s / r;
            assert!((p.x_m - r * th.sin()).abs() < 1e-9, "{s}");
            assert!((p.y_m - r * (1.0 - th.cos())).abs() < 1e-9, "{s}");
            assert!((p.heading_rad - th).abs() < 1e-15);
        }
    }

    /// A clothoid's position from the quadrature agrees with the Fresnel
    /// series x = Σ (−1)ⁿ s^{4n+1} / ((4n+1)(2n)! (2A²)^{2n}), y likewise,
    /// to 1e-9 m (A² = R·L).
    #[test]
    fn clothoid_positions_match_the_fresnel_series() {
        let (r, l) = (250.0, 90.0);
        let e = PlanElement::new(
            PlanShape::Transition(Ramp::Linear),
            l,
            0.0,
            1.0 / r,
            [0.0, 0.0],
            0.0,
        );
        let a2 = r * l;
        for k in 0..=90 {
            let s = f64::from(k);
            let (mut x, mut y, mut fact) = (0.0, 0.0, 1.0_f64);
            // θ = s²/(2A²); cos θ = Σ (−1)ⁿ θ^{2n}/(2n)!, sin θ likewise.
            for n in 0..12 {
                let n2 = 2 * n;
                if n2 > 0 {
                    fact *= f64::from(n2 - 1) * f64::from(n2);
                }
                let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
                let p = f64::from(2 * n2 + 1);
                x += sign * s.powf(p) / (p * fact * (2.0 * a2).powi(n2));
                let q = f64::from(2 * n2 + 3);
                y += sign * s.powf(q) / (q * fact * f64::from(n2 + 1) * (2.0 * a2).powi(n2 + 1));
            }
            let pt = e.at(s);
            assert!(
                (pt.x_m - x).abs() < 1e-9 && (pt.y_m - y).abs() < 1e-9,
                "{s}: {pt:?} {x} {y}"
            );
        }
    }

    /// The cubic parabola's exit mirrors its entry: it ends at the heading
    /// and curvature of the straight, and its curvature is continuous.
    #[test]
    fn cubic_parabola_exit_mirrors_the_entry() {
        let p = CubicParabola::new(80.0, 1.0 / 600.0).unwrap();
        let entry = PlanElement::new(
            PlanShape::CubicParabola {
                parabola: p,
                entry: true,
            },
            80.0,
            0.0,
            1.0 / 600.0,
            [0.0, 0.0],
            0.0,
        );
        let exit = PlanElement::new(
            PlanShape::CubicParabola {
                parabola: p,
                entry: false,
            },
            80.0,
            1.0 / 600.0,
            0.0,
            entry.end(),
            entry.heading_end(),
        );
        assert!((exit.heading_end() - 2.0 * entry.heading_end()).abs() < 1e-15);
        assert!((exit.at(0.0).kappa_1_m - 1.0 / 600.0).abs() < 1e-15);
        assert!(exit.at(80.0).kappa_1_m.abs() < 1e-15);
        let [x, y] = exit.end();
        // Symmetric about the mid-normal: the end lies on the line through
        // the joint at the joint's heading reflected.
        let [xm, ym] = entry.end();
        let th = entry.heading_end();
        let (dx, dy) = (x - xm, y - ym);
        let along = dx * th.cos() + dy * th.sin();
        let [x0, y0] = [0.0, 0.0];
        let back = (xm - x0) * th.cos() + (ym - y0) * th.sin();
        assert!((along - back).abs() < 1e-9, "{along} {back}");
    }
}
