"""List the import cycles among gridfield's modules: every import statement counted (function-level and
``TYPE_CHECKING`` ones, a package's ``__init__`` and its own modules), on grimp's graph of the package.

Run ``python tools/import_cycles.py [PACKAGE_DIR]`` (exit status 1 when there is a cycle); the test suite
runs it (``tests/test_layers.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _cycles(package: Path) -> list[list[str]]:
    """The import cycles (strongly connected components of more than one module, or a module importing
    itself) of grimp's graph of the package at ``package``, every import statement counted."""
    import grimp

    sys.path.insert(0, str(package.parent))
    try:
        graph = grimp.build_graph(package.name, cache_dir=None)
    finally:
        sys.path.pop(0)
    edges = {m: {w for w in graph.find_modules_directly_imported_by(m) if w.startswith(package.name)}
             for m in graph.modules if m.startswith(package.name)}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    for root in sorted(edges):  # Tarjan's algorithm, iteratively
        if root in index:
            continue
        work = [(root, iter(sorted(edges[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            v, children = work[-1]
            w = next(children, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(edges[w]))))
                elif w in on_stack:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    x = stack.pop()
                    on_stack.discard(x)
                    comp.append(x)
                    if x == v:
                        break
                if len(comp) > 1 or v in edges[v]:
                    found.append(sorted(comp))
    return found


def main(argv: list[str]) -> int:
    package = Path(argv[0]).resolve() if argv else ROOT / "gridfield"
    found = _cycles(package)
    for comp in found:
        print("cycle: " + " <-> ".join(comp))
    print(f"{len(found)} import cycle(s)")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
