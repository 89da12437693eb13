"""CI does not depend on dependencies' warnings: only warnings from gridfield's own code (and tests) are errors."""

from __future__ import annotations

import ast
import contextlib
import os
import socket
import subprocess
import sys
from pathlib import Path

import pytest

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


# The suite's Dask clusters bind no fixed port. ``dashboard_address=None`` only turns the dashboard off: the
# scheduler still serves its HTTP routes on 8787, which a cluster of another xdist worker (or of anybody on
# the machine) may hold; distributed then warns "Port 8787 is already in use" and leaves the socket of the
# failed bind unclosed (a ResourceWarning): two warnings in every `pytest -n 2` summary. ":0" asks for a
# free port.
CLUSTER_TESTS = [  # the in-process clusters, a few seconds each; the process clusters are checked statically
    "tests/test_bad_input2.py::test_dask_killed_worker_is_one_error_and_the_rows_are_kept",
    "tests/test_bad_input2.py::test_dask_cluster_without_workers_ends_the_sweep",
    "tests/test_sweep.py::test_local_pool_and_dask_localcluster_give_the_same_rows",
]


def test_every_test_cluster_asks_for_a_free_port() -> None:
    offenders = []
    for f in sorted((ROOT / "tests").glob("*.py")):
        for node in ast.walk(ast.parse(f.read_text(), str(f))):
            func = node.func if isinstance(node, ast.Call) else None
            if getattr(func, "attr", getattr(func, "id", None)) != "LocalCluster":
                continue
            given = {k.arg: k.value for k in node.keywords}  # type: ignore[union-attr]
            value = given.get("dashboard_address")
            if not (isinstance(value, ast.Constant) and value.value == ":0"):
                offenders.append(f"{f.name}:{node.lineno}")
    assert not offenders, f"LocalCluster without dashboard_address=':0' (binds port 8787): {', '.join(offenders)}"


def test_the_test_clusters_warn_of_nothing_while_port_8787_is_taken() -> None:
    """The cluster tests run in a pytest of their own while this process holds port 8787 (as a concurrent
    cluster does): its summary lists no warning."""
    pytest.importorskip("distributed")
    with contextlib.ExitStack() as stack:
        held = stack.enter_context(socket.socket(socket.AF_INET, socket.SOCK_STREAM))
        with contextlib.suppress(OSError):  # taken already: by someone else, which serves the test as well
            held.bind(("0.0.0.0", 8787))
            held.listen()
        proc = subprocess.run(
            [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q", *CLUSTER_TESTS],
            capture_output=True, text=True, timeout=600, cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)},
        )
    out = proc.stdout
    summary = out.strip().splitlines()[-1]
    assert proc.returncode == 0, out
    assert summary.startswith(f"{len(CLUSTER_TESTS)} passed") and "warning" not in summary, out
