//! Contact extremes (issue 7, part B): Nadal's quotient under a large
//! lateral load, flange climbing to derailment, two-point contact with lead
//! and lag, wheel lift (drop) and a lateral impact on the flange, a
//! near-vertical flange, a nearly conformal worn tread, very soft and very
//! stiff materials. Every case is `sim run` (the ML95-like unsuspended
//! wheelset, tables/scenes/wheelset_straight.toml, on an ideal 60 m
//! straight) or `sim contact`, with the scene sections `[load]` and
//! `[perturbation]` (src/load.rs) where it needs a load or a push, and the
//! property it must keep:
//!
//! - no panic, and a results record whose every value is finite except
//!   where the schema writes NaN for "no contact" ([`check_record`]);
//! - the physics it exercises (force balance, sign rules, energy,
//!   restitution, Hertz scaling), with the figures in docs/guide/extremes-and-diagnostics.md "Extremes:
//!   contact";
//! - where the model leaves its validity, a run that stops cleanly with its
//!   results written and an error naming the time, the wheelset, wheel and
//!   zone and the wheelset's state — or goes on through a documented
//!   fallback that is flagged and counted.
//!
//! Figures: the ML95-like wheelset has m = 1430 kg, I_yaw = 790 kg·m²,
//! r₀ = 0.43 m, a 70° flank (Nadal limit (tan 70° − 0.3)/(1 + 0.3 tan 70°)
//! = 1.3416 at μ = 0.3) and 7.0 kN per wheel.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use runtime::{io::schema::read_results, results::RunResults};
use serde_json::Value;

use crate::common::*;

/// Nadal's limit of the ML95-like 70° flank at μ = 0.3.
const NADAL_70: f64 = 1.341_64;
/// Mass (kg) of the ML95-like wheelset and gravity (m/s²) of the runs.
const MASS_KG: f64 = 1430.0;
const G_M_S2: f64 = 9.81;

/// The outcome of one `sim run`.
struct Run {
    name: String,
    /// `--json` summary when the run completed.
    summary: Option<Value>,
    stderr: String,
    h5: PathBuf,
}

impl Run {
    fn summary(&self) -> &Value {
        self.summary
            .as_ref()
            .unwrap_or_else(|| panic!("{}: the run failed:\n{}", self.name, self.stderr))
    }

    fn results(&self) -> RunResults {
        read_results(&self.h5).unwrap_or_else(|e| panic!("{}: {e}", self.name))
    }

    /// `wheelsets[0].nadal[wheel]` of the summary.
    fn nadal(&self, wheel: usize) -> &Value {
        &self.summary()["wheelsets"][0]["nadal"][wheel]
    }

    fn energy(&self, key: &str) -> f64 {
        self.summary()["energy"][key]
            .as_f64()
            .unwrap_or_else(|| panic!("{}: energy.{key}", self.name))
    }
}

/// `sim run` of the wheelset scene on an ideal 60 m straight with
/// `overrides`; the record is checked with [`check_record`] whether the run
/// completed or not.
fn sim_run(dir: &Path, name: &str, overrides: &[&str]) -> Run {
    let h5 = dir.join(format!("{name}.h5"));
    let mut cmd = sim();
    cmd.env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .arg("run")
        .arg(shipped("scenes/wheelset_straight.toml"))
        .arg("-o")
        .arg(&h5)
        .args(["--no-plots", "--json"]);
    let base = [
        "track.centerline=",
        "track.straight_m=60",
        "run.distance_m=",
    ];
    for o in base.iter().chain(overrides) {
        cmd.args(["--set", o]);
    }
    let o = run(&mut cmd);
    let summary = o
        .status
        .success()
        .then(|| serde_json::from_str(&stdout(&o)).expect("JSON summary"));
    let r = Run {
        name: name.to_string(),
        summary,
        stderr: stderr(&o),
        h5,
    };
    assert!(r.h5.exists(), "{name}: no results file\n{}", r.stderr);
    let n = check_record(&r.results());
    eprintln!(
        "{name}: {} samples, {n} values checked{}",
        r.results().len(),
        if r.summary.is_some() {
            ""
        } else {
            " (failed run)"
        }
    );
    r
}

/// Every value of a record is finite, except the NaN the schema writes for
/// "no contact": a zone's f64 series are finite exactly where its
/// `in_contact` is 1 (and its normal force ≥ 0 there), NaN elsewhere; a
/// wheel's Y and Q are finite when a zone is in contact, Y/Q when Q > 0.
/// Returns the number of values checked.
fn check_record(r: &RunResults) -> usize {
    let mut n = 0;
    assert!(r.time_s.iter().all(|t| t.is_finite()));
    for (i, ws) in r.wheelsets.iter().enumerate() {
        for (name, s) in [
            ("lateral_m", &ws.lateral_m),
            ("yaw_rad", &ws.yaw_rad),
            ("roll_rad", &ws.roll_rad),
            ("distance_m", &ws.distance_m),
            ("speed_m_s", &ws.speed_m_s),
        ] {
            assert!(s.iter().all(|v| v.is_finite()), "wheelset_{i}/{name}");
            n += s.len();
        }
        for (k, wheel) in ws.wheels.iter().enumerate() {
            assert!(wheel.travelled_m.iter().all(|v| v.is_finite()));
            for j in 0..r.len() {
                let any = wheel.zones.iter().any(|z| z.in_contact[j] == 1);
                assert_eq!(wheel.q_n[j].is_finite(), any, "wheel {k} Q at {j}");
                assert_eq!(wheel.y_n[j].is_finite(), any, "wheel {k} Y at {j}");
                assert_eq!(
                    wheel.y_over_q[j].is_finite(),
                    any && wheel.q_n[j] > 0.0,
                    "wheel {k} Y/Q at {j}"
                );
                for (z, zone) in wheel.zones.iter().enumerate() {
                    let s = zone.sample(j).expect("sample");
                    let values = [
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
                    ];
                    if s.in_contact {
                        assert!(
                            values.iter().all(|v| v.is_finite()),
                            "wheelset_{i} wheel {k} zone {z} sample {j}: {s:?}"
                        );
                        assert!(s.normal_n >= 0.0, "N < 0: {s:?}");
                    } else {
                        assert!(values.iter().all(|v| v.is_nan()), "{s:?}");
                    }
                    n += values.len();
                }
            }
        }
    }
    n
}

/// Mean of the finite values of `v` at samples with t ≥ `from_s`.
fn mean_from(t: &[f64], v: &[f64], from_s: f64) -> f64 {
    let x: Vec<f64> = t
        .iter()
        .zip(v)
        .filter(|(t, v)| **t >= from_s && v.is_finite())
        .map(|(_, v)| *v)
        .collect();
    assert!(!x.is_empty(), "no finite values after {from_s} s");
    x.iter().sum::<f64>() / x.len() as f64
}

/// A wheelset pushed into its left (`force_n` > 0) or right flange by a
/// constant lateral force, its yaw held near `yaw_rad` by the `[load]` yaw
/// spring (5 MN·m/rad), started 6.8 mm towards that flange, 0.4 s at
/// 10 m/s.
fn flanging(dir: &Path, name: &str, force_n: f64, yaw_rad: f64) -> Run {
    let f = format!("load.lateral_force_n={force_n}");
    let y = format!("load.yaw_angle_rad={yaw_rad}");
    let y0 = format!("initial.lateral_m={}", 0.0068 * force_n.signum());
    sim_run(
        dir,
        name,
        &[
            "run.duration_s=0.4",
            "contact.flange=on",
            "load.yaw_stiffness_nm_rad=5e6",
            &f,
            &y,
            &y0,
        ],
    )
}

/// Lead/lag of the flanging wheel (0 left, 1 right) of a [`flanging`] run
/// after 0.2 s, checked against the sign rule and the geometry of a yawed
/// cone: the flange point leads the axle by r·tan γ·tan ψ (γ the contact
/// angle, ψ the yaw towards the flange's rail), so it has the sign of the
/// yaw on the left wheel and the opposite sign on the right one; the tread
/// point stays near the axle. Returns the mean flange lead (m).
fn check_two_point_lead(r: &Run, wheel: usize) -> f64 {
    let res = r.results();
    let ws = &res.wheelsets[0];
    let w = &ws.wheels[wheel];
    let (tread, flange) = (&w.zones[0], &w.zones[1]);
    let late: Vec<usize> = (0..res.len()).filter(|&j| res.time_s[j] >= 0.2).collect();
    let both = late
        .iter()
        .filter(|&&j| tread.in_contact[j] == 1 && flange.in_contact[j] == 1)
        .count();
    assert!(
        both * 10 >= late.len() * 9,
        "{}: two-point contact at {both} of {} samples",
        r.name,
        late.len()
    );
    let towards = if wheel == 0 { 1.0 } else { -1.0 };
    let mut leads = Vec::new();
    for &j in &late {
        if flange.in_contact[j] == 0 {
            continue;
        }
        let (lead, psi) = (flange.lead_m[j], ws.yaw_rad[j]);
        assert!(psi.abs() > 2e-3, "{}: yaw {psi} too small", r.name);
        assert_eq!(
            lead.signum(),
            towards * psi.signum(),
            "{}: flange lead {lead} m at yaw {psi} rad breaks the sign rule",
            r.name
        );
        let radius = lead / (flange.contact_angle_rad[j].tan() * (towards * psi).tan());
        assert!(
            (0.42..0.47).contains(&radius),
            "{}: lead {lead} m = r tan γ tan ψ gives r = {radius} m",
            r.name
        );
        if tread.in_contact[j] == 1 {
            assert!(tread.lead_m[j].abs() < 0.05 * lead.abs(), "{}", r.name);
        }
        leads.push(lead);
    }
    leads.iter().sum::<f64>() / leads.len() as f64
}

#[test]
fn contact_nadal_quotient_rises_with_the_lateral_load() {
    let dir = scratch("extremes_contact_nadal");
    let mut previous = 0.0;
    eprintln!("lateral force (kN) | mean Y/Q | max Y/Q | max 2 m mean | Y_L − Y_R (kN)");
    for (force_n, risk) in [(2.5e3, false), (5e3, false), (10e3, false), (20e3, true)] {
        let r = flanging(&dir, &format!("nadal_{force_n}"), force_n, 0.005);
        let res = r.results();
        let (t, left, right) = (
            &res.time_s,
            &res.wheelsets[0].wheels[0],
            &res.wheelsets[0].wheels[1],
        );
        let mean_yq = mean_from(t, &left.y_over_q, 0.2);
        // Lateral balance of the wheelset (the load against the rails):
        // Y is + towards the track centre, so Y_left − Y_right = F.
        let balance: Vec<f64> = left
            .y_n
            .iter()
            .zip(&right.y_n)
            .map(|(l, r)| l - if r.is_finite() { *r } else { 0.0 })
            .collect();
        let mean_balance = mean_from(t, &balance, 0.2);
        let nadal = r.nadal(0);
        let max = nadal["max_y_over_q"].as_f64().expect("max");
        let max_2m = nadal["max_y_over_q_2m"].as_f64().expect("2 m mean");
        eprintln!(
            "{:5.1} | {mean_yq:.3} | {max:.3} | {max_2m:.3} | {:.3}",
            force_n / 1e3,
            mean_balance / 1e3
        );
        assert!(
            (mean_balance - force_n).abs() < 0.01 * force_n,
            "{}: Y_L − Y_R = {mean_balance} N against F = {force_n} N",
            r.name
        );
        assert!(mean_yq > previous, "Y/Q must rise with the load");
        previous = mean_yq;
        let limit = nadal["nadal_limit"].as_f64().expect("limit");
        assert!((limit - NADAL_70).abs() < 1e-3, "{limit}");
        let gamma = nadal["flange_angle_deg"].as_f64().expect("angle");
        assert!((gamma - 70.0).abs() < 0.05, "{gamma}");
        assert_eq!(nadal["derailment_risk"].as_bool(), Some(risk), "{}", r.name);
        assert_eq!(mean_yq > limit, risk, "{}: mean Y/Q {mean_yq}", r.name);
        // The same in the results file.
        let stored = left.nadal.expect("the wheel's Nadal limit is stored");
        assert!((stored.limit - limit).abs() < 1e-12);
        assert_eq!(
            res.attribute("rejected_steps").and_then(|v| v.as_i64()),
            Some(0)
        );
        assert!(res.attribute("steps").is_some());
        check_two_point_lead(&r, 0);
    }
}

#[test]
fn contact_two_point_lead_and_lag_follow_the_sign_rule() {
    let dir = scratch("extremes_contact_lead");
    // Left flange, nose left: the flange point leads; nose right: it lags.
    let lead = check_two_point_lead(&flanging(&dir, "left_lead", 5e3, 0.005), 0);
    let lag = check_two_point_lead(&flanging(&dir, "left_lag", 5e3, -0.005), 0);
    // Right flange, nose right: it leads.
    let right = check_two_point_lead(&flanging(&dir, "right_lead", -5e3, -0.005), 1);
    eprintln!(
        "flange lead: left +5 mrad {:.2} mm, left −5 mrad {:.2} mm, right −5 mrad {:.2} mm",
        lead * 1e3,
        lag * 1e3,
        right * 1e3
    );
    assert!(lead > 0.0 && lag < 0.0 && right > 0.0);
}

#[test]
fn contact_flange_climb_stops_cleanly_with_a_diagnostic() {
    let dir = scratch("extremes_contact_climb");
    // 25 kN against 7 kN of wheel load at a 40 mrad angle of attack.
    let r = sim_run(
        &dir,
        "climb",
        &[
            "run.duration_s=1.0",
            "contact.flange=on",
            "initial.lateral_m=0.0068",
            "load.lateral_force_n=25000",
            "load.yaw_stiffness_nm_rad=5e6",
            "load.yaw_angle_rad=0.04",
        ],
    );
    assert!(r.summary.is_none(), "the wheel must climb off its rail");
    for needle in [
        "the run failed at t = ",
        "derailed",
        "wheelset 'wheelset'",
        "y = +",
        "yaw = ",
        "roll = ",
        "height = ",
        "the results so far are in",
    ] {
        assert!(r.stderr.contains(needle), "{needle} missing:\n{}", r.stderr);
    }
    // The wheel rose on its flange before it left the rail.
    let height_mm: f64 = r
        .stderr
        .split("height = ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .expect("height in the diagnostic");
    assert!(height_mm > 435.0, "height {height_mm} mm");
    let res = r.results();
    let status = res.attribute_text("status").expect("status");
    assert!(status.starts_with("failed:"), "{status}");
    let diag = res
        .attribute_text("diagnostic")
        .expect("diagnostic attribute");
    assert!(diag.contains("derailed") && diag.contains("y = "), "{diag}");
    assert!(res.attribute("steps").is_some());
    let left = &res.wheelsets[0].wheels[0];
    let max = left.max_y_over_q().expect("Y/Q");
    eprintln!(
        "climb: max Y/Q {max:.3} (limit {NADAL_70}), height at the end {height_mm} mm; {}",
        r.stderr.lines().next().unwrap_or("")
    );
    assert!(max > NADAL_70);
}

/// Flight times of a bouncing wheel from its tread's contact flags: the
/// time of the first impact and the durations between contact episodes.
fn flights(t: &[f64], in_contact: &[u8]) -> (f64, Vec<f64>) {
    let mut first = None;
    let mut flights = Vec::new();
    let mut left_at = None;
    for j in 1..t.len() {
        match (in_contact[j - 1], in_contact[j]) {
            (0, 1) => {
                if first.is_none() {
                    first = Some(t[j]);
                }
                if let Some(l) = left_at.take() {
                    flights.push(t[j] - l);
                }
            }
            (1, 0) => left_at = Some(t[j]),
            _ => {}
        }
    }
    (first.expect("an impact"), flights)
}

#[test]
fn contact_wheel_drop_loses_and_regains_contact() {
    let dir = scratch("extremes_contact_drop");
    let h = 0.003;
    let t0 = (2.0 * h / G_M_S2).sqrt();
    let mut ratios = Vec::new();
    for e in [1.0, 0.9] {
        // At standstill, without creep: a vertical bounce on both treads.
        let r = sim_run(
            &dir,
            &format!("drop_e{e}"),
            &[
                "run.duration_s=0.2",
                "run.output_interval_s=2.5e-4",
                "initial.speed_m_s=0",
                "initial.lateral_m=0",
                "contact.creep_law=none",
                &format!("contact.restitution={e}"),
                &format!("perturbation.drop_m={h}"),
            ],
        );
        let res = r.results();
        let tread = &res.wheelsets[0].wheels[0].zones[0];
        assert_eq!(tread.in_contact[0], 0, "lifted at the start");
        let (impact, flight) = flights(&res.time_s, &tread.in_contact);
        assert!(
            (impact - t0).abs() < 1e-3,
            "first impact {impact} s, free fall {t0} s"
        );
        assert!(flight.len() >= 2, "contact lost and regained: {flight:?}");
        // Rebound: a flight after the impact lasts 2 v1/g, the fall 2 v0/g.
        let ratio = flight[0] / (2.0 * t0);
        ratios.push(ratio);
        let (e0, e1) = (r.energy("initial_j"), r.energy("final_j"));
        let damping = r.energy("contact_damping_dissipation_j");
        let potential = MASS_KG * G_M_S2 * h;
        eprintln!(
            "drop e = {e}: impact at {:.2} ms (free fall {:.2} ms), rebound flight ratio {ratio:.3}, E {e0:.3} → {e1:.3} J, contact damping {damping:.3} J of m g h = {potential:.1} J, residual {:.2e} J",
            impact * 1e3,
            t0 * 1e3,
            r.energy("residual_j")
        );
        assert!(r.energy("residual_j").abs() < 1e-3 * potential);
        if e == 1.0 {
            assert!((e1 - e0).abs() < 1e-3 * potential, "{e0} → {e1}");
            assert_eq!(damping, 0.0);
            assert!((0.97..1.02).contains(&ratio), "{ratio}");
        } else {
            assert!(damping > 0.0 && e1 < e0);
            // The hysteresis model's rebound at e = 0.9 (docs/guide/creep-curves.md: 0.913).
            assert!((0.86..0.95).contains(&ratio), "{ratio}");
        }
    }
    assert!(ratios[1] < ratios[0]);
    // Rolling at 10 m/s with creep: the drop still lands cleanly.
    let r = sim_run(
        &dir,
        "drop_rolling",
        &["run.duration_s=0.2", "perturbation.drop_m=0.003"],
    );
    let res = r.results();
    let (_, flight) = flights(&res.time_s, &res.wheelsets[0].wheels[1].zones[0].in_contact);
    assert!(!flight.is_empty());
}

#[test]
fn contact_lateral_impact_on_the_flange() {
    let dir = scratch("extremes_contact_impact");
    let v = 0.3;
    for e in [1.0, 0.5] {
        // Frictionless (no creep law): the flange pushes back along its
        // normal only, so Y/Q at the impact is tan γ of the flank.
        let r = sim_run(
            &dir,
            &format!("impact_e{e}"),
            &[
                "run.duration_s=0.15",
                "run.output_interval_s=5e-4",
                "initial.lateral_m=0",
                "contact.flange=on",
                "contact.creep_law=none",
                &format!("contact.restitution={e}"),
                &format!("perturbation.lateral_velocity_m_s={v}"),
            ],
        );
        let res = r.results();
        let ws = &res.wheelsets[0];
        let flange = &ws.wheels[0].zones[1];
        assert!(flange.in_contact.contains(&1), "no flange impact");
        let y_max = ws.lateral_m.iter().copied().fold(f64::MIN, f64::max);
        let y_end = *ws.lateral_m.last().expect("samples");
        assert!(y_end < y_max - 5e-4, "the wheelset must bounce back");
        let max_yq = ws.wheels[0].max_y_over_q().expect("Y/Q");
        let tan_gamma = (70f64 * PI / 180.0).tan();
        let (e0, e1) = (r.energy("initial_j"), r.energy("final_j"));
        let damping = r.energy("contact_damping_dissipation_j");
        let lateral_ke = 0.5 * MASS_KG * v * v;
        eprintln!(
            "impact e = {e}: peak y {:.2} mm, max Y/Q {max_yq:.3} (tan 70° = {tan_gamma:.3}), E {e0:.3} → {e1:.3} J, contact damping {damping:.2} J of ½mv² = {lateral_ke:.1} J",
            y_max * 1e3
        );
        assert!((max_yq / tan_gamma - 1.0).abs() < 0.03, "{max_yq}");
        assert!(r.energy("residual_j").abs() < 1e-3 * lateral_ke);
        if e == 1.0 {
            assert!((e1 - e0).abs() < 1e-3 * lateral_ke, "{e0} → {e1}");
        } else {
            assert!(damping > 0.1 * lateral_ke && e1 < e0);
        }
    }
}

/// A wheel profile (CSV, y_mm,z_mm, the toolkit's convention: flange at
/// negative y, z up) with a 1:20 tread, a 10 mm concave throat, a straight
/// flank at `flank_deg` to the horizontal, an 8 mm tip 28 mm below the
/// tread and an 85° back face; the flank passes 10 mm below the tread at
/// y = −39.5 mm (the ML95-like wheel's flange thickness, to within a
/// millimetre). Walked from the field side in steps of `step_mm` of arc
/// length along its curvature: θ the descent angle, dy = −cos θ ds,
/// dz = −sin θ ds.
fn flange_profile_csv(flank_deg: f64, step_mm: f64) -> String {
    let gamma = flank_deg.to_radians();
    let cone = 0.05f64.atan();
    let back = -(85f64.to_radians());
    let (r_throat, r_tip, depth) = (10.0, 8.0, 28.0);
    let mut y_throat = -25.0;
    let mut points = Vec::new();
    for _ in 0..4 {
        points.clear();
        let z_throat = y_throat / 20.0;
        let flank =
            (z_throat - r_throat * (cone.cos() - gamma.cos()) - r_tip * (1.0 - gamma.cos())
                + depth)
                / gamma.sin();
        let n = ((65.0 - y_throat) / 0.5).ceil() as usize;
        for k in 0..=n {
            let y = 65.0 - (65.0 - y_throat) * k as f64 / n as f64;
            points.push((y, y / 20.0));
        }
        let (mut y, mut z, mut theta) = (y_throat, z_throat, cone);
        let mut walk = |length: f64, curvature: f64, points: &mut Vec<(f64, f64)>| {
            let m = (length / step_mm).ceil().max(1.0) as usize;
            let h = length / m as f64;
            for _ in 0..m {
                let mid = theta + 0.5 * h * curvature;
                y -= mid.cos() * h;
                z -= mid.sin() * h;
                theta += h * curvature;
                points.push((y, z));
            }
        };
        walk(r_throat * (gamma - cone), 1.0 / r_throat, &mut points);
        walk(flank, 0.0, &mut points);
        walk(r_tip * (gamma - back), -1.0 / r_tip, &mut points);
        let z_tip_end = points.last().expect("points").1;
        walk(-z_tip_end / (-back).sin(), 0.0, &mut points);
        // Shift the flange so that the flank crosses z = −10 mm at −39.5.
        let crossing = points
            .windows(2)
            .find(|w| w[0].1 > -10.0 && w[1].1 <= -10.0)
            .expect("the flank crosses z = -10 mm")[1]
            .0;
        y_throat += -39.5 - crossing;
    }
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    points.dedup_by(|b, a| b.0 - a.0 < 1e-6);
    let mut csv = String::from("y_mm,z_mm\n");
    for (y, z) in points {
        csv += &format!("{y:.6},{z:.6}\n");
    }
    csv
}

/// The ML95-like wheel with a worn, hollow tread: around y = 2.5 mm (the
/// contact of the centred wheelset on its 1:20 rail) its radius grows by
/// h(s) = a w/(2R) − s²/(2R) for |s| < a = 8 mm (concave, radius R), then
/// recovers convexly to the cone at |s| = w = 16 mm (h and h' continuous).
/// With R near the rail head's 300 mm crown the contact is conformal.
fn hollow_profile_csv(radius_mm: f64) -> String {
    let (yc, a, w) = (2.5, 8.0, 16.0);
    let k2 = a / (radius_mm * (w - a));
    let h0 = a * w / (2.0 * radius_mm);
    let hollow = |y: f64| {
        let s = (y - yc).abs();
        if s >= w {
            0.0
        } else if s < a {
            h0 - s * s / (2.0 * radius_mm)
        } else {
            h0 - a * a / (2.0 * radius_mm) - a / radius_mm * (s - a) + 0.5 * k2 * (s - a).powi(2)
        }
    };
    let shipped_csv =
        std::fs::read_to_string(shipped("profiles/ml95_like/ml95_like_wheel.csv")).expect("ML95");
    let mut points: Vec<(f64, f64)> = shipped_csv
        .lines()
        .skip(1)
        .map(|l| {
            let (y, z) = l.split_once(',').expect("y,z");
            (y.parse().expect("y"), z.parse().expect("z"))
        })
        .filter(|(y, _)| !(yc - w - 1.0 < *y && *y < yc + w + 1.0))
        .collect();
    let n = (2.0 * (w + 1.0) / 0.25).round() as usize;
    for k in 0..=n {
        let y = yc - w - 1.0 + 0.25 * k as f64;
        points.push((y, y / 20.0));
    }
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    points.dedup_by(|b, a| b.0 - a.0 < 1e-4);
    let mut csv = String::from("y_mm,z_mm\n");
    for (y, z) in points {
        csv += &format!("{y:.6},{:.6}\n", z + hollow(y));
    }
    csv
}

/// A copy of the ML95-like wheelset's vehicle file with another wheel
/// profile.
fn vehicle_with_wheel(dir: &Path, name: &str, profile_csv: &str) -> PathBuf {
    let profile = dir.join(format!("{name}.csv"));
    std::fs::write(&profile, profile_csv).expect("write the profile");
    let text = std::fs::read_to_string(shipped("vehicles/ml95_like_wheelset.toml"))
        .expect("vehicle file")
        .replace(
            "../profiles/ml95_like/ml95_like_wheel.csv",
            &profile.display().to_string(),
        );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).expect("write the vehicle");
    path
}

/// `sim contact --json` of a wheel profile on the scenes' rail (UIC60,
/// 1:40 in the file, declared, + 1:40), R0 0.43 m.
fn sim_contact(wheel: &Path, extra: &[&str]) -> std::process::Output {
    run(sim()
        .arg("contact")
        .arg("--wheel")
        .arg(wheel)
        .arg("--rail")
        .arg(shipped("profiles/MBench_UIC60_v3.prr"))
        .args([
            "--rail-inclination",
            "1:40",
            "--rail-profile-cant",
            "1:40",
            "--wheel-radius",
            "0.43",
            "--json",
        ])
        .args(extra))
}

#[test]
fn contact_near_vertical_flange() {
    let dir = scratch("extremes_contact_steep");
    // 79.5°: just inside the importer's 80° trim angle.
    let steep = dir.join("flank_79.5.csv");
    std::fs::write(&steep, flange_profile_csv(79.5, 0.02)).expect("write");
    // The contact search's point (the deepest) lies on the flank, at its
    // angle; the patch centre (the default of `sim contact`) is the centroid
    // of the interpenetration, which reaches the flank's root fillet, so its
    // angle is a little smaller (docs/reference/06-contact-detection.md §6.9).
    for (location, tolerance_deg) in [("deepest", 0.3), ("centre", 1.0)] {
        let o = sim_contact(
            &steep,
            &[
                "--y-mm",
                "7.5",
                "--yaw-mrad",
                "5",
                "--patch-location",
                location,
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let json: Value = serde_json::from_str(&stdout(&o)).expect("JSON");
        let flange = json["wheels"][0]["contacts"]
            .as_array()
            .expect("contacts")
            .iter()
            .find(|c| c["zone"] == "flange")
            .expect("a flange contact at 7.5 mm")
            .clone();
        let angle = flange["contact_angle_rad"]
            .as_f64()
            .expect("angle")
            .to_degrees();
        let normal = flange["normal_n"].as_f64().expect("N");
        eprintln!(
            "79.5° flank at y = 7.5 mm ({location}): contact angle {angle:.2}°, N {normal:.0} N"
        );
        assert!((angle - 79.5).abs() < tolerance_deg, "{location}: {angle}");
        assert!(normal.is_finite() && normal > 0.0);
    }

    // A run pushed into that flange: completes, contact at the flank angle.
    let vehicle = vehicle_with_wheel(&dir, "steep", &flange_profile_csv(79.5, 0.02));
    let r = sim_run(
        &dir,
        "steep_run",
        &[
            &format!("vehicle.file={}", vehicle.display()),
            "run.duration_s=0.4",
            "initial.lateral_m=0",
            "load.lateral_force_n=15000",
            "load.yaw_stiffness_nm_rad=5e6",
            "load.yaw_angle_rad=0.005",
        ],
    );
    let res = r.results();
    let max_angle = res.wheelsets[0].wheels[0].zones[1]
        .contact_angle_rad
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(f64::MIN, f64::max)
        .to_degrees();
    let limit = r.nadal(0)["nadal_limit"].as_f64().expect("limit");
    let t = 79.5f64.to_radians().tan();
    eprintln!(
        "79.5° run: largest flange contact angle {max_angle:.2}°, Nadal limit {limit:.3}, max Y/Q {}",
        r.nadal(0)["max_y_over_q"]
    );
    assert!((max_angle - 79.5).abs() < 0.5, "{max_angle}");
    assert!(
        (limit - (t - 0.3) / (1.0 + 0.3 * t)).abs() < 5e-3,
        "{limit}"
    );

    // Steeper flanks are outside the model: refused with a clear error,
    // never imported without their flange.
    for (deg, step) in [(85.0, 0.5), (89.0, 0.5)] {
        let path = dir.join(format!("flank_{deg}.csv"));
        std::fs::write(&path, flange_profile_csv(deg, step)).expect("write");
        let o = sim_contact(&path, &["--y-mm", "9"]);
        let err = stderr(&o);
        eprintln!("{deg}° flank: {}", err.lines().next().unwrap_or(""));
        assert!(!o.status.success());
        assert!(err.contains(&path.display().to_string()), "{err}");
        assert!(
            err.contains("would lose its flange") || err.contains("steeper than 80°"),
            "{err}"
        );
    }
}

/// A worn, hollow tread of radius 301 mm on the 300 mm rail crown: nearly
/// conformal (B = ½(1/0.300 − 1/0.301) ≈ 0.006 1/m inside the hollow, and
/// the spline's curvature ripple makes it negative at places). Those places
/// are maxima of the gap between two minima, not contacts: the search
/// reports the minima, where the hollow meets its convex recovery and the
/// relative curvature is clearly positive (docs/reference/06-contact-detection.md
/// §6.1, §6.7). Before issue 13 the search kept a maximum (B = −0.54 1/m
/// on the left wheel of the centred wheelset, while the right wheel, at
/// the mirrored pose, had B = +1.87 1/m), and a run stopped there as
/// non-Hertzian. Now every contact is Hertzian: the run with
/// `non_hertzian = "stop"` goes through, with no floored contact, and
/// `sim contact` gives the centred wheelset mirrored contacts.
#[test]
fn contact_nearly_conformal_worn_tread() {
    let dir = scratch("extremes_contact_conformal");
    let vehicle = vehicle_with_wheel(&dir, "hollow301", &hollow_profile_csv(301.0));
    let vehicle_set = format!("vehicle.file={}", vehicle.display());
    let scene = [
        vehicle_set.as_str(),
        "run.duration_s=2",
        "initial.lateral_m=-0.004",
        "contact.non_hertzian=stop",
    ];
    let r = sim_run(&dir, "conformal_stop", &scene);
    assert!(r.summary.is_some(), "the run stopped:\n{}", r.stderr);
    let f = &r.summary()["fallbacks"];
    assert_eq!(f["hertz_floor_evaluations"].as_u64(), Some(0), "{f}");

    // `sim contact`: finite Hertzian contacts at every pose, B > 0; the
    // centred wheelset's two contacts mirror each other.
    let profile = dir.join("hollow301.csv");
    for y in [-1.0, -0.5, 0.0, 0.5, 1.0] {
        let o = sim_contact(
            &profile,
            &["--y-mm", &format!("{y}"), "--wheel-load-n", "7000"],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let json: Value = serde_json::from_str(&stdout(&o)).expect("JSON");
        let mut per_wheel = Vec::new();
        for w in json["wheels"].as_array().expect("wheels") {
            let contacts = w["contacts"].as_array().expect("contacts");
            assert_eq!(contacts.len(), 1, "y = {y}: {w}");
            let c = &contacts[0];
            assert!(c["force_error"].is_null(), "y = {y}: {c}");
            let b = c["wheel_lateral_curvature_1_m"].as_f64().expect("κ_w")
                + c["rail_lateral_curvature_1_m"].as_f64().expect("κ_r");
            assert!(b > 0.1, "y = {y}: B = {b}");
            for key in ["normal_n", "a_m", "b_m", "penetration_m"] {
                let v = c[key].as_f64().unwrap_or(f64::NAN);
                assert!(v.is_finite(), "{key} at y = {y}: {c}");
            }
            per_wheel.push((c["y_wheel_mm"].as_f64().expect("y"), b));
        }
        eprintln!("hollow 301 mm at y = {y} mm: (wheel y mm, 2B 1/m) {per_wheel:?}");
        if y == 0.0 {
            let (l, r) = (per_wheel[0], per_wheel[1]);
            assert!(
                (l.0 - r.0).abs() < 1e-6 && (l.1 - r.1).abs() < 1e-6,
                "{per_wheel:?}"
            );
        }
    }
}

#[test]
fn contact_soft_and_stiff_materials() {
    let dir = scratch("extremes_contact_materials");
    // Hertz at a fixed load: δ ∝ E^(-2/3) (docs/reference/07-contact-forces.md §7.1), the semi-axes ∝ E^(-1/3).
    let ml95 = shipped("profiles/ml95_like/ml95_like_wheel.csv");
    let mut rows = Vec::new();
    for young in [1e9_f64, 1e10, 2.1e11, 1e12, 1e13] {
        let o = sim_contact(&ml95, &["--young-pa", &format!("{young:e}")]);
        assert!(o.status.success(), "{}", stderr(&o));
        let json: Value = serde_json::from_str(&stdout(&o)).expect("JSON");
        let c = &json["wheels"][0]["contacts"][0];
        rows.push((
            young,
            c["penetration_m"].as_f64().expect("δ"),
            c["a_m"].as_f64().expect("a"),
        ));
    }
    let (e_ref, d_ref, a_ref) = rows[2];
    for &(young, delta, a) in &rows {
        let s = young / e_ref;
        eprintln!(
            "E = {young:.0e} Pa: δ = {:.4} mm ({:.5} of E^(-2/3) scaling), a = {:.3} mm",
            delta * 1e3,
            delta / (d_ref * s.powf(-2.0 / 3.0)),
            a * 1e3
        );
        assert!((delta / (d_ref * s.powf(-2.0 / 3.0)) - 1.0).abs() < 1e-3);
        assert!((a / (a_ref * s.powf(-1.0 / 3.0)) - 1.0).abs() < 1e-3);
    }
    // A scene refuses moduli outside the plausible 50–500 GPa (a unit
    // slip: src/config/scene.rs YOUNG_PA_RANGE); short runs at both ends of
    // that range (DOPRI5 adapts its step to the contact stiffness).
    for young in ["1e9", "1e13"] {
        let o = run(sim()
            .env("RAILSIM_CACHE_DIR", dir.join("cache"))
            .arg("run")
            .arg(shipped("scenes/wheelset_straight.toml"))
            .args(["--no-plots", "-o"])
            .arg(dir.join("refused.h5"))
            .args(["--set", &format!("contact.young_pa={young}")]));
        assert!(!o.status.success(), "E = {young} Pa");
        assert!(stderr(&o).contains("check the unit"), "{}", stderr(&o));
    }
    for young in ["5e10", "5e11"] {
        let r = sim_run(
            &dir,
            &format!("young_{young}"),
            &[
                "run.duration_s=0.2",
                "run.integrator=dopri5",
                &format!("contact.young_pa={young}"),
            ],
        );
        let s = r.summary();
        eprintln!(
            "E = {young} Pa: DOPRI5 {} steps, {} rejected",
            s["steps"], s["rejected_steps"]
        );
        assert!(s["steps"].as_u64().is_some_and(|n| n > 0));
    }
}
