"""README's install commands compile the kernels once (issue 30).

README says so; each of its commands is a single ``pip install`` (none installs one extra after
another, which would compile the kernels again); the build configuration compiles the kernels at install
only (Cython and setuptools are build requirements, not run-time ones, and no module of the package
imports them); and planning runs no compiler: no process is started, no compiler module is imported and
nothing in the package's folder is written.
"""

from __future__ import annotations

import ast
import json
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import gridfield

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = Path(gridfield.__file__).parent
README = (ROOT / "README.md").read_text()

#: Modules that build extensions (a compiler at run time), by their top-level or full names.
BUILDERS = ("setuptools", "distutils", "pyximport", "Cython.Build", "Cython.Compiler.Main", "numba")


def readme_commands() -> list[str]:
    """Every shell command of README: the lines of its fenced code blocks and of its indented blocks."""
    commands: list[str] = []
    fenced = False
    for line in README.splitlines():
        if line.startswith("```"):
            fenced = not fenced
        elif fenced and line.strip():
            commands.append(line.strip())
        elif line.startswith("    ") and line.strip():
            commands.append(line.strip().removeprefix("$ "))
    return commands


def test_readme_opens_with_its_two_install_commands_each_a_single_pip_install() -> None:
    commands = readme_commands()
    assert commands[:2] == ['pip install . && gridfield demo --out gridfield-demo',
                            'pip install -e ".[test]" && python -m pytest -n 2']
    installing = [c for c in commands if "pip install" in c]
    assert len(installing) >= 3  # the two above and the documentation's
    for command in installing:
        steps = [s.strip() for s in re.split(r"&&|;|\|\|", command)]
        pips = [s for s in steps if s.startswith("pip install")]
        assert len(pips) == 1 and command.count("pip install") == 1, f"{command!r} runs pip install more than once"
        # one target, with every extra it needs in one bracket: ".", ".[a,b]", -e ".[a]"
        assert re.fullmatch(r'pip install (-e )?("\.(\[[a-z,-]+\])?"|\.)', pips[0]), pips[0]


def test_readme_says_each_install_compiles_the_kernels_once_and_nothing_at_run_time() -> None:
    text = " ".join(README.split())
    assert "Run one of the two, not both." in text
    assert "Each command is a single `pip install`, which compiles the kernels once" in text
    assert "nothing is compiled at run time" in text
    assert "rather than one extra after another" in text


def test_the_build_compiles_at_install_only() -> None:
    """Cython and setuptools are what pip's build needs (build-system.requires), not dependencies of the
    installed package; setup.py cythonizes; no module of the package imports a builder, even in a function."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert config["build-system"]["build-backend"] == "setuptools.build_meta"
    build = {re.split(r"[<>=!~ \[]", r)[0].lower() for r in config["build-system"]["requires"]}
    assert {"setuptools", "cython"} <= build
    runtime = {re.split(r"[<>=!~ \[]", r)[0].lower() for r in config["project"]["dependencies"]}
    assert not runtime & {"setuptools", "cython", "pyximport", "numba"}
    assert "cythonize(" in (ROOT / "setup.py").read_text()
    offenders = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level else [])
            if isinstance(node, ast.Call) and getattr(node.func, "attr", getattr(node.func, "id", "")) in (
                    "import_module", "__import__") and node.args and isinstance(node.args[0], ast.Constant):
                names.append(str(node.args[0].value))
            offenders += [f"{path.relative_to(PACKAGE)}: {n}" for n in names
                          if n.split(".")[0].lower() in ("setuptools", "distutils", "pyximport", "cython")]
    assert offenders == []


_PROBE = """
import json, sys
started = []
def hook(event, args):
    if event in ("subprocess.Popen", "os.system", "os.posix_spawn", "os.spawn", "os.exec", "os.fork"):
        started.append(event + " " + repr(args)[:120])
sys.addaudithook(hook)
from gridfield.cli import main
codes = [main(["plan", MAP, "--scenario", MAP + ".scen", "--index", "40", "--planner", p, "--json"]) for p in PLANNERS]
builders = sorted(m for m in sys.modules if any(m == b or m.startswith(b + ".") for b in BUILDERS))
print(json.dumps({"codes": codes, "started": started, "builders": builders}), file=sys.stderr)
"""


def _package_files() -> dict[str, float]:
    return {str(p.relative_to(PACKAGE)): p.stat().st_mtime for p in PACKAGE.rglob("*") if "__pycache__" not in p.parts}


def test_planning_starts_no_compiler_and_writes_nothing_into_the_package() -> None:
    """Plans with the compiled planners (potential field, wavefront, navfn, any-angle visibility) in a fresh
    interpreter: an audit hook sees every process it would start; afterwards no module that builds
    extensions is loaded and no file of the package (its kernels included) is new or newer."""
    planners = ["potential", "wavefront-octile", "navfn", "visibility"]
    code = (f"MAP = {str(ROOT / 'maps' / 'arena' / 'arena.map')!r}\nPLANNERS = {planners!r}\n"
            f"BUILDERS = {BUILDERS!r}\n" + _PROBE)
    before = _package_files()
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONPATH": str(ROOT), "PYTHONDONTWRITEBYTECODE": "1"}
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=env,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    report = json.loads(proc.stderr.strip().splitlines()[-1])
    assert report["codes"] == [0] * len(planners), proc.stdout[-2000:]
    assert report["started"] == []
    assert report["builders"] == []
    assert _package_files() == before
