//! Curving quantities derived from a sample's contact forces and
//! creepages, stored as their own series ([`super::columns`]):
//!
//! - the **wear number** Tγ of a contact zone (N): the creep forces'
//!   work per metre rolled, |Fx ξ| + |Fy η| + |Mz φ| (Pearce & Sherratt
//!   1991, "Prediction of wheel profile wear", Wear 144; the spin term
//!   Mz φ is included because both the spin moment and the spin creepage
//!   are stored; absolute values so that each term is a dissipation ≥ 0
//!   whatever the signs of force and creepage);
//! - the **track shifting force** ΣY of a wheelset (N): the sum of the
//!   lateral contact forces of both wheels (tread + flange) in the track
//!   plane, the force the wheelset puts on the track sideways (Prud'homme
//!   1970; EN 14363 §7.6's (ΣY)).
//!
//! Frames and signs: docs/reference/01-units-frames.md §1 (track `n` left).

use super::{WheelsetSample, ZoneSample};

/// Tγ of one zone (N; module docs): |Fx ξ| + |Fy η| + |Mz φ|; NaN out of
/// contact (or when a force or creepage is missing).
pub fn wear_number_n(z: &ZoneSample) -> f64 {
    if !z.in_contact {
        return f64::NAN;
    }
    (z.fx_n * z.xi).abs() + (z.fy_n * z.eta).abs() + (z.mz_nm * z.phi_1_m).abs()
}

/// Tγ of a wheel (N): the sum over its zones in contact; NaN when none is.
pub fn wheel_wear_number_n(zones: &[ZoneSample; 2]) -> f64 {
    zones
        .iter()
        .filter(|z| z.in_contact)
        .map(wear_number_n)
        .reduce(|a, b| a + b)
        .unwrap_or(f64::NAN)
}

/// ΣY of a wheelset (N; module docs): the lateral contact forces of both
/// wheels summed along the track's lateral axis, + left (on the
/// wheelset). With the wheels' Y (+ towards the track centre) it is
/// Y_right − Y_left. 0 when no zone of either wheel is in contact (an
/// airborne wheelset puts no force on the track).
pub fn sum_y_n(s: &WheelsetSample) -> f64 {
    s.wheels
        .iter()
        .flat_map(|w| w.zones.iter())
        .filter(|z| z.in_contact)
        .map(|z| z.lateral_force_n)
        .sum::<f64>()
        + 0.0
}

#[cfg(test)]
mod tests {
    use super::super::{WheelSample, wheel_y_q};
    use super::*;

    fn zone(lateral_n: f64, fx_n: f64, xi: f64, fy_n: f64, eta: f64) -> ZoneSample {
        ZoneSample {
            in_contact: true,
            lateral_force_n: lateral_n,
            vertical_force_n: 50e3,
            fx_n,
            xi,
            fy_n,
            eta,
            mz_nm: 0.0,
            phi_1_m: 0.0,
            ..ZoneSample::NO_CONTACT
        }
    }

    #[test]
    fn wear_number_sums_the_absolute_products() {
        // Creep forces oppose the creepages: each product is negative.
        let mut z = zone(0.0, -2000.0, 1e-3, 3000.0, -2e-3);
        assert!((wear_number_n(&z) - 8.0).abs() < 1e-12);
        z.mz_nm = 10.0;
        z.phi_1_m = -0.1;
        assert!((wear_number_n(&z) - 9.0).abs() < 1e-12);
        assert!(wear_number_n(&ZoneSample::NO_CONTACT).is_nan());
        let wheel = [z, zone(0.0, 100.0, 0.01, 0.0, 0.0)];
        assert!((wheel_wear_number_n(&wheel) - 10.0).abs() < 1e-12);
        assert!(wheel_wear_number_n(&[ZoneSample::NO_CONTACT; 2]).is_nan());
    }

    #[test]
    fn sum_y_is_the_net_lateral_force_and_y_right_minus_y_left() {
        // Left curve, outer (right) wheel flanging: the rail pushes the
        // wheelset left (+n) with 30 kN at the flange, the inner tread
        // pulls it right with 5 kN.
        let left = WheelSample {
            travelled_m: 0.0,
            zones: [zone(-5e3, 0.0, 0.0, 0.0, 0.0), ZoneSample::NO_CONTACT],
        };
        let right = WheelSample {
            travelled_m: 0.0,
            zones: [
                zone(2e3, 0.0, 0.0, 0.0, 0.0),
                zone(28e3, 0.0, 0.0, 0.0, 0.0),
            ],
        };
        let s = WheelsetSample {
            wheels: [left, right],
            ..WheelsetSample::default()
        };
        assert!((sum_y_n(&s) - 25e3).abs() < 1e-9);
        let (yl, _, _) = wheel_y_q(0, &left.zones);
        let (yr, _, _) = wheel_y_q(1, &right.zones);
        assert!((sum_y_n(&s) - (yr - yl)).abs() < 1e-9);
        // Airborne: no force on the track (+0.0, not the −0.0 of an empty sum).
        assert_eq!(
            sum_y_n(&WheelsetSample::default()).to_bits(),
            0f64.to_bits()
        );
    }
}
