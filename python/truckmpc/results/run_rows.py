"""The rows and lines of a run's table (:mod:`truckmpc.results.run_table`), each read from the
``summary.json`` document alone: a controller's figures, its Δ against each baseline, the
equal-time search, the heading and the notes."""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any, NamedTuple

from truckmpc.consumption import ENERGY, FUEL, Consumption, consumption_of
from truckmpc.legs import stops_text
from truckmpc.results.table_model import Row
from truckmpc.schema import SUMMARY
from truckmpc.units import M_PER_KM

__all__ = [
    "Figure",
    "comparison_rows",
    "driving_rows",
    "end_speed_note",
    "equal_time_of",
    "equal_time_rows",
    "figure_rows",
    "heading",
    "notes",
    "optimum_rows",
]

NAMES = {"pi": "PI", "vecto_cc": "VECTO CC", "pcc": "PCC", "mpc": "MPC", "optimal": "optimum"}
"""How a controller is named in a row's label."""

LEGEND = (
    "Δ [%] = (column − baseline) / baseline: negative = less than the baseline.",
    "At equal trip time: the baseline re-run at the set speed that matches the column's trip time.",
    "And end speed: each run's fuel less the fuel worth the kinetic energy it ends with above its start speed.",
)
LEGEND_ENERGY = LEGEND[2].replace("fuel less the fuel", "battery energy less the energy")
"""The end-speed line for a battery-electric truck's runs, whose Δ compare battery energy."""
LEGEND_TARGETS = (LEGEND[0], LEGEND[1].replace("at the set speed", "with its target speeds offset to the speed"))
LEGEND_PCC = (
    "pcc: its neutral coasting entries are the starts of its use cases 1 (coasting ahead of a descent) and 2 "
    "(rolling down one) plus its eco-roll entries, which the eco-roll row counts alone."
)
"""Why the PCC's neutral entries exceed its eco-roll entries (said when the PCC ran)."""


class Figure(NamedTuple):
    """A summary figure: the row reads its declared label (:mod:`truckmpc.schema`) and ``[unit]``,
    each cell the run's ``key`` times ``scale``, formatted with ``spec``. The unit is the declared
    one (none for a count, the per 100 km the label says dropped) unless ``unit`` gives another, as
    a scaled figure must."""

    key: str
    spec: str
    scale: float = 1.0
    unit: str | None = None

    @property
    def label(self) -> str:
        return SUMMARY[self.key].label

    @property
    def shown_unit(self) -> str:
        if self.unit is not None:
            return self.unit
        declared = SUMMARY[self.key].unit.removesuffix("/100km")
        return "" if declared in ("-", "1") else declared


_DRIVING = (
    Figure("fuel_kg_per_100km", ".2f"),
    Figure("energy_kwh_per_100km", ".2f"),
    Figure("recovered_kwh", ".2f"),
    Figure("soc_start_pct", ".2f"),
    Figure("soc_end_pct", ".2f"),
    Figure("mean_speed_kmh", ".2f"),
    Figure("end_speed_kmh", ".2f"),
    Figure("gear_shifts_per_100km", ".1f"),
    Figure("neutral_engagements_per_100km", ".1f"),
    Figure("neutral_distance_m", ".1f", 1 / M_PER_KM, "km"),
    Figure("eco_roll_entries_per_100km", ".1f"),
    Figure("brake_energy_kj", ".1f", 1e-3, "MJ"),
)


def figure_rows(figures: Sequence[Figure], runs: Sequence[Mapping[str, Any]]) -> tuple[Row, ...]:
    """One row per figure, one cell per run ("" where the run has no value)."""
    rows = []
    for figure in figures:
        cells = tuple(_number(run.get(figure.key), figure.spec, figure.scale) for run in runs)
        rows.append(Row(figure.label, figure.shown_unit, cells))
    return tuple(rows)


def driving_rows(runs: Sequence[Mapping[str, Any]]) -> tuple[Row, ...]:
    """Fuel per 100 km, speeds, gear shifts, neutral coasting, the PCC's eco-roll and brake energy.
    A gear shift is a change between forward gears (a stretch in neutral bridged); a neutral entry
    is every declutching from a gear, eco-roll's among them."""
    return figure_rows(_DRIVING, runs)


def comparison_rows(
    summary: Mapping[str, Any],
    columns: Sequence[str],
    measures: Sequence[tuple[str, str]],
    baselines: Sequence[str] | None = None,
) -> tuple[Row, ...]:
    """For each ``(key, label)`` of ``measures`` and each baseline that ran (or of ``baselines``),
    the row ``label vs BASELINE [%]``: each controller's ``key`` (a comparison's Δ [%]) against it
    in its own column; "" where it was not compared (the baseline's own cell) or not comparable (a stalled run:
    :func:`notes` says why)."""
    comparisons = _comparisons(summary)
    rows = []
    for key, label in measures:
        for baseline in _baselines(summary) if baselines is None else baselines:
            cells = []
            for name in columns:
                entry = comparisons.get((name, baseline))
                cells.append("" if entry is None else _number(entry.get(key), "+.2f"))
            rows.append(Row(f"{label} vs {NAMES.get(baseline, baseline)}", "%", tuple(cells)))
    return tuple(rows)


def optimum_rows(summary: Mapping[str, Any], columns: Sequence[str]) -> tuple[Row, ...]:
    """The MPC's fuel (battery energy) above the whole-road optimum's [%], in the MPC's column."""
    if "gap_to_optimal_pct" not in summary:
        return ()
    gap = _number(summary["gap_to_optimal_pct"], "+.2f")
    word = _consumption(summary, columns).word
    return (Row(f"Δ{word} vs optimum", "%", tuple(gap if name == "mpc" else "" for name in columns)),)


def _consumption(summary: Mapping[str, Any], columns: Sequence[str]) -> Consumption:
    """What the runs of the table consume (fuel unless its first run is a battery-electric truck's)."""
    return consumption_of(summary[columns[0]]) if columns else FUEL


def equal_time_rows(summary: Mapping[str, Any], columns: Sequence[str]) -> tuple[Row, ...]:
    """Per baseline, what its equal-time search found for each controller: its set speed (or target
    offset), trip time, fuel (battery energy), runs and time error, and the end-speed-corrected Δ."""
    rows: list[Row] = []
    c = _consumption(summary, columns)
    for baseline in _baselines(summary):
        found = [equal_time_of(summary, name, baseline) for name in columns]
        who = f"{NAMES.get(baseline, baseline)} re-run"
        offset = any(f"{baseline}_target_offset_kmh" in entry for entry in found)
        setting = ("target offset", "target_offset_kmh", "+.2f") if offset else ("v_ref", "v_ref_kmh", ".2f")
        for label, key, unit, spec in (
            (setting[0], setting[1], "km/h", setting[2]),
            ("trip time", "time_s", "s", ".1f"),
            (SUMMARY[c.key].label, c.key, c.unit, ".3f"),
            ("search runs", "runs", "", "d"),
        ):
            cells = tuple(_number(entry.get(f"{baseline}_{key}"), spec) for entry in found)
            rows.append(Row(f"{who}: {label}", unit, cells))
        errors = tuple(_number(entry.get("time_error_pct"), "+.3f") for entry in found)
        rows.append(Row(f"{who}: time error", "%", errors))
        measure = ((c.delta_key("_equal_time_corrected"), f"Δ{c.word} at equal trip time, end speeds corrected"),)
        rows += comparison_rows(summary, columns, measure, (baseline,))
    return tuple(rows)


END_SPEED_GAP_PTS = 0.5
"""How far [points] the end-speed correction may move a Δ at equal trip time before the table says so."""


def end_speed_note(summary: Mapping[str, Any]) -> str | None:
    """One line when the end speeds move some Δ at equal trip time by more than
    :data:`END_SPEED_GAP_PTS` points (the headline is the corrected one); None otherwise."""
    moved = []
    word = "fuel"
    for (name, baseline), entry in _comparisons(summary).items():
        c = consumption_of(summary[name])
        word = c.word
        raw, fair = (_finite(entry.get(key)) for key in (c.delta_key("_equal_time"), "headline_pct"))
        if raw is not None and fair is not None and abs(raw - fair) > END_SPEED_GAP_PTS:
            ends = _ends(summary[name], summary[baseline], name, baseline)
            moved.append(f"{name} vs {NAMES.get(baseline, baseline)} {raw:+.2f} → {fair:+.2f} % ({ends})")
    if not moved:
        return None
    return (
        f"end speeds: correcting them moves Δ{word} at equal trip time by more than {END_SPEED_GAP_PTS:g} points, "
        f"{'; '.join(moved)}: quote the figure at equal trip time and end speed."
    )


def _ends(own: Mapping[str, Any], other: Mapping[str, Any], name: str, baseline: str) -> str:
    """Where two runs end [km/h]; on a road with stops, where each leg ends (each leg is corrected
    to its own entry speed)."""
    if own.get("legs") and other.get("legs"):
        exits = ["/".join(f"{leg['exit_speed_kmh']:.1f}" for leg in run["legs"]) for run in (own, other)]
        return (
            f"each leg corrected to its entry speed; legs end at {exits[0]} km/h for {name}, {exits[1]} for {baseline}"
        )
    return f"{name} ends at {own['end_speed_kmh']:.1f} km/h, {baseline} at {other['end_speed_kmh']:.1f}"


def heading(summary: Mapping[str, Any]) -> str:
    """``road <name>: 108.17 km; truck 40000 kg; v_ref 85 km/h, band 77-90 km/h`` (on a road with
    target speeds, the band around them; with ``--controller-road``, the file the controllers
    planned on after the length); the truck and band from the run record when present."""
    text = f"road {summary.get('road', '?')}: {float(summary.get('length_m', math.nan)) / M_PER_KM:.2f} km"
    run = summary.get("run") or {}
    told = run.get("controller_road")
    if isinstance(told, Mapping) and told.get("path"):
        text += f" (the controllers planned on {Path(str(told['path'])).name})"
    settings = run.get("settings") or {}
    truck = run.get("vehicle")
    if isinstance(truck, Mapping) and truck.get("mass_kg") is not None:
        text += f"; truck {truck['mass_kg']:.0f} kg (VECTO {Path(str(truck.get('vecto_job'))).name})"
    elif (settings.get("vehicle") or {}).get("mass_kg") is not None:
        text += f"; truck {settings['vehicle']['mass_kg']:.0f} kg"
    cruise = settings.get("cruise")
    if not cruise:
        return text
    v_ref, v_inc, v_dec = cruise["v_ref_kmh"], cruise["v_inc_kmh"], cruise["v_dec_kmh"]
    if not _has_targets(summary):
        return text + f"; v_ref {v_ref:g} km/h, band {v_ref - v_dec:g}-{v_ref + v_inc:g} km/h"
    offset = cruise.get("target_offset_kmh") or 0.0
    moved = f" {offset:+g} km/h" if offset else ""
    band = f"band -{v_dec:g}/+{v_inc:g} km/h"
    return text + f"; set speed: the road's targets{moved} up to v_ref {v_ref:g} km/h, {band}"


def notes(summary: Mapping[str, Any], columns: Sequence[str], legend: bool) -> Iterator[str]:
    """The lines under the table: how the stops are driven, the ``legend`` of the Δ (when one is
    shown), why a Δ is not comparable, and each run's message."""
    runs = [summary[name] for name in columns]
    stops = next((run["stops_not_simulated"] for run in runs if run.get("stops_not_simulated")), None)
    if stops is not None:
        legs = stops.get("legs", max(len(run.get("legs") or ()) for run in runs))
        yield stops_text(stops["count"], stops["total_stop_s"], legs)
    if legend:
        lines = LEGEND_TARGETS if _has_targets(summary) else LEGEND
        electric = _consumption(summary, columns) is ENERGY
        yield from (LEGEND_ENERGY if electric and line is LEGEND[2] else line for line in lines)
    if "pcc" in columns:
        yield LEGEND_PCC
    against: dict[tuple[str, str], list[str]] = {}  # (controller, reason): the baselines
    for (name, baseline), entry in _comparisons(summary).items():
        if entry.get("not_comparable"):
            against.setdefault((name, entry["not_comparable"]), []).append(baseline)
    for (name, reason), baselines in against.items():
        yield f"{name} vs {', '.join(baselines)}: {reason}"
    moved = end_speed_note(summary)
    if moved is not None:
        yield moved
    for name, run in zip(columns, runs, strict=True):
        if run.get("message"):
            yield f"{name}: {run['message']}"


def _comparisons(summary: Mapping[str, Any]) -> dict[tuple[str, str], Mapping[str, Any]]:
    """The summary's ``comparisons`` by (controller, baseline)."""
    entries = summary.get("comparisons") or ()
    return {(entry["controller"], entry["baseline"]): entry for entry in entries}


def _baselines(summary: Mapping[str, Any]) -> list[str]:
    """The baselines compared against, in the summary's order (the PI first)."""
    return list(dict.fromkeys(baseline for _, baseline in _comparisons(summary)))


def equal_time_of(summary: Mapping[str, Any], name: str, baseline: str) -> Mapping[str, Any]:
    """The equal-time object of ``name`` against ``baseline`` ({} when there is none): against the
    PI ``equal_time_<name>``, or ``equal_time`` when only two controllers ran."""
    if (name, baseline) not in _comparisons(summary):
        return {}
    if baseline != "pi":
        return summary.get(f"equal_time_{name}_vs_{baseline}") or {}
    return summary.get(f"equal_time_{name}") or summary.get("equal_time") or {}


def _has_targets(summary: Mapping[str, Any]) -> bool:
    """Whether the road has target speeds: the run record says so, or an equal-time search moved a
    target offset."""
    road = (summary.get("run") or {}).get("road") or {}
    if "target_speeds" in road:
        return bool(road["target_speeds"])
    objects = (v for k, v in summary.items() if k.startswith("equal_time") and isinstance(v, Mapping))
    return any(key.endswith("_target_offset_kmh") for entry in objects for key in entry)


def _finite(value: Any) -> float | None:
    """`value` as a float when it is a finite number; None otherwise."""
    finite = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    return float(value) if finite else None


def _number(value: Any, spec: str, scale: float = 1.0) -> str:
    """``value * scale`` formatted with ``spec``; "" for None, NaN, an infinity or no number."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        return ""
    if spec.endswith("d"):
        return format(round(value), spec)
    text = format(value * scale, spec)
    return format(0.0, spec) if float(text) == 0 else text  # no "-0.000"
