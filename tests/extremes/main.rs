//! Numerical stability at the extremes (issue 7): each case is a scene (or a
//! track, a profile pair, an input file) pushed to the edge of its range and
//! the property it must keep there — no panic, no NaN or infinity in the
//! results, energy/momentum bookkeeping where it applies, and a clear
//! diagnostic (time, wheel, state) where the model leaves its validity.
//!
//! Cargo builds this directory as one test target: `cargo test --test extremes`.
//! Cases that take minutes are `#[ignore]` (docs/guide/extremes-and-diagnostics.md).

mod bad_input;
#[path = "../common/mod.rs"]
mod common;
mod contact;
mod contact_search;
mod fuzz;
mod motion;
mod overrides;
mod track;
mod trust;
mod trust_diagnostics;
mod trust_inclination;
mod trust_profiles;
mod trust_track;
