"""Reading back the table `truckmpc simulate` prints: its header of controllers, its rows (each
cell found under the column whose name it is right-aligned with) and the lines after the table."""

from __future__ import annotations

import re
from dataclasses import dataclass, field


@dataclass
class PrintedTable:
    """The printed table: the heading line, the columns, each row's label with its cells by column
    ("" where blank) in print order, the section titles, and the lines after the table."""

    heading: str
    columns: list[str]
    rows: list[tuple[str, dict[str, str]]] = field(default_factory=list)
    titles: list[str] = field(default_factory=list)
    after: list[str] = field(default_factory=list)

    def row(self, label: str) -> dict[str, str]:
        """The cells of the row labelled `label` (KeyError when it is not printed)."""
        for name, cells in self.rows:
            if name == label:
                return cells
        raise KeyError(label)

    def labels(self) -> list[str]:
        return [label for label, _ in self.rows]


def parse_table(text: str) -> PrintedTable:
    """`text` (the command's output) read as a table; the header is the first line of only
    controller names, right after the heading `road ...` line."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("road "))
    header = lines[start + 1]
    lead = len(header) - len(header.lstrip())
    ends = {m.end(): m.group() for m in re.finditer(r"\S+", header)}
    table = PrintedTable(lines[start], list(ends.values()))
    for number, line in enumerate(lines[start + 2 :], start=start + 2):
        row = _row(line, lead, ends)
        if row is not None:
            table.rows.append(row)
        elif line.strip() and not lines[number - 1].strip():
            table.titles.append(line)
        elif line.strip():
            table.after = lines[number:]
            break
    return table


def _row(line: str, lead: int, ends: dict[int, str]) -> tuple[str, dict[str, str]] | None:
    """The label and cells (by column) of a row, or None when `line` is not one: a row's label
    ends before the header's first name begins, and each token after it ends where a column's name
    ends (cells are right-aligned under their column)."""
    label_end, cells = 0, dict.fromkeys(ends.values(), "")
    for m in re.finditer(r"\S+", line):
        if m.end() <= lead and not any(cells.values()):
            label_end = m.end()
        elif m.end() in ends:
            cells[ends[m.end()]] = m.group()
        else:
            return None
    if not label_end or not any(cells.values()):
        return None
    return line[:label_end], cells
