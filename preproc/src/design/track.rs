//! The evaluated design track (docs/reference/03-track-preproc.md §3h):
//! the plan elements placed one after the other (position and heading
//! continuous), the vertical profile and the cant, evaluated at any track
//! distance s (the 3D arc length). Curvature, heading, grade, cant and cant
//! rate are the element formulas' closed forms; the plan position is their
//! quadrature ([`super::element`]).

use nalgebra::Vector3;

use super::cant::CantRamp;
use super::cubic_parabola::CubicParabola;
use super::element::{PlanElement, PlanShape};
use super::file::{DesignInput, ElementKind, TransitionShape};
use super::vertical::{Vertical, VerticalElement};
use crate::error::InputError;
use crate::space_curve::CurvePoint;

/// The design track at one track distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DesignPoint {
    /// Track distance s (3D arc length, m).
    pub s_m: f64,
    /// Plan distance σ (m); equal to s on level track.
    pub sigma_m: f64,
    /// Position (m).
    pub position: Vector3<f64>,
    /// Heading θ of the plan tangent to +X (rad).
    pub heading_rad: f64,
    /// Signed plan curvature κ = dθ/dσ (1/m; > 0 turning left).
    pub curvature_1_m: f64,
    /// dκ/dσ (1/m²).
    pub curvature_rate_1_m2: f64,
    /// Grade g = dz/dσ and its rate dg/dσ (1/m).
    pub grade: f64,
    pub grade_rate_1_m: f64,
    /// Cant φ (rad; > 0 left rail higher) and its rate dφ/ds (rad/m).
    pub cant_rad: f64,
    pub cant_rate_rad_m: f64,
}

impl DesignPoint {
    /// Position and derivatives with respect to τ = s: d1 the unit
    /// tangent, d2 = dt/ds, d3 = d²t/ds², from the formulas. With
    /// t̂ = (cos θ, sin θ, g), w = dσ/ds = (1 + g²)^{-1/2}:
    /// d1 = w t̂, d2 = w w' t̂ + w² t̂', d3 = w[(w w')' t̂ + 3 w w' t̂' + w² t̂'']
    /// (' = d/dσ; t̂' = (−κ sin θ, κ cos θ, g'),
    /// t̂'' = (−κ' sin θ − κ² cos θ, κ' cos θ − κ² sin θ, 0) on parabolic
    /// vertical curves).
    pub fn curve_point(&self) -> CurvePoint {
        let (c, s) = (self.heading_rad.cos(), self.heading_rad.sin());
        let (k, dk, g, dg) = (
            self.curvature_1_m,
            self.curvature_rate_1_m2,
            self.grade,
            self.grade_rate_1_m,
        );
        let w = 1.0 / (1.0 + g * g).sqrt();
        let w1 = -g * dg * w.powi(3);
        let w2 = -(dg * dg) * w.powi(3) - 3.0 * g * dg * w * w * w1;
        let t = Vector3::new(c, s, g);
        let t1 = Vector3::new(-k * s, k * c, dg);
        let t2 = Vector3::new(-dk * s - k * k * c, dk * c - k * k * s, 0.0);
        let a = w * w1;
        let a1 = w1 * w1 + w * w2;
        CurvePoint {
            tau: self.s_m,
            r: self.position,
            d1: w * t,
            d2: a * t + w * w * t1,
            d3: w * (a1 * t + 3.0 * a * t1 + w * w * t2),
        }
    }
}

/// A design track ready to evaluate.
#[derive(Debug, Clone)]
pub struct DesignTrack {
    pub(super) elements: Vec<PlanElement>,
    pub(super) cant: Vec<CantRamp>,
    /// Plan distance σ at the start of each element (m).
    pub(super) sigma_start_m: Vec<f64>,
    pub(super) vertical: Vertical,
    /// Track distance s at each element joint, first 0, last the length (m).
    pub(super) joints_s_m: Vec<f64>,
}

impl DesignTrack {
    /// Place the elements of `input` one after the other.
    pub fn build(input: &DesignInput) -> Result<Self, InputError> {
        let mut elements: Vec<PlanElement> = Vec::with_capacity(input.elements.len());
        let mut sigma_start_m = Vec::with_capacity(input.elements.len());
        let mut at = [input.start.x_m, input.start.y_m];
        let mut heading = input.start.heading_rad;
        let mut sigma = 0.0;
        for e in &input.elements {
            let shape = match e.kind {
                ElementKind::Straight => PlanShape::Straight,
                ElementKind::Arc => PlanShape::Arc,
                ElementKind::Transition(TransitionShape::Ramp(r)) => PlanShape::Transition(r),
                ElementKind::Transition(TransitionShape::CubicParabola) => {
                    let entry = e.kappa_start_1_m == 0.0;
                    let k = if entry {
                        e.kappa_end_1_m
                    } else {
                        e.kappa_start_1_m
                    };
                    let parabola = CubicParabola::new(e.length_m, k.abs()).ok_or_else(|| {
                        InputError::new(
                            &input.path,
                            Some(e.line),
                            format!(
                                "no cubic parabola reaches the radius {:.3} m in {} m: its curvature peaks where its slope is 1/√5 (κL ≤ 0.78); lengthen it or use a clothoid",
                                1.0 / k.abs(),
                                e.length_m
                            ),
                        )
                    })?;
                    PlanShape::CubicParabola { parabola, entry }
                }
            };
            let placed = PlanElement::new(
                shape,
                e.length_m,
                e.kappa_start_1_m,
                e.kappa_end_1_m,
                at,
                heading,
            );
            at = placed.end();
            heading = placed.heading_end();
            sigma_start_m.push(sigma);
            sigma += e.length_m;
            elements.push(placed);
        }
        let vertical = if input.vertical.is_empty() {
            Vertical::new(vec![VerticalElement {
                sigma_start_m: 0.0,
                length_m: sigma,
                z_start_m: input.start.z_m,
                grade_start: 0.0,
                grade_end: 0.0,
            }])
        } else {
            let mut v = Vec::with_capacity(input.vertical.len());
            let (mut s0, mut z0) = (0.0, input.start.z_m);
            for spec in &input.vertical {
                let e = VerticalElement {
                    sigma_start_m: s0,
                    length_m: spec.length_m,
                    z_start_m: z0,
                    grade_start: spec.grade_start,
                    grade_end: spec.grade_end,
                };
                z0 = e.at(spec.length_m).z_m;
                s0 += spec.length_m;
                v.push(e);
            }
            Vertical::new(v)
        };
        let mut joints_s_m: Vec<f64> = sigma_start_m.iter().map(|&s| vertical.s_at(s)).collect();
        joints_s_m.push(vertical.length_m());
        Ok(Self {
            cant: input.elements.iter().map(|e| e.cant).collect(),
            elements,
            sigma_start_m,
            vertical,
            joints_s_m,
        })
    }

    /// Track length s (m).
    pub fn length_m(&self) -> f64 {
        self.joints_s_m[self.joints_s_m.len() - 1]
    }

    /// Track distance of each element joint, from 0 to the length (m).
    pub fn joints_s_m(&self) -> &[f64] {
        &self.joints_s_m
    }

    /// The element holding σ.
    fn element_at(&self, sigma_m: f64) -> usize {
        self.sigma_start_m
            .partition_point(|&s| s <= sigma_m)
            .saturating_sub(1)
    }

    /// Cant φ (rad) at s (clamped to the track).
    pub fn cant_at(&self, s_m: f64) -> f64 {
        self.at(s_m).cant_rad
    }

    /// The track at s (clamped to [0, length]).
    pub fn at(&self, s_m: f64) -> DesignPoint {
        let s_m = s_m.clamp(0.0, self.length_m());
        let sigma_m = self.vertical.sigma_at(s_m);
        let k = self.element_at(sigma_m);
        let e = &self.elements[k];
        let local = (sigma_m - self.sigma_start_m[k]).clamp(0.0, e.length_m);
        let p = e.at(local);
        let v = self.vertical.at(sigma_m);
        let w = 1.0 / (1.0 + v.grade * v.grade).sqrt();
        let (cant_rad, dphi_dsigma) = self.cant[k].at(local / e.length_m, e.length_m);
        DesignPoint {
            s_m,
            sigma_m,
            position: Vector3::new(p.x_m, p.y_m, v.z_m),
            heading_rad: p.heading_rad,
            curvature_1_m: p.kappa_1_m,
            curvature_rate_1_m2: p.dkappa_1_m2,
            grade: v.grade,
            grade_rate_1_m: v.grade_rate_1_m,
            cant_rad,
            cant_rate_rad_m: dphi_dsigma * w,
        }
    }
}
