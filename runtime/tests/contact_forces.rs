//! The contact-force pipeline on a real contact (S1002 on UIC60, settled
//! under 50 kN per wheel): creepages of a rolling, yawed or shifted
//! wheelset against the textbook small-angle values (Wickens,
//! *Fundamentals of Rail Vehicle Dynamics*, 2003, §2), the signs of the
//! creep forces (they oppose the slip), the normal force of a static
//! contact, "no contact" and non-Hertzian geometry. Tolerances at each
//! check.

use runtime::contact::quasi_static::{Settled, Support, settle};
use runtime::contact::{Candidate, WheelsetContactModel};
use runtime::fixtures::wheelsets::{flange_solver, s1002_uic60, straight_track_for};
use runtime::forces::creep::{CreepLaw, kalker_coefficients};
use runtime::forces::hertz::{HertzError, Material};
use runtime::forces::normal::ContactMemory;
use runtime::geometry::profile::Zone;
use runtime::geometry::track::{Side, TrackTables};
use runtime::multibody::contact_force::{
    ContactForceError, ContactForceSettings, WheelsetMotion, contact_creepages, evaluate_contact,
    hertz_shape, tangential_forces,
};

const LOAD_N: f64 = 50e3;
const SPEED_M_S: f64 = 30.0;

struct Case {
    model: WheelsetContactModel,
    track: TrackTables,
}

impl Case {
    fn new() -> Self {
        let model = s1002_uic60().unwrap();
        let track = straight_track_for(&model, 20.0);
        Case { model, track }
    }

    fn settle(&self, y_m: f64, yaw_rad: f64) -> Settled {
        let mut solver = flange_solver();
        settle(
            &self.model,
            &self.track,
            10.0,
            y_m,
            yaw_rad,
            Support::Elastic {
                load_per_wheel_n: LOAD_N,
                material: Material::default(),
            },
            &mut solver,
        )
        .unwrap()
    }

    fn r0(&self) -> f64 {
        self.model.wheel(Side::Left).nominal_radius_m()
    }

    /// Rolling along the track (global X) at SPEED_M_S with ω = V/r₀ about
    /// the axle.
    fn motion(&self, st: &Settled) -> WheelsetMotion {
        WheelsetMotion::rolling(
            st.pose.position,
            nalgebra::Vector3::x(),
            st.pose.axle(),
            SPEED_M_S,
            self.r0(),
        )
    }
}

fn main_contact(st: &Settled, side: Side) -> Candidate {
    *st.main_contact(side).expect("a contact on each wheel")
}

/// Yaw ψ, centred: η = −sin ψ·cos γ-ish on both treads (Wickens 2003
/// eq. 2.11: η = ẏ/V − ψ), and the lateral creep force on each wheel points
/// to the left (it opposes the rightward slip of the wheel over the rail).
#[test]
fn yawed_wheelset_lateral_creepage_and_force_direction() {
    let case = Case::new();
    let yaw = 2e-3;
    let st = case.settle(0.0, yaw);
    let settings = ContactForceSettings {
        creep_law: CreepLaw::KalkerLinear,
        ..Default::default()
    };
    let motion = case.motion(&st);
    let mut fy_global = 0.0;
    for side in Side::BOTH {
        let c = main_contact(&st, side);
        let cr = contact_creepages(&settings, &c, &motion).unwrap();
        // Tolerance: the contact angle on the tread (< 0.05 rad) changes η
        // by cos γ (< 0.13 %), the rolling-radius offset at y = 0 adds a
        // tiny ξ; 1 % on η.
        assert!(
            (cr.eta + yaw).abs() < 0.01 * yaw,
            "{side}: η = {} (expected ≈ {})",
            cr.eta,
            -yaw
        );
        let shape = hertz_shape(&c).unwrap();
        let f = tangential_forces(&settings, &c, &shape, LOAD_N, &cr).unwrap();
        let force = c.tangent * f.creep.fx_n + c.lateral * f.creep.fy_n;
        assert!(force.y > 0.0, "{side}: lateral creep force {}", force.y);
        fy_global += force.y;
    }
    // The spin parts (opposite on the two wheels) cancel in the sum, which
    // is 2 G a b c22 ψ to within the small left/right differences.
    let c = main_contact(&st, Side::Left);
    let hz = runtime::forces::hertz::HertzContact::from_shape(
        &hertz_shape(&c).unwrap(),
        LOAD_N,
        &settings.material,
    )
    .unwrap();
    let c22 = kalker_coefficients(hz.a_rolling_m / hz.b_lateral_m, 0.3)
        .unwrap()
        .c22;
    let expected =
        2.0 * settings.material.shear_modulus_pa() * hz.a_rolling_m * hz.b_lateral_m * c22 * yaw;
    assert!(
        (fy_global - expected).abs() < 0.02 * expected,
        "ΣFy = {fy_global:.1} N, expected {expected:.1} N"
    );
}

/// Shifted left by 3 mm (no yaw): the left wheel rolls on a larger radius,
/// so its contact point moves backwards over the rail, ξ = (r₀ − r)/r₀ < 0
/// (Wickens 2003 eq. 2.10), and the creep force pushes it forwards; the
/// right wheel the opposite. Spin φ = −sin γ / r₀ on the left tread and
/// +sin γ / r₀ on the right (docs/reference/01-units-frames.md §1 frames, `runtime::forces::creepage`).
#[test]
fn shifted_wheelset_longitudinal_creepage_and_spin() {
    let case = Case::new();
    let st = case.settle(3e-3, 0.0);
    let settings = ContactForceSettings {
        creep_law: CreepLaw::KalkerLinear,
        ..Default::default()
    };
    let motion = case.motion(&st);
    let r0 = case.r0();
    for side in Side::BOTH {
        let c = main_contact(&st, side);
        let cr = contact_creepages(&settings, &c, &motion).unwrap();
        let xi_expected = (r0 - c.rolling_radius_m) / r0;
        // The contact point lies (slightly) off the axle's vertical and the
        // wheelset rolls (tiny roll angle): 2 % + 1e-6.
        assert!(
            (cr.xi - xi_expected).abs() < 0.02 * xi_expected.abs() + 1e-6,
            "{side}: ξ = {:e}, expected {:e}",
            cr.xi,
            xi_expected
        );
        let phi_expected = match side {
            Side::Left => -c.contact_angle_rad.sin() / r0,
            Side::Right => c.contact_angle_rad.sin() / r0,
        };
        assert!(
            (cr.phi_1_m - phi_expected).abs() < 0.03 * phi_expected.abs() + 1e-4,
            "{side}: φ = {}, expected {}",
            cr.phi_1_m,
            phi_expected
        );
        let shape = hertz_shape(&c).unwrap();
        let f = tangential_forces(&settings, &c, &shape, LOAD_N, &cr).unwrap();
        assert!(
            f.creep.fx_n * cr.xi < 0.0,
            "{side}: Fx {} must oppose ξ {}",
            f.creep.fx_n,
            cr.xi
        );
    }
    let left = contact_creepages(&settings, &main_contact(&st, Side::Left), &motion).unwrap();
    assert!(
        left.xi < 0.0,
        "left wheel on the larger radius: ξ = {}",
        left.xi
    );
}

/// A static contact entered at start-up (δ̇ = 0): the hysteresis term is
/// zero and N = K δ^1.5 equals the settled Hertzian force; the total force
/// on the wheel is N n_c (no creepage when rolling freely on r₀... up to the
/// small ξ of the actual radius) and every law gives |F_t| ≤ μN.
#[test]
fn evaluate_contact_static_normal_force_and_saturation() {
    let case = Case::new();
    let st = case.settle(0.0, 0.0);
    let motion = case.motion(&st);
    for law in ["kalker", "heuristic", "polach", "fastsim"] {
        let settings = ContactForceSettings {
            creep_law: CreepLaw::from_name(law).unwrap(),
            ..Default::default()
        };
        for side in Side::BOTH {
            let c = main_contact(&st, side);
            let i = match side {
                Side::Left => 0,
                Side::Right => 1,
            };
            let settled_n = st.normal_force_n[i][c.segment];
            let f = evaluate_contact(&settings, &c, &ContactMemory::started_in_contact(), &motion)
                .unwrap()
                .expect("in contact");
            // Only rounding separates the two evaluations of K δ^1.5; the
            // penetration rate of a wheelset rolling at constant height is
            // zero to rounding (|δ̇| < 1e-9 m/s), so the damping is nil.
            assert!(
                (f.normal.force_n - settled_n).abs() < 1e-6 * settled_n,
                "{law} {side}: N = {} vs settled {}",
                f.normal.force_n,
                settled_n
            );
            assert!(f.normal.damping_n.abs() < 1e-6 * settled_n);
            let ft = f.tangential.creep.tangential_n();
            if law != "kalker" {
                assert!(ft <= settings.friction_coefficient * f.normal.force_n * (1.0 + 1e-12));
            }
            // Force on the wheel: normal plus tangential, and the point.
            let n_part = f.force_on_wheel_n.dot(&c.normal);
            assert!((n_part - f.normal.force_n).abs() < 1e-6 * f.normal.force_n);
            assert_eq!(f.point_m, c.wheel_point);
        }
    }
}

/// A candidate with a gap is "no contact" (Ok(None)), not an error; a
/// candidate with concave relative curvature is an error naming the wheel
/// and zone, never a clamped ellipse.
#[test]
fn no_contact_and_non_hertzian_are_distinct() {
    let case = Case::new();
    let st = case.settle(0.0, 0.0);
    let motion = case.motion(&st);
    let settings = ContactForceSettings::default();
    let mut c = main_contact(&st, Side::Right);
    c.penetration_m = -1e-5;
    assert!(
        evaluate_contact(&settings, &c, &ContactMemory::default(), &motion)
            .unwrap()
            .is_none()
    );
    let mut c = main_contact(&st, Side::Right);
    c.curvatures.wheel_lateral_1_m = -2.0 * c.curvatures.rail_lateral_1_m.abs() - 10.0;
    let e = evaluate_contact(&settings, &c, &ContactMemory::default(), &motion).unwrap_err();
    match e {
        ContactForceError::Hertz {
            side,
            zone,
            source: HertzError::NonHertzian { b_curv_1_m, .. },
        } => {
            assert_eq!(side, Side::Right);
            assert_eq!(zone, Zone::Tread);
            assert!(b_curv_1_m < 0.0);
        }
        other => panic!("unexpected {other:?}"),
    }
    assert!(e.to_string().contains("right wheel"), "{e}");
}

/// Settings are checked, naming the rule.
#[test]
fn settings_validation_names_the_rule() {
    let mut s = ContactForceSettings::default();
    assert!(s.validate().is_ok());
    s.friction_coefficient = -0.1;
    assert!(s.validate().unwrap_err().to_string().contains("friction"));
    let mut s = ContactForceSettings::default();
    s.material.poisson = 0.7;
    assert!(s.validate().unwrap_err().to_string().contains("Poisson"));
    let mut s = ContactForceSettings::default();
    s.normal.restitution = 1.5;
    assert!(
        s.validate()
            .unwrap_err()
            .to_string()
            .contains("restitution")
    );
    let mut s = ContactForceSettings::default();
    s.creepage.min_rolling_speed_m_s = 0.0;
    assert!(
        s.validate()
            .unwrap_err()
            .to_string()
            .contains("rolling speed")
    );
}
