//! A study on a real Slurm cluster (issue 18): a single-node Slurm —
//! Debian's `slurm-wlm` and `munge`, slurmctld and slurmd on localhost
//! with a generated minimal `slurm.conf` and munge key, all under a
//! temporary directory — runs `sim sweep slurm --submit`: a 4-task job
//! array plus the merge job (`--dependency=afterok`). The merged table must
//! equal a local run's, byte for byte. The daemons are stopped at the end,
//! whatever happens.
//!
//! It needs root (slurmd runs the jobs as root here) and the packages;
//! `.ci/run` installs them and sets `RAILSIM_REQUIRE_SLURM=1`, which turns
//! a missing prerequisite into a failure. Elsewhere, without them, the
//! test says loudly that it did not run.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::*;

fn have(cmd: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {cmd}")])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Why the test cannot run here, if it cannot.
fn missing_prerequisite() -> Option<String> {
    // SAFETY: getuid has no preconditions and cannot fail.
    if unsafe { libc::getuid() } != 0 {
        return Some("it must run as root (slurmd runs the jobs as root here)".into());
    }
    for cmd in [
        "munged",
        "slurmctld",
        "slurmd",
        "sbatch",
        "scontrol",
        "sinfo",
    ] {
        if !have(cmd) {
            return Some(format!(
                "`{cmd}` is not installed (apt-get install slurm-wlm munge)"
            ));
        }
    }
    None
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free port")
}

fn short_hostname() -> String {
    let o = Command::new("hostname")
        .arg("-s")
        .output()
        .expect("hostname");
    String::from_utf8_lossy(&o.stdout).trim().to_string()
}

/// A running single-node cluster; dropping it stops the daemons.
struct Cluster {
    dir: PathBuf,
    conf: PathBuf,
}

impl Cluster {
    fn start(dir: &Path) -> Cluster {
        let munge = dir.join("munge");
        for d in ["munge", "state", "spool", "log"] {
            std::fs::create_dir_all(dir.join(d)).unwrap();
        }
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o700)).unwrap();
        std::fs::set_permissions(&munge, std::fs::Permissions::from_mode(0o700)).unwrap();
        let key: Vec<u8> = (0..1024u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8 ^ std::process::id() as u8)
            .collect();
        let key_file = munge.join("munge.key");
        std::fs::write(&key_file, key).unwrap();
        std::fs::set_permissions(&key_file, std::fs::Permissions::from_mode(0o400)).unwrap();
        let socket = munge.join("munge.socket");
        let status = Command::new("munged")
            .arg("--force")
            .arg(format!("--key-file={}", key_file.display()))
            .arg(format!("--socket={}", socket.display()))
            .arg(format!("--pid-file={}", munge.join("munged.pid").display()))
            .arg(format!("--log-file={}", munge.join("munged.log").display()))
            .arg(format!(
                "--seed-file={}",
                munge.join("munged.seed").display()
            ))
            .status()
            .expect("munged starts");
        assert!(
            status.success(),
            "munged failed: {}",
            read_or(&munge.join("munged.log"))
        );
        let host = short_hostname();
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        let d = dir.display();
        let conf_text = format!(
            "ClusterName=railsimtest\n\
             SlurmctldHost={host}\n\
             SlurmUser=root\n\
             SlurmdUser=root\n\
             AuthType=auth/munge\n\
             AuthInfo=socket={socket}\n\
             CredType=cred/munge\n\
             StateSaveLocation={d}/state\n\
             SlurmdSpoolDir={d}/spool\n\
             SlurmctldPidFile={d}/slurmctld.pid\n\
             SlurmdPidFile={d}/slurmd.pid\n\
             SlurmctldPort={ctld}\n\
             SlurmdPort={slurmd}\n\
             ProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\n\
             SchedulerType=sched/builtin\n\
             SelectType=select/cons_tres\n\
             SelectTypeParameters=CR_CPU\n\
             ReturnToService=2\n\
             MpiDefault=none\n\
             MinJobAge=3600\n\
             JobCompType=jobcomp/none\n\
             AccountingStorageType=accounting_storage/none\n\
             JobAcctGatherType=jobacct_gather/none\n\
             SlurmctldLogFile={d}/log/slurmctld.log\n\
             SlurmdLogFile={d}/log/slurmd.log\n\
             NodeName={host} NodeAddr=127.0.0.1 CPUs={cpus} State=UNKNOWN\n\
             PartitionName=debug Nodes={host} Default=YES MaxTime=INFINITE State=UP\n",
            socket = socket.display(),
            ctld = free_port(),
            slurmd = free_port(),
        );
        let conf = dir.join("slurm.conf");
        std::fs::write(&conf, conf_text).unwrap();
        let cluster = Cluster {
            dir: dir.to_path_buf(),
            conf: conf.clone(),
        };
        for (daemon, args) in [("slurmctld", vec!["-c"]), ("slurmd", vec![])] {
            let status = Command::new(daemon)
                .arg("-f")
                .arg(&conf)
                .args(args)
                .status()
                .expect("the daemon starts");
            assert!(status.success(), "{daemon} failed:\n{}", cluster.logs());
        }
        let started = Instant::now();
        loop {
            let state = cluster.run("sinfo", &["-h", "-o", "%T"]);
            if state.trim() == "idle" {
                break;
            }
            assert!(
                started.elapsed() < Duration::from_secs(60),
                "the node did not become idle (state '{}'):\n{}",
                state.trim(),
                cluster.logs()
            );
            std::thread::sleep(Duration::from_millis(500));
        }
        cluster
    }

    fn command(&self, cmd: &str) -> Command {
        let mut c = Command::new(cmd);
        c.env("SLURM_CONF", &self.conf);
        c
    }

    fn run(&self, cmd: &str, args: &[&str]) -> String {
        let o = self
            .command(cmd)
            .args(args)
            .output()
            .expect("slurm command");
        String::from_utf8_lossy(&o.stdout).to_string()
    }

    fn logs(&self) -> String {
        ["log/slurmctld.log", "log/slurmd.log", "munge/munged.log"]
            .iter()
            .map(|f| format!("== {f}\n{}", read_or(&self.dir.join(f))))
            .collect()
    }

    /// The job's state (COMPLETED, FAILED, PENDING, …) and the array tasks'.
    fn states(&self, job: &str) -> Vec<String> {
        self.run("scontrol", &["-o", "show", "job", job])
            .lines()
            .map(|l| {
                let field = |k: &str| {
                    l.split_whitespace()
                        .find_map(|w| w.strip_prefix(k))
                        .unwrap_or("?")
                        .to_string()
                };
                let task = field("ArrayTaskId=");
                let id = if task == "?" {
                    field("JobId=")
                } else {
                    format!("{}_{task}", field("ArrayJobId="))
                };
                format!("{id} {}", field("JobState="))
            })
            .collect()
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = self.command("scontrol").arg("shutdown").status();
        std::thread::sleep(Duration::from_millis(500));
        let socket = self.dir.join("munge/munge.socket");
        let _ = Command::new("munged")
            .arg("--stop")
            .arg(format!("--socket={}", socket.display()))
            .status();
        for pid_file in ["slurmctld.pid", "slurmd.pid"] {
            if let Ok(pid) = std::fs::read_to_string(self.dir.join(pid_file)) {
                let _ = Command::new("kill").arg(pid.trim()).status();
            }
        }
    }
}

fn read_or(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| format!("({e})"))
}

fn study(dir: &Path) -> PathBuf {
    let scene = shipped("scenes/wheelset_straight.toml");
    let text = format!(
        r#"title = "Slurm test study"
scene = "{}"
[set]
"run.distance_m" = 3.0
[[vary]]
key = "initial.speed_m_s"
values = [6.0, 8.0, 10.0, 12.0]
[[vary]]
key = "contact.creep_law"
values = ["polach", "heuristic"]
[compute]
kind = "run"
figures = ["wheelsets.0.peak_lateral_mm", "steps"]
"#,
        scene.display()
    );
    let p = dir.join("study.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// Why the test cannot run, said loudly (or, with RAILSIM_REQUIRE_SLURM,
/// a failure); `None` when it can.
fn skip_reason() -> Option<String> {
    let why = missing_prerequisite()?;
    let banner = "#".repeat(78);
    if std::env::var_os("RAILSIM_REQUIRE_SLURM").is_some() {
        panic!("RAILSIM_REQUIRE_SLURM is set but the Slurm test cannot run: {why}");
    }
    eprintln!(
        "\n{banner}\n# NOT RUN: the real-Slurm test of `sim sweep slurm` did not run: {why}.\n# CI runs it (.ci/run installs slurm-wlm and munge and runs as root).\n{banner}\n"
    );
    Some(why)
}

/// Runs `study` locally and as a `shards`-task array plus the merge job on
/// `cluster`; checks that both tables are the same; returns the merged
/// row count.
fn local_and_on_the_cluster(cluster: &Cluster, study: &Path, work: &Path, shards: usize) -> usize {
    let cache = work.join("cache");
    let local = work.join("local");
    let o = run(sim()
        .args([
            "sweep",
            study.to_str().unwrap(),
            "--out",
            local.to_str().unwrap(),
            "--quiet",
        ])
        .env("RAILSIM_CACHE_DIR", &cache));
    assert!(o.status.success(), "local study: {}", stderr(&o));
    let out = work.join("cluster");
    let o = run(sim()
        .args([
            "sweep",
            "slurm",
            study.to_str().unwrap(),
            "--shards",
            &shards.to_string(),
        ])
        .args(["--out", out.to_str().unwrap(), "--submit"])
        .env("SLURM_CONF", &cluster.conf)
        .env("RAILSIM_CACHE_DIR", &cache));
    let text = stdout(&o);
    assert!(
        o.status.success(),
        "sim sweep slurm: {text}{}\n{}",
        stderr(&o),
        cluster.logs()
    );
    eprint!("{text}");
    // "submitted: array job A (tasks 0-3), merge job M (afterok:A)"
    let line = text
        .lines()
        .find(|l| l.starts_with("submitted:"))
        .expect("submitted line");
    let words: Vec<&str> = line.split_whitespace().collect();
    let (array_job, merge_job) = (
        words[3].to_string(),
        words[8].trim_end_matches(',').to_string(),
    );
    assert!(
        [&array_job, &merge_job]
            .iter()
            .all(|id| id.parse::<u64>().is_ok()),
        "{line}"
    );
    let started = Instant::now();
    loop {
        let merge = cluster.states(&merge_job);
        let done = merge.iter().any(|s| s.ends_with("COMPLETED"));
        let failed = merge
            .iter()
            .chain(cluster.states(&array_job).iter())
            .any(|s| s.contains("FAILED") || s.contains("CANCELLED") || s.contains("TIMEOUT"));
        if done || failed {
            break;
        }
        assert!(
            started.elapsed() < Duration::from_secs(1800),
            "the jobs did not finish in 30 min: {:?} {:?}\n{}",
            cluster.states(&array_job),
            merge,
            cluster.logs()
        );
        std::thread::sleep(Duration::from_secs(1));
    }
    let array_states = cluster.states(&array_job);
    let merge_states = cluster.states(&merge_job);
    eprintln!("array job {array_job}: {array_states:?}");
    eprintln!("merge job {merge_job}: {merge_states:?}");
    eprintln!(
        "jobs finished {:.1} s after submission",
        started.elapsed().as_secs_f64()
    );
    assert_eq!(array_states.len(), shards, "{array_states:?}");
    assert!(
        array_states.iter().all(|s| s.ends_with("COMPLETED")),
        "{array_states:?}\n{}",
        read_or(&out.join("slurm/shard_0.out"))
    );
    assert!(
        merge_states.iter().all(|s| s.ends_with("COMPLETED")),
        "{merge_states:?}\n{}",
        read_or(&out.join("slurm/merge.out"))
    );
    let merged = read_or(&out.join("table.csv"));
    let rows = merged.lines().count() - 1;
    eprint!(
        "merged table: {rows} rows; {}",
        read_or(&out.join("slurm/merge.out"))
    );
    assert_eq!(
        merged,
        read_or(&local.join("table.csv")),
        "the cluster's table differs from the local run's"
    );
    rows
}

#[test]
fn a_study_on_a_real_single_node_slurm_cluster() {
    if skip_reason().is_some() {
        return;
    }
    let work = scratch("slurm_cluster");
    let tmp = tempfile::Builder::new()
        .prefix("railsim-slurm")
        .tempdir()
        .expect("a temporary directory");
    let cluster = Cluster::start(tmp.path());
    let study = study(&work);
    assert_eq!(
        local_and_on_the_cluster(&cluster, &study, &work.join("small"), 4),
        8
    );
    // Each task ran its shard: variants I and I + 4.
    for i in 0..4 {
        let shard = read_or(&work.join(format!("small/cluster/shards/shard_{i}_of_4.csv")));
        let ids: Vec<&str> = shard
            .lines()
            .skip(1)
            .map(|l| l.split(',').next().unwrap())
            .collect();
        assert_eq!(ids.len(), 2, "shard {i}: {shard}");
        assert!(
            ids.iter().all(|v| v.parse::<usize>().unwrap() % 4 == i),
            "shard {i}: {shard}"
        );
    }
    // A shipped study (the cheapest: 15 runs of the Cooperrider car).
    let shipped_study = shipped("sweeps/cooperrider_yaw_damper.toml");
    assert_eq!(
        local_and_on_the_cluster(&cluster, &shipped_study, &work.join("yaw_damper"), 4),
        15
    );
    drop(cluster);
}

/// Every shipped study on the cluster (minutes: `cargo test --release
/// --test slurm_cluster -- --ignored --nocapture`).
#[test]
#[ignore]
fn every_shipped_study_on_a_real_single_node_slurm_cluster() {
    if skip_reason().is_some() {
        return;
    }
    let work = scratch("slurm_cluster_shipped");
    let tmp = tempfile::Builder::new()
        .prefix("railsim-slurm")
        .tempdir()
        .expect("a temporary directory");
    let cluster = Cluster::start(tmp.path());
    for (name, rows) in [
        ("bogie_friction_critical_speed", 12),
        ("cooperrider_yaw_damper", 15),
        ("bogie_r250_curving", 14),
    ] {
        let study = shipped(&format!("sweeps/{name}.toml"));
        let started = Instant::now();
        assert_eq!(
            local_and_on_the_cluster(&cluster, &study, &work.join(name), 4),
            rows
        );
        eprintln!(
            "{name}: local run and cluster run in {:.1} s\n",
            started.elapsed().as_secs_f64()
        );
    }
    drop(cluster);
}
