"""The validation pages state what the tool computes: the stationary points of the thesis
reproduction (docs/validation/thesis.md, tables B.1/B.2) are the model's, row by row, and every
image a page shows is one scripts/docs_figures.py makes."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from truckmpc import default_test_track, simulate
from truckmpc.config import SPEC_BY_KEY, load_run_config
from truckmpc.stationary import stationary_point

DOCS = Path(__file__).resolve().parent.parent / "docs"
SCRIPTS = Path(__file__).resolve().parent.parent / "scripts"
# | 40 t | 85 | 0 | 12 | P 0.443, −0.238 | P 0.4487, −0.2420 |
ROW = re.compile(
    r"^\| (\d+) t \| (\d+) \| (−?[\d.]+) \| (\d+|neutral) \| [^|]+ \| ([PB]) ([\d.]+), (−?[\d.]+) \|$", re.M
)


def number(text: str) -> float:
    return float(text.replace("−", "-"))


def stationary_rows() -> list[tuple[str, ...]]:
    return ROW.findall((DOCS / "validation" / "thesis.md").read_text(encoding="utf-8"))


def test_the_page_carries_all_six_rows_of_tables_b1_and_b2() -> None:
    assert len(stationary_rows()) == 6


@pytest.mark.parametrize("row", stationary_rows())
def test_each_stationary_row_is_what_the_model_computes(row: tuple[str, ...]) -> None:
    mass_t, speed, slope, gear, level, value, eigenvalue = row
    config = load_run_config(overrides=[f"mass_kg={int(mass_t) * 1000}"])
    point = stationary_point(config, number(speed), number(slope), 0 if gear == "neutral" else int(gear))
    assert point["gear"] == (0 if gear == "neutral" else int(gear))
    shown = point["pedal"] if level == "P" else point["brake"]
    assert shown == pytest.approx(number(value), abs=0.6 * 10 ** -len(value.split(".")[1]))
    assert point["eigenvalue_per_m"] * 1e3 == pytest.approx(number(eigenvalue), abs=0.6e-4)


def test_every_image_the_pages_show_is_made_by_the_figure_script() -> None:
    shown = set()
    for page in DOCS.rglob("*.md"):
        shown |= set(re.findall(r"\]\(\.\./images/([^)]+\.png)\)", page.read_text(encoding="utf-8")))
    script = (SCRIPTS / "docs_figures.py").read_text(encoding="utf-8")
    assert shown, "the validation pages show no image"
    assert all(f'"{name}"' in script for name in shown), shown


def test_the_pareto_tutorials_pcc_step_is_what_the_pcc_does_at_79_and_81_kmh() -> None:
    """The tutorial explains the step of the PCC's Pareto curve by its enabling speed and quotes the
    test track at 79 and 81 km/h: no use case below the enabling speed, some above, and the savings
    against VECTO's cruise driver it names."""
    text = (DOCS / "tutorials" / "against-pcc.md").read_text(encoding="utf-8")
    enabling = SPEC_BY_KEY["pcc_enabling_speed_kmh"].default
    assert f"at least {enabling:g} km/h (`pcc_enabling_speed_kmh`" in text
    quoted = re.search(r"saves (\d+\.\d) % against the cruise driver instead of (\d+\.\d) %", text)
    assert quoted is not None
    road = default_test_track()
    saving = {}
    for v_ref in (79, 81):
        config = load_run_config(overrides=[f"v_ref_kmh={v_ref}"])
        pcc, cruise = (simulate(road, config, name).summary for name in ("pcc", "vecto_cc"))
        assert (pcc["pcc_events"] > 0) == (v_ref >= enabling)
        saving[v_ref] = f"{(1 - pcc['fuel_kg'] / cruise['fuel_kg']) * 100:.1f}"
    assert (saving[81], saving[79]) == quoted.groups()
