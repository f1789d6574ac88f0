"""``truckmpc config``: the parameters' key tables (:func:`truckmpc.config.key_table`) and the
packaged default files (:func:`truckmpc.config.write_packaged_defaults`)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from truckmpc.config import SECTION_NAMES, key_table, rewrite_key_tables, write_packaged_defaults
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
) -> None:
    """Print the Markdown table of every key (unit, default, allowed values, meaning), per section."""
    if section is not None and section not in SECTION_NAMES:
        raise typer.BadParameter(
            f"expected one of {', '.join(SECTION_NAMES)}, got {section!r}", param_hint="'--section'"
        )
    if write is not None:
        rewritten = rewrite_key_tables(write)
        typer.echo(f"rewrote {len(rewritten)} key tables in {write}: {', '.join(rewritten)}")
        return
    for name in SECTION_NAMES if section is None else (section,):
        typer.echo(f"<!-- keys:{name} -->\n{key_table(name)}\n<!-- /keys:{name} -->")


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
