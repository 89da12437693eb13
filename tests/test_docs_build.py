"""The documentation site builds with warnings as errors (``python -m sphinx -W -b html docs OUT``).

The build runs every gallery example and imports every documented object, so a broken example, a
docstring numpydoc cannot parse or an API page naming a removed function fails here.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_docs_build_without_warnings(tmp_path: Path) -> None:
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONPATH": str(ROOT)}
    proc = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "-q", "-b", "html", "-d", str(tmp_path / "doctrees"),
         str(ROOT / "docs"), str(tmp_path / "html")],
        capture_output=True, text=True, env=env, cwd=ROOT, timeout=600,
    )
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-4000:]
    html = tmp_path / "html"
    assert (html / "index.html").is_file()
    # the gallery ran: every example has its page and drew at least one figure
    examples = sorted(p.stem for p in (ROOT / "docs" / "examples").glob("plot_*.py"))
    assert len(examples) >= 9
    for name in examples:
        assert (html / "auto_examples" / f"{name}.html").is_file(), name
        assert list((html / "_images").glob(f"sphx_glr_{name}_*.png")), name
    # one API page per public module
    assert (html / "api" / "following.follower.html").is_file()
