"""List the private names and modules of gridfield imported from outside their owner.

The rule (ARCHITECTURE.md, "Namespace"): a name with a leading underscore belongs to the module
that defines it; a private module (``_name.py`` or ``_name/``) belongs to its package, whose
modules may use it and its underscore names; nothing else imports them. The compiled kernels (the
``_name.pyx`` modules beside their callers, e.g. ``gridfield.distance._brushfire``) are exempt: a layer
above may call the kernels of one below (the chunked brushfire runs the distance layer's rows).
Function-local imports count like module-level ones.

Run ``python tools/private_imports.py`` (exit status 1 when any is found); the test suite runs it
(``tests/test_layers.py``).
"""

from __future__ import annotations

import ast
import sys
from collections.abc import Iterable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _kernels(root: Path) -> set[str]:
    """The dotted names of the compiled kernel modules (the ``.pyx`` sources under ``root``)."""
    return {".".join(p.relative_to(root).with_suffix("").parts) for p in root.rglob("*.pyx")}


def _private(part: str) -> bool:
    return part.startswith("_") and not part.startswith("__")


def _module_name(path: Path, root: Path) -> tuple[str, bool]:
    parts = list(path.relative_to(root).with_suffix("").parts)
    is_pkg = parts[-1] == "__init__"
    return ".".join(parts[:-1] if is_pkg else parts), is_pkg


def _resolve(current: str, is_pkg: bool, node: ast.ImportFrom) -> str:
    if node.level == 0:
        return node.module or ""
    base = current.split(".") if is_pkg else current.split(".")[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _owner_of_module(module: str, kernels: set[str]) -> str | None:
    """The package owning the first private part of ``module``; None when nothing in it is private
    (or it is a kernel)."""
    if module in kernels:
        return None
    parts = module.split(".")
    for i, part in enumerate(parts):
        if _private(part):
            return ".".join(parts[:i])
    return None


def _inside(current: str, owner: str) -> bool:
    return current == owner or current.startswith(owner + ".")


def violations(files: Iterable[Path], root: Path) -> list[tuple[str, str, str]]:
    """``(importer, module, name)`` of every import that breaks the rule (``name`` is ``(module)``
    for a private module imported from outside its package)."""
    package_dir = root
    kernels = _kernels(root)
    out = []
    for f in sorted(files):
        current, is_pkg = _module_name(f, root)
        for node in ast.walk(ast.parse(f.read_text(), str(f))):
            if isinstance(node, ast.Import):
                mods = [(a.name, None) for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                mod = _resolve(current, is_pkg, node)
                mods = [(mod, a.name) for a in node.names]
            else:
                continue
            for mod, name in mods:
                owner = _owner_of_module(mod, kernels)
                if owner is not None and not _inside(current, owner):
                    out.append((current, mod, "(module)"))
                    continue
                if name is None or not _private(name) or f"{mod}.{name}" in kernels or mod in kernels:
                    continue
                sub = package_dir / Path(*f"{mod}.{name}".split("."))
                if sub.with_suffix(".py").exists() or sub.is_dir():  # a private submodule of mod
                    if not _inside(current, mod):
                        out.append((current, mod, name))
                    continue
                last = mod.split(".")[-1]
                if _private(last):  # an underscore name of a private module: its package may use it
                    if not _inside(current, mod.rsplit(".", 1)[0]):
                        out.append((current, mod, name))
                elif current != mod:
                    out.append((current, mod, name))
    return out


def main() -> int:
    found = violations((ROOT / "gridfield").rglob("*.py"), ROOT)
    for importer, module, name in found:
        print(f"{importer}: imports {name} from {module}")
    print(f"{len(found)} private import(s) from outside their owner")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
