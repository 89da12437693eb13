"""Generate the suite's voxel test maps: Moving AI 3-D ``.3dmap`` files and their ``.3dscen`` scenarios.

No publicly licensed Moving AI 3-D map small enough for the test data could be found, so gridfield makes its
own, in the benchmark's format (Brewer and Sturtevant 2018): a header ``voxel W H D`` and one ``x y z`` line
per blocked voxel; scenarios ``version 1``, the map's name, then ``sx sy sz gx gy gz optimal_cost ratio``.

Three maps, each from a fixed seed (the same files on every run):

- ``building``: three floors of rooms with doors, slabs between the floors, a stair shaft through each;
- ``random20``: a cube with 20 % of its voxels blocked at random;
- ``cave``: smoothed random noise, thresholded (open caverns and tunnels).

The optimal costs are computed here by a plain Dijkstra search, independent of gridfield's planners: 26
neighbours, moves of cost 1, sqrt 2 and sqrt 3, and a move allowed only when every voxel of its bounding box
is free (the benchmark's rule: no corner or edge cutting). ``ratio`` is the cost over the obstacle-free
(3-D octile) cost.

Usage::

    python tools/make_voxel_maps.py [--out tests/data/maps/voxel] [--manifest]

``--manifest`` prints the MANIFEST.md rows of the files written (sha256 of the published and stored bytes).
"""

from __future__ import annotations

import argparse
import gzip
import hashlib
import heapq
import itertools
import math
from pathlib import Path

import numpy as np
from scipy import ndimage

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "tests" / "data" / "maps" / "voxel"
SCENARIOS = 12


def building(rng: np.random.Generator) -> np.ndarray:
    """Three floors of 4 x 4 rooms (doors in every wall), slabs between them, a stair shaft per slab."""
    d, h, w = 13, 33, 33
    occ = np.zeros((d, h, w), dtype=bool)
    occ[:, 0, :] = occ[:, -1, :] = occ[:, :, 0] = occ[:, :, -1] = True  # outer walls
    for z in (0, 4, 8, 12):
        occ[z] = True  # ground, two slabs, roof
    for floor in range(3):
        z0 = 4 * floor + 1
        for k in (8, 16, 24):  # interior walls, every 8 voxels both ways
            occ[z0:z0 + 3, k, :] = True
            occ[z0:z0 + 3, :, k] = True
        for a in range(4):  # a door (2 wide, 2 high) in each wall segment, at a random place
            for k in (8, 16, 24):
                c = 8 * a + int(rng.integers(2, 6))
                occ[z0:z0 + 2, k, c:c + 2] = False
                c = 8 * a + int(rng.integers(2, 6))
                occ[z0:z0 + 2, c:c + 2, k] = False
    for z in (4, 8):  # a 3 x 3 shaft through each slab, in a random room
        r, c = (8 * int(rng.integers(0, 4)) + 3 for _ in range(2))
        occ[z, r:r + 3, c:c + 3] = False
    return occ


def random20(rng: np.random.Generator) -> np.ndarray:
    return rng.random((24, 24, 24)) < 0.2


def cave(rng: np.random.Generator) -> np.ndarray:
    noise = ndimage.gaussian_filter(rng.random((20, 40, 40)), sigma=2.0, mode="wrap")
    return noise > np.quantile(noise, 0.55)


MAPS = {"building": (building, 1), "random20": (random20, 2), "cave": (cave, 3)}

_MOVES = [m for m in itertools.product((-1, 0, 1), repeat=3) if m != (0, 0, 0)]


def _box(m: tuple[int, int, int]) -> list[tuple[int, int, int]]:
    """The offsets of the voxels of a move's bounding box (its end included, its start excluded)."""
    return [b for b in itertools.product(*[(0, v) if v else (0,) for v in m]) if b != (0, 0, 0)]


def dijkstra(occ: np.ndarray, start: tuple[int, int, int]) -> dict[tuple[int, int, int], float]:
    """Costs from ``start`` (``(z, y, x)``) to every voxel reachable under the bounding-box rule."""
    d, h, w = occ.shape
    moves = [(m, math.sqrt(sum(abs(v) for v in m)), _box(m)) for m in _MOVES]
    dist = {start: 0.0}
    heap = [(0.0, start)]
    done = set()
    while heap:
        g, v = heapq.heappop(heap)
        if v in done:
            continue
        done.add(v)
        z, y, x = v
        for m, cost, box in moves:
            ok = True
            for bz, by, bx in box:
                zz, yy, xx = z + bz, y + by, x + bx
                if not (0 <= zz < d and 0 <= yy < h and 0 <= xx < w) or occ[zz, yy, xx]:
                    ok = False
                    break
            if not ok:
                continue
            u = (z + m[0], y + m[1], x + m[2])
            ng = g + cost
            if ng < dist.get(u, math.inf) - 1e-12:
                dist[u] = ng
                heapq.heappush(heap, (ng, u))
    return dist


def octile3(a: tuple[int, int, int], b: tuple[int, int, int]) -> float:
    d1, d2, d3 = sorted((abs(p - q) for p, q in zip(a, b, strict=True)), reverse=True)
    return (d1 - d2) + (d2 - d3) * math.sqrt(2) + d3 * math.sqrt(3)


def scenarios(occ: np.ndarray, rng: np.random.Generator, n: int) -> list[tuple[tuple[int, int, int], ...] | float]:
    free = np.argwhere(~occ)
    rows: list = []
    while len(rows) < n:
        s = tuple(int(v) for v in free[rng.integers(len(free))])
        dist = dijkstra(occ, s)  # type: ignore[arg-type]
        if len(dist) < 2:
            continue
        reach = sorted(dist)
        g = reach[int(rng.integers(len(reach)))]
        if g == s:
            continue
        rows.append((s, g, dist[g]))
    return rows


def map_text(occ: np.ndarray) -> str:
    d, h, w = occ.shape
    zyx = np.argwhere(occ)
    return f"voxel {w} {h} {d}\n" + "".join(f"{x} {y} {z}\n" for z, y, x in zyx)


def scen_text(name: str, rows: list) -> str:
    out = ["version 1", name]
    for s, g, cost in rows:
        (sz, sy, sx), (gz, gy, gx) = s, g
        out.append(f"{sx} {sy} {sz} {gx} {gy} {gz} {cost:.8f} {cost / octile3(s, g):.8f}")
    return "\n".join(out) + "\n"


def write_gz(path: Path, text: str) -> tuple[bytes, bytes]:
    raw = text.encode("ascii")
    packed = gzip.compress(raw, compresslevel=9, mtime=0)
    path.write_bytes(packed)
    return raw, packed


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--manifest", action="store_true", help="print the MANIFEST.md rows")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    manifest = []
    for name, (make, seed) in MAPS.items():
        rng = np.random.default_rng(seed)
        occ = make(rng)
        rows = scenarios(occ, rng, SCENARIOS)
        for fname, text in ((f"{name}.3dmap", map_text(occ)), (f"{name}.3dmap.3dscen", scen_text(f"{name}.3dmap", rows))):
            raw, packed = write_gz(args.out / (fname + ".gz"), text)
            rel = (args.out / (fname + ".gz")).resolve().relative_to(REPO / "tests" / "data" / "maps").as_posix()
            manifest.append(
                f"| `{rel}` | generated by tools/make_voxel_maps.py, seed {seed} | `tools/make_voxel_maps.py` | `` "
                f"| MIT (gridfield) | {len(raw)} | `{hashlib.sha256(raw).hexdigest()}` | gzip -9 | "
                f"`{hashlib.sha256(packed).hexdigest()}` |")
        print(f"{name}: {occ.shape[::-1]} (W, H, D), {occ.mean():.1%} blocked, {len(rows)} scenarios")
    if args.manifest:
        print("\n".join(manifest))


if __name__ == "__main__":
    main()
