//! The continuous track model — centreline, irregularities and both rails as
//! splines — and its tabulation into the databases of paper Fig. 1.

use rayon::prelude::*;
use runtime::geometry::track::{
    CenterlineRow, CenterlineTable, DesignElement, RailRow, RailTable, Side, TrackMeta, TrackTables,
};

use crate::centerline::Centerline;
use crate::config::BuildConfig;
use crate::design::{DesignInput, DesignTrack};
use crate::error::BuildError;
use crate::inputs::{CantInput, CenterlineInput, IrregularityInput};
use crate::irregularity::Irregularities;
use crate::progress::{Progress, ProgressSink};
use crate::rails::{Rail, node_spacing_m};

/// The `cant_scheme` a table file records for a track from design
/// elements: the cant is the elements' formulas, not a spline.
pub const DESIGN_CANT_SCHEME: &str = "design";

/// Rows computed per parallel task.
const CHUNK_ROWS: usize = 1 << 15;

/// Most rows of one table, and most rail nodal points, a build accepts:
/// 2 × 10⁷ (2000 km at the default 0.1 m step; the three tables alone are
/// then 7.8 GB, at 184 + 2 × 104 bytes per row).
pub const MAX_TABLE_ROWS: f64 = 2e7;

/// Refuses `what` if `length_m / spacing_m` rows would exceed
/// [`MAX_TABLE_ROWS`] (or is not finite).
fn check_rows(
    what: &'static str,
    length_m: f64,
    spacing_m: f64,
    hint: &'static str,
) -> Result<(), BuildError> {
    let rows = length_m / spacing_m;
    if rows.is_finite() && rows <= MAX_TABLE_ROWS {
        Ok(())
    } else {
        Err(BuildError::TooLarge {
            what,
            length_m,
            spacing_m,
            rows,
            max: MAX_TABLE_ROWS,
            hint,
        })
    }
}

/// Refuses a build whose tables or rail nodes would exceed
/// [`MAX_TABLE_ROWS`] (a track of 10⁹ m, or control points 10⁻⁸ m apart).
fn check_size(length_m: f64, step_m: f64, node_spacing_m: f64) -> Result<(), BuildError> {
    check_rows(
        "track tables",
        length_m,
        step_m,
        "use a larger --step or split the track",
    )?;
    check_rows(
        "rail nodal points (one per closest control-point spacing)",
        length_m,
        node_spacing_m,
        "remove control points that almost repeat, or split the track",
    )
}

/// The parsed inputs of a build.
#[derive(Debug, Clone)]
pub struct TrackInputs {
    pub centerline: CenterlineInput,
    pub cant: Option<CantInput>,
    pub irregularities: Option<IrregularityInput>,
}

/// The parsed inputs of a build from a design file.
#[derive(Debug, Clone)]
pub struct DesignInputs {
    pub design: DesignInput,
    pub irregularities: Option<IrregularityInput>,
}

/// The parsed inputs of either kind of build.
#[derive(Debug, Clone)]
pub enum Inputs {
    /// Control points (and a cant table).
    ControlPoints(Box<TrackInputs>),
    /// Design elements (docs/reference/03-track-preproc.md §3h).
    Design(Box<DesignInputs>),
}

/// The track as continuous curves.
#[derive(Debug, Clone)]
pub struct TrackModel {
    pub config: BuildConfig,
    pub centerline: Centerline,
    pub irregularities: Option<Irregularities>,
    pub left: Rail,
    pub right: Rail,
}

impl TrackModel {
    /// Fit every curve of the track (paper §2a–f).
    pub fn build(inputs: &TrackInputs, config: &BuildConfig) -> Result<Self, BuildError> {
        config.validate()?;
        let centerline = Centerline::build(
            &inputs.centerline,
            inputs.cant.as_ref(),
            config.scheme,
            config.cant_scheme,
            config.cant_base_m(),
        )?;
        Self::around(centerline, inputs.irregularities.as_ref(), config)
    }

    /// The track of a design file (docs/reference/03-track-preproc.md
    /// §3h): the centreline from the element formulas, the rails built
    /// around it as for control points.
    pub fn build_design(inputs: &DesignInputs, config: &BuildConfig) -> Result<Self, BuildError> {
        config.validate()?;
        let centerline = Centerline::from_design(DesignTrack::build(&inputs.design)?);
        Self::around(centerline, inputs.irregularities.as_ref(), config)
    }

    /// Either kind of build.
    pub fn from_inputs(inputs: &Inputs, config: &BuildConfig) -> Result<Self, BuildError> {
        match inputs {
            Inputs::ControlPoints(i) => Self::build(i, config),
            Inputs::Design(i) => Self::build_design(i, config),
        }
    }

    /// Irregularities and rails around a centreline.
    fn around(
        centerline: Centerline,
        irregularities: Option<&IrregularityInput>,
        config: &BuildConfig,
    ) -> Result<Self, BuildError> {
        let irregularities = irregularities
            .map(|i| Irregularities::build(i, centerline.length_m(), config.step_m))
            .transpose()?;
        let spacing = node_spacing_m(&centerline, irregularities.as_ref());
        check_size(centerline.length_m(), config.step_m, spacing)?;
        let rail = |side| {
            Rail::build(
                side,
                &centerline,
                irregularities.as_ref(),
                config.rail_spacing_m(),
                spacing,
                config.scheme,
                config.inclination.angle_rad,
            )
        };
        let (left, right) = rayon::join(|| rail(Side::Left), || rail(Side::Right));
        Ok(Self {
            config: config.clone(),
            centerline,
            irregularities,
            left: left?,
            right: right?,
        })
    }

    /// One rail.
    pub fn rail(&self, side: Side) -> &Rail {
        match side {
            Side::Left => &self.left,
            Side::Right => &self.right,
        }
    }

    /// Sample the model every `config.step_m` into the centreline and rail
    /// databases (in parallel chunks), and check what is built
    /// ([`crate::built`]).
    pub fn tabulate(&self, progress: &dyn ProgressSink) -> Result<TrackTables, BuildError> {
        let step = self.config.step_m;
        let s_grid = grid(self.centerline.length_m(), step);
        progress.event(Progress::Stage {
            name: "centerline",
            rows: s_grid.len() as u64,
        });
        let mut rows = vec![CenterlineRow::default(); s_grid.len()];
        rows.par_chunks_mut(CHUNK_ROWS)
            .zip(s_grid.par_chunks(CHUNK_ROWS))
            .try_for_each(|(out, s)| {
                self.centerline_rows(s, out)?;
                progress.event(Progress::Rows(s.len() as u64));
                Ok::<_, BuildError>(())
            })?;
        let centerline = CenterlineTable::new(rows)
            .map_err(|e| BuildError::Geometry(format!("centreline table: {e}")))?;

        let mut rails = Vec::with_capacity(2);
        for side in Side::BOTH {
            let rail = self.rail(side);
            let l_grid = grid(rail.length_m(), step);
            progress.event(Progress::Stage {
                name: side.rail_name(),
                rows: l_grid.len() as u64,
            });
            let mut rows = vec![RailRow::default(); l_grid.len()];
            rows.par_chunks_mut(CHUNK_ROWS)
                .zip(l_grid.par_chunks(CHUNK_ROWS))
                .try_for_each(|(out, l)| {
                    self.rail_rows(side, l, out)?;
                    progress.event(Progress::Rows(l.len() as u64));
                    Ok::<_, BuildError>(())
                })?;
            rails.push(
                RailTable::new(side, rows).map_err(|e| {
                    BuildError::Geometry(format!("{} table: {e}", side.rail_name()))
                })?,
            );
        }
        let right = rails.pop().expect("two rails");
        let left = rails.pop().expect("two rails");
        let (s_lo, s_hi) = centerline.range_m();
        let tables = TrackTables {
            meta: self.meta(),
            centerline,
            left,
            right,
            design_elements: self.design_elements(s_lo, s_hi),
        };
        self.check(&tables)?;
        Ok(tables)
    }

    /// The plan elements of a design track over [s_from, s_to] (m; the
    /// tables' range), clipped to it; none for a track from control points.
    fn design_elements(&self, s_from_m: f64, s_to_m: f64) -> Vec<DesignElement> {
        self.centerline
            .design()
            .map(|d| d.plan_elements(s_from_m, s_to_m))
            .unwrap_or_default()
    }

    /// The checks on what is built ([`crate::built`]).
    fn check(&self, tables: &TrackTables) -> Result<(), BuildError> {
        crate::built::check_tables(
            tables,
            self.centerline.cant_peak(),
            self.config.cant_scheme.name(),
        )
    }

    /// The tables over the stretch `[s_from_m, s_to_m]` of the centreline
    /// only (m; clipped to the track): the rows of the whole-track grid
    /// (abscissae k·h of s and of each rail's L, see [`grid`]) that cover
    /// the stretch, one row beyond each end, computed exactly as
    /// [`TrackModel::tabulate`] computes them, so they equal the
    /// whole-track table's rows. Used for a run that covers only part of a
    /// long track (`sim run`'s planner). `tool` names the producer in the
    /// tables' metadata. The checks of [`crate::built`] apply to the
    /// stretch.
    pub fn tabulate_range(
        &self,
        s_from_m: f64,
        s_to_m: f64,
        tool: &str,
    ) -> Result<TrackTables, BuildError> {
        let h = self.config.step_m;
        let length = self.centerline.length_m();
        let (a, b) = (s_from_m.max(0.0), s_to_m.min(length));
        if b <= a + h || !(s_from_m.is_finite() && s_to_m.is_finite()) {
            return Err(BuildError::Geometry(format!(
                "the stretch {s_from_m} … {s_to_m} m leaves less than one table step ({h} m) of the {length:.1} m track"
            )));
        }
        // The grid points that bracket [lo, hi].
        let window = |grid: Vec<f64>, lo: f64, hi: f64| -> Vec<f64> {
            let first = grid.iter().rposition(|&x| x <= lo).unwrap_or(0);
            let last = grid.iter().position(|&x| x >= hi).unwrap_or(grid.len() - 1);
            grid[first..=last].to_vec()
        };
        let s = window(grid(length, h), a, b);
        let mut rows = vec![CenterlineRow::default(); s.len()];
        self.centerline_rows(&s, &mut rows)?;
        let centerline = CenterlineTable::new(rows)
            .map_err(|e| BuildError::Geometry(format!("centreline table of the stretch: {e}")))?;
        let (s_lo, s_hi) = (s[0], s[s.len() - 1]);
        let mut rails = Vec::with_capacity(2);
        for side in Side::BOTH {
            let rail = self.rail(side);
            let l = window(
                grid(rail.length_m(), h),
                rail.l_at_s(s_lo),
                rail.l_at_s(s_hi),
            );
            let mut rows = vec![RailRow::default(); l.len()];
            self.rail_rows(side, &l, &mut rows)?;
            rails.push(RailTable::new(side, rows).map_err(|e| {
                BuildError::Geometry(format!("{} table of the stretch: {e}", side.rail_name()))
            })?);
        }
        let right = rails.pop().expect("two rails");
        let left = rails.pop().expect("two rails");
        let mut meta = self.meta();
        meta.tool = tool.to_string();
        let tables = TrackTables {
            meta,
            centerline,
            left,
            right,
            design_elements: self.design_elements(s_lo, s_hi),
        };
        self.check(&tables)?;
        Ok(tables)
    }

    /// Rail rows at the rail's own arc lengths `l` (m).
    fn rail_rows(&self, side: Side, l: &[f64], out: &mut [RailRow]) -> Result<(), BuildError> {
        for (o, r) in out
            .iter_mut()
            .zip(self.rail(side).sample(l, &self.centerline)?)
        {
            *o = RailRow {
                l_m: r.l_m,
                position: r.point.r.into(),
                t: r.frame.t.into(),
                n: r.frame.n.into(),
                b: r.frame.b.into(),
            };
        }
        Ok(())
    }

    fn centerline_rows(&self, s: &[f64], out: &mut [CenterlineRow]) -> Result<(), BuildError> {
        for (o, c) in out.iter_mut().zip(self.centerline.sample(s)?) {
            *o = {
                let d = self
                    .irregularities
                    .as_ref()
                    .map(|i| i.at(c.s_m))
                    .unwrap_or_default();
                CenterlineRow {
                    s_m: c.s_m,
                    position: c.point.r.into(),
                    t: c.frame.t.into(),
                    n: c.frame.n.into(),
                    b: c.frame.b.into(),
                    cant_rad: c.cant_rad,
                    curvature_1_m: c.point.curvature(),
                    horizontal_curvature_1_m: c.point.horizontal_curvature(),
                    torsion_1_m: c.point.torsion(),
                    l_left_m: self.left.l_at_s(c.s_m),
                    l_right_m: self.right.l_at_s(c.s_m),
                    align_left_m: d.align_left_m,
                    align_right_m: d.align_right_m,
                    level_left_m: d.level_left_m,
                    level_right_m: d.level_right_m,
                }
            };
        }
        Ok(())
    }

    fn meta(&self) -> TrackMeta {
        let c = &self.config;
        TrackMeta {
            scheme: c.scheme.name().to_string(),
            cant_scheme: match self.centerline.design() {
                Some(_) => DESIGN_CANT_SCHEME.to_string(),
                None => c.cant_scheme.name().to_string(),
            },
            step_m: c.step_m,
            gauge_m: c.gauge_m,
            rail_spacing_m: c.rail_spacing_m(),
            cant_base_m: c.cant_base_m(),
            rail_inclination: c.inclination.text.clone(),
            rail_inclination_rad: c.inclination.angle_rad,
            rail_profile: None,
            tool: "track-preproc".into(),
            tool_version: env!("CARGO_PKG_VERSION").into(),
        }
    }
}

/// Table abscissae 0, h, 2h, … and the end `length` itself (the last
/// interval may be shorter; a remainder below 1e-6·h is merged).
pub fn grid(length: f64, step: f64) -> Vec<f64> {
    let n = (length / step).floor() as usize;
    let mut g: Vec<f64> = (0..=n).map(|k| k as f64 * step).collect();
    let last = g[g.len() - 1];
    if length - last > 1e-6 * step {
        g.push(length);
    } else {
        let k = g.len() - 1;
        g[k] = length;
        if k == 0 {
            g.push(length);
        }
    }
    g
}

#[cfg(test)]
mod tests {
    use super::{BuildError, MAX_TABLE_ROWS, check_size, grid};

    #[test]
    fn oversized_builds_are_refused_before_allocating() {
        assert!(check_size(100e3, 0.1, 1.0).is_ok());
        let e = check_size(3e9, 0.1, 1.0).unwrap_err();
        assert!(
            matches!(e, BuildError::TooLarge { what: "track tables", rows, .. } if rows > MAX_TABLE_ROWS),
            "{e}"
        );
        assert!(e.to_string().contains("--step"), "{e}");
        let e = check_size(3000.0, 0.1, 1e-8).unwrap_err();
        assert!(e.to_string().contains("rail nodal points"), "{e}");
        assert!(check_size(f64::INFINITY, 0.1, 1.0).is_err());
    }

    #[test]
    fn grid_ends_at_the_length() {
        assert_eq!(grid(1.0, 0.25), vec![0.0, 0.25, 0.5, 0.75, 1.0]);
        let g = grid(1.1, 0.25);
        assert_eq!(g.len(), 6);
        assert_eq!(*g.last().unwrap(), 1.1);
        let g = grid(1.0 + 1e-9, 0.25);
        assert_eq!(g.len(), 5);
        assert_eq!(*g.last().unwrap(), 1.0 + 1e-9);
    }
}
