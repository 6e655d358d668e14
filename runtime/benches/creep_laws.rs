//! Criterion bench: one evaluation of each creep law (docs/reference/07-contact-forces.md §7.3) for a
//! typical tread contact (N = 80 kN, a = 6.65 mm, b = 5.0 mm — S1002-like
//! wheel of r = 0.46 m on a 0.3 m rail head — G = 80.8 GPa, ν = 0.3,
//! μ = 0.3, V = 30 m/s) at moderate combined creepages (ξ = 1e-3,
//! η = −1.5e-3, φ = 0.2 1/m, partly saturated); plus the Kalker
//! coefficients alone, the Hertz shape they need, FASTSIM at three
//! discretisations (its default included, and with the ellipsoidal bound)
//! and FaStrip on FASTSIM's default grid.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use runtime::forces::creep::{
    CreepInput, CreepLaw, FastripParams, FastsimParams, PolachParams, kalker_coefficients,
};
use runtime::forces::hertz::HertzShape;

fn input() -> CreepInput {
    CreepInput {
        xi: 1e-3,
        eta: -1.5e-3,
        phi_1_m: 0.2,
        normal_force_n: 80e3,
        a_m: 6.65e-3,
        b_m: 5.0e-3,
        friction_coefficient: 0.3,
        rolling_speed_m_s: 30.0,
        shear_modulus_pa: 80.77e9,
        poisson: 0.3,
    }
}

fn bench(c: &mut Criterion) {
    let i = input();
    c.bench_function("kalker_coefficients", |b| {
        b.iter(|| kalker_coefficients(black_box(i.a_m / i.b_m), black_box(0.3)))
    });
    c.bench_function("hertz_shape", |b| {
        b.iter(|| HertzShape::new(black_box(1.087), black_box(1.667)))
    });
    let fastsim_default = FastsimParams::default();
    let laws = [
        ("creep_kalker_linear".to_string(), CreepLaw::KalkerLinear),
        ("creep_heuristic".to_string(), CreepLaw::Heuristic),
        (
            "creep_polach_1999".to_string(),
            CreepLaw::Polach(PolachParams::default()),
        ),
        (
            "creep_polach_dry_2005".to_string(),
            CreepLaw::Polach(PolachParams::dry_2005()),
        ),
        (
            format!(
                "creep_fastsim_default_{}x{}",
                fastsim_default.strips, fastsim_default.elements_per_strip
            ),
            CreepLaw::Fastsim(fastsim_default),
        ),
        (
            format!(
                "creep_fastsim_ellipsoidal_{}x{}",
                fastsim_default.strips, fastsim_default.elements_per_strip
            ),
            CreepLaw::Fastsim(FastsimParams::ellipsoidal(
                fastsim_default.strips,
                fastsim_default.elements_per_strip,
            )),
        ),
        (
            format!(
                "creep_fastrip_default_{}x{}",
                FastripParams::default().strips,
                FastripParams::default().elements_per_strip
            ),
            CreepLaw::Fastrip(FastripParams::default()),
        ),
        (
            "creep_fastsim_10x10".to_string(),
            CreepLaw::Fastsim(FastsimParams {
                strips: 10,
                elements_per_strip: 10,
                ..fastsim_default
            }),
        ),
        (
            "creep_fastsim_50x50".to_string(),
            CreepLaw::Fastsim(FastsimParams {
                strips: 50,
                elements_per_strip: 50,
                ..fastsim_default
            }),
        ),
    ];
    for (name, law) in laws {
        law.validate().expect("bench law parameters");
        c.bench_function(&name, |b| b.iter(|| law.evaluate(black_box(&i))));
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
