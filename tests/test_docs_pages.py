"""The documentation's generated pages and front page, checked without a full build (test_docs_build
builds the site): constants show their values, the planners page opens with ``plan()``, the CLI
reference comes from the parsers, and the front page's five-line example prints what it shows."""

from __future__ import annotations

import ast
import contextlib
import io
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "docs"))

import _api  # noqa: E402


def test_constants_show_their_values_not_their_types_docstring() -> None:
    for name in _api.MODULES:
        page = _api._page(name)
        assert ".. autodata::" not in page, name  # autodata of a tuple shows tuple's docstring
        assert "Alias for field number" not in page
    descent = _api._page("following.descent")
    assert ".. py:data:: STEP_RULES\n   :value: (" in descent


def test_planners_page_opens_with_plan() -> None:
    page = _api._page("planners")
    entries = re.findall(r"^\.\. (?:autofunction|autoclass|py:data):: (\w+)", page, re.M)
    assert entries[0] == "plan"
    assert ".. autoclass:: Planner\n   :no-members:" in page  # a named tuple: its docstring, not field aliases


def test_cli_page_is_generated_from_the_parsers() -> None:
    from gridfield.cli import COMMANDS

    text = _api.cli_page()
    for name in COMMANDS:
        assert f"\ngridfield {name}\n" in text and f"usage: gridfield {name}" in text
    for flag in ("--planner", "--scenario", "--escape", "--robot-radius", "--q-star"):
        assert flag in text


def test_theme_is_readable_and_in_the_docs_extra() -> None:
    conf = ast.parse((ROOT / "docs" / "conf.py").read_text())
    theme = next(n.value.value for n in ast.walk(conf) if isinstance(n, ast.Assign)
                 and getattr(n.targets[0], "id", "") == "html_theme")
    assert theme in ("furo", "pydata_sphinx_theme")


def test_front_page_has_install_example_figure_and_prints_what_it_shows() -> None:
    index = (ROOT / "docs" / "index.rst").read_text()
    assert "pip install" in index and ".. image:: figures/" in index
    code = re.search(r"\.\. code-block:: python\n\n((?:    .*\n)+)", index).group(1)
    lines = [ln[4:] for ln in code.splitlines()]
    assert len(lines) <= 5
    shown = re.search(r"prints::\n\n((?:    .*\n)+)", index).group(1)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec("\n".join(lines), {})
    assert out.getvalue().splitlines() == [ln[4:] for ln in shown.splitlines()]


def test_user_guide_covers_robot_shape_and_hints() -> None:
    toc = (ROOT / "docs" / "guide" / "index.rst").read_text()
    assert "   robot" in toc and "   hints" in toc
    assert "Path.hint" in (ROOT / "docs" / "guide" / "hints.rst").read_text()
