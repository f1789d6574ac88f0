"""Issue 44: the study report of a fleet (two roads, two trucks, no grid) shows the headline as a
figure per road and truck and fits a 1280 px wide window: its table is as wide as the page, its cells
wrap, and it has few enough columns to be read at that width."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from truckmpc.cli import app
from truckmpc.config.keys import CONFIG_DIR

REPO = Path(__file__).resolve().parent.parent
runner = CliRunner()


@pytest.fixture(scope="module")
def fleet_page(tmp_path_factory: pytest.TempPathFactory) -> str:
    pytest.importorskip("matplotlib")
    out = tmp_path_factory.mktemp("fleet") / "sweep"
    roads = [
        arg for name in ("hill_L500_A2.csv", "hill_L300_A-3.csv") for arg in ("--road", str(REPO / "roads" / name))
    ]
    trucks = [f"--vehicle={CONFIG_DIR / name}" for name in ("truck-40t.yaml", "truck-20t.yaml")]
    result = runner.invoke(app, ["sweep", *roads, *trucks, "--controller", "pcc,mpc", "--jobs", "1", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "truck-20t, mpc against the PCC at equal trip time and end speed: Δfuel " in result.stdout
    report = runner.invoke(app, ["report", str(out)])
    assert report.exit_code == 0, report.output
    return (out / "report.html").read_text(encoding="utf-8")


def css_rule(page: str, selector: str) -> str:
    """The declarations of `selector`'s rule in the page's style."""
    match = re.search(re.escape(selector) + r" \{([^}]*)\}", page)
    assert match, selector
    return match.group(1)


def test_the_fleet_report_draws_the_headline_per_road_and_truck(fleet_page: str) -> None:
    assert "No figures" not in fleet_page
    assert fleet_page.count('<img src="data:image/png;base64,') == 1 and "(headline.png)" in fleet_page


def test_the_fleet_report_fits_1280_px(fleet_page: str) -> None:
    # the page's content: at most 1180 px wide with 2rem (32 px) of padding each side, < 1280 px
    assert "max-width: 1180px" in css_rule(fleet_page, "body") and "2rem 4rem" in css_rule(fleet_page, "body")
    table = css_rule(fleet_page, "table.sweep")
    assert "width: 100%" in table and "table-layout: fixed" in table  # never wider than the page
    assert "overflow-wrap: anywhere" in css_rule(fleet_page, "table.sweep th, table.sweep td")
    assert '<div class="wide"><table class="numbers sweep"' not in fleet_page  # nothing scrolls sideways
    head = fleet_page[fleet_page.index('id="sweep-table"') :]
    headings = re.findall(r'<th scope="col"[^>]*>([^<]*)</th>', head[: head.index("</thead>")])
    # road and vehicle, the headline (% and kg) of MPC vs PCC, MPC vs PI, PCC vs PI, Δfuel and Δtime as driven
    assert len(headings) == 2 + 3 * 2 + 2 * 2


def test_a_road_name_wraps_between_its_words(fleet_page: str) -> None:
    """A narrow column breaks a road's name after an underscore, not inside a word, set left as text."""
    table = fleet_page[fleet_page.index('id="sweep-table"') :]
    assert '<td class="key">hill_<wbr>L500_<wbr>A2</td>' in table
    assert "text-align: left" in css_rule(fleet_page, "table.numbers .key")
