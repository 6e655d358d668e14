//! Time integrators for the multibody equations of motion (docs/reference/08-multibody.md §8):
//! fixed-step classical Runge–Kutta (RK4), adaptive Dormand–Prince 5(4)
//! (DOPRI5) and, for the stiff contact modes, the adaptive linearly
//! implicit Rosenbrock-W method ROS34PW2 with a block-diagonal
//! finite-difference Jacobian ([`rosenbrock`], docs/reference/08-multibody.md §8.5), all with dense
//! output, behind one entry point, [`integrate`].
//!
//! # Why hand-written rather than a crate
//!
//! docs/reference/08-multibody.md §8 prefers a well-kept crate where it fits the warm-started contact
//! state. It does not fit here: the simulator's right-hand side carries
//! **history that may only change at accepted states** — the contact's
//! hysteresis memory (the impact velocity δ̇⁽⁻⁾ and the start-up rule's
//! running maximum δ̇max of paper eq. 22, [`crate::forces::normal`]) — and warm-start
//! data (the surface parameters of the last step are the next initial guess,
//! docs/reference/08-multibody.md §8). Trial stages and rejected steps must not commit it. Both methods
//! already evaluate the right-hand side at every accepted state (RK4's k1 of
//! the next step, DOPRI5's FSAL stage k7), so committing history from that
//! very evaluation costs nothing: [`OdeSystem::accept`] is called right after
//! it. Crates such as `ode_solvers` expose accepted steps only after the fact
//! through a `solout` callback, so the system would have to evaluate the
//! right-hand side once more per step to commit (1 extra evaluation on 4 for
//! RK4, on 6 for DOPRI5: 17–25 % of the cost). The same hook ends a run on an
//! end condition or Ctrl-C ([`Control::Stop`]), and the output grid is
//! sampled with each method's dense output instead of forcing steps onto it.
//!
//! # Protocol
//!
//! For every accepted state (t, y) — the initial state included — the
//! integrator calls [`OdeSystem::rhs`] at (t, y) and then, **immediately and
//! exactly once**, [`OdeSystem::accept`] at the same (t, y) (bit-identical
//! arguments). All other `rhs` calls are trial stages: they may update
//! caches (warm starts) but must not commit history. A rejected DOPRI5 step
//! evaluates its end state (k7 enters the error estimate) but is never
//! accepted. After `accept`, the observer is called for the output times of
//! the step just completed (see below); it receives the system and may call
//! `rhs` itself (e.g. to evaluate forces at an output time). The integrator
//! keeps its own copies of the stage derivatives, so such calls do not
//! disturb it; note that history has then already been committed at the
//! step's end, at most one step after the output time.
//!
//! # Output grid
//!
//! Output times are t_k = t0 + k·`interval_s` (k = 0, 1, …; computed from k,
//! not accumulated) strictly before the final time t_f minus a tolerance
//! ε = 10⁻⁶·`interval_s` + 4·ε_mach·max(|t0|, |t_end|), then t_f itself,
//! **always, last and exactly once**. t_f is `t_end`, or the accepted time at
//! which [`Control::Stop`] was returned. So a grid time that lands on t_end
//! (within ε, e.g. 3·0.1 = 0.30000000000000004 for t_end = 0.3) is emitted
//! once, as t_end exactly; a t_end off the grid adds one shorter last
//! interval. t0 and t_f receive the exact states; times in between receive
//! the dense-output state of the step containing them (DOPRI5: the
//! 4th-order continuous extension, [`dopri5`]; RK4: cubic Hermite between
//! the step's end states and derivatives, [`rk4`]). t0 == t_end is allowed:
//! one evaluation, one accept, one observer call. The Rosenbrock method
//! ends a step capped by its largest step on the last grid time the step
//! would pass ([`rosenbrock`], "Steps on the output grid"), so that time
//! receives the exact state.
//!
//! # Errors
//!
//! No panics on user input. Settings are validated first
//! ([`IntegratorError::InvalidSettings`] names the setting, its value and the
//! rule). A non-finite initial state or initial derivative, a non-finite RK4
//! stage or a DOPRI5 step that keeps failing on non-finite values is
//! [`IntegratorError::NonFinite`] (time of the offending evaluation, index
//! of the first non-finite component of the state or derivative). Errors of
//! the system (from `rhs`, `accept` or the observer) are passed through as
//! [`IntegratorError::System`].

pub mod body_blocks;
pub mod dopri5;
pub mod jacobian;
pub mod kinematic;
pub mod rk4;
pub mod rosenbrock;

pub use dopri5::Dopri5;
pub use jacobian::{ColoredColumns, ColumnColor, JacobianBlocks};
pub use kinematic::KinematicBlock;
pub use rk4::Rk4;
pub use rosenbrock::{JacobianApprox, Rosenbrock};

/// What the right-hand side tells the integrator after an accepted state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Go on integrating.
    Continue,
    /// End the integration at this accepted state (end condition, Ctrl-C):
    /// the observer still receives the output times up to it and the state
    /// itself, and [`IntegrationStats::stopped`] is set.
    Stop,
}

/// A first-order system y′ = f(t, y) (t in s) with history committed at
/// accepted states only (module docs, "Protocol").
pub trait OdeSystem {
    /// The system's own error type, passed through in
    /// [`IntegratorError::System`].
    type Error: std::error::Error + 'static;

    /// dy/dt at (t, y) into `dydt` (same length as y). May update caches;
    /// must not commit history.
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) -> Result<(), Self::Error>;

    /// The most recent `rhs` call was made at an accepted state (t, y):
    /// commit history from it. Called exactly once per accepted state,
    /// immediately after that `rhs` call (so the system can commit what
    /// that evaluation computed), the initial state included. Returning
    /// [`Control::Stop`] ends the integration after this state.
    fn accept(&mut self, t: f64, y: &[f64]) -> Result<Control, Self::Error>;

    /// The diagonal blocks of the Jacobian the stiff integrator
    /// approximates, and which of them may be perturbed together
    /// ([`jacobian`] module docs). Default: one dense block over all `n`
    /// components.
    fn jacobian_blocks(&self, n: usize) -> JacobianBlocks {
        JacobianBlocks::dense(n)
    }

    /// dy/dt at (t, y) where y differs from the state of the last
    /// [`Self::accept`] call in the components `changed` only: one column
    /// of a finite-difference Jacobian, or several perturbed together
    /// ([`jacobian`] module docs). A system may reuse what those components
    /// cannot change (the vehicle: the contacts of the other wheelsets),
    /// and must give the same derivative as [`Self::rhs`] up to its own
    /// convergence tolerances. Default: [`Self::rhs`].
    fn rhs_column(
        &mut self,
        t: f64,
        y: &[f64],
        changed: &[usize],
        dydt: &mut [f64],
    ) -> Result<(), Self::Error> {
        let _ = changed;
        self.rhs(t, y, dydt)
    }

    /// Called right after [`Self::accept`]: whether the system's structure
    /// changed since the previous call (a contact opened or closed, a flange
    /// came into contact), so that the stiff integrator renews its Jacobian
    /// there and does not grow the next step. Default: never.
    fn structure_changed(&mut self) -> bool {
        false
    }
}

/// The output callback of [`integrate`]: `observer(system, t, y)` at each
/// output time t (s) with the state y there; errors end the integration as
/// [`IntegratorError::System`].
pub type Observer<'a, S> =
    dyn FnMut(&mut S, f64, &[f64]) -> Result<(), <S as OdeSystem>::Error> + 'a;

/// The integration method and its settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Fixed-step classical Runge–Kutta, 4th order.
    Rk4(Rk4),
    /// Adaptive Dormand–Prince 5(4) with 4th-order dense output.
    Dopri5(Dopri5),
    /// Adaptive linearly implicit Rosenbrock-W ROS34PW2 (order 3) for
    /// stiff systems, with cubic Hermite dense output.
    Rosenbrock(Rosenbrock),
}

/// Output times t0 + k·`interval_s` (k = 0, 1, …) before the final time,
/// then the final time (t_end, or the stop time) itself, always and once
/// (module docs, "Output grid").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputGrid {
    /// Output interval (s), finite and > 0. An interval ≥ t_end − t0 gives
    /// the initial and the final state only.
    pub interval_s: f64,
}

/// Counters of one [`integrate`] call.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntegrationStats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected step attempts (always 0 for RK4).
    pub rejected: u64,
    /// Right-hand-side evaluations made by the integrator (the observer's
    /// own calls are not counted). RK4: 4·steps + 1; DOPRI5: 6·(steps +
    /// rejected) + 1, + 1 for the initial-step heuristic; Rosenbrock: 3 per
    /// attempt + 1 per accepted step + 1, plus the Jacobians' evaluations.
    pub rhs_evaluations: u64,
    /// Finite-difference Jacobians evaluated (Rosenbrock; 0 otherwise).
    pub jacobian_evaluations: u64,
    /// Factorisations of W that fell back from the block elimination to
    /// the dense LU (a pivot below the threshold; [`body_blocks`];
    /// Rosenbrock on rigid bodies only, 0 otherwise).
    pub dense_lu_fallbacks: u64,
    /// Observer calls (output times, the final one included).
    pub outputs: u64,
    /// The time of the last accepted state (s): t_end, or the stop time.
    pub t_end_reached: f64,
    /// Whether [`OdeSystem::accept`] returned [`Control::Stop`].
    pub stopped: bool,
    /// Smallest accepted step (s), the shortened last step included; 0 when
    /// no step was taken.
    pub min_step_s: f64,
    /// Largest accepted step (s); 0 when no step was taken.
    pub max_step_s: f64,
}

/// Why an integration failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntegratorError<E> {
    /// The system's `rhs`, `accept` or the observer failed.
    #[error("{0}")]
    System(#[source] E),
    /// DOPRI5: the step size the error control asks for fell below
    /// `min_step_s` or below the time resolution at t.
    #[error("step size {step_s} s at t = {t} s is below the minimum (min_step_s or round-off)")]
    StepSizeTooSmall { t: f64, step_s: f64 },
    /// DOPRI5: `max_steps` step attempts (accepted + rejected) were made
    /// before reaching t_end.
    #[error("{steps} step attempts reached the limit at t = {t} s before t_end")]
    TooManySteps { t: f64, steps: u64 },
    /// A state or derivative component is NaN or infinite: t is the time of
    /// the offending evaluation (or state), `component` the index of its
    /// first non-finite entry.
    #[error("non-finite state or derivative, component {component}, at t = {t} s")]
    NonFinite { t: f64, component: usize },
    /// A setting or argument breaks its rule.
    #[error("invalid setting {setting} = {value}: {rule}")]
    InvalidSettings {
        setting: &'static str,
        value: f64,
        rule: &'static str,
    },
}

/// Integrate y′ = f(t, y) from (t0, y0) to t_end (s) with `method`.
///
/// `observer(system, t, y)` is called for every output time of `output`
/// (module docs, "Output grid") with the state at that time — exact at t0
/// and at the final time, otherwise DOPRI5's 4th-order continuous extension
/// (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.6) or, for RK4, the
/// cubic Hermite interpolant between step ends — with the system passed back
/// in so it can evaluate outputs (forces) at that state. The accept protocol
/// is in the module docs. Work vectors are allocated once per call; the step
/// loop does not allocate.
pub fn integrate<S: OdeSystem>(
    method: &Method,
    system: &mut S,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    output: &OutputGrid,
    observer: &mut Observer<'_, S>,
) -> Result<IntegrationStats, IntegratorError<S::Error>> {
    validate_common(t0, y0, t_end, output)?;
    match method {
        Method::Rk4(settings) => {
            rk4::integrate_rk4(settings, system, t0, y0, t_end, output, observer)
        }
        Method::Dopri5(settings) => {
            dopri5::integrate_dopri5(settings, system, t0, y0, t_end, output, observer)
        }
        Method::Rosenbrock(settings) => {
            rosenbrock::integrate_rosenbrock(settings, system, t0, y0, t_end, output, observer)
        }
    }
}

fn invalid<E>(setting: &'static str, value: f64, rule: &'static str) -> IntegratorError<E> {
    IntegratorError::InvalidSettings {
        setting,
        value,
        rule,
    }
}

/// Checks shared by both methods: times, state, output grid.
fn validate_common<E>(
    t0: f64,
    y0: &[f64],
    t_end: f64,
    output: &OutputGrid,
) -> Result<(), IntegratorError<E>> {
    if !t0.is_finite() {
        return Err(invalid("t0", t0, "must be finite"));
    }
    if !t_end.is_finite() {
        return Err(invalid("t_end", t_end, "must be finite"));
    }
    if t_end < t0 {
        return Err(invalid("t_end", t_end, "must be >= t0"));
    }
    if y0.is_empty() {
        return Err(invalid(
            "y0.len()",
            0.0,
            "the state must have at least one component",
        ));
    }
    if !(output.interval_s.is_finite() && output.interval_s > 0.0) {
        return Err(invalid(
            "interval_s",
            output.interval_s,
            "must be finite and > 0",
        ));
    }
    if let Some(component) = first_non_finite(y0) {
        return Err(IntegratorError::NonFinite { t: t0, component });
    }
    Ok(())
}

/// Checks shared by the adaptive methods (DOPRI5, Rosenbrock): tolerances,
/// step limits, the attempt budget; each rule named in the error.
fn validate_adaptive<E>(
    rtol: f64,
    atol: f64,
    max_step_s: f64,
    min_step_s: f64,
    max_steps: u64,
) -> Result<(), IntegratorError<E>> {
    if !(rtol.is_finite() && rtol > 10.0 * f64::EPSILON) {
        return Err(invalid(
            "rtol",
            rtol,
            "must be finite and > 10·eps (2.2e-15)",
        ));
    }
    if !(atol.is_finite() && atol > 0.0) {
        return Err(invalid("atol", atol, "must be finite and > 0"));
    }
    if max_step_s.is_nan() || max_step_s <= 0.0 {
        return Err(invalid(
            "max_step_s",
            max_step_s,
            "must be > 0 (may be +inf)",
        ));
    }
    if !(min_step_s.is_finite() && min_step_s >= 0.0) {
        return Err(invalid("min_step_s", min_step_s, "must be finite and >= 0"));
    }
    if min_step_s > max_step_s {
        return Err(invalid("min_step_s", min_step_s, "must be <= max_step_s"));
    }
    if max_steps == 0 {
        return Err(invalid("max_steps", 0.0, "must be > 0"));
    }
    Ok(())
}

/// The adaptive methods' guard before a step attempt from t with the
/// proposed step h (s): the attempt budget, the smallest step (the last
/// non-finite value, if one caused the shrinking, is the error then), and
/// the landing on t_end within `stretch`·h. Returns (h_step, t_new).
#[allow(clippy::too_many_arguments)]
fn next_attempt<E>(
    t: f64,
    h: f64,
    t_end: f64,
    attempts: u64,
    max_steps: u64,
    min_step_s: f64,
    stretch: f64,
    last_non_finite: Option<(f64, usize)>,
) -> Result<(f64, f64), IntegratorError<E>> {
    if attempts >= max_steps {
        return Err(IntegratorError::TooManySteps { t, steps: attempts });
    }
    if h < min_step_s || h <= 10.0 * f64::EPSILON * t.abs() || h.is_nan() {
        return Err(match last_non_finite {
            Some((t, component)) => IntegratorError::NonFinite { t, component },
            None => IntegratorError::StepSizeTooSmall { t, step_s: h },
        });
    }
    Ok(if t + stretch * h >= t_end {
        (t_end - t, t_end)
    } else {
        (h, t + h)
    })
}

/// Index of the first NaN or infinite entry.
fn first_non_finite(v: &[f64]) -> Option<usize> {
    v.iter().position(|x| !x.is_finite())
}

/// Calls `rhs`, counts it, and checks the derivative is finite.
fn eval<S: OdeSystem>(
    system: &mut S,
    t: f64,
    y: &[f64],
    dydt: &mut [f64],
    evaluations: &mut u64,
) -> Result<Option<usize>, IntegratorError<S::Error>> {
    system.rhs(t, y, dydt).map_err(IntegratorError::System)?;
    *evaluations += 1;
    Ok(first_non_finite(dydt))
}

/// [`eval`] of Jacobian columns perturbed together ([`OdeSystem::rhs_column`]).
fn eval_column<S: OdeSystem>(
    system: &mut S,
    t: f64,
    y: &[f64],
    changed: &[usize],
    dydt: &mut [f64],
    evaluations: &mut u64,
) -> Result<Option<usize>, IntegratorError<S::Error>> {
    system
        .rhs_column(t, y, changed, dydt)
        .map_err(IntegratorError::System)?;
    *evaluations += 1;
    Ok(first_non_finite(dydt))
}

/// Relative round-off a step may be stretched by to end on a grid time
/// ([`OutputCursor::landing`]): a step of exactly one output interval from
/// a grid time reaches the next one within a few ulps.
const LANDING_ROUND_OFF: f64 = 1e-9;

/// A step is not shortened below this fraction of itself to end on a
/// grid time ([`OutputCursor::landing`]): it would cost a whole step.
const LANDING_MIN_FRACTION: f64 = 0.01;

/// Walks the output grid (module docs, "Output grid").
#[derive(Debug, Clone)]
struct OutputCursor {
    t0: f64,
    interval_s: f64,
    t_end: f64,
    /// ε of the module docs (s).
    eps: f64,
    /// Index k of the next grid time to emit.
    next_k: u64,
    /// Observer calls so far.
    emitted: u64,
}

impl OutputCursor {
    fn new(t0: f64, t_end: f64, output: &OutputGrid) -> Self {
        let eps = 1e-6 * output.interval_s + 4.0 * f64::EPSILON * t0.abs().max(t_end.abs());
        Self {
            t0,
            interval_s: output.interval_s,
            t_end,
            eps,
            next_k: 0,
            emitted: 0,
        }
    }

    /// The next grid time in the step ending at `t_curr` (and not yet
    /// emitted), advancing past it; `is_final` when `t_curr` is the final
    /// time (which [`Self::emit_step`] emits exactly afterwards).
    fn next_in_step(&mut self, t_curr: f64, is_final: bool) -> Option<f64> {
        let t_k = self.t0 + self.next_k as f64 * self.interval_s;
        let before_final = if is_final {
            t_k < t_curr - self.eps
        } else {
            t_k <= t_curr
        };
        if before_final && t_k < self.t_end - self.eps {
            self.next_k += 1;
            Some(t_k)
        } else {
            None
        }
    }

    /// The grid time a step from `t` of `h` may end on instead of passing
    /// it (module docs, "Output grid"): the last one not yet emitted in
    /// (t + [`LANDING_MIN_FRACTION`]·h, t + h·(1 + [`LANDING_ROUND_OFF`])],
    /// before the final time.
    fn landing(&self, t: f64, h: f64) -> Option<f64> {
        let reach = t + h * (1.0 + LANDING_ROUND_OFF);
        let mut k = ((reach - self.t0) / self.interval_s).floor();
        if !(k.is_finite() && k >= 0.0) {
            return None;
        }
        // The grid time from k, as `next_in_step` computes it; one back if
        // the division rounded up.
        let mut t_k = self.t0 + k * self.interval_s;
        if t_k > reach {
            k -= 1.0;
            t_k = self.t0 + k * self.interval_s;
        }
        let on_grid = k >= self.next_k as f64;
        (on_grid && t_k > t + LANDING_MIN_FRACTION * h && t_k < self.t_end - self.eps)
            .then_some(t_k)
    }

    /// After an accepted state at `t_curr` (the step from `t_prev`, or the
    /// initial state when `t_prev == t_curr`): the grid times in the step,
    /// with `interpolate(t, out)` filling the state at t, then the final
    /// state exactly when `is_final`.
    #[allow(clippy::too_many_arguments)]
    fn emit_step<S: OdeSystem>(
        &mut self,
        system: &mut S,
        observer: &mut Observer<'_, S>,
        t_curr: f64,
        y_curr: &[f64],
        is_final: bool,
        y_out: &mut [f64],
        interpolate: &mut dyn FnMut(f64, &mut [f64]),
    ) -> Result<(), IntegratorError<S::Error>> {
        while let Some(t_k) = self.next_in_step(t_curr, is_final) {
            if t_k == t_curr {
                observer(system, t_k, y_curr).map_err(IntegratorError::System)?;
            } else {
                interpolate(t_k, y_out);
                observer(system, t_k, y_out).map_err(IntegratorError::System)?;
            }
            self.emitted += 1;
        }
        if is_final {
            observer(system, t_curr, y_curr).map_err(IntegratorError::System)?;
            self.emitted += 1;
        }
        Ok(())
    }
}

/// Running min/max of accepted step sizes.
#[derive(Debug, Clone, Copy)]
struct StepRange {
    min_s: f64,
    max_s: f64,
}

impl StepRange {
    fn new() -> Self {
        Self {
            min_s: f64::INFINITY,
            max_s: 0.0,
        }
    }

    fn record(&mut self, h: f64) {
        self.min_s = self.min_s.min(h);
        self.max_s = self.max_s.max(h);
    }

    /// (min, max), (0, 0) when empty.
    fn get(&self) -> (f64, f64) {
        if self.min_s.is_finite() {
            (self.min_s, self.max_s)
        } else {
            (0.0, 0.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::convert::Infallible;

    /// y′ = 1 (so y = t exactly, any method).
    struct Clock;

    impl OdeSystem for Clock {
        type Error = Infallible;
        fn rhs(&mut self, _t: f64, _y: &[f64], dydt: &mut [f64]) -> Result<(), Infallible> {
            dydt[0] = 1.0;
            Ok(())
        }
        fn accept(&mut self, _t: f64, _y: &[f64]) -> Result<Control, Infallible> {
            Ok(Control::Continue)
        }
    }

    fn output_times(method: &Method, t0: f64, t_end: f64, interval_s: f64) -> Vec<(f64, f64)> {
        let mut times = Vec::new();
        let stats = integrate(
            method,
            &mut Clock,
            t0,
            &[t0],
            t_end,
            &OutputGrid { interval_s },
            &mut |_, t, y| {
                times.push((t, y[0]));
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(stats.outputs as usize, times.len());
        times
    }

    fn methods() -> [Method; 3] {
        [
            Method::Rk4(Rk4 { step_s: 0.07 }),
            Method::Dopri5(Dopri5::default()),
            Method::Rosenbrock(Rosenbrock::default()),
        ]
    }

    #[test]
    fn grid_landing_on_t_end_is_emitted_once_as_t_end() {
        for method in methods() {
            // 3·0.1 = 0.30000000000000004 > 0.3: snapped, emitted once.
            let out = output_times(&method, 0.0, 0.3, 0.1);
            let t: Vec<f64> = out.iter().map(|p| p.0).collect();
            assert_eq!(t, vec![0.0, 0.1, 0.2, 0.3], "{method:?}");
            // 0.25 lands exactly.
            let out = output_times(&method, 0.0, 1.0, 0.25);
            let t: Vec<f64> = out.iter().map(|p| p.0).collect();
            assert_eq!(t, vec![0.0, 0.25, 0.5, 0.75, 1.0], "{method:?}");
            // y = t: the interpolants reproduce a linear solution.
            for (t, y) in out {
                assert!((y - t).abs() < 1e-14, "{method:?} t {t} y {y}");
            }
        }
    }

    #[test]
    fn t_end_off_the_grid_is_emitted_last() {
        for method in methods() {
            let out = output_times(&method, 1.0, 2.0, 0.3);
            let t: Vec<f64> = out.iter().map(|p| p.0).collect();
            assert_eq!(t.len(), 5, "{method:?} {t:?}");
            for (k, tk) in t[..4].iter().enumerate() {
                assert_eq!(*tk, 1.0 + k as f64 * 0.3);
            }
            assert_eq!(t[4], 2.0);
            // A grid coarser than the span: the two ends only.
            let out = output_times(&method, 0.0, 1.0, 5.0);
            let t: Vec<f64> = out.iter().map(|p| p.0).collect();
            assert_eq!(t, vec![0.0, 1.0], "{method:?}");
        }
    }

    #[test]
    fn zero_length_interval_gives_one_output() {
        for method in methods() {
            let out = output_times(&method, 2.0, 2.0, 0.1);
            assert_eq!(out, vec![(2.0, 2.0)], "{method:?}");
        }
    }

    #[test]
    fn common_settings_are_validated() {
        let method = Method::Rk4(Rk4 { step_s: 0.1 });
        let grid = OutputGrid { interval_s: 0.1 };
        let mut obs = |_: &mut Clock, _: f64, _: &[f64]| Ok(());
        let setting = |r: Result<IntegrationStats, IntegratorError<Infallible>>| match r {
            Err(IntegratorError::InvalidSettings { setting, .. }) => setting,
            other => panic!("expected InvalidSettings, got {other:?}"),
        };
        assert_eq!(
            setting(integrate(
                &method,
                &mut Clock,
                1.0,
                &[0.0],
                0.5,
                &grid,
                &mut obs
            )),
            "t_end"
        );
        assert_eq!(
            setting(integrate(
                &method,
                &mut Clock,
                f64::NAN,
                &[0.0],
                0.5,
                &grid,
                &mut obs
            )),
            "t0"
        );
        assert_eq!(
            setting(integrate(
                &method,
                &mut Clock,
                0.0,
                &[0.0],
                f64::INFINITY,
                &grid,
                &mut obs
            )),
            "t_end"
        );
        assert_eq!(
            setting(integrate(
                &method,
                &mut Clock,
                0.0,
                &[],
                1.0,
                &grid,
                &mut obs
            )),
            "y0.len()"
        );
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(
                setting(integrate(
                    &method,
                    &mut Clock,
                    0.0,
                    &[0.0],
                    1.0,
                    &OutputGrid { interval_s: bad },
                    &mut obs
                )),
                "interval_s"
            );
        }
        assert!(matches!(
            integrate(
                &method,
                &mut Clock,
                0.0,
                &[0.0, f64::NAN],
                1.0,
                &grid,
                &mut obs
            ),
            Err(IntegratorError::NonFinite {
                t: 0.0,
                component: 1
            })
        ));
    }
}
