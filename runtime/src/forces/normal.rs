//! Normal contact force: Hertz with Lankarani–Nikravesh hysteresis damping
//! (paper §4.4, eq. 22, Fig. 12; docs/reference/07-contact-forces.md §7.2).
//!
//! # The law
//!
//! ```text
//! N = K δ^1.5 [1 + 3(1 − e²)/4 · δ̇/δ̇⁽⁻⁾]          (paper eq. 22)
//! ```
//!
//! - K: Hertz stiffness (N/m^1.5), computed by
//!   [`crate::forces::hertz::HertzShape::stiffness_n_m15`] (docs/reference/07-contact-forces.md §7.1); an input here.
//! - δ: penetration (m), > 0 in contact (the contact search's
//!   `penetration_m`, δ = −dᵀn_c, paper eq. 20–21).
//! - δ̇: penetration rate (m/s), > 0 while the bodies approach; the normal
//!   component of the relative velocity of the two material points at the
//!   contact, δ̇ = (v_r − v_w)·n_c (paper §4.4: "the projection of the relative
//!   velocity vector of the bodies at the point of contact on the vector
//!   normal to the contact surfaces"; see [`penetration_rate_m_s`]).
//! - e: coefficient of restitution (dimensionless), in (0, 1].
//! - δ̇⁽⁻⁾: penetration rate at impact (m/s), the reference velocity.
//!
//! The exponent 1.5 is Hertz's (metal to metal, paper eq. 22, docs/reference/07-contact-forces.md §7.1).
//! The damping term is Lankarani & Nikravesh's hysteresis damping (H. M.
//! Lankarani, P. E. Nikravesh, "A contact force model with hysteresis damping
//! for impact analysis of multibody systems", J. Mech. Des. 112 (1990)
//! 369–376): a damping coefficient D = 3(1 − e²) K δ^1.5 / (4 δ̇⁽⁻⁾) chosen
//! so that the energy dissipated in one impact of two free bodies equals
//! the kinetic-energy loss ½ m_eff δ̇⁽⁻⁾² (1 − e²) implied by e. That energy
//! balance is approximate (it assumes the dissipated energy is small, i.e. e
//! close to 1): the drop test `runtime/tests/normal_drop.rs` measures the
//! achieved rebound ratio v_out/v_in against e.
//!
//! # Reference velocity, start-up rule and floor
//!
//! The reference velocity v_ref of the ratio δ̇/v_ref is kept per contact in
//! a [`ContactMemory`]:
//!
//! 1. **Impact** (a transition from no contact, δ ≤ 0, to contact, δ > 0):
//!    v_ref = δ̇⁽⁻⁾ = the penetration rate at the first evaluation in
//!    contact (paper eq. 22, "velocity of indentation at the initial instant
//!    of contact"), kept until contact is lost.
//! 2. **Start-up** (the run starts with the bodies already in contact, so
//!    δ̇⁽⁻⁾ is unknown; [`ContactMemory::started_in_contact`]). Paper §4.4:
//!    "the ratio δ̇/δ̇⁽⁻⁾ appearing in equation (22) is set to be the unity,
//!    while the maximum velocity of penetration is not reached. When the
//!    maximum penetration velocity δ̇max is obtained, the ratio δ̇/δ̇⁽⁻⁾ is
//!    considered to be δ̇/δ̇max until there is contact loss" (Fig. 12: ratio 1
//!    on the loading branch from δ₀, δ̇/δ̇max on the unloading branch).
//!    **Our reading:** the maximum is tracked as the running maximum
//!    M = max(0, δ̇ seen so far) (starting from 0, the rate of a contact at
//!    rest). While δ̇ ≥ M (the penetration rate is still rising, so its
//!    maximum has not been reached) M follows δ̇ and the ratio is δ̇/M = 1
//!    (above the floor, rule 3);
//!    at the first evaluation with δ̇ < M the maximum has been reached:
//!    δ̇max = M is frozen and the ratio is δ̇/δ̇max until contact is lost
//!    (then the next contact is an impact, rule 1). The switch is continuous
//!    (the ratio is 1 on both sides of it). A run that starts in contact
//!    while unloading (δ̇ < 0 at once) freezes δ̇max = 0 immediately, i.e.
//!    falls back on the floor below.
//! 3. **Floor.** The ratio is δ̇ / max(v_ref, v_floor) with v_floor =
//!    [`NormalForceModel::min_impact_velocity_m_s`]: a contact that starts
//!    with a tiny or zero rate (a grazing impact, a start at rest) would
//!    otherwise divide by ~0 and produce an unbounded force. With the floor
//!    |ratio| ≤ |δ̇|/v_floor, so |N| ≤ K δ^1.5 (1 + 3(1 − e²)/4 · |δ̇|/v_floor),
//!    finite for finite inputs; impacts faster than v_floor are untouched,
//!    slower ones are damped less than e says (their ratio is δ̇/v_floor < 1),
//!    which is harmless since their kinetic energy is negligible. During
//!    start-up the floor also applies to the running maximum (ratio =
//!    δ̇/max(δ̇, v_floor), i.e. 1 only once δ̇ ≥ v_floor), so the force is
//!    continuous in δ̇ at the start of a run at rest (no jump of
//!    3(1 − e²)/4 · K δ^1.5 when the rate departs from 0).
//!
//! With these rules the reference velocity is always ≥ v_floor > 0 and the
//! ratio has the sign of δ̇, so the damping force times δ̇ is ≥ 0: **the
//! model never creates energy** (for a constant K); this is tested.
//!
//! # Non-negative force
//!
//! On fast unloading the damping term can exceed the elastic one
//! (3(1 − e²)/4 · δ̇/v_ref < −1); a contact cannot pull, so N is clamped:
//! N = max(0, K δ^1.5 (1 + 3(1 − e²)/4 · ratio)). The reported damping
//! [`NormalForce::damping_n`] is the applied one, N − K δ^1.5, so that
//! `force_n = elastic_n + damping_n` always; the clamp only reduces the
//! magnitude of a negative damping force, so the clamped model stays
//! dissipative.
//!
//! # Committing the memory (one per contact slot, accepted steps only)
//!
//! The simulator keeps one [`ContactMemory`] per wheel–rail contact slot
//! (side × patch slot, [`crate::contact::WheelsetContacts`]).
//! [`NormalForceModel::evaluate`] is pure: it returns
//! the force and the memory that *would* follow, and the caller commits
//! `next_memory` only for **accepted** states, never from trial stages of a
//! Runge–Kutta step or from a rejected adaptive step. The protocol used by
//! the drop test, and recommended for the simulator:
//!
//! 1. at every accepted state y_n (including the initial one), evaluate with
//!    the committed memory and commit the result's `next_memory`;
//! 2. evaluate every stage of the step from y_n with that committed memory
//!    (a stage that finds contact where the memory says "not in contact"
//!    treats it as an impact at its own δ̇, ratio 1: consistent).
//!
//! `evaluate` is idempotent on a committed memory (evaluating again at the
//! same state with the returned memory gives the same force and memory), so
//! step 1's force equals the first stage's force and may be reused.
//!
//! # Bad input
//!
//! No panics. Non-finite δ, a non-finite δ̇ or a non-finite/negative K while
//! in contact, and invalid model parameters return a [`NormalForceError`]
//! naming the value and the rule; so does a force that overflows to
//! infinity (e.g. δ̇ = 1e300 m/s). δ ≤ 0 is "no contact": zero force and a
//! reset memory, whatever K and δ̇ are (they are not used). Tiny penetrations
//! (δ = 1e-300 m) give a tiny or zero (underflowed) force.

use nalgebra::Vector3;

/// Why a normal force could not be evaluated.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum NormalForceError {
    /// The coefficient of restitution is not finite or not in (0, 1].
    #[error("coefficient of restitution e = {restitution} must be finite and lie in (0, 1]")]
    InvalidRestitution { restitution: f64 },
    /// The floor of the reference velocity is not finite or not > 0.
    #[error(
        "minimum impact velocity (damping floor) {min_impact_velocity_m_s} m/s must be finite and > 0"
    )]
    InvalidMinImpactVelocity { min_impact_velocity_m_s: f64 },
    /// The Hertz stiffness is not finite or is negative (checked in contact).
    #[error("Hertz stiffness K = {stiffness_n_m15} N/m^1.5 must be finite and >= 0")]
    InvalidStiffness { stiffness_n_m15: f64 },
    /// The penetration is NaN or infinite.
    #[error("penetration {penetration_m} m must be finite")]
    NonFinitePenetration { penetration_m: f64 },
    /// The penetration rate is NaN or infinite (checked in contact).
    #[error("penetration rate {penetration_rate_m_s} m/s must be finite while in contact")]
    NonFinitePenetrationRate { penetration_rate_m_s: f64 },
    /// The force overflowed (finite but extreme inputs).
    #[error(
        "normal force is not finite: elastic {elastic_n} N, damping {damping_n} N (penetration {penetration_m} m, rate {penetration_rate_m_s} m/s)"
    )]
    ForceOverflow {
        elastic_n: f64,
        damping_n: f64,
        penetration_m: f64,
        penetration_rate_m_s: f64,
    },
}

/// Parameters of the Hertz + hysteresis-damping normal force (paper eq. 22).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalForceModel {
    /// Coefficient of restitution e (dimensionless), in (0, 1]; e = 1 is pure
    /// Hertz (no damping).
    pub restitution: f64,
    /// Floor v_floor (m/s) of the reference velocity δ̇⁽⁻⁾ or δ̇max: the ratio
    /// is δ̇ / max(v_ref, v_floor) (module docs, "Floor"). Finite, > 0.
    pub min_impact_velocity_m_s: f64,
}

impl Default for NormalForceModel {
    /// e = 0.9, v_floor = 5e-3 m/s.
    ///
    /// **e = 0.9**: the paper does not state its value. 0.9 is a typical
    /// steel-on-steel restitution at the low normal velocities of wheel–rail
    /// contact and lies where Lankarani–Nikravesh's energy balance (derived
    /// for e near 1) is still accurate: the drop test
    /// (`tests/normal_drop.rs`) measures v_out/v_in = 0.9132 for e = 0.9
    /// (+1.5 %), 0.9535 for e = 0.95, but 0.7960 for e = 0.7 (+14 %).
    ///
    /// **v_floor = 5e-3 m/s**: it bounds the damping coefficient
    /// D = 3(1 − e²) K δ^1.5 / (4 v_floor) = 3(1 − e²) N / (4 v_floor) when
    /// the reference velocity is tiny (a run that starts at rest in contact,
    /// where the start-up rule freezes a δ̇max ≈ 0; the usual case of a
    /// vehicle simulation). For a wheel at 50 kN and e = 0.9,
    /// D ≤ 0.1425 · 50 kN / v_floor = 1.4e6 N·s/m, a pole D/m ≈ 1000 1/s on a
    /// 1430 kg wheelset: explicit RK4 stays stable up to a 2.8 ms step, well
    /// above the 0.2–0.5 ms the contact stiffness and the creep damping call
    /// for. Measured on the ML95-like bogie at 20 m/s (RK4): with a 1e-3 m/s
    /// floor (D/m ≈ 5000 1/s) a 0.4 ms step already ended in a spurious
    /// state (a wheel unloaded to 2.3 kN); with 5e-3 m/s the 0.4 ms run
    /// matches the 0.2 ms one. Impacts slower than v_floor are damped less
    /// than e says (ratio δ̇/v_floor < 1); at 5 mm/s their kinetic energy is
    /// negligible, and flange impacts (0.01–0.5 m/s normal velocity) are
    /// modelled exactly.
    fn default() -> Self {
        NormalForceModel {
            restitution: 0.9,
            min_impact_velocity_m_s: 5e-3,
        }
    }
}

/// The normal force at one contact and the memory that follows it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalForce {
    /// Normal force N (N), ≥ 0, on the wheel along n_c (and on the rail along
    /// −n_c); `force_n = elastic_n + damping_n`.
    pub force_n: f64,
    /// Hertz elastic part K δ^1.5 (N), ≥ 0.
    pub elastic_n: f64,
    /// Applied hysteresis damping part (N), clamped so that `force_n ≥ 0`
    /// (≥ −`elastic_n`); has the sign of δ̇.
    pub damping_n: f64,
    /// True when the clamp N ≥ 0 was active (the unclamped damping was
    /// below −`elastic_n`).
    pub clamped: bool,
    /// The ratio δ̇ / max(v_ref, v_floor) actually used (dimensionless); 0
    /// out of contact.
    pub velocity_ratio: f64,
    /// Memory to commit if this state is accepted (module docs).
    pub next_memory: ContactMemory,
}

/// Phase of one contact slot (see [`ContactMemory`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum ContactPhase {
    /// Not in contact (δ ≤ 0 at the last committed state): the next state
    /// with δ > 0 is an impact.
    #[default]
    NotInContact,
    /// The run started in contact and the penetration rate is still rising
    /// (paper §4.4 start-up rule): ratio 1 (above the floor);
    /// `max_penetration_rate_m_s` is the running maximum M ≥ 0 (m/s).
    StartUp { max_penetration_rate_m_s: f64 },
    /// In contact with a known reference velocity (m/s): δ̇⁽⁻⁾ after an
    /// impact, or the frozen δ̇max after the start-up (not yet floored).
    InContact { reference_velocity_m_s: f64 },
}

/// Per-contact state carried between accepted steps: one per wheel–rail
/// contact slot (side × patch slot), committed only on accepted states
/// (module docs). `Default` is "not in contact".
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactMemory {
    phase: ContactPhase,
}

impl ContactMemory {
    /// Not in contact: the first evaluation with δ > 0 is an impact and
    /// records δ̇⁽⁻⁾ (same as `Default`).
    pub fn not_in_contact() -> Self {
        ContactMemory {
            phase: ContactPhase::NotInContact,
        }
    }

    /// The run starts with this contact already closed: δ̇⁽⁻⁾ is unknown and
    /// the start-up rule applies (paper §4.4, Fig. 12; module docs). If the
    /// first evaluation finds δ ≤ 0 the memory simply resets.
    pub fn started_in_contact() -> Self {
        ContactMemory {
            phase: ContactPhase::StartUp {
                max_penetration_rate_m_s: 0.0,
            },
        }
    }

    /// The memory for the initial state of a run: start-up if the contact is
    /// closed (δ > 0), otherwise not in contact (NaN counts as not in
    /// contact; `evaluate` reports it).
    pub fn at_start(penetration_m: f64) -> Self {
        if penetration_m > 0.0 {
            Self::started_in_contact()
        } else {
            Self::not_in_contact()
        }
    }

    /// The phase (for diagnostics and output).
    pub fn phase(&self) -> ContactPhase {
        self.phase
    }

    /// True unless the memory is "not in contact".
    pub fn is_in_contact(&self) -> bool {
        !matches!(self.phase, ContactPhase::NotInContact)
    }
}

impl NormalForceModel {
    /// Checks e finite in (0, 1] and v_floor finite > 0, naming the broken
    /// rule.
    pub fn validate(&self) -> Result<(), NormalForceError> {
        let e = self.restitution;
        if !(e.is_finite() && e > 0.0 && e <= 1.0) {
            return Err(NormalForceError::InvalidRestitution { restitution: e });
        }
        let v = self.min_impact_velocity_m_s;
        if !(v.is_finite() && v > 0.0) {
            return Err(NormalForceError::InvalidMinImpactVelocity {
                min_impact_velocity_m_s: v,
            });
        }
        Ok(())
    }

    /// The hysteresis factor 3(1 − e²)/4 (dimensionless) of paper eq. 22
    /// (Lankarani & Nikravesh 1990).
    pub fn hysteresis_factor(&self) -> f64 {
        0.75 * (1.0 - self.restitution * self.restitution)
    }

    /// Normal force for Hertz stiffness `stiffness_n_m15` (N/m^1.5),
    /// penetration `penetration_m` (m, > 0 in contact) and penetration rate
    /// `penetration_rate_m_s` (m/s, > 0 approaching), given the committed
    /// `memory` of this contact slot. Pure: the caller commits
    /// [`NormalForce::next_memory`] on accepted states (module docs).
    ///
    /// N = max(0, K δ^1.5 [1 + 3(1 − e²)/4 · δ̇/max(v_ref, v_floor)]) (paper
    /// eq. 22 with the start-up rule and floor of the module docs); δ ≤ 0
    /// gives zero force and a "not in contact" memory.
    pub fn evaluate(
        &self,
        memory: &ContactMemory,
        stiffness_n_m15: f64,
        penetration_m: f64,
        penetration_rate_m_s: f64,
    ) -> Result<NormalForce, NormalForceError> {
        self.validate()?;
        if !penetration_m.is_finite() {
            return Err(NormalForceError::NonFinitePenetration { penetration_m });
        }
        if penetration_m <= 0.0 {
            return Ok(NormalForce {
                force_n: 0.0,
                elastic_n: 0.0,
                damping_n: 0.0,
                clamped: false,
                velocity_ratio: 0.0,
                next_memory: ContactMemory::not_in_contact(),
            });
        }
        if !(stiffness_n_m15.is_finite() && stiffness_n_m15 >= 0.0) {
            return Err(NormalForceError::InvalidStiffness { stiffness_n_m15 });
        }
        let rate = penetration_rate_m_s;
        if !rate.is_finite() {
            return Err(NormalForceError::NonFinitePenetrationRate {
                penetration_rate_m_s: rate,
            });
        }
        let floor = self.min_impact_velocity_m_s;
        // Reference velocity and next phase (module docs, rules 1–3).
        let (reference_m_s, next_phase) = match memory.phase {
            // Rule 1: impact; δ̇⁽⁻⁾ = the rate at the first state in contact.
            ContactPhase::NotInContact => (
                rate,
                ContactPhase::InContact {
                    reference_velocity_m_s: rate,
                },
            ),
            // Rule 2: start-up; the ratio is 1 while δ̇ is still rising ...
            ContactPhase::StartUp {
                max_penetration_rate_m_s: max,
            } if rate >= max => (
                rate,
                ContactPhase::StartUp {
                    max_penetration_rate_m_s: rate,
                },
            ),
            // ... and δ̇/δ̇max from the first fall on (δ̇max frozen).
            ContactPhase::StartUp {
                max_penetration_rate_m_s: max,
            } => (
                max,
                ContactPhase::InContact {
                    reference_velocity_m_s: max,
                },
            ),
            ContactPhase::InContact {
                reference_velocity_m_s,
            } => (reference_velocity_m_s, memory.phase),
        };
        // Rule 3: floor on the reference velocity (≥ v_floor > 0).
        let ratio = rate / reference_m_s.max(floor);
        // Hertz: K δ^1.5 (paper eq. 22, docs/reference/07-contact-forces.md §7.1), δ^1.5 = δ √δ.
        let elastic_n = stiffness_n_m15 * penetration_m * penetration_m.sqrt();
        // Lankarani–Nikravesh hysteresis damping (paper eq. 22; 1990).
        let damping_raw_n = elastic_n * self.hysteresis_factor() * ratio;
        let total_n = elastic_n + damping_raw_n;
        if !(total_n.is_finite() && elastic_n.is_finite() && damping_raw_n.is_finite()) {
            return Err(NormalForceError::ForceOverflow {
                elastic_n,
                damping_n: damping_raw_n,
                penetration_m,
                penetration_rate_m_s: rate,
            });
        }
        // A contact cannot pull: N ≥ 0 (module docs, "Non-negative force").
        let clamped = total_n < 0.0;
        let force_n = if clamped { 0.0 } else { total_n };
        Ok(NormalForce {
            force_n,
            elastic_n,
            damping_n: if clamped { -elastic_n } else { damping_raw_n },
            clamped,
            velocity_ratio: ratio,
            next_memory: ContactMemory { phase: next_phase },
        })
    }
}

/// Penetration rate δ̇ = (v_r − v_w)·n_c (m/s), > 0 while the bodies
/// approach: the projection of the relative velocity of the two material
/// points at the contact on the contact normal (paper §4.4, after eq. 22).
/// `wheel_point_velocity_m_s` and `rail_point_velocity_m_s` are the
/// velocities (m/s, global) of the wheel and rail material points at the
/// contact (see [`crate::forces::creepage::material_point_velocity_m_s`]); `normal`
/// is n_c (unit, from the rail into the wheel, docs/reference/01-units-frames.md §1). It is the time
/// derivative of δ = −dᵀn_c (d = r_w − r_r): the term −dᵀṅ_c vanishes since
/// d ∥ n_c at the contact and ṅ_c ⟂ n_c, and the contact points' motion over
/// the surfaces is tangent, ⟂ n_c.
pub fn penetration_rate_m_s(
    wheel_point_velocity_m_s: &Vector3<f64>,
    rail_point_velocity_m_s: &Vector3<f64>,
    normal: &Vector3<f64>,
) -> f64 {
    (rail_point_velocity_m_s - wheel_point_velocity_m_s).dot(normal)
}

#[cfg(test)]
mod tests {
    use super::*;

    const K: f64 = 1.0e11; // N/m^1.5, a typical wheel–rail Hertz stiffness

    fn model(e: f64) -> NormalForceModel {
        NormalForceModel {
            restitution: e,
            ..NormalForceModel::default()
        }
    }

    #[test]
    fn default_is_valid_and_validation_names_the_rule() {
        NormalForceModel::default().validate().unwrap();
        for e in [0.0, -0.1, 1.0 + 1e-12, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                model(e).validate(),
                Err(NormalForceError::InvalidRestitution { .. })
            ));
            let msg = model(e).validate().unwrap_err().to_string();
            assert!(msg.contains("restitution"), "{msg}");
            assert!(matches!(
                model(e).evaluate(&ContactMemory::default(), K, 1e-4, 0.1),
                Err(NormalForceError::InvalidRestitution { .. })
            ));
        }
        model(1.0).validate().unwrap();
        for v in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
            let m = NormalForceModel {
                min_impact_velocity_m_s: v,
                ..NormalForceModel::default()
            };
            assert!(matches!(
                m.validate(),
                Err(NormalForceError::InvalidMinImpactVelocity { .. })
            ));
            let msg = m.validate().unwrap_err().to_string();
            assert!(msg.contains("minimum impact velocity"), "{msg}");
        }
    }

    #[test]
    fn impact_uses_first_rate_as_reference() {
        let m = model(0.9);
        let f0 = m.evaluate(&ContactMemory::default(), K, 1e-4, 0.2).unwrap();
        assert_eq!(
            f0.next_memory.phase(),
            ContactPhase::InContact {
                reference_velocity_m_s: 0.2
            }
        );
        // Ratio 1 at impact: N = K δ^1.5 (1 + 3(1 − e²)/4).
        let elastic = K * 1e-4_f64.powf(1.5);
        assert!((f0.elastic_n - elastic).abs() <= 1e-12 * elastic);
        let expect = elastic * (1.0 + 0.75 * (1.0 - 0.81));
        assert!((f0.force_n - expect).abs() <= 1e-12 * expect);
        // Later: ratio δ̇/δ̇⁽⁻⁾ with the same reference.
        let f1 = m.evaluate(&f0.next_memory, K, 2e-4, -0.1).unwrap();
        assert_eq!(f1.next_memory, f0.next_memory);
        assert!((f1.velocity_ratio + 0.5).abs() < 1e-15);
        let el1 = K * 2e-4_f64.powf(1.5);
        let expect1 = el1 * (1.0 - 0.75 * 0.19 * 0.5);
        assert!((f1.force_n - expect1).abs() <= 1e-12 * expect1);
        // Contact lost: zero force, memory reset.
        let f2 = m.evaluate(&f1.next_memory, K, -1e-6, -0.1).unwrap();
        assert_eq!(f2.force_n, 0.0);
        assert!(!f2.next_memory.is_in_contact());
        // δ = 0 exactly is not contact.
        let f3 = m.evaluate(&f1.next_memory, K, 0.0, 0.3).unwrap();
        assert_eq!(f3.force_n, 0.0);
        assert_eq!(f3.next_memory, ContactMemory::not_in_contact());
    }

    #[test]
    fn start_up_rule_ratio_one_until_max_then_frozen() {
        let m = model(0.8);
        let h = m.hysteresis_factor();
        let mut mem = ContactMemory::started_in_contact();
        let delta = 1e-4;
        let el = K * delta * delta.sqrt();
        // Rising rates above the floor: ratio 1.
        for rate in [0.01, 0.05, 0.08] {
            let f = m.evaluate(&mem, K, delta, rate).unwrap();
            assert_eq!(f.velocity_ratio, 1.0);
            assert!((f.force_n - el * (1.0 + h)).abs() <= 1e-12 * el);
            mem = f.next_memory;
            assert_eq!(
                mem.phase(),
                ContactPhase::StartUp {
                    max_penetration_rate_m_s: rate
                }
            );
        }
        // First fall: δ̇max = 0.08 frozen, ratio δ̇/δ̇max.
        let f = m.evaluate(&mem, K, delta, 0.04).unwrap();
        assert!((f.velocity_ratio - 0.5).abs() < 1e-15);
        mem = f.next_memory;
        assert_eq!(
            mem.phase(),
            ContactPhase::InContact {
                reference_velocity_m_s: 0.08
            }
        );
        // A later rate above δ̇max gives a ratio above 1 (frozen, not running).
        let f = m.evaluate(&mem, K, delta, 0.16).unwrap();
        assert!((f.velocity_ratio - 2.0).abs() < 1e-15);
        assert_eq!(f.next_memory, mem);
        // at_start chooses the start-up only for a closed contact.
        assert_eq!(
            ContactMemory::at_start(1e-5),
            ContactMemory::started_in_contact()
        );
        assert_eq!(ContactMemory::at_start(0.0), ContactMemory::default());
        assert_eq!(ContactMemory::at_start(f64::NAN), ContactMemory::default());
    }

    /// Evaluating again at the same state with the returned memory gives the
    /// same force and memory (the commit protocol relies on it).
    #[test]
    fn evaluate_is_idempotent_on_its_memory() {
        let m = model(0.9);
        let mems = [
            ContactMemory::not_in_contact(),
            ContactMemory::started_in_contact(),
            ContactMemory {
                phase: ContactPhase::StartUp {
                    max_penetration_rate_m_s: 0.05,
                },
            },
            ContactMemory {
                phase: ContactPhase::InContact {
                    reference_velocity_m_s: 0.3,
                },
            },
        ];
        for mem in mems {
            for rate in [-0.2, -1e-5, 0.0, 1e-5, 0.03, 0.05, 0.4] {
                for delta in [-1e-5, 1e-7, 1e-4] {
                    let a = m.evaluate(&mem, K, delta, rate).unwrap();
                    let b = m.evaluate(&a.next_memory, K, delta, rate).unwrap();
                    assert_eq!(a, b, "{mem:?} δ={delta} δ̇={rate}");
                }
            }
        }
    }

    /// A contact starting at rest (δ̇ = 0) then seeing small rates: finite,
    /// bounded force, continuous in the rate (the floor, module docs).
    #[test]
    fn tiny_reference_velocity_is_floored() {
        let m = model(0.9);
        let floor = m.min_impact_velocity_m_s;
        let h = m.hysteresis_factor();
        let delta = 6.3e-5;
        let el = K * delta * delta.sqrt();
        // Start-up at rest: zero rate gives exactly the elastic force.
        let f = m
            .evaluate(&ContactMemory::started_in_contact(), K, delta, 0.0)
            .unwrap();
        assert_eq!(f.force_n, el);
        let mut mem = f.next_memory;
        // Small rising rates stay below the floor: ratio δ̇/v_floor < 1.
        for rate in [1e-9, 1e-7, 1e-5, 2e-5] {
            let f = m.evaluate(&mem, K, delta, rate).unwrap();
            assert!((f.velocity_ratio - rate / floor).abs() < 1e-15);
            assert!(f.force_n.is_finite() && f.force_n <= el * (1.0 + h));
            mem = f.next_memory;
        }
        // The rate falls: δ̇max = 2e-5 m/s frozen, floored to v_floor.
        mem = m.evaluate(&mem, K, delta, 1e-5).unwrap().next_memory;
        assert_eq!(
            mem.phase(),
            ContactPhase::InContact {
                reference_velocity_m_s: 2e-5
            }
        );
        for rate in [1e-5, -1e-5, 5e-4, -5e-4, 1e-2] {
            let f = m.evaluate(&mem, K, delta, rate).unwrap();
            let bound = el * (1.0 + h * rate.abs() / floor);
            assert!(f.force_n.is_finite(), "{rate}");
            assert!(
                f.force_n >= 0.0 && f.force_n <= bound * (1.0 + 1e-12),
                "{rate}"
            );
            assert!((f.velocity_ratio - rate / floor).abs() < 1e-12);
        }
        // An impact at zero velocity (grazing) likewise.
        let f = m.evaluate(&ContactMemory::default(), K, 1e-9, 0.0).unwrap();
        assert_eq!(f.velocity_ratio, 0.0);
        let g = m.evaluate(&f.next_memory, K, 1e-6, 1e-4).unwrap();
        assert!((g.velocity_ratio - 1e-4 / floor).abs() < 1e-15);
        assert!(g.force_n.is_finite());
    }

    /// Property sweep: never negative, never NaN, always dissipative
    /// (damping·δ̇ ≥ 0), force = elastic + damping; NaN/∞ input is an error,
    /// never a panic; overflow is an error.
    #[test]
    fn never_negative_never_creates_energy_sweep() {
        let deltas = [
            -1e300, -1.0, -1e-300, 0.0, 5e-324, 1e-300, 1e-12, 1e-6, 1e-4, 1e-3, 1e-2, 1.0, 1e10,
        ];
        let rates = [
            -1e300, -1e6, -10.0, -0.5, -1e-3, -1e-9, -1e-300, 0.0, 1e-300, 1e-9, 1e-3, 0.5, 10.0,
            1e6, 1e300,
        ];
        let mems = [
            ContactMemory::not_in_contact(),
            ContactMemory::started_in_contact(),
            ContactMemory {
                phase: ContactPhase::StartUp {
                    max_penetration_rate_m_s: 0.1,
                },
            },
            ContactMemory {
                phase: ContactPhase::InContact {
                    reference_velocity_m_s: -0.2,
                },
            },
            ContactMemory {
                phase: ContactPhase::InContact {
                    reference_velocity_m_s: 0.0,
                },
            },
            ContactMemory {
                phase: ContactPhase::InContact {
                    reference_velocity_m_s: 1.0,
                },
            },
        ];
        let mut n_ok = 0;
        let mut n_clamped = 0;
        let mut n_overflow = 0;
        for e in [0.05, 0.5, 0.9, 1.0] {
            let m = model(e);
            for mem in mems {
                for &d in &deltas {
                    for &r in &rates {
                        for k in [0.0, 1e11, 1e30] {
                            match m.evaluate(&mem, k, d, r) {
                                Ok(f) => {
                                    n_ok += 1;
                                    assert!(f.force_n >= 0.0 && f.force_n.is_finite());
                                    assert!(f.elastic_n >= 0.0);
                                    assert_eq!(f.force_n, f.elastic_n + f.damping_n);
                                    assert!(f.damping_n * r >= 0.0, "{e} {mem:?} {d} {r}");
                                    if f.clamped {
                                        n_clamped += 1;
                                        assert_eq!(f.force_n, 0.0);
                                    }
                                    if d <= 0.0 {
                                        assert_eq!(f.force_n, 0.0);
                                        assert!(!f.next_memory.is_in_contact());
                                    } else {
                                        assert!(f.next_memory.is_in_contact());
                                    }
                                }
                                Err(NormalForceError::ForceOverflow { .. }) => n_overflow += 1,
                                Err(other) => panic!("unexpected {other} for {d} {r} {k}"),
                            }
                        }
                    }
                }
            }
        }
        assert!(n_ok > 1000 && n_clamped > 100 && n_overflow > 10);
        // Non-finite input: errors, not panics, in or out of contact.
        let m = model(0.9);
        let mem = ContactMemory::default();
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(matches!(
                m.evaluate(&mem, K, bad, 0.1),
                Err(NormalForceError::NonFinitePenetration { .. })
            ));
            assert!(matches!(
                m.evaluate(&mem, K, 1e-4, bad),
                Err(NormalForceError::NonFinitePenetrationRate { .. })
            ));
            assert!(matches!(
                m.evaluate(&mem, bad, 1e-4, 0.1),
                Err(NormalForceError::InvalidStiffness { .. })
            ));
            // Out of contact, K and δ̇ are not used.
            assert_eq!(m.evaluate(&mem, bad, -1e-4, bad).unwrap().force_n, 0.0);
        }
        assert!(matches!(
            m.evaluate(&mem, -1.0, 1e-4, 0.1),
            Err(NormalForceError::InvalidStiffness { .. })
        ));
    }

    #[test]
    fn penetration_rate_sign() {
        let n = Vector3::z();
        // Wheel moving down onto a fixed rail: approaching, δ̇ > 0.
        let v_w = Vector3::new(30.0, 0.1, -0.2);
        assert_eq!(penetration_rate_m_s(&v_w, &Vector3::zeros(), &n), 0.2);
        // Rail moving up towards the wheel as well.
        let v_r = Vector3::new(0.0, 0.0, 0.05);
        assert!((penetration_rate_m_s(&v_w, &v_r, &n) - 0.25).abs() < 1e-15);
    }
}
