//! Trust (issue 12) for the track inputs of `track-preproc build`: a file
//! as editors save it reads (byte-order mark), one that cannot be read is
//! refused where the fault is (line, column), implausible values are
//! refused as unit errors naming their bound, and what is built is checked
//! as well as what is read (table step against the irregularities, rail
//! lengths, the cant after the spline). Bounds: docs/reference/02-inputs.md §2.5.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Output;

use super::common::*;

/// `track-preproc build --centerline C [EXTRA…] -o DIR/out.h5`.
fn build(dir: &Path, centerline: &Path, extra: &[&str]) -> Output {
    run(track_preproc()
        .args(["build", "--centerline"])
        .arg(centerline)
        .args(extra)
        .arg("-o")
        .arg(dir.join("out.h5")))
}

/// Writes `bytes` to `dir/name`.
fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// A 300 m straight every 1 m, with a `cant_mm`/`cant` column given by
/// `cant(i)` for point i when `column` is given.
fn straight(column: Option<(&str, &dyn Fn(usize) -> f64)>) -> String {
    let mut s = match column {
        Some((name, _)) => format!("x,y,z,{name}\n"),
        None => "x,y,z\n".to_string(),
    };
    for i in 0..=300 {
        match column {
            // Values to 1e-6, as a file would hold them.
            Some((_, f)) => s += &format!("{i},0,0,{}\n", (f(i) * 1e6).round() / 1e6),
            None => s += &format!("{i},0,0\n"),
        }
    }
    s
}

/// A cant ramp 0 → `top` over 50 m (points 50…100), held to 200, down to 0
/// by 250: smooth enough that no spline overshoots.
fn ramp(top: f64) -> impl Fn(usize) -> f64 {
    move |i| {
        let i = i as f64;
        top * ((i - 50.0) / 50.0).clamp(0.0, 1.0) * ((250.0 - i) / 50.0).clamp(0.0, 1.0)
    }
}

fn refused(o: &Output, what: &str, expect: &[&str]) {
    let err = stderr(o);
    assert!(!o.status.success(), "{what}: built\n{}", stdout(o));
    assert!(!err.contains("panicked"), "{what}: {err}");
    for e in expect {
        assert!(err.contains(e), "{what}: no '{e}' in\n{err}");
    }
}

fn built(o: &Output, what: &str) -> String {
    assert!(o.status.success(), "{what}: {}", stderr(o));
    stdout(o)
}

/// A UTF-8 byte-order mark before a first comment line (as Windows editors
/// save) is ignored: the file builds the same track as without it.
#[test]
fn trust_track_byte_order_mark() {
    let dir = scratch("trust_track_bom");
    let text = format!("# saved by a Windows editor\n{}", straight(None));
    let plain = built(&build(&dir, &write(&dir, "plain.csv", &text), &[]), "plain");
    let mut bytes = "\u{feff}".as_bytes().to_vec();
    bytes.extend(text.as_bytes());
    let bom = built(&build(&dir, &write(&dir, "bom.csv", bytes), &[]), "bom");
    let length = |s: &str| s.lines().nth(1).unwrap_or_default().to_string();
    assert_eq!(length(&bom), length(&plain));
    assert!(length(&bom).contains("300.000 m"), "{bom}");
}

/// A byte that is not UTF-8 (a Latin-1 degree sign) is refused at its line
/// and column, in each of the three track CSV files.
#[test]
fn trust_track_not_utf8_names_line_and_column() {
    let dir = scratch("trust_track_latin1");
    let mut text = straight(None).into_bytes();
    // "x,y,z\n0,0,0\n1,0,0\n2,0,0\n": line 4 is "2,0,0"; append " \xb0".
    let at = text
        .iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .nth(3)
        .unwrap()
        .0;
    text.splice(at..at, *b" \xb0");
    let c = write(&dir, "latin1.csv", &text);
    refused(
        &build(&dir, &c, &[]),
        "centreline",
        &["latin1.csv, line 4, column 7", "byte 0xb0 is not UTF-8"],
    );
    let good = write(&dir, "c.csv", straight(None));
    let cant = write(
        &dir,
        "cant.csv",
        b"s,cant_mm\n0,0\n100,0\n200,0\n# \xe9t\xe9\n300,0\n",
    );
    refused(
        &build(&dir, &good, &["--cant", cant.to_str().unwrap()]),
        "cant",
        &["cant.csv, line 5, column 3", "not UTF-8"],
    );
    let irr = write(
        &dir,
        "irr.csv",
        b"s,align_left,align_right,level_left,level_right\n\xff\n",
    );
    refused(
        &build(&dir, &good, &["--irregularities", irr.to_str().unwrap()]),
        "irregularities",
        &["irr.csv, line 2, column 1", "not UTF-8"],
    );
}

/// 1e308 (finite, but it overflows every length computed from it) is
/// refused at its line and column as a unit error, in a coordinate and in
/// a table's s; it used to be reported as "point 7" of a spline.
#[test]
fn trust_track_1e308_names_line_and_column() {
    let dir = scratch("trust_track_1e308");
    let text = straight(None).replace("\n8,0,0\n", "\n8,1e308,0\n");
    refused(
        &build(&dir, &write(&dir, "huge.csv", text), &[]),
        "coordinate",
        &[
            "huge.csv, line 10, column 2",
            "y = 1e308 m is beyond ±1e8 m",
            "check the unit",
        ],
    );
    let good = write(&dir, "c.csv", straight(None));
    let cant = write(&dir, "cant.csv", "s,cant\n0,0\n100,0\n1e308,0\n400,0\n");
    refused(
        &build(&dir, &good, &["--cant", cant.to_str().unwrap()]),
        "cant s",
        &[
            "cant.csv, line 4, column 1",
            "s = 1e308 m",
            "check the unit",
        ],
    );
}

/// Metres in a `cant_mm` column (0.1 for 100 mm) read as 0.1 mm of cant:
/// refused as a unit error at the largest value.
#[test]
fn trust_track_metres_in_cant_mm() {
    let dir = scratch("trust_track_cant_m_in_mm");
    let c = write(&dir, "c.csv", straight(Some(("cant_mm", &ramp(0.1)))));
    refused(
        &build(&dir, &c, &[]),
        "cant_mm in metres",
        &[
            "c.csv, line 102, column 4",
            "the largest |cant| of the column is 0.1 mm",
            "check the unit",
        ],
    );
    let c = write(&dir, "mm.csv", straight(Some(("cant_mm", &ramp(100.0)))));
    let out = built(&build(&dir, &c, &[]), "cant_mm in mm");
    // 100 mm, and the cubic's small overshoot at the ramps' kinks.
    assert!(out.contains("rad (100."), "{out}");
}

/// A cant of 0.15 m written in the `cant` (rad) column reads as 0.15 rad,
/// 224 mm on the 1.5 m cant base: beyond the 200 mm bound (it passed the
/// old ±0.3 rad); refused naming the value in mm and the bound.
#[test]
fn trust_track_metres_in_cant_rad() {
    let dir = scratch("trust_track_cant_m_in_rad");
    let c = write(&dir, "c.csv", straight(Some(("cant", &ramp(0.15)))));
    refused(
        &build(&dir, &c, &[]),
        "cant in metres",
        // The ramp reaches 0.135 rad (0.9 × 0.15) at point 95, line 97:
        // 1.5 m × sin 0.135 = 201.9 mm.
        &[
            "c.csv, line 97, column 4",
            "cant = 0.135 rad (201.9 mm on the cant base 1.5 m)",
            "±0.1337 rad",
            "check the unit",
        ],
    );
}

/// Irregularities in metres under `_mm` headers (0.004 for 4 mm) are
/// refused as a unit error; millimetres without `_mm` (beyond ±50 mm) too.
#[test]
fn trust_track_irregularity_units() {
    let dir = scratch("trust_track_irr_units");
    let c = write(&dir, "c.csv", straight(None));
    let table = |scale: f64, suffix: &str| {
        let mut t = format!(
            "s,align_left{suffix},align_right{suffix},level_left{suffix},level_right{suffix}\n"
        );
        for i in 0..=300 {
            let v = scale * (2.0 * PI * f64::from(i) / 20.0).sin();
            t += &format!("{i},{v:.6},{v:.6},0,0\n");
        }
        t
    };
    let irr = write(&dir, "m_in_mm.csv", table(0.004, "_mm"));
    refused(
        &build(&dir, &c, &["--irregularities", irr.to_str().unwrap()]),
        "metres under _mm",
        &[
            "m_in_mm.csv, line ",
            "column 2: align_left_mm: the largest |value| of the column is 0.004 mm",
            "check the unit",
        ],
    );
    let irr = write(&dir, "mm_in_m.csv", table(4.0, ""));
    refused(
        &build(&dir, &c, &["--irregularities", irr.to_str().unwrap()]),
        "millimetres without _mm",
        // The largest value, 4 at s = 5 m (line 7).
        &[
            "mm_in_m.csv, line 7, column 2",
            "align_left = 4 m",
            "check the unit",
        ],
    );
    let irr = write(&dir, "ok.csv", table(4.0, "_mm"));
    let out = built(
        &build(&dir, &c, &["--irregularities", irr.to_str().unwrap()]),
        "4 mm",
    );
    assert!(out.contains("max irregularity  4.00 mm"), "{out}");
}

/// A 600 m curve whose coordinates were written in km has a radius of
/// 0.6 "m": refused as a unit error (it used to build a 0.3 m track).
#[test]
fn trust_track_tiny_radius() {
    let dir = scratch("trust_track_km");
    let mut text = String::from("x,y,z\n");
    for i in 0..=60 {
        let phi = 5.0 * f64::from(i) / 600.0;
        text += &format!("{:.9},{:.9},0\n", 0.6 * phi.sin(), 0.6 * (1.0 - phi.cos()));
    }
    refused(
        &build(&dir, &write(&dir, "km.csv", text), &[]),
        "km as m",
        &[
            "km.csv, line ",
            "radius of curvature of 0.600 m",
            "below the 10 m",
            "check the unit",
        ],
    );
}

/// An irregularity of wavelength 0.05 m sampled every 0.01 m is zero at
/// every 0.1 m table row ("max irregularity 0.00 mm") while the rails
/// followed it (327 m on a 300 m track): refused (sampling theorem),
/// naming the line, the column and the step; a 0.01 m step holds it.
#[test]
fn trust_track_irregularity_below_twice_the_step() {
    let dir = scratch("trust_track_nyquist");
    let c = write(&dir, "c.csv", straight(None));
    let mut t = String::from("s,align_left_mm,align_right_mm,level_left_mm,level_right_mm\n");
    for k in 0..=30_000 {
        let s = f64::from(k) * 0.01;
        let v = 2.0 * (2.0 * PI * s / 0.05).sin();
        t += &format!("{s:.2},{v:.6},{v:.6},0,0\n");
    }
    let irr = write(&dir, "fine.csv", t);
    refused(
        &build(&dir, &c, &["--irregularities", irr.to_str().unwrap()]),
        "0.05 m wavelength",
        &[
            "fine.csv, line ",
            "column 2: align_left_mm varies between the rows of the 0.1 m table step",
            "2 × step = 0.2 m",
            "--step 0.01",
        ],
    );
    let out = built(
        &build(
            &dir,
            &c,
            &["--irregularities", irr.to_str().unwrap(), "--step", "0.01"],
        ),
        "0.01 m step",
    );
    // Rows every 0.01 m sample the 0.05 m sine at 72° of phase apart:
    // 2 mm × sin 72° = 1.90 mm at the most.
    assert!(out.contains("max irregularity  1.90 mm"), "{out}");
}

/// A cant alternating 0 / 100 mm at every 1 m control point lifts each
/// rail up and down every 2 m (300.46 m of rail on 300 m of straight);
/// rows every 10 m cannot show that: refused by the rail-length check,
/// naming the rail and both lengths. At the default 0.1 m step the rows
/// resolve it and it builds.
#[test]
fn trust_track_rail_length_against_its_rows() {
    let dir = scratch("trust_track_rail_length");
    let zigzag = |i: usize| if i % 2 == 1 { 100.0 } else { 0.0 };
    let c = write(&dir, "c.csv", straight(Some(("cant_mm", &zigzag))));
    refused(
        &build(&dir, &c, &["--step", "10"]),
        "10 m step",
        &[
            "the left rail is 300.46",
            "m long but its table rows resolve 300.000 m",
            "use a finer --step",
        ],
    );
    let out = built(&build(&dir, &c, &[]), "0.1 m step");
    assert!(out.contains("rails: left 300.46"), "{out}");
}

/// A cant of 195 mm (within the 200 mm bound) reached in 1 m: the cubic
/// spline (`--cant-scheme cubic`) overshoots it to 216 mm in the table;
/// refused at the s of the overshoot, naming the input's line and advising
/// pchip, the cant's default, with which it builds at 195 mm.
#[test]
fn trust_track_built_cant_overshoot() {
    let dir = scratch("trust_track_cant_overshoot");
    let step = |i: usize| if (100..=200).contains(&i) { 195.0 } else { 0.0 };
    let c = write(&dir, "c.csv", straight(Some(("cant_mm", &step))));
    refused(
        &build(&dir, &c, &["--cant-scheme", "cubic"]),
        "cubic",
        &[
            "the built cant reaches +0.1444 rad (+215.8 mm) at s = 199.600 m",
            "the input's largest cant is 0.1304 rad",
            "line 102",
            "--cant-scheme pchip",
        ],
    );
    let out = built(&build(&dir, &c, &[]), "pchip");
    assert!(
        out.contains("max cant          0.1304 rad (195.0 mm)"),
        "{out}"
    );
}

/// A gauge, step or cant base given in millimetres is refused as a unit
/// error naming the option and its plausible range.
#[test]
fn trust_track_options_in_millimetres() {
    let dir = scratch("trust_track_options");
    let c = write(&dir, "c.csv", straight(None));
    for (option, expect) in [
        (
            "--gauge",
            "--gauge 1435 m is outside the plausible 0.5 … 2 m",
        ),
        (
            "--cant-base",
            "--cant-base 1435 m is outside the plausible 0.5 … 2.2 m",
        ),
        (
            "--step",
            "--step 1435 m is outside the plausible 0.0001 … 10 m",
        ),
    ] {
        refused(
            &build(&dir, &c, &[option, "1435"]),
            option,
            &[expect, "check the unit"],
        );
    }
}
