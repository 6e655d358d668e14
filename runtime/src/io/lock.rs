//! A lock on an output made of several files (a run's results file and
//! its plots, docs/guide/run-a-scene.md "What is written when"): each file
//! is written atomically ([`crate::io::atomic`]), but two processes
//! writing the same outputs at once would leave the results of one and
//! the plots of the other. The first to take the lock writes; the second
//! is refused at once, before any work, naming the first's process id.
//!
//! The lock is a file `.<name>.lock` beside the output holding the
//! owner's process id, created with `create_new` (atomic on local file
//! systems). It is removed when the [`OutputLock`] is dropped, and by a
//! binary's SIGINT/SIGTERM handler ([`super::remove_temporaries_in_flight`]);
//! a lock left by a process that is no longer running (kill -9) is
//! removed by the next taker.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Why a lock could not be taken.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    #[error(
        "{} is being written by another process (PID {pid}; lock file {}): wait for it to finish or choose another output",
        output.display(),
        lock.display()
    )]
    Busy {
        output: PathBuf,
        pid: u32,
        lock: PathBuf,
    },
    #[error("cannot create the lock file {}: {source}", lock.display())]
    Io {
        lock: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// A taken lock on an output; see the module docs.
#[derive(Debug)]
pub struct OutputLock {
    lock: PathBuf,
}

/// The lock file of `output`: `.<name>.lock` in its directory.
pub fn lock_path(output: &Path) -> PathBuf {
    let name = output
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    output.with_file_name(format!(".{name}.lock"))
}

impl OutputLock {
    /// Take the lock of `output` (see the module docs).
    pub fn acquire(output: &Path) -> Result<Self, LockError> {
        let lock = lock_path(output);
        let io = |source| LockError::Io {
            lock: lock.clone(),
            source,
        };
        // Twice at most: a stale lock is removed and the create retried.
        for _ in 0..2 {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&lock)
            {
                Ok(mut f) => {
                    super::atomic::register_in_flight(&lock);
                    let taken = Self { lock: lock.clone() };
                    write!(f, "{}", std::process::id()).map_err(io)?;
                    return Ok(taken);
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let owner = std::fs::read_to_string(&lock)
                        .ok()
                        .and_then(|s| s.trim().parse::<u32>().ok());
                    match owner {
                        Some(pid) if super::atomic::process_running(pid) => {
                            return Err(LockError::Busy {
                                output: output.to_path_buf(),
                                pid,
                                lock,
                            });
                        }
                        // A dead owner's lock, or one being written this
                        // instant (no id yet): a dead owner's is removed.
                        Some(_) => {
                            let _ = std::fs::remove_file(&lock);
                        }
                        None => {
                            return Err(LockError::Busy {
                                output: output.to_path_buf(),
                                pid: 0,
                                lock,
                            });
                        }
                    }
                }
                Err(e) => return Err(io(e)),
            }
        }
        Err(io(std::io::Error::other(
            "a stale lock file came back after it was removed",
        )))
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.lock);
        super::atomic::unregister_in_flight(&self.lock);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("lock-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_second_taker_is_refused_until_the_first_lets_go() {
        let dir = scratch("second");
        let out = dir.join("run.h5");
        let first = OutputLock::acquire(&out).unwrap();
        assert_eq!(
            std::fs::read_to_string(lock_path(&out)).unwrap(),
            std::process::id().to_string()
        );
        match OutputLock::acquire(&out) {
            Err(LockError::Busy { pid, .. }) => assert_eq!(pid, std::process::id()),
            other => panic!("expected Busy, got {other:?}"),
        }
        drop(first);
        assert!(!lock_path(&out).exists());
        let again = OutputLock::acquire(&out).unwrap();
        drop(again);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_dead_owners_lock_is_taken_over() {
        let dir = scratch("stale");
        let out = dir.join("run.h5");
        // No process has this id (above Linux's pid_max limit of 2^22).
        std::fs::write(lock_path(&out), "4194304999").unwrap();
        if Path::new("/proc/self").exists() {
            let taken = OutputLock::acquire(&out).unwrap();
            drop(taken);
            assert!(!lock_path(&out).exists());
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
