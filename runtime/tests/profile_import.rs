//! Profile import on the real profile files (Manchester benchmark S1002 /
//! UIC60 in SIMPACK format, EN 15302 reference wheel and rail A as plain
//! millimetre columns) and on small synthetic files; every error case
//! through the public API.
//!
//! The real files are copies in `tests/data/profiles/` (see the README
//! there). When the project's shipped copies (`tables/profiles/`,
//! `tests/data/en15302/`) exist, they must import to the same points.

use std::path::{Path, PathBuf};

use runtime::fixtures::{repository_dir, test_profile};
use runtime::io::profile_import::{
    ImportOptions, MIN_POINTS, ProfileFile, ProfileFormat, ProfileImportError as E, ProfileKind,
    YOrder, parse_profile, read_profile,
};

fn fixture(name: &str) -> PathBuf {
    test_profile(name)
}

fn read(name: &str) -> ProfileFile {
    read_profile(&fixture(name), &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn text(name: &str) -> String {
    std::fs::read_to_string(fixture(name)).unwrap()
}

/// Point in millimetres.
fn mm(p: [f64; 2]) -> [f64; 2] {
    [p[0] * 1e3, p[1] * 1e3]
}

fn assert_mm(got_m: [f64; 2], want_mm: [f64; 2]) {
    let g = mm(got_m);
    assert!(
        (g[0] - want_mm[0]).abs() < 1e-9 && (g[1] - want_mm[1]).abs() < 1e-9,
        "got {g:?} mm, want {want_mm:?} mm"
    );
}

/// Index of the point with the largest (`max`) or smallest z.
fn extreme_z(f: &ProfileFile, max: bool) -> usize {
    let mut best = 0;
    for (i, p) in f.points_m.iter().enumerate() {
        let b = f.points_m[best][1];
        if (max && p[1] > b) || (!max && p[1] < b) {
            best = i;
        }
    }
    best
}

/// z at `y` by linear interpolation (profile must be monotone in y).
fn z_at(f: &ProfileFile, y: f64) -> f64 {
    let mut p = f.points_m.clone();
    p.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let k = p.partition_point(|q| q[0] < y).clamp(1, p.len() - 1);
    let (a, b) = (p[k - 1], p[k]);
    a[1] + (b[1] - a[1]) * (y - a[0]) / (b[0] - a[0])
}

#[test]
fn s1002_wheel_simpack() {
    let f = read("MBench_S1002_v3.prw");
    assert_eq!(f.format, ProfileFormat::Simpack);
    assert_eq!(f.kind, Some(ProfileKind::Wheel));
    assert!(f.z_down);
    // Lines 44..=442 hold the points; line 43 is a commented-out point.
    assert_eq!(f.len(), 399);
    assert_eq!(
        (f.lines[0], f.lines[398]),
        (442, 44),
        "inversion = 1 reverses the order"
    );
    let s = f.simpack.as_ref().unwrap();
    assert!(s.mirror_y && !s.mirror_z && s.inversion);
    assert_eq!((s.units_len_f, s.bound_y, s.bound_z), (1000.0, None, None));
    assert_eq!(s.source_file.as_deref(), Some("S1002_v3.whe.txt"));
    assert!(
        f.comment
            .as_deref()
            .unwrap()
            .starts_with("S1002 wheel profile v3")
    );

    // After mirror.y and inversion the file's last row (line 442,
    // "-60 -2.6356764") is the first point and its first row (line 44) the last.
    assert_mm(f.points_m[0], [60.0, -2.6356764]);
    assert_mm(f.points_m[398], [-69.612628, 13.485642]);
    assert_eq!(
        f.y_order,
        YOrder::Decreasing,
        "field side first, flange back last"
    );

    // Flange tip: largest z (z down), at negative y, 28 mm below the tread.
    let tip = extreme_z(&f, true);
    assert_mm(f.points_m[tip], [-54.892493, 27.999518]);
    assert_eq!(f.lines[tip], 82);
    // Tread datum: z ≈ 0 at y = 0; the field-side end is the highest point.
    assert!(z_at(&f, 0.0).abs() < 1e-5, "{}", z_at(&f, 0.0));
    assert_eq!(extreme_z(&f, false), 0);
    let (y0, y1) = f.y_range_m();
    let (z0, z1) = f.z_range_m();
    assert!((y0 + 0.069612628).abs() < 1e-12 && (y1 - 0.060).abs() < 1e-12);
    assert!((z0 + 0.0026356764).abs() < 1e-12 && (z1 - 0.027999518).abs() < 1e-12);
}

#[test]
fn uic60_rail_simpack() {
    let f = read("MBench_UIC60_v3.prr");
    assert_eq!(f.kind, Some(ProfileKind::Rail));
    assert!(f.z_down);
    assert_eq!(f.len(), 495);
    assert_eq!((f.lines[0], f.lines[494]), (43, 537));
    assert_mm(f.points_m[0], [-43.704898, 38.510726]);
    assert_mm(f.points_m[494], [30.595912, 36.653225]);
    assert_eq!(f.y_order, YOrder::Increasing);
    assert!(f.comment.as_deref().unwrap().contains("already canted"));
    // Top of rail: smallest z (z down), near y = 0.
    let top = extreme_z(&f, false);
    assert_mm(f.points_m[top], [-0.18441236, 6.0323487e-05]);
    assert_eq!(f.lines[top], 306);
    // The gauge face (first points, deep below the top) is at negative y.
    assert!(f.points_m[0][0] < -0.04 && f.points_m[0][1] > 0.035);
}

#[test]
fn en15302_wheel_a_plain_millimetres() {
    let f = read("A_WRCC_RUIC519A.dat");
    assert_eq!(f.format, ProfileFormat::Plain);
    assert_eq!(f.kind, None);
    assert!(!f.z_down);
    assert_eq!(f.len(), 1001);
    assert_eq!((f.lines[0], f.lines[1000]), (1, 1001));
    assert_mm(f.points_m[0], [-70.0, -9.519]);
    assert_mm(f.points_m[1000], [65.0, 7.493]);
    assert_eq!(f.y_order, YOrder::Increasing);
    // Flange at negative y, z up: the flange tip is the lowest point.
    let tip = extreme_z(&f, false);
    assert_mm(f.points_m[tip], [-55.015, -27.99999]);
    assert!(z_at(&f, 0.0).abs() < 1e-5);
}

#[test]
fn en15302_rail_a_plain_millimetres() {
    let f = read("A_WRCC_SUIC519A.dat");
    assert_eq!(f.len(), 1001);
    assert!(!f.z_down);
    assert_eq!(f.y_order, YOrder::Increasing);
    assert_mm(f.points_m[0], [-32.5, -14.0]);
    assert_mm(f.points_m[1000], [39.0, -10.665]);
    // z up: the highest point of the head.
    let top = extreme_z(&f, true);
    assert_mm(f.points_m[top], [14.3325, 0.491777]);
    assert!(z_at(&f, 0.0).abs() < 1e-5);
}

/// The two conventions agree: the S1002 wheel read from SIMPACK (z down)
/// and the EN 15302 wheel A (z up), which share the flange of S1002, lie on
/// top of each other over the flange once z is negated; their treads differ
/// by the documented few tenths of a millimetre.
#[test]
fn simpack_and_plain_conventions_agree_on_the_s1002_flange() {
    let simpack = read("MBench_S1002_v3.prw");
    let flipped = read_profile(
        &fixture("MBench_S1002_v3.prw"),
        &ImportOptions {
            mirror_z: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        flipped.z_down,
        "the option corrects the data, not the convention flag"
    );
    for (a, b) in simpack.points_m.iter().zip(&flipped.points_m) {
        assert_eq!([a[0], -a[1]], *b);
    }
    let en = read("A_WRCC_RUIC519A.dat");
    for y_mm in [-60.0, -55.0, -50.0, -45.0, -40.0] {
        let d = z_at(&flipped, y_mm * 1e-3) - z_at(&en, y_mm * 1e-3);
        assert!(d.abs() < 1e-5, "flange at y = {y_mm} mm differs by {d} m");
    }
    for y_mm in [-30.0, -10.0, 0.0, 10.0, 30.0, 50.0] {
        let d = z_at(&flipped, y_mm * 1e-3) - z_at(&en, y_mm * 1e-3);
        assert!(d.abs() < 0.5e-3, "tread at y = {y_mm} mm differs by {d} m");
    }
}

#[test]
fn mirror_y_option_moves_the_flange_to_positive_y() {
    let o = ImportOptions {
        mirror_y: true,
        ..Default::default()
    };
    let f = read_profile(&fixture("A_WRCC_RUIC519A.dat"), &o).unwrap();
    assert_eq!(f.y_order, YOrder::Decreasing, "order kept, y negated");
    let tip = extreme_z(&f, false);
    assert_mm(f.points_m[tip], [55.015, -27.99999]);
}

#[test]
fn synthetic_simpack_file_applies_all_steps() {
    let f = read("synthetic_transforms.prw");
    assert_eq!(f.kind, Some(ProfileKind::Wheel));
    // See the file: drop line 26 (point.dist.min), shift, rotate 180°, drop
    // line 31 (bound.y), mirror y, invert, centimetres.
    let want = [
        [0.04, -0.065],
        [0.03, -0.035],
        [0.02, -0.015],
        [0.01, -0.005],
        [0.0, 0.0],
    ];
    assert_eq!(f.len(), want.len());
    for (p, q) in f.points_m.iter().zip(want) {
        assert!(
            (p[0] - q[0]).abs() < 1e-15 && (p[1] - q[1]).abs() < 1e-15,
            "{p:?} vs {q:?}"
        );
    }
    assert_eq!(f.lines, vec![30, 29, 28, 27, 25]);
    let s = f.simpack.unwrap();
    assert_eq!((s.removed_by_point_dist_min, s.removed_by_bound_y), (1, 1));
    assert!((s.rotate_rad - std::f64::consts::PI).abs() < 1e-15);
    assert_eq!(
        f.comment.as_deref(),
        Some("synthetic wheel: shift, rotate, bounds, mirror, inversion, cm")
    );
}

#[test]
fn synthetic_csv_in_millimetres() {
    let f = read("synthetic_rail_mm.csv");
    assert_eq!(f.format, ProfileFormat::Csv);
    assert!(!f.z_down);
    assert_eq!(f.len(), 7);
    assert_eq!(f.lines[0], 4);
    assert_mm(f.points_m[3], [0.0, 0.0]);
    assert_mm(f.points_m[0], [-30.0, -1.5037689]);
    assert!(f.comment.as_deref().unwrap().contains("radius 300 mm"));
}

#[test]
fn shipped_copies_import_like_the_fixtures() {
    let root = repository_dir();
    let pairs = [
        ("tables/profiles/MBench_S1002_v3.prw", "MBench_S1002_v3.prw"),
        ("tables/profiles/MBench_UIC60_v3.prr", "MBench_UIC60_v3.prr"),
        (
            "tests/data/en15302/A_WRCC_RUIC519A.dat",
            "A_WRCC_RUIC519A.dat",
        ),
        (
            "tests/data/en15302/A_WRCC_SUIC519A.dat",
            "A_WRCC_SUIC519A.dat",
        ),
    ];
    for (shipped, name) in pairs {
        let path = root.join(shipped);
        if !path.exists() {
            continue; // not shipped (yet): the fixtures stand alone
        }
        let a = read_profile(&path, &ImportOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let b = read(name);
        assert_eq!(a.points_m, b.points_m, "{shipped}");
        assert_eq!(
            (a.kind, a.z_down, a.format),
            (b.kind, b.z_down, b.format),
            "{shipped}"
        );
    }
}

// ---------------------------------------------------------------- errors

/// `text` with the first occurrence of `from` replaced by `to`.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

fn parse(name: &str, text: &str) -> Result<ProfileFile, E> {
    parse_profile(Path::new(name), text, &ImportOptions::default())
}

/// The error's message starts with the file and the line (and the column,
/// for a value in a row of numbers), and `line()` agrees.
fn assert_located(e: &E, file: &str, line: usize) {
    assert_eq!(e.line(), Some(line), "{e}");
    assert_eq!(e.path(), Path::new(file));
    let msg = e.to_string();
    let at = format!("'{file}', line {line}");
    let column = match e {
        E::NotANumber { column, .. } | E::NonFinite { column, .. } => *column,
        _ => None,
    };
    let want = match column {
        Some(c) => format!("{at}, column {c}: "),
        None => format!("{at}: "),
    };
    assert!(msg.starts_with(&want), "{msg}");
}

#[test]
fn error_unsupported_transform_value_in_the_real_wheel() {
    let t = edit(
        &text("MBench_S1002_v3.prw"),
        "mirror.y       =  1",
        "mirror.y       =  2",
    );
    let e = parse("MBench_S1002_v3.prw", &t).unwrap_err();
    assert!(
        matches!(&e, E::UnsupportedValue { key, value, .. } if key == "mirror.y" && value == "2"),
        "{e:?}"
    );
    assert_located(&e, "MBench_S1002_v3.prw", 32);
    assert!(e.to_string().contains("must be 0 (off) or 1 (on)"), "{e}");

    let t = edit(
        &text("MBench_S1002_v3.prw"),
        "inversion      =  1",
        "inversion      =  yes",
    );
    let e = parse("w.prw", &t).unwrap_err();
    assert!(matches!(&e, E::NotANumber { .. }), "{e:?}");
    assert_located(&e, "w.prw", 34);
}

#[test]
fn error_missing_point_block() {
    let t = text("MBench_UIC60_v3.prr");
    let start = t.find("    point.begin").unwrap();
    let end = t.find("  spline.end").unwrap();
    let cut = format!("{}{}", &t[..start], &t[end..]);
    let e = parse("r.prr", &cut).unwrap_err();
    assert!(matches!(e, E::MissingPointBlock { .. }), "{e:?}");
    assert_located(&e, "r.prr", 39); // the spline.end line
}

#[test]
fn error_duplicate_point_in_the_real_rail() {
    // Repeat the row of line 100 right after it: the copy is line 101.
    let t = text("MBench_UIC60_v3.prr");
    let lines: Vec<&str> = t.lines().collect();
    let mut v = lines.clone();
    v.insert(100, lines[99]);
    let e = parse("r.prr", &v.join("\n")).unwrap_err();
    assert!(
        matches!(
            e,
            E::DuplicatePoint {
                previous_line: 100,
                ..
            }
        ),
        "{e:?}"
    );
    assert_located(&e, "r.prr", 101);
}

#[test]
fn error_non_numeric_and_non_finite_values() {
    let t = edit(&text("A_WRCC_RUIC519A.dat"), "-69.73000", "-69.73OOO");
    let e = parse("a.dat", &t).unwrap_err();
    assert!(
        matches!(&e, E::NotANumber { text, .. } if text == "-69.73OOO"),
        "{e:?}"
    );
    assert_located(&e, "a.dat", 3);
    let t = edit(&text("A_WRCC_RUIC519A.dat"), "-10.73762", "NaN");
    let e = parse("a.dat", &t).unwrap_err();
    assert!(matches!(e, E::NonFinite { .. }), "{e:?}");
    assert_located(&e, "a.dat", 2);
    let t = edit(
        &text("MBench_S1002_v3.prw"),
        "6.9225256E+01",
        "6.9225256E+400",
    );
    let e = parse("w.prw", &t).unwrap_err();
    assert!(matches!(e, E::NonFinite { .. }), "{e:?}");
    assert_located(&e, "w.prw", 45);
}

#[test]
fn error_wrong_number_of_values() {
    let t = edit(
        &text("A_WRCC_SUIC519A.dat"),
        "-32.4285 -13.63499",
        "-32.4285 -13.63499 7",
    );
    let e = parse("s.dat", &t).unwrap_err();
    assert!(matches!(e, E::FieldCount { found: 3, .. }), "{e:?}");
    assert_located(&e, "s.dat", 2);
}

#[test]
fn error_fewer_than_four_points() {
    let e = parse("a.dat", "-1 0\n0 0\n1 0\n").unwrap_err();
    assert!(
        matches!(
            e,
            E::TooFewPoints {
                found: 3,
                min: MIN_POINTS,
                ..
            }
        ),
        "{e:?}"
    );
    assert_located(&e, "a.dat", 3);
    // In a SIMPACK file, points removed by bound.y count.
    let t = edit(
        &text("MBench_UIC60_v3.prr"),
        "bound.y.min    = +1.0",
        "bound.y.min    = -0.1",
    );
    let t = edit(&t, "bound.y.max    = +0.0", "bound.y.max    = +0.1");
    let e = parse("r.prr", &t).unwrap_err();
    assert!(
        matches!(e, E::TooFewPoints { in_file: 495, found, .. } if found < 4),
        "{e:?}"
    );
    assert_located(&e, "r.prr", 538); // point.end
}

#[test]
fn error_unknown_and_duplicate_keys_and_bad_nesting() {
    let t = edit(
        &text("MBench_S1002_v3.prw"),
        "shift.y        =",
        "shift.x        =",
    );
    let e = parse("w.prw", &t).unwrap_err();
    assert!(
        matches!(&e, E::UnknownKey { key, .. } if key == "shift.x"),
        "{e:?}"
    );
    assert_located(&e, "w.prw", 25);
    let t = edit(
        &text("MBench_S1002_v3.prw"),
        "shift.z        =",
        "shift.y        =",
    );
    let e = parse("w.prw", &t).unwrap_err();
    assert!(matches!(e, E::DuplicateKey { first_line: 25, .. }), "{e:?}");
    assert_located(&e, "w.prw", 26);
    let t = edit(&text("MBench_S1002_v3.prw"), "  header.end", "  ");
    let e = parse("w.prw", &t).unwrap_err();
    assert!(matches!(e, E::Syntax { .. }), "{e:?}");
    assert_located(&e, "w.prw", 18); // spline.begin inside the header block
}

#[test]
fn error_header_type_contradicts_extension() {
    let e = parse("MBench_S1002_v3.prr", &text("MBench_S1002_v3.prw")).unwrap_err();
    assert!(
        matches!(
            e,
            E::KindConflict {
                header_kind: ProfileKind::Wheel,
                extension_kind: ProfileKind::Rail,
                ..
            }
        ),
        "{e:?}"
    );
    assert_located(&e, "MBench_S1002_v3.prr", 12);
}

#[test]
fn error_csv_header() {
    let e = parse("p.csv", "# c\ny,x\n0,0\n").unwrap_err();
    assert!(matches!(e, E::CsvHeader { .. }), "{e:?}");
    assert_located(&e, "p.csv", 2);
}

#[test]
fn error_invalid_option_and_missing_file() {
    let o = ImportOptions {
        length_unit: Some(-1e-3),
        ..Default::default()
    };
    let e = read_profile(&fixture("A_WRCC_RUIC519A.dat"), &o).unwrap_err();
    assert!(matches!(e, E::InvalidOption { .. }), "{e:?}");
    assert!(e.to_string().contains("A_WRCC_RUIC519A.dat"), "{e}");

    let missing = fixture("no_such_profile.prw");
    let e = read_profile(&missing, &ImportOptions::default()).unwrap_err();
    assert!(matches!(e, E::Io { .. }), "{e:?}");
    assert_eq!(e.path(), missing);
    assert_eq!(e.line(), None);
}

#[test]
fn later_checks_can_name_a_points_line() {
    let f = read("MBench_S1002_v3.prw");
    let tip = extreme_z(&f, true);
    let e = f.error_at(tip, "flange region not convex");
    assert!(matches!(e, E::Invalid { line: 82, .. }), "{e:?}");
    assert!(
        e.to_string()
            .ends_with("MBench_S1002_v3.prw', line 82: flange region not convex"),
        "{e}"
    );
}

/// Bad input never panics: every truncation of the real files, and
/// pseudo-random byte edits, give a profile or an error.
#[test]
fn truncated_or_garbled_input_never_panics() {
    for name in [
        "MBench_S1002_v3.prw",
        "synthetic_transforms.prw",
        "synthetic_rail_mm.csv",
    ] {
        let t = text(name);
        let ends: Vec<usize> = t.match_indices('\n').map(|(i, _)| i).collect();
        for &end in &ends {
            let _ = parse(name, &t[..end]);
        }
        // A small linear congruential generator: reproducible edits.
        let mut state: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 33) as usize
        };
        let alphabet = b"0123456789.-+eE !=',\n\t#%abcxyz";
        for _ in 0..300 {
            let mut bytes = t.clone().into_bytes();
            for _ in 0..1 + next() % 4 {
                let at = next() % bytes.len();
                bytes[at] = alphabet[next() % alphabet.len()];
            }
            let garbled = String::from_utf8_lossy(&bytes);
            if let Err(e) = parse(name, &garbled) {
                // Content errors name a line of the file.
                let line = e.line().expect("a content error has a line");
                assert!(line >= 1 && line <= garbled.lines().count().max(1), "{e}");
            }
        }
    }
}
