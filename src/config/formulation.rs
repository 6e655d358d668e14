//! `[formulation]`: the modelling choices where the published Cooperrider
//! formulation (DYTSI) and ours differ and which the framework can switch,
//! one at a time or all together (`preset`). The audit of every difference,
//! switchable or not, and what each one changes:
//! docs/guide/cooperrider-cross-code.md.
//!
//! ```toml
//! [formulation]
//! preset = "published"                 # or "ours" (the default): every switch below on that side
//! table_interpolation = "linear"       # one switch set alone overrides the preset
//! ```

use anyhow::{Result, ensure};
use serde::{Deserialize, Serialize};

use runtime::contact::imported_lookup::TableInterpolation;
use runtime::multibody::formulation::{Formulation, LongitudinalMotion};

use super::choices::ContactMethodKind;

/// Which side every switch takes unless it is set alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FormulationPreset {
    /// Ours (the default).
    #[default]
    Ours,
    /// The published Cooperrider formulation as DYTSI implements it.
    Published,
}

/// `table_interpolation`: how an imported table's columns are read between
/// rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TableInterpolationChoice {
    /// Linear (ours).
    Linear,
    /// Natural cubic spline through each column (published).
    CubicSpline,
}

/// `longitudinal_motion`: whether bodies move along the track under their
/// forces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LongitudinalMotionChoice {
    /// Free (ours).
    Free,
    /// Imposed at the references' speed (published: no longitudinal degree
    /// of freedom).
    Imposed,
}

/// The `[formulation]` section (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FormulationSection {
    #[serde(default)]
    pub preset: FormulationPreset,
    #[serde(default)]
    pub table_interpolation: Option<TableInterpolationChoice>,
    #[serde(default)]
    pub longitudinal_motion: Option<LongitudinalMotionChoice>,
}

/// Every switch resolved (preset, then the switches set alone).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ResolvedFormulation {
    pub table_interpolation: TableInterpolation,
    pub equations: Formulation,
}

impl FormulationSection {
    fn published(&self) -> bool {
        self.preset == FormulationPreset::Published
    }

    /// The switches with the preset applied (module docs).
    pub fn resolve(&self) -> ResolvedFormulation {
        let p = self.published();
        let table_interpolation = match self.table_interpolation {
            Some(TableInterpolationChoice::CubicSpline) => TableInterpolation::CubicSpline,
            Some(TableInterpolationChoice::Linear) => TableInterpolation::Linear,
            None if p => TableInterpolation::CubicSpline,
            None => TableInterpolation::Linear,
        };
        let longitudinal_motion = match self.longitudinal_motion {
            Some(LongitudinalMotionChoice::Imposed) => LongitudinalMotion::Imposed,
            Some(LongitudinalMotionChoice::Free) => LongitudinalMotion::Free,
            None if p => LongitudinalMotion::Imposed,
            None => LongitudinalMotion::Free,
        };
        ResolvedFormulation {
            table_interpolation,
            equations: Formulation {
                longitudinal_motion,
            },
        }
    }

    /// Checks the switches against the contact method: the imported
    /// table's switches need an imported table (the preset applies them
    /// only where they mean something).
    pub fn validate(&self, method: ContactMethodKind) -> Result<()> {
        ensure!(
            method == ContactMethodKind::Imported
                || self.table_interpolation != Some(TableInterpolationChoice::CubicSpline),
            "[formulation] table_interpolation = \"cubic_spline\" reads an imported contact table: it needs [contact] method = \"imported\""
        );
        Ok(())
    }

    /// One line for the run's summary: the switches that are not ours.
    pub fn describe(&self) -> Option<String> {
        let r = self.resolve();
        let mut parts = Vec::new();
        if r.table_interpolation != TableInterpolation::Linear {
            parts.push(format!(
                "table interpolation {}",
                r.table_interpolation.name()
            ));
        }
        if r.equations.longitudinal_motion != LongitudinalMotion::Free {
            parts.push(format!(
                "longitudinal motion {}",
                r.equations.longitudinal_motion.name()
            ));
        }
        (!parts.is_empty()).then(|| parts.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn section(text: &str) -> FormulationSection {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn the_preset_sets_every_switch_and_one_switch_overrides_it() {
        let ours = section("").resolve();
        assert_eq!(ours.table_interpolation, TableInterpolation::Linear);
        assert_eq!(ours.equations, Formulation::default());
        let published = section("preset = \"published\"").resolve();
        assert_eq!(
            published.table_interpolation,
            TableInterpolation::CubicSpline
        );
        assert_eq!(
            published.equations.longitudinal_motion,
            LongitudinalMotion::Imposed
        );
        let one = section("preset = \"published\"\ntable_interpolation = \"linear\"").resolve();
        assert_eq!(one.table_interpolation, TableInterpolation::Linear);
        assert_eq!(
            one.equations.longitudinal_motion,
            LongitudinalMotion::Imposed
        );
        let alone = section("longitudinal_motion = \"imposed\"").resolve();
        assert_eq!(alone.table_interpolation, TableInterpolation::Linear);
        assert_eq!(
            alone.equations.longitudinal_motion,
            LongitudinalMotion::Imposed
        );
    }

    #[test]
    fn unknown_switches_and_values_are_refused() {
        assert!(toml::from_str::<FormulationSection>("preset = \"dytsi\"").is_err());
        assert!(toml::from_str::<FormulationSection>("kinematic = \"small\"").is_err());
        let e = section("table_interpolation = \"cubic_spline\"")
            .validate(ContactMethodKind::Online)
            .unwrap_err()
            .to_string();
        assert!(e.contains("method = \"imported\""), "{e}");
        // The preset alone is fine with any method.
        section("preset = \"published\"")
            .validate(ContactMethodKind::Online)
            .unwrap();
    }
}
