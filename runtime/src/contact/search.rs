//! Cold start: a coarse search for a starting point of Newton's method when
//! there is no previous solution (or it failed). In the rail's cross-section
//! through the wheelset, the signed distance between a wheel-piece point
//! (its lowest point, s_w = 0) and the rail head (negative when overlapping)
//! is minimised over the piece: by sampling, then a golden-section
//! refinement around the best sample. Distances are measured in the plane,
//! not vertically, so a flange hanging beside the rail's gauge face finds
//! its start too. When the minimum lies at an end of the piece (or of the
//! rail head), the piece has no contact of its own: its closest approach
//! belongs to the neighbouring piece.

use nalgebra::{Vector3, Vector4};

use super::geometry::Pair;

/// Samples across the wheel piece (both ends included) and the rail head.
pub(crate) const WHEEL_SAMPLES: usize = 41;
pub(crate) const RAIL_SAMPLES: usize = 81;
/// A refined minimum closer than this to an end is "at the end" (m).
const END_TOL_M: f64 = 5e-5;

/// What the coarse search found.
pub(crate) struct Search {
    /// Up to `keep` starting points, the refined minimum first.
    pub starts: Vec<Vector4<f64>>,
    /// The refined minimum itself, when found: the direct-minimisation
    /// solution used when Newton's method fails (s_w = 0).
    pub minimum: Option<Vector4<f64>>,
    /// The closest approach lies at an end of the wheel piece or of the rail
    /// head.
    pub at_boundary: bool,
    /// Smallest signed distance found (m); negative when overlapping.
    pub min_distance_m: f64,
}

/// Rail head samples in internal coordinates: (u, z, outward normal u, z).
struct RailSamples(Vec<(f64, f64, f64, f64)>);

impl RailSamples {
    fn new(pair: &Pair<'_>) -> Self {
        let (r0, r1) = pair.rail.head().domain_m();
        Self(
            (0..RAIL_SAMPLES)
                .map(|k| {
                    let v = r0 + (r1 - r0) * k as f64 / (RAIL_SAMPLES - 1) as f64;
                    let p = pair.rail.head().at(v);
                    let norm = (1.0 + p.dz * p.dz).sqrt();
                    (v, p.z_m, -p.dz / norm, 1.0 / norm)
                })
                .collect(),
        )
    }
}

/// Signed distance of the wheel point at internal `u_int` from the rail
/// head: (distance, rail internal u, rail index at an end?, s_r).
fn distance(
    pair: &Pair<'_>,
    rail: &RailSamples,
    s_rail0_m: f64,
    u_int: f64,
) -> Option<(f64, f64, bool, f64)> {
    let u_w = pair.sigma * u_int;
    let f_w = pair.wheel_curve.at(u_int).z_m - pair.wheel.nominal_radius_m();
    let r_w = pair.pose.position + pair.pose.frame * Vector3::new(0.0, pair.h_m + u_w, f_w);
    let mut s_r = s_rail0_m;
    for _ in 0..2 {
        let p = pair.rail_table.at(s_r).ok()?;
        s_r += (r_w - p.position).dot(&p.frame.t);
    }
    let p = pair.rail_table.at(s_r).ok()?;
    let delta = r_w - p.position;
    let (wu, wz) = (pair.sigma * delta.dot(&p.frame.n), delta.dot(&p.frame.b));
    let (mut best_d2, mut best_j) = (f64::INFINITY, 0);
    for (j, &(v, z, _, _)) in rail.0.iter().enumerate() {
        let (du, dz) = (wu - v, wz - z);
        let d2 = du * du + dz * dz;
        if d2 < best_d2 {
            best_d2 = d2;
            best_j = j;
        }
    }
    let at_end = best_j == 0 || best_j == RAIL_SAMPLES - 1;
    // Refine the foot point on the rail: (w − r(v))·r'(v) = 0 by Newton.
    let head = pair.rail.head();
    let (r0, r1) = head.domain_m();
    let mut v = rail.0[best_j].0;
    for _ in 0..4 {
        let p = head.at(v);
        let (du, dz) = (wu - v, wz - p.z_m);
        let g = du + dz * p.dz;
        let dg = -1.0 - p.dz * p.dz + dz * p.d2z_1_m;
        if dg.abs() < 1e-12 {
            break;
        }
        v = (v - g / dg).clamp(r0, r1);
    }
    let p = head.at(v);
    let norm = (1.0 + p.dz * p.dz).sqrt();
    let (du, dz) = (wu - v, wz - p.z_m);
    let signed = (du * (-p.dz / norm) + dz / norm).signum() * (du * du + dz * dz).sqrt();
    Some((signed, v, at_end, s_r))
}

/// Search the piece of `pair` (see the module docs).
pub(crate) fn search(pair: &Pair<'_>, s_rail0_m: f64, keep: usize) -> Search {
    let (u0, u1) = pair.wheel_curve.domain_m();
    let rail = RailSamples::new(pair);
    let at = |k: usize| u0 + (u1 - u0) * k as f64 / (WHEEL_SAMPLES - 1) as f64;
    let mut found: Vec<(f64, f64, f64, f64)> = (0..WHEEL_SAMPLES)
        .filter_map(|k| {
            let u = at(k);
            distance(pair, &rail, s_rail0_m, u).map(|(d, v, _, s_r)| (d, u, v, s_r))
        })
        .collect();
    if found.is_empty() {
        return Search {
            starts: Vec::new(),
            minimum: None,
            at_boundary: false,
            min_distance_m: f64::INFINITY,
        };
    }
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Golden-section refinement around the best sample.
    let h = (u1 - u0) / (WHEEL_SAMPLES - 1) as f64;
    let (mut a, mut b) = ((found[0].1 - h).max(u0), (found[0].1 + h).min(u1));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let f = |u: f64| distance(pair, &rail, s_rail0_m, u).map_or(f64::INFINITY, |r| r.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..30 {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    let u_best = 0.5 * (a + b);
    let refined = distance(pair, &rail, s_rail0_m, u_best);
    let mut starts = Vec::with_capacity(keep);
    let mut at_boundary = false;
    let mut min_distance_m = found[0].0;
    let mut minimum = None;
    if let Some((dist, v, rail_end, s_r)) = refined {
        at_boundary = rail_end || u_best - u0 < END_TOL_M || u1 - u_best < END_TOL_M;
        min_distance_m = min_distance_m.min(dist);
        let x = Vector4::new(s_r, pair.sigma * v, 0.0, pair.sigma * u_best);
        minimum = Some(x);
        starts.push(x);
    }
    // Further starts from the best samples, spread at least 1/8 of the piece
    // apart (near-conformal pieces have several stationary points).
    let spread = (u1 - u0) / 8.0;
    let mut used: Vec<f64> = vec![u_best];
    for &(_, u, v, s_r) in &found {
        if starts.len() >= keep {
            break;
        }
        if used.iter().all(|&w| (w - u).abs() >= spread) {
            used.push(u);
            starts.push(Vector4::new(s_r, pair.sigma * v, 0.0, pair.sigma * u));
        }
    }
    Search {
        starts,
        minimum,
        at_boundary,
        min_distance_m,
    }
}
