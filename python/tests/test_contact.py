"""`railsim.contact` against `sim contact` on the Manchester benchmark's
A-2.2 poses, and its errors against the CLI's."""

import csv
import math

import numpy as np
import pytest

import railsim
from conftest import TABLES

WHEEL = TABLES / "profiles" / "MBench_S1002_v3.prw"
RAIL = TABLES / "profiles" / "MBench_UIC60_v3.prr"
POSES = TABLES / "contact" / "mbench_a22_poses.csv"
MODEL = dict(young_pa=209.92e9, poisson=0.28, mu=0.3, creep="fastrip")
CLI_MODEL = [
    "--rail-inclination", "0", "--young-pa", "209.92e9", "--poisson", "0.28",
    "--mu", "0.3", "--creep", "fastrip",
]


def _poses():
    with open(POSES) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def test_a22_sweep_equals_the_cli_json(sim, tmp_path):
    p = _poses()
    ours = railsim.contact(
        WHEEL, RAIL, y_mm=p["y_mm"], yaw_mrad=p["yaw_mrad"], roll_rad=p["roll_rad"],
        pitch_rate_rad_s=p["axle_rate_rad_s"], speed_m_s=2.0,
        vertical_force_per_wheel_n=p["vertical_force_per_wheel_n"], **MODEL,
    )
    out = tmp_path / "a22.csv"
    sim("contact", "--wheel", WHEEL, "--rail", RAIL, *CLI_MODEL,
        "--poses", POSES, "--format", "csv", "-o", out)
    with open(out) as f:
        cli = list(csv.DictReader(f))
    assert len(cli) == len(ours["case"]) >= 42  # 21 poses, two wheels, some two patches
    assert list(ours) == list(cli[0])  # the same columns, in the same order
    for key, values in ours.items():
        for i, row in enumerate(cli):
            theirs = row[key]
            if values.dtype.kind == "U":
                assert values[i] == theirs, (key, i)
            elif theirs == "":
                assert math.isnan(values[i]), (key, i)
            else:
                # The CSV prints the shortest text that reads back exactly.
                assert values[i] == pytest.approx(float(theirs), rel=1e-12, abs=1e-12), (key, i)
    # Physics through the arrays: each wheel's patches carry its 10 kN
    # vertical load (the benchmark's load convention) within 0.1 %.
    first = ours["patch"] == 1
    assert np.allclose(ours["wheel_fz_tr_n"][first], 1e4, rtol=1e-3)
    # Centred pose 1: both wheels on their treads, contact angle a few
    # hundredths of a radian.
    pose1 = ours["case"] == 1
    assert set(ours["zone"][pose1]) == {"tread"}
    assert np.all(np.abs(ours["contact_angle_rad"][pose1]) < 0.1)


def test_scalar_pose_and_broadcasting():
    one = railsim.contact(WHEEL, RAIL, y_mm=0.0, **MODEL)
    many = railsim.contact(WHEEL, RAIL, y_mm=[0.0, 0.0, 0.0], yaw_mrad=0.0, **MODEL)
    assert len(one["case"]) == 2
    assert len(many["case"]) == 6
    np.testing.assert_array_equal(many["fn_n"][:2], one["fn_n"])
    # The wheelset shifted left puts the left wheel nearer its flange: a
    # larger rolling radius on the left (positive conicity).
    shifted = railsim.contact(WHEEL, RAIL, y_mm=[0.0, 4.0], **MODEL)
    left = shifted["side"] == "left"
    r = shifted["rolling_radius_mm"][left & (shifted["patch"] == 1)]
    assert r[1] > r[0]


def test_errors_carry_the_cli_message(sim, tmp_path):
    missing = tmp_path / "no_such_wheel.prw"
    with pytest.raises(ValueError) as e:
        railsim.contact(missing, RAIL, y_mm=0.0, **MODEL)
    cli = sim("contact", "--wheel", missing, "--rail", RAIL, *CLI_MODEL, check=False)
    assert cli.returncode != 0
    expected = cli.stderr.strip().removeprefix("error: ")
    assert str(e.value) == expected
    with pytest.raises(ValueError, match="creep"):
        railsim.contact(WHEEL, RAIL, y_mm=0.0, creep="coulomb")
    with pytest.raises(ValueError, match="yaw_mrad has 2 values"):
        railsim.contact(WHEEL, RAIL, y_mm=[0.0, 1.0, 2.0], yaw_mrad=[0.0, 1.0], **MODEL)
