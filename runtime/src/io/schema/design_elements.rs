//! The group `/design` of a track table file: the plan elements of the
//! design file the track was built from, one entry per element in 1-D
//! datasets with `units` and `description` attributes
//! (docs/reference/04-table-files.md §4.1). Files without the group (tracks
//! from control points, files written before it existed) read as no
//! elements.

use std::path::Path;

use hdf5::types::VarLenUnicode;

use super::columns::to_vlu;
use super::{SchemaError, attrs};
use crate::geometry::track::{DesignElement, PlanElementKind, check_design_elements};

/// Name of the group.
pub const GROUP: &str = "design";

/// The numeric datasets: name, unit, description, value.
type Pick = fn(&DesignElement) -> f64;
const NUMBERS: [(&str, &str, &str, Pick); 6] = [
    (
        "s_start_m",
        "m",
        "track distance s at the element's start",
        |e| e.s_start_m,
    ),
    (
        "s_end_m",
        "m",
        "track distance s at the element's end",
        |e| e.s_end_m,
    ),
    (
        "radius_start_m",
        "m",
        "signed plan radius at the start (+ turning left, inf on a straight)",
        |e| e.radius_start_m,
    ),
    (
        "radius_end_m",
        "m",
        "signed plan radius at the end (+ turning left, inf on a straight)",
        |e| e.radius_end_m,
    ),
    (
        "cant_start_rad",
        "rad",
        "cant at the start (+ left rail higher)",
        |e| e.cant_start_rad,
    ),
    (
        "cant_end_rad",
        "rad",
        "cant at the end (+ left rail higher)",
        |e| e.cant_end_rad,
    ),
];

/// The text datasets: name, description, value.
type PickText = fn(&DesignElement) -> &str;
const TEXTS: [(&str, &str, PickText); 3] = [
    ("kind", "straight, transition or arc", |e| e.kind.name()),
    (
        "shape",
        "a transition's curvature shape: clothoid, cubic-parabola, bloss or cosine; empty for straights and arcs",
        |e| e.shape.as_str(),
    ),
    (
        "cant_ramp",
        "shape of the cant ramp over the element: linear, bloss or cosine",
        |e| e.cant_ramp.as_str(),
    ),
];

fn hdf(path: &Path, action: String) -> impl FnOnce(hdf5::Error) -> SchemaError + '_ {
    move |source| SchemaError::Hdf5 {
        path: path.to_path_buf(),
        action,
        source,
    }
}

/// Write `/design` (nothing when there are no elements).
pub(super) fn write(
    path: &Path,
    file: &hdf5::File,
    elements: &[DesignElement],
) -> Result<(), SchemaError> {
    if elements.is_empty() {
        return Ok(());
    }
    let g = file
        .create_group(GROUP)
        .map_err(hdf(path, "creating /design".into()))?;
    attrs::write_str(
        path,
        &g,
        "description",
        "plan elements of the design file the track was built from, in order (docs/reference/04-table-files.md §4.1)",
    )?;
    for (name, units, description, pick) in NUMBERS {
        let v: Vec<f64> = elements.iter().map(pick).collect();
        let ds = g
            .new_dataset_builder()
            .with_data(v.as_slice())
            .create(name)
            .map_err(hdf(path, format!("writing /design/{name}")))?;
        attrs::write_str(path, &ds, "units", units)?;
        attrs::write_str(path, &ds, "description", description)?;
    }
    for (name, description, pick) in TEXTS {
        let v: Vec<VarLenUnicode> = elements.iter().map(|e| to_vlu(pick(e))).collect();
        let ds = g
            .new_dataset_builder()
            .with_data(v.as_slice())
            .create(name)
            .map_err(hdf(path, format!("writing /design/{name}")))?;
        attrs::write_str(path, &ds, "units", "")?;
        attrs::write_str(path, &ds, "description", description)?;
    }
    Ok(())
}

/// Read `/design`: no elements when the file has no such group.
pub(super) fn read(path: &Path, file: &hdf5::File) -> Result<Vec<DesignElement>, SchemaError> {
    if !file.link_exists(GROUP) {
        return Ok(Vec::new());
    }
    let g = file
        .group(GROUP)
        .map_err(hdf(path, "opening /design".into()))?;
    let invalid = |rule: String| SchemaError::Invalid {
        path: path.to_path_buf(),
        object: "/design".into(),
        rule,
    };
    let mut numbers = Vec::with_capacity(NUMBERS.len());
    for (name, ..) in NUMBERS {
        let ds = g.dataset(name).map_err(|_| SchemaError::Missing {
            path: path.to_path_buf(),
            what: format!("dataset /design/{name}"),
        })?;
        numbers.push(
            ds.read_raw::<f64>()
                .map_err(hdf(path, format!("reading /design/{name}")))?,
        );
    }
    let mut texts = Vec::with_capacity(TEXTS.len());
    for (name, ..) in TEXTS {
        let ds = g.dataset(name).map_err(|_| SchemaError::Missing {
            path: path.to_path_buf(),
            what: format!("dataset /design/{name}"),
        })?;
        let v: Vec<String> = ds
            .read_raw::<VarLenUnicode>()
            .map_err(hdf(path, format!("reading /design/{name}")))?
            .iter()
            .map(|s| s.as_str().to_string())
            .collect();
        texts.push(v);
    }
    let n = numbers[0].len();
    if let Some((name, len)) = NUMBERS
        .iter()
        .map(|t| t.0)
        .zip(numbers.iter().map(Vec::len))
        .chain(TEXTS.iter().map(|t| t.0).zip(texts.iter().map(Vec::len)))
        .find(|&(_, len)| len != n)
    {
        return Err(invalid(format!(
            "{name} has {len} entries, s_start_m has {n}: one entry per element in every dataset"
        )));
    }
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let kind = PlanElementKind::from_name(&texts[0][i]).ok_or_else(|| {
            invalid(format!(
                "kind[{i}] is '{}', not straight, transition or arc",
                texts[0][i]
            ))
        })?;
        out.push(DesignElement {
            kind,
            s_start_m: numbers[0][i],
            s_end_m: numbers[1][i],
            radius_start_m: numbers[2][i],
            radius_end_m: numbers[3][i],
            cant_start_rad: numbers[4][i],
            cant_end_rad: numbers[5][i],
            shape: texts[1][i].clone(),
            cant_ramp: texts[2][i].clone(),
        });
    }
    check_design_elements(&out).map_err(invalid)?;
    Ok(out)
}
