"""Every result type prints a short summary, never its arrays (a notebook shows reprs)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt

from gridfield.core.params import validate
from gridfield.demo import DemoResult
from gridfield.distance.brushfire import brushfire
from gridfield.fields.navigation import wavefront
from gridfield.fields.potential import build_field
from gridfield.following.follower import basins
from gridfield.io import bundled_map, read, read_scen, read_world
from gridfield.planners import plan
from gridfield.plot import plot_map


def test_reprs_are_short_and_hold_no_arrays():
    m = read(bundled_map("turtlebot3_world/map.yaml"))  # 384 x 384: any printed array would be long
    goal, start = (1.8, 0.5), (-2.0, -0.5)
    f = build_field(m, goal)
    w = read_world(bundled_map("seed000.yaml"))
    path = plan("potential", m, start, goal)
    art = plot_map(m, paths=[path])
    demo = DemoResult(bundled_map("seed000.yaml").parent, rows=[{"part": "x"}] * 500, files=[], seconds=1.0)
    from gridfield.distance.incremental import IncrementalBrushfire
    from gridfield.exact.continuous import ExactField
    from gridfield.explore import Explorer

    explorer = Explorer(w, resolution=1.0)
    objects = [m, brushfire(m), f, basins(f), wavefront(m, goal), path, ExactField(w, w.goal),
               IncrementalBrushfire(m), explorer,
               read_scen(bundled_map("arena/arena.map.scen")), validate({"q_star": 0.5}), w, w.obstacles[0],
               art, demo]
    for obj in objects:
        text = repr(obj)
        assert len(text) < 200, (type(obj).__name__, len(text))
        assert "array(" not in text and "[[" not in text, text
        assert text.startswith(type(obj).__name__ + "("), text
    plt.close("all")
    # the reprs say what matters
    assert repr(w) == "World(obstacles=3, bounds=(0, 0, 25, 20), border='open', start=(1, 10), goal=(22, 12), " \
                      "source='seed000.yaml')"
    assert repr(w.obstacles[1]) == "Obstacle(id=2, kind='polygon', bounds=(6, 4, 12, 10))"
    assert "rows=500" in repr(demo) and "paths=1" in repr(art)
    assert repr(explorer) == ("Explorer(planner='potential', start=(1.0, 10.0), goal=(22.0, 12.0), "
                              f"path={explorer.path.status!r}, cspace=False, updates=1)")
    explorer.close()
