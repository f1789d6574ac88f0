"""Fuel–time curves from ``pareto.csv`` rows, and the saving at equal trip time read off them.

A curve is one controller's (trip time [s], end-speed-corrected consumption) points on one road,
sorted by time; between points it is taken as linear. The consumption is fuel [kg], or battery
energy [kWh] in a battery-electric truck's study (:func:`truckmpc.consumption.consumption_of` reads
which from the rows' columns). The equal-time saving of a curve is its corrected consumption at the
baseline's trip time at the reference set speed against the baseline's corrected consumption there:
the headline, at equal trip time and equal end speed (:func:`truckmpc.compare.headline`), in %
(negative: it saves) and in kg or kWh saved. The baseline is the PI, or the PCC when its curve was run.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from truckmpc.compare import HEADLINE_BASELINES, headline
from truckmpc.consumption import consumption_of
from truckmpc.sweep.cells import parse_cell

BASELINE = "pi"
"""The baseline every curve is compared with; also :data:`BASELINES`' others, where they ran."""

BASELINES = HEADLINE_BASELINES
"""The curves a look-ahead curve's saving is read against, in the order it is printed."""


@dataclass(frozen=True)
class Curve:
    """One controller's points on one road, by trip time: times [s], corrected consumptions (fuel
    [kg] or battery energy [kWh]), and the parameter values (set speed or β) they were driven at."""

    road: str
    controller: str
    time_s: np.ndarray
    consumed: np.ndarray
    values: np.ndarray

    def consumed_at(self, time_s: float) -> float | None:
        """Corrected consumption [kg or kWh] at trip time `time_s` by linear interpolation; None
        outside the curve."""
        if len(self.time_s) == 0 or not self.time_s[0] <= time_s <= self.time_s[-1]:
            return None
        return float(np.interp(time_s, self.time_s, self.consumed))


def curves(rows: Sequence[Mapping[str, str]]) -> dict[str, dict[str, Curve]]:
    """Road -> controller -> curve, from ``pareto.csv`` rows (stalled runs left out)."""
    points: dict[tuple[str, str], list[tuple[float, float, float]]] = {}
    for row in rows:
        if parse_cell(row["stalled"]) is not False:
            continue
        time_s, consumed = parse_cell(row["time_s"]), parse_cell(row[consumption_of(row).corrected_key])
        if time_s is None or consumed is None:
            continue
        points.setdefault((row["road"], row["controller"]), []).append((time_s, consumed, parse_cell(row["value"])))
    out: dict[str, dict[str, Curve]] = {}
    for (road, controller), found in points.items():
        found.sort()
        time_s, consumed, values = (np.array(column, dtype=float) for column in zip(*found, strict=True))
        out.setdefault(road, {})[controller] = Curve(road, controller, time_s, consumed, values)
    return out


@dataclass(frozen=True)
class Saving:
    """A look-ahead curve's headline at the baseline's trip time at the reference set speed: Δfuel
    (Δenergy) [%] (negative: it saves) and what it saved [kg or kWh], or why there is none."""

    pct: float | None
    reason: str | None = None
    saved: float | None = None


def reference_point(
    rows: Sequence[Mapping[str, str]], road: str, v_ref_kmh: float, baseline: str = BASELINE
) -> tuple[float, float] | str:
    """(trip time [s], corrected consumption [kg or kWh]) of `baseline` at the reference set speed
    on `road`, or why there is none."""
    for row in rows:
        if row["road"] == road and row["controller"] == baseline and abs(float(row["v_ref_kmh"]) - v_ref_kmh) < 1e-9:
            if parse_cell(row["stalled"]) is not False:
                what = "failed" if row.get("error") else "stalled"
                return f"not comparable: the {baseline} {what} at v_ref {v_ref_kmh:g} km/h"
            return float(row["time_s"]), float(row[consumption_of(row).corrected_key])
    return f"not comparable: no {baseline} run at v_ref {v_ref_kmh:g} km/h (the reference; add it to --speeds)"


def equal_time_savings(
    rows: Sequence[Mapping[str, str]], v_ref_kmh: float, baseline: str = BASELINE
) -> dict[str, dict[str, Saving]]:
    """Road -> look-ahead controller -> its saving at `baseline`'s trip time at `v_ref_kmh` (every
    curve but the PI's and the baseline's); a curve with a stalled run, or whose times do not reach
    the reference's, has none."""
    out: dict[str, dict[str, Saving]] = {}
    stalls = {
        (row["road"], row["controller"]): ("failed" if row.get("error") else "stalled", row["value"])
        for row in rows
        if parse_cell(row["stalled"]) is not False
    }
    for road in dict.fromkeys(row["road"] for row in rows):
        reference = reference_point(rows, road, v_ref_kmh, baseline)
        by_controller = curves(rows).get(road, {})
        for controller in dict.fromkeys(row["controller"] for row in rows if row["road"] == road):
            if controller in (BASELINE, baseline):
                continue
            curve = by_controller.get(controller)
            if isinstance(reference, str):
                saving = Saving(None, reference)
            elif (road, controller) in stalls:
                what, value = stalls[road, controller]
                saving = Saving(None, f"not comparable: {controller} {what} at {value}")
            elif curve is None or (consumed := curve.consumed_at(reference[0])) is None:
                saving = Saving(
                    None, f"not comparable: the {baseline}'s trip time at v_ref is outside {controller}'s times"
                )
            else:
                quoted = headline(consumed, reference[1])
                saving = Saving(quoted.pct, saved=quoted.saved)
            out.setdefault(road, {})[controller] = saving
    return out


def below(curve: Curve, other: Curve, samples: int = 50) -> tuple[bool, float]:
    """Whether `curve` consumes less than `other` at every common trip time (sampled), and the
    smallest margin [kg or kWh] found (other − curve)."""
    lo, hi = max(curve.time_s[0], other.time_s[0]), min(curve.time_s[-1], other.time_s[-1])
    if hi <= lo:
        return False, float("nan")
    grid = np.linspace(lo, hi, samples)
    margin = np.interp(grid, other.time_s, other.consumed) - np.interp(grid, curve.time_s, curve.consumed)
    return bool(np.all(margin > 0)), float(margin.min())
