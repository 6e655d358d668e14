//! Polach's creep force method (being written).

use super::{CreepError, CreepForces, CreepInput};

/// Parameters of Polach's method (being written).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PolachParams {
    /// Slip-velocity dependent friction, if any.
    pub slip_friction: Option<SlipVelocityFriction>,
}

/// μ(w) = μ0[(1 − A)e^(−Bw) + A] (being written).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipVelocityFriction {
    /// A = μ∞/μ0.
    pub a_ratio: f64,
    /// B (s/m).
    pub b_s_m: f64,
}

impl PolachParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), CreepError> {
        Ok(())
    }
}

pub(crate) fn forces(input: &CreepInput, _p: &PolachParams) -> Result<CreepForces, CreepError> {
    super::kalker::linear_forces(input)
}
