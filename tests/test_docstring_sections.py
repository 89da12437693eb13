"""Every public function and class of the modules in OWNED has numpydoc Parameters, Returns (or
Yields) and Examples sections, checked by the same code as ``python tools/docstring_sections.py``.

The examples themselves run as doctests (``--doctest-modules``); this test checks that they exist.
OWNED is every module of ``docs/_api.py``; a public module missing there fails too.
"""

from __future__ import annotations

import sys
import types
from collections.abc import Iterator
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "docs"))
from _api import MODULES  # docs/_api.py: the API pages
from docstring_sections import missing_sections

#: every public module: all of them are documented
OWNED = list(MODULES)


@pytest.mark.parametrize("module", OWNED)
def test_public_names_have_sections(module: str) -> None:
    total, missing = missing_sections([module])
    assert total > 0, f"gridfield.{module} lists no public function or class in __all__"
    lacking = {section: names for section, names in missing.items() if names}
    assert not lacking, f"gridfield.{module}: public names without a section: {lacking}"


def test_every_public_module_is_checked() -> None:
    import pkgutil

    import gridfield

    public = {m.name for m in pkgutil.iter_modules(gridfield.__path__) if not m.name.startswith("_")}
    assert public - {"cli", "maps"} <= {m.split(".")[0] for m in OWNED}, "a public module has no API page (docs/_api.py MODULES)"


@pytest.fixture
def probe_module() -> Iterator[str]:
    """A throwaway ``gridfield._docprobe`` module: one complete function, one without Returns and
    Examples, one class without Examples, one parameterless function without Parameters."""
    module = types.ModuleType("gridfield._docprobe")

    def complete(x: int) -> int:
        """Double.

        Parameters
        ----------
        x : int

        Returns
        -------
        int

        Examples
        --------
        >>> complete(2)
        4
        """
        return 2 * x

    def bare(x: int) -> int:
        """Double.

        Parameters
        ----------
        x : int
        """
        return 2 * x

    def no_args() -> int:
        """One.

        Returns
        -------
        int

        Examples
        --------
        >>> no_args()
        1
        """
        return 1

    class Thing:
        """A thing.

        Parameters
        ----------
        size : int
        """

        def __init__(self, size: int) -> None:
            self.size = size

    for obj in (complete, bare, no_args, Thing):
        setattr(module, obj.__name__, obj)
    module.__all__ = ["complete", "bare", "no_args", "Thing"]  # type: ignore[attr-defined]
    sys.modules[module.__name__] = module
    try:
        yield "_docprobe"
    finally:
        del sys.modules[module.__name__]


def test_checker_reports_what_is_missing(probe_module: str) -> None:
    total, missing = missing_sections([probe_module])
    assert total == 4
    assert missing == {
        "Parameters": [],
        "Returns": [f"{probe_module}.bare"],
        "Examples": [f"{probe_module}.bare", f"{probe_module}.Thing"],
    }
