//! Newton's method on the four contact equations, with a step limit that
//! keeps the iterates on the profiles and a backtracking line search on the
//! residual (so the iteration cannot cycle where the equations are nearly
//! singular, e.g. S1002 on UIC60 1:40 near the centre, where both profiles
//! have almost the same curvature).

use nalgebra::Vector4;

use super::geometry::{Pair, PairEval};
use super::lu4;

/// Largest change per iteration of (s_r, u_r, s_w, u_w) (m, m, rad, m):
/// steps are scaled down to respect them.
const MAX_STEP: [f64; 4] = [0.2, 0.005, 0.1, 0.005];
/// Convergence: every component of the last step below these (m, m, rad, m).
const STEP_TOL: [f64; 4] = [1e-8, 1e-9, 1e-9, 1e-9];
/// Residual accepted at convergence: |N·t| (–) and |d·t| (m).
const RESIDUAL_TOL: f64 = 1e-9;
/// Length scale weighting the distance equations in the merit function (m).
const MERIT_LENGTH_M: f64 = 0.01;
/// Step halvings tried by the line search.
const MAX_HALVINGS: u32 = 8;

/// A converged solve; the evaluation at `x` is the one left in the
/// storage the solve was given.
pub(crate) struct Converged {
    pub x: Vector4<f64>,
    pub iterations: u32,
}

/// A failed solve: the state where it stopped.
pub(crate) struct Failed {
    pub x: Vector4<f64>,
    pub iterations: u32,
    pub residual: f64,
}

fn merit(e: &PairEval) -> f64 {
    let r = &e.residual;
    let (a, b) = (r[2] / MERIT_LENGTH_M, r[3] / MERIT_LENGTH_M);
    r[0] * r[0] + r[1] * r[1] + a * a + b * b
}

/// Solve from `x0` with at most `max_iterations` Newton steps, evaluating
/// into `e` and factoring into `lu` (one storage for every evaluation and
/// every factorisation, nothing copied): on convergence `e` holds the
/// evaluation at the returned `x` and `lu` the factors of the last Newton
/// step's Jacobian — at `x`, or at the iterate before when the converging
/// step was taken (within [`STEP_TOL`] of `x`). A trial point
/// of the line search overwrites the current evaluation, whose Jacobian
/// has been used by then; only its residual is kept aside, for the
/// failure's report.
pub(crate) fn solve(
    pair: &Pair<'_>,
    x0: Vector4<f64>,
    max_iterations: u32,
    e: &mut PairEval,
    lu: &mut lu4::Lu4,
) -> Result<Converged, Failed> {
    let fail = |x, iterations, residual| Failed {
        x,
        iterations,
        residual,
    };
    let mut x = x0;
    if pair.eval_into(&x, e).is_err() {
        return Err(fail(x, 0, f64::INFINITY));
    }
    for it in 0..max_iterations {
        let Some(step) = lu.factor_solve(&e.jacobian, &(-e.residual)) else {
            return Err(fail(x, it, e.residual.amax()));
        };
        let scale = (0..4).fold(1.0_f64, |s, k| {
            let a = step[k].abs();
            if a > MAX_STEP[k] {
                s.min(MAX_STEP[k] / a)
            } else {
                s
            }
        });
        let full = step * scale;
        if !full.iter().all(|v| v.is_finite()) {
            return Err(fail(x, it, f64::INFINITY));
        }
        let converging = scale == 1.0 && (0..4).all(|k| full[k].abs() < STEP_TOL[k]);
        // Converged at x: the Newton step, x's distance to the root up to
        // second order, is below the tolerances and so is the residual.
        // Taking x (not x + step) saves the evaluation at x + step, a third
        // of a warm solve; x is within STEP_TOL of the root.
        if converging && e.residual.amax() < RESIDUAL_TOL {
            return Ok(Converged {
                x,
                iterations: it + 1,
            });
        }
        // Backtracking on the merit function; a converging step is taken whole.
        let m0 = merit(e);
        let residual = e.residual;
        let mut lambda = 1.0;
        let mut accepted = false;
        for _ in 0..=MAX_HALVINGS {
            let xt = x + full * lambda;
            if pair.eval_into(&xt, e).is_ok()
                && (converging || merit(e) < m0 * (1.0 - 1e-4 * lambda))
            {
                x = xt;
                accepted = true;
                break;
            }
            lambda *= 0.5;
        }
        if !accepted {
            return Err(fail(x, it + 1, residual.amax()));
        }
        if converging {
            return if e.residual.amax() < RESIDUAL_TOL {
                Ok(Converged {
                    x,
                    iterations: it + 1,
                })
            } else {
                Err(fail(x, it + 1, e.residual.amax()))
            };
        }
    }
    Err(fail(x, max_iterations, e.residual.amax()))
}
