//! Nadal's flange-climbing limit (Nadal 1908; see Iwnicki (ed.), *Handbook
//! of Railway Vehicle Dynamics*, 2006, ch. 8 "Derailment", and EN 14363
//! §7.6.3 for its use as an acceptance criterion).
//!
//! # The criterion
//!
//! A flange in contact with its rail at flange angle γ (the slope of the
//! flange flank from the axle direction, i.e. the contact angle at the
//! flange) and friction coefficient μ starts climbing when the ratio of the
//! lateral force Y to the vertical force Q on the wheel exceeds
//!
//! ```text
//! (Y/Q)_lim = (tan γ − μ) / (1 + μ tan γ)
//! ```
//!
//! (equilibrium of the flange contact with the friction force saturated and
//! pointing down the flank, i.e. a positive angle of attack; Nadal 1908).
//! The steepest point of the flank gives the largest limit and is the value
//! used by the standards: 70° and μ = 0.3 give 1.34, 75° gives 1.62.
//!
//! # Sign convention
//!
//! Y is the lateral force **on the wheel** in the track frame, positive
//! towards the track centre (for the left wheel along −n, for the right
//! wheel along +n: the force with which the rail pushes a flanging wheel
//! back, the one that pushes its flange up the rail), summed over every
//! contact of the wheel (tread and flange). Q is the vertical force on the
//! wheel along the track's up axis b (the wheel load, > 0 in contact).
//! Both are in N; Y/Q is dimensionless and undefined (NaN) while the
//! wheel has no contact.

use crate::geometry::profile::{WheelProfile, Zone};

/// Sampling step along the flange flank when looking for its steepest
/// point (m): 0.05 mm, well below the profile's point spacing.
const FLANK_STEP_M: f64 = 5e-5;

/// The steepest flank angle of the wheel's flange (rad): the largest
/// atan(−dz/du) between the start of the flange function(s) and the
/// flange tip, in the profile's internal convention (u towards the track
/// centre, z up, radius R0 − z: the active flank descends towards the
/// tip). `None` for a profile without a flange.
pub fn max_flange_angle_rad(wheel: &WheelProfile) -> Option<f64> {
    let tip = wheel.flange_tip_u_m()?;
    let mut best: Option<f64> = None;
    for seg in wheel.zone_segments(Zone::Flange) {
        let (u0, u1) = seg.curve.domain_m();
        let end = u1.min(tip);
        if end <= u0 {
            continue;
        }
        let n = ((end - u0) / FLANK_STEP_M).ceil().max(1.0) as usize;
        for k in 0..=n {
            let u = u0 + (end - u0) * k as f64 / n as f64;
            let slope = -seg.curve.at(u).dz;
            if slope.is_finite() {
                let angle = slope.atan();
                best = Some(best.map_or(angle, |b: f64| b.max(angle)));
            }
        }
    }
    best
}

/// Nadal's limit (Y/Q)_lim = (tan γ − μ)/(1 + μ tan γ) for flange angle
/// `flange_angle_rad` (γ, rad) and friction coefficient `friction` (μ ≥ 0,
/// dimensionless); module docs. Equal to tan(γ − atan μ).
pub fn nadal_limit(flange_angle_rad: f64, friction: f64) -> f64 {
    let t = flange_angle_rad.tan();
    (t - friction) / (1.0 + friction * t)
}

/// The Nadal data of one wheel: its steepest flange angle, the friction
/// coefficient and the resulting limit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NadalLimit {
    /// Steepest flank angle γ (rad), [`max_flange_angle_rad`].
    pub flange_angle_rad: f64,
    /// Friction coefficient μ (dimensionless).
    pub friction: f64,
    /// (tan γ − μ)/(1 + μ tan γ) (dimensionless).
    pub limit: f64,
}

impl NadalLimit {
    /// For `wheel` at friction `friction`; `None` without a flange.
    pub fn of_wheel(wheel: &WheelProfile, friction: f64) -> Option<Self> {
        let gamma = max_flange_angle_rad(wheel)?;
        Some(Self {
            flange_angle_rad: gamma,
            friction,
            limit: nadal_limit(gamma, friction),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nadal_limit_textbook_values() {
        // 70°, μ = 0.3 → 1.34 (the usual quoted value); 75° → 1.62.
        let l70 = nadal_limit(70f64.to_radians(), 0.3);
        assert!((l70 - 1.341_64).abs() < 1e-5, "{l70}");
        let l75 = nadal_limit(75f64.to_radians(), 0.3);
        assert!((l75 - 1.619_19).abs() < 1e-5, "{l75}");
        // tan(γ − atan μ) identity; frictionless: tan γ.
        for (g, mu) in [(60f64, 0.1), (72.0, 0.5), (80.0, 0.25)] {
            let g = g.to_radians();
            assert!((nadal_limit(g, mu) - (g - mu.atan()).tan()).abs() < 1e-12);
        }
        assert!((nadal_limit(1.0, 0.0) - 1f64.tan()).abs() < 1e-15);
        // More friction, lower limit.
        assert!(nadal_limit(1.2, 0.5) < nadal_limit(1.2, 0.2));
    }
}
