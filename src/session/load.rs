//! The scene's `[load]` and `[perturbation]` sections applied to the
//! vehicle model and its initial state (the sections and their meaning:
//! [`crate::config::load`]).

use anyhow::{Result, ensure};
use nalgebra::Vector3;
use runtime::geometry::track::TrackTables;
use runtime::multibody::body::BodyState;
use runtime::multibody::track_motion::track_rotation;
use runtime::multibody::{ElementSpec, End, ReferenceSpec, VehicleModel};

use crate::config::load::{LoadSection, PerturbationSection, YAW_COUPLE_ARM_M, YAW_DAMPING_RATIO};

/// The wheelsets a section applies to.
fn targets(wheelset: Option<usize>, n: usize, section: &str) -> Result<Vec<usize>> {
    match wheelset {
        Some(i) => {
            ensure!(
                i < n,
                "[{section}] wheelset = {i}: the vehicle has {n} wheelset(s), numbered from 0"
            );
            Ok(vec![i])
        }
        None => Ok((0..n).collect()),
    }
}

/// Adds the `[load]` elements (and their track-following references) to
/// the vehicle (module docs).
pub fn add_loads(vehicle: &mut VehicleModel, load: &LoadSection) -> Result<()> {
    load.validate()?;
    if load.lateral_force_n == 0.0 && load.yaw_moment_nm == 0.0 && load.yaw_stiffness_nm_rad == 0.0
    {
        return Ok(());
    }
    for i in targets(load.wheelset, vehicle.wheelsets.len(), "load")? {
        let w = &vehicle.wheelsets[i];
        let centre = Vector3::new(w.x_m, w.y_m, w.nominal_radius_m);
        let name = w.name.clone();
        let yaw_inertia_kg_m2 = w.body.inertia_kg_m2[(2, 2)];
        let reference = vehicle.references.len();
        vehicle.references.push(ReferenceSpec {
            name: format!("[load] frame of '{name}'"),
            origin_m: centre,
        });
        let none = [0.0; 3];
        let mut element =
            |label: &str, at: Vector3<f64>, k: [f64; 3], c: [f64; 3], f0: Vector3<f64>| {
                let point = centre + at;
                vehicle.elements.push(ElementSpec {
                    name: format!("[load] {label} on '{name}'"),
                    a: End::Reference(reference),
                    b: End::Wheelset(i),
                    point_a_m: point,
                    point_b_m: point,
                    stiffness_n_m: k,
                    damping_n_s_m: c,
                    preload_n: f0,
                    laws: Default::default(),
                });
            };
        let lateral = |f: f64| Vector3::new(0.0, f, 0.0);
        let ahead = |d: f64| Vector3::new(d, 0.0, 0.0);
        if load.lateral_force_n != 0.0 {
            let f = lateral(load.lateral_force_n);
            element("lateral force", Vector3::zeros(), none, none, f);
        }
        if load.yaw_moment_nm != 0.0 {
            // r × F about b: (+d t) × (+F n) = +d F b, nose left.
            let f = load.yaw_moment_nm / (2.0 * YAW_COUPLE_ARM_M);
            element(
                "yaw moment, front",
                ahead(YAW_COUPLE_ARM_M),
                none,
                none,
                lateral(f),
            );
            element(
                "yaw moment, rear",
                ahead(-YAW_COUPLE_ARM_M),
                none,
                none,
                lateral(-f),
            );
        }
        if load.yaw_stiffness_nm_rad > 0.0 {
            let b = YAW_COUPLE_ARM_M;
            let k = load.yaw_stiffness_nm_rad / (2.0 * b * b);
            let c_yaw =
                2.0 * YAW_DAMPING_RATIO * (load.yaw_stiffness_nm_rad * yaw_inertia_kg_m2).sqrt();
            let c = c_yaw / (2.0 * b * b);
            let f0 = k * b * load.yaw_angle_rad;
            let side = |y: f64| Vector3::new(0.0, y, 0.0);
            let (kx, cx) = ([k, 0.0, 0.0], [c, 0.0, 0.0]);
            element("yaw spring, left", side(b), kx, cx, ahead(-f0));
            element("yaw spring, right", side(-b), kx, cx, ahead(f0));
        }
    }
    Ok(())
}

/// Applies the `[perturbation]` to the initial state `y0` (13 variables per
/// wheelset, wheelsets first: position, quaternion, velocity, body angular
/// velocity), in the track frame at each wheelset.
pub fn perturb(
    y0: &mut [f64],
    vehicle: &VehicleModel,
    track: &TrackTables,
    s_start_m: f64,
    p: &PerturbationSection,
) -> Result<()> {
    p.validate()?;
    if p.drop_m == 0.0 && p.lateral_velocity_m_s == 0.0 {
        return Ok(());
    }
    for i in targets(p.wheelset, vehicle.wheelsets.len(), "perturbation")? {
        let w = &vehicle.wheelsets[i];
        let frame = track_rotation(&track.centerline, s_start_m + w.x_m)?;
        let (n, b) = (frame.column(1).into_owned(), frame.column(2).into_owned());
        let slot = &mut y0[BodyState::slot(i)];
        let mut st = BodyState::read_from(slot);
        st.position_m += b * p.drop_m;
        st.velocity_m_s += n * p.lateral_velocity_m_s;
        st.write_to(slot);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_values_name_the_entry() {
        let e = LoadSection {
            lateral_force_n: f64::NAN,
            ..Default::default()
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().contains("[load] lateral_force_n"), "{e}");
        let e = PerturbationSection {
            drop_m: -0.001,
            ..Default::default()
        }
        .validate()
        .unwrap_err();
        assert!(e.to_string().contains("[perturbation] drop_m"), "{e}");
        let e = targets(Some(2), 1, "load").unwrap_err();
        assert!(e.to_string().contains("wheelset = 2"), "{e}");
        assert_eq!(targets(None, 3, "load").unwrap(), [0, 1, 2]);
    }
}
