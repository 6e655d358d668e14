//! Vehicle files (`tables/vehicles/*.toml`): a vehicle is data — its
//! bodies, wheelsets, track-following references and suspension elements —
//! so a full car is a file, not code (docs/reference/08-multibody.md §8).
//!
//! # Coordinates
//!
//! Positions are given at the **assembly configuration**: the vehicle
//! standing centred on straight, level track, in the vehicle's reference
//! frame — origin on the track centreline in the plane of the rail tops
//! under the vehicle's reference point, x forward (direction of travel),
//! y to the left, z up (docs/reference/01-units-frames.md §1). A wheelset's height is not given: it is
//! settled on the rails under its static load before the run.
//!
//! # Format
//!
//! ```toml
//! name = "ML95-like bogie"
//! description = "…"                # optional
//!
//! [[wheelsets]]
//! name = "front"
//! x_m = 1.0                        # axle position ahead of the reference point (m)
//! mass_kg = 1100.0
//! inertia_kg_m2 = [650.0, 90.0, 650.0]  # roll (x), spin (y, the axle), yaw (z) about the CG
//! wheel_profile = "../profiles/ml95_like_wheel.csv"  # relative to this file
//! back_to_back_m = 1.360           # flange back to flange back (m)
//! nominal_radius_m = 0.43          # rolling radius at the taping line (m)
//!
//! [[bodies]]                       # free rigid bodies (6 DOF)
//! name = "frame"
//! cg_m = [0.0, 0.0, 0.60]          # centre of gravity (m)
//! mass_kg = 2500.0
//! inertia_kg_m2 = [1500.0, 1700.0, 3000.0]  # principal, about x, y, z through the CG
//!
//! [[references]]                   # bodies moving with the track at the run's speed
//! name = "car"
//! origin_m = [0.0, 0.0, 1.5]       # origin of its axes (m)
//!
//! [[elements]]                     # spring–dampers
//! name = "primary front left"
//! body_a = "frame"                 # its axes give the x, y, z of stiffness and damping
//! body_b = "front"                 # a body, wheelset or reference name
//! point_m = [1.0, 1.0, 0.43]       # attachment point (or point_a_m and point_b_m)
//! stiffness_n_m = [1.0e7, 5.0e6, 1.2e6]
//! damping_n_s_m = [0.0, 0.0, 1.0e4]
//! preload_n = [0.0, 0.0, 0.0]      # a constant force on body_b, body_a's axes (optional)
//! ```
//!
//! `body_a` or `body_b` may also be `"ground"` (a fixed point). Nonlinear
//! parts per axis (`spring.x`, `damper.y`, `series.z`, …):
//! [`super::suspension`]. A reference may carry a mass for the static
//! solve (`carried_mass_kg`).
//!
//! Preloads (`preload = "solve" | "given"` at the top level,
//! [`super::statics`]): by default the preload of every element is solved
//! for static equilibrium at assembly (each `preload_n` is kept as a
//! constant force and the rest follows from the stiffnesses); with
//! `"given"` the `preload_n` are the preloads and must hold every free
//! body in static equilibrium (checked by [`VehicleFile::validate`], which
//! names the body and the net force). Wheelsets take their static wheel
//! loads from the elements acting on them plus their own weight.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail, ensure};
use serde::Deserialize;

use super::statics::{PreloadMode, StaticPreloads};
use super::suspension::{DamperEntry, PerAxis, SeriesEntry, SpringEntry, axis_laws};

/// A wheelset entry.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetEntry {
    pub name: String,
    /// Axle position ahead of the vehicle reference point (m).
    pub x_m: f64,
    /// Lateral position at assembly (m); 0 for a centred vehicle.
    #[serde(default)]
    pub y_m: f64,
    pub mass_kg: f64,
    /// Principal moments of inertia about the CG: roll (x), spin (y, along
    /// the axle), yaw (z) (kg·m²).
    pub inertia_kg_m2: [f64; 3],
    /// Wheel profile file, relative to the vehicle file (both wheels; the
    /// left one is the mirror image).
    pub wheel_profile: PathBuf,
    /// Distance between the flange backs (m).
    pub back_to_back_m: f64,
    /// Rolling radius at the taping line (m).
    pub nominal_radius_m: f64,
}

/// A free rigid body.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyEntry {
    pub name: String,
    /// Centre of gravity at assembly (m).
    pub cg_m: [f64; 3],
    pub mass_kg: f64,
    /// Principal moments of inertia about x, y, z through the CG (kg·m²).
    pub inertia_kg_m2: [f64; 3],
}

/// A body that follows the track at the run's speed (e.g. the car body's
/// share above a single bogie).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceEntry {
    pub name: String,
    /// Origin of its axes at assembly (m); its axes are the track frame.
    pub origin_m: [f64; 3],
    /// Mass whose weight its elements carry in the static preload solve
    /// (kg; at the origin). 0 (default): the reference is a fixed support
    /// there. Its motion in the run stays prescribed either way.
    #[serde(default)]
    pub carried_mass_kg: f64,
}

/// A spring–damper: linear, with nonlinear parts per axis
/// (docs/reference/08-multibody.md §8).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElementEntry {
    pub name: String,
    /// Body whose axes give the element's x, y, z directions.
    pub body_a: String,
    pub body_b: String,
    /// Common attachment point (m), or the two below.
    #[serde(default)]
    pub point_m: Option<[f64; 3]>,
    #[serde(default)]
    pub point_a_m: Option<[f64; 3]>,
    #[serde(default)]
    pub point_b_m: Option<[f64; 3]>,
    /// Stiffness along a's x, y, z (N/m); default 0.
    #[serde(default)]
    pub stiffness_n_m: [f64; 3],
    /// Damping along a's x, y, z (N·s/m).
    #[serde(default)]
    pub damping_n_s_m: [f64; 3],
    /// Force on body_b at assembly, in a's axes (N): with
    /// `preload = "given"` the preload; with `"solve"` a constant force
    /// kept in the solved preload (friction-free preload).
    #[serde(default)]
    pub preload_n: [f64; 3],
    /// Nonlinear springs per axis ([`super::suspension`]).
    #[serde(default)]
    pub spring: PerAxis<SpringEntry>,
    /// Nonlinear dampers per axis.
    #[serde(default)]
    pub damper: PerAxis<DamperEntry>,
    /// Series spring–dampers per axis.
    #[serde(default)]
    pub series: PerAxis<SeriesEntry>,
}

impl ElementEntry {
    /// The attachment points on a and on b at assembly (m).
    pub fn points(&self) -> Result<([f64; 3], [f64; 3])> {
        match (self.point_m, self.point_a_m, self.point_b_m) {
            (Some(p), None, None) => Ok((p, p)),
            (None, Some(a), Some(b)) => Ok((a, b)),
            _ => bail!(
                "element '{}': give either point_m, or both point_a_m and point_b_m",
                self.name
            ),
        }
    }
}

/// A vehicle file as written.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleFile {
    pub name: String,
    #[serde(default)]
    pub description: String,
    /// Where the element preloads come from (default: solved).
    #[serde(default)]
    pub preload: PreloadMode,
    pub wheelsets: Vec<WheelsetEntry>,
    #[serde(default)]
    pub bodies: Vec<BodyEntry>,
    #[serde(default)]
    pub references: Vec<ReferenceEntry>,
    #[serde(default)]
    pub elements: Vec<ElementEntry>,
    /// Directory the file was read from (profile paths are relative to it).
    #[serde(skip)]
    pub dir: PathBuf,
    /// The resolved preloads, set by [`VehicleFile::load`] (or
    /// [`VehicleFile::resolve`]).
    #[serde(skip)]
    pub statics: Option<StaticPreloads>,
}

/// Name of the fixed ground, usable as an element end.
pub const GROUND: &str = "ground";

/// Standard gravity (m/s²), docs/reference/01-units-frames.md §1.
pub const GRAVITY_M_S2: f64 = 9.81;

impl VehicleFile {
    /// Reads and checks a vehicle file.
    pub fn load(path: &Path) -> Result<VehicleFile> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("reading the vehicle file {}", path.display()))?;
        let mut v = Self::parse(&text)
            .with_context(|| format!("in the vehicle file {}", path.display()))?;
        v.dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        v.resolve()
            .with_context(|| format!("in the vehicle file {}", path.display()))?;
        Ok(v)
    }

    /// Multiplies the linear damping of every element whose name starts
    /// with a key of `scale` by its factor, then checks the vehicle again
    /// ([`VehicleFile::resolve`]). Refused: a factor outside
    /// [0, [`super::scene::MAX_DAMPING_SCALE`]], a prefix that matches no
    /// element, a matched element with a nonlinear or series damper (its
    /// law has no single coefficient to scale).
    pub fn scale_damping(&mut self, scale: &std::collections::BTreeMap<String, f64>) -> Result<()> {
        for (prefix, &factor) in scale {
            if !(factor.is_finite() && (0.0..=super::scene::MAX_DAMPING_SCALE).contains(&factor)) {
                bail!(
                    "'{prefix}' = {factor}: a damping factor lies in [0, {}] (a factor, not a coefficient: check the unit)",
                    super::scene::MAX_DAMPING_SCALE
                );
            }
            let mut matched = 0;
            for e in self
                .elements
                .iter_mut()
                .filter(|e| e.name.starts_with(prefix.as_str()))
            {
                if [&e.damper.x, &e.damper.y, &e.damper.z]
                    .iter()
                    .any(|d| d.is_some())
                    || [&e.series.x, &e.series.y, &e.series.z]
                        .iter()
                        .any(|d| d.is_some())
                {
                    bail!(
                        "'{prefix}' matches element '{}', whose damping is nonlinear or in series: it has no single coefficient to scale",
                        e.name
                    );
                }
                for c in &mut e.damping_n_s_m {
                    *c *= factor;
                }
                matched += 1;
            }
            if matched == 0 {
                bail!(
                    "'{prefix}' matches no element of the vehicle '{}' (element names: {})",
                    self.name,
                    self.elements
                        .iter()
                        .map(|e| e.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                );
            }
        }
        self.resolve()
    }

    /// Checks every rule ([`VehicleFile::validate`]) and keeps the
    /// resolved preloads ([`VehicleFile::element_preloads_n`]).
    pub fn resolve(&mut self) -> Result<()> {
        self.statics = None;
        self.validate()?;
        self.statics = Some(self.static_preloads()?);
        Ok(())
    }

    /// Parses the TOML text (no checks beyond the format).
    pub fn parse(text: &str) -> Result<VehicleFile> {
        Ok(toml::from_str(text)?)
    }

    /// A wheel profile path resolved against the file's directory.
    pub fn profile_path(&self, w: &WheelsetEntry) -> PathBuf {
        self.dir.join(&w.wheel_profile)
    }

    /// Checks every rule, naming the entry and the rule violated: names
    /// unique and known, masses and inertias positive (principal moments
    /// obeying the triangle inequality), geometry finite and plausible,
    /// element coefficients ≥ 0, nonlinear parts plausible
    /// ([`super::suspension`]), and the preloads: solved for static
    /// equilibrium (`preload = "solve"`), or with `"given"` every free body
    /// in static equilibrium at assembly under gravity and the element
    /// preloads (within 0.5 % of its weight, or 1 N); no wheelset lifted.
    pub fn validate(&self) -> Result<()> {
        ensure!(
            !self.wheelsets.is_empty(),
            "a vehicle needs at least one wheelset"
        );
        let mut names = BTreeSet::new();
        let all = self
            .wheelsets
            .iter()
            .map(|w| &w.name)
            .chain(self.bodies.iter().map(|b| &b.name))
            .chain(self.references.iter().map(|r| &r.name));
        for n in all {
            ensure!(!n.is_empty(), "a body has an empty name");
            ensure!(n != GROUND, "'{GROUND}' is reserved for the fixed ground");
            ensure!(names.insert(n.clone()), "two bodies are named '{n}'");
        }
        let inertia_ok = |i: &[f64; 3]| {
            i.iter().all(|v| v.is_finite() && *v > 0.0)
                && i[0] + i[1] >= i[2]
                && i[1] + i[2] >= i[0]
                && i[0] + i[2] >= i[1]
        };
        for w in &self.wheelsets {
            let n = &w.name;
            ensure!(
                w.mass_kg.is_finite() && w.mass_kg > 0.0,
                "wheelset '{n}': mass_kg must be > 0, got {}",
                w.mass_kg
            );
            ensure!(
                inertia_ok(&w.inertia_kg_m2),
                "wheelset '{n}': inertia_kg_m2 {:?} must be positive and obey the triangle inequality",
                w.inertia_kg_m2
            );
            ensure!(
                w.x_m.is_finite() && w.y_m.is_finite() && w.y_m.abs() < 0.05,
                "wheelset '{n}': x_m must be finite and |y_m| < 0.05 m"
            );
            ensure!(
                w.nominal_radius_m > 0.1 && w.nominal_radius_m < 1.0,
                "wheelset '{n}': nominal_radius_m {} is outside 0.1 … 1 m",
                w.nominal_radius_m
            );
            ensure!(
                w.back_to_back_m > 0.5 && w.back_to_back_m < 2.0,
                "wheelset '{n}': back_to_back_m {} is outside 0.5 … 2 m",
                w.back_to_back_m
            );
        }
        for b in &self.bodies {
            let n = &b.name;
            ensure!(
                b.mass_kg.is_finite() && b.mass_kg > 0.0,
                "body '{n}': mass_kg must be > 0, got {}",
                b.mass_kg
            );
            ensure!(
                inertia_ok(&b.inertia_kg_m2),
                "body '{n}': inertia_kg_m2 {:?} must be positive and obey the triangle inequality",
                b.inertia_kg_m2
            );
            ensure!(
                b.cg_m.iter().all(|v| v.is_finite()),
                "body '{n}': cg_m must be finite"
            );
        }
        for r in &self.references {
            ensure!(
                r.origin_m.iter().all(|v| v.is_finite()),
                "reference '{}': origin_m must be finite",
                r.name
            );
            // A car body is at most ~100 t (a loaded freight wagon, 25 t
            // per axle on four axles); 1e6 kg means grams or a typo.
            ensure!(
                r.carried_mass_kg.is_finite() && (0.0..=1e6).contains(&r.carried_mass_kg),
                "reference '{}': carried_mass_kg = {} must lie in 0 … 1e6 kg (check the unit: kg)",
                r.name,
                r.carried_mass_kg
            );
        }
        for e in &self.elements {
            let n = &e.name;
            for end in [&e.body_a, &e.body_b] {
                ensure!(
                    end == GROUND || names.contains(end),
                    "element '{n}': unknown body '{end}'"
                );
            }
            ensure!(
                e.body_a != e.body_b,
                "element '{n}': body_a and body_b are the same"
            );
            let (pa, pb) = e.points()?;
            ensure!(
                pa.iter().chain(&pb).all(|v| v.is_finite()),
                "element '{n}': attachment points must be finite"
            );
            for (what, v) in [
                ("stiffness_n_m", e.stiffness_n_m),
                ("damping_n_s_m", e.damping_n_s_m),
            ] {
                ensure!(
                    v.iter().all(|x| x.is_finite() && *x >= 0.0),
                    "element '{n}': {what} {v:?} must be finite and >= 0"
                );
            }
            ensure!(
                e.preload_n.iter().all(|x| x.is_finite()),
                "element '{n}': preload_n must be finite"
            );
            axis_laws(n, &e.spring, &e.damper, &e.series)?;
            let nothing = e.stiffness_n_m == [0.0; 3]
                && e.damping_n_s_m == [0.0; 3]
                && e.preload_n == [0.0; 3]
                && e.spring.is_empty()
                && e.damper.is_empty()
                && e.series.is_empty();
            ensure!(
                !nothing,
                "element '{n}': no stiffness, damping, preload_n or nonlinear part: the element does nothing"
            );
        }
        match self.preload {
            PreloadMode::Given => self.check_static_equilibrium(),
            PreloadMode::Solve => {
                let solved = self.static_preloads()?;
                self.check_wheelsets_loaded(&solved.preloads_n)
            }
        }
    }

    /// Net force (N) on a body at assembly from gravity and the element
    /// preloads ([`VehicleFile::element_preloads_n`]). At assembly every
    /// body's axes are the track axes, so an element's preload (given in
    /// a's axes) is the global force on b.
    pub fn static_force_on(&self, name: &str, mass_kg: f64) -> [f64; 3] {
        self.force_from(name, mass_kg, &self.element_preloads_n())
    }

    fn check_static_equilibrium(&self) -> Result<()> {
        let given = self.given_preloads_n();
        for b in &self.bodies {
            let f = self.force_from(&b.name, b.mass_kg, &given);
            let tol = (0.005 * b.mass_kg * GRAVITY_M_S2).max(1.0);
            let net = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
            if net > tol {
                bail!(
                    "body '{}' is not in static equilibrium at assembly: net force [{:.1}, {:.1}, {:.1}] N from gravity and the element preloads (allowed {:.1} N); the preload_n of the elements on it must carry its weight and what it supports",
                    b.name,
                    f[0],
                    f[1],
                    f[2],
                    tol
                );
            }
        }
        self.check_wheelsets_loaded(&given)
    }

    /// No wheelset lifted off the rails by the element preloads
    /// `preloads_n` (file order).
    fn check_wheelsets_loaded(&self, preloads_n: &[[f64; 3]]) -> Result<()> {
        for w in &self.wheelsets {
            let f = self.force_from(&w.name, w.mass_kg, preloads_n);
            ensure!(
                f[2] < 0.0,
                "wheelset '{}': the elements lift it off the rails at assembly (net vertical force {:.1} N)",
                w.name,
                f[2]
            );
        }
        Ok(())
    }

    /// Static vertical load of one wheel of a wheelset (N): half of its
    /// weight plus the vertical preloads acting on it.
    pub fn static_wheel_load_n(&self, w: &WheelsetEntry) -> f64 {
        -0.5 * self.static_force_on(&w.name, w.mass_kg)[2]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damping_scale_multiplies_the_matched_elements_and_refuses_what_it_cannot() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tables/vehicles/cooperrider_car.toml");
        let original = VehicleFile::load(&path).unwrap();
        let mut v = original.clone();
        let scale = |k: &str, f: f64| std::collections::BTreeMap::from([(k.to_string(), f)]);
        v.scale_damping(&scale("secondary yaw", 2.0)).unwrap();
        let mut scaled = 0;
        for (a, b) in original.elements.iter().zip(&v.elements) {
            if a.name.starts_with("secondary yaw") {
                scaled += 1;
                assert_eq!(b.damping_n_s_m[0], 2.0 * a.damping_n_s_m[0]);
            } else {
                assert_eq!(a.damping_n_s_m, b.damping_n_s_m, "{}", a.name);
            }
        }
        assert_eq!(scaled, 4);
        let e = original
            .clone()
            .scale_damping(&scale("yaw damper", 2.0))
            .unwrap_err();
        assert!(format!("{e:#}").contains("matches no element"), "{e:#}");
        let e = original
            .clone()
            .scale_damping(&scale("secondary yaw", 1.66669e5))
            .unwrap_err();
        assert!(format!("{e:#}").contains("check the unit"), "{e:#}");
    }
    use crate::config::statics::PreloadMode;

    const WHEELSET: &str = r#"
        name = "test wheelset"
        [[wheelsets]]
        name = "ws"
        x_m = 0.0
        mass_kg = 1000.0
        inertia_kg_m2 = [600.0, 100.0, 600.0]
        wheel_profile = "wheel.csv"
        back_to_back_m = 1.36
        nominal_radius_m = 0.43
    "#;

    #[test]
    fn a_bare_wheelset_parses_and_validates() {
        let v = VehicleFile::parse(WHEELSET).unwrap();
        v.validate().unwrap();
        let load = v.static_wheel_load_n(&v.wheelsets[0]);
        assert!((load - 0.5 * 1000.0 * GRAVITY_M_S2).abs() < 1e-9);
    }

    #[test]
    fn unknown_fields_and_bad_values_are_named() {
        let bad = WHEELSET.replace("mass_kg = 1000.0", "mass_kg = 1000.0\nmass_lb = 3.0");
        assert!(VehicleFile::parse(&bad).is_err());
        let bad = WHEELSET.replace("mass_kg = 1000.0", "mass_kg = -1.0");
        let e = VehicleFile::parse(&bad).unwrap().validate().unwrap_err();
        assert!(e.to_string().contains("mass_kg"), "{e}");
        let bad = WHEELSET.replace("[600.0, 100.0, 600.0]", "[600.0, 100.0, 2000.0]");
        let e = VehicleFile::parse(&bad).unwrap().validate().unwrap_err();
        assert!(e.to_string().contains("triangle"), "{e}");
    }

    #[test]
    fn static_equilibrium_is_checked() {
        let text = format!(
            "{WHEELSET}
            [[bodies]]
            name = \"frame\"
            cg_m = [0.0, 0.0, 0.6]
            mass_kg = 2000.0
            inertia_kg_m2 = [1000.0, 1000.0, 1500.0]
            [[elements]]
            name = \"spring\"
            body_a = \"frame\"
            body_b = \"ws\"
            point_m = [0.0, 0.0, 0.43]
            stiffness_n_m = [1e6, 1e6, 1e6]
            preload_n = [0.0, 0.0, PRELOAD]
            "
        );
        // The spring pushes the wheelset down with the frame's weight: the
        // frame is held up (reaction on a = −preload).
        let ok = text.replace("PRELOAD", &format!("{}", -2000.0 * GRAVITY_M_S2));
        let v = VehicleFile::parse(&ok).unwrap();
        v.validate().unwrap();
        let load = v.static_wheel_load_n(&v.wheelsets[0]);
        assert!((load - 0.5 * 3000.0 * GRAVITY_M_S2).abs() < 1e-6);
        // With preload = "given" (the old behaviour) a preload that does
        // not carry the frame is refused with the net force.
        let bad = text.replace("PRELOAD", "-1000.0");
        let given = format!("preload = \"given\"\n{bad}");
        let e = VehicleFile::parse(&given).unwrap().validate().unwrap_err();
        assert!(
            e.to_string()
                .contains("body 'frame' is not in static equilibrium at assembly: net force"),
            "{e}"
        );
        // Solved (the default): the spring carries the frame whatever
        // preload_n says beyond it (−1000 N kept as a constant force on
        // the wheelset, the spring's deflection adds the rest).
        let mut v = VehicleFile::parse(&bad).unwrap();
        v.resolve().unwrap();
        let p = v.element_preloads_n()[0][2];
        assert!((p + 2000.0 * GRAVITY_M_S2).abs() < 1e-6, "{p}");
        let unknown = ok.replace("body_b = \"ws\"", "body_b = \"rear\"");
        let e = VehicleFile::parse(&unknown)
            .unwrap()
            .validate()
            .unwrap_err();
        assert!(e.to_string().contains("unknown body 'rear'"), "{e}");
    }

    /// A bump stop, a yaw damper with its bushes and a constant force in a
    /// vehicle file: parsed, solved (the bump stop in its clearance and the
    /// series element carry no static force, the constant force is kept),
    /// and the new rules named.
    #[test]
    fn nonlinear_elements_and_constant_forces_in_a_file() {
        let text = format!(
            "{WHEELSET}
            [[bodies]]
            name = \"frame\"
            cg_m = [0.0, 0.0, 0.6]
            mass_kg = 2000.0
            inertia_kg_m2 = [1000.0, 1000.0, 1500.0]
            [[elements]]
            name = \"spring\"
            body_a = \"frame\"
            body_b = \"ws\"
            point_m = [0.0, 0.0, 0.43]
            stiffness_n_m = [1e6, 1e6, 1e6]
            [elements.spring.y]
            kind = \"bump_stop\"
            clearance_m = 0.02
            stiffness_n_m = 5e6
            [[elements]]
            name = \"yaw damper\"
            body_a = \"frame\"
            body_b = \"ws\"
            point_m = [0.0, 1.2, 0.43]
            [elements.damper.x]
            kind = \"bilinear\"
            damping_n_s_m = 2e6
            blow_off_m_s = 0.02
            damping_beyond_n_s_m = 1e5
            [elements.series.x]
            stiffness_n_m = 6e6
            damping_n_s_m = 2e6
            [[elements]]
            name = \"ballast\"
            body_a = \"ground\"
            body_b = \"frame\"
            point_m = [0.0, 0.0, 0.6]
            preload_n = [0.0, 0.0, -1000.0]
            "
        );
        let mut v = VehicleFile::parse(&text).unwrap();
        assert_eq!(v.preload, PreloadMode::Solve);
        v.resolve().unwrap();
        let p = v.element_preloads_n();
        // The spring carries the frame's weight and the 1 kN ballast.
        assert!(
            (p[0][2] + 2000.0 * GRAVITY_M_S2 + 1000.0).abs() < 1e-6,
            "{p:?}"
        );
        assert_eq!(p[1], [0.0; 3]);
        assert_eq!(p[2], [0.0, 0.0, -1000.0]);
        let load = v.static_wheel_load_n(&v.wheelsets[0]);
        assert!((load - 0.5 * (3000.0 * GRAVITY_M_S2 + 1000.0)).abs() < 1e-6);
        // An element that does nothing; a carried mass in grams.
        let idle = text.replace("preload_n = [0.0, 0.0, -1000.0]", "");
        let e = VehicleFile::parse(&idle).unwrap().validate().unwrap_err();
        assert!(e.to_string().contains("element 'ballast'"), "{e}");
        assert!(e.to_string().contains("does nothing"), "{e}");
        let heavy = format!(
            "{text}
            [[references]]
            name = \"car\"
            origin_m = [0.0, 0.0, 1.5]
            carried_mass_kg = 1.4e7"
        );
        let e = VehicleFile::parse(&heavy).unwrap().validate().unwrap_err();
        assert!(e.to_string().contains("carried_mass_kg"), "{e}");
        assert!(e.to_string().contains("check the unit"), "{e}");
        // A typo in the mode is a parse error naming the choices.
        let typo = format!("preload = \"solved\"\n{text}");
        let e = VehicleFile::parse(&typo).unwrap_err();
        assert!(format!("{e:#}").contains("solve"), "{e:#}");
    }
}
