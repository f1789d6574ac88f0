"""The model of a run's table, shared by the text the CLI prints and the HTML report:
:class:`RunTable` of :class:`Section` of :class:`Row` (:mod:`truckmpc.results.run_table` builds it)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Row", "RunTable", "Section"]


@dataclass(frozen=True)
class Row:
    """One line of the table: ``label [unit]``, then one formatted cell per column ("" where the
    row does not apply to that controller)."""

    label: str
    unit: str
    cells: tuple[str, ...]


@dataclass(frozen=True)
class Section:
    """Rows under a title ("" for the headline section)."""

    title: str
    rows: tuple[Row, ...]


@dataclass(frozen=True)
class RunTable:
    """A run's table: the heading line (road, truck, set speed and band), the controllers as
    columns, the sections, and the notes printed under it (the legend, stops, why a Δ is not
    comparable, run messages, convergence lines)."""

    heading: str
    columns: tuple[str, ...]
    sections: tuple[Section, ...]
    notes: tuple[str, ...]
