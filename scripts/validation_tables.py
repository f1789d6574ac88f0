"""Print the validation pages' tables (docs/validation/) as Markdown, by running `truckmpc simulate`.

    python scripts/validation_tables.py pcc                  # docs/validation/pcc.md, the controllers compared
    python scripts/validation_tables.py convergence          # docs/validation/convergence.md, the default
    python scripts/validation_tables.py levels-convergence   # docs/validation/convergence.md, 16 pedal levels
    python scripts/validation_tables.py thesis-convergence   # docs/validation/convergence.md, the thesis preset
    python scripts/validation_tables.py shift-price          # docs/validation/pcc.md, the MPC at each Q4
    python scripts/validation_tables.py neutral-price        # docs/validation/pcc.md, the MPC at each q_neutral
    python scripts/validation_tables.py tractor-shift-price  # docs/validation/pcc.md, VECTO's tractor at each Q4

Each row is one `truckmpc simulate` run on a shared road (../shared/roads from the repository root,
or $TRUCKMPC_SHARED_ROADS); the command of every row is printed above the table. Δ are in %, moves
in percentage points, read from the run's summary.json.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parent.parent
SHARED = Path(os.environ.get("TRUCKMPC_SHARED_ROADS", REPO.parent / "shared" / "roads"))
TRACTOR = SHARED.parent / "vehicles" / "vecto-generic-class5-tractor" / "Class5_Tractor_DECL.xml"
TRUCK_20T = ["--set", "mass_kg=20000"]
VECTO_108 = "eu_vecto_longhaul_2015_108km.csv"
VECTO_100 = "eu_vecto_longhaul_100km.csv"
SE = "se_E6_E20_goteborg_malmo_volvo_chalmers.csv"
EPA = "us_epa_gem_ph2_grade_20km.csv"
US_805 = "us_fastsim_longhaul_805km.csv"
CYCLE = "raw/vecto-longhaul-2015.vdri"
Case = tuple[str, str, list[str]]  # label, road file under SHARED, extra arguments

HILLY: list[Case] = [
    ("VECTO 108 km", VECTO_108, []),
    ("VECTO 108 km reversed", VECTO_108, ["--reverse"]),
    ("VECTO 100 km", VECTO_100, []),
    ("VECTO 100 km reversed", VECTO_100, ["--reverse"]),
    ("SE E6/E20 Göteborg → Malmö", SE, []),
    ("SE E6/E20 Malmö → Göteborg", SE, ["--reverse"]),
    ("US EPA grade 20 km", EPA, []),
    ("US EPA grade 20 km reversed", EPA, ["--reverse"]),
]
PCC_CASES: list[Case] = [
    *HILLY,
    ("VECTO cycle (.vdri, target speeds)", CYCLE, []),
    ("VECTO 108 km, 20 t", VECTO_108, TRUCK_20T),
    ("US long-haul 805 km", US_805, []),
    ("US long-haul 805 km reversed", US_805, ["--reverse"]),
    ("VECTO 108 km, VECTO tractor", VECTO_108, ["--vehicle", str(TRACTOR)]),
    ("VECTO 100 km, VECTO tractor", VECTO_100, ["--vehicle", str(TRACTOR)]),
    ("SE E6/E20, VECTO tractor", SE, ["--vehicle", str(TRACTOR)]),
    ("US EPA 20 km, VECTO tractor", EPA, ["--vehicle", str(TRACTOR)]),
]
THESIS_CASES: list[Case] = [
    ("VECTO 108 km", VECTO_108, []),
    ("VECTO 100 km", VECTO_100, []),
    ("SE E6/E20 Göteborg → Malmö", SE, []),
    ("SE E6/E20 Malmö → Göteborg (`--reverse`)", SE, ["--reverse"]),
    ("US EPA grade 20 km", EPA, []),
    ("US long-haul 805 km", US_805, []),
]


def simulate(road: str, extra: list[str]) -> dict[str, Any]:
    """Run `truckmpc simulate` on a shared road into a temporary directory; return its summary.json."""
    with tempfile.TemporaryDirectory() as out:
        command = ["truckmpc", "simulate", "--road", str(SHARED / road), *extra, "--out", out]
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
        summary: dict[str, Any] = json.loads((Path(out) / "summary.json").read_text(encoding="utf-8"))
        return summary


def signed(value: float | None, digits: int = 2) -> str:
    """A signed figure, `n/a` where the summary has none (a stalled run, no equal-time set speed)."""
    return "n/a" if value is None else f"{value:+.{digits}f}"


def comparison(summary: dict[str, Any], controller: str, baseline: str) -> dict[str, Any]:
    """The summary's comparison of one controller against one baseline."""
    return next(c for c in summary["comparisons"] if c["controller"] == controller and c["baseline"] == baseline)


def raw_and_equal_time(summary: dict[str, Any], controller: str, baseline: str) -> str:
    """Δfuel [%] raw / at equal trip time."""
    found = comparison(summary, controller, baseline)
    return f"{signed(found['delta_fuel_pct'])} / {signed(found.get('delta_fuel_equal_time_pct'))}"


def per_100km(summary: dict[str, Any], controller: str, key: str) -> str:
    return f"{summary[controller][key]:.1f}"


def pcc_row(summary: dict[str, Any]) -> list[str]:
    """One road of the controller comparison (docs/validation/pcc.md)."""
    cc = comparison(summary, "vecto_cc", "pi")
    return [
        f"{signed(cc['delta_fuel_pct'])} ({signed(cc['delta_time_pct'])})",
        raw_and_equal_time(summary, "pcc", "pi"),
        raw_and_equal_time(summary, "pcc", "vecto_cc"),
        raw_and_equal_time(summary, "mpc", "vecto_cc"),
        f"**{raw_and_equal_time(summary, 'mpc', 'pcc')}**",
        per_100km(summary, "pcc", "eco_roll_entries_per_100km"),
        ", ".join(per_100km(summary, c, "neutral_engagements_per_100km") for c in ("pcc", "mpc")),
        ", ".join(per_100km(summary, c, "gear_shifts_per_100km") for c in ("pcc", "mpc")),
    ]


def convergence_row(summary: dict[str, Any], halves: tuple[str, ...] = ("delta", "stage")) -> list[str]:
    """Moves at each of `halves` (δ/2 and S/2): raw Δfuel / Δtime / Δfuel at equal trip time / fuel +
    β·time [points]."""
    moves = summary["convergence"]
    figures = ("fuel", "time", "fuel_equal_time", "cost")
    return [" / ".join(signed(moves.get(f"delta_{figure}_pct_half_{half}")) for figure in figures) for half in halves]


def levels_row(summary: dict[str, Any]) -> list[str]:
    """Moves at δ/2, S/2 and twice the pedal levels, as :func:`convergence_row`."""
    return convergence_row(summary, ("delta", "stage", "pedal"))


def thesis_row(summary: dict[str, Any]) -> list[str]:
    """Δfuel / Δtime against the PI, then the Δfuel moves at δ/2 and S/2 [points]."""
    moves = summary["convergence"]
    return [
        f"{signed(summary['delta_fuel_pct'])} % / {signed(summary['delta_time_pct'])} %",
        f"{signed(moves['delta_fuel_pct_half_delta'], 3)}, {signed(moves['delta_fuel_pct_half_stage'], 3)}",
    ]


Study = tuple[list[Case], list[str], list[str], Callable[[dict[str, Any]], list[str]]]
STUDIES: dict[str, Study] = {
    "pcc": (
        PCC_CASES,
        ["--controller", "pi,vecto_cc,pcc,mpc"],
        [
            "vecto_cc vs PI, raw (Δtime)",
            "PCC vs PI",
            "PCC vs vecto_cc",
            "MPC vs vecto_cc",
            "**MPC vs PCC**",
            "eco-roll entries / 100 km PCC",
            "neutral engagements / 100 km PCC, MPC",
            "gear shifts / 100 km PCC, MPC",
        ],
        pcc_row,
    ),
    "convergence": (PCC_CASES, ["--controller", "pi,mpc", "--check-convergence"], ["δ/2", "S/2"], convergence_row),
    "levels-convergence": (
        HILLY[::2],
        ["--controller", "pi,mpc", "--set", "pedal_levels=16", "--check-convergence"],
        ["δ/2", "S/2", "32 levels"],
        levels_row,
    ),
    "thesis-convergence": (
        THESIS_CASES,
        ["--config", "thesis", "--check-convergence"],
        ["thesis preset: Δfuel / Δtime", "moves at δ/2, S/2"],
        thesis_row,
    ),
}


TRACTOR_BOTH_WAYS: list[Case] = [
    (f"{label}{', reversed' if way else ''}", road, ["--vehicle", str(TRACTOR), *way])
    for label, road in (
        ("VECTO 108 km", VECTO_108),
        ("VECTO 100 km", VECTO_100),
        ("SE E6/E20", SE),
        ("US EPA 20 km", EPA),
        ("US long-haul 805 km", US_805),
    )
    for way in ([], ["--reverse"])
]
SHIFTS = ("gear_shifts_per_100km",)
GEARBOX_OPERATIONS = ("gear_shifts_per_100km", "neutral_engagements_per_100km")

# A price study: per road (rows), one run of the MPC and the PCC per value of one MPC key (columns);
# per cell the count (the sum of the keys) per 100 km of the PCC and the MPC.
PriceStudy = tuple[list[Case], str, list[str], tuple[str, ...]]
PRICES: dict[str, PriceStudy] = {
    "shift-price": (
        [
            ("VECTO 100 km", VECTO_100, []),
            ("US EPA grade 20 km reversed", EPA, ["--reverse"]),
            ("US long-haul 805 km", US_805, []),
        ],
        "q_gear_shift",
        ["20", "40", "60", "80"],
        SHIFTS,
    ),
    "tractor-shift-price": (TRACTOR_BOTH_WAYS, "q_gear_shift", ["0", "15", "30", "60"], GEARBOX_OPERATIONS),
    "neutral-price": (
        [
            ("SE E6/E20 Göteborg → Malmö", SE, []),
            ("VECTO 108 km", VECTO_108, []),
            ("VECTO 100 km", VECTO_100, []),
            ("US long-haul 805 km", US_805, []),
            *PCC_CASES[-3:-1],
        ],
        "q_neutral",
        ["20", "30", "40", "60"],
        ("neutral_engagements_per_100km",),
    ),
}


def price_cell(summary: dict[str, Any], count: tuple[str, ...]) -> str:
    """Δfuel of the MPC against the PCC at equal trip time [%]; then the sum of the `count` keys (per
    100 km) of the PCC and the MPC."""
    found = comparison(summary, "mpc", "pcc")
    counts = (sum(summary[c][key] for key in count) for c in ("pcc", "mpc"))
    return f"{signed(found.get('delta_fuel_equal_time_pct'))}; " + ", ".join(f"{n:.1f}" for n in counts)


def table_head(arguments: str, header: list[str]) -> None:
    """Print the command a table's rows run and the table's heading."""
    print(f"truckmpc simulate --road ROAD {arguments} (per row: the road and its options)\n")
    print("| road | " + " | ".join(header) + " |")
    print("|---|" + "---|" * len(header))


def table_row(case: Case, cells: list[str]) -> None:
    """Print one road's row; its road and options to stderr."""
    label, road, extra = case
    print(f"| {label} | " + " | ".join(cells) + " |", flush=True)
    print(f"  {label}: --road {road} {' '.join(extra)}", file=sys.stderr)


def price_table(study: PriceStudy) -> None:
    """Print a price study's table, a row per road and a column per value of its key."""
    cases, key, values, count = study
    table_head(f"--controller pcc,mpc --set {key}=VALUE", [f"{key} {value}" for value in values])
    for case in cases:
        _, road, extra = case
        runs = [simulate(road, ["--controller", "pcc,mpc", "--set", f"{key}={value}", *extra]) for value in values]
        table_row(case, [price_cell(summary, count) for summary in runs])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("study", choices=sorted([*STUDIES, *PRICES]))
    name = parser.parse_args().study
    if name in PRICES:
        price_table(PRICES[name])
        return
    study = STUDIES[name]
    cases, arguments, header, row = study
    table_head(" ".join(arguments), header)
    for case in cases:
        _, road, extra = case
        table_row(case, row(simulate(road, [*arguments, *extra])))


if __name__ == "__main__":
    main()
