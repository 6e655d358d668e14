//! The column list of the results: every time series of a wheelset, a
//! wheel and a contact zone, defined once (dataset name, unit, meaning with
//! its sign convention, and how to reach its values), so that recording,
//! validating, writing and reading loop over the list instead of spelling
//! each series.
//!
//! Frames and signs are those of docs/reference/01-units-frames.md §1: track frame `t` forward, `n`
//! left, `b` up; contact frame `n_c` from rail into wheel, `t_c` rolling
//! direction, `l_c = n_c × t_c`; forces and moments act **on the wheel**.

use super::curving::{sum_y_n, wear_number_n};
use super::{
    FALLBACK_HERTZ_FLOOR, FALLBACK_MINIMISATION, WheelSeries, WheelValues, WheelsetSample,
    WheelsetSeries, ZoneSample, ZoneSeries,
};

/// Name, unit and meaning of one stored series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dataset {
    /// The series' name (its dataset name in the results file).
    pub name: &'static str,
    /// Its unit ("1" for dimensionless values and flags).
    pub units: &'static str,
    /// What it is, with its sign convention.
    pub description: &'static str,
}

/// How one column's values are reached in a series struct `S` (e.g.
/// [`ZoneSeries`]) and in the sample struct `V` it is filled from (e.g.
/// [`ZoneSample`]).
pub struct Access<S, V, T> {
    /// The stored series.
    pub series: fn(&S) -> &[T],
    /// The stored series, to append to or replace.
    pub series_mut: fn(&mut S) -> &mut Vec<T>,
    /// The column's value in a sample.
    pub value: fn(&V) -> T,
    /// Set the column's value in a sample.
    pub set: fn(&mut V, T),
}

/// The element type of a column.
pub enum Values<S, V> {
    /// `f64` values (NaN where a zone is out of contact).
    F64(Access<S, V, f64>),
    /// `u8` flags; a value may hold only the bits of `allowed` (1 for a
    /// 0-or-1 flag).
    Flags {
        access: Access<S, V, u8>,
        allowed: u8,
    },
}

/// One column: a series of every wheelset, wheel or zone.
pub struct Column<S, V> {
    pub dataset: Dataset,
    pub values: Values<S, V>,
    /// Added to results schema version 1 after its first files were
    /// written: a reader of an older file that lacks it fills it (zones:
    /// the value of [`ZoneSample::NO_CONTACT`], i.e. NaN leads and no
    /// fallbacks; wheels: Y, Q, Y/Q and Tγ from the zones,
    /// [`WheelValues::of`]; derived columns, ΣY and the zones' Tγ, from
    /// the samples read).
    pub added_later: bool,
}

impl<S, V> Column<S, V> {
    /// The column's name.
    pub fn name(&self) -> &'static str {
        self.dataset.name
    }

    /// Number of stored values.
    pub fn len(&self, s: &S) -> usize {
        match &self.values {
            Values::F64(a) => (a.series)(s).len(),
            Values::Flags { access, .. } => (access.series)(s).len(),
        }
    }

    /// Append the column's value of sample `v`.
    pub fn push(&self, s: &mut S, v: &V) {
        match &self.values {
            Values::F64(a) => (a.series_mut)(s).push((a.value)(v)),
            Values::Flags { access: a, .. } => (a.series_mut)(s).push((a.value)(v)),
        }
    }

    /// Copy stored value `i`, if there is one, into sample `v`.
    pub fn copy_into(&self, s: &S, i: usize, v: &mut V) {
        match &self.values {
            Values::F64(a) => {
                if let Some(&x) = (a.series)(s).get(i) {
                    (a.set)(v, x);
                }
            }
            Values::Flags { access: a, .. } => {
                if let Some(&x) = (a.series)(s).get(i) {
                    (a.set)(v, x);
                }
            }
        }
    }

    /// Replace the stored series by the column's values of `samples`.
    pub fn fill(&self, s: &mut S, samples: &[V]) {
        match &self.values {
            Values::F64(a) => *(a.series_mut)(s) = samples.iter().map(a.value).collect(),
            Values::Flags { access: a, .. } => {
                *(a.series_mut)(s) = samples.iter().map(a.value).collect();
            }
        }
    }

    /// The first stored flag holding a bit outside `allowed`, as (index,
    /// value); `None` for `f64` columns.
    pub fn bad_flag(&self, s: &S) -> Option<(usize, u8)> {
        match &self.values {
            Values::F64(_) => None,
            Values::Flags { access, allowed } => (access.series)(s)
                .iter()
                .enumerate()
                .find(|&(_, f)| f & !allowed != 0)
                .map(|(i, &f)| (i, f)),
        }
    }
}

/// An `f64` column whose series field, sample field and dataset are all
/// named `$field`.
macro_rules! f64_column {
    ($field:ident, $units:literal, $description:literal, added_later: $later:literal) => {
        Column {
            dataset: Dataset {
                name: stringify!($field),
                units: $units,
                description: $description,
            },
            values: Values::F64(Access {
                series: |s| &s.$field,
                series_mut: |s| &mut s.$field,
                value: |v| v.$field,
                set: |v, x| v.$field = x,
            }),
            added_later: $later,
        }
    };
    ($field:ident, $units:literal, $description:literal) => {
        f64_column!($field, $units, $description, added_later: false)
    };
}

/// A 0-or-1 flag column stored as `u8` from a `bool` sample field, all
/// named `$field`.
macro_rules! bool_column {
    ($field:ident, $description:literal) => {
        Column {
            dataset: Dataset {
                name: stringify!($field),
                units: "1",
                description: $description,
            },
            values: Values::Flags {
                access: Access {
                    series: |s| &s.$field,
                    series_mut: |s| &mut s.$field,
                    value: |v| u8::from(v.$field),
                    set: |v, x| v.$field = x != 0,
                },
                allowed: 1,
            },
            added_later: false,
        }
    };
}

/// An `f64` column derived from the sample by `$value` (no field of its
/// own in the sample; a sample read back does not carry it), added later.
macro_rules! derived_column {
    ($field:ident, $units:literal, $description:literal, $value:expr) => {
        Column {
            dataset: Dataset {
                name: stringify!($field),
                units: $units,
                description: $description,
            },
            values: Values::F64(Access {
                series: |s| &s.$field,
                series_mut: |s| &mut s.$field,
                value: $value,
                set: |_, _| {},
            }),
            added_later: true,
        }
    };
}

/// The time of every sample ([`super::RunResults::time_s`]).
pub const TIME_S: Dataset = Dataset {
    name: "time_s",
    units: "s",
    description: "time since the start of the run",
};

/// The series of a wheelset, in file order.
pub const WHEELSET_COLUMNS: [Column<WheelsetSeries, WheelsetSample>; 7] = [
    f64_column!(
        lateral_m,
        "m",
        "lateral displacement of the wheelset centre from the track centreline, + left"
    ),
    f64_column!(
        yaw_rad,
        "rad",
        "yaw angle relative to the track, + nose left"
    ),
    f64_column!(
        roll_rad,
        "rad",
        "roll angle relative to the track, + raising the left wheel"
    ),
    f64_column!(
        distance_m,
        "m",
        "distance travelled along the track centreline since the start"
    ),
    f64_column!(speed_m_s, "m/s", "forward speed along the track"),
    f64_column!(
        track_s_m,
        "m",
        "track position of the wheelset centre: arc length s of the track centreline at its section (NaN in files from before it was stored)",
        added_later: true
    ),
    derived_column!(
        sum_y_n,
        "N",
        "sum Y, the track shifting force: lateral contact forces of both wheels (tread + flange) summed along the track's lateral axis, on the wheelset, + left (= Y_right - Y_left); 0 without contact",
        sum_y_n
    ),
];

/// The series of a wheel (its zones apart), in file order.
pub const WHEEL_COLUMNS: [Column<WheelSeries, WheelValues>; 6] = [
    f64_column!(
        travelled_m,
        "m",
        "distance travelled by the wheel along its rail: arc length of the contact point on the rail since the start"
    ),
    bool_column!(
        flange_contact,
        "1 when the flange zone of this wheel is in contact, else 0"
    ),
    f64_column!(
        y_n,
        "N",
        "Y: lateral contact force on the wheel (tread + flange) in the track frame, + towards the track centre (left wheel along -n, right wheel along +n); NaN without contact",
        added_later: true
    ),
    f64_column!(
        q_n,
        "N",
        "Q: vertical contact force on the wheel (tread + flange) along the track's up axis, the wheel load; NaN without contact",
        added_later: true
    ),
    f64_column!(
        y_over_q,
        "1",
        "Y/Q, Nadal's derailment quotient; compare with the group's nadal_limit attribute; NaN without contact",
        added_later: true
    ),
    f64_column!(
        wear_number_n,
        "N",
        "wear number T gamma of the wheel: its zones' wear numbers summed; NaN without contact",
        added_later: true
    ),
];

/// The series of a contact zone, in file order.
pub const ZONE_COLUMNS: [Column<ZoneSeries, ZoneSample>; 16] = [
    bool_column!(
        in_contact,
        "1 when this zone is in contact, else 0 (the zone's other series are NaN then)"
    ),
    f64_column!(
        normal_n,
        "N",
        "normal contact force on the wheel along n_c (from rail into wheel), >= 0; NaN out of contact"
    ),
    f64_column!(
        fx_n,
        "N",
        "longitudinal creep force on the wheel along t_c (rolling direction); NaN out of contact"
    ),
    f64_column!(
        fy_n,
        "N",
        "lateral creep force on the wheel along l_c = n_c x t_c; NaN out of contact"
    ),
    f64_column!(
        mz_nm,
        "N m",
        "spin creep moment on the wheel about n_c; NaN out of contact"
    ),
    f64_column!(
        lateral_force_n,
        "N",
        "total contact force (normal + creep) on the wheel along the track's lateral axis, + left; NaN out of contact"
    ),
    f64_column!(
        vertical_force_n,
        "N",
        "total contact force (normal + creep) on the wheel along the track's up axis, + up; NaN out of contact"
    ),
    f64_column!(
        xi,
        "1",
        "longitudinal creepage xi = (v_wheel - v_rail).t_c / V; NaN out of contact"
    ),
    f64_column!(
        eta,
        "1",
        "lateral creepage eta = (v_wheel - v_rail).l_c / V; NaN out of contact"
    ),
    f64_column!(
        phi_1_m,
        "1/m",
        "spin creepage phi = (omega_wheel - omega_rail).n_c / V; NaN out of contact"
    ),
    f64_column!(
        y_wheel_m,
        "m",
        "lateral coordinate of the contact point on the wheel profile (profile file coordinates); NaN out of contact"
    ),
    f64_column!(
        y_rail_m,
        "m",
        "lateral coordinate of the contact point on the rail profile (profile file coordinates); NaN out of contact"
    ),
    f64_column!(
        contact_angle_rad,
        "rad",
        "angle of the contact normal from the track's up axis in the cross-section, + towards the gauge (flange) side on both wheels; NaN out of contact"
    ),
    f64_column!(
        lead_m,
        "m",
        "lead of the contact point: distance ahead of the axle along the wheelset's forward direction, r sin(s_w); < 0: lag; NaN out of contact",
        added_later: true
    ),
    Column {
        dataset: Dataset {
            name: "fallback",
            units: "1",
            description: "bit flags of the fallbacks: 1 = contact point from the minimisation fallback (nearly conformal contact, Newton's Jacobian singular), 2 = non-Hertzian geometry, ellipse from floored relative curvatures (non_hertzian = floor); 0 none",
        },
        values: Values::Flags {
            access: Access {
                series: |s| &s.fallback,
                series_mut: |s| &mut s.fallback,
                value: |v| v.fallback,
                set: |v, x| v.fallback = x,
            },
            allowed: FALLBACK_MINIMISATION | FALLBACK_HERTZ_FLOOR,
        },
        added_later: true,
    },
    derived_column!(
        wear_number_n,
        "N",
        "wear number T gamma = |Fx xi| + |Fy eta| + |Mz phi| (creep forces times creepages, spin included); NaN out of contact",
        wear_number_n
    ),
];
