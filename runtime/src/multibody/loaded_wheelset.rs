//! A wheelset posed on the rails under a prescribed vertical load per
//! wheel: the quasi-static contact evaluator behind `sim contact`
//! (docs/reference/07-contact-forces.md §7.8), set up as the Manchester
//! contact benchmark poses a wheelset (Shackleton & Iwnicki, VSD 46(2),
//! 2008, case ).
//!
//! Given: lateral shift, yaw, optionally the roll and the angular velocity
//! of the axle, the forward speed and the vertical force each wheel
//! carries. Solved: the vertical position (and the roll when it is not
//! given) at which each wheel carries its load, every patch's normal force
//! (Hertz, N = K δ^1.5), its creepages and its creep forces — together,
//! since with the `vertical` convention the creep forces carry part of the
//! load.
//!
//! * Roll given: each wheel is solved on its own, the wheelset lowered
//!   until that wheel carries its load (its own height; the two heights
//!   differ a little, as in CONTACT's treatment of the benchmark, where the
//!   left and the right wheel are two separate problems).
//! * Roll not given: one height and the roll are solved together so that
//!   both wheels carry their loads.
//!
//! Where a patch is: at the deepest point by default; with
//! [`PatchLocation::Centre`] (the default of `sim contact`) at its
//! **centre**, the centroid of the undeformed interpenetration volume
//! ([`crate::contact::patch_centre()`], docs/reference/06-contact-detection.md
//! §6.9), as CONTACT reports its contact reference location; the normal
//! force and the Hertz ellipse come from the deepest point (δ and the
//! curvatures of the gap's minimum, the quadratic expansion Hertz's theory
//! is built on), the contact frame, position and creepages from the centre.
//! [`PatchLocation::DeepestPoint`] (the default) keeps everything at the
//! deepest point.
//!
//! Axes: the track frame (`t` forward, `n` lateral pointing left, `b` up;
//! docs/reference/01-units-frames.md §1); forces are those **on the
//! wheel**; the contact frame of each patch is the candidate's (normal
//! from rail into wheel, `t_c` rolling, `l_c = n_c × t_c`).

use nalgebra::Vector3;

use crate::contact::{
    Candidate, ContactError, ContactSolver, WheelsetContactModel, WheelsetContacts, WheelsetPose,
    patch_centre,
};
use crate::forces::hertz::HertzShape;
use crate::geometry::track::{Side, TrackTables};

use super::contact_force::{
    ContactForceError, ContactForceSettings, NonHertzianPolicy, TangentialContact, WheelsetMotion,
    contact_creepages, hertz_shape_with_policy, tangential_forces,
};

/// What the prescribed vertical force per wheel balances
/// (docs/reference/07-contact-forces.md §7.8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LoadConvention {
    /// The vertical components of the normal **and** the tangential forces
    /// of all the wheel's patches together (the benchmark's definition; the
    /// creep forces are solved with the normal forces).
    #[default]
    Vertical,
    /// The vertical components of the normal forces alone (N·cos δ summed
    /// over the patches); the creep forces are evaluated afterwards and do
    /// not change the normal forces.
    Normal,
}

impl LoadConvention {
    /// `vertical` or `normal`.
    pub fn name(self) -> &'static str {
        match self {
            LoadConvention::Vertical => "vertical",
            LoadConvention::Normal => "normal",
        }
    }
}

impl std::str::FromStr for LoadConvention {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "vertical" => Ok(Self::Vertical),
            "normal" => Ok(Self::Normal),
            other => Err(format!(
                "load convention '{other}' is not vertical or normal"
            )),
        }
    }
}

/// Where each patch's position, contact frame and creepages are taken
/// (docs/reference/06-contact-detection.md §6.9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PatchLocation {
    /// The centroid of the patch's undeformed interpenetration volume
    /// (where the pressure's resultant lies, and the contact reference
    /// location CONTACT reports; identical to the deepest point for a
    /// Hertzian, quadratic gap). The default of `sim contact`.
    Centre,
    /// The point of maximum penetration (the solution of the contact
    /// equations), as the time-stepping runs use it: the library's
    /// default.
    #[default]
    DeepestPoint,
}

impl PatchLocation {
    /// `centre` or `deepest`.
    pub fn name(self) -> &'static str {
        match self {
            PatchLocation::Centre => "centre",
            PatchLocation::DeepestPoint => "deepest",
        }
    }
}

impl std::str::FromStr for PatchLocation {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "centre" | "center" => Ok(Self::Centre),
            "deepest" => Ok(Self::DeepestPoint),
            other => Err(format!("patch location '{other}' is not centre or deepest")),
        }
    }
}

/// One pose to evaluate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseInput {
    /// Track distance of the wheelset centre (m).
    pub s_m: f64,
    /// Lateral shift of the wheelset centre, positive to the left (m).
    pub y_m: f64,
    /// Yaw about the track normal, positive turning the nose left (rad).
    pub yaw_rad: f64,
    /// Roll about the wheelset's longitudinal axis, positive raising the
    /// left wheel (rad); `None`: solved so that both wheels carry their load.
    pub roll_rad: Option<f64>,
    /// Angular velocity of the axle about itself, positive rolling forward
    /// (rad/s); `None`: V/r₀ with r₀ the wheels' mean nominal radius.
    pub axle_rate_rad_s: Option<f64>,
    /// Forward speed along the track (m/s).
    pub speed_m_s: f64,
    /// Vertical force carried by the left and the right wheel (N).
    pub load_per_wheel_n: [f64; 2],
}

/// Why a loaded pose could not be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LoadedPoseError {
    #[error(transparent)]
    Contact(#[from] ContactError),
    #[error("pose input {what} = {value}: {rule}")]
    Invalid {
        what: &'static str,
        value: f64,
        rule: &'static str,
    },
    #[error(
        "no contact candidate on the {side} wheel at y = {y_mm:.2} mm, yaw = {yaw_mrad:.2} mrad: the wheel is off its rail"
    )]
    OffRail {
        side: Side,
        y_mm: f64,
        yaw_mrad: f64,
    },
    #[error(
        "the {what} could not be solved at y = {y_mm:.2} mm, yaw = {yaw_mrad:.2} mrad after {iterations} iterations (load residual {residual_n:.1} N){detail}"
    )]
    NotSettled {
        what: &'static str,
        y_mm: f64,
        yaw_mrad: f64,
        iterations: u32,
        residual_n: f64,
        detail: String,
    },
}

/// One contact patch with its forces.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedPatch {
    /// The deepest point: the solution of the contact equations, whose
    /// penetration δ and curvatures give the normal force and the ellipse.
    pub candidate: Candidate,
    /// Where the patch is reported and its forces act: position, contact
    /// frame (the direction of the normal and creep forces), angle,
    /// rolling radius and creepages. The patch centre with
    /// [`PatchLocation::Centre`] (its `penetration_m` is the deepest δ),
    /// a copy of `candidate` with [`PatchLocation::DeepestPoint`].
    pub centre: Candidate,
    /// Lateral width of the patch's undeformed interpenetration in the
    /// rail's cross-section (m); `None` with [`PatchLocation::DeepestPoint`].
    pub overlap_width_m: Option<f64>,
    /// The interpenetration reached the sampled window
    /// ([`crate::contact::patch_centre::WINDOW_HALF_WIDTH_M`]) or a
    /// profile's end: the part beyond is not in the centre (reported as a
    /// warning by `sim contact`).
    pub centre_truncated: bool,
    /// Normal force N = K δ^1.5 (N).
    pub normal_n: f64,
    /// Ellipse, creepages and creep forces; `None` when they could not be
    /// evaluated (`force_error` says why; the patch then carries its normal
    /// force only).
    pub tangential: Option<TangentialContact>,
    pub force_error: Option<ContactForceError>,
    /// The geometry is not Hertzian and the stiffness (and, with
    /// [`NonHertzianPolicy::Floor`], the ellipse) comes from the floored
    /// curvatures ([`super::contact_force::NON_HERTZIAN_FLOOR_1_M`]).
    pub hertz_fallback: bool,
    /// N n_c + Fx t_c + Fy l_c (N, global), the contact frame of `centre`.
    pub force_on_wheel_n: Vector3<f64>,
}

/// One wheel at its solved position.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedWheel {
    pub side: Side,
    /// The pose this wheel was solved at (its own height when the roll is
    /// given).
    pub pose: WheelsetPose,
    /// Height of the wheelset centre above the track plane (m).
    pub height_m: f64,
    /// Patches in contact, deepest first.
    pub patches: Vec<LoadedPatch>,
    /// Sum of the patches' forces on the wheel in the track frame
    /// (t, n, b) at the wheelset's section (N).
    pub force_track_n: Vector3<f64>,
}

/// The solved pose.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedWheelset {
    pub input: PoseInput,
    pub convention: LoadConvention,
    pub location: PatchLocation,
    /// The roll used (given, or solved) (rad).
    pub roll_rad: f64,
    pub roll_solved: bool,
    /// The axle's angular velocity used (rad/s).
    pub axle_rate_rad_s: f64,
    pub wheels: [LoadedWheel; 2],
    /// Newton iterations of the solve (both wheels).
    pub iterations: u32,
}

/// Residual tolerance of the solve, as an effective penetration (m): the
/// load is matched to about 1e-7 relative.
const TOLERANCE_M: f64 = 1e-11;
/// Largest change of the height per iteration (m) and of the roll (rad).
const MAX_DZ_M: f64 = 1e-3;
const MAX_DROLL_RAD: f64 = 2e-3;
const MAX_ITERATIONS: u32 = 60;
/// Finite-difference step of the Jacobian (m, rad).
const FD_STEP: f64 = 1e-8;

/// Plausible bounds of the inputs (a unit slip is refused).
const MAX_SHIFT_M: f64 = 0.05;
const MAX_ANGLE_RAD: f64 = 0.1;
const MAX_LOAD_N: f64 = 5e5;

struct WheelEval {
    patches: Vec<LoadedPatch>,
    /// Vertical force carried (N), by the convention.
    vertical_n: f64,
    /// Vertical stiffness scale K·cos of the main patch (N/m^1.5).
    k_ref: f64,
    /// Largest penetration of the wheel's candidates (m), negative = gap.
    deepest_m: f64,
}

impl WheelEval {
    /// The residual as an effective penetration (m): nearly linear in the
    /// height, so Newton's method converges from the first touch on.
    fn residual_m(&self, load_n: f64) -> f64 {
        let eff = |f: f64| f.signum() * (f.abs() / self.k_ref).powf(2.0 / 3.0);
        let now = if self.vertical_n > 0.0 {
            eff(self.vertical_n)
        } else {
            self.deepest_m
        };
        now - eff(load_n)
    }
}

struct Context<'a> {
    model: &'a WheelsetContactModel,
    track: &'a TrackTables,
    settings: &'a ContactForceSettings,
    input: &'a PoseInput,
    convention: LoadConvention,
    location: PatchLocation,
    axle_rate_rad_s: f64,
    forward: Vector3<f64>,
    up: Vector3<f64>,
}

impl Context<'_> {
    fn pose(&self, z_m: f64, roll_rad: f64) -> Result<WheelsetPose, LoadedPoseError> {
        let i = self.input;
        Ok(
            WheelsetPose::on_track(self.track, i.s_m, i.y_m, z_m, i.yaw_rad, roll_rad)
                .map_err(ContactError::from)?,
        )
    }

    fn off_rail(&self, side: Side) -> LoadedPoseError {
        LoadedPoseError::OffRail {
            side,
            y_mm: self.input.y_m * 1e3,
            yaw_mrad: self.input.yaw_rad * 1e3,
        }
    }

    /// Both wheels' contacts and forces at a pose.
    fn eval(
        &self,
        solver: &mut ContactSolver,
        pose: &WheelsetPose,
    ) -> Result<[WheelEval; 2], LoadedPoseError> {
        let contacts = solver.solve(self.model, self.track, pose)?;
        let motion = self.motion(pose);
        Ok([
            self.wheel(&contacts, pose, &motion, Side::Left)?,
            self.wheel(&contacts, pose, &motion, Side::Right)?,
        ])
    }

    /// One wheel's contacts and forces at a pose (the other wheel's forces,
    /// and its patch centres, are not computed: with the roll given each
    /// wheel is solved on its own).
    fn eval_side(
        &self,
        solver: &mut ContactSolver,
        pose: &WheelsetPose,
        side: Side,
    ) -> Result<WheelEval, LoadedPoseError> {
        let contacts = solver.solve(self.model, self.track, pose)?;
        self.wheel(&contacts, pose, &self.motion(pose), side)
    }

    fn motion(&self, pose: &WheelsetPose) -> WheelsetMotion {
        WheelsetMotion {
            centre_m: pose.position,
            velocity_m_s: self.forward * self.input.speed_m_s,
            angular_velocity_rad_s: pose.axle() * self.axle_rate_rad_s,
            forward_speed_m_s: self.input.speed_m_s,
        }
    }

    fn wheel(
        &self,
        contacts: &WheelsetContacts,
        pose: &WheelsetPose,
        motion: &WheelsetMotion,
        side: Side,
    ) -> Result<WheelEval, LoadedPoseError> {
        let cands: Vec<&Candidate> = contacts.side(side).collect();
        if cands.is_empty() {
            return Err(self.off_rail(side));
        }
        let deepest_m = cands
            .iter()
            .map(|c| c.penetration_m)
            .fold(f64::NEG_INFINITY, f64::max);
        let mut patches = Vec::new();
        let mut k_ref = 0.0;
        let mut best = f64::NEG_INFINITY;
        for c in cands {
            let (patch, k) = self.patch(c, pose, motion)?;
            let cos = patch.centre.normal.dot(&self.up).max(1e-3);
            let weight = if c.in_contact() {
                patch.normal_n * cos
            } else {
                c.penetration_m
            };
            if weight > best {
                best = weight;
                k_ref = k * cos;
            }
            if c.in_contact() {
                patches.push(patch);
            }
        }
        patches.sort_by(|a, b| {
            b.candidate
                .penetration_m
                .total_cmp(&a.candidate.penetration_m)
        });
        let vertical_n = patches
            .iter()
            .map(|p| match self.convention {
                LoadConvention::Vertical => p.force_on_wheel_n.dot(&self.up),
                LoadConvention::Normal => p.normal_n * p.centre.normal.dot(&self.up),
            })
            .sum();
        Ok(WheelEval {
            patches,
            vertical_n,
            k_ref,
            deepest_m,
        })
    }

    /// A candidate's forces and its Hertz stiffness (N/m^1.5): normal force
    /// and ellipse from the deepest point `c`, frame and creepages at the
    /// patch's location (see the module docs).
    fn patch(
        &self,
        c: &Candidate,
        pose: &WheelsetPose,
        motion: &WheelsetMotion,
    ) -> Result<(LoadedPatch, f64), LoadedPoseError> {
        let s = self.settings;
        let located = match self.location {
            PatchLocation::Centre if c.in_contact() => {
                patch_centre(self.model, self.track, pose, c)?
            }
            _ => None,
        };
        let (centre, overlap_width_m, centre_truncated) = match located {
            Some(pc) => (pc.candidate, Some(pc.overlap_width_m), pc.truncated),
            None => (*c, None, false),
        };
        // The stiffness always exists (floored where the geometry is not
        // Hertzian: the normal force of a conformal patch is then an
        // estimate, flagged); the ellipse and creep forces follow the
        // settings' policy.
        let floored = hertz_shape_with_policy(c, NonHertzianPolicy::Floor);
        let (k, hertz_fallback) = match &floored {
            Ok((shape, fallback)) => (shape.stiffness_n_m15(&s.material), *fallback),
            Err(_) => (floor_stiffness(s), true),
        };
        let normal_n = k * c.penetration_m.max(0.0).powf(1.5);
        let mut patch = LoadedPatch {
            candidate: *c,
            centre,
            overlap_width_m,
            centre_truncated,
            normal_n,
            tangential: None,
            force_error: None,
            hertz_fallback,
            force_on_wheel_n: centre.normal * normal_n,
        };
        if !c.in_contact() {
            return Ok((patch, k));
        }
        let forces = hertz_shape_with_policy(c, s.non_hertzian).and_then(|(shape, _)| {
            let creepages = contact_creepages(s, &centre, motion)?;
            tangential_forces(s, &centre, &shape, normal_n, &creepages)
        });
        match forces {
            Ok(t) => {
                patch.force_on_wheel_n +=
                    centre.tangent * t.creep.fx_n + centre.lateral * t.creep.fy_n;
                patch.tangential = Some(t);
            }
            Err(e) => patch.force_error = Some(e),
        }
        Ok((patch, k))
    }
}

/// Stiffness of the floored curvatures where even the floored shape fails
/// (N/m^1.5).
fn floor_stiffness(s: &ContactForceSettings) -> f64 {
    let f = super::contact_force::NON_HERTZIAN_FLOOR_1_M;
    HertzShape::new(f, f)
        .map(|shape| shape.stiffness_n_m15(&s.material))
        .unwrap_or(1e10)
}

fn check(input: &PoseInput) -> Result<(), LoadedPoseError> {
    let bad = |what, value, rule| Err(LoadedPoseError::Invalid { what, value, rule });
    if !(input.y_m.is_finite() && input.y_m.abs() <= MAX_SHIFT_M) {
        return bad(
            "lateral shift (m)",
            input.y_m,
            "must be finite and within ±0.05 m (check the unit: metres, not millimetres)",
        );
    }
    if !(input.yaw_rad.is_finite() && input.yaw_rad.abs() <= MAX_ANGLE_RAD) {
        return bad(
            "yaw (rad)",
            input.yaw_rad,
            "must be finite and within ±0.1 rad (check the unit: radians, not milliradians)",
        );
    }
    if let Some(r) = input.roll_rad
        && !(r.is_finite() && r.abs() <= MAX_ANGLE_RAD)
    {
        return bad(
            "roll (rad)",
            r,
            "must be finite and within ±0.1 rad (check the unit: radians)",
        );
    }
    if let Some(w) = input.axle_rate_rad_s
        && !w.is_finite()
    {
        return bad("angular velocity of the axle (rad/s)", w, "must be finite");
    }
    if !(input.speed_m_s.is_finite() && input.speed_m_s >= 0.0 && input.speed_m_s < 200.0) {
        return bad(
            "speed (m/s)",
            input.speed_m_s,
            "must be finite, >= 0 and below 200 m/s (check the unit: m/s, not km/h)",
        );
    }
    for load in input.load_per_wheel_n {
        if !(load.is_finite() && load > 0.0 && load <= MAX_LOAD_N) {
            return bad(
                "vertical force per wheel (N)",
                load,
                "must be > 0 and at most 500 kN (check the unit: newtons, not kN)",
            );
        }
    }
    Ok(())
}

/// Solve the pose (see the module docs), each patch at the default
/// [`PatchLocation`] (the deepest point).
pub fn solve_loaded_pose(
    model: &WheelsetContactModel,
    track: &TrackTables,
    solver: &mut ContactSolver,
    settings: &ContactForceSettings,
    input: &PoseInput,
    convention: LoadConvention,
) -> Result<LoadedWheelset, LoadedPoseError> {
    solve_loaded_pose_at(
        model,
        track,
        solver,
        settings,
        input,
        convention,
        PatchLocation::default(),
    )
}

/// Solve the pose with the patches located at `location`.
pub fn solve_loaded_pose_at(
    model: &WheelsetContactModel,
    track: &TrackTables,
    solver: &mut ContactSolver,
    settings: &ContactForceSettings,
    input: &PoseInput,
    convention: LoadConvention,
    location: PatchLocation,
) -> Result<LoadedWheelset, LoadedPoseError> {
    check(input)?;
    let frame = track
        .centerline
        .at(input.s_m)
        .map_err(ContactError::from)?
        .frame;
    let r0 = 0.5
        * (model.wheel(Side::Left).nominal_radius_m()
            + model.wheel(Side::Right).nominal_radius_m());
    let axle_rate_rad_s = input
        .axle_rate_rad_s
        .unwrap_or(input.speed_m_s / r0.max(1e-3));
    let ctx = Context {
        model,
        track,
        settings,
        input,
        convention,
        location,
        axle_rate_rad_s,
        forward: frame.t.normalize(),
        up: frame.b.normalize(),
    };
    let saved = solver.options.flange;
    solver.options.flange = crate::contact::FlangeSearch::On;
    let result = match input.roll_rad {
        Some(roll) => solve_each_wheel(&ctx, solver, r0, roll),
        None => solve_with_roll(&ctx, solver, r0),
    };
    solver.options.flange = saved;
    let (wheels, roll_rad, iterations) = result?;
    Ok(LoadedWheelset {
        input: *input,
        convention,
        location,
        roll_rad,
        roll_solved: input.roll_rad.is_none(),
        axle_rate_rad_s,
        wheels,
        iterations,
    })
}

fn finish(
    ctx: &Context<'_>,
    side: Side,
    pose: WheelsetPose,
    height_m: f64,
    e: WheelEval,
) -> LoadedWheel {
    let frame = ctx.track.centerline.at(ctx.input.s_m).map(|c| c.frame).ok();
    let total: Vector3<f64> = e.patches.iter().map(|p| p.force_on_wheel_n).sum();
    let force_track_n = frame.map_or(total, |f| {
        Vector3::new(
            total.dot(&f.t.normalize()),
            total.dot(&f.n.normalize()),
            total.dot(&f.b.normalize()),
        )
    });
    LoadedWheel {
        side,
        pose,
        height_m,
        patches: e.patches,
        force_track_n,
    }
}

fn not_settled(
    ctx: &Context<'_>,
    what: &'static str,
    iterations: u32,
    residual_n: f64,
    last: Option<&[WheelEval]>,
) -> LoadedPoseError {
    let detail = last
        .and_then(|w| {
            w.iter()
                .flat_map(|e| e.patches.iter())
                .max_by(|a, b| {
                    a.candidate
                        .penetration_m
                        .total_cmp(&b.candidate.penetration_m)
                })
                .map(|p| {
                    format!(
                        " (deepest patch: {} wheel {}, penetration {:.4} mm at a contact angle of {:.1}°)",
                        p.candidate.side,
                        p.candidate.zone.name(),
                        p.candidate.penetration_m * 1e3,
                        p.candidate.contact_angle_rad.to_degrees()
                    )
                })
        })
        .unwrap_or_default();
    LoadedPoseError::NotSettled {
        what,
        y_mm: ctx.input.y_m * 1e3,
        yaw_mrad: ctx.input.yaw_rad * 1e3,
        iterations,
        residual_n,
        detail,
    }
}

/// Roll given: each wheel lowered on its own until it carries its load
/// (Newton on the height with a finite-difference slope; a trial height
/// that loses the wheel's contact is halved back).
fn solve_each_wheel(
    ctx: &Context<'_>,
    solver: &mut ContactSolver,
    r0: f64,
    roll: f64,
) -> Result<([LoadedWheel; 2], f64, u32), LoadedPoseError> {
    let mut wheels = Vec::with_capacity(2);
    let mut total_iterations = 0;
    for (i, side) in Side::BOTH.into_iter().enumerate() {
        let load = ctx.input.load_per_wheel_n[i];
        let residual =
            |z: f64, solver: &mut ContactSolver| -> Result<(f64, WheelEval), LoadedPoseError> {
                let pose = ctx.pose(z, roll)?;
                let e = ctx.eval_side(solver, &pose, side)?;
                Ok((e.residual_m(load), e))
            };
        let mut z = r0;
        let (mut g, mut e) = residual(z, solver)?;
        let mut done = false;
        for it in 0..MAX_ITERATIONS {
            total_iterations += 1;
            if g.abs() < TOLERANCE_M {
                done = true;
                break;
            }
            let slope = match residual(z + FD_STEP, solver) {
                Ok((gp, _)) => (gp - g) / FD_STEP,
                Err(_) => (g - residual(z - FD_STEP, solver)?.0) / FD_STEP,
            };
            // δ falls as the wheelset rises: the slope is about −cos γ.
            let slope = if slope < -1e-3 { slope } else { -1.0 };
            let step = (-g / slope).clamp(-MAX_DZ_M, MAX_DZ_M);
            let mut lambda = 1.0;
            let mut next = None;
            for _ in 0..20 {
                if let Ok(t) = residual(z + lambda * step, solver) {
                    next = Some(t);
                    break;
                }
                lambda *= 0.5;
            }
            let Some((gn, en)) = next else {
                return Err(not_settled(ctx, "height", it, load, Some(&[e])));
            };
            z += lambda * step;
            g = gn;
            e = en;
        }
        if !done {
            let res = (e.vertical_n - load).abs();
            return Err(not_settled(ctx, "height", MAX_ITERATIONS, res, Some(&[e])));
        }
        let pose = ctx.pose(z, roll)?;
        wheels.push(finish(ctx, side, pose, z, e));
    }
    let right = wheels.pop().expect("two wheels");
    let left = wheels.pop().expect("two wheels");
    Ok(([left, right], roll, total_iterations))
}

/// Roll not given: height and roll solved together (Newton, 2 × 2
/// finite-difference Jacobian, steps limited and halved back when a trial
/// pose loses a wheel's contact).
fn solve_with_roll(
    ctx: &Context<'_>,
    solver: &mut ContactSolver,
    r0: f64,
) -> Result<([LoadedWheel; 2], f64, u32), LoadedPoseError> {
    use nalgebra::{Matrix2, Vector2};
    let loads = ctx.input.load_per_wheel_n;
    let residual = |z: f64,
                    roll: f64,
                    solver: &mut ContactSolver|
     -> Result<(Vector2<f64>, [WheelEval; 2]), LoadedPoseError> {
        let pose = ctx.pose(z, roll)?;
        let e = ctx.eval(solver, &pose)?;
        Ok((
            Vector2::new(e[0].residual_m(loads[0]), e[1].residual_m(loads[1])),
            e,
        ))
    };
    let (mut z, mut roll) = (r0, 0.0);
    let (mut g, mut e) = residual(z, roll, solver)?;
    for it in 0..MAX_ITERATIONS {
        if g.amax() < TOLERANCE_M {
            let pose = ctx.pose(z, roll)?;
            let [l, r] = e;
            return Ok((
                [
                    finish(ctx, Side::Left, pose, z, l),
                    finish(ctx, Side::Right, pose, z, r),
                ],
                roll,
                it,
            ));
        }
        let mut column = |dz: f64, dr: f64| -> Result<Vector2<f64>, LoadedPoseError> {
            match residual(z + dz, roll + dr, solver) {
                Ok((p, _)) => Ok((p - g) / FD_STEP),
                Err(_) => Ok((g - residual(z - dz, roll - dr, solver)?.0) / FD_STEP),
            }
        };
        let j = Matrix2::from_columns(&[column(FD_STEP, 0.0)?, column(0.0, FD_STEP)?]);
        let Some(step) = j.lu().solve(&(-g)) else {
            break;
        };
        let scale = 1.0_f64
            .min(MAX_DZ_M / step[0].abs().max(1e-300))
            .min(MAX_DROLL_RAD / step[1].abs().max(1e-300));
        let mut lambda = scale;
        let mut next = None;
        for _ in 0..20 {
            if let Ok(t) = residual(z + lambda * step[0], roll + lambda * step[1], solver) {
                next = Some(t);
                break;
            }
            lambda *= 0.5;
        }
        let Some((gn, en)) = next else { break };
        z += lambda * step[0];
        roll += lambda * step[1];
        g = gn;
        e = en;
    }
    let res = (e[0].vertical_n - loads[0])
        .abs()
        .max((e[1].vertical_n - loads[1]).abs());
    Err(not_settled(
        ctx,
        "height and roll",
        MAX_ITERATIONS,
        res,
        Some(&e),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::wheelsets::{flange_solver, s1002_uic60, straight_track_for};
    use crate::forces::creep::CreepLaw;
    use crate::forces::hertz::Material;

    fn settings() -> ContactForceSettings {
        ContactForceSettings {
            material: Material {
                young_pa: 2.0 * 82e9 * 1.28,
                poisson: 0.28,
            },
            creep_law: CreepLaw::from_name("fastsim").expect("law"),
            ..Default::default()
        }
    }

    fn input(y_mm: f64, yaw_mrad: f64, roll_rad: Option<f64>) -> PoseInput {
        PoseInput {
            s_m: 5.0,
            y_m: y_mm * 1e-3,
            yaw_rad: yaw_mrad * 1e-3,
            roll_rad,
            axle_rate_rad_s: None,
            speed_m_s: 2.0,
            load_per_wheel_n: [10_000.0, 10_000.0],
        }
    }

    fn solve(i: &PoseInput, c: LoadConvention) -> Result<LoadedWheelset, LoadedPoseError> {
        let model = s1002_uic60().expect("profiles");
        let track = straight_track_for(&model, 10.0);
        solve_loaded_pose(&model, &track, &mut flange_solver(), &settings(), i, c)
    }

    /// Each convention balances its own sum: Σ f·b (vertical) or Σ N n·b
    /// (normal) equals the load on both wheels, to 1e-6 relative.
    #[test]
    fn each_convention_carries_the_load_its_way() {
        for c in [LoadConvention::Vertical, LoadConvention::Normal] {
            let l = solve(&input(-6.0, -14.4, None), c).expect("solves");
            assert!(l.roll_solved);
            for w in &l.wheels {
                let sum: f64 = w
                    .patches
                    .iter()
                    .map(|p| match c {
                        LoadConvention::Vertical => p.force_on_wheel_n.z,
                        LoadConvention::Normal => p.normal_n * p.candidate.normal.z,
                    })
                    .sum();
                assert!((sum - 1e4).abs() < 1e-2, "{c:?} {}: {sum}", w.side);
            }
        }
    }

    /// A given roll solves each wheel at its own height; the roll is kept.
    #[test]
    fn a_given_roll_gives_each_wheel_its_height() {
        let l = solve(&input(-3.0, -7.2, Some(-0.0018)), LoadConvention::Vertical).expect("solves");
        assert_eq!(l.roll_rad, -0.0018);
        assert!(!l.roll_solved);
        assert!((l.wheels[0].height_m - l.wheels[1].height_m).abs() > 1e-7);
        for w in &l.wheels {
            assert!(
                (w.force_track_n.z - 1e4).abs() < 1e-2,
                "{}",
                w.force_track_n
            );
        }
    }

    /// Inputs out of range (a unit slip) are refused before any work.
    #[test]
    fn implausible_inputs_are_refused() {
        let mut i = input(0.0, 0.0, None);
        i.y_m = 5.0;
        let e = solve(&i, LoadConvention::Vertical).unwrap_err();
        assert!(e.to_string().contains("check the unit"), "{e}");
        let mut i = input(0.0, 0.0, None);
        i.load_per_wheel_n = [10.0e6, 10.0e6];
        let e = solve(&i, LoadConvention::Vertical).unwrap_err();
        assert!(e.to_string().contains("check the unit"), "{e}");
        let mut i = input(0.0, 0.0, None);
        i.speed_m_s = 300.0;
        assert!(solve(&i, LoadConvention::Vertical).is_err());
    }

    #[test]
    fn convention_names_round_trip() {
        for c in [LoadConvention::Vertical, LoadConvention::Normal] {
            assert_eq!(c.name().parse::<LoadConvention>(), Ok(c));
        }
        assert!("weight".parse::<LoadConvention>().is_err());
    }

    use crate::fixtures::wheelsets;

    fn centred(location: PatchLocation) -> LoadedWheelset {
        let model = wheelsets::s1002_uic60().expect("fixture");
        let track = wheelsets::straight_track_for(&model, 20.0);
        let mut solver = wheelsets::flange_solver();
        let input = PoseInput {
            s_m: 10.0,
            y_m: 0.0,
            yaw_rad: 0.0,
            roll_rad: Some(0.0),
            axle_rate_rad_s: None,
            speed_m_s: 2.0,
            load_per_wheel_n: [1e4, 1e4],
        };
        solve_loaded_pose_at(
            &model,
            &track,
            &mut solver,
            &ContactForceSettings::default(),
            &input,
            LoadConvention::Vertical,
            location,
        )
        .expect("solved")
    }

    /// The centred S1002/UIC60 wheelset (near-conformal): with `Centre` the
    /// patch is located, and its forces directed, at the centre of the
    /// interpenetration, millimetres from the deepest point, with the
    /// deepest point's δ; `DeepestPoint` (the default) keeps the old location.
    #[test]
    fn patches_at_their_centre_on_request() {
        assert_eq!(PatchLocation::default(), PatchLocation::DeepestPoint);
        let l = centred(PatchLocation::Centre);
        assert_eq!(l.location, PatchLocation::Centre);
        let p = &l.wheels[0].patches[0];
        let lateral = (p.centre.rail_point - p.candidate.rail_point).norm();
        assert!(lateral > 5e-4, "centre {lateral} m from the deepest point");
        assert_eq!(p.centre.penetration_m, p.candidate.penetration_m);
        assert!(p.overlap_width_m.is_some_and(|w| w > 0.005), "{p:?}");
        // The normal force acts along the centre's normal.
        let t = p.tangential.expect("forces");
        let along =
            p.force_on_wheel_n - p.centre.tangent * t.creep.fx_n - p.centre.lateral * t.creep.fy_n;
        assert!((along - p.centre.normal * p.normal_n).norm() < 1e-6 * p.normal_n);

        let old = centred(PatchLocation::DeepestPoint);
        let q = &old.wheels[0].patches[0];
        assert_eq!(q.centre, q.candidate);
        assert!(q.overlap_width_m.is_none());
    }

    #[test]
    fn patch_location_names_parse() {
        for l in [PatchLocation::Centre, PatchLocation::DeepestPoint] {
            assert_eq!(l.name().parse::<PatchLocation>(), Ok(l));
        }
        assert!("middle".parse::<PatchLocation>().is_err());
    }
}
