//! Checks on what a build produced, not only on its input
//! (docs/reference/03-track-preproc.md §3g, "Checks on the built tables"):
//! the tables' cant and irregularities within the bounds of
//! [`crate::bounds`] (a spline may overshoot inputs that are within them),
//! and the centreline and each rail as long as their table rows resolve
//! (geometry varying between rows is geometry the tables cannot show).

use nalgebra::Vector3;
use runtime::geometry::track::{CenterlineRow, TrackTables};

use crate::bounds::{LENGTH_TOLERANCE, MAX_CANT_RAD, MAX_IRREGULARITY_M};
use crate::centerline::CantPeak;
use crate::error::BuildError;

/// Check built `tables` (the whole track or a stretch of it); `cant_peak`
/// is the largest cant of the input, if it had one, and `scheme` the
/// spline scheme used (for the messages).
pub fn check_tables(
    tables: &TrackTables,
    cant_peak: Option<&CantPeak>,
    scheme: &str,
) -> Result<(), BuildError> {
    let rows = tables.centerline.rows();
    check_cant(rows, cant_peak, scheme, tables.meta.cant_base_m)?;
    check_irregularities(rows)?;
    check_lengths(rows, tables.meta.rail_spacing_m, tables.meta.step_m)
}

fn check_cant(
    rows: &[CenterlineRow],
    peak: Option<&CantPeak>,
    scheme: &str,
    cant_base_m: f64,
) -> Result<(), BuildError> {
    let Some(worst) = rows
        .iter()
        .max_by(|a, b| a.cant_rad.abs().total_cmp(&b.cant_rad.abs()))
    else {
        return Ok(());
    };
    if worst.cant_rad.abs() <= MAX_CANT_RAD {
        return Ok(());
    }
    let input = match peak {
        Some(p) => format!(
            "the input's largest cant is {:.4} rad ({}, line {}), within the bound: the {scheme} spline overshoots it by {:.4} rad between the control points. Use --cant-scheme pchip (the default; shape-preserving, no overshoot), or add control points along the cant ramps",
            p.cant_rad,
            p.path.display(),
            p.line,
            worst.cant_rad.abs() - p.cant_rad
        ),
        None => "the track has no cant input".into(),
    };
    Err(BuildError::BuiltCant {
        s_m: worst.s_m,
        cant_rad: worst.cant_rad,
        cant_mm: cant_base_m * worst.cant_rad.sin() * 1e3,
        bound_rad: MAX_CANT_RAD,
        input,
    })
}

fn check_irregularities(rows: &[CenterlineRow]) -> Result<(), BuildError> {
    for r in rows {
        for (component, v) in [
            ("align_left", r.align_left_m),
            ("align_right", r.align_right_m),
            ("level_left", r.level_left_m),
            ("level_right", r.level_right_m),
        ] {
            if v.abs() > MAX_IRREGULARITY_M {
                return Err(BuildError::BuiltIrregularity {
                    component,
                    s_m: r.s_m,
                    value_m: v,
                    bound_m: MAX_IRREGULARITY_M,
                });
            }
        }
    }
    Ok(())
}

/// A curve as its table rows resolve it: the polygon through its points
/// at every row (`fine`) and at every other row (`coarse`).
#[derive(Debug, Clone, Copy, Default)]
struct Polygon {
    fine_m: f64,
    coarse_m: f64,
}

impl Polygon {
    fn through(points: &[Vector3<f64>]) -> Self {
        let len = |pts: &mut dyn Iterator<Item = &Vector3<f64>>| {
            let mut prev: Option<&Vector3<f64>> = None;
            let mut total = 0.0;
            for p in pts {
                if let Some(q) = prev {
                    total += (p - q).norm();
                }
                prev = Some(p);
            }
            total
        };
        let last = points.len().saturating_sub(1);
        Self {
            fine_m: len(&mut points.iter()),
            coarse_m: len(&mut points
                .iter()
                .enumerate()
                .filter(|(k, _)| k % 2 == 0 || *k == last)
                .map(|(_, p)| p)),
        }
    }

    /// The curve's length from the two polygons: a polygon of chords h
    /// falls short of the arc by κ²h²/24 per unit length, so
    /// Richardson's extrapolation `fine + (fine − coarse)/3` removes that
    /// term (docs/reference/03-track-preproc.md §3g).
    fn length_m(&self) -> f64 {
        self.fine_m + (self.fine_m - self.coarse_m) / 3.0
    }

    /// The discretisation error of the fine polygon, estimated by its
    /// difference from the coarse one (three times the error it removes).
    fn uncertainty_m(&self) -> f64 {
        (self.fine_m - self.coarse_m).abs()
    }
}

/// The centreline (its rows' s) and each rail (its s → L mapping at the
/// rows) must be as long as the polygons through the rows resolve,
/// within [`LENGTH_TOLERANCE`] plus the polygons' own discretisation
/// error. The rails' points are the nodal-point formula of
/// docs/reference/03-track-preproc.md §3e at the rows: the rail as the tables show it.
fn check_lengths(
    rows: &[CenterlineRow],
    rail_spacing_m: f64,
    step_m: f64,
) -> Result<(), BuildError> {
    let (Some(first), Some(last)) = (rows.first(), rows.last()) else {
        return Ok(());
    };
    let half = 0.5 * rail_spacing_m;
    let point = |r: &CenterlineRow, lateral: f64, vertical: f64| {
        Vector3::from(r.position) + Vector3::from(r.n) * lateral + Vector3::from(r.b) * vertical
    };
    let centreline_m = last.s_m - first.s_m;
    let curves: [(&'static str, f64, Vec<Vector3<f64>>); 3] = [
        (
            "centreline",
            centreline_m,
            rows.iter().map(|r| point(r, 0.0, 0.0)).collect(),
        ),
        (
            "left rail",
            last.l_left_m - first.l_left_m,
            rows.iter()
                .map(|r| point(r, half + r.align_left_m, r.level_left_m))
                .collect(),
        ),
        (
            "right rail",
            last.l_right_m - first.l_right_m,
            rows.iter()
                .map(|r| point(r, -half + r.align_right_m, r.level_right_m))
                .collect(),
        ),
    ];
    for (what, built_m, points) in curves {
        let p = Polygon::through(&points);
        let resolved_m = p.length_m();
        let tolerance_m = LENGTH_TOLERANCE * centreline_m.abs() + p.uncertainty_m() + 1e-9;
        if (built_m - resolved_m).abs() > tolerance_m {
            return Err(BuildError::Length {
                what,
                built_m,
                resolved_m,
                centreline_m,
                tolerance_m,
                step_m,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};

    use super::*;
    use crate::inputs::CenterlineInput;
    use crate::{BuildConfig, NoProgress, TrackInputs, TrackModel};

    /// The tables of a 60 m arc of radius 300 m (control points every 2 m).
    fn arc_tables() -> TrackTables {
        let mut csv = String::from("x,y,z\n");
        for i in 0..=30 {
            let phi = 2.0 * f64::from(i) / 300.0;
            csv += &format!("{},{},0\n", 300.0 * phi.sin(), 300.0 * (1.0 - phi.cos()));
        }
        let inputs = TrackInputs {
            centerline: CenterlineInput::parse(Path::new("c.csv"), &csv).unwrap(),
            cant: None,
            irregularities: None,
        };
        TrackModel::build(&inputs, &BuildConfig::default())
            .unwrap()
            .tabulate(&NoProgress)
            .unwrap()
    }

    /// Sound tables pass; a rail 3 % longer than its rows (its s → L
    /// mapping stretched, as when the rail follows irregularities the
    /// rows miss) is refused, naming the rail and both lengths. The right
    /// rail is the outer one: 60 m × (1 + 0.7535/300) = 60.151 m.
    #[test]
    fn a_rail_longer_than_its_rows_is_refused() {
        let t = arc_tables();
        check_tables(&t, None, "cubic").unwrap();
        let mut rows = t.centerline.rows().to_vec();
        for r in &mut rows {
            r.l_right_m *= 1.03;
        }
        let e = check_lengths(&rows, t.meta.rail_spacing_m, t.meta.step_m)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("the right rail is 61.955 m long but its table rows resolve 60.151 m"),
            "{e}"
        );
    }

    /// The polygon extrapolation recovers the arc of a circle from coarse
    /// chords: 90° of R = 10 m in 1 m chords to 1e-6 relative.
    #[test]
    fn polygon_length_of_an_arc() {
        let r = 10.0;
        let n = 16;
        let pts: Vec<Vector3<f64>> = (0..=n)
            .map(|k| {
                let a = std::f64::consts::FRAC_PI_2 * k as f64 / n as f64;
                Vector3::new(r * a.sin(), r * (1.0 - a.cos()), 0.0)
            })
            .collect();
        let p = Polygon::through(&pts);
        let exact = r * std::f64::consts::FRAC_PI_2;
        assert!(p.fine_m < exact);
        assert!(
            (p.length_m() - exact).abs() < 1e-5 * exact,
            "{}",
            p.length_m()
        );
        assert!(p.uncertainty_m() > (p.length_m() - exact).abs());
    }

    /// A built cant beyond the bound is refused at its s, with the input's
    /// peak and the pchip advice; irregularities likewise.
    #[test]
    fn built_values_beyond_the_bounds() {
        let t = arc_tables();
        let mut rows = t.centerline.rows().to_vec();
        rows[100].cant_rad = 0.14;
        let peak = CantPeak {
            cant_rad: 0.13,
            path: PathBuf::from("cant.csv"),
            line: 7,
        };
        let e = check_cant(&rows, Some(&peak), "cubic", 1.5)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("reaches +0.1400 rad (+209.3 mm) at s = 10.000 m")
                && e.contains("cant.csv, line 7")
                && e.contains("overshoots it by 0.0100 rad")
                && e.contains("--cant-scheme pchip"),
            "{e}"
        );
        rows[100].cant_rad = 0.0;
        rows[50].level_right_m = -0.06;
        let e = check_irregularities(&rows).unwrap_err().to_string();
        assert!(
            e.contains("level_right reaches -60.0 mm at s = 5.000 m"),
            "{e}"
        );
    }
}
