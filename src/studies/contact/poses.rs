//! The poses file of `sim contact --poses` (docs/guide/contact-benchmark.md):
//! a CSV table with a header row, one pose per row.
//!
//! | column | unit | required | meaning |
//! |---|---|---|---|
//! | `y_mm` | mm | yes | lateral shift of the wheelset, positive to the left |
//! | `yaw_mrad` | mrad | yes | yaw, positive turning the nose to the left |
//! | `roll_rad` | rad | no | roll, positive raising the left wheel (else solved) |
//! | `axle_rate_rad_s` | rad/s | no | angular velocity of the axle, positive rolling forward (else V/r₀) |
//! | `speed_m_s` | m/s | no | forward speed (else `--speed-m-s`) |
//! | `vertical_force_per_wheel_n` | N | no | load of each wheel (else `--wheel-load-n`) |
//! | `case` | – | no | the pose's number in the output (else its row, from 1) |
//!
//! Comment lines start with `#`. An optional column is given for every row
//! or for none; a column not in this list is refused (a misspelt name must
//! not silently fall back to a default).

use std::path::Path;

use anyhow::{Result, bail};
use runtime::io::csv::{CsvTable, Separator};

/// One row of the poses file, in SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseRow {
    /// The pose's number (the `case` column, or its row from 1).
    pub case: u32,
    /// 1-based line of the file (for messages).
    pub line: usize,
    pub y_m: f64,
    pub yaw_rad: f64,
    pub roll_rad: Option<f64>,
    pub axle_rate_rad_s: Option<f64>,
    pub speed_m_s: Option<f64>,
    pub load_n: Option<f64>,
}

/// The columns a poses file may have.
pub const COLUMNS: [&str; 7] = [
    "case",
    "y_mm",
    "yaw_mrad",
    "roll_rad",
    "axle_rate_rad_s",
    "speed_m_s",
    "vertical_force_per_wheel_n",
];

/// Read the poses of `path`.
pub fn read_poses(path: &Path) -> Result<Vec<PoseRow>> {
    let table = CsvTable::read(path, Separator::Comma)?;
    parse_poses(&table)
}

/// The poses of a parsed table (pure).
pub fn parse_poses(table: &CsvTable) -> Result<Vec<PoseRow>> {
    let path = table.path.display();
    for (k, c) in table.columns.iter().enumerate() {
        if !COLUMNS.contains(&c.as_str()) {
            bail!(
                "{path}:{}: column {} '{c}' is not a poses column (expected some of: {})",
                table.header_line,
                k + 1,
                COLUMNS.join(", ")
            );
        }
    }
    let required = |name: &str| {
        table.column(name).ok_or_else(|| {
            anyhow::anyhow!(
                "{path}:{}: the poses file has no '{name}' column (columns: {})",
                table.header_line,
                table.columns.join(", ")
            )
        })
    };
    let (y, yaw) = (required("y_mm")?, required("yaw_mrad")?);
    let col = |name: &str| table.column(name);
    let (case, roll, rate, speed, load) = (
        col("case"),
        col("roll_rad"),
        col("axle_rate_rad_s"),
        col("speed_m_s"),
        col("vertical_force_per_wheel_n"),
    );
    if table.rows.is_empty() {
        bail!("{path}: the poses file has a header but no pose");
    }
    let mut out = Vec::with_capacity(table.rows.len());
    for (row, (line, v)) in table.rows.iter().enumerate() {
        let at = |k: usize| v[k];
        let number = match case {
            Some(k) => {
                let c = at(k);
                if !(c >= 0.0 && c.fract() == 0.0 && c < 1e9) {
                    bail!(
                        "{path}:{line}:{}: case '{c}' must be a whole number >= 0",
                        k + 1
                    );
                }
                c as u32
            }
            None => row as u32 + 1,
        };
        out.push(PoseRow {
            case: number,
            line: *line,
            y_m: at(y) * 1e-3,
            yaw_rad: at(yaw) * 1e-3,
            roll_rad: roll.map(at),
            axle_rate_rad_s: rate.map(at),
            speed_m_s: speed.map(at),
            load_n: load.map(at),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> CsvTable {
        CsvTable::parse(Path::new("p.csv"), text, Separator::Comma).expect("parses")
    }

    #[test]
    fn reads_required_and_optional_columns_in_si() {
        let t = table(
            "# A-2.2\ncase,y_mm,yaw_mrad,roll_rad,axle_rate_rad_s\n7,-3.0,-7.2,-0.00018,4.345\n",
        );
        let p = parse_poses(&t).expect("poses");
        assert_eq!(p.len(), 1);
        assert_eq!(p[0].case, 7);
        assert!((p[0].y_m + 0.003).abs() < 1e-15);
        assert!((p[0].yaw_rad + 0.0072).abs() < 1e-15);
        assert_eq!(p[0].roll_rad, Some(-0.00018));
        assert_eq!(p[0].axle_rate_rad_s, Some(4.345));
        assert_eq!(p[0].speed_m_s, None);
        assert_eq!(p[0].load_n, None);
    }

    #[test]
    fn unknown_or_missing_columns_are_refused() {
        let e = parse_poses(&table("y_mm,yaw_mrad,rol_rad\n1,2,3\n")).unwrap_err();
        assert!(
            e.to_string().contains("'rol_rad' is not a poses column"),
            "{e}"
        );
        let e = parse_poses(&table("y_mm,roll_rad\n1,2\n")).unwrap_err();
        assert!(e.to_string().contains("no 'yaw_mrad' column"), "{e}");
        let e = parse_poses(&table("y_mm,yaw_mrad\n")).unwrap_err();
        assert!(e.to_string().contains("no pose"), "{e}");
    }

    #[test]
    fn rows_are_numbered_from_one_without_a_case_column() {
        let p = parse_poses(&table("y_mm,yaw_mrad\n0,0\n1,1\n")).expect("poses");
        assert_eq!(p.iter().map(|r| r.case).collect::<Vec<_>>(), [1, 2]);
        assert_eq!(p[1].line, 3);
    }
}
