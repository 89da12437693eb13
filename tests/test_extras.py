"""The extras of pyproject.toml are complete, checked statically (AST, nothing is imported or installed).

- Every import of a third-party module inside gridfield that is not a core dependency (an optional
  import) sits in a ``try`` whose ``ImportError`` message names an extra (``gridfield[NAME]``), and
  that extra lists the module's distribution.
- The documentation build (``[docs]``) can run every gallery example: each module an example imports,
  and each optional module imported where a planner the example names (``plan("fmm", ...)``) is
  defined, is a core dependency or listed in ``[docs]``; so are the Sphinx extensions and the theme
  of ``docs/conf.py``.
- README and the installing page list every extra.
"""

from __future__ import annotations

import ast
import re
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
CORE = PYPROJECT["project"]["dependencies"]
EXTRAS: dict[str, list[str]] = PYPROJECT["project"]["optional-dependencies"]

# import name -> distribution name, where they differ
DISTRIBUTION = {
    "skfmm": "scikit-fmm", "skimage": "scikit-image", "yaml": "pyyaml", "PIL": "pillow",
    "distributed": "dask", "imageio_ffmpeg": "imageio-ffmpeg", "sphinx_gallery": "sphinx-gallery",
    "cv2": "opencv-python-headless", "mpl_toolkits": "matplotlib",
}


def _dist(requirement: str) -> str:
    """``'dask[distributed]>=2024.1'`` -> ``'dask'`` (normalized)."""
    return re.split(r"[\[<>=!~; ]", requirement, maxsplit=1)[0].lower().replace("_", "-")


def _names(requirements: list[str]) -> set[str]:
    return {_dist(r) for r in requirements}


def _distribution(module: str) -> str:
    return DISTRIBUTION.get(module, module).lower().replace("_", "-")


def _top(module: str) -> str:
    return module.split(".")[0]


def _third_party(module: str) -> bool:
    return bool(module) and module not in sys.stdlib_module_names and module not in ("gridfield", "__future__")


def _imports(tree: ast.AST) -> list[tuple[ast.stmt, str]]:
    found: list[tuple[ast.stmt, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(node, _top(a.name)) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.append((node, _top(node.module)))
    return found


def _guarded_extra(tree: ast.AST, node: ast.stmt) -> str | None:
    """The extra named (``gridfield[NAME]``) by the ImportError handler of the ``try`` around ``node``."""
    for t in ast.walk(tree):
        if isinstance(t, ast.Try) and any(node is s for b in t.body for s in ast.walk(b)):
            for h in t.handlers:
                text = " ".join(c.value for c in ast.walk(h) if isinstance(c, ast.Constant) and isinstance(c.value, str))
                if m := re.search(r"gridfield\[(\w[\w-]*)\]", text):
                    return m.group(1)
    return None


def _package_files() -> list[Path]:
    return sorted((ROOT / "gridfield").rglob("*.py"))


def _optional_imports(path: Path) -> list[tuple[str, str | None]]:
    """(module, extra named by its guard) for each third-party import of ``path`` outside the core."""
    tree = ast.parse(path.read_text(), str(path))
    core = _names(CORE)
    return [(mod, _guarded_extra(tree, node)) for node, mod in _imports(tree)
            if _third_party(mod) and _distribution(mod) not in core]


#: Optional imports that only refine a result and have a fallback in the code (no extra needed):
#: module -> (file, what happens without it). Each is checked to sit in a try with a fallback branch.
SOFT = {"psutil": ("gridfield/core/limits.py", "the available memory is read from /proc/meminfo")}


def test_every_optional_import_names_an_extra_that_lists_it() -> None:
    seen = []
    for path in _package_files():
        found = _optional_imports(path)
        guarded = {_top(m): e for m, e in found if e is not None}
        for mod, extra in found:
            where = path.relative_to(ROOT)
            if extra is None and _top(mod) in guarded:  # reached only after the guarded import of its package
                extra = guarded[_top(mod)]
            seen.append(mod)
            if _top(mod) in SOFT and SOFT[_top(mod)][0] == where.as_posix():
                assert "import psutil" in path.read_text() and "except Exception" in path.read_text(), (where, mod)
                continue
            assert extra is not None, f"{where}: optional import {mod} has no ImportError message naming gridfield[EXTRA]"
            assert extra in EXTRAS, f"{where}: names gridfield[{extra}], not an extra of pyproject.toml"
            assert _distribution(mod) in _names(EXTRAS[extra]), (where, mod, extra)
    assert {"skfmm", "tornado", "distributed"} <= set(seen)  # the check sees the known ones


def _planner_files() -> dict[str, Path]:
    """Planner name -> the file that defines its function (PLANNERS read from the table's source)."""
    table = ast.parse((ROOT / "gridfield" / "core" / "planner_table.py").read_text())
    planners: dict[str, str] = {}
    for node in ast.walk(table):
        if isinstance(node, ast.Dict):
            for k, v in zip(node.keys, node.values, strict=True):
                if (isinstance(k, ast.Constant) and isinstance(v, ast.Call) and getattr(v.func, "id", "") == "Planner"
                        and isinstance(v.args[1], ast.Constant)):
                    planners[k.value] = v.args[1].value
    assert "fmm" in planners
    defined = {}
    for path in _package_files():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef) and node.name in planners.values():
                defined[node.name] = path
    return {name: defined[fn] for name, fn in planners.items()}


def test_docs_extra_covers_the_gallery_and_conf() -> None:
    docs = _names(CORE) | _names(EXTRAS["docs"])
    planner_files = _planner_files()
    needed: dict[str, str] = {}
    for example in sorted((ROOT / "docs" / "examples").glob("*.py")):
        tree = ast.parse(example.read_text())
        for _, mod in _imports(tree):
            if _third_party(mod):
                needed[_distribution(mod)] = example.name
        strings = {c.value for c in ast.walk(tree) if isinstance(c, ast.Constant) and isinstance(c.value, str)}
        for name in strings & planner_files.keys():
            for mod, _ in _optional_imports(planner_files[name]):
                needed[_distribution(mod)] = f"{example.name} (planner {name})"
    conf = ast.parse((ROOT / "docs" / "conf.py").read_text())
    for node in ast.walk(conf):
        if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", "") in ("extensions", "html_theme"):
            for c in ast.walk(node.value):
                if isinstance(c, ast.Constant) and _third_party(mod := _top(c.value)) and mod != "alabaster":
                    needed[_distribution(mod)] = "docs/conf.py"
    assert "scikit-fmm" in needed  # plot_seed002_completeness plans with fmm
    missing = {dist: why for dist, why in needed.items() if dist not in docs}
    assert not missing, f"[docs] lacks what the build imports: {missing}"


def test_readme_and_installing_page_list_every_extra() -> None:
    readme = (ROOT / "README.md").read_text()
    installing = (ROOT / "docs" / "guide" / "installing.rst").read_text()
    for extra in EXTRAS:
        assert f"[{extra}]" in readme, f"README does not list [{extra}]"
        assert f"[{extra}]" in installing, f"installing.rst does not list [{extra}]"
