//! The approximate Jacobian of the stiff integrator ([`super::rosenbrock`]):
//! its block structure, its finite-difference evaluation and the
//! factorisation of the iteration matrix W = I/(hγ) − J, block by block.
//!
//! # Block-diagonal structure (docs/reference/08-multibody.md §8.5)
//!
//! A Rosenbrock-W method keeps its order with *any* matrix in place of the
//! Jacobian ∂f/∂y (Steihaug & Wolfbrandt 1979; Hairer & Wanner, *Solving
//! ODEs II*, §IV.7, "W-methods"); the matrix only decides which modes are
//! treated implicitly, i.e. the method's stability. A system whose stiff
//! modes act on disjoint groups of its states may declare diagonal
//! **blocks** ([`super::OdeSystem::jacobian_blocks`]) and the Jacobian is
//! approximated by them; the coupling between blocks is then integrated
//! explicitly by the stages, and components outside every block get a zero
//! Jacobian row and column. The default is one dense block. The vehicle
//! keeps the default: its primary suspensions couple wheelset and frame as
//! stiffly as the contact (docs/reference/08-multibody.md §8.5, measured).

//! # Finite differences with simultaneous perturbation
//!
//! Blocks whose states do not act directly on each other's derivatives are
//! put in one **group** and perturbed together: column j of
//! every block of the group is perturbed in the same evaluation and each
//! block reads only its own rows, which no other block of the group
//! disturbs (Curtis, Powell & Reid, "On the estimation of sparse Jacobian
//! matrices", J. Inst. Math. Appl. 13 (1974) 117–119). A group costs as
//! many evaluations as its largest block has columns. Forward differences with the increment
//! δ_i = [`FD_RELATIVE_STEP`]·max(|y_i|, 1) (state units): large against the
//! contact solve's convergence tolerance, small against the forces'
//! nonlinearity — the Jacobian need not be accurate (W-method), only
//! representative of the stiff modes.
//!
//! # Colours
//!
//! Inside the one dense block, a system may declare **colours**
//! ([`JacobianBlocks::colors`]): ranges of columns with the rows they can
//! change; the members of a colour change disjoint rows, so column j of
//! each member is perturbed in the same evaluation and each member reads
//! its own rows (the rest of its columns are zero) — the same
//! Curtis–Powell–Reid idea applied to a sparse dense block. The vehicle
//! colours its bodies: a body's state acts on its own rows, on those of the
//! bodies an element joins it to and on those elements' internal states
//! (docs/reference/08-multibody.md §8.5). On the Cooperrider car (two bogies)
//! the 91 columns take 52 evaluations instead of 91, with the same
//! Jacobian bit for bit; a bogie has no two bodies that can share one.
//!
//! # Factorisation
//!
//! W = I/(hγ) − J is block diagonal too: each block gets an in-place LU
//! factorisation with partial pivoting (Golub & Van Loan, *Matrix
//! Computations*, 4th ed., Alg. 3.4.1), a few hundred flops for a 13×13
//! block, redone whenever h or J changes; rows outside the blocks are
//! I/(hγ). No allocation after construction.

use std::ops::Range;

use super::kinematic::{KinematicBlock, KinematicReduction};
use super::{IntegratorError, OdeSystem, eval, eval_column};

/// Relative finite-difference increment of the Jacobian's columns
/// (module docs): δ_i = 1e-6·max(|y_i|, 1) — 1 µm on a lateral or
/// vertical displacement, 2·10⁻⁵ m/s on a 20 m/s velocity.
///
/// Chosen against the noise of the evaluations
/// (docs/reference/08-multibody.md §8.5, "Jacobian"): the contact Newton
/// stops within 1e-9 m of its root (docs/reference/06-contact-detection.md
/// §6), which at a Hertz stiffness dN/dδ = 1.5 N/δ ≈ 1.5·10⁹ N/m (50 kN at
/// 50 µm) is about 1.5 N of normal force. A forward difference over h
/// carries that noise ε as ε/h and its truncation N″h/2 = 0.375 N h/δ²
/// (N = K δ^1.5); the sum is least at h = δ √(ε/(0.375 N)) ≈ 0.45 µm. At
/// 1e-7 m the noise (1.5·10⁷ N/m, 1 % of the stiffness) dominated; 1e-6 m
/// leaves 0.1 % noise and 0.5 % truncation. Measured on the bogie at
/// 20 m/s: 51 → 31 rejected steps and 5 % fewer instructions, the lateral
/// error 8.8 → 7.8 µm.
pub const FD_RELATIVE_STEP: f64 = 1e-6;

/// Relative difference of 1/(hγ) within which W's factors are kept
/// ([`BlockJacobian::factored_near`]): a step that ends on an output time
/// differs from the last by round-off (reference 8.5, "Steps on the
/// output grid").
pub(super) const W_REUSE_ROUND_OFF: f64 = 1e-9;

/// Which diagonal blocks of the Jacobian the system asks the stiff
/// integrator to approximate, and which blocks may be perturbed together
/// (module docs).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JacobianBlocks {
    /// Disjoint ranges of state indices, each a diagonal block.
    pub blocks: Vec<Range<usize>>,
    /// Groups of indices into `blocks`; every block in exactly one group.
    /// The blocks of a group must not act directly on each other's
    /// derivatives.
    pub groups: Vec<Vec<usize>>,
    /// Kinematic rows eliminated from the linear solves ([`super::kinematic`]),
    /// only with one dense block over the whole state; empty: none.
    pub kinematics: Vec<KinematicBlock>,
    /// Columns of the one dense block perturbed together (module docs,
    /// "Colours"), only with one dense block over the whole state; columns
    /// in no colour are perturbed one at a time. Empty: none.
    pub colors: Vec<ColumnColor>,
}

/// Column ranges of a dense Jacobian perturbed in the same evaluations
/// (module docs, "Colours"): the members' rows must be disjoint.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ColumnColor {
    pub members: Vec<ColoredColumns>,
}

impl ColumnColor {
    /// Evaluations the colour costs: its widest member's columns.
    pub fn width(&self) -> usize {
        self.members
            .iter()
            .map(|m| m.columns.len())
            .max()
            .unwrap_or(0)
    }
}

/// A range of columns and every row those columns can change (the other
/// rows of the columns are zero).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ColoredColumns {
    pub columns: Range<usize>,
    pub rows: Vec<Range<usize>>,
}

impl JacobianBlocks {
    /// One dense block over all `n` components (n evaluations per
    /// Jacobian).
    pub fn dense(n: usize) -> Self {
        #[allow(clippy::single_range_in_vec_init)]
        Self {
            blocks: vec![0..n],
            groups: vec![vec![0]],
            kinematics: Vec::new(),
            colors: Vec::new(),
        }
    }

    /// One dense block with the kinematic rows `kinematics` eliminated
    /// from the solves ([`super::kinematic`]).
    pub fn dense_kinematic(n: usize, kinematics: Vec<KinematicBlock>) -> Self {
        Self {
            kinematics,
            ..Self::dense(n)
        }
    }

    /// Whether the blocks are disjoint, inside 0..n, non-empty, and every
    /// block is in exactly one group: the rule broken, if any.
    pub fn check(&self, n: usize) -> Result<(), &'static str> {
        let mut owner = vec![false; n];
        for b in &self.blocks {
            if b.start >= b.end || b.end > n {
                return Err("every block must be a non-empty range inside the state");
            }
            for o in &mut owner[b.clone()] {
                if *o {
                    return Err("the blocks must be disjoint");
                }
                *o = true;
            }
        }
        let mut seen = vec![0usize; self.blocks.len()];
        for g in &self.groups {
            for &b in g {
                match seen.get_mut(b) {
                    Some(s) => *s += 1,
                    None => return Err("a group names a block that does not exist"),
                }
            }
        }
        if seen.iter().any(|&s| s != 1) {
            return Err("every block must be in exactly one group");
        }
        if !self.kinematics.is_empty() {
            if self.blocks.len() != 1 || self.blocks[0] != (0..n) {
                return Err("kinematic rows need one dense block over the whole state");
            }
            KinematicReduction::check(&self.kinematics, n)?;
        }
        if !self.colors.is_empty() {
            if self.blocks.len() != 1 || self.blocks[0] != (0..n) {
                return Err("colours need one dense block over the whole state");
            }
            let mut column_seen = vec![false; n];
            for color in &self.colors {
                let mut row_seen = vec![false; n];
                for m in &color.members {
                    let c = &m.columns;
                    if c.start >= c.end || c.end > n {
                        return Err("coloured columns must be a non-empty range inside the state");
                    }
                    for s in &mut column_seen[c.clone()] {
                        if *s {
                            return Err("a column may be in one colour only");
                        }
                        *s = true;
                    }
                    for r in &m.rows {
                        if r.start > r.end || r.end > n {
                            return Err("coloured rows must be ranges inside the state");
                        }
                        for s in &mut row_seen[r.clone()] {
                            if *s {
                                return Err("the members of a colour must change disjoint rows");
                            }
                            *s = true;
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Evaluations of one finite-difference Jacobian.
    pub fn evaluations(&self) -> usize {
        if !self.colors.is_empty() {
            let n = self.blocks.first().map_or(0, |b| b.len());
            let colored: usize = self
                .colors
                .iter()
                .flat_map(|c| &c.members)
                .map(|m| m.columns.len())
                .sum();
            let widths: usize = self.colors.iter().map(ColumnColor::width).sum();
            return widths + n - colored;
        }
        self.groups
            .iter()
            .map(|g| g.iter().map(|&b| self.blocks[b].len()).max().unwrap_or(0))
            .sum()
    }
}

/// The block-diagonal Jacobian and the LU factors of W, with scratch.
pub(super) struct BlockJacobian {
    layout: JacobianBlocks,
    /// Row-major J blocks, one per block (len × len).
    jac: Vec<Vec<f64>>,
    /// Row-major LU factors of W per block, and the pivot rows.
    lu: Vec<Vec<f64>>,
    pivots: Vec<Vec<usize>>,
    /// 1/(hγ) the factors were made for (0: none yet).
    factored_for: f64,
    y_pert: Vec<f64>,
    f_pert: Vec<f64>,
    rhs_scratch: Vec<f64>,
    /// State indices outside every block.
    outside: Vec<usize>,
    /// The solves with the kinematic rows eliminated, if declared (then
    /// `lu` and `pivots` stay empty).
    reduction: Option<KinematicReduction>,
}

impl BlockJacobian {
    pub(super) fn new(layout: JacobianBlocks, n: usize) -> Self {
        let sizes: Vec<usize> = layout.blocks.iter().map(|b| b.len()).collect();
        let max = sizes.iter().copied().max().unwrap_or(0);
        let outside = (0..n)
            .filter(|i| !layout.blocks.iter().any(|r| r.contains(i)))
            .collect();
        let reduction =
            (!layout.kinematics.is_empty()).then(|| KinematicReduction::new(&layout.kinematics, n));
        let factored = if reduction.is_some() {
            &[][..]
        } else {
            &sizes[..]
        };
        Self {
            outside,
            jac: sizes.iter().map(|&m| vec![0.0; m * m]).collect(),
            lu: factored.iter().map(|&m| vec![0.0; m * m]).collect(),
            pivots: factored.iter().map(|&m| vec![0; m]).collect(),
            reduction,
            layout,
            factored_for: 0.0,
            y_pert: vec![0.0; n],
            f_pert: vec![0.0; n],
            rhs_scratch: vec![0.0; max],
        }
    }

    /// Forward-difference blocks at (t, y) with f0 = f(t, y) (module docs).
    /// Returns the evaluations made.
    pub(super) fn evaluate<S: OdeSystem>(
        &mut self,
        system: &mut S,
        t: f64,
        y: &[f64],
        f0: &[f64],
        evaluations: &mut u64,
    ) -> Result<(), IntegratorError<S::Error>> {
        self.y_pert.copy_from_slice(y);
        if !self.layout.colors.is_empty() {
            return self.evaluate_colored(system, t, y, f0, evaluations);
        }
        for group in &self.layout.groups {
            let width = group
                .iter()
                .map(|&b| self.layout.blocks[b].len())
                .max()
                .unwrap_or(0);
            for j in 0..width {
                for &b in group {
                    let r = &self.layout.blocks[b];
                    if j < r.len() {
                        let i = r.start + j;
                        self.y_pert[i] = y[i] + fd_step(y[i]);
                    }
                }
                // A non-finite perturbed derivative leaves that column at
                // zero (treated explicitly); the step's error control sees
                // the trouble, if any, in the stages themselves.
                // One perturbed component: the system may reuse what it
                // cannot change ([`OdeSystem::rhs_column`]).
                let single = match group.as_slice() {
                    [b] => Some(self.layout.blocks[*b].start + j),
                    _ => None,
                };
                let bad = match single {
                    Some(i) => {
                        eval_column(system, t, &self.y_pert, &[i], &mut self.f_pert, evaluations)?
                    }
                    None => eval(system, t, &self.y_pert, &mut self.f_pert, evaluations)?,
                };
                for &b in group {
                    let r = self.layout.blocks[b].clone();
                    if j >= r.len() {
                        continue;
                    }
                    let i = r.start + j;
                    let delta = self.y_pert[i] - y[i];
                    let m = r.len();
                    for (row, k) in r.clone().enumerate() {
                        self.jac[b][row * m + j] =
                            fd_entry(self.f_pert[k], f0[k], delta, bad.is_some());
                    }
                    self.y_pert[i] = y[i];
                }
            }
        }
        self.factored_for = 0.0;
        Ok(())
    }

    /// [`Self::evaluate`] of the one dense block with colours (module
    /// docs, "Colours"): column j of every member of a colour in one
    /// evaluation, each member reading its own rows (the others of its
    /// columns are zero); the columns in no colour one at a time.
    fn evaluate_colored<S: OdeSystem>(
        &mut self,
        system: &mut S,
        t: f64,
        y: &[f64],
        f0: &[f64],
        evaluations: &mut u64,
    ) -> Result<(), IntegratorError<S::Error>> {
        let n = y.len();
        let jac = &mut self.jac[0];
        let mut colored = vec![false; n];
        let mut changed = Vec::new();
        for color in &self.layout.colors {
            for j in 0..color.width() {
                changed.clear();
                for m in color.members.iter().filter(|m| j < m.columns.len()) {
                    let i = m.columns.start + j;
                    self.y_pert[i] = y[i] + fd_step(y[i]);
                    changed.push(i);
                }
                let bad = eval_column(
                    system,
                    t,
                    &self.y_pert,
                    &changed,
                    &mut self.f_pert,
                    evaluations,
                )?;
                for m in color.members.iter().filter(|m| j < m.columns.len()) {
                    let i = m.columns.start + j;
                    let delta = self.y_pert[i] - y[i];
                    for row in 0..n {
                        jac[row * n + i] = 0.0;
                    }
                    for row in m.rows.iter().flat_map(|r| r.clone()) {
                        jac[row * n + i] =
                            fd_entry(self.f_pert[row], f0[row], delta, bad.is_some());
                    }
                    self.y_pert[i] = y[i];
                    colored[i] = true;
                }
            }
        }
        for i in (0..n).filter(|&i| !colored[i]) {
            self.y_pert[i] = y[i] + fd_step(y[i]);
            let bad = eval_column(system, t, &self.y_pert, &[i], &mut self.f_pert, evaluations)?;
            let delta = self.y_pert[i] - y[i];
            for row in 0..n {
                jac[row * n + i] = fd_entry(self.f_pert[row], f0[row], delta, bad.is_some());
            }
            self.y_pert[i] = y[i];
        }
        self.factored_for = 0.0;
        Ok(())
    }

    /// The 1/(hγ) W is factored for, when it lies within
    /// [`W_REUSE_ROUND_OFF`] (relative) of `inv_h_gamma`.
    pub(super) fn factored_near(&self, inv_h_gamma: f64) -> Option<f64> {
        let f = self.factored_for;
        (f > 0.0 && (f - inv_h_gamma).abs() <= W_REUSE_ROUND_OFF * inv_h_gamma).then_some(f)
    }

    /// LU-factorise W = I·`inv_h_gamma` − J block by block (unless already
    /// done for this value). Returns false when a block is singular.
    pub(super) fn factor(&mut self, inv_h_gamma: f64) -> bool {
        if self.factored_for == inv_h_gamma {
            return true;
        }
        if let Some(red) = &mut self.reduction {
            let ok = red.factor(&self.jac[0], self.y_pert.len(), inv_h_gamma);
            self.factored_for = if ok { inv_h_gamma } else { 0.0 };
            return ok;
        }
        for b in 0..self.layout.blocks.len() {
            let m = self.layout.blocks[b].len();
            let lu = &mut self.lu[b];
            for (w, j) in lu.iter_mut().zip(&self.jac[b]) {
                *w = -j;
            }
            for d in 0..m {
                lu[d * m + d] += inv_h_gamma;
            }
            if !lu_in_place(lu, m, &mut self.pivots[b]) {
                self.factored_for = 0.0;
                return false;
            }
        }
        self.factored_for = inv_h_gamma;
        true
    }

    /// Factorisations that fell back from the block elimination to the
    /// dense LU ([`super::body_blocks`]).
    pub(super) fn dense_fallbacks(&self) -> u64 {
        self.reduction
            .as_ref()
            .map_or(0, KinematicReduction::dense_fallbacks)
    }

    /// Solves W x = v in place (after [`Self::factor`] with `inv_h_gamma`).
    pub(super) fn solve(&mut self, inv_h_gamma: f64, v: &mut [f64]) {
        if let Some(red) = &mut self.reduction {
            red.solve(inv_h_gamma, v);
            return;
        }
        let h_gamma = 1.0 / inv_h_gamma;
        // Rows outside the blocks: W = I/(hγ).
        for &i in &self.outside {
            v[i] *= h_gamma;
        }
        for b in 0..self.layout.blocks.len() {
            let r = self.layout.blocks[b].clone();
            let m = r.len();
            let x = &mut self.rhs_scratch[..m];
            x.copy_from_slice(&v[r.clone()]);
            lu_solve(&self.lu[b], m, &self.pivots[b], x);
            v[r].copy_from_slice(x);
        }
    }
}

/// One forward-difference entry (f_pert − f0)/δ; zero when the perturbed
/// evaluation or the entry is not finite (that column is then treated
/// explicitly; the step's error control sees the trouble, if any, in the
/// stages themselves).
fn fd_entry(f_pert: f64, f0: f64, delta: f64, bad: bool) -> f64 {
    let d = (f_pert - f0) / delta;
    if bad || !d.is_finite() { 0.0 } else { d }
}

/// The forward-difference increment for a component of value `y`.
fn fd_step(y: f64) -> f64 {
    let delta = FD_RELATIVE_STEP * y.abs().max(1.0);
    // Make y + δ − y exact in floating point.
    (y + delta) - y
}

/// In-place LU with partial pivoting of the row-major m×m `a` (Golub & Van
/// Loan Alg. 3.4.1): L (unit, below the diagonal) and U overwrite `a`,
/// `piv[k]` is the row swapped with row k. False when a pivot is zero or
/// not finite.
pub(super) fn lu_in_place(a: &mut [f64], m: usize, piv: &mut [usize]) -> bool {
    for k in 0..m {
        let mut p = k;
        let mut best = a[k * m + k].abs();
        for r in k + 1..m {
            let v = a[r * m + k].abs();
            if v > best {
                best = v;
                p = r;
            }
        }
        if !(best.is_finite() && best > 0.0) {
            return false;
        }
        piv[k] = p;
        if p != k {
            let (upper, lower) = a.split_at_mut(p * m);
            upper[k * m..(k + 1) * m].swap_with_slice(&mut lower[..m]);
        }
        let inv = 1.0 / a[k * m + k];
        // Rows below k: the pivot row's tail (row k, columns k+1..) is
        // subtracted from each, an axpy on contiguous slices.
        let (head, tail) = a.split_at_mut((k + 1) * m);
        let pivot_row = &head[k * m + k + 1..(k + 1) * m];
        for row in tail.chunks_exact_mut(m) {
            let l = row[k] * inv;
            row[k] = l;
            if l != 0.0 {
                for (x, &u) in row[k + 1..].iter_mut().zip(pivot_row) {
                    *x -= l * u;
                }
            }
        }
    }
    true
}

/// Σ a_i b_i with four partial sums, so that the compiler may use vector
/// instructions (the order of the additions is fixed, the result
/// deterministic).
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0; 4];
    for (x, y) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        for l in 0..4 {
            acc[l] += x[l] * y[l];
        }
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    let tail = n - n % 4;
    for (x, y) in a[tail..].iter().zip(&b[tail..]) {
        s += x * y;
    }
    s
}

/// Solves (LU) x = P b in place with the factors of [`lu_in_place`].
pub(super) fn lu_solve(lu: &[f64], m: usize, piv: &[usize], x: &mut [f64]) {
    for (k, &p) in piv.iter().enumerate().take(m) {
        x.swap(k, p);
    }
    for r in 1..m {
        let s = dot(&lu[r * m..r * m + r], &x[..r]);
        x[r] -= s;
    }
    for r in (0..m).rev() {
        let (head, tail) = x.split_at_mut(r + 1);
        let s = dot(&lu[r * m + r + 1..(r + 1) * m], tail);
        head[r] = (head[r] - s) / lu[r * m + r];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lu_solves_a_pivoting_system() {
        // A zero leading pivot forces a swap.
        let a0 = [0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0];
        let mut a = a0;
        let mut piv = [0; 3];
        assert!(lu_in_place(&mut a, 3, &mut piv));
        let x_true = [1.0, -2.0, 0.5];
        let mut b = [0.0; 3];
        for r in 0..3 {
            for c in 0..3 {
                b[r] += a0[r * 3 + c] * x_true[c];
            }
        }
        lu_solve(&a, 3, &piv, &mut b);
        for (x, t) in b.iter().zip(x_true) {
            assert!((x - t).abs() < 1e-14, "{x} vs {t}");
        }
        let mut singular = [1.0, 2.0, 2.0, 4.0];
        assert!(!lu_in_place(&mut singular, 2, &mut [0; 2]));
    }

    /// A 40 × 40 system (the bogie's size) with a dominant but not
    /// diagonal structure: the residual of the solve is at rounding level.
    #[test]
    fn lu_solves_a_bogie_sized_system() {
        let m = 40;
        let mut a0 = vec![0.0; m * m];
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for r in 0..m {
            for c in 0..m {
                a0[r * m + c] = next() * if (r + 7) % m == c { 50.0 } else { 1.0 };
            }
        }
        let x_true: Vec<f64> = (0..m).map(|i| (i as f64 * 0.37).sin()).collect();
        let b: Vec<f64> = (0..m)
            .map(|r| (0..m).map(|c| a0[r * m + c] * x_true[c]).sum())
            .collect();
        let mut a = a0.clone();
        let mut piv = vec![0; m];
        assert!(lu_in_place(&mut a, m, &mut piv));
        let mut x = b.clone();
        lu_solve(&a, m, &piv, &mut x);
        for (xi, ti) in x.iter().zip(&x_true) {
            assert!((xi - ti).abs() < 1e-12, "{xi} vs {ti}");
        }
        assert_eq!(dot(&[1.0, 2.0, 3.0, 4.0, 5.0], &[1.0; 5]), 15.0);
        assert_eq!(dot(&[], &[]), 0.0);
    }

    /// A chain of three pairs: f_k = A y with pair 1 coupled to pairs 0
    /// and 2, pairs 0 and 2 not to each other; a pair's columns change its
    /// own rows and pair 1's (pair 1's: all rows).
    struct Chain;

    const CHAIN: [[f64; 6]; 6] = [
        [-3.0, 1.0, 0.5, 0.0, 0.0, 0.0],
        [2.0, -4.0, 0.0, 0.25, 0.0, 0.0],
        [0.5, 0.0, -5.0, 1.0, 0.75, 0.0],
        [0.0, 0.25, 1.0, -6.0, 0.0, 0.5],
        [0.0, 0.0, 0.75, 0.0, -7.0, 2.0],
        [0.0, 0.0, 0.0, 0.5, 1.0, -8.0],
    ];

    impl OdeSystem for Chain {
        type Error = std::convert::Infallible;
        fn rhs(&mut self, _t: f64, y: &[f64], dydt: &mut [f64]) -> Result<(), Self::Error> {
            for (row, d) in CHAIN.iter().zip(dydt.iter_mut()) {
                *d = row.iter().zip(y).map(|(a, v)| a * v).sum();
            }
            Ok(())
        }
        fn accept(&mut self, _t: f64, _y: &[f64]) -> Result<super::super::Control, Self::Error> {
            Ok(super::super::Control::Continue)
        }
    }

    #[test]
    #[allow(clippy::single_range_in_vec_init)]
    fn coloured_columns_give_the_dense_jacobian() {
        let y = [0.1, -0.2, 0.3, 0.4, -0.5, 0.6];
        let mut f0 = [0.0; 6];
        Chain.rhs(0.0, &y, &mut f0).unwrap();
        let mut dense = BlockJacobian::new(JacobianBlocks::dense(6), 6);
        let (mut e_dense, mut e_col) = (0, 0);
        dense
            .evaluate(&mut Chain, 0.0, &y, &f0, &mut e_dense)
            .unwrap();
        let layout = JacobianBlocks {
            colors: vec![ColumnColor {
                members: vec![
                    ColoredColumns {
                        columns: 0..2,
                        rows: vec![0..4],
                    },
                    ColoredColumns {
                        columns: 4..6,
                        rows: vec![4..6],
                    },
                ],
            }],
            ..JacobianBlocks::dense(6)
        };
        // `layout` is wrong: columns 4..6 act on rows 2..4 as well (row 2
        // holds 0.75·y_4), so pairing them with columns 0..2 mixes both
        // into rows 2..4. The right declaration (columns 0..2 alone, rows
        // 0..4) gives the dense Jacobian bit for bit: colouring is only as
        // right as the system's declared rows.
        let right = JacobianBlocks {
            colors: vec![ColumnColor {
                members: vec![ColoredColumns {
                    columns: 0..2,
                    rows: vec![0..4],
                }],
            }],
            ..JacobianBlocks::dense(6)
        };
        for (l, expect_equal) in [(right, true), (layout, false)] {
            l.check(6).unwrap();
            let mut col = BlockJacobian::new(l, 6);
            col.evaluate(&mut Chain, 0.0, &y, &f0, &mut e_col).unwrap();
            let same = col.jac[0]
                .iter()
                .zip(&dense.jac[0])
                .all(|(a, b)| a.to_bits() == b.to_bits());
            assert_eq!(same, expect_equal);
        }
        assert_eq!(e_dense, 6);
        // Right: 2 coloured + 4 single; wrong: 2 joint + 2 single.
        assert_eq!(e_col, 6 + 4);
    }

    #[test]
    #[allow(clippy::single_range_in_vec_init)]
    fn the_layout_rules_are_checked() {
        assert!(JacobianBlocks::dense(4).check(4).is_ok());
        let overlap = JacobianBlocks {
            blocks: vec![0..3, 2..4],
            groups: vec![vec![0], vec![1]],
            kinematics: Vec::new(),
            colors: Vec::new(),
        };
        assert_eq!(overlap.check(4), Err("the blocks must be disjoint"));
        let twice = JacobianBlocks {
            blocks: vec![0..2, 2..4],
            groups: vec![vec![0, 1], vec![1]],
            kinematics: Vec::new(),
            colors: Vec::new(),
        };
        assert_eq!(
            twice.check(4),
            Err("every block must be in exactly one group")
        );
        #[allow(clippy::single_range_in_vec_init)]
        let outside = JacobianBlocks {
            blocks: vec![0..5],
            groups: vec![vec![0]],
            kinematics: Vec::new(),
            colors: Vec::new(),
        };
        assert!(outside.check(4).is_err());
        let grouped = JacobianBlocks {
            blocks: vec![0..3, 3..5, 6..7],
            groups: vec![vec![0, 1], vec![2]],
            kinematics: Vec::new(),
            colors: Vec::new(),
        };
        assert_eq!(grouped.check(8), Ok(()));
        assert_eq!(grouped.evaluations(), 3 + 1);
        // Colours: two members with disjoint rows share the evaluations of
        // the wider; column 6 stays alone.
        let member =
            |columns: Range<usize>, rows: Vec<Range<usize>>| ColoredColumns { columns, rows };
        let coloured = JacobianBlocks {
            colors: vec![ColumnColor {
                members: vec![member(0..3, vec![0..3]), member(3..5, vec![3..6])],
            }],
            ..JacobianBlocks::dense(7)
        };
        assert_eq!(coloured.check(7), Ok(()));
        assert_eq!(coloured.evaluations(), 3 + 2);
        let shared_rows = JacobianBlocks {
            colors: vec![ColumnColor {
                members: vec![member(0..3, vec![0..4]), member(3..5, vec![3..6])],
            }],
            ..JacobianBlocks::dense(7)
        };
        assert_eq!(
            shared_rows.check(7),
            Err("the members of a colour must change disjoint rows")
        );
        let not_dense = JacobianBlocks {
            colors: coloured.colors.clone(),
            ..grouped.clone()
        };
        assert_eq!(
            not_dense.check(8),
            Err("colours need one dense block over the whole state")
        );
    }
}
