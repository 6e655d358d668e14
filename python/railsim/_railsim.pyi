"""Type stubs of railsim's Rust extension (units in every name; the
docstrings at run time are the reference: help(railsim.contact))."""

import os
from typing import Any, Callable, Mapping, Sequence, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, os.PathLike[str]]
Floats = Union[float, Sequence[float], npt.NDArray[np.float64]]

__version__: str

class RunFailed(RuntimeError):
    """A run that ended early with an error; args[1] holds the Results so far."""

class Track:
    """The per-rail track tables of a table file, in memory."""

    @staticmethod
    def open(path: PathLike) -> Track: ...
    @property
    def path(self) -> str: ...
    @property
    def length_m(self) -> float: ...
    @property
    def s_range_m(self) -> tuple[float, float]: ...
    @property
    def step_m(self) -> float: ...
    @property
    def summary(self) -> dict[str, Any] | None: ...
    def probe(self, s_m: Floats) -> dict[str, npt.NDArray[np.float64]]: ...

def build_track(
    *,
    centerline: PathLike | None = None,
    design: PathLike | None = None,
    cant: PathLike | None = None,
    irregularities: PathLike | None = None,
    scheme: str = "cubic",
    step_m: float = 0.1,
    out: PathLike,
    gauge_m: float | None = None,
    rail_inclination: str | None = None,
    rail: PathLike | None = None,
    wheel: PathLike | None = None,
) -> Track: ...

def contact(
    wheel: PathLike,
    rail: PathLike,
    y_mm: Floats,
    yaw_mrad: Floats | None = None,
    roll_rad: Floats | None = None,
    pitch_rate_rad_s: Floats | None = None,
    wheel_load_n: float = 10000.0,
    speed_m_s: float = 2.0,
    creep: str = "polach",
    mu: float = 0.3,
    young_pa: float = 210e9,
    poisson: float = 0.3,
    gauge_m: float = 1.435,
    back_to_back_m: float = 1.360,
    wheel_radius_m: float = 0.46,
    rail_inclination: str = "0",
    load: str = "vertical",
    patch_location: str = "centre",
    rigid: bool = False,
    rail_profile_cant: str | None = None,
    profile_scheme: str = "cubic",
    vertical_force_per_wheel_n: Floats | None = None,
) -> dict[str, npt.NDArray[Any]]: ...

def equivalent_conicity(
    wheel: PathLike,
    rail: PathLike,
    amplitudes_mm: Floats | None = None,
    gauge_m: float = 1.435,
    back_to_back_m: float = 1.360,
    wheel_radius_m: float = 0.46,
    rail_inclination: str = "1:40",
    y_step_mm: float = 0.1,
    rail_profile_cant: str | None = None,
    profile_scheme: str = "cubic",
) -> dict[str, Any]: ...

def creep_forces(
    law: str,
    xi: Floats,
    eta: Floats,
    phi: Floats,
    a_m: Floats,
    b_m: Floats,
    normal_n: Floats,
    mu: Floats,
    shear_modulus_pa: Floats,
    poisson: Floats,
    speed_m_s: Floats | None = None,
) -> dict[str, npt.NDArray[np.float64]]: ...

class Results:
    """A run's time series by their results-file paths."""

    @staticmethod
    def open(path: PathLike) -> Results: ...
    def __getitem__(self, name: str) -> npt.NDArray[Any]: ...
    def __contains__(self, name: str) -> bool: ...
    def __len__(self) -> int: ...
    def keys(self) -> list[str]: ...
    def units(self, name: str) -> str: ...
    @property
    def time_s(self) -> npt.NDArray[np.float64]: ...
    @property
    def wheelsets(self) -> list[str]: ...
    @property
    def summary(self) -> dict[str, Any] | None: ...
    @property
    def attributes(self) -> dict[str, str | float | int | bool]: ...
    @property
    def scene_toml(self) -> str: ...
    def save(self, path: PathLike) -> None: ...
    def to_xarray(self) -> Any: ...

def run(
    scene: PathLike | Mapping[str, Any] | None = None,
    set: Mapping[str, Any] | None = None,
    progress: bool | Callable[[float, float, float], Any] | None = True,
) -> Results: ...

def critical_speed(
    scene: PathLike | Mapping[str, Any],
    creep: Sequence[str] | None = None,
    method: Sequence[str] | None = None,
    min_m_s: float = 10.0,
    max_m_s: float = 120.0,
    tol_m_s: float = 0.1,
    jobs: int | None = None,
    set: Mapping[str, Any] | None = None,
    out: PathLike | None = None,
    skip_s: float = 1.0,
    ramp_deceleration_m_s2: float = 0.5,
    criterion: str = "all",
) -> list[dict[str, Any]]: ...
