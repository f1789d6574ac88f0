"""The help of every command, read as a user reads it (``truckmpc ... --help`` at 80 columns): whole
summaries, every option explained with its choices, its unit and its default."""

from __future__ import annotations

import enum
import functools
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import typer.main
from typer.testing import CliRunner

import truckmpc
from truckmpc.cli import app
from truckmpc.cli.robustness import STUDIED
from truckmpc.cli.simulate import GROUPS
from truckmpc.pareto.plan import CURVE_CONTROLLERS
from truckmpc.roads.sections import SECTION_KINDS
from truckmpc.sim import CONTROLLERS
from truckmpc.sweep.columns import LOOK_AHEAD

runner = CliRunner()
ROOT = typer.main.get_command(app)
PRESETS = sorted(p.stem for p in (Path(truckmpc.__file__).parent / "configs" / "presets").glob("*.yaml"))


# Typer builds click objects (its own copy of click from 0.20 on): they are read by their attributes.


def is_group(command: Any) -> bool:
    return hasattr(command, "commands")


def is_option(param: Any) -> bool:
    return param.param_type_name == "option" and param.name != "help"


def commands(group: Any = ROOT, path: tuple[str, ...] = ()) -> Iterator[tuple[tuple[str, ...], Any]]:
    """(path, command) of every command and group under `group`, `group` first."""
    yield path, group
    if is_group(group):
        for name, command in group.commands.items():
            yield from commands(command, (*path, name))


LEAVES = [(path, command) for path, command in commands() if not is_group(command)]
GROUPS_WITH_COMMANDS = [(path, command) for path, command in commands() if is_group(command)]


@functools.cache
def help_text(path: tuple[str, ...]) -> str:
    result = runner.invoke(app, [*path, "--help"], env={"COLUMNS": "80"})
    assert result.exit_code == 0, result.output
    return result.stdout


def section(text: str, title: str) -> list[str]:
    """The lines of a help section (``Options:``, ``Commands:``, ``Arguments:``), up to the next one."""
    lines = text.splitlines()
    if f"{title}:" not in lines:
        return []
    start = lines.index(f"{title}:") + 1
    end = next((i for i in range(start, len(lines)) if lines[i] and not lines[i].startswith(" ")), len(lines))
    return lines[start:end]


def entries(lines: list[str]) -> list[str]:
    """Each entry of a section (an option, a command) as one line, whitespace collapsed."""
    out: list[str] = []
    for line in lines:
        if re.match(r"^  \S", line):
            out.append(line.strip())
        elif line.strip() and out:
            out[-1] += " " + line.strip()
    return [re.sub(r"\s+", " ", entry) for entry in out]


def option_entry(text: str, name: str) -> str:
    """The help entry of option `name` (``--controller``) in a command's help."""
    found = [e for e in entries(section(text, "Options")) if re.match(rf"^(-[\w-]+, )*{re.escape(name)}[ ,]", e)]
    assert len(found) == 1, (name, found)
    return found[0]


@pytest.mark.parametrize("path", [path for path, _ in GROUPS_WITH_COMMANDS], ids=" ".join)
def test_every_command_summary_is_whole_and_fits(path):
    """The command lists show each command's whole summary (a sentence, not cut with "...") on one
    line of 80 columns; every command is listed."""
    text = help_text(path)
    listed = section(text, "Commands")
    group = next(c for p, c in GROUPS_WITH_COMMANDS if p == path)
    assert [line.split()[0] for line in listed] == list(group.commands)
    for line in listed:
        assert re.fullmatch(r"  \S+ +\S.*\.", line) and not line.endswith("..."), line
        assert len(line) <= 80, line
    assert not [line for line in text.splitlines()[1:] if line.rstrip().endswith("...")]  # but the usage line


@pytest.mark.parametrize("path", [path for path, _ in LEAVES], ids=" ".join)
def test_every_option_says_what_it_is(path):
    """Every option has a help text and a metavar that says what to give (no bare <str> or <path>)."""
    text = help_text(path)
    command = next(c for p, c in LEAVES if p == path)
    assert (command.help or "").strip() and (command.short_help or "").strip()
    for param in command.params:
        if not is_option(param):
            continue
        assert (param.help or "").strip(), (path, param.opts)
        entry = option_entry(text, param.opts[-1])
        assert not re.search(r"<(str|path|list\[str\]|int range)>", entry), entry


def choice_cases() -> list[tuple[tuple[str, ...], str, list[str]]]:
    """(command, option, the choices its help must name)."""
    cases = [
        (("simulate",), "--controller", [*CONTROLLERS, *GROUPS]),
        (("sweep",), "--controller", list(LOOK_AHEAD)),
        (("pareto",), "--curves", list(CURVE_CONTROLLERS)),
        (("robustness",), "--controller", list(STUDIED)),
    ]
    for path, command in LEAVES:
        if any("--config" in p.opts for p in command.params):
            cases.append((path, "--config", PRESETS))
    return cases


@pytest.mark.parametrize(
    ("path", "option", "choices"), choice_cases(), ids=lambda v: " ".join(v) if isinstance(v, tuple) else v
)
def test_choice_options_list_their_choices(path, option, choices):
    entry = option_entry(help_text(path), option)
    for choice in choices:
        assert re.search(rf"(?<![\w-]){re.escape(choice)}(?![\w-])", entry), (choice, entry)


def test_the_presets_are_the_packaged_files_and_named_by_config():
    assert PRESETS == ["fuel_time", "thesis"]  # the files of configs/presets/
    assert "fuel_time, thesis" in option_entry(help_text(("simulate",)), "--config")


def test_the_pcc_is_among_simulates_controllers():
    entry = option_entry(help_text(("simulate",)), "--controller")
    assert "pi, vecto_cc, pcc, mpc, optimal" in entry and "both = pi,mpc" in entry and "(default: both)" in entry


def test_config_keys_names_every_section_it_prints():
    printed = re.findall(r"<!-- keys:(\w+) -->", runner.invoke(app, ["config", "keys", "--markdown"]).stdout)
    entry = option_entry(help_text(("config", "keys")), "--section")
    assert printed and all(re.search(rf"\b{name}\b", entry) for name in printed), (printed, entry)


@pytest.mark.parametrize("path", [path for path, _ in LEAVES], ids=" ".join)
def test_every_choice_parameter_lists_its_choices(path):
    """Options and arguments of a fixed set of values (a click Choice) show all of them."""
    text = help_text(path)
    command = next(c for p, c in LEAVES if p == path)
    for param in command.params:
        kind = getattr(param, "type_descriptor", None)
        annotation = getattr(kind, "annotation", None)
        if isinstance(annotation, type) and issubclass(annotation, enum.Enum):
            for choice in annotation:
                assert str(choice.value) in text, (path, param.name, choice)


def test_road_make_lists_the_section_kinds_and_their_default_lengths():
    text = help_text(("road", "make"))
    assert "<" + "|".join(SECTION_KINDS) + ">" in text
    lead = option_entry(text, "--lead-m")
    for kind, (lead_m, _) in SECTION_KINDS.items():
        assert re.search(rf"{lead_m:g} m for [\w, ]*\b{kind}\b", lead), (kind, lead)


UNITS = {"-m": "[m]", "-kmh": "[km/h]", "-pct": "[%]", "-s": "[s]"}


@pytest.mark.parametrize("path", [path for path, _ in LEAVES], ids=" ".join)
def test_every_quantity_has_its_unit(path):
    """An option named for a quantity (``--length-m``, ``--speed-kmh``, ``--slope-pct``) gives its unit."""
    text = help_text(path)
    command = next(c for p, c in LEAVES if p == path)
    for param in command.params:
        if not is_option(param):
            continue
        name = param.opts[-1]
        for suffix, unit in UNITS.items():
            if name.endswith(suffix):
                assert unit in option_entry(text, name), (path, name)


def test_quantities_without_a_unit_in_the_name_give_theirs():
    text = help_text(("pareto",))
    assert "[km/h]" in option_entry(text, "--speeds") and "[g/s]" in option_entry(text, "--betas")


NO_DEFAULT = {
    "--slope-pct",
    "--replay",
    "--controller-road",
    "--scheduler",
    "--write",
    "--run",
    "--out",
    "--grid",
    "--config",
    "--set",
}
"""Options that do nothing when not given (an extra output, another mode), are lists to add to, or
that some choices need and others refuse (``road make --slope-pct``)."""


@pytest.mark.parametrize("path", [path for path, _ in LEAVES], ids=" ".join)
def test_every_option_with_a_default_shows_it(path):
    """A valued option shows its default: typer's ``[default: ...]`` or, where it depends on the
    other inputs, ``(default: ...)`` in the text; flags are off unless given."""
    text = help_text(path)
    command = next(c for p, c in LEAVES if p == path)
    for param in command.params:
        if not is_option(param) or param.is_flag or param.required:
            continue
        name = param.opts[-1]
        if param.default is None and name in NO_DEFAULT:
            continue
        entry = option_entry(text, name)
        assert "[default: " in entry or "(default" in entry, (path, name, entry)
