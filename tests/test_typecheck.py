"""mypy on the package, with the configuration in pyproject.toml ([tool.mypy]), must be clean."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def test_mypy_clean():
    proc = subprocess.run([sys.executable, "-m", "mypy", "--no-incremental"], cwd=ROOT, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, f"mypy found type errors:\n{proc.stdout}\n{proc.stderr}"
