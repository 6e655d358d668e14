"""The package's surface: version, names, docstrings with units."""

import pathlib
import re

import railsim

REPO = pathlib.Path(__file__).resolve().parents[2]


def test_version_is_the_workspace_version():
    cargo = (REPO / "Cargo.toml").read_text()
    version = re.search(r'^version = "([^"]+)"', cargo, re.M).group(1)
    assert railsim.__version__ == version


def test_every_public_function_documents_its_units():
    for name, unit in [
        ("build_track", "(m)"),
        ("contact", "(mm)"),
        ("creep_forces", "(N)"),
        ("equivalent_conicity", "(mm)"),
        ("run", "set"),
        ("critical_speed", "(m/s)"),
    ]:
        doc = getattr(railsim, name).__doc__
        assert doc and unit in doc, f"railsim.{name}: {doc!r}"
    assert "numpy" in railsim.Results.__doc__
    assert "probe" in railsim.Track.__doc__


def test_stubs_name_every_public_function():
    stub = (REPO / "python" / "railsim" / "_railsim.pyi").read_text()
    for name in railsim.__all__:
        if name != "__version__":
            assert re.search(rf"\b(def|class) {name}\b", stub), name
