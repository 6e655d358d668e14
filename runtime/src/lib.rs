//! Run-time library of the wheel–rail contact toolkit (Pombo, Ambrósio &
//! Silva; the equations, units, frames and file formats are in the
//! repository's `docs/reference/`).
//!
//! The folders follow the paper's pipeline:
//!
//! - [`geometry`]: splines, the tabulated track and its frames, the wheel
//!   and rail profiles;
//! - [`contact`]: the contact search (Newton on the surface parameters,
//!   tread and flange, lead/lag), quasi-static settling, Nadal's limit, our
//!   contact lookup table and another code's imported table;
//! - [`forces`]: Hertz, the normal force, creepages and the creep laws;
//! - [`multibody`]: bodies, suspension elements, the vehicle, the system
//!   y′ = f(t, y) (assemble, evaluate, energy) and its contact sources;
//! - [`integrators`]: RK4 and DOPRI5;
//! - [`results`]: a run's sampled results as plain data;
//! - `io` (feature `io`, on by default): the only modules that touch files
//!   (HDF5 table and results files, profile files, the atomic writer, the
//!   numeric table reader). Without `io` the crate builds without HDF5.
//!
//! The `fixtures` feature (off by default, turns on `io`) adds `fixtures`:
//! test support (wheelsets, ODE test problems) shared by the workspace's
//! tests and benches.
//!
//! Units: SI throughout (m, s, kg, N, rad). Global frame Z up; track frame
//! `t` tangent, `n` lateral pointing left, `b = t × n` up (docs/reference/01-units-frames.md §1).

pub mod contact;
#[cfg(feature = "fixtures")]
pub mod fixtures;
pub mod forces;
pub mod geometry;
pub mod integrators;
#[cfg(feature = "io")]
pub mod io;
pub mod multibody;
pub mod quadrature;
pub mod results;

pub use nalgebra::Vector3;
