"""The truck held at a constant speed on a constant grade (``truckmpc model stationary``): the
pedal or brake level that holds it, whether the levels reach, and the eigenvalue of the speed
dynamics there."""

from __future__ import annotations

from typing import Any

from truckmpc import _core
from truckmpc.config import RunConfig
from truckmpc.units import KMH_PER_MPS, PCT_PER_FRACTION

__all__ = ["stationary_point"]


def stationary_point(config: RunConfig, speed_kmh: float, slope_pct: float, gear: int | None = None) -> dict[str, Any]:
    """The stationary point of `config`'s truck at `speed_kmh` [km/h] on `slope_pct` [%, negative
    downhill] in `gear` (0: neutral; None: the gear the PI gear logic settles in at that speed).

    Returns ``speed_kmh``, ``slope_pct``, ``gear``, ``pedal`` and ``brake`` (levels 0..1),
    ``feasible`` (False when the levels were clipped to [0, 1]) and ``eigenvalue_per_m``,
    λ = ∂(dv/ds)/∂v [1/m].
    """
    v_mps = speed_kmh / KMH_PER_MPS
    chosen = _core.steady_gear(config.settings, v_mps) if gear is None else gear
    point = config.core_vehicle.stationary(v_mps, slope_pct / PCT_PER_FRACTION, chosen)
    return {
        "speed_kmh": speed_kmh,
        "slope_pct": slope_pct,
        "gear": chosen,
        "pedal": point["pedal"],
        "brake": point["brake"],
        "feasible": bool(point["feasible"]),
        "eigenvalue_per_m": point["eigenvalue_per_m"],
    }
