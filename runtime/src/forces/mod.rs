//! Contact forces (paper §4.4–4.5; `docs/reference/07-contact-forces.md`):
//! the Hertz ellipse ([`hertz`], with the elliptic integrals of
//! [`elliptic`]), the normal force with hysteresis damping ([`normal`]),
//! creepages ([`creepage`]), the creep laws ([`creep`]) and their
//! combination per contact ([`contact_force`]).

pub mod contact_force;
pub mod creep;
pub mod creepage;
pub mod elliptic;
pub mod hertz;
pub mod normal;
