//! `railsim.contact` (`sim contact --poses` on arrays) and
//! `railsim.equivalent_conicity` (EN 15302).

use std::path::PathBuf;

use clap::Parser;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{broadcast, columns_dict, floats, optional_floats};
use crate::errors::{OrValueError, warn_all};

/// The `sim contact` arguments of the profiles and the force model, parsed
/// by the CLI's own parser (its defaults, checks and messages).
struct ContactOptions<'a> {
    wheel: &'a std::path::Path,
    rail: &'a std::path::Path,
    numbers: Vec<(&'static str, f64)>,
    words: Vec<(&'static str, &'a str)>,
    rigid: bool,
}

impl ContactOptions<'_> {
    fn parse(&self) -> PyResult<railsim::cli::ContactArgs> {
        let mut args = vec![
            "sim".to_string(),
            "contact".into(),
            format!("--wheel={}", self.wheel.display()),
            format!("--rail={}", self.rail.display()),
        ];
        args.extend(self.numbers.iter().map(|(f, v)| format!("--{f}={v}")));
        args.extend(self.words.iter().map(|(f, v)| format!("--{f}={v}")));
        if self.rigid {
            args.push("--rigid".into());
        }
        let cli = railsim::cli::Cli::try_parse_from(&args)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.render().to_string()))?;
        match cli.command {
            railsim::cli::Command::Contact(a) => Ok(a),
            _ => unreachable!("the arguments start with `contact`"),
        }
    }
}

/// The contact patches and forces of a wheelset on straight track at each
/// pose, as `sim contact --poses POSES.csv --format csv` gives them (one
/// row per pose, wheel and patch; left wheel first, deepest patch first),
/// as a dict of numpy arrays keyed by the CSV's columns, in the Manchester
/// contact benchmark's units: mm, rad, N, N·mm, MPa (docs/guide/contact-benchmark.md).
///
/// Per pose (float or array; length-1 inputs are repeated):
/// - `y_mm`: lateral shift of the wheelset, + left (mm);
/// - `yaw_mrad`: yaw, + nose left (mrad); None: 0;
/// - `roll_rad`: roll, + raising the left wheel (rad); None: solved so that
///   both wheels carry `wheel_load_n`;
/// - `pitch_rate_rad_s`: angular velocity of the axle, + rolling forward
///   (rad/s); None: V/r₀;
/// - `vertical_force_per_wheel_n`: the pose's load per wheel (N); None:
///   `wheel_load_n`.
///
/// Model: `wheel_load_n` (N) per wheel, `speed_m_s` (m/s), `creep` (kalker,
/// heuristic, polach, fastsim, fastrip, none), `mu` (–), `young_pa` (Pa),
/// `poisson` (–), `gauge_m`, `back_to_back_m`, `wheel_radius_m` (m),
/// `rail_inclination` ("0" for profiles that carry it, "1:40", …), `load`
/// ("vertical": the vertical components of normal and creep forces balance
/// the load, the benchmark's definition; "normal": the normal forces'
/// alone), `patch_location` ("centre" or "deepest").
///
/// Keys: case, side, patch, zone, y_ws_mm, yaw_ws_rad, roll_ws_rad,
/// axle_rate_rad_s, z_ws_mm, x_tr_mm, y_tr_mm, z_tr_mm, y_rail_mm,
/// z_rail_mm, y_wheel_mm, z_wheel_mm, contact_angle_rad, rolling_radius_mm,
/// lead_mm, xi, eta, phi_1_mm, fn_n, fx_n, fs_n, mz_nmm, approach_mm, a_mm,
/// b_mm, pmax_mpa, wheel_fx_tr_n, wheel_fy_tr_n, wheel_fz_tr_n,
/// overlap_width_mm (NaN where the CSV has an empty field).
///
/// A refused input raises ValueError with the CLI's message; a pose that
/// cannot be solved names its index (`<poses>:K`, K from 1).
#[pyfunction]
#[pyo3(signature = (wheel, rail, y_mm, yaw_mrad=None, roll_rad=None, pitch_rate_rad_s=None,
    wheel_load_n=10000.0, speed_m_s=2.0, creep="polach", mu=0.3, young_pa=210e9, poisson=0.3,
    gauge_m=1.435, back_to_back_m=1.360, wheel_radius_m=0.46, rail_inclination="0",
    load="vertical", patch_location="centre", rigid=false, rail_profile_cant=None,
    profile_scheme="cubic", vertical_force_per_wheel_n=None))]
#[allow(clippy::too_many_arguments)]
pub fn contact<'py>(
    py: Python<'py>,
    wheel: PathBuf,
    rail: PathBuf,
    y_mm: &Bound<'py, PyAny>,
    yaw_mrad: Option<&Bound<'py, PyAny>>,
    roll_rad: Option<&Bound<'py, PyAny>>,
    pitch_rate_rad_s: Option<&Bound<'py, PyAny>>,
    wheel_load_n: f64,
    speed_m_s: f64,
    creep: &str,
    mu: f64,
    young_pa: f64,
    poisson: f64,
    gauge_m: f64,
    back_to_back_m: f64,
    wheel_radius_m: f64,
    rail_inclination: &str,
    load: &str,
    patch_location: &str,
    rigid: bool,
    rail_profile_cant: Option<&str>,
    profile_scheme: &str,
    vertical_force_per_wheel_n: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut words = vec![
        ("creep", creep),
        ("rail-inclination", rail_inclination),
        ("load-convention", load),
        ("patch-location", patch_location),
        ("profile-scheme", profile_scheme),
    ];
    if let Some(c) = rail_profile_cant {
        words.push(("rail-profile-cant", c));
    }
    let args = ContactOptions {
        wheel: &wheel,
        rail: &rail,
        numbers: vec![
            ("wheel-load-n", wheel_load_n),
            ("speed-m-s", speed_m_s),
            ("mu", mu),
            ("young-pa", young_pa),
            ("poisson", poisson),
            ("gauge", gauge_m),
            ("back-to-back", back_to_back_m),
            ("wheel-radius", wheel_radius_m),
        ],
        words,
        rigid,
    }
    .parse()?;
    let poses = poses(
        py,
        y_mm,
        yaw_mrad,
        roll_rad,
        pitch_rate_rad_s,
        vertical_force_per_wheel_n,
    )?;
    let (cases, warnings) = py
        .detach(|| -> anyhow::Result<_> {
            use railsim::studies::contact as study;
            let config = args.to_config()?;
            let rolling = args.to_rolling()?;
            let mut warnings = config.check_rail().map(|c| c.warnings).unwrap_or_default();
            let (_, cases) =
                study::contact_batch(&config, &poses, std::path::Path::new("<poses>"), &rolling)?;
            warnings.extend(cases.iter().flat_map(|c| c.warnings.iter().cloned()));
            Ok((study::patch_rows(&cases), warnings))
        })
        .or_value_error()?;
    warn_all(py, &warnings)?;
    columns_dict(
        py,
        &railsim::studies::contact::CSV_COLUMNS,
        &["case", "patch"],
        &cases,
    )
}

/// The per-pose inputs as the poses file's rows (pose K on "line" K).
fn poses<'py>(
    _py: Python<'py>,
    y_mm: &Bound<'py, PyAny>,
    yaw_mrad: Option<&Bound<'py, PyAny>>,
    roll_rad: Option<&Bound<'py, PyAny>>,
    pitch_rate_rad_s: Option<&Bound<'py, PyAny>>,
    load_n: Option<&Bound<'py, PyAny>>,
) -> PyResult<Vec<railsim::studies::contact::PoseRow>> {
    let y = floats(y_mm, "y_mm")?;
    let yaw = optional_floats(yaw_mrad, "yaw_mrad")?.unwrap_or_else(|| vec![0.0]);
    let roll = optional_floats(roll_rad, "roll_rad")?;
    let rate = optional_floats(pitch_rate_rad_s, "pitch_rate_rad_s")?;
    let load = optional_floats(load_n, "vertical_force_per_wheel_n")?;
    let n = [
        Some(y.len()),
        Some(yaw.len()),
        roll.as_ref().map(Vec::len),
        rate.as_ref().map(Vec::len),
        load.as_ref().map(Vec::len),
    ]
    .into_iter()
    .flatten()
    .max()
    .unwrap_or(1);
    if y.is_empty() {
        return Err(pyo3::exceptions::PyValueError::new_err(
            "y_mm: no pose given",
        ));
    }
    let y = broadcast("y_mm", y, n)?;
    let yaw = broadcast("yaw_mrad", yaw, n)?;
    let opt = |name, v: Option<Vec<f64>>| v.map(|v| broadcast(name, v, n)).transpose();
    let roll = opt("roll_rad", roll)?;
    let rate = opt("pitch_rate_rad_s", rate)?;
    let load = opt("vertical_force_per_wheel_n", load)?;
    Ok((0..n)
        .map(|k| railsim::studies::contact::PoseRow {
            case: k as u32 + 1,
            line: k + 1,
            y_m: y[k] * 1e-3,
            yaw_rad: yaw[k] * 1e-3,
            roll_rad: roll.as_ref().map(|v| v[k]),
            axle_rate_rad_s: rate.as_ref().map(|v| v[k]),
            speed_m_s: None,
            load_n: load.as_ref().map(|v| v[k]),
        })
        .collect())
}

/// EN 15302 equivalent conicity tan γe of a wheelset (the same `wheel`
/// profile on both wheels) on a rail pair, at each amplitude ŷ (mm;
/// `amplitudes_mm=None`: 1, 2, …, 6 mm): the
/// standard's idealised wheelset (level, each wheel lowered onto its rail,
/// rigid contact) gives Δr(y) = r_left − r_right on a lateral grid of step
/// `y_step_mm`, and the kinematic oscillation of each amplitude its tan γe
/// (Annex B, e = 1.5 m, r₀ = 0.46 m) and wavelength.
///
/// - `amplitudes_mm`: amplitudes ŷ (mm), each in (0, 50);
/// - `gauge_m`, `back_to_back_m`, `wheel_radius_m`: track gauge, flange
///   back distance and nominal rolling radius (m);
/// - `rail_inclination`: "1:40", "1:20", "0" (profiles that carry it);
/// - `y_step_mm`: step of the lateral grid of Δr (mm), in (0, 1].
///
/// Keys: `amplitude_mm`, `tan_gamma_e` (–, NaN where the amplitude lies
/// beyond the Δr the grid supports), `wavelength_m` (m), `y_mm` and
/// `delta_r_mm` (the Δr function), `max_amplitude_mm` (float or None).
#[pyfunction]
#[pyo3(signature = (wheel, rail, amplitudes_mm=None, gauge_m=1.435, back_to_back_m=1.360,
    wheel_radius_m=0.46, rail_inclination="1:40", y_step_mm=0.1, rail_profile_cant=None,
    profile_scheme="cubic"))]
#[allow(clippy::too_many_arguments)]
pub fn equivalent_conicity<'py>(
    py: Python<'py>,
    wheel: PathBuf,
    rail: PathBuf,
    amplitudes_mm: Option<&Bound<'py, PyAny>>,
    gauge_m: f64,
    back_to_back_m: f64,
    wheel_radius_m: f64,
    rail_inclination: &str,
    y_step_mm: f64,
    rail_profile_cant: Option<&str>,
    profile_scheme: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let amplitudes = optional_floats(amplitudes_mm, "amplitudes_mm")?
        .unwrap_or_else(|| vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    if let Some(a) = amplitudes
        .iter()
        .find(|a| !(a.is_finite() && **a > 0.0 && **a < 50.0))
    {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "amplitudes_mm: {a} mm is not an amplitude in (0, 50) mm (check the unit: millimetres)"
        )));
    }
    if !(y_step_mm.is_finite() && y_step_mm > 0.0 && y_step_mm <= 1.0) {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "y_step_mm: {y_step_mm} mm must lie in (0, 1] mm"
        )));
    }
    let mut words = vec![
        ("rail-inclination", rail_inclination),
        ("profile-scheme", profile_scheme),
    ];
    if let Some(c) = rail_profile_cant {
        words.push(("rail-profile-cant", c));
    }
    let args = ContactOptions {
        wheel: &wheel,
        rail: &rail,
        numbers: vec![
            ("gauge", gauge_m),
            ("back-to-back", back_to_back_m),
            ("wheel-radius", wheel_radius_m),
        ],
        words,
        rigid: true,
    }
    .parse()?;
    let (curve, dr, warnings) = py
        .detach(|| -> anyhow::Result<_> {
            use preproc::conicity::{
                EN15302_CONTACT_DISTANCE_M, EN15302_NOMINAL_RADIUS_M, conicity_curve,
            };
            let config = args.to_config()?;
            let mut warnings = config.check_rail().map(|c| c.warnings).unwrap_or_default();
            let (model, profile_warnings) = config.model()?;
            warnings.extend(profile_warnings.iter().map(ToString::to_string));
            // The grid reaches 3 mm beyond the largest amplitude (the
            // oscillation's turning points lie inside ±ŷ).
            let half_mm = amplitudes.iter().fold(0.0_f64, |m, a| m.max(*a)) + 3.0;
            let steps = (half_mm / y_step_mm).ceil() as usize;
            let y_m: Vec<f64> = (0..=2 * steps)
                .map(|i| (i as f64 - steps as f64) * y_step_mm * 1e-3)
                .collect();
            let dr = preproc::contact_table::en15302_delta_r(&model, &config, &y_m)?;
            let amplitudes_m: Vec<f64> = amplitudes.iter().map(|a| a * 1e-3).collect();
            let curve = conicity_curve(
                &dr,
                EN15302_CONTACT_DISTANCE_M,
                EN15302_NOMINAL_RADIUS_M,
                &amplitudes_m,
            );
            Ok((curve, dr, warnings))
        })
        .or_value_error()?;
    warn_all(py, &warnings)?;
    let out = PyDict::new(py);
    out.set_item("amplitude_mm", amplitudes.clone().into_pyarray(py))?;
    let tan: Vec<f64> = curve
        .iter()
        .map(|p| p.tan_gamma_e().unwrap_or(f64::NAN))
        .collect();
    let wavelength: Vec<f64> = curve
        .iter()
        .map(|p| p.wavelength_m().unwrap_or(f64::NAN))
        .collect();
    out.set_item("tan_gamma_e", tan.into_pyarray(py))?;
    out.set_item("wavelength_m", wavelength.into_pyarray(py))?;
    let y_mm: Vec<f64> = dr.y_m().iter().map(|y| y * 1e3).collect();
    let dr_mm: Vec<f64> = dr.delta_r_m().iter().map(|d| d * 1e3).collect();
    out.set_item("y_mm", y_mm.into_pyarray(py))?;
    out.set_item("delta_r_mm", dr_mm.into_pyarray(py))?;
    out.set_item(
        "max_amplitude_mm",
        dr.max_amplitude_m().ok().map(|a| a * 1e3),
    )?;
    Ok(out)
}
