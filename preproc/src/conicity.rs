//! Equivalent conicity tan γe of a wheelset on track, EN 15302 Annex B:
//! integration of the nonlinear kinematic equation of the wheelset and
//! comparison of its wavelength with Klingel's formula.
//!
//! # Method (sources)
//!
//! - Kinematic (Klingel) motion of a free wheelset, EN 15302:2008+A1:2010
//!   Annex B, eq. (B.1); Klingel, *Über den Lauf der Eisenbahnwagen auf
//!   gerader Bahn*, Organ für die Fortschritte des Eisenbahnwesens 38 (1883);
//!   Wickens, *Fundamentals of Rail Vehicle Dynamics* (2003), §2.2:
//!
//!   y'' = −Δr(y) / (e·r0),   (′ = d/dx along the track)
//!
//!   with Δr(y) the rolling-radius difference, e the distance between the
//!   contact points and r0 the rolling radius of the centred wheelset.
//! - Energy integral (EN 15302 Annex B, steps b–e): with
//!   W(y) = ∫_{y0}^{y} Δr dy′ (y0 the zero of Δr, the centre), an oscillation
//!   of amplitude ŷ has turning points y1 < y2 with y2 − y1 = 2ŷ and
//!   W(y1) = W(y2) = E, and (dy/dx)² = 2 (E − W(y)) / (e·r0).
//!   Its wavelength is λ = 2 ∫_{y1}^{y2} dy / |dy/dx|.
//! - Klingel's formula (EN 15302 §3 and Annex B, eq. (B.5)):
//!   λ = 2π √(e·r0 / (2 tan γe)), hence tan γe = e·r0 (2π/λ)² / 2.
//!
//! Writing I = ∫_{y1}^{y2} dy / √(E − W(y)), the two formulas give
//! λ = √(2 e r0) · I and **tan γe = (π / I)²**: the equivalent conicity
//! depends on Δr(y) and ŷ only. e and r0 scale the wavelength and cancel out
//! of tan γe (a pure cone Δr = 2λ·y gives tan γe = λ whatever e·r0 is). The
//! EN 15302 reference cases are therefore reproduced with any e, r0; this
//! module's defaults for reporting wavelengths are
//! [`EN15302_CONTACT_DISTANCE_M`] = 1.5 m (standard gauge, docs/reference/01-units-frames.md §1) and
//! [`EN15302_NOMINAL_RADIUS_M`] = 0.46 m (the 920 mm reference wheels of
//! EN 15302 Annex E; for the 920/918 mm cases E5–E8 the mean 0.4595 m gives
//! the same tan γe and a wavelength 0.05 % shorter).
//!
//! # Numerics
//!
//! Δr is interpolated linearly between the tabulated points, so W is
//! piecewise quadratic and the turning points are found in closed form; the
//! energy E is found by bisection on the width y2 − y1 of the oscillation.
//! The 1/√ singularities at the turning points are removed by the
//! substitution y = yc + ŷ sin θ (yc = (y1 + y2)/2): with
//! E − W(y) = (y2 − y)(y − y1)·R(y), the integrand becomes dθ / √R(θ), which
//! is finite and smooth between the tabulated points. Each half of the
//! oscillation is integrated from its own turning point (φ = π/2 ∓ θ,
//! t = 2ŷ sin²(φ/2) the distance from the turning point, E − W accumulated
//! from that turning point, so nothing cancels), split at the tabulated
//! points and integrated by adaptive 8-point Gauss–Legendre
//! ([`runtime::quadrature::gauss_legendre_8`]).
//!
//! Special cases:
//! - Δr = 0 over a stretch around the centre (EN 15302 case E4): an
//!   amplitude that fits inside the stretch meets no restoring force, the
//!   wavelength is infinite and tan γe = 0 (the reference result of E4).
//! - asymmetric Δr (different wheel diameters, different profiles left and
//!   right): the centre is the zero of Δr, not y = 0, and the oscillation is
//!   not symmetric about it; only y2 − y1 = 2ŷ is imposed.
//! - Δr that is not monotone: handled as long as E − W stays positive
//!   between the turning points. When Δr has several restoring zeros, the
//!   centre is the one nearest to y = 0; an amplitude at which the
//!   oscillation around it would jump into a neighbouring well is an error
//!   ([`ConicityError::NoOrbit`]).
//!
//! # Sign convention
//!
//! Project convention (docs/reference/01-units-frames.md §1): y is the lateral displacement of the
//! wheelset, positive to the **left**, and Δr = r_left − r_right, so a
//! wheelset displaced to the left has Δr > 0 for ordinary profiles and
//! y·Δr > 0 away from the centre (restoring). The EN 15302 reference Δr
//! tables follow the same pattern (Δr < 0 for y < y0, Δr > 0 for y > y0).
//! Data in the mirrored convention (y positive to the right and
//! Δr = r_right − r_left) describe the same wheelset seen from the other
//! side and give the same tan γe; data with only one of the two signs flipped
//! have a non-restoring centre and are refused with
//! [`ConicityError::NoRestoringZero`] (flip them with
//! [`DeltaRFunction::mirrored`] or by negating Δr as appropriate).

use std::cell::Cell;
use std::f64::consts::{FRAC_PI_2, PI};

use runtime::quadrature::gauss_legendre_8;
use serde::Serialize;

/// Distance between the contact points used for reporting wavelengths (m):
/// 1.500 m for standard gauge (docs/reference/01-units-frames.md §1). tan γe does not depend on it.
pub const EN15302_CONTACT_DISTANCE_M: f64 = 1.5;

/// Rolling radius of the centred wheelset used for reporting wavelengths
/// (m): the 920 mm reference wheels of EN 15302 Annex E. tan γe does not
/// depend on it.
pub const EN15302_NOMINAL_RADIUS_M: f64 = 0.46;

/// Amplitudes ŷ of [`ConicitySummary::new`] (mm).
pub const SUMMARY_AMPLITUDES_MM: [f64; 6] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];

/// Why an equivalent conicity could not be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConicityError {
    #[error("Δr function: {y_points} lateral positions but {delta_r_points} Δr values")]
    LengthMismatch {
        y_points: usize,
        delta_r_points: usize,
    },
    #[error("Δr function: {points} points, at least {min} are needed")]
    TooFewPoints { points: usize, min: usize },
    #[error("Δr function: point {index} has a non-finite {quantity} ({value})")]
    NonFinite {
        index: usize,
        quantity: &'static str,
        value: f64,
    },
    #[error(
        "Δr function: lateral positions must increase strictly, but point {index} \
         (y = {y_m} m) follows y = {previous_y_m} m"
    )]
    NotIncreasing {
        index: usize,
        previous_y_m: f64,
        y_m: f64,
    },
    #[error("{name} must be finite and positive, got {value}")]
    InvalidParameter { name: &'static str, value: f64 },
    #[error(
        "Δr never changes sign (it ranges over [{min_delta_r_m}, {max_delta_r_m}] m): \
         there is no centred position (flange-only or one-sided data?)"
    )]
    NoZeroCrossing {
        min_delta_r_m: f64,
        max_delta_r_m: f64,
    },
    #[error(
        "Δr crosses zero only from positive to negative (at y = {y_zero_m} m): the centre \
         is unstable; the data may use the opposite sign convention for y or Δr \
         (project convention: y positive to the left, Δr = r_left − r_right)"
    )]
    NoRestoringZero { y_zero_m: f64 },
    #[error(
        "amplitude {amplitude_m} m is beyond the tabulated Δr function: the largest \
         oscillation inside it has amplitude {max_amplitude_m} m"
    )]
    AmplitudeOutOfRange {
        amplitude_m: f64,
        max_amplitude_m: f64,
    },
    #[error(
        "no oscillation of amplitude {amplitude_m} m: Δr has several restoring zeros and \
         the oscillation around the centre jumps from width {width_below_m} m to \
         {width_above_m} m where it merges with a neighbouring one"
    )]
    NoOrbit {
        amplitude_m: f64,
        width_below_m: f64,
        width_above_m: f64,
    },
    #[error(
        "amplitude {amplitude_m} m: the wavelength integrand is not positive and finite \
         at y = {y_m} m (E − W = {value} m²)"
    )]
    Integration {
        amplitude_m: f64,
        y_m: f64,
        value: f64,
    },
}

/// Rolling-radius difference Δr(y) tabulated against the lateral
/// displacement y of the wheelset, both in m (project convention: y positive
/// to the left, Δr = r_left − r_right). Linear between the points.
#[derive(Debug, Clone, PartialEq)]
pub struct DeltaRFunction {
    y_m: Vec<f64>,
    delta_r_m: Vec<f64>,
}

impl DeltaRFunction {
    /// Fewest points accepted.
    pub const MIN_POINTS: usize = 3;

    /// Checks equal lengths, at least [`Self::MIN_POINTS`] points, finite
    /// values and strictly increasing y.
    pub fn new(y_m: Vec<f64>, delta_r_m: Vec<f64>) -> Result<Self, ConicityError> {
        if y_m.len() != delta_r_m.len() {
            return Err(ConicityError::LengthMismatch {
                y_points: y_m.len(),
                delta_r_points: delta_r_m.len(),
            });
        }
        if y_m.len() < Self::MIN_POINTS {
            return Err(ConicityError::TooFewPoints {
                points: y_m.len(),
                min: Self::MIN_POINTS,
            });
        }
        for (index, (&y, &d)) in y_m.iter().zip(&delta_r_m).enumerate() {
            if !y.is_finite() {
                return Err(ConicityError::NonFinite {
                    index,
                    quantity: "y",
                    value: y,
                });
            }
            if !d.is_finite() {
                return Err(ConicityError::NonFinite {
                    index,
                    quantity: "Δr",
                    value: d,
                });
            }
        }
        for (index, w) in y_m.windows(2).enumerate() {
            if w[1] <= w[0] {
                return Err(ConicityError::NotIncreasing {
                    index: index + 1,
                    previous_y_m: w[0],
                    y_m: w[1],
                });
            }
        }
        Ok(Self { y_m, delta_r_m })
    }

    /// The same from values in mm (as EN 15302 tabulates them).
    pub fn from_mm(y_mm: &[f64], delta_r_mm: &[f64]) -> Result<Self, ConicityError> {
        Self::new(
            y_mm.iter().map(|v| v * 1e-3).collect(),
            delta_r_mm.iter().map(|v| v * 1e-3).collect(),
        )
    }

    /// Lateral positions (m).
    pub fn y_m(&self) -> &[f64] {
        &self.y_m
    }

    /// Rolling-radius differences (m).
    pub fn delta_r_m(&self) -> &[f64] {
        &self.delta_r_m
    }

    /// Δr at y (m), linear between the points; `None` outside the table.
    pub fn value_m(&self, y_m: f64) -> Option<f64> {
        let (first, last) = (self.y_m[0], self.y_m[self.y_m.len() - 1]);
        (y_m >= first && y_m <= last).then(|| self.interpolate(y_m))
    }

    /// The same wheelset seen from the other side: y → −y, Δr → −Δr. This
    /// converts between the project convention (y left, Δr = r_left −
    /// r_right) and its mirror image (y right, Δr = r_right − r_left); the
    /// equivalent conicity is unchanged.
    pub fn mirrored(&self) -> Self {
        Self {
            y_m: self.y_m.iter().rev().map(|y| -y).collect(),
            delta_r_m: self.delta_r_m.iter().rev().map(|d| -d).collect(),
        }
    }

    /// The centre: the zero of Δr where it changes from negative to positive
    /// (the bottom of W), as (left end, right end) in m; the two are equal
    /// unless Δr vanishes over a stretch. With several such zeros, the one
    /// nearest to y = 0.
    pub fn centre_m(&self) -> Result<(f64, f64), ConicityError> {
        let well = self.well()?;
        Ok((well.left, well.right))
    }

    /// The largest amplitude ŷ (m) whose oscillation stays inside the table.
    pub fn max_amplitude_m(&self) -> Result<f64, ConicityError> {
        Ok(Solver::new(self)?.max_amplitude_m())
    }

    /// Linear interpolation, clamped to the end segments.
    fn interpolate(&self, y: f64) -> f64 {
        let n = self.y_m.len();
        let k = self.y_m.partition_point(|&v| v <= y).clamp(1, n - 1) - 1;
        let (y0, y1) = (self.y_m[k], self.y_m[k + 1]);
        let (d0, d1) = (self.delta_r_m[k], self.delta_r_m[k + 1]);
        d0 + (d1 - d0) * (y - y0) / (y1 - y0)
    }

    /// The potential well around the centre.
    fn well(&self) -> Result<Well, ConicityError> {
        let (y, d) = (&self.y_m, &self.delta_r_m);
        // Consecutive non-zero points (p, i) with zeros between them.
        let mut restoring: Vec<(usize, usize)> = Vec::new();
        let mut unstable: Option<f64> = None;
        let mut previous: Option<usize> = None;
        for i in 0..y.len() {
            if d[i] == 0.0 {
                continue;
            }
            if let Some(p) = previous {
                if d[p] < 0.0 && d[i] > 0.0 {
                    restoring.push((p, i));
                } else if d[p] > 0.0 && d[i] < 0.0 && unstable.is_none() {
                    unstable = Some(if i == p + 1 {
                        y[p] + (y[i] - y[p]) * d[p] / (d[p] - d[i])
                    } else {
                        0.5 * (y[p + 1] + y[i - 1])
                    });
                }
            }
            previous = Some(i);
        }
        let centre = |&(p, i): &(usize, usize)| -> (f64, f64) {
            if i == p + 1 {
                let y0 = y[p] + (y[i] - y[p]) * (-d[p]) / (d[i] - d[p]);
                (y0, y0)
            } else {
                (y[p + 1], y[i - 1])
            }
        };
        let distance = |(l, r): (f64, f64)| {
            if l <= 0.0 && r >= 0.0 {
                0.0
            } else {
                l.abs().min(r.abs())
            }
        };
        let Some(&(p, i)) = restoring
            .iter()
            .min_by(|a, b| distance(centre(a)).total_cmp(&distance(centre(b))))
        else {
            if let Some(y_zero_m) = unstable {
                return Err(ConicityError::NoRestoringZero { y_zero_m });
            }
            let min = d.iter().copied().fold(f64::INFINITY, f64::min);
            let max = d.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            return Err(ConicityError::NoZeroCrossing {
                min_delta_r_m: min,
                max_delta_r_m: max,
            });
        };
        let (left, right) = centre(&(p, i));
        let n = y.len();
        let slope = |k: usize| (d[k + 1] - d[k]) / (y[k + 1] - y[k]);

        // Right side: segments from the one holding `right` to the end.
        let first_right = if i == p + 1 { p } else { i - 1 };
        let mut right_side = Side::new(1.0);
        for k in first_right..n - 1 {
            let (start, g0) = if k == first_right {
                (right, 0.0)
            } else {
                (y[k], d[k])
            };
            right_side.push(start, y[k + 1] - start, g0, d[k + 1], slope(k));
        }
        // Left side: segments from the one holding `left` down to the first;
        // the outward slope of W is −Δr.
        let mut left_side = Side::new(-1.0);
        for k in (0..=p).rev() {
            let (start, g0) = if k == p {
                (left, 0.0)
            } else {
                (y[k + 1], -d[k + 1])
            };
            left_side.push(start, start - y[k], g0, -d[k], slope(k));
        }
        Ok(Well {
            left,
            right,
            left_side,
            right_side,
        })
    }
}

/// One piece of W on one side of the centre, parameterised by the distance
/// t ≥ 0 from its start outwards: W = w0 + g0 t + s t²/2 (W relative to the
/// centre, g = dW/dt = ±Δr, s = dΔr/dy).
#[derive(Debug, Clone, Copy)]
struct Piece {
    start_y: f64,
    len: f64,
    w0: f64,
    g0: f64,
    s: f64,
    w_end: f64,
    /// Interior maximum of W on the piece, if it has one.
    w_peak: Option<f64>,
}

/// W outwards from the centre on one side (`dir` = +1 right, −1 left).
#[derive(Debug, Clone)]
struct Side {
    dir: f64,
    pieces: Vec<Piece>,
}

impl Side {
    fn new(dir: f64) -> Self {
        Self {
            dir,
            pieces: Vec::new(),
        }
    }

    fn push(&mut self, start_y: f64, len: f64, g0: f64, g_end: f64, s: f64) {
        let w0 = self.pieces.last().map_or(0.0, |p| p.w_end);
        // Trapezoid: exact for linear Δr.
        let w_end = w0 + 0.5 * len * (g0 + g_end);
        let w_peak = (s < 0.0 && g0 > 0.0 && -g0 / s < len).then(|| w0 + g0 * g0 / (-2.0 * s));
        self.pieces.push(Piece {
            start_y,
            len,
            w0,
            g0,
            s,
            w_end,
            w_peak,
        });
    }

    /// Highest W on the side.
    fn max_w(&self) -> f64 {
        self.pieces.iter().fold(0.0_f64, |m, p| {
            m.max(p.w_end).max(p.w_peak.unwrap_or(f64::NEG_INFINITY))
        })
    }

    /// The first y outwards from the centre where W reaches `e` (> 0);
    /// `None` if it does not within the table.
    fn turn(&self, e: f64) -> Option<f64> {
        for p in &self.pieces {
            if p.w0 >= e {
                return Some(p.start_y);
            }
            let reached = p.w_end >= e || p.w_peak.is_some_and(|w| w >= e);
            if !reached {
                continue;
            }
            // First root of f(t) = (w0 − e) + g0 t + s t²/2 in (0, len], by the
            // cancellation-free form of the quadratic formula.
            let f0 = p.w0 - e;
            let disc = (p.g0 * p.g0 - 2.0 * p.s * f0).max(0.0);
            let t = if p.g0 >= 0.0 {
                let den = p.g0 + disc.sqrt();
                if den > 0.0 { -2.0 * f0 / den } else { p.len }
            } else if p.s > 0.0 {
                (-p.g0 + disc.sqrt()) / p.s
            } else {
                p.len
            };
            let t = if t.is_finite() {
                t.clamp(0.0, p.len)
            } else {
                p.len
            };
            return Some(p.start_y + self.dir * t);
        }
        None
    }
}

/// The potential well around the centre [left, right] (W = 0 there).
#[derive(Debug, Clone)]
struct Well {
    left: f64,
    right: f64,
    left_side: Side,
    right_side: Side,
}

impl Well {
    /// Turning points (y1, y2) at energy e.
    fn turns(&self, e: f64) -> Option<(f64, f64)> {
        Some((self.left_side.turn(e)?, self.right_side.turn(e)?))
    }
}

/// Turning points of one oscillation.
#[derive(Debug, Clone, Copy)]
enum Orbit {
    /// The amplitude fits where Δr = 0: no restoring force.
    Free { y1: f64, y2: f64 },
    /// A proper oscillation between y1 and y2.
    Turning { y1: f64, y2: f64 },
}

/// Everything that depends on Δr only, shared by the amplitudes of a curve.
struct Solver<'a> {
    dr: &'a DeltaRFunction,
    well: Well,
    /// Energy at which the oscillation reaches the end of the table (or
    /// would leave the well for good).
    e_cap: f64,
    /// Width y2 − y1 at `e_cap`.
    width_max: f64,
}

impl<'a> Solver<'a> {
    fn new(dr: &'a DeltaRFunction) -> Result<Self, ConicityError> {
        let well = dr.well()?;
        let e_cap = well.left_side.max_w().min(well.right_side.max_w());
        let width_max = match well.turns(e_cap) {
            Some((y1, y2)) => y2 - y1,
            // Only by round-off: fall back on the table ends.
            None => {
                let y = dr.y_m();
                y[y.len() - 1] - y[0]
            }
        }
        .max(well.right - well.left);
        Ok(Self {
            dr,
            well,
            e_cap,
            width_max,
        })
    }

    fn max_amplitude_m(&self) -> f64 {
        0.5 * self.width_max
    }

    fn width(&self, e: f64) -> f64 {
        self.well.turns(e).map_or(f64::INFINITY, |(y1, y2)| y2 - y1)
    }

    /// Turning points of the oscillation of amplitude `a` (m).
    fn orbit(&self, a: f64) -> Result<Orbit, ConicityError> {
        let target = 2.0 * a;
        let flat = self.well.right - self.well.left;
        // (Relative slack: a tabulated grid rarely spans the stretch exactly.)
        if target <= flat * (1.0 + 1e-12) {
            let mid = 0.5 * (self.well.left + self.well.right);
            return Ok(Orbit::Free {
                y1: mid - a,
                y2: mid + a,
            });
        }
        if target > self.width_max * (1.0 + 1e-12) {
            return Err(ConicityError::AmplitudeOutOfRange {
                amplitude_m: a,
                max_amplitude_m: self.max_amplitude_m(),
            });
        }
        if target >= self.width_max {
            let (y1, y2) =
                self.well
                    .turns(self.e_cap)
                    .ok_or(ConicityError::AmplitudeOutOfRange {
                        amplitude_m: a,
                        max_amplitude_m: self.max_amplitude_m(),
                    })?;
            return Ok(Orbit::Turning { y1, y2 });
        }
        // Bisection on the energy: the width grows with it.
        let (mut lo, mut hi) = (0.0_f64, self.e_cap);
        let (mut w_lo, mut w_hi) = (flat, self.width_max);
        for _ in 0..2000 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            let w = self.width(mid);
            if w < target {
                (lo, w_lo) = (mid, w);
            } else {
                (hi, w_hi) = (mid, w);
            }
            if (w - target).abs() <= 1e-15 * target {
                break;
            }
        }
        let e = if (w_hi - target).abs() <= (target - w_lo).abs() {
            hi
        } else {
            lo
        };
        let (y1, y2) = match self.well.turns(e) {
            Some(t) if ((t.1 - t.0) - target).abs() <= 1e-9 * target => t,
            _ => {
                return Err(ConicityError::NoOrbit {
                    amplitude_m: a,
                    width_below_m: w_lo,
                    width_above_m: w_hi,
                });
            }
        };
        Ok(Orbit::Turning { y1, y2 })
    }

    fn oscillation(
        &self,
        contact_distance_m: f64,
        nominal_radius_m: f64,
        amplitude_m: f64,
    ) -> Result<KinematicOscillation, ConicityError> {
        check_positive("contact distance e", contact_distance_m)?;
        check_positive("nominal rolling radius r0", nominal_radius_m)?;
        check_positive("amplitude", amplitude_m)?;
        let free = |y1: f64, y2: f64| KinematicOscillation {
            amplitude_m,
            y_min_m: y1,
            y_max_m: y2,
            wavelength_m: f64::INFINITY,
            tan_gamma_e: 0.0,
        };
        let (y1, y2) = match self.orbit(amplitude_m)? {
            Orbit::Free { y1, y2 } => return Ok(free(y1, y2)),
            Orbit::Turning { y1, y2 } => (y1, y2),
        };
        let Some(integral) = self.period_integral(y1, y2, amplitude_m)? else {
            // Δr = 0 at a turning point: the wheelset creeps up to it and
            // never returns (infinite wavelength).
            return Ok(free(y1, y2));
        };
        // λ = 2 ∫ dy / |y′| with |y′| = √(2 (E − W) / (e r0))  (EN 15302 B.1)
        let wavelength_m = (2.0 * contact_distance_m * nominal_radius_m).sqrt() * integral;
        // Klingel: λ = 2π √(e r0 / (2 tan γe))  ⇔  tan γe = (π / I)²
        let tan_gamma_e = (PI / integral).powi(2);
        Ok(KinematicOscillation {
            amplitude_m,
            y_min_m: y1,
            y_max_m: y2,
            wavelength_m,
            tan_gamma_e,
        })
    }

    /// I = ∫_{y1}^{y2} dy / √(E − W(y)) (√m), or `None` when it diverges
    /// because Δr vanishes at a turning point.
    fn period_integral(
        &self,
        y1: f64,
        y2: f64,
        amplitude_m: f64,
    ) -> Result<Option<f64>, ConicityError> {
        let h = 0.5 * (y2 - y1);
        let ym = 0.5 * (y1 + y2);
        let y = self.dr.y_m();
        let d = self.dr.delta_r_m();
        // Right half: distance t = y2 − y from the right turning point, outward
        // force g = Δr; left half: t = y − y1, g = −Δr.
        let mut right = vec![(0.0, self.dr.interpolate(y2))];
        right.extend(
            y.iter()
                .zip(d)
                .rev()
                .filter(|&(&yk, _)| yk > ym && yk < y2)
                .map(|(&yk, &dk)| (y2 - yk, dk)),
        );
        right.push((h, self.dr.interpolate(ym)));
        let mut left = vec![(0.0, -self.dr.interpolate(y1))];
        left.extend(
            y.iter()
                .zip(d)
                .filter(|&(&yk, _)| yk > y1 && yk < ym)
                .map(|(&yk, &dk)| (yk - y1, -dk)),
        );
        left.push((h, -self.dr.interpolate(ym)));
        if right[0].1 <= 0.0 || left[0].1 <= 0.0 {
            return Ok(None);
        }
        let bad = Cell::new(None);
        let total = half_integral(&right, h, &|t| y2 - t, &bad)
            + half_integral(&left, h, &|t| y1 + t, &bad);
        if let Some((y_m, value)) = bad.get() {
            return Err(ConicityError::Integration {
                amplitude_m,
                y_m,
                value,
            });
        }
        if !total.is_finite() || total <= 0.0 {
            return Err(ConicityError::Integration {
                amplitude_m,
                y_m: ym,
                value: total,
            });
        }
        Ok(Some(total))
    }
}

/// ∫ over one half of the oscillation, from its turning point (t = 0) to the
/// middle (t = h), of dy / √(E − W), in the variable φ with
/// t = 2h sin²(φ/2) (so that t (2h − t) = h² sin²φ and the integrand is
/// h sin φ / √(E − W), finite at φ = 0). `nodes` are (t, g) at the turning
/// point, the tabulated points and the middle, g the outward slope of W.
fn half_integral(
    nodes: &[(f64, f64)],
    h: f64,
    y_of_t: &dyn Fn(f64) -> f64,
    bad: &Cell<Option<(f64, f64)>>,
) -> f64 {
    // E − W at the nodes, accumulated from the turning point (trapezoid,
    // exact for linear Δr).
    let mut q = Vec::with_capacity(nodes.len());
    q.push(0.0);
    for w in nodes.windows(2) {
        let last = q[q.len() - 1];
        q.push(last + 0.5 * (w[1].0 - w[0].0) * (w[0].1 + w[1].1));
    }
    let phi_of_t = |t: f64| 2.0 * (t / (2.0 * h)).clamp(0.0, 0.5).sqrt().asin();
    let mut sum = 0.0;
    for j in 0..nodes.len() - 1 {
        let ((ta, ga), (tb, gb)) = (nodes[j], nodes[j + 1]);
        let len = tb - ta;
        if len <= 0.0 {
            continue;
        }
        let qa = q[j];
        let slope = (gb - ga) / len;
        let f = |phi: f64| -> f64 {
            let t = 2.0 * h * (0.5 * phi).sin().powi(2);
            let u = t - ta;
            // E − W = Q(ta) + ∫_ta^t g, g linear on the piece.
            let qt = qa + u * (ga + 0.5 * slope * u);
            if qt > 0.0 && qt.is_finite() {
                h * phi.sin() / qt.sqrt()
            } else {
                if bad.get().is_none() {
                    bad.set(Some((y_of_t(t), qt)));
                }
                0.0
            }
        };
        let phi_a = phi_of_t(ta);
        let phi_b = if j + 2 == nodes.len() {
            FRAC_PI_2
        } else {
            phi_of_t(tb)
        };
        if phi_b > phi_a {
            let whole = gauss_legendre_8(phi_a, phi_b, f);
            sum += adaptive(&f, phi_a, phi_b, whole, 60);
        }
    }
    sum
}

/// Adaptive Gauss–Legendre: split until the halves agree with the whole to
/// 1e-13 (relative).
fn adaptive(f: &dyn Fn(f64) -> f64, a: f64, b: f64, whole: f64, depth: u32) -> f64 {
    let m = 0.5 * (a + b);
    let l = gauss_legendre_8(a, m, f);
    let r = gauss_legendre_8(m, b, f);
    let sum = l + r;
    if depth == 0 || (sum - whole).abs() <= 1e-13 * sum.abs() || m <= a || m >= b {
        return sum;
    }
    adaptive(f, a, m, l, depth - 1) + adaptive(f, m, b, r, depth - 1)
}

fn check_positive(name: &'static str, value: f64) -> Result<(), ConicityError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ConicityError::InvalidParameter { name, value })
    }
}

/// The kinematic oscillation of one amplitude.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct KinematicOscillation {
    /// Amplitude ŷ = (y_max − y_min)/2 asked for (m).
    pub amplitude_m: f64,
    /// Turning points y1 < y2 (m); for a free wheelset (tan γe = 0) the
    /// amplitude placed about the middle of the stretch where Δr = 0.
    pub y_min_m: f64,
    pub y_max_m: f64,
    /// Wavelength of the kinematic motion (m); infinite when Δr does not
    /// restore the wheelset over the amplitude (then tan γe = 0).
    pub wavelength_m: f64,
    /// Equivalent conicity tan γe (–).
    pub tan_gamma_e: f64,
}

/// The kinematic oscillation of amplitude `amplitude_m` (m): turning points,
/// wavelength (for contact distance `contact_distance_m` and rolling radius
/// `nominal_radius_m`, both m) and tan γe (EN 15302 Annex B).
pub fn kinematic_oscillation(
    dr: &DeltaRFunction,
    contact_distance_m: f64,
    nominal_radius_m: f64,
    amplitude_m: f64,
) -> Result<KinematicOscillation, ConicityError> {
    check_positive("contact distance e", contact_distance_m)?;
    check_positive("nominal rolling radius r0", nominal_radius_m)?;
    check_positive("amplitude", amplitude_m)?;
    Solver::new(dr)?.oscillation(contact_distance_m, nominal_radius_m, amplitude_m)
}

/// Equivalent conicity tan γe (–) at amplitude `amplitude_m` (m), EN 15302
/// Annex B. `contact_distance_m` (e) and `nominal_radius_m` (r0) are checked
/// but cancel out of tan γe (see the module documentation).
pub fn equivalent_conicity(
    dr: &DeltaRFunction,
    contact_distance_m: f64,
    nominal_radius_m: f64,
    amplitude_m: f64,
) -> Result<f64, ConicityError> {
    kinematic_oscillation(dr, contact_distance_m, nominal_radius_m, amplitude_m)
        .map(|o| o.tan_gamma_e)
}

/// One point of a conicity curve.
#[derive(Debug, Clone, PartialEq)]
pub struct ConicityPoint {
    /// Amplitude ŷ (m).
    pub amplitude_m: f64,
    pub result: Result<KinematicOscillation, ConicityError>,
}

impl ConicityPoint {
    /// tan γe (–), if it could be evaluated.
    pub fn tan_gamma_e(&self) -> Option<f64> {
        self.result.as_ref().ok().map(|o| o.tan_gamma_e)
    }

    /// Wavelength (m), if it could be evaluated (infinite for tan γe = 0).
    pub fn wavelength_m(&self) -> Option<f64> {
        self.result.as_ref().ok().map(|o| o.wavelength_m)
    }
}

/// tan γe and wavelength at each amplitude (m); the Δr analysis is shared.
pub fn conicity_curve(
    dr: &DeltaRFunction,
    contact_distance_m: f64,
    nominal_radius_m: f64,
    amplitudes_m: &[f64],
) -> Vec<ConicityPoint> {
    let solver = Solver::new(dr);
    amplitudes_m
        .iter()
        .map(|&amplitude_m| ConicityPoint {
            amplitude_m,
            result: solver
                .as_ref()
                .map_err(Clone::clone)
                .and_then(|s| s.oscillation(contact_distance_m, nominal_radius_m, amplitude_m)),
        })
        .collect()
}

/// tan γe at a few amplitudes, for reports (JSON).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConicitySummary {
    /// Amplitudes ŷ (mm).
    pub amplitude_mm: Vec<f64>,
    /// tan γe (–) at each amplitude; `null` where it cannot be evaluated
    /// (amplitude beyond the tabulated Δr, no centre, ...).
    pub tan_gamma_e: Vec<Option<f64>>,
    /// Largest amplitude the tabulated Δr supports (mm); `null` when Δr has
    /// no restoring centre.
    pub max_amplitude_mm: Option<f64>,
}

impl ConicitySummary {
    /// At ŷ = 1, 2, …, 6 mm ([`SUMMARY_AMPLITUDES_MM`]).
    pub fn new(dr: &DeltaRFunction) -> Self {
        Self::at_amplitudes_mm(dr, &SUMMARY_AMPLITUDES_MM)
    }

    /// No values (a Δr function that could not be formed).
    pub fn empty() -> Self {
        Self {
            amplitude_mm: SUMMARY_AMPLITUDES_MM.to_vec(),
            tan_gamma_e: vec![None; SUMMARY_AMPLITUDES_MM.len()],
            max_amplitude_mm: None,
        }
    }

    /// At the given amplitudes (mm).
    pub fn at_amplitudes_mm(dr: &DeltaRFunction, amplitudes_mm: &[f64]) -> Self {
        let amplitudes_m: Vec<f64> = amplitudes_mm.iter().map(|a| a * 1e-3).collect();
        let curve = conicity_curve(
            dr,
            EN15302_CONTACT_DISTANCE_M,
            EN15302_NOMINAL_RADIUS_M,
            &amplitudes_m,
        );
        Self {
            amplitude_mm: amplitudes_mm.to_vec(),
            tan_gamma_e: curve.iter().map(ConicityPoint::tan_gamma_e).collect(),
            max_amplitude_mm: dr.max_amplitude_m().ok().map(|a| a * 1e3),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const E: f64 = EN15302_CONTACT_DISTANCE_M;
    const R0: f64 = EN15302_NOMINAL_RADIUS_M;

    /// Δr(y) = f(y) on y = −half … half (mm) at `step` (mm).
    fn tabulate(half_mm: f64, step_mm: f64, f: impl Fn(f64) -> f64) -> DeltaRFunction {
        let n = (2.0 * half_mm / step_mm).round() as usize;
        let y: Vec<f64> = (0..=n)
            .map(|i| (-half_mm + i as f64 * step_mm) * 1e-3)
            .collect();
        let d = y.iter().map(|&y| f(y)).collect();
        DeltaRFunction::new(y, d).unwrap()
    }

    /// Pure cone Δr = 2λy: tan γe = λ at every amplitude and the wavelength
    /// is Klingel's 2π √(e r0 / (2λ)).
    #[test]
    fn pure_cone() {
        for lambda in [0.01, 0.05, 0.15, 0.4] {
            let dr = tabulate(10.0, 0.5, |y| 2.0 * lambda * y);
            for a_mm in [0.1, 0.5, 1.0, 2.37, 3.0, 6.0, 9.9, 10.0] {
                let o = kinematic_oscillation(&dr, E, R0, a_mm * 1e-3).unwrap();
                assert!(
                    (o.tan_gamma_e - lambda).abs() < 1e-9,
                    "{lambda} {a_mm}: {o:?}"
                );
                let klingel = 2.0 * PI * (E * R0 / (2.0 * lambda)).sqrt();
                assert!((o.wavelength_m / klingel - 1.0).abs() < 1e-9);
                assert!((o.y_min_m + a_mm * 1e-3).abs() < 1e-12);
                assert!((o.y_max_m - a_mm * 1e-3).abs() < 1e-12);
            }
        }
    }

    /// Klingel: 2π √(b0 R0 / λ) = 15.96 m for b0 = 0.75 m, R0 = 0.43 m,
    /// λ = 0.05 (e = 2 b0).
    #[test]
    fn klingel_wavelength() {
        let dr = tabulate(8.0, 0.1, |y| 2.0 * 0.05 * y);
        let o = kinematic_oscillation(&dr, 1.5, 0.43, 3e-3).unwrap();
        let expected = 2.0 * PI * (0.75_f64 * 0.43 / 0.05).sqrt();
        assert!((o.wavelength_m - expected).abs() < 1e-9, "{o:?}");
        assert!((o.wavelength_m - 15.96).abs() < 0.005, "{o:?}");
        assert!((o.tan_gamma_e - 0.05).abs() < 1e-12);
    }

    /// tan γe does not depend on e and r0; the wavelength scales with √(e r0).
    #[test]
    fn contact_distance_and_radius_cancel() {
        let dr = tabulate(8.0, 0.1, |y| 0.3 * y + 40.0 * y * y * y);
        let a = kinematic_oscillation(&dr, 1.5, 0.46, 4e-3).unwrap();
        let b = kinematic_oscillation(&dr, 1.435, 0.4595, 4e-3).unwrap();
        assert!((a.tan_gamma_e - b.tan_gamma_e).abs() < 1e-12);
        let ratio = (1.5 * 0.46 / (1.435 * 0.4595_f64)).sqrt();
        assert!((a.wavelength_m / b.wavelength_m - ratio).abs() < 1e-12);
    }

    /// A cone centred off y = 0 (different wheel diameters).
    #[test]
    fn shifted_cone() {
        let (lambda, y0) = (0.2, 1.3e-3);
        let dr = tabulate(8.0, 0.1, |y| 2.0 * lambda * (y - y0));
        let (l, r) = dr.centre_m().unwrap();
        assert!((l - y0).abs() < 1e-15 && (r - y0).abs() < 1e-15);
        let o = kinematic_oscillation(&dr, E, R0, 3e-3).unwrap();
        assert!((o.tan_gamma_e - lambda).abs() < 1e-9);
        assert!((o.y_min_m - (y0 - 3e-3)).abs() < 1e-12);
        assert!((o.y_max_m - (y0 + 3e-3)).abs() < 1e-12);
    }

    /// Two cones, λ1 for y < 0 and λ2 for y > 0: half a harmonic period on
    /// each side, tan γe = 4 / (1/√λ1 + 1/√λ2)², turning points with
    /// λ1 y1² = λ2 y2².
    #[test]
    fn two_cones() {
        let (l1, l2) = (0.05, 0.3);
        let dr = tabulate(8.0, 0.1, |y| 2.0 * if y < 0.0 { l1 } else { l2 } * y);
        let expected = 4.0 / (1.0 / l1.sqrt() + 1.0 / l2.sqrt()).powi(2);
        for a_mm in [0.05, 0.5, 1.0, 2.5, 4.0] {
            let o = kinematic_oscillation(&dr, E, R0, a_mm * 1e-3).unwrap();
            assert!((o.tan_gamma_e - expected).abs() < 1e-9, "{a_mm}: {o:?}");
            let w = l1 * o.y_min_m * o.y_min_m - l2 * o.y_max_m * o.y_max_m;
            assert!(w.abs() < 1e-18, "{w}");
        }
    }

    /// Δr = 0 for |y| ≤ a, cones 2λ(y ∓ a) beyond: tan γe = 0 for ŷ ≤ a and
    /// λ / (1 + 2a / (π (ŷ − a)))² beyond (straight run across the dead band
    /// plus half a harmonic period on each side).
    #[test]
    fn dead_band() {
        let (lambda, band) = (0.15, 1.5e-3);
        let dr = tabulate(8.0, 0.1, |y| {
            if y.abs() <= band {
                0.0
            } else {
                2.0 * lambda * (y - band.copysign(y))
            }
        });
        let (l, r) = dr.centre_m().unwrap();
        assert!((l + band).abs() < 1e-15 && (r - band).abs() < 1e-15);
        for a_mm in [0.5, 1.0, 1.5] {
            let o = kinematic_oscillation(&dr, E, R0, a_mm * 1e-3).unwrap();
            assert_eq!(o.tan_gamma_e, 0.0);
            assert!(o.wavelength_m.is_infinite());
        }
        for a_mm in [1.5001, 1.52, 1.6, 2.0, 3.0, 6.0] {
            let a = a_mm * 1e-3;
            let o = kinematic_oscillation(&dr, E, R0, a).unwrap();
            let expected = lambda / (1.0 + 2.0 * band / (PI * (a - band))).powi(2);
            assert!(
                (o.tan_gamma_e - expected).abs() < 1e-9 * expected.max(1e-3),
                "{a_mm}: {} vs {expected}",
                o.tan_gamma_e
            );
        }
    }

    #[test]
    fn mirrored_is_the_same_wheelset() {
        let dr = tabulate(8.0, 0.1, |y| {
            0.0005 + 0.2 * y + 10.0 * y * y + 4000.0 * y * y * y
        });
        let m = dr.mirrored();
        assert_eq!(m.y_m()[0], -dr.y_m()[dr.y_m().len() - 1]);
        for a_mm in [0.5, 1.0, 2.0, 3.0] {
            let a = equivalent_conicity(&dr, E, R0, a_mm * 1e-3).unwrap();
            let b = equivalent_conicity(&m, E, R0, a_mm * 1e-3).unwrap();
            assert!((a - b).abs() < 1e-12, "{a_mm}: {a} {b}");
        }
    }

    #[test]
    fn bad_tables_are_refused() {
        use ConicityError::*;
        let err = DeltaRFunction::new(vec![0.0, 1.0, 2.0], vec![0.0, 1.0]).unwrap_err();
        assert!(matches!(
            err,
            LengthMismatch {
                y_points: 3,
                delta_r_points: 2
            }
        ));
        let err = DeltaRFunction::new(vec![0.0, 1.0], vec![0.0, 1.0]).unwrap_err();
        assert!(matches!(err, TooFewPoints { points: 2, min: 3 }));
        let err = DeltaRFunction::new(vec![0.0, 1.0, 1.0], vec![0.0, 1.0, 2.0]).unwrap_err();
        assert!(matches!(err, NotIncreasing { index: 2, .. }));
        let err = DeltaRFunction::new(vec![0.0, 1.0, 2.0], vec![0.0, f64::NAN, 2.0]).unwrap_err();
        assert!(matches!(
            err,
            NonFinite {
                index: 1,
                quantity: "Δr",
                ..
            }
        ));
        let err =
            DeltaRFunction::new(vec![0.0, f64::INFINITY, 2.0], vec![0.0, 1.0, 2.0]).unwrap_err();
        assert!(matches!(
            err,
            NonFinite {
                index: 1,
                quantity: "y",
                ..
            }
        ));
        assert!(err.to_string().contains("non-finite"));
    }

    #[test]
    fn bad_calls_are_refused() {
        use ConicityError::*;
        let cone = tabulate(5.0, 0.1, |y| 0.4 * y);
        for a in [0.0, -1e-3, f64::NAN] {
            let err = equivalent_conicity(&cone, E, R0, a).unwrap_err();
            assert!(matches!(
                err,
                InvalidParameter {
                    name: "amplitude",
                    ..
                }
            ));
        }
        let err = equivalent_conicity(&cone, 0.0, R0, 1e-3).unwrap_err();
        assert!(matches!(err, InvalidParameter { .. }));
        let err = equivalent_conicity(&cone, E, R0, 5.5e-3).unwrap_err();
        match err {
            AmplitudeOutOfRange {
                amplitude_m,
                max_amplitude_m,
            } => {
                assert_eq!(amplitude_m, 5.5e-3);
                assert!((max_amplitude_m - 5e-3).abs() < 1e-12);
            }
            other => panic!("{other:?}"),
        }
        // The full width of the table is still an oscillation.
        let t = equivalent_conicity(&cone, E, R0, 5e-3).unwrap();
        assert!((t - 0.2).abs() < 1e-9);

        let one_sided = tabulate(5.0, 0.1, |y| 0.01 + 0.4 * y * y);
        let err = equivalent_conicity(&one_sided, E, R0, 1e-3).unwrap_err();
        assert!(matches!(err, NoZeroCrossing { .. }), "{err:?}");

        let reversed = tabulate(5.0, 0.1, |y| -0.4 * (y - 1e-3));
        let err = equivalent_conicity(&reversed, E, R0, 1e-3).unwrap_err();
        match err {
            NoRestoringZero { y_zero_m } => assert!((y_zero_m - 1e-3).abs() < 1e-15),
            other => panic!("{other:?}"),
        }
        // Mirroring alone does not cure a single flipped sign ...
        assert!(equivalent_conicity(&reversed.mirrored(), E, R0, 1e-3).is_err());
        // ... negating Δr does.
        let fixed = DeltaRFunction::new(
            reversed.y_m().to_vec(),
            reversed.delta_r_m().iter().map(|d| -d).collect(),
        )
        .unwrap();
        assert!((equivalent_conicity(&fixed, E, R0, 1e-3).unwrap() - 0.2).abs() < 1e-9);
    }

    /// Δr with restoring zeros at 1 mm and 4 mm and an unstable one at
    /// 2.5 mm: small oscillations around 1 mm, a gap where the well merges
    /// with the one at 4 mm, then oscillations across both.
    #[test]
    fn two_wells() {
        let y_mm = [-5.0, 1.0, 2.0, 3.0, 4.0, 10.0];
        let d_mm = [-6.0, 0.0, 1.0, -1.0, 0.0, 6.0];
        let dr = DeltaRFunction::from_mm(&y_mm, &d_mm).unwrap();
        let (l, r) = dr.centre_m().unwrap();
        assert!((l - 1e-3).abs() < 1e-15 && (r - 1e-3).abs() < 1e-15);
        // Below the barrier at W = 0.75 mm²: width up to 2.5 + (√1.5 − 1) mm.
        let o = kinematic_oscillation(&dr, E, R0, 1e-3).unwrap();
        assert!(o.tan_gamma_e > 0.0 && o.y_max_m < 2.5e-3);
        let err = equivalent_conicity(&dr, E, R0, 2e-3).unwrap_err();
        match err {
            ConicityError::NoOrbit {
                width_below_m,
                width_above_m,
                ..
            } => {
                assert!((width_below_m - (1.5 + 1.5_f64.sqrt()) * 1e-3).abs() < 1e-9);
                assert!((width_above_m - 2.0 * 1.5_f64.sqrt() * 1e-3 - 3e-3).abs() < 1e-9);
            }
            other => panic!("{other:?}"),
        }
        let o = kinematic_oscillation(&dr, E, R0, 3e-3).unwrap();
        assert!(o.tan_gamma_e > 0.0 && o.y_max_m > 4e-3);
    }

    #[test]
    fn curve_and_summary() {
        let cone = tabulate(5.0, 0.1, |y| 0.4 * y);
        let curve = conicity_curve(&cone, E, R0, &[1e-3, 3e-3, 7e-3]);
        assert_eq!(curve.len(), 3);
        assert!((curve[0].tan_gamma_e().unwrap() - 0.2).abs() < 1e-9);
        assert!(curve[1].wavelength_m().unwrap() > 0.0);
        assert!(matches!(
            curve[2].result,
            Err(ConicityError::AmplitudeOutOfRange { .. })
        ));

        let summary = ConicitySummary::new(&cone);
        assert_eq!(summary.amplitude_mm, SUMMARY_AMPLITUDES_MM.to_vec());
        assert_eq!(summary.tan_gamma_e[5], None);
        assert!((summary.tan_gamma_e[4].unwrap() - 0.2).abs() < 1e-9);
        assert!((summary.max_amplitude_mm.unwrap() - 5.0).abs() < 1e-9);
        let json = serde_json::to_value(&summary).unwrap();
        assert_eq!(json["amplitude_mm"][0], 1.0);
        assert!(json["tan_gamma_e"][5].is_null());

        let no_centre = tabulate(5.0, 0.1, |_| 1e-3);
        let summary = ConicitySummary::new(&no_centre);
        assert!(summary.tan_gamma_e.iter().all(Option::is_none));
        assert_eq!(summary.max_amplitude_mm, None);
    }
}
