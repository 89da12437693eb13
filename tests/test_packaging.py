"""The package layout: every subpackage ships in the wheel, and io does not import later stages."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_every_subpackage_is_listed_in_pyproject() -> None:
    """``[tool.setuptools] packages`` is an explicit list: a subpackage missing from it is missing from the wheel."""
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    on_disk = {".".join(p.parent.relative_to(ROOT).parts) for p in (ROOT / "gridfield").rglob("__init__.py")}
    assert on_disk, "no package found"
    assert on_disk - listed == set(), f"subpackages not listed in pyproject.toml: {sorted(on_disk - listed)}"
    assert "gridfield.maps" in listed  # the bundled maps (gridfield.io.bundled_map)


def test_io_imports_no_later_stage() -> None:
    """Data flows io -> ... -> potential: importing gridfield.io loads neither potential nor brushfire
    (``io.load_field`` imports them when it is called)."""
    code = ("import sys, gridfield.io; "
            "print(','.join(m for m in ('gridfield.fields.potential', 'gridfield.brushfire', 'gridfield.fields.navigation') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT).stdout
    assert out.strip() == ""
