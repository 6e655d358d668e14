//! `sim creep-curves`: creep curves (force / μN against creepage) of every
//! creep law for one contact ellipse — the figure a report compares creep
//! laws with (e.g. Shen, Hedrick & Elkins 1983, Fig. 2; Polach 1999,
//! Fig. 3). Pure longitudinal creepage ξ, pure lateral creepage η, pure spin
//! φ (lateral force and spin moment), and Polach's 2005 dry and wet
//! presets (falling friction with the slip velocity) over a wide creepage
//! range.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use preproc::plot::{LineChart, Series, write_multi_panel};
use runtime::forces::creep::{
    CreepInput, CreepLaw, FastripParams, FastsimParams, PolachParams, kalker_coefficients,
};
use runtime::forces::hertz::{HertzContact, Material};

/// The contact the curves are drawn for, and the ranges (checked settings).
#[derive(Debug, Clone, PartialEq)]
pub struct CreepCurveConfig {
    /// Normal force N (N).
    pub normal_force_n: f64,
    /// Semi-axes a (rolling) and b (lateral) (m).
    pub a_m: f64,
    pub b_m: f64,
    /// Coefficient of friction μ.
    pub friction_coefficient: f64,
    /// Rolling speed V (m/s) (slip-velocity dependent friction only).
    pub speed_m_s: f64,
    pub material: Material,
    /// Largest |ξ| and |η| of the creepage sweeps; `None`: twice the
    /// creepage at which the heuristic law saturates, 6μN/(G a b C11).
    pub max_creepage: Option<f64>,
    /// Points per curve.
    pub points: usize,
    /// FASTSIM discretisation; FaStrip's curves use the same grid.
    pub fastsim: FastsimParams,
}

impl CreepCurveConfig {
    /// The ellipse of a wheel of rolling radius `wheel_radius_m` on a rail
    /// head of radius `rail_head_radius_m` (crossed cylinders; A = 1/(2 r_w),
    /// B = 1/(2 r_rail), docs/reference/07-contact-forces.md §7.1) at normal force `normal_force_n`.
    pub fn from_radii(
        normal_force_n: f64,
        wheel_radius_m: f64,
        rail_head_radius_m: f64,
        material: Material,
    ) -> Result<(f64, f64)> {
        let hz = HertzContact::new(
            0.5 / wheel_radius_m,
            0.5 / rail_head_radius_m,
            normal_force_n,
            &material,
        )
        .context("Hertz contact of the chosen wheel and rail radii")?;
        Ok((hz.a_rolling_m, hz.b_lateral_m))
    }

    /// Checks every rule, naming the one violated.
    pub fn validate(&self) -> Result<()> {
        if !(self.normal_force_n.is_finite() && self.normal_force_n > 0.0) {
            bail!("normal force must be > 0 N, got {}", self.normal_force_n);
        }
        if !(self.a_m > 0.0 && self.b_m > 0.0 && self.a_m.is_finite() && self.b_m.is_finite()) {
            bail!(
                "semi-axes must be finite and > 0, got a = {} m, b = {} m",
                self.a_m,
                self.b_m
            );
        }
        if !(self.friction_coefficient.is_finite() && self.friction_coefficient > 0.0) {
            bail!(
                "friction coefficient must be > 0, got {}",
                self.friction_coefficient
            );
        }
        if !(self.speed_m_s.is_finite() && self.speed_m_s >= 0.0) {
            bail!("speed must be >= 0 m/s, got {}", self.speed_m_s);
        }
        if let Some(m) = self.max_creepage
            && !(m.is_finite() && m > 0.0 && m <= 1.0)
        {
            bail!("maximum creepage must lie in (0, 1], got {m}");
        }
        if !(10..=100_000).contains(&self.points) {
            bail!(
                "points per curve must lie in 10..=100000, got {}",
                self.points
            );
        }
        self.material.validate()?;
        CreepLaw::Fastsim(self.fastsim).validate()?;
        Ok(())
    }
}

/// One sweep: creepage values and, per law, the normalised responses.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    /// What is swept, with unit, e.g. "ξ [-]".
    pub x_label: String,
    pub x: Vec<f64>,
    /// `(law name, values)`.
    pub curves: Vec<(String, Vec<f64>)>,
    /// What is plotted, e.g. "−Fx / μN".
    pub y_label: String,
    pub title: String,
}

/// All the curves.
#[derive(Debug, Clone, PartialEq)]
pub struct CreepCurves {
    pub config: CreepCurveConfig,
    pub sweeps: Vec<Sweep>,
}

fn laws(config: &CreepCurveConfig) -> Vec<(String, CreepLaw)> {
    vec![
        ("Kalker linear".into(), CreepLaw::KalkerLinear),
        ("Heuristic".into(), CreepLaw::Heuristic),
        ("Polach".into(), CreepLaw::Polach(PolachParams::default())),
        (
            format!(
                "FASTSIM {}×{}",
                config.fastsim.strips, config.fastsim.elements_per_strip
            ),
            CreepLaw::Fastsim(config.fastsim),
        ),
        (
            format!(
                "FaStrip {}×{}",
                config.fastsim.strips, config.fastsim.elements_per_strip
            ),
            CreepLaw::Fastrip(FastripParams {
                strips: config.fastsim.strips,
                elements_per_strip: config.fastsim.elements_per_strip,
            }),
        ),
    ]
}

/// Evaluates every law over the sweeps of `config`.
pub fn creep_curves(config: &CreepCurveConfig) -> Result<CreepCurves> {
    config.validate()?;
    let mu_n = config.friction_coefficient * config.normal_force_n;
    let g_pa = config.material.shear_modulus_pa();
    let c = kalker_coefficients(config.a_m / config.b_m, config.material.poisson)?;
    let ab = config.a_m * config.b_m;
    let max_creepage = config
        .max_creepage
        .unwrap_or((6.0 * mu_n / (g_pa * ab * c.c11)).min(1.0));
    // Spin at which the Kalker spin force alone reaches 3μN, doubled.
    let max_spin_1_m = 6.0 * mu_n / (g_pa * ab * ab.sqrt() * c.c23);
    let base = CreepInput {
        xi: 0.0,
        eta: 0.0,
        phi_1_m: 0.0,
        normal_force_n: config.normal_force_n,
        a_m: config.a_m,
        b_m: config.b_m,
        friction_coefficient: config.friction_coefficient,
        rolling_speed_m_s: config.speed_m_s,
        shear_modulus_pa: g_pa,
        poisson: config.material.poisson,
    };
    let n = config.points;
    let grid = |max: f64| -> Vec<f64> { (0..n).map(|i| max * i as f64 / (n - 1) as f64).collect() };
    let all_laws = laws(config);
    let sweep_with = |laws: &[(String, CreepLaw, f64)],
                      title: &str,
                      x_label: &str,
                      y_label: &str,
                      x: Vec<f64>,
                      set: &dyn Fn(&mut CreepInput, f64),
                      pick: &dyn Fn(&runtime::forces::creep::CreepForces, f64) -> f64|
     -> Result<Sweep> {
        let mut curves = Vec::new();
        for (name, law, mu) in laws {
            let mut ys = Vec::with_capacity(x.len());
            for &xv in &x {
                let mut input = base;
                input.friction_coefficient = *mu;
                set(&mut input, xv);
                let f = law
                    .evaluate(&input)
                    .with_context(|| format!("{name} at {x_label} = {xv}"))?;
                ys.push(pick(&f, *mu));
            }
            curves.push((name.clone(), ys));
        }
        Ok(Sweep {
            x_label: x_label.into(),
            x,
            curves,
            y_label: y_label.into(),
            title: title.into(),
        })
    };
    let main_laws: Vec<(String, CreepLaw, f64)> = all_laws
        .into_iter()
        .map(|(n, l)| (n, l, config.friction_coefficient))
        .collect();
    let sweep =
        |title: &str,
         x_label: &str,
         y_label: &str,
         x: Vec<f64>,
         set: &dyn Fn(&mut CreepInput, f64),
         pick: &dyn Fn(&runtime::forces::creep::CreepForces, f64) -> f64|
         -> Result<Sweep> { sweep_with(&main_laws, title, x_label, y_label, x, set, pick) };
    let mu_n_m = mu_n * (ab.sqrt());
    let n_n = config.normal_force_n;
    let presets: Vec<(String, CreepLaw, f64)> = vec![
        (
            format!("Polach 2005 dry, μ0 = {}", PolachParams::DRY_2005_MU0),
            CreepLaw::Polach(PolachParams::dry_2005()),
            PolachParams::DRY_2005_MU0,
        ),
        (
            format!("Polach 2005 wet, μ0 = {}", PolachParams::WET_2005_MU0),
            CreepLaw::Polach(PolachParams::wet_2005()),
            PolachParams::WET_2005_MU0,
        ),
        (
            format!("Polach 1999, μ = {}", config.friction_coefficient),
            CreepLaw::Polach(PolachParams::default()),
            config.friction_coefficient,
        ),
    ];
    let sweeps = vec![
        sweep(
            "Longitudinal creepage",
            "ξ [-]",
            "−Fx / μN",
            grid(max_creepage),
            &|i, v| i.xi = v,
            &|f, _| -f.fx_n / mu_n,
        )?,
        sweep(
            "Lateral creepage",
            "η [-]",
            "−Fy / μN",
            grid(max_creepage),
            &|i, v| i.eta = v,
            &|f, _| -f.fy_n / mu_n,
        )?,
        sweep(
            "Spin: lateral force",
            "φ [1/m]",
            "−Fy / μN",
            grid(max_spin_1_m),
            &|i, v| i.phi_1_m = v,
            &|f, _| -f.fy_n / mu_n,
        )?,
        sweep(
            "Spin: spin moment",
            "φ [1/m]",
            "−Mz / (μN √(ab))",
            grid(max_spin_1_m),
            &|i, v| i.phi_1_m = v,
            &|f, _| -f.mz_nm / mu_n_m,
        )?,
        sweep_with(
            &presets,
            &format!(
                "Polach: falling friction with slip velocity, V = {} m/s",
                config.speed_m_s
            ),
            "ξ [-]",
            "−Fx / μ0N",
            grid(0.2),
            &|i, v| i.xi = v,
            &|f, mu| -f.fx_n / (mu * n_n),
        )?,
    ];
    Ok(CreepCurves {
        config: config.clone(),
        sweeps,
    })
}

impl CreepCurves {
    /// Writes `creep_curves.png` (four panels) and `creep_curves.csv` (one
    /// block per sweep) into `dir`; returns the paths.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("creating the output directory {}", dir.display()))?;
        let c = &self.config;
        let panels: Vec<LineChart> = self
            .sweeps
            .iter()
            .map(|s| {
                let mut chart = LineChart::new(&s.title, &s.x_label, &s.y_label);
                for (k, (name, ys)) in s.curves.iter().enumerate() {
                    chart.series.push(
                        Series::line(name, s.x.iter().copied().zip(ys.iter().copied()).collect())
                            .with_colour(k),
                    );
                }
                // The saturating laws set the scale; Kalker linear's
                // straight line runs off the top.
                let top = s
                    .curves
                    .iter()
                    .filter(|(name, _)| name != "Kalker linear")
                    .flat_map(|(_, ys)| ys.iter().copied())
                    .filter(|v| v.is_finite())
                    .fold(0.0_f64, f64::max);
                chart.y_range = Some((0.0, 1.15 * top.max(1e-3)));
                chart
            })
            .collect();
        let png = dir.join("creep_curves.png");
        write_multi_panel(
            &png,
            &format!(
                "Creep curves: N = {:.1} kN, a = {:.2} mm, b = {:.2} mm, μ = {}, G = {:.1} GPa, ν = {}",
                c.normal_force_n * 1e-3,
                c.a_m * 1e3,
                c.b_m * 1e3,
                c.friction_coefficient,
                c.material.shear_modulus_pa() * 1e-9,
                c.material.poisson
            ),
            &panels,
            2,
            (1600, 1800),
        )?;
        let csv = dir.join("creep_curves.csv");
        let mut text = format!(
            "# creep curves: normal_force_n={}, a_m={}, b_m={}, mu={}, shear_modulus_pa={}, poisson={}, speed_m_s={}\n",
            c.normal_force_n,
            c.a_m,
            c.b_m,
            c.friction_coefficient,
            c.material.shear_modulus_pa(),
            c.material.poisson,
            c.speed_m_s
        );
        text += "# columns: force / (mu N) (spin moment: / (mu N sqrt(ab))); the last block is normalised by each preset's mu0\n";
        text += "sweep,creepage,kalker,heuristic,polach,fastsim\n";
        for (k, s) in self.sweeps.iter().enumerate() {
            let name = [
                "xi",
                "eta",
                "phi_lateral_force",
                "phi_spin_moment",
                "xi_polach_presets",
            ][k.min(4)];
            if k == 4 {
                text += "sweep,creepage,polach_dry_2005,polach_wet_2005,polach_1999\n";
            }
            for (i, x) in s.x.iter().enumerate() {
                text += &format!("{name},{x:e}");
                for (_, ys) in &s.curves {
                    text += &format!(",{:e}", ys[i]);
                }
                text += "\n";
            }
        }
        runtime::io::write_atomically(&csv, |tmp| std::fs::write(tmp, &text))
            .with_context(|| format!("writing {}", csv.display()))?;
        Ok(vec![png, csv])
    }
}
