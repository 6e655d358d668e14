//! The irregularities decision: the build's irregularity stage runs only
//! when the scene gives an irregularity table (module docs of [`super`]).

use super::facts::TrackFacts;
use super::{By, Decision, mm};

/// State whether the irregularity stage runs, with the largest deviation
/// over the run's range.
pub(super) fn decide(facts: &TrackFacts) -> Decision {
    Decision {
        item: "irregularities".into(),
        value: if facts.irregularities {
            "built"
        } else {
            "none"
        }
        .into(),
        by: By::Scene,
        reason: if facts.irregularities {
            format!(
                "the scene gives an irregularity table: largest deviation {} over the run's range",
                mm(facts.max_irregularity_m)
            )
        } else {
            "the scene has none: the irregularity stage is skipped".into()
        },
    }
}
