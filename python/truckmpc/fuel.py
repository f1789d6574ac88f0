"""Fuel (or battery energy) bookkeeping that the simulation and the comparisons share: the end-speed
correction, in the unit of what the run consumes (:mod:`truckmpc.consumption`).

**End-speed correction.** Two runs that end at different speeds leave different kinetic energy in
the truck. At a fixed engine speed, engine torque and fuel rate are both affine in the pedal, so
each unit of ½v² [m²/s²] the engine adds costs the same fuel whatever the speed and load (the core's
``Settings.derived()["kinetic_fuel_g_per_half_v2"]``, in the gear the PI's gear logic settles in at v_ref; about
2.2 g per m²/s² for the 40 t truck, some 610 g for the whole of 85 km/h). A run's
end-speed-corrected fuel is its fuel less the fuel worth the kinetic energy it gained from its
start to its end speed (so it grows when the run ends slower than it started)::

    fuel_corrected_kg = fuel_kg − c · ½(v_end² − v_start²) / 1000

:mod:`truckmpc.sim` puts each run's corrected fuel in its summary (``fuel_corrected_kg``);
:mod:`truckmpc.equal_time` prices a re-tuned baseline's at the original run's rate.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from truckmpc.consumption import consumption_of
from truckmpc.units import KMH_PER_MPS

__all__ = ["beta_per_s", "corrected", "kinetic_correction", "plan_gap_pct", "summary_corrected"]


def kinetic_correction(summary: Mapping[str, Any], per_half_v2: float) -> float:
    """What the kinetic energy a run gained from its start to its end speed is worth, in the run's
    consumption's unit (kg of fuel, kWh of battery energy): c · ½(v_end² − v_start²), c in the
    core's store unit (grams, joules) per m²/s²."""
    v_start, v_end = summary["start_speed_kmh"] / KMH_PER_MPS, summary["end_speed_kmh"] / KMH_PER_MPS
    return float(per_half_v2 * 0.5 * (v_end**2 - v_start**2) / consumption_of(summary).store_per_unit)


def corrected(summary: Mapping[str, Any], per_half_v2: float) -> float:
    """A run's consumption (fuel [kg] or battery energy [kWh]) with its end speed brought back to
    its start speed (negative correction when it ends faster than it started)."""
    return float(summary[consumption_of(summary).key]) - kinetic_correction(summary, per_half_v2)


def summary_corrected(summary: Mapping[str, Any], per_half_v2: float) -> float:
    """A run's corrected consumption (:func:`corrected`); for a road driven in legs (a road with
    stops, :mod:`truckmpc.legs`) the sum over its legs, each corrected to its own entry speed. Not
    the summary's own `fuel_corrected_kg` (`energy_corrected_kwh`): that prices kinetic energy in
    the gear at the run's v_ref, while a re-tuned baseline must be priced at the original run's
    (`per_half_v2`)."""
    legs = summary.get("legs")
    if legs is None:
        return corrected(summary, per_half_v2)
    key = consumption_of(summary).key
    return sum(
        corrected(
            {key: leg[key], "start_speed_kmh": leg["entry_speed_kmh"], "end_speed_kmh": leg["exit_speed_kmh"]},
            per_half_v2,
        )
        for leg in legs
    )


def plan_gap_pct(summary: Mapping[str, Any], per_half_v2: float, beta: float | None) -> float | None:
    """How far a whole-road optimum's run is from its plan [%], as a magnitude: the run's consumption
    brought to the plan's end speed (kinetic energy at ``per_half_v2``) and to the plan's trip time
    (each second at ``beta``, the DP's price of time; both in the core's store unit per m²/s²
    and per second), against the plan's own. The closed loop may settle on another split of energy
    and time than the plan on a flat optimum (a battery-electric truck's pulse and glide); this
    compares what the DP minimises. None without a plan, when the plan has no path, or without β (a
    cost that does not price time so)."""
    consumption = consumption_of(summary)
    plan_key = f"plan_{consumption.key}"
    plan, plan_time_s, plan_end_kmh = (summary.get(k) for k in (plan_key, "plan_time_s", "plan_end_speed_kmh"))
    if (
        beta is None
        or plan is None
        or plan_time_s is None
        or plan_end_kmh is None
        or summary.get("stalled")
        or not plan > 0
    ):
        return None
    v_plan, v_end = plan_end_kmh / KMH_PER_MPS, summary["end_speed_kmh"] / KMH_PER_MPS
    brought = per_half_v2 * 0.5 * (v_plan**2 - v_end**2) + beta * (summary["time_s"] - plan_time_s)
    run = float(summary[consumption.key]) + brought / consumption.store_per_unit
    return float(100.0 * abs(run / plan - 1.0))


def beta_per_s(derived: Mapping[str, Any]) -> float | None:
    """β of the fuel_time cost from a run's derived settings, in the core's store unit per second:
    ``beta_j_per_s`` [J/s] for a battery-electric truck, else ``beta_g_per_s`` [g/s]; None with
    another cost."""
    value = derived.get("beta_j_per_s", derived.get("beta_g_per_s"))
    return None if value is None else float(value)
