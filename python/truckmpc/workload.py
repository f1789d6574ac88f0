"""Estimates of a run's work and memory, so that settings which would take practically forever or
fill the memory are refused before anything runs.

The estimates are rough (within a factor of a few) and only decide whether to refuse:

- plant steps ≈ road length / (v_ref · plant_dt_s), each about a tenth of a microsecond of RK4 in the core;
- the MPC's dynamic program ≈ solves × stages × (speed band / δ)² "units" per run (solves = length /
  replan, stages = (horizon + replan) / S − 1; the one-stage decisions in between are negligible);
  each unit is a fraction of the DP's transitions (the gear choices, the admissible band) at a few
  nanoseconds each, folded into one constant, which grows once a solve's rows no longer fit in the
  processor's caches;
- the DP's memory ≈ stages × (speed band / δ)² units at a few bytes each (its cached rows);
- with ``pedal_levels`` K ≥ 2, road stages × (band / δ) × (K − 1) arcs, each computed once (a few
  tenths of a microsecond), and stages × (band / δ) × (K − 1) arcs held (some 70 bytes each, all gears);
- trace rows ≈ road length / trace_step_m, each kept in memory and written to the trace CSV.

The constants are measured; the measurements are in docs/validation/benchmark.md ("The work estimate's
constants").
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from truckmpc.config.keys import CONFIG_DIR
from truckmpc.errors import TruckmpcError
from truckmpc.units import KMH_PER_MPS

if TYPE_CHECKING:
    from truckmpc.config import RunConfig
    from truckmpc.roads import RoadProfile

MAX_WORK_S = 3600.0
"""Estimated work [s] beyond which a command refuses to start without ``--force`` (an hour)."""

MAX_TRACE_ROWS = 2_000_000
"""Most trace rows a run may record (about 0.6 GB in memory while recording, 0.3 GB of CSV); a
10 000 km road at the default 25 m spacing needs 400 000."""

PLANT_STEP_S = 1e-7
"""Seconds per plant step [s] of the Rust closed loop, measured with the PI and rounded up."""

DP_UNIT_S = 1.2e-9
"""Seconds per DP unit (one stage × one grid point²) [s] while a solve's rows fit in the caches:
meant to be right within a factor of ten, enough to refuse hours of work."""

DP_UNIT_LARGE_S = 2.6e-9
"""Seconds per DP unit [s] once a solve's rows outgrow the caches (:data:`DP_CACHED_BYTES`)."""

DP_CACHED_BYTES = 256e6
"""A solve's rows [bytes] beyond which :data:`DP_UNIT_LARGE_S` applies."""

DP_BYTES_PER_UNIT = 2.5
"""Memory of the DP [bytes] per stage × grid point², its cached rows, rounded up from what was measured."""

WHOLE_ROAD_BYTES_PER_POINT = 110.0
"""Memory of a whole-road optimum run [bytes] per road stage × grid point: the plan (its decisions
for every gear and its stored values) and the process, besides the rows it keeps by key
(:data:`WHOLE_ROAD_KEPT_ROWS_BYTES`)."""

WHOLE_ROAD_KEPT_ROWS_BYTES = float(256 << 20)
"""The rows the whole-road solve keeps by stage key [bytes]: the core's budget for them (256 MiB)."""

LEVEL_UNIT_S = 4e-7
"""Seconds per pedal-level arc unit (one road stage × one grid point × one level arc, ``pedal_levels``)
[s]: each is computed once per road stage in every usable gear; a VECTO truck's are the dearer."""

LEVEL_BYTES_PER_UNIT = 70.0
"""Memory [bytes] per cached stage × grid point × pedal level: the arcs of every gear, kept while the
stage stays in the horizon."""

_PLANT_KEYS = ("plant_dt_s", "v_ref_kmh")
_DP_KEYS = ("delta_kmh", "stage_m", "horizon_m", "replan_m", "v_inc_kmh", "v_dec_kmh", "pedal_levels")


class WorkError(TruckmpcError):
    """A run or sweep that would take too long (unless forced) or need too much memory."""


@dataclass(frozen=True)
class Work:
    """Estimated seconds of one run [s]: its plant integration and its dynamic programs; and the
    memory its dynamic program holds [bytes]. A PI run's work is the plant part alone."""

    plant_s: float
    dp_s: float
    dp_bytes: float = 0.0

    @property
    def total_s(self) -> float:
        return self.plant_s + self.dp_s


EQUAL_TIME_RUNS = 5
"""Baseline runs a typical equal-time search makes (:mod:`truckmpc.equal_time`), for estimates."""


def plant_steps(profile: RoadProfile, config: RunConfig) -> float:
    """Plant steps of a run: road length / (v_ref · plant_dt_s) (speeds stay near v_ref)."""
    get = config.settings.get
    return profile.length_m / (float(get("v_ref_kmh")) / KMH_PER_MPS * float(get("plant_dt_s")))


def grid_points(config: RunConfig) -> float:
    """Speed-grid points across the band: (v_inc + v_dec) / δ + 1."""
    get = config.settings.get
    return (float(get("v_inc_kmh")) + float(get("v_dec_kmh"))) / float(get("delta_kmh")) + 1


def solve_units(config: RunConfig) -> float:
    """DP units of one horizon solve: its stages (the horizon, and the stages decided from it until
    the next) × speed-grid points² per stage."""
    derived = config.settings.derived()
    return (derived["horizon_stages"] + derived["replan_stages"] - 1) * grid_points(config) ** 2


def road_stages(profile: RoadProfile, config: RunConfig) -> float:
    """Stage boundaries along the road: one MPC solve at each, one stage of the whole-road plan."""
    return profile.length_m / float(config.settings.get("stage_m")) + 1


def dp_units(profile: RoadProfile, config: RunConfig) -> float:
    """DP units of an MPC run: horizon solves (one per `replan_m`) × :func:`solve_units`."""
    return road_stages(profile, config) / config.settings.derived()["replan_stages"] * solve_units(config)


def run_work(profile: RoadProfile, config: RunConfig, controller: str) -> Work:
    """Estimated seconds and DP memory of one run of `controller` ("pi", "mpc" or "optimal") over
    `profile`. The whole-road optimum is one solve over all the road's stages (computing each stage's
    rows, as the estimate counts, though a grade that comes back finds them kept) and a one-stage
    solve per stage, holding every stage's values."""
    plant_s = plant_steps(profile, config) * PLANT_STEP_S
    stages, points = road_stages(profile, config), grid_points(config)
    level_arcs = max(float(config.settings.get("pedal_levels")) - 1, 0.0)  # the levels between 0 and 1
    # Level arcs: once per road stage in the MPC's cache; twice in the optimum (its one-stage solves
    # keep no rows, and its whole-road solve keeps them only by grade).
    levels_s = stages * points * level_arcs * LEVEL_UNIT_S
    if controller == "optimal":
        dp_s = stages * points**2 * DP_UNIT_LARGE_S + 2 * levels_s
        return Work(plant_s, dp_s, stages * points * WHOLE_ROAD_BYTES_PER_POINT + WHOLE_ROAD_KEPT_ROWS_BYTES)
    if controller != "mpc":
        return Work(plant_s, 0.0)
    rows_bytes = solve_units(config) * DP_BYTES_PER_UNIT
    unit_s = DP_UNIT_S if rows_bytes <= DP_CACHED_BYTES else DP_UNIT_LARGE_S
    derived = config.settings.derived()
    cached_stages = derived["horizon_stages"] + derived["replan_stages"]
    dp_bytes = rows_bytes + cached_stages * points * level_arcs * LEVEL_BYTES_PER_UNIT
    return Work(plant_s, dp_units(profile, config) * unit_s + levels_s, dp_bytes)


def memory_limit_bytes() -> float:
    """Memory a run's dynamic program may hold [bytes]: half the machine's physical memory (8 GB
    where the system does not tell)."""
    try:
        return 0.5 * os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return 8e9


def trace_rows(profile: RoadProfile, config: RunConfig) -> float:
    """Rows of a run's trace: road length / trace_step_m, plus the end point."""
    return profile.length_m / float(config.settings.get("trace_step_m")) + 1


def check_trace(profile: RoadProfile, config: RunConfig) -> None:
    """Refuse a trace of more than :data:`MAX_TRACE_ROWS` rows, naming where trace_step_m was set."""
    rows = trace_rows(profile, config)
    if rows > MAX_TRACE_ROWS:
        raise WorkError(
            f"{config.origins['trace_step_m'].where('trace_step_m')}: expected at most {MAX_TRACE_ROWS} trace rows "
            f"(road length / trace_step_m), got about {rows:.3g} for the {profile.length_m:g} m road"
        )


def check_runs(
    profile: RoadProfile,
    config: RunConfig,
    controllers: Sequence[str],
    *,
    force: bool = False,
    extra: Iterable[RunConfig] = (),
) -> float:
    """The estimated seconds of running `controllers` one after another over `profile`, and the
    MPC at each configuration of `extra` after them; refuse, unless `force`, beyond
    :data:`MAX_WORK_S` or a DP beyond :func:`memory_limit_bytes`, and a trace beyond
    :data:`MAX_TRACE_ROWS` always."""
    check_trace(profile, config)
    works = [run_work(profile, config, name) for name in controllers]
    works += [run_work(profile, other, "mpc") for other in extra]
    total_s = sum(work.total_s for work in works)
    if force:
        return total_s
    if total_s > MAX_WORK_S:
        dp_bound = sum(w.dp_s for w in works) > sum(w.plant_s for w in works)
        where = _culprit(config, _DP_KEYS if dp_bound else _PLANT_KEYS) or (profile.source or profile.name)
        raise WorkError(f"{where}: {too_long(total_s, 'at this setting')}")
    dp_bytes, limit_bytes = max(work.dp_bytes for work in works), memory_limit_bytes()
    if dp_bytes > limit_bytes:
        where = _culprit(config, _DP_KEYS) or (profile.source or profile.name)
        raise WorkError(f"{where}: {too_big(dp_bytes, limit_bytes, 'at this setting')}")
    return total_s


def too_long(seconds: float, what: str) -> str:
    """The refusal's text: `about 3.2 h of work <what> (limit 1 h); pass --force ...`."""
    return f"about {duration(seconds)} of work {what} (limit {duration(MAX_WORK_S)}); pass --force to run it anyway"


def too_big(dp_bytes: float, limit_bytes: float, what: str) -> str:
    """The refusal's text: `about 15 GB of memory for the dynamic program <what> (limit 12 GB); ...`."""
    return (
        f"about {dp_bytes / 1e9:.3g} GB of memory for the dynamic program {what} "
        f"(limit {limit_bytes / 1e9:.3g} GB, half this machine's); pass --force to run it anyway"
    )


def duration(seconds: float) -> str:
    """A duration, briefly: `40 s`, `12 min`, `3.2 h`, `41 days`."""
    if not math.isfinite(seconds):
        return "forever"
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min" if seconds != 3600 else "1 h"
    if seconds < 3 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.3g} days"


def _culprit(config: RunConfig, keys: Iterable[str]) -> str | None:
    """Where the user last set one of `keys` (a `--set` or their own file), else None."""
    chosen = [key for key in keys if key in config.origins and _set_by_user(config.origins[key].text)]
    if not chosen:
        return None
    key = max(chosen, key=lambda k: config.origins[k].rank)
    return config.origins[key].where(key)


def _set_by_user(origin_text: str) -> bool:
    """Whether a value came from the user (a `--set` or a file not among the packaged defaults)."""
    if origin_text.startswith("--set "):
        return True
    path = Path(origin_text.rsplit(":", 1)[0] if origin_text[-1:].isdigit() else origin_text)
    return path.resolve().parent != CONFIG_DIR
