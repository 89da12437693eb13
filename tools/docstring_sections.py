"""Count the public functions and classes (every name in a public module's ``__all__``) whose
numpydoc docstring lacks a Parameters, Returns or Examples section.

    python tools/docstring_sections.py [-v]

``-v`` lists the names missing each section. Classes need no Returns section (and an Attributes
section stands for Parameters); functions without parameters need no Parameters section.
"""

from __future__ import annotations

import importlib
import inspect
import sys
from pathlib import Path

from numpydoc.docscrape import FunctionDoc, NumpyDocString

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "docs"))
from _api import MODULES, _is_code

SECTIONS = ("Parameters", "Returns", "Examples")


def missing_sections(modules: list[str]) -> tuple[int, dict[str, list[str]]]:
    """The number of public functions and classes of ``gridfield.<module>`` for each of ``modules``
    (exceptions not counted) and, per section, the ``module.name`` of those lacking it."""
    missing: dict[str, list[str]] = {section: [] for section in SECTIONS}
    total = 0
    for name in modules:
        module = importlib.import_module(f"gridfield.{name}")
        for n in getattr(module, "__all__", []):
            obj = getattr(module, n)
            if not _is_code(obj) or (inspect.isclass(obj) and issubclass(obj, BaseException)):
                continue
            total += 1
            doc = NumpyDocString(inspect.getdoc(obj) or "") if inspect.isclass(obj) else FunctionDoc(obj)
            qual = f"{name}.{n}"
            try:
                has_args = any(p.name not in ("self", "cls") for p in inspect.signature(obj).parameters.values())
            except (TypeError, ValueError):
                has_args = True
            if has_args and not (doc["Parameters"] or (inspect.isclass(obj) and doc["Attributes"])):
                missing["Parameters"].append(qual)
            if not inspect.isclass(obj) and not (doc["Returns"] or doc["Yields"]):
                missing["Returns"].append(qual)
            if not doc["Examples"]:
                missing["Examples"].append(qual)
    return total, missing


def main(argv: list[str]) -> int:
    total, missing = missing_sections(MODULES)
    print(f"{total} public functions and classes (exceptions not counted)")
    for section, names in missing.items():
        print(f"missing {section}: {len(names)}")
        if "-v" in argv:
            print("    " + ", ".join(names))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
