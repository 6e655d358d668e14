//! The cant a rail profile carries as drawn in its file (docs/reference/05-surfaces.md §5.7).
//!
//! Some rail profile files are drawn upright (the rail's axis of symmetry
//! vertical), others already canted by the rail inclination, like the
//! Manchester benchmark's `MBench_UIC60_v3.prr` (1:40). The rail
//! inclination of a track turns the profile *as drawn*, so giving 1:40 to
//! a file that already carries 1:40 cants the rail twice (1:20 in all).
//!
//! # Method
//!
//! A standard rail head (UIC60, UIC54, 60E1, 54E1, …) is symmetric about
//! its vertical axis when upright. The profile is turned back by a trial
//! angle β and cut by horizontal chords at depths d below its top, between
//! [`CHORD_DEPTH_FROM`] and [`CHORD_DEPTH_TO`] of the depth both sides of
//! the head reach (the crown, nearly flat, makes chord ends ill-defined
//! near the top); the midpoints m(d) of the chords lie on a vertical line
//! exactly when the turned profile is symmetric. The slope dm/dd of their
//! least-squares line is driven to zero ([`detect_cant_rad`]): the root is
//! the carried cant. Only the sides' shape is used, so the file's origin
//! does not matter.
//!
//! The cant is positive when the head is turned towards the track centre,
//! the sense of the rail inclination (docs/reference/01-units-frames.md §1.6).
//! A head that does not reach [`MIN_SIDE_DEPTH_M`] on both sides (a crown
//! alone) has no sides to compare, and one whose midpoints stray more than
//! [`MAX_ASYMMETRY_M`] from a vertical line however it is turned is not
//! symmetric (worn, or not a standard head): its cant is not guessed and
//! must be declared ([`check_rail_cant`] warns).

/// A detected cant smaller than this (rad) counts as upright: half the
/// smallest inclination in use, 1:40 (atan(1/80) = 0.0125 rad). Measured
/// on the shipped UIC60 file turned upright: below 1e-6 rad.
pub const UPRIGHT_BELOW_RAD: f64 = 0.012_499_349_000_680_3;

/// Both sides of the head must reach this far below its top (m) for the
/// cant to be detected: a UIC60 or 54E1 head is 37–51 mm deep, a profile
/// of the crown alone a few millimetres.
pub const MIN_SIDE_DEPTH_M: f64 = 0.010;

/// The chords span this fraction of the depth both sides reach: from
/// [`CHORD_DEPTH_FROM`] (below the flat crown) to [`CHORD_DEPTH_TO`] (short
/// of the shallower end).
pub const CHORD_DEPTH_FROM: f64 = 0.25;
pub const CHORD_DEPTH_TO: f64 = 0.95;

/// Number of chords of the fit.
const CHORDS: usize = 64;

/// Step of the search for the turn that makes the head symmetric (rad).
pub const SEARCH_STEP_RAD: f64 = 0.01;

/// Largest RMS distance (m) of the chord midpoints from a vertical line,
/// once turned upright, for a head to count as symmetric: 0.1 mm, a tenth
/// of the 1 mm a 1:80 tilt moves them over the 40 mm deep head of a UIC60
/// and five times a profile gauge's resolution (about ±0.02 mm). The
/// shipped UIC60 file: below 1 µm.
pub const MAX_ASYMMETRY_M: f64 = 1e-4;

/// The search stays within ±this (rad): steeper than 1:5 is no rail
/// inclination (`preproc::Inclination` refuses it).
pub const MAX_CANT_RAD: f64 = 0.3;

/// Why a profile's cant could not be detected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CantDetectionError {
    #[error(
        "the profile reaches only {depth_mm:.1} mm below its top on one side of the head (at least {min_mm:.0} mm is needed to compare the two sides)"
    )]
    TooShallow { depth_mm: f64, min_mm: f64 },
    #[error("the profile has {points} points; at least 4 are needed")]
    TooFewPoints { points: usize },
    #[error("the profile holds a non-finite coordinate at point {index}")]
    NotFinite { index: usize },
    #[error(
        "no orientation within ±{max_rad} rad makes the head symmetric to 0.1 mm (not a symmetric rail head, or a worn one)"
    )]
    NotSymmetric { max_rad: f64 },
}

/// The chord midpoints of `points` (internal u, z, as ordered along the
/// outline) turned back by `beta_rad`: their least-squares slope dm/dd and
/// their RMS distance from that line (m); `Err` when the sides are too
/// shallow.
fn midline(points: &[(f64, f64)], beta_rad: f64) -> Result<(f64, f64), CantDetectionError> {
    let (sb, cb) = beta_rad.sin_cos();
    let p: Vec<(f64, f64)> = points
        .iter()
        .map(|&(u, z)| (u * cb - z * sb, u * sb + z * cb))
        .collect();
    let top = (0..p.len())
        .max_by(|&a, &b| p[a].1.total_cmp(&p[b].1))
        .unwrap_or(0);
    let z_top = p[top].1;
    let sides: [Vec<(f64, f64)>; 2] =
        [p[..=top].iter().rev().copied().collect(), p[top..].to_vec()];
    let depth = |side: &[(f64, f64)]| side.iter().map(|q| z_top - q.1).fold(0.0_f64, f64::max);
    let reach = depth(&sides[0]).min(depth(&sides[1]));
    // NaN-safe: a NaN reach is too shallow too.
    if reach.is_nan() || reach < MIN_SIDE_DEPTH_M {
        return Err(CantDetectionError::TooShallow {
            depth_mm: reach * 1e3,
            min_mm: MIN_SIDE_DEPTH_M * 1e3,
        });
    }
    // The first crossing of the level z_top − d, walking from the top
    // outwards along one side (it exists: d < reach). The chords go deeper
    // one after the other, so each side's walk resumes at the window where
    // the previous chord crossed (`from`): one pass per side, not one per
    // chord.
    let crossing = |side: &[(f64, f64)], from: &mut usize, d: f64| -> f64 {
        let level = z_top - d;
        for (i, w) in side.windows(2).enumerate().skip(*from) {
            let (a, b) = (w[0], w[1]);
            if b.1 <= level {
                *from = i;
                let t = if a.1 > b.1 {
                    (a.1 - level) / (a.1 - b.1)
                } else {
                    1.0
                };
                return a.0 + t * (b.0 - a.0);
            }
        }
        *from = side.len();
        side[side.len() - 1].0
    };
    let mut from = [0, 0];
    let chords: Vec<(f64, f64)> = (0..CHORDS)
        .map(|j| {
            let f = CHORD_DEPTH_FROM
                + (CHORD_DEPTH_TO - CHORD_DEPTH_FROM) * j as f64 / (CHORDS - 1) as f64;
            let d = f * reach;
            let left = crossing(&sides[0], &mut from[0], d);
            let right = crossing(&sides[1], &mut from[1], d);
            (d, 0.5 * (left + right))
        })
        .collect();
    let n = CHORDS as f64;
    let d_mean = chords.iter().map(|c| c.0).sum::<f64>() / n;
    let m_mean = chords.iter().map(|c| c.1).sum::<f64>() / n;
    let sdd: f64 = chords.iter().map(|c| (c.0 - d_mean).powi(2)).sum();
    let sdm: f64 = chords.iter().map(|c| (c.0 - d_mean) * (c.1 - m_mean)).sum();
    let slope = sdm / sdd;
    let rms = (chords
        .iter()
        .map(|c| (c.1 - m_mean - slope * (c.0 - d_mean)).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    Ok((slope, rms))
}

/// The cant (rad, positive turned towards the track centre) that
/// `points` — a rail profile in the internal convention (u towards the
/// track centre, z up; metres), in order along the outline — carries:
/// the angle that turns the head symmetric (module docs). The turns tried
/// are searched every [`SEARCH_STEP_RAD`] within ±[`MAX_CANT_RAD`] for a
/// change of sign of the midline's slope, the one nearest upright refined
/// by false position (Illinois); a head whose chord midpoints then stray
/// more than [`MAX_ASYMMETRY_M`] (RMS) from a vertical line is not
/// symmetric, and its cant is not guessed.
pub fn detect_cant_rad(points: &[(f64, f64)]) -> Result<f64, CantDetectionError> {
    if points.len() < 4 {
        return Err(CantDetectionError::TooFewPoints {
            points: points.len(),
        });
    }
    if let Some(index) = points
        .iter()
        .position(|p| !(p.0.is_finite() && p.1.is_finite()))
    {
        return Err(CantDetectionError::NotFinite { index });
    }
    let not_symmetric = CantDetectionError::NotSymmetric {
        max_rad: MAX_CANT_RAD,
    };
    midline(points, 0.0)?;
    let steps = (MAX_CANT_RAD / SEARCH_STEP_RAD).round() as i32;
    let slope = |b: f64| midline(points, b).map(|m| m.0).unwrap_or(f64::NAN);
    let grid: Vec<(f64, f64)> = (-steps..=steps)
        .map(|k| {
            let b = k as f64 * SEARCH_STEP_RAD;
            (b, slope(b))
        })
        .collect();
    let bracket = grid
        .windows(2)
        .filter(|w| w[0].1 * w[1].1 <= 0.0)
        .min_by(|a, b| (a[0].0 + a[1].0).abs().total_cmp(&(b[0].0 + b[1].0).abs()))
        .ok_or(not_symmetric.clone())?;
    let ((mut a, mut fa), (mut b, mut fb)) = (bracket[0], bracket[1]);
    let mut side = 0;
    let mut root = if fa == 0.0 { a } else { b };
    for _ in 0..200 {
        if fa == 0.0 || fb == 0.0 || (b - a).abs() < 1e-14 {
            break;
        }
        let c = (a * fb - b * fa) / (fb - fa);
        let fc = slope(c);
        if !fc.is_finite() {
            return Err(not_symmetric);
        }
        root = c;
        if fc == 0.0 {
            break;
        }
        if fc * fb < 0.0 {
            (a, fa) = (b, fb);
            (b, fb) = (c, fc);
            side = 0;
        } else {
            (b, fb) = (c, fc);
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    let (_, rms) = midline(points, root)?;
    if rms > MAX_ASYMMETRY_M {
        return Err(not_symmetric);
    }
    Ok(root)
}

/// Whether a cant (rad) is that of an upright rail ([`UPRIGHT_BELOW_RAD`]).
pub fn is_upright(cant_rad: f64) -> bool {
    cant_rad.abs() < UPRIGHT_BELOW_RAD
}

/// A cant (rad) as a slope "1:n" — n whole when within 0.05 of a whole
/// number, else to one decimal — and "0" for none.
pub fn slope_text(cant_rad: f64) -> String {
    let t = cant_rad.tan();
    if t.abs() < 1e-9 {
        return "0".into();
    }
    let n = 1.0 / t.abs();
    let sign = if t < 0.0 { "-" } else { "" };
    if (n - n.round()).abs() < 0.05 {
        format!("{sign}1:{:.0}", n.round())
    } else {
        format!("{sign}1:{n:.1}")
    }
}

/// The outline of a profile file's points (file convention, m: y towards
/// the field side, z down when `z_down`) in the internal convention (u
/// towards the track centre, z up), in file order.
pub fn internal_outline(points_file_m: &[[f64; 2]], z_down: bool) -> Vec<(f64, f64)> {
    let z_sign = if z_down { -1.0 } else { 1.0 };
    points_file_m
        .iter()
        .map(|p| (-p[0], z_sign * p[1]))
        .collect()
}

/// How the cant a rail profile file carries is known.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CantSource {
    /// Detected from the head's symmetry ([`detect_cant_rad`]).
    Detected,
    /// Declared by the user (`--rail-profile-cant`, `[track]
    /// rail_profile_cant`); overrides detection.
    Declared,
    /// Neither: the head cannot tell (a crown alone, an asymmetric head);
    /// the profile is taken as drawn upright, with a warning.
    Unknown,
}

impl CantSource {
    /// `detected`, `declared` or `unknown` (as stored in table files).
    pub fn name(self) -> &'static str {
        match self {
            CantSource::Detected => "detected",
            CantSource::Declared => "declared",
            CantSource::Unknown => "unknown",
        }
    }

    /// The inverse of [`Self::name`].
    pub fn from_name(name: &str) -> Option<Self> {
        [Self::Detected, Self::Declared, Self::Unknown]
            .into_iter()
            .find(|s| s.name() == name)
    }
}

/// The rail profile a table was built with: its file, the SHA-256 of the
/// file's bytes (`sha256sum` prints the same) and the cant it carries as
/// drawn. Recorded in table files (docs/reference/04-table-files.md §4.1)
/// so that a scene naming another profile is refused.
#[derive(Debug, Clone, PartialEq)]
pub struct RailProfileRecord {
    /// The file as given.
    pub file: String,
    /// SHA-256 of its bytes, 64 lowercase hex digits.
    pub sha256: String,
    /// The cant it carries as drawn (rad, positive towards the track
    /// centre); 0 when unknown.
    pub carried_cant_rad: f64,
    pub carried_cant_source: CantSource,
}

impl RailProfileRecord {
    /// The file's name without its folders (for messages).
    pub fn file_name(&self) -> &str {
        self.file.rsplit(['/', '\\']).next().unwrap_or(&self.file)
    }

    /// The first 12 hex digits of the digest (for messages).
    pub fn short_sha256(&self) -> &str {
        self.sha256.get(..12).unwrap_or(&self.sha256)
    }
}

/// SHA-256 of `bytes` as 64 lowercase hex digits.
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    sha2::Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// How the options are spelled where the user gave them, so that a
/// refusal says what to give instead.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spelling {
    /// `--rail-inclination`, `--rail-profile-cant` (`sim contact`,
    /// `track-preproc build` and `contact-table`).
    CommandLine,
    /// `[track] rail_inclination`, `[track] rail_profile_cant` (scenes).
    Scene,
    /// A scene on a table file, whose inclination is the file's: another
    /// file, built with `--rail-inclination`; `[track] rail_profile_cant`.
    SceneTables,
}

impl Spelling {
    /// The rail inclination option set to `value`.
    pub fn inclination(self, value: &str) -> String {
        match self {
            Spelling::CommandLine => format!("--rail-inclination {value}"),
            Spelling::Scene => format!("[track] rail_inclination = \"{value}\""),
            Spelling::SceneTables => {
                format!("a table file built with --rail-inclination {value}")
            }
        }
    }

    /// The option declaring the profile's carried cant, set to `value`.
    pub fn declared_cant(self, value: &str) -> String {
        match self {
            Spelling::CommandLine => format!("--rail-profile-cant {value}"),
            Spelling::Scene | Spelling::SceneTables => {
                format!("[track] rail_profile_cant = \"{value}\"")
            }
        }
    }
}

/// Why a rail profile cannot be used with a rail inclination.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RailCantError {
    /// The file cannot be read or parsed; `message` names it.
    #[error("{message}")]
    Read {
        path: std::path::PathBuf,
        message: String,
    },
    #[error(
        "double canting: the rail profile {path} already carries a cant of {carried} ({carried_rad:.4} rad, detected from the symmetry of its head), and the rail inclination {inclination} would turn it again, to {total} in all. Give {instead} to use the file's own cant, or, to add the inclination on purpose, declare the file's cant with {declare}",
        carried = slope_text(*carried_rad),
        inclination = slope_text(*inclination_rad),
        total = slope_text(carried_rad + inclination_rad),
        instead = spelling.inclination("0"),
        declare = spelling.declared_cant(&slope_text(*carried_rad)),
    )]
    DoubleCanting {
        path: std::path::PathBuf,
        carried_rad: f64,
        inclination_rad: f64,
        spelling: Spelling,
    },
}

/// A rail profile checked against the inclination it is given: its record
/// and the warnings to show (a cant that cannot be detected, a declared
/// cant the head contradicts).
#[derive(Debug, Clone, PartialEq)]
pub struct RailCantCheck {
    pub record: RailProfileRecord,
    pub warnings: Vec<String>,
}

/// Checks the rail profile `path` against the rail inclination
/// `inclination_rad` it is to be turned by (docs/reference/05-surfaces.md §5.7):
///
/// - the cant the file carries is `declared_rad` when given, else detected
///   ([`detect_cant_rad`]);
/// - a detected cant (not [upright](is_upright)) with a non-zero
///   inclination is refused: [`RailCantError::DoubleCanting`], naming the
///   file, both angles and what to give instead;
/// - a declared cant is the user's word: the inclination is added to it on
///   purpose (the ML95-like wheel's 1:20 track from the 1:40 file); a
///   detected cant that contradicts it is a warning;
/// - a cant that cannot be detected, with a non-zero inclination, is a
///   warning (the profile is taken as drawn upright).
pub fn check_rail_cant(
    path: &std::path::Path,
    bytes: &[u8],
    outline: Result<Vec<(f64, f64)>, String>,
    declared_rad: Option<f64>,
    inclination_rad: f64,
    spelling: Spelling,
) -> Result<RailCantCheck, RailCantError> {
    let outline = outline.map_err(|message| RailCantError::Read {
        path: path.to_path_buf(),
        message,
    })?;
    let detected = detect_cant_rad(&outline);
    let shown = path.display();
    let mut warnings = Vec::new();
    let (carried_cant_rad, carried_cant_source) = match (declared_rad, &detected) {
        (Some(d), found) => {
            if let Ok(found) = found
                && (is_upright(*found) != is_upright(d) || (found - d).abs() >= UPRIGHT_BELOW_RAD)
            {
                warnings.push(format!(
                    "warning: the rail profile {shown} is declared to carry a cant of {}, but its head looks canted {} (detected from its symmetry); the declared cant is used",
                    slope_text(d),
                    slope_text(*found)
                ));
            }
            (d, CantSource::Declared)
        }
        (None, Ok(found)) => {
            if !is_upright(*found) && inclination_rad != 0.0 {
                return Err(RailCantError::DoubleCanting {
                    path: path.to_path_buf(),
                    carried_rad: *found,
                    inclination_rad,
                    spelling,
                });
            }
            (*found, CantSource::Detected)
        }
        (None, Err(why)) => {
            if inclination_rad != 0.0 {
                warnings.push(format!(
                    "warning: cannot tell whether the rail profile {shown} already carries a cant ({why}); it is taken as drawn upright and turned by the rail inclination {}. If the file is canted, give {}; declare its cant with {} to silence this warning",
                    slope_text(inclination_rad),
                    spelling.inclination("0"),
                    spelling.declared_cant("0")
                ));
            }
            (0.0, CantSource::Unknown)
        }
    };
    Ok(RailCantCheck {
        record: RailProfileRecord {
            file: shown.to_string(),
            sha256: sha256_hex(bytes),
            carried_cant_rad,
            carried_cant_source,
        },
        warnings,
    })
}

/// [`check_rail_cant`] of the rail profile file `path`, read once (its
/// bytes for the digest, its points for the detection).
#[cfg(feature = "io")]
pub fn check_rail_file(
    path: &std::path::Path,
    declared_rad: Option<f64>,
    inclination_rad: f64,
    spelling: Spelling,
) -> Result<RailCantCheck, RailCantError> {
    let bytes = std::fs::read(path).map_err(|e| RailCantError::Read {
        path: path.to_path_buf(),
        message: format!("cannot read the rail profile {}: {e}", path.display()),
    })?;
    // Comments of old files may be Latin-1; numbers and keys are ASCII
    // (as `read_profile` reads them).
    let text = String::from_utf8_lossy(&bytes);
    let outline = crate::io::profile_import::parse_profile(path, &text, &Default::default())
        .map(|f| internal_outline(&f.points_m, f.z_down))
        .map_err(|e| e.to_string());
    check_rail_cant(
        path,
        &bytes,
        outline,
        declared_rad,
        inclination_rad,
        spelling,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric head, ordered along the outline from the field side:
    /// sides falling from 40 mm below the top to a corner 10 mm below it,
    /// then a crown of radius 300 mm over ±30 mm.
    fn upright_head() -> Vec<(f64, f64)> {
        let crown = |u: f64| -u * u / 0.6;
        let mut field = vec![(-0.037, -0.040), (-0.0365, -0.025), (-0.036, -0.010)];
        for k in 0..=10 {
            let u = -0.036 + 0.006 * k as f64 / 10.0;
            let t = k as f64 / 10.0;
            field.push((u, -0.010 + t * (0.010 + crown(-0.030)) * (2.0 - t)));
        }
        let mut pts = field.clone();
        for k in 1..60 {
            let u = -0.030 + 0.060 * k as f64 / 60.0;
            pts.push((u, crown(u)));
        }
        pts.extend(field.iter().rev().map(|&(u, z)| (-u, z)));
        pts
    }

    fn turned(points: &[(f64, f64)], cant_rad: f64) -> Vec<(f64, f64)> {
        let (s, c) = (-cant_rad).sin_cos();
        points
            .iter()
            .map(|&(u, z)| (u * c - z * s, u * s + z * c))
            .collect()
    }

    #[test]
    fn slope_texts() {
        assert_eq!(slope_text(0.0), "0");
        assert_eq!(slope_text((1.0_f64 / 40.0).atan()), "1:40");
        assert_eq!(slope_text(-(1.0_f64 / 20.0).atan()), "-1:20");
        assert_eq!(slope_text(0.0302), "1:33.1");
    }

    #[test]
    fn crown_alone_is_too_shallow() {
        let pts: Vec<(f64, f64)> = (0..=50)
            .map(|k| {
                let u = -0.03 + 0.06 * k as f64 / 50.0;
                (u, -u * u / 0.6)
            })
            .collect();
        assert!(matches!(
            detect_cant_rad(&pts),
            Err(CantDetectionError::TooShallow { .. })
        ));
    }

    #[test]
    fn synthetic_head_upright_and_turned() {
        let head = upright_head();
        assert!(detect_cant_rad(&head).unwrap().abs() < 1e-9);
        for cant in [(1.0_f64 / 40.0).atan(), (1.0_f64 / 20.0).atan(), -0.02] {
            let found = detect_cant_rad(&turned(&head, cant)).unwrap();
            assert!((found - cant).abs() < 1e-6, "{cant} → {found}");
        }
    }

    #[cfg(feature = "io")]
    fn shipped_outline(rel: &str) -> Vec<(f64, f64)> {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(rel);
        let f = crate::io::profile_import::read_profile(&path, &Default::default()).unwrap();
        internal_outline(&f.points_m, f.z_down)
    }

    #[cfg(feature = "io")]
    #[test]
    fn shipped_uic60_carries_1_in_40() {
        let mbench = shipped_outline("tables/profiles/MBench_UIC60_v3.prr");
        let found = detect_cant_rad(&mbench).unwrap();
        let upright = detect_cant_rad(&turned(&mbench, -found)).unwrap();
        let steep = detect_cant_rad(&turned(&mbench, (1.0_f64 / 20.0).atan() - found)).unwrap();
        // Drawn as 1:40 to a few µrad, symmetric to below 1 µm once upright.
        assert!((found - (1.0_f64 / 40.0).atan()).abs() < 1e-5, "{found}");
        let (slope, rms) = midline(&mbench, found).unwrap();
        assert!(slope.abs() < 1e-9 && rms < 1e-6, "{slope} {rms}");
        assert!(upright.abs() < 1e-6, "{upright}");
        assert!((steep - (1.0_f64 / 20.0).atan()).abs() < 1e-5, "{steep}");
    }

    fn check(
        points: &[(f64, f64)],
        declared: Option<f64>,
        inclination: f64,
    ) -> Result<RailCantCheck, RailCantError> {
        check_rail_cant(
            std::path::Path::new("r.prr"),
            b"abc",
            Ok(points.to_vec()),
            declared,
            inclination,
            Spelling::Scene,
        )
    }

    #[test]
    fn double_canting_refused_declared_allowed() {
        let i40 = (1.0_f64 / 40.0).atan();
        let canted = turned(&upright_head(), i40);
        let e = check(&canted, None, i40).unwrap_err().to_string();
        for part in [
            "double canting",
            "r.prr",
            "1:40",
            "1:20 in all",
            "[track] rail_inclination = \"0\"",
            "[track] rail_profile_cant = \"1:40\"",
        ] {
            assert!(e.contains(part), "{part}: {e}");
        }
        // The file's own cant: fine, recorded as detected.
        let ok = check(&canted, None, 0.0).unwrap();
        assert_eq!(ok.record.carried_cant_source, CantSource::Detected);
        assert!((ok.record.carried_cant_rad - i40).abs() < 1e-6);
        assert!(ok.warnings.is_empty());
        // An upright file with the inclination: fine.
        assert!(
            check(&upright_head(), None, i40)
                .unwrap()
                .warnings
                .is_empty()
        );
        // Declared: added on purpose, no warning when the head agrees.
        let on_purpose = check(&canted, Some(i40), i40).unwrap();
        assert_eq!(on_purpose.record.carried_cant_source, CantSource::Declared);
        assert!(on_purpose.warnings.is_empty(), "{:?}", on_purpose.warnings);
        // The digest of the bytes (sha256sum of "abc").
        assert_eq!(
            ok.record.sha256,
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }

    #[test]
    fn contradicted_declaration_and_unknown_cant_are_warned() {
        let i40 = (1.0_f64 / 40.0).atan();
        let canted = turned(&upright_head(), i40);
        let w = check(&canted, Some(0.0), i40).unwrap().warnings;
        assert!(
            w.len() == 1 && w[0].contains("declared to carry a cant of 0") && w[0].contains("1:40"),
            "{w:?}"
        );
        let crown: Vec<(f64, f64)> = (0..=50)
            .map(|k| {
                let u = -0.03 + 0.06 * k as f64 / 50.0;
                (u, -u * u / 0.6)
            })
            .collect();
        let c = check(&crown, None, i40).unwrap();
        assert_eq!(c.record.carried_cant_source, CantSource::Unknown);
        assert!(
            c.warnings.len() == 1 && c.warnings[0].contains("cannot tell"),
            "{:?}",
            c.warnings
        );
        assert!(check(&crown, None, 0.0).unwrap().warnings.is_empty());
    }
}
