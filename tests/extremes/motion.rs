//! Motion extremes (issue 7, part C): starting from rest and stopping,
//! speeds from 0.1 to 120 m/s, friction from 0.05 to 0.6, restitution from
//! 0.1 to 1, traction and braking creep far into saturation. Every case is
//! `sim run` on a shipped scene (tables/scenes/wheelset_straight.toml, the
//! ML95-like unsuspended wheelset, or bogie_straight.toml, the ML95-like
//! bogie under a track-following car body share) with `--set` overrides, on
//! an ideal straight tabulated in memory, integrated by DOPRI5 (its step and
//! rejection counts are printed: `cargo test --test extremes motion --
//! --nocapture`; the module takes about 16 s in the dev profile, one test
//! thread). Every run keeps:
//!
//! - no panic, a completed run, and no NaN or infinity in any float dataset
//!   of its results file except where the schema writes NaN for "no
//!   contact" ([`check_results_finite`]);
//! - its energy balance (`runtime::multibody::EnergyLedger`,
//!   reported by `sim run --json`): E − E0 = axle torque work + reference
//!   work + element turning work − creep, contact damping and damper
//!   dissipation, up to a residual ≤ 2e-3 of the largest term + 0.05 J.
//!
//! Figures of the ML95-like wheelset (tables/vehicles/ml95_like_wheelset.toml):
//! m = 1430 kg, spin inertia I = 82 kg·m², r₀ = 0.43 m; a torque T about
//! the axle rolls it (no slip) at dV/dt = T / (r₀ (m + I/r₀²)) (Newton for
//! the translation and the spin, with the creep force as the unknown
//! coupling: m V̇ = F, I Ω̇ = T − r₀ F, V = r₀ Ω).

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common::*;

/// Mass (kg), spin inertia (kg·m²) and nominal rolling radius (m) of the
/// ML95-like wheelset.
const MASS_KG: f64 = 1430.0;
const SPIN_INERTIA_KG_M2: f64 = 82.0;
const R0_M: f64 = 0.43;
/// Static load per wheel of the unsuspended wheelset (N): m g / 2, the
/// wheelset vehicle file's gravity (9.81 m/s²).
const WHEEL_LOAD_N: f64 = 0.5 * MASS_KG * 9.81;
/// Friction coefficient of the shipped scenes.
const MU: f64 = 0.3;

/// Translational mass equivalent of a rolling wheelset, m + I/r₀² (kg).
fn rolling_mass_kg() -> f64 {
    MASS_KG + SPIN_INERTIA_KG_M2 / (R0_M * R0_M)
}

/// A finished run: its `--json` summary and results file.
struct Run {
    name: String,
    summary: Value,
    h5: PathBuf,
}

/// `sim run` of a shipped scene (`scenes/…`) on an ideal 60 m straight
/// with DOPRI5 and `overrides`; asserts a completed run and prints the
/// integrator's counts.
fn sim_run(dir: &Path, name: &str, scene: &str, overrides: &[&str]) -> Run {
    let h5 = dir.join(format!("{name}.h5"));
    let mut cmd = sim();
    cmd.env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .arg("run")
        .arg(shipped(scene))
        .arg("-o")
        .arg(&h5)
        .args(["--no-plots", "--json"]);
    let base = [
        "track.centerline=",
        "track.straight_m=60",
        "run.distance_m=",
        "run.integrator=dopri5",
    ];
    for o in base.iter().chain(overrides) {
        cmd.args(["--set", o]);
    }
    let o = run(&mut cmd);
    assert!(o.status.success(), "{name}: sim run failed\n{}", stderr(&o));
    let summary: Value = serde_json::from_str(&stdout(&o)).expect("JSON summary");
    assert!(summary["error"].is_null(), "{name}: {}", summary["error"]);
    assert!(
        summary["stopped"].is_null(),
        "{name}: stopped early: {}",
        summary["stopped"]
    );
    eprintln!(
        "{name}: {} {} steps, {} rejected, {} evaluations, {:.2} s wall for {} s",
        summary["integrator"].as_str().unwrap_or("?"),
        summary["steps"],
        summary["rejected_steps"],
        summary["rhs_evaluations"],
        summary["wall_time_s"].as_f64().unwrap_or(f64::NAN),
        summary["simulated_time_s"]
    );
    assert!(summary["steps"].as_u64().is_some_and(|s| s > 0));
    let r = Run {
        name: name.to_string(),
        summary,
        h5,
    };
    check_results_finite(&r.h5);
    r.check_energy();
    r
}

impl Run {
    /// A term of the energy summary (J).
    fn energy(&self, key: &str) -> f64 {
        self.summary["energy"][key]
            .as_f64()
            .unwrap_or_else(|| panic!("{}: energy.{key} missing", self.name))
    }

    /// The balance closes (module docs).
    fn check_energy(&self) {
        let terms = [
            "axle_torque_work_j",
            "reference_work_j",
            "element_turning_work_j",
            "creep_dissipation_j",
            "contact_damping_dissipation_j",
            "damper_dissipation_j",
        ];
        let scale = terms
            .iter()
            .map(|k| self.energy(k).abs())
            .fold(0.0, f64::max);
        for k in &terms[3..] {
            assert!(self.energy(k) >= 0.0, "{}: {k} < 0", self.name);
        }
        let residual = self.energy("residual_j");
        eprintln!(
            "{}: energy residual {residual:.3e} J against {scale:.3e} J",
            self.name
        );
        assert!(
            residual.abs() <= 2e-3 * scale + 0.05,
            "{}: energy residual {residual} J, largest term {scale} J: {}",
            self.name,
            self.summary["energy"]
        );
    }

    /// A float series (`wheelset_0/speed_m_s`, …).
    fn series(&self, name: &str) -> Vec<f64> {
        hdf5::File::open(&self.h5)
            .expect("results open")
            .dataset(name)
            .unwrap_or_else(|e| panic!("{}: {name}: {e}", self.name))
            .read_raw()
            .expect("f64 series")
    }

    fn time_s(&self) -> Vec<f64> {
        self.series("time_s")
    }

    fn wheelsets(&self) -> usize {
        self.summary["wheelsets"].as_array().map_or(0, Vec::len)
    }
}

/// Walks every dataset of a results file: every float value finite, except
/// where the schema writes NaN for "no contact" (`runtime::results`)
/// — in a zone group at the samples where `in_contact` is 0, and in a
/// wheel group at the samples where no zone carries a positive normal
/// force (Y, Q, Y/Q). Infinity never. Returns the number of values checked.
fn check_results_finite(path: &Path) -> usize {
    fn flags(g: &hdf5::Group, zone: &str) -> Option<Vec<bool>> {
        let z = g.group(zone).ok()?;
        let c: Vec<u8> = z.dataset("in_contact").ok()?.read_raw().ok()?;
        let n: Vec<f64> = z.dataset("normal_n").ok()?.read_raw().ok()?;
        Some(c.iter().zip(&n).map(|(c, n)| *c == 1 && *n > 0.0).collect())
    }
    fn walk(g: &hdf5::Group, zone: Option<&[u8]>, wheel: Option<&[bool]>, n: &mut usize) {
        for name in g.member_names().expect("members") {
            if let Ok(sub) = g.group(&name) {
                let zone_flags: Option<Vec<u8>> = sub
                    .dataset("in_contact")
                    .ok()
                    .map(|d| d.read_raw().expect("in_contact"));
                let wheel_flags = match (flags(&sub, "tread"), flags(&sub, "flange")) {
                    (Some(a), Some(b)) => {
                        Some(a.iter().zip(&b).map(|(a, b)| *a || *b).collect::<Vec<_>>())
                    }
                    (a, b) => a.or(b),
                };
                walk(
                    &sub,
                    zone_flags.as_deref(),
                    wheel_flags.as_deref().or(wheel),
                    n,
                );
                continue;
            }
            let ds = g.dataset(&name).expect("a dataset");
            if !matches!(
                ds.dtype().and_then(|t| t.to_descriptor()),
                Ok(hdf5::types::TypeDescriptor::Float(_))
            ) {
                continue;
            }
            let values: Vec<f64> = ds.read_raw().expect("floats");
            for (i, v) in values.iter().enumerate() {
                assert!(!v.is_infinite(), "{} sample {i}: {v}", ds.name());
                let nan_allowed = match zone {
                    Some(z) => z.get(i) == Some(&0),
                    None => wheel.is_some_and(|w| w.get(i) == Some(&false)),
                };
                assert!(
                    v.is_finite() || nan_allowed,
                    "{} sample {i}: NaN where the zone is in contact",
                    ds.name()
                );
            }
            *n += values.len();
        }
    }
    let file = hdf5::File::open(path).expect("results open");
    let mut n = 0;
    walk(&file, None, None, &mut n);
    assert!(n > 0, "{}: no float data", path.display());
    n
}

/// ∫ y dt by the trapezoidal rule over the samples.
fn trapezoid(t: &[f64], y: &[f64]) -> f64 {
    t.windows(2)
        .zip(y.windows(2))
        .map(|(t, y)| 0.5 * (y[0] + y[1]) * (t[1] - t[0]))
        .sum()
}

/// Index of the first sample at or after `t` (s).
fn at(time: &[f64], t: f64) -> usize {
    time.iter()
        .position(|&x| x >= t - 1e-9)
        .unwrap_or(time.len() - 1)
}

/// Per wheel of wheelset `w`: the tread's normal force, Fx, |(Fx, Fy)| and
/// ξ series.
struct Tread {
    normal_n: Vec<f64>,
    fx_n: Vec<f64>,
    tangential_n: Vec<f64>,
    xi: Vec<f64>,
}

fn treads(r: &Run, w: usize) -> [Tread; 2] {
    ["left", "right"].map(|side| {
        let g = format!("wheelset_{w}/{side}/tread");
        let fx = r.series(&format!("{g}/fx_n"));
        let fy = r.series(&format!("{g}/fy_n"));
        Tread {
            normal_n: r.series(&format!("{g}/normal_n")),
            tangential_n: fx.iter().zip(&fy).map(|(x, y)| x.hypot(*y)).collect(),
            fx_n: fx,
            xi: r.series(&format!("{g}/xi")),
        }
    })
}

/// |(Fx, Fy)| ≤ μN on every tread and flange sample in contact (the
/// saturating laws' bound), to round-off.
fn check_friction_bound(r: &Run, mu: f64) {
    for w in 0..r.wheelsets() {
        for side in ["left", "right"] {
            for zone in ["tread", "flange"] {
                let g = format!("wheelset_{w}/{side}/{zone}");
                let n = r.series(&format!("{g}/normal_n"));
                let fx = r.series(&format!("{g}/fx_n"));
                let fy = r.series(&format!("{g}/fy_n"));
                for i in 0..n.len() {
                    if n[i].is_nan() {
                        continue;
                    }
                    let f = fx[i].hypot(fy[i]);
                    assert!(
                        f <= mu * n[i] * (1.0 + 1e-9) + 1e-9,
                        "{}: {g} sample {i}: |F| = {f} N > μN = {} N",
                        r.name,
                        mu * n[i]
                    );
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Case 1: from rest, and to rest

/// The unsuspended wheelset at rest, driven by 500 N·m (below the 1.8 kN·m
/// that would saturate μN on both wheels): it rolls off through the
/// creepages' regularised range |V| < 0.1 m/s and follows the rolling
/// solution V = T t / (r₀ (m + I/r₀²)); the start-up rule of the normal
/// force keeps the wheel loads at their static value.
#[test]
fn wheelset_starts_from_rest_under_traction() {
    let dir = scratch("extremes_motion_start_wheelset");
    let torque_nm = 500.0;
    let r = sim_run(
        &dir,
        "from_rest",
        "scenes/wheelset_straight.toml",
        &[
            "initial.speed_m_s=0",
            "run.duration_s=0.5",
            "run.axle_torque_nm=500",
        ],
    );
    let (t, v) = (r.time_s(), r.series("wheelset_0/speed_m_s"));
    let accel = torque_nm / (R0_M * rolling_mass_kg());
    for (t, v) in t.iter().zip(&v) {
        let exact = accel * t;
        assert!(
            (v - exact).abs() <= 1e-3 + 2e-3 * exact,
            "t = {t} s: V = {v} m/s, rolling solution {exact} m/s"
        );
    }
    for tread in treads(&r, 0) {
        for n in &tread.normal_n {
            assert!(
                (n / WHEEL_LOAD_N - 1.0).abs() < 0.02,
                "wheel load {n} N, static {WHEEL_LOAD_N} N"
            );
        }
    }
    check_friction_bound(&r, MU);
    // The torque's work went into the rolling kinetic energy.
    let v_end = v[v.len() - 1];
    let kinetic = 0.5 * rolling_mass_kg() * v_end * v_end;
    let work = r.energy("axle_torque_work_j");
    assert!(
        (work - kinetic).abs() < 2e-3 * kinetic,
        "torque work {work} J, kinetic energy {kinetic} J"
    );
}

/// The unsuspended wheelset at 0.5 m/s braked by a 1 kN·m friction brake:
/// it decelerates at T/(r₀ (m + I/r₀²)), stops after V0²/(2a) and stays
/// stopped — no reversal, no drift.
#[test]
fn wheelset_brakes_to_a_stop_and_holds() {
    let dir = scratch("extremes_motion_stop_wheelset");
    let (v0, brake_nm) = (0.5, 1000.0);
    let r = sim_run(
        &dir,
        "to_rest",
        "scenes/wheelset_straight.toml",
        &[
            "initial.speed_m_s=0.5",
            "run.duration_s=0.6",
            "run.axle_brake_torque_nm=1000",
            "run.output_interval_s=0.001",
        ],
    );
    let (t, v, d) = (
        r.time_s(),
        r.series("wheelset_0/speed_m_s"),
        r.series("wheelset_0/distance_m"),
    );
    let decel = brake_nm / (R0_M * rolling_mass_kg());
    let stop = v
        .iter()
        .position(|&v| v < 1e-3)
        .expect("the wheelset stops");
    let t_stop_exact = v0 / decel;
    eprintln!(
        "stopped at {:.3} s (rigid rolling {t_stop_exact:.3} s) after {:.5} m (V0²/2a = {:.5} m)",
        t[stop],
        d[stop],
        v0 * v0 / (2.0 * decel)
    );
    assert!(
        (t[stop] - t_stop_exact).abs() < 0.01,
        "stop at {} s",
        t[stop]
    );
    let d_end = d[d.len() - 1];
    assert!(
        (d_end / (v0 * v0 / (2.0 * decel)) - 1.0).abs() < 0.01,
        "braking distance {d_end} m"
    );
    // Held: no reversal, no drift over the last 0.15 s.
    assert!(v.iter().all(|&v| v > -1e-6), "reversed: {:?}", v);
    let hold = at(&t, t[stop] + 0.03);
    for i in hold..v.len() {
        assert!(v[i].abs() < 1e-6, "t = {}: V = {} m/s", t[i], v[i]);
    }
    assert!(
        (d_end - d[hold]).abs() < 1e-6,
        "drift {} m",
        d_end - d[hold]
    );
    // The brake took the kinetic energy (and the creep a little).
    let kinetic = 0.5 * rolling_mass_kg() * v0 * v0;
    let brake = -r.energy("axle_torque_work_j");
    assert!(
        (brake + r.energy("creep_dissipation_j") - kinetic).abs() < 2e-3 * kinetic,
        "brake work {brake} J, kinetic energy {kinetic} J"
    );
}

/// The bogie at rest under a car body that accelerates from 0 at 1 m/s²:
/// it follows (the secondary springs let it lag and swing) over 0.18 m in
/// 0.6 s; wheel loads stay within ±20 % of their static 49.8 kN (start-up
/// rule); the car body's work is the energy gained plus the losses.
#[test]
fn bogie_starts_from_rest_and_accelerates() {
    let dir = scratch("extremes_motion_start_bogie");
    let r = sim_run(
        &dir,
        "bogie_from_rest",
        "scenes/bogie_straight.toml",
        &[
            "initial.speed_m_s=0",
            "initial.acceleration_m_s2=1",
            "run.duration_s=0.6",
            "run.max_step_s=2e-3",
            "run.output_interval_s=0.01",
        ],
    );
    for w in 0..2 {
        let d = r.series(&format!("wheelset_{w}/distance_m"));
        let d_end = d[d.len() - 1];
        assert!((d_end - 0.18).abs() < 0.04, "wheelset {w}: {d_end} m");
        for tread in treads(&r, w) {
            let n0 = tread.normal_n[0];
            for n in &tread.normal_n {
                assert!((n / n0 - 1.0).abs() < 0.2, "wheel load {n} N from {n0} N");
            }
        }
    }
    check_friction_bound(&r, MU);
    assert!(r.energy("reference_work_j") > 1000.0);
}

/// The bogie at 1 m/s under a car body braking at 2 m/s² to a stop, with a
/// 3.2 kN·m friction brake on each axle (the bogie's share of the
/// deceleration): the car body stops at 0.5 s and stays (no reversal), the
/// wheelsets stop with it and do not drift.
#[test]
fn bogie_brakes_to_a_stop_and_stays() {
    let dir = scratch("extremes_motion_stop_bogie");
    let r = sim_run(
        &dir,
        "bogie_to_rest",
        "scenes/bogie_straight.toml",
        &[
            "initial.speed_m_s=1",
            "initial.deceleration_m_s2=2",
            "run.axle_brake_torque_nm=3200",
            "run.duration_s=0.8",
            "run.max_step_s=2e-3",
            "run.output_interval_s=0.01",
        ],
    );
    let t = r.time_s();
    let hold = at(&t, 0.55);
    for w in 0..2 {
        let v = r.series(&format!("wheelset_{w}/speed_m_s"));
        let d = r.series(&format!("wheelset_{w}/distance_m"));
        // The car body covers V0²/(2a) = 0.25 m; the wheelsets within the
        // springs' deflection of it.
        assert!((d[hold] - 0.25).abs() < 0.01, "wheelset {w}: {} m", d[hold]);
        for i in hold..v.len() {
            assert!(
                v[i].abs() < 1e-3,
                "wheelset {w} at {} s: V = {} m/s",
                t[i],
                v[i]
            );
        }
        let drift = d[d.len() - 1] - d[hold];
        eprintln!("wheelset {w}: drift {drift:.2e} m over 0.25 s at rest");
        assert!(drift.abs() < 1e-4, "wheelset {w}: drift {drift} m");
    }
    check_friction_bound(&r, MU);
    assert!(r.energy("axle_torque_work_j") < 0.0);
}

/// A reversal happens only when asked: the car body braking at 2 m/s² from
/// 0.3 m/s to a final speed of −0.3 m/s runs backwards, and the bogie
/// with it (creepages with |V| = V_eff, `runtime::forces::creepage`).
#[test]
fn bogie_reverses_when_asked() {
    let dir = scratch("extremes_motion_reverse_bogie");
    let r = sim_run(
        &dir,
        "bogie_reverse",
        "scenes/bogie_straight.toml",
        &[
            "initial.speed_m_s=0.3",
            "initial.deceleration_m_s2=2",
            "initial.final_speed_m_s=-0.3",
            "run.duration_s=0.45",
            "run.max_step_s=2e-3",
            "run.output_interval_s=0.01",
        ],
    );
    for w in 0..2 {
        let v = r.series(&format!("wheelset_{w}/speed_m_s"));
        let d = r.series(&format!("wheelset_{w}/distance_m"));
        let n = v.len();
        assert!(v[n - 1] < -0.1, "wheelset {w}: V = {} m/s", v[n - 1]);
        assert!(d[n - 1] < d[n - 2], "wheelset {w} is not going back");
    }
    check_friction_bound(&r, MU);
}

// ---------------------------------------------------------------------------
// Case 2: speed, friction and restitution ranges

/// The unsuspended wheelset from 0.1 to 120 m/s for 0.2 s (up to 24 m; at
/// 80 and 120 m/s the hunting reaches the flanges), and the bogie at
/// 120 m/s, by DOPRI5; 120 m/s also by RK4 at 0.1 ms. The speed holds (no
/// torque, a straight), the balance closes.
#[test]
fn speeds_from_0_1_to_120_m_s() {
    let dir = scratch("extremes_motion_speeds");
    for v in [0.1, 1.0, 10.0, 40.0, 80.0, 120.0] {
        let r = sim_run(
            &dir,
            &format!("wheelset_{v}"),
            "scenes/wheelset_straight.toml",
            &[&format!("initial.speed_m_s={v}"), "run.duration_s=0.2"],
        );
        let speed = r.series("wheelset_0/speed_m_s");
        let v_end = speed[speed.len() - 1];
        assert!(
            (v_end - v).abs() < 1e-3 + 1e-3 * v,
            "{v} m/s: ended at {v_end} m/s"
        );
        check_friction_bound(&r, MU);
    }
    sim_run(
        &dir,
        "wheelset_120_rk4",
        "scenes/wheelset_straight.toml",
        &[
            "initial.speed_m_s=120",
            "run.duration_s=0.2",
            "run.integrator=rk4",
            "run.step_s=1e-4",
        ],
    );
    let r = sim_run(
        &dir,
        "bogie_120",
        "scenes/bogie_straight.toml",
        &[
            "initial.speed_m_s=120",
            "run.duration_s=0.1",
            "run.max_step_s=2e-3",
        ],
    );
    check_friction_bound(&r, MU);
}

/// μ from 0.05 to 0.6 with a 6 kN·m traction torque (above 2 μ N r₀ for
/// every μ, 3.6 kN·m at 0.6): each tread's creep force reaches μN and never
/// exceeds it.
#[test]
fn friction_from_0_05_to_0_6() {
    let dir = scratch("extremes_motion_friction");
    for mu in [0.05, 0.15, 0.3, 0.6] {
        let r = sim_run(
            &dir,
            &format!("mu_{mu}"),
            "scenes/wheelset_straight.toml",
            &[
                "initial.speed_m_s=10",
                "run.duration_s=0.2",
                "run.axle_torque_nm=6000",
                &format!("contact.friction={mu}"),
            ],
        );
        check_friction_bound(&r, mu);
        for tread in treads(&r, 0) {
            let i = tread.fx_n.len() - 1;
            let ratio = tread.fx_n[i] / (mu * tread.normal_n[i]);
            assert!(ratio > 0.99, "μ = {mu}: Fx/μN = {ratio} at the end");
        }
    }
}

/// Restitution from 0.1 to 1 at 80 m/s, where the wheelset's hunting hits
/// a flange within 0.3 s: the contact damping dissipates for e < 1 and
/// nothing at e = 1.
#[test]
fn restitution_from_0_1_to_1() {
    let dir = scratch("extremes_motion_restitution");
    for e in [0.1, 0.5, 0.9, 1.0] {
        let r = sim_run(
            &dir,
            &format!("e_{e}"),
            "scenes/wheelset_straight.toml",
            &[
                "initial.speed_m_s=80",
                "run.duration_s=0.3",
                "run.output_interval_s=0.001",
                &format!("contact.restitution={e}"),
            ],
        );
        let flange: u64 = r.summary["flange_contact_states"].as_u64().unwrap_or(0);
        assert!(flange > 0, "e = {e}: no flange contact");
        let damping = r.energy("contact_damping_dissipation_j");
        if e == 1.0 {
            assert!(damping.abs() < 1e-9, "e = 1: contact damping {damping} J");
        } else {
            assert!(damping > 0.0, "e = {e}: contact damping {damping} J");
        }
        check_friction_bound(&r, MU);
    }
}

// ---------------------------------------------------------------------------
// Case 3: traction and braking far into saturation

/// Momentum and spin of the unsuspended wheelset under a torque T from the
/// results: m ΔV = ∫ ΣFx dt, and I ΔΩ = T t − r₀ ∫ ΣFx dt with the spin
/// read back from the creepage, Ω = V (1 − ξ)/r₀ (ξ = (V − Ω r)/V on a
/// tread rolling at r ≈ r₀). Returns the largest Fx/μN over the last 0.1 s.
fn check_momentum_and_spin(r: &Run, torque_nm: f64, mu: f64) -> f64 {
    let (t, v) = (r.time_s(), r.series("wheelset_0/speed_m_s"));
    let tr = treads(r, 0);
    let total_fx: Vec<f64> = (0..t.len())
        .map(|i| tr[0].fx_n[i] + tr[1].fx_n[i])
        .collect();
    let impulse = trapezoid(&t, &total_fx);
    let n = t.len() - 1;
    let dv = v[n] - v[0];
    assert!(
        (MASS_KG * dv - impulse).abs() < 0.01 * impulse.abs(),
        "{}: m ΔV = {} N·s, creep impulse {impulse} N·s",
        r.name,
        MASS_KG * dv
    );
    let spin0 = v[0] / R0_M;
    let spin_expected = spin0 + (torque_nm * t[n] - R0_M * impulse) / SPIN_INERTIA_KG_M2;
    let xi = 0.5 * (tr[0].xi[n] + tr[1].xi[n]);
    let spin = v[n] * (1.0 - xi) / R0_M;
    eprintln!(
        "{}: V {} → {:.3} m/s, ξ = {xi:.3}, spin {spin0:.2} → {spin:.2} rad/s (equation: {spin_expected:.2})",
        r.name, v[0], v[n]
    );
    assert!(
        (spin - spin_expected).abs() < 0.01 * (spin_expected - spin0).abs() + 0.02,
        "{}: spin {spin} rad/s from ξ, {spin_expected} from the spin equation",
        r.name
    );
    let late = at(&t, t[n] - 0.1);
    tr.iter()
        .flat_map(|w| (late..=n).map(move |i| w.fx_n[i].abs() / (mu * w.normal_n[i])))
        .fold(f64::NAN, f64::max)
}

/// ±6 kN·m on the wheelset at 10 m/s (3.3 × the 1.8 kN·m that saturates
/// both treads): with the saturating laws the longitudinal creep force
/// reaches μN per wheel (Fx/μN > 0.999) and never exceeds it, ξ runs to
/// ∓0.5, the spin follows its equation, momentum and energy balance (torque
/// work = kinetic energy change + creep dissipation).
#[test]
fn traction_and_braking_saturate_at_mu_n() {
    let dir = scratch("extremes_motion_saturation");
    for law in ["polach", "heuristic", "fastsim"] {
        for torque in [6000.0, -6000.0] {
            let r = sim_run(
                &dir,
                &format!("{law}_{torque}"),
                "scenes/wheelset_straight.toml",
                &[
                    "initial.speed_m_s=10",
                    "run.duration_s=0.3",
                    "run.output_interval_s=0.001",
                    &format!("run.axle_torque_nm={torque}"),
                    &format!("contact.creep_law={law}"),
                ],
            );
            check_friction_bound(&r, MU);
            let peak = check_momentum_and_spin(&r, torque, MU);
            eprintln!("{}: Fx/μN = {peak:.7} in the last 0.1 s", r.name);
            assert!(peak > 0.999, "{}: Fx/μN = {peak}", r.name);
            for tread in treads(&r, 0) {
                let n = tread.xi.len() - 1;
                // Traction spins the wheel faster than it rolls: ξ < 0 and
                // the force on the wheel forwards; braking the opposite.
                assert!(tread.xi[n] * torque.signum() < -0.3, "ξ = {}", tread.xi[n]);
                assert!(tread.fx_n[n] * torque.signum() > 0.0);
                assert!(tread.tangential_n[n] <= MU * tread.normal_n[n] * (1.0 + 1e-9));
            }
            let work = r.energy("axle_torque_work_j");
            let gained = r.energy("final_j") - r.energy("initial_j");
            let creep = r.energy("creep_dissipation_j");
            assert!(
                (work - gained - creep).abs() < 1e-6 * work.abs(),
                "{}: torque work {work} J, energy gained {gained} J, creep {creep} J",
                r.name
            );
        }
    }
}

/// Kalker's linear law has no friction limit by design (paper eq. 23): the
/// same 6 kN·m is transmitted at a small creepage with Fx ≈ 2.5 μN per
/// wheel. The run stays finite and balanced.
#[test]
fn kalker_linear_is_unbounded_by_design() {
    let dir = scratch("extremes_motion_kalker");
    let r = sim_run(
        &dir,
        "kalker_6000",
        "scenes/wheelset_straight.toml",
        &[
            "initial.speed_m_s=10",
            "run.duration_s=0.3",
            "run.output_interval_s=0.001",
            "run.axle_torque_nm=6000",
            "contact.creep_law=kalker",
        ],
    );
    let peak = check_momentum_and_spin(&r, 6000.0, MU);
    eprintln!("kalker: Fx/μN = {peak:.3} in the last 0.1 s");
    assert!(peak > 2.0, "Kalker linear Fx/μN = {peak}");
}
