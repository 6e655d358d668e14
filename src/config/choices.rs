//! The choices of a scene file as typed enums (never strings): each
//! deserialises from, and prints as, the word the scene file uses
//! (`docs/reference/10-scene-files.md`), so a misspelt choice is refused
//! by the TOML reader with its line and column and the list of the words
//! it accepts.

use runtime::contact::FlangeSearch;
use runtime::multibody::contact_force::NonHertzianPolicy;

/// Defines a choice enum with its scene-file words: serde, `Display`,
/// `FromStr` (for the command line) and the list of words.
macro_rules! choice {
    ($(#[$meta:meta])* $name:ident { $($(#[$vmeta:meta])* $variant:ident = $word:literal),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
        pub enum $name {
            $($(#[$vmeta])* #[serde(rename = $word)] $variant),+
        }

        impl $name {
            /// Every choice, in the order of the documentation.
            pub const ALL: &'static [$name] = &[$($name::$variant),+];
            /// The words of the scene file, in the order of [`Self::ALL`].
            pub const WORDS: &'static [&'static str] = &[$($word),+];

            /// The word of the scene file.
            pub fn as_str(self) -> &'static str {
                match self {
                    $($name::$variant => $word),+
                }
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.pad(self.as_str())
            }
        }

        impl std::str::FromStr for $name {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                match s.trim() {
                    $($word => Ok($name::$variant),)+
                    other => Err(format!("'{other}' is not one of {}", Self::WORDS.join(", "))),
                }
            }
        }
    };
}

pub(crate) use choice;

choice! {
    /// How the contact is evaluated (`[contact] method`).
    ContactMethodKind {
        /// Newton on the surface parameters at every evaluation
        /// (`docs/reference/06-contact-detection.md`).
        Online = "online",
        /// Our contact lookup table, built on demand for the wheel/rail pair.
        Table = "table",
        /// One contact per wheel from another code's table (`imported_table`).
        Imported = "imported",
    }
}

choice! {
    /// Flange search (`[contact] flange`; `runtime::contact::FlangeSearch`).
    FlangeMode {
        /// Never searched.
        Off = "off",
        /// Always searched.
        On = "on",
        /// Searched when the flange may be near its rail.
        Auto = "auto",
    }
}

impl From<FlangeMode> for FlangeSearch {
    fn from(m: FlangeMode) -> FlangeSearch {
        match m {
            FlangeMode::Off => FlangeSearch::Off,
            FlangeMode::On => FlangeSearch::On,
            FlangeMode::Auto => FlangeSearch::Auto,
        }
    }
}

choice! {
    /// The creep law (`[contact] creep_law`;
    /// `docs/reference/07-contact-forces.md` §7.3).
    CreepLawName {
        /// Kalker's linear theory.
        Kalker = "kalker",
        /// Shen–Hedrick–Elkins' heuristic saturation of Kalker's law.
        Heuristic = "heuristic",
        /// Polach's method (parameters: `polach_preset`).
        Polach = "polach",
        /// Kalker's FASTSIM (discretisation: `fastsim_strips`, `fastsim_elements`).
        Fastsim = "fastsim",
        /// FaStrip, strip theory + FASTSIM (discretisation: `fastrip_strips`,
        /// `fastrip_elements`).
        Fastrip = "fastrip",
        /// No creep forces.
        None = "none",
    }
}

choice! {
    /// Polach's parameter set (`[contact] polach_preset`; Polach 1999, 2005).
    PolachPreset {
        /// kA = kS = 1, constant friction (Polach 1999).
        P1999 = "1999",
        /// Dry rail, Polach 2005 Table 1.
        Dry2005 = "dry-2005",
        /// Wet rail, Polach 2005 Table 1.
        Wet2005 = "wet-2005",
    }
}

choice! {
    /// Where the contact geometry is not Hertzian (`[contact] non_hertzian`).
    NonHertzianMode {
        /// The run ends with a diagnostic.
        Stop = "stop",
        /// Floored curvatures, flagged and counted.
        Floor = "floor",
    }
}

impl From<NonHertzianMode> for NonHertzianPolicy {
    fn from(m: NonHertzianMode) -> NonHertzianPolicy {
        match m {
            NonHertzianMode::Stop => NonHertzianPolicy::Stop,
            NonHertzianMode::Floor => NonHertzianPolicy::Floor,
        }
    }
}

choice! {
    /// The time integrator (`[run] integrator`;
    /// `docs/reference/08-multibody.md`).
    IntegratorKind {
        /// Classical Runge–Kutta, fixed step `step_s`.
        Rk4 = "rk4",
        /// Dormand–Prince 5(4), adaptive (`rtol`, `atol`, `max_step_s`).
        Dopri5 = "dopri5",
        /// Linearly implicit Rosenbrock-W ROS34PW2, adaptive (`rtol`,
        /// `atol`, `max_step_s`): for the stiff contact modes
        /// (docs/reference/08-multibody.md §8.5).
        Rosenbrock = "rosenbrock",
    }
}

choice! {
    /// Who decides the planner's items (`[plan] mode`).
    PlanMode {
        /// The scene runs as written; the planner only reports.
        Scene = "scene",
        /// The planner chooses every item the scene leaves out.
        Required = "required",
        /// The reference: everything modelled at its finest.
        Everything = "everything",
    }
}

choice! {
    /// An item the planner may choose (`[plan] choose`).
    PlanItem {
        /// The flange search.
        Flange = "flange",
        /// The contact method.
        Method = "method",
        /// The table step.
        Step = "step",
        /// The track range.
        Range = "range",
        /// The integrator and its step or tolerances.
        Integrator = "integrator",
        /// Every item.
        All = "all",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_round_trip_and_misspellings_list_the_choices() {
        for m in ContactMethodKind::ALL {
            assert_eq!(m.as_str().parse::<ContactMethodKind>().unwrap(), *m);
        }
        for p in PolachPreset::ALL {
            assert_eq!(p.to_string().parse::<PolachPreset>().unwrap(), *p);
        }
        let e = "tabel".parse::<ContactMethodKind>().unwrap_err();
        assert!(e.contains("online, table, imported"), "{e}");
        #[derive(serde::Deserialize)]
        struct T {
            law: CreepLawName,
        }
        let t: T = toml::from_str("law = \"fastsim\"").unwrap();
        assert_eq!(t.law, CreepLawName::Fastsim);
        let t: T = toml::from_str("law = \"fastrip\"").unwrap();
        assert_eq!(t.law, CreepLawName::Fastrip);
        let e = toml::from_str::<T>("law = \"polak\"")
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("polak") && e.contains("polach"), "{e}");
    }
}

choice! {
    /// A spline scheme of the track build (`[track] scheme`, `cant_scheme`;
    /// docs/reference/03-track-preproc.md §3a: the schemes and their accuracy).
    SplineScheme {
        /// Cubic spline, not-a-knot ends.
        Cubic = "cubic",
        /// Cubic spline, natural ends.
        CubicNatural = "cubic-natural",
        /// Akima's local spline.
        Akima = "akima",
        /// Shape-preserving piecewise cubic Hermite (Fritsch–Carlson).
        Pchip = "pchip",
    }
}

impl SplineScheme {
    /// The runtime's scheme.
    pub fn scheme(self) -> runtime::geometry::spline::Scheme {
        use runtime::geometry::spline::Scheme;
        match self {
            SplineScheme::Cubic => Scheme::Cubic,
            SplineScheme::CubicNatural => Scheme::CubicNatural,
            SplineScheme::Akima => Scheme::Akima,
            SplineScheme::Pchip => Scheme::Pchip,
        }
    }

    /// The scene's word of a runtime scheme.
    pub fn of(scheme: runtime::geometry::spline::Scheme) -> Self {
        use runtime::geometry::spline::Scheme;
        match scheme {
            Scheme::Cubic => SplineScheme::Cubic,
            Scheme::CubicNatural => SplineScheme::CubicNatural,
            Scheme::Akima => SplineScheme::Akima,
            Scheme::Pchip => SplineScheme::Pchip,
        }
    }
}

choice! {
    /// How a critical speed is found (`--method`; `crate::studies::critical_speed`).
    CriticalSpeedMethod {
        /// Growth rates of runs at many speeds, bracketed to zero.
        Time = "time",
        /// The speed ramped down from a hunting cycle until it dies out.
        Ramp = "ramp",
        /// Eigenvalues of the linearised centred run.
        Linear = "linear",
    }
}
