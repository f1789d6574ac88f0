"""The command-line reference, generated when the site is built: every command and sub-command of
the ``truckmpc`` Typer app, in the order of ``truckmpc --help``, with its description, usage,
arguments and options in the words of its ``--help`` (choices, defaults, ranges and units
included). The page reference/cli.md holds a hand-written introduction and the line
``<!-- cli-reference -->``, which this MkDocs hook replaces.

A hook rather than mkdocs-click: Typer builds its command tree on its own copy of click, which
mkdocs-click's option tables do not recognise; mkdocs-click pastes help text into the page as
Markdown (``DIR/trace-<controller>.csv`` would lose ``<controller>`` as an HTML tag), sorts commands
by name and cuts each command's summary at the first line break of its docstring. Here the text
is escaped, the order is the app's, and summaries are whole paragraphs.
"""

from __future__ import annotations

import html
import re
from collections.abc import Iterator
from typing import Any

import typer
from mkdocs.exceptions import PluginError

from truckmpc.cli import app

PAGE = "reference/cli.md"
MARKER = "<!-- cli-reference -->"
PROG = "truckmpc"


def contexts(ctx: Any = None) -> Iterator[Any]:
    """The app's commands as click contexts, depth first in the order of ``--help``, the root
    first."""
    if ctx is None:
        root = typer.main.get_command(app)
        ctx = root.context_class(root, info_name=PROG)
    yield ctx
    for child in _children(ctx):
        yield from contexts(child)


def _children(ctx: Any) -> list[Any]:
    """The sub-commands of a command group in the order of its ``--help`` (hidden ones left out)."""
    group = ctx.command
    if not hasattr(group, "list_commands"):
        return []
    subs = [(name, group.get_command(ctx, name)) for name in group.list_commands(ctx)]
    return [sub.context_class(sub, info_name=name, parent=ctx) for name, sub in subs if sub and not sub.hidden]


def cli_reference() -> str:
    """The Markdown of every command: an index of them all, then a section per command (a group's
    sub-commands follow it, a heading level down)."""
    root, *commands = contexts()
    lines = [*_paragraphs(root.command.help), "", *_command_table(commands)]
    for ctx in commands:
        lines += _command_section(ctx)
    return "\n".join(lines)


def on_page_markdown(markdown: str, page: Any, **_: Any) -> str:
    """MkDocs hook: fill the CLI reference page's marker."""
    if page.file.src_uri != PAGE:
        return markdown
    if MARKER not in markdown:
        raise PluginError(f"{PAGE}: expected the line {MARKER} where the command reference goes")
    return markdown.replace(MARKER, cli_reference())


def anchor(ctx: Any) -> str:
    """The heading id of a command: ``truckmpc-road-import-gpx``."""
    return str(ctx.command_path).replace(" ", "-")


def _command_section(ctx: Any) -> list[str]:
    depth = str(ctx.command_path).count(" ")
    command = ctx.command
    lines = [
        f'{"#" * (depth + 1)} {ctx.command_path} {{ #{anchor(ctx)} data-toc-label="{ctx.info_name}" }}',
        "",
        *_paragraphs(command.help),
        "",
        "```text",
        " ".join([ctx.command_path, *command.collect_usage_pieces(ctx)]),
        "```",
        "",
    ]
    params = [p for p in command.get_params(ctx) if not p.hidden and "--help" not in p.opts]
    for kind, title in (("argument", "Arguments"), ("option", "Options")):
        rows = [_param_row(p, ctx) for p in params if p.param_type_name == kind]
        if rows:
            lines += [f"**{title}**", "", *_table([f"| {kind} | meaning |", "|---|---|", *rows])]
    return lines


def _command_table(ctxs: list[Any]) -> list[str]:
    rows = [f"| [{_code(_name(ctx))}](#{anchor(ctx)}) | {_text(_summary(ctx.command.help))} |" for ctx in ctxs]
    return _table(["| command | what it does |", "|---|---|", *rows])


def _table(lines: list[str]) -> list[str]:
    """A Markdown table in the reference pages' style (docs/stylesheets/reference.css)."""
    return ['<div class="reference-table" markdown>', "", *lines, "", "</div>", ""]


def _name(ctx: Any) -> str:
    """A command's path without the program: ``road import gpx``."""
    return str(ctx.command_path).removeprefix(PROG + " ")


def _param_row(param: Any, ctx: Any) -> str:
    record = param.get_help_record(ctx)
    name, meaning = record if record is not None else (param.human_readable_name, "")
    return f"| {_code(name)} | {_text(meaning)} |"


def _code(code: str) -> str:
    """Code in a table cell (a bare ``|`` would end the cell)."""
    return "<code>" + html.escape(code, quote=False).replace("|", "&#124;") + "</code>"


def _summary(help_text: str | None) -> str:
    """A command's first paragraph, whole."""
    return next(iter(_paragraph_texts(help_text)), "")


def _paragraphs(help_text: str | None) -> list[str]:
    return [line for text in _paragraph_texts(help_text) for line in (_text(text), "")]


def _paragraph_texts(help_text: str | None) -> list[str]:
    """The paragraphs of a help text (click's ``\\f`` ends what ``--help`` shows), each on one line."""
    text = (help_text or "").split("\f")[0]
    return [" ".join(p.split()) for p in re.split(r"\n\s*\n", text) if p.strip()]


_MARKDOWN_SIGNS = re.compile(r"([\\`*_\[\]|#])")


def _text(text: str) -> str:
    """Plain text as Markdown that shows it as typed: no HTML tags, emphasis, links or table cells."""
    return _MARKDOWN_SIGNS.sub(r"\\\1", html.escape(text, quote=False))
