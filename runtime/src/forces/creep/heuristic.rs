//! Shen–Hedrick–Elkins heuristic creep law (paper eq. 24–26; Z. Y. Shen,
//! J. K. Hedrick, J. A. Elkins, "A comparison of alternative creep force
//! models for rail vehicle dynamic analysis", Proc. 8th IAVSD Symposium,
//! 1983, pp. 591–605).
//!
//! The Kalker linear forces Fx′, Fy′ (paper eq. 23, spin included in Fy′)
//! are saturated along their resultant F′ = √(Fx′² + Fy′²) with the
//! Johnson–Vermeulen cubic, u = F′/(μN):
//!
//! ```text
//! F = μN (u − u²/3 + u³/27)   for u ≤ 3,     F = μN   for u > 3,
//! Fx = Fx′ F/F′,  Fy = Fy′ F/F′,  Mz = 0 (spin moment neglected, docs/reference/07-contact-forces.md §7.3)
//! ```
//!
//! The scale factor F/F′ = 1 − u/3 + u²/27 (u ≤ 3) or 1/u (u > 3) is
//! evaluated in that form, so F′ = 0 needs no division. The cubic has zero
//! slope at u = 3, where F = μN: the law is C¹ and |F| ≤ μN everywhere. As
//! u → 0 it tends to Kalker's linear law (F/F′ = 1 − u/3 + …).

use super::kalker::linear_forces;
use super::{CreepError, CreepForces, CreepInput};

/// Heuristic forces on the wheel (module docs); input already validated,
/// N > 0.
pub(crate) fn forces(input: &CreepInput) -> Result<CreepForces, CreepError> {
    let linear = linear_forces(input)?;
    let limit_n = input.friction_coefficient * input.normal_force_n;
    if limit_n == 0.0 {
        return Ok(CreepForces::ZERO);
    }
    let u = linear.tangential_n() / limit_n;
    let scale = saturation_ratio(u);
    Ok(CreepForces {
        fx_n: linear.fx_n * scale,
        fy_n: linear.fy_n * scale,
        mz_nm: 0.0,
    })
}

/// The heuristic law (module docs) on Kalker's linear forces built from
/// **given** coefficients instead of Kalker's table at the ellipse ratio:
/// for contact data that carry their own C11, C22, C23 (an imported contact
/// table, [`crate::multibody::imported_contact`]). With `saturate = false`
/// the Kalker linear forces themselves. Such data have no C33: the spin
/// moment is neglected either way (Mz = 0, as in the Shen–Hedrick–Elkins
/// law). `c.c33` is not used. The input is validated here.
pub fn heuristic_with_coefficients(
    input: &CreepInput,
    c: &super::KalkerCoefficients,
    saturate: bool,
) -> Result<CreepForces, CreepError> {
    input.validate()?;
    if input.normal_force_n == 0.0 {
        return Ok(CreepForces::ZERO);
    }
    let linear = super::kalker::linear_forces_with(input, c);
    let limit_n = input.friction_coefficient * input.normal_force_n;
    let scale = if !saturate {
        1.0
    } else if limit_n == 0.0 {
        0.0
    } else {
        saturation_ratio(linear.tangential_n() / limit_n)
    };
    Ok(CreepForces {
        fx_n: linear.fx_n * scale,
        fy_n: linear.fy_n * scale,
        mz_nm: 0.0,
    })
}

/// F/F′ as a function of u = F′/(μN) ≥ 0 (module docs).
fn saturation_ratio(u: f64) -> f64 {
    if u <= 3.0 {
        1.0 - u / 3.0 + u * u / 27.0
    } else {
        1.0 / u
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn saturation_curve_is_continuous_and_bounded() {
        // F/μN = u · ratio(u): 0 at 0, 1 at u = 3 from both sides, never > 1,
        // non-decreasing.
        let mut last = 0.0;
        for k in 0..=6000 {
            let u = k as f64 * 1e-3;
            let f = u * saturation_ratio(u);
            assert!(f <= 1.0 + 1e-15 && f >= last - 1e-15, "u = {u}: {f}");
            last = f;
        }
        assert!((3.0 * saturation_ratio(3.0) - 1.0).abs() < 1e-15);
        assert!((3.000001 * saturation_ratio(3.000001) - 1.0).abs() < 1e-15);
        assert_eq!(saturation_ratio(0.0), 1.0);
    }
}
