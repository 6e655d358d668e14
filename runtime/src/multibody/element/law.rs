//! Nonlinear force laws of one axis of an element, beside its linear
//! stiffness and damping (docs/reference/08-multibody.md §8.2): piecewise-linear
//! springs (a bump stop with a clearance, a force–deflection table) and
//! piecewise-linear dampers (a bilinear damper with a blow-off, a
//! force–velocity table).
//!
//! The characteristics are those of the suspension-component chapters of
//! Iwnicki (ed.), *Handbook of Railway Vehicle Dynamics* (CRC, 2006; bump
//! stops as clearance–stiffness characteristics, hydraulic dampers with a
//! blow-off valve as bilinear force–velocity curves) and of Knothe &
//! Stichel, *Rail Vehicle Dynamics* (Springer, 2017; piecewise-linear
//! characteristics of springs and dampers).
//!
//! Sign convention: every law gives the element's **restoring** force F
//! along the axis; the force on anchor b is −F (as −k δ and −c δ̇ of the
//! linear part).

/// Why a law is not usable (the rule it breaks).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LawError {
    /// A coefficient is NaN, infinite or out of its range.
    #[error("{what} = {value} must be finite and {rule}")]
    Coefficient {
        what: &'static str,
        value: f64,
        rule: &'static str,
    },
    /// A table breaks a rule.
    #[error("table: {rule}")]
    Table { rule: &'static str },
}

/// A piecewise-linear function y(x) through points with strictly increasing
/// x, through (0, 0), non-decreasing (slopes ≥ 0: stable springs,
/// dissipative dampers), continued beyond its ends with the end segments'
/// slopes.
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseLinear {
    x: Vec<f64>,
    y: Vec<f64>,
}

impl PiecewiseLinear {
    /// Checks the rules (type docs) and builds the table.
    pub fn new(x: Vec<f64>, y: Vec<f64>) -> Result<Self, LawError> {
        let err = |rule| Err(LawError::Table { rule });
        if x.len() != y.len() {
            return err("as many forces as abscissae");
        }
        if x.len() < 2 {
            return err("at least two points");
        }
        if !x.iter().chain(&y).all(|v| v.is_finite()) {
            return err("every value finite");
        }
        if x.windows(2).any(|w| w[1] <= w[0]) {
            return err("abscissae strictly increasing");
        }
        if y.windows(2).any(|w| w[1] < w[0]) {
            return err("forces non-decreasing (no negative slope)");
        }
        if !x.iter().zip(&y).any(|(&a, &b)| a == 0.0 && b == 0.0) {
            return err("the point (0, 0) in the table (a constant force is a preload)");
        }
        Ok(Self { x, y })
    }

    /// The abscissae.
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    /// The ordinates.
    pub fn y(&self) -> &[f64] {
        &self.y
    }

    /// Segment index (0 … n−2) holding x, end segments continued.
    fn segment(&self, x: f64) -> usize {
        let n = self.x.len();
        self.x[1..n - 1].partition_point(|&xi| xi <= x)
    }

    fn slope(&self, i: usize) -> f64 {
        (self.y[i + 1] - self.y[i]) / (self.x[i + 1] - self.x[i])
    }

    /// y(x), linear interpolation (and extrapolation with the end slopes).
    pub fn value(&self, x: f64) -> f64 {
        let i = self.segment(x);
        self.y[i] + self.slope(i) * (x - self.x[i])
    }

    /// ∫₀ˣ y(ξ) dξ, exact (trapezoids over the breakpoints between 0 and x).
    pub fn integral_from_zero(&self, x: f64) -> f64 {
        let (lo, hi, sign) = if x >= 0.0 {
            (0.0, x, 1.0)
        } else {
            (x, 0.0, -1.0)
        };
        let mut knots = vec![lo];
        knots.extend(self.x.iter().copied().filter(|&k| k > lo && k < hi));
        knots.push(hi);
        let area: f64 = knots
            .windows(2)
            .map(|w| 0.5 * (self.value(w[0]) + self.value(w[1])) * (w[1] - w[0]))
            .sum();
        sign * area
    }

    /// Slope at x = 0: the mean of the slopes left and right of 0 (the
    /// tangent where the table is smooth there).
    pub fn slope_at_zero(&self) -> f64 {
        let right = self.segment(0.0);
        let left = self.x[..self.x.len() - 1].partition_point(|&xi| xi < 0.0);
        let left = left.saturating_sub(1).min(self.x.len() - 2);
        0.5 * (self.slope(left) + self.slope(right))
    }
}

fn check(what: &'static str, value: f64, positive: bool) -> Result<(), LawError> {
    let ok = value.is_finite() && if positive { value > 0.0 } else { value >= 0.0 };
    if ok {
        Ok(())
    } else {
        Err(LawError::Coefficient {
            what,
            value,
            rule: if positive { "> 0" } else { ">= 0" },
        })
    }
}

/// A nonlinear spring on one axis, beside the linear stiffness.
#[derive(Debug, Clone, PartialEq)]
pub enum SpringLaw {
    /// A bump stop: no force while |δ| ≤ clearance, then
    /// F = k (|δ| − clearance) sign δ.
    BumpStop {
        clearance_m: f64,
        stiffness_n_m: f64,
    },
    /// A force–deflection table F(δ) (N against m).
    Table(PiecewiseLinear),
}

impl SpringLaw {
    /// Checks the coefficients (the table is checked when built).
    pub fn validate(&self) -> Result<(), LawError> {
        match self {
            Self::BumpStop {
                clearance_m,
                stiffness_n_m,
            } => {
                check("bump stop clearance (m)", *clearance_m, false)?;
                check("bump stop stiffness (N/m)", *stiffness_n_m, false)
            }
            Self::Table(_) => Ok(()),
        }
    }

    /// Restoring force F(δ) (N) at the deflection δ (m).
    pub fn force_n(&self, deflection_m: f64) -> f64 {
        match self {
            Self::BumpStop {
                clearance_m,
                stiffness_n_m,
            } => {
                let beyond = deflection_m.abs() - clearance_m;
                if beyond > 0.0 {
                    stiffness_n_m * beyond * deflection_m.signum()
                } else {
                    0.0
                }
            }
            Self::Table(t) => t.value(deflection_m),
        }
    }

    /// Stored energy ∫₀^δ F dξ (J) ≥ 0.
    pub fn energy_j(&self, deflection_m: f64) -> f64 {
        match self {
            Self::BumpStop {
                clearance_m,
                stiffness_n_m,
            } => {
                let beyond = (deflection_m.abs() - clearance_m).max(0.0);
                0.5 * stiffness_n_m * beyond * beyond
            }
            Self::Table(t) => t.integral_from_zero(deflection_m),
        }
    }

    /// Stiffness at δ = 0 (N/m) for the static preload solve: zero inside a
    /// bump stop's clearance (k if the clearance is zero), the table's slope
    /// at zero ([`PiecewiseLinear::slope_at_zero`]).
    pub fn stiffness_at_zero_n_m(&self) -> f64 {
        match self {
            Self::BumpStop {
                clearance_m,
                stiffness_n_m,
            } => {
                if *clearance_m > 0.0 {
                    0.0
                } else {
                    *stiffness_n_m
                }
            }
            Self::Table(t) => t.slope_at_zero(),
        }
    }
}

/// A nonlinear damper on one axis, beside the linear damping.
#[derive(Debug, Clone, PartialEq)]
pub enum DamperLaw {
    /// Bilinear (a blow-off valve): F = c₁ v for |v| ≤ v_b, then
    /// F = (c₁ v_b + c₂ (|v| − v_b)) sign v.
    Bilinear {
        damping_n_s_m: f64,
        blow_off_m_s: f64,
        damping_beyond_n_s_m: f64,
    },
    /// A force–velocity table F(v) (N against m/s).
    Table(PiecewiseLinear),
}

impl DamperLaw {
    /// Checks the coefficients (the table is checked when built).
    pub fn validate(&self) -> Result<(), LawError> {
        match self {
            Self::Bilinear {
                damping_n_s_m,
                blow_off_m_s,
                damping_beyond_n_s_m,
            } => {
                check("damping below the blow-off (N·s/m)", *damping_n_s_m, false)?;
                check("blow-off velocity (m/s)", *blow_off_m_s, true)?;
                check(
                    "damping beyond the blow-off (N·s/m)",
                    *damping_beyond_n_s_m,
                    false,
                )
            }
            Self::Table(_) => Ok(()),
        }
    }

    /// Restoring force F(v) (N) at the deflection rate v (m/s); F v ≥ 0.
    pub fn force_n(&self, rate_m_s: f64) -> f64 {
        match self {
            Self::Bilinear {
                damping_n_s_m,
                blow_off_m_s,
                damping_beyond_n_s_m,
            } => {
                let speed = rate_m_s.abs();
                if speed <= *blow_off_m_s {
                    damping_n_s_m * rate_m_s
                } else {
                    (damping_n_s_m * blow_off_m_s + damping_beyond_n_s_m * (speed - blow_off_m_s))
                        * rate_m_s.signum()
                }
            }
            Self::Table(t) => t.value(rate_m_s),
        }
    }
}

/// A spring in series with a damper on one axis (a damper with its rubber
/// bush; a Maxwell element: Iwnicki (ed.), *Handbook of Railway Vehicle
/// Dynamics*, suspension components, damper models with series
/// stiffness). Internal state: the damper's stroke q (m); the spring's
/// deflection is δ − q. See [`crate::multibody::element::series`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeriesLaw {
    /// The series spring (the bush) (N/m), > 0.
    pub stiffness_n_m: f64,
    /// The damper (N·s/m), > 0.
    pub damping_n_s_m: f64,
}

impl SeriesLaw {
    pub fn validate(&self) -> Result<(), LawError> {
        check("series stiffness (N/m)", self.stiffness_n_m, true)?;
        check("series damping (N·s/m)", self.damping_n_s_m, true)
    }
}

/// The nonlinear additions of one axis.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AxisLaws {
    pub spring: Option<SpringLaw>,
    pub damper: Option<DamperLaw>,
    pub series: Option<SeriesLaw>,
}

impl AxisLaws {
    pub fn validate(&self) -> Result<(), LawError> {
        if let Some(s) = &self.spring {
            s.validate()?;
        }
        if let Some(d) = &self.damper {
            d.validate()?;
        }
        if let Some(s) = &self.series {
            s.validate()?;
        }
        Ok(())
    }

    /// Whether there is nothing beyond the linear part.
    pub fn is_linear(&self) -> bool {
        self.spring.is_none() && self.damper.is_none() && self.series.is_none()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> PiecewiseLinear {
        PiecewiseLinear::new(vec![-0.02, 0.0, 0.01, 0.03], vec![-4e3, 0.0, 1e3, 5e3]).unwrap()
    }

    /// Bump stop, 15 mm clearance, 2 MN/m: 0 inside, k (|δ| − c) beyond,
    /// odd; energy ½ k (|δ| − c)².
    #[test]
    fn bump_stop_inside_and_outside_the_clearance() {
        let s = SpringLaw::BumpStop {
            clearance_m: 0.015,
            stiffness_n_m: 2e6,
        };
        assert_eq!(s.force_n(0.0), 0.0);
        assert_eq!(s.force_n(0.010), 0.0);
        assert_eq!(s.force_n(-0.015), 0.0);
        assert!((s.force_n(0.020) - 1e4).abs() < 1e-6);
        assert!((s.force_n(-0.025) + 2e4).abs() < 1e-6);
        assert_eq!(s.energy_j(0.01), 0.0);
        assert!((s.energy_j(-0.025) - 0.5 * 2e6 * 0.01 * 0.01).abs() < 1e-9);
        assert_eq!(s.stiffness_at_zero_n_m(), 0.0);
        let touching = SpringLaw::BumpStop {
            clearance_m: 0.0,
            stiffness_n_m: 2e6,
        };
        assert_eq!(touching.stiffness_at_zero_n_m(), 2e6);
    }

    /// Yaw damper: c₁ = 2 MN·s/m up to 0.02 m/s (40 kN), c₂ = 0.1 MN·s/m
    /// beyond: F(0.01) = 20 kN, F(0.05) = 40 + 3 = 43 kN, F(−0.05) = −43 kN.
    #[test]
    fn bilinear_damper_below_and_above_blow_off() {
        let d = DamperLaw::Bilinear {
            damping_n_s_m: 2e6,
            blow_off_m_s: 0.02,
            damping_beyond_n_s_m: 1e5,
        };
        assert!((d.force_n(0.01) - 2e4).abs() < 1e-6);
        assert!((d.force_n(0.02) - 4e4).abs() < 1e-6);
        assert!((d.force_n(0.05) - 4.3e4).abs() < 1e-6);
        assert!((d.force_n(-0.05) + 4.3e4).abs() < 1e-6);
        d.validate().unwrap();
        let bad = DamperLaw::Bilinear {
            damping_n_s_m: 2e6,
            blow_off_m_s: 0.0,
            damping_beyond_n_s_m: 1e5,
        };
        assert!(matches!(
            bad.validate(),
            Err(LawError::Coefficient {
                what: "blow-off velocity (m/s)",
                ..
            })
        ));
    }

    /// Table: interpolation, extrapolation with the end slopes, the exact
    /// integral, the slope at 0.
    #[test]
    fn table_values_integral_and_slope() {
        let t = table();
        assert!((t.value(0.005) - 500.0).abs() < 1e-9);
        assert!((t.value(-0.01) + 2000.0).abs() < 1e-9);
        assert!((t.value(0.04) - 7000.0).abs() < 1e-9); // slope 2e5 beyond
        assert!((t.value(-0.03) + 6000.0).abs() < 1e-9); // slope 2e5 before
        // ∫₀^0.03: ½·1e3·0.01 + ½(1e3 + 5e3)·0.02 = 5 + 60 = 65 J.
        assert!((t.integral_from_zero(0.03) - 65.0).abs() < 1e-9);
        // ∫₀^−0.02 F dξ = ½·(−4e3)·(−0.02) = 40 J.
        assert!((t.integral_from_zero(-0.02) - 40.0).abs() < 1e-9);
        // Slopes 2e5 left of 0 and 1e5 right.
        assert!((t.slope_at_zero() - 1.5e5).abs() < 1e-6);
        let spring = SpringLaw::Table(t.clone());
        assert_eq!(spring.force_n(0.005), t.value(0.005));
        let damper = DamperLaw::Table(t);
        assert!(damper.force_n(-0.01) * -0.01 > 0.0);
    }

    #[test]
    fn table_rules_are_named() {
        let rule = |x: Vec<f64>, y: Vec<f64>| match PiecewiseLinear::new(x, y) {
            Err(LawError::Table { rule }) => rule,
            other => panic!("{other:?}"),
        };
        assert!(rule(vec![0.0], vec![0.0]).contains("two points"));
        assert!(rule(vec![0.0, 1.0], vec![0.0]).contains("as many"));
        assert!(rule(vec![0.0, 0.0], vec![0.0, 1.0]).contains("increasing"));
        assert!(rule(vec![0.0, 1.0], vec![0.0, -1.0]).contains("non-decreasing"));
        assert!(rule(vec![0.0, 1.0], vec![1.0, 2.0]).contains("(0, 0)"));
        assert!(rule(vec![0.0, f64::NAN], vec![0.0, 2.0]).contains("finite"));
    }
}
