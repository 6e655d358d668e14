//! The per-step contact search of a wheelset (paper Fig. 8 steps b and f):
//! both wheels, every piece of their profiles (tread and flange), warm
//! started from the previous step's surface parameters, with the flange
//! search rule.

use super::candidate::Candidate;
use super::geometry::SurfaceParams;
use super::model::WheelsetContactModel;
use super::{ContactError, WheelsetPose};
use crate::geometry::profile::{MAX_SEGMENTS, Zone};
use crate::geometry::track::{Side, TrackTables};

/// When the flange zones are searched (paper §4.3: the user chooses whether
/// flange contact matters; docs/reference/06-contact-detection.md §6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FlangeSearch {
    /// Never: tread contact only.
    Off,
    /// At every solve.
    On,
    /// Only when the flange may be near its rail (see [`ContactOptions`]).
    #[default]
    Auto,
}

impl std::str::FromStr for FlangeSearch {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "off" => Ok(Self::Off),
            "on" => Ok(Self::On),
            "auto" => Ok(Self::Auto),
            other => Err(format!("flange search '{other}' is not off, on or auto")),
        }
    }
}

/// Options of the contact search.
///
/// # The `auto` flange rule
///
/// A wheel's flange zone is searched when either
/// * its flange was within `auto_margin_m` of its rail (gap) or in contact
///   at the previous solve, or
/// * the wheel's lateral approach towards its rail, plus the reach of a
///   yawed flange `|ψ|·√(2·R0·h_f)` (ψ the yaw relative to the rail, h_f the
///   flange depth), exceeds `flange_clearance_m − auto_margin_m`.
///
/// `flange_clearance_m` is the lateral displacement at which the flange
/// meets the rail for the centred, unyawed wheelset (from
/// [`super::quasi_static::flange_clearance_m`]); with 0 (the default) the
/// `auto` rule searches always.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactOptions {
    pub flange: FlangeSearch,
    /// Newton iterations allowed per start.
    pub max_iterations: u32,
    /// Safety margin of the `auto` rule (m).
    pub auto_margin_m: f64,
    /// Flangeway clearance of each side, left and right (m).
    pub flange_clearance_m: [f64; 2],
    /// Where Newton's method fails from every start on a piece that is in
    /// or near contact (a nearly conformal contact, whose Jacobian is
    /// singular), take the contact from the direct minimisation of the
    /// cross-sectional distance instead of failing. Such contacts are marked
    /// [`super::SolveMethod::Minimisation`] and counted in [`SolverStats`].
    /// With `false` they are [`ContactError::NotConverged`] errors.
    pub minimisation_fallback: bool,
    /// Remember pieces found without a contact of their own (no stationary
    /// point) and skip them until the wheel has moved (see `Clear` in this
    /// file: 0.2 mm laterally or vertically, 0.5 mrad of yaw or roll, 2 m
    /// along the track). For time stepping, where consecutive poses differ
    /// by micrometres and a cold search of such a piece (about 100 µs)
    /// would otherwise be repeated at every evaluation. Off by default:
    /// quasi-static sweeps jump between poses on purpose.
    pub reuse_clear_pieces: bool,
}

impl Default for ContactOptions {
    fn default() -> Self {
        Self {
            flange: FlangeSearch::Auto,
            max_iterations: 25,
            auto_margin_m: 0.003,
            flange_clearance_m: [0.0, 0.0],
            minimisation_fallback: true,
            reuse_clear_pieces: false,
        }
    }
}

/// The candidates of one wheelset: for each wheel (left, right) one slot
/// per piece of its profile.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelsetContacts {
    pub candidates: [[Option<Candidate>; MAX_SEGMENTS]; 2],
}

impl WheelsetContacts {
    /// The candidates of one wheel.
    pub fn side(&self, side: Side) -> impl Iterator<Item = &Candidate> {
        self.candidates[si(side)].iter().flatten()
    }

    /// The deepest candidate of a wheel's zone, if any.
    pub fn get(&self, side: Side, zone: Zone) -> Option<&Candidate> {
        self.side(side)
            .filter(|c| c.zone == zone)
            .max_by(|a, b| a.penetration_m.total_cmp(&b.penetration_m))
    }

    /// All candidates.
    pub fn iter(&self) -> impl Iterator<Item = &Candidate> {
        self.candidates.iter().flatten().flatten()
    }

    /// The candidates that are in contact (δ ≥ 0).
    pub fn contacts(&self) -> impl Iterator<Item = &Candidate> {
        self.iter().filter(|c| c.in_contact())
    }
}

/// Counters of the solver's work.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SolverStats {
    /// Pair solves performed.
    pub solves: u64,
    /// Newton iterations over all solves.
    pub iterations: u64,
    /// Solves that needed the coarse search.
    pub cold_starts: u64,
    /// Flange pieces skipped by the `auto` rule or `off`.
    pub flange_skipped: u64,
    /// Contacts taken from the minimisation fallback.
    pub minimisations: u64,
    /// Pieces not searched again because they were found clear (no
    /// stationary point) and the wheel has hardly moved since
    /// (see `Clear` in the solver's source).
    pub clear_skipped: u64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Warm {
    params: SurfaceParams,
    /// Rail arc length at the wheelset's track position when solved.
    rail_l_m: f64,
    /// Gap (−δ) at that solve (m).
    gap_m: f64,
    /// The solve before, for the linear predictor.
    previous: Option<(SurfaceParams, f64)>,
}

/// Largest change of a lateral surface parameter the predictor may add (m).
const MAX_PREDICTED_SHIFT_M: f64 = 0.002;

impl Warm {
    /// Starting point for the next solve at rail arc length `l_now`: the last
    /// solution moved along the rail, plus the linear trend of the lateral
    /// parameters over the last two solves (a first-order predictor, which
    /// saves an iteration when the contact point travels across the profiles).
    fn guess(&self, l_now: f64) -> SurfaceParams {
        let mut g = SurfaceParams {
            s_rail_m: self.params.s_rail_m + (l_now - self.rail_l_m),
            ..self.params
        };
        if let Some((p0, l0)) = self.previous {
            let dl = self.rail_l_m - l0;
            if dl.abs() > 1e-9 {
                let f = ((l_now - self.rail_l_m) / dl).clamp(-2.0, 2.0);
                let lim = |d: f64| (f * d).clamp(-MAX_PREDICTED_SHIFT_M, MAX_PREDICTED_SHIFT_M);
                g.u_rail_m += lim(self.params.u_rail_m - p0.u_rail_m);
                g.u_wheel_m += lim(self.params.u_wheel_m - p0.u_wheel_m);
                g.s_wheel_rad += f * (self.params.s_wheel_rad - p0.s_wheel_rad);
            }
        }
        g
    }
}

/// Where a wheel is relative to its rail, for the flange rule and the
/// clear-piece cache.
#[derive(Debug, Clone, Copy, PartialEq)]
struct WheelPosition {
    /// Lateral approach of the wheel towards its rail from the centred
    /// position (m), along the track's lateral vector.
    approach_m: f64,
    /// Yaw of the wheelset relative to the track (rad, signed).
    yaw_rad: f64,
    /// Height of the wheel's profile origin along the track normal (m).
    vertical_m: f64,
    /// Roll of the axle relative to the track (rad, signed).
    roll_rad: f64,
}

fn wheel_position(
    model: &WheelsetContactModel,
    track: &TrackTables,
    pose: &WheelsetPose,
    side: Side,
) -> Result<WheelPosition, ContactError> {
    let sigma = match side {
        Side::Left => -1.0,
        Side::Right => 1.0,
    };
    let l = track.centerline.rail_l(side, pose.s_track_m)?;
    let rail = track.rail(side).at(l)?;
    // Lateral measures along the track's lateral vector (not the rail
    // frame's, which is tilted by the rail inclination: with it, the axle
    // height would leak into the approach).
    let frame = track.centerline.at(pose.s_track_m)?.frame;
    let n = frame.n.normalize();
    let b = frame.b.normalize();
    let h = -sigma * model.half_spacing_m(side);
    let origin = pose.position + pose.frame.column(1) * h;
    let delta = (origin - rail.position).dot(&n);
    let spacing = model.placement().rail_spacing_m;
    let delta0 = -sigma * (model.half_spacing_m(side) - 0.5 * spacing);
    Ok(WheelPosition {
        approach_m: -sigma * (delta - delta0),
        yaw_rad: pose.frame.column(0).dot(&n).clamp(-1.0, 1.0).asin(),
        vertical_m: (origin - rail.position).dot(&b),
        roll_rad: pose.frame.column(1).dot(&b).clamp(-1.0, 1.0).asin(),
    })
}

/// A piece found without contact of its own (no stationary point on it):
/// where the wheel was then. It is searched again only when the wheel has
/// moved relative to its rail by more than [`CLEAR_RECHECK_M`] laterally,
/// vertically, [`CLEAR_RECHECK_RAD`] in yaw or roll, or
/// [`CLEAR_RECHECK_ALONG_M`] along the track — a cold search costs about
/// 100 µs, a Newton solve about 1 µs.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Clear {
    at: WheelPosition,
    s_track_m: f64,
}

/// Lateral motion of a wheel after which a clear piece is searched again
/// (m). The pieces this applies to have no stationary point at all; one
/// appears only when the wheel moves so that the piece faces the rail, a
/// motion of millimetres for a flange root, so 0.2 mm is conservative.
const CLEAR_RECHECK_M: f64 = 2e-4;
/// Yaw change after which a clear piece is searched again (rad).
const CLEAR_RECHECK_RAD: f64 = 5e-4;
/// Travel along the track after which a clear piece is searched again (m).
/// The lateral and vertical measures above are taken against the rail's
/// actual position, so alignment and level irregularities are already
/// watched; this bound covers what they do not (changes of the rail's
/// roll, a curve's frame turning), which vary over metres.
const CLEAR_RECHECK_ALONG_M: f64 = 2.0;

impl Clear {
    fn still_clear(&self, now: &WheelPosition, s_track_m: f64) -> bool {
        (now.approach_m - self.at.approach_m).abs() < CLEAR_RECHECK_M
            && (now.vertical_m - self.at.vertical_m).abs() < CLEAR_RECHECK_M
            && (now.yaw_rad - self.at.yaw_rad).abs() < CLEAR_RECHECK_RAD
            && (now.roll_rad - self.at.roll_rad).abs() < CLEAR_RECHECK_RAD
            && (s_track_m - self.s_track_m).abs() < CLEAR_RECHECK_ALONG_M
    }
}

pub(crate) fn si(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

/// Contact search with memory of the previous step.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSolver {
    pub options: ContactOptions,
    warm: [[Option<Warm>; MAX_SEGMENTS]; 2],
    clear: [[Option<Clear>; MAX_SEGMENTS]; 2],
    pub stats: SolverStats,
}

impl ContactSolver {
    pub fn new(options: ContactOptions) -> Self {
        Self {
            options,
            warm: Default::default(),
            clear: Default::default(),
            stats: SolverStats::default(),
        }
    }

    /// Forget the previous solutions (the next solve starts cold).
    pub fn reset(&mut self) {
        self.warm = Default::default();
        self.clear = Default::default();
    }

    /// Whether the `auto` rule asks for the flange pieces of `side`.
    fn flange_needed(&self, model: &WheelsetContactModel, w: &WheelPosition, side: Side) -> bool {
        match self.options.flange {
            FlangeSearch::Off => return false,
            FlangeSearch::On => return true,
            FlangeSearch::Auto => {}
        }
        let margin = self.options.auto_margin_m;
        let wheel = model.wheel(side);
        let flange_warm = wheel
            .segments()
            .iter()
            .zip(&self.warm[si(side)])
            .any(|(seg, w)| seg.zone == Zone::Flange && w.is_some_and(|w| w.gap_m < margin));
        if flange_warm {
            return true;
        }
        let reach =
            w.yaw_rad.abs() * (2.0 * wheel.nominal_radius_m() * wheel.flange_depth_m()).sqrt();
        w.approach_m + reach >= self.options.flange_clearance_m[si(side)] - margin
    }

    /// Solve every piece of both wheels for `pose` (paper Fig. 8 step b),
    /// keeping the surface parameters for the next call (step f).
    pub fn solve(
        &mut self,
        model: &WheelsetContactModel,
        track: &TrackTables,
        pose: &WheelsetPose,
    ) -> Result<WheelsetContacts, ContactError> {
        let mut out = WheelsetContacts::default();
        for side in Side::BOTH {
            let l_now = track.centerline.rail_l(side, pose.s_track_m)?;
            let position = wheel_position(model, track, pose, side)?;
            let flange = self.flange_needed(model, &position, side);
            for (k, seg) in model.wheel(side).segments().iter().enumerate() {
                if seg.zone == Zone::Flange && !flange {
                    self.stats.flange_skipped += 1;
                    continue;
                }
                let clear = &mut self.clear[si(side)][k];
                if self.options.reuse_clear_pieces
                    && self.warm[si(side)][k].is_none()
                    && clear.is_some_and(|c| c.still_clear(&position, pose.s_track_m))
                {
                    self.stats.clear_skipped += 1;
                    continue;
                }
                *clear = None;
                let warm = &mut self.warm[si(side)][k];
                let guess = warm.map(|w| w.guess(l_now));
                let result = model.solve_pair(track, pose, side, k, guess, &self.options)?;
                self.stats.solves += 1;
                if let Some(c) = &result {
                    if c.method == super::SolveMethod::Minimisation {
                        self.stats.minimisations += 1;
                    }
                    self.stats.iterations += u64::from(c.iterations);
                    if c.cold_start {
                        self.stats.cold_starts += 1;
                    }
                    let previous = warm
                        .filter(|_| !c.cold_start)
                        .map(|w| (w.params, w.rail_l_m));
                    *warm = Some(Warm {
                        params: c.params,
                        rail_l_m: l_now,
                        gap_m: -c.penetration_m,
                        previous,
                    });
                } else {
                    *warm = None;
                    self.clear[si(side)][k] = Some(Clear {
                        at: position,
                        s_track_m: pose.s_track_m,
                    });
                }
                out.candidates[si(side)][k] = result;
            }
        }
        Ok(out)
    }
}
