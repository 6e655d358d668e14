//! The simulation results file: time series of every wheelset, wheel and
//! contact zone of a run, in HDF5 (the public format engineers open with
//! h5py, h5dump or MATLAB).
//!
//! # Layout (results schema version 1)
//!
//! ```text
//! /                              root attributes:
//!                                  schema = "railsim-results"   (string)
//!                                  schema_version = 1           (u32)
//!                                  tool = "sim", tool_version   (strings; the crate version)
//!                                  <key> = <value>              (strings: the run's free-form
//!                                                                metadata, e.g. creep_law,
//!                                                                integrator, speed_m_s)
//! /time_s                        1-D f64 [n], units "s"
//! /scene                         scalar string: the scene TOML as run (after overrides)
//! /wheelset_<i>/                 i = 0, 1, … in vehicle order (front first);
//!                                attribute `name` (string)
//!     lateral_m                  1-D f64 [n], lateral displacement of the wheelset centre
//!                                from the track centreline, + left (m)
//!     yaw_rad                    yaw relative to the track, + nose left (rad)
//!     roll_rad                   roll relative to the track, + raising the left wheel (rad)
//!     distance_m                 distance travelled along the track centreline since the start (m)
//!     speed_m_s                  forward speed along the track (m/s)
//!     left/  right/              the two wheels (left/right facing the direction of travel)
//!         travelled_m            1-D f64 [n], distance travelled by the wheel along its rail:
//!                                the contact point's rail arc length since the start (m)
//!         flange_contact         1-D u8 [n], 1 when the flange zone is in contact, else 0
//!         y_n                    f64, Y: lateral contact force on the wheel, tread + flange,
//!                                + towards the track centre (left wheel −n, right wheel +n)
//!                                (N); NaN when the wheel has no contact
//!         q_n                    f64, Q: vertical contact force on the wheel, tread + flange,
//!                                along the track's up axis (N, the wheel load); NaN likewise
//!         y_over_q               f64, Y/Q (1), Nadal's derailment quotient; NaN likewise
//!                                attributes (when the wheel has a flange): flange_angle_rad
//!                                (steepest flank), friction, nadal_limit =
//!                                (tan γ − μ)/(1 + μ tan γ) (Nadal 1908)
//!         tread/  flange/        the two contact zones, each with 1-D datasets [n]:
//!             in_contact         u8, 1 when the zone is in contact, else 0
//!             normal_n           f64, normal force on the wheel along n_c (N, ≥ 0)
//!             fx_n               f64, longitudinal creep force on the wheel along t_c (N)
//!             fy_n               f64, lateral creep force on the wheel along l_c = n_c × t_c (N)
//!             mz_nm              f64, spin creep moment on the wheel about n_c (N m)
//!             lateral_force_n    f64, total contact force on the wheel along the track's
//!                                lateral axis, + left (N)
//!             vertical_force_n   f64, total contact force on the wheel along the track's
//!                                up axis, + up (N)
//!             xi                 f64, longitudinal creepage ξ = (v_w − v_r)·t_c / V (1)
//!             eta                f64, lateral creepage η = (v_w − v_r)·l_c / V (1)
//!             phi_1_m            f64, spin creepage φ = (ω_w − ω_r)·n_c / V (1/m)
//!             y_wheel_m          f64, contact point's lateral coordinate on the wheel
//!                                profile (profile file coordinates, m)
//!             y_rail_m           f64, the same on the rail profile (m)
//!             contact_angle_rad  f64, angle of the contact normal from the track's up
//!                                axis in the cross-section, + towards the flange side
//!                                (the gauge side) on both wheels (rad)
//!             lead_m             f64, lead of the contact point: its distance ahead of the
//!                                axle along the wheelset's forward direction, r·sin s_w
//!                                (m; < 0: lag)
//!             fallback           u8, bit flags of the documented fallbacks the contact
//!                                went through: 1 = contact point from the minimisation
//!                                fallback (nearly conformal, Newton's Jacobian singular;
//!                                `runtime::contact`), 2 = non-Hertzian geometry, ellipse
//!                                from floored curvatures (`NonHertzianPolicy::Floor`); 0 none
//! ```
//!
//! Every dataset has the same length n as `/time_s`, a `units` attribute
//! ("1" for dimensionless and flags) and a `description` attribute stating
//! its meaning and sign convention (the text of the table above). Frames and
//! signs are those of SPEC §1: track frame `t` forward, `n` left, `b` up;
//! contact frame `n_c` from rail into wheel, `t_c` rolling direction,
//! `l_c = n_c × t_c`; forces and moments are those acting **on the wheel**.
//! A zone's f64 values are NaN at samples where it is not in contact.
//!
//! `y_n`, `q_n`, `y_over_q`, `lead_m` and `fallback` were added after the
//! first files of version 1 were written: the reader fills them (Y, Q and
//! Y/Q from the zones, NaN leads, no fallbacks) when a file lacks them.
//!
//! Datasets are contiguous and uncompressed (a 13.5 s run sampled at 1 kHz
//! with two wheelsets is about 12 MB). Root attribute creation order is
//! tracked, so the run metadata reads back in the order it was written.
//! The file is written atomically ([`AtomicFile`]): nothing appears at the
//! destination unless the whole file was written.
//!
//! The reader refuses a file whose `schema` is not `railsim-results` or
//! whose `schema_version` it does not know. Readers look datasets up by
//! name: later versions may add datasets or attributes without breaking
//! this reader; anything that changes the meaning of an existing one bumps
//! [`RESULTS_SCHEMA_VERSION`].
//!
//! ```text
//! # h5py
//! import h5py
//! f = h5py.File("run.h5")
//! t = f["time_s"][:]; y = f["wheelset_0/lateral_m"][:]
//! Y = f["wheelset_0/left/flange/lateral_force_n"][:]
//! ```

use std::path::Path;

use hdf5::types::VarLenUnicode;
use hdf5::{IndexType, IterationOrder};

use super::columns::to_vlu;
use super::{AtomicFile, SchemaError, attrs};
use crate::contact::nadal::NadalLimit;

/// Value of the root attribute `schema` of a results file.
pub const RESULTS_SCHEMA: &str = "railsim-results";
/// Version of the results layout this build writes and reads.
pub const RESULTS_SCHEMA_VERSION: u32 = 1;
/// Value of the root attribute `tool`.
pub const RESULTS_TOOL: &str = "sim";
/// Root attribute names the writer sets itself; run metadata may not use them.
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
    /// integrator, speed); values are strings. Names must be non-empty,
    /// unique and not one of [`RESERVED_ATTRIBUTES`].
    pub attributes: Vec<(String, String)>,
}

/// Time series of one wheelset (all the length of [`RunResults::time_s`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WheelsetSeries {
    /// The wheelset's name in the vehicle (e.g. "front").
    pub name: String,
    /// Lateral displacement of the wheelset centre from the track
    /// centreline (m), + towards the left rail (SPEC §1).
    pub lateral_m: Vec<f64>,
    /// Yaw angle relative to the track (rad), + nose left.
    pub yaw_rad: Vec<f64>,
    /// Roll angle relative to the track (rad), + raising the left wheel.
    pub roll_rad: Vec<f64>,
    /// Distance travelled along the track centreline since the start (m).
    pub distance_m: Vec<f64>,
    /// Forward speed along the track (m/s).
    pub speed_m_s: Vec<f64>,
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
    /// The wheel's Nadal limit (steepest flange angle, friction), when it
    /// has a flange and the writer knew it.
    pub nadal: Option<NadalLimit>,
    /// `[tread, flange]`.
    pub zones: [ZoneSeries; 2],
}

/// Time series of one contact zone (tread or flange) of one wheel. Every
/// f64 series is NaN at samples where the zone is not in contact. Contact
/// frame (SPEC §1): `n_c` from rail into wheel, `t_c` rolling direction,
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
/// floored curvatures (`crate::contact_force::NonHertzianPolicy::Floor`).
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
}

/// Name, unit and description of one dataset.
struct Field {
    name: &'static str,
    units: &'static str,
    description: &'static str,
}

const fn field(name: &'static str, units: &'static str, description: &'static str) -> Field {
    Field {
        name,
        units,
        description,
    }
}

/// The f64 datasets of a wheelset group, in the order of
/// [`WheelsetSeries::columns`].
const WHEELSET_F64: [Field; 5] = [
    field(
        "lateral_m",
        "m",
        "lateral displacement of the wheelset centre from the track centreline, + left",
    ),
    field(
        "yaw_rad",
        "rad",
        "yaw angle relative to the track, + nose left",
    ),
    field(
        "roll_rad",
        "rad",
        "roll angle relative to the track, + raising the left wheel",
    ),
    field(
        "distance_m",
        "m",
        "distance travelled along the track centreline since the start",
    ),
    field("speed_m_s", "m/s", "forward speed along the track"),
];

const TRAVELLED: Field = field(
    "travelled_m",
    "m",
    "distance travelled by the wheel along its rail: arc length of the contact point on the rail since the start",
);
const FLANGE_CONTACT: Field = field(
    "flange_contact",
    "1",
    "1 when the flange zone of this wheel is in contact, else 0",
);
const IN_CONTACT: Field = field(
    "in_contact",
    "1",
    "1 when this zone is in contact, else 0 (the zone's other series are NaN then)",
);
const FALLBACK: Field = field(
    "fallback",
    "1",
    "bit flags of the fallbacks: 1 = contact point from the minimisation fallback (nearly conformal contact, Newton's Jacobian singular), 2 = non-Hertzian geometry, ellipse from floored relative curvatures (non_hertzian = floor); 0 none",
);

/// The per-wheel f64 datasets, in the order of [`WheelSeries::quotient_columns`].
const WHEEL_F64: [Field; 3] = [
    field(
        "y_n",
        "N",
        "Y: lateral contact force on the wheel (tread + flange) in the track frame, + towards the track centre (left wheel along -n, right wheel along +n); NaN without contact",
    ),
    field(
        "q_n",
        "N",
        "Q: vertical contact force on the wheel (tread + flange) along the track's up axis, the wheel load; NaN without contact",
    ),
    field(
        "y_over_q",
        "1",
        "Y/Q, Nadal's derailment quotient; compare with the group's nadal_limit attribute; NaN without contact",
    ),
];

/// The f64 datasets of a zone group, in the order of [`ZoneSeries::columns`].
const ZONE_F64: [Field; 13] = [
    field(
        "normal_n",
        "N",
        "normal contact force on the wheel along n_c (from rail into wheel), >= 0; NaN out of contact",
    ),
    field(
        "fx_n",
        "N",
        "longitudinal creep force on the wheel along t_c (rolling direction); NaN out of contact",
    ),
    field(
        "fy_n",
        "N",
        "lateral creep force on the wheel along l_c = n_c x t_c; NaN out of contact",
    ),
    field(
        "mz_nm",
        "N m",
        "spin creep moment on the wheel about n_c; NaN out of contact",
    ),
    field(
        "lateral_force_n",
        "N",
        "total contact force (normal + creep) on the wheel along the track's lateral axis, + left; NaN out of contact",
    ),
    field(
        "vertical_force_n",
        "N",
        "total contact force (normal + creep) on the wheel along the track's up axis, + up; NaN out of contact",
    ),
    field(
        "xi",
        "1",
        "longitudinal creepage xi = (v_wheel - v_rail).t_c / V; NaN out of contact",
    ),
    field(
        "eta",
        "1",
        "lateral creepage eta = (v_wheel - v_rail).l_c / V; NaN out of contact",
    ),
    field(
        "phi_1_m",
        "1/m",
        "spin creepage phi = (omega_wheel - omega_rail).n_c / V; NaN out of contact",
    ),
    field(
        "y_wheel_m",
        "m",
        "lateral coordinate of the contact point on the wheel profile (profile file coordinates); NaN out of contact",
    ),
    field(
        "y_rail_m",
        "m",
        "lateral coordinate of the contact point on the rail profile (profile file coordinates); NaN out of contact",
    ),
    field(
        "contact_angle_rad",
        "rad",
        "angle of the contact normal from the track's up axis in the cross-section, + towards the gauge (flange) side on both wheels; NaN out of contact",
    ),
    field(
        "lead_m",
        "m",
        "lead of the contact point: distance ahead of the axle along the wheelset's forward direction, r sin(s_w); < 0: lag; NaN out of contact",
    ),
];

impl ZoneSeries {
    /// The f64 series in the order of `ZONE_F64`.
    fn columns(&self) -> [&Vec<f64>; 13] {
        [
            &self.normal_n,
            &self.fx_n,
            &self.fy_n,
            &self.mz_nm,
            &self.lateral_force_n,
            &self.vertical_force_n,
            &self.xi,
            &self.eta,
            &self.phi_1_m,
            &self.y_wheel_m,
            &self.y_rail_m,
            &self.contact_angle_rad,
            &self.lead_m,
        ]
    }

    fn columns_mut(&mut self) -> [&mut Vec<f64>; 13] {
        [
            &mut self.normal_n,
            &mut self.fx_n,
            &mut self.fy_n,
            &mut self.mz_nm,
            &mut self.lateral_force_n,
            &mut self.vertical_force_n,
            &mut self.xi,
            &mut self.eta,
            &mut self.phi_1_m,
            &mut self.y_wheel_m,
            &mut self.y_rail_m,
            &mut self.contact_angle_rad,
            &mut self.lead_m,
        ]
    }

    /// Append one sample. A sample out of contact is stored as
    /// [`ZoneSample::NO_CONTACT`] (flag 0, NaN values) whatever its values.
    pub fn push(&mut self, s: &ZoneSample) {
        let s = if s.in_contact {
            s
        } else {
            &ZoneSample::NO_CONTACT
        };
        self.in_contact.push(u8::from(s.in_contact));
        self.fallback.push(s.fallback);
        let values = [
            s.normal_n,
            s.fx_n,
            s.fy_n,
            s.mz_nm,
            s.lateral_force_n,
            s.vertical_force_n,
            s.xi,
            s.eta,
            s.phi_1_m,
            s.y_wheel_m,
            s.y_rail_m,
            s.contact_angle_rad,
            s.lead_m,
        ];
        for (col, v) in self.columns_mut().into_iter().zip(values) {
            col.push(v);
        }
    }

    /// Sample `i`, if there is one.
    pub fn sample(&self, i: usize) -> Option<ZoneSample> {
        let c = self.columns();
        let v = |k: usize| c[k].get(i).copied().unwrap_or(f64::NAN);
        Some(ZoneSample {
            in_contact: *self.in_contact.get(i)? != 0,
            normal_n: v(0),
            fx_n: v(1),
            fy_n: v(2),
            mz_nm: v(3),
            lateral_force_n: v(4),
            vertical_force_n: v(5),
            xi: v(6),
            eta: v(7),
            phi_1_m: v(8),
            y_wheel_m: v(9),
            y_rail_m: v(10),
            contact_angle_rad: v(11),
            lead_m: v(12),
            fallback: self.fallback.get(i).copied().unwrap_or(0),
        })
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
        self.travelled_m.push(s.travelled_m);
        self.flange_contact.push(u8::from(s.zones[1].in_contact));
        let (y, q, ratio) = wheel_y_q(side, &s.zones);
        self.y_n.push(y);
        self.q_n.push(q);
        self.y_over_q.push(ratio);
        for (zone, z) in self.zones.iter_mut().zip(&s.zones) {
            zone.push(z);
        }
    }

    /// Y, Q, Y/Q in the order of `WHEEL_F64`.
    fn quotient_columns(&self) -> [&Vec<f64>; 3] {
        [&self.y_n, &self.q_n, &self.y_over_q]
    }

    fn quotient_columns_mut(&mut self) -> [&mut Vec<f64>; 3] {
        [&mut self.y_n, &mut self.q_n, &mut self.y_over_q]
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

    /// The f64 series in the order of `WHEELSET_F64`.
    fn columns(&self) -> [&Vec<f64>; 5] {
        [
            &self.lateral_m,
            &self.yaw_rad,
            &self.roll_rad,
            &self.distance_m,
            &self.speed_m_s,
        ]
    }

    fn columns_mut(&mut self) -> [&mut Vec<f64>; 5] {
        [
            &mut self.lateral_m,
            &mut self.yaw_rad,
            &mut self.roll_rad,
            &mut self.distance_m,
            &mut self.speed_m_s,
        ]
    }

    /// Append one sample.
    pub fn push(&mut self, s: &WheelsetSample) {
        let values = [
            s.lateral_m,
            s.yaw_rad,
            s.roll_rad,
            s.distance_m,
            s.speed_m_s,
        ];
        for (col, v) in self.columns_mut().into_iter().zip(values) {
            col.push(v);
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
    /// in order. Nothing is appended when the count is wrong.
    pub fn push(&mut self, time_s: f64, samples: &[WheelsetSample]) -> Result<(), ResultsError> {
        if samples.len() != self.wheelsets.len() {
            return Err(ResultsError::WheelsetCount {
                expected: self.wheelsets.len(),
                found: samples.len(),
            });
        }
        self.time_s.push(time_s);
        for (ws, s) in self.wheelsets.iter_mut().zip(samples) {
            ws.push(s);
        }
        Ok(())
    }

    /// The value of run attribute `name`, if set.
    pub fn attribute(&self, name: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// Check that the record is consistent: every series as long as
    /// `time_s`, times finite and non-decreasing, flags 0 or 1, run
    /// attribute names non-empty, unique and not reserved.
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
        let check_len = |series: &dyn Fn() -> String, len: usize| {
            if len == n {
                Ok(())
            } else {
                Err(ResultsError::LengthMismatch {
                    series: series(),
                    len,
                    expected: n,
                })
            }
        };
        let check_flags = |series: &dyn Fn() -> String, flags: &[u8]| {
            check_len(series, flags.len())?;
            match flags.iter().position(|&f| f > 1) {
                None => Ok(()),
                Some(index) => Err(ResultsError::FlagValue {
                    series: series(),
                    index,
                    value: flags[index],
                }),
            }
        };
        for (i, ws) in self.wheelsets.iter().enumerate() {
            let g = wheelset_group(i);
            for (f, col) in WHEELSET_F64.iter().zip(ws.columns()) {
                check_len(&|| format!("{g}/{}", f.name), col.len())?;
            }
            for (wheel, wg) in ws.wheels.iter().zip(WHEEL_GROUPS) {
                let g = format!("{g}/{wg}");
                check_len(
                    &|| format!("{g}/{}", TRAVELLED.name),
                    wheel.travelled_m.len(),
                )?;
                check_flags(
                    &|| format!("{g}/{}", FLANGE_CONTACT.name),
                    &wheel.flange_contact,
                )?;
                for (f, col) in WHEEL_F64.iter().zip(wheel.quotient_columns()) {
                    check_len(&|| format!("{g}/{}", f.name), col.len())?;
                }
                for (zone, zg) in wheel.zones.iter().zip(ZONE_GROUPS) {
                    let g = format!("{g}/{zg}");
                    check_flags(&|| format!("{g}/{}", IN_CONTACT.name), &zone.in_contact)?;
                    let series = || format!("{g}/{}", FALLBACK.name);
                    check_len(&series, zone.fallback.len())?;
                    let all = FALLBACK_MINIMISATION | FALLBACK_HERTZ_FLOOR;
                    if let Some(index) = zone.fallback.iter().position(|&f| f & !all != 0) {
                        return Err(ResultsError::FlagValue {
                            series: series(),
                            index,
                            value: zone.fallback[index],
                        });
                    }
                    for (f, col) in ZONE_F64.iter().zip(zone.columns()) {
                        check_len(&|| format!("{g}/{}", f.name), col.len())?;
                    }
                }
            }
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

// ---------------------------------------------------------------------------
// Writing

fn hdf5_err(path: &Path, action: impl Into<String>) -> impl FnOnce(hdf5::Error) -> SchemaError {
    let path = path.to_path_buf();
    let action = action.into();
    move |source| SchemaError::Hdf5 {
        path,
        action,
        source,
    }
}

/// Write a 1-D dataset with its `units` and `description`.
fn write_series<T: hdf5::H5Type>(
    path: &Path,
    group: &hdf5::Group,
    field: &Field,
    values: &[T],
) -> Result<(), SchemaError> {
    let what = format!("{}/{}", group.name().trim_end_matches('/'), field.name);
    let ds = group
        .new_dataset_builder()
        .with_data(values)
        .create(field.name)
        .map_err(hdf5_err(path, format!("writing {what}")))?;
    attrs::write_str(path, &ds, "units", field.units)?;
    attrs::write_str(path, &ds, "description", field.description)
}

fn create_group(path: &Path, parent: &hdf5::Group, name: &str) -> Result<hdf5::Group, SchemaError> {
    parent
        .create_group(name)
        .map_err(hdf5_err(path, format!("creating group {name}")))
}

/// Write `/scene` (the dataset handle is closed on return, so the file can
/// be closed completely).
fn write_scene(path: &Path, file: &hdf5::File, text: &str) -> Result<(), SchemaError> {
    let scene = file
        .new_dataset::<VarLenUnicode>()
        .shape(())
        .create("scene")
        .map_err(hdf5_err(path, "creating /scene"))?;
    scene
        .write_scalar(&to_vlu(text))
        .map_err(hdf5_err(path, "writing /scene"))?;
    attrs::write_str(
        path,
        &scene,
        "description",
        "the scene (TOML) as run, after command-line overrides",
    )
}

/// Write `results` to `path` atomically (see the module docs for the
/// layout). The record is validated first; an inconsistent one is refused
/// and nothing is written.
pub fn write_results(path: &Path, results: &RunResults) -> Result<(), SchemaError> {
    results
        .validate()
        .map_err(|source| SchemaError::InvalidResults {
            path: path.to_path_buf(),
            source,
        })?;
    let atomic = AtomicFile::new(path);
    let file = hdf5::File::with_options()
        .with_fcpl(|p| p.attr_creation_order(hdf5::plist::file_create::AttrCreationOrder::Indexed))
        .create(atomic.temp_path())
        .map_err(|source| SchemaError::Create {
            path: path.to_path_buf(),
            source,
        })?;

    attrs::write_str(path, &file, "schema", RESULTS_SCHEMA)?;
    attrs::write_u32(path, &file, "schema_version", RESULTS_SCHEMA_VERSION)?;
    attrs::write_str(path, &file, "tool", RESULTS_TOOL)?;
    attrs::write_str(path, &file, "tool_version", env!("CARGO_PKG_VERSION"))?;
    for (name, value) in &results.attributes {
        attrs::write_str(path, &file, name, value)?;
    }

    write_series(
        path,
        &file,
        &field("time_s", "s", "time since the start of the run"),
        &results.time_s,
    )?;
    write_scene(path, &file, &results.scene_toml)?;

    for (i, ws) in results.wheelsets.iter().enumerate() {
        let g = create_group(path, &file, &wheelset_group(i))?;
        attrs::write_str(path, &g, "name", &ws.name)?;
        for (f, col) in WHEELSET_F64.iter().zip(ws.columns()) {
            write_series(path, &g, f, col)?;
        }
        for (wheel, wg) in ws.wheels.iter().zip(WHEEL_GROUPS) {
            let g = create_group(path, &g, wg)?;
            write_series(path, &g, &TRAVELLED, &wheel.travelled_m)?;
            write_series(path, &g, &FLANGE_CONTACT, &wheel.flange_contact)?;
            for (f, col) in WHEEL_F64.iter().zip(wheel.quotient_columns()) {
                write_series(path, &g, f, col)?;
            }
            if let Some(n) = &wheel.nadal {
                attrs::write_f64(path, &g, "flange_angle_rad", n.flange_angle_rad)?;
                attrs::write_f64(path, &g, "friction", n.friction)?;
                attrs::write_f64(path, &g, "nadal_limit", n.limit)?;
            }
            for (zone, zg) in wheel.zones.iter().zip(ZONE_GROUPS) {
                let g = create_group(path, &g, zg)?;
                write_series(path, &g, &IN_CONTACT, &zone.in_contact)?;
                for (f, col) in ZONE_F64.iter().zip(zone.columns()) {
                    write_series(path, &g, f, col)?;
                }
                write_series(path, &g, &FALLBACK, &zone.fallback)?;
            }
        }
    }

    file.close().map_err(hdf5_err(path, "closing"))?;
    atomic.commit().map_err(|source| SchemaError::Io {
        path: path.to_path_buf(),
        source,
    })
}

// ---------------------------------------------------------------------------
// Reading

/// Read a 1-D dataset `group/name` of exactly `n` values.
fn read_series<T: hdf5::H5Type>(
    path: &Path,
    group: &hdf5::Group,
    name: &str,
    n: Option<usize>,
) -> Result<Vec<T>, SchemaError> {
    let what = format!("{}/{name}", group.name().trim_end_matches('/'));
    let ds = group.dataset(name).map_err(|_| SchemaError::Missing {
        path: path.to_path_buf(),
        what: format!("dataset {what}"),
    })?;
    let shape = ds.shape();
    let invalid = |rule: String| SchemaError::Invalid {
        path: path.to_path_buf(),
        object: what.clone(),
        rule,
    };
    if shape.len() != 1 {
        return Err(invalid(format!(
            "expected a 1-D dataset, found shape {shape:?}"
        )));
    }
    if let Some(n) = n
        && shape[0] != n
    {
        return Err(invalid(format!(
            "has {} samples, but /time_s has {n}",
            shape[0]
        )));
    }
    ds.read_raw()
        .map_err(hdf5_err(path, format!("reading {what}")))
}

/// Datasets added to version 1 after its first files (module docs): read
/// when present, filled when not.
const ADDED_LATER: [&str; 1] = ["lead_m"];

/// Whether `group` has a member `name`.
fn has(group: &hdf5::Group, name: &str) -> bool {
    group.link_exists(name)
}

fn open_group(path: &Path, parent: &hdf5::Group, name: &str) -> Result<hdf5::Group, SchemaError> {
    parent.group(name).map_err(|_| SchemaError::Missing {
        path: path.to_path_buf(),
        what: format!("group {}/{name}", parent.name().trim_end_matches('/')),
    })
}

/// Open a results file and check `schema` and `schema_version`.
fn open_results(path: &Path) -> Result<hdf5::File, SchemaError> {
    let file = hdf5::File::open(path).map_err(|source| SchemaError::Open {
        path: path.to_path_buf(),
        source,
    })?;
    let schema = attrs::read_str(path, &file, "the file", "schema").map_err(|e| match e {
        SchemaError::Missing { .. } => SchemaError::NotResults {
            path: path.to_path_buf(),
            found: None,
        },
        e => e,
    })?;
    if schema != RESULTS_SCHEMA {
        return Err(SchemaError::NotResults {
            path: path.to_path_buf(),
            found: Some(schema),
        });
    }
    let found: u32 = attrs::read(path, &file, "the file", "schema_version")?;
    if found != RESULTS_SCHEMA_VERSION {
        return Err(SchemaError::UnsupportedResultsVersion {
            path: path.to_path_buf(),
            found,
            supported: RESULTS_SCHEMA_VERSION,
        });
    }
    Ok(file)
}

/// The run metadata: every root attribute but the reserved ones, in
/// creation order when the file tracks it (files written here do), else in
/// name order.
fn read_run_attributes(
    path: &Path,
    file: &hdf5::File,
) -> Result<Vec<(String, String)>, SchemaError> {
    let by_creation = file
        .attr_names_by(IndexType::CreationOrder, IterationOrder::Increasing)
        .ok();
    let names = match by_creation {
        Some(names) => names,
        None => file
            .attr_names()
            .map_err(hdf5_err(path, "listing the root attributes"))?,
    };
    names
        .into_iter()
        .filter(|n| !RESERVED_ATTRIBUTES.contains(&n.as_str()))
        .map(|name| {
            let value = attrs::read_str(path, file, "the file", &name)?;
            Ok((name, value))
        })
        .collect()
}

/// Load a results file written by [`write_results`] (or any file following
/// the documented layout).
pub fn read_results(path: &Path) -> Result<RunResults, SchemaError> {
    let file = open_results(path)?;
    let attributes = read_run_attributes(path, &file)?;
    let time_s: Vec<f64> = read_series(path, &file, "time_s", None)?;
    let n = Some(time_s.len());
    let scene_toml = file
        .dataset("scene")
        .map_err(|_| SchemaError::Missing {
            path: path.to_path_buf(),
            what: "dataset /scene".into(),
        })?
        .read_scalar::<VarLenUnicode>()
        .map_err(hdf5_err(path, "reading /scene"))?
        .as_str()
        .to_string();

    // Wheelset groups must be numbered 0, 1, … without gaps.
    let members = file
        .member_names()
        .map_err(hdf5_err(path, "listing the root group"))?;
    let mut indices: Vec<usize> = members
        .iter()
        .filter_map(|m| m.strip_prefix("wheelset_")?.parse().ok())
        .collect();
    indices.sort_unstable();
    if let Some(gap) = indices.iter().enumerate().find(|(k, i)| *k != **i) {
        return Err(SchemaError::Missing {
            path: path.to_path_buf(),
            what: format!("group /{}", wheelset_group(gap.0)),
        });
    }

    let mut wheelsets = Vec::with_capacity(indices.len());
    for i in 0..indices.len() {
        let g = open_group(path, &file, &wheelset_group(i))?;
        let what = format!("/{}", wheelset_group(i));
        let mut ws = WheelsetSeries::new(attrs::read_str(path, &g, &what, "name")?);
        for (f, col) in WHEELSET_F64.iter().zip(ws.columns_mut()) {
            *col = read_series(path, &g, f.name, n)?;
        }
        for (side, (wheel, wg)) in ws.wheels.iter_mut().zip(WHEEL_GROUPS).enumerate() {
            let g = open_group(path, &g, wg)?;
            let what = format!("{what}/{wg}");
            wheel.travelled_m = read_series(path, &g, TRAVELLED.name, n)?;
            wheel.flange_contact = read_series(path, &g, FLANGE_CONTACT.name, n)?;
            let len = time_s.len();
            for (zone, zg) in wheel.zones.iter_mut().zip(ZONE_GROUPS) {
                let g = open_group(path, &g, zg)?;
                zone.in_contact = read_series(path, &g, IN_CONTACT.name, n)?;
                for (f, col) in ZONE_F64.iter().zip(zone.columns_mut()) {
                    *col = if ADDED_LATER.contains(&f.name) && !has(&g, f.name) {
                        vec![f64::NAN; len]
                    } else {
                        read_series(path, &g, f.name, n)?
                    };
                }
                zone.fallback = if has(&g, FALLBACK.name) {
                    read_series(path, &g, FALLBACK.name, n)?
                } else {
                    vec![0; len]
                };
            }
            if WHEEL_F64.iter().all(|f| has(&g, f.name)) {
                for (f, col) in WHEEL_F64.iter().zip(wheel.quotient_columns_mut()) {
                    *col = read_series(path, &g, f.name, n)?;
                }
            } else {
                // A file from before Y/Q was stored: from the zones.
                for i in 0..len {
                    let zones = [0, 1].map(|z| wheel.zones[z].sample(i).unwrap_or_default());
                    let (y, q, ratio) = wheel_y_q(side, &zones);
                    wheel.y_n.push(y);
                    wheel.q_n.push(q);
                    wheel.y_over_q.push(ratio);
                }
            }
            let names = g
                .attr_names()
                .map_err(hdf5_err(path, format!("listing the attributes of {what}")))?;
            let attr = |name: &str| -> Result<Option<f64>, SchemaError> {
                if names.iter().any(|n| n == name) {
                    Ok(Some(attrs::read(path, &g, &what, name)?))
                } else {
                    Ok(None)
                }
            };
            if let (Some(flange_angle_rad), Some(friction), Some(limit)) = (
                attr("flange_angle_rad")?,
                attr("friction")?,
                attr("nadal_limit")?,
            ) {
                wheel.nadal = Some(NadalLimit {
                    flange_angle_rad,
                    friction,
                    limit,
                });
            }
        }
        wheelsets.push(ws);
    }

    let results = RunResults {
        time_s,
        wheelsets,
        scene_toml,
        attributes,
    };
    results
        .validate()
        .map_err(|source| SchemaError::InvalidResults {
            path: path.to_path_buf(),
            source,
        })?;
    Ok(results)
}
