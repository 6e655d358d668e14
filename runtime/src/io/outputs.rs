//! Outputs checked before the work (`docs/guide/run-a-scene.md`, "What is
//! written when"): a command lists its inputs and its outputs, and
//! [`check_outputs`] refuses, before any computation,
//!
//! - an output that is one of the inputs (the same file by canonical path,
//!   through any spelling, link or `..`): writing it would replace the
//!   user's data with results;
//! - an output file whose path names an existing directory, or an output
//!   directory whose path names an existing file;
//! - an output whose directory is missing or not writable: a temporary file
//!   is created there and removed (the probe), so that the failure comes
//!   now and not after a long run or build whose work would be lost.
//!
//! It is one mechanism for every command of the workspace (`sim run`,
//! `track-preproc build`, …), so that none can miss a case.

use std::path::{Path, PathBuf};

/// What an output is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputKind {
    /// A file, written atomically (`super::atomic`).
    File,
    /// A directory of files (created when missing).
    Directory,
}

/// One output of a command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Output {
    pub path: PathBuf,
    pub kind: OutputKind,
    /// What it is, for messages ("the results file", "the plots folder").
    pub role: &'static str,
}

/// Why an output is refused; every variant names the paths.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The output would replace one of the command's inputs.
    #[error(
        "{role} '{output}' is the input '{input}': writing it would replace the input; choose another output path"
    )]
    ReplacesInput {
        role: &'static str,
        output: PathBuf,
        input: PathBuf,
    },
    /// A file output names a directory (or a directory output a file).
    #[error("{role} '{path}' {reason}")]
    WrongKind {
        role: &'static str,
        path: PathBuf,
        reason: &'static str,
    },
    /// The output's directory cannot be written.
    #[error(
        "{role} '{path}' cannot be written: {reason} (checked before the work, so that nothing is lost)"
    )]
    NotWritable {
        role: &'static str,
        path: PathBuf,
        reason: String,
    },
}

/// The canonical form of `path`, also for a path that does not exist yet:
/// its existing ancestor canonicalised, the rest appended.
fn canonical(path: &Path) -> PathBuf {
    if let Ok(c) = path.canonicalize() {
        return c;
    }
    let absolute = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir()
            .map(|d| d.join(path))
            .unwrap_or_else(|_| path.to_path_buf())
    };
    let mut rest = Vec::new();
    let mut cur = absolute.as_path();
    loop {
        if let Ok(c) = cur.canonicalize() {
            let mut out = c;
            for part in rest.iter().rev() {
                out.push(part);
            }
            return out;
        }
        match (cur.parent(), cur.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                cur = parent;
            }
            _ => return absolute,
        }
    }
}

/// The directory a file output is written in.
fn directory_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Creates and removes a temporary file in `dir`.
fn probe(dir: &Path) -> Result<(), String> {
    if !dir.is_dir() {
        return Err(format!("the directory '{}' does not exist", dir.display()));
    }
    let name = format!(".railsim-probe-{}", std::process::id());
    let tmp = dir.join(name);
    match std::fs::File::create(&tmp) {
        Ok(_) => {
            let _ = std::fs::remove_file(&tmp);
            Ok(())
        }
        Err(e) => Err(format!(
            "the directory '{}' is not writable ({e})",
            dir.display()
        )),
    }
}

/// Checks `outputs` against `inputs` and probes their locations (module
/// docs). Inputs that do not exist are ignored here (their readers report
/// them).
pub fn check_outputs(inputs: &[PathBuf], outputs: &[Output]) -> Result<(), OutputError> {
    let inputs: Vec<(PathBuf, &PathBuf)> = inputs
        .iter()
        .filter(|p| p.exists())
        .map(|p| (canonical(p), p))
        .collect();
    for o in outputs {
        let c = canonical(&o.path);
        if let Some((_, input)) = inputs.iter().find(|(ci, _)| *ci == c) {
            return Err(OutputError::ReplacesInput {
                role: o.role,
                output: o.path.clone(),
                input: input.to_path_buf(),
            });
        }
        match o.kind {
            OutputKind::File => {
                if o.path.is_dir() {
                    return Err(OutputError::WrongKind {
                        role: o.role,
                        path: o.path.clone(),
                        reason: "is a directory: give a file name",
                    });
                }
                probe(&directory_of(&o.path)).map_err(|reason| OutputError::NotWritable {
                    role: o.role,
                    path: o.path.clone(),
                    reason,
                })?;
            }
            OutputKind::Directory => {
                if o.path.exists() && !o.path.is_dir() {
                    return Err(OutputError::WrongKind {
                        role: o.role,
                        path: o.path.clone(),
                        reason: "is a file: give a directory",
                    });
                }
                // Every input inside the output directory would be at risk
                // of being overwritten by an output of the same name.
                let target = if o.path.is_dir() {
                    o.path.clone()
                } else {
                    directory_of(&o.path)
                };
                probe(&target).map_err(|reason| OutputError::NotWritable {
                    role: o.role,
                    path: o.path.clone(),
                    reason,
                })?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("railsim-outputs-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn file(path: &Path) -> Output {
        Output {
            path: path.to_path_buf(),
            kind: OutputKind::File,
            role: "the results file",
        }
    }

    #[test]
    fn an_output_that_is_an_input_is_refused_through_any_spelling() {
        let d = scratch("same");
        let input = d.join("t.h5");
        std::fs::write(&input, b"tables").unwrap();
        std::fs::create_dir_all(d.join("sub")).unwrap();
        for spelling in [input.clone(), d.join("sub/../t.h5"), d.join("./t.h5")] {
            let e = check_outputs(std::slice::from_ref(&input), &[file(&spelling)]).unwrap_err();
            assert!(matches!(e, OutputError::ReplacesInput { .. }), "{e}");
            assert!(e.to_string().contains("would replace the input"), "{e}");
        }
        #[cfg(unix)]
        {
            let link = d.join("link.h5");
            std::os::unix::fs::symlink(&input, &link).unwrap();
            assert!(check_outputs(std::slice::from_ref(&input), &[file(&link)]).is_err());
        }
        // Another name in the same directory is fine, and so is the input
        // untouched.
        check_outputs(std::slice::from_ref(&input), &[file(&d.join("results.h5"))]).unwrap();
        assert_eq!(std::fs::read(&input).unwrap(), b"tables");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn directories_and_missing_locations_are_found_before_the_work() {
        let d = scratch("where");
        let e = check_outputs(&[], &[file(&d)]).unwrap_err();
        assert!(e.to_string().contains("is a directory"), "{e}");
        let e = check_outputs(&[], &[file(&d.join("missing/out.h5"))]).unwrap_err();
        assert!(e.to_string().contains("does not exist"), "{e}");
        let f = d.join("plain");
        std::fs::write(&f, b"x").unwrap();
        let e = check_outputs(
            &[],
            &[Output {
                path: f.clone(),
                kind: OutputKind::Directory,
                role: "the plots folder",
            }],
        )
        .unwrap_err();
        assert!(e.to_string().contains("is a file"), "{e}");
        // The probe leaves nothing behind.
        check_outputs(&[], &[file(&d.join("ok.h5"))]).unwrap();
        let left: Vec<_> = std::fs::read_dir(&d).unwrap().collect();
        assert_eq!(left.len(), 1, "only 'plain' remains");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn the_probe_agrees_with_the_directory_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let d = scratch("ro");
        let ro = d.join("ro");
        std::fs::create_dir_all(&ro).unwrap();
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
        let probe_ok = std::fs::File::create(ro.join("x")).is_ok(); // root may write anyway
        let r = check_outputs(&[], &[file(&ro.join("out.h5"))]);
        if probe_ok {
            let _ = std::fs::remove_file(ro.join("x"));
            assert!(r.is_ok());
        } else {
            let e = r.unwrap_err();
            assert!(e.to_string().contains("not writable"), "{e}");
        }
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
        std::fs::remove_dir_all(&d).unwrap();
    }
}
