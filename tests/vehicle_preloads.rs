//! The static preload solve on the shipped vehicles
//! (docs/reference/08-multibody.md §8.3): with every `preload_n` removed,
//! the solved preloads equal the hand-written ones, and a run with them
//! keeps the results of the given preloads; `preload = "given"` keeps the
//! old equilibrium check and its message.

mod common;

use common::*;
use railsim::config::statics::PreloadMode;
use railsim::config::vehicle::VehicleFile;

/// The shipped file's text with its profile paths made absolute (so that a
/// variant can live in a scratch directory).
fn shipped_text(name: &str) -> String {
    let path = shipped(&format!("vehicles/{name}"));
    let text = std::fs::read_to_string(&path).unwrap();
    let profiles = shipped("profiles");
    text.replace("\"../profiles", &format!("\"{}", profiles.display()))
}

/// Without any `preload_n` line (the solve alone).
fn stripped(text: &str) -> String {
    text.lines()
        .filter(|l| !l.trim_start().starts_with("preload_n"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// With `preload = "given"` (the hand-written preloads as the old code
/// used them).
fn given(text: &str) -> String {
    let at = text.find("\nname = ").expect("a top-level name");
    format!("{}\npreload = \"given\"{}", &text[..at], &text[at..])
}

fn resolved(text: &str) -> VehicleFile {
    let mut v = VehicleFile::parse(text).unwrap();
    v.resolve().unwrap_or_else(|e| panic!("{e:#}"));
    v
}

/// Largest difference between the solved preloads (no `preload_n` in the
/// file) and the hand-written ones, relative to the largest preload:
/// below 1e-9 (the SVD solve's rounding is ~1e-12 relative; the
/// hand-written values are exact decimals of m g / n).
#[test]
fn solved_preloads_equal_the_hand_written_ones() {
    for name in ["ml95_like_bogie.toml", "cooperrider_car.toml"] {
        let text = shipped_text(name);
        let hand = resolved(&given(&text));
        assert_eq!(hand.statics.as_ref().unwrap().mode, PreloadMode::Given);
        let solved = resolved(&stripped(&text));
        let s = solved.statics.as_ref().unwrap();
        assert_eq!(s.mode, PreloadMode::Solve);
        let h = hand.element_preloads_n();
        let p = solved.element_preloads_n();
        let scale = h.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(scale > 4e4, "{name}: {scale}");
        let mut worst = 0.0_f64;
        for ((e, a), b) in hand.elements.iter().zip(&h).zip(&p) {
            for k in 0..3 {
                let d = (a[k] - b[k]).abs() / scale;
                assert!(d < 1e-9, "{name}: element '{}': {a:?} vs {b:?}", e.name);
                worst = worst.max(d);
            }
        }
        // The wheel loads follow.
        for w in &hand.wheelsets {
            let (qa, qb) = (hand.static_wheel_load_n(w), solved.static_wheel_load_n(w));
            assert!((qa - qb).abs() < 1e-9 * qa, "{name}: {qa} vs {qb}");
        }
        // Residuals at rounding level (N, N·m).
        for (body, f, m) in &s.residual {
            let worst_fm = f.iter().chain(m).fold(0.0_f64, |a, v| a.max(v.abs()));
            assert!(worst_fm < 1e-6, "{name}: {body}: {f:?} {m:?}");
        }
        println!("{name}: worst relative preload difference {worst:.1e}");
        // The shipped file (hand-written preload_n kept as constant forces,
        // solved on top) gives the same preloads.
        let shipped = resolved(&text);
        for (a, b) in h.iter().zip(shipped.element_preloads_n()) {
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() < 1e-9 * scale);
            }
        }
        // The report names every element and body.
        let table = s.table(&solved);
        assert!(table.contains("solved for static equilibrium"), "{table}");
        assert!(table.contains(&solved.elements[0].name), "{table}");
        assert!(table.contains("residual on"), "{table}");
    }
}

/// `preload = "given"` keeps the old rule and its message; the same file
/// with the solve (default) is accepted.
#[test]
fn given_preloads_keep_the_equilibrium_check() {
    let text = shipped_text("ml95_like_bogie.toml");
    let bad = given(&text).replace("-67885.2", "-60000.0");
    let e = VehicleFile::parse(&bad).unwrap().resolve().unwrap_err();
    let msg = format!("{e:#}");
    assert!(
        msg.contains("body 'frame' is not in static equilibrium at assembly: net force"),
        "{msg}"
    );
    let solved = resolved(&text.replace("-67885.2", "-60000.0"));
    // The air springs now carry the car share whatever preload_n says.
    let p = solved.element_preloads_n();
    let air: Vec<_> = solved
        .elements
        .iter()
        .zip(&p)
        .filter(|(e, _)| e.body_a == "car")
        .collect();
    for (_, pre) in air {
        assert!((pre[2] + 67_885.2).abs() < 1e-6, "{pre:?}");
    }
}

/// Lateral displacement of wheelset `w` over the run in `file` (m).
fn lateral(file: &std::path::Path, w: usize) -> Vec<f64> {
    let f = hdf5::File::open(file).unwrap();
    f.dataset(&format!("wheelset_{w}/lateral_m"))
        .unwrap()
        .read_raw()
        .unwrap()
}

fn run_with(
    dir: &std::path::Path,
    scene: &str,
    vehicle: &std::path::Path,
    out: &str,
    extra: &[&str],
) -> std::path::PathBuf {
    let out = dir.join(out);
    let mut cmd = sim();
    cmd.arg("run")
        .arg(shipped(scene))
        .arg("-o")
        .arg(&out)
        .args(["--no-plots", "--quiet"])
        .args(["--set", &format!("vehicle.file=\"{}\"", vehicle.display())]);
    for e in extra {
        cmd.args(["--set", e]);
    }
    let o = run(&mut cmd);
    assert!(o.status.success(), "{}", stderr(&o));
    // `sim run` prints the preload table before the run.
    let text = stdout(&o);
    assert!(
        text.contains("static preloads, solved for static equilibrium")
            || text.contains("static preloads, as given"),
        "{text}"
    );
    assert!(text.contains("residual on '"), "{text}");
    out
}

/// A short run of each shipped vehicle with the solved preloads (no
/// `preload_n` in the file) against the given ones: the lateral
/// displacements agree to 1e-9 m (the preloads differ by rounding only,
/// ~1e-10 N).
#[test]
fn runs_with_solved_preloads_keep_their_results() {
    let dir = scratch("vehicle_preloads");
    for (name, scene, wheelsets, duration) in [
        (
            "ml95_like_bogie.toml",
            "scenes/bogie_straight.toml",
            2,
            "run.distance_m=3",
        ),
        (
            "cooperrider_car.toml",
            "scenes/cooperrider_straight.toml",
            4,
            "run.duration_s=0.3",
        ),
    ] {
        let text = shipped_text(name);
        let given_path = dir.join(format!("given_{name}"));
        let solved_path = dir.join(format!("solved_{name}"));
        std::fs::write(&given_path, given(&text)).unwrap();
        std::fs::write(&solved_path, stripped(&text)).unwrap();
        let a = run_with(
            &dir,
            scene,
            &given_path,
            &format!("given_{name}.h5"),
            &[duration],
        );
        let b = run_with(
            &dir,
            scene,
            &solved_path,
            &format!("solved_{name}.h5"),
            &[duration],
        );
        for w in 0..wheelsets {
            let (la, lb) = (lateral(&a, w), lateral(&b, w));
            assert_eq!(la.len(), lb.len());
            assert!(la.len() > 10);
            let worst = la
                .iter()
                .zip(&lb)
                .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
            let moved = la.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            assert!(moved > 1e-4, "{name}: wheelset {w} does not move");
            assert!(worst < 1e-9, "{name}: wheelset {w}: {worst:e} m");
            println!("{name}: wheelset {w}: lateral difference {worst:.1e} m");
        }
    }
}

/// The bogie with a lateral bump stop on each wheelset (0.5 mm free play,
/// so the 2 mm start engages it) and two yaw dampers with blow-off and
/// bushes runs through `sim run`, and its wheelsets move differently from
/// the plain bogie's (the nonlinear elements act).
#[test]
fn a_bogie_with_nonlinear_elements_runs() {
    let dir = scratch("vehicle_preloads_nonlinear");
    let text = shipped_text("ml95_like_bogie.toml");
    let mut extra = String::new();
    for (ws, x) in [("front", 1.05), ("rear", -1.05)] {
        extra += &format!(
            "\n[[elements]]\nname = \"bump stop {ws}\"\nbody_a = \"frame\"\nbody_b = \"{ws}\"\npoint_m = [{x}, 0.0, 0.43]\n[elements.spring.y]\nkind = \"bump_stop\"\nclearance_m = 0.0005\nstiffness_n_m = 5.0e6\n"
        );
    }
    for y in [1.3, -1.3] {
        extra += &format!(
            "\n[[elements]]\nname = \"yaw damper {y}\"\nbody_a = \"car\"\nbody_b = \"frame\"\npoint_m = [0.0, {y}, 0.6]\n[elements.damper.x]\nkind = \"bilinear\"\ndamping_n_s_m = 2.0e6\nblow_off_m_s = 0.02\ndamping_beyond_n_s_m = 1.0e5\n[elements.series.x]\nstiffness_n_m = 6.0e6\ndamping_n_s_m = 2.0e6\n"
        );
    }
    let plain = dir.join("plain.toml");
    let nonlinear = dir.join("nonlinear.toml");
    std::fs::write(&plain, &text).unwrap();
    std::fs::write(&nonlinear, format!("{text}\n{extra}")).unwrap();
    let scene = "scenes/bogie_straight.toml";
    let a = run_with(&dir, scene, &plain, "plain.h5", &["run.distance_m=3"]);
    let b = run_with(
        &dir,
        scene,
        &nonlinear,
        "nonlinear.h5",
        &["run.distance_m=3"],
    );
    let (la, lb) = (lateral(&a, 0), lateral(&b, 0));
    let differ = la
        .iter()
        .zip(&lb)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(lb.iter().all(|v| v.is_finite()));
    assert!(
        differ > 1e-6,
        "the nonlinear elements changed nothing: {differ:e} m"
    );
    println!("front wheelset: lateral difference {differ:.2e} m");
}
