//! Akima slopes (H. Akima, "A new method of interpolation and smooth curve
//! fitting based on local procedures", J. ACM 17(4), 1970, eq. (1)–(4)),
//! with the end extension and the degenerate-weight rule of SciPy's
//! `Akima1DInterpolator(method="akima")`:
//!
//! * two extra secant slopes at each end by linear extrapolation
//!   (`m_{−1} = 2m_0 − m_1`, `m_{−2} = 2m_{−1} − m_0`, likewise at the end);
//! * knot slope `t_i = (w1·m_{i−1} + w2·m_i)/(w1 + w2)` with
//!   `w1 = |m_{i+1} − m_i|`, `w2 = |m_{i−1} − m_{i−2}|`;
//! * where `w1 + w2 ≤ 1e-9·max(w1 + w2)` (locally straight data) the mean
//!   `½(m_{i−1} + m_i)` is used.

pub(super) fn slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    // Secant slopes, padded with two extrapolated values on each side:
    // m[k + 2] is the slope of piece k.
    let mut m = vec![0.0; n + 3];
    for k in 0..n - 1 {
        m[k + 2] = (y[k + 1] - y[k]) / (x[k + 1] - x[k]);
    }
    if n == 2 {
        return vec![m[2], m[2]];
    }
    m[1] = 2.0 * m[2] - m[3];
    m[0] = 2.0 * m[1] - m[2];
    m[n + 1] = 2.0 * m[n] - m[n - 1];
    m[n + 2] = 2.0 * m[n + 1] - m[n];

    // |Δm| between neighbouring secants: dm[k] = |m[k+1] − m[k]|.
    let dm: Vec<f64> = m.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    // Knot i uses f1 = dm[i + 2] (ahead) and f2 = dm[i] (behind).
    let f12: Vec<f64> = (0..n).map(|i| dm[i + 2] + dm[i]).collect();
    let f12_max = f12.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let cutoff = 1e-9 * f12_max;
    (0..n)
        .map(|i| {
            if f12[i] > cutoff {
                // SciPy's form: m_{i−1} + (f2/f12)(m_i − m_{i−1}).
                m[i + 1] + (dm[i] / f12[i]) * (m[i + 2] - m[i + 1])
            } else {
                0.5 * (m[i + 3] + m[i])
            }
        })
        .collect()
}
