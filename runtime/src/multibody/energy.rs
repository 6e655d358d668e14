//! Energy bookkeeping of a run: the mechanical energy of the vehicle at a
//! state, the powers of the non-conservative forces, and their work
//! integrated over the accepted states ([`EnergyLedger`]; work–energy
//! theorem, e.g. Goldstein, *Classical Mechanics*, §1.2).

use nalgebra::{Matrix3, Vector3};

use super::system::VehicleSystem;
use crate::forces::creepage::material_point_velocity_m_s;
use crate::multibody::element::Anchor;

/// Energy bookkeeping of a run (J): the mechanical energy E
/// ([`VehicleSystem::mechanical_energy_j`]) at the first and the last
/// accepted state, and the work of every non-conservative force between
/// them, integrated over the accepted states: over each step, the integral
/// of the quadratic through the powers at the step's two ends and the
/// accepted state before it (the variable-step 3-point Adams–Moulton rule,
/// third order in the step; Hairer, Nørsett & Wanner, *Solving ODEs I*,
/// §III.5), the trapezoidal rule on the first step. The stiff integrator's
/// steps of several milliseconds need the third order: on the Cooperrider
/// car at 8 ms steps the trapezoidal rule alone leaves 1 % of the damper
/// work unexplained. Balance (work–energy theorem):
///
/// E − E0 = W_torque + W_references + W_turning + W_normal − D_creep − D_contact − D_dampers,
///
/// with the powers at a state (W = watts, all ≥ 0 for the D's):
/// - axle torques: Σ T·Ω (T about the axle, Ω the spin about it);
/// - references (prescribed motion): −Σ F·v, F the elements' forces on
///   them at their attachment points, v those points' velocities (what
///   drives a reference does the opposite work on the elements);
/// - creep: −Σ (Fx s_x + Fy s_y + Mz s_φ) over the contacts, the forces
///   on the wheel times the slip velocities of the wheel's material point
///   against the (fixed) rail (`crate::forces::creepage`), ≥ 0 for every creep law
///   (they oppose the slip) — but for the imported table's, whose lateral
///   force has the spin term c23 without the spin moment that cancels its
///   work in Kalker's linear law, so its creep work can take either sign;
/// - contact damping: Σ N_d δ̇ (the hysteresis part of paper eq. 22, with
///   the sign of δ̇);
/// - dampers: Σ Δ̇ᵀ C Δ̇ of the elements, with their nonlinear dampers'
///   Σ D(v) v and their series dampers' Σ c_s q̇² (the series springs'
///   ½ k_s (δ − q)² and the nonlinear springs' ∫ S are in the elements'
///   potential, `crate::multibody::element`);
/// - element turning: Σ F_b·(ω_a × (p_b − p_a)), the work of the
///   elements' forces beyond their potential ½ΔᵀKΔ − f₀·Δ, which is exact
///   only while body a does not rotate (`crate::multibody::element`): the forces are
///   along a's turning axes (f₀ the preload; −f₀·Δ the preload's energy);
/// - contact normal work, for the wheelsets whose contact source's normal
///   force is not the gradient of 0.4 K δ^2.5
///   ([`super::ContactSource::normal_force_is_gradient`]: the imported
///   table): W_normal = ∫ Σ N n·v dt + E_el − E_el,0, the normal forces'
///   power on the wheels' material points under them integrated like the
///   others, plus the change of those contacts' elastic energy — the work
///   they do beyond their energy (docs/reference/08-multibody.md §8.6).
///
/// The Hertz elastic energy in E is 0.4 K δ^2.5 with the stiffness K of
/// the current contact geometry; K changes as the contact point moves
/// across the profiles, which leaves a small residual.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EnergyLedger {
    /// E at the first accepted state (J).
    pub initial_energy_j: f64,
    /// E at the last accepted state (J).
    pub energy_j: f64,
    pub axle_torque_work_j: f64,
    pub reference_work_j: f64,
    pub creep_dissipation_j: f64,
    pub contact_damping_dissipation_j: f64,
    pub damper_dissipation_j: f64,
    pub element_turning_work_j: f64,
    /// Work of the non-gradient contacts' elastic normal forces beyond
    /// their elastic energy (J): ∫ Σ N n·v dt + E_el − E_el,0 (struct docs).
    pub contact_normal_work_j: f64,
    /// ∫ Σ N n·v dt, the elastic normal forces' work on the wheels (J).
    normal_force_work_j: f64,
    /// Those contacts' elastic energy Σ 0.4 K δ^2.5 at the first accepted
    /// state (J).
    initial_contact_elastic_j: f64,
    /// Time (s) and powers (W) at the last accepted state: torque,
    /// references, creep, contact damping, dampers, element turning,
    /// elastic normal forces.
    last: Option<(f64, [f64; N_POWERS])>,
    /// The same at the accepted state before it.
    before_last: Option<(f64, [f64; N_POWERS])>,
}

/// Number of powers of [`VehicleSystem::powers_w`].
pub(super) const N_POWERS: usize = 7;

impl EnergyLedger {
    /// The balance's residual (J): E − E0 − (W_torque + W_references +
    /// W_turning + W_normal − D_creep − D_contact − D_dampers); zero but for the
    /// integration and quadrature errors (struct docs).
    pub fn residual_j(&self) -> f64 {
        self.energy_j
            - self.initial_energy_j
            - (self.axle_torque_work_j
                + self.reference_work_j
                + self.element_turning_work_j
                + self.contact_normal_work_j
                - self.creep_dissipation_j
                - self.contact_damping_dissipation_j
                - self.damper_dissipation_j)
    }

    /// Adds the powers `p` (W; order of `last`) at the accepted time `t_s`
    /// (trapezoidal rule), the energy there and the elastic energy of the
    /// non-gradient contacts (J).
    pub(super) fn add(
        &mut self,
        t_s: f64,
        p: [f64; N_POWERS],
        energy_j: f64,
        contact_elastic_j: f64,
    ) {
        match self.last {
            None => {
                self.initial_energy_j = energy_j;
                self.initial_contact_elastic_j = contact_elastic_j;
            }
            Some((t0, p0)) => {
                let h2 = t_s - t0;
                let w = |k: usize| match self.before_last {
                    Some((tm, pm)) if t0 > tm && h2 > 0.0 => {
                        step_integral(t0 - tm, h2, pm[k], p0[k], p[k])
                    }
                    _ => 0.5 * (p0[k] + p[k]) * h2,
                };
                self.axle_torque_work_j += w(0);
                self.reference_work_j += w(1);
                self.creep_dissipation_j += w(2);
                self.contact_damping_dissipation_j += w(3);
                self.damper_dissipation_j += w(4);
                self.element_turning_work_j += w(5);
                self.normal_force_work_j += w(6);
            }
        }
        self.contact_normal_work_j =
            self.normal_force_work_j + contact_elastic_j - self.initial_contact_elastic_j;
        self.energy_j = energy_j;
        self.before_last = self.last;
        self.last = Some((t_s, p));
    }
}

/// ∫ over [t_n, t_n + h2] of the quadratic through (t_n − h1, p_m),
/// (t_n, p0), (t_n + h2, p1) (s, W → J): with τ = t − t_n, p = p0 + bτ + cτ²,
/// c = (h1 (p1 − p0) + h2 (p_m − p0)) / (h1 h2 (h1 + h2)),
/// b = ((p1 − p0) − c h2²) / h2. Equal steps give h (5 p1 + 8 p0 − p_m)/12.
fn step_integral(h1: f64, h2: f64, p_m: f64, p0: f64, p1: f64) -> f64 {
    let (d1, d2) = (p_m - p0, p1 - p0);
    let c = (h1 * d2 + h2 * d1) / (h1 * h2 * (h1 + h2));
    let b = (d2 - c * h2 * h2) / h2;
    p0 * h2 + b * h2 * h2 / 2.0 + c * h2 * h2 * h2 / 3.0
}

impl VehicleSystem<'_> {
    /// Mechanical energy (J) at the last evaluated state: kinetic energy of
    /// every body, gravitational potential (zero at Z = 0), the elements'
    /// potential, and the elastic energy of the Hertz contacts,
    /// ∫ K δ^1.5 dδ = 0.4 K δ^2.5 (docs/reference/07-contact-forces.md §7.1). With restitution 1, no creep
    /// and no dampers it is conserved; the references' prescribed motion can
    /// do work on the elements (none on a straight track at constant speed).
    pub fn mechanical_energy_j(&self) -> f64 {
        let g = Vector3::new(0.0, 0.0, -self.settings.gravity_m_s2);
        let vehicle = self.vehicle;
        let bodies = vehicle
            .wheelsets
            .iter()
            .map(|w| &w.body)
            .chain(vehicle.bodies.iter().map(|b| &b.body));
        let mut e = 0.0;
        for (st, body) in self.states.iter().zip(bodies) {
            e += st.kinetic_energy_j(body) + st.potential_energy_j(body, &g);
        }
        // The elements' deflections are the last evaluation's (its
        // `element_forces`, at the same anchors and internal states).
        for (idx, el) in self.elements.iter().enumerate() {
            let q = self.element_internal(idx);
            e += el.potential_energy_j(&self.element_forces[idx].deflection_m, q);
        }
        e + self.contact_elastic_energy_j()
    }

    /// Elastic energy of the Hertz contacts at the last evaluated state,
    /// Σ 0.4 K δ^2.5 (J), K the stiffness of each contact's current geometry
    /// (part of [`Self::mechanical_energy_j`]).
    pub fn contact_elastic_energy_j(&self) -> f64 {
        self.elastic_energy_where_j(|_| true)
    }

    /// [`Self::contact_elastic_energy_j`] of the wheelsets whose contact
    /// source's normal force is not the gradient of it
    /// ([`super::ContactSource::normal_force_is_gradient`]) (J).
    pub(super) fn non_gradient_elastic_energy_j(&self) -> f64 {
        self.elastic_energy_where_j(|i| !self.sources[i].normal_force_is_gradient())
    }

    fn elastic_energy_where_j(&self, include: impl Fn(usize) -> bool) -> f64 {
        let mut e = 0.0;
        for (i, snap) in self.snapshots.iter().enumerate() {
            if !include(i) {
                continue;
            }
            for f in snap.forces.iter().flatten().flatten() {
                // δ from the elastic part of the normal force, N_el = K δ^1.5.
                let k = f.tangential.hertz.stiffness_n_m15;
                if k > 0.0 && f.normal.elastic_n > 0.0 {
                    let delta = (f.normal.elastic_n / k).powf(2.0 / 3.0);
                    e += 0.4 * k * delta * delta * delta.sqrt();
                }
            }
        }
        e
    }

    /// The non-conservative powers (W) at the last evaluated state, in the
    /// order of [`EnergyLedger`]: axle torques, references, creep
    /// dissipation, contact damping dissipation, damper dissipation, the
    /// elements' work beyond their potential, the elastic normal forces of
    /// the non-gradient contacts (Σ N n·v at the wheel's material point).
    pub(super) fn powers_w(&self) -> [f64; N_POWERS] {
        let mut p = [0.0; N_POWERS];
        for ((snap, st), source) in self.snapshots.iter().zip(&self.states).zip(&self.sources) {
            p[0] += snap.axle_torque_nm * snap.spin_rad_s;
            let books_normal_work = !source.normal_force_is_gradient();
            let omega = st.angular_velocity_global();
            for (forces, cands) in snap.forces.iter().zip(&snap.contacts.candidates) {
                for (f, c) in forces.iter().zip(cands) {
                    let (Some(f), Some(c)) = (f, c) else {
                        continue;
                    };
                    let (cr, slip) = (&f.tangential.creep, &f.tangential.creepages.slip);
                    p[2] -= cr.fx_n * slip.longitudinal_m_s
                        + cr.fy_n * slip.lateral_m_s
                        + cr.mz_nm * slip.spin_rad_s;
                    p[3] += f.normal.damping_n * slip.penetration_rate_m_s;
                    if !books_normal_work {
                        continue;
                    }
                    // The wheel's material point under the force.
                    let v = material_point_velocity_m_s(
                        &st.velocity_m_s,
                        &omega,
                        &st.position_m,
                        &f.point_m,
                    );
                    p[6] += f.normal.elastic_n * c.normal.dot(&v);
                }
            }
        }
        let vehicle = self.vehicle;
        let n_refs_from = vehicle.wheelsets.len() + vehicle.bodies.len();
        let ground = Anchor::fixed(Vector3::zeros(), Matrix3::identity());
        for (idx, (el, spec)) in self.elements.iter().zip(&vehicle.elements).enumerate() {
            let ia = self.anchor_index(spec.a);
            let ib = self.anchor_index(spec.b);
            let a = ia.map_or(&ground, |k| &self.anchors[k]);
            let b = ib.map_or(&ground, |k| &self.anchors[k]);
            let q = self.element_internal(idx);
            // The axes the element acts along: a's, or the track's
            // (`ElementAxes::Track`, kept by the last evaluation).
            let axes = ia.and_then(|k| self.element_axes.get(k));
            // The element's force at the last evaluated state, as that
            // evaluation computed it (the same anchors and internal states).
            let f = &self.element_forces[idx];
            // Velocity of a point p of an anchor: v + ω × (p − origin).
            let point_velocity = |an: &Anchor, point: &Vector3<f64>| {
                an.velocity_m_s + an.angular_velocity_rad_s.cross(&(point - an.position_m))
            };
            // The reference's driver does on the element the work the
            // element does on the reference, negated.
            if ia.is_some_and(|k| k >= n_refs_from) {
                p[1] -= f.force_on_a_n().dot(&point_velocity(a, &f.point_a_m));
            }
            if ib.is_some_and(|k| k >= n_refs_from) {
                p[1] -= f.force_on_b_n.dot(&point_velocity(b, &f.point_b_m));
            }
            p[4] += el.dissipated_power_w(&f.deflection_m, &f.rate_m_s, q);
            // The elements' directions turn with a: their forces on the
            // bodies do F_b·(ω_a × (p_b − p_a)) more work than their
            // potential and dampers account for.
            let turning = axes.map_or(a.angular_velocity_rad_s, |x| x.angular_velocity_rad_s);
            p[5] += f
                .force_on_b_n
                .dot(&turning.cross(&(f.point_b_m - f.point_a_m)));
        }
        // What a published formulation imposes from outside the model's
        // forces is driven like the references: the imposed longitudinal
        // motion's constraint, and the extra wheelset moments (gyroscopic,
        // roll arm; docs/reference/08-multibody.md §8.6).
        p[1] += self.imposed_power_w + self.formulation_power_w;
        p
    }
}

#[cfg(test)]
mod quadrature_tests {
    use super::step_integral;

    /// Exact for quadratics on unequal steps; the equal-step weights.
    #[test]
    fn the_step_integral_is_exact_for_quadratics() {
        let p = |t: f64| 3.0 - 2.0 * t + 5.0 * t * t;
        let (tm, t0, t1) = (0.1, 0.4, 0.45);
        let exact = |a: f64, b: f64| {
            let f = |t: f64| 3.0 * t - t * t + 5.0 / 3.0 * t * t * t;
            f(b) - f(a)
        };
        let q = step_integral(t0 - tm, t1 - t0, p(tm), p(t0), p(t1));
        assert!((q - exact(t0, t1)).abs() < 1e-14, "{q}");
        let h = 0.2;
        let q = step_integral(h, h, 1.0, 0.0, 0.0);
        assert!((q - (-h / 12.0)).abs() < 1e-15, "{q}");
    }
}
