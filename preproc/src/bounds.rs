//! Plausibility bounds of the track inputs and of the tables built from
//! them (docs/reference/02-inputs.md §2.5, table "Plausibility bounds").
//! A value beyond its bound is not a track that exists: almost always a
//! unit written wrongly (metres in a millimetre column, kilometres as
//! metres), so the refusal says "check the unit". Each bound states the
//! railway practice it rests on.

/// Largest |cant| φ (rad): asin(0.200 m / 1.500 m), a cant height of
/// 200 mm on the standard cant base. EN 13803 limits the cant of plain
/// line to 160 mm (recommended) and 180 mm (maximum); no line in service
/// exceeds 200 mm. On another gauge the same angle applies (it sets the
/// lateral acceleration g·sin φ): 142 mm on a metre-gauge cant base of
/// 1.065 m, 232 mm on the 1.741 m of Indian broad gauge (e0 = gauge +
/// 65 mm).
pub const MAX_CANT_RAD: f64 = 0.133_731_589_409_941_54;
/// The cant height of [`MAX_CANT_RAD`] on the standard cant base (mm).
pub const MAX_CANT_ON_STANDARD_BASE_MM: f64 = 200.0;
/// Smallest largest-|value| of a non-zero `cant_mm` column (mm): track
/// cant is set in steps of a few millimetres (EN 13803 ramps run from
/// 0 to tens of mm), so a column whose values all lie below 1 mm holds
/// metres (0.1 for 100 mm).
pub const MIN_PEAK_CANT_MM: f64 = 1.0;

/// Largest |irregularity| of any column and any rail (m). EN 13848-5
/// immediate-action limits for isolated defects (longitudinal level,
/// alignment, gauge, cross level) are a few tens of millimetres at every
/// speed class (about 35 mm at the most); a per-rail deviation
/// (alignment ± gauge/2) beyond 50 mm is track out of service, or
/// millimetres written in a metres column.
pub const MAX_IRREGULARITY_M: f64 = 0.050;
/// Smallest largest-|value| of a non-zero `_mm` irregularity column (mm):
/// below the resolution of track recording cars (tenths of a millimetre);
/// a column whose values all lie below 0.1 mm holds metres.
pub const MIN_PEAK_IRREGULARITY_MM: f64 = 0.1;

/// Largest |coordinate| of a control point and |s| of a table row (m):
/// more than any projected map coordinate (UTM eastings with the zone
/// number prefixed, as German survey files write them, reach 6.1 × 10⁷ m;
/// the Earth's circumference is 4 × 10⁷ m). A value beyond it is a unit
/// error or an overflowing number (1e308).
pub const MAX_COORDINATE_M: f64 = 1e8;

/// Smallest radius of curvature of the built centreline (m). The
/// tightest curves railway vehicles run through are tram curves of
/// 15–20 m (historic city-centre lines and depots; new tram lines are
/// designed to 25 m or more); below 10 m no railway runs, and a radius
/// like 0.6 m is a 600 m curve whose coordinates were written in km.
pub const MIN_CURVE_RADIUS_M: f64 = 10.0;

/// Largest |grade| of a design track (‰). Main lines are built to 35 ‰ at
/// most (TSI INF, Regulation (EU) 1299/2014 §4.2.3.3, "maximum gradients");
/// the steepest adhesion tramways reach about 135 ‰ (Lisbon); 150 ‰ is
/// beyond any adhesion railway, and a grade of 0.012 meant as 12 ‰ is
/// caught by [`MIN_NONZERO_GRADE_PERMILLE`].
pub const MAX_GRADE_PERMILLE: f64 = 150.0;
/// Smallest |grade| other than 0 of a design track (‰): 0.1 ‰ is 1 cm in
/// 100 m, below the accuracy of a track's vertical alignment; a smaller
/// grade is a fraction (0.012) written into a permille key.
pub const MIN_NONZERO_GRADE_PERMILLE: f64 = 0.1;

/// Longest design track, and longest element of one (m): 10⁷ m, more than
/// the longest railway line (the Trans-Siberian, 9289 km); a length beyond
/// it is a unit error (mm for m). It also bounds the work of placing the
/// elements (one quadrature panel per 5 m: at most 2 × 10⁶ panels).
pub const MAX_DESIGN_LENGTH_M: f64 = 1e7;

/// Track gauge range (m): from below the narrowest public railways
/// (597 mm Ffestiniog, 600 mm Decauville) to above the broadest in service
/// (1676 mm Indian broad gauge). A gauge of 1435 is millimetres.
pub const GAUGE_RANGE_M: (f64, f64) = (0.5, 2.0);
/// Cant base e0 range (m): the gauge range plus the rail-head width
/// (e0 = gauge + 0.065 m for standard rails).
pub const CANT_BASE_RANGE_M: (f64, f64) = (0.5, 2.2);
/// Range of the distance between the rail space curves (m): the gauge
/// range plus twice the largest gauge-face offset.
pub const RAIL_SPACING_RANGE_M: (f64, f64) = (0.5, 2.4);
/// Range of the offset of the gauge face from the rail profile's origin
/// (m): half the head width, 36 mm for UIC60; 0.2 m is far more than
/// any rail head.
pub const GAUGE_FACE_OFFSET_RANGE_M: (f64, f64) = (0.0, 0.2);
/// Table step range (m): 0.1 mm (finer than the accuracy of any track
/// geometry) to 10 m (a coarser table holds no useful track geometry: it
/// misses the 3 m wavelengths of EN 13848 and leaves the arc of a 300 m
/// curve by h²/(8R) = 4 cm between rows; a step of 100 is centimetres or
/// millimetres).
pub const STEP_RANGE_M: (f64, f64) = (1e-4, 10.0);

/// Largest content of an irregularity file that the table step cannot
/// hold (m): re-interpolated from its values at the table's nodes, the
/// file must reproduce every one of its samples to 0.1 mm (the
/// resolution of track recording cars), docs/reference/03-track-preproc.md §3d.
pub const UNRESOLVED_IRREGULARITY_M: f64 = 1e-4;

/// Relative tolerance of the check of each built rail's (and the
/// centreline's) length against the length its table rows resolve
/// (docs/reference/03-track-preproc.md §3g): 10⁻⁵ (1 mm per 100 m), on top
/// of the discretisation error of the rows' polygon, which the check
/// estimates from the rows themselves. Sound tracks agree to 10⁻⁸ or
/// better (the shipped examples, every scheme, steps 1 mm … 5 m); a rail
/// offset by e/2 on a curve of radius R is e/(2R) longer or shorter than
/// the centreline (2.5 × 10⁻³ on R = 300 m), which the rows resolve.
pub const LENGTH_TOLERANCE: f64 = 1e-5;

/// `value` lies in the closed range.
pub fn within(value: f64, (lo, hi): (f64, f64)) -> bool {
    value.is_finite() && value >= lo && value <= hi
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cant_bound_is_200_mm_on_the_standard_base() {
        assert_eq!(
            MAX_CANT_RAD,
            (MAX_CANT_ON_STANDARD_BASE_MM * 1e-3 / 1.5).asin()
        );
        assert!(within(1.435, GAUGE_RANGE_M) && within(0.597, GAUGE_RANGE_M));
        assert!(within(1.676, GAUGE_RANGE_M) && !within(1435.0, GAUGE_RANGE_M));
        assert!(!within(f64::NAN, STEP_RANGE_M));
    }
}
