"""What a run consumes, named for the truck's store: fuel [kg] for an engine-driven truck, net
battery energy [kWh] for a battery-electric one. The comparisons read a run's consumption through
:func:`consumption_of`, so their keys are named for what they compare (``delta_fuel_pct`` or
``delta_energy_pct``, ``saved_kg`` or ``saved_kwh``) and a figure of one is never read as the
other's.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from truckmpc.units import G_PER_KG, J_PER_KWH

__all__ = ["ENERGY", "FUEL", "Consumption", "consumption_of"]


@dataclass(frozen=True)
class Consumption:
    """One kind of consumption: its word in keys and labels, its summary keys and unit, and how many
    of the core's store units (grams of fuel, joules) make one of its unit."""

    word: str
    key: str
    corrected_key: str
    unit: str
    store_per_unit: float
    beta_key: str
    """The key of β, the look-ahead cost's price of a second, in the store unit per second."""
    label: str
    """What it is called in a sentence or on an axis: ``fuel``, ``battery energy``."""

    def delta_key(self, kind: str = "") -> str:
        """The key of a Δ [%] of this consumption: ``delta_fuel_pct``, ``delta_energy_equal_time_pct``."""
        return f"delta_{self.word}{kind}_pct"

    @property
    def saved_key(self) -> str:
        """The key of what a run saves against its baseline: ``saved_kg`` or ``saved_kwh``."""
        return f"saved_{self.unit.lower()}"

    def worded(self, name: str) -> str:
        """A key, kind or heading written for fuel, written for this consumption: ``fuel`` becomes
        its word and the kilogram its unit (``mpc_saved_kg`` → ``mpc_saved_kwh``,
        ``fuel_equal_time`` → ``energy_equal_time``, ``Δfuel [%]`` → ``Δenergy [%]``,
        ``saved [kg]`` → ``saved [kWh]``); β's key becomes this consumption's."""
        name = name.replace(FUEL.beta_key, self.beta_key).replace(f"[{FUEL.unit}]", f"[{self.unit}]")
        # Only what a consumption names: fuel_kg, fuel_corrected_kg, saved_kg; not mass_kg.
        name = re.sub(rf"(fuel|corrected|saved)_{FUEL.unit}(?=_|$)", rf"\1_{self.unit.lower()}", name)
        return re.sub(rf"(?<![a-z]){FUEL.word}(?![a-z])", self.word, name)


FUEL = Consumption("fuel", "fuel_kg", "fuel_corrected_kg", "kg", G_PER_KG, "beta_g_per_s", "fuel")
ENERGY = Consumption("energy", "energy_kwh", "energy_corrected_kwh", "kWh", J_PER_KWH, "beta_j_per_s", "battery energy")


def consumption_of(summary: Mapping[str, Any]) -> Consumption:
    """A run's consumption, from its summary (or a CSV row of its figures): battery energy where it
    gives ``energy_kwh``, else fuel."""
    return ENERGY if ENERGY.key in summary else FUEL
