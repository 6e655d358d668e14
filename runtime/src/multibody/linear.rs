//! Linear stability of the centred run on straight track (issue 6, the
//! cross-check of the time-domain critical speed): the right-hand side of
//! [`VehicleSystem`] is linearised by central differences around the
//! centred steady run, in coordinates that follow the track, and the
//! eigenvalues of the Jacobian give the modes; the hunting mode is the
//! least-damped oscillatory mode dominated by lateral and yaw motion, and
//! the linear critical speed is where its real part crosses zero.
//!
//! # Coordinates (a track-following frame)
//!
//! The steady run is not a fixed point of the full state: positions advance
//! at V and the wheelsets' quaternions turn with the spin. Perturbations are
//! therefore taken in track axes (t forward, n left, b up) relative to the
//! steady state at t = 0, which on a straight track at constant speed is
//! the same at every instant:
//!
//! - every free body: Δx, Δy, Δz, Δroll, Δpitch, Δyaw (a small global
//!   rotation about t, n, b applied on top of the steady orientation), their
//!   rates Δẋ, Δẏ, Δż and the angular-velocity perturbation (12 states);
//! - every wheelset: the same without the pitch angle, which is the spin
//!   angle (the wheel is a surface of revolution, the spin angle changes
//!   nothing), and with the spin-rate perturbation ΔΩ along the (perturbed)
//!   axle in place of the pitch rate (11 states).
//!
//! For a wheelset spinning at Ω about η, a small rotation δθ(t) on top of
//! the steady orientation gives ω = (Ω + ΔΩ) η' + δθ̇ with η' = η + δθ × η
//! (first order), so the reduced rates are δθ̇ = (Δωx, 0, Δωz) and the spin
//! perturbation ΔΩ; differentiating, ω̇ − (Ω + ΔΩ)(δθ̇ × η') = ΔΩ̇ η' +
//! (Δω̇x, 0, Δω̇z), projected on η', t and b. For the other bodies the
//! steady ω is zero and δθ̇ = Δω.
//!
//! The Jacobian is scaled (diagonal similarity, Parlett–Reinsch balancing)
//! before the real Schur decomposition of nalgebra: the states mix
//! micrometres and radians per second, contact stiffnesses of 10⁹ N/m and
//! masses of 10³ kg.

use std::f64::consts::PI;

use nalgebra::{Complex, DMatrix, DVector, UnitQuaternion, Vector3};

use super::DynamicsError;
use super::system::VehicleSystem;
use super::track_motion::track_rotation;
use crate::integrators::OdeSystem;
use crate::multibody::body::BodyState;

/// One mode of the linearised system.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mode {
    /// Eigenvalue (1/s).
    pub eigenvalue: Complex<f64>,
    /// Damped frequency (Hz), |Im λ|/2π.
    pub frequency_hz: f64,
    /// Damping ratio −Re λ / |λ| (negative: growing).
    pub damping_ratio: f64,
    /// Share of the mode's (scaled) amplitude in the lateral and yaw states
    /// of the wheelsets and bodies, 0 … 1.
    pub lateral_share: f64,
}

/// The linearised system at one speed.
#[derive(Debug, Clone, PartialEq)]
pub struct Linearisation {
    /// Names of the reduced states ("wheelset 'front' Δy", …).
    pub states: Vec<String>,
    /// Jacobian d(ẋ)/dx of the reduced states.
    pub jacobian: DMatrix<f64>,
    /// Every eigenvalue, as modes, sorted by decreasing real part.
    pub modes: Vec<Mode>,
}

impl Linearisation {
    /// The hunting mode: the oscillatory mode (0.1 … 30 Hz) with at least
    /// half its amplitude in lateral and yaw motion and the largest real
    /// part; `None` when there is none.
    pub fn hunting(&self) -> Option<Mode> {
        self.modes
            .iter()
            .filter(|m| {
                m.eigenvalue.im > 0.0
                    && (0.1..30.0).contains(&m.frequency_hz)
                    && m.lateral_share >= 0.5
            })
            .max_by(|a, b| a.eigenvalue.re.total_cmp(&b.eigenvalue.re))
            .copied()
    }
}

/// Which reduced coordinate a state is, per body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Position(usize),
    Angle(usize),
    Velocity(usize),
    Rate(usize),
    Spin,
}

struct Layout {
    /// (body index, kind) per reduced state.
    states: Vec<(usize, Kind)>,
    names: Vec<String>,
}

fn layout(system: &VehicleSystem<'_>) -> Layout {
    let v = system.vehicle();
    let axes = ["x", "y", "z"];
    let angles = ["roll", "pitch", "yaw"];
    let mut states = Vec::new();
    let mut names = Vec::new();
    let n_ws = v.wheelsets.len();
    for k in 0..n_ws + v.bodies.len() {
        let wheelset = k < n_ws;
        let name = if wheelset {
            format!("wheelset '{}'", v.wheelsets[k].name)
        } else {
            format!("body '{}'", v.bodies[k - n_ws].name)
        };
        for (a, ax) in axes.iter().enumerate() {
            states.push((k, Kind::Position(a)));
            names.push(format!("{name} Δ{ax}"));
        }
        for (a, an) in angles.iter().enumerate() {
            if !(wheelset && a == 1) {
                states.push((k, Kind::Angle(a)));
                names.push(format!("{name} Δ{an}"));
            }
        }
        for (a, ax) in axes.iter().enumerate() {
            states.push((k, Kind::Velocity(a)));
            names.push(format!("{name} Δv{ax}"));
        }
        for (a, an) in angles.iter().enumerate() {
            if wheelset && a == 1 {
                states.push((k, Kind::Spin));
                names.push(format!("{name} ΔΩ (spin)"));
            } else {
                states.push((k, Kind::Rate(a)));
                names.push(format!("{name} Δω {an}"));
            }
        }
    }
    Layout { states, names }
}

/// Finite-difference step of a reduced state (its unit: m, rad, m/s, rad/s):
/// small against the contact's penetration (≈ 70 µm) so that the Hertz
/// non-linearity stays below 1 % over ±h, large against the contact
/// solver's and the creep laws' round-off.
fn step(kind: Kind) -> f64 {
    match kind {
        Kind::Position(_) | Kind::Angle(_) => 1e-6,
        Kind::Velocity(_) | Kind::Rate(_) | Kind::Spin => 1e-5,
    }
}

/// The steady state and what the maps need.
struct Base {
    y0: Vec<f64>,
    /// Track rotation (columns t, n, b) at each body.
    frames: Vec<nalgebra::Matrix3<f64>>,
    n_ws: usize,
}

fn full_state(base: &Base, layout: &Layout, x: &DVector<f64>) -> Vec<f64> {
    let mut y = base.y0.clone();
    let n_bodies = base.frames.len();
    let mut d = vec![[[0.0; 3]; 4]; n_bodies]; // pos, angle, vel, rate
    let mut spin = vec![0.0; n_bodies];
    for ((k, kind), v) in layout.states.iter().zip(x.iter()) {
        match kind {
            Kind::Position(a) => d[*k][0][*a] = *v,
            Kind::Angle(a) => d[*k][1][*a] = *v,
            Kind::Velocity(a) => d[*k][2][*a] = *v,
            Kind::Rate(a) => d[*k][3][*a] = *v,
            Kind::Spin => spin[*k] = *v,
        }
    }
    for k in 0..n_bodies {
        let r = base.frames[k];
        let st0 = BodyState::read_from(&base.y0[BodyState::slot(k)]);
        let dpos = r * Vector3::from(d[k][0]);
        let dtheta = r * Vector3::from(d[k][1]);
        let dvel = r * Vector3::from(d[k][2]);
        let drate = r * Vector3::from(d[k][3]);
        let rot = UnitQuaternion::from_scaled_axis(dtheta);
        let orientation = rot * st0.orientation;
        let omega0 = st0.angular_velocity_global();
        let omega = if k < base.n_ws {
            // Spinning wheelset: ω = (Ω + ΔΩ) η' + δθ̇ (module docs).
            let eta0 = st0.rotation().column(1).into_owned();
            let spin0 = omega0.dot(&eta0);
            let eta = rot * eta0;
            let rest0 = omega0 - eta0 * spin0;
            eta * (spin0 + spin[k]) + rest0 + drate
        } else {
            omega0 + dtheta.cross(&omega0) + drate
        };
        let st = BodyState {
            position_m: st0.position_m + dpos,
            orientation,
            velocity_m_s: st0.velocity_m_s + dvel,
            angular_velocity_rad_s: orientation.inverse_transform_vector(&omega),
        };
        st.write_to(&mut y[BodyState::slot(k)]);
    }
    y
}

/// Reduced derivative at reduced state `x`.
fn reduced_rhs(
    system: &mut VehicleSystem<'_>,
    base: &Base,
    layout: &Layout,
    x: &DVector<f64>,
) -> Result<DVector<f64>, DynamicsError> {
    let y = full_state(base, layout, x);
    let mut dy = vec![0.0; y.len()];
    system.rhs(0.0, &y, &mut dy)?;
    let n_bodies = base.frames.len();
    // Reduced rates straight from the state, accelerations from dy.
    let mut rates = vec![[0.0; 3]; n_bodies];
    let mut spins = vec![0.0; n_bodies];
    for ((k, kind), v) in layout.states.iter().zip(x.iter()) {
        match kind {
            Kind::Rate(a) => rates[*k][*a] = *v,
            Kind::Spin => spins[*k] = *v,
            _ => {}
        }
    }
    let mut out = DVector::zeros(x.len());
    for (i, (k, kind)) in layout.states.iter().enumerate() {
        let k = *k;
        let r = base.frames[k];
        let st = BodyState::read_from(&y[BodyState::slot(k)]);
        let d = &dy[BodyState::slot(k)];
        let vdot = Vector3::new(d[7], d[8], d[9]);
        let wdot_body = Vector3::new(d[10], d[11], d[12]);
        // ω̇ (global) = d(R ω)/dt = R (ω̇ + ω_f × ω), ω_f the frame's own
        // angular velocity in its axes: ω itself for a body (so ω̇ = R ω̇_b),
        // ω without the spin for a wheelset in its axle frame
        // (docs/reference/08-multibody.md §8.1).
        let w = st.angular_velocity_rad_s;
        let w_frame = if k < base.n_ws {
            Vector3::new(w.x, 0.0, w.z)
        } else {
            w
        };
        let wdot = st.orientation * (wdot_body + w_frame.cross(&w));
        out[i] = match kind {
            Kind::Position(a) => {
                // Δẋ: the velocity perturbation state.
                let j = layout
                    .states
                    .iter()
                    .position(|s| *s == (k, Kind::Velocity(*a)))
                    .expect("every body has velocities");
                x[j]
            }
            Kind::Angle(a) => rates[k][*a],
            Kind::Velocity(a) => (r.transpose() * vdot)[*a],
            Kind::Rate(_) | Kind::Spin if k < base.n_ws => {
                let st0 = BodyState::read_from(&base.y0[BodyState::slot(k)]);
                let eta0 = st0.rotation().column(1).into_owned();
                let spin0 = st0.angular_velocity_global().dot(&eta0);
                let eta = st.rotation().column(1).into_owned();
                let dthetadot = r * Vector3::from(rates[k]);
                let u = wdot - dthetadot.cross(&eta) * (spin0 + spins[k]);
                match kind {
                    Kind::Spin => u.dot(&eta),
                    Kind::Rate(a) => u.dot(&r.column(*a).into_owned()),
                    _ => unreachable!("matched above"),
                }
            }
            Kind::Rate(a) => (r.transpose() * wdot)[*a],
            Kind::Spin => 0.0,
        };
    }
    Ok(out)
}

/// Linearises `system` around the steady state `y0` (the centred run at
/// t = 0, as returned by [`VehicleSystem::assemble`] with zero initial
/// offsets) and computes its modes.
pub fn linearise(
    system: &mut VehicleSystem<'_>,
    y0: &[f64],
) -> Result<Linearisation, DynamicsError> {
    let n_internal = system.vehicle().internal_state_len();
    if n_internal > 0 {
        return Err(DynamicsError::Setting {
            setting: "series spring–damper axes (internal states)",
            value: n_internal as f64,
            rule: "the linearisation does not include the elements' internal states: use a time run (docs/reference/08-multibody.md §8.2)",
        });
    }
    let layout = layout(system);
    let track = system.track();
    let n_ws = system.vehicle().wheelsets.len();
    let mut frames = Vec::new();
    for k in 0..system.vehicle().body_state_len() / BodyState::LEN {
        let st = BodyState::read_from(&y0[BodyState::slot(k)]);
        let s = super::track_motion::project_s(&track.centerline, &st.position_m, 0.0).map_err(
            |source| DynamicsError::Track {
                what: "linearisation".into(),
                t_s: 0.0,
                source,
            },
        )?;
        frames.push(track_rotation(&track.centerline, s).map_err(|source| {
            DynamicsError::Track {
                what: "linearisation".into(),
                t_s: 0.0,
                source,
            }
        })?);
    }
    let base = Base {
        y0: y0.to_vec(),
        frames,
        n_ws,
    };
    let n = layout.states.len();
    // Warm the contact solver at the base state.
    reduced_rhs(system, &base, &layout, &DVector::zeros(n))?;
    let mut jac = DMatrix::zeros(n, n);
    for j in 0..n {
        let h = step(layout.states[j].1);
        let mut xp = DVector::zeros(n);
        xp[j] = h;
        let fp = reduced_rhs(system, &base, &layout, &xp)?;
        xp[j] = -h;
        let fm = reduced_rhs(system, &base, &layout, &xp)?;
        jac.set_column(j, &((fp - fm) / (2.0 * h)));
    }
    // An eigen-decomposition of a non-finite matrix never converges.
    if let Some(v) = jac.iter().find(|v| !v.is_finite()) {
        return Err(DynamicsError::Setting {
            setting: "linearised system matrix entry",
            value: *v,
            rule: "the finite-difference Jacobian must be finite: a force overflows near the steady state (check the units of the vehicle's elements)",
        });
    }
    let modes = modes(&jac, &layout)?;
    Ok(Linearisation {
        states: layout.names,
        jacobian: jac,
        modes,
    })
}

/// Diagonal scaling d (powers of two) that balances the row and column
/// norms of `a` (Parlett & Reinsch 1969): D⁻¹ A D has the same eigenvalues.
fn balance(a: &DMatrix<f64>) -> (DMatrix<f64>, Vec<f64>) {
    let n = a.nrows();
    let mut m = a.clone();
    let mut d = vec![1.0; n];
    for _ in 0..100 {
        let mut changed = false;
        for i in 0..n {
            let c: f64 = (0..n).filter(|&k| k != i).map(|k| m[(k, i)].abs()).sum();
            let r: f64 = (0..n).filter(|&k| k != i).map(|k| m[(i, k)].abs()).sum();
            if c == 0.0 || r == 0.0 {
                continue;
            }
            let mut f = 1.0;
            let (mut cc, mut rr) = (c, r);
            while cc < rr / 2.0 {
                cc *= 2.0;
                rr /= 2.0;
                f *= 2.0;
            }
            while cc > rr * 2.0 {
                cc /= 2.0;
                rr *= 2.0;
                f /= 2.0;
            }
            if (cc + rr) < 0.95 * (c + r) {
                changed = true;
                d[i] *= f;
                for k in 0..n {
                    m[(i, k)] /= f;
                    m[(k, i)] *= f;
                }
            }
        }
        if !changed {
            break;
        }
    }
    (m, d)
}

/// Bound on the real Schur decomposition's QR sweeps: a few per
/// eigenvalue converge; more means a degenerate matrix.
const SCHUR_MAX_ITERATIONS: usize = 100_000;

fn modes(jac: &DMatrix<f64>, layout: &Layout) -> Result<Vec<Mode>, DynamicsError> {
    let (balanced, _) = balance(jac);
    let eig =
        nalgebra::linalg::Schur::try_new(balanced.clone(), f64::EPSILON, SCHUR_MAX_ITERATIONS)
            .ok_or(DynamicsError::Setting {
                setting: "linearised system matrix size",
                value: jac.nrows() as f64,
                rule: "the eigenvalues did not converge within the iteration bound",
            })?
            .complex_eigenvalues();
    let n = jac.nrows();
    let lateral: Vec<bool> = layout
        .states
        .iter()
        .map(|(_, kind)| {
            matches!(
                kind,
                Kind::Position(1) | Kind::Angle(0) | Kind::Angle(2) | Kind::Velocity(1)
            ) || matches!(kind, Kind::Rate(0) | Kind::Rate(2))
        })
        .collect();
    let cjac: DMatrix<Complex<f64>> = balanced.map(|v| Complex::new(v, 0.0));
    let mut out: Vec<Mode> = eig
        .iter()
        .map(|&lambda| {
            // Inverse iteration for the eigenvector (in balanced
            // coordinates, where the states are comparably scaled).
            let shift = lambda + Complex::new(1e-9 * (1.0 + lambda.norm()), 0.0);
            let m = &cjac - DMatrix::<Complex<f64>>::identity(n, n) * shift;
            let lu = m.lu();
            let mut v = DVector::from_element(n, Complex::new(1.0, 0.0));
            for _ in 0..3 {
                if let Some(w) = lu.solve(&v) {
                    let norm = w.norm();
                    if norm.is_finite() && norm > 0.0 {
                        v = w / Complex::new(norm, 0.0);
                    }
                }
            }
            let total: f64 = v.iter().map(|c| c.norm_sqr()).sum();
            let lat: f64 = v
                .iter()
                .zip(&lateral)
                .filter(|(_, l)| **l)
                .map(|(c, _)| c.norm_sqr())
                .sum();
            Mode {
                eigenvalue: lambda,
                frequency_hz: lambda.im.abs() / (2.0 * PI),
                damping_ratio: if lambda.norm() > 0.0 {
                    -lambda.re / lambda.norm()
                } else {
                    0.0
                },
                lateral_share: if total > 0.0 { lat / total } else { 0.0 },
            }
        })
        .collect();
    out.sort_by(|a, b| b.eigenvalue.re.total_cmp(&a.eigenvalue.re));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn balancing_keeps_the_eigenvalues() {
        // A badly scaled 2-DOF oscillator: x'' = −1e6 x, written with x in
        // µm-like and velocity in km/s-like units.
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1e6, -1.0, 0.0]);
        let (b, d) = balance(&a);
        assert!(d.iter().any(|v| *v != 1.0));
        let ea = a.complex_eigenvalues();
        let eb = b.complex_eigenvalues();
        for (x, y) in ea.iter().zip(eb.iter()) {
            assert!((x.im.abs() - y.im.abs()).abs() < 1e-9 * x.norm());
            assert!((x.im.abs() - 1e3).abs() < 1e-6);
        }
    }
}
