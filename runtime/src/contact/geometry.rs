//! The four contact equations of one wheel–rail pair and zone (paper
//! §4.2, eq. 18–19; docs/reference/06-contact-detection.md §6) and their analytic Jacobian.
//!
//! Unknowns `x = (s_r, u_r, s_w, u_w)`:
//! * `s_r` — arc length of the rail (its table's L) (m);
//! * `u_r` — lateral coordinate on the rail profile, along the rail's
//!   lateral axis `n` (positive left) (m);
//! * `s_w` — angle of the wheel's profile plane about the axle (rad),
//!   positive when the point lies **ahead** of the axle (lead);
//! * `u_w` — lateral coordinate on the wheel profile along the axle η
//!   (positive left) (m).
//!
//! Surfaces (paper eq. 2–10):
//! * rail: `r_r = p(s_r) + u_r·n(s_r) + f_r(u_r)·b(s_r)`, with
//!   `f_r(u) = z_rail(σu)` (σ = +1 right, −1 left: the internal profile is the
//!   right-hand one, see [`crate::geometry::profile`]);
//! * wheel: `r_w = r_ws + A (h + (−f_w sin s_w, u_w, f_w cos s_w))`, with
//!   `A = [ξ η ζ]`, `h = (0, −σH/2, 0)` and `f_w(u) = z_wheel(σu) − R0`
//!   (minus the wheel radius).
//!
//! Equations: `N·t1 = 0`, `N·t2 = 0` (normals parallel, eq. 18) and
//! `d·t1 = 0`, `d·t2 = 0` (distance along the normal, eq. 19), with
//! `N = b − f_r'·n` the rail normal in its profile plane (paper eq. 5),
//! `t1 = A (cos s_w, 0, sin s_w)` and `t2 = A (−f_w' sin s_w, 1, f_w' cos s_w)`
//! the wheel's tangents (eq. 11–12) and `d = r_w − r_r`.

use std::cell::Cell;

use nalgebra::{Matrix4, Vector3, Vector4};

use super::WheelsetPose;
use super::small_angle;
use crate::geometry::profile::{CurvePoint, PlacedRailProfile, ProfileCurve, WheelProfile};
use crate::geometry::track::{RailPointDerivative, RailTable, Side, TrackError};

/// Surface parameters of a candidate contact (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SurfaceParams {
    /// Rail arc length (m).
    pub s_rail_m: f64,
    /// Lateral position on the rail profile along `n` (m).
    pub u_rail_m: f64,
    /// Angle of the wheel point about the axle, positive ahead (rad).
    pub s_wheel_rad: f64,
    /// Lateral position on the wheel profile along the axle η (m).
    pub u_wheel_m: f64,
}

impl SurfaceParams {
    pub(crate) fn to_vector(self) -> Vector4<f64> {
        Vector4::new(
            self.s_rail_m,
            self.u_rail_m,
            self.s_wheel_rad,
            self.u_wheel_m,
        )
    }

    pub(crate) fn from_vector(v: &Vector4<f64>) -> Self {
        Self {
            s_rail_m: v[0],
            u_rail_m: v[1],
            s_wheel_rad: v[2],
            u_wheel_m: v[3],
        }
    }
}

/// Everything computed at one point `x` of the equations.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct PairEval {
    pub residual: Vector4<f64>,
    pub jacobian: Matrix4<f64>,
    pub wheel_point: Vector3<f64>,
    pub rail_point: Vector3<f64>,
    /// Unnormalised rail normal `b − f_r' n`.
    pub rail_normal: Vector3<f64>,
    /// ∂r_r/∂s_r (the rail's rolling direction).
    pub rail_ds: Vector3<f64>,
    pub rail_d: RailPointDerivative,
    /// Profile values at the internal (right-hand) coordinates σu.
    pub rail_profile: CurvePoint,
    pub wheel_profile: CurvePoint,
    /// (sin s_w, cos s_w).
    pub wheel_angle_sin_cos: (f64, f64),
}

/// Where a pair's lookups start: the rail head's and the wheel curve's
/// spline pieces and the rail table's interval of an evaluation (see
/// [`Pair`]). A hint changes how a piece is found, never which piece: any
/// value, even one of another curve or out of range, gives the same bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PieceHints {
    pub rail_piece: usize,
    pub wheel_piece: usize,
    pub rail_row: usize,
}

impl PieceHints {
    /// No hint: the first lookups search.
    pub const NONE: Self = Self {
        rail_piece: usize::MAX,
        wheel_piece: usize::MAX,
        rail_row: usize::MAX,
    };
}

/// One wheel–rail pair and zone, ready to be evaluated.
pub(crate) struct Pair<'a> {
    pub rail_table: &'a RailTable,
    pub rail: &'a PlacedRailProfile,
    pub wheel: &'a WheelProfile,
    pub wheel_curve: &'a ProfileCurve,
    pub sigma: f64,
    /// Lateral position of the wheel's profile origin on the axle (m): −σH/2.
    pub h_m: f64,
    pub pose: &'a WheelsetPose,
    /// The rail head's and the wheel curve's spline pieces of the last
    /// evaluation: the next lookups start there (the same values, found
    /// without a binary search while the iterates stay on or next to them).
    pub rail_piece: Cell<usize>,
    pub wheel_piece: Cell<usize>,
    /// The rail table's interval of the last evaluation (the same use).
    pub rail_row: Cell<usize>,
    /// Columns ξ, η, ζ of the pose's axle frame `A` (global).
    axes: [Vector3<f64>; 3],
}

/// `A v` for `v = (x, 0, z)` from the columns `a` of `A`: `a_ξ x + a_ζ z`,
/// the operations of nalgebra's `A * v` (column by column, in order)
/// without the product by the zero component.
#[inline(always)]
fn frame_xz(a: &[Vector3<f64>; 3], x: f64, z: f64) -> Vector3<f64> {
    a[0] * x + a[2] * z
}

impl<'a> Pair<'a> {
    pub fn new(
        rail_table: &'a RailTable,
        rail: &'a PlacedRailProfile,
        wheel: &'a WheelProfile,
        wheel_curve: &'a ProfileCurve,
        half_spacing_m: f64,
        pose: &'a WheelsetPose,
    ) -> Self {
        let sigma = match rail_table.side() {
            Side::Left => -1.0,
            Side::Right => 1.0,
        };
        Self {
            rail_table,
            rail,
            wheel,
            wheel_curve,
            sigma,
            h_m: -sigma * half_spacing_m,
            pose,
            rail_piece: Cell::new(usize::MAX),
            wheel_piece: Cell::new(usize::MAX),
            rail_row: Cell::new(usize::MAX),
            axes: [
                pose.frame.column(0).into_owned(),
                pose.frame.column(1).into_owned(),
                pose.frame.column(2).into_owned(),
            ],
        }
    }

    /// Start the next lookups from `h` (e.g. the pieces of the same patch's
    /// last solve): the same values, found without a search while the
    /// iterates stay on or next to them.
    #[inline]
    pub fn set_hints(&self, h: PieceHints) {
        self.rail_piece.set(h.rail_piece);
        self.wheel_piece.set(h.wheel_piece);
        self.rail_row.set(h.rail_row);
    }

    /// The pieces and interval of the last evaluation.
    #[inline]
    pub fn hints(&self) -> PieceHints {
        PieceHints {
            rail_piece: self.rail_piece.get(),
            wheel_piece: self.wheel_piece.get(),
            rail_row: self.rail_row.get(),
        }
    }

    /// The wheel's surface point at angle `s_w_rad` about the axle and
    /// lateral position `u_w_m` on the profile (global, m): `r_w` of the
    /// module docs, the same expression [`Self::eval`] uses.
    pub fn wheel_point_m(&self, s_w_rad: f64, u_w_m: f64) -> Vector3<f64> {
        let f_w = self.wheel_curve.at(self.sigma * u_w_m).z_m - self.wheel.nominal_radius_m();
        let (ss, cs) = small_angle::sin_cos(s_w_rad);
        self.pose.position + self.pose.frame * Vector3::new(-f_w * ss, self.h_m + u_w_m, f_w * cs)
    }

    /// Residual and Jacobian at `x`.
    pub fn eval(&self, x: &Vector4<f64>) -> Result<PairEval, TrackError> {
        let mut e = PairEval::default();
        self.eval_into(x, &mut e)?;
        Ok(e)
    }

    /// [`Self::eval`] written into `out` (every field; left untouched on
    /// an error): the Newton iteration reuses one evaluation's storage
    /// instead of moving the large result around.
    #[inline]
    pub fn eval_into(&self, x: &Vector4<f64>, out: &mut PairEval) -> Result<(), TrackError> {
        let (s_r, u_r, s_w, u_w) = (x[0], x[1], x[2], x[3]);
        let sg = self.sigma;
        // The calls first: `sin_cos` (a library call beyond the small
        // angles, [`small_angle`]) and the profiles' spline lookups (a call
        // when a hint misses), so that few values are live across them
        // (none of the rail's and the vectors below is spilled to the stack
        // around them); each value is the same.
        let (ss, cs) = small_angle::sin_cos(s_w);
        let rp = self.rail.head().at_near(sg * u_r, &self.rail_piece);
        let wp = self.wheel_curve.at_near(sg * u_w, &self.wheel_piece);
        // Rail.
        let (rail, rd) = self
            .rail_table
            .at_with_derivative_near(s_r, &self.rail_row)?;
        let (p, n, b) = (rail.position, rail.frame.n, rail.frame.b);
        let (f_r, f_r1, f_r2) = (rp.z_m, sg * rp.dz, rp.d2z_1_m);
        let r_r = p + n * u_r + b * f_r;
        let r_r_s = rd.position + rd.n * u_r + rd.b * f_r;
        let r_r_u = n + b * f_r1;
        let big_n = b - n * f_r1;
        let big_n_s = rd.b - rd.n * f_r1;
        let big_n_u = -n * f_r2;
        // Wheel.
        let r0 = self.wheel.nominal_radius_m();
        let (f_w, f_w1, f_w2) = (wp.z_m - r0, sg * wp.dz, wp.d2z_1_m);
        // The wheel's vectors A q, each as nalgebra's `A * q` computes it
        // (the same bits), without the products by q's zero components.
        let a = &self.axes;
        let r_w = self.pose.position
            + ((a[0] * (-f_w * ss) + a[1] * (self.h_m + u_w)) + a[2] * (f_w * cs));
        let r_w_s = frame_xz(a, -f_w * cs, -f_w * ss);
        let t1 = frame_xz(a, cs, ss);
        let t1_s = frame_xz(a, -ss, cs);
        let t2 = (a[0] * (-f_w1 * ss) + a[1]) + a[2] * (f_w1 * cs);
        let t2_s = frame_xz(a, -f_w1 * cs, -f_w1 * ss);
        let t2_u = frame_xz(a, -f_w2 * ss, f_w2 * cs);
        let r_w_u = t2;
        let d = r_w - r_r;

        let residual = Vector4::new(big_n.dot(&t1), big_n.dot(&t2), d.dot(&t1), d.dot(&t2));
        #[rustfmt::skip]
        let jacobian = Matrix4::new(
            big_n_s.dot(&t1), big_n_u.dot(&t1), big_n.dot(&t1_s), 0.0,
            big_n_s.dot(&t2), big_n_u.dot(&t2), big_n.dot(&t2_s), big_n.dot(&t2_u),
            -r_r_s.dot(&t1), -r_r_u.dot(&t1), r_w_s.dot(&t1) + d.dot(&t1_s), r_w_u.dot(&t1),
            -r_r_s.dot(&t2), -r_r_u.dot(&t2), r_w_s.dot(&t2) + d.dot(&t2_s), r_w_u.dot(&t2) + d.dot(&t2_u),
        );
        *out = PairEval {
            residual,
            jacobian,
            wheel_point: r_w,
            rail_point: r_r,
            rail_normal: big_n,
            rail_ds: r_r_s,
            rail_d: rd,
            rail_profile: rp,
            wheel_profile: wp,
            wheel_angle_sin_cos: (ss, cs),
        };
        Ok(())
    }
}
