//! Tracks from design elements (docs/reference/03-track-preproc.md §3h):
//! the two shipped examples build from their design files, and their
//! centreline tables hold the element formulas' curvature, heading and
//! cant (written again here, independently of `preproc::design`) to 1e-6
//! relative; the design model's closed-form cant rate through the build
//! path likewise; joints are continuous; bad files are refused at their
//! line and column. Also: the cant's own spline scheme (pchip by default)
//! keeps a hand-written cant ramp within its values, where the cubic
//! overshoots.

use std::path::{Path, PathBuf};

use preproc::design::DesignInput;
use preproc::inputs::CenterlineInput;
use preproc::{
    BuildConfig, BuildRequest, GeometryFiles, NoProgress, TrackInputs, TrackModel, build_tables,
};
use runtime::geometry::spline::Scheme;
use runtime::geometry::track::TrackTables;

const E0_M: f64 = 1.5;

fn shipped(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tables/tracks")
        .join(rel)
}

/// One element as the example's comment table gives it: length (m),
/// curvature at the ends (1/m), Bloss (else linear) curvature and cant
/// shape, cant height at the ends (mm).
#[derive(Clone, Copy)]
struct El {
    l: f64,
    k0: f64,
    k1: f64,
    bloss: bool,
    h0: f64,
    h1: f64,
}

const fn el(l: f64, k0: f64, k1: f64, bloss: bool, h0: f64, h1: f64) -> El {
    El {
        l,
        k0,
        k1,
        bloss,
        h0,
        h1,
    }
}

fn r600() -> Vec<El> {
    let k = 1.0 / 600.0;
    vec![
        el(200.0, 0.0, 0.0, false, 0.0, 0.0),
        el(80.0, 0.0, -k, false, 0.0, 120.0),
        el(300.0, -k, -k, false, 120.0, 120.0),
        el(80.0, -k, 0.0, false, 120.0, 0.0),
        el(80.0, 0.0, k, false, 0.0, -120.0),
        el(200.0, k, k, false, -120.0, -120.0),
        el(80.0, k, 0.0, false, -120.0, 0.0),
        el(100.0, 0.0, 0.0, false, 0.0, 0.0),
    ]
}

fn r250() -> Vec<El> {
    let k = 1.0 / 250.0;
    vec![
        el(100.0, 0.0, 0.0, false, 0.0, 0.0),
        el(60.0, 0.0, k, false, 0.0, -120.0),
        el(120.0, k, k, false, -120.0, -120.0),
        el(60.0, k, 0.0, false, -120.0, 0.0),
        el(90.0, 0.0, -k, true, 0.0, 120.0),
        el(120.0, -k, -k, true, 120.0, 120.0),
        el(90.0, -k, 0.0, true, 120.0, 0.0),
        el(100.0, 0.0, 0.0, false, 0.0, 0.0),
    ]
}

/// The formulas at s: (κ, θ, φ, dφ/ds). Linear: f = u, F = u²/2;
/// Bloss: f = 3u² − 2u³, F = u³ − u⁴/2, f' = 6u − 6u².
fn formulas(els: &[El], s: f64) -> (f64, f64, f64, f64) {
    let (mut s0, mut th0) = (0.0, 0.0);
    for (i, e) in els.iter().enumerate() {
        // At a joint, the element that starts there (as the model does).
        if s < s0 + e.l || i == els.len() - 1 {
            let u = ((s - s0) / e.l).clamp(0.0, 1.0);
            let (f, big_f, df) = if e.bloss {
                (
                    3.0 * u * u - 2.0 * u * u * u,
                    u * u * u - 0.5 * u * u * u * u,
                    6.0 * u - 6.0 * u * u,
                )
            } else {
                (u, 0.5 * u * u, 1.0)
            };
            let kappa = e.k0 + (e.k1 - e.k0) * f;
            let theta = th0 + e.k0 * u * e.l + (e.k1 - e.k0) * e.l * big_f;
            let h = 1e-3 * (e.h0 + (e.h1 - e.h0) * f);
            let dh = 1e-3 * (e.h1 - e.h0) * df / e.l;
            return (
                kappa,
                theta,
                (h / E0_M).asin(),
                dh / (E0_M * E0_M - h * h).sqrt(),
            );
        }
        s0 += e.l;
        th0 += 0.5 * (e.k0 + e.k1) * e.l;
    }
    unreachable!()
}

fn request(design: &str) -> BuildRequest {
    BuildRequest {
        geometry: GeometryFiles::Design(shipped(design)),
        irregularities: None,
        output: PathBuf::from("unused.h5"),
        config: BuildConfig::default(),
        contact: None,
        command_line: String::new(),
    }
}

fn build(design: &str) -> (TrackTables, TrackModel) {
    let req = request(design);
    let (tables, provenance) = build_tables(&req, &NoProgress).expect("builds");
    assert!(
        provenance
            .inputs
            .iter()
            .any(|i| i.role == "design" && i.text.contains("[[element]]")),
        "the design file is recorded"
    );
    assert_eq!(tables.meta.cant_scheme, "design");
    let (inputs, _) = preproc::pipeline::read_inputs(&req).expect("reads");
    let model = TrackModel::from_inputs(&inputs, &req.config).expect("model");
    (tables, model)
}

/// |a − b| within 1e-6 of |b| (or of `scale` where b is 0).
fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-6 * b.abs().max(scale)
}

fn check_example(design: &str, els: &[El], radius_m: f64) {
    let (tables, model) = build(design);
    let total: f64 = els.iter().map(|e| e.l).sum();
    assert!((tables.centerline.length_m() - total).abs() < 1e-9);
    let d = model.centerline.design().expect("a design track");
    let k_scale = 1.0 / radius_m;
    let phi_scale = (0.12_f64 / E0_M).asin();
    for r in tables.centerline.rows() {
        let (kappa, theta, phi, dphi) = formulas(els, r.s_m);
        let s = r.s_m;
        assert!(
            close(r.horizontal_curvature_1_m, kappa, k_scale),
            "{design} s {s}: κ {} vs {kappa}",
            r.horizontal_curvature_1_m
        );
        assert!(
            close(r.curvature_1_m, kappa.abs(), k_scale),
            "{design} s {s}"
        );
        let heading = r.t[1].atan2(r.t[0]);
        assert!(
            close(heading, theta, 1e-3),
            "{design} s {s}: θ {heading} vs {theta}"
        );
        assert!(
            close(r.cant_rad, phi, phi_scale),
            "{design} s {s}: φ {} vs {phi}",
            r.cant_rad
        );
        let p = d.at(s);
        assert!(
            close(p.cant_rate_rad_m, dphi, phi_scale / 60.0),
            "{design} s {s}: dφ/ds {} vs {dphi}",
            p.cant_rate_rad_m
        );
        // The frame is rolled by the cant: b·Z = cos φ.
        assert!((r.b[2] - phi.cos()).abs() < 1e-9, "{design} s {s}");
    }
}

#[test]
fn r600_design_matches_the_element_formulas() {
    check_example("r600_design.toml", &r600(), 600.0);
}

#[test]
fn r250_reverse_matches_the_element_formulas() {
    check_example("r250_reverse.toml", &r250(), 250.0);
}

/// Position, heading, curvature and cant are continuous at every element
/// joint of both examples (across ±1 nm: to 1e-8 m, 1e-10 rad, 1e-10 1/m), and the arcs'
/// points lie on their circles to 1e-9 m (the quadrature's accuracy).
#[test]
fn joints_are_continuous_and_arcs_are_circles() {
    for design in ["r600_design.toml", "r250_reverse.toml"] {
        let (_, model) = build(design);
        let d = model.centerline.design().unwrap();
        let joints = d.joints_s_m().to_vec();
        for &s in &joints[1..joints.len() - 1] {
            let (a, b) = (d.at(s - 1e-9), d.at(s + 1e-9));
            assert!((a.position - b.position).norm() < 1e-8, "{design} {s}");
            assert!(
                (a.heading_rad - b.heading_rad).abs() < 1e-10,
                "{design} {s}"
            );
            assert!(
                (a.curvature_1_m - b.curvature_1_m).abs() < 1e-10,
                "{design} {s}"
            );
            assert!((a.cant_rad - b.cant_rad).abs() < 1e-10, "{design} {s}");
        }
        // The first arc (third element): a circle about its centre.
        let (s0, s1) = (joints[2], joints[3]);
        let p0 = d.at(s0);
        let r = 1.0 / p0.curvature_1_m;
        let centre = p0.position.xy()
            + r * nalgebra::Vector2::new(-p0.heading_rad.sin(), p0.heading_rad.cos());
        for k in 0..=100 {
            let p = d.at(s0 + (s1 - s0) * f64::from(k) / 100.0);
            assert!(
                ((p.position.xy() - centre).norm() - r.abs()).abs() < 1e-9,
                "{design} {}",
                p.s_m
            );
        }
    }
}

/// A grade with a parabolic vertical curve: s is the 3D arc length, the
/// table's tangent climbs at the grade, and the vertical curvature is the
/// formula's g'/(1 + g²)^{3/2}.
#[test]
fn grades_and_vertical_curves() {
    let text = "[[element]]\ntype = \"straight\"\nlength_m = 300.0\n\
        [[vertical]]\ntype = \"grade\"\nlength_m = 100.0\ngrade_permille = 0\n\
        [[vertical]]\ntype = \"curve\"\nlength_m = 100.0\ngrade_end_permille = 20\n\
        [[vertical]]\ntype = \"grade\"\nlength_m = 100.0\n";
    let input = DesignInput::parse(Path::new("v.toml"), text, E0_M).unwrap();
    let d = preproc::design::DesignTrack::build(&input).unwrap();
    // 100 + ∫√(1+g²) over the curve + 100·√(1 + 0.02²).
    let g1: f64 = 0.02;
    let hh = |u: f64| 0.5 * (u * (1.0 + u * u).sqrt() + u.asinh());
    let expect = 100.0 + (hh(g1) - hh(0.0)) / (g1 / 100.0) + 100.0 * (1.0 + g1 * g1).sqrt();
    assert!(
        (d.length_m() - expect).abs() < 1e-9,
        "{} {expect}",
        d.length_m()
    );
    let p = d.at(d.length_m() - 1.0);
    assert!((p.position.z - (1.0 + 0.02 * (p.sigma_m - 200.0))).abs() < 1e-9);
    let c = d.at(150.0).curve_point();
    assert!((c.d1.norm() - 1.0).abs() < 1e-15);
    let g = d.at(150.0).grade;
    let kv = (g1 / 100.0) / (1.0 + g * g).powf(1.5);
    assert!(
        (c.curvature() - kv).abs() < 1e-6 * kv,
        "{} {kv}",
        c.curvature()
    );
}

/// Every rule broken is named at its line and column; values beyond the
/// plausibility bounds say "check the unit".
#[test]
fn bad_files_are_refused_at_their_line_and_column() {
    let parse = |t: &str| {
        DesignInput::parse(Path::new("bad.toml"), t, E0_M)
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let head = "[[element]]\ntype = \"straight\"\nlength_m = 100.0\n";
    // A radius in km.
    let e = parse(&format!(
        "{head}[[element]]\ntype = \"transition\"\nlength_m = 80\nradius_end_m = 0.6\n"
    ));
    assert!(
        e.starts_with("bad.toml, line 7, column 16: radius_end_m = 0.6 m")
            && e.contains("check the unit"),
        "{e}"
    );
    // Cant in metres in a mm key.
    let e = parse(&format!(
        "{head}[[element]]\ntype = \"transition\"\nlength_m = 80\nradius_end_m = -600\ncant_end_mm = 0.12\n"
    ));
    assert!(
        e.starts_with("bad.toml, line 8, column 15:") && e.contains("check the unit"),
        "{e}"
    );
    // Cant beyond 200 mm.
    let e = parse(&format!(
        "{head}[[element]]\ntype = \"transition\"\nlength_m = 80\nradius_end_m = -600\ncant_end_mm = 250\n"
    ));
    assert!(e.contains("line 8") && e.contains("check the unit"), "{e}");
    // A negative length.
    let e = parse("[[element]]\ntype = \"straight\"\nlength_m = -5\n");
    assert!(
        e.starts_with("bad.toml, line 3, column 12:") && e.contains("check the unit"),
        "{e}"
    );
    // An arc straight after a straight: curvature step.
    let e = parse(&format!(
        "{head}[[element]]\ntype = \"arc\"\nlength_m = 80\nradius_m = 600\n"
    ));
    assert!(
        e.starts_with("bad.toml, line 7, column 12:") && e.contains("transition"),
        "{e}"
    );
    // ... allowed with jump = true.
    assert!(
        DesignInput::parse(
            Path::new("ok.toml"),
            &format!(
                "{head}[[element]]\ntype = \"arc\"\nlength_m = 80\nradius_m = 600\njump = true\n"
            ),
            E0_M
        )
        .is_ok()
    );
    // A cant step.
    let e = parse(&format!(
        "{head}[[element]]\ntype = \"straight\"\nlength_m = 80\ncant_mm = 50\n"
    ));
    assert!(
        e.starts_with("bad.toml, line 7, column 11:") && e.contains("steps"),
        "{e}"
    );
    // Cant raising the inner rail (sign convention).
    let e = parse(&format!(
        "{head}[[element]]\ntype = \"transition\"\nlength_m = 80\nradius_end_m = 600\ncant_end_mm = 120\n"
    ));
    assert!(e.contains("line 8") && e.contains("negative cant"), "{e}");
    // An unknown key, and a TOML syntax error.
    let e = parse("[[element]]\ntype = \"straight\"\nlenght_m = 5\n");
    assert!(e.starts_with("bad.toml, line 3, column 1:"), "{e}");
    let e = parse("[[element]]\ntype = \n");
    assert!(e.starts_with("bad.toml, line 2"), "{e}");
    // A cubic parabola between two arcs; too sharp for its length.
    let e = parse(
        "[[element]]\ntype = \"arc\"\nlength_m = 50\nradius_m = 600\n[[element]]\ntype = \"transition\"\nshape = \"cubic-parabola\"\nlength_m = 80\nradius_end_m = 300\n",
    );
    assert!(
        e.contains("line 7") && e.contains("from or to a straight"),
        "{e}"
    );
    let input = DesignInput::parse(
        Path::new("cp.toml"),
        &format!("{head}[[element]]\ntype = \"transition\"\nshape = \"cubic-parabola\"\nlength_m = 80\nradius_end_m = 50\n"),
        E0_M,
    )
    .unwrap();
    let e = preproc::design::DesignTrack::build(&input)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("cp.toml, line 4:") && e.contains("cubic parabola"),
        "{e}"
    );
    // A length in mm, one element or all of them beyond 10⁷ m.
    let e = parse("[[element]]\ntype = \"straight\"\nlength_m = 2e7\n");
    assert!(
        e.starts_with("bad.toml, line 3, column 12:") && e.contains("check the unit"),
        "{e}"
    );
    let e = parse(
        "[[element]]\ntype = \"straight\"\nlength_m = 6e6\n[[element]]\ntype = \"straight\"\nlength_m = 6e6\n",
    );
    assert!(
        e.contains("add up to") && e.contains("check the unit"),
        "{e}"
    );
    // A grade in a fraction.
    let e = parse(&format!(
        "{head}[[vertical]]\ntype = \"grade\"\nlength_m = 100\ngrade_permille = 0.012\n"
    ));
    assert!(e.contains("line 7") && e.contains("check the unit"), "{e}");
}

/// Every transition shape builds, ends at the arc's curvature, and the
/// cubic parabola's table curvature reaches exactly 1/R at its end.
#[test]
fn every_transition_shape_builds() {
    for shape in ["clothoid", "cubic-parabola", "bloss", "cosine"] {
        let text = format!(
            "[[element]]\ntype = \"straight\"\nlength_m = 50\n\
             [[element]]\ntype = \"transition\"\nshape = \"{shape}\"\nlength_m = 80\nradius_end_m = -600\ncant_end_mm = 100\n\
             [[element]]\ntype = \"arc\"\nlength_m = 100\nradius_m = -600\n\
             [[element]]\ntype = \"transition\"\nshape = \"{shape}\"\nlength_m = 80\nradius_end_m = inf\ncant_end_mm = 0\n\
             [[element]]\ntype = \"straight\"\nlength_m = 50\n"
        );
        let input = DesignInput::parse(Path::new("s.toml"), &text, E0_M).unwrap();
        let d = preproc::design::DesignTrack::build(&input).unwrap();
        for s in [130.0, 230.0] {
            let p = d.at(s);
            assert!(
                (p.curvature_1_m * -600.0 - 1.0).abs() < 1e-12,
                "{shape} {s}"
            );
            assert!(
                (p.cant_rad - (0.1_f64 / E0_M).asin()).abs() < 1e-12,
                "{shape} {s}"
            );
        }
        // Symmetric: the track ends heading back along +X turned by the arc
        // and both transitions (−(100 + 80)/600 rad for every shape whose
        // mean f is 1/2, the cubic parabola too by its construction).
        let end = d.at(d.length_m());
        if shape != "cubic-parabola" {
            assert!((end.heading_rad + 180.0 / 600.0).abs() < 1e-12, "{shape}");
        }
    }
}

fn ramp_mm(s: f64) -> f64 {
    if s <= 200.0 {
        0.0
    } else if s <= 280.0 {
        120.0 * (s - 200.0) / 80.0
    } else if s <= 580.0 {
        120.0
    } else if s <= 660.0 {
        120.0 * (660.0 - s) / 80.0
    } else {
        0.0
    }
}

/// Issue 14: a hand-written cant ramp 0 → 120 mm (control points at the
/// element joints of the R 600 m example and at most 40 m apart inside
/// each, cant_mm on the ramp) rings with the cubic spline — below 0 on the
/// straight before the curve and to a 124.3 mm peak — and stays within
/// [0, 120 mm] with the cant's default scheme, pchip.
#[test]
fn the_cant_scheme_defaults_to_pchip_and_keeps_a_ramp_within_its_values() {
    let joints: [f64; 6] = [0.0, 200.0, 280.0, 580.0, 660.0, 860.0];
    let mut s = vec![0.0];
    for w in joints.windows(2) {
        let m = ((w[1] - w[0]) / 40.0).ceil() as usize;
        for k in 1..=m {
            s.push(w[0] + (w[1] - w[0]) * k as f64 / m as f64);
        }
    }
    let mut csv = String::from("x,y,z,cant_mm\n");
    for &x in &s {
        csv += &format!("{x},0,0,{}\n", ramp_mm(x));
    }
    let centerline = CenterlineInput::parse(Path::new("ramp.csv"), &csv).unwrap();
    let inputs = TrackInputs {
        centerline,
        cant: None,
        irregularities: None,
    };
    let cant_mm = |cant_scheme: Scheme| -> (f64, f64, TrackTables) {
        let config = BuildConfig {
            cant_scheme,
            ..BuildConfig::default()
        };
        let tables = TrackModel::build(&inputs, &config)
            .unwrap()
            .tabulate(&NoProgress)
            .unwrap();
        let mm = |r: &runtime::geometry::track::CenterlineRow| E0_M * r.cant_rad.sin() * 1e3;
        let rows = tables.centerline.rows();
        let before = rows
            .iter()
            .filter(|r| r.s_m < 200.0)
            .map(mm)
            .fold(f64::INFINITY, f64::min);
        let peak = rows.iter().map(mm).fold(f64::NEG_INFINITY, f64::max);
        (before, peak, tables)
    };
    let (before, peak, _) = cant_mm(Scheme::Cubic);
    assert!(
        before < -4.5 && (peak - 124.3).abs() < 0.05,
        "cubic: {before} {peak}"
    );
    assert_eq!(BuildConfig::default().cant_scheme, Scheme::Pchip);
    let (before, peak, tables) = cant_mm(BuildConfig::default().cant_scheme);
    assert!(
        before >= -1e-9 && peak <= 120.0 + 1e-9,
        "pchip: {before} {peak}"
    );
    assert_eq!(tables.meta.cant_scheme, "pchip");
    assert_eq!(tables.meta.scheme, "cubic");
}
