//! Track from design elements (docs/reference/03-track-preproc.md §3h;
//! file format docs/reference/02-inputs.md §2.9): straights, circular
//! arcs and transition curves (clothoid, cubic parabola, Bloss, cosine)
//! with cant ramps, grades and parabolic vertical curves, each with its
//! length and its radius and cant at the ends. Curvature, heading, cant,
//! cant rate and grade come from the element formulas in closed form; the
//! plan position is their Gauss–Legendre quadrature. The
//! [`crate::centerline::Centerline`] of a design track samples this model
//! instead of a spline through control points.
//!
//! - [`shape`]: the ramp functions f(u) of transitions and cant ramps;
//! - [`cubic_parabola`]: y = c·x³;
//! - [`element`]: one plan element placed in the plan;
//! - [`vertical`]: grades and vertical curves, s ↔ σ;
//! - [`cant`]: the cant along one element;
//! - [`file`](mod@file): the TOML design file and its rules;
//! - [`track`]: the evaluated track;
//! - [`records`]: its plan elements as the table file records them.

pub mod cant;
pub mod cubic_parabola;
pub mod element;
pub mod file;
pub mod records;
pub mod shape;
pub mod track;
pub mod vertical;

pub use file::DesignInput;
pub use track::{DesignPoint, DesignTrack};
