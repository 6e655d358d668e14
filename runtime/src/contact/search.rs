//! Cold start: starting points for Newton's method when there is no
//! previous solution (or it failed, or the search is repeated to find every
//! patch), from the contact conditions reduced to one parameter — the
//! lateral position u on the wheel piece — along the wheel's **contact
//! locus** (docs/reference/06-contact-detection.md §6.3).
//!
//! For each wheel point u, the angle s_w about the axle is the one at which
//! the wheel's surface normal lies in the cross-section of the rail (is
//! perpendicular to the rail's tangent): the only points of the wheel where
//! the normals can be parallel (paper eq. 18). With the wheel normal
//! (−sin s_w, −f_w', cos s_w) in the axle frame and the rail tangent
//! (a, b, c) there, that is c·cos s_w − a·sin s_w = b·f_w', so
//! s_w = atan2(c, a) − asin(b·f_w'/√(a² + c²)): zero for an unyawed
//! wheelset (the bottom of the wheel), ≈ ψ·f_w' for a yaw ψ — the lead or
//! lag of a yawed flange contact, r·ψ·tan γ (about 15 mm for a 60° flange
//! at 18 mrad on a 0.46 m wheel), which a search confined to s_w = 0 would
//! miss.
//!
//! In the rail's cross-section through that wheel point the rail head is
//! convex, so its slope decreases monotonically across it: the rail point
//! with the wheel's slope (normals parallel) is found from a table of the
//! head's slopes (built once per model) and a safeguarded Newton iteration.
//! The remaining condition (the connecting vector along the normal,
//! eq. 19) is `g = (P_w − P_r)·t_r = 0`; its sign changes along the wheel
//! piece bracket the stationary points of the gap (minima and the maxima
//! between them), which are refined by the Illinois method. Each root's
//! signed distance along the normal is its gap (negative when overlapping,
//! paper Fig. 10 case II); the roots are returned deepest first.
//!
//! No sign change means the piece has no stationary point of its own (its
//! closest approach to the rail is at one of its ends, which belongs to the
//! neighbouring piece, or the slopes it needs are beyond the modelled rail).

use nalgebra::{Vector3, Vector4};

use super::geometry::Pair;
use crate::geometry::profile::PlacedRailProfile;

/// Samples across the wheel piece (both ends included) and the rail head.
pub(crate) const WHEEL_SAMPLES: usize = 41;
pub(crate) const RAIL_SAMPLES: usize = 121;
/// Iterations refining a root of g (Illinois) or a rail point of given slope
/// (safeguarded Newton); both converge superlinearly, to `ROOT_TOL_M`.
const MAX_REFINE: usize = 60;
/// Tolerance on the wheel's and the rail's lateral coordinates of a
/// refined root (m): far below what Newton's method needs as a start, and
/// the accuracy of the minimisation fallback's contact point.
const ROOT_TOL_M: f64 = 1e-11;
/// Passes of the rail-section iteration (wheel point → nearest rail section
/// → locus angle at that section's tangent). The section moves by the
/// lead/lag, millimetres; the rail's tangent turns by lead/radius over it
/// (1e-4 rad on a 150 m curve), so two passes leave an error far below the
/// Newton tolerance.
const SECTION_PASSES: usize = 2;

/// What the coarse search found.
pub(crate) struct Search {
    /// Starting points at every stationary point of the gap along the piece
    /// (minima and maxima), deepest first.
    pub starts: Vec<Vector4<f64>>,
    /// The deepest cross-sectional solution, the direct-minimisation result
    /// used when Newton's method fails.
    pub minimum: Option<Vector4<f64>>,
    /// No cross-sectional solution on this piece.
    pub at_boundary: bool,
    /// Signed distance of the deepest solution (m); negative when
    /// overlapping; +∞ when there is none.
    pub min_distance_m: f64,
}

/// The rail head's slopes sampled once (internal u, slope): the head is
/// convex, so the slope decreases with u and the point of a given slope is
/// bracketed by two samples.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RailSlopes(Vec<(f64, f64)>);

impl RailSlopes {
    pub(crate) fn new(rail: &PlacedRailProfile) -> Self {
        let head = rail.head();
        let (r0, r1) = head.domain_m();
        Self(
            (0..RAIL_SAMPLES)
                .map(|k| {
                    let v = r0 + (r1 - r0) * k as f64 / (RAIL_SAMPLES - 1) as f64;
                    (v, head.at(v).dz)
                })
                .collect(),
        )
    }

    /// The rail point (internal u) whose slope is `slope`. `None` outside the
    /// head's slope range.
    fn with_slope(&self, rail: &PlacedRailProfile, slope: f64) -> Option<f64> {
        let s = &self.0;
        let (first, last) = (s[0].1, s[s.len() - 1].1);
        if !(slope <= first && slope >= last) {
            return None;
        }
        let k = s.partition_point(|p| p.1 > slope).clamp(1, s.len() - 1);
        let (mut a, mut b) = (s[k - 1].0, s[k].0);
        let (sa, sb) = (s[k - 1].1, s[k].1);
        // Safeguarded Newton on dz(v) − slope, from the linear interpolation;
        // a step leaving the bracket [a, b] is replaced by bisection.
        let mut v = if sa > sb {
            a + (b - a) * (sa - slope) / (sa - sb)
        } else {
            0.5 * (a + b)
        };
        for _ in 0..MAX_REFINE {
            let p = rail.head().at(v);
            let f = p.dz - slope;
            if f > 0.0 {
                a = v;
            } else {
                b = v;
            }
            let newton = v - f / p.d2z_1_m;
            let next = if p.d2z_1_m < 0.0 && newton > a && newton < b {
                newton
            } else {
                0.5 * (a + b)
            };
            let done = (next - v).abs() < ROOT_TOL_M || b - a < ROOT_TOL_M;
            v = next;
            if done {
                break;
            }
        }
        Some(v)
    }
}

/// One wheel point of the locus evaluated in its rail cross-section.
#[derive(Clone, Copy)]
struct Section {
    /// g = (P_w − P_r)·t_r (m).
    g: f64,
    /// Signed distance along the rail normal (m).
    distance: f64,
    /// Rail internal u of the matching point.
    v: f64,
    /// Rail arc length of the section.
    s_r: f64,
    /// Angle of the wheel point about the axle (rad).
    s_w: f64,
}

/// A wheel point on the contact locus, expressed in its rail section.
struct LocusPoint {
    /// Angle of the wheel point about the axle (rad).
    s_w: f64,
    /// Rail arc length of its section (m).
    s_r: f64,
    /// The wheel point in the section's internal rail coordinates (u, z) (m).
    point: (f64, f64),
    /// The wheel's profile tangent (paper eq. 12) in the same coordinates.
    tangent: (f64, f64),
}

/// The wheel point at internal `u_int` on the contact locus (see the module
/// docs), located in the cross-section of its rail starting from arc length
/// `s_rail0_m`. `None` where the wheel normal cannot lie in a rail
/// cross-section (a face steeper than 90° − the yaw) or off the track tables.
fn locus(pair: &Pair<'_>, s_rail0_m: f64, u_int: f64) -> Option<LocusPoint> {
    let sg = pair.sigma;
    let wp = pair.wheel_curve.at(u_int);
    let f_w = wp.z_m - pair.wheel.nominal_radius_m();
    let f1 = sg * wp.dz;
    let u_w = sg * u_int;
    let a = &pair.pose.frame;
    let mut s_r = s_rail0_m;
    let mut s_w = 0.0;
    for _ in 0..SECTION_PASSES {
        let p = pair.rail_table.at(s_r).ok()?;
        // The rail tangent in the axle frame, turned forwards (its sign does
        // not matter for perpendicularity; forwards keeps s_w near 0).
        let mut t = a.transpose() * p.frame.t;
        if t.x < 0.0 {
            t = -t;
        }
        let r = t.x.hypot(t.z);
        let x = t.y * f1 / r;
        if x.is_nan() || x.abs() >= 1.0 {
            return None;
        }
        s_w = t.z.atan2(t.x) - x.asin();
        let (ss, cs) = s_w.sin_cos();
        let r_w = pair.pose.position + a * Vector3::new(-f_w * ss, pair.h_m + u_w, f_w * cs);
        s_r += (r_w - p.position).dot(&p.frame.t);
    }
    let (ss, cs) = s_w.sin_cos();
    let r_w = pair.pose.position + a * Vector3::new(-f_w * ss, pair.h_m + u_w, f_w * cs);
    // Wheel tangent across the profile (paper eq. 12), which lies in the
    // section up to the rail's own curvature.
    let t_w = a * Vector3::new(-f1 * ss, 1.0, f1 * cs);
    let p = pair.rail_table.at(s_r).ok()?;
    let delta = r_w - p.position;
    // Internal rail coordinates: u = σ(Δ·n), z = Δ·b.
    Some(LocusPoint {
        s_w,
        s_r,
        point: (sg * delta.dot(&p.frame.n), delta.dot(&p.frame.b)),
        tangent: (sg * t_w.dot(&p.frame.n), t_w.dot(&p.frame.b)),
    })
}

/// Whether the wheel point at internal `u_int` on the contact locus lies
/// inside the rail head (below its surface in the rail's cross-section);
/// `None` where the locus point does not exist. A point beside the head
/// (outside the rail profile's lateral extent) is outside.
pub(crate) fn inside_rail(pair: &Pair<'_>, s_rail0_m: f64, u_int: f64) -> Option<bool> {
    let l = locus(pair, s_rail0_m, u_int)?;
    let (wu, wz) = l.point;
    Some(pair.rail.head().contains(wu, 0.0) && wz < pair.rail.head().at(wu).z_m)
}

/// The wheel point at internal `u_int` on the contact locus, its rail
/// section and the rail point of the same slope there.
fn section(pair: &Pair<'_>, rail: &RailSlopes, s_rail0_m: f64, u_int: f64) -> Option<Section> {
    let l = locus(pair, s_rail0_m, u_int)?;
    let ((wu, wz), (tu, tz)) = (l.point, l.tangent);
    if tu.abs() < 1e-12 {
        return None;
    }
    let v = rail.with_slope(pair.rail, tz / tu)?;
    let rp = pair.rail.head().at(v);
    let norm = (1.0 + rp.dz * rp.dz).sqrt();
    let (du, dz) = (wu - v, wz - rp.z_m);
    Some(Section {
        g: (du + dz * rp.dz) / norm,
        distance: (-du * rp.dz + dz) / norm,
        v,
        s_r: l.s_r,
        s_w: l.s_w,
    })
}

/// The root of g between the samples `(ua, sa)` and `(ub, sb)` (opposite
/// signs), by the Illinois variant of regula falsi (superlinear, and never
/// leaving the bracket); `None` when a section inside the bracket cannot be
/// evaluated.
fn refine(
    pair: &Pair<'_>,
    rail: &RailSlopes,
    s_rail0_m: f64,
    (mut ua, mut sa): (f64, Section),
    (mut ub, mut sb): (f64, Section),
) -> Option<(f64, Section)> {
    let (mut ga, mut gb) = (sa.g, sb.g);
    if ga == 0.0 {
        return Some((ua, sa));
    }
    let mut side = 0;
    for _ in 0..MAX_REFINE {
        let m = if gb != ga {
            (ua * gb - ub * ga) / (gb - ga)
        } else {
            0.5 * (ua + ub)
        };
        let m = if m > ua.min(ub) && m < ua.max(ub) {
            m
        } else {
            0.5 * (ua + ub)
        };
        let sm = section(pair, rail, s_rail0_m, m)?;
        if sm.g == 0.0 || (ub - ua).abs() < ROOT_TOL_M {
            return Some((m, sm));
        }
        if sm.g.signum() == ga.signum() {
            (ua, sa, ga) = (m, sm, sm.g);
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        } else {
            (ub, sb, gb) = (m, sm, sm.g);
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        }
    }
    Some(if ga.abs() < gb.abs() {
        (ua, sa)
    } else {
        (ub, sb)
    })
}

/// Search the piece of `pair` (see the module docs).
pub(crate) fn search(pair: &Pair<'_>, rail: &RailSlopes, s_rail0_m: f64) -> Search {
    let (u0, u1) = pair.wheel_curve.domain_m();
    let at = |k: usize| u0 + (u1 - u0) * k as f64 / (WHEEL_SAMPLES - 1) as f64;
    let mut samples: Vec<(f64, Option<Section>)> = Vec::with_capacity(WHEEL_SAMPLES);
    let mut s_r = s_rail0_m;
    for k in 0..WHEEL_SAMPLES {
        // Each sample's section starts from its neighbour's.
        let sec = section(pair, rail, s_r, at(k));
        if let Some(s) = sec {
            s_r = s.s_r;
        }
        samples.push((at(k), sec));
    }
    let mut roots: Vec<(f64, f64, Section)> = Vec::new();
    for w in samples.windows(2) {
        let ((ua, Some(sa)), (ub, Some(sb))) = (w[0], w[1]) else {
            continue;
        };
        if sa.g == 0.0 || sa.g.signum() != sb.g.signum() {
            let start = sa.s_r;
            if let Some((u, s)) = refine(pair, rail, start, (ua, sa), (ub, sb)) {
                roots.push((s.distance, u, s));
            }
        }
    }
    roots.sort_by(|a, b| a.0.total_cmp(&b.0));
    let sg = pair.sigma;
    let point = |u: f64, s: &Section| Vector4::new(s.s_r, sg * s.v, s.s_w, sg * u);
    Search {
        starts: roots.iter().map(|(_, u, s)| point(*u, s)).collect(),
        minimum: roots.first().map(|(_, u, s)| point(*u, s)),
        at_boundary: roots.is_empty(),
        min_distance_m: roots.first().map_or(f64::INFINITY, |r| r.0),
    }
}
