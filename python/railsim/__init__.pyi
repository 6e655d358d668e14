from ._railsim import (
    Results as Results,
    RunFailed as RunFailed,
    Track as Track,
    __version__ as __version__,
    build_track as build_track,
    contact as contact,
    creep_forces as creep_forces,
    critical_speed as critical_speed,
    equivalent_conicity as equivalent_conicity,
    run as run,
)

__all__: list[str]
