"""Every result type prints a short summary, never its arrays (a notebook shows reprs)."""

from __future__ import annotations

from gridfield.brushfire import brushfire
from gridfield.follow import basins
from gridfield.io import bundled_map, read, read_scen
from gridfield.navigation import wavefront
from gridfield.params import validate
from gridfield.planners import plan
from gridfield.potential import build_field


def test_reprs_are_short_and_hold_no_arrays():
    m = read(bundled_map("turtlebot3_world/map.yaml"))  # 384 x 384: any printed array would be long
    goal, start = (1.8, 0.5), (-2.0, -0.5)
    f = build_field(m, goal)
    objects = [m, brushfire(m), f, basins(f), wavefront(m, goal), plan("potential", m, start, goal),
               read_scen(bundled_map("arena/arena.map.scen")), validate({"q_star": 0.5})]
    for obj in objects:
        text = repr(obj)
        assert len(text) < 200, (type(obj).__name__, len(text))
        assert "array(" not in text and "[[" not in text, text
        assert text.startswith(type(obj).__name__ + "("), text
