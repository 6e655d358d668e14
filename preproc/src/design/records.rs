//! The plan elements of a design track as the table file records them
//! (`/design`, docs/reference/04-table-files.md §4.1): kind, track
//! distance s at both ends, signed radius and cant at both ends, and the
//! shapes. Over a stretch of the track (`sim run`'s in-memory tables) the
//! elements are clipped to the stretch and the radius and cant at a
//! clipped end are the element formulas' values there.

use runtime::geometry::track::{DesignElement, PlanElementKind};

use super::element::PlanShape;
use super::shape::Ramp;
use super::track::DesignTrack;

/// The signed radius 1/κ (m), +∞ where κ = 0 (a straight has no sign).
fn radius_m(kappa_1_m: f64) -> f64 {
    if kappa_1_m == 0.0 {
        f64::INFINITY
    } else {
        1.0 / kappa_1_m
    }
}

impl DesignTrack {
    /// The plan elements that overlap [s_from, s_to] (m), clipped to it;
    /// all of them, unclipped, for [0, length].
    pub fn plan_elements(&self, s_from_m: f64, s_to_m: f64) -> Vec<DesignElement> {
        let mut out = Vec::new();
        for (k, e) in self.elements.iter().enumerate() {
            let (s0, s1) = (self.joints_s_m[k], self.joints_s_m[k + 1]);
            let (a, b) = (s0.max(s_from_m), s1.min(s_to_m));
            if b <= a {
                continue;
            }
            // Curvature and cant at a track distance inside the element.
            let at = |s_m: f64| {
                let local =
                    (self.vertical.sigma_at(s_m) - self.sigma_start_m[k]).clamp(0.0, e.length_m);
                (
                    e.at(local).kappa_1_m,
                    self.cant[k].at(local / e.length_m, e.length_m).0,
                )
            };
            let (k_start, c_start) = match a > s0 {
                true => at(a),
                false => (e.kappa_start_1_m, self.cant[k].at(0.0, e.length_m).0),
            };
            let (k_end, c_end) = match b < s1 {
                true => at(b),
                false => (e.kappa_end_1_m, self.cant[k].at(1.0, e.length_m).0),
            };
            let (kind, shape) = match e.shape {
                PlanShape::Straight => (PlanElementKind::Straight, ""),
                PlanShape::Arc => (PlanElementKind::Arc, ""),
                PlanShape::Transition(Ramp::Linear) => (PlanElementKind::Transition, "clothoid"),
                PlanShape::Transition(r) => (PlanElementKind::Transition, r.name()),
                PlanShape::CubicParabola { .. } => (PlanElementKind::Transition, "cubic-parabola"),
            };
            out.push(DesignElement {
                kind,
                s_start_m: a,
                s_end_m: b,
                radius_start_m: radius_m(k_start),
                radius_end_m: radius_m(k_end),
                cant_start_rad: c_start,
                cant_end_rad: c_end,
                shape: shape.to_string(),
                cant_ramp: self.cant[k].ramp.name().to_string(),
            });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::design::DesignInput;

    const FILE: &str = r#"
[[element]]
type = "straight"
length_m = 100.0

[[element]]
type = "transition"
shape = "bloss"
length_m = 60.0
radius_end_m = -300.0
cant_end_mm = 90.0

[[element]]
type = "arc"
length_m = 100.0
radius_m = -300.0
"#;

    #[test]
    fn the_elements_are_recorded_whole_and_clipped_to_a_stretch() {
        let input = DesignInput::parse(Path::new("t.toml"), FILE, 1.5).unwrap();
        let track = DesignTrack::build(&input).unwrap();
        let all = track.plan_elements(0.0, track.length_m());
        let kinds: Vec<_> = all.iter().map(|e| e.kind).collect();
        use PlanElementKind::*;
        assert_eq!(kinds, [Straight, Transition, Arc]);
        assert_eq!((all[1].s_start_m, all[1].s_end_m), (100.0, 160.0));
        assert_eq!(all[0].radius_start_m, f64::INFINITY);
        assert_eq!(all[1].radius_start_m, f64::INFINITY);
        assert_eq!(all[1].radius_end_m, -300.0);
        assert_eq!(all[1].shape, "bloss");
        assert_eq!(all[2].shape, "");
        assert_eq!(all[1].cant_start_rad, 0.0);
        assert!((all[1].cant_end_rad - (0.09_f64 / 1.5).asin()).abs() < 1e-15);
        assert_eq!(all[2].cant_start_rad, all[2].cant_end_rad);
        // A stretch from the middle of the transition (u = 1/2: the Bloss
        // f = 1/2, curvature half the arc's) into the arc.
        let part = track.plan_elements(130.0, 200.0);
        assert_eq!(part.len(), 2, "{part:#?}");
        assert_eq!((part[0].s_start_m, part[0].s_end_m), (130.0, 160.0));
        assert!((part[0].radius_start_m + 600.0).abs() < 1e-9, "{part:?}");
        assert_eq!(part[0].radius_end_m, -300.0);
        assert!((part[0].cant_start_rad - (0.045_f64 / 1.5).asin()).abs() < 1e-15);
        assert_eq!((part[1].s_start_m, part[1].s_end_m), (160.0, 200.0));
        assert!(track.plan_elements(300.0, 400.0).is_empty());
    }
}
