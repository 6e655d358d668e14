//! Where a wheelset's contacts come from: one [`ContactSource`] per
//! wheelset, built from the run's [`ContactMethod`] at assembly
//! ([`ContactMethod::sources`]), through which the vehicle system settles
//! the wheelset ([`super::VehicleSystem::assemble`]), finds its contacts
//! and their forces ([`super::VehicleSystem::evaluate`]) without knowing
//! which method it runs:
//!
//! - [`OnlineContact`]: Newton on the surface parameters at every
//!   evaluation, warm-started from the previous solve (paper §4.2–4.3;
//!   [`ContactSolver`]), Hertz normal force with hysteresis and the run's
//!   creep law ([`evaluate_contact`]; paper eqs. 22–23, docs/reference/07-contact-forces.md §7);
//! - [`TableContact`]: the contact points interpolated from the
//!   wheelset's contact lookup table (paper §2, docs/reference/01-units-frames.md §0, §7.4;
//!   [`super::table_contact`]), evaluated for the actual pose, forces as
//!   online;
//! - [`ImportedContact`]: one contact per wheel from a table computed by
//!   another code, with that code's normal force and creep model
//!   ([`super::imported_contact`]).
//!
//! # What a source provides
//!
//! Units SI (m, rad, N, N·m, s); vectors in the global frame (Z up), the
//! track frame `t, n, b` as in docs/reference/01-units-frames.md §1; candidates indexed `[left,
//! right][piece]` ([`WheelsetContacts`]).
//!
//! - [`ContactSource::settle`]: the wheelset seated on the rails under
//!   its static wheel load at track distance s (m), lateral shift y (m, +
//!   left) and yaw (rad, + nose left) — its pose, contacts and normal
//!   forces ([`Settled`]). Called at assembly only.
//! - [`ContactSource::contacts`]: the candidates of the wheelset at its
//!   pose (centre, non-spinning axle frame, track distance) and its
//!   position relative to the track ([`TrackRelative`]): for each, the
//!   wheel and rail points (m, global), the contact frame (normal from
//!   rail into wheel, rolling and lateral directions; unit vectors,
//!   global), the penetration (m, + overlapping), contact angle (rad),
//!   rolling radius (m) and principal curvatures (1/m). A source may keep
//!   state between calls (a warm start, the rows it read), which
//!   [`ContactSource::force`] may use.
//! - [`ContactSource::force`]: the force of one of those candidates (on
//!   the wheel, N and N·m at the contact point, global; `None` out of
//!   contact) for the wheelset's motion and the candidate's hysteresis
//!   memory, with the run's [`ContactForceSettings`]. It returns the next
//!   memory with the force; the system commits it at accepted states only.
//!
//! The wheelset's [`ContactSolver`] is the system's (its statistics are
//! reported per wheelset, [`super::VehicleSystem::solvers`]) and is lent
//! to the source in its [`ContactContext`]; sources that do not search
//! leave it untouched.

use std::sync::Arc;

use super::error::DynamicsError;
use super::imported_contact::ImportedContact;
use super::settings::ContactMethod;
use super::table_contact::TableContact;
use super::track_motion::TrackRelative;
use super::vehicle::WheelsetSpec;
use crate::contact::imported_lookup::ImportedLookup;
use crate::contact::quasi_static::{Settled, Support, settle};
use crate::contact::{Candidate, ContactError, ContactSolver, WheelsetContacts, WheelsetPose};
use crate::forces::normal::ContactMemory;
use crate::geometry::track::TrackTables;
use crate::multibody::contact_force::{
    ContactForce, ContactForceError, ContactForceSettings, WheelsetMotion, evaluate_contact,
};

/// What a [`ContactSource`] may use besides its own data: the track, the
/// wheelset (profiles as a contact model, static wheel load, nominal
/// radius) and the wheelset's contact solver (module docs).
pub struct ContactContext<'c> {
    pub track: &'c TrackTables,
    pub wheelset: &'c WheelsetSpec,
    pub solver: &'c mut ContactSolver,
}

/// The contacts of one wheelset (module docs: what a source provides,
/// units and frames).
pub trait ContactSource: std::fmt::Debug {
    /// The wheelset seated on the rails under its static wheel load at
    /// track distance `s_m` (m), lateral shift `y_m` (m, + left) and
    /// `yaw_rad` (rad, + nose left), with the run's force settings
    /// (material of the Hertz contacts). By default on the wheelset's
    /// profiles with elastic support (`crate::contact::quasi_static`); a
    /// source with its own contact geometry (imported) settles on that.
    fn settle(
        &mut self,
        ctx: ContactContext<'_>,
        forces: &ContactForceSettings,
        s_m: f64,
        y_m: f64,
        yaw_rad: f64,
    ) -> Result<Settled, ContactError> {
        settle_on_profiles(ctx, forces, s_m, y_m, yaw_rad)
    }

    /// The wheelset's candidates at `pose`, `relative` to the track.
    fn contacts(
        &mut self,
        ctx: ContactContext<'_>,
        pose: &WheelsetPose,
        relative: &TrackRelative,
    ) -> Result<WheelsetContacts, ContactError>;

    /// [`Self::contacts`] written into `out` (the vehicle's snapshot, at
    /// every right-hand side: a returned value of kilobytes would be copied
    /// there). On error `out` may be partly written and must not be used.
    fn contacts_into(
        &mut self,
        ctx: ContactContext<'_>,
        pose: &WheelsetPose,
        relative: &TrackRelative,
        out: &mut WheelsetContacts,
    ) -> Result<(), ContactError> {
        *out = self.contacts(ctx, pose, relative)?;
        Ok(())
    }

    /// The force of candidate `c` of the last [`Self::contacts`] for the
    /// wheelset's `motion`, from the candidate's hysteresis `memory`;
    /// `Ok(None)` out of contact. By default the per-contact pipeline on
    /// the candidate's own geometry ([`evaluate_contact`]); a source that
    /// brings its own contact data (imported) computes it from that.
    fn force(
        &self,
        forces: &ContactForceSettings,
        c: &Candidate,
        memory: &ContactMemory,
        motion: &WheelsetMotion,
    ) -> Result<Option<ContactForce>, ContactForceError> {
        evaluate_contact(forces, c, memory, motion)
    }

    /// Whether the normal force is, by construction, the gradient of the
    /// elastic energy 0.4 K δ^2.5 the energy ledger counts (up to the change
    /// of K across the profiles): true for the profile-based sources (force
    /// along the profiles' common normal, δ their approach). False for the
    /// imported table, whose normal force does work beyond that energy; the
    /// ledger books it as the contact normal work
    /// (docs/reference/08-multibody.md §8.6).
    fn normal_force_is_gradient(&self) -> bool {
        true
    }
}

/// Settling on the wheelset's profiles, elastic support under its static
/// wheel load (`crate::contact::quasi_static`): the online and table
/// sources.
pub(super) fn settle_on_profiles(
    ctx: ContactContext<'_>,
    forces: &ContactForceSettings,
    s_m: f64,
    y_m: f64,
    yaw_rad: f64,
) -> Result<Settled, ContactError> {
    let w = ctx.wheelset;
    let support = Support::Elastic {
        load_per_wheel_n: w.static_wheel_load_n,
        material: forces.material,
    };
    settle(
        &w.contact, ctx.track, s_m, y_m, yaw_rad, support, ctx.solver,
    )
}

/// Newton on the surface parameters at every evaluation (module docs).
#[derive(Debug, Clone, Copy, Default)]
pub struct OnlineContact;

impl ContactSource for OnlineContact {
    fn contacts(
        &mut self,
        ctx: ContactContext<'_>,
        pose: &WheelsetPose,
        _relative: &TrackRelative,
    ) -> Result<WheelsetContacts, ContactError> {
        ctx.solver.solve(&ctx.wheelset.contact, ctx.track, pose)
    }

    fn contacts_into(
        &mut self,
        ctx: ContactContext<'_>,
        pose: &WheelsetPose,
        _relative: &TrackRelative,
        out: &mut WheelsetContacts,
    ) -> Result<(), ContactError> {
        ctx.solver
            .solve_into(&ctx.wheelset.contact, ctx.track, pose, out)
    }
}

impl ContactMethod {
    /// One source per wheelset (`n_wheelsets`, vehicle order), checked
    /// against the run: a table per wheelset; an imported table's creep
    /// law and shear modulus ([`super::imported_contact::ImportedContactMethod::validate`]).
    pub fn sources(
        &self,
        forces: &ContactForceSettings,
        n_wheelsets: usize,
    ) -> Result<Vec<Box<dyn ContactSource>>, DynamicsError> {
        let refuse = |reason: String| DynamicsError::Assembly {
            wheelset: String::from("(all)"),
            reason,
        };
        let count = |tables: usize| {
            if tables == n_wheelsets {
                Ok(())
            } else {
                Err(refuse(format!(
                    "{tables} contact tables for {n_wheelsets} wheelsets"
                )))
            }
        };
        Ok(match self {
            ContactMethod::Online => (0..n_wheelsets)
                .map(|_| Box::new(OnlineContact) as Box<dyn ContactSource>)
                .collect(),
            ContactMethod::Table(tables) => {
                count(tables.len())?;
                tables
                    .iter()
                    .map(|t| Box::new(TableContact::new(Arc::clone(t))) as Box<dyn ContactSource>)
                    .collect()
            }
            ContactMethod::Imported(m) => {
                m.validate(forces, n_wheelsets).map_err(refuse)?;
                let g = m.shear_modulus_pa(forces);
                m.tables
                    .iter()
                    .map(|t| {
                        let lookup = ImportedLookup::new(Arc::clone(t), m.interpolation)
                            .map_err(|e| refuse(e.to_string()))?;
                        Ok(
                            Box::new(ImportedContact::with_lookup(lookup, g).with_normal(m.normal))
                                as Box<dyn ContactSource>,
                        )
                    })
                    .collect::<Result<_, _>>()?
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::imported::{ImportedContactTable, ImportedRow};
    use crate::contact::table::{ConicityTable, ContactTable, ContactTableMeta};
    use crate::multibody::imported_contact::ImportedContactMethod;

    fn contact_table() -> Arc<ContactTable> {
        Arc::new(ContactTable {
            meta: ContactTableMeta::default(),
            y_m: vec![-0.01, 0.01],
            yaw_rad: vec![0.0],
            rows: vec![Default::default(); 2],
            conicity: ConicityTable::default(),
        })
    }

    fn imported_table() -> Arc<ImportedContactTable> {
        let row = ImportedRow {
            normal_force_n: 66_000.0,
            contact_angle_rad: 0.014,
            a_m: 6e-3,
            b_m: 6.5e-3,
            wheel_lateral_m: 0.756,
            rolling_radius_m: 0.425,
            c11: 4.1,
            c22: 3.6,
            c23: 1.4,
            rail_vertical_m: -6e-5,
            penetration_m: 7e-5,
        };
        Arc::new(ImportedContactTable {
            source: "test".into(),
            format: "test".into(),
            y_m: vec![-0.01, 0.0, 0.01],
            rows: vec![row; 3],
        })
    }

    #[test]
    fn one_source_per_wheelset_or_a_named_refusal() {
        let forces = ContactForceSettings::default();
        assert_eq!(ContactMethod::Online.sources(&forces, 3).unwrap().len(), 3);
        let table = ContactMethod::Table(vec![contact_table(); 2]);
        assert_eq!(table.sources(&forces, 2).unwrap().len(), 2);
        // Fewer tables than wheelsets: refused, not a panic at run time.
        let e = table.sources(&forces, 3).unwrap_err().to_string();
        assert!(e.contains("2 contact tables for 3 wheelsets"), "{e}");
        let imported = |n| {
            ContactMethod::Imported(ImportedContactMethod {
                tables: vec![imported_table(); n],
                shear_modulus_override_pa: None,
                interpolation: Default::default(),
                normal: Default::default(),
            })
        };
        let heuristic = ContactForceSettings {
            creep_law: crate::forces::creep::CreepLaw::Heuristic,
            ..Default::default()
        };
        assert_eq!(imported(2).sources(&heuristic, 2).unwrap().len(), 2);
        let e = imported(1).sources(&heuristic, 2).unwrap_err().to_string();
        assert!(
            e.contains("1 imported contact tables for 2 wheelsets"),
            "{e}"
        );
        // The imported method's own checks (its creep laws) still apply.
        assert!(imported(2).sources(&forces, 2).is_err());
    }
}
