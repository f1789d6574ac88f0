"""The equal-time search: the baseline's set speed moved until its trip time is a target's.

The baseline's set speed v_ref is adjusted, the speed band moving with it and
the start speed kept (clipped into the moved band), until its trip time equals the look-ahead controller's within
:data:`TIME_TOLERANCE`; the search is regula falsi (Illinois) on the trip time as a function of
v_ref, started from the mean-speed estimate v_ref · t_base / t_target. Each evaluation is a whole
closed-loop run, and it stops on the time tolerance, not on a tolerance in v_ref. Where no v_ref in
the search range reaches the time (the baseline stalls, or cannot go as fast), the result says so.

On a road with target speeds v_ref only caps the targets (the set speed is min(v_ref, target) +
target_offset_kmh), so raising it changes little: there the search moves `target_offset_kmh`
instead, over x = v_ref + offset (the same search, the start speed kept as configured), and reports
the offset found.

The search only calls a function driving the baseline at a set speed;
:mod:`truckmpc.equal_time.baselines` makes that function from the simulation.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from truckmpc.compare import delta_pct
from truckmpc.consumption import FUEL, Consumption, consumption_of
from truckmpc.fuel import summary_corrected

if TYPE_CHECKING:
    from truckmpc.sim import RunResult

__all__ = [
    "MAX_RUNS",
    "SEARCH_KMH",
    "TARGET_OFFSET_LIMIT_KMH",
    "TIME_TOLERANCE",
    "EqualTime",
    "RunAt",
    "equal_time",
]

TIME_TOLERANCE = 1e-4
"""Relative trip-time tolerance of the equal-time baseline (0.01 %)."""

SEARCH_KMH = 15.0
"""The equal-time search keeps v_ref within this many km/h of the run's v_ref [km/h]."""

MAX_RUNS = 16
"""Most baseline runs one equal-time search makes."""

TARGET_OFFSET_LIMIT_KMH = 50.0
"""|target_offset_kmh| the configuration accepts [km/h]: the lower end of the search on a road with
target speeds is v_ref − this."""


@dataclass
class EqualTime:
    """The baseline driven to a target trip time.

    ``setting_kmh`` (the search variable), ``time_s``, ``consumed`` and ``consumed_corrected`` (what
    the run consumed, raw and end-speed corrected, in its ``consumption``'s unit: kg of fuel or kWh
    of battery energy) are those of the closest run found; ``reached`` says whether it is within :data:`TIME_TOLERANCE`,
    and ``reason`` why not. The search variable is v_ref [km/h]; with ``offset_from_kmh`` set (a
    road with target speeds) it is x = v_ref + target_offset_kmh, ``offset_from_kmh`` the v_ref
    [km/h] kept.
    """

    target_time_s: float
    setting_kmh: float | None = None
    time_s: float | None = None
    consumed: float | None = None
    consumed_corrected: float | None = None
    consumption: Consumption = FUEL
    runs: int = 0
    reason: str | None = None
    tried: list[tuple[float, float]] = field(default_factory=list)
    offset_from_kmh: float | None = None

    @property
    def reached(self) -> bool:
        return self.reason is None and self.time_s is not None

    def delta_pct_of(self, consumed: float) -> float | None:
        """Δ [%] of a run that consumed `consumed` (in this baseline's unit) against this baseline
        run; None where the search missed the time."""
        if not self.reached or self.consumed is None:
            return None
        return delta_pct(consumed, self.consumed)

    @property
    def v_ref_kmh(self) -> float | None:
        """The v_ref [km/h] of the closest run: the setting found, or the one kept on a road with
        target speeds."""
        return self.setting_kmh if self.offset_from_kmh is None else self.offset_from_kmh

    @property
    def target_offset_kmh(self) -> float | None:
        """The target offset [km/h] of the closest run on a road with target speeds, else None."""
        if self.offset_from_kmh is None or self.setting_kmh is None:
            return None
        return self.setting_kmh - self.offset_from_kmh

    def setting(self, x_kmh: float | None) -> str:
        """What the search variable `x_kmh` sets, for messages: `v_ref 84.00 km/h` or `target offset +1.00 km/h`."""
        if x_kmh is None:
            return "no setting"
        if self.offset_from_kmh is None:
            return f"v_ref {x_kmh:.2f} km/h"
        return f"target offset {x_kmh - self.offset_from_kmh:+.2f} km/h"

    def document(self, baseline: str = "pi") -> dict[str, Any]:
        """The ``equal_time`` object of ``summary.json``: the re-tuned baseline's figures (keys
        prefixed with its name), null (with ``not_comparable``) where the time was not reached. On a
        road with target speeds, ``<baseline>_v_ref_kmh`` is the v_ref kept and
        ``<baseline>_target_offset_kmh`` the target offset found."""
        found = self.reached
        doc: dict[str, Any] = {
            f"{baseline}_v_ref_kmh": self.v_ref_kmh if found else None,
            f"{baseline}_time_s": self.time_s if found else None,
            f"{baseline}_{self.consumption.key}": self.consumed if found else None,
            f"{baseline}_{self.consumption.corrected_key}": self.consumed_corrected if found else None,
            "target_time_s": self.target_time_s,
            "time_error_pct": delta_pct(self.time_s, self.target_time_s) if found and self.time_s else None,
            f"{baseline}_runs": self.runs,
        }
        if self.offset_from_kmh is not None:
            doc[f"{baseline}_target_offset_kmh"] = self.target_offset_kmh if found else None
        if self.reason is not None:
            doc["not_comparable"] = self.reason
        return doc


RunAt = Callable[[float], "RunResult"]
"""Drive the baseline at a set speed [km/h] (on a road with target speeds: at x = v_ref + target offset)."""


def equal_time(
    run_at: RunAt,
    v_ref_kmh: float,
    v_floor_kmh: float,
    first: RunResult,
    target_time_s: float,
    g_per_half_v2: float,
    offset_from_kmh: float | None = None,
    v_ceiling_kmh: float = math.inf,
) -> EqualTime:
    """Search v_ref in [max(v_ref − SEARCH, v_floor), min(v_ref + SEARCH, v_ceiling)] until the
    baseline's trip time is within :data:`TIME_TOLERANCE` of `target_time_s`; `first` is the
    baseline already driven at `v_ref_kmh`. `v_floor_kmh` and `v_ceiling_kmh` are the lowest and
    highest set speeds [km/h] whose band the truck can drive (a set speed beyond them is refused by
    the core): a time that needs one beyond them is not comparable. With
    `offset_from_kmh` (a road with target speeds) the search variable is x = v_ref + target offset,
    `v_ref_kmh` the configured x and `offset_from_kmh` the v_ref [km/h] the offset counts from."""
    found = EqualTime(target_time_s, offset_from_kmh=offset_from_kmh)
    search = _Search(found, g_per_half_v2, TIME_TOLERANCE * target_time_s)
    lo_kmh, hi_kmh = max(v_ref_kmh - SEARCH_KMH, v_floor_kmh), min(v_ref_kmh + SEARCH_KMH, v_ceiling_kmh)
    if offset_from_kmh is not None:
        # The offset is a key with a range: the search stays inside it.
        hi_kmh = min(hi_kmh, offset_from_kmh + TARGET_OFFSET_LIMIT_KMH)
    error = search.record(v_ref_kmh, first)
    if error is None or search.done(error):
        return search.found
    # Trip time ∝ 1 / mean speed: the first guess scales v_ref by the time ratio.
    v_next: float | None = min(max(v_ref_kmh * (error + target_time_s) / target_time_s, lo_kmh), hi_kmh)
    while search.bracket() is None:
        if search.found.runs >= MAX_RUNS:
            return search.no_bracket()
        if v_next is None:
            return search.unreachable(lo_kmh, hi_kmh)
        if search.done(search.record(v_next, run_at(v_next))):
            return search.found
        v_next = _extrapolate(search.points, lo_kmh, hi_kmh)
    return search.illinois(run_at)


@dataclass
class _Search:
    """The state of one equal-time search: the closest run so far and every (v_ref, time error)."""

    found: EqualTime
    g_per_half_v2: float
    tolerance_s: float
    points: list[tuple[float, float]] = field(default_factory=list)

    def record(self, v_kmh: float, result: RunResult) -> float | None:
        """Note a run at `v_kmh`; its time error [s] (time − target), None if it stalled."""
        found = self.found
        found.runs += 1
        if result.stalled:
            found.reason = f"not comparable: the pi stalls at {found.setting(v_kmh)} ({result.message})"
            return None
        time_s = float(result.summary["time_s"])
        error = time_s - found.target_time_s
        if found.time_s is None or abs(error) < abs(found.time_s - found.target_time_s):
            found.setting_kmh, found.time_s = v_kmh, time_s
            found.consumption = consumption_of(result.summary)
            found.consumed = float(result.summary[found.consumption.key])
            found.consumed_corrected = summary_corrected(result.summary, self.g_per_half_v2)
        self.points.append((v_kmh, error))
        found.tried.append((v_kmh, time_s))
        return error

    def done(self, error: float | None) -> bool:
        return error is None or abs(error) <= self.tolerance_s

    def bracket(self) -> tuple[tuple[float, float], tuple[float, float]] | None:
        """The tightest tried pair whose time errors differ in sign (slow end first), or None."""
        slow = [p for p in self.points if p[1] > 0]
        fast = [p for p in self.points if p[1] < 0]
        if not slow or not fast:
            return None
        return max(slow, key=lambda p: p[0]), min(fast, key=lambda p: p[0])

    def illinois(self, run_at: RunAt) -> EqualTime:
        """False position inside the bracket; an end kept twice in a row has its error halved."""
        bracket = self.bracket()
        assert bracket is not None
        (v_a, e_a), (v_b, e_b) = bracket
        kept_last = 0
        while self.found.runs < MAX_RUNS:
            v = v_a - e_a * (v_b - v_a) / (e_b - e_a)
            error = self.record(v, run_at(v))
            if error is None or self.done(error):
                return self.found
            if error > 0:
                (v_a, e_a), kept = (v, error), 1
                e_b = e_b / 2 if kept_last == kept else e_b
            else:
                (v_b, e_b), kept = (v, error), -1
                e_a = e_a / 2 if kept_last == kept else e_a
            kept_last = kept
        found = self.found
        assert found.time_s is not None
        miss_s = abs(found.time_s - found.target_time_s)
        found.reason = (
            f"not comparable: the baseline's trip time came no closer than {miss_s:.2f} s "
            f"to {found.target_time_s:.1f} s in {MAX_RUNS} runs"
        )
        return found

    def no_bracket(self) -> EqualTime:
        found = self.found
        found.reason = found.reason or (
            f"not comparable: {MAX_RUNS} baseline runs found no set speed on each side of the trip time "
            f"{found.target_time_s:.1f} s"
        )
        return found

    def unreachable(self, lo_kmh: float, hi_kmh: float) -> EqualTime:
        found = self.found
        if found.reason is None:
            slow = self.points[-1][1] > 0
            base = found.offset_from_kmh
            searched = (
                f"v_ref in {lo_kmh:.1f}-{hi_kmh:.1f} km/h"
                if base is None
                else (f"the target offset in {lo_kmh - base:+.1f}..{hi_kmh - base:+.1f} km/h")
            )
            closest = f"{found.setting_kmh:.2f} km/h" if base is None else found.setting(found.setting_kmh)
            found.reason = (
                f"not comparable: the pi cannot reach the trip time {found.target_time_s:.1f} s with {searched} "
                f"(closest {found.time_s:.1f} s at {closest}{', too slow' if slow else ', too fast'})"
            )
        return found


def _extrapolate(points: list[tuple[float, float]], lo_kmh: float, hi_kmh: float) -> float | None:
    """The secant step through the last two points towards the target, 10 % beyond so that the
    next point is likely to bracket it, clamped to the search range; None when that end of the
    range has been tried already."""
    (v_a, e_a), (v_b, e_b) = points[-2], points[-1]
    secant = e_b != e_a
    v = v_b - 1.1 * e_b * (v_b - v_a) / (e_b - e_a) if secant else v_b + (1.0 if e_b > 0 else -1.0)
    v = min(max(v, lo_kmh), hi_kmh)
    if any(abs(v - tried) < 1e-9 for tried, _ in points):
        return None
    return v
