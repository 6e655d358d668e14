//! The variants of the speed/accuracy study: the reference run, one knob
//! turned at a time, a few combinations and the user's own; each is the
//! scene varied by the reference's overrides and then its own
//! ([`crate::config::Variation`]).

use anyhow::{Context, Result, ensure};
use serde::Serialize;

use crate::config::Variation;
use crate::config::scene::{IntegratorKind, LoadedScene, Scene};

/// The reference run: finest table step, online contact with the flange
/// always searched, RK4 at 0.1 ms. Measured on the bogie at 84 m/s over
/// 100 m: within 1.3e-10 m of RK4 at 0.02 ms and of DOPRI5 at rtol 1e-10
/// (`docs/guide/speed-accuracy-tradeoff.md`), so converged far below any variant's error; DOPRI5 at rtol 1e-9
/// is no more accurate and no faster.
pub const REFERENCE_OVERRIDES: [&str; 5] = [
    "track.step_m=0.01",
    "contact.flange=\"on\"",
    "contact.method=\"online\"",
    "run.integrator=\"rk4\"",
    "run.step_s=1e-4",
];

/// Largest DOPRI5 step of the dopri5 variants (s): DOPRI5 is limited by
/// stability near 1.2 ms on the bogie (`docs/guide/performance.md`), 2 ms lets it choose.
pub const DOPRI5_MAX_STEP_S: f64 = 2e-3;

/// Run length of `--quick` (m) unless the scene's length is overridden.
pub const QUICK_DISTANCE_M: f64 = 50.0;

/// One run setting: the overrides it applies after the reference's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Variant {
    pub name: String,
    /// Which knob (or "combination", "reference", …).
    pub knob: String,
    /// The knob's value, as shown in the plot's legend.
    pub value: String,
    /// Overrides applied after [`REFERENCE_OVERRIDES`].
    pub overrides: Vec<String>,
    /// The variant with the same settings and the reference's table step
    /// (for the table-step rule), if this one differs from it in the table
    /// step only.
    pub fine_table_partner: Option<String>,
}

impl Variant {
    fn new(name: &str, knob: &str, value: &str, overrides: &[&str]) -> Variant {
        Variant {
            name: name.into(),
            knob: knob.into(),
            value: value.into(),
            overrides: overrides.iter().map(|s| s.to_string()).collect(),
            fine_table_partner: None,
        }
    }

    fn partner(mut self, name: &str) -> Variant {
        self.fine_table_partner = Some(name.into());
        self
    }

    /// A user's variant `NAME:KEY=VALUE;KEY=VALUE…` (`--variant`).
    pub fn parse(spec: &str) -> Result<Variant> {
        let (name, rest) = spec
            .split_once(':')
            .context("a variant is NAME:KEY=VALUE;KEY=VALUE…")?;
        let name = name.trim();
        ensure!(!name.is_empty(), "the variant has no name");
        let overrides: Vec<String> = rest
            .split(';')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect();
        for o in &overrides {
            ensure!(o.contains('='), "'{o}' is not KEY=VALUE");
        }
        Ok(Variant {
            name: name.into(),
            knob: "user".into(),
            value: name.into(),
            overrides,
            fine_table_partner: None,
        })
    }

    /// File-name form of the name.
    pub fn slug(&self) -> String {
        let s: String = self
            .name
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        let mut out = String::new();
        for c in s.chars() {
            if !(c == '_' && out.ends_with('_')) {
                out.push(c);
            }
        }
        out.trim_matches('_').to_string()
    }
}

/// Name of the reference variant.
pub const REFERENCE: &str = "reference";

/// The scene's own settings of the reference's keys, as overrides.
fn scene_settings(scene: &Scene) -> Vec<String> {
    let mut v = vec![
        format!("track.step_m={}", scene.track.step_m),
        format!("contact.flange=\"{}\"", scene.contact.flange),
        format!("contact.method=\"{}\"", scene.contact.method),
        format!("run.integrator=\"{}\"", scene.run.integrator),
        format!("run.step_s={}", scene.run.step_s),
    ];
    if scene.run.integrator != IntegratorKind::Rk4 {
        let (rtol, atol, max_step_s) = scene.run.tolerances();
        v.push(format!("run.rtol={rtol}"));
        v.push(format!("run.atol={atol}"));
        v.push(format!("run.max_step_s={max_step_s}"));
    }
    v
}

/// The variants of a study of `scene` (module docs); `quick`: the reference
/// and five (RK4 at 1 and 0.2 ms, Rosenbrock at its defaults, table step
/// 1 m, "quick look"). The table
/// step and scheme knobs are left out when the scene reads a table file
/// (they are ignored then) and the scheme when it uses an ideal straight;
/// the reasons are returned.
pub fn variants(scene: &Scene, quick: bool) -> (Vec<Variant>, Vec<String>) {
    let dp = |rtol: &str| -> Vec<String> {
        vec![
            "run.integrator=\"dopri5\"".into(),
            format!("run.rtol={rtol}"),
            format!("run.max_step_s={DOPRI5_MAX_STEP_S}"),
        ]
    };
    // The stiff integrator at its defaults but atol
    // (docs/reference/08-multibody.md §8.5).
    let ros = |atol: &str| -> Vec<String> {
        vec![
            "run.integrator=\"rosenbrock\"".into(),
            format!("run.atol={atol}"),
        ]
    };
    let quick_look = Variant::new(
        "quick look",
        "combination",
        "quick look",
        &[
            "contact.method=\"table\"",
            "contact.flange=\"auto\"",
            "track.step_m=0.5",
            "run.step_s=1e-3",
        ],
    );
    let reference = Variant::new(REFERENCE, "reference", "reference", &[]);
    let mut skipped = Vec::new();
    let tables_file = scene.track.tables.is_some();
    if tables_file {
        skipped.push(
            "table step, spline scheme: the scene reads a table file (step and scheme are fixed in it)"
                .to_string(),
        );
    } else if scene.track.straight_m.is_some() {
        skipped.push("spline scheme: the scene's track is an ideal straight (no spline)".into());
    }
    if quick {
        let mut v = vec![
            reference,
            Variant::new("rk4 1 ms", "rk4 step", "1 ms", &["run.step_s=1e-3"]),
            Variant::new("rk4 0.2 ms", "rk4 step", "0.2 ms", &["run.step_s=2e-4"]),
        ];
        let mut r = Variant::new("rosenbrock atol 5e-6", "rosenbrock atol", "5e-6", &[]);
        r.overrides = ros("5e-6");
        v.push(r);
        if !tables_file {
            v.push(
                Variant::new("table step 1 m", "table step", "1 m", &["track.step_m=1"])
                    .partner(REFERENCE),
            );
        }
        v.push(quick_look);
        return (v, skipped);
    }
    let mut v = vec![reference];
    if !tables_file {
        for (step, name) in [("1", "1 m"), ("0.5", "0.5 m"), ("0.1", "0.1 m")] {
            v.push(
                Variant::new(
                    &format!("table step {name}"),
                    "table step",
                    name,
                    &[&format!("track.step_m={step}")],
                )
                .partner(REFERENCE),
            );
        }
    }
    v.push(Variant::new(
        "contact table",
        "contact",
        "table",
        &["contact.method=\"table\""],
    ));
    v.push(Variant::new(
        "flange off",
        "contact",
        "flange off",
        &["contact.flange=\"off\""],
    ));
    v.push(Variant::new(
        "flange auto",
        "contact",
        "flange auto",
        &["contact.flange=\"auto\""],
    ));
    for (step, name) in [
        ("1e-3", "1 ms"),
        ("5e-4", "0.5 ms"),
        ("2e-4", "0.2 ms"),
        ("5e-5", "0.05 ms"),
    ] {
        v.push(Variant::new(
            &format!("rk4 {name}"),
            "rk4 step",
            name,
            &[&format!("run.step_s={step}")],
        ));
    }
    for rtol in ["1e-4", "1e-6", "1e-8", "1e-9"] {
        let mut var = Variant::new(&format!("dopri5 rtol {rtol}"), "dopri5 rtol", rtol, &[]);
        var.overrides = dp(rtol);
        v.push(var);
    }
    for atol in ["5e-6", "1e-6", "2e-7"] {
        let mut var = Variant::new(
            &format!("rosenbrock atol {atol}"),
            "rosenbrock atol",
            atol,
            &[],
        );
        var.overrides = ros(atol);
        v.push(var);
    }
    for law in ["kalker", "heuristic", "polach", "fastsim", "fastrip"] {
        if law != scene.contact.creep_law.as_str() {
            v.push(Variant::new(
                &format!("creep {law}"),
                "model",
                law,
                &[&format!("contact.creep_law=\"{law}\"")],
            ));
        }
    }
    if scene.track.centerline.is_some() {
        for scheme in ["cubic", "akima", "pchip"] {
            if scheme != scene.track.scheme.as_str() {
                v.push(Variant::new(
                    &format!("scheme {scheme}"),
                    "model",
                    scheme,
                    &[&format!("track.scheme=\"{scheme}\"")],
                ));
            }
        }
    }
    if !tables_file {
        for (step, name) in [("0.1", "0.1 m"), ("0.5", "0.5 m"), ("1", "1 m")] {
            v.push(
                Variant::new(
                    &format!("table step {name} + rk4 1 ms"),
                    "table step × rk4 1 ms",
                    name,
                    &[&format!("track.step_m={step}"), "run.step_s=1e-3"],
                )
                .partner("rk4 1 ms"),
            );
        }
    }
    v.push(quick_look);
    v.push(Variant::new(
        "design study",
        "combination",
        "design study",
        &[
            "contact.flange=\"auto\"",
            "track.step_m=0.1",
            "run.step_s=5e-4",
        ],
    ));
    let mut adaptive = Variant::new("adaptive", "combination", "adaptive", &[]);
    adaptive.overrides = [
        "contact.flange=\"auto\"".to_string(),
        "track.step_m=0.1".into(),
    ]
    .into_iter()
    .chain(dp("1e-6"))
    .collect();
    v.push(adaptive);
    let mut given = Variant::new("scene as given", "combination", "scene as given", &[]);
    given.overrides = scene_settings(scene);
    v.push(given);
    (v, skipped)
}

/// The scene shortened for `--quick`: [`QUICK_DISTANCE_M`] unless `keep`
/// (the user set the length).
pub fn quick_scene(scene: &LoadedScene, keep: bool) -> Result<LoadedScene> {
    if keep {
        return Ok(scene.clone());
    }
    let mut o = vec![Variation::Distance(QUICK_DISTANCE_M)];
    if scene.scene.run.duration_s.is_some() {
        o.push(Variation::Remove("run.duration_s".into()));
    }
    let mut quick = scene.varied(&o)?;
    quick.origin = scene.origin.clone();
    Ok(quick)
}

/// The scene of a variant: the reference's overrides, then its own.
pub fn variant_scene(scene: &LoadedScene, v: &Variant) -> Result<LoadedScene> {
    let variations = REFERENCE_OVERRIDES
        .iter()
        .copied()
        .chain(v.overrides.iter().map(String::as_str))
        .map(Variation::parse)
        .collect::<Result<Vec<_>>>()
        .with_context(|| format!("variant '{}'", v.name))?;
    let mut vs = scene
        .varied(&variations)
        .with_context(|| format!("variant '{}'", v.name))?;
    vs.origin = format!("{} [{}]", scene.origin, v.name);
    Ok(vs)
}
