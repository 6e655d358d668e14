//! The per-step contact search of a wheelset (paper Fig. 8 steps b and f):
//! both wheels, every piece of their profiles (tread and flange), warm
//! started from the previous step's surface parameters, with the flange
//! search rule.

use nalgebra::Vector3;

use super::candidate::Candidate;
use super::geometry::{PieceHints, SurfaceParams};
use super::model::{WheelsetContactModel, same_contact};
use super::predictor::Linearisation;
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

/// The candidates of one wheelset: for each wheel (left, right) up to
/// [`MAX_SEGMENTS`] slots, one per patch — a minimum of the gap between the
/// wheel and its rail, in contact or not (docs/reference/06-contact-detection.md §6.7). A slot is not a
/// piece of the profile: a piece may hold several patches (S1002 on UIC60
/// around 5 mm of lateral shift touches with its tread and its flange root),
/// and [`Candidate::segment`] names the piece a patch lies on. Each patch is
/// listed once.
///
/// Slot order: after a fresh search (quasi-static solves, and the first solve
/// of a run) the deepest patch of each wheel comes first; during time
/// stepping ([`ContactOptions::reuse_clear_pieces`]) a patch keeps its slot
/// from step to step while it is followed, and a new patch takes the first
/// free slot.
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
    /// Searches of a piece (the coarse search, then Newton from every
    /// stationary point it finds).
    pub cold_starts: u64,
    /// Flange pieces skipped by the `auto` rule or `off`.
    pub flange_skipped: u64,
    /// Contacts taken from the minimisation fallback.
    pub minimisations: u64,
    /// Pieces without a patch not searched again during time stepping
    /// because the wheel has hardly moved since their last search (see
    /// `Searched` in the solver's source).
    pub clear_skipped: u64,
}

/// A patch remembered from the previous solve.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Warm {
    /// The piece it lay on.
    segment: usize,
    zone: Zone,
    params: SurfaceParams,
    /// Rail arc length at the wheelset's track position when solved.
    rail_l_m: f64,
    /// Gap (−δ) at that solve (m).
    gap_m: f64,
    /// The solve before, for the linear predictor.
    previous: Option<(SurfaceParams, f64)>,
    /// Where the lookups of its last follow ended (the next follow starts
    /// there: the same values, found without a search).
    hints: PieceHints,
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
    /// Yaw of the wheelset relative to the track (rad, signed): the flange
    /// rule's (docs/reference/06-contact-detection.md §6.5).
    yaw_rad: f64,
    /// Height of the wheel's profile origin along the track normal (m).
    vertical_m: f64,
    /// Sine of the yaw of the axle relative to this wheel's rail, about the
    /// rail's normal: −η·t_r, η the axle, t_r the rail's own tangent (–,
    /// positive as `yaw_rad`). Unlike `yaw_rad` it sees the rail's own
    /// direction, which alignment irregularities turn by milliradians.
    rail_yaw_sin: f64,
    /// Sine of the roll of the axle relative to this wheel's rail, about
    /// the rail's tangent: η·b_r, b_r the rail's own normal (–; it includes
    /// the rail inclination, a constant: only its changes are used).
    /// Both sines are compared by their changes, which for the angles of a
    /// wheelset on its rail (below 0.1 rad) are the angles' changes to
    /// within 0.5 %.
    rail_roll_sin: f64,
}

/// Where wheel `side` is; `l` the rail's arc length at the wheelset's
/// track distance and `n`, `b` the centreline frame's lateral and normal
/// vectors there, normalised (looked up once per solve for both wheels).
/// Lateral measures are taken along the track's lateral vector (not the
/// rail frame's, which is tilted by the rail inclination: with it, the
/// axle height would leak into the approach); the angles for the
/// clear-piece cache against the rail's own frame.
fn wheel_position(
    model: &WheelsetContactModel,
    track: &TrackTables,
    pose: &WheelsetPose,
    side: Side,
    l: f64,
    n: &Vector3<f64>,
    b: &Vector3<f64>,
) -> Result<WheelPosition, ContactError> {
    let sigma = match side {
        Side::Left => -1.0,
        Side::Right => 1.0,
    };
    let rail = track.rail(side).at(l)?;
    let axle = pose.frame.column(1);
    let h = -sigma * model.half_spacing_m(side);
    let origin = pose.position + axle * h;
    let delta = (origin - rail.position).dot(n);
    let spacing = model.placement().rail_spacing_m;
    let delta0 = -sigma * (model.half_spacing_m(side) - 0.5 * spacing);
    Ok(WheelPosition {
        approach_m: -sigma * (delta - delta0),
        yaw_rad: pose.frame.column(0).dot(n).clamp(-1.0, 1.0).asin(),
        vertical_m: (origin - rail.position).dot(b),
        rail_yaw_sin: -axle.dot(&rail.frame.t),
        rail_roll_sin: axle.dot(&rail.frame.b),
    })
}

/// Where the wheel was when a piece was last searched (time stepping). The
/// piece is searched again only when the wheel has moved relative to its
/// rail by more than [`CLEAR_RECHECK_M`] laterally or vertically or
/// [`CLEAR_RECHECK_RAD`] in yaw or roll, or when a patch followed on it is
/// lost; in between, its patches are followed by warm start (a Newton
/// solve, 0.3–0.5 µs, where a search of one piece and the Newton solves
/// from its starts cost about 15 µs: `--bench contact_solve`) and a piece
/// found without any stays clear.
///
/// Travel alone does not call for a search: the gap between a wheel piece
/// and the rail is fixed by the wheel's position and angles relative to
/// the rail's own point and frame at the wheel, which are watched, up to
/// the rail's bending over the patch's lead or lag (15 mm on a 150 m
/// radius: 0.75 µm). The wheelset's rotation about its axle changes
/// nothing (a wheel is a body of revolution) and neither does the rail's
/// pitch about it.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Searched {
    at: WheelPosition,
}

/// Lateral motion of a wheel after which a piece is searched again (m). A
/// patch appears on a piece only when the wheel moves so that the piece
/// faces the rail or a second minimum of the gap forms on it, a motion of
/// millimetres (S1002's flange root takes over between 5 and 7 mm of shift),
/// so 0.2 mm is conservative.
const CLEAR_RECHECK_M: f64 = 2e-4;
/// Yaw or roll change relative to the rail after which a piece is searched
/// again (rad; compared as the change of the angle's sine, see
/// `WheelPosition`).
const CLEAR_RECHECK_RAD: f64 = 5e-4;

/// Largest gap (m) of a patch other than the deepest of its piece that is
/// kept (and followed during time stepping) although not in contact: a
/// second minimum of the gap this close to the rail comes into contact with
/// a fraction of a millimetre of further motion, and following it costs one
/// Newton solve per step where a search costs tens of µs. The deepest
/// minimum of each piece is kept whatever its gap (the flange rule and the
/// settling use it).
pub const SECOND_PATCH_GAP_M: f64 = 5e-4;

impl Searched {
    fn still_valid(&self, now: &WheelPosition) -> bool {
        (now.approach_m - self.at.approach_m).abs() < CLEAR_RECHECK_M
            && (now.vertical_m - self.at.vertical_m).abs() < CLEAR_RECHECK_M
            && (now.rail_yaw_sin - self.at.rail_yaw_sin).abs() < CLEAR_RECHECK_RAD
            && (now.rail_roll_sin - self.at.rail_roll_sin).abs() < CLEAR_RECHECK_RAD
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
    /// The patches of the last solve, by slot.
    warm: [[Option<Warm>; MAX_SEGMENTS]; 2],
    /// The last solve's linearisation of each slot's patch when it was
    /// followed (the next start, docs/reference/06-contact-detection.md
    /// §6.2); kept apart from `warm` so that it is updated in place.
    linear: [[Option<Linearisation>; MAX_SEGMENTS]; 2],
    /// Each piece's last search, by piece.
    searched: [[Option<Searched>; MAX_SEGMENTS]; 2],
    pub stats: SolverStats,
    /// Working list of the patches found for a wheel (empty between calls;
    /// kept so that a step allocates nothing).
    scratch: Vec<(Option<usize>, Candidate)>,
}

impl ContactSolver {
    pub fn new(options: ContactOptions) -> Self {
        Self {
            options,
            warm: Default::default(),
            linear: Default::default(),
            searched: Default::default(),
            stats: SolverStats::default(),
            scratch: Vec::with_capacity(4 * MAX_SEGMENTS),
        }
    }

    /// Forget the previous solutions (the next solve starts cold).
    pub fn reset(&mut self) {
        self.warm = Default::default();
        self.linear = Default::default();
        self.searched = Default::default();
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
        let flange_warm = self.warm[si(side)]
            .iter()
            .flatten()
            .any(|w| w.zone == Zone::Flange && w.gap_m < margin);
        if flange_warm {
            return true;
        }
        let reach =
            w.yaw_rad.abs() * (2.0 * wheel.nominal_radius_m() * wheel.flange_depth_m()).sqrt();
        w.approach_m + reach >= self.options.flange_clearance_m[si(side)] - margin
    }

    /// Find every patch of both wheels for `pose` (paper Fig. 8 step b),
    /// keeping the surface parameters for the next call (step f); see
    /// docs/reference/06-contact-detection.md §6.7.
    ///
    /// * Quasi-static (`reuse_clear_pieces` off, the default): every piece is
    ///   searched afresh, so the result depends on the pose only — never on
    ///   the poses solved before.
    /// * Time stepping (`reuse_clear_pieces` on): each patch of the last
    ///   solve is followed by warm start, and a piece is searched again only
    ///   when the wheel has moved (see `Searched`) or a patch on it is lost.
    ///
    /// Of the minima of the gap found, each patch is kept once
    /// ([`super::DUPLICATE_M`]): every patch in contact, the deepest of
    /// each piece, and others within [`super::SECOND_PATCH_GAP_M`] of the rail. An
    /// error when a wheel has more patches in contact than slots.
    pub fn solve(
        &mut self,
        model: &WheelsetContactModel,
        track: &TrackTables,
        pose: &WheelsetPose,
    ) -> Result<WheelsetContacts, ContactError> {
        let mut out = WheelsetContacts::default();
        self.solve_into(model, track, pose, &mut out)?;
        Ok(out)
    }

    /// [`Self::solve`], written into `out` (every slot of both wheels set):
    /// the candidates are kilobytes, and a caller that keeps them (a
    /// vehicle's snapshot, at every right-hand side) saves the copy of a
    /// returned value. On error `out` is partly written and must not be used.
    pub fn solve_into(
        &mut self,
        model: &WheelsetContactModel,
        track: &TrackTables,
        pose: &WheelsetPose,
        out: &mut WheelsetContacts,
    ) -> Result<(), ContactError> {
        let stepping = self.options.reuse_clear_pieces;
        // The centreline frame and the rails' arc lengths at the wheelset,
        // one lookup for both wheels.
        let (frame, rail_l) = track.centerline.frame_and_rail_l(pose.s_track_m)?;
        let (n, b) = (frame.n.normalize(), frame.b.normalize());
        for side in Side::BOTH {
            let i = si(side);
            let l_now = rail_l[i];
            let position = wheel_position(model, track, pose, side, l_now, &n, &b)?;
            let flange = self.flange_needed(model, &position, side);
            let segments = model.wheel(side).segments();
            // (slot followed from the last solve, patch)
            let mut found = std::mem::take(&mut self.scratch);
            found.clear();
            let mut lost = [false; MAX_SEGMENTS];
            // Patches on flange pieces the rule does not search now: kept
            // in memory, not reported.
            let mut parked = [false; MAX_SEGMENTS];
            // The lookup hints each followed slot ended with.
            let mut hints = [PieceHints::NONE; MAX_SEGMENTS];
            if stepping {
                for (slot, park) in parked.iter_mut().enumerate() {
                    let Some(w) = self.warm[i][slot] else {
                        continue;
                    };
                    if w.zone == Zone::Flange && !flange {
                        *park = true;
                        continue;
                    }
                    let guess = w.guess(l_now);
                    hints[slot] = w.hints;
                    let mut c = None;
                    let iterations = model.follow(
                        track,
                        pose,
                        side,
                        w.segment,
                        guess,
                        &mut hints[slot],
                        Some(&mut self.linear[i][slot]),
                        &self.options,
                        &mut c,
                    );
                    self.stats.solves += 1;
                    self.stats.iterations += u64::from(iterations);
                    match c {
                        Some(c) => found.push((Some(slot), c)),
                        None => lost[w.segment] = true,
                    }
                }
            }
            for (k, seg) in segments.iter().enumerate() {
                if seg.zone == Zone::Flange && !flange {
                    self.stats.flange_skipped += 1;
                    continue;
                }
                if stepping
                    && !lost[k]
                    && self.searched[i][k].is_some_and(|c| c.still_valid(&position))
                {
                    if !found.iter().any(|(_, c)| c.segment == k) {
                        self.stats.clear_skipped += 1;
                    }
                    continue;
                }
                let patches = model.search_piece(track, pose, side, k, &self.options)?;
                self.searched[i][k] = Some(Searched { at: position });
                self.stats.solves += 1;
                self.stats.cold_starts += 1;
                if let Some(c) = patches.first() {
                    self.stats.iterations += u64::from(c.iterations);
                }
                found.extend(patches.into_iter().map(|c| (None, c)));
            }
            keep(&mut found, side, |a, b| model.separated(track, pose, a, b))?;
            // Slots: a followed patch keeps its own, the others fill the free
            // ones, deepest first.
            let mut taken = parked;
            for (slot, _) in &found {
                if let Some(k) = slot {
                    taken[*k] = true;
                }
            }
            let mut assigned: [Option<usize>; MAX_SEGMENTS] = [None; MAX_SEGMENTS];
            for (n, (slot, c)) in found.iter().enumerate() {
                let k = match slot {
                    Some(k) => Some(*k),
                    None => {
                        let free = (0..MAX_SEGMENTS).find(|&k| !taken[k]);
                        if let Some(k) = free {
                            taken[k] = true;
                        }
                        free
                    }
                };
                match k {
                    Some(k) => assigned[k] = Some(n),
                    // Surplus gaps are not patches (see `keep`).
                    None if !c.in_contact() => {}
                    None => {
                        return Err(ContactError::TooManyPatches {
                            side,
                            capacity: MAX_SEGMENTS,
                        });
                    }
                }
            }
            for k in 0..MAX_SEGMENTS {
                out.candidates[i][k] = None;
                if parked[k] {
                    continue;
                }
                let Some(n) = assigned[k] else {
                    self.warm[i][k] = None;
                    self.linear[i][k] = None;
                    continue;
                };
                let (followed, c) = &found[n];
                if followed.is_none() {
                    self.linear[i][k] = None;
                }
                if c.method == super::SolveMethod::Minimisation {
                    self.stats.minimisations += 1;
                }
                let previous = self.warm[i][k]
                    .filter(|_| followed.is_some())
                    .map(|w| (w.params, w.rail_l_m));
                self.warm[i][k] = Some(Warm {
                    segment: c.segment,
                    zone: c.zone,
                    params: c.params,
                    rail_l_m: l_now,
                    gap_m: -c.penetration_m,
                    previous,
                    hints: if followed.is_some() {
                        hints[k]
                    } else {
                        PieceHints::NONE
                    },
                });
                out.candidates[i][k] = Some(*c);
            }
            found.clear();
            self.scratch = found;
        }
        Ok(())
    }
}

/// The patches of one wheel to report, from the minima found (followed ones
/// first): each once ([`same_contact`], the first found kept); of the ones in
/// contact, deepest first, those not `separated` from a deeper one dropped
/// (one connected overlap is one patch); then every remaining one in
/// contact, the deepest of each piece, and the others within
/// [`super::SECOND_PATCH_GAP_M`]; at most [`MAX_SEGMENTS`], deepest first (an error
/// when patches in contact would be dropped; surplus gaps are not patches
/// and are dropped).
fn keep(
    found: &mut Vec<(Option<usize>, Candidate)>,
    side: Side,
    separated: impl Fn(&Candidate, &Candidate) -> bool,
) -> Result<(), ContactError> {
    let mut n = 0;
    while n < found.len() {
        if found[..n].iter().any(|(_, u)| same_contact(u, &found[n].1)) {
            found.remove(n);
        } else {
            n += 1;
        }
    }
    found.sort_by(|a, b| b.1.penetration_m.total_cmp(&a.1.penetration_m));
    let mut n = 0;
    while n < found.len() {
        let c = &found[n].1;
        if c.in_contact() && found[..n].iter().any(|(_, d)| !separated(d, c)) {
            found.remove(n);
        } else {
            n += 1;
        }
    }
    let mut deepest = [f64::NEG_INFINITY; MAX_SEGMENTS];
    for (_, c) in found.iter() {
        if let Some(d) = deepest.get_mut(c.segment) {
            *d = d.max(c.penetration_m);
        }
    }
    found.retain(|(_, c)| {
        c.in_contact()
            || -c.penetration_m < SECOND_PATCH_GAP_M
            || deepest.get(c.segment).is_none_or(|&d| c.penetration_m >= d)
    });
    if found.len() > MAX_SEGMENTS {
        if found[MAX_SEGMENTS].1.in_contact() {
            return Err(ContactError::TooManyPatches {
                side,
                capacity: MAX_SEGMENTS,
            });
        }
        found.truncate(MAX_SEGMENTS);
    }
    Ok(())
}

#[cfg(test)]
#[cfg(feature = "fixtures")] // the shared S1002/UIC60 wheelset
mod tests {
    use super::*;

    /// A real tread contact, moved `dy_m` across and set to `penetration_m`
    /// on piece `segment`.
    fn patch(dy_m: f64, penetration_m: f64, segment: usize) -> Candidate {
        let mut c = crate::fixtures::wheelsets::centred_s1002_left_tread();
        c.wheel_point.y += dy_m;
        c.rail_point.y += dy_m;
        c.penetration_m = penetration_m;
        c.segment = segment;
        c
    }

    fn kept(
        found: &[(Option<usize>, Candidate)],
        separated: bool,
    ) -> Result<Vec<(Option<usize>, f64)>, ContactError> {
        let mut v = found.to_vec();
        keep(&mut v, Side::Left, |_, _| separated)?;
        Ok(v.iter().map(|(s, c)| (*s, c.penetration_m)).collect())
    }

    /// The same contact found twice (within 0.1 mm) is kept once, the first
    /// found (a followed patch before a search's).
    #[test]
    fn a_patch_found_twice_is_kept_once() {
        let a = patch(0.0, 1e-5, 0);
        let b = patch(5e-5, 1.1e-5, 1);
        let v = kept(&[(Some(3), a), (None, b)], true).unwrap();
        assert_eq!(v, vec![(Some(3), 1e-5)]);
        let c = patch(2e-4, 1.1e-5, 0);
        assert_eq!(kept(&[(Some(3), a), (None, c)], true).unwrap().len(), 2);
    }

    /// Two minima in contact are two patches only when their overlaps are
    /// separate; joined, the deepest stays.
    #[test]
    fn joined_minima_are_one_patch() {
        let found = [(None, patch(0.0, 1e-5, 0)), (None, patch(0.01, 2e-5, 0))];
        assert_eq!(
            kept(&found, true).unwrap(),
            vec![(None, 2e-5), (None, 1e-5)]
        );
        assert_eq!(kept(&found, false).unwrap(), vec![(None, 2e-5)]);
    }

    /// Gaps: the deepest of each piece stays, others only within
    /// `SECOND_PATCH_GAP_M`.
    #[test]
    fn gaps_beside_a_patch() {
        let found = [
            (None, patch(0.0, 1e-5, 0)),
            (None, patch(0.01, -4e-4, 0)),
            (None, patch(0.02, -6e-4, 0)),
            (None, patch(0.03, -3e-3, 1)),
        ];
        assert_eq!(
            kept(&found, true).unwrap(),
            vec![(None, 1e-5), (None, -4e-4), (None, -3e-3)]
        );
    }

    /// More patches in contact than slots is an error naming the wheel;
    /// surplus gaps are dropped.
    #[test]
    fn more_patches_than_slots() {
        let mut found: Vec<(Option<usize>, Candidate)> = (0..=MAX_SEGMENTS)
            .map(|k| (None, patch(0.01 * k as f64, 1e-5 * (k + 1) as f64, 0)))
            .collect();
        let e = kept(&found, true).unwrap_err();
        assert!(
            e.to_string()
                .contains("left wheel touches its rail in more than 6"),
            "{e}"
        );
        found[0].1.penetration_m = -1e-5;
        assert_eq!(kept(&found, true).unwrap().len(), MAX_SEGMENTS);
    }

    /// Written in place, every slot of both wheels is set: a snapshot
    /// holding stale candidates in all slots comes back equal to the
    /// returned value of the same solve.
    #[test]
    fn solve_into_sets_every_slot() {
        use crate::fixtures::wheelsets;
        let m = wheelsets::s1002_uic60().unwrap();
        let track = wheelsets::straight_track_for(&m, 20.0);
        let pose = WheelsetPose::on_track(&track, 10.0, 0.002, 0.4597, 0.0, 0.0).unwrap();
        let mut a = ContactSolver::new(ContactOptions::default());
        let mut b = a.clone();
        let expect = a.solve(&m, &track, &pose).unwrap();
        assert!(expect.iter().count() >= 2, "{expect:?}");
        let stale = patch(0.0, 1e-5, 0);
        let mut out = WheelsetContacts {
            candidates: [[Some(stale); MAX_SEGMENTS]; 2],
        };
        b.solve_into(&m, &track, &pose, &mut out).unwrap();
        assert_eq!(out, expect);
    }
}
