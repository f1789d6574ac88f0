"""Types of the native module `truckmpc._core` (the pyo3 binding of truckmpc-core).

Checked against the compiled module by `python -m mypy.stubtest truckmpc._core` in `.ci/run`.
"""

from collections.abc import Mapping
from typing import Any, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "MpcSolver",
    "ParamError",
    "ParamSpec",
    "Plant",
    "Road",
    "Settings",
    "Solution",
    "Vehicle",
    "parameter_specs",
]

class ParamError(ValueError):
    """An invalid parameter: the key, what was expected, the value given, the other keys involved."""

    key: str
    expected: str
    got: str | None
    related: list[str]

@final
class ParamSpec:
    """One declared parameter."""

    @property
    def name(self) -> str: ...
    @property
    def section(self) -> str: ...
    @property
    def kind(self) -> str: ...
    @property
    def unit(self) -> str: ...
    @property
    def doc(self) -> str: ...
    @property
    def default(self) -> Any: ...
    @property
    def choices(self) -> list[str] | None: ...
    @property
    def expected(self) -> str: ...

def parameter_specs() -> list[ParamSpec]:
    """Every declared parameter, section by section."""

@final
class Settings:
    """A validated set of every parameter of a run (keys not given take their defaults)."""

    def __new__(cls, values: Mapping[str, Any]) -> Settings: ...
    def values(self) -> dict[str, Any]: ...
    def get(self, key: str) -> Any: ...
    @property
    def vehicle(self) -> Vehicle: ...
    @property
    def k_lim_stages(self) -> int: ...
    @property
    def q_speed_below_weight(self) -> float: ...

@final
class Vehicle:
    """A validated truck model."""

    def __new__(cls, params: Mapping[str, Any]) -> Vehicle: ...
    @property
    def forward_gears(self) -> int: ...
    @property
    def stall_speed_mps(self) -> float: ...
    def engine_speed_rpm(self, v_mps: float, gear: int) -> float: ...
    def stationary(self, v_mps: float, slope: float, gear: int) -> dict[str, Any]: ...

@final
class Road:
    """A road profile: points and the grade of each segment; flat beyond its end."""

    def __new__(cls, distance_m: npt.NDArray[np.float64], slope: npt.NDArray[np.float64]) -> Road: ...
    @property
    def start_m(self) -> float: ...
    @property
    def end_m(self) -> float: ...
    def altitude_at(self, s_m: float) -> float: ...
    def mean_slope(self, s0_m: float, s1_m: float) -> float: ...

_StateTuple = tuple[float, float, float, float, float, bool]

@final
class Plant:
    """The simulated truck, stepped from Python."""

    def __new__(cls, vehicle: Vehicle, road: Road, s_m: float, v_mps: float) -> Plant: ...
    def state(self) -> _StateTuple: ...
    def step_until(self, pedal: float, brake: float, gear: int, dt_s: float, s_limit_m: float) -> _StateTuple: ...
    def advance_to(self, pedal: float, brake: float, gear: int, dt_s: float, s_target_m: float) -> _StateTuple: ...

@final
class Solution:
    """What one DP solve decided for its first stage."""

    @property
    def feasible(self) -> bool: ...
    @property
    def pedal(self) -> float: ...
    @property
    def brake(self) -> float: ...
    @property
    def gear(self) -> int: ...
    @property
    def cost(self) -> float: ...
    @property
    def states(self) -> int: ...
    @property
    def transitions(self) -> int: ...

@final
class MpcSolver:
    """The look-ahead DP on a road, one solve at a time."""

    def __new__(cls, settings: Settings, road: Road) -> MpcSolver: ...
    def predict_speed(self, s_m: float, v_mps: float, pedal: float, brake: float, gear: int) -> float: ...
    def solve(self, s_m: float, v_mps: float, gear: int, stages_since_shift: int) -> Solution: ...
