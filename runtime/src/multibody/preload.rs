//! The static preload solve (docs/reference/08-multibody.md §8.3): the
//! preloads that hold every free body in static equilibrium under gravity
//! at the nominal (assembly) geometry.
//!
//! # Rule
//!
//! The geometry stays the nominal one; the preloads are the element forces
//! of the **linearised static deflection** u of the free bodies under
//! gravity and the given constant forces, with the supports fixed:
//!
//! ```text
//! K u = f,   K = Σₑ Gₑᵀ Kₑ Gₑ,   f = Σ_bodies (0, 0, −m g; 0) + Σₑ Gₑᵀ f_given,e
//! preload_e = f_given,e − Kₑ Gₑ u
//! ```
//!
//! u holds 6 values per free body (translation and small rotation about
//! its CG, vehicle axes); Gₑ maps u to the element's deflection
//! δ = δp_b − δp_a with δp = δx + θ × (p − cg) (a's axes are the vehicle
//! axes at assembly; the turning of a's axes, θ_a × Δ₀, is left out — it
//! changes only how an indeterminate load is shared, not the equilibrium);
//! Kₑ is the element's diagonal static stiffness (its linear stiffness plus
//! its nonlinear spring's slope at zero deflection; dampers and series
//! spring–dampers carry no static force). This is the preload distribution
//! the stiffnesses imply, the usual rule for a statically indeterminate
//! suspension (the static deflection of a linear structure, e.g.
//! Knothe & Stichel, *Rail Vehicle Dynamics*, Springer 2017, on the
//! static equilibrium before a dynamic run).
//!
//! Because the generalised force of the preloads is Σₑ Gₑᵀ preload_e =
//! f − K u, the preloads balance every free body exactly (to rounding)
//! whatever u is; u only decides how a load is shared.
//!
//! # Supports
//!
//! Wheelsets are fixed in all six directions at their assembly position —
//! supported by the rails as rigid supports; the wheel loads then follow
//! from the solved element forces on them plus their own weight. The
//! ground and track-following references without a carried mass are fixed
//! too. A reference with a carried mass is a free body of the solve (its
//! weight is carried by its elements; its motion in the run stays
//! prescribed).
//!
//! # Singular stiffness
//!
//! K is solved by SVD with singular values below 1e-12 of the largest
//! dropped (the minimum-norm u; the preloads do not depend on the
//! dropped directions, which deflect no element). If a body's weight has
//! a part in a direction without stiffness, the residual shows it and
//! [`PreloadError::NotSupported`] names the body.

use nalgebra::{DMatrix, DVector, Vector3};

/// A free body of the solve.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticBody {
    pub name: String,
    /// Mass whose weight the elements carry (kg).
    pub mass_kg: f64,
    /// Centre of gravity at assembly, vehicle frame (m).
    pub cg_m: Vector3<f64>,
}

/// An element of the solve.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticElement {
    pub name: String,
    /// End a and b: index of a free body, or `None` for a support.
    pub a: Option<usize>,
    pub b: Option<usize>,
    /// Attachment points at assembly, vehicle frame (m).
    pub point_a_m: Vector3<f64>,
    pub point_b_m: Vector3<f64>,
    /// Static stiffness along x, y, z (N/m).
    pub stiffness_n_m: [f64; 3],
    /// Given constant force on b (N), kept in the preload.
    pub given_n: Vector3<f64>,
}

/// The solution.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticSolution {
    /// Preload of each element: force on b at assembly (N), a's axes.
    pub preloads_n: Vec<Vector3<f64>>,
    /// Static deflection of each free body: translation (m), rotation (rad).
    pub deflection: Vec<(Vector3<f64>, Vector3<f64>)>,
    /// Net force (N) and moment about the CG (N·m) on each free body at
    /// assembly from gravity and the preloads (zero but for rounding).
    pub residual: Vec<(Vector3<f64>, Vector3<f64>)>,
}

/// Why the preloads cannot be solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PreloadError {
    #[error(
        "body '{body}' cannot be held in static equilibrium by its elements: net force [{:.1}, {:.1}, {:.1}] N, moment [{:.1}, {:.1}, {:.1}] N·m left over (a direction with no stiffness; add stiffness, or give the preloads with preload = \"given\")",
        force_n[0], force_n[1], force_n[2], moment_nm[0], moment_nm[1], moment_nm[2]
    )]
    NotSupported {
        body: String,
        force_n: [f64; 3],
        moment_nm: [f64; 3],
    },
    #[error("element '{element}': {what} must be finite (and the stiffness >= 0)")]
    NonFinite { element: String, what: &'static str },
    #[error("body '{body}': mass {mass_kg} kg and its centre of gravity must be finite, mass >= 0")]
    InvalidBody { body: String, mass_kg: f64 },
    #[error(
        "the stiffness matrix or the weights overflow the floating-point range: a stiffness, mass or attachment point is implausibly large (check the unit)"
    )]
    Overflow,
    #[error(
        "the stiffness matrix's singular value decomposition did not converge in {SVD_MAX_ITERATIONS} iterations"
    )]
    NotConverged,
}

/// Bound on the SVD's iterations: a 6 n × 6 n stiffness matrix converges
/// in a few dozen sweeps; a matrix that needs more is degenerate.
pub const SVD_MAX_ITERATIONS: usize = 10_000;

/// Largest residual accepted, relative to a body's weight (force) and to
/// its weight × 1 m (moment), plus 1e-6 N or N·m: rounding in the solve is
/// ~1e-12 relative, so 1e-6 separates rounding from a load without
/// support.
pub const RESIDUAL_TOLERANCE: f64 = 1e-6;

/// The 3 × 6 map from a body's (δx, θ) to a point's displacement:
/// [I | −S(r)], r = p − cg.
fn point_map(r: &Vector3<f64>) -> nalgebra::SMatrix<f64, 3, 6> {
    let mut m = nalgebra::SMatrix::<f64, 3, 6>::zeros();
    for i in 0..3 {
        m[(i, i)] = 1.0;
    }
    // θ × r = −r × θ = −S(r) θ.
    let s = r.cross_matrix();
    m.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-s));
    m
}

/// Solves the preloads (module docs) with gravity `gravity_m_s2` along −z.
pub fn solve_static_preloads(
    bodies: &[StaticBody],
    elements: &[StaticElement],
    gravity_m_s2: f64,
) -> Result<StaticSolution, PreloadError> {
    for b in bodies {
        if !(b.mass_kg.is_finite() && b.mass_kg >= 0.0 && b.cg_m.iter().all(|v| v.is_finite())) {
            return Err(PreloadError::InvalidBody {
                body: b.name.clone(),
                mass_kg: b.mass_kg,
            });
        }
    }
    for e in elements {
        let bad = |what| {
            Err(PreloadError::NonFinite {
                element: e.name.clone(),
                what,
            })
        };
        if !e.stiffness_n_m.iter().all(|k| k.is_finite() && *k >= 0.0) {
            return bad("stiffness");
        }
        if !e.given_n.iter().all(|v| v.is_finite()) {
            return bad("given preload");
        }
        if !e
            .point_a_m
            .iter()
            .chain(e.point_b_m.iter())
            .all(|v| v.is_finite())
        {
            return bad("attachment point");
        }
    }
    let n = 6 * bodies.len();
    // Element maps: (body, sign, 3×6 map) for each free end.
    let ends = |e: &StaticElement| {
        [(e.a, -1.0, e.point_a_m), (e.b, 1.0, e.point_b_m)]
            .into_iter()
            .filter_map(|(end, sign, p)| end.map(|k| (k, sign, point_map(&(p - bodies[k].cg_m)))))
            .collect::<Vec<_>>()
    };
    let mut k_mat = DMatrix::<f64>::zeros(n, n);
    let mut f = DVector::<f64>::zeros(n);
    for (k, b) in bodies.iter().enumerate() {
        f[6 * k + 2] = -b.mass_kg * gravity_m_s2;
    }
    for e in elements {
        let kd = nalgebra::Matrix3::from_diagonal(&Vector3::from(e.stiffness_n_m));
        let ends = ends(e);
        for (i, si, gi) in &ends {
            // Generalised force of the given force: Gᵀ f_given (a: −f).
            let fi = gi.transpose() * (e.given_n * *si);
            for r in 0..6 {
                f[6 * i + r] += fi[r];
            }
            for (j, sj, gj) in &ends {
                let block = gi.transpose() * kd * gj * (si * sj);
                let mut view = k_mat.view_mut((6 * i, 6 * j), (6, 6));
                view += block;
            }
        }
    }
    let u = if n == 0 {
        DVector::zeros(0)
    } else {
        // Finite inputs can still overflow in the products (a stiffness of
        // 1e308 N/m times a lever arm); an SVD of a non-finite matrix never
        // converges, so it is refused before, and the iterations are bounded.
        if !k_mat.iter().chain(f.iter()).all(|v| v.is_finite()) {
            return Err(PreloadError::Overflow);
        }
        let svd = k_mat
            .try_svd(true, true, f64::EPSILON, SVD_MAX_ITERATIONS)
            .ok_or(PreloadError::NotConverged)?;
        let eps = 1e-12 * svd.singular_values.max();
        svd.solve(&f, eps).unwrap_or_else(|_| DVector::zeros(n))
    };
    let body_u =
        |k: usize| nalgebra::SVector::<f64, 6>::from_iterator(u.rows(6 * k, 6).iter().copied());
    let mut preloads_n = Vec::with_capacity(elements.len());
    let mut residual = vec![(Vector3::zeros(), Vector3::zeros()); bodies.len()];
    for (k, b) in bodies.iter().enumerate() {
        residual[k].0.z -= b.mass_kg * gravity_m_s2;
    }
    for e in elements {
        let mut delta = Vector3::zeros();
        for (k, sign, g) in ends(e) {
            delta += g * body_u(k) * sign;
        }
        let preload = e.given_n - Vector3::from(e.stiffness_n_m).component_mul(&delta);
        // The actual forces at assembly: preload on b at p_b, its opposite
        // on a at p_a, moments about the CGs.
        for (end, sign, p) in [(e.a, -1.0, e.point_a_m), (e.b, 1.0, e.point_b_m)] {
            if let Some(k) = end {
                let force = preload * sign;
                residual[k].0 += force;
                residual[k].1 += (p - bodies[k].cg_m).cross(&force);
            }
        }
        preloads_n.push(preload);
    }
    for (b, (force, moment)) in bodies.iter().zip(&residual) {
        let weight = b.mass_kg * gravity_m_s2;
        let tol = RESIDUAL_TOLERANCE * (weight + 1.0);
        if force.norm() > tol || moment.norm() > tol {
            return Err(PreloadError::NotSupported {
                body: b.name.clone(),
                force_n: [force.x, force.y, force.z],
                moment_nm: [moment.x, moment.y, moment.z],
            });
        }
    }
    let deflection = (0..bodies.len())
        .map(|k| {
            let v = body_u(k);
            (
                Vector3::new(v[0], v[1], v[2]),
                Vector3::new(v[3], v[4], v[5]),
            )
        })
        .collect();
    Ok(StaticSolution {
        preloads_n,
        deflection,
        residual,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const G: f64 = 9.81;

    fn spring(
        name: &str,
        a: Option<usize>,
        b: Option<usize>,
        z: f64,
        k: [f64; 3],
    ) -> StaticElement {
        StaticElement {
            name: name.into(),
            a,
            b,
            point_a_m: Vector3::new(0.0, 0.0, z),
            point_b_m: Vector3::new(0.0, 0.0, z),
            stiffness_n_m: k,
            given_n: Vector3::zeros(),
        }
    }

    fn body(name: &str, m: f64, z: f64) -> StaticBody {
        StaticBody {
            name: name.into(),
            mass_kg: m,
            cg_m: Vector3::new(0.0, 0.0, z),
        }
    }

    /// Two masses: body 0 (m₁) between a spring k₁ down to a support and
    /// a spring k₃ up to a support (statically indeterminate), body 1 (m₂)
    /// on body 0 through k₂. By hand: k₂ carries m₂ g; body 0 moves
    /// u₁ = −(m₁ + m₂) g / (k₁ + k₃), so k₁ pushes it up with
    /// k₁/(k₁+k₃) (m₁+m₂) g and k₃ pulls it up with k₃/(k₁+k₃) (m₁+m₂) g.
    /// Elements: a = upper body, b = lower (force on b as preload).
    /// Regression (the vehicle-file fuzz test hung here): finite inputs
    /// whose products overflow made an SVD that never converged; they are
    /// refused with "check the unit".
    #[test]
    fn overflowing_stiffness_is_refused_not_looped_on() {
        let bodies = [body("frame", 1000.0, 0.5)];
        for (k, z) in [(1e308, 10.0), (1e200, 1e200)] {
            let elements = [spring("huge", Some(0), None, z, [k, k, k])];
            let e = solve_static_preloads(&bodies, &elements, G).expect_err("refused");
            assert!(matches!(e, PreloadError::Overflow), "{e}");
            assert!(e.to_string().contains("check the unit"), "{e}");
        }
    }

    #[test]
    fn two_masses_share_by_stiffness() {
        let (m1, m2, k1, k2, k3) = (1000.0, 500.0, 3e6, 1e6, 1e6);
        let bodies = [body("lower", m1, 0.5), body("upper", m2, 1.0)];
        let k = |kz: f64| [1e6, 1e6, kz];
        let elements = [
            spring("k1 (lower on support)", Some(0), None, 0.3, k(k1)),
            spring("k2 (upper on lower)", Some(1), Some(0), 0.8, k(k2)),
            spring("k3 (support above lower)", None, Some(0), 0.7, k(k3)),
        ];
        let sol = solve_static_preloads(&bodies, &elements, G).unwrap();
        let w = (m1 + m2) * G;
        // k1: force on b (support) = −(share) downwards.
        let p = &sol.preloads_n;
        assert!((p[0].z + k1 / (k1 + k3) * w).abs() < 1e-6, "{}", p[0]);
        assert!((p[1].z + m2 * G).abs() < 1e-6, "{}", p[1]);
        // k3: force on b (the lower body) upwards.
        assert!((p[2].z - k3 / (k1 + k3) * w).abs() < 1e-6, "{}", p[2]);
        for pre in p {
            assert!(pre.x.abs() < 1e-9 && pre.y.abs() < 1e-9);
        }
        assert!((sol.deflection[0].0.z + w / (k1 + k3)).abs() < 1e-12);
        assert!((sol.deflection[1].0.z - sol.deflection[0].0.z + m2 * G / k2).abs() < 1e-12);
        for (f, m) in &sol.residual {
            assert!(f.norm() < 1e-8 && m.norm() < 1e-8, "{f} {m}");
        }
    }

    /// A given constant force is kept and its load is carried too: a body
    /// on one spring with a 1 kN downward force on it gets a spring preload
    /// of its weight plus 1 kN.
    #[test]
    fn given_forces_are_kept_and_carried() {
        let bodies = [body("b", 100.0, 1.0)];
        let mut push = spring("push", None, Some(0), 1.0, [0.0; 3]);
        push.given_n = Vector3::new(0.0, 0.0, -1000.0);
        let elements = [spring("k", Some(0), None, 0.5, [1e5, 1e5, 1e5]), push];
        let sol = solve_static_preloads(&bodies, &elements, G).unwrap();
        assert!((sol.preloads_n[0].z + 100.0 * G + 1000.0).abs() < 1e-6);
        assert_eq!(sol.preloads_n[1], Vector3::new(0.0, 0.0, -1000.0));
    }

    /// Off-centre springs share a load by the lever rule: a beam of mass m
    /// with its CG at x = 0.25 on springs at x = 0 and x = 1 (equal k)
    /// carries 3/4 and 1/4 of its weight.
    #[test]
    fn lever_rule() {
        let m = 200.0;
        let bodies = [StaticBody {
            name: "beam".into(),
            mass_kg: m,
            cg_m: Vector3::new(0.25, 0.0, 1.0),
        }];
        let at = |x: f64| StaticElement {
            name: format!("x = {x}"),
            a: Some(0),
            b: None,
            point_a_m: Vector3::new(x, 0.0, 1.0),
            point_b_m: Vector3::new(x, 0.0, 1.0),
            stiffness_n_m: [1e6; 3],
            given_n: Vector3::zeros(),
        };
        // Two more springs across y keep roll determined.
        let mut side = at(0.25);
        side.point_a_m.y = 1.0;
        side.point_b_m.y = 1.0;
        side.stiffness_n_m = [1e6, 1e6, 0.0];
        let sol = solve_static_preloads(&bodies, &[at(0.0), at(1.0), side], G).unwrap();
        let w = m * G;
        assert!(
            (sol.preloads_n[0].z + 0.75 * w).abs() < 1e-6,
            "{}",
            sol.preloads_n[0]
        );
        assert!(
            (sol.preloads_n[1].z + 0.25 * w).abs() < 1e-6,
            "{}",
            sol.preloads_n[1]
        );
    }

    /// A body held only sideways cannot carry its weight: the error names
    /// it and the force left over.
    #[test]
    fn unsupported_weight_is_named() {
        let bodies = [body("hanging", 100.0, 1.0)];
        let elements = [spring("lateral only", Some(0), None, 1.0, [1e5, 1e5, 0.0])];
        let e = solve_static_preloads(&bodies, &elements, G).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("'hanging'") && text.contains("-981.0"),
            "{text}"
        );
        let bad = [spring("nan", Some(0), None, 1.0, [f64::NAN, 0.0, 1e5])];
        assert!(matches!(
            solve_static_preloads(&bodies, &bad, G),
            Err(PreloadError::NonFinite {
                what: "stiffness",
                ..
            })
        ));
    }
}
