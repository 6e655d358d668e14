//! One row per contact patch, in the Manchester contact benchmark's units
//! (mm, rad, N, N·mm): the `--format csv` output of `sim contact` and the
//! table of its text output for many poses. Our axes and signs
//! (docs/guide/contact-benchmark.md "Columns"): track frame forward, left,
//! up; forces on the wheel; the contact frame of each patch.

use serde::Serialize;

use super::ContactCase;

/// One patch of one wheel at one pose.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct PatchRow {
    pub case: u32,
    pub side: &'static str,
    pub patch: u32,
    pub zone: &'static str,
    pub y_ws_mm: f64,
    pub yaw_ws_rad: f64,
    pub roll_ws_rad: f64,
    pub axle_rate_rad_s: f64,
    /// Height of the wheelset centre above the track plane at which this
    /// wheel carries its load (mm).
    pub z_ws_mm: f64,
    /// Contact point on the rail, track frame (mm): ahead, left, up.
    pub x_tr_mm: f64,
    pub y_tr_mm: f64,
    pub z_tr_mm: f64,
    /// Contact point in the rail and wheel profile files' coordinates (mm).
    pub y_rail_mm: f64,
    pub z_rail_mm: f64,
    pub y_wheel_mm: f64,
    pub z_wheel_mm: f64,
    /// Contact angle, positive towards the track centre (rad).
    pub contact_angle_rad: f64,
    pub rolling_radius_mm: f64,
    /// Distance of the contact point ahead of the axle (mm).
    pub lead_mm: f64,
    /// Creepages: longitudinal, lateral (–), spin (1/mm).
    pub xi: Option<f64>,
    pub eta: Option<f64>,
    pub phi_1_mm: Option<f64>,
    /// Normal force (N).
    pub fn_n: f64,
    /// Creep forces on the wheel along t_c and l_c (N); spin moment about
    /// n_c (N·mm).
    pub fx_n: Option<f64>,
    pub fs_n: Option<f64>,
    pub mz_nmm: Option<f64>,
    /// Approach (penetration) δ (mm).
    pub approach_mm: f64,
    /// Hertz semi-axes (mm), maximum pressure (MPa).
    pub a_mm: Option<f64>,
    pub b_mm: Option<f64>,
    pub pmax_mpa: Option<f64>,
    /// Total force of the wheel's patches on the wheel, track frame (N).
    pub wheel_fx_tr_n: f64,
    pub wheel_fy_tr_n: f64,
    pub wheel_fz_tr_n: f64,
    /// Lateral width of the patch's undeformed interpenetration (mm);
    /// empty for rigid contact.
    pub overlap_width_mm: Option<f64>,
}

/// The rows of some poses, in pose order, left wheel first, deepest patch
/// first.
pub fn patch_rows(cases: &[ContactCase]) -> Vec<PatchRow> {
    let mut out = Vec::new();
    for case in cases {
        let w = &case.wheelset;
        for wheel in &case.wheels {
            for c in &wheel.contacts {
                out.push(PatchRow {
                    case: w.case,
                    side: wheel.side,
                    patch: c.patch,
                    zone: c.zone,
                    y_ws_mm: w.y_m * 1e3,
                    yaw_ws_rad: w.yaw_rad,
                    roll_ws_rad: w.roll_rad,
                    axle_rate_rad_s: w.axle_rate_rad_s,
                    z_ws_mm: wheel.height_m * 1e3,
                    x_tr_mm: c.x_track_mm,
                    y_tr_mm: c.y_track_mm,
                    z_tr_mm: c.z_track_mm,
                    y_rail_mm: c.y_rail_mm,
                    z_rail_mm: c.z_rail_mm,
                    y_wheel_mm: c.y_wheel_mm,
                    z_wheel_mm: c.z_wheel_mm,
                    contact_angle_rad: c.contact_angle_rad,
                    rolling_radius_mm: c.rolling_radius_m * 1e3,
                    lead_mm: c.lead_m * 1e3,
                    xi: c.xi,
                    eta: c.eta,
                    phi_1_mm: c.phi_per_m.map(|p| p * 1e-3),
                    fn_n: c.normal_n,
                    fx_n: c.fx_n,
                    fs_n: c.fy_n,
                    mz_nmm: c.mz_nm.map(|m| m * 1e3),
                    approach_mm: c.penetration_m * 1e3,
                    a_mm: c.a_m.map(|a| a * 1e3),
                    b_mm: c.b_m.map(|b| b * 1e3),
                    pmax_mpa: c.pmax_pa.map(|p| p * 1e-6),
                    wheel_fx_tr_n: wheel.force_track_n[0],
                    wheel_fy_tr_n: wheel.force_track_n[1],
                    wheel_fz_tr_n: wheel.force_track_n[2],
                    overlap_width_mm: c.overlap_width_m.map(|w| w * 1e3),
                });
            }
        }
    }
    out
}

/// Column names of [`rows_csv`], in order.
pub const CSV_COLUMNS: [&str; 34] = [
    "case",
    "side",
    "patch",
    "zone",
    "y_ws_mm",
    "yaw_ws_rad",
    "roll_ws_rad",
    "axle_rate_rad_s",
    "z_ws_mm",
    "x_tr_mm",
    "y_tr_mm",
    "z_tr_mm",
    "y_rail_mm",
    "z_rail_mm",
    "y_wheel_mm",
    "z_wheel_mm",
    "contact_angle_rad",
    "rolling_radius_mm",
    "lead_mm",
    "xi",
    "eta",
    "phi_1_mm",
    "fn_n",
    "fx_n",
    "fs_n",
    "mz_nmm",
    "approach_mm",
    "a_mm",
    "b_mm",
    "pmax_mpa",
    "wheel_fx_tr_n",
    "wheel_fy_tr_n",
    "wheel_fz_tr_n",
    "overlap_width_mm",
];

/// The rows as CSV with a header (a missing value is an empty field).
pub fn rows_csv(rows: &[PatchRow]) -> String {
    let names = CSV_COLUMNS;
    let mut out = names.join(",") + "\n";
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v}"));
    for r in rows {
        let fields = [
            r.case.to_string(),
            r.side.to_string(),
            r.patch.to_string(),
            r.zone.to_string(),
            format!("{}", r.y_ws_mm),
            format!("{}", r.yaw_ws_rad),
            format!("{}", r.roll_ws_rad),
            format!("{}", r.axle_rate_rad_s),
            format!("{}", r.z_ws_mm),
            format!("{}", r.x_tr_mm),
            format!("{}", r.y_tr_mm),
            format!("{}", r.z_tr_mm),
            format!("{}", r.y_rail_mm),
            format!("{}", r.z_rail_mm),
            format!("{}", r.y_wheel_mm),
            format!("{}", r.z_wheel_mm),
            format!("{}", r.contact_angle_rad),
            format!("{}", r.rolling_radius_mm),
            format!("{}", r.lead_mm),
            opt(r.xi),
            opt(r.eta),
            opt(r.phi_1_mm),
            format!("{}", r.fn_n),
            opt(r.fx_n),
            opt(r.fs_n),
            opt(r.mz_nmm),
            format!("{}", r.approach_mm),
            opt(r.a_mm),
            opt(r.b_mm),
            opt(r.pmax_mpa),
            format!("{}", r.wheel_fx_tr_n),
            format!("{}", r.wheel_fy_tr_n),
            format!("{}", r.wheel_fz_tr_n),
            opt(r.overlap_width_mm),
        ];
        debug_assert_eq!(fields.len(), names.len());
        out += &fields.join(",");
        out.push('\n');
    }
    out
}

/// A compact table of the rows for the terminal and the docs.
pub fn rows_table(rows: &[PatchRow]) -> String {
    let mut out = String::from(
        "case side  p zone    y_ws   yaw_ws    y_tr     y_rail  y_wheel  angle    FN       Fx       Fs       ξ          η          φ\n\
         \x20               mm     mrad      mm       mm      mm       rad      N        N        N                             1/mm\n",
    );
    let opt = |v: Option<f64>, p: usize| v.map_or("—".to_string(), |v| format!("{v:+.p$}"));
    let opt_e = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:+.3e}"));
    for r in rows {
        out += &format!(
            "{:>4} {:<5} {} {:<6} {:>6.2} {:>7.2} {:>8.2} {:>8.2} {:>8.2} {:>+7.4} {:>8.0} {:>8} {:>8} {:>10} {:>10} {:>10}\n",
            r.case,
            r.side,
            r.patch,
            r.zone,
            r.y_ws_mm,
            r.yaw_ws_rad * 1e3,
            r.y_tr_mm,
            r.y_rail_mm,
            r.y_wheel_mm,
            r.contact_angle_rad,
            r.fn_n,
            opt(r.fx_n, 0),
            opt(r.fs_n, 0),
            opt_e(r.xi),
            opt_e(r.eta),
            opt_e(r.phi_1_mm),
        );
    }
    out
}
