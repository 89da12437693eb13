"""README's example commands print what README shows (numbers included).

Each indented ``$ gridfield ...`` line of README.md is run from the repository root, and each line
README shows under it must match a line of the output: text and numbers exactly, ``...`` standing for
anything and ``N ms`` timings for any time. Commands that start a server or a long sweep are skipped
(listed in ``SKIP``); a new example is checked automatically.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SKIP = ("gridfield explore", "gridfield sweep")  # a web server; a 60-run sweep writing runs.csv


def examples() -> list[tuple[str, list[str]]]:
    out: list[tuple[str, list[str]]] = []
    lines = (ROOT / "README.md").read_text().splitlines()
    for i, line in enumerate(lines):
        if line.startswith("    $ gridfield "):
            expected = []
            for nxt in lines[i + 1:]:
                if not nxt.startswith("    ") or nxt.startswith("    $ "):
                    break
                expected.append(nxt[4:])
            out.append((line[6:], expected))
    return out


def _pattern(expected: str) -> re.Pattern[str]:
    parts = re.split(r"(\.\.\.|\d+(?:\.\d+)? ms)", expected)
    regex = "".join(".*" if p == "..." else r"[0-9.]+ ms" if p.endswith(" ms") and p[0].isdigit() else re.escape(p)
                    for p in parts)
    return re.compile(regex)


EXAMPLES = examples()


def test_readme_has_examples() -> None:
    assert len(EXAMPLES) >= 8
    assert any("exact-potential" in cmd for cmd, _ in EXAMPLES)


@pytest.mark.parametrize(("command", "expected"), [e for e in EXAMPLES if not e[0].startswith(SKIP)],
                         ids=[e[0][10:60] for e in EXAMPLES if not e[0].startswith(SKIP)])
def test_readme_example_prints_what_readme_shows(command: str, expected: list[str], tmp_path: Path) -> None:
    args = shlex.split(command)[1:]
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, "-m", "gridfield", *args], capture_output=True, text=True, cwd=ROOT,
                          env=env, timeout=300)
    printed = (proc.stdout + proc.stderr).splitlines()
    assert proc.returncode in (0, 1, 2) and "Traceback" not in proc.stderr, proc.stderr[-2000:]
    for want in expected:
        pat = _pattern(want)
        assert any(pat.fullmatch(line) for line in printed), f"README shows\n  {want}\nbut {command} printed\n  " + \
            "\n  ".join(printed)
