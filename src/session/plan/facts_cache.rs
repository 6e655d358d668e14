//! The track facts of a scene built from CSV or design inputs, cached
//! ([`crate::session::cache`]): probing the fitted centreline and rails
//! every 5 cm over the run's range ([`super::facts::track_facts`]) costs
//! 28 M instructions for the 300 m straight (4.5 % of the 13.5 s bogie
//! run's, 6 % of the 7.8 s one at 36 m/s) and gives the same facts for the
//! same inputs at every run.
//!
//! Key: everything the track is built from ([`super::track_inputs_key`]:
//! tool version, build configuration, the input files' texts) and the
//! range probed. The values are written in Rust's shortest round-trip
//! form, so cached facts are the probed ones bit for bit. A damaged or
//! foreign entry is not used: the facts are probed again and the entry
//! rewritten.

use anyhow::Result;
use preproc::BuildConfig;

use super::facts::TrackFacts;
use crate::config::scene::LoadedScene;

/// The `kind` of facts probed from a centreline or design file.
pub(super) const KIND: &str = "centerline";

/// The facts of `ls`'s track over `range` (m) from the cache, or from
/// `probe` (called on a cache miss only) and then cached.
pub(super) fn cached(
    ls: &LoadedScene,
    config: &BuildConfig,
    range: [f64; 2],
    probe: impl FnOnce() -> Result<TrackFacts>,
) -> Result<TrackFacts> {
    let mut key = super::track_inputs_key(ls, config)?;
    key.write_str("track facts")
        .write_str(&format!("{:e} {:e}", range[0], range[1]));
    let path =
        crate::session::cache::cache_dir()?.join(format!("track-facts-{:016x}.txt", key.finish()));
    if let Some(f) = std::fs::read_to_string(&path).ok().and_then(|t| parse(&t)) {
        return Ok(f);
    }
    let facts = probe()?;
    // Written atomically (the workspace's one atomic writer); a failure to
    // cache is not an error: the next run probes again.
    let _ = runtime::io::write_atomically(&path, |tmp| std::fs::write(tmp, format(&facts)));
    Ok(facts)
}

/// One `name value` line per fact.
fn format(f: &TrackFacts) -> String {
    format!(
        "length_m {:e}\nmax_curvature_1_m {:e}\nmax_cant_rad {:e}\nirregularities {}\nmax_irregularity_m {:e}\n",
        f.length_m, f.max_curvature_1_m, f.max_cant_rad, f.irregularities, f.max_irregularity_m
    )
}

/// The facts of a cache file: exactly the lines of [`format`], in order,
/// with finite values of the right sign.
fn parse(text: &str) -> Option<TrackFacts> {
    let lines: Vec<(&str, &str)> = text
        .lines()
        .map(|l| l.split_once(' '))
        .collect::<Option<_>>()?;
    let [length, curvature, cant, irregular, irregularity] = lines.as_slice() else {
        return None;
    };
    let value = |(n, v): &(&str, &str), name: &str| -> Option<f64> {
        let v: f64 = v.parse().ok()?;
        (*n == name && v.is_finite() && v >= 0.0).then_some(v)
    };
    let irregularities = match *irregular {
        ("irregularities", "true") => true,
        ("irregularities", "false") => false,
        _ => return None,
    };
    Some(TrackFacts {
        kind: KIND.into(),
        length_m: value(length, "length_m").filter(|v| *v > 0.0)?,
        max_curvature_1_m: value(curvature, "max_curvature_1_m")?,
        max_cant_rad: value(cant, "max_cant_rad")?,
        irregularities,
        max_irregularity_m: value(irregularity, "max_irregularity_m")?,
        file_step_m: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn facts() -> TrackFacts {
        TrackFacts {
            kind: KIND.into(),
            length_m: 300.0,
            max_curvature_1_m: 0.1 + 0.2,
            max_cant_rad: 7.123456789012345e-3,
            irregularities: true,
            max_irregularity_m: 4.2e-3,
            file_step_m: None,
        }
    }

    #[test]
    fn the_cache_text_round_trips_bit_for_bit() {
        let f = facts();
        let back = parse(&format(&f)).expect("parses");
        assert_eq!(back, f);
        assert_eq!(back.max_curvature_1_m.to_bits(), (0.1f64 + 0.2).to_bits());
        // Damaged or foreign text is not used.
        let text = format(&f);
        assert_eq!(
            parse(&text.replace("irregularities true", "irregularities yes")),
            None
        );
        assert_eq!(parse(&text.replace("max_cant_rad", "max_cant")), None);
        assert_eq!(parse(&text.replace("4.2e-3", "-4.2e-3")), None);
        assert_eq!(parse(&text.replace("4.2e-3", "NaN")), None);
        assert_eq!(parse(&format!("{text}extra 1\n")), None);
        assert_eq!(parse(&text[..text.len() / 2]), None);
    }

    /// The planner's facts of the default scene (a 300 m straight from its
    /// centreline file) are the probed ones, and the second lookup takes
    /// them from the cache: the probe is not called.
    #[test]
    fn a_second_plan_takes_the_probed_facts_from_the_cache() {
        let ls = LoadedScene::default_scene(&[]).expect("scene");
        let config = crate::session::plan::build_config(&ls).expect("config");
        let range = [1.0, 250.0];
        let probed = super::super::facts::probe_facts(&ls, &config, range).expect("probed");
        assert_eq!(probed.kind, KIND);
        let first = cached(&ls, &config, range, || Ok(probed.clone())).expect("first");
        assert_eq!(first, probed);
        let again = cached(&ls, &config, range, || anyhow::bail!("probed again")).expect("cached");
        assert_eq!(again, probed);
        assert_eq!(
            super::super::facts::track_facts(&ls, range).expect("facts"),
            probed
        );
        // Another range is another entry.
        let other = cached(&ls, &config, [1.0, 251.0], || anyhow::bail!("probed"));
        assert!(other.is_err());
    }
}
