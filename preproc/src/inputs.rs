//! The three CSV inputs of docs/reference/02-inputs.md §2 — centreline control points, cant table,
//! irregularity table — parsed and checked against their rules.

use std::path::{Path, PathBuf};

use crate::bounds::{
    MAX_CANT_ON_STANDARD_BASE_MM, MAX_COORDINATE_M, MIN_PEAK_CANT_MM, MIN_PEAK_IRREGULARITY_MM,
};
pub use crate::bounds::{MAX_CANT_RAD, MAX_IRREGULARITY_M};
use crate::csv::{CsvTable, find_length_column};
use crate::error::InputError;

/// Fewest data rows accepted in any input table (docs/reference/02-inputs.md §2).
pub const MIN_ROWS: usize = 4;

/// A cant column: angles (`cant`, rad) or heights (`cant_mm`, converted to
/// metres on reading), with the line of each value for messages.
#[derive(Debug, Clone, PartialEq)]
pub struct CantColumn {
    path: PathBuf,
    lines: Vec<usize>,
    /// 1-based column of the cant in its file.
    column: usize,
    /// φ (rad) or h (m).
    values: Vec<f64>,
    /// The values as the file has them (rad or mm), for messages.
    file_values: Vec<f64>,
    is_height: bool,
}

impl CantColumn {
    fn from_table(table: &CsvTable) -> Result<Option<Self>, InputError> {
        let rad = table.column("cant");
        let mm = table.column("cant_mm");
        let (idx, is_height) = match (rad, mm) {
            (Some(_), Some(_)) => {
                return Err(table.error("columns 'cant' and 'cant_mm' both given; keep one"));
            }
            (Some(i), None) => (i, false),
            (None, Some(i)) => (i, true),
            (None, None) => return Ok(None),
        };
        if is_height
            && let Some((row, peak_mm)) = peak(&table.values(idx))
            && peak_mm > 0.0
            && peak_mm < MIN_PEAK_CANT_MM
        {
            return Err(table.error_at_value(
                row,
                idx,
                format!(
                    "cant_mm: the largest |cant| of the column is {peak_mm} mm, below the {MIN_PEAK_CANT_MM} mm of any real cant: these are metres in a millimetre column (check the unit: write 100 for a cant of 100 mm)"
                ),
            ));
        }
        let scale = if is_height { 1e-3 } else { 1.0 };
        Ok(Some(Self {
            path: table.path.clone(),
            lines: table.rows.iter().map(|(l, _)| *l).collect(),
            column: idx + 1,
            values: table.rows.iter().map(|(_, v)| v[idx] * scale).collect(),
            file_values: table.values(idx),
            is_height,
        }))
    }

    /// The file of the column.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// 1-based line of each value.
    pub fn lines(&self) -> &[usize] {
        &self.lines
    }

    /// Cant angles φ (rad): heights convert by φ = asin(h / e0) (docs/reference/01-units-frames.md §1),
    /// `cant_base_m` = e0. Fails, naming the line and column, on the first
    /// value beyond ±[`MAX_CANT_RAD`] (200 mm on the standard cant base)
    /// or a height not smaller than e0.
    pub fn radians(&self, cant_base_m: f64) -> Result<Vec<f64>, InputError> {
        self.values
            .iter()
            .zip(&self.file_values)
            .zip(&self.lines)
            .map(|((&v, &given), &line)| {
                let err = |rule: String| InputError::at_value(&self.path, line, self.column, rule);
                let phi = if self.is_height {
                    if v.abs() >= cant_base_m {
                        return Err(err(format!(
                            "cant height {} mm is not smaller than the cant base {:.1} mm (check the unit: 'cant_mm' is in mm)",
                            number(given),
                            cant_base_m * 1e3
                        )));
                    }
                    (v / cant_base_m).asin()
                } else {
                    v
                };
                if phi.abs() > MAX_CANT_RAD {
                    let given = if self.is_height {
                        format!(
                            "cant_mm = {} mm ({phi:.4} rad on the cant base {cant_base_m} m)",
                            number(given)
                        )
                    } else {
                        format!(
                            "cant = {} rad ({:.1} mm on the cant base {cant_base_m} m)",
                            number(given),
                            cant_base_m * phi.sin() * 1e3
                        )
                    };
                    return Err(err(format!(
                        "{given} is beyond the ±{MAX_CANT_RAD:.4} rad of any track ({MAX_CANT_ON_STANDARD_BASE_MM} mm on the standard cant base 1.5 m; EN 13803 allows 180 mm): check the unit ('cant' is in rad, 'cant_mm' in mm)"
                    )));
                }
                Ok(phi)
            })
            .collect()
    }
}

/// The row and value of the largest |value| of a column (the first, if
/// several are equal), if any.
pub(crate) fn peak(values: &[f64]) -> Option<(usize, f64)> {
    let mut best: Option<(usize, f64)> = None;
    for (k, v) in values.iter().map(|v| v.abs()).enumerate() {
        if best.is_none_or(|(_, b)| v > b) {
            best = Some((k, v));
        }
    }
    best
}

/// A number as read from a file, shown plainly or, when very large or
/// small, in exponent form (1e308 rather than 309 digits).
fn number(v: f64) -> String {
    if v != 0.0 && !(1e-4..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// Refuse a coordinate or track distance beyond ±[`MAX_COORDINATE_M`]
/// (a unit error, or an overflowing number such as 1e308), naming its
/// line and column.
fn check_coordinates(t: &CsvTable, columns: &[usize]) -> Result<(), InputError> {
    for (row, (_, values)) in t.rows.iter().enumerate() {
        for &c in columns {
            if values[c].abs() > MAX_COORDINATE_M {
                return Err(t.error_at_value(
                    row,
                    c,
                    format!(
                        "{} = {} m is beyond ±{MAX_COORDINATE_M:e} m, more than any map coordinate or track distance (check the unit: metres)",
                        t.columns[c],
                        number(values[c])
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Centreline control points (`x, y, z` in m) with optional cant.
#[derive(Debug, Clone, PartialEq)]
pub struct CenterlineInput {
    pub path: PathBuf,
    /// Control points (m).
    pub points: Vec<[f64; 3]>,
    /// 1-based line of each point in the file.
    pub lines: Vec<usize>,
    /// Cant at each point, if the file has a `cant` or `cant_mm` column.
    pub cant: Option<CantColumn>,
}

impl CenterlineInput {
    /// Parse a centreline CSV.
    pub fn parse(path: &Path, text: &str) -> Result<Self, InputError> {
        let t = CsvTable::parse(path, text)?;
        allow_only(&t, &["x", "y", "z", "cant", "cant_mm"])?;
        let col = |name: &str| {
            t.column(name).ok_or_else(|| {
                t.error(format!(
                    "missing column '{name}' (a centreline needs x, y, z [m] and optionally cant [rad] or cant_mm)"
                ))
            })
        };
        let (ix, iy, iz) = (col("x")?, col("y")?, col("z")?);
        t.require_rows(MIN_ROWS)?;
        check_coordinates(&t, &[ix, iy, iz])?;
        let points: Vec<[f64; 3]> = t.rows.iter().map(|(_, v)| [v[ix], v[iy], v[iz]]).collect();
        for k in 1..points.len() {
            let d = distance(points[k], points[k - 1]);
            if d <= 1e-9 {
                return Err(t.error_at(
                    k,
                    format!(
                        "control point repeats the previous one (line {}): points must be distinct",
                        t.line(k - 1)
                    ),
                ));
            }
        }
        Ok(Self {
            path: path.to_path_buf(),
            lines: t.rows.iter().map(|(l, _)| *l).collect(),
            cant: CantColumn::from_table(&t)?,
            points,
        })
    }
}

/// A cant table `s, cant` or `s, cant_mm` (s = track distance, m).
#[derive(Debug, Clone, PartialEq)]
pub struct CantInput {
    pub path: PathBuf,
    pub s_m: Vec<f64>,
    pub cant: CantColumn,
}

impl CantInput {
    /// Parse a cant CSV.
    pub fn parse(path: &Path, text: &str) -> Result<Self, InputError> {
        let t = CsvTable::parse(path, text)?;
        allow_only(&t, &["s", "cant", "cant_mm"])?;
        let is = t
            .column("s")
            .ok_or_else(|| t.error("missing column 's' (track distance, m)"))?;
        let cant = CantColumn::from_table(&t)?
            .ok_or_else(|| t.error("missing column 'cant' [rad] or 'cant_mm' [mm]"))?;
        t.require_rows(MIN_ROWS)?;
        check_coordinates(&t, &[is])?;
        t.require_increasing(is)?;
        Ok(Self {
            path: path.to_path_buf(),
            s_m: t.values(is),
            cant,
        })
    }
}

/// Irregularities per rail (m): lateral deviation along `n` (positive to the
/// left) and vertical deviation along `b` (positive up), against track
/// distance s.
#[derive(Debug, Clone, PartialEq)]
pub struct IrregularityInput {
    pub path: PathBuf,
    pub s_m: Vec<f64>,
    pub align_left_m: Vec<f64>,
    pub align_right_m: Vec<f64>,
    pub level_left_m: Vec<f64>,
    pub level_right_m: Vec<f64>,
    /// 1-based line of each row.
    pub lines: Vec<usize>,
    /// Where each per-rail component (align_left, align_right, level_left,
    /// level_right) comes from in the file, for messages.
    pub sources: [ColumnSource; 4],
}

/// The file column(s) a per-rail irregularity is read from.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnSource {
    /// The per-rail name and, for the measurement-car form, its formula
    /// ("align_left = alignment + gauge/2").
    pub what: String,
    /// 1-based column of the (first) file column it is read from.
    pub column: usize,
}

const PER_RAIL: [&str; 4] = ["align_left", "align_right", "level_left", "level_right"];
const MEASUREMENT_CAR: [&str; 4] = ["alignment", "gauge", "level", "cross_level"];

/// One value column of an irregularity file, in metres.
struct RawColumn {
    /// Index in the file (0-based).
    idx: usize,
    /// The name as written (with its `_mm`, if any).
    name: String,
    values_m: Vec<f64>,
}

impl IrregularityInput {
    /// Parse an irregularity CSV in either form of docs/reference/02-inputs.md §2:
    /// per rail `s, align_left, align_right, level_left, level_right`, or the
    /// measurement-car form `s, alignment, gauge, level, cross_level`, any
    /// column with an optional `_mm` suffix. The measurement-car form converts
    /// by (EN 13848-1 definitions, left minus right):
    /// `align_left = alignment + gauge/2`, `align_right = alignment − gauge/2`,
    /// `level_left = level + cross_level/2`, `level_right = level − cross_level/2`
    /// (gauge > 0 widens the track; cross_level > 0 raises the left rail).
    /// Every value and every per-rail deviation must lie within
    /// ±[`MAX_IRREGULARITY_M`]; a `_mm` column whose values all lie below
    /// [`MIN_PEAK_IRREGULARITY_MM`] (and not all zero) holds metres.
    pub fn parse(path: &Path, text: &str) -> Result<Self, InputError> {
        let t = CsvTable::parse(path, text)?;
        let mut allowed: Vec<String> = vec!["s".into()];
        for n in PER_RAIL.iter().chain(&MEASUREMENT_CAR) {
            allowed.push(n.to_string());
            allowed.push(format!("{n}_mm"));
        }
        let allowed: Vec<&str> = allowed.iter().map(String::as_str).collect();
        allow_only(&t, &allowed)?;
        let is = t
            .column("s")
            .ok_or_else(|| t.error("missing column 's' (track distance, m)"))?;

        let read = |names: &[&str; 4]| -> Result<Vec<Option<RawColumn>>, InputError> {
            names
                .iter()
                .map(|n| {
                    Ok(find_length_column(&t, n)?.map(|(idx, f)| RawColumn {
                        idx,
                        name: t.columns[idx].clone(),
                        values_m: t.rows.iter().map(|(_, v)| v[idx] * f).collect(),
                    }))
                })
                .collect()
        };
        let per_rail = read(&PER_RAIL)?;
        let car = read(&MEASUREMENT_CAR)?;
        let any = |v: &[Option<RawColumn>]| v.iter().any(Option::is_some);
        let missing = |v: &[Option<RawColumn>], names: &[&str; 4]| -> Vec<String> {
            v.iter()
                .zip(names)
                .filter(|(c, _)| c.is_none())
                .map(|(_, n)| n.to_string())
                .collect()
        };
        let car_form = match (any(&per_rail), any(&car)) {
            (true, true) => {
                return Err(t.error(
                    "mixes the per-rail columns (align_left, …) with the measurement-car columns (alignment, gauge, …); use one form",
                ));
            }
            (false, false) => {
                return Err(t.error(
                    "no irregularity columns: expected s, align_left, align_right, level_left, level_right or s, alignment, gauge, level, cross_level",
                ));
            }
            (true, false) => false,
            (false, true) => true,
        };
        let (raw, names) = if car_form {
            (car, &MEASUREMENT_CAR)
        } else {
            (per_rail, &PER_RAIL)
        };
        let m = missing(&raw, names);
        if !m.is_empty() {
            return Err(t.error(format!("missing column(s) {}", m.join(", "))));
        }
        let raw: Vec<RawColumn> = raw.into_iter().flatten().collect();
        t.require_rows(MIN_ROWS)?;
        check_coordinates(&t, &[is])?;
        t.require_increasing(is)?;
        for c in &raw {
            check_raw_column(&t, c)?;
        }
        let (values, sources): (Vec<Vec<f64>>, Vec<ColumnSource>) = if car_form {
            let (a, g, l, c) = (&raw[0], &raw[1], &raw[2], &raw[3]);
            let zip = |x: &RawColumn, y: &RawColumn, sign: f64, name: &str| {
                let values = x
                    .values_m
                    .iter()
                    .zip(&y.values_m)
                    .map(|(x, y)| x + sign * 0.5 * y)
                    .collect();
                let op = if sign > 0.0 { '+' } else { '−' };
                let source = ColumnSource {
                    what: format!("{name} = {} {op} {}/2", x.name, y.name),
                    column: x.idx + 1,
                };
                (values, source)
            };
            [
                zip(a, g, 1.0, "align_left"),
                zip(a, g, -1.0, "align_right"),
                zip(l, c, 1.0, "level_left"),
                zip(l, c, -1.0, "level_right"),
            ]
            .into_iter()
            .unzip()
        } else {
            raw.into_iter()
                .map(|c| {
                    let source = ColumnSource {
                        what: c.name.clone(),
                        column: c.idx + 1,
                    };
                    (c.values_m, source)
                })
                .unzip()
        };
        for (v, src) in values.iter().zip(&sources) {
            if let Some(k) = v.iter().position(|v| v.abs() > MAX_IRREGULARITY_M) {
                return Err(t.error_at_value(
                    k,
                    src.column - 1,
                    format!(
                        "{} is {:.1} mm, beyond the ±{} mm of any track in service (check the unit: columns without _mm are in metres)",
                        src.what,
                        v[k] * 1e3,
                        MAX_IRREGULARITY_M * 1e3
                    ),
                ));
            }
        }
        let [al, ar, ll, lr]: [Vec<f64>; 4] = values.try_into().expect("four columns");
        Ok(Self {
            path: path.to_path_buf(),
            s_m: t.values(is),
            align_left_m: al,
            align_right_m: ar,
            level_left_m: ll,
            level_right_m: lr,
            lines: t.rows.iter().map(|(l, _)| *l).collect(),
            sources: sources.try_into().expect("four sources"),
        })
    }

    /// The four per-rail columns (m), in the order of [`Self::sources`].
    pub fn components(&self) -> [&[f64]; 4] {
        [
            &self.align_left_m,
            &self.align_right_m,
            &self.level_left_m,
            &self.level_right_m,
        ]
    }

    /// Largest |value| over the four columns (m).
    pub fn max_abs_m(&self) -> f64 {
        [
            &self.align_left_m,
            &self.align_right_m,
            &self.level_left_m,
            &self.level_right_m,
        ]
        .iter()
        .flat_map(|c| c.iter())
        .fold(0.0_f64, |m, v| m.max(v.abs()))
    }

    /// Smallest spacing of the s samples (m).
    pub fn min_spacing_m(&self) -> f64 {
        self.s_m
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min)
    }
}

fn allow_only(t: &CsvTable, allowed: &[&str]) -> Result<(), InputError> {
    for c in &t.columns {
        if !allowed.contains(&c.as_str()) {
            return Err(t.error(format!(
                "unknown column '{c}' (allowed: {})",
                allowed.join(", ")
            )));
        }
    }
    Ok(())
}

/// The bounds of one file column of irregularities: every |value| within
/// [`MAX_IRREGULARITY_M`], and a `_mm` column not all below
/// [`MIN_PEAK_IRREGULARITY_MM`] unless all zero.
fn check_raw_column(t: &CsvTable, c: &RawColumn) -> Result<(), InputError> {
    let Some((row, peak_m)) = peak(&c.values_m) else {
        return Ok(());
    };
    let in_mm = c.name.ends_with("_mm");
    if peak_m > MAX_IRREGULARITY_M {
        return Err(t.error_at_value(
            row,
            c.idx,
            format!(
                "{} = {} {} is beyond the ±{} mm of any track in service (check the unit: columns without _mm are in metres)",
                c.name,
                number(t.rows[row].1[c.idx]),
                if in_mm { "mm" } else { "m" },
                MAX_IRREGULARITY_M * 1e3
            ),
        ));
    }
    if in_mm && peak_m > 0.0 && peak_m * 1e3 < MIN_PEAK_IRREGULARITY_MM {
        return Err(t.error_at_value(
            row,
            c.idx,
            format!(
                "{}: the largest |value| of the column is {} mm, below the {MIN_PEAK_IRREGULARITY_MM} mm a track recording car resolves: these look like metres in a millimetre column (check the unit; write 0 for no irregularity)",
                c.name,
                peak_m * 1e3
            ),
        ));
    }
    Ok(())
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> &'static Path {
        Path::new("in.csv")
    }

    #[test]
    fn centerline_with_cant_mm() {
        let c = CenterlineInput::parse(
            p(),
            "x,y,z,cant_mm\n0,0,0,0\n1,0,0,10\n2,0,0,20\n3,0,0,30\n",
        )
        .unwrap();
        assert_eq!(c.points.len(), 4);
        let phi = c.cant.unwrap().radians(1.5).unwrap();
        assert!((phi[3] - (0.03_f64 / 1.5).asin()).abs() < 1e-15);
    }

    #[test]
    fn centerline_rules() {
        let e = CenterlineInput::parse(p(), "x,y\n0,0\n").unwrap_err();
        assert!(e.to_string().contains("missing column 'z'"), "{e}");
        let e = CenterlineInput::parse(p(), "x,y,z\n0,0,0\n1,0,0\n2,0,0\n").unwrap_err();
        assert!(e.to_string().contains("at least 4"), "{e}");
        let e = CenterlineInput::parse(p(), "x,y,z\n0,0,0\n1,0,0\n1,0,0\n2,0,0\n").unwrap_err();
        assert!(
            e.to_string().contains("line 4") && e.to_string().contains("repeats"),
            "{e}"
        );
        let e = CenterlineInput::parse(p(), "x,y,z,q\n0,0,0,1\n").unwrap_err();
        assert!(e.to_string().contains("unknown column 'q'"), "{e}");
        let c =
            CenterlineInput::parse(p(), "x,y,z,cant\n0,0,0,0\n1,0,0,0.1\n2,0,0,0.35\n3,0,0,0\n")
                .unwrap();
        let e = c.cant.unwrap().radians(1.5).unwrap_err();
        assert!(
            e.to_string().contains("line 4, column 4") && e.to_string().contains("0.1337 rad"),
            "{e}"
        );
    }

    #[test]
    fn measurement_car_form_converts_to_per_rail() {
        let text = "s,alignment_mm,gauge_mm,level_mm,cross_level_mm\n0,1,2,3,4\n1,0,0,0,0\n2,0,0,0,0\n3,0,0,0,0\n";
        let i = IrregularityInput::parse(p(), text).unwrap();
        assert!((i.align_left_m[0] - 2e-3).abs() < 1e-15);
        assert!((i.align_right_m[0] - 0.0).abs() < 1e-15);
        assert!((i.level_left_m[0] - 5e-3).abs() < 1e-15);
        assert!((i.level_right_m[0] - 1e-3).abs() < 1e-15);
    }

    #[test]
    fn irregularity_rules() {
        let e = IrregularityInput::parse(p(), "s,align_left,level_left\n0,0,0\n").unwrap_err();
        assert!(e.to_string().contains("align_right"), "{e}");
        let e = IrregularityInput::parse(p(), "s,align_left,alignment\n0,0,0\n").unwrap_err();
        assert!(e.to_string().contains("mixes"), "{e}");
        let e = IrregularityInput::parse(
            p(),
            "s,align_left,align_right,level_left,level_right\n0,0,0,0,0\n2,0,0,0,0\n1,0,0,0,0\n3,0,0,0,0\n",
        )
        .unwrap_err();
        assert!(e.to_string().contains("line 4"), "{e}");
    }

    /// Found by fuzzing (tests/extremes/fuzz.rs): an alignment of 10²³ m
    /// made the rail's table overflow its capacity; irregularities beyond
    /// 0.2 m are now refused at the line that has them.
    #[test]
    fn irregularities_beyond_the_limit() {
        let e = IrregularityInput::parse(
            p(),
            "s,alignment,gauge,level,cross_level\n0,0,0,0,0\n30,99999999999999999999999,0,0,0\n60,0,0,0,0\n90,0,0,0,0\n",
        )
        .unwrap_err();
        assert!(
            e.to_string().contains("line 3, column 2")
                && e.to_string().contains("alignment = 1e23 m"),
            "{e}"
        );
        // Millimetres in a metres column.
        let e = IrregularityInput::parse(
            p(),
            "s,align_left,align_right,level_left,level_right\n0,0,0,0,0\n1,0,0,3,0\n2,0,0,0,0\n3,0,0,0,0\n",
        )
        .unwrap_err();
        assert!(e.to_string().contains("level_left = 3"), "{e}");
        assert!(
            IrregularityInput::parse(
                p(),
                "s,align_left_mm,align_right_mm,level_left_mm,level_right_mm\n0,0,0,0,0\n1,0,0,30,0\n2,0,0,0,0\n3,0,0,0,0\n",
            )
            .is_ok()
        );
    }

    /// Metres in a `cant_mm` column (all values below 1 mm): refused at
    /// the largest value; a real cant in mm passes.
    #[test]
    fn metres_in_a_cant_mm_column() {
        let e = CantInput::parse(p(), "s,cant_mm\n0,0\n10,0.1\n20,0.12\n30,0\n").unwrap_err();
        let e = e.to_string();
        assert!(
            e.starts_with(
                "in.csv, line 4, column 2: cant_mm: the largest |cant| of the column is 0.12 mm"
            ) && e.contains("check the unit"),
            "{e}"
        );
        assert!(CantInput::parse(p(), "s,cant_mm\n0,0\n10,100\n20,120\n30,0\n").is_ok());
        assert!(CantInput::parse(p(), "s,cant_mm\n0,0\n10,0\n20,0\n30,0\n").is_ok());
    }

    /// A cant in metres in the `cant` (rad) column beyond 0.134 m reads as
    /// an angle beyond the 200 mm bound; heights beyond 200 mm likewise.
    #[test]
    fn cant_beyond_200_mm() {
        let c = CantInput::parse(p(), "s,cant\n0,0\n10,0.15\n20,0.15\n30,0\n").unwrap();
        let e = c.cant.radians(1.5).unwrap_err().to_string();
        assert!(
            e.starts_with(
                "in.csv, line 3, column 2: cant = 0.15 rad (224.2 mm on the cant base 1.5 m)"
            ) && e.contains("±0.1337 rad")
                && e.contains("check the unit"),
            "{e}"
        );
        let c = CantInput::parse(p(), "s,cant_mm\n0,0\n10,200\n20,201\n30,0\n").unwrap();
        let e = c.cant.radians(1.5).unwrap_err().to_string();
        assert!(e.contains("line 4, column 2: cant_mm = 201 mm"), "{e}");
        // 200 mm itself is inside.
        let c = CantInput::parse(p(), "s,cant_mm\n0,0\n10,200\n20,-200\n30,0\n").unwrap();
        assert!(c.cant.radians(1.5).is_ok());
    }

    /// Irregularities: beyond ±50 mm refused (column and line); metres in
    /// a `_mm` column (all below 0.1 mm) refused; the measurement-car form
    /// is checked per rail as well.
    #[test]
    fn irregularity_bounds() {
        let head = "s,align_left_mm,align_right_mm,level_left_mm,level_right_mm\n";
        let e = IrregularityInput::parse(
            p(),
            &format!("{head}0,0,0,0,0\n1,0,0,0,51\n2,0,0,0,0\n3,0,0,0,0\n"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("in.csv, line 3, column 5: level_right_mm = 51 mm is beyond the ±50 mm")
                && e.contains("check the unit"),
            "{e}"
        );
        let e = IrregularityInput::parse(
            p(),
            &format!("{head}0,0,0,0,0\n1,0.004,0,2,0\n2,-0.003,0,1,0\n3,0,0,0,0\n"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("in.csv, line 3, column 2: align_left_mm: the largest |value| of the column is 0.004 mm")
                && e.contains("check the unit"),
            "{e}"
        );
        // alignment 30 mm + gauge 50 mm / 2 = 55 mm on the left rail.
        let e = IrregularityInput::parse(
            p(),
            "s,alignment_mm,gauge_mm,level_mm,cross_level_mm\n0,0,0,0,0\n1,30,50,0,0\n2,0,0,0,0\n3,0,0,0,0\n",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("line 3, column 2: align_left = alignment_mm + gauge_mm/2 is 55.0 mm"),
            "{e}"
        );
    }

    /// A coordinate or s of 1e308 (or any beyond ±1e8 m) is refused at
    /// its line and column, before any spline sees it.
    #[test]
    fn huge_numbers_are_refused_at_their_line_and_column() {
        let e = CenterlineInput::parse(p(), "x,y,z\n0,0,0\n1,0,0\n2,1e308,0\n3,0,0\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("in.csv, line 4, column 2: y = 1e308 m is beyond ±1e8 m")
                && e.contains("check the unit"),
            "{e}"
        );
        let e = CantInput::parse(p(), "cant,s\n0,0\n0,1\n0,2\n0,1e308\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 5, column 2: s = 1e308 m"), "{e}");
        let e = IrregularityInput::parse(
            p(),
            "s,align_left,align_right,level_left,level_right\n0,0,0,0,0\n1,0,0,0,0\n2e9,0,0,0,0\n3e9,0,0,0,0\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("line 4, column 1: s = 2e9 m"), "{e}");
        // UTM coordinates with the zone prefixed are fine.
        assert!(
            CenterlineInput::parse(
                p(),
                "x,y,z\n32500000,5500000,100\n32500001,5500000,100\n32500002,5500000,100\n32500003,5500000,100\n"
            )
            .is_ok()
        );
    }

    #[test]
    fn cant_table() {
        let c = CantInput::parse(p(), "s,cant\n0,0\n10,0.01\n20,0.02\n30,0.02\n").unwrap();
        assert_eq!(c.cant.radians(1.5).unwrap()[2], 0.02);
        let e = CantInput::parse(p(), "s\n0\n").unwrap_err();
        assert!(e.to_string().contains("cant"), "{e}");
    }
}
