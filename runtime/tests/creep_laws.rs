//! Cross-law checks of the creep laws through the public API (docs/reference/07-contact-forces.md §7.3):
//! small-creepage limits against Kalker's linear law, Polach's 2005 initial
//! slope, saturation |F| ≤ μN, odd symmetry, slip-velocity dependent friction
//! and the shape of the creep curves.
//!
//! Contact used throughout (a representative wheel–rail contact): N = 80 kN,
//! G = 80.8 GPa, ν = 0.28, μ = 0.3, V = 30 m/s, and three ellipses with
//! a/b = 1.5 (a = 6 mm, b = 4 mm), 0.3 (3 mm × 10 mm) and 3 (9 mm × 3 mm).
//! Run with `--nocapture` to see the measured figures.

use runtime::forces::creep::{
    CreepForces, CreepInput, CreepLaw, FastripParams, FastsimParams, PolachParams,
    SlipVelocityFriction, kalker_coefficients,
};

const N: f64 = 80e3;
const G: f64 = 80.8e9;
const NU: f64 = 0.28;
const MU: f64 = 0.3;
const V: f64 = 30.0;

/// (a, b) in m: a/b = 1.5, 0.3, 3.
const ELLIPSES: [(f64, f64); 3] = [(6e-3, 4e-3), (3e-3, 10e-3), (9e-3, 3e-3)];

fn input(a: f64, b: f64, xi: f64, eta: f64, phi: f64) -> CreepInput {
    CreepInput {
        xi,
        eta,
        phi_1_m: phi,
        normal_force_n: N,
        a_m: a,
        b_m: b,
        friction_coefficient: MU,
        rolling_speed_m_s: V,
        shear_modulus_pa: G,
        poisson: NU,
    }
}

fn eval(law: &CreepLaw, i: &CreepInput) -> CreepForces {
    law.validate().expect("law parameters");
    law.evaluate(i).expect("valid input")
}

fn kalker(i: &CreepInput) -> CreepForces {
    eval(&CreepLaw::KalkerLinear, i)
}

fn polach_1999() -> CreepLaw {
    CreepLaw::Polach(PolachParams::default())
}

fn fastsim() -> CreepLaw {
    CreepLaw::Fastsim(FastsimParams::default())
}

fn fastrip() -> CreepLaw {
    CreepLaw::Fastrip(FastripParams::default())
}

/// Every law with its label; the saturating ones are all but the first.
fn all_laws() -> Vec<(&'static str, CreepLaw)> {
    vec![
        ("kalker", CreepLaw::KalkerLinear),
        ("heuristic", CreepLaw::Heuristic),
        ("polach-1999", polach_1999()),
        (
            "polach-dry-2005",
            CreepLaw::Polach(PolachParams::dry_2005()),
        ),
        (
            "polach-wet-2005",
            CreepLaw::Polach(PolachParams::wet_2005()),
        ),
        ("fastsim", fastsim()),
        ("fastrip", fastrip()),
    ]
}

/// A creepage direction of the small-creepage study: base (ξ, η, φ) and the
/// force component compared.
#[derive(Clone, Copy, Debug)]
enum Component {
    Fx,
    Fy,
}

fn component(f: &CreepForces, c: Component) -> f64 {
    match c {
        Component::Fx => f.fx_n,
        Component::Fy => f.fy_n,
    }
}

/// Relative difference of `law` to Kalker linear on `c` for the creepages
/// (ξ, η, φ) scaled by 10⁻¹ … 10⁻⁴; also checks the sign agrees.
fn relative_differences(
    law: &CreepLaw,
    a: f64,
    b: f64,
    base: (f64, f64, f64),
    c: Component,
) -> Vec<f64> {
    (1..=4)
        .map(|k| {
            let scale = 10f64.powi(-k);
            let i = input(a, b, base.0 * scale, base.1 * scale, base.2 * scale);
            let want = component(&kalker(&i), c);
            let got = component(&eval(law, &i), c);
            assert!(want != 0.0);
            assert_eq!(
                got.signum(),
                want.signum(),
                "{law:?} a/b={} {base:?}·{scale}: sign of {c:?}",
                a / b
            );
            (got - want).abs() / want.abs()
        })
        .collect()
}

/// `[1.23e-4, …]` for the measured-figure printouts.
fn sci(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|x| format!("{x:.2e}")).collect();
    format!("[{}]", parts.join(", "))
}

/// Base creepages of the small-creepage study for an ellipse with semi-axis
/// a: pure ξ, pure η, pure spin (φ a = 3·10⁻³), and combinations the laws
/// should also reproduce (Polach: only pairs with ξ = 0, module docs of
/// `polach.rs`).
fn pure_cases(a: f64) -> Vec<(&'static str, (f64, f64, f64), Component)> {
    let phi = 3e-3 / a;
    vec![
        ("pure xi", (2e-3, 0.0, 0.0), Component::Fx),
        ("pure -eta", (0.0, -2e-3, 0.0), Component::Fy),
        ("pure spin", (0.0, 0.0, phi), Component::Fy),
        ("eta+spin same sign", (0.0, 1e-3, phi), Component::Fy),
        ("eta+spin opposed", (0.0, 2e-3, -0.5 * phi), Component::Fy),
    ]
}

/// Heuristic and Polach (kA = kS = 1) tend to Kalker's linear law as the
/// creepage → 0: the relative difference falls with every decade and is
/// below 1e-3 at the smallest creepage (10⁻⁴ of the base).
#[test]
fn heuristic_and_polach_tend_to_kalker_linear() {
    for (name, law) in [
        ("heuristic", CreepLaw::Heuristic),
        ("polach", polach_1999()),
    ] {
        for (a, b) in ELLIPSES {
            for (case, base, c) in pure_cases(a) {
                let d = relative_differences(&law, a, b, base, c);
                eprintln!("{name} a/b={:.1} {case}: rel. diff {}", a / b, sci(&d));
                for w in d.windows(2) {
                    assert!(
                        w[1] < w[0] || w[1] < 1e-12,
                        "{name} a/b={} {case}: not decreasing {d:?}",
                        a / b
                    );
                }
                assert!(d[3] < 1e-3, "{name} a/b={} {case}: {d:?}", a / b);
            }
        }
    }
    // The Heuristic law saturates the Kalker resultant, spin included, so it
    // also tends to Kalker for all three creepages together.
    for (a, b) in ELLIPSES {
        let base = (1e-3, -1.5e-3, 2e-3 / a);
        let dx = relative_differences(&CreepLaw::Heuristic, a, b, base, Component::Fx);
        let dy = relative_differences(&CreepLaw::Heuristic, a, b, base, Component::Fy);
        assert!(dx[3] < 1e-3 && dy[3] < 1e-3, "{dx:?} {dy:?}");
    }
}

/// Polach's spin part alone (pure spin): → −G (ab)^1.5 c23 φ, the spin term
/// of Kalker's Fy, same sign. Tolerance: 1e-6 relative at φ a = 3·10⁻⁷.
#[test]
fn polach_pure_spin_tends_to_kalker_spin_term() {
    for (a, b) in ELLIPSES {
        let c = kalker_coefficients(a / b, NU).unwrap();
        for phi in [3e-7 / a, -3e-7 / a] {
            let f = eval(&polach_1999(), &input(a, b, 0.0, 0.0, phi));
            let want = -G * (a * b).powf(1.5) * c.c23 * phi;
            let rel = (f.fy_n - want).abs() / want.abs();
            eprintln!("polach pure spin a/b={:.1}: rel. diff {rel:.2e}", a / b);
            assert!(rel < 1e-6, "a/b={} {rel}", a / b);
            assert_eq!(f.fx_n, 0.0);
            assert_eq!(f.mz_nm, 0.0);
        }
    }
}

/// Polach as published (module docs of `polach.rs`): with ξ and η both
/// non-zero the small-creepage force lies along the creepage with the
/// combined coefficient c_jj = √((c11 ξ/s)² + (c22 η/s)²), not Kalker's
/// (c11 ξ, c22 η); with ξ and φ both non-zero the spin force is Kalker's
/// times |s_yC|/s_C. This pins the published behaviour and measures the
/// difference to Kalker.
#[test]
fn polach_combined_creepage_limit_uses_c_jj() {
    for (a, b) in ELLIPSES {
        let c = kalker_coefficients(a / b, NU).unwrap();
        let (xi, eta): (f64, f64) = (1e-8, -1e-8);
        let s = xi.hypot(eta);
        let c_jj = (c.c11 * xi / s).hypot(c.c22 * eta / s);
        let f = eval(&polach_1999(), &input(a, b, xi, eta, 0.0));
        let gab = G * a * b;
        assert!((f.fx_n / (-gab * c_jj * xi) - 1.0).abs() < 1e-8);
        assert!((f.fy_n / (-gab * c_jj * eta) - 1.0).abs() < 1e-8);
        eprintln!(
            "polach xi = -eta a/b={:.1}: Fx/Kalker = {:.4}, Fy/Kalker = {:.4}",
            a / b,
            c_jj / c.c11,
            c_jj / c.c22
        );
        // ξ with spin: the spin force is Kalker's times |s_yC|/s_C, here
        // s_yC = φa = ξ, so 1/√2.
        let phi = xi / a;
        let f = eval(&polach_1999(), &input(a, b, xi, 0.0, phi));
        let kalker_spin = -G * (a * b).powf(1.5) * c.c23 * phi;
        let ratio = f.fy_n / kalker_spin;
        assert!((ratio * 2f64.sqrt() - 1.0).abs() < 1e-8, "{ratio}");
        assert!((f.fx_n / (-gab * c.c11 * xi) - 1.0).abs() < 1e-8);
    }
}

/// FASTSIM (default discretisation) against Kalker's linear law for pure ξ,
/// pure η and pure spin (Fx, Fy; its spin moment differs by design): within
/// 2 % at the smallest creepage, same signs.
#[test]
fn fastsim_tends_to_kalker_linear() {
    for (a, b) in ELLIPSES {
        for (case, base, c) in pure_cases(a).into_iter().take(3) {
            let d = relative_differences(&fastsim(), a, b, base, c);
            eprintln!("fastsim a/b={:.1} {case}: rel. diff {}", a / b, sci(&d));
            assert!(d[3] < 0.02, "a/b={} {case}: {d:?}", a / b);
        }
    }
}

/// FaStrip tends to Kalker's linear law for pure ξ, pure η and pure spin
/// (Fx, Fy; its spin moment is the strip theory's): within 2e-3 at the
/// smallest creepage, same signs. The zone integrals are exact, so pure ξ
/// and η come within 3e-5; with spin the trailing sliver of each strip
/// takes its direction from FASTSIM's grid (measured ≤ 6.7e-4).
#[test]
fn fastrip_tends_to_kalker_linear() {
    for (a, b) in ELLIPSES {
        for (case, base, c) in pure_cases(a).into_iter().take(3) {
            let d = relative_differences(&fastrip(), a, b, base, c);
            eprintln!("fastrip a/b={:.1} {case}: rel. diff {}", a / b, sci(&d));
            assert!(d[3] < 2e-3, "a/b={} {case}: {d:?}", a / b);
        }
    }
}

/// Polach 2005: the initial slope is (kA + kS)/2 times Kalker's, with or
/// without slip-velocity dependent friction (μ(w) → μ0 as w → 0 and the
/// slope does not depend on μ). Tolerance 1e-6 relative at creepage 10⁻⁸.
#[test]
fn polach_2005_factors_scale_the_initial_slope() {
    let friction = Some(SlipVelocityFriction {
        a_ratio: 0.4,
        b_s_m: 0.6,
    });
    let params = [
        PolachParams::dry_2005(),
        PolachParams::wet_2005(),
        PolachParams {
            k_a: 0.7,
            k_s: 0.7,
            slip_friction: None,
        },
        PolachParams {
            k_a: 0.8,
            k_s: 0.2,
            slip_friction: friction,
        },
    ];
    for p in params {
        let factor = 0.5 * (p.k_a + p.k_s);
        assert_eq!(p.initial_slope_factor(), factor);
        for (a, b) in ELLIPSES {
            for (base, c) in [((1e-8, 0.0), Component::Fx), ((0.0, 1e-8), Component::Fy)] {
                let i = input(a, b, base.0, base.1, 0.0);
                let ratio =
                    component(&eval(&CreepLaw::Polach(p), &i), c) / component(&kalker(&i), c);
                assert!(
                    (ratio / factor - 1.0).abs() < 1e-6,
                    "{p:?} a/b={} {c:?}: {ratio} vs {factor}",
                    a / b
                );
            }
        }
    }
}

/// Creepage values of the saturation grid (ξ, η and φ·a each).
fn grid_values() -> Vec<f64> {
    let mut v = vec![0.0];
    for m in [1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0] {
        v.push(m);
        v.push(-m);
    }
    v
}

/// |(Fx, Fy)| ≤ μN (1 + 1e-12) for every saturating law over a grid of
/// creepages up to 1 (ξ, η, φa and their signs), three ellipses.
#[test]
fn saturating_laws_never_exceed_mu_n() {
    let values = grid_values();
    let limit = MU * N * (1.0 + 1e-12);
    for (name, law) in all_laws().into_iter().skip(1) {
        let mut worst: f64 = 0.0;
        for (a, b) in ELLIPSES {
            for &xi in &values {
                for &eta in &values {
                    for &phi_a in &values {
                        let f = eval(&law, &input(a, b, xi, eta, phi_a / a));
                        let t = f.tangential_n();
                        assert!(
                            t <= limit && t.is_finite(),
                            "{name} a/b={} ({xi}, {eta}, {phi_a}/a): {t} > muN",
                            a / b
                        );
                        worst = worst.max(t / (MU * N));
                    }
                }
            }
        }
        eprintln!("{name}: max |F|/muN over the grid = {worst:.15}");
    }
}

/// At large creepage (no spin) the saturating laws approach μN.
#[test]
fn large_creepage_approaches_mu_n() {
    let cases = [(1.0, 0.0), (0.0, -1.0), (0.7, 0.7), (-0.3, 0.2)];
    for (name, law) in [
        ("heuristic", CreepLaw::Heuristic),
        ("polach", polach_1999()),
        ("fastsim", fastsim()),
        ("fastrip", fastrip()),
    ] {
        for (a, b) in ELLIPSES {
            for (xi, eta) in cases {
                let f = eval(&law, &input(a, b, xi, eta, 0.0));
                let r = f.tangential_n() / (MU * N);
                assert!(
                    r > 0.99 && r <= 1.0 + 1e-12,
                    "{name} a/b={} ({xi}, {eta}): {r}",
                    a / b
                );
                // Along the creepage, opposing it.
                assert!(f.fx_n * xi <= 0.0 && f.fy_n * eta <= 0.0);
            }
        }
    }
}

/// Odd symmetry: (−ξ, −η, −φ) → (−Fx, −Fy, −Mz) for every law, to 1e-12
/// relative (absolute floor 1e-9 N, N·m).
#[test]
fn every_law_is_odd() {
    let cases = [
        (1e-3, 0.0, 0.0),
        (0.0, 2e-3, 0.0),
        (0.0, 0.0, 0.5),
        (2e-3, -1e-3, 0.3),
        (-5e-3, 3e-3, -2.0),
        (0.05, 0.02, 1.0),
        (0.0, 4e-3, -0.4),
        (0.3, -0.5, 10.0),
    ];
    for (name, law) in all_laws() {
        for (a, b) in ELLIPSES {
            for (xi, eta, phi) in cases {
                let p = eval(&law, &input(a, b, xi, eta, phi));
                let m = eval(&law, &input(a, b, -xi, -eta, -phi));
                for (u, v, what) in [
                    (p.fx_n, m.fx_n, "Fx"),
                    (p.fy_n, m.fy_n, "Fy"),
                    (p.mz_nm, m.mz_nm, "Mz"),
                ] {
                    let tol = 1e-12 * u.abs().max(v.abs()) + 1e-9;
                    assert!(
                        (u + v).abs() <= tol,
                        "{name} a/b={} ({xi}, {eta}, {phi}) {what}: {u} vs {v}",
                        a / b
                    );
                }
            }
        }
    }
}

/// μ = 0 gives no force for the saturating laws.
#[test]
fn zero_friction_gives_zero_force() {
    for (name, law) in all_laws().into_iter().skip(1) {
        let mut i = input(6e-3, 4e-3, 0.01, -0.02, 1.0);
        i.friction_coefficient = 0.0;
        let f = eval(&law, &i);
        assert_eq!(f.tangential_n(), 0.0, "{name}");
        assert_eq!(f.mz_nm, 0.0, "{name}");
    }
}

/// Polach 2005 dry preset (μ0 = 0.55 as the preset advises), pure ξ = 0.5:
/// the force equals Polach's formula evaluated here independently,
/// F = 2Nμ/π [kA ε/(1 + (kA ε)²) + atan(kS ε)], ε = π G a b c11 ξ/(4Nμ),
/// μ = μ0[(1 − A)e^(−B V ξ) + A] (to 1e-12), and falls with the rolling
/// speed (w = V ξ grows) toward A μ0 N.
#[test]
fn slip_velocity_friction_falls_with_speed() {
    let p = PolachParams::dry_2005();
    let mu0 = PolachParams::DRY_2005_MU0;
    let fr = p.slip_friction.unwrap();
    let law = CreepLaw::Polach(p);
    let xi = 0.5;
    for (a, b) in ELLIPSES {
        let c11 = kalker_coefficients(a / b, NU).unwrap().c11;
        let mut last = f64::INFINITY;
        let mut ratios = Vec::new();
        for v in [0.0, 1.0, 3.0, 10.0, 30.0, 100.0, 1000.0] {
            let mut i = input(a, b, xi, 0.0, 0.0);
            i.friction_coefficient = mu0;
            i.rolling_speed_m_s = v;
            let f = eval(&law, &i);
            let mu = mu0 * ((1.0 - fr.a_ratio) * (-fr.b_s_m * v * xi).exp() + fr.a_ratio);
            let eps = std::f64::consts::PI * G * a * b * c11 * xi / (4.0 * N * mu);
            let ka_eps = p.k_a * eps;
            let want = 2.0 * N * mu / std::f64::consts::PI
                * (ka_eps / (1.0 + ka_eps * ka_eps) + (p.k_s * eps).atan());
            assert!(
                (-f.fx_n / want - 1.0).abs() < 1e-12,
                "a/b={} V={v}: {} vs {want}",
                a / b,
                -f.fx_n
            );
            assert_eq!(f.fy_n, 0.0);
            let t = f.tangential_n();
            assert!(t < last, "a/b={} V={v}: {t} !< {last}", a / b);
            last = t;
            ratios.push(t / (mu0 * N));
        }
        eprintln!("dry-2005 a/b={:.1} |F|/mu0N vs V: {ratios:.4?}", a / b);
        // V = 0: μ = μ0, close to saturation (kS = 0.4 approaches it slowly).
        assert!(ratios[0] > 0.98 && ratios[0] < 1.0);
        // V = 1000 m/s (w = 500 m/s): μ = A μ0 to 1e-100; F within 1 %.
        let end = ratios.last().unwrap() / fr.a_ratio;
        assert!(end > 0.99 && end <= 1.0, "{end}");
    }
}

/// With slip-velocity friction, V → 0 gives the constant-friction law.
#[test]
fn slip_velocity_friction_at_zero_speed_is_constant_friction() {
    let dry = PolachParams::dry_2005();
    let constant = PolachParams {
        slip_friction: None,
        ..dry
    };
    for (xi, eta, phi) in [(0.01, 0.0, 0.0), (0.1, -0.05, 2.0), (0.0, 0.0, 1.0)] {
        let mut i = input(6e-3, 4e-3, xi, eta, phi);
        i.rolling_speed_m_s = 0.0;
        assert_eq!(
            eval(&CreepLaw::Polach(dry), &i),
            eval(&CreepLaw::Polach(constant), &i)
        );
    }
}

/// ξ values 0 … 1: fine near the origin, then geometric.
fn xi_sweep() -> Vec<f64> {
    let mut v: Vec<f64> = (0..=400).map(|k| k as f64 * 2.5e-5).collect();
    let mut x = 0.0101;
    while x <= 1.0 {
        v.push(x);
        x *= 1.02;
    }
    v
}

/// Polach 1999 creep curves in pure ξ (and pure η) never fall: |F| is
/// non-decreasing (kA = kS = 1: dF/dε = (4Qμ/π)/(1 + ε²)² > 0).
#[test]
fn polach_1999_creep_curve_is_monotone() {
    for (a, b) in ELLIPSES {
        for lateral in [false, true] {
            let mut last = 0.0;
            for x in xi_sweep() {
                let i = if lateral {
                    input(a, b, 0.0, x, 0.0)
                } else {
                    input(a, b, x, 0.0, 0.0)
                };
                let f = eval(&polach_1999(), &i);
                let m = f.tangential_n();
                assert!(m >= last, "a/b={} x={x}: {m} < {last}", a / b);
                last = m;
            }
            assert!(last > 0.999 * MU * N);
        }
    }
}

/// Polach 2005 presets at V = 30 m/s (μ0 as advised): the creep curve in ξ
/// rises to a maximum, then falls (falling friction), ending below 90 % of
/// the maximum at ξ = 0.2.
#[test]
fn polach_2005_creep_curve_has_a_maximum_then_falls() {
    let presets = [
        (PolachParams::dry_2005(), PolachParams::DRY_2005_MU0),
        (PolachParams::wet_2005(), PolachParams::WET_2005_MU0),
    ];
    for (p, mu0) in presets {
        for (a, b) in ELLIPSES {
            let curve: Vec<(f64, f64)> = (1..=2000)
                .map(|k| {
                    let xi = k as f64 * 1e-4;
                    let mut i = input(a, b, xi, 0.0, 0.0);
                    i.friction_coefficient = mu0;
                    (xi, -eval(&CreepLaw::Polach(p), &i).fx_n / (mu0 * N))
                })
                .collect();
            let (peak, &(xi_peak, f_peak)) = curve
                .iter()
                .enumerate()
                .max_by(|x, y| x.1.1.total_cmp(&y.1.1))
                .unwrap();
            let f_end = curve.last().unwrap().1;
            eprintln!(
                "{p:?} a/b={:.1}: peak {f_peak:.4} muN at xi = {xi_peak}, {f_end:.4} at 0.2",
                a / b
            );
            assert!(peak > 0 && peak < curve.len() - 1);
            assert!(curve[..=peak].windows(2).all(|w| w[1].1 > w[0].1));
            assert!(curve[peak..].windows(2).all(|w| w[1].1 < w[0].1));
            assert!(f_end < 0.9 * f_peak);
        }
    }
}

/// Parameter rules of Polach's law through [`CreepLaw::validate`].
#[test]
fn polach_parameters_are_validated() {
    for name in PolachParams::PRESET_NAMES {
        let (p, _) = PolachParams::preset(name).unwrap();
        CreepLaw::Polach(p).validate().unwrap();
    }
    let bad = [
        PolachParams {
            k_a: 0.3,
            k_s: 0.5,
            slip_friction: None,
        },
        PolachParams {
            k_a: 1.5,
            k_s: 1.0,
            slip_friction: None,
        },
        PolachParams {
            k_a: 1.0,
            k_s: -0.1,
            slip_friction: None,
        },
        PolachParams {
            slip_friction: Some(SlipVelocityFriction {
                a_ratio: -0.1,
                b_s_m: 0.6,
            }),
            ..PolachParams::default()
        },
        PolachParams {
            slip_friction: Some(SlipVelocityFriction {
                a_ratio: 0.4,
                b_s_m: f64::NAN,
            }),
            ..PolachParams::default()
        },
    ];
    for p in bad {
        let law = CreepLaw::Polach(p);
        let e = law.validate().unwrap_err();
        assert!(e.to_string().contains("Polach"), "{e}");
        // Evaluating with unchecked parameters is an error too, not NaN.
        let e2 = law.evaluate(&input(6e-3, 4e-3, 0.1, 0.0, 0.0)).unwrap_err();
        assert_eq!(e.to_string(), e2.to_string());
    }
}
