"""The title of ``run.png``: the road and the controllers drawn, then one line per look-ahead
controller with its headline Δfuel — at equal trip time (the baseline re-tuned to its trip time)
against the PI, and against the PCC where one ran; the raw Δfuel and Δtime where no equal-time
figure exists; the reason where the runs are not comparable — then the MPC's settings.

The Δ come from ``comparisons`` in ``summary.json``; a summary written before that list existed
has them as top-level keys (unsuffixed with one look-ahead controller, ``_<controller>`` with
several), which are read instead.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from truckmpc.consumption import consumption_of
from truckmpc.units import M_PER_KM

CONTROLLER_STYLE = {
    "pi": ("PI", "tab:blue"),
    "vecto_cc": ("cruise control (VECTO)", "tab:olive"),
    "pcc": ("PCC (VECTO)", "tab:green"),
    "mpc": ("MPC", "tab:red"),
    "optimal": ("whole-road optimum", "tab:purple"),
}
"""Label and colour per controller, the same in every panel."""

BASELINES = ("pi", "pcc")
"""The baselines whose comparisons the title shows, in that order."""

_SHORT = {"pi": "PI", "pcc": "PCC", "mpc": "MPC", "optimal": "optimum", "vecto_cc": "VECTO CC"}
_KEYS = (
    "delta_fuel_pct",
    "delta_time_pct",
    "delta_fuel_corrected_pct",
    "delta_fuel_equal_time_pct",
    "delta_fuel_equal_time_corrected_pct",
    "not_comparable",
)


def label(name: str) -> str:
    """The legend label of controller `name`."""
    return CONTROLLER_STYLE.get(name, (name, None))[0]


def fmt_pct(value: Any) -> str:
    """A Δ [%] as text: signed, two decimals, a real minus sign; "–" for none."""
    if not isinstance(value, (int, float)) or not math.isfinite(value):
        return "–"
    return "0.00 %" if round(value, 2) == 0 else f"{value:+.2f} %".replace("-", "−")


def comparisons(summary: Mapping[str, Any], names: Sequence[str]) -> list[dict[str, Any]]:
    """The comparisons of a run (``controller``, ``baseline`` and the Δ keys of ``summary.json``),
    from its ``comparisons`` list or, in an older summary, from its top-level keys."""
    listed = summary.get("comparisons")
    if isinstance(listed, list):
        return [c for c in listed if isinstance(c, dict)]
    others = [n for n in names if n != "pi"]
    if not isinstance(summary.get("pi"), dict):
        return []
    found = []
    for name in others:
        suffix = "" if len(others) == 1 else f"_{name}"
        entry = {key: summary[key + suffix] for key in _KEYS if key + suffix in summary}
        if entry:
            found.append({"controller": name, "baseline": "pi", **entry})
    return found


def run_title(summary: Mapping[str, Any], names: Sequence[str]) -> str:
    """The title: road and length, the controllers drawn, each look-ahead controller's headline
    Δ (:func:`headline`), and the MPC's settings if it ran."""
    road = summary.get("road", "?")
    length = summary.get("length_m")
    head = f"{road}" + (f", {length / M_PER_KM:.1f} km" if isinstance(length, (int, float)) else "")
    lines = [head + " — " + ", ".join(label(n) for n in names)]
    entries = comparisons(summary, names)
    for name in names:
        mine = [c for b in BASELINES for c in entries if c.get("controller") == name and c.get("baseline") == b]
        if mine:
            lines.append(f"{label(name)}: {headline(mine, summary, name)}")
    settings = _mpc_settings(summary)
    if "mpc" in names and settings:
        lines.append("MPC settings: " + settings)
    return "\n".join(lines)


def headline(entries: Sequence[Mapping[str, Any]], summary: Mapping[str, Any], name: str) -> str:
    """One controller's Δ against each baseline: Δfuel (Δenergy for a battery-electric truck) at
    equal trip time where there is one, else the raw Δ and Δtime, else why the runs are not
    comparable."""
    equal, others = [], []
    c = consumption_of(summary.get(name) or {})
    for entry in entries:
        baseline = str(entry.get("baseline"))
        base = _SHORT.get(baseline, baseline)
        equal_pct, raw_pct = entry.get(c.delta_key("_equal_time")), entry.get(c.delta_key())
        stalled = _stalled(summary, name) or _stalled(summary, baseline)
        if _finite(equal_pct) and not stalled:
            equal.append(f"{fmt_pct(equal_pct)} vs {base}")
        elif _finite(raw_pct) and not stalled:
            others.append(f"Δ{c.word} {fmt_pct(raw_pct)}, Δtime {fmt_pct(entry.get('delta_time_pct'))} vs {base} (raw)")
        else:
            others.append(f"vs {base}: {stalled or entry.get('not_comparable') or 'no Δ recorded'}")
    parts = [f"Δ{c.word} at equal trip time " + ", ".join(equal)] if equal else []
    gap = summary.get("gap_to_optimal_pct") if name == "mpc" else None
    if _finite(gap):
        parts.append(f"{fmt_pct(gap)} {c.word} against the whole-road optimum")
    return "; ".join(parts + others)


def _finite(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _stalled(summary: Mapping[str, Any], name: str) -> str | None:
    """Why a comparison with controller `name` means nothing, if its run stalled."""
    block = summary.get(name)
    if not (isinstance(block, dict) and block.get("stalled")):
        return None
    where: Any = block.get("stall_distance_m")
    at = f" at km {where / M_PER_KM:.2f}" if _finite(where) else ""
    return f"not comparable: {_SHORT.get(name, name)} stalled{at}"


def _mpc_settings(summary: Mapping[str, Any]) -> str:
    """The MPC's stage, δ, horizon and neutral setting, as text ("" when not recorded)."""
    block = summary.get("mpc")
    s = block.get("settings") if isinstance(block, dict) else None
    if not isinstance(s, dict):
        return ""
    parts = []
    if "stage_m" in s:
        parts.append(f"S {s['stage_m']:g} m")
    if "delta_kmh" in s:
        parts.append(f"δ {s['delta_kmh']:g} km/h")
    if "horizon_m" in s:
        parts.append(f"horizon {s['horizon_m']:g} m")
    if "allow_neutral" in s:
        parts.append("neutral allowed" if s["allow_neutral"] else "no neutral")
    return ", ".join(parts)
