//! SIMPACK `.prw` (wheel) / `.prr` (rail) profile files.
//!
//! Layout: `!` comments (outside quoted strings), blank lines, and
//!
//! ```text
//! header.begin
//!   version = 1             ! the only version this reader knows
//!   type    = 1             ! 0 = rail, 1 = wheel
//! header.end
//! spline.begin
//!   approx.smooth = 0       file = '…'     file.mtime = 0   comment = '…'
//!   type = 0                ! original data file type (not used)
//!   point.dist.min = 0      shift.y = 0    shift.z = 0      rotate = 0
//!   bound.y.min = 1         bound.y.max = 0   bound.z.min = 1   bound.z.max = 0
//!   mirror.y = 0            mirror.z = 0   inversion = 0
//!   units.len = 'mm'        units.ang = 'rad'   ! names, optional
//!   units.len.f = 1000      units.ang.f = 1     ! l[file]/l[m], a[file]/a[rad]
//!   point.begin
//!     y z [weight]          ! one point a row, file length units
//!   point.end
//! spline.end
//! ```
//!
//! Keys and block names are case-insensitive; an unknown key, a key given
//! twice, a key outside `header`/`spline` or inside `point`, and badly
//! nested blocks are errors (an unknown key may be a transform this reader
//! would otherwise silently skip).
//!
//! See [`SimpackSettings`] for the processing order.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::path::Path;

use super::{ProfileImportError as E, ProfileKind, RawPoint, RawProfile, number};

/// The processing a SIMPACK file asks for, as applied by the reader.
///
/// # Order (steps numbered as in the files' own comments)
///
/// All steps work in the file's length unit; the points are converted to
/// metres last.
///
/// 1. `point.dist.min` (≥ 0): walking the points in file order, a point
///    closer than `point.dist.min` (Euclidean distance in the y-z plane) to
///    the last point kept is dropped; 0 = no filtering.
/// 2. `shift.y`, `shift.z` are added to y, z.
/// 3. `rotate` / `units.ang.f` (rad) rotates the points about the x axis
///    through the origin: y' = y cos φ − z sin φ, z' = y sin φ + z cos φ
///    (a right-handed rotation about x for the SIMPACK profile axes: x
///    along the track, y lateral, z down).
/// 4. Bounds, each pair active only if min < max (the benchmark files write
///    min = 1 > max = 0 to switch them off): points with y outside
///    [`bound.y.min`, `bound.y.max`] are removed; z is clipped to
///    [`bound.z.min`, `bound.z.max`].
/// 5. `mirror.y = 1` negates y, `mirror.z = 1` negates z.
/// 6. `inversion = 1` reverses the order of the points.
/// 7. `units.len.f` (l\[file\] / l\[m\]) converts to metres: divide by it.
///
/// The result is in SIMPACK's profile coordinate system: z **down**, y
/// lateral; for the Manchester benchmark files the flange / gauge face ends
/// up at negative y.
///
/// # Source and assumptions
///
/// The order and the meaning of the keys are those written in the comments
/// of SIMPACK-generated files ("1: Minimum point distance", "2: y shift",
/// "3: Rotation angle about x", "4: y boundary min", "5: y mirror mode",
/// "6: Inversion of data order", "7: Unit factor for lengths (l\[User\] /
/// l\[m\])"). SIMPACK's own manual was not available; where the comments are
/// silent this reader follows the open-source CONTACT code by E. Vollebregt
/// (github `eve70a/CONTACT`, Apache-2.0: `src/m_profile.f90`,
/// `read_simpack_profile` and `filter_close_points`, and
/// `matlab/read_simpack.m`), which reads the same files:
///
/// * the distance of step 1 is Euclidean and measured to the last point
///   kept (CONTACT's Fortran reader; its older MATLAB reader uses |Δy|);
/// * the rotation sign of step 3 is CONTACT MATLAB's
///   (`points * [cos −sin; sin cos]ᵀ`); CONTACT's Fortran reader refuses
///   non-zero rotations, so this sign is the least certain item: check a
///   rotated file against SIMPACK before relying on it;
/// * bound.y removes points while bound.z clips z to the interval (both
///   CONTACT readers), and a pair is active only when min < max;
/// * missing keys take the values 0 (shifts, rotation, distance, flags) and
///   1 (`units.len.f`, i.e. metres; `units.ang.f`, i.e. radians). If only
///   `units.len` / `units.ang` is given, the factor is derived from the
///   name (m, dm, cm, mm, um, km; rad, mrad, deg); if both are given they
///   must agree.
/// * Unlike CONTACT, no automatic mirroring, reordering or zig-zag filtering
///   is done: the file's settings are applied as written.
#[derive(Debug, Clone, PartialEq)]
pub struct SimpackSettings {
    /// Header `version` (this reader knows 1), if given.
    pub version: Option<i64>,
    /// Header `type`: 0 rail, 1 wheel, if given.
    pub header_type: Option<i64>,
    /// `approx.smooth`: SIMPACK's smoothing value for an approximating spline
    /// (0 = interpolating). Not applied here; reported for the caller.
    pub approx_smooth: f64,
    /// `file`: the original data file named by the file.
    pub source_file: Option<String>,
    /// Step 1 (file length unit).
    pub point_dist_min: f64,
    /// Step 2 (file length unit).
    pub shift_y: f64,
    /// Step 2 (file length unit).
    pub shift_z: f64,
    /// Step 3 (rad) (`rotate / units.ang.f`).
    pub rotate_rad: f64,
    /// Step 4, when active: (min, max) (file length unit).
    pub bound_y: Option<(f64, f64)>,
    /// Step 4, when active: (min, max) (file length unit).
    pub bound_z: Option<(f64, f64)>,
    /// Step 5.
    pub mirror_y: bool,
    /// Step 5.
    pub mirror_z: bool,
    /// Step 6.
    pub inversion: bool,
    /// Step 7: file length units per metre (1000 = mm).
    pub units_len_f: f64,
    /// File angle units per radian.
    pub units_ang_f: f64,
    /// Points removed by step 1.
    pub removed_by_point_dist_min: usize,
    /// Points removed by `bound.y`.
    pub removed_by_bound_y: usize,
}

const HEADER_KEYS: &[&str] = &["version", "type"];
const SPLINE_KEYS: &[&str] = &[
    "approx.smooth",
    "file",
    "file.mtime",
    "comment",
    "type",
    "point.dist.min",
    "shift.y",
    "shift.z",
    "rotate",
    "bound.y.min",
    "bound.y.max",
    "bound.z.min",
    "bound.z.max",
    "mirror.y",
    "mirror.z",
    "inversion",
    "units.len",
    "units.ang",
    "units.len.f",
    "units.ang.f",
];

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Block {
    Outside,
    Header,
    Spline,
    Point,
}

impl Block {
    fn name(self) -> &'static str {
        match self {
            Block::Outside => "outside",
            Block::Header => "header",
            Block::Spline => "spline",
            Block::Point => "point",
        }
    }
}

/// A `key = value` as written, with its line.
#[derive(Debug, Clone)]
struct Entry {
    value: String,
    line: usize,
}

/// Keys of one block.
#[derive(Debug, Default)]
struct Keys(HashMap<String, Entry>);

impl Keys {
    fn get(&self, key: &str) -> Option<&Entry> {
        self.0.get(key)
    }
}

pub(super) fn parse(
    path: &Path,
    text: &str,
    ext_kind: Option<ProfileKind>,
) -> Result<RawProfile, E> {
    let syntax = |line: usize, rule: String| E::Syntax {
        path: path.to_path_buf(),
        line,
        rule,
    };

    let mut block = Block::Outside;
    // Line where each block was opened / closed (None = not seen).
    let mut header_begin = None;
    let mut spline_begin = None;
    let mut spline_end = None;
    let mut point_begin = None;
    let mut point_end = None;
    let mut header = Keys::default();
    let mut spline = Keys::default();
    let mut points: Vec<RawPoint> = Vec::new();
    let mut last_line = 0;

    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        last_line = line;
        let s = strip_comment(raw).trim();
        if s.is_empty() {
            continue;
        }

        if let Some((k, v)) = s.split_once('=') {
            let key = k.trim().to_ascii_lowercase();
            let value = unquote(v.trim()).map_err(|rule| syntax(line, rule))?;
            let (keys, known) = match block {
                Block::Header => (&mut header, HEADER_KEYS),
                Block::Spline => (&mut spline, SPLINE_KEYS),
                Block::Outside => {
                    return Err(syntax(
                        line,
                        format!(
                            "'{key} = …' outside a block (keys belong in 'header.begin … header.end' or 'spline.begin … spline.end')"
                        ),
                    ));
                }
                Block::Point => {
                    return Err(syntax(
                        line,
                        format!(
                            "'{key} = …' inside the point block (expected rows 'y z [weight]' or 'point.end')"
                        ),
                    ));
                }
            };
            if !known.contains(&key.as_str()) {
                return Err(E::UnknownKey {
                    path: path.to_path_buf(),
                    line,
                    block: block.name().to_string(),
                    key,
                    known: known.join(", "),
                });
            }
            if let Some(first) = keys.get(&key) {
                return Err(E::DuplicateKey {
                    path: path.to_path_buf(),
                    line,
                    key,
                    first_line: first.line,
                });
            }
            keys.0.insert(key, Entry { value, line });
            continue;
        }

        let lower = s.to_ascii_lowercase();
        let marker = if let Some(name) = lower.strip_suffix(".begin") {
            Some((name.trim(), true))
        } else {
            lower.strip_suffix(".end").map(|name| (name.trim(), false))
        };
        if let Some((name, begin)) = marker {
            let nesting = |rule: &str| syntax(line, format!("'{s}': {rule}"));
            match (name, begin) {
                ("header", true) => {
                    if block != Block::Outside {
                        return Err(nesting(&format!(
                            "blocks do not nest (inside the {} block)",
                            block.name()
                        )));
                    }
                    if let Some(first) = header_begin {
                        return Err(nesting(&format!(
                            "a second header block (the first began on line {first})"
                        )));
                    }
                    header_begin = Some(line);
                    block = Block::Header;
                }
                ("spline", true) => {
                    if block != Block::Outside {
                        return Err(nesting(&format!(
                            "blocks do not nest (inside the {} block)",
                            block.name()
                        )));
                    }
                    if let Some(first) = spline_begin {
                        return Err(nesting(&format!(
                            "a second spline block (the first began on line {first}); one profile a file"
                        )));
                    }
                    spline_begin = Some(line);
                    block = Block::Spline;
                }
                ("point", true) => {
                    if block != Block::Spline {
                        return Err(nesting(&format!(
                            "the point block must be inside the spline block (found in the {} block)",
                            block.name()
                        )));
                    }
                    if let Some(first) = point_begin {
                        return Err(nesting(&format!(
                            "a second point block (the first began on line {first})"
                        )));
                    }
                    point_begin = Some(line);
                    block = Block::Point;
                }
                ("header", false) | ("spline", false) | ("point", false) => {
                    let expected = match name {
                        "header" => Block::Header,
                        "spline" => Block::Spline,
                        _ => Block::Point,
                    };
                    if block != expected {
                        return Err(nesting(&format!(
                            "closes a block that is not open (current: {} block)",
                            block.name()
                        )));
                    }
                    match expected {
                        Block::Point => {
                            point_end = Some(line);
                            block = Block::Spline;
                        }
                        Block::Spline => {
                            spline_end = Some(line);
                            block = Block::Outside;
                        }
                        _ => block = Block::Outside,
                    }
                }
                _ => {
                    return Err(nesting("unknown block (known: header, spline, point)"));
                }
            }
            continue;
        }

        if block == Block::Point {
            points.push(point_row(path, line, s)?);
            continue;
        }
        return Err(syntax(
            line,
            format!(
                "unexpected text '{s}' in the {} block (expected 'key = value', a block marker, or point rows inside 'point.begin … point.end')",
                block.name()
            ),
        ));
    }

    if block != Block::Outside {
        let opened = match block {
            Block::Header => header_begin,
            Block::Spline => spline_begin,
            _ => point_begin,
        };
        return Err(syntax(
            last_line.max(1),
            format!(
                "the {} block opened on line {} is never closed ('{}.end' missing)",
                block.name(),
                opened.unwrap_or(1),
                block.name()
            ),
        ));
    }
    let Some(point_end) = point_end else {
        return Err(E::MissingPointBlock {
            path: path.to_path_buf(),
            line: spline_end.unwrap_or(last_line).max(1),
        });
    };

    let settings = Settings::resolve(path, &header, &spline, ext_kind)?;
    let in_file = points.len();
    let (points, settings) = settings.apply(points);
    Ok(RawProfile {
        points,
        in_file,
        end_line: point_end,
        per_m: [settings.units_len_f, settings.units_len_f],
        z_down: true,
        kind: settings.header_type.map(|t| {
            if t == 1 {
                ProfileKind::Wheel
            } else {
                ProfileKind::Rail
            }
        }),
        comment: spline
            .get("comment")
            .map(|e| e.value.trim().to_string())
            .filter(|c| !c.is_empty()),
        simpack: Some(settings),
    })
}

/// One row of the point block: `y z [weight]`, white space (or commas)
/// between the values.
fn point_row(path: &Path, line: usize, s: &str) -> Result<RawPoint, E> {
    let fields: Vec<&str> = s
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|f| !f.is_empty())
        .collect();
    if !(2..=3).contains(&fields.len()) {
        return Err(E::FieldCount {
            path: path.to_path_buf(),
            line,
            expected: "2 or 3 values (y z [weight])".into(),
            found: fields.len(),
        });
    }
    let names = ["y", "z", "weight"];
    let mut v = [0.0, 0.0, 1.0];
    for (k, f) in fields.iter().enumerate() {
        v[k] = number(path, line, Some(k + 1), || names[k].to_string(), f)?;
    }
    if v[2] < 0.0 {
        return Err(E::UnsupportedValue {
            path: path.to_path_buf(),
            line,
            key: "weight".into(),
            value: fields[2].to_string(),
            allowed: "a point's weight must not be negative".into(),
        });
    }
    Ok(RawPoint {
        y: v[0],
        z: v[1],
        weight: v[2],
        line,
    })
}

/// The line up to its first `!` outside a quoted string.
fn strip_comment(line: &str) -> &str {
    let mut quote = None;
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (None, '!') => return &line[..i],
            (None, '\'' | '"') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            _ => {}
        }
    }
    line
}

/// A value without its quotes (`'…'` or `"…"`), or as written.
fn unquote(v: &str) -> Result<String, String> {
    let Some(q) = v.chars().next().filter(|c| *c == '\'' || *c == '"') else {
        return Ok(v.to_string());
    };
    let inner = &v[1..];
    match inner.find(q) {
        None => Err(format!("unterminated string {v} (missing closing {q})")),
        Some(end) if !inner[end + 1..].trim().is_empty() => Err(format!(
            "text '{}' after the closing quote of {}",
            inner[end + 1..].trim(),
            &v[..end + 2]
        )),
        Some(end) => Ok(inner[..end].to_string()),
    }
}

/// Typed access to the keys of one block, with errors naming their lines.
#[derive(Clone, Copy)]
struct Ctx<'a> {
    path: &'a Path,
    keys: &'a Keys,
}

impl<'a> Ctx<'a> {
    fn unsupported(&self, key: &str, e: &Entry, allowed: &str) -> E {
        E::UnsupportedValue {
            path: self.path.to_path_buf(),
            line: e.line,
            key: key.to_string(),
            value: e.value.clone(),
            allowed: allowed.to_string(),
        }
    }

    /// The numeric value of `key`, if given.
    fn num(&self, key: &str) -> Result<Option<(f64, &'a Entry)>, E> {
        self.keys
            .get(key)
            .map(|e| {
                number(
                    self.path,
                    e.line,
                    None,
                    || format!("value of '{key}'"),
                    e.value.trim(),
                )
                .map(|v| (v, e))
            })
            .transpose()
    }

    /// The numeric value of `key`, 0 if not given.
    fn value(&self, key: &str) -> Result<f64, E> {
        Ok(self.num(key)?.map_or(0.0, |(v, _)| v))
    }

    /// The integer value of `key`, if given.
    fn int(&self, key: &str) -> Result<Option<(i64, &'a Entry)>, E> {
        match self.num(key)? {
            None => Ok(None),
            Some((v, e)) if v.fract() == 0.0 && v.abs() < 1e15 => Ok(Some((v as i64, e))),
            Some((_, e)) => Err(self.unsupported(key, e, "must be an integer")),
        }
    }

    /// A 0/1 switch, 0 if not given.
    fn flag(&self, key: &str) -> Result<bool, E> {
        match self.int(key)? {
            None | Some((0, _)) => Ok(false),
            Some((1, _)) => Ok(true),
            Some((_, e)) => Err(self.unsupported(key, e, "must be 0 (off) or 1 (on)")),
        }
    }

    /// A bound pair, active only if min < max (both missing: inactive).
    fn bound(&self, lo: &str, hi: &str) -> Result<Option<(f64, f64)>, E> {
        let (a, b) = (self.value(lo)?, self.value(hi)?);
        Ok((a < b).then_some((a, b)))
    }
}

/// The resolved settings.
struct Settings {
    s: SimpackSettings,
}

impl Settings {
    fn resolve(
        path: &Path,
        header: &Keys,
        spline: &Keys,
        ext_kind: Option<ProfileKind>,
    ) -> Result<Self, E> {
        let h = Ctx { path, keys: header };
        let sp = Ctx { path, keys: spline };

        let version = h.int("version")?;
        if let Some((v, e)) = version
            && v != 1
        {
            return Err(h.unsupported(
                "version",
                e,
                "this reader knows SIMPACK profile version 1 only",
            ));
        }
        let header_type = h.int("type")?;
        if let Some((t, e)) = header_type {
            let kind = match t {
                0 => ProfileKind::Rail,
                1 => ProfileKind::Wheel,
                _ => return Err(h.unsupported("type", e, "must be 0 (rail) or 1 (wheel)")),
            };
            if let Some(ext) = ext_kind
                && ext != kind
            {
                return Err(E::KindConflict {
                    path: path.to_path_buf(),
                    line: e.line,
                    header_type: t,
                    header_kind: kind,
                    extension_kind: ext,
                });
            }
        }

        let approx_smooth = match sp.num("approx.smooth")? {
            Some((v, e)) if v < 0.0 => {
                return Err(sp.unsupported("approx.smooth", e, "must not be negative"));
            }
            Some((v, _)) => v,
            None => 0.0,
        };
        // Not used, but must be numbers.
        sp.num("file.mtime")?;
        sp.num("type")?;
        let point_dist_min = match sp.num("point.dist.min")? {
            Some((v, e)) if v < 0.0 => {
                return Err(sp.unsupported(
                    "point.dist.min",
                    e,
                    "must not be negative (0 = no filtering)",
                ));
            }
            Some((v, _)) => v,
            None => 0.0,
        };

        let units_len_f = unit_factor(
            sp,
            "units.len",
            &[
                ("m", 1.0),
                ("dm", 10.0),
                ("cm", 100.0),
                ("mm", 1000.0),
                ("um", 1e6),
                ("µm", 1e6),
                ("km", 1e-3),
            ],
        )?;
        let units_ang_f = unit_factor(
            sp,
            "units.ang",
            &[
                ("rad", 1.0),
                ("mrad", 1000.0),
                ("deg", 180.0 / PI),
                ("°", 180.0 / PI),
            ],
        )?;

        Ok(Settings {
            s: SimpackSettings {
                version: version.map(|(v, _)| v),
                header_type: header_type.map(|(t, _)| t),
                approx_smooth,
                source_file: spline
                    .get("file")
                    .map(|e| e.value.clone())
                    .filter(|f| !f.is_empty()),
                point_dist_min,
                shift_y: sp.value("shift.y")?,
                shift_z: sp.value("shift.z")?,
                rotate_rad: sp.value("rotate")? / units_ang_f,
                bound_y: sp.bound("bound.y.min", "bound.y.max")?,
                bound_z: sp.bound("bound.z.min", "bound.z.max")?,
                mirror_y: sp.flag("mirror.y")?,
                mirror_z: sp.flag("mirror.z")?,
                inversion: sp.flag("inversion")?,
                units_len_f,
                units_ang_f,
                removed_by_point_dist_min: 0,
                removed_by_bound_y: 0,
            },
        })
    }

    /// Steps 1–6 (see [`SimpackSettings`]); step 7 is the unit factor
    /// handed back to the caller.
    fn apply(self, mut p: Vec<RawPoint>) -> (Vec<RawPoint>, SimpackSettings) {
        let mut s = self.s;

        // 1. Minimum point distance, to the last point kept.
        if s.point_dist_min > 0.0 && !p.is_empty() {
            let n = p.len();
            let d2 = s.point_dist_min * s.point_dist_min;
            let mut kept: Vec<RawPoint> = Vec::with_capacity(n);
            for q in p {
                match kept.last() {
                    Some(last) if (q.y - last.y).powi(2) + (q.z - last.z).powi(2) < d2 => {}
                    _ => kept.push(q),
                }
            }
            s.removed_by_point_dist_min = n - kept.len();
            p = kept;
        }

        // 2. Shift.
        for q in &mut p {
            q.y += s.shift_y;
            q.z += s.shift_z;
        }

        // 3. Rotation about x through the origin.
        if s.rotate_rad != 0.0 {
            let (sin, cos) = s.rotate_rad.sin_cos();
            for q in &mut p {
                let (y, z) = (q.y, q.z);
                q.y = y * cos - z * sin;
                q.z = y * sin + z * cos;
            }
        }

        // 4. Bounds: y removes, z clips.
        if let Some((lo, hi)) = s.bound_y {
            let n = p.len();
            p.retain(|q| (lo..=hi).contains(&q.y));
            s.removed_by_bound_y = n - p.len();
        }
        if let Some((lo, hi)) = s.bound_z {
            for q in &mut p {
                q.z = q.z.clamp(lo, hi);
            }
        }

        // 5. Mirror.
        if s.mirror_y {
            for q in &mut p {
                q.y = -q.y;
            }
        }
        if s.mirror_z {
            for q in &mut p {
                q.z = -q.z;
            }
        }

        // 6. Inversion.
        if s.inversion {
            p.reverse();
        }
        (p, s)
    }
}

/// `units.len.f` / `units.ang.f` (units per SI unit), from the factor key
/// or else from the unit name; both given must agree; default 1.
fn unit_factor(sp: Ctx<'_>, name_key: &str, names: &[(&str, f64)]) -> Result<f64, E> {
    let factor_key = format!("{name_key}.f");
    let factor = sp.num(&factor_key)?;
    if let Some((f, e)) = factor
        && f <= 0.0
    {
        return Err(sp.unsupported(&factor_key, e, "a unit factor must be positive"));
    }
    let named = sp.keys.get(name_key).map(|e| {
        let n = e.value.trim();
        (
            names
                .iter()
                .find(|(k, _)| k.eq_ignore_ascii_case(n))
                .map(|(_, f)| *f),
            e,
        )
    });
    match (factor, named) {
        (Some((f, _)), None | Some((None, _))) => Ok(f),
        (None, None) => Ok(1.0),
        (None, Some((Some(g), _))) => Ok(g),
        (None, Some((None, e))) => {
            let known = names.iter().map(|(k, _)| *k).collect::<Vec<_>>().join(", ");
            Err(sp.unsupported(
                name_key,
                e,
                &format!("unknown unit name (known: {known}); give '{factor_key}' instead"),
            ))
        }
        (Some((f, fe)), Some((Some(g), e))) => {
            if (f - g).abs() <= 1e-9 * g {
                Ok(f)
            } else {
                Err(sp.unsupported(
                    &factor_key,
                    fe,
                    &format!(
                        "contradicts {name_key} = '{}' on line {} (which means {factor_key} = {g})",
                        e.value, e.line
                    ),
                ))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{ImportOptions, ProfileFile, ProfileFormat, YOrder, parse_profile};
    use super::*;

    /// A SIMPACK file with `settings` in the spline block and `points`.
    fn file(kind: i32, settings: &str, points: &str) -> String {
        format!(
            "! test\nheader.begin\n  version = 1\n  type = {kind}\nheader.end\nspline.begin\n{settings}\n  point.begin\n{points}\n  point.end\nspline.end\n"
        )
    }

    fn parse(name: &str, text: &str) -> Result<ProfileFile, E> {
        parse_profile(Path::new(name), text, &ImportOptions::default())
    }

    /// Points in file units (metres × `f`).
    fn pts(f: &ProfileFile, scale: f64) -> Vec<[f64; 2]> {
        f.points_m
            .iter()
            .map(|p| [p[0] * scale, p[1] * scale])
            .collect()
    }

    fn close(a: &[[f64; 2]], b: &[[f64; 2]]) -> bool {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(p, q)| (p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12)
    }

    const FOUR: &str = "1 10\n2 20\n3 30\n4 40";
    const MM: &str = "units.len.f = 1000";

    #[test]
    fn plain_file_without_transforms() {
        let text = file(
            1,
            &format!("comment = 'a wheel ! not a comment'\nfile = 'w.txt'\n{MM}"),
            "1 10\n2 20 0.5\n3 30\n4 40 ! last",
        );
        let f = parse("w.prw", &text).unwrap();
        assert_eq!(f.format, ProfileFormat::Simpack);
        assert_eq!(f.kind, Some(ProfileKind::Wheel));
        assert!(f.z_down);
        assert_eq!(
            f.points_m,
            vec![[1e-3, 10e-3], [2e-3, 20e-3], [3e-3, 30e-3], [4e-3, 40e-3]]
        );
        assert_eq!(f.weights, vec![1.0, 0.5, 1.0, 1.0]);
        assert_eq!(f.lines, vec![11, 12, 13, 14]);
        assert_eq!(f.comment.as_deref(), Some("a wheel ! not a comment"));
        let s = f.simpack.unwrap();
        assert_eq!(s.source_file.as_deref(), Some("w.txt"));
        assert_eq!((s.version, s.header_type), (Some(1), Some(1)));
        assert_eq!(f.y_order, YOrder::Increasing);
    }

    #[test]
    fn units_default_to_metres_and_follow_the_factor_or_name() {
        let f = parse("r.prr", &file(0, "", FOUR)).unwrap();
        assert_eq!(f.points_m[0], [1.0, 10.0]);
        assert_eq!(f.kind, Some(ProfileKind::Rail));
        let f = parse("r.prr", &file(0, "units.len = 'cm'", FOUR)).unwrap();
        assert_eq!(f.points_m[0], [1e-2, 10e-2]);
        let f = parse(
            "r.prr",
            &file(0, "units.len = 'mm'\nunits.len.f = 1000", FOUR),
        )
        .unwrap();
        assert_eq!(f.points_m[0], [1e-3, 10e-3]);
        let f = parse("r.prr", &file(0, "units.len.f = 2.54e1", FOUR)).unwrap();
        assert!((f.points_m[0][0] - 1.0 / 25.4).abs() < 1e-15);
    }

    #[test]
    fn shift_then_units() {
        let f = parse(
            "r.prr",
            &file(0, &format!("shift.y = -1\nshift.z = 5\n{MM}"), FOUR),
        )
        .unwrap();
        assert!(close(
            &pts(&f, 1e3),
            &[[0.0, 15.0], [1.0, 25.0], [2.0, 35.0], [3.0, 45.0]]
        ));
    }

    #[test]
    fn rotate_by_90_degrees_in_radians_and_in_degrees() {
        let p = "1 0\n0 1\n-1 0\n2 2";
        let want = [[0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [-2.0, 2.0]];
        let f = parse("r.prr", &file(0, "rotate = 1.5707963267948966", p)).unwrap();
        assert!(close(&pts(&f, 1.0), &want), "{:?}", f.points_m);
        let f = parse(
            "r.prr",
            &file(0, "rotate = 90\nunits.ang.f = 57.29577951308232", p),
        )
        .unwrap();
        assert!(close(&pts(&f, 1.0), &want), "{:?}", f.points_m);
        let f = parse("r.prr", &file(0, "rotate = 90\nunits.ang = 'deg'", p)).unwrap();
        assert!(close(&pts(&f, 1.0), &want), "{:?}", f.points_m);
        assert!((f.simpack.unwrap().rotate_rad - PI / 2.0).abs() < 1e-15);
    }

    #[test]
    fn rotation_comes_after_the_shift() {
        // (0,0) shifted to (1,0), then rotated to (0,1).
        let f = parse(
            "r.prr",
            &file(
                0,
                "shift.y = 1\nrotate = 1.5707963267948966",
                "0 0\n1 0\n2 0\n3 0",
            ),
        )
        .unwrap();
        assert!(
            close(
                &pts(&f, 1.0),
                &[[0.0, 1.0], [0.0, 2.0], [0.0, 3.0], [0.0, 4.0]]
            ),
            "{:?}",
            f.points_m
        );
    }

    #[test]
    fn bounds_remove_in_y_clip_in_z_and_min_above_max_is_off() {
        let p = "-2 5\n-1 1\n0 0\n1 -1\n2 -5\n3 -9";
        let f = parse("r.prr", &file(0, "bound.y.min = -1\nbound.y.max = 2", p)).unwrap();
        assert!(close(
            &pts(&f, 1.0),
            &[[-1.0, 1.0], [0.0, 0.0], [1.0, -1.0], [2.0, -5.0]]
        ));
        assert_eq!(f.lines, vec![11, 12, 13, 14]);
        let s = f.simpack.as_ref().unwrap();
        assert_eq!((s.bound_y, s.removed_by_bound_y), (Some((-1.0, 2.0)), 2));
        let f = parse("r.prr", &file(0, "bound.z.min = -2\nbound.z.max = 3", p)).unwrap();
        assert!(close(
            &pts(&f, 1.0),
            &[
                [-2.0, 3.0],
                [-1.0, 1.0],
                [0.0, 0.0],
                [1.0, -1.0],
                [2.0, -2.0],
                [3.0, -2.0]
            ]
        ));
        // Inactive (min > max and min == max), as in the benchmark files.
        let off = "bound.y.min = 1\nbound.y.max = 0\nbound.z.min = 4\nbound.z.max = 4";
        let f = parse("r.prr", &file(0, off, p)).unwrap();
        assert_eq!(f.len(), 6);
        let s = f.simpack.unwrap();
        assert_eq!((s.bound_y, s.bound_z), (None, None));
        // Bounds act on the rotated points (step 4 after step 3): rotating by
        // 90° maps z to -y, so bound.y keeps the points with z in [-5, 1].
        let f = parse(
            "r.prr",
            &file(
                0,
                "rotate = 1.5707963267948966\nbound.y.min = -1\nbound.y.max = 5",
                p,
            ),
        )
        .unwrap();
        assert_eq!(f.lines, vec![12, 13, 14, 15]);
        assert!(
            close(
                &pts(&f, 1.0),
                &[[-1.0, -1.0], [0.0, 0.0], [1.0, 1.0], [5.0, 2.0]]
            ),
            "{:?}",
            f.points_m
        );
        // Too few after the bounds: reported with the count in the file.
        let e = parse("r.prr", &file(0, "bound.y.min = 0\nbound.y.max = 1", p)).unwrap_err();
        assert!(
            matches!(
                e,
                E::TooFewPoints {
                    found: 2,
                    in_file: 6,
                    line: 16,
                    ..
                }
            ),
            "{e}"
        );
        assert!(
            e.to_string().contains("removed by the file's processing"),
            "{e}"
        );
    }

    #[test]
    fn mirror_y_and_z_negate_after_the_bounds() {
        let f = parse("r.prr", &file(0, "mirror.y = 1", FOUR)).unwrap();
        assert!(close(
            &pts(&f, 1.0),
            &[[-1.0, 10.0], [-2.0, 20.0], [-3.0, 30.0], [-4.0, 40.0]]
        ));
        assert_eq!(f.y_order, YOrder::Decreasing);
        let f = parse("r.prr", &file(0, "mirror.z = 1", FOUR)).unwrap();
        assert!(close(
            &pts(&f, 1.0),
            &[[1.0, -10.0], [2.0, -20.0], [3.0, -30.0], [4.0, -40.0]]
        ));
        // bound.y selects on the unmirrored y.
        let f = parse(
            "r.prr",
            &file(
                0,
                "mirror.y = 1\nbound.y.min = 0\nbound.y.max = 10",
                "-1 0\n1 1\n2 2\n3 3\n4 4",
            ),
        )
        .unwrap();
        assert!(close(
            &pts(&f, 1.0),
            &[[-1.0, 1.0], [-2.0, 2.0], [-3.0, 3.0], [-4.0, 4.0]]
        ));
    }

    #[test]
    fn inversion_reverses_points_lines_and_weights() {
        let f = parse(
            "r.prr",
            &file(0, "inversion = 1", "1 10 0.1\n2 20 0.2\n3 30 0.3\n4 40 0.4"),
        )
        .unwrap();
        assert!(close(
            &pts(&f, 1.0),
            &[[4.0, 40.0], [3.0, 30.0], [2.0, 20.0], [1.0, 10.0]]
        ));
        assert_eq!(f.lines, vec![12, 11, 10, 9]);
        assert_eq!(f.weights, vec![0.4, 0.3, 0.2, 0.1]);
    }

    #[test]
    fn the_benchmark_wheel_recipe_mirror_then_invert() {
        // As MBench_S1002_v3.prw: mirror.y = 1, inversion = 1, mm.
        let f = parse(
            "w.prw",
            &file(
                1,
                &format!("mirror.y = 1\ninversion = 1\n{MM}"),
                "70 9\n60 3\n-30 28\n-60 30",
            ),
        )
        .unwrap();
        assert!(close(
            &pts(&f, 1e3),
            &[[60.0, 30.0], [30.0, 28.0], [-60.0, 3.0], [-70.0, 9.0]]
        ));
    }

    #[test]
    fn point_dist_min_drops_points_close_to_the_last_kept() {
        // 0.3 and 0.6 along y are within 1 of (0,0); (0.9, 0.5) is 1.03 away.
        let p = "0 0\n0.3 0\n0.6 0\n0.9 0.5\n1.5 0.5\n1.6 0.5\n3 0.5\n4 0.5";
        let f = parse("r.prr", &file(0, "point.dist.min = 1", p)).unwrap();
        assert!(
            close(
                &pts(&f, 1.0),
                &[[0.0, 0.0], [0.9, 0.5], [3.0, 0.5], [4.0, 0.5]]
            ),
            "{:?}",
            f.points_m
        );
        assert_eq!(f.simpack.unwrap().removed_by_point_dist_min, 4);
        // It also removes exact repeats, which are an error otherwise.
        let p = "0 0\n1 1\n1 1\n2 2\n3 3";
        assert!(matches!(
            parse("r.prr", &file(0, "", p)),
            Err(E::DuplicatePoint {
                line: 11,
                previous_line: 10,
                ..
            })
        ));
        assert_eq!(
            parse("r.prr", &file(0, "point.dist.min = 1e-9", p))
                .unwrap()
                .len(),
            4
        );
    }

    #[test]
    fn all_steps_in_order() {
        // 1 drop (0.1,0), 2 shift y+1, 3 rotate 90°, 4 bound y in [-3,0.5]
        // (removes the rotated point with y = -4), clip z to [0, 3],
        // 5 mirror z, 6 invert, 7 mm.
        let settings = "point.dist.min = 0.5\nshift.y = 1\nrotate = 90\nunits.ang.f = 57.29577951308232\n\
                        bound.y.min = -3\nbound.y.max = 0.5\nbound.z.min = 0\nbound.z.max = 3\n\
                        mirror.z = 1\ninversion = 1\nunits.len.f = 1000";
        let p = "0 0\n0.1 0\n1 1\n2 2\n3 3\n4 4";
        // After 1: (0,0) (1,1) (2,2) (3,3) (4,4); 2: (1,0) (2,1) (3,2) (4,3) (5,4)
        // 3: (0,1) (-1,2) (-2,3) (-3,4) (-4,5); 4: drop (-4,5); clip z≤3:
        // (0,1) (-1,2) (-2,3) (-3,3); 5: (0,-1) (-1,-2) (-2,-3) (-3,-3); 6: reverse.
        let f = parse("r.prr", &file(0, settings, p)).unwrap();
        assert!(
            close(
                &pts(&f, 1e3),
                &[[-3.0, -3.0], [-2.0, -3.0], [-1.0, -2.0], [0.0, -1.0]]
            ),
            "{:?}",
            f.points_m
        );
        assert_eq!(f.lines, vec![23, 22, 21, 19]);
    }

    #[test]
    fn keys_are_case_insensitive_and_comments_anywhere() {
        let text = "HEADER.BEGIN ! h\n Version = 1\n Type = 0\nheader.END\n\n! between\nSpline.Begin\n Units.Len.F = 1000 ! mm\n Point.Begin\n 1,10\n 2,20\n 3,30\n 4,40\n Point.End\nSpline.End\n! end\n";
        let f = parse("r.prr", text).unwrap();
        assert_eq!(f.points_m[1], [2e-3, 20e-3]);
        assert_eq!(f.kind, Some(ProfileKind::Rail));
    }

    #[test]
    fn the_header_is_optional_and_the_extension_gives_the_kind() {
        let text = "spline.begin\npoint.begin\n1 1\n2 2\n3 3\n4 4\npoint.end\nspline.end\n";
        assert_eq!(parse("w.prw", text).unwrap().kind, Some(ProfileKind::Wheel));
        assert_eq!(parse("x.txt", text).unwrap().kind, None);
        assert_eq!(
            parse("x.txt", &file(1, "", FOUR)).unwrap().kind,
            Some(ProfileKind::Wheel)
        );
    }

    #[test]
    fn comment_stripping_respects_quotes() {
        assert_eq!(strip_comment("a = 'x ! y' ! z"), "a = 'x ! y' ");
        assert_eq!(strip_comment("a = \"x ! y\"! z"), "a = \"x ! y\"");
        assert_eq!(strip_comment("!7.0E+01 9.5"), "");
        assert_eq!(unquote("'abc'").unwrap(), "abc");
        assert_eq!(unquote("plain text").unwrap(), "plain text");
        assert!(unquote("'abc").is_err());
        assert!(unquote("'abc' def").is_err());
    }

    /// (text, expected line, predicate on the error)
    #[test]
    fn every_simpack_error_names_its_line() {
        type Check = fn(&E) -> bool;
        let cases: Vec<(String, usize, Check)> = vec![
            (file(0, "mirror.y = 2", FOUR), 7, |e| matches!(e, E::UnsupportedValue { key, .. } if key == "mirror.y")),
            (file(0, "mirror.z = 0.5", FOUR), 7, |e| matches!(e, E::UnsupportedValue { key, .. } if key == "mirror.z")),
            (file(0, "inversion = -1", FOUR), 7, |e| matches!(e, E::UnsupportedValue { key, .. } if key == "inversion")),
            (file(0, "units.len.f = 0", FOUR), 7, |e| matches!(e, E::UnsupportedValue { key, .. } if key == "units.len.f")),
            (file(0, "units.ang.f = -1", FOUR), 7, |e| matches!(e, E::UnsupportedValue { key, .. } if key == "units.ang.f")),
            (file(0, "units.len = 'furlong'", FOUR), 7, |e| matches!(e, E::UnsupportedValue { key, .. } if key == "units.len")),
            (file(0, "units.len = 'mm'\nunits.len.f = 1", FOUR), 8, |e| matches!(e, E::UnsupportedValue { key, .. } if key == "units.len.f")),
            (file(0, "point.dist.min = -1", FOUR), 7, |e| matches!(e, E::UnsupportedValue { .. })),
            (file(0, "approx.smooth = -1", FOUR), 7, |e| matches!(e, E::UnsupportedValue { .. })),
            (file(2, "", FOUR), 4, |e| matches!(e, E::UnsupportedValue { key, .. } if key == "type")),
            (file(0, "", "1 1\n2 2 -1\n3 3\n4 4"), 10, |e| matches!(e, E::UnsupportedValue { key, .. } if key == "weight")),
            (file(0, "shift.y = abc", FOUR), 7, |e| matches!(e, E::NotANumber { what, .. } if what.contains("shift.y"))),
            (file(0, "rotate = nan", FOUR), 7, |e| matches!(e, E::NonFinite { .. })),
            (file(0, "", "1 1\n2 x\n3 3\n4 4"), 10, |e| matches!(e, E::NotANumber { what, column: Some(2), .. } if what == "z")),
            (file(0, "", "1 1\n2 2\n3 1e400\n4 4"), 11, |e| matches!(e, E::NonFinite { .. })),
            (file(0, "", "1 1\n2 2 1 1\n3 3\n4 4"), 10, |e| matches!(e, E::FieldCount { found: 4, .. })),
            (file(0, "", "1 1\n2\n3 3\n4 4"), 10, |e| matches!(e, E::FieldCount { found: 1, .. })),
            (file(0, "mirror.x = 1", FOUR), 7, |e| matches!(e, E::UnknownKey { key, .. } if key == "mirror.x")),
            (file(0, "shift.y = 1\nshift.y = 2", FOUR), 8, |e| matches!(e, E::DuplicateKey { first_line: 7, .. })),
            (file(0, "", "1 1\ny = 2\n3 3\n4 4"), 10, |e| matches!(e, E::Syntax { .. })),
            (file(0, "comment = 'open", FOUR), 7, |e| matches!(e, E::Syntax { .. })),
            (file(0, "point.begin\n1 1\npoint.end", FOUR), 10, |e| matches!(e, E::Syntax { .. })),
            (file(0, "garbage", FOUR), 7, |e| matches!(e, E::Syntax { .. })),
            (file(0, "extra.begin", FOUR), 7, |e| matches!(e, E::Syntax { .. })),
            (file(0, "", "1 1\n2 2\n3 3"), 12, |e| matches!(e, E::TooFewPoints { found: 3, .. })),
            ("version = 1\n".into(), 1, |e| matches!(e, E::Syntax { .. })),
            ("header.begin\nversion = 2\nheader.end\nspline.begin\npoint.begin\n1 1\n2 2\n3 3\n4 4\npoint.end\nspline.end\n".into(), 2, |e| matches!(e, E::UnsupportedValue { key, .. } if key == "version")),
            ("header.begin\nspline.begin\n".into(), 2, |e| matches!(e, E::Syntax { .. })),
            ("spline.begin\npoint.begin\n1 1\n".into(), 3, |e| matches!(e, E::Syntax { rule, .. } if rule.contains("line 2"))),
            ("spline.begin\npoint.end\n".into(), 2, |e| matches!(e, E::Syntax { .. })),
            ("point.begin\n".into(), 1, |e| matches!(e, E::Syntax { .. })),
            ("header.begin\nheader.end\nheader.begin\nheader.end\n".into(), 3, |e| matches!(e, E::Syntax { .. })),
            ("spline.begin\nspline.end\nspline.begin\nspline.end\n".into(), 3, |e| matches!(e, E::Syntax { .. })),
            ("spline.begin\nshift.y = 1\nspline.end\n! end\n".into(), 3, |e| matches!(e, E::MissingPointBlock { .. })),
            ("! only a comment\n".into(), 1, |e| matches!(e, E::MissingPointBlock { .. })),
            ("".into(), 1, |e| matches!(e, E::MissingPointBlock { .. })),
        ];
        for (text, line, check) in cases {
            let e = parse("r.prr", &text).expect_err(&text);
            assert!(check(&e), "{text}\n→ {e:?}");
            assert_eq!(e.line(), Some(line), "{text}\n→ {e}");
            let msg = e.to_string();
            let at = format!("'r.prr', line {line}");
            assert!(
                msg.starts_with(&format!("{at}: ")) || msg.starts_with(&format!("{at}, column ")),
                "{msg}"
            );
        }
    }

    #[test]
    fn header_type_must_agree_with_the_extension() {
        let e = parse("w.prw", &file(0, "", FOUR)).unwrap_err();
        assert!(
            matches!(
                e,
                E::KindConflict {
                    line: 4,
                    header_type: 0,
                    header_kind: ProfileKind::Rail,
                    extension_kind: ProfileKind::Wheel,
                    ..
                }
            ),
            "{e}"
        );
        let e = parse("r.PRR", &file(1, "", FOUR)).unwrap_err();
        assert!(matches!(e, E::KindConflict { .. }), "{e}");
    }
}
