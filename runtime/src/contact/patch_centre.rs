//! The centre of a contact patch: the centre of gravity of the undeformed
//! interpenetration volume of wheel and rail
//! (docs/reference/06-contact-detection.md §6.9).
//!
//! The contact equations (§6.1) find the point of **maximum** penetration.
//! Where the gap between the profiles is quadratic (Hertzian) the
//! interpenetration is symmetric about that point and its centroid is the
//! point itself; where the gap is nearly flat (near-conformal tread contact,
//! S1002 on UIC60 1:40 near the centre) the overlap is wide and lopsided and
//! the centroid, where the pressure's resultant acts, lies a millimetre or
//! so away. CONTACT (Vollebregt) reports this centroid as its "contact
//! reference location"; semi-Hertzian methods (Kik–Piotrowski, Ayasse–
//! Chollet's STRIPES) also place the patch at the centre of the
//! interpenetration.
//!
//! The overlap is taken in the rail's cross-section at the candidate's
//! `s_r`, along the deepest point's normal, as a function of the
//! coordinate along the patch's tangent, for the wheel's section at the
//! candidate's angle `s_w` (its lead for a yawed wheelset); each lateral
//! strip weighs z^{3/2}, its overlap volume (§6.9).

use super::candidate::Candidate;
use super::geometry::SurfaceParams;
use super::{ContactError, WheelsetContactModel, WheelsetPose};
use crate::geometry::track::TrackTables;

/// Half-width of the sampled window about the deepest point (m): ±25 mm
/// holds the widest overlap of a near-conformal tread patch (about 20 mm
/// for S1002 on UIC60 1:40 at 10 kN); an overlap reaching it is reported
/// as truncated ([`PatchCentre::truncated`]).
pub const WINDOW_HALF_WIDTH_M: f64 = 0.025;
/// Lateral sampling step on the wheel profile (m): 0.05 mm, 1/100 of a
/// typical 5 mm half-width, so the trapezoidal centroid of a smooth overlap
/// is exact to well below 1 µm (error O(h²)).
pub const SAMPLE_STEP_M: f64 = 5e-5;

/// A patch's centre and its interpenetration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PatchCentre {
    /// The candidate re-evaluated at the centre: points, contact frame,
    /// angle, rolling radius, curvatures and profile coordinates are those
    /// at the centre; `penetration_m` is the deepest point's δ (the
    /// approach), unchanged, and so are `iterations`, `cold_start` and
    /// `method`.
    pub candidate: Candidate,
    /// Lateral width of the connected overlap region in the rail's
    /// cross-section (m); 0 when the overlap is narrower than one sample.
    pub overlap_width_m: f64,
    /// Lateral distance from the deepest point's rail point to the centre
    /// along the rail's lateral axis `n` (positive left) (m).
    pub offset_m: f64,
    /// The overlap reached the sampled window ([`WINDOW_HALF_WIDTH_M`]) or
    /// the end of a profile: the part beyond is not in the centroid.
    pub truncated: bool,
}

/// One sample of the overlap: lateral coordinate ℓ along the rail's `n`
/// (m) and vertical overlap z (m, > 0 where the undeformed bodies
/// interpenetrate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct OverlapSample {
    pub lateral_m: f64,
    pub overlap_m: f64,
}

/// The connected overlap region around sample 0 and its volume-weighted
/// centroid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct OverlapCentroid {
    /// ∫ z^{3/2} τ dτ / ∫ z^{3/2} dτ (m).
    pub lateral_m: f64,
    /// Distance between the region's two zero crossings (m).
    pub width_m: f64,
    /// The region reached the last sample on a side (or a sample outside
    /// a profile) with z > 0.
    pub truncated: bool,
}

/// The weight of the lateral strip at overlap depth z (> 0): the volume
/// of interpenetration per unit lateral length. Along the rolling
/// direction the gap grows as A_x x² (A_x the relative rolling curvature,
/// nearly constant across a patch: the wheel's 1/r), so a strip of depth z
/// overlaps over |x| < √(z/A_x) and holds ∫(z − A_x x²) dx = (4/3) z^{3/2}/√A_x.
/// The centroid of the overlap **volume** therefore weights each lateral
/// position by z^{3/2} (the constant factor cancels). This is the centre
/// of gravity of the interpenetration over the contact plane (x and y), the
/// definition CONTACT's reference location uses (its user guide: the
/// "interpenetration center of gravity", weighted by the gap over the
/// plane, the integral over x evaluated with a quadratic gap).
fn strip_weight(z: f64) -> f64 {
    z.max(0.0).powf(1.5)
}

/// ∫ w(z) dℓ and ∫ w(z) ℓ dℓ over the segment between two samples, z
/// linear in between, clipped to the part where z > 0 (so the sums are
/// continuous as the region's ends move between samples), by Simpson's
/// rule on the clipped part (w = z^{3/2} is smooth there).
fn positive_moments(a: OverlapSample, b: OverlapSample) -> (f64, f64) {
    let (a, b) = if a.lateral_m <= b.lateral_m {
        (a, b)
    } else {
        (b, a)
    };
    let (mut l0, mut z0, mut l1, mut z1) = (a.lateral_m, a.overlap_m, b.lateral_m, b.overlap_m);
    if z0 <= 0.0 && z1 <= 0.0 {
        return (0.0, 0.0);
    }
    // Clip to the sub-segment where z > 0.
    if z0 < 0.0 {
        let t = z0 / (z0 - z1);
        l0 += t * (l1 - l0);
        z0 = 0.0;
    } else if z1 < 0.0 {
        let t = z0 / (z0 - z1);
        l1 = l0 + t * (l1 - l0);
        z1 = 0.0;
    }
    let dl = l1 - l0;
    let (lm, zm) = (0.5 * (l0 + l1), 0.5 * (z0 + z1));
    let (w0, wm, w1) = (strip_weight(z0), strip_weight(zm), strip_weight(z1));
    let area = dl / 6.0 * (w0 + 4.0 * wm + w1);
    let moment = dl / 6.0 * (w0 * l0 + 4.0 * wm * lm + w1 * l1);
    (area, moment)
}

/// Where a region's end lies between its last overlapping sample `inside`
/// and the first clear one `outside` (linear zero crossing) (m).
fn zero_crossing(inside: OverlapSample, outside: OverlapSample) -> f64 {
    let t = inside.overlap_m / (inside.overlap_m - outside.overlap_m);
    inside.lateral_m + t * (outside.lateral_m - inside.lateral_m)
}

/// The centroid of the connected overlap region containing sample 0.
/// `sample(k)` gives sample k (k = −n … n, in order of increasing
/// lateral coordinate), `None` outside the profiles. Samples are evaluated
/// outwards from 0 only until the overlap ends, so the cost is proportional
/// to the region's width, not the window's. `None` when sample 0 does not
/// overlap.
pub(crate) fn overlap_centroid(
    n: i64,
    mut sample: impl FnMut(i64) -> Option<OverlapSample>,
) -> Option<OverlapCentroid> {
    let s0 = sample(0).filter(|s| s.overlap_m > 0.0)?;
    let (mut area, mut moment) = (0.0, 0.0);
    let mut truncated = false;
    let mut ends = [s0.lateral_m; 2];
    for (i, dir) in [-1i64, 1].into_iter().enumerate() {
        let mut prev = s0;
        let mut k = 0;
        loop {
            k += dir;
            let next = if k.abs() <= n { sample(k) } else { None };
            let Some(next) = next else {
                truncated = true;
                ends[i] = prev.lateral_m;
                break;
            };
            let (a, m) = positive_moments(prev, next);
            area += a;
            moment += m;
            if next.overlap_m <= 0.0 {
                ends[i] = zero_crossing(prev, next);
                break;
            }
            prev = next;
        }
    }
    if area <= 0.0 {
        // A single overlapping sample between two clear ones has a
        // positive area; this is a degenerate (zero-width) overlap.
        return Some(OverlapCentroid {
            lateral_m: s0.lateral_m,
            width_m: 0.0,
            truncated,
        });
    }
    Some(OverlapCentroid {
        lateral_m: moment / area,
        width_m: (ends[1] - ends[0]).abs(),
        truncated,
    })
}

/// The centre of the patch of candidate `c` (in contact, δ ≥ 0) of the
/// wheelset at `pose` (see the module docs). `Ok(None)` when `c` is not in
/// contact or its wheel piece does not exist; the candidate itself (offset
/// 0, width 0) when its overlap is narrower than the sampling resolves.
pub fn patch_centre(
    model: &WheelsetContactModel,
    track: &TrackTables,
    pose: &WheelsetPose,
    c: &Candidate,
) -> Result<Option<PatchCentre>, ContactError> {
    if !c.in_contact() {
        return Ok(None);
    }
    let Some(pair) = model.pair(track, pose, c.side, c.segment) else {
        return Ok(None);
    };
    let rail = pair.rail_table.at(c.params.s_rail_m)?;
    let (p, n, b) = (
        rail.position,
        rail.frame.n.normalize(),
        rail.frame.b.normalize(),
    );
    let sg = pair.sigma;
    let head = pair.rail.head();
    let wheel = model.wheel(c.side);
    let (w_min, w_max) = match (wheel.segments().first(), wheel.segments().last()) {
        (Some(f), Some(l)) => (f.curve.domain_m().0, l.curve.domain_m().1),
        _ => return Ok(None),
    };
    let s_w = c.params.s_wheel_rad;
    let u_w0 = c.params.u_wheel_m;
    let wheel_u = |k: i64| u_w0 + k as f64 * SAMPLE_STEP_M;
    // The patch's own axes in the cross-section (n, b): its normal N at the
    // deepest point and the tangent T = (N_b, −N_n). Overlap is measured
    // along N and located along T, so a steep (flange) patch is measured
    // across its own width, not vertically.
    let (nn, nb) = {
        let (a, bb) = (c.normal.dot(&n), c.normal.dot(&b));
        let len = (a * a + bb * bb).sqrt().max(1e-12);
        (a / len, bb / len)
    };
    let (tn, tb) = (nb, -nn);
    // Rail point (ℓ, f_r(ℓ)) of the cross-section whose tangential
    // coordinate is τ: Newton from ℓ0 (the rail head is a graph over ℓ and
    // T is within the patch's slope range, so τ(ℓ) is monotonic there).
    // Internal (right-hand) profile coordinates are σ·u (geometry module).
    let rail_at = |tau: f64, l0: f64| -> Option<(f64, f64)> {
        let mut l = l0;
        for _ in 0..20 {
            if !head.contains(sg * l, 0.0) {
                return None;
            }
            let h = head.at(sg * l);
            let g = l * tn + h.z_m * tb - tau;
            let dg = tn + sg * h.dz * tb;
            if dg.abs() < 1e-9 {
                return None;
            }
            let step = g / dg;
            l -= step;
            if step.abs() < 1e-12 {
                break;
            }
        }
        head.contains(sg * l, 0.0)
            .then(|| (l, l * nn + head.at(sg * l).z_m * nb))
    };
    let sample = |k: i64| -> Option<OverlapSample> {
        let u_w = wheel_u(k);
        let uw_int = sg * u_w;
        if !(w_min..=w_max).contains(&uw_int) {
            return None;
        }
        let d = pair.wheel_point_m(s_w, u_w) - p;
        let (l, h) = (d.dot(&n), d.dot(&b));
        let tau = l * tn + h * tb;
        let (_, nu_rail) = rail_at(tau, l)?;
        Some(OverlapSample {
            lateral_m: tau,
            overlap_m: nu_rail - (l * nn + h * nb),
        })
    };
    let n_samples = (WINDOW_HALF_WIDTH_M / SAMPLE_STEP_M).round() as i64;
    let Some(centroid) = overlap_centroid(n_samples, sample) else {
        // δ ≥ 0 but no vertical overlap at the deepest point's own section
        // (δ below the rounding of the heights): the patch is a point.
        return Ok(Some(PatchCentre {
            candidate: *c,
            overlap_width_m: 0.0,
            offset_m: 0.0,
            truncated: false,
        }));
    };
    let l0 = sample(0).map_or(centroid.lateral_m, |s| s.lateral_m);
    // The wheel's u at the centroid's lateral coordinate: ℓ(u_w) is
    // monotonic (≈ u_w cos roll), so bracket it among the samples.
    let direction = if centroid.lateral_m >= l0 { 1 } else { -1 };
    let mut k: i64 = 0;
    let mut u_w = u_w0;
    let mut prev = (wheel_u(0), l0);
    while k.abs() < n_samples {
        k += direction;
        let Some(s) = sample(k) else { break };
        let here = (wheel_u(k), s.lateral_m);
        let (lo, hi) = (prev.1.min(here.1), prev.1.max(here.1));
        if (lo..=hi).contains(&centroid.lateral_m) {
            let t = if hi > lo {
                (centroid.lateral_m - prev.1) / (here.1 - prev.1)
            } else {
                0.0
            };
            u_w = prev.0 + t * (here.0 - prev.0);
            break;
        }
        prev = here;
        u_w = here.0;
    }
    let rail_centre_m =
        rail_at(centroid.lateral_m, c.params.u_rail_m).map_or(c.params.u_rail_m, |(l, _)| l);
    let params = SurfaceParams {
        u_rail_m: rail_centre_m,
        u_wheel_m: u_w,
        ..c.params
    };
    let Some(mut at_centre) = model.candidate_at(track, pose, c.side, c.segment, params)? else {
        return Ok(None);
    };
    at_centre.penetration_m = c.penetration_m;
    at_centre.iterations = c.iterations;
    at_centre.cold_start = c.cold_start;
    at_centre.method = c.method;
    Ok(Some(PatchCentre {
        candidate: at_centre,
        overlap_width_m: centroid.width_m,
        offset_m: rail_centre_m - c.params.u_rail_m,
        truncated: centroid.truncated,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::ContactSolver;
    use crate::fixtures::wheelsets;
    use crate::geometry::profile::Zone;
    use crate::geometry::track::Side;

    const H: f64 = 1e-4;

    /// Samples of z(ℓ) every H.
    fn centroid_of(z: impl Fn(f64) -> f64, n: i64) -> Option<OverlapCentroid> {
        overlap_centroid(n, |k| {
            let l = k as f64 * H;
            Some(OverlapSample {
                lateral_m: l,
                overlap_m: z(l),
            })
        })
    }

    #[test]
    fn symmetric_quadratic_gap_centroid_is_the_deepest_point() {
        // Hertzian gap: overlap δ − A ℓ², δ = 0.05 mm, A = 2 1/m → half-width 5 mm.
        let c = centroid_of(|l| 5e-5 - 2.0 * l * l, 250).expect("overlap");
        assert!(c.lateral_m.abs() < 1e-12, "{c:?}");
        assert!((c.width_m - 0.01).abs() < 1e-9, "{c:?}");
        assert!(!c.truncated);
    }

    #[test]
    fn asymmetric_gap_centroid_moves_towards_the_wider_side() {
        // Deepest at 0; flatter (wider) to the right: half-widths 5 mm left,
        // 10 mm right. Piecewise parabolas z = δ(1 − (ℓ/w)²) weighted by
        // z^{3/2}: a cap of half-width w has ∫ z^{3/2} dℓ = δ^{3/2}·w·3π/16
        // and ∫ z^{3/2} ℓ dℓ = ±δ^{3/2}·w²/5, so the centroid is
        // 16(w_r² − w_l²)/(15π(w_l + w_r)) = 1200/(225π) mm = 1.6977 mm.
        let d = 5e-5;
        let z = |l: f64| {
            let w: f64 = if l < 0.0 { 0.005 } else { 0.010 };
            d * (1.0 - (l / w).powi(2))
        };
        let c = centroid_of(z, 250).expect("overlap");
        assert!(
            (c.lateral_m - 1.2e-3 / (0.225 * std::f64::consts::PI)).abs() < 1e-6,
            "{c:?}"
        );
        assert!((c.width_m - 0.015).abs() < 1e-9, "{c:?}");
    }

    #[test]
    fn a_separate_overlap_region_is_another_patch() {
        // Two caps: the seed's (centred at 0, half-width 2 mm) and a deeper
        // one at 8 mm; only the first counts.
        let z = |l: f64| {
            let a = 2e-5 * (1.0 - (l / 0.002).powi(2));
            let b = 9e-5 * (1.0 - ((l - 0.008) / 0.002).powi(2));
            a.max(b)
        };
        let c = centroid_of(z, 250).expect("overlap");
        assert!(c.lateral_m.abs() < 1e-9, "{c:?}");
        assert!((c.width_m - 0.004).abs() < 1e-9, "{c:?}");
    }

    #[test]
    fn an_overlap_beyond_the_window_is_flagged_truncated() {
        let c = centroid_of(|l| 5e-5 - 0.01 * l * l, 50).expect("overlap");
        assert!(c.truncated, "{c:?}");
        assert!(centroid_of(|_| -1e-6, 50).is_none());
    }

    /// The centred S1002/UIC60 wheelset, 10 kN-like approach (A-2.2 case 1):
    /// the gap is nearly flat, the overlap wide and lopsided, and the centre
    /// is re-evaluated there with the deepest point's penetration.
    #[test]
    fn near_conformal_tread_centre_is_off_the_deepest_point() {
        let model = wheelsets::s1002_uic60().expect("fixture");
        let track = wheelsets::straight_track_for(&model, 20.0);
        let mut solver = wheelsets::flange_solver();
        let tread = |z: f64, solver: &mut ContactSolver| {
            let pose = WheelsetPose::on_track(&track, 10.0, 0.0, z, 0.0, 0.0).expect("pose");
            let cs = solver.solve(&model, &track, &pose).expect("solve");
            (pose, *cs.get(Side::Left, Zone::Tread).expect("tread"))
        };
        // Lower the wheelset until the approach is about 0.02 mm.
        let (_, c0) = tread(0.46, &mut solver);
        let (pose, c) = tread(0.46 + c0.penetration_m - 2e-5, &mut solver);
        assert!(c.penetration_m > 1e-5, "{c:?}");
        let centre = patch_centre(&model, &track, &pose, &c)
            .expect("centre")
            .expect("in contact");
        let cc = centre.candidate;
        assert_eq!(cc.penetration_m, c.penetration_m);
        assert!(!centre.truncated, "{centre:?}");
        assert!(centre.overlap_width_m > 0.005, "{centre:?}");
        // Off by more than the 0.1 mm a Hertzian patch would give, less than
        // half the width.
        assert!(
            centre.offset_m.abs() > 1e-4 && centre.offset_m.abs() < 0.5 * centre.overlap_width_m,
            "{centre:?}"
        );
        // Rail and wheel points at the centre lie on one line along the
        // deepest point's normal (the same coordinate along its tangent).
        let rail = track.rail(Side::Left).at(c.params.s_rail_m).expect("rail");
        let (n, b) = (rail.frame.n.normalize(), rail.frame.b.normalize());
        let lat = |v: nalgebra::Vector3<f64>| (v - rail.position).dot(&n);
        assert!((lat(cc.rail_point) - lat(c.rail_point) - centre.offset_m).abs() < 1e-9);
        let (nn, nb) = (c.normal.dot(&n), c.normal.dot(&b));
        let tau = |v: nalgebra::Vector3<f64>| {
            let d = v - rail.position;
            d.dot(&n) * nb - d.dot(&b) * nn
        };
        assert!(
            (tau(cc.wheel_point) - tau(cc.rail_point)).abs() < 1e-7,
            "{cc:?}"
        );
        // The frame and the angle are those of the rail at the centre.
        assert!(cc.contact_angle_rad != c.contact_angle_rad);
        assert!((cc.normal.norm() - 1.0).abs() < 1e-12);
    }

    /// Not in contact: no centre.
    #[test]
    fn a_gap_has_no_centre() {
        let model = wheelsets::s1002_uic60().expect("fixture");
        let track = wheelsets::straight_track_for(&model, 20.0);
        let mut solver = wheelsets::flange_solver();
        let pose = WheelsetPose::on_track(&track, 10.0, 0.0, 0.465, 0.0, 0.0).expect("pose");
        let cs = solver.solve(&model, &track, &pose).expect("solve");
        let c = cs.get(Side::Left, Zone::Tread).expect("tread candidate");
        assert!(!c.in_contact());
        assert!(
            patch_centre(&model, &track, &pose, c)
                .expect("ok")
                .is_none()
        );
    }
}
