"""
A sweep and its summary
=======================

The runs of ``maps/sweep_example.yaml`` (random pairs on seed 000, Moving AI scenarios on arena;
the potential planner and the octile wavefront for two values of ``q_star``), a few of them run
here in-process, summarized per (map, planner, parameters): the success rate of each.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

from gridfield.io import bundled_map
from gridfield.sweep import load_spec, run_one, summarize

with tempfile.TemporaryDirectory() as tmp:
    runs, _ = load_spec(bundled_map("sweep_example.yaml"), output=Path(tmp) / "runs.csv")
rows = [run_one(run) for run in runs[::4]]
summary = summarize(rows)
labels = [f"{Path(s['map']).name}\n{s['planner']}\n{s['params']}" for s in summary]
rates = [100 * float(s["success_rate"]) for s in summary]

fig, ax = plt.subplots(figsize=(8, 4.5), layout="constrained")
ax.barh(labels, rates)
ax.set_xlabel("success rate (%)")
ax.tick_params(axis="y", labelsize=7)
ax.set_title(f"{len(rows)} of the {len(runs)} runs")
