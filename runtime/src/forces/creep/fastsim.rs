//! FASTSIM: Kalker's simplified theory of rolling contact on the Hertz
//! ellipse (J. J. Kalker, "A fast algorithm for the simplified theory of
//! rolling contact", *Vehicle System Dynamics* 11 (1982) 1–13).
//!
//! # Model (simplified theory)
//!
//! The elastic displacement difference at a point of the contact patch is
//! taken proportional to the traction there, u = L p, with one flexibility
//! L (m/Pa) per kind of creepage (Kalker 1982; the "three flexibilities"
//! variant, CONTACT's `M = 3`). Kalker's choice of the flexibilities makes the
//! small-creepage limit of the longitudinal and lateral forces equal
//! Kalker's linear theory (`kalker.rs`, docs/reference/07-contact-forces.md §7.3) for any ellipse:
//!
//! ```text
//! L1 = 8a / (3 C11 G),    L2 = 8a / (3 C22 G),    L3 = π a √(a/b) / (4 C23 G)
//! ```
//!
//! (Kalker 1982; the same formulas are in the open CONTACT code,
//! `m_hertz.f90`, routine `simpflex`). C11, C22, C23 are Kalker's coefficients
//! from [`super::kalker_coefficients`] for a/b and ν of the input.
//!
//! # Frame, rolling direction, signs (docs/reference/01-units-frames.md §1)
//!
//! x is the rolling direction `t_c`, y the lateral `l_c`, both from the
//! centre of the ellipse; a is the semi-axis along x, b along y. The wheel
//! rolls forward in +`t_c`, so in the contact-fixed frame the material
//! flows through the patch with velocity −V: a particle **enters at the
//! leading edge x = +a(y)** and leaves at x = −a(y), a(y) = a√(1 − y²/b²).
//! The rigid slip of the wheel relative to the rail over the rolling speed
//! is w = (ξ − φy, η + φx) (docs/reference/07-contact-forces.md §7.3 creepages; the same signs as the
//! CONTACT user guide's rigid slip, eq. `rig_shift_roll`). With p the traction **on the
//! wheel** and the steady-state slip s = w − L ∂p/∂x, a particle that
//! adheres (s = 0) builds up traction as it travels from the leading edge:
//!
//! ```text
//! ∂p_x/∂x = ξ/L1 − φ y/L3,    ∂p_y/∂x = η/L2 + φ x/L3,    p = 0 at x = +a(y)
//! ```
//!
//! so p opposes the slip: Fx = −G a b C11 ξ in the linear limit, the sign of
//! docs/reference/07-contact-forces.md §7.3. Where |p| would exceed the traction bound g = μ p_n the
//! particle slips and p = −g s/|s| (Coulomb).
//!
//! # Algorithm (Kalker 1982)
//!
//! The ellipse is cut into [`FastsimParams::strips`] strips of equal width
//! 2b/n_y across y; the strip through y_i (its centre) has half-length
//! a_i = a(y_i) and is cut into [`FastsimParams::elements_per_strip`]
//! elements of equal length dx_i = 2a_i/n_x. Tractions live at the element
//! centres x_j = a_i − (j − ½) dx_i (as in Kalker's and CONTACT's element
//! schemes). Marching from the leading edge (p = 0) to centre j over a step
//! of length h (h = dx_i/2 for the first element, dx_i after):
//!
//! 1. predictor (elastic increment; the rigid slip is linear in x, so its
//!    value at the middle of the step integrates it exactly):
//!    p* = p_{j−1} − h (ξ/L1 − φ y_i/L3, η/L2 + φ x_mid/L3);
//! 2. slip update: if |p*| ≤ g(x_j, y_i) the element adheres, p_j = p*;
//!    otherwise it slips, p_j = g p*/|p*| (the traction is scaled back onto
//!    the bound along the predictor; this is the implicit form of
//!    p = −g s/|s|, since s ∥ p* − p_j ∥ −p*).
//!
//! Forces and spin moment are the element sums (midpoint rule per element,
//! area dx_i · 2b/n_y):
//!
//! ```text
//! Fx = Σ p_x dA,   Fy = Σ p_y dA,   Mz = Σ (x p_y − y p_x) dA
//! ```
//!
//! Mz is about the normal `n_c` through the centre of the ellipse, on the
//! wheel. Everything is a loop over the grid: no allocation, cost
//! ∝ strips × elements.
//!
//! # Traction bound ([`TractionBound`])
//!
//! - [`TractionBound::Parabolic`] (default): p_n = (2N/(πab))(1 − x²/a² −
//!   y²/b²), the bound of Kalker's 1982 FASTSIM ("the original Fastsim
//!   algorithm with parabolic traction bound", CONTACT user guide, section
//!   "Calculation of creep force curves"; CONTACT `B = 3`).
//! - [`TractionBound::Ellipsoidal`]: the Hertz pressure p_n =
//!   (3N/(2πab))√(1 − x²/a² − y²/b²) (CONTACT `B = 2`).
//!
//! In both, the peak value is replaced by the one that makes the **discrete**
//! pressure sum over the grid equal N exactly (it tends to the continuum
//! value as the grid is refined; on the default grid it differs from it by
//! 0.06 % parabolic, 0.26 % ellipsoidal).
//! Then |(Fx, Fy)| ≤ μN holds to rounding on any grid, and full sliding gives
//! exactly μN, so a coarse grid never shifts the saturation level.
//!
//! # Limits and known properties
//!
//! - Small creepage: the continuum FASTSIM gives exactly Kalker's Fx
//!   (C11) and Fy (C22, C23). Its spin moment is **not** Kalker's: it gives
//!   Mz = G c^3 [R_η C23 η] − G c^4 [R_φ C33 φ] (c = √(ab)) with
//!
//!   ```text
//!   R_η = (3π/32) (C22/C23) √(a/b),        R_φ = (32/(15π)) (C23/C33) (b/a)^1.5
//!   ```
//!
//!   (derived here by integrating the adhesion tractions above over the
//!   ellipse). For ν = 0.28: R_η = 0.73, R_φ = 0.85 for a circle; 0.62, 0.96
//!   for a/b = 1/3; 0.79, 0.78 for a/b = 3. This is a property of the
//!   simplified theory with L3 chosen to reproduce C23 in Fy; it is reported
//!   (and tested against the formula), not forced.
//! - Full sliding without spin: every element slides along (ξ/L1, η/L2), so
//!   the force is μN along −(C11 ξ, C22 η): with three flexibilities it is
//!   exactly opposite to the slip (ξ, η) only if C11 = C22 or one creepage is
//!   zero (a few degrees off for steel; CONTACT's current FASTSIM blends the
//!   flexibilities towards a single one at large creepage for this reason,
//!   `m_hertz.f90` routine `simpflex`; not done here).
//! - Pure longitudinal (or lateral) creepage has closed forms for the
//!   continuum model: with the ellipsoidal bound the total force is
//!   F/μN = (2/π)[atan r + r/(1 + r²)], r = πGabC11|ξ|/(4μN) — Polach's
//!   (1999) formula (docs/reference/07-contact-forces.md §7.3), which is therefore FASTSIM's continuum limit;
//!   with the parabolic bound it is an elementary expression in
//!   u = 3πGabC11|ξ|/(32μN) that reaches μN at u = 1 (derived and checked in
//!   `tests/fastsim_reference.rs`).
//! - Odd in the creepages, exactly (the grid is symmetric and every step is
//!   linear in the creepages up to the scaling onto the bound).
//!
//! # Accuracy and default discretisation
//!
//! Pure creepage converges at second order in the grid (parabolic bound;
//! about 1.6 with the ellipsoidal bound, whose square root limits the
//! midpoint rule at the edges). With spin the slip direction turns along a
//! strip and Kalker's slip update is first order in the element length
//! (Vollebregt & Wilders' FASTSIM2, *Comput. Mech.* 47 (2011) 105–116, was
//! designed to lift this); the strip width still enters at second order.
//! Hence the default of 16 strips × 64 elements, chosen by measuring
//! accuracy against a 200 × 200 run and cost (`tests/fastsim_reference.rs`,
//! `#[ignore]`d test `discretisation_study`; figures in
//! [`FastsimParams::default`]).

use std::f64::consts::PI;

use super::{CreepError, CreepForces, CreepInput, KalkerCoefficients, kalker_coefficients};

/// Pressure distribution used as the traction bound g = μ p_n (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TractionBound {
    /// p_n ∝ 1 − x²/a² − y²/b², Kalker's 1982 FASTSIM bound (default).
    #[default]
    Parabolic,
    /// p_n ∝ √(1 − x²/a² − y²/b²), the Hertz pressure.
    Ellipsoidal,
}

/// FASTSIM parameters: the discretisation of the ellipse and the traction
/// bound (module docs). Checked by [`FastsimParams::validate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FastsimParams {
    /// Number of strips of equal width across the ellipse, along the lateral
    /// axis y (`l_c`); 1 ≤ strips ≤ [`FastsimParams::MAX_DIVISIONS`].
    pub strips: usize,
    /// Number of elements of equal length along each strip, in the rolling
    /// direction x (`t_c`); 1 ≤ elements ≤ [`FastsimParams::MAX_DIVISIONS`].
    pub elements_per_strip: usize,
    /// Pressure distribution of the traction bound.
    pub traction_bound: TractionBound,
}

impl Default for FastsimParams {
    /// 16 strips × 64 elements per strip, parabolic bound (Kalker 1982).
    ///
    /// Chosen from the `discretisation_study` in
    /// `tests/fastsim_reference.rs`: 45 creepage combinations (pure ξ, η, φ
    /// and mixtures, from the linear range to full sliding: ξ*, η*, φ* from
    /// 0.1 to 3 in units of the linear-theory force over μN) on ellipses
    /// a/b = 0.3, 1, 3, ν = 0.28, compared with a 200 × 200 run of the same
    /// bound. Largest error over all cases, forces in units of μN, Mz in
    /// units of μN√(ab); cost per call in a release build on the development
    /// machine (one core of a virtualised Xeon; about 5.3 ns per element):
    ///
    /// | strips × elements | force error (parab. / ellips.) | Mz error (parab. / ellips.) | cost |
    /// |---|---|---|---|
    /// | 12 × 12 | 3.9e-2 / 3.8e-2 | 9.1e-3 / 8.0e-3 | 0.9 µs |
    /// | 24 × 24 | 2.2e-2 / 2.1e-2 | 6.0e-3 / 4.4e-3 | 3.2 µs |
    /// | 48 × 48 | 8.7e-3 / 8.6e-3 | 3.0e-3 / 2.3e-3 | 12 µs |
    /// | 8 × 16 | 3.4e-2 / 3.2e-2 | 1.1e-2 / 1.5e-2 | 0.8 µs |
    /// | 12 × 32 | 1.4e-2 / 1.3e-2 | 4.2e-3 / 6.2e-3 | 2.1 µs |
    /// | 16 × 48 | 1.0e-2 / 8.5e-3 | 2.7e-3 / 2.9e-3 | 4.1 µs |
    /// | **16 × 64** | **7.7e-3 / 6.0e-3** | **1.8e-3 / 3.0e-3** | **5.4 µs** |
    /// | 20 × 80 | 6.7e-3 / 5.5e-3 | 1.4e-3 / 1.7e-3 | 8.4 µs |
    /// | 24 × 96 | 5.1e-3 / 4.6e-3 | 1.0e-3 / 1.2e-3 | 12 µs |
    /// | 32 × 128 | 2.7e-3 / 2.3e-3 | 5.4e-4 / 6.6e-4 | 21 µs |
    ///
    /// The error is largest with spin, where Kalker's slip update is first
    /// order in the element length (the slip direction turns along a strip),
    /// while the strip width enters at second order: more elements per strip
    /// than strips buys the most accuracy per element. 16 × 64 keeps the
    /// worst case under 0.8 % of μN (pure creepage: 6e-4 parabolic, 1e-3
    /// ellipsoidal) — well inside the simplified theory's own deviation from
    /// the exact theory — at about twice the cost of 24 × 24, which is three
    /// times less accurate.
    fn default() -> Self {
        FastsimParams {
            strips: 16,
            elements_per_strip: 64,
            traction_bound: TractionBound::Parabolic,
        }
    }
}

impl FastsimParams {
    /// Largest accepted number of strips or elements per strip (a 2000 ×
    /// 2000 grid already costs milliseconds per call).
    pub const MAX_DIVISIONS: usize = 2000;

    /// `strips` × `elements_per_strip` with Kalker's parabolic bound.
    pub fn parabolic(strips: usize, elements_per_strip: usize) -> Self {
        FastsimParams {
            strips,
            elements_per_strip,
            traction_bound: TractionBound::Parabolic,
        }
    }

    /// `strips` × `elements_per_strip` with the Hertz (ellipsoidal) bound.
    pub fn ellipsoidal(strips: usize, elements_per_strip: usize) -> Self {
        FastsimParams {
            strips,
            elements_per_strip,
            traction_bound: TractionBound::Ellipsoidal,
        }
    }

    /// Checks that both divisions lie in 1 ..= [`Self::MAX_DIVISIONS`].
    pub fn validate(&self) -> Result<(), CreepError> {
        validate_divisions("FASTSIM", self.strips, self.elements_per_strip)
    }
}

/// The grid rule of FASTSIM and FaStrip: strips and elements per strip in
/// 1 ..= [`FastsimParams::MAX_DIVISIONS`]; `law` names the law in the error.
pub(super) fn validate_divisions(
    law: &'static str,
    strips: usize,
    elements_per_strip: usize,
) -> Result<(), CreepError> {
    for (parameter, n) in [
        ("strips", strips),
        ("elements_per_strip", elements_per_strip),
    ] {
        if !(1..=FastsimParams::MAX_DIVISIONS).contains(&n) {
            return Err(CreepError::InvalidParameter {
                law,
                parameter,
                value: n as f64,
                rule: "must be an integer from 1 to 2000",
            });
        }
    }
    Ok(())
}

/// The three flexibilities of the simplified theory (m/Pa), Kalker 1982
/// (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Flexibilities {
    /// L1 = 8a/(3 C11 G), longitudinal creepage.
    pub(super) l1_m_pa: f64,
    /// L2 = 8a/(3 C22 G), lateral creepage.
    pub(super) l2_m_pa: f64,
    /// L3 = π a √(a/b)/(4 C23 G), spin.
    pub(super) l3_m_pa: f64,
}

impl Flexibilities {
    /// Kalker's flexibilities for semi-axes `a_m` (rolling) and `b_m`
    /// (lateral), shear modulus `g_pa` and coefficients `c`.
    pub(super) fn kalker(a_m: f64, b_m: f64, g_pa: f64, c: &KalkerCoefficients) -> Self {
        Flexibilities {
            l1_m_pa: 8.0 * a_m / (3.0 * c.c11 * g_pa),
            l2_m_pa: 8.0 * a_m / (3.0 * c.c22 * g_pa),
            l3_m_pa: PI * a_m * (a_m / b_m).sqrt() / (4.0 * c.c23 * g_pa),
        }
    }
}

/// Shape of the bound along one normalised axis, s ∈ [−1, 1]: the bound is
/// p_n(x, y) = p̂ σ(y/b) σ(x/a(y)) for both distributions, since
/// 1 − x²/a² − y²/b² = (1 − y²/b²)(1 − x²/a(y)²).
fn shape(bound: TractionBound, s: f64) -> f64 {
    let q = (1.0 - s * s).max(0.0);
    match bound {
        TractionBound::Parabolic => q,
        TractionBound::Ellipsoidal => q.sqrt(),
    }
}

/// Continuum peak pressure p̂ (Pa) of each bound for normal force N over the
/// ellipse a × b: 2N/(πab) parabolic, 3N/(2πab) ellipsoidal (Hertz).
#[cfg(test)]
fn continuum_peak_pressure_pa(bound: TractionBound, n_n: f64, a_m: f64, b_m: f64) -> f64 {
    match bound {
        TractionBound::Parabolic => 2.0 * n_n / (PI * a_m * b_m),
        TractionBound::Ellipsoidal => 3.0 * n_n / (2.0 * PI * a_m * b_m),
    }
}

/// Peak pressure p̂ (Pa) that makes the discrete pressure sum over the
/// `p` grid equal `n_n` (module docs, "Traction bound").
///
/// Every strip uses the same normalised centres t_j = 1 − (2j − 1)/n_x, so
/// Σ_i Σ_j σ(s_i) σ(t_j) dx_i dy = (Σ_j σ(t_j)) · Σ_i σ(s_i) (2a_i/n_x) dy.
fn discrete_peak_pressure_pa(p: &FastsimParams, n_n: f64, a_m: f64, b_m: f64) -> f64 {
    let (nx, ny) = (p.elements_per_strip, p.strips);
    let mut sum_x = 0.0;
    for j in 1..=nx {
        sum_x += shape(p.traction_bound, element_centre(j, nx));
    }
    let dy = 2.0 * b_m / ny as f64;
    let mut sum_y = 0.0;
    for i in 1..=ny {
        let s = element_centre(i, ny);
        sum_y += shape(p.traction_bound, s) * half_chord(s) * (2.0 * a_m / nx as f64) * dy;
    }
    n_n / (sum_x * sum_y)
}

/// Normalised centre 1 − (2k − 1)/n of element k of n (k = 1 at +1).
pub(super) fn element_centre(k: usize, n: usize) -> f64 {
    1.0 - (2.0 * k as f64 - 1.0) / n as f64
}

/// √(1 − s²): half-length of the strip at normalised lateral position s, in
/// units of a.
pub(super) fn half_chord(s: f64) -> f64 {
    (1.0 - s * s).max(0.0).sqrt()
}

/// Spin-moment ratios of the continuum simplified theory to Kalker's linear
/// theory in the small-creepage limit (module docs): (R_η, R_φ), with
/// Mz = R_η · G(ab)^1.5 C23 η − R_φ · G(ab)² C33 φ.
#[cfg(test)]
pub(crate) fn linear_spin_moment_ratios(a_over_b: f64, c: &KalkerCoefficients) -> (f64, f64) {
    let r_eta = 3.0 * PI / 32.0 * c.c22 / c.c23 * a_over_b.sqrt();
    let r_phi = 32.0 / (15.0 * PI) * c.c23 / c.c33 * a_over_b.powf(-1.5);
    (r_eta, r_phi)
}

/// FASTSIM forces on the wheel (module docs). `input` is validated and has
/// N > 0; `p` is checked here as well (it bounds the loop lengths). μ = 0 or
/// zero creepages give zero force.
pub(crate) fn forces(input: &CreepInput, p: &FastsimParams) -> Result<CreepForces, CreepError> {
    p.validate()?;
    let mu = input.friction_coefficient;
    let (xi, eta, phi) = (input.xi, input.eta, input.phi_1_m);
    if input.normal_force_n == 0.0 || mu == 0.0 || (xi == 0.0 && eta == 0.0 && phi == 0.0) {
        return Ok(CreepForces::ZERO);
    }
    let (a, b) = (input.a_m, input.b_m);
    let c = kalker_coefficients(a / b, input.poisson)?;
    let flex = Flexibilities::kalker(a, b, input.shear_modulus_pa, &c);
    let rates = SlipRates {
        xi: xi / flex.l1_m_pa,
        eta: eta / flex.l2_m_pa,
        phi: phi / flex.l3_m_pa,
    };
    let bound_peak_pa = mu * discrete_peak_pressure_pa(p, input.normal_force_n, a, b);

    let ny = p.strips;
    let dy = 2.0 * b / ny as f64;
    let mut total = CreepForces::ZERO;
    let mut add = |y: f64, sums: StripSums, a_i: f64| {
        let area = 2.0 * a_i / p.elements_per_strip as f64 * dy;
        total.fx_n += sums.px * area;
        total.fy_n += sums.py * area;
        total.mz_nm += (sums.x_py - y * sums.px) * area;
    };
    // Strips in symmetric pairs (y, −y), two pairs per pass: four
    // independent recurrences in one loop hide the latency of the slip
    // update (a square root and a division on the critical path); the
    // last pair and the middle strip of an odd count on their own.
    let strip = |i: usize| {
        let s = element_centre(i, ny);
        (
            s * b,
            a * half_chord(s),
            bound_peak_pa * shape(p.traction_bound, s),
        )
    };
    let pairs = ny / 2;
    let mut i = 1;
    while i < pairs {
        let (y1, a1, g1) = strip(i);
        let (y2, a2, g2) = strip(i + 1);
        let sums = march(
            [y1, -y1, y2, -y2],
            [a1, a1, a2, a2],
            [g1, g1, g2, g2],
            &rates,
            p,
        );
        for (k, (y, a_i)) in [(y1, a1), (-y1, a1), (y2, a2), (-y2, a2)]
            .into_iter()
            .enumerate()
        {
            add(y, sums[k], a_i);
        }
        i += 2;
    }
    if i <= pairs {
        let (y, a_i, g) = strip(i);
        let [upper, lower] = march([y, -y], [a_i; 2], [g; 2], &rates, p);
        add(y, upper, a_i);
        add(-y, lower, a_i);
    }
    if ny % 2 == 1 {
        let [middle] = march([0.0], [a], [bound_peak_pa], &rates, p);
        add(0.0, middle, a);
    }
    Ok(total)
}

/// Rigid slip over flexibility (Pa/m): ξ/L1, η/L2, φ/L3.
#[derive(Debug, Clone, Copy)]
struct SlipRates {
    xi: f64,
    eta: f64,
    phi: f64,
}

/// Sums over the element centres of one strip: Σ p_x, Σ p_y (Pa) and
/// Σ x p_y (Pa·m).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct StripSums {
    px: f64,
    py: f64,
    x_py: f64,
}

/// Marches `K` independent strips at lateral positions `ys_m` (m), with
/// half-lengths `a_m` (m) and peak bounds `g_pa` (Pa, the bound at x = 0),
/// from the leading edge x = +a to the trailing edge (module docs,
/// "Algorithm").
fn march<const K: usize>(
    ys_m: [f64; K],
    a_m: [f64; K],
    g_pa: [f64; K],
    rates: &SlipRates,
    p: &FastsimParams,
) -> [StripSums; K] {
    let nx = p.elements_per_strip;
    let dt = 2.0 / nx as f64;
    let g2_peak = g_pa.map(|g| g * g);
    // d p_x/d(−x) = −(ξ/L1 − φ y/L3) is constant along a strip.
    let rate_x = ys_m.map(|y| rates.xi - rates.phi * y);
    let mut px = [0.0_f64; K];
    let mut py = [0.0_f64; K];
    let mut sums = [StripSums::default(); K];
    let mut t_prev = 1.0;
    for j in 1..=nx {
        // Normalised centre t = x/a of element j and middle of the step.
        let t = 1.0 - (j as f64 - 0.5) * dt;
        let t_mid = 0.5 * (t_prev + t);
        let dt_step = t_prev - t;
        // g² without a square root: σ² is a polynomial in t for both bounds.
        let q = (1.0 - t * t).max(0.0);
        let sigma2 = match p.traction_bound {
            TractionBound::Parabolic => q * q,
            TractionBound::Ellipsoidal => q,
        };
        for k in 0..K {
            let h = dt_step * a_m[k];
            px[k] -= h * rate_x[k];
            py[k] -= h * (rates.eta + rates.phi * t_mid * a_m[k]);
            let norm2 = px[k] * px[k] + py[k] * py[k];
            let g2 = g2_peak[k] * sigma2;
            if norm2 > g2 {
                let scale = (g2 / norm2).sqrt();
                px[k] *= scale;
                py[k] *= scale;
            }
            sums[k].px += px[k];
            sums[k].py += py[k];
            sums[k].x_py += t * a_m[k] * py[k];
        }
        t_prev = t;
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(xi: f64, eta: f64, phi_1_m: f64) -> CreepInput {
        CreepInput {
            xi,
            eta,
            phi_1_m,
            normal_force_n: 80e3,
            a_m: 6e-3,
            b_m: 4e-3,
            friction_coefficient: 0.3,
            rolling_speed_m_s: 30.0,
            shear_modulus_pa: 80.77e9,
            poisson: 0.28,
        }
    }

    #[test]
    fn validate_bounds_the_divisions() {
        assert!(FastsimParams::default().validate().is_ok());
        assert!(FastsimParams::parabolic(1, 1).validate().is_ok());
        assert!(FastsimParams::ellipsoidal(2000, 2000).validate().is_ok());
        for (s, e, name) in [
            (0, 10, "strips"),
            (10, 0, "elements_per_strip"),
            (2001, 10, "strips"),
            (10, usize::MAX, "elements_per_strip"),
        ] {
            match FastsimParams::parabolic(s, e).validate() {
                Err(CreepError::InvalidParameter { law, parameter, .. }) => {
                    assert_eq!(law, "FASTSIM");
                    assert_eq!(parameter, name);
                }
                other => panic!("{s}×{e}: {other:?}"),
            }
        }
        // `forces` refuses them too (no runaway loop if a caller skipped
        // `CreepLaw::validate`).
        assert!(forces(&input(1e-3, 0.0, 0.0), &FastsimParams::parabolic(0, 5)).is_err());
    }

    #[test]
    fn flexibilities_follow_kalker_1982() {
        let c = KalkerCoefficients {
            c11: 4.0,
            c22: 3.5,
            c23: 1.5,
            c33: 1.2,
        };
        let f = Flexibilities::kalker(8e-3, 2e-3, 80e9, &c);
        assert!((f.l1_m_pa - 8.0 * 8e-3 / (3.0 * 4.0 * 80e9)).abs() < 1e-28);
        assert!((f.l2_m_pa - 8.0 * 8e-3 / (3.0 * 3.5 * 80e9)).abs() < 1e-28);
        // √(a/b) = 2.
        assert!((f.l3_m_pa - PI * 8e-3 * 2.0 / (4.0 * 1.5 * 80e9)).abs() < 1e-28);
    }

    #[test]
    fn shapes_and_helpers() {
        for bound in [TractionBound::Parabolic, TractionBound::Ellipsoidal] {
            assert_eq!(shape(bound, 0.0), 1.0);
            assert_eq!(shape(bound, 1.0), 0.0);
            assert_eq!(shape(bound, -1.5), 0.0);
        }
        assert!((shape(TractionBound::Parabolic, 0.6) - 0.64).abs() < 1e-15);
        assert!((shape(TractionBound::Ellipsoidal, 0.6) - 0.8).abs() < 1e-15);
        assert_eq!(element_centre(1, 1), 0.0);
        assert_eq!(element_centre(1, 4), 0.75);
        assert_eq!(element_centre(4, 4), -0.75);
        assert!((half_chord(0.8) - 0.6).abs() < 1e-15);
    }

    /// The discrete peak pressure tends to the continuum value 2N/(πab)
    /// (parabolic) or 3N/(2πab) (Hertz), and is within 0.4 % of it on the
    /// default grid.
    #[test]
    fn discrete_pressure_normalisation_converges() {
        let (n, a, b) = (1e5, 7e-3, 5e-3);
        for bound in [TractionBound::Parabolic, TractionBound::Ellipsoidal] {
            let exact = continuum_peak_pressure_pa(bound, n, a, b);
            let mut last = f64::INFINITY;
            for k in [4, 8, 16, 32, 64, 128] {
                let p = FastsimParams {
                    strips: k,
                    elements_per_strip: k,
                    traction_bound: bound,
                };
                let err = (discrete_peak_pressure_pa(&p, n, a, b) / exact - 1.0).abs();
                assert!(err < last, "{bound:?} {k}: {err}");
                last = err;
            }
            assert!(last < 3e-4, "{bound:?}: {last}");
            let p = FastsimParams {
                traction_bound: bound,
                ..FastsimParams::default()
            };
            let err = (discrete_peak_pressure_pa(&p, n, a, b) / exact - 1.0).abs();
            assert!(err < 4e-3, "{bound:?} default grid: {err}");
        }
    }

    #[test]
    fn spin_moment_ratios_formula() {
        // Circle, ν = 0.25 (Table E.3: C22 = 3.67, C23 = 1.47, C33 = 1.19).
        let c = kalker_coefficients(1.0, 0.25).unwrap();
        let (r_eta, r_phi) = linear_spin_moment_ratios(1.0, &c);
        assert!((r_eta - 3.0 * PI / 32.0 * 3.67 / 1.47).abs() < 1e-12);
        assert!((r_phi - 32.0 / (15.0 * PI) * 1.47 / 1.19).abs() < 1e-12);
        assert!(r_eta > 0.7 && r_eta < 0.8 && r_phi > 0.8 && r_phi < 0.9);
    }

    #[test]
    fn zero_friction_or_creepage_gives_zero() {
        let mut i = input(1e-3, -2e-3, 0.5);
        i.friction_coefficient = 0.0;
        assert_eq!(
            forces(&i, &FastsimParams::default()).unwrap(),
            CreepForces::ZERO
        );
        let i = input(0.0, 0.0, 0.0);
        assert_eq!(
            forces(&i, &FastsimParams::default()).unwrap(),
            CreepForces::ZERO
        );
    }

    /// Pure longitudinal creepage in full adhesion near the leading edge: a
    /// 1 × n_x grid (one strip at y = 0) reproduces the linear traction
    /// growth exactly at the element centres while below the bound.
    #[test]
    fn single_strip_adhesion_is_exact() {
        let i = input(1e-7, 0.0, 0.0);
        let p = FastsimParams::parabolic(1, 10);
        let f = forces(&i, &p).unwrap();
        let c = kalker_coefficients(i.a_m / i.b_m, i.poisson).unwrap();
        let l1 = 8.0 * i.a_m / (3.0 * c.c11 * i.shear_modulus_pa);
        // One strip of width 2b through y = 0, half-length a; traction
        // −(ξ/L1)(a − x) at the centres, midpoint rule exact for a linear
        // function: ∫ = −(ξ/L1) 2a², times the width 2b.
        let want = -(i.xi / l1) * 2.0 * i.a_m * i.a_m * 2.0 * i.b_m;
        assert!((f.fx_n / want - 1.0).abs() < 1e-12, "{} vs {want}", f.fx_n);
        assert_eq!(f.fy_n, 0.0);
        assert_eq!(f.mz_nm, 0.0);
    }
}
