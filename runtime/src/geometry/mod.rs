//! Geometry of the track and the profiles (paper §2–3;
//! `docs/reference/03-track-preproc.md`, `docs/reference/05-surfaces.md`):
//! the splines ([`spline`]), the tabulated track and its frames
//! ([`track`]), and the wheel and rail profiles ([`profile`]).

pub mod profile;
pub mod spline;
pub mod track;
