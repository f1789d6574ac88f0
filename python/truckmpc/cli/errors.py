"""How the ``truckmpc`` command ends on bad input: one line ``error: ...`` on stderr and exit code 2,
never a traceback; a signal ends it with one line and 128 + the signal's number."""

from __future__ import annotations

import importlib
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

import typer
from typer.core import TyperGroup

from truckmpc.cli.invocation import remember_arguments
from truckmpc.errors import TruckmpcError
from truckmpc.signals import Stopped

__all__ = ["USAGE_EXIT_CODE", "OneLineErrors", "fail"]

USAGE_EXIT_CODE = 2


def _usage_error_types() -> tuple[type[Exception], ...]:
    """Usage-error base classes: Typer >= 0.20 vendors click (``typer.TyperException``); older
    versions raise ``click.ClickException``."""
    types: list[type[Exception]] = []
    if hasattr(typer, "TyperException"):
        types.append(typer.TyperException)
    try:
        click = importlib.import_module("click")  # not a static import: typer >= 0.20 does not install it
    except ImportError:
        pass
    else:
        types.append(click.ClickException)
    return tuple(types)


_USAGE_ERRORS = _usage_error_types()


def fail(message: str, code: int = USAGE_EXIT_CODE) -> NoReturn:
    """End the command with `message` as one line ``error: ...`` on stderr and exit `code`."""
    text = " ".join(str(message).split())
    typer.echo(f"error: {text}", err=True)
    sys.exit(code)


class OneLineErrors(TyperGroup):
    """Root command group that turns every user-facing error into one ``error:`` line and exit code 2.

    Living in the group (not only in :func:`truckmpc.cli.main`) means Typer's ``CliRunner`` sees the
    same behaviour as the installed command.
    """

    def main(
        self,
        args: Sequence[str] | None = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        windows_expand_args: bool = True,
        **extra: Any,
    ) -> Any:
        remember_arguments(args)
        try:
            rv = super().main(
                args=args,
                prog_name=prog_name,
                complete_var=complete_var,
                standalone_mode=False,
                windows_expand_args=windows_expand_args,
                **extra,
            )
        except _USAGE_ERRORS as err:  # usage errors, bad parameter values
            message = err.format_message() if hasattr(err, "format_message") else str(err)
            fail(message or "missing command or arguments (usage above; --help for more)")
        except TruckmpcError as err:
            fail(str(err))
        except OSError as err:  # e.g. an output directory that cannot be written
            where = f"{err.filename}: " if err.filename else ""
            fail(f"{where}{err.strerror or err}")
        except typer.Abort:
            fail("aborted", 1)
        except Stopped as stop:  # SIGINT or SIGTERM: one line, exit 130 or 143
            typer.echo(str(stop), err=True)
            sys.exit(stop.exit_code)
        if not standalone_mode:
            return rv
        sys.exit(rv if isinstance(rv, int) else 0)
