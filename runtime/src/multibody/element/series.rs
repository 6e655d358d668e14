//! The series spring–damper (Maxwell element) of one axis
//! (docs/reference/08-multibody.md §8.2): a damper c in series with a spring k — a
//! hydraulic damper with its rubber end bushes (Iwnicki (ed.), *Handbook of
//! Railway Vehicle Dynamics*, CRC 2006, chapter on suspension components:
//! the damper's series stiffness; Knothe & Stichel, *Rail Vehicle
//! Dynamics*, Springer 2017, series spring–damper models).
//!
//! With the element's deflection δ along the axis and the damper's stroke q
//! (the internal state, m), the spring is deflected by δ − q and the force
//! through both is the same:
//!
//! ```text
//! F = k (δ − q)            restoring force (force on b: −F)
//! c q̇ = F  ⇒  q̇ = k (δ − q) / c
//! ```
//!
//! Energy: the spring stores U = ½ k (δ − q)², the damper dissipates
//! P = c q̇² = F² / c ≥ 0, and F δ̇ = dU/dt + P (the power put in at the
//! ends is stored or dissipated). After a step δ = δ₀ at t = 0 with q(0) = 0
//! the force relaxes as F(t) = k δ₀ e^{−k t / c} (time constant c/k).
//!
//! At rest (static equilibrium) the damper has crept until F = 0: a series
//! element carries no static force and adds no static stiffness.

use super::law::SeriesLaw;

impl SeriesLaw {
    /// Restoring force F = k (δ − q) (N) at the deflection δ and the
    /// stroke q (m).
    pub fn force_n(&self, deflection_m: f64, stroke_m: f64) -> f64 {
        self.stiffness_n_m * (deflection_m - stroke_m)
    }

    /// The stroke's rate q̇ = k (δ − q) / c (m/s).
    pub fn stroke_rate_m_s(&self, deflection_m: f64, stroke_m: f64) -> f64 {
        self.force_n(deflection_m, stroke_m) / self.damping_n_s_m
    }

    /// Energy in the spring ½ k (δ − q)² (J).
    pub fn energy_j(&self, deflection_m: f64, stroke_m: f64) -> f64 {
        let d = deflection_m - stroke_m;
        0.5 * self.stiffness_n_m * d * d
    }

    /// Power dissipated by the damper c q̇² = F²/c (W) ≥ 0.
    pub fn dissipated_power_w(&self, deflection_m: f64, stroke_m: f64) -> f64 {
        let f = self.force_n(deflection_m, stroke_m);
        f * f / self.damping_n_s_m
    }

    /// Time constant c/k (s).
    pub fn time_constant_s(&self) -> f64 {
        self.damping_n_s_m / self.stiffness_n_m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LAW: SeriesLaw = SeriesLaw {
        stiffness_n_m: 5e6,
        damping_n_s_m: 5e4,
    };

    /// Step δ₀ = 2 mm held from t = 0, q(0) = 0: F(t) = k δ₀ e^{−k t/c}
    /// (τ = 10 ms). Integrated with RK4 at h = τ/100 (global error
    /// ~(h/τ)⁴ = 1e-8 relative); compared to 1e-7 of k δ₀ over 5 τ.
    #[test]
    fn relaxation_after_a_step_is_exponential() {
        let (delta0, tau) = (0.002, LAW.time_constant_s());
        assert!((tau - 0.01).abs() < 1e-15);
        let h = tau / 100.0;
        let f0 = LAW.stiffness_n_m * delta0;
        let mut q = 0.0;
        for n in 1..=500 {
            let k1 = LAW.stroke_rate_m_s(delta0, q);
            let k2 = LAW.stroke_rate_m_s(delta0, q + 0.5 * h * k1);
            let k3 = LAW.stroke_rate_m_s(delta0, q + 0.5 * h * k2);
            let k4 = LAW.stroke_rate_m_s(delta0, q + h * k3);
            q += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            let t = n as f64 * h;
            let exact = f0 * (-LAW.stiffness_n_m * t / LAW.damping_n_s_m).exp();
            let f = LAW.force_n(delta0, q);
            assert!((f - exact).abs() < 1e-7 * f0, "t = {t}: {f} vs {exact}");
        }
    }

    /// F δ̇ = dU/dt + P along a prescribed δ(t) = A sin ωt: the work put in
    /// equals the stored energy plus the dissipated energy (RK4, h = 1e-5 s,
    /// trapezoidal work; 1e-6 relative to the work put in).
    #[test]
    fn energy_is_stored_or_dissipated() {
        let (a, w) = (0.003, 2.0 * std::f64::consts::PI * 8.0);
        let delta = |t: f64| a * (w * t).sin();
        let rate = |t: f64| a * w * (w * t).cos();
        let h = 1e-5;
        let (mut q, mut work, mut dissipated) = (0.0, 0.0, 0.0);
        let mut t = 0.0;
        let power_in = |t: f64, q: f64| LAW.force_n(delta(t), q) * rate(t);
        let mut total_in = 0.0;
        for _ in 0..20_000 {
            let (p0, d0) = (power_in(t, q), LAW.dissipated_power_w(delta(t), q));
            let f = |t: f64, q: f64| LAW.stroke_rate_m_s(delta(t), q);
            let k1 = f(t, q);
            let k2 = f(t + 0.5 * h, q + 0.5 * h * k1);
            let k3 = f(t + 0.5 * h, q + 0.5 * h * k2);
            let k4 = f(t + h, q + h * k3);
            q += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            t += h;
            let (p1, d1) = (power_in(t, q), LAW.dissipated_power_w(delta(t), q));
            work += 0.5 * (p0 + p1) * h;
            total_in += 0.5 * (p0.abs() + p1.abs()) * h;
            dissipated += 0.5 * (d0 + d1) * h;
        }
        let stored = LAW.energy_j(delta(t), q);
        assert!(dissipated > 0.1 * total_in, "{dissipated} of {total_in}");
        assert!(
            (work - stored - dissipated).abs() < 1e-6 * total_in,
            "work {work}, stored {stored}, dissipated {dissipated}"
        );
    }
}
