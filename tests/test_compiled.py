"""The kernels are extension modules compiled at install, never Python fallbacks."""

from __future__ import annotations

import ast
import importlib
import importlib.machinery
import pkgutil
import subprocess
import sys
from pathlib import Path

import pytest

import gridfield

PACKAGE = Path(gridfield.__file__).parent
REPO = Path(__file__).resolve().parent.parent


#: Kernel modules still in numba (merged into main after the Cython port; to be ported). Listed
#: here so that a new plain-Python kernel cannot slip in unnoticed.
NOT_YET_PORTED = {"_kernels_anyangle", "_kernels_incremental"}


def _kernel_sources() -> set[str]:
    return {p.stem for p in (REPO / "gridfield").glob("_kernels_*.pyx")}


def test_every_kernel_source_is_built_by_setup_py():
    """setup.py's KERNELS lists exactly the .pyx modules of the tree (adding one is a one-line change)."""
    tree = ast.parse((REPO / "setup.py").read_text())
    listed = next(ast.literal_eval(node.value) for node in ast.walk(tree)
                  if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "KERNELS" for t in node.targets))
    assert set(listed) == _kernel_sources()
    assert len(_kernel_sources()) >= 4


def test_no_kernel_is_plain_python():
    """No ``_kernels_*.py`` beside the compiled modules (it would shadow or replace them)."""
    found = {m.name for m in pkgutil.iter_modules([str(PACKAGE)]) if m.name.startswith("_kernels_")}
    assert found == _kernel_sources() | NOT_YET_PORTED
    assert {p.stem for p in PACKAGE.glob("_kernels_*.py")} == NOT_YET_PORTED


@pytest.mark.parametrize("name", sorted({p.stem for p in (Path(__file__).resolve().parent.parent / "gridfield")
                                         .glob("_kernels_*.pyx")}))
def test_kernel_module_is_a_compiled_extension(name):
    mod = importlib.import_module(f"gridfield.{name}")
    assert mod.__file__ is not None
    assert mod.__file__.endswith(tuple(importlib.machinery.EXTENSION_SUFFIXES)), mod.__file__
    assert isinstance(mod.__loader__, importlib.machinery.ExtensionFileLoader)


def test_planning_imports_no_jit_compiler():
    """A potential plan runs without numba or pyximport (a compiler at run time) being imported."""
    code = ("import sys, numpy as np; from gridfield.grid import Grid, GridMap; "
            "from gridfield.follow import plan_potential; occ = np.zeros((12, 12), bool); occ[5:7, 5:7] = True; "
            "plan_potential(GridMap(Grid((12, 12), 1.0), occ), np.array([1.5, 1.5]), np.array([10.5, 10.5]), "
            "{'q_star': 2.0, 'step': 0.5, 'tolerance': 0.5}); "
            "print(sorted(m for m in ('numba', 'llvmlite', 'pyximport') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=REPO)
    assert out.stdout.strip() == "[]"
