"""The discretisation error of a look-ahead run: the MPC driven again at half the speed step δ, at
half the stage length S and, where it plans pedal levels off the grid, at twice the levels, and how
far Δfuel and Δtime against the baseline move.

The halved runs solve the same problem at a finer resolution: the shift limit keeps its spacing in
metres (k_lim doubled at S/2), weights given per kilometre (``q_speed_below_per_km``,
``q_brake_per_km``) keep their value per kilometre, and a speed-deficit weight Q2 given per stage
keeps the value the run used (its table 6.2 default depends on δ). Weights given per stage (the
thesis's Q2 and Q5) weigh twice as much per kilometre at S/2; that is the cost as defined, not
rounding.

``summary.json`` gets::

    "convergence": {"delta_fuel_pct_half_delta": <points>, "delta_fuel_pct_half_stage": ...,
                    "delta_time_pct_half_delta": ..., "delta_time_pct_half_stage": ...,
                    "delta_fuel_equal_time_pct_half_delta": ..., "..._half_stage": ...,
                    "delta_headline_pct_half_delta": ..., "delta_headline_pct_half_stage": ...,
                    "delta_cost_pct_half_delta": ..., "delta_cost_pct_half_stage": ...,
                    "half_delta": {"delta_kmh", "delta_fuel_pct", "delta_time_pct",
                                   "delta_fuel_equal_time_pct", "fuel_kg", "time_s"},
                    "half_stage": {"stage_m", "k_lim", ...},
                    "half_pedal": {"pedal_levels", ...} and its moves, where pedal_levels > 0,
                    "flag_points": 0.3, "flagged": [<fields beyond it>]}

For a battery-electric truck the same fields compare battery energy and say so: ``energy`` for
``fuel`` in each key (``delta_energy_pct_half_delta``, ``delta_energy_equal_time_pct``,
``energy_kwh``), and the cost is battery energy + β·trip time.

Each ``*_half_*`` field is Δ at the halved setting minus Δ of the run, in percentage points; null
(with ``not_comparable`` in the half's object) when a halved run is not comparable. With the
fuel_time cost, ``delta_cost_pct_half_*`` is how far what that cost minimises moves, fuel (end speed
corrected) + β·trip time, in percent of the PI's fuel; absent with another cost. The headline's
move (``truckmpc simulate``'s; a sweep's rows carry the others) is that of the figure to quote, at
equal trip time and end speed: the equal-time move with both end speeds corrected too, which a run
ending a little faster or slower at a finer resolution does not move. The equal-time
move compares each at the PI re-tuned to its own trip time: a finer resolution that trades fuel for
time along the cost's β moves the raw Δfuel but not this one (null where a search missed its time).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from truckmpc.compare import compare
from truckmpc.config import RunConfig
from truckmpc.consumption import consumption_of
from truckmpc.errors import ConfigError
from truckmpc.fuel import beta_per_s
from truckmpc.roads import RoadProfile
from truckmpc.sim import RunResult, simulate

FLAG_POINTS = 0.3
"""A Δ that moves by more than this many percentage points at a halved setting is flagged."""

HALVES = ("half_delta", "half_stage", "half_pedal")
"""The halved settings, in the order they run: δ/2, S/2 and, where the run plans pedal levels off
the grid (``pedal_levels`` K > 0), the pedal step halved (2K levels)."""

_LABELS = {"half_delta": "δ/2", "half_stage": "S/2", "half_pedal": "2×levels"}
"""How each halving is named in the printed lines."""


def halved_configs(config: RunConfig) -> dict[str, RunConfig]:
    """The run's configuration at δ/2 and at S/2: weights given per kilometre kept, a Q2 given per
    stage (or by table 6.2's δ rule) held at the run's value, k_lim kept at its spacing in metres;
    with pedal levels K > 0, also at 2K levels (the pedal step halved)."""
    settings = config.settings
    derived = settings.derived()
    # Q2 given per kilometre scales with S by itself; per stage (or by the δ rule) it is held.
    pinned: dict[str, Any] = {}
    if settings.get("q_speed_below_per_km") is None:
        pinned["q_speed_below"] = derived["q_speed_below"]
    where = "--check-convergence"
    stage_m, delta_kmh, levels = settings.get("stage_m"), settings.get("delta_kmh"), settings.get("pedal_levels")
    halves = {
        "half_delta": config.with_values({**pinned, "delta_kmh": delta_kmh / 2}, where),
        "half_stage": config.with_values({**pinned, "stage_m": stage_m / 2, "k_lim": 2 * derived["k_lim"]}, where),
    }
    if levels > 0:
        try:
            halves["half_pedal"] = config.with_values({**pinned, "pedal_levels": 2 * levels}, where)
        except ConfigError as error:
            raise ConfigError(f"{error} (the check runs the MPC again at twice pedal_levels = {levels})") from None
    return halves


def run_halves(road: RoadProfile, configs: Mapping[str, RunConfig]) -> dict[str, RunResult]:
    """The MPC over `road` at each halved configuration."""
    return {half: simulate(road, config, "mpc") for half, config in configs.items()}


def convergence_document(
    results: Mapping[str, RunResult],
    halves: Mapping[str, RunResult],
    configs: Mapping[str, RunConfig],
    equal_time_pct: Mapping[str, float | None] | None = None,
    headline_pct: Mapping[str, float | None] | None = None,
) -> dict[str, Any]:
    """The ``convergence`` object of ``summary.json`` from the run's PI and MPC results and the
    halved MPC runs; `equal_time_pct`: Δfuel [%] against the PI re-tuned to the trip time of the
    run (``"mpc"``) and of each half (the keys of `halves`), None where a search missed it;
    `headline_pct`: the headline [%] likewise (both end speeds corrected too), whose moves are
    ``delta_headline_pct_<half>``."""
    base, mpc = results["pi"].summary, results["mpc"].summary
    run, consumption = compare(base, mpc), consumption_of(mpc)
    word = consumption.word
    equal_time_pct = equal_time_pct or {}
    run_equal = equal_time_pct.get("mpc")
    quoted = headline_pct or {}
    doc: dict[str, Any] = {}
    objects: dict[str, dict[str, Any]] = {}
    for half in (half for half in HALVES if half in halves):
        summary = halves[half].summary
        moved = compare(base, summary)
        mpc_settings = configs[half].mpc
        detail: dict[str, Any] = {
            "delta_kmh": mpc_settings.delta_kmh,
            "stage_m": mpc_settings.stage_m,
            "k_lim": configs[half].settings.derived()["k_lim"],
            "pedal_levels": mpc_settings.pedal_levels,
            consumption.delta_key(): moved.delta_consumed_pct,
            "delta_time_pct": moved.delta_time_pct,
            consumption.delta_key("_equal_time"): equal_time_pct.get(half),
            **({"headline_pct": quoted.get(half)} if quoted else {}),
            consumption.key: summary[consumption.key],
            "time_s": summary["time_s"],
        }
        reason = moved.not_comparable or run.not_comparable
        if reason is not None:
            detail["not_comparable"] = reason
        for name, at_run, at_half in (
            (word, run.delta_consumed_pct, moved.delta_consumed_pct),
            ("time", run.delta_time_pct, moved.delta_time_pct),
            (f"{word}_equal_time", run_equal, detail[consumption.delta_key("_equal_time")]),
            *((("headline", quoted.get("mpc"), quoted.get(half)),) if quoted else ()),
        ):
            doc[f"delta_{name}_pct_{half}"] = None if at_run is None or at_half is None else at_half - at_run
        if configs[half].mpc.cost == "fuel_time":
            beta = beta_per_s(configs[half].settings.derived())
            doc[f"delta_cost_pct_{half}"] = None if reason is not None else cost_move_pct(base, mpc, summary, beta)
        objects[half] = detail
    moves = {key: value for key, value in doc.items() if value is not None}
    doc.update(objects)
    doc["flag_points"] = FLAG_POINTS
    doc["flagged"] = [key for key, value in moves.items() if abs(value) > FLAG_POINTS]
    return doc


def cost_move_pct(
    base: Mapping[str, Any], run: Mapping[str, Any], half: Mapping[str, Any], beta: float | None
) -> float | None:
    """How far the cost the fuel_time controller minimises moves from `run` to `half` (summaries),
    in percent of the baseline's consumption: (fuel or battery energy with the end speed corrected +
    β·trip time [s]) at the half less at the run, over the baseline's, in the core's store unit
    (grams, joules; β in that unit per second). None without β (another cost) or where a run has no
    corrected consumption (a stall, an empty battery). The drivability prices (shifts, neutral
    engagements) are left out: they are not fuel or time."""
    consumption = consumption_of(base)
    used = (run.get(consumption.corrected_key), half.get(consumption.corrected_key))
    if beta is None or used[0] is None or used[1] is None:
        return None
    unit = consumption.store_per_unit
    moved = unit * (used[1] - used[0]) + beta * (half["time_s"] - run["time_s"])
    return float(100.0 * moved / (unit * base[consumption.key]))


_MOVED = {
    "fuel": "Δfuel vs PI",
    "energy": "Δenergy vs PI",
    "time": "Δtrip time vs PI",
    "fuel_equal_time": "Δfuel at equal trip time vs PI",
    "energy_equal_time": "Δenergy at equal trip time vs PI",
    "cost": "{word} + β·time vs PI",
    "headline": "headline vs PI",
}
"""How each moved Δ is named in the printed lines (``energy``: a battery-electric truck's)."""


def convergence_lines(doc: Mapping[str, Any], width: int) -> list[str]:
    """The printed table's lines for a ``convergence`` object: how far each Δ moves at the halved
    setting (``Δfuel vs PI δ/2 [pts]``), flagged beyond :data:`FLAG_POINTS`, or why it is not
    comparable."""
    lines = []
    halves = [(half, label) for half, label in _LABELS.items() if half in doc]
    word = "energy" if any(key.startswith("delta_energy_") for key in doc) else "fuel"
    longest = max(len(text) for text in _MOVED.values()) + max(len(f" {label} [pts]") for _, label in halves)
    width = max(width, longest + 2)
    for half, label in halves:
        for name in (word, "time", f"{word}_equal_time", "headline", "cost"):
            key = f"delta_{name}_pct_{half}"
            if key not in doc:  # the cost's move, with another cost than fuel_time
                continue
            value = doc[key]
            text = f"{_MOVED[name].format(word=word)} {label} [pts]"
            if value is None:
                lines.append(f"{text:<{width}}{'n/a':>14}  {doc[half].get('not_comparable', '')}")
                continue
            flag = f"  not converged (> {FLAG_POINTS} pts)" if key in doc["flagged"] else ""
            lines.append(f"{text:<{width}}{value:>+14.2f}{flag}")
    return lines
