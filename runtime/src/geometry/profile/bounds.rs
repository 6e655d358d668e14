//! Plausibility bounds of a profile's size (docs/reference/02-inputs.md
//! §2.6): a profile read in the wrong length unit is refused with a message
//! that says "check the unit", instead of building a wheel 0.135 mm wide
//! without a flange and a run that completes.

use std::path::Path;

use super::ProfileError;

/// Narrowest lateral span of a profile's points (m). A rail head is about
/// 70 mm wide (UIC60: 72 mm) and a wheel's tread and flange about 135 mm
/// (S1002: 130 mm); lengths read a thousand times too small (metres under
/// a `y_mm,z_mm` header) give 0.07–0.14 mm, and ten times too small
/// (centimetres read as millimetres) 7–14 mm. 20 mm lies below any wheel
/// or rail profile and above both.
pub const MIN_PROFILE_SPAN_M: f64 = 0.020;

/// Widest lateral span of a profile's points (m). The widest cross-section
/// a profile file draws is a rail in full, its foot 150 mm wide (UIC60);
/// lengths ten times too large (millimetres read as centimetres) give a
/// rail head of 0.7 m and a wheel of 1.3 m, a thousand times too large
/// (millimetres read as metres) 70–140 m. The profiles are also scanned
/// every 0.05 mm, so a span of 10²² m (found by fuzzing) overflowed the scan
/// grid's capacity.
pub const MAX_PROFILE_SPAN_M: f64 = 0.5;

/// Lowest plausible flange height of a wheel profile (m): the depth of the
/// flange tip below the tread at the taping line. Every wheel profile has a
/// flange (the model splits it into tread and flange functions,
/// docs/reference/05-surfaces.md §5.4, and no shipped wheel lacks one);
/// 10 mm is the depth below which this toolkit used to treat a profile as a
/// plain tread, well under the 28 mm of new profiles (EN 13715), and a
/// profile in centimetres read as millimetres has a 2.8 mm flange.
pub const MIN_FLANGE_HEIGHT_M: f64 = 0.010;

/// Highest plausible flange height of a wheel profile (m). New EN 13715
/// profiles (S1002) have 28 mm and worn wheels are taken out of service at
/// 36 mm (EN 15313's limit for mainline wheels); 50 mm leaves room for
/// special profiles, while millimetres read as centimetres give 280 mm.
pub const MAX_FLANGE_HEIGHT_M: f64 = 0.050;

/// Refuse a profile whose points span laterally (internal `u`, m) less
/// than [`MIN_PROFILE_SPAN_M`] or more than [`MAX_PROFILE_SPAN_M`].
pub(crate) fn check_span(path: &Path, u_m: impl Iterator<Item = f64>) -> Result<(), ProfileError> {
    let (lo, hi) = u_m.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), u| {
        (lo.min(u), hi.max(u))
    });
    let span_m = hi - lo;
    if span_m.is_finite() && (MIN_PROFILE_SPAN_M..=MAX_PROFILE_SPAN_M).contains(&span_m) {
        return Ok(());
    }
    Err(ProfileError::Implausible {
        path: path.to_path_buf(),
        quantity: "lateral span of the profile's points",
        value_mm: span_m * 1e3,
        min_mm: MIN_PROFILE_SPAN_M * 1e3,
        max_mm: MAX_PROFILE_SPAN_M * 1e3,
        typical: "a rail head is about 70 mm wide, a wheel profile about 135 mm",
    })
}

/// Refuse a wheel whose flange height (m) lies outside
/// [`MIN_FLANGE_HEIGHT_M`] … [`MAX_FLANGE_HEIGHT_M`].
pub(crate) fn check_flange_height(path: &Path, height_m: f64) -> Result<(), ProfileError> {
    if (MIN_FLANGE_HEIGHT_M..=MAX_FLANGE_HEIGHT_M).contains(&height_m) {
        return Ok(());
    }
    Err(ProfileError::Implausible {
        path: path.to_path_buf(),
        quantity: "flange height (depth of the flange tip below the tread at the taping line)",
        value_mm: height_m * 1e3,
        min_mm: MIN_FLANGE_HEIGHT_M * 1e3,
        max_mm: MAX_FLANGE_HEIGHT_M * 1e3,
        typical: "S1002 has 28 mm; every wheel profile needs a flange",
    })
}
