//! `railsim.creep_forces`: the creep laws on numpy arrays.

use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArrayDyn};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use runtime::forces::creep::{CreepInput, CreepLaw};

/// Creep forces on the wheel of one law (kalker, heuristic, polach, fastsim,
/// fastrip, none; default parameters, as in a scene) at every element of
/// the inputs, which numpy broadcasts together (floats or arrays):
///
/// - `xi`, `eta`: longitudinal and lateral creepages (–), along t_c, l_c;
/// - `phi`: spin creepage (1/m), about n_c;
/// - `a_m`, `b_m`: Hertz semi-axes, rolling direction and lateral (m);
/// - `normal_n`: normal force N ≥ 0 (N);
/// - `mu`: coefficient of friction (–);
/// - `shear_modulus_pa`: combined shear modulus G (Pa), e.g. 80.8e9;
/// - `poisson`: combined Poisson's ratio (–);
/// - `speed_m_s`: rolling speed (m/s), used only by a law whose friction
///   depends on the slip velocity.
///
/// Returns `fx_n`, `fy_n` (N) and `mz_nm` (N·m) arrays of the broadcast
/// shape: the forces on the wheel in the contact frame, opposing the
/// creepages (docs/reference/07-contact-forces.md §7.3). An invalid input
/// raises ValueError naming the quantity and its index.
#[pyfunction]
#[pyo3(signature = (law, xi, eta, phi, a_m, b_m, normal_n, mu, shear_modulus_pa, poisson, speed_m_s=None))]
#[allow(clippy::too_many_arguments)]
pub fn creep_forces<'py>(
    py: Python<'py>,
    law: &str,
    xi: &Bound<'py, PyAny>,
    eta: &Bound<'py, PyAny>,
    phi: &Bound<'py, PyAny>,
    a_m: &Bound<'py, PyAny>,
    b_m: &Bound<'py, PyAny>,
    normal_n: &Bound<'py, PyAny>,
    mu: &Bound<'py, PyAny>,
    shear_modulus_pa: &Bound<'py, PyAny>,
    poisson: &Bound<'py, PyAny>,
    speed_m_s: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let law_value = CreepLaw::from_name(law).ok_or_else(|| {
        pyo3::exceptions::PyValueError::new_err(format!(
            "creep law '{law}' is not one of: {}",
            CreepLaw::NAMES.join(", ")
        ))
    })?;
    let np = py.import("numpy")?;
    let zero = 0.0_f64.into_pyobject(py)?.into_any();
    let inputs = (
        xi,
        eta,
        phi,
        a_m,
        b_m,
        normal_n,
        mu,
        shear_modulus_pa,
        poisson,
        speed_m_s.unwrap_or(&zero),
    );
    let broadcast = np.getattr("broadcast_arrays")?.call1(inputs).map_err(|e| {
        pyo3::exceptions::PyValueError::new_err(format!(
            "the inputs cannot be broadcast together: {e}"
        ))
    })?;
    let shape: Vec<usize> = broadcast.get_item(0)?.getattr("shape")?.extract()?;
    let mut columns: Vec<Vec<f64>> = Vec::with_capacity(10);
    for item in broadcast.try_iter()? {
        let a = np.getattr("ascontiguousarray")?.call1((item?, "float64"))?;
        let a: PyReadonlyArrayDyn<'_, f64> = a.extract()?;
        columns.push(a.as_array().iter().copied().collect());
    }
    let n = columns[0].len();
    let forces = py
        .detach(|| -> Result<Vec<[f64; 3]>, String> {
            (0..n)
                .map(|k| {
                    let c = |i: usize| columns[i][k];
                    let input = CreepInput {
                        xi: c(0),
                        eta: c(1),
                        phi_1_m: c(2),
                        a_m: c(3),
                        b_m: c(4),
                        normal_force_n: c(5),
                        friction_coefficient: c(6),
                        shear_modulus_pa: c(7),
                        poisson: c(8),
                        rolling_speed_m_s: c(9),
                    };
                    law_value
                        .evaluate(&input)
                        .map(|f| [f.fx_n, f.fy_n, f.mz_nm])
                        .map_err(|e| format!("element {k}: {e}"))
                })
                .collect()
        })
        .map_err(pyo3::exceptions::PyValueError::new_err)?;
    let out = PyDict::new(py);
    for (j, name) in ["fx_n", "fy_n", "mz_nm"].into_iter().enumerate() {
        let v: Vec<f64> = forces.iter().map(|f| f[j]).collect();
        out.set_item(name, v.into_pyarray(py).reshape(shape.clone())?)?;
    }
    Ok(out)
}
