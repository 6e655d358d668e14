//! Read a profile file and build the wheel or rail profile of the internal
//! convention ([`crate::geometry::profile`]) from it, in one call. The
//! result carries the warnings of the build ([`Loaded::warnings`]) for the
//! caller to show: a profile cut to its longest usable stretch
//! (`keep_longest_stretch`) names every line it dropped.

use std::path::Path;

use super::{ImportOptions, ProfileImportError, ProfileKind, read_profile};
use crate::geometry::profile::{
    ProfileError, ProfileWarning, RailProfile, RailProfileOptions, WheelProfile,
    WheelProfileOptions,
};

/// A profile loaded from its file, with the warnings the caller must show
/// (print them, or put them in its summary).
#[derive(Debug, Clone, PartialEq)]
#[must_use = "a loaded profile carries warnings to show"]
pub struct Loaded<P> {
    pub profile: P,
    /// What the build dropped and why (empty for a profile built from all
    /// its usable points).
    pub warnings: Vec<ProfileWarning>,
}

/// Why a profile could not be loaded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileLoadError {
    #[error(transparent)]
    Import(#[from] ProfileImportError),
    #[error(transparent)]
    Profile(#[from] ProfileError),
    #[error("{path}: this is a {found} profile, a {wanted} profile was expected")]
    WrongKind {
        path: std::path::PathBuf,
        found: &'static str,
        wanted: &'static str,
    },
}

fn kind_name(k: ProfileKind) -> &'static str {
    match k {
        ProfileKind::Wheel => "wheel",
        ProfileKind::Rail => "rail",
    }
}

fn check_kind(
    path: &Path,
    found: Option<ProfileKind>,
    wanted: ProfileKind,
) -> Result<(), ProfileLoadError> {
    match found {
        Some(k) if k != wanted => Err(ProfileLoadError::WrongKind {
            path: path.to_path_buf(),
            found: kind_name(k),
            wanted: kind_name(wanted),
        }),
        _ => Ok(()),
    }
}

/// Load a wheel profile file.
pub fn load_wheel(
    path: &Path,
    import: &ImportOptions,
    options: WheelProfileOptions,
) -> Result<Loaded<WheelProfile>, ProfileLoadError> {
    let file = read_profile(path, import)?;
    check_kind(path, file.kind, ProfileKind::Wheel)?;
    let profile =
        WheelProfile::from_points(path, &file.points_m, &file.lines, file.z_down, options)?;
    Ok(Loaded {
        warnings: profile.warnings().to_vec(),
        profile,
    })
}

/// Load a rail profile file.
pub fn load_rail(
    path: &Path,
    import: &ImportOptions,
    options: RailProfileOptions,
) -> Result<Loaded<RailProfile>, ProfileLoadError> {
    let file = read_profile(path, import)?;
    check_kind(path, file.kind, ProfileKind::Rail)?;
    let profile =
        RailProfile::from_points(path, &file.points_m, &file.lines, file.z_down, options)?;
    Ok(Loaded {
        warnings: profile.warnings().to_vec(),
        profile,
    })
}
