//! `sim contact`: the contact of a wheelset at a prescribed pose on a
//! straight track, without building a table file — the wheelset's height
//! and roll solved so that each wheel carries the load (as in the
//! Manchester contact benchmark), or rigid contact — and, for a wheelset
//! rolling at a given speed, the contact forces of each contact: Hertz
//! ellipse, creepages and the creep forces of the chosen law
//! (`runtime::multibody::contact_force`).

use anyhow::{Context, Result};
use preproc::contact_table::{ContactTableConfig, TableSupport};
use runtime::contact::quasi_static::{Settled, Support, settle};
use runtime::contact::{Candidate, ContactOptions, ContactSolver, FlangeSearch};
use runtime::forces::hertz::Material;
use runtime::geometry::track::{Side, straight_track};
use runtime::multibody::contact_force::{
    ContactForceSettings, WheelsetMotion, contact_creepages, hertz_shape, tangential_forces,
};
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
    /// Semi-axes of the Hertz ellipse, rolling direction and lateral (m);
    /// null when there is no force (rigid) or the geometry is not Hertzian.
    pub a_m: Option<f64>,
    pub b_m: Option<f64>,
    /// Creepages (docs/reference/07-contact-forces.md §7.3): longitudinal, lateral (dimensionless), spin
    /// (1/m); wheel minus rail slip over the rolling speed.
    pub xi: Option<f64>,
    pub eta: Option<f64>,
    pub phi_per_m: Option<f64>,
    /// Creep forces on the wheel in the contact frame (N): along the
    /// rolling direction t_c and the lateral l_c = n_c × t_c; spin moment
    /// about the normal n_c (N·m).
    pub fx_n: Option<f64>,
    pub fy_n: Option<f64>,
    pub mz_nm: Option<f64>,
    /// Why the forces are missing, when they are (e.g. non-Hertzian
    /// geometry).
    pub force_error: Option<String>,
}

/// The wheelset's motion and the force models of `sim contact`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rolling {
    /// Forward speed along the track (m/s); the wheelset spins at V/r₀.
    pub speed_m_s: f64,
    pub settings: ContactForceSettings,
}

/// One wheel's contacts.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelReport {
    pub side: &'static str,
    pub contacts: Vec<ContactReport>,
}

/// The force models used (echoed in the answer).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ForceModelReport {
    pub speed_m_s: f64,
    /// `kalker`, `heuristic`, `polach` or `fastsim`.
    pub creep_law: &'static str,
    pub friction_coefficient: f64,
    pub young_pa: f64,
    pub poisson: f64,
    pub shear_modulus_pa: f64,
}

/// The whole answer (the stable `--json` interface).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ContactCase {
    pub wheelset: WheelsetReport,
    pub forces: ForceModelReport,
    pub wheels: Vec<WheelReport>,
    /// Warnings of the profiles: what was dropped from a profile cut to its
    /// longest usable stretch (`--keep-longest-stretch`).
    pub warnings: Vec<String>,
}

/// Track section where the wheelset is placed on the in-memory track (m).
const S_WHEELSET_M: f64 = 5.0;

fn report(
    c: &Candidate,
    normal_n: f64,
    rolling: &Rolling,
    motion: &WheelsetMotion,
) -> ContactReport {
    let mut r = geometry_report(c, normal_n);
    if normal_n <= 0.0 {
        return r;
    }
    let settings = &rolling.settings;
    let forces = hertz_shape(c).and_then(|shape| {
        let creepages = contact_creepages(settings, c, motion)?;
        tangential_forces(settings, c, &shape, normal_n, &creepages)
    });
    match forces {
        Ok(t) => {
            r.a_m = Some(t.hertz.a_rolling_m);
            r.b_m = Some(t.hertz.b_lateral_m);
            r.xi = Some(t.creepages.xi);
            r.eta = Some(t.creepages.eta);
            r.phi_per_m = Some(t.creepages.phi_1_m);
            r.fx_n = Some(t.creep.fx_n);
            r.fy_n = Some(t.creep.fy_n);
            r.mz_nm = Some(t.creep.mz_nm);
        }
        Err(e) => r.force_error = Some(e.to_string()),
    }
    r
}

fn geometry_report(c: &Candidate, normal_n: f64) -> ContactReport {
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
        a_m: None,
        b_m: None,
        xi: None,
        eta: None,
        phi_per_m: None,
        fx_n: None,
        fy_n: None,
        mz_nm: None,
        force_error: None,
    }
}

/// Settle the wheelset of `config` (profiles, gauge, inclination, support)
/// at lateral shift `y_m` and yaw `yaw_rad`, and evaluate the contact
/// forces of the wheelset rolling as `rolling` says.
pub fn contact_case(
    config: &ContactTableConfig,
    y_m: f64,
    yaw_rad: f64,
    rolling: &Rolling,
) -> Result<(ContactCase, Settled)> {
    config.validate()?;
    rolling.settings.validate()?;
    if !(rolling.speed_m_s.is_finite() && rolling.speed_m_s >= 0.0) {
        anyhow::bail!(
            "speed must be finite and >= 0 m/s, got {}",
            rolling.speed_m_s
        );
    }
    let (model, warnings) = config.model()?;
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
    // Rolling along the track tangent at the wheelset's section, spinning
    // at V/r₀ about the axle (r₀ = the nominal rolling radius).
    let forward = track
        .centerline
        .at(S_WHEELSET_M)
        .context("track frame at the wheelset")?
        .frame
        .t
        .normalize();
    let motion = WheelsetMotion::rolling(
        st.pose.position,
        forward,
        st.pose.axle(),
        rolling.speed_m_s,
        config.wheel_radius_m,
    );
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
                .map(|(c, f)| report(c, f, rolling, &motion))
                .collect(),
        })
        .collect();
    let s = &rolling.settings;
    Ok((
        ContactCase {
            wheelset: WheelsetReport {
                z_m: st.height_m,
                roll_rad: st.roll_rad,
                y_m,
                yaw_rad,
            },
            forces: ForceModelReport {
                speed_m_s: rolling.speed_m_s,
                creep_law: s.creep_law.name(),
                friction_coefficient: s.friction_coefficient,
                young_pa: s.material.young_pa,
                poisson: s.material.poisson,
                shear_modulus_pa: s.material.shear_modulus_pa(),
            },
            wheels,
            warnings: warnings.iter().map(ToString::to_string).collect(),
        },
        st,
    ))
}

impl ContactCase {
    /// Human-readable form.
    pub fn to_text(&self) -> String {
        let w = &self.wheelset;
        let mut out: String = self.warnings.iter().map(|w| format!("{w}\n")).collect();
        out += &format!(
            "wheelset  y = {:+.3} mm, yaw = {:+.3} mrad: height {:.6} m, roll {:+.6} rad\n",
            w.y_m * 1e3,
            w.yaw_rad * 1e3,
            w.z_m,
            w.roll_rad
        );
        let f = &self.forces;
        out += &format!(
            "rolling at {} m/s, creep law {}, μ = {}, E = {:.0} GPa, ν = {}\n",
            f.speed_m_s,
            f.creep_law,
            f.friction_coefficient,
            f.young_pa * 1e-9,
            f.poisson
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
                if let (Some(a), Some(b), Some(xi), Some(eta), Some(phi)) =
                    (c.a_m, c.b_m, c.xi, c.eta, c.phi_per_m)
                {
                    out += &format!(
                        "          ellipse a {:.3} mm, b {:.3} mm; creepages ξ {:+.4e}, η {:+.4e}, φ {:+.4e} 1/m\n",
                        a * 1e3,
                        b * 1e3,
                        xi,
                        eta,
                        phi
                    );
                }
                if let (Some(fx), Some(fy), Some(mz)) = (c.fx_n, c.fy_n, c.mz_nm) {
                    out += &format!(
                        "          creep forces on the wheel Fx {:+.1} N, Fy {:+.1} N, Mz {:+.3} N·m (contact frame)\n",
                        fx, fy, mz
                    );
                }
                if let Some(e) = &c.force_error {
                    out += &format!("          no forces: {e}\n");
                }
            }
        }
        out
    }
}

/// Material helper for the CLI.
pub fn material(young_pa: f64, poisson: f64) -> Material {
    Material { young_pa, poisson }
}
