"""Make the NavFn agreement fixtures of tests/data/navfn/ (see the README there).

Runs a NavFn reference driver (Nav2's own navfn.cpp built outside the repository, see
tests/data/navfn/README.md) on gridfield's inflated costmaps of the ROS maps in ../shared/maps and
one Moving AI map, for seeded random start/goal pairs, and stores the numbers it prints: the
potential at a subsample of the assigned cells (and how many there are), the path in cells, and a
digest of the costmap it ran on. This script holds no Nav2 code.

    PYTHONPATH=. python tools/navfn_fixtures.py --driver /tmp/navfn_ref/driver --maps ../shared/maps --out tests/data/navfn
"""

from __future__ import annotations

import argparse
import hashlib
import subprocess
import tempfile
from pathlib import Path

import numpy as np

#: (fixture name, map file, inflation options (None: Nav2's defaults), queries)
MAPS = [
    ("turtlebot3_world", "ros_maps/turtlebot3_world/map.yaml", None, 4),
    ("nav2_depot", "ros_maps/nav2_depot/depot.yaml", None, 4),
    ("nav2_smoothers_world", "ros_maps/nav2_smoothers_world/smoothers_world.yaml", None, 4),
    ("mdr_wrs20_arena", "ros_maps/mdr_wrs20-arena/map.yaml", None, 4),
    ("aws_small_warehouse_005", "ros_maps/aws_small_warehouse_005/map.yaml", None, 3),
    ("movingai_den312d", "movingai/den312d/den312d.map",
     {"robot_radius": 1.0, "inflation_radius": 4.0, "cost_scaling_factor": 1.0}, 4),
]
SAMPLE = 1500  # potential values kept per query
POT_HIGH = np.float32(1.0e10)


def costmap_of(path: Path, options: dict | None):
    from gridfield.fields.costmap import inflate
    from gridfield.io import read

    return inflate(read(path), **(options or {}))


def digest(cost: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(cost).tobytes()).hexdigest()


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--driver", required=True)
    ap.add_argument("--maps", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--seed", type=int, default=7)
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(a.seed)
    for name, rel, res, nq in MAPS:
        cm = costmap_of(Path(a.maps) / rel, res)
        rows, cols = cm.shape
        free = np.argwhere(cm.cost[1:-1, 1:-1] < 253) + 1
        rec: dict[str, list] = {k: [] for k in ("start", "goal", "assigned", "idx", "pot", "path", "path_len")}
        with tempfile.TemporaryDirectory() as d:
            binf = Path(d) / "cost.bin"
            binf.write_bytes(np.ascontiguousarray(cm.cost).tobytes())  # row 0 = the origin's row, as Costmap2D
            while len(rec["start"]) < nq:
                s, g = free[rng.integers(len(free), size=2)]
                run = subprocess.run([a.driver, str(binf), str(cols), str(rows), str(s[1]), str(s[0]), str(g[1]),
                                      str(g[0]), "1", str(Path(d) / "q")], capture_output=True, text=True, check=True)
                n = int(run.stdout.split()[0])
                pot = np.fromfile(Path(d) / "q.pot", dtype=np.float32)
                if n == 0 or np.hypot(*(s - g)) < 20:
                    continue  # unreachable or too short: pick another pair
                path = np.fromfile(Path(d) / "q.path", dtype=np.float32).reshape(-1, 2)
                assigned = np.flatnonzero(pot < POT_HIGH)
                pick = np.sort(rng.choice(assigned, size=min(SAMPLE, len(assigned)), replace=False))
                rec["start"].append(s)
                rec["goal"].append(g)
                rec["assigned"].append(len(assigned))
                rec["idx"].append(pick)
                rec["pot"].append(pot[pick])
                rec["path"].append(path)
                rec["path_len"].append(len(path))
        np.savez_compressed(
            out / f"{name}.npz", map=rel, options=repr(res or {}), cost_sha256=digest(cm.cost),
            shape=np.array([rows, cols]), start=np.array(rec["start"]), goal=np.array(rec["goal"]),
            assigned=np.array(rec["assigned"]), sample_len=np.array([len(i) for i in rec["idx"]]),
            idx=np.concatenate(rec["idx"]), pot=np.concatenate(rec["pot"]), path_len=np.array(rec["path_len"]),
            path=np.concatenate(rec["path"]))
        print(name, rows, cols, rec["path_len"])


if __name__ == "__main__":
    main()
