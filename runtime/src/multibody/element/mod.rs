//! Suspension elements between two anchors (docs/reference/08-multibody.md §8):
//! linear springs and dampers per axis, with the nonlinear additions of
//! [`law`] (bump stops, force–deflection tables, bilinear and tabulated
//! dampers) and [`series`] (a spring in series with a damper, with one
//! internal state per axis), and a constant preload.
//!
//! # Anchors
//!
//! An [`Anchor`] is anything an element attaches to: an origin with its
//! velocity, and a set of axes with its angular velocity, all in global
//! components. Ordinary bodies give one through [`Anchor::from_body`]; the
//! simulator also builds anchors for frames that are not a body's own (a
//! wheelset's non-spinning axle frame, a reference moving along the track).
//!
//! # The element
//!
//! Three uncoupled linear springs and dampers act along the axes of anchor
//! **a** — the directions x, y, z are "in the frame of one body" (Pombo,
//! Ambrósio & Silva's suspension model; e.g. a primary suspension expressed
//! in the bogie frame). With the attachment points p_a, p_b (global), R_a the
//! rotation of a's axes into global and ω_a its angular velocity (global):
//!
//! ```text
//! Δ  = R_aᵀ (p_b − p_a)                     relative displacement, a's axes (m)
//! Δ̇  = R_aᵀ (v_pb − v_pa) − ω_a,loc × Δ      its rate in a's axes (m/s), ω_a,loc = R_aᵀ ω_a
//! f  = f₀ − K (Δ − Δ₀) − C Δ̇                 force on b, a's axes (N); K, C diagonal
//! F_b = R_a f at p_b,    F_a = −R_a f at p_a  (global)
//! ```
//!
//! Δ₀ is the relative displacement at the reference (assembly)
//! configuration and f₀ the preload, the force on b there. With the
//! nonlinear additions of axis i ([`AxisLaws`]; δ = Δ − Δ₀, v = Δ̇, qᵢ the
//! series damper's stroke):
//!
//! ```text
//! fᵢ = f₀ᵢ − kᵢ δᵢ − cᵢ vᵢ − S(δᵢ) − D(vᵢ) − k_sᵢ (δᵢ − qᵢ),   q̇ᵢ = k_sᵢ (δᵢ − qᵢ) / c_sᵢ
//! ```
//!
//! S a [`SpringLaw`], D a [`DamperLaw`], (k_s, c_s) a [`SeriesLaw`]; each
//! absent term is zero. The strokes q are the element's internal state
//! ([`SpringDamper::internal_len`] values, one per series axis, in axis
//! order), zero at assembly.
//!
//! Derivation of Δ̇ (S(ω) is the cross-product matrix, S(ω) u = ω × u):
//!
//! ```text
//! d = p_b − p_a,   Ṙ_a = S(ω_a) R_a   ⇒   d(R_aᵀ)/dt = −R_aᵀ S(ω_a)
//! Δ̇ = R_aᵀ ḋ − R_aᵀ (ω_a × d) = R_aᵀ ḋ − (R_aᵀ ω_a) × (R_aᵀ d) = R_aᵀ ḋ − ω_a,loc × Δ
//! ```
//!
//! with ḋ = v_pb − v_pa: the rate at which
//! the separation changes **as seen by an observer fixed to a's axes**
//! (the derivative of a vector in a moving frame, e.g. Shabana, *Dynamics
//! of Multibody Systems*, 3rd ed., 2005, ch. 2). So a rigid rotation of the
//! whole pair produces no damping force.
//!
//! # Balance and energy
//!
//! The forces on a and b are equal and opposite (total force zero), but they
//! act at different points: the pair exerts the couple
//! (p_b − p_a) × F_b = R_a (Δ × f) on the system, zero only when f ∥ Δ (or
//! the points coincide). That is the model as specified (no end moments, as
//! in a coil spring's shear stiffness without its bending stiffness); it is
//! small for short elements.
//!
//! [`SpringDamper::potential_energy_j`], U = ½ Σ kᵢ (Δᵢ − Δ₀ᵢ)² − f₀·(Δ − Δ₀) +
//! Σ ∫₀^δᵢ S + Σ ½ k_sᵢ (δᵢ − qᵢ)², satisfies f·Δ̇ = −dU/dt − P_diss with
//! [`SpringDamper::dissipated_power_w`] P_diss = Σ cᵢ Δ̇ᵢ² + Σ D(vᵢ) vᵢ +
//! Σ k_sᵢ² (δᵢ − qᵢ)² / c_sᵢ ≥ 0 (the series damper's c_s q̇², [`series`]). The power the
//! element delivers to the two anchors is
//! F_b·v_pb + F_a·v_pa = f·R_aᵀ(v_pb − v_pa) = f·Δ̇ + f·(ω_a,loc × Δ), so U
//! is the element's exact potential energy (and total energy with U is
//! conserved without damping) **when anchor a does not rotate**, or when
//! f ∥ Δ; otherwise the unbalanced couple does the work f·(ω_a,loc × Δ).

pub mod law;
pub mod series;

use nalgebra::{Matrix3, Vector3};

pub use law::{AxisLaws, DamperLaw, LawError, PiecewiseLinear, SeriesLaw, SpringLaw};

use crate::multibody::body::{BodyState, Wrench};

/// A frame an element can attach to: origin and axes with their rates, all
/// in global components.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Anchor {
    /// Origin (a body's CG), global (m).
    pub position_m: Vector3<f64>,
    /// Rotation anchor axes → global.
    pub rotation: Matrix3<f64>,
    /// Velocity of the origin, global (m/s).
    pub velocity_m_s: Vector3<f64>,
    /// Angular velocity of the axes, **global** (rad/s).
    pub angular_velocity_rad_s: Vector3<f64>,
}

impl Anchor {
    /// A frame fixed in space.
    pub fn fixed(position_m: Vector3<f64>, rotation: Matrix3<f64>) -> Self {
        Self {
            position_m,
            rotation,
            velocity_m_s: Vector3::zeros(),
            angular_velocity_rad_s: Vector3::zeros(),
        }
    }

    /// The body's own frame: origin at the CG, body axes, ω converted to
    /// global axes.
    pub fn from_body(state: &BodyState) -> Self {
        Self {
            position_m: state.position_m,
            rotation: state.rotation(),
            velocity_m_s: state.velocity_m_s,
            angular_velocity_rad_s: state.angular_velocity_global(),
        }
    }

    /// Global position (m) of a point given in anchor axes from the origin
    /// (m): o + R p.
    pub fn point_position(&self, local_point_m: &Vector3<f64>) -> Vector3<f64> {
        self.position_m + self.rotation * local_point_m
    }

    /// Global velocity (m/s) of a point fixed in the anchor frame, given in
    /// anchor axes (m): v + ω × (R p).
    pub fn point_velocity(&self, local_point_m: &Vector3<f64>) -> Vector3<f64> {
        self.velocity_m_s
            + self
                .angular_velocity_rad_s
                .cross(&(self.rotation * local_point_m))
    }
}

/// Why a [`SpringDamper`] is not usable.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ElementError {
    /// A stiffness is NaN, infinite or negative (axis 0, 1, 2 = a's x, y, z).
    #[error("stiffness along axis {axis} = {value_n_m} N/m must be finite and >= 0")]
    InvalidStiffness { axis: usize, value_n_m: f64 },
    /// A damping coefficient is NaN, infinite or negative.
    #[error("damping along axis {axis} = {value_n_s_m} N·s/m must be finite and >= 0")]
    InvalidDamping { axis: usize, value_n_s_m: f64 },
    /// A preload component is NaN or infinite.
    #[error("preload {preload_n:?} N (anchor a's axes) must be finite")]
    NonFinitePreload { preload_n: [f64; 3] },
    /// An attachment point or the reference offset is not finite.
    #[error("{field} {value_m:?} m must be finite")]
    NonFiniteGeometry {
        field: &'static str,
        value_m: [f64; 3],
    },
    /// A nonlinear law of an axis breaks a rule.
    #[error("the nonlinear law along axis {axis}: {source}")]
    Law {
        axis: usize,
        #[source]
        source: LawError,
    },
}

/// A spring–damper with three uncoupled directions, anchor a's axes
/// (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct SpringDamper {
    /// Attachment point on a, in a's axes from its origin (m).
    pub point_a_m: Vector3<f64>,
    /// Attachment point on b, in b's axes from its origin (m).
    pub point_b_m: Vector3<f64>,
    /// Stiffness along a's x, y, z (N/m).
    pub stiffness_n_m: [f64; 3],
    /// Damping along a's x, y, z (N·s/m).
    pub damping_n_s_m: [f64; 3],
    /// Force on b at the reference configuration, a's axes (N).
    pub preload_n: Vector3<f64>,
    /// Δ₀, the relative displacement R_aᵀ(p_b − p_a) at the reference
    /// configuration, a's axes (m).
    pub reference_offset_m: Vector3<f64>,
    /// Nonlinear additions along a's x, y, z (none: linear).
    pub laws: [AxisLaws; 3],
}

/// Result of [`SpringDamper::evaluate`] (default: all zero).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ElementForce {
    /// Force on anchor b, global (N); the force on a is its opposite.
    pub force_on_b_n: Vector3<f64>,
    /// Attachment point on a, global (m).
    pub point_a_m: Vector3<f64>,
    /// Attachment point on b, global (m).
    pub point_b_m: Vector3<f64>,
    /// Deflection Δ − Δ₀, a's axes (m).
    pub deflection_m: Vector3<f64>,
    /// Deflection rate Δ̇, a's axes (m/s).
    pub rate_m_s: Vector3<f64>,
    /// Rates q̇ of the internal states (the series dampers' strokes, m/s),
    /// the first [`SpringDamper::internal_len`] used.
    pub internal_rate_m_s: [f64; 3],
}

impl ElementForce {
    /// Force on anchor a, global (N): −force on b.
    pub fn force_on_a_n(&self) -> Vector3<f64> {
        -self.force_on_b_n
    }

    /// Adds the element's forces to the wrenches of the two bodies carrying
    /// the anchors (CGs `cg_a_m`, `cg_b_m`, global, m): −F_b at p_a into
    /// `wrench_a`, F_b at p_b into `wrench_b`.
    pub fn add_to_wrenches(
        &self,
        wrench_a: &mut Wrench,
        cg_a_m: &Vector3<f64>,
        wrench_b: &mut Wrench,
        cg_b_m: &Vector3<f64>,
    ) {
        wrench_a.add_force_at(cg_a_m, &self.point_a_m, &self.force_on_a_n());
        wrench_b.add_force_at(cg_b_m, &self.point_b_m, &self.force_on_b_n);
    }
}

fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

impl SpringDamper {
    /// An element assembled at the current configuration of the two anchors:
    /// the global attachment points become local points of their anchors,
    /// Δ₀ is set to the current R_aᵀ(p_b − p_a), so that the element exerts
    /// exactly `preload_n` (a's axes, on b) there when at rest. Validated.
    pub fn assembled(
        anchor_a: &Anchor,
        anchor_b: &Anchor,
        point_a_global_m: &Vector3<f64>,
        point_b_global_m: &Vector3<f64>,
        stiffness_n_m: [f64; 3],
        damping_n_s_m: [f64; 3],
        preload_n: Vector3<f64>,
    ) -> Result<Self, ElementError> {
        let element = Self {
            point_a_m: anchor_a.rotation.transpose() * (point_a_global_m - anchor_a.position_m),
            point_b_m: anchor_b.rotation.transpose() * (point_b_global_m - anchor_b.position_m),
            stiffness_n_m,
            damping_n_s_m,
            preload_n,
            reference_offset_m: anchor_a.rotation.transpose()
                * (point_b_global_m - point_a_global_m),
            laws: Default::default(),
        };
        element.validate()?;
        Ok(element)
    }

    /// The element with the nonlinear additions `laws` (a's x, y, z).
    /// Validated.
    pub fn with_laws(mut self, laws: [AxisLaws; 3]) -> Result<Self, ElementError> {
        self.laws = laws;
        self.validate()?;
        Ok(self)
    }

    /// Number of internal states: one per axis with a series
    /// spring–damper.
    pub fn internal_len(&self) -> usize {
        self.laws.iter().filter(|l| l.series.is_some()).count()
    }

    /// Stiffness per axis at zero deflection for the static preload solve
    /// (N/m): the linear stiffness plus the nonlinear spring's
    /// ([`SpringLaw::stiffness_at_zero_n_m`]); series elements carry no
    /// static force ([`series`]).
    pub fn static_stiffness_n_m(&self) -> [f64; 3] {
        std::array::from_fn(|i| {
            self.stiffness_n_m[i]
                + self.laws[i]
                    .spring
                    .as_ref()
                    .map_or(0.0, SpringLaw::stiffness_at_zero_n_m)
        })
    }

    /// Checks: stiffness and damping finite and ≥ 0 per axis, preload
    /// finite, attachment points and Δ₀ finite.
    pub fn validate(&self) -> Result<(), ElementError> {
        for axis in 0..3 {
            let k = self.stiffness_n_m[axis];
            if !(k.is_finite() && k >= 0.0) {
                return Err(ElementError::InvalidStiffness { axis, value_n_m: k });
            }
            let c = self.damping_n_s_m[axis];
            if !(c.is_finite() && c >= 0.0) {
                return Err(ElementError::InvalidDamping {
                    axis,
                    value_n_s_m: c,
                });
            }
            self.laws[axis]
                .validate()
                .map_err(|source| ElementError::Law { axis, source })?;
        }
        if !self.preload_n.iter().all(|v| v.is_finite()) {
            return Err(ElementError::NonFinitePreload {
                preload_n: arr(&self.preload_n),
            });
        }
        for (field, v) in [
            ("attachment point on a", &self.point_a_m),
            ("attachment point on b", &self.point_b_m),
            ("reference offset", &self.reference_offset_m),
        ] {
            if !v.iter().all(|x| x.is_finite()) {
                return Err(ElementError::NonFiniteGeometry {
                    field,
                    value_m: arr(v),
                });
            }
        }
        Ok(())
    }

    /// Forces of the element between anchors `a` and `b` (module docs),
    /// with the internal states `internal_m` (the series strokes q,
    /// [`Self::internal_len`] values; missing ones are taken as zero).
    pub fn evaluate(&self, a: &Anchor, b: &Anchor, internal_m: &[f64]) -> ElementForce {
        self.evaluate_along(a, b, internal_m, None)
    }

    /// [`Self::evaluate`] with the stiffness, damping and preload acting
    /// along `axes` instead of anchor a's (only their rotation and angular
    /// velocity are used; [`super::formulation::ElementAxes::Track`]).
    /// Deflections and rates are then measured in those axes; the
    /// attachment points still move with their anchors.
    pub fn evaluate_along(
        &self,
        a: &Anchor,
        b: &Anchor,
        internal_m: &[f64],
        axes: Option<&Anchor>,
    ) -> ElementForce {
        let mut out = ElementForce::default();
        self.evaluate_along_into(a, b, internal_m, axes, &mut out);
        out
    }

    /// [`Self::evaluate_along`] written into `out` (the vehicle's force
    /// slots: a force is 144 bytes, and building it elsewhere to copy it in
    /// showed in the profile).
    pub fn evaluate_along_into(
        &self,
        a: &Anchor,
        b: &Anchor,
        internal_m: &[f64],
        axes: Option<&Anchor>,
        out: &mut ElementForce,
    ) {
        let (rotation, omega) = axes.map_or((a.rotation, a.angular_velocity_rad_s), |f| {
            (f.rotation, f.angular_velocity_rad_s)
        });
        // Each attachment point's lever arm R p, once for its position and
        // its velocity (the values of `Anchor::point_position` and
        // `Anchor::point_velocity`).
        let arm_a_m = a.rotation * self.point_a_m;
        let arm_b_m = b.rotation * self.point_b_m;
        let point_a_m = a.position_m + arm_a_m;
        let point_b_m = b.position_m + arm_b_m;
        let velocity_a_m_s = a.velocity_m_s + a.angular_velocity_rad_s.cross(&arm_a_m);
        let velocity_b_m_s = b.velocity_m_s + b.angular_velocity_rad_s.cross(&arm_b_m);
        let rt = rotation.transpose();
        let delta = rt * (point_b_m - point_a_m);
        let w_local = rt * omega;
        let rate_m_s = rt * (velocity_b_m_s - velocity_a_m_s) - w_local.cross(&delta);
        let deflection_m = delta - self.reference_offset_m;
        let k = Vector3::from(self.stiffness_n_m);
        let c = Vector3::from(self.damping_n_s_m);
        let mut f_local =
            self.preload_n - k.component_mul(&deflection_m) - c.component_mul(&rate_m_s);
        let mut internal_rate_m_s = [0.0; 3];
        if self.laws.iter().any(|l| !l.is_linear()) {
            let mut slot = 0;
            for (i, law) in self.laws.iter().enumerate() {
                if let Some(s) = &law.spring {
                    f_local[i] -= s.force_n(deflection_m[i]);
                }
                if let Some(d) = &law.damper {
                    f_local[i] -= d.force_n(rate_m_s[i]);
                }
                if let Some(s) = &law.series {
                    let q = internal_m.get(slot).copied().unwrap_or(0.0);
                    f_local[i] -= s.force_n(deflection_m[i], q);
                    internal_rate_m_s[slot] = s.stroke_rate_m_s(deflection_m[i], q);
                    slot += 1;
                }
            }
        }
        *out = ElementForce {
            force_on_b_n: rotation * f_local,
            point_a_m,
            point_b_m,
            deflection_m,
            rate_m_s,
            internal_rate_m_s,
        };
    }

    /// Calls `f(axis, law, stroke)` for every series axis with its stroke
    /// from `internal_m` (zero if missing).
    fn for_series(&self, internal_m: &[f64], mut f: impl FnMut(usize, &SeriesLaw, f64)) {
        let mut slot = 0;
        for (i, law) in self.laws.iter().enumerate() {
            if let Some(s) = &law.series {
                f(i, s, internal_m.get(slot).copied().unwrap_or(0.0));
                slot += 1;
            }
        }
    }

    /// Potential energy (J) for a deflection δ = Δ − Δ₀ (a's axes, m) and
    /// the internal states `internal_m`: ½ Σ kᵢ δᵢ² − f₀·δ + Σ ∫₀^δᵢ Sᵢ +
    /// Σ ½ k_sᵢ (δᵢ − qᵢ)²; zero at the reference configuration. Exact
    /// potential of the element when anchor a does not rotate (module
    /// docs).
    pub fn potential_energy_j(&self, deflection_m: &Vector3<f64>, internal_m: &[f64]) -> f64 {
        let k = Vector3::from(self.stiffness_n_m);
        let mut u = 0.5 * k.dot(&deflection_m.component_mul(deflection_m))
            - self.preload_n.dot(deflection_m);
        for (i, law) in self.laws.iter().enumerate() {
            if let Some(s) = &law.spring {
                u += s.energy_j(deflection_m[i]);
            }
        }
        self.for_series(internal_m, |i, s, q| u += s.energy_j(deflection_m[i], q));
        u
    }

    /// Power dissipated by the dampers (W) at a deflection δ (m), a
    /// deflection rate Δ̇ (a's axes, m/s) and the internal states:
    /// Σ cᵢ Δ̇ᵢ² + Σ D(Δ̇ᵢ) Δ̇ᵢ + Σ k_sᵢ² (δᵢ − qᵢ)² / c_sᵢ ≥ 0.
    pub fn dissipated_power_w(
        &self,
        deflection_m: &Vector3<f64>,
        rate_m_s: &Vector3<f64>,
        internal_m: &[f64],
    ) -> f64 {
        let mut p = Vector3::from(self.damping_n_s_m).dot(&rate_m_s.component_mul(rate_m_s));
        for (i, law) in self.laws.iter().enumerate() {
            if let Some(d) = &law.damper {
                p += d.force_n(rate_m_s[i]) * rate_m_s[i];
            }
        }
        self.for_series(internal_m, |i, s, q| {
            p += s.dissipated_power_w(deflection_m[i], q)
        });
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

    fn rot(v: [f64; 3]) -> Matrix3<f64> {
        UnitQuaternion::from_scaled_axis(Vector3::from(v))
            .to_rotation_matrix()
            .into_inner()
    }

    fn moving(p: [f64; 3], r: [f64; 3], v: [f64; 3], w: [f64; 3]) -> Anchor {
        Anchor {
            position_m: Vector3::from(p),
            rotation: rot(r),
            velocity_m_s: Vector3::from(v),
            angular_velocity_rad_s: Vector3::from(w),
        }
    }

    fn element() -> SpringDamper {
        SpringDamper {
            point_a_m: Vector3::new(0.3, -0.2, 0.1),
            point_b_m: Vector3::new(-0.1, 0.4, -0.5),
            stiffness_n_m: [1e5, 2e5, 3e5],
            damping_n_s_m: [1e3, 2e3, 5e3],
            preload_n: Vector3::new(10.0, -20.0, 3e4),
            reference_offset_m: Vector3::new(0.0, 0.0, 0.3),
            laws: Default::default(),
        }
    }

    #[test]
    fn along_other_axes_the_preload_keeps_their_direction_when_body_a_rolls() {
        // A preloaded vertical spring, body a rolled by 0.1 rad, b placed
        // where the undeflected spring puts it: along a's axes the preload
        // tilts with a (a lateral component −sin(0.1)·3e4 on b), along the
        // track axes it stays vertical.
        let e = SpringDamper {
            point_a_m: Vector3::zeros(),
            point_b_m: Vector3::zeros(),
            stiffness_n_m: [0.0, 0.0, 1e5],
            damping_n_s_m: [0.0; 3],
            preload_n: Vector3::new(0.0, 0.0, 3e4),
            reference_offset_m: Vector3::zeros(),
            laws: Default::default(),
        };
        let a = moving([0.0; 3], [0.1, 0.0, 0.0], [0.0; 3], [0.0; 3]);
        let b = moving([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
        let body = e.evaluate(&a, &b, &[]);
        assert!((body.force_on_b_n.y - (-(0.1_f64).sin() * 3e4)).abs() < 1e-9);
        let track = Anchor::fixed(Vector3::zeros(), Matrix3::identity());
        let along = e.evaluate_along(&a, &b, &[], Some(&track));
        assert!(along.force_on_b_n.y.abs() < 1e-12, "{}", along.force_on_b_n);
        assert!((along.force_on_b_n.z - 3e4).abs() < 1e-9);
        // Without other axes the two agree.
        assert_eq!(e.evaluate_along(&a, &b, &[], None), body);
    }

    #[test]
    fn validate_names_the_rule() {
        assert_eq!(element().validate(), Ok(()));
        let mut e = element();
        e.stiffness_n_m[1] = -1.0;
        assert!(matches!(
            e.validate(),
            Err(ElementError::InvalidStiffness { axis: 1, .. })
        ));
        e = element();
        e.damping_n_s_m[2] = f64::INFINITY;
        assert!(matches!(
            e.validate(),
            Err(ElementError::InvalidDamping { axis: 2, .. })
        ));
        e = element();
        e.preload_n.x = f64::NAN;
        assert!(matches!(
            e.validate(),
            Err(ElementError::NonFinitePreload { .. })
        ));
        e = element();
        e.point_b_m.y = f64::NAN;
        assert!(matches!(
            e.validate(),
            Err(ElementError::NonFiniteGeometry {
                field: "attachment point on b",
                ..
            })
        ));
        let a = Anchor::fixed(Vector3::zeros(), Matrix3::identity());
        assert!(matches!(
            SpringDamper::assembled(
                &a,
                &a,
                &Vector3::zeros(),
                &Vector3::zeros(),
                [1.0, 1.0, f64::NAN],
                [0.0; 3],
                Vector3::zeros()
            ),
            Err(ElementError::InvalidStiffness { axis: 2, .. })
        ));
    }

    #[test]
    fn anchor_from_body_matches_body_kinematics() {
        let s = BodyState {
            position_m: Vector3::new(1.0, -2.0, 0.5),
            orientation: UnitQuaternion::from_scaled_axis(Vector3::new(0.2, 0.5, -0.3)),
            velocity_m_s: Vector3::new(3.0, 0.1, -0.2),
            angular_velocity_rad_s: Vector3::new(0.7, -1.1, 2.0),
        };
        let a = Anchor::from_body(&s);
        let p = Vector3::new(0.4, -0.6, 0.9);
        assert!((a.point_position(&p) - s.point_position(&p)).norm() < 1e-14);
        assert!((a.point_velocity(&p) - s.point_velocity(&p)).norm() < 1e-14);
    }

    /// Total force zero; total moment about any point equals the couple
    /// (p_b − p_a) × F_b = R_a (Δ × f) (module docs), and vanishes when the
    /// attachment points coincide. Tolerance 1e-9 relative to |F| (forces of
    /// ~1e4 N, lever arms ~1 m).
    #[test]
    fn newtons_third_law() {
        let a = moving(
            [0.1, 0.2, 0.3],
            [0.1, -0.2, 0.4],
            [1.0, 0.0, 0.5],
            [0.3, 0.2, -0.1],
        );
        let b = moving(
            [0.4, 0.1, -0.2],
            [-0.3, 0.2, 0.1],
            [0.8, 0.2, 0.1],
            [-0.2, 0.5, 0.3],
        );
        let e = element();
        let f = e.evaluate(&a, &b, &[]);
        let scale = f.force_on_b_n.norm();
        assert!(scale > 1e3);
        assert_eq!(f.force_on_a_n() + f.force_on_b_n, Vector3::zeros());
        let o = Vector3::new(5.0, -3.0, 2.0);
        let moment =
            (f.point_a_m - o).cross(&f.force_on_a_n()) + (f.point_b_m - o).cross(&f.force_on_b_n);
        let couple = (f.point_b_m - f.point_a_m).cross(&f.force_on_b_n);
        assert!((moment - couple).norm() < 1e-9 * scale);
        let delta = f.deflection_m + e.reference_offset_m;
        let f_local = a.rotation.transpose() * f.force_on_b_n;
        assert!((couple - a.rotation * delta.cross(&f_local)).norm() < 1e-9 * scale);
        // Wrenches: same total force and the same couple.
        let (mut wa, mut wb) = (Wrench::zero(), Wrench::zero());
        f.add_to_wrenches(&mut wa, &a.position_m, &mut wb, &b.position_m);
        assert_eq!(wa.force_n + wb.force_n, Vector3::zeros());
        let m_o = wa.moment_nm
            + (a.position_m - o).cross(&wa.force_n)
            + wb.moment_nm
            + (b.position_m - o).cross(&wb.force_n);
        assert!((m_o - couple).norm() < 1e-9 * scale);
        // Coincident attachment points: no couple.
        let mut e0 = e.clone();
        e0.point_b_m = b.rotation.transpose() * (a.point_position(&e.point_a_m) - b.position_m);
        let f0 = e0.evaluate(&a, &b, &[]);
        let m0 = (f0.point_a_m - o).cross(&f0.force_on_a_n())
            + (f0.point_b_m - o).cross(&f0.force_on_b_n);
        assert!(m0.norm() < 1e-9 * f0.force_on_b_n.norm(), "{m0}");
    }

    /// Stretch by d along a's x (a rotated, both at rest, no preload):
    /// force on b = −k_x d along a's x (global R_a x̂), to 1e-9 N.
    /// The same local configuration with a rotated differently gives the
    /// same local force, rotated with a.
    #[test]
    fn stretch_along_a_x_and_rotating_a() {
        let mut e = element();
        e.preload_n = Vector3::zeros();
        e.reference_offset_m = Vector3::new(0.5, 0.0, 0.0);
        let d = 0.01;
        for r in [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, std::f64::consts::FRAC_PI_2],
            [0.4, -0.9, 1.3],
        ] {
            let a = moving([1.0, 2.0, 3.0], r, [0.0; 3], [0.0; 3]);
            // b's origin placed so that Δ = (0.5 + d, 0, 0) in a's axes.
            let pb = a.point_position(&(e.point_a_m + Vector3::new(0.5 + d, 0.0, 0.0)));
            let b = Anchor::fixed(pb - e.point_b_m, Matrix3::identity());
            let f = e.evaluate(&a, &b, &[]);
            assert!((f.deflection_m - Vector3::new(d, 0.0, 0.0)).norm() < 1e-14);
            let expected = a.rotation * Vector3::new(-1e5 * d, 0.0, 0.0);
            assert!(
                (f.force_on_b_n - expected).norm() < 1e-9,
                "{r:?}: {}",
                f.force_on_b_n
            );
        }
        // 90° yaw: a's x is global y, so the restoring force is along −Y.
        let a = moving(
            [0.0; 3],
            [0.0, 0.0, std::f64::consts::FRAC_PI_2],
            [0.0; 3],
            [0.0; 3],
        );
        let pb = a.point_position(&(e.point_a_m + Vector3::new(0.5 + d, 0.0, 0.0)));
        let f = e.evaluate(
            &a,
            &Anchor::fixed(pb - e.point_b_m, Matrix3::identity()),
            &[],
        );
        assert!((f.force_on_b_n - Vector3::new(0.0, -1e5 * d, 0.0)).norm() < 1e-9);
    }

    /// Damping: at zero deflection and no preload, force = −C Δ̇ with
    /// Δ̇ = R_aᵀ v_rel for non-rotating anchors, opposing the relative
    /// velocity (f·v_rel < 0, power −Σ cᵢΔ̇ᵢ²).
    #[test]
    fn damper_opposes_relative_velocity() {
        let mut e = element();
        e.preload_n = Vector3::zeros();
        let a = moving([0.0; 3], [0.3, 0.1, -0.2], [0.5, 0.0, 0.0], [0.0; 3]);
        let pa = a.point_position(&e.point_a_m);
        let pb = pa + a.rotation * e.reference_offset_m;
        let v_b = Vector3::new(0.2, -0.3, 0.7);
        let b = Anchor {
            velocity_m_s: v_b,
            ..Anchor::fixed(pb - e.point_b_m, Matrix3::identity())
        };
        let f = e.evaluate(&a, &b, &[]);
        assert!(f.deflection_m.norm() < 1e-14);
        let v_rel = v_b - a.velocity_m_s;
        let rate = a.rotation.transpose() * v_rel;
        assert!((f.rate_m_s - rate).norm() < 1e-15);
        let expected = a.rotation * -Vector3::from(e.damping_n_s_m).component_mul(&rate);
        assert!((f.force_on_b_n - expected).norm() < 1e-9);
        let power = f.force_on_b_n.dot(&v_rel);
        assert!(power < 0.0);
        assert!((power + e.dissipated_power_w(&f.deflection_m, &f.rate_m_s, &[])).abs() < 1e-9);
    }

    /// Δ̇ = R_aᵀ(v_pb − v_pa) − ω_a,loc × Δ equals the finite-difference
    /// derivative of Δ(t) = R_a(t)ᵀ (p_b(t) − p_a(t)) with both anchors
    /// translating and rotating (central difference, h = 1e-5 s: error
    /// ~1e-10 m/s on rates of ~1 m/s; tolerance 1e-8).
    #[test]
    fn rate_is_derivative_in_a_axes() {
        let e = element();
        let a0 = moving(
            [0.1, 0.2, 0.3],
            [0.1, -0.2, 0.4],
            [1.0, 0.0, 0.5],
            [0.3, 2.0, -1.1],
        );
        let b0 = moving(
            [0.4, 0.1, -0.2],
            [-0.3, 0.2, 0.1],
            [0.8, 0.2, 0.1],
            [-0.2, 0.5, 1.3],
        );
        let at = |an: &Anchor, t: f64| Anchor {
            position_m: an.position_m + an.velocity_m_s * t,
            rotation: rot(arr(&(an.angular_velocity_rad_s * t))) * an.rotation,
            ..*an
        };
        let h = 1e-5;
        let delta = |t: f64| {
            let f = e.evaluate(&at(&a0, t), &at(&b0, t), &[]);
            f.deflection_m
        };
        let fd = (delta(h) - delta(-h)) / (2.0 * h);
        let rate = e.evaluate(&a0, &b0, &[]).rate_m_s;
        assert!(rate.norm() > 0.5);
        assert!((rate - fd).norm() < 1e-8, "{rate} vs {fd}");
        // A rigid rotation of the whole pair about a's origin: Δ̇ = 0.
        let w = Vector3::new(0.4, -1.2, 0.9);
        let b_rigid = Anchor {
            velocity_m_s: a0.velocity_m_s + w.cross(&(b0.position_m - a0.position_m)),
            angular_velocity_rad_s: w,
            ..b0
        };
        let a_rigid = Anchor {
            angular_velocity_rad_s: w,
            ..a0
        };
        assert!(e.evaluate(&a_rigid, &b_rigid, &[]).rate_m_s.norm() < 1e-14);
    }

    /// Assembled at a configuration, at rest there: force = R_a f₀, zero
    /// deflection and zero energy (to rounding: 1e-15 m deflection,
    /// 1e-9 N force with k ~ 1e5 N/m).
    #[test]
    fn preload_at_assembly() {
        let a = moving([0.1, 0.2, 0.3], [0.1, -0.2, 0.4], [0.0; 3], [0.0; 3]);
        let b = moving([0.4, 0.1, -0.8], [-0.3, 0.2, 0.1], [0.0; 3], [0.0; 3]);
        let pa = Vector3::new(0.2, 0.3, 0.0);
        let pb = Vector3::new(0.3, 0.1, -0.6);
        let preload = Vector3::new(100.0, -50.0, 4e4);
        let e = SpringDamper::assembled(&a, &b, &pa, &pb, [1e5, 2e5, 3e5], [1e3; 3], preload)
            .expect("valid element");
        let f = e.evaluate(&a, &b, &[]);
        assert!((f.point_a_m - pa).norm() < 1e-15);
        assert!((f.point_b_m - pb).norm() < 1e-15);
        assert!(f.deflection_m.norm() < 1e-15, "{}", f.deflection_m);
        assert!((f.force_on_b_n - a.rotation * preload).norm() < 1e-9);
        assert!(e.potential_energy_j(&f.deflection_m, &[]).abs() < 1e-9);
    }

    /// U = ½ Σ kᵢδᵢ² − f₀·δ: its gradient is the spring part of −f
    /// (central difference, tolerance 1e-6 N on ~1e3 N).
    #[test]
    fn potential_gradient_is_spring_force() {
        let e = element();
        let d = Vector3::new(0.01, -0.02, 0.005);
        let h = 1e-6;
        for i in 0..3 {
            let mut dp = d;
            dp[i] += h;
            let mut dm = d;
            dm[i] -= h;
            let grad =
                (e.potential_energy_j(&dp, &[]) - e.potential_energy_j(&dm, &[])) / (2.0 * h);
            let spring = e.preload_n[i] - e.stiffness_n_m[i] * d[i];
            assert!((grad + spring).abs() < 1e-6, "axis {i}: {grad} vs {spring}");
        }
    }

    /// Nonlinear additions along a's y: at rest with δ_y = 20 mm, a bump
    /// stop (15 mm, 2 MN/m) adds 10 kN, a series element (k_s 1 MN/m) with
    /// stroke q = 5 mm adds 15 kN and reports q̇ = k_s (δ − q)/c_s; moving
    /// at 0.05 m/s a bilinear damper (c₁ 1e5 to 0.02 m/s, c₂ 1e4) adds
    /// 2 kN + 0.3 kN. The energy's gradient is the spring part of −f.
    #[test]
    fn nonlinear_axis_adds_to_the_linear_force() {
        let mut e = element();
        e.preload_n = Vector3::zeros();
        e.reference_offset_m = Vector3::zeros();
        e.point_b_m = Vector3::zeros();
        e.point_a_m = Vector3::zeros();
        e = e
            .with_laws([
                AxisLaws::default(),
                AxisLaws {
                    spring: Some(SpringLaw::BumpStop {
                        clearance_m: 0.015,
                        stiffness_n_m: 2e6,
                    }),
                    damper: Some(DamperLaw::Bilinear {
                        damping_n_s_m: 1e5,
                        blow_off_m_s: 0.02,
                        damping_beyond_n_s_m: 1e4,
                    }),
                    series: Some(SeriesLaw {
                        stiffness_n_m: 1e6,
                        damping_n_s_m: 1e4,
                    }),
                },
                AxisLaws::default(),
            ])
            .unwrap();
        assert_eq!(e.internal_len(), 1);
        let a = Anchor::fixed(Vector3::zeros(), Matrix3::identity());
        let mut b = Anchor::fixed(Vector3::new(0.0, 0.02, 0.0), Matrix3::identity());
        let q = [0.005];
        let f = e.evaluate(&a, &b, &q);
        let linear = 2e5 * 0.02;
        let expected = -(linear + 1e4 + 1e6 * 0.015);
        assert!(
            (f.force_on_b_n.y - expected).abs() < 1e-6,
            "{}",
            f.force_on_b_n
        );
        assert!((f.internal_rate_m_s[0] - 1e6 * 0.015 / 1e4).abs() < 1e-12);
        b.velocity_m_s.y = 0.05;
        let g = e.evaluate(&a, &b, &q);
        let damping = 2e3 * 0.05 + 1e5 * 0.02 + 1e4 * 0.03;
        assert!((g.force_on_b_n.y - (expected - damping)).abs() < 1e-6);
        let p = e.dissipated_power_w(&g.deflection_m, &g.rate_m_s, &q);
        let series = 1.5e4 * 1.5e4 / 1e4;
        assert!((p - (2e3 * 0.05 * 0.05 + 2.3e3 * 0.05 + series)).abs() < 1e-6);
        // dU/dδ_y = −(spring part of f_y) at q fixed.
        let h = 1e-7;
        let d = f.deflection_m;
        let u = |dy: f64| e.potential_energy_j(&(d + Vector3::new(0.0, dy, 0.0)), &q);
        let grad = (u(h) - u(-h)) / (2.0 * h);
        assert!((grad + expected).abs() < 1e-3, "{grad} vs {expected}");
        // A bad law is refused with its axis.
        let bad = element().with_laws([
            AxisLaws::default(),
            AxisLaws::default(),
            AxisLaws {
                series: Some(SeriesLaw {
                    stiffness_n_m: 0.0,
                    damping_n_s_m: 1.0,
                }),
                ..Default::default()
            },
        ]);
        assert!(matches!(bad, Err(ElementError::Law { axis: 2, .. })));
    }
}
