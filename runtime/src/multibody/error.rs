//! Why a simulation cannot go on ([`DynamicsError`]): the wheelset, body,
//! element or setting concerned, and the time.

use crate::contact::ContactError;
use crate::geometry::track::TrackError;
use crate::multibody::body::BodyError;
use crate::multibody::contact_force::ContactForceError;
use crate::multibody::element::ElementError;

/// Why the simulation cannot go on.
#[derive(Debug, thiserror::Error)]
pub enum DynamicsError {
    #[error("wheelset '{wheelset}' at t = {t_s:.6} s: contact search failed: {source}")]
    Contact {
        wheelset: String,
        t_s: f64,
        #[source]
        source: ContactError,
    },
    #[error("wheelset '{wheelset}' at t = {t_s:.6} s: contact force: {source}")]
    Force {
        wheelset: String,
        t_s: f64,
        #[source]
        source: ContactForceError,
    },
    #[error("{what} at t = {t_s:.6} s is off the track tables: {source}")]
    Track {
        what: String,
        t_s: f64,
        #[source]
        source: TrackError,
    },
    #[error(
        "wheelset '{wheelset}' derailed at t = {t_s:.6} s: lateral displacement {lateral_mm:.1} mm exceeds {limit_mm:.1} mm"
    )]
    Derailed {
        wheelset: String,
        t_s: f64,
        lateral_mm: f64,
        limit_mm: f64,
    },
    #[error("body '{name}': {source}")]
    Body {
        name: String,
        #[source]
        source: BodyError,
    },
    #[error("element '{name}': {source}")]
    Element {
        name: String,
        #[source]
        source: ElementError,
    },
    #[error("setting {setting} = {value}: {rule}")]
    Setting {
        setting: &'static str,
        value: f64,
        rule: &'static str,
    },
    #[error("wheelset '{wheelset}': {reason}")]
    Assembly { wheelset: String, reason: String },
    /// The samples could not be handed to the results file while the run
    /// went on (`crate::results::ResultsSink`; the message names the file).
    #[error("writing the results at t = {t_s:.6} s: {message}")]
    Output { t_s: f64, message: String },
}
