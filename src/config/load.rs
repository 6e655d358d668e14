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
//! whose preload is the force (`runtime::multibody::element`: f = f₀ − K(Δ − Δ₀) −
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
use serde::{Deserialize, Serialize};

/// Lever arm of the couple that makes the yaw moment (m).
pub const YAW_COUPLE_ARM_M: f64 = 1.0;
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
