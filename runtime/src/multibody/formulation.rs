//! Modelling choices of the equations of motion where a published
//! formulation differs from ours and the difference can be switched (the
//! Cooperrider car against DYTSI, docs/guide/cooperrider-cross-code.md).
//! The default of every choice is ours; the contact choices of an imported
//! table are in [`super::imported_contact::ImportedContactMethod`].

use nalgebra::{Matrix3, Vector3};

/// The bodies' motion along the track.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LongitudinalMotion {
    /// Every body moves along the track under its forces (ours): the
    /// wheelsets' longitudinal creep forces, the suspension's longitudinal
    /// elements and the drive set its longitudinal motion.
    #[default]
    Free,
    /// No longitudinal degree of freedom (DYTSI's Cooperrider model: its
    /// bodies have lateral, vertical and angular coordinates only, and run
    /// at the imposed speed): the tangential component of every body's
    /// centre-of-mass acceleration is the references' dV/dt, whatever the
    /// forces — an ideal longitudinal constraint whose reaction is not
    /// booked. From bodies started at the references' speed (every run
    /// does) each body's speed along the track stays V(t) exactly on a
    /// straight; on a curve to first order in the lateral velocity.
    Imposed,
}

impl LongitudinalMotion {
    pub fn name(self) -> &'static str {
        match self {
            LongitudinalMotion::Free => "free",
            LongitudinalMotion::Imposed => "imposed",
        }
    }
}

/// The axes along which the suspension elements' stiffness, damping and
/// preload act.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ElementAxes {
    /// Body a's axes, turning with it (ours, docs/reference/08-multibody.md
    /// §8.2): a preloaded vertical spring on a rolled frame pushes along
    /// the frame's tilted vertical.
    #[default]
    Body,
    /// The track frame at body a's centre (DYTSI: its lateral, vertical
    /// and longitudinal springs and dampers act along the global axes, and
    /// a preload stays vertical whatever the bodies' angles). The
    /// deflection is measured in those axes; the attachment points still
    /// move with their bodies.
    Track,
}

impl ElementAxes {
    pub fn name(self) -> &'static str {
        match self {
            ElementAxes::Body => "body",
            ElementAxes::Track => "track",
        }
    }
}

/// The wheelsets' gyroscopic moments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GyroscopicMoments {
    /// Exact (ours): Euler's equations of the spinning wheelset in its own
    /// axes. Linearised in the axle frame (which does not spin) the
    /// gyroscopic moments are +I_y Ω ψ̇ about the roll axis and −I_y Ω φ̇
    /// about the yaw axis.
    #[default]
    Exact,
    /// DYTSI's: Euler's body-axis equations written in the axle frame as if
    /// it spun with the wheelset, (I_y − I_z) Ω ψ̇ on roll and
    /// (I_x − I_y) Ω φ̇ on yaw (its `WheelSetComponent`). Run here as the
    /// exact moments plus the difference −Ω â × (J ω) (â the axle, J the
    /// wheelset's inertia in global axes, ω its angular velocity): in the
    /// axle frame (−I_z Ω ψ̇, 0, +I_x Ω φ̇).
    AxleFrameEuler,
}

impl GyroscopicMoments {
    pub fn name(self) -> &'static str {
        match self {
            GyroscopicMoments::Exact => "exact",
            GyroscopicMoments::AxleFrameEuler => "axle_frame_euler",
        }
    }
}

/// The lever arms of the contact forces' moment about the wheelset's roll
/// axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RollMoment {
    /// The whole arm from the wheelset's centre to the contact point (ours):
    /// a lateral contact force, r below the axle, rolls the wheelset by
    /// r F_y.
    #[default]
    Full,
    /// Only the arm along the axle (DYTSI: its roll moment is
    /// w (F_z + N_z − (F_y + N_y) φ), the rolling radius's arm dropped):
    /// run here as the full moment minus the roll component of the arm
    /// perpendicular to the axle.
    AxleArmOnly,
}

impl RollMoment {
    pub fn name(self) -> &'static str {
        match self {
            RollMoment::Full => "full",
            RollMoment::AxleArmOnly => "axle_arm_only",
        }
    }
}

/// The switchable choices of the equations of motion (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Formulation {
    pub longitudinal_motion: LongitudinalMotion,
    pub element_axes: ElementAxes,
    pub gyroscopic: GyroscopicMoments,
    pub roll_moment: RollMoment,
}

/// The moment (N·m, global) that turns the wheelset's exact gyroscopic
/// moments into DYTSI's ([`GyroscopicMoments::AxleFrameEuler`]):
/// −Ω â × (J ω), Ω = ω·â, J = R J_body Rᵀ. `rotation` is the wheelset's
/// body → global rotation, `inertia_kg_m2` its body-axes inertia, `omega`
/// its angular velocity (rad/s, global), `axle` its axle (unit, global).
pub fn axle_frame_euler_correction(
    rotation: &Matrix3<f64>,
    inertia_kg_m2: &Matrix3<f64>,
    omega: &Vector3<f64>,
    axle: &Vector3<f64>,
) -> Vector3<f64> {
    let spin = omega.dot(axle);
    let j_omega = rotation * (inertia_kg_m2 * (rotation.transpose() * omega));
    -spin * axle.cross(&j_omega)
}

/// The moment (N·m, global) that removes from a contact force's moment
/// about the wheelset's centre its roll component through the arm
/// perpendicular to the axle ([`RollMoment::AxleArmOnly`]): with d = P − c
/// the arm, d⊥ = d − (d·â) â, the correction is −((d⊥ × F)·x̂) x̂, x̂ the
/// roll axis (the track's tangent).
pub fn roll_arm_correction(
    centre_m: &Vector3<f64>,
    axle: &Vector3<f64>,
    roll_axis: &Vector3<f64>,
    point_m: &Vector3<f64>,
    force_n: &Vector3<f64>,
) -> Vector3<f64> {
    let d = point_m - centre_m;
    let d_perp = d - axle * d.dot(axle);
    -roll_axis * d_perp.cross(force_n).dot(roll_axis)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gyroscopic_correction_in_the_axle_frame() {
        // Axle along global y, wheelset turned about its axle (the
        // correction does not depend on the spin angle), roll rate 0.1,
        // yaw rate 0.2, spin 50 rad/s; I = diag(678, 80, 678).
        let j = Matrix3::from_diagonal(&Vector3::new(678.0, 80.0, 678.0));
        let spin_angle: f64 = 0.7;
        let r = nalgebra::Rotation3::from_axis_angle(&Vector3::y_axis(), spin_angle).into_inner();
        let omega = Vector3::new(0.1, 50.0, 0.2);
        let m = axle_frame_euler_correction(&r, &j, &omega, &Vector3::y());
        // (−I_z Ω ψ̇, 0, +I_x Ω φ̇)
        assert!((m.x - (-678.0 * 50.0 * 0.2)).abs() < 1e-9, "{m}");
        assert!(m.y.abs() < 1e-9, "{m}");
        assert!((m.z - 678.0 * 50.0 * 0.1).abs() < 1e-9, "{m}");
    }

    #[test]
    fn the_roll_arm_correction_removes_only_the_radius_arm_about_roll() {
        // Left contact 0.75 m out along the axle and 0.425 m below it; a
        // lateral force of 10 kN (towards the centre: −y) and a vertical
        // one of 60 kN.
        let c = Vector3::new(0.0, 0.0, 0.425);
        let p = Vector3::new(0.0, 0.75, 0.0);
        let f = Vector3::new(1e3, -1e4, 6e4);
        let m = roll_arm_correction(&c, &Vector3::y(), &Vector3::x(), &p, &f);
        // Full roll moment: (d × F)_x = d_y F_z − d_z F_y = 0.75·6e4 −
        // (−0.425)(−1e4); the corrected one keeps 0.75·6e4.
        let full = (p - c).cross(&f).x;
        assert!((full + m.x - 0.75 * 6e4).abs() < 1e-9, "{}", full + m.x);
        assert!(m.y.abs() < 1e-12 && m.z.abs() < 1e-12, "{m}");
    }
}
