"""How much of a look-ahead controller's saving survives a wrong model of the world.

A controller on a real truck knows neither its mass nor the road's slope exactly. Two kinds of
error are studied, each against the PI on the same true truck and road (the PI does not look ahead,
so a wrong map or mass does not change it):

- **mass**: the truck weighs `mass_kg` × (1 ± error) while the controller assumes `mass_kg`
  (`controller_mass_kg`); the reference is the same controller told the true mass;
- **map**: the controller plans on the road with grade noise added (`controller_map`): an AR(1)
  process sampled every `step_m`, standard deviation σ [% of grade] and correlation length
  `correlation_m` (the error of a terrain model or a GPS import after smoothing), integrated to
  altitude; the reference is the controller on the true map.

For each case the table gives the headline first, the controller's Δfuel against the PI at equal
trip time and equal end speed (the PI re-tuned to the controller's time, both end speeds corrected,
:func:`truckmpc.compare.headline`) [%] and the fuel it saves [kg], the share of the reference's
headline saving that is kept, then Δfuel and Δtime as driven [%]. A battery-electric truck's rows
and table speak of battery energy [kWh] (``delta_energy_pct``, ``saved_kwh``).

A VECTO truck's mass is set by its load: the truck of another mass is the same truck with the
payload changed by the difference (:meth:`truckmpc.config.RunConfig.with_truck_values`), no lighter
than empty; its label gives the mass it has.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from truckmpc.compare import compare, headline
from truckmpc.config import RunConfig
from truckmpc.consumption import ENERGY, FUEL, Consumption, consumption_of
from truckmpc.equal_time import equal_time_baselines
from truckmpc.gauss_markov import gauss_markov
from truckmpc.roads import RoadProfile
from truckmpc.roads.profile import altitude_from_grade
from truckmpc.sim import simulate
from truckmpc.units import KG_PER_T, PCT_PER_FRACTION

MASS_ERRORS = (-0.25, 0.25)
"""Relative errors of the truck's mass the controller does not know (the truck is 30 t or 50 t
while the controller assumes 40 t)."""

GRADE_SIGMAS_PCT = (0.2, 0.5, 1.0)
"""Standard deviations of the map's grade noise [% of grade]."""

CORRELATION_M = 100.0
"""Correlation length of the grade noise [m]."""

NOISE_STEP_M = 25.0
"""Spacing of the noisy map's points [m]."""


def noisy_map(road: RoadProfile, sigma_pct: float, seed: int, correlation_m: float = CORRELATION_M) -> RoadProfile:
    """`road` with AR(1) grade noise of standard deviation `sigma_pct` [% of grade] and correlation
    length `correlation_m` [m] added, on points every NOISE_STEP_M metres (and the end)."""
    # The road's own points are kept, so that σ → 0 gives back the road exactly.
    grid_m = np.union1d(road.distance_m, road.resampled(NOISE_STEP_M).distance_m)
    targets = None if road.target_speed_kmh is None else road.target_speed_at(grid_m)
    step_m = np.diff(grid_m)
    rho = np.exp(-step_m / correlation_m)
    shocks = np.random.default_rng(seed).standard_normal(step_m.size)
    # One grade per segment; the last point's is unused by the integration.
    grade = np.append(gauss_markov(rho[1:], sigma_pct / PCT_PER_FRACTION, shocks), 0.0)
    altitude_m = np.interp(grid_m, road.distance_m, road.altitude_m) + altitude_from_grade(grid_m, grade)
    name = f"{road.name}-grade-noise-{sigma_pct:g}pct-seed{seed}"
    return RoadProfile(name, grid_m, altitude_m, road.source, targets)


@dataclass(frozen=True)
class Case:
    """One world: the truck's mass [kg], the mass the controller assumes [kg] and its map's grade
    noise [% of grade, 0: the true road] with the noise's seed."""

    label: str
    mass_kg: float
    controller_mass_kg: float
    sigma_pct: float = 0.0
    seed: int = 0


def cases(mass_kg: float, seeds: Sequence[int]) -> list[Case]:
    """The studied cases: the exact model, each mass error (with its own exact reference), each
    grade noise level for each seed."""
    return cases_of(mass_kg, [mass_kg * (1.0 + error) for error in MASS_ERRORS], seeds)


def cases_of(mass_kg: float, masses_kg: Sequence[float], seeds: Sequence[int]) -> list[Case]:
    """:func:`cases` with the trucks of `masses_kg` [kg] whose controller assumes `mass_kg` [kg]."""
    out = [Case("exact", mass_kg, mass_kg)]
    for truck in masses_kg:
        truck_t, assumed_t = truck / KG_PER_T, mass_kg / KG_PER_T
        out.append(Case(f"truck {truck_t:.3g} t, told it (reference)", truck, truck))
        out.append(Case(f"truck {truck_t:.3g} t, controller assumes {assumed_t:.3g} t", truck, mass_kg))
    for sigma in GRADE_SIGMAS_PCT:
        out += [Case(f"map grade noise {sigma:g} %, seed {seed}", mass_kg, mass_kg, sigma, seed) for seed in seeds]
    return out


def run_case(road: RoadProfile, config: RunConfig, case: Case, controller: str = "mpc") -> dict[str, Any]:
    """Drive the PI and `controller` in `case`'s world; Δfuel, Δtime and Δfuel at equal time [%],
    and the headline (at equal trip time and end speed) [%] with the fuel saved [kg] (battery
    energy [kWh], keys named for it, for a battery-electric truck)."""
    truth = _truth(config, case.mass_kg, case.label)
    world = truth.with_values({"controller_mass_kg": case.controller_mass_kg}, case.label)
    told = noisy_map(road, case.sigma_pct, case.seed) if case.sigma_pct > 0 else None
    # The PI (and its re-tuned runs) know the true truck: only the studied controller is wrong.
    results = {"pi": simulate(road, truth, "pi"), controller: simulate(_with_map(road, told), world, controller)}
    summary = results[controller].summary
    consumption = consumption_of(summary)
    deltas = compare(results["pi"].summary, summary, "pi", controller)
    found = equal_time_baselines(road, truth, results).get(controller)
    equal = None if found is None else found.delta_pct_of(summary[consumption.key])
    base = found.consumed_corrected if found is not None and found.reached else None
    quoted = headline(summary.get(consumption.corrected_key), base)
    return {
        "case": case.label,
        "mass_kg": case.mass_kg,
        "controller_mass_kg": case.controller_mass_kg,
        "grade_sigma_pct": case.sigma_pct,
        "seed": case.seed,
        consumption.delta_key(): deltas.delta_consumed_pct,
        "delta_time_pct": deltas.delta_time_pct,
        consumption.delta_key("_equal_time"): equal,
        "headline_pct": quoted.pct,
        consumption.saved_key: quoted.saved,
        "not_comparable": deltas.not_comparable,
    }


def _truth(config: RunConfig, mass_kg: float, where: str) -> RunConfig:
    """`config`'s truck at `mass_kg` [kg], its controller told that mass: the thesis's truck with
    that ``mass_kg``, a VECTO truck with its payload changed by the difference."""
    if config.truck is None:
        return config.with_values({"mass_kg": mass_kg, "controller_mass_kg": None}, where)
    payload_kg = config.truck.payload_kg + mass_kg - config.truck.mass_kg
    return config.with_truck_values({"payload_kg": payload_kg, "controller_mass_kg": None}, where)


def _with_map(road: RoadProfile, told: RoadProfile | None) -> RoadProfile:
    return road if told is None else dataclasses.replace(road, controller_map=told)


def kept_shares(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Each row with `kept_pct`: its headline saving as a share of its reference's [%] (the exact
    model at the same truck mass); None where either is missing or the reference saves nothing."""
    exact = [row for row in rows if row["controller_mass_kg"] == row["mass_kg"] and not row["grade_sigma_pct"]]
    reference = {row["mass_kg"]: row for row in exact}
    out = []
    for row in rows:
        base = reference.get(row["mass_kg"])
        mine, ref = row["headline_pct"], None if base is None else base["headline_pct"]
        kept = None if mine is None or ref is None or ref >= 0 else PCT_PER_FRACTION * mine / ref
        out.append({**row, "kept_pct": kept})
    return out


def study(
    road: RoadProfile, config: RunConfig, controller: str = "mpc", seeds: Sequence[int] = (1, 2)
) -> list[dict[str, Any]]:
    """Every case of :func:`cases` for `road`, with the shares of the saving kept; a VECTO truck's
    lighter truck no lighter than empty (its payload 0)."""
    mass_kg = float(config.settings.get("mass_kg"))
    masses_kg = [mass_kg * (1.0 + error) for error in MASS_ERRORS]
    if config.truck is not None:
        empty_kg = config.truck.mass_kg - config.truck.payload_kg
        masses_kg = [max(m, empty_kg) for m in masses_kg]
    rows = [run_case(road, config, case, controller) for case in cases_of(mass_kg, masses_kg, seeds)]
    return kept_shares(rows)


def format_study(rows: list[dict[str, Any]], controller: str) -> str:
    """The study as a text table: the headline against the PI [%] and the fuel saved [kg], the
    share of the reference's headline saving kept [%], then Δfuel and Δtime as driven [%]
    (battery energy [kWh] for a battery-electric truck's rows)."""
    consumption = consumption_of_rows(rows)
    word, unit = consumption.word, consumption.unit
    heads = [f"Δ{word} %", f"saved {unit}", f"as driven: Δ{word} %"]
    header = f"{'case':<44} {heads[0]:>8} {heads[1]:>9} {'kept %':>7} {heads[2]:>18} {'Δtime %':>8}"
    lines = [
        f"{controller} against the PI on the true truck and road, at equal trip time and end speed (the PI re-run "
        f"at the {controller}'s trip time, both end speeds corrected), then as driven",
        header,
    ]
    for row in rows:
        cells = [_cell(row[consumption.worded(key)], width, digits) for key, width, digits in _COLUMNS]
        note = f"  ({row['not_comparable']})" if row["not_comparable"] else ""
        lines.append(f"{row['case']:<44} " + " ".join(cells) + note)
    return "\n".join(lines)


_COLUMNS = (
    ("headline_pct", 8, 2),
    ("saved_kg", 9, 3),
    ("kept_pct", 7, 2),
    ("delta_fuel_pct", 18, 2),
    ("delta_time_pct", 8, 2),
)
"""Each column of the table: its row key, width and decimals."""


def consumption_of_rows(rows: Sequence[dict[str, Any]]) -> Consumption:
    """What the study's rows compare: battery energy where they carry ``saved_kwh``, else fuel."""
    return ENERGY if rows and ENERGY.saved_key in rows[0] else FUEL


def _cell(value: float | None, width: int, digits: int) -> str:
    return f"{'n/a':>{width}}" if value is None else f"{value:>+{width}.{digits}f}"
