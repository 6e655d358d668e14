//! Cold start: starting points for Newton's method when there is no
//! previous solution (or it failed), from the contact conditions reduced to
//! the rail's cross-section through the wheelset (s_w = 0: each wheel point
//! taken at the bottom of its circle).
//!
//! In that plane, the rail head is convex, so its slope decreases
//! monotonically across it: for every sampled wheel point, the rail point
//! with the same slope (normals parallel, paper eq. 18) is found by
//! bisection. The remaining condition (the connecting vector along the
//! normal, eq. 19) is `g = (P_w − P_r)·t_r = 0`; its sign changes along the
//! wheel piece bracket the candidates, which are refined by bisection. Each
//! candidate's signed distance along the normal is its gap (negative when
//! overlapping, paper Fig. 10 case II); the deepest comes first.
//!
//! No sign change means the piece has no contact of its own (its closest
//! approach to the rail is at one of its ends, which belongs to the
//! neighbouring piece, or the slopes it needs are beyond the modelled rail).

use nalgebra::{Vector3, Vector4};

use super::geometry::Pair;

/// Samples across the wheel piece (both ends included) and the rail head.
pub(crate) const WHEEL_SAMPLES: usize = 41;
pub(crate) const RAIL_SAMPLES: usize = 121;
/// Bisection steps refining a root of g.
const BISECTIONS: usize = 40;

/// What the coarse search found.
pub(crate) struct Search {
    /// Starting points, deepest first.
    pub starts: Vec<Vector4<f64>>,
    /// The deepest cross-sectional solution, the direct-minimisation result
    /// used when Newton's method fails (s_w = 0).
    pub minimum: Option<Vector4<f64>>,
    /// No cross-sectional solution on this piece.
    pub at_boundary: bool,
    /// Signed distance of the deepest solution (m); negative when
    /// overlapping; +∞ when there is none.
    pub min_distance_m: f64,
}

/// The rail head sampled in internal coordinates: (u, z, slope).
struct RailSamples(Vec<(f64, f64, f64)>);

impl RailSamples {
    fn new(pair: &Pair<'_>) -> Self {
        let (r0, r1) = pair.rail.head().domain_m();
        Self(
            (0..RAIL_SAMPLES)
                .map(|k| {
                    let v = r0 + (r1 - r0) * k as f64 / (RAIL_SAMPLES - 1) as f64;
                    let p = pair.rail.head().at(v);
                    (v, p.z_m, p.dz)
                })
                .collect(),
        )
    }

    /// The rail point (internal u) whose slope is `slope`: the head is convex,
    /// so the slope decreases with u. `None` outside the head's slope range.
    fn with_slope(&self, pair: &Pair<'_>, slope: f64) -> Option<f64> {
        let s = &self.0;
        let (first, last) = (s[0].2, s[s.len() - 1].2);
        if !(slope <= first && slope >= last) {
            return None;
        }
        let k = s.partition_point(|p| p.2 > slope).clamp(1, s.len() - 1);
        let (mut a, mut b) = (s[k - 1].0, s[k].0);
        for _ in 0..BISECTIONS {
            let m = 0.5 * (a + b);
            if pair.rail.head().at(m).dz > slope {
                a = m;
            } else {
                b = m;
            }
        }
        Some(0.5 * (a + b))
    }
}

/// One wheel sample evaluated in the cross-section.
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
}

fn section(pair: &Pair<'_>, rail: &RailSamples, s_rail0_m: f64, u_int: f64) -> Option<Section> {
    let sg = pair.sigma;
    let wp = pair.wheel_curve.at(u_int);
    let f_w = wp.z_m - pair.wheel.nominal_radius_m();
    let u_w = sg * u_int;
    let a = &pair.pose.frame;
    let r_w = pair.pose.position + a * Vector3::new(0.0, pair.h_m + u_w, f_w);
    // Wheel tangent across the profile (s_w = 0): A (0, 1, f_w'), f_w' = σ z'.
    let t_w = a * Vector3::new(0.0, 1.0, sg * wp.dz);
    let mut s_r = s_rail0_m;
    for _ in 0..2 {
        let p = pair.rail_table.at(s_r).ok()?;
        s_r += (r_w - p.position).dot(&p.frame.t);
    }
    let p = pair.rail_table.at(s_r).ok()?;
    let delta = r_w - p.position;
    // Internal rail coordinates: u = σ(Δ·n), z = Δ·b.
    let (wu, wz) = (sg * delta.dot(&p.frame.n), delta.dot(&p.frame.b));
    let (tu, tz) = (sg * t_w.dot(&p.frame.n), t_w.dot(&p.frame.b));
    if tu.abs() < 1e-12 {
        return None;
    }
    let v = rail.with_slope(pair, tz / tu)?;
    let rp = pair.rail.head().at(v);
    let norm = (1.0 + rp.dz * rp.dz).sqrt();
    let (du, dz) = (wu - v, wz - rp.z_m);
    Some(Section {
        g: (du + dz * rp.dz) / norm,
        distance: (-du * rp.dz + dz) / norm,
        v,
        s_r,
    })
}

/// Search the piece of `pair` (see the module docs).
pub(crate) fn search(pair: &Pair<'_>, s_rail0_m: f64, keep: usize) -> Search {
    let (u0, u1) = pair.wheel_curve.domain_m();
    let rail = RailSamples::new(pair);
    let at = |k: usize| u0 + (u1 - u0) * k as f64 / (WHEEL_SAMPLES - 1) as f64;
    let samples: Vec<(f64, Option<Section>)> = (0..WHEEL_SAMPLES)
        .map(|k| (at(k), section(pair, &rail, s_rail0_m, at(k))))
        .collect();
    let mut roots: Vec<(f64, f64, Section)> = Vec::new();
    for w in samples.windows(2) {
        let ((ua, Some(sa)), (ub, Some(sb))) = (w[0], w[1]) else {
            continue;
        };
        if sa.g == 0.0 || sa.g.signum() != sb.g.signum() {
            let (mut a, mut b, mut ga) = (ua, ub, sa.g);
            let mut best = sa;
            for _ in 0..BISECTIONS {
                let m = 0.5 * (a + b);
                let Some(sm) = section(pair, &rail, s_rail0_m, m) else {
                    break;
                };
                best = sm;
                if sm.g.signum() == ga.signum() {
                    a = m;
                    ga = sm.g;
                } else {
                    b = m;
                }
            }
            roots.push((best.distance, 0.5 * (a + b), best));
        }
    }
    roots.sort_by(|a, b| a.0.total_cmp(&b.0));
    let sg = pair.sigma;
    let point = |u: f64, s: &Section| Vector4::new(s.s_r, sg * s.v, 0.0, sg * u);
    Search {
        starts: roots
            .iter()
            .take(keep)
            .map(|(_, u, s)| point(*u, s))
            .collect(),
        minimum: roots.first().map(|(_, u, s)| point(*u, s)),
        at_boundary: roots.is_empty(),
        min_distance_m: roots.first().map_or(f64::INFINITY, |r| r.0),
    }
}
