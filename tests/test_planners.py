"""The planner registry: ``get_planner`` turns only a missing optional third-party package into
"not available in this installation"; a broken import inside gridfield and a registry entry naming a
function that does not exist are bugs and surface as such, from ``get_planner`` and from ``plan``."""

from __future__ import annotations

import sys
import textwrap

import pytest

from gridfield.errors import GridfieldError
from gridfield.planners import PLANNERS, get_planner, plan
from gridfield.world import world_from_dict

WORLD = world_from_dict({"bounds": [0, 0, 10, 10], "obstacles": [{"rectangle": [4, 2, 6, 8]}]})


@pytest.fixture
def register(tmp_path, monkeypatch):
    """``register(name, source)``: a throwaway module ``fake_planner_<name>`` holding ``source`` on
    sys.path, and a PLANNERS entry ``name`` pointing at its ``plan_fake``."""

    def make(name: str, source: str, func: str = "plan_fake", kind: str = "world") -> str:
        module = f"fake_planner_{name}"
        (tmp_path / f"{module}.py").write_text(textwrap.dedent(source))
        monkeypatch.setitem(PLANNERS, name, (module, func, kind))
        monkeypatch.delitem(sys.modules, module, raising=False)  # undone on teardown: no module left behind
        return name

    monkeypatch.syspath_prepend(str(tmp_path))
    return make


PLAN_FAKE = """
def plan_fake(world, start, goal, params):
    raise AssertionError("never called")
"""


def test_a_missing_third_party_dependency_is_not_available(register):
    name = register("optional", "import no_such_optional_dependency.sub\n" + PLAN_FAKE)
    with pytest.raises(GridfieldError, match=r"planner 'optional' is not available in this installation "
                                             r"\(install the package providing 'no_such_optional_dependency'"):
        get_planner(name)
    with pytest.raises(GridfieldError, match="not available in this installation"):
        plan(name, WORLD, (1, 5), (9, 5))


@pytest.mark.parametrize("source", [
    "from gridfield.path import NoSuchName\n",           # a broken import of gridfield's own code
    "import gridfield.no_such_submodule\n",               # a gridfield module that does not exist
    "raise ImportError('broken', name='gridfield.follow')\n",
])
def test_a_broken_gridfield_import_propagates(register, source):
    name = register("broken", source + PLAN_FAKE)
    with pytest.raises(ImportError) as got:
        get_planner(name)
    assert got.type is not GridfieldError and "not available" not in str(got.value)
    assert got.value.name.startswith("gridfield.")
    with pytest.raises(ImportError) as got:
        plan(name, WORLD, (1, 5), (9, 5))
    assert "not available" not in str(got.value)


def test_a_registry_entry_naming_a_missing_gridfield_module_propagates(monkeypatch):
    monkeypatch.setitem(PLANNERS, "lost", ("gridfield.no_such_planner_module", "plan_lost", "grid"))
    with pytest.raises(ModuleNotFoundError, match=r"gridfield\.no_such_planner_module"):
        get_planner("lost")


def test_a_misspelt_function_name_is_a_registry_bug_not_unavailable(monkeypatch):
    monkeypatch.setitem(PLANNERS, "typo", ("gridfield.follow", "plan_potentail", "grid"))
    for call in (lambda: get_planner("typo"), lambda: plan("typo", WORLD, (1, 5), (9, 5), resolution=0.5)):
        with pytest.raises(AttributeError, match=r"PLANNERS\['typo'\] names gridfield.follow.plan_potentail") as got:
            call()
        assert not isinstance(got.value, GridfieldError) and "not available" not in str(got.value)


def test_an_attribute_error_while_importing_propagates(register):
    name = register("attr", "import gridfield\ngridfield.no_such_attribute\n" + PLAN_FAKE)
    with pytest.raises(AttributeError, match="no_such_attribute"):
        get_planner(name)
