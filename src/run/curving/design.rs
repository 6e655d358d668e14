//! The track's elements from its design file: when the track tables carry
//! the plan elements of the design file they were built from
//! (`/design`, docs/reference/04-table-files.md §4.1), the curving outputs
//! take them as they are — exact boundaries and radii, the arcs are the
//! design's arc elements — instead of finding them from the tabulated
//! curvature ([`super::elements`]; docs/guide/curving-and-safety.md,
//! "Finding the arcs").

use runtime::geometry::track::{DesignElement, PlanElementKind};
use serde::Serialize;

use super::elements::{ElementKind, TrackElement};

/// Where the track elements of the curving outputs come from.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum ElementSource {
    /// The design file's elements recorded with the tables.
    DesignFile,
    /// Found from the centreline table's curvature.
    #[default]
    Curvature,
}

impl ElementSource {
    /// The words of the text summary: "design file" / "from the curvature".
    pub fn text(self) -> &'static str {
        match self {
            ElementSource::DesignFile => "design file",
            ElementSource::Curvature => "from the curvature",
        }
    }
}

/// Signed curvature 1/R (1/m; 0 for an infinite radius).
fn curvature_1_m(radius_m: f64) -> f64 {
    if radius_m.is_finite() {
        1.0 / radius_m
    } else {
        0.0
    }
}

/// The design elements as track elements. The mean curvature of a
/// transition is the mean of its end curvatures (exact for a whole
/// clothoid, Bloss or cosine transition, whose ramps f(u) average 1/2; it
/// draws the curvature outline of the plot); an arc's radius is its
/// design radius.
pub fn from_design(elements: &[DesignElement]) -> Vec<TrackElement> {
    elements
        .iter()
        .map(|e| {
            let kind = match e.kind {
                PlanElementKind::Straight => ElementKind::Straight,
                PlanElementKind::Transition => ElementKind::Transition,
                PlanElementKind::Arc => ElementKind::Arc,
            };
            TrackElement {
                kind,
                start_s_m: e.s_start_m,
                end_s_m: e.s_end_m,
                mean_curvature_1_m: 0.5
                    * (curvature_1_m(e.radius_start_m) + curvature_1_m(e.radius_end_m)),
                radius_m: (kind == ElementKind::Arc).then_some(e.radius_start_m),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn design_elements_keep_their_boundaries_and_radii() {
        let e = |kind, a, b, r0: f64, r1: f64| DesignElement {
            kind,
            s_start_m: a,
            s_end_m: b,
            radius_start_m: r0,
            radius_end_m: r1,
            cant_start_rad: 0.0,
            cant_end_rad: 0.0,
            shape: String::new(),
            cant_ramp: "linear".into(),
        };
        use PlanElementKind::*;
        let t = from_design(&[
            e(Straight, 0.0, 200.0, f64::INFINITY, f64::INFINITY),
            e(Transition, 200.0, 280.0, f64::INFINITY, -600.0),
            e(Arc, 280.0, 580.0, -600.0, -600.0),
        ]);
        assert_eq!(t[0].mean_curvature_1_m, 0.0);
        assert_eq!(t[0].radius_m, None);
        assert_eq!(t[1].kind, ElementKind::Transition);
        assert_eq!(t[1].mean_curvature_1_m, -0.5 / 600.0);
        assert_eq!((t[2].start_s_m, t[2].end_s_m), (280.0, 580.0));
        assert_eq!(t[2].radius_m, Some(-600.0));
        assert_eq!(t[2].mean_curvature_1_m, -1.0 / 600.0);
    }
}
