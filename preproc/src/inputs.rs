//! The three CSV inputs of docs/reference/02-inputs.md §2 — centreline control points, cant table,
//! irregularity table — parsed and checked against their rules.

use std::path::{Path, PathBuf};

use crate::csv::{CsvTable, find_length_column};
use crate::error::InputError;

/// Fewest data rows accepted in any input table (docs/reference/02-inputs.md §2).
pub const MIN_ROWS: usize = 4;
/// Largest cant magnitude accepted (rad) (docs/reference/02-inputs.md §2).
pub const MAX_CANT_RAD: f64 = 0.3;
/// Largest irregularity accepted per rail (m): measured track geometry
/// defects are millimetres (EN 13848-5 limits are tens of mm), so 0.2 m is
/// a unit error — millimetres in a column without `_mm`.
pub const MAX_IRREGULARITY_M: f64 = 0.2;

/// A cant column: angles (`cant`, rad) or heights (`cant_mm`, converted to
/// metres on reading), with the line of each value for messages.
#[derive(Debug, Clone, PartialEq)]
pub struct CantColumn {
    path: PathBuf,
    lines: Vec<usize>,
    values: Vec<f64>,
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
        let scale = if is_height { 1e-3 } else { 1.0 };
        Ok(Some(Self {
            path: table.path.clone(),
            lines: table.rows.iter().map(|(l, _)| *l).collect(),
            values: table.rows.iter().map(|(_, v)| v[idx] * scale).collect(),
            is_height,
        }))
    }

    /// Cant angles φ (rad): heights convert by φ = asin(h / e0) (docs/reference/01-units-frames.md §1),
    /// `cant_base_m` = e0. Fails on the first value beyond ±0.3 rad or a
    /// height not smaller than e0.
    pub fn radians(&self, cant_base_m: f64) -> Result<Vec<f64>, InputError> {
        self.values
            .iter()
            .zip(&self.lines)
            .map(|(&v, &line)| {
                let phi = if self.is_height {
                    if v.abs() >= cant_base_m {
                        return Err(InputError::new(
                            &self.path,
                            Some(line),
                            format!(
                                "cant height {:.1} mm is not smaller than the cant base {:.1} mm",
                                v * 1e3,
                                cant_base_m * 1e3
                            ),
                        ));
                    }
                    (v / cant_base_m).asin()
                } else {
                    v
                };
                if phi.abs() > MAX_CANT_RAD {
                    return Err(InputError::new(
                        &self.path,
                        Some(line),
                        format!(
                            "cant {phi:.4} rad is beyond ±{MAX_CANT_RAD} rad (check the unit: 'cant' is in rad, 'cant_mm' in mm)"
                        ),
                    ));
                }
                Ok(phi)
            })
            .collect()
    }
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
}

const PER_RAIL: [&str; 4] = ["align_left", "align_right", "level_left", "level_right"];
const MEASUREMENT_CAR: [&str; 4] = ["alignment", "gauge", "level", "cross_level"];

impl IrregularityInput {
    /// Parse an irregularity CSV in either form of docs/reference/02-inputs.md §2:
    /// per rail `s, align_left, align_right, level_left, level_right`, or the
    /// measurement-car form `s, alignment, gauge, level, cross_level`, any
    /// column with an optional `_mm` suffix. The measurement-car form converts
    /// by (EN 13848-1 definitions, left minus right):
    /// `align_left = alignment + gauge/2`, `align_right = alignment − gauge/2`,
    /// `level_left = level + cross_level/2`, `level_right = level − cross_level/2`
    /// (gauge > 0 widens the track; cross_level > 0 raises the left rail).
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

        let read = |names: &[&str; 4]| -> Result<Vec<Option<Vec<f64>>>, InputError> {
            names
                .iter()
                .map(|n| {
                    Ok(find_length_column(&t, n)?
                        .map(|(i, f)| t.rows.iter().map(|(_, v)| v[i] * f).collect()))
                })
                .collect()
        };
        let per_rail = read(&PER_RAIL)?;
        let car = read(&MEASUREMENT_CAR)?;
        let any = |v: &[Option<Vec<f64>>]| v.iter().any(Option::is_some);
        let missing = |v: &[Option<Vec<f64>>], names: &[&str; 4]| -> Vec<String> {
            v.iter()
                .zip(names)
                .filter(|(c, _)| c.is_none())
                .map(|(_, n)| n.to_string())
                .collect()
        };
        let [al, ar, ll, lr]: [Vec<f64>; 4] = match (any(&per_rail), any(&car)) {
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
            (true, false) => {
                let m = missing(&per_rail, &PER_RAIL);
                if !m.is_empty() {
                    return Err(t.error(format!("missing column(s) {}", m.join(", "))));
                }
                let v: Vec<Vec<f64>> = per_rail.into_iter().flatten().collect();
                v.try_into().expect("four columns")
            }
            (false, true) => {
                let m = missing(&car, &MEASUREMENT_CAR);
                if !m.is_empty() {
                    return Err(t.error(format!("missing column(s) {}", m.join(", "))));
                }
                let v: Vec<Vec<f64>> = car.into_iter().flatten().collect();
                let (a, g, l, c) = (&v[0], &v[1], &v[2], &v[3]);
                let zip = |x: &Vec<f64>, y: &Vec<f64>, sign: f64| -> Vec<f64> {
                    x.iter().zip(y).map(|(x, y)| x + sign * 0.5 * y).collect()
                };
                [
                    zip(a, g, 1.0),
                    zip(a, g, -1.0),
                    zip(l, c, 1.0),
                    zip(l, c, -1.0),
                ]
            }
        };
        t.require_rows(MIN_ROWS)?;
        t.require_increasing(is)?;
        for (name, values) in [
            ("align_left", &al),
            ("align_right", &ar),
            ("level_left", &ll),
            ("level_right", &lr),
        ] {
            if let Some(k) = values.iter().position(|v| v.abs() > MAX_IRREGULARITY_M) {
                return Err(t.error_at(
                    k,
                    format!(
                        "{name} = {:.4e} m is beyond ±{MAX_IRREGULARITY_M} m (check the unit: columns without _mm are in metres)",
                        values[k]
                    ),
                ));
            }
        }
        Ok(Self {
            path: path.to_path_buf(),
            s_m: t.values(is),
            align_left_m: al,
            align_right_m: ar,
            level_left_m: ll,
            level_right_m: lr,
        })
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
            e.to_string().contains("line 4") && e.to_string().contains("0.3"),
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
            e.to_string().contains("line 3") && e.to_string().contains("align_left"),
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

    #[test]
    fn cant_table() {
        let c = CantInput::parse(p(), "s,cant\n0,0\n10,0.01\n20,0.02\n30,0.02\n").unwrap();
        assert_eq!(c.cant.radians(1.5).unwrap()[2], 0.02);
        let e = CantInput::parse(p(), "s\n0\n").unwrap_err();
        assert!(e.to_string().contains("cant"), "{e}");
    }
}
