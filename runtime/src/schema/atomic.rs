//! Atomic creation of an output file: write under a temporary name in the
//! same directory, rename over the destination when complete. Dropping an
//! uncommitted [`AtomicFile`] deletes the temporary, so an error leaves
//! nothing behind (SPEC §2).

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
        static BEGUN: AtomicU64 = AtomicU64::new(0);
        let name = dest
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "output".into());
        let n = BEGUN.fetch_add(1, Ordering::Relaxed);
        let temp = dest.with_file_name(format!(".{name}.tmp-{}-{n}", std::process::id()));
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
    }
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
}
