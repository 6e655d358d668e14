//! Bad input (docs/reference/02-inputs.md §2, issue 2 item 9): every case gets a clear error
//! naming the file, the line and the rule, a non-zero exit, and no output
//! file (nor a temporary) left behind.

mod common;

use std::path::{Path, PathBuf};

use common::*;

const GOOD_CENTERLINE: &str = "x,y,z\n0,0,0\n1,0,0\n2,0,0\n3,0,0\n4,0,0\n5,0,0\n";

struct Case {
    name: &'static str,
    centerline: &'static str,
    cant: Option<&'static str>,
    irregularities: Option<&'static str>,
    extra: &'static [&'static str],
    /// Substrings the error must contain (besides the file name).
    expect: &'static [&'static str],
    /// File the message must name.
    names: &'static str,
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn check(case: &Case) {
    let dir = scratch(&format!("bad_{}", case.name));
    let mut cmd = track_preproc();
    cmd.arg("build")
        .arg("--centerline")
        .arg(write(&dir, "centerline.csv", case.centerline));
    if let Some(t) = case.cant {
        cmd.arg("--cant").arg(write(&dir, "cant.csv", t));
    }
    if let Some(t) = case.irregularities {
        cmd.arg("--irregularities")
            .arg(write(&dir, "irregularities.csv", t));
    }
    let out = dir.join("out.h5");
    cmd.args(case.extra).arg("-o").arg(&out);
    let before = files_in(&dir);
    let o = run(&mut cmd);
    let err = stderr(&o);
    assert!(
        !o.status.success(),
        "{}: expected failure, got success",
        case.name
    );
    assert!(
        err.contains(case.names),
        "{}: error does not name {}:\n{err}",
        case.name,
        case.names
    );
    for e in case.expect {
        assert!(err.contains(e), "{}: error lacks '{e}':\n{err}", case.name);
    }
    assert!(!out.exists(), "{}: output file left behind", case.name);
    assert_eq!(
        files_in(&dir),
        before,
        "{}: stray files left behind",
        case.name
    );
}

#[test]
fn every_bad_input_case_is_reported_cleanly() {
    let cases = [
        Case {
            name: "non_finite",
            centerline: "x,y,z\n0,0,0\n1,0,0\n2,nan,0\n3,0,0\n",
            cant: None,
            irregularities: None,
            extra: &[],
            expect: &["line 4", "non-finite"],
            names: "centerline.csv",
        },
        Case {
            name: "not_a_number",
            centerline: "x,y,z\n0,0,0\n1,0,0\n2,0.0.1,0\n3,0,0\n",
            cant: None,
            irregularities: None,
            extra: &[],
            expect: &["line 4", "not a number"],
            names: "centerline.csv",
        },
        Case {
            name: "too_few_points",
            centerline: "x,y,z\n0,0,0\n1,0,0\n2,0,0\n",
            cant: None,
            irregularities: None,
            extra: &[],
            expect: &["at least 4"],
            names: "centerline.csv",
        },
        Case {
            name: "repeated_point",
            centerline: "x,y,z\n0,0,0\n1,0,0\n1,0,0\n2,0,0\n3,0,0\n",
            cant: None,
            irregularities: None,
            extra: &[],
            expect: &["line 4", "repeats"],
            names: "centerline.csv",
        },
        Case {
            name: "doubles_back",
            centerline: "x,y,z\n0,0,0\n10,0,0\n10.5,0.2,0\n10,0.4,0\n0,0.4,0\n",
            cant: None,
            irregularities: None,
            extra: &[],
            expect: &["doubles back", "line"],
            names: "centerline.csv",
        },
        Case {
            name: "missing_column",
            centerline: "x,y\n0,0\n1,0\n2,0\n3,0\n",
            cant: None,
            irregularities: None,
            extra: &[],
            expect: &["missing column 'z'"],
            names: "centerline.csv",
        },
        Case {
            name: "wrong_field_count",
            centerline: "x,y,z\n0,0,0\n1,0\n2,0,0\n3,0,0\n",
            cant: None,
            irregularities: None,
            extra: &[],
            expect: &["line 3", "expected 3 values"],
            names: "centerline.csv",
        },
        Case {
            name: "empty_file",
            centerline: "# nothing here\n",
            cant: None,
            irregularities: None,
            extra: &[],
            expect: &["empty"],
            names: "centerline.csv",
        },
        Case {
            name: "cant_too_large",
            centerline: "x,y,z,cant\n0,0,0,0\n1,0,0,0.1\n2,0,0,0.31\n3,0,0,0\n",
            cant: None,
            irregularities: None,
            extra: &[],
            expect: &["line 4, column 4", "0.1337 rad", "check the unit"],
            names: "centerline.csv",
        },
        Case {
            name: "cant_table_too_large_mm",
            centerline: GOOD_CENTERLINE,
            cant: Some("s,cant_mm\n0,0\n2,100\n4,500\n5,0\n"),
            irregularities: None,
            extra: &[],
            expect: &[
                "line 4, column 2",
                "cant_mm = 500 mm",
                "0.1337 rad",
                "check the unit",
            ],
            names: "cant.csv",
        },
        Case {
            name: "cant_table_short",
            centerline: GOOD_CENTERLINE,
            cant: Some("s,cant\n0,0\n1,0\n2,0\n3,0\n"),
            irregularities: None,
            extra: &[],
            expect: &["covers", "0 to 5.000 m"],
            names: "cant.csv",
        },
        Case {
            name: "irregularities_not_covering",
            centerline: GOOD_CENTERLINE,
            cant: None,
            irregularities: Some(
                "s,align_left,align_right,level_left,level_right\n0,0,0,0,0\n1,0,0,0,0\n2,0,0,0,0\n3,0,0,0,0\n",
            ),
            extra: &[],
            expect: &["covers", "track runs from 0 to 5.000 m"],
            names: "irregularities.csv",
        },
        Case {
            name: "irregularities_not_increasing",
            centerline: GOOD_CENTERLINE,
            cant: None,
            irregularities: Some(
                "s,align_left,align_right,level_left,level_right\n0,0,0,0,0\n2,0,0,0,0\n2,0,0,0,0\n5,0,0,0,0\n",
            ),
            extra: &[],
            expect: &["line 4", "strictly increase"],
            names: "irregularities.csv",
        },
        Case {
            name: "irregularities_mixed_forms",
            centerline: GOOD_CENTERLINE,
            cant: None,
            irregularities: Some("s,align_left,gauge\n0,0,0\n"),
            extra: &[],
            expect: &["mixes"],
            names: "irregularities.csv",
        },
        Case {
            name: "unknown_column",
            centerline: GOOD_CENTERLINE,
            cant: None,
            irregularities: Some("s,align_left,align_right,level_left,level_rigth\n0,0,0,0,0\n"),
            extra: &[],
            expect: &["unknown column 'level_rigth'"],
            names: "irregularities.csv",
        },
        Case {
            name: "bad_step",
            centerline: GOOD_CENTERLINE,
            cant: None,
            irregularities: None,
            extra: &["--step", "0"],
            expect: &["--step"],
            names: "--step",
        },
        Case {
            name: "bad_inclination",
            centerline: GOOD_CENTERLINE,
            cant: None,
            irregularities: None,
            extra: &["--rail-inclination", "steep"],
            expect: &["1:40"],
            names: "--rail-inclination",
        },
    ];
    for c in &cases {
        check(c);
    }
}

#[test]
fn missing_input_file_is_named() {
    let dir = scratch("bad_missing_file");
    let out = dir.join("out.h5");
    let o = run(track_preproc()
        .args(["build", "--centerline"])
        .arg(dir.join("nope.csv"))
        .arg("-o")
        .arg(&out));
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("nope.csv") && err.contains("cannot read"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn unwritable_output_is_reported_and_leaves_nothing() {
    let dir = scratch("bad_output_dir");
    let centerline = write(&dir, "centerline.csv", GOOD_CENTERLINE);
    let out = dir.join("no_such_dir").join("out.h5");
    let o = run(track_preproc()
        .args(["build", "--centerline"])
        .arg(&centerline)
        .arg("-o")
        .arg(&out));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("out.h5"), "{}", stderr(&o));
    assert_eq!(files_in(&dir), vec!["centerline.csv".to_string()]);
}

/// The run-time reader refuses a table of another schema version, saying
/// which version it found, and a truncated file, naming it.
#[test]
fn reader_rejects_other_versions_and_truncated_files() {
    let dir = scratch("bad_tables");
    let centerline = write(&dir, "centerline.csv", GOOD_CENTERLINE);
    let good = dir.join("good.h5");
    let o = run(track_preproc()
        .args(["build", "--centerline"])
        .arg(&centerline)
        .arg("-o")
        .arg(&good));
    assert!(o.status.success(), "{}", stderr(&o));

    // Another schema version.
    let other = dir.join("other_version.h5");
    std::fs::copy(&good, &other).unwrap();
    {
        // Opened with the strong close degree and closed explicitly, so
        // that H5Fclose closes every object of the file and drops its lock
        // before `sim probe` opens it: twice, on CI, the probe found the
        // file still locked (errno 11), after the handle's drop and then
        // after a close with the default (weak) degree, which leaves the
        // file open while any of its objects is.
        let f = hdf5::File::with_options()
            .with_fapl(|p| p.fclose_degree(hdf5::plist::file_access::FileCloseDegree::Strong))
            .open_rw(&other)
            .unwrap();
        f.attr("schema_version")
            .unwrap()
            .write_scalar(&99u32)
            .unwrap();
        f.close().unwrap();
    }
    let o = run(sim().arg("probe").arg(&other).args(["--s", "1"]));
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("other_version.h5")
            && err.contains("schema version 99")
            && err.contains("reads version 1"),
        "{err}"
    );

    // Truncated.
    let bytes = std::fs::read(&good).unwrap();
    let truncated = dir.join("truncated.h5");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    let o = run(sim().arg("probe").arg(&truncated).args(["--s", "1"]));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("truncated.h5"), "{}", stderr(&o));

    // Not HDF5 at all.
    let o = run(sim().arg("probe").arg(&centerline).args(["--s", "1"]));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("cannot open"), "{}", stderr(&o));

    // Outside the table.
    let o = run(sim().arg("probe").arg(&good).args(["--s", "7.5"]));
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("outside the centerline table"),
        "{}",
        stderr(&o)
    );
}
