//! `key=value` overrides of a scene's entries (`--set`, the studies'
//! variations), applied to the scene's TOML table before it is read into
//! the typed scene (docs/reference/10-scene-files.md, "Overrides").
//!
//! - The value is read as TOML (`20`, `1e-4`, `"x"`, `[1, 2]`), or else as
//!   a string (`polach`, `1:40`); an empty value removes the entry.
//! - A relative path given on the command line to one of the file entries
//!   ([`PATH_KEYS`]) names a file from where the user typed it: it is
//!   resolved against the current directory ([`command_line_assignment`]),
//!   while paths written in the scene resolve against the scene's directory.
//! - A number or boolean given to an entry that is a string
//!   (`track.rail_inclination=0`) is taken as the string typed ([`typed`]).

use std::path::Path;

use anyhow::{Context, Result};
use serde::de::DeserializeOwned;

/// The scene's entries that name a file.
pub const PATH_KEYS: [&str; 8] = [
    "track.tables",
    "track.centerline",
    "track.design",
    "track.cant",
    "track.irregularities",
    "track.rail_profile",
    "vehicle.file",
    "contact.imported_table",
];

/// The dotted key and the value of `key=value` (`None`: remove the entry).
pub fn parse_assignment(assignment: &str) -> Result<(String, Option<toml::Value>)> {
    let (key, value) = assignment
        .split_once('=')
        .context("an override is key=value, e.g. initial.speed_m_s=20")?;
    let key = key.trim();
    anyhow::ensure!(!key.is_empty(), "empty key");
    let value = value.trim();
    if value.is_empty() {
        return Ok((key.to_string(), None));
    }
    let parsed: toml::Value = match format!("v = {value}").parse::<toml::Table>() {
        Ok(mut t) => t.remove("v").context("parsed value")?,
        Err(_) => toml::Value::String(value.to_string()),
    };
    Ok((key.to_string(), Some(parsed)))
}

/// [`parse_assignment`] of a `--set` typed by the user, with a relative
/// path to a file entry ([`PATH_KEYS`]) resolved against the current
/// directory.
pub fn command_line_assignment(assignment: &str) -> Result<(String, Option<toml::Value>)> {
    let (key, value) = parse_assignment(assignment)?;
    match &value {
        Some(toml::Value::String(p))
            if PATH_KEYS.contains(&key.as_str()) && !Path::new(p).is_absolute() =>
        {
            let cwd = std::env::current_dir()
                .context("the current directory, to resolve a path given with --set")?;
            let resolved = cwd.join(p).display().to_string();
            Ok((key, Some(toml::Value::String(resolved))))
        }
        _ => Ok((key, value)),
    }
}

/// Sets (or, with `None`, removes) a dotted key in a TOML table; removing
/// an entry that is not set is an error (a misspelt key would otherwise
/// pass unnoticed).
pub fn set_entry(table: &mut toml::Table, key: &str, value: Option<toml::Value>) -> Result<()> {
    let parts: Vec<&str> = key.split('.').collect();
    anyhow::ensure!(parts.iter().all(|p| !p.is_empty()), "empty key in '{key}'");
    let (last, sections) = parts.split_last().expect("split gives one part at least");
    let mut cur = table;
    for p in sections {
        if value.is_none() {
            cur = cur
                .get_mut(*p)
                .and_then(toml::Value::as_table_mut)
                .with_context(|| format!("'{p}' is not a section of the scene"))?;
        } else {
            cur = cur
                .entry(p.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .with_context(|| format!("'{p}' is not a section"))?;
        }
    }
    match value {
        Some(v) => {
            cur.insert(last.to_string(), v);
        }
        None => {
            cur.remove(*last)
                .with_context(|| format!("'{key}' is not set, nothing to remove"))?;
        }
    }
    Ok(())
}

/// `table` read as `T`. When the reading fails because an overridden entry
/// (`keys`) holds a number or boolean where a string is expected, that
/// entry is turned into its text and the reading is tried again; `table`
/// keeps the turned entries (so the recorded scene text reads back).
pub fn typed<T: DeserializeOwned>(table: &mut toml::Table, keys: &[String]) -> Result<T> {
    loop {
        let err = match table.clone().try_into::<T>() {
            Ok(v) => return Ok(v),
            Err(e) => e,
        };
        let msg = err.to_string();
        let turned = msg.contains("expected a string")
            && keys
                .iter()
                .any(|key| msg.contains(&format!("`{key}`")) && scalar_to_string(table, key));
        if !turned {
            return Err(anyhow::Error::new(err).context("the scene's entries"));
        }
    }
}

/// Replaces the number or boolean at dotted `key` by its text; false when
/// the entry is missing or not such a scalar.
fn scalar_to_string(table: &mut toml::Table, key: &str) -> bool {
    let parts: Vec<&str> = key.split('.').collect();
    let Some((last, sections)) = parts.split_last() else {
        return false;
    };
    let mut cur = table;
    for p in sections {
        match cur.get_mut(*p).and_then(toml::Value::as_table_mut) {
            Some(t) => cur = t,
            None => return false,
        }
    }
    let text = match cur.get(*last) {
        Some(toml::Value::Integer(i)) => i.to_string(),
        Some(toml::Value::Float(x)) => x.to_string(),
        Some(toml::Value::Boolean(b)) => b.to_string(),
        _ => return false,
    };
    cur.insert(last.to_string(), toml::Value::String(text));
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    struct Track {
        inclination: String,
        step_m: f64,
    }
    #[derive(Debug, serde::Deserialize)]
    struct Doc {
        track: Track,
    }

    fn table() -> toml::Table {
        "[track]\ninclination = \"1:40\"\nstep_m = 0.1\n"
            .parse()
            .unwrap()
    }

    #[test]
    fn a_number_for_a_string_entry_is_the_string_typed() {
        let mut t = table();
        let (k, v) = parse_assignment("track.inclination=0").unwrap();
        assert_eq!(v, Some(toml::Value::Integer(0)));
        set_entry(&mut t, &k, v).unwrap();
        // Without the key listed as overridden the reading fails as before.
        assert!(typed::<Doc>(&mut t.clone(), &[]).is_err());
        let d: Doc = typed(&mut t, &[k]).unwrap();
        assert_eq!(d.track.inclination, "0");
        assert_eq!(t["track"]["inclination"].as_str(), Some("0"));
        // A number where a number is expected stays a number, and a string
        // where a number is expected is still refused.
        let (k, v) = parse_assignment("track.step_m=0.2").unwrap();
        set_entry(&mut t, &k, v).unwrap();
        assert_eq!(typed::<Doc>(&mut t, &[k]).unwrap().track.step_m, 0.2);
        let (k, v) = parse_assignment("track.step_m=fine").unwrap();
        set_entry(&mut t, &k, v).unwrap();
        let e = typed::<Doc>(&mut t, &[k]).unwrap_err();
        assert!(format!("{e:#}").contains("step_m"), "{e:#}");
    }

    #[test]
    fn a_path_typed_on_the_command_line_resolves_against_the_current_directory() {
        let cwd = std::env::current_dir().unwrap();
        let (_, v) = command_line_assignment("track.centerline=my/track.csv").unwrap();
        assert_eq!(
            v,
            Some(toml::Value::String(
                cwd.join("my/track.csv").display().to_string()
            ))
        );
        // Absolute paths and other entries are kept as typed.
        let (_, v) = command_line_assignment("track.centerline=/data/c.csv").unwrap();
        assert_eq!(v, Some(toml::Value::String("/data/c.csv".into())));
        let (_, v) = command_line_assignment("track.rail_inclination=1:20").unwrap();
        assert_eq!(v, Some(toml::Value::String("1:20".into())));
    }

    #[test]
    fn removing_an_entry_that_is_not_set_is_refused() {
        let mut t = table();
        set_entry(&mut t, "track.step_m", None).unwrap();
        assert!(t["track"].get("step_m").is_none());
        let e = set_entry(&mut t, "track.step_m", None).unwrap_err();
        assert!(e.to_string().contains("nothing to remove"), "{e}");
        let e = set_entry(&mut t, "trak.step_m", None).unwrap_err();
        assert!(e.to_string().contains("not a section"), "{e}");
    }
}
