//! The state of every rigid body of the vehicle at each sample — the
//! wheelsets and the free bodies (bogie frames, car body) — relative to
//! the track, as an engineer reads it (docs/reference/04-table-files.md
//! §4.4, group `bodies/`), and which body is the car body.
//!
//! # Frame
//!
//! Every quantity refers to the **track frame at the body's own track
//! position** s (the centreline point nearest to its centre of gravity,
//! CG): `t` forward, `n` left, `b` up (docs/reference/01-units-frames.md
//! §1).
//!
//! - Position: `track_s_m` = s; `longitudinal_m` = s − (s_ref(t) + x₀),
//!   the CG's lead (+) or lag along the track behind the place it holds in
//!   the vehicle frame carried along at the run's reference motion (s_ref
//!   the vehicle reference point's track position at the sample's time,
//!   x₀ the body's assembly x: the wheelset's `x_m`, the free body's
//!   `cg_m[0]`; attribute `assembly_x_m`); `lateral_m` = (r − c(s))·n, from
//!   the centreline, + left; `vertical_m` = (r − c(s))·b, the CG's height
//!   above the rail-top plane at the centreline, + up (a wheelset sits at
//!   about its rolling radius; the free body's assembly height is the
//!   attribute `assembly_height_m`).
//! - Orientation: the rotation of the body's axes relative to the track
//!   axes, R_rel = Tᵀ R (T: columns t, n, b; R: body → global), written
//!   R_rel = R_z(ψ) R_x(φ) R_y(θ) — yaw ψ about `b`, then roll φ about the
//!   yawed forward axis, then pitch θ about the body's own lateral axis.
//!   Signs: yaw + nose left, roll + raising the left side, pitch + nose
//!   down (right-handed about the left-pointing axis). This sequence is
//!   singular only at roll ±90°, and makes a wheelset's yaw and roll the
//!   same as the wheelset columns `yaw_rad` and `roll_rad` (its axle
//!   R_rel e_y = (−sin ψ cos φ, cos ψ cos φ, sin φ)); a wheelset's pitch is
//!   its rolling angle, wrapped to (−π, π].
//! - Velocities: the CG's velocity and the body's angular velocity
//!   (absolute, i.e. relative to the ground) resolved in the track axes at
//!   s: `longitudinal_velocity_m_s` = v·t, … ; `roll_rate_rad_s` = ω·t,
//!   `pitch_rate_rad_s` = ω·n (a rolling wheelset's spin), `yaw_rate_rad_s`
//!   = ω·b (on a curve of radius R it includes the track's V/R).
//! - Accelerations (ride assessment): what an accelerometer at the CG fixed
//!   to the body reads, the specific force f = a − g = (applied
//!   non-gravity force)/m, taken from the equations of motion at the
//!   sample (the right-hand side's resultant force, not differences of
//!   output samples), resolved in the **body's axes** (a wheelset: its
//!   non-spinning axle frame, R_z(ψ) R_x(φ) in the track axes):
//!   `lateral_acceleration_m_s2` = f·y_body, + left (in a curve: the
//!   uncompensated lateral acceleration plus g·sin of the body's roll
//!   relative to the level); `vertical_acceleration_m_s2` = f·z_body − g,
//!   + up, so 0 at rest on level track (g the run's gravity).
//!
//! # The car body
//!
//! [`recognise_car_body`]: a free body whose name, lower-cased without
//! spaces, `_` and `-`, is `carbody` or `car` (e.g. "car body",
//! "Car_Body"); failing that, the heaviest free body when the vehicle has
//! at least two (car body above bogie frames), provided it is at least
//! [`CAR_BODY_MASS_RATIO`] times as heavy as every other free body. A
//! vehicle with one free body (a bogie frame below a track-following car
//! body, the ML95-like bogie) has no car body in its results: its car body
//! is a reference moving with the track frame at the run's speed, so its
//! state is the track frame itself (zero displacements and angles,
//! accelerations those of the track's curvature and cant).

use super::columns::{Access, Column, Dataset, Values};

/// The heaviest free body counts as the car body only when it is at least
/// this many times as heavy as every other free body: a car body is five to
/// fifteen times a bogie frame (44.4 t against 2.9 t in the Cooperrider
/// car, tables/vehicles/cooperrider_car.toml); two bodies of similar mass
/// are no such pair and none is taken.
pub const CAR_BODY_MASS_RATIO: f64 = 2.0;

/// Whether a body is a wheelset or a free body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BodyKind {
    #[default]
    Wheelset,
    Free,
}

impl BodyKind {
    /// The value of the group's `kind` attribute.
    pub fn as_str(self) -> &'static str {
        match self {
            BodyKind::Wheelset => "wheelset",
            BodyKind::Free => "body",
        }
    }

    /// From the `kind` attribute.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "wheelset" => Some(BodyKind::Wheelset),
            "body" => Some(BodyKind::Free),
            _ => None,
        }
    }
}

/// Which body is the car body and by which rule ([`recognise_car_body`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CarBody {
    /// The body's name (one of [`super::RunResults::bodies`]).
    pub name: String,
    /// The rule that picked it: [`CarBody::BY_NAME`] or [`CarBody::BY_MASS`].
    pub rule: String,
}

impl CarBody {
    pub const BY_NAME: &'static str = "named car body";
    pub const BY_MASS: &'static str = "heaviest free body";
}

/// The car body among free bodies `(name, mass_kg)` (module docs).
pub fn recognise_car_body<'a>(free: impl IntoIterator<Item = (&'a str, f64)>) -> Option<CarBody> {
    let free: Vec<(&str, f64)> = free.into_iter().collect();
    let key = |n: &str| -> String {
        n.chars()
            .filter(|c| !matches!(c, ' ' | '_' | '-'))
            .flat_map(char::to_lowercase)
            .collect()
    };
    if let Some((name, _)) = free
        .iter()
        .find(|(n, _)| matches!(key(n).as_str(), "carbody" | "car"))
    {
        return Some(CarBody {
            name: name.to_string(),
            rule: CarBody::BY_NAME.into(),
        });
    }
    if free.len() < 2 {
        return None;
    }
    let (k, &(name, mass)) = free
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.1.total_cmp(&b.1.1))?;
    let others_ok = free
        .iter()
        .enumerate()
        .all(|(j, &(_, m))| j == k || mass >= CAR_BODY_MASS_RATIO * m);
    others_ok.then(|| CarBody {
        name: name.to_string(),
        rule: CarBody::BY_MASS.into(),
    })
}

/// Time series of one rigid body (units, frames and signs in the module
/// docs and in [`BODY_COLUMNS`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BodySeries {
    /// The body's name in the vehicle.
    pub name: String,
    pub kind: BodyKind,
    /// Mass (kg).
    pub mass_kg: f64,
    /// x₀: the body's assembly position ahead of the vehicle reference
    /// point (m), the origin of `longitudinal_m`.
    pub assembly_x_m: f64,
    /// The free body's CG height above the rail-top plane at assembly (m);
    /// NaN for a wheelset (settled on its rails at assembly).
    pub assembly_height_m: f64,
    pub track_s_m: Vec<f64>,
    pub longitudinal_m: Vec<f64>,
    pub lateral_m: Vec<f64>,
    pub vertical_m: Vec<f64>,
    pub roll_rad: Vec<f64>,
    pub pitch_rad: Vec<f64>,
    pub yaw_rad: Vec<f64>,
    pub longitudinal_velocity_m_s: Vec<f64>,
    pub lateral_velocity_m_s: Vec<f64>,
    pub vertical_velocity_m_s: Vec<f64>,
    pub roll_rate_rad_s: Vec<f64>,
    pub pitch_rate_rad_s: Vec<f64>,
    pub yaw_rate_rad_s: Vec<f64>,
    pub lateral_acceleration_m_s2: Vec<f64>,
    pub vertical_acceleration_m_s2: Vec<f64>,
}

/// One sample of a body, for [`BodySeries::push`]; fields as in
/// [`BodySeries`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodySample {
    pub track_s_m: f64,
    pub longitudinal_m: f64,
    pub lateral_m: f64,
    pub vertical_m: f64,
    pub roll_rad: f64,
    pub pitch_rad: f64,
    pub yaw_rad: f64,
    pub longitudinal_velocity_m_s: f64,
    pub lateral_velocity_m_s: f64,
    pub vertical_velocity_m_s: f64,
    pub roll_rate_rad_s: f64,
    pub pitch_rate_rad_s: f64,
    pub yaw_rate_rad_s: f64,
    pub lateral_acceleration_m_s2: f64,
    pub vertical_acceleration_m_s2: f64,
}

/// The series of a body, in file order (group `bodies/<name>/`).
pub const BODY_COLUMNS: [Column<BodySeries, BodySample>; 15] = [
    f64_column!(
        track_s_m,
        "m",
        "track position of the CG: arc length s of the centreline point nearest to it; every other series refers to the track frame (t forward, n left, b up) at this s"
    ),
    f64_column!(
        longitudinal_m,
        "m",
        "lead (+) or lag of the CG along the track from its assembly place carried along at the run's reference motion: s - (s_ref(t) + assembly_x_m)"
    ),
    f64_column!(
        lateral_m,
        "m",
        "lateral displacement of the CG from the track centreline, (r - c(s)).n, + left"
    ),
    f64_column!(
        vertical_m,
        "m",
        "height of the CG above the rail-top plane at the centreline, (r - c(s)).b, + up"
    ),
    f64_column!(
        roll_rad,
        "rad",
        "roll relative to the track, + raising the left side (R_rel = Rz(yaw) Rx(roll) Ry(pitch))"
    ),
    f64_column!(
        pitch_rad,
        "rad",
        "pitch relative to the track, + nose down (right-handed about the left-pointing lateral axis); a wheelset: its rolling angle, wrapped to (-pi, pi]"
    ),
    f64_column!(yaw_rad, "rad", "yaw relative to the track, + nose left"),
    f64_column!(
        longitudinal_velocity_m_s,
        "m/s",
        "CG velocity (absolute) along the track's forward axis t"
    ),
    f64_column!(
        lateral_velocity_m_s,
        "m/s",
        "CG velocity (absolute) along the track's lateral axis n, + left"
    ),
    f64_column!(
        vertical_velocity_m_s,
        "m/s",
        "CG velocity (absolute) along the track's up axis b, + up"
    ),
    f64_column!(
        roll_rate_rad_s,
        "rad/s",
        "angular velocity (absolute) about the track's forward axis t, + raising the left side"
    ),
    f64_column!(
        pitch_rate_rad_s,
        "rad/s",
        "angular velocity (absolute) about the track's lateral axis n, + nose down; a rolling wheelset: its spin"
    ),
    f64_column!(
        yaw_rate_rad_s,
        "rad/s",
        "angular velocity (absolute) about the track's up axis b, + nose left; on a curve of radius R it includes V/R"
    ),
    f64_column!(
        lateral_acceleration_m_s2,
        "m/s^2",
        "lateral acceleration for ride assessment: specific force (a - g, the applied non-gravity force over the mass, from the equations of motion at the sample) along the body's lateral axis (a wheelset: its non-spinning axle frame), + left"
    ),
    f64_column!(
        vertical_acceleration_m_s2,
        "m/s^2",
        "vertical acceleration for ride assessment: specific force (a - g) along the body's up axis minus g, + up; 0 at rest on level track"
    ),
];

impl BodySeries {
    /// A body with no samples yet.
    pub fn new(name: impl Into<String>, kind: BodyKind, mass_kg: f64) -> Self {
        Self {
            name: name.into(),
            kind,
            mass_kg,
            assembly_height_m: f64::NAN,
            ..Self::default()
        }
    }

    /// The same body (name, kind, mass, assembly place) without samples.
    pub fn empty_like(&self) -> Self {
        Self {
            name: self.name.clone(),
            kind: self.kind,
            mass_kg: self.mass_kg,
            assembly_x_m: self.assembly_x_m,
            assembly_height_m: self.assembly_height_m,
            ..Self::default()
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.track_s_m.len()
    }

    /// No samples.
    pub fn is_empty(&self) -> bool {
        self.track_s_m.is_empty()
    }

    /// Append one sample.
    pub fn push(&mut self, s: &BodySample) {
        for c in &BODY_COLUMNS {
            c.push(self, s);
        }
    }

    /// Sample `i`, if there is one.
    pub fn sample(&self, i: usize) -> Option<BodySample> {
        self.track_s_m.get(i)?;
        let mut s = BodySample::default();
        for c in &BODY_COLUMNS {
            c.copy_into(self, i, &mut s);
        }
        Some(s)
    }

    /// Apply `f` to every series, in column order.
    pub fn for_each_series(&mut self, f: &mut dyn FnMut(&mut Vec<f64>)) {
        for c in &BODY_COLUMNS {
            if let Values::F64(a) = &c.values {
                f((a.series_mut)(self));
            }
        }
    }
}

/// The datasets of [`BODY_COLUMNS`], for documentation checks.
pub fn body_datasets() -> impl Iterator<Item = Dataset> {
    BODY_COLUMNS.iter().map(|c| c.dataset)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_car_body_by_name_then_by_mass() {
        let named = recognise_car_body([("front frame", 2918.9), ("Car_Body", 4.0e4)]);
        assert_eq!(named.as_ref().map(|c| c.name.as_str()), Some("Car_Body"));
        assert_eq!(named.unwrap().rule, CarBody::BY_NAME);
        // The Cooperrider car's bodies: "car body" by its name.
        let coop = recognise_car_body([
            ("front frame", 2918.9),
            ("rear frame", 2918.9),
            ("car body", 44388.0),
        ])
        .unwrap();
        assert_eq!(
            (coop.name.as_str(), coop.rule.as_str()),
            ("car body", CarBody::BY_NAME)
        );
        // Unnamed: the heaviest, when much heavier than the others.
        let heavy = recognise_car_body([("b1", 2900.0), ("shell", 30000.0), ("b2", 2900.0)]);
        assert_eq!(
            heavy,
            Some(CarBody {
                name: "shell".into(),
                rule: CarBody::BY_MASS.into()
            })
        );
        // Two similar bodies, or a bogie frame alone: none.
        assert_eq!(recognise_car_body([("a", 3000.0), ("b", 4000.0)]), None);
        assert_eq!(recognise_car_body([("frame", 2500.0)]), None);
        assert_eq!(recognise_car_body([]), None);
    }

    #[test]
    fn a_body_sample_comes_back_field_by_field() {
        let mut s = BodySample::default();
        let mut b = BodySeries::new("car body", BodyKind::Free, 4e4);
        // Distinct values in every field, so a column reaching the wrong
        // field shows.
        let mut k = 0.0;
        for c in &BODY_COLUMNS {
            k += 1.0;
            if let Values::F64(a) = &c.values {
                (a.set)(&mut s, k);
            }
        }
        b.push(&s);
        assert_eq!(b.sample(0), Some(s));
        assert_eq!(b.sample(1), None);
        assert_eq!(b.lateral_m, vec![3.0]);
        let e = b.empty_like();
        assert!(e.is_empty() && e.name == "car body" && e.kind == BodyKind::Free);
        let names: Vec<&str> = body_datasets().map(|d| d.name).collect();
        for (k, n) in names.iter().enumerate() {
            assert!(!names[..k].contains(n), "{n} twice");
        }
    }
}
