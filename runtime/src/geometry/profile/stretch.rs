//! The usable stretch of a profile: the points the contact model describes
//! as a function z(u), and the one rule that decides which points those are
//! (docs/reference/05-surfaces.md §5.3), for every file format alike.
//!
//! # The rule
//!
//! A segment between two consecutive points (in the internal convention,
//! `u` increasing along the profile) is **usable** when it advances in `u`
//! and is no steeper than the trim angle. The usable stretch runs from the
//! first usable segment to the last one.
//!
//! * **Inside** the stretch every segment must be usable. A point whose
//!   lateral coordinate goes back (a loop, two points swapped), repeats (a
//!   vertical step) or a face steeper than the trim angle between usable
//!   parts is refused, naming the file line of the first offending point
//!   (of a refused pair of consecutive points, the one later in the file).
//! * **Outside** it, at each end, the profile must leave the stretch
//!   through a **face**: the segment next to the stretch is steeper than the
//!   trim angle (a vertical or an overhanging face included). What follows
//!   a face is trimmed: a wheel's flange back and outer faces, a rail's
//!   sides and web. A flat step back in `u` next to the stretch is a fold
//!   back, not a face, and is refused like one inside.
//!
//! So the points dropped are always steep faces at the ends and what lies
//! beyond them; a profile whose interior breaks is never cut down silently.
//!
//! # Keeping the longest stretch
//!
//! With `keep_longest_stretch` a profile the rule refuses is built from the
//! longest run of usable segments instead (what this toolkit did silently
//! before), and the result carries a [`ProfileWarning`] naming the refusal
//! and every dropped line, for the caller to show. Even then, a profile of
//! which more than half the points would be dropped is refused. A profile
//! the rule accepts is built the same way with or without the option, and
//! without a warning.

use std::path::{Path, PathBuf};

use super::{FileMapping, ProfileError};

/// How one segment between consecutive points runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Step {
    /// Advances in u, no steeper than the trim angle.
    Usable,
    /// Advances in u, steeper than the trim angle.
    Steep,
    /// Same u (a vertical step).
    Repeat,
    /// Goes back in u.
    Back,
}

fn step(a: (f64, f64), b: (f64, f64), max_slope: f64) -> Step {
    let (du, dz) = (b.0 - a.0, b.1 - a.1);
    if du > 0.0 {
        if dz.abs() <= max_slope * du {
            Step::Usable
        } else {
            Step::Steep
        }
    } else if du == 0.0 {
        Step::Repeat
    } else {
        Step::Back
    }
}

/// A face: steeper than the trim angle, whichever way it runs in u (a
/// vertical or an overhanging face included).
fn is_face(a: (f64, f64), b: (f64, f64), max_slope: f64) -> bool {
    (b.1 - a.1).abs() > max_slope * (b.0 - a.0).abs()
}

/// A profile built from fewer than all of its usable points because the
/// caller asked to keep the longest usable stretch
/// (`keep_longest_stretch`): what was refused, what was kept, and every
/// line that was dropped. Its [`Display`](std::fmt::Display) is the
/// warning to show.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileWarning {
    /// The profile file.
    pub path: PathBuf,
    /// Why the rule refused the profile (the error it would have been).
    pub refused: String,
    /// File lines (or point numbers) of the first and the last point kept.
    pub kept: [usize; 2],
    /// The dropped points as ranges of file lines (or point numbers),
    /// each `[first, last]`, in the order of the profile.
    pub dropped: Vec<[usize; 2]>,
    /// Number of points dropped.
    pub dropped_points: usize,
    /// `true` when `kept` and `dropped` are file lines, `false` when they
    /// are point numbers (points not read from a file).
    pub file_lines: bool,
}

impl std::fmt::Display for ProfileWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let unit = if self.file_lines { "lines" } else { "points" };
        let ranges: Vec<String> = self
            .dropped
            .iter()
            .map(|[a, b]| {
                if a == b {
                    a.to_string()
                } else {
                    format!("{a}–{b}")
                }
            })
            .collect();
        write!(
            f,
            "warning: '{}': kept the longest usable stretch ({unit} {}–{}, keep_longest_stretch) and dropped {} point(s), {unit} {}; without the option the profile is refused: {}",
            self.path.display(),
            self.kept[0],
            self.kept[1],
            self.dropped_points,
            ranges.join(", "),
            self.refused
        )
    }
}

/// The points kept: indices `first..=last` of the oriented points, and
/// the warning when the longest stretch was kept instead of refusing.
pub(crate) struct Stretch {
    pub first: usize,
    pub last: usize,
    pub warning: Option<ProfileWarning>,
}

/// Names points in messages: by file line when the lines are known.
pub(crate) struct PointNames<'a> {
    /// File line of each oriented point, or empty.
    pub lines: &'a [usize],
    /// Whether the oriented order is the reverse of the given order.
    pub reversed: bool,
    pub n: usize,
}

impl PointNames<'_> {
    /// The file line, or the 1-based number in the given order, of oriented
    /// point `i`.
    pub fn number(&self, i: usize) -> usize {
        if self.has_lines() {
            self.lines[i]
        } else {
            self.position(i)
        }
    }

    /// The 1-based number in the given order of oriented point `i`.
    pub fn position(&self, i: usize) -> usize {
        if self.reversed { self.n - i } else { i + 1 }
    }

    fn has_lines(&self) -> bool {
        self.lines.len() == self.n
    }

    fn name(&self, i: usize) -> String {
        let word = if self.has_lines() { "line" } else { "point" };
        format!("{word} {}", self.number(i))
    }
}

/// One break of the rule: the segment `k → k+1` (oriented indices).
struct Defect {
    k: usize,
    step: Step,
    /// Next to the stretch, outside it.
    at_end: bool,
}

/// Choose the usable stretch of `pts` (oriented: u increasing overall).
pub(crate) fn usable_stretch(
    path: &Path,
    pts: &[(f64, f64)],
    names: &PointNames<'_>,
    mapping: &FileMapping,
    trim_angle_rad: f64,
    keep_longest_stretch: bool,
) -> Result<Stretch, ProfileError> {
    let max_slope = trim_angle_rad.tan();
    let steps: Vec<Step> = pts
        .windows(2)
        .map(|w| step(w[0], w[1], max_slope))
        .collect();
    let too_short = || ProfileError::Invalid {
        path: path.to_path_buf(),
        rule: format!(
            "no usable stretch of at least 4 points where the profile is a function of the lateral coordinate with faces flatter than {:.0}°",
            trim_angle_rad.to_degrees()
        ),
    };
    let (Some(first), Some(last)) = (
        steps.iter().position(|s| *s == Step::Usable),
        steps.iter().rposition(|s| *s == Step::Usable),
    ) else {
        return Err(too_short());
    };

    // Breaks inside the stretch, and fold-backs next to it.
    let mut defects: Vec<Defect> = (first..=last)
        .filter(|&k| steps[k] != Step::Usable)
        .map(|k| Defect {
            k,
            step: steps[k],
            at_end: false,
        })
        .collect();
    for k in [first.checked_sub(1), Some(last + 1)].into_iter().flatten() {
        if k < steps.len() && !is_face(pts[k], pts[k + 1], max_slope) {
            defects.push(Defect {
                k,
                step: steps[k],
                at_end: true,
            });
        }
    }
    // The first offending point in the file: of each refused pair, the
    // point later in the file.
    let offending = |d: &Defect| {
        let (a, b) = (names.number(d.k), names.number(d.k + 1));
        if a > b {
            (d.k, d.k + 1)
        } else {
            (d.k + 1, d.k)
        }
    };
    let Some(defect) = defects.iter().min_by_key(|d| names.number(offending(d).0)) else {
        if last + 2 - first < 4 {
            return Err(too_short());
        }
        return Ok(Stretch {
            first,
            last: last + 1,
            warning: None,
        });
    };

    let (at, before) = offending(defect);
    let refusal = refusal(
        path,
        pts,
        names,
        mapping,
        defect,
        (at, before),
        (first, last + 1),
        trim_angle_rad,
    );
    if !keep_longest_stretch {
        return Err(refusal);
    }
    // Keep the longest run of usable segments.
    let (mut best, mut run_start) = ((0usize, 0usize), None);
    for (k, step) in steps.iter().enumerate() {
        match (*step == Step::Usable, run_start) {
            (true, None) => run_start = Some(k),
            (false, Some(start)) => {
                if k - start > best.1 - best.0 {
                    best = (start, k);
                }
                run_start = None;
            }
            _ => {}
        }
    }
    if let Some(start) = run_start
        && steps.len() - start > best.1 - best.0
    {
        best = (start, steps.len());
    }
    let (first, last) = (best.0, best.1); // points first..=last
    if last - first < 3 {
        return Err(too_short());
    }
    let dropped_points = pts.len() - (last + 1 - first);
    if dropped_points * 2 > pts.len() {
        return Err(ProfileError::Invalid {
            path: path.to_path_buf(),
            rule: format!(
                "only {} of {} points form the longest usable stretch (keep_longest_stretch); more than half would be dropped. Without the option: {}",
                last + 1 - first,
                pts.len(),
                rule_of(&refusal)
            ),
        });
    }
    let range = |a: usize, b: usize| {
        let (x, y) = (names.number(a), names.number(b));
        [x.min(y), x.max(y)]
    };
    let mut dropped = Vec::new();
    if first > 0 {
        dropped.push(range(0, first - 1));
    }
    if last + 1 < pts.len() {
        dropped.push(range(last + 1, pts.len() - 1));
    }
    dropped.sort();
    Ok(Stretch {
        first,
        last,
        warning: Some(ProfileWarning {
            path: path.to_path_buf(),
            refused: rule_of(&refusal),
            kept: range(first, last),
            dropped,
            dropped_points,
            file_lines: names.has_lines(),
        }),
    })
}

/// How to keep the longest stretch, at the end of a refusal.
const KEEP_HINT: &str = ". Fix the file, or keep the longest usable stretch (scene key track.keep_longest_stretch, or --keep-longest-stretch), which drops the rest with a warning";

/// The refusal, named by its line, without [`KEEP_HINT`] (for the warning
/// when the option is set).
fn rule_of(e: &ProfileError) -> String {
    match e {
        ProfileError::AtPoint { rule, line, .. } => {
            let rule = rule.strip_suffix(KEEP_HINT).unwrap_or(rule);
            match line {
                Some(l) => format!("line {l}: {rule}"),
                None => rule.to_string(),
            }
        }
        other => other.to_string(),
    }
}

/// The error for `defect`, naming the offending point `at` and the point
/// `before` it in the file.
#[allow(clippy::too_many_arguments)]
fn refusal(
    path: &Path,
    pts: &[(f64, f64)],
    names: &PointNames<'_>,
    mapping: &FileMapping,
    defect: &Defect,
    (at, before): (usize, usize),
    (first, last): (usize, usize),
    trim_angle_rad: f64,
) -> ProfileError {
    let file_mm = |i: usize| {
        let (y, z) = mapping.to_file(pts[i].0, pts[i].1);
        (y * 1e3, z * 1e3)
    };
    let (y, z) = file_mm(at);
    let (y0, z0) = file_mm(before);
    let what = match defect.step {
        Step::Back => format!(
            "the lateral coordinate turns back: file y = {y:.3} mm after {y0:.3} mm on {} (a loop, or points out of order)",
            names.name(before)
        ),
        Step::Repeat => format!(
            "file y = {y:.3} mm repeats the y of {} (z = {z:.3} mm after {z0:.3} mm: a vertical step)",
            names.name(before)
        ),
        Step::Steep | Step::Usable => {
            let (du, dz) = (pts[at].0 - pts[before].0, pts[at].1 - pts[before].1);
            format!(
                "the step from {} (file y = {y0:.3}, z = {z0:.3} mm) to here (y = {y:.3}, z = {z:.3} mm) is at {:.1}°, steeper than {:.0}° (a face that steep puts the contact normal within {:.0}° of horizontal, outside the contact model)",
                names.name(before),
                dz.abs().atan2(du.abs()).to_degrees(),
                trim_angle_rad.to_degrees(),
                90.0 - trim_angle_rad.to_degrees()
            )
        }
    };
    // The stretch in file order.
    let (a, b) = if names.number(first) <= names.number(last) {
        (first, last)
    } else {
        (last, first)
    };
    let stretch = format!(
        "{} to {}, file y = {:.3} to {:.3} mm",
        names.name(a),
        names.number(b),
        file_mm(a).0,
        file_mm(b).0
    );
    let angle = trim_angle_rad.to_degrees();
    let place = if defect.at_end {
        format!(
            "next to the end of the usable stretch ({stretch}), where only a face steeper than {angle:.0}° may end a profile"
        )
    } else {
        format!(
            "inside the usable stretch ({stretch}); only faces steeper than {angle:.0}° at the ends of a profile are trimmed"
        )
    };
    ProfileError::AtPoint {
        path: path.to_path_buf(),
        line: names.has_lines().then(|| names.number(at)),
        point: names.position(at),
        rule: format!("{what}, {place}{KEEP_HINT}"),
    }
}

#[cfg(test)]
mod tests {
    use super::super::{ProfileError, RailProfile, RailProfileOptions};
    use std::path::Path;

    /// A rail head (file convention: y towards the field side, z up, m):
    /// a 300 mm crown from y = −35 to 35 mm every 0.5 mm, and at both ends
    /// a side face at 87° for 16 mm, as rail files draw them (past the gauge
    /// point 14 mm below the top).
    fn rail() -> Vec<[f64; 2]> {
        let head = |y: f64| -y * y / 0.6;
        let side = |y0: f64, dir: f64| {
            (1..=32).map(move |k| {
                let d = 0.0005 * k as f64;
                let a = 87f64.to_radians();
                [y0 + dir * d * a.cos(), head(y0) - d * a.sin()]
            })
        };
        let mut pts: Vec<[f64; 2]> = side(-0.035, -1.0).collect::<Vec<_>>();
        pts.reverse();
        pts.extend((0..=140).map(|k| {
            let y = -0.035 + 0.0005 * k as f64;
            [y, head(y)]
        }));
        pts.extend(side(0.035, 1.0));
        pts
    }

    /// File lines of the points: a header line, then one point a line.
    fn lines(n: usize) -> Vec<usize> {
        (2..n + 2).collect()
    }

    fn build(pts: &[[f64; 2]], keep: bool) -> Result<RailProfile, ProfileError> {
        RailProfile::from_points(
            Path::new("r.csv"),
            pts,
            &lines(pts.len()),
            false,
            RailProfileOptions {
                keep_longest_stretch: keep,
                ..Default::default()
            },
        )
    }

    /// The line of point `i` (0-based) in [`lines`].
    fn line_of(i: usize) -> usize {
        i + 2
    }

    #[test]
    fn steep_faces_at_the_ends_are_trimmed_without_a_warning() {
        let r = build(&rail(), false).unwrap();
        assert!(r.warnings().is_empty());
        // The kept head: between the faces, a little beyond ±35 mm (the
        // first face segment is the first one steeper than 80°).
        let placed = r
            .placed(&super::super::RailPlacement {
                gauge_m: 1.435,
                rail_spacing_m: 1.505,
                inclination_rad: 0.0,
            })
            .unwrap();
        let (u0, u1) = placed.head().domain_m();
        assert!((u1 - u0 - 0.070).abs() < 1e-9, "{u0} {u1}");
        // The same with the option: nothing to keep longer, no warning.
        assert!(build(&rail(), true).unwrap().warnings().is_empty());
    }

    /// (what was done to the rail, the line expected, a word of the rule)
    fn broken() -> Vec<(&'static str, Vec<[f64; 2]>, usize, &'static str)> {
        let base = rail();
        let mut cases = Vec::new();
        // Two points swapped in the middle of the head: 100 and 101.
        let mut p = base.clone();
        p.swap(110, 111);
        cases.push(("zig-zag", p, line_of(111), "turns back"));
        // A loop: the profile runs 2 mm on, back 3 mm above, and on again.
        let mut p = base.clone();
        let (y, z) = (p[100][0], p[100][1]);
        let lp = [
            [y + 0.0005, z + 0.0002],
            [y - 0.0010, z + 0.0004],
            [y - 0.0020, z + 0.0002],
        ];
        p.splice(101..101, lp);
        cases.push(("loop", p, line_of(102), "turns back"));
        // The same y twice (z 0.1 mm apart).
        let mut p = base.clone();
        p[81][0] = p[80][0];
        cases.push(("repeated y", p, line_of(81), "repeats"));
        // A step steeper than 80° inside the head.
        let mut p = base.clone();
        for q in p.iter_mut().skip(70) {
            q[1] -= 0.003;
        }
        p[70][0] = p[69][0] + 1e-5;
        cases.push(("steep step", p, line_of(70), "steeper than 80°"));
        // Two points swapped next to an end of the head (the last two).
        let mut p = base[..173].to_vec();
        p.swap(171, 172);
        cases.push(("swap at the end", p, line_of(172), "next to the end"));
        cases
    }

    #[test]
    fn a_profile_that_breaks_inside_is_refused_at_its_line() {
        for (case, pts, line, word) in broken() {
            let e = build(&pts, false).expect_err(case);
            assert_eq!(e.line(), Some(line), "{case}: {e}");
            let msg = e.to_string();
            assert!(msg.starts_with(&format!("'r.csv', line {line}: ")), "{msg}");
            assert!(msg.contains(word), "{case}: {msg}");
            assert!(msg.contains("--keep-longest-stretch"), "{msg}");
        }
    }

    #[test]
    fn the_first_offending_point_in_the_file_is_named_whatever_the_order() {
        // The zig-zag, the points written from the other end: the old
        // points 110 and 111 are now n − 1 − 111 and n − 1 − 110, the later
        // one in the file named.
        let (_, mut pts, _, _) = broken().swap_remove(0);
        pts.reverse();
        let e = build(&pts, false).unwrap_err();
        let n = pts.len();
        assert_eq!(e.line(), Some(line_of(n - 1 - 110)), "{e}");
        // Without file lines the points are numbered.
        let (_, pts, _, _) = broken().swap_remove(0);
        let e = RailProfile::from_points(
            Path::new("r"),
            &pts,
            &[],
            false,
            RailProfileOptions::default(),
        )
        .unwrap_err();
        assert_eq!(e.line(), None);
        assert!(e.to_string().starts_with("'r', point 112: "), "{e}");
    }

    #[test]
    fn keep_longest_stretch_warns_naming_the_dropped_lines() {
        // Points 150 and 151 swapped (the head runs from 32 to 172).
        let mut pts = rail();
        pts.swap(150, 151);
        let e = build(&pts, false).unwrap_err();
        assert_eq!(e.line(), Some(line_of(151)));
        let r = build(&pts, true).unwrap();
        let [w] = r.warnings() else {
            panic!("one warning expected: {:?}", r.warnings())
        };
        // The longest run: the head from its start to the swapped pair;
        // dropped: the near face, and the rest of the head from 151 on
        // with the far face.
        assert_eq!(w.kept, [line_of(32), line_of(150)]);
        assert_eq!(
            w.dropped,
            vec![[line_of(0), line_of(31)], [line_of(151), line_of(204)]]
        );
        assert_eq!(w.dropped_points, 32 + 54);
        let text = w.to_string();
        for needle in [
            "warning: 'r.csv'",
            "kept the longest usable stretch (lines 34–152",
            "dropped 86 point(s), lines 2–33, 153–206",
            "line 153: the lateral coordinate turns back",
        ] {
            assert!(text.contains(needle), "{needle}: {text}");
        }
    }

    #[test]
    fn keep_longest_stretch_still_refuses_to_drop_more_than_half() {
        let mut pts = rail();
        pts.swap(70, 71);
        pts.swap(130, 131);
        let e = build(&pts, true).unwrap_err();
        assert!(e.to_string().contains("more than half"), "{e}");
        assert!(e.to_string().contains("turns back"), "{e}");
    }
}
