//! Shapes of transition curves and cant ramps as functions of the
//! normalised position u = σ/L ∈ [0, 1] along an element
//! (docs/reference/03-track-preproc.md §3h): the curvature (or the cant)
//! runs from its start value to its end value as `start + Δ·f(u)`.
//!
//! - linear (clothoid; linear cant ramp): f = u — the Euler spiral, used
//!   on most railways (EN 13803:2017 §6.6; Lindahl 2001, §2.2);
//! - Bloss: f = 3u² − 2u³ — Bloss, "Der Übergangsbogen mit geschwungener
//!   Überhöhungsrampe" (1936); curvature and cant rate zero at both ends
//!   (Lindahl 2001, §2.3; EN 13803 lists it among the S-shaped ramps);
//! - cosine (sinusoidal half-wave): f = (1 − cos πu)/2 — the other
//!   S-shaped transition of EN 13803 (Lindahl 2001, §2.3).
//!
//! Each shape also gives F(u) = ∫₀ᵘ f(v) dv in closed form, so the heading
//! θ = ∫κ dσ of a transition is closed form too.

use std::f64::consts::PI;

/// How a value runs from its start to its end over an element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ramp {
    /// f = u (clothoid, linear cant ramp).
    Linear,
    /// f = 3u² − 2u³ (Bloss 1936).
    Bloss,
    /// f = (1 − cos πu)/2 (sinusoidal).
    Cosine,
}

impl Ramp {
    /// The name used in design files.
    pub fn name(self) -> &'static str {
        match self {
            Ramp::Linear => "linear",
            Ramp::Bloss => "bloss",
            Ramp::Cosine => "cosine",
        }
    }

    /// f(u), f(0) = 0, f(1) = 1.
    pub fn f(self, u: f64) -> f64 {
        match self {
            Ramp::Linear => u,
            Ramp::Bloss => u * u * (3.0 - 2.0 * u),
            Ramp::Cosine => 0.5 * (1.0 - (PI * u).cos()),
        }
    }

    /// df/du.
    pub fn df(self, u: f64) -> f64 {
        match self {
            Ramp::Linear => 1.0,
            Ramp::Bloss => 6.0 * u * (1.0 - u),
            Ramp::Cosine => 0.5 * PI * (PI * u).sin(),
        }
    }

    /// d²f/du².
    pub fn d2f(self, u: f64) -> f64 {
        match self {
            Ramp::Linear => 0.0,
            Ramp::Bloss => 6.0 - 12.0 * u,
            Ramp::Cosine => 0.5 * PI * PI * (PI * u).cos(),
        }
    }

    /// F(u) = ∫₀ᵘ f(v) dv.
    pub fn integral(self, u: f64) -> f64 {
        match self {
            Ramp::Linear => 0.5 * u * u,
            Ramp::Bloss => u * u * u * (1.0 - 0.5 * u),
            Ramp::Cosine => 0.5 * u - (PI * u).sin() / (2.0 * PI),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f, its derivatives and its integral agree with each other
    /// (central differences; Simpson's rule).
    #[test]
    fn shapes_are_consistent() {
        for r in [Ramp::Linear, Ramp::Bloss, Ramp::Cosine] {
            assert_eq!(r.f(0.0), 0.0);
            assert!((r.f(1.0) - 1.0).abs() < 1e-15);
            let h = 1e-5;
            for k in 1..10 {
                let u = f64::from(k) / 10.0;
                let df = (r.f(u + h) - r.f(u - h)) / (2.0 * h);
                assert!((df - r.df(u)).abs() < 1e-8, "{r:?} {u}");
                let d2 = (r.df(u + h) - r.df(u - h)) / (2.0 * h);
                assert!((d2 - r.d2f(u)).abs() < 1e-7, "{r:?} {u}");
                let n = 200;
                let simpson: f64 = (0..n)
                    .map(|i| {
                        let (a, b) = (u * i as f64 / n as f64, u * (i + 1) as f64 / n as f64);
                        (b - a) / 6.0 * (r.f(a) + 4.0 * r.f(0.5 * (a + b)) + r.f(b))
                    })
                    .sum();
                assert!((simpson - r.integral(u)).abs() < 1e-12, "{r:?} {u}");
            }
        }
        // S-shaped ramps start and end with zero slope.
        assert_eq!(Ramp::Bloss.df(0.0), 0.0);
        assert!(Ramp::Cosine.df(1.0).abs() < 1e-15);
    }
}
