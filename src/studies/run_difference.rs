//! The lateral difference of one wheelset between two runs, the one helper
//! behind `sim compare` (by track position) and the speed/accuracy study
//! (by time, runs of one scene at one speed; docs/guide/speed-accuracy-tradeoff.md).
//!
//! Compared at equal **track position** (the default of `sim compare`),
//! runs at different speeds line up where the vehicle was on the same
//! piece of track: a hunting wheelset whose wavelength does not depend on
//! the speed (Klingel's kinematic wavelength) gives the same curve against
//! s at 10 and 12 m/s, while against time the two curves drift apart by
//! their whole amplitude. The abscissa is the wheelset's `track_s_m`
//! series; a file written before it was stored (NaN there) falls back to
//! `distance_m` (the distance travelled since the start), which lines up
//! only runs that started at the same s: the caller is told
//! ([`Difference::fell_back`]) and warns, naming the file.

use anyhow::{Result, bail, ensure};
use runtime::results::{RunResults, WheelsetSeries};

/// What the runs are compared at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Abscissa {
    /// Equal time since the start (s).
    Time,
    /// Equal track position of the wheelset (m).
    TrackPosition,
}

impl Abscissa {
    /// The unit of [`Difference::span`].
    pub fn unit(self) -> &'static str {
        match self {
            Abscissa::Time => "s",
            Abscissa::TrackPosition => "m",
        }
    }
}

/// The lateral difference of one wheelset, run minus reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Difference {
    /// Largest |difference| (m).
    pub max_m: f64,
    /// RMS of the difference (m).
    pub rms_m: f64,
    /// The compared abscissa range (s or m, [`Abscissa::unit`]): from the
    /// first to the last reference sample inside the run's span.
    pub from: f64,
    pub to: f64,
    /// Samples compared.
    pub samples: usize,
    /// By track position: which of `[reference, run]` had no track
    /// position (NaN `track_s_m`, an older file); when either had none,
    /// both were compared by `distance_m`.
    pub fell_back: [bool; 2],
}

impl Difference {
    /// The length of the compared range (s or m).
    pub fn span(&self) -> f64 {
        self.to - self.from
    }
}

/// Whether wheelset `ws` has its track position at every sample.
fn has_track_position(ws: &WheelsetSeries) -> bool {
    !ws.track_s_m.is_empty() && ws.track_s_m.iter().all(|s| s.is_finite())
}

/// The abscissa of wheelset `ws` of `r`; by track position `track_s_m`,
/// or `distance_m` when `with_s` is false.
fn abscissa<'a>(
    r: &'a RunResults,
    ws: &'a WheelsetSeries,
    by: Abscissa,
    with_s: bool,
) -> &'a [f64] {
    match by {
        Abscissa::Time => &r.time_s,
        Abscissa::TrackPosition if with_s => &ws.track_s_m,
        Abscissa::TrackPosition => &ws.distance_m,
    }
}

/// The abscissa the runs' wheelset `wheelset` is plotted against by track
/// position: `track_s_m` when every run has it, else `distance_m` for all
/// (one axis for every curve); `true` when it is `track_s_m`.
pub fn all_have_track_position(runs: &[&RunResults], wheelset: usize) -> bool {
    runs.iter()
        .all(|r| r.wheelsets.get(wheelset).is_some_and(has_track_position))
}

/// Linear interpolation of `(x, y)` at `at` (x non-decreasing, `at` within).
fn interpolate(x: &[f64], y: &[f64], at: f64) -> f64 {
    let i = x.partition_point(|&v| v <= at);
    if i == 0 {
        return y[0];
    }
    if i >= x.len() {
        return y[x.len() - 1];
    }
    let (x0, x1) = (x[i - 1], x[i]);
    if x1 <= x0 {
        return y[i - 1];
    }
    y[i - 1] + (y[i] - y[i - 1]) * (at - x0) / (x1 - x0)
}

/// Max and RMS of wheelset `wheelset`'s lateral difference between `run`
/// and `reference` at equal `by`: over the reference's samples within the
/// run's span, the run interpolated linearly at them.
pub fn lateral_difference_by(
    reference: &RunResults,
    run: &RunResults,
    wheelset: usize,
    by: Abscissa,
) -> Result<Difference> {
    let (wr, wv) = match (
        reference.wheelsets.get(wheelset),
        run.wheelsets.get(wheelset),
    ) {
        (Some(a), Some(b)) => (a, b),
        _ => bail!("wheelset {wheelset} is not in both runs"),
    };
    ensure!(
        run.time_s.len() >= 2,
        "the run has {} samples, too few to compare",
        run.time_s.len()
    );
    // Both by s, or (one lacks it) both by the distance travelled: an s
    // against a distance would compare different places.
    let (has_r, has_v) = (has_track_position(wr), has_track_position(wv));
    let with_s = has_r && has_v;
    let xr = abscissa(reference, wr, by, with_s);
    let xv = abscissa(run, wv, by, with_s);
    let fell_back = match by {
        Abscissa::Time => [false, false],
        Abscissa::TrackPosition => [!has_r, !has_v],
    };
    for (x, which) in [(xr, "reference"), (xv, "run")] {
        if let Some(i) = (1..x.len()).find(|&i| x[i] < x[i - 1] || x[i].is_nan()) {
            bail!(
                "the {which}'s {} goes back at sample {i} ({} then {}): the wheelset runs backwards, compare by time",
                if by == Abscissa::Time {
                    "time"
                } else {
                    "track position"
                },
                x[i - 1],
                x[i]
            );
        }
    }
    let (x0, x1) = (xv[0], xv[xv.len() - 1]);
    let eps = 1e-12 * x1.abs().max(1.0);
    let (mut max, mut sum2, mut n) = (0.0_f64, 0.0, 0usize);
    let (mut first, mut last) = (f64::NAN, f64::NAN);
    for (&x, &yr) in xr.iter().zip(&wr.lateral_m) {
        if x < x0 - eps || x > x1 + eps {
            continue;
        }
        let d = interpolate(xv, &wv.lateral_m, x) - yr;
        ensure!(
            d.is_finite(),
            "the lateral displacement is not finite at {x} {}",
            by.unit()
        );
        max = max.max(d.abs());
        sum2 += d * d;
        n += 1;
        if first.is_nan() {
            first = x;
        }
        last = x;
    }
    ensure!(
        n > 0,
        "the run and the reference have no common {} span (run {x0} … {x1} {})",
        if by == Abscissa::Time {
            "time"
        } else {
            "track"
        },
        by.unit()
    );
    Ok(Difference {
        max_m: max,
        rms_m: (sum2 / n as f64).sqrt(),
        from: first,
        to: last,
        samples: n,
        fell_back,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use runtime::results::WheelsetSample;

    /// A wheelset hunting with a 16 m wavelength in s, run at `v` m/s from
    /// s = `s0`, 1 ms samples over 30 m.
    fn hunting(v: f64, s0: f64, with_s: bool) -> RunResults {
        let mut r = RunResults::with_wheelsets(["w"]);
        let n = (30.0 / v / 1e-3) as usize;
        for k in 0..=n {
            let t = k as f64 * 1e-3;
            let s = s0 + v * t;
            r.push(
                t,
                &[WheelsetSample {
                    lateral_m: 3e-3 * (2.0 * std::f64::consts::PI * s / 16.0).sin(),
                    distance_m: v * t,
                    track_s_m: if with_s { s } else { f64::NAN },
                    ..WheelsetSample::default()
                }],
            )
            .unwrap();
        }
        r
    }

    #[test]
    fn by_position_runs_at_two_speeds_agree_and_by_time_they_do_not() {
        let (slow, fast) = (hunting(10.0, 5.0, true), hunting(12.0, 5.0, true));
        let p = lateral_difference_by(&slow, &fast, 0, Abscissa::TrackPosition).unwrap();
        assert!(p.max_m < 1e-6, "{p:?}");
        assert!(
            (p.from - 5.0).abs() < 1e-9 && (p.span() - 30.0).abs() < 0.02,
            "{p:?}"
        );
        assert_eq!(p.fell_back, [false, false]);
        let t = lateral_difference_by(&slow, &fast, 0, Abscissa::Time).unwrap();
        assert!(t.max_m > 3e-3, "{t:?}");
        assert!((t.span() - 2.5).abs() < 1e-9, "{t:?}");
        // An old file (no s): by the distance travelled, told.
        let old = hunting(12.0, 5.0, false);
        let f = lateral_difference_by(&slow, &old, 0, Abscissa::TrackPosition).unwrap();
        assert_eq!(f.fell_back, [false, true]);
        // Both by distance: the same place, from 0.
        assert!(f.max_m < 1e-6 && f.from.abs() < 1e-12, "{f:?}");
        assert!(!all_have_track_position(&[&slow, &old], 0));
        assert!(all_have_track_position(&[&slow, &fast], 0));
        // Runs on different pieces of track have no common span.
        let far = hunting(10.0, 100.0, true);
        let e = lateral_difference_by(&slow, &far, 0, Abscissa::TrackPosition).unwrap_err();
        assert!(e.to_string().contains("no common track span"), "{e}");
    }
}
