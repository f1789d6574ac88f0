"""Property: whatever road file, config file and `--set` values `truckmpc simulate` is given, it
either succeeds with complete outputs (exit 0, summary.json and a trace per controller) or fails
with exactly one `error:` line, exit 2, no traceback and no output directory; never anything else.

The default run tries a few dozen examples; the 10 000-example run is selected with
``python -m pytest -m slow tests/test_cli_property.py``.
"""

from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from truckmpc.cli import app
from truckmpc.config import KEYS, VEHICLE_KEYS

runner = CliRunner()

# Keys whose values multiply the MPC's work: an MPC example leaves them alone so that it stays fast
# (the PI examples vary them; refusing hour-long settings is tested in tests/test_workload.py).
MPC_WORK_KEYS = {"stage_m", "horizon_m", "delta_kmh", "v_inc_kmh", "v_dec_kmh", "plant_dt_s", "trace_step_m"}

NUMBERS = (
    st.sampled_from([0, 1, -1, 2, 12, 85, 1000, 40000, 0.5, 0.05, 1e-3, 1e-9, 1e6, 1e308, -1e308, 1e-308, 1e400, -0.0])
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.integers(-(10**20), 10**20)
)
SCALAR_TEXT = st.sampled_from(
    ["true", "false", "null", "~", "nearest", "interpolate", "moving", "fixed", ".nan", ".inf", "-.inf", "'x'", ""]
)
LISTS = st.lists(NUMBERS | st.none(), max_size=14).map(lambda items: "[" + ", ".join(_yaml(v) for v in items) + "]")
VALUE_TEXT = NUMBERS.map(lambda v: _yaml(v)) | SCALAR_TEXT | LISTS | st.text(max_size=12)


def _yaml(value: object) -> str:
    if value is None:
        return "null"
    if isinstance(value, float) and not math.isfinite(value):
        return ".nan" if math.isnan(value) else (".inf" if value > 0 else "-.inf")
    return repr(value)


@st.composite
def valid_road(draw: st.DrawFn) -> str:
    """A road of 2 to 6 points over at most about 400 m, grades within +-10 %."""
    count = draw(st.integers(2, 6))
    steps = draw(st.lists(st.floats(1.0, 80.0), min_size=count - 1, max_size=count - 1))
    grades = draw(st.lists(st.floats(-0.1, 0.1), min_size=count - 1, max_size=count - 1))
    start = draw(st.sampled_from([0.0, 0.0, 1000.0, -50.0]))
    distance, altitude = [start], [0.0]
    for step, grade in zip(steps, grades, strict=True):
        distance.append(distance[-1] + step)
        altitude.append(altitude[-1] + grade * step)
    lines = [f"{d!r},{h!r}" for d, h in zip(distance, altitude, strict=True)]
    return "# a road\ndistance_m,altitude_m\n" + "\n".join(lines) + "\n"


CELLS = st.sampled_from(["nan", "inf", "-inf", "1e308", "-1e308", "1e400", "", "x", "1,2", "0x10", "１", "1e-320"])


@st.composite
def broken_road(draw: st.DrawFn) -> str:
    """A valid road with one thing done to it, or arbitrary text."""
    lines = draw(valid_road()).splitlines()
    how = draw(st.sampled_from(["cell", "swap", "drop_header", "repeat", "columns", "steep", "text"]))
    row = draw(st.integers(2, len(lines) - 1))
    if how == "cell":
        cells = lines[row].split(",")
        cells[draw(st.integers(0, 1))] = draw(CELLS | st.text(max_size=8))
        lines[row] = ",".join(cells)
    elif how == "swap" and len(lines) > 3:
        lines[2], lines[3] = lines[3], lines[2]
    elif how == "drop_header":
        del lines[1]
    elif how == "repeat":
        lines.insert(row, lines[row])
    elif how == "columns":
        lines[row] += ",1"
    elif how == "steep":
        distance = lines[row].split(",")[0]
        lines[row] = f"{distance},{draw(st.sampled_from(['1e6', '-1e6', '1e308']))}"
    else:
        return draw(st.text(max_size=80))
    return "\n".join(lines) + "\n"


@st.composite
def config_file(draw: st.DrawFn, keys: list[str]) -> str | None:
    """None (no --config), a mapping of known and unknown keys to values, or arbitrary text."""
    kind = draw(st.sampled_from(["none", "none", "mapping", "mapping", "text"]))
    if kind == "none":
        return None
    if kind == "text":
        return draw(st.text(max_size=60))
    names = draw(st.lists(st.sampled_from([*keys, "mass_kg", "unknown_key"]), max_size=3))
    return "".join(f"{name}: {draw(VALUE_TEXT)}\n" for name in names)


@st.composite
def cli_case(draw: st.DrawFn) -> tuple[str, str, str | None, list[str]]:
    """(controller, road text, config text or None, --set items)."""
    controller = draw(st.sampled_from(["pi"] * 9 + ["mpc"]))
    keys = [k for k in KEYS if controller == "pi" or k not in MPC_WORK_KEYS]
    road = draw(valid_road() | broken_road()) if controller == "pi" else draw(valid_road())
    config = draw(config_file([k for k in keys if k not in VEHICLE_KEYS]))
    sets = draw(st.lists(st.tuples(st.sampled_from([*keys, "nope"]), VALUE_TEXT), max_size=3))
    return controller, road, config, [f"{key}={value}" for key, value in sets]


def check_case(case: tuple[str, str, str | None, list[str]]) -> int:
    """Run one case in a fresh directory; assert the property; return the exit code."""
    controller, road, config, sets = case
    with tempfile.TemporaryDirectory() as tmp:
        tmp_path = Path(tmp)
        (tmp_path / "road.csv").write_text(road, encoding="utf-8", errors="surrogatepass")
        args = ["simulate", "--road", str(tmp_path / "road.csv"), "--controller", controller]
        if config is not None:
            (tmp_path / "c.yaml").write_text(config, encoding="utf-8", errors="surrogatepass")
            args += ["--config", str(tmp_path / "c.yaml")]
        for item in sets:
            args += ["--set", item]
        out = tmp_path / "out"
        result = runner.invoke(app, [*args, "--out", str(out)])
        assert "Traceback" not in result.output, result.output
        assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
        if result.exit_code == 0:
            assert result.stderr == "", result.stderr
            assert (out / "summary.json").is_file() and (out / f"trace-{controller}.csv").is_file()
        else:
            assert result.exit_code == 2, (result.exit_code, result.output)
            assert result.stderr.count("\n") == 1 and result.stderr.startswith("error: "), result.stderr
            assert result.stdout == "" and not out.exists()
    return result.exit_code


@settings(
    max_examples=int(os.environ.get("TRUCKMPC_PROPERTY_EXAMPLES", "60")),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(cli_case())
def test_simulate_succeeds_completely_or_fails_with_one_error_line(case):
    event(f"exit {check_case(case)}")


@pytest.mark.slow
@settings(max_examples=10_000, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cli_case())
def test_simulate_succeeds_completely_or_fails_with_one_error_line_10000_examples(case):
    event(f"exit {check_case(case)}")


@pytest.fixture(autouse=True)
def _only_when_slow_is_selected(request):
    """The 10 000-example run only under ``-m slow`` (about ten minutes)."""
    if "10000" in request.node.name and "slow" not in (request.config.getoption("markexpr") or ""):
        pytest.skip("10 000 examples: select with -m slow")
