//! Solve of a 4×4 linear system by LU decomposition with partial (row)
//! pivoting, unrolled on fixed-size arrays for the Newton steps of the
//! contact equations (four unknowns, docs/reference/06-contact-detection.md §6).
//!
//! It performs exactly the floating-point operations of nalgebra's
//! `Matrix4::lu().solve(b)`, in the same order (pivot = first row of largest
//! |a| in the column, multipliers scaled by the pivot's reciprocal, row
//! updates `a_rk ← (−a_ik)·l_r + a_rk`, unit lower then upper triangular
//! substitution), so its results are bit-identical to it (checked by the
//! tests below); it only avoids the generic code's permutation sequence,
//! views and loops over dynamic ranges. The factors are kept ([`Lu4`]) to
//! solve again with another right-hand side. It works on the matrix's own
//! column-major storage (no transposed copy): the multipliers, the column
//! updates and both substitutions then read and write whole columns.

use nalgebra::{Matrix4, Vector4};

/// `x` with `a x = b`, or `None` when `a` is singular (a zero pivot in U),
/// as nalgebra's `LU::solve` (the tests' reference form).
#[cfg(test)]
fn solve(a: &Matrix4<f64>, b: &Vector4<f64>) -> Option<Vector4<f64>> {
    let mut lu = Lu4::ZERO;
    lu.factor_solve(a, b)
}

/// The LU factors of a 4×4 matrix with the row swaps made, kept to solve
/// again with another right-hand side (a Newton step's factors reused by
/// the next solve's predictor, [`super::predictor`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Lu4 {
    /// m[c][r]: column c, row r (nalgebra's storage): L's multipliers below
    /// the diagonal, U on and above it.
    m: [[f64; 4]; 4],
    /// The row swapped with row I at elimination step I.
    swaps: [u8; 4],
}

impl Lu4 {
    /// Storage to factor into.
    pub(crate) const ZERO: Self = Self {
        m: [[0.0; 4]; 4],
        swaps: [0, 1, 2, 3],
    };

    /// Factor `a` in place (the storage is reused, nothing is moved) and
    /// solve `a x = b` with it: the row swaps applied to `b` as they are
    /// made (before any substitution, as nalgebra's permutation sequence
    /// applies them), then the two substitutions. `None` when `a` is
    /// singular (the factors are then not usable).
    #[inline]
    pub(crate) fn factor_solve(
        &mut self,
        a: &Matrix4<f64>,
        b: &Vector4<f64>,
    ) -> Option<Vector4<f64>> {
        self.m = a.data.0;
        let [mut x] = b.data.0;
        let m = &mut self.m;
        self.swaps[0] = eliminate::<0>(m, &mut x)?;
        self.swaps[1] = eliminate::<1>(m, &mut x)?;
        self.swaps[2] = eliminate::<2>(m, &mut x)?;
        self.swaps[3] = eliminate::<3>(m, &mut x)?;
        substitute(m, x)
    }

    /// `x` with `a x = b`; `None` on a zero pivot in U. The row swaps are
    /// applied to `b` in the order they were made, then the two
    /// substitutions: the operations of nalgebra's solve, in its order.
    #[inline]
    pub(crate) fn solve(&self, b: &Vector4<f64>) -> Option<Vector4<f64>> {
        let m = &self.m;
        let [mut x] = b.data.0;
        // (`& 3`: the rows are 0..4, which lets the bounds checks go.)
        x.swap(0, usize::from(self.swaps[0]) & 3);
        x.swap(1, usize::from(self.swaps[1]) & 3);
        x.swap(2, usize::from(self.swaps[2]) & 3);
        x.swap(3, usize::from(self.swaps[3]) & 3);
        substitute(m, x)
    }
}

/// The substitutions with the factors `m` on the permuted right-hand side
/// `x`: L (unit diagonal), then U; `None` on a zero pivot in U.
#[inline(always)]
fn substitute(m: &[[f64; 4]; 4], mut x: [f64; 4]) -> Option<Vector4<f64>> {
    forward::<0>(m, &mut x);
    forward::<1>(m, &mut x);
    forward::<2>(m, &mut x);
    backward::<3>(m, &mut x)?;
    backward::<2>(m, &mut x)?;
    backward::<1>(m, &mut x)?;
    backward::<0>(m, &mut x)?;
    Some(Vector4::new(x[0], x[1], x[2], x[3]))
}

/// Column `I` of the elimination: pivot (first row of largest |a|, the
/// row returned), row swap (of `x` too), multipliers `l_r = a_rI·(1/pivot)`, updates `a_rk ← a_rk + (−a_Ik)·l_r`.
/// Constant `I` lets every loop unroll.
///
/// `None` when the column has no non-zero entry from row `I` down: nalgebra
/// skips the step, and U's diagonal entry `I` stays zero (later steps change
/// only the rows below), so its solve returns `None` too.
#[inline(always)]
fn eliminate<const I: usize>(m: &mut [[f64; 4]; 4], x: &mut [f64; 4]) -> Option<u8> {
    let col = &m[I];
    let (piv, _) = (I + 1..4).fold((I, col[I].abs()), |(piv, max), r| {
        let v = col[r].abs();
        if v > max { (r, v) } else { (piv, max) }
    });
    let diag = m[I][piv];
    if diag == 0.0 {
        return None;
    }
    if piv != I {
        for col in m.iter_mut() {
            col.swap(I, piv);
        }
        x.swap(I, piv);
    }
    let inv_diag = 1.0 / diag;
    let (done, rest) = m.split_at_mut(I + 1);
    let l = &mut done[I];
    for v in &mut l[I + 1..] {
        *v *= inv_diag;
    }
    for col in rest {
        let p = -col[I];
        for r in I + 1..4 {
            col[r] += p * l[r];
        }
    }
    Some(piv as u8)
}

/// Forward substitution with L's column `I` (unit diagonal).
#[inline(always)]
fn forward<const I: usize>(m: &[[f64; 4]; 4], x: &mut [f64; 4]) {
    let coeff = x[I];
    for r in I + 1..4 {
        x[r] += (-coeff) * m[I][r];
    }
}

/// Back substitution with U's column `I`; `None` on a zero pivot.
#[inline(always)]
fn backward<const I: usize>(m: &[[f64; 4]; 4], x: &mut [f64; 4]) -> Option<()> {
    let diag = m[I][I];
    if diag == 0.0 {
        return None;
    }
    let coeff = x[I] / diag;
    x[I] = coeff;
    for r in 0..I {
        x[r] += (-coeff) * m[I][r];
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (xorshift64*), values in [−1, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let v = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
            (v >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    fn same_bits(a: Option<Vector4<f64>>, b: Option<Vector4<f64>>) -> bool {
        match (a, b) {
            (None, None) => true,
            (Some(a), Some(b)) => a
                .iter()
                .zip(b.iter())
                .all(|(x, y)| x.to_bits() == y.to_bits()),
            _ => false,
        }
    }

    /// Random matrices with entries over six decades (every pivoting order
    /// occurs), matrices with zero and repeated columns (singular), ties in
    /// the pivot column, and the contact Jacobian's pattern (a structural
    /// zero at (0, 3)): the same bits as nalgebra's LU solve, from the
    /// combined factor-and-solve and from the kept factors.
    #[test]
    fn bit_identical_to_nalgebra_lu() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let mut checked_singular = 0;
        for k in 0..20_000 {
            let mut a = Matrix4::from_fn(|_, _| rng.next() * 10f64.powf(3.0 * rng.next()));
            match k % 7 {
                1 => a[(0, 3)] = 0.0,
                2 => a.set_column(2, &Vector4::zeros()),
                3 => {
                    let c = a.column(0).into_owned();
                    a.set_column(3, &c);
                }
                4 => {
                    // Ties: equal magnitudes in the first column.
                    let v = a[(0, 0)];
                    a[(1, 0)] = -v;
                    a[(3, 0)] = v;
                }
                5 => a.set_row(1, &a.row(2).into_owned()),
                _ => {}
            }
            let b = Vector4::from_fn(|_, _| rng.next());
            let expect = a.lu().solve(&b);
            if expect.is_none() {
                checked_singular += 1;
            }
            assert!(same_bits(solve(&a, &b), expect), "{a} {b}");
            // The kept factors solve another right-hand side as nalgebra
            // does (the predictor's use).
            let mut lu = Lu4::ZERO;
            if lu.factor_solve(&a, &b).is_some() {
                let c = Vector4::from_fn(|_, _| rng.next());
                assert!(same_bits(lu.solve(&c), a.lu().solve(&c)), "{a} {c}");
            }
        }
        assert!(checked_singular > 1000, "{checked_singular}");
    }

    #[test]
    fn solves_and_refuses_the_singular() {
        let a = Matrix4::new(
            0.0, 2.0, 0.0, 0.0, //
            1.0, 0.0, 0.0, 0.0, //
            0.0, 0.0, 0.0, 4.0, //
            0.0, 0.0, 3.0, 0.0,
        );
        let x = solve(&a, &Vector4::new(2.0, 1.0, 8.0, 3.0)).expect("regular");
        assert_eq!(x, Vector4::new(1.0, 1.0, 1.0, 2.0));
        assert!(solve(&Matrix4::zeros(), &Vector4::repeat(1.0)).is_none());
        let nan = solve(&Matrix4::repeat(f64::NAN), &Vector4::repeat(1.0));
        assert!(same_bits(
            nan,
            Matrix4::repeat(f64::NAN).lu().solve(&Vector4::repeat(1.0))
        ));
    }
}
