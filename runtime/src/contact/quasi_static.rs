//! Quasi-static wheelset positions: for a prescribed lateral displacement
//! and yaw, the height and roll at which the wheelset rests on the rails —
//! rigidly (both wheels just touching, the classic contact-geometry
//! computation) or elastically (each wheel carrying a given vertical load
//! through Hertzian contact, as in the Manchester contact benchmark) — and
//! the flangeway clearance derived from it.

use nalgebra::Vector2;

use super::solver::si;
use super::{
    Candidate, ContactError, ContactOptions, ContactSolver, FlangeSearch, WheelsetContactModel,
    WheelsetContacts, WheelsetPose,
};
use crate::forces::hertz::{HertzShape, Material};
use crate::geometry::profile::{MAX_SEGMENTS, Zone};
use crate::geometry::track::{Side, TrackTables, straight_track};

/// How the wheelset is supported.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Support {
    /// Rigid bodies: both wheels touch (largest penetration zero per wheel).
    Rigid,
    /// Hertzian contact; each wheel carries `load_per_wheel_n` vertically (N).
    Elastic {
        load_per_wheel_n: f64,
        material: Material,
    },
}

/// A settled wheelset.
#[derive(Debug, Clone, PartialEq)]
pub struct Settled {
    pub pose: WheelsetPose,
    /// Height of the wheelset centre above the track plane (m).
    pub height_m: f64,
    /// Roll relative to the track (rad), positive raising the left wheel.
    pub roll_rad: f64,
    pub contacts: WheelsetContacts,
    /// Hertzian normal force of each candidate, `[left, right][piece]` as in
    /// [`WheelsetContacts::candidates`] (N); zero for rigid support and for
    /// candidates not in contact.
    pub normal_force_n: [[f64; MAX_SEGMENTS]; 2],
    /// Newton iterations of the settling.
    pub iterations: u32,
}

impl Settled {
    /// The candidate that carries a wheel: the one with the largest normal
    /// force (elastic) or penetration (rigid).
    pub fn main_contact(&self, side: Side) -> Option<&Candidate> {
        let i = si(side);
        self.contacts.candidates[i]
            .iter()
            .zip(&self.normal_force_n[i])
            .filter_map(|(c, f)| c.as_ref().map(|c| (c, *f)))
            .max_by(|a, b| {
                a.1.total_cmp(&b.1)
                    .then(a.0.penetration_m.total_cmp(&b.0.penetration_m))
            })
            .map(|(c, _)| c)
    }

    /// Rolling radius difference Δr = r_left − r_right at the main contacts (m).
    pub fn rolling_radius_difference_m(&self) -> Option<f64> {
        Some(
            self.main_contact(Side::Left)?.rolling_radius_m
                - self.main_contact(Side::Right)?.rolling_radius_m,
        )
    }
}

/// Hertz stiffness K (N/m^1.5) of a candidate, with the principal relative
/// curvatures of docs/reference/07-contact-forces.md §7.1; `None` when the geometry is not Hertzian.
pub fn hertz_stiffness(c: &Candidate, material: &Material) -> Option<f64> {
    let a = 0.5 * (c.curvatures.wheel_rolling_1_m + c.curvatures.rail_rolling_1_m);
    let b = 0.5 * (c.curvatures.wheel_lateral_1_m + c.curvatures.rail_lateral_1_m);
    HertzShape::new(a, b)
        .ok()
        .map(|s| s.stiffness_n_m15(material))
}

/// Smallest relative curvature used when the geometry is not Hertzian
/// (conformal): 1/(20 m). Only for settling; the contact is still reported.
const MIN_RELATIVE_CURVATURE_1_M: f64 = 0.05;

fn stiffness_or_floor(c: &Candidate, material: &Material) -> f64 {
    hertz_stiffness(c, material).unwrap_or_else(|| {
        let a = 0.5 * (c.curvatures.wheel_rolling_1_m + c.curvatures.rail_rolling_1_m);
        let b = 0.5 * (c.curvatures.wheel_lateral_1_m + c.curvatures.rail_lateral_1_m);
        HertzShape::new(
            a.max(MIN_RELATIVE_CURVATURE_1_M),
            b.max(MIN_RELATIVE_CURVATURE_1_M),
        )
        .map(|s| s.stiffness_n_m15(material))
        .unwrap_or(1e10)
    })
}

struct Evaluation {
    contacts: WheelsetContacts,
    residual: Vector2<f64>,
    forces: [[f64; MAX_SEGMENTS]; 2],
}

/// Settle the wheelset at lateral displacement `y_m` and yaw `yaw_rad` at
/// track distance `s_m`.
///
/// Past the flange contact the wheel must climb its flange, and at a fixed
/// lateral position of the wheelset centre it can only do so by rolling
/// about the centre, which also swings the flange contact point (a depth
/// r_f below the axle) outwards by r_f per radian. With rigid contact the
/// flange penetration changes by (sin γ · r_f − cos γ · (b_f + b_o)) per
/// radian of roll that keeps the other wheel on its rail (γ the flange
/// angle, b_f and b_o the lateral distances of the flange point and of the
/// other wheel's contact from the centre): positive for a steep flank —
/// about γ > 73° for a 0.43 m wheel on standard gauge — so that no rest
/// position exists there and the error says so, naming the deepest
/// contact (the flange blocks the wheelset; only a lateral motion of the
/// centre lets it climb, as in a dynamic run).
#[allow(clippy::too_many_arguments)]
pub fn settle(
    model: &WheelsetContactModel,
    track: &TrackTables,
    s_m: f64,
    y_m: f64,
    yaw_rad: f64,
    support: Support,
    solver: &mut ContactSolver,
) -> Result<Settled, ContactError> {
    let saved = solver.options.flange;
    solver.options.flange = FlangeSearch::On;
    let result = settle_inner(model, track, s_m, y_m, yaw_rad, support, solver);
    solver.options.flange = saved;
    result
}

fn settle_inner(
    model: &WheelsetContactModel,
    track: &TrackTables,
    s_m: f64,
    y_m: f64,
    yaw_rad: f64,
    support: Support,
    solver: &mut ContactSolver,
) -> Result<Settled, ContactError> {
    let b_track = track.centerline.at(s_m)?.frame.b;
    let eval = |z: f64,
                roll: f64,
                solver: &mut ContactSolver|
     -> Result<Evaluation, ContactError> {
        let pose = WheelsetPose::on_track(track, s_m, y_m, z, yaw_rad, roll)?;
        let contacts = solver.solve(model, track, &pose)?;
        let mut residual = Vector2::zeros();
        let mut forces = [[0.0; MAX_SEGMENTS]; 2];
        for side in Side::BOTH {
            let i = si(side);
            let cands: Vec<&Candidate> = contacts.candidates[i].iter().flatten().collect();
            if cands.is_empty() {
                return Err(ContactError::Setup(format!(
                    "no contact candidate on the {side} wheel at y = {:.2} mm: the wheel is off its rail",
                    y_m * 1e3
                )));
            }
            let deepest = cands
                .iter()
                .map(|c| c.penetration_m)
                .fold(f64::NEG_INFINITY, f64::max);
            residual[i] = match support {
                Support::Rigid => deepest,
                Support::Elastic {
                    load_per_wheel_n,
                    material,
                } => {
                    let mut f_vert = 0.0;
                    let mut k_ref = 0.0;
                    let mut best = 0.0;
                    for (slot, c) in contacts.candidates[i].iter().enumerate() {
                        let Some(c) = c else { continue };
                        let k = stiffness_or_floor(c, &material);
                        let cos = c.normal.dot(&b_track).max(1e-3);
                        let n = k * c.penetration_m.max(0.0).powf(1.5);
                        forces[i][slot] = n;
                        f_vert += n * cos;
                        let weight = if c.penetration_m > 0.0 { n * cos } else { 0.0 };
                        if weight > best || k_ref == 0.0 {
                            best = weight;
                            k_ref = k * cos;
                        }
                    }
                    let target = (load_per_wheel_n / k_ref).powf(2.0 / 3.0);
                    let effective = if f_vert > 0.0 {
                        (f_vert / k_ref).powf(2.0 / 3.0)
                    } else {
                        deepest
                    };
                    effective - target
                }
            };
        }
        Ok(Evaluation {
            contacts,
            residual,
            forces,
        })
    };

    let r0 = 0.5
        * (model.wheel(Side::Left).nominal_radius_m()
            + model.wheel(Side::Right).nominal_radius_m());
    let (mut z, mut roll) = (r0, 0.0);
    let mut e = eval(z, roll, solver)?;
    let h = 1e-8;
    for it in 0..60u32 {
        if e.residual.amax() < 1e-11 {
            let pose = WheelsetPose::on_track(track, s_m, y_m, z, yaw_rad, roll)?;
            return Ok(Settled {
                pose,
                height_m: z,
                roll_rad: roll,
                contacts: e.contacts,
                normal_force_n: e.forces,
                iterations: it,
            });
        }
        // Finite-difference Jacobian (one-sided; the other side where a
        // probe loses a wheel's contact).
        let mut column = |dz: f64, dr: f64| -> Result<Vector2<f64>, ContactError> {
            match eval(z + dz, roll + dr, solver) {
                Ok(p) => Ok((p.residual - e.residual) / h),
                Err(_) => Ok((e.residual - eval(z - dz, roll - dr, solver)?.residual) / h),
            }
        };
        let j = nalgebra::Matrix2::from_columns(&[column(h, 0.0)?, column(0.0, h)?]);
        let Some(step) = j.lu().solve(&(-e.residual)) else {
            break;
        };
        let scale = (1.0_f64)
            .min(1e-3 / step[0].abs().max(1e-300))
            .min(2e-3 / step[1].abs().max(1e-300));
        // Backtrack while a trial position loses a wheel's contact.
        let mut lambda = scale;
        let mut next = None;
        for _ in 0..20 {
            if let Ok(t) = eval(z + lambda * step[0], roll + lambda * step[1], solver) {
                next = Some(t);
                break;
            }
            lambda *= 0.5;
        }
        let Some(t) = next else { break };
        z += lambda * step[0];
        roll += lambda * step[1];
        e = t;
    }
    let deepest = e
        .contacts
        .iter()
        .max_by(|a, b| a.penetration_m.total_cmp(&b.penetration_m))
        .map_or(String::new(), |c| {
            format!(
                " (the deepest contact is the {} wheel's {}, penetration {:.4} mm at a contact angle of {:.1}°{})",
                c.side,
                c.zone.name(),
                c.penetration_m * 1e3,
                c.contact_angle_rad.to_degrees(),
                if c.zone == Zone::Flange {
                    ": past the flange contact a steep flank has no rest position at a fixed lateral displacement"
                } else {
                    ""
                }
            )
        });
    Err(ContactError::Setup(format!(
        "the wheelset could not be settled at y = {:.2} mm, yaw = {:.2} mrad{deepest}",
        y_m * 1e3,
        yaw_rad * 1e3
    )))
}

/// Lateral displacement (m, ≥ 0) of the centred, unyawed wheelset towards
/// `side` at which that wheel's flange touches its rail (rigid contact, on a
/// straight track with the model's rail placement); `None` when the flange
/// does not touch within 25 mm.
pub fn flange_clearance_m(
    model: &WheelsetContactModel,
    side: Side,
) -> Result<Option<f64>, ContactError> {
    if model.wheel(side).flange_tip_u_m().is_none() {
        return Ok(None);
    }
    let p = model.placement();
    let track = straight_track(4.0, 0.1, p.gauge_m, p.rail_spacing_m, p.inclination_rad);
    let mut solver = ContactSolver::new(ContactOptions {
        flange: FlangeSearch::On,
        ..Default::default()
    });
    // Moving towards `side` brings that wheel's flange to its rail (the
    // flange runs inside the rail): left wheel → y > 0. Past the flange
    // contact a steep flank has no rest position ([`settle`]): a failure
    // to settle within 1 mm of a flange gap counts as touching.
    let dir = side.sign();
    let mut last_gap_m = f64::INFINITY;
    let mut touching = |y: f64, solver: &mut ContactSolver| -> Result<bool, ContactError> {
        match settle(model, &track, 2.0, dir * y, 0.0, Support::Rigid, solver) {
            Ok(s) => {
                let gap = s
                    .contacts
                    .get(side, Zone::Flange)
                    .map_or(f64::INFINITY, |c| -c.penetration_m);
                last_gap_m = last_gap_m.min(gap.max(0.0));
                Ok(gap < 1e-7)
            }
            Err(ContactError::Setup(_)) if y > 0.0 && last_gap_m < 1e-3 => Ok(true),
            Err(e) => Err(e),
        }
    };
    let step = 2e-4;
    let mut y = 0.0;
    while y <= 0.025 {
        if touching(y, &mut solver)? {
            let (mut lo, mut hi) = ((y - step).max(0.0), y);
            for _ in 0..12 {
                let mid = 0.5 * (lo + hi);
                if touching(mid, &mut solver)? {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Ok(Some(hi));
        }
        y += step;
    }
    Ok(None)
}

/// The contacts of a wheelset kept level (no roll), each wheel lowered
/// separately until it touches its rail (rigid): the idealisation of
/// EN 15302 for the rolling-radius-difference function, whose reference
/// results neglect the roll of the wheelset. Returns, left then right, the
/// touching wheel's deepest candidate (penetration 0).
pub fn level_wheel_contacts(
    model: &WheelsetContactModel,
    track: &TrackTables,
    s_m: f64,
    y_m: f64,
    yaw_rad: f64,
    solver: &mut ContactSolver,
) -> Result<[Candidate; 2], ContactError> {
    let saved = solver.options.flange;
    solver.options.flange = FlangeSearch::On;
    let mut out = Vec::with_capacity(2);
    for side in Side::BOTH {
        let i = si(side);
        let deepest = |z: f64, solver: &mut ContactSolver| -> Result<Candidate, ContactError> {
            let pose = WheelsetPose::on_track(track, s_m, y_m, z, yaw_rad, 0.0)?;
            let c = solver.solve(model, track, &pose)?;
            c.candidates[i]
                .iter()
                .flatten()
                .max_by(|a, b| a.penetration_m.total_cmp(&b.penetration_m))
                .copied()
                .ok_or_else(|| {
                    ContactError::Setup(format!(
                        "no contact candidate on the {side} wheel at y = {:.2} mm",
                        y_m * 1e3
                    ))
                })
        };
        // δ(z) decreases with z at a slope of about −1 (tread) to −cos γ
        // (flange): secant iterations from the nominal radius.
        let mut z0 = model.wheel(side).nominal_radius_m();
        let mut c0 = deepest(z0, solver)?;
        let mut z1 = z0 + c0.penetration_m;
        let mut c1 = deepest(z1, solver)?;
        for _ in 0..40 {
            if c1.penetration_m.abs() < 1e-12 {
                break;
            }
            let slope = (c1.penetration_m - c0.penetration_m) / (z1 - z0);
            let step = if slope.abs() > 1e-3 {
                -c1.penetration_m / slope
            } else {
                c1.penetration_m
            };
            (z0, c0) = (z1, c1);
            z1 += step.clamp(-1e-3, 1e-3);
            c1 = deepest(z1, solver)?;
        }
        if c1.penetration_m.abs() > 1e-9 {
            solver.options.flange = saved;
            return Err(ContactError::Setup(format!(
                "the {side} wheel could not be brought to touch at y = {:.2} mm",
                y_m * 1e3
            )));
        }
        out.push(c1);
    }
    solver.options.flange = saved;
    Ok([out[0], out[1]])
}
