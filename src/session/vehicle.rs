//! The vehicle file as a runtime [`VehicleModel`]: profiles loaded, bodies,
//! references and suspension elements resolved by name.

use std::path::Path;

use anyhow::{Context, Result, anyhow, ensure};
use nalgebra::{Matrix3, Vector3};
use runtime::contact::WheelsetContactModel;
use runtime::geometry::profile::{
    ProfileWarning, RailPlacement, RailProfileOptions, WheelProfile, WheelProfileOptions,
};
use runtime::geometry::track::TrackTables;
use runtime::io::profile_import::{ImportOptions, load_rail, load_wheel};
use runtime::multibody::body::RigidBody;
use runtime::multibody::{BodySpec, ElementSpec, End, ReferenceSpec, VehicleModel, WheelsetSpec};

use crate::config::suspension::axis_laws;
use crate::config::vehicle::{GROUND, VehicleFile};

fn diag(i: [f64; 3]) -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::from(i))
}

/// The vehicle file as a [`VehicleModel`] on `track` (its rail placement)
/// with the scene's rail profile; with it the warnings of the profiles (one
/// per file cut to its longest usable stretch, with
/// `keep_longest_stretch`), which the caller must show.
pub fn vehicle_model(
    v: &VehicleFile,
    track: &TrackTables,
    rail: &Path,
    keep_longest_stretch: bool,
) -> Result<(VehicleModel, Vec<ProfileWarning>)> {
    let loaded = load_rail(
        rail,
        &ImportOptions::default(),
        RailProfileOptions {
            keep_longest_stretch,
            ..Default::default()
        },
    )
    .with_context(|| format!("rail profile {}", rail.display()))?;
    let rail_profile = loaded.profile;
    let mut warnings = loaded.warnings;
    let placement = RailPlacement {
        gauge_m: track.meta.gauge_m,
        rail_spacing_m: track.meta.rail_spacing_m,
        inclination_rad: track.meta.rail_inclination_rad,
    };
    let mut wheelsets = Vec::new();
    // Profiles loaded so far, by file and nominal radius: a car's wheelsets
    // usually share one file, loaded (read, fitted) once.
    let mut loaded_wheels: Vec<((std::path::PathBuf, u64), WheelProfile)> = Vec::new();
    for w in &v.wheelsets {
        let path = v.profile_path(w);
        let key = (path.clone(), w.nominal_radius_m.to_bits());
        let wheel = match loaded_wheels.iter().find(|(k, _)| *k == key) {
            Some((_, wheel)) => wheel.clone(),
            None => {
                let loaded = load_wheel(
                    &path,
                    &ImportOptions::default(),
                    WheelProfileOptions {
                        nominal_radius_m: w.nominal_radius_m,
                        keep_longest_stretch,
                        ..Default::default()
                    },
                )
                .with_context(|| format!("wheel profile {}", path.display()))?;
                // Wheelsets sharing a profile file warn once.
                for warning in loaded.warnings {
                    if !warnings.contains(&warning) {
                        warnings.push(warning);
                    }
                }
                loaded_wheels.push((key, loaded.profile.clone()));
                loaded.profile
            }
        };
        let contact = WheelsetContactModel::new(
            wheel.clone(),
            wheel,
            w.back_to_back_m,
            &rail_profile,
            &rail_profile,
            placement,
        )
        .with_context(|| format!("wheelset '{}'", w.name))?;
        wheelsets.push(WheelsetSpec {
            name: w.name.clone(),
            body: RigidBody {
                mass_kg: w.mass_kg,
                inertia_kg_m2: diag(w.inertia_kg_m2),
            },
            contact,
            x_m: w.x_m,
            y_m: w.y_m,
            nominal_radius_m: w.nominal_radius_m,
            static_wheel_load_n: v.static_wheel_load_n(w),
        });
    }
    let bodies: Vec<BodySpec> = v
        .bodies
        .iter()
        .map(|b| BodySpec {
            name: b.name.clone(),
            body: RigidBody {
                mass_kg: b.mass_kg,
                inertia_kg_m2: diag(b.inertia_kg_m2),
            },
            cg_m: Vector3::from(b.cg_m),
        })
        .collect();
    let references: Vec<ReferenceSpec> = v
        .references
        .iter()
        .map(|r| ReferenceSpec {
            name: r.name.clone(),
            origin_m: Vector3::from(r.origin_m),
        })
        .collect();
    let end = |name: &str| -> Result<End> {
        if name == GROUND {
            return Ok(End::Ground);
        }
        if let Some(i) = v.wheelsets.iter().position(|w| w.name == name) {
            return Ok(End::Wheelset(i));
        }
        if let Some(i) = v.bodies.iter().position(|b| b.name == name) {
            return Ok(End::Body(i));
        }
        if let Some(i) = v.references.iter().position(|r| r.name == name) {
            return Ok(End::Reference(i));
        }
        Err(anyhow!("unknown body '{name}'"))
    };
    let mut elements = Vec::new();
    let preloads = v.element_preloads_n();
    for (e, preload) in v.elements.iter().zip(preloads) {
        let (pa, pb) = e.points()?;
        let laws = axis_laws(&e.name, &e.spring, &e.damper, &e.series)?;
        elements.push(ElementSpec {
            name: e.name.clone(),
            a: end(&e.body_a)?,
            b: end(&e.body_b)?,
            point_a_m: Vector3::from(pa),
            point_b_m: Vector3::from(pb),
            stiffness_n_m: e.stiffness_n_m,
            damping_n_s_m: e.damping_n_s_m,
            preload_n: Vector3::from(preload),
            laws,
        });
    }
    ensure!(!wheelsets.is_empty(), "the vehicle has no wheelset");
    Ok((
        VehicleModel {
            name: v.name.clone(),
            wheelsets,
            bodies,
            references,
            elements,
        },
        warnings,
    ))
}
