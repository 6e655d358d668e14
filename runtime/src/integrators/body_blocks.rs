//! The reduced W of a vehicle of rigid bodies, factorised by 6 × 6 blocks
//! (docs/reference/08-multibody.md §8.5, "Block elimination").
//!
//! After the kinematic rows are eliminated ([`super::kinematic`]), the
//! reduced matrix has one 6 × 6 block row and column per body (its velocity
//! and angular velocity), and its block (K, L) is
//!
//! ```text
//! W_KL = δ_KL I/(hγ) − J_{V_K V_L} − hγ J_{V_K P_L} B_L
//! ```
//!
//! with B_L = ∂(ṗ, q̇)/∂(v, ω) of body L (7 × 6). Bodies act on each other
//! only through the elements that join them, so W_KL is zero unless K = L or
//! an element joins K and L: each wheelset meets its frame, each frame the
//! car body, a tree. Gaussian elimination over the blocks in the state's
//! order (wheelsets, then frames, then the car body) creates no new nonzero
//! block, and it skips every zero one: the Cooperrider car's 7 × 7 blocks
//! have 19 nonzero. The blocks are fixed-size matrices, so that every
//! product is unrolled code. On the car the solves cost a fifth of the
//! dense LU's and the factorisations, more than half of it reading the
//! Jacobian, two fifths (docs/reference/08-multibody.md §8.5).
//!
//! The pattern is read from the Jacobian at each factorisation (a block is
//! zero when all its entries are exactly 0.0) and filled: (K, L) becomes
//! nonzero when some J < K, L has (K, J) and (J, L) nonzero.
//!
//! Pivots are searched inside the diagonal block, so that the pattern
//! holds, and accepted when at least [`PIVOT_THRESHOLD`] times the largest
//! entry of their column below them in any block: threshold partial
//! pivoting (I. S. Duff, A. M. Erisman & J. K. Reid, *Direct Methods for
//! Sparse Matrices*, Oxford 1986), which bounds each elimination step's
//! growth of the entries by 1 + 1/u. A pivot that fails the test, or a
//! singular diagonal block, makes the caller fall back to the dense LU with
//! partial pivoting, counted and reported by `sim run`.

use nalgebra::{SMatrix, SVector};

use super::kinematic::KinematicBlock;

type M66 = SMatrix<f64, 6, 6>;
type M67 = SMatrix<f64, 6, 7>;
type M76 = SMatrix<f64, 7, 6>;
type V6 = SVector<f64, 6>;
type V7 = SVector<f64, 7>;

/// A rigid body's velocities (velocity and angular velocity).
pub const BODY_VELOCITIES: usize = 6;
/// A rigid body's positions (position and orientation quaternion).
pub const BODY_POSITIONS: usize = 7;

/// u of the threshold pivoting test (module docs): the value Duff, Erisman
/// & Reid recommend for sparse elimination.
pub const PIVOT_THRESHOLD: f64 = 0.1;

/// The block factorisation of the reduced W (module docs).
#[derive(Debug, Clone)]
pub(super) struct BodyBlocks {
    /// Per body: the first state index of its positions and velocities.
    positions: Vec<usize>,
    velocities: Vec<usize>,
    /// W's blocks (K, L) at K·nb + L, factorised in place: L below the
    /// diagonal blocks (unit diagonal), U on and above them.
    w: Vec<M66>,
    /// J_{V_K P_L} at K·nb + L, and B per body.
    j_vp: Vec<M67>,
    b: Vec<M76>,
    /// The filled pattern (K·nb + L) and the next one read.
    nonzero: Vec<bool>,
    scratch: Vec<bool>,
    /// Per block row K: the blocks L < K (`lower`) and L > K (`upper`) in
    /// the filled pattern; per block column K: the rows I > K (`below`);
    /// per block row K: the bodies L with J_{V_K P_L} ≠ 0 (`touches`).
    lower: Vec<Vec<usize>>,
    upper: Vec<Vec<usize>>,
    below: Vec<Vec<usize>>,
    touches: Vec<Vec<usize>>,
    /// In-block pivot rows of each diagonal block.
    pivots: Vec<[usize; BODY_VELOCITIES]>,
    /// Solve scratch: the reduced right-hand side per body, and r_P.
    x: Vec<V6>,
    r_p: Vec<V7>,
}

impl BodyBlocks {
    /// For `blocks` whose every member is a rigid body (7 positions, 6
    /// velocities) and which together hold every state component once;
    /// `None` otherwise (the caller keeps the dense LU).
    pub(super) fn new(blocks: &[KinematicBlock], n: usize) -> Option<Self> {
        let rigid = blocks
            .iter()
            .all(|b| b.positions.len() == BODY_POSITIONS && b.velocities.len() == BODY_VELOCITIES);
        if !rigid || blocks.len() * (BODY_POSITIONS + BODY_VELOCITIES) != n {
            return None;
        }
        let mut held = vec![false; n];
        for b in blocks {
            for i in b.positions.clone().chain(b.velocities.clone()) {
                if i >= n || std::mem::replace(&mut held[i], true) {
                    return None;
                }
            }
        }
        let nb = blocks.len();
        Some(Self {
            positions: blocks.iter().map(|b| b.positions.start).collect(),
            velocities: blocks.iter().map(|b| b.velocities.start).collect(),
            w: vec![M66::zeros(); nb * nb],
            j_vp: vec![M67::zeros(); nb * nb],
            b: vec![M76::zeros(); nb],
            nonzero: vec![false; nb * nb],
            scratch: vec![false; nb * nb],
            lower: vec![Vec::new(); nb],
            upper: vec![Vec::new(); nb],
            below: vec![Vec::new(); nb],
            touches: vec![Vec::new(); nb],
            pivots: vec![[0; BODY_VELOCITIES]; nb],
            x: vec![V6::zeros(); nb],
            r_p: vec![V7::zeros(); nb],
        })
    }

    fn bodies(&self) -> usize {
        self.positions.len()
    }

    /// Assembles W = I/(hγ) − J (reduced) from the dense row-major n × n
    /// Jacobian `jac` and factorises it. False when a pivot fails the
    /// threshold test or a diagonal block is singular: the caller then
    /// factorises densely.
    pub(super) fn factor(&mut self, jac: &[f64], n: usize, inv_h_gamma: f64) -> bool {
        self.assemble(jac, n, inv_h_gamma);
        self.eliminate()
    }

    fn assemble(&mut self, jac: &[f64], n: usize, inv_h_gamma: f64) {
        let nb = self.bodies();
        let h_gamma = 1.0 / inv_h_gamma;
        for q in 0..nb {
            let (p, v) = (self.positions[q], self.velocities[q]);
            let b = &mut self.b[q];
            for i in 0..BODY_POSITIONS {
                let row = &jac[(p + i) * n + v..(p + i) * n + v + BODY_VELOCITIES];
                for (j, &x) in row.iter().enumerate() {
                    b[(i, j)] = x;
                }
            }
        }
        for k in 0..nb {
            let vk = self.velocities[k];
            self.touches[k].clear();
            for l in 0..nb {
                let (pl, vl) = (self.positions[l], self.velocities[l]);
                let (mut j_vp, mut w) = (M67::zeros(), M66::zeros());
                let (mut any_vp, mut any_vv) = (false, false);
                for i in 0..BODY_VELOCITIES {
                    let row = &jac[(vk + i) * n..(vk + i + 1) * n];
                    for (j, &x) in row[pl..pl + BODY_POSITIONS].iter().enumerate() {
                        j_vp[(i, j)] = x;
                        any_vp |= x != 0.0;
                    }
                    for (j, &x) in row[vl..vl + BODY_VELOCITIES].iter().enumerate() {
                        w[(i, j)] = -x;
                        any_vv |= x != 0.0;
                    }
                }
                if any_vp {
                    self.touches[k].push(l);
                    w -= (j_vp * self.b[l]) * h_gamma;
                }
                if k == l {
                    for d in 0..BODY_VELOCITIES {
                        w[(d, d)] += inv_h_gamma;
                    }
                }
                self.scratch[k * nb + l] = k == l || any_vp || any_vv;
                self.j_vp[k * nb + l] = j_vp;
                self.w[k * nb + l] = w;
            }
        }
        // Fill (module docs).
        for j in 0..nb {
            for k in j + 1..nb {
                if self.scratch[k * nb + j] {
                    for l in j + 1..nb {
                        if self.scratch[j * nb + l] {
                            self.scratch[k * nb + l] = true;
                        }
                    }
                }
            }
        }
        if self.scratch != self.nonzero {
            std::mem::swap(&mut self.nonzero, &mut self.scratch);
            for k in 0..nb {
                let nz = &self.nonzero;
                self.lower[k] = (0..k).filter(|&l| nz[k * nb + l]).collect();
                self.upper[k] = (k + 1..nb).filter(|&l| nz[k * nb + l]).collect();
                self.below[k] = (k + 1..nb).filter(|&i| nz[i * nb + k]).collect();
            }
        }
    }

    /// Right-looking block LU: per block column, the panel (diagonal block
    /// and the blocks below it) by columns, then U's blocks right of the
    /// diagonal, then the Schur complement (Golub & Van Loan, *Matrix
    /// Computations*, 4th ed., §3.2.9, restricted to the nonzero blocks).
    fn eliminate(&mut self) -> bool {
        let nb = self.bodies();
        for k in 0..nb {
            let kk = k * nb + k;
            for c in 0..BODY_VELOCITIES {
                let d = &self.w[kk];
                let mut p = c;
                for r in c + 1..BODY_VELOCITIES {
                    if d[(r, c)].abs() > d[(p, c)].abs() {
                        p = r;
                    }
                }
                let best = d[(p, c)].abs();
                // NaN-propagating maximum: a NaN fails the test below.
                let mut column_max = 0.0_f64;
                for &i in &self.below[k] {
                    for x in self.w[i * nb + k].column(c).iter() {
                        if x.abs() > column_max || x.is_nan() {
                            column_max = x.abs();
                        }
                    }
                }
                if !(best.is_finite() && best > 0.0 && best >= PIVOT_THRESHOLD * column_max) {
                    return false;
                }
                self.pivots[k][c] = p;
                if p != c {
                    let diagonal = [k];
                    let row = self.lower[k].iter().chain(&diagonal).chain(&self.upper[k]);
                    for &l in row {
                        self.w[k * nb + l].swap_rows(c, p);
                    }
                }
                let d = self.w[kk];
                let inv = 1.0 / d[(c, c)];
                for r in c + 1..BODY_VELOCITIES {
                    let l = self.w[kk][(r, c)] * inv;
                    self.w[kk][(r, c)] = l;
                    for j in c + 1..BODY_VELOCITIES {
                        self.w[kk][(r, j)] -= l * d[(c, j)];
                    }
                }
                for &i in &self.below[k] {
                    let b = &mut self.w[i * nb + k];
                    for r in 0..BODY_VELOCITIES {
                        let l = b[(r, c)] * inv;
                        b[(r, c)] = l;
                        for j in c + 1..BODY_VELOCITIES {
                            b[(r, j)] -= l * d[(c, j)];
                        }
                    }
                }
            }
            let d = self.w[kk];
            for &j in &self.upper[k] {
                let u = &mut self.w[k * nb + j];
                for c in 0..BODY_VELOCITIES {
                    for r in c + 1..BODY_VELOCITIES {
                        let l = d[(r, c)];
                        for col in 0..BODY_VELOCITIES {
                            u[(r, col)] -= l * u[(c, col)];
                        }
                    }
                }
            }
            for &i in &self.below[k] {
                let l = self.w[i * nb + k];
                for &j in &self.upper[k] {
                    let u = self.w[k * nb + j];
                    self.w[i * nb + j] -= l * u;
                }
            }
        }
        true
    }

    /// Solves W x = v in place (the whole state: the kept rows through the
    /// factors, the positions by x_P = hγ (r_P + B x_V); module
    /// [`super::kinematic`]).
    pub(super) fn solve(&mut self, inv_h_gamma: f64, v: &mut [f64]) {
        let nb = self.bodies();
        let h_gamma = 1.0 / inv_h_gamma;
        for q in 0..nb {
            let p = self.positions[q];
            self.r_p[q] = V7::from_column_slice(&v[p..p + BODY_POSITIONS]);
        }
        for k in 0..nb {
            let vk = self.velocities[k];
            let mut s = V6::zeros();
            for &l in &self.touches[k] {
                s += self.j_vp[k * nb + l] * self.r_p[l];
            }
            let mut x = V6::from_column_slice(&v[vk..vk + BODY_VELOCITIES]) + s * h_gamma;
            for (c, &p) in self.pivots[k].iter().enumerate() {
                x.swap_rows(c, p);
            }
            self.x[k] = x;
        }
        for k in 0..nb {
            let mut x = self.x[k];
            for &j in &self.lower[k] {
                x -= self.w[k * nb + j] * self.x[j];
            }
            let d = &self.w[k * nb + k];
            for c in 0..BODY_VELOCITIES {
                for r in c + 1..BODY_VELOCITIES {
                    x[r] -= d[(r, c)] * x[c];
                }
            }
            self.x[k] = x;
        }
        for k in (0..nb).rev() {
            let mut x = self.x[k];
            for &j in &self.upper[k] {
                x -= self.w[k * nb + j] * self.x[j];
            }
            let d = &self.w[k * nb + k];
            for c in (0..BODY_VELOCITIES).rev() {
                x[c] /= d[(c, c)];
                for r in 0..c {
                    x[r] -= d[(r, c)] * x[c];
                }
            }
            self.x[k] = x;
        }
        for k in 0..nb {
            let (p, vk) = (self.positions[k], self.velocities[k]);
            v[vk..vk + BODY_VELOCITIES].copy_from_slice(self.x[k].as_slice());
            let x_p = (self.r_p[k] + self.b[k] * self.x[k]) * h_gamma;
            v[p..p + BODY_POSITIONS].copy_from_slice(x_p.as_slice());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::jacobian::{lu_in_place, lu_solve};
    use super::super::kinematic::KinematicReduction;
    use super::*;

    /// A deterministic pseudo-random value in [−1, 1) (the SplitMix64
    /// finaliser of i: neighbouring indices give unrelated values).
    fn noise(i: usize) -> f64 {
        let mut x = (i as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
        x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        x ^= x >> 31;
        ((x >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// Rigid bodies in the vehicle's state layout (per body 7 positions,
    /// then 6 velocities) and a Jacobian whose position rows are exactly
    /// B (so that the reduced solve is exact) and whose velocity rows act
    /// on the bodies `pattern` marks ('X'), with `diagonal` added to J_VV's
    /// diagonal (1/s) and the other bodies' blocks scaled by `coupling`.
    fn system(
        pattern: &[&str],
        diagonal: f64,
        coupling: f64,
    ) -> (Vec<f64>, Vec<KinematicBlock>, usize) {
        let nb = pattern.len();
        let n = nb * 13;
        let blocks: Vec<KinematicBlock> = (0..nb)
            .map(|k| KinematicBlock {
                positions: 13 * k..13 * k + 7,
                velocities: 13 * k + 7..13 * k + 13,
            })
            .collect();
        let mut jac = vec![0.0; n * n];
        for (k, b) in blocks.iter().enumerate() {
            for i in b.positions.clone() {
                for j in b.velocities.clone() {
                    jac[i * n + j] = 0.5 * noise(i * n + j);
                }
            }
            for (l, c) in pattern[k].chars().enumerate() {
                if c != 'X' {
                    continue;
                }
                let scale = if l == k { 40.0 } else { 40.0 * coupling };
                for i in b.velocities.clone() {
                    for j in 13 * l..13 * l + 13 {
                        jac[i * n + j] = scale * noise(i * n + j);
                    }
                }
            }
            for d in b.velocities.clone() {
                jac[d * n + d] += diagonal;
            }
        }
        (jac, blocks, n)
    }

    /// The backward error max |W x − r| / (‖W‖∞ ‖x‖∞ + ‖r‖∞) over the
    /// whole state, W = I/(hγ) − J dense: of the order of the unit round-off
    /// for a stable solve, whatever W's condition.
    fn residual(jac: &[f64], n: usize, inv_hg: f64, x: &[f64], r: &[f64]) -> f64 {
        let norm = |v: &[f64]| v.iter().fold(0.0, |m: f64, a| m.max(a.abs()));
        let w_norm = (0..n)
            .map(|row| {
                (0..n)
                    .map(|c| (if c == row { inv_hg } else { 0.0 } - jac[row * n + c]).abs())
                    .sum::<f64>()
            })
            .fold(0.0, f64::max);
        let worst = (0..n)
            .map(|row| {
                let wx: f64 =
                    inv_hg * x[row] - (0..n).map(|c| jac[row * n + c] * x[c]).sum::<f64>();
                (wx - r[row]).abs()
            })
            .fold(0.0, f64::max);
        worst / (w_norm * norm(x) + norm(r))
    }

    const INV_HG: f64 = 1.0 / (0.435_866_521_508_459 * 0.005);

    fn solve(pattern: &[&str], diagonal: f64, coupling: f64) -> (f64, u64, Vec<f64>) {
        let (jac, blocks, n) = system(pattern, diagonal, coupling);
        let mut red = KinematicReduction::new(&blocks, n);
        assert!(red.factor(&jac, n, INV_HG));
        let r: Vec<f64> = (0..n).map(|i| noise(7 * i + 3)).collect();
        let mut x = r.clone();
        red.solve(INV_HG, &mut x);
        // The dense LU of the whole W, for comparison.
        let mut w: Vec<f64> = jac.iter().map(|j| -j).collect();
        for d in 0..n {
            w[d * n + d] += INV_HG;
        }
        let mut piv = vec![0; n];
        assert!(lu_in_place(&mut w, n, &mut piv));
        let mut dense = r.clone();
        lu_solve(&w, n, &piv, &mut dense);
        let scale = dense.iter().fold(0.0, |m: f64, a| m.max(a.abs()));
        let gap = x
            .iter()
            .zip(&dense)
            .map(|(a, b)| (a - b).abs() / scale)
            .fold(0.0, f64::max);
        assert!(
            gap < 1e-9,
            "block and dense solves differ by {gap:e} of the largest"
        );
        (residual(&jac, n, INV_HG, &x, &r), red.dense_fallbacks(), x)
    }

    /// [`solve`] without a fallback and to the round-off, and the block
    /// factorisation of the same system.
    fn solved_by_blocks(pattern: &[&str], diagonal: f64, coupling: f64) -> BodyBlocks {
        let (res, fallbacks, _) = solve(pattern, diagonal, coupling);
        assert_eq!(fallbacks, 0);
        assert!(res < 1e-15, "backward error {res:e}");
        let (jac, blocks, n) = system(pattern, diagonal, coupling);
        let mut bb = BodyBlocks::new(&blocks, n).expect("rigid bodies");
        assert!(bb.factor(&jac, n, INV_HG));
        bb
    }

    /// The Cooperrider car's pattern: four wheelsets, two frames, the car
    /// body; no fill, 19 nonzero blocks, solved by blocks.
    #[test]
    fn a_vehicle_tree_is_solved_by_blocks() {
        let car = [
            "X...X..", ".X..X..", "..X..X.", "...X.X.", "XX..X.X", "..XX.XX", "....XXX",
        ];
        let bb = solved_by_blocks(&car, 0.0, 1.0);
        assert_eq!(bb.nonzero.iter().filter(|&&z| z).count(), 19);
    }

    /// The car body first: eliminating it fills the blocks between the
    /// frames; the fill is found and the solve stays exact.
    #[test]
    fn fill_is_found() {
        let arrow = ["XXXX", "XX..", "X.X.", "X..X"];
        let bb = solved_by_blocks(&arrow, 0.0, 1.0);
        assert!(bb.nonzero.iter().all(|&z| z), "every block filled");
    }

    /// J_VV's diagonal equal to 1/(hγ) empties W's diagonal: rows are
    /// swapped inside the diagonal blocks.
    #[test]
    fn rows_are_pivoted_inside_a_block() {
        let bb = solved_by_blocks(&["XX", "XX"], INV_HG, 0.01);
        let swapped = bb
            .pivots
            .iter()
            .flat_map(|p| p.iter().enumerate())
            .filter(|(c, p)| c != *p);
        assert!(swapped.count() > 0, "some rows swapped");
    }

    /// A diagonal block far smaller than the block below it fails the
    /// threshold test: the dense LU solves it, and the fallback is counted.
    #[test]
    fn a_weak_pivot_falls_back_to_the_dense_lu() {
        let (mut jac, blocks, n) = system(&["XX", "XX"], 0.0, 1.0);
        // Body 0's own velocity columns: W_00 ≈ 0 against W_10 ≈ 40·10³.
        for i in 7..13 {
            for j in 7..13 {
                jac[i * n + j] = if i == j { INV_HG } else { 0.0 };
            }
            for j in 0..7 {
                jac[i * n + j] = 0.0;
            }
            for j in 20..26 {
                jac[(i + 13) * n + j - 13] = 4e4 * noise(i * j);
            }
        }
        for i in 7..13 {
            jac[i * n + i] -= 1e-3 * (1.0 + noise(i));
        }
        let mut red = KinematicReduction::new(&blocks, n);
        assert!(red.factor(&jac, n, INV_HG));
        assert_eq!(red.dense_fallbacks(), 1);
        let r: Vec<f64> = (0..n).map(|i| noise(5 * i)).collect();
        let mut x = r.clone();
        red.solve(INV_HG, &mut x);
        let res = residual(&jac, n, INV_HG, &x, &r);
        assert!(res < 1e-15, "backward error {res:e}");
    }

    /// Only a state of rigid bodies and nothing else is factorised by
    /// blocks.
    #[test]
    fn other_layouts_keep_the_dense_lu() {
        let b = |p: std::ops::Range<usize>, v: std::ops::Range<usize>| KinematicBlock {
            positions: p,
            velocities: v,
        };
        assert!(BodyBlocks::new(&[b(0..7, 7..13)], 13).is_some());
        assert!(
            BodyBlocks::new(&[b(0..7, 7..13)], 14).is_none(),
            "an internal state"
        );
        assert!(
            BodyBlocks::new(&[b(0..2, 2..4)], 4).is_none(),
            "not a rigid body"
        );
        assert!(
            BodyBlocks::new(&[b(0..7, 14..20), b(7..14, 14..20)], 26).is_none(),
            "two bodies on the same velocities"
        );
    }
}
