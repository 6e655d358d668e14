//! `sim compare` lines runs up at equal track position (issue 14 §2): the
//! ML95-like wheelset at 10 and 12 m/s over 20 m hunts along the same
//! curve in s (Klingel's wavelength does not depend on the speed), so by
//! position the two differ little, while by time they drift apart by
//! about their amplitude. A file without track positions falls back to
//! the distance travelled, with a warning naming it.

mod common;

use common::*;

const SCENE: &str = "scenes/wheelset_straight.toml";

fn run_at(dir: &std::path::Path, speed: &str) -> std::path::PathBuf {
    let out = dir.join(format!("v{speed}.h5"));
    let o = run(sim()
        .arg("run")
        .arg(shipped(SCENE))
        .arg("-o")
        .arg(&out)
        .args(["--no-plots", "--quiet", "--set", "run.distance_m=20"])
        .args(["--set", &format!("initial.speed_m_s={speed}")]));
    assert!(o.status.success(), "{}", stderr(&o));
    out
}

/// The (max µm, rest of the line) of every "lateral difference" line.
fn differences(out: &str) -> Vec<(f64, String)> {
    out.lines()
        .filter(|l| l.contains("lateral difference max"))
        .map(|l| {
            let after = l.split("max ").nth(1).unwrap();
            let v = after.split(' ').next().unwrap().parse().unwrap();
            (v, l.to_string())
        })
        .collect()
}

#[test]
fn runs_at_two_speeds_agree_by_position_not_by_time() {
    let dir = scratch("compare_by_position");
    let (slow, fast) = (run_at(&dir, "10"), run_at(&dir, "12"));
    let compare = |by: &str, b: &std::path::Path| {
        let o = run(sim()
            .arg("compare")
            .arg(&slow)
            .arg(b)
            .arg("--out")
            .arg(dir.join(format!("{by}.png")))
            .args(["--by", by]));
        assert!(o.status.success(), "{}", stderr(&o));
        (stdout(&o), stderr(&o))
    };
    let (pos, pos_err) = compare("position", &fast);
    let (time, _) = compare("time", &fast);
    let (p, t) = (&differences(&pos)[0], &differences(&time)[0]);
    eprintln!("{}\n{}", p.1, t.1);
    assert!(p.0 < 150.0, "by position: {}", p.1);
    assert!(t.0 > 1000.0, "by time: {}", t.1);
    // The span compared is printed, in metres of track: the slower run's
    // s from 5 m to where the faster one ends (both ran 20 m).
    assert!(p.1.contains("m of track (5.000 …"), "{}", p.1);
    assert!(t.1.contains(" s (t 0.000 …"), "{}", t.1);
    assert!(!pos_err.contains("warning"), "{pos_err}");
    assert!(dir.join("position.png").exists());

    // An older file without track positions: by the distance travelled
    // (the runs started at the same s, so the same numbers), with a
    // warning naming the file.
    let old = dir.join("old.h5");
    std::fs::copy(&fast, &old).unwrap();
    {
        let f = hdf5::File::open_rw(&old).unwrap();
        let g = f.group("wheelset_0").unwrap();
        g.unlink("track_s_m").unwrap();
    }
    let (fell, fell_err) = compare("position", &old);
    let f = &differences(&fell)[0];
    assert!(
        fell_err.contains("warning") && fell_err.contains("old.h5"),
        "{fell_err}"
    );
    assert!(f.1.contains("m of distance travelled"), "{}", f.1);
    assert!((f.0 - p.0).abs() < 1.0, "{} against {}", f.1, p.1);
}
