"""The PI cruise controller of thesis section 2.5 (table A.4) and its gear logic (table A.3), in Python.

This is the Python implementation the package shipped before the PI moved into the Rust closed loop.
It stays here as an independent reference: driven through the Python loop of ``truckmpc.sim`` (as a
Python-defined controller), it must give the same trace, to the bit, as the Rust PI.

Errors in km/h, integrator states in km/h*s clamped to +-limit; the brake acts on v - v_max; the pedal
integrator starts at the level holding v_ref on the first grade, the brake integrator at its lower
clamp; each decision integrates the current error over the time since the previous one.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from truckmpc.controller import Control, Decision, PlantState
from truckmpc.errors import ConfigError

if TYPE_CHECKING:
    from truckmpc._core import Vehicle
    from truckmpc.config import RunConfig
    from truckmpc.roads import RoadProfile

KMH_PER_MPS = 3.6


class GearLogic:
    """Engine-speed thresholds of table A.3 for a given vehicle.

    Parameters
    ----------
    vehicle
        The truck model; gives the number of gears and the engine speed per unit speed in each gear.
    down_rpm, up_rpm
        Thresholds [rpm] per forward gear, lowest first; ``down_rpm[0]`` (gear 1) and ``up_rpm[-1]``
        (top gear) are None.
    """

    def __init__(self, vehicle: Vehicle, down_rpm: Sequence[float | None], up_rpm: Sequence[float | None]):
        n = vehicle.forward_gears
        if len(down_rpm) != n or len(up_rpm) != n:
            raise ConfigError(
                f"gear_down_rpm/gear_up_rpm: expected {n} entries (one per forward gear), "
                f"got {len(down_rpm)} and {len(up_rpm)}"
            )
        self.forward_gears = n
        # Engine speed is proportional to road speed in a forward gear (2.9).
        self._rpm_per_mps = [0.0] + [vehicle.engine_speed_rpm(1.0, g) for g in range(1, n + 1)]
        self._down = [math.inf] + [-math.inf if x is None else float(x) for x in down_rpm]
        self._up = [math.inf] + [math.inf if x is None else float(x) for x in up_rpm]
        self._down[1] = -math.inf
        self._up[n] = math.inf
        for g in range(1, n + 1):
            if self._down[g] >= self._up[g]:
                raise ConfigError(
                    f"gear_down_rpm: gear {g} downshifts at {self._down[g]:g} rpm, "
                    f"expected below its upshift threshold {self._up[g]:g} rpm"
                )
        for g in range(1, n):
            landing = self._up[g] * self._rpm_per_mps[g + 1] / self._rpm_per_mps[g]
            if landing < self._down[g + 1]:
                raise ConfigError(
                    f"gear_up_rpm: an upshift from gear {g} at {self._up[g]:g} rpm lands at {landing:.0f} rpm "
                    f"in gear {g + 1}, below its downshift threshold {self._down[g + 1]:g} rpm (the gears would hunt)"
                )

    def next_gear(self, gear: int, v_mps: float) -> int:
        """Gear after one evaluation of the thresholds in ``gear`` at speed ``v_mps`` (at most one shift)."""
        if gear <= 0:  # neutral (e.g. handed over by another controller): take the settled gear
            return self.steady_gear(v_mps)
        n_rpm = v_mps * self._rpm_per_mps[gear]
        if n_rpm > self._up[gear]:
            return gear + 1
        if n_rpm < self._down[gear]:
            return gear - 1
        return gear

    def steady_gear(self, v_mps: float) -> int:
        """The gear the logic settles in at constant speed ``v_mps`` when reached by accelerating from gear 1."""
        gear = 1
        for _ in range(2 * self.forward_gears):
            nxt = self.next_gear(gear, v_mps)
            if nxt == gear:
                return gear
            gear = nxt
        return gear  # unreachable with validated thresholds; kept as a bound on the loop


def _clamp(x: float, lo: float, hi: float) -> float:
    return lo if x < lo else hi if x > hi else x


class PiController:
    """The PI cruise controller with gear logic, sampled at every plant step (see the module docstring).

    Parameters
    ----------
    vehicle
        The truck model (for the gear logic and the starting pedal level).
    config
        Gains, integrator limits, speeds [km/h] and gear thresholds [rpm] (``configs/pi.yaml``).
    """

    name = "pi"

    def __init__(self, vehicle: Vehicle, run_config: RunConfig):
        config = run_config.pi
        self._vehicle = vehicle
        self._config = config
        self._gears = GearLogic(vehicle, config.gear_down_rpm, config.gear_up_rpm)
        self._v_ref_kmh = float(run_config.cruise.v_ref_kmh)
        self._v_max_kmh = float(run_config.v_max_kmh)
        self._kp, self._ki = float(config.pedal_kp), float(config.pedal_ki)
        self._kb, self._ib = float(config.brake_kp), float(config.brake_ki)
        self._p_lim = float(config.pedal_integrator_limit)
        self._b_lim = float(config.brake_integrator_limit)
        self.gear = 0
        self.pedal_integrator = 0.0
        self.brake_integrator = 0.0
        self._t_last = 0.0

    @property
    def gear_logic(self) -> GearLogic:
        return self._gears

    def start(self, road: RoadProfile, state: PlantState) -> None:
        """Reset at the start of a run: settled gear, pedal integrator holding v_ref on the first grade."""
        slope = float(road.slope[0]) if len(road.slope) else 0.0
        self.reset(state.v_mps, slope, state.t_s)

    def reset(self, v_mps: float, slope: float, t_s: float = 0.0) -> None:
        """Reset the controller for speed ``v_mps`` [m/s] on grade ``slope`` [-] at time ``t_s`` [s]."""
        v_ref_mps = self._v_ref_kmh / KMH_PER_MPS
        self.gear = self._gears.steady_gear(v_mps)
        hold = self._vehicle.stationary(v_ref_mps, slope, self._gears.steady_gear(v_ref_mps))
        pedal = _clamp(hold["pedal"], 0.0, 1.0)
        self.pedal_integrator = _clamp(pedal / self._ki, -self._p_lim, self._p_lim) if self._ki > 0 else 0.0
        self.brake_integrator = -self._b_lim
        self._t_last = t_s

    def decide(self, state: PlantState) -> Decision:
        """Pedal, brake and gear for the next plant step."""
        dt = state.t_s - self._t_last
        self._t_last = state.t_s
        v_kmh = state.v_mps * KMH_PER_MPS
        e_p = self._v_ref_kmh - v_kmh
        e_b = v_kmh - self._v_max_kmh
        ip = self.pedal_integrator + e_p * dt
        ip = self._p_lim if ip > self._p_lim else -self._p_lim if ip < -self._p_lim else ip
        ib = self.brake_integrator + e_b * dt
        ib = self._b_lim if ib > self._b_lim else -self._b_lim if ib < -self._b_lim else ib
        self.pedal_integrator = ip
        self.brake_integrator = ib
        pedal = self._kp * e_p + self._ki * ip
        brake = self._kb * e_b + self._ib * ib
        pedal = 0.0 if pedal < 0.0 else 1.0 if pedal > 1.0 else pedal
        brake = 0.0 if brake < 0.0 else 1.0 if brake > 1.0 else brake
        self.gear = self._gears.next_gear(self.gear, state.v_mps)
        return Control(pedal, brake, self.gear), None
