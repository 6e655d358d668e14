//! A runnable model assembled from a configuration: the track tables, the
//! vehicle model, the contact data and the system settings, with the
//! planner's decisions ([`plan`]).

pub mod cache;
pub mod contact;
pub mod load;
pub mod plan;
pub mod settings;
pub mod track;
pub mod vehicle;
