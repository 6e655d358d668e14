//! Scene files (`tables/scenes/*.toml`): everything one run needs — the
//! track, the vehicle, the contact and force models, the initial
//! conditions, the run length and the integrator (docs/reference/08-multibody.md §8). Paths are
//! relative to the scene file. `--set key=value` overrides any entry
//! (dotted keys, TOML values; a bare word is taken as a string), so a
//! sweep is one scene and a list of overrides.
//!
//! ```toml
//! title = "ML95-like wheelset, 300 m straight (paper §5, Fig. 15)"
//!
//! (track)
//! centerline = "../tracks/straight_300m/centerline.csv"  # built on demand, cached
//! # cant = "…", irregularities = "…"      optional CSV inputs
//! # design = "../tracks/r600_design.toml"  or a track from design elements
//! # tables = "straight.h5"                or a table file from track-preproc
//! step_m = 0.1
//! scheme = "cubic"            # centreline and rails
//! cant_scheme = "pchip"        # the cant of control points (default pchip)
//! gauge_m = 1.435
//! rail_inclination = "1:40"    # turns the profile as drawn; default 1:40
//! rail_profile = "../profiles/MBench_UIC60_v3.prr"
//! rail_profile_cant = "1:40"   # the file is drawn canted 1:40 (declared:
//! #                            # the inclination is added on purpose, 1:20 in all)
//!
//! (vehicle)
//! file = "../vehicles/ml95_like_wheelset.toml"
//!
//! (contact)
//! method = "online"         # online | table | imported
//! # imported_table = "../contact/cooperrider_RSGEO.dat"  # method = "imported": a .h5 from
//! #                         # track-preproc import-contact-table, or the RSGEO .dat itself
//! # shear_modulus_pa = 1.4384e11  # imported only: G of the creep forces instead of E/(2(1+ν))
//! flange = "auto"           # off | on | auto
//! creep_law = "polach"      # kalker | heuristic | polach | fastsim | fastrip | none
//! friction = 0.3
//! restitution = 0.9
//! # non_hertzian = "stop"   # stop | floor: where Hertz does not apply (conformal contact)
//!
//! (initial)
//! speed_m_s = 10.0
//! s_m = 5.0                 # track distance of the vehicle reference point
//! lateral_m = -0.002        # every wheelset, + left
//! yaw_rad = 0.0
//! # deceleration_m_s2 = 0.5 # or acceleration_m_s2 (from rest with speed_m_s = 0):
//! # final_speed_m_s = 0.0   # a speed ramp of the track-following references, held at
//! #                         # final_speed_m_s (braking: 0 by default; < 0 reverses)
//! # speed_profile = ((0, 10.0), (20, 10.0), (30, 5.0))  # or knots (t s, V m/s): V
//! #                         # piecewise linear, the last held; first t = 0 at speed_m_s
//!
//! (run)
//! distance_m = 280.0        # or duration_s
//! integrator = "rk4"        # rk4 | dopri5 | rosenbrock
//! step_s = 1e-4             # rk4
//! rtol = 1e-6               # dopri5
//! atol = 1e-9
//! output_interval_s = 0.01
//! # axle_torque_nm = 2000.0     # every axle: + traction, − a constant braking torque
//! # axle_brake_torque_nm = 500.0  # every axle: a friction brake that holds at standstill
//! # lateral_tolerance_m = 1e-5  # optional: the error of the lateral displacement the
//! #                             # run accepts; lets the planner use the contact table
//!
//! # (plan)                      # optional: model only what the scene requires
//! # mode = "required"           # scene (default) | required | everything
//! # choose = ("flange")         # items the planner chooses even when set above
//!
//! # (load)                      # optional: constant loads on the wheelsets (crate::config::load)
//! # lateral_force_n = 20000.0   # + left; yaw_moment_nm, yaw_stiffness_nm_rad, yaw_angle_rad
//! # (perturbation)              # optional: drop_m, lateral_velocity_m_s at t = 0
//! ```
//!
//! The `(plan)` section and `track.range_m` are described in
//! the planner (`docs/guide/speed-accuracy-tradeoff.md`): with `mode = "required"` the planner chooses the
//! flange search, the contact method, the table step and the track range
//! wherever the scene leaves them out (or lists them in `choose`).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail, ensure};
use runtime::forces::creep::{CreepLaw, FastripParams, FastsimParams, PolachParams};
use runtime::integrators::{Dopri5, Method, Rk4, Rosenbrock};
use runtime::multibody::speed_profile::{SpeedKnot, SpeedProfile};
use runtime::multibody::{DynamicsError, SystemSettings};
use serde::{Deserialize, Serialize};

use super::overrides::{command_line_assignment, set_entry, typed};

pub use super::choices::{
    ContactMethodKind, CreepLawName, FlangeMode, IntegratorKind, NonHertzianMode, PlanItem,
    PlanMode, PolachPreset, SplineScheme,
};

/// The track: a table file, or CSV inputs built on demand (and cached).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackSection {
    /// A table file from `track-preproc build` (exclusive with `centerline`).
    #[serde(default)]
    pub tables: Option<PathBuf>,
    /// Centreline control points (CSV).
    #[serde(default)]
    pub centerline: Option<PathBuf>,
    /// Or: a track from design elements (TOML, docs/reference/02-inputs.md
    /// §2.6), built on demand and cached like `centerline`.
    #[serde(default)]
    pub design: Option<PathBuf>,
    /// Or: an ideal straight track of this length (m), tabulated in memory
    /// at `step_m` (no file; for long stability runs).
    #[serde(default)]
    pub straight_m: Option<f64>,
    #[serde(default)]
    pub cant: Option<PathBuf>,
    #[serde(default)]
    pub irregularities: Option<PathBuf>,
    /// Table step (m), spline scheme, gauge (m) of the build; ignored with
    /// `tables`.
    #[serde(default = "default_step")]
    pub step_m: f64,
    #[serde(default = "default_scheme")]
    pub scheme: SplineScheme,
    /// Spline scheme of the cant of control points (default `pchip`,
    /// shape-preserving; docs/reference/03-track-preproc.md §3c).
    #[serde(default = "default_cant_scheme")]
    pub cant_scheme: SplineScheme,
    #[serde(default = "default_gauge")]
    pub gauge_m: f64,
    /// Rail inclination towards the track centre, turning the rail profile
    /// as drawn ("1:40", "1:20", "0", …). Absent: 1:40
    /// (`preproc::config::DEFAULT_RAIL_INCLINATION`), or with `tables` the
    /// table file's; stated with `tables`, it must be the table file's.
    #[serde(default)]
    pub rail_inclination: Option<String>,
    /// Rail profile (both rails; SIMPACK .prr, two columns or CSV). A file
    /// already canted (detected from its head's symmetry, like the shipped
    /// `MBench_UIC60_v3.prr`) is refused with a non-zero inclination —
    /// double canting — unless its cant is declared (`rail_profile_cant`);
    /// with `tables`, it must be the profile the table file records.
    pub rail_profile: PathBuf,
    /// Keep the longest usable stretch of a profile (this rail profile and
    /// the vehicle's wheel profiles) that folds back, repeats its lateral
    /// coordinate or breaks inside, instead of refusing it; the run's
    /// summary then warns, naming the dropped lines
    /// (docs/reference/05-surfaces.md §5.3).
    #[serde(default)]
    pub keep_longest_stretch: bool,
    /// The cant the rail profile file carries as drawn ("1:40", "0", …),
    /// declared: overrides its detection, and the rail inclination is then
    /// added to it on purpose (docs/reference/05-surfaces.md §5.7).
    #[serde(default)]
    pub rail_profile_cant: Option<String>,
    /// Tabulate only this stretch `[from, to]` of the centreline (track
    /// distance, m), built in memory; CSV inputs only. Set by the planner
    /// (the planner) or by hand; absent: the whole track.
    #[serde(default)]
    pub range_m: Option<[f64; 2]>,
}

fn default_step() -> f64 {
    0.1
}
fn default_scheme() -> SplineScheme {
    SplineScheme::Cubic
}
fn default_cant_scheme() -> SplineScheme {
    SplineScheme::of(preproc::config::DEFAULT_CANT_SCHEME)
}
fn default_gauge() -> f64 {
    1.435
}

impl TrackSection {
    /// The rail inclination the scene states, parsed (`None`: not stated).
    pub fn stated_inclination(&self) -> Result<Option<preproc::Inclination>> {
        self.rail_inclination
            .as_deref()
            .map(|t| {
                t.parse::<preproc::Inclination>()
                    .map_err(anyhow::Error::msg)
                    .context("[track] rail_inclination")
            })
            .transpose()
    }

    /// The rail inclination of a track the scene builds: the stated one,
    /// else the default 1:40.
    pub fn inclination(&self) -> Result<preproc::Inclination> {
        Ok(self.stated_inclination()?.unwrap_or_default())
    }

    /// The cant the rail profile carries, when the scene declares it.
    pub fn declared_rail_cant(&self) -> Result<Option<preproc::Inclination>> {
        self.rail_profile_cant
            .as_deref()
            .map(|t| {
                t.parse::<preproc::Inclination>()
                    .map_err(anyhow::Error::msg)
                    .context("[track] rail_profile_cant")
            })
            .transpose()
    }
}

/// The vehicle file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSection {
    pub file: PathBuf,
    /// Factors on the linear damping (`damping_n_s_m`) of the vehicle's
    /// elements, by element-name prefix: `damping_scale = { "secondary
    /// yaw" = 0.5 }` halves every element whose name starts with
    /// "secondary yaw" (a study's way to vary a damper: the key
    /// `vehicle.damping_scale.secondary yaw`). A prefix that matches no
    /// element, or one with a nonlinear damper, is refused; a factor must
    /// lie in [0, 100] (beyond: check the unit).
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub damping_scale: std::collections::BTreeMap<String, f64>,
}

/// Largest factor of `[vehicle] damping_scale` (above it, a coefficient
/// was given instead of a factor).
pub const MAX_DAMPING_SCALE: f64 = 100.0;

/// Contact geometry and force models.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSection {
    /// `online` (Newton at every evaluation), `table` (contact lookup
    /// table, built on demand for the wheel/rail pair and cached) or
    /// `imported` (one contact per wheel from a table computed by another
    /// code, `imported_table`; `runtime::multibody::imported_contact`).
    #[serde(default = "default_method")]
    pub method: ContactMethodKind,
    /// With `method = "imported"`: the table, for every wheelset — a `.h5`
    /// (or `.hdf5`) written by `track-preproc import-contact-table`, or
    /// anything else read as a DYTSI RSGEO text table on the fly.
    #[serde(default)]
    pub imported_table: Option<PathBuf>,
    /// With `method = "imported"`: the shear modulus G of the creep forces
    /// (Pa), instead of E/(2(1 + ν)) (DYTSI's Cooperrider model: 1.4384e11).
    #[serde(default)]
    pub shear_modulus_pa: Option<f64>,
    /// Flange search: `off`, `on` or `auto`.
    #[serde(default = "default_flange")]
    pub flange: FlangeMode,
    /// `kalker`, `heuristic`, `polach`, `fastsim`, `fastrip` or `none`.
    #[serde(default = "default_creep")]
    pub creep_law: CreepLawName,
    /// Polach parameter set: `1999`, `dry-2005`, `wet-2005`.
    #[serde(default = "default_polach")]
    pub polach_preset: PolachPreset,
    /// FASTSIM discretisation (strips × elements per strip).
    #[serde(default)]
    pub fastsim_strips: Option<usize>,
    #[serde(default)]
    pub fastsim_elements: Option<usize>,
    /// FaStrip discretisation (strips × elements per strip).
    #[serde(default)]
    pub fastrip_strips: Option<usize>,
    #[serde(default)]
    pub fastrip_elements: Option<usize>,
    /// Coefficient of friction (for Polach with slip-velocity dependent
    /// friction, μ0).
    #[serde(default = "default_friction")]
    pub friction: f64,
    #[serde(default = "default_young")]
    pub young_pa: f64,
    #[serde(default = "default_poisson")]
    pub poisson: f64,
    /// Restitution coefficient of the normal contact (paper eq. 22).
    #[serde(default = "default_restitution")]
    pub restitution: f64,
    /// Creepage regularisation speed (m/s).
    #[serde(default = "default_min_speed")]
    pub min_rolling_speed_m_s: f64,
    /// Where the contact geometry is not Hertzian (conformal): `stop` (the
    /// run ends with a diagnostic naming the time, wheel, zone and state)
    /// or `floor` (go on with floored curvatures, flagged and counted;
    /// `runtime::multibody::contact_force::NonHertzianPolicy`).
    #[serde(default = "default_non_hertzian")]
    pub non_hertzian: NonHertzianMode,
}

/// Plausible Young's modulus of wheel and rail steel (Pa): steels lie at
/// 190–215 GPa, cast irons at 100–170 GPa; 50–500 GPa brackets every
/// engineering metal from aluminium (70 GPa) to tungsten (411 GPa), and
/// refuses 210 000 (MPa given as Pa) and 210 (GPa given as Pa).
pub const YOUNG_PA_RANGE: [f64; 2] = [50e9, 500e9];

/// Plausible shear modulus G (Pa): E/(2(1 + ν)) over [`YOUNG_PA_RANGE`]
/// and [`POISSON_RANGE`] is 17–217 GPa (steel: 81 GPa; DYTSI's Cooperrider
/// model: 144 GPa).
pub const SHEAR_MODULUS_PA_RANGE: [f64; 2] = [15e9, 250e9];

/// Plausible Poisson's ratio: metals lie at 0.25–0.35 (steel 0.28–0.30);
/// 0.1–0.45 leaves margin on both sides and refuses 30 (a percentage).
pub const POISSON_RANGE: [f64; 2] = [0.1, 0.45];

/// Plausible wheel–rail friction coefficient: measured adhesion lies
/// between about 0.05 (leaves, ice) and 0.6 (dry, sanded); no steel
/// contact in air exceeds 1. 0 (frictionless) stays allowed; 30 is a
/// percentage.
pub const FRICTION_RANGE: [f64; 2] = [0.0, 1.0];

/// `value` in `[lo, hi]` (finite), or an error naming the entry, its unit
/// (" Pa": numbers in exponent form) and the range with "check the unit".
fn plausible(key: &str, value: f64, [lo, hi]: [f64; 2], unit: &str, hint: &str) -> Result<()> {
    let show = |v: f64| {
        if unit.is_empty() {
            format!("{v}")
        } else {
            format!("{v:e}")
        }
    };
    ensure!(
        value.is_finite() && value >= lo && value <= hi,
        "[contact] {key} = {} is outside the plausible {} … {}{unit} of a wheel–rail contact (check the unit{hint})",
        show(value),
        show(lo),
        show(hi)
    );
    Ok(())
}

impl ContactSection {
    /// The material and friction entries against their plausible ranges
    /// ([`YOUNG_PA_RANGE`], [`POISSON_RANGE`], [`SHEAR_MODULUS_PA_RANGE`],
    /// [`FRICTION_RANGE`]): a unit slip is refused before the run instead
    /// of ending it as a blow-up or a failed settling.
    pub fn validate_material(&self) -> Result<()> {
        plausible(
            "young_pa",
            self.young_pa,
            YOUNG_PA_RANGE,
            " Pa",
            ": pascals — steel is 2.1e11 Pa; 210000 is MPa given as Pa",
        )?;
        plausible(
            "poisson",
            self.poisson,
            POISSON_RANGE,
            "",
            ": a ratio, not a percentage — steel is 0.3",
        )?;
        if let Some(g) = self.shear_modulus_pa {
            plausible(
                "shear_modulus_pa",
                g,
                SHEAR_MODULUS_PA_RANGE,
                " Pa",
                ": pascals — steel is 8.1e10 Pa",
            )?;
        }
        plausible(
            "friction",
            self.friction,
            FRICTION_RANGE,
            "",
            ": a coefficient, not a percentage — dry rail is about 0.3",
        )
    }
}

fn default_non_hertzian() -> NonHertzianMode {
    NonHertzianMode::Stop
}

fn default_method() -> ContactMethodKind {
    ContactMethodKind::Online
}
fn default_flange() -> FlangeMode {
    FlangeMode::Auto
}
fn default_creep() -> CreepLawName {
    CreepLawName::Polach
}
fn default_polach() -> PolachPreset {
    PolachPreset::P1999
}
fn default_friction() -> f64 {
    0.3
}
fn default_young() -> f64 {
    210e9
}
fn default_poisson() -> f64 {
    0.3
}
fn default_restitution() -> f64 {
    0.9
}
fn default_min_speed() -> f64 {
    0.1
}

impl Default for ContactSection {
    fn default() -> Self {
        toml::from_str("").expect("every field has a default")
    }
}

/// Initial conditions.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSection {
    /// Forward speed (m/s): every body's initial speed and the references'.
    pub speed_m_s: f64,
    /// Track distance of the vehicle reference point at t = 0 (m).
    #[serde(default = "default_s")]
    pub s_m: f64,
    /// Lateral shift of every wheelset (m), + left.
    #[serde(default)]
    pub lateral_m: f64,
    /// Yaw of every wheelset (rad), + nose left.
    #[serde(default)]
    pub yaw_rad: f64,
    /// Deceleration of the track-following references (m/s², ≥ 0): a speed
    /// ramp V(t) = V0 − a t (nonlinear critical speed) down to
    /// `final_speed_m_s` (default 0: the references stop and stay stopped).
    #[serde(default)]
    pub deceleration_m_s2: f64,
    /// Acceleration of the references (m/s², ≥ 0; not with a deceleration):
    /// V(t) = V0 + a t up to `final_speed_m_s` (default: no limit); V0 may
    /// be 0 (a start from rest).
    #[serde(default)]
    pub acceleration_m_s2: f64,
    /// Speed where the ramp ends and is held (m/s); below 0 with a
    /// deceleration, a reversal (`runtime::multibody::track_motion::SpeedRamp`).
    #[serde(default)]
    pub final_speed_m_s: Option<f64>,
    /// A piecewise-linear speed schedule of the references instead of a
    /// ramp: knots `[t_s, speed_m_s]` (s, m/s), the first at t = 0 with
    /// `speed_m_s`, t strictly increasing, speeds ≥ 0; the last speed is
    /// held (`runtime::multibody::speed_profile::SpeedSchedule`). Not with
    /// an acceleration, deceleration or final speed.
    #[serde(default)]
    pub speed_profile: Option<Vec<[f64; 2]>>,
}

fn default_s() -> f64 {
    5.0
}

impl InitialSection {
    /// The scene's rules of `speed_profile` (the runtime checks them again,
    /// `SystemSettings::validate_motion`), each naming the knot.
    fn validate_speed_profile(&self, knots: &[[f64; 2]]) -> Result<()> {
        ensure!(
            self.acceleration_m_s2 == 0.0
                && self.deceleration_m_s2 == 0.0
                && self.final_speed_m_s.is_none(),
            "[initial] speed_profile goes without acceleration_m_s2, deceleration_m_s2 and final_speed_m_s (the schedule gives the whole motion): remove them or the profile"
        );
        let Some([t0, v0]) = knots.first().copied() else {
            bail!(
                "[initial] speed_profile is empty: give knots [t_s, speed_m_s], the first at t = 0"
            )
        };
        ensure!(
            t0 == 0.0,
            "[initial] speed_profile: the first knot's time is {t0} s; it must be 0 (the start of the run)"
        );
        for (k, [t, v]) in knots.iter().copied().enumerate() {
            ensure!(
                t.is_finite() && v.is_finite(),
                "[initial] speed_profile knot {k} [{t}, {v}] must be finite"
            );
            ensure!(
                (0.0..=150.0).contains(&v),
                "[initial] speed_profile knot {k}: speed {v} m/s must lie in [0, 150] m/s (check the unit: m/s, not km/h)"
            );
            if k > 0 {
                let before = knots[k - 1][0];
                ensure!(
                    t > before,
                    "[initial] speed_profile knot {k}: time {t} s must be greater than knot {}'s {before} s (times strictly increasing)",
                    k - 1
                );
            }
        }
        ensure!(
            self.speed_m_s == v0,
            "[initial] speed_m_s = {} differs from the first knot's speed of [initial] speed_profile, {v0} m/s: the references start at one speed, give the same in both",
            self.speed_m_s
        );
        Ok(())
    }
}

/// Run length, integrator, outputs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSection {
    /// Distance to run (m) — or `duration_s`.
    #[serde(default)]
    pub distance_m: Option<f64>,
    #[serde(default)]
    pub duration_s: Option<f64>,
    /// `rk4`, `dopri5` or `rosenbrock`.
    #[serde(default = "default_integrator")]
    pub integrator: IntegratorKind,
    /// RK4 step (s).
    #[serde(default = "default_step_s")]
    pub step_s: f64,
    /// The adaptive methods' relative and absolute tolerances and largest
    /// step (s); each integrator has its own defaults
    /// ([`RunSection::tolerances`]).
    #[serde(default)]
    pub rtol: Option<f64>,
    #[serde(default)]
    pub atol: Option<f64>,
    #[serde(default)]
    pub max_step_s: Option<f64>,
    /// Output sampling interval (s).
    #[serde(default = "default_output")]
    pub output_interval_s: f64,
    /// Torque about every wheelset's axle (N·m), + driving forwards
    /// (traction), − braking; constant, so it does not stop at standstill.
    #[serde(default)]
    pub axle_torque_nm: f64,
    /// Friction brake on every axle (N·m, ≥ 0): opposes the spin and holds
    /// the wheelset at standstill (`runtime::multibody::SystemSettings`).
    #[serde(default)]
    pub axle_brake_torque_nm: f64,
    /// The largest error of any wheelset's lateral displacement (m) the run
    /// accepts against the fully modelled run; optional. The planner uses
    /// the contact lookup table only where its measured error is within it.
    #[serde(default)]
    pub lateral_tolerance_m: Option<f64>,
}

fn default_integrator() -> IntegratorKind {
    IntegratorKind::Rk4
}
fn default_step_s() -> f64 {
    2e-4
}

/// The adaptive methods' tolerances when the scene leaves them out:
/// DOPRI5 1e-6, 1e-9, 1 ms (its step is stability-limited near 1 ms
/// anyway); Rosenbrock the runtime's defaults, 1e-9, 5e-6, 10 ms
/// (`runtime::integrators::Rosenbrock`: measured to keep the lateral
/// displacement within 10 µm of RK4 at 0.1 ms on the bogie, the car and
/// the flange-limited wheelset, docs/guide/speed-accuracy-tradeoff.md).
pub const DOPRI5_DEFAULT_TOLERANCES: (f64, f64, f64) = (1e-6, 1e-9, 1e-3);
pub const ROSENBROCK_DEFAULT_TOLERANCES: (f64, f64, f64) = (1e-9, 5e-6, 1e-2);

impl RunSection {
    /// (rtol, atol, max_step_s) of the adaptive integrator: the scene's,
    /// else the integrator's defaults (RK4: DOPRI5's, unused).
    pub fn tolerances(&self) -> (f64, f64, f64) {
        let d = match self.integrator {
            IntegratorKind::Rosenbrock => ROSENBROCK_DEFAULT_TOLERANCES,
            _ => DOPRI5_DEFAULT_TOLERANCES,
        };
        (
            self.rtol.unwrap_or(d.0),
            self.atol.unwrap_or(d.1),
            self.max_step_s.unwrap_or(d.2),
        )
    }
}
fn default_output() -> f64 {
    0.005
}

/// A scene as written (after overrides).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    #[serde(default)]
    pub title: String,
    pub track: TrackSection,
    pub vehicle: VehicleSection,
    #[serde(default)]
    pub contact: ContactSection,
    pub initial: InitialSection,
    pub run: RunSection,
    #[serde(default)]
    pub plan: PlanSection,
    /// External loads on the wheelsets (`[load]`, [`crate::config::load`]).
    #[serde(default)]
    pub load: crate::config::load::LoadSection,
    /// Changes to the settled initial state (`[perturbation]`, [`crate::config::load`]).
    #[serde(default)]
    pub perturbation: crate::config::load::PerturbationSection,
    /// Published-formulation switches (`[formulation]`,
    /// [`crate::config::formulation`]).
    #[serde(default)]
    pub formulation: crate::config::formulation::FormulationSection,
}

/// What the planner may choose (the planner, `docs/guide/speed-accuracy-tradeoff.md`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanSection {
    /// `scene` (the default: run the scene as written; the planner only
    /// reports), `required` (the planner chooses every item the scene leaves
    /// out) or `everything` (the reference: flange always searched, online
    /// contact, the finest table step, the whole track).
    #[serde(default = "default_plan_mode")]
    pub mode: PlanMode,
    /// Items the planner chooses even when the scene sets them (with
    /// `mode = "required"`): `flange`, `method`, `step`, `range`,
    /// `integrator`, or `all`.
    #[serde(default)]
    pub choose: Vec<PlanItem>,
}

fn default_plan_mode() -> PlanMode {
    PlanMode::Scene
}

impl PlanSection {
    /// Checks the section: `choose` goes with `mode = "required"`.
    pub fn validate(&self) -> Result<()> {
        ensure!(
            self.choose.is_empty() || self.mode == PlanMode::Required,
            "[plan] choose goes with mode = \"required\""
        );
        Ok(())
    }

    /// Whether the planner chooses `item` even when the scene sets it.
    pub fn chooses(&self, item: PlanItem) -> bool {
        self.choose
            .iter()
            .any(|c| *c == item || *c == PlanItem::All)
    }
}

impl Default for PlanSection {
    fn default() -> Self {
        Self {
            mode: default_plan_mode(),
            choose: Vec::new(),
        }
    }
}

/// A scene with its origin: the directory its paths are relative to and
/// the text as run.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedScene {
    pub scene: Scene,
    pub dir: PathBuf,
    /// The scene text after the overrides (written to the results file).
    pub text: String,
    /// Where it came from (a file, or the built-in default).
    pub origin: String,
    /// The scene file it was read from (none for the built-in scene or
    /// one made from text): an input no output may replace.
    pub file: Option<PathBuf>,
}

/// The paper's single-wheelset case on the shipped data, run by `sim run`
/// without a scene.
pub const DEFAULT_SCENE: &str = include_str!("../../tables/scenes/wheelset_straight.toml");
/// Directory of the built-in scene's relative paths.
pub const DEFAULT_SCENE_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/scenes");

impl LoadedScene {
    /// Reads a scene file and applies `overrides` (`key=value`).
    pub fn load(path: &Path, overrides: &[String]) -> Result<LoadedScene> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("reading the scene {}", path.display()))?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let mut ls = Self::from_text(&text, dir, overrides, path.display().to_string())
            .with_context(|| format!("in the scene {}", path.display()))?;
        ls.file = Some(path.to_path_buf());
        Ok(ls)
    }

    /// The built-in default scene with `overrides`.
    pub fn default_scene(overrides: &[String]) -> Result<LoadedScene> {
        Self::from_text(
            DEFAULT_SCENE,
            PathBuf::from(DEFAULT_SCENE_DIR),
            overrides,
            "built-in scene (tables/scenes/wheelset_straight.toml)".into(),
        )
    }

    /// Parses, overrides, validates.
    pub fn from_text(
        text: &str,
        dir: PathBuf,
        overrides: &[String],
        origin: String,
    ) -> Result<LoadedScene> {
        let mut table: toml::Table = text.parse().context("the scene is not valid TOML")?;
        for o in overrides {
            apply_override(&mut table, o).with_context(|| format!("--set {o}"))?;
        }
        if overrides.is_empty() {
            let scene: Scene = table.try_into().context("the scene's entries")?;
            scene.validate()?;
            return Ok(LoadedScene {
                scene,
                dir,
                text: text.to_string(),
                origin,
                file: None,
            });
        }
        Self::from_table(table, dir, overrides, origin)
    }

    /// A scene from its entries after `overrides` (`key=value`, recorded
    /// in the text's first line), checked.
    pub(crate) fn from_table(
        mut table: toml::Table,
        dir: PathBuf,
        overrides: &[String],
        origin: String,
    ) -> Result<LoadedScene> {
        let keys: Vec<String> = overrides
            .iter()
            .filter_map(|o| o.split_once('=').map(|(k, _)| k.trim().to_string()))
            .collect();
        let scene: Scene = typed(&mut table, &keys)?;
        let text = format!(
            "# overrides: {}\n{}",
            overrides.join(" "),
            toml::to_string(&table)?
        );
        scene.validate()?;
        Ok(LoadedScene {
            scene,
            dir,
            text,
            origin,
            file: None,
        })
    }

    /// The scene's vehicle file, loaded and checked, with the scene's
    /// `[vehicle] damping_scale` applied (the one way every part of `sim`
    /// reads a scene's vehicle).
    pub fn vehicle_file(&self) -> Result<super::vehicle::VehicleFile> {
        let mut v = super::vehicle::VehicleFile::load(&self.path(&self.scene.vehicle.file))?;
        if !self.scene.vehicle.damping_scale.is_empty() {
            v.scale_damping(&self.scene.vehicle.damping_scale)
                .context("[vehicle] damping_scale")?;
        }
        Ok(v)
    }

    /// Every file the scene reads (resolved): the scene file itself, track tables or CSV inputs,
    /// the rail profile, the vehicle file and its wheel profiles, an
    /// imported contact table. Outputs are checked against these before a
    /// run (`runtime::io::check_outputs`). A vehicle file that cannot be
    /// read adds only itself (its reader reports it).
    pub fn input_paths(&self) -> Vec<PathBuf> {
        let s = &self.scene;
        let t = &s.track;
        let mut out: Vec<PathBuf> = [
            &t.tables,
            &t.centerline,
            &t.design,
            &t.cant,
            &t.irregularities,
        ]
        .into_iter()
        .flatten()
        .chain(std::iter::once(&t.rail_profile))
        .chain(s.contact.imported_table.iter())
        .map(|p| self.path(p))
        .collect();
        let vehicle = self.path(&s.vehicle.file);
        if let Ok(v) = super::vehicle::VehicleFile::load(&vehicle) {
            out.extend(v.wheelsets.iter().map(|w| v.profile_path(w)));
        }
        out.push(vehicle);
        out.extend(self.file.iter().cloned());
        out
    }

    /// A path of the scene, resolved against its directory.
    pub fn path(&self, p: &Path) -> PathBuf {
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.dir.join(p)
        }
    }
}

/// Sets `a.b.c = value` in `table` as `--set key=value` does
/// ([`super::overrides`]: the value read as TOML, or else as a string; a
/// relative path to a file entry resolved against the current directory;
/// an empty value removes the entry, e.g. `track.centerline=` to use
/// `track.tables` or `track.straight_m` instead).
pub fn apply_override(table: &mut toml::Table, assignment: &str) -> Result<()> {
    let (key, value) = command_line_assignment(assignment)?;
    set_entry(table, &key, value)
}

/// The scene key of a runtime motion setting (its error names the setting
/// by its meaning; the user wrote the key).
fn scene_key(setting: &str) -> &'static str {
    match setting {
        "speed (m/s)" => "[initial] speed_m_s",
        "deceleration (m/s²)" => "[initial] deceleration_m_s2",
        "acceleration (m/s²)" => "[initial] acceleration_m_s2",
        "final speed (m/s)" => "[initial] final_speed_m_s",
        "speed profile (knots)" | "speed profile time (s)" | "speed profile speed (m/s)" => {
            "[initial] speed_profile"
        }
        "axle torque (N·m)" => "[run] axle_torque_nm",
        "axle brake torque (N·m)" => "[run] axle_brake_torque_nm",
        _ => "[initial]/[run] motion",
    }
}

/// Smallest integrator step a scene may ask for (s): below it a run is a
/// unit slip (1e-4 written as 1e-10), not a finer computation.
pub const MIN_STEP_S: f64 = 1e-7;

/// Largest number of output samples of a run: the results are held in
/// memory until written (about [`BYTES_PER_WHEELSET_SAMPLE`] bytes per
/// wheelset and sample: 75 series of f64).
pub const MAX_OUTPUT_SAMPLES: f64 = 5e6;

/// Memory of one output sample of one wheelset (bytes): 5 wheelset series,
/// 2 × 5 wheel series and 2 × 2 × 15 zone series of f64 (`runtime::results`).
pub const BYTES_PER_WHEELSET_SAMPLE: f64 = 75.0 * 8.0;

impl Scene {
    /// Checks every rule, naming the entry.
    pub fn validate(&self) -> Result<()> {
        self.load.validate()?;
        self.perturbation.validate()?;
        let t = &self.track;
        match (&t.tables, &t.centerline, &t.design, t.straight_m) {
            (Some(_), None, None, None)
            | (None, Some(_), None, None)
            | (None, None, Some(_), None) => {}
            (None, None, None, Some(l)) => ensure!(
                l.is_finite() && l > 10.0 && l <= 1e6,
                "[track] straight_m = {l} must lie in (10, 1e6] m"
            ),
            _ => bail!(
                "[track]: give one of tables (a .h5 file), centerline (CSV inputs), design (a design file) or straight_m (an ideal straight)"
            ),
        }
        ensure!(
            t.design.is_none() || t.cant.is_none(),
            "[track]: the cant of a design track is in its design file (cant_mm on its elements); remove cant"
        );
        ensure!(
            t.tables.is_none() || (t.cant.is_none() && t.irregularities.is_none()),
            "[track]: cant and irregularities are CSV inputs; with tables they are already built in"
        );
        ensure!(
            t.step_m.is_finite() && t.step_m > 0.0 && t.step_m <= 5.0,
            "[track] step_m = {} must lie in (0, 5] m",
            t.step_m
        );
        if let Some([a, b]) = t.range_m {
            ensure!(
                a.is_finite() && b.is_finite() && a >= 0.0 && b > a,
                "[track] range_m = [{a}, {b}] must be [from, to] with 0 <= from < to (m)"
            );
            ensure!(
                t.centerline.is_some() || t.design.is_some(),
                "[track] range_m needs centerline or design inputs (a table file is used as it is; an ideal straight is shortened with straight_m)"
            );
        }
        t.stated_inclination()?;
        t.declared_rail_cant()?;
        ensure!(
            t.gauge_m > 0.5 && t.gauge_m < 2.5,
            "[track] gauge_m = {} must lie in 0.5 … 2.5 m",
            t.gauge_m
        );
        let c = &self.contact;
        if c.method == ContactMethodKind::Imported {
            ensure!(
                c.imported_table.is_some(),
                "[contact] method = \"imported\" needs imported_table (a .h5 from track-preproc import-contact-table, or an RSGEO .dat)"
            );
            ensure!(
                matches!(
                    c.creep_law,
                    CreepLawName::Heuristic | CreepLawName::Kalker | CreepLawName::None
                ),
                "[contact] creep_law '{}' is not available with method = \"imported\" (the table brings its own Kalker coefficients): use heuristic, kalker or none",
                c.creep_law
            );
        } else {
            ensure!(
                c.imported_table.is_none() && c.shear_modulus_pa.is_none(),
                "[contact] imported_table and shear_modulus_pa go with method = \"imported\" only"
            );
        }
        c.validate_material()?;
        self.formulation.validate(c.method)?;
        self.creep_law()?;
        ensure!(
            c.restitution > 0.0 && c.restitution <= 1.0,
            "[contact] restitution = {} must lie in (0, 1]",
            c.restitution
        );
        ensure!(
            c.min_rolling_speed_m_s.is_finite() && c.min_rolling_speed_m_s > 0.0,
            "[contact] min_rolling_speed_m_s = {} must be finite and > 0",
            c.min_rolling_speed_m_s
        );
        let i = &self.initial;
        // Plausibility (a unit slip: km/h for m/s); the rules of the motion
        // itself are the runtime's, checked once below.
        ensure!(
            i.speed_m_s.is_nan() || i.speed_m_s <= 150.0,
            "[initial] speed_m_s = {} must lie in [0, 150] m/s (check the unit: m/s, not km/h)",
            i.speed_m_s
        );
        ensure!(
            i.final_speed_m_s
                .is_none_or(|vf| vf.is_nan() || vf.abs() <= 150.0),
            "[initial] final_speed_m_s = {} must lie in [-150, 150] m/s (check the unit: m/s, not km/h)",
            i.final_speed_m_s.unwrap_or_default()
        );
        ensure!(i.s_m.is_finite(), "[initial] s_m must be finite");
        if let Some(knots) = &i.speed_profile {
            i.validate_speed_profile(knots)?;
        }
        self.motion_settings()
            .validate_motion()
            .map_err(|e| match e {
                DynamicsError::Setting {
                    setting,
                    value,
                    rule,
                } => anyhow::anyhow!("{} = {value} {rule}", scene_key(setting)),
                other => anyhow::anyhow!(other),
            })?;
        ensure!(
            i.lateral_m.is_finite() && i.lateral_m.abs() <= 0.02,
            "[initial] lateral_m = {} must lie within ±0.02 m",
            i.lateral_m
        );
        ensure!(
            i.yaw_rad.is_finite() && i.yaw_rad.abs() <= 0.05,
            "[initial] yaw_rad = {} must lie within ±0.05 rad",
            i.yaw_rad
        );
        let r = &self.run;
        match (r.distance_m, r.duration_s) {
            (Some(d), None) => ensure!(
                d.is_finite() && d > 0.0,
                "[run] distance_m = {d} must be finite and > 0"
            ),
            (None, Some(d)) => ensure!(
                d.is_finite() && d > 0.0,
                "[run] duration_s = {d} must be finite and > 0"
            ),
            _ => bail!("[run]: give either distance_m or duration_s"),
        }
        if let Some(d) = r.distance_m {
            let profile_moves = i
                .speed_profile
                .as_ref()
                .is_some_and(|k| k.iter().any(|[_, v]| *v > 0.0));
            ensure!(
                i.speed_m_s > 0.0 || i.acceleration_m_s2 > 0.0 || profile_moves,
                "[run] distance_m needs [initial] speed_m_s > 0, acceleration_m_s2 > 0 or a speed_profile that moves (use duration_s at standstill)"
            );
            ensure!(
                self.speed_profile().time_to_cover_s(d).is_some()
                    || i.final_speed_m_s.is_none_or(|vf| vf >= 0.0),
                "[run] distance_m = {d} is never covered: the references reverse first (use duration_s)"
            );
        }
        for (key, v) in [
            ("axle_torque_nm", r.axle_torque_nm),
            ("axle_brake_torque_nm", r.axle_brake_torque_nm),
        ] {
            ensure!(
                v.is_nan() || v.abs() <= 1e6,
                "[run] {key} = {v} must lie within ±1e6 N·m (check the unit)"
            );
        }
        self.method()?;
        ensure!(
            r.output_interval_s.is_finite() && r.output_interval_s > 0.0,
            "[run] output_interval_s = {} must be finite and > 0",
            r.output_interval_s
        );
        // The results are held in memory until written: bound their size
        // before the run, not when the machine runs out of memory. (Output
        // finer than the step is legitimate: both integrators have dense
        // output, docs/reference/08-multibody.md §8.5.)
        let samples = self.duration_s() / r.output_interval_s;
        ensure!(
            samples <= MAX_OUTPUT_SAMPLES,
            "[run] output_interval_s = {:e} s gives {samples:.3e} samples over the run's {:.1} s, more than {MAX_OUTPUT_SAMPLES:e} (about {} MB per wheelset in memory): raise it (check the unit)",
            r.output_interval_s,
            self.duration_s(),
            (MAX_OUTPUT_SAMPLES * BYTES_PER_WHEELSET_SAMPLE / 1e6).round()
        );
        if let Some(tol) = r.lateral_tolerance_m {
            ensure!(
                tol.is_finite() && tol > 0.0,
                "[run] lateral_tolerance_m = {tol} must be finite and > 0 (m)"
            );
        }
        self.plan.validate()?;
        Ok(())
    }

    /// The runtime's settings of the motion (speed, its ramp, axle torques,
    /// start), the rest at their defaults: the one place the scene's
    /// `[initial]` and `[run]` motion entries become runtime settings
    /// (checked by [`SystemSettings::validate_motion`], completed with the
    /// force and contact models by the session).
    pub fn motion_settings(&self) -> SystemSettings {
        let (i, r) = (&self.initial, &self.run);
        SystemSettings {
            speed_m_s: i.speed_m_s,
            deceleration_m_s2: i.deceleration_m_s2,
            acceleration_m_s2: i.acceleration_m_s2,
            final_speed_m_s: i.final_speed_m_s,
            speed_profile: i.speed_profile.as_ref().map(|k| {
                k.iter()
                    .map(|[t_s, speed_m_s]| SpeedKnot {
                        t_s: *t_s,
                        speed_m_s: *speed_m_s,
                    })
                    .collect()
            }),
            axle_torque_nm: r.axle_torque_nm,
            axle_brake_torque_nm: r.axle_brake_torque_nm,
            s_start_m: i.s_m,
            ..SystemSettings::default()
        }
    }

    /// The references' speed against time (`[initial]` speed_m_s,
    /// acceleration_m_s2 or deceleration_m_s2, final_speed_m_s, or
    /// speed_profile): the runtime's profile of [`Self::motion_settings`].
    pub fn speed_profile(&self) -> SpeedProfile {
        self.motion_settings().speed_profile()
    }

    /// Simulated time (s): for `distance_m`, the time the references take
    /// to cover it (with a deceleration, until they stop, if they stop
    /// first).
    pub fn duration_s(&self) -> f64 {
        let ramp = self.speed_profile();
        match (self.run.distance_m, self.run.duration_s) {
            (Some(d), _) => ramp.time_to_cover_s(d).or(ramp.end_time_s()).unwrap_or(0.0),
            (None, Some(t)) => t,
            (None, None) => 0.0,
        }
    }

    /// The creep law with its parameters.
    pub fn creep_law(&self) -> Result<CreepLaw> {
        let c = &self.contact;
        let law = match c.creep_law {
            CreepLawName::Polach => {
                let (params, _) = PolachParams::preset(c.polach_preset.as_str())
                    .context("[contact] polach_preset: a preset the creep law does not know")?;
                CreepLaw::Polach(params)
            }
            CreepLawName::Fastsim => {
                let mut p = FastsimParams::default();
                if let Some(k) = c.fastsim_strips {
                    p.strips = k;
                }
                if let Some(k) = c.fastsim_elements {
                    p.elements_per_strip = k;
                }
                CreepLaw::Fastsim(p)
            }
            CreepLawName::Fastrip => {
                let mut p = FastripParams::default();
                if let Some(k) = c.fastrip_strips {
                    p.strips = k;
                }
                if let Some(k) = c.fastrip_elements {
                    p.elements_per_strip = k;
                }
                CreepLaw::Fastrip(p)
            }
            CreepLawName::Kalker => CreepLaw::KalkerLinear,
            CreepLawName::Heuristic => CreepLaw::Heuristic,
            CreepLawName::None => CreepLaw::None,
        };
        law.validate().context("[contact] creep law parameters")?;
        Ok(law)
    }

    /// The integration method.
    pub fn method(&self) -> Result<Method> {
        let r = &self.run;
        Ok(match r.integrator {
            IntegratorKind::Rk4 => {
                ensure!(
                    r.step_s.is_finite() && r.step_s > 0.0 && r.step_s <= 0.01,
                    "[run] step_s = {} must lie in (0, 0.01] s",
                    r.step_s
                );
                ensure!(
                    r.step_s >= MIN_STEP_S,
                    "[run] step_s = {:e} s is below {MIN_STEP_S:e} s (check the unit: seconds; the stiffest contact modes need about 1e-4 s)",
                    r.step_s
                );
                Method::Rk4(Rk4 { step_s: r.step_s })
            }
            IntegratorKind::Dopri5 | IntegratorKind::Rosenbrock => {
                let (rtol, atol, max_step_s) = r.tolerances();
                ensure!(
                    rtol > 0.0 && rtol < 1.0 && atol > 0.0,
                    "[run] rtol = {rtol} must lie in (0, 1) and atol = {atol} be > 0"
                );
                ensure!(
                    max_step_s > 0.0 && max_step_s.is_finite(),
                    "[run] max_step_s = {max_step_s} must be finite and > 0"
                );
                ensure!(
                    max_step_s >= MIN_STEP_S,
                    "[run] max_step_s = {max_step_s:e} s is below {MIN_STEP_S:e} s (check the unit: seconds)"
                );
                if r.integrator == IntegratorKind::Dopri5 {
                    Method::Dopri5(Dopri5 {
                        rtol,
                        atol,
                        max_step_s,
                        ..Dopri5::default()
                    })
                } else {
                    Method::Rosenbrock(Rosenbrock {
                        rtol,
                        atol,
                        max_step_s,
                        ..Rosenbrock::default()
                    })
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_scene_is_valid() {
        let s = LoadedScene::default_scene(&[]).unwrap();
        assert!(s.scene.duration_s() > 0.0);
        assert!(
            s.path(&s.scene.vehicle.file).exists(),
            "{:?}",
            s.scene.vehicle.file
        );
    }

    /// `creep_law = "fastrip"` gives FaStrip with its default grid, or the
    /// scene's `fastrip_strips` × `fastrip_elements`; a grid outside
    /// 1 … 2000 is refused, naming the law and the parameter.
    #[test]
    fn fastrip_and_its_grid() {
        let s = LoadedScene::default_scene(&["contact.creep_law=fastrip".into()]).unwrap();
        assert_eq!(
            s.scene.creep_law().unwrap(),
            CreepLaw::Fastrip(FastripParams::default())
        );
        let s = LoadedScene::default_scene(&[
            "contact.creep_law=fastrip".into(),
            "contact.fastrip_strips=8".into(),
            "contact.fastrip_elements=32".into(),
        ])
        .unwrap();
        assert_eq!(
            s.scene.creep_law().unwrap(),
            CreepLaw::Fastrip(FastripParams {
                strips: 8,
                elements_per_strip: 32
            })
        );
        let Err(e) = LoadedScene::default_scene(&[
            "contact.creep_law=fastrip".into(),
            "contact.fastrip_strips=0".into(),
        ]) else {
            panic!("fastrip_strips = 0 must be refused");
        };
        let text = format!("{e:#}");
        assert!(
            text.contains("FaStrip") && text.contains("strips"),
            "{text}"
        );
    }

    #[test]
    fn overrides_set_values_and_are_recorded() {
        let s = LoadedScene::default_scene(&[
            "initial.speed_m_s=20".into(),
            "contact.creep_law=kalker".into(),
            "run.integrator = \"dopri5\"".into(),
        ])
        .unwrap();
        assert_eq!(s.scene.initial.speed_m_s, 20.0);
        assert_eq!(s.scene.contact.creep_law, CreepLawName::Kalker);
        assert_eq!(s.scene.run.integrator, IntegratorKind::Dopri5);
        assert!(s.text.starts_with("# overrides:"));
        let straight = LoadedScene::default_scene(&[
            "track.centerline=".into(),
            "track.straight_m=2000".into(),
        ])
        .unwrap();
        assert_eq!(straight.scene.track.centerline, None);
        assert_eq!(straight.scene.track.straight_m, Some(2000.0));
        let again = LoadedScene::from_text(&s.text, s.dir.clone(), &[], "x".into()).unwrap();
        assert_eq!(again.scene, s.scene);
    }

    #[test]
    fn bad_entries_name_the_rule() {
        let cases = [
            ("contact.creep_law=coulomb", "creep_law"),
            ("initial.speed_m_s=-1", "speed_m_s"),
            ("contact.flange=sometimes", "flange"),
            ("run.integrator=euler", "integrator"),
            ("run.step_s=0", "step_s"),
            ("contact.restitution=1.5", "restitution"),
            ("contact.frction=0.3", "frction"),
            ("speed", "key=value"),
        ];
        for (o, what) in cases {
            let e = LoadedScene::default_scene(&[o.into()]).unwrap_err();
            let chain = format!("{e:#}");
            assert!(chain.contains(what), "{o}: {chain}");
        }
    }

    #[test]
    fn implausible_materials_are_refused_with_check_the_unit() {
        let scene = |o: &str| LoadedScene::default_scene(&[o.into()]);
        for (o, needle) in [
            // MPa given as Pa: before, the settling failed on a flange
            // 126 mm deep in its rail.
            (
                "contact.young_pa=210000",
                "young_pa = 2.1e5 is outside the plausible 5e10 … 5e11 Pa",
            ),
            ("contact.young_pa=210", "young_pa = 2.1e2"),
            // Before, a blow-up reported as a derailment.
            ("contact.young_pa=1e30", "young_pa = 1e30"),
            ("contact.young_pa=nan", "young_pa = NaN"),
            (
                "contact.poisson=30",
                "poisson = 30 is outside the plausible 0.1 … 0.45",
            ),
            (
                "contact.friction=30",
                "friction = 30 is outside the plausible 0 … 1",
            ),
            ("contact.friction=-0.1", "friction = -0.1"),
        ] {
            let chain = format!("{:#}", scene(o).unwrap_err());
            assert!(chain.contains(needle), "{o}: {chain}");
            assert!(chain.contains("check the unit"), "{o}: {chain}");
        }
        // The ends of the ranges and steel itself pass.
        for o in [
            "contact.young_pa=5e10",
            "contact.young_pa=5e11",
            "contact.young_pa=2.1e11",
            "contact.poisson=0.28",
            "contact.friction=0",
            "contact.friction=0.6",
        ] {
            scene(o).unwrap_or_else(|e| panic!("{o}: {e:#}"));
        }
        let cooperrider = ContactSection {
            method: ContactMethodKind::Imported,
            shear_modulus_pa: Some(1.4384e11),
            ..ContactSection::default()
        };
        cooperrider.validate_material().expect("DYTSI's G");
        let mpa = ContactSection {
            shear_modulus_pa: Some(81000.0),
            ..ContactSection::default()
        };
        let e = format!("{:#}", mpa.validate_material().unwrap_err());
        assert!(
            e.contains("shear_modulus_pa = 8.1e4") && e.contains("check the unit"),
            "{e}"
        );
    }

    #[test]
    fn speed_ramps_and_axle_torques() {
        let scene = |o: &[&str]| {
            let o: Vec<String> = o.iter().map(|s| s.to_string()).collect();
            LoadedScene::default_scene(&o)
        };
        // From rest over 4 m at 2 m/s²: 2 s.
        let s = scene(&[
            "initial.speed_m_s=0",
            "initial.acceleration_m_s2=2",
            "run.distance_m=4",
        ])
        .unwrap();
        assert!((s.scene.duration_s() - 2.0).abs() < 1e-12);
        // Braking from 10 m/s at 2 m/s² stops after 25 m, at 5 s.
        let s = scene(&["initial.deceleration_m_s2=2", "run.distance_m=100"]).unwrap();
        assert!((s.scene.duration_s() - 5.0).abs() < 1e-12);
        let s = scene(&["run.axle_torque_nm=-2000", "run.axle_brake_torque_nm=500"]).unwrap();
        assert_eq!(s.scene.run.axle_torque_nm, -2000.0);
        let cases: [(&[&str], &str); 9] = [
            (
                &["initial.acceleration_m_s2=1", "initial.deceleration_m_s2=1"],
                "not both",
            ),
            (
                &["initial.final_speed_m_s=3"],
                "[initial] final_speed_m_s = 3 needs an acceleration or a deceleration",
            ),
            (
                &["initial.acceleration_m_s2=1", "initial.final_speed_m_s=3"],
                "[initial] final_speed_m_s = 3 must be >= the initial speed when accelerating",
            ),
            (
                &[
                    "initial.deceleration_m_s2=1",
                    "initial.final_speed_m_s=-2",
                    "run.distance_m=1000",
                ],
                "never covered",
            ),
            (
                &["run.axle_brake_torque_nm=-1"],
                "[run] axle_brake_torque_nm = -1 must be finite and >= 0",
            ),
            (&["run.axle_torque_nm=nan"], "[run] axle_torque_nm"),
            (&["initial.speed_m_s=300"], "check the unit"),
            (
                &["initial.deceleration_m_s2=-1"],
                "[initial] deceleration_m_s2 = -1",
            ),
            (
                &["initial.speed_m_s=-1"],
                "[initial] speed_m_s = -1 must be finite and >= 0",
            ),
        ];
        for (o, what) in cases {
            let chain = format!("{:#}", scene(o).unwrap_err());
            assert!(chain.contains(what), "{o:?}: {chain}");
        }
    }

    #[test]
    fn speed_profiles_give_the_schedule_and_name_the_broken_rule() {
        let scene = |o: &[&str]| {
            let o: Vec<String> = o.iter().map(|s| s.to_string()).collect();
            LoadedScene::default_scene(&o)
        };
        // 10 m/s for 2 s (20 m), down to 6 m/s over 2 s (16 m), held: 40 m
        // at 4 + 4/6 s.
        let profile = "initial.speed_profile=[[0, 10.0], [2, 10.0], [4.0, 6.0]]";
        let s = scene(&[profile, "run.distance_m=40"]).unwrap();
        assert!((s.scene.duration_s() - (4.0 + 4.0 / 6.0)).abs() < 1e-12);
        assert!((s.scene.speed_profile().speed_m_s(3.0) - 8.0).abs() < 1e-12);
        // A duration: the planner's travel is the schedule's integral.
        let s = scene(&[profile, "run.distance_m=", "run.duration_s=5"]).unwrap();
        assert!((crate::session::plan::facts::travel_m(&s) - 42.0).abs() < 1e-12);
        let cases: [(&[&str], &str); 6] = [
            (
                &[profile, "initial.deceleration_m_s2=1"],
                "[initial] speed_profile goes without acceleration_m_s2",
            ),
            (&["initial.speed_profile=[]"], "speed_profile is empty"),
            (
                &["initial.speed_profile=[[1, 10.0]]"],
                "the first knot's time is 1 s; it must be 0",
            ),
            (
                &["initial.speed_profile=[[0, 10.0], [2, 8.0], [2, 6.0]]"],
                "knot 2: time 2 s must be greater than knot 1's 2 s",
            ),
            (
                &["initial.speed_profile=[[0, 10.0], [2, 300.0]]"],
                "check the unit",
            ),
            (
                &["initial.speed_profile=[[0, 12.0], [2, 8.0]]"],
                "[initial] speed_m_s = 10 differs from the first knot's speed of [initial] speed_profile, 12 m/s",
            ),
        ];
        for (o, what) in cases {
            let chain = format!("{:#}", scene(o).unwrap_err());
            assert!(chain.contains(what), "{o:?}: {chain}");
        }
    }
}
