"""railsim — railway vehicle dynamics with the Pombo–Ambrósio–Silva
wheel–rail contact model, from Python.

The same library as the ``sim`` and ``track-preproc`` command lines, with
numpy arrays in and out (docs/guide/python.md):

- :func:`build_track` / :class:`Track` — track tables (``track-preproc
  build``, ``sim probe``);
- :func:`contact` — wheelset contact at prescribed poses (``sim contact
  --poses``);
- :func:`creep_forces` — the creep laws on arrays;
- :func:`equivalent_conicity` — EN 15302;
- :func:`run` / :class:`Results` — a scene run (``sim run``) and its time
  series;
- :func:`critical_speed` — ``sim critical-speed``.

Units are in every name (SI unless it says ``_mm``, ``_mrad``, ``_mpa``);
signs follow the track frame: forward, left, up; forces act on the wheel.
Refused inputs raise ``ValueError`` with the command line's message.
"""

from ._railsim import (
    Results,
    RunFailed,
    Track,
    __version__,
    build_track,
    contact,
    creep_forces,
    critical_speed,
    equivalent_conicity,
    run,
)

__all__ = [
    "Results",
    "RunFailed",
    "Track",
    "__version__",
    "build_track",
    "contact",
    "creep_forces",
    "critical_speed",
    "equivalent_conicity",
    "run",
]
