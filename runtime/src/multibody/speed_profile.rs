//! The prescribed speed of the track-following references against time:
//! a constant-rate [`SpeedRamp`] or a piecewise-linear [`SpeedSchedule`]
//! through knots (t, V), both behind [`SpeedProfile`]
//! (docs/reference/10-scene-files.md, `[initial] speed_profile`).

use super::track_motion::SpeedRamp;

/// One knot of a [`SpeedSchedule`]: the speed `speed_m_s` (m/s) at time
/// `t_s` (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedKnot {
    pub t_s: f64,
    pub speed_m_s: f64,
}

/// A piecewise-linear speed schedule through knots (t₀ = 0 < t₁ < … < tₙ,
/// V_k ≥ 0; checked by [`crate::multibody::SystemSettings::validate_motion`]):
///
/// V(t) = V_k + a_k (t − t_k) on [t_k, t_{k+1}], a_k = (V_{k+1} − V_k)/(t_{k+1} − t_k),
/// V(t) = Vₙ after the last knot (held), V(t) = V₀ before t = 0;
///
/// the distance covered is its exact integral,
/// s(t) − s0 = S_k + V_k τ + a_k τ²/2 with τ = t − t_k and S_k the distance
/// at knot k (uniformly accelerated motion on each segment). The speeds are
/// never negative, so the distance never decreases.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedSchedule {
    knots: Vec<SpeedKnot>,
    /// S_k (m), the distance covered at knot k.
    distance_at_knot_m: Vec<f64>,
}

impl SpeedSchedule {
    /// The schedule through `knots` (taken as given: the rules are the
    /// settings' validation; an empty schedule is at rest).
    pub fn new(knots: Vec<SpeedKnot>) -> Self {
        let mut distance_at_knot_m = Vec::with_capacity(knots.len());
        let mut s = 0.0;
        for (k, knot) in knots.iter().enumerate() {
            if k > 0 {
                let prev = knots[k - 1];
                // Trapezoid: exact for a linear V.
                s += 0.5 * (prev.speed_m_s + knot.speed_m_s) * (knot.t_s - prev.t_s);
            }
            distance_at_knot_m.push(s);
        }
        SpeedSchedule {
            knots,
            distance_at_knot_m,
        }
    }

    /// The knots.
    pub fn knots(&self) -> &[SpeedKnot] {
        &self.knots
    }

    /// The segment containing `t_s` (the index k of its first knot), `None`
    /// before the first knot or after the last one.
    fn segment(&self, t_s: f64) -> Option<usize> {
        let n = self.knots.len();
        if n < 2 || t_s < self.knots[0].t_s || t_s >= self.knots[n - 1].t_s {
            return None;
        }
        // The last knot with t_k <= t.
        Some(
            self.knots
                .partition_point(|k| k.t_s <= t_s)
                .saturating_sub(1),
        )
    }

    /// a_k (m/s²), the rate of segment k.
    fn rate_m_s2(&self, k: usize) -> f64 {
        let (p, q) = (self.knots[k], self.knots[k + 1]);
        (q.speed_m_s - p.speed_m_s) / (q.t_s - p.t_s)
    }

    /// V(t) (m/s), struct docs.
    pub fn speed_m_s(&self, t_s: f64) -> f64 {
        let (Some(first), Some(last)) = (self.knots.first(), self.knots.last()) else {
            return 0.0;
        };
        match self.segment(t_s) {
            Some(k) => self.knots[k].speed_m_s + self.rate_m_s2(k) * (t_s - self.knots[k].t_s),
            None if t_s < first.t_s => first.speed_m_s,
            None => last.speed_m_s,
        }
    }

    /// s(t) − s0 (m), the distance covered since t = 0, struct docs.
    pub fn distance_m(&self, t_s: f64) -> f64 {
        let (Some(first), Some(last)) = (self.knots.first(), self.knots.last()) else {
            return 0.0;
        };
        match self.segment(t_s) {
            Some(k) => {
                let tau = t_s - self.knots[k].t_s;
                self.distance_at_knot_m[k]
                    + self.knots[k].speed_m_s * tau
                    + 0.5 * self.rate_m_s2(k) * tau * tau
            }
            None if t_s < first.t_s => first.speed_m_s * (t_s - first.t_s),
            None => {
                let s_n = self.distance_at_knot_m.last().copied().unwrap_or(0.0);
                s_n + last.speed_m_s * (t_s - last.t_s)
            }
        }
    }

    /// The first time (s) at which the distance covered reaches `d_m`, or
    /// `None` if it never does (the schedule ends at rest first): found in
    /// the segment whose distances bracket `d_m`, the smallest root τ ≥ 0
    /// of V_k τ + a_k τ²/2 = d − S_k written as 2Δ/(V_k + √(V_k² + 2 a_k Δ))
    /// (no cancellation as a_k → 0).
    pub fn time_to_cover_s(&self, d_m: f64) -> Option<f64> {
        let first = self.knots.first()?;
        if d_m <= 0.0 {
            return Some(first.t_s);
        }
        for k in 0..self.knots.len() - 1 {
            if self.distance_at_knot_m[k + 1] >= d_m {
                let (v, a) = (self.knots[k].speed_m_s, self.rate_m_s2(k));
                let delta = d_m - self.distance_at_knot_m[k];
                let disc = (v * v + 2.0 * a * delta).max(0.0);
                let den = v + disc.sqrt();
                // den = 0 only for Δ = 0 (a segment at rest reaching d at its start).
                let tau = if den > 0.0 { 2.0 * delta / den } else { 0.0 };
                return Some(self.knots[k].t_s + tau);
            }
        }
        let (last, s_n) = (self.knots.last()?, *self.distance_at_knot_m.last()?);
        (last.speed_m_s > 0.0).then(|| last.t_s + (d_m - s_n) / last.speed_m_s)
    }

    /// The time of the last knot (s), after which the speed is held.
    pub fn end_time_s(&self) -> Option<f64> {
        self.knots.last().map(|k| k.t_s)
    }
}

/// The references' speed against time: a constant-rate ramp or a
/// piecewise-linear schedule ([`crate::multibody::SystemSettings::speed_profile`]).
#[derive(Debug, Clone, PartialEq)]
pub enum SpeedProfile {
    Ramp(SpeedRamp),
    Schedule(SpeedSchedule),
}

impl SpeedProfile {
    /// V(t) (m/s).
    pub fn speed_m_s(&self, t_s: f64) -> f64 {
        match self {
            SpeedProfile::Ramp(r) => r.speed_m_s(t_s),
            SpeedProfile::Schedule(s) => s.speed_m_s(t_s),
        }
    }

    /// s(t) − s0 (m), the distance covered since t = 0.
    pub fn distance_m(&self, t_s: f64) -> f64 {
        match self {
            SpeedProfile::Ramp(r) => r.distance_m(t_s),
            SpeedProfile::Schedule(s) => s.distance_m(t_s),
        }
    }

    /// The first time (s) at which the distance covered reaches `d_m`, or
    /// `None` if it never does.
    pub fn time_to_cover_s(&self, d_m: f64) -> Option<f64> {
        match self {
            SpeedProfile::Ramp(r) => r.time_to_cover_s(d_m),
            SpeedProfile::Schedule(s) => s.time_to_cover_s(d_m),
        }
    }

    /// When the speed is held from on (s): the ramp's end, the schedule's
    /// last knot; `None` for a constant speed or an unbounded acceleration.
    pub fn end_time_s(&self) -> Option<f64> {
        match self {
            SpeedProfile::Ramp(r) => r.end_time_s(),
            SpeedProfile::Schedule(s) => s.end_time_s(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn knot(t_s: f64, speed_m_s: f64) -> SpeedKnot {
        SpeedKnot { t_s, speed_m_s }
    }

    /// 10 m/s held 2 s, down to 6 m/s over 2 s (a = −2), held 1 s, up to
    /// 8 m/s over 1 s (a = +2), then held. Knot distances (hand): S = 0,
    /// 20, 20 + 16 = 36, 36 + 6 = 42, 42 + 7 = 49 m.
    fn schedule() -> SpeedSchedule {
        SpeedSchedule::new(vec![
            knot(0.0, 10.0),
            knot(2.0, 10.0),
            knot(4.0, 6.0),
            knot(5.0, 6.0),
            knot(6.0, 8.0),
        ])
    }

    #[test]
    fn speed_distance_and_time_in_every_segment() {
        let s = schedule();
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        // Held segment: V = 10, s = 10 t.
        assert_eq!(s.speed_m_s(1.0), 10.0);
        assert!(close(s.distance_m(1.0), 10.0));
        assert!(close(s.time_to_cover_s(15.0).unwrap(), 1.5));
        // Braking segment at τ = 1 s: V = 8, s = 20 + 10 − 1 = 29.
        assert!(close(s.speed_m_s(3.0), 8.0));
        assert!(close(s.distance_m(3.0), 29.0));
        assert!(close(s.time_to_cover_s(29.0).unwrap(), 3.0));
        // The knot itself: V = 6, s = 36.
        assert!(close(s.speed_m_s(4.0), 6.0));
        assert!(close(s.distance_m(4.0), 36.0));
        assert!(close(s.time_to_cover_s(36.0).unwrap(), 4.0));
        // Held at 6: t = 4.5 s, s = 39.
        assert!(close(s.distance_m(4.5), 39.0));
        assert!(close(s.time_to_cover_s(39.0).unwrap(), 4.5));
        // Accelerating segment at τ = 0.5 s: V = 7, s = 42 + 3 + 0.25.
        assert!(close(s.speed_m_s(5.5), 7.0));
        assert!(close(s.distance_m(5.5), 45.25));
        assert!(close(s.time_to_cover_s(45.25).unwrap(), 5.5));
        // After the last knot: 8 m/s held, s = 49 + 8 (t − 6).
        assert_eq!(s.speed_m_s(100.0), 8.0);
        assert!(close(s.distance_m(8.0), 65.0));
        assert!(close(s.time_to_cover_s(65.0).unwrap(), 8.0));
        assert_eq!(s.end_time_s(), Some(6.0));
        // Before t = 0: V0 held (no extrapolation of the first segment).
        assert_eq!(s.speed_m_s(-1.0), 10.0);
        assert_eq!(s.time_to_cover_s(0.0), Some(0.0));
    }

    #[test]
    fn a_schedule_ending_at_rest_never_covers_more() {
        // 4 m/s down to 0 over 2 s: 4 m, then at rest.
        let s = SpeedSchedule::new(vec![knot(0.0, 4.0), knot(2.0, 0.0)]);
        assert!((s.distance_m(10.0) - 4.0).abs() < 1e-12);
        assert!((s.time_to_cover_s(4.0).unwrap() - 2.0).abs() < 1e-12);
        // s = 4t − t² = 3 at t = 1.
        assert!((s.time_to_cover_s(3.0).unwrap() - 1.0).abs() < 1e-12);
        assert_eq!(s.time_to_cover_s(4.1), None);
        // From rest: a start, then a held speed.
        let s = SpeedSchedule::new(vec![knot(0.0, 0.0), knot(2.0, 4.0)]);
        assert!((s.time_to_cover_s(1.0).unwrap() - 1.0).abs() < 1e-12);
        assert!((s.time_to_cover_s(8.0).unwrap() - 3.0).abs() < 1e-12);
        // One knot: a constant speed; none: at rest, no panic.
        let one = SpeedSchedule::new(vec![knot(0.0, 5.0)]);
        assert_eq!((one.speed_m_s(3.0), one.distance_m(3.0)), (5.0, 15.0));
        assert_eq!(one.time_to_cover_s(10.0), Some(2.0));
        let none = SpeedSchedule::new(vec![]);
        assert_eq!((none.speed_m_s(1.0), none.distance_m(1.0)), (0.0, 0.0));
        assert_eq!(none.time_to_cover_s(1.0), None);
    }

    #[test]
    fn the_profile_dispatches_to_the_ramp_or_the_schedule() {
        let ramp = SpeedProfile::Ramp(SpeedRamp::constant(12.0));
        assert_eq!(ramp.distance_m(2.0), 24.0);
        assert_eq!(ramp.end_time_s(), None);
        let sched = SpeedProfile::Schedule(schedule());
        assert!((sched.distance_m(3.0) - 29.0).abs() < 1e-12);
        assert_eq!(sched.end_time_s(), Some(6.0));
    }
}
