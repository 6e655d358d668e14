//! The variants of a study: the cartesian product of its grid axes (the
//! last axis fastest), times its random draws; numbered from 0 in that
//! order, so that a variant's number names the same parameters wherever the
//! study runs.

use anyhow::{Context, Result};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::Distribution as _;

use crate::config::sweep::{Distribution, SweepFile};

/// One variant: its number and the values of the varied keys, in the
/// table's key order.
#[derive(Debug, Clone, PartialEq)]
pub struct Variant {
    pub index: usize,
    pub params: Vec<(String, toml::Value)>,
}

impl Variant {
    /// `key=value …`, for messages.
    pub fn describe(&self) -> String {
        self.params
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// The draws of a study's `[random]`: draw d's values, one per parameter,
/// from the ChaCha8 stream d of the study's seed.
fn draws(sweep: &SweepFile) -> Result<Vec<Vec<(String, toml::Value)>>> {
    let Some(r) = &sweep.random else {
        return Ok(vec![Vec::new()]);
    };
    let mut out = Vec::with_capacity(r.draws);
    for d in 0..r.draws {
        let mut rng = ChaCha8Rng::seed_from_u64(r.seed);
        rng.set_stream(d as u64);
        let mut values = Vec::with_capacity(r.params.len());
        for p in &r.params {
            let v = match p.distribution {
                Distribution::Uniform { low, high } => toml::Value::Float(
                    rand_distr::Uniform::new(low, high)
                        .with_context(|| format!("[[random.params]] {}", p.key))?
                        .sample(&mut rng),
                ),
                Distribution::Normal { mean, std } => toml::Value::Float(
                    rand_distr::Normal::new(mean, std)
                        .with_context(|| format!("[[random.params]] {}", p.key))?
                        .sample(&mut rng),
                ),
                Distribution::Integer { low, high } => toml::Value::Integer(
                    rand_distr::Uniform::new_inclusive(low, high)
                        .with_context(|| format!("[[random.params]] {}", p.key))?
                        .sample(&mut rng),
                ),
            };
            values.push((p.key.clone(), v));
        }
        out.push(values);
    }
    Ok(out)
}

/// Every variant of `sweep` (checked by `SweepFile::validate`).
pub fn expand(sweep: &SweepFile) -> Result<Vec<Variant>> {
    let axes: Vec<(String, Vec<toml::Value>)> = sweep
        .vary
        .iter()
        .map(|a| Ok((a.key.clone(), a.values()?)))
        .collect::<Result<_>>()?;
    let draws = draws(sweep)?;
    let grid: usize = axes.iter().map(|(_, v)| v.len()).product();
    let mut out = Vec::with_capacity(grid * draws.len());
    for g in 0..grid {
        // Mixed-radix digits of g, the last axis fastest.
        let mut rest = g;
        let mut point = vec![toml::Value::Boolean(false); axes.len()];
        for (k, (_, values)) in axes.iter().enumerate().rev() {
            point[k] = values[rest % values.len()].clone();
            rest /= values.len();
        }
        for draw in &draws {
            let mut params: Vec<(String, toml::Value)> = axes
                .iter()
                .zip(&point)
                .map(|((key, _), v)| (key.clone(), v.clone()))
                .collect();
            params.extend(draw.iter().cloned());
            out.push(Variant {
                index: out.len(),
                params,
            });
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sweep(text: &str) -> SweepFile {
        let s: SweepFile = toml::from_str(text).unwrap();
        s.validate().unwrap();
        s
    }

    #[test]
    fn grid_is_a_cartesian_product_last_axis_fastest() {
        let s = sweep(
            r#"title = "t"
            scene = "s.toml"
            [compute]
            kind = "critical_speed"
            method = "linear"
            [[vary]]
            key = "a"
            values = [1, 2]
            [[vary]]
            key = "b"
            values = ["x", "y", "z"]"#,
        );
        let v = expand(&s).unwrap();
        assert_eq!(v.len(), 6);
        assert_eq!(v[1].describe(), "a=1 b=\"y\"");
        assert_eq!(v[3].describe(), "a=2 b=\"x\"");
        assert!(v.iter().enumerate().all(|(i, v)| v.index == i));
    }

    #[test]
    fn draws_are_seeded_shared_by_grid_points_and_in_range() {
        let text = r#"title = "t"
            scene = "s.toml"
            [compute]
            kind = "critical_speed"
            method = "linear"
            [[vary]]
            key = "a"
            values = [1, 2]
            [random]
            draws = 50
            seed = 7
            [[random.params]]
            key = "u"
            distribution = "uniform"
            low = 0.1
            high = 0.2
            [[random.params]]
            key = "seed"
            distribution = "integer"
            low = 1
            high = 3"#;
        let v = expand(&sweep(text)).unwrap();
        assert_eq!(v.len(), 100);
        // The same draw d at both grid points; reproducible.
        assert_eq!(v[5].params[1..], v[55].params[1..]);
        assert_eq!(expand(&sweep(text)).unwrap(), v);
        for x in &v {
            let u = x.params[1].1.as_float().unwrap();
            assert!((0.1..0.2).contains(&u));
            let s = x.params[2].1.as_integer().unwrap();
            assert!((1..=3).contains(&s));
        }
        // Different draws differ.
        assert_ne!(v[0].params[1], v[1].params[1]);
    }
}
