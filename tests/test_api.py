"""The curated top-level API: ``gridfield.read``, ``gridfield.plan``, ``gridfield.brushfire``, ... loaded on first
use, declared for editors and mypy by ``gridfield/__init__.pyi``."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import gridfield

ROOT = Path(__file__).resolve().parents[1]


def _stub_names() -> dict[str, str]:
    """name -> module (relative to gridfield) of each ``from .module import name as name`` in the stub."""
    tree = ast.parse((ROOT / "gridfield" / "__init__.pyi").read_text())
    return {a.asname or a.name: node.module or "" for node in tree.body if isinstance(node, ast.ImportFrom)
            for a in node.names}


def test_stub_runtime_and_all_agree() -> None:
    stub = _stub_names()
    assert sorted([*stub, "__version__"]) == sorted(gridfield.__all__)
    tree = ast.parse((ROOT / "gridfield" / "__init__.pyi").read_text())
    (stub_all,) = [n.value for n in tree.body if isinstance(n, ast.Assign) and n.targets[0].id == "__all__"]
    assert sorted(ast.literal_eval(stub_all)) == sorted(gridfield.__all__)
    assert set(gridfield.__all__) <= set(dir(gridfield))


@pytest.mark.parametrize("name", sorted(set(gridfield.__all__) - {"__version__"}))
def test_each_name_is_the_object_of_its_home(name: str) -> None:
    import importlib

    home = importlib.import_module(f"gridfield.{_stub_names()[name]}".rstrip("."))
    value = getattr(gridfield, name)
    if isinstance(value, type(importlib)):  # a subpackage (or the errors module): the module itself
        assert value is importlib.import_module(value.__name__) and value.__name__.startswith("gridfield.")
    else:
        assert value is getattr(home, name)


def _run(code: str) -> str:
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return r.stdout.strip()


def test_import_gridfield_stays_light() -> None:
    heavy = ("matplotlib", "scipy", "shapely", "yaml", "skimage", "gridfield.fields.potential", "gridfield.distance.brushfire",
             "gridfield.io", "gridfield.planners", "gridfield.distance._brushfire", "gridfield.distance._chamfer",
             "gridfield.distance._edt", "gridfield.fields._potential")
    out = _run(f"import sys, gridfield; print(','.join(m for m in {heavy!r} if m in sys.modules))")
    assert out == "", f"import gridfield imports {out}"


@pytest.mark.parametrize("first", ["import gridfield.fields.potential", "import gridfield.distance.brushfire as bf",
                                   "from gridfield.distance.brushfire import brushfire", "import gridfield"])
def test_top_level_functions_whatever_imported_their_modules_first(first: str) -> None:
    """However the module was first imported (here, or inside another module), ``gridfield.brushfire`` is the
    function and ``gridfield.distance.brushfire`` the module."""
    out = _run(f"{first}\n"
               "import numpy as np, gridfield, gridfield.distance.brushfire as bf, gridfield.following.follower as fo\n"
               "gm = gridfield.GridMap(gridfield.Grid((2, 3), 1.0), np.zeros((2, 3), bool))\n"
               "d = gridfield.brushfire(gm, metric='euclidean'); e = bf.brushfire(gm, metric='euclidean')\n"
               "print(bf.DistanceMap.__name__, fo.follow_many.__name__, type(d).__name__, "
               "bool(np.array_equal(d.distance, e.distance)))")
    assert out == "DistanceMap follow_many DistanceMap True"


def test_the_curated_names_plan() -> None:
    gm = gridfield.GridMap(gridfield.Grid((3, 5), 1.0), np.zeros((3, 5), bool))
    field = gridfield.build_field(gm, (4.5, 1.5))
    path = gridfield.follow(field, (0.5, 1.5), params={"step": 0.5})
    assert path.status == "reached"
    assert gridfield.plan("potential", gm, (0.5, 1.5), (4.5, 1.5), {"step": 0.5}).status == "reached"
    assert gridfield.rasterize(gridfield.read(gridfield.bundled_map("seed000.yaml")), 0.5).grid.resolution == 0.5


def test_mypy_reads_the_stub(tmp_path: Path) -> None:
    """mypy types the lazy names from the stub: a call with a wrong argument type is an error, the rest is clean."""
    snippet = tmp_path / "use_api.py"
    snippet.write_text(
        "import numpy as np\n"
        "import gridfield as gf\n"
        "gm = gf.GridMap(gf.Grid((2, 2), 1.0), np.zeros((2, 2), bool))\n"
        "d: gf.DistanceMap = gf.brushfire(gm)\n"
        "p: gf.Path = gf.plan('wavefront', gm, (0.5, 0.5), (1.5, 1.5))\n"
        "f: gf.Field = gf.build_field(gm, (1.5, 1.5))\n"
        "w: gf.World | gf.GridMap = gf.read(gf.bundled_map('seed000.yaml'))\n"
        "bad: str = gf.brushfire(gm)\n")
    r = subprocess.run([sys.executable, "-m", "mypy", "--follow-imports=silent", "--no-incremental",
                        "--config-file", str(ROOT / "pyproject.toml"), str(snippet)], cwd=ROOT, capture_output=True,
                       text=True, timeout=600)
    errors = [line for line in r.stdout.splitlines() if ": error:" in line]
    assert len(errors) == 1 and "use_api.py:8:" in errors[0] and "DistanceMap" in errors[0], r.stdout


def test_every_planner_function_takes_cache() -> None:
    """``plan`` passes ``cache=`` to every planner (it no longer inspects signatures)."""
    import inspect

    from gridfield.planners import GRID_VARIANTS, PLANNERS, get_planner

    functions = [get_planner(name)[0] for name in PLANNERS]
    functions += [getattr(__import__(module, fromlist=[func]), func) for module, func in GRID_VARIANTS.values()]
    for fn in functions:
        p = inspect.signature(fn).parameters.get("cache")
        assert p is not None and p.kind is inspect.Parameter.KEYWORD_ONLY and p.default is None, fn.__qualname__
    assert "inspect" not in inspect.getsource(__import__("gridfield.planners", fromlist=["plan"]))
