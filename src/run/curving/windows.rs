//! Sliding 2 m means and percentiles of a run's series, the evaluation
//! EN 14363:2016 §7.6 prescribes for the running-safety quantities
//! ((ΣY)_2m, (Y/Q)_2m: the mean over 2 m of track; the quasi-static values
//! Y_qst, Q_qst: the 50 % percentile of the signal over a curve section;
//! the estimated maximum: the 99.85 % percentile). The windows and their
//! validity are those of Nadal's criterion ([`crate::run::nadal`]): a
//! trailing window (d − 2 m, d] ends at every sample once 2 m are covered,
//! samples without a value are left out of its mean, and it is valid only
//! with at least [`MIN_LOADED_SAMPLES`] values that are more than
//! [`MIN_LOADED_FRACTION`] of its samples.

use crate::run::nadal::{MIN_LOADED_FRACTION, MIN_LOADED_SAMPLES};

/// The mean of the trailing window ending at each sample (`None` before
/// `window_m` is covered, or when the window is not valid); `position_m`
/// is non-decreasing (a NaN position never completes a window).
pub fn sliding_means(
    values: &[Option<f64>],
    position_m: &[f64],
    window_m: f64,
) -> Vec<Option<f64>> {
    let n = values.len().min(position_m.len());
    let mut out = vec![None; n];
    let Some(&start) = position_m.first() else {
        return out;
    };
    let mut lo = 0;
    let (mut sum, mut count) = (0.0, 0usize);
    for i in 0..n {
        let d = position_m[i];
        if let Some(v) = values[i] {
            sum += v;
            count += 1;
        }
        while lo < i && position_m[lo] <= d - window_m {
            if let Some(v) = values[lo] {
                sum -= v;
                count -= 1;
            }
            lo += 1;
        }
        let covered = d - start >= window_m;
        if !covered {
            continue;
        }
        let samples = i + 1 - lo;
        if count >= MIN_LOADED_SAMPLES && count as f64 > MIN_LOADED_FRACTION * samples as f64 {
            out[i] = Some(sum / count as f64);
        }
    }
    out
}

/// The `p` percentile (0 … 100) of the finite `values`: linear
/// interpolation between the order statistics at rank p/100·(n − 1)
/// (Hyndman & Fan 1996, definition 7); `None` without finite values.
pub fn percentile(values: &[f64], p: f64) -> Option<f64> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() || !(0.0..=100.0).contains(&p) {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let rank = p / 100.0 * (v.len() - 1) as f64;
    let (i, f) = (rank.floor() as usize, rank.fract());
    let hi = v[(i + 1).min(v.len() - 1)];
    Some(v[i] + f * (hi - v[i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sliding_means_follow_the_nadal_windows() {
        // 0.5 m apart: a 2 m window holds 4 samples.
        let d: Vec<f64> = (0..8).map(|k| 0.5 * f64::from(k)).collect();
        let v: Vec<Option<f64>> = (0..8).map(|k| Some(f64::from(k))).collect();
        let m = sliding_means(&v, &d, 2.0);
        assert_eq!(&m[..4], &[None; 4]);
        // Window ending at sample 4 (2 m): samples 1 … 4.
        assert_eq!(m[4], Some(2.5));
        assert_eq!(m[7], Some(5.5));
        // Two of four without a value: not valid.
        let mut v = v;
        v[6] = None;
        v[7] = None;
        let m = sliding_means(&v, &d, 2.0);
        assert_eq!(m[6], Some(4.0));
        assert_eq!(m[7], None);
    }

    #[test]
    fn percentiles_interpolate_the_order_statistics() {
        let v = [3.0, 1.0, f64::NAN, 2.0, 4.0];
        assert_eq!(percentile(&v, 50.0), Some(2.5));
        assert_eq!(percentile(&v, 0.0), Some(1.0));
        assert_eq!(percentile(&v, 100.0), Some(4.0));
        // 99.85 % of 1 … 1001: rank 998.5.
        let w: Vec<f64> = (1..=1001).map(f64::from).collect();
        assert!((percentile(&w, 99.85).unwrap() - 999.5).abs() < 1e-9);
        assert_eq!(percentile(&[f64::NAN], 50.0), None);
        assert_eq!(percentile(&v, 101.0), None);
    }
}
