//! The simulation results file: round trip, layout seen by h5dump,
//! validation and schema checks.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{RwLock, RwLockReadGuard};

use runtime::contact::nadal::{NadalLimit, nadal_limit};
use runtime::io::schema::{RESULTS_SCHEMA_VERSION, SchemaError, read_results, write_results};
use runtime::results::{
    AttrValue, BODY_COLUMNS, BodyKind, BodySample, BodySeries, CarBody, ResultsError, RunResults,
    Values, WheelSample, WheelsetSample, ZoneSample,
};

/// Spawning `h5dump` forks this process: the child inherits the file
/// descriptors (and HDF5's file locks) of files other tests have open at
/// that moment, which then fail to open their files. The h5dump test takes
/// this lock exclusively, the others shared.
static SPAWN: RwLock<()> = RwLock::new(());

fn shared() -> RwLockReadGuard<'static, ()> {
    SPAWN.read().unwrap_or_else(|e| e.into_inner())
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A zone sample whose every value is distinct (so a swapped column is
/// caught), in contact on a pattern that depends on `k`.
fn zone(k: usize, seed: f64, in_contact: bool) -> ZoneSample {
    let v = |j: f64| seed + 0.01 * j + 1e-3 * k as f64;
    ZoneSample {
        in_contact,
        normal_n: v(1.0) * 1e4,
        fx_n: v(2.0),
        fy_n: v(3.0),
        mz_nm: v(4.0),
        lateral_force_n: v(5.0),
        vertical_force_n: v(6.0),
        xi: v(7.0),
        eta: v(8.0),
        phi_1_m: v(9.0),
        y_wheel_m: v(10.0),
        y_rail_m: v(11.0),
        contact_angle_rad: v(12.0),
        lead_m: v(13.0),
        fallback: (k % 4) as u8,
    }
}

/// Two wheelsets, `n` samples at 1 kHz, flange contact now and then.
fn synthetic(n: usize) -> RunResults {
    let mut r = RunResults::with_wheelsets(["leading", "trailing"]);
    r.scene_toml = "[vehicle]\nkind = \"bogie\"\n# ünïcödé: ξ η φ\n".into();
    r.attributes = vec![
        ("creep_law".into(), "polach".into()),
        ("integrator".into(), "rk4".into()),
        ("speed_m_s".into(), 36.0.into()),
        ("steps".into(), 50910_u64.into()),
        ("flag".into(), true.into()),
        ("a_first_by_name_last_by_order".into(), "x".into()),
    ];
    let mut car = BodySeries::new("car body", BodyKind::Free, 44388.0);
    car.assembly_x_m = 0.0;
    car.assembly_height_m = 2.0596;
    let mut ws = BodySeries::new("leading", BodyKind::Wheelset, 1500.0);
    ws.assembly_x_m = 1.25;
    // A name HDF5 cannot take as a link: stored under "frame_a", named in
    // its `name` attribute.
    let frame = BodySeries::new("frame/a", BodyKind::Free, 2900.0);
    r.bodies = vec![ws, frame, car];
    r.car_body = Some(CarBody {
        name: "car body".into(),
        rule: CarBody::BY_NAME.into(),
    });
    for k in 0..n {
        let t = k as f64 * 1e-3;
        let samples: Vec<WheelsetSample> = (0..2)
            .map(|w| {
                let seed = 10.0 * w as f64;
                let wheel = |side: usize| WheelSample {
                    travelled_m: 36.0 * t + 0.001 * side as f64,
                    zones: [
                        zone(k, seed + side as f64, k % 7 != 3),
                        zone(k, seed + 5.0 + side as f64, k % 5 == side),
                    ],
                };
                WheelsetSample {
                    lateral_m: 0.002 * (t * 10.0 + w as f64).sin(),
                    yaw_rad: 1e-3 * t,
                    roll_rad: -1e-4 * t,
                    distance_m: 36.0 * t,
                    speed_m_s: 36.0,
                    track_s_m: 12.5 + 36.0 * t,
                    wheels: [wheel(0), wheel(1)],
                }
            })
            .collect();
        let bodies: Vec<BodySample> = (0..3).map(|b| body_sample(k, b)).collect();
        r.push_sample(t, &samples, &bodies).unwrap();
    }
    r.wheelsets[0].wheels[1].nadal = Some(NadalLimit {
        flange_angle_rad: 1.2,
        friction: 0.3,
        limit: nadal_limit(1.2, 0.3),
    });
    r
}

/// A body sample whose every value is distinct (a swapped column shows).
fn body_sample(k: usize, body: usize) -> BodySample {
    let mut s = BodySample::default();
    for (j, c) in BODY_COLUMNS.iter().enumerate() {
        if let Values::F64(a) = &c.values {
            (a.set)(&mut s, 100.0 * body as f64 + j as f64 + 1e-3 * k as f64);
        }
    }
    s
}

/// Bitwise equality of two f64 series (NaN positions included).
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

fn assert_same(a: &RunResults, b: &RunResults) {
    assert!(same_bits(&a.time_s, &b.time_s));
    assert_eq!(a.scene_toml, b.scene_toml);
    assert_eq!(a.attributes, b.attributes);
    assert_eq!(a.car_body, b.car_body);
    assert_eq!(a.bodies.len(), b.bodies.len());
    for (x, y) in a.bodies.iter().zip(&b.bodies) {
        assert_eq!((&x.name, x.kind), (&y.name, y.kind));
        for v in [
            (x.mass_kg, y.mass_kg),
            (x.assembly_x_m, y.assembly_x_m),
            (x.assembly_height_m, y.assembly_height_m),
        ] {
            assert_eq!(v.0.to_bits(), v.1.to_bits(), "{}", x.name);
        }
        for i in 0..a.len() {
            assert_eq!(x.sample(i), y.sample(i), "{} sample {i}", x.name);
        }
    }
    assert_eq!(a.wheelsets.len(), b.wheelsets.len());
    for (x, y) in a.wheelsets.iter().zip(&b.wheelsets) {
        assert_eq!(x.name, y.name);
        for (p, q) in [
            (&x.lateral_m, &y.lateral_m),
            (&x.yaw_rad, &y.yaw_rad),
            (&x.roll_rad, &y.roll_rad),
            (&x.distance_m, &y.distance_m),
            (&x.speed_m_s, &y.speed_m_s),
        ] {
            assert!(same_bits(p, q));
        }
        for (wx, wy) in x.wheels.iter().zip(&y.wheels) {
            assert!(same_bits(&wx.travelled_m, &wy.travelled_m));
            assert!(same_bits(&wx.y_n, &wy.y_n));
            assert!(same_bits(&wx.q_n, &wy.q_n));
            assert!(same_bits(&wx.y_over_q, &wy.y_over_q));
            assert_eq!(wx.nadal, wy.nadal);
            assert_eq!(wx.flange_contact, wy.flange_contact);
            for (zx, zy) in wx.zones.iter().zip(&wy.zones) {
                assert_eq!(zx.in_contact, zy.in_contact);
                for i in 0..a.len() {
                    let (sx, sy) = (zx.sample(i).unwrap(), zy.sample(i).unwrap());
                    let bits = |s: &ZoneSample| {
                        [
                            s.normal_n,
                            s.fx_n,
                            s.fy_n,
                            s.mz_nm,
                            s.lateral_force_n,
                            s.vertical_force_n,
                            s.xi,
                            s.eta,
                            s.phi_1_m,
                            s.y_wheel_m,
                            s.y_rail_m,
                            s.contact_angle_rad,
                            s.lead_m,
                        ]
                        .map(f64::to_bits)
                    };
                    assert_eq!(bits(&sx), bits(&sy), "sample {i}");
                    assert_eq!(sx.fallback, sy.fallback, "sample {i}");
                }
            }
        }
    }
}

#[test]
fn results_round_trip_is_exact() {
    let _guard = shared();
    let dir = scratch("results_round_trip");
    let path = dir.join("run.h5");
    let r = synthetic(500);
    r.validate().unwrap();
    // The pattern gives both flags and NaN gaps.
    let flange = &r.wheelsets[0].wheels[0].zones[1];
    assert!(flange.in_contact.contains(&1) && flange.in_contact.contains(&0));
    assert!(flange.normal_n.iter().any(|v| v.is_nan()));
    assert_eq!(
        r.wheelsets[0].wheels[0].flange_contact, flange.in_contact,
        "the flange flag follows the flange zone"
    );

    write_results(&path, &r).unwrap();
    let back = read_results(&path).unwrap();
    assert_same(&r, &back);
    assert_eq!(back.len(), 500);
    assert_eq!(back.attribute_text("creep_law"), Some("polach"));
    // Numbers come back as numbers.
    assert_eq!(back.attribute("speed_m_s"), Some(&AttrValue::Float(36.0)));
    assert_eq!(back.attribute("steps"), Some(&AttrValue::Int(50910)));
    assert_eq!(back.attribute("flag"), Some(&AttrValue::Bool(true)));
    assert_eq!(back.bodies[1].name, "frame/a");
    // No temporary left behind.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["run.h5"]);
}

#[test]
fn results_round_trip_of_an_empty_run() {
    let _guard = shared();
    let dir = scratch("results_empty");
    let path = dir.join("empty.h5");
    let r = RunResults::with_wheelsets(["only"]);
    assert!(r.is_empty());
    write_results(&path, &r).unwrap();
    let back = read_results(&path).unwrap();
    assert_eq!(back, r);
}

#[test]
fn results_out_of_contact_samples_are_nan() {
    let mut r = RunResults::with_wheelsets(["w"]);
    let mut s = WheelsetSample::default();
    s.wheels[0].zones[0] = ZoneSample {
        in_contact: false,
        ..zone(0, 1.0, true)
    };
    r.push(0.0, &[s]).unwrap();
    let z = &r.wheelsets[0].wheels[0].zones[0];
    assert_eq!(z.in_contact, [0]);
    assert!(z.normal_n[0].is_nan() && z.xi[0].is_nan());
    assert!(matches!(
        r.push(0.001, &[s, s]),
        Err(ResultsError::WheelsetCount {
            expected: 1,
            found: 2
        })
    ));
    assert_eq!(r.len(), 1, "a refused push appends nothing");
}

#[test]
fn results_h5dump_shows_the_layout() {
    let _guard = SPAWN.write().unwrap_or_else(|e| e.into_inner());
    let dir = scratch("results_h5dump");
    let path = dir.join("run.h5");
    write_results(&path, &synthetic(20)).unwrap();
    let out = match Command::new("h5dump").arg("-H").arg(&path).output() {
        Ok(o) => o,
        Err(e) => panic!("h5dump (hdf5-tools) is needed for this test: {e}"),
    };
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "GROUP \"/\"",
        "ATTRIBUTE \"schema\"",
        "ATTRIBUTE \"schema_version\"",
        "ATTRIBUTE \"tool_version\"",
        "ATTRIBUTE \"creep_law\"",
        "DATASET \"time_s\"",
        "DATASET \"scene\"",
        "GROUP \"wheelset_0\"",
        "GROUP \"wheelset_1\"",
        "GROUP \"left\"",
        "GROUP \"right\"",
        "GROUP \"tread\"",
        "GROUP \"flange\"",
        "DATASET \"lateral_m\"",
        "DATASET \"travelled_m\"",
        "DATASET \"flange_contact\"",
        "DATASET \"lateral_force_n\"",
        "DATASET \"phi_1_m\"",
        "DATASET \"contact_angle_rad\"",
        "DATASET \"lead_m\"",
        "DATASET \"fallback\"",
        "DATASET \"y_over_q\"",
        "DATASET \"track_s_m\"",
        "DATASET \"sum_y_n\"",
        "DATASET \"wear_number_n\"",
        "ATTRIBUTE \"units\"",
        "ATTRIBUTE \"description\"",
        // Extendable: 20 samples now, no fixed maximum.
        "DATASPACE  SIMPLE { ( 20 ) / ( H5S_UNLIMITED ) }",
        "H5T_STD_U8LE",
        "H5T_IEEE_F64LE",
    ] {
        assert!(text.contains(needle), "h5dump -H lacks {needle}:\n{text}");
    }
    // Every wheel has 2 zones × 16 datasets (in_contact, 13 values,
    // fallback, wear_number_n) + 6 (travelled_m, flange_contact, y_n, q_n,
    // y_over_q, wear_number_n): 38 per wheel, 76 + 7 per wheelset
    // (lateral_m, yaw_rad, roll_rad, distance_m, speed_m_s, track_s_m,
    // sum_y_n), 15 per body (3), plus time_s and scene.
    assert_eq!(
        text.matches("DATASET \"").count(),
        2 * (7 + 2 * 38) + 3 * BODY_COLUMNS.len() + 2
    );
    assert_eq!(BODY_COLUMNS.len(), 15);
    for needle in [
        "GROUP \"bodies\"",
        "GROUP \"car body\"",
        "GROUP \"frame_a\"",
        "DATASET \"vertical_acceleration_m_s2\"",
        "ATTRIBUTE \"car_body\"",
    ] {
        assert!(text.contains(needle), "h5dump -H lacks {needle}:\n{text}");
    }
    // Numeric run attributes are HDF5 numbers.
    let out = Command::new("h5dump")
        .args(["-a", "/speed_m_s", "-a", "/steps"])
        .arg(&path)
        .output()
        .unwrap();
    let attrs = String::from_utf8_lossy(&out.stdout);
    assert!(
        attrs.contains("H5T_IEEE_F64LE") && attrs.contains("H5T_STD_I64LE"),
        "{attrs}"
    );
    assert!(
        attrs.contains("(0): 36") && attrs.contains("(0): 50910"),
        "{attrs}"
    );

    // The values, not just the header: schema and a units attribute.
    let out = Command::new("h5dump")
        .args([
            "-a",
            "/schema",
            "-a",
            "/wheelset_0/left/tread/phi_1_m/units",
        ])
        .arg(&path)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("\"railsim-results\""), "{text}");
    assert!(text.contains("\"1/m\""), "{text}");
}

#[test]
fn results_mismatched_lengths_are_refused() {
    let _guard = shared();
    let dir = scratch("results_mismatch");
    let path = dir.join("bad.h5");
    let mut r = synthetic(10);
    r.wheelsets[1].wheels[1].zones[0].eta.pop();
    let e = r.validate().unwrap_err();
    assert_eq!(
        e,
        ResultsError::LengthMismatch {
            series: "wheelset_1/right/tread/eta".into(),
            len: 9,
            expected: 10
        }
    );
    let e = write_results(&path, &r).unwrap_err();
    assert!(
        matches!(e, SchemaError::InvalidResults { .. }),
        "unexpected error {e}"
    );
    assert!(e.to_string().contains("wheelset_1/right/tread/eta"), "{e}");
    assert!(!path.exists(), "nothing written");

    let mut r = synthetic(10);
    r.wheelsets[0].wheels[0].flange_contact.push(1);
    assert!(matches!(
        r.validate(),
        Err(ResultsError::LengthMismatch { .. })
    ));

    let mut r = synthetic(10);
    r.wheelsets[0].wheels[0].zones[1].in_contact[3] = 2;
    assert!(matches!(
        r.validate(),
        Err(ResultsError::FlagValue {
            index: 3,
            value: 2,
            ..
        })
    ));

    let mut r = synthetic(10);
    r.time_s[4] = r.time_s[2];
    assert!(matches!(
        r.validate(),
        Err(ResultsError::TimeDecreasing { index: 4, .. })
    ));

    let mut r = synthetic(10);
    r.attributes.push(("schema".into(), "mine".into()));
    assert!(matches!(r.validate(), Err(ResultsError::Attribute { .. })));
    let mut r = synthetic(10);
    r.attributes.push(("integrator".into(), "dopri5".into()));
    assert!(matches!(r.validate(), Err(ResultsError::Attribute { .. })));
}

#[test]
fn results_unknown_schema_version_is_refused() {
    let _guard = shared();
    let dir = scratch("results_version");
    let path = dir.join("future.h5");
    write_results(&path, &synthetic(5)).unwrap();
    {
        let f = hdf5::File::open_rw(&path).unwrap();
        f.delete_attr("schema_version").unwrap();
        f.new_attr::<u32>()
            .shape(())
            .create("schema_version")
            .unwrap()
            .write_scalar(&(RESULTS_SCHEMA_VERSION + 1))
            .unwrap();
    }
    let e = read_results(&path).unwrap_err();
    match &e {
        SchemaError::UnsupportedResultsVersion {
            found, supported, ..
        } => {
            assert_eq!(*found, RESULTS_SCHEMA_VERSION + 1);
            assert_eq!(*supported, RESULTS_SCHEMA_VERSION);
        }
        other => panic!("unexpected error {other}"),
    }
    assert!(
        e.to_string().contains("version 3") && e.to_string().contains("versions 1 to 2"),
        "{e}"
    );
}

#[test]
fn results_reader_refuses_other_files() {
    let _guard = shared();
    let dir = scratch("results_other");
    let path = dir.join("table.h5");
    {
        let f = hdf5::File::create(&path).unwrap();
        f.new_attr::<u32>()
            .shape(())
            .create("schema_version")
            .unwrap()
            .write_scalar(&1u32)
            .unwrap();
    }
    let e = read_results(&path).unwrap_err();
    assert!(
        matches!(e, SchemaError::NotResults { found: None, .. }),
        "{e}"
    );

    // A truncated dataset in an otherwise valid file names the dataset.
    let path = dir.join("truncated.h5");
    write_results(&path, &synthetic(5)).unwrap();
    {
        let f = hdf5::File::open_rw(&path).unwrap();
        let g = f.group("wheelset_0/left").unwrap();
        g.unlink("travelled_m").unwrap();
        g.new_dataset_builder()
            .with_data(&[1.0_f64, 2.0][..])
            .create("travelled_m")
            .unwrap();
    }
    let e = read_results(&path).unwrap_err();
    assert!(matches!(e, SchemaError::Invalid { .. }), "{e}");
    assert!(
        e.to_string().contains("/wheelset_0/left/travelled_m"),
        "{e}"
    );
}

#[test]
fn results_y_over_q_sign_and_old_files() {
    let _guard = shared();
    // Y is + towards the track centre: a left wheel pushed back to the
    // right (lateral −) and a right wheel pushed back to the left (+) both
    // have Y > 0; Q sums the zones.
    let tread = ZoneSample {
        in_contact: true,
        lateral_force_n: -1000.0,
        vertical_force_n: 40e3,
        ..zone(0, 1.0, true)
    };
    let flange = ZoneSample {
        lateral_force_n: -20e3,
        vertical_force_n: 10e3,
        ..tread
    };
    let mut s = WheelsetSample::default();
    s.wheels[0].zones = [tread, flange];
    s.wheels[1].zones = [
        ZoneSample {
            lateral_force_n: 3000.0,
            ..tread
        },
        ZoneSample::NO_CONTACT,
    ];
    let mut r = RunResults::with_wheelsets(["w"]);
    r.push(0.0, &[s]).unwrap();
    r.push(0.001, &[WheelsetSample::default()]).unwrap();
    let left = &r.wheelsets[0].wheels[0];
    assert_eq!(left.y_n[0], 21e3);
    assert_eq!(left.q_n[0], 50e3);
    assert_eq!(left.y_over_q[0], 21e3 / 50e3);
    let right = &r.wheelsets[0].wheels[1];
    assert_eq!(right.y_over_q[0], 3000.0 / 40e3);
    assert!(left.y_over_q[1].is_nan(), "no contact: NaN");
    // Fallback flags are bits 1 and 2; anything else is refused.
    let mut bad = r.clone();
    bad.wheelsets[0].wheels[0].zones[1].fallback[1] = 4;
    assert!(matches!(
        bad.validate(),
        Err(ResultsError::FlagValue { value: 4, .. })
    ));
    bad.wheelsets[0].wheels[0].zones[1].fallback[1] = 3;
    assert!(bad.validate().is_ok());
    assert_eq!(left.max_y_over_q(), Some(0.42));

    // A version-1 file written before y_n, q_n, y_over_q, lead_m,
    // fallback and track_s_m existed reads back with Y/Q recomputed from
    // the zones.
    let dir = scratch("results_old_layout");
    let path = dir.join("old.h5");
    write_results(&path, &synthetic(6)).unwrap();
    let full = read_results(&path).unwrap();
    {
        let f = hdf5::File::open_rw(&path).unwrap();
        for ws in ["wheelset_0", "wheelset_1"] {
            for wheel in ["left", "right"] {
                let g = f.group(&format!("{ws}/{wheel}")).unwrap();
                for name in ["y_n", "q_n", "y_over_q", "wear_number_n"] {
                    g.unlink(name).unwrap();
                }
                for zone in ["tread", "flange"] {
                    let z = g.group(zone).unwrap();
                    for name in ["lead_m", "fallback", "wear_number_n"] {
                        z.unlink(name).unwrap();
                    }
                }
            }
            for name in ["track_s_m", "sum_y_n"] {
                f.group(ws).unwrap().unlink(name).unwrap();
            }
        }
        // Version 1: no bodies, and string attributes, as before they were
        // typed.
        f.delete_attr("schema_version").unwrap();
        f.new_attr::<u32>()
            .shape(())
            .create("schema_version")
            .unwrap()
            .write_scalar(&1)
            .unwrap();
        f.unlink("bodies").unwrap();
        for name in ["speed_m_s", "steps", "flag"] {
            f.delete_attr(name).unwrap();
        }
        let text = |v: &str| -> hdf5::types::VarLenUnicode { v.parse().unwrap() };
        f.new_attr::<hdf5::types::VarLenUnicode>()
            .shape(())
            .create("speed_m_s")
            .unwrap()
            .write_scalar(&text("22"))
            .unwrap();
    }
    let old = read_results(&path).unwrap();
    // The track position is stored and read back; unknown (NaN) in a file
    // from before it was stored.
    assert_eq!(full.wheelsets[0].track_s_m[2], 12.5 + 36.0 * 0.002);
    assert!(old.wheelsets[0].track_s_m.iter().all(|v| v.is_nan()));
    // No bodies group: no bodies, no car body; a string attribute stays
    // text, and reads as a number when asked for one.
    assert!(old.bodies.is_empty() && old.car_body.is_none());
    assert_eq!(full.bodies.len(), 3);
    let speed = old.attribute("speed_m_s").unwrap();
    assert_eq!(speed, &AttrValue::Text("22".into()));
    assert_eq!(speed.as_f64(), Some(22.0));
    assert_eq!(old.wheelsets[0].track_s_m.len(), old.time_s.len());
    let (a, b) = (&full.wheelsets[1].wheels[1], &old.wheelsets[1].wheels[1]);
    assert!(same_bits(&a.y_over_q, &b.y_over_q));
    assert!(same_bits(&a.q_n, &b.q_n));
    assert!(b.zones[0].lead_m.iter().all(|v| v.is_nan()));
    assert!(b.zones[0].fallback.iter().all(|&f| f == 0));
    // ΣY and the wear numbers are derived again from the zones.
    assert!(same_bits(&a.wear_number_n, &b.wear_number_n));
    for z in 0..2 {
        assert!(same_bits(
            &a.zones[z].wear_number_n,
            &b.zones[z].wear_number_n
        ));
    }
    assert!(a.wear_number_n.iter().any(|v| v.is_finite() && *v > 0.0));
    let (a, b) = (&full.wheelsets[1], &old.wheelsets[1]);
    assert!(same_bits(&a.sum_y_n, &b.sum_y_n));
    assert!(a.sum_y_n.iter().any(|v| v.is_finite() && *v != 0.0));
}

/// The writer `sim run` uses: samples appended chunk by chunk while the
/// run goes on (and restarted once, as a repeated run does) read back
/// exactly as the record written in one piece; nothing is at the
/// destination before `finish`, and the datasets are chunked and
/// extendable.
#[test]
fn results_written_in_chunks_read_back_as_one_record() {
    use runtime::io::schema::{RESULTS_CHUNK_SAMPLES, ResultsWriter};
    let _guard = shared();
    let dir = scratch("results_chunks");
    let path = dir.join("run.h5");
    let full = synthetic(RESULTS_CHUNK_SAMPLES + 700);
    let mut writer = ResultsWriter::create(&path).unwrap();
    // A first attempt, then forgotten.
    let mut first = full.clone();
    first.keep_every(3);
    writer.append_chunk(&first).unwrap();
    writer.clear().unwrap();
    assert_eq!(writer.samples(), 0);
    // Chunks of 1000 samples taken from the front of a growing record.
    let mut pending = full.clone();
    let _ = pending.take_samples();
    for start in (0..full.len()).step_by(1000) {
        pending.append_where(&full, |i| (start..start + 1000).contains(&i));
        writer.append_chunk(&pending.take_samples()).unwrap();
    }
    assert_eq!(writer.samples(), full.len());
    // A chunk going back in time is refused.
    let mut back_in_time = full.clone();
    back_in_time.keep_every(full.len());
    assert!(matches!(
        writer.append_chunk(&back_in_time),
        Err(SchemaError::InvalidResults { .. })
    ));
    assert!(!path.exists(), "nothing at the destination before finish");
    writer.finish(&full).unwrap();
    let back = read_results(&path).unwrap();
    assert_same(&full, &back);
    let file = hdf5::File::open(&path).unwrap();
    let ds = file.dataset("wheelset_1/right/flange/normal_n").unwrap();
    assert_eq!(ds.chunk(), Some(vec![RESULTS_CHUNK_SAMPLES]));
    assert!(ds.is_resizable());
}

/// A run that ends before its first sample (it failed at the start) still
/// leaves a complete file: `finish` makes every series, empty, and the
/// file reads back as the record's wheelsets and bodies with no samples.
#[test]
fn results_writer_finished_before_any_sample_has_every_series() {
    use runtime::io::schema::ResultsWriter;
    let _guard = shared();
    let dir = scratch("results_no_sample");
    let path = dir.join("run.h5");
    let mut record = synthetic(3);
    let _ = record.take_samples();
    assert!(record.is_empty());
    let writer = ResultsWriter::create(&path).unwrap();
    writer.finish(&record).unwrap();
    let back = read_results(&path).unwrap();
    assert_same(&record, &back);
    assert_eq!(back.wheelsets.len(), record.wheelsets.len());
    assert_eq!(back.bodies.len(), record.bodies.len());
    let file = hdf5::File::open(&path).unwrap();
    for name in [
        "time_s",
        "wheelset_1/right/flange/normal_n",
        "wheelset_0/left/tread/in_contact",
    ] {
        assert_eq!(file.dataset(name).unwrap().shape(), vec![0], "{name}");
    }
}
