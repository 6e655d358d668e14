"""`railsim.creep_forces` against published values (the same references as
the Rust tests: runtime/tests/creep_laws.rs, fastsim_reference.rs)."""

import numpy as np
import pytest

import railsim

G, NU, MU, N = 80e9, 0.25, 0.3, 80e3


def test_kalker_linear_is_table_e3():
    # Kalker (1990) Table E.3, a/b = 1, ν = 0.25: C11 = 4.12, C22 = 3.67,
    # C23 = 1.47, C33 = 1.19 (Fx = −G a b C11 ξ, …; paper eq. 23).
    a = b = 5e-3
    xi = np.array([1e-5, 1e-4, 2e-4])
    f = railsim.creep_forces("kalker", xi, 0.0, 0.0, a, b, N, MU, G, NU)
    np.testing.assert_allclose(f["fx_n"], -G * a * b * 4.12 * xi, rtol=1e-9)
    assert np.all(f["fy_n"] == 0.0)
    f = railsim.creep_forces("kalker", 0.0, 1e-4, 0.0, a, b, N, MU, G, NU)
    assert f["fy_n"] == pytest.approx(-G * a * b * 3.67 * 1e-4, rel=1e-9)
    assert f["mz_nm"] == pytest.approx(G * (a * b) ** 1.5 * 1.47 * 1e-4, rel=1e-9)


def test_fastsim_on_the_contact_user_guide_spin_case():
    # CONTACT user guide's spin case (a = 8 mm, b = 4 mm, η = −0.000625,
    # φ = 0.625 1/m, G = 82 GPa, ν = 0.28, N = 82 kN, μ = 0.3): FASTSIM
    # published Fy/μN = −0.64 (two decimals), the exact theory −0.61.
    f = railsim.creep_forces(
        "fastsim", 0.0, -0.000625, 0.625, 8e-3, 4e-3, 82e3, 0.3, 82e9, 0.28, speed_m_s=30.0
    )
    assert f["fy_n"] / (0.3 * 82e3) == pytest.approx(-0.64, abs=0.015)
    assert abs(f["fx_n"]) < 1e-9 * 0.3 * 82e3


@pytest.mark.parametrize("law", ["heuristic", "polach", "fastsim", "fastrip"])
def test_saturating_laws_stay_within_coulomb(law):
    xi = np.geomspace(1e-6, 0.1, 40)
    f = railsim.creep_forces(law, xi[:, None], xi[None, :] * 0.5, 0.0, 6e-3, 4e-3, N, MU, G, NU)
    assert f["fx_n"].shape == (40, 40)
    traction = np.hypot(f["fx_n"], f["fy_n"])
    assert np.all(traction <= MU * N * (1 + 1e-9))
    # Full sliding at 10 % creepage: within 5 % of μN.
    assert traction[-1, -1] > 0.95 * MU * N
    # Forces oppose the creepages.
    assert np.all(f["fx_n"] < 0.0)


def test_vectorised_equals_elementwise_and_bad_input_is_named():
    xi = np.array([1e-4, -3e-4, 2e-3])
    many = railsim.creep_forces("polach", xi, 1e-4, 0.5, 6e-3, 4e-3, N, MU, G, NU)
    for k, x in enumerate(xi):
        one = railsim.creep_forces("polach", x, 1e-4, 0.5, 6e-3, 4e-3, N, MU, G, NU)
        assert one["fx_n"] == many["fx_n"][k]
    with pytest.raises(ValueError, match=r"element 1: .*normal force"):
        railsim.creep_forces("polach", 1e-4, 0.0, 0.0, 6e-3, 4e-3, [N, -1.0], MU, G, NU)
    with pytest.raises(ValueError, match="not one of"):
        railsim.creep_forces("coulomb", 1e-4, 0.0, 0.0, 6e-3, 4e-3, N, MU, G, NU)
