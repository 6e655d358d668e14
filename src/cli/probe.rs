//! `sim probe`: both rails' interpolated position and frame at a centreline
//! distance, read from a table file with the run-time reader (the same code
//! path a simulation uses).

use std::path::Path;

use anyhow::{Context, Result};
use runtime::geometry::track::{Side, TrackTables};
use runtime::io::schema;
use serde::Serialize;

/// One rail at the probed distance.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RailProbe {
    pub side: &'static str,
    /// Rail arc length at the probed centreline distance (m).
    pub l_m: f64,
    /// Position of the rail profile origin (m).
    pub position_m: [f64; 3],
    /// Rail frame: tangent, lateral (left), normal.
    pub t: [f64; 3],
    pub n: [f64; 3],
    pub b: [f64; 3],
}

/// The result of a probe.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Probe {
    pub file: String,
    /// Centreline distance probed (m).
    pub s_m: f64,
    /// Cant at s (rad).
    pub cant_rad: f64,
    pub rails: Vec<RailProbe>,
}

/// Probe loaded tables at centreline distance `s_m`.
pub fn probe_tables(tables: &TrackTables, file: &str, s_m: f64) -> Result<Probe> {
    let c = tables.centerline.at(s_m)?;
    let mut rails = Vec::new();
    for side in Side::BOTH {
        let p = tables.rail_at_s(side, s_m)?;
        rails.push(RailProbe {
            side: side.name(),
            l_m: p.l_m,
            position_m: p.position.into(),
            t: p.frame.t.into(),
            n: p.frame.n.into(),
            b: p.frame.b.into(),
        });
    }
    Ok(Probe {
        file: file.to_string(),
        s_m,
        cant_rad: c.cant_rad,
        rails,
    })
}

/// The track tables of a table file, with the error naming it.
pub fn load_tables(path: &Path) -> Result<TrackTables> {
    schema::read_track(path)
        .with_context(|| format!("loading track tables from {}", path.display()))
}

/// Load `path` and probe it at `s_m`.
pub fn probe_file(path: &Path, s_m: f64) -> Result<Probe> {
    let tables = load_tables(path)?;
    probe_tables(&tables, &path.display().to_string(), s_m)
        .with_context(|| format!("probing {} at s = {s_m} m", path.display()))
}

impl Probe {
    /// Human-readable form.
    pub fn to_text(&self) -> String {
        let v = |a: [f64; 3]| format!("[{:+.9}, {:+.9}, {:+.9}]", a[0], a[1], a[2]);
        let mut out = format!(
            "{} at s = {} m (cant {:.6} rad)\n",
            self.file, self.s_m, self.cant_rad
        );
        for r in &self.rails {
            out += &format!(
                "  {:<5} rail  L = {:.6} m\n    position  {} m\n    t         {}\n    n         {}\n    b         {}\n",
                r.side,
                r.l_m,
                v(r.position_m),
                v(r.t),
                v(r.n),
                v(r.b)
            );
        }
        out
    }
}
