//! Curving, running-safety and wear outputs of a run
//! (docs/guide/curving-and-safety.md): per wheelset the track shifting
//! force ΣY against Prud'homme's limit, the wheel unloading ΔQ/Q0, the
//! angle of attack and the wear number Tγ ([`safety`]); the track's
//! straights, transitions and arcs from its design file when the tables
//! carry them ([`design`]), else from its curvature ([`elements`]); and
//! per arc the EN 14363-style quasi-static values ([`arcs`]), all from
//! the 2 m sliding means and percentiles of [`windows`].

pub mod arcs;
pub mod design;
pub mod elements;
pub mod safety;
pub mod text;
pub mod windows;

use runtime::geometry::track::TrackTables;
use runtime::results::RunResults;
use serde::Serialize;

pub use arcs::ArcSummary;
pub use design::ElementSource;
pub use elements::{ElementKind, TrackElement};
pub use safety::{SafetyVerdict, WheelsetSafety};

/// The track's elements and the quasi-static values over its arcs.
#[derive(Debug, Clone, Serialize, PartialEq, Default)]
pub struct CurvingSummary {
    /// Straights, transitions and arcs of the tabulated track, in order.
    pub track_elements: Vec<TrackElement>,
    /// Where they come from: the design file (the tables' `/design`) or
    /// the centreline's curvature.
    pub track_elements_source: ElementSource,
    /// Every arc a wheelset's samples reach.
    pub arcs: Vec<ArcSummary>,
}

impl CurvingSummary {
    /// The elements of `track` (its design elements when it has them,
    /// else from its centreline table's horizontal curvature) and the
    /// arcs' values from `results`.
    pub fn of(track: &TrackTables, results: &RunResults) -> Self {
        let (track_elements, track_elements_source) = if track.design_elements.is_empty() {
            let rows = track.centerline.rows();
            let s: Vec<f64> = rows.iter().map(|r| r.s_m).collect();
            let k: Vec<f64> = rows.iter().map(|r| r.horizontal_curvature_1_m).collect();
            (elements::find_elements(&s, &k), ElementSource::Curvature)
        } else {
            (
                design::from_design(&track.design_elements),
                ElementSource::DesignFile,
            )
        };
        let cant = |s_m: f64| track.centerline.at(s_m).ok().map(|p| p.cant_rad);
        let arcs = arcs::arc_summaries(
            &results.wheelsets,
            &track_elements,
            &cant,
            track.meta.cant_base_m,
        );
        Self {
            track_elements,
            track_elements_source,
            arcs,
        }
    }
}
