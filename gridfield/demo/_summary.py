"""The demo's summary: ``summary.csv`` and ``summary.md``, the Markdown table (:func:`format_table`,
which the command line prints too) and the wrapped list items and paragraphs under it (:func:`wrap_item`).

Part of :mod:`gridfield.demo` (which re-exports every public name here); private to it.
"""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

from ._run import DemoResult

#: Columns of ``summary.csv`` (and of the rows :func:`run_demo` returns).
SUMMARY_COLUMNS = ("part", "map", "planner", "model", "status", "length", "steps", "ms", "note")


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return "" if math.isnan(v) else f"{v:g}"
    return str(v)


#: The summary's columns of free text (the notes and hints): listed under the table, which holds each
#: item's number in their place.
LISTED_COLUMNS = ("note",)
#: The longest cell the summary table holds; longer text is listed under the table too.
MAX_CELL = 60
#: The width the list under the table (and the other text of ``summary.md``) is wrapped at.
TEXT_WIDTH = 100

# A word that would open a Markdown block (a list item, a heading, a quote) at the start of a wrapped line.
_BLOCK_START = re.compile(r"(?:[-+*]|#{1,6}|\d{1,9}[.)]|>.*)")


def wrap_item(text: str, marker: str = "", width: int = TEXT_WIDTH) -> str:
    """``marker + text`` wrapped at ``width`` characters, the lines after the first indented under the
    text: a Markdown list item (or paragraph, without a marker) that reads the same in a terminal.

    A word that would open a Markdown block at the start of a line (``-``, ``1.``, ``#``, ``>``) stays at
    the end of the line before; a word longer than the width (a path) has a line of its own.

    Parameters
    ----------
    text : str
        The text (its runs of white space become single spaces).
    marker : str
        What the first line starts with (``"- "``, ``"3. "``); the other lines are indented as wide.
    width : int
        The longest line, but for a word that does not fit on a line of its own.

    Returns
    -------
    str
        The lines, joined by newlines.

    Examples
    --------
    >>> print(wrap_item("the potential's minimum - here - is off the goal", "1. ", width=24))
    1. the potential's
       minimum - here - is
       off the goal
    """
    indent = " " * len(marker)
    lines = [marker]
    for word in text.split():
        line = lines[-1]
        if len(line) > len(indent) and len(line) + 1 + len(word) > width and not _BLOCK_START.fullmatch(word):
            lines.append(indent + word)
        else:
            lines[-1] = f"{line} {word}" if len(line) > len(indent) else line + word
    return "\n".join(lines)


def format_table(rows: Sequence[Mapping[str, Any]], columns: Sequence[str] = SUMMARY_COLUMNS, *,
                 listed: Sequence[str] = LISTED_COLUMNS, max_cell: int = MAX_CELL) -> str:
    """Rows as a Markdown table (also readable as plain text), and the text too long for it in a
    numbered list below.

    The cells of the ``listed`` columns (the notes and hints) and any cell longer than ``max_cell``
    characters are listed under the table, each as ``N. map, planner: text`` (wrapped at
    :data:`TEXT_WIDTH` characters); the table holds ``see N`` in their place, so that no column is
    padded to the longest hint. ``|`` in a cell is escaped.

    Parameters
    ----------
    rows : sequence of mapping
        The summary rows (missing keys are empty cells).
    columns : sequence of str
        The columns, in order.
    listed : sequence of str
        Columns whose text always goes to the list.
    max_cell : int
        The longest text a cell of the other columns holds.

    Returns
    -------
    str
        The table, then (when there is one) a blank line and the list.

    Examples
    --------
    >>> print(format_table([{"planner": "potential", "ms": 1.5}], ("planner", "ms")))
    | planner   | ms  |
    |-----------|-----|
    | potential | 1.5 |
    >>> print(format_table([{"map": "arena", "planner": "potential", "note": "stalls at (45.69, 3.65)"}],
    ...                    ("map", "planner", "note")))
    | map   | planner   | note  |
    |-------|-----------|-------|
    | arena | potential | see 1 |
    <BLANKLINE>
    1. arena, potential: stalls at (45.69, 3.65)
    """
    cells = [[_fmt(r.get(c, "")) for c in columns] for r in rows]
    items: list[str] = []
    for r, row in zip(rows, cells, strict=True):
        for i, c in enumerate(columns):
            if row[i] and (c in listed or len(row[i]) > max_cell):
                who = ", ".join(_fmt(r[k]) for k in ("map", "planner") if r.get(k, "") != "")
                items.append(f"{who}: {row[i]}" if who else row[i])
                row[i] = f"see {len(items)}"
            row[i] = row[i].replace("|", "\\|")
    widths = [max([len(c)] + [len(row[i]) for row in cells]) for i, c in enumerate(columns)]
    line = "| " + " | ".join(c.ljust(w) for c, w in zip(columns, widths, strict=True)) + " |"
    rule = "|" + "|".join("-" * (w + 2) for w in widths) + "|"
    body = ["| " + " | ".join(v.ljust(w) for v, w in zip(row, widths, strict=True)) + " |" for row in cells]
    listing = [wrap_item(text, f"{n}. ") for n, text in enumerate(items, 1)]
    return "\n".join([line, rule, *body, *(["", *listing] if listing else [])])


def _write_summary(result: DemoResult) -> None:
    out = result.out_dir
    csv_path, md_path = out / "summary.csv", out / "summary.md"
    with csv_path.open("w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(SUMMARY_COLUMNS))
        writer.writeheader()
        for r in result.rows:
            writer.writerow({k: _fmt(r.get(k, "")) for k in SUMMARY_COLUMNS})
    lines = ["# gridfield demo", "", format_table(result.rows), "",
             wrap_item("`length` in map units, `steps`: follower iterations or expanded path cells, "
                       "`ms`: wall time of the planner call (rasterization and field building included); "
                       "`see N`: the row's note, numbered under the table."), ""]
    if result.notes:
        lines += ["## Notes", "", *[wrap_item(s, "- ") for s in result.notes], ""]
    if result.skipped:
        lines += ["## Skipped", "", *[wrap_item(s, "- ") for s in result.skipped], ""]
    lines += ["## Files", ""]
    for f in result.files:
        lines.append(f"![{f.stem}]({f.name})" if f.suffix in (".png", ".gif") else f"- {f.name}")
        lines.append("")
    md_path.write_text("\n".join(lines), encoding="utf-8")
    result.files += [md_path, csv_path]
