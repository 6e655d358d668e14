//! Trust (issue 12): nothing lost, nothing silently wrong. Each test checks
//! one class of fault for every binary it concerns.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use super::common::*;

/// `track-preproc build --centerline CENTERLINE -o OUT`.
fn build(centerline: &Path, out: &Path) -> Command {
    let mut c = track_preproc();
    c.args(["build", "--centerline"])
        .arg(centerline)
        .arg("-o")
        .arg(out);
    c
}

/// The shipped 300 m straight's centreline.
fn straight_centerline() -> PathBuf {
    shipped("tracks/straight_300m/centerline.csv")
}

/// Runs `cmd` with its standard output closed before it prints: it must
/// end quietly (no panic, no "Broken pipe" message), as Unix tools do.
fn closed_pipe(mut cmd: Command, what: &str) {
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    drop(child.stdout.take()); // the reader goes away before any output
    let out = child.wait_with_output().expect("wait");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !err.contains("panicked") && !err.contains("Broken pipe"),
        "{what}: {err}"
    );
}

#[test]
fn every_binary_ends_quietly_on_a_closed_pipe() {
    let dir = scratch("trust_closed_pipe");
    let mut contact = sim();
    contact.args([
        "contact",
        "--wheel",
        shipped("profiles/MBench_S1002_v3.prw").to_str().unwrap(),
        "--rail",
        shipped("profiles/MBench_UIC60_v3.prr").to_str().unwrap(),
        "--rail-inclination",
        "0",
    ]);
    closed_pipe(contact, "sim contact");
    let o = run(&mut build(&straight_centerline(), &dir.join("straight.h5")));
    assert!(o.status.success(), "{}", stderr(&o));
    closed_pipe(
        build(&straight_centerline(), &dir.join("again.h5")),
        "track-preproc build",
    );
    let mut probe = sim();
    probe.args([
        "probe",
        dir.join("straight.h5").to_str().unwrap(),
        "--s",
        "10",
    ]);
    closed_pipe(probe, "sim probe");
}

/// The scene of the shipped wheelset case as a string path.
fn wheelset_scene() -> String {
    shipped("scenes/wheelset_straight.toml")
        .to_str()
        .unwrap()
        .to_string()
}

/// An output that is one of the inputs is refused before any work, however
/// it is spelt, for every kind of input and every command; the input is
/// left as it was, and no work was done (no track table built in the cache).
#[test]
fn no_output_replaces_an_input() {
    let dir = scratch("trust_output_is_input");
    let cache = dir.join("cache");
    // Copies of the shipped inputs, so that a failure of the check cannot
    // damage the repository.
    let centerline = dir.join("centerline.csv");
    std::fs::copy(shipped("tracks/straight_300m/centerline.csv"), &centerline).unwrap();
    let wheel = dir.join("wheel.prw");
    std::fs::copy(shipped("profiles/MBench_S1002_v3.prw"), &wheel).unwrap();
    let vehicle = dir.join("vehicle.toml");
    std::fs::copy(shipped("vehicles/ml95_like_wheelset.toml"), &vehicle).unwrap();
    let tables = dir.join("t.h5");
    let o = run(&mut build(&centerline, &tables));
    assert!(o.status.success(), "{}", stderr(&o));
    let before = |p: &std::path::Path| std::fs::read(p).unwrap();
    let (c0, t0, v0) = (before(&centerline), before(&tables), before(&vehicle));

    // track-preproc: the output is the centreline (also through `..`).
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    for out in [centerline.clone(), dir.join("sub/../centerline.csv")] {
        let o = run(&mut build(&centerline, &out));
        assert!(!o.status.success());
        assert!(
            stderr(&o).contains("would replace the input"),
            "{}",
            stderr(&o)
        );
    }
    // sim run: the output is the track tables, the scene, the vehicle file.
    let sim_run = |sets: &[String], out: &std::path::Path| {
        let mut c = sim();
        c.env("RAILSIM_CACHE_DIR", &cache).args([
            "run",
            &wheelset_scene(),
            "--no-plots",
            "-o",
            out.to_str().unwrap(),
        ]);
        for s in sets {
            c.args(["--set", s]);
        }
        run(&mut c)
    };
    let with_tables = [
        "track.centerline=".to_string(),
        format!("track.tables={}", tables.display()),
    ];
    let with_vehicle = [format!("vehicle.file={}", vehicle.display())];
    for (sets, out) in [
        (&with_tables[..], tables.clone()),
        (&with_vehicle[..], vehicle.clone()),
        (&[][..], shipped("scenes/wheelset_straight.toml")),
    ] {
        let o = sim_run(sets, &out);
        assert!(!o.status.success(), "{}", out.display());
        assert!(
            stderr(&o).contains("would replace the input"),
            "{}",
            stderr(&o)
        );
    }
    // Nothing was replaced, and nothing was built.
    assert_eq!(before(&centerline), c0);
    assert_eq!(before(&tables), t0);
    assert_eq!(before(&vehicle), v0);
    assert!(
        !cache.exists() || files_in(&cache).iter().all(|f| !f.starts_with("track-")),
        "the refused runs did work: {:?}",
        files_in(&cache)
    );
}

/// Output locations that cannot be written are found before the work: a
/// directory given as the results file, a missing directory, a plots
/// folder that is a file.
#[test]
fn output_locations_are_checked_before_the_work() {
    let dir = scratch("trust_output_location");
    let cache = dir.join("cache");
    let plain = dir.join("plain");
    std::fs::write(&plain, b"x").unwrap();
    let (missing, results) = (dir.join("missing/run.h5"), dir.join("run.h5"));
    let cases: [(&[&str], &str); 3] = [
        (
            &["-o", dir.to_str().unwrap(), "--no-plots"],
            "is a directory",
        ),
        (
            &["-o", missing.to_str().unwrap(), "--no-plots"],
            "does not exist",
        ),
        (
            &[
                "-o",
                results.to_str().unwrap(),
                "--plots",
                plain.to_str().unwrap(),
            ],
            "is a file",
        ),
    ];
    for (args, what) in cases {
        let o = run(sim()
            .env("RAILSIM_CACHE_DIR", &cache)
            .args(["run", &wheelset_scene()])
            .args(args));
        assert!(!o.status.success(), "{args:?}");
        assert!(stderr(&o).contains(what), "{args:?}: {}", stderr(&o));
    }
    assert!(
        !cache.exists() || files_in(&cache).is_empty(),
        "work was done"
    );
    // track-preproc: the table file is a directory.
    let o = run(&mut build(&straight_centerline(), &dir));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("is a directory"), "{}", stderr(&o));
}

/// kill -9 mid-write leaves a temporary (nothing can run then): the next
/// write of the same output removes the temporaries of writers that are no
/// longer running, and keeps the others'.
#[test]
fn stale_temporaries_are_removed_by_the_next_write() {
    let dir = scratch("trust_stale_temporaries");
    let out = dir.join("t.h5");
    let dead = dir.join(".t.h5.tmp-4294967295-0");
    let other = dir.join(".u.h5.tmp-4294967295-0");
    std::fs::write(&dead, vec![0u8; 1 << 20]).unwrap();
    std::fs::write(&other, b"another output's").unwrap();
    let o = run(&mut build(&straight_centerline(), &out));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!dead.exists(), "{:?}", files_in(&dir));
    assert!(other.exists());
    assert!(out.exists());
}

/// SIGTERM (`kill`) is Ctrl-C's twin: `sim run` stops at the next step,
/// writes the results so far marked interrupted and exits with 130, leaving
/// no temporary.
#[test]
fn sigterm_stops_a_run_cleanly() {
    let dir = scratch("trust_sigterm");
    let out = dir.join("run.h5");
    let child = sim()
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .args([
            "run",
            &wheelset_scene(),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "initial.speed_m_s=2",
            "--no-plots",
            "--quiet",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sim starts");
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let k = run(Command::new("kill").args(["-TERM", &child.id().to_string()]));
    assert!(k.status.success());
    let o = child.wait_with_output().expect("sim ends");
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    let r = runtime::io::schema::read_results(&out).expect("the results so far");
    assert_eq!(r.attribute_text("status"), Some("interrupted"));
    assert!(
        files_in(&dir).iter().all(|f| !f.contains(".tmp-")),
        "{:?}",
        files_in(&dir)
    );
}

/// What would exhaust the memory or the time (a unit slip) is refused
/// before the run, naming the entry: more samples than memory holds (with
/// either integrator: both have dense output, so samples finer than the
/// step are legitimate until then), a step of 1e-300 s.
#[test]
fn unit_slips_in_the_run_section_are_refused_before_the_run() {
    let dir = scratch("trust_run_section");
    for (set, expected) in [
        (
            "run.output_interval_s=1e-9",
            "[run] output_interval_s = 1e-9 s gives 2.800e10 samples",
        ),
        (
            "run.step_s=1e-300",
            "[run] step_s = 1e-300 s is below 1e-7 s (check the unit",
        ),
    ] {
        let o = run(sim()
            .env("RAILSIM_CACHE_DIR", dir.join("cache"))
            .args(["run", &wheelset_scene(), "--no-plots", "-o"])
            .arg(dir.join("run.h5"))
            .args(["--set", set]));
        assert!(!o.status.success(), "{set}");
        let err = stderr(&o);
        assert!(
            err.contains(expected) && err.contains("check the unit"),
            "{set}: {err}"
        );
        assert!(!dir.join("run.h5").exists());
    }
    // DOPRI5's dense output may sample finer than its steps, but not
    // beyond what memory holds: 28 s at 1 µs is 2.8e7 samples.
    let o = run(sim()
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .args(["run", &wheelset_scene(), "--no-plots", "-o"])
        .arg(dir.join("run.h5"))
        .args([
            "--set",
            "run.integrator=dopri5",
            "--set",
            "run.output_interval_s=1e-6",
        ]));
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("samples over the run"),
        "{}",
        stderr(&o)
    );
}

/// A run's results file and its plots are one output: while one `sim run`
/// writes them, a second one naming the same results file, or the same
/// plots folder, is refused at once (naming the first's process id) and
/// writes nothing; once the first has finished the outputs are free again.
#[test]
fn two_runs_of_one_output_at_once_are_refused() {
    let dir = scratch("trust_concurrent_runs");
    let out = dir.join("run.h5");
    let plots = dir.join("plots");
    let cache = dir.join("cache");
    let start = |out: &Path, plots: &Path| {
        sim()
            .env("RAILSIM_CACHE_DIR", &cache)
            .args(["run", &wheelset_scene(), "--quiet", "-o"])
            .arg(out)
            .arg("--plots")
            .arg(plots)
            .args(["--set", "initial.speed_m_s=2"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("sim starts")
    };
    let first = start(&out, &plots);
    let lock = dir.join(".run.h5.lock");
    let waited = std::time::Instant::now();
    while !lock.exists() && waited.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    assert!(lock.exists(), "the first run takes its lock");
    let pid = first.id().to_string();
    for (o, p, what) in [
        (
            out.clone(),
            dir.join("other_plots"),
            "the same results file",
        ),
        (dir.join("other.h5"), plots.clone(), "the same plots folder"),
    ] {
        let second = start(&o, &p).wait_with_output().expect("sim ends");
        assert!(!second.status.success(), "{what}");
        let err = stderr(&second);
        assert!(
            err.contains("is being written by another process") && err.contains(&pid),
            "{what}: {err}"
        );
        assert!(!o.exists() || o == out, "{what}: nothing written");
    }
    assert!(!dir.join("other.h5").exists());
    let k = run(Command::new("kill").args(["-TERM", &pid]));
    assert!(k.status.success());
    let o = first.wait_with_output().expect("sim ends");
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(!lock.exists(), "the lock goes with its run");
    assert!(files_in(&dir).iter().all(|f| !f.ends_with(".lock")));
}

/// A run longer than the in-memory view (200 000 samples) streams every
/// sample to the file and keeps every 2nd for its summary and plots, and
/// says so; the summary reports the peak memory.
#[test]
fn a_long_run_streams_its_samples_and_bounds_its_memory() {
    let dir = scratch("trust_long_run");
    let out = dir.join("run.h5");
    let o = run(sim()
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .args(["run", &wheelset_scene(), "--no-plots", "--json", "-o"])
        .arg(&out)
        .args([
            "--set",
            "run.distance_m=2.1", // 0.21 s at the scene's 10 m/s
            "--set",
            "run.output_interval_s=1e-6",
        ]));
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON summary");
    let n = j["output_samples"].as_u64().expect("a count") as usize;
    assert!((200_001..=210_001).contains(&n), "{j}");
    assert_eq!(j["summary_stride"], 2, "{j}");
    assert!(
        j["peak_memory_mib"].as_f64().is_some_and(|m| m > 1.0),
        "{j}"
    );
    let r = runtime::io::schema::read_results(&out).unwrap();
    assert_eq!(r.len(), n, "the file holds every sample");
    assert!(r.time_s.windows(2).all(|w| w[1] > w[0]));
    let dt = (r.time_s[n - 1] - r.time_s[0]) / (n - 1) as f64;
    assert!((dt - 1e-6).abs() < 1e-12, "{dt}");
}
