//! `runtime::multibody::body` and `runtime::multibody::element` integrated in time (docs/reference/08-multibody.md §8)
//! against closed-form solutions and conservation laws.
//!
//! The integrator is the classical fixed-step RK4, written here (the crate's
//! own integrators are tested elsewhere). It does **not** renormalise the
//! stored quaternion: `BodyState::read_from` does, and the tests report how
//! far the stored norm drifts.
//!
//! # Tolerances (what each test asserts; measured values in the messages,
//! `cargo test -p runtime --test body_dynamics -- --nocapture`)
//!
//! | test | quantity | tolerance |
//! |---|---|---|
//! | constant ω | angle between q(t) and q₀ ⊗ exp(ωt/2), 10 s, h = 1 ms | 1e-9 rad |
//! | symmetric top | |ω(t) − analytic| / |ω|, precession Ω = (I₃ − I₁)/I₁ ω₃, 20 s | 1e-9; error ratio h/(h/2) ≈ 16 (14–18) |
//! | Dzhanibekov | relative change of |L|, T, and of the global vector L, 40 s | 1e-8 |
//! | free fall | |r − (r₀ + v₀t + ½gt²)|, |v − (v₀ + gt)| | 1e-12 m, m/s |
//! | oscillator | x(t) vs x₀ cos √(k/m) t, per axis, 2 s, h = 50 µs | 1e-9 of x₀ |
//! | oscillator | frequency from zero crossings | 1e-8 relative |
//! | damped oscillator | x(t) vs the analytic underdamped solution | 1e-9 of x₀ |
//! | damped oscillator | energy lost vs ∫ Σcᵢ Δ̇ᵢ² dt | 1e-9 of E₀ |
//! | two free bodies | relative motion at √(k/μ); total momentum | 1e-9 of x₀; 1e-12 of |p| |
//! | spring pendulum | T + U_spring + U_gravity, 10 s, h = 0.1 ms | 1e-9 of the largest kinetic energy |
//! | damped pendulum | E₀ − E vs ∫ P_diss dt | 1e-9 of E₀ − E_end |

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use runtime::multibody::body::{BodyState, RigidBody, Wrench, derivatives};
use runtime::multibody::element::{Anchor, SpringDamper};

const G: Vector3<f64> = Vector3::new(0.0, 0.0, -9.81);

/// One classical RK4 step of ẏ = f(y) (autonomous).
fn rk4_step(f: &mut impl FnMut(&[f64], &mut [f64]), y: &mut [f64], h: f64) {
    let n = y.len();
    let (mut k1, mut k2, mut k3, mut k4) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut tmp = vec![0.0; n];
    f(y, &mut k1);
    for i in 0..n {
        tmp[i] = y[i] + 0.5 * h * k1[i];
    }
    f(&tmp, &mut k2);
    for i in 0..n {
        tmp[i] = y[i] + 0.5 * h * k2[i];
    }
    f(&tmp, &mut k3);
    for i in 0..n {
        tmp[i] = y[i] + h * k3[i];
    }
    f(&tmp, &mut k4);
    for i in 0..n {
        y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
}

fn free_body_rhs(body: RigidBody, gravity: Vector3<f64>) -> impl FnMut(&[f64], &mut [f64]) {
    move |y, dy| {
        let s = BodyState::read_from(y);
        derivatives(&body, &s, &Wrench::zero(), &gravity, dy);
    }
}

fn diag(a: f64, b: f64, c: f64) -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::new(a, b, c))
}

fn quat_norm(y: &[f64]) -> f64 {
    (y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt()
}

/// Torque-free sphere: ω constant in body axes, so q(t) = q₀ ⊗ exp(½ω t).
#[test]
fn constant_omega_rotates_as_exponential() {
    let body = RigidBody {
        mass_kg: 3.0,
        inertia_kg_m2: diag(2.0, 2.0, 2.0),
    };
    let q0 = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, 0.2, -0.5));
    let w = Vector3::new(0.9, -1.3, 2.2);
    let s0 = BodyState {
        angular_velocity_rad_s: w,
        ..BodyState::at_rest(Vector3::zeros(), q0)
    };
    let mut y = [0.0; BodyState::LEN];
    s0.write_to(&mut y);
    let mut f = free_body_rhs(body, Vector3::zeros());
    let h = 1e-3;
    let mut max_angle: f64 = 0.0;
    for step in 1..=10_000 {
        rk4_step(&mut f, &mut y, h);
        let t = step as f64 * h;
        let exact = q0 * UnitQuaternion::from_scaled_axis(w * t);
        max_angle = max_angle.max(BodyState::read_from(&y).orientation.angle_to(&exact));
    }
    let drift = (quat_norm(&y) - 1.0).abs();
    println!("constant ω: max angle error {max_angle:.2e} rad over 10 s, |q| drift {drift:.2e}");
    assert!(max_angle < 1e-9);
}

/// Integrates the symmetric top and returns max |ω − ω_exact| / |ω|.
fn symmetric_top_error(h: f64, t_end: f64) -> (f64, f64) {
    let (i1, i3) = (2.0, 3.0);
    let body = RigidBody {
        mass_kg: 1.0,
        inertia_kg_m2: diag(i1, i1, i3),
    };
    let w0 = Vector3::new(0.3, 0.1, 5.0);
    let s0 = BodyState {
        angular_velocity_rad_s: w0,
        ..BodyState::at_rest(
            Vector3::zeros(),
            UnitQuaternion::from_scaled_axis(Vector3::new(0.2, -0.1, 0.7)),
        )
    };
    let l0 = s0.angular_momentum_global(&body);
    // Euler's equations for I₁ = I₂: ω₃ constant and ω₁ + iω₂ rotates at
    // Ω = (I₃ − I₁)/I₁ ω₃ (e.g. Goldstein, Classical Mechanics, §5.6).
    let big_omega = (i3 - i1) / i1 * w0.z;
    let mut y = [0.0; BodyState::LEN];
    s0.write_to(&mut y);
    let mut f = free_body_rhs(body, Vector3::zeros());
    let steps = (t_end / h).round() as usize;
    let (mut max_err, mut max_l): (f64, f64) = (0.0, 0.0);
    for step in 1..=steps {
        rk4_step(&mut f, &mut y, h);
        let t = step as f64 * h;
        let (c, s) = ((big_omega * t).cos(), (big_omega * t).sin());
        let exact = Vector3::new(w0.x * c - w0.y * s, w0.x * s + w0.y * c, w0.z);
        let st = BodyState::read_from(&y);
        max_err = max_err.max((st.angular_velocity_rad_s - exact).norm() / w0.norm());
        max_l = max_l.max((st.angular_momentum_global(&body) - l0).norm() / l0.norm());
    }
    (max_err, max_l)
}

#[test]
fn symmetric_top_precesses_at_analytic_rate() {
    let (e1, l1) = symmetric_top_error(1e-3, 20.0);
    let (e2, _) = symmetric_top_error(5e-4, 20.0);
    let ratio = e1 / e2;
    println!(
        "symmetric top: max |ω error|/|ω| {e1:.2e} (h = 1 ms), {e2:.2e} (h = 0.5 ms), ratio {ratio:.2} (RK4: 16); global L change {l1:.2e}"
    );
    assert!(e1 < 1e-9);
    assert!(l1 < 1e-9);
    assert!((14.0..18.0).contains(&ratio), "order ratio {ratio}");
}

/// Rotation near the intermediate axis flips (Dzhanibekov effect) while the
/// global angular momentum vector and the kinetic energy stay constant.
#[test]
fn dzhanibekov_flip_conserves_momentum_and_energy() {
    let body = RigidBody {
        mass_kg: 1.0,
        inertia_kg_m2: diag(1.0, 2.0, 3.0),
    };
    let s0 = BodyState {
        angular_velocity_rad_s: Vector3::new(1e-2, 1.0, 1e-2),
        ..BodyState::at_rest(Vector3::zeros(), UnitQuaternion::identity())
    };
    let (l0, t0) = (
        s0.angular_momentum_global(&body),
        s0.kinetic_energy_j(&body),
    );
    let mut y = [0.0; BodyState::LEN];
    s0.write_to(&mut y);
    let mut f = free_body_rhs(body, Vector3::zeros());
    let h = 1e-3;
    let (mut min_w2, mut flips, mut last_sign) = (f64::INFINITY, 0, 1.0);
    let (mut dl, mut dl_norm, mut dt): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for _ in 0..40_000 {
        rk4_step(&mut f, &mut y, h);
        let s = BodyState::read_from(&y);
        let w2 = s.angular_velocity_rad_s.y;
        min_w2 = min_w2.min(w2);
        if w2.signum() != last_sign && w2.abs() > 0.5 {
            flips += 1;
            last_sign = w2.signum();
        }
        let l = s.angular_momentum_global(&body);
        dl = dl.max((l - l0).norm() / l0.norm());
        dl_norm = dl_norm.max((l.norm() - l0.norm()).abs() / l0.norm());
        dt = dt.max((s.kinetic_energy_j(&body) - t0).abs() / t0);
    }
    println!(
        "Dzhanibekov: {flips} flips in 40 s, min ω₂ {min_w2:.4}; max relative change: L vector {dl:.2e}, |L| {dl_norm:.2e}, T {dt:.2e}; |q| drift {:.2e}",
        (quat_norm(&y) - 1.0).abs()
    );
    assert!(flips >= 2, "the intermediate axis must flip (and back)");
    assert!(min_w2 < -0.99);
    assert!(dl < 1e-8 && dl_norm < 1e-8 && dt < 1e-8);
}

#[test]
fn free_fall() {
    let body = RigidBody {
        mass_kg: 5.0,
        inertia_kg_m2: diag(1.0, 2.0, 2.5),
    };
    let s0 = BodyState {
        position_m: Vector3::new(1.0, -2.0, 10.0),
        orientation: UnitQuaternion::identity(),
        velocity_m_s: Vector3::new(3.0, 1.0, 4.0),
        angular_velocity_rad_s: Vector3::new(0.5, 1.0, -0.3),
    };
    let mut y = [0.0; BodyState::LEN];
    s0.write_to(&mut y);
    let mut f = free_body_rhs(body, G);
    let h = 1e-2;
    for _ in 0..200 {
        rk4_step(&mut f, &mut y, h);
    }
    let t = 2.0;
    let s = BodyState::read_from(&y);
    let r = s0.position_m + s0.velocity_m_s * t + 0.5 * G * t * t;
    let v = s0.velocity_m_s + G * t;
    let (er, ev) = ((s.position_m - r).norm(), (s.velocity_m_s - v).norm());
    println!("free fall: position error {er:.2e} m, velocity error {ev:.2e} m/s");
    assert!(er < 1e-12 && ev < 1e-12);
}

/// A body on a spring–damper to a fixed anchor, attached at its CG, hanging
/// under gravity with preload = weight: equilibrium at the assembly point.
struct Hanging {
    body: RigidBody,
    ground: Anchor,
    spring: SpringDamper,
    /// Energy at the equilibrium (J), subtracted by [`Hanging::energy_j`].
    equilibrium_energy_j: f64,
}

impl Hanging {
    fn new(
        stiffness: [f64; 3],
        damping: [f64; 3],
        body_point_m: Vector3<f64>,
    ) -> (Self, BodyState) {
        let body = RigidBody {
            mass_kg: 100.0,
            inertia_kg_m2: diag(10.0, 12.0, 8.0),
        };
        let s0 = BodyState::at_rest(Vector3::new(0.0, 0.0, 1.0), UnitQuaternion::identity());
        let ground = Anchor::fixed(Vector3::new(0.0, 0.0, 2.0), Matrix3::identity());
        let p = s0.point_position(&body_point_m);
        let spring = SpringDamper::assembled(
            &ground,
            &Anchor::from_body(&s0),
            &ground.position_m,
            &p,
            stiffness,
            damping,
            -body.mass_kg * G,
        )
        .expect("valid element");
        let equilibrium_energy_j = s0.potential_energy_j(&body, &G);
        (
            Self {
                body,
                ground,
                spring,
                equilibrium_energy_j,
            },
            s0,
        )
    }

    /// y = [body ([`BodyState::LEN`]), ∫ P_diss dt (J)].
    fn rhs(&self, y: &[f64], dy: &mut [f64]) {
        let s = BodyState::read_from(y);
        let f = self
            .spring
            .evaluate(&self.ground, &Anchor::from_body(&s), &[]);
        let mut w_ground = Wrench::zero();
        let mut w = Wrench::zero();
        f.add_to_wrenches(
            &mut w_ground,
            &self.ground.position_m,
            &mut w,
            &s.position_m,
        );
        derivatives(&self.body, &s, &w, &G, dy);
        dy[BodyState::LEN] = self
            .spring
            .dissipated_power_w(&f.deflection_m, &f.rate_m_s, &[]);
    }

    fn energy_j(&self, y: &[f64]) -> f64 {
        let s = BodyState::read_from(y);
        let f = self
            .spring
            .evaluate(&self.ground, &Anchor::from_body(&s), &[]);
        s.kinetic_energy_j(&self.body)
            + s.potential_energy_j(&self.body, &G)
            + self.spring.potential_energy_j(&f.deflection_m, &[])
            - self.equilibrium_energy_j
    }
}

/// Undamped: each axis oscillates as x₀ cos(√(kᵢ/m) t) about the assembly
/// point (gravity balanced by the preload), and the zero crossings give the
/// analytic frequency.
#[test]
fn oscillator_frequency() {
    let k = [2e5, 3e5, 4e5];
    let (sys, mut s0) = Hanging::new(k, [0.0; 3], Vector3::zeros());
    let m = sys.body.mass_kg;
    let eq = s0.position_m;
    let x0 = Vector3::new(0.01, -0.005, 0.02);
    s0.position_m += x0;
    let mut y = [0.0; BodyState::LEN + 1];
    s0.write_to(&mut y);
    let h = 5e-5;
    let w: Vec<f64> = k.iter().map(|ki| (ki / m).sqrt()).collect();
    let (mut max_err, mut crossings) = (0.0f64, Vec::new());
    let mut prev_x = x0.x;
    for step in 1..=40_000 {
        rk4_step(&mut |y, dy| sys.rhs(y, dy), &mut y, h);
        let t = step as f64 * h;
        let x = BodyState::read_from(&y).position_m - eq;
        for i in 0..3 {
            max_err = max_err.max((x[i] - x0[i] * (w[i] * t).cos()).abs() / x0.amax());
        }
        if prev_x.signum() != x.x.signum() {
            crossings.push(t - h * x.x / (x.x - prev_x)); // linear interpolation
        }
        prev_x = x.x;
    }
    // Crossings are half a period apart; fit the mean spacing.
    let n = crossings.len() - 1;
    let measured = std::f64::consts::PI * n as f64 / (crossings[n] - crossings[0]);
    let rel = (measured - w[0]).abs() / w[0];
    println!(
        "oscillator: max |x − x₀cos ωt| / x₀ {max_err:.2e}; x frequency from {n} half periods {measured:.9} rad/s vs √(k/m) {:.9} (relative {rel:.2e})",
        w[0]
    );
    assert!(max_err < 1e-9);
    assert!(rel < 1e-8);
}

/// Damped: x(t) = e^(−ζωt) (x₀ cos ω_d t + ζω x₀/ω_d sin ω_d t),
/// ω_d = ω√(1 − ζ²), ζ = c / (2√(km)); and E₀ − E(t) = ∫ Σcᵢ Δ̇ᵢ² dt.
#[test]
fn damped_oscillator_decay() {
    let k = [2e5, 3e5, 4e5];
    let c = [500.0, 2000.0, 8000.0];
    let (sys, mut s0) = Hanging::new(k, c, Vector3::zeros());
    let m = sys.body.mass_kg;
    let eq = s0.position_m;
    let x0 = Vector3::new(0.01, -0.005, 0.02);
    s0.position_m += x0;
    let mut y = [0.0; BodyState::LEN + 1];
    s0.write_to(&mut y);
    let e0 = sys.energy_j(&y);
    let h = 1e-4;
    let (mut max_err, mut max_balance) = (0.0f64, 0.0f64);
    for step in 1..=10_000 {
        rk4_step(&mut |y, dy| sys.rhs(y, dy), &mut y, h);
        let t = step as f64 * h;
        let x = BodyState::read_from(&y).position_m - eq;
        for i in 0..3 {
            let w = (k[i] / m).sqrt();
            let zeta = c[i] / (2.0 * (k[i] * m).sqrt());
            let wd = w * (1.0 - zeta * zeta).sqrt();
            let exact = (-zeta * w * t).exp()
                * (x0[i] * (wd * t).cos() + zeta * w * x0[i] / wd * (wd * t).sin());
            max_err = max_err.max((x[i] - exact).abs() / x0.amax());
        }
        max_balance = max_balance.max((e0 - sys.energy_j(&y) - y[BodyState::LEN]).abs() / e0);
    }
    println!(
        "damped oscillator: max trajectory error / x₀ {max_err:.2e}; energy balance error / E₀ {max_balance:.2e} (E lost {:.3} of E₀)",
        y[BodyState::LEN] / e0
    );
    assert!(max_err < 1e-9);
    assert!(max_balance < 1e-9);
}

/// Two free bodies joined at their CGs: the separation oscillates at
/// √(k/μ), μ = m₁m₂/(m₁ + m₂); the total momentum is constant.
#[test]
fn two_free_bodies_reduced_mass() {
    let b1 = RigidBody {
        mass_kg: 300.0,
        inertia_kg_m2: diag(30.0, 40.0, 50.0),
    };
    let b2 = RigidBody {
        mass_kg: 700.0,
        inertia_kg_m2: diag(70.0, 80.0, 60.0),
    };
    let s1 = BodyState::at_rest(Vector3::zeros(), UnitQuaternion::identity());
    let s2 = BodyState::at_rest(Vector3::new(1.0, 0.0, 0.0), UnitQuaternion::identity());
    let k = 1e6;
    let spring = SpringDamper::assembled(
        &Anchor::from_body(&s1),
        &Anchor::from_body(&s2),
        &s1.position_m,
        &s2.position_m,
        [k, 2.0 * k, 3.0 * k],
        [0.0; 3],
        Vector3::zeros(),
    )
    .expect("valid element");
    let x0 = 0.01;
    let mut y = [0.0; 2 * BodyState::LEN];
    s1.write_to(&mut y[..BodyState::LEN]);
    BodyState {
        position_m: s2.position_m + Vector3::new(x0, 0.0, 0.0),
        velocity_m_s: Vector3::new(0.0, 0.0, 0.3), // drifts the pair, p = 210 N·s
        ..s2
    }
    .write_to(&mut y[BodyState::LEN..]);
    let momentum = |y: &[f64]| {
        b1.mass_kg * BodyState::read_from(&y[..BodyState::LEN]).velocity_m_s
            + b2.mass_kg * BodyState::read_from(&y[BodyState::LEN..]).velocity_m_s
    };
    let p0 = momentum(&y);
    let mut rhs = |y: &[f64], dy: &mut [f64]| {
        let (a, b) = (
            BodyState::read_from(&y[..BodyState::LEN]),
            BodyState::read_from(&y[BodyState::LEN..]),
        );
        let f = spring.evaluate(&Anchor::from_body(&a), &Anchor::from_body(&b), &[]);
        let (mut wa, mut wb) = (Wrench::zero(), Wrench::zero());
        f.add_to_wrenches(&mut wa, &a.position_m, &mut wb, &b.position_m);
        derivatives(&b1, &a, &wa, &Vector3::zeros(), &mut dy[..BodyState::LEN]);
        derivatives(&b2, &b, &wb, &Vector3::zeros(), &mut dy[BodyState::LEN..]);
    };
    let mu = b1.mass_kg * b2.mass_kg / (b1.mass_kg + b2.mass_kg);
    let w = (k / mu).sqrt();
    let h = 2e-5;
    let (mut max_err, mut max_dp) = (0.0f64, 0.0f64);
    for step in 1..=20_000 {
        rk4_step(&mut rhs, &mut y, h);
        let t = step as f64 * h;
        let sep = BodyState::read_from(&y[BodyState::LEN..]).position_m.x
            - BodyState::read_from(&y[..BodyState::LEN]).position_m.x;
        max_err = max_err.max((sep - 1.0 - x0 * (w * t).cos()).abs() / x0);
        max_dp = max_dp.max((momentum(&y) - p0).norm());
    }
    println!(
        "two bodies: ω = √(k/μ) = {w:.4} rad/s, max separation error / x₀ {max_err:.2e}, momentum change {max_dp:.2e} N·s"
    );
    assert!(max_err < 1e-9);
    assert!(max_dp < 1e-12 * p0.norm());
}

/// Spring pendulum: the body hangs from a fixed anchor by an anisotropic
/// spring attached 0.4 m above its CG (preload = weight), and sways, rolls,
/// bounces and yaws. Anchor a (the ground) does not rotate, so
/// T + U_spring + U_gravity is exactly conserved by the model.
#[test]
fn spring_pendulum_conserves_energy() {
    let (sys, mut s0) = Hanging::new([2e4, 5e4, 1e5], [0.0; 3], Vector3::new(0.0, 0.0, 0.4));
    s0.position_m += Vector3::new(0.03, -0.02, 0.01);
    s0.orientation = UnitQuaternion::from_scaled_axis(Vector3::new(0.1, -0.05, 0.2));
    s0.velocity_m_s = Vector3::new(0.1, 0.2, -0.1);
    s0.angular_velocity_rad_s = Vector3::new(0.5, -0.3, 1.0);
    let mut y = [0.0; BodyState::LEN + 1];
    s0.write_to(&mut y);
    let e0 = sys.energy_j(&y);
    let ke0 = s0.kinetic_energy_j(&sys.body);
    let h = 1e-4;
    let mut max_de = 0.0f64;
    let mut max_ke = ke0;
    for _ in 0..100_000 {
        rk4_step(&mut |y, dy| sys.rhs(y, dy), &mut y, h);
        max_de = max_de.max((sys.energy_j(&y) - e0).abs());
        max_ke = max_ke.max(BodyState::read_from(&y).kinetic_energy_j(&sys.body));
    }
    let rel = max_de / max_ke;
    println!(
        "spring pendulum: E₀ = {e0:.6} J, max kinetic {max_ke:.4} J, max |E − E₀| {max_de:.2e} J ({rel:.2e} of the max kinetic energy) over 10 s; |q| drift {:.2e}",
        (quat_norm(&y) - 1.0).abs()
    );
    assert!(rel < 1e-9);
}

/// The same pendulum with dampers: E₀ − E(t) = ∫ P_diss dt.
#[test]
fn damped_pendulum_energy_balance() {
    let (sys, mut s0) = Hanging::new(
        [2e4, 5e4, 1e5],
        [300.0, 500.0, 800.0],
        Vector3::new(0.0, 0.0, 0.4),
    );
    s0.position_m += Vector3::new(0.03, -0.02, 0.01);
    s0.angular_velocity_rad_s = Vector3::new(0.5, -0.3, 1.0);
    let mut y = [0.0; BodyState::LEN + 1];
    s0.write_to(&mut y);
    let e0 = sys.energy_j(&y);
    let h = 1e-4;
    let mut max_bal = 0.0f64;
    for _ in 0..50_000 {
        rk4_step(&mut |y, dy| sys.rhs(y, dy), &mut y, h);
        max_bal = max_bal.max((e0 - sys.energy_j(&y) - y[BodyState::LEN]).abs());
    }
    let lost = e0 - sys.energy_j(&y);
    println!(
        "damped pendulum: lost {lost:.4} J of {e0:.4} J in 5 s; max |E₀ − E − ∫P dt| {max_bal:.2e} J ({:.2e} of the loss)",
        max_bal / lost
    );
    assert!(lost > 0.5 * e0);
    assert!(max_bal < 1e-9 * lost);
}
