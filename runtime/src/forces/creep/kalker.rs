//! Kalker's creepage and spin coefficients C11, C22, C23, C33 of the linear
//! theory of rolling contact for elliptical contact areas (docs/reference/07-contact-forces.md §7.3; paper
//! eq. 23), and the Kalker linear creep law built on them.
//!
//! # Source and interpolation
//!
//! J. J. Kalker, *Three-dimensional elastic bodies in rolling contact*,
//! Kluwer 1990, Table E.3: the coefficients for ν = 0, 0.25, 0.5 and semi-axis
//! ratios a/b = 0.1 … 1 (a ≤ b) and b/a = 1 … 0.1 (a ≥ b), where a is the
//! semi-axis in the **rolling** direction. The table is compiled in from
//! `runtime/data/kalker_cij.csv` (see `runtime/data/README.md`).
//!
//! - **Ratio**: with g = min(a/b, b/a), linear interpolation in g between the
//!   two bracketing rows of the side the ellipse is on (a ≤ b or a ≥ b) —
//!   both sides share the circle row g = 1, so the result is continuous
//!   across a = b.
//! - **Poisson's ratio** (Kalker 1990, App. E, "parabola in 1/C"): the three
//!   ν columns, already interpolated in g, define 1/C(ν) as the quadratic
//!   through (0, 1/C₀), (¼, 1/C₂₅), (½, 1/C₅₀):
//!
//!   ```text
//!   1/C(ν) = 8(ν − ¼)(ν − ½)/C₀ − 16ν(ν − ½)/C₂₅ + 8ν(ν − ¼)/C₅₀
//!   ```
//!
//!   exact at the three nodes. Supported range 0 ≤ ν ≤ ½ (steel: 0.28–0.30).
//! - **Outside the table** (g < 0.1, i.e. a/b < 0.1 or a/b > 10), Kalker's
//!   asymptotes for g → 0 (Kalker 1990, App. E; also in the open CONTACT
//!   code, `m_hertz.f90`, routine `linrol`), with Λ = ln(16/g²):
//!
//!   a/b = g → 0 (ellipse narrow in the rolling direction):
//!   ```text
//!   C11 = π²/(4(1 − ν)),   C22 = π²/4,
//!   C23 = π√g/(3(1 − ν)) · [1 + ν(ln(16/g) − 5)],   C33 = π²/(16(1 − ν)g)
//!   ```
//!   b/a = g → 0 (ellipse long in the rolling direction):
//!   ```text
//!   C11 = 2π/((Λ − 2ν)g) · [1 + (3 − ln 4)/(Λ − 2ν)]
//!   C22 = 2π/(g((1 − ν)Λ + 2ν)) · [1 + (1 − ν)(3 − ln 4)/((1 − ν)Λ + 2ν)]
//!   C23 = 2π/(3g^1.5((1 − ν)Λ − 2 + 4ν))
//!   ```
//!   The asymptotes are the leading terms as g → 0; at g = 0.1 they differ
//!   from the table by up to 3 % (e.g. C11 at b/a = 0.1, ν = 0: 10.38 vs
//!   10.7). So that the coefficients stay **continuous** at g = 0.1 (a jump
//!   in a creep coefficient is a jump in force that an integrator sees), each
//!   asymptote is multiplied by 1 + (ρ − 1)·g/0.1, with ρ = table/asymptote
//!   at g = 0.1: the correction vanishes as g → 0, where the asymptote is
//!   exact, and is exactly the table value at g = 0.1.
//!
//!   C33 for b/a → 0: the table shows C33 bounded and falling slowly as
//!   b/a → 0 (0.912, 0.868, 0.828, 0.795 at b/a = 0.4 … 0.1 for ν = 0). We
//!   have not been able to check a closed-form asymptote for this one
//!   coefficient against a primary source, so the table's last interval
//!   (b/a = 0.2 → 0.1) is extended **linearly in g** to g = 0 (limits 0.762,
//!   0.451, 0.115 for ν = 0, ¼, ½, then the ν rule). This is our choice,
//!   documented here; it affects only the spin moment of contacts more than
//!   ten times longer than wide.

use std::f64::consts::PI;
use std::sync::OnceLock;

use super::{CreepError, CreepForces, CreepInput};

/// Kalker's creepage and spin coefficients (dimensionless) for one ellipse
/// shape and Poisson's ratio (Kalker 1990, Table E.3; docs/reference/07-contact-forces.md §7.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KalkerCoefficients {
    /// Longitudinal creepage → longitudinal force.
    pub c11: f64,
    /// Lateral creepage → lateral force.
    pub c22: f64,
    /// Spin → lateral force, and lateral creepage → spin moment.
    pub c23: f64,
    /// Spin → spin moment.
    pub c33: f64,
}

/// Table rows per side: g = 0.1, 0.2, …, 1.0.
const ROWS: usize = 10;
/// Poisson's ratios of the table's columns.
const NU_NODES: [f64; 3] = [0.0, 0.25, 0.5];
/// Smallest tabulated ratio g = min(a/b, b/a).
const G_MIN: f64 = 0.1;

/// One side of the table: `[row][ν column][coefficient]`, rows g = 0.1…1.0,
/// coefficients in the order C11, C22, C23, C33.
type Side = [[[f64; 4]; 3]; ROWS];

/// The parsed table: side 0 is a ≤ b (g = a/b), side 1 is a ≥ b (g = b/a);
/// both hold the circle row g = 1.
#[derive(Debug)]
struct KalkerTable {
    sides: [Side; 2],
}

const TABLE_CSV: &str = include_str!("../../../data/kalker_cij.csv");

fn table() -> &'static KalkerTable {
    static TABLE: OnceLock<KalkerTable> = OnceLock::new();
    TABLE.get_or_init(|| match parse_table(TABLE_CSV) {
        Ok(t) => t,
        // The CSV is compiled in and checked by the unit tests below; a
        // failure here is a build defect, not a user error.
        Err(msg) => panic!("compiled-in Kalker table is malformed: {msg}"),
    })
}

/// Parses `kalker_cij.csv` (header `ratio_kind,ratio,nu,c11,c22,c23,c33`)
/// into the two sides; every (side, g, ν) cell must be present exactly once.
fn parse_table(text: &str) -> Result<KalkerTable, String> {
    let mut sides = [[[[f64::NAN; 4]; 3]; ROWS]; 2];
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header = lines.next().ok_or("empty table")?;
    if header.trim() != "ratio_kind,ratio,nu,c11,c22,c23,c33" {
        return Err(format!("unexpected header {header:?}"));
    }
    for line in lines {
        let cols: Vec<&str> = line.split(',').map(str::trim).collect();
        if cols.len() != 7 {
            return Err(format!("row {line:?} has {} columns", cols.len()));
        }
        let num = |i: usize| -> Result<f64, String> {
            cols[i]
                .parse::<f64>()
                .map_err(|e| format!("row {line:?}: {e}"))
        };
        let g = num(1)?;
        let nu = num(2)?;
        let row = (g * 10.0).round() as i64 - 1;
        if !(0..ROWS as i64).contains(&row) || ((row + 1) as f64 * 0.1 - g).abs() > 1e-9 {
            return Err(format!("row {line:?}: ratio not on the 0.1 grid"));
        }
        let col = NU_NODES
            .iter()
            .position(|&n| (n - nu).abs() < 1e-12)
            .ok_or_else(|| format!("row {line:?}: nu not one of 0, 0.25, 0.5"))?;
        let coefs = [num(3)?, num(4)?, num(5)?, num(6)?];
        let targets: &[usize] = match (cols[0], row as usize) {
            ("a/b", r) if r == ROWS - 1 => &[0, 1],
            ("a/b", _) => &[0],
            ("b/a", _) => &[1],
            (kind, _) => return Err(format!("row {line:?}: unknown ratio kind {kind:?}")),
        };
        for &side in targets {
            let cell = &mut sides[side][row as usize][col];
            if !cell[0].is_nan() {
                return Err(format!("row {line:?} duplicated"));
            }
            *cell = coefs;
        }
    }
    if sides
        .iter()
        .flatten()
        .flatten()
        .flatten()
        .any(|v| v.is_nan())
    {
        return Err("missing rows".into());
    }
    Ok(KalkerTable { sides })
}

/// Kalker's rule in ν: 1/C is the parabola through the three columns
/// (module docs); `c` holds C at ν = 0, ¼, ½.
fn nu_rule(c: [f64; 3], nu: f64) -> f64 {
    let inv = 8.0 * (nu - 0.25) * (nu - 0.5) / c[0] - 16.0 * nu * (nu - 0.5) / c[1]
        + 8.0 * nu * (nu - 0.25) / c[2];
    1.0 / inv
}

/// Table value of all four coefficients at ratio `g` ∈ [0.1, 1] on `side`
/// (linear in g, then the ν rule).
fn tabulated(side: usize, g: f64, nu: f64) -> [f64; 4] {
    let t = &table().sides[side];
    // Row index of the lower bracket: g = 0.1 (i + 1) + 0.1 w, w ∈ [0, 1].
    let x = (g * 10.0 - 1.0).clamp(0.0, (ROWS - 1) as f64);
    let i = (x.floor() as usize).min(ROWS - 2);
    let w = x - i as f64;
    let mut out = [0.0; 4];
    for (k, o) in out.iter_mut().enumerate() {
        let at_nu = |col: usize| t[i][col][k] + w * (t[i + 1][col][k] - t[i][col][k]);
        *o = nu_rule([at_nu(0), at_nu(1), at_nu(2)], nu);
    }
    out
}

/// Kalker's asymptotes for a/b = g → 0 (module docs): C11, C22, C23, C33.
fn asymptote_narrow(g: f64, nu: f64) -> [f64; 4] {
    let pi2 = PI * PI;
    [
        pi2 / (4.0 * (1.0 - nu)),
        pi2 / 4.0,
        PI * g.sqrt() / (3.0 * (1.0 - nu)) * (1.0 + nu * ((16.0 / g).ln() - 5.0)),
        pi2 / (16.0 * (1.0 - nu) * g),
    ]
}

/// Kalker's asymptotes for b/a = g → 0 (module docs): C11, C22, C23 (C33 is
/// extended linearly from the table instead, see the module docs).
fn asymptote_long(g: f64, nu: f64) -> [f64; 3] {
    let lambda = (16.0 / (g * g)).ln();
    let three_minus_ln4 = 3.0 - 4.0_f64.ln();
    let d11 = lambda - 2.0 * nu;
    let d22 = (1.0 - nu) * lambda + 2.0 * nu;
    [
        2.0 * PI / (d11 * g) * (1.0 + three_minus_ln4 / d11),
        2.0 * PI / (g * d22) * (1.0 + (1.0 - nu) * three_minus_ln4 / d22),
        2.0 * PI / (3.0 * g.powf(1.5) * ((1.0 - nu) * lambda - 2.0 + 4.0 * nu)),
    ]
}

/// C33 for b/a = g < 0.1: the table's interval g = 0.2 → 0.1 extended
/// linearly in g per ν column, then the ν rule (module docs).
fn c33_long_extended(g: f64, nu: f64) -> f64 {
    let t = &table().sides[1];
    let at_nu = |col: usize| {
        let c01 = t[0][col][3];
        let c02 = t[1][col][3];
        c01 + (g - 0.1) * (c02 - c01) / 0.1
    };
    nu_rule([at_nu(0), at_nu(1), at_nu(2)], nu)
}

/// Kalker's coefficients for the semi-axis ratio `a_over_b` (a in the rolling
/// direction, b lateral; finite, > 0) and Poisson's ratio `poisson`
/// (0 ≤ ν ≤ 0.5). Table E.3 of Kalker 1990 inside 0.1 ≤ a/b ≤ 10 (linear in
/// the ratio, Kalker's rule in ν), his asymptotes outside, continuous at the
/// table's ends (module docs).
pub fn kalker_coefficients(a_over_b: f64, poisson: f64) -> Result<KalkerCoefficients, CreepError> {
    if !(a_over_b.is_finite() && a_over_b > 0.0) {
        return Err(CreepError::InvalidInput {
            quantity: "semi-axis ratio a/b",
            value: a_over_b,
            rule: "must be finite and > 0",
        });
    }
    if !(0.0..=0.5).contains(&poisson) {
        return Err(CreepError::InvalidInput {
            quantity: "Poisson's ratio",
            value: poisson,
            rule: "Kalker's table covers 0 <= nu <= 0.5",
        });
    }
    let (side, g) = if a_over_b <= 1.0 {
        (0, a_over_b)
    } else {
        (1, 1.0 / a_over_b)
    };
    let c = if g >= G_MIN {
        tabulated(side, g, poisson)
    } else if side == 0 {
        let at_edge = tabulated(0, G_MIN, poisson);
        let asym_edge = asymptote_narrow(G_MIN, poisson);
        let asym = asymptote_narrow(g, poisson);
        let mut c = [0.0; 4];
        for k in 0..4 {
            c[k] = asym[k] * blend(at_edge[k] / asym_edge[k], g);
        }
        c
    } else {
        let at_edge = tabulated(1, G_MIN, poisson);
        let asym_edge = asymptote_long(G_MIN, poisson);
        let asym = asymptote_long(g, poisson);
        let mut c = [0.0; 4];
        for k in 0..3 {
            c[k] = asym[k] * blend(at_edge[k] / asym_edge[k], g);
        }
        c[3] = c33_long_extended(g, poisson);
        c
    };
    Ok(KalkerCoefficients {
        c11: c[0],
        c22: c[1],
        c23: c[2],
        c33: c[3],
    })
}

/// Continuity factor 1 + (ρ − 1) g/0.1 of an asymptote whose ratio to the
/// table at g = 0.1 is ρ (module docs).
fn blend(rho: f64, g: f64) -> f64 {
    1.0 + (rho - 1.0) * (g / G_MIN)
}

/// Kalker's linear creep law (paper eq. 23, docs/reference/07-contact-forces.md §7.3), forces on the wheel
/// in the contact frame:
///
/// ```text
/// Fx = −G a b C11 ξ
/// Fy = −G a b C22 η − G (ab)^1.5 C23 φ
/// Mz =  G (ab)^1.5 C23 η − G (ab)² C33 φ
/// ```
///
/// No saturation: |F| grows without bound with the creepage (use it for
/// small creepages and linear analysis).
pub(crate) fn linear_forces(input: &CreepInput) -> Result<CreepForces, CreepError> {
    if input.normal_force_n == 0.0 {
        return Ok(CreepForces::ZERO);
    }
    let c = kalker_coefficients(input.a_m / input.b_m, input.poisson)?;
    Ok(linear_forces_with(input, &c))
}

/// [`linear_forces`] with the coefficients already known (validated input).
pub(crate) fn linear_forces_with(input: &CreepInput, c: &KalkerCoefficients) -> CreepForces {
    let g = input.shear_modulus_pa;
    let ab = input.a_m * input.b_m;
    let ab15 = ab * ab.sqrt();
    CreepForces {
        fx_n: -g * ab * c.c11 * input.xi,
        fy_n: -g * ab * c.c22 * input.eta - g * ab15 * c.c23 * input.phi_1_m,
        mz_nm: g * ab15 * c.c23 * input.eta - g * ab * ab * c.c33 * input.phi_1_m,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv_rows() -> Vec<(String, f64, f64, [f64; 4])> {
        TABLE_CSV
            .lines()
            .skip(1)
            .filter(|l| !l.trim().is_empty())
            .map(|l| {
                let c: Vec<&str> = l.split(',').collect();
                let f = |i: usize| c[i].parse::<f64>().unwrap();
                (c[0].to_string(), f(1), f(2), [f(3), f(4), f(5), f(6)])
            })
            .collect()
    }

    fn as_array(c: KalkerCoefficients) -> [f64; 4] {
        [c.c11, c.c22, c.c23, c.c33]
    }

    #[test]
    fn table_parses_with_every_cell() {
        let t = parse_table(TABLE_CSV).unwrap();
        // Circle row shared by both sides.
        assert_eq!(t.sides[0][ROWS - 1], t.sides[1][ROWS - 1]);
        assert_eq!(csv_rows().len(), 57);
    }

    #[test]
    fn malformed_tables_are_rejected() {
        assert!(parse_table("").is_err());
        assert!(parse_table("ratio_kind,ratio,nu,c11,c22,c23,c33\na/b,0.1,0.0,1,2,3,4\n").is_err());
        let dup = format!("{TABLE_CSV}a/b,0.1,0.0,1,2,3,4\n");
        assert!(parse_table(&dup).unwrap_err().contains("duplicated"));
        let bad_nu = TABLE_CSV.replacen("a/b,0.1,0.0,", "a/b,0.1,0.1,", 1);
        assert!(parse_table(&bad_nu).is_err());
    }

    /// Every node of the table (ratio and ν) is reproduced to rounding.
    #[test]
    fn nodes_reproduced_exactly() {
        for (kind, g, nu, want) in csv_rows() {
            let a_over_b = if kind == "a/b" { g } else { 1.0 / g };
            let got = as_array(kalker_coefficients(a_over_b, nu).unwrap());
            for k in 0..4 {
                assert!(
                    (got[k] - want[k]).abs() <= 1e-12 * want[k],
                    "{kind}={g} nu={nu} coef {k}: {} vs {}",
                    got[k],
                    want[k]
                );
            }
        }
    }

    /// ν = 0.3: the parabola in 1/C evaluated independently (Newton's divided
    /// differences rather than Lagrange's form).
    #[test]
    fn poisson_03_follows_kalkers_rule() {
        for (kind, g) in [
            ("a/b", 0.1),
            ("a/b", 0.5),
            ("a/b", 1.0),
            ("b/a", 0.3),
            ("b/a", 0.1),
        ] {
            let a_over_b = if kind == "a/b" { g } else { 1.0 / g };
            let got = as_array(kalker_coefficients(a_over_b, 0.3).unwrap());
            let rows: Vec<_> = csv_rows()
                .into_iter()
                .filter(|r| r.0 == kind && (r.1 - g).abs() < 1e-9)
                .collect();
            assert_eq!(rows.len(), 3);
            for (k, &got_k) in got.iter().enumerate() {
                let y: Vec<f64> = rows.iter().map(|r| 1.0 / r.3[k]).collect();
                let d1 = (y[1] - y[0]) / 0.25;
                let d2 = ((y[2] - y[1]) / 0.25 - d1) / 0.5;
                let inv = y[0] + d1 * 0.3 + d2 * 0.3 * (0.3 - 0.25);
                assert!(
                    (got_k - 1.0 / inv).abs() < 1e-12 * got_k,
                    "{kind}={g} coef {k}"
                );
            }
        }
        // Sanity: between the ν = 0.25 and 0.5 columns for C11 at a = b.
        let c = kalker_coefficients(1.0, 0.3).unwrap();
        assert!(c.c11 > 4.12 && c.c11 < 5.2, "{}", c.c11);
    }

    /// Continuous across a/b = 1 (the shared circle row) and linear between
    /// rows.
    #[test]
    fn continuous_across_the_circle_row() {
        for nu in [0.0, 0.28, 0.5] {
            let below = as_array(kalker_coefficients(1.0 - 1e-9, nu).unwrap());
            let above = as_array(kalker_coefficients(1.0 + 1e-9, nu).unwrap());
            let at = as_array(kalker_coefficients(1.0, nu).unwrap());
            for k in 0..4 {
                assert!((below[k] - at[k]).abs() < 1e-7 * at[k]);
                assert!((above[k] - at[k]).abs() < 1e-7 * at[k]);
            }
        }
        // Midway between two a/b rows at ν = 0: the mean of the nodes.
        let mid = kalker_coefficients(0.65, 0.0).unwrap();
        assert!((mid.c11 - 0.5 * (2.98 + 3.09)).abs() < 1e-12, "{}", mid.c11);
    }

    /// Asymptotes: continuous at the table's ends and tending to Kalker's
    /// closed forms as g → 0.
    #[test]
    fn asymptotes_continuous_and_limiting() {
        for nu in [0.0, 0.25, 0.3, 0.5] {
            for a_over_b in [0.1, 10.0] {
                let at = as_array(kalker_coefficients(a_over_b, nu).unwrap());
                let eps = if a_over_b < 1.0 {
                    1.0 - 1e-10
                } else {
                    1.0 + 1e-10
                };
                let out = as_array(kalker_coefficients(a_over_b * eps, nu).unwrap());
                for k in 0..4 {
                    assert!(
                        (out[k] - at[k]).abs() < 1e-7 * at[k],
                        "{a_over_b} nu {nu} {k}"
                    );
                }
            }
            // Narrow side: ratio to the closed form → 1.
            let g = 1e-6;
            let c = as_array(kalker_coefficients(g, nu).unwrap());
            let asym = asymptote_narrow(g, nu);
            for k in 0..4 {
                assert!((c[k] / asym[k] - 1.0).abs() < 1e-4, "narrow {k}");
            }
            let c = as_array(kalker_coefficients(1.0 / g, nu).unwrap());
            let asym = asymptote_long(g, nu);
            for k in 0..3 {
                assert!((c[k] / asym[k] - 1.0).abs() < 1e-4, "long {k}");
            }
            assert!(c[3] > 0.0 && c[3] < 1.0);
        }
    }

    #[test]
    fn coefficients_positive_and_finite_over_the_whole_range() {
        // A fine sweep over eight decades of a/b and the ν range: nothing
        // negative or non-finite anywhere (table, asymptotes, blends).
        let mut r = 1e-4;
        while r < 1e4 {
            for nu in [0.0, 0.3, 0.5] {
                let c = as_array(kalker_coefficients(r, nu).unwrap());
                assert!(
                    c.iter().all(|v| v.is_finite() && *v > 0.0),
                    "{r} {nu} {c:?}"
                );
            }
            r *= 1.07;
        }
    }

    #[test]
    fn invalid_inputs_are_errors() {
        for r in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(kalker_coefficients(r, 0.3).is_err());
        }
        for nu in [-0.1, 0.51, f64::NAN] {
            assert!(kalker_coefficients(1.0, nu).is_err());
        }
    }
}
