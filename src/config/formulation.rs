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
use runtime::multibody::formulation::{
    ElementAxes, Formulation, GyroscopicMoments, LongitudinalMotion, RollMoment,
};
use runtime::multibody::imported_contact::ContactNormal;

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

/// A switch: two sides, ours and the published one.
trait Switch: Copy + PartialEq {
    const OURS: Self;
    const PUBLISHED: Self;
    /// The switch set alone, else the preset's side.
    fn pick(set: Option<Self>, published: bool) -> Self {
        set.unwrap_or(if published {
            Self::PUBLISHED
        } else {
            Self::OURS
        })
    }
}

/// Declares a switch's config enum (snake_case in the file), its two sides
/// and its runtime value.
macro_rules! switch {
    ($(#[$doc:meta])* $name:ident => $runtime:ty {
        $(#[$od:meta])* $ours:ident = $rours:expr,
        $(#[$pd:meta])* $published:ident = $rpublished:expr $(,)?
    }) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
        #[serde(rename_all = "snake_case")]
        pub enum $name {
            $(#[$od])* $ours,
            $(#[$pd])* $published,
        }

        impl Switch for $name {
            const OURS: Self = $name::$ours;
            const PUBLISHED: Self = $name::$published;
        }

        impl From<$name> for $runtime {
            fn from(c: $name) -> $runtime {
                match c {
                    $name::$ours => $rours,
                    $name::$published => $rpublished,
                }
            }
        }
    };
}

switch! {
    /// `table_interpolation`: how an imported table's columns are read
    /// between rows.
    TableInterpolationChoice => TableInterpolation {
        /// Linear (ours).
        Linear = TableInterpolation::Linear,
        /// A natural cubic spline through each column (published).
        CubicSpline = TableInterpolation::CubicSpline,
    }
}

switch! {
    /// `contact_normal`: whether an imported table's contact normal turns
    /// with the wheelset's roll.
    ContactNormalChoice => ContactNormal {
        /// Fixed in the track frame (ours).
        Track = ContactNormal::Track,
        /// Turned by the wheelset's roll (published).
        Rolled = ContactNormal::Rolled,
    }
}

switch! {
    /// `longitudinal_motion`: whether bodies move along the track under
    /// their forces.
    LongitudinalMotionChoice => LongitudinalMotion {
        /// Free (ours).
        Free = LongitudinalMotion::Free,
        /// Imposed at the references' speed (published: no longitudinal
        /// degree of freedom).
        Imposed = LongitudinalMotion::Imposed,
    }
}

switch! {
    /// `element_axes`: the axes the suspension elements act along.
    ElementAxesChoice => ElementAxes {
        /// Body a's axes (ours).
        Body = ElementAxes::Body,
        /// The track frame (published).
        Track = ElementAxes::Track,
    }
}

switch! {
    /// `gyroscopic`: the wheelsets' gyroscopic moments.
    GyroscopicChoice => GyroscopicMoments {
        /// Exact (ours).
        Exact = GyroscopicMoments::Exact,
        /// Euler's body-axis equations in the axle frame (published).
        AxleFrameEuler = GyroscopicMoments::AxleFrameEuler,
    }
}

switch! {
    /// `roll_moment`: the arms of the contact forces' roll moment.
    RollMomentChoice => RollMoment {
        /// The whole arm (ours).
        Full = RollMoment::Full,
        /// Only the arm along the axle (published).
        AxleArmOnly = RollMoment::AxleArmOnly,
    }
}

/// The `[formulation]` section (module docs). Every switch left out takes
/// the preset's side.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FormulationSection {
    #[serde(default)]
    pub preset: FormulationPreset,
    #[serde(default)]
    pub table_interpolation: Option<TableInterpolationChoice>,
    #[serde(default)]
    pub contact_normal: Option<ContactNormalChoice>,
    #[serde(default)]
    pub longitudinal_motion: Option<LongitudinalMotionChoice>,
    #[serde(default)]
    pub element_axes: Option<ElementAxesChoice>,
    #[serde(default)]
    pub gyroscopic: Option<GyroscopicChoice>,
    #[serde(default)]
    pub roll_moment: Option<RollMomentChoice>,
}

/// Every switch resolved (preset, then the switches set alone).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ResolvedFormulation {
    pub table_interpolation: TableInterpolation,
    pub contact_normal: ContactNormal,
    pub equations: Formulation,
}

impl FormulationSection {
    /// The switches with the preset applied (module docs).
    pub fn resolve(&self) -> ResolvedFormulation {
        let p = self.preset == FormulationPreset::Published;
        ResolvedFormulation {
            table_interpolation: Switch::pick(self.table_interpolation, p).into(),
            contact_normal: Switch::pick(self.contact_normal, p).into(),
            equations: Formulation {
                longitudinal_motion: Switch::pick(self.longitudinal_motion, p).into(),
                element_axes: Switch::pick(self.element_axes, p).into(),
                gyroscopic: Switch::pick(self.gyroscopic, p).into(),
                roll_moment: Switch::pick(self.roll_moment, p).into(),
            },
        }
    }

    /// Checks the switches against the contact method: the imported
    /// table's switches, set alone to their published side, need an
    /// imported table (the preset applies them only where they mean
    /// something).
    pub fn validate(&self, method: ContactMethodKind) -> Result<()> {
        if method != ContactMethodKind::Imported {
            for (set, key) in [
                (
                    self.table_interpolation == Some(TableInterpolationChoice::CubicSpline),
                    "table_interpolation = \"cubic_spline\"",
                ),
                (
                    self.contact_normal == Some(ContactNormalChoice::Rolled),
                    "contact_normal = \"rolled\"",
                ),
            ] {
                ensure!(
                    !set,
                    "[formulation] {key} applies to an imported contact table: it needs [contact] method = \"imported\""
                );
            }
        }
        Ok(())
    }

    /// The switches that are not ours, as `key = value` (empty: ours).
    pub fn describe(&self) -> Vec<String> {
        let r = self.resolve();
        let e = r.equations;
        let ours = FormulationSection::default().resolve();
        let o = ours.equations;
        let mut parts = Vec::new();
        let mut add = |differs: bool, key: &str, value: &str| {
            if differs {
                parts.push(format!("{key} = {value}"));
            }
        };
        add(
            r.table_interpolation != ours.table_interpolation,
            "table_interpolation",
            r.table_interpolation.name(),
        );
        add(
            r.contact_normal != ours.contact_normal,
            "contact_normal",
            r.contact_normal.name(),
        );
        add(
            e.longitudinal_motion != o.longitudinal_motion,
            "longitudinal_motion",
            e.longitudinal_motion.name(),
        );
        add(
            e.element_axes != o.element_axes,
            "element_axes",
            e.element_axes.name(),
        );
        add(
            e.gyroscopic != o.gyroscopic,
            "gyroscopic",
            e.gyroscopic.name(),
        );
        add(
            e.roll_moment != o.roll_moment,
            "roll_moment",
            e.roll_moment.name(),
        );
        parts
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
