//! Options of a track build, with their defaults and the rules they must
//! keep ([`BuildConfig::validate`]).

use std::fmt;
use std::str::FromStr;

use runtime::geometry::spline::Scheme;

use crate::bounds::{
    CANT_BASE_RANGE_M, GAUGE_FACE_OFFSET_RANGE_M, GAUGE_RANGE_M, RAIL_SPACING_RANGE_M,
    STEP_RANGE_M, within,
};
use crate::error::BuildError;

/// Default table step Δs (m) (docs/reference/03-track-preproc.md §3g).
pub const DEFAULT_STEP_M: f64 = 0.1;
/// Default track gauge (m): standard gauge.
pub const DEFAULT_GAUGE_M: f64 = 1.435;
/// Default lateral distance from a rail's profile origin (the rail head's
/// centre line) to its gauge face at the gauge measuring height (m): half the
/// 72 mm head width of UIC60/UIC54 rails. With 1435 mm gauge this gives a
/// rail spacing of 1.507 m.
pub const DEFAULT_GAUGE_FACE_OFFSET_M: f64 = 0.036;
/// Distance between the rail contact points minus the gauge (m), used for
/// the default cant base e0 = gauge + 0.065 (1.500 m for standard gauge,
/// docs/reference/01-units-frames.md §1).
pub const CANT_BASE_OVER_GAUGE_M: f64 = 0.065;

/// The rail inclination of every command and scene when none is given:
/// 1:40, the most common inclination of European main lines (1:20 is the
/// other in use, on older and Iberian track), applied to the rail profile
/// as drawn in its file, i.e. meant for upright profiles. A file already canted (the shipped
/// `MBench_UIC60_v3.prr`) is detected and refused with it
/// (`runtime::geometry::profile::rail_cant`; docs/reference/05-surfaces.md §5.7).
pub const DEFAULT_RAIL_INCLINATION: &str = "1:40";

/// The default spline scheme of the cant: `pchip` (Fritsch–Carlson),
/// shape-preserving, so a cant ramp written as a few control points stays
/// within its end values — the not-a-knot cubic rings on a ramp (−5.8 mm
/// before a 0 → 120 mm ramp and a 124.3 mm peak; preproc/tests/design_track.rs).
pub const DEFAULT_CANT_SCHEME: Scheme = Scheme::Pchip;

/// How far apart the two rail space curves (the rails' profile origins) are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RailSpacing {
    /// gauge + 2 × offset of the gauge face from the profile origin (m).
    FromGauge { gauge_face_offset_m: f64 },
    /// Given directly (m).
    Explicit { spacing_m: f64 },
}

impl Default for RailSpacing {
    fn default() -> Self {
        RailSpacing::FromGauge {
            gauge_face_offset_m: DEFAULT_GAUGE_FACE_OFFSET_M,
        }
    }
}

/// Rail inclination: the rail profiles are turned about the rail tangent
/// towards the track centre by atan(1/n) for "1:n".
#[derive(Debug, Clone, PartialEq)]
pub struct Inclination {
    /// As the user wrote it ("1:40", "0", …).
    pub text: String,
    /// Angle (rad), ≥ 0 towards the track centre.
    pub angle_rad: f64,
}

impl Default for Inclination {
    fn default() -> Self {
        DEFAULT_RAIL_INCLINATION.parse().expect("valid default")
    }
}

impl fmt::Display for Inclination {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

impl FromStr for Inclination {
    type Err = String;
    /// Accepts `1:40`, `1/40` (a slope of one in forty), `0` (none) or a
    /// plain slope such as `0.025`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim();
        let bad = || {
            format!("rail inclination '{s}' is not of the form 1:40, 1/40, 0 or a slope like 0.025")
        };
        let slope = if let Some((a, b)) = t.split_once([':', '/']) {
            let a: f64 = a.trim().parse().map_err(|_| bad())?;
            let b: f64 = b.trim().parse().map_err(|_| bad())?;
            if !(a.is_finite() && b.is_finite()) || b <= 0.0 || a < 0.0 {
                return Err(bad());
            }
            a / b
        } else {
            let v: f64 = t.parse().map_err(|_| bad())?;
            if !v.is_finite() || v < 0.0 {
                return Err(bad());
            }
            v
        };
        if slope > 0.2 {
            return Err(format!(
                "rail inclination '{s}' (slope {slope}) is steeper than 1:5; rails are inclined 1:20 or 1:40"
            ));
        }
        Ok(Inclination {
            text: t.to_string(),
            angle_rad: slope.atan(),
        })
    }
}

/// Options of a track build.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildConfig {
    /// Spline scheme for the centreline and the rails (docs/reference/03-track-preproc.md §3a, f).
    pub scheme: Scheme,
    /// Spline scheme for the cant of control-point inputs
    /// (docs/reference/03-track-preproc.md §3c): default
    /// [`DEFAULT_CANT_SCHEME`].
    pub cant_scheme: Scheme,
    /// Table step Δs (m).
    pub step_m: f64,
    /// Nominal track gauge (m).
    pub gauge_m: f64,
    /// Distance between the rail space curves.
    pub rail_spacing: RailSpacing,
    /// Rail inclination towards the track centre.
    pub inclination: Inclination,
    /// Cant base e0 for cant heights (m); `None` = gauge + 0.065 m.
    pub cant_base_m: Option<f64>,
    /// The rail profile the track is built for, when known: checked against
    /// the inclination (double canting) and recorded in the table file
    /// with its SHA-256 and carried cant (docs/reference/04-table-files.md §4.1).
    pub rail_profile: Option<std::path::PathBuf>,
    /// The cant that profile carries as drawn, declared by the user
    /// (overrides detection; `--rail-profile-cant`).
    pub rail_profile_cant: Option<Inclination>,
}

impl Default for BuildConfig {
    fn default() -> Self {
        Self {
            scheme: Scheme::Cubic,
            cant_scheme: DEFAULT_CANT_SCHEME,
            step_m: DEFAULT_STEP_M,
            gauge_m: DEFAULT_GAUGE_M,
            rail_spacing: RailSpacing::default(),
            inclination: Inclination::default(),
            cant_base_m: None,
            rail_profile: None,
            rail_profile_cant: None,
        }
    }
}

impl BuildConfig {
    /// Lateral distance between the rail space curves (m).
    pub fn rail_spacing_m(&self) -> f64 {
        match self.rail_spacing {
            RailSpacing::FromGauge {
                gauge_face_offset_m,
            } => self.gauge_m + 2.0 * gauge_face_offset_m,
            RailSpacing::Explicit { spacing_m } => spacing_m,
        }
    }

    /// Cant base e0 (m).
    pub fn cant_base_m(&self) -> f64 {
        self.cant_base_m
            .unwrap_or(self.gauge_m + CANT_BASE_OVER_GAUGE_M)
    }

    /// Check every rule against its plausibility bound
    /// ([`crate::bounds`]); the message names the option, the bound and
    /// says "check the unit".
    pub fn validate(&self) -> Result<(), BuildError> {
        let check = |what: &str, value: f64, range: (f64, f64)| {
            if within(value, range) {
                Ok(())
            } else {
                Err(BuildError::Config(format!(
                    "{what} {value} m is outside the plausible {} … {} m (check the unit: metres)",
                    range.0, range.1
                )))
            }
        };
        check("--step", self.step_m, STEP_RANGE_M)?;
        check("--gauge", self.gauge_m, GAUGE_RANGE_M)?;
        if let RailSpacing::FromGauge {
            gauge_face_offset_m,
        } = self.rail_spacing
        {
            check(
                "--gauge-face-offset",
                gauge_face_offset_m,
                GAUGE_FACE_OFFSET_RANGE_M,
            )?;
        }
        check(
            "rail spacing (--rail-spacing, or gauge + 2 × gauge-face offset)",
            self.rail_spacing_m(),
            RAIL_SPACING_RANGE_M,
        )?;
        check("--cant-base", self.cant_base_m(), CANT_BASE_RANGE_M)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inclination_forms() {
        let b: Inclination = "1:40".parse().unwrap();
        assert!((b.angle_rad - (1.0_f64 / 40.0).atan()).abs() < 1e-15);
        assert_eq!(
            "1/20".parse::<Inclination>().unwrap().angle_rad,
            (0.05_f64).atan()
        );
        assert_eq!("0".parse::<Inclination>().unwrap().angle_rad, 0.0);
        assert!("1:0".parse::<Inclination>().is_err());
        assert!("steep".parse::<Inclination>().is_err());
        assert!("1:2".parse::<Inclination>().is_err());
    }

    #[test]
    fn defaults_and_rules() {
        let c = BuildConfig::default();
        c.validate().unwrap();
        assert!((c.rail_spacing_m() - 1.507).abs() < 1e-12);
        assert!((c.cant_base_m() - 1.5).abs() < 1e-12);
        let bad = BuildConfig {
            step_m: 0.0,
            ..Default::default()
        };
        assert!(bad.validate().unwrap_err().to_string().contains("--step"));
        let bad = BuildConfig {
            gauge_m: f64::NAN,
            ..Default::default()
        };
        assert!(bad.validate().unwrap_err().to_string().contains("--gauge"));
    }

    /// Millimetres given for metres are refused with "check the unit",
    /// naming the option and the bound.
    #[test]
    fn options_in_the_wrong_unit() {
        for (bad, option) in [
            (
                BuildConfig {
                    gauge_m: 1435.0,
                    ..Default::default()
                },
                "--gauge 1435 m is outside the plausible 0.5 … 2 m",
            ),
            (
                BuildConfig {
                    step_m: 100.0,
                    ..Default::default()
                },
                "--step 100 m is outside the plausible 0.0001 … 10 m",
            ),
            (
                BuildConfig {
                    cant_base_m: Some(1500.0),
                    ..Default::default()
                },
                "--cant-base 1500 m",
            ),
            (
                BuildConfig {
                    rail_spacing: RailSpacing::Explicit { spacing_m: 1507.0 },
                    ..Default::default()
                },
                "rail spacing",
            ),
        ] {
            let e = bad.validate().unwrap_err().to_string();
            assert!(e.contains(option) && e.contains("check the unit"), "{e}");
        }
    }
}
