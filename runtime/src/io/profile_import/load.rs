//! Read a profile file and build the wheel or rail profile of the internal
//! convention ([`crate::geometry::profile`]) from it, in one call.

use std::path::Path;

use super::{ImportOptions, ProfileImportError, ProfileKind, read_profile};
use crate::geometry::profile::{
    ProfileError, RailProfile, RailProfileOptions, WheelProfile, WheelProfileOptions,
};

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
) -> Result<WheelProfile, ProfileLoadError> {
    let file = read_profile(path, import)?;
    check_kind(path, file.kind, ProfileKind::Wheel)?;
    Ok(WheelProfile::from_points(
        path,
        &file.points_m,
        file.z_down,
        options,
    )?)
}

/// Load a rail profile file.
pub fn load_rail(
    path: &Path,
    import: &ImportOptions,
    options: RailProfileOptions,
) -> Result<RailProfile, ProfileLoadError> {
    let file = read_profile(path, import)?;
    check_kind(path, file.kind, ProfileKind::Rail)?;
    Ok(RailProfile::from_points(
        path,
        &file.points_m,
        file.z_down,
        options,
    )?)
}
