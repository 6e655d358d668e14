//! Contact from an imported contact geometry table
//! ([`crate::contact::imported`]; DYTSI's `RSGEO.dat` for the Cooperrider
//! car): the contact model of that code, run inside ours so that the two
//! codes can be compared on the same vehicle. One contact per wheel, no
//! profiles, no search.
//!
//! # Geometry (per wheel, σ = +1 left, −1 right; η the axle pointing left,
//! ζ the axle frame's up; t, n, b the track frame at the wheelset's s)
//!
//! The row is the table's at the wheelset's lateral displacement y (left
//! wheel) or at −y (right wheel; module docs of [`crate::contact::imported`]).
//!
//! - **Wheel point** P_w: the wheel's material point at the table's contact
//!   position, on the axle at ±`wheel_lateral_m` and the rolling radius
//!   below it: P_w = c + σ w η − r ζ (c the wheelset centre).
//! - **Normal** n_c (rail into wheel, docs/reference/01-units-frames.md §1): the track-plane normal b
//!   tilted in the track cross-section by the contact angle δ towards the
//!   track centre: n_c = cos δ b − σ sin δ n. It is the rail's normal at
//!   its contact point, fixed in the track frame; the wheelset's roll does
//!   not turn it (DYTSI tilts it by δ ± roll, a difference of the order of
//!   the roll, 1e-3 rad).
//! - **Rail point** P_r: the rail's contact point, at the table's height
//!   `rail_vertical_m` (z up from the rail-top plane) directly below the
//!   wheel point — P_r = O + (d·t) t + (d·n) n + z_r b, d = P_w − O, O the
//!   centreline point. Not at the table's nominal lateral position
//!   y ± w: with roll φ the wheel point moves laterally by ≈ r φ from it
//!   (0.4 mm at φ = 1 mrad), and on a rail face at 1.2 rad that would read
//!   as a spurious gap r φ tan δ ≈ 1 mm, ten times q0. DYTSI does the same
//!   (`WheelSetComponent::find_rsgeodata` recomputes the rail point's
//!   lateral coordinate from y, the roll and the wheel point).
//! - **Rolling direction** t_c = t (⟂ n_c), lateral l_c = n_c × t_c.
//!
//! # Penetration and normal force
//!
//! The table gives, at its quasi-static state for y, the normal force N0
//! and the penetration q0, with N = N0 (1 + Δq/q0)^1.5 for an additional
//! approach Δq (that model: DYTSI `WheelSetComponent::dynamic_aux`, i.e.
//! Hertz N ∝ δ^1.5 about the tabulated state; Johnson, *Contact
//! Mechanics*, 1985, §4.2). Its quasi-static state is the one in which the
//! wheel's contact point lies on the rail's contact point; the additional
//! approach is the distance of P_w beyond the rail's tangent plane at P_r:
//!
//! ```text
//! Δq = (P_r − P_w)·n_c = (z_r − (P_w − O)·b) cos δ      (P_r below P_w)
//! δ_act = q0 + Δq,   N = N0 (δ_act/q0)^1.5 = N0 (1 + Δq/q0)^1.5  for δ_act > 0, else 0
//! ```
//!
//! so that δ_act = q0 and N = N0 exactly when the wheel point sits on the
//! table's rail point, and N = K δ_act^1.5 with K = N0/q0^1.5. No contact
//! damping (as that model). The candidate's `penetration_m` is δ_act, so
//! `in_contact()` is δ_act ≥ 0.
//!
//! # Ellipse and creep forces
//!
//! The semi-axes scale with the load as in Hertz theory at a fixed shape,
//! a, b ∝ N^(1/3) (Johnson 1985, eq. 4.32; DYTSI `dynamic_aux` scales them
//! by (N/N0)^(1/3) too): a = a0 (N/N0)^(1/3), b = b0 (N/N0)^(1/3).
//! Creepages from the wheel's material-point velocity at P_w
//! ([`crate::forces::creepage`], V = the forward speed). Creep forces: Kalker's
//! linear forces with the **table's** C11, C22, C23 (docs/reference/07-contact-forces.md §7.3, eq. 23),
//! saturated by Shen–Hedrick–Elkins (`creep_law = heuristic`, that model's
//! law), or left linear (`kalker`), or none; spin moment neglected (the
//! table has no C33). G is the run's E/(2(1 + ν)) unless
//! [`ImportedContactMethod::shear_modulus_override_pa`] gives it (DYTSI's
//! Cooperrider model sets G = 1.4384e11 Pa directly).
//!
//! # What the rest of the system sees
//!
//! Each wheel's contact is a [`Candidate`] in piece 0, zone Tread (the
//! flange contact flags of the results are therefore never set with this
//! method), with NaN curvatures, `params.s_rail_m` the rail's arc length at
//! the wheelset's s (the recorder's travelled distance), and in the
//! profile-point fields: wheel (w, −r) and rail (lateral position of P_r
//! from the centreline, z_r). Its force is a [`ContactForce`] with
//! `normal.elastic_n = N` and a `tangential.hertz` whose semi-axes,
//! approach (δ_act) and stiffness (K = N0/q0^1.5) are the ones above, so
//! that the recorder and [`super::VehicleSystem::mechanical_energy_j`]
//! (0.4 K δ^2.5) work unchanged.
//!
//! # Energy
//!
//! The normal force is not the gradient of the elastic energy 0.4 K δ^2.5
//! ([`super::VehicleSystem::mechanical_energy_j`]): n_c is tilted by δ in
//! the cross-section while δ_act ignores the wheel point's sliding across
//! the rail (the rail point follows it), so the lateral component
//! −σ N sin δ does work on the lateral slip velocity of the wheel point
//! (in steady curving V times the angle of attack; the contact point of a
//! yawed wheelset is kept under the axle, not shifted along the rail), and
//! K, q0, z_r, r and w change with y. The energy ledger books that work as
//! the contact normal work (docs/reference/08-multibody.md §8.6;
//! [`ContactSource::normal_force_is_gradient`] is false).
//!
//! # Settling
//!
//! At assembly ([`settle_imported`]) each wheel is placed so that the
//! vertical component of its normal force, N cos δ, carries the static
//! wheel load W: δ_act = q0 (W/(N0 cos δ))^(2/3) per wheel gives the heights
//! of both wheel points, hence the wheelset's height and roll in closed form
//! (below). For the Cooperrider car W = 66.60 kN and N0(0) = 66.66 kN: the
//! table was made for that load.

use std::sync::{Arc, OnceLock};

use nalgebra::{Matrix3, Vector3};

use super::contact_source::{ContactContext, ContactSource};
use super::track_motion::{TrackRelative, frame_rotation};
use crate::contact::imported::{ImportedContactTable, ImportedRow, ImportedTableError};
use crate::contact::imported_lookup::{ImportedLookup, ImportedRows, TableInterpolation};
use crate::contact::quasi_static::Settled;
use crate::contact::{
    Candidate, ContactError, Curvatures, SolveMethod, SurfaceParams, WheelsetContacts, WheelsetPose,
};
use crate::forces::creep::{CreepForces, CreepInput, CreepLaw, KalkerCoefficients};
use crate::forces::hertz::{HertzContact, HertzError, HertzShape};
use crate::forces::normal::{ContactMemory, NormalForce};
use crate::geometry::profile::{MAX_SEGMENTS, Zone};
use crate::geometry::track::grid::within;
use crate::geometry::track::{Side, TrackError, TrackTables};
use crate::multibody::contact_force::{
    ContactForce, ContactForceError, ContactForceSettings, TangentialContact, WheelsetMotion,
    contact_creepages,
};

/// The imported-table contact method of a run (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedContactMethod {
    /// One table per wheelset, in vehicle order.
    pub tables: Vec<Arc<ImportedContactTable>>,
    /// Shear modulus G of the creep forces (Pa), instead of the run's
    /// E/(2(1 + ν)). DYTSI's Cooperrider model sets G = 1.4384e11 Pa
    /// (E = 2.1e11 Pa divided by 2(1 − 0.27)); E/(2(1 + ν)) would give
    /// 8.27e10 Pa.
    pub shear_modulus_override_pa: Option<f64>,
    /// How the tables' columns are read between rows (ours: linear;
    /// DYTSI's: a natural cubic spline, [`TableInterpolation`]).
    pub interpolation: TableInterpolation,
    /// Whether the contact normal turns with the wheelset's roll (ours: it
    /// does not; DYTSI's: it does, [`ContactNormal`]).
    pub normal: ContactNormal,
}

/// The contact normal of an imported table's contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ContactNormal {
    /// The rail's normal at the contact, fixed in the track frame: the
    /// track-plane normal tilted by the table's contact angle δ (ours,
    /// module docs "Geometry").
    #[default]
    Track,
    /// That normal turned about the track's tangent by the wheelset's roll
    /// φ: tilted by δ + φ on the left wheel and δ − φ on the right (DYTSI's
    /// `WheelSetComponent`, which tilts the contact frame and the
    /// penetration's direction by the roll).
    Rolled,
}

impl ContactNormal {
    pub fn name(self) -> &'static str {
        match self {
            ContactNormal::Track => "track",
            ContactNormal::Rolled => "rolled",
        }
    }
}

impl ImportedContactMethod {
    /// The shear modulus of the creep forces (Pa).
    pub fn shear_modulus_pa(&self, settings: &ContactForceSettings) -> f64 {
        self.shear_modulus_override_pa
            .unwrap_or_else(|| settings.material.shear_modulus_pa())
    }

    /// Checks the method against the run: one valid table per wheelset, a
    /// supported creep law (heuristic, kalker, none), G finite and > 0.
    pub fn validate(
        &self,
        settings: &ContactForceSettings,
        n_wheelsets: usize,
    ) -> Result<(), String> {
        if self.tables.len() != n_wheelsets {
            return Err(format!(
                "{} imported contact tables for {n_wheelsets} wheelsets",
                self.tables.len()
            ));
        }
        for t in &self.tables {
            t.validate().map_err(|e| e.to_string())?;
        }
        match settings.creep_law {
            CreepLaw::Heuristic | CreepLaw::KalkerLinear | CreepLaw::None => {}
            other => {
                return Err(format!(
                    "creep law '{}' is not available with an imported contact table (its Kalker coefficients C11, C22, C23 come with the table): use heuristic (that model's law), kalker or none",
                    other.name()
                ));
            }
        }
        let g = self.shear_modulus_pa(settings);
        if !(g.is_finite() && g > 0.0) {
            return Err(format!("shear modulus {g} Pa must be finite and > 0"));
        }
        Ok(())
    }
}

/// The [`ContactSource`] of a wheelset with an imported table (module
/// docs): seated by [`settle_imported`], one contact per wheel from the
/// rows at its lateral displacement ([`imported_contacts`]), forces by
/// [`imported_force`] from those rows (kept from the last
/// [`ContactSource::contacts`]). Neither profiles nor the contact solver
/// are used, nor the hysteresis memory (that model has no damping).
#[derive(Debug, Clone)]
pub struct ImportedContact {
    table: ImportedLookup,
    /// Shear modulus G of the creep forces (Pa),
    /// [`ImportedContactMethod::shear_modulus_pa`].
    shear_modulus_pa: f64,
    /// The rows `[left, right]` of the last contacts.
    rows: Option<[ImportedRow; 2]>,
    /// The contact normal's rule.
    normal: ContactNormal,
}

impl ImportedContact {
    /// The source reading `table` linearly.
    pub fn new(table: Arc<ImportedContactTable>, shear_modulus_pa: f64) -> Self {
        Self::with_lookup(ImportedLookup::Linear(table), shear_modulus_pa)
    }

    /// The source reading its table through `lookup`.
    pub fn with_lookup(lookup: ImportedLookup, shear_modulus_pa: f64) -> Self {
        ImportedContact {
            table: lookup,
            shear_modulus_pa,
            rows: None,
            normal: ContactNormal::Track,
        }
    }

    /// The same source with the contact normal's rule `normal`.
    pub fn with_normal(self, normal: ContactNormal) -> Self {
        ImportedContact { normal, ..self }
    }
}

impl ContactSource for ImportedContact {
    fn settle(
        &mut self,
        ctx: ContactContext<'_>,
        _forces: &ContactForceSettings,
        s_m: f64,
        y_m: f64,
        yaw_rad: f64,
    ) -> Result<Settled, ContactError> {
        let load = ctx.wheelset.static_wheel_load_n;
        settle_imported(ctx.track, &self.table, s_m, y_m, yaw_rad, load)
    }

    fn contacts(
        &mut self,
        ctx: ContactContext<'_>,
        pose: &WheelsetPose,
        relative: &TrackRelative,
    ) -> Result<WheelsetContacts, ContactError> {
        let mut out = WheelsetContacts::default();
        self.contacts_into(ctx, pose, relative, &mut out)?;
        Ok(out)
    }

    /// [`Self::contacts`] written into `out` (piece 0 of each wheel set,
    /// every other piece cleared; the way `contacts` makes its value too):
    /// the trait default's returned value and copy of the whole snapshot
    /// showed in the car's profile.
    fn contacts_into(
        &mut self,
        ctx: ContactContext<'_>,
        pose: &WheelsetPose,
        relative: &TrackRelative,
        out: &mut WheelsetContacts,
    ) -> Result<(), ContactError> {
        let rows = wheel_rows(&self.table, relative.lateral_m)?;
        candidates_into(ctx.track, pose, &rows, self.normal, out)?;
        self.rows = Some(rows);
        Ok(())
    }

    fn force(
        &self,
        forces: &ContactForceSettings,
        c: &Candidate,
        _memory: &ContactMemory,
        motion: &WheelsetMotion,
    ) -> Result<Option<ContactForce>, ContactForceError> {
        let Some(rows) = &self.rows else {
            return Err(ContactForceError::InvalidSetting {
                setting: "imported contact",
                value: f64::NAN,
                rule: "a force needs the rows of a contact search first",
            });
        };
        imported_force(
            forces,
            self.shear_modulus_pa,
            &rows[side_index(c.side)],
            c,
            motion,
        )
    }

    /// The normal force along the tabulated normal with the penetration
    /// measured under the wheel point is not the gradient of 0.4 K δ^2.5
    /// (module docs, "Energy").
    fn normal_force_is_gradient(&self) -> bool {
        false
    }
}

fn sigma(side: Side) -> f64 {
    match side {
        Side::Left => 1.0,
        Side::Right => -1.0,
    }
}

fn side_index(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

/// Name of the table in out-of-range errors.
const TABLE_NAME: &str = "imported contact";
/// The coordinate in out-of-range errors.
const COORDINATE: &str =
    "wheelset lateral displacement (derailed: no contact beyond the table in that model)";

fn table_error<T: ImportedRows + ?Sized>(
    e: ImportedTableError,
    y_m: f64,
    table: &T,
) -> ContactError {
    match e {
        ImportedTableError::OutOfRange { .. } => {
            let (min_m, max_m) = table.wheelset_range_m();
            ContactError::Track(TrackError::OutOfRange {
                table: TABLE_NAME,
                coordinate: COORDINATE,
                value_m: y_m,
                min_m,
                max_m,
            })
        }
        other => ContactError::Setup(other.to_string()),
    }
}

/// The rows of both wheels `[left, right]` at lateral displacement `y_m`
/// (the right wheel's at −y); out of the wheelset's range: a track-range
/// error naming it (derailment in that model).
pub fn wheel_rows<T: ImportedRows + ?Sized>(
    table: &T,
    y_m: f64,
) -> Result<[ImportedRow; 2], ContactError> {
    let (lo, hi) = table.wheelset_range_m();
    if !within(y_m, lo, hi, 0.0) {
        return Err(table_error(
            ImportedTableError::OutOfRange {
                y_mm: y_m * 1e3,
                min_mm: lo * 1e3,
                max_mm: hi * 1e3,
            },
            y_m,
            table,
        ));
    }
    let row = |side| {
        table
            .wheel_row(side, y_m)
            .map_err(|e| table_error(e, y_m, table))
    };
    Ok([row(Side::Left)?, row(Side::Right)?])
}

/// The track at a wheelset's section s: what both wheels' contacts read
/// from the centreline, looked up once per wheelset.
struct Section {
    /// Centreline point O (m).
    origin: Vector3<f64>,
    /// Track frame columns t, n, b ([`super::track_motion::track_rotation`]).
    frame: Matrix3<f64>,
    /// Arc length of each rail at s (m), [left, right].
    rail_l_m: [f64; 2],
}

impl Section {
    fn at(track: &TrackTables, s_m: f64) -> Result<Self, TrackError> {
        let c = &track.centerline;
        let centre = c.at(s_m)?;
        let (_, rail_l_m) = c.frame_and_rail_l(s_m)?;
        Ok(Section {
            origin: centre.position,
            frame: frame_rotation(&centre.frame),
            rail_l_m,
        })
    }
}

/// The contact of one wheel with its row (module docs, "Geometry"), the
/// track read at the wheelset's `section`.
fn wheel_candidate(
    section: &Section,
    pose: &WheelsetPose,
    side: Side,
    row: &ImportedRow,
    normal_rule: ContactNormal,
) -> Candidate {
    let (origin, frame) = (section.origin, &section.frame);
    let (t, n, b) = (
        frame.column(0).into_owned(),
        frame.column(1).into_owned(),
        frame.column(2).into_owned(),
    );
    let sg = sigma(side);
    let eta = pose.frame.column(1).into_owned();
    let zeta = pose.frame.column(2).into_owned();
    let wheel_point =
        pose.position + eta * (sg * row.wheel_lateral_m) - zeta * row.rolling_radius_m;
    let d = wheel_point - origin;
    let rail_point = origin + t * d.dot(&t) + n * d.dot(&n) + b * row.rail_vertical_m;
    // The wheelset's roll φ about the tangent (+ lifts the left wheel):
    // sin φ = η·b.
    let tilt = match normal_rule {
        ContactNormal::Track => row.contact_angle_rad,
        ContactNormal::Rolled => row.contact_angle_rad + sg * eta.dot(&b).clamp(-1.0, 1.0).asin(),
    };
    let (sin_d, cos_d) = tilt.sin_cos();
    let normal = b * cos_d - n * (sg * sin_d);
    let tangent = (t - normal * t.dot(&normal)).normalize();
    let lateral = normal.cross(&tangent);
    let penetration_m = row.penetration_m + (rail_point - wheel_point).dot(&normal);
    Candidate {
        side,
        zone: Zone::Tread,
        segment: 0,
        params: SurfaceParams {
            s_rail_m: section.rail_l_m[side_index(side)],
            u_rail_m: d.dot(&n),
            s_wheel_rad: 0.0,
            u_wheel_m: sg * row.wheel_lateral_m,
        },
        iterations: 0,
        cold_start: false,
        method: SolveMethod::Newton,
        penetration_m,
        wheel_point,
        rail_point,
        normal,
        tangent,
        lateral,
        contact_angle_rad: row.contact_angle_rad,
        rolling_radius_m: row.rolling_radius_m,
        curvatures: Curvatures {
            wheel_rolling_1_m: f64::NAN,
            wheel_lateral_1_m: f64::NAN,
            rail_rolling_1_m: f64::NAN,
            rail_lateral_1_m: f64::NAN,
        },
        wheel_profile_point_m: (row.wheel_lateral_m, -row.rolling_radius_m),
        rail_profile_point_m: (d.dot(&n), row.rail_vertical_m),
    }
}

/// Both wheels' contacts (piece 0 of each wheel) of a wheelset at `pose`
/// whose lateral displacement from the centreline is `lateral_m`, and the
/// rows they used `[left, right]`.
pub fn imported_contacts<T: ImportedRows + ?Sized>(
    track: &TrackTables,
    pose: &WheelsetPose,
    lateral_m: f64,
    table: &T,
) -> Result<(WheelsetContacts, [ImportedRow; 2]), ContactError> {
    imported_contacts_with(track, pose, lateral_m, table, ContactNormal::Track)
}

/// [`imported_contacts`] with the contact normal's rule `normal`.
pub fn imported_contacts_with<T: ImportedRows + ?Sized>(
    track: &TrackTables,
    pose: &WheelsetPose,
    lateral_m: f64,
    table: &T,
    normal: ContactNormal,
) -> Result<(WheelsetContacts, [ImportedRow; 2]), ContactError> {
    let rows = wheel_rows(table, lateral_m)?;
    let mut out = WheelsetContacts::default();
    candidates_into(track, pose, &rows, normal, &mut out)?;
    Ok((out, rows))
}

/// Both wheels' contacts from their `rows` `[left, right]` written into
/// `out`: piece 0 of each wheel, every other piece cleared.
fn candidates_into(
    track: &TrackTables,
    pose: &WheelsetPose,
    rows: &[ImportedRow; 2],
    normal: ContactNormal,
    out: &mut WheelsetContacts,
) -> Result<(), ContactError> {
    let section = Section::at(track, pose.s_track_m)?;
    for side in Side::BOTH {
        let k = side_index(side);
        let pieces = &mut out.candidates[k];
        pieces[0] = Some(wheel_candidate(&section, pose, side, &rows[k], normal));
        pieces[1..].fill(None);
    }
    Ok(())
}

/// Normal force N (N) of a wheel at actual penetration `delta_m` (m):
/// N0 (δ_act/q0)^1.5, 0 when δ_act ≤ 0 (module docs).
pub fn normal_force_n(row: &ImportedRow, delta_m: f64) -> f64 {
    normal_force_and_scale(row, delta_m).0
}

/// N (N, as [`normal_force_n`]) and the semi-axes' load scale
/// (N/N0)^(1/3) = (δ_act/q0)^(1/2) (module docs, "Ellipse"), both from
/// r = δ_act/q0 and √r: N = N0 r √r. One square root instead of a `powf`
/// and a `cbrt` (two of the costliest calls of a car's right-hand side,
/// eight wheels at every evaluation). (0, 0) when δ_act ≤ 0.
fn normal_force_and_scale(row: &ImportedRow, delta_m: f64) -> (f64, f64) {
    if delta_m > 0.0 {
        let ratio = delta_m / row.penetration_m;
        let root = ratio.sqrt();
        (row.normal_force_n * ratio * root, root)
    } else {
        (0.0, 0.0)
    }
}

/// A unit sphere's Hertz shape, the placeholder shape of the Hertz record
/// [`imported_force`] makes (its other fields are the imported contact's).
fn placeholder_shape() -> Result<HertzShape, HertzError> {
    static SHAPE: OnceLock<Result<HertzShape, HertzError>> = OnceLock::new();
    *SHAPE.get_or_init(|| HertzShape::new(1.0, 1.0))
}

/// The force of one wheel's contact `c` with its `row` (module docs):
/// `Ok(None)` when δ_act ≤ 0. `shear_modulus_pa` is G of the creep forces.
pub fn imported_force(
    settings: &ContactForceSettings,
    shear_modulus_pa: f64,
    row: &ImportedRow,
    c: &Candidate,
    motion: &WheelsetMotion,
) -> Result<Option<ContactForce>, ContactForceError> {
    let (n, scale) = normal_force_and_scale(row, c.penetration_m);
    if n <= 0.0 {
        return Ok(None);
    }
    let hertz_err = |source| ContactForceError::Hertz {
        side: c.side,
        zone: c.zone,
        source,
    };
    let creep_err = |source| ContactForceError::Creep {
        side: c.side,
        zone: c.zone,
        source,
    };
    let creepages = contact_creepages(settings, c, motion)?;
    // a, b ∝ N^(1/3) at the table's shape (Hertz): `scale` = (N/N0)^(1/3).
    let (a_m, b_m) = (row.a_m * scale, row.b_m * scale);
    let input = CreepInput {
        xi: creepages.xi,
        eta: creepages.eta,
        phi_1_m: creepages.phi_1_m,
        normal_force_n: n,
        a_m,
        b_m,
        friction_coefficient: settings.friction_coefficient,
        rolling_speed_m_s: creepages.effective_speed_m_s,
        shear_modulus_pa,
        poisson: settings.material.poisson,
    };
    let coefficients = KalkerCoefficients {
        c11: row.c11,
        c22: row.c22,
        c23: row.c23,
        c33: 0.0,
    };
    let creep = match settings.creep_law {
        CreepLaw::None => CreepForces::ZERO,
        CreepLaw::Heuristic => {
            crate::forces::creep::heuristic_with_coefficients(&input, &coefficients, true)
                .map_err(creep_err)?
        }
        CreepLaw::KalkerLinear => {
            crate::forces::creep::heuristic_with_coefficients(&input, &coefficients, false)
                .map_err(creep_err)?
        }
        _ => {
            return Err(ContactForceError::InvalidSetting {
                setting: "creep law",
                value: f64::NAN,
                rule: "an imported contact table supports heuristic, kalker or none",
            });
        }
    };
    // The Hertz record: a placeholder shape with the imported contact's own
    // N, semi-axes, approach and stiffness K = N0/q0^1.5 (module docs),
    // after the checks `HertzContact::from_shape` makes of its inputs.
    settings.material.validate().map_err(hertz_err)?;
    if !n.is_finite() {
        return Err(hertz_err(HertzError::InvalidNormalForce {
            normal_force_n: n,
        }));
    }
    let q0 = row.penetration_m;
    let hertz = HertzContact {
        shape: placeholder_shape().map_err(hertz_err)?,
        normal_force_n: n,
        a_rolling_m: a_m,
        b_lateral_m: b_m,
        approach_m: c.penetration_m,
        stiffness_n_m15: row.normal_force_n / (q0 * q0.sqrt()),
    };
    Ok(Some(ContactForce {
        normal: NormalForce {
            force_n: n,
            elastic_n: n,
            damping_n: 0.0,
            clamped: false,
            velocity_ratio: 0.0,
            next_memory: ContactMemory::not_in_contact(),
        },
        tangential: TangentialContact {
            hertz,
            creepages,
            creep,
        },
        force_on_wheel_n: c.normal * n + c.tangent * creep.fx_n + c.lateral * creep.fy_n,
        moment_on_wheel_nm: Vector3::zeros(),
        point_m: c.wheel_point,
        hertz_fallback: false,
    }))
}

/// The wheelset at lateral displacement `y_m` and yaw `yaw_rad`, at track
/// distance `s_m`, resting on the rails with each wheel's normal force
/// carrying `load_per_wheel_n` vertically (module docs, "Settling"). Closed
/// form: with Z_i the height of wheel point i above the track plane that
/// gives δ_act,i = q0,i (W/(N0,i cos δ_i))^(2/3), i.e.
/// Z_i = z_r,i + (q0,i − δ_act,i)/cos δ_i, and the wheel points at
/// h + w_L sin φ − r_L cos φ (left) and h − w_R sin φ − r_R cos φ (right)
/// for centre height h and roll φ (exact for any yaw):
///
/// ```text
/// (w_L + w_R) sin φ − (r_L − r_R) cos φ = Z_L − Z_R
///   ⇒ φ = atan2(r_L − r_R, w_L + w_R) + asin((Z_L − Z_R)/√((w_L + w_R)² + (r_L − r_R)²))
/// h = Z_L − w_L sin φ + r_L cos φ
/// ```
pub fn settle_imported<T: ImportedRows + ?Sized>(
    track: &TrackTables,
    table: &T,
    s_m: f64,
    y_m: f64,
    yaw_rad: f64,
    load_per_wheel_n: f64,
) -> Result<Settled, ContactError> {
    if !(load_per_wheel_n.is_finite() && load_per_wheel_n > 0.0) {
        return Err(ContactError::Setup(format!(
            "static wheel load {load_per_wheel_n} N must be finite and > 0"
        )));
    }
    let rows = wheel_rows(table, y_m)?;
    let z = |r: &ImportedRow| {
        let cos = r.contact_angle_rad.cos();
        let delta = r.penetration_m * (load_per_wheel_n / (r.normal_force_n * cos)).powf(2.0 / 3.0);
        r.rail_vertical_m + (r.penetration_m - delta) / cos
    };
    let [left, right] = &rows;
    let (zl, zr) = (z(left), z(right));
    let a = left.wheel_lateral_m + right.wheel_lateral_m;
    let b = left.rolling_radius_m - right.rolling_radius_m;
    let ratio = (zl - zr) / a.hypot(b);
    if ratio.abs() >= 1.0 {
        return Err(ContactError::Setup(format!(
            "the imported contact table cannot seat the wheelset at y = {:.3} mm (wheel heights {zl} m, {zr} m)",
            y_m * 1e3
        )));
    }
    let roll = b.atan2(a) + ratio.asin();
    let height = zl - left.wheel_lateral_m * roll.sin() + left.rolling_radius_m * roll.cos();
    let pose = WheelsetPose::on_track(track, s_m, y_m, height, yaw_rad, roll)?;
    let (contacts, _) = imported_contacts(track, &pose, y_m, table)?;
    let mut normal_force_n = [[0.0; MAX_SEGMENTS]; 2];
    for (k, row) in rows.iter().enumerate() {
        if let Some(c) = &contacts.candidates[k][0] {
            normal_force_n[k][0] = self::normal_force_n(row, c.penetration_m);
        }
    }
    Ok(Settled {
        pose,
        height_m: height,
        roll_rad: roll,
        contacts,
        normal_force_n,
        iterations: 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::imported::ImportedRow;
    use crate::forces::hertz::Material;
    use crate::geometry::track::straight_track;

    /// A table shaped like DYTSI's near the centre: δ, r and the rail
    /// height change with y, the left flange side at + y.
    fn table() -> ImportedContactTable {
        let y_m: Vec<f64> = (0..=200).map(|i| -0.01 + 1e-4 * i as f64).collect();
        let rows = y_m
            .iter()
            .map(|&y| ImportedRow {
                normal_force_n: 66_661.0 - 2e5 * y,
                contact_angle_rad: 0.0142 + 5.0 * y + 300.0 * y * y,
                a_m: 5.95e-3,
                b_m: 6.65e-3,
                wheel_lateral_m: 0.7563 - 0.9 * y,
                rolling_radius_m: 0.424883 + 0.12 * y + 3.0 * y * y,
                c11: 4.12,
                c22: 3.56,
                c23: 1.37,
                rail_vertical_m: -5.9e-5 - 0.03 * y * y,
                penetration_m: 7.01e-5 + 1e-3 * y,
            })
            .collect();
        ImportedContactTable {
            source: "test".into(),
            format: "test".into(),
            y_m,
            rows,
        }
    }

    #[test]
    fn settled_wheels_carry_the_load_and_the_contact_is_symmetric_at_zero() {
        let track = straight_track(100.0, 0.1, 1.435, 1.507, 0.0);
        let t = table();
        let w = 66_602.3;
        for (y, yaw) in [(0.0, 0.0), (0.004, 0.002), (-0.007, -0.001)] {
            let s = settle_imported(&track, &t, 50.0, y, yaw, w).unwrap();
            for k in 0..2 {
                let c = s.contacts.candidates[k][0].unwrap();
                let n = s.normal_force_n[k][0];
                let vertical = n * c.normal.z;
                assert!((vertical - w).abs() < 1e-6 * w, "y {y}: {vertical}");
                // The contact point on the rail lies under the wheel point.
                assert!((c.wheel_point.x - c.rail_point.x).abs() < 1e-12);
                assert!((c.wheel_point.y - c.rail_point.y).abs() < 1e-12);
            }
            if y == 0.0 {
                let [l, r] = [
                    s.contacts.candidates[0][0].unwrap(),
                    s.contacts.candidates[1][0].unwrap(),
                ];
                assert!(s.roll_rad.abs() < 1e-15);
                assert!((l.penetration_m - r.penetration_m).abs() < 1e-18);
                // Mirror images: lateral components opposite, the rest equal.
                assert!((l.normal.y + r.normal.y).abs() < 1e-15);
                assert!((l.normal.z - r.normal.z).abs() < 1e-15);
                assert!(
                    (l.wheel_point.y + r.wheel_point.y
                        - 2.0 * track.centerline.at(50.0).unwrap().position.y)
                        .abs()
                        < 1e-12
                );
                // Normal tilted towards the track centre on both sides.
                assert!(l.normal.y < 0.0 && r.normal.y > 0.0);
            }
        }
    }

    #[test]
    fn mirrored_poses_give_mirrored_contacts() {
        let track = straight_track(100.0, 0.1, 1.435, 1.507, 0.0);
        let t = table();
        let (y, yaw, roll, h) = (0.0035, 0.003, 0.0008, 0.4249);
        let p = WheelsetPose::on_track(&track, 50.0, y, h, yaw, roll).unwrap();
        let m = WheelsetPose::on_track(&track, 50.0, -y, h, -yaw, -roll).unwrap();
        let (a, _) = imported_contacts(&track, &p, y, &t).unwrap();
        let (b, _) = imported_contacts(&track, &m, -y, &t).unwrap();
        let centre_y = track.centerline.at(50.0).unwrap().position.y;
        for k in 0..2 {
            let ca = a.candidates[k][0].unwrap();
            let cb = b.candidates[1 - k][0].unwrap();
            assert!((ca.penetration_m - cb.penetration_m).abs() < 1e-15);
            assert!((ca.contact_angle_rad - cb.contact_angle_rad).abs() < 1e-15);
            assert!((ca.normal.y + cb.normal.y).abs() < 1e-15);
            assert!(((ca.wheel_point.y - centre_y) + (cb.wheel_point.y - centre_y)).abs() < 1e-12);
            assert!((ca.wheel_point.x - cb.wheel_point.x).abs() < 1e-12);
        }
        // Lifting the wheelset by 10 µm reduces each penetration by 10 µm·cos δ.
        let lifted = WheelsetPose::on_track(&track, 50.0, y, h + 1e-5, yaw, roll).unwrap();
        let (c, _) = imported_contacts(&track, &lifted, y, &t).unwrap();
        for k in 0..2 {
            let d0 = a.candidates[k][0].unwrap();
            let d1 = c.candidates[k][0].unwrap();
            let expected = 1e-5 * d0.contact_angle_rad.cos();
            assert!(((d0.penetration_m - d1.penetration_m) - expected).abs() < 1e-15);
        }
        // Out of the table: an error naming the range.
        let e = imported_contacts(&track, &p, 0.0105, &t)
            .unwrap_err()
            .to_string();
        assert!(e.contains("derailed") && e.contains("0.01"), "{e}");
    }

    #[test]
    #[cfg(feature = "fixtures")] // the shared S1002/UIC60 wheelset
    fn the_source_gives_the_functions_settling_contacts_and_forces() {
        use crate::contact::{ContactOptions, ContactSolver};
        use crate::fixtures::wheelsets;
        use crate::multibody::body::RigidBody;
        use crate::multibody::track_motion::TrackRelative;
        use crate::multibody::{ContactContext, ContactSource, WheelsetSpec};
        let track = straight_track(100.0, 0.1, 1.435, 1.507, 0.0);
        let t = table();
        let g = 1.4384e11;
        let settings = ContactForceSettings {
            creep_law: CreepLaw::Heuristic,
            ..Default::default()
        };
        let load = 66_602.3;
        let w = WheelsetSpec {
            name: "ws".into(),
            body: RigidBody {
                mass_kg: 1000.0,
                inertia_kg_m2: nalgebra::Matrix3::identity(),
            },
            // The wheelset's profiles and solver are not used, but a
            // wheelset has them.
            contact: wheelsets::s1002_uic60().unwrap(),
            x_m: 0.0,
            y_m: 0.0,
            nominal_radius_m: 0.425,
            static_wheel_load_n: load,
        };
        let mut solver = ContactSolver::new(ContactOptions::default());
        let mut source = ImportedContact::new(Arc::new(t.clone()), g);
        let y = 0.003;
        let expected = settle_imported(&track, &t, 50.0, y, 0.001, load).unwrap();
        macro_rules! ctx {
            () => {
                ContactContext {
                    track: &track,
                    wheelset: &w,
                    solver: &mut solver,
                }
            };
        }
        // The same values, bit for bit (their curvatures are NaN, hence
        // the comparison of the printed values).
        let same = |a: &dyn std::fmt::Debug, b: &dyn std::fmt::Debug| {
            assert_eq!(format!("{a:?}"), format!("{b:?}"))
        };
        let settled = source.settle(ctx!(), &settings, 50.0, y, 0.001).unwrap();
        same(&settled, &expected);
        let relative = TrackRelative {
            lateral_m: y,
            ..Default::default()
        };
        let c = settled.contacts.candidates[1][0].unwrap();
        let motion = WheelsetMotion {
            centre_m: settled.pose.position,
            velocity_m_s: Vector3::new(30.0, 0.1, 0.0),
            angular_velocity_rad_s: settled.pose.frame.column(1) * (30.0 / 0.425),
            forward_speed_m_s: 30.0,
        };
        let memory = ContactMemory::not_in_contact();
        // No rows before a contact search: an error, not a guess.
        assert!(source.force(&settings, &c, &memory, &motion).is_err());
        let contacts = source.contacts(ctx!(), &settled.pose, &relative).unwrap();
        let (direct, rows) = imported_contacts(&track, &settled.pose, y, &t).unwrap();
        same(&contacts, &direct);
        // Written in place over a snapshot that still holds other pieces
        // (an online solve's): the same contacts, the stale pieces cleared.
        let mut snapshot = WheelsetContacts::default();
        for side in &mut snapshot.candidates {
            side.fill(Some(direct.candidates[0][0].unwrap()));
        }
        source
            .contacts_into(ctx!(), &settled.pose, &relative, &mut snapshot)
            .unwrap();
        same(&snapshot, &direct);
        for (k, row) in rows.iter().enumerate() {
            let c = contacts.candidates[k][0].unwrap();
            let f = source.force(&settings, &c, &memory, &motion).unwrap();
            assert!(f.is_some());
            same(&f, &imported_force(&settings, g, row, &c, &motion).unwrap());
        }
        assert_eq!(solver.stats.solves, 0);
    }

    #[test]
    fn force_at_the_tabulated_state_is_n0_and_creep_saturates() {
        let track = straight_track(100.0, 0.1, 1.435, 1.507, 0.0);
        let t = table();
        let row = t.row_at(0.0).unwrap();
        assert_eq!(normal_force_n(&row, row.penetration_m), row.normal_force_n);
        assert!(
            (normal_force_n(&row, 2.0 * row.penetration_m) / row.normal_force_n - 2f64.powf(1.5))
                .abs()
                < 1e-14
        );
        assert_eq!(normal_force_n(&row, -1e-9), 0.0);
        let s = settle_imported(&track, &t, 50.0, 0.0, 0.0, 66_000.0).unwrap();
        let c = s.contacts.candidates[0][0].unwrap();
        let mut settings = ContactForceSettings {
            material: Material::default(),
            friction_coefficient: 0.15,
            creep_law: CreepLaw::Heuristic,
            ..Default::default()
        };
        let g = 1.4384e11;
        // A wheelset sliding sideways at 1 m/s while rolling at 30 m/s.
        let axle = s.pose.frame.column(1).into_owned();
        let motion = WheelsetMotion {
            centre_m: s.pose.position,
            velocity_m_s: Vector3::new(30.0, 1.0, 0.0),
            angular_velocity_rad_s: axle * (30.0 / row.rolling_radius_m),
            forward_speed_m_s: 30.0,
        };
        let f = imported_force(&settings, g, &row, &c, &motion)
            .unwrap()
            .unwrap();
        let n = f.normal.force_n;
        assert!((f.tangential.creep.tangential_n() - 0.15 * n).abs() < 1e-6 * n);
        assert!(
            f.tangential.creep.fy_n < 0.0,
            "opposes the slip to the left"
        );
        let scale = (n / row.normal_force_n).cbrt();
        assert!((f.tangential.hertz.a_rolling_m - row.a_m * scale).abs() < 1e-15);
        // Small creepage: Kalker linear with the table's C22 and G.
        settings.creep_law = CreepLaw::KalkerLinear;
        let slow = WheelsetMotion {
            velocity_m_s: Vector3::new(30.0, 1e-4, 0.0),
            ..motion
        };
        let f = imported_force(&settings, g, &row, &c, &slow)
            .unwrap()
            .unwrap();
        let ab = f.tangential.hertz.a_rolling_m * f.tangential.hertz.b_lateral_m;
        let eta = f.tangential.creepages.eta;
        let phi = f.tangential.creepages.phi_1_m;
        let expected = -g * ab * row.c22 * eta - g * ab * ab.sqrt() * row.c23 * phi;
        assert!((f.tangential.creep.fy_n - expected).abs() < 1e-9 * expected.abs());
        settings.creep_law = CreepLaw::default();
        assert!(imported_force(&settings, g, &row, &c, &slow).is_err());
    }
}
