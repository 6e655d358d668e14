//! Contact forces (paper §4.4–4.5; `docs/reference/07-contact-forces.md`):
//! the Hertz ellipse ([`hertz`], with the elliptic integrals of
//! [`elliptic`]), the normal force with hysteresis damping ([`normal`]),
//! creepages ([`creepage`]) and the creep laws ([`creep`]). Their
//! combination per contact of the multibody system is
//! [`crate::multibody::contact_force`].

pub mod creep;
pub mod creepage;
pub mod elliptic;
pub mod hertz;
pub mod normal;
