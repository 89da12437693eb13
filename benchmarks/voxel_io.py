"""Benchmark: reading a Moving AI ``.3dmap`` of millions of voxel lines.

Run ``python benchmarks/voxel_io.py`` (options: ``--size`` voxels per side, ``--fraction`` blocked,
``--repeat``). Writes one random map to a temporary folder and times, round robin in one process (compare by
ratio):

- ``read_3dmap``: gridfield's reader (header, size guard, the body parsed from its bytes with numpy, checks,
  the occupancy array);
- ``split + np.array``: the body as ``np.array(body.split(), dtype=np.int64)`` and the same occupancy
  scatter (no checks: the usual quick parse);
- ``np.loadtxt``: ``np.loadtxt(path, skiprows=1, dtype=np.int64)`` and the scatter.

All three must give the same occupancy (checked).
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np
from _common import markdown_table, round_robin

from gridfield.io import read_3dmap


def write_map(path: Path, size: int, fraction: float, seed: int = 0) -> np.ndarray:
    occ = np.random.default_rng(seed).random((size, size, size)) < fraction
    zyx = np.argwhere(occ)
    with open(path, "w") as f:
        f.write(f"voxel {size} {size} {size}\n")
        np.savetxt(f, zyx[:, ::-1], fmt="%d")
    return occ


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=160, help="voxels per side")
    ap.add_argument("--fraction", type=float, default=0.5, help="blocked fraction")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "bench.3dmap"
        occ = write_map(path, args.size, args.fraction)
        n = int(occ.sum())
        shape = occ.shape

        def scatter(t: np.ndarray) -> np.ndarray:
            out = np.zeros(shape, dtype=bool)
            out[t[:, 2], t[:, 1], t[:, 0]] = True
            return out

        def split_parse() -> np.ndarray:
            data = path.read_bytes()
            body = data[data.index(b"\n") + 1:]
            return scatter(np.array(body.split(), dtype=np.int64).reshape(-1, 3))

        def loadtxt() -> np.ndarray:
            return scatter(np.loadtxt(path, skiprows=1, dtype=np.int64, ndmin=2))

        candidates = {"read_3dmap": lambda: read_3dmap(path).occupied, "split + np.array": split_parse,
                      "np.loadtxt": loadtxt}
        for name, f in candidates.items():
            assert np.array_equal(f(), occ), name
        res = round_robin(candidates, repeat=args.repeat)
        base = res["read_3dmap"].median_ms
        print(f"{args.size}^3 voxels, {n} lines ({path.stat().st_size / 1e6:.1f} MB)")
        print(markdown_table(["reader", "median ms", "x read_3dmap"],
                             [[k, f"{t.median_ms:.0f}", f"{t.median_ms / base:.2f}"] for k, t in res.items()]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
