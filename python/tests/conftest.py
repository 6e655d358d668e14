"""Shared fixtures of the Python tests: the repository's shipped data, the
`sim` binary the same checkout built (to compare the package with the CLI),
and a private table cache per test session."""

import os
import pathlib
import shutil
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
TABLES = REPO / "tables"
TEST_DATA = REPO / "tests" / "data"


def _sim_binary():
    """The `sim` of this checkout: $RAILSIM_SIM, else target/release/sim or
    target/debug/sim (built by the README's `cargo test`)."""
    explicit = os.environ.get("RAILSIM_SIM")
    if explicit:
        return pathlib.Path(explicit)
    for profile in ("release", "debug"):
        candidate = REPO / "target" / profile / "sim"
        if candidate.exists():
            return candidate
    found = shutil.which("sim")
    return pathlib.Path(found) if found else None


@pytest.fixture(scope="session")
def sim():
    """A function running `sim ARGS…`; returns the CompletedProcess."""
    binary = _sim_binary()
    if binary is None:
        pytest.fail(
            "no `sim` binary to compare with: run `cargo build --bin sim` "
            "(or set RAILSIM_SIM) before the Python tests"
        )

    def run(*args, check=True):
        p = subprocess.run(
            [str(binary), *map(str, args)], capture_output=True, text=True
        )
        if check and p.returncode != 0:
            raise AssertionError(f"sim {' '.join(map(str, args))}: {p.stderr}")
        return p

    return run


@pytest.fixture(autouse=True, scope="session")
def private_cache(tmp_path_factory):
    """Track tables built from a scene's CSV go to a private cache."""
    os.environ["RAILSIM_CACHE_DIR"] = str(tmp_path_factory.mktemp("cache"))
    yield
