//! A profile function z(u) on a closed domain, with slope and curvature.

use std::cell::Cell;

use crate::geometry::spline::{PiecewiseCubic, Scheme};

/// Height, slope and second derivative of a profile at one lateral position.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CurvePoint {
    /// z (m).
    pub z_m: f64,
    /// dz/du (–).
    pub dz: f64,
    /// d²z/du² (1/m).
    pub d2z_1_m: f64,
}

impl CurvePoint {
    /// Signed curvature z''/(1 + z'²)^{3/2} (1/m), the power taken as
    /// w·√w (w = 1 + z'²): a square root, not a general power.
    #[inline]
    pub fn curvature_1_m(&self) -> f64 {
        let w = 1.0 + self.dz * self.dz;
        self.d2z_1_m / (w * w.sqrt())
    }

    /// Cosine of the slope angle, cos(atan z') = 1/√(1 + z'²) (–).
    #[inline]
    pub fn slope_cos(&self) -> f64 {
        1.0 / (1.0 + self.dz * self.dz).sqrt()
    }
}

/// z(u) fitted with one of the spline schemes, valid on `[u_min, u_max]`
/// (evaluation outside extends the end pieces).
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileCurve {
    spline: PiecewiseCubic,
    u_min_m: f64,
    u_max_m: f64,
}

impl ProfileCurve {
    /// Fit `z(u)` (u strictly increasing) and restrict it to `[u_min, u_max]`.
    pub(crate) fn fit(
        scheme: Scheme,
        u: &[f64],
        z: &[f64],
        u_min_m: f64,
        u_max_m: f64,
    ) -> Result<Self, crate::geometry::spline::SplineError> {
        Ok(Self {
            spline: PiecewiseCubic::fit(scheme, u, z)?,
            u_min_m,
            u_max_m,
        })
    }

    /// The same fitted function restricted to another domain.
    pub(crate) fn restricted(&self, u_min_m: f64, u_max_m: f64) -> Self {
        Self {
            spline: self.spline.clone(),
            u_min_m,
            u_max_m,
        }
    }

    /// The same function shifted by (du, dz): z'(u) = z(u − du) + dz.
    pub(crate) fn shifted(&self, du_m: f64, dz_m: f64) -> Self {
        Self {
            spline: self.spline.translated(du_m, dz_m),
            u_min_m: self.u_min_m + du_m,
            u_max_m: self.u_max_m + du_m,
        }
    }

    /// Domain `(u_min, u_max)` (m).
    pub fn domain_m(&self) -> (f64, f64) {
        (self.u_min_m, self.u_max_m)
    }

    /// True when `u_m` lies in the domain, widened by `tol_m`.
    pub fn contains(&self, u_m: f64, tol_m: f64) -> bool {
        u_m >= self.u_min_m - tol_m && u_m <= self.u_max_m + tol_m
    }

    /// Height, slope and second derivative at `u_m`.
    #[inline]
    pub fn at(&self, u_m: f64) -> CurvePoint {
        let d = self.spline.derivatives(u_m);
        CurvePoint {
            z_m: d.value,
            dz: d.d1,
            d2z_1_m: d.d2,
        }
    }

    /// [`Self::at`], looking the spline piece up from `hint` first (see
    /// [`PiecewiseCubic::piece_index_near`]; the same values bit for bit)
    /// and leaving the piece used in it.
    #[inline]
    pub(crate) fn at_near(&self, u_m: f64, hint: &Cell<usize>) -> CurvePoint {
        let i = self.spline.piece_index_near(u_m, hint.get());
        hint.set(i);
        let d = self.spline.derivatives_in_piece(i, u_m);
        CurvePoint {
            z_m: d.value,
            dz: d.d1,
            d2z_1_m: d.d2,
        }
    }

    /// The underlying spline's scheme.
    pub fn scheme(&self) -> Scheme {
        self.spline.scheme()
    }
}
