//! Studies: many runs (or evaluations) of one scene varied in a typed way,
//! their results used in memory.

pub mod bifurcation;
pub mod compare_tables;
pub mod contact;
pub mod creep_curves;
pub mod critical_speed;
pub mod cross_code;
pub mod cycle_death;
pub mod run_difference;
pub mod step_dwell;
pub mod sweep;
pub mod tradeoff;
