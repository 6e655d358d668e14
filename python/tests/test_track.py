"""`railsim.build_track` and `Track.probe` against `sim probe`."""

import json

import numpy as np
import pytest

import railsim
from conftest import TABLES


@pytest.fixture(scope="module")
def straight(tmp_path_factory):
    out = tmp_path_factory.mktemp("track") / "straight.h5"
    return railsim.build_track(
        centerline=TABLES / "tracks" / "straight_300m" / "centerline.csv", step_m=0.5, out=out
    )


def test_probe_is_vectorised_and_matches_sim_probe(straight, sim):
    s = np.linspace(10.0, 290.0, 57)
    p = straight.probe(s)
    assert p["left_position_m"].shape == (57, 3)
    assert p["cant_rad"].shape == (57,)
    cli = json.loads(sim("probe", "--s", "123.4", "--json", straight.path).stdout)
    one = straight.probe(123.4)
    assert one["cant_rad"][0] == pytest.approx(cli["cant_rad"], abs=1e-15)
    for rail in cli["rails"]:
        side = rail["side"]
        np.testing.assert_allclose(one[f"{side}_position_m"][0], rail["position_m"], atol=1e-12)
        np.testing.assert_allclose(one[f"{side}_n"][0], rail["n"], atol=1e-12)
        assert one[f"{side}_l_m"][0] == pytest.approx(rail["l_m"], abs=1e-12)


def test_straight_geometry(straight):
    p = straight.probe(np.arange(5.0, 295.0, 7.0))
    # Level straight: no curvature, no cant; rails 1.435 m + 2 × 36 mm
    # apart (profile origins), symmetric about the centreline, left at +y.
    assert np.all(np.abs(p["curvature_1_m"]) < 1e-9)
    assert np.all(np.abs(p["cant_rad"]) < 1e-12)
    spacing = np.linalg.norm(p["left_position_m"] - p["right_position_m"], axis=1)
    np.testing.assert_allclose(spacing, 1.435 + 2 * 0.036, atol=1e-9)
    assert np.all(p["left_position_m"][:, 1] > p["right_position_m"][:, 1])
    # Orthonormal, right-handed frames (b = t × n).
    np.testing.assert_allclose(np.cross(p["t"], p["n"]), p["b"], atol=1e-9)
    assert straight.length_m == pytest.approx(300.0, abs=1e-6)
    assert straight.summary["rows"]["centerline"] > 0


def test_build_refuses_what_the_cli_refuses(tmp_path):
    centerline = TABLES / "tracks" / "straight_300m" / "centerline.csv"
    with pytest.raises(ValueError, match="replace|input"):
        railsim.build_track(centerline=centerline, out=centerline)
    with pytest.raises(ValueError, match="no_such"):
        railsim.build_track(centerline=tmp_path / "no_such.csv", out=tmp_path / "t.h5")
    assert not (tmp_path / "t.h5").exists()  # all or nothing
    with pytest.raises(ValueError, match=r"outside|beyond|range"):
        railsim.Track.open(
            railsim.build_track(centerline=centerline, out=tmp_path / "ok.h5").path
        ).probe([1.0, 1e6])
