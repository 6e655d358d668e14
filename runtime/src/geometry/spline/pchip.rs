//! Shape-preserving slopes: F. N. Fritsch & J. Butland, "A method for
//! constructing local monotone piecewise cubic interpolants", SIAM J. Sci.
//! Stat. Comput. 5(2), 1984 (weighted harmonic mean), with the three-point
//! end formula of C. Moler, *Numerical Computing with MATLAB* §3.6
//! (`pchiptx.m`) — the rules of MATLAB `pchip` and SciPy `PchipInterpolator`.
//!
//! Interior knot `k`: `d_k = 0` if the neighbouring secants `m_{k−1}`, `m_k`
//! differ in sign or either is zero, else
//! `1/d_k = (w1/m_{k−1} + w2/m_k)/(w1 + w2)`, `w1 = 2h_k + h_{k−1}`,
//! `w2 = h_k + 2h_{k−1}`.

pub(super) fn slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let m: Vec<f64> = y
        .windows(2)
        .zip(&h)
        .map(|(w, h)| (w[1] - w[0]) / h)
        .collect();
    if n == 2 {
        return vec![m[0], m[0]];
    }
    let mut d = vec![0.0; n];
    for k in 1..n - 1 {
        let (m0, m1) = (m[k - 1], m[k]);
        if m0 == 0.0 || m1 == 0.0 || m0.signum() != m1.signum() {
            d[k] = 0.0;
        } else {
            let w1 = 2.0 * h[k] + h[k - 1];
            let w2 = h[k] + 2.0 * h[k - 1];
            d[k] = 1.0 / ((w1 / m0 + w2 / m1) / (w1 + w2));
        }
    }
    d[0] = end_slope(h[0], h[1], m[0], m[1]);
    d[n - 1] = end_slope(h[n - 2], h[n - 3], m[n - 2], m[n - 3]);
    d
}

/// One-sided three-point slope at an end, limited to keep the shape.
fn end_slope(h0: f64, h1: f64, m0: f64, m1: f64) -> f64 {
    let d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
    if sign(d) != sign(m0) {
        0.0
    } else if sign(m0) != sign(m1) && d.abs() > 3.0 * m0.abs() {
        3.0 * m0
    } else {
        d
    }
}

/// numpy's `sign`: −1, 0 or +1 (zero maps to zero, unlike `f64::signum`).
fn sign(v: f64) -> i8 {
    if v > 0.0 {
        1
    } else if v < 0.0 {
        -1
    } else {
        0
    }
}
