//! Typed variations of a scene: what a study changes between its runs
//! (speed, creep law, contact method, … or any scene key), applied to the
//! scene's entries as `--set` would be, then checked by the same
//! [`Scene::validate`](super::scene::Scene::validate). An entry a variation
//! sets counts as written in the scene (the planner leaves it as set).

use anyhow::{Context, Result};

use super::choices::{ContactMethodKind, CreepLawName, FlangeMode, IntegratorKind};
use super::overrides::{parse_assignment, set_entry};
use super::scene::{LoadedScene, Scene};

/// One change to a scene.
#[derive(Debug, Clone, PartialEq)]
pub enum Variation {
    /// `[initial] speed_m_s` (m/s).
    Speed(f64),
    /// `[initial] deceleration_m_s2` (m/s²): a speed ramp.
    Deceleration(f64),
    /// `[run] distance_m` (m).
    Distance(f64),
    /// `[contact] creep_law`.
    CreepLaw(CreepLawName),
    /// `[contact] method`.
    Method(ContactMethodKind),
    /// `[contact] flange`.
    Flange(FlangeMode),
    /// `[run] integrator`.
    Integrator(IntegratorKind),
    /// `[run] step_s` (s), the RK4 step.
    Step(f64),
    /// `[track] straight_m` (m): an ideal straight of that length.
    StraightTrack(f64),
    /// Any scene entry, by its dotted key (`run.rtol`), to a TOML value.
    Set(String, toml::Value),
    /// Removes an entry (its default applies, or another entry replaces it).
    Remove(String),
}

impl Variation {
    /// The dotted key and the new value (`None`: removed).
    pub fn entry(&self) -> (String, Option<toml::Value>) {
        use toml::Value::{Float, String as Str};
        let (k, v) = match self {
            Variation::Speed(v) => ("initial.speed_m_s", Some(Float(*v))),
            Variation::Deceleration(a) => ("initial.deceleration_m_s2", Some(Float(*a))),
            Variation::Distance(d) => ("run.distance_m", Some(Float(*d))),
            Variation::CreepLaw(l) => ("contact.creep_law", Some(Str(l.to_string()))),
            Variation::Method(m) => ("contact.method", Some(Str(m.to_string()))),
            Variation::Flange(f) => ("contact.flange", Some(Str(f.to_string()))),
            Variation::Integrator(i) => ("run.integrator", Some(Str(i.to_string()))),
            Variation::Step(h) => ("run.step_s", Some(Float(*h))),
            Variation::StraightTrack(l) => ("track.straight_m", Some(Float(*l))),
            Variation::Set(k, v) => (k.as_str(), Some(v.clone())),
            Variation::Remove(k) => (k.as_str(), None),
        };
        (k.to_string(), v)
    }

    /// A speed ramp down at `deceleration_m_s2` (m/s²) over `distance_m`
    /// (m) on an ideal straight of `length_m` (m): the scene's track
    /// inputs and duration give way to it (the nonlinear critical speed and
    /// the bifurcation diagram's ramp-down).
    pub fn ramp_on_straight(
        scene: &Scene,
        deceleration_m_s2: f64,
        distance_m: f64,
        length_m: f64,
    ) -> Vec<Variation> {
        let mut out = vec![
            Variation::Deceleration(deceleration_m_s2),
            Variation::Distance(distance_m),
            Variation::StraightTrack(length_m),
        ];
        // The ramp's length is a distance: a scene's duration gives way to it.
        if scene.run.duration_s.is_some() {
            out.push(Variation::Remove("run.duration_s".into()));
        }
        out.extend(Self::track_inputs_removed(scene));
        out
    }

    /// Removals of the scene's track inputs other than `straight_m` (for an
    /// ideal straight set by [`Variation::StraightTrack`]).
    pub fn track_inputs_removed(scene: &Scene) -> Vec<Variation> {
        let mut out = Vec::new();
        let t = &scene.track;
        for (key, set) in [
            ("centerline", t.centerline.is_some()),
            ("design", t.design.is_some()),
            ("tables", t.tables.is_some()),
            ("cant", t.cant.is_some()),
            ("irregularities", t.irregularities.is_some()),
        ] {
            if set {
                out.push(Variation::Remove(format!("track.{key}")));
            }
        }
        out
    }

    /// A `key=value` assignment as `--set` takes it: the value is read as
    /// TOML, or else as a string; an empty value removes the entry.
    pub fn parse(assignment: &str) -> Result<Variation> {
        Ok(match parse_assignment(assignment)? {
            (key, Some(value)) => Variation::Set(key, value),
            (key, None) => Variation::Remove(key),
        })
    }

    /// `key=value` as on the command line (for the run's origin and the
    /// scene text's `# overrides` line).
    pub fn describe(&self) -> String {
        match self.entry() {
            (k, Some(v)) => format!("{k}={v}"),
            (k, None) => format!("{k}="),
        }
    }
}

impl LoadedScene {
    /// This scene with `variations` applied (module docs); the origin
    /// names them.
    pub fn varied(&self, variations: &[Variation]) -> Result<LoadedScene> {
        let mut table: toml::Table = self.text.parse().context("the scene is not valid TOML")?;
        let described: Vec<String> = variations.iter().map(Variation::describe).collect();
        for v in variations {
            let (key, value) = v.entry();
            set_entry(&mut table, &key, value).with_context(|| v.describe())?;
        }
        let mut varied = LoadedScene::from_table(
            table,
            self.dir.clone(),
            &described,
            format!("{} ({})", self.origin, described.join(" ")),
        )?;
        varied.file = self.file.clone();
        Ok(varied)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variations_change_the_typed_scene_and_the_recorded_text() {
        let base = LoadedScene::default_scene(&[]).unwrap();
        let v = base
            .varied(&[
                Variation::Speed(12.5),
                Variation::CreepLaw(CreepLawName::Kalker),
                Variation::Method(ContactMethodKind::Table),
            ])
            .unwrap();
        assert_eq!(v.scene.initial.speed_m_s, 12.5);
        assert_eq!(v.scene.contact.creep_law, CreepLawName::Kalker);
        assert_eq!(v.scene.contact.method, ContactMethodKind::Table);
        assert!(v.text.contains("initial.speed_m_s=12.5"), "{}", v.text);
        assert!(
            v.origin.contains("contact.creep_law=\"kalker\""),
            "{}",
            v.origin
        );
        // The base is untouched, and a varied scene is checked like any scene.
        assert_eq!(base.scene.contact.creep_law, CreepLawName::Polach);
        let e = base.varied(&[Variation::Speed(-1.0)]).unwrap_err();
        assert!(format!("{e:#}").contains("speed_m_s"), "{e:#}");
        let e = base
            .varied(&[Variation::Set(
                "contact.friction".into(),
                toml::Value::Float(9.0),
            )])
            .unwrap_err();
        assert!(format!("{e:#}").contains("friction"), "{e:#}");
        // Removing an entry: its default applies.
        let r = base
            .varied(&[Variation::Remove("contact.restitution".into())])
            .unwrap();
        assert_eq!(r.scene.contact.restitution, 0.9);
    }
}
