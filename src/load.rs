//! External loads and initial perturbations of the wheelsets, for the
//! extreme cases of a run (scene sections `[load]` and `[perturbation]`,
//! both optional):
//!
//! ```toml
//! [load]                      # constant, from t = 0, in the track frame
//! wheelset = 0                # vehicle order (0 = front); omitted: every wheelset
//! lateral_force_n = 20000.0   # on the wheelset centre along the track's lateral axis n, + left
//! yaw_moment_nm = 2000.0      # about the track's up axis b, + turning the nose left
//! yaw_stiffness_nm_rad = 5e6  # a yaw spring to the track frame (like a bogie's primary
//! yaw_angle_rad = 0.01        #   suspension), relaxed at this yaw: holds an angle of attack
//!
//! [perturbation]              # added to the settled initial state
//! wheelset = 0                # omitted: every wheelset
//! drop_m = 0.003              # lift above the settled position (m, >= 0): a drop onto the rails
//! lateral_velocity_m_s = 0.2  # initial lateral velocity, + left: a lateral impact on a flange
//! ```
//!
//! How the loads are applied: as elements of zero stiffness and damping
//! whose preload is the force (`runtime::element`: f = f₀ − K(Δ − Δ₀) −
//! CΔ̇ = f₀), between a track-following reference (its axes are the track
//! frame t, n, b at the wheelset, so the force follows the track) and the
//! wheelset's centre; the yaw moment is a couple of two such lateral
//! forces ±M/(2d) at d = 1 m ahead of and behind the centre; the yaw
//! spring is a pair of longitudinal springs at B = 1 m either side of the
//! centre, each k = k_ψ/(2B²), preloaded ∓k B ψ₀ (left, right) so that
//! their moment 2kB²(ψ₀ − ψ) vanishes at ψ₀ (they also tie the wheelset
//! longitudinally to the reference with 2k: a traction link), with dampers
//! c = c_ψ/(2B²) giving [`YAW_DAMPING_RATIO`] of the critical yaw damping
//! c_ψ = 2ζ√(k_ψ I_zz), so that the spring holds the angle instead of
//! ringing about it. The
//! reactions act on the references, which are not bodies: the loads are
//! external. Their potential −f₀·(Δ − Δ₀) enters the mechanical energy
//! like any element's.
//!
//! The perturbations move the wheelset after it was settled: `drop_m`
//! raises it along the track's up axis (its contacts open; the hysteresis
//! memory restarts at the first impact, paper eq. 22), and
//! `lateral_velocity_m_s` adds a velocity along the track's lateral axis.
//! Both are checked: the drop up to 20 mm, the velocity up to 2 m/s.

use anyhow::{Result, ensure};
use nalgebra::Vector3;
use runtime::body::BodyState;
use runtime::dynamics::track_motion::track_rotation;
use runtime::dynamics::{ElementSpec, End, ReferenceSpec, VehicleModel};
use runtime::track::TrackTables;
use serde::{Deserialize, Serialize};

/// Lever arm of the couple that makes the yaw moment (m).
const YAW_COUPLE_ARM_M: f64 = 1.0;
/// Fraction of the critical damping of the `[load]` yaw spring (ζ).
pub const YAW_DAMPING_RATIO: f64 = 0.2;
/// Largest accepted drop (m).
const MAX_DROP_M: f64 = 0.02;
/// Largest accepted initial lateral velocity (m/s).
const MAX_LATERAL_VELOCITY_M_S: f64 = 2.0;

/// `[load]`: constant external loads on the wheelsets (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct LoadSection {
    /// Wheelset index in vehicle order (0 = front); `None`: every wheelset.
    #[serde(default)]
    pub wheelset: Option<usize>,
    /// Force on the wheelset centre along the track's lateral axis (N), + left.
    #[serde(default)]
    pub lateral_force_n: f64,
    /// Moment about the track's up axis (N·m), + turning the nose left
    /// (the yaw sign of the results).
    #[serde(default)]
    pub yaw_moment_nm: f64,
    /// Yaw stiffness to the track frame (N·m/rad, ≥ 0); 0: none.
    #[serde(default)]
    pub yaw_stiffness_nm_rad: f64,
    /// Yaw at which that spring is relaxed (rad), + nose left.
    #[serde(default)]
    pub yaw_angle_rad: f64,
}

/// `[perturbation]`: changes to the settled initial state (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct PerturbationSection {
    /// Wheelset index in vehicle order; `None`: every wheelset.
    #[serde(default)]
    pub wheelset: Option<usize>,
    /// Lift above the settled position at t = 0 (m, ≥ 0).
    #[serde(default)]
    pub drop_m: f64,
    /// Lateral velocity at t = 0 (m/s), + left.
    #[serde(default)]
    pub lateral_velocity_m_s: f64,
}

impl LoadSection {
    /// Checks the values, naming the entry.
    pub fn validate(&self) -> Result<()> {
        ensure!(
            self.lateral_force_n.is_finite() && self.lateral_force_n.abs() <= 1e6,
            "[load] lateral_force_n = {} must be finite and within ±1e6 N",
            self.lateral_force_n
        );
        ensure!(
            self.yaw_moment_nm.is_finite() && self.yaw_moment_nm.abs() <= 1e6,
            "[load] yaw_moment_nm = {} must be finite and within ±1e6 N·m",
            self.yaw_moment_nm
        );
        ensure!(
            self.yaw_stiffness_nm_rad.is_finite()
                && (0.0..=1e9).contains(&self.yaw_stiffness_nm_rad),
            "[load] yaw_stiffness_nm_rad = {} must lie in [0, 1e9] N·m/rad",
            self.yaw_stiffness_nm_rad
        );
        ensure!(
            self.yaw_angle_rad.is_finite() && self.yaw_angle_rad.abs() <= 0.05,
            "[load] yaw_angle_rad = {} must lie within ±0.05 rad",
            self.yaw_angle_rad
        );
        ensure!(
            self.yaw_angle_rad == 0.0 || self.yaw_stiffness_nm_rad > 0.0,
            "[load] yaw_angle_rad needs yaw_stiffness_nm_rad > 0"
        );
        Ok(())
    }
}

impl PerturbationSection {
    /// Checks the values, naming the entry.
    pub fn validate(&self) -> Result<()> {
        ensure!(
            self.drop_m.is_finite() && (0.0..=MAX_DROP_M).contains(&self.drop_m),
            "[perturbation] drop_m = {} must lie in [0, {MAX_DROP_M}] m",
            self.drop_m
        );
        ensure!(
            self.lateral_velocity_m_s.is_finite()
                && self.lateral_velocity_m_s.abs() <= MAX_LATERAL_VELOCITY_M_S,
            "[perturbation] lateral_velocity_m_s = {} must lie within ±{MAX_LATERAL_VELOCITY_M_S} m/s",
            self.lateral_velocity_m_s
        );
        Ok(())
    }
}

/// The wheelsets a section applies to.
fn targets(wheelset: Option<usize>, n: usize, section: &str) -> Result<Vec<usize>> {
    match wheelset {
        Some(i) => {
            ensure!(
                i < n,
                "[{section}] wheelset = {i}: the vehicle has {n} wheelset(s), numbered from 0"
            );
            Ok(vec![i])
        }
        None => Ok((0..n).collect()),
    }
}

/// Adds the `[load]` elements (and their track-following references) to
/// the vehicle (module docs).
pub fn add_loads(vehicle: &mut VehicleModel, load: &LoadSection) -> Result<()> {
    load.validate()?;
    if load.lateral_force_n == 0.0 && load.yaw_moment_nm == 0.0 && load.yaw_stiffness_nm_rad == 0.0
    {
        return Ok(());
    }
    for i in targets(load.wheelset, vehicle.wheelsets.len(), "load")? {
        let w = &vehicle.wheelsets[i];
        let centre = Vector3::new(w.x_m, w.y_m, w.nominal_radius_m);
        let name = w.name.clone();
        let yaw_inertia_kg_m2 = w.body.inertia_kg_m2[(2, 2)];
        let reference = vehicle.references.len();
        vehicle.references.push(ReferenceSpec {
            name: format!("[load] frame of '{name}'"),
            origin_m: centre,
        });
        let none = [0.0; 3];
        let mut element =
            |label: &str, at: Vector3<f64>, k: [f64; 3], c: [f64; 3], f0: Vector3<f64>| {
                let point = centre + at;
                vehicle.elements.push(ElementSpec {
                    name: format!("[load] {label} on '{name}'"),
                    a: End::Reference(reference),
                    b: End::Wheelset(i),
                    point_a_m: point,
                    point_b_m: point,
                    stiffness_n_m: k,
                    damping_n_s_m: c,
                    preload_n: f0,
                });
            };
        let lateral = |f: f64| Vector3::new(0.0, f, 0.0);
        let ahead = |d: f64| Vector3::new(d, 0.0, 0.0);
        if load.lateral_force_n != 0.0 {
            let f = lateral(load.lateral_force_n);
            element("lateral force", Vector3::zeros(), none, none, f);
        }
        if load.yaw_moment_nm != 0.0 {
            // r × F about b: (+d t) × (+F n) = +d F b, nose left.
            let f = load.yaw_moment_nm / (2.0 * YAW_COUPLE_ARM_M);
            element(
                "yaw moment, front",
                ahead(YAW_COUPLE_ARM_M),
                none,
                none,
                lateral(f),
            );
            element(
                "yaw moment, rear",
                ahead(-YAW_COUPLE_ARM_M),
                none,
                none,
                lateral(-f),
            );
        }
        if load.yaw_stiffness_nm_rad > 0.0 {
            let b = YAW_COUPLE_ARM_M;
            let k = load.yaw_stiffness_nm_rad / (2.0 * b * b);
            let c_yaw =
                2.0 * YAW_DAMPING_RATIO * (load.yaw_stiffness_nm_rad * yaw_inertia_kg_m2).sqrt();
            let c = c_yaw / (2.0 * b * b);
            let f0 = k * b * load.yaw_angle_rad;
            let side = |y: f64| Vector3::new(0.0, y, 0.0);
            let (kx, cx) = ([k, 0.0, 0.0], [c, 0.0, 0.0]);
            element("yaw spring, left", side(b), kx, cx, ahead(-f0));
            element("yaw spring, right", side(-b), kx, cx, ahead(f0));
        }
    }
    Ok(())
}

/// Applies the `[perturbation]` to the initial state `y0` (13 variables per
/// wheelset, wheelsets first: position, quaternion, velocity, body angular
/// velocity), in the track frame at each wheelset.
pub fn perturb(
    y0: &mut [f64],
    vehicle: &VehicleModel,
    track: &TrackTables,
    s_start_m: f64,
    p: &PerturbationSection,
) -> Result<()> {
    p.validate()?;
    if p.drop_m == 0.0 && p.lateral_velocity_m_s == 0.0 {
        return Ok(());
    }
    for i in targets(p.wheelset, vehicle.wheelsets.len(), "perturbation")? {
        let w = &vehicle.wheelsets[i];
        let frame = track_rotation(&track.centerline, s_start_m + w.x_m)?;
        let (n, b) = (frame.column(1).into_owned(), frame.column(2).into_owned());
        let slot = &mut y0[13 * i..13 * i + 13];
        let mut st = BodyState::read_from(slot);
        st.position_m += b * p.drop_m;
        st.velocity_m_s += n * p.lateral_velocity_m_s;
        st.write_to(slot);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_values_name_the_entry() {
        let e = LoadSection {
            lateral_force_n: f64::NAN,
            ..Default::default()
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().contains("[load] lateral_force_n"), "{e}");
        let e = PerturbationSection {
            drop_m: -0.001,
            ..Default::default()
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().contains("[perturbation] drop_m"), "{e}");
        let e = targets(Some(2), 1, "load").unwrap_err();
        assert!(e.to_string().contains("wheelset = 2"), "{e}");
        assert_eq!(targets(None, 3, "load").unwrap(), [0, 1, 2]);
    }
}
