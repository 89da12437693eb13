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

#: Every kernel module of the package by dotted name, all compiled, each beside its callers (a new one is
#: added to setup.py's KERNELS, to the mypy overrides of pyproject.toml and here).
KERNELS = {
    "gridfield.chunked._chunked",
    "gridfield.distance._brushfire", "gridfield.distance._chamfer", "gridfield.distance._edt",
    "gridfield.distance._incremental", "gridfield.distance._incremental3", "gridfield.distance._edt3",
    "gridfield.exact._anyangle", "gridfield.exact._astar", "gridfield.exact._occlusion", "gridfield.exact._polyanya",
    "gridfield.fields._eikonal", "gridfield.fields._laplace", "gridfield.fields._navfn", "gridfield.fields._navigation",
    "gridfield.fields._navigation3", "gridfield.fields._voxelpath",
    "gridfield.fields._potential", "gridfield.fields._samplers", "gridfield.following._taut",
}
#: The longest a kernel source (.pyx, .pxd, .h) may be, as any other file of the package (issue 43).
MAX_LINES = 800


def _kernel_sources() -> set[str]:
    return {".".join(p.relative_to(REPO).with_suffix("").parts) for p in (REPO / "gridfield").rglob("*.pyx")}


def test_every_kernel_source_is_built_by_setup_py():
    """setup.py's KERNELS lists exactly the .pyx modules of the tree (adding one is a one-line change)."""
    tree = ast.parse((REPO / "setup.py").read_text())
    listed = next(ast.literal_eval(node.value) for node in ast.walk(tree)
                  if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "KERNELS" for t in node.targets))
    assert set(listed) == _kernel_sources() == KERNELS


def test_no_kernel_is_plain_python():
    """No ``_name.py`` beside a compiled ``_name`` module (it would shadow or replace it)."""
    for name in sorted(KERNELS):
        package, _, module = name.rpartition(".")
        folder = REPO.joinpath(*package.split("."))
        assert module in {m.name for m in pkgutil.iter_modules([str(folder)])}, name
        assert not (folder / f"{module}.py").exists(), name


def test_every_kernel_module_is_typed_as_a_compiled_one():
    """pyproject.toml's mypy override for the kernels (no stubs: Any to their callers) names every one."""
    import tomllib

    overrides = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["mypy"]["overrides"]
    listed = {m for o in overrides if o.get("follow_imports") == "skip" for m in o["module"]}
    assert listed >= KERNELS, sorted(KERNELS - listed)


def test_no_kernel_source_is_over_the_line_limit():
    sources = sorted(p for ext in ("*.pyx", "*.pxd", "*.h") for p in PACKAGE.rglob(ext))
    long = {str(p.relative_to(REPO)): n for p in sources if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert sources and long == {}


@pytest.mark.parametrize("name", sorted(KERNELS))
def test_kernel_module_is_a_compiled_extension(name):
    mod = importlib.import_module(name)
    assert mod.__file__ is not None
    assert mod.__file__.endswith(tuple(importlib.machinery.EXTENSION_SUFFIXES)), mod.__file__
    assert isinstance(mod.__loader__, importlib.machinery.ExtensionFileLoader)


def test_planning_imports_no_jit_compiler():
    """A potential plan runs without numba or pyximport (a compiler at run time) being imported."""
    code = ("import sys, numpy as np; from gridfield.core.grid import Grid, GridMap; "
            "from gridfield.following.follower import plan_potential; occ = np.zeros((12, 12), bool); occ[5:7, 5:7] = True; "
            "plan_potential(GridMap(Grid((12, 12), 1.0), occ), np.array([1.5, 1.5]), np.array([10.5, 10.5]), "
            "{'q_star': 2.0, 'step': 0.5, 'tolerance': 0.5}); "
            "print(sorted(m for m in ('numba', 'llvmlite', 'pyximport') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=REPO)
    assert out.stdout.strip() == "[]"


def test_no_module_of_the_package_imports_numba():
    """numba left the package: no module imports it (nor llvmlite), at top level or inside a function."""
    offenders = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level else [])
            offenders += [f"{path.name}: {n}" for n in names if n.split(".")[0] in ("numba", "llvmlite")]
    assert offenders == []


def test_incremental_and_anyangle_import_no_jit_compiler():
    """An incremental update, a potential window update and an any-angle plan run without numba."""
    code = ("import sys, numpy as np; from gridfield.core.grid import Grid, GridMap; "
            "from gridfield.distance.incremental import IncrementalBrushfire; from gridfield.fields.incremental import update_field; "
            "from gridfield.fields.potential import build_field; from gridfield.exact.anyangle import grid_graph; "
            "occ = np.zeros((12, 12), bool); occ[5:7, 3:9] = True; gm = GridMap(Grid((12, 12), 1.0), occ); "
            "ib = IncrementalBrushfire(gm); f = build_field(ib.gridmap, (10.5, 10.5), {'q_star': 2.0}, "
            "dmap=ib.distance_map); f = update_field(f, ib, ib.update(occupied=[[2, 2]], freed=[[5, 3]])); "
            "pts, length = grid_graph(gm).shortest_path((1.5, 1.5), (10.5, 10.5)); assert 13 < length < 14; "
            "print(sorted(m for m in ('numba', 'llvmlite', 'pyximport') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=REPO)
    assert out.stdout.strip() == "[]"
