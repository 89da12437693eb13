"""The layers of ARCHITECTURE.md, enforced: ``lint-imports`` checks the contracts of ``[tool.importlinter]``
in pyproject.toml (no import cycles between siblings, the layers, plotting never computes, matplotlib only
where it draws), and a strongly-connected-components search on grimp's graph of every module finds no
import cycle at all (a package and its own modules included).

grimp (import-linter's graph) reads every import statement, function-local and ``TYPE_CHECKING`` ones
included, so a cycle hidden inside a function counts as a module-level one does; nothing is exempt.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LINT = shutil.which("lint-imports")

pytestmark = pytest.mark.skipif(LINT is None, reason="import-linter is not installed (pip install -e .[test])")


def _lint(cwd: Path) -> subprocess.CompletedProcess[str]:
    # --no-cache: the cache is keyed by file times, and the copy below has fresh ones anyway
    return subprocess.run([str(LINT), "--no-cache"], cwd=cwd, capture_output=True, text=True, timeout=300)


def test_every_contract_is_kept() -> None:
    r = _lint(ROOT)
    assert r.returncode == 0, r.stdout[-6000:] + r.stderr[-2000:]
    assert "0 broken" in r.stdout
    assert "no import cycles" in r.stdout  # the contract that gives "0 cycles" ran


@pytest.mark.parametrize(("module", "line", "contract"), [
    # the cycle world <-> cspace that world's robot parser used to make (function-local)
    ("geometry/world.py", "    from .cspace import check_robot_polygon  # noqa\n", "no import cycles"),
    # an upward import without a cycle: the distance layer reaching up into the fields
    ("distance/incremental.py", "    from ..fields.navigation import wavefront  # noqa\n", "layers"),
    # a figure computing its own distance map
    ("plot/_layers.py", "    from ..distance.brushfire import brushfire  # noqa\n", "plotting never computes"),
])
def test_a_broken_contract_fails(tmp_path: Path, module: str, line: str, contract: str) -> None:
    """The check can fail: the same sources with one bad import, function-local, in a copy."""
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    shutil.copytree(ROOT / "gridfield", tmp_path / "gridfield", ignore=shutil.ignore_patterns("*.so", "*.c", "__pycache__"))
    target = tmp_path / "gridfield" / module
    target.write_text(target.read_text() + "\n\ndef _injected() -> None:\n" + line)
    r = _lint(tmp_path)
    assert r.returncode == 1, r.stdout[-3000:]
    broken = [s for s in r.stdout.splitlines() if " BROKEN" in s]
    assert any(contract in s for s in broken), r.stdout[-3000:]


def test_contract_names_every_module_of_the_package() -> None:
    """``exhaustive = true``: a module left out of the layers is reported (here: checked independently)."""
    import tomllib

    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
    (layers,) = [c for c in cfg["contracts"] if c["type"] == "layers"]
    listed = {name.strip() for layer in layers["layers"] for name in layer.replace(":", "|").split("|")}
    package = ROOT / "gridfield"
    modules = {p.stem for p in package.glob("*.py") if p.stem != "__init__"}
    modules |= {p.parent.name for p in package.glob("*/__init__.py")}
    assert modules == listed, (sorted(modules - listed), sorted(listed - modules))


def _private_imports():
    import sys

    sys.path.insert(0, str(ROOT / "tools"))
    try:
        import private_imports
    finally:
        sys.path.pop(0)
    return private_imports


def test_no_private_name_is_imported_from_outside_its_owner() -> None:
    """Private names and modules stay with their owner (kernels exempt): ``tools/private_imports.py``."""
    found = _private_imports().violations((ROOT / "gridfield").rglob("*.py"), ROOT)
    assert found == [], "\n".join(f"{a}: imports {n} from {m}" for a, m, n in found)


@pytest.mark.parametrize(("module", "line", "expected"), [
    ("following/follower.py", "    from ..fields.sampling import _lazy_force  # noqa\n", ("gridfield.following.follower", "gridfield.fields.sampling", "_lazy_force")),
    ("fields/navfn.py", "    from .navigation import _field  # noqa\n", ("gridfield.fields.navfn", "gridfield.fields.navigation", "_field")),
    ("cli/plan.py", "    from ..io._common import check  # noqa\n", ("gridfield.cli.plan", "gridfield.io._common", "(module)")),
])
def test_a_private_import_is_reported(tmp_path: Path, module: str, line: str, expected: tuple[str, str, str]) -> None:
    """The check can fail: one offending function-local import in a copy of the package is found,
    while the same package uses its own private modules freely (io's readers share io._common)."""
    shutil.copytree(ROOT / "gridfield", tmp_path / "gridfield", ignore=shutil.ignore_patterns("*.so", "*.c", "__pycache__"))
    target = tmp_path / "gridfield" / module
    target.write_text(target.read_text() + "\n\ndef _injected() -> None:\n" + line)
    found = _private_imports().violations((tmp_path / "gridfield").rglob("*.py"), tmp_path)
    assert found == [expected]


def _cycles(package: Path) -> subprocess.CompletedProcess[str]:
    """``tools/import_cycles.py`` on the package at ``package``, in its own process (grimp finds the package
    by import: a copy must not meet the gridfield this process has imported)."""
    import os
    import sys

    env = {**os.environ, "PYTHONPATH": str(package.parent)}
    return subprocess.run([sys.executable, str(ROOT / "tools" / "import_cycles.py"), str(package)], cwd=package.parent,
                          capture_output=True, text=True, timeout=300, env=env)


def test_no_import_cycle_among_all_modules() -> None:
    """0 cycles among gridfield's modules, counting every import (function-level, TYPE_CHECKING, a package's
    ``__init__`` and its own modules)."""
    r = _cycles(ROOT / "gridfield")
    assert r.returncode == 0 and "0 import cycle(s)" in r.stdout, r.stdout + r.stderr


def test_a_cycle_through_a_package_init_is_found(tmp_path: Path) -> None:
    """The search can fail: a module importing its own package's ``__init__``, which imports it back."""
    shutil.copytree(ROOT / "gridfield", tmp_path / "gridfield", ignore=shutil.ignore_patterns("*.so", "*.c", "__pycache__"))
    target = tmp_path / "gridfield" / "io" / "_npz.py"
    target.write_text(target.read_text() + "\n\ndef _injected() -> None:\n    from . import read  # noqa\n")
    r = _cycles(tmp_path / "gridfield")
    assert r.returncode == 1, r.stdout + r.stderr
    assert any("gridfield.io <-> " in line and "gridfield.io._npz" in line for line in r.stdout.splitlines()), r.stdout


def test_no_module_is_loaded_by_name() -> None:
    """No ``importlib.import_module`` or ``__import__`` in gridfield: every import is a statement tools can see."""
    offenders = [f"{p.relative_to(ROOT)}:{i}" for p in (ROOT / "gridfield").rglob("*.py")
                 for i, line in enumerate(p.read_text().splitlines(), 1)
                 if "import_module(" in line or "__import__(" in line]
    assert offenders == []
