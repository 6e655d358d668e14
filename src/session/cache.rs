//! The on-demand table cache: track tables built from a scene's CSV inputs
//! and contact lookup tables built for a wheel/rail pair are kept, keyed by
//! a hash of everything they are built from (input texts, settings, tool
//! version), so a scene runs with one command and the second run skips the
//! build. The flangeway clearances (`super::flange_clearance`) and the
//! planner's track facts (`super::plan`) are kept the same way.
//!
//! Location: `$RAILSIM_CACHE_DIR`, else `$XDG_CACHE_HOME/railsim`, else
//! `$HOME/.cache/railsim`, else `<temp dir>/railsim-cache`. Files are
//! written atomically by the builders, so an interrupted build leaves no
//! partial entry; deleting the directory is always safe.

use std::path::PathBuf;

use anyhow::{Context, Result};

/// FNV-1a, 64 bit (Fowler–Noll–Vo): a stable, dependency-free hash for
/// cache keys (std's `DefaultHasher` is not stable across Rust releases).
#[derive(Debug, Clone, Copy)]
pub struct Fnv64(u64);

impl Default for Fnv64 {
    fn default() -> Self {
        Fnv64(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv64 {
    /// Feeds bytes, then a separator so that ("ab", "c") ≠ ("a", "bc").
    pub fn write(&mut self, bytes: &[u8]) -> &mut Self {
        for b in bytes.iter().chain(&[0xff]) {
            self.0 ^= u64::from(*b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
        self
    }

    pub fn write_str(&mut self, s: &str) -> &mut Self {
        self.write(s.as_bytes())
    }

    pub fn finish(&self) -> u64 {
        self.0
    }
}

/// The cache directory (module docs), created if missing.
pub fn cache_dir() -> Result<PathBuf> {
    let dir = if let Some(d) = std::env::var_os("RAILSIM_CACHE_DIR") {
        PathBuf::from(d)
    } else if let Some(d) = std::env::var_os("XDG_CACHE_HOME") {
        PathBuf::from(d).join("railsim")
    } else if let Some(h) = std::env::var_os("HOME") {
        PathBuf::from(h).join(".cache").join("railsim")
    } else {
        std::env::temp_dir().join("railsim-cache")
    };
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("creating the table cache {}", dir.display()))?;
    Ok(dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv_is_stable_and_separates_fields() {
        // Reference value of FNV-1a 64 for "a" (no separator): af63dc4c8601ec8c.
        let mut h = Fnv64::default();
        h.0 ^= u64::from(b'a');
        h.0 = h.0.wrapping_mul(0x0000_0100_0000_01b3);
        assert_eq!(h.finish(), 0xaf63_dc4c_8601_ec8c);
        let a = Fnv64::default().write_str("ab").write_str("c").finish();
        let b = Fnv64::default().write_str("a").write_str("bc").finish();
        assert_ne!(a, b);
        assert_eq!(a, Fnv64::default().write_str("ab").write_str("c").finish());
    }
}
