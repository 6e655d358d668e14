//! End to end: `sim sweep` — a study run on the local cores, the same
//! study in shards joined by `sim sweep merge` (the same table, byte for
//! byte), resuming after a kill without redoing finished variants, failed
//! variants recorded and computed again, refusals before the work.

mod common;

use std::path::{Path, PathBuf};

use common::*;

/// A small study on the shipped wheelset scene: 3 speeds × 2 creep laws,
/// 4 m each; `extra` is appended to the study file.
fn small_study(dir: &Path, extra: &str) -> PathBuf {
    let scene = shipped("scenes/wheelset_straight.toml");
    let text = format!(
        r#"title = "wheelset test study"
scene = "{}"

[set]
"run.distance_m" = 4.0

[[vary]]
key = "initial.speed_m_s"
values = [8.0, 10.0, 12.0]

[[vary]]
key = "contact.creep_law"
values = ["polach", "kalker"]

[compute]
kind = "run"
figures = ["wheelsets.0.peak_lateral_mm", "steps", "wheelsets.0.no_such_figure"]

[plot]
x = "initial.speed_m_s"
lines = "contact.creep_law"
figures = ["wheelsets.0.peak_lateral_mm"]
{extra}"#,
        scene.display()
    );
    std::fs::create_dir_all(dir).unwrap();
    let p = dir.join("study.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// The table cache the tests share (built once, not wiped per test).
fn cache() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("sweep_table_cache");
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn sweep(args: &[&str]) -> std::process::Output {
    run(sim()
        .arg("sweep")
        .args(args)
        .env("RAILSIM_CACHE_DIR", cache()))
}

fn ok(o: &std::process::Output) -> String {
    assert!(o.status.success(), "{}\n{}", stdout(o), stderr(o));
    stdout(o)
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The log lines (variant, status, wall) of every shard of a folder.
fn computations(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir.join("shards")).unwrap() {
        let p = e.unwrap().path();
        if p.to_str().unwrap().ends_with(".log.csv") {
            out.extend(
                read(&p)
                    .lines()
                    .skip(1)
                    .map(|l| l.split(',').next().unwrap().to_string()),
            );
        }
    }
    out.sort();
    out
}

#[test]
fn sharded_study_merges_to_the_unsharded_table() {
    let dir = scratch("sweep_shards");
    let study = small_study(&dir, "");
    let (s, whole, parts) = (
        study.to_str().unwrap(),
        dir.join("whole"),
        dir.join("parts"),
    );
    let text = ok(&sweep(&[s, "--out", whole.to_str().unwrap(), "--quiet"]));
    assert!(text.contains("6 computed (0 failed)"), "{text}");
    let table = read(&whole.join("table.csv"));
    let lines: Vec<&str> = table.lines().collect();
    assert_eq!(lines.len(), 7, "{table}");
    assert_eq!(
        lines[0],
        "variant,initial.speed_m_s,contact.creep_law,status,wheelsets.0.peak_lateral_mm,steps,wheelsets.0.no_such_figure,message,results"
    );
    // Variant 1: the first speed with the second law (last axis fastest).
    assert!(lines[2].starts_with("1,8,kalker,ok,"), "{}", lines[2]);
    for l in &lines[1..] {
        let f: Vec<&str> = l.split(',').collect();
        // Released 2 mm off centre: the peak is at least that; a figure
        // not in the summary is an empty cell.
        let peak: f64 = f[4].parse().unwrap();
        assert!((2.0..10.0).contains(&peak), "{l}");
        assert!(f[5].parse::<u64>().unwrap() > 100, "{l}");
        assert_eq!(f[6], "", "{l}");
    }
    assert!(whole.join("table.h5").exists());
    assert!(whole.join("plots/wheelsets_0_peak_lateral_mm.png").exists());

    // Three shards: merging before the last is refused, naming what is missing.
    for i in 0..2 {
        ok(&sweep(&[
            s,
            "--out",
            parts.to_str().unwrap(),
            "--shard",
            &format!("{i}/3"),
            "--quiet",
        ]));
    }
    let early = sweep(&["merge", parts.to_str().unwrap()]);
    assert!(!early.status.success());
    let e = stderr(&early);
    assert!(
        e.contains("2 of the 6 variants have no row")
            && e.contains("2 (initial.speed_m_s=10.0 contact.creep_law=\"polach\")"),
        "{e}"
    );
    ok(&sweep(&[
        s,
        "--out",
        parts.to_str().unwrap(),
        "--shard",
        "2/3",
        "--quiet",
    ]));
    ok(&sweep(&["merge", parts.to_str().unwrap()]));
    // Deterministic runs: the merged table is the unsharded one, byte for byte.
    assert_eq!(read(&parts.join("table.csv")), table);
    // Shard 1/3 holds variants 1 and 4 (in the order they finished).
    let shard1 = read(&parts.join("shards/shard_1_of_3.csv"));
    let mut ids: Vec<&str> = shard1
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    ids.sort_unstable();
    assert_eq!(ids, ["1", "4"]);
    // A re-run computes nothing.
    let again = ok(&sweep(&[s, "--out", whole.to_str().unwrap(), "--quiet"]));
    assert!(again.contains("6 done before, 0 computed"), "{again}");
    assert_eq!(computations(&whole).len(), 6);
}

#[test]
fn failed_variants_are_recorded_and_computed_again() {
    let dir = scratch("sweep_failed");
    // A 5 ms RK4 step, far above the wheelset's stability limit: Kalker's
    // unsaturated law blows the wheelset up (variants 1, 3, 5); Polach's
    // saturating law keeps the motion bounded for a while, so its runs may
    // end or fail (which, depends on round-off: the integration is
    // unstable). The study goes on to the end either way.
    let study = small_study(&dir, "");
    let text = read(&study).replace(
        "\"run.distance_m\" = 4.0",
        "\"run.distance_m\" = 4.0\n\"run.step_s\" = 5e-3\n\"run.integrator\" = \"rk4\"",
    );
    std::fs::write(&study, text).unwrap();
    let out = dir.join("out");
    let o = ok(&sweep(&[
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]));
    let table = read(&out.join("table.csv"));
    let mut failed_ids = Vec::new();
    for l in table.lines().skip(1) {
        let failed = l.contains(",failed,") && l.contains("the run failed at t =");
        assert!(failed || l.contains(",polach,ok,"), "{l}");
        assert!(!l.contains(",kalker,") || failed, "{l}");
        if failed {
            failed_ids.push(l.split(',').next().unwrap().to_string());
        }
    }
    let n = failed_ids.len();
    assert!(n >= 3, "{table}");
    assert!(o.contains(&format!("6 computed ({n} failed)")), "{o}");
    // The failed ones, and only they, are computed again by the next run.
    let o = ok(&sweep(&[
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]));
    assert!(
        o.contains(&format!("{} done before, {n} computed ({n} failed)", 6 - n))
            && o.contains(&format!("{n} failed rows of an earlier run computed again")),
        "{o}"
    );
    let mut expected: Vec<String> = (0..6).map(|i| i.to_string()).collect();
    expected.extend(failed_ids);
    expected.sort();
    assert_eq!(computations(&out), expected);
}

#[test]
fn a_killed_study_resumes_without_redoing_finished_variants() {
    let dir = scratch("sweep_killed");
    let study = small_study(&dir, "");
    let out = dir.join("out");
    let mut child = sim()
        .args([
            "sweep",
            study.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--jobs",
            "1",
        ])
        .env("RAILSIM_CACHE_DIR", cache())
        .spawn()
        .expect("sim runs");
    let csv = out.join("shards/shard_0_of_1.csv");
    let started = std::time::Instant::now();
    // Kill it (SIGKILL: no clean-up) once two variants are done.
    loop {
        let rows = std::fs::read_to_string(&csv).map_or(0, |t| t.lines().count().saturating_sub(1));
        if rows >= 2 {
            break;
        }
        assert!(
            started.elapsed().as_secs() < 300,
            "the study did not progress"
        );
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    let before = computations(&out);
    assert!(
        before.len() >= 2 && before.len() < 6,
        "killed too late to test: {before:?}"
    );
    let o = ok(&sweep(&[
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]));
    assert!(o.contains(&format!("{} done before", before.len())), "{o}");
    // Every variant computed exactly once over both runs.
    let all = computations(&out);
    let mut unique = all.clone();
    unique.dedup();
    assert_eq!(all, unique, "a finished variant was computed again");
    assert_eq!(all.len(), 6);
    assert_eq!(read(&out.join("table.csv")).lines().count(), 7);
}

#[test]
fn refusals_before_the_work() {
    let dir = scratch("sweep_refused");
    // A key that is not a scene key is refused before any run, naming the variant.
    let study = small_study(&dir, "");
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        read(&study).replace("contact.creep_law", "contact.creep_lwa"),
    )
    .unwrap();
    let o = sweep(&[
        bad.to_str().unwrap(),
        "--out",
        dir.join("o1").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(e.contains("variant 0") && e.contains("creep_lwa"), "{e}");
    assert!(!dir.join("o1").exists(), "a refused study wrote its folder");
    // Another study into a folder that holds one is refused.
    let out = dir.join("o2");
    ok(&sweep(&[
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--shard",
        "0/6",
    ]));
    let other = dir.join("other.toml");
    std::fs::write(&other, read(&study).replace("12.0]", "13.0]")).unwrap();
    let o = sweep(&[other.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("holds the rows of another study"),
        "{}",
        stderr(&o)
    );
    // A malformed shard.
    let o = sweep(&[
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--shard",
        "6/6",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("0 <= I < N"), "{}", stderr(&o));
}

#[test]
fn slurm_scripts_run_each_shard_and_merge_after() {
    let dir = scratch("sweep_slurm_scripts");
    let study = small_study(&dir, "");
    let out = dir.join("out");
    let o = ok(&sweep(&[
        "slurm",
        study.to_str().unwrap(),
        "--shards",
        "4",
        "--out",
        out.to_str().unwrap(),
        "--partition",
        "batch",
        "--time",
        "0:30:00",
        "--cpus-per-task",
        "2",
    ]));
    assert!(
        o.contains("sbatch --parsable") && o.contains("--dependency=afterok:"),
        "{o}"
    );
    let array = read(&out.join("slurm/array.sbatch"));
    for line in [
        "#SBATCH --array=0-3",
        "#SBATCH --cpus-per-task=2",
        "#SBATCH --partition=batch",
        "#SBATCH --time=0:30:00",
        "--shard \"${SLURM_ARRAY_TASK_ID}/4\"",
    ] {
        assert!(array.contains(line), "{line} missing:\n{array}");
    }
    let merge = read(&out.join("slurm/merge.sbatch"));
    assert!(merge.contains("sweep merge"), "{merge}");
    // A shell injection in a job setting is refused.
    let o = sweep(&[
        "slurm",
        study.to_str().unwrap(),
        "--shards",
        "2",
        "--out",
        out.to_str().unwrap(),
        "--partition",
        "a;rm",
    ]);
    assert!(!o.status.success());
}

#[test]
fn shipped_studies_check_every_variant() {
    // `sim sweep slurm` loads a study and checks every variant's scene
    // before writing its scripts: the shipped studies pass.
    let dir = scratch("sweep_shipped");
    for name in [
        "bogie_friction_critical_speed.toml",
        "cooperrider_yaw_damper.toml",
        "bogie_r250_curving.toml",
    ] {
        let study = shipped(&format!("sweeps/{name}"));
        let out = dir.join(name);
        let o = ok(&sweep(&[
            "slurm",
            study.to_str().unwrap(),
            "--shards",
            "2",
            "--out",
            out.to_str().unwrap(),
        ]));
        assert!(o.contains("variants in 2 array tasks"), "{name}: {o}");
    }
}

#[test]
fn tradeoff_points_against_one_reference() {
    // The RK4 step against a 0.05 ms reference: the error grows with the
    // step, the steps fall.
    let dir = scratch("sweep_tradeoff");
    let scene = shipped("scenes/wheelset_straight.toml");
    let study = dir.join("tradeoff.toml");
    std::fs::write(
        &study,
        format!(
            r#"title = "RK4 step against a fine reference"
scene = "{}"
[set]
"run.distance_m" = 4.0
"run.integrator" = "rk4"
[[vary]]
key = "run.step_s"
values = [1e-4, 2e-4, 4e-4]
[compute]
kind = "tradeoff"
reference = {{ "run.step_s" = 5e-5 }}
"#,
            scene.display()
        ),
    )
    .unwrap();
    let out = dir.join("out");
    ok(&sweep(&[
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]));
    let table = read(&out.join("table.csv"));
    let mut lines = table.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f[col("status")], "ok", "{l}");
            ["lateral_error_max_um", "lateral_error_rms_um", "steps"]
                .iter()
                .map(|c| f[col(c)].parse().unwrap())
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), 3);
    for r in &rows {
        assert!(
            r[0] >= r[1] && r[0] < 1.0,
            "RK4 at ≤ 0.4 ms is within 1 µm: {r:?}"
        );
    }
    assert!(
        rows[0][0] < rows[2][0],
        "the error grows with the step: {rows:?}"
    );
    assert!(
        rows[0][2] > rows[1][2] && rows[1][2] > rows[2][2],
        "{rows:?}"
    );
}
