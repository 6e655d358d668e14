//! A level straight track built directly in memory (no pre-processing):
//! the reference geometry for contact studies at a prescribed wheelset pose
//! (`sim contact`, contact tables, flangeway clearance).

use super::{
    CenterlineRow, CenterlineTable, Frame, RailRow, RailTable, Side, TrackMeta, TrackTables,
    rail_roll_rad,
};
use nalgebra::Vector3;

/// A straight track along +X at z = 0, `length_m` long with rows every
/// `step_m`, rails `rail_spacing_m` apart and inclined by `inclination_rad`.
pub fn straight_track(
    length_m: f64,
    step_m: f64,
    gauge_m: f64,
    rail_spacing_m: f64,
    inclination_rad: f64,
) -> TrackTables {
    let n = (length_m / step_m).round().max(1.0) as usize;
    let s = |k: usize| length_m * k as f64 / n as f64;
    let centerline = (0..=n)
        .map(|k| CenterlineRow {
            s_m: s(k),
            position: [s(k), 0.0, 0.0],
            t: [1.0, 0.0, 0.0],
            n: [0.0, 1.0, 0.0],
            b: [0.0, 0.0, 1.0],
            l_left_m: s(k),
            l_right_m: s(k),
            ..Default::default()
        })
        .collect();
    let rail = |side: Side| {
        let f = Frame::from_tangent(Vector3::x(), rail_roll_rad(side, 0.0, inclination_rad))
            .expect("horizontal tangent");
        let rows = (0..=n)
            .map(|k| RailRow {
                l_m: s(k),
                position: [s(k), 0.5 * rail_spacing_m * side.sign(), 0.0],
                t: f.t.into(),
                n: f.n.into(),
                b: f.b.into(),
            })
            .collect();
        RailTable::new(side, rows).expect("valid straight rail")
    };
    TrackTables {
        meta: TrackMeta {
            scheme: "exact".into(),
            cant_scheme: "exact".into(),
            step_m: length_m / n as f64,
            gauge_m,
            rail_spacing_m,
            cant_base_m: gauge_m + 0.065,
            rail_inclination: format!("{inclination_rad} rad"),
            rail_inclination_rad: inclination_rad,
            rail_profile: None,
            tool: "runtime::geometry::track::straight_track".into(),
            tool_version: env!("CARGO_PKG_VERSION").into(),
        },
        centerline: CenterlineTable::new(centerline).expect("valid straight centreline"),
        left: rail(Side::Left),
        right: rail(Side::Right),
        design_elements: Vec::new(),
    }
}
