//! Adaptive linearly implicit Rosenbrock-W method ROS34PW2 for the stiff
//! vehicle equations, with a block-diagonal finite-difference Jacobian
//! reused over many steps.
//!
//! # Why (docs/reference/08-multibody.md §8.5)
//!
//! The explicit methods' step is capped by stability, not accuracy: the
//! creep damping of a wheelset's spin and lateral motion and the Hertzian
//! contact stiffness have eigenvalues of 10³ s⁻¹ and more, 500 times the
//! hunting mode's, so RK4 fails beyond ≈ 1.1 ms and DOPRI5 cannot pass it
//! either. A linearly implicit method treats those modes through a linear
//! solve with W = I/(hγ) − J and takes the steps the slow motion needs.
//!
//! # Method (Rang & Angermann 2005)
//!
//! ROS34PW2 of J. Rang & L. Angermann, "New Rosenbrock W-methods of order
//! 3 for partial differential algebraic equations of index 1", BIT Numer.
//! Math. 45 (2005) 761–787: four stages, order 3 with **any** matrix in
//! place of the Jacobian (a W-method), an embedded method of order 2 for
//! the error estimate, stiffly accurate and L-stable (R(∞) = 0), γ =
//! 0.43586652150845900. With the published coefficients α_ij (stage
//! arguments), γ_ij (Jacobian couplings, Γ lower triangular with diagonal
//! γ), weights b and embedded b̂, one step from (t, y) is (Hairer & Wanner,
//! *Solving ODEs II*, 2nd ed., §IV.7, eqs. 7.4 and the W-method form):
//!
//! ```text
//! k_i = h f(t + α_i h, y + Σ_{j<i} α_ij k_j) + h J Σ_{j≤i} γ_ij k_j
//! y⁺ = y + Σ b_i k_i,     ŷ⁺ = y + Σ b̂_i k_i
//! ```
//!
//! computed in HW's transformed variables u_i = Σ_j γ_ij k_j (HW eqs.
//! 7.25–7.26), one linear solve per stage with the same W:
//!
//! ```text
//! (I/(hγ) − J) u_i = f(t + α_i h, y + Σ_{j<i} a_ij u_j) + Σ_{j<i} (c_ij / h) u_j
//! y⁺ = y + Σ m_i u_i,     error = Σ (m_i − m̂_i) u_i
//! a = A Γ⁻¹,  c_ij = −(Γ⁻¹)_ij (j < i),  m = b Γ⁻¹,  m̂ = b̂ Γ⁻¹
//! ```
//!
//! The transformed coefficients are computed from the published ones by
//! `Tableau::ros34pw2` (tested against the order conditions). The
//! time derivative ∂f/∂t is taken as zero: for a W-method this is one more
//! admissible choice of the matrix (the Jacobian of the autonomous form
//! with its time column approximated by zero), so the order stays 3.
//!
//! Four evaluations per step: f(t, y) is the first stage — the evaluation
//! at the last accepted state that the accept protocol makes anyway — and
//! stages 2–4 are trial evaluations. The evaluation at the new state is
//! made before the step is accepted (it is the next step's first stage), so
//! a non-finite derivative there rejects the step.
//!
//! # Jacobian (module [`super::jacobian`])
//!
//! The system may declare diagonal blocks ([`OdeSystem::jacobian_blocks`])
//! or, by default, one dense block — the vehicle keeps the default: its
//! primary suspensions (10 MN/m on the bogie) couple wheelset and frame as
//! stiffly as the contact, and a block-diagonal Jacobian that leaves that
//! coupling explicit was measured 90 µm off on the bogie with 20 times the
//! steps. The Jacobian is evaluated by forward differences at the start,
//! after [`Rosenbrock::jacobian_max_age`] accepted steps, after a rejected
//! step when it is older than it, and at an accepted state where the
//! system reports a change of structure ([`OdeSystem::structure_changed`]:
//! a contact that opens or closes, a flange that comes into contact) — the
//! step after such a change may not grow. W is refactorised at every new h
//! or J.
//!
//! # Error control (HW §IV.8)
//!
//! err = √(1/n Σ (e_i / sk_i)²), sk_i = atol + rtol·max(|y_i|, |y⁺_i|); the
//! step is accepted when err ≤ 1 and the next one is h·clamp(0.9·err^(−1/3),
//! 0.2, 6) (the error estimate is O(h³)), kept at h when that factor lies in
//! [1, 1.2] so that W's factors are reused; after a rejection the factor is
//! at most 1 and the next accepted step may not grow. A stage or a new
//! state with a non-finite entry, or a singular W, rejects the step with
//! factor 0.2. Steps are capped by `max_step_s`, stretched or shortened to
//! land on t_end within 1 %, and a step below `min_step_s` or the time
//! resolution ends the run ([`IntegratorError::StepSizeTooSmall`], or
//! [`IntegratorError::NonFinite`] when a non-finite value caused it).
//!
//! # Steps on the output grid
//!
//! A step capped by `max_step_s` (the controller asked for at least that)
//! that would pass an output time ends on the last one it passes, unless
//! that would leave less than 1 % of the step: the state there is then a
//! step's end, exact, and its evaluation — made anyway as the next step's
//! first stage — serves the sample (the vehicle's recorder evaluates the
//! system at every output time that is not a step's end). With
//! `max_step_s` a multiple of the output interval the capped steps stay
//! on the grid once one has landed: on the Cooperrider car, whose steps
//! are capped for most of its last 8 s, the 1 001 samples needed 999
//! evaluations of their own and need 168 (−4 % instructions). A landed
//! step differs from the last by round-off, so W's factors are kept when
//! 1/(hγ) is within 10⁻⁹ of theirs: for a W-method that is the matrix
//! I/(hγ) − (J + δI) with δ of that size, one more admissible choice
//! (module docs of [`super::jacobian`]).
//! Steps the error control shortens are left as they are: shortening
//! them further would cost steps.
//!
//! # Dense output
//!
//! Cubic Hermite interpolation between the step's end states and their
//! derivatives (HNW I §II.6, eq. 6.7, as for RK4): both derivatives are
//! evaluated anyway, the interpolation error O(h⁴) is below the method's
//! O(h³) local error estimate.

use super::jacobian::{BlockJacobian, JacobianBlocks};
use super::rk4::hermite;
use super::{
    Control, IntegrationStats, IntegratorError, Observer, OdeSystem, OutputCursor, OutputGrid,
    StepRange, eval, first_non_finite, invalid, next_attempt, validate_adaptive,
};

/// Which Jacobian approximation the method uses (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum JacobianApprox {
    /// The blocks the system declares ([`OdeSystem::jacobian_blocks`]).
    #[default]
    SystemBlocks,
    /// One dense block over the whole state (n evaluations per Jacobian).
    Dense,
}

/// Adaptive ROS34PW2 settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rosenbrock {
    /// Relative tolerance (dimensionless), finite and > 10·ε_mach.
    /// Default 1e-9: negligible, because a relative tolerance means nothing
    /// physical on the vehicle's states — 10⁻⁵ of a wheelset's 100 m track
    /// position or of its 94 rad/s spin (a longitudinal creepage of 10⁻⁵)
    /// would let the creep modes go unresolved.
    pub rtol: f64,
    /// Absolute tolerance (state units: m, m/s, rad/s, quaternion), finite
    /// and > 0. Default 5e-6: measured to keep every wheelset's lateral
    /// displacement within 10 µm of RK4 at 0.1 ms on the shipped bogie,
    /// car and wheelset scenes (docs/guide/speed-accuracy-tradeoff.md).
    pub atol: f64,
    /// First step (s), finite and > 0. Default 1e-4 s, grown by the error
    /// control (at most ×6 per step).
    pub initial_step_s: f64,
    /// Largest step (s), > 0, may be +∞. Default 0.01 s: beyond it the
    /// Jacobian, reused over several steps, no longer holds the 10³ s⁻¹
    /// creep modes (measured on the car: at 20 ms one step in three is
    /// rejected on the wheelsets' spin).
    pub max_step_s: f64,
    /// Smallest step (s) the error control may ask for before the run
    /// fails, finite, ≥ 0 and ≤ `max_step_s`. Default 1e-10 s.
    pub min_step_s: f64,
    /// Largest number of step attempts, accepted plus rejected, > 0.
    /// Default 10⁷.
    pub max_steps: u64,
    /// Accepted steps after which the Jacobian is re-evaluated, ≥ 1.
    /// Default 25.
    pub jacobian_max_age: u32,
    /// The Jacobian approximation. Default: the system's blocks.
    pub jacobian: JacobianApprox,
}

impl Default for Rosenbrock {
    fn default() -> Self {
        Self {
            rtol: 1e-9,
            atol: 5e-6,
            initial_step_s: 1e-4,
            max_step_s: 0.01,
            min_step_s: 1e-10,
            max_steps: 10_000_000,
            jacobian_max_age: 25,
            jacobian: JacobianApprox::SystemBlocks,
        }
    }
}

/// Safety factor and step-factor limits of the controller (module docs).
const SAFETY: f64 = 0.9;
const FACTOR_MIN: f64 = 0.2;
const FACTOR_MAX: f64 = 6.0;
/// An accepted step whose proposed growth lies in [1, `KEEP_STEP_MAX`]
/// keeps its size, so that W = I/(hγ) − J and its LU factors are reused
/// (the window of Hairer & Wanner's RADAU5 code, `quot1` = 1, `quot2` =
/// 1.2; *Solving ODEs II*, §IV.8): an LU costs as much as several
/// stages' solves, a 20 % longer step saves less.
const KEEP_STEP_MAX: f64 = 1.2;
/// A last step within this factor of t_end is stretched to land on it.
const LAST_STEP_STRETCH: f64 = 1.01;

/// Number of stages.
const S: usize = 4;

/// ROS34PW2 as published (Rang & Angermann 2005; γ, α_ij, γ_ij, b, b̂),
/// digits as printed there.
#[allow(clippy::excessive_precision)]
const GAMMA: f64 = 4.358_665_215_084_590e-1;
#[allow(clippy::excessive_precision)]
const ALPHA: [[f64; S]; S] = [
    [0.0, 0.0, 0.0, 0.0],
    [8.717_330_430_169_180_1e-1, 0.0, 0.0, 0.0],
    [
        8.445_706_001_536_942_3e-1,
        -1.129_906_423_648_418_5e-1,
        0.0,
        0.0,
    ],
    [0.0, 0.0, 1.0, 0.0],
];
#[allow(clippy::excessive_precision)]
const GAMMA_IJ: [[f64; S]; S] = [
    [GAMMA, 0.0, 0.0, 0.0],
    [-8.717_330_430_169_180_1e-1, GAMMA, 0.0, 0.0],
    [
        -9.033_805_701_304_408_2e-1,
        5.418_067_238_809_532_6e-2,
        GAMMA,
        0.0,
    ],
    [
        2.421_238_070_609_534_6e-1,
        -1.223_250_583_904_514_7,
        5.452_602_553_351_021_4e-1,
        GAMMA,
    ],
];
#[allow(clippy::excessive_precision)]
const B: [f64; S] = [
    2.421_238_070_609_534_6e-1,
    -1.223_250_583_904_514_7,
    1.545_260_255_335_102,
    GAMMA,
];
#[allow(clippy::excessive_precision)]
const B_HAT: [f64; S] = [
    3.781_090_314_581_936_9e-1,
    -9.604_229_221_242_317_8e-2,
    0.5,
    2.179_332_607_542_295e-1,
];

/// The transformed coefficients (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Tableau {
    pub(crate) a: [[f64; S]; S],
    pub(crate) c: [[f64; S]; S],
    pub(crate) m: [f64; S],
    pub(crate) m_hat: [f64; S],
    /// Stage times α_i = Σ_j α_ij.
    pub(crate) alpha: [f64; S],
}

impl Tableau {
    #[allow(clippy::needless_range_loop)]
    pub(crate) fn ros34pw2() -> Self {
        // Γ⁻¹ of the lower-triangular Γ by forward substitution.
        let mut inv = [[0.0; S]; S];
        for col in 0..S {
            for row in col..S {
                let mut s = if row == col { 1.0 } else { 0.0 };
                for k in col..row {
                    s -= GAMMA_IJ[row][k] * inv[k][col];
                }
                inv[row][col] = s / GAMMA_IJ[row][row];
            }
        }
        let mut a = [[0.0; S]; S];
        let mut c = [[0.0; S]; S];
        let mut alpha = [0.0; S];
        for i in 0..S {
            for j in 0..i {
                a[i][j] = (0..S).map(|k| ALPHA[i][k] * inv[k][j]).sum();
                c[i][j] = -inv[i][j];
            }
            alpha[i] = ALPHA[i].iter().sum();
        }
        let m = std::array::from_fn(|j| (0..S).map(|k| B[k] * inv[k][j]).sum());
        let m_hat = std::array::from_fn(|j| (0..S).map(|k| B_HAT[k] * inv[k][j]).sum());
        Self {
            a,
            c,
            m,
            m_hat,
            alpha,
        }
    }
}

fn validate<E>(s: &Rosenbrock) -> Result<(), IntegratorError<E>> {
    validate_adaptive(s.rtol, s.atol, s.max_step_s, s.min_step_s, s.max_steps)?;
    if !(s.initial_step_s.is_finite() && s.initial_step_s > 0.0) {
        return Err(invalid(
            "initial_step_s",
            s.initial_step_s,
            "must be finite and > 0",
        ));
    }
    if s.jacobian_max_age == 0 {
        return Err(invalid("jacobian_max_age", 0.0, "must be >= 1"));
    }
    Ok(())
}

/// Work vectors of one integration, allocated once.
struct Work {
    y: Vec<f64>,
    /// f(t, y) at the current accepted state.
    f: Vec<f64>,
    y_new: Vec<f64>,
    f_new: Vec<f64>,
    y_stage: Vec<f64>,
    u: [Vec<f64>; S],
    err: Vec<f64>,
}

/// Outcome of one step attempt.
enum Attempt {
    Accepted { err: f64 },
    Rejected { err: f64 },
    NonFinite { t: f64, component: usize },
    Singular,
}

#[allow(clippy::too_many_arguments)]
fn attempt<S_: OdeSystem>(
    s: &Rosenbrock,
    tab: &Tableau,
    system: &mut S_,
    jac: &mut BlockJacobian,
    w: &mut Work,
    t: f64,
    h: f64,
    t_new: f64,
    evaluations: &mut u64,
) -> Result<Attempt, IntegratorError<S_::Error>> {
    let n = w.y.len();
    // W's factors for a step within round-off of this one serve as they
    // are (module docs, "Steps on the output grid").
    let inv_hg = 1.0 / (h * GAMMA);
    let inv_hg = jac.factored_near(inv_hg).unwrap_or(inv_hg);
    if !jac.factor(inv_hg) {
        return Ok(Attempt::Singular);
    }
    for i in 0..S {
        let (done, rest) = w.u.split_at_mut(i);
        let ui = &mut rest[0];
        if i == 0 {
            ui.copy_from_slice(&w.f);
        } else {
            for k in 0..n {
                let mut sum = 0.0;
                for (j, uj) in done.iter().enumerate() {
                    sum += tab.a[i][j] * uj[k];
                }
                w.y_stage[k] = w.y[k] + sum;
            }
            let ts = if tab.alpha[i] == 1.0 {
                t_new
            } else {
                t + tab.alpha[i] * h
            };
            if let Some(component) = first_non_finite(&w.y_stage) {
                return Ok(Attempt::NonFinite { t: ts, component });
            }
            if let Some(component) = eval(system, ts, &w.y_stage, ui, evaluations)? {
                return Ok(Attempt::NonFinite { t: ts, component });
            }
            for k in 0..n {
                let mut sum = 0.0;
                for (j, uj) in done.iter().enumerate() {
                    sum += tab.c[i][j] * uj[k];
                }
                ui[k] += sum / h;
            }
        }
        jac.solve(inv_hg, ui);
    }
    let mut sum = 0.0;
    for k in 0..n {
        let mut dy = 0.0;
        let mut e = 0.0;
        for j in 0..S {
            dy += tab.m[j] * w.u[j][k];
            e += (tab.m[j] - tab.m_hat[j]) * w.u[j][k];
        }
        w.y_new[k] = w.y[k] + dy;
        w.err[k] = e;
        let sk = s.atol + s.rtol * w.y[k].abs().max(w.y_new[k].abs());
        let r = e / sk;
        sum += r * r;
    }
    if let Some(component) = first_non_finite(&w.y_new) {
        return Ok(Attempt::NonFinite {
            t: t_new,
            component,
        });
    }
    let err = (sum / n as f64).sqrt();
    if err.is_nan() || err > 1.0 {
        return Ok(Attempt::Rejected {
            err: if err.is_nan() { f64::INFINITY } else { err },
        });
    }
    // The next step's first stage, and the accept protocol's evaluation.
    if let Some(component) = eval(system, t_new, &w.y_new, &mut w.f_new, evaluations)? {
        return Ok(Attempt::NonFinite {
            t: t_new,
            component,
        });
    }
    Ok(Attempt::Accepted { err })
}

pub(super) fn integrate_rosenbrock<S_: OdeSystem>(
    settings: &Rosenbrock,
    system: &mut S_,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    output: &OutputGrid,
    observer: &mut Observer<'_, S_>,
) -> Result<IntegrationStats, IntegratorError<S_::Error>> {
    validate(settings)?;
    let n = y0.len();
    let layout = match settings.jacobian {
        JacobianApprox::SystemBlocks => system.jacobian_blocks(n),
        JacobianApprox::Dense => JacobianBlocks::dense(n),
    };
    if let Err(rule) = layout.check(n) {
        return Err(invalid("jacobian_blocks", layout.blocks.len() as f64, rule));
    }
    let tab = Tableau::ros34pw2();
    let mut jac = BlockJacobian::new(layout, n);
    let mut w = Work {
        y: y0.to_vec(),
        f: vec![0.0; n],
        y_new: vec![0.0; n],
        f_new: vec![0.0; n],
        y_stage: vec![0.0; n],
        u: std::array::from_fn(|_| vec![0.0; n]),
        err: vec![0.0; n],
    };
    let mut y_out = vec![0.0; n];
    let mut evaluations = 0u64;
    let mut jacobians = 0u64;
    let mut cursor = OutputCursor::new(t0, t_end, output);
    let mut range = StepRange::new();
    let (mut steps, mut rejected) = (0u64, 0u64);

    if let Some(component) = eval(system, t0, &w.y, &mut w.f, &mut evaluations)? {
        return Err(IntegratorError::NonFinite { t: t0, component });
    }
    let mut stopped = system.accept(t0, &w.y).map_err(IntegratorError::System)? == Control::Stop;
    let mut t = t0;
    cursor.emit_step(
        system,
        observer,
        t0,
        &w.y,
        stopped || t_end == t0,
        &mut y_out,
        &mut |_, _| {},
    )?;

    let mut h = settings.initial_step_s.min(settings.max_step_s);
    let mut age: u32 = 0;
    let mut fresh = false;
    let mut last_rejected = false;
    let mut last_non_finite: Option<(f64, usize)> = None;
    if !stopped && t < t_end {
        jac.evaluate(system, t, &w.y, &w.f, &mut evaluations)?;
        jacobians += 1;
        fresh = true;
    }

    while !stopped && t < t_end {
        let capped = h >= settings.max_step_s;
        h = h.min(settings.max_step_s);
        let (mut h_step, mut t_new) = next_attempt(
            t,
            h,
            t_end,
            steps + rejected,
            settings.max_steps,
            settings.min_step_s,
            LAST_STEP_STRETCH,
            last_non_finite,
        )?;
        // A step capped by max_step_s ends on the output time it would
        // pass (module docs, "Steps on the output grid").
        if capped
            && t_new < t_end
            && let Some(t_k) = cursor.landing(t, h_step)
        {
            h_step = t_k - t;
            t_new = t_k;
        }
        let outcome = attempt(
            settings,
            &tab,
            system,
            &mut jac,
            &mut w,
            t,
            h_step,
            t_new,
            &mut evaluations,
        )?;
        let factor = match outcome {
            Attempt::Accepted { err } => {
                stopped = system
                    .accept(t_new, &w.y_new)
                    .map_err(IntegratorError::System)?
                    == Control::Stop;
                steps += 1;
                range.record(h_step);
                let is_final = stopped || t_new == t_end;
                {
                    let (y, f, y1, f1) = (&w.y, &w.f, &w.y_new, &w.f_new);
                    cursor.emit_step(
                        system,
                        observer,
                        t_new,
                        y1,
                        is_final,
                        &mut y_out,
                        &mut |tk, out| hermite((tk - t) / h_step, h_step, y, f, y1, f1, out),
                    )?;
                }
                std::mem::swap(&mut w.y, &mut w.y_new);
                std::mem::swap(&mut w.f, &mut w.f_new);
                t = t_new;
                let mut fac = (SAFETY * err.powf(-1.0 / 3.0)).clamp(FACTOR_MIN, FACTOR_MAX);
                let changed = system.structure_changed();
                if last_rejected || changed {
                    fac = fac.min(1.0);
                }
                if (1.0..=KEEP_STEP_MAX).contains(&fac) {
                    fac = 1.0;
                }
                if changed {
                    age = settings.jacobian_max_age;
                }
                last_rejected = false;
                last_non_finite = None;
                age += 1;
                fresh = false;
                if age >= settings.jacobian_max_age && !stopped && t < t_end {
                    jac.evaluate(system, t, &w.y, &w.f, &mut evaluations)?;
                    jacobians += 1;
                    age = 0;
                    fresh = true;
                }
                h = h_step * fac;
                continue;
            }
            Attempt::Rejected { err } => {
                last_non_finite = None;
                (SAFETY * err.powf(-1.0 / 3.0)).clamp(FACTOR_MIN, 1.0)
            }
            Attempt::NonFinite { t: tf, component } => {
                last_non_finite = Some((tf, component));
                FACTOR_MIN
            }
            Attempt::Singular => {
                last_non_finite = None;
                FACTOR_MIN
            }
        };
        // Rejected: a Jacobian older than this state is renewed here.
        rejected += 1;
        last_rejected = true;
        if !fresh {
            jac.evaluate(system, t, &w.y, &w.f, &mut evaluations)?;
            jacobians += 1;
            age = 0;
            fresh = true;
        }
        h = h_step * factor;
    }

    let (min_step_s, max_step_s) = range.get();
    Ok(IntegrationStats {
        steps,
        rejected,
        rhs_evaluations: evaluations,
        jacobian_evaluations: jacobians,
        dense_lu_fallbacks: jac.dense_fallbacks(),
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

    /// The published coefficients meet the quadrature conditions to order
    /// 3 and the W-method condition of order 2 (Σ b_i Σ_{j≤i} γ_ij = 0:
    /// the Jacobian term contributes nothing to the order-2 expansion,
    /// whatever the matrix; HW II §IV.7); the embedded weights to order 2.
    /// Order 3 with any matrix is checked by convergence in
    /// tests/integrator_reference.rs.
    #[test]
    fn the_published_coefficients_meet_the_order_conditions() {
        let alpha_i: [f64; S] = std::array::from_fn(|i| ALPHA[i].iter().sum());
        let gamma_i: [f64; S] = std::array::from_fn(|i| GAMMA_IJ[i].iter().sum());
        let dot = |w: &[f64; S], f: &dyn Fn(usize) -> f64| (0..S).map(|i| w[i] * f(i)).sum::<f64>();
        for (w, name) in [(&B, "b"), (&B_HAT, "b̂")] {
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14, "{name}");
            assert!((dot(w, &|i| alpha_i[i]) - 0.5).abs() < 1e-14, "{name}");
            assert!(dot(w, &|i| gamma_i[i]).abs() < 1e-14, "{name}");
        }
        assert!((dot(&B, &|i| alpha_i[i] * alpha_i[i]) - 1.0 / 3.0).abs() < 1e-14);
        // Stiffly accurate: b is the last row of α + Γ, so y⁺ is the last
        // stage's argument plus its own increment.
        for j in 0..S {
            assert!((B[j] - ALPHA[3][j] - GAMMA_IJ[3][j]).abs() < 1e-15, "j {j}");
        }
        // The transformed weights reproduce y⁺ = y + Σ b k.
        let tab = Tableau::ros34pw2();
        let m_from_b: [f64; S] =
            std::array::from_fn(|j| (0..S).map(|i| tab.m[i] * GAMMA_IJ[i][j]).sum::<f64>());
        for j in 0..S {
            assert!((m_from_b[j] - B[j]).abs() < 1e-13, "j {j}");
        }
    }

    use crate::fixtures::ode::Oscillator;
    use crate::integrators::{Method, OutputGrid, integrate};
    use std::convert::Infallible;

    fn fixed(h: f64) -> Rosenbrock {
        Rosenbrock {
            rtol: 1e3,
            atol: 1e3,
            initial_step_s: h,
            max_step_s: h,
            ..Rosenbrock::default()
        }
    }

    fn oscillator_error(settings: Rosenbrock) -> f64 {
        let mut osc = Oscillator::new(1.0);
        let y0 = osc.initial();
        let mut last = [0.0; 2];
        integrate(
            &Method::Rosenbrock(settings),
            &mut osc,
            0.0,
            &y0,
            2.0,
            &OutputGrid { interval_s: 10.0 },
            &mut |_, _, y| {
                last = [y[0], y[1]];
                Ok(())
            },
        )
        .unwrap();
        let exact = Oscillator::new(1.0).exact(2.0);
        (last[0] - exact[0]).hypot(last[1] - exact[1])
    }

    /// Order 3 at fixed steps, with the finite-difference Jacobian and
    /// with a Jacobian refreshed only every 1000 steps (a W-method keeps
    /// its order with a stale matrix): halving h divides the error by
    /// 2³ = 8 (measured 7.5–8.5).
    #[test]
    fn the_method_is_of_order_three_with_any_jacobian() {
        for age in [1, 1000] {
            let e1 = oscillator_error(Rosenbrock {
                jacobian_max_age: age,
                ..fixed(0.02)
            });
            let e2 = oscillator_error(Rosenbrock {
                jacobian_max_age: age,
                ..fixed(0.01)
            });
            let ratio = e1 / e2;
            assert!(
                (7.0..9.0).contains(&ratio),
                "age {age}: {e1:e} / {e2:e} = {ratio}"
            );
        }
    }

    /// Prothero–Robinson, y′ = −λ (y − sin t) + cos t, y(0) = 0, λ = 10⁶
    /// (1/s): y = sin t. An explicit method needs h < 2.8·10⁻⁶ s; the
    /// linearly implicit one follows sin t to atol with steps of
    /// centiseconds.
    struct ProtheroRobinson;

    impl OdeSystem for ProtheroRobinson {
        type Error = Infallible;
        fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) -> Result<(), Infallible> {
            dydt[0] = -1e6 * (y[0] - t.sin()) + t.cos();
            Ok(())
        }
        fn accept(&mut self, _t: f64, _y: &[f64]) -> Result<Control, Infallible> {
            Ok(Control::Continue)
        }
    }

    #[test]
    fn a_stiff_problem_takes_large_steps() {
        let mut worst = 0.0_f64;
        let stats = integrate(
            &Method::Rosenbrock(Rosenbrock {
                atol: 1e-6,
                max_step_s: 1.0,
                ..Rosenbrock::default()
            }),
            &mut ProtheroRobinson,
            0.0,
            &[0.0],
            2.0,
            &OutputGrid { interval_s: 0.05 },
            &mut |_, t, y| {
                worst = worst.max((y[0] - t.sin()).abs());
                Ok(())
            },
        )
        .unwrap();
        assert!(worst < 1e-5, "worst error {worst:e}");
        assert!(stats.steps < 300, "{stats:?}");
        assert!(stats.max_step_s > 0.01, "{stats:?}");
        assert!(stats.jacobian_evaluations >= 1);
    }
}
