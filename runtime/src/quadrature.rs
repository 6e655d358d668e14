//! Gauss–Legendre quadrature (Abramowitz & Stegun, *Handbook of Mathematical
//! Functions*, Table 25.4: 8-point nodes and weights on [−1, 1]).

/// Positive nodes of the 8-point rule (the rule is symmetric).
const NODES_8: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
/// Weights belonging to [`NODES_8`].
const WEIGHTS_8: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// ∫ₐᵇ f(x) dx by the 8-point Gauss–Legendre rule (exact for polynomials of
/// degree ≤ 15).
#[inline]
pub fn gauss_legendre_8(a: f64, b: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
    let half = 0.5 * (b - a);
    let mid = 0.5 * (a + b);
    let mut sum = 0.0;
    for (x, w) in NODES_8.iter().zip(WEIGHTS_8) {
        sum += w * (f(mid - half * x) + f(mid + half * x));
    }
    sum * half
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_sum_to_two() {
        let s: f64 = 2.0 * WEIGHTS_8.iter().sum::<f64>();
        assert!((s - 2.0).abs() < 1e-15);
    }

    #[test]
    fn exact_for_degree_15() {
        let v = gauss_legendre_8(-0.3, 1.7, |x| x.powi(15) - 2.0 * x.powi(7) + 1.0);
        let prim = |x: f64| x.powi(16) / 16.0 - x.powi(8) / 4.0 + x;
        let exact = prim(1.7) - prim(-0.3);
        assert!((v - exact).abs() < 1e-12 * exact.abs());
    }

    #[test]
    fn smooth_function() {
        let v = gauss_legendre_8(0.0, std::f64::consts::PI, f64::sin);
        assert!((v - 2.0).abs() < 1e-12);
    }
}
