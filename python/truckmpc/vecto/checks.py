"""Checks of an engine's and a transmission's tables that every VECTO file format shares: the
rows come with where each was read (``file:line``, and the element for XML) so that a refusal
names it."""

from __future__ import annotations

from collections.abc import Sequence

from truckmpc.errors import VehicleError

__all__ = ["Located", "check_full_load", "check_once"]

Located = tuple[str, int, tuple[float, float, float]]
"""A row of three numbers with where it was read (``file:line``, or more) and its line."""


def check_full_load(rows: Sequence[Located]) -> None:
    """(engine speed [rpm], full-load torque [Nm], drag torque [Nm]) rows: speeds increase, the drag
    torque is at most zero and at most the full-load torque."""
    for (where, _, (n, _, _)), (_, _, (n_prev, _, _)) in zip(rows[1:], rows[:-1], strict=True):
        if n <= n_prev:
            raise VehicleError(f"{where}: expected engine speeds that increase, got {n:g} after {n_prev:g}")
    for where, _, (_, full, drag) in rows:
        if drag > 0:
            raise VehicleError(f"{where}: expected a drag (motoring) torque <= 0, got {drag:g}")
        if drag > full:
            raise VehicleError(f"{where}: expected a drag torque <= the full-load torque, got {drag:g} > {full:g}")


def check_once(rows: Sequence[Located], what: str) -> None:
    """Each (first, second number) pair of a map once; ``what`` names the pair."""
    seen: dict[tuple[float, float], int] = {}
    for where, line, (a, b, _) in rows:
        if (a, b) in seen:
            raise VehicleError(f"{where}: expected each {what} once, got {a:g}, {b:g} again (line {seen[(a, b)]})")
        seen[(a, b)] = line
