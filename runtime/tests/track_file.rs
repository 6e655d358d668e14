//! Track table files read back as one track (issue 12): a file whose
//! `columns` attribute was permuted or relabelled is refused by the reader,
//! not read with wrong positions.

use std::path::PathBuf;

use hdf5::types::VarLenUnicode;
use runtime::geometry::track::{Provenance, straight_track};
use runtime::io::schema::{read_track, write_track_file};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("railsim-trackfile-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Rewrites the `columns` attribute of `dataset` with `a` and `b` swapped.
fn swap_columns(path: &std::path::Path, dataset: &str, a: &str, b: &str) {
    let file = hdf5::File::open_rw(path).unwrap();
    let ds = file.dataset(dataset).unwrap();
    let names: Vec<VarLenUnicode> = ds.attr("columns").unwrap().read_raw().unwrap();
    let swapped: Vec<VarLenUnicode> = names
        .iter()
        .map(|n| {
            let s = n.as_str();
            let t = if s == a {
                b
            } else if s == b {
                a
            } else {
                s
            };
            t.parse().unwrap()
        })
        .collect();
    ds.delete_attr("columns").unwrap();
    ds.new_attr::<VarLenUnicode>()
        .shape(swapped.len())
        .create("columns")
        .unwrap()
        .write(&swapped)
        .unwrap();
}

#[test]
fn permuted_columns_are_refused_not_read_wrongly() {
    let d = scratch("permuted");
    let track = straight_track(50.0, 0.1, 1.435, 1.507, 0.025);
    let provenance = Provenance {
        command_line: "test".into(),
        inputs: vec![],
    };
    let good = d.join("good.h5");
    write_track_file(&good, &track, &provenance).unwrap();
    read_track(&good).expect("the written file reads back");
    for (dataset, a, b) in [
        ("left_rail/database", "y", "z"),
        ("right_rail/database", "ny", "nz"),
        ("centerline/database", "nx", "ny"),
    ] {
        let bad = d.join(format!("{}-{a}-{b}.h5", dataset.replace('/', "_")));
        std::fs::copy(&good, &bad).unwrap();
        swap_columns(&bad, dataset, a, b);
        let Err(e) = read_track(&bad) else {
            panic!("{dataset} {a}<->{b}: a permuted table must be refused")
        };
        let msg = format!("{e}");
        assert!(
            msg.contains("do not describe one track") || msg.contains("not orthonormal"),
            "{dataset} {a}<->{b}: {msg}"
        );
    }
    std::fs::remove_dir_all(&d).unwrap();
}

/// The cant's spline scheme is recorded (`cant_scheme`); a file written
/// before it was (no attribute) reads it as the centreline's `scheme`, the
/// one its cant was splined with then.
#[test]
fn cant_scheme_is_recorded_and_older_files_read_it_as_scheme() {
    let dir = scratch("cant_scheme");
    let path = dir.join("t.h5");
    let mut tables = straight_track(20.0, 0.5, 1.435, 1.507, 0.0);
    tables.meta.scheme = "akima".into();
    tables.meta.cant_scheme = "pchip".into();
    write_track_file(&path, &tables, &Provenance::default()).unwrap();
    assert_eq!(read_track(&path).unwrap().meta.cant_scheme, "pchip");
    let f = hdf5::File::open_rw(&path).unwrap();
    f.delete_attr("cant_scheme").unwrap();
    drop(f);
    let meta = read_track(&path).unwrap().meta;
    assert_eq!(meta.cant_scheme, "akima");
    assert_eq!(meta.scheme, "akima");
}

/// The plan elements of a design track (`/design`) round-trip through the
/// file, infinite radii included; a file without them (a control-point
/// track, an older file) reads as none; a damaged group is refused.
#[test]
fn design_elements_round_trip_and_files_without_them_read_as_none() {
    use runtime::geometry::track::{DesignElement, PlanElementKind};
    let dir = scratch("design_elements");
    let plain = dir.join("plain.h5");
    let mut tables = straight_track(20.0, 0.5, 1.435, 1.507, 0.0);
    write_track_file(&plain, &tables, &Provenance::default()).unwrap();
    assert!(read_track(&plain).unwrap().design_elements.is_empty());
    assert!(!hdf5::File::open(&plain).unwrap().link_exists("design"));

    let cant = (0.12_f64 / 1.5).asin();
    let e = |kind, a: f64, b: f64, r: [f64; 2], c: [f64; 2], shape: &str| DesignElement {
        kind,
        s_start_m: a,
        s_end_m: b,
        radius_start_m: r[0],
        radius_end_m: r[1],
        cant_start_rad: c[0],
        cant_end_rad: c[1],
        shape: shape.into(),
        cant_ramp: "linear".into(),
    };
    let inf = f64::INFINITY;
    tables.design_elements = vec![
        e(
            PlanElementKind::Straight,
            0.0,
            5.0,
            [inf, inf],
            [0.0, 0.0],
            "",
        ),
        e(
            PlanElementKind::Transition,
            5.0,
            12.5,
            [inf, -600.0],
            [0.0, cant],
            "clothoid",
        ),
        e(
            PlanElementKind::Arc,
            12.5,
            20.0,
            [-600.0, -600.0],
            [cant, cant],
            "",
        ),
    ];
    let path = dir.join("design.h5");
    write_track_file(&path, &tables, &Provenance::default()).unwrap();
    let back = read_track(&path).unwrap();
    assert_eq!(back.design_elements, tables.design_elements);
    // Every dataset carries its unit and description.
    {
        let f = hdf5::File::open(&path).unwrap();
        let ds = f.dataset("design/radius_start_m").unwrap();
        let units: VarLenUnicode = ds.attr("units").unwrap().read_scalar().unwrap();
        assert_eq!(units.as_str(), "m");
        assert!(ds.attr("description").is_ok());
    }

    // A missing dataset is named.
    let f = hdf5::File::open_rw(&path).unwrap();
    f.unlink("design/cant_end_rad").unwrap();
    drop(f);
    let msg = read_track(&path).unwrap_err().to_string();
    assert!(msg.contains("/design/cant_end_rad"), "{msg}");
    std::fs::remove_dir_all(&dir).unwrap();
}
