//! The answer of `sim contact` for one pose (the stable `--json`
//! interface) and its text form.

use runtime::contact::Candidate;
use runtime::contact::quasi_static::Settled;
use runtime::geometry::track::Side;
use runtime::multibody::loaded_wheelset::{LoadedPatch, LoadedWheelset};
use serde::Serialize;

use super::{ContactSetup, PoseRequest, Rolling, S_WHEELSET_M};

/// The wheelset's pose.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelsetReport {
    /// The pose's number (its row in a poses file, or its `case`).
    pub case: u32,
    /// Height of the wheelset centre above the track plane (m): the mean
    /// of the wheels' heights when the roll is given (each wheel is then
    /// solved at its own height, `WheelReport::height_m`).
    pub z_m: f64,
    /// Roll, positive raising the left wheel (rad).
    pub roll_rad: f64,
    /// True when the roll was solved (not given).
    pub roll_solved: bool,
    /// Lateral shift, positive to the left (m).
    pub y_m: f64,
    /// Yaw, positive turning the nose left (rad).
    pub yaw_rad: f64,
    /// Angular velocity of the axle, positive rolling forward (rad/s).
    pub axle_rate_rad_s: f64,
    /// Forward speed (m/s).
    pub speed_m_s: f64,
    /// Vertical force per wheel (N); null for rigid contact.
    pub load_per_wheel_n: Option<f64>,
    /// `vertical`, `normal`, or `rigid`.
    pub load_convention: &'static str,
}

/// One contact patch of one wheel. Profile coordinates are those of the
/// profile files as given (before mirroring for the left side).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ContactReport {
    /// Patch number on its wheel, 1 = deepest.
    pub patch: u32,
    /// "tread" or "flange".
    pub zone: &'static str,
    /// Lateral position on the rail and on the wheel profile (mm).
    pub y_rail_mm: f64,
    pub y_wheel_mm: f64,
    /// Vertical position on the rail and on the wheel profile (mm).
    pub z_rail_mm: f64,
    pub z_wheel_mm: f64,
    /// The contact point on the rail in the track frame at the wheelset's
    /// section (mm): ahead, to the left, up, from the centreline.
    pub x_track_mm: f64,
    pub y_track_mm: f64,
    pub z_track_mm: f64,
    /// Contact angle in the track cross-section, positive towards the
    /// track centre (rad).
    pub contact_angle_rad: f64,
    /// Penetration (approach) δ (m).
    pub penetration_m: f64,
    /// Rolling radius (m).
    pub rolling_radius_m: f64,
    /// Angle of the contact point about the axle, positive ahead (rad),
    /// and its distance ahead of the axle (m).
    pub s_wheel_rad: f64,
    pub lead_m: f64,
    /// Rail arc length of the contact, relative to the wheelset's section (m).
    pub s_rail_m: f64,
    /// Principal curvatures (1/m), convex positive, at the deepest point
    /// (those the Hertz ellipse uses, also when the patch is reported at its
    /// centre).
    pub wheel_rolling_curvature_1_m: f64,
    pub wheel_lateral_curvature_1_m: f64,
    pub rail_rolling_curvature_1_m: f64,
    pub rail_lateral_curvature_1_m: f64,
    /// Hertzian normal force (N); 0 for rigid contact.
    pub normal_n: f64,
    /// Vertical force of this patch on the wheel, normal and creep forces
    /// (N); 0 for rigid contact.
    pub vertical_n: f64,
    /// "newton" or "minimisation".
    pub method: &'static str,
    /// The geometry is not Hertzian: the normal force comes from the
    /// floored curvatures (docs/reference/07-contact-forces.md §7.1).
    pub hertz_fallback: bool,
    /// Semi-axes of the Hertz ellipse, rolling direction and lateral (m),
    /// and the maximum pressure 3N/(2πab) (Pa); null when there is no force.
    pub a_m: Option<f64>,
    pub b_m: Option<f64>,
    pub pmax_pa: Option<f64>,
    /// Creepages (docs/reference/07-contact-forces.md §7.3): longitudinal,
    /// lateral (dimensionless), spin (1/m); wheel minus rail slip over the
    /// rolling speed.
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
    /// Lateral width of the patch's undeformed interpenetration (m), over
    /// which its centre is taken (docs/reference/06-contact-detection.md
    /// §6.9); null for rigid contact.
    pub overlap_width_m: Option<f64>,
}

/// One wheel's contacts.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelReport {
    pub side: &'static str,
    /// Height of the wheelset centre at which this wheel carries its load (m).
    pub height_m: f64,
    /// Total force of the patches on the wheel in the track frame (N):
    /// forward, left, up.
    pub force_track_n: [f64; 3],
    pub contacts: Vec<ContactReport>,
}

/// The force models used (echoed in the answer).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ForceModelReport {
    pub speed_m_s: f64,
    /// `kalker`, `heuristic`, `polach`, `fastsim`, …
    pub creep_law: &'static str,
    pub friction_coefficient: f64,
    pub young_pa: f64,
    pub poisson: f64,
    pub shear_modulus_pa: f64,
}

/// The whole answer for one pose.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ContactCase {
    pub wheelset: WheelsetReport,
    pub forces: ForceModelReport,
    pub wheels: Vec<WheelReport>,
    /// Warnings: what was dropped from a profile cut to its longest usable
    /// stretch (`--keep-longest-stretch`), and patches without creep forces.
    pub warnings: Vec<String>,
}

fn forces_report(rolling: &Rolling, speed_m_s: f64) -> ForceModelReport {
    let s = &rolling.settings;
    ForceModelReport {
        speed_m_s,
        creep_law: s.creep_law.name(),
        friction_coefficient: s.friction_coefficient,
        young_pa: s.material.young_pa,
        poisson: s.material.poisson,
        shear_modulus_pa: s.material.shear_modulus_pa(),
    }
}

fn geometry_report(setup: &ContactSetup, patch: u32, c: &Candidate) -> ContactReport {
    let (x, y, z) = setup
        .track
        .centerline
        .at(S_WHEELSET_M)
        .map(|p| {
            let d = c.rail_point - p.position;
            (
                d.dot(&p.frame.t.normalize()),
                d.dot(&p.frame.n.normalize()),
                d.dot(&p.frame.b.normalize()),
            )
        })
        .unwrap_or((f64::NAN, f64::NAN, f64::NAN));
    ContactReport {
        patch,
        zone: c.zone.name(),
        y_rail_mm: c.rail_profile_point_m.0 * 1e3,
        y_wheel_mm: c.wheel_profile_point_m.0 * 1e3,
        z_rail_mm: c.rail_profile_point_m.1 * 1e3,
        z_wheel_mm: c.wheel_profile_point_m.1 * 1e3,
        x_track_mm: x * 1e3,
        y_track_mm: y * 1e3,
        z_track_mm: z * 1e3,
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
        normal_n: 0.0,
        vertical_n: 0.0,
        method: match c.method {
            runtime::contact::SolveMethod::Newton => "newton",
            runtime::contact::SolveMethod::Minimisation => "minimisation",
        },
        hertz_fallback: false,
        a_m: None,
        b_m: None,
        pmax_pa: None,
        xi: None,
        eta: None,
        phi_per_m: None,
        fx_n: None,
        fy_n: None,
        mz_nm: None,
        force_error: None,
        overlap_width_m: None,
    }
}

fn patch_report(
    setup: &ContactSetup,
    k: usize,
    p: &LoadedPatch,
    up: &nalgebra::Vector3<f64>,
) -> ContactReport {
    // Position, frame and angle where the patch is: its centre (the
    // penetration reported is the deepest point's δ either way).
    let mut r = geometry_report(setup, k as u32 + 1, &p.centre);
    // The curvatures the Hertz ellipse and the normal force use: those of
    // the gap's minimum, the deepest point (docs/reference/06-contact-detection.md §6.9).
    let deepest = &p.candidate.curvatures;
    r.wheel_rolling_curvature_1_m = deepest.wheel_rolling_1_m;
    r.wheel_lateral_curvature_1_m = deepest.wheel_lateral_1_m;
    r.rail_rolling_curvature_1_m = deepest.rail_rolling_1_m;
    r.rail_lateral_curvature_1_m = deepest.rail_lateral_1_m;
    r.overlap_width_m = p.overlap_width_m;
    r.normal_n = p.normal_n;
    r.vertical_n = p.force_on_wheel_n.dot(up);
    r.hertz_fallback = p.hertz_fallback;
    if let Some(t) = &p.tangential {
        let (a, b) = (t.hertz.a_rolling_m, t.hertz.b_lateral_m);
        r.a_m = Some(a);
        r.b_m = Some(b);
        r.pmax_pa =
            (a > 0.0 && b > 0.0).then(|| 3.0 * p.normal_n / (2.0 * std::f64::consts::PI * a * b));
        r.xi = Some(t.creepages.xi);
        r.eta = Some(t.creepages.eta);
        r.phi_per_m = Some(t.creepages.phi_1_m);
        r.fx_n = Some(t.creep.fx_n);
        r.fy_n = Some(t.creep.fy_n);
        r.mz_nm = Some(t.creep.mz_nm);
    }
    r.force_error = p.force_error.as_ref().map(ToString::to_string);
    r
}

/// The report of a loaded (elastic) pose.
pub(super) fn loaded_case(
    setup: &ContactSetup,
    request: &PoseRequest,
    rolling: &Rolling,
    l: &LoadedWheelset,
) -> ContactCase {
    let up = setup
        .track
        .centerline
        .at(S_WHEELSET_M)
        .map(|p| p.frame.b.normalize())
        .unwrap_or_else(|_| nalgebra::Vector3::z());
    let mut warnings = setup.warnings.clone();
    let wheels: Vec<WheelReport> = l
        .wheels
        .iter()
        .map(|w| {
            let contacts: Vec<ContactReport> = w
                .patches
                .iter()
                .enumerate()
                .map(|(k, p)| patch_report(setup, k, p, &up))
                .collect();
            for (p, c) in w.patches.iter().zip(&contacts) {
                if p.centre_truncated {
                    warnings.push(format!(
                        "pose {}: {} wheel patch {} ({}): the interpenetration reaches the sampled window (±{:.0} mm) or a profile's end; its part beyond is left out of the patch centre",
                        request.case,
                        w.side,
                        c.patch,
                        c.zone,
                        runtime::contact::patch_centre::WINDOW_HALF_WIDTH_M * 1e3
                    ));
                }
                if let Some(e) = &c.force_error {
                    warnings.push(format!(
                        "pose {}: {} wheel patch {} ({}) carries its normal force only: {e}",
                        request.case, w.side, c.patch, c.zone
                    ));
                }
            }
            WheelReport {
                side: w.side.name(),
                height_m: w.height_m,
                force_track_n: w.force_track_n.into(),
                contacts,
            }
        })
        .collect();
    ContactCase {
        wheelset: WheelsetReport {
            case: request.case,
            z_m: 0.5 * (l.wheels[0].height_m + l.wheels[1].height_m),
            roll_rad: l.roll_rad,
            roll_solved: l.roll_solved,
            y_m: l.input.y_m,
            yaw_rad: l.input.yaw_rad,
            axle_rate_rad_s: l.axle_rate_rad_s,
            speed_m_s: l.input.speed_m_s,
            load_per_wheel_n: Some(l.input.load_per_wheel_n[0]),
            load_convention: l.convention.name(),
        },
        forces: forces_report(rolling, l.input.speed_m_s),
        wheels,
        warnings,
    }
}

/// The report of a rigid pose (geometry only).
pub(super) fn rigid_case(
    setup: &ContactSetup,
    request: &PoseRequest,
    rolling: &Rolling,
    speed_m_s: f64,
    st: &Settled,
) -> ContactCase {
    let r0 = 0.5 * (setup.nominal_radius_m(Side::Left) + setup.nominal_radius_m(Side::Right));
    let wheels = Side::BOTH
        .into_iter()
        .map(|side| {
            let mut cands: Vec<&Candidate> = st
                .contacts
                .side(side)
                .filter(|c| c.penetration_m >= -1e-9)
                .collect();
            cands.sort_by(|a, b| b.penetration_m.total_cmp(&a.penetration_m));
            WheelReport {
                side: side.name(),
                height_m: st.height_m,
                force_track_n: [0.0; 3],
                contacts: cands
                    .iter()
                    .enumerate()
                    .map(|(k, c)| geometry_report(setup, k as u32 + 1, c))
                    .collect(),
            }
        })
        .collect();
    ContactCase {
        wheelset: WheelsetReport {
            case: request.case,
            z_m: st.height_m,
            roll_rad: st.roll_rad,
            roll_solved: true,
            y_m: request.y_m,
            yaw_rad: request.yaw_rad,
            axle_rate_rad_s: request.axle_rate_rad_s.unwrap_or(speed_m_s / r0.max(1e-3)),
            speed_m_s,
            load_per_wheel_n: None,
            load_convention: "rigid",
        },
        forces: forces_report(rolling, speed_m_s),
        wheels,
        warnings: setup.warnings.clone(),
    }
}

impl ContactCase {
    /// Human-readable form.
    pub fn to_text(&self) -> String {
        let w = &self.wheelset;
        let mut out: String = self.warnings.iter().map(|w| format!("{w}\n")).collect();
        out += &format!(
            "wheelset  y = {:+.3} mm, yaw = {:+.3} mrad: height {:.6} m, roll {:+.6} rad ({}), axle {:+.5} rad/s\n",
            w.y_m * 1e3,
            w.yaw_rad * 1e3,
            w.z_m,
            w.roll_rad,
            if w.roll_solved { "solved" } else { "given" },
            w.axle_rate_rad_s,
        );
        let f = &self.forces;
        out += &format!(
            "rolling at {} m/s, creep law {}, μ = {}, E = {:.0} GPa, ν = {}; load {} per wheel ({} convention)\n",
            f.speed_m_s,
            f.creep_law,
            f.friction_coefficient,
            f.young_pa * 1e-9,
            f.poisson,
            w.load_per_wheel_n
                .map_or("none".to_string(), |l| format!("{l:.0} N")),
            w.load_convention
        );
        for wheel in &self.wheels {
            out += &format!(
                "{} wheel (height {:.6} m; forces on the wheel: forward {:+.1} N, left {:+.1} N, up {:+.1} N)\n",
                wheel.side,
                wheel.height_m,
                wheel.force_track_n[0],
                wheel.force_track_n[1],
                wheel.force_track_n[2]
            );
            if wheel.contacts.is_empty() {
                out += "  no contact\n";
            }
            for c in &wheel.contacts {
                out += &format!(
                    "  {} {:<6} rail y {:+8.3} mm, wheel y {:+8.3} mm, angle {:+.4} rad ({:+.2}°), δ {:.4} mm, r {:.6} m, lead {:+.2} mm, N {:.0} N\n          curvatures wheel {:+.3}/{:+.3} rail {:+.3}/{:+.3} 1/m (rolling/lateral)\n",
                    c.patch,
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
                    out += &format!("          no creep forces: {e}\n");
                }
            }
        }
        out
    }
}
