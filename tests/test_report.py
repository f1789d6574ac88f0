"""`truckmpc report DIR`: one HTML page for a run or a sweep. Each test parses the page with the
stdlib's html.parser and checks it against the run's own files (summary.json, sweep.csv) read here
independently: the numbers, the pictures, the parameters and a replay command that really replays."""

from __future__ import annotations

import base64
import csv
import json
import shlex
import struct
from html.parser import HTMLParser
from pathlib import Path

import pytest
from typer.testing import CliRunner

from truckmpc.cli import app

ROADS = Path(__file__).resolve().parent.parent / "roads"
ROAD = ROADS / "hill_L500_A2.csv"
runner = CliRunner()


class Page(HTMLParser):
    """What a reader sees of the page: every table (by id, rows of cell texts), every <img> source,
    every <code> text by id, each definition (dt -> dd text), the links, and all of its text."""

    def __init__(self, text: str) -> None:
        super().__init__()
        self.tables: dict[str, list[list[str]]] = {}
        self.images: list[str] = []
        self.codes: dict[str, str] = {}
        self.definitions: dict[str, str] = {}
        self.links: list[str] = []
        self.text: list[str] = []
        self._table: list[list[str]] | None = None
        self._cell: list[str] | None = None
        self._code: tuple[str, list[str]] | None = None
        self._dt: list[str] | None = None
        self._dd: tuple[str, list[str]] | None = None
        self._settings = 0
        self.feed(text)

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        attr = dict(attrs)
        if tag == "table":
            self._table = self.tables.setdefault(attr.get("id") or f"table-{len(self.tables)}", [])
        elif tag == "tr" and self._table is not None:
            self._table.append([])
        elif tag in ("td", "th"):
            self._cell = []
        elif tag == "img":
            self.images.append(attr.get("src") or "")
        elif tag == "code" and attr.get("id"):
            self._code = (attr["id"] or "", [])
        elif tag == "dt":
            self._dt = []
        elif tag == "dd" and self._dt is not None:
            self._dd, self._dt = ("".join(self._dt), []), None
        for name in ("href", "src"):
            if attr.get(name):
                self.links.append(attr[name] or "")

    def handle_endtag(self, tag: str) -> None:
        if tag in ("td", "th") and self._cell is not None and self._table is not None and self._table:
            self._table[-1].append("".join(self._cell).strip())
            self._cell = None
        elif tag == "table":
            self._table = None
        elif tag == "code" and self._code is not None:
            self.codes[self._code[0]] = "".join(self._code[1])
            self._code = None
        elif tag == "dd" and self._dd is not None:
            self.definitions.setdefault(self._dd[0], "".join(self._dd[1]).strip())
            self._dd = None

    def handle_data(self, data: str) -> None:
        self.text.append(data)
        for part in (self._cell, self._code[1] if self._code else None, self._dt, self._dd[1] if self._dd else None):
            if part is not None:
                part.append(data)

    def row(self, table: str, label: str) -> list[str]:
        """The cells after the row heading `label` of `table`."""
        rows = [r for r in self.tables[table] if r and r[0] == label]
        assert len(rows) == 1, f"{label!r} in {table}: {rows}"
        return rows[0][1:]


def cli(*args: str) -> tuple[int, str, str]:
    result = runner.invoke(app, list(args))
    return result.exit_code, result.stdout, result.stderr


def is_png(uri: str) -> bool:
    """Whether a data: URI holds a PNG with a header that names a non-empty picture."""
    prefix = "data:image/png;base64,"
    if not uri.startswith(prefix):
        return False
    data = base64.b64decode(uri[len(prefix) :], validate=True)
    width, height = struct.unpack(">II", data[16:24])  # the IHDR chunk follows the 8-byte signature
    return data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR" and width > 100 and height > 100


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("report") / "run"
    code, _, err = cli(
        "simulate", "--road", str(ROAD), "--controller", "pi,pcc,mpc", "--set", "mass_kg=30000", "--out", str(out)
    )
    assert code == 0, err
    code, stdout, err = cli("report", str(out))
    assert code == 0, err
    assert stdout.strip() == f"wrote {out / 'report.html'}"
    return out


@pytest.fixture(scope="module")
def run_page(run_dir: Path) -> Page:
    return Page((run_dir / "report.html").read_text(encoding="utf-8"))


def test_the_run_table_has_a_column_per_controller_and_the_summary_numbers(run_dir: Path, run_page: Page) -> None:
    summary = json.loads((run_dir / "summary.json").read_text())
    assert run_page.tables["run-table"][0] == ["", "pi", "pcc", "mpc"]
    fuel = [float(c) for c in run_page.row("run-table", "fuel [kg]")]
    time = [float(c) for c in run_page.row("run-table", "trip time [s]")]
    for i, name in enumerate(("pi", "pcc", "mpc")):
        assert fuel[i] == pytest.approx(summary[name]["fuel_kg"], abs=5e-4)
        assert time[i] == pytest.approx(summary[name]["time_s"], abs=0.05)
    equal_time = run_page.row("run-table", "Δfuel at equal trip time vs PI [%]")
    by_controller = {c["controller"]: c for c in summary["comparisons"] if c["baseline"] == "pi"}
    assert equal_time[0] == ""  # the baseline's own cell
    for i, name in ((1, "pcc"), (2, "mpc")):
        assert float(equal_time[i]) == pytest.approx(by_controller[name]["delta_fuel_equal_time_pct"], abs=5e-3)
    page_text = "".join(run_page.text)
    assert f"{abs(by_controller['mpc']['delta_fuel_equal_time_pct']):.2f} %" in page_text  # the headline sentence


def test_the_page_embeds_its_figures_and_fetches_nothing(run_page: Page) -> None:
    assert run_page.images and all(is_png(src) for src in run_page.images)
    assert not [link for link in run_page.links if not link.startswith(("#", "data:"))]


def test_the_page_lists_every_resolved_parameter_and_where_the_run_came_from(run_dir: Path, run_page: Page) -> None:
    record = json.loads((run_dir / "summary.json").read_text())["run"]
    settings_rows = {
        row[0]: row[1]
        for name, rows in run_page.tables.items()
        if rows and rows[0][:2] == ["parameter", "value"]
        for row in rows[1:]
    }
    for section in record["settings"].values():
        for key, value in section.items():
            shown = settings_rows[key]
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                assert float(shown.split(" (default")[0]) == pytest.approx(value, rel=1e-5), key
            elif isinstance(value, str):
                assert shown == value, key
    assert settings_rows["mass_kg"].startswith("30000 (default 40000")  # a changed value names the default
    facts = run_page.definitions
    assert facts["road SHA-256"] == record["road"]["sha256"]
    assert facts["road file"] == str(ROAD)
    assert facts["program"] == f"truckmpc {record['program']['version']}"
    assert facts["--set overrides"] == "mass_kg=30000"


def test_the_replay_command_reproduces_the_run(run_dir: Path, run_page: Page, tmp_path: Path) -> None:
    argv = shlex.split(run_page.codes["replay-command"])
    assert argv[:3] == ["truckmpc", "simulate", "--replay"] and Path(argv[3]) == (run_dir / "summary.json").resolve()
    code, _, err = cli(*argv[1:-1], str(tmp_path / "again"))  # into a directory of this test's
    assert code == 0, err
    first, again = (json.loads((d / "summary.json").read_text()) for d in (run_dir, tmp_path / "again"))
    for name in ("pi", "pcc", "mpc"):
        assert again[name]["fuel_kg"] == first[name]["fuel_kg"]


def test_the_typed_command_is_recorded_shown_and_repeats_the_run(
    run_dir: Path, run_page: Page, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    command = json.loads((run_dir / "summary.json").read_text())["run"]["command"]
    assert command["argv"][:4] == ["truckmpc", "simulate", "--road", str(ROAD)] and Path(command["cwd"]).is_dir()
    cd, directory, and_then, *argv = shlex.split(run_page.codes["typed-command"])
    assert [cd, directory, and_then] == ["cd", command["cwd"], "&&"] and argv == command["argv"]
    monkeypatch.chdir(directory)
    at = argv.index("--out") + 1
    code, _, err = cli(*argv[1:at], str(tmp_path / "again"), *argv[at + 1 :])
    assert code == 0, err
    first, again = (json.loads((d / "summary.json").read_text()) for d in (run_dir, tmp_path / "again"))
    assert [again[n]["fuel_kg"] for n in ("pi", "pcc", "mpc")] == [first[n]["fuel_kg"] for n in ("pi", "pcc", "mpc")]


def test_a_new_run_replaces_the_report_of_the_old(tmp_path: Path) -> None:
    out = tmp_path / "run"
    assert cli("simulate", "--road", str(ROAD), "--controller", "pi", "--out", str(out))[0] == 0
    assert cli("report", str(out), "--out", str(out / "report.html"))[0] == 0
    code, _, err = cli("simulate", "--road", str(ROAD), "--controller", "pi", "--out", str(out))
    assert (
        code == 2
        and err.strip() == f"error: {out}: holds an earlier run; add --replace to replace it, or choose another --out"
    )
    assert cli("simulate", "--road", str(ROAD), "--controller", "pi", "--out", str(out), "--replace")[0] == 0
    assert sorted(p.name for p in out.iterdir()) == ["summary.json", "trace-pi.csv"]


def test_a_second_run_to_the_default_directory_goes_to_a_new_one_and_says_where(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    for _ in range(2):
        code, printed, err = cli("simulate", "--road", str(ROAD), "--controller", "pi")
        assert code == 0, err
    first, second = tmp_path / "out" / ROAD.stem, tmp_path / "out" / f"{ROAD.stem}-2"
    assert (
        f"{Path('out') / ROAD.stem} holds an earlier run: this one goes to {Path('out') / (ROAD.stem + '-2')}"
        in printed
    )
    first_doc, second_doc = (json.loads((d / "summary.json").read_text()) for d in (first, second))
    assert first_doc["pi"]["fuel_kg"] == second_doc["pi"]["fuel_kg"]


@pytest.fixture(scope="module")
def sweep_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("report") / "sweep"
    grid = ("--grid", "horizon_m=500,1000")
    code, _, err = cli("sweep", "--road", str(ROAD), "--controller", "pcc,mpc", *grid, "--jobs", "1", "--out", str(out))
    assert code == 0, err
    return out


def test_a_sweep_report_has_a_row_per_row_of_the_sweep(sweep_dir: Path, tmp_path: Path) -> None:
    target = tmp_path / "sweep.html"
    code, _, err = cli("report", str(sweep_dir), "--out", str(target))
    assert code == 0, err
    assert not (sweep_dir / "report.html").exists()
    page = Page(target.read_text(encoding="utf-8"))
    with (sweep_dir / "sweep.csv").open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    table = page.tables["sweep-table"]
    groups, headings, body = table[0], table[1], table[2:]
    assert groups[1:4] == [
        "mpc vs pcc, equal time and end speed",
        "mpc vs pi, equal time and end speed",
        "pcc vs pi, equal time and end speed",
    ]
    assert headings[0] == "horizon_m" and len(body) == len(rows) == 2
    assert headings[1:3] == ["Δfuel [%]", "saved [kg]"]  # the headline first: the MPC against the PCC
    fuel_at = [i for i, h in enumerate(page.tables["runs-table"][1]) if h == "fuel [kg]"]  # pi, pcc, mpc
    for cells, runs, row in zip(body, page.tables["runs-table"][2:], rows, strict=True):
        assert float(cells[0]) == float(row["horizon_m"])
        for at, name in zip(fuel_at, ("pi", "pcc", "mpc"), strict=True):
            assert float(runs[at]) == pytest.approx(float(row[f"{name}_fuel_kg"]), abs=5e-4)
        own, pcc = float(row["mpc_fuel_corrected_kg"]), float(row["mpc_equal_time_pcc_fuel_corrected_kg"])
        assert float(cells[1]) == pytest.approx(100 * (own - pcc) / pcc, abs=5e-3)
        assert float(cells[2]) == pytest.approx(pcc - own, abs=5e-4)
    assert len(page.images) == 3 and all(is_png(src) for src in page.images)
    replay = shlex.split(page.codes["replay-command"])
    assert replay[:2] == ["cd", json.loads((sweep_dir / "sweep.json").read_text())["command"]["cwd"]]
    assert replay[replay.index("--out") + 1] == str(sweep_dir.resolve()) + "-replay"
    assert "--grid" in replay and "horizon_m=500,1000" in replay
    assert page.definitions["program"].startswith("truckmpc ")


def test_bad_directories_are_one_line_exit_2_and_nothing_written(tmp_path: Path) -> None:
    empty, corrupt, not_a_run = tmp_path / "empty", tmp_path / "corrupt", tmp_path / "other"
    for d in (empty, corrupt, not_a_run):
        d.mkdir()
    (corrupt / "summary.json").write_text('{"road": "x", ')
    (not_a_run / "summary.json").write_text('{"road": "x"}')
    cases = [
        (tmp_path / "missing", "no such directory"),
        (empty, "no summary.json"),
        (corrupt, "summary.json:1: expected a summary.json written by truckmpc simulate, got invalid JSON"),
        (not_a_run, "summary.json: expected a 'run' object"),
    ]
    for directory, expected in cases:
        code, _, err = cli("report", str(directory))
        assert code == 2 and err.startswith("error: ") and len(err.strip().splitlines()) == 1, err
        assert expected in err and str(directory) in err
        assert not (directory / "report.html").exists()
    code, _, err = cli("report", str(corrupt), "--out", str(tmp_path / "elsewhere.html"))
    assert code == 2 and not (tmp_path / "elsewhere.html").exists()


def test_without_matplotlib_the_report_is_written_without_figures_and_says_so(
    run_dir: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from truckmpc.plot import MISSING_MATPLOTLIB, PlotError
    from truckmpc.report import figures

    def no_matplotlib(*args: object, **kwargs: object) -> list[Path]:
        raise PlotError(MISSING_MATPLOTLIB)

    monkeypatch.setattr(figures, "plot_dir", no_matplotlib)
    target = tmp_path / "plain.html"
    code, _, err = cli("report", str(run_dir), "--out", str(target))
    assert code == 0 and MISSING_MATPLOTLIB in err
    page = Page(target.read_text(encoding="utf-8"))
    assert not page.images and "No figures: " + MISSING_MATPLOTLIB in "".join(page.text)
    assert page.tables["run-table"][0] == ["", "pi", "pcc", "mpc"]


def test_the_run_page_leads_with_the_headline_against_the_pcc(run_dir: Path, run_page: Page) -> None:
    """The first sentence of the page is the MPC's saving against the PCC at equal trip time and end
    speed, recomputed here from summary.json's fuels (the PCC re-run at the MPC's trip time)."""
    doc = json.loads((run_dir / "summary.json").read_text(encoding="utf-8"))
    own, pcc = doc["mpc"]["fuel_corrected_kg"], doc["equal_time_mpc_vs_pcc"]["pcc_fuel_corrected_kg"]
    pct = 100 * (own - pcc) / pcc
    lead = next(text for text in run_page.text if text.startswith("The "))
    word = "less" if pct < 0 else "more"
    expected = f"The MPC uses {abs(pct):.2f} % {word} fuel than the PCC at equal trip time and equal end speed"
    assert lead.startswith(expected) and f"({pcc - own:.3f} kg saved)" in lead
