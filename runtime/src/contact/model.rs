//! A wheelset's contact model: its two wheel profiles and the two rail
//! profiles placed on the track, with the pair-level solve (warm or cold).

use nalgebra::Vector4;

use super::candidate::{Candidate, SolveMethod, from_eval};
use super::geometry::{Pair, PairEval, PieceHints, SurfaceParams};
use super::lu4::Lu4;
use super::predictor::{Linearisation, Start};
use super::search::RailSlopes;
use super::{ContactError, ContactOptions, WheelsetPose, newton, search};
use crate::geometry::profile::{
    PlacedRailProfile, ProfileError, RailPlacement, RailProfile, WheelProfile,
};
use crate::geometry::track::{Side, TrackTables};

/// Tolerance on the profile domains when accepting a solution (m).
const DOMAIN_TOL_M: f64 = 1e-4;
/// Largest |s_w| of an acceptable solution (rad): beyond it the "contact"
/// would be on the side of the wheel, not under it.
const MAX_S_WHEEL_RAD: f64 = 0.6;
/// A failed solve whose last iterate lies farther than this outside the
/// profiles (m) has left its zone: no contact there, not a failure.
const OUTSIDE_M: f64 = 0.002;
/// Sampled gap beyond which a piece whose exact closest point was not found
/// is still certainly clear of the rail (m); see `clear_gap_m`.
const CLEAR_GAP_M: f64 = 0.001;
/// Resolution of the test whether two patches are separate (m along the
/// wheel profile): a lift-off narrower than this between two minima of the
/// gap in contact may go unseen, and the two are then one patch — 0.25 mm,
/// a tenth of a tread patch's half-width, where elastic deformation closes
/// such a gap anyway.
const SEPARATION_STEP_M: f64 = 2.5e-4;
/// Bisection levels of that test at most (2⁸ points: 0.25 mm over 64 mm).
const SEPARATION_LEVELS: u32 = 8;

/// Two solutions whose wheel points and rail points both lie closer than
/// this (m) are the same contact, found twice (from two starts, or by the
/// searches of two neighbouring pieces when it lies at their split). Two
/// distinct minima of the gap are separated by a maximum, and where they are
/// this close they are about to merge and vanish (a fold): 0.1 mm is far
/// below a contact patch's size.
pub const DUPLICATE_M: f64 = 1e-4;

fn side_index(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

/// The profiles of one wheelset on one track.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelsetContactModel {
    wheels: [WheelProfile; 2],
    rails: [PlacedRailProfile; 2],
    back_to_back_m: f64,
    placement: RailPlacement,
    /// The rail heads' slope tables for the search (left, right).
    slopes: [RailSlopes; 2],
}

impl WheelsetContactModel {
    /// Assemble the model; rails are placed with `placement` (see
    /// [`RailProfile::placed`]). Left and right profiles may differ.
    pub fn new(
        left_wheel: WheelProfile,
        right_wheel: WheelProfile,
        back_to_back_m: f64,
        left_rail: &RailProfile,
        right_rail: &RailProfile,
        placement: RailPlacement,
    ) -> Result<Self, ProfileError> {
        if !(back_to_back_m > 0.3 && back_to_back_m < 3.0) {
            return Err(ProfileError::Invalid {
                path: left_wheel.path().to_path_buf(),
                rule: format!("back-to-back distance {back_to_back_m} m must lie in 0.3 … 3 m"),
            });
        }
        let rails = [
            left_rail.placed(&placement)?,
            right_rail.placed(&placement)?,
        ];
        Ok(Self {
            slopes: [RailSlopes::new(&rails[0]), RailSlopes::new(&rails[1])],
            rails,
            wheels: [left_wheel, right_wheel],
            back_to_back_m,
            placement,
        })
    }

    /// The wheel profile of a side.
    pub fn wheel(&self, side: Side) -> &WheelProfile {
        &self.wheels[side_index(side)]
    }

    /// The placed rail profile of a side.
    pub fn rail(&self, side: Side) -> &PlacedRailProfile {
        &self.rails[side_index(side)]
    }

    /// Back-to-back distance (m).
    pub fn back_to_back_m(&self) -> f64 {
        self.back_to_back_m
    }

    /// How the rails were placed.
    pub fn placement(&self) -> &RailPlacement {
        &self.placement
    }

    /// Lateral distance from the wheelset centre to a wheel's taping line
    /// (m): back-to-back/2 + the wheel's flange-back distance (b0 of the
    /// paper for identical wheels).
    pub fn half_spacing_m(&self, side: Side) -> f64 {
        0.5 * self.back_to_back_m + self.wheel(side).flange_back_m()
    }

    pub(crate) fn pair<'a>(
        &'a self,
        track: &'a TrackTables,
        pose: &'a WheelsetPose,
        side: Side,
        segment: usize,
    ) -> Option<Pair<'a>> {
        let wheel = self.wheel(side);
        let seg = wheel.segments().get(segment)?;
        Some(Pair::new(
            track.rail(side),
            self.rail(side),
            wheel,
            &seg.curve,
            self.half_spacing_m(side),
            pose,
        ))
    }

    /// Solve the contact equations of one wheel and one piece of its profile
    /// (see [`WheelProfile::segments`]): from `guess` when given, falling back
    /// to the search of the piece, whose deepest patch is returned (a piece
    /// may hold several: [`super::ContactSolver`] returns them all).
    /// `Ok(None)` when the piece does not exist or has no minimum of the gap
    /// of its own (no contact possible on this piece); an error when no start
    /// converges.
    pub fn solve_pair(
        &self,
        track: &TrackTables,
        pose: &WheelsetPose,
        side: Side,
        segment: usize,
        guess: Option<SurfaceParams>,
        options: &ContactOptions,
    ) -> Result<Option<Candidate>, ContactError> {
        // Every path returns `result`, so the candidate is written where
        // the caller receives it (no copies).
        let mut result = Ok(None);
        if let (Some(g), Ok(found)) = (guess, &mut result) {
            let mut hints = PieceHints::NONE;
            self.follow(
                track, pose, side, segment, g, &mut hints, None, options, found,
            );
            if found.as_ref().is_some_and(|c| c.segment == segment) {
                return result;
            }
        }
        result = self
            .search_piece(track, pose, side, segment, options)
            .map(|v| v.into_iter().find(|c| c.segment == segment));
        result
    }

    /// Follow a patch from the previous solution `guess` (warm start):
    /// Newton's method from it, accepted when it converges to a minimum of
    /// the gap on the wheel's profile (possibly on a neighbouring piece: the
    /// candidate names the piece it lies on), written into `found` (`None`
    /// when none is accepted); returns the iterations spent. The lookups
    /// start from `hints` (the same results whatever they hold), which are
    /// left at the last evaluation's pieces. With `linear` (time stepping)
    /// the start is the predictor's from the patch's last linearisation when
    /// there is one (only `guess`'s rail arc length is used then), and the
    /// linearisation is renewed at the solution (`None` when lost).
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn follow(
        &self,
        track: &TrackTables,
        pose: &WheelsetPose,
        side: Side,
        segment: usize,
        guess: SurfaceParams,
        hints: &mut PieceHints,
        mut linear: Option<&mut Option<Linearisation>>,
        options: &ContactOptions,
        found: &mut Option<Candidate>,
    ) -> u32 {
        let Some(pair) = self.pair(track, pose, side, segment) else {
            *found = None;
            if let Some(l) = linear {
                *l = None;
            }
            return 0;
        };
        pair.set_hints(*hints);
        let start = linear
            .as_deref()
            .and_then(|l| l.as_ref().map(|l| l.start(pose, guess.s_rail_m)))
            .unwrap_or(Start::Guess);
        let x0 = match start {
            Start::Guess => guess.to_vector(),
            Start::Same(x) | Start::Predicted { x, .. } => x,
        };
        let mut eval = PairEval::default();
        // The solve factors into the linearisation's own storage when there
        // is one (its factors have given the start and are replaced by the
        // new ones in place: nothing is copied), else into a fresh one.
        let mut fresh_lu = None;
        let lu = match linear.as_deref_mut() {
            Some(Some(l)) => l.lu_mut(),
            _ => fresh_lu.insert(Lu4::ZERO),
        };
        let solved = newton::solve(&pair, x0, options.max_iterations, &mut eval, lu);
        *hints = pair.hints();
        match solved {
            Ok(c) => {
                if let Some(l) = linear.as_deref_mut() {
                    Linearisation::store(l, &pair, pose, &c, &eval, fresh_lu.as_ref(), &start);
                }
                self.accept_into(&pair, side, segment, &c, &eval, false, found);
                c.iterations
            }
            Err(f) => {
                *found = None;
                if let Some(l) = linear {
                    *l = None;
                }
                f.iterations
            }
        }
    }

    /// Every patch the search of one piece finds (docs/reference/06-contact-detection.md §6.3):
    /// Newton's method from each stationary point of the gap along the piece's
    /// contact locus, keeping the converged minima of the gap (maxima between
    /// two patches are not contacts), each once, deepest first. A solution
    /// may lie on a neighbouring piece (a start near the split converging
    /// across it): it is kept, naming its own piece. Empty when the piece
    /// has no minimum of its own; an error when no start converges on a
    /// piece in or near contact and the minimisation fallback is off.
    pub(crate) fn search_piece(
        &self,
        track: &TrackTables,
        pose: &WheelsetPose,
        side: Side,
        segment: usize,
        options: &ContactOptions,
    ) -> Result<Vec<Candidate>, ContactError> {
        let max_iterations = options.max_iterations;
        let Some(pair) = self.pair(track, pose, side, segment) else {
            return Ok(Vec::new());
        };
        let zone = self.wheel(side).segments()[segment].zone;
        let mut any_converged = false;
        let mut last_fail = None;
        let mut total_iterations = 0;
        let s_rail0 = track.centerline.rail_l(side, pose.s_track_m)?;
        let found = search::search(&pair, &self.slopes[side_index(side)], s_rail0);
        let mut out: Vec<Candidate> = Vec::new();
        let mut eval = PairEval::default();
        let mut lu = Lu4::ZERO;
        for &x0 in &found.starts {
            match newton::solve(&pair, x0, max_iterations, &mut eval, &mut lu) {
                Ok(c) => {
                    any_converged = true;
                    total_iterations += c.iterations;
                    let mut accepted = None;
                    self.accept_into(&pair, side, segment, &c, &eval, true, &mut accepted);
                    if let Some(cand) = accepted
                        && !out.iter().any(|o| same_contact(o, &cand))
                    {
                        out.push(cand);
                    }
                }
                Err(f) => {
                    total_iterations += f.iterations;
                    last_fail = Some(f)
                }
            }
        }
        if !out.is_empty() {
            out.sort_by(|a, b| b.penetration_m.total_cmp(&a.penetration_m));
            for c in &mut out {
                c.iterations = total_iterations;
            }
            return Ok(out);
        }
        match (any_converged, last_fail) {
            (true, _) | (false, None) => Ok(Vec::new()),
            // No stationary point inside this piece: its closest approach is at
            // an end (the contact belongs to the neighbouring piece, or lies
            // beyond the modelled rail), or Newton left the piece for good.
            (false, Some(f))
                if found.at_boundary
                    || !self.near_domains(&pair, &f.x)
                    || found.min_distance_m > self.clear_gap_m(side, pose) =>
            {
                Ok(Vec::new())
            }
            (false, Some(_)) if options.minimisation_fallback && found.minimum.is_some() => {
                let x = found.minimum.expect("checked");
                let e = pair.eval(&x)?;
                let mut c = from_eval(
                    side,
                    zone,
                    segment,
                    SurfaceParams::from_vector(&x),
                    total_iterations,
                    true,
                    &e,
                    pair.sigma,
                    pair.wheel.nominal_radius_m(),
                    self.placement.inclination_rad,
                    |u, z| pair.wheel.to_file_m(u, z),
                    |u, z| pair.rail.to_file_m(u, z),
                );
                c.method = SolveMethod::Minimisation;
                Ok(vec![c])
            }
            (false, Some(f)) => Err(ContactError::NotConverged {
                side,
                zone,
                iterations: total_iterations,
                residual: f.residual,
                params: SurfaceParams::from_vector(&f.x),
                s_track_m: pose.s_track_m,
                position_m: pose.position.into(),
            }),
        }
    }

    /// The candidate of one wheel and piece at given surface parameters,
    /// without solving (the contact lookup table's points, evaluated for
    /// the actual pose: penetration along the rail normal, contact frame,
    /// curvatures). `Ok(None)` when the piece does not exist.
    pub fn candidate_at(
        &self,
        track: &TrackTables,
        pose: &WheelsetPose,
        side: Side,
        segment: usize,
        params: SurfaceParams,
    ) -> Result<Option<Candidate>, ContactError> {
        let Some(pair) = self.pair(track, pose, side, segment) else {
            return Ok(None);
        };
        let zone = self.wheel(side).segments()[segment].zone;
        let e = pair.eval(&params.to_vector())?;
        let wheel = pair.wheel;
        let rail = pair.rail;
        Ok(Some(from_eval(
            side,
            zone,
            segment,
            params,
            0,
            false,
            &e,
            pair.sigma,
            wheel.nominal_radius_m(),
            self.placement.inclination_rad,
            |u, z| wheel.to_file_m(u, z),
            |u, z| rail.to_file_m(u, z),
        )))
    }

    /// A sampled gap larger than this (m) means the piece is clear of the rail
    /// even if its exact closest point was not found: 1 mm plus the reach of
    /// a yawed wheel ahead of its lowest point, |ψ|·√(2·R0·h_f).
    fn clear_gap_m(&self, side: Side, pose: &WheelsetPose) -> f64 {
        let wheel = self.wheel(side);
        let yaw = pose
            .frame
            .column(0)
            .y
            .abs()
            .max(pose.frame.column(0).z.abs());
        CLEAR_GAP_M
            + yaw * (2.0 * wheel.nominal_radius_m() * wheel.flange_depth_m().max(0.01)).sqrt()
    }

    /// Whether two patches in contact on one wheel are separate: some wheel
    /// point between them on the contact locus lies outside the rail (the
    /// overlap of the wheel with its rail has two separate parts). Minima
    /// of the gap joined by an overlap throughout — a nearly conformal
    /// stretch such as S1002's throat against UIC60's gauge corner, both of
    /// radius 13 mm — are one patch (docs/reference/06-contact-detection.md §6.7).
    /// The points between are tried midpoint first, then at every level of
    /// bisection down to [`SEPARATION_STEP_M`].
    pub(crate) fn separated(
        &self,
        track: &TrackTables,
        pose: &WheelsetPose,
        a: &Candidate,
        b: &Candidate,
    ) -> bool {
        let Some(pair) = self.pair(track, pose, a.side, a.segment) else {
            return true;
        };
        let (ua, ub) = (
            pair.sigma * a.params.u_wheel_m,
            pair.sigma * b.params.u_wheel_m,
        );
        let s_r0 = 0.5 * (a.params.s_rail_m + b.params.s_rail_m);
        let span = (ub - ua).abs();
        let mut parts = 2_usize;
        while parts <= 1 << SEPARATION_LEVELS {
            for k in (1..parts).step_by(2) {
                let u = ua + (ub - ua) * k as f64 / parts as f64;
                if search::inside_rail(&pair, s_r0, u) != Some(true) {
                    return true;
                }
            }
            if span / parts as f64 <= SEPARATION_STEP_M {
                break;
            }
            parts *= 2;
        }
        false
    }

    /// True when `x` lies within the profiles, widened by [`OUTSIDE_M`].
    fn near_domains(&self, pair: &Pair<'_>, x: &Vector4<f64>) -> bool {
        pair.wheel_curve.contains(pair.sigma * x[3], OUTSIDE_M)
            && pair.rail.head().contains(pair.sigma * x[1], OUTSIDE_M)
    }

    /// The candidate of a converged solve, or `None` when it is not a
    /// contact: outside the wheel's profile (all pieces) or the rail head,
    /// beyond [`MAX_S_WHEEL_RAD`], or a maximum of the gap (the stationary
    /// point between two patches, [`Candidate::is_gap_minimum`]). A solution
    /// outside the piece `segment` that was solved but on another piece of
    /// the wheel is that piece's. `eval` is the evaluation at `c.x`;
    /// the candidate is written into `out` (built in place).
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn accept_into(
        &self,
        pair: &Pair<'_>,
        side: Side,
        segment: usize,
        c: &newton::Converged,
        eval: &PairEval,
        cold: bool,
        out: &mut Option<Candidate>,
    ) {
        let x: Vector4<f64> = c.x;
        let sg = pair.sigma;
        let u = sg * x[3];
        let segments = self.wheel(side).segments();
        let piece = if pair.wheel_curve.contains(u, DOMAIN_TOL_M) {
            segment
        } else {
            match segments
                .iter()
                .position(|s| s.curve.contains(u, DOMAIN_TOL_M))
            {
                Some(p) => p,
                None => {
                    *out = None;
                    return;
                }
            }
        };
        let rail_ok = pair.rail.head().contains(sg * x[1], DOMAIN_TOL_M);
        if !(rail_ok && x[2].abs() < MAX_S_WHEEL_RAD) {
            *out = None;
            return;
        }
        let wheel = pair.wheel;
        let rail = pair.rail;
        let cand = out.insert(from_eval(
            side,
            segments[piece].zone,
            piece,
            SurfaceParams::from_vector(&x),
            c.iterations,
            cold,
            eval,
            sg,
            wheel.nominal_radius_m(),
            self.placement.inclination_rad,
            |u, z| wheel.to_file_m(u, z),
            |u, z| rail.to_file_m(u, z),
        ));
        if !cand.is_gap_minimum() {
            *out = None;
        }
    }
}

/// True when `a` and `b` are the same contact ([`DUPLICATE_M`]).
pub(crate) fn same_contact(a: &Candidate, b: &Candidate) -> bool {
    (a.wheel_point - b.wheel_point).norm() < DUPLICATE_M
        && (a.rail_point - b.rail_point).norm() < DUPLICATE_M
}
