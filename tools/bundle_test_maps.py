"""Copy the externally authored maps the test suite reads into ``tests/data/maps`` and write its MANIFEST.

The suite, the benchmarks' smoke tests and the docs build read only what is in the repository. This tool
made that copy once from a collection of public benchmark files (the Moving AI and ROS maps, the ROS
map-loader fixtures and the polygon fixtures, each with a manifest naming its source repository, path,
commit and licence) and is kept so that the copy can be checked or redone:

    python tools/bundle_test_maps.py --source DIR            # write tests/data/maps from DIR
    python tools/bundle_test_maps.py --source DIR --check    # compare tests/data/maps with DIR

``DIR`` is the collection's root (it holds ``MANIFEST.md``, ``movingai/``, ``ros_maps/``, ...). Text maps,
scenario lists and PGM images (but the loader fixtures') are stored gzip-compressed (level 9, no time
stamp, so the bytes are the same on every run): gridfield reads ``.map.gz``, ``.scen.gz`` and ``.pgm.gz`` directly. A ROS map's YAML
then names the compressed image (its only change, marked in the manifest). Every other file is copied
byte for byte.
"""

from __future__ import annotations

import argparse
import gzip
import hashlib
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
OUT = HERE.parent / "tests" / "data" / "maps"

#: The files the suite reads, relative to the collection's root (found by tracing the suite's file opens).
FILES = """
movingai/16room_000/16room_000.map movingai/16room_000/16room_000.map.scen
movingai/64room_000/64room_000.map movingai/64room_000/64room_000.map.scen
movingai/8room_000/8room_000.map movingai/8room_000/8room_000.map.scen
movingai/AR0011SR/AR0011SR.map movingai/AR0011SR/AR0011SR.map.scen
movingai/AcrosstheCape/AcrosstheCape.map movingai/AcrosstheCape/AcrosstheCape.map.scen
movingai/Aurora/Aurora.map movingai/Aurora/Aurora.map.scen
movingai/Berlin_0_256/Berlin_0_256.map movingai/Berlin_0_256/Berlin_0_256.map.scen
movingai/arena/arena.map movingai/arena/arena.map.scen
movingai/arena2/arena2.map movingai/arena2/arena2.map.scen
movingai/brc202d/brc202d.map movingai/brc202d/brc202d.map.scen
movingai/den312d/den312d.map movingai/den312d/den312d.map.scen
movingai/isound1/isound1.map movingai/isound1/isound1.map.scen
movingai/lak303d/lak303d.map movingai/lak303d/lak303d.map.scen
movingai/mapf_empty-48-48/empty-48-48.map movingai/mapf_empty-48-48/empty-48-48-even-1.scen
movingai/mapf_ht_chantry/ht_chantry.map movingai/mapf_ht_chantry/ht_chantry-even-1.scen
movingai/mapf_maze-32-32-2/maze-32-32-2.map movingai/mapf_maze-32-32-2/maze-32-32-2-even-10.scen
movingai/mapf_random-32-32-10/random-32-32-10.map movingai/mapf_random-32-32-10/random-32-32-10-random-1.scen
movingai/mapf_room-64-64-8/room-64-64-8.map movingai/mapf_room-64-64-8/room-64-64-8-even-1.scen
movingai/maze512-32-9/maze512-32-9.map movingai/maze512-32-9/maze512-32-9.map.scen
movingai/orz100d/orz100d.map movingai/orz100d/orz100d.map.scen
movingai/ost003d/ost003d.map movingai/ost003d/ost003d.map.scen
movingai/random512-10-0/random512-10-0.map movingai/random512-10-0/random512-10-0.map.scen
movingai/rmtst01/rmtst01.map movingai/rmtst01/rmtst01.map.scen
ros_maps/aws_small_warehouse_005/map.yaml ros_maps/aws_small_warehouse_005/map_rotated.png
ros_maps/mdr_wrs20-arena/map.yaml ros_maps/mdr_wrs20-arena/map.pgm
ros_maps/nav2_depot/depot.yaml ros_maps/nav2_depot/depot.pgm
ros_maps/nav2_depot_speed_mask/depot_speed.yaml ros_maps/nav2_depot_speed_mask/depot_speed.pgm
ros_maps/nav2_planner_benchmark_100by100_10/100by100_10.yaml ros_maps/nav2_planner_benchmark_100by100_10/100by100_10.pgm
ros_maps/nav2_smoothers_world/smoothers_world.yaml ros_maps/nav2_smoothers_world/smoothers_world.pgm
ros_maps/nav2_warehouse/warehouse.yaml ros_maps/nav2_warehouse/warehouse.pgm
ros_maps/turtlebot3_world/map.yaml ros_maps/turtlebot3_world/map.pgm
ros_map_fixtures/nav2_testmap/testmap.yaml ros_map_fixtures/nav2_testmap/testmap.png
ros_map_fixtures/nav2_testmap/testmap.pgm ros_map_fixtures/nav2_testmap/testmap.bmp
ros_map_fixtures/nav2_testmap/test_constants.cpp
ros_map_fixtures/ros1_map_server_test/testmap.yaml ros_map_fixtures/ros1_map_server_test/testmap.png
ros_map_fixtures/ros1_map_server_test/testmap2.yaml ros_map_fixtures/ros1_map_server_test/testmap2.png
ros_map_fixtures/ros1_map_server_test/spectrum.png ros_map_fixtures/ros1_map_server_test/test_constants.cpp
polygon/extremitypathfinder/cases.json polygon/extremitypathfinder/LICENSE
polygon/polyanya_arena/arena_cases.json polygon/polyanya_arena/LICENSE polygon/polyanya_arena/LICENSE-MIT
polygon/polyanya_cpp_tests/cases.json polygon/polyanya_cpp_tests/LICENSE
polygon/polyanya_cpp_tests/square.mesh polygon/polyanya_cpp_tests/bad-ambig.mesh
polygon/polyanya_cpp_tests/bad-collinear.mesh polygon/polyanya_cpp_tests/bad-collinear2-rot0.mesh
polygon/polyanya_cpp_tests/bad-collinear2-rot45.mesh polygon/polyanya_cpp_tests/bad-collinear2-rot90.mesh
""".split()  # noqa: SIM905 (one line per folder reads better than a list literal)

#: Files the collection's manifest marks as derived (written by its collectors from the upstream files).
DERIVED = {"polygon/extremitypathfinder/cases.json": "jannikmi/extremitypathfinder `tests/test_cases.py`",
           "polygon/polyanya_arena/arena_cases.json": "vleue/polyanya `tests/arena.rs`, `tests/arena-merged.rs`",
           "polygon/polyanya_cpp_tests/cases.json": "krnbatta/warthog `polyanya/scenarios/test/*.scen`"}

COMPRESSED = (".map", ".scen", ".pgm")


def _sha(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _provenance(manifest: str) -> dict[str, tuple[str, str, str, str]]:
    """Local path -> (repo, source path, commit, licence), from the collection's per-file appendix."""
    rows: dict[str, tuple[str, str, str, str]] = {}
    for line in manifest.splitlines():
        cols = [c.strip() for c in line.split("|")]
        if len(cols) == 10 and cols[1].startswith("`open/") and re.fullmatch(r"`[0-9a-f]{40}`", cols[4]):
            local = cols[1].strip("`").removeprefix("open/")
            rows[local] = (cols[2], cols[3].strip("`"), cols[4].strip("`")[:12], cols[8])
    return rows


def _lookup(prov: dict[str, tuple[str, str, str, str]], rel: str) -> tuple[str, str, str, str]:
    if rel in prov:
        return prov[rel]
    # the collection lists a few files by folder and suffix only (an empty stem); match on those
    folder, suffix = rel.rsplit("/", 1)[0], Path(rel).suffix
    for local, row in prov.items():
        if local == f"{folder}/{suffix}":
            repo, src, commit, lic = row
            return repo, src[: -len(suffix)] + Path(rel).name, commit, lic
    raise SystemExit(f"{rel}: no provenance row in the collection's manifest")


def _scenarios(data: bytes) -> int:
    lines = [ln for ln in data.decode().splitlines() if ln.strip()]
    return len(lines) - (1 if lines and lines[0].lower().startswith("version") else 0)


def build(source: Path) -> dict[str, bytes]:
    """The files to ship (path under tests/data/maps -> bytes), MANIFEST.md included."""
    prov = _provenance((source / "MANIFEST.md").read_text())
    out: dict[str, bytes] = {}
    rows, mai = [], []
    for rel in FILES:
        data = (source / rel).read_bytes()
        name, stored, note = rel, data, "copied"
        if Path(rel).suffix in COMPRESSED and not rel.startswith("ros_map_fixtures/"):  # fixtures: as named
            name, stored, note = rel + ".gz", gzip.compress(data, 9, mtime=0), "gzip -9"
        elif rel.startswith("ros_maps/") and rel.endswith(".yaml"):
            text = data.decode()
            new = re.sub(r"^(image:\s*)(\S+\.pgm)\s*$", r"\1\2.gz", text, flags=re.M)
            if new != text:
                stored, note = new.encode(), "`image:` names the .pgm.gz"
        out[name] = stored
        if rel in DERIVED:
            repo, src, commit, lic = "derived from " + DERIVED[rel], "", "", "as its source"
        else:
            repo, src, commit, lic = _lookup(prov, rel)
        rows.append(f"| `{name}` | {repo} | `{src}` | `{commit}` | {lic} | {len(data)} | `{_sha(data)}` | "
                    f"{note} | `{_sha(stored)}` |")
        if rel.startswith("movingai/") and rel.endswith(".scen"):
            mai.append(f"| `{rel.split('/')[1]}` | {_scenarios(data)} |")
    head = """# Test data: externally authored maps

Copies of public benchmark maps and loader fixtures that gridfield's test suite, the benchmarks' smoke
tests and the documentation build read (nothing outside the repository is read). None was authored by
the gridfield developers but the three `cases.json` files marked derived (answers transcribed from the
named upstream tests by the collectors of these files). Written by `tools/bundle_test_maps.py`, which
also checks the copy (`--check`).

Text maps, scenario lists and PGM images (not the loader fixtures') are stored gzip-compressed (`gzip -9`, no time stamp); gridfield
reads `.map.gz`, `.scen.gz` and `.pgm.gz` directly. `sha256 (upstream)` is that of the file as
published (decompress to check it); `sha256 (here)` that of the file in this folder. A ROS map YAML's
only change is its `image:` line, which names the compressed image.

Licences: each file is under the licence of its source repository, named per row (the Moving AI maps
are N. Sturtevant's benchmark data, movingai.com, "Benchmarks for Grid-Based Pathfinding", IEEE TCIAIG
2012, as redistributed by the repositories named). The licence texts of the polygon fixtures are in
their folders.

## Moving AI scenario counts

| map | scenarios |
|---|---:|
"""
    table = ("\n## Files\n\n| file | source repository | source path | commit | licence | bytes (upstream) | "
             "sha256 (upstream) | stored | sha256 (here) |\n|---|---|---|---|---|---:|---|---|---|\n")
    out["MANIFEST.md"] = (head + "\n".join(mai) + "\n" + table + "\n".join(rows) + "\n").encode()
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--source", required=True, type=Path, help="the collection's root folder (holds MANIFEST.md)")
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--check", action="store_true", help="compare instead of writing")
    args = ap.parse_args(argv)
    files = build(args.source)
    bad = 0
    for name, data in sorted(files.items()):
        target = args.out / name
        if args.check:
            if not target.is_file() or target.read_bytes() != data:
                print(f"differs: {target}")
                bad += 1
        else:
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
    if not args.check:
        total = sum(len(d) for d in files.values())
        print(f"wrote {len(files)} files, {total / 1e6:.2f} MB, to {args.out}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
