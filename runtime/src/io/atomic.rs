//! Atomic creation of an output file, the one writer of the workspace for
//! every file it writes (HDF5 tables and results, PNG plots, text): write
//! under a temporary name in the destination's directory, rename over the
//! destination when complete (docs/reference/02-inputs.md §2). Guarantees:
//!
//! * nothing appears at the destination unless the whole file was written
//!   (an existing file there stays as it was until the rename replaces it);
//! * the temporary is in the destination's directory (so the rename is
//!   atomic: same file system), hidden, named `.<name>.tmp-<pid>-<n>`,
//!   `n` counting the files this process has begun, so two writes of one
//!   destination at once (threads, processes) never share a temporary;
//! * the temporary is removed when the write fails, and when an
//!   uncommitted [`AtomicFile`] is dropped (an error returned with `?`, a
//!   panic unwinding);
//! * a process killed mid-write (kill -9, a power cut) leaves its
//!   temporary, but the next write of the same destination removes every
//!   temporary of it whose process is no longer running
//!   ([`remove_stale_temporaries`]);
//! * the temporaries being written are listed ([`remove_temporaries_in_flight`]),
//!   so that a binary's SIGINT/SIGTERM handler removes them before it exits.
//!
//! Two ways to use it:
//!
//! * [`write_atomically`]`(dest, |tmp| …)`: the closure writes the file at
//!   `tmp`; on `Ok` it is renamed into place, on `Err` removed.
//! * [`AtomicFile`]: for a writer that must keep the temporary open across
//!   calls (the HDF5 table writer creates its file at
//!   [`AtomicFile::temp_path`], writes groups over several calls, closes it
//!   and then calls [`AtomicFile::commit`]).
//!
//! Writers that pick their format from the file name (plotters' bitmap
//! backend) get a temporary ending in the destination's extension with
//! [`AtomicFile::keeping_extension`] (`.<name>.tmp-<pid>-<n>.<ext>`).
//!
//! The `tempfile` crate was considered: its temporaries are created and
//! opened by the crate with random names, whereas the HDF5 library must
//! create the file itself at a path and the documented name pattern above
//! is what tells a stray temporary's writer (process id); the guarantees
//! need only `rename` and `remove_file` from std.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// A file being written; see the module docs.
#[derive(Debug)]
pub struct AtomicFile {
    temp: PathBuf,
    dest: PathBuf,
    committed: bool,
}

impl AtomicFile {
    /// Prepare to write `dest`. The temporary is `.<name>.tmp-<pid>-<n>`
    /// beside it, `n` counting the files this process has begun, so that
    /// threads writing the same destination at once (parallel runs filling
    /// one cache entry) never share a temporary: each writes its own and
    /// the last rename wins with a complete file. (With one name per
    /// process, HDF5 refused the second thread's create: "unable to
    /// truncate a file which is already open".)
    pub fn new(dest: &Path) -> Self {
        Self::with_suffix(dest, "")
    }

    /// As [`AtomicFile::new`], the temporary ending in the destination's
    /// extension (`.<name>.tmp-<pid>-<n>.<ext>`), for writers that choose
    /// the format from the file name.
    pub fn keeping_extension(dest: &Path) -> Self {
        let suffix = dest
            .extension()
            .map(|e| format!(".{}", e.to_string_lossy()))
            .unwrap_or_default();
        Self::with_suffix(dest, &suffix)
    }

    fn with_suffix(dest: &Path, suffix: &str) -> Self {
        static BEGUN: AtomicU64 = AtomicU64::new(0);
        remove_stale_temporaries(dest);
        let name = dest
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "output".into());
        let n = BEGUN.fetch_add(1, Ordering::Relaxed);
        let temp = dest.with_file_name(format!(".{name}.tmp-{}-{n}{suffix}", std::process::id()));
        in_flight().push(temp.clone());
        Self {
            temp,
            dest: dest.to_path_buf(),
            committed: false,
        }
    }

    /// Where to write the content.
    pub fn temp_path(&self) -> &Path {
        &self.temp
    }

    /// The final destination.
    pub fn dest_path(&self) -> &Path {
        &self.dest
    }

    /// Move the finished temporary into place.
    pub fn commit(mut self) -> std::io::Result<()> {
        std::fs::rename(&self.temp, &self.dest)?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_file(&self.temp);
        }
        in_flight().retain(|t| *t != self.temp);
    }
}

/// The temporaries this process is writing.
fn in_flight() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    static IN_FLIGHT: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());
    // A poisoned list is still a list of paths.
    IN_FLIGHT.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes the temporaries this process is writing (and its output locks,
/// [`super::lock`]): for a binary's
/// SIGINT/SIGTERM handler, just before it exits (the outputs being written
/// are then incomplete and are not committed). Returns how many it removed.
pub fn remove_temporaries_in_flight() -> usize {
    let mut list = in_flight();
    let n = list
        .iter()
        .filter(|t| std::fs::remove_file(t).is_ok())
        .count();
    list.clear();
    n
}

/// List `path` among the files this process is writing, for
/// [`remove_temporaries_in_flight`] (a lock file, [`super::lock`]).
pub(crate) fn register_in_flight(path: &Path) {
    in_flight().push(path.to_path_buf());
}

/// No longer list `path` ([`register_in_flight`]).
pub(crate) fn unregister_in_flight(path: &Path) {
    in_flight().retain(|t| t != path);
}

/// Whether process `pid` is running (Linux: `/proc/<pid>`; elsewhere it is
/// assumed running, so that nothing of a live writer is removed).
pub(crate) fn process_running(pid: u32) -> bool {
    let proc_dir = Path::new("/proc");
    if !proc_dir.join("self").exists() {
        return true;
    }
    proc_dir.join(pid.to_string()).exists()
}

/// Removes the temporaries of `dest` (`.<name>.tmp-<pid>-<n>[.<ext>]`)
/// left by processes that are no longer running (killed mid-write).
/// Returns how many it removed; errors are ignored (another process may
/// be removing them too).
pub fn remove_stale_temporaries(dest: &Path) -> usize {
    let Some(name) = dest.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return 0;
    };
    let dir = match dest.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let prefix = format!(".{name}.tmp-");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return 0;
    };
    let mut removed = 0;
    for e in entries.flatten() {
        let file = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = file.strip_prefix(&prefix) else {
            continue;
        };
        let Some(pid) = rest.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        if pid != std::process::id()
            && !process_running(pid)
            && std::fs::remove_file(e.path()).is_ok()
        {
            removed += 1;
        }
    }
    removed
}

/// Why [`write_atomically`] failed; nothing was written at the
/// destination either way.
#[derive(Debug, thiserror::Error)]
pub enum AtomicWriteError<E> {
    /// The writer's own error.
    #[error(transparent)]
    Write(E),
    /// The finished temporary could not be renamed over the destination.
    #[error("cannot move the finished temporary '{temp}' to '{dest}': {source}")]
    Commit {
        temp: PathBuf,
        dest: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// Write `dest` atomically (module docs): `write` creates and fills the
/// file at the temporary path it is given; when it returns `Ok` the file is
/// renamed over `dest`, otherwise (or if it panics) the temporary is
/// removed.
pub fn write_atomically<T, E>(
    dest: &Path,
    write: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, AtomicWriteError<E>> {
    write_with(AtomicFile::new(dest), write)
}

/// [`write_atomically`] with a temporary that keeps the destination's
/// extension ([`AtomicFile::keeping_extension`]).
pub fn write_atomically_keeping_extension<T, E>(
    dest: &Path,
    write: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, AtomicWriteError<E>> {
    write_with(AtomicFile::keeping_extension(dest), write)
}

fn write_with<T, E>(
    file: AtomicFile,
    write: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, AtomicWriteError<E>> {
    let value = write(file.temp_path()).map_err(AtomicWriteError::Write)?;
    let (temp, dest) = (file.temp.clone(), file.dest.clone());
    file.commit()
        .map_err(|source| AtomicWriteError::Commit { temp, dest, source })?;
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uncommitted_file_leaves_nothing() {
        let dir = std::env::temp_dir().join(format!("atomic-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let dest = dir.join("a.h5");
        {
            let f = AtomicFile::new(&dest);
            std::fs::write(f.temp_path(), b"partial").unwrap();
        }
        assert!(!dest.exists());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        let f = AtomicFile::new(&dest);
        std::fs::write(f.temp_path(), b"done").unwrap();
        f.commit().unwrap();
        assert_eq!(std::fs::read(&dest).unwrap(), b"done");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn two_writers_of_one_destination_have_their_own_temporaries() {
        let dest = Path::new("/somewhere/table.h5");
        let (a, b) = (AtomicFile::new(dest), AtomicFile::new(dest));
        assert_ne!(a.temp_path(), b.temp_path());
        assert_eq!(a.dest_path(), b.dest_path());
        assert!(a.temp_path().to_string_lossy().contains(".table.h5.tmp-"));
    }

    #[test]
    fn write_atomically_commits_on_ok_and_cleans_up_on_err() {
        let dir = std::env::temp_dir().join(format!("atomic-fn-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let dest = dir.join("notes.txt");
        std::fs::write(&dest, b"old").unwrap();
        let e = write_atomically(&dest, |tmp| {
            std::fs::write(tmp, b"partial")?;
            Err::<(), _>(std::io::Error::other("the writer failed"))
        })
        .unwrap_err();
        assert!(matches!(e, AtomicWriteError::Write(_)), "{e}");
        assert_eq!(std::fs::read(&dest).unwrap(), b"old", "untouched");
        let n = write_atomically(&dest, |tmp| std::fs::write(tmp, b"new").map(|()| 7)).unwrap();
        assert_eq!(n, 7);
        assert_eq!(std::fs::read(&dest).unwrap(), b"new");
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "no temporary left"
        );
        // A destination whose directory does not exist: the writer's error.
        let e = write_atomically(&dir.join("no/such/dir.txt"), |tmp| {
            std::fs::write(tmp, b"x")
        });
        assert!(matches!(e, Err(AtomicWriteError::Write(_))));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_extension_can_be_kept() {
        let f = AtomicFile::keeping_extension(Path::new("/plots/chart.png"));
        let name = f.temp_path().file_name().unwrap().to_string_lossy();
        assert!(name.starts_with(".chart.png.tmp-"), "{name}");
        assert_eq!(f.temp_path().extension().unwrap(), "png");
        assert_eq!(f.temp_path().parent(), Some(Path::new("/plots")));
    }

    #[cfg(unix)]
    #[test]
    fn stale_temporaries_of_dead_processes_are_removed_by_the_next_write() {
        let d = std::env::temp_dir().join(format!("atomic-stale-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        let dest = d.join("run.h5");
        // A dead writer's (pid beyond any running one), a live writer's
        // (this process's parent), and another file's temporary.
        let dead = d.join(".run.h5.tmp-4294967295-0");
        let live = d.join(format!(
            ".run.h5.tmp-{}-3",
            std::os::unix::process::parent_id()
        ));
        let other = d.join(".other.h5.tmp-4294967295-0");
        for p in [&dead, &live, &other] {
            std::fs::write(p, b"partial").unwrap();
        }
        write_atomically(&dest, |tmp| std::fs::write(tmp, b"done")).unwrap();
        assert!(!dead.exists(), "the dead writer's temporary is removed");
        assert!(live.exists(), "a running writer's temporary is kept");
        assert!(other.exists(), "another destination's temporary is kept");
        assert_eq!(std::fs::read(&dest).unwrap(), b"done");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn temporaries_in_flight_are_listed_for_the_signal_handler() {
        let d = std::env::temp_dir().join(format!("atomic-flight-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        let f = AtomicFile::new(&d.join("big.h5"));
        std::fs::write(f.temp_path(), b"half").unwrap();
        assert!(in_flight().contains(&f.temp_path().to_path_buf()));
        let temp = f.temp_path().to_path_buf();
        assert!(remove_temporaries_in_flight() >= 1);
        assert!(!temp.exists());
        drop(f);
        assert!(!in_flight().contains(&temp));
        std::fs::remove_dir_all(&d).unwrap();
    }
}
