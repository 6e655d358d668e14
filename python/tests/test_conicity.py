"""`railsim.equivalent_conicity` on EN 15302's reference case E1 (profile
A on rail A; data and licence in tests/data/en15302/README.md)."""

import numpy as np
import pytest

import railsim
from conftest import TEST_DATA

EN = TEST_DATA / "en15302"


def test_e1_within_the_standards_tolerance():
    ben = np.loadtxt(EN / "ben_E1.dat")
    amplitudes = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    reference = np.interp(amplitudes, ben[:, 0], ben[:, 1])
    c = railsim.equivalent_conicity(
        EN / "A_WRCC_RUIC519A.dat", EN / "A_WRCC_SUIC519A.dat", amplitudes_mm=amplitudes,
        gauge_m=1.43516, wheel_radius_m=0.46, rail_inclination="0",
    )
    # EN 15302: |Δ tan γe| ≤ min(0.05, 0.5 tan γe).
    tolerance = np.minimum(0.05, 0.5 * reference)
    assert np.all(np.abs(c["tan_gamma_e"] - reference) <= tolerance), (c["tan_gamma_e"], reference)
    # Klingel: λ = 2π √(r0 e / (2 tan γe)) with e = 1.5 m, r0 = 0.46 m.
    klingel = 2 * np.pi * np.sqrt(0.46 * 1.5 / (2 * c["tan_gamma_e"]))
    np.testing.assert_allclose(c["wavelength_m"], klingel, rtol=0.02)
    assert c["y_mm"].shape == c["delta_r_mm"].shape
    assert c["max_amplitude_mm"] > 5.0


def test_unit_slip_is_refused():
    with pytest.raises(ValueError, match="check the unit"):
        railsim.equivalent_conicity(
            EN / "A_WRCC_RUIC519A.dat", EN / "A_WRCC_SUIC519A.dat", amplitudes_mm=[3000.0],
            rail_inclination="0",
        )
