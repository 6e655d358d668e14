//! The runtime's [`SystemSettings`] from a scene: force models, contact
//! method (building or reading the contact tables when `method = "table"`),
//! speed and start.

use crate::config::scene::ContactMethodKind;
use crate::session::contact::{contact_tables, imported_table};
use std::sync::Arc;

use anyhow::{Context, Result};
use runtime::contact::{ContactOptions, FlangeSearch};
use runtime::forces::creepage::CreepageOptions;
use runtime::forces::hertz::Material;
use runtime::forces::normal::NormalForceModel;
use runtime::geometry::track::TrackTables;
use runtime::multibody::contact_force::ContactForceSettings;
use runtime::multibody::imported_contact::ImportedContactMethod;
use runtime::multibody::{ContactMethod, SystemSettings};

use crate::config::scene::LoadedScene;
use crate::config::vehicle::VehicleFile;

/// The system settings of a scene (force models, contact method — building
/// or reading the contact tables when `method = "table"` — speed, start).
pub fn system_settings(
    ls: &LoadedScene,
    vfile: &VehicleFile,
    track: &TrackTables,
) -> Result<SystemSettings> {
    let scene = &ls.scene;
    let rail_path = ls.path(&scene.track.rail_profile);
    let material = Material {
        young_pa: scene.contact.young_pa,
        poisson: scene.contact.poisson,
    };
    let creep_law = scene.creep_law()?;
    let formulation = scene.formulation.resolve();
    let method = match scene.contact.method {
        ContactMethodKind::Table => {
            let declared = scene.track.declared_rail_cant()?.map(|c| c.angle_rad);
            ContactMethod::Table(contact_tables(
                vfile,
                track,
                &rail_path,
                declared,
                material,
                scene.track.keep_longest_stretch,
            )?)
        }
        ContactMethodKind::Imported => {
            let path = ls.path(
                scene
                    .contact
                    .imported_table
                    .as_ref()
                    .context("[contact] imported_table")?,
            );
            let table = Arc::new(imported_table(&path)?);
            ContactMethod::Imported(ImportedContactMethod {
                tables: vec![table; vfile.wheelsets.len()],
                shear_modulus_override_pa: scene.contact.shear_modulus_pa,
                interpolation: formulation.table_interpolation,
                normal: formulation.contact_normal,
            })
        }
        ContactMethodKind::Online => ContactMethod::Online,
    };
    let flange: FlangeSearch = scene.contact.flange.into();
    let settings = SystemSettings {
        forces: ContactForceSettings {
            material,
            friction_coefficient: scene.contact.friction,
            creep_law,
            normal: NormalForceModel {
                restitution: scene.contact.restitution,
                ..NormalForceModel::default()
            },
            creepage: CreepageOptions {
                min_rolling_speed_m_s: scene.contact.min_rolling_speed_m_s,
            },
            non_hertzian: scene.contact.non_hertzian.into(),
        },
        contact: ContactOptions {
            flange,
            ..ContactOptions::default()
        },
        method,
        formulation: formulation.equations,
        ..scene.motion_settings()
    };
    Ok(settings)
}
