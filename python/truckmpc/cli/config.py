"""``truckmpc config``: the parameters' key tables (:func:`truckmpc.config.key_table`) and the
packaged default files (:func:`truckmpc.config.write_packaged_defaults`)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table
from rich.text import Text

from truckmpc.config import (
    KEY_COLUMNS,
    SECTION_NAMES,
    key_rows,
    key_table,
    rewrite_key_tables,
    write_packaged_defaults,
)
from truckmpc.config.docs import SECTION_TITLES
from truckmpc.config.keys import CONFIG_DIR, SECTION_FILES, VEHICLE_FILES

__all__ = ["config_app"]

config_app = typer.Typer(
    help="The parameters: key tables and the packaged default files.",
    short_help="List the parameters; write the default files.",
    no_args_is_help=True,
    rich_markup_mode=None,
)

_DEFAULT_FILES = ", ".join([*VEHICLE_FILES, *SECTION_FILES.values()])
"""The packaged default files ``config defaults`` writes."""


@config_app.command("keys", short_help="Print the table of every parameter key.")
def config_keys_cmd(
    section: Annotated[
        str | None,
        typer.Option("--section", metavar="SECTION", help=f"One of {', '.join(SECTION_NAMES)} (default: all)."),
    ] = None,
    write: Annotated[
        Path | None,
        typer.Option(
            "--write", metavar="FILE", help="Rewrite the tables between <!-- keys:SECTION --> markers in FILE."
        ),
    ] = None,
    markdown: Annotated[
        bool, typer.Option("--markdown", help="Print Markdown tables between <!-- keys:SECTION --> markers.")
    ] = False,
) -> None:
    """Print a table of every key (unit, default, allowed values, meaning), per section."""
    if section is not None and section not in SECTION_NAMES:
        raise typer.BadParameter(
            f"expected one of {', '.join(SECTION_NAMES)}, got {section!r}", param_hint="'--section'"
        )
    if write is not None:
        rewritten = rewrite_key_tables(write)
        typer.echo(f"rewrote {len(rewritten)} key tables in {write}: {', '.join(rewritten)}")
        return
    sections = SECTION_NAMES if section is None else (section,)
    if markdown:
        for name in sections:
            typer.echo(f"<!-- keys:{name} -->\n{key_table(name)}\n<!-- /keys:{name} -->")
        return
    console = Console(highlight=False)
    for name in sections:
        console.print(_terminal_table(name))


_RATIOS = {"allowed": 1, "meaning": 2}
"""How the columns that wrap share the width the others leave."""


def _terminal_table(section: str) -> Table:
    """One section's keys as a table for the terminal, wrapped to its width (key names never)."""
    title = SECTION_TITLES[section].replace("\n# ", " ")  # the YAML files' comment lines, joined
    table = Table(title=f"{section}: {title}", title_justify="left", show_lines=True, expand=True)
    for column in KEY_COLUMNS:
        table.add_column(column, no_wrap=column == "key", ratio=_RATIOS.get(column))
    for row in key_rows(section):
        table.add_row(*(Text(cell) for cell in row))  # Text: a unit like [km/h] is not rich markup
    return table


@config_app.command(
    "defaults",
    help=f"Write the default YAML files ({_DEFAULT_FILES}) from the parameter declarations.",
    short_help="Write the packaged default YAML files.",
)
def config_defaults_cmd(
    directory: Annotated[
        Path | None, typer.Option("--dir", metavar="DIR", help="Directory to write (default: the packaged configs).")
    ] = None,
) -> None:
    """Write the default YAML files from the parameter declarations."""
    target = CONFIG_DIR if directory is None else directory
    target.mkdir(parents=True, exist_ok=True)
    written = write_packaged_defaults(target)
    typer.echo(f"wrote {len(written)} files to {target}")
