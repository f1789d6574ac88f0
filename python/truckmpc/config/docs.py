"""Text that follows from the declarations: the packaged YAML defaults and the key tables (of the
docs site's parameter reference, made when the site is built). The tests check both against the
declarations; `truckmpc config defaults --dir` and `truckmpc config keys` write and print them."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from truckmpc.config.keys import CONFIG_DIR, SECTION_FILES, SPECS, VEHICLE_FILES, ParamSpec

SECTION_TITLES = {
    "vehicle": "The truck: tables A.1 (vehicle, engine) and A.2 (gearbox) of Hellström's thesis.",
    "cruise": "The set speed and the one speed band every controller works to.",
    "pi": "The PI cruise controller (section 2.5; gains table A.4, gear thresholds table A.3). Its error\n"
    "# signals are in km/h, so each integrator state is in km/h s, clamped to +-limit (the anti-windup).",
    "mpc": "The look-ahead DP-MPC (chapter 5; tables 5.2, 6.1, 6.2). The cost weighs fuel in grams and\n"
    "# speeds in m/s: with these units table 6.2's weights give chapter 6's behaviour. These defaults\n"
    "# converge as delta_kmh and stage_m shrink; --config thesis is the controller as printed.",
    "pcc": "VECTO's driver with its declaration defaults: its cruise driver (--controller vecto_cc), and\n"
    "# its rule-based predictive cruise control (use cases 1-3) with eco-roll on that driver\n"
    "# (--controller pcc). The PCC's allowed underspeed, and its overspeed with use case 3, are the\n"
    "# cruise band's v_dec_kmh and v_inc_kmh.",
    "sim": "How the closed loop is simulated and recorded.",
    "vecto": "A truck from VECTO's files (--vehicle JOB.vecto or JOB.xml): declaration mode's mission, load,\n"
    "# trailer, cross wind and auxiliaries, and the driveline losses where the job gives no loss map.\n"
    "# null: VECTO's value for this truck, or its files'. With the thesis's truck these keep their defaults.",
}


_COMMENT_COLUMN = 32
"""Comments start here, or two spaces after a longer line."""


def yaml_value(value: Any) -> str:
    """A value in YAML that reads back as the same value (floats keep a decimal point)."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        text = repr(value)
        return text if any(c in text for c in ".en") else text + ".0"
    if isinstance(value, list):
        return "[" + ", ".join(yaml_value(item) for item in value) + "]"
    return str(value)


def _specs_of(section: str) -> list[ParamSpec]:
    return [spec for spec in SPECS if spec.section == section]


def defaults_yaml(section: str, changes: dict[str, Any] | None = None) -> str:
    """A complete YAML file of one section's declared defaults (with `changes`), one commented key a line."""
    lines = [
        f"# {SECTION_TITLES[section]}",
        "# Generated from the parameter declarations: truckmpc config defaults.",
        "",
    ]
    rows = [
        (f"{spec.name}: {yaml_value((changes or {}).get(spec.name, spec.default))}", spec)
        for spec in _specs_of(section)
    ]
    width = min(max(len(text) for text, _ in rows), _COMMENT_COLUMN) + 2
    for text, spec in rows:
        unit = "" if spec.unit == "-" else f" [{spec.unit}]"
        lines.append(f"{text}{' ' * max(2, width - len(text))}# {spec.doc.rstrip('.')}{unit}")
    return "\n".join(lines) + "\n"


def packaged_defaults() -> dict[str, str]:
    """The text of every packaged default file, by file name."""
    files = {name: defaults_yaml("vehicle", changes) for name, changes in VEHICLE_FILES.items()}
    files.update({name: defaults_yaml(section) for section, name in SECTION_FILES.items()})
    return files


def write_packaged_defaults(directory: Path = CONFIG_DIR) -> list[Path]:
    """Rewrite the packaged default files in `directory`; returns the paths written."""
    written = []
    for name, text in packaged_defaults().items():
        path = directory / name
        path.write_text(text, encoding="utf-8")
        written.append(path)
    return written


KEY_COLUMNS = ("key", "unit", "default", "allowed", "meaning")
"""The columns of a section's key table."""


def key_rows(section: str) -> list[tuple[str, str, str, str, str]]:
    """One section's keys as rows of :data:`KEY_COLUMNS`: key, unit, default (as YAML writes it),
    the values allowed, meaning."""
    return [(s.name, s.unit, yaml_value(s.default), s.expected, s.doc) for s in _specs_of(section)]


def key_table(section: str) -> str:
    """A Markdown table of one section's keys (:func:`key_rows`)."""
    lines = [f"| {' | '.join(KEY_COLUMNS)} |", "|---|---|---|---|---|"]
    for key, unit, default, allowed, meaning in key_rows(section):
        cells = [f"`{key}`", _cell(unit), f"`{default}`", _cell(allowed), _cell(meaning)]
        lines.append(f"| {' | '.join(cells)} |")
    return "\n".join(lines)


def _cell(text: str) -> str:
    """Text for a Markdown table cell: a bare `|` (as in `|Δv|`) would end the cell."""
    return text.replace("|", "\\|")


def rewrite_key_tables(path: Path) -> list[str]:
    """Replace every `<!-- keys:SECTION -->` ... `<!-- /keys:SECTION -->` block of the Markdown file
    `path` by the section's current table; returns the sections rewritten."""
    text = path.read_text(encoding="utf-8")
    found: list[str] = []

    def table(match: re.Match[str]) -> str:
        found.append(match.group(1))
        return f"<!-- keys:{match.group(1)} -->\n{key_table(match.group(1))}\n<!-- /keys:{match.group(1)} -->"

    path.write_text(_KEY_BLOCK.sub(table, text), encoding="utf-8")
    return found


_KEY_BLOCK = re.compile(r"<!-- keys:(\w+) -->\n.*?\n<!-- /keys:\1 -->", re.S)
