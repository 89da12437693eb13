"""The registry (gridfield/params.py) is the only source of parameter defaults and rules.

A planner reads its parameters as typed groups (``validate(params).group(Follower)``, ``params.known``),
never as ``params.get(name, default)`` with a default of its own; and where the code needs a rule the
registry states it. The bugs that the private defaults and rules caused are pinned here.
"""

from __future__ import annotations

import ast
import warnings
from pathlib import Path

import numpy as np
import pytest

from gridfield.core.errors import ParameterError
from gridfield.fields.navigation import StarNavWarning
from gridfield.fields.navtable import navigation_field
from gridfield.geometry.rasterize import rasterize
from gridfield.geometry.world import world_from_dict
from gridfield.planners import plan

PACKAGE = Path(__file__).resolve().parents[1] / "gridfield"

#: The one module that states parameter defaults (the follower's tables are gone too).
ALLOWED = {"params.py"}

#: The names gridfield gives a mapping of planner parameters.
PARAM_MAPPINGS = {"params", "p", "merged"}


def _gets_with_default(path: Path, root: Path = PACKAGE.parent) -> list[str]:
    out = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "get"
                and isinstance(node.func.value, ast.Name) and node.func.value.id in PARAM_MAPPINGS
                and len(node.args) + len(node.keywords) >= 2):
            out.append(f"{path.relative_to(root)}:{node.lineno}: {ast.unparse(node)}")
    return out


def test_no_parameter_default_outside_the_registry() -> None:
    found = [hit for f in sorted(PACKAGE.rglob("*.py")) if f.name not in ALLOWED or f.parent != PACKAGE
             for hit in _gets_with_default(f)]
    assert not found, "parameter defaults outside gridfield/params.py:\n" + "\n".join(found)


def test_the_ast_check_can_fail(tmp_path: Path) -> None:
    f = tmp_path / "m.py"
    f.write_text("def g(params, p):\n    return float(params.get('kappa', 3.0)), p.get('step'), p.get(k, 1)\n")
    hits = [h.split(": ", 1)[1] for h in _gets_with_default(f, tmp_path)]
    assert sorted(hits) == ["p.get(k, 1)", "params.get('kappa', 3.0)"]


# ----------------------------------------------------------------------------------------------
# kappa=none (the registry allows None: "not given")
# ----------------------------------------------------------------------------------------------
ONE_CIRCLE = {"bounds": [0, 0, 10, 10], "obstacles": [{"circle": {"center": [5, 5], "radius": 1.5}}],
              "start": [2, 5.5], "goal": [8, 5], "resolution": 0.25}


def test_cli_field_sphere_nav_kappa_none(tmp_path: Path, capsys) -> None:
    """Was a TypeError traceback and exit 1; now ``none`` means "not given" (the number of discs + 1)."""
    import yaml

    from gridfield.cli import main

    world = tmp_path / "one_circle.yaml"
    world.write_text(yaml.safe_dump(ONE_CIRCLE))
    code = main(["field", str(world), "--planner", "sphere-nav", "--param", "kappa=none",
                 "--npz", str(tmp_path / "none.npz")])
    err = capsys.readouterr().err
    assert code == 0, err
    assert "Traceback" not in err
    assert main(["field", str(world), "--planner", "sphere-nav", "--param", "kappa=2",
                 "--npz", str(tmp_path / "two.npz")]) == 0
    a, b = np.load(tmp_path / "none.npz"), np.load(tmp_path / "two.npz")
    np.testing.assert_array_equal(a["potential"], b["potential"])  # one disc: kappa 1 + 1


def test_navigation_field_kappa_none_is_not_given() -> None:
    w = world_from_dict(ONE_CIRCLE)
    gm = rasterize(w, 0.5)
    none, unset = navigation_field(gm, w.goal, "sphere-nav", {"kappa": None}), navigation_field(gm, w.goal, "sphere-nav")
    assert none.params["kappa"] == unset.params["kappa"] == 2.0
    np.testing.assert_array_equal(none.value, unset.value)


@pytest.mark.parametrize("name", ["step", "tolerance", "max_iterations", "kappa"])
def test_sphere_nav_none_is_not_given(name: str) -> None:
    """An explicit None (allowed by the registry) was float(None): a TypeError."""
    w = world_from_dict(ONE_CIRCLE)
    a = plan("sphere-nav", w, w.start, w.goal, {name: None})
    b = plan("sphere-nav", w, w.start, w.goal, {})
    assert a.status == b.status == "reached"
    np.testing.assert_array_equal(a.points, b.points)


# ----------------------------------------------------------------------------------------------
# star-nav: its own rules replaced by the registry's
# ----------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def star_two():
    from gridfield.io import bundled_map, read_world

    return read_world(bundled_map("star_two.yaml"))


def test_star_nav_tiny_step_is_refused_up_front(star_two) -> None:
    """step=1e-9 made the default step budget ~1e12 (killed after 300 s); now a ParameterError naming the bound."""
    from gridfield.fields.navigation._sphere import MAX_DEFAULT_ITERATIONS

    with pytest.raises(ParameterError, match=rf"star-nav: step=1e-09 is too small .* more than {MAX_DEFAULT_ITERATIONS}"):
        plan("star-nav", star_two, star_two.start, star_two.goal, {**star_two.params, "step": 1e-9})
    # with a budget of its own the step is followed (3 steps of 1e-9)
    p = plan("star-nav", star_two, star_two.start, star_two.goal, {**star_two.params, "step": 1e-9, "max_iterations": 3})
    assert (p.status, p.iterations) == ("max_iterations", 3)
    assert np.hypot(*(p.points[-1] - p.points[0])) <= 3e-9 * (1 + 1e-9)


def test_star_nav_max_iterations_0_is_no_step(star_two) -> None:
    """The registry allows max_iterations=0; star-nav refused it."""
    p = plan("star-nav", star_two, star_two.start, star_two.goal, {**star_two.params, "max_iterations": 0})
    assert (p.status, p.iterations) == ("max_iterations", 0)
    np.testing.assert_array_equal(p.points, [star_two.start])


def test_star_nav_progress_window_0_is_off(star_two) -> None:
    """The registry says progress_window=0 is off; star-nav refused it. Off = a window never reached."""
    base = {**star_two.params, "max_iterations": 40}
    off = plan("star-nav", star_two, star_two.start, star_two.goal, {**base, "progress_window": 0})
    huge = plan("star-nav", star_two, star_two.start, star_two.goal, {**base, "progress_window": 10**9})
    assert off.status == huge.status
    np.testing.assert_array_equal(off.points, huge.points)


def test_star_nav_kappa_and_lambda_follow_the_registry(star_two) -> None:
    """kappa and lambda: finite numbers > 0, as the registry says (star-nav had [1, 1000] and [1e-6, 1e12]).
    A kappa too small for the world is warned about (spurious minima), not refused."""
    base = {**star_two.params, "max_iterations": 5}
    with pytest.warns(StarNavWarning, match="kappa=0.5 is too small"):
        plan("star-nav", star_two, star_two.start, star_two.goal, {**base, "kappa": 0.5})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert plan("star-nav", star_two, star_two.start, star_two.goal, {**base, "lambda": 1e13}).iterations == 5
        assert plan("star-nav", star_two, star_two.start, star_two.goal, {**base, "kappa": 5000.0}).iterations == 5
    with pytest.raises(ParameterError, match="kappa must be a finite number > 0"):
        plan("star-nav", star_two, star_two.start, star_two.goal, {**base, "kappa": 0})
