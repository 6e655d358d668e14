//! Configuration: scene and vehicle files → typed structs with serde enums,
//! each checked by one `validate()` that names the violated rule
//! (`docs/reference/10-scene-files.md`, `docs/reference/11-vehicle-files.md`).

pub mod choices;
pub mod formulation;
pub mod load;
pub mod overrides;
pub mod scene;
pub mod statics;
pub mod suspension;
pub mod sweep;
pub mod variation;
pub mod vehicle;

pub use variation::Variation;
