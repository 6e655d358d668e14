//! Drop tests of the Hertz + Lankarani–Nikravesh normal force
//! (`runtime::forces::normal`, paper eq. 22, docs/reference/07-contact-forces.md §7.2).
//!
//! A rigid mass m = 1000 kg (about a quarter of a loaded wheelset's share of
//! a vehicle) falls on a rail with a Hertz contact of a wheel of radius
//! 0.46 m on a rail head of radius 0.3 m: A = 1/(2·0.46), B = 1/(2·0.3) 1/m,
//! steel (E = 210 GPa, ν = 0.3), K = `HertzShape::stiffness_n_m15`. One
//! coordinate z (m), the height of the wheel's lowest point above the rail
//! (δ = −z, δ̇ = −ż). Integration: classical fixed-step RK4 written here,
//! dt = 1 µs, i.e. ≥ 2000 steps per contact (contacts last 2–4 ms); the
//! memory of the contact is committed at each accepted state and held fixed
//! over the stages of a step (the protocol of `runtime::forces::normal`).
//!
//! **Rebound ratio** (gravity off, so that the ratio measures the contact
//! law alone: with gravity on, the impulse m·g·t_contact would change the
//! velocity by ~3 % of 0.1 m/s during the ~3 ms contact). The Hertz + LN
//! problem is self-similar: v_out/v_in depends on e only (not on m, K or
//! v0), which is checked (v0 = 0.1 and 0.5 m/s agree to 1e-6). Measured
//! (v0 = 0.1 m/s; contact 3.3 ms, δmax ≈ 0.11 mm; at 0.5 m/s 2.4 ms,
//! 0.39 mm):
//!
//! | e    | v_out/v_in | − e     | energy lost / ½mv0² | LN design 1 − e² | SciPy reference |
//! |------|------------|---------|---------------------|------------------|-----------------|
//! | 0.95 | 0.9535060  | +0.0035 | 0.0908              | 0.0975           | 0.9535060       |
//! | 0.9  | 0.9131767  | +0.0132 | 0.1661              | 0.19             | 0.9131767       |
//! | 0.7  | 0.7959726  | +0.0960 | 0.3664              | 0.51             | 0.7959726       |
//!
//! The SciPy reference integrates the same law nondimensionally, x'' =
//! −x^1.5 (1 + 3(1 − e²)/4 · x'), x(0) = 0⁺, x'(0) = 1, with `solve_ivp`
//! (RK45, rtol 1e-12, atol 1e-14) to the return to x = 0; our RK4 agrees to
//! 1e-8 and is asserted to 1e-6. Lankarani–Nikravesh's energy balance
//! assumes the dissipated energy is small (e near 1), so the model
//! dissipates less than 1 − e² and rebounds faster than e; the error grows
//! as e falls. Tolerances on |ratio − e|: 0.005 for e = 0.95, 0.02 for
//! e = 0.9, and the looser 0.12 for e = 0.7 (the known over-estimate,
//! stated, not hidden); the ratio is always above e.
//!
//! **Energy**: E = ½mv² + m·g·z + (2/5)Kδ^2.5 (the Hertz potential, ∫Kδ^1.5).
//! Out of contact it is constant (gravity off: exactly; gravity on: drift
//! ≤ 3.3e-14·E over 60 ms, asserted ≤ 1e-12). During contact it never
//! increases over a step with both ends in contact (measured: 0, asserted
//! ≤ 1e-12·E0); a step that enters or leaves the contact may gain up to
//! 6.1e-10·E0 (measured; asserted ≤ 1e-9·E0): RK4 loses order across the
//! δ^1.5 kink at δ = 0, an integration error, not a model one. The total
//! drop equals ½m(v_in² − v_out²). With gravity on, a mass dropped from
//! 0.5 mm (e = 0.9) keeps 4.905 → 3.862 → 3.009 → 2.314 J after three
//! bounces.

use runtime::forces::hertz::{HertzShape, Material};
use runtime::forces::normal::{ContactMemory, ContactPhase, NormalForceModel};

const MASS_KG: f64 = 1000.0;
const G_M_S2: f64 = 9.81;
const DT_S: f64 = 1e-6;

fn stiffness_n_m15() -> f64 {
    let shape = HertzShape::new(1.0 / (2.0 * 0.46), 1.0 / (2.0 * 0.3)).expect("Hertz shape");
    shape.stiffness_n_m15(&Material::default())
}

/// The falling mass: height z (m) of the wheel above the rail, velocity v
/// (m/s, up positive).
struct Drop {
    model: NormalForceModel,
    k_n_m15: f64,
    gravity_m_s2: f64,
    z_m: f64,
    v_m_s: f64,
    memory: ContactMemory,
}

impl Drop {
    /// Normal force (N) at (z, v) with the given memory; the memory that
    /// would follow.
    fn force(&self, memory: &ContactMemory, z_m: f64, v_m_s: f64) -> (f64, ContactMemory) {
        let f = self
            .model
            .evaluate(memory, self.k_n_m15, -z_m, -v_m_s)
            .expect("normal force");
        (f.force_n, f.next_memory)
    }

    fn accel(&self, memory: &ContactMemory, z_m: f64, v_m_s: f64) -> f64 {
        self.force(memory, z_m, v_m_s).0 / MASS_KG - self.gravity_m_s2
    }

    fn energy_j(&self) -> f64 {
        let delta = (-self.z_m).max(0.0);
        0.5 * MASS_KG * self.v_m_s * self.v_m_s
            + MASS_KG * self.gravity_m_s2 * self.z_m
            + 0.4 * self.k_n_m15 * delta * delta * delta.sqrt()
    }

    /// Commit the memory at the current (accepted) state, then one RK4 step
    /// with that memory held over the stages. Returns the force (N) at the
    /// start of the step.
    fn step(&mut self) -> f64 {
        let (f0, mem) = self.force(&self.memory, self.z_m, self.v_m_s);
        self.memory = mem;
        let (z, v, h) = (self.z_m, self.v_m_s, DT_S);
        let a1 = f0 / MASS_KG - self.gravity_m_s2;
        let (z2, v2) = (z + 0.5 * h * v, v + 0.5 * h * a1);
        let a2 = self.accel(&mem, z2, v2);
        let (z3, v3) = (z + 0.5 * h * v2, v + 0.5 * h * a2);
        let a3 = self.accel(&mem, z3, v3);
        let (z4, v4) = (z + h * v3, v + h * a3);
        let a4 = self.accel(&mem, z4, v4);
        self.z_m = z + h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4);
        self.v_m_s = v + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
        f0
    }
}

/// What one gravity-free impact measured.
#[derive(Debug)]
struct Impact {
    ratio: f64,
    energy_lost_fraction: f64,
    /// Largest energy increase of one step with both ends in contact, over
    /// E0.
    max_rise_in_contact: f64,
    /// Largest energy increase of a step that enters or leaves the contact,
    /// over E0 (RK4 loses order across the δ^1.5 kink at δ = 0).
    max_rise_crossing: f64,
    /// Largest energy change of one step out of contact, over E0.
    max_change_in_flight: f64,
    contact_time_s: f64,
    max_penetration_m: f64,
    impact_reference_m_s: f64,
}

/// Drop with velocity v0 (m/s) from 10 steps' flight above the rail,
/// gravity off, until the mass has left the contact.
fn impact(restitution: f64, v0_m_s: f64) -> Impact {
    let model = NormalForceModel {
        restitution,
        ..NormalForceModel::default()
    };
    let mut d = Drop {
        model,
        k_n_m15: stiffness_n_m15(),
        gravity_m_s2: 0.0,
        z_m: 10.0 * v0_m_s * DT_S,
        v_m_s: -v0_m_s,
        memory: ContactMemory::default(),
    };
    let e0 = d.energy_j();
    let (mut rise, mut rise_crossing) = (0.0_f64, 0.0_f64);
    let (mut flight_change, mut steps_in_contact) = (0.0_f64, 0usize);
    let mut max_pen = 0.0_f64;
    let mut reference = f64::NAN;
    let mut touched = false;
    for _ in 0..1_000_000 {
        let e_before = d.energy_j();
        let in_before = d.z_m < 0.0;
        d.step();
        if let ContactPhase::InContact {
            reference_velocity_m_s,
        } = d.memory.phase()
        {
            reference = reference_velocity_m_s;
        }
        let e_after = d.energy_j();
        let in_after = d.z_m < 0.0;
        if in_before || in_after {
            if in_before && in_after {
                rise = rise.max((e_after - e_before) / e0);
            } else {
                rise_crossing = rise_crossing.max((e_after - e_before) / e0);
            }
            steps_in_contact += 1;
            touched = true;
            max_pen = max_pen.max(-d.z_m);
        } else {
            flight_change = flight_change.max(((e_after - e_before) / e0).abs());
        }
        if touched && !in_after && d.v_m_s > 0.0 {
            // Left the contact: a few flight steps to check conservation.
            for _ in 0..10 {
                let e_before = d.energy_j();
                d.step();
                flight_change = flight_change.max(((d.energy_j() - e_before) / e0).abs());
            }
            return Impact {
                ratio: d.v_m_s / v0_m_s,
                energy_lost_fraction: 1.0 - d.energy_j() / e0,
                max_rise_in_contact: rise,
                max_rise_crossing: rise_crossing,
                max_change_in_flight: flight_change,
                contact_time_s: steps_in_contact as f64 * DT_S,
                max_penetration_m: max_pen,
                impact_reference_m_s: reference,
            };
        }
    }
    panic!("the mass never left the contact (e = {restitution}, v0 = {v0_m_s})");
}

#[test]
fn rebound_ratio_close_to_restitution() {
    // (e, tolerance on |ratio − e|); e = 0.7 is checked separately below.
    for (e, tol, scipy) in [(0.95, 0.005, 0.953_506_045), (0.9, 0.02, 0.913_176_678)] {
        let mut ratios = Vec::new();
        for v0 in [0.1, 0.5] {
            let r = impact(e, v0);
            println!("e = {e}, v0 = {v0} m/s: {r:?}");
            assert!((r.ratio - e).abs() <= tol, "e = {e}: ratio {}", r.ratio);
            assert!(
                (r.ratio - scipy).abs() <= 1e-6,
                "e = {e}: ratio {}",
                r.ratio
            );
            // LN overestimates the rebound (dissipates less than 1 − e²).
            assert!(r.ratio > e);
            assert!((r.energy_lost_fraction - (1.0 - r.ratio * r.ratio)).abs() < 1e-9);
            assert!(r.energy_lost_fraction > 0.0);
            // δ̇⁽⁻⁾ is the impact velocity (gravity off: exactly v0).
            assert!((r.impact_reference_m_s - v0).abs() < 1e-6 * v0);
            ratios.push(r.ratio);
        }
        // Self-similarity: the ratio does not depend on v0.
        assert!((ratios[0] - ratios[1]).abs() < 1e-6, "{ratios:?}");
    }
}

#[test]
fn rebound_ratio_low_restitution_is_overestimated_as_expected() {
    let r = impact(0.7, 0.1);
    println!("e = 0.7: {r:?}");
    // Lankarani–Nikravesh is derived for e near 1; at e = 0.7 it rebounds
    // faster than e (measured 0.796): accept |ratio − e| ≤ 0.12, above e.
    assert!(r.ratio > 0.7 && r.ratio - 0.7 <= 0.12, "{}", r.ratio);
    assert!((r.ratio - 0.795_972_595).abs() <= 1e-6, "{}", r.ratio);
    // e = 1 is pure Hertz: elastic rebound.
    let r1 = impact(1.0, 0.1);
    assert!((r1.ratio - 1.0).abs() < 1e-9, "{}", r1.ratio);
}

#[test]
fn energy_conserved_in_flight_and_only_lost_in_contact() {
    for (e, v0) in [(0.95, 0.1), (0.9, 0.5), (0.7, 0.1)] {
        let r = impact(e, v0);
        assert!(r.max_change_in_flight <= 1e-12, "{r:?}");
        assert!(r.max_rise_in_contact <= 1e-12, "{r:?}");
        assert!(r.max_rise_crossing <= 1e-9, "{r:?}");
        // Hertz impact scale: δmax = (5mv0²/(4K))^(2/5) for e = 1; the
        // damped contact penetrates less.
        let k = stiffness_n_m15();
        let hertz_max = (5.0 * MASS_KG * v0 * v0 / (4.0 * k)).powf(0.4);
        assert!(r.max_penetration_m < hertz_max && r.max_penetration_m > 0.8 * hertz_max);
        assert!(r.contact_time_s > 1e-3 && r.contact_time_s < 5e-3, "{r:?}");
    }
}

/// Gravity on: a mass dropped from 0.5 mm bounces; mechanical energy is
/// constant in flight and non-increasing in every contact.
#[test]
fn bouncing_with_gravity_loses_energy_only_in_contact() {
    let mut d = Drop {
        model: NormalForceModel::default(),
        k_n_m15: stiffness_n_m15(),
        gravity_m_s2: G_M_S2,
        z_m: 5e-4,
        v_m_s: 0.0,
        memory: ContactMemory::default(),
    };
    let e0 = d.energy_j() + MASS_KG * G_M_S2 * 1e-3; // reference scale (J)
    let mut impacts = 0;
    let mut in_contact = false;
    let mut flight_start_e = d.energy_j();
    let mut worst_flight = 0.0_f64;
    let mut worst_rise = 0.0_f64;
    let mut bounce_energies = vec![d.energy_j()];
    // 60 ms: three bounces (flight times 20, 18, 16 ms).
    for _ in 0..60_000 {
        let e_before = d.energy_j();
        d.step();
        let now_in = d.z_m < 0.0;
        let e_after = d.energy_j();
        if now_in || in_contact {
            worst_rise = worst_rise.max((e_after - e_before) / e0);
        }
        if now_in && !in_contact {
            impacts += 1;
        }
        if !now_in && in_contact {
            flight_start_e = e_after;
            bounce_energies.push(e_after);
        }
        if !now_in && !in_contact {
            worst_flight = worst_flight.max(((e_after - flight_start_e) / e0).abs());
        }
        in_contact = now_in;
    }
    println!(
        "impacts {impacts}, energies after each bounce {bounce_energies:?}, worst flight drift {worst_flight:e}, worst contact rise {worst_rise:e}"
    );
    assert!(impacts >= 3, "{impacts}");
    assert!(worst_flight <= 1e-12, "{worst_flight:e}");
    assert!(worst_rise <= 1e-12, "{worst_rise:e}");
    for w in bounce_energies.windows(2) {
        assert!(w[1] < w[0], "{bounce_energies:?}");
    }
}

/// A run that starts in contact (start-up rule, paper Fig. 12) at rest and
/// compressed to three times the static penetration: finite, non-negative
/// forces, energy never created, and the mass settles at the static
/// penetration (the floor keeps the damping bounded though δ̇max ≈ 0).
#[test]
fn start_in_contact_settles_without_blow_up() {
    let k = stiffness_n_m15();
    let static_pen_m = (MASS_KG * G_M_S2 / k).powf(2.0 / 3.0);
    // At rest at the static penetration: stays there.
    let mut d = Drop {
        model: NormalForceModel::default(),
        k_n_m15: k,
        gravity_m_s2: G_M_S2,
        z_m: -static_pen_m,
        v_m_s: 0.0,
        memory: ContactMemory::at_start(static_pen_m),
    };
    for _ in 0..10_000 {
        d.step();
    }
    assert!(
        (d.z_m + static_pen_m).abs() < 1e-9 * static_pen_m,
        "{}",
        d.z_m
    );

    // Compressed three times, released at rest.
    let mut d = Drop {
        z_m: -3.0 * static_pen_m,
        memory: ContactMemory::started_in_contact(),
        ..d
    };
    d.v_m_s = 0.0;
    let e0 = d.energy_j();
    let scale = MASS_KG * G_M_S2 * static_pen_m;
    let mut max_force = 0.0_f64;
    let mut worst_rise = 0.0_f64;
    for _ in 0..200_000 {
        let e_before = d.energy_j();
        let f = d.step();
        assert!(f.is_finite() && f >= 0.0);
        max_force = max_force.max(f);
        worst_rise = worst_rise.max((d.energy_j() - e_before) / scale);
    }
    println!(
        "static penetration {static_pen_m:e} m; max force {:.3} mg; final penetration {:.6} static; energy {e0:e} -> {:e} J; worst rise {worst_rise:e}",
        max_force / (MASS_KG * G_M_S2),
        -d.z_m / static_pen_m,
        d.energy_j()
    );
    assert!(worst_rise <= 1e-9, "{worst_rise:e}");
    // The start-up force is bounded by K δ^1.5 (1 + 3(1 − e²)/4 · |δ̇|/v_floor)
    // and, here, by a few times the initial elastic force 3^1.5 mg = 5.2 mg.
    assert!(max_force < 10.0 * MASS_KG * G_M_S2, "{max_force}");
    assert!(((-d.z_m) / static_pen_m - 1.0).abs() < 1e-3, "{}", d.z_m);
    assert!(d.v_m_s.abs() < 1e-4, "{}", d.v_m_s);
}
