//! The linear solves of the stiff integrator with the kinematic rows
//! eliminated (docs/reference/08-multibody.md §8.5, "Kinematic rows").
//!
//! A mechanical system's state holds, per body, positions P (here a
//! position and an orientation quaternion) whose derivative is a function
//! of the body's own velocities V: ṗ = v, q̇ = ½ q ⊗ (0, ω). In W = I/(hγ) −
//! J their rows are I/(hγ) − B on the body's own velocity columns, with
//! B = ∂(ṗ, q̇)/∂(v, ω), plus ∂q̇/∂q = ½ Ω(ω), of the order of the body's
//! slow rotation rates. A Rosenbrock-W method keeps its order with any
//! matrix in place of J (Hairer & Wanner, *Solving ODEs II*, §IV.7), so the
//! matrix used drops ∂q̇/∂q and every other entry of the P rows: those
//! modes (|λ| ≈ |ω|/2, a few s⁻¹) are integrated explicitly by the stages.
//! Then W x = r splits, with R the components not in any P:
//!
//! ```text
//! x_P = hγ (r_P + B x_V)                                   (per body)
//! (I/(hγ) − J_RR − hγ Σ_k J_{R,P_k} B_k) x_R = r_R + hγ Σ_k J_{R,P_k} r_{P_k}
//! ```
//!
//! (substitute the first line into the R rows; V ⊂ R). The LU factors are
//! those of an |R| × |R| matrix: for the car, 42 instead of 91 rows, a
//! tenth of the factorisation's work; each solve costs about half.
//!
//! When the state is rigid bodies only, that matrix is factorised by 6 × 6
//! blocks, one per body pair, skipping the zero ones
//! ([`super::body_blocks`]); otherwise, and when a block pivot fails its
//! threshold test, by the dense LU below.

use std::ops::Range;

use super::body_blocks::BodyBlocks;
use super::jacobian::{dot, lu_in_place, lu_solve};

/// One body's kinematic rows: `positions` (eliminated) whose derivative
/// depends on `velocities` (kept), both ranges of state indices.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KinematicBlock {
    pub positions: Range<usize>,
    pub velocities: Range<usize>,
}

/// The reduced factorisation (module docs), built for a state of `n`
/// components; J is the dense row-major n × n Jacobian.
#[derive(Debug, Clone)]
pub(super) struct KinematicReduction {
    /// The kept components R, ascending.
    kept: Vec<usize>,
    /// The eliminated components P, block after block.
    eliminated: Vec<usize>,
    /// Per eliminated component: where its block's velocities start in R,
    /// and how many there are.
    velocities_in_kept: Vec<(usize, usize)>,
    /// J_RP (|R| × |P|) and B (per eliminated row, its block's velocity
    /// columns; `MAX_VELOCITIES` wide), copied from J at each
    /// factorisation so that the solves read contiguous rows.
    j_rp: Vec<f64>,
    b: Vec<f64>,
    /// Row-major LU of the reduced matrix (|R| × |R|) and its pivots.
    lu: Vec<f64>,
    pivots: Vec<usize>,
    rhs: Vec<f64>,
    r_p: Vec<f64>,
    /// The factorisation by 6 × 6 blocks when every block is a rigid body
    /// and the state holds nothing else ([`super::body_blocks`]), whether
    /// the current factors are those, and how many factorisations fell
    /// back to the dense LU above.
    bodies: Option<BodyBlocks>,
    by_blocks: bool,
    dense_fallbacks: u64,
}

/// Most velocity components one kinematic block may have (6 for a rigid
/// body).
pub const MAX_VELOCITIES: usize = 8;

impl KinematicReduction {
    /// Checks the blocks against a state of `n` components: the rule
    /// broken, if any.
    pub(super) fn check(blocks: &[KinematicBlock], n: usize) -> Result<(), &'static str> {
        let mut eliminated = vec![false; n];
        for b in blocks {
            let p = &b.positions;
            if p.start >= p.end || p.end > n {
                return Err("kinematic positions must be a non-empty range inside the state");
            }
            for e in &mut eliminated[p.clone()] {
                if *e {
                    return Err("kinematic positions must be disjoint");
                }
                *e = true;
            }
        }
        for b in blocks {
            let v = &b.velocities;
            if v.start >= v.end || v.end > n {
                return Err("kinematic velocities must be a non-empty range inside the state");
            }
            if v.len() > MAX_VELOCITIES {
                return Err("a kinematic block has at most 8 velocities");
            }
            if v.clone().any(|i| eliminated[i]) {
                return Err("kinematic velocities must not be positions");
            }
        }
        Ok(())
    }

    pub(super) fn new(blocks: &[KinematicBlock], n: usize) -> Self {
        let mut index_in_kept = vec![Some(0); n];
        for b in blocks {
            for i in b.positions.clone() {
                index_in_kept[i] = None;
            }
        }
        let mut kept = Vec::with_capacity(n);
        for (i, slot) in index_in_kept.iter_mut().enumerate() {
            if slot.is_some() {
                *slot = Some(kept.len());
                kept.push(i);
            }
        }
        let mut eliminated = Vec::new();
        let mut velocities_in_kept = Vec::new();
        for b in blocks {
            // Velocities are a range of kept components, hence contiguous in R.
            let first = index_in_kept[b.velocities.start].unwrap_or(0);
            for p in b.positions.clone() {
                eliminated.push(p);
                velocities_in_kept.push((first, b.velocities.len()));
            }
        }
        let (m, np) = (kept.len(), eliminated.len());
        Self {
            kept,
            eliminated,
            velocities_in_kept,
            j_rp: vec![0.0; m * np],
            b: vec![0.0; np * MAX_VELOCITIES],
            lu: vec![0.0; m * m],
            pivots: vec![0; m],
            rhs: vec![0.0; m],
            r_p: vec![0.0; np],
            bodies: BodyBlocks::new(blocks, n),
            by_blocks: false,
            dense_fallbacks: 0,
        }
    }

    /// Factorisations by blocks that fell back to the dense LU (a pivot
    /// failed the threshold test, or a diagonal block was singular).
    pub(super) fn dense_fallbacks(&self) -> u64 {
        self.dense_fallbacks
    }

    /// LU factors of the reduced matrix for 1/(hγ) = `inv_h_gamma`. False
    /// when it is singular.
    pub(super) fn factor(&mut self, jac: &[f64], n: usize, inv_h_gamma: f64) -> bool {
        if let Some(bodies) = &mut self.bodies {
            if bodies.factor(jac, n, inv_h_gamma) {
                self.by_blocks = true;
                return true;
            }
            self.dense_fallbacks += 1;
        }
        self.by_blocks = false;
        let (m, np) = (self.kept.len(), self.eliminated.len());
        let h_gamma = 1.0 / inv_h_gamma;
        for (q, &p) in self.eliminated.iter().enumerate() {
            let (first, len) = self.velocities_in_kept[q];
            let v0 = self.kept[first];
            self.b[q * MAX_VELOCITIES..q * MAX_VELOCITIES + len]
                .copy_from_slice(&jac[p * n + v0..p * n + v0 + len]);
        }
        for (row, &i) in self.kept.iter().enumerate() {
            let j_row = &jac[i * n..(i + 1) * n];
            let j_rp = &mut self.j_rp[row * np..(row + 1) * np];
            for (o, &p) in j_rp.iter_mut().zip(&self.eliminated) {
                *o = j_row[p];
            }
            let out = &mut self.lu[row * m..(row + 1) * m];
            for (o, &j) in out.iter_mut().zip(&self.kept) {
                *o = -j_row[j];
            }
            out[row] += inv_h_gamma;
            // − hγ J_{i,P} B, added on each block's velocity columns.
            for (q, &a) in j_rp.iter().enumerate() {
                if a == 0.0 {
                    continue;
                }
                let (first, len) = self.velocities_in_kept[q];
                let b = &self.b[q * MAX_VELOCITIES..q * MAX_VELOCITIES + len];
                for (o, bv) in out[first..first + len].iter_mut().zip(b) {
                    *o -= h_gamma * a * bv;
                }
            }
        }
        lu_in_place(&mut self.lu, m, &mut self.pivots)
    }

    /// Solves W x = v in place with the factors of [`Self::factor`] (made
    /// for the same `inv_h_gamma` and J).
    pub(super) fn solve(&mut self, inv_h_gamma: f64, v: &mut [f64]) {
        if self.by_blocks {
            if let Some(bodies) = &mut self.bodies {
                bodies.solve(inv_h_gamma, v);
                return;
            }
        }
        let (m, np) = (self.kept.len(), self.eliminated.len());
        let h_gamma = 1.0 / inv_h_gamma;
        for (r, &p) in self.r_p.iter_mut().zip(&self.eliminated) {
            *r = v[p];
        }
        for (row, &i) in self.kept.iter().enumerate() {
            let j_rp = &self.j_rp[row * np..(row + 1) * np];
            self.rhs[row] = v[i] + h_gamma * dot(j_rp, &self.r_p);
        }
        lu_solve(&self.lu, m, &self.pivots, &mut self.rhs);
        for (row, &i) in self.kept.iter().enumerate() {
            v[i] = self.rhs[row];
        }
        // x_P = hγ (r_P + B x_V).
        for (q, &p) in self.eliminated.iter().enumerate() {
            let (first, len) = self.velocities_in_kept[q];
            let b = &self.b[q * MAX_VELOCITIES..q * MAX_VELOCITIES + len];
            v[p] = h_gamma * (self.r_p[q] + dot(b, &self.rhs[first..first + len]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A damped oscillator pair in first-order form, positions first:
    /// y = [x₁, x₂, v₁, v₂], ẋ = v, v̇ = −K x − C v. Its P rows are exactly
    /// [0 | I], so the reduced solve must equal the dense one to rounding.
    #[test]
    fn the_reduced_solve_equals_the_dense_one_when_the_p_rows_are_kinematic() {
        let n = 4;
        let (k, c) = (
            [[400.0, -100.0], [-100.0, 250.0]],
            [[3.0, -1.0], [-1.0, 2.0]],
        );
        let mut jac = vec![0.0; n * n];
        jac[2] = 1.0; // ∂ẋ₁/∂v₁
        jac[n + 3] = 1.0; // ∂ẋ₂/∂v₂
        for r in 0..2 {
            for col in 0..2 {
                jac[(2 + r) * n + col] = -k[r][col];
                jac[(2 + r) * n + 2 + col] = -c[r][col];
            }
        }
        let blocks = vec![KinematicBlock {
            positions: 0..2,
            velocities: 2..4,
        }];
        assert_eq!(KinematicReduction::check(&blocks, n), Ok(()));
        let mut red = KinematicReduction::new(&blocks, n);
        let inv_hg = 1.0 / (0.435_866_521_508_459 * 0.01);
        assert!(red.factor(&jac, n, inv_hg));
        let r = [0.3, -1.2, 4.0, 0.7];
        let mut x = r;
        red.solve(inv_hg, &mut x);
        // Residual of the dense W = I/(hγ) − J.
        for row in 0..n {
            let mut s = inv_hg * x[row];
            for col in 0..n {
                s -= jac[row * n + col] * x[col];
            }
            assert!(
                (s - r[row]).abs() < 1e-10 * (1.0 + r[row].abs()),
                "row {row}: {s} vs {}",
                r[row]
            );
        }
    }

    #[test]
    fn the_blocks_are_checked() {
        let b = |p: Range<usize>, v: Range<usize>| KinematicBlock {
            positions: p,
            velocities: v,
        };
        assert!(KinematicReduction::check(&[b(0..2, 2..4)], 4).is_ok());
        assert_eq!(
            KinematicReduction::check(&[b(0..2, 2..4), b(1..3, 3..4)], 4),
            Err("kinematic positions must be disjoint")
        );
        assert_eq!(
            KinematicReduction::check(&[b(0..2, 1..3)], 4),
            Err("kinematic velocities must not be positions")
        );
        assert!(KinematicReduction::check(&[b(0..2, 2..5)], 4).is_err());
    }
}
