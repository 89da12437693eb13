"""CI does not depend on dependencies' warnings: only warnings from gridfield's own code (and tests) are errors."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

PROBES = '''
import warnings

def test_a_dependency_warning_about_itself():
    warnings.warn_explicit("unclosed transport", ResourceWarning, "distributed/comm/tcp.py", 1, module="distributed.comm.tcp")

def test_a_resource_warning_at_garbage_collection():  # attributed to whatever code runs when GC happens
    warnings.warn_explicit("unclosed socket", ResourceWarning, "gridfield/sweep.py", 1, module="gridfield.sweep")

def test_a_warning_from_gridfield():
    warnings.warn_explicit("ours", RuntimeWarning, "gridfield/io.py", 1, module="gridfield.io")

def test_a_numpy_warning_in_a_test():
    import numpy as np
    np.array([1.0]) / 0
'''


def test_warning_filters_are_scoped_to_gridfield(tmp_path: Path) -> None:
    (tmp_path / "test_probes.py").write_text(PROBES)
    proc = subprocess.run(
        [sys.executable, "-m", "pytest", "-c", str(ROOT / "pyproject.toml"), "--rootdir", str(tmp_path),
         "-p", "no:cacheprovider", "-q", "-rfE", str(tmp_path / "test_probes.py")],
        capture_output=True, text=True, timeout=120, cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(ROOT)},
    )
    out = proc.stdout
    assert proc.returncode == 1, out
    assert "2 failed, 2 passed" in out
    assert "FAILED test_probes.py::test_a_warning_from_gridfield" in out
    assert "FAILED test_probes.py::test_a_numpy_warning_in_a_test" in out
