//! Modelling choices of the equations of motion where a published
//! formulation differs from ours and the difference can be switched (the
//! Cooperrider car against DYTSI, docs/guide/cooperrider-cross-code.md).
//! The default of every choice is ours; the contact choices of an imported
//! table are in [`super::imported_contact::ImportedContactMethod`].

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

/// The switchable choices of the equations of motion (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Formulation {
    pub longitudinal_motion: LongitudinalMotion,
}
