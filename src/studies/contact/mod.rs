//! `sim contact`: a wheelset's contacts and forces at prescribed poses on a
//! straight track, without building a table file
//! (docs/guide/contact-benchmark.md): the quasi-static evaluator of
//! [`runtime::multibody::loaded_wheelset`] — the height (and the roll
//! when it is not given) solved so that each wheel carries its vertical
//! load, every patch with its Hertz ellipse, creepages and creep forces —
//! for one pose or a file of poses (the Manchester contact benchmark's
//! set-up); or rigid contact (both wheels just touching, no forces).

pub mod poses;
mod report;
mod rows;

use anyhow::{Context, Result};
use preproc::contact_table::{ContactTableConfig, TableSupport};
use runtime::contact::quasi_static::{Support, settle};
use runtime::contact::{ContactOptions, ContactSolver, FlangeSearch, WheelsetContactModel};
use runtime::forces::hertz::Material;
use runtime::geometry::track::{Side, TrackTables, straight_track};
use runtime::multibody::contact_force::ContactForceSettings;
use runtime::multibody::loaded_wheelset::{
    LoadConvention, PatchLocation, PoseInput, solve_loaded_pose_at,
};

pub use poses::{PoseRow, read_poses};
pub use report::{ContactCase, ContactReport, ForceModelReport, WheelReport, WheelsetReport};
pub use rows::{CSV_COLUMNS, PatchRow, patch_rows, rows_csv, rows_table};

/// The wheelset's motion and the force models of `sim contact`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rolling {
    /// Forward speed along the track (m/s) of the poses that do not give
    /// their own.
    pub speed_m_s: f64,
    pub settings: ContactForceSettings,
    /// What the vertical load per wheel balances.
    pub convention: LoadConvention,
    /// Where each patch is located (its centre or its deepest point).
    pub location: PatchLocation,
}

/// One pose to evaluate (SI units; see [`PoseInput`] for the signs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseRequest {
    /// The pose's number in the output.
    pub case: u32,
    pub y_m: f64,
    pub yaw_rad: f64,
    pub roll_rad: Option<f64>,
    pub axle_rate_rad_s: Option<f64>,
    /// Forward speed (m/s); `None`: [`Rolling::speed_m_s`].
    pub speed_m_s: Option<f64>,
    /// Vertical force per wheel (N); `None`: the configuration's load.
    pub load_n: Option<f64>,
}

impl From<&PoseRow> for PoseRequest {
    fn from(r: &PoseRow) -> Self {
        PoseRequest {
            case: r.case,
            y_m: r.y_m,
            yaw_rad: r.yaw_rad,
            roll_rad: r.roll_rad,
            axle_rate_rad_s: r.axle_rate_rad_s,
            speed_m_s: r.speed_m_s,
            load_n: r.load_n,
        }
    }
}

/// Track section where the wheelset is placed on the in-memory track (m).
pub(crate) const S_WHEELSET_M: f64 = 5.0;

/// The profiles placed on an in-memory straight track, built once for any
/// number of poses.
pub struct ContactSetup {
    pub config: ContactTableConfig,
    pub model: WheelsetContactModel,
    pub track: TrackTables,
    /// Warnings of the profiles (what `--keep-longest-stretch` dropped).
    pub warnings: Vec<String>,
}

impl ContactSetup {
    /// Read the profiles of `config` and place them.
    pub fn new(config: &ContactTableConfig) -> Result<Self> {
        config.validate()?;
        let (model, warnings) = config.model()?;
        let track = straight_track(
            2.0 * S_WHEELSET_M,
            0.1,
            config.gauge_m,
            config.rail_spacing_m,
            config.rail_inclination_rad,
        );
        Ok(Self {
            config: config.clone(),
            model,
            track,
            warnings: warnings.iter().map(ToString::to_string).collect(),
        })
    }

    /// A contact solver for this set-up (flange always searched).
    pub fn solver(&self) -> ContactSolver {
        ContactSolver::new(ContactOptions {
            flange: FlangeSearch::On,
            ..Default::default()
        })
    }

    /// Evaluate one pose.
    pub fn evaluate(
        &self,
        solver: &mut ContactSolver,
        rolling: &Rolling,
        request: &PoseRequest,
    ) -> Result<ContactCase> {
        let speed_m_s = request.speed_m_s.unwrap_or(rolling.speed_m_s);
        if !(speed_m_s.is_finite() && speed_m_s >= 0.0) {
            anyhow::bail!("speed must be finite and >= 0 m/s, got {speed_m_s}");
        }
        let context = || {
            format!(
                "pose {}: y = {:.2} mm, yaw = {:.2} mrad",
                request.case,
                request.y_m * 1e3,
                request.yaw_rad * 1e3
            )
        };
        match self.config.support {
            TableSupport::Rigid => {
                if request.roll_rad.is_some() || request.load_n.is_some() {
                    anyhow::bail!(
                        "{}: rigid contact solves the roll and carries no load; a prescribed roll or load needs elastic contact",
                        context()
                    );
                }
                let st = settle(
                    &self.model,
                    &self.track,
                    S_WHEELSET_M,
                    request.y_m,
                    request.yaw_rad,
                    Support::Rigid,
                    solver,
                )
                .with_context(context)?;
                Ok(report::rigid_case(self, request, rolling, speed_m_s, &st))
            }
            TableSupport::Elastic { wheel_load_n, .. } => {
                let load = request.load_n.unwrap_or(wheel_load_n);
                let input = PoseInput {
                    s_m: S_WHEELSET_M,
                    y_m: request.y_m,
                    yaw_rad: request.yaw_rad,
                    roll_rad: request.roll_rad,
                    axle_rate_rad_s: request.axle_rate_rad_s,
                    speed_m_s,
                    load_per_wheel_n: [load, load],
                };
                let loaded = solve_loaded_pose_at(
                    &self.model,
                    &self.track,
                    solver,
                    &rolling.settings,
                    &input,
                    rolling.convention,
                    rolling.location,
                )
                .with_context(context)?;
                Ok(report::loaded_case(self, request, rolling, &loaded))
            }
        }
    }

    /// Nominal rolling radius of a side (m).
    pub fn nominal_radius_m(&self, side: Side) -> f64 {
        self.model.wheel(side).nominal_radius_m()
    }
}

/// One pose of `config` (profiles, gauge, inclination, support) with the
/// wheelset rolling as `rolling` says.
pub fn contact_case(
    config: &ContactTableConfig,
    request: &PoseRequest,
    rolling: &Rolling,
) -> Result<ContactCase> {
    rolling.settings.validate()?;
    let setup = ContactSetup::new(config)?;
    let mut solver = setup.solver();
    setup.evaluate(&mut solver, rolling, request)
}

/// Every pose of a poses file, in one process (the profiles read once; each
/// pose starts the contact search afresh, so the result of a pose does not
/// depend on the poses before it). The first pose that fails stops the
/// batch with an error naming it and its line.
pub fn contact_batch(
    config: &ContactTableConfig,
    poses: &[PoseRow],
    poses_path: &std::path::Path,
    rolling: &Rolling,
) -> Result<(ContactSetup, Vec<ContactCase>)> {
    rolling.settings.validate()?;
    let setup = ContactSetup::new(config)?;
    let mut solver = setup.solver();
    let mut cases = Vec::with_capacity(poses.len());
    for row in poses {
        solver.reset();
        let case = setup
            .evaluate(&mut solver, rolling, &PoseRequest::from(row))
            .with_context(|| format!("{}:{}", poses_path.display(), row.line))?;
        cases.push(case);
    }
    Ok((setup, cases))
}

/// Material helper for the CLI.
pub fn material(young_pa: f64, poisson: f64) -> Material {
    Material { young_pa, poisson }
}
