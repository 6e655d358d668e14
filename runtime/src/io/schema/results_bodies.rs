//! The `bodies/` group of the results file: one subgroup per rigid body
//! (wheelsets first, then the free bodies, in vehicle order) holding the
//! series of [`crate::results::BODY_COLUMNS`] (frames and signs in
//! [`crate::results::bodies`]):
//!
//! ```text
//! /bodies/                 attributes (when the vehicle has one): car_body (its name),
//!                          car_body_rule ("named car body" | "heaviest free body")
//!     <name>/              the body's name (a '/' in it becomes '_'; a name
//!                          that would repeat another gets "_<index>");
//!                          attributes name, kind ("wheelset" | "body"),
//!                          index (u32, the order), mass_kg, assembly_x_m,
//!                          assembly_height_m (NaN for a wheelset)
//!         track_s_m, longitudinal_m, lateral_m, vertical_m, roll_rad, pitch_rad,
//!         yaw_rad, longitudinal_velocity_m_s, lateral_velocity_m_s,
//!         vertical_velocity_m_s, roll_rate_rad_s, pitch_rate_rad_s, yaw_rate_rad_s,
//!         lateral_acceleration_m_s2, vertical_acceleration_m_s2
//! ```
//!
//! A file without `bodies/` (written before the bodies were stored) reads
//! as no bodies.

use std::path::Path;

use super::results_file::{has, hdf5_err, open_group, read_columns};
use super::results_series::{SeriesCursor, SeriesSlot, add_columns};
use super::results_writer::create_group;
use super::{SchemaError, attrs};
use crate::results::paths::{BODIES_GROUP, body_group_names};
use crate::results::{BODY_COLUMNS, BodyKind, BodySeries, CarBody, RunResults};

/// Make `bodies/` and one subgroup per body of `record`, their series
/// listed on `series` (for [`append`], in this order).
pub(super) fn create(
    path: &Path,
    file: &hdf5::File,
    record: &RunResults,
    series: &mut Vec<SeriesSlot>,
) -> Result<(), SchemaError> {
    let g = create_group(path, file, BODIES_GROUP)?;
    if let Some(c) = &record.car_body {
        attrs::write_str(path, &g, "car_body", &c.name)?;
        attrs::write_str(path, &g, "car_body_rule", &c.rule)?;
    }
    let names = body_group_names(&record.bodies);
    for (k, (b, name)) in record.bodies.iter().zip(&names).enumerate() {
        let bg = create_group(path, &g, name)?;
        attrs::write_str(path, &bg, "name", &b.name)?;
        attrs::write_str(path, &bg, "kind", b.kind.as_str())?;
        attrs::write_u32(path, &bg, "index", u32::try_from(k).unwrap_or(u32::MAX))?;
        attrs::write_f64(path, &bg, "mass_kg", b.mass_kg)?;
        attrs::write_f64(path, &bg, "assembly_x_m", b.assembly_x_m)?;
        attrs::write_f64(path, &bg, "assembly_height_m", b.assembly_height_m)?;
        add_columns(&bg, &BODY_COLUMNS, series);
    }
    Ok(())
}

/// Append the samples of `bodies` to the next datasets of `series` (those
/// [`create`] listed, in its order) from sample `from` on.
pub(super) fn append(
    series: &mut SeriesCursor<'_>,
    bodies: &[BodySeries],
    from: usize,
) -> Result<(), SchemaError> {
    for b in bodies {
        series.append_columns(&BODY_COLUMNS, b, from)?;
    }
    Ok(())
}

/// The bodies of a results file, in their `index` order, and the car body;
/// none when the file has no `bodies/` group.
pub(super) fn read(
    path: &Path,
    file: &hdf5::File,
    n: Option<usize>,
) -> Result<(Vec<BodySeries>, Option<CarBody>), SchemaError> {
    if !has(file, BODIES_GROUP) {
        return Ok((Vec::new(), None));
    }
    let g = open_group(path, file, BODIES_GROUP)?;
    let what = format!("/{BODIES_GROUP}");
    let group_attrs = g
        .attr_names()
        .map_err(hdf5_err(path, format!("listing the attributes of {what}")))?;
    let car_body = if group_attrs.iter().any(|a| a == "car_body") {
        Some(CarBody {
            name: attrs::read_str(path, &g, &what, "car_body")?,
            rule: attrs::read_str(path, &g, &what, "car_body_rule")?,
        })
    } else {
        None
    };
    let members = g
        .member_names()
        .map_err(hdf5_err(path, format!("listing {what}")))?;
    let mut bodies = Vec::with_capacity(members.len());
    for m in members {
        let bg = open_group(path, &g, &m)?;
        let what = format!("{what}/{m}");
        let index: u32 = attrs::read(path, &bg, &what, "index")?;
        let kind_text = attrs::read_str(path, &bg, &what, "kind")?;
        let kind = BodyKind::parse(&kind_text).ok_or_else(|| SchemaError::Invalid {
            path: path.to_path_buf(),
            object: what.clone(),
            rule: format!("kind is \"{kind_text}\"; expected \"wheelset\" or \"body\""),
        })?;
        let mut b = BodySeries::new(
            attrs::read_str(path, &bg, &what, "name")?,
            kind,
            attrs::read_f64(path, &bg, &what, "mass_kg")?,
        );
        b.assembly_x_m = attrs::read_f64(path, &bg, &what, "assembly_x_m")?;
        b.assembly_height_m = attrs::read_f64(path, &bg, &what, "assembly_height_m")?;
        // No body column was added later yet: every one must be there.
        let missing = read_columns(path, &bg, &BODY_COLUMNS, &mut b, n)?;
        debug_assert!(missing.is_empty());
        bodies.push((index, b));
    }
    bodies.sort_by_key(|(i, _)| *i);
    Ok((bodies.into_iter().map(|(_, b)| b).collect(), car_body))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn group_names_are_valid_and_unique() {
        let b = |n: &str| BodySeries::new(n, BodyKind::Free, 1.0);
        let names = body_group_names(&[b("car body"), b("a/b"), b("a_b"), b(".")]);
        assert_eq!(names, ["car body", "a_b", "a_b_2", "_"]);
    }
}
