//! The simulation results file: time series of every wheelset, wheel and
//! contact zone of a run, in HDF5 (the public format engineers open with
//! h5py, h5dump or MATLAB).
//!
//! # Layout (results schema version 2)
//!
//! ```text
//! /                              root attributes:
//!                                  schema = "railsim-results"   (string)
//!                                  schema_version = 2           (u32)
//!                                  tool = "sim", tool_version   (strings; the crate version)
//!                                  <key> = <value>              (the run's free-form metadata,
//!                                                                typed: strings, f64, i64,
//!                                                                booleans, e.g. creep_law,
//!                                                                speed_m_s = 22.0, steps)
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
//!     track_s_m                  track position of the wheelset centre: the centreline's
//!                                arc length s at its section (m; NaN in older files)
//!     sum_y_n                    ΣY, track shifting force: both wheels' lateral contact
//!                                forces summed on the wheelset, + left (N) = Y_right − Y_left
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
//!         wear_number_n          f64, Tγ of the wheel, its zones' summed (N); NaN likewise
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
//!             wear_number_n      f64, wear number Tγ = |Fx ξ| + |Fy η| + |Mz φ| (N)
//! /bodies/<name>/                every rigid body's track-relative state (position,
//!                                yaw–roll–pitch, velocities, ride accelerations); layout in
//!                                `results_bodies`, definitions in [`crate::results::bodies`]
//! ```
//!
//! Every dataset has the same length n as `/time_s`, a `units` attribute
//! ("1" for dimensionless and flags) and a `description` attribute stating
//! its meaning and sign convention (the text of the table above). The
//! datasets of the wheelset, wheel and zone groups are those of the column
//! lists of [`crate::results`] (one definition each: name, unit,
//! description), written and read in a loop over them; the data types are
//! [`crate::results::RunResults`] and its parts. Frames and
//! signs are those of docs/reference/01-units-frames.md §1: track frame `t` forward, `n` left, `b` up;
//! contact frame `n_c` from rail into wheel, `t_c` rolling direction,
//! `l_c = n_c × t_c`; forces and moments are those acting **on the wheel**.
//! A zone's f64 values are NaN at samples where it is not in contact.
//!
//! # Versions
//!
//! `y_n`, `q_n`, `y_over_q`, `lead_m`, `fallback`, `track_s_m`, `sum_y_n`
//! and the `wear_number_n` of wheels and zones were added after the first
//! files of version 1 were written (`Column::added_later`): the reader
//! fills them (Y, Q, Y/Q, ΣY and Tγ from the zones, NaN leads, no
//! fallbacks, NaN track positions) when a file lacks
//! them. Version 2 stores the run attributes typed
//! ([`crate::results::AttrValue`]; a version-1 reader reads every root
//! attribute as a string and would fail on a number, hence the bump) and
//! adds `bodies/`. This build writes version 2 and reads versions 1 and 2:
//! a version-1 file's string attributes stay text and it has no bodies.
//!
//! Datasets are uncompressed, chunked ([`super::RESULTS_CHUNK_SAMPLES`]
//! samples per chunk) and extendable: `sim run` appends the samples while
//! the run goes on ([`super::ResultsWriter`]), so its memory does not grow
//! with the run's length (about 1.6 kB a sample for two wheelsets and
//! three bodies: a 13.5 s run sampled at 1 kHz is about 22 MB; docs/reference/04-table-files.md
//! §4.4). Root attribute creation order is
//! tracked, so the run metadata reads back in the order it was written.
//! The file is written atomically ([`AtomicFile`]): nothing appears at the
//! destination unless the whole file was written.
//!
//! The reader refuses a file whose `schema` is not `railsim-results` or
//! whose `schema_version` is outside 1 ..= [`RESULTS_SCHEMA_VERSION`]. Readers look datasets up by
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

use super::raw_series::SeriesMaker;
use super::results_writer::ResultsWriter;
use super::{SchemaError, attrs};
use crate::contact::nadal::NadalLimit;
use crate::results::{
    AttrValue, Column, RESERVED_ATTRIBUTES, RunResults, TIME_S, Values, WHEEL_COLUMNS,
    WHEEL_GROUPS, WHEELSET_COLUMNS, WheelValues, WheelsetSample, WheelsetSeries, ZONE_COLUMNS,
    ZONE_GROUPS, ZoneSample, wheelset_group,
};

/// Value of the root attribute `schema` of a results file.
pub const RESULTS_SCHEMA: &str = "railsim-results";
/// Version of the results layout this build writes; it reads every
/// version from 1 to this one (module docs, "Versions").
pub const RESULTS_SCHEMA_VERSION: u32 = 2;
/// Value of the root attribute `tool`.
pub const RESULTS_TOOL: &str = "sim";

/// Attributes of a wheel group holding its Nadal limit.
pub(super) const NADAL_ATTRIBUTES: [&str; 3] = ["flange_angle_rad", "friction", "nadal_limit"];

// ---------------------------------------------------------------------------
// Writing

pub(super) fn hdf5_err(
    path: &Path,
    action: impl Into<String>,
) -> impl FnOnce(hdf5::Error) -> SchemaError {
    let path = path.to_path_buf();
    let action = action.into();
    move |source| SchemaError::Hdf5 {
        path,
        action,
        source,
    }
}

/// Write `/scene` (through `maker`; the dataset is closed on return, so
/// the file can be closed completely).
pub(super) fn write_scene(
    path: &Path,
    maker: &SeriesMaker,
    file: &hdf5::File,
    text: &str,
) -> Result<(), SchemaError> {
    maker
        .write_text_dataset(
            file,
            "scene",
            text,
            "the scene (TOML) as run, after command-line overrides",
        )
        .map_err(hdf5_err(path, "writing /scene"))
}

/// Write `results` to `path` atomically (see the module docs for the
/// layout), in one chunk of a [`ResultsWriter`]. The record is validated
/// first; an inconsistent one is refused and nothing is written.
pub fn write_results(path: &Path, results: &RunResults) -> Result<(), SchemaError> {
    results
        .validate()
        .map_err(|source| SchemaError::InvalidResults {
            path: path.to_path_buf(),
            source,
        })?;
    let mut writer = ResultsWriter::create(path)?;
    writer.append_chunk(results)?;
    writer.finish(results)
}

// ---------------------------------------------------------------------------
// Reading
/// Read a 1-D dataset `group/name` of exactly `n` values.
pub(super) fn read_series<T: hdf5::H5Type>(
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

/// Whether `group` has a member `name`.
pub(super) fn has(group: &hdf5::Group, name: &str) -> bool {
    group.link_exists(name)
}

pub(super) fn open_group(
    path: &Path,
    parent: &hdf5::Group,
    name: &str,
) -> Result<hdf5::Group, SchemaError> {
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
    if !(1..=RESULTS_SCHEMA_VERSION).contains(&found) {
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
) -> Result<Vec<(String, AttrValue)>, SchemaError> {
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
            let value = attrs::read_value(path, file, "the file", &name)?;
            Ok((name, value))
        })
        .collect()
}

/// Read the columns of `columns` present in `group` into the series `s`
/// (`n` values each). A column added later that the file lacks is left
/// out and returned, for [`fill_columns`]; any other missing one is an
/// error.
pub(super) fn read_columns<'c, S, V>(
    path: &Path,
    group: &hdf5::Group,
    columns: &'c [Column<S, V>],
    s: &mut S,
    n: Option<usize>,
) -> Result<Vec<&'c Column<S, V>>, SchemaError> {
    let mut missing = Vec::new();
    for c in columns {
        if c.added_later && !has(group, c.name()) {
            missing.push(c);
            continue;
        }
        match &c.values {
            Values::F64(a) => *(a.series_mut)(s) = read_series(path, group, c.name(), n)?,
            Values::Flags { access, .. } => {
                *(access.series_mut)(s) = read_series(path, group, c.name(), n)?;
            }
        }
    }
    Ok(missing)
}

/// Fill the `missing` columns of the series `s` from its `len` samples as
/// read (`sample`: the sample at an index).
fn fill_columns<S, V>(
    s: &mut S,
    missing: &[&Column<S, V>],
    len: usize,
    sample: impl Fn(&S, usize) -> V,
) {
    if missing.is_empty() {
        return;
    }
    let samples: Vec<V> = (0..len).map(|i| sample(s, i)).collect();
    for c in missing {
        c.fill(s, &samples);
    }
}

/// Load a results file written by [`write_results`] (or any file following
/// the documented layout).
pub fn read_results(path: &Path) -> Result<RunResults, SchemaError> {
    let file = open_results(path)?;
    let attributes = read_run_attributes(path, &file)?;
    let time_s: Vec<f64> = read_series(path, &file, TIME_S.name, None)?;
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
        let len = time_s.len();
        let ws_missing = read_columns(path, &g, &WHEELSET_COLUMNS, &mut ws, n)?;
        for (side, (wheel, wg)) in ws.wheels.iter_mut().zip(WHEEL_GROUPS).enumerate() {
            let g = open_group(path, &g, wg)?;
            let what = format!("{what}/{wg}");
            let missing = read_columns(path, &g, &WHEEL_COLUMNS, wheel, n)?;
            for (zone, zg) in wheel.zones.iter_mut().zip(ZONE_GROUPS) {
                let g = open_group(path, &g, zg)?;
                let missing = read_columns(path, &g, &ZONE_COLUMNS, zone, n)?;
                // Derived columns (Tγ) from the zone's values read.
                fill_columns(zone, &missing, len, |z, i| {
                    z.sample(i).unwrap_or(ZoneSample::NO_CONTACT)
                });
            }
            // A file from before Y/Q was stored: from the zones.
            fill_columns(wheel, &missing, len, |w, i| {
                WheelValues::of(side, &w.sample(i).unwrap_or_default())
            });
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
            let [angle, friction, limit] = NADAL_ATTRIBUTES;
            if let (Some(flange_angle_rad), Some(friction), Some(limit)) =
                (attr(angle)?, attr(friction)?, attr(limit)?)
            {
                wheel.nadal = Some(NadalLimit {
                    flange_angle_rad,
                    friction,
                    limit,
                });
            }
        }
        // A file from before the track position was stored: unknown (NaN);
        // ΣY from the wheels read.
        fill_columns(&mut ws, &ws_missing, len, |ws, i| WheelsetSample {
            track_s_m: f64::NAN,
            wheels: [0, 1].map(|k| ws.wheels[k].sample(i).unwrap_or_default()),
            ..WheelsetSample::default()
        });
        wheelsets.push(ws);
    }
    let (bodies, car_body) = super::results_bodies::read(path, &file, n)?;
    let results = RunResults {
        time_s,
        wheelsets,
        scene_toml,
        attributes,
        bodies,
        car_body,
    };
    results
        .validate()
        .map_err(|source| SchemaError::InvalidResults {
            path: path.to_path_buf(),
            source,
        })?;
    Ok(results)
}
