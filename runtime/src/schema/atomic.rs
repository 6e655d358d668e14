//! Atomic creation of an output file: write under a temporary name in the
//! same directory, rename over the destination when complete. Dropping an
//! uncommitted [`AtomicFile`] deletes the temporary, so an error leaves
//! nothing behind (SPEC §2).

use std::path::{Path, PathBuf};

/// A file being written; see the module docs.
#[derive(Debug)]
pub struct AtomicFile {
    temp: PathBuf,
    dest: PathBuf,
    committed: bool,
}

impl AtomicFile {
    /// Prepare to write `dest`. The temporary is `.<name>.tmp-<pid>` beside it.
    pub fn new(dest: &Path) -> Self {
        let name = dest
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "output".into());
        let temp = dest.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
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
}
