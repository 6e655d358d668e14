//! The track frame of docs/reference/03-track-preproc.md §3c and the rail frames of §3f.
//!
//! Sign rules (docs/reference/01-units-frames.md §1): global Z up; `t` the unit tangent in the direction of
//! increasing track distance; `n` lateral, pointing **left**; `b = t × n`
//! (up-ish). A positive roll angle rotates `(n, b)` about `t` so that the left
//! side rises (positive cant lifts the left rail).

use nalgebra::Vector3;

/// Right-handed orthonormal frame `(t, n, b)` with `t × n = b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Unit tangent (direction of travel).
    pub t: Vector3<f64>,
    /// Unit lateral vector, pointing left.
    pub n: Vector3<f64>,
    /// Unit normal `t × n`, pointing up when the roll is small.
    pub b: Vector3<f64>,
}

impl Frame {
    /// The un-canted frame of a tangent: `n₀ ∝ Z × t` (horizontal), `b₀ = t × n₀`,
    /// then rolled by `roll_rad` about `t` (docs/reference/03-track-preproc.md §3c). Unlike the Frenet frame
    /// it exists on straight track and does not flip at inflection points.
    ///
    /// Returns `None` when `tangent` is (nearly) vertical or zero, where the
    /// horizontal lateral direction is undefined.
    pub fn from_tangent(tangent: Vector3<f64>, roll_rad: f64) -> Option<Frame> {
        let t = tangent.try_normalize(1e-300)?;
        let n0 = Vector3::new(-t.y, t.x, 0.0); // Z × t
        let n0 = n0.try_normalize(1e-9)?;
        let b0 = t.cross(&n0);
        Some(Frame { t, n: n0, b: b0 }.rolled(roll_rad))
    }

    /// This frame rotated by `angle_rad` about `t` (positive lifts `n`
    /// towards `b`): `n' = cos·n + sin·b`, `b' = −sin·n + cos·b`.
    pub fn rolled(&self, angle_rad: f64) -> Frame {
        let (s, c) = angle_rad.sin_cos();
        Frame {
            t: self.t,
            n: self.n * c + self.b * s,
            b: self.b * c - self.n * s,
        }
    }

    /// Largest deviation of `[t n b]` from an orthonormal, right-handed
    /// matrix: max over |tᵀt − 1|, |tᵀn|, …, |t × n − b|.
    pub fn orthonormality_error(&self) -> f64 {
        let d = [
            (self.t.norm_squared() - 1.0).abs(),
            (self.n.norm_squared() - 1.0).abs(),
            (self.b.norm_squared() - 1.0).abs(),
            self.t.dot(&self.n).abs(),
            self.t.dot(&self.b).abs(),
            self.n.dot(&self.b).abs(),
            (self.t.cross(&self.n) - self.b).amax(),
        ];
        d.into_iter().fold(0.0, f64::max)
    }
}

/// Roll of a rail's frame about its tangent: the track cant plus the rail
/// inclination turned towards the track centre (docs/reference/03-track-preproc.md §3f). For the left rail
/// (at +n) "towards the centre" is a positive roll, for the right rail a
/// negative one: a 1:40 inclination tilts both rail heads inwards.
pub fn rail_roll_rad(side: super::Side, cant_rad: f64, inclination_rad: f64) -> f64 {
    match side {
        super::Side::Left => cant_rad + inclination_rad,
        super::Side::Right => cant_rad - inclination_rad,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::track::Side;

    #[test]
    fn level_straight_frame_is_the_global_one() {
        let f = Frame::from_tangent(Vector3::new(2.0, 0.0, 0.0), 0.0).unwrap();
        assert_eq!(f.t, Vector3::x());
        assert_eq!(f.n, Vector3::y());
        assert_eq!(f.b, Vector3::z());
    }

    #[test]
    fn positive_cant_lifts_the_left_side() {
        let f = Frame::from_tangent(Vector3::x(), 0.1).unwrap();
        assert!(f.n.z > 0.0, "left (n) must rise");
        assert!((f.n.z - 0.1_f64.sin()).abs() < 1e-15);
        assert!(f.orthonormality_error() < 1e-15);
    }

    #[test]
    fn graded_tangent_keeps_n_horizontal_without_cant() {
        let f = Frame::from_tangent(Vector3::new(1.0, 1.0, 0.04), 0.0).unwrap();
        assert!(f.n.z.abs() < 1e-16);
        assert!(f.b.z > 0.99);
        assert!(f.orthonormality_error() < 1e-15);
    }

    #[test]
    fn vertical_tangent_has_no_frame() {
        assert!(Frame::from_tangent(Vector3::z(), 0.0).is_none());
        assert!(Frame::from_tangent(Vector3::zeros(), 0.0).is_none());
    }

    #[test]
    fn inclination_tilts_both_rail_heads_inwards() {
        let beta = (1.0_f64 / 40.0).atan();
        let left = Frame::from_tangent(Vector3::x(), rail_roll_rad(Side::Left, 0.0, beta)).unwrap();
        let right =
            Frame::from_tangent(Vector3::x(), rail_roll_rad(Side::Right, 0.0, beta)).unwrap();
        // The left rail sits at +y: its head normal b leans towards −y, and vice versa.
        assert!(left.b.y < 0.0 && right.b.y > 0.0);
        assert!((left.b.y + beta.sin()).abs() < 1e-15);
    }
}
