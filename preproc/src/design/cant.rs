//! The cant along an element (docs/reference/03-track-preproc.md §3h): a
//! height h over the cant base e0 (`cant_mm`; φ = asin(h/e0), as the CSV
//! inputs convert it, docs/reference/01-units-frames.md §1.5) or an angle
//! φ (`cant_rad`), constant or ramped from its start value to its end
//! value with a linear or S-shaped ([`Ramp`]) ramp. The ramp shapes the
//! given quantity (h for heights, φ for angles).

use super::shape::Ramp;

/// The unit a cant is given in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CantUnit {
    /// Height over the cant base e0 (m), converted by φ = asin(h/e0).
    Height { cant_base_m: f64 },
    /// Angle (rad).
    Angle,
}

/// The cant of one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CantRamp {
    pub unit: CantUnit,
    /// Start and end value (m for heights, rad for angles).
    pub start: f64,
    pub end: f64,
    pub ramp: Ramp,
}

impl CantRamp {
    /// The value's angle φ (rad).
    pub fn angle_of(unit: CantUnit, v: f64) -> f64 {
        match unit {
            CantUnit::Height { cant_base_m } => (v / cant_base_m).asin(),
            CantUnit::Angle => v,
        }
    }

    /// Cant φ (rad) and dφ/dσ (rad/m) at u = σ/L of an element of
    /// length `length_m`.
    pub fn at(&self, u: f64, length_m: f64) -> (f64, f64) {
        let d = self.end - self.start;
        let v = self.start + d * self.ramp.f(u);
        let dv = d * self.ramp.df(u) / length_m;
        match self.unit {
            CantUnit::Height { cant_base_m } => (
                (v / cant_base_m).asin(),
                dv / (cant_base_m * cant_base_m - v * v).sqrt(),
            ),
            CantUnit::Angle => (v, dv),
        }
    }
}
