"""`railsim.run`, `railsim.Results` and `railsim.critical_speed`: the
physics through Python, and the same answers as `sim`."""

import json
import math
import os
import signal
import threading

import numpy as np
import pytest

import railsim
from conftest import TABLES

SCENES = TABLES / "scenes"
# Klingel's wavelength of the ML95-like wheelset: 2π √(b0 R0 / λ) with
# b0 = 0.75 m, R0 = 0.43 m, λ = 0.05 (tests/sim_run.rs).
KLINGEL_M = 2 * math.pi * math.sqrt(0.75 * 0.43 / 0.05)


def upward_zero_crossings(x, y):
    i = np.nonzero((y[:-1] < 0.0) & (y[1:] >= 0.0))[0]
    return x[i] + (x[i + 1] - x[i]) * (-y[i]) / (y[i + 1] - y[i])


def test_wheelset_hunts_with_the_klingel_wavelength():
    r = railsim.run(SCENES / "wheelset_straight.toml", set={"run.distance_m": 80}, progress=False)
    z = upward_zero_crossings(r["wheelset_0/distance_m"], r["wheelset_0/lateral_m"])
    assert len(z) >= 3
    wavelength = (z[-1] - z[0]) / (len(z) - 1)
    assert wavelength == pytest.approx(KLINGEL_M, rel=0.03)
    # The unsuspended wheelset is unstable at 10 m/s: the amplitude grows.
    d, y = r["wheelset_0/distance_m"], np.abs(r["wheelset_0/lateral_m"])
    assert y[(d >= 60) & (d < 80)].max() > 1.1 * y[(d >= 5) & (d < 25)].max()
    s = r.summary
    assert s["simulated_time_s"] == pytest.approx(8.0, abs=1e-9)
    assert s["wheelsets"][0]["travelled_left_m"] == pytest.approx(80.0, abs=0.05)
    assert r.attributes["creep_law"] == "polach"
    assert r.units("wheelset_0/lateral_m") == "m"
    assert "overrides: run.distance_m=80" in r.scene_toml


def test_same_results_as_sim_run(sim, tmp_path):
    overrides = {"run.distance_m": 20, "initial.speed_m_s": 12.5, "contact.creep_law": "kalker"}
    ours = railsim.run(SCENES / "wheelset_straight.toml", set=overrides, progress=False)
    cli_file = tmp_path / "cli.h5"
    sets = [a for k, v in overrides.items() for a in ("--set", f"{k}={v}")]
    sim("run", SCENES / "wheelset_straight.toml", *sets, "-o", cli_file, "--no-plots", "--quiet")
    theirs = railsim.Results.open(cli_file)
    assert ours.keys() == theirs.keys()
    for key in ["time_s", "wheelset_0/lateral_m", "wheelset_0/left/tread/normal_n", "wheelset_0/yaw_rad"]:
        np.testing.assert_array_equal(ours[key], theirs[key], err_msg=key)
    saved = tmp_path / "saved.h5"
    ours.save(saved)
    again = railsim.Results.open(saved)
    for key in ours.keys():
        np.testing.assert_array_equal(ours[key], again[key], err_msg=key)
    # An output never replaces an input.
    with pytest.raises(ValueError):
        ours.save(SCENES / "wheelset_straight.toml")
    with pytest.raises(KeyError, match="keys"):
        ours["wheelset_0/no_such_series"]


def test_scene_as_a_dict_and_refused_values():
    text = (SCENES / "wheelset_straight.toml").read_text()
    import tomllib

    scene = tomllib.loads(text)
    os.chdir(SCENES)  # the scene's relative paths
    r = railsim.run(scene, set={"run.distance_m": 5}, progress=False)
    assert len(r) > 10
    with pytest.raises(ValueError, match="speed_m_s"):
        railsim.run(scene, set={"initial.speed_m_s": -5}, progress=False)
    with pytest.raises(ValueError, match="check the unit"):
        railsim.run(scene, set={"run.step_s": 1e-10}, progress=False)


def test_progress_callback_and_ctrl_c_keeps_the_partial_results():
    calls = []
    # Python's own SIGINT handler, even where the test process was started
    # with SIGINT ignored (a background job of a non-interactive shell).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(1.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt) as e:
            # 5 km on an ideal straight: far longer than the 1.5 s.
            railsim.run(
                SCENES / "wheelset_straight.toml",
                set={"track.centerline": None, "track.straight_m": 5100, "run.distance_m": 5000},
                progress=lambda t, total, wall: calls.append((t, total, wall)),
            )
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    partial = e.value.args[1]
    assert isinstance(partial, railsim.Results)
    assert 0 < partial.time_s[-1] < 500.0
    assert partial.summary["stopped"] == "interrupted"
    assert calls and all(total == pytest.approx(500.0) for _, total, _ in calls)


def test_critical_speed_equals_the_cli(sim, tmp_path):
    ours = railsim.critical_speed(SCENES / "bogie_straight.toml", method=["linear"], jobs=2)
    cli = json.loads(
        sim("critical-speed", SCENES / "bogie_straight.toml", "--method", "linear", "--json",
            "--out", tmp_path / "cs").stdout
    )["results"]
    assert len(ours) == len(cli) == 1
    assert ours[0]["method"] == "linear" and ours[0]["creep_law"] == "polach"
    assert ours[0]["speed_m_s"] == pytest.approx(cli[0]["speed_m_s"], rel=1e-12)
    assert 20.0 < ours[0]["speed_m_s"] < 120.0
    with pytest.raises(ValueError, match="method"):
        railsim.critical_speed(SCENES / "bogie_straight.toml", method=["guess"])


def test_to_xarray_keeps_every_series_with_its_unit():
    xr = pytest.importorskip("xarray", reason="pip install xarray (the [test] extra has it)")
    r = railsim.run(SCENES / "wheelset_straight.toml", set={"run.distance_m": 3}, progress=False)
    ds = r.to_xarray()
    assert isinstance(ds, xr.Dataset)
    assert ds.sizes["time_s"] == len(r)
    assert set(ds.data_vars) == set(r.keys()) - {"time_s"}
    np.testing.assert_array_equal(ds["wheelset_0/lateral_m"].values, r["wheelset_0/lateral_m"])
    assert ds["wheelset_0/lateral_m"].attrs["units"] == "m"
    assert ds.attrs["creep_law"] == "polach"
