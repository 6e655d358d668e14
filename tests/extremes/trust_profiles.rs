//! Trust (issue 12), wheel and rail profiles: nothing lost, nothing
//! silently wrong, in every format (SIMPACK `.prw` / `.prr`, plain
//! two-column, CSV; docs/reference/02-inputs.md §2.6).
//!
//! - A profile that folds back (a loop), zig-zags (two points swapped) or
//!   repeats its lateral coordinate is refused at the file line of the
//!   first offending point; before, its longest increasing stretch was kept
//!   silently.
//! - `keep_longest_stretch` keeps that stretch, with a warning naming every
//!   dropped line, which `sim contact`, `sim run` and `track-preproc
//!   contact-table` show.
//! - Lengths in the wrong unit (metres under a `y_mm,z_mm` header) are
//!   refused with "check the unit"; so is a wheel without a flange.
//! - A UTF-8 byte order mark is read in every format; a bad number names
//!   the file, the line and the column.
//! - The shipped profiles load as before: only the steep faces at their
//!   ends are trimmed, without a warning.

use std::path::{Path, PathBuf};

use runtime::geometry::profile::{
    ProfileError, RailPlacement, RailProfileOptions, WheelProfile, WheelProfileOptions,
};
use runtime::io::profile_import::{
    ImportOptions, Loaded, ProfileImportError, ProfileLoadError, load_rail, load_wheel,
    read_profile,
};

use super::common::*;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Wheel,
    Rail,
}

/// A profile in one format: its text, where its points are, and a lateral
/// position (file units, as written) in the middle of its tread or head,
/// on the field side, where the faults are put.
struct Sample {
    /// File name, whose extension picks the format.
    name: &'static str,
    kind: Kind,
    text: String,
    target_y: f64,
}

/// The shipped profiles, and the ML95-like wheel also as plain columns.
fn samples() -> Vec<Sample> {
    let read = |rel: &str| std::fs::read_to_string(shipped(rel)).expect("shipped profile");
    let csv = read("profiles/ml95_like/ml95_like_wheel.csv");
    // The same points as plain millimetre columns, after a comment line
    // (so the line numbers stay those of the CSV).
    let dat = std::iter::once("% ML95-like wheel, y z in mm".to_string())
        .chain(csv.lines().skip(1).map(|l| l.replace(',', " ")))
        .collect::<Vec<_>>()
        .join("\n")
        + "\n";
    vec![
        // S1002: mirror.y = 1, so the field side is at negative y as written.
        Sample {
            name: "s1002.prw",
            kind: Kind::Wheel,
            text: read("profiles/MBench_S1002_v3.prw"),
            target_y: -20.0,
        },
        Sample {
            name: "uic60.prr",
            kind: Kind::Rail,
            text: read("profiles/MBench_UIC60_v3.prr"),
            target_y: 26.5,
        },
        Sample {
            name: "ml95.dat",
            kind: Kind::Wheel,
            text: dat,
            target_y: 20.0,
        },
        Sample {
            name: "ml95.csv",
            kind: Kind::Wheel,
            text: csv,
            target_y: 20.0,
        },
    ]
}

/// 0-based indices of the text lines holding points, in file order.
fn point_rows(s: &Sample) -> Vec<usize> {
    let simpack = s.name.ends_with(".prw") || s.name.ends_with(".prr");
    let mut inside = !simpack;
    let mut rows = Vec::new();
    for (i, line) in s.text.lines().enumerate() {
        let data = line.split(['!', '%', '#']).next().unwrap_or("").trim();
        let lower = data.to_ascii_lowercase();
        if simpack && lower == "point.begin" {
            inside = true;
        } else if simpack && lower == "point.end" {
            inside = false;
        } else if inside && !data.is_empty() && fields(data)[0].parse::<f64>().is_ok() {
            rows.push(i);
        }
    }
    rows
}

fn fields(data: &str) -> Vec<&str> {
    data.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|f| !f.is_empty())
        .collect()
}

/// (y, z) of a point row, as written.
fn yz(line: &str) -> (f64, f64) {
    let f = fields(line);
    (f[0].parse().unwrap(), f[1].parse().unwrap())
}

/// A point row in the sample's format.
fn row(s: &Sample, y: f64, z: f64) -> String {
    if s.name.ends_with(".csv") {
        format!("{y:.6},{z:.6}")
    } else {
        format!("{y:.7e}\t{z:.7e}")
    }
}

/// A fault put into a profile's text: the faulty text and the 1-based
/// line of the first offending point.
struct Fault {
    what: &'static str,
    text: String,
    line: usize,
}

fn faults(s: &Sample) -> Vec<Fault> {
    let lines: Vec<String> = s.text.lines().map(str::to_string).collect();
    let rows = point_rows(s);
    // The row nearest the target.
    let k = (1..rows.len() - 2)
        .min_by(|&a, &b| {
            let d = |i: usize| (yz(&lines[rows[i]]).0 - s.target_y).abs();
            d(a).total_cmp(&d(b))
        })
        .expect("rows");
    let (i, j) = (rows[k], rows[k + 1]);
    let join = |v: &[String]| v.join("\n") + "\n";

    // Two points swapped: the later of the two is the first offending one.
    let mut swapped = lines.clone();
    swapped.swap(i, j);
    // The y of the point before repeated (z kept).
    let mut repeated = lines.clone();
    let (y0, _) = yz(&lines[rows[k - 1]]);
    let (_, z1) = yz(&lines[i]);
    repeated[i] = row(s, y0, z1);
    // A loop: on half a step (on the chord), back two and a half steps
    // 0.05 mm off the profile, then on again to the next point.
    let ((ya, za), (yb, zb)) = (yz(&lines[i]), yz(&lines[j]));
    let step = yb - ya;
    let mut looped = lines.clone();
    looped.splice(
        j..j,
        [
            row(s, ya + 0.5 * step, 0.5 * (za + zb)),
            row(s, ya - 1.5 * step, za + 0.05),
            row(s, ya - 2.5 * step, za + 0.05),
        ],
    );
    vec![
        Fault {
            what: "zig-zag",
            text: join(&swapped),
            line: j + 1,
        },
        Fault {
            what: "repeated y",
            text: join(&repeated),
            line: i + 1,
        },
        // The first step back is to the second point inserted.
        Fault {
            what: "loop",
            text: join(&looped),
            line: j + 2,
        },
    ]
}

/// Load `path` as the sample's kind; the profile's warnings as text.
fn load(kind: Kind, path: &Path, keep: bool) -> Result<Vec<String>, ProfileLoadError> {
    let import = ImportOptions::default();
    let text = |w: &[runtime::geometry::profile::ProfileWarning]| {
        w.iter().map(ToString::to_string).collect()
    };
    match kind {
        Kind::Wheel => {
            let l = load_wheel(
                path,
                &import,
                WheelProfileOptions {
                    keep_longest_stretch: keep,
                    ..Default::default()
                },
            )?;
            assert_eq!(l.warnings, l.profile.warnings());
            Ok(text(&l.warnings))
        }
        Kind::Rail => {
            let l = load_rail(
                path,
                &import,
                RailProfileOptions {
                    keep_longest_stretch: keep,
                    ..Default::default()
                },
            )?;
            Ok(text(&l.warnings))
        }
    }
}

#[test]
fn a_profile_that_folds_back_is_refused_at_its_line_in_every_format() {
    let dir = scratch("trust_profiles_fold_back");
    for s in samples() {
        for f in faults(&s) {
            let path = dir.join(format!("{}_{}", f.what.replace(' ', "_"), s.name));
            std::fs::write(&path, &f.text).unwrap();
            let case = format!("{} {}", s.name, f.what);
            let e = load(s.kind, &path, false).expect_err(&case);
            let ProfileLoadError::Profile(ProfileError::AtPoint { line, .. }) = &e else {
                panic!("{case}: {e:?}")
            };
            assert_eq!(*line, Some(f.line), "{case}: {e}");
            let msg = e.to_string();
            assert!(
                msg.starts_with(&format!("'{}', line {}: ", path.display(), f.line)),
                "{case}: {msg}"
            );
            let word = if f.what == "repeated y" {
                "repeats"
            } else {
                "turns back"
            };
            assert!(msg.contains(word), "{case}: {msg}");
            assert!(msg.contains("--keep-longest-stretch"), "{case}: {msg}");
        }
    }
}

/// The dropped line ranges of a warning, parsed back from its text
/// ("dropped N point(s), lines a–b, c–d;").
fn dropped_ranges(warning: &str) -> Vec<[usize; 2]> {
    let tail = warning
        .split("point(s), lines ")
        .nth(1)
        .expect("dropped lines");
    let list = tail.split(';').next().unwrap();
    list.split(", ")
        .map(|r| {
            let mut it = r.split('–').map(|n| n.trim().parse::<usize>().unwrap());
            let a = it.next().unwrap();
            [a, it.next().unwrap_or(a)]
        })
        .collect()
}

#[test]
fn keep_longest_stretch_warns_naming_the_dropped_lines_in_every_format() {
    let dir = scratch("trust_profiles_keep");
    for s in samples() {
        for f in faults(&s) {
            let path = dir.join(format!("{}_{}", f.what.replace(' ', "_"), s.name));
            std::fs::write(&path, &f.text).unwrap();
            let case = format!("{} {}", s.name, f.what);
            let warnings = load(s.kind, &path, true).unwrap_or_else(|e| panic!("{case}: {e}"));
            let [w] = &warnings[..] else {
                panic!("{case}: one warning expected, got {warnings:?}")
            };
            assert!(
                w.starts_with(&format!("warning: '{}'", path.display())),
                "{w}"
            );
            assert!(w.contains("keep_longest_stretch"), "{w}");
            assert!(w.contains(&format!("line {}: ", f.line)), "{case}: {w}");
            // The offending point is among the dropped lines, and every
            // dropped point's line is named.
            let ranges = dropped_ranges(w);
            assert!(
                ranges.iter().any(|[a, b]| (*a..=*b).contains(&f.line)),
                "{case}: {ranges:?} in {w}"
            );
            let rows = point_rows(&Sample {
                name: s.name,
                kind: s.kind,
                text: f.text.clone(),
                target_y: 0.0,
            });
            let named = rows
                .iter()
                .filter(|&&i| ranges.iter().any(|[a, b]| (*a..=*b).contains(&(i + 1))))
                .count();
            let count: usize = w
                .split("dropped ")
                .nth(1)
                .and_then(|t| t.split(' ').next())
                .and_then(|n| n.parse().ok())
                .expect("the number dropped");
            // SIMPACK's commented-out flange back point is no point.
            assert_eq!(named, count, "{case}: {w}");
        }
    }
}

#[test]
fn the_shipped_profiles_load_as_before_without_a_warning() {
    for s in samples() {
        let path = shipped(match s.name {
            "s1002.prw" => "profiles/MBench_S1002_v3.prw",
            "uic60.prr" => "profiles/MBench_UIC60_v3.prr",
            _ => "profiles/ml95_like/ml95_like_wheel.csv",
        });
        for keep in [false, true] {
            let w = load(s.kind, &path, keep).unwrap_or_else(|e| panic!("{}: {e}", s.name));
            assert!(w.is_empty(), "{}: {w:?}", s.name);
        }
    }
    // Only the steep faces at the ends are trimmed (docs/reference/02-inputs.md
    // §2.6): the rail head runs from line 440 to line 141 of the file (its
    // sides, lines 441–537 and 43–140, are dropped), the ML95-like wheel
    // ends at line 40 (its flange back face, lines 2–39, is dropped), and
    // the S1002 wheel keeps its last point, line 44.
    let file_y = |rel: &str, line: usize| {
        let f = read_profile(&shipped(rel), &ImportOptions::default()).unwrap();
        let k = f.lines.iter().position(|&l| l == line).expect("line");
        f.points_m[k][0]
    };
    let Loaded { profile: rail, .. } = load_rail(
        &shipped("profiles/MBench_UIC60_v3.prr"),
        &ImportOptions::default(),
        RailProfileOptions::default(),
    )
    .unwrap();
    let placed = rail
        .placed(&RailPlacement {
            gauge_m: 1.435,
            rail_spacing_m: 1.507,
            inclination_rad: 0.0,
        })
        .unwrap();
    let (u0, u1) = placed.head().domain_m();
    let rail_y = |u: f64| placed.to_file_m(u, 0.0).0;
    let uic = "profiles/MBench_UIC60_v3.prr";
    // u runs towards the gauge face (file y down).
    assert!((rail_y(u0) - file_y(uic, 440)).abs() < 1e-12);
    assert!((rail_y(u1) - file_y(uic, 141)).abs() < 1e-12);
    let flange_end = |rel: &str| {
        let w: WheelProfile = load_wheel(
            &shipped(rel),
            &ImportOptions::default(),
            WheelProfileOptions::default(),
        )
        .unwrap()
        .profile;
        let (_, u1) = w.segments().last().unwrap().curve.domain_m();
        w.to_file_m(u1, 0.0).0
    };
    let ml95 = "profiles/ml95_like/ml95_like_wheel.csv";
    assert!((flange_end(ml95) - file_y(ml95, 40)).abs() < 1e-12);
    let s1002 = "profiles/MBench_S1002_v3.prw";
    assert!((flange_end(s1002) - file_y(s1002, 44)).abs() < 1e-12);
}

/// The samples with every length divided by 1000 (metres written under a
/// millimetre unit), and S1002 declaring metres for its millimetres.
#[test]
fn lengths_in_the_wrong_unit_are_refused_with_check_the_unit() {
    let dir = scratch("trust_profiles_unit");
    for s in samples() {
        let lines: Vec<String> = s.text.lines().map(str::to_string).collect();
        let mut metres = lines.clone();
        for i in point_rows(&s) {
            let (y, z) = yz(&lines[i]);
            metres[i] = row(&s, y / 1000.0, z / 1000.0);
        }
        let path = dir.join(format!("metres_{}", s.name));
        std::fs::write(&path, metres.join("\n") + "\n").unwrap();
        let e = load(s.kind, &path, false).expect_err(s.name);
        let msg = e.to_string();
        assert!(
            matches!(
                e,
                ProfileLoadError::Profile(ProfileError::Implausible { .. })
            ),
            "{msg}"
        );
        for needle in [
            &path.display().to_string(),
            "lateral span",
            "20–500 mm",
            "check the unit",
        ] {
            assert!(msg.contains(needle), "{}: {needle}: {msg}", s.name);
        }
    }
    let s1002 = std::fs::read_to_string(shipped("profiles/MBench_S1002_v3.prw")).unwrap();
    let declared_m = s1002.replace(
        "units.len.f    = +1.000000000000000e+03",
        "units.len.f    = +1.000000000000000e+00",
    );
    assert_ne!(declared_m, s1002);
    let path = dir.join("declared_metres.prw");
    std::fs::write(&path, declared_m).unwrap();
    let msg = load(Kind::Wheel, &path, false).unwrap_err().to_string();
    assert!(msg.contains("is 129612.628 mm"), "{msg}");
    assert!(msg.contains("check the unit"), "{msg}");
}

/// The ML95-like wheel with its flange cut off (no wheel in tables/ lacks
/// one), and with its heights 1.9 times too large (a 53 mm flange; its
/// 70° flank becomes 79°, still within the trim angle).
#[test]
fn a_wheel_without_a_plausible_flange_is_refused() {
    let dir = scratch("trust_profiles_flange");
    let csv = std::fs::read_to_string(shipped("profiles/ml95_like/ml95_like_wheel.csv")).unwrap();
    let mut lines = csv.lines();
    let header = lines.next().unwrap();
    let points: Vec<(f64, f64)> = lines.map(yz).collect();
    let write = |name: &str, pts: &mut dyn Iterator<Item = (f64, f64)>| {
        let mut t = format!("{header}\n");
        for (y, z) in pts {
            t += &format!("{y:.6},{z:.6}\n");
        }
        let p = dir.join(name);
        std::fs::write(&p, t).unwrap();
        p
    };
    let no_flange = write(
        "no_flange.csv",
        &mut points.iter().copied().filter(|p| p.0 > -30.0),
    );
    let tall = write(
        "tall_flange.csv",
        &mut points.iter().map(|&(y, z)| (y, 1.9 * z)),
    );
    for (path, height) in [(no_flange, "is 1.776 mm"), (tall, "is 53.2")] {
        let e = load(Kind::Wheel, &path, false).unwrap_err();
        let msg = e.to_string();
        for needle in ["flange height", height, "10–50 mm", "check the unit"] {
            assert!(msg.contains(needle), "{needle}: {msg}");
        }
    }
}

#[test]
fn a_byte_order_mark_is_read_in_every_format() {
    let dir = scratch("trust_profiles_bom");
    for s in samples() {
        let plain = dir.join(s.name);
        let bom = dir.join(format!("bom_{}", s.name));
        std::fs::write(&plain, &s.text).unwrap();
        std::fs::write(&bom, format!("\u{feff}{}", s.text)).unwrap();
        let a = read_profile(&plain, &ImportOptions::default()).unwrap();
        let b = read_profile(&bom, &ImportOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", s.name));
        assert_eq!((a.points_m, a.lines), (b.points_m, b.lines), "{}", s.name);
        assert!(load(s.kind, &bom, false).is_ok(), "{}", s.name);
    }
    // And through a command.
    let o = run(sim().args([
        "contact",
        "--wheel",
        dir.join("bom_s1002.prw").to_str().unwrap(),
        "--rail",
        dir.join("bom_uic60.prr").to_str().unwrap(),
        // The MBench rail file carries its 1:40 already.
        "--rail-inclination",
        "0",
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn a_bad_number_names_the_file_line_and_column_in_every_format() {
    let dir = scratch("trust_profiles_number");
    for s in samples() {
        let mut lines: Vec<String> = s.text.lines().map(str::to_string).collect();
        let i = point_rows(&s)[7];
        let (y, _) = yz(&lines[i]);
        lines[i] = if s.name.ends_with(".csv") {
            format!("{y:.6},1.2.3")
        } else {
            format!("{y:.7e}\t1.2.3")
        };
        let path = dir.join(s.name);
        std::fs::write(&path, lines.join("\n") + "\n").unwrap();
        let e = read_profile(&path, &ImportOptions::default()).unwrap_err();
        assert!(
            matches!(
                e,
                ProfileImportError::NotANumber {
                    column: Some(2),
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(
            e.to_string().starts_with(&format!(
                "'{}', line {}, column 2: z: '1.2.3' is not a number",
                path.display(),
                i + 1
            )),
            "{e}"
        );
    }
}

/// The ML95-like wheel with two points swapped on its field-side tread
/// (lines 500 and 501: y = 49.5 and 50 mm).
fn zigzag_wheel(dir: &Path) -> PathBuf {
    let csv = std::fs::read_to_string(shipped("profiles/ml95_like/ml95_like_wheel.csv")).unwrap();
    let mut lines: Vec<&str> = csv.lines().collect();
    assert!(lines[499].starts_with("49.5") && lines[500].starts_with("50.0"));
    lines.swap(499, 500);
    let path = dir.join("zigzag.csv");
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    path
}

const ZIGZAG_REFUSED: &str = "line 501: the lateral coordinate turns back";
const ZIGZAG_WARNING: &str = "kept the longest usable stretch (lines 40–500, keep_longest_stretch) and dropped 94 point(s), lines 2–39, 501–556";

#[test]
fn sim_contact_refuses_or_warns() {
    let dir = scratch("trust_profiles_sim_contact");
    let wheel = zigzag_wheel(&dir);
    let contact = |extra: &[&str]| {
        run(sim()
            .args(["contact", "--wheel", wheel.to_str().unwrap(), "--rail"])
            .arg(shipped("profiles/MBench_UIC60_v3.prr"))
            // The shipped ML95-like set-up: 1:40 more on the canted file,
            // declared (a 1:20 track for the 1:20 tread).
            .args(["--rail-inclination", "1:40", "--rail-profile-cant", "1:40"])
            .args(["--wheel-radius", "0.43"])
            .args(extra))
    };
    let o = contact(&[]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.contains(&wheel.display().to_string()), "{err}");
    assert!(err.contains(ZIGZAG_REFUSED), "{err}");

    let o = contact(&["--keep-longest-stretch"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.starts_with("warning: '"), "{out}");
    assert!(out.contains(ZIGZAG_WARNING), "{out}");
    let o = contact(&["--keep-longest-stretch", "--json"]);
    let json: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("json");
    let w = json["warnings"].as_array().expect("warnings");
    assert_eq!(w.len(), 1, "{json}");
    assert!(w[0].as_str().unwrap().contains(ZIGZAG_WARNING), "{json}");
}

#[test]
fn track_preproc_contact_table_refuses_or_warns() {
    let dir = scratch("trust_profiles_contact_table");
    let wheel = zigzag_wheel(&dir);
    let table = |extra: &[&str]| {
        run(track_preproc()
            .args([
                "contact-table",
                "--wheel",
                wheel.to_str().unwrap(),
                "--rail",
            ])
            .arg(shipped("profiles/MBench_UIC60_v3.prr"))
            .args([
                "--rail-inclination",
                "1:40",
                "--rail-profile-cant",
                "1:40",
                "--wheel-radius",
                "0.43",
                "--y-range-mm",
                "3",
                "--y-step-mm",
                "1",
            ])
            .arg("-o")
            .arg(dir.join("t.h5"))
            .args(extra))
    };
    let o = table(&[]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains(ZIGZAG_REFUSED), "{}", stderr(&o));
    assert!(!dir.join("t.h5").exists());

    let o = table(&["--keep-longest-stretch"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains(ZIGZAG_WARNING), "{}", stdout(&o));
    let o = table(&["--keep-longest-stretch", "--json"]);
    let json: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("json");
    let w = &json["contact_table"]["warnings"];
    assert!(w[0].as_str().unwrap().contains(ZIGZAG_WARNING), "{json}");
}

#[test]
fn sim_run_refuses_or_warns_in_its_summary() {
    let dir = scratch("trust_profiles_sim_run");
    let wheel = zigzag_wheel(&dir);
    let vehicle = dir.join("vehicle.toml");
    let text = std::fs::read_to_string(shipped("vehicles/ml95_like_wheelset.toml"))
        .unwrap()
        .replace(
            "../profiles/ml95_like/ml95_like_wheel.csv",
            wheel.to_str().unwrap(),
        );
    std::fs::write(&vehicle, text).unwrap();
    let sim_run = |extra: &[&str]| {
        let mut c = sim();
        c.env("RAILSIM_CACHE_DIR", dir.join("cache"))
            .arg("run")
            .arg(shipped("scenes/wheelset_straight.toml"))
            .args(["--no-plots", "--quiet", "-o"])
            .arg(dir.join("run.h5"))
            .args(["--set", &format!("vehicle.file={}", vehicle.display())])
            .args(["--set", "run.distance_m=", "--set", "run.duration_s=0.01"])
            .args(extra);
        run(&mut c)
    };
    let o = sim_run(&[]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.contains(ZIGZAG_REFUSED), "{err}");
    assert!(err.contains("track.keep_longest_stretch"), "{err}");

    let o = sim_run(&["--set", "track.keep_longest_stretch=true"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains(ZIGZAG_WARNING), "{}", stdout(&o));
    let o = sim_run(&["--set", "track.keep_longest_stretch=true", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("json");
    let w = json["warnings"].as_array().expect("warnings");
    assert_eq!(w.len(), 1, "{json}");
    assert_eq!(w[0]["kind"], "input", "{json}");
    assert!(
        w[0]["message"].as_str().unwrap().contains(ZIGZAG_WARNING),
        "{json}"
    );
    // The results file says it too.
    let r = runtime::io::schema::read_results(&dir.join("run.h5")).unwrap();
    assert!(
        r.attribute_text("status")
            .is_some_and(|s| s.contains("input points dropped")),
        "{:?}",
        r.attribute_text("status")
    );
}
