"""A new follower parameter is one field in the registry's tables (``gridfield/core/_param_table.py``)
and the code that reads it.

The follower has no table of its own (``follow.FOLLOW_DEFAULTS`` and ``descent.RULE_PARAMS`` are
gone): its values come from the registry as the typed groups ``params.Follower`` and
``params.Escape`` (:func:`gridfield.following.descent.rules`). The test below copies the package, adds one
field to ``Follower`` in the copy's ``core/_param_table.py`` (no other file is touched), and checks in a
fresh interpreter that the new parameter is validated, resolved, handed to both followers' rules
and recorded in the path, and that the CLI's ``--param`` parser knows it.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "gridfield"

ANCHOR = '    confine_window: int = _p("follower", "integer", 20,'
NEW_FIELD = ('    turn_limit: float = _p("follower", "number", 90.0, "test only: a new follower parameter", '
             'minimum=0.0)\n')

CHECK = textwrap.dedent('''
    import numpy as np
    from gridfield.following.descent import descend, resolve_rules
    from gridfield.core.errors import ParameterError
    from gridfield.following.follower import _setup, follow, follow_many, resolve_follow_params
    from gridfield.core.grid import Grid, GridMap
    from gridfield.core.params import REGISTRY, Follower, parse
    from types import SimpleNamespace

    assert REGISTRY["turn_limit"].default == 90.0 and Follower().turn_limit == 90.0
    assert resolve_follow_params({}, unit=0.5)["turn_limit"] == 90.0
    assert resolve_rules({"turn_limit": 30}).follower.turn_limit == 30.0
    try:
        resolve_rules({"turn_limit": -1})
    except ParameterError as e:
        assert str(e).startswith("turn_limit must be a finite number >= 0"), e
    else:
        raise AssertionError("turn_limit=-1 accepted")
    assert parse("turn_limit", "45") == 45.0
    g = Grid((8, 8), 1.0)
    X, Y = np.meshgrid(*g.cell_centers())
    f = SimpleNamespace(map=GridMap(g, np.zeros(g.shape, bool)), grad_x=X - 6.5, grad_y=Y - 6.5,
                        goal=(6.5, 6.5), potential=None, params={}, distance=None)
    assert _setup(f, {"turn_limit": 45.0}).rules.follower.turn_limit == 45.0
    assert follow(f, (1.5, 1.5), params={"turn_limit": 45.0}).params["turn_limit"] == 45.0
    assert follow_many(f, [[1.5, 1.5]], params={"turn_limit": 45.0})[0].params["turn_limit"] == 45.0
    p = descend(lambda q: (1.0 - q[0], 0.0), (0.0, 0.0), (1.0, 0.0), turn_limit=10.0)
    assert p.params["turn_limit"] == 10.0 and p.status == "reached"
    print("ok")
''')


def test_a_new_follower_parameter_is_one_field_in_params(tmp_path: Path) -> None:
    copy = tmp_path / "gridfield"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__", "*.c", "*.pyx"))
    params = copy / "core" / "_param_table.py"
    text = params.read_text()
    assert text.count(ANCHOR) == 1 and "turn_limit" not in text
    params.write_text(text.replace(ANCHOR, NEW_FIELD + ANCHOR))
    out = subprocess.run([sys.executable, "-c", CHECK], cwd=tmp_path, capture_output=True, text=True,
                         env={"PYTHONPATH": str(tmp_path), "PATH": "/usr/bin:/bin"}, timeout=300)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr[-3000:]
    # the original package does not know the name (the test changed only the copy)
    unpatched = subprocess.run([sys.executable, "-c", "from gridfield.core.params import REGISTRY; "
                                "print('turn_limit' in REGISTRY)"], cwd=PACKAGE.parent, capture_output=True,
                               text=True, env={"PYTHONPATH": str(PACKAGE.parent), "PATH": "/usr/bin:/bin"},
                               timeout=300)
    assert unpatched.stdout.strip() == "False", unpatched.stderr[-3000:]
