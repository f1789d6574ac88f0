"""The documentation site's generated reference pages (the MkDocs hooks of docs/hooks/): the command
line page lists every command and option that `--help` shows, in the words of `--help`; the
parameter page carries every declared key with its unit, default and range; both refuse a page
that lacks the place their text goes; the Python API page shows Sphinx roles as code. The site
itself is built with `mkdocs build --strict` in .ci/run."""

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
from typer.testing import CliRunner

from truckmpc.cli import app
from truckmpc.config import SECTION_NAMES, SPECS

DOCS = Path(__file__).resolve().parents[1] / "docs"


def hook(name: str) -> ModuleType:
    """A hook module of docs/hooks/, loaded as MkDocs loads it (by path)."""
    spec = importlib.util.spec_from_file_location(f"docs_hook_{name}", DOCS / "hooks" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


cli_reference = hook("cli_reference")
parameter_reference = hook("parameter_reference")
api_reference = hook("api_reference")


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


# --- the command line -----------------------------------------------------------------------


def help_of(path: list[str]) -> dict[str, Any]:
    """What `truckmpc PATH --help` shows, parsed from its text: the description, the sub-commands,
    and the names of the arguments and options (`--help` itself left out)."""
    result = CliRunner().invoke(app, [*path, "--help"], prog_name="truckmpc")
    assert result.exit_code == 0, result.output
    sections: dict[str, list[str]] = {}
    head, *rest = re.split(r"^(\w+):\n", result.output.split("\n", 1)[1], flags=re.M)
    for title, body in zip(rest[::2], rest[1::2], strict=True):
        # entries start two spaces in; their wrapped help is indented further
        sections[title] = [re.split(r" {2,}", line.strip())[0] for line in body.splitlines() if re.match(r"  \S", line)]
    entries = [e for e in sections.get("Arguments", []) + sections.get("Options", []) if e != "--help"]
    return {
        "description": " ".join(head.split()),
        "commands": sections.get("Commands", []),
        "entries": entries,
        "params": [name.split()[0] for entry in entries for name in entry.split(", ")],
    }


def every_command(path: list[str] | None = None) -> list[list[str]]:
    """Every command path of the app, found by following `--help` from the top."""
    path = path or []
    found = [path] if path else []
    for name in help_of(path)["commands"]:
        found += every_command([*path, name.split()[0]])
    return found


def command_sections(page: str) -> dict[str, str]:
    """The generated page cut at its command headings: command path -> that command's Markdown."""
    parts = re.split(r"^#+ (truckmpc[\w -]*?) \{ #[\w-]+ [^}]*\}$", page, flags=re.M)
    return dict(zip(parts[1::2], parts[2::2], strict=True))


def test_cli_reference_lists_every_command_and_option() -> None:
    page = cli_reference.cli_reference()
    sections = command_sections(page)
    commands = every_command()
    assert sorted(sections) == sorted(" ".join(["truckmpc", *path]) for path in commands)
    assert len(commands) > 20 and ["road", "import", "gpx"] in commands  # sub-sub-commands too
    for path in commands:
        shown = help_of(path)
        section = sections[" ".join(["truckmpc", *path])]
        rows = [line for line in section.splitlines() if line.startswith("| <code>")]
        row_names = [re.match(r"\| <code>(.*?)</code>", row).group(1) for row in rows]  # type: ignore[union-attr]
        for param in shown["params"]:
            assert any(re.search(rf"(^|, ){re.escape(param)}( |,|$)", name) for name in row_names), (path, param)
        assert len(rows) == len(shown["entries"]), path
        # the description reads as --help prints it: nothing lost to Markdown (DIR/trace-<controller>.csv)
        assert shown["description"] in rendered_text(section), path


def test_cli_reference_options_carry_their_choices_and_defaults() -> None:
    text = rendered_text(cli_reference.cli_reference())
    assert "--method <spline|savgol|none>" in text  # a choice, from the option's type
    assert "[default: 8.0; x>=0.0]" in text  # a default and a range, as --help shows them
    assert "kind <flat|hill|crest|depression>" in text  # an argument's choices


def test_cli_reference_index_links_every_command_section() -> None:
    page = cli_reference.cli_reference()
    anchors = re.findall(r"^#+ truckmpc[\w -]*? \{ #([\w-]+) ", page, flags=re.M)
    index = re.findall(r"^\| \[<code>[^<]*</code>\]\(#([\w-]+)\) \|", page, flags=re.M)
    assert index == anchors and len(set(anchors)) == len(anchors)


def test_cli_page_without_its_marker_fails_the_build() -> None:
    with pytest.raises(PluginError, match="<!-- cli-reference -->"):
        cli_reference.on_page_markdown("# Command line\n", Page("reference/cli.md"))
    assert cli_reference.on_page_markdown("# Other\n", Page("index.md")) == "# Other\n"


# --- the Python API -------------------------------------------------------------------------


def test_api_page_shows_sphinx_roles_as_code() -> None:
    html_in = (
        "<p>Read by :func:<code>~truckmpc.roads.vdri.read_vdri</code>, named in :data:<code>CONTROLLERS</code>"
        " and :class:<code>truckmpc.controller.Controller</code>. Public API::</p>"
    )
    assert api_reference.plain_roles(html_in) == (
        "<p>Read by <code>read_vdri</code>, named in <code>CONTROLLERS</code>"
        " and <code>truckmpc.controller.Controller</code>. Public API:</p>"
    )
