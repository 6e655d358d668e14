//! FaStrip: the strip theory in the adhesion zone, FASTSIM's slip direction
//! in the slip zone, on the Hertz ellipse (M. Sh. Sichani, R. Enblom,
//! M. Berg, "An alternative to FASTSIM for tangential solution of the
//! wheel–rail contact", *Vehicle System Dynamics* 54(6) (2016) 748–764).
//!
//! # Sources, and what was (not) read
//!
//! The paper itself could not be read while writing this module (it is not
//! in the stored corpora we could search, and there is no network): **no
//! equation number of the paper is cited**, and two rules below are our
//! reading of the method (marked *our reading*). What the method is, is
//! taken from the open CONTACT user guide (E. A. H. Vollebregt, Vtech CMCC
//! report 20-01, `github.com/eve70a/CONTACT`, `doc/user-guide.tex`: section
//! "Flexibilities of the simplified theory" — FaStrip "combines the
//! simplified theory with strip theory [Kalker 1966, Sichani 2016]";
//! section "The use of the FASTSIM algorithm" — FaStrip with the elliptical
//! traction bound) and from the strip theory it builds on (D. J. Haines,
//! E. Ollerton 1963; J. J. Kalker 1967; Carter's 2D solution, K. L. Johnson,
//! *Contact Mechanics*, 1985, §8.2). Every formula below is **derived
//! here** (derivation in this comment; equations (S1)–(S3) are this
//! module's numbering). CONTACT's open implementation (`src/m_solvpt.f90`,
//! routine `modif_fastrip`) was read to understand the structure; no code is
//! taken from it, and where we differ from it this is said.
//!
//! # Frame and signs
//!
//! As FASTSIM ([`super::fastsim`], docs/reference/01-units-frames.md §1): x
//! rolling direction, leading edge x = +a(y), a(y) = a√(1 − y²/b²); rigid
//! slip w = (ξ − φy, η + φx); p is the traction **on the wheel**; forces
//! oppose the slip (Fx = −G a b C11 ξ in the linear limit). FaStrip gives
//! the traction distribution, so Fx, Fy **and** the spin moment
//! Mz = ∫ (x p_y − y p_x) dA (about `n_c` through the ellipse centre) are
//! returned.
//!
//! # Strip theory on one strip (derived here)
//!
//! Each strip y = const is a 2D rolling contact under the Hertz pressure
//! p_n = (p̂/a)√(a_y² − x²) (p̂ the peak pressure, a_y = a(y)). On a
//! half-plane, the traction (q/a)√(a_y² − x²) gives a displacement-difference
//! gradient proportional to q x/a inside [−a_y, a_y], with compliance
//! k = 2(1 − ν)/G for the longitudinal (plane strain) and k = 2/G for the
//! lateral (anti-plane) component. (Check: with the 2D Hertz
//! p̂ = aG/(2R(1 − ν)) this gives Carter's ξ = μ(a − a′)/R, the formula in the
//! CONTACT user guide's "2D Carter/Fromm problem".) The adhesion zone is at
//! the leading edge, [2d − a_y, a_y] (centre d, half-length a′ = a_y − d),
//! the slip zone behind it. In the zone the traction is the difference of
//! two semi-ellipses,
//!
//! ```text
//! p = (μ p̂ / a) [ √(a_y² − x²) e − √(a′² − (x − d)²) g ]          (S1)
//! ```
//!
//! with a unit vector e (the slip zone's traction direction in the strip
//! theory). No slip on the zone (s = w − ∂u/∂x = 0), with w_x constant and
//! w_y linear in x along the strip, fixes g and d: g_x = e_x,
//! g_y = e_y + φ̂, and
//!
//! ```text
//! d e = −(ξ̂, η̂ + φ̂ d)                                               (S2)
//! (1 − φ̂²) d² − 2 η̂ φ̂ d − (ξ̂² + η̂²) = 0   (|e| = 1)
//! d = (ξ̂² + η̂²) / (√(η̂² + (1 − φ̂²) ξ̂²) − η̂ φ̂)                     (S3)
//! ```
//!
//! with the creepages measured as lengths, ξ̂ = (a/(μp̂)) (ξ/k_ξ − φ y/k_φx),
//! η̂ = (a/(μp̂)) η/k_η, and the spin as a number, φ̂ = (a/(μp̂)) φ/k_φy. (S3)
//! is the root d ≥ 0, written without a division by 1 − φ̂². The strip
//! slides fully where (S3) has no such root or d ≥ a_y. For d → 0 (S1)
//! stays finite: e multiplies √(a_y² − x²) − √(a′² − (x − d)²) → 0 (pure spin
//! at y = 0 gives p = −φ̂ μ p_n ŷ). Since √(a′² − (x − d)²) ≤ √(a_y² − x²),
//! (S1) is within the bound μ p_n on the whole zone whenever |φ̂| ≤ 1
//! (|p| ≤ μp_n ⇔ ρ|g|² ≤ 2 e·g with ρ the ratio of the two roots, and
//! |g|² ≤ 2 e·g ⇔ φ̂² ≤ 1).
//!
//! # FaStrip's creepage scaling
//!
//! Pure strip theory has the creep coefficients of a narrow ellipse:
//! C11ˢ = π²/(4(1 − ν)), C22ˢ = π²/4, C23ˢ = (π/3)√(a/b) (derived by
//! integrating (S1) in the linear limit over the ellipse; they are Kalker's
//! a/b → 0 asymptotes of `kalker.rs`, for C23 at ν = 0). FaStrip scales each
//! compliance by Cˢ/C with Kalker's coefficient C for the actual a/b and ν
//! (as FASTSIM's flexibilities do), so that the small-creepage limit of Fx,
//! Fy is Kalker's linear theory for any ellipse:
//!
//! ```text
//! k_ξ = π²/(2 G C11),   k_η = π²/(2 G C22),
//! k_φy = 2π √(a/b)/(3 G C23),   k_φx = (1 − ν) k_φy
//! ```
//!
//! so φ̂ = G (ab)^{3/2} C23 φ/(μN) with p̂ = 3N/(2πab): the linear theory's
//! spin force in units of μN. The spin's longitudinal slip −φy takes the
//! longitudinal compliance scaled like the spin's lateral part (k_φx: one
//! scaling per kind of creepage, as FASTSIM uses one L3 for both
//! components; CONTACT's implementation does the same). CONTACT's direction
//! e divides the spin term φ̂d by a further 1 − ν; then e and d no longer
//! satisfy (S2) together, so we keep (S2) exactly.
//!
//! # The FaStrip traction
//!
//! The ellipse is cut into [`FastripParams::strips`] strips, each into
//! [`FastripParams::elements_per_strip`] elements (FASTSIM's grid). On each
//! strip:
//!
//! - **adhesion zone**: (S1), integrated over the zone in closed form
//!   ([`zone_integrals`]): element midpoints would converge slowly, since in
//!   the linear limit (S1) has Carter's 1/√ singularity at the zone's end;
//! - **slip zone** (the whole strip if it slides fully): |p| = μ p_n along
//!   the traction of FASTSIM (Kalker's three flexibilities, ellipsoidal
//!   bound μ p_n, p_n the Hertz pressure) marched from the leading edge over
//!   the whole strip, element midpoints, the element cut by the zone
//!   boundary counted by its part behind it. *Our reading*: the strip theory
//!   declares these particles sliding, so Coulomb's law gives the magnitude
//!   μ p_n; FASTSIM gives the direction, which spin turns along the strip
//!   (the strip theory's e is constant). Without spin FASTSIM's direction
//!   is e, and FaStrip is the Kalker-scaled strip theory itself. CONTACT's
//!   implementation keeps FASTSIM's whole traction there instead (below the
//!   bound where FASTSIM adheres): at small and moderate creepage FASTSIM's
//!   slip zone is much shorter than the strip theory's (second against
//!   first order in the creepage), so that loses part of the slip zone's
//!   force.
//!
//! Each strip stands for the area of the ellipse between its edges (width
//! w_i = b ∫ √(1 − s²) ds / √(1 − s_i²) over the strip instead of 2b/n_y),
//! so the strips' chords sum to the ellipse exactly; with the exact zone
//! integrals the linear limit is then Kalker's to rounding (the plain midpoint sum over 16 strips is
//! 0.48 % high). The part of an element the zone boundary cuts gets μ p_n
//! integrated in closed form over that part ([`bound_integrals`]); a whole
//! element, μ p_n at its midpoint. p̂ makes the pressure summed this way
//! over the grid N exactly, in the bound and in ξ̂, η̂, φ̂ alike: full
//! sliding without spin gives |(Fx, Fy)| = μN exactly.
//!
//! # Large spin, |φ̂| > 1 (*our reading*)
//!
//! (S3) keeps a root when η̂φ̂ < 0, continuous through |φ̂| = 1; we keep the
//! zone there, and where (S1) would exceed μ p_n (possible only for
//! |φ̂| > 1, near the leading edge) it is limited to the bound element by
//! element ([`StripAdhesion::within_bound`]). CONTACT's implementation
//! instead lets every strip slide for |φ'| ≥ 1; for the reference case of
//! the CONTACT user guide (φ̂ = 1.002) that rule would move Fy/μN by 0.062
//! (unit test `sliding_at_unit_spin_would_jump`), a jump in force where the exact theory
//! is continuous.
//!
//! # Limits and known properties
//!
//! - Small creepage: Fx, Fy tend to Kalker's linear theory (C11, C22, C23)
//!   for any a/b; Mz is the strip theory's, not Kalker's C33 (reported,
//!   not forced).
//! - A strip switches from a zone to full sliding where the root (S3)
//!   disappears for |φ̂| > 1 (discriminant < 0) while d < a_y: a jump of
//!   that strip's share of the force (largest step measured in
//!   `tests/fastrip_reference.rs`, docs/reference/07-contact-forces.md
//!   §7.3). Everywhere else the forces are continuous in the creepages.
//! - Odd in the creepages exactly: d is even, e and g odd.
//! - Cost ∝ strips × elements, no allocation: FASTSIM's march plus one
//!   square root per slip-zone element and a closed form per strip.

use std::f64::consts::PI;

use super::fastsim::{FastsimParams, Flexibilities, element_centre, half_chord};
use super::{CreepError, CreepForces, CreepInput, kalker_coefficients};

/// FaStrip parameters: the discretisation of the ellipse (module docs).
/// Checked by [`FastripParams::validate`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FastripParams {
    /// Number of strips of equal width across the ellipse (lateral axis);
    /// 1 ≤ strips ≤ [`FastripParams::MAX_DIVISIONS`].
    pub strips: usize,
    /// Number of elements of equal length along each strip (rolling
    /// direction); 1 ≤ elements ≤ [`FastripParams::MAX_DIVISIONS`].
    pub elements_per_strip: usize,
}

impl Default for FastripParams {
    /// 16 strips × 64 elements: FASTSIM's default grid, chosen for FaStrip
    /// by the `discretisation_study` of `tests/fastrip_reference.rs` (table
    /// in docs/reference/07-contact-forces.md §7.3, "FaStrip").
    fn default() -> Self {
        FastripParams {
            strips: 16,
            elements_per_strip: 64,
        }
    }
}

impl FastripParams {
    /// Largest number of strips or of elements per strip (the same bound as
    /// FASTSIM's, [`FastsimParams::MAX_DIVISIONS`]).
    pub const MAX_DIVISIONS: usize = FastsimParams::MAX_DIVISIONS;

    /// Checks that both divisions lie in 1 ..= [`Self::MAX_DIVISIONS`].
    pub fn validate(&self) -> Result<(), CreepError> {
        super::fastsim::validate_divisions("FaStrip", self.strips, self.elements_per_strip)
    }
}

/// The strip theory's scaled creepages of the whole contact (module docs):
/// ξ̂ = xi_m − phi_x · y (m), η̂ = eta_m (m), φ̂ = phi (dimensionless).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StripCreepages {
    /// (a/(μp̂)) ξ/k_ξ (m).
    pub(crate) xi_m: f64,
    /// (a/(μp̂)) / k_φx · φ (dimensionless; times y gives metres).
    pub(crate) phi_x: f64,
    /// η̂ = (a/(μp̂)) η/k_η (m).
    pub(crate) eta_m: f64,
    /// φ̂ = (a/(μp̂)) φ/k_φy (dimensionless).
    pub(crate) phi: f64,
}

impl StripCreepages {
    /// For the input's creepages, ellipse and Kalker coefficients, with peak
    /// pressure `p_hat_pa` (module docs, "FaStrip's creepage scaling").
    pub(crate) fn new(
        input: &CreepInput,
        c11: f64,
        c22: f64,
        c23: f64,
        p_hat_pa: f64,
    ) -> StripCreepages {
        let (a, b) = (input.a_m, input.b_m);
        let g = input.shear_modulus_pa;
        let scale = a / (input.friction_coefficient * p_hat_pa);
        let inv_k_xi = 2.0 * g * c11 / (PI * PI);
        let inv_k_eta = 2.0 * g * c22 / (PI * PI);
        let inv_k_phi_y = 3.0 * g * c23 / (2.0 * PI * (a / b).sqrt());
        let inv_k_phi_x = inv_k_phi_y / (1.0 - input.poisson);
        StripCreepages {
            xi_m: scale * input.xi * inv_k_xi,
            phi_x: scale * input.phi_1_m * inv_k_phi_x,
            eta_m: scale * input.eta * inv_k_eta,
            phi: scale * input.phi_1_m * inv_k_phi_y,
        }
    }
}

/// The strip theory's solution on one strip (module docs, (S1)–(S3)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StripAdhesion {
    /// Centre d of the adhesion zone (m); the zone is [2d − a_y, a_y].
    pub(crate) centre_m: f64,
    /// Half-length a′ = a_y − d of the adhesion zone (m).
    pub(crate) half_length_m: f64,
    /// Slip-zone traction direction e (unit, or 0 when d = 0).
    pub(crate) e: [f64; 2],
    /// Coefficient g of the adhesion-zone semi-ellipse.
    pub(crate) g: [f64; 2],
    /// (S1) stays within the bound μ p_n over the zone (module docs, "Large
    /// spin"): the zone integrals have closed forms; otherwise (S1) is
    /// limited to the bound element by element.
    pub(crate) within_bound: bool,
}

/// The adhesion zone of the strip at `y_m` with half-length `a_y_m`, or
/// `None` if the strip slides fully: (S3) has no root d ≥ 0, or d ≥ a_y.
/// (S3) in the form d = (ξ̂² + η̂²) / (√(η̂² + (1 − φ̂²) ξ̂²) − η̂φ̂), the
/// same root without the division by 1 − φ̂² (module docs, "Large spin").
pub(crate) fn strip_adhesion(s: &StripCreepages, y_m: f64, a_y_m: f64) -> Option<StripAdhesion> {
    let phi = s.phi;
    let xi = s.xi_m - s.phi_x * y_m;
    let eta = s.eta_m;
    let num = xi * xi + eta * eta;
    let d = if num == 0.0 {
        0.0
    } else {
        let disc = eta * eta + (1.0 - phi * phi) * xi * xi;
        if disc < 0.0 {
            return None;
        }
        let den = disc.sqrt() - eta * phi;
        if den.is_nan() || den <= 0.0 {
            return None;
        }
        num / den
    };
    if d.is_nan() || d >= a_y_m {
        return None;
    }
    let e = if d > 0.0 {
        [-xi / d, -(eta + phi * d) / d]
    } else {
        [0.0, 0.0]
    };
    Some(StripAdhesion {
        centre_m: d,
        half_length_m: a_y_m - d,
        e,
        g: [e[0], e[1] + phi],
        within_bound: within_bound(e, [e[0], e[1] + phi], d, a_y_m, phi),
    })
}

/// Whether (S1) stays within μ p_n over the whole zone (module docs,
/// "Large spin"): with ρ = √(a′² − (x − d)²)/√(a_y² − x²), largest at the
/// leading edge, ρ² → a′/a_y, the condition |p| ≤ μ p_n is
/// ρ |g|² ≤ 2 e·g (|e| = 1), or ρ |g| ≤ 1 when d = 0 (e = 0). Always true
/// for |φ̂| ≤ 1.
fn within_bound(e: [f64; 2], g: [f64; 2], d: f64, a_y_m: f64, phi: f64) -> bool {
    if d == 0.0 {
        return phi.abs() <= 1.0;
    }
    let g2 = g[0] * g[0] + g[1] * g[1];
    let eg = e[0] * g[0] + e[1] * g[1];
    let rho2 = (a_y_m - d) / a_y_m;
    // ρ |g|² ≤ 2 e·g  ⇔  e·g ≥ 0 and ρ² |g|⁴ ≤ 4 (e·g)².
    eg >= 0.0 && rho2 * g2 * g2 <= 4.0 * eg * eg
}

/// FaStrip forces on the wheel (module docs). `input` is validated and has
/// N > 0; `p` is checked here as well (it bounds the loop lengths).
pub(crate) fn forces(input: &CreepInput, p: &FastripParams) -> Result<CreepForces, CreepError> {
    forces_with(input, p, false)
}

/// [`forces`]; with `slide_at_unit_spin`, every strip slides fully when
/// |φ̂| ≥ 1 (CONTACT's rule, module docs "Large spin"; for the comparison
/// test only).
fn forces_with(
    input: &CreepInput,
    p: &FastripParams,
    slide_at_unit_spin: bool,
) -> Result<CreepForces, CreepError> {
    p.validate()?;
    let mu = input.friction_coefficient;
    let (xi, eta, phi) = (input.xi, input.eta, input.phi_1_m);
    if input.normal_force_n == 0.0 || mu == 0.0 || (xi == 0.0 && eta == 0.0 && phi == 0.0) {
        return Ok(CreepForces::ZERO);
    }
    let (a, b) = (input.a_m, input.b_m);
    let c = kalker_coefficients(a / b, input.poisson)?;
    let flex = Flexibilities::kalker(a, b, input.shear_modulus_pa, &c);
    let (ny, nx) = (p.strips, p.elements_per_strip);
    let p_hat_pa = discrete_peak_pressure_pa(ny, nx, input.normal_force_n, a, b);
    let strip = StripCreepages::new(input, c.c11, c.c22, c.c23, p_hat_pa);
    let rates = Rates {
        xi: xi / flex.l1_m_pa,
        eta: eta / flex.l2_m_pa,
        phi: phi / flex.l3_m_pa,
    };
    let mu_p_over_a = mu * p_hat_pa / a;
    let setup = |i: usize| {
        let s = element_centre(i, ny);
        let y = s * b;
        let sigma_y = half_chord(s);
        let a_y = a * sigma_y;
        let zone = if slide_at_unit_spin && strip.phi.abs() >= 1.0 {
            None
        } else {
            strip_adhesion(&strip, y, a_y)
        };
        StripSetup {
            y_m: y,
            a_y_m: a_y,
            g_peak_pa: mu * p_hat_pa * sigma_y,
            zone,
        }
    };
    let mut total = CreepForces::ZERO;
    // Antiderivative of √(1 − s²) at the upper edge of the next strip
    // (strips come in order, from s = 1 down).
    let mut upper = prim_half_disc(1.0);
    let mut add = |i: usize, st: &StripSetup, mut line: LineIntegrals| {
        if let Some(z) = st.zone.as_ref().filter(|z| z.within_bound) {
            let inside = zone_integrals(z, st.a_y_m, mu_p_over_a);
            line.px += inside.px;
            line.py += inside.py;
            line.x_py += inside.x_py;
        }
        let lower = prim_half_disc(element_centre(i, ny) - 1.0 / ny as f64);
        let w = b * (upper - lower) / half_chord(element_centre(i, ny));
        upper = lower;
        total.fx_n += line.px * w;
        total.fy_n += line.py * w;
        total.mz_nm += (line.x_py - st.y_m * line.px) * w;
    };
    // Four strips per pass: four independent FASTSIM recurrences in one
    // loop hide the latency of the slip update (as `fastsim::forces`).
    let mut i = 1;
    while i + 3 <= ny {
        let st = [setup(i), setup(i + 1), setup(i + 2), setup(i + 3)];
        let lines = march(&st, mu_p_over_a, &rates, nx);
        for k in 0..4 {
            add(i + k, &st[k], lines[k]);
        }
        i += 4;
    }
    while i <= ny {
        let st = [setup(i)];
        let [line] = march(&st, mu_p_over_a, &rates, nx);
        add(i, &st[0], line);
        i += 1;
    }
    Ok(total)
}

/// One strip's constants for [`march`].
#[derive(Debug, Clone, Copy)]
struct StripSetup {
    /// Lateral position y (m).
    y_m: f64,
    /// Half-length a_y (m).
    a_y_m: f64,
    /// μ p̂ σ(y) (Pa): the bound at x = 0.
    g_peak_pa: f64,
    /// The strip theory's adhesion zone, if any.
    zone: Option<StripAdhesion>,
}

/// ∫ √(1 − u²) du from 0 to `s` (clamped to [−1, 1]):
/// ½ [s √(1 − s²) + asin s].
fn prim_half_disc(s: f64) -> f64 {
    let s = s.clamp(-1.0, 1.0);
    0.5 * (s * (1.0 - s * s).max(0.0).sqrt() + s.asin())
}

/// The width (m) strip `i` of `ny` stands for: its chord 2a(y_i) times this
/// width is the area of the ellipse between its edges,
/// w_i = b ∫ √(1 − s²) ds / √(1 − s_i²) over s_i ± 1/n_y (module docs,
/// "The FaStrip traction": the zone integrals are exact along x, and with
/// w_i instead of 2b/n_y the strips' chords also sum to the ellipse exactly;
/// the plain midpoint sum is 0.48 % high on 16 strips). [`forces`] computes
/// the same sum strip by strip, sharing the edges.
#[cfg(test)]
fn strip_weight_m(i: usize, ny: usize, b_m: f64) -> f64 {
    let s = element_centre(i, ny);
    let half = 1.0 / ny as f64;
    b_m * (prim_half_disc(s + half) - prim_half_disc(s - half)) / half_chord(s)
}

/// The grid constant K(n_y, n_x) = Σ_j σ(t_j) · Σ_i σ(s_i) ∫ σ over strip i
/// (σ(u) = √(1 − u²)): the pressure p̂ σ(s_i) σ(t_j) summed over the grid,
/// each strip i standing for the width w_i = b ∫σ/σ(s_i) and each element
/// for 2a σ(s_i)/n_x, is p̂ · 2ab K/n_x. Depends on the grid only, so the
/// last grid's value is kept (per thread).
fn grid_constant(ny: usize, nx: usize) -> f64 {
    thread_local! {
        static LAST: std::cell::Cell<(usize, usize, f64)> =
            const { std::cell::Cell::new((0, 0, 0.0)) };
    }
    LAST.with(|last| {
        let (cy, cx, k) = last.get();
        if (cy, cx) == (ny, nx) {
            return k;
        }
        let sum_x: f64 = (1..=nx).map(|j| half_chord(element_centre(j, nx))).sum();
        let mut upper = prim_half_disc(1.0);
        let mut sum_y = 0.0;
        for i in 1..=ny {
            let s = element_centre(i, ny);
            let lower = prim_half_disc(s - 1.0 / ny as f64);
            sum_y += half_chord(s) * (upper - lower);
            upper = lower;
        }
        let k = sum_x * sum_y;
        last.set((ny, nx, k));
        k
    })
}

/// Peak pressure p̂ (Pa) that makes the pressure of the FaStrip grid sum to
/// `n_n` exactly (see [`grid_constant`]).
fn discrete_peak_pressure_pa(ny: usize, nx: usize, n_n: f64, a_m: f64, b_m: f64) -> f64 {
    n_n * nx as f64 / (2.0 * a_m * b_m * grid_constant(ny, nx))
}

/// Rigid slip over FASTSIM's flexibilities (Pa/m): ξ/L1, η/L2, φ/L3.
#[derive(Debug, Clone, Copy)]
struct Rates {
    xi: f64,
    eta: f64,
    phi: f64,
}

/// Integrals along one strip: ∫ p_x dx, ∫ p_y dx (N/m), ∫ x p_y dx (N).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct LineIntegrals {
    pub(crate) px: f64,
    pub(crate) py: f64,
    pub(crate) x_py: f64,
}

/// `K` independent strips `st` (module docs, "The FaStrip traction"),
/// integrated element by element (midpoint rule):
///
/// - behind the adhesion zone (the whole strip when there is none): μ p_n
///   along the traction of FASTSIM (ellipsoidal bound) marched from the
///   leading edge over the whole strip (along the zone's e where FASTSIM's
///   traction is zero);
/// - inside a zone whose (S1) can exceed the bound (`within_bound` false):
///   (S1) with μp̂/a = `mu_p_over_a`, limited to μ p_n. A zone within the
///   bound is left to [`zone_integrals`] (closed forms).
fn march<const K: usize>(
    st: &[StripSetup; K],
    mu_p_over_a: f64,
    rates: &Rates,
    nx: usize,
) -> [LineIntegrals; K] {
    let dt = 2.0 / nx as f64;
    let h = st.map(|s| dt * s.a_y_m);
    let rate_x = st.map(|s| rates.xi - rates.phi * s.y_m);
    let g2_peak = st.map(|s| s.g_peak_pa * s.g_peak_pa);
    // Trailing end of the adhesion zone (+∞: no zone, the strip slides).
    let x_b = st.map(|s| s.zone.map_or(f64::INFINITY, |z| 2.0 * z.centre_m - s.a_y_m));
    let mut px = [0.0_f64; K];
    let mut py = [0.0_f64; K];
    let mut sums = [LineIntegrals::default(); K];
    let mut t_prev = 1.0;
    for j in 1..=nx {
        let t = 1.0 - (j as f64 - 0.5) * dt;
        let t_mid = 0.5 * (t_prev + t);
        let dt_step = t_prev - t;
        let q = (1.0 - t * t).max(0.0);
        t_prev = t;
        for k in 0..K {
            let a_y = st[k].a_y_m;
            // FASTSIM step (as in `fastsim::march`, ellipsoidal bound).
            let step = dt_step * a_y;
            px[k] -= step * rate_x[k];
            py[k] -= step * (rates.eta + rates.phi * t_mid * a_y);
            let g2 = g2_peak[k] * q;
            let norm2 = px[k] * px[k] + py[k] * py[k];
            let sliding = norm2 > g2;
            if sliding {
                let scale = (g2 / norm2).sqrt();
                px[k] *= scale;
                py[k] *= scale;
            }
            // The element [lo, up]; its part behind the zone, [lo, min(up, x_b)].
            let x = t * a_y;
            let lo = x - 0.5 * h[k];
            let up = x + 0.5 * h[k];
            if up <= x_b[k] {
                // A whole element behind the zone: μ p_n at its midpoint
                // (the grid's pressure normalisation) along FASTSIM.
                let (qx, qy) = if sliding {
                    (px[k], py[k])
                } else {
                    along(px[k], py[k], g2, st[k].zone)
                };
                sums[k].px += h[k] * qx;
                sums[k].py += h[k] * qy;
                sums[k].x_py += h[k] * x * qy;
            } else if lo < x_b[k] {
                // The element the zone boundary cuts: ∫ μ p_n over its part
                // behind the zone in closed form (its midpoint would
                // misplace the bound), along FASTSIM.
                let (ux, uy) = along(px[k], py[k], 1.0, st[k].zone);
                let (m0, m1) = bound_integrals(lo, x_b[k], a_y, mu_p_over_a);
                sums[k].px += m0 * ux;
                sums[k].py += m0 * uy;
                sums[k].x_py += m1 * uy;
            }
            if let Some(z) = st[k].zone.filter(|z| !z.within_bound) {
                let start = lo.max(x_b[k]);
                if up > start {
                    let xm = 0.5 * (start + up);
                    let (qx, qy) = clipped_strip_traction(&z, xm, a_y, mu_p_over_a);
                    let len = up - start;
                    sums[k].px += len * qx;
                    sums[k].py += len * qy;
                    sums[k].x_py += len * xm * qy;
                }
            }
        }
    }
    sums
}

/// The vector of length √`g2` along (px, py), or along the zone's e where
/// (px, py) = 0 (zero without a zone).
fn along(px: f64, py: f64, g2: f64, zone: Option<StripAdhesion>) -> (f64, f64) {
    let n2 = px * px + py * py;
    if n2 > 0.0 {
        let scale = (g2 / n2).sqrt();
        (px * scale, py * scale)
    } else {
        let e = zone.map_or([0.0, 0.0], |z| z.e);
        let g = g2.sqrt();
        (e[0] * g, e[1] * g)
    }
}

/// ∫ μ p_n dx and ∫ x μ p_n dx over [lo, hi] ⊂ [−a_y, a_y], with
/// μ p_n = (μp̂/a) √(a_y² − x²) and μp̂/a = `mu_p_over_a`: closed forms
/// (antiderivatives ½[x√(a_y² − x²) + a_y² asin(x/a_y)] and
/// −(a_y² − x²)^{3/2}/3).
fn bound_integrals(lo: f64, hi: f64, a_y_m: f64, mu_p_over_a: f64) -> (f64, f64) {
    let a2 = a_y_m * a_y_m;
    let f0 = |u: f64| {
        let u = u.clamp(-a_y_m, a_y_m);
        0.5 * (u * (a2 - u * u).max(0.0).sqrt() + a2 * (u / a_y_m).asin())
    };
    let f1 = |u: f64| {
        let r = (a2 - u * u).max(0.0);
        -r * r.sqrt() / 3.0
    };
    (
        mu_p_over_a * (f0(hi) - f0(lo)),
        mu_p_over_a * (f1(hi) - f1(lo)),
    )
}

/// (S1) at `x_m` in the zone `z` of a strip of half-length `a_y_m`, limited
/// to |p| ≤ μ p_n (μp̂/a = `mu_p_over_a`).
fn clipped_strip_traction(z: &StripAdhesion, x_m: f64, a_y_m: f64, mu_p_over_a: f64) -> (f64, f64) {
    let bound = mu_p_over_a * (a_y_m * a_y_m - x_m * x_m).max(0.0).sqrt();
    let dx = x_m - z.centre_m;
    let s_a = mu_p_over_a
        * (z.half_length_m * z.half_length_m - dx * dx)
            .max(0.0)
            .sqrt();
    let px = bound * z.e[0] - s_a * z.g[0];
    let py = bound * z.e[1] - s_a * z.g[1];
    let n2 = px * px + py * py;
    let b2 = bound * bound;
    if n2 > b2 {
        let scale = (b2 / n2).sqrt();
        (px * scale, py * scale)
    } else {
        (px, py)
    }
}

/// The integrals of (S1) over the adhesion zone `z` of a strip of
/// half-length `a_y_m`, with μp̂/a = `mu_p_over_a` (Pa/m), in closed form:
/// with x_b = 2d − a_y,
///
/// ```text
/// ∫ √(a_y² − x²) dx  over [x_b, a_y] = π a_y²/4 − ½ [x_b √(a_y² − x_b²) + a_y² asin(x_b/a_y)]
/// ∫ x √(a_y² − x²) dx over [x_b, a_y] = (a_y² − x_b²)^{3/2} / 3
/// ∫ √(a′² − (x − d)²) dx (the zone)   = π a′²/2,  and ∫ x (…) dx = d π a′²/2
/// ```
///
/// Exact, where element midpoints would not be: in the linear limit
/// (d → 0) (S1) has Carter's 1/√ singularity at the trailing edge.
pub(crate) fn zone_integrals(z: &StripAdhesion, a_y_m: f64, mu_p_over_a: f64) -> LineIntegrals {
    let x_b = (2.0 * z.centre_m - a_y_m).clamp(-a_y_m, a_y_m);
    let a2 = a_y_m * a_y_m;
    let rest = (a2 - x_b * x_b).max(0.0);
    let i_c = PI * a2 / 4.0 - 0.5 * (x_b * rest.sqrt() + a2 * (x_b / a_y_m).asin());
    let j_c = rest * rest.sqrt() / 3.0;
    let i_a = 0.5 * PI * z.half_length_m * z.half_length_m;
    let j_a = z.centre_m * i_a;
    LineIntegrals {
        px: mu_p_over_a * (z.e[0] * i_c - z.g[0] * i_a),
        py: mu_p_over_a * (z.e[1] * i_c - z.g[1] * i_a),
        x_py: mu_p_over_a * (z.e[1] * j_c - z.g[1] * j_a),
    }
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
        assert!(FastripParams::default().validate().is_ok());
        for (s, e, name) in [(0, 10, "strips"), (10, 2001, "elements_per_strip")] {
            match (FastripParams {
                strips: s,
                elements_per_strip: e,
            })
            .validate()
            {
                Err(CreepError::InvalidParameter { law, parameter, .. }) => {
                    assert_eq!(law, "FaStrip");
                    assert_eq!(parameter, name);
                }
                other => panic!("{s}×{e}: {other:?}"),
            }
        }
        let bad = FastripParams {
            strips: 3,
            elements_per_strip: 0,
        };
        assert!(forces(&input(1e-3, 0.0, 0.0), &bad).is_err());
    }

    /// (S3) and (S2): e is a unit vector, d solves the quadratic, and the
    /// pure-creepage case reduces to d = √(ξ̂² + η̂²).
    #[test]
    fn strip_solution_satisfies_its_equations() {
        let s = StripCreepages {
            xi_m: 3e-4,
            phi_x: 0.02,
            eta_m: -2e-4,
            phi: 0.4,
        };
        let y = 1e-3;
        let z = strip_adhesion(&s, y, 5e-3).unwrap();
        let d = z.centre_m;
        let xi = s.xi_m - s.phi_x * y;
        assert!((z.e[0].hypot(z.e[1]) - 1.0).abs() < 1e-12);
        assert!((d * z.e[0] + xi).abs() < 1e-15);
        assert!((d * z.e[1] + s.eta_m + s.phi * d).abs() < 1e-15);
        assert_eq!(z.g, [z.e[0], z.e[1] + s.phi]);
        assert!((z.half_length_m - (5e-3 - d)).abs() < 1e-18);
        let pure = StripCreepages {
            phi_x: 0.0,
            phi: 0.0,
            ..s
        };
        let z = strip_adhesion(&pure, y, 5e-3).unwrap();
        assert!((z.centre_m - 3e-4_f64.hypot(2e-4)).abs() < 1e-18);
        // Full sliding: d ≥ a_y; no root with |φ̂| ≥ 1 and η̂φ̂ ≥ 0.
        assert!(strip_adhesion(&pure, y, 3e-4).is_none());
        let spin = StripCreepages {
            phi: 1.0,
            eta_m: 2e-4,
            ..s
        };
        assert!(strip_adhesion(&spin, y, 5e-3).is_none());
        let spin = StripCreepages { phi: 1.5, ..spin };
        assert!(strip_adhesion(&spin, y, 5e-3).is_none());
    }

    /// Across |φ̂| = 1 with η̂φ̂ < 0 the root (S3) is continuous (module
    /// docs, "Large spin"), and it still solves (S2); (S1) is within the
    /// bound for |φ̂| ≤ 1 and may leave it above.
    #[test]
    fn root_is_continuous_through_unit_spin() {
        let base = StripCreepages {
            xi_m: 1e-4,
            phi_x: 0.0,
            eta_m: -3e-4,
            phi: 1.0,
        };
        let a_y = 5e-3;
        let d = |phi: f64| {
            strip_adhesion(&StripCreepages { phi, ..base }, 0.0, a_y)
                .unwrap()
                .centre_m
        };
        let d1 = d(1.0);
        assert!((d(1.0 - 1e-9) - d1).abs() < 1e-12 && (d(1.0 + 1e-9) - d1).abs() < 1e-12);
        for phi in [0.5, 0.999, 1.0, 1.2, 2.0] {
            let z = strip_adhesion(&StripCreepages { phi, ..base }, 0.0, a_y).unwrap();
            let dd = z.centre_m;
            assert!((dd * z.e[0] + base.xi_m).abs() < 1e-15, "φ̂ = {phi}");
            assert!(
                (dd * z.e[1] + base.eta_m + phi * dd).abs() < 1e-15,
                "φ̂ = {phi}"
            );
            assert!((z.e[0].hypot(z.e[1]) - 1.0).abs() < 1e-12);
            if phi <= 1.0 {
                assert!(z.within_bound, "φ̂ = {phi}");
            }
        }
        // Small zone centre and φ̂ = 2: (S1) leaves the bound at the leading
        // edge; the clipped traction does not.
        let big = StripCreepages {
            xi_m: 0.0,
            phi_x: 0.0,
            eta_m: -1e-5,
            phi: 2.0,
        };
        let z = strip_adhesion(&big, 0.0, a_y).unwrap();
        assert!(!z.within_bound);
        let k = 1e11;
        for x in [4.99e-3, 4.9e-3, 0.0, -4.9e-3] {
            let (px, py) = clipped_strip_traction(&z, x, a_y, k);
            let bound = k * (a_y * a_y - x * x).sqrt();
            assert!(px.hypot(py) <= bound * (1.0 + 1e-12), "x = {x}");
        }
    }

    /// Pure spin at y = 0: d = 0, and (S1) is −φ̂ μ p_n ŷ (module docs):
    /// ∫ p_y dx = −φ̂ μp̂/a · π a_y²/2, no p_x, no moment.
    #[test]
    fn pure_spin_on_the_centre_line() {
        let s = StripCreepages {
            xi_m: 0.0,
            phi_x: 0.05,
            eta_m: 0.0,
            phi: 0.3,
        };
        let a_y = 4e-3;
        let z = strip_adhesion(&s, 0.0, a_y).unwrap();
        assert_eq!(z.centre_m, 0.0);
        let k = 1e11;
        let i = zone_integrals(&z, a_y, k);
        let want = -0.3 * k * PI * a_y * a_y / 2.0;
        assert_eq!(i.px, 0.0);
        assert!((i.py / want - 1.0).abs() < 1e-12, "{} vs {want}", i.py);
        assert!(i.x_py.abs() < 1e-12 * want.abs() * a_y);
    }

    /// The closed forms against a fine midpoint sum of (S1), with spin and
    /// a zone that ends inside the strip; and (S1) never exceeds the bound
    /// (|φ̂| < 1, module docs).
    #[test]
    fn zone_integrals_match_quadrature_and_respect_the_bound() {
        let s = StripCreepages {
            xi_m: 4e-4,
            phi_x: 0.1,
            eta_m: -3e-4,
            phi: 0.6,
        };
        let (y, a_y, k) = (5e-4, 5e-3, 1e11);
        let z = strip_adhesion(&s, y, a_y).unwrap();
        let (d, ap) = (z.centre_m, z.half_length_m);
        let x_b = 2.0 * d - a_y;
        let n = 200_000;
        let h = (a_y - x_b) / n as f64;
        let mut q = LineIntegrals::default();
        for j in 0..n {
            let x = x_b + (j as f64 + 0.5) * h;
            let sc = k * (a_y * a_y - x * x).max(0.0).sqrt();
            let sa = k * (ap * ap - (x - d) * (x - d)).max(0.0).sqrt();
            let (px, py) = (sc * z.e[0] - sa * z.g[0], sc * z.e[1] - sa * z.g[1]);
            assert!(px.hypot(py) <= sc * (1.0 + 1e-12) + 1e-6, "x = {x}");
            q.px += px * h;
            q.py += py * h;
            q.x_py += x * py * h;
        }
        let i = zone_integrals(&z, a_y, k);
        for (got, want) in [(i.px, q.px), (i.py, q.py), (i.x_py, q.x_py)] {
            assert!(
                (got - want).abs() < 1e-6 * want.abs().max(1.0),
                "{got} vs {want}"
            );
        }
    }

    #[test]
    fn zero_friction_or_creepage_gives_zero() {
        let p = FastripParams::default();
        let mut i = input(1e-3, -2e-3, 0.5);
        i.friction_coefficient = 0.0;
        assert_eq!(forces(&i, &p).unwrap(), CreepForces::ZERO);
        assert_eq!(
            forces(&input(0.0, 0.0, 0.0), &p).unwrap(),
            CreepForces::ZERO
        );
    }

    /// The CONTACT user guide's spin case (`examples/fastsim.inp`, φ̂ = 1.002
    /// with our C23): letting every strip slide at |φ̂| ≥ 1 (CONTACT's rule)
    /// moves Fy/μN by more than 0.05 (measured 0.062) from our continued
    /// root, which is within 0.01 of the exact −0.6074 (module docs, "Large
    /// spin"; `tests/fastrip_reference.rs`).
    #[test]
    fn sliding_at_unit_spin_would_jump() {
        let i = CreepInput {
            xi: 0.0,
            eta: -6.25e-4,
            phi_1_m: 0.625,
            normal_force_n: 82e3,
            a_m: 8e-3,
            b_m: 4e-3,
            friction_coefficient: 0.3,
            rolling_speed_m_s: 30.0,
            shear_modulus_pa: 82e9,
            poisson: 0.28,
        };
        let mun = 0.3 * 82e3;
        let p = FastripParams::default();
        let ours = forces_with(&i, &p, false).unwrap().fy_n / mun;
        let slide = forces_with(&i, &p, true).unwrap().fy_n / mun;
        eprintln!("Fy/μN continued {ours:.4}, sliding at |φ̂| ≥ 1 {slide:.4}");
        assert!((ours - slide).abs() > 0.05, "{ours} {slide}");
        assert!((ours + 0.6074).abs() < 0.01, "{ours}");
    }

    /// The strip widths stand for the ellipse's area exactly, and p̂ makes
    /// the grid's pressure sum N exactly (against a direct sum).
    #[test]
    fn strip_widths_and_pressure_normalisation() {
        let (a, b) = (7e-3, 5e-3);
        for (ny, nx) in [(1, 1), (5, 7), (16, 64), (17, 3)] {
            let area: f64 = (1..=ny)
                .map(|i| 2.0 * a * half_chord(element_centre(i, ny)) * strip_weight_m(i, ny, b))
                .sum();
            assert!((area / (PI * a * b) - 1.0).abs() < 1e-13, "{ny}: {area}");
            let p_hat = discrete_peak_pressure_pa(ny, nx, 1e5, a, b);
            let mut n = 0.0;
            for i in 1..=ny {
                let sy = half_chord(element_centre(i, ny));
                for j in 1..=nx {
                    let sx = half_chord(element_centre(j, nx));
                    n += p_hat * sy * sx * (2.0 * a * sy / nx as f64) * strip_weight_m(i, ny, b);
                }
            }
            assert!((n / 1e5 - 1.0).abs() < 1e-13, "{ny}x{nx}: {n}");
        }
    }

    /// φ̂ is the linear theory's spin force over μN (module docs).
    #[test]
    fn scaled_spin_is_kalkers_spin_force() {
        let i = input(0.0, 0.0, 0.7);
        let c = kalker_coefficients(i.a_m / i.b_m, i.poisson).unwrap();
        let p_hat = 3.0 * i.normal_force_n / (2.0 * PI * i.a_m * i.b_m);
        let s = StripCreepages::new(&i, c.c11, c.c22, c.c23, p_hat);
        let want = i.shear_modulus_pa * (i.a_m * i.b_m).powf(1.5) * c.c23 * i.phi_1_m
            / (i.friction_coefficient * i.normal_force_n);
        assert!((s.phi / want - 1.0).abs() < 1e-12, "{} vs {want}", s.phi);
        assert!((s.phi_x * (1.0 - i.poisson) / s.phi - 1.0).abs() < 1e-12);
    }
}
