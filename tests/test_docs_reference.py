"""The documentation site's generated reference pages (the MkDocs hooks of docs/hooks/): the command
line page lists every command and option that `--help` shows, in the words of `--help`; the
parameter page carries every declared key with its unit, default and range; both refuse a page
that lacks the place their text goes. The site itself is built with `mkdocs build --strict` in
.ci/run."""

from __future__ import annotations

import html
import importlib.util
import re
from pathlib import Path
from types import ModuleType
from typing import Any

import markdown
import pytest
import yaml
from mkdocs.exceptions import PluginError

from truckmpc.config import SECTION_NAMES, SPECS

DOCS = Path(__file__).resolve().parents[1] / "docs"


def hook(name: str) -> ModuleType:
    """A hook module of docs/hooks/, loaded as MkDocs loads it (by path)."""
    spec = importlib.util.spec_from_file_location(f"docs_hook_{name}", DOCS / "hooks" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


parameter_reference = hook("parameter_reference")


class Page:
    """What a hook is given: the page's source path, as MkDocs names it."""

    def __init__(self, src_uri: str) -> None:
        self.file = type("File", (), {"src_uri": src_uri})()


def rendered_text(md: str) -> str:
    """A page's Markdown rendered as the site renders it, as plain text with single spaces."""
    body = markdown.markdown(md, extensions=["tables", "attr_list", "md_in_html", "fenced_code"])
    return " ".join(html.unescape(re.sub(r"<[^>]+>", " ", body)).split())


# --- the parameters -------------------------------------------------------------------------


def table_rows(block: str) -> list[list[str]]:
    """The body rows of the first Markdown table in `block`, cells split at unescaped `|`."""
    lines = [line for line in block.splitlines() if line.startswith("|")]
    return [[cell.strip().replace("\\|", "|") for cell in re.split(r"(?<!\\)\|", line)[1:-1]] for line in lines[2:]]


def test_parameter_page_carries_every_declared_key_with_unit_default_and_range() -> None:
    source = (DOCS / "reference" / "parameters.md").read_text(encoding="utf-8")
    page = parameter_reference.parameters_page(source)
    blocks = dict(re.findall(r"^<!-- keys:(\w+) -->\n(.*?)(?=^#|^<!-- keys:|\Z)", page, flags=re.M | re.S))
    assert list(blocks) == list(SECTION_NAMES)
    for section, block in blocks.items():
        rows = {row[0].strip("`"): row for row in table_rows(block)}
        declared = [spec for spec in SPECS if spec.section == section]
        assert sorted(rows) == sorted(spec.name for spec in declared), section
        for spec in declared:
            _, unit, default, allowed, meaning = rows[spec.name]
            assert unit == spec.unit and allowed == spec.expected and meaning == spec.doc, spec.name
            assert yaml.safe_load(default.strip("`")) == spec.default, spec.name
        # each section has a heading of its own to link to: parameters.md#mpc
        assert re.search(rf"^## .* \{{ #{section} \}}\n", source, flags=re.M), section
    assert "Q3·|Δv|" in rendered_text(page)  # a `|` inside a cell does not split it


@pytest.mark.parametrize(
    ("change", "named"),
    [
        (lambda text: text.replace("<!-- keys:pcc -->\n", ""), "no marker: pcc"),
        (lambda text: text + "\n<!-- keys:brakes -->\n", "no such section: brakes"),
        (lambda text: text + "\n<!-- keys:sim -->\n", "two markers: sim"),
    ],
)
def test_parameter_page_without_its_place_for_every_section_fails_the_build(change: Any, named: str) -> None:
    source = (DOCS / "reference" / "parameters.md").read_text(encoding="utf-8")
    with pytest.raises(PluginError, match=named):
        parameter_reference.on_page_markdown(change(source), Page("reference/parameters.md"))
