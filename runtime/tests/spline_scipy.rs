//! `runtime::geometry::spline::PiecewiseCubic` against SciPy.
//!
//! The reference values in `tests/data/spline_reference.json` are produced by
//! `tests/data/make_spline_reference.py` (SciPy `CubicSpline` not-a-knot and
//! natural, `Akima1DInterpolator(method="akima", extrapolate=True)`,
//! `PchipInterpolator`); see that script for the data sets and evaluation
//! points. Floats are stored as decimal strings and parsed with
//! `str::parse::<f64>`, which is correctly rounded (serde_json's default
//! number parser is not, and an ulp matters for the points just below a knot).
//!
//! # Tolerance
//!
//! For each case (data set × scheme) and each quantity q ∈ {value, d1, d2}
//! with reference values r_j and our values o_j at the evaluation points,
//!
//! ```text
//! |o_j − r_j| ≤ TOL · max(|r_j|, FLOOR · max_k |r_k|),   TOL = 1e-12, FLOOR = 0.1
//! ```
//!
//! i.e. a pointwise relative error of 1e-12 wherever |r_j| is at least a tenth
//! of the case's largest |q|, and an absolute error of 1e-13 · max|q| nearer
//! to a zero of q, where a relative error measures only cancellation. Where
//! every r_j is exactly zero, o_j must be exactly zero.
//!
//! Measured (SciPy 1.17.1): the sup-norm relative error |o − r| / max|r| is
//! below 5e-14 for every scheme and quantity, and the floored error above
//! stays below 4e-13. The largest errors are second derivatives of the C²
//! splines, which are ill-conditioned in the slopes (an error δ in a knot
//! slope moves d2 by ~δ/h); SciPy's own d2 differs from exact arithmetic by
//! about as much. A floor of 1e-2 fails on `clustered_knots` (1.2e-12) for that
//! reason, not because of a difference in the method.

use std::sync::OnceLock;

use runtime::geometry::spline::{PiecewiseCubic, Scheme};
use serde::{Deserialize, Deserializer};

/// Relative tolerance (module docs).
const TOL: f64 = 1e-12;
/// Floor of the relative-error denominator, as a fraction of the case's
/// largest |reference| of the quantity (module docs).
const FLOOR: f64 = 0.1;

/// Data sets the reference file must contain for every scheme.
const REQUIRED_SETS: [&str; 14] = [
    "smooth_nonuniform",
    "uniform_linspace",
    "uniform_seeded",
    "clustered_knots",
    "step",
    "corner_flat_runs",
    "akima_near_degenerate",
    "pchip_end_cases",
    "small_n2",
    "small_n3",
    "small_n4",
    "small_n5",
    "track_wide",
    "track_offset",
];

#[derive(Debug, Deserialize)]
struct Reference {
    scipy_version: String,
    numpy_version: String,
    cases: Vec<Case>,
}

#[derive(Debug, Deserialize)]
struct Case {
    name: String,
    scheme: String,
    #[serde(deserialize_with = "floats")]
    x: Vec<f64>,
    #[serde(deserialize_with = "floats")]
    y: Vec<f64>,
    #[serde(deserialize_with = "floats")]
    eval_x: Vec<f64>,
    #[serde(deserialize_with = "floats")]
    value: Vec<f64>,
    #[serde(deserialize_with = "floats")]
    d1: Vec<f64>,
    #[serde(deserialize_with = "floats")]
    d2: Vec<f64>,
}

/// A list of decimal strings, parsed exactly.
fn floats<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    let strings = Vec::<String>::deserialize(d)?;
    strings
        .iter()
        .map(|s| s.parse::<f64>().map_err(serde::de::Error::custom))
        .collect()
}

fn reference() -> &'static Reference {
    static REFERENCE: OnceLock<Reference> = OnceLock::new();
    REFERENCE.get_or_init(|| {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/spline_reference.json"
        );
        let text =
            std::fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {path}: {e}"));
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("cannot parse {path}: {e}"))
    })
}

fn cases_of(scheme: Scheme) -> Vec<&'static Case> {
    reference()
        .cases
        .iter()
        .filter(|c| c.scheme == scheme.name())
        .collect()
}

/// The worst error of one quantity over all cases of a scheme.
#[derive(Debug, Default)]
struct Worst {
    /// Error as defined in the module docs (relative to the floored |ref|).
    error: f64,
    /// Largest |o − r| / max_k |r_k| (sup-norm relative error), for the report.
    sup_norm: f64,
    case: String,
    x: f64,
    ours: f64,
    reference: f64,
    points: usize,
}

impl Worst {
    fn line(&self, quantity: &str) -> String {
        format!(
            "{quantity:>5}: worst error {:.3e} (sup-norm relative {:.3e}) over {} points; \
             worst at case {} x = {:e}: ours {:e}, SciPy {:e}",
            self.error, self.sup_norm, self.points, self.case, self.x, self.ours, self.reference
        )
    }
}

fn check_scheme(scheme: Scheme) {
    let cases = cases_of(scheme);
    assert!(!cases.is_empty(), "no reference cases for {scheme}");

    type Eval = fn(&PiecewiseCubic, f64) -> f64;
    let quantities: [(&str, Eval); 3] = [
        ("value", PiecewiseCubic::value),
        ("d1", PiecewiseCubic::d1),
        ("d2", PiecewiseCubic::d2),
    ];
    let mut worst: [Worst; 3] = Default::default();

    for case in &cases {
        let spline = PiecewiseCubic::fit(scheme, &case.x, &case.y)
            .unwrap_or_else(|e| panic!("{scheme} fit of {} failed: {e}", case.name));
        let refs = [&case.value, &case.d1, &case.d2];
        for ((_, eval), (refs, worst)) in quantities.iter().zip(refs.iter().zip(&mut worst)) {
            assert_eq!(refs.len(), case.eval_x.len(), "{}", case.name);
            let scale = refs.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
            for (&x, &r) in case.eval_x.iter().zip(refs.iter()) {
                let ours = eval(&spline, x);
                let diff = (ours - r).abs();
                let denominator = r.abs().max(FLOOR * scale);
                let (error, sup_norm) = if diff.is_nan() {
                    (f64::INFINITY, f64::INFINITY)
                } else if scale == 0.0 {
                    // All references exactly zero: demand exactly zero.
                    let e = if diff == 0.0 { 0.0 } else { f64::INFINITY };
                    (e, e)
                } else {
                    (diff / denominator, diff / scale)
                };
                if error > worst.error || worst.points == 0 {
                    worst.error = error;
                    worst.case = case.name.clone();
                    worst.x = x;
                    worst.ours = ours;
                    worst.reference = r;
                }
                worst.sup_norm = worst.sup_norm.max(sup_norm);
                worst.points += 1;
            }
        }
    }

    let report: Vec<String> = quantities
        .iter()
        .zip(&worst)
        .map(|((name, _), w)| w.line(name))
        .collect();
    let report = format!(
        "{scheme} vs SciPy {} ({} cases, tolerance {TOL:e}, floor {FLOOR:e}·max|ref|):\n  {}",
        reference().scipy_version,
        cases.len(),
        report.join("\n  ")
    );
    eprintln!("{report}");
    for w in &worst {
        assert!(w.points > 0, "{report}");
        assert!(w.error <= TOL, "tolerance exceeded\n{report}");
    }
}

#[test]
fn cubic_not_a_knot_matches_scipy() {
    check_scheme(Scheme::Cubic);
}

#[test]
fn cubic_natural_matches_scipy() {
    check_scheme(Scheme::CubicNatural);
}

#[test]
fn akima_matches_scipy() {
    check_scheme(Scheme::Akima);
}

#[test]
fn pchip_matches_scipy() {
    check_scheme(Scheme::Pchip);
}

/// The reference file covers every scheme, every required data set, and the
/// evaluation points the script promises (so it cannot silently shrink).
#[test]
fn reference_file_covers_all_schemes_and_data_sets() {
    let reference = reference();
    assert!(!reference.scipy_version.is_empty());
    assert!(!reference.numpy_version.is_empty());
    for scheme in Scheme::ALL {
        let cases = cases_of(scheme);
        for name in REQUIRED_SETS {
            assert!(
                cases.iter().any(|c| c.name == name),
                "reference has no {scheme} case for data set {name}"
            );
        }
        for case in cases {
            let (x, ex) = (&case.x, &case.eval_x);
            let n = x.len();
            assert!(n >= 2 && n == case.y.len(), "{}", case.name);
            for q in [&case.value, &case.d1, &case.d2] {
                assert_eq!(q.len(), ex.len(), "{}", case.name);
            }
            // Every knot, a point strictly inside every interval, and points
            // beyond both ends.
            for k in x {
                assert!(ex.contains(k), "{}: knot {k} not evaluated", case.name);
            }
            for w in x.windows(2) {
                assert!(
                    ex.iter().filter(|&&e| w[0] < e && e < w[1]).count() >= 3,
                    "{}: too few points inside [{}, {}]",
                    case.name,
                    w[0],
                    w[1]
                );
            }
            assert!(
                ex.iter().filter(|&&e| e < x[0]).count() >= 2,
                "{}",
                case.name
            );
            assert!(
                ex.iter().filter(|&&e| e > x[n - 1]).count() >= 2,
                "{}",
                case.name
            );
        }
    }
    for (name, n) in [
        ("small_n2", 2),
        ("small_n3", 3),
        ("small_n4", 4),
        ("small_n5", 5),
    ] {
        let case = reference.cases.iter().find(|c| c.name == name).unwrap();
        assert_eq!(case.x.len(), n, "{name}");
    }
    // The uniform data sets must take the O(1) lookup path, the others not.
    let uniform = |name: &str| {
        let case = reference.cases.iter().find(|c| c.name == name).unwrap();
        PiecewiseCubic::fit(Scheme::Cubic, &case.x, &case.y)
            .unwrap()
            .has_uniform_knots()
    };
    for name in ["uniform_linspace", "uniform_seeded", "step", "track_offset"] {
        assert!(uniform(name), "{name} should have uniform knots");
    }
    for name in [
        "smooth_nonuniform",
        "clustered_knots",
        "corner_flat_runs",
        "track_wide",
    ] {
        assert!(!uniform(name), "{name} should not have uniform knots");
    }
}
