//! Building the contact lookup table of a wheel/rail profile pair (docs/reference/04-table-files.md §4):
//! the wheelset settled on straight track at every lateral shift (and yaw)
//! of a grid — rigidly, or elastically under a wheel load — with its contact
//! points, radii, angles, penetrations, curvatures, roll and height, the
//! rolling radius difference Δr(y), and its EN 15302 equivalent conicity.

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use runtime::contact::quasi_static::{Settled, Support, level_wheel_contacts, settle};
use runtime::contact::table::{
    ConicityTable, ContactTable, ContactTableMeta, ContactTableRow, ZoneEntry,
};
use runtime::contact::{
    Candidate, ContactError, ContactOptions, ContactSolver, FlangeSearch, WheelsetContactModel,
};
use runtime::forces::hertz::Material;
use runtime::geometry::profile::rail_cant::{
    RailCantCheck, RailCantError, Spelling, check_rail_file,
};
use runtime::geometry::profile::{
    ProfileWarning, RailPlacement, RailProfileOptions, WheelProfileOptions, Zone,
};
use runtime::geometry::spline::Scheme;
use runtime::geometry::track::{Side, straight_track};
use runtime::io::profile_import::{ImportOptions, ProfileLoadError, load_rail, load_wheel};

use crate::conicity::{ConicitySummary, DeltaRFunction};
use crate::progress::{Progress, ProgressSink};

/// Default vertical load per wheel for elastic tables (N): a 10 t axle.
pub const DEFAULT_WHEEL_LOAD_N: f64 = 49_050.0;

/// How the wheelset rests in the table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TableSupport {
    /// Rigid contact: both wheels just touch.
    Rigid,
    /// Hertzian contact, each wheel carrying `wheel_load_n` vertically.
    Elastic {
        wheel_load_n: f64,
        material: Material,
    },
}

/// What a contact table is built from.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactTableConfig {
    /// Wheel and rail profile files (SIMPACK, plain columns or CSV).
    pub wheel_profile: PathBuf,
    pub rail_profile: PathBuf,
    /// Spline scheme of the profile functions.
    pub profile_scheme: Scheme,
    /// Nominal rolling radius at the taping line (m).
    pub wheel_radius_m: f64,
    /// A different right wheel (profile and/or radius; EN 15302 cases E5–E9);
    /// `None` = the same as the left.
    pub right_wheel_profile: Option<PathBuf>,
    pub right_wheel_radius_m: Option<f64>,
    /// Back-to-back distance of the wheels (m).
    pub back_to_back_m: f64,
    /// Track gauge (m), rail spacing (m), rail inclination (rad).
    pub gauge_m: f64,
    pub rail_spacing_m: f64,
    pub rail_inclination_rad: f64,
    /// The cant the rail profile file carries as drawn, declared by the
    /// user (rad; `--rail-profile-cant`); `None`: detected from the file
    /// (`runtime::geometry::profile::rail_cant`).
    pub rail_profile_cant_rad: Option<f64>,
    /// Lateral shifts: from `y_min_m` to `y_max_m` every `y_step_m` (m).
    pub y_min_m: f64,
    pub y_max_m: f64,
    pub y_step_m: f64,
    /// Yaw angles (rad); `[0]` for the classic table.
    pub yaw_rad: Vec<f64>,
    pub support: TableSupport,
    /// Keep the longest usable stretch of a profile that folds back,
    /// repeats its lateral coordinate or breaks inside, instead of refusing
    /// it (`--keep-longest-stretch`); [`Self::model`] then returns a warning
    /// naming the dropped lines (docs/reference/05-surfaces.md §5.3).
    pub keep_longest_stretch: bool,
}

impl Default for ContactTableConfig {
    fn default() -> Self {
        Self {
            wheel_profile: PathBuf::new(),
            rail_profile: PathBuf::new(),
            profile_scheme: Scheme::Cubic,
            wheel_radius_m: 0.46,
            right_wheel_profile: None,
            right_wheel_radius_m: None,
            back_to_back_m: 1.360,
            gauge_m: 1.435,
            rail_spacing_m: 1.507,
            rail_inclination_rad: 0.0,
            rail_profile_cant_rad: None,
            y_min_m: -0.015,
            y_max_m: 0.015,
            y_step_m: 1e-4,
            yaw_rad: vec![0.0],
            support: TableSupport::Elastic {
                wheel_load_n: DEFAULT_WHEEL_LOAD_N,
                material: Material::default(),
            },
            keep_longest_stretch: false,
        }
    }
}

/// Why a contact table could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ContactTableBuildError {
    #[error("invalid contact-table option: {0}")]
    Config(String),
    #[error(transparent)]
    Profile(#[from] ProfileLoadError),
    #[error(transparent)]
    RailCant(#[from] RailCantError),
    #[error("{0}")]
    Model(String),
    #[error(
        "the wheelset cannot be settled at y = {y_mm:.2} mm, yaw = {yaw_mrad:.1} mrad: {source}"
    )]
    Settle {
        y_mm: f64,
        yaw_mrad: f64,
        #[source]
        source: ContactError,
    },
}

impl ContactTableConfig {
    /// Check every rule; the message names the option.
    pub fn validate(&self) -> Result<(), ContactTableBuildError> {
        let fail = |m: String| Err(ContactTableBuildError::Config(m));
        if !(self.wheel_radius_m > 0.1 && self.wheel_radius_m < 1.5) {
            return fail(format!(
                "--wheel-radius {} m must lie in 0.1 … 1.5 m",
                self.wheel_radius_m
            ));
        }
        if !(self.back_to_back_m > 0.5 && self.back_to_back_m < 2.5) {
            return fail(format!(
                "--back-to-back {} m must lie in 0.5 … 2.5 m",
                self.back_to_back_m
            ));
        }
        if !(self.y_step_m > 0.0 && self.y_step_m <= 0.005) {
            return fail(format!(
                "--y-step {} m must lie in (0, 5 mm]",
                self.y_step_m
            ));
        }
        if !(self.y_min_m < 0.0 && self.y_max_m > 0.0 && self.y_max_m - self.y_min_m <= 0.1) {
            return fail(format!(
                "the lateral range {} … {} m must contain 0 and span at most 100 mm",
                self.y_min_m, self.y_max_m
            ));
        }
        if self.yaw_rad.is_empty()
            || self.yaw_rad.iter().any(|y| !y.is_finite() || y.abs() > 0.1)
            || !self.yaw_rad.windows(2).all(|w| w[1] > w[0])
        {
            return fail("yaw angles must be increasing and within ±100 mrad".into());
        }
        if let TableSupport::Elastic {
            wheel_load_n,
            material,
        } = self.support
        {
            if !(wheel_load_n > 0.0 && wheel_load_n < 1e6) {
                return fail(format!(
                    "--wheel-load-n {wheel_load_n} must lie in (0, 1e6) N"
                ));
            }
            material
                .validate()
                .map_err(|e| ContactTableBuildError::Config(e.to_string()))?;
        }
        Ok(())
    }

    /// The lateral grid (m), symmetric about 0 when the range is.
    pub fn y_grid(&self) -> Vec<f64> {
        let lo = (self.y_min_m / self.y_step_m - 1e-9).ceil() as i64;
        let hi = (self.y_max_m / self.y_step_m + 1e-9).floor() as i64;
        (lo..=hi).map(|k| k as f64 * self.y_step_m).collect()
    }

    /// The rail profile checked against the rail inclination (double
    /// canting refused, `runtime::geometry::profile::rail_cant::check_rail_cant`),
    /// with its record and warnings; messages name the command-line options.
    pub fn check_rail(&self) -> Result<RailCantCheck, ContactTableBuildError> {
        Ok(check_rail_file(
            &self.rail_profile,
            self.rail_profile_cant_rad,
            self.rail_inclination_rad,
            Spelling::CommandLine,
        )?)
    }

    /// Load the profiles and assemble the wheelset's contact model (a rail
    /// profile canted twice is refused, [`Self::check_rail`]); with it the
    /// warnings of the profiles (one per profile cut to its longest usable
    /// stretch), which the caller must show.
    pub fn model(
        &self,
    ) -> Result<(WheelsetContactModel, Vec<ProfileWarning>), ContactTableBuildError> {
        let wheel = |path: &Path, radius: f64| {
            load_wheel(
                path,
                &ImportOptions::default(),
                WheelProfileOptions {
                    scheme: self.profile_scheme,
                    nominal_radius_m: radius,
                    keep_longest_stretch: self.keep_longest_stretch,
                    ..Default::default()
                },
            )
        };
        let left = wheel(&self.wheel_profile, self.wheel_radius_m)?;
        let right_path = self.right_wheel_profile.as_deref();
        let right = wheel(
            right_path.unwrap_or(&self.wheel_profile),
            self.right_wheel_radius_m.unwrap_or(self.wheel_radius_m),
        )?;
        let rail = load_rail(
            &self.rail_profile,
            &ImportOptions::default(),
            RailProfileOptions {
                scheme: self.profile_scheme,
                keep_longest_stretch: self.keep_longest_stretch,
                ..Default::default()
            },
        )?;
        self.check_rail()?;
        // The same wheel file twice warns once.
        let mut warnings = left.warnings;
        if right_path.is_some_and(|p| p != self.wheel_profile) {
            warnings.extend(right.warnings);
        }
        warnings.extend(rail.warnings);
        let (left, right, rail) = (left.profile, right.profile, rail.profile);
        let model = WheelsetContactModel::new(
            left,
            right,
            self.back_to_back_m,
            &rail,
            &rail,
            RailPlacement {
                gauge_m: self.gauge_m,
                rail_spacing_m: self.rail_spacing_m,
                inclination_rad: self.rail_inclination_rad,
            },
        )
        .map_err(|e| ContactTableBuildError::Model(e.to_string()))?;
        Ok((model, warnings))
    }
}

/// The entry of a candidate, with its normal force.
fn entry(c: &Candidate, normal_force_n: f64) -> ZoneEntry {
    ZoneEntry {
        y_wheel_m: c.wheel_profile_point_m.0,
        z_wheel_m: c.wheel_profile_point_m.1,
        y_rail_m: c.rail_profile_point_m.0,
        z_rail_m: c.rail_profile_point_m.1,
        rolling_radius_m: c.rolling_radius_m,
        contact_angle_rad: c.contact_angle_rad,
        penetration_m: c.penetration_m,
        wheel_rolling_curvature_1_m: c.curvatures.wheel_rolling_1_m,
        wheel_lateral_curvature_1_m: c.curvatures.wheel_lateral_1_m,
        rail_rolling_curvature_1_m: c.curvatures.rail_rolling_1_m,
        rail_lateral_curvature_1_m: c.curvatures.rail_lateral_1_m,
        normal_force_n,
        s_wheel_rad: c.params.s_wheel_rad,
        lead_m: c.lead_m(),
    }
}

/// A table row from a settled wheelset: per wheel and zone, the candidate
/// carrying the most load (elastic) or the deepest (rigid).
fn row(y_m: f64, yaw_rad: f64, st: &Settled) -> ContactTableRow {
    let mut zones = [[None; 2]; 2];
    for (w, side) in Side::BOTH.into_iter().enumerate() {
        for (z, zone) in Zone::BOTH.into_iter().enumerate() {
            let best = st.contacts.candidates[w]
                .iter()
                .zip(&st.normal_force_n[w])
                .filter_map(|(c, f)| c.as_ref().map(|c| (c, *f)))
                .filter(|(c, _)| c.zone == zone && c.side == side)
                .max_by(|a, b| {
                    a.1.total_cmp(&b.1)
                        .then(a.0.penetration_m.total_cmp(&b.0.penetration_m))
                });
            zones[w][z] = best.map(|(c, f)| entry(c, f));
        }
    }
    ContactTableRow {
        y_m,
        yaw_rad,
        height_m: st.height_m,
        roll_rad: st.roll_rad,
        delta_r_m: st.rolling_radius_difference_m().unwrap_or(f64::NAN),
        zones,
    }
}

/// Build the table for `model` (see [`ContactTableConfig::model`]).
pub fn build_contact_table(
    model: &WheelsetContactModel,
    config: &ContactTableConfig,
    progress: &dyn ProgressSink,
) -> Result<ContactTable, ContactTableBuildError> {
    config.validate()?;
    let rail = config.check_rail()?;
    let y = config.y_grid();
    let zero = y
        .iter()
        .position(|v| v.abs() < 0.5 * config.y_step_m)
        .ok_or_else(|| ContactTableBuildError::Config("the lateral grid misses y = 0".into()))?;
    let track = straight_track(
        4.0,
        0.1,
        config.gauge_m,
        config.rail_spacing_m,
        config.rail_inclination_rad,
    );
    let support = match config.support {
        TableSupport::Rigid => Support::Rigid,
        TableSupport::Elastic {
            wheel_load_n,
            material,
        } => Support::Elastic {
            load_per_wheel_n: wheel_load_n,
            material,
        },
    };
    progress.event(Progress::Stage {
        name: "contact table",
        rows: (y.len() * config.yaw_rad.len()) as u64,
    });
    // Each yaw is a continuation from y = 0 outwards, in both directions.
    let columns: Vec<Vec<ContactTableRow>> = config
        .yaw_rad
        .par_iter()
        .map(|&yaw| {
            let mut col = vec![ContactTableRow::default(); y.len()];
            let directions: [Vec<usize>; 2] =
                [(zero..y.len()).collect(), (0..=zero).rev().collect()];
            for order in directions {
                for i in order {
                    // A cold start per row: the search of every piece finds
                    // all its candidates and keeps the deepest, so a jump of
                    // the contact (to the flange root of a hollow tread, say)
                    // is not missed, as continuation from the previous row
                    // would (it follows one contact point continuously).
                    let mut solver = ContactSolver::new(ContactOptions {
                        flange: FlangeSearch::On,
                        ..Default::default()
                    });
                    let st = settle(model, &track, 2.0, y[i], yaw, support, &mut solver).map_err(
                        |source| ContactTableBuildError::Settle {
                            y_mm: y[i] * 1e3,
                            yaw_mrad: yaw * 1e3,
                            source,
                        },
                    )?;
                    col[i] = row(y[i], yaw, &st);
                    progress.event(Progress::Rows(1));
                }
            }
            Ok(col)
        })
        .collect::<Result<_, ContactTableBuildError>>()?;
    let n_yaw = config.yaw_rad.len();
    let rows = (0..y.len())
        .flat_map(|i| columns.iter().map(move |c| c[i]).collect::<Vec<_>>())
        .collect::<Vec<_>>();
    debug_assert_eq!(rows.len(), y.len() * n_yaw);
    let (material, load) = match config.support {
        TableSupport::Rigid => (Material::default(), 0.0),
        TableSupport::Elastic {
            wheel_load_n,
            material,
        } => (material, wheel_load_n),
    };
    let mut table = ContactTable {
        meta: ContactTableMeta {
            wheel_profile: config.wheel_profile.display().to_string(),
            rail_profile: config.rail_profile.display().to_string(),
            wheel_radius_m: config.wheel_radius_m,
            back_to_back_m: config.back_to_back_m,
            gauge_m: config.gauge_m,
            rail_spacing_m: config.rail_spacing_m,
            rail_inclination_rad: config.rail_inclination_rad,
            rail_record: Some(rail.record),
            support: match config.support {
                TableSupport::Rigid => "rigid".into(),
                TableSupport::Elastic { .. } => "elastic".into(),
            },
            wheel_load_n: load,
            young_pa: material.young_pa,
            poisson: material.poisson,
            source: "track-preproc".into(),
        },
        y_m: y,
        yaw_rad: config.yaw_rad.clone(),
        rows,
        conicity: ConicityTable::default(),
    };
    let level = en15302_delta_r(model, config, &table.y_m)?;
    let summary = ConicitySummary::new(&level);
    table.conicity = ConicityTable {
        amplitude_m: summary.amplitude_mm.iter().map(|a| a * 1e-3).collect(),
        tan_gamma_e: summary
            .tan_gamma_e
            .iter()
            .map(|t| t.unwrap_or(f64::NAN))
            .collect(),
        level_y_m: level.y_m().to_vec(),
        level_delta_r_m: level.delta_r_m().to_vec(),
    };
    Ok(table)
}

/// |Δr| below this is round-off of identical radii (m).
const DELTA_R_ROUND_OFF_M: f64 = 1e-9;

/// The rolling radius difference Δr(y) = r_left − r_right of EN 15302's
/// idealised wheelset on the lateral grid `y_m`: kept level (no roll), each
/// wheel lowered separately onto its rail (rigid contact), zero yaw — the
/// conditions of the standard's reference results, which neglect the
/// wheelset's roll (a rolling wheelset tilts its profiles by φ and moves the
/// jumps of the contact point by 0.1–0.4 mm). Each lateral shift starts
/// cold, so every jump of the contact is found. |Δr| below 1 nm is taken as
/// 0 (identical radii), so round-off cannot create spurious centres.
pub fn en15302_delta_r(
    model: &WheelsetContactModel,
    config: &ContactTableConfig,
    y_m: &[f64],
) -> Result<DeltaRFunction, ContactTableBuildError> {
    let track = straight_track(
        4.0,
        0.1,
        config.gauge_m,
        config.rail_spacing_m,
        config.rail_inclination_rad,
    );
    let dr: Vec<f64> = y_m
        .par_iter()
        .map(|&y| {
            let mut solver = ContactSolver::new(ContactOptions::default());
            let c = level_wheel_contacts(model, &track, 2.0, y, 0.0, &mut solver).map_err(
                |source| ContactTableBuildError::Settle {
                    y_mm: y * 1e3,
                    yaw_mrad: 0.0,
                    source,
                },
            )?;
            let d = c[0].rolling_radius_m - c[1].rolling_radius_m;
            Ok(if d.abs() < DELTA_R_ROUND_OFF_M {
                0.0
            } else {
                d
            })
        })
        .collect::<Result<_, ContactTableBuildError>>()?;
    DeltaRFunction::new(y_m.to_vec(), dr)
        .map_err(|e| ContactTableBuildError::Model(format!("EN 15302 Δr function: {e}")))
}

/// EN 15302 equivalent conicity (1…6 mm) of a table, from the level
/// wheelset's Δr stored with it (see [`en15302_delta_r`]).
pub fn conicity_of(table: &ContactTable) -> ConicitySummary {
    let c = &table.conicity;
    match DeltaRFunction::new(c.level_y_m.clone(), c.level_delta_r_m.clone()) {
        Ok(f) => ConicitySummary::new(&f),
        Err(_) => ConicitySummary::empty(),
    }
}

/// The profile file paths of a config, for provenance.
pub fn profile_paths(config: &ContactTableConfig) -> [(&'static str, &Path); 2] {
    [
        ("wheel_profile", config.wheel_profile.as_path()),
        ("rail_profile", config.rail_profile.as_path()),
    ]
}
