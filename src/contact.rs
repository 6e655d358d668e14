//! `sim contact`: the contact of a wheelset at a prescribed pose on a
//! straight track, without building a table file — the wheelset's height
//! and roll solved so that each wheel carries the load (as in the
//! Manchester contact benchmark), or rigid contact.

use anyhow::{Context, Result};
use preproc::contact_table::{ContactTableConfig, TableSupport};
use runtime::contact::quasi_static::{Settled, Support, settle};
use runtime::contact::{Candidate, ContactOptions, ContactSolver, FlangeSearch};
use runtime::hertz::Material;
use runtime::track::{Side, straight_track};
use serde::Serialize;

/// The wheelset's settled pose.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelsetReport {
    /// Height of the wheelset centre above the track plane (m).
    pub z_m: f64,
    /// Roll, positive raising the left wheel (rad).
    pub roll_rad: f64,
    /// Lateral shift, positive to the left (m).
    pub y_m: f64,
    /// Yaw, positive turning the nose left (rad).
    pub yaw_rad: f64,
}

/// One contact of one wheel. Profile coordinates are those of the profile
/// files as given (before mirroring for the left side).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ContactReport {
    /// "tread" or "flange".
    pub zone: &'static str,
    /// Lateral position on the rail and on the wheel profile (mm).
    pub y_rail_mm: f64,
    pub y_wheel_mm: f64,
    /// Vertical position on the rail and on the wheel profile (mm).
    pub z_rail_mm: f64,
    pub z_wheel_mm: f64,
    /// Contact angle in the track cross-section, positive towards the
    /// track centre (rad).
    pub contact_angle_rad: f64,
    /// Penetration δ (m).
    pub penetration_m: f64,
    /// Rolling radius (m).
    pub rolling_radius_m: f64,
    /// Angle of the contact point about the axle, positive ahead (rad),
    /// and its distance ahead of the axle (m).
    pub s_wheel_rad: f64,
    pub lead_m: f64,
    /// Rail arc length of the contact, relative to the wheelset's section (m).
    pub s_rail_m: f64,
    /// Principal curvatures (1/m), convex positive.
    pub wheel_rolling_curvature_1_m: f64,
    pub wheel_lateral_curvature_1_m: f64,
    pub rail_rolling_curvature_1_m: f64,
    pub rail_lateral_curvature_1_m: f64,
    /// Hertzian normal force (N); 0 for rigid contact.
    pub normal_n: f64,
    /// "newton" or "minimisation".
    pub method: &'static str,
}

/// One wheel's contacts.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelReport {
    pub side: &'static str,
    pub contacts: Vec<ContactReport>,
}

/// The whole answer (the stable `--json` interface).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ContactCase {
    pub wheelset: WheelsetReport,
    pub wheels: Vec<WheelReport>,
}

/// Track section where the wheelset is placed on the in-memory track (m).
const S_WHEELSET_M: f64 = 5.0;

fn report(c: &Candidate, normal_n: f64) -> ContactReport {
    ContactReport {
        zone: c.zone.name(),
        y_rail_mm: c.rail_profile_point_m.0 * 1e3,
        y_wheel_mm: c.wheel_profile_point_m.0 * 1e3,
        z_rail_mm: c.rail_profile_point_m.1 * 1e3,
        z_wheel_mm: c.wheel_profile_point_m.1 * 1e3,
        contact_angle_rad: c.contact_angle_rad,
        penetration_m: c.penetration_m,
        rolling_radius_m: c.rolling_radius_m,
        s_wheel_rad: c.params.s_wheel_rad,
        lead_m: c.lead_m(),
        s_rail_m: c.params.s_rail_m - S_WHEELSET_M,
        wheel_rolling_curvature_1_m: c.curvatures.wheel_rolling_1_m,
        wheel_lateral_curvature_1_m: c.curvatures.wheel_lateral_1_m,
        rail_rolling_curvature_1_m: c.curvatures.rail_rolling_1_m,
        rail_lateral_curvature_1_m: c.curvatures.rail_lateral_1_m,
        normal_n,
        method: match c.method {
            runtime::contact::SolveMethod::Newton => "newton",
            runtime::contact::SolveMethod::Minimisation => "minimisation",
        },
    }
}

/// Settle the wheelset of `config` (profiles, gauge, inclination, support)
/// at lateral shift `y_m` and yaw `yaw_rad`.
pub fn contact_case(
    config: &ContactTableConfig,
    y_m: f64,
    yaw_rad: f64,
) -> Result<(ContactCase, Settled)> {
    config.validate()?;
    let model = config.model()?;
    let track = straight_track(
        2.0 * S_WHEELSET_M,
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
    let mut solver = ContactSolver::new(ContactOptions {
        flange: FlangeSearch::On,
        ..Default::default()
    });
    let st = settle(
        &model,
        &track,
        S_WHEELSET_M,
        y_m,
        yaw_rad,
        support,
        &mut solver,
    )
    .with_context(|| {
        format!(
            "settling the wheelset at y = {:.2} mm, yaw = {:.2} mrad",
            y_m * 1e3,
            yaw_rad * 1e3
        )
    })?;
    let wheels = Side::BOTH
        .into_iter()
        .enumerate()
        .map(|(w, side)| WheelReport {
            side: side.name(),
            contacts: st.contacts.candidates[w]
                .iter()
                .zip(&st.normal_force_n[w])
                .filter_map(|(c, f)| c.as_ref().map(|c| (c, *f)))
                .filter(|(c, _)| c.penetration_m >= -1e-9)
                .map(|(c, f)| report(c, f))
                .collect(),
        })
        .collect();
    Ok((
        ContactCase {
            wheelset: WheelsetReport {
                z_m: st.height_m,
                roll_rad: st.roll_rad,
                y_m,
                yaw_rad,
            },
            wheels,
        },
        st,
    ))
}

impl ContactCase {
    /// Human-readable form.
    pub fn to_text(&self) -> String {
        let w = &self.wheelset;
        let mut out = format!(
            "wheelset  y = {:+.3} mm, yaw = {:+.3} mrad: height {:.6} m, roll {:+.6} rad\n",
            w.y_m * 1e3,
            w.yaw_rad * 1e3,
            w.z_m,
            w.roll_rad
        );
        for wheel in &self.wheels {
            out += &format!("{} wheel\n", wheel.side);
            if wheel.contacts.is_empty() {
                out += "  no contact\n";
            }
            for c in &wheel.contacts {
                out += &format!(
                    "  {:<6} rail y {:+8.3} mm, wheel y {:+8.3} mm, angle {:+.4} rad ({:+.2}°), δ {:.4} mm, r {:.6} m, lead {:+.2} mm, N {:.0} N\n          curvatures wheel {:+.3}/{:+.3} rail {:+.3}/{:+.3} 1/m (rolling/lateral)\n",
                    c.zone,
                    c.y_rail_mm,
                    c.y_wheel_mm,
                    c.contact_angle_rad,
                    c.contact_angle_rad.to_degrees(),
                    c.penetration_m * 1e3,
                    c.rolling_radius_m,
                    c.lead_m * 1e3,
                    c.normal_n,
                    c.wheel_rolling_curvature_1_m,
                    c.wheel_lateral_curvature_1_m,
                    c.rail_rolling_curvature_1_m,
                    c.rail_lateral_curvature_1_m
                );
            }
        }
        out
    }
}

/// Material helper for the CLI.
pub fn material(young_pa: f64, poisson: f64) -> Material {
    Material { young_pa, poisson }
}
