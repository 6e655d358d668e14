//! One patch followed from solve to solve, as time stepping follows it
//! (docs/reference/06-contact-detection.md §6.2): Newton's method from the
//! predictor's start ([`super::predictor`]) with the lookups starting at
//! the last solve's pieces. [`super::ContactSolver`] does this for every
//! patch of a wheelset; [`FollowedPatch`] exposes it for one (a bench of
//! the warm solve, a user's own loop).

use std::cell::Cell;

use super::candidate::Candidate;
use super::geometry::{PieceHints, SurfaceParams};
use super::predictor::Linearisation;
use super::{ContactError, ContactOptions, WheelsetContactModel, WheelsetPose};
use crate::geometry::track::{Side, TrackTables};

/// A patch of one wheel between two solves: where it was and what the
/// next solve starts from.
#[derive(Debug, Clone, PartialEq)]
pub struct FollowedPatch {
    side: Side,
    segment: usize,
    params: SurfaceParams,
    /// The rail's arc length at the wheelset's track position when last
    /// solved (m).
    rail_l_m: f64,
    /// The centreline table's interval of that position: the next lookup
    /// starts there.
    centerline_row: usize,
    hints: PieceHints,
    linear: Option<Linearisation>,
    /// The last solve's patch (`None` when it was lost).
    found: Option<Candidate>,
}

impl FollowedPatch {
    /// Start following `c`, a patch of the wheelset at `pose` (its first
    /// follow starts from `c`'s parameters moved along the rail; the next
    /// ones from the predictor).
    pub fn new(
        track: &TrackTables,
        pose: &WheelsetPose,
        c: &Candidate,
    ) -> Result<Self, ContactError> {
        let centerline_row = Cell::new(usize::MAX);
        let rail_l_m = track
            .centerline
            .rail_l_near(c.side, pose.s_track_m, &centerline_row)?;
        Ok(Self {
            side: c.side,
            segment: c.segment,
            params: c.params,
            rail_l_m,
            centerline_row: centerline_row.get(),
            hints: PieceHints::NONE,
            linear: None,
            found: None,
        })
    }

    /// Solve the patch for the wheelset at `pose`: the patch found, kept
    /// in `self` until the next solve (not copied out: `.copied()` keeps
    /// it longer); `Ok(None)` when it is lost (no convergence to a minimum
    /// of the gap from the start: the caller searches again, as
    /// [`super::ContactSolver`] does); the patch then starts from its last
    /// parameters again.
    pub fn solve(
        &mut self,
        model: &WheelsetContactModel,
        track: &TrackTables,
        pose: &WheelsetPose,
        options: &ContactOptions,
    ) -> Result<Option<&Candidate>, ContactError> {
        let row = Cell::new(self.centerline_row);
        let l_now = track
            .centerline
            .rail_l_near(self.side, pose.s_track_m, &row)?;
        self.centerline_row = row.get();
        let guess = SurfaceParams {
            s_rail_m: self.params.s_rail_m + (l_now - self.rail_l_m),
            ..self.params
        };
        model.follow(
            track,
            pose,
            self.side,
            self.segment,
            guess,
            &mut self.hints,
            Some(&mut self.linear),
            options,
            &mut self.found,
        );
        if let Some(c) = &self.found {
            self.segment = c.segment;
            self.params = c.params;
            self.rail_l_m = l_now;
        }
        Ok(self.found.as_ref())
    }
}
