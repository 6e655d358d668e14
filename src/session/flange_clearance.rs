//! The flangeway clearance of every wheelset (the quasi-static sweep of
//! `runtime::contact::quasi_static::flange_clearance_m`, about 0.1 s per
//! contact model), computed once and cached ([`super::cache`]) for the
//! planner's flange facts and for assembly
//! (`SystemSettings::flange_clearances_m`), so that a run, a repeated run
//! and every run of a study (a critical-speed sweep) do not sweep again.
//!
//! Key: the tool version, the rail profile's text, the rail placement
//! (gauge, rail spacing, inclination), `track.keep_longest_stretch`, and per
//! wheelset its wheel profile's text, nominal radius and back-to-back
//! distance: everything the wheelset's contact model is built from
//! (`super::vehicle::vehicle_model`). The values are written in Rust's
//! shortest round-trip form, so a cached clearance is the swept one bit
//! for bit.

use std::path::Path;

use anyhow::{Context, Result};
use runtime::contact::WheelsetContactModel;
use runtime::contact::quasi_static::flange_clearance_m;
use runtime::geometry::profile::RailPlacement;
use runtime::geometry::track::Side;
use runtime::multibody::{FlangeClearances, VehicleModel};

use crate::config::vehicle::VehicleFile;

/// What the clearances are computed from, apart from the model itself.
pub struct ClearanceInputs<'a> {
    pub vehicle_file: &'a VehicleFile,
    /// The scene's rail profile.
    pub rail: &'a Path,
    pub placement: RailPlacement,
    pub keep_longest_stretch: bool,
}

/// The clearances of every wheelset of the vehicle, in vehicle order, from
/// the cache or swept on `model()` (built only on a cache miss) and cached.
pub fn flange_clearances<'m>(
    inputs: &ClearanceInputs<'_>,
    model: impl FnOnce() -> Result<&'m VehicleModel>,
) -> Result<Vec<FlangeClearances>> {
    let v = inputs.vehicle_file;
    let mut key = super::cache::Fnv64::default();
    let p = &inputs.placement;
    key.write_str(env!("CARGO_PKG_VERSION"))
        .write_str("flange clearances")
        .write_str(
            &std::fs::read_to_string(inputs.rail)
                .with_context(|| format!("reading {}", inputs.rail.display()))?,
        )
        .write_str(&format!(
            "{:e} {:e} {:e} {}",
            p.gauge_m, p.rail_spacing_m, p.inclination_rad, inputs.keep_longest_stretch
        ));
    for w in &v.wheelsets {
        let path = v.profile_path(w);
        key.write_str(
            &std::fs::read_to_string(&path)
                .with_context(|| format!("reading {}", path.display()))?,
        )
        .write_str(&format!("{:e} {:e}", w.nominal_radius_m, w.back_to_back_m));
    }
    let path = super::cache::cache_dir()?.join(format!("clearances-{:016x}.txt", key.finish()));
    if let Some(c) = std::fs::read_to_string(&path)
        .ok()
        .and_then(|t| parse(&t, v.wheelsets.len()))
    {
        return Ok(c);
    }
    let clearances = sweep(model()?)?;
    // Written atomically (the workspace's one atomic writer); a failure to
    // cache is not an error: the next run sweeps again.
    let _ = runtime::io::write_atomically(&path, |tmp| std::fs::write(tmp, format(&clearances)));
    Ok(clearances)
}

/// The sweep, once per distinct contact model.
fn sweep(vehicle: &VehicleModel) -> Result<Vec<FlangeClearances>> {
    let mut done: Vec<(&WheelsetContactModel, FlangeClearances)> = Vec::new();
    let mut out = Vec::new();
    for w in &vehicle.wheelsets {
        if let Some((_, c)) = done.iter().find(|(m, _)| *m == &w.contact) {
            out.push(*c);
            continue;
        }
        let mut c: FlangeClearances = [None, None];
        for (k, side) in Side::BOTH.into_iter().enumerate() {
            c[k] = flange_clearance_m(&w.contact, side)
                .with_context(|| format!("flangeway clearance of wheelset '{}'", w.name))?;
        }
        done.push((&w.contact, c));
        out.push(c);
    }
    Ok(out)
}

/// One line per wheelset, "left right" (m), "-" where the flange does not
/// touch.
fn format(clearances: &[FlangeClearances]) -> String {
    let one = |c: Option<f64>| c.map_or("-".to_string(), |v| format!("{v:e}"));
    clearances
        .iter()
        .map(|[l, r]| format!("{} {}\n", one(*l), one(*r)))
        .collect()
}

/// The cache file's clearances, if it holds `n` valid lines.
fn parse(text: &str, n: usize) -> Option<Vec<FlangeClearances>> {
    let one = |t: &str| -> Option<Option<f64>> {
        match t {
            "-" => Some(None),
            _ => t
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v >= 0.0)
                .map(Some),
        }
    };
    let c: Vec<FlangeClearances> = text
        .lines()
        .map(|l| {
            let mut it = l.split_whitespace();
            let c = [one(it.next()?)?, one(it.next()?)?];
            it.next().is_none().then_some(c)
        })
        .collect::<Option<_>>()?;
    (c.len() == n).then_some(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::scene::LoadedScene;

    /// A session with the flange search `auto` hands assembly the swept
    /// clearances of its vehicle; a second computation comes from the
    /// cache (the model is not asked for).
    #[test]
    fn a_session_gives_assembly_the_cached_sweep() {
        let scene = LoadedScene::default_scene(&["contact.flange=auto".into()]).expect("scene");
        let session = crate::session::Session::new(&scene).expect("session");
        let given = session
            .settings
            .flange_clearances_m
            .clone()
            .expect("clearances given to assembly");
        assert_eq!(given, sweep(&session.vehicle).expect("sweep"));
        assert!(given[0].iter().all(|c| c.is_some_and(|c| c > 0.001)));
        let s = &session.scene.scene;
        let m = &session.track.meta;
        let inputs = ClearanceInputs {
            vehicle_file: &session.vehicle_file,
            rail: &session.scene.path(&s.track.rail_profile),
            placement: RailPlacement {
                gauge_m: m.gauge_m,
                rail_spacing_m: m.rail_spacing_m,
                inclination_rad: m.rail_inclination_rad,
            },
            keep_longest_stretch: s.track.keep_longest_stretch,
        };
        let cached = flange_clearances(&inputs, || anyhow::bail!("swept again")).expect("cached");
        assert_eq!(cached, given);
        // The flange search off: no sweep needed, none given.
        let off = LoadedScene::default_scene(&["contact.flange=off".into()]).expect("scene");
        let session = crate::session::Session::new(&off).expect("session");
        assert_eq!(session.settings.flange_clearances_m, None);
    }

    #[test]
    fn the_cache_text_round_trips_bit_for_bit() {
        let c = vec![[Some(0.1 + 0.2), None], [None, Some(7.123456789012345e-3)]];
        let back = parse(&format(&c), 2).expect("parses");
        assert_eq!(back, c);
        assert_eq!(back[0][0].unwrap().to_bits(), (0.1f64 + 0.2).to_bits());
        // A file for another vehicle, or damaged, is not used.
        assert_eq!(parse(&format(&c), 3), None);
        assert_eq!(parse("0.1 x\n", 1), None);
        assert_eq!(parse("0.1\n", 1), None);
        assert_eq!(parse("0.1 0.2 0.3\n", 1), None);
        assert_eq!(parse("-0.1 -\n", 1), None);
    }
}
