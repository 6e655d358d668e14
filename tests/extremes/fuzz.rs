//! Fuzzing the readers of everything a user supplies (issue 7, part A),
//! with proptest: the track CSVs of `track-preproc` (centreline, cant,
//! irregularities — parsed, then fitted and tabulated when small), the
//! profile files (`runtime::io::profile_import`: SIMPACK .prw/.prr, two
//! columns, CSV — then turned into wheel and rail profiles), scenes
//! (`railsim::config::scene::LoadedScene::from_text`, with `--set` overrides),
//! vehicle files and DYTSI RSGEO contact tables. Each reader gets
//! arbitrary text and mutations of a valid file (characters deleted,
//! tokens inserted — `nan`, `1e308`, block markers, separators —, lines
//! duplicated, the text cut); it must return `Ok` or `Err`, never panic
//! (a panic fails the property and proptest shrinks it to a minimal input).
//!
//! Each property runs 256 cases (proptest's default), the whole module in
//! a few seconds in the dev profile; `PROPTEST_CASES=100000 cargo test
//! --test extremes fuzz::` runs longer. Failures are not persisted to
//! files: a case that once failed is kept below as a regression test.

use std::path::{Path, PathBuf};

use preproc::csv::CsvTable;
use preproc::inputs::{CantInput, CenterlineInput, IrregularityInput};
use preproc::{BuildConfig, NoProgress, TrackInputs, TrackModel};
use proptest::prelude::*;
use railsim::config::scene::LoadedScene;
use railsim::config::vehicle::VehicleFile;
use runtime::geometry::profile::{
    RailProfile, RailProfileOptions, WheelProfile, WheelProfileOptions,
};
use runtime::geometry::spline::Scheme;
use runtime::io::profile_import::{ImportOptions, parse_profile};

use crate::common::shipped;

/// 256 cases by default, `PROPTEST_CASES` to change; no failure files.
fn config() -> ProptestConfig {
    ProptestConfig {
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Characters that matter to the formats, plus anything.
const ALPHABET: &[char] = &[
    '0', '1', '2', '5', '9', '.', ',', '-', '+', 'e', 'E', ' ', '\t', '\n', '\r', '#', '!', '%',
    '"', '\'', '=', '[', ']', '{', '}', '_', 'x', 'y', 'z', 's', 'n', 'a', 'i', 'f', 'm', ';',
    '\u{feff}', 'é', '\0',
];

/// Text made of format characters (mostly) and arbitrary ones.
fn text() -> impl Strategy<Value = String> {
    proptest::collection::vec(
        prop_oneof![
            4 => proptest::sample::select(ALPHABET),
            1 => any::<char>(),
        ],
        0..400,
    )
    .prop_map(String::from_iter)
}

/// Tokens inserted by the mutations: extreme numbers, separators, format
/// keywords.
const TOKENS: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e-320",
    "0",
    "-0",
    "1e400",
    "99999999999999999999999",
    "0x10",
    "1_000",
    "",
    ",",
    ",,",
    "\n",
    "\n\n",
    "#",
    "!",
    "\"",
    "=",
    "[",
    "]",
    "[[",
    " = ",
    "\u{feff}",
    "point.begin",
    "point.end",
    "spline.begin",
    "spline.end",
    "header.begin",
    "header.end",
    "mirror.y = 1",
    "inversion = 1",
    "units.len.f = 0",
    "shift.y = 1e300",
    "rotate = 90",
    "type = 7",
    "x,y,z",
    "cant_mm",
    "s",
    "[[wheelsets]]",
    "[[elements]]",
    "[run]",
    "[track]",
    "mass_kg = -1",
    "step_s = 0",
];

/// Numbers that replace a number of the text: ordinary, extreme and
/// non-finite values.
const NUMBERS: &[&str] = &[
    "0", "-0", "1", "-1", "0.5", "-3", "7", "12.5", "100", "-250", "1e3", "1e5", "1e-9", "-1e-12",
    "3.14159", "1e9", "1e308", "-1e308", "1e-320", "nan", "inf", "-inf", "1e400",
];

/// One mutation: at the fraction `at` of the text, `kind` picks what is
/// done, `n` how much.
#[derive(Debug, Clone)]
struct Mutation {
    at: f64,
    kind: u8,
    n: usize,
}

/// One to four mutations, mostly number replacements (which keep the text
/// readable, so that the later stages are reached too), cuts rarely.
fn mutations() -> impl Strategy<Value = Vec<Mutation>> {
    let kind = prop_oneof![
        2 => Just(0u8),
        2 => Just(1u8),
        6 => Just(2u8),
        2 => Just(3u8),
        2 => Just(4u8),
        1 => Just(5u8),
    ];
    proptest::collection::vec(
        (0.0..1.0_f64, kind, 0usize..64).prop_map(|(at, kind, n)| Mutation { at, kind, n }),
        1..5,
    )
}

/// Nearest char boundary at or below `i`.
fn boundary(s: &str, i: usize) -> usize {
    let mut i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// Applies the mutations to `base`: delete up to 8 bytes, insert a token,
/// replace the number under the cursor by another, duplicate the line,
/// delete the line, cut the text.
fn mutate(base: &str, ms: &[Mutation]) -> String {
    let mut s = base.to_string();
    for m in ms {
        let i = boundary(&s, (m.at * s.len() as f64) as usize);
        let token = TOKENS[m.n % TOKENS.len()];
        match m.kind {
            0 => {
                let j = boundary(&s, i + 1 + m.n % 8);
                s.replace_range(i..j.max(i), "");
            }
            1 => s.insert_str(i, token),
            2 => {
                // The run of number characters around i.
                let is_num = |c: char| c.is_ascii_digit() || ".-+eE".contains(c);
                let start = s[..i]
                    .char_indices()
                    .rev()
                    .take_while(|(_, c)| is_num(*c))
                    .last()
                    .map_or(i, |(k, _)| k);
                let end = s[i..]
                    .char_indices()
                    .find(|(_, c)| !is_num(*c))
                    .map_or(s.len(), |(k, _)| i + k);
                s.replace_range(start..end, NUMBERS[m.n % NUMBERS.len()]);
            }
            3 | 4 => {
                let start = s[..i].rfind('\n').map_or(0, |k| k + 1);
                let end = s[i..].find('\n').map_or(s.len(), |k| i + k + 1);
                if m.kind == 3 {
                    let line = s[start..end].to_string();
                    s.insert_str(end, &line);
                } else {
                    s.replace_range(start..end, "");
                }
            }
            _ => s.truncate(i),
        }
    }
    s
}

// ---------------------------------------------------------------------------
// Track CSVs

const CENTERLINE: &str = "# a small curve\nx,y,z,cant_mm\n0,0,0,0\n10,0,0,0\n20,0.2,0,20\n30,0.8,0.1,50\n40,1.8,0.2,50\n50,3.2,0.2,20\n60,5,0.2,0\n";
const CANT: &str = "s,cant_mm\n0,0\n20,10\n40,60\n60,60\n80,0\n";
const IRREGULARITIES: &str = "s,align_left_mm,align_right_mm,level_left_mm,level_right_mm\n0,0,0,0,0\n10,1,1,-1,0.5\n20,-2,-2,1,0\n40,0,0,0,0\n70,0,0,0,0\n";
const MEASUREMENT_CAR: &str =
    "s,alignment,gauge,level,cross_level\n0,0,0,0,0\n30,0.001,0,0,0.002\n60,0,0,0,0\n90,0,0,0,0\n";

/// Parses `centerline` (and the optional cant and irregularity texts);
/// when they parse and the track is small (polyline under 2 km, control
/// points at least 5 cm apart), fits and tabulates it at 0.5 m.
fn parse_and_build(
    centerline: &str,
    cant: Option<&str>,
    irregularities: Option<&str>,
    scheme: Scheme,
) {
    let p = Path::new("fuzz.csv");
    let _ = CsvTable::parse(p, centerline);
    let Ok(c) = CenterlineInput::parse(p, centerline) else {
        return;
    };
    let cant = match cant.map(|t| CantInput::parse(Path::new("cant.csv"), t)) {
        Some(Ok(c)) => Some(c),
        Some(Err(_)) => return,
        None => None,
    };
    let irregularities =
        match irregularities.map(|t| IrregularityInput::parse(Path::new("irr.csv"), t)) {
            Some(Ok(i)) => Some(i),
            Some(Err(_)) => return,
            None => None,
        };
    let gaps: Vec<f64> = c
        .points
        .windows(2)
        .map(|w| {
            ((w[1][0] - w[0][0]).powi(2)
                + (w[1][1] - w[0][1]).powi(2)
                + (w[1][2] - w[0][2]).powi(2))
            .sqrt()
        })
        .collect();
    let length: f64 = gaps.iter().sum();
    let closest = gaps.iter().copied().fold(f64::INFINITY, f64::min);
    if !(length < 2000.0 && closest > 0.05) {
        return;
    }
    let inputs = TrackInputs {
        centerline: c,
        cant,
        irregularities,
    };
    let config = BuildConfig {
        scheme,
        step_m: 0.5,
        ..BuildConfig::default()
    };
    if let Ok(model) = TrackModel::build(&inputs, &config) {
        let _ = model.tabulate(&NoProgress);
    }
}

fn scheme() -> impl Strategy<Value = Scheme> {
    proptest::sample::select(vec![
        Scheme::Cubic,
        Scheme::CubicNatural,
        Scheme::Akima,
        Scheme::Pchip,
    ])
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn track_csv_readers_take_any_text(t in text()) {
        let p = Path::new("fuzz.csv");
        let _ = CsvTable::parse(p, &t);
        let _ = CenterlineInput::parse(p, &t);
        let _ = CantInput::parse(p, &t);
        let _ = IrregularityInput::parse(p, &t);
    }

    #[test]
    fn track_csvs_mutated_parse_and_build(
        ms in mutations(),
        which in 0usize..4,
        s in scheme(),
    ) {
        match which {
            0 => parse_and_build(&mutate(CENTERLINE, &ms), None, None, s),
            1 => parse_and_build(CENTERLINE, Some(&mutate(CANT, &ms)), None, s),
            2 => parse_and_build(CENTERLINE, None, Some(&mutate(IRREGULARITIES, &ms)), s),
            _ => parse_and_build(CENTERLINE, None, Some(&mutate(MEASUREMENT_CAR, &ms)), s),
        }
    }
}

/// A random centreline: 4 to 30 control points advancing 6 cm to 30 m in
/// x, wandering up to ±20 m sideways and ±2 m vertically per point (sharp
/// kinks, radii down to centimetres), cant up to ±500 mm (beyond the
/// 0.3 rad limit now and then).
fn random_centreline() -> impl Strategy<Value = String> {
    proptest::collection::vec(
        (
            0.06..30.0_f64,
            -20.0..20.0_f64,
            -2.0..2.0_f64,
            -300.0..300.0_f64,
        ),
        4..30,
    )
    .prop_map(|rows| {
        let mut text = String::from("x,y,z,cant_mm\n");
        let (mut x, mut y, mut z) = (0.0, 0.0, 0.0);
        for (k, (dx, dy, dz, cant)) in rows.into_iter().enumerate() {
            if k > 0 {
                x += dx;
                y += dy * dx / 30.0;
                z += dz * dx / 30.0;
            }
            text.push_str(&format!("{x},{y},{z},{cant}\n"));
        }
        text
    })
}

proptest! {
    #![proptest_config(config())]

    /// Any geometry either builds into tables whose frames are orthonormal
    /// and right-handed, or is refused with an error.
    #[test]
    fn random_geometry_builds_or_is_refused(text in random_centreline(), s in scheme()) {
        let c = CenterlineInput::parse(Path::new("random.csv"), &text).expect("well-formed");
        let inputs = TrackInputs { centerline: c, cant: None, irregularities: None };
        let config = BuildConfig { scheme: s, step_m: 0.5, ..BuildConfig::default() };
        if let Ok(model) = TrackModel::build(&inputs, &config)
            && let Ok(tables) = model.tabulate(&NoProgress)
        {
            for r in tables.centerline.rows() {
                let (t, n, b) = (
                    nalgebra::Vector3::from(r.t),
                    nalgebra::Vector3::from(r.n),
                    nalgebra::Vector3::from(r.b),
                );
                let err = (t.norm() - 1.0).abs().max((n.norm() - 1.0).abs())
                    .max(t.dot(&n).abs())
                    .max((t.cross(&n) - b).norm());
                prop_assert!(err < 1e-9, "frame error {err:e} at s = {}\n{text}", r.s_m);
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Profiles

/// Parses `text` as the file `name` (its extension picks the format); when
/// it reads, builds both a wheel and a rail profile from the points.
fn parse_profile_deep(name: &str, text: &str) {
    let path = PathBuf::from(name);
    let Ok(file) = parse_profile(&path, text, &ImportOptions::default()) else {
        return;
    };
    // Both ways of choosing the stretch: refusing, and keeping the longest.
    for keep_longest_stretch in [false, true] {
        let _ = WheelProfile::from_points(
            &path,
            &file.points_m,
            &file.lines,
            file.z_down,
            WheelProfileOptions {
                keep_longest_stretch,
                ..Default::default()
            },
        );
        let _ = RailProfile::from_points(
            &path,
            &file.points_m,
            &file.lines,
            file.z_down,
            RailProfileOptions {
                keep_longest_stretch,
                ..Default::default()
            },
        );
    }
}

fn shipped_text(rel: &str) -> String {
    std::fs::read_to_string(shipped(rel)).expect("shipped file")
}

const TWO_COLUMNS: &str =
    "% y z in mm\n-60 30\n-40 12\n-30 2\n-20 0.5\n0 0\n20 0.9\n40 2.1\n60 3.5\n";

proptest! {
    #![proptest_config(config())]

    #[test]
    fn profile_readers_take_any_text(
        t in text(),
        ext in proptest::sample::select(vec!["prw", "prr", "dat", "csv", "txt"]),
    ) {
        parse_profile_deep(&format!("fuzz.{ext}"), &t);
    }

    #[test]
    fn profiles_mutated_parse_and_build(ms in mutations(), which in 0usize..4) {
        let (name, base) = match which {
            0 => ("w.prw", shipped_text("profiles/MBench_S1002_v3.prw")),
            1 => ("r.prr", shipped_text("profiles/MBench_UIC60_v3.prr")),
            2 => ("w.csv", shipped_text("profiles/ml95_like/ml95_like_wheel.csv")),
            _ => ("w.dat", TWO_COLUMNS.to_string()),
        };
        parse_profile_deep(name, &mutate(&base, &ms));
    }
}

// ---------------------------------------------------------------------------
// Scenes, vehicle files, RSGEO tables

/// Keys `--set` is fuzzed with (every section, some unknown keys).
const KEYS: &[&str] = &[
    "title",
    "track.step_m",
    "track.tables",
    "track.centerline",
    "track.straight_m",
    "track.gauge_m",
    "track.scheme",
    "contact.method",
    "contact.flange",
    "contact.creep_law",
    "contact.friction",
    "contact.restitution",
    "contact.fastsim_strips",
    "contact.fastrip_strips",
    "initial.speed_m_s",
    "initial.lateral_m",
    "initial.deceleration_m_s2",
    "run.distance_m",
    "run.duration_s",
    "run.integrator",
    "run.step_s",
    "run.rtol",
    "run.output_interval_s",
    "run",
    "initial",
    "nope.nope",
    "",
    ".",
    "a..b",
];

fn overrides() -> impl Strategy<Value = Vec<String>> {
    proptest::collection::vec(
        (
            proptest::sample::select(KEYS),
            proptest::sample::select(TOKENS),
            any::<bool>(),
        )
            .prop_map(|(k, v, eq)| {
                if eq {
                    format!("{k}={v}")
                } else {
                    format!("{k}{v}")
                }
            }),
        0..4,
    )
}

fn scene(text: &str, overrides: &[String]) {
    let _ = LoadedScene::from_text(
        text,
        PathBuf::from("/nonexistent"),
        overrides,
        "fuzz".into(),
    );
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn scenes_take_any_text(t in text(), o in overrides()) {
        scene(&t, &o);
    }

    #[test]
    fn scenes_mutated_with_overrides(ms in mutations(), o in overrides(), which in 0usize..3) {
        let base = match which {
            0 => railsim::config::scene::DEFAULT_SCENE.to_string(),
            1 => shipped_text("scenes/bogie_straight.toml"),
            _ => shipped_text("scenes/cooperrider_straight.toml"),
        };
        scene(&mutate(&base, &ms), &o);
    }

    #[test]
    fn vehicle_files_mutated(ms in mutations(), which in 0usize..3) {
        let base = match which {
            0 => shipped_text("vehicles/ml95_like_wheelset.toml"),
            1 => shipped_text("vehicles/ml95_like_bogie.toml"),
            _ => shipped_text("vehicles/cooperrider_car.toml"),
        };
        if let Ok(v) = VehicleFile::parse(&mutate(&base, &ms)) {
            let _ = v.validate();
        }
    }

    #[test]
    fn rsgeo_tables_mutated(ms in mutations(), t in text(), arbitrary in any::<bool>()) {
        let text = if arbitrary {
            t
        } else {
            // The header and the first rows are enough to reach every rule.
            let base: String = shipped_text("contact/cooperrider_RSGEO.dat")
                .lines()
                .take(40)
                .map(|l| format!("{l}\n"))
                .collect();
            mutate(&base, &ms)
        };
        let _ = preproc::rsgeo::parse_rsgeo(&text, Path::new("fuzz.dat"));
    }
}

// ---------------------------------------------------------------------------
// Regressions: inputs that once broke a reader.

/// A centreline spanning 3 × 10⁹ m, and one with control points 10⁻⁸ m
/// apart, used to abort the build on a failed allocation (the tables, or
/// the rails' nodal points, would have needed 3 × 10¹⁰ and 3 × 10¹¹
/// rows); they are now refused before allocating
/// (`preproc::model::MAX_TABLE_ROWS`). Coordinates beyond 10⁸ m are now
/// refused on reading (`preproc::bounds::MAX_COORDINATE_M`), so the long
/// track spans 3 × 10⁷ m (3 × 10⁸ rows), and the 3 × 10⁹ m one is refused
/// at its line and column.
#[test]
fn regression_oversized_tracks_are_refused() {
    let e = CenterlineInput::parse(
        Path::new("big.csv"),
        "x,y,z\n0,0,0\n1e9,0,0\n2e9,0,0\n3e9,0,0\n",
    )
    .expect_err("refused");
    assert!(e.to_string().contains("big.csv, line 3, column 1"), "{e}");
    for text in [
        "x,y,z\n0,0,0\n1e7,0,0\n2e7,0,0\n3e7,0,0\n",
        "x,y,z\n0,0,0\n1e-8,0,0\n1000,0,0\n2000,0,0\n3000,0,0\n",
    ] {
        let c = CenterlineInput::parse(Path::new("big.csv"), text).expect("parses");
        let inputs = TrackInputs {
            centerline: c,
            cant: None,
            irregularities: None,
        };
        let e = TrackModel::build(&inputs, &BuildConfig::default()).expect_err("refused");
        assert!(matches!(e, preproc::BuildError::TooLarge { .. }), "{e}");
    }
}

/// A two-column wheel profile with a point at y = 10²² m (a mutation of
/// `TWO_COLUMNS`): building the wheel profile panicked with "capacity
/// overflow" (its scan grid every 0.05 mm across the span); a profile
/// wider than 0.5 m is now refused (`runtime::geometry::profile::MAX_PROFILE_SPAN_M`).
#[test]
fn regression_profile_spanning_1e22_m() {
    let text =
        "% y z in mm\n-60 30\n-30 2\n-20 0.5\n0 0\n20 0.9\n9999999999999999999999940 2.1\n60 3.5\n";
    let path = Path::new("w.dat");
    let file = parse_profile(path, text, &ImportOptions::default()).expect("parses");
    let e = WheelProfile::from_points(
        path,
        &file.points_m,
        &file.lines,
        file.z_down,
        WheelProfileOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("lateral span"), "{e}");
    assert!(e.to_string().contains("check the unit"), "{e}");
    parse_profile_deep("w.dat", text);
}

/// A measurement-car irregularity table with an alignment of 10²³ m (a
/// mutation of `MEASUREMENT_CAR`): the rail built from it was 10²³ m long
/// and its table overflowed its capacity; irregularities beyond 0.2 m are
/// now refused at their line (`preproc::inputs::MAX_IRREGULARITY_M`).
#[test]
fn regression_irregularity_of_1e23_m() {
    let text = "s,alignment,gauge,level,cross_level\n0,0,0,0,0\n30,99999999999999999999999,0,0,0.002\n60,0,0,0,0\n90,0,0,0,0\n";
    let e = IrregularityInput::parse(Path::new("irr.csv"), text).unwrap_err();
    assert!(e.to_string().contains("line 3"), "{e}");
    parse_and_build(CENTERLINE, None, Some(text), Scheme::Cubic);
}

/// The mutation helper itself: every kind applies without panicking on
/// multi-byte text, and the cut shortens it.
#[test]
fn mutations_apply_to_any_text() {
    let base = "é,ü\n1,2\n";
    for kind in 0..6 {
        for at in [0.0, 0.3, 0.99] {
            let s = mutate(base, &[Mutation { at, kind, n: 5 }]);
            if kind == 5 {
                assert!(s.len() < base.len(), "{s:?}");
            }
        }
    }
}
