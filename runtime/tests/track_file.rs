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
