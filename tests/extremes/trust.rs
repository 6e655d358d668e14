//! Trust (issue 12): nothing lost, nothing silently wrong. Each test checks
//! one class of fault for every binary it concerns.

use std::process::{Command, Stdio};

use super::common::*;

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
    ]);
    closed_pipe(contact, "sim contact");
    let build = |out: &str| {
        let mut c = track_preproc();
        c.args([
            "build",
            "--centerline",
            shipped("tracks/straight_300m/centerline.csv")
                .to_str()
                .unwrap(),
            "-o",
            dir.join(out).to_str().unwrap(),
        ]);
        c
    };
    let o = run(&mut build("straight.h5"));
    assert!(o.status.success(), "{}", stderr(&o));
    closed_pipe(build("again.h5"), "track-preproc build");
    let mut probe = sim();
    probe.args([
        "probe",
        dir.join("straight.h5").to_str().unwrap(),
        "--s",
        "10",
    ]);
    closed_pipe(probe, "sim probe");
}
