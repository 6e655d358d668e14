//! FASTSIM (being written).

use super::{CreepError, CreepForces, CreepInput};

/// FASTSIM discretisation (being written).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FastsimParams {
    /// Strips across the ellipse.
    pub strips: usize,
    /// Elements per strip.
    pub elements_per_strip: usize,
}

impl Default for FastsimParams {
    fn default() -> Self {
        FastsimParams {
            strips: 20,
            elements_per_strip: 20,
        }
    }
}

impl FastsimParams {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), CreepError> {
        Ok(())
    }
}

pub(crate) fn forces(input: &CreepInput, _p: &FastsimParams) -> Result<CreepForces, CreepError> {
    super::kalker::linear_forces(input)
}
