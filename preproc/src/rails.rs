//! The two rails (paper §2e–f, docs/reference/03-track-preproc.md §3e–f): nodal points offset from the
//! centreline by half the rail spacing along the track's lateral vector plus
//! the irregularities, re-fitted with the chosen scheme, parameterised by
//! each rail's own arc length L, with their own frames (cant and rail
//! inclination).

use nalgebra::Vector3;
use runtime::geometry::spline::{PiecewiseCubic, Scheme};
use runtime::geometry::track::{Frame, Side, rail_roll_rad};

use crate::centerline::Centerline;
use crate::error::BuildError;
use crate::irregularity::Irregularities;
use crate::space_curve::{CurvePoint, SpaceCurve};

/// Coarsest spacing of the rail nodal points (m). Nodes are also no coarser
/// than the closest control points and the irregularity samples.
pub const MAX_NODE_SPACING_M: f64 = 1.0;

/// A rail at one arc length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailSample {
    /// Rail arc length (m).
    pub l_m: f64,
    /// Track distance of the centreline point this rail point belongs to (m).
    pub s_m: f64,
    /// Position and τ-derivatives.
    pub point: CurvePoint,
    /// Rail frame (cant ± inclination).
    pub frame: Frame,
}

/// One fitted rail.
#[derive(Debug, Clone)]
pub struct Rail {
    side: Side,
    curve: SpaceCurve,
    /// Rail arc length at each node against the node's track distance, and
    /// the inverse (not-a-knot cubic splines; both monotone).
    l_of_s: PiecewiseCubic,
    s_of_l: PiecewiseCubic,
    inclination_rad: f64,
}

/// Spacing of the rail nodal points for this track (m): no coarser than
/// [`MAX_NODE_SPACING_M`], the closest control points or the irregularity
/// samples.
pub fn node_spacing_m(centerline: &Centerline, irregularities: Option<&Irregularities>) -> f64 {
    let control = centerline
        .control_point_s()
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let irr = irregularities.map_or(f64::INFINITY, Irregularities::min_spacing_m);
    MAX_NODE_SPACING_M.min(control).min(irr)
}

impl Rail {
    /// Build rail `side` from nodes every `node_spacing_m` (at most; the
    /// spacing is shrunk to divide the track evenly).
    pub fn build(
        side: Side,
        centerline: &Centerline,
        irregularities: Option<&Irregularities>,
        rail_spacing_m: f64,
        node_spacing_m: f64,
        scheme: Scheme,
        inclination_rad: f64,
    ) -> Result<Self, BuildError> {
        let length = centerline.length_m();
        let intervals = ((length / node_spacing_m).ceil() as usize).max(3);
        let s_nodes: Vec<f64> = (0..=intervals)
            .map(|j| length * j as f64 / intervals as f64)
            .collect();
        let half = 0.5 * rail_spacing_m * side.sign();
        let nodes: Vec<[f64; 3]> = centerline
            .sample(&s_nodes)?
            .iter()
            .map(|c| {
                let d = irregularities.map(|i| i.at(c.s_m)).unwrap_or_default();
                let (align, level) = match side {
                    Side::Left => (d.align_left_m, d.level_left_m),
                    Side::Right => (d.align_right_m, d.level_right_m),
                };
                let p = c.point.r + c.frame.n * (half + align) + c.frame.b * level;
                [p.x, p.y, p.z]
            })
            .collect();
        let curve = SpaceCurve::fit(scheme, &nodes).map_err(|e| {
            BuildError::Geometry(format!(
                "the {} cannot be fitted through its nodal points: {e} (is the curve radius smaller than half the rail spacing?)",
                side.rail_name()
            ))
        })?;
        let l_nodes = curve.knot_arc_lengths().to_vec();
        let spline = |x: &[f64], y: &[f64], what: &str| {
            PiecewiseCubic::fit(Scheme::Cubic, x, y).map_err(|source| BuildError::Spline {
                what: format!("{} {what}", side.rail_name()),
                source,
            })
        };
        Ok(Self {
            side,
            l_of_s: spline(&s_nodes, &l_nodes, "L(s) mapping")?,
            s_of_l: spline(&l_nodes, &s_nodes, "s(L) mapping")?,
            curve,
            inclination_rad,
        })
    }

    /// Which rail.
    pub fn side(&self) -> Side {
        self.side
    }

    /// Length of the rail (m).
    pub fn length_m(&self) -> f64 {
        self.curve.length()
    }

    /// Rail arc length at centreline distance `s_m` (m).
    pub fn l_at_s(&self, s_m: f64) -> f64 {
        self.l_of_s.value(s_m)
    }

    /// Centreline distance at rail arc length `l_m` (m).
    pub fn s_at_l(&self, l_m: f64) -> f64 {
        self.s_of_l.value(l_m)
    }

    /// Rail position at centreline distance `s_m` (m), from the splines.
    pub fn position_at_s(&self, s_m: f64) -> Vector3<f64> {
        self.curve.at_arc_length(self.l_at_s(s_m)).r
    }

    /// The rail at the increasing arc lengths `l`.
    pub fn sample(
        &self,
        l: &[f64],
        centerline: &Centerline,
    ) -> Result<Vec<RailSample>, BuildError> {
        self.curve
            .at_arc_lengths(l)
            .into_iter()
            .zip(l)
            .map(|(point, &l_m)| {
                let s_m = self.s_at_l(l_m);
                let roll = rail_roll_rad(self.side, centerline.cant_at(s_m), self.inclination_rad);
                let frame = Frame::from_tangent(point.d1, roll).ok_or_else(|| {
                    BuildError::Geometry(format!(
                        "the {} is vertical at L = {l_m:.3} m",
                        self.side.rail_name()
                    ))
                })?;
                Ok(RailSample {
                    l_m,
                    s_m,
                    point,
                    frame,
                })
            })
            .collect()
    }
}
