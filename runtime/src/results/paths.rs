//! The path of every series in the results file (`time_s`,
//! `wheelset_0/lateral_m`, `wheelset_0/left/y_n`,
//! `wheelset_0/left/flange/normal_n`, `bodies/<name>/lateral_m`), with its
//! unit and meaning: the one naming shared by the file's writer
//! ([`crate::io::schema`]) and by readers that hold a run in memory (the
//! Python package's `Results["wheelset_0/lateral_m"]`). The layout is
//! docs/reference/04-table-files.md, "Results file".

use super::{
    BODY_COLUMNS, BodySeries, Column, Dataset, RunResults, TIME_S, Values, WHEEL_COLUMNS,
    WHEEL_GROUPS, WHEELSET_COLUMNS, ZONE_COLUMNS, ZONE_GROUPS, wheelset_group,
};

/// Name of the group holding the bodies.
pub const BODIES_GROUP: &str = "bodies";

/// The values of one series, borrowed from the results.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SeriesValues<'a> {
    F64(&'a [f64]),
    /// 0/1 flags, or the bits of a fallback code.
    Flags(&'a [u8]),
}

/// One series with its path in the results file.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedSeries<'a> {
    /// Path in the file, '/'-separated, without a leading '/'.
    pub path: String,
    pub dataset: Dataset,
    pub values: SeriesValues<'a>,
}

/// Group name of body `k`: its name with '/' (not allowed in an HDF5 link
/// name) replaced by '_', "." and ".." spelled "_"; `_<k>` appended when
/// that repeats the group name of an earlier body.
pub fn body_group_names(bodies: &[BodySeries]) -> Vec<String> {
    let mut names: Vec<String> = Vec::with_capacity(bodies.len());
    for (k, b) in bodies.iter().enumerate() {
        let mut n = b.name.replace('/', "_");
        if n.is_empty() || n == "." || n == ".." {
            n = "_".into();
        }
        if names.contains(&n) {
            n = format!("{n}_{k}");
        }
        names.push(n);
    }
    names
}

fn push_columns<'a, S, V>(
    out: &mut Vec<NamedSeries<'a>>,
    group: &str,
    columns: &[Column<S, V>],
    s: &'a S,
) {
    for c in columns {
        let values = match &c.values {
            Values::F64(a) => SeriesValues::F64((a.series)(s)),
            Values::Flags { access, .. } => SeriesValues::Flags((access.series)(s)),
        };
        out.push(NamedSeries {
            path: format!("{group}/{}", c.name()),
            dataset: c.dataset,
            values,
        });
    }
}

impl RunResults {
    /// Every series, in file order: `time_s`, then each wheelset's, its
    /// wheels' and their zones', then each body's.
    pub fn named_series(&self) -> Vec<NamedSeries<'_>> {
        let mut out = vec![NamedSeries {
            path: TIME_S.name.to_string(),
            dataset: TIME_S,
            values: SeriesValues::F64(&self.time_s),
        }];
        for (i, ws) in self.wheelsets.iter().enumerate() {
            let g = wheelset_group(i);
            push_columns(&mut out, &g, &WHEELSET_COLUMNS, ws);
            for (wheel, wg) in ws.wheels.iter().zip(WHEEL_GROUPS) {
                let g = format!("{g}/{wg}");
                push_columns(&mut out, &g, &WHEEL_COLUMNS, wheel);
                for (zone, zg) in wheel.zones.iter().zip(ZONE_GROUPS) {
                    push_columns(&mut out, &format!("{g}/{zg}"), &ZONE_COLUMNS, zone);
                }
            }
        }
        for (b, name) in self.bodies.iter().zip(body_group_names(&self.bodies)) {
            push_columns(
                &mut out,
                &format!("{BODIES_GROUP}/{name}"),
                &BODY_COLUMNS,
                b,
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::{BodyKind, WheelsetSample};

    #[test]
    fn paths_follow_the_file_layout_and_every_series_has_one_value_per_sample() {
        let mut r = RunResults::with_wheelsets(["front", "rear"]);
        let s = WheelsetSample {
            lateral_m: 0.001,
            ..Default::default()
        };
        r.push(0.0, &[s, s]).unwrap();
        r.bodies = vec![
            BodySeries::new("bogie/frame", BodyKind::Free, 2000.0),
            BodySeries::new("bogie/frame", BodyKind::Free, 2000.0),
        ];
        for b in &mut r.bodies {
            b.push(&Default::default());
        }
        let all = r.named_series();
        let paths: Vec<&str> = all.iter().map(|n| n.path.as_str()).collect();
        assert_eq!(paths[0], "time_s");
        for p in [
            "wheelset_0/lateral_m",
            "wheelset_1/yaw_rad",
            "wheelset_0/left/y_n",
            "wheelset_1/right/flange/normal_n",
            "wheelset_0/left/tread/in_contact",
            "bodies/bogie_frame/lateral_m",
            "bodies/bogie_frame_1/yaw_rad",
        ] {
            assert!(paths.contains(&p), "{p} missing from {paths:?}");
        }
        let lateral = all
            .iter()
            .find(|n| n.path == "wheelset_0/lateral_m")
            .unwrap();
        assert_eq!(lateral.values, SeriesValues::F64(&[0.001]));
        assert_eq!(lateral.dataset.units, "m");
        for n in &all {
            let len = match n.values {
                SeriesValues::F64(v) => v.len(),
                SeriesValues::Flags(v) => v.len(),
            };
            assert_eq!(len, 1, "{}", n.path);
        }
        let mut unique = paths.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), paths.len(), "a path is repeated");
    }
}
