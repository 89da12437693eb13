"""Write docs/api/*.rst: one page per public gridfield module, listing its ``__all__``."""

from __future__ import annotations

import ast
import importlib
import importlib.util
import inspect
import sys
import types
from pathlib import Path

# Every public module, by its dotted name under gridfield (the compiled kernels and the ``cli`` package are
# implementation details; the layer packages' own pages are those of their modules).
MODULES = [
    "io", "geometry.world", "core.grid", "core.limits", "geometry.rasterize", "geometry.cspace", "distance.brushfire",
    "chunked", "distance.incremental", "fields.incremental", "fields.potential", "fields.navfield", "fields.vortex",
    "core.params", "following.descent", "fields.sampling", "following.follower", "following.basins",
    "following.escapes", "following.diagnose", "following.taut", "fields.navigation", "fields.navtable", "fields.costmap", "fields.navfn",
    "exact.continuous", "exact.visibility", "geometry.gridpoly", "exact.anyangle", "planners", "core.path",
    "core.results", "compare", "sweep", "plot", "demo", "explore", "core.errors",
    # voxel grids and a robot that turns (issues 44, 45)
    "fields.navigation3d", "fields.navfield3d", "fields.potential3d", "fields.posefield", "following.follow3d",
    "following.posefollow", "plot.poses",
]


def _is_code(obj: object) -> bool:
    """A class or a function (not a type alias such as ``tuple[int, int]``, nor a constant)."""
    return not isinstance(obj, types.GenericAlias) and (inspect.isclass(obj) or callable(obj))


def _comment_of(module: types.ModuleType, name: str) -> str:
    """The ``#:`` comment lines just above ``name = ...`` in the module's source (autodoc's convention)."""
    src = inspect.getsource(module).splitlines()
    for i, line in enumerate(src):
        if line.startswith(f"{name} = "):
            notes = []
            while i > 0 and src[i - 1].startswith("#:"):
                i -= 1
                notes.insert(0, src[i][2:].strip())
            return " ".join(notes)
    return ""


def _source_module(module: types.ModuleType, name: str) -> types.ModuleType:
    """The module whose source assigns ``name``: ``module``, or the one it imports ``name`` from by a
    relative import, followed (a public module re-exporting a constant of a private one beside it)."""
    package = module.__name__ if hasattr(module, "__path__") else module.__name__.rpartition(".")[0]
    for node in ast.parse(inspect.getsource(module)).body:
        if (isinstance(node, ast.ImportFrom) and node.level
                and any(a.name == name and a.asname in (None, name) for a in node.names)):
            where = importlib.util.resolve_name("." * node.level + (node.module or ""), package)
            return _source_module(sys.modules[where], name)  # imported already: module imports it
    return module


def _home(obj: object) -> str | None:
    """The public module (of ``MODULES``) that defines ``obj``, a package for its private submodules."""
    where = getattr(obj, "__module__", None) or ""
    for name in MODULES:
        full = f"gridfield.{name}"
        if where == full or where.startswith(full + "."):
            return name
    return None


#: Names a page shows first (the entry point before the machinery it dispatches through).
FIRST = {"planners": ["plan", "get_planner", "check_params"]}


def _value(obj: object) -> str:
    """A constant's value for its entry: the repr when short, else its type and size."""
    text = repr(obj)
    if len(text) <= 100 and "\n" not in text:
        return text
    size = f" of {len(obj)} entries" if hasattr(obj, "__len__") else ""  # type: ignore[arg-type]
    return f"{type(obj).__name__}{size}"


def _is_tuple_class(obj: object) -> bool:
    return inspect.isclass(obj) and issubclass(obj, tuple)


def _page(name: str) -> str:
    module = importlib.import_module(f"gridfield.{name}")
    names = list(getattr(module, "__all__", []))
    first = [n for n in FIRST.get(name, []) if n in names]
    names = first + [n for n in names if n not in first]
    title = f"gridfield.{name}"
    lines = [title, "=" * len(title), "", f".. automodule:: gridfield.{name}", "   :no-members:", ""]
    # a name another public module defines (and this one re-exports) is documented once, on its home page
    elsewhere = {n: home for n in names if _is_code(getattr(module, n)) and (home := _home(getattr(module, n)))
                 not in (None, name)}
    names = [n for n in names if n not in elsewhere]
    if elsewhere:
        refs = ", ".join(f":{'class' if inspect.isclass(getattr(module, n)) else 'func'}:`gridfield.{home}.{n}`"
                         for n, home in elsewhere.items())
        lines += [f"Also importable from ``gridfield.{name}`` (documented where they are defined): {refs}.", ""]
    documented = [n for n in names if _is_code(getattr(module, n))]
    if documented:
        lines += [".. currentmodule:: " + f"gridfield.{name}", "", ".. autosummary::", ""]
        lines += [f"   {n}" for n in documented] + [""]
    for n in names:
        obj = getattr(module, n)
        if _is_tuple_class(obj):  # a named tuple: its docstring lists the fields (not "Alias for field number 0")
            lines += [f".. autoclass:: {n}", "   :no-members:", ""]
        elif inspect.isclass(obj):
            directive = "autoexception" if issubclass(obj, BaseException) else "autoclass"
            lines += [f".. {directive}:: {n}", "   :members:", ""]
        elif _is_code(obj):
            lines += [f".. autofunction:: {n}", ""]
        elif isinstance(obj, types.GenericAlias):
            lines += [f".. py:data:: {n}", "", f"   {_comment_of(module, n)}", "", f"   Type alias: ``{obj}``.", ""]
        else:  # a constant: its ``#:`` comment and its value (never the docstring of its type)
            note = _comment_of(_source_module(module, n), n) or _comment_of(
                importlib.import_module(getattr(obj, "__module__", "") or module.__name__), n)
            value = _value(obj).replace("`", "'")
            lines += [f".. py:data:: {n}", f"   :value: {value}", "", f"   {note}" if note else "", ""]
    return "\n".join(lines)


def write_api_pages(out: Path) -> None:
    """Write one ``.rst`` page per module and an index page; rewrite a file only when it changes."""
    out.mkdir(exist_ok=True)
    pages = {f"{name}.rst": _page(name) for name in MODULES}
    toc = "\n".join(f"   {name}" for name in MODULES)
    pages["index.rst"] = (
        "API reference\n=============\n\nOne page per public module, generated from its ``__all__``\n"
        f"(``docs/_api.py``).\n\n.. toctree::\n   :maxdepth: 1\n\n{toc}\n"
    )
    for fname, text in pages.items():
        path = out / fname
        if not path.exists() or path.read_text() != text:
            path.write_text(text)


def cli_page() -> str:
    """The command-line reference: every sub-command's ``--help``, generated from the parsers."""
    import argparse
    import os

    from gridfield.cli import COMMANDS, build_parser

    os.environ.setdefault("COLUMNS", "100")  # argparse wraps its help to the terminal width: a fixed one
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    lines = ["Command line", "============", "",
             "Every sub-command of ``gridfield`` with its ``--help``, generated from the parsers on each build",
             "(``docs/_api.py``), so it lists exactly the options the installed version takes. Bad input is",
             "one line on stderr and exit code 2; a misspelt option gets a \"did you mean\".", "",
             ".. code-block:: text", ""]
    lines += ["   " + ln if ln else "" for ln in parser.format_help().splitlines()] + [""]
    for name in COMMANDS:
        title = f"gridfield {name}"
        lines += [title, "-" * len(title), "", ".. code-block:: text", ""]
        lines += ["   " + ln if ln else "" for ln in sub.choices[name].format_help().splitlines()] + [""]
    return "\n".join(lines)


def write_cli_page(path: Path) -> None:
    """Write :func:`cli_page` to ``path`` (only when it changes)."""
    text = cli_page()
    if not path.exists() or path.read_text() != text:
        path.write_text(text)
