"""List the lines of the repository's tests, benchmarks, docs and CI that name the ``../shared`` folder.

That folder (the developers' collection of external maps) lies beside this project's own checkouts only:
a user's clone has none, so the suite, the benchmarks and the docs build read their maps from
``tests/data/maps`` instead. Run ``python tools/outside_data.py`` (exit status 1 when a line names it);
the test suite runs it (``tests/test_data_manifest.py``).
"""

from __future__ import annotations

import re
import subprocess
import sys
from collections.abc import Iterable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: What is searched: the folders and files a clone's tests, benchmarks, docs build and CI read.
SEARCHED = ("tests", "benchmarks", "docs", ".ci", "conftest.py")
#: Ways a path to the folder is written: literally, or joined from parts with pathlib.
PATTERN = re.compile(r"""\.\./shared|["']shared["']\s*/|/\s*["']shared["']|parent\s*/\s*["']shared|shared/maps""")
BINARY = {".gz", ".png", ".gif", ".npz", ".pgm", ".bmp", ".mp4", ".jpg"}


def offenders(root: Path, names: Iterable[str]) -> list[str]:
    """``file:line`` of every line of the text files ``names`` (relative to ``root``) naming the folder."""
    found = []
    for name in names:
        path = root / name
        if path.suffix in BINARY or not path.is_file():
            continue
        text = path.read_text(errors="replace")
        found += [f"{name}:{i}" for i, line in enumerate(text.splitlines(), 1) if PATTERN.search(line)]
    return found


def tracked(root: Path) -> list[str]:
    """The files git tracks under :data:`SEARCHED`."""
    out = subprocess.run(["git", "ls-files", *SEARCHED], cwd=root, capture_output=True, text=True, check=True)
    return out.stdout.split()


def main() -> int:
    found = offenders(ROOT, tracked(ROOT))
    for line in found:
        print(line)
    print(f"{len(found)} line(s) naming the folder beside the repository")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
