//! Run-time library of the wheel–rail contact toolkit (Pombo, Ambrósio &
//! Silva; the equations, units, frames and file formats are in the
//! repository's `docs/reference/`).
//!
//! Math modules take plain structs and return plain structs; only the
//! modules of the `io` feature (on by default) touch files: [`schema`]
//! (the HDF5 table and results files, read and write, so the
//! pre-processor's writer and the simulator's reader cannot drift apart)
//! [`io`] (the one atomic file writer, the one numeric table reader) and
//! [`profile_import`] (profile files). Without `io` the crate builds
//! without HDF5.
//!
//! The `fixtures` feature (off by default, turns on `io`) adds
//! `fixtures` (feature `fixtures`): test support shared by the workspace's tests and benches.
//!
//! Units: SI throughout (m, s, kg, N, rad). Global frame Z up; track frame
//! `t` tangent, `n` lateral pointing left, `b = t × n` up (docs/reference/01-units-frames.md §1).

pub mod profile;
pub mod quadrature;
pub mod results;
#[cfg(feature = "io")]
pub mod schema;
pub mod spline;
pub mod track;

pub use nalgebra::Vector3;
pub mod body;
pub mod contact;
pub mod contact_force;
pub mod contact_table;
pub mod creep;
pub mod creepage;
pub mod dynamics;
pub mod element;
pub mod elliptic;
#[cfg(feature = "fixtures")]
pub mod fixtures;
pub mod hertz;
pub mod imported_contact;
pub mod integrator;
#[cfg(feature = "io")]
pub mod io;
pub mod normal;
#[cfg(feature = "io")]
pub mod profile_import;
