//! The creep law: never chosen (it is physics, not numerics); its cost
//! relative to Polach's, measured by `sim tradeoff`
//! (`tables/planner/measured.toml`), is stated (module docs of [`super`]).

use anyhow::Result;

use super::measured::measured;
use super::{By, Decision};
use crate::config::scene::CreepLawName;

/// State the scene's creep law and its measured cost.
pub(super) fn decide(law: CreepLawName) -> Result<Decision> {
    let cost = &measured()?.creep_law_cost;
    let rel = |l| cost.relative(l).unwrap_or(f64::NAN);
    Ok(Decision {
        item: "creep_law".into(),
        value: law.to_string(),
        by: By::Scene,
        reason: match cost.relative(law) {
            Some(f) => format!(
                "wall time ×{f:.2} of Polach's (FASTSIM ×{:.2}, FaStrip ×{:.2}, Kalker ×{:.2}, Heuristic ×{:.2}; {})",
                rel(CreepLawName::Fastsim),
                rel(CreepLawName::Fastrip),
                rel(CreepLawName::Kalker),
                rel(CreepLawName::Heuristic),
                cost.study
            ),
            None => "cost not measured".into(),
        },
    })
}
