"""The order of the stop rules: written once (``descent.STOP_RULES``), spelled out by both followers.

``descend`` checks the rules as one scalar chain in its step loop and ``follow_many`` as masks (in
``_stops_before_step`` beside it and its own loop): a table of rule functions iterated per step would
cost the scalar follower about 40 % more time per step (1.7 -> 2.4 us, measured with
``benchmarks/follow.py --descend-only``), so the chains stay inline. These tests read both chains
from the source and check that each names the stop reasons in ``STOP_RULES`` order, so that a rule
moved in one follower (or in the table) fails here, not only where the random cases of
``tests/test_follower_spec.py`` happen to make two rules fire at the same step.
"""

from __future__ import annotations

import ast
import inspect
import textwrap

from gridfield.following import descent
from gridfield.following import follower as follow
from gridfield.following.descent import STOP_RULES


def _function(module: object, name: str) -> ast.FunctionDef:
    tree = ast.parse(textwrap.dedent(inspect.getsource(module)))
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef) and node.name == name:
            return node
    raise AssertionError(f"no function {name}")


def _in_order(nodes: list[ast.AST]) -> list[ast.AST]:
    return sorted(nodes, key=lambda n: (n.lineno, n.col_offset))


def _step_loop(fn: ast.FunctionDef) -> ast.While:
    loops = [n for n in ast.walk(fn) if isinstance(n, ast.While)]
    assert len(loops) == 1, f"{fn.name}: expected one step loop, found {len(loops)}"
    return loops[0]


def _first_occurrences(names: list[str]) -> list[str]:
    out: list[str] = []
    for n in names:
        if n in STOP_RULES and n not in out:
            out.append(n)
    return out


def test_stop_rules_table():
    assert STOP_RULES[0] == "goal" and len(set(STOP_RULES)) == len(STOP_RULES)
    # follow_many finishes a pinned point at the step that found no free move, descend at the next
    # check: the same only because nothing but the goal (never met by a point that did not move)
    # comes before blocked
    assert STOP_RULES[1] == "blocked"


def test_descend_checks_the_stop_rules_in_table_order():
    loop = _step_loop(_function(descent, "descend"))
    # the loop's condition is the goal rule (reached); the others are the reasons (and the budget's
    # status) the chain assigns, in source order
    assert isinstance(loop.test, ast.UnaryOp) and isinstance(loop.test.operand, ast.Call)
    assert ast.unparse(loop.test.operand.func) == "reached"
    named = [n.value for n in _in_order([n for n in ast.walk(loop) if isinstance(n, ast.Constant)])
             if isinstance(n.value, str)]
    assert ["goal", *_first_occurrences(named)] == list(STOP_RULES)


def test_follow_many_checks_the_stop_rules_in_table_order():
    loops = inspect.getmodule(follow.follow_many)  # where it is written (follower re-exports it)
    before_step = _function(loops, "_stops_before_step")
    loop = _step_loop(_function(loops, "follow_many"))

    def finishes(node: ast.AST) -> list[str]:
        out: list[str] = []
        for call in _in_order([n for n in ast.walk(node) if isinstance(n, ast.Call)]):
            callee = ast.unparse(call.func)
            if callee == "_stops_before_step":
                out += finishes(before_step)
            elif callee == "finish":
                why = call.args[2]
                assert isinstance(why, ast.Constant) and isinstance(why.value, str)
                out.append(why.value)
        return out

    order = finishes(loop)
    assert sorted(order) == sorted(STOP_RULES), order
    # blocked is found (and finished) by the step, after the other rules of that step; see
    # test_stop_rules_table for why that is the table's order
    assert order[-1] == "blocked"
    assert ["goal", "blocked", *order[1:-1]] == list(STOP_RULES)
