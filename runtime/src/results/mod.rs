//! The record of a run as plain data: time series of every wheelset,
//! wheel and contact zone (docs/reference/08-multibody.md §8 outputs), filled by
//! [`crate::multibody::recorder`] and written and read by the results file
//! of [`crate::io::schema`] (HDF5, behind the `io` feature). No file access
//! here.
//!
//! Every series is defined once in the column lists of [`columns`]
//! ([`WHEELSET_COLUMNS`], [`WHEEL_COLUMNS`], [`ZONE_COLUMNS`]): its name,
//! unit, meaning with its sign convention, and how to reach its values.
//! Frames and signs are those of docs/reference/01-units-frames.md §1: track frame `t` forward, `n`
//! left, `b` up; contact frame `n_c` from rail into wheel, `t_c` rolling
//! direction, `l_c = n_c × t_c`; forces and moments are those acting **on
//! the wheel**. A zone's f64 values are NaN at samples where it is not in
//! contact.

pub mod attribute;
#[macro_use]
pub mod columns;
pub mod bodies;
pub mod chunks;
pub mod curving;
pub mod paths;

pub use attribute::AttrValue;
pub use bodies::{BODY_COLUMNS, BodyKind, BodySample, BodySeries, CarBody};
pub use chunks::{DecimatedView, ResultsSink, SinkError};
pub use columns::{
    Access, Column, Dataset, TIME_S, Values, WHEEL_COLUMNS, WHEELSET_COLUMNS, ZONE_COLUMNS,
};
pub use paths::{NamedSeries, SeriesValues};

use crate::contact::nadal::NadalLimit;

/// Root attribute names the results file's writer sets itself
/// ([`crate::io::schema`]); run metadata ([`RunResults::attributes`]) may not
/// use them.
pub const RESERVED_ATTRIBUTES: [&str; 4] = ["schema", "schema_version", "tool", "tool_version"];

/// Group names of the two wheels, in the order of [`WheelsetSeries::wheels`].
pub const WHEEL_GROUPS: [&str; 2] = ["left", "right"];
/// Group names of the two contact zones, in the order of [`WheelSeries::zones`].
pub const ZONE_GROUPS: [&str; 2] = ["tread", "flange"];

/// The whole record of one run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunResults {
    /// Sample times (s), finite and non-decreasing.
    pub time_s: Vec<f64>,
    /// One entry per wheelset, in vehicle order (front first).
    pub wheelsets: Vec<WheelsetSeries>,
    /// The scene text as run (TOML, after overrides).
    pub scene_toml: String,
    /// Free-form run metadata written as root attributes (e.g. creep law,
    /// integrator, speed): text, numbers (stored as HDF5 numbers) or flags
    /// ([`AttrValue`]). Names must be non-empty, unique and not one of
    /// [`RESERVED_ATTRIBUTES`].
    pub attributes: Vec<(String, AttrValue)>,
    /// Track-relative state of every rigid body (wheelsets first, then the
    /// free bodies, in vehicle order), each series the length of `time_s`;
    /// empty in files written before the bodies were stored
    /// ([`bodies`]).
    pub bodies: Vec<BodySeries>,
    /// Which of `bodies` is the car body, and how it was recognised.
    pub car_body: Option<CarBody>,
}

/// Time series of one wheelset (all the length of [`RunResults::time_s`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WheelsetSeries {
    /// The wheelset's name in the vehicle (e.g. "front").
    pub name: String,
    /// Lateral displacement of the wheelset centre from the track
    /// centreline (m), + towards the left rail (docs/reference/01-units-frames.md §1).
    pub lateral_m: Vec<f64>,
    /// Yaw angle relative to the track (rad), + nose left.
    pub yaw_rad: Vec<f64>,
    /// Roll angle relative to the track (rad), + raising the left wheel.
    pub roll_rad: Vec<f64>,
    /// Distance travelled along the track centreline since the start (m).
    pub distance_m: Vec<f64>,
    /// Forward speed along the track (m/s).
    pub speed_m_s: Vec<f64>,
    /// Track position of the wheelset centre: the centreline's arc length
    /// s at the wheelset's section (m), as the track tables and the track
    /// files count it; NaN in files written before it was stored.
    pub track_s_m: Vec<f64>,
    /// ΣY, the track shifting force: the lateral contact forces of both
    /// wheels summed in the track plane (N), + left ([`curving::sum_y_n`]);
    /// 0 without contact.
    pub sum_y_n: Vec<f64>,
    /// `[left, right]`, facing the direction of travel.
    pub wheels: [WheelSeries; 2],
}

/// Time series of one wheel.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WheelSeries {
    /// Distance travelled by the wheel along its rail (m): the arc length of
    /// the contact point on the rail since the start.
    pub travelled_m: Vec<f64>,
    /// 1 when the flange zone is in contact, else 0.
    pub flange_contact: Vec<u8>,
    /// Y: lateral contact force on the wheel summed over its zones (N), +
    /// towards the track centre (left wheel along −n, right wheel along
    /// +n, so that a flanging wheel's Y is positive); NaN without contact.
    pub y_n: Vec<f64>,
    /// Q: vertical contact force on the wheel summed over its zones, along
    /// the track's up axis (N, the wheel load); NaN without contact.
    pub q_n: Vec<f64>,
    /// Y/Q (dimensionless), Nadal's derailment quotient
    /// ([`crate::contact::nadal`]); NaN without contact.
    pub y_over_q: Vec<f64>,
    /// Tγ of the wheel: the wear numbers of its zones in contact summed
    /// (N, [`curving::wheel_wear_number_n`]); NaN without contact.
    pub wear_number_n: Vec<f64>,
    /// The wheel's Nadal limit (steepest flange angle, friction), when it
    /// has a flange and the writer knew it.
    pub nadal: Option<NadalLimit>,
    /// `[tread, flange]`.
    pub zones: [ZoneSeries; 2],
}

/// Time series of one contact zone (tread or flange) of one wheel. Every
/// f64 series is NaN at samples where the zone is not in contact. Contact
/// frame (docs/reference/01-units-frames.md §1): `n_c` from rail into wheel, `t_c` rolling direction,
/// `l_c = n_c × t_c`; forces and moments act on the wheel.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ZoneSeries {
    /// 1 when the zone is in contact, else 0.
    pub in_contact: Vec<u8>,
    /// Normal force on the wheel along `n_c` (N), ≥ 0.
    pub normal_n: Vec<f64>,
    /// Longitudinal creep force on the wheel along `t_c` (N).
    pub fx_n: Vec<f64>,
    /// Lateral creep force on the wheel along `l_c` (N).
    pub fy_n: Vec<f64>,
    /// Spin creep moment on the wheel about `n_c` (N m).
    pub mz_nm: Vec<f64>,
    /// Total contact force (normal + creep) on the wheel along the track's
    /// lateral axis (N), + left.
    pub lateral_force_n: Vec<f64>,
    /// Total contact force on the wheel along the track's up axis (N), + up.
    pub vertical_force_n: Vec<f64>,
    /// Longitudinal creepage ξ = (v_w − v_r)·t_c / V (dimensionless).
    pub xi: Vec<f64>,
    /// Lateral creepage η = (v_w − v_r)·l_c / V (dimensionless).
    pub eta: Vec<f64>,
    /// Spin creepage φ = (ω_w − ω_r)·n_c / V (1/m).
    pub phi_1_m: Vec<f64>,
    /// Lateral coordinate of the contact point on the wheel profile (m,
    /// profile file coordinates).
    pub y_wheel_m: Vec<f64>,
    /// Lateral coordinate of the contact point on the rail profile (m,
    /// profile file coordinates).
    pub y_rail_m: Vec<f64>,
    /// Angle of the contact normal from the track's up axis in the
    /// cross-section (rad), + towards the gauge (flange) side on both wheels.
    pub contact_angle_rad: Vec<f64>,
    /// Lead of the contact point ahead of the axle along the wheelset's
    /// forward direction (m), r·sin s_w; negative: lag.
    pub lead_m: Vec<f64>,
    /// Bit flags of the fallbacks ([`FALLBACK_MINIMISATION`],
    /// [`FALLBACK_HERTZ_FLOOR`]); 0 none.
    pub fallback: Vec<u8>,
    /// Wear number Tγ = |Fx ξ| + |Fy η| + |Mz φ| (N,
    /// [`curving::wear_number_n`]), from the values above.
    pub wear_number_n: Vec<f64>,
}

/// One sample of a contact zone, for [`ZoneSeries::push`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZoneSample {
    pub in_contact: bool,
    /// See the fields of [`ZoneSeries`] of the same names for units and signs.
    pub normal_n: f64,
    pub fx_n: f64,
    pub fy_n: f64,
    pub mz_nm: f64,
    pub lateral_force_n: f64,
    pub vertical_force_n: f64,
    pub xi: f64,
    pub eta: f64,
    pub phi_1_m: f64,
    pub y_wheel_m: f64,
    pub y_rail_m: f64,
    pub contact_angle_rad: f64,
    pub lead_m: f64,
    /// Bit flags of the fallbacks ([`FALLBACK_MINIMISATION`],
    /// [`FALLBACK_HERTZ_FLOOR`]); 0 none.
    pub fallback: u8,
}

/// [`ZoneSeries::fallback`] bit: the contact point came from the
/// minimisation fallback of the contact search (nearly conformal contact).
pub const FALLBACK_MINIMISATION: u8 = 1;
/// [`ZoneSeries::fallback`] bit: non-Hertzian geometry, the ellipse from
/// floored curvatures (`crate::multibody::contact_force::NonHertzianPolicy::Floor`).
pub const FALLBACK_HERTZ_FLOOR: u8 = 2;

impl ZoneSample {
    /// A zone out of contact: flag 0, every value NaN.
    pub const NO_CONTACT: Self = Self {
        in_contact: false,
        normal_n: f64::NAN,
        fx_n: f64::NAN,
        fy_n: f64::NAN,
        mz_nm: f64::NAN,
        lateral_force_n: f64::NAN,
        vertical_force_n: f64::NAN,
        xi: f64::NAN,
        eta: f64::NAN,
        phi_1_m: f64::NAN,
        y_wheel_m: f64::NAN,
        y_rail_m: f64::NAN,
        contact_angle_rad: f64::NAN,
        lead_m: f64::NAN,
        fallback: 0,
    };
}

impl Default for ZoneSample {
    fn default() -> Self {
        Self::NO_CONTACT
    }
}

/// One sample of a wheel, for [`WheelSeries::push`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelSample {
    /// Distance travelled along the rail (m), see [`WheelSeries::travelled_m`].
    pub travelled_m: f64,
    /// `[tread, flange]`; the flange-contact flag is the flange zone's
    /// `in_contact`.
    pub zones: [ZoneSample; 2],
}

/// One sample of a wheelset, for [`WheelsetSeries::push`] and
/// [`RunResults::push`]. Units and signs as in [`WheelsetSeries`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelsetSample {
    pub lateral_m: f64,
    pub yaw_rad: f64,
    pub roll_rad: f64,
    pub distance_m: f64,
    pub speed_m_s: f64,
    pub track_s_m: f64,
    /// `[left, right]`.
    pub wheels: [WheelSample; 2],
}

/// Why a [`RunResults`] is not a consistent record. Series are named by
/// their path in the file (e.g. `wheelset_0/left/tread/xi`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ResultsError {
    #[error("series {series} has {len} samples, but time_s has {expected}")]
    LengthMismatch {
        series: String,
        len: usize,
        expected: usize,
    },
    #[error("time_s[{index}] = {value} is not finite")]
    NonFiniteTime { index: usize, value: f64 },
    #[error("time_s decreases at sample {index}: {previous} s then {value} s")]
    TimeDecreasing {
        index: usize,
        previous: f64,
        value: f64,
    },
    #[error(
        "flag series {series} holds {value} at sample {index}; flags are 0 or 1 (fallback: bits 1 and 2)"
    )]
    FlagValue {
        series: String,
        index: usize,
        value: u8,
    },
    #[error("run attribute '{name}': {rule}")]
    Attribute { name: String, rule: &'static str },
    #[error("a sample has {found} wheelsets, but the results have {expected}")]
    WheelsetCount { expected: usize, found: usize },
    #[error("a sample has {found} bodies, but the results have {expected}")]
    BodyCount { expected: usize, found: usize },
    #[error("body {index} is named '{name}' like an earlier one; body names must be unique")]
    BodyName { index: usize, name: String },
    #[error("the car body '{name}' is not one of the bodies")]
    CarBody { name: String },
}

/// The values stored per wheel for one sample ([`WHEEL_COLUMNS`]): the
/// wheel's own, and Y, Q and Y/Q from its zones ([`wheel_y_q`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelValues {
    /// See [`WheelSeries::travelled_m`].
    pub travelled_m: f64,
    /// The flange zone is in contact.
    pub flange_contact: bool,
    /// See [`WheelSeries::y_n`].
    pub y_n: f64,
    /// See [`WheelSeries::q_n`].
    pub q_n: f64,
    /// See [`WheelSeries::y_over_q`].
    pub y_over_q: f64,
    /// See [`WheelSeries::wear_number_n`].
    pub wear_number_n: f64,
}

impl WheelValues {
    /// The values of wheel `side` (0 left, 1 right; the sign of Y depends
    /// on it) at sample `s`.
    pub fn of(side: usize, s: &WheelSample) -> Self {
        let (y_n, q_n, y_over_q) = wheel_y_q(side, &s.zones);
        Self {
            travelled_m: s.travelled_m,
            flange_contact: s.zones[1].in_contact,
            y_n,
            q_n,
            y_over_q,
            wear_number_n: curving::wheel_wear_number_n(&s.zones),
        }
    }
}

impl ZoneSeries {
    /// Append one sample. A sample out of contact is stored as
    /// [`ZoneSample::NO_CONTACT`] (flag 0, NaN values) whatever its values.
    pub fn push(&mut self, s: &ZoneSample) {
        let s = if s.in_contact {
            s
        } else {
            &ZoneSample::NO_CONTACT
        };
        for c in &ZONE_COLUMNS {
            c.push(self, s);
        }
    }

    /// Sample `i`, if there is one (values missing from a shorter series
    /// are those of [`ZoneSample::NO_CONTACT`]).
    pub fn sample(&self, i: usize) -> Option<ZoneSample> {
        self.in_contact.get(i)?;
        let mut s = ZoneSample::NO_CONTACT;
        for c in &ZONE_COLUMNS {
            c.copy_into(self, i, &mut s);
        }
        Some(s)
    }
}

/// Y (+ towards the track centre), Q and Y/Q of a wheel from its zones'
/// track-frame forces (module docs); NaN when no zone is in contact.
/// `side` is the wheel's index, 0 left, 1 right.
pub fn wheel_y_q(side: usize, zones: &[ZoneSample; 2]) -> (f64, f64, f64) {
    // Lateral forces are + left (+n): towards the centre is −n for the left
    // wheel and +n for the right one.
    let sign = if side == 0 { -1.0 } else { 1.0 };
    let mut y = 0.0;
    let mut q = 0.0;
    let mut any = false;
    for z in zones.iter().filter(|z| z.in_contact) {
        any = true;
        y += sign * z.lateral_force_n;
        q += z.vertical_force_n;
    }
    if !any {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    let ratio = if q > 0.0 { y / q } else { f64::NAN };
    (y, q, ratio)
}

impl WheelSeries {
    /// Append one sample of wheel `side` (0 left, 1 right; the sign of Y
    /// depends on it); the flange-contact flag is the flange zone's
    /// `in_contact`, Y, Q and Y/Q come from the zones ([`wheel_y_q`]).
    pub fn push(&mut self, side: usize, s: &WheelSample) {
        let values = WheelValues::of(side, s);
        for c in &WHEEL_COLUMNS {
            c.push(self, &values);
        }
        for (zone, z) in self.zones.iter_mut().zip(&s.zones) {
            zone.push(z);
        }
    }

    /// Sample `i` (the wheel's travelled distance and its zones), if there
    /// is one.
    pub fn sample(&self, i: usize) -> Option<WheelSample> {
        Some(WheelSample {
            travelled_m: *self.travelled_m.get(i)?,
            zones: [self.zones[0].sample(i)?, self.zones[1].sample(i)?],
        })
    }

    /// Largest finite Y/Q over the samples, if any.
    pub fn max_y_over_q(&self) -> Option<f64> {
        self.y_over_q
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .reduce(f64::max)
    }
}

impl WheelsetSeries {
    /// A wheelset with no samples yet.
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            ..Self::default()
        }
    }

    /// Append one sample.
    pub fn push(&mut self, s: &WheelsetSample) {
        for c in &WHEELSET_COLUMNS {
            c.push(self, s);
        }
        for (side, (wheel, w)) in self.wheels.iter_mut().zip(&s.wheels).enumerate() {
            wheel.push(side, w);
        }
    }
}

/// Group name of wheelset `i`.
pub fn wheelset_group(i: usize) -> String {
    format!("wheelset_{i}")
}

impl RunResults {
    /// Empty results for wheelsets of the given names (vehicle order).
    pub fn with_wheelsets<S: Into<String>>(names: impl IntoIterator<Item = S>) -> Self {
        Self {
            wheelsets: names.into_iter().map(WheelsetSeries::new).collect(),
            ..Self::default()
        }
    }

    /// Number of samples (the length of `time_s`).
    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    /// No samples yet.
    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }

    /// Append the sample at `time_s`: one [`WheelsetSample`] per wheelset,
    /// in order, for results without [`Self::bodies`] (else
    /// [`Self::push_sample`]). Nothing is appended when a count is wrong.
    pub fn push(&mut self, time_s: f64, samples: &[WheelsetSample]) -> Result<(), ResultsError> {
        self.push_sample(time_s, samples, &[])
    }

    /// Append the sample at `time_s`: one [`WheelsetSample`] per wheelset
    /// and one [`BodySample`] per body, each in order. Nothing is appended
    /// when a count is wrong.
    pub fn push_sample(
        &mut self,
        time_s: f64,
        samples: &[WheelsetSample],
        bodies: &[BodySample],
    ) -> Result<(), ResultsError> {
        if samples.len() != self.wheelsets.len() {
            return Err(ResultsError::WheelsetCount {
                expected: self.wheelsets.len(),
                found: samples.len(),
            });
        }
        if bodies.len() != self.bodies.len() {
            return Err(ResultsError::BodyCount {
                expected: self.bodies.len(),
                found: bodies.len(),
            });
        }
        self.time_s.push(time_s);
        for (ws, s) in self.wheelsets.iter_mut().zip(samples) {
            ws.push(s);
        }
        for (b, s) in self.bodies.iter_mut().zip(bodies) {
            b.push(s);
        }
        Ok(())
    }

    /// The value of run attribute `name`, if set.
    pub fn attribute(&self, name: &str) -> Option<&AttrValue> {
        self.attributes
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v)
    }

    /// The text of run attribute `name`, if set and a text
    /// ([`AttrValue::Text`]).
    pub fn attribute_text(&self, name: &str) -> Option<&str> {
        self.attribute(name).and_then(AttrValue::as_str)
    }

    /// Set run attribute `name` (replacing a value set before).
    pub fn set_attribute(&mut self, name: impl Into<String>, value: impl Into<AttrValue>) {
        let (name, value) = (name.into(), value.into());
        match self.attributes.iter_mut().find(|(k, _)| *k == name) {
            Some(slot) => slot.1 = value,
            None => self.attributes.push((name, value)),
        }
    }

    /// Check that the record is consistent: every series as long as
    /// `time_s`, times finite and non-decreasing, flags 0 or 1, body names
    /// non-empty and unique (the car body one of them), run attribute names
    /// non-empty, unique and not reserved.
    pub fn validate(&self) -> Result<(), ResultsError> {
        let n = self.time_s.len();
        for (index, &value) in self.time_s.iter().enumerate() {
            if !value.is_finite() {
                return Err(ResultsError::NonFiniteTime { index, value });
            }
            if index > 0 && value < self.time_s[index - 1] {
                return Err(ResultsError::TimeDecreasing {
                    index,
                    previous: self.time_s[index - 1],
                    value,
                });
            }
        }
        for (i, ws) in self.wheelsets.iter().enumerate() {
            let g = wheelset_group(i);
            for c in &WHEELSET_COLUMNS {
                check_column(n, &g, c, ws)?;
            }
            for (wheel, wg) in ws.wheels.iter().zip(WHEEL_GROUPS) {
                let g = format!("{g}/{wg}");
                for c in &WHEEL_COLUMNS {
                    check_column(n, &g, c, wheel)?;
                }
                for (zone, zg) in wheel.zones.iter().zip(ZONE_GROUPS) {
                    let g = format!("{g}/{zg}");
                    for c in &ZONE_COLUMNS {
                        check_column(n, &g, c, zone)?;
                    }
                }
            }
        }
        for (k, b) in self.bodies.iter().enumerate() {
            let g = format!("bodies/{}", b.name);
            for c in &BODY_COLUMNS {
                check_column(n, &g, c, b)?;
            }
            if b.name.is_empty() || self.bodies[..k].iter().any(|o| o.name == b.name) {
                return Err(ResultsError::BodyName {
                    index: k,
                    name: b.name.clone(),
                });
            }
        }
        if let Some(c) = &self.car_body
            && !self.bodies.iter().any(|b| b.name == c.name)
        {
            return Err(ResultsError::CarBody {
                name: c.name.clone(),
            });
        }
        for (k, (name, _)) in self.attributes.iter().enumerate() {
            let bad = |rule| {
                Err(ResultsError::Attribute {
                    name: name.clone(),
                    rule,
                })
            };
            if name.is_empty() || name.contains('\0') {
                return bad("the name must be non-empty and free of NUL characters");
            }
            if RESERVED_ATTRIBUTES.contains(&name.as_str()) {
                return bad("the name is reserved for the file's own attributes");
            }
            if self.attributes[..k].iter().any(|(other, _)| other == name) {
                return bad("the name is given twice");
            }
        }
        Ok(())
    }
}

/// Column `c` of the series `s` in group `group`: `n` values, flags within
/// their allowed bits.
fn check_column<S, V>(n: usize, group: &str, c: &Column<S, V>, s: &S) -> Result<(), ResultsError> {
    let series = || format!("{group}/{}", c.name());
    let len = c.len(s);
    if len != n {
        return Err(ResultsError::LengthMismatch {
            series: series(),
            len,
            expected: n,
        });
    }
    match c.bad_flag(s) {
        None => Ok(()),
        Some((index, value)) => Err(ResultsError::FlagValue {
            series: series(),
            index,
            value,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names<S, V>(columns: &[Column<S, V>]) -> Vec<&'static str> {
        columns.iter().map(Column::name).collect()
    }

    #[test]
    fn column_names_are_unique_and_documented() {
        for list in [
            names(&WHEELSET_COLUMNS),
            names(&WHEEL_COLUMNS),
            names(&ZONE_COLUMNS),
        ] {
            for (k, n) in list.iter().enumerate() {
                assert!(!list[..k].contains(n), "{n} twice");
            }
        }
        let docs = WHEELSET_COLUMNS
            .iter()
            .map(|c| c.dataset)
            .chain(WHEEL_COLUMNS.iter().map(|c| c.dataset))
            .chain(ZONE_COLUMNS.iter().map(|c| c.dataset));
        for d in docs {
            assert!(!d.units.is_empty() && !d.description.is_empty(), "{d:?}");
        }
    }

    #[test]
    fn a_zone_sample_comes_back_field_by_field() {
        // Every field distinct, so a column reaching the wrong field shows.
        let s = ZoneSample {
            in_contact: true,
            normal_n: 1.0,
            fx_n: 2.0,
            fy_n: 3.0,
            mz_nm: 4.0,
            lateral_force_n: 5.0,
            vertical_force_n: 6.0,
            xi: 7.0,
            eta: 8.0,
            phi_1_m: 9.0,
            y_wheel_m: 10.0,
            y_rail_m: 11.0,
            contact_angle_rad: 12.0,
            lead_m: 13.0,
            fallback: FALLBACK_HERTZ_FLOOR,
        };
        let mut z = ZoneSeries::default();
        z.push(&s);
        z.push(&ZoneSample::NO_CONTACT);
        assert_eq!(z.sample(0), Some(s));
        assert_eq!(z.sample(1).map(|s| s.in_contact), Some(false));
        assert!(z.sample(2).is_none());
        for c in &ZONE_COLUMNS {
            assert_eq!(c.len(&z), 2, "{}", c.name());
        }
    }
}
