"""The `gridfield` command as a whole: start-up imports, --version, python -m."""

from __future__ import annotations

import subprocess
import sys

from gridfield import __version__

HEAVY = ("shapely", "matplotlib", "numba", "scipy", "skimage", "yaml", "PIL")


def test_help_imports_no_heavy_module() -> None:
    """`gridfield --help` builds every sub-command's parser without loading heavy libraries."""
    code = ("import sys, gridfield.cli; gridfield.cli.build_parser(); "
            f"print(','.join(m for m in {HEAVY!r} if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "", f"gridfield --help imports {out}"


def test_python_dash_m_and_version() -> None:
    res = subprocess.run([sys.executable, "-m", "gridfield", "--version"], capture_output=True, text=True)
    assert res.returncode == 0 and res.stdout.strip() == f"gridfield {__version__}"


def test_every_documented_command_is_there() -> None:
    """Each command of README's synopsis is a sub-command, listed with its own help line."""
    import argparse
    import re

    from gridfield.cli import build_parser

    documented = ["demo", "info", "brushfire", "costmap", "field", "plan", "compare", "explore", "sweep"]
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    assert list(sub.choices) == documented
    res = subprocess.run([sys.executable, "-m", "gridfield", "--help"], capture_output=True, text=True, check=True)
    listed = re.findall(r"^    (\w+)\s+\S", res.stdout, flags=re.M)
    assert listed == documented
