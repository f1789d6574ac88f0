"""The PI cruise controller's gear logic (thesis table A.3), for callers outside the closed loop.

The PI controller itself (section 2.5, table A.4) runs in the Rust closed loop
(``truckmpc.simulate(..., "pi")``); this module exposes the gear its logic settles in.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from truckmpc import _core

if TYPE_CHECKING:
    from truckmpc.config import PiConfig


def steady_gear(vehicle: _core.Vehicle, v_mps: float, pi_config: PiConfig) -> int:
    """The gear the PI gear logic (table A.3) settles in at a constant speed ``v_mps`` [m/s], reached
    by accelerating from gear 1.

    Used as the starting gear of a run and as the default gear of ``truckmpc model stationary``.
    """
    return _core.steady_gear(vehicle, v_mps, list(pi_config.gear_down_rpm), list(pi_config.gear_up_rpm))
