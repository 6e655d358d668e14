//! The start of a warm solve from the last solve of the same patch: the
//! contact equations linearised at its solution and moved to the new pose
//! (docs/reference/06-contact-detection.md §6.2).
//!
//! At a converged solve x₀ (pose P₀) the equations F(x; P) = 0 of
//! [`super::geometry`] hold. For the next pose P₁ one Newton step from
//! g = x₀ + Δs·e_s (the rail arc length moved with the wheelset, Δs its
//! change) with the last Jacobian J₀ (its LU factors, kept from the
//! solve's last step) gives the start
//!
//!   x = g − J₀⁻¹ F(g; P₁),
//!
//! first-order exact in the pose change: the travel, the lateral and
//! vertical motion and the rotations of the wheelset are all in F(g; P₁).
//! It costs no profile, table or trigonometric lookup:
//! * the rail's terms are affine in s_r within one interval of its table
//!   (the table interpolates linearly, [`crate::geometry::track`]), so
//!   r_r(g) = r_r(x₀) + Δs ∂r_r/∂s_r and N(g) = N(x₀) + Δs ∂N/∂s_r are
//!   exact there (beyond it, a kink of the rail the next solve corrects);
//! * the wheel's terms depend on P only through its frame: the vectors
//!   are kept in the axle's frame (body coordinates) and turned by P₁.
//!
//! Its error is second order in the change of (u_r, s_w, u_w) (and in the
//! Jacobian's change between poses times that change), where the trend of
//! the last two solves (the fallback, [`super::solver`]) is first order in
//! the stages' departures from a smooth path.
//!
//! The second-order term, ½ x″[Δ, Δ] for a pose change Δ, is even in Δ
//! and scales with |Δ|² along one line of motion. The last solve's miss —
//! its solution minus its first-order start — is that term for the last
//! change; when the new linear correction lies along the same line
//! (either way: cos² ≥ 0.8 between the lateral parts of the two
//! corrections) and is of a similar size (ratio of squares r² in
//! [1/4, 4]), the miss scaled by r² is added. On S1002/UIC60, where the
//! equations are least linear (near-conformal tread), a 10 µm move leaves
//! the first-order start 7 nm off and this term takes it below the 1 nm
//! tolerance.
//!
//! Either way the start is only a start: the solve accepts a point by the
//! unchanged test (the Newton step at an evaluated point below the
//! tolerances), and in a run most solves now converge at their first
//! evaluation.

use nalgebra::{Vector3, Vector4};

use super::WheelsetPose;
use super::geometry::{Pair, PairEval};
use super::lu4::Lu4;
use super::newton::Converged;

/// Largest correction of (s_r, u_r, s_w, u_w) (m, m, rad, m) the predictor
/// may make: beyond it the linearisation is not trusted (a jump of the
/// pose, a patch moving across a profile's kink) and the caller's guess
/// is used (time stepping's: g plus the trend of the last two solves).
const MAX_CORRECTION: [f64; 4] = [0.01, 0.002, 0.02, 0.002];

/// The contact equations of one patch linearised at a converged solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Linearisation {
    /// The solution (s_r, u_r, s_w, u_w) (m, m, rad, m).
    x: Vector4<f64>,
    /// The rail's point r_r and ∂r_r/∂s_r there (global; m, –).
    rail_point: Vector3<f64>,
    rail_point_s: Vector3<f64>,
    /// The rail's (unnormalised) normal N = b − f_r′ n and ∂N/∂s_r (global;
    /// –, 1/m).
    rail_normal: Vector3<f64>,
    rail_normal_s: Vector3<f64>,
    /// The wheel's point relative to the wheelset's centre and its two
    /// tangents t1, t2, in the axle's frame (m, –, –).
    wheel_point_body: Vector3<f64>,
    t1_body: Vector3<f64>,
    t2_body: Vector3<f64>,
    /// The wheelset's pose at the solve: at the same pose the next start
    /// is the solution itself, so a solve repeated at one state gives the
    /// same bits.
    pose: WheelsetPose,
    /// The LU factors of ∂F/∂x at the solution (of the solve's last
    /// Newton step).
    lu: Lu4,
    /// The last solve's miss — its solution minus its predicted start's
    /// first-order part — and the predictor's correction then (see
    /// [`Self::start`]); `None` when that solve was not started by the
    /// predictor.
    miss: Option<(Vector4<f64>, Vector4<f64>)>,
}

/// Where a followed solve starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Start {
    /// From the caller's guess (no linearisation, or the predictor's
    /// correction not trusted).
    Guess,
    /// The same pose and arc length as the linearisation's solve: from
    /// that solution itself (the same bits again).
    Same(Vector4<f64>),
    /// From the predictor: the start `x`, its first-order part `linear`
    /// (g plus the linear correction) and that correction.
    Predicted {
        x: Vector4<f64>,
        linear: Vector4<f64>,
        correction: Vector4<f64>,
    },
}

impl Linearisation {
    /// The storage of the factors: a solve started from this linearisation
    /// factors into it ([`super::newton::solve`]), replacing the factors
    /// that gave its start.
    pub(crate) fn lu_mut(&mut self) -> &mut Lu4 {
        &mut self.lu
    }

    /// Store into `slot` the linearisation at the solution `c`, where
    /// `pair` was evaluated into `e`, with the factors of the solve's last
    /// Newton step ([`super::newton::solve`]) in `lu`, or already in the
    /// slot's linearisation when `lu` is `None` ([`Self::lu_mut`]).
    pub(crate) fn store(
        slot: &mut Option<Self>,
        pair: &Pair<'_>,
        pose: &WheelsetPose,
        c: &Converged,
        e: &PairEval,
        lu: Option<&Lu4>,
        start: &Start,
    ) {
        let x = &c.x;
        let sg = pair.sigma;
        let (ss, cs) = e.wheel_angle_sin_cos;
        let f_w = e.wheel_profile.z_m - pair.wheel.nominal_radius_m();
        let f_w1 = sg * e.wheel_profile.dz;
        let f_r1 = sg * e.rail_profile.dz;
        // Written field by field into the slot (no temporary of a few
        // hundred bytes copied at every solve).
        let l = slot.get_or_insert_with(|| Self {
            x: Vector4::zeros(),
            rail_point: Vector3::zeros(),
            rail_point_s: Vector3::zeros(),
            rail_normal: Vector3::zeros(),
            rail_normal_s: Vector3::zeros(),
            wheel_point_body: Vector3::zeros(),
            t1_body: Vector3::zeros(),
            t2_body: Vector3::zeros(),
            pose: *pose,
            lu: Lu4::ZERO,
            miss: None,
        });
        l.x = *x;
        l.rail_point = e.rail_point;
        l.rail_point_s = e.rail_ds;
        l.rail_normal = e.rail_normal;
        l.rail_normal_s = e.rail_d.b - e.rail_d.n * f_r1;
        l.wheel_point_body = Vector3::new(-f_w * ss, pair.h_m + x[3], f_w * cs);
        l.t1_body = Vector3::new(cs, 0.0, ss);
        l.t2_body = Vector3::new(-f_w1 * ss, 1.0, f_w1 * cs);
        l.pose = *pose;
        if let Some(lu) = lu {
            l.lu = *lu;
        }
        l.miss = match *start {
            Start::Guess => None,
            // A repeat at one pose says nothing new about the miss.
            Start::Same(_) => l.miss,
            Start::Predicted {
                linear, correction, ..
            } => Some((x - linear, correction)),
        };
    }

    /// The start for the wheelset at `pose` with the rail arc length moved
    /// to `s_rail_m` (see the module docs): the solution itself at the
    /// same pose and arc length; the caller's guess when the correction is
    /// not finite or beyond [`MAX_CORRECTION`].
    pub(crate) fn start(&self, pose: &WheelsetPose, s_rail_m: f64) -> Start {
        self.predict(pose, s_rail_m).unwrap_or(Start::Guess)
    }

    fn predict(&self, pose: &WheelsetPose, s_rail_m: f64) -> Option<Start> {
        let ds = s_rail_m - self.x[0];
        if ds == 0.0 && *pose == self.pose {
            return Some(Start::Same(self.x));
        }
        let a = &pose.frame;
        let t1 = a * self.t1_body;
        let t2 = a * self.t2_body;
        let d =
            pose.position + a * self.wheel_point_body - (self.rail_point + self.rail_point_s * ds);
        let big_n = self.rail_normal + self.rail_normal_s * ds;
        let f = Vector4::new(big_n.dot(&t1), big_n.dot(&t2), d.dot(&t1), d.dot(&t2));
        let dx = self.lu.solve(&(-f))?;
        if !(0..4).all(|k| dx[k].abs() <= MAX_CORRECTION[k]) {
            return None;
        }
        let mut g = self.x;
        g[0] = s_rail_m;
        let linear = g + dx;
        let mut x = linear;
        // The second-order term: the last miss, scaled by the square of
        // the lateral correction's size, when the correction is along the
        // same line (either way: the term is even in the motion).
        if let Some((miss, dx0)) = self.miss {
            let lateral = |v: &Vector4<f64>| (v[1], v[3]);
            let ((a1, b1), (a0, b0)) = (lateral(&dx), lateral(&dx0));
            let (n1, n0, dot) = (a1 * a1 + b1 * b1, a0 * a0 + b0 * b0, a1 * a0 + b1 * b0);
            if n0 > 0.0 && dot * dot >= 0.8 * n1 * n0 {
                let r2 = n1 / n0;
                if (0.25..=4.0).contains(&r2) {
                    x += miss * r2;
                }
            }
        }
        Some(Start::Predicted {
            x,
            linear,
            correction: dx,
        })
    }
}
