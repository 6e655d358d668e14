//! Slopes of the C² cubic spline (de Boor, *A Practical Guide to Splines*,
//! ch. IV; the same linear system as SciPy's `CubicSpline`).
//!
//! Unknowns are the first derivatives `s_i` at the knots. Interior rows
//! (continuity of the second derivative):
//! `h_i s_{i−1} + 2(h_{i−1} + h_i) s_i + h_{i−1} s_{i+1} = 3(h_i m_{i−1} + h_{i−1} m_i)`,
//! with `h_i = x_{i+1} − x_i` and `m_i = (y_{i+1} − y_i)/h_i`.

/// End condition of the C² spline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum EndCondition {
    /// Third derivative continuous across the second and the last-but-one knot.
    NotAKnot,
    /// Second derivative zero at both ends.
    Natural,
}

/// Knot slopes of the C² spline through `(x, y)` (n ≥ 2, validated by the caller).
pub(super) fn slopes(x: &[f64], y: &[f64], end: EndCondition) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let m: Vec<f64> = y
        .windows(2)
        .zip(&h)
        .map(|(w, h)| (w[1] - w[0]) / h)
        .collect();

    if n == 2 {
        // One piece: the straight line (both end conditions reduce to it).
        return vec![m[0], m[0]];
    }

    // Tridiagonal system: lower[i]·s[i−1] + diag[i]·s[i] + upper[i]·s[i+1] = rhs[i].
    let mut lower = vec![0.0; n];
    let mut diag = vec![0.0; n];
    let mut upper = vec![0.0; n];
    let mut rhs = vec![0.0; n];
    for i in 1..n - 1 {
        lower[i] = h[i];
        diag[i] = 2.0 * (h[i - 1] + h[i]);
        upper[i] = h[i - 1];
        rhs[i] = 3.0 * (h[i] * m[i - 1] + h[i - 1] * m[i]);
    }

    match end {
        EndCondition::NotAKnot if n == 3 => {
            // Both conditions coincide: the parabola through the three points
            // (s0 + s1 = 2 m0, s1 + s2 = 2 m1), SciPy's rule.
            diag[0] = 1.0;
            upper[0] = 1.0;
            rhs[0] = 2.0 * m[0];
            lower[2] = 1.0;
            diag[2] = 1.0;
            rhs[2] = 2.0 * m[1];
        }
        EndCondition::NotAKnot => {
            let d0 = x[2] - x[0];
            diag[0] = h[1];
            upper[0] = d0;
            rhs[0] = ((h[0] + 2.0 * d0) * h[1] * m[0] + h[0] * h[0] * m[1]) / d0;
            let dn = x[n - 1] - x[n - 3];
            diag[n - 1] = h[n - 3];
            lower[n - 1] = dn;
            rhs[n - 1] =
                (h[n - 2] * h[n - 2] * m[n - 3] + (2.0 * dn + h[n - 2]) * h[n - 3] * m[n - 2]) / dn;
        }
        EndCondition::Natural => {
            diag[0] = 2.0 * h[0];
            upper[0] = h[0];
            rhs[0] = 3.0 * (y[1] - y[0]);
            diag[n - 1] = 2.0 * h[n - 2];
            lower[n - 1] = h[n - 2];
            rhs[n - 1] = 3.0 * (y[n - 1] - y[n - 2]);
        }
    }
    solve_tridiagonal(&lower, &diag, &upper, &mut rhs);
    rhs
}

/// Thomas algorithm; the solution overwrites `rhs`. The spline systems are
/// diagonally dominant except the not-a-knot end rows, whose elimination
/// leaves a positive pivot `h0 + h1` (no pivoting needed).
fn solve_tridiagonal(lower: &[f64], diag: &[f64], upper: &[f64], rhs: &mut [f64]) {
    let n = diag.len();
    let mut c = vec![0.0; n];
    let mut beta = diag[0];
    c[0] = upper[0] / beta;
    rhs[0] /= beta;
    for i in 1..n {
        beta = diag[i] - lower[i] * c[i - 1];
        c[i] = upper[i] / beta;
        rhs[i] = (rhs[i] - lower[i] * rhs[i - 1]) / beta;
    }
    for i in (0..n - 1).rev() {
        rhs[i] -= c[i] * rhs[i + 1];
    }
}
