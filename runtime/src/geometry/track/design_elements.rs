//! The plan elements of a track built from a design file (straights,
//! transitions, arcs with their radii and cant at the ends), kept with its
//! tables so that the outputs of a run can use the design's exact element
//! boundaries instead of finding them from the tabulated curvature
//! (docs/reference/04-table-files.md §4.1, group `/design`). A vertical
//! curve or grade is not a plan element. Tracks from control points have
//! none.

/// Kind of a plan element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanElementKind {
    Straight,
    Transition,
    Arc,
}

impl PlanElementKind {
    /// The word stored in the table file (`/design/kind`).
    pub fn name(self) -> &'static str {
        match self {
            PlanElementKind::Straight => "straight",
            PlanElementKind::Transition => "transition",
            PlanElementKind::Arc => "arc",
        }
    }

    /// The kind named `name` (the words of [`PlanElementKind::name`]).
    pub fn from_name(name: &str) -> Option<Self> {
        [Self::Straight, Self::Transition, Self::Arc]
            .into_iter()
            .find(|k| k.name() == name)
    }
}

/// One plan element over [s_start, s_end] of the track distance s.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignElement {
    pub kind: PlanElementKind,
    /// Track distance s at its start and end (m).
    pub s_start_m: f64,
    pub s_end_m: f64,
    /// Signed plan radius at the start and end (m; > 0 turning left,
    /// ±∞ on a straight and at a transition's straight end).
    pub radius_start_m: f64,
    pub radius_end_m: f64,
    /// Cant φ at the start and end (rad; > 0 left rail higher).
    pub cant_start_rad: f64,
    pub cant_end_rad: f64,
    /// Shape of a transition's curvature ("clothoid", "cubic-parabola",
    /// "bloss", "cosine", the design file's words); empty for straights
    /// and arcs.
    pub shape: String,
    /// Shape of the cant ramp over the element ("linear", "bloss",
    /// "cosine").
    pub cant_ramp: String,
}

/// Largest |cant| accepted when reading (rad): 0.2 rad is 290 mm over a
/// 1.5 m cant base, above any cant in service (EN 13803 limits it to
/// 180–200 mm); a larger value is a cant in mm or degrees.
pub const MAX_CANT_RAD: f64 = 0.2;
/// Smallest |radius| accepted when reading (m): the smallest radius a
/// design file accepts (docs/reference/02-inputs.md §2.9).
pub const MIN_RADIUS_M: f64 = 10.0;
/// Gap or overlap accepted between consecutive elements (m).
pub const JOINT_TOLERANCE_M: f64 = 1e-6;

/// The first rule `elements` break, as "element k: …": each element's s
/// finite with s_start < s_end, consecutive elements meeting at their
/// joints, radii not NaN and |R| ≥ [`MIN_RADIUS_M`], cants finite with
/// |φ| ≤ [`MAX_CANT_RAD`].
pub fn check_design_elements(elements: &[DesignElement]) -> Result<(), String> {
    for (k, e) in elements.iter().enumerate() {
        let at = |rule: String| Err(format!("element {k} ({}): {rule}", e.kind.name()));
        if !(e.s_start_m.is_finite() && e.s_end_m.is_finite() && e.s_start_m < e.s_end_m) {
            return at(format!(
                "s runs from {} to {} m, not forwards",
                e.s_start_m, e.s_end_m
            ));
        }
        if let Some(p) = k.checked_sub(1).map(|p| &elements[p])
            && (e.s_start_m - p.s_end_m).abs() > JOINT_TOLERANCE_M
        {
            return at(format!(
                "starts at s = {} m but the element before ends at {} m",
                e.s_start_m, p.s_end_m
            ));
        }
        for r in [e.radius_start_m, e.radius_end_m] {
            if r.is_nan() || r.abs() < MIN_RADIUS_M {
                return at(format!(
                    "radius {r} m is below {MIN_RADIUS_M} m (check the unit: metres)"
                ));
            }
        }
        for c in [e.cant_start_rad, e.cant_end_rad] {
            if !c.is_finite() || c.abs() > MAX_CANT_RAD {
                return at(format!(
                    "cant {c} rad exceeds {MAX_CANT_RAD} rad (check the unit: radians)"
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(from: f64, to: f64) -> DesignElement {
        DesignElement {
            kind: PlanElementKind::Arc,
            s_start_m: from,
            s_end_m: to,
            radius_start_m: -600.0,
            radius_end_m: -600.0,
            cant_start_rad: 0.08,
            cant_end_rad: 0.08,
            shape: String::new(),
            cant_ramp: "linear".into(),
        }
    }

    #[test]
    fn kinds_round_trip_their_names_and_bad_elements_are_refused() {
        for k in [
            PlanElementKind::Straight,
            PlanElementKind::Transition,
            PlanElementKind::Arc,
        ] {
            assert_eq!(PlanElementKind::from_name(k.name()), Some(k));
        }
        assert_eq!(PlanElementKind::from_name("spiral"), None);
        assert_eq!(
            check_design_elements(&[arc(0.0, 10.0), arc(10.0, 20.0)]),
            Ok(())
        );
        let e = check_design_elements(&[arc(0.0, 10.0), arc(11.0, 20.0)]).unwrap_err();
        assert!(e.contains("element 1 (arc): starts at s = 11"), "{e}");
        assert!(check_design_elements(&[arc(5.0, 5.0)]).is_err());
        let mut c = arc(0.0, 1.0);
        c.cant_end_rad = 120.0;
        let e = check_design_elements(&[c]).unwrap_err();
        assert!(e.contains("check the unit"), "{e}");
        let mut r = arc(0.0, 1.0);
        r.radius_start_m = 0.6;
        assert!(
            check_design_elements(&[r])
                .unwrap_err()
                .contains("check the unit")
        );
    }
}
