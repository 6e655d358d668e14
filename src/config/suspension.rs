//! The nonlinear parts of a vehicle file's elements
//! (docs/reference/11-vehicle-files.md; the laws: docs/reference/08-multibody.md §8.2):
//! per axis of `body_a`, a nonlinear spring (`spring.x|y|z`), a nonlinear
//! damper (`damper.x|y|z`) and a series spring–damper (`series.x|y|z`),
//! beside the element's linear `stiffness_n_m` and `damping_n_s_m`.
//!
//! ```toml
//! [elements.spring.y]             # lateral bump stop
//! kind = "bump_stop"
//! clearance_m = 0.025
//! stiffness_n_m = 2.0e6
//!
//! [elements.damper.x]             # yaw damper with a blow-off
//! kind = "bilinear"
//! damping_n_s_m = 2.0e6           # up to the blow-off
//! blow_off_m_s = 0.02
//! damping_beyond_n_s_m = 1.0e5
//!
//! [elements.series.x]             # its rubber bushes
//! stiffness_n_m = 6.0e6
//! damping_n_s_m = 2.0e6
//! ```
//!
//! Tables: `kind = "table"` with `deflection_m` and `force_n` (a spring) or
//! `velocity_m_s` and `force_n` (a damper).
//!
//! Plausibility bounds (a value outside is refused with "check the
//! unit"): the stiffest suspension parts of rail vehicles (rubber bushes,
//! traction rods) are 1e7–1e9 N/m and the softest useful bump stops or
//! bushes above 1e4 N/m, yaw dampers reach ~1e6–1e7 N·s/m (Iwnicki (ed.),
//! *Handbook of Railway Vehicle Dynamics*, CRC 2006, suspension
//! components): stiffness 1e3 … 1e10 N/m, damping 1e2 … 1e8 N·s/m (a
//! factor 100 or more outside, as a value in N/mm or kN/m would be);
//! clearances 0 … 0.2 m and table deflections within ±0.5 m (free play
//! of millimetres to a few centimetres; 15 meaning 15 mm would be 15 m);
//! blow-off velocities 1e-4 … 2 m/s (typically 0.01–0.1 m/s; 50 meaning
//! mm/s would be 50 m/s); table velocities within ±10 m/s; table forces
//! within ±1e7 N (ten times the heaviest axle load).

use anyhow::{Result, bail, ensure};
use runtime::multibody::element::{AxisLaws, DamperLaw, PiecewiseLinear, SeriesLaw, SpringLaw};
use serde::Deserialize;

/// One entry per axis of `body_a` (each optional).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, bound(deserialize = "T: Deserialize<'de>"))]
pub struct PerAxis<T> {
    #[serde(default)]
    pub x: Option<T>,
    #[serde(default)]
    pub y: Option<T>,
    #[serde(default)]
    pub z: Option<T>,
}

impl<T> Default for PerAxis<T> {
    fn default() -> Self {
        Self {
            x: None,
            y: None,
            z: None,
        }
    }
}

impl<T> PerAxis<T> {
    /// The entries as (axis name, entry) in x, y, z order.
    pub fn axes(&self) -> [(&'static str, Option<&T>); 3] {
        [
            ("x", self.x.as_ref()),
            ("y", self.y.as_ref()),
            ("z", self.z.as_ref()),
        ]
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_none() && self.y.is_none() && self.z.is_none()
    }
}

/// A nonlinear spring (restoring force F(δ); force on body_b −F).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum SpringEntry {
    /// No force within ±clearance_m, stiffness_n_m beyond.
    BumpStop {
        clearance_m: f64,
        stiffness_n_m: f64,
    },
    /// Force against deflection, through (0, 0), non-decreasing.
    Table {
        deflection_m: Vec<f64>,
        force_n: Vec<f64>,
    },
}

/// A nonlinear damper (restoring force F(v); force on body_b −F).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum DamperEntry {
    /// damping_n_s_m up to blow_off_m_s, damping_beyond_n_s_m beyond.
    Bilinear {
        damping_n_s_m: f64,
        blow_off_m_s: f64,
        damping_beyond_n_s_m: f64,
    },
    /// Force against velocity, through (0, 0), non-decreasing.
    Table {
        velocity_m_s: Vec<f64>,
        force_n: Vec<f64>,
    },
}

/// A spring in series with a damper (Maxwell element).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeriesEntry {
    pub stiffness_n_m: f64,
    pub damping_n_s_m: f64,
}

/// Plausible nonzero stiffness (N/m) (module docs).
pub const STIFFNESS_RANGE_N_M: (f64, f64) = (1e3, 1e10);
/// Plausible nonzero damping (N·s/m).
pub const DAMPING_RANGE_N_S_M: (f64, f64) = (1e2, 1e8);
/// Largest bump-stop clearance (m).
pub const MAX_CLEARANCE_M: f64 = 0.2;
/// Plausible blow-off velocity (m/s).
pub const BLOW_OFF_RANGE_M_S: (f64, f64) = (1e-4, 2.0);
/// Largest |deflection| in a table (m).
pub const MAX_TABLE_DEFLECTION_M: f64 = 0.5;
/// Largest |velocity| in a table (m/s).
pub const MAX_TABLE_VELOCITY_M_S: f64 = 10.0;
/// Largest |force| in a table (N).
pub const MAX_TABLE_FORCE_N: f64 = 1e7;

fn in_range(key: &str, v: f64, (lo, hi): (f64, f64), unit: &str, zero_ok: bool) -> Result<()> {
    ensure!(
        v.is_finite() && ((zero_ok && v == 0.0) || (lo..=hi).contains(&v)),
        "{key} = {v} is outside the plausible {lo:e} … {hi:e} {unit}{} (check the unit: {unit})",
        if zero_ok { " (or 0)" } else { "" }
    );
    Ok(())
}

fn table(
    key: &str,
    x_name: &str,
    x: &[f64],
    x_max: f64,
    x_unit: &str,
    force_n: &[f64],
) -> Result<PiecewiseLinear> {
    for &v in x {
        in_range(
            &format!("{key}.{x_name}"),
            v,
            (-x_max, x_max),
            x_unit,
            false,
        )?;
    }
    for &f in force_n {
        in_range(
            &format!("{key}.force_n"),
            f,
            (-MAX_TABLE_FORCE_N, MAX_TABLE_FORCE_N),
            "N",
            false,
        )?;
    }
    PiecewiseLinear::new(x.to_vec(), force_n.to_vec()).map_err(|e| anyhow::anyhow!("{key}: {e}"))
}

impl SpringEntry {
    fn to_law(&self, key: &str) -> Result<SpringLaw> {
        Ok(match self {
            Self::BumpStop {
                clearance_m,
                stiffness_n_m,
            } => {
                in_range(
                    &format!("{key}.clearance_m"),
                    *clearance_m,
                    (0.0, MAX_CLEARANCE_M),
                    "m",
                    false,
                )?;
                in_range(
                    &format!("{key}.stiffness_n_m"),
                    *stiffness_n_m,
                    STIFFNESS_RANGE_N_M,
                    "N/m",
                    false,
                )?;
                SpringLaw::BumpStop {
                    clearance_m: *clearance_m,
                    stiffness_n_m: *stiffness_n_m,
                }
            }
            Self::Table {
                deflection_m,
                force_n,
            } => SpringLaw::Table(table(
                key,
                "deflection_m",
                deflection_m,
                MAX_TABLE_DEFLECTION_M,
                "m",
                force_n,
            )?),
        })
    }
}

impl DamperEntry {
    fn to_law(&self, key: &str) -> Result<DamperLaw> {
        Ok(match self {
            Self::Bilinear {
                damping_n_s_m,
                blow_off_m_s,
                damping_beyond_n_s_m,
            } => {
                in_range(
                    &format!("{key}.damping_n_s_m"),
                    *damping_n_s_m,
                    DAMPING_RANGE_N_S_M,
                    "N·s/m",
                    false,
                )?;
                in_range(
                    &format!("{key}.blow_off_m_s"),
                    *blow_off_m_s,
                    BLOW_OFF_RANGE_M_S,
                    "m/s",
                    false,
                )?;
                in_range(
                    &format!("{key}.damping_beyond_n_s_m"),
                    *damping_beyond_n_s_m,
                    DAMPING_RANGE_N_S_M,
                    "N·s/m",
                    true,
                )?;
                DamperLaw::Bilinear {
                    damping_n_s_m: *damping_n_s_m,
                    blow_off_m_s: *blow_off_m_s,
                    damping_beyond_n_s_m: *damping_beyond_n_s_m,
                }
            }
            Self::Table {
                velocity_m_s,
                force_n,
            } => DamperLaw::Table(table(
                key,
                "velocity_m_s",
                velocity_m_s,
                MAX_TABLE_VELOCITY_M_S,
                "m/s",
                force_n,
            )?),
        })
    }
}

impl SeriesEntry {
    fn to_law(self, key: &str) -> Result<SeriesLaw> {
        in_range(
            &format!("{key}.stiffness_n_m"),
            self.stiffness_n_m,
            STIFFNESS_RANGE_N_M,
            "N/m",
            false,
        )?;
        in_range(
            &format!("{key}.damping_n_s_m"),
            self.damping_n_s_m,
            DAMPING_RANGE_N_S_M,
            "N·s/m",
            false,
        )?;
        Ok(SeriesLaw {
            stiffness_n_m: self.stiffness_n_m,
            damping_n_s_m: self.damping_n_s_m,
        })
    }
}

/// The nonlinear parts of one element, checked (module docs): the runtime
/// laws along a's x, y, z. `element` names the element in messages.
pub fn axis_laws(
    element: &str,
    spring: &PerAxis<SpringEntry>,
    damper: &PerAxis<DamperEntry>,
    series: &PerAxis<SeriesEntry>,
) -> Result<[AxisLaws; 3]> {
    let mut laws: [AxisLaws; 3] = Default::default();
    for (i, law) in laws.iter_mut().enumerate() {
        let (axis, s) = spring.axes()[i];
        if let Some(s) = s {
            law.spring = Some(s.to_law(&format!("element '{element}': spring.{axis}"))?);
        }
        let (axis, d) = damper.axes()[i];
        if let Some(d) = d {
            law.damper = Some(d.to_law(&format!("element '{element}': damper.{axis}"))?);
        }
        let (axis, s) = series.axes()[i];
        if let Some(s) = s {
            law.series = Some(s.to_law(&format!("element '{element}': series.{axis}"))?);
        }
        if let Err(e) = law.validate() {
            bail!("element '{element}': axis {axis}: {e}");
        }
    }
    Ok(laws)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Deserialize)]
    struct Probe {
        #[serde(default)]
        spring: PerAxis<SpringEntry>,
        #[serde(default)]
        damper: PerAxis<DamperEntry>,
        #[serde(default)]
        series: PerAxis<SeriesEntry>,
    }

    fn laws(text: &str) -> Result<[AxisLaws; 3]> {
        let p: Probe = toml::from_str(text)?;
        axis_laws("e", &p.spring, &p.damper, &p.series)
    }

    #[test]
    fn typed_entries_parse_into_laws() {
        let l = laws(
            r#"
            [spring.y]
            kind = "bump_stop"
            clearance_m = 0.025
            stiffness_n_m = 2.0e6
            [spring.z]
            kind = "table"
            deflection_m = [-0.05, 0.0, 0.05]
            force_n = [-1e5, 0.0, 2e5]
            [damper.x]
            kind = "bilinear"
            damping_n_s_m = 2.0e6
            blow_off_m_s = 0.02
            damping_beyond_n_s_m = 1.0e5
            [series.x]
            stiffness_n_m = 6.0e6
            damping_n_s_m = 2.0e6
            "#,
        )
        .unwrap();
        assert!(matches!(
            l[1].spring,
            Some(SpringLaw::BumpStop {
                clearance_m: 0.025,
                ..
            })
        ));
        assert!(matches!(l[2].spring, Some(SpringLaw::Table(_))));
        assert!(matches!(l[0].damper, Some(DamperLaw::Bilinear { .. })));
        assert_eq!(l[0].series.unwrap().stiffness_n_m, 6.0e6);
        assert!(l[1].damper.is_none() && l[2].series.is_none());
    }

    #[test]
    fn unknown_kinds_and_keys_are_refused() {
        let e = laws("[spring.y]\nkind = \"bumpstop\"\nclearance_m = 0.02\nstiffness_n_m = 1e6")
            .unwrap_err();
        assert!(e.to_string().contains("bumpstop"), "{e}");
        let e = laws("[spring.w]\nkind = \"bump_stop\"\nclearance_m = 0.02\nstiffness_n_m = 1e6")
            .unwrap_err();
        assert!(e.to_string().contains("unknown field"), "{e}");
        let e =
            laws("[series.x]\nstiffness_n_m = 1e6\ndamping_n_s_m = 1e4\ngap_m = 0.1").unwrap_err();
        assert!(e.to_string().contains("gap_m"), "{e}");
    }

    /// A clearance in mm, a blow-off in mm/s, a stiffness in N/mm: refused
    /// with the key and "check the unit"; a table breaking a rule names it.
    #[test]
    fn implausible_values_say_check_the_unit() {
        for (text, key) in [
            (
                "[spring.y]\nkind = \"bump_stop\"\nclearance_m = 25.0\nstiffness_n_m = 2e6",
                "spring.y.clearance_m",
            ),
            (
                "[damper.x]\nkind = \"bilinear\"\ndamping_n_s_m = 2e6\nblow_off_m_s = 20.0\ndamping_beyond_n_s_m = 1e5",
                "damper.x.blow_off_m_s",
            ),
            (
                "[series.z]\nstiffness_n_m = 600.0\ndamping_n_s_m = 2e4",
                "series.z.stiffness_n_m",
            ),
            (
                "[spring.z]\nkind = \"table\"\ndeflection_m = [0.0, 30.0]\nforce_n = [0.0, 1e4]",
                "spring.z.deflection_m",
            ),
        ] {
            let e = laws(text).unwrap_err().to_string();
            assert!(e.contains(key) && e.contains("check the unit"), "{e}");
            assert!(e.contains("element 'e'"), "{e}");
        }
        let e =
            laws("[damper.y]\nkind = \"table\"\nvelocity_m_s = [-0.1, 0.1]\nforce_n = [-1e3, 1e3]")
                .unwrap_err()
                .to_string();
        assert!(e.contains("damper.y") && e.contains("(0, 0)"), "{e}");
    }
}
