//! The element preloads of a vehicle file (docs/reference/08-multibody.md §8.3,
//! docs/reference/11-vehicle-files.md): solved for static equilibrium at
//! assembly (`preload = "solve"`, the default) or as written
//! (`preload = "given"`, the old behaviour, where a file whose preloads do
//! not hold every free body is refused with the net force).

use anyhow::{Result, anyhow};
use nalgebra::Vector3;
use runtime::multibody::preload::{StaticBody, StaticElement, solve_static_preloads};
use serde::Deserialize;

use super::suspension::axis_laws;
use super::vehicle::{GRAVITY_M_S2, GROUND, VehicleFile};

/// Where the element preloads come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PreloadMode {
    /// Solved: each element's `preload_n` (a constant force, default 0)
    /// plus the force of the linearised static deflection under gravity
    /// (runtime::multibody::preload).
    #[default]
    Solve,
    /// As written in `preload_n`; every free body must be in equilibrium
    /// under them (within 0.5 % of its weight, or 1 N).
    Given,
}

/// The preloads and the equilibrium they leave.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticPreloads {
    pub mode: PreloadMode,
    /// Preload of each element (file order): force on body_b at assembly,
    /// body_a's axes (N).
    pub preloads_n: Vec<[f64; 3]>,
    /// Per free body of the solve (bodies, then references with a carried
    /// mass): name, net force (N) and moment about its CG (N·m) at
    /// assembly from gravity and the preloads. With `given`: the bodies'
    /// net forces (moments not checked, reported as 0).
    pub residual: Vec<(String, [f64; 3], [f64; 3])>,
}

fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

impl VehicleFile {
    /// The free bodies of the static solve: the bodies, then the
    /// references with a carried mass (a body's index is its position).
    fn static_bodies(&self) -> Vec<StaticBody> {
        let bodies = self.bodies.iter().map(|b| StaticBody {
            name: b.name.clone(),
            mass_kg: b.mass_kg,
            cg_m: Vector3::from(b.cg_m),
        });
        let refs = self
            .references
            .iter()
            .filter(|r| r.carried_mass_kg > 0.0)
            .map(|r| StaticBody {
                name: r.name.clone(),
                mass_kg: r.carried_mass_kg,
                cg_m: Vector3::from(r.origin_m),
            });
        bodies.chain(refs).collect()
    }

    /// Solves or checks the preloads ([`PreloadMode`]). The rule checks of
    /// [`VehicleFile::validate`] come first.
    pub fn static_preloads(&self) -> Result<StaticPreloads> {
        match self.preload {
            PreloadMode::Given => self.given_preloads(),
            PreloadMode::Solve => self.solved_preloads(),
        }
    }

    fn given_preloads(&self) -> Result<StaticPreloads> {
        let preloads_n = self.given_preloads_n();
        let residual = self
            .bodies
            .iter()
            .map(|b| {
                let f = self.force_from(&b.name, b.mass_kg, &preloads_n);
                (b.name.clone(), f, [0.0; 3])
            })
            .collect();
        Ok(StaticPreloads {
            mode: PreloadMode::Given,
            preloads_n,
            residual,
        })
    }

    /// The `preload_n` as written (file order).
    pub(super) fn given_preloads_n(&self) -> Vec<[f64; 3]> {
        self.elements.iter().map(|e| e.preload_n).collect()
    }

    fn solved_preloads(&self) -> Result<StaticPreloads> {
        let bodies = self.static_bodies();
        let index = |name: &str| {
            if name == GROUND {
                None
            } else {
                bodies.iter().position(|b| b.name == name)
            }
        };
        let mut elements = Vec::with_capacity(self.elements.len());
        for e in &self.elements {
            let laws = axis_laws(&e.name, &e.spring, &e.damper, &e.series)?;
            let (pa, pb) = e.points()?;
            let stiffness_n_m = std::array::from_fn(|i| {
                e.stiffness_n_m[i]
                    + laws[i]
                        .spring
                        .as_ref()
                        .map_or(0.0, |s| s.stiffness_at_zero_n_m())
            });
            elements.push(StaticElement {
                name: e.name.clone(),
                a: index(&e.body_a),
                b: index(&e.body_b),
                point_a_m: Vector3::from(pa),
                point_b_m: Vector3::from(pb),
                stiffness_n_m,
                given_n: Vector3::from(e.preload_n),
            });
        }
        let sol = solve_static_preloads(&bodies, &elements, GRAVITY_M_S2)
            .map_err(|e| anyhow!("static preload solve (preload = \"solve\"): {e}"))?;
        Ok(StaticPreloads {
            mode: PreloadMode::Solve,
            preloads_n: sol.preloads_n.iter().map(arr).collect(),
            residual: bodies
                .iter()
                .zip(&sol.residual)
                .map(|(b, (f, m))| (b.name.clone(), arr(f), arr(m)))
                .collect(),
        })
    }

    /// The preload of every element (file order, N, body_a's axes): the
    /// resolved ones once [`VehicleFile::load`] has run, else as written.
    pub fn element_preloads_n(&self) -> Vec<[f64; 3]> {
        match &self.statics {
            Some(s) => s.preloads_n.clone(),
            None => self.given_preloads_n(),
        }
    }

    /// Net force (N) on a body at assembly from its weight and the
    /// preloads `preloads_n` (file order) of the elements on it. At assembly every
    /// body's axes are the track axes, so a preload (in a's axes) is the
    /// global force on b.
    pub(super) fn force_from(&self, name: &str, mass_kg: f64, preloads_n: &[[f64; 3]]) -> [f64; 3] {
        let mut f = [0.0, 0.0, -mass_kg * GRAVITY_M_S2];
        for (e, p) in self.elements.iter().zip(preloads_n) {
            let sign = if e.body_b == name {
                1.0
            } else if e.body_a == name {
                -1.0
            } else {
                continue;
            };
            for (fk, pk) in f.iter_mut().zip(p) {
                *fk += sign * pk;
            }
        }
        f
    }
}

impl StaticPreloads {
    /// The report: each element's preload and each free body's residual
    /// (what `sim run` prints).
    pub fn table(&self, v: &VehicleFile) -> String {
        let mode = match self.mode {
            PreloadMode::Solve => "solved for static equilibrium at assembly (preload = \"solve\")",
            PreloadMode::Given => "as given in the vehicle file (preload = \"given\")",
        };
        let mut s = format!("  static preloads, {mode}:\n");
        let width = v.elements.iter().map(|e| e.name.len()).max().unwrap_or(0);
        for (e, p) in v.elements.iter().zip(&self.preloads_n) {
            s += &format!(
                "    {:width$}  [{:>11.1}, {:>11.1}, {:>11.1}] N  (on '{}', '{}' axes)\n",
                e.name, p[0], p[1], p[2], e.body_b, e.body_a
            );
        }
        for (name, f, m) in &self.residual {
            let fmax = f.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
            let mmax = m.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
            s += &format!(
                "    residual on '{name}': force {fmax:.2e} N, moment {mmax:.2e} N·m (largest component)\n"
            );
        }
        s
    }
}
