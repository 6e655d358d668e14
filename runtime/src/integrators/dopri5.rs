//! Adaptive Dormand–Prince 5(4) with 4th-order dense output.
//!
//! # Method
//!
//! The explicit 7-stage pair of J. R. Dormand & P. J. Prince, "A family of
//! embedded Runge–Kutta formulae", J. Comput. Appl. Math. 6 (1980) 19–26;
//! coefficients as tabulated in Hairer, Nørsett & Wanner (HNW), *Solving
//! Ordinary Differential Equations I*, 2nd ed. (1993), §II.5, Table 5.2, and
//! as coded in Hairer's `dopri5.f` (stage coefficients `A..`, `C..`, error
//! coefficients `E..` = b − b̂). The step advances with the 5th-order weights
//! (local extrapolation); the last stage is evaluated at the new state, so
//! k7 = f(t + h, y⁺) is the next step's k1 (FSAL, "first same as last").
//!
//! ```text
//! c:  0, 1/5, 3/10, 4/5, 8/9, 1, 1
//! a:  1/5
//!     3/40        9/40
//!     44/45      −56/15      32/9
//!     19372/6561 −25360/2187 64448/6561 −212/729
//!     9017/3168  −355/33     46732/5247 49/176  −5103/18656
//!     35/384      0          500/1113   125/192 −2187/6784  11/84
//! b = last row of a (and 0 for k7)
//! b − b̂ = 71/57600, 0, −71/16695, 71/1920, −17253/339200, 22/525, −1/40
//! ```
//!
//! # Error control (HNW §II.4, "Automatic Step Size Control")
//!
//! err_i = h·Σ_j (b_j − b̂_j) k_j,i, sk_i = atol + rtol·max(|y_i|, |y⁺_i|),
//! err = √(1/n Σ (err_i/sk_i)²) (RMS). The step is accepted when err ≤ 1.
//! New step (Hairer's `dopri5.f` controller: the elementary controller with
//! Gustafsson's PI stabilisation — K. Gustafsson, "Control theoretic
//! techniques for stepsize selection in explicit Runge–Kutta methods", ACM
//! TOMS 17 (1991) 533–554; HNW Vol. II, §IV.2):
//!
//! ```text
//! h_new = h · clamp(0.9 · err^(−(1/5 − 0.75 β)) · err_old^β, 0.2, 10)
//! ```
//!
//! with safety factor 0.9, factor limits [0.2, 10] (`dopri5.f`'s FAC1, FAC2),
//! β = [`Dopri5::pi_beta`] (0.04 by default, `dopri5.f`'s BETA; β = 0 is the
//! elementary controller h·clamp(0.9·err^(−1/5), 0.2, 10)), err_old =
//! max(err of the previous accepted step, 10⁻⁴). After a rejection the step
//! shrinks by max(0.9·err^(−(1/5 − 0.75 β)), 0.2) (< 1 since err > 1; no PI
//! term) and the step after it may not grow. A stage with a NaN or infinite
//! entry (state or derivative) counts as err = ∞: the step is rejected and
//! shrinks by 0.2.
//!
//! The next step is capped by `max_step_s`; when t + 1.01·h ≥ t_end the step
//! is stretched or shortened to land exactly on t_end (`dopri5.f`). A step
//! below `min_step_s` or below the time resolution (h ≤ 10·ε_mach·|t|,
//! `dopri5.f`) ends the run: with [`IntegratorError::NonFinite`] if the last
//! rejection was caused by a non-finite value (its time and component), else
//! [`IntegratorError::StepSizeTooSmall`].
//!
//! # Initial step (HNW §II.4, "Starting step size", steps a–f; `dopri5.f`
//! HINIT)
//!
//! With the weighted RMS norm ‖·‖ (sk_i = atol + rtol·|y0_i|):
//! d0 = ‖y0‖, d1 = ‖f(t0, y0)‖, h0 = 0.01·d0/d1 (10⁻⁶ s if d0 or d1 < 10⁻⁵),
//! capped by max_step_s and t_end − t0; one explicit Euler step gives
//! d2 = ‖f(t0 + h0, y0 + h0 f0) − f0‖/h0; h1 = (0.01/max(d1, d2))^(1/5)
//! (max(10⁻⁶, 10⁻³ h0) if max(d1, d2) ≤ 10⁻¹⁵); h = min(100 h0, h1,
//! max_step_s), at least min_step_s. The trial evaluation is made after the
//! initial accept and is never accepted.
//!
//! # Dense output (HNW §II.6, "Dense output for DOPRI5"; Hairer's
//! `dopri5.f` CONTD5, coefficients from L. F. Shampine, "Some practical
//! Runge–Kutta formulas", Math. Comp. 46 (1986) 135–150)
//!
//! A 4th-order continuous extension from the stages of the step, no extra
//! evaluation: with θ = (t − t_n)/h, Δ = y⁺ − y,
//!
//! ```text
//! r1 = y, r2 = Δ, r3 = h k1 − Δ, r4 = Δ − h k7 − r3,
//! r5 = h (d1 k1 + d3 k3 + d4 k4 + d5 k5 + d6 k6 + d7 k7),
//! u(θ) = r1 + θ (r2 + (1 − θ)(r3 + θ (r4 + (1 − θ) r5)))
//! d1 = −12715105075/11282082432, d3 = 87487479700/32700410799,
//! d4 = −10690763975/1880347072,  d5 = 701980252875/199316789632,
//! d6 = −1453857185/822651844,    d7 = 69997945/29380423
//! ```
//!
//! u(0) = y, u(1) = y⁺, u′ matches k1 and k7 at the ends (so the dense
//! output is C¹ across steps); its local error is O(h⁵), like the step's
//! error estimate (measured in tests).

use super::{
    Control, IntegrationStats, IntegratorError, Observer, OdeSystem, OutputCursor, OutputGrid,
    StepRange, eval, first_non_finite, invalid, next_attempt, validate_adaptive,
};

/// Adaptive Dormand–Prince 5(4) settings. The defaults suit the
/// simulator's states (positions in m, angles in rad, velocities in m/s and
/// rad/s, quaternion components).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dopri5 {
    /// Relative tolerance (dimensionless), finite and > 10·ε_mach (≈ 2.2e-15;
    /// `dopri5.f`'s rule). Default 1e-6.
    pub rtol: f64,
    /// Absolute tolerance (state units), finite and > 0 (so components
    /// through zero keep a finite weight). Default 1e-9 (1 nm on positions,
    /// against penetrations of ~0.1 mm).
    pub atol: f64,
    /// First step (s), finite and > 0; `None` (default): HNW's heuristic
    /// (module docs).
    pub initial_step_s: Option<f64>,
    /// Largest step (s), > 0, may be +∞. Default +∞ (limited by t_end − t0
    /// only); cap it to keep the run from stepping over short events.
    pub max_step_s: f64,
    /// Smallest step (s) the error control may ask for before the run fails,
    /// finite, ≥ 0 and ≤ `max_step_s` (the last step, shortened to land on
    /// t_end, may be smaller). Default 1e-12 s.
    pub min_step_s: f64,
    /// Largest number of step attempts, accepted plus rejected, > 0. Default
    /// 10⁷ (a 7.5 s run at 1 µs steps is 7.5·10⁶).
    pub max_steps: u64,
    /// Gustafsson PI-control exponent β, in [0, 0.2] (`dopri5.f`: β ≤ 0.2);
    /// 0 is the elementary controller. Default 0.04 (`dopri5.f`).
    pub pi_beta: f64,
}

impl Default for Dopri5 {
    fn default() -> Self {
        Self {
            rtol: 1e-6,
            atol: 1e-9,
            initial_step_s: None,
            max_step_s: f64::INFINITY,
            min_step_s: 1e-12,
            max_steps: 10_000_000,
            pi_beta: 0.04,
        }
    }
}

// Dormand & Prince (1980); HNW Table 5.2; dopri5.f.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
// b − b̂ (dopri5.f E1..E7).
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output (Shampine 1986; dopri5.f D1..D7).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Stage rows: (c_i, a_i1 … a_i,i−1) for stages 2–7 (the 7th is y⁺).
const STAGES: [(f64, &[f64]); 6] = [
    (C2, &[A21]),
    (C3, &[A31, A32]),
    (C4, &[A41, A42, A43]),
    (C5, &[A51, A52, A53, A54]),
    (1.0, &[A61, A62, A63, A64, A65]),
    (1.0, &[A71, 0.0, A73, A74, A75, A76]),
];
const ERROR_WEIGHTS: [f64; 7] = [E1, 0.0, E3, E4, E5, E6, E7];
const DENSE_WEIGHTS: [f64; 7] = [D1, 0.0, D3, D4, D5, D6, D7];

/// Step-size controller constants (`dopri5.f`: SAFE, FAC1, FAC2; HNW §II.4).
const SAFETY: f64 = 0.9;
const FACTOR_MIN: f64 = 0.2;
const FACTOR_MAX: f64 = 10.0;
/// Floor of err_old in the PI term (`dopri5.f`).
const ERR_OLD_FLOOR: f64 = 1e-4;
/// Land on t_end when within this many steps of it (`dopri5.f`).
const LAST_STEP_STRETCH: f64 = 1.01;

fn validate<E>(s: &Dopri5) -> Result<(), IntegratorError<E>> {
    validate_adaptive(s.rtol, s.atol, s.max_step_s, s.min_step_s, s.max_steps)?;
    if let Some(h) = s.initial_step_s
        && !(h.is_finite() && h > 0.0)
    {
        return Err(invalid("initial_step_s", h, "must be finite and > 0"));
    }
    if !(s.pi_beta.is_finite() && (0.0..=0.2).contains(&s.pi_beta)) {
        return Err(invalid("pi_beta", s.pi_beta, "must lie in [0, 0.2]"));
    }
    Ok(())
}

/// Work vectors of one integration, allocated once.
struct Work {
    /// Stage derivatives k1…k7 (k[6] = f(t + h, y⁺), the next k1).
    k: [Vec<f64>; 7],
    y: Vec<f64>,
    y_new: Vec<f64>,
    y_stage: Vec<f64>,
    /// Dense-output coefficients r1…r5 of the last accepted step.
    rcont: [Vec<f64>; 5],
}

impl Work {
    fn new(y0: &[f64]) -> Self {
        let n = y0.len();
        Self {
            k: std::array::from_fn(|_| vec![0.0; n]),
            y: y0.to_vec(),
            y_new: vec![0.0; n],
            y_stage: vec![0.0; n],
            rcont: std::array::from_fn(|_| vec![0.0; n]),
        }
    }
}

/// Outcome of one step attempt.
enum Attempt {
    /// err ≤ 1 (the RMS error norm).
    Accepted { err: f64 },
    /// err > 1.
    Rejected { err: f64 },
    /// A stage state or derivative had a non-finite entry (time, index).
    NonFinite { t: f64, component: usize },
}

/// One attempt from (t, work.y) with step h to t_new (= t + h, or t_end on
/// the last step): stages 2–7 into work.k[1..], y⁺ into work.y_new, the
/// error norm. work.k[0] holds f(t, y).
fn attempt<S: OdeSystem>(
    s: &Dopri5,
    system: &mut S,
    work: &mut Work,
    t: f64,
    h: f64,
    t_new: f64,
    evaluations: &mut u64,
) -> Result<Attempt, IntegratorError<S::Error>> {
    let n = work.y.len();
    for (stage, (c, a)) in STAGES.iter().enumerate() {
        let out = stage + 1;
        let is_last = out == 6;
        let (done, rest) = work.k.split_at_mut(out);
        let target = if is_last {
            &mut work.y_new
        } else {
            &mut work.y_stage
        };
        for i in 0..n {
            let mut sum = 0.0;
            for (aj, kj) in a.iter().zip(done.iter()) {
                sum += aj * kj[i];
            }
            target[i] = work.y[i] + h * sum;
        }
        let ts = if *c == 1.0 { t_new } else { t + c * h };
        if let Some(component) = first_non_finite(target) {
            return Ok(Attempt::NonFinite { t: ts, component });
        }
        if let Some(component) = eval(system, ts, target, &mut rest[0], evaluations)? {
            return Ok(Attempt::NonFinite { t: ts, component });
        }
    }
    let mut sum = 0.0;
    for i in 0..n {
        let mut e = 0.0;
        for (w, kj) in ERROR_WEIGHTS.iter().zip(work.k.iter()) {
            e += w * kj[i];
        }
        let sk = s.atol + s.rtol * work.y[i].abs().max(work.y_new[i].abs());
        let r = h * e / sk;
        sum += r * r;
    }
    let err = (sum / n as f64).sqrt();
    Ok(if err <= 1.0 {
        Attempt::Accepted { err }
    } else {
        // Also NaN/∞ from an overflowing norm.
        Attempt::Rejected {
            err: if err.is_nan() { f64::INFINITY } else { err },
        }
    })
}

/// Dense-output coefficients of the accepted step (module docs).
fn prepare_dense(work: &mut Work, h: f64) {
    let n = work.y.len();
    for i in 0..n {
        let y = work.y[i];
        let diff = work.y_new[i] - y;
        let bspl = h * work.k[0][i] - diff;
        let mut d = 0.0;
        for (w, kj) in DENSE_WEIGHTS.iter().zip(work.k.iter()) {
            d += w * kj[i];
        }
        work.rcont[0][i] = y;
        work.rcont[1][i] = diff;
        work.rcont[2][i] = bspl;
        work.rcont[3][i] = diff - h * work.k[6][i] - bspl;
        work.rcont[4][i] = h * d;
    }
}

/// The continuous extension at θ ∈ [0, 1] (module docs).
fn dense(rcont: &[Vec<f64>; 5], theta: f64, out: &mut [f64]) {
    let theta1 = 1.0 - theta;
    for (i, o) in out.iter_mut().enumerate() {
        *o = rcont[0][i]
            + theta
                * (rcont[1][i]
                    + theta1 * (rcont[2][i] + theta * (rcont[3][i] + theta1 * rcont[4][i])));
    }
}

/// Weighted RMS norm with weights atol + rtol·|y0_i|.
fn weighted_rms(s: &Dopri5, y0: &[f64], v: impl Fn(usize) -> f64) -> f64 {
    let n = y0.len();
    let sum: f64 = (0..n)
        .map(|i| {
            let r = v(i) / (s.atol + s.rtol * y0[i].abs());
            r * r
        })
        .sum();
    (sum / n as f64).sqrt()
}

/// HNW §II.4 starting step (module docs). work.k[0] = f(t0, y0); uses
/// work.y_stage and work.k[1] as scratch.
fn initial_step<S: OdeSystem>(
    s: &Dopri5,
    system: &mut S,
    work: &mut Work,
    t0: f64,
    t_end: f64,
    evaluations: &mut u64,
) -> Result<f64, IntegratorError<S::Error>> {
    let cap = s.max_step_s.min(t_end - t0);
    let d0 = weighted_rms(s, &work.y, |i| work.y[i]);
    let d1 = weighted_rms(s, &work.y, |i| work.k[0][i]);
    let h0 = if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    }
    .min(cap);
    for i in 0..work.y.len() {
        work.y_stage[i] = work.y[i] + h0 * work.k[0][i];
    }
    let trial_ok = first_non_finite(&work.y_stage).is_none()
        && eval(system, t0 + h0, &work.y_stage, &mut work.k[1], evaluations)?.is_none();
    let h = if trial_ok {
        let d2 = weighted_rms(s, &work.y, |i| work.k[1][i] - work.k[0][i]) / h0;
        let dmax = d1.max(d2);
        let h1 = if dmax <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / dmax).powf(0.2)
        };
        (100.0 * h0).min(h1)
    } else {
        // The step loop shrinks it if the trouble persists.
        h0
    };
    Ok(h.min(s.max_step_s).max(s.min_step_s))
}

pub(super) fn integrate_dopri5<S: OdeSystem>(
    settings: &Dopri5,
    system: &mut S,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    output: &OutputGrid,
    observer: &mut Observer<'_, S>,
) -> Result<IntegrationStats, IntegratorError<S::Error>> {
    validate(settings)?;
    let mut work = Work::new(y0);
    let mut y_out = vec![0.0; y0.len()];
    let mut evaluations = 0u64;
    let mut cursor = OutputCursor::new(t0, t_end, output);
    let mut range = StepRange::new();
    let (mut steps, mut rejected) = (0u64, 0u64);

    // The initial state: evaluate, accept, output.
    if let Some(component) = eval(system, t0, &work.y, &mut work.k[0], &mut evaluations)? {
        return Err(IntegratorError::NonFinite { t: t0, component });
    }
    let mut stopped = system
        .accept(t0, &work.y)
        .map_err(IntegratorError::System)?
        == Control::Stop;
    let mut t = t0;
    cursor.emit_step(
        system,
        observer,
        t0,
        &work.y,
        stopped || t_end == t0,
        &mut y_out,
        &mut |_, _| {},
    )?;

    let mut h = if stopped || t_end == t0 {
        0.0
    } else {
        match settings.initial_step_s {
            Some(h) => h.min(settings.max_step_s),
            None => initial_step(settings, system, &mut work, t0, t_end, &mut evaluations)?,
        }
    };
    let expo = 0.2 - 0.75 * settings.pi_beta;
    let mut err_old = ERR_OLD_FLOOR;
    let mut last_rejected = false;
    let mut last_non_finite: Option<(f64, usize)> = None;

    while !stopped && t < t_end {
        h = h.min(settings.max_step_s);
        let (h_step, t_new) = next_attempt(
            t,
            h,
            t_end,
            steps + rejected,
            settings.max_steps,
            settings.min_step_s,
            LAST_STEP_STRETCH,
            last_non_finite,
        )?;

        match attempt(
            settings,
            system,
            &mut work,
            t,
            h_step,
            t_new,
            &mut evaluations,
        )? {
            Attempt::Accepted { err } => {
                // The rhs at (t_new, y⁺) was the last call: accept right after.
                stopped = system
                    .accept(t_new, &work.y_new)
                    .map_err(IntegratorError::System)?
                    == Control::Stop;
                steps += 1;
                range.record(h_step);
                let is_final = stopped || t_new == t_end;
                prepare_dense(&mut work, h_step);
                {
                    let rcont = &work.rcont;
                    cursor.emit_step(
                        system,
                        observer,
                        t_new,
                        &work.y_new,
                        is_final,
                        &mut y_out,
                        &mut |tk, out| dense(rcont, (tk - t) / h_step, out),
                    )?;
                }

                // PI controller (dopri5.f): h_new = h / fac.
                let fac11 = err.powf(expo);
                let fac = (fac11 / err_old.powf(settings.pi_beta) / SAFETY)
                    .clamp(1.0 / FACTOR_MAX, 1.0 / FACTOR_MIN);
                let mut h_new = h_step / fac;
                if last_rejected {
                    h_new = h_new.min(h_step);
                }
                err_old = err.max(ERR_OLD_FLOOR);
                last_rejected = false;
                last_non_finite = None;
                h = h_new;

                std::mem::swap(&mut work.y, &mut work.y_new);
                work.k.swap(0, 6);
                t = t_new;
            }
            Attempt::Rejected { err } => {
                let fac11 = err.powf(expo);
                h = h_step / (fac11 / SAFETY).min(1.0 / FACTOR_MIN);
                rejected += 1;
                last_rejected = true;
                last_non_finite = None;
            }
            Attempt::NonFinite { t: tf, component } => {
                h = h_step * FACTOR_MIN;
                rejected += 1;
                last_rejected = true;
                last_non_finite = Some((tf, component));
            }
        }
    }

    let (min_step_s, max_step_s) = range.get();
    Ok(IntegrationStats {
        steps,
        rejected,
        rhs_evaluations: evaluations,
        jacobian_evaluations: 0,
        dense_lu_fallbacks: 0,
        outputs: cursor.emitted,
        t_end_reached: t,
        stopped,
        min_step_s,
        max_step_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::{Method, integrate};
    use std::convert::Infallible;

    fn tableau() -> ([f64; 7], [[f64; 7]; 7], [f64; 7], [f64; 7]) {
        let c = [0.0, C2, C3, C4, C5, 1.0, 1.0];
        let mut a = [[0.0; 7]; 7];
        for (row, (_, coeffs)) in STAGES.iter().enumerate() {
            for (j, v) in coeffs.iter().enumerate() {
                a[row + 1][j] = *v;
            }
        }
        let b = [A71, 0.0, A73, A74, A75, A76, 0.0];
        let mut bh = [0.0; 7];
        for j in 0..7 {
            bh[j] = b[j] - ERROR_WEIGHTS[j];
        }
        (c, a, b, bh)
    }

    #[test]
    fn tableau_satisfies_row_sums_and_order_conditions() {
        let (c, a, b, bh) = tableau();
        for i in 0..7 {
            let s: f64 = a[i].iter().sum();
            assert!((s - c[i]).abs() < 1e-14, "row {i}: {s} vs {}", c[i]);
        }
        // Order conditions Σ b c^(q−1) = 1/q, q = 1..5, and two of order 4
        // and 5 with A; b̂ to order 4 only.
        let dot = |w: &[f64; 7], f: &dyn Fn(usize) -> f64| (0..7).map(|i| w[i] * f(i)).sum::<f64>();
        let ac = |i: usize| (0..7).map(|j| a[i][j] * c[j]).sum::<f64>();
        let ac2 = |i: usize| (0..7).map(|j| a[i][j] * c[j] * c[j]).sum::<f64>();
        for q in 1..=5 {
            let v = dot(&b, &|i| c[i].powi(q - 1));
            assert!((v - 1.0 / q as f64).abs() < 1e-14, "b, q {q}: {v}");
        }
        for q in 1..=4 {
            let v = dot(&bh, &|i| c[i].powi(q - 1));
            assert!((v - 1.0 / q as f64).abs() < 1e-14, "b̂, q {q}: {v}");
        }
        // b̂ is of order 4 exactly: the 5th-order quadrature condition fails.
        assert!((dot(&bh, &|i| c[i].powi(4)) - 0.2).abs() > 1e-5);
        assert!((dot(&b, &|i| c[i] * ac(i)) - 1.0 / 8.0).abs() < 1e-14);
        assert!((dot(&b, &ac2) - 1.0 / 12.0).abs() < 1e-14);
        assert!((dot(&b, &|i| c[i] * c[i] * ac(i)) - 1.0 / 10.0).abs() < 1e-14);
        // Dense weights: Σ d = 0 (u(θ) is consistent for y′ = const).
        let sd: f64 = DENSE_WEIGHTS.iter().sum();
        assert!(sd.abs() < 1e-13, "Σd = {sd}");
    }

    /// y′ = cos t, y(0) = 0 (y = sin t): one step from exact data.
    struct Sine;

    impl OdeSystem for Sine {
        type Error = Infallible;
        fn rhs(&mut self, t: f64, _y: &[f64], dydt: &mut [f64]) -> Result<(), Infallible> {
            dydt[0] = t.cos();
            Ok(())
        }
        fn accept(&mut self, _t: f64, _y: &[f64]) -> Result<Control, Infallible> {
            Ok(Control::Continue)
        }
    }

    /// y′ = −y·(1 + t): y = exp(−t − t²/2), a state-dependent one.
    struct Decay;

    impl OdeSystem for Decay {
        type Error = Infallible;
        fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) -> Result<(), Infallible> {
            dydt[0] = -y[0] * (1.0 + t);
            Ok(())
        }
        fn accept(&mut self, _t: f64, _y: &[f64]) -> Result<Control, Infallible> {
            Ok(Control::Continue)
        }
    }

    /// Local errors of one step of size h from exact data at t = 0.3: the
    /// step (order 5 method → local O(h⁶)) and the dense output at θ = 0.5
    /// (4th-order extension → local O(h⁵)).
    fn local_errors<S: OdeSystem>(system: &mut S, exact: fn(f64) -> f64, h: f64) -> (f64, f64) {
        let t = 0.3;
        let s = Dopri5::default();
        let mut work = Work::new(&[exact(t)]);
        let mut ev = 0;
        eval(system, t, &work.y.clone(), &mut work.k[0], &mut ev)
            .ok()
            .unwrap();
        match attempt(&s, system, &mut work, t, h, t + h, &mut ev)
            .ok()
            .unwrap()
        {
            Attempt::Accepted { .. } | Attempt::Rejected { .. } => {}
            Attempt::NonFinite { .. } => panic!("non-finite"),
        }
        prepare_dense(&mut work, h);
        let mut mid = [0.0];
        dense(&work.rcont, 0.5, &mut mid);
        let mut end = [0.0];
        dense(&work.rcont, 1.0, &mut end);
        assert!((end[0] - work.y_new[0]).abs() < 1e-15);
        let mut start = [0.0];
        dense(&work.rcont, 0.0, &mut start);
        assert_eq!(start[0], work.y[0]);
        (
            (work.y_new[0] - exact(t + h)).abs(),
            (mid[0] - exact(t + 0.5 * h)).abs(),
        )
    }

    fn slope(hs: &[f64], errs: &[f64]) -> f64 {
        let x: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
        let y: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
        let n = x.len() as f64;
        let mx = x.iter().sum::<f64>() / n;
        let my = y.iter().sum::<f64>() / n;
        let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
        let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
        sxy / sxx
    }

    #[test]
    fn local_orders_of_step_and_dense_output() {
        // Steps from 0.2 s down: the step's local error of Decay reaches
        // 1.8e-13 at 0.025 s, still clear of round-off.
        let hs = [0.2, 0.1, 0.05, 0.025];
        let (mut step, mut mid) = (vec![], vec![]);
        for h in hs {
            let (e1, e2) = local_errors(&mut Decay, |t| (-t - 0.5 * t * t).exp(), h);
            step.push(e1);
            mid.push(e2);
        }
        let (ps, pm) = (slope(&hs, &step), slope(&hs, &mid));
        // Measured: step 6.17, dense output 5.18.
        assert!((5.7..6.5).contains(&ps), "step local order {ps}: {step:?}");
        assert!((4.7..5.4).contains(&pm), "dense local order {pm}: {mid:?}");
        // A quadrature (the stages enter through c, b, d only); larger steps,
        // its step errors are much smaller.
        let hs = [0.8, 0.4, 0.2, 0.1];
        let (mut step, mut mid) = (vec![], vec![]);
        for h in hs {
            let (e1, e2) = local_errors(&mut Sine, f64::sin, h);
            step.push(e1);
            mid.push(e2);
        }
        let (ps, pm) = (slope(&hs, &step), slope(&hs, &mid));
        // Measured: step 6.02, dense output 5.00.
        assert!(
            (5.7..6.5).contains(&ps),
            "sine step local order {ps}: {step:?}"
        );
        assert!(
            (4.7..5.4).contains(&pm),
            "sine dense local order {pm}: {mid:?}"
        );
    }

    #[test]
    fn settings_are_validated() {
        let grid = OutputGrid { interval_s: 0.1 };
        let check = |s: Dopri5, name: &str| {
            let r = integrate(
                &Method::Dopri5(s),
                &mut Sine,
                0.0,
                &[0.0],
                1.0,
                &grid,
                &mut |_, _, _| Ok(()),
            );
            match r {
                Err(IntegratorError::InvalidSettings { setting, .. }) => {
                    assert_eq!(setting, name, "{s:?}")
                }
                other => panic!("{s:?}: expected InvalidSettings({name}), got {other:?}"),
            }
        };
        let d = Dopri5::default();
        for rtol in [0.0, -1e-6, f64::NAN, f64::INFINITY, 1e-16] {
            check(Dopri5 { rtol, ..d }, "rtol");
        }
        for atol in [0.0, -1e-9, f64::NAN] {
            check(Dopri5 { atol, ..d }, "atol");
        }
        for h in [0.0, -0.1, f64::NAN, f64::INFINITY] {
            check(
                Dopri5 {
                    initial_step_s: Some(h),
                    ..d
                },
                "initial_step_s",
            );
        }
        for max_step_s in [0.0, -1.0, f64::NAN] {
            check(Dopri5 { max_step_s, ..d }, "max_step_s");
        }
        for min_step_s in [-1.0, f64::NAN, f64::INFINITY] {
            check(Dopri5 { min_step_s, ..d }, "min_step_s");
        }
        check(
            Dopri5 {
                min_step_s: 0.5,
                max_step_s: 0.1,
                ..d
            },
            "min_step_s",
        );
        check(Dopri5 { max_steps: 0, ..d }, "max_steps");
        for pi_beta in [-0.01, 0.3, f64::NAN] {
            check(Dopri5 { pi_beta, ..d }, "pi_beta");
        }
    }

    #[test]
    fn too_many_steps_is_reported() {
        let r = integrate(
            &Method::Dopri5(Dopri5 {
                max_steps: 5,
                rtol: 1e-10,
                atol: 1e-12,
                ..Dopri5::default()
            }),
            &mut Sine,
            0.0,
            &[0.0],
            100.0,
            &OutputGrid { interval_s: 1.0 },
            &mut |_, _, _| Ok(()),
        );
        match r {
            Err(IntegratorError::TooManySteps { t, steps }) => {
                assert_eq!(steps, 5);
                assert!(t > 0.0 && t < 100.0, "t {t}");
            }
            other => panic!("expected TooManySteps, got {other:?}"),
        }
    }
}
